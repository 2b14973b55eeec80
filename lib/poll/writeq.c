/*
 * writeq.c - queued writes: df1_tag_write() from any thread, and the queue
 * run between two transactions of df1_poll().
 */
#include "poll_int.h"

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
	}
	pthread_mutex_unlock(&e->mu);
	return w;
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
		r = poll_write_one(h, e, w);
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
	uint64_t one = 1;
	ssize_t wr;
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
	for (size_t i = 0; i < n; i++) {
		uint8_t scratch[96];
		int r;

		if (t->cfg.addr.bit != DF1_ADDR_NONE) {
			if (v[i].kind != DF1_VAL_BIT)
				return DF1_E_TYPE;
			continue;
		}
		r = value_encode_element(vt, &v[i], scratch, sizeof scratch, VALUE_FLOAT_LE);
		if (r < 0)
			return r;
	}
	w = malloc(sizeof *w + n * sizeof *v);
	if (!w)
		return DF1_E_NOMEM;
	w->next = NULL;
	w->tag = id;
	w->done = done;
	w->user = user;
	w->n = n;
	memcpy(w->v, v, n * sizeof *v);
	pthread_mutex_lock(&e->mu);
	w->wid = wid = e->next_wid;
	e->next_wid = e->next_wid == INT_MAX ? 1 : e->next_wid + 1;
	if (e->wq_tail)
		e->wq_tail->next = w;
	else
		e->wq_head = w;
	e->wq_tail = w;
	e->wq_len++;
	wr = write(e->wake_fd, &one, sizeof one);   /* under the lock: the fd outlives it */
	pthread_mutex_unlock(&e->mu);
	(void)wr;                                   /* EAGAIN: the counter is full, still readable */
	return wid;                                 /* w may be gone already */
}
