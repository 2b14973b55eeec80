/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer_int - what gw_buffer.c (the interface, the ring in memory, the
 * option parsers) and gw_buffer_sql.c (the SQLite file) share. Not for other
 * modules: they use gw_buffer.h.
 */
#ifndef DF1_TOOLS_GW_BUFFER_INT_H
#define DF1_TOOLS_GW_BUFFER_INT_H

#include "df1gw/gw_buffer.h"

/* A record with its own storage (the ring's slots, the rows a peek read). */
struct gw_buffer_slot {
	struct gw_buffer_rec r;
	char *key;
	size_t keycap;
	unsigned char *data;
	size_t datacap;
	bool acked;
};

struct gw_buffer_sql;

struct gw_buffer {
	struct gw_buffer_limits lim;
	struct gw_buffer_sql *sql;   /* NULL: in memory */
	/* the ring: n slots from head, seq increasing; acknowledged ones inside
	 * stay until they reach the head */
	struct gw_buffer_slot *ring;
	size_t cap, head, n;
	/* what a peek returns (and, on a file, the rows it read) */
	struct gw_buffer_rec *out;
	struct gw_buffer_slot *rows;
	size_t outcap;
	uint64_t next_seq;           /* the next append's */
	uint64_t handed;             /* peek goes past the records up to it */
	/* of records and bytes, those handed over and not acknowledged (seq up
	 * to handed): in flight, outside the bounds, never dropped */
	uint64_t handed_n, handed_bytes;
	uint64_t drop_mark;          /* in memory: the records not handed over up to it are gone */
	uint64_t records, bytes;
	uint64_t appended, acked, dropped_size, dropped_age, dropped_pending;
	char note[512];
	bool has_note;
};

/* gw_buffer_mem.c: records in memory. A record's size against max_bytes. */
uint64_t gw_buffer_rec_size(const struct gw_buffer_rec *r);
/* Copies r into slot s (its storage grown as needed). 0 or GW_BUFFER_ERR. */
int gw_buffer_slot_set(struct gw_buffer_slot *s, const struct gw_buffer_rec *r);
/* The output array of a peek, at least n long. 0 or GW_BUFFER_ERR. */
int gw_buffer_out_reserve(struct gw_buffer *b, size_t n);
/* Appends r to the ring as it is (its seq kept). 0 or GW_BUFFER_ERR. */
int gw_buffer_mem_push(struct gw_buffer *b, const struct gw_buffer_rec *r);
void gw_buffer_set_note(struct gw_buffer *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void gw_buffer_slots_free(struct gw_buffer_slot *s, size_t n);
struct gw_buffer_slot *gw_buffer_ring_at(struct gw_buffer *b, size_t i);
/* Acknowledged slots at the head go (their storage stays for reuse). */
void gw_buffer_ring_trim(struct gw_buffer *b);
/* The oldest record neither handed over nor acknowledged, or NULL. */
struct gw_buffer_slot *gw_buffer_mem_oldest_pending(struct gw_buffer *b);
/* That record goes; *size its size. 0, 1 when none. */
int gw_buffer_mem_drop_oldest(struct gw_buffer *b, uint64_t *size);
/* The records held with seq in (lo, hi]: how many (*n) and their sizes. */
void gw_buffer_mem_span(struct gw_buffer *b, uint64_t lo, uint64_t hi, uint64_t *n, uint64_t *bytes);
/* The slot of seq, or NULL. */
struct gw_buffer_slot *gw_buffer_mem_find(struct gw_buffer *b, uint64_t seq);
int64_t gw_buffer_mem_oldest_ms(const struct gw_buffer *b);

/* The file: open (0, GW_BUFFER_LOCKED, or GW_BUFFER_ERR with err: the caller
 * falls back to memory), close, and the operations of gw_buffer.h on it. Each
 * returns GW_BUFFER_ERR with err when the file failed. */
int gw_buffer_sql_open(struct gw_buffer *b, const char *path, char *err, size_t errcap);
void gw_buffer_sql_close(struct gw_buffer *b);
int gw_buffer_sql_append(struct gw_buffer *b, const struct gw_buffer_rec *r, char *err, size_t errcap);
/* Deletes the oldest record not handed over (seq above b->handed); *size its
 * size. 0, 1 when there is none, or GW_BUFFER_ERR. */
int gw_buffer_sql_drop_oldest(struct gw_buffer *b, uint64_t *size, char *err, size_t errcap);
/* Deletes the records not handed over read before cutoff_ms. */
int gw_buffer_sql_expire(struct gw_buffer *b, int64_t cutoff_ms, char *err, size_t errcap);
/* The records held with seq in (lo, hi]: how many (*n) and their sizes. */
int gw_buffer_sql_span(struct gw_buffer *b, uint64_t lo, uint64_t hi, uint64_t *n, uint64_t *bytes, char *err,
                       size_t errcap);
int gw_buffer_sql_peek(struct gw_buffer *b, size_t max, char *err, size_t errcap);
int gw_buffer_sql_ack(struct gw_buffer *b, uint64_t seq, char *err, size_t errcap);
int64_t gw_buffer_sql_oldest_ms(const struct gw_buffer *b);
/* Every record of the file into the ring (the fall back to memory). */
int gw_buffer_sql_to_mem(struct gw_buffer *b, char *err, size_t errcap);

#endif
