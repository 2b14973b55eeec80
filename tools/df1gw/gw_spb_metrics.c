/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_spb_metrics - tags as Sparkplug metrics and commands back into values
 * (see gw_spb_metrics.h).
 */
#include "df1gw/gw_spb_metrics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the list ---- */

void gw_spb_list_init(struct gw_spb_list *l)
{
	memset(l, 0, sizeof *l);
}

void gw_spb_list_reset(struct gw_spb_list *l)
{
	for (size_t i = 0; i < l->nown; i++)
		free(l->own[i]);
	l->nown = 0;
	l->n = 0;
	l->oom = false;
}

void gw_spb_list_free(struct gw_spb_list *l)
{
	gw_spb_list_reset(l);
	free(l->v);
	free(l->own);
	gw_spb_list_init(l);
}

struct gw_spb_metric *gw_spb_list_add(struct gw_spb_list *l)
{
	if (l->n == l->cap) {
		size_t cap = l->cap ? l->cap * 2 : 16;
		struct gw_spb_metric *v = realloc(l->v, cap * sizeof *v);

		if (!v) {
			l->oom = true;
			return NULL;
		}
		l->v = v;
		l->cap = cap;
	}
	gw_spb_metric_init(&l->v[l->n]);
	return &l->v[l->n++];
}

static void *list_keep(struct gw_spb_list *l, void *p)
{
	if (!p) {
		l->oom = true;
		return NULL;
	}
	if (l->nown == l->capown) {
		size_t cap = l->capown ? l->capown * 2 : 16;
		void **v = realloc(l->own, cap * sizeof *v);

		if (!v) {
			free(p);
			l->oom = true;
			return NULL;
		}
		l->own = v;
		l->capown = cap;
	}
	l->own[l->nown++] = p;
	return p;
}

const char *gw_spb_list_text(struct gw_spb_list *l, const char *s)
{
	return list_keep(l, strdup(s));
}

/* ---- tags as metrics ---- */

/* The members of a whole T, C or R element, in their alias order. */
static const char *const tcr_members_t[] = { "EN", "TT", "DN", "PRE", "ACC", NULL };
static const char *const tcr_members_c[] = { "CU", "CD", "DN", "OV", "UN", "UA", "PRE", "ACC", NULL };
static const char *const tcr_members_r[] = { "EN", "EU", "DN", "EM", "ER", "UL", "IN", "FD", "LEN", "POS", NULL };

static const char *const *tcr_members(enum df1_file_type t)
{
	return t == DF1_FT_T ? tcr_members_t : t == DF1_FT_C ? tcr_members_c : tcr_members_r;
}

uint64_t gw_spb_alias(int id, unsigned member)
{
	return ((uint64_t)(id + 1) << 16) | member;
}

/* Quality and Reason of a tag that is not GOOD (none when it is). */
static void tag_quality(const struct gw_tag_out *t, bool *has_quality, int32_t *quality, const char **reason)
{
	const struct df1_tag_state *st = t->st;
	int q = t->quality >= 0 ? t->quality : (int)st->quality;
	const char *why = t->reason ? t->reason : df1_reason_name(st->reason);

	*has_quality = false;
	*reason = NULL;
	if (q == DF1_QUALITY_GOOD)
		return;
	*has_quality = true;
	if (q == DF1_QUALITY_UNCERTAIN)       /* no value: a Receive row no PLC wrote yet */
		*quality = st->has_value ? GW_SPB_Q_UNCERTAIN_LAST_KNOWN : GW_SPB_Q_UNCERTAIN;
	else if (strcmp(why, "line_lost") == 0 || st->reason == DF1_REASON_STATION_OFFLINE)
		*quality = GW_SPB_Q_BAD_NOT_CONNECTED;
	else if (st->reason == DF1_REASON_COMM_FAILURE)
		*quality = GW_SPB_Q_BAD_STALE;
	else
		*quality = GW_SPB_Q_BAD;
	*reason = why;
}

/* PLC text (bytes, any value) as UTF-8: bytes 0x80-0xFF as ISO 8859-1. */
static const char *latin1_text(struct gw_spb_list *l, const char *s, size_t n)
{
	char *u = malloc(2 * n + 1), *p = u;

	if (!u)
		return list_keep(l, NULL);
	for (size_t i = 0; i < n; i++) {
		unsigned char c = (unsigned char)s[i];

		if (c < 0x80) {
			*p++ = (char)c;
		} else {
			*p++ = (char)(0xC0 | (c >> 6));
			*p++ = (char)(0x80 | (c & 0x3F));
		}
	}
	*p = '\0';
	return list_keep(l, u);
}

/* The scalar value v into m, datatype by kind. */
static void scalar_value(struct gw_spb_list *l, struct gw_spb_metric *m, enum df1_value_kind k,
                         const struct df1_value *v)
{
	switch (k) {
	case DF1_VAL_INT16: m->datatype = GW_SPB_INT16; break;
	case DF1_VAL_INT32: m->datatype = GW_SPB_INT32; break;
	case DF1_VAL_FLOAT: m->datatype = GW_SPB_FLOAT; break;
	case DF1_VAL_BIT: m->datatype = GW_SPB_BOOLEAN; break;
	default: m->datatype = GW_SPB_STRING; break;
	}
	if (!v) {
		m->is_null = true;
		return;
	}
	switch (k) {
	case DF1_VAL_INT16: m->kind = GW_SPB_V_INT; m->v.i = (uint16_t)v->v.i16; break;
	case DF1_VAL_INT32: m->kind = GW_SPB_V_INT; m->v.i = (uint32_t)v->v.i32; break;
	case DF1_VAL_FLOAT: m->kind = GW_SPB_V_FLOAT; m->v.f = v->v.f; break;
	case DF1_VAL_BIT: m->kind = GW_SPB_V_BOOL; m->v.b = v->v.bit; break;
	default:
		m->kind = GW_SPB_V_STRING;
		m->str = latin1_text(l, v->v.str.text, v->v.str.len);
		break;
	}
}

static void put_le(uint8_t *p, uint32_t x, int bytes)
{
	for (int i = 0; i < bytes; i++)
		p[i] = (uint8_t)(x >> (8 * i));
}

/* n values as one array metric: numbers little-endian, booleans a 4-byte
 * count then bits from the high bit of each byte, strings NUL-terminated. */
static void array_value(struct gw_spb_list *l, struct gw_spb_metric *m, enum df1_value_kind k,
                        const struct df1_value *v, size_t n)
{
	size_t size = k == DF1_VAL_INT16 ? 2 : k == DF1_VAL_BIT ? 0 : 4;
	uint8_t *b;

	m->datatype = k == DF1_VAL_INT16 ? GW_SPB_INT16_ARRAY : k == DF1_VAL_INT32 ? GW_SPB_INT32_ARRAY :
	              k == DF1_VAL_FLOAT ? GW_SPB_FLOAT_ARRAY : k == DF1_VAL_BIT ? GW_SPB_BOOLEAN_ARRAY :
	              GW_SPB_STRING_ARRAY;
	if (!v) {
		m->is_null = true;
		return;
	}
	m->kind = GW_SPB_V_BYTES;
	if (k == DF1_VAL_STRING) {
		size_t total = 0;

		for (size_t i = 0; i < n; i++)
			total += 2u * v[i].v.str.len + 1;
		b = list_keep(l, calloc(total ? total : 1, 1));
		m->bytes = b;
		for (size_t i = 0, at = 0; b && i < n; i++) {
			const char *u = latin1_text(l, v[i].v.str.text, v[i].v.str.len);

			if (!u)
				return;
			memcpy(b + at, u, strlen(u) + 1);
			at += strlen(u) + 1;
			m->nbytes = at;
		}
		return;
	}
	m->nbytes = k == DF1_VAL_BIT ? 4 + (n + 7) / 8 : n * size;
	b = list_keep(l, calloc(m->nbytes, 1));
	m->bytes = b;
	for (size_t i = 0; b && i < n; i++) {
		if (k == DF1_VAL_INT16)
			put_le(b + 2 * i, (uint16_t)v[i].v.i16, 2);
		else if (k == DF1_VAL_INT32)
			put_le(b + 4 * i, (uint32_t)v[i].v.i32, 4);
		else if (k == DF1_VAL_FLOAT) {
			/* the IEEE 754 bits, little-endian whatever the host's order */
			uint32_t u;

			memcpy(&u, &v[i].v.f, 4);
			put_le(b + 4 * i, u, 4);
		} else if (v[i].v.bit)
			b[4 + i / 8] |= (uint8_t)(0x80 >> (i % 8));
	}
	if (b && k == DF1_VAL_BIT)
		put_le(b, (uint32_t)n, 4);
}

/* One metric of tag t with the common fields: name (birth or no aliases),
 * alias, time, quality. */
static struct gw_spb_metric *tag_metric(struct gw_spb_list *l, const struct gw_tag_out *t, const char *name,
                                        unsigned member, int64_t ms, const struct gw_spb_how *how)
{
	struct gw_spb_metric *m = gw_spb_list_add(l);

	if (!m)
		return NULL;
	if (how->birth || !how->aliases)
		m->name = gw_spb_list_text(l, name);
	if (how->aliases) {
		m->has_alias = true;
		m->alias = gw_spb_alias(t->st->id, member);
	}
	m->timestamp = ms > 0 ? (uint64_t)ms : 0;
	m->is_historical = how->historical;
	tag_quality(t, &m->has_quality, &m->quality, &m->reason);
	return m;
}

/* A whole timer, counter or control element i as its members. */
static int tcr_metrics(struct gw_spb_list *l, const struct gw_tag_out *t, size_t i, const struct df1_value *v,
                       int64_t ms, const struct gw_spb_how *how)
{
	const struct df1_tag_config *c = t->st->config;
	const char *const *mem = tcr_members(c->addr.type);
	char name[96];

	for (unsigned j = 0; mem[j]; j++) {
		struct gw_spb_metric *m;
		int bit = df1_tcr_bit(c->addr.type, mem[j]);

		if (c->count > 1)
			snprintf(name, sizeof name, "%s/%zu/%s", c->name, i, mem[j]);
		else
			snprintf(name, sizeof name, "%s/%s", c->name, mem[j]);
		m = tag_metric(l, t, name, (unsigned)(i * 16 + j + 1), ms, how);
		if (!m)
			return -1;
		m->datatype = bit >= 0 ? GW_SPB_BOOLEAN : GW_SPB_INT16;
		if (!v) {
			m->is_null = true;
		} else if (bit >= 0) {
			m->kind = GW_SPB_V_BOOL;
			m->v.b = (v->v.tcr.ctl >> bit) & 1;
		} else {
			m->kind = GW_SPB_V_INT;
			m->v.i = (uint16_t)(strcmp(mem[j], "PRE") == 0 || strcmp(mem[j], "LEN") == 0 ? v->v.tcr.pre
			                                                                          : v->v.tcr.acc);
		}
	}
	return 0;
}

int gw_spb_tag_metrics(struct gw_spb_list *l, const struct gw_tag_out *t, int64_t ms, const struct gw_spb_how *how)
{
	const struct df1_tag_state *st = t->st;
	const struct df1_tag_config *c = st->config;
	enum df1_value_kind k = df1_addr_value_kind(&c->addr);
	bool has = st->has_value && st->values && st->count > 0;
	struct gw_spb_metric *m;

	if (k == DF1_VAL_TCR) {
		for (size_t i = 0; i < (size_t)(c->count > 0 ? c->count : 1); i++)
			if (tcr_metrics(l, t, i, has && i < st->count ? &st->values[i] : NULL, ms, how) < 0)
				return -1;
		return l->oom ? -1 : 0;
	}
	m = tag_metric(l, t, c->name, 0, ms, how);
	if (!m)
		return -1;
	if (c->count > 1)
		array_value(l, m, k, has ? st->values : NULL, st->count);
	else
		scalar_value(l, m, k, has ? &st->values[0] : NULL);
	return l->oom ? -1 : 0;
}

int gw_spb_ddata_encode(struct gw_buf *out, struct gw_spb_list *scratch, const struct gw_spb_sample *s, size_t n,
                        bool historical, bool aliases, int64_t payload_ms)
{
	struct gw_spb_how how = { false, aliases, historical };
	int r = 0;

	gw_spb_list_reset(scratch);
	for (size_t i = 0; i < n && r == 0; i++)
		r = gw_spb_tag_metrics(scratch, s[i].t, s[i].ms, &how);
	if (r == 0)
		r = gw_spb_encode(out, payload_ms > 0 ? (uint64_t)payload_ms : 0, scratch->v, scratch->n);
	gw_spb_list_reset(scratch);
	return r;
}
