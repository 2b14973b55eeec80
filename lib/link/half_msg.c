/* SPDX-License-Identifier: MPL-2.0 */
/*
 * half_msg.c - a half-duplex slave's own MSG (doc/PROTOCOL.md 2.3, 2.5;
 * libdf1(7) UNSOLICITED MESSAGES): df1_read/df1_write on a slave handle.
 *
 * Decisions (relied on by tests/unit/link/test_route.c):
 *  - The command waits in the responder's queue as a reply would, and goes
 *    out as the answer to the next poll of our station (cfg.station), with
 *    the queue's retries (sent again on the next poll until the master ACKs
 *    it, at most nak_retries times, then DF1_E_NAK_LIMIT).
 *  - Meanwhile the line is served as df1_serve serves it: polls answered,
 *    the master's commands run by df1_set_responder's ops (STS 10h without).
 *  - Its reply comes as a master message addressed to us with the reply bit,
 *    from the station we sent it to (the master forwards the target's reply,
 *    or answers itself with an error STS), with our TNS: ACKed and returned.
 *  - A broadcast (DST 255) has no reply: done when the master ACKs it.
 *  - No reply within Cmd_Timeout (df1_set_cmd_timeout_ms, the MSG block's
 *    timeout) from the call: DF1_E_TIMEOUT, and a command not yet sent is
 *    taken back.
 */
#include "link/link.h"

#include <string.h>

#include "link/link_int.h"

/* The master's commands while our MSG waits: df1_set_responder's ops. */
static int half_msg_handler(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *reply,
                            size_t cap)
{
	(void)ctx;
	return peer_answer(h, cmd, n, reply, cap);
}

/* Where the MSG stands after a while of serving: 1 done (m->rc, m->len), 0 waiting. */
static int half_msg_state(struct df1 *h, struct link_own_msg *m, int64_t deadline)
{
	const uint8_t *c = m->cmd;

	if (m->done)
		return 1;
	if (c[0] == 255 && m->acked) {
		/* a broadcast: nobody replies; done as an empty STS 0 reply */
		uint8_t *o = m->reply;

		if (m->cap < 6) {
			m->rc = df1_fail(h, DF1_E_NOSPACE, 255, "no room for the reply");
			return 1;
		}
		o[0] = c[1], o[1] = c[0], o[2] = (uint8_t)(c[2] | 0x40), o[3] = 0, o[4] = c[4], o[5] = c[5];
		m->len = 6;
		return 1;
	}
	if (!m->acked && (!m->slot->used || m->slot->seq != m->seq)) {
		m->rc = df1_fail(h, DF1_E_NAK_LIMIT, c[0], "the master did not ACK our message (%d tries)",
		                 h->cfg.nak_retries + 1);
		return 1;
	}
	if (df1_now_ms() >= deadline) {
		df1_count(h, DF1_ID_CNT_COMMAND_TIMEOUTS);
		df1_log(h, DF1_ID_ERR_COMMAND_TIMEOUT);
		m->rc = df1_fail(h, DF1_E_TIMEOUT, c[0], "no reply from station %d within %d ms%s", c[0],
		                 h->cfg.cmd_timeout_ms, m->acked ? "" : " (not polled)");
		return 1;
	}
	return 0;
}

int half_slave_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap)
{
	struct link_own_msg m = { .cmd = cmd, .reply = reply, .cap = cap };
	struct link_responder *saved = h->resp, *resp = peer_responder(h);
	int64_t deadline = df1_now_ms() + (h->cfg.cmd_timeout_ms > 0 ? h->cfg.cmd_timeout_ms : 1000);
	int r = 0;

	if (!resp)
		return df1_fail(h, DF1_E_NOMEM, cmd[0], "no memory for the message queue");
	if (h->own_msg)
		return df1_fail(h, DF1_E_INVAL, cmd[0], "a half-duplex slave sends one message at a time");
	h->resp = resp;
	m.slot = link_slot_new(h, cmd[1], cmd, n);
	if (!m.slot) {
		h->resp = saved;
		return df1_fail(h, DF1_E_NOSPACE, cmd[0], "no room in the queue for our message");
	}
	m.slot->stale_first = false;
	m.slot->due_ms = 0; /* a MSG goes out on the next poll, not at the end of a scan */
	m.seq = m.slot->seq;
	h->own_msg = &m;
	while (!half_msg_state(h, &m, deadline)) {
		r = half_serve(h, half_msg_handler, NULL, deadline);
		if (r < 0)
			break;
	}
	h->own_msg = NULL;
	if (!m.acked && m.slot->used && m.slot->seq == m.seq) {
		m.slot->used = false; /* not sent: taken back */
		if (h->resp->awaiting == (int)(m.slot - h->resp->replies) + 1)
			h->resp->awaiting = 0;
	}
	h->resp = saved;
	if (h->tx_hold_len && r >= 0)
		r = link_tx_flush(h);
	if (r < 0)
		return r;
	return m.rc < 0 ? m.rc : (int)m.len;
}
