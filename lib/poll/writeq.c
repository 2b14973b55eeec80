/* SPDX-License-Identifier: MPL-2.0 */
/*
 * writeq.c - queued writes and raw PCCC commands: df1_tag_write() and
 * df1_poll_submit_pccc() from any thread, and the queue run between two
 * transactions of df1_poll().
 */
#include "poll/poll_int.h"

#include "link/link.h"
#include "proto/pccc.h"
#include "proto/value_type.h"

static int poll_write_one(struct df1 *h, struct poll_engine *e, struct wnode *w)
{
	struct ptag *t = e->tags[w->tag];
	int stn = t->cfg.station, rc;
	enum outcome o;
	int64_t now = df1_now_ms();

	poll_attempt(e, stn, now);
	e->stats.writes++;
	rc = client_write_at(h, stn, t->cfg.plc, &t->cfg.addr, w->v, w->n);
	o = poll_outcome(h, rc);
	now = df1_now_ms();
	if (o == OUT_OK || o == OUT_ADDR || o == OUT_PLC) {
		poll_station_answer(e, stn, now);
	} else if (o == OUT_LINK) {
		e->st[stn].last_error = rc;
		poll_station_fail(e, stn, rc, now);
	}
	if (rc >= 0) {
		if (t->readable) {
			t->next_due_ms = 0;             /* read the value back */
			if (t->block >= 0 && (size_t)t->block < e->nblocks)
				e->blocks[t->block].due_ms = 0;
		}
	} else {
		e->stats.write_failures++;
	}
	if (w->done)
		w->done(w->user, w->tag, w->wid, rc >= 0 ? 0 : rc);
	free(w);
	return o == OUT_ABORT ? rc : 1;
}

/* One attempt of a raw command: the reply's app bytes (DST SRC CMD|40 ...) in
 * r, their length, or DF1_E_*. The line's TNS goes out, not the requester's. */
static int poll_pccc_try(struct df1 *h, const struct wnode *w, uint8_t *r, size_t cap)
{
	uint8_t c[FRAME_MAX_DATA];
	int rc;

	c[0] = (uint8_t)w->station;
	memcpy(c + 2, w->pccc, w->n);  /* SRC and TNS are the link's */
	df1_clear_error(h);
	rc = link_transact(h, c, w->n + 2, r, cap);
	if (rc < 0)
		return rc;
	if (rc < PCCC_HDR_LEN)
		return df1_fail(h, DF1_E_BAD_REPLY, w->station, "PCCC %02X: %d-byte reply", w->pccc[0], rc);
	if (r[2] != (w->pccc[0] | PCCC_REPLY_BIT))
		return df1_fail(h, DF1_E_BAD_FUNCTION, w->station, "PCCC %02X: reply CMD %02X",
		                w->pccc[0], r[2]);
	return rc;
}

/* A raw command: tries while the link fails and the command surely did not
 * execute (or only reads); the reply with the requester's TNS to pdone. */
static int poll_pccc_one(struct df1 *h, struct poll_engine *e, struct wnode *w)
{
	uint8_t r[FRAME_MAX_DATA];
	int stn = w->station, tries = poll_tries(&e->st[stn]), rc;
	bool writes = df1_pccc_is_write(w->pccc, w->n);
	enum outcome o;

	for (;;) {
		poll_attempt(e, stn, df1_now_ms());
		rc = poll_pccc_try(h, w, r, sizeof r);
		o = poll_outcome(h, rc);
		if (o != OUT_LINK)
			break;
		e->st[stn].last_error = rc;
		poll_station_fail(e, stn, rc, df1_now_ms());
		if (--tries <= 0 || e->st[stn].state == DF1_STATION_OFFLINE ||
		    (writes && !df1_error_unexecuted(rc)))
			break;
		e->stats.retries++;
	}
	if (rc >= 0) {
		poll_station_answer(e, stn, df1_now_ms());
		r[4] = w->pccc[2];              /* the requester's TNS again */
		r[5] = w->pccc[3];
		w->pdone(w->user, 0, r + 2, (size_t)rc - 2);
	} else {
		w->pdone(w->user, rc, NULL, 0);
	}
	free(w);
	return o == OUT_ABORT ? rc : 1;
}

static struct wnode *poll_wq_pop(struct poll_engine *e)
{
	struct wnode *w;

	pthread_mutex_lock(&e->mu);
	w = e->wq_head;
	if (w) {
		e->wq_head = w->next;
		if (!e->wq_head)
			e->wq_tail = NULL;
		e->wq_len--;
		if (w->pdone)
			e->pccc_len--;
	}
	pthread_mutex_unlock(&e->mu);
	return w;
}

/* Append w to the FIFO and wake df1_poll(); e->mu held. */
static void poll_wq_push_locked(struct poll_engine *e, struct wnode *w)
{
	uint64_t one = 1;
	ssize_t wr;

	if (e->wq_tail)
		e->wq_tail->next = w;
	else
		e->wq_head = w;
	e->wq_tail = w;
	e->wq_len++;
	wr = write(e->wake_fd, &one, sizeof one);   /* under the lock: the fd outlives it */
	(void)wr;                                   /* EAGAIN: the counter is full, still readable */
}

/* The writes queued now, in order: the free slot between two transactions. */
int poll_run_writes(struct df1 *h, struct poll_engine *e)
{
	unsigned limit;
	int done = 0;

	pthread_mutex_lock(&e->mu);
	limit = e->wq_len;
	pthread_mutex_unlock(&e->mu);
	while (limit-- > 0) {
		struct wnode *w = poll_wq_pop(e);
		int r;

		if (!w)
			break;
		r = w->pdone ? poll_pccc_one(h, e, w) : poll_write_one(h, e, w);
		if (r < 0)
			return r;
		done += r;
	}
	return done;
}

int df1_tag_write(df1_t *h, int id, const struct df1_value *v, size_t n, df1_write_done_fn done,
                  void *user)
{
	struct poll_engine *e = h ? h->poll : NULL;
	struct ptag *t = NULL;
	struct wnode *w;
	enum df1_file_type vt;
	int wid;

	/* any thread: no df1_fail() here (the error detail belongs to the poll thread) */
	if (!e || !v || n == 0)
		return DF1_E_INVAL;
	pthread_mutex_lock(&e->mu);
	if (id >= 0 && (size_t)id < e->ntags)
		t = e->tags[id];
	pthread_mutex_unlock(&e->mu);
	if (!t || !t->writable || n > (size_t)t->cfg.count)
		return DF1_E_INVAL;
	vt = t->cfg.addr.sub != DF1_ADDR_NONE ? DF1_FT_N : t->cfg.addr.type;
	w = malloc(sizeof *w + n * sizeof *v);
	if (!w)
		return DF1_E_NOMEM;
	memset(w, 0, sizeof *w);
	memcpy(w->v, v, n * sizeof *v);
	for (size_t i = 0; i < n; i++) {
		uint8_t scratch[96];
		int r = 0;

		/* the Type's values (DINT, REAL on a word) back to the address's, range checked */
		if (w->v[i].kind == t->kind)
			r = value_type_narrow(&w->v[i], df1_addr_value_kind(&t->cfg.addr));
		if (r == 0 && t->cfg.addr.bit != DF1_ADDR_NONE)
			r = w->v[i].kind == DF1_VAL_BIT ? 0 : DF1_E_TYPE;
		else if (r == 0)
			r = value_encode_element(vt, &w->v[i], scratch, sizeof scratch, VALUE_FLOAT_LE);
		if (r < 0) {
			free(w);
			return r;
		}
	}
	w->tag = id;
	w->done = done;
	w->user = user;
	w->n = n;
	pthread_mutex_lock(&e->mu);
	w->wid = wid = e->next_wid;
	e->next_wid = e->next_wid == INT_MAX ? 1 : e->next_wid + 1;
	poll_wq_push_locked(e, w);
	pthread_mutex_unlock(&e->mu);
	return wid;                                 /* w may be gone already */
}

int df1_poll_submit_pccc(df1_t *h, int station, const uint8_t *pccc, size_t n,
                         df1_pccc_done_fn done, void *user)
{
	struct poll_engine *e;
	struct wnode *w;

	/* any thread: no df1_fail() here, as df1_tag_write() */
	if (!h || !pccc || !done || n < 4 || n > DF1_PCCC_MAX || station < 0 || station > 254 ||
	    (pccc[0] & PCCC_REPLY_BIT))
		return DF1_E_INVAL;
	e = h->poll;
	if (!e)
		return DF1_E_INVAL;     /* df1_poll_fd() or df1_poll() make the engine first */
	w = malloc(sizeof *w + n);
	if (!w)
		return DF1_E_NOMEM;
	memset(w, 0, sizeof *w);
	w->pdone = done;
	w->station = station;
	w->user = user;
	w->n = n;
	w->pccc = (uint8_t *)w->v;
	memcpy(w->pccc, pccc, n);
	pthread_mutex_lock(&e->mu);
	if (e->pccc_len >= DF1_PCCC_QUEUE_MAX) {
		pthread_mutex_unlock(&e->mu);
		free(w);
		return DF1_E_BUSY;
	}
	e->pccc_len++;
	poll_wq_push_locked(e, w);
	pthread_mutex_unlock(&e->mu);
	return 0;
}
