/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_wqueue - the queue of writes from MQTT and its policy (see gw_wqueue.h).
 * A plain array in arrival order: at most --max-pending-writes entries
 * (100 000), so a linear search for a tag's waiting write and a memmove to
 * take one out cost less than the message that brought it.
 */
#include "df1gw/gw_wqueue.h"

#include <stdlib.h>
#include <string.h>

static void wq_depth(struct gw_wq *q)
{
	q->c.depth = (unsigned)q->n;
	if (q->c.depth > q->c.high_water)
		q->c.high_water = q->c.depth;
}

int gw_wq_init(struct gw_wq *q, enum gw_wopt opt, unsigned max, gw_wend_fn end, void *ctx)
{
	memset(q, 0, sizeof *q);
	q->opt = opt;
	q->max = max < 1 ? 1 : max > GW_WQ_MAX_LIMIT ? GW_WQ_MAX_LIMIT : max;
	q->end = end;
	q->ctx = ctx;
	q->cap = q->max < 64 ? q->max : 64;
	q->v = calloc(q->cap, sizeof *q->v);
	return q->v ? 0 : -1;
}

/* Take out entry i; it ends why (counted) and is freed. */
static void wq_end(struct gw_wq *q, size_t i, enum gw_wend why, const struct gw_witem *by)
{
	struct gw_witem *it = q->v[i];

	memmove(q->v + i, q->v + i + 1, (q->n - i - 1) * sizeof *q->v);
	q->n--;
	if (why == GW_WEND_SUPERSEDED)
		q->c.superseded++;
	else if (why == GW_WEND_EXPIRED)
		q->c.expired++;
	else
		q->c.dropped++;
	if (q->end)
		q->end(q->ctx, it, why, by);
	free(it);
	wq_depth(q);
}

void gw_wq_drop_all(struct gw_wq *q)
{
	while (q->n > 0)
		wq_end(q, 0, GW_WEND_DROPPED, NULL);
}

void gw_wq_free(struct gw_wq *q)
{
	if (q->v)
		gw_wq_drop_all(q);
	free(q->v);
	q->v = NULL;
	q->cap = 0;
}

struct gw_witem *gw_witem_new(int tag, bool keep, int64_t deadline_ms, const struct df1_value *v, size_t n,
                              void *user)
{
	struct gw_witem *it = malloc(sizeof *it + n * sizeof *v);

	if (!it)
		return NULL;
	it->tag = tag;
	it->keep = keep;
	it->deadline_ms = deadline_ms;
	it->user = user;
	it->n = n;
	if (n)
		memcpy(it->v, v, n * sizeof *v);
	return it;
}

/* The waiting write that it replaces under the policy, or -1. */
static long wq_replaces(const struct gw_wq *q, const struct gw_witem *it)
{
	if (q->opt == GW_WOPT_ALL || (q->opt == GW_WOPT_LATEST_NON_BOOL && it->keep))
		return -1;
	for (size_t i = 0; i < q->n; i++)
		if (q->v[i]->tag == it->tag)
			return (long)i;         /* at most one waits per tag under this policy */
	return -1;
}

int gw_wq_push(struct gw_wq *q, struct gw_witem *it)
{
	long r = wq_replaces(q, it);

	if (r >= 0) {
		struct gw_witem *old = q->v[r];

		/* the new write takes the old one's place: a slider moved all the
		 * time is written in its turn, not pushed back at every move */
		q->v[r] = it;
		q->c.superseded++;
		if (q->end)
			q->end(q->ctx, old, GW_WEND_SUPERSEDED, it);
		free(old);
		return 0;
	}
	if (q->n >= q->max) {
		q->c.refused_busy++;
		return -1;
	}
	if (q->n == q->cap) {
		size_t cap = q->cap * 2 > q->max ? q->max : q->cap * 2;
		struct gw_witem **v = realloc(q->v, cap * sizeof *v);

		if (!v) {
			q->c.refused_busy++;
			return -1;
		}
		q->v = v;
		q->cap = cap;
	}
	q->v[q->n++] = it;
	wq_depth(q);
	return 0;
}

void gw_wq_expire(struct gw_wq *q, int64_t now)
{
	for (size_t i = 0; i < q->n;) {
		if (q->v[i]->deadline_ms <= now) {
			wq_end(q, i, GW_WEND_EXPIRED, NULL);
			continue;
		}
		i++;
	}
}

struct gw_witem *gw_wq_pop(struct gw_wq *q, int64_t now)
{
	struct gw_witem *it;

	gw_wq_expire(q, now);
	if (q->n == 0)
		return NULL;
	it = q->v[0];
	memmove(q->v, q->v + 1, (q->n - 1) * sizeof *q->v);
	q->n--;
	wq_depth(q);
	return it;
}

int64_t gw_wq_next_deadline(const struct gw_wq *q)
{
	int64_t d = INT64_MAX;

	for (size_t i = 0; i < q->n; i++)
		if (q->v[i]->deadline_ms < d)
			d = q->v[i]->deadline_ms;
	return d;
}

int gw_outbox_init(struct gw_outbox *o, size_t cap)
{
	memset(o, 0, sizeof *o);
	o->cap = cap ? cap : 1;
	o->v = calloc(o->cap, sizeof *o->v);
	return o->v ? 0 : -1;
}

void gw_outbox_free(struct gw_outbox *o)
{
	for (size_t i = 0; o->v && i < o->n; i++)
		gw_msg_free(&o->v[i]);
	free(o->v);
	memset(o, 0, sizeof *o);
}

bool gw_outbox_add(struct gw_outbox *o, const struct gw_msg *m)
{
	struct gw_msg *k;

	if (!o->v || o->n >= o->cap) {
		o->lost++;
		return false;
	}
	k = &o->v[o->n];
	gw_msg_init(k);
	memcpy(k->topic, m->topic, sizeof k->topic);
	k->retain = m->retain;
	gw_buf_add(&k->body, m->body.p ? m->body.p : "", m->body.len);
	if (k->body.oom) {
		gw_msg_free(k);
		o->lost++;
		return false;
	}
	o->n++;
	return true;
}

static const char *const wopt_names[] = { "all", "latest", "latest-non-bool" };

const char *gw_wopt_name(enum gw_wopt opt)
{
	return (unsigned)opt < 3 ? wopt_names[opt] : "?";
}

int gw_wopt_parse(const char *s, enum gw_wopt *out)
{
	for (int i = 0; i < 3; i++) {
		if (strcmp(s, wopt_names[i]) == 0) {
			*out = (enum gw_wopt)i;
			return 0;
		}
	}
	return -1;
}
