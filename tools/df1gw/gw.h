/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw - what df1gw's files share: the daemon's state (struct gw), and the
 * northbound work of gw_pub.c (publishing tags and stations, taking writes
 * from .../set) in the payload formats enabled (gw_format.h). df1gw.c owns
 * the loop, the line and the reload, gw_options.c the command line; gw_pub.c
 * never calls back into df1gw.c.
 */
#ifndef DF1_TOOLS_GW_H
#define DF1_TOOLS_GW_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "common/cli.h"
#include "df1gw/gw_eip.h"
#include "df1gw/gw_format.h"
#include "df1gw/gw_format_sparkplug.h"
#include "df1gw/gw_health.h"
#include "df1gw/gw_json.h"
#include "df1gw/gw_mqtt.h"
#include "df1gw/gw_receive.h"
#include "df1gw/gw_sfwd.h"
#include "df1gw/gw_state.h"
#include "df1gw/gw_turn.h"
#include "df1gw/gw_url.h"
#include "df1gw/gw_write.h"
#include "df1gw/gw_wqueue.h"

#define GW_PROG "df1gw"

struct gw {
	struct cli cli;

	/* options */
	const char *map_path;
	const char *mqtt_url;
	struct gw_url url;           /* mqtt_url parsed */
	const char *cafile, *cert, *keyfile;
	const char *client_id_opt, *username, *password_file, *prefix_opt;
	int qos;
	int keepalive_s;
	int refresh_s;
	int watchdog_ms;
	bool once;
	bool counters;               /* --counters */
	struct gw_eip eip;           /* --eip (listen NULL: off) */

	char client_id[320];
	char prefix[400];
	char *password;

	/* the line: h is configured (cli_configure) with the tags loaded; open
	 * or not. While it is closed its tags are published BAD, line_error. */
	df1_t *h;
	bool line_up;
	bool line_ever_up;
	char line_error[640];
	int line_backoff_ms;
	int64_t line_next_try_ms;
	int64_t line_opened_ms;      /* monotonic ms of the last df1_open */
	int64_t line_down_ms;        /* since when it is lost or cannot be opened */
	bool stations[255];          /* stations that have tags */
	unsigned char *dirty;        /* per tag id: changed since published */
	int ntags;
	int *pub_of;                 /* per tag id: index in pubs */

	struct gw_fmts fmts;         /* the payload formats, each publishing through mq */
	struct gw_mqtt mq;
	bool mq_configured;
	struct gw_msg will;          /* the last will, as the first format with one makes it */
	struct gw_pubs pubs;         /* tag/<name> and station/<n>: their change keys */
	struct gw_ids ids;
	struct gw_msg msg;           /* the message being made */
	struct gw_buf key;           /* its change key */
	bool republish;              /* everything, at the next chance (connected, line change) */
	int64_t next_refresh_ms;
	unsigned writes_pending;     /* handed to the line (df1_tag_write), not ended yet */

	/* Sparkplug B (--sparkplug; df1gw(1) SPARKPLUG) */
	struct gw_spb_conf spb;
	bool json_off;               /* --json no: Sparkplug alone */
	const char *spb_state_path;  /* the bdSeq file (--sparkplug-state, or spb_state_auto); NULL: not kept */
	char spb_state_auto[4096];   /* the default one, in the state folder (gw_bdseq.h) */
	bool spb_state_mkdir;        /* its folder is to be made before the first write */
	unsigned bdseq_next;         /* the bdSeq of the next connect */
	unsigned generation;         /* the tags' configuration: a reload changes it */

	/* the write policy (gw_wqueue.h; df1gw(1), WRITE POLICY) */
	enum gw_wopt write_optimize; /* --write-optimize */
	int duty_cycle;              /* --duty-cycle: writes per batch, and before a due read */
	int write_timeout_ms;        /* --write-timeout */
	int max_pending;             /* --max-pending-writes */
	struct gw_wq wq;             /* waiting writes; its counters are the write side's */
	unsigned writes_since_read;  /* handed to the line since the poll engine last read */
	uint64_t reads_seen;         /* the engine's reads + probes when last looked at */
	enum gw_turn turn_last;      /* whose turn the line gave last: the bridge's or the writes' */
	bool in_line_work;           /* inside df1_poll (line_tick serves the bridge too) */
	struct gw_outbox outbox;     /* results that fell while the broker was away */

	/* Receive rows: df1gw's own data table on the line (gw_receive.h) */
	struct gw_rx rx;

	/* systemd notifications and --http (gw_health.h) */
	struct gw_health health;

	/* store and forward: --buffer, --buffer-max, --buffer-max-age, --replay-rate (gw_sfwd.h) */
	struct gw_sfwd sfwd;
};

/* The command line into g (gw_options.c): CLI_CONTINUE or the exit status,
 * having said why. */
int gw_options_parse(struct gw *g, int argc, char **argv);
/* df1gw.c: g (zeroed) made from the command line, up to its loop: the line built (not opened), the broker's
 * client made (not connected), the listeners open. CLI_CONTINUE or the exit
 * status, having said why. gw_shutdown() ends what it made, also after a
 * failure. The HTTP fuzz target (tests/fuzz/fuzz_http.c) sets a gateway up
 * with them. */
int gw_setup(struct gw *g, int argc, char **argv);
void gw_shutdown(struct gw *g);

/* Monotonic and wall-clock milliseconds. */
int64_t gw_now_ms(void);
int64_t gw_wall_ms(void);

/* Publish what changed: dirty tags, station health; all when force (or
 * g->republish). Nothing while the broker is down. */
void gw_publish_changes(struct gw *g, bool force);
/* A tag removed (its entry, not live): what each format that published it
 * says for that (JSON: its retained topic cleared). */
void gw_publish_gone(struct gw *g, const struct gw_pub *e);
/* Stopping: each format's offline status (not printed with -v). */
void gw_publish_offline(struct gw *g);
/* The tag callback of df1_set_tag_callback: marks the tag dirty. */
void gw_on_tag(void *user, int id, const struct df1_tag_state *st);
/* A message on a format's write topics, <prefix>/tag/+/set for JSON, or on
 * a session format's own (Sparkplug's NCMD, DCMD, STATE) (gw_mqtt_events.message). */
void gw_on_message(void *user, const char *topic, const void *payload, int len, bool retain);
/* Connected (again): status online, subscribe, republish everything; a
 * session format's births. */
void gw_on_connected(void *user);
/* Before each connect (gw_mqtt_events.connecting): a session format's will
 * with the next bdSeq, written first to the bdSeq file (gw_bdseq.h). */
void gw_on_connecting(void *user);
/* The bdSeq of the first connect: one more than the bdSeq file's (--sparkplug-state, else the
 * state folder's, gw_bdseq.h; 0 without one), having said once why a file cannot be used. */
void gw_bdseq_load(struct gw *g);
/* --counters: each format's own line. */
void gw_publish_counters(const struct gw *g, FILE *out);
/* The line's turns (gw_turn.h): the bridge's waiting requests and the MQTT
 * writes (a batch of at most --duty-cycle, not while a due poll read has
 * waited behind as many) handed to the line in turn; what expired answered.
 * Once per turn of the loop, and from inside the line's work (in_line: the
 * bridge's requests only, no batch starts there). */
void gw_line_turns(struct gw *g, int64_t now, bool in_line);
/* The queue made from the options (gw_wqueue.h). 0, or -1 (no memory). */
int gw_writes_init(struct gw *g);
/* The line is gone (or replaced): every waiting write is answered "not written". */
void gw_writes_drop(struct gw *g);
/* --counters: the write side's line. */
void gw_writes_counters(const struct gw *g, FILE *out);
/* A tag's configuration as one line of text (a reload compares them). */
void gw_tag_config_text(const struct df1_tag_config *c, char *out, size_t cap);

#endif
