/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer - df1gw's store and forward buffer (doc/ARCHITECTURE.md 11): the
 * changes that could not be published, kept in order until the broker has
 * acknowledged them. On a SQLite file (WAL, synchronous=NORMAL, one process
 * per file) or in memory (a ring, lost on exit), behind one interface.
 *
 * A record is topic-independent: what it is (kind), which tag or station
 * (id and key), when it was read (ms), its quality and an opaque blob (the
 * value as the caller encodes it, enough to re-encode it in any format).
 * The buffer numbers records in append order (seq, never reused in a file),
 * hands them out oldest first (peek, then handed), and deletes one only on
 * acknowledgement (ack, as PUBACK arrives). A record handed over but not
 * acknowledged when the connection drops is handed out again after rewind.
 *
 * Bounds: at most max_records records, max_bytes bytes (a record's size is
 * its blob plus its key plus GW_BUFFER_REC_OVERHEAD) and max_age_ms old; the
 * oldest go first, counted. They hold the records not handed over: one
 * handed over is in flight until its acknowledgement (or a rewind) and is
 * never dropped meanwhile, so a drop is always a record the broker never
 * acknowledged; the caller bounds what is in flight (the replay's window,
 * gw_replay.h). The module never prints: notes (a file moved
 * aside, a fall back to memory) and drop counts are returned for the caller
 * to log.
 */
#ifndef DF1_TOOLS_GW_BUFFER_H
#define DF1_TOOLS_GW_BUFFER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* What a record is. */
enum gw_buffer_kind {
	GW_BUFFER_TAG = 1,       /* a tag's value and quality */
	GW_BUFFER_HEALTH = 2,    /* a station's health */
	GW_BUFFER_WRITE = 3,     /* a write's result */
	GW_BUFFER_RECEIVE = 4,   /* a Receive tag's value as a PLC wrote it (id: the PLC's station) */
};

/* Results beyond 0. */
#define GW_BUFFER_ERR (-1)       /* out of memory, or an argument out of range */
#define GW_BUFFER_LOCKED (-2)    /* another process holds the file: exit 2 */

/* The size a record counts for beyond its blob and key (seq, kind, id, ms,
 * quality), so that empty records bound the buffer too. */
#define GW_BUFFER_REC_OVERHEAD 32u

/* In memory (no file, or a file that failed) without a bound on records or
 * bytes: 100 000 records, Kepware IoT Gateway's figure, and at most 64 MiB. */
#define GW_BUFFER_MEM_DEFAULT_RECORDS 100000u
#define GW_BUFFER_MEM_DEFAULT_BYTES (64u * 1024u * 1024u)

struct gw_buffer_rec {
	uint64_t seq;            /* set by append */
	int kind;                /* enum gw_buffer_kind */
	int id;                  /* tag id or station */
	int quality;
	int64_t ms;              /* read time, ms since the epoch */
	const char *key;         /* tag name ("" for none) */
	const void *data;        /* the value as the caller encoded it */
	size_t len;
};

struct gw_buffer_limits {
	uint64_t max_records;    /* 0: no bound */
	uint64_t max_bytes;      /* 0: no bound */
	int64_t max_age_ms;      /* 0: no bound */
};

struct gw_buffer_stats {
	uint64_t records;        /* held now (handed over or not) */
	uint64_t handed;         /* of them, handed over and not acknowledged (in flight) */
	uint64_t bytes;          /* their sizes */
	int64_t oldest_ms;       /* read time of the oldest, 0 when empty */
	uint64_t appended;       /* since open */
	uint64_t acked;
	uint64_t dropped_size;   /* dropped by max_records or max_bytes */
	uint64_t dropped_age;    /* dropped by max_age_ms */
	bool in_memory;          /* no file, or fell back to memory */
};

struct gw_buffer;

/* Opens the buffer on file path (NULL: in memory) with bounds lim.
 * Returns 0 with *out set; a note (a corrupt or foreign file moved aside, an
 * unusable file and the fall back to memory: path and errno text) is then in
 * gw_buffer_note(). GW_BUFFER_LOCKED when another process has the file,
 * GW_BUFFER_ERR on no memory; err says what. */
int gw_buffer_open(struct gw_buffer **out, const char *path, const struct gw_buffer_limits *lim, char *err,
                   size_t errcap);
/* Closes; the records not acknowledged stay in the file. */
void gw_buffer_close(struct gw_buffer *b);

/* Appends r (its seq set here), dropping the oldest as the bounds demand
 * (now_ms: the clock for max_age_ms). 0, or GW_BUFFER_ERR. A file that fails
 * (a full disk) is left for memory: the records it held move with their seq,
 * and gw_buffer_note() says why. */
int gw_buffer_append(struct gw_buffer *b, struct gw_buffer_rec *r, int64_t now_ms);
/* Drops what is older than max_age_ms at now_ms. 0 or GW_BUFFER_ERR. */
int gw_buffer_expire(struct gw_buffer *b, int64_t now_ms);

/* Up to max records not handed over yet, oldest first, in *recs (storage of
 * b's, valid until the next call on b). Returns how many, or GW_BUFFER_ERR. */
int gw_buffer_peek(struct gw_buffer *b, size_t max, const struct gw_buffer_rec **recs);
/* The records up to seq have been handed to the broker: peek goes past them,
 * and the bounds neither count nor drop them until ack or rewind. */
void gw_buffer_handed(struct gw_buffer *b, uint64_t seq);
/* The connection dropped: what was handed over and not acknowledged is
 * handed out again. */
void gw_buffer_rewind(struct gw_buffer *b);
/* The broker acknowledged record seq: deleted. 0 (also when it was gone
 * already: dropped, or acknowledged twice) or GW_BUFFER_ERR. */
int gw_buffer_ack(struct gw_buffer *b, uint64_t seq);

void gw_buffer_stats(const struct gw_buffer *b, struct gw_buffer_stats *s);
/* Records dropped since the last call (for one log line per outage). */
uint64_t gw_buffer_take_dropped(struct gw_buffer *b);
/* The last note, or NULL; cleared by reading it. */
const char *gw_buffer_note(struct gw_buffer *b);

/* --buffer-max: "1000r" or "1000records" (records), "64k" "64M" "2G" (bytes,
 * powers of 1024) or a plain number of bytes. 0, or -1 with err. */
int gw_buffer_parse_max(const char *s, struct gw_buffer_limits *lim, char *err, size_t errcap);
/* --buffer-max-age: "90s", "15m", "12h", "7d" (a plain number: seconds). */
int gw_buffer_parse_age(const char *s, int64_t *ms, char *err, size_t errcap);

#endif
