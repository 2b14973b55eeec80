/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_format - df1gw's northbound payload formats: what a format makes (a
 * tag's message and the change key that says it changed, a station's
 * message, a write's result, the online/offline status and the broker's last
 * will, the topics, how an incoming write is parsed), the table of formats,
 * and the list of those enabled. Every enabled format publishes through the
 * same carrier (gw_mqtt.c, which knows no payload); gw_pub.c decides when.
 * Pure: no I/O, no clock.
 *
 * A new format is one file, tools/df1gw/gw_format_NAME.c defining
 * `const struct gw_format gw_format_NAME`, plus one line X(NAME) \ in
 * gw_format.c's table.
 */
#ifndef DF1_TOOLS_GW_FORMAT_H
#define DF1_TOOLS_GW_FORMAT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1.h"
#include "df1gw/gw_json.h"
#include "df1gw/gw_msg.h"
#include "df1gw/gw_state.h"

#define GW_FORMATS_MAX GW_PUB_KEYS   /* formats enabled at once: a change key each */
#define GW_WRITE_ID_MAX 128          /* bytes of a write's id as its format echoes it */

/* A tag's state as the gateway tells it (what it says beyond the library's). */
struct gw_tag_out {
	const struct df1_tag_state *st;
	const char *reason;          /* NULL: df1_reason_name() of the state's */
	int quality;                 /* -1: the state's */
	const char *error;           /* the last error in the catalog's form, or NULL */
	int64_t wall_ms;             /* now, ms since the epoch (0: not known) */
};

/* A station's health. */
struct gw_station_out {
	int station;
	const char *state;           /* "ok", "failing", "offline" (also: the line lost), "unknown" */
	const char *error;           /* the catalog's form, or NULL */
	const struct df1_station_health *sh;
	int64_t last_good_wall_ms;   /* ms since the epoch of its last good answer, 0: never */
};

/* The one result of a write. */
struct gw_result_out {
	const char *tag;
	const char *id;              /* as parsed (gw_write_in.id), "" when none */
	bool ok;
	const char *error;           /* NULL when ok */
	bool unconfirmed;            /* the PLC may have executed it (gw_write_unconfirmed) */
	const struct gw_tag_out *now; /* the tag as it is now, or NULL */
};

/* An incoming write, as its format parsed the payload. */
struct gw_write_in {
	char id[GW_WRITE_ID_MAX + 1];  /* "" when none; at most once per id */
	long timeout_ms;             /* this write's --write-timeout, <= 0: the option's */
	void *data;                  /* the format's parsed payload */
};

struct gw_fmt;

/* The line as a session format tells it (Sparkplug's node metrics). */
struct gw_line_out {
	bool up;
	const char *device;
	const struct df1_poll_stats *ps;
	unsigned generation;         /* changes when the tags change (a reload) */
	int64_t wall_ms;             /* now, ms since the epoch */
	int64_t now_ms;              /* now, monotonic ms */
	/* the line's settings as text ("Baud" "19200", ...): properties of Line/Device */
	const char *const *setting_keys;
	const char *const *setting_vals;
	size_t nsettings;
};

/* What a session format (one with births and commands: Sparkplug) sees of
 * the gateway: gw_pub.c gives it to the session ops. */
struct gw_node {
	void *user;
	int ntags;
	/* tag id's state into *st and what the gateway says of it into *t
	 * (t->st = st; err its error's room); false: no such tag */
	bool (*tag)(void *user, int id, struct df1_tag_state *st, struct gw_tag_out *t, char *err, size_t cap);
	/* station stn's health (sh its room); false: no tags on it */
	bool (*station)(void *user, int stn, struct gw_station_out *s, struct df1_station_health *sh);
	void (*line)(void *user, struct gw_line_out *l, struct df1_poll_stats *ps);
	/* m published at once, as it is (the format stamped it) */
	void (*emit)(void *user, const struct gw_fmt *f, struct gw_msg *m);
	int (*subscribe)(void *user, const char *pattern);
	/* a write a command asks for: the gateway's checks, the write queue, one
	 * result through f's result op; w is taken (write_free) */
	void (*write)(void *user, const struct gw_fmt *f, const char *tag, struct gw_write_in *w, bool retain);
	/* leave the broker cleanly and connect again (its will not sent) */
	void (*reconnect)(void *user);
	void (*log)(void *user, const char *text);
};

/* A format's counter as a metric (gw_format.figures): a name in Prometheus'
 * form ("births_total"), what it counts, and its value. */
struct gw_figure {
	const char *name, *type, *help;
	double value;
};

/* What a format does. Every function is given but open and close; a message
 * function fills all of *m (topic, body, retain) and returns 0, or -1 when it
 * has nothing to say or no memory. */
struct gw_format {
	const char *name;
	/* Its own state in f->priv (NULL: none). 0, or -1 with err. */
	int (*open)(struct gw_fmt *f, char *err, size_t errcap);
	void (*close)(struct gw_fmt *f);

	/* A tag's message, and into key (reset first) what says it changed: the
	 * message without what changes at every publication (its time). One call
	 * makes both. */
	int (*tag)(const struct gw_fmt *f, const struct gw_tag_out *t, struct gw_msg *m, struct gw_buf *key);
	/* A tag no longer configured: what removes its retained message. */
	int (*tag_gone)(const struct gw_fmt *f, const char *tag, struct gw_msg *m);
	int (*station)(const struct gw_fmt *f, const struct gw_station_out *s, struct gw_msg *m,
	               struct gw_buf *key);
	int (*result)(const struct gw_fmt *f, const struct gw_result_out *r, struct gw_msg *m);
	/* online (connected) or offline (stopping); none with --once. */
	int (*status)(const struct gw_fmt *f, bool online, struct gw_msg *m);
	/* The broker's last will, set before connecting. A connection has one:
	 * the first enabled format that makes one gives it. */
	int (*will)(const struct gw_fmt *f, struct gw_msg *m);

	/* Writes: the subscription's pattern; the tag a topic writes (false: not
	 * one of this format's write topics); the payload parsed (0, then
	 * write_free when done; or -1 with err and nothing kept); the values it
	 * asks of tag c (cur: the tag's state, may be NULL), returning 0 or
	 * DF1_E_TYPE / DF1_E_RANGE with err as gw_value_from_json() does. */
	void (*set_pattern)(const struct gw_fmt *f, char *out, size_t cap);
	bool (*set_tag)(const struct gw_fmt *f, const char *topic, char *tag, size_t cap);
	int (*write_parse)(const struct gw_fmt *f, const void *payload, size_t n, struct gw_write_in *w,
	                   char *err, size_t errcap);
	int (*write_values)(const struct gw_fmt *f, const struct gw_write_in *w, const struct df1_tag_config *c,
	                    const struct df1_tag_state *cur, struct df1_value *out, size_t cap, size_t *n,
	                    char *err, size_t errcap);
	void (*write_free)(struct gw_write_in *w);

	/* A session format (Sparkplug; NULL and false for JSON). Its messages
	 * are not republished by force (--refresh, a reconnect): it has births.
	 * set_pattern and set_tag may then be NULL. */
	bool session;
	/* Before each connect: the will of that connection into m (bdseq: its
	 * number, 0-255, counted by the gateway); -1: none. Preferred to will. */
	int (*will_next)(const struct gw_fmt *f, unsigned bdseq, struct gw_msg *m);
	/* Connected: its subscriptions, its births. */
	void (*connected)(const struct gw_fmt *f, const struct gw_node *n);
	/* After each pass of publication: what follows from the stations' and the line's state. */
	void (*tick)(const struct gw_fmt *f, const struct gw_node *n);
	/* A message: true when it was on one of its topics (then taken). */
	bool (*message)(const struct gw_fmt *f, const struct gw_node *n, const char *topic, const void *payload,
	                size_t len, bool retain);
	/* m about to be published: its last touch (Sparkplug's seq). */
	void (*stamp)(const struct gw_fmt *f, struct gw_msg *m);
	/* Its counters as one line of text (--counters) into out; -1: none. */
	int (*counters)(const struct gw_fmt *f, char *out, size_t cap);
	/* The same counters as figures for /metrics and /api/status
	 * (gw_metrics.c: df1_<format>_<name>); how many were put in out (NULL:
	 * none). */
	size_t (*figures)(const struct gw_fmt *f, struct gw_figure *out, size_t cap);

	/* Store and forward (gw_sfwd.h; NULL: none). A change buffered while
	 * the broker was away, replayed: tag t (or station s) as it was read
	 * (t->wall_ms; a station's read_ms), seq its record's number (a duplicate after a crash
	 * keeps it), as a historical message into m (JSON: not retained,
	 * "historical", "seq" and "read"; Sparkplug: DDATA, is_historical).
	 * 0, or -1 when it has nothing to say (a device not born). */
	int (*tag_historical)(const struct gw_fmt *f, const struct gw_tag_out *t, uint64_t seq, struct gw_msg *m);
	int (*station_historical)(const struct gw_fmt *f, const struct gw_station_out *s, uint64_t seq,
	                          int64_t read_ms, struct gw_msg *m);
	/* A session format: its data may go out now (born; NULL: always). */
	bool (*ready)(const struct gw_fmt *f);
};

/* An enabled format. */
struct gw_fmt {
	const struct gw_format *ops;
	const char *prefix;          /* the topic prefix (--prefix) */
	int slot;                    /* its place in the list: its change key in gw_pub */
	void *priv;                  /* the format's own state */
	const void *conf;            /* its options (gw_fmts_enable_conf), or NULL */
};

/* The formats enabled, in order. */
struct gw_fmts {
	struct gw_fmt v[GW_FORMATS_MAX];
	int n;
};

/* The format of the table named name, or NULL. */
const struct gw_format *gw_format_find(const char *name);
/* The table's i-th format (0, 1, ...), NULL past the end. */
const struct gw_format *gw_format_at(size_t i);

/* Enable the format named name with topics under prefix (kept, not copied).
 * 0, or -1 with err (unknown, enabled already, too many, its open failed). */
int gw_fmts_enable(struct gw_fmts *l, const char *name, const char *prefix, char *err, size_t errcap);
/* The same with the format's options (kept, not copied; the format knows their type). */
int gw_fmts_enable_conf(struct gw_fmts *l, const char *name, const char *prefix, const void *conf, char *err,
                        size_t errcap);
/* Enable each of names, a comma-separated list ("json"), in its order. 0, or -1 with err. */
int gw_fmts_enable_list(struct gw_fmts *l, const char *names, const char *prefix, char *err, size_t errcap);
void gw_fmts_close(struct gw_fmts *l);

/* f's message of tag t into m, its change key compared with the one last
 * published on e (one call of f->ops->tag, whose key lands in key): true when
 * m is to be published (changed, or force), the key then kept. */
bool gw_fmt_tag_changed(const struct gw_fmt *f, struct gw_pub *e, const struct gw_tag_out *t, struct gw_msg *m,
                        struct gw_buf *key, int64_t now, bool force);
/* The same for station s. */
bool gw_fmt_station_changed(const struct gw_fmt *f, struct gw_pub *e, const struct gw_station_out *s,
                            struct gw_msg *m, struct gw_buf *key, int64_t now, bool force);

#endif
