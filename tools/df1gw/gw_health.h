/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_health - how df1gw shows its health: to systemd (gw_notify: READY,
 * STATUS, WATCHDOG, RELOADING, STOPPING) and over HTTP (--http: gw_http
 * serves gw_metrics' table as Prometheus text and JSON, and gw_page's status
 * page). df1gw.c calls these at its hooks: gw_health_open in setup, the
 * descriptor and timeout in its wait, gw_health_turn once per loop turn,
 * gw_health_reloading / gw_health_stopping at SIGHUP and on the way out.
 * Everything runs on df1gw's one thread; nothing here writes to the PLC.
 */
#ifndef DF1_TOOLS_GW_HEALTH_H
#define DF1_TOOLS_GW_HEALTH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1gw/gw_notify.h"

struct gw;
struct gw_http;

/* Scan durations: upper bounds of the histogram's buckets, in seconds. */
#define GW_SCAN_BUCKETS 12

struct gw_health {
	const char *http_listen;     /* --http [ADDR:]PORT, NULL: off */
	struct gw_notify notify;
	struct gw_http *http;        /* NULL: no --http */
	int64_t start_wall_ms;       /* the process's start (wall clock) */
	int64_t start_mono_ms;       /* the same on gw_now_ms()'s clock (uptime_s of /api/status) */
	int64_t status_next_ms;      /* the next STATUS= look */
	uint64_t scans_seen;         /* df1_poll_stats scans at the last turn */
	uint64_t scan_bucket[GW_SCAN_BUCKETS];   /* cumulative counts: <= gw_scan_le[i] */
	uint64_t scan_count;
	double scan_sum_s;
	uint64_t published;          /* MQTT messages handed to the broker */
	uint64_t http_requests;      /* requests --http answered */
	/* per station: the round trip of its last answered transaction (ms), once one is known */
	int32_t reply_ms[255];
	bool reply_known[255];
	bool reloaded;               /* since the last SIGHUP: READY=1 is due again */
};

extern const double gw_scan_le[GW_SCAN_BUCKETS];   /* gw_metrics.c */

/* systemd's socket (when NOTIFY_SOCKET is set) and --http's server; says
 * where HTTP listens. 0 or the exit status, having said why. */
int gw_health_open(struct gw *g);
/* The HTTP server's descriptor to poll for POLLIN (-1: none). */
int gw_health_fd(const struct gw *g);
/* Milliseconds until gw_health_turn has work of its own (watchdog, HTTP timers). */
int gw_health_wait_ms(const struct gw *g, int64_t now);
/* Once per loop turn, after the loop's work: HTTP requests answered, the
 * scan histogram and the stations' reply times fed, READY when the line (and broker) are up, STATUS when
 * it changed, WATCHDOG when due. */
void gw_health_turn(struct gw *g, int64_t now);
/* SIGHUP: RELOADING=1 before the reload; READY=1 follows from gw_health_turn. */
void gw_health_reloading(struct gw *g);
/* On the way out: STOPPING=1. */
void gw_health_stopping(struct gw *g);
void gw_health_close(struct gw *g);
/* The one-line summary of STATUS= and the page (gw_status.c): "line ok, 3 stations ok,
 * 120 tags (2 BAD), broker connected". */
void gw_health_summary(const struct gw *g, char *out, size_t cap);

#endif
