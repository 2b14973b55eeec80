/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_sfwd.c - df1gw's store and forward (gw_sfwd.h): the buffer opened from
 * the options, what gw_pub.c hands over appended, the replay after a
 * reconnect, the acknowledgements, the figures.
 */
#include "df1gw/gw_sfwd.h"

#include <inttypes.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "df1gw/gw.h"
#include "df1gw/gw_buffer_rec.h"
#include "df1gw/gw_buffer_tag.h"
#include "df1gw/gw_rx_table.h"

#define EXPIRE_EVERY_MS 1000         /* --buffer-max-age: a look a second */

/* One record's blob at a time, and a tag's values unpacked: not on the stack. */
static uint8_t blob[GW_BUFFER_TAG_MAX > GW_BUFFER_REC_MAX ? GW_BUFFER_TAG_MAX : GW_BUFFER_REC_MAX];
static struct df1_value vals[1000];

/* The wall clock of a record's read time (gw_pub.c's gw_wall_ms(); its own,
 * so that gw_pub.c, which calls in here, is not called back). */
static int64_t sf_wall_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static void say(const struct gw *g, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void say(const struct gw *g, const char *fmt, ...)
{
	va_list ap;

	if (g->cli.quiet)
		return;
	fprintf(stderr, "%s: ", GW_PROG);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
}

/* A note of the buffer (a file moved aside, the fall back to memory). */
static void say_note(struct gw *g)
{
	const char *n = g->sfwd.b ? gw_buffer_note(g->sfwd.b) : NULL;

	if (n)
		say(g, "%s", n);        /* "buffer FILE: ..." */
}

static void bound_text(const struct gw_sfwd *s, char *out, size_t cap)
{
	if (s->lim.max_records)
		snprintf(out, cap, "%" PRIu64 " records", s->lim.max_records);
	else if (s->lim.max_bytes)
		snprintf(out, cap, "%" PRIu64 " bytes", s->lim.max_bytes);
	else
		snprintf(out, cap, "%u records, %u MiB", GW_BUFFER_MEM_DEFAULT_RECORDS,
		         GW_BUFFER_MEM_DEFAULT_BYTES / (1024u * 1024u));
}

int gw_sfwd_open(struct gw *g)
{
	struct gw_sfwd *s = &g->sfwd;
	char err[512], bound[64];
	int r;

	gw_replay_init(&s->r, s->rate);
	if (!g->mqtt_url || g->once)
		return 0;               /* nothing to store for: no broker, or one scan */
	/* a file size limit (ulimit -f) fails the write with EFBIG, which the
	 * buffer answers by falling back to memory: not a reason to stop */
	signal(SIGXFSZ, SIG_IGN);
	if (s->path && !s->lim.max_records && !s->lim.max_bytes)
		s->lim.max_bytes = GW_SFWD_FILE_DEFAULT_BYTES;
	r = gw_buffer_open(&s->b, s->path, &s->lim, err, sizeof err);
	if (r == GW_BUFFER_LOCKED) {
		fprintf(stderr, "%s: %s: another df1gw uses this file (one process per buffer file)\n", GW_PROG, err);
		return CLI_EXIT_USAGE;
	}
	if (r < 0) {
		fprintf(stderr, "%s: --buffer %s: %s\n", GW_PROG, s->path ? s->path : "(memory)", err);
		return CLI_EXIT_FAIL;
	}
	if (gw_live_init(&s->live, 0) < 0) {
		fprintf(stderr, "%s: out of memory\n", GW_PROG);
		return CLI_EXIT_FAIL;
	}
	say_note(g);
	bound_text(s, bound, sizeof bound);
	if (!s->path)
		say(g, "no --buffer: the changes made while the broker is away are kept in memory (at most %s) "
		    "and lost on exit", bound);
	else if (g->cli.verbose)
		say(g, "buffer %s: at most %s", s->path, bound);
	return 0;
}

void gw_sfwd_close(struct gw *g)
{
	if (g->sfwd.b)
		gw_buffer_close(g->sfwd.b);
	g->sfwd.b = NULL;
	gw_live_free(&g->sfwd.live);
}

static uint64_t backlog(const struct gw_sfwd *s)
{
	struct gw_buffer_stats st;

	if (!s->b)
		return 0;
	gw_buffer_stats(s->b, &st);
	return st.records;
}

/* Every session format born (Sparkplug: its primary host online). */
static bool sessions_ready(const struct gw *g)
{
	for (int i = 0; i < g->fmts.n; i++)
		if (g->fmts.v[i].ops->ready && !g->fmts.v[i].ops->ready(&g->fmts.v[i]))
			return false;
	return true;
}

bool gw_sfwd_holding(const struct gw *g)
{
	/* until gw_sfwd_turn has seen the backlog drained (then one republish) */
	return g->sfwd.draining || backlog(&g->sfwd) > 0;
}

bool gw_sfwd_capturing(const struct gw *g)
{
	if (!g->sfwd.b)
		return false;
	if (backlog(&g->sfwd) > 0)
		return true;
	/* before the first connection there is nothing to forward to yet:
	 * the first connection publishes every tag as it is */
	return g->mq.ever_up && (!gw_mqtt_up(&g->mq) || !sessions_ready(g));
}

/* Drops since the last look: the first of an outage said (once), counted;
 * how many is said at the reconnection (outage_end), and those after it
 * (the bound passed while the replay goes on) once the backlog drains. */
static void drops_look(struct gw *g)
{
	struct gw_sfwd *s = &g->sfwd;
	uint64_t d = gw_buffer_take_dropped(s->b);
	char bound[64];

	say_note(g);
	if (!d)
		return;
	s->outage_dropped += d;
	/* said while the broker (or a session's host) is away: during the
	 * replay they are counted for the line said when it has drained */
	if (!s->full_said && (!gw_mqtt_up(&g->mq) || !sessions_ready(g))) {
		bound_text(s, bound, sizeof bound);
		say(g, "buffer: full (%s%s): the oldest records are dropped; how many is said when the broker "
		    "is back", bound, s->lim.max_age_ms ? ", or older than --buffer-max-age" : "");
		s->full_said = true;
	}
}

static void append(struct gw *g, struct gw_buffer_rec *rec)
{
	struct gw_sfwd *s = &g->sfwd;

	if (gw_buffer_append(s->b, rec, sf_wall_ms()) < 0) {
		if (!s->err_said)
			say(g, "buffer: cannot keep a change (out of memory): it is lost");
		s->err_said = true;
	}
	drops_look(g);
}

void gw_sfwd_tag(struct gw *g, const struct gw_tag_out *t)
{
	int n = gw_buffer_tag_pack(t, blob, sizeof blob);
	struct gw_buffer_rec rec = { 0, GW_BUFFER_TAG, t->st->id, t->quality >= 0 ? t->quality : (int)t->st->quality,
	                             t->wall_ms, t->st->config->name, blob, (size_t)(n < 0 ? 0 : n) };

	if (n >= 0 && g->sfwd.b)
		append(g, &rec);
}

void gw_sfwd_receive(struct gw *g, const struct gw_tag_out *t, int from)
{
	int n = gw_buffer_tag_pack(t, blob, sizeof blob);
	struct gw_buffer_rec rec = { 0, GW_BUFFER_RECEIVE, from, (int)t->st->quality, t->wall_ms,
	                             t->st->config->name, blob, (size_t)(n < 0 ? 0 : n) };

	if (n >= 0 && g->sfwd.b)
		append(g, &rec);
}

void gw_sfwd_live_tag(struct gw *g, const struct gw_tag_out *t)
{
	int n;

	if (!g->sfwd.b || (n = gw_buffer_tag_pack(t, blob, sizeof blob)) < 0)
		return;
	struct gw_buffer_rec rec = { 0, GW_BUFFER_TAG, t->st->id, t->quality >= 0 ? t->quality : (int)t->st->quality,
	                             t->wall_ms, t->st->config->name, blob, (size_t)n };

	gw_live_open(&g->sfwd.live, &rec);
}

void gw_sfwd_live_receive(struct gw *g, const struct gw_tag_out *t, int from)
{
	int n;

	if (!g->sfwd.b || (n = gw_buffer_tag_pack(t, blob, sizeof blob)) < 0)
		return;
	struct gw_buffer_rec rec = { 0, GW_BUFFER_RECEIVE, from, (int)t->st->quality, t->wall_ms, t->st->config->name,
	                             blob, (size_t)n };

	gw_live_open(&g->sfwd.live, &rec);
}

void gw_sfwd_live_mid(struct gw *g, int mid)
{
	gw_live_mid(&g->sfwd.live, mid);
}

void gw_sfwd_live_close(struct gw *g)
{
	gw_live_close(&g->sfwd.live);
}

static uint64_t fnv(uint64_t h, const char *p)
{
	for (; p && *p; p++)
		h = (h ^ (unsigned char)*p) * 1099511628211ull;
	return (h ^ 0xFF) * 1099511628211ull;
}

void gw_sfwd_station(struct gw *g, const struct gw_station_out *st)
{
	struct gw_sfwd *s = &g->sfwd;
	uint64_t key = fnv(fnv(14695981039346656037ull, st->state), st->error);
	int n;

	if (!s->b || st->station < 0 || st->station >= 255 || (s->st_known[st->station] && s->st_key[st->station] == key))
		return;
	s->st_known[st->station] = true;
	s->st_key[st->station] = key;
	n = gw_buffer_station_pack(st, blob, sizeof blob);
	if (n >= 0) {
		struct gw_buffer_rec rec = { 0, GW_BUFFER_HEALTH, st->station, 0, sf_wall_ms(), "", blob, (size_t)n };

		append(g, &rec);
	}
}

int gw_sfwd_result(struct gw *g, const struct gw_fmt *f, const struct gw_result_out *r)
{
	int n;

	if (!g->sfwd.b || (n = gw_buffer_result_pack(r, blob, sizeof blob)) < 0)
		return -1;
	struct gw_buffer_rec rec = { 0, GW_BUFFER_WRITE, f->slot, r->ok ? DF1_QUALITY_GOOD : DF1_QUALITY_BAD,
	                             sf_wall_ms(), r->tag, blob, (size_t)n };

	append(g, &rec);
	return 0;
}

/* ---- the replay ---- */

/* m of format f out for record seq: true when it waits for its PUBACK (QoS
 * 1, its mid noted). The format's QoS 0 (Sparkplug's DDATA) has no
 * acknowledgement (libmosquitto may even call back before the publish
 * returns): handed over, it is done with. */
static bool replay_send(struct gw *g, const struct gw_fmt *f, struct gw_msg *m, uint64_t seq)
{
	int mid = 0;

	if (f->ops->stamp)
		f->ops->stamp(f, m);
	if (gw_mqtt_publish_mid(&g->mq, m->topic, m->body.p ? m->body.p : "", m->body.len, m->qos == 0 ? 0 : 1,
	                        m->retain, &mid) < 0)
		return false;
	g->health.published++;
	if (g->cli.verbose && !g->cli.quiet)
		fprintf(stderr, "%s: > %s (historical, record %" PRIu64 ", %zu bytes)\n", GW_PROG, m->topic, seq,
		        m->body.len);
	return m->qos != 0 && gw_replay_sent(&g->sfwd.r, mid, seq) == 0;
}

/* A tag record by each format; how many messages went. */
static int replay_tag(struct gw *g, const struct gw_buffer_rec *rec)
{
	static struct gw_buffer_tag_out o;
	struct df1_tag_state cur;
	int id = g->h && rec->key ? df1_tag_find(g->h, rec->key) : -1, sent = 0;

	/* a tag no longer in the mapping file (a reload, a restart) is dropped */
	if (id < 0 || df1_tag_get(g->h, id, &cur) < 0)
		return 0;
	o.values = vals;
	o.cap = sizeof vals / sizeof vals[0];
	if (gw_buffer_tag_unpack(rec->data, rec->len, &o) < 0 || o.st.count != cur.count)
		return 0;
	o.st.config = cur.config;
	o.st.id = id;
	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (f->ops->tag_historical && f->ops->tag_historical(f, &o.out, rec->seq, &g->msg) == 0)
			sent += replay_send(g, f, &g->msg, rec->seq);
	}
	return sent;
}

/* A Receive tag's record (gw_receive.c): as a tag's, JSON with "from". */
static int replay_receive(struct gw *g, const struct gw_buffer_rec *rec)
{
	static struct gw_buffer_tag_out o;
	struct df1_tag_state cur;
	int sent = 0;

	/* a Receive row no longer in the mapping file is dropped */
	if (!rec->key || !gw_rx_tag_state(&g->rx, g->ntags, rec->key, &cur))
		return 0;
	o.values = vals;
	o.cap = sizeof vals / sizeof vals[0];
	if (gw_buffer_tag_unpack(rec->data, rec->len, &o) < 0 || o.st.count != cur.count)
		return 0;
	o.st.config = cur.config;
	o.st.id = cur.id;
	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (!f->ops->tag_historical || f->ops->tag_historical(f, &o.out, rec->seq, &g->msg) < 0)
			continue;
		if (rec->id >= 0 && strcmp(f->ops->name, "json") == 0 && gw_msg_json_add_int(&g->msg, "from", rec->id) < 0)
			continue;
		sent += replay_send(g, f, &g->msg, rec->seq);
	}
	return sent;
}

static int replay_station(struct gw *g, const struct gw_buffer_rec *rec)
{
	static struct gw_buffer_station_out o;
	int sent = 0;

	if (gw_buffer_station_unpack(rec->data, rec->len, rec->id, &o) < 0)
		return 0;
	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (f->ops->station_historical && f->ops->station_historical(f, &o.out, rec->seq, rec->ms, &g->msg) == 0)
			sent += replay_send(g, f, &g->msg, rec->seq);
	}
	return sent;
}

/* A write's result, by the format it came in (as it would have gone then). */
static int replay_result(struct gw *g, const struct gw_buffer_rec *rec)
{
	static struct gw_buffer_result_out o;
	const struct gw_fmt *f = rec->id >= 0 && rec->id < g->fmts.n ? &g->fmts.v[rec->id] : NULL;

	if (!f || f->ops->session || gw_buffer_result_unpack(rec->data, rec->len, &o) < 0 ||
	    f->ops->result(f, &o.out, &g->msg) < 0)
		return 0;
	return replay_send(g, f, &g->msg, rec->seq);
}

static int replay_one(struct gw *g, const struct gw_buffer_rec *rec)
{
	switch (rec->kind) {
	case GW_BUFFER_TAG: return replay_tag(g, rec);
	case GW_BUFFER_HEALTH: return replay_station(g, rec);
	case GW_BUFFER_WRITE: return replay_result(g, rec);
	case GW_BUFFER_RECEIVE: return replay_receive(g, rec);
	default: return 0;
	}
}

/* What the rate and the window allow of the backlog, handed over. */
static void replay(struct gw *g, int64_t now)
{
	struct gw_sfwd *s = &g->sfwd;
	const struct gw_buffer_rec *recs;
	uint64_t nothing[GW_REPLAY_WINDOW], last = 0;
	size_t k = gw_replay_budget(&s->r, now, (size_t)(g->fmts.n > 0 ? g->fmts.n : 1)), nn = 0;
	int n;

	if (k == 0)
		return;
	if (k > GW_REPLAY_WINDOW)
		k = GW_REPLAY_WINDOW;
	n = gw_buffer_peek(s->b, k, &recs);
	if (n <= 0)
		return;
	for (int i = 0; i < n; i++) {
		last = recs[i].seq;
		if (replay_one(g, &recs[i]) == 0)
			nothing[nn++] = recs[i].seq;    /* nothing of it waits for a PUBACK: done with */
	}
	gw_buffer_handed(s->b, last);
	for (size_t i = 0; i < nn; i++)
		gw_buffer_ack(s->b, nothing[i]);
	s->r.replayed += nn;
	gw_replay_spent(&s->r, (size_t)n);
}

/* The retained PREFIX/status/buffer (JSON only). */
static void status_publish(struct gw *g)
{
	char topic[GW_TOPIC_MAX];

	g->sfwd.status_due = false;
	if (g->json_off || !gw_mqtt_up(&g->mq))
		return;
	gw_buf_reset(&g->key);
	gw_sfwd_json(g, &g->key);
	snprintf(topic, sizeof topic, "%s/status/buffer", g->prefix);
	if (!g->key.oom && gw_mqtt_publish_qos(&g->mq, topic, g->key.p, g->key.len, -1, true) == 0)
		g->health.published++;
	gw_buf_reset(&g->key);
}

/* The broker back: what this outage dropped, said once. */
static void outage_end(struct gw *g)
{
	struct gw_sfwd *s = &g->sfwd;
	struct gw_buffer_stats st;

	gw_buffer_stats(s->b, &st);
	if (s->outage_dropped)
		say(g, "buffer: %" PRIu64 " records dropped during the outage (bounds: --buffer-max, "
		    "--buffer-max-age); %" PRIu64 " to replay", s->outage_dropped, st.records);
	else if (st.records && g->cli.verbose)
		say(g, "buffer: %" PRIu64 " records to replay", st.records);
	s->outage_dropped = 0;
	s->full_said = false;
	s->status_due = true;
}

void gw_sfwd_turn(struct gw *g, int64_t now)
{
	struct gw_sfwd *s = &g->sfwd;
	bool up;

	if (!s->b)
		return;
	if (!gw_sfwd_capturing(g))
		memset(s->st_known, 0, sizeof s->st_known);     /* an outage starts with each station's state */
	if (s->lim.max_age_ms && now >= s->expire_next_ms) {
		gw_buffer_expire(s->b, sf_wall_ms());
		s->expire_next_ms = now + EXPIRE_EVERY_MS;
		drops_look(g);
	}
	up = gw_mqtt_up(&g->mq);
	if (up && !s->was_up)
		outage_end(g);
	s->was_up = up;
	if (!up || !sessions_ready(g))
		return;
	if (backlog(s) == 0) {
		if (s->draining) {
			/* drained: every tag and station retained and current again */
			s->draining = false;
			g->republish = true;
			s->status_due = true;
			if (s->outage_dropped)
				say(g, "buffer: %" PRIu64 " more records dropped before the backlog drained (bounds: "
				    "--buffer-max, --buffer-max-age)", s->outage_dropped);
			s->outage_dropped = 0;
			s->full_said = false;
			if (g->cli.verbose)
				say(g, "buffer: backlog replayed (%" PRIu64 " records so far)", s->r.replayed);
		}
		if (s->status_due)
			status_publish(g);
		return;
	}
	s->draining = true;
	replay(g, now);
}

int gw_sfwd_wait_ms(const struct gw *g, int64_t now)
{
	const struct gw_sfwd *s = &g->sfwd;

	/* nothing to replay now: a PUBACK, a STATE or the connection wakes the
	 * loop through the socket */
	if (!s->b || !gw_mqtt_up(&g->mq) || !sessions_ready(g) || backlog(s) == 0 || s->r.n >= GW_REPLAY_WINDOW)
		return 1000;
	return gw_replay_wait_ms(&s->r, now);
}

void gw_sfwd_acked(void *user, int mid)
{
	struct gw *g = user;
	uint64_t seq;

	if (!g->sfwd.b)
		return;
	if (gw_replay_acked(&g->sfwd.r, mid, &seq))
		gw_buffer_ack(g->sfwd.b, seq);
	else
		gw_live_acked(&g->sfwd.live, mid);
}

/* A live publication the drop cut off: into the buffer, replayed as historical. */
static void live_keep(void *u, struct gw_buffer_rec *r)
{
	struct gw *g = u;

	r->seq = 0;
	append(g, r);
}

void gw_sfwd_lost(void *user)
{
	struct gw *g = user;

	if (!g->sfwd.b)
		return;
	gw_buffer_rewind(g->sfwd.b);
	gw_replay_reset(&g->sfwd.r);
	gw_live_drain(&g->sfwd.live, live_keep, g);
}

/* ---- figures ---- */

bool gw_sfwd_on(const struct gw *g)
{
	return g->sfwd.b != NULL;
}

double gw_sfwd_figure(const struct gw *g, enum gw_sfwd_fig which)
{
	struct gw_buffer_stats st;

	if (!g->sfwd.b)
		return 0;
	gw_buffer_stats(g->sfwd.b, &st);
	switch (which) {
	case GW_SF_BUFFERED: return (double)st.appended;
	case GW_SF_DROPPED_SIZE: return (double)st.dropped_size;
	case GW_SF_DROPPED_AGE: return (double)st.dropped_age;
	case GW_SF_REPLAYED: return (double)g->sfwd.r.replayed;
	case GW_SF_RECORDS: return (double)st.records;
	case GW_SF_BYTES: return (double)st.bytes;
	case GW_SF_AGE_S: return st.records && st.oldest_ms ? (double)(sf_wall_ms() - st.oldest_ms) / 1000.0 : 0;
	case GW_SF_IN_MEMORY: return st.in_memory ? 1 : 0;
	}
	return 0;
}

void gw_sfwd_counters(const struct gw *g, FILE *out)
{
	if (!g->sfwd.b)
		return;
	fprintf(out, "buffer %.0f buffered, %.0f dropped (%.0f size, %.0f age), %.0f replayed, backlog %.0f records "
	        "%.0f bytes, oldest %.1f s, %s\n", gw_sfwd_figure(g, GW_SF_BUFFERED),
	        gw_sfwd_figure(g, GW_SF_DROPPED_SIZE) + gw_sfwd_figure(g, GW_SF_DROPPED_AGE),
	        gw_sfwd_figure(g, GW_SF_DROPPED_SIZE), gw_sfwd_figure(g, GW_SF_DROPPED_AGE),
	        gw_sfwd_figure(g, GW_SF_REPLAYED), gw_sfwd_figure(g, GW_SF_RECORDS), gw_sfwd_figure(g, GW_SF_BYTES),
	        gw_sfwd_figure(g, GW_SF_AGE_S), gw_sfwd_figure(g, GW_SF_IN_MEMORY) ? "in memory" : "on file");
}

void gw_sfwd_json(const struct gw *g, struct gw_buf *b)
{
	if (!g->sfwd.b) {
		gw_buf_puts(b, "null");
		return;
	}
	gw_buf_printf(b, "{\"storage\":\"%s\",\"buffered\":%.0f,\"dropped\":%.0f,\"dropped_size\":%.0f,"
	              "\"dropped_age\":%.0f,\"replayed\":%.0f,\"backlog_records\":%.0f,\"backlog_bytes\":%.0f,"
	              "\"backlog_age_seconds\":%.3f}", gw_sfwd_figure(g, GW_SF_IN_MEMORY) ? "memory" : "file",
	              gw_sfwd_figure(g, GW_SF_BUFFERED),
	              gw_sfwd_figure(g, GW_SF_DROPPED_SIZE) + gw_sfwd_figure(g, GW_SF_DROPPED_AGE),
	              gw_sfwd_figure(g, GW_SF_DROPPED_SIZE), gw_sfwd_figure(g, GW_SF_DROPPED_AGE),
	              gw_sfwd_figure(g, GW_SF_REPLAYED), gw_sfwd_figure(g, GW_SF_RECORDS),
	              gw_sfwd_figure(g, GW_SF_BYTES), gw_sfwd_figure(g, GW_SF_AGE_S));
}
