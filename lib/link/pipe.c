/* SPDX-License-Identifier: MPL-2.0 */
/*
 * pipe.c - the full-duplex master's pipeline (DF1_OPT_MAX_OUTSTANDING; doc/PROTOCOL.md
 * 1.6 rule 6): commands are submitted into slots (h->pipe) and sent one after
 * the other, each as soon as the previous frame of ours has been ACKed and
 * fewer than the option's number are outstanding (ACKed, reply not in). Each
 * reply frame is matched to its slot by SRC == the command's DST and the full
 * TNS, as full_transact matches its one reply. Per slot, as there: the ACK
 * timer and its ENQs, the NAK retransmissions (only the frame waiting for its
 * ACK gets them: the link sends the next frame only after an ACK, so there is
 * never more than one), and the reply timer, max(timeout_ms, cmd_timeout_ms)
 * from the ACK. A failure ends only its own slot; its error detail is kept in
 * the slot and becomes the handle's when the slot is taken (link_pipe_wait).
 *
 * Decisions:
 *  - A frame is never sent again once ACKed (or once its reply came): a reply
 *    lost after the ACK is the slot's DF1_E_TIMEOUT, as in full_transact, so a
 *    write is executed at most once and reported unconfirmed.
 *  - Slots are fixed (LINK_PIPE_MAX), no allocation. A slot whose result is
 *    not wanted any more (a scan ended, a block was skipped) is abandoned: it
 *    stays until its reply (or failure) is in, so that reply is matched and
 *    dropped quietly instead of counting as stale.
 *  - With no slot in use, link_transact keeps using full_transact: N = 1 and
 *    the synchronous calls behave exactly as before.
 *  - The ACK of a reply is held (link_send_sym_held) so that it goes out in
 *    one write with our next command; when no command may go yet, it goes
 *    before the link waits for input or before link_pipe_wait returns.
 *  - Timers that wait for an answer start when our bytes have left the line
 *    (link_after_tx_ms), as full_transact's.
 */
#include "link/link.h"

#include <string.h>

#include "link/link_int.h"

enum { PIPE_FREE, PIPE_QUEUED, PIPE_TX, PIPE_WAIT, PIPE_DONE };

/* ------------------------------------------------------------------------
 * Slots
 * ------------------------------------------------------------------------ */

int link_pipe_depth(const struct df1 *h)
{
	/* a scheme's own link (eip://) has no DF1 line: one request at a time */
	if (h->cfg.duplex != DF1_FULL_DUPLEX || h->cfg.max_outstanding < 1 || h->own_link)
		return 1;
	return h->cfg.max_outstanding < LINK_PIPE_MAX - 1 ? h->cfg.max_outstanding : LINK_PIPE_MAX - 1;
}

static int pipe_count(const struct df1 *h, bool line_only)
{
	int n = 0;

	for (int i = 0; i < LINK_PIPE_MAX; i++) {
		uint8_t st = h->pipe.slot[i].state;

		if (line_only ? (st == PIPE_TX || st == PIPE_WAIT) : (st != PIPE_FREE && st != PIPE_DONE))
			n++;
	}
	return n;
}

int link_pipe_pending(const struct df1 *h)
{
	return pipe_count(h, false);
}

int link_pipe_used(const struct df1 *h)
{
	return h->pipe.used;
}

static void pipe_free_slot(struct df1 *h, struct link_pipe_slot *p)
{
	if (p->state == PIPE_FREE)
		return;
	if (h->pipe.tx && &h->pipe.slot[h->pipe.tx - 1] == p)
		h->pipe.tx = 0;
	p->state = PIPE_FREE;
	p->abandoned = false;
	h->pipe.used--;
}

/* The slot ends: rc is its reply length or DF1_E_* (h->err has the detail). */
static void pipe_end(struct df1 *h, struct link_pipe_slot *p, int rc)
{
	if (h->pipe.tx && &h->pipe.slot[h->pipe.tx - 1] == p)
		h->pipe.tx = 0;
	if (p->abandoned) {
		pipe_free_slot(h, p);
		return;
	}
	p->state = PIPE_DONE;
	p->rc = rc;
	if (rc < 0)
		p->err = h->err;
}

int link_pipe_submit(struct df1 *h, const uint8_t *cmd, size_t n)
{
	struct link_pipe_slot *p = NULL;

	for (int i = 0; i < LINK_PIPE_MAX && !p; i++)
		if (h->pipe.slot[i].state == PIPE_FREE)
			p = &h->pipe.slot[i];
	if (!p)
		return df1_fail(h, DF1_E_NOSPACE, cmd[0], "no pipeline slot free");
	memset(p, 0, offsetof(struct link_pipe_slot, err));
	p->state = PIPE_QUEUED;
	p->seq = ++h->pipe.seq;
	p->cmd_len = n;
	memcpy(p->cmd, cmd, n);
	h->pipe.used++;
	return (int)(p - h->pipe.slot);
}

void link_pipe_abandon(struct df1 *h, int slot)
{
	struct link_pipe_slot *p;

	if (slot < 0 || slot >= LINK_PIPE_MAX)
		return;
	p = &h->pipe.slot[slot];
	if (p->state == PIPE_QUEUED || p->state == PIPE_DONE)
		pipe_free_slot(h, p);
	else if (p->state != PIPE_FREE)
		p->abandoned = true;
}

/* ------------------------------------------------------------------------
 * The line
 * ------------------------------------------------------------------------ */

static int pipe_send(struct df1 *h, struct link_pipe_slot *p, bool first)
{
	uint8_t wire[FRAME_MAX_WIRE];
	size_t wn = frame_encode_full(link_tx_check(h), p->cmd, p->cmd_len, wire, sizeof wire);
	int r;

	if (wn == 0) {
		pipe_end(h, p, df1_fail(h, DF1_E_INVAL, p->cmd[0], "command of %zu bytes does not fit a frame",
		                        p->cmd_len));
		return 0;
	}
	r = link_send_raw(h, wire, wn);
	if (r < 0)
		return r;
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_SENT);
	if (first)
		df1_count(h, DF1_ID_CNT_CMD_MSGS_SENT);
	p->state = PIPE_TX;
	p->deadline_ms = link_after_tx_ms(h, link_timeout_ms(h));
	h->pipe.tx = (int)(p - h->pipe.slot) + 1;
	return 0;
}

/* The oldest queued command goes out when the line is free for it. */
static int pipe_start(struct df1 *h)
{
	struct link_pipe_slot *next = NULL;

	while (!h->pipe.tx && !peer_on_line(h) && pipe_count(h, true) < link_pipe_depth(h)) {
		int r;

		next = NULL;
		for (int i = 0; i < LINK_PIPE_MAX; i++) {
			struct link_pipe_slot *p = &h->pipe.slot[i];

			if (p->state == PIPE_QUEUED && (!next || (int32_t)(p->seq - next->seq) < 0))
				next = p;
		}
		if (!next)
			return 0;
		r = pipe_send(h, next, true);
		if (r < 0)
			return r;
	}
	return 0;
}

static int64_t pipe_reply_wait(const struct df1 *h)
{
	int64_t w = link_timeout_ms(h);

	return h->cfg.cmd_timeout_ms > w ? h->cfg.cmd_timeout_ms : w;
}

static void pipe_acked(struct df1 *h, struct link_pipe_slot *p)
{
	p->state = PIPE_WAIT;
	p->deadline_ms = df1_now_ms() + pipe_reply_wait(h);
	h->pipe.tx = 0;
}

/* The port's read ran to deadline dl: the timers of the slots on the line that
 * end there ran out (doc/PROTOCOL.md 1.6 rule 4). The port said so; the clock is not asked
 * again (core.c). */
static int pipe_timeouts(struct df1 *h, int64_t dl)
{
	for (int i = 0; i < LINK_PIPE_MAX; i++) {
		struct link_pipe_slot *p = &h->pipe.slot[i];
		int r;

		if ((p->state != PIPE_TX && p->state != PIPE_WAIT) || p->deadline_ms > dl)
			continue;
		if (p->state == PIPE_WAIT) {
			df1_count(h, DF1_ID_CNT_COMMAND_TIMEOUTS);
			df1_log(h, DF1_ID_ERR_COMMAND_TIMEOUT);
			pipe_end(h, p, df1_fail(h, DF1_E_TIMEOUT, p->cmd[0], "no reply from station %d",
			                        p->cmd[0]));
			continue;
		}
		if (p->enqs >= h->cfg.enq_retries) {
			df1_count(h, DF1_ID_CNT_ENQ_LIMIT_EXCEEDED);
			df1_log(h, DF1_ID_NTC_ENQ_LIMIT_EXCEEDED, h->cfg.enq_retries);
			pipe_end(h, p, df1_fail(h, DF1_E_ENQ_LIMIT, p->cmd[0],
			                        "no ACK from station %d after %d ENQ", p->cmd[0], p->enqs));
			continue;
		}
		p->enqs++;
		df1_count(h, DF1_ID_CNT_ENQ_RETRIES);
		df1_log(h, DF1_ID_NTC_ENQ_RETRY, p->enqs, DF1_ID_ERR_COMMAND_TIMEOUT);
		r = link_send_sym(h, DF1_ENQ);
		if (r < 0)
			return r;
		p->deadline_ms = link_after_tx_ms(h, link_timeout_ms(h));
	}
	return 0;
}

static int pipe_nak(struct df1 *h)
{
	struct link_pipe_slot *p;

	df1_count(h, DF1_ID_CNT_NAKS_RCVD);
	if (!h->pipe.tx) {
		df1_log(h, DF1_ID_ERR_RCVD_NAK_SYMBOL); /* no frame of ours waits for a response */
		return 0;
	}
	p = &h->pipe.slot[h->pipe.tx - 1];
	df1_log(h, DF1_ID_NTC_RCVD_NAK_SYMBOL);
	if (p->naks >= h->cfg.nak_retries) {
		df1_count(h, DF1_ID_CNT_NAK_LIMIT_EXCEEDED);
		df1_log(h, DF1_ID_NTC_NAK_LIMIT_EXCEEDED, h->cfg.nak_retries);
		pipe_end(h, p, df1_fail(h, DF1_E_NAK_LIMIT, p->cmd[0], "station %d answered NAK %d times",
		                        p->cmd[0], p->naks + 1));
		return 0;
	}
	p->naks++;
	df1_count(h, DF1_ID_CNT_NAK_RETRIES);
	df1_log(h, DF1_ID_NTC_NAK_RETRY, p->naks, DF1_ID_NTC_RCVD_NAK_SYMBOL);
	return pipe_send(h, p, false);
}

/* The slot on the line whose command this reply answers (SRC, full TNS), or NULL. */
static struct link_pipe_slot *pipe_match(struct df1 *h, const uint8_t *d)
{
	for (int i = 0; i < LINK_PIPE_MAX; i++) {
		struct link_pipe_slot *p = &h->pipe.slot[i];

		if ((p->state == PIPE_TX || p->state == PIPE_WAIT) && d[1] == p->cmd[0] &&
		    d[4] == p->cmd[4] && d[5] == p->cmd[5])
			return p;
	}
	return NULL;
}

/* A frame with a good check, as full_transact takes it. */
static int pipe_frame(struct df1 *h, const struct df1_symbol *s)
{
	struct link_pipe_slot *p;
	size_t len = 0;
	int r;

	if (link_is_dup(h, s->data[1], s->data, s->len))
		return link_ack_dup(h, s);
	if (!(s->data[2] & 0x40))
		return peer_command(h, s, true); /* the peer's own command (peer.c) */
	/* held: it goes out with our next command, in one write (or before we wait) */
	r = link_send_sym_held(h, DF1_ACK);
	if (r < 0)
		return r;
	link_remember(h, s->data[1], s->data, s->len);
	p = (s->data[2] & 0x40) ? pipe_match(h, s->data) : NULL;
	if (!p) {
		(void)link_take_reply(h, NULL, s, NULL, 0, &len); /* stale or a command: counted */
		return 0;
	}
	if (p->state == PIPE_TX)
		h->pipe.tx = 0; /* the reply proves delivery (its ACK was lost) */
	r = link_take_reply(h, p->cmd, s, p->reply, sizeof p->reply, &len);
	if (r == 1)
		p->reply_len = len;
	pipe_end(h, p, r == 1 ? (int)len : r);
	return 0;
}

/* One step: start what may go, wait for the next symbol or timer, handle it. */
static int pipe_step(struct df1 *h)
{
	int64_t dl = INT64_MAX, pdl;
	struct df1_symbol s;
	int r = h->pipe.tx ? 0 : peer_start(h); /* a reply to the peer goes first */

	if (r >= 0)
		r = pipe_start(h);
	if (r < 0)
		return r;
	for (int i = 0; i < LINK_PIPE_MAX; i++) {
		const struct link_pipe_slot *p = &h->pipe.slot[i];

		if ((p->state == PIPE_TX || p->state == PIPE_WAIT) && p->deadline_ms < dl)
			dl = p->deadline_ms;
	}
	pdl = peer_deadline(h); /* a reply to the peer on the line (or due) holds our next command */
	if (pdl < dl)
		dl = pdl;
	if (dl == INT64_MAX)
		return 0; /* nothing on the line */
	r = link_read_symbol(h, dl, &s);
	if (r < 0)
		return r;
	if (r == 0) {
		r = pdl <= dl ? peer_timeout(h, dl) : 0;
		return r < 0 ? r : pipe_timeouts(h, dl);
	}
	switch (s.kind) {
	case DF1_SYM_ACK:
		if (peer_on_line(h)) {
			peer_acked(h); /* the ACK of our reply to the peer */
			return 0;
		}
		df1_count(h, DF1_ID_CNT_ACKS_RCVD);
		if (h->pipe.tx)
			pipe_acked(h, &h->pipe.slot[h->pipe.tx - 1]);
		return 0;
	case DF1_SYM_NAK:
		return peer_on_line(h) ? peer_nak(h) : pipe_nak(h);
	case DF1_SYM_ENQ:
		return link_send_sym(h, h->last_response); /* the peer asks for our last response */
	case DF1_SYM_FRAME:
		if (s.master_msg) {
			link_noise(h);
			return 0;
		}
		if (!s.check_ok) {
			link_bad_check(h, &s);
			return link_send_sym(h, DF1_NAK);
		}
		return pipe_frame(h, &s);
	case DF1_SYM_ERROR:
		if (!link_log_error(h, &s)) {
			link_noise(h);
			return 0;
		}
		return link_send_sym(h, DF1_NAK);
	default:
		link_noise(h);
		return 0;
	}
}

int link_pipe_wait(struct df1 *h, int slot, uint8_t *reply, size_t cap)
{
	struct df1_error_detail saved = h->err;
	struct link_pipe_slot *p;
	int r = 0;

	if (slot < 0 || slot >= LINK_PIPE_MAX || h->pipe.slot[slot].state == PIPE_FREE)
		return df1_fail(h, DF1_E_INVAL, -1, "no pipeline slot %d", slot);
	p = &h->pipe.slot[slot];
	while (p->state != PIPE_DONE) {
		r = pipe_step(h);
		if (r < 0) {
			/* the port failed or the wait was cancelled: this one is given up */
			link_pipe_abandon(h, slot);
			return r;
		}
	}
	/* the ACK of the reply just taken goes with the next command if one may
	 * go now; if not, at once: the caller may not come back for a while */
	r = pipe_start(h);
	if (r >= 0 && h->tx_hold_len)
		r = link_tx_flush(h);
	if (r < 0) {
		link_pipe_abandon(h, slot);
		return r;
	}
	h->err = saved; /* other slots' failures are theirs */
	r = p->rc;
	if (r < 0) {
		h->err = p->err;
	} else if ((size_t)r > cap) {
		r = df1_fail(h, DF1_E_NOSPACE, p->cmd[0], "reply of %d bytes, buffer holds %zu", r, cap);
	} else {
		memcpy(reply, p->reply, (size_t)r);
	}
	pipe_free_slot(h, p);
	return r;
}

void link_pipe_reset(struct df1 *h)
{
	for (int i = 0; i < LINK_PIPE_MAX; i++)
		h->pipe.slot[i].state = PIPE_FREE;
	h->pipe.used = h->pipe.tx = 0;
}

int link_pipe_flush(struct df1 *h)
{
	/* the commands already on the line: wait for their outcome, and drop it */
	for (int i = 0; i < LINK_PIPE_MAX; i++)
		link_pipe_abandon(h, i);
	while (h->pipe.used > 0) {
		int r = pipe_step(h);

		if (r < 0) {
			link_pipe_reset(h); /* the line failed: nothing of it is coming */
			return r;
		}
	}
	return 0;
}

/* A command through the pipeline while other slots are in use: submit and wait. */
int pipe_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap)
{
	int slot = link_pipe_submit(h, cmd, n);

	if (slot < 0)
		return slot;
	return link_pipe_wait(h, slot, reply, cap);
}
