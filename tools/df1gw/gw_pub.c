/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_pub - df1gw's northbound work (see gw.h): when to publish a tag or a
 * station (its content changed, --refresh, a reconnect), the status, and
 * writes through df1_tag_write(), each with one result; what the messages
 * hold and which topics they go to is each enabled payload format's
 * (gw_format.h).
 */
#include "df1gw/gw.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>


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

/* One message of a format to the broker; said with -v. */
static void publish(struct gw *g, const struct gw_msg *m)
{
	const char *body = m->body.p ? m->body.p : "";

	if (gw_mqtt_publish(&g->mq, m->topic, body, m->body.len, m->retain) < 0)
		return;
	g->health.published++;          /* df1_mqtt_publications_total (gw_metrics.c) */
	if (g->cli.verbose && !g->cli.quiet)
		fprintf(stderr, "%s: > %s %.*s\n", GW_PROG, m->topic, (int)m->body.len, body);
}

/* ---- tags ---- */

/* What the gateway says of tag st beyond the library's state, into *t (error
 * is t->error's room); false when there is nothing to say yet. */
static bool tag_out(const struct gw *g, const struct df1_tag_state *st, bool force, struct gw_tag_out *t,
                    char *error, size_t cap)
{
	*t = (struct gw_tag_out){ st, NULL, -1, NULL };
	if (!(st->config->access & DF1_ACCESS_READ)) {
		t->reason = "write_only";
	} else if (!g->line_up) {
		t->quality = DF1_QUALITY_BAD;
		t->reason = "line_lost";
		t->error = g->line_error[0] ? g->line_error : NULL;
	} else if (st->quality != DF1_QUALITY_GOOD && st->last_error) {
		err_text(st->last_error, st->sts, st->ext_sts, error, cap);
		t->error = error;
	} else if (st->reason == DF1_REASON_NOT_YET_READ && !force) {
		return false;   /* nothing to say before its first read (and kept through a reload) */
	}
	return true;
}

/* Tag id in state st, by every format whose message of it changed (or all when force). */
static void tag_publish(struct gw *g, int id, const struct df1_tag_state *st, bool force, int64_t now)
{
	struct gw_tag_out t;
	struct gw_pub *e;
	char error[256];

	if (id < 0 || id >= g->ntags || !gw_mqtt_up(&g->mq) || !tag_out(g, st, force, &t, error, sizeof error))
		return;
	e = &g->pubs.v[g->pub_of[id]];
	for (int i = 0; i < g->fmts.n; i++)
		if (gw_fmt_tag_changed(&g->fmts.v[i], e, &t, &g->msg, &g->key, now, force))
			publish(g, &g->msg);
}

static void station_publish(struct gw *g, int stn, bool force, int64_t now);

/* Published at once, from inside df1_poll(): a scan with retries can take
 * seconds, and libmosquitto writes a publication out as it is made. st is
 * the tag's state as df1_tag_get() would give it. */
void gw_on_tag(void *user, int id, const struct df1_tag_state *st)
{
	struct gw *g = user;
	int64_t now = gw_now_ms();

	if (id < 0 || id >= g->ntags)
		return;
	if (!st || !gw_mqtt_up(&g->mq)) {
		g->dirty[id] = 1;
		return;
	}
	g->dirty[id] = 0;
	tag_publish(g, id, st, false, now);
	if (st->config && st->config->station >= 0 && st->config->station < 255)
		station_publish(g, st->config->station, false, now);
}

/* ---- stations ---- */

static void station_publish(struct gw *g, int stn, bool force, int64_t now)
{
	struct df1_station_health sh;
	struct gw_station_out s = { stn, NULL, NULL, &sh, 0 };
	struct gw_pub *e;
	char name[32], error[700];

	snprintf(name, sizeof name, "station/%d", stn);
	e = gw_pubs_get(&g->pubs, name, true);
	if (!e || !gw_mqtt_up(&g->mq) || df1_station_health(g->h, stn, &sh) < 0)
		return;
	if (g->line_up && sh.state == DF1_STATION_UNKNOWN && !force)
		return;         /* not polled yet (a reload, a reopened line): nothing new */
	s.state = g->line_up ? df1_station_state_name(sh.state) : "offline";
	if (!g->line_up) {
		s.error = g->line_error[0] ? g->line_error : NULL;
	} else if (sh.last_error != 0 && sh.state != DF1_STATION_OK) {
		err_text(sh.last_error, 0, 0, error, sizeof error);
		s.error = error;
	}
	if (sh.last_good_ms > 0)
		s.last_good_wall_ms = gw_wall_ms() - (now - sh.last_good_ms);
	for (int i = 0; i < g->fmts.n; i++)
		if (gw_fmt_station_changed(&g->fmts.v[i], e, &s, &g->msg, &g->key, now, force))
			publish(g, &g->msg);
}

void gw_publish_changes(struct gw *g, bool force)
{
	int64_t now = gw_now_ms();

	if (!g->h || !gw_mqtt_up(&g->mq))
		return;
	force = force || g->republish;
	g->republish = false;
	for (int id = 0; id < g->ntags; id++) {
		struct df1_tag_state st;

		if ((force || g->dirty[id]) && df1_tag_get(g->h, id, &st) == 0) {
			g->dirty[id] = 0;
			tag_publish(g, id, &st, force, now);
		}
	}
	for (int stn = 0; stn < 255; stn++)
		if (g->stations[stn])
			station_publish(g, stn, force, now);
}

void gw_publish_gone(struct gw *g, const struct gw_pub *e)
{
	if (strncmp(e->name, "tag/", 4) != 0)
		return;
	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (e->key[f->slot] && f->ops->tag_gone(f, e->name + 4, &g->msg) == 0)
			publish(g, &g->msg);
	}
}

void gw_publish_offline(struct gw *g)
{
	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		/* said on the way out, not printed with -v */
		if (f->ops->status(f, false, &g->msg) == 0)
			gw_mqtt_publish(&g->mq, g->msg.topic, g->msg.body.p, g->msg.body.len, g->msg.retain);
	}
}

void gw_on_connected(void *user)
{
	struct gw *g = user;
	char topic[GW_TOPIC_MAX];

	for (int i = 0; i < g->fmts.n && !g->once; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (f->ops->status(f, true, &g->msg) == 0)
			publish(g, &g->msg);
		f->ops->set_pattern(f, topic, sizeof topic);
		if (gw_mqtt_subscribe(&g->mq, topic) < 0 && !g->cli.quiet)
			fprintf(stderr, "%s: cannot subscribe to %s\n", GW_PROG, topic);
	}
	g->republish = true;
	gw_publish_changes(g, true);
}

/* ---- writes ---- */

struct gw_wr {
	struct gw *g;
	const struct gw_fmt *f;      /* the format it came in: its result goes out the same way */
	char tag[80];
	char id[GW_WRITE_ID_MAX + 1];
};

static void result_publish(struct gw *g, const struct gw_fmt *f, const char *tag, const char *id, int err,
                           const char *detail)
{
	struct gw_result_out r = { tag, id, err == 0, NULL, false };
	char text[1024];

	if (err) {
		char base[256];

		err_text(err, 0, 0, base, sizeof base);
		if (detail)
			snprintf(text, sizeof text, "%s: %s", base, detail);
		else
			snprintf(text, sizeof text, "%s", base);
		r.error = text;
		r.unconfirmed = gw_write_unconfirmed(err);
	}
	if (!g->cli.quiet && err && g->cli.verbose)
		fprintf(stderr, "%s: write %s%s%s: %s\n", GW_PROG, tag, *id ? " id " : "", id, text);
	if (f->ops->result(f, &r, &g->msg) == 0)
		publish(g, &g->msg);
}

static void write_done(void *user, int tag_id, int write_id, int result)
{
	struct gw_wr *w = user;

	(void)tag_id;
	(void)write_id;
	result_publish(w->g, w->f, w->tag, w->id, result, NULL);
	if (w->g->writes_pending)
		w->g->writes_pending--;
	free(w);
}

/* The values write w of tag name asks for, into vals (*n), checked as far as
 * the gateway can before the line: not retained, not seen before, a tag that
 * can be written, values that fit it, the line up. false when it goes no
 * further (its result published, or a redelivery said with -v). */
static bool write_check(struct gw *g, const struct gw_fmt *f, const char *name, const struct gw_write_in *w,
                        bool retain, int *id, struct df1_value *vals, size_t cap, size_t *n)
{
	struct df1_tag_state st;
	char err[700];
	int r;

	if (retain) {
		/* a retained .../set would write again at every subscription */
		result_publish(g, f, name, w->id, DF1_E_INVAL,
		               "a retained message is not a write: publish .../set without the retain flag");
		return false;
	}
	if (w->id[0]) {
		if (gw_ids_seen(&g->ids, w->id)) {
			if (g->cli.verbose && !g->cli.quiet)
				fprintf(stderr, "%s: write %s id %s: seen before, not executed again\n", GW_PROG, name, w->id);
			return false;
		}
		gw_ids_add(&g->ids, w->id);
	}
	*id = g->h ? df1_tag_find(g->h, name) : -1;
	if (*id < 0 || df1_tag_get(g->h, *id, &st) < 0) {
		snprintf(err, sizeof err, "no tag \"%.64s\" in %s", name, g->map_path);
		result_publish(g, f, name, w->id, DF1_E_INVAL, err);
		return false;
	}
	if (!(st.config->access & DF1_ACCESS_WRITE)) {
		result_publish(g, f, name, w->id, DF1_E_INVAL, "read-only tag (Command Read in the mapping file)");
		return false;
	}
	r = f->ops->write_values(f, w, st.config, &st, vals, cap, n, err, sizeof err);
	if (r < 0) {
		result_publish(g, f, name, w->id, r, err);
		return false;
	}
	if (!g->line_up) {
		result_publish(g, f, name, w->id, DF1_E_NOT_OPEN, g->line_error[0] ? g->line_error : NULL);
		return false;
	}
	return true;
}

/* A write that came in format f's topic for tag name: checked, then queued
 * with df1_tag_write(); one result either way. */
static void write_take(struct gw *g, const struct gw_fmt *f, const char *name, const void *payload, int len,
                       bool retain)
{
	struct gw_write_in in;
	struct df1_value vals[1000];
	struct gw_wr *w;
	char err[700];
	size_t n;
	int id, r;

	if (f->ops->write_parse(f, payload, (size_t)(len < 0 ? 0 : len), &in, err, sizeof err) < 0) {
		result_publish(g, f, name, "", DF1_E_INVAL, err);
		return;
	}
	if (!write_check(g, f, name, &in, retain, &id, vals, sizeof vals / sizeof vals[0], &n)) {
		f->ops->write_free(&in);
		return;
	}
	w = calloc(1, sizeof *w);
	if (!w) {
		result_publish(g, f, name, in.id, DF1_E_NOMEM, NULL);
		f->ops->write_free(&in);
		return;
	}
	w->g = g;
	w->f = f;
	snprintf(w->tag, sizeof w->tag, "%s", name);
	snprintf(w->id, sizeof w->id, "%s", in.id);
	f->ops->write_free(&in);
	r = df1_tag_write(g->h, id, vals, n, write_done, w);
	if (r < 0) {
		result_publish(g, f, name, w->id, r, NULL);
		free(w);
		return;
	}
	g->writes_pending++;
}

void gw_on_message(void *user, const char *topic, const void *payload, int len, bool retain)
{
	struct gw *g = user;
	char name[80];

	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (!f->ops->set_tag(f, topic, name, sizeof name))
			continue;
		if (g->cli.verbose && !g->cli.quiet)
			fprintf(stderr, "%s: < %s%s %.*s\n", GW_PROG, topic, retain ? " (retained)" : "", len,
			        (const char *)payload);
		write_take(g, f, name, payload, len, retain);
		return;
	}
}

void gw_tag_config_text(const struct df1_tag_config *c, char *out, size_t cap)
{
	char addr[80];

	if (df1_addr_format(&c->addr, addr, sizeof addr) < 0)
		snprintf(addr, sizeof addr, "?");
	snprintf(out, cap, "%d|%s|%d|%d|%s|%d|%d", (int)c->access, c->type, c->station, (int)c->plc, addr,
	         c->count, c->scan_ms);
}
