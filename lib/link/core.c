/* SPDX-License-Identifier: MPL-2.0 */
/*
 * core.c - what every DF1 link mode shares (doc/PROTOCOL.md 1-2, doc/ARCHITECTURE.md 4,
 * doc/REQUIREMENTS.md 004): setup, transmission with TX_Delay, line pacing, trace, echo
 * discard and the character counters; symbol reception with deadlines;
 * duplicate detection; the master's reply matching; the responder's reply
 * queue and where faults act. Used by full.c (full-duplex peer) and half.c
 * (half-duplex master and slave); link.c above them picks the mode. It calls
 * neither of them. The fault dice are in fault.c.
 *
 * Decisions the sources leave open (documented here, relied on by tests):
 *  - The receiver's last-response variable starts as NAK: an ENQ before any
 *    frame was taken must make the sender retransmit, not believe a frame got
 *    through (doc/PROTOCOL.md 1.7: noise also sets NAK).
 *  - Every wait is a port read against an absolute deadline. A read that
 *    returns 0 means its deadline passed (port contract); the link does not
 *    second-guess it with the clock. A symbol under way when the deadline
 *    passes gets until its last byte + the inter-character gap (timeout_ms,
 *    clamped to 100..1000 ms) to finish; a symbol cut short is 2518 and sets
 *    the last response to NAK.
 *  - Full-duplex master: ACK timeout -> DLE ENQ, at most enq_retries ENQs, the
 *    next timeout is DF1_E_ENQ_LIMIT (the serial-tap capture: three ENQs 1 s
 *    apart, then the sender gave up). NAK (also the peer's NAK answer to an ENQ)
 *    -> retransmit, at most nak_retries times, the next NAK is DF1_E_NAK_LIMIT.
 *    After the ACK the reply is awaited max(timeout_ms, cmd_timeout_ms). A
 *    matching reply that arrives before the ACK (ACK lost in noise) completes
 *    the transaction: the reply proves delivery.
 *  - A DLE NAK answering a frame of ours is 2517 NTC_RCVD_NAK_SYMBOL (and a
 *    retransmission); one when no frame of ours waits for a response is
 *    2511 ERR_RCVD_NAK_SYMBOL, counted (2534) and otherwise ignored.
 *  - Replies are matched on the full 16-bit TNS and SRC == the command's DST.
 *    DST is not compared: behind a 1770-KF2 the reply's DST is the KF2's node,
 *    not our SRC (doc/PROTOCOL.md 1.9, M p.14-3). CMD must be the command's CMD | 40h, or
 *    the transaction ends with DF1_E_BAD_FUNCTION (2505).
 *  - Duplicate detection keeps the first 6 bytes of the last message accepted
 *    per station (h->stations[]): in full duplex and on the half-duplex master
 *    keyed by the SRC / the polled station, on the half-duplex slave by the
 *    addressed STN. A duplicate is ACKed and dropped (2549, 2524), not
 *    answered: the reply of the message it repeats has its own retries. One
 *    whose bytes differ (a length and a hash are kept too) is a master that
 *    started again on its last TNS: the responder drops the reply it still
 *    holds under that header, which is not the answer to it.
 *  - A command frame received by a full-duplex master while its commands are
 *    on the line is ACKed and answered through the responder of
 *    df1_set_responder, or STS 10h without one (peer.c; doc/PROTOCOL.md 1.10).
 *  - Full duplex has no Active Station List (one peer on a point-to-point link);
 *    the list and its single probing poll are the half-duplex master's.
 *  - 2525/2526 count frames on the wire (retransmissions and duplicates
 *    included; a frame with a bad check is 2546/2547, not 2526); 2527 and
 *    2529 count distinct command / reply messages (retransmissions are 2541).
 *    2561 counts every byte read, including the echo discarded on 2-wire
 *    lines. Port read errors (2551) are counted by the port backends.
 *  - Full-duplex responder: one reply in flight; a new command supersedes a
 *    reply still waiting for its ACK (the master has moved on). With a queue
 *    (df1_server_set_max_queue) the replies go out in command order instead,
 *    each after the ACK of the one before, and a command beyond the queue is
 *    NAKed and not run (doc/PROTOCOL.md 1.7: a full message sink).
 *  - Faults: DROP_ACK and NAK_COMMAND act on new commands only (duplicates are
 *    ACKed), so one dropped ACK leads to exactly one execution. DROP_ACK leaves
 *    the last response at ACK, as a lost ACK would: an ENQ then gets the ACK.
 *    STALE_REPLY sends a copy of the reply with TNS - 2 first; CORRUPT_REPLY
 *    inverts the last check byte of the first transmission; NOISE puts 3 random
 *    non-DLE bytes before a reply frame; DELAY_REPLY holds the reply back for
 *    `value` ms while the link keeps answering; SILENT_STATION ignores frames
 *    (and, in full duplex, the ENQs that follow them) for station `value`, or
 *    for every station and every ENQ with value FAULT_SILENT_ALL (256).
 */
#include "link/link.h"

#include <poll.h>
#include <string.h>

#include "link/link_int.h"

/* ------------------------------------------------------------------------
 * Setup
 * ------------------------------------------------------------------------ */

/* The decoder follows the configuration (the setters may change it at any time). */
int link_setup(struct df1 *h)
{
	unsigned opts;

	if (!h->port || h->fd < 0)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "handle is not open");
	opts = link_decoder_opts(h);
	if (h->dec.max_len == 0 || h->dec.check != h->cfg.check || h->dec.opts != opts)
		frame_decoder_init(&h->dec, h->cfg.check, opts);
	if (h->last_response != DF1_ACK && h->last_response != DF1_NAK)
		h->last_response = DF1_NAK;
	return 0;
}

/* The check we send with: the configured one; AUTO (decoder only) answers in
 * what the decoder has locked onto. */
enum df1_check link_tx_check(const struct df1 *h)
{
	if (h->cfg.check == DF1_CHECK_BCC || h->cfg.check == DF1_CHECK_CRC)
		return h->cfg.check;
	return h->dec.locked == DF1_CHECK_BCC ? DF1_CHECK_BCC : DF1_CHECK_CRC;
}

int64_t link_timeout_ms(const struct df1 *h)
{
	return h->cfg.timeout_ms > 0 ? h->cfg.timeout_ms : 0;
}

/* ------------------------------------------------------------------------
 * Transmission
 * ------------------------------------------------------------------------ */

/* Wait until deadline_ms without reading: poll() on the cancel fd only. */
static int link_pause(struct df1 *h, int64_t deadline_ms)
{
	if (df1_now_ms() >= deadline_ms)
		return 0;
	return port_wait(h, -1, 0, deadline_ms);
}

/* The same to the microsecond (pacing: a character's time at 19200 baud is 521 µs). */
static int link_pause_us(struct df1 *h, int64_t deadline_us)
{
	if ((int64_t)df1_now_us() >= deadline_us)
		return 0;
	return port_wait_us(h, -1, 0, deadline_us);
}

/* Microseconds one character takes on the line at baud: start bit, data bits,
 * parity bit, stop bits (10 for 8N1). */
int64_t link_char_us(const struct df1 *h, int baud)
{
	int bits = 1 + (h->cfg.data_bits > 0 ? h->cfg.data_bits : 8) + (h->cfg.parity != 'N') +
	           (h->cfg.stop_bits > 0 ? h->cfg.stop_bits : 1);

	return baud > 0 ? (int64_t)bits * 1000000 / baud : 0;
}

/* When the bytes just written will have left the line. A paced line (df1sim,
 * df1_set_line_baud) handed each chunk over when its last character was due,
 * so they have. A real UART takes them into the kernel's buffer at once and
 * sends them at the configured baud, after what it still holds of ours;
 * tcdrain would wait for that but blocks past the cancel descriptor, so the
 * link keeps its own account from the line rate (link_fill ends it when the
 * peer answers: an answer shows our bytes are through, and a pseudo-terminal,
 * which carries them at once, must not let the account run ahead of the
 * clock). A backend whose bytes take no line time here (not port_ops.paced:
 * TCP to a device server, other descriptors) has no such delay. */
static void link_tx_account(struct df1 *h, size_t n)
{
	int64_t now = (int64_t)df1_now_us();

	if (h->cfg.line_baud <= 0 && h->port && h->port->paced && h->cfg.baud > 0) {
		int64_t from = h->tx_end_us > now ? h->tx_end_us : now;

		h->tx_end_us = from + (int64_t)n * link_char_us(h, h->cfg.baud);
	} else {
		h->tx_end_us = now;
	}
}

int64_t link_after_tx_ms(const struct df1 *h, int64_t ms)
{
	int64_t now = df1_now_ms();
	int64_t end = (h->tx_end_us + 999) / 1000;

	return (end > now ? end : now) + ms;
}

static int link_write(struct df1 *h, const uint8_t *buf, size_t n, int64_t deadline_ms)
{
	size_t off = 0;

	while (off < n) {
		ssize_t w = h->port->write(h, buf + off, n - off, deadline_ms);

		if (w < 0)
			return (int)w;
		if (w == 0)
			return df1_fail(h, DF1_E_SYS, -1, "write to %s made no progress", h->port_name);
		if (h->trace_fn)
			h->trace_fn(h->trace_user, DF1_DIR_TX, buf + off, (size_t)w, df1_now_us());
		off += (size_t)w;
	}
	return 0;
}

/* Remember our own bytes: on a 2-wire line they come back and are dropped. */
static void link_echo_add(struct df1 *h, const uint8_t *buf, size_t n)
{
	size_t cap = sizeof h->echo_buf;

	if (h->echo_pos >= h->echo_len) {
		h->echo_pos = h->echo_len = 0;
	} else if (h->echo_pos > 0) {
		memmove(h->echo_buf, h->echo_buf + h->echo_pos, h->echo_len - h->echo_pos);
		h->echo_len -= h->echo_pos;
		h->echo_pos = 0;
	}
	if (h->echo_len + n > cap) {
		/* more than a frame not yet read back: keep what fits */
		n = h->echo_len < cap ? cap - h->echo_len : 0;
	}
	memcpy(h->echo_buf + h->echo_len, buf, n);
	h->echo_len += n;
}

static int link_send_wire(struct df1 *h, const uint8_t *buf, size_t n, bool delay);

int link_send_raw(struct df1 *h, const uint8_t *buf, size_t n)
{
	uint8_t both[sizeof h->tx_hold + FRAME_MAX_WIRE];

	if (h->tx_hold_len == 0 || h->tx_hold_len + n > sizeof both) {
		int r = link_tx_flush(h);

		return r < 0 ? r : link_send_wire(h, buf, n, true);
	}
	/* the symbols held (an ACK) first, then this, in one write */
	memcpy(both, h->tx_hold, h->tx_hold_len);
	memcpy(both + h->tx_hold_len, buf, n);
	n += h->tx_hold_len;
	h->tx_hold_len = 0;
	return link_send_wire(h, both, n, true);
}

int link_tx_flush(struct df1 *h)
{
	uint8_t held[sizeof h->tx_hold];
	size_t n = h->tx_hold_len;

	if (n == 0)
		return 0;
	memcpy(held, h->tx_hold, n);
	h->tx_hold_len = 0;
	return link_send_wire(h, held, n, true);
}

int link_send_now(struct df1 *h, const uint8_t *buf, size_t n)
{
	int r = link_tx_flush(h);

	return r < 0 ? r : link_send_wire(h, buf, n, false);
}

int link_pause_ms(struct df1 *h, int64_t deadline_ms)
{
	return link_pause(h, deadline_ms);
}

static int link_send_wire(struct df1 *h, const uint8_t *buf, size_t n, bool delay)
{
	int64_t wire_ms, deadline;
	int r;

	if (!h->port || h->fd < 0)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "handle is not open");
	if (h->cfg.listen_only)
		return port_refuse_tx(h); /* before TX_Delay: nothing is waited for either */
	if (n == 0)
		return 0;
	if (delay && h->cfg.tx_delay_ms > 0) {
		/* TX_Delay before every transmission (doc/REQUIREMENTS.md 004, radio key-up) */
		r = link_pause(h, df1_now_ms() + h->cfg.tx_delay_ms);
		if (r < 0)
			return r;
	}
	wire_ms = h->cfg.line_baud > 0 ? (int64_t)(n * 10 * 1000 / (size_t)h->cfg.line_baud) + 1 : 0;
	deadline = df1_now_ms() + (link_timeout_ms(h) > 1000 ? link_timeout_ms(h) : 1000) + wire_ms;
	if (h->cfg.line_baud <= 0) {
		r = link_write(h, buf, n, deadline);
		if (r < 0)
			return r;
	} else {
		/* a slow line: about 4 ms of characters per write, each handed
		 * over when its last character would have arrived on the wire
		 * (10 bits per character), so the far end never sees a byte early */
		int64_t start = (int64_t)df1_now_us();
		int64_t char_us = link_char_us(h, h->cfg.line_baud);
		size_t chunk = (size_t)h->cfg.line_baud / 10 / 250;
		size_t off;

		if (chunk < 1)
			chunk = 1;
		if (start < h->tx_end_us)
			start = h->tx_end_us; /* the previous transmission is still on the line */
		for (off = 0; off < n;) {
			size_t c = n - off < chunk ? n - off : chunk;
			int64_t due_us = start + (int64_t)(off + c) * char_us;

			r = link_pause_us(h, due_us);
			if (r < 0)
				return r;
			r = link_write(h, buf + off, c, deadline);
			if (r < 0)
				return r;
			off += c;
		}
	}
	link_tx_account(h, n);
	df1_count_n(h, DF1_ID_CRD_CHAR_SENT, n);
	if (h->cfg.echo_discard)
		link_echo_add(h, buf, n);
	return 0;
}

static void link_sym_sent(struct df1 *h, uint8_t sym);

/* DLE ACK / NAK / EOT / ENQ with its counter; ACK and NAK become the last response. */
int link_send_sym(struct df1 *h, uint8_t sym)
{
	uint8_t b[2] = { DF1_DLE, sym };
	int r = link_send_raw(h, b, sizeof b);

	if (r < 0)
		return r;
	link_sym_sent(h, sym);
	return 0;
}

int link_send_sym_held(struct df1 *h, uint8_t sym)
{
	if (!h->port || h->fd < 0)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "handle is not open");
	if (h->cfg.listen_only)
		return port_refuse_tx(h);
	if (h->tx_hold_len + 2 > sizeof h->tx_hold) {
		int r = link_tx_flush(h);

		if (r < 0)
			return r;
	}
	h->tx_hold[h->tx_hold_len++] = DF1_DLE;
	h->tx_hold[h->tx_hold_len++] = sym;
	link_sym_sent(h, sym);
	return 0;
}

static void link_sym_sent(struct df1 *h, uint8_t sym)
{
	switch (sym) {
	case DF1_ACK:
		df1_count(h, DF1_ID_CNT_ACKS_SENT);
		h->last_response = DF1_ACK;
		break;
	case DF1_NAK:
		df1_count(h, DF1_ID_CNT_NAKS_SENT);
		h->last_response = DF1_NAK;
		break;
	case DF1_EOT:
		df1_count(h, DF1_ID_CNT_EOTS_SENT);
		break;
	default:
		break;
	}
}

void link_flush(struct df1 *h)
{
	frame_decoder_reset(&h->dec);
	h->rx_len = h->rx_pos = 0;
	h->echo_len = h->echo_pos = 0;
}

/* ------------------------------------------------------------------------
 * Reception
 * ------------------------------------------------------------------------ */

/* Noise or a broken symbol: the receiver's last response becomes NAK (doc/PROTOCOL.md 1.7). */
void link_noise(struct df1 *h)
{
	h->last_response = DF1_NAK;
}

/* One port read into the empty rx buffer. Returns bytes now buffered (0 when
 * all were our echo), or DF1_E_* ; *expired when the read hit its deadline. */
static int link_fill(struct df1 *h, int64_t deadline_ms, bool *expired)
{
	ssize_t n;
	size_t i = 0;

	*expired = false;
	h->rx_pos = h->rx_len = 0;
	if (h->cfg.line_baud > 0) {
		/* a paced line delivers no faster than its baud: a few ms of
		 * characters per read, each handed on when its last character
		 * has arrived, so the sender sees what a UART would do to it */
		size_t chunk = (size_t)h->cfg.line_baud / 10 / 250;

		n = h->port->read(h, h->rxbuf, chunk < 1 ? 1 : chunk, deadline_ms);
		if (n > 0) {
			int64_t now = (int64_t)df1_now_us();
			int64_t char_us = link_char_us(h, h->cfg.line_baud);
			int64_t due = h->rx_due_us + (int64_t)n * char_us;
			int r;

			/* the line delivers each byte a character after the one before
			 * it, and none before it was written: a burst (a UART's write)
			 * trickles in, bytes a paced sender handed over at line rate
			 * are taken as they come, not delayed once more. Each of those
			 * is read a wake-up after it was written, some later than
			 * others: the account, started at the first, would carry the
			 * latest wake-up to the frame's end and delay every answer
			 * (bench/README.md), so being up to a character behind it is
			 * our own lateness and not waited for */
			h->rx_due_us = due > now ? due : now;
			r = link_pause_us(h, h->rx_due_us - char_us);
			if (r < 0)
				return r;
		}
	} else {
		n = h->port->read(h, h->rxbuf, sizeof h->rxbuf, deadline_ms);
	}
	if (n < 0)
		return (int)n; /* the backend counted 2551 and recorded the error */
	if (n == 0) {
		*expired = true;
		return 0;
	}
	h->rx_last_ms = df1_now_ms();
	if (h->trace_fn)
		h->trace_fn(h->trace_user, DF1_DIR_RX, h->rxbuf, (size_t)n, df1_now_us());
	df1_count_n(h, DF1_ID_CRD_CHAR_RECV, (uint64_t)n);
	/* 2-wire line: our own bytes come back first; drop exactly those */
	while (h->echo_pos < h->echo_len && i < (size_t)n) {
		if (h->rxbuf[i] != h->echo_buf[h->echo_pos]) {
			h->echo_pos = h->echo_len = 0; /* echo lost (collision): stop expecting it */
			break;
		}
		i++;
		h->echo_pos++;
	}
	h->rx_pos = i;
	h->rx_len = (size_t)n;
	if (h->rx_pos < h->rx_len && h->tx_end_us > (int64_t)df1_now_us())
		h->tx_end_us = (int64_t)df1_now_us(); /* the peer talks (not our echo): we are through */
	return (int)(h->rx_len - h->rx_pos);
}

static int64_t link_gap_ms(const struct df1 *h)
{
	int64_t g = link_timeout_ms(h);

	return g < 100 ? 100 : g > 1000 ? 1000 : g;
}

/* How far past its deadline a symbol under way may run: twice the time of the
 * longest frame at the configured baud rate, at least a second. */
static int64_t link_overrun_ms(const struct df1 *h)
{
	int64_t baud = h->cfg.baud > 0 ? h->cfg.baud : 1200;
	int64_t ms = 2 * (int64_t)FRAME_MAX_WIRE * 10 * 1000 / baud;

	return ms < 1000 ? 1000 : ms;
}

int link_read_symbol(struct df1 *h, int64_t deadline_ms, struct df1_symbol *sym)
{
	int64_t hard = deadline_ms + link_overrun_ms(h);

	for (;;) {
		bool busy, expired;
		int64_t dl;
		int r;

		if (h->rx_pos < h->rx_len) {
			size_t noise = h->dec.noise;

			h->rx_pos += frame_decoder_feed(&h->dec, h->rxbuf + h->rx_pos,
			                                h->rx_len - h->rx_pos, sym);
			if (h->dec.noise != noise)
				link_noise(h);
			if (sym->kind != DF1_SYM_NONE)
				return 1;
			continue;
		}
		/* a symbol under way may finish past the deadline, within the character gap */
		busy = frame_decoder_busy(&h->dec);
		dl = deadline_ms;
		if (busy) {
			dl = h->rx_last_ms + link_gap_ms(h);
			if (dl > hard)
				dl = hard; /* a line that never stops talking */
		}
		if (h->tx_hold_len) {
			/* nothing followed the ACK held: it goes before we wait */
			r = link_tx_flush(h);
			if (r < 0)
				return r;
		}
		r = link_fill(h, dl, &expired);
		if (r < 0)
			return r;
		if (!expired)
			continue;
		if (busy) {
			/* cut short: the line went quiet (or never stopped) mid-symbol */
			if (h->dec.wire >= 2)
				df1_log(h, DF1_ID_NTC_NO_ETX_RCVD);
			frame_decoder_reset(&h->dec);
			link_noise(h);
			if (df1_now_ms() < deadline_ms)
				continue;
		}
		memset(sym, 0, sizeof *sym);
		return 0;
	}
}

/* A pause until deadline_us that input ends early, to the microsecond (a
 * read's deadline is a whole ms, up to one late: the half-duplex master's
 * pause before a poll, lib/link/half.c). What is held goes out first, as
 * before any wait for input. 1: input is there (buffered or readable), 0: the
 * time came, DF1_E_*. */
int link_wait_input_us(struct df1 *h, int64_t deadline_us)
{
	int r = link_tx_flush(h);

	if (r < 0)
		return r;
	if (h->rx_pos < h->rx_len)
		return 1;
	return port_wait_us(h, h->fd, POLLIN, deadline_us);
}

/* 2506/2507 with counters 2547/2546 for a frame (or poll) with a bad check. */
void link_bad_check(struct df1 *h, const struct df1_symbol *s)
{
	unsigned a = s->check_actual, e = s->check_expected;

	if (s->check == DF1_CHECK_BCC) {
		df1_count(h, DF1_ID_CNT_BCC_ERRORS);
		df1_log(h, DF1_ID_ERR_BAD_BCC, (int)(a >> 8), (int)(a & 0xFF), (int)(e >> 8),
		        (int)(e & 0xFF));
	} else {
		df1_count(h, DF1_ID_CNT_CRC_ERRORS);
		df1_log(h, DF1_ID_ERR_BAD_CRC, (int)(a >> 8), (int)(a & 0xFF), (int)(e >> 8),
		        (int)(e & 0xFF));
	}
}

/* The notice of an ERROR symbol. Returns true if it broke a frame (or its header). */
bool link_log_error(struct df1 *h, const struct df1_symbol *s)
{
	switch (s->error) {
	case DF1_ID_NTC_RCVD_MSG_TOO_LONG:
		df1_log(h, DF1_ID_NTC_RCVD_MSG_TOO_LONG,
		        (int)(h->dec.max_len ? h->dec.max_len : FRAME_MAX_DATA));
		return true;
	case DF1_ID_NTC_RCVD_MSG_TOO_SHORT:
		df1_log(h, DF1_ID_NTC_RCVD_MSG_TOO_SHORT, FRAME_MIN_DATA);
		return true;
	case DF1_ID_NTC_NO_ETX_RCVD:
		df1_log(h, DF1_ID_NTC_NO_ETX_RCVD);
		return true;
	case DF1_ID_ERR_BAD_BCC: /* a half-duplex poll with a wrong BCC */
	case DF1_ID_ERR_BAD_CRC:
		link_bad_check(h, s);
		return false;
	case DF1_ID_NTC_INVALID_SYMBOL:
	default:
		df1_log(h, DF1_ID_NTC_INVALID_SYMBOL, (int)s->bad_byte);
		/* DLE x outside anything is 2 bytes; inside a frame or header, more */
		return s->wire_len > 2;
	}
}

/* ------------------------------------------------------------------------
 * Duplicate detection (doc/PROTOCOL.md 1.7, 2.3): SRC, CMD and both TNS bytes.
 * ------------------------------------------------------------------------ */

bool link_is_dup(const struct df1 *h, uint8_t key, const uint8_t *app, size_t n)
{
	const struct station_state *st = &h->stations[key];

	if (!h->cfg.dup_detect || !st->have_last || n < 6)
		return false;
	return st->last_hdr[1] == app[1] && st->last_hdr[2] == app[2] &&
	       st->last_hdr[4] == app[4] && st->last_hdr[5] == app[5];
}

/* FNV-1a: tells a retransmission (the same bytes) from another message. */
static uint32_t link_hash(const uint8_t *app, size_t n)
{
	uint32_t x = 2166136261u;

	for (size_t i = 0; i < n; i++)
		x = (x ^ app[i]) * 16777619u;
	return x;
}

void link_remember(struct df1 *h, uint8_t key, const uint8_t *app, size_t n)
{
	struct station_state *st = &h->stations[key];

	if (n < 6)
		return;
	memcpy(st->last_hdr, app, 6);
	st->last_len = n;
	st->last_hash = link_hash(app, n);
	st->have_last = true;
}

/* A duplicate that is not the message accepted under its header: a master
 * that started again on the TNS it last used (a new run of a tool), not one
 * that sends the same frame again. */
static bool link_dup_differs(const struct df1 *h, uint8_t key, const uint8_t *app, size_t n)
{
	const struct station_state *st = &h->stations[key];

	return st->last_len != n || st->last_hash != link_hash(app, n);
}

/* Drop the reply held for the accepted message whose header d repeats (full
 * duplex: in flight; half duplex: queued for station key). */
static void link_slots_drop_reply_to(struct df1 *h, uint8_t key, const uint8_t *d)
{
	for (int i = 0; i < LINK_REPLY_SLOTS; i++) {
		struct link_reply *r = &h->resp->replies[i];

		if (!r->used || r->stn != key || r->len < 6 || r->app[2] != (uint8_t)(d[2] | 0x40) ||
		    r->app[4] != d[4] || r->app[5] != d[5])
			continue;
		r->used = false;
		if (h->resp->awaiting == i + 1) {
			h->resp->awaiting = 0;
			h->resp->awaiting_stale = false;
		}
	}
}

/* A duplicate: ACKed again and dropped (2526, 2549, 2524), counted even when
 * the ACK cannot be sent. Returns the ACK's result. */
int link_ack_dup(struct df1 *h, const struct df1_symbol *s)
{
	int r = link_send_sym(h, DF1_ACK);

	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	df1_count(h, DF1_ID_CNT_DUPLICATE_MSGS_RCVD);
	df1_log(h, DF1_ID_NTC_DUPLICATE_MSG_RCVD, (int)s->data[1]);
	return r;
}

int link_serve_screen(struct df1 *h, uint8_t key, const struct df1_symbol *s)
{
	const uint8_t *d = s->data;
	int r;

	if (link_is_dup(h, key, d, s->len)) {
		r = link_ack_dup(h, s);
		/* Not run again (doc/PROTOCOL.md 1.7). Its reply is not sent for it either: a
		 * retransmitted command's reply has its own retries (ENQ and NAK, or
		 * the next poll), and a different command under the same header is
		 * a master that started again on its last TNS; the reply still held
		 * is not its own, and would report its write done. */
		if (link_dup_differs(h, key, d, s->len))
			link_slots_drop_reply_to(h, key, d);
		return r < 0 ? r : 0;
	}
	if (d[2] & 0x40) {
		/* a reply, and the responder has no command outstanding: stale */
		r = link_send_sym(h, DF1_ACK);
		link_remember(h, key, d, s->len);
		df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
		df1_count(h, DF1_ID_CNT_STALE_MSGS_RCVD);
		df1_log(h, DF1_ID_ERR_WRONG_MESSAGE, (int)d[1], (int)d[0], (int)(d[4] | d[5] << 8));
		return r < 0 ? r : 0;
	}
	return 1;
}

/* A message the master accepted (already ACKed): the reply it waits for?
 * Returns 1 (matched: copied to reply, *len set), 0 (stale, or a command when
 * no caller took it (peer.c takes them first):
 * counted and dropped) or DF1_E_* (wrong CMD, reply buffer too small). */
int link_take_reply(struct df1 *h, const uint8_t *cmd, const struct df1_symbol *s,
                    uint8_t *reply, size_t cap, size_t *len)
{
	const uint8_t *d = s->data;
	uint16_t tns = (uint16_t)(d[4] | d[5] << 8);
	int r;

	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	if (!(d[2] & 0x40)) {
		/* a command: we are not the responder here */
		df1_count(h, DF1_ID_CNT_CMD_MSGS_RCVD);
		df1_count(h, DF1_ID_CNT_INVALID_MSGS_RCVD);
		df1_log(h, DF1_ID_ERR_WRONG_MESSAGE, (int)d[1], (int)d[0], (int)tns);
		return 0;
	}
	if (!cmd || d[1] != cmd[0] || d[4] != cmd[4] || d[5] != cmd[5]) {
		df1_count(h, DF1_ID_CNT_STALE_MSGS_RCVD);
		df1_log(h, DF1_ID_ERR_WRONG_MESSAGE, (int)d[1], (int)d[0], (int)tns);
		return 0;
	}
	r = link_reply_copy(h, cmd, s, reply, cap);
	if (r < 0)
		return r;
	*len = (size_t)r;
	return 1;
}

int link_reply_copy(struct df1 *h, const uint8_t *cmd, const struct df1_symbol *s, uint8_t *reply,
                    size_t cap)
{
	const uint8_t *d = s->data;

	if (d[2] != (uint8_t)(cmd[2] | 0x40)) {
		df1_count(h, DF1_ID_CNT_INVALID_MSGS_RCVD);
		df1_log(h, DF1_ID_ERR_BAD_FUNCTION_CODE, (int)cmd[0], (int)d[2],
		        (int)(cmd[2] | 0x40));
		return df1_fail(h, DF1_E_BAD_FUNCTION, cmd[0],
		                "reply with command code 0x%02X, expected 0x%02X", d[2], cmd[2] | 0x40);
	}
	df1_count(h, DF1_ID_CNT_REPLY_MSGS_RCVD);
	if (d[3] != 0)
		df1_count(h, DF1_ID_CNT_ERROR_MSGS_RCVD);
	df1_log(h, DF1_ID_NTC_REPLY_MSG_RCVD, (int)cmd[0]);
	if (s->len > cap)
		return df1_fail(h, DF1_E_NOSPACE, cmd[0], "reply of %zu bytes, buffer holds %zu",
		                s->len, cap);
	memcpy(reply, d, s->len);
	return (int)s->len;
}

/* ------------------------------------------------------------------------
 * Reply slots (the responder's queue)
 * ------------------------------------------------------------------------ */

struct link_reply *link_slot_new(struct df1 *h, uint8_t stn, const uint8_t *app, size_t n)
{
	for (int i = 0; i < LINK_REPLY_SLOTS; i++) {
		struct link_reply *r = &h->resp->replies[i];

		if (r->used)
			continue;
		memset(r, 0, sizeof *r);
		r->used = true;
		r->stn = stn;
		r->seq = ++h->resp->seq;
		r->len = n;
		memcpy(r->app, app, n);
		r->corrupt = link_fault(h->resp, DF1_FAULT_CORRUPT_REPLY);
		r->stale_first = link_fault(h->resp, DF1_FAULT_STALE_REPLY);
		if (h->cfg.scan_time_ms > 0) {
			/* answered at the end of the program scan in progress */
			int64_t scan = h->cfg.scan_time_ms, now = df1_now_ms();

			r->due_ms = h->scan_epoch_ms + ((now - h->scan_epoch_ms) / scan + 1) * scan;
		}
		if (link_fault(h->resp, DF1_FAULT_DELAY_REPLY))
			r->due_ms += (r->due_ms ? 0 : df1_now_ms()) +
			             h->resp->faults.value[DF1_FAULT_DELAY_REPLY];
		return r;
	}
	return NULL;
}

bool link_slot_free_exists(const struct df1 *h)
{
	for (int i = 0; i < LINK_REPLY_SLOTS; i++)
		if (!h->resp->replies[i].used)
			return true;
	return false;
}

/* The oldest queued reply (for station stn, or any when all). */
struct link_reply *link_slot_oldest(struct df1 *h, bool all, uint8_t stn)
{
	struct link_reply *best = NULL;

	for (int i = 0; i < LINK_REPLY_SLOTS; i++) {
		struct link_reply *r = &h->resp->replies[i];

		if (!r->used || (!all && r->stn != stn))
			continue;
		if (!best || (int32_t)(r->seq - best->seq) < 0)
			best = r;
	}
	return best;
}

void link_slots_clear(struct df1 *h)
{
	for (int i = 0; i < LINK_REPLY_SLOTS; i++)
		h->resp->replies[i].used = false;
	h->resp->awaiting = 0;
	h->resp->awaiting_stale = false;
}

/* Encode (a stale copy of) a queued reply, with the faults of this
 * transmission, and send it. first: the reply's first transmission. */
int link_slot_send(struct df1 *h, struct link_reply *r, bool stale, bool first)
{
	uint8_t wire[3 + FRAME_MAX_WIRE];
	uint8_t app[FRAME_MAX_DATA];
	size_t off = 0, n;
	int rc;

	memcpy(app, r->app, r->len);
	if (stale) {
		/* TNS - 2, not - 1: a master that increments its TNS has just accepted
		 * TNS - 1, and that copy would be a duplicate, not a stale reply. */
		uint16_t tns = (uint16_t)((app[4] | app[5] << 8) - 2);

		app[4] = (uint8_t)(tns & 0xFF);
		app[5] = (uint8_t)(tns >> 8);
	}
	if (link_fault(h->resp, DF1_FAULT_NOISE))
		off = link_noise_bytes(h->resp, wire);
	n = frame_encode_slave(link_tx_check(h), app, r->len, wire + off, sizeof wire - off);
	if (n == 0)
		return df1_fail(h, DF1_E_INVAL, r->stn, "reply of %zu bytes does not fit a frame", r->len);
	if (r->corrupt && !stale) {
		wire[off + n - 1] ^= 0xFF; /* the last check byte: a receiver must reject it */
		r->corrupt = false;        /* the retransmission is good */
	}
	rc = link_send_raw(h, wire, off + n);
	if (rc < 0)
		return rc;
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_SENT);
	if (first) {
		df1_count(h, DF1_ID_CNT_REPLY_MSGS_SENT);
		if (app[3] != 0)
			df1_count(h, DF1_ID_CNT_ERROR_MSGS_SENT);
	}
	return 0;
}

