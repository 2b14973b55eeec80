/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer_rec.c - station health and write results as store and forward
 * blobs and back; the layouts are in gw_buffer_rec.h.
 */
#include "df1gw/gw_buffer_rec.h"

#include <string.h>

#define REC_VERSION 1
#define TEXT_NONE 0xFFFFu
#define RES_OK 1u
#define RES_UNCONFIRMED 2u

struct wr {
	uint8_t *p;
	size_t n, cap;
	bool over;
};

struct rd {
	const uint8_t *p;
	size_t n, len;
	bool bad;
};

static void put_u(struct wr *w, uint64_t v, size_t bytes)
{
	if (w->over || bytes > w->cap - w->n) {
		w->over = true;
		return;
	}
	for (size_t i = 0; i < bytes; i++)
		w->p[w->n++] = (uint8_t)(v >> (8 * i));
}

static void put_text(struct wr *w, const char *s)
{
	size_t n;

	if (!s) {
		put_u(w, TEXT_NONE, 2);
		return;
	}
	n = strlen(s);
	if (n > GW_BUFFER_TEXT_MAX)
		n = GW_BUFFER_TEXT_MAX;
	put_u(w, n, 2);
	if (w->over || n > w->cap - w->n) {
		w->over = true;
		return;
	}
	memcpy(w->p + w->n, s, n);
	w->n += n;
}

static uint64_t get_u(struct rd *r, size_t bytes)
{
	uint64_t v = 0;

	if (r->bad || bytes > r->len - r->n) {
		r->bad = true;
		return 0;
	}
	for (size_t i = 0; i < bytes; i++)
		v |= (uint64_t)r->p[r->n++] << (8 * i);
	return v;
}

/* A text into buf (GW_BUFFER_TEXT_MAX + 1 bytes): buf, or NULL for none. */
static const char *get_text(struct rd *r, char *buf)
{
	uint64_t n = get_u(r, 2);

	buf[0] = '\0';
	if (r->bad || n == TEXT_NONE)
		return NULL;
	if (n > GW_BUFFER_TEXT_MAX || n > r->len - r->n) {
		r->bad = true;
		return NULL;
	}
	memcpy(buf, r->p + r->n, n);
	buf[n] = '\0';
	r->n += n;
	return buf;
}

int gw_buffer_station_pack(const struct gw_station_out *s, uint8_t *buf, size_t cap)
{
	struct wr w = { buf, 0, cap, false };

	put_u(&w, REC_VERSION, 1);
	put_text(&w, s->state ? s->state : "unknown");
	put_text(&w, s->error);
	put_u(&w, (uint64_t)s->last_good_wall_ms, 8);
	put_u(&w, (uint32_t)(s->sh ? s->sh->tags : 0), 4);
	put_u(&w, (uint32_t)(s->sh ? s->sh->consecutive_failures : 0), 4);
	put_u(&w, s->sh ? s->sh->attempts : 0, 8);
	put_u(&w, s->sh ? s->sh->failures : 0, 8);
	return w.over ? -1 : (int)w.n;
}

int gw_buffer_station_unpack(const void *b, size_t len, int stn, struct gw_buffer_station_out *o)
{
	struct rd r = { b, 0, len, false };
	const char *state, *error;

	memset(&o->sh, 0, sizeof o->sh);
	if (get_u(&r, 1) != REC_VERSION)
		return -1;
	state = get_text(&r, o->state);
	error = get_text(&r, o->error);
	o->out.last_good_wall_ms = (int64_t)get_u(&r, 8);
	o->sh.tags = (int)(int32_t)get_u(&r, 4);
	o->sh.consecutive_failures = (int)(int32_t)get_u(&r, 4);
	o->sh.attempts = get_u(&r, 8);
	o->sh.failures = get_u(&r, 8);
	if (r.bad || r.n != len || !state)
		return -1;
	o->sh.station = stn;
	o->out.station = stn;
	o->out.state = state;
	o->out.error = error;
	o->out.sh = &o->sh;
	return 0;
}

int gw_buffer_result_pack(const struct gw_result_out *r, uint8_t *buf, size_t cap)
{
	struct wr w = { buf, 0, cap, false };

	put_u(&w, REC_VERSION, 1);
	put_u(&w, (r->ok ? RES_OK : 0) | (r->unconfirmed ? RES_UNCONFIRMED : 0), 1);
	put_text(&w, r->tag ? r->tag : "");
	put_text(&w, r->id ? r->id : "");
	put_text(&w, r->ok ? NULL : r->error);
	return w.over ? -1 : (int)w.n;
}

int gw_buffer_result_unpack(const void *b, size_t len, struct gw_buffer_result_out *o)
{
	struct rd r = { b, 0, len, false };
	uint64_t flags;
	const char *tag, *id;

	if (get_u(&r, 1) != REC_VERSION)
		return -1;
	flags = get_u(&r, 1);
	tag = get_text(&r, o->tag);
	id = get_text(&r, o->id);
	o->out.error = get_text(&r, o->error);
	if (r.bad || r.n != len || !tag || !*tag || !id || flags > (RES_OK | RES_UNCONFIRMED))
		return -1;
	o->out.tag = tag;
	o->out.id = id;
	o->out.ok = (flags & RES_OK) != 0;
	o->out.unconfirmed = (flags & RES_UNCONFIRMED) != 0;
	o->out.now = NULL;
	if (!o->out.ok && !o->out.error)
		o->out.error = "";
	return 0;
}
