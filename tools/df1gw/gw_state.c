/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_state - the last publication of each retained topic (see gw_state.h).
 */
#include "df1gw/gw_state.h"

#include <stdlib.h>
#include <string.h>

void gw_pubs_init(struct gw_pubs *p)
{
	memset(p, 0, sizeof *p);
}

static void pub_clear(struct gw_pub *e)
{
	free(e->name);
	gw_pub_forget(e);
	free(e->config);
}

void gw_pubs_free(struct gw_pubs *p)
{
	for (size_t i = 0; i < p->n; i++)
		pub_clear(&p->v[i]);
	free(p->v);
	gw_pubs_init(p);
}

struct gw_pub *gw_pubs_get(struct gw_pubs *p, const char *name, bool create)
{
	struct gw_pub *e;

	for (size_t i = 0; i < p->n; i++)
		if (strcmp(p->v[i].name, name) == 0)
			return &p->v[i];
	if (!create)
		return NULL;
	if (p->n == p->cap) {
		size_t cap = p->cap ? p->cap * 2 : 32;
		struct gw_pub *v = realloc(p->v, cap * sizeof *v);

		if (!v)
			return NULL;
		p->v = v;
		p->cap = cap;
	}
	e = &p->v[p->n];
	memset(e, 0, sizeof *e);
	e->name = strdup(name);
	if (!e->name)
		return NULL;
	e->live = true;
	e->tag_id = -1;
	p->n++;
	return e;
}

void gw_pubs_remove(struct gw_pubs *p, struct gw_pub *e)
{
	size_t i = (size_t)(e - p->v);

	if (i >= p->n)
		return;
	pub_clear(e);
	memmove(&p->v[i], &p->v[i + 1], (p->n - i - 1) * sizeof *p->v);
	p->n--;
}

int gw_pub_set(char **field, const char *s)
{
	char *copy = NULL;

	if (s && !(copy = strdup(s)))
		return -1;
	free(*field);
	*field = copy;
	return 0;
}

bool gw_pub_update(struct gw_pub *e, int slot, const char *key, int64_t now, bool force)
{
	char **k = &e->key[slot];

	if (!force && *k && strcmp(*k, key) == 0)
		return false;
	if (gw_pub_set(k, key) < 0) {
		free(*k);
		*k = NULL;
	}
	e->last_ms = now;
	return true;
}

void gw_pub_forget(struct gw_pub *e)
{
	for (int i = 0; i < GW_PUB_KEYS; i++) {
		free(e->key[i]);
		e->key[i] = NULL;
	}
}
