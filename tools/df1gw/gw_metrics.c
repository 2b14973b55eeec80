/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_metrics - the table of df1gw's metrics, written through gw_msink.c
 * (gw_metrics.h). Names follow Prometheus' conventions: df1_ prefix, base
 * units in the name (_seconds), _total for counters, an enum as one 0/1
 * sample per state, the version as a _info gauge of 1.
 *
 * A new figure is one line of GW_SCALARS (a value of struct gw, the poll
 * engine's stats ps or the EtherNet/IP server's es, and when it exists), or,
 * for a family with labels, one function in gw_families[] (doc/HACKING.md 5.6).
 */
#include "df1gw/gw_metrics.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "df1gw/gw.h"

/* ---- what the table reads ---- */

/* Scan durations' buckets (seconds): a fast line scans in tens of ms, a slow
 * multi-drop one in seconds. */
const double gw_scan_le[GW_SCAN_BUCKETS] = { 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30 };


struct gw_mctx {
	const struct gw *g;
	struct df1_poll_stats ps;
	struct df1_eip_server_stats es;
	bool line, broker, eip;      /* a handle with a line; --mqtt; --eip */
};

/* name, type, help, when it exists, value: one line per figure. */
#define GW_SCALARS(X) \
	X(df1_line_up, "gauge", "1 when the DF1 line is open", true, g->line_up) \
	X(df1_scans_total, "counter", "scans of the tags completed", c->line, ps->scans) \
	X(df1_scan_last_seconds, "gauge", "duration of the last scan", c->line, ps->last_scan_ms / 1000.0) \
	X(df1_transactions_total, "counter", "transactions on the line: reads, probes, writes", c->line, \
	  ps->transactions) \
	X(df1_reads_total, "counter", "block reads, retries included", c->line, ps->reads) \
	X(df1_read_failures_total, "counter", "block reads that failed", c->line, ps->read_failures) \
	X(df1_probes_total, "counter", "probes of offline stations", c->line, ps->probes) \
	X(df1_probe_failures_total, "counter", "probes not answered", c->line, ps->probe_failures) \
	X(df1_writes_total, "counter", "writes sent to the PLC", c->line, ps->writes) \
	X(df1_write_failures_total, "counter", "writes that failed", c->line, ps->write_failures) \
	X(df1_retries_total, "counter", "retries of a station that answered", c->line, ps->retries) \
	X(df1_block_splits_total, "counter", "block reads split after an address error", c->line, ps->splits) \
	X(df1_scan_blocks, "gauge", "block reads in a full scan", c->line, ps->blocks) \
	X(df1_stations_offline, "gauge", "stations whose watchdog expired", c->line, ps->stations_offline) \
	X(df1_write_queue_depth, "gauge", "writes queued for the line", c->line, ps->writes_queued) \
	X(df1_mqtt_writes_pending, "gauge", "writes from MQTT waiting for their result", c->broker, \
	  g->writes_pending) \
	X(df1_mqtt_writes_received_total, "counter", "writes taken from MQTT (/set, DCMD)", c->broker, \
	  g->wq.c.received) \
	X(df1_mqtt_writes_refused_total, "counter", "writes answered at once: invalid, read-only, line down", \
	  c->broker, g->wq.c.refused) \
	X(df1_mqtt_writes_written_total, "counter", "writes the PLC took", c->broker, g->wq.c.written) \
	X(df1_mqtt_writes_failed_total, "counter", "writes handed to the line that failed", c->broker, \
	  g->wq.c.failed) \
	X(df1_mqtt_writes_superseded_total, "counter", "writes replaced by a later one (--write-optimize)", \
	  c->broker, g->wq.c.superseded) \
	X(df1_mqtt_writes_expired_total, "counter", "writes not started within their timeout", c->broker, \
	  g->wq.c.expired) \
	X(df1_mqtt_writes_busy_total, "counter", "writes refused: --max-pending-writes reached", c->broker, \
	  g->wq.c.refused_busy) \
	X(df1_mqtt_writes_dropped_total, "counter", "writes waiting when the line went away", c->broker, \
	  g->wq.c.dropped) \
	X(df1_mqtt_writes_waiting, "gauge", "writes waiting for the line (the write policy's queue)", c->broker, \
	  g->wq.c.depth) \
	X(df1_mqtt_writes_waiting_max, "gauge", "the most writes ever waiting", c->broker, g->wq.c.high_water) \
	X(df1_mqtt_connected, "gauge", "1 when the MQTT broker accepted the connection", c->broker, \
	  gw_mqtt_up(&g->mq)) \
	X(df1_mqtt_publications_total, "counter", "MQTT messages handed to the broker", c->broker, \
	  g->health.published) \
	X(df1_mqtt_inflight, "gauge", "QoS 1 publications not acknowledged yet", c->broker, g->mq.inflight) \
	X(df1_eip_sessions_total, "counter", "EtherNet/IP sessions registered", c->eip, es->sessions) \
	X(df1_eip_sessions_open, "gauge", "EtherNet/IP sessions registered now", c->eip, es->sessions_open) \
	X(df1_eip_requests_total, "counter", "EtherNet/IP encapsulation messages received", c->eip, \
	  es->requests) \
	X(df1_eip_errors_total, "counter", "EtherNet/IP replies with an error status", c->eip, es->errors) \
	X(df1_eip_refused_clients_total, "counter", "EtherNet/IP clients refused", c->eip, \
	  es->refused_clients) \
	X(df1_eip_forwarded_total, "counter", "PCCC requests forwarded to the line", c->eip, \
	  g->eip.forwarded) \
	X(df1_eip_no_answer_total, "counter", "PCCC requests the controller did not answer", c->eip, \
	  g->eip.no_answer) \
	X(df1_eip_busy_total, "counter", "PCCC requests refused: the line's queue was full", c->eip, \
	  g->eip.busy) \
	X(df1_buffer_records_total, "counter", "changes stored while the broker was away (store and forward)", \
	  gw_sfwd_on(g), gw_sfwd_figure(g, GW_SF_BUFFERED)) \
	X(df1_buffer_dropped_size_total, "counter", "stored changes dropped by --buffer-max, oldest first", \
	  gw_sfwd_on(g), gw_sfwd_figure(g, GW_SF_DROPPED_SIZE)) \
	X(df1_buffer_dropped_age_total, "counter", "stored changes dropped by --buffer-max-age", gw_sfwd_on(g), \
	  gw_sfwd_figure(g, GW_SF_DROPPED_AGE)) \
	X(df1_buffer_replayed_total, "counter", "stored changes replayed and acknowledged by the broker", \
	  gw_sfwd_on(g), gw_sfwd_figure(g, GW_SF_REPLAYED)) \
	X(df1_buffer_backlog_records, "gauge", "stored changes not yet acknowledged", gw_sfwd_on(g), \
	  gw_sfwd_figure(g, GW_SF_RECORDS)) \
	X(df1_buffer_backlog_bytes, "gauge", "their size as --buffer-max counts it", gw_sfwd_on(g), \
	  gw_sfwd_figure(g, GW_SF_BYTES)) \
	X(df1_buffer_backlog_age_seconds, "gauge", "age of the oldest stored change (0: none)", gw_sfwd_on(g), \
	  gw_sfwd_figure(g, GW_SF_AGE_S)) \
	X(df1_buffer_in_memory, "gauge", "1 when the buffer is in memory (no --buffer, or its file failed)", \
	  gw_sfwd_on(g), gw_sfwd_figure(g, GW_SF_IN_MEMORY)) \
	X(df1_http_requests_total, "counter", "HTTP requests answered (--http)", g->health.http, \
	  g->health.http_requests) \
	X(df1_process_start_time_seconds, "gauge", "start time of the process since the epoch", true, \
	  g->health.start_wall_ms / 1000.0)

static void scalars(const struct gw_mctx *c, struct gw_msink *s)
{
	const struct gw *g = c->g;
	const struct df1_poll_stats *ps = &c->ps;
	const struct df1_eip_server_stats *es = &c->es;

	(void)g, (void)ps, (void)es;
#define GW_SCALAR_EMIT(name, type, help, when, value) \
	if (when) { \
		gw_msink_family(s, #name, type, help); \
		gw_msink_sample(s, #name, NULL, (double)(value)); \
	}
	GW_SCALARS(GW_SCALAR_EMIT)
#undef GW_SCALAR_EMIT
}

/* ---- families with labels ---- */

static void build_info(const struct gw_mctx *c, struct gw_msink *s)
{
	const struct df1_version *v = df1_version();
	const char *l[] = { "version", DF1_VERSION_STRING, "library", v->string, NULL };

	(void)c;
	gw_msink_family(s, "df1_build_info", "gauge", "df1gw's version and the library's, as labels");
	gw_msink_sample(s, "df1_build_info", l, 1);
}

/* The line's catalog counters (doc/REQUIREMENTS.md 004): one family each,
 * named by its mnemonic, its ID a label. */
static void catalog(const struct gw_mctx *c, struct gw_msink *s)
{
	const struct df1_catalog_entry *e;

	if (!c->g->h)
		return;
	for (size_t i = 0; (e = df1_catalog_at(i)) != NULL; i++) {
		char name[80], help[160], id[12];
		const char *l[] = { "id", id, NULL };
		uint64_t v = 0;

		if (e->severity != DF1_SEV_COUNTER || df1_counter(c->g->h, e->id, &v) < 0)
			continue;
		cli_counter_metric_name(e, name, sizeof name);
		snprintf(help, sizeof help, "[%d] %s: %s", e->id, e->mnemonic, e->description ? e->description : "");
		snprintf(id, sizeof id, "%d", e->id);
		gw_msink_family(s, name, "counter", help);
		gw_msink_sample(s, name, l, (double)v);
	}
}

static const enum df1_station_state station_states[] = {
	DF1_STATION_UNKNOWN, DF1_STATION_OK, DF1_STATION_FAILING, DF1_STATION_OFFLINE,
};

/* Per station with tags: state (one sample per state), attempts, failures,
 * consecutive failures, the age of its last answer. */
static void stations(const struct gw_mctx *c, struct gw_msink *s)
{
	static const char *const fam[][3] = {
		{ "df1_station_state", "gauge", "the station's state: 1 for the one it is in" },
		{ "df1_station_attempts_total", "counter", "transactions to the station" },
		{ "df1_station_failures_total", "counter", "transactions to the station that failed" },
		{ "df1_station_consecutive_failures", "gauge", "failures since its last answer" },
		{ "df1_station_last_answer_age_seconds", "gauge", "time since its last answer (NaN: never)" },
		{ "df1_station_last_reply_seconds", "gauge",
		  "round trip of its last answered transaction (NaN: none yet)" },
	};
	int64_t now = gw_now_ms();

	if (!c->line)
		return;
	for (size_t f = 0; f < sizeof fam / sizeof fam[0]; f++) {
		gw_msink_family(s, fam[f][0], fam[f][1], fam[f][2]);
		for (int stn = 0; stn < 255; stn++) {
			struct df1_station_health sh;
			char num[12];                  /* an int's text, whatever the compiler knows of stn */
			const char *l[] = { "station", num, NULL, NULL, NULL };

			if (!c->g->stations[stn] || df1_station_health(c->g->h, stn, &sh) < 0)
				continue;
			snprintf(num, sizeof num, "%d", stn);
			if (!c->g->line_up && sh.state == DF1_STATION_OK)
				sh.state = DF1_STATION_OFFLINE;         /* the line lost: nobody answers */
			switch (f) {
			case 0:
				l[2] = "state";
				for (size_t k = 0; k < sizeof station_states / sizeof station_states[0]; k++) {
					l[3] = df1_station_state_name(station_states[k]);
					gw_msink_sample(s, fam[f][0], l, sh.state == station_states[k]);
				}
				break;
			case 1: gw_msink_sample(s, fam[f][0], l, (double)sh.attempts); break;
			case 2: gw_msink_sample(s, fam[f][0], l, (double)sh.failures); break;
			case 3: gw_msink_sample(s, fam[f][0], l, sh.consecutive_failures); break;
			case 4:
				gw_msink_sample(s, fam[f][0], l, sh.last_good_ms ? (now - sh.last_good_ms) / 1000.0 : NAN);
				break;
			default:
				gw_msink_sample(s, fam[f][0], l, c->g->health.reply_known[stn] ?
				                c->g->health.reply_ms[stn] / 1000.0 : NAN);
				break;
			}
		}
	}
}

/* How many readable tags are GOOD, UNCERTAIN, BAD (all BAD while the line is lost). */
static void tag_qualities(const struct gw_mctx *c, struct gw_msink *s)
{
	static const enum df1_quality q[] = { DF1_QUALITY_GOOD, DF1_QUALITY_UNCERTAIN, DF1_QUALITY_BAD };
	unsigned n[3] = { 0 };

	if (!c->g->h || !c->g->map_path)
		return;
	for (int id = 0; id < c->g->ntags; id++) {
		struct df1_tag_state st;

		if (df1_tag_get(c->g->h, id, &st) < 0 || !(st.config->access & DF1_ACCESS_READ))
			continue;
		for (int k = 0; k < 3; k++)
			n[k] += (c->g->line_up ? st.quality : DF1_QUALITY_BAD) == q[k];
	}
	gw_msink_family(s, "df1_tags", "gauge", "readable tags by quality");
	for (int k = 0; k < 3; k++) {
		const char *l[] = { "quality", df1_quality_name(q[k]), NULL };

		gw_msink_sample(s, "df1_tags", l, n[k]);
	}
}

static void scan_histogram(const struct gw_mctx *c, struct gw_msink *s)
{
	const struct gw_health *h = &c->g->health;
	char le[24];
	const char *l[] = { "le", le, NULL };

	if (!c->line)
		return;
	gw_msink_family(s, "df1_scan_duration_seconds", "histogram", "durations of the scans");
	for (int i = 0; i < GW_SCAN_BUCKETS; i++) {
		snprintf(le, sizeof le, "%g", gw_scan_le[i]);
		gw_msink_sample(s, "df1_scan_duration_seconds_bucket", l, (double)h->scan_bucket[i]);
	}
	snprintf(le, sizeof le, "+Inf");
	gw_msink_sample(s, "df1_scan_duration_seconds_bucket", l, (double)h->scan_count);
	gw_msink_sample(s, "df1_scan_duration_seconds_sum", NULL, h->scan_sum_s);
	gw_msink_sample(s, "df1_scan_duration_seconds_count", NULL, (double)h->scan_count);
}

/* Each payload format's own counters (gw_format.figures): df1_<format>_<name>. */
static void format_figures(const struct gw_mctx *c, struct gw_msink *s)
{
	const struct gw *g = c->g;

	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];
		struct gw_figure v[16];
		size_t n = f->ops->figures ? f->ops->figures(f, v, sizeof v / sizeof v[0]) : 0;

		for (size_t k = 0; k < n; k++) {
			char name[96];

			snprintf(name, sizeof name, "df1_%s_%s", f->ops->name, v[k].name);
			gw_msink_family(s, name, v[k].type, v[k].help);
			gw_msink_sample(s, name, NULL, v[k].value);
		}
	}
}

/* The families with labels, in the order written. */
static void (*const gw_families[])(const struct gw_mctx *, struct gw_msink *) = {
	build_info,
	catalog,
	stations,
	tag_qualities,
	scan_histogram,
	format_figures,
};

void gw_metrics_write(const struct gw *g, struct gw_buf *b, bool json)
{
	struct gw_mctx c = { .g = g };
	struct gw_msink s = { .b = b, .json = json };

	c.line = g->h != NULL && df1_poll_stats(g->h, &c.ps) == 0;
	c.broker = g->mq_configured;
	c.eip = g->eip.s != NULL;
	if (c.eip)
		df1_eip_server_stats(g->eip.s, &c.es);
	for (size_t i = 0; i < sizeof gw_families / sizeof gw_families[0]; i++)
		gw_families[i](&c, &s);
	scalars(&c, &s);
	gw_msink_end(&s);
}
