/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer_tag.c - a tag's state as a store and forward blob and back; the
 * layout is in gw_buffer_tag.h.
 */
#include "df1gw/gw_buffer_tag.h"

#include <string.h>

#define TAG_BLOB_VERSION 1
#define TEXT_NONE 255

struct wr {
	uint8_t *p;
	size_t n, cap;
	bool over;
};

static void put(struct wr *w, const void *src, size_t n)
{
	if (w->over || n > w->cap - w->n) {
		w->over = true;
		return;
	}
	memcpy(w->p + w->n, src, n);
	w->n += n;
}

static void put_u(struct wr *w, uint64_t v, size_t bytes)
{
	uint8_t b[8];

	for (size_t i = 0; i < bytes; i++)
		b[i] = (uint8_t)(v >> (8 * i));
	put(w, b, bytes);
}

static void put_text(struct wr *w, const char *s)
{
	if (!s) {
		put_u(w, TEXT_NONE, 1);
		return;
	}
	size_t n = strlen(s);
	if (n > TEXT_NONE - 1)
		n = TEXT_NONE - 1;
	put_u(w, n, 1);
	put(w, s, n);
}

static void put_value(struct wr *w, const struct df1_value *v)
{
	uint32_t f;

	put_u(w, (uint64_t)v->kind, 1);
	switch (v->kind) {
	case DF1_VAL_INT16: put_u(w, (uint16_t)v->v.i16, 2); break;
	case DF1_VAL_INT32: put_u(w, (uint32_t)v->v.i32, 4); break;
	case DF1_VAL_FLOAT:
		memcpy(&f, &v->v.f, 4);
		put_u(w, f, 4);
		break;
	case DF1_VAL_BIT: put_u(w, v->v.bit ? 1 : 0, 1); break;
	case DF1_VAL_STRING: {
		size_t n = v->v.str.len > DF1_STRING_MAX ? DF1_STRING_MAX : v->v.str.len;
		put_u(w, n, 1);
		put(w, v->v.str.text, n);
		break;
	}
	case DF1_VAL_TCR:
		put_u(w, v->v.tcr.ctl, 2);
		put_u(w, (uint16_t)v->v.tcr.pre, 2);
		put_u(w, (uint16_t)v->v.tcr.acc, 2);
		break;
	default:
		w->over = true;
	}
}

int gw_buffer_tag_pack(const struct gw_tag_out *t, uint8_t *buf, size_t cap)
{
	const struct df1_tag_state *st = t->st;
	struct wr w = { buf, 0, cap, false };

	put_u(&w, TAG_BLOB_VERSION, 1);
	put_u(&w, (uint64_t)st->quality, 1);
	put_u(&w, (uint64_t)st->reason, 1);
	put_u(&w, st->has_value ? 1 : 0, 1);
	put_u(&w, (uint16_t)(int16_t)t->quality, 2);
	put_u(&w, (uint32_t)(int32_t)st->last_error, 4);
	put_u(&w, st->sts, 1);
	put_u(&w, st->ext_sts, 1);
	put_u(&w, (uint64_t)st->last_good_wall_ms, 8);
	put_u(&w, (uint64_t)t->wall_ms, 8);
	size_t count = st->values ? st->count : 0;
	if (count > 0xffff)
		return -1;
	put_u(&w, count, 2);
	for (size_t i = 0; i < count; i++)
		put_value(&w, &st->values[i]);
	put_text(&w, t->reason);
	put_text(&w, t->error);
	return w.over ? -1 : (int)w.n;
}

struct rd {
	const uint8_t *p;
	size_t n, len;
	bool bad;
};

static uint64_t get_u(struct rd *r, size_t bytes)
{
	uint64_t v = 0;

	if (r->bad || bytes > r->len - r->n) {
		r->bad = true;
		return 0;
	}
	for (size_t i = 0; i < bytes; i++)
		v |= (uint64_t)r->p[r->n + i] << (8 * i);
	r->n += bytes;
	return v;
}

static void get(struct rd *r, void *dst, size_t n)
{
	if (r->bad || n > r->len - r->n) {
		r->bad = true;
		return;
	}
	memcpy(dst, r->p + r->n, n);
	r->n += n;
}

/* A text into buf (256), or NULL for none. */
static const char *get_text(struct rd *r, char *buf)
{
	size_t n = (size_t)get_u(r, 1);

	if (r->bad || n == TEXT_NONE)
		return NULL;
	get(r, buf, n);
	buf[r->bad ? 0 : n] = '\0';
	return buf;
}

static void get_value(struct rd *r, struct df1_value *v)
{
	uint32_t f;

	memset(v, 0, sizeof *v);
	v->kind = (enum df1_value_kind)get_u(r, 1);
	switch (v->kind) {
	case DF1_VAL_INT16: v->v.i16 = (int16_t)(uint16_t)get_u(r, 2); break;
	case DF1_VAL_INT32: v->v.i32 = (int32_t)(uint32_t)get_u(r, 4); break;
	case DF1_VAL_FLOAT:
		f = (uint32_t)get_u(r, 4);
		memcpy(&v->v.f, &f, 4);
		break;
	case DF1_VAL_BIT: v->v.bit = get_u(r, 1) != 0; break;
	case DF1_VAL_STRING:
		v->v.str.len = (uint16_t)get_u(r, 1);
		if (v->v.str.len > DF1_STRING_MAX)
			r->bad = true;
		else
			get(r, v->v.str.text, v->v.str.len);
		break;
	case DF1_VAL_TCR:
		v->v.tcr.ctl = (uint16_t)get_u(r, 2);
		v->v.tcr.pre = (int16_t)(uint16_t)get_u(r, 2);
		v->v.tcr.acc = (int16_t)(uint16_t)get_u(r, 2);
		break;
	default:
		r->bad = true;
	}
}

int gw_buffer_tag_unpack(const void *b, size_t len, struct gw_buffer_tag_out *o)
{
	struct rd r = { b, 0, len, false };
	struct df1_tag_state *st = &o->st;

	memset(st, 0, sizeof *st);
	if (get_u(&r, 1) != TAG_BLOB_VERSION)
		return -1;
	st->quality = (enum df1_quality)get_u(&r, 1);
	st->reason = (enum df1_quality_reason)get_u(&r, 1);
	st->has_value = get_u(&r, 1) != 0;
	o->out.quality = (int16_t)(uint16_t)get_u(&r, 2);
	st->last_error = (int32_t)(uint32_t)get_u(&r, 4);
	st->sts = (uint8_t)get_u(&r, 1);
	st->ext_sts = (uint8_t)get_u(&r, 1);
	st->last_good_wall_ms = (int64_t)get_u(&r, 8);
	o->out.wall_ms = (int64_t)get_u(&r, 8);
	st->count = (size_t)get_u(&r, 2);
	if (r.bad || st->count > o->cap)
		return -1;
	for (size_t i = 0; i < st->count && !r.bad; i++)
		get_value(&r, &o->values[i]);
	o->out.reason = get_text(&r, o->reason);
	o->out.error = get_text(&r, o->error);
	if (r.bad || r.n != len)
		return -1;
	st->values = o->values;
	if (st->count)
		st->value = o->values[0];
	st->last_good_ms = 0;
	st->age_ms = -1;
	o->out.st = st;
	return 0;
}
