/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_live.c - the live publications kept until their PUBACKs (gw_live.h).
 */
#include "df1gw/gw_live.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int gw_live_init(struct gw_live *l, size_t cap)
{
	memset(l, 0, sizeof *l);
	l->v = calloc(cap ? cap : GW_LIVE_DEFAULT, sizeof *l->v);
	if (!l->v)
		return -1;
	l->cap = cap ? cap : GW_LIVE_DEFAULT;
	return 0;
}

void gw_live_free(struct gw_live *l)
{
	for (size_t i = 0; l->v && i < l->cap; i++)
		free(l->v[i].blob);
	free(l->v);
	memset(l, 0, sizeof *l);
}

static struct gw_live_ent *at(struct gw_live *l, size_t i)
{
	return &l->v[(l->head + i) % l->cap];
}

/* The done entries at the head go. */
static void trim(struct gw_live *l)
{
	while (l->n && !at(l, 0)->used) {
		l->head = (l->head + 1) % l->cap;
		l->n--;
	}
}

int gw_live_open(struct gw_live *l, const struct gw_buffer_rec *r)
{
	struct gw_live_ent *e;

	l->open = NULL;
	if (!l->v)
		return -1;
	trim(l);
	if (l->n == l->cap) {           /* full: the oldest in flight is let go */
		at(l, 0)->used = false;
		l->let_go++;
		trim(l);
	}
	e = at(l, l->n);
	if (r->len > e->cap) {
		uint8_t *p = realloc(e->blob, r->len);

		if (!p)
			return -1;
		e->blob = p;
		e->cap = r->len;
	}
	if (r->len)
		memcpy(e->blob, r->data, r->len);
	snprintf(e->key, sizeof e->key, "%s", r->key ? r->key : "");
	e->r = *r;
	e->r.key = e->key;
	e->r.data = e->blob;
	e->nmids = 0;
	e->used = true;
	l->n++;
	l->open = e;
	return 0;
}

void gw_live_mid(struct gw_live *l, int mid)
{
	if (l->open && l->open->nmids < GW_LIVE_MIDS)
		l->open->mids[l->open->nmids++] = mid;
}

void gw_live_close(struct gw_live *l)
{
	if (l->open && l->open->nmids == 0)
		l->open->used = false;
	l->open = NULL;
	trim(l);
}

bool gw_live_acked(struct gw_live *l, int mid)
{
	for (size_t i = 0; i < l->n; i++) {
		struct gw_live_ent *e = at(l, i);

		for (int k = 0; e->used && k < e->nmids; k++) {
			if (e->mids[k] != mid)
				continue;
			e->mids[k] = e->mids[--e->nmids];
			if (e->nmids == 0 && e != l->open)
				e->used = false;
			trim(l);
			return true;
		}
	}
	return false;
}

void gw_live_drain(struct gw_live *l, void (*fn)(void *u, struct gw_buffer_rec *r), void *u)
{
	for (size_t i = 0; i < l->n; i++) {
		struct gw_live_ent *e = at(l, i);

		if (e->used)
			fn(u, &e->r);
		e->used = false;
	}
	l->head = l->n = 0;
	l->open = NULL;
}
