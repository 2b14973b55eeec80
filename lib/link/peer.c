/* SPDX-License-Identifier: MPL-2.0 */
/*
 * peer.c - a full-duplex master that also answers its peer (df1_set_responder(3);
 * doc/PROTOCOL.md 1.10, doc/ARCHITECTURE.md 4): a command frame that arrives
 * while our own commands are on the line is ACKed, run through the handler
 * that df1_set_responder attached (lib/server), and its reply queued; the
 * reply goes out when no frame of ours waits for its ACK, and gets its own
 * ACK timer, ENQs and NAK retransmissions: the transmitter of full.c's
 * responder, which lives here. The
 * master's loops (full_transact, pipe.c) ask here who a DLE ACK or DLE NAK
 * belongs to: the reply on the line, else their command.
 *
 * Decisions (relied on by tests/unit/link/test_peer.c):
 *  - One frame of ours waits for an ACK at a time, in both roles (doc/PROTOCOL.md 1.6:
 *    the transmitter sends the next frame after the ACK of the last); our
 *    command is sent first when both are ready, the replies in command order.
 *  - Without a responder the command is answered STS 10h ("illegal command
 *    or format"), the status every node in the project gives a command it
 *    does not implement (lib/server/server_dispatch.c), and counted as a
 *    command received (2528) and an invalid message (2550); the reply is an
 *    error message sent (2535).
 *  - Replies are queued (LINK_REPLY_SLOTS): a command that finds the queue
 *    full is NAKed and not run (doc/PROTOCOL.md 1.7: message sink full), and
 *    the peer sends it again.
 *  - Duplicates are found by the master's per-station rule (core.c): the peer
 *    sends its next frame only after our ACK, so the last message accepted
 *    from a station is the one it may repeat.
 *  - The server's faults (df1_server_set_fault) act on these commands and
 *    replies as in df1_serve: a simulator keeps its faults while its own
 *    MSG is outstanding.
 */
#include "link/link.h"

#include <stdlib.h>

#include "link/link_int.h"

/* STS of a command a node does not implement (doc/PROTOCOL.md 1.10). */
#define PEER_STS_UNSUPPORTED 0x10

/* ------------------------------------------------------------------------
 * The full-duplex reply transmitter: df1_serve's (full.c) and the master's
 * ------------------------------------------------------------------------ */

int peer_tx_start(struct df1 *h, struct link_reply *t)
{
	bool first = !t->stale_now && t->naks == 0 && t->enqs == 0;
	int r;

	if (t->stale_first) {
		t->stale_first = false;
		t->stale_now = true;
		first = true;
	}
	r = link_slot_send(h, t, t->stale_now, first);
	if (r < 0)
		return r;
	t->sent = true;
	t->ack_deadline_ms = link_after_tx_ms(h, link_timeout_ms(h));
	return 0;
}

/* The master's ACK of our reply. */
int peer_tx_acked(struct df1 *h, struct link_reply *t)
{
	if (t->stale_now) {
		/* the stale copy is through; the real reply goes next */
		t->stale_now = false;
		t->sent = false;
		t->naks = t->enqs = 0;
		return peer_tx_start(h, t);
	}
	t->used = false;
	return 0;
}

int peer_tx_nak(struct df1 *h, struct link_reply *t)
{
	int r;

	if (t->naks >= h->cfg.nak_retries) {
		df1_count(h, DF1_ID_CNT_NAK_LIMIT_EXCEEDED);
		df1_log(h, DF1_ID_NTC_NAK_LIMIT_EXCEEDED, h->cfg.nak_retries);
		t->used = false;
		return 0;
	}
	t->naks++;
	df1_count(h, DF1_ID_CNT_NAK_RETRIES);
	df1_log(h, DF1_ID_NTC_NAK_RETRY, t->naks, DF1_ID_NTC_RCVD_NAK_SYMBOL);
	r = link_slot_send(h, t, t->stale_now, false);
	if (r < 0)
		return r;
	t->ack_deadline_ms = link_after_tx_ms(h, link_timeout_ms(h));
	return 0;
}

int peer_tx_timeout(struct df1 *h, struct link_reply *t)
{
	int r;

	if (t->enqs >= h->cfg.enq_retries) {
		df1_count(h, DF1_ID_CNT_ENQ_LIMIT_EXCEEDED);
		df1_log(h, DF1_ID_NTC_ENQ_LIMIT_EXCEEDED, h->cfg.enq_retries);
		t->used = false;
		return 0;
	}
	t->enqs++;
	df1_count(h, DF1_ID_CNT_ENQ_RETRIES);
	df1_log(h, DF1_ID_NTC_ENQ_RETRY, t->enqs, DF1_ID_ERR_COMMAND_TIMEOUT);
	r = link_send_sym(h, DF1_ENQ);
	if (r < 0)
		return r;
	t->ack_deadline_ms = link_after_tx_ms(h, link_timeout_ms(h));
	return 0;
}

/* ------------------------------------------------------------------------
 * The master's own responder
 * ------------------------------------------------------------------------ */

/* The slots the replies wait in: the server's, or the link's own. */
static struct link_responder *peer_slots(struct df1 *h, bool alloc)
{
	if (h->peer_resp)
		return h->peer_resp;
	if (!h->peer_own && alloc)
		h->peer_own = calloc(1, sizeof *h->peer_own); /* once per handle */
	return h->peer_own;
}

struct link_responder *peer_responder(struct df1 *h)
{
	return peer_slots(h, true);
}

/* The oldest reply (on the line or next to go), with h->resp lent to core.c. */
static struct link_reply *peer_oldest(struct df1 *h, struct link_responder **saved)
{
	struct link_responder *r = peer_slots(h, false);

	*saved = h->resp;
	if (!r)
		return NULL;
	h->resp = r;
	return link_slot_oldest(h, true, 0);
}

bool peer_on_line(struct df1 *h)
{
	struct link_responder *saved;
	struct link_reply *t = peer_oldest(h, &saved);
	bool on = t && t->sent;

	h->resp = saved;
	return on;
}

int64_t peer_deadline(struct df1 *h)
{
	struct link_responder *saved;
	struct link_reply *t = peer_oldest(h, &saved);
	int64_t dl = INT64_MAX;

	if (t && t->sent)
		dl = t->ack_deadline_ms;
	else if (t && t->due_ms > 0)
		dl = t->due_ms;
	h->resp = saved;
	return dl;
}

int peer_start(struct df1 *h)
{
	struct link_responder *saved;
	struct link_reply *t = peer_oldest(h, &saved);
	int r = 0;

	if (t && !t->sent && t->due_ms <= df1_now_ms())
		r = peer_tx_start(h, t);
	h->resp = saved;
	return r;
}

void peer_acked(struct df1 *h)
{
	struct link_responder *saved;
	struct link_reply *t = peer_oldest(h, &saved);

	df1_count(h, DF1_ID_CNT_ACKS_RCVD);
	if (t && t->sent)
		(void)peer_tx_acked(h, t);
	h->resp = saved;
}

int peer_nak(struct df1 *h)
{
	struct link_responder *saved;
	struct link_reply *t = peer_oldest(h, &saved);
	int r = 0;

	df1_count(h, DF1_ID_CNT_NAKS_RCVD);
	df1_log(h, DF1_ID_NTC_RCVD_NAK_SYMBOL);
	if (t && t->sent)
		r = peer_tx_nak(h, t);
	h->resp = saved;
	return r;
}

int peer_timeout(struct df1 *h, int64_t dl)
{
	struct link_responder *saved;
	struct link_reply *t = peer_oldest(h, &saved);
	int r = 0;

	if (t && t->sent && t->ack_deadline_ms <= dl)
		r = peer_tx_timeout(h, t);
	else if (t && !t->sent && t->due_ms <= dl)
		t->due_ms = 0;
	h->resp = saved;
	return r;
}

/* The reply to cmd: the responder's, or STS 10h without one. Its length, 0, or DF1_E_*. */
int peer_answer(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *out, size_t cap)
{
	if (h->peer_fn)
		return h->peer_fn(h, h->peer_ctx, cmd, n, out, cap);
	df1_count(h, DF1_ID_CNT_INVALID_MSGS_RCVD);
	out[0] = cmd[1];
	out[1] = cmd[0];
	out[2] = (uint8_t)(cmd[2] | 0x40);
	out[3] = PEER_STS_UNSUPPORTED;
	out[4] = cmd[4];
	out[5] = cmd[5];
	return 6;
}

/* Take the command (a good check, not a duplicate) or NAK it when the queue is full. */
static int peer_take(struct df1 *h, const struct df1_symbol *s, bool held)
{
	uint8_t out[FRAME_MAX_DATA];
	const uint8_t *d = s->data;
	int r, rlen;

	if (!link_slot_free_exists(h) || link_fault(h->resp, DF1_FAULT_NAK_COMMAND))
		return link_send_sym(h, DF1_NAK);
	if (link_fault(h->resp, DF1_FAULT_DROP_ACK)) {
		h->last_response = DF1_ACK; /* as if our ACK was lost on the line */
	} else {
		r = held ? link_send_sym_held(h, DF1_ACK) : link_send_sym(h, DF1_ACK);
		if (r < 0)
			return r;
	}
	link_remember(h, d[1], d, s->len);
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	df1_count(h, DF1_ID_CNT_CMD_MSGS_RCVD);
	rlen = peer_answer(h, d, s->len, out, sizeof out);
	if (rlen < 0)
		return rlen;
	if (rlen > 0 && (size_t)rlen <= sizeof out && !link_slot_new(h, d[1], out, (size_t)rlen))
		return df1_fail(h, DF1_E_NOSPACE, d[1], "no reply slot free");
	return 0;
}

int peer_command(struct df1 *h, const struct df1_symbol *s, bool held)
{
	struct link_responder *saved = h->resp, *r = peer_slots(h, true);
	int rc;

	if (!r)
		return df1_fail(h, DF1_E_NOMEM, s->data[1], "no memory for the reply to a command");
	h->resp = r;
	rc = peer_take(h, s, held);
	h->resp = saved;
	return rc;
}
