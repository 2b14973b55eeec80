/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_pub - df1gw's northbound work (see gw.h): when to publish a tag or a
 * station (its content changed, --refresh, a reconnect), the status, and
 * writes through df1_tag_write(), each with one result; what the messages
 * hold and which topics they go to is each enabled payload format's
 * (gw_format.h). A session format (Sparkplug) is also given what it sees of
 * the gateway (struct gw_node, at the end of this file).
 */
#include "df1gw/gw.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "df1gw/gw_bdseq.h"


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

	bool text = gw_utf8_valid(body, m->body.len);

	for (size_t i = 0; i < m->body.len && text; i++)
		text = (unsigned char)body[i] >= 0x20 || body[i] == '\n' || body[i] == '\t';
	int mid = 0;

	if (gw_mqtt_publish_mid(&g->mq, m->topic, body, m->body.len, m->qos, m->retain, &mid) < 0)
		return;
	if ((m->qos < 0 ? g->qos : m->qos) > 0)
		gw_sfwd_live_mid(g, mid);       /* store and forward: a tag's message kept until its PUBACK */
	g->health.published++;          /* df1_mqtt_publications_total (gw_metrics.c) */
	if (g->cli.verbose && !g->cli.quiet) {
		if (text)
			fprintf(stderr, "%s: > %s %.*s\n", GW_PROG, m->topic, (int)m->body.len, body);
		else            /* a binary payload (Sparkplug's protobuf) */
			fprintf(stderr, "%s: > %s (%zu bytes)\n", GW_PROG, m->topic, m->body.len);
	}
}

/* A message of format f: its last touch (Sparkplug's seq), then out. */
static void fmt_publish(struct gw *g, const struct gw_fmt *f, struct gw_msg *m)
{
	if (f->ops->stamp)
		f->ops->stamp(f, m);
	publish(g, m);
}

/* ---- tags ---- */

/* What the gateway says of tag st beyond the library's state, into *t (error
 * is t->error's room); false when there is nothing to say yet. */
static bool tag_out(const struct gw *g, const struct df1_tag_state *st, bool force, struct gw_tag_out *t,
                    char *error, size_t cap)
{
	*t = (struct gw_tag_out){ st, NULL, -1, NULL, gw_wall_ms() };
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
	gw_sfwd_live_tag(g, &t);        /* store and forward: not lost if the connection drops now */
	for (int i = 0; i < g->fmts.n; i++)
		if (gw_fmt_tag_changed(&g->fmts.v[i], e, &t, &g->msg, &g->key, now, force))
			fmt_publish(g, &g->fmts.v[i], &g->msg);
	gw_sfwd_live_close(g);
}

static void station_publish(struct gw *g, int stn, bool force, int64_t now);
static void station_capture(struct gw *g, int stn);
static void gw_session_tick(struct gw *g);
static void gw_session_connected(struct gw *g, const struct gw_fmt *f);
static bool gw_session_message(struct gw *g, const struct gw_fmt *f, const char *topic, const void *payload,
                               int len, bool retain);

/* Published at once, from inside df1_poll(): a scan with retries can take
 * seconds, and libmosquitto writes a publication out as it is made. st is
 * the tag's state as df1_tag_get() would give it. */
void gw_on_tag(void *user, int id, const struct df1_tag_state *st)
{
	struct gw *g = user;
	int64_t now = gw_now_ms();

	if (id < 0 || id >= g->ntags)
		return;
	if (st && gw_sfwd_capturing(g)) {
		/* store and forward (gw_sfwd.c): into the buffer, published after */
		struct gw_tag_out t;
		char error[256];

		g->dirty[id] = 1;
		if (tag_out(g, st, false, &t, error, sizeof error))
			gw_sfwd_tag(g, &t);
		if (st->config && st->config->station >= 0 && st->config->station < 255)
			station_capture(g, st->config->station);
		return;
	}
	if (!st || !gw_mqtt_up(&g->mq)) {
		g->dirty[id] = 1;
		return;
	}
	g->dirty[id] = 0;
	tag_publish(g, id, st, false, now);
	if (st->config && st->config->station >= 0 && st->config->station < 255)
		station_publish(g, st->config->station, false, now);
	gw_mqtt_turn(&g->mq, now);      /* a long scan does not silence the broker */
}

/* ---- stations ---- */

/* Station stn's health as the formats tell it into *s (sh and error its
 * room); false when there is nothing to say. */
static bool station_out(struct gw *g, int stn, bool force, int64_t now, struct gw_station_out *s,
                        struct df1_station_health *sh, char *error, size_t cap)
{
	*s = (struct gw_station_out){ stn, NULL, NULL, sh, 0 };
	if (!g->h || df1_station_health(g->h, stn, sh) < 0)
		return false;
	if (g->line_up && sh->state == DF1_STATION_UNKNOWN && !force)
		return false;   /* not polled yet (a reload, a reopened line): nothing new */
	s->state = g->line_up ? df1_station_state_name(sh->state) : "offline";
	if (!g->line_up) {
		s->error = g->line_error[0] ? g->line_error : NULL;
	} else if (sh->last_error != 0 && sh->state != DF1_STATION_OK) {
		err_text(sh->last_error, 0, 0, error, cap);
		s->error = error;
	}
	if (sh->last_good_ms > 0)
		s->last_good_wall_ms = gw_wall_ms() - (now - sh->last_good_ms);
	return true;
}

/* Store and forward: station stn's health into the buffer (when it changed). */
static void station_capture(struct gw *g, int stn)
{
	struct df1_station_health sh;
	struct gw_station_out s;
	char error[700];

	if (station_out(g, stn, false, gw_now_ms(), &s, &sh, error, sizeof error))
		gw_sfwd_station(g, &s);
}

static void station_publish(struct gw *g, int stn, bool force, int64_t now)
{
	struct df1_station_health sh;
	struct gw_station_out s;
	struct gw_pub *e;
	char name[32], error[700];

	snprintf(name, sizeof name, "station/%d", stn);
	e = gw_pubs_get(&g->pubs, name, true);
	if (!e || !gw_mqtt_up(&g->mq) || !station_out(g, stn, force, now, &s, &sh, error, sizeof error))
		return;
	for (int i = 0; i < g->fmts.n; i++)
		if (gw_fmt_station_changed(&g->fmts.v[i], e, &s, &g->msg, &g->key, now, force))
			fmt_publish(g, &g->fmts.v[i], &g->msg);
}

void gw_publish_changes(struct gw *g, bool force)
{
	int64_t now = gw_now_ms();

	if (g->h && gw_sfwd_capturing(g))
		for (int stn = 0; stn < 255; stn++)
			if (g->stations[stn])
				station_capture(g, stn);
	if (!g->h || !gw_mqtt_up(&g->mq))
		return;
	if (gw_sfwd_holding(g)) {
		gw_session_tick(g);     /* the backlog first; g->republish waits for its end */
		return;
	}
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
	if (force)
		gw_rx_publish_all(g);   /* Receive tags: as the table holds them */
	gw_session_tick(g);
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
			gw_mqtt_publish_qos(&g->mq, g->msg.topic, g->msg.body.p, g->msg.body.len, g->msg.qos,
			                    g->msg.retain);
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
		if (f->ops->set_pattern) {
			f->ops->set_pattern(f, topic, sizeof topic);
			if (gw_mqtt_subscribe(&g->mq, topic) < 0 && !g->cli.quiet)
				fprintf(stderr, "%s: cannot subscribe to %s\n", GW_PROG, topic);
		}
		if (f->ops->connected)
			gw_session_connected(g, f);
	}
	g->republish = true;
	gw_publish_changes(g, true);
	/* the results that fell while the broker was away, once each */
	for (size_t i = 0; i < g->outbox.n; i++)
		publish(g, &g->outbox.v[i]);
	for (size_t i = 0; i < g->outbox.n; i++)
		gw_msg_free(&g->outbox.v[i]);
	g->outbox.n = 0;
}

/* ---- writes ---- */

/* A write's owner: the format it came in (its result goes out the same way). */
struct gw_wr {
	struct gw *g;
	const struct gw_fmt *f;
	char tag[80];
	char id[GW_WRITE_ID_MAX + 1];
	long timeout_ms;             /* the deadline it was given */
};

/* The one result of a write: ok, or error (then unconfirmed says whether the
 * PLC may have executed it), with the tag's true value and quality for a
 * format that answers with them (Sparkplug). While the broker is away a
 * result waits in the outbox; a session format's births say it all then. */
static void result_send(struct gw *g, const struct gw_fmt *f, const char *tag, const char *id,
                        const char *error, bool unconfirmed)
{
	struct gw_result_out r = { tag, id, error == NULL, error, error ? unconfirmed : false, NULL };
	struct df1_tag_state st;
	struct gw_tag_out now;
	char nowerr[256];
	int tid = g->h ? df1_tag_find(g->h, tag) : -1;

	if (!g->cli.quiet && error && (g->cli.verbose || f->ops->session))
		fprintf(stderr, "%s: write %s%s%s: %s\n", GW_PROG, tag, *id ? " id " : "", id, error);
	if (tid >= 0 && df1_tag_get(g->h, tid, &st) == 0 && tag_out(g, &st, true, &now, nowerr, sizeof nowerr))
		r.now = &now;
	if (f->ops->result(f, &r, &g->msg) < 0)
		return;
	if (gw_mqtt_up(&g->mq))
		fmt_publish(g, f, &g->msg);
	else if (!f->ops->session && gw_sfwd_result(g, f, &r) == 0)
		;       /* store and forward (gw_sfwd.c): replayed when the broker is back */
	else if (!f->ops->session)
		gw_outbox_add(&g->outbox, &g->msg);     /* published when the broker is back */
}

static void result_publish(struct gw *g, const struct gw_fmt *f, const char *tag, const char *id, int err,
                           const char *detail)
{
	char text[1024], base[256];

	if (!err) {
		result_send(g, f, tag, id, NULL, false);
		return;
	}
	err_text(err, 0, 0, base, sizeof base);
	if (detail)
		snprintf(text, sizeof text, "%s: %s", base, detail);
	else
		snprintf(text, sizeof text, "%s", base);
	result_send(g, f, tag, id, text, gw_write_unconfirmed(err));
}

/* A write the line has done (from inside df1_poll): its result, and the
 * broker served, so that a batch on a slow line never silences it. */
static void write_done(void *user, int tag_id, int write_id, int result)
{
	struct gw_wr *w = user;
	struct gw *g = w->g;

	(void)tag_id;
	(void)write_id;
	if (result == 0)
		g->wq.c.written++;
	else
		g->wq.c.failed++;
	result_publish(g, w->f, w->tag, w->id, result, NULL);
	if (g->writes_pending)
		g->writes_pending--;
	free(w);
	if (g->mq_configured)
		gw_mqtt_turn(&g->mq, gw_now_ms());
}

/* The queue's end of a write that was not handed to the line. */
static void write_ended(void *ctx, struct gw_witem *it, enum gw_wend why, const struct gw_witem *by)
{
	struct gw *g = ctx;
	struct gw_wr *w = it->user;
	char text[800];

	if (why == GW_WEND_SUPERSEDED) {
		const struct gw_wr *b = by->user;

		snprintf(text, sizeof text, "superseded by a later write (%s%s), not written", b->id[0] ? "id " : "no id",
		         b->id);
	} else if (why == GW_WEND_EXPIRED) {
		snprintf(text, sizeof text, "expired, not written: not started within %ld ms", w->timeout_ms);
	} else {
		snprintf(text, sizeof text, "not written: %s", g->line_error[0] ? g->line_error : "the line closed");
	}
	result_send(g, w->f, w->tag, w->id, text, false);
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
			*id = -2;               /* no result: not counted as refused */
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

static void write_go(struct gw *g, const struct gw_fmt *f, const char *name, struct gw_write_in *w_in, bool retain);

/* A bit or a BOOL tag: every write kept under latest-non-bool (a push
 * button's 1 and its 0). */
static bool write_keeps(const struct gw *g, int id)
{
	struct df1_tag_state st;

	if (df1_tag_get(g->h, id, &st) < 0)
		return true;
	return st.config->addr.bit != DF1_ADDR_NONE || strcasecmp(st.config->type, "BOOL") == 0;
}

/* Into the queue (gw_wqueue.h): waiting, or answered busy at once. */
static void write_queue(struct gw *g, struct gw_wr *w, int id, const struct df1_value *vals, size_t n)
{
	struct gw_witem *it;

	it = gw_witem_new(id, write_keeps(g, id), gw_now_ms() + w->timeout_ms, vals, n, w);
	if (!it) {
		g->wq.c.refused++;
		result_publish(g, w->f, w->tag, w->id, DF1_E_NOMEM, NULL);
		free(w);
		return;
	}
	if (gw_wq_push(&g->wq, it) < 0) {
		char text[200];

		snprintf(text, sizeof text, "busy, not written: %u writes wait already (--max-pending-writes)",
		         (unsigned)g->wq.n);
		result_send(g, w->f, w->tag, w->id, text, false);
		free(w);
		free(it);
	}
}

/* A write that came in format f's topic for tag name: parsed (an invalid
 * one answered at once, without the line), then write_go. */
static void write_take(struct gw *g, const struct gw_fmt *f, const char *name, const void *payload, int len,
                       bool retain)
{
	struct gw_write_in in;
	char err[700];

	g->wq.c.received++;
	if (f->ops->write_parse(f, payload, (size_t)(len < 0 ? 0 : len), &in, err, sizeof err) < 0) {
		g->wq.c.refused++;
		result_publish(g, f, name, "", DF1_E_INVAL, err);
		return;
	}
	write_go(g, f, name, &in, retain);
}

/* A write parsed (in, taken): checked, then into the write queue (gw_wqueue.h);
 * one result either way. */
static void write_go(struct gw *g, const struct gw_fmt *f, const char *name, struct gw_write_in *w_in, bool retain)
{
	static struct df1_value vals[1000];     /* one message at a time: not on the stack */
	struct gw_write_in in = *w_in;
	struct gw_wr *w;
	size_t n;
	int id = -1;

	if (gw_rx_write(g, f, name, w_in, retain))
		return;         /* a Receive tag: df1gw's own table, never the line */
	if (!write_check(g, f, name, &in, retain, &id, vals, sizeof vals / sizeof vals[0], &n)) {
		if (id != -2)
			g->wq.c.refused++;
		f->ops->write_free(&in);
		return;
	}
	w = calloc(1, sizeof *w);
	if (!w) {
		g->wq.c.refused++;
		result_publish(g, f, name, in.id, DF1_E_NOMEM, NULL);
		f->ops->write_free(&in);
		return;
	}
	w->g = g;
	w->f = f;
	snprintf(w->tag, sizeof w->tag, "%s", name);
	snprintf(w->id, sizeof w->id, "%s", in.id);
	w->timeout_ms = in.timeout_ms > 0 ? in.timeout_ms : g->write_timeout_ms;
	f->ops->write_free(&in);
	write_queue(g, w, id, vals, n);
}

/* Reads (and probes) the poll engine made since the last look: the duty
 * cycle counts writes between two of them. */
static void writes_reads_seen(struct gw *g)
{
	struct df1_poll_stats ps;

	if (df1_poll_stats(g->h, &ps) == 0 && ps.reads + ps.probes != g->reads_seen) {
		g->reads_seen = ps.reads + ps.probes;
		g->writes_since_read = 0;
	}
}

/* The writes' turn: a batch of at most --duty-cycle handed to the line. */
static void writes_batch(struct gw *g, int64_t now)
{
	for (int k = 0; k < g->duty_cycle; k++) {
		struct gw_witem *it = gw_wq_pop(&g->wq, now);
		struct gw_wr *w;
		int r;

		if (!it)
			break;
		w = it->user;
		r = df1_tag_write(g->h, it->tag, it->v, it->n, write_done, w);
		free(it);
		if (r < 0) {
			g->wq.c.failed++;
			result_publish(g, w->f, w->tag, w->id, r, NULL);
			free(w);
			continue;
		}
		g->writes_pending++;
		g->writes_since_read++;
	}
}

void gw_line_turns(struct gw *g, int64_t now, bool in_line)
{
	if (g->wq.v)
		gw_wq_expire(&g->wq, now);
	if (!g->h || !g->line_up)
		return;
	writes_reads_seen(g);
	/* a turn handed changes what waits: ask again, a few times at most */
	for (int i = 0; i < 4; i++) {
		struct gw_turn_state s = {
			.bridge = gw_eip_waiting(&g->eip),
			.backlog = g->wq.v ? g->wq.n : 0,
			.batch = g->writes_pending,
			.since_read = g->writes_since_read,
			.duty = (unsigned)g->duty_cycle,
			.in_line = in_line,
			.last = g->turn_last,
		};
		enum gw_turn t;

		s.poll_due = s.backlog > 0 && df1_poll_next_ms(g->h) == 0;
		t = gw_turn_next(&s);
		if (t == GW_TURN_BRIDGE)
			gw_eip_hand(&g->eip);
		else if (t == GW_TURN_WRITES)
			writes_batch(g, now);
		else
			return;
		g->turn_last = t;
	}
}

void gw_writes_drop(struct gw *g)
{
	if (g->wq.v)
		gw_wq_drop_all(&g->wq);
}

int gw_writes_init(struct gw *g)
{
	if (gw_outbox_init(&g->outbox, (size_t)g->max_pending) < 0)
		return -1;
	return gw_wq_init(&g->wq, g->write_optimize, (unsigned)g->max_pending, write_ended, g);
}

void gw_writes_counters(const struct gw *g, FILE *out)
{
	const struct gw_wcounters *c = &g->wq.c;

	fprintf(out, "writes %llu received, %llu written, %llu failed, %llu refused, %llu superseded, "
	        "%llu expired, %llu refused busy, %llu dropped, queue high-water %u\n",
	        (unsigned long long)c->received, (unsigned long long)c->written, (unsigned long long)c->failed,
	        (unsigned long long)c->refused, (unsigned long long)c->superseded, (unsigned long long)c->expired,
	        (unsigned long long)c->refused_busy, (unsigned long long)c->dropped, c->high_water);
}

void gw_on_message(void *user, const char *topic, const void *payload, int len, bool retain)
{
	struct gw *g = user;
	char name[80];

	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (f->ops->message && gw_session_message(g, f, topic, payload, len, retain))
			return;
		if (!f->ops->set_tag || !f->ops->set_tag(f, topic, name, sizeof name))
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

	if (df1_addr_format_plc(c->plc, &c->addr, addr, sizeof addr) < 0)
		snprintf(addr, sizeof addr, "?");
	snprintf(out, cap, "%d|%s|%d|%d|%s|%d|%d", (int)c->access, c->type, c->station, (int)c->plc, addr,
	         c->count, c->scan_ms);
}

/* ---- session formats (Sparkplug): what they see of the gateway (gw_node) ---- */

static bool node_tag(void *user, int id, struct df1_tag_state *st, struct gw_tag_out *t, char *err, size_t cap)
{
	struct gw *g = user;

	if (id >= g->ntags)
		return gw_rx_node_tag(g, id - g->ntags, st, t);        /* Receive rows (gw_receive.h) */
	if (!g->h || id < 0 || df1_tag_get(g->h, id, st) < 0)
		return false;
	tag_out(g, st, true, t, err, cap);
	return true;
}

static bool node_station(void *user, int stn, struct gw_station_out *s, struct df1_station_health *sh)
{
	struct gw *g = user;

	if (gw_rx_node_station(g, stn, s, sh))
		return true;    /* df1gw's own station: its Receive rows */
	if (!g->h || stn < 0 || stn >= 255 || !g->stations[stn] || df1_station_health(g->h, stn, sh) < 0)
		return false;
	*s = (struct gw_station_out){ stn, df1_station_state_name(sh->state), NULL, sh, 0 };
	return true;
}

static void node_line(void *user, struct gw_line_out *l, struct df1_poll_stats *ps)
{
	static const char *const keys[] = { "Baud", "Framing", "Duplex", "Check", "PLC" };
	static const char *const plcs[] = { "SLC", "MicroLogix", "SLC 5/01-5/02", "PLC-5", "PLC-2" };
	static char baud[16], framing[8];
	static const char *vals[5];
	struct gw *g = user;

	memset(ps, 0, sizeof *ps);
	if (g->h)
		df1_poll_stats(g->h, ps);
	snprintf(baud, sizeof baud, "%d", g->cli.baud);
	snprintf(framing, sizeof framing, "%d%c%d", g->cli.data_bits, g->cli.parity, g->cli.stop_bits);
	vals[0] = baud;
	vals[1] = framing;
	vals[2] = g->cli.radio ? "radio" : g->cli.half_duplex ? "half" : "full";
	vals[3] = g->cli.check == DF1_CHECK_BCC ? "BCC" : "CRC";
	vals[4] = (unsigned)g->cli.plc < 5 ? plcs[g->cli.plc] : "?";
	*l = (struct gw_line_out){ g->line_up, g->cli.device, ps, g->generation, gw_wall_ms(), gw_now_ms(),
	                           keys, vals, 5 };
}

static void node_emit(void *user, const struct gw_fmt *f, struct gw_msg *m)
{
	(void)f;
	publish(user, m);
}

static int node_subscribe(void *user, const char *pattern)
{
	struct gw *g = user;
	int r = gw_mqtt_subscribe(&g->mq, pattern);

	if (r < 0 && !g->cli.quiet)
		fprintf(stderr, "%s: cannot subscribe to %s\n", GW_PROG, pattern);
	return r;
}

static void node_write(void *user, const struct gw_fmt *f, const char *tag, struct gw_write_in *w, bool retain)
{
	struct gw *g = user;

	g->wq.c.received++;
	write_go(g, f, tag, w, retain);
}

static void node_reconnect(void *user)
{
	struct gw *g = user;

	gw_mqtt_reconnect(&g->mq, gw_now_ms());
}

static void node_log(void *user, const char *text)
{
	struct gw *g = user;

	if (!g->cli.quiet)
		fprintf(stderr, "%s: %s\n", GW_PROG, text);
}

static struct gw_node node_of(struct gw *g)
{
	return (struct gw_node){ g, g->ntags + (int)g->rx.n, node_tag, node_station, node_line, node_emit, node_subscribe,
	                         node_write, node_reconnect, node_log };
}

static void gw_session_connected(struct gw *g, const struct gw_fmt *f)
{
	struct gw_node n = node_of(g);

	f->ops->connected(f, &n);
}

static void gw_session_tick(struct gw *g)
{
	struct gw_node n = node_of(g);

	for (int i = 0; i < g->fmts.n; i++)
		if (g->fmts.v[i].ops->tick && gw_mqtt_up(&g->mq))
			g->fmts.v[i].ops->tick(&g->fmts.v[i], &n);
}

static bool gw_session_message(struct gw *g, const struct gw_fmt *f, const char *topic, const void *payload,
                               int len, bool retain)
{
	struct gw_node n = node_of(g);

	return f->ops->message(f, &n, topic, payload, (size_t)(len < 0 ? 0 : len), retain);
}

/* The bdSeq file by default, in the state folder (gw_bdseq.h; the folder is
 * made at the first write); NULL, having said why, when none can be named. */
static const char *bdseq_default(struct gw *g)
{
	char dir[sizeof g->spb_state_auto - 64];

	if (gw_bdseq_dir(dir, sizeof dir) < 0) {
		if (!g->cli.quiet)
			fprintf(stderr, "%s: no state folder for Sparkplug's bdSeq (STATE_DIRECTORY, XDG_STATE_HOME and "
			        "HOME are not set): bdSeq starts at 0 at every start (--sparkplug-state FILE keeps it)\n",
			        GW_PROG);
		return NULL;
	}
	if (gw_bdseq_path(dir, g->spb.group, g->spb.edge_node, g->spb_state_auto, sizeof g->spb_state_auto) < 0) {
		if (!g->cli.quiet)
			fprintf(stderr, "%s: state folder %s: the group and edge node ids make too long a file name: bdSeq "
			        "is not kept (--sparkplug-state FILE keeps it)\n", GW_PROG, dir);
		return NULL;
	}
	g->spb_state_mkdir = true;
	return g->spb_state_auto;
}

void gw_bdseq_load(struct gw *g)
{
	unsigned last;
	int r;

	g->bdseq_next = 0;
	if (!g->spb.group || g->once)
		return;
	if (!g->spb_state_path)
		g->spb_state_path = bdseq_default(g);
	if (!g->spb_state_path)
		return;
	r = gw_bdseq_read(g->spb_state_path, &last);
	if (r > 0)
		g->bdseq_next = (last + 1) & 0xFF;
	else if (r < 0 && !(g->spb_state_mkdir && errno == ENOTDIR) && !g->cli.quiet)   /* said by bdseq_folder */
		fprintf(stderr, "%s: bdSeq file %s: %s: bdSeq starts at 0\n", GW_PROG, g->spb_state_path,
		        errno == EINVAL ? "not a line \"bdSeq N\" (N 0-255)" : strerror(errno));
}

/* The state folder of the default bdSeq file, made if missing: 0, or -1
 * having said why (the path, the reason). */
static int bdseq_folder(struct gw *g)
{
	char dir[sizeof g->spb_state_auto];
	char *slash;

	snprintf(dir, sizeof dir, "%s", g->spb_state_auto);
	slash = strrchr(dir, '/');
	if (slash)
		*slash = '\0';
	if (!slash || gw_bdseq_mkdir(dir) == 0) {
		g->spb_state_mkdir = false;
		return 0;
	}
	if (!g->cli.quiet)
		fprintf(stderr, "%s: state folder %s: %s: bdSeq is not kept, it starts at 0 at every start "
		        "(--sparkplug-state FILE keeps it elsewhere)\n", GW_PROG, dir, strerror(errno));
	return -1;
}

/* The bdSeq of this connect, written down before it is used (a restart goes
 * on from it); a failure said once, the count then goes on in memory. */
static void bdseq_save(struct gw *g, unsigned bdseq)
{
	if (!g->spb_state_path)
		return;
	if (g->spb_state_mkdir && bdseq_folder(g) < 0) {
		g->spb_state_path = NULL;
		return;
	}
	if (gw_bdseq_write(g->spb_state_path, bdseq) == 0)
		return;
	if (!g->cli.quiet)
		fprintf(stderr, "%s: bdSeq file %s: cannot write it: %s: bdSeq is not kept for the next start\n",
		        GW_PROG, g->spb_state_path, strerror(errno));
	g->spb_state_path = NULL;
}

void gw_on_connecting(void *user)
{
	struct gw *g = user;

	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];
		unsigned bdseq = g->bdseq_next;

		if (!f->ops->will_next || f->ops->will_next(f, bdseq, &g->will) < 0)
			continue;
		bdseq_save(g, bdseq);
		g->bdseq_next = (bdseq + 1) & 0xFF;
		if (gw_mqtt_will(&g->mq, g->will.topic, g->will.body.p, g->will.body.len, g->will.qos,
		                 g->will.retain) < 0 && !g->cli.quiet)
			fprintf(stderr, "%s: cannot set the last will on %s\n", GW_PROG, g->will.topic);
		return;         /* a connection has one will */
	}
}

void gw_publish_counters(const struct gw *g, FILE *out)
{
	char line[512];

	for (int i = 0; i < g->fmts.n; i++)
		if (g->fmts.v[i].ops->counters && g->fmts.v[i].ops->counters(&g->fmts.v[i], line, sizeof line) == 0)
			fprintf(out, "%s\n", line);
}
