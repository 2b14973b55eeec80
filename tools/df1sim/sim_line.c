/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_line.c - the line with fixed settings (tools/df1sim/sim_line.h): the
 * UART model and the relay thread between the master and the handle.
 *
 * The model works in bit times: a character is a start bit (0), the data
 * bits least significant first, the parity bit if any and the stop bits (1),
 * then the idle line (1). The receiver waits for a fall from 1 to 0, checks
 * the start bit at its middle, samples each further bit at its own middle at
 * its own rate, and reads a character with a bad parity or stop bit as 0x00,
 * as Linux's tty layer does without IGNPAR or PARMRK (termios(3)). Time is
 * counted in units of 1 / (2 * tx baud * rx baud) s, so every sampling
 * instant is an integer: a sender's bit lasts 2 * rx baud units, a
 * receiver's 2 * tx baud.
 *
 * Paced (char_us > 0, --line-baud in full duplex), the relay is also the
 * line's full-duplex UART: each direction goes through its own queue at the
 * line's rate (tools/df1sim/sim_pace.c) and the handle runs unpaced.
 */
#include "df1sim/sim_line.h"

#include <errno.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

void sim_msg(const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, "df1sim: ");
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
}

bool sim_uart_parse(const char *s, struct sim_uart *u)
{
	char *end;
	long baud = strtol(s, &end, 10);

	if (end == s || baud < 50 || baud > 4000000)
		return false;
	u->baud = (int)baud;
	u->data_bits = 8;
	u->parity = 'N';
	u->stop_bits = 1;
	if (*end == '\0')
		return true;
	if (*end != ',' || strlen(end + 1) != 3 || end[1] < '5' || end[1] > '8' ||
	    !strchr("NEOneo", end[2]) || (end[3] != '1' && end[3] != '2'))
		return false;
	u->data_bits = end[1] - '0';
	u->parity = (char)(end[2] & ~0x20);
	u->stop_bits = end[3] - '0';
	return true;
}

const char *sim_uart_text(const struct sim_uart *u, char *buf, size_t cap)
{
	snprintf(buf, cap, "%d %d%c%d", u->baud, u->data_bits, u->parity, u->stop_bits);
	return buf;
}

static int sim_parity_bit(unsigned v, int bits, char parity)
{
	int ones = __builtin_popcount(v & ((1u << bits) - 1));

	return parity == 'E' ? ones & 1 : !(ones & 1);
}

/* The sender's bits of one character, then idle: bits[] and how many. */
static int sim_uart_bits(const struct sim_uart *tx, uint8_t byte, uint8_t bits[16])
{
	int n = 0;

	bits[n++] = 0;
	for (int i = 0; i < tx->data_bits; i++)
		bits[n++] = (byte >> i) & 1;
	if (tx->parity != 'N')
		bits[n++] = (uint8_t)sim_parity_bit(byte, tx->data_bits, tx->parity);
	for (int i = 0; i < tx->stop_bits; i++)
		bits[n++] = 1;
	return n;
}

static size_t sim_uart_one(const struct sim_uart *tx, const struct sim_uart *rx, uint8_t byte,
                           uint8_t *out, size_t cap)
{
	uint8_t bits[16];
	int nbits = sim_uart_bits(tx, byte, bits);
	int64_t tb = 2 * (int64_t)rx->baud, rb = 2 * (int64_t)tx->baud; /* bit lengths in units */
	int64_t t = 0;
	size_t n = 0;

#define LEVEL(when) ((when) / tb < nbits ? bits[(when) / tb] : 1)
	while (n < cap) {
		int64_t edge = -1, s;
		unsigned v = 0;
		bool bad = false;
		int k;

		for (int i = 0; i < nbits; i++) {      /* the next fall from 1 to 0 at or after t */
			if (bits[i] == 0 && (i == 0 || bits[i - 1] == 1) && i * tb >= t) {
				edge = i * tb;
				break;
			}
		}
		if (edge < 0)
			break;
		if (LEVEL(edge + rb / 2) != 0) {       /* a glitch, not a start bit */
			t = edge + rb / 2 + 1;
			continue;
		}
		for (k = 0; k < rx->data_bits; k++) {
			s = edge + rb / 2 + (int64_t)(k + 1) * rb;
			v |= (unsigned)LEVEL(s) << k;
		}
		if (rx->parity != 'N') {
			s = edge + rb / 2 + (int64_t)(++k) * rb;
			bad = LEVEL(s) != sim_parity_bit(v, rx->data_bits, rx->parity);
		}
		s = edge + rb / 2 + (int64_t)(k + 1) * rb;  /* the stop bit */
		if (LEVEL(s) != 1)
			bad = true;
		out[n++] = bad ? 0x00 : (uint8_t)v;
		t = s;
	}
#undef LEVEL
	return n;
}

size_t sim_uart_garble(const struct sim_uart *tx, const struct sim_uart *rx, const uint8_t *in,
                       size_t n, uint8_t *out, size_t cap)
{
	size_t o = 0;

	for (size_t i = 0; i < n && o < cap; i++) {
		if (tx->baud == rx->baud && tx->data_bits == rx->data_bits && tx->parity == rx->parity)
			out[o++] = in[i];
		else
			o += sim_uart_one(tx, rx, in[i], out + o, cap - o);
	}
	return o;
}

static int sim_speed_baud(speed_t s)
{
	static const struct { speed_t s; int baud; } map[] = {
		{ B300, 300 }, { B600, 600 }, { B1200, 1200 }, { B2400, 2400 }, { B4800, 4800 },
		{ B9600, 9600 }, { B19200, 19200 }, { B38400, 38400 }, { B57600, 57600 },
		{ B115200, 115200 }, { B230400, 230400 },
	};

	for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
		if (map[i].s == s)
			return map[i].baud;
	return 0;
}

/* The master's settings on a pty: the termios its side set (tcgetattr on the
 * master reads the slave's). Linux's pty forces CS8 and no parity, so only
 * the rate can be seen: data bits and parity are taken as the line's. */
static void sim_relay_pty_master(struct sim_relay *r)
{
	struct termios t;
	int baud;

	if (tcgetattr(r->wire, &t) < 0)
		return;
	baud = sim_speed_baud(cfgetospeed(&t));
	if (baud && baud != r->master.baud) {
		char a[32];

		r->master.baud = baud;
		if (r->verbose)
			sim_msg("line: the master's termios says %d baud (the line: %s)%s", baud,
			        sim_uart_text(&r->line, a, sizeof a),
			        baud == r->line.baud ? "" : ": what passes is garbled");
	}
}

/* Bytes from the master to the PLC: 0 on, -1 the relay ends. */
static int sim_relay_in(struct sim_relay *r)
{
	uint8_t in[256], data[256], out[256 * 12];
	ssize_t n = read(r->wire, in, sizeof in);
	size_t m;

	if (n <= 0)
		return n < 0 && (errno == EINTR || errno == EAGAIN) ? 0 : -1;
	if (r->kind == SIM_RELAY_PTY) {
		if (r->line.baud)
			sim_relay_pty_master(r);
		memcpy(data, in, (size_t)n);
		m = (size_t)n;
	} else {
		m = sim_rfc2217_input(r, in, (size_t)n, data, sizeof data);
	}
	if (r->line.baud && r->master.baud)
		m = sim_uart_garble(&r->master, &r->line, data, m, out, sizeof out);
	else
		memcpy(out, data, m);
	if (m == 0)
		return 0;
	if (r->char_us > 0)
		return sim_pace_put(&r->to_lib, r->char_us, out, m) ? 0 : -1;
	return sim_relay_emit_lib(r, out, m);
}

int sim_relay_emit_lib(struct sim_relay *r, const uint8_t *b, size_t n)
{
	return write(r->lib, b, n) == (ssize_t)n ? 0 : -1;
}

int sim_relay_emit_wire(struct sim_relay *r, const uint8_t *g, size_t m)
{
	uint8_t esc[512];
	size_t done = 0;

	while (done < m) {
		size_t used = m - done, k;
		const uint8_t *p = g + done;

		if (r->kind == SIM_RELAY_RFC2217) {
			k = sim_rfc2217_output(g + done, m - done, esc, sizeof esc, &used);
			p = esc;
		} else {
			k = used;
		}
		if (write(r->wire, p, k) != (ssize_t)k)
			return -1;
		done += used;
	}
	return 0;
}

/* Bytes from the PLC to the master. */
static int sim_relay_out(struct sim_relay *r)
{
	uint8_t in[256], g[256 * 12];
	ssize_t n = read(r->lib, in, sizeof in);
	size_t m;

	if (n <= 0)
		return n < 0 && (errno == EINTR || errno == EAGAIN) ? 0 : -1;
	if (r->kind == SIM_RELAY_PTY && r->line.baud)
		sim_relay_pty_master(r);
	if (r->line.baud && r->master.baud)
		m = sim_uart_garble(&r->line, &r->master, in, (size_t)n, g, sizeof g);
	else {
		memcpy(g, in, (size_t)n);
		m = (size_t)n;
	}
	if (r->char_us > 0)
		return sim_pace_put(&r->to_wire, r->char_us, g, m) ? 0 : -1;
	return sim_relay_emit_wire(r, g, m);
}

/* The poll's wait: until the next paced byte is due, else none. */
static struct timespec *sim_relay_wait(struct sim_relay *r, struct timespec *ts)
{
	int64_t a = sim_pace_wait_us(&r->to_lib), b = sim_pace_wait_us(&r->to_wire), w;

	w = a < 0 ? b : b < 0 ? a : a < b ? a : b;
	if (w < 0)
		return NULL;
	ts->tv_sec = (time_t)(w / 1000000);
	ts->tv_nsec = (long)(w % 1000000) * 1000;
	return ts;
}

static void *sim_relay_main(void *arg)
{
	struct sim_relay *r = arg;

	for (;;) {
		/* a full queue takes nothing more until it drains (the sender waits, as on flow control) */
		struct pollfd p[2] = {
			{ r->wire, r->to_lib.len + 256 * 12 <= SIM_PACE_MAX ? POLLIN : 0, 0 },
			{ r->lib, r->to_wire.len + 256 * 12 <= SIM_PACE_MAX ? POLLIN : 0, 0 },
		};
		struct timespec ts;

		if (r->char_us > 0 && (sim_pace_flush(r, &r->to_lib, sim_relay_emit_lib) < 0 ||
		                       sim_pace_flush(r, &r->to_wire, sim_relay_emit_wire) < 0))
			break;
		if (ppoll(p, 2, sim_relay_wait(r, &ts), NULL) < 0) {
			if (errno == EINTR)
				continue;
			break;
		}
		if ((p[0].revents & (POLLIN | POLLHUP | POLLERR)) && sim_relay_in(r) < 0)
			break;
		if ((p[1].revents & (POLLIN | POLLHUP | POLLERR)) && sim_relay_out(r) < 0)
			break;
	}
	/* the handle sees the end of its socket: DF1_E_CLOSED, as a client gone */
	shutdown(r->lib, SHUT_RDWR);
	return NULL;
}

int sim_relay_start(struct sim_relay *r, int *lib_fd)
{
	int sp[2];

	if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sp) < 0)
		return -1;
	r->lib = sp[1];
	r->master = r->line;          /* until the master says otherwise */
	if (r->kind == SIM_RELAY_PTY)
		r->master.baud = 0;       /* not seen yet: the first look at the termios says it */
	if (r->kind == SIM_RELAY_RFC2217 && !(r->rfc = sim_rfc2217_new())) {
		close(sp[0]);
		close(sp[1]);
		errno = ENOMEM;
		return -1;
	}
	errno = pthread_create(&r->thread, NULL, sim_relay_main, r);
	if (errno) {
		close(sp[0]);
		close(sp[1]);
		free(r->rfc);
		r->rfc = NULL;
		return -1;
	}
	r->started = true;
	*lib_fd = sp[0];
	return 0;
}

void sim_relay_join(struct sim_relay *r)
{
	if (!r->started)
		return;
	pthread_join(r->thread, NULL);
	r->started = false;
	close(r->lib);
	if (r->own_wire)
		close(r->wire);
	free(r->rfc);
	r->rfc = NULL;
}

int sim_relay_open(df1_t *h, struct sim_relay *r, enum sim_relay_kind kind, int wire,
                   const struct sim_uart *line, int verbose)
{
	int fd, rc;

	r->kind = kind;
	r->wire = wire;
	r->own_wire = true;
	r->line = *line;
	r->verbose = verbose;
	if (sim_relay_start(r, &fd) < 0) {
		sim_msg("relay: %s", strerror(errno));
		close(wire);
		return DF1_E_SYS;
	}
	rc = df1_open_fd(h, fd, true);
	if (rc < 0) {
		close(fd);              /* the relay sees its end go, and ends */
		sim_relay_join(r);
	}
	return rc;
}
