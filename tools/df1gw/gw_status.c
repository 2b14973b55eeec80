/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_status - /api/status: what the status page shows, as JSON
 * (gw_metrics.h), and the summary line STATUS= sends (gw_health.h): the
 * summary line, the uptime and scans (the page's charts take rates from
 * them), the line's settings, state and port note, each
 * station, each tag (its payload as gw_value.c makes it, with its name and
 * age), the broker, EtherNet/IP, and the metrics table. Strings go through
 * gw_json_text, so a tag name with markup in it stays text to the page.
 */
#include "df1gw/gw_metrics.h"

#include <stdio.h>
#include <string.h>

#include "df1gw/gw.h"
#include "df1gw/gw_value.h"

static void jstr(struct gw_buf *b, const char *key, const char *s)
{
	gw_buf_printf(b, "\"%s\":", key);
	if (s)
		gw_json_text(b, s, strlen(s));
	else
		gw_buf_puts(b, "null");
}

static void err_text(int err, char *out, size_t cap)
{
	char tag[64];

	cli_error_tag(err, df1_error_catalog_id(err), tag, sizeof tag);
	snprintf(out, cap, "%s: %s", tag, df1_strerror(err));
}

static void line_json(const struct gw *g, struct gw_buf *b)
{
	const struct cli *c = &g->cli;
	char framing[16];

	snprintf(framing, sizeof framing, "%d%c%d", c->data_bits, c->parity, c->stop_bits);
	gw_buf_puts(b, "\"line\":{");
	jstr(b, "device", c->device);
	gw_buf_printf(b, ",\"up\":%s,", g->line_up ? "true" : "false");
	jstr(b, "error", g->line_error[0] ? g->line_error : NULL);
	gw_buf_printf(b, ",\"baud\":%d,", c->baud);
	jstr(b, "framing", framing);
	gw_buf_printf(b, ",\"duplex\":\"%s\",\"check\":\"%s\",\"timeout_ms\":%d,\"network_file\":%s,",
	              c->radio ? "radio" : c->half_duplex ? "half" : "full", c->check == DF1_CHECK_BCC ? "BCC" : "CRC", c->timeout_ms,
	              c->net_file ? "true" : "false");
	/* what the library noticed when it opened the port (a USB adapter's
	 * latency timer it could not lower: libdf1(7) USB ADAPTERS), or null */
	jstr(b, "port_note", g->h && *df1_port_note(g->h) ? df1_port_note(g->h) : NULL);
	gw_buf_puts(b, "}");
}

static void stations_json(const struct gw *g, struct gw_buf *b)
{
	int64_t now = gw_now_ms();
	int n = 0;

	gw_buf_puts(b, "\"stations\":[");
	for (int stn = 0; stn < 255 && g->h; stn++) {
		struct df1_station_health sh;
		char err[160];

		if (!g->stations[stn] || df1_station_health(g->h, stn, &sh) < 0)
			continue;
		gw_buf_printf(b, "%s{\"station\":%d,", n++ ? "," : "", stn);
		jstr(b, "state", g->line_up ? df1_station_state_name(sh.state) : "offline");
		gw_buf_printf(b, ",\"tags\":%d,\"attempts\":%llu,\"failures\":%llu,\"consecutive_failures\":%d,", sh.tags,
		              (unsigned long long)sh.attempts, (unsigned long long)sh.failures, sh.consecutive_failures);
		if (sh.last_error)
			err_text(sh.last_error, err, sizeof err);
		jstr(b, "last_error", sh.last_error ? err : NULL);
		if (g->health.reply_known[stn])
			gw_buf_printf(b, ",\"last_reply_ms\":%d", (int)g->health.reply_ms[stn]);
		else
			gw_buf_puts(b, ",\"last_reply_ms\":null");
		if (sh.last_good_ms)
			gw_buf_printf(b, ",\"last_answer_age_s\":%.3f}", (now - sh.last_good_ms) / 1000.0);
		else
			gw_buf_puts(b, ",\"last_answer_age_s\":null}");
	}
	gw_buf_puts(b, "]");
}

/* One tag: {"name":..,"age_s":..,<its payload's members>}. */
static void tag_json(const struct gw *g, const struct df1_tag_state *st, struct gw_buf *b, struct gw_buf *tmp)
{
	struct gw_tag_view v = { NULL, -1, NULL, true };
	char err[160];

	if (!(st->config->access & DF1_ACCESS_READ)) {
		v.reason = "write_only";
	} else if (!g->line_up) {
		v.quality = DF1_QUALITY_BAD;
		v.reason = "line_lost";
		v.error = g->line_error[0] ? g->line_error : NULL;
	} else if (st->quality != DF1_QUALITY_GOOD && st->last_error) {
		err_text(st->last_error, err, sizeof err);
		v.error = err;
	}
	gw_buf_reset(tmp);
	gw_tag_json(tmp, st, &v);
	gw_buf_puts(b, "{");
	jstr(b, "name", st->config->name);
	if (st->age_ms >= 0)
		gw_buf_printf(b, ",\"age_s\":%.3f,", st->age_ms / 1000.0);
	else
		gw_buf_puts(b, ",\"age_s\":null,");
	if (tmp->p && tmp->len > 1)
		gw_buf_add(b, tmp->p + 1, tmp->len - 1);
	else
		gw_buf_puts(b, "\"value\":null}");
}

static void tags_json(const struct gw *g, struct gw_buf *b)
{
	struct gw_buf tmp;
	int n = 0;

	gw_buf_init(&tmp);
	gw_buf_puts(b, "\"tags\":[");
	for (int id = 0; id < g->ntags && g->h && g->map_path; id++) {
		struct df1_tag_state st;

		if (df1_tag_get(g->h, id, &st) < 0)
			continue;
		if (n++)
			gw_buf_puts(b, ",");
		tag_json(g, &st, b, &tmp);
	}
	gw_buf_puts(b, "]");
	gw_buf_free(&tmp);
}

static void broker_json(const struct gw *g, struct gw_buf *b)
{
	static const char *const state[] = { "down", "connecting", "connected" };

	if (!g->mq_configured) {
		gw_buf_puts(b, "\"broker\":null");
		return;
	}
	gw_buf_puts(b, "\"broker\":{");
	jstr(b, "url", g->mqtt_url);
	gw_buf_puts(b, ",");
	jstr(b, "prefix", g->prefix);
	gw_buf_puts(b, ",");
	jstr(b, "state", state[g->mq.state]);
	gw_buf_puts(b, ",");
	jstr(b, "refused", g->mq.refused ? g->mq.refused_text : NULL);
	gw_buf_printf(b, ",\"publications\":%llu,\"inflight\":%u}", (unsigned long long)g->health.published,
	              g->mq.inflight);
}

static void eip_json(const struct gw *g, struct gw_buf *b)
{
	struct df1_eip_server_stats es;

	if (!g->eip.s) {
		gw_buf_puts(b, "\"eip\":null");
		return;
	}
	df1_eip_server_stats(g->eip.s, &es);
	gw_buf_puts(b, "\"eip\":{");
	jstr(b, "address", df1_eip_server_address(g->eip.s));
	gw_buf_printf(b, ",\"sessions_open\":%llu,\"sessions\":%llu,\"requests\":%llu,\"forwarded\":%llu,"
	              "\"no_answer\":%llu,\"read_only\":%s}", (unsigned long long)es.sessions_open,
	              (unsigned long long)es.sessions, (unsigned long long)es.requests,
	              (unsigned long long)g->eip.forwarded, (unsigned long long)g->eip.no_answer,
	              g->eip.opts.read_only ? "true" : "false");
}

/* The summary of STATUS= and the page (gw_health.h). */
void gw_health_summary(const struct gw *g, char *out, size_t cap)
{
	int stations = 0, ok = 0, tags = 0, bad = 0;
	size_t len;

	for (int stn = 0; stn < 255 && g->h; stn++) {
		struct df1_station_health sh;

		if (!g->stations[stn] || df1_station_health(g->h, stn, &sh) < 0)
			continue;
		stations++;
		ok += g->line_up && sh.state == DF1_STATION_OK;
	}
	for (int id = 0; id < g->ntags && g->h && g->map_path; id++) {
		struct df1_tag_state st;

		if (df1_tag_get(g->h, id, &st) < 0 || !(st.config->access & DF1_ACCESS_READ))
			continue;
		tags++;
		bad += !g->line_up || st.quality == DF1_QUALITY_BAD;
	}
	if (g->line_up)
		len = (size_t)snprintf(out, cap, "line ok");
	else
		len = (size_t)snprintf(out, cap, "line down (%s)", g->line_error[0] ? g->line_error : "not open yet");
	if (len < cap && stations)
		len += ok == stations ? (size_t)snprintf(out + len, cap - len, ", %d station%s ok", ok, ok == 1 ? "" : "s")
		                      : (size_t)snprintf(out + len, cap - len, ", %d of %d stations ok", ok, stations);
	if (len < cap && g->map_path)
		len += (size_t)snprintf(out + len, cap - len, ", %d tag%s (%d BAD)", tags, tags == 1 ? "" : "s", bad);
	if (len < cap && g->mq_configured)
		len += (size_t)snprintf(out + len, cap - len, ", broker %s",
		                        gw_mqtt_up(&g->mq) ? "connected" : g->mq.state == GW_MQTT_CONNECTING ?
		                        "connecting" : "down");
	if (len < cap && g->eip.s) {
		struct df1_eip_server_stats es;

		df1_eip_server_stats(g->eip.s, &es);
		len += (size_t)snprintf(out + len, cap - len, ", EtherNet/IP %llu session%s",
		                        (unsigned long long)es.sessions_open, es.sessions_open == 1 ? "" : "s");
	}
	/* the port's note last (it is long: the sysfs file and the udev rule) */
	if (len < cap && g->line_up && g->h && *df1_port_note(g->h))
		snprintf(out + len, cap - len, "; %s", df1_port_note(g->h));
}

void gw_status_json(const struct gw *g, struct gw_buf *b)
{
	char text[1536], ts[32];        /* the summary with a port note in full */

	gw_health_summary(g, text, sizeof text);
	gw_buf_puts(b, "{");
	jstr(b, "summary", text);
	gw_buf_puts(b, ",");
	jstr(b, "version", DF1_VERSION_STRING);
	gw_rfc3339(g->health.start_wall_ms, ts, sizeof ts);
	gw_buf_puts(b, ",");
	jstr(b, "start_time", ts);
	gw_rfc3339(gw_wall_ms(), ts, sizeof ts);
	gw_buf_puts(b, ",");
	jstr(b, "time", ts);
	/* for rates between two answers (the page's charts): seconds on a clock
	 * that does not jump, and the scans completed since the start */
	gw_buf_printf(b, ",\"uptime_s\":%.3f,\"scans\":%llu,", (gw_now_ms() - g->health.start_mono_ms) / 1000.0,
	              (unsigned long long)g->health.scan_count);
	line_json(g, b);
	gw_buf_puts(b, ",");
	stations_json(g, b);
	gw_buf_puts(b, ",");
	tags_json(g, b);
	gw_buf_puts(b, ",");
	broker_json(g, b);
	gw_buf_puts(b, ",\"buffer\":");
	gw_sfwd_json(g, b);             /* store and forward (gw_sfwd.c) */
	gw_buf_puts(b, ",");
	eip_json(g, b);
	gw_buf_printf(b, ",\"http_requests\":%llu,\"metrics\":",
	              (unsigned long long)g->health.http_requests);
	gw_metrics_write(g, b, true);
	gw_buf_puts(b, "}");
}
