/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer_mem.c - the store and forward buffer's records in memory
 * (gw_buffer_int.h): a record's size and storage, the ring (the buffer
 * without a file, and where a failing file's records go), the notes.
 * gw_buffer.c and gw_buffer_sql.c both use it.
 */
#include "df1gw/gw_buffer_int.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

uint64_t gw_buffer_rec_size(const struct gw_buffer_rec *r)
{
	return (uint64_t)r->len + (r->key ? strlen(r->key) : 0) + GW_BUFFER_REC_OVERHEAD;
}

void gw_buffer_set_note(struct gw_buffer *b, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(b->note, sizeof b->note, fmt, ap);
	va_end(ap);
	b->has_note = true;
}

int gw_buffer_slot_set(struct gw_buffer_slot *s, const struct gw_buffer_rec *r)
{
	const char *key = r->key ? r->key : "";
	size_t kl = strlen(key) + 1;

	/* storage kept and grown, so a ring in steady state allocates nothing */
	if (kl > s->keycap) {
		char *k = realloc(s->key, kl);
		if (!k)
			return GW_BUFFER_ERR;
		s->key = k;
		s->keycap = kl;
	}
	if (r->len > s->datacap) {
		unsigned char *d = realloc(s->data, r->len);
		if (!d)
			return GW_BUFFER_ERR;
		s->data = d;
		s->datacap = r->len;
	}
	memcpy(s->key, key, kl);
	if (r->len)
		memcpy(s->data, r->data, r->len);
	s->r = *r;
	s->r.key = s->key;
	s->r.data = s->data;
	s->acked = false;
	return 0;
}

void gw_buffer_slots_free(struct gw_buffer_slot *s, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		free(s[i].key);
		free(s[i].data);
	}
	free(s);
}

int gw_buffer_out_reserve(struct gw_buffer *b, size_t n)
{
	if (n <= b->outcap)
		return 0;
	struct gw_buffer_rec *o = realloc(b->out, n * sizeof *o);
	if (!o)
		return GW_BUFFER_ERR;
	b->out = o;
	struct gw_buffer_slot *r = realloc(b->rows, n * sizeof *r);
	if (!r)
		return GW_BUFFER_ERR;
	memset(r + b->outcap, 0, (n - b->outcap) * sizeof *r);
	b->rows = r;
	b->outcap = n;
	return 0;
}

struct gw_buffer_slot *gw_buffer_ring_at(struct gw_buffer *b, size_t i)
{
	return &b->ring[(b->head + i) % b->cap];
}

/* Twice the slots, the records moved to the start. */
static int ring_grow(struct gw_buffer *b)
{
	size_t ncap = b->cap ? b->cap * 2 : 64;
	struct gw_buffer_slot *r = calloc(ncap, sizeof *r);

	if (!r)
		return GW_BUFFER_ERR;
	for (size_t i = 0; i < b->cap; i++)
		r[i] = *gw_buffer_ring_at(b, i);
	free(b->ring);
	b->ring = r;
	b->cap = ncap;
	b->head = 0;
	return 0;
}

int gw_buffer_mem_push(struct gw_buffer *b, const struct gw_buffer_rec *r)
{
	if (b->n == b->cap && ring_grow(b) < 0)
		return GW_BUFFER_ERR;
	if (gw_buffer_slot_set(gw_buffer_ring_at(b, b->n), r) < 0)
		return GW_BUFFER_ERR;
	b->n++;
	b->records++;
	b->bytes += gw_buffer_rec_size(r);
	return 0;
}

/* Acknowledged slots at the head go (their storage stays for reuse). */
void gw_buffer_ring_trim(struct gw_buffer *b)
{
	while (b->n && gw_buffer_ring_at(b, 0)->acked) {
		b->head = (b->head + 1) % b->cap;
		b->n--;
	}
}

/* The index of the first slot whose seq is above seq (b->n: none); the
 * slots' seq increases along the ring, acknowledged ones included. */
static size_t first_after(struct gw_buffer *b, uint64_t seq)
{
	size_t lo = 0, hi = b->n;

	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2;
		if (gw_buffer_ring_at(b, mid)->r.seq <= seq)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo;
}

/* The records handed over wait for their acknowledgement ahead of it: the
 * search starts past them and past what was dropped already (drops take
 * the oldest first, so nothing up to drop_mark is left to drop). */
struct gw_buffer_slot *gw_buffer_mem_oldest_pending(struct gw_buffer *b)
{
	gw_buffer_ring_trim(b);
	for (size_t i = first_after(b, b->handed > b->drop_mark ? b->handed : b->drop_mark); i < b->n; i++) {
		struct gw_buffer_slot *s = gw_buffer_ring_at(b, i);
		if (!s->acked)
			return s;
	}
	return NULL;
}

int gw_buffer_mem_drop_oldest(struct gw_buffer *b, uint64_t *size)
{
	struct gw_buffer_slot *s = gw_buffer_mem_oldest_pending(b);

	if (!s)
		return 1;
	*size = gw_buffer_rec_size(&s->r);
	s->acked = true;
	b->drop_mark = s->r.seq;
	b->records--;
	b->bytes -= *size;
	gw_buffer_ring_trim(b);
	return 0;
}

void gw_buffer_mem_span(struct gw_buffer *b, uint64_t lo, uint64_t hi, uint64_t *n, uint64_t *bytes)
{
	*n = 0;
	*bytes = 0;
	for (size_t i = first_after(b, lo); i < b->n; i++) {
		const struct gw_buffer_slot *s = gw_buffer_ring_at(b, i);
		if (s->r.seq > hi)
			break;
		if (!s->acked) {
			(*n)++;
			*bytes += gw_buffer_rec_size(&s->r);
		}
	}
}

/* The slot of seq, or NULL (binary search: seq increases along the ring). */
struct gw_buffer_slot *gw_buffer_mem_find(struct gw_buffer *b, uint64_t seq)
{
	size_t lo = 0, hi = b->n;

	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2;
		uint64_t s = gw_buffer_ring_at(b, mid)->r.seq;
		if (s == seq)
			return gw_buffer_ring_at(b, mid);
		if (s < seq)
			lo = mid + 1;
		else
			hi = mid;
	}
	return NULL;
}

int64_t gw_buffer_mem_oldest_ms(const struct gw_buffer *b)
{
	for (size_t i = 0; i < b->n; i++) {
		const struct gw_buffer_slot *s = &b->ring[(b->head + i) % b->cap];
		if (!s->acked)
			return s->r.ms;
	}
	return 0;
}
