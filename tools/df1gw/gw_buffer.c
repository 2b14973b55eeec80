/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer.c - df1gw's store and forward buffer (gw_buffer.h): the
 * interface, the bounds, the fall back from a file to memory, the parsers
 * of --buffer-max and --buffer-max-age. The records in memory are
 * gw_buffer_mem.c, the SQLite file gw_buffer_sql.c.
 */
#include "df1gw/gw_buffer_int.h"

#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* In memory without a bound on size: the defaults of gw_buffer.h, so that
 * memory is never filled without limit. */
static void mem_bounds(struct gw_buffer *b)
{
	if (!b->lim.max_records && !b->lim.max_bytes) {
		b->lim.max_records = GW_BUFFER_MEM_DEFAULT_RECORDS;
		b->lim.max_bytes = GW_BUFFER_MEM_DEFAULT_BYTES;
	}
}

/* The file failed (err): its records to the ring, the file closed. */
static void fall_back(struct gw_buffer *b, const char *err)
{
	char why[sizeof b->note];

	mem_bounds(b);

	snprintf(why, sizeof why, "%s", err);
	uint64_t before = b->records;
	b->records = 0;
	b->bytes = 0;
	char lerr[256] = "";
	int rc = gw_buffer_sql_to_mem(b, lerr, sizeof lerr);
	gw_buffer_sql_close(b);
	/* what is in flight, of what the ring holds now */
	b->drop_mark = 0;
	gw_buffer_mem_span(b, 0, b->handed, &b->handed_n, &b->handed_bytes);
	if (rc < 0)
		gw_buffer_set_note(b, "%s; buffering in memory from now on, the %" PRIu64
		                   " records of the file stay in it (%s)", why, before, lerr);
	else
		gw_buffer_set_note(b, "%s; buffering in memory from now on (the file's %" PRIu64
		                   " records copied; they stay in the file too)", why, b->records);
}

static int drop_oldest(struct gw_buffer *b, uint64_t *size)
{
	char err[400];

	if (!b->sql)
		return gw_buffer_mem_drop_oldest(b, size);
	int rc = gw_buffer_sql_drop_oldest(b, size, err, sizeof err);
	if (rc == GW_BUFFER_ERR) {
		fall_back(b, err);
		return gw_buffer_mem_drop_oldest(b, size);
	}
	return rc;
}

/* Room for a record of size sz: the oldest go while a bound would be passed.
 * The bounds hold the records not handed over yet; those handed over and
 * waiting for their PUBACK (at most the replay's window, gw_replay.h) are
 * outside them and never dropped: a record the broker may be delivering
 * right now is not counted as lost. A record counted as dropped is thus one
 * the broker never acknowledged (after a rewind, one whose PUBACK the drop
 * of the connection cut off may have reached it). */
static int make_room(struct gw_buffer *b, uint64_t sz)
{
	const struct gw_buffer_limits *l = &b->lim;

	for (;;) {
		uint64_t n = b->records - b->handed_n, bytes = b->bytes - b->handed_bytes;
		if (!n || !((l->max_records && n + 1 > l->max_records) || (l->max_bytes && bytes + sz > l->max_bytes)))
			break;
		uint64_t got = 0;
		int rc = drop_oldest(b, &got);
		if (rc < 0)
			return rc;
		if (rc == 1)
			break;
		b->dropped_size++;
		b->dropped_pending++;
	}
	return 0;
}

int gw_buffer_expire(struct gw_buffer *b, int64_t now_ms)
{
	char err[400];

	if (!b->lim.max_age_ms)
		return 0;
	int64_t cutoff = now_ms - b->lim.max_age_ms;
	if (b->sql) {
		uint64_t before = b->records;
		if (gw_buffer_sql_expire(b, cutoff, err, sizeof err) == 0) {
			b->dropped_age += before - b->records;
			b->dropped_pending += before - b->records;
			return 0;
		}
		fall_back(b, err);
	}
	for (;;) {
		/* as the bounds: what is in flight stays until its PUBACK */
		const struct gw_buffer_slot *s = gw_buffer_mem_oldest_pending(b);
		if (!s || s->r.ms >= cutoff)
			return 0;
		uint64_t got;
		gw_buffer_mem_drop_oldest(b, &got);
		b->dropped_age++;
		b->dropped_pending++;
	}
}

int gw_buffer_append(struct gw_buffer *b, struct gw_buffer_rec *r, int64_t now_ms)
{
	char err[400];
	uint64_t sz = gw_buffer_rec_size(r);

	if (gw_buffer_expire(b, now_ms) < 0 || make_room(b, sz) < 0)
		return GW_BUFFER_ERR;
	r->seq = b->next_seq;
	if (b->sql) {
		if (gw_buffer_sql_append(b, r, err, sizeof err) == 0)
			goto done;
		fall_back(b, err);
		if (make_room(b, sz) < 0)
			return GW_BUFFER_ERR;
	}
	if (gw_buffer_mem_push(b, r) < 0)
		return GW_BUFFER_ERR;
done:
	b->next_seq++;
	b->appended++;
	return 0;
}

int gw_buffer_peek(struct gw_buffer *b, size_t max, const struct gw_buffer_rec **recs)
{
	char err[400];
	size_t k = 0;

	*recs = NULL;
	if (gw_buffer_out_reserve(b, max ? max : 1) < 0)
		return GW_BUFFER_ERR;
	*recs = b->out;
	if (b->sql) {
		int n = gw_buffer_sql_peek(b, max, err, sizeof err);
		if (n >= 0)
			return n;
		fall_back(b, err);
	}
	for (size_t i = 0; i < b->n && k < max; i++) {
		struct gw_buffer_slot *s = gw_buffer_ring_at(b, i);
		if (!s->acked && s->r.seq > b->handed)
			b->out[k++] = s->r;
	}
	return (int)k;
}

void gw_buffer_handed(struct gw_buffer *b, uint64_t seq)
{
	char err[400];
	uint64_t n = 0, bytes = 0;

	if (seq <= b->handed)
		return;
	if (b->sql && gw_buffer_sql_span(b, b->handed, seq, &n, &bytes, err, sizeof err) < 0)
		fall_back(b, err);
	if (!b->sql)
		gw_buffer_mem_span(b, b->handed, seq, &n, &bytes);
	b->handed = seq;
	b->handed_n += n;
	b->handed_bytes += bytes;
}

void gw_buffer_rewind(struct gw_buffer *b)
{
	/* nothing in flight: all of it within the bounds again */
	b->handed = 0;
	b->handed_n = 0;
	b->handed_bytes = 0;
	b->drop_mark = 0;
}

int gw_buffer_ack(struct gw_buffer *b, uint64_t seq)
{
	char err[400];

	if (b->sql) {
		uint64_t n = b->records, bytes = b->bytes;
		if (gw_buffer_sql_ack(b, seq, err, sizeof err) == 0) {
			if (seq <= b->handed) {
				b->handed_n -= n - b->records;
				b->handed_bytes -= bytes - b->bytes;
			}
			return 0;
		}
		fall_back(b, err);
	}
	struct gw_buffer_slot *s = gw_buffer_mem_find(b, seq);
	if (s && !s->acked) {
		uint64_t sz = gw_buffer_rec_size(&s->r);
		s->acked = true;
		b->records--;
		b->bytes -= sz;
		b->acked++;
		if (seq <= b->handed) {
			b->handed_n--;
			b->handed_bytes -= sz;
		}
		gw_buffer_ring_trim(b);
	}
	return 0;
}

void gw_buffer_stats(const struct gw_buffer *b, struct gw_buffer_stats *s)
{
	memset(s, 0, sizeof *s);
	s->records = b->records;
	s->bytes = b->bytes;
	s->handed = b->handed_n;
	s->oldest_ms = b->sql ? gw_buffer_sql_oldest_ms(b) : gw_buffer_mem_oldest_ms(b);
	s->appended = b->appended;
	s->acked = b->acked;
	s->dropped_size = b->dropped_size;
	s->dropped_age = b->dropped_age;
	s->in_memory = !b->sql;
}

uint64_t gw_buffer_take_dropped(struct gw_buffer *b)
{
	uint64_t n = b->dropped_pending;

	b->dropped_pending = 0;
	return n;
}

const char *gw_buffer_note(struct gw_buffer *b)
{
	if (!b->has_note)
		return NULL;
	b->has_note = false;
	return b->note;
}

int gw_buffer_open(struct gw_buffer **out, const char *path, const struct gw_buffer_limits *lim, char *err,
                   size_t errcap)
{
	struct gw_buffer *b = calloc(1, sizeof *b);

	*out = NULL;
	if (!b) {
		snprintf(err, errcap, "out of memory");
		return GW_BUFFER_ERR;
	}
	b->lim = *lim;
	b->next_seq = 1;
	if (path) {
		char serr[400];
		int rc = gw_buffer_sql_open(b, path, serr, sizeof serr);
		if (rc == GW_BUFFER_LOCKED) {
			snprintf(err, errcap, "%s", serr);
			free(b);
			return rc;
		}
		if (rc < 0)
			gw_buffer_set_note(b, "%s; buffering in memory", serr);
	}
	if (!b->sql)
		mem_bounds(b);
	*out = b;
	return 0;
}

void gw_buffer_close(struct gw_buffer *b)
{
	if (!b)
		return;
	if (b->sql)
		gw_buffer_sql_close(b);
	gw_buffer_slots_free(b->ring, b->cap);
	gw_buffer_slots_free(b->rows, b->outcap);
	free(b->out);
	free(b);
}

/* A number and its suffix; -1 when there is no number or it overflows. */
static int parse_num(const char *s, uint64_t *v, const char **suffix)
{
	char *end;

	if (*s < '0' || *s > '9')
		return -1;
	errno = 0;
	unsigned long long n = strtoull(s, &end, 10);
	if (errno)
		return -1;
	*v = n;
	*suffix = end;
	return 0;
}

int gw_buffer_parse_max(const char *s, struct gw_buffer_limits *lim, char *err, size_t errcap)
{
	static const struct { const char *sfx; uint64_t mul; bool records; } units[] = {
		{ "", 1, false }, { "k", 1024, false }, { "K", 1024, false }, { "M", 1024 * 1024, false },
		{ "G", 1024 * 1024 * 1024, false }, { "r", 1, true }, { "records", 1, true },
	};
	uint64_t v;
	const char *sfx;

	if (parse_num(s, &v, &sfx) == 0 && v > 0) {
		for (size_t i = 0; i < sizeof units / sizeof units[0]; i++) {
			if (strcmp(sfx, units[i].sfx) != 0)
				continue;
			if (v > UINT64_MAX / units[i].mul)
				break;
			if (units[i].records) {
				lim->max_records = v;
				lim->max_bytes = 0;
			} else {
				lim->max_bytes = v * units[i].mul;
				lim->max_records = 0;
			}
			return 0;
		}
	}
	snprintf(err, errcap, "'%s' is not a size: bytes (1000000, 64k, 64M, 2G) or records (100000r)", s);
	return -1;
}

int gw_buffer_parse_age(const char *s, int64_t *ms, char *err, size_t errcap)
{
	static const struct { const char *sfx; uint64_t sec; } units[] = {
		{ "", 1 }, { "s", 1 }, { "m", 60 }, { "h", 3600 }, { "d", 86400 },
	};
	uint64_t v;
	const char *sfx;

	if (parse_num(s, &v, &sfx) == 0 && v > 0) {
		for (size_t i = 0; i < sizeof units / sizeof units[0]; i++) {
			if (strcmp(sfx, units[i].sfx) == 0 && v <= (uint64_t)INT64_MAX / 1000 / units[i].sec) {
				*ms = (int64_t)(v * units[i].sec * 1000);
				return 0;
			}
		}
	}
	snprintf(err, errcap, "'%s' is not a duration: a number with s, m, h or d (90s, 15m, 12h, 7d)", s);
	return -1;
}
