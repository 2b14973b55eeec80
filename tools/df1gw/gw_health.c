/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_health - df1gw's hooks for systemd and --http (gw_health.h): when READY
 * is true, what STATUS says, when the watchdog is pinged, the scan
 * histogram, the HTTP server's place in the loop.
 */
#include "df1gw/gw_health.h"

#include <stdio.h>
#include <string.h>

#include "df1gw/gw.h"
#include "df1gw/gw_http.h"

#define STATUS_EVERY_MS 1000     /* STATUS= looked at (and sent if changed) at most this often */

int gw_health_open(struct gw *g)
{
	struct gw_health *h = &g->health;
	char err[256];

	h->start_wall_ms = gw_wall_ms();
	h->start_mono_ms = gw_now_ms();
	if (gw_notify_open(&h->notify, gw_now_ms(), err, sizeof err) < 0)
		fprintf(stderr, "%s: %s (no readiness or watchdog notifications)\n", GW_PROG, err);
	if (!h->http_listen)
		return 0;
	if (gw_http_open(&h->http, h->http_listen, g, &h->http_requests, err, sizeof err) < 0) {
		fprintf(stderr, "%s: --http %s: %s\n", GW_PROG, h->http_listen, err);
		return CLI_EXIT_USAGE;
	}
	if (!gw_http_loopback(h->http))
		fprintf(stderr, "%s: HTTP on %s: listening on a network, reachable from other hosts (read-only, "
		        "no authentication: the tags, stations and counters are visible to anyone who can reach it)\n",
		        GW_PROG, gw_http_address(h->http));
	else if (!g->cli.quiet)
		fprintf(stderr, "%s: HTTP on %s (loopback only, read-only)\n", GW_PROG, gw_http_address(h->http));
	return 0;
}

int gw_health_fd(const struct gw *g)
{
	return gw_http_fd(g->health.http);
}

int gw_health_wait_ms(const struct gw *g, int64_t now)
{
	int a = gw_notify_wait_ms(&g->health.notify, now), b = gw_http_wait_ms(g->health.http);

	return a < b ? a : b;
}

/* Scans completed since the last turn, each counted with the last one's
 * duration (the loop runs df1_poll once a turn: one scan at most, as a rule). */
static void scan_sample(struct gw *g)
{
	struct gw_health *h = &g->health;
	struct df1_poll_stats ps;
	double s;

	if (!g->h || df1_poll_stats(g->h, &ps) < 0)
		return;
	if (ps.scans < h->scans_seen)
		h->scans_seen = 0;      /* a reload: a new handle counts from 0 */
	s = ps.last_scan_ms / 1000.0;
	for (; h->scans_seen < ps.scans; h->scans_seen++) {
		for (int i = 0; i < GW_SCAN_BUCKETS; i++)
			h->scan_bucket[i] += s <= gw_scan_le[i];
		h->scan_count++;
		h->scan_sum_s += s;
	}
}

/* Each station's last reply time: a transaction's attempt and answer are
 * stamped before and after it (lib/poll/health.c), and df1_poll returns
 * between transactions, so an answer not older than the attempt is the
 * last attempt's round trip. A failed attempt keeps the last one known. */
static void reply_sample(struct gw *g)
{
	struct gw_health *h = &g->health;

	for (int stn = 0; stn < 255 && g->h && g->line_up; stn++) {
		struct df1_station_health sh;

		if (!g->stations[stn] || df1_station_health(g->h, stn, &sh) < 0)
			continue;
		if (sh.last_good_ms && sh.last_attempt_ms && sh.last_good_ms >= sh.last_attempt_ms &&
		    sh.last_good_ms - sh.last_attempt_ms < INT32_MAX) {
			h->reply_ms[stn] = (int32_t)(sh.last_good_ms - sh.last_attempt_ms);
			h->reply_known[stn] = true;
		}
	}
}

/* READY: the line open with its first scan done, and the broker connected
 * when there is one; after a reload also when the line could not be opened
 * again (the reload is over; STATUS says what is wrong). */
static bool is_ready(const struct gw *g)
{
	struct df1_poll_stats ps;

	if (!g->line_up)
		return g->health.reloaded;
	if (g->mq_configured && !gw_mqtt_up(&g->mq))
		return false;
	if (!g->map_path || g->ntags == 0)
		return true;
	return df1_poll_stats(g->h, &ps) == 0 && ps.scans > 0;
}

void gw_health_turn(struct gw *g, int64_t now)
{
	struct gw_health *h = &g->health;

	gw_http_run(h->http);
	scan_sample(g);
	reply_sample(g);
	if (!gw_notify_on(&h->notify))
		return;
	if (now >= h->status_next_ms || !h->notify.ready) {
		char text[sizeof h->notify.status];

		gw_health_summary(g, text, sizeof text);
		gw_notify_status(&h->notify, text);
		h->status_next_ms = now + STATUS_EVERY_MS;
	}
	if (!h->notify.ready && is_ready(g)) {
		gw_notify_ready(&h->notify);
		h->reloaded = false;
	}
	gw_notify_tick(&h->notify, now);
}

void gw_health_reloading(struct gw *g)
{
	gw_notify_reloading(&g->health.notify);
	g->health.reloaded = true;
}

void gw_health_stopping(struct gw *g)
{
	gw_notify_send(&g->health.notify, "STOPPING=1");
}

void gw_health_close(struct gw *g)
{
	gw_http_close(g->health.http);
	g->health.http = NULL;
	gw_notify_close(&g->health.notify);
}
