/* SPDX-License-Identifier: MPL-2.0 */
/*
 * radio.c - the DF1 Radio Modem link (doc/PROTOCOL.md 2.6, doc/ARCHITECTURE.md
 * 4): full-duplex frames (DLE STX ... DLE ETX BCC|CRC, DLE doubled) and no
 * link control at all. The command goes out once, the reply comes back once;
 * duplicate detection and store and forward (radio_dup.c); keying the radio
 * with RTS/CTS and waiting for the carrier to drop through the port's modem
 * lines. link.c dispatches here; it sits on core.c like full.c and half.c.
 *
 * Decisions the sources leave open (relied on by tests/unit/link/test_link_radio.c):
 *  - Nothing is ever sent but frames: no ACK, NAK, ENQ, EOT or poll. Control
 *    symbols heard between frames are ignored; a DLE pair inside a frame, a
 *    frame cut short or a bad check drops the frame silently, counted as a
 *    bad packet (and 2546/2547 for a check).
 *  - The reply to our command is the frame with DST = our station, SRC = the
 *    command's DST, CMD | 40h and the command's TNS. A wrong CMD under that
 *    header ends the transaction as in full duplex (DF1_E_BAD_FUNCTION).
 *    Anything else is ignored: other stations' traffic, our own packets
 *    relayed back (SRC = our station: never executed, never taken), a reply
 *    already taken (stale, 2548).
 *  - The reply is awaited max(Timeout, Cmd_Timeout) from the end of our
 *    transmission. Then the command goes out again, unchanged (same TNS, so
 *    a late reply to the first copy still counts, and a responder with
 *    duplicate detection drops the copy), up to DF1_OPT_APP_RETRIES times
 *    (default 0, counted 2541), then DF1_E_TIMEOUT (2508, 2545).
 *  - A broadcast (DST 255) goes out once and is done at once, with an empty
 *    STS 0 reply as a half-duplex slave's broadcast (half_msg.c). Broadcasts
 *    heard are executed and never answered.
 *  - Duplicate detection (DF1_OPT_RADIO_DUP_DETECT): auto = on while a
 *    forward table is set. Every good packet heard is checked against the
 *    last 20 and held; a repeat is dropped (not executed, relayed or
 *    answered; 2549, 2524).
 *  - Store and forward (df1_set_forward): a packet that is not a duplicate,
 *    not from our station, and whose DST is another station with its bit set
 *    (or 255 with bit 255) is sent again unchanged, before it is executed
 *    when it is a broadcast. It happens wherever this link reads: df1_serve,
 *    and a transaction waiting for its reply.
 *  - df1_serve's replies go through the responder's slots (core.c): at once,
 *    or at the end of a program scan (DF1_OPT_SCAN_TIME_MS) or after a
 *    DF1_FAULT_DELAY_REPLY, while the link goes on listening and relaying;
 *    DF1_FAULT_CORRUPT_REPLY, STALE_REPLY and SILENT_STATION act as in full
 *    duplex, the faults on link symbols (DROP_ACK, NAK_COMMAND) have nothing
 *    to act on.
 *  - A command for us heard while our own waits is answered at once through
 *    df1_set_responder's handler (STS 10h without one), as a full-duplex
 *    master answers its peer (peer.c).
 *  - Keying (DF1_OPT_RADIO_RTS_CTS, DF1_OPT_DCD_WAIT_MS): TX_Delay, then the
 *    wait for DCD to drop, then RTS up, the RTS send delay, the wait for CTS
 *    (1 s), the frame, the RTS off delay after its last byte has left the
 *    line, RTS down. No CTS or DCD still up: the packet is not sent, counted
 *    undelivered, and the error recorded; a transaction goes on as if no
 *    reply came. A port without modem lines (a pty, a socket, TCP) sends
 *    without keying, and says so once in the log (ID 0).
 */
#include "link/link.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "link/link_int.h"

#define RADIO_CTS_WAIT_MS 1000   /* doc/PROTOCOL.md 2.6: CTS within 1 s */
#define RADIO_LINE_STEP_MS 2     /* the modem lines are read this often while waited for */

/* Automatic: on for a relay (a forward table, doc/PROTOCOL.md 2.6) and for
 * any node that executes commands (df1_serve, a responder): two relays in
 * parallel deliver every packet twice, and a command must run once. A pure
 * master takes replies by TNS, so a second copy is stale anyway. */
static bool radio_dup_on(const struct df1 *h)
{
	if (h->cfg.radio_dup != DF1_DUP_AUTO)
		return h->cfg.radio_dup != 0;
	return h->cfg.forward_set || h->peer_fn || h->radio_served;
}

/* A station this node answers as: its own, or one a responder serves. */
static bool radio_ours(const struct df1 *h, uint8_t dst)
{
	return dst == h->cfg.station || (h->resp && dst < 255 && h->resp->serve_station[dst]);
}

/* A message outside the catalog (ID 0: the catalog of doc/REQUIREMENTS.md 004 is closed). */
static void radio_note(struct df1 *h, enum df1_severity sev, const char *text)
{
	if (h->log_fn)
		h->log_fn(h->log_user, 0, sev, text);
}

/* ------------------------------------------------------------------------
 * Keying: the port's modem lines
 * ------------------------------------------------------------------------ */

/* 1 the lines are there (state read), 0 none (said once), DF1_E_*. */
static int radio_lines(struct df1 *h, unsigned set, unsigned clear, unsigned *state)
{
	int r = h->port->modem ? h->port->modem(h, set, clear, state) : DF1_E_NOTSUP;

	if (r == DF1_E_NOTSUP) {
		if (!h->modem_noted) {
			char t[200];

			h->modem_noted = true;
			snprintf(t, sizeof t, "%s has no modem lines: the radio is not keyed "
			         "(no RTS/CTS, no DCD wait)", h->port_name);
			radio_note(h, DF1_SEV_NOTICE, t);
		}
		return 0;
	}
	return r < 0 ? r : 1;
}

/* Until line bit is up (want) or down, or deadline: 1 it is, 0 not in time, DF1_E_*. */
static int radio_wait_line(struct df1 *h, unsigned bit, bool want, int64_t deadline)
{
	for (;;) {
		unsigned st = 0;
		int64_t now, next;
		int r = radio_lines(h, 0, 0, &st);

		if (r <= 0)
			return r < 0 ? r : 1;
		if (((st & bit) != 0) == want)
			return 1;
		now = df1_now_ms();
		if (now >= deadline)
			return 0;
		/* no descriptor tells a line change: look again shortly (the cancel fd ends it) */
		next = now + RADIO_LINE_STEP_MS < deadline ? now + RADIO_LINE_STEP_MS : deadline;
		r = link_pause_ms(h, next);
		if (r < 0)
			return r;
	}
}

/* A packet not sent: counted, logged, the error recorded; 1. */
static int radio_undelivered(struct df1 *h, const uint8_t *app, const char *why)
{
	h->radio_st.undelivered++;
	df1_fail(h, DF1_E_TIMEOUT, app[0], "radio: packet for station %d not sent: %s", app[0], why);
	radio_note(h, DF1_SEV_ERROR, h->err.message);
	return 1;
}

/* The frame with the radio keyed (doc/PROTOCOL.md 2.6): 0 sent, 1 undelivered, DF1_E_*. */
static int radio_keyed(struct df1 *h, const uint8_t *app, const uint8_t *wire, size_t wn)
{
	unsigned st = 0;
	int r = radio_lines(h, 0, 0, &st), p, d;

	if (r <= 0)
		return r < 0 ? r : link_send_raw(h, wire, wn);
	r = link_tx_flush(h);
	if (r == 0 && h->cfg.tx_delay_ms > 0)
		r = link_pause_ms(h, df1_now_ms() + h->cfg.tx_delay_ms);
	if (r == 0 && h->cfg.dcd_wait_ms > 0) {
		r = radio_wait_line(h, PORT_LINE_DCD, false, df1_now_ms() + h->cfg.dcd_wait_ms);
		if (r == 0)
			return radio_undelivered(h, app, "carrier (DCD) still up");
		r = r < 0 ? r : 0;
	}
	if (r < 0)
		return r;
	if (!h->cfg.radio_rts_cts)
		return link_send_now(h, wire, wn);
	r = radio_lines(h, PORT_LINE_RTS, 0, NULL);
	if (r >= 0 && h->cfg.rts_send_ms > 0)
		r = link_pause_ms(h, df1_now_ms() + h->cfg.rts_send_ms);
	if (r >= 0)
		r = radio_wait_line(h, PORT_LINE_CTS, true, df1_now_ms() + RADIO_CTS_WAIT_MS);
	if (r <= 0) {
		(void)radio_lines(h, 0, PORT_LINE_RTS, NULL);
		return r < 0 ? r : radio_undelivered(h, app, "no CTS within 1 s of RTS");
	}
	r = link_send_now(h, wire, wn);
	p = link_pause_ms(h, link_after_tx_ms(h, h->cfg.rts_off_ms));
	d = radio_lines(h, 0, PORT_LINE_RTS, NULL);
	return r < 0 ? r : p < 0 ? p : d < 0 ? d : 0;
}

/* One packet on the air: 0 sent, 1 undelivered (counted), DF1_E_*. corrupt:
 * DF1_FAULT_CORRUPT_REPLY, the last check byte inverted. */
static int radio_send(struct df1 *h, const uint8_t *app, size_t n, bool corrupt)
{
	uint8_t wire[FRAME_MAX_WIRE];
	size_t wn = frame_encode_full(link_tx_check(h), app, n, wire, sizeof wire);
	int r;

	if (wn == 0)
		return df1_fail(h, DF1_E_INVAL, app[0], "packet of %zu bytes does not fit a frame", n);
	if (corrupt)
		wire[wn - 1] ^= 0xFF;
	if (h->cfg.radio_rts_cts || h->cfg.dcd_wait_ms > 0)
		r = radio_keyed(h, app, wire, wn);
	else
		r = link_send_raw(h, wire, wn);
	if (r != 0)
		return r;
	h->radio_st.sent++;
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_SENT);
	return 0;
}

/* ------------------------------------------------------------------------
 * Reception: what every receive loop does with what it hears
 * ------------------------------------------------------------------------ */

/* One symbol heard: 1 a good packet for this node (a command or a reply to
 * it, or a broadcast), 0 nothing more to do (ignored, dropped, relayed), DF1_E_*. */
static int radio_heard(struct df1 *h, const struct df1_symbol *s)
{
	const uint8_t *d = s->data;
	bool ours;

	if (s->kind == DF1_SYM_ERROR) {
		if (link_log_error(h, s))
			h->radio_st.bad_packets++; /* a frame broken off: dropped */
		return 0;
	}
	if (s->kind != DF1_SYM_FRAME)
		return 0; /* a stray ACK, NAK, ENQ, EOT: nothing answers it */
	if (!s->check_ok || s->master_msg) {
		if (!s->check_ok)
			link_bad_check(h, s);
		h->radio_st.bad_packets++;
		return 0;
	}
	h->radio_st.received++;
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	if (radio_dup_on(h)) {
		if (radio_dup_seen(&h->radio_dups, d, s->len)) {
			h->radio_st.duplicates++;
			df1_count(h, DF1_ID_CNT_DUPLICATE_MSGS_RCVD);
			df1_log(h, DF1_ID_NTC_DUPLICATE_MSG_RCVD, (int)d[1]);
			return 0;
		}
		radio_dup_add(&h->radio_dups, d, s->len);
	}
	ours = d[0] != 255 && radio_ours(h, d[0]);
	if (h->cfg.forward_set && !ours &&
	    radio_fwd_rule(h->cfg.forward, (uint8_t)h->cfg.station, d, s->len)) {
		int r = radio_send(h, d, s->len, false);

		if (r < 0)
			return r;
		if (r == 0)
			h->radio_st.relayed++;
	}
	if (d[1] == h->cfg.station)
		return 0; /* our own packet relayed back */
	return ours || d[0] == 255;
}

/* A reply of ours on the air (corrupt: DF1_FAULT_CORRUPT_REPLY); 0 or DF1_E_*. */
static int radio_reply(struct df1 *h, const uint8_t *out, size_t n, bool corrupt)
{
	int r = radio_send(h, out, n, corrupt);

	if (r < 0)
		return r;
	if (r == 0) {
		df1_count(h, DF1_ID_CNT_REPLY_MSGS_SENT);
		if (out[3] != 0)
			df1_count(h, DF1_ID_CNT_ERROR_MSGS_SENT);
	}
	return 0;
}

/* The responder's replies that are due, oldest first: at once, or at the end
 * of a program scan (DF1_OPT_SCAN_TIME_MS) or after DF1_FAULT_DELAY_REPLY,
 * with the faults of core.c (a stale copy with TNS - 2 first, a bad check).
 * *next: when the next one is due, INT64_MAX when none waits. 0 or DF1_E_*. */
static int radio_due(struct df1 *h, int64_t *next)
{
	*next = INT64_MAX;
	for (;;) {
		struct link_reply *best = NULL;
		int64_t now = df1_now_ms();
		int r = 0;

		for (int i = 0; i < LINK_REPLY_SLOTS; i++) {
			struct link_reply *q = &h->resp->replies[i];

			if (!q->used)
				continue;
			if (q->due_ms > now) {
				*next = q->due_ms < *next ? q->due_ms : *next;
				continue;
			}
			if (!best || (int32_t)(q->seq - best->seq) < 0)
				best = q;
		}
		if (!best)
			return 0;
		best->used = false;
		if (best->stale_first && best->len >= 6) {
			uint8_t old[FRAME_MAX_DATA];
			uint16_t tns = (uint16_t)((best->app[4] | best->app[5] << 8) - 2);

			memcpy(old, best->app, best->len);
			old[4] = (uint8_t)(tns & 0xFF);
			old[5] = (uint8_t)(tns >> 8);
			r = radio_send(h, old, best->len, false);
		}
		if (r >= 0)
			r = radio_reply(h, best->app, best->len, best->corrupt);
		if (r < 0)
			return r;
	}
}

/* A command for this node (or a broadcast): run by fn, its reply sent (df1_serve:
 * queued in the responder's slots, radio_due) unless it is a broadcast. 1
 * handled, 0 ignored (a silent station), DF1_E_*. */
static int radio_command(struct df1 *h, const struct df1_symbol *s, link_handler_fn fn, void *ctx)
{
	uint8_t out[FRAME_MAX_DATA];
	const uint8_t *d = s->data;
	int rlen, r;

	if (h->resp && link_fault_silent(h->resp, d[0]))
		return 0;
	df1_count(h, DF1_ID_CNT_CMD_MSGS_RCVD);
	rlen = fn(h, ctx, d, s->len, out, sizeof out);
	if (d[0] == 255 || rlen <= 0 || (size_t)rlen > sizeof out)
		return 1; /* a broadcast is executed, never answered */
	if (h->resp && link_slot_new(h, d[0], out, (size_t)rlen) != NULL) {
		int64_t next;

		r = radio_due(h, &next); /* at once unless a scan or a delay holds it */
		return r < 0 ? r : 1;
	}
	r = radio_reply(h, out, (size_t)rlen, false);
	return r < 0 ? r : 1;
}

/* A reply for us with no command of ours waiting for it: counted, dropped. */
static void radio_stale(struct df1 *h, const uint8_t *d)
{
	df1_count(h, DF1_ID_CNT_STALE_MSGS_RCVD);
	df1_log(h, DF1_ID_ERR_WRONG_MESSAGE, (int)d[1], (int)d[0], (int)(d[4] | d[5] << 8));
}

/* ------------------------------------------------------------------------
 * Our command
 * ------------------------------------------------------------------------ */

/* A reply for us: ours (its length, copied), 0 another one, DF1_E_*. */
static int radio_take(struct df1 *h, const uint8_t *cmd, const struct df1_symbol *s,
                      uint8_t *reply, size_t cap)
{
	const uint8_t *d = s->data;

	if (d[0] != h->cfg.station || d[1] != cmd[0] || d[4] != cmd[4] || d[5] != cmd[5]) {
		radio_stale(h, d);
		return 0;
	}
	return link_reply_copy(h, cmd, s, reply, cap);
}

/* The peer's commands while ours waits: df1_set_responder's handler. */
static int radio_peer_fn(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *out,
                         size_t cap)
{
	(void)ctx;
	return peer_answer(h, cmd, n, out, cap);
}

/* Listen until deadline: the reply's length, 0 none came, DF1_E_*. */
static int radio_wait_reply(struct df1 *h, const uint8_t *cmd, uint8_t *reply, size_t cap,
                            int64_t deadline)
{
	for (;;) {
		struct df1_symbol s;
		int r = link_read_symbol(h, deadline, &s);

		if (r <= 0)
			return r;
		r = radio_heard(h, &s);
		if (r == 1 && !(s.data[2] & 0x40))
			r = radio_command(h, &s, radio_peer_fn, NULL);
		else if (r == 1)
			r = radio_take(h, cmd, &s, reply, cap);
		if (r < 0 || (r > 0 && (s.data[2] & 0x40)))
			return r;
	}
}

int radio_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap)
{
	int64_t wait = link_timeout_ms(h);
	int tries = 0, r;

	if (h->cfg.cmd_timeout_ms > wait)
		wait = h->cfg.cmd_timeout_ms;
	for (;;) {
		r = radio_send(h, cmd, n, false);
		if (r < 0)
			return r;
		if (r == 0 && tries == 0)
			df1_count(h, DF1_ID_CNT_CMD_MSGS_SENT);
		if (cmd[0] == 255) {
			/* a broadcast: nobody replies; done as an empty STS 0 reply */
			if (r == 1)
				return DF1_E_TIMEOUT; /* not sent: the error is recorded */
			if (cap < 6)
				return df1_fail(h, DF1_E_NOSPACE, 255, "no room for the reply");
			reply[0] = cmd[1], reply[1] = cmd[0], reply[2] = (uint8_t)(cmd[2] | 0x40);
			reply[3] = 0, reply[4] = cmd[4], reply[5] = cmd[5];
			return 6;
		}
		if (r == 0) {
			r = radio_wait_reply(h, cmd, reply, cap, link_after_tx_ms(h, wait));
			if (r != 0)
				return r;
			r = 0;
		}
		if (tries >= h->cfg.app_retries)
			break;
		tries++;
		df1_count(h, DF1_ID_CNT_NAK_RETRIES);
		df1_log(h, DF1_ID_NTC_NAK_RETRY, tries, DF1_ID_ERR_COMMAND_TIMEOUT);
	}
	df1_count(h, DF1_ID_CNT_COMMAND_TIMEOUTS);
	df1_log(h, DF1_ID_ERR_COMMAND_TIMEOUT);
	if (r == 1)
		return DF1_E_TIMEOUT; /* the last copy was not sent: its error is recorded */
	return df1_fail(h, DF1_E_TIMEOUT, cmd[0], "no reply from station %d within %lld ms (%d %s)",
	                cmd[0], (long long)wait, tries + 1, tries ? "tries" : "try");
}

/* ------------------------------------------------------------------------
 * The responder (df1_serve, df1sim)
 * ------------------------------------------------------------------------ */

int radio_serve(struct df1 *h, link_handler_fn fn, void *ctx, int64_t deadline_ms)
{
	int served = 0;

	h->radio_served = true;

	for (;;) {
		struct df1_symbol s;
		int64_t next;
		int r = radio_due(h, &next);

		if (r < 0)
			return r;
		if (served > 0 && next == INT64_MAX && h->rx_pos >= h->rx_len &&
		    !frame_decoder_busy(&h->dec))
			return served; /* answered, nothing under way: back to the caller */
		r = link_read_symbol(h, next < deadline_ms ? next : deadline_ms, &s);
		if (r < 0)
			return r;
		if (r == 0 && next < deadline_ms)
			continue; /* a reply is due */
		if (r == 0)
			return served;
		r = radio_heard(h, &s);
		if (r == 1 && (s.data[2] & 0x40)) {
			radio_stale(h, s.data); /* a reply, and we sent no command */
			r = 0;
		} else if (r == 1) {
			r = radio_command(h, &s, fn, ctx);
			served += r > 0;
		}
		if (r < 0)
			return r;
	}
}

/* ------------------------------------------------------------------------
 * Public: the forward table and the statistics
 * ------------------------------------------------------------------------ */

DF1_API int df1_set_forward(df1_t *h, const uint8_t *table)
{
	bool any = false;

	if (!h)
		return DF1_E_INVAL;
	if (table)
		memcpy(h->cfg.forward, table, sizeof h->cfg.forward);
	else
		memset(h->cfg.forward, 0, sizeof h->cfg.forward);
	for (size_t i = 0; i < sizeof h->cfg.forward; i++)
		any = any || h->cfg.forward[i] != 0;
	h->cfg.forward_set = any;
	return 0;
}

DF1_API int df1_get_forward(const df1_t *h, uint8_t *table)
{
	if (!h || !table)
		return DF1_E_INVAL;
	memcpy(table, h->cfg.forward, sizeof h->cfg.forward);
	return h->cfg.forward_set ? 1 : 0;
}

DF1_API int df1_forward_parse(const char *list, uint8_t *table)
{
	if (!list || !table)
		return DF1_E_INVAL;
	return radio_fwd_parse(list, table) < 0 ? DF1_E_INVAL : 0;
}

DF1_API int df1_radio_stats(const df1_t *h, struct df1_radio_stats *out)
{
	if (!h || !out)
		return DF1_E_INVAL;
	*out = h->radio_st;
	return 0;
}
