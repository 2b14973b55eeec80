/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_port.c - the port layer on real descriptors: pseudo-terminals through
 * the termios backend, loopback TCP, socketpairs/pipes/pty masters through
 * df1_open_fd(); listen-only handles (DF1_OPT_LISTEN_ONLY) and df1_recv_raw on
 * ptys, loopback TCP and a pipe. Every wait is bounded by a deadline; nothing
 * sleeps.
 *
 * tcsetattr() is interposed (defined here, the real one found with
 * RTLD_NEXT) to record what the library asked for: Linux's pty driver forces
 * CS8 and clears PARENB, so data bits and parity can only be checked on the
 * request; speed, stop bits, RTS/CTS and raw mode are checked on the pty.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "df1_int.h"
#include "link/link.h"

/* ---- tcsetattr interposition ------------------------------------------ */

static struct termios last_set;
static int n_set;

int tcsetattr(int fd, int act, const struct termios *t)
{
	static int (*real)(int, int, const struct termios *);

	if (!real)
		*(void **)&real = dlsym(RTLD_NEXT, "tcsetattr");
	last_set = *t;
	n_set++;
	return real(fd, act, t);
}

/* ---- helpers ----------------------------------------------------------- */

struct pty {
	int master;
	char path[64];
};

static void pty_make(struct pty *p)
{
	struct termios t;

	p->master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
	assert_true(p->master >= 0);
	assert_int_equal(grantpt(p->master), 0);
	assert_int_equal(unlockpt(p->master), 0);
	assert_int_equal(ptsname_r(p->master, p->path, sizeof p->path), 0);
	/* a cooked, 9600 7E1 starting point, unlike anything the library sets */
	assert_int_equal(tcgetattr(p->master, &t), 0);
	t.c_lflag |= ICANON | ECHO | ISIG;
	t.c_iflag |= ICRNL;
	t.c_oflag |= OPOST;
	t.c_cc[VMIN] = 1;
	cfsetispeed(&t, B9600);
	cfsetospeed(&t, B9600);
	assert_int_equal(tcsetattr(p->master, TCSANOW, &t), 0);
}

static void pty_free(struct pty *p)
{
	close(p->master);
}

static df1_t *handle_new(void)
{
	df1_t *h = NULL;

	assert_int_equal(df1_new(&h), 0);
	assert_non_null(h);
	return h;
}

/* Read exactly n bytes from a plain fd before a deadline. */
static void fd_read_exact(int fd, uint8_t *buf, size_t n, int timeout_ms)
{
	int64_t deadline = df1_now_ms() + timeout_ms;
	size_t got = 0;

	while (got < n) {
		struct pollfd p = { .fd = fd, .events = POLLIN };
		int64_t left = deadline - df1_now_ms();
		ssize_t r;

		assert_true(left > 0);
		if (poll(&p, 1, (int)left) <= 0)
			continue;
		r = read(fd, buf + got, n - got);
		if (r < 0 && (errno == EAGAIN || errno == EINTR))
			continue;
		assert_true(r > 0);
		got += (size_t)r;
	}
}

/* Read exactly n bytes through the handle's port. */
static void port_read_exact(df1_t *h, uint8_t *buf, size_t n, int timeout_ms)
{
	int64_t deadline = df1_now_ms() + timeout_ms;
	size_t got = 0;

	while (got < n) {
		ssize_t r = h->port->read(h, buf + got, n - got, deadline);

		assert_true(r > 0);
		got += (size_t)r;
	}
}

static bool termios_same(const struct termios *a, const struct termios *b)
{
	return a->c_iflag == b->c_iflag && a->c_oflag == b->c_oflag && a->c_cflag == b->c_cflag &&
	       a->c_lflag == b->c_lflag && memcmp(a->c_cc, b->c_cc, sizeof a->c_cc) == 0 &&
	       cfgetispeed(a) == cfgetispeed(b) && cfgetospeed(a) == cfgetospeed(b);
}

static void both_ways(df1_t *h, int peer)
{
	static const uint8_t out[] = { 0x10, 0x02, 0x01, 0x00, 0x0F, 0x00, 0x10, 0x10, 0x0D, 0x0A,
	                               0x11, 0x13, 0x03, 0x7F, 0xFF, 0x10, 0x03, 0xAB };
	static const uint8_t in[] = { 0x10, 0x06, 0x0D, 0x0A, 0x00, 0x04, 0x03, 0x1A, 0x11 };
	uint8_t buf[64];

	/* every byte value that cooked mode would mangle (CR, LF, XON, XOFF, ^C, ^D, ^Z, DEL) */
	assert_int_equal(h->port->write(h, out, sizeof out, df1_now_ms() + 2000), (ssize_t)sizeof out);
	fd_read_exact(peer, buf, sizeof out, 2000);
	assert_memory_equal(buf, out, sizeof out);
	assert_int_equal(write(peer, in, sizeof in), (ssize_t)sizeof in);
	port_read_exact(h, buf, sizeof in, 2000);
	assert_memory_equal(buf, in, sizeof in);
}

/* ---- termios backend on a pty ------------------------------------------ */

static void test_port_pty_bytes_both_ways(void **state)
{
	struct pty p;
	df1_t *h = handle_new();

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_open(h, p.path), 0);
	assert_true(df1_is_open(h));
	assert_ptr_equal(h->port, &port_termios_ops);
	both_ways(h, p.master);
	df1_close(h);
	assert_false(df1_is_open(h));
	df1_free(h);
	pty_free(&p);
}

static void test_port_read_without_data_returns_zero_at_deadline(void **state)
{
	struct pty p;
	df1_t *h = handle_new();
	uint8_t buf[8];

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_open(h, p.path), 0);
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 50), 0);
	/* a deadline already passed still returns (0), without blocking */
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() - 1000), 0);
	/* ... and still delivers bytes that are already there */
	assert_int_equal(write(p.master, "\x10\x06", 2), 2);
	port_read_exact(h, buf, 2, 2000);
	df1_free(h);
	pty_free(&p);
}

static volatile sig_atomic_t alarms;

static void on_alarm(int sig)
{
	static const struct itimerval off = { { 0, 0 }, { 0, 0 } };

	(void)sig;
	/* bounded, so that a wait that restarted its timeout on EINTR would still
	 * end (and fail the test) instead of hanging */
	if (++alarms >= 50)
		setitimer(ITIMER_REAL, &off, NULL);
}

static void test_port_eintr_does_not_restart_the_wait(void **state)
{
	struct pty p;
	df1_t *h = handle_new();
	struct sigaction sa, old;
	struct itimerval it = { { 0, 10000 }, { 0, 10000 } }, off = { { 0, 0 }, { 0, 0 } };
	uint8_t buf[8];
	ssize_t r;

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_open(h, p.path), 0);
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_alarm; /* no SA_RESTART: poll() sees EINTR every 10 ms */
	sigemptyset(&sa.sa_mask);
	assert_int_equal(sigaction(SIGALRM, &sa, &old), 0);
	alarms = 0;
	assert_int_equal(setitimer(ITIMER_REAL, &it, NULL), 0);
	r = h->port->read(h, buf, sizeof buf, df1_now_ms() + 100);
	assert_int_equal(setitimer(ITIMER_REAL, &off, NULL), 0);
	sigaction(SIGALRM, &old, NULL);
	assert_int_equal(r, 0);
	assert_true(alarms > 0);
	assert_true(alarms < 50); /* returned at its deadline while signals kept coming */
	df1_free(h);
	pty_free(&p);
}

static void test_port_termios_restored_on_close(void **state)
{
	struct pty p;
	struct termios before, during, after;
	df1_t *h = handle_new();

	(void)state;
	pty_make(&p);
	assert_int_equal(tcgetattr(p.master, &before), 0);
	assert_int_equal(df1_open(h, p.path), 0);
	assert_int_equal(tcgetattr(p.master, &during), 0);
	assert_false(during.c_lflag & (ICANON | ECHO | ISIG));
	assert_false(during.c_iflag & (ICRNL | IXON));
	assert_false(during.c_oflag & OPOST);
	assert_int_equal(during.c_cc[VMIN], 0);
	assert_int_equal(during.c_cc[VTIME], 0);
	assert_true(cfgetospeed(&during) == B19200);
	assert_true((during.c_cflag & (CLOCAL | CREAD)) == (CLOCAL | CREAD));
	df1_close(h);
	assert_int_equal(tcgetattr(p.master, &after), 0);
	assert_true(termios_same(&before, &after));

	/* df1_free() of an open handle restores too */
	assert_int_equal(df1_open(h, p.path), 0);
	df1_free(h);
	assert_int_equal(tcgetattr(p.master, &after), 0);
	assert_true(termios_same(&before, &after));
	pty_free(&p);
}

static void test_port_second_open_is_busy(void **state)
{
	struct pty p;
	df1_t *h1 = handle_new(), *h2 = handle_new();
	const struct df1_error_detail *e;

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_open(h1, p.path), 0);
	assert_int_equal(df1_open(h2, p.path), DF1_E_BUSY);
	assert_false(df1_is_open(h2));
	e = df1_last_error(h2);
	assert_int_equal(e->code, DF1_E_BUSY);
	assert_non_null(strstr(e->message, "port busy"));
	assert_non_null(strstr(e->message, p.path));
	assert_non_null(strstr(e->message, "in use by another process"));
	/* the holder is unaffected, and once it lets go the port is free */
	both_ways(h1, p.master);
	df1_close(h1);
	assert_int_equal(df1_open(h2, p.path), 0);
	df1_free(h2);
	df1_free(h1);
	pty_free(&p);
}

static void test_port_rs485_on_pty_is_notsup(void **state)
{
	struct pty p;
	struct termios before, after;
	df1_t *h = handle_new();
	const struct df1_error_detail *e;
	char want[96];

	(void)state;
	pty_make(&p);
	snprintf(want, sizeof want, "RS-485 mode not supported by %s", p.path);
	assert_int_equal(tcgetattr(p.master, &before), 0);

	/* asked before open: the open fails, nothing stays open, termios restored */
	assert_int_equal(df1_set_option(h, DF1_OPT_RS485, 1), 0);
	assert_int_equal(df1_open(h, p.path), DF1_E_NOTSUP);
	e = df1_last_error(h);
	assert_int_equal(e->code, DF1_E_NOTSUP);
	assert_string_equal(e->message, want);
	assert_false(df1_is_open(h));
	assert_int_equal(h->fd, -1);
	assert_int_equal(tcgetattr(p.master, &after), 0);
	assert_true(termios_same(&before, &after));

	/* asked on an open port: refused, the setting stays off, the port stays open */
	assert_int_equal(df1_set_option(h, DF1_OPT_RS485, 0), 0);
	assert_int_equal(df1_open(h, p.path), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_RS485, 1), DF1_E_NOTSUP);
	assert_string_equal(df1_last_error(h)->message, want);
	assert_int_equal(df1_get_option(h, DF1_OPT_RS485), 0);
	assert_true(df1_is_open(h));
	both_ways(h, p.master);
	df1_free(h);
	pty_free(&p);
}

/* The modem lines (the radio modem's keying, lib/link/radio.c): a pty's slave
 * side and a socket have none; the op says DF1_E_NOTSUP, not a failure. */
static void test_port_modem_lines_absent_is_notsup(void **state)
{
	struct pty p;
	int sv[2];
	unsigned st = 0;
	df1_t *h = handle_new();

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_open(h, p.path), 0);
	assert_non_null(h->port->modem);
	assert_int_equal(h->port->modem(h, PORT_LINE_RTS, 0, &st), DF1_E_NOTSUP);
	assert_int_equal(h->port->modem(h, 0, 0, &st), DF1_E_NOTSUP);
	df1_close(h);
	pty_free(&p);
	assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
	assert_int_equal(df1_open_fd(h, sv[0], false), 0);
	assert_int_equal(h->port->modem(h, 0, 0, &st), DF1_E_NOTSUP);
	df1_free(h);
	close(sv[0]);
	close(sv[1]);
}

static void test_port_bad_device_is_nodev(void **state)
{
	df1_t *h = handle_new();

	(void)state;
	assert_int_equal(df1_open(h, "/dev/ttyDF1-does-not-exist"), DF1_E_NODEV);
	assert_non_null(strstr(df1_last_error(h)->message, "/dev/ttyDF1-does-not-exist"));
	assert_false(df1_is_open(h));
	/* a character device that is not a terminal */
	assert_int_equal(df1_open(h, "/dev/null"), DF1_E_NODEV);
	assert_non_null(strstr(df1_last_error(h)->message, "not a serial port"));
	assert_false(df1_is_open(h));
	assert_int_equal(h->fd, -1);
	df1_free(h);
}

static void test_port_unreadable_device_is_perm(void **state)
{
	char path[] = "/tmp/df1-perm-XXXXXX";
	int fd;
	df1_t *h;

	(void)state;
	if (geteuid() == 0)
		skip(); /* root opens anything */
	fd = mkstemp(path);
	assert_true(fd >= 0);
	close(fd);
	assert_int_equal(chmod(path, 0), 0);
	h = handle_new();
	assert_int_equal(df1_open(h, path), DF1_E_PERM);
	assert_non_null(strstr(df1_last_error(h)->message, path));
	df1_free(h);
	unlink(path);
}

static void test_port_cancel_fd_ends_wait_with_intr(void **state)
{
	struct pty p;
	df1_t *h = handle_new();
	int pfd[2];
	uint8_t buf[8];
	char c;

	(void)state;
	pty_make(&p);
	assert_int_equal(pipe(pfd), 0);
	assert_int_equal(df1_open(h, p.path), 0);
	assert_int_equal(df1_set_cancel_fd(h, pfd[0]), 0);
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 20), 0);
	assert_int_equal(write(pfd[1], "x", 1), 1);
	/* far deadline: only the cancel fd can end this wait */
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 60000), DF1_E_INTR);
	assert_int_equal(df1_last_error(h)->code, DF1_E_INTR);
	/* cancellation wins over pending data */
	assert_int_equal(write(p.master, "\x10\x06", 2), 2);
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 60000), DF1_E_INTR);
	/* drained: waits work again */
	assert_int_equal(read(pfd[0], &c, 1), 1);
	port_read_exact(h, buf, 2, 2000);
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 20), 0);
	/* a pause on no descriptor: ends at the deadline, or on the cancel fd */
	assert_int_equal(port_wait(h, -1, 0, df1_now_ms() + 20), 0);
	assert_int_equal(write(pfd[1], "x", 1), 1);
	assert_int_equal(port_wait(h, -1, 0, df1_now_ms() + 60000), DF1_E_INTR);
	assert_int_equal(read(pfd[0], &c, 1), 1);
	/* no cancel fd */
	assert_int_equal(df1_set_cancel_fd(h, -1), 0);
	assert_int_equal(port_wait(h, -1, 0, df1_now_ms() + 20), 0);
	assert_int_equal(df1_set_cancel_fd(h, -5), DF1_E_INVAL);
	df1_free(h);
	close(pfd[0]);
	close(pfd[1]);
	pty_free(&p);
}

static void test_port_every_serial_combination_applied(void **state)
{
	static const int bauds[] = { 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200 };
	static const speed_t speeds[] = { B1200, B2400, B4800, B9600, B19200, B38400, B57600, B115200 };
	static const tcflag_t csize[] = { CS5, CS6, CS7, CS8 };
	static const char parities[] = { 'N', 'E', 'O' };
	struct pty p;
	df1_t *h = handle_new();
	size_t b, d, q;
	int s, hs, combos = 0;

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_open(h, p.path), 0);
	for (b = 0; b < 8; b++)
		for (d = 0; d < 4; d++)
			for (q = 0; q < 3; q++)
				for (s = 1; s <= 2; s++)
					for (hs = 0; hs <= 1; hs++) {
						struct termios t;

						assert_int_equal(df1_set_handshake(h, hs), 0);
						if (df1_set_serial(h, bauds[b], (int)d + 5, parities[q], s) != 0)
							fail_msg("%d %zu%c%d hs %d: %s", bauds[b], d + 5, parities[q], s, hs,
							         df1_last_error(h)->message);
						/* what the library asked for */
						assert_true((last_set.c_cflag & CSIZE) == csize[d]);
						assert_int_equal(!!(last_set.c_cflag & PARENB), parities[q] != 'N');
						assert_int_equal(!!(last_set.c_cflag & PARODD), parities[q] == 'O');
						assert_int_equal(!!(last_set.c_iflag & INPCK), parities[q] != 'N');
						/* what the port holds */
						assert_int_equal(tcgetattr(p.master, &t), 0);
						assert_true(cfgetospeed(&t) == speeds[b]);
						assert_true(cfgetispeed(&t) == speeds[b]);
						assert_int_equal(!!(t.c_cflag & CSTOPB), s == 2);
						assert_int_equal(!!(t.c_cflag & CRTSCTS), hs);
						assert_false(t.c_lflag & (ICANON | ECHO | ISIG));
						assert_false(t.c_iflag & (IXON | IXOFF | ICRNL));
						assert_int_equal(t.c_cc[VMIN], 0);
						assert_int_equal(t.c_cc[VTIME], 0);
						combos++;
					}
	assert_int_equal(combos, 8 * 4 * 3 * 2 * 2);
	/* settings made before open are applied by the open */
	df1_close(h);
	assert_int_equal(df1_set_serial(h, 2400, 7, 'e', 2), 0);
	assert_int_equal(df1_set_handshake(h, true), 0);
	n_set = 0;
	assert_int_equal(df1_open(h, p.path), 0);
	assert_true(n_set > 0);
	assert_true((last_set.c_cflag & (CSIZE | PARENB | PARODD | CSTOPB | CRTSCTS)) ==
	            (CS7 | PARENB | CSTOPB | CRTSCTS));
	/* an invalid setting on an open port changes nothing */
	assert_int_equal(df1_set_serial(h, 12345, 8, 'N', 1), DF1_E_CONFIG);
	assert_int_equal(h->cfg.baud, 2400);
	df1_free(h);
	pty_free(&p);
}

static void test_port_slave_closed_by_master_is_closed(void **state)
{
	struct pty p;
	df1_t *h = handle_new();
	uint8_t buf[8];

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_open(h, p.path), 0);
	pty_free(&p); /* the other end goes away: EIO/HUP on the slave */
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 2000), DF1_E_CLOSED);
	df1_free(h);
}

/* ---- fd backend ------------------------------------------------------- */

static void test_port_fd_socketpair_not_owned(void **state)
{
	int sv[2], fl;
	df1_t *h = handle_new();

	(void)state;
	assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
	fl = fcntl(sv[0], F_GETFL);
	assert_false(fl & O_NONBLOCK);
	assert_int_equal(df1_open_fd(h, sv[0], false), 0);
	assert_ptr_equal(h->port, &port_fd_ops);
	assert_true(fcntl(sv[0], F_GETFL) & O_NONBLOCK);
	both_ways(h, sv[1]);
	df1_close(h);
	/* still open, flags as they were */
	assert_int_equal(fcntl(sv[0], F_GETFL), fl);
	/* the other end closing: DF1_E_CLOSED */
	assert_int_equal(df1_open_fd(h, sv[0], false), 0);
	close(sv[1]);
	{
		uint8_t buf[4];

		assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 2000), DF1_E_CLOSED);
		/* writing to a closed socket: no SIGPIPE, DF1_E_CLOSED */
		assert_int_equal(h->port->write(h, buf, sizeof buf, df1_now_ms() + 2000), DF1_E_CLOSED);
	}
	df1_free(h);
	assert_true(fcntl(sv[0], F_GETFD) >= 0);
	close(sv[0]);
}

static void test_port_fd_owned_is_closed(void **state)
{
	int pfd[2];
	df1_t *h = handle_new();
	uint8_t buf[4];

	(void)state;
	assert_int_equal(pipe(pfd), 0);
	assert_int_equal(df1_open_fd(h, pfd[0], true), 0);
	assert_int_equal(write(pfd[1], "ab", 2), 2);
	port_read_exact(h, buf, 2, 2000);
	assert_memory_equal(buf, "ab", 2);
	close(pfd[1]);
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 2000), DF1_E_CLOSED);
	df1_close(h);
	assert_true(fcntl(pfd[0], F_GETFD) < 0 && errno == EBADF);
	/* invalid descriptors */
	assert_int_equal(df1_open_fd(h, -1, false), DF1_E_INVAL);
	assert_int_equal(df1_open_fd(h, pfd[0], false), DF1_E_INVAL);
	assert_false(df1_is_open(h));
	df1_free(h);
}

static void test_port_fd_write_blocked_times_out(void **state)
{
	static uint8_t big[4 << 20];
	int sv[2];
	df1_t *h = handle_new();

	(void)state;
	assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
	assert_int_equal(df1_open_fd(h, sv[0], true), 0);
	/* nobody reads sv[1]: the socket buffer fills and the deadline ends the write */
	assert_int_equal(h->port->write(h, big, sizeof big, df1_now_ms() + 100), DF1_E_TIMEOUT);
	assert_non_null(strstr(df1_last_error(h)->message, "bytes sent before the deadline"));
	df1_free(h);
	close(sv[1]);
}

/* df1sim serves a pty master: clients open and close the slave at will; the
 * server must see "no data" between them, never a hangup. */
static void test_port_fd_pty_master_survives_clients(void **state)
{
	struct pty p;
	df1_t *srv = handle_new(), *cli = handle_new();
	uint8_t buf[8];
	int round;

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_open_fd(srv, p.master, false), 0);
	assert_true(port_fd_peer(srv) >= 0);
	/* the pair is raw now: no echo of what the server writes */
	{
		struct termios t;

		assert_int_equal(tcgetattr(p.master, &t), 0);
		assert_false(t.c_lflag & (ECHO | ICANON));
	}
	assert_int_equal(srv->port->read(srv, buf, sizeof buf, df1_now_ms() + 20), 0);
	for (round = 0; round < 3; round++) {
		assert_int_equal(df1_open(cli, p.path), 0);
		assert_int_equal(cli->port->write(cli, (const uint8_t *)"\x10\x05", 2, df1_now_ms() + 2000), 2);
		port_read_exact(srv, buf, 2, 2000);
		assert_memory_equal(buf, "\x10\x05", 2);
		assert_int_equal(srv->port->write(srv, (const uint8_t *)"\x10\x06", 2, df1_now_ms() + 2000), 2);
		port_read_exact(cli, buf, 2, 2000);
		assert_memory_equal(buf, "\x10\x06", 2);
		df1_close(cli);
		/* no client: the server's read ends at its deadline with 0 */
		assert_int_equal(srv->port->read(srv, buf, sizeof buf, df1_now_ms() + 20), 0);
	}
	df1_close(srv);
	assert_int_equal(port_fd_peer(srv), -1);
	assert_true(fcntl(p.master, F_GETFD) >= 0); /* not owned: still open */
	df1_free(cli);
	df1_free(srv);
	pty_free(&p);
}

/* ---- listen-only ports and df1_recv_raw --------------------------------- */

/* Every way of transmitting on a listen-only handle fails with DF1_E_NOTSUP,
 * and nothing reaches the peer descriptor. */
static void listen_only_never_transmits(df1_t *h, int peer)
{
	static const uint8_t enq[] = { 0x10, 0x05 };
	struct pollfd p = { .fd = peer, .events = POLLIN };
	uint8_t buf[8];
	int16_t v;
	ssize_t n;

	assert_int_equal(h->port->write(h, enq, sizeof enq, df1_now_ms() + 100), DF1_E_NOTSUP);
	assert_non_null(strstr(df1_last_error(h)->message, "listen only"));
	assert_int_equal(link_send_raw(h, enq, sizeof enq), DF1_E_NOTSUP);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), DF1_E_NOTSUP);
	assert_int_equal(df1_link_test(h, 1), DF1_E_NOTSUP);
	/* nothing was sent: the peer has no data (a shut TCP side reads as EOF) */
	if (poll(&p, 1, 0) == 1) {
		n = read(peer, buf, sizeof buf);
		assert_true(n <= 0);
	}
}

static void test_port_listen_only_pty_reads_raw_never_writes(void **state)
{
	static const uint8_t line[] = { 0x10, 0x02, 0x01, 0x00, 0x10, 0x10, 0x10, 0x03, 0xAB };
	struct pty p;
	struct termios before, after;
	struct timespec t0, when = { 0, 0 };
	df1_t *h = handle_new(), *other = handle_new();
	uint8_t buf[64];
	size_t got = 0;
	uint64_t cnt = 0;
	int fd, pfd[2];

	(void)state;
	pty_make(&p);
	assert_int_equal(tcgetattr(p.master, &before), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_LISTEN_ONLY), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_LISTEN_ONLY, 2), DF1_E_CONFIG);
	assert_int_equal(df1_set_option(h, DF1_OPT_LISTEN_ONLY, 1), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_LISTEN_ONLY), 1);
	assert_int_equal(df1_port_fd(h), DF1_E_NOT_OPEN);
	assert_int_equal(df1_recv_raw(h, buf, sizeof buf, 0, NULL), DF1_E_NOT_OPEN);
	assert_int_equal(df1_set_serial(h, 38400, 8, 'N', 1), 0);
	assert_int_equal(df1_open(h, p.path), 0);
	/* read only, at the line settings, locked like any other open */
	fd = df1_port_fd(h);
	assert_true(fd >= 0);
	assert_int_equal(fcntl(fd, F_GETFL) & O_ACCMODE, O_RDONLY);
	assert_int_equal(tcgetattr(p.master, &after), 0);
	assert_true(cfgetispeed(&after) == B38400);
	assert_int_equal(df1_open(other, p.path), DF1_E_BUSY);
	/* the option is read at open: not changed on an open handle */
	assert_int_equal(df1_set_option(h, DF1_OPT_LISTEN_ONLY, 0), DF1_E_INVAL);
	assert_int_equal(df1_set_option(h, DF1_OPT_LISTEN_ONLY, 1), 0);

	/* nothing there: 0 at the deadline */
	assert_int_equal(df1_recv_raw(h, buf, sizeof buf, 20, &when), 0);
	assert_int_equal(df1_recv_raw(h, buf, sizeof buf, 0, NULL), 0);
	assert_int_equal(df1_recv_raw(h, NULL, 4, 0, NULL), DF1_E_INVAL);
	assert_int_equal(df1_recv_raw(h, buf, 0, 0, NULL), DF1_E_INVAL);
	assert_int_equal(df1_recv_raw(h, buf, sizeof buf, -2, NULL), DF1_E_INVAL);
	assert_int_equal(df1_recv_raw(NULL, buf, sizeof buf, 0, NULL), DF1_E_INVAL);

	/* bytes as they are, DLEs and all, with a wall-clock time */
	clock_gettime(CLOCK_REALTIME, &t0);
	assert_int_equal(write(p.master, line, sizeof line), (ssize_t)sizeof line);
	while (got < sizeof line) {
		int n = df1_recv_raw(h, buf + got, sizeof buf - got, 2000, &when);

		assert_true(n > 0);
		got += (size_t)n;
		assert_true(when.tv_sec > t0.tv_sec ||
		            (when.tv_sec == t0.tv_sec && when.tv_nsec >= t0.tv_nsec));
	}
	assert_int_equal(got, sizeof line);
	assert_memory_equal(buf, line, sizeof line);
	assert_int_equal(df1_counter(h, 2561, &cnt), 0);
	assert_int_equal(cnt, sizeof line);

	/* a small buffer takes what fits; the rest comes next */
	assert_int_equal(write(p.master, line, 4), 4);
	got = 0;
	while (got < 4) {
		int n = df1_recv_raw(h, buf + got, 1, 2000, NULL);

		assert_int_equal(n, 1);
		got++;
	}
	assert_memory_equal(buf, line, 4);

	/* the cancel fd ends a wait without a deadline */
	assert_int_equal(pipe(pfd), 0);
	assert_int_equal(write(pfd[1], "x", 1), 1);
	assert_int_equal(df1_set_cancel_fd(h, pfd[0]), 0);
	assert_int_equal(df1_recv_raw(h, buf, sizeof buf, -1, NULL), DF1_E_INTR);
	assert_int_equal(df1_set_cancel_fd(h, -1), 0);
	close(pfd[0]);
	close(pfd[1]);

	listen_only_never_transmits(h, p.master);

	/* closed: the line's own settings are back, and the port is free */
	df1_close(h);
	assert_int_equal(tcgetattr(p.master, &after), 0);
	assert_true(termios_same(&before, &after));
	assert_int_equal(df1_open(other, p.path), 0);
	df1_free(other);
	df1_free(h);
	pty_free(&p);
}

/* A listen-only tap is refused like any other open while a normal user
 * holds the port. */
static void test_port_listen_only_busy_like_any_open(void **state)
{
	struct pty p;
	df1_t *h1 = handle_new(), *tap = handle_new();

	(void)state;
	pty_make(&p);
	assert_int_equal(df1_set_option(tap, DF1_OPT_LISTEN_ONLY, 1), 0);
	assert_int_equal(df1_open(h1, p.path), 0);
	assert_int_equal(df1_open(tap, p.path), DF1_E_BUSY);
	assert_non_null(strstr(df1_last_error(tap)->message, "port busy"));
	assert_false(df1_is_open(tap));
	df1_close(h1);
	assert_int_equal(df1_open(tap, p.path), 0);
	df1_free(tap);
	df1_free(h1);
	pty_free(&p);
}

/* An unknown baud rate is a configuration error, never a fallback. */
static void test_port_unknown_baud_is_config_error(void **state)
{
	df1_t *h = handle_new();

	(void)state;
	assert_int_equal(df1_set_serial(h, 14400, 8, 'N', 1), DF1_E_CONFIG);
	assert_non_null(strstr(df1_last_error(h)->message, "invalid baud rate 14400"));
	df1_free(h);
}

/* The end of a FIFO given with df1_open_fd is DF1_E_CLOSED after its bytes. */
static void test_port_recv_raw_fifo_end_is_closed(void **state)
{
	df1_t *h = handle_new();
	uint8_t buf[16];
	int pfd[2], n;

	(void)state;
	assert_int_equal(pipe(pfd), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_LISTEN_ONLY, 1), 0);
	assert_int_equal(df1_open_fd(h, pfd[0], true), 0);
	assert_int_equal(df1_port_fd(h), pfd[0]);
	assert_int_equal(write(pfd[1], "\x10\x06", 2), 2);
	close(pfd[1]);
	n = df1_recv_raw(h, buf, sizeof buf, 2000, NULL);
	assert_int_equal(n, 2);
	assert_memory_equal(buf, "\x10\x06", 2);
	assert_int_equal(df1_recv_raw(h, buf, sizeof buf, 2000, NULL), DF1_E_CLOSED);
	df1_free(h); /* owned: closes pfd[0] */
}

/* ---- TCP backend ------------------------------------------------------ */

static int tcp_listener(int family, int *port)
{
	struct sockaddr_storage ss;
	socklen_t len;
	int fd = socket(family, SOCK_STREAM | SOCK_CLOEXEC, 0), one = 1;

	if (fd < 0)
		return -1;
	setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
	memset(&ss, 0, sizeof ss);
	if (family == AF_INET) {
		struct sockaddr_in *a = (struct sockaddr_in *)&ss;

		a->sin_family = AF_INET;
		a->sin_addr.s_addr = htonl(INADDR_LOOPBACK);
		len = sizeof *a;
	} else {
		struct sockaddr_in6 *a = (struct sockaddr_in6 *)&ss;

		a->sin6_family = AF_INET6;
		a->sin6_addr = in6addr_loopback;
		len = sizeof *a;
	}
	if (bind(fd, (struct sockaddr *)&ss, len) < 0 || listen(fd, 4) < 0) {
		close(fd);
		return -1;
	}
	len = sizeof ss;
	getsockname(fd, (struct sockaddr *)&ss, &len);
	*port = ntohs(family == AF_INET ? ((struct sockaddr_in *)&ss)->sin_port
	                                : ((struct sockaddr_in6 *)&ss)->sin6_port);
	return fd;
}

static int tcp_accept(int lfd)
{
	struct pollfd p = { .fd = lfd, .events = POLLIN };

	assert_int_equal(poll(&p, 1, 5000), 1);
	return accept4(lfd, NULL, NULL, SOCK_CLOEXEC);
}

static void tcp_round_trip(int family, const char *fmt)
{
	int port = 0, lfd, cfd;
	char target[64];
	df1_t *h = handle_new();
	uint8_t buf[8];

	lfd = tcp_listener(family, &port);
	if (lfd < 0) {
		df1_free(h);
		skip(); /* no IPv6 loopback here */
	}
	snprintf(target, sizeof target, fmt, port);
	assert_int_equal(df1_open(h, target), 0);
	assert_ptr_equal(h->port, &port_tcp_ops);
	assert_ptr_equal(h->port->write, port_send_fd); /* send(MSG_NOSIGNAL) */
	cfd = tcp_accept(lfd);
	assert_true(cfd >= 0);
	both_ways(h, cfd);
	/* nothing sent: 0 at the deadline */
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 20), 0);
	/* peer closes: DF1_E_CLOSED naming host:port */
	close(cfd);
	assert_int_equal(h->port->read(h, buf, sizeof buf, df1_now_ms() + 2000), DF1_E_CLOSED);
	assert_int_equal(df1_last_error(h)->code, DF1_E_CLOSED);
	assert_non_null(strstr(df1_last_error(h)->message, "closed"));
	df1_close(h);
	assert_false(df1_is_open(h));
	df1_free(h);
	close(lfd);
}

static void test_port_tcp_ipv4(void **state)
{
	(void)state;
	tcp_round_trip(AF_INET, "tcp://127.0.0.1:%d");
}

static void test_port_tcp_localhost_name(void **state)
{
	(void)state;
	tcp_round_trip(AF_INET, "tcp://localhost:%d");
}

static void test_port_tcp_ipv6(void **state)
{
	(void)state;
	tcp_round_trip(AF_INET6, "tcp://[::1]:%d");
}

/* URI scheme names are case-insensitive (RFC 3986 3.1; df1_open(3)) */
static void test_port_tcp_scheme_any_case(void **state)
{
	(void)state;
	tcp_round_trip(AF_INET, "TCP://127.0.0.1:%d");
	tcp_round_trip(AF_INET, "Tcp://127.0.0.1:%d");
	tcp_round_trip(AF_INET, "TCP:127.0.0.1:%d");
}

static void test_port_tcp_refused(void **state)
{
	struct sockaddr_in a;
	socklen_t len = sizeof a;
	int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
	char target[64], hostport[32];
	df1_t *h = handle_new();
	const struct df1_error_detail *e;

	(void)state;
	/* bound but not listening: connections to it are refused */
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(bind(fd, (struct sockaddr *)&a, sizeof a), 0);
	getsockname(fd, (struct sockaddr *)&a, &len);
	snprintf(target, sizeof target, "tcp://127.0.0.1:%d", ntohs(a.sin_port));
	snprintf(hostport, sizeof hostport, "127.0.0.1:%d", ntohs(a.sin_port));
	assert_int_equal(df1_open(h, target), DF1_E_SYS);
	e = df1_last_error(h);
	assert_int_equal(e->sys_errno, ECONNREFUSED);
	assert_non_null(strstr(e->message, hostport));
	assert_non_null(strstr(e->message, "refused"));
	assert_false(df1_is_open(h));
	assert_int_equal(h->fd, -1);
	df1_free(h);
	close(fd);
}

/* Listen-only TCP: the normal connect, then our sending side is shut (the peer
 * reads EOF at once) and bytes from the peer come through df1_recv_raw. */
static void test_port_listen_only_tcp_shut_for_sending(void **state)
{
	static const uint8_t bytes[] = { 0x10, 0x02, 0x00, 0x10, 0x03 };
	int port = 0, lfd, cfd;
	char target[64];
	df1_t *h = handle_new();
	uint8_t buf[16];
	size_t got = 0;
	struct pollfd p;

	(void)state;
	lfd = tcp_listener(AF_INET, &port);
	assert_true(lfd >= 0);
	snprintf(target, sizeof target, "tcp://127.0.0.1:%d", port);
	assert_int_equal(df1_set_option(h, DF1_OPT_LISTEN_ONLY, 1), 0);
	assert_int_equal(df1_open(h, target), 0);
	cfd = tcp_accept(lfd);
	assert_true(cfd >= 0);
	p = (struct pollfd){ .fd = cfd, .events = POLLIN };
	assert_int_equal(poll(&p, 1, 5000), 1);
	assert_int_equal(read(cfd, buf, sizeof buf), 0); /* our FIN: nothing will ever come */
	assert_int_equal(write(cfd, bytes, sizeof bytes), (ssize_t)sizeof bytes);
	while (got < sizeof bytes) {
		int n = df1_recv_raw(h, buf + got, sizeof buf - got, 2000, NULL);

		assert_true(n > 0);
		got += (size_t)n;
	}
	assert_memory_equal(buf, bytes, sizeof bytes);
	listen_only_never_transmits(h, cfd);
	/* the peer goes: DF1_E_CLOSED */
	close(cfd);
	assert_int_equal(df1_recv_raw(h, buf, sizeof buf, 2000, NULL), DF1_E_CLOSED);
	df1_free(h);
	close(lfd);
}

/* The listen-only connect has the normal deadline: a listener whose accept
 * queue is full drops our SYN, and df1_open gives up after the handle's
 * timeout (at least 1000 ms) with ETIMEDOUT; the cancel fd ends it sooner. */
static void test_port_listen_only_tcp_connect_deadline(void **state)
{
	struct sockaddr_in a;
	int lfd, port = 0, fill[8], nfill = 0, pfd[2];
	bool full = false;
	char target[64];
	df1_t *h = handle_new();
	int64_t t0;

	(void)state;
	lfd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
	assert_true(lfd >= 0);
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(bind(lfd, (struct sockaddr *)&a, sizeof a), 0);
	assert_int_equal(listen(lfd, 0), 0);
	{
		socklen_t len = sizeof a;

		assert_int_equal(getsockname(lfd, (struct sockaddr *)&a, &len), 0);
		port = ntohs(a.sin_port);
	}
	/* fill the accept queue until a connect is left hanging */
	while (nfill < 8 && !full) {
		struct pollfd p;
		int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);

		assert_true(fd >= 0);
		fill[nfill++] = fd;
		if (connect(fd, (struct sockaddr *)&a, sizeof a) == 0)
			continue;
		assert_int_equal(errno, EINPROGRESS);
		p = (struct pollfd){ .fd = fd, .events = POLLOUT };
		full = poll(&p, 1, 300) == 0;
	}
	if (!full) {
		for (int i = 0; i < nfill; i++)
			close(fill[i]);
		close(lfd);
		df1_free(h);
		skip(); /* this kernel takes every connection */
	}
	snprintf(target, sizeof target, "tcp://127.0.0.1:%d", port);
	assert_int_equal(df1_set_option(h, DF1_OPT_LISTEN_ONLY, 1), 0);
	assert_int_equal(df1_set_timeout_ms(h, 0), 0);
	t0 = df1_now_ms();
	assert_int_equal(df1_open(h, target), DF1_E_SYS);
	assert_true(df1_now_ms() - t0 < 10000);
	assert_int_equal(df1_last_error(h)->sys_errno, ETIMEDOUT);
	assert_non_null(strstr(df1_last_error(h)->message, "no answer within 1000 ms"));
	assert_false(df1_is_open(h));
	/* a cancel fd that is readable ends the connect at once */
	assert_int_equal(pipe(pfd), 0);
	assert_int_equal(write(pfd[1], "x", 1), 1);
	assert_int_equal(df1_set_cancel_fd(h, pfd[0]), 0);
	assert_int_equal(df1_open(h, target), DF1_E_INTR);
	assert_false(df1_is_open(h));
	close(pfd[0]);
	close(pfd[1]);
	for (int i = 0; i < nfill; i++)
		close(fill[i]);
	close(lfd);
	df1_free(h);
}

static void test_port_tcp_bad_targets(void **state)
{
	static const char *bad[] = {
		"tcp://", "tcp://127.0.0.1", "tcp://127.0.0.1:", "tcp://:502", "tcp://127.0.0.1:0",
		"tcp://127.0.0.1:65536", "tcp://127.0.0.1:12x", "tcp://::1:502", "tcp://[::1]502",
		"tcp://[::1", "tcp://127.0.0.1:-5", "TCP://", "TCP://127.0.0.1",
	};
	df1_t *h = handle_new();
	size_t i;

	(void)state;
	for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		assert_int_equal(df1_open(h, bad[i]), DF1_E_INVAL);
		assert_non_null(strstr(df1_last_error(h)->message, "tcp://HOST:PORT"));
		assert_false(df1_is_open(h));
	}
	df1_free(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_port_pty_bytes_both_ways),
		cmocka_unit_test(test_port_read_without_data_returns_zero_at_deadline),
		cmocka_unit_test(test_port_eintr_does_not_restart_the_wait),
		cmocka_unit_test(test_port_termios_restored_on_close),
		cmocka_unit_test(test_port_second_open_is_busy),
		cmocka_unit_test(test_port_rs485_on_pty_is_notsup),
		cmocka_unit_test(test_port_modem_lines_absent_is_notsup),
		cmocka_unit_test(test_port_bad_device_is_nodev),
		cmocka_unit_test(test_port_unreadable_device_is_perm),
		cmocka_unit_test(test_port_cancel_fd_ends_wait_with_intr),
		cmocka_unit_test(test_port_every_serial_combination_applied),
		cmocka_unit_test(test_port_slave_closed_by_master_is_closed),
		cmocka_unit_test(test_port_fd_socketpair_not_owned),
		cmocka_unit_test(test_port_fd_owned_is_closed),
		cmocka_unit_test(test_port_fd_write_blocked_times_out),
		cmocka_unit_test(test_port_fd_pty_master_survives_clients),
		cmocka_unit_test(test_port_tcp_ipv4),
		cmocka_unit_test(test_port_tcp_localhost_name),
		cmocka_unit_test(test_port_tcp_ipv6),
		cmocka_unit_test(test_port_tcp_scheme_any_case),
		cmocka_unit_test(test_port_tcp_refused),
		cmocka_unit_test(test_port_tcp_bad_targets),
		cmocka_unit_test(test_port_listen_only_pty_reads_raw_never_writes),
		cmocka_unit_test(test_port_listen_only_busy_like_any_open),
		cmocka_unit_test(test_port_unknown_baud_is_config_error),
		cmocka_unit_test(test_port_recv_raw_fifo_end_is_closed),
		cmocka_unit_test(test_port_listen_only_tcp_shut_for_sending),
		cmocka_unit_test(test_port_listen_only_tcp_connect_deadline),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
