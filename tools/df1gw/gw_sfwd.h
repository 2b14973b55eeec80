/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_sfwd - df1gw's store and forward (df1gw(1), STORE AND FORWARD;
 * doc/ARCHITECTURE.md 11.5): while the broker is away (with Sparkplug also
 * while its session is not born: the primary host offline), every tag
 * change, station health change and write result goes into the buffer
 * (gw_buffer.h) instead of out; after the reconnect the backlog is replayed
 * oldest first (gw_replay.h: rate, window, PUBACKs), each record by every
 * format's historical message (gw_format.h tag_historical,
 * station_historical, result), and once it has drained every tag and
 * station is published retained and current again. While a backlog is
 * there, live changes join it behind, so everything leaves in read order.
 * gw_pub.c asks gw_sfwd_capturing() and hands over what it would have
 * published; df1gw.c calls gw_sfwd_turn() once per loop turn.
 */
#ifndef DF1_TOOLS_GW_SFWD_H
#define DF1_TOOLS_GW_SFWD_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "df1gw/gw_buffer.h"
#include "df1gw/gw_format.h"
#include "df1gw/gw_live.h"
#include "df1gw/gw_replay.h"

#define GW_SFWD_FILE_DEFAULT_BYTES (1024ull * 1024 * 1024)   /* --buffer FILE without --buffer-max */

struct gw;

struct gw_sfwd {
	/* options (gw_options.c) */
	const char *path;            /* --buffer FILE; NULL: in memory */
	struct gw_buffer_limits lim; /* --buffer-max, --buffer-max-age */
	unsigned rate;               /* --replay-rate, records a second (0: the default) */

	struct gw_buffer *b;         /* NULL: none (--once, no broker) */
	struct gw_replay r;
	struct gw_live live;         /* live tag publications until their PUBACKs */
	bool draining;               /* a backlog goes out: the republish follows it */
	bool was_up;                 /* the broker at the last turn */
	bool status_due;             /* the retained PREFIX/status/buffer to publish */
	bool full_said;              /* this outage's first drop was said */
	bool err_said;               /* an append that failed was said */
	uint64_t outage_dropped;     /* drops since the outage began */
	int64_t expire_next_ms;      /* monotonic: the next look at --buffer-max-age */
	uint64_t st_key[255];        /* per station: what was last buffered of it */
	bool st_known[255];
};

/* The buffer the options name (a file, or memory: said to be lost on
 * exit), its notes logged. 0, or the exit status (2: another process has
 * the file), having said why. */
int gw_sfwd_open(struct gw *g);
void gw_sfwd_close(struct gw *g);

/* Changes go into the buffer now, not out: the broker away (after the
 * first connection), a session format not born, or a backlog not drained. */
bool gw_sfwd_capturing(const struct gw *g);
/* A backlog is there: live tag and station publication waits behind it. */
bool gw_sfwd_holding(const struct gw *g);
/* What would have been published, buffered. */
void gw_sfwd_tag(struct gw *g, const struct gw_tag_out *t);
/* A Receive tag as station from's write left it (gw_receive.c). */
void gw_sfwd_receive(struct gw *g, const struct gw_tag_out *t, int from);
void gw_sfwd_station(struct gw *g, const struct gw_station_out *s);
/* A live tag publication (gw_pub.c's tag_publish): t kept from _tag until
 * the PUBACK of every QoS 1 message (_mid) published before _close; what is
 * not acknowledged when the connection drops goes into the buffer. */
void gw_sfwd_live_tag(struct gw *g, const struct gw_tag_out *t);
/* The same for a Receive tag as station from's write left it (gw_receive.c):
 * cut off, it is replayed as gw_sfwd_receive's record. */
void gw_sfwd_live_receive(struct gw *g, const struct gw_tag_out *t, int from);
void gw_sfwd_live_mid(struct gw *g, int mid);
void gw_sfwd_live_close(struct gw *g);
/* A write's result of format f while the broker is away: 0 buffered, -1
 * not (no buffer: the caller keeps it its own way). */
int gw_sfwd_result(struct gw *g, const struct gw_fmt *f, const struct gw_result_out *r);

/* Once per loop turn: expiry by age, drops and notes said, the replay. */
void gw_sfwd_turn(struct gw *g, int64_t now);
/* Milliseconds until gw_sfwd_turn has work (a replay's next record). */
int gw_sfwd_wait_ms(const struct gw *g, int64_t now);
/* gw_mqtt_events.acked and .lost (user: struct gw). */
void gw_sfwd_acked(void *user, int mid);
void gw_sfwd_lost(void *user);

/* The figures: --counters' line, /metrics (gw_metrics.c), /api/status and
 * the retained status message. */
enum gw_sfwd_fig {
	GW_SF_BUFFERED, GW_SF_DROPPED_SIZE, GW_SF_DROPPED_AGE, GW_SF_REPLAYED, GW_SF_RECORDS, GW_SF_BYTES,
	GW_SF_AGE_S, GW_SF_IN_MEMORY,
};
double gw_sfwd_figure(const struct gw *g, enum gw_sfwd_fig which);
bool gw_sfwd_on(const struct gw *g);
void gw_sfwd_counters(const struct gw *g, FILE *out);
/* {"storage":"file","buffered":..,...} */
void gw_sfwd_json(const struct gw *g, struct gw_buf *b);

#endif
