/* SPDX-License-Identifier: MPL-2.0 */
/*
 * full.c - the DF1 full-duplex peer (doc/PROTOCOL.md 1, doc/ARCHITECTURE.md 4): the
 * receiver rules, the master's transaction (ACK timer, ENQ and NAK retries)
 * and the responder (one reply in flight). The decisions it follows are listed
 * in core.c, which holds what it shares with half.c; link.c dispatches here.
 */
#include "link/link.h"

#include "link/link_int.h"

/* ------------------------------------------------------------------------
 * Full duplex: the receiver (doc/PROTOCOL.md 1.7)
 * ------------------------------------------------------------------------ */

/* A frame with a bad check or an ERROR symbol: DLE NAK when a frame was broken,
 * else only the last response becomes NAK. */
static int full_reject(struct df1 *h, const struct df1_symbol *s)
{
	bool in_frame;

	if (s->kind == DF1_SYM_FRAME) {
		link_bad_check(h, s);
		in_frame = true;
	} else {
		in_frame = link_log_error(h, s);
	}
	if (!in_frame) {
		link_noise(h);
		return 0;
	}
	return link_send_sym(h, DF1_NAK);
}

/* ------------------------------------------------------------------------
 * Full duplex: master transaction
 * ------------------------------------------------------------------------ */

/* One command of ours on the line (full_transact). */
struct full_cmd {
	const uint8_t *cmd;
	uint8_t wire[FRAME_MAX_WIRE];
	size_t wn;
	int stn, naks, enqs;
	int64_t reply_wait;          /* max(timeout_ms, cmd_timeout_ms), from the ACK */
	int64_t deadline;            /* ACK timer, then reply timer */
	bool sent;                   /* on the line (it waits while a reply of ours does) */
	bool acked;
};

/* The timer ran out: no reply after the ACK, or no ACK: ENQ (doc/PROTOCOL.md 1.6 rule 4)
 * until the limit. 0 (go on) or DF1_E_*. */
static int full_cmd_timeout(struct df1 *h, struct full_cmd *t)
{
	int r;

	if (t->acked) {
		df1_count(h, DF1_ID_CNT_COMMAND_TIMEOUTS);
		df1_log(h, DF1_ID_ERR_COMMAND_TIMEOUT);
		return df1_fail(h, DF1_E_TIMEOUT, t->stn, "no reply from station %d", t->stn);
	}
	if (t->enqs >= h->cfg.enq_retries) {
		df1_count(h, DF1_ID_CNT_ENQ_LIMIT_EXCEEDED);
		df1_log(h, DF1_ID_NTC_ENQ_LIMIT_EXCEEDED, h->cfg.enq_retries);
		return df1_fail(h, DF1_E_ENQ_LIMIT, t->stn,
		                "no ACK from station %d after %d ENQ", t->stn, t->enqs);
	}
	t->enqs++;
	df1_count(h, DF1_ID_CNT_ENQ_RETRIES);
	df1_log(h, DF1_ID_NTC_ENQ_RETRY, t->enqs, DF1_ID_ERR_COMMAND_TIMEOUT);
	r = link_send_sym(h, DF1_ENQ);
	if (r < 0)
		return r;
	t->deadline = link_after_tx_ms(h, link_timeout_ms(h));
	return 0;
}

/* A NAK: the command again, until the limit. 0 or DF1_E_*. */
static int full_cmd_nak(struct df1 *h, struct full_cmd *t)
{
	int r;

	df1_count(h, DF1_ID_CNT_NAKS_RCVD);
	if (t->acked) {
		/* no frame of ours is waiting for a response */
		df1_log(h, DF1_ID_ERR_RCVD_NAK_SYMBOL);
		return 0;
	}
	df1_log(h, DF1_ID_NTC_RCVD_NAK_SYMBOL);
	if (t->naks >= h->cfg.nak_retries) {
		df1_count(h, DF1_ID_CNT_NAK_LIMIT_EXCEEDED);
		df1_log(h, DF1_ID_NTC_NAK_LIMIT_EXCEEDED, h->cfg.nak_retries);
		return df1_fail(h, DF1_E_NAK_LIMIT, t->stn,
		                "station %d answered NAK %d times", t->stn, t->naks + 1);
	}
	t->naks++;
	df1_count(h, DF1_ID_CNT_NAK_RETRIES);
	df1_log(h, DF1_ID_NTC_NAK_RETRY, t->naks, DF1_ID_NTC_RCVD_NAK_SYMBOL);
	r = link_send_raw(h, t->wire, t->wn);
	if (r < 0)
		return r;
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_SENT);
	t->deadline = link_after_tx_ms(h, link_timeout_ms(h));
	return 0;
}

/* A frame with a good check: a duplicate is ACKed again; anything else is
 * ACKed and taken: 1 when it is our reply (its length in *len), 0 go on, DF1_E_*. */
static int full_cmd_frame(struct df1 *h, const struct full_cmd *t, const struct df1_symbol *s,
                          uint8_t *reply, size_t cap, size_t *len)
{
	int r;

	if (link_is_dup(h, s->data[1], s->data, s->len)) {
		r = link_send_sym(h, DF1_ACK);
		if (r < 0)
			return r;
		df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
		df1_count(h, DF1_ID_CNT_DUPLICATE_MSGS_RCVD);
		df1_log(h, DF1_ID_NTC_DUPLICATE_MSG_RCVD, (int)s->data[1]);
		return 0;
	}
	if (!(s->data[2] & 0x40))
		return peer_command(h, s, h->hold_reply_ack); /* the peer's own command (peer.c) */
	/* in a poll engine's scan, with our next command in one write
	 * (alone before any wait, or when df1_poll returns) */
	r = h->hold_reply_ack ? link_send_sym_held(h, DF1_ACK) : link_send_sym(h, DF1_ACK);
	if (r < 0)
		return r;
	link_remember(h, s->data[1], s->data, s->len);
	return link_take_reply(h, t->cmd, s, reply, cap, len);
}

/* One symbol while our command is on the line: 1 when it is our reply, 0 go on, DF1_E_*. */
static int full_cmd_symbol(struct df1 *h, struct full_cmd *t, const struct df1_symbol *s,
                           uint8_t *reply, size_t cap, size_t *len)
{
	switch (s->kind) {
	case DF1_SYM_ACK:
		if (peer_on_line(h)) {
			peer_acked(h); /* the ACK of our reply to the peer */
			return 0;
		}
		df1_count(h, DF1_ID_CNT_ACKS_RCVD);
		if (!t->acked) {
			t->acked = true;
			t->deadline = df1_now_ms() + t->reply_wait;
		}
		return 0;
	case DF1_SYM_NAK:
		return peer_on_line(h) ? peer_nak(h) : full_cmd_nak(h, t);
	case DF1_SYM_ENQ:
		/* the peer asks for our last response */
		return link_send_sym(h, h->last_response);
	case DF1_SYM_FRAME:
		if (s->master_msg) {
			link_noise(h); /* no half-duplex framing on a full-duplex link */
			return 0;
		}
		if (!s->check_ok)
			return full_reject(h, s);
		return full_cmd_frame(h, t, s, reply, cap, len);
	case DF1_SYM_ERROR:
		return full_reject(h, s);
	default: /* EOT, poll: not full-duplex symbols */
		link_noise(h);
		return 0;
	}
}

/* What may go on the line now: one frame of ours waits for an ACK at a time
 * (peer.c): our command first, then the replies to the peer's commands. */
static int full_cmd_line(struct df1 *h, struct full_cmd *t)
{
	int r;

	if (peer_on_line(h) || (t->sent && !t->acked))
		return 0;
	if (t->sent)
		return peer_start(h);
	r = link_send_raw(h, t->wire, t->wn);
	if (r < 0)
		return r;
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_SENT);
	df1_count(h, DF1_ID_CNT_CMD_MSGS_SENT);
	t->sent = true;
	t->deadline = link_after_tx_ms(h, link_timeout_ms(h));
	return 0;
}

int full_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap)
{
	struct full_cmd t = { .cmd = cmd, .stn = cmd[0] };
	int r;

	t.wn = frame_encode_full(link_tx_check(h), cmd, n, t.wire, sizeof t.wire);
	if (t.wn == 0)
		return df1_fail(h, DF1_E_INVAL, t.stn, "command of %zu bytes does not fit a frame", n);
	t.reply_wait = link_timeout_ms(h);
	if (h->cfg.cmd_timeout_ms > t.reply_wait)
		t.reply_wait = h->cfg.cmd_timeout_ms;
	for (;;) {
		struct df1_symbol s;
		size_t len = 0;
		int64_t dl, pdl;

		r = full_cmd_line(h, &t);
		if (r < 0)
			return r;
		pdl = peer_deadline(h);
		dl = t.sent && t.deadline < pdl ? t.deadline : pdl;
		r = link_read_symbol(h, dl, &s);
		if (r < 0)
			return r;
		if (r == 0 && pdl <= dl)
			r = peer_timeout(h, dl); /* our reply to the peer: its ENQ (or its due time) */
		else if (r == 0)
			r = full_cmd_timeout(h, &t);
		else
			r = full_cmd_symbol(h, &t, &s, reply, cap, &len);
		if (r < 0)
			return r;
		if (r == 1)
			return (int)len;
	}
}

/* Full duplex DLE ENQ: any response symbol means the peer is there. */
int full_test(struct df1 *h)
{
	int64_t deadline;
	int r = link_send_sym(h, DF1_ENQ);

	if (r < 0)
		return r;
	deadline = link_after_tx_ms(h, link_timeout_ms(h));
	for (;;) {
		struct df1_symbol s;

		r = link_read_symbol(h, deadline, &s);
		if (r < 0)
			return r;
		if (r == 0)
			return df1_fail(h, DF1_E_TIMEOUT, -1, "no answer to DLE ENQ");
		switch (s.kind) {
		case DF1_SYM_ACK:
			df1_count(h, DF1_ID_CNT_ACKS_RCVD);
			return 0;
		case DF1_SYM_NAK:
			df1_count(h, DF1_ID_CNT_NAKS_RCVD);
			return 0;
		case DF1_SYM_ENQ:
			r = link_send_sym(h, h->last_response);
			break;
		case DF1_SYM_FRAME:
			if (s.master_msg) {
				link_noise(h);
			} else if (!s.check_ok) {
				r = full_reject(h, &s);
			} else if (link_is_dup(h, s.data[1], s.data, s.len)) {
				r = link_ack_dup(h, &s);
			} else {
				size_t len;

				r = link_send_sym(h, DF1_ACK);
				link_remember(h, s.data[1], s.data, s.len);
				if (r >= 0)
					r = link_take_reply(h, NULL, &s, NULL, 0, &len);
			}
			break;
		case DF1_SYM_ERROR:
			r = full_reject(h, &s);
			break;
		default:
			link_noise(h);
			break;
		}
		if (r < 0)
			return r;
	}
}

/* ------------------------------------------------------------------------
 * Full duplex: responder
 * ------------------------------------------------------------------------ */

/* A controller with full buffers NAKs a new command (doc/PROTOCOL.md 1.7: "message source
 * full"): the commands accepted whose reply is not through (queued, or sent
 * and not ACKed) fill max_queue. */
static bool full_queue_full(struct df1 *h)
{
	int n = 0;

	if (h->resp->max_queue == 0)
		return false;
	for (int i = 0; i < LINK_REPLY_SLOTS; i++)
		n += h->resp->replies[i].used;
	return n >= h->resp->max_queue;
}

/* A frame for the responder. Returns 1 when the handler ran, 0, or DF1_E_*. */
static int full_serve_frame(struct df1 *h, const struct df1_symbol *s, link_handler_fn fn, void *ctx)
{
	uint8_t out[FRAME_MAX_DATA];
	const uint8_t *d = s->data;
	bool drop_ack;
	int r, rlen;

	if (s->master_msg) {
		link_noise(h);
		return 0;
	}
	if (!s->check_ok)
		return full_reject(h, s);
	if (link_fault_silent(h->resp, d[0])) {
		h->resp->silenced = true; /* not even a response to the ENQs that follow */
		return 0;
	}
	h->resp->silenced = false;
	r = link_serve_screen(h, d[1], s);
	if (r <= 0)
		return r;
	if (link_fault(h->resp, DF1_FAULT_NAK_COMMAND) || full_queue_full(h)) {
		r = link_send_sym(h, DF1_NAK);
		return r < 0 ? r : 0;
	}
	drop_ack = link_fault(h->resp, DF1_FAULT_DROP_ACK);
	if (drop_ack) {
		h->last_response = DF1_ACK; /* as if our ACK was lost on the line */
	} else {
		/* with the reply if it is ready at once (full_serve sends it next) */
		r = link_send_sym_held(h, DF1_ACK);
		if (r < 0)
			return r;
	}
	link_remember(h, d[1], d, s->len);
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	df1_count(h, DF1_ID_CNT_CMD_MSGS_RCVD);
	/* without a queue, a new command means the master no longer waits for an
	 * older reply; with one, the replies go out in order */
	if (h->resp->max_queue == 0)
		link_slots_clear(h);
	rlen = fn(h, ctx, d, s->len, out, sizeof out);
	if (rlen > 0 && (size_t)rlen <= sizeof out && link_slot_new(h, d[1], out, (size_t)rlen) == NULL)
		return df1_fail(h, DF1_E_NOSPACE, d[1], "no reply slot free");
	return 1;
}

int full_serve(struct df1 *h, link_handler_fn fn, void *ctx, int64_t deadline_ms)
{
	int served = 0;

	for (;;) {
		struct link_reply *t = link_slot_oldest(h, true, 0);
		int64_t now = df1_now_ms(), dl = deadline_ms;
		enum { W_END, W_ACK, W_DUE } which = W_END;
		struct df1_symbol s;
		int r = 0;

		if (t && !t->sent && t->due_ms <= now) {
			r = peer_tx_start(h, t);
			if (r < 0)
				return r;
		}
		if (now >= deadline_ms)
			return served;
		if (served > 0 && !t && h->rx_pos >= h->rx_len && !frame_decoder_busy(&h->dec))
			return served; /* answered, nothing in flight: back to the caller */
		if (t && t->sent && t->ack_deadline_ms < dl) {
			dl = t->ack_deadline_ms;
			which = W_ACK;
		} else if (t && !t->sent && t->due_ms < dl) {
			dl = t->due_ms;
			which = W_DUE;
		}
		r = link_read_symbol(h, dl, &s);
		if (r < 0)
			return r;
		if (r == 0) {
			if (which == W_END)
				return served;
			if (which == W_ACK)
				r = peer_tx_timeout(h, t);
			else
				t->due_ms = 0;
			if (r < 0)
				return r;
			continue;
		}
		switch (s.kind) {
		case DF1_SYM_ACK:
			df1_count(h, DF1_ID_CNT_ACKS_RCVD);
			if (t && t->sent)
				r = peer_tx_acked(h, t);
			break;
		case DF1_SYM_NAK:
			df1_count(h, DF1_ID_CNT_NAKS_RCVD);
			if (t && t->sent) {
				df1_log(h, DF1_ID_NTC_RCVD_NAK_SYMBOL);
				r = peer_tx_nak(h, t);
			} else {
				/* no frame of ours is waiting for a response */
				df1_log(h, DF1_ID_ERR_RCVD_NAK_SYMBOL);
			}
			break;
		case DF1_SYM_ENQ:
			if (!h->resp->silenced && !link_fault_silent_all(h->resp))
				r = link_send_sym(h, h->last_response);
			break;
		case DF1_SYM_FRAME:
			r = full_serve_frame(h, &s, fn, ctx);
			if (r > 0) {
				served++;
				r = 0;
			}
			break;
		case DF1_SYM_ERROR:
			r = full_reject(h, &s);
			break;
		default:
			link_noise(h);
			break;
		}
		if (r < 0)
			return r;
	}
}

