/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_wqueue - df1gw's queue of writes from MQTT and its policy (df1gw(1),
 * WRITE POLICY), pure: no I/O, no clock (the caller says what time it is).
 * A write waits here until the loop hands it to the line (gw_pub.c, in
 * batches of at most --duty-cycle); here it may be replaced by a later write
 * to the same tag (--write-optimize), expire (--write-timeout), or be refused
 * because too many wait (--max-pending-writes). Each end is told to the
 * owner's callback once, so every /set gets exactly one result. The counters
 * are one struct for every reader (--counters, a metrics page). The outbox
 * keeps the results that fall while the broker is away.
 */
#ifndef DF1_TOOLS_GW_WQUEUE_H
#define DF1_TOOLS_GW_WQUEUE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1.h"
#include "df1gw/gw_format.h"

/* --write-optimize */
enum gw_wopt {
	GW_WOPT_ALL,                 /* every write is written, in order */
	GW_WOPT_LATEST,              /* a waiting write to the same tag is replaced */
	GW_WOPT_LATEST_NON_BOOL,     /* the same, but bits and BOOL tags keep every write */
};

/* How a write ended without being handed to the line. */
enum gw_wend {
	GW_WEND_SUPERSEDED,          /* replaced by a later write to its tag */
	GW_WEND_EXPIRED,             /* not started before its deadline */
	GW_WEND_DROPPED,             /* the line lost, or stopping: not written */
};

#define GW_WQ_MAX_LIMIT 100000       /* --max-pending-writes at most */

/* The write side's figures (--counters prints them; other readers take the
 * same struct). */
struct gw_wcounters {
	uint64_t received;           /* /set messages taken */
	uint64_t refused;            /* answered at once: invalid, read-only, not JSON, retained, line down */
	uint64_t written;            /* the PLC took it */
	uint64_t failed;             /* handed to the line, failed (unconfirmed or refused) */
	uint64_t superseded;
	uint64_t expired;
	uint64_t refused_busy;       /* --max-pending-writes reached */
	uint64_t dropped;            /* waiting when the line went away or at the stop */
	unsigned depth;              /* waiting now */
	unsigned high_water;         /* the most ever waiting */
};

/* A write waiting; made by gw_witem_new, owned by the queue once pushed. */
struct gw_witem {
	int tag;                     /* the tag's id */
	bool keep;                   /* a bit: never replaced under latest-non-bool */
	int64_t deadline_ms;         /* not started by then: expired (monotonic ms) */
	void *user;                  /* the owner's: whose result it is */
	size_t n;
	struct df1_value v[];        /* the values to write */
};

struct gw_wq;
/* it ended without being written (why); by is the write that replaced it
 * (SUPERSEDED), else NULL. The callback frees nothing: the queue frees it
 * after the call. */
typedef void (*gw_wend_fn)(void *ctx, struct gw_witem *it, enum gw_wend why, const struct gw_witem *by);

struct gw_wq {
	enum gw_wopt opt;
	unsigned max;                /* waiting at most */
	struct gw_witem **v;         /* FIFO: v[0] is handed to the line first */
	size_t n, cap;
	gw_wend_fn end;
	void *ctx;
	struct gw_wcounters c;
};

/* opt, max (1..GW_WQ_MAX_LIMIT), the end callback. 0, or -1 (no memory). */
int gw_wq_init(struct gw_wq *q, enum gw_wopt opt, unsigned max, gw_wend_fn end, void *ctx);
/* Every write still waiting ends DROPPED; the memory freed. */
void gw_wq_free(struct gw_wq *q);

/* A write of n values v to tag (keep: a bit or BOOL), due by deadline_ms.
 * NULL when out of memory. */
struct gw_witem *gw_witem_new(int tag, bool keep, int64_t deadline_ms, const struct df1_value *v, size_t n,
                              void *user);

/* Queue it: 0 (waiting; a write it replaced has ended SUPERSEDED), or -1
 * when max writes wait already (busy: counted, the caller answers and frees
 * it with free()). */
int gw_wq_push(struct gw_wq *q, struct gw_witem *it);
/* Every waiting write past its deadline at now ends EXPIRED. */
void gw_wq_expire(struct gw_wq *q, int64_t now);
/* The next write for the line (the caller owns it, free()), after expiring
 * what is due at now; NULL when none waits. */
struct gw_witem *gw_wq_pop(struct gw_wq *q, int64_t now);
/* Every waiting write ends DROPPED (the line lost). */
void gw_wq_drop_all(struct gw_wq *q);
/* The earliest deadline of a waiting write, or INT64_MAX. */
int64_t gw_wq_next_deadline(const struct gw_wq *q);

/* Results that fell while the broker was away, published when it is back
 * (gw_pub.c): at most cap, the later ones counted as lost. */
struct gw_outbox {
	struct gw_msg *v;
	size_t n, cap;
	uint64_t lost;
};
/* 0, or -1 (no memory). */
int gw_outbox_init(struct gw_outbox *o, size_t cap);
void gw_outbox_free(struct gw_outbox *o);
/* A copy of m kept; false when full or out of memory (counted lost). */
bool gw_outbox_add(struct gw_outbox *o, const struct gw_msg *m);

/* The name of opt ("all", "latest", "latest-non-bool"); parse one: 0 or -1. */
const char *gw_wopt_name(enum gw_wopt opt);
int gw_wopt_parse(const char *s, enum gw_wopt *out);

#endif
