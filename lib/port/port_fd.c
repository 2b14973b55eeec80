/*
 * port_fd.c - a descriptor the application opened (df1_open_fd): a pty master
 * (df1sim --pty), a connected socket (df1sim --listen), a pipe, a tty set up
 * elsewhere. The descriptor is switched to O_NONBLOCK; when the handle does not
 * own it, its file status flags are put back at close and it stays open.
 * Serial settings are not applied (configure is NULL), except that a pty master
 * is put in raw mode: DF1 is binary, and echo or CR/NL mapping would corrupt it.
 *
 * A pty master and POLLHUP: once a process has opened the slave side and closed
 * it again, poll() on the master reports POLLHUP at once, every time, until the
 * slave is opened again. A simulator serving the master would either spin or
 * have to treat "no client" as fatal. So on a pty master the port opens the
 * slave side itself (TIOCGPTPEER, else ptsname) and holds that descriptor
 * (h->peer_fd, never read or written): the master never sees a hangup, and
 * "no client attached" simply reads as no data until the deadline. Clients
 * come and go freely; the slave is still exclusive to the first client that
 * opens it with df1_open() (flock/TIOCEXCL), and a client's df1_open() flushes
 * whatever the master wrote while nobody listened. If the slave cannot be
 * opened (still locked: unlockpt() not called), the port works without it and
 * a hangup ends reads with DF1_E_CLOSED, as on any other descriptor.
 *
 * SIGPIPE: sockets are written with send(MSG_NOSIGNAL); on a pipe whose reader
 * is gone the application must ignore SIGPIPE to get DF1_E_CLOSED instead.
 */
#include "port.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include "df1_int.h"

#ifndef TIOCGPTPEER
#define TIOCGPTPEER _IO('T', 0x41) /* Linux 4.13 */
#endif

/* If fd is a pty master, open and keep its slave side (see above). */
static void fd_hold_pty_peer(struct df1 *h)
{
	unsigned int ptn;
	char path[64];
	struct termios t;
	int peer;

	if (ioctl(h->fd, TIOCGPTN, &ptn) < 0)
		return; /* not a pty master */
	if (tcgetattr(h->fd, &t) == 0) { /* the pair shares the slave's termios */
		cfmakeraw(&t);
		t.c_cflag |= CLOCAL | CREAD;
		t.c_cc[VMIN] = 0;
		t.c_cc[VTIME] = 0;
		(void)tcsetattr(h->fd, TCSANOW, &t);
	}
	peer = ioctl(h->fd, TIOCGPTPEER, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
	if (peer < 0 && ptsname_r(h->fd, path, sizeof path) == 0)
		peer = open(path, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
	h->peer_fd = peer; /* -1 if neither worked */
}

static int fd_open(struct df1 *h, const char *target)
{
	struct stat st;
	int fl;

	if (target)
		snprintf(h->port_name, sizeof h->port_name, "%s", target);
	else
		snprintf(h->port_name, sizeof h->port_name, "fd %d", h->fd);
	h->peer_fd = -1;
	h->saved_fl = -1;
	fl = fcntl(h->fd, F_GETFL);
	if (fl < 0)
		return df1_fail(h, DF1_E_INVAL, -1, "fd %d is not an open descriptor", h->fd);
	if (!(fl & O_NONBLOCK)) {
		if (fcntl(h->fd, F_SETFL, fl | O_NONBLOCK) < 0)
			return port_fail_sys(h, DF1_E_SYS, errno, "cannot set O_NONBLOCK on");
		if (!h->own_fd)
			h->saved_fl = fl;
	}
	h->is_socket = fstat(h->fd, &st) == 0 && S_ISSOCK(st.st_mode);
	fd_hold_pty_peer(h);
	return 0;
}

static void fd_close(struct df1 *h)
{
	if (h->peer_fd >= 0)
		close(h->peer_fd);
	h->peer_fd = -1;
	if (h->fd >= 0) {
		if (h->own_fd)
			close(h->fd);
		else if (h->saved_fl >= 0)
			(void)fcntl(h->fd, F_SETFL, h->saved_fl);
	}
	h->saved_fl = -1;
	h->fd = -1;
	h->is_socket = false;
}

const struct port_ops port_fd_ops = {
	.name = "fd",
	.open = fd_open,
	.close = fd_close,
	.read = port_read_fd,
	.write = port_write_fd,
	.configure = NULL,
	.drain = NULL,
};
