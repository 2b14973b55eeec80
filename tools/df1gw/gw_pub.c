/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_pub - df1gw's northbound work (see gw.h): the retained tag and station
 * topics, published when their content changes; the status topic; writes
 * from <prefix>/tag/<name>/set through df1_tag_write(), each with one result.
 */
#include "df1gw/gw.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "df1gw/gw_value.h"

int64_t gw_now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

int64_t gw_wall_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* "[2508] ERR_COMMAND_TIMEOUT: command timed out"; a PLC's refusal with its STS. */
static void err_text(int err, uint8_t sts, uint8_t ext, char *buf, size_t cap)
{
	char tag[64];

	cli_error_tag(err, df1_error_catalog_id(err), tag, sizeof tag);
	if (err == DF1_E_REMOTE && sts == 0xF0)
		snprintf(buf, cap, "%s: STS 0x%02X (%s), EXT STS 0x%02X (%s)", tag, sts, df1_sts_text(sts), ext,
		         df1_ext_sts_text(ext));
	else if (err == DF1_E_REMOTE && sts)
		snprintf(buf, cap, "%s: STS 0x%02X (%s)", tag, sts, df1_sts_text(sts));
	else
		snprintf(buf, cap, "%s: %s", tag, df1_strerror(err));
}

static void topic_of(const struct gw *g, const char *name, const char *tail, char *out, size_t cap)
{
	snprintf(out, cap, "%s/%s%s", g->prefix, name, tail ? tail : "");
}

static void publish(struct gw *g, const char *topic, const char *payload, size_t len, bool retain)
{
	if (gw_mqtt_publish(&g->mq, topic, payload, len, retain) == 0 && g->cli.verbose && !g->cli.quiet)
		fprintf(stderr, "%s: > %s %.*s\n", GW_PROG, topic, (int)len, payload);
}

/* ---- tags ---- */

static void tag_publish(struct gw *g, int id, bool force, int64_t now)
{
	struct df1_tag_state st;
	struct gw_tag_view view = { NULL, -1, NULL, false };
	struct gw_pub *e;
	char error[256], topic[GW_TOPIC_MAX];

	if (id < 0 || id >= g->ntags || !gw_mqtt_up(&g->mq) || df1_tag_get(g->h, id, &st) < 0)
		return;
	e = &g->pubs.v[g->pub_of[id]];
	if (!(st.config->access & DF1_ACCESS_READ)) {
		view.reason = "write_only";
	} else if (!g->line_up) {
		view.quality = DF1_QUALITY_BAD;
		view.reason = "line_lost";
		view.error = g->line_error[0] ? g->line_error : NULL;
	} else if (st.quality != DF1_QUALITY_GOOD && st.last_error) {
		err_text(st.last_error, st.sts, st.ext_sts, error, sizeof error);
		view.error = error;
	} else if (st.reason == DF1_REASON_NOT_YET_READ && !force) {
		return;         /* nothing to say before its first read (and kept through a reload) */
	}
	gw_buf_reset(&g->key);
	gw_tag_json(&g->key, &st, &view);
	if (g->key.oom || !gw_pub_update(e, g->key.p, now, force))
		return;
	view.with_ts = true;
	gw_buf_reset(&g->buf);
	gw_tag_json(&g->buf, &st, &view);
	if (g->buf.oom)
		return;
	topic_of(g, e->name, NULL, topic, sizeof topic);
	publish(g, topic, g->buf.p, g->buf.len, true);
}

static void station_publish(struct gw *g, int stn, bool force, int64_t now);

/* Published at once, from inside df1_poll(): a scan with retries can take
 * seconds, and libmosquitto writes a publication out as it is made. */
void gw_on_tag(void *user, int id, const struct df1_tag_state *st)
{
	struct gw *g = user;
	int64_t now = gw_now_ms();

	if (id < 0 || id >= g->ntags)
		return;
	if (!gw_mqtt_up(&g->mq)) {
		g->dirty[id] = 1;
		return;
	}
	g->dirty[id] = 0;
	tag_publish(g, id, false, now);
	if (st && st->config && st->config->station >= 0 && st->config->station < 255)
		station_publish(g, st->config->station, false, now);
}

/* ---- stations ---- */

static void station_publish(struct gw *g, int stn, bool force, int64_t now)
{
	struct df1_station_health sh;
	struct gw_pub *e;
	char name[32], topic[GW_TOPIC_MAX], error[700], ts[40];
	const char *state;
	bool have_err;

	snprintf(name, sizeof name, "station/%d", stn);
	e = gw_pubs_get(&g->pubs, name, true);
	if (!e || !gw_mqtt_up(&g->mq) || df1_station_health(g->h, stn, &sh) < 0)
		return;
	if (g->line_up && sh.state == DF1_STATION_UNKNOWN && !force)
		return;         /* not polled yet (a reload, a reopened line): nothing new */
	state = g->line_up ? df1_station_state_name(sh.state) : "offline";
	have_err = !g->line_up ? g->line_error[0] != '\0' : sh.last_error != 0 && sh.state != DF1_STATION_OK;
	if (!g->line_up)
		snprintf(error, sizeof error, "%s", g->line_error);
	else if (have_err)
		err_text(sh.last_error, 0, 0, error, sizeof error);
	gw_buf_reset(&g->key);
	gw_buf_printf(&g->key, "{\"station\":%d,\"state\":\"%s\",\"error\":", stn, state);
	if (have_err)
		gw_json_text(&g->key, error, strlen(error));
	else
		gw_buf_puts(&g->key, "null");
	if (g->key.oom || !gw_pub_update(e, g->key.p, now, force))
		return;
	gw_buf_reset(&g->buf);
	gw_buf_add(&g->buf, g->key.p, g->key.len);
	gw_buf_printf(&g->buf, ",\"tags\":%d,\"attempts\":%llu,\"failures\":%llu,\"consecutive_failures\":%d,"
	              "\"last_good\":", sh.tags, (unsigned long long)sh.attempts,
	              (unsigned long long)sh.failures, sh.consecutive_failures);
	if (sh.last_good_ms > 0) {
		gw_rfc3339(gw_wall_ms() - (now - sh.last_good_ms), ts, sizeof ts);
		gw_buf_printf(&g->buf, "\"%s\"}", ts);
	} else {
		gw_buf_puts(&g->buf, "null}");
	}
	if (g->buf.oom)
		return;
	topic_of(g, name, NULL, topic, sizeof topic);
	publish(g, topic, g->buf.p, g->buf.len, true);
}

void gw_publish_changes(struct gw *g, bool force)
{
	int64_t now = gw_now_ms();

	if (!g->h || !gw_mqtt_up(&g->mq))
		return;
	force = force || g->republish;
	g->republish = false;
	for (int id = 0; id < g->ntags; id++) {
		if (force || g->dirty[id]) {
			g->dirty[id] = 0;
			tag_publish(g, id, force, now);
		}
	}
	for (int stn = 0; stn < 255; stn++)
		if (g->stations[stn])
			station_publish(g, stn, force, now);
}

void gw_publish_clear(struct gw *g, const char *name)
{
	char topic[GW_TOPIC_MAX];

	topic_of(g, name, NULL, topic, sizeof topic);
	publish(g, topic, "", 0, true);
}

void gw_on_connected(void *user)
{
	struct gw *g = user;
	char topic[GW_TOPIC_MAX];

	if (!g->once) {
		topic_of(g, "status", NULL, topic, sizeof topic);
		publish(g, topic, "online", 6, true);
		topic_of(g, "tag/+/set", NULL, topic, sizeof topic);
		if (gw_mqtt_subscribe(&g->mq, topic) < 0 && !g->cli.quiet)
			fprintf(stderr, "%s: cannot subscribe to %s\n", GW_PROG, topic);
	}
	g->republish = true;
	gw_publish_changes(g, true);
}

/* ---- writes ---- */

struct gw_wr {
	struct gw *g;
	char tag[80];
	char id[GW_ID_MAX + 1];
};

static void result_publish(struct gw *g, const char *tag, const char *id, int err, const char *detail)
{
	char topic[GW_TOPIC_MAX], name[96], text[1024];

	if (err) {
		char base[256];

		err_text(err, 0, 0, base, sizeof base);
		if (detail)
			snprintf(text, sizeof text, "%s: %s", base, detail);
		else
			snprintf(text, sizeof text, "%s", base);
	}
	if (!g->cli.quiet && err && g->cli.verbose)
		fprintf(stderr, "%s: write %s%s%s: %s\n", GW_PROG, tag, *id ? " id " : "", id, text);
	snprintf(name, sizeof name, "tag/%s", tag);
	topic_of(g, name, "/result", topic, sizeof topic);
	gw_buf_reset(&g->buf);
	gw_result_json(&g->buf, id, err == 0, err ? text : NULL, err ? gw_write_unconfirmed(err) : false);
	if (!g->buf.oom)
		publish(g, topic, g->buf.p, g->buf.len, false);
}

static void write_done(void *user, int tag_id, int write_id, int result)
{
	struct gw_wr *w = user;

	(void)tag_id;
	(void)write_id;
	result_publish(w->g, w->tag, w->id, result, NULL);
	if (w->g->writes_pending)
		w->g->writes_pending--;
	free(w);
}

/* The tag name of <prefix>/tag/<name>/set, into name; false if topic is not one. */
static bool set_topic_name(const struct gw *g, const char *topic, char *name, size_t cap)
{
	size_t pl = strlen(g->prefix), tl = strlen(topic), nl;

	if (tl < pl + 5 + 4 || strncmp(topic, g->prefix, pl) != 0 || strncmp(topic + pl, "/tag/", 5) != 0 ||
	    strcmp(topic + tl - 4, "/set") != 0)
		return false;
	nl = tl - pl - 5 - 4;
	if (nl == 0 || nl >= cap)
		return false;
	memcpy(name, topic + pl + 5, nl);
	name[nl] = '\0';
	return strchr(name, '/') == NULL;
}

void gw_on_message(void *user, const char *topic, const void *payload, int len, bool retain)
{
	struct gw *g = user;
	struct gw_set s;
	struct df1_tag_state st;
	struct df1_value vals[1000];
	struct gw_wr *w;
	char name[80], err[700];
	size_t n;
	int id, r;

	if (!set_topic_name(g, topic, name, sizeof name))
		return;
	if (g->cli.verbose && !g->cli.quiet)
		fprintf(stderr, "%s: < %s%s %.*s\n", GW_PROG, topic, retain ? " (retained)" : "", len,
		        (const char *)payload);
	if (gw_set_parse(payload, (size_t)(len < 0 ? 0 : len), &s, err, sizeof err) < 0) {
		result_publish(g, name, "", DF1_E_INVAL, err);
		return;
	}
	if (retain) {
		/* a retained .../set would write again at every subscription */
		result_publish(g, name, s.id, DF1_E_INVAL,
		               "a retained message is not a write: publish .../set without the retain flag");
		gw_set_free(&s);
		return;
	}
	if (s.id[0]) {
		if (gw_ids_seen(&g->ids, s.id)) {
			if (g->cli.verbose && !g->cli.quiet)
				fprintf(stderr, "%s: write %s id %s: seen before, not executed again\n", GW_PROG, name, s.id);
			gw_set_free(&s);
			return;
		}
		gw_ids_add(&g->ids, s.id);
	}
	id = g->h ? df1_tag_find(g->h, name) : -1;
	if (id < 0 || df1_tag_get(g->h, id, &st) < 0) {
		snprintf(err, sizeof err, "no tag \"%.64s\" in %s", name, g->map_path);
		result_publish(g, name, s.id, DF1_E_INVAL, err);
		gw_set_free(&s);
		return;
	}
	if (!(st.config->access & DF1_ACCESS_WRITE)) {
		result_publish(g, name, s.id, DF1_E_INVAL, "read-only tag (Command Read in the mapping file)");
		gw_set_free(&s);
		return;
	}
	r = gw_value_from_json(s.value, st.config, &st, vals, sizeof vals / sizeof vals[0], &n, err, sizeof err);
	if (r < 0) {
		result_publish(g, name, s.id, r, err);
		gw_set_free(&s);
		return;
	}
	if (!g->line_up) {
		result_publish(g, name, s.id, DF1_E_NOT_OPEN, g->line_error[0] ? g->line_error : NULL);
		gw_set_free(&s);
		return;
	}
	w = calloc(1, sizeof *w);
	if (!w) {
		result_publish(g, name, s.id, DF1_E_NOMEM, NULL);
		gw_set_free(&s);
		return;
	}
	w->g = g;
	snprintf(w->tag, sizeof w->tag, "%s", name);
	snprintf(w->id, sizeof w->id, "%s", s.id);
	gw_set_free(&s);
	r = df1_tag_write(g->h, id, vals, n, write_done, w);
	if (r < 0) {
		result_publish(g, name, w->id, r, NULL);
		free(w);
		return;
	}
	g->writes_pending++;
}

void gw_tag_config_text(const struct df1_tag_config *c, char *out, size_t cap)
{
	char addr[80];

	if (df1_addr_format(&c->addr, addr, sizeof addr) < 0)
		snprintf(addr, sizeof addr, "?");
	snprintf(out, cap, "%d|%s|%d|%d|%s|%d|%d", (int)c->access, c->type, c->station, (int)c->plc, addr,
	         c->count, c->scan_ms);
}
