/* SPDX-License-Identifier: MPL-2.0 */
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
 * (fd_port.peer_fd, never read or written): the master never sees a hangup, and
 * "no client attached" simply reads as no data until the deadline. Clients
 * come and go freely; the slave is still exclusive to the first client that
 * opens it with df1_open() (flock/TIOCEXCL), and a client's df1_open() flushes
 * whatever the master wrote while nobody listened. If the slave cannot be
 * opened (still locked: unlockpt() not called), the port works without it and
 * a hangup ends reads with DF1_E_CLOSED, as on any other descriptor.
 *
 * The backend's state (ownership, the flags to put back, the pty peer) is its
 * struct fd_port behind h->port_data. A listen-only handle never writes to the
 * descriptor (port_write_fd refuses); the descriptor itself stays as given.
 *
 * SIGPIPE: sockets are written with send(MSG_NOSIGNAL); on a pipe whose reader
 * is gone the application must ignore SIGPIPE to get DF1_E_CLOSED instead.
 */
#include "port/port.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include "df1_int.h"

#ifndef TIOCGPTPEER
#define TIOCGPTPEER _IO('T', 0x41) /* Linux 4.13 */
#endif

/* The backend's state (h->port_data), from open to close. */
struct fd_port {
	bool own;                    /* close the descriptor at close */
	bool is_socket;              /* write with send(MSG_NOSIGNAL) */
	int saved_fl;                /* file status flags to restore on close (-1: none) */
	int peer_fd;                 /* on a pty master: our own fd on the slave side (-1) */
};

/* If fd is a pty master, open and keep its slave side (see above). */
static void fd_hold_pty_peer(struct df1 *h, struct fd_port *fp)
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
	fp->peer_fd = peer; /* -1 if neither worked */
}

static void fd_close(struct df1 *h)
{
	struct fd_port *fp = h->port_data;

	if (fp && fp->peer_fd >= 0)
		close(fp->peer_fd);
	if (h->fd >= 0 && fp) {
		if (fp->own)
			close(h->fd);
		else if (fp->saved_fl >= 0)
			(void)fcntl(h->fd, F_SETFL, fp->saved_fl);
	}
	free(fp);
	h->port_data = NULL;
	h->fd = -1;
}

int port_fd_open(struct df1 *h, int fd, bool own)
{
	struct stat st;
	struct fd_port *fp;
	int fl;

	snprintf(h->port_name, sizeof h->port_name, "fd %d", fd);
	fl = fcntl(fd, F_GETFL);
	if (fl < 0)
		return df1_fail(h, DF1_E_INVAL, -1, "fd %d is not an open descriptor", fd);
	fp = calloc(1, sizeof *fp);
	if (!fp)
		return df1_fail(h, DF1_E_NOMEM, -1, "fd %d: out of memory", fd);
	fp->saved_fl = -1;
	fp->peer_fd = -1;
	if (!(fl & O_NONBLOCK)) {
		if (fcntl(fd, F_SETFL, fl | O_NONBLOCK) < 0) {
			int err = errno;

			free(fp);
			return port_fail_sys(h, DF1_E_SYS, err, "cannot set O_NONBLOCK on");
		}
		if (!own)
			fp->saved_fl = fl;
	}
	fp->own = own;
	fp->is_socket = fstat(fd, &st) == 0 && S_ISSOCK(st.st_mode);
	h->fd = fd;
	h->port_data = fp;
	fd_hold_pty_peer(h, fp);
	return 0;
}

/* Called through h->port->peer: h->port_data is ours. */
static int fd_peer(const struct df1 *h)
{
	const struct fd_port *fp = h->port_data;

	return fp ? fp->peer_fd : -1;
}

static ssize_t fd_write(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms)
{
	const struct fd_port *fp = h->port_data;

	if (fp && fp->is_socket)
		return port_send_fd(h, buf, len, deadline_ms);
	return port_write_fd(h, buf, len, deadline_ms);
}

const struct port_ops port_fd_ops = {
	.name = "fd",
	.open = NULL,           /* port_fd_open(): a descriptor, not a target name */
	.close = fd_close,
	.read = port_read_fd,
	.write = fd_write,
	.configure = NULL,
	.drain = NULL,
	.peer = fd_peer,
	.modem = port_modem_fd,
};
