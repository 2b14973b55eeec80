/* SPDX-License-Identifier: MPL-2.0 */
/*
 * tags.c - the poll engine's tags: df1_tag_add() and its checks, each tag's
 * layout in its file, quality changes and the change callback, the getters,
 * the index of their names, and df1_tag_load_map().
 */
#include "poll/poll_int.h"

#include "proto/value_type.h"

static bool poll_is_tcr(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R;
}

/* Elements a tag needs and how its values come out of them. */
static int poll_tag_layout(struct ptag *t)
{
	const struct df1_addr *a = &t->cfg.addr;
	int es = df1_file_type_element_size(a->type);

	if (es <= 0)
		return DF1_E_INVAL;
	t->esize = (size_t)es;
	t->e0 = a->element;
	t->ecount = t->cfg.count;
	t->word = -1;
	t->wbits = 0;
	if (a->ascii[0] || (a->sub != DF1_ADDR_NONE && !poll_is_tcr(a->type))) {
		t->how = HOW_ALONE;     /* "$N7:0", I/O words "I1:0.1": the client's own forms */
		return 0;
	}
	if (a->bit != DF1_ADDR_NONE) {
		t->how = HOW_BITS;
		if (poll_is_tcr(a->type)) {
			t->wbits = 16;
			t->word = a->sub == DF1_ADDR_NONE ? 0 : a->sub;
			if (a->bit + t->cfg.count > 16)
				return DF1_E_ADDR_RANGE;
			t->ecount = 1;
		} else {
			t->wbits = a->type == DF1_FT_L ? 32 : 16;
			if ((size_t)t->wbits != t->esize * 8)
				return DF1_E_TYPE;      /* no bits in F / ST */
			t->ecount = (a->bit + t->cfg.count - 1) / t->wbits + 1;
		}
		return 0;
	}
	if (a->sub != DF1_ADDR_NONE) {
		t->how = HOW_WORD;      /* T/C/R word */
		t->word = a->sub;
		if ((size_t)(a->sub * 2 + 2) > t->esize)
			return DF1_E_ADDR_RANGE;
		return 0;
	}
	t->how = HOW_ELEM;
	return 0;
}

static void poll_tag_state(const struct ptag *t, int64_t now, struct df1_tag_state *st)
{
	memset(st, 0, sizeof *st);
	st->id = t->id;
	st->config = &t->cfg;
	st->count = (size_t)t->cfg.count;
	st->values = t->values;
	st->value = t->values[0];
	st->has_value = t->has_value;
	st->quality = t->q;
	st->reason = t->r;
	st->last_good_ms = t->last_good_ms;
	st->last_good_wall_ms = t->last_good_wall_ms;
	st->age_ms = t->last_good_ms ? now - t->last_good_ms : -1;
	st->last_error = t->last_error;
	st->sts = t->sts;
	st->ext_sts = t->ext;
	st->reads = t->reads;
}

static void poll_notify(struct poll_engine *e, const struct ptag *t)
{
	struct df1_tag_state st;

	if (!e->cb)
		return;
	poll_tag_state(t, df1_now_ms(), &st);
	e->cb(e->cb_user, t->id, &st);
}

/* Set quality and reason; fires the callback on a change (or when forced by a value change). */
void poll_set_quality(struct poll_engine *e, struct ptag *t, enum df1_quality q,
                      enum df1_quality_reason r, bool value_changed)
{
	bool changed = value_changed || t->q != q || t->r != r;

	t->q = q;
	t->r = r;
	if (changed)
		poll_notify(e, t);
}

/* ---- name index ----
 * Tag names are found through a hash index (open addressing, linear probing,
 * at most half full), so that adding n tags, and loading a mapping file of n
 * rows, is linear in n (a search through every tag per add was quadratic:
 * 40 000 tags took 10 s). */

typedef const char *(*poll_name_fn)(const void *ctx, int id);

static size_t poll_name_hash(const char *s)
{
	uint32_t h = 2166136261u;       /* FNV-1a */

	for (; *s; s++)
		h = (h ^ (unsigned char)*s) * 16777619u;
	return h;
}

/* The slot holding name, or the empty slot (-1) where it would go. */
static size_t poll_name_slot(const int *slots, size_t cap, const char *name, poll_name_fn name_of,
                             const void *ctx)
{
	size_t i = poll_name_hash(name) & (cap - 1);

	while (slots[i] >= 0 && strcmp(name_of(ctx, slots[i]), name) != 0)
		i = (i + 1) & (cap - 1);
	return i;
}

/* A new index of cap slots (a power of two), all empty; NULL when out of memory. */
static int *poll_names_new(size_t cap)
{
	int *slots = malloc(cap * sizeof *slots);

	if (slots)
		for (size_t i = 0; i < cap; i++)
			slots[i] = -1;
	return slots;
}

static const char *poll_tag_name(const void *ctx, int id)
{
	return ((const struct poll_engine *)ctx)->tags[id]->cfg.name;
}

/* Room in the engine's index for one more name: false when out of memory. */
static bool poll_names_reserve(struct poll_engine *e)
{
	size_t cap = e->names_cap ? e->names_cap : 64;
	int *slots;

	while ((e->ntags + 1) * 2 > cap)
		cap *= 2;
	if (cap == e->names_cap)
		return true;
	slots = poll_names_new(cap);
	if (!slots)
		return false;
	for (size_t i = 0; i < e->ntags; i++)
		if (e->tags[i]->cfg.name[0])
			slots[poll_name_slot(slots, cap, e->tags[i]->cfg.name, poll_tag_name, e)] = (int)i;
	free(e->names);
	e->names = slots;
	e->names_cap = cap;
	return true;
}

/* Check a tag configuration and work out its layout into *t (t->cfg = *c). */
static int poll_tag_check(struct df1 *h, const struct df1_tag_config *c, struct ptag *t)
{
	char at[64];
	const char *why;
	int rc;

	if (c->station < 0 || c->station > 254)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag %s: station %d out of range 0-254",
		                c->name, c->station);
	if (c->count < 1 || c->count > POLL_COUNT_MAX)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag %s: count %d out of range 1-%d",
		                c->name, c->count, POLL_COUNT_MAX);
	if (c->scan_ms < 0)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag %s: negative scan period", c->name);
	if (!(c->access & DF1_ACCESS_READWRITE) || c->plc < DF1_PLC_SLC || c->plc > DF1_PLC_PLC3)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag %s: invalid access or PLC type", c->name);
	rc = value_type_check(memchr(c->type, '\0', sizeof c->type) ? c->type : "?", &c->addr, &t->kind, &why);
	if (rc < 0) {
		if (df1_addr_format(&c->addr, at, sizeof at) < 0)
			snprintf(at, sizeof at, "?");
		return df1_fail(h, rc, c->station, "tag %s: Type %.15s on %s: %s", c->name, c->type, at, why);
	}
	t->cfg = *c;
	rc = poll_tag_layout(t);
	if (rc < 0) {
		if (df1_addr_format_plc(c->plc, &c->addr, at, sizeof at) < 0)
			snprintf(at, sizeof at, "?");
		return df1_fail(h, rc, c->station, "tag %s: %s: %s", c->name, at, df1_strerror(rc));
	}
	return 0;
}

int df1_tag_add(df1_t *h, const struct df1_tag_config *c)
{
	struct poll_engine *e;
	struct ptag *t;
	int rc;

	if (!h || !c)
		return DF1_E_INVAL;
	if (memchr(c->name, '\0', sizeof c->name) == NULL)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag name not terminated");
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	if (c->name[0] && df1_tag_find(h, c->name) >= 0)
		return df1_fail(h, DF1_E_CONFIG, c->station, "tag %s is defined twice", c->name);
	t = calloc(1, sizeof *t);
	if (!t)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	rc = poll_tag_check(h, c, t);
	if (rc < 0) {
		free(t);
		return rc;
	}
	t->values = calloc((size_t)c->count, sizeof *t->values);
	if (!t->values) {
		free(t);
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	}
	for (int i = 0; i < c->count; i++)
		t->values[i].kind = t->kind;
	t->readable = (c->access & DF1_ACCESS_READ) != 0;
	t->writable = (c->access & DF1_ACCESS_WRITE) != 0;
	t->q = DF1_QUALITY_BAD;
	t->r = DF1_REASON_NOT_YET_READ;
	t->block = -1;

	pthread_mutex_lock(&e->mu);
	if (e->ntags == e->tags_cap) {
		size_t ncap = e->tags_cap ? e->tags_cap * 2 : 16;
		struct ptag **nt = realloc(e->tags, ncap * sizeof *nt);

		if (!nt) {
			pthread_mutex_unlock(&e->mu);
			free(t->values);
			free(t);
			return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
		}
		e->tags = nt;
		e->tags_cap = ncap;
	}
	if (!poll_names_reserve(e)) {
		pthread_mutex_unlock(&e->mu);
		free(t->values);
		free(t);
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	}
	t->id = (int)e->ntags;
	e->tags[e->ntags++] = t;
	if (t->cfg.name[0])
		e->names[poll_name_slot(e->names, e->names_cap, t->cfg.name, poll_tag_name, e)] = t->id;
	pthread_mutex_unlock(&e->mu);
	if (t->readable)
		e->dirty = true;
	return t->id;
}

int df1_tag_value_kind(const struct df1_tag_config *c)
{
	enum df1_value_kind k;
	const char *why;
	int rc;

	if (!c || !memchr(c->type, '\0', sizeof c->type))
		return DF1_E_INVAL;
	rc = value_type_check(c->type, &c->addr, &k, &why);
	return rc < 0 ? rc : (int)k;
}

int df1_tag_count(const df1_t *h)
{
	const struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	e = h->poll;
	return e ? (int)e->ntags : 0;
}

int df1_tag_find(const df1_t *h, const char *name)
{
	const struct poll_engine *e;
	int id;

	if (!h || !name || !*name)
		return DF1_E_INVAL;
	e = h->poll;
	if (!e || !e->names_cap)
		return DF1_E_INVAL;
	id = e->names[poll_name_slot(e->names, e->names_cap, name, poll_tag_name, e)];
	return id >= 0 ? id : DF1_E_INVAL;
}

int df1_tag_get(const df1_t *h, int id, struct df1_tag_state *st)
{
	const struct poll_engine *e;

	if (!h || !st)
		return DF1_E_INVAL;
	e = h->poll;
	if (!e || id < 0 || (size_t)id >= e->ntags)
		return DF1_E_INVAL;
	poll_tag_state(e->tags[id], df1_now_ms(), st);
	return 0;
}

int df1_set_tag_callback(df1_t *h, df1_tag_fn fn, void *user)
{
	struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	e->cb = fn;
	e->cb_user = user;
	return 0;
}

/* ---- mapping CSV ---- */

/* df1_map_load hands one user pointer to both callbacks: this one, which
 * forwards issues to the caller's. */
struct poll_load {
	struct df1_tag_config *rows;
	size_t n, cap;
	df1_config_issue_fn issue_fn;
	void *user;
};

static void poll_load_forward(void *user, const struct df1_config_issue *issue)
{
	struct poll_load *l = user;

	if (l->issue_fn)
		l->issue_fn(l->user, issue);
}

static int poll_load_row(void *user, const struct df1_tag_config *tag)
{
	struct poll_load *l = user;

	if (tag->access == DF1_ACCESS_RECEIVE)
		return 0;       /* not polled: the loader's own table (df1gw(1) RECEIVE) */

	if (l->n == l->cap) {
		size_t ncap = l->cap ? l->cap * 2 : 64;
		struct df1_tag_config *nr = realloc(l->rows, ncap * sizeof *nr);

		if (!nr)
			return DF1_E_NOMEM;
		l->rows = nr;
		l->cap = ncap;
	}
	l->rows[l->n++] = *tag;
	return 0;
}

static const char *poll_row_name(const void *ctx, int id)
{
	return ((const struct df1_tag_config *)ctx)[id].name;
}

static void poll_load_issue(df1_config_issue_fn fn, void *user, const char *name, const char *why)
{
	struct df1_config_issue is;

	if (!fn)
		return;
	memset(&is, 0, sizeof is);
	snprintf(is.text, sizeof is.text, "Tag %.63s: %.120s", name, why);
	fn(user, &is);
}

int df1_tag_load_map(df1_t *h, const char *path, bool strict, df1_config_issue_fn issue_fn, void *user)
{
	struct poll_load l = { NULL, 0, 0, issue_fn, user };
	bool *skip, bad = false;
	int rc, added = 0, *names;
	size_t names_cap = 64;

	if (!h || !path)
		return DF1_E_INVAL;
	if (!poll_engine(h))
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	/* the rows are collected first: on any failure nothing is added */
	rc = df1_map_load(path, strict, poll_load_row, poll_load_forward, &l);
	if (rc < 0) {
		free(l.rows);
		if (rc == DF1_E_NOMEM)
			return df1_fail(h, rc, -1, "%s: out of memory", path);
		return df1_fail(h, rc, -1, "%s: %s", path, df1_strerror(rc));
	}
	/* the file's names seen so far (rows kept), hashed: linear in the rows */
	while (names_cap < l.n * 2)
		names_cap *= 2;
	skip = calloc(l.n ? l.n : 1, sizeof *skip);
	names = poll_names_new(names_cap);
	if (!skip || !names) {
		free(skip);
		free(names);
		free(l.rows);
		return df1_fail(h, DF1_E_NOMEM, -1, "%s: out of memory", path);
	}
	/* duplicate names (in the file, or tags already added), and rows the engine
	 * cannot poll (bits of an F file...): reported, skipped */
	for (size_t i = 0; i < l.n; i++) {
		struct ptag scratch;
		const char *name = l.rows[i].name;
		size_t slot = 0;
		bool dup = false;

		if (name[0]) {
			slot = poll_name_slot(names, names_cap, name, poll_row_name, l.rows);
			dup = names[slot] >= 0 || df1_tag_find(h, name) >= 0;
		}
		if (dup) {
			poll_load_issue(issue_fn, user, name, "defined twice, the first definition is kept");
			skip[i] = bad = true;
			continue;
		}
		memset(&scratch, 0, sizeof scratch);
		if (poll_tag_check(h, &l.rows[i], &scratch) < 0) {
			poll_load_issue(issue_fn, user, name, df1_last_error(h)->message);
			skip[i] = bad = true;
			continue;
		}
		if (name[0])
			names[slot] = (int)i;
	}
	free(names);
	if (bad && strict) {
		free(skip);
		free(l.rows);
		return df1_fail(h, DF1_E_CONFIG, -1, "%s: tags that cannot be added", path);
	}
	for (size_t i = 0; i < l.n; i++) {
		if (skip[i])
			continue;
		rc = df1_tag_add(h, &l.rows[i]);
		if (rc < 0) {
			/* only out of memory is left */
			free(skip);
			free(l.rows);
			return rc;
		}
		added++;
	}
	free(skip);
	free(l.rows);
	return added;
}
