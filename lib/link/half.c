/* SPDX-License-Identifier: MPL-2.0 */
/*
 * half.c - DF1 half duplex (doc/PROTOCOL.md 2, doc/REQUIREMENTS.md 004 "Network Reads"
 * and "Active Station List"): the master's transaction (master message, ACK,
 * polls until the reply) and the slave that answers it.
 *
 * Master decisions:
 *  - Active Station List: a transaction for an inactive station first sends
 *    ONE poll; an EOT or any slave message (ACKed, counted stale) makes the
 *    station active and the transaction goes on; anything else fails at once
 *    with DF1_E_INACTIVE (2509). A transaction that fails on the link (NAK,
 *    ENQ limit, command timeout) marks its station inactive; a reply marks it
 *    active.
 *  - Master message: the slave must DLE ACK within timeout_ms. A NAK or the
 *    timeout is a retry (2541, 2521: retransmission); more than nak_retries
 *    is DF1_E_NAK_LIMIT. Other symbols meanwhile are 2515 (after the
 *    decoder's own notice for a broken one) and ignored.
 *  - Polls run from the first poll until cmd_timeout_ms (Cmd_Timeout; DLE EOT
 *    means "not yet", the message is known to be outstanding). A frame with a
 *    bad check (not ACKed: the slave sends it again, doc/PROTOCOL.md 2.3), a broken
 *    symbol or a NAK is an ENQ retry (2543, 2522); more than enq_retries is
 *    DF1_E_ENQ_LIMIT. An answer that is neither DLE EOT nor a slave frame (DLE
 *    ACK, DLE NAK, DLE + an invalid byte) is also 2516 NTC_EOT_STX_EXPECTED.
 *    A poll whose answer does not begin within the poll-answer time
 *    (half_poll_answer_ms, DF1_OPT_POLL_TIMEOUT_MS) counts as an EOT: some
 *    slaves send nothing when they have nothing, and a whole ACK timeout per
 *    poll would exceed Cmd_Timeout before their reply is ready.
 *  - Poll timing (lib/link/half_repoll.h): the first poll after the ACK and the
 *    next after each EOT go out when the station's reply is likely ready,
 *    from its learned reply latency; never closer than two characters (at
 *    least 1 ms, so a TCP-attached line is not flooded). Each pause is a
 *    read with that deadline: anything arriving is still handled.
 *  - Cmd_Timeout: DLE NAK to the line (doc/REQUIREMENTS.md 004 2545: "a NAK Symbol is sent
 *    to the remote device to terminate processing"; in half duplex a NAK from
 *    the master is the global link reset), 2545, 2508, DF1_E_TIMEOUT.
 *  - Every good slave message is ACKed. Duplicates (same SRC CMD TNS as the
 *    last message accepted from the polled station) are dropped (2549, 2524),
 *    other non-matching messages are stale (2548, 2510); polling goes on.
 *
 * Slave decisions:
 *  - Stations answered: h->resp->serve_station[] (df1_server_add_station), or our own
 *    cfg.station when none was added.
 *  - A master message with a good check is ACKed and run; a bad one gets no
 *    answer at all (doc/PROTOCOL.md 2.3). A duplicate is ACKed and not run again: the
 *    reply of the message it repeats is still queued and goes out on the next
 *    poll (a duplicate with other bytes drops that reply: core.c). With no reply slot free the
 *    message is not ACKed (sink full): the master retries.
 *  - A poll gets the oldest queued reply of that station, or DLE EOT. A reply
 *    stays queued until the master's ACK, which must come before the master's
 *    next poll or message (ACKs for other stations are on the line too; slave
 *    frames in between, such as our own echo on a 2-wire line, do not count);
 *    an unacknowledged reply is sent again on the next poll, at most
 *    nak_retries times (2541), then dropped (2542, 2519).
 *  - DLE NAK from the master: global link reset, every queued reply is dropped.
 */
#include "link/link.h"

#include <string.h>

#include "link/link_int.h"

/* polls of a reply overdue by far are at most this far apart (repoll.h) */
#define HD_REPOLL_MAX_GAP_US 20000

/* The least time between an answer and the next poll: two characters at the
 * line's rate, at least a millisecond (a TCP-attached line is not flooded). */
static int64_t half_min_gap_us(const struct df1 *h)
{
	int baud = h->cfg.line_baud > 0 ? h->cfg.line_baud : h->cfg.baud;
	int64_t g = 2 * link_char_us(h, baud);

	return g < 1000 ? 1000 : g;
}

/* How long a poll's answer may take to begin (DF1_OPT_POLL_TIMEOUT_MS; 0:
 * six characters at the line's rate + 20 ms turnaround, + 50 ms of network
 * slack on a port that has it: port_ops.net_slack, TCP), never
 * more than the ACK timeout. */
static int64_t half_poll_answer_ms(const struct df1 *h)
{
	int baud = h->cfg.line_baud > 0 ? h->cfg.line_baud : h->cfg.baud;
	int64_t ms = h->cfg.poll_timeout_ms;

	if (ms <= 0) {
		ms = 6 * link_char_us(h, baud) / 1000 + 20;
		if (h->port && h->port->net_slack)
			ms += 50;
	}
	return ms < link_timeout_ms(h) ? ms : link_timeout_ms(h);
}

/* How long a poll takes to reach the slave (DLE ENQ STN BCC: four characters)
 * on a paced line (df1_set_line_baud): the reply needs to be ready when the
 * poll arrives, not when it is sent. Elsewhere 0: a serial port may be a
 * pseudo-terminal that carries the bytes at once, and a poll sent early by
 * a wire time it does not take would draw more EOTs (TCP takes none). */
static int64_t half_poll_wire_us(const struct df1 *h)
{
	return h->cfg.line_baud > 0 ? 4 * link_char_us(h, h->cfg.line_baud) : 0;
}

enum half_answer {
	ANS_TIMEOUT = 0, /* nothing within the deadline */
	ANS_EOT,         /* DLE EOT: nothing to send yet */
	ANS_REPLY,       /* the reply to our command (copied out) */
	ANS_SKIP,        /* a good message that is not it: ACKed and dropped */
	ANS_BAD,         /* bad check, broken symbol, NAK */
};

/* ------------------------------------------------------------------------
 * Master
 * ------------------------------------------------------------------------ */

/* The answer to a poll of stn (or what arrives while waiting after an EOT).
 * cmd: the outstanding command, or NULL. Returns enum half_answer or DF1_E_*;
 * *cause is the catalog ID behind ANS_BAD / ANS_TIMEOUT. */
static int half_answer(struct df1 *h, uint8_t stn, const uint8_t *cmd, int64_t deadline_ms,
                     uint8_t *reply, size_t cap, size_t *len, int *cause)
{
	for (;;) {
		struct df1_symbol s;
		int r = link_read_symbol(h, deadline_ms, &s);

		if (r < 0)
			return r;
		if (r == 0) {
			*cause = DF1_ID_ERR_COMMAND_TIMEOUT;
			return ANS_TIMEOUT;
		}
		switch (s.kind) {
		case DF1_SYM_EOT:
			df1_count(h, DF1_ID_CNT_EOTS_RCVD);
			return ANS_EOT;
		case DF1_SYM_FRAME:
			if (s.master_msg)
				break; /* our own echo or another master: not an answer */
			if (!s.check_ok) {
				/* no ACK: the slave sends the same message on the next poll */
				link_bad_check(h, &s);
				*cause = s.check == DF1_CHECK_BCC ? DF1_ID_ERR_BAD_BCC
				                                  : DF1_ID_ERR_BAD_CRC;
				return ANS_BAD;
			}
			if (link_is_dup(h, stn, s.data, s.len)) {
				r = link_send_sym(h, DF1_ACK);
				if (r < 0)
					return r;
				df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
				df1_count(h, DF1_ID_CNT_DUPLICATE_MSGS_RCVD);
				df1_log(h, DF1_ID_NTC_DUPLICATE_MSG_RCVD, (int)stn);
				return ANS_SKIP;
			}
			/* in a poll engine's scan, with the next block's message in one
			 * write (the ACK goes alone before any wait, or when df1_poll returns) */
			r = h->hold_reply_ack && cmd ? link_send_sym_held(h, DF1_ACK) : link_send_sym(h, DF1_ACK);
			if (r < 0)
				return r;
			link_remember(h, stn, s.data, s.len);
			if (!route_is_ours(h, s.data)) {
				/* a slave's own command, or a reply for another slave (route.c) */
				r = route_take(h, &s);
				return r < 0 ? r : ANS_SKIP;
			}
			r = link_take_reply(h, cmd, &s, reply, cap, len);
			if (r < 0)
				return r;
			return r == 1 ? ANS_REPLY : ANS_SKIP;
		case DF1_SYM_ERROR:
			if (s.master_msg || (s.has_station && s.error == DF1_ID_ERR_BAD_BCC))
				break; /* a broken master message or poll: our echo, garbled */
			if (!link_log_error(h, &s))
				/* DLE x: not EOT, not STX */
				df1_log(h, DF1_ID_NTC_EOT_STX_EXPECTED, (int)s.bad_byte);
			*cause = s.error;
			return ANS_BAD;
		case DF1_SYM_NAK:
			df1_count(h, DF1_ID_CNT_NAKS_RCVD);
			df1_log(h, DF1_ID_NTC_RCVD_NAK_SYMBOL);
			df1_log(h, DF1_ID_NTC_EOT_STX_EXPECTED, DF1_NAK);
			*cause = DF1_ID_NTC_RCVD_NAK_SYMBOL;
			return ANS_BAD;
		case DF1_SYM_ACK:
			df1_count(h, DF1_ID_CNT_ACKS_RCVD); /* a stray ACK */
			df1_log(h, DF1_ID_NTC_EOT_STX_EXPECTED, DF1_ACK);
			break;
		default: /* a poll: our echo or another master */
			break;
		}
	}
}

static int half_send_poll(struct df1 *h, uint8_t stn)
{
	uint8_t poll[5];
	size_t n = frame_encode_poll(stn, poll, sizeof poll);
	int r = link_send_raw(h, poll, n);

	if (r < 0)
		return r;
	df1_count(h, DF1_ID_CNT_POLL_MSGS_SENT);
	return 0;
}

/* Wait for the slave's DLE ACK of our master message: 1 ACK, 0 not (NAK or
 * timeout, *cause), DF1_E_*. */
static int half_wait_ack(struct df1 *h, int64_t deadline_ms, int *cause)
{
	for (;;) {
		struct df1_symbol s;
		int r = link_read_symbol(h, deadline_ms, &s);

		if (r < 0)
			return r;
		if (r == 0) {
			*cause = DF1_ID_ERR_COMMAND_TIMEOUT;
			return 0;
		}
		switch (s.kind) {
		case DF1_SYM_ACK:
			df1_count(h, DF1_ID_CNT_ACKS_RCVD);
			return 1;
		case DF1_SYM_NAK:
			df1_count(h, DF1_ID_CNT_NAKS_RCVD);
			df1_log(h, DF1_ID_NTC_RCVD_NAK_SYMBOL);
			*cause = DF1_ID_NTC_RCVD_NAK_SYMBOL;
			return 0;
		case DF1_SYM_EOT:
			df1_log(h, DF1_ID_NTC_ACK_EXPECTED, DF1_EOT);
			break;
		case DF1_SYM_FRAME:
			if (!s.master_msg)
				df1_log(h, DF1_ID_NTC_ACK_EXPECTED, DF1_STX);
			break;
		case DF1_SYM_ERROR:
			if (s.master_msg || (s.has_station && s.error == DF1_ID_ERR_BAD_BCC))
				break; /* a master message or poll, garbled: not the slave's */
			link_log_error(h, &s); /* what was wrong with it (2512-2514, 2518) */
			df1_log(h, DF1_ID_NTC_ACK_EXPECTED, (int)s.bad_byte);
			break;
		default:
			break;
		}
	}
}

/* One poll of stn with no command outstanding: enum half_answer (*cause as
 * half_answer's) or DF1_E_*. An EOT or a slave message makes stn active. */
static int half_poll_once(struct df1 *h, uint8_t stn, int *cause)
{
	size_t len = 0;
	int r = half_send_poll(h, stn);

	if (r < 0)
		return r;
	r = half_answer(h, stn, NULL, link_after_tx_ms(h, link_timeout_ms(h)), NULL, 0, &len, cause);
	if (r == ANS_EOT || r == ANS_SKIP)
		h->stations[stn].active = true;
	return r;
}

/* The Active Station List probe: one poll. 0 (the station answered) or DF1_E_*. */
static int half_probe(struct df1 *h, uint8_t stn)
{
	int cause = 0;
	int r = half_poll_once(h, stn, &cause);

	if (r < 0)
		return r;
	if (r == ANS_EOT || r == ANS_SKIP)
		return 0;
	df1_log(h, DF1_ID_ERR_INACTIVE_STATION, (int)stn);
	return df1_fail(h, DF1_E_INACTIVE, stn, "slave station %d inactive", stn);
}

int half_poll_station(struct df1 *h, uint8_t stn)
{
	size_t len = 0;
	int cause = 0, r = half_send_poll(h, stn);

	if (r < 0)
		return r;
	r = half_answer(h, stn, NULL, link_after_tx_ms(h, half_poll_answer_ms(h)), NULL, 0, &len, &cause);
	if (r < 0)
		return r;
	if (r == ANS_EOT || r == ANS_SKIP)
		h->stations[stn].active = true;
	return r == ANS_SKIP ? 1 : 0;
}

int half_send_msg(struct df1 *h, uint8_t stn, const uint8_t *app, size_t n)
{
	uint8_t wire[FRAME_MAX_WIRE];
	size_t wn = frame_encode_master(link_tx_check(h), stn, h->cfg.hd_bcc_stx, app, n, wire, sizeof wire);
	int cause = 0, r;

	if (wn == 0)
		return df1_fail(h, DF1_E_INVAL, stn, "message of %zu bytes does not fit a frame", n);
	for (int tries = 0;; tries++) {
		r = link_send_raw(h, wire, wn);
		if (r < 0)
			return r;
		df1_count(h, DF1_ID_CNT_MSG_PACKETS_SENT);
		if (tries == 0)
			df1_count(h, app[2] & 0x40 ? DF1_ID_CNT_REPLY_MSGS_SENT : DF1_ID_CNT_CMD_MSGS_SENT);
		if (stn == 255)
			return 1; /* a broadcast: nobody ACKs it (doc/PROTOCOL.md 2.3) */
		r = half_wait_ack(h, link_after_tx_ms(h, link_timeout_ms(h)), &cause);
		if (r != 0)
			return r;
		if (tries >= h->cfg.nak_retries) {
			df1_count(h, DF1_ID_CNT_NAK_LIMIT_EXCEEDED);
			df1_log(h, DF1_ID_NTC_NAK_LIMIT_EXCEEDED, h->cfg.nak_retries);
			h->stations[stn].active = false;
			return 0;
		}
		df1_count(h, DF1_ID_CNT_NAK_RETRIES);
		df1_log(h, DF1_ID_NTC_NAK_RETRY, tries + 1, cause);
	}
}

/* A link failure of a transaction: the station leaves the active list. */
static int half_failed(struct df1 *h, uint8_t stn, int code)
{
	h->stations[stn].active = false;
	return code;
}

/* One command of ours on the line (half_transact). */
struct half_cmd {
	const uint8_t *cmd;
	uint8_t wire[FRAME_MAX_WIRE];
	size_t wn;
	uint8_t stn;
	int enqs, cause;
	int64_t wait;                /* Cmd_Timeout, from the ACK */
	int64_t deadline;            /* ms: the ACK plus wait */
	int64_t ack_us;              /* the ACK */
	int64_t poll_at_us, poll_us; /* the next poll, the last one sent */
	int64_t prev_poll_us;        /* the one before it (answered "not yet"), 0 none */
	struct repoll_est *lat;
};

/* 1. the master message, until the slave ACKs it: 0 or DF1_E_*. */
static int half_cmd_send(struct df1 *h, struct half_cmd *t)
{
	int tries = 0, r;

	for (;;) {
		r = link_send_raw(h, t->wire, t->wn);
		if (r < 0)
			return r;
		df1_count(h, DF1_ID_CNT_MSG_PACKETS_SENT);
		if (tries == 0)
			df1_count(h, DF1_ID_CNT_CMD_MSGS_SENT);
		r = half_wait_ack(h, link_after_tx_ms(h, link_timeout_ms(h)), &t->cause);
		if (r < 0)
			return r;
		if (r == 1)
			return 0;
		if (tries >= h->cfg.nak_retries) {
			df1_count(h, DF1_ID_CNT_NAK_LIMIT_EXCEEDED);
			df1_log(h, DF1_ID_NTC_NAK_LIMIT_EXCEEDED, h->cfg.nak_retries);
			return half_failed(h, t->stn, df1_fail(h, DF1_E_NAK_LIMIT, t->stn,
			                 "station %d did not ACK the command (%d tries)", t->stn,
			                 tries + 1));
		}
		tries++;
		df1_count(h, DF1_ID_CNT_NAK_RETRIES);
		df1_log(h, DF1_ID_NTC_NAK_RETRY, tries, t->cause);
	}
}

/* Cmd_Timeout ran out: DF1_E_*. */
static int half_cmd_timeout(struct df1 *h, struct half_cmd *t)
{
	int r = link_send_sym(h, DF1_NAK); /* end the slave's processing (doc/REQUIREMENTS.md 004) */

	if (r < 0)
		return r;
	df1_count(h, DF1_ID_CNT_COMMAND_TIMEOUTS);
	df1_log(h, DF1_ID_ERR_COMMAND_TIMEOUT);
	return half_failed(h, t->stn, df1_fail(h, DF1_E_TIMEOUT, t->stn,
	                 "no reply from station %d within %lld ms", t->stn, (long long)t->wait));
}

/* A poll when one is due (*polled), else the pause before it: the end of the
 * read for what comes (*dl, at most Cmd_Timeout). The pause is waited to the
 * microsecond first (the read's deadline is a whole ms, on average half a ms
 * late after every ACK): when it ends with nothing come, the poll is due and
 * goes now. 0 or DF1_E_*. */
static int half_cmd_poll(struct df1 *h, struct half_cmd *t, int64_t now_us, bool *polled, int64_t *dl)
{
	int r;

	if (!*polled) {
		r = link_wait_input_us(h, t->poll_at_us);
		if (r < 0)
			return r;
		if (r == 0) {
			*polled = true;
			now_us = (int64_t)df1_now_us();
		}
	}
	if (*polled) {
		t->prev_poll_us = t->poll_us;
		t->poll_us = now_us;
		r = half_send_poll(h, t->stn);
		if (r < 0)
			return r;
		/* a slave that suppresses DLE EOT sends nothing at all: a short
		 * wait for the first byte, then a poll again (DF1_OPT_POLL_TIMEOUT_MS) */
		*dl = link_after_tx_ms(h, half_poll_answer_ms(h));
	} else {
		/* the pause before the next poll is a read: anything arriving is handled */
		*dl = (t->poll_at_us + 999) / 1000;
	}
	if (*dl > t->deadline)
		*dl = t->deadline;
	return 0;
}

/* An answer with no valid message: a poll again now, until the ENQ retry
 * limit. 0 or DF1_E_*. */
static int half_cmd_bad(struct df1 *h, struct half_cmd *t, int64_t now_us)
{
	if (t->enqs >= h->cfg.enq_retries) {
		df1_count(h, DF1_ID_CNT_ENQ_LIMIT_EXCEEDED);
		df1_log(h, DF1_ID_NTC_ENQ_LIMIT_EXCEEDED, h->cfg.enq_retries);
		return half_failed(h, t->stn, df1_fail(h, DF1_E_ENQ_LIMIT, t->stn,
		                 "no valid answer to %d polls of station %d", t->enqs + 1, t->stn));
	}
	t->enqs++;
	df1_count(h, DF1_ID_CNT_ENQ_RETRIES);
	df1_log(h, DF1_ID_NTC_ENQ_RETRY, t->enqs, t->cause);
	t->poll_at_us = now_us;
	return 0;
}

/* What came in the read (enum half_answer a) after a poll (polled) or in the
 * pause: 1 our reply, 0 go on (poll_at_us set), DF1_E_*. */
static int half_cmd_answer(struct df1 *h, struct half_cmd *t, int a, bool polled)
{
	int64_t now_us = (int64_t)df1_now_us();

	switch (a) {
	case ANS_REPLY:
		h->stations[t->stn].active = true;
		/* the reply was ready when the poll that drew it arrived (not
		 * when the reply had arrived: its own wire time is no latency) */
		/* after a "not yet" from a poll shortly before (a scan's few ms),
		 * between the two polls' arrivals: the midpoint (the later one
		 * alone teaches a latency a whole EOT round late, and every first
		 * poll after it waits that much longer). Polls far apart (a slow
		 * reply polled sparsely) keep the later one: fewer polls next time. */
		repoll_learn(t->lat, (t->prev_poll_us && t->poll_us - t->prev_poll_us <= HD_REPOLL_MAX_GAP_US / 2
		                      ? (t->prev_poll_us + t->poll_us) / 2 : t->poll_us) +
		                     half_poll_wire_us(h) - t->ack_us);
		return 1;
	case ANS_TIMEOUT:
		if (!polled)
			return 0; /* the pause ended: poll now */
		/* a poll nobody answered: not ready yet, as an EOT */
		__attribute__((fallthrough));
	case ANS_EOT:
		/* the message is outstanding: poll again when it is likely ready */
		t->poll_at_us = now_us + repoll_next_us(t->lat, now_us + half_poll_wire_us(h) - t->ack_us,
		                                        half_min_gap_us(h), HD_REPOLL_MAX_GAP_US);
		return 0;
	case ANS_SKIP:
		t->poll_at_us = now_us;
		return 0;
	case ANS_BAD:
	default:
		return half_cmd_bad(h, t, now_us);
	}
}

int half_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap)
{
	struct half_cmd t = { .cmd = cmd, .stn = cmd[0] };
	int r;

	t.wn = frame_encode_master(link_tx_check(h), t.stn, h->cfg.hd_bcc_stx, cmd, n, t.wire,
	                           sizeof t.wire);
	t.wait = h->cfg.cmd_timeout_ms > 0 ? h->cfg.cmd_timeout_ms : link_timeout_ms(h);
	if (t.wn == 0)
		return df1_fail(h, DF1_E_INVAL, t.stn, "command of %zu bytes does not fit a frame", n);
	route_seen(h, t.stn); /* polled between our transactions too (route.c) */
	if (!h->stations[t.stn].active) {
		r = half_probe(h, t.stn);
		if (r < 0)
			return r;
	}
	r = half_cmd_send(h, &t);
	if (r < 0)
		return r;

	/* 2. polls until the reply, the ENQ retry limit or Cmd_Timeout; the
	 * first when the reply is likely ready (repoll.h), the next ones after
	 * each EOT or unanswered poll when it is likely ready then */
	t.ack_us = (int64_t)df1_now_us();
	t.deadline = df1_now_ms() + t.wait;
	t.lat = &h->stations[t.stn].reply_latency;
	t.poll_at_us = t.ack_us + repoll_first_us(t.lat) - half_poll_wire_us(h);
	for (;;) {
		int64_t now = df1_now_ms(), now_us = (int64_t)df1_now_us(), dl;
		bool polled = t.poll_at_us <= now_us;
		size_t len = 0;

		if (now >= t.deadline)
			return half_cmd_timeout(h, &t);
		r = half_cmd_poll(h, &t, now_us, &polled, &dl);
		if (r < 0)
			return r;
		r = half_answer(h, t.stn, cmd, dl, reply, cap, &len, &t.cause);
		if (r < 0)
			return r;
		r = half_cmd_answer(h, &t, r, polled);
		if (r < 0)
			return r;
		if (r == 1)
			return (int)len;
	}
}

int half_test(struct df1 *h, uint8_t stn)
{
	int cause = 0;
	int r = half_poll_once(h, stn, &cause);

	if (r < 0)
		return r;
	switch (r) {
	case ANS_EOT:
	case ANS_SKIP:
		return 0;
	case ANS_TIMEOUT:
		return df1_fail(h, DF1_E_TIMEOUT, stn, "station %d did not answer the poll", stn);
	default:
		switch (cause) {
		case DF1_ID_ERR_BAD_CRC:
			return df1_fail(h, DF1_E_CRC, stn, "station %d answered with a bad CRC", stn);
		case DF1_ID_ERR_BAD_BCC:
			return df1_fail(h, DF1_E_BCC, stn, "station %d answered with a bad BCC", stn);
		case DF1_ID_NTC_RCVD_NAK_SYMBOL:
			return df1_fail(h, DF1_E_NAK, stn, "station %d answered NAK", stn);
		default:
			return df1_fail(h, DF1_E_BAD_REPLY, stn, "station %d answered garbage", stn);
		}
	}
}

/* ------------------------------------------------------------------------
 * Slave
 * ------------------------------------------------------------------------ */

static bool half_serves(const struct df1 *h, uint8_t stn, bool any_added)
{
	return any_added ? h->resp->serve_station[stn] : stn == (uint8_t)h->cfg.station;
}

/* A poll for one of our stations: the oldest queued reply, or DLE EOT. */
static int half_slave_poll(struct df1 *h, uint8_t stn)
{
	struct link_reply *t;
	int r;

	df1_count(h, DF1_ID_CNT_POLL_MSGS_RCVD);
	for (;;) {
		t = link_slot_oldest(h, false, stn);
		if (!t || !t->sent)
			break;
		/* sent on an earlier poll and not ACKed: again, up to nak_retries times */
		if (t->naks < h->cfg.nak_retries) {
			t->naks++;
			df1_count(h, DF1_ID_CNT_NAK_RETRIES);
			df1_log(h, DF1_ID_NTC_NAK_RETRY, t->naks, DF1_ID_NTC_ACK_EXPECTED);
			break;
		}
		df1_count(h, DF1_ID_CNT_NAK_LIMIT_EXCEEDED);
		df1_log(h, DF1_ID_NTC_NAK_LIMIT_EXCEEDED, h->cfg.nak_retries);
		t->used = false;
	}
	if (t && t->due_ms > df1_now_ms())
		t = NULL; /* DF1_FAULT_DELAY_REPLY, DF1_OPT_SCAN_TIME_MS: not ready yet */
	if (!t)
		return h->cfg.no_eot ? 0 : link_send_sym(h, DF1_EOT); /* DF1_OPT_NO_EOT: silence */
	h->resp->awaiting = (int)(t - h->resp->replies) + 1;
	if (t->stale_first) {
		t->stale_first = false;
		h->resp->awaiting_stale = true;
		return link_slot_send(h, t, true, true);
	}
	h->resp->awaiting_stale = false;
	r = link_slot_send(h, t, false, !t->sent);
	t->sent = true;
	return r;
}

/* A master message. Returns 1 when the handler ran, 0, or DF1_E_*. */
static int half_slave_msg(struct df1 *h, const struct df1_symbol *s, link_handler_fn fn, void *ctx)
{
	uint8_t out[FRAME_MAX_DATA];
	const uint8_t *d = s->data;
	uint8_t stn = s->station;
	int r, rlen;

	if (!s->check_ok) {
		link_bad_check(h, s); /* no answer: the master times out and retries */
		return 0;
	}
	/* a duplicate is not run again (and one with other bytes drops the reply
	 * queued under its header: core.c) */
	if ((d[2] & 0x40) && !link_is_dup(h, stn, d, s->len) && half_msg_reply(h, s))
		return 0; /* the reply to our own MSG (half_msg.c) */
	r = link_serve_screen(h, stn, s);
	if (r <= 0)
		return r;
	if (link_fault(h->resp, DF1_FAULT_NAK_COMMAND)) {
		r = link_send_sym(h, DF1_NAK);
		return r < 0 ? r : 0;
	}
	if (!link_slot_free_exists(h))
		return 0; /* sink full: no ACK, the master sends it again later */
	if (!link_fault(h->resp, DF1_FAULT_DROP_ACK)) {
		r = link_send_sym(h, DF1_ACK);
		if (r < 0)
			return r;
	}
	link_remember(h, stn, d, s->len);
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	df1_count(h, DF1_ID_CNT_CMD_MSGS_RCVD);
	rlen = fn(h, ctx, d, s->len, out, sizeof out);
	if (rlen > 0 && (size_t)rlen <= sizeof out)
		(void)link_slot_new(h, stn, out, (size_t)rlen);
	return 1;
}

/* A broadcast master message (station 255): run, neither ACKed nor answered
 * (doc/PROTOCOL.md 2.3; a slave's broadcast that its master forwards, route.c). */
static void half_slave_broadcast(struct df1 *h, const struct df1_symbol *s, link_handler_fn fn,
                                 void *ctx)
{
	uint8_t out[FRAME_MAX_DATA];

	if (!s->check_ok || (s->data[2] & 0x40)) {
		if (!s->check_ok)
			link_bad_check(h, s);
		return;
	}
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	df1_count(h, DF1_ID_CNT_CMD_MSGS_RCVD);
	(void)fn(h, ctx, s->data, s->len, out, sizeof out);
}

int half_serve(struct df1 *h, link_handler_fn fn, void *ctx, int64_t deadline_ms)
{
	bool any_added = false;
	int served = 0;

	for (int i = 0; i < 256; i++)
		any_added = any_added || h->resp->serve_station[i];
	for (;;) {
		struct df1_symbol s;
		int r, awaiting;
		bool awaiting_stale;

		if (df1_now_ms() >= deadline_ms || half_msg_over(h))
			return served;
		if (served > 0 && h->rx_pos >= h->rx_len && !frame_decoder_busy(&h->dec))
			return served;
		r = link_read_symbol(h, deadline_ms, &s);
		if (r < 0)
			return r;
		if (r == 0)
			return served;
		/* An ACK is for our reply only before the master moves on (its next
		 * poll or message); slave frames in between are our own echo. */
		awaiting = h->resp->awaiting;
		awaiting_stale = h->resp->awaiting_stale;
		if (s.kind == DF1_SYM_ACK || s.kind == DF1_SYM_POLL ||
		    (s.kind == DF1_SYM_FRAME && s.master_msg)) {
			h->resp->awaiting = 0;
			h->resp->awaiting_stale = false;
		}
		r = 0;
		switch (s.kind) {
		case DF1_SYM_ACK:
			if (awaiting > 0) {
				df1_count(h, DF1_ID_CNT_ACKS_RCVD);
				if (!awaiting_stale) {
					half_msg_acked(h, &h->resp->replies[awaiting - 1]);
					h->resp->replies[awaiting - 1].used = false;
				}
			}
			break;
		case DF1_SYM_NAK:
			/* the master's global link reset (doc/PROTOCOL.md 2.1) */
			df1_count(h, DF1_ID_CNT_NAKS_RCVD);
			df1_log(h, DF1_ID_NTC_RCVD_NAK_SYMBOL);
			link_slots_clear(h);
			break;
		case DF1_SYM_POLL:
			if (half_serves(h, s.station, any_added) && !link_fault_silent(h->resp, s.station))
				r = half_slave_poll(h, s.station);
			break;
		case DF1_SYM_FRAME:
			if (s.master_msg && s.station == 255) {
				half_slave_broadcast(h, &s, fn, ctx);
				break;
			}
			/* slave messages on the line are other stations' business */
			if (s.master_msg && half_serves(h, s.station, any_added) &&
			    !link_fault_silent(h->resp, s.station)) {
				r = half_slave_msg(h, &s, fn, ctx);
				if (r > 0) {
					served++;
					r = 0;
				}
			}
			break;
		case DF1_SYM_ERROR:
			if (s.has_station && half_serves(h, s.station, any_added))
				link_log_error(h, &s); /* no answer */
			break;
		default:
			break;
		}
		if (r < 0)
			return r;
	}
}
