/* SPDX-License-Identifier: MPL-2.0 */
/*
 * port.c - what every transport shares: the deadline wait (port descriptor +
 * the handle's cancel descriptor; the clock is lib/base/clock.c), and
 * descriptor read/write with the port_ops contracts (lib/port/port.h).
 *
 * Waits are ppoll() against an absolute CLOCK_MONOTONIC deadline in
 * microseconds (a paced transmission ends when its last character would, not
 * at the next whole millisecond): after EINTR the wait goes on for what is
 * left of it, never for a fresh full timeout. Nothing here sleeps or spins:
 * ppoll() blocks until the descriptor is ready, the cancel descriptor is
 * readable, or the deadline passes. The read/write contracts keep their
 * deadlines in milliseconds (timeouts are configured in ms).
 */
#include "port/port.h"

#include <errno.h>
#include <limits.h>
#include <poll.h>
#include <string.h>
#include <time.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "df1_int.h"

int port_fail_sys(struct df1 *h, int code, int err, const char *what)
{
	char buf[96];
	const char *text = strerror_r(err, buf, sizeof buf); /* GNU: thread-safe, returns the text */

	errno = err;
	return df1_fail(h, code, -1, "%s %s: %s", what, h->port_name, text);
}

/* ppoll() fd for events (and the cancel fd for input) until deadline_us
 * (df1_now_us() clock). Returns the fd's revents (> 0), 0 at the deadline,
 * DF1_E_INTR, DF1_E_INVAL (cancel fd closed under us) or DF1_E_SYS. */
static int port_poll_us(struct df1 *h, int fd, short events, int64_t deadline_us)
{
	struct pollfd pfd[2];
	nfds_t n = 1;

	pfd[0].fd = fd;
	pfd[0].events = events;
	pfd[0].revents = 0;
	if (h->cancel_fd >= 0) {
		pfd[1].fd = h->cancel_fd;
		pfd[1].events = POLLIN;
		pfd[1].revents = 0;
		n = 2;
	}
	for (;;) {
		int64_t left = deadline_us - (int64_t)df1_now_us();
		struct timespec ts;
		int r;

		if (left < 0)
			left = 0;
		ts.tv_sec = (time_t)(left / 1000000);
		ts.tv_nsec = (long)(left % 1000000) * 1000;
		r = ppoll(pfd, n, &ts, NULL);

		if (r < 0) {
			if (errno == EINTR)
				continue; /* same absolute deadline: only the rest of it is waited */
			return port_fail_sys(h, DF1_E_SYS, errno, "poll on");
		}
		if (n == 2 && pfd[1].revents) {
			if (pfd[1].revents & POLLNVAL)
				return df1_fail(h, DF1_E_INVAL, -1, "cancel fd %d is not open", h->cancel_fd);
			/* readable, or its writer went away (POLLHUP): either way, stop */
			return df1_fail(h, DF1_E_INTR, -1, "wait on %s cancelled", h->port_name);
		}
		if (pfd[0].revents & POLLNVAL)
			return port_fail_sys(h, DF1_E_SYS, EBADF, "poll on");
		if (pfd[0].revents)
			return pfd[0].revents;
		if (left == 0 || (int64_t)df1_now_us() >= deadline_us)
			return 0;
		/* ppoll() returned before our clock reached the deadline: wait for the rest */
	}
}

static int port_poll(struct df1 *h, int fd, short events, int64_t deadline_ms)
{
	return port_poll_us(h, fd, events, deadline_ms > INT64_MAX / 1000 ? INT64_MAX : deadline_ms * 1000);
}

/* fd < 0 is allowed: poll() ignores it, so this is a pause that only the
 * cancel fd can cut short (TX delay, reply delay). */
int port_wait(struct df1 *h, int fd, short events, int64_t deadline_ms)
{
	int r = port_poll(h, fd, events, deadline_ms);

	return r > 0 ? 1 : r;
}

int port_wait_us(struct df1 *h, int fd, short events, int64_t deadline_us)
{
	int r = port_poll_us(h, fd, events, deadline_us);

	return r > 0 ? 1 : r;
}

/* errno of a failed read/write that means the other end is gone. EIO: a tty
 * hung up (USB adapter unplugged, pty master closed) or a pty master whose
 * slave side nobody holds open. */
static bool port_errno_closed(int err)
{
	return err == EIO || err == EPIPE || err == ECONNRESET || err == ENOTCONN ||
	       err == ETIMEDOUT || err == ENXIO || err == ENODEV;
}

static ssize_t port_read_failed(struct df1 *h, int code, int err)
{
	df1_count(h, DF1_ID_CNT_COM_READ_ERRORS);
	if (code == DF1_E_CLOSED && err == 0)
		return df1_fail(h, DF1_E_CLOSED, -1, "%s: connection closed by peer", h->port_name);
	return port_fail_sys(h, code, err, "read from");
}

ssize_t port_read_fd(struct df1 *h, uint8_t *buf, size_t cap, int64_t deadline_ms)
{
	if (h->fd < 0)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "port is not open");
	if (cap == 0)
		return 0;
	for (;;) {
		int rev = port_poll(h, h->fd, POLLIN, deadline_ms);
		ssize_t n;

		if (rev <= 0)
			return rev; /* 0 at the deadline, or DF1_E_INTR / DF1_E_SYS */
		n = read(h->fd, buf, cap);
		if (n > 0)
			return n;
		if (n == 0) /* EOF: socket or pipe peer closed, tty hung up */
			return port_read_failed(h, DF1_E_CLOSED, 0);
		if (errno == EINTR)
			continue;
		if (errno == EAGAIN || errno == EWOULDBLOCK) {
			/* poll said ready but nothing to read: a hangup or error with no
			 * data would make poll() return at once forever, so that ends it */
			if (rev & (POLLHUP | POLLERR))
				return port_read_failed(h, DF1_E_CLOSED, 0);
			continue; /* someone else took the bytes; poll blocks again */
		}
		return port_read_failed(h, port_errno_closed(errno) ? DF1_E_CLOSED : DF1_E_SYS, errno);
	}
}

int port_fd_peer(const struct df1 *h)
{
	return h->port && h->port->peer ? h->port->peer(h) : -1;
}

int port_modem_fd(struct df1 *h, unsigned set, unsigned clear, unsigned *state)
{
	int bits = 0, m = 0;

	if (h->fd < 0)
		return DF1_E_NOT_OPEN;
	if (set & PORT_LINE_RTS)
		bits = TIOCM_RTS;
	if (bits && ioctl(h->fd, TIOCMBIS, &bits) < 0)
		goto fail;
	bits = (clear & PORT_LINE_RTS) ? TIOCM_RTS : 0;
	if (bits && ioctl(h->fd, TIOCMBIC, &bits) < 0)
		goto fail;
	if (!state)
		return 0;
	if (ioctl(h->fd, TIOCMGET, &m) < 0)
		goto fail;
	*state = ((m & TIOCM_RTS) ? PORT_LINE_RTS : 0) | ((m & TIOCM_CTS) ? PORT_LINE_CTS : 0) |
	         ((m & TIOCM_CAR) ? PORT_LINE_DCD : 0);
	return 0;
fail:
	/* a pty or a socket has no modem lines: not an error of the port */
	if (errno == ENOTTY || errno == EINVAL || errno == ENOTSUP || errno == EOPNOTSUPP)
		return DF1_E_NOTSUP;
	return port_fail_sys(h, DF1_E_SYS, errno, "modem lines of");
}

int port_refuse_tx(struct df1 *h)
{
	return df1_fail(h, DF1_E_NOTSUP, -1, "%s is listen only: nothing is transmitted",
	                h->port_name);
}

static ssize_t port_out(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms,
                        bool sock)
{
	size_t done = 0;

	if (h->fd < 0)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "port is not open");
	if (h->cfg.listen_only)
		return port_refuse_tx(h);
	while (done < len) {
		ssize_t n;
		int rev;

		if (sock)
			n = send(h->fd, buf + done, len - done, MSG_NOSIGNAL);
		else
			n = write(h->fd, buf + done, len - done);
		if (n > 0) {
			done += (size_t)n;
			continue;
		}
		if (n < 0 && errno == EINTR)
			continue;
		if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) {
			int err = n == 0 ? EIO : errno;

			return port_fail_sys(h, port_errno_closed(err) ? DF1_E_CLOSED : DF1_E_SYS, err,
			                     "write to");
		}
		rev = port_poll(h, h->fd, POLLOUT, deadline_ms);
		if (rev < 0)
			return rev;
		if (rev == 0)
			return df1_fail(h, DF1_E_TIMEOUT, -1,
			                "write to %s: %zu of %zu bytes sent before the deadline "
			                "(output blocked, flow control?)", h->port_name, done, len);
		if ((rev & (POLLHUP | POLLERR)) && !(rev & POLLOUT))
			return df1_fail(h, DF1_E_CLOSED, -1, "write to %s: connection closed by peer",
			                h->port_name);
	}
	return (ssize_t)done;
}

ssize_t port_write_fd(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms)
{
	return port_out(h, buf, len, deadline_ms, false);
}

ssize_t port_send_fd(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms)
{
	return port_out(h, buf, len, deadline_ms, true);
}
