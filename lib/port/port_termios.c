/* SPDX-License-Identifier: MPL-2.0 */
/*
 * port_termios.c - serial ports through POSIX termios (Linux).
 *
 * Open: O_RDWR|O_NOCTTY|O_NONBLOCK|O_CLOEXEC (no controlling tty, never block
 * in open() on DCD, no leak into children; O_RDONLY instead when the handle is
 * listen only, DF1_OPT_LISTEN_ONLY); exclusive use with flock(LOCK_EX)
 * (other libdf1 users and cooperating tools, root included) plus TIOCEXCL
 * (further open()s by non-root programs fail with EBUSY); the original termios
 * is saved and restored on close and on every error path after it was read.
 * What the backend keeps from open to close (the saved termios, the RS-485
 * flags it changed) is its own struct termios_port behind h->port_data.
 * A USB serial adapter is also asked for low latency (lib/port/port_usb.c),
 * undone at close like the rest.
 *
 * The line is raw: no echo, no canonical mode, no signals, no CR/NL mapping,
 * no software flow control; RTS/CTS only when asked; VMIN = VTIME = 0 because
 * every wait is a poll() against a deadline (lib/port/port.c).
 */
#include "port/port.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/serial.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>
#include <unistd.h>

#include "df1_int.h"
#include "port/port_usb.h"

#define RS485_BITS (SER_RS485_ENABLED | SER_RS485_RTS_ON_SEND | SER_RS485_RTS_AFTER_SEND)

/* The backend's state (h->port_data), from open to close. */
struct termios_port {
	bool have_saved;             /* saved holds the termios found at open */
	struct termios saved;
	bool rs485_changed;          /* restore saved_rs485_flags on close */
	uint32_t saved_rs485_flags;
	struct port_usb usb;         /* a USB adapter's low latency (lib/port/port_usb.c) */
};

static speed_t termios_speed(int baud)
{
	switch (baud) {
	case 1200: return B1200;
	case 2400: return B2400;
	case 4800: return B4800;
	case 9600: return B9600;
	case 19200: return B19200;
	case 38400: return B38400;
	case 57600: return B57600;
	case 115200: return B115200;
	default: return B0;
	}
}

static tcflag_t termios_csize(int data_bits)
{
	switch (data_bits) {
	case 5: return CS5;
	case 6: return CS6;
	case 7: return CS7;
	default: return CS8;
	}
}

/* A pseudo-terminal slave: Linux's pty driver forces CS8 and clears PARENB
 * (drivers/tty/pty.c), so data bits and parity cannot be verified there. */
static bool termios_is_pty(int fd)
{
	struct stat st;
	unsigned int maj;

	if (fstat(fd, &st) < 0 || !S_ISCHR(st.st_mode))
		return false;
	maj = major(st.st_rdev);
	return (maj >= 136 && maj <= 143) /* UNIX98_PTY_SLAVE_MAJOR .. +7 */ || maj == 3 /* BSD */;
}

/* ENOSYS: a layer between the program and the kernel that does not know the
 * request (qemu-user, where make cross-check runs the tests) */
static int termios_rs485_ioctl_fail(struct df1 *h, const char *what)
{
	if (errno == ENOTTY || errno == EINVAL || errno == EOPNOTSUPP || errno == ENOSYS)
		return df1_fail(h, DF1_E_NOTSUP, -1, "RS-485 mode not supported by %s", h->port_name);
	return port_fail_sys(h, DF1_E_SYS, errno, what);
}

/* Kernel RS-485 (TIOCSRS485): RTS high while sending. Touches the driver only
 * when asked to enable it, or to undo what we enabled. */
static int termios_rs485(struct df1 *h)
{
	struct termios_port *tp = h->port_data;
	struct serial_rs485 rs;

	if (!h->cfg.rs485 && !tp->rs485_changed)
		return 0;
	memset(&rs, 0, sizeof rs);
	if (ioctl(h->fd, TIOCGRS485, &rs) < 0)
		return termios_rs485_ioctl_fail(h, "TIOCGRS485 on");
	if (!tp->rs485_changed)
		tp->saved_rs485_flags = rs.flags;
	rs.flags &= ~(uint32_t)RS485_BITS;
	if (h->cfg.rs485)
		rs.flags |= SER_RS485_ENABLED | SER_RS485_RTS_ON_SEND;
	else
		rs.flags |= tp->saved_rs485_flags & RS485_BITS;
	if (ioctl(h->fd, TIOCSRS485, &rs) < 0)
		return termios_rs485_ioctl_fail(h, "TIOCSRS485 on");
	tp->rs485_changed = h->cfg.rs485;
	return 0;
}

static int termios_configure(struct df1 *h)
{
	struct termios t, chk;
	speed_t speed = termios_speed(h->cfg.baud);
	tcflag_t cmask;

	if (h->fd < 0 || !h->port_data)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "port is not open");
	if (speed == B0)
		return df1_fail(h, DF1_E_CONFIG, -1, "invalid baud rate %d", h->cfg.baud);
	if (tcgetattr(h->fd, &t) < 0)
		return port_fail_sys(h, DF1_E_SYS, errno, "tcgetattr on");

	/* raw (cfmakeraw): no break/parity marking, no CR/NL mapping, no XON/XOFF */
	t.c_iflag &= ~(tcflag_t)(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL |
	                         IXON | IXOFF | IXANY | IUCLC | IMAXBEL | INPCK | IGNPAR);
	t.c_oflag &= ~(tcflag_t)OPOST;          /* bytes go out as they are */
	t.c_lflag &= ~(tcflag_t)(ECHO | ECHOE | ECHOK | ECHONL | ECHOCTL | ECHOKE | ICANON |
	                         ISIG | IEXTEN | NOFLSH | TOSTOP);
	/* framing: data bits, parity, stop bits, RTS/CTS; CLOCAL: ignore modem
	 * lines (DCD), CREAD: enable the receiver */
	t.c_cflag &= ~(tcflag_t)(CSIZE | PARENB | PARODD | CMSPAR | CSTOPB | CRTSCTS);
	t.c_cflag |= CLOCAL | CREAD | termios_csize(h->cfg.data_bits);
	if (h->cfg.parity == 'E' || h->cfg.parity == 'O') {
		t.c_cflag |= PARENB;
		if (h->cfg.parity == 'O')
			t.c_cflag |= PARODD;
		t.c_iflag |= INPCK;             /* check received parity */
	}
	if (h->cfg.stop_bits == 2)
		t.c_cflag |= CSTOPB;
	if (h->cfg.rts_cts)
		t.c_cflag |= CRTSCTS;
	/* read() returns at once with what is there: timing is poll()'s job */
	t.c_cc[VMIN] = 0;
	t.c_cc[VTIME] = 0;
	cfsetispeed(&t, speed);
	cfsetospeed(&t, speed);

	/* EINVAL is not final: glibc reports it when PARENB/CSIZE did not stick
	 * and nothing else changed (always the case on a pty, whose driver forces
	 * CS8 without parity). The read-back below is what decides. */
	if (tcsetattr(h->fd, TCSANOW, &t) < 0 && errno != EINVAL)
		return port_fail_sys(h, DF1_E_SYS, errno, "tcsetattr on");

	/* tcsetattr() succeeds if any one change took: read back and compare */
	if (tcgetattr(h->fd, &chk) < 0)
		return port_fail_sys(h, DF1_E_SYS, errno, "tcgetattr on");
	if (cfgetospeed(&chk) != speed || cfgetispeed(&chk) != speed)
		return df1_fail(h, DF1_E_NOTSUP, -1, "%s does not support %d baud", h->port_name,
		                h->cfg.baud);
	cmask = CSTOPB | CRTSCTS | CLOCAL | CREAD;
	if (!termios_is_pty(h->fd))
		cmask |= CSIZE | PARENB | PARODD;
	if ((chk.c_cflag & cmask) != (t.c_cflag & cmask))
		return df1_fail(h, DF1_E_NOTSUP, -1, "%s does not support %d%c%d%s", h->port_name,
		                h->cfg.data_bits, h->cfg.parity, h->cfg.stop_bits,
		                h->cfg.rts_cts ? " with RTS/CTS handshake" : "");
	if ((chk.c_lflag & (ICANON | ECHO | ISIG)) || (chk.c_oflag & OPOST) ||
	    chk.c_cc[VMIN] != 0 || chk.c_cc[VTIME] != 0)
		return df1_fail(h, DF1_E_NOTSUP, -1, "%s did not accept raw mode", h->port_name);

	return termios_rs485(h);
}

static void termios_close(struct df1 *h)
{
	struct termios_port *tp = h->port_data;

	if (tp)
		port_usb_close(h, &tp->usb);
	if (h->fd >= 0 && tp && tp->rs485_changed) {
		struct serial_rs485 rs;

		memset(&rs, 0, sizeof rs);
		if (ioctl(h->fd, TIOCGRS485, &rs) == 0) {
			rs.flags = (rs.flags & ~(uint32_t)RS485_BITS) | (tp->saved_rs485_flags & RS485_BITS);
			(void)ioctl(h->fd, TIOCSRS485, &rs);
		}
	}
	if (h->fd >= 0 && tp && tp->have_saved) {
		/* TCSANOW: TCSADRAIN could wait forever on a flow-controlled line */
		(void)tcsetattr(h->fd, TCSANOW, &tp->saved);
	}
	if (h->fd >= 0) {
		(void)ioctl(h->fd, TIOCNXCL);
		close(h->fd); /* also drops the flock */
	}
	free(tp);
	h->port_data = NULL;
	h->fd = -1;
}

static int termios_open(struct df1 *h, const char *path)
{
	struct termios_port *tp;
	int fd, r;

	snprintf(h->port_name, sizeof h->port_name, "%s", path);
	tp = calloc(1, sizeof *tp);
	if (!tp)
		return df1_fail(h, DF1_E_NOMEM, -1, "%s: out of memory", path);
	/* listen only: a descriptor that cannot transmit at all */
	fd = open(path, (h->cfg.listen_only ? O_RDONLY : O_RDWR) | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
	if (fd < 0) {
		free(tp);
		switch (errno) {
		case ENOENT:
		case ENODEV:
		case ENXIO:
		case ENOTDIR:
			return df1_fail(h, DF1_E_NODEV, -1, "no such device: %s", path);
		case EACCES:
		case EPERM:
			return df1_fail(h, DF1_E_PERM, -1,
			                "permission denied: %s (is the user in the dialout group?)", path);
		case EBUSY: /* TIOCEXCL set by another process */
			return df1_fail(h, DF1_E_BUSY, -1,
			                "port busy: %s is in use by another process", path);
		default:
			return port_fail_sys(h, DF1_E_SYS, errno, "cannot open");
		}
	}
	h->fd = fd;
	h->port_data = tp;
	if (flock(fd, LOCK_EX | LOCK_NB) < 0) {
		if (errno == EWOULDBLOCK)
			r = df1_fail(h, DF1_E_BUSY, -1, "port busy: %s is in use by another process", path);
		else
			r = port_fail_sys(h, DF1_E_SYS, errno, "cannot lock");
		goto fail;
	}
	if (tcgetattr(fd, &tp->saved) < 0) {
		if (errno == ENOTTY || errno == EINVAL)
			r = df1_fail(h, DF1_E_NODEV, -1, "%s is not a serial port", path);
		else
			r = port_fail_sys(h, DF1_E_SYS, errno, "tcgetattr on");
		goto fail;
	}
	tp->have_saved = true;
	/* keeps out later open()s by non-root programs; flock above is the lock
	 * that also holds against root. Failure is not fatal. */
	(void)ioctl(fd, TIOCEXCL);
	r = termios_configure(h);
	if (r < 0)
		goto fail;
	/* input only: on a pty, flushing output from this side would also drop
	 * what the peer has not read yet (the previous user's last DLE ACK). A
	 * listen-only tap keeps everything: what is on the line is what it shows. */
	if (!h->cfg.listen_only && tcflush(fd, TCIFLUSH) < 0) {
		r = port_fail_sys(h, DF1_E_SYS, errno, "tcflush on");
		goto fail;
	}
	/* after the termios: the driver may reset its flags when the line is set */
	port_usb_open(h, &tp->usb);
	return 0;
fail:
	termios_close(h); /* restores the saved termios, frees tp; h->err keeps the first error */
	return r;
}

/* tcdrain() has no timeout: with RTS/CTS a peer holding CTS low would block
 * it forever, so then it does not wait (the bytes are queued in the UART). */
static int termios_drain(struct df1 *h)
{
	if (h->fd < 0)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "port is not open");
	if (h->cfg.rts_cts)
		return 0;
	while (tcdrain(h->fd) < 0) {
		if (errno != EINTR)
			return port_fail_sys(h, DF1_E_SYS, errno, "tcdrain on");
	}
	return 0;
}

const struct port_ops port_termios_ops = {
	.name = "termios",
	.paced = true,          /* a UART sends at the baud: lib/link/core.c keeps the account */
	.open = termios_open,
	.close = termios_close,
	.read = port_read_fd,
	.write = port_write_fd,
	.configure = termios_configure,
	.drain = termios_drain,
	.modem = port_modem_fd,
};
