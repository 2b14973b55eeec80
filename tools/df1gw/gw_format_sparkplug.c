/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_format_sparkplug - Sparkplug B (Eclipse Sparkplug 3.0.0), a session
 * payload format of gw_format.h (df1gw(1), SPARKPLUG): the line is the edge
 * node, each station a device, each tag one or more metrics
 * (gw_spb_metrics.c). Topics spBv1.0/GROUP/TYPE/EDGE[/DEVICE]. The NDEATH of
 * each connection is its will (bdSeq counted by the gateway per connect);
 * NBIRTH (seq 0) and the DBIRTH of each station that answers follow every
 * connect and every rebirth; DDATA carries changed metrics; DDEATH when a
 * station goes offline. Commands: NCMD "Node Control/Rebirth", DCMD writes
 * through the gateway's write path. With a primary host, no birth before its
 * STATE says online. Pure: the gateway (gw_pub.c) does the I/O.
 */
#include "df1gw/gw_format.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1gw/gw_format_sparkplug.h"
#include "df1gw/gw_spb_codec.h"
#include "df1gw/gw_spb_metrics.h"

#define NS "spBv1.0"
#define NDATA_MS 10000           /* node metrics at most this often */
#define DUP_MS 10000             /* a DCMD without timestamp: the same bytes again within this are one command */
#define DUP_RING 32              /* such commands remembered */

/* The node metrics after "Node Control/Rebirth" and "bdSeq", aliases 1... */
enum { NM_DEVICE, NM_UP, NM_SCANS, NM_TRANSACTIONS, NM_READ_FAIL, NM_WRITE_FAIL, NM_RETRIES, NM_BIRTHS,
       NM_DEATHS, NM_COMMANDS, NM_REJECTED, NM_REBIRTHS, NM_COUNT };
static const char *const node_names[NM_COUNT] = {
	"Line/Device", "Line/Up", "Line/Scans", "Line/Transactions", "Line/Read failures", "Line/Write failures",
	"Line/Retries", "Sparkplug/Births", "Sparkplug/Deaths", "Sparkplug/Commands",
	"Sparkplug/Rejected commands", "Sparkplug/Rebirths",
};

struct spb {
	const struct gw_spb_conf *c;
	unsigned bdseq;
	unsigned seq;                /* of the next message that has one */
	bool connected, node_born, host_online;
	bool dev_born[GW_SPB_STATIONS];
	unsigned generation;
	int64_t next_ndata_ms;
	uint64_t node_sent[NM_COUNT];
	uint64_t births, deaths, commands, rejected, rebirths;
	struct gw_spb_list scratch;
	struct gw_buf tmp;
	/* per tag id: a hash of each of its metrics as the host was last told
	 * it (DBIRTH or DDATA, without times), so that a DDATA carries only the
	 * metrics that changed since */
	struct spb_told {
		uint64_t *h;
		size_t n;
	} *told;
	size_t ntold;
	uint64_t sent;               /* DDATA made: every change key is new */
	/* DCMDs without a payload timestamp lately taken: a hash of device and
	 * bytes, and when (monotonic ms), to know a redelivery (dcmd_again) */
	struct spb_dup {
		uint64_t h;
		int64_t ms;
	} dup[DUP_RING];
	unsigned dup_next;
	/* the primary host's last STATE timestamp taken (has_host_ts): an older
	 * STATE is a past session's, ignored (host_state) */
	bool has_host_ts;
	uint64_t host_ts;
};

/* A command's metric, as the write path carries it. */
struct spb_wr {
	struct gw_spb_metric m;
	char member[64];
	unsigned alias_member;
};

static struct spb *S(const struct gw_fmt *f)
{
	return f->priv;
}

static bool id_ok(const char *s)
{
	return s && *s && !strpbrk(s, "/+#");
}

static int spb_open(struct gw_fmt *f, char *err, size_t errcap)
{
	const struct gw_spb_conf *c = f->conf;
	struct spb *s;

	if (!c || !id_ok(c->group) || !id_ok(c->edge_node) || (c->primary_host && !id_ok(c->primary_host))) {
		snprintf(err, errcap, "sparkplug: the group, edge node and primary host ids are one topic level "
		         "each: not empty, without '/', '+' or '#'");
		return -1;
	}
	for (int i = 0; i < GW_SPB_STATIONS; i++) {
		if (c->device_name[i] && !id_ok(c->device_name[i])) {
			snprintf(err, errcap, "sparkplug: device name \"%s\" of station %d: one topic level, without "
			         "'/', '+' or '#'", c->device_name[i], i);
			return -1;
		}
	}
	s = calloc(1, sizeof *s);
	if (!s) {
		snprintf(err, errcap, "out of memory");
		return -1;
	}
	s->c = c;
	gw_spb_list_init(&s->scratch);
	gw_buf_init(&s->tmp);
	f->priv = s;
	return 0;
}

static void spb_close(struct gw_fmt *f)
{
	struct spb *s = S(f);

	if (!s)
		return;
	gw_spb_list_free(&s->scratch);
	gw_buf_free(&s->tmp);
	for (size_t i = 0; i < s->ntold; i++)
		free(s->told[i].h);
	free(s->told);
	free(s);
	f->priv = NULL;
}

static void device_name(const struct spb *s, int stn, char *out, size_t cap)
{
	if (s->c->device_name[stn])
		snprintf(out, cap, "%s", s->c->device_name[stn]);
	else
		snprintf(out, cap, "station%d", stn);
}

/* The station a device name names, or -1. */
static int device_station(const struct spb *s, const char *name)
{
	char d[80];

	for (int stn = 0; stn < GW_SPB_STATIONS; stn++) {
		device_name(s, stn, d, sizeof d);
		if (strcmp(d, name) == 0)
			return stn;
	}
	return -1;
}

/* m reset for TYPE of the node (stn < 0) or of station stn's device. */
static void start(const struct spb *s, struct gw_msg *m, const char *type, int stn, int qos)
{
	char d[80];

	gw_msg_reset(m);
	m->qos = qos;
	if (stn < 0) {
		snprintf(m->topic, sizeof m->topic, NS "/%s/%s/%s", s->c->group, type, s->c->edge_node);
	} else {
		device_name(s, stn, d, sizeof d);
		snprintf(m->topic, sizeof m->topic, NS "/%s/%s/%s/%s", s->c->group, type, s->c->edge_node, d);
	}
}

/* ---- data ---- */

/* The time of a tag's value: its read, or now when it is not good. */
static int64_t tag_ms(const struct gw_tag_out *t)
{
	if (t->quality < 0 && t->st->quality == DF1_QUALITY_GOOD && t->st->last_good_wall_ms > 0)
		return t->st->last_good_wall_ms;
	return t->wall_ms;
}

static uint64_t fnv1a_more(uint64_t h, const void *p, size_t n)
{
	const unsigned char *c = p;

	for (size_t i = 0; i < n; i++)
		h = (h ^ c[i]) * 1099511628211ull;
	return h;
}

static uint64_t fnv1a(const struct gw_buf *b)
{
	return fnv1a_more(14695981039346656037ull, b->p, b->len);
}

/* The host now knows tag id's metrics as h[0..n) (taken); chg[i] (when
 * not NULL) says whether metric i changed. Returns how many changed. */
static size_t tell(struct spb *s, int id, uint64_t *h, size_t n, bool *chg)
{
	struct spb_told *o;
	size_t k = 0;

	if (id < 0 || !h) {
		free(h);
		return n;
	}
	if ((size_t)id >= s->ntold) {
		size_t cap = (size_t)id + 64;
		struct spb_told *v = realloc(s->told, cap * sizeof *v);

		if (!v) {
			free(h);
			return n;       /* no memory: say all of it */
		}
		memset(v + s->ntold, 0, (cap - s->ntold) * sizeof *v);
		s->told = v;
		s->ntold = cap;
	}
	o = &s->told[id];
	for (size_t i = 0; i < n; i++) {
		bool c = o->n != n || o->h[i] != h[i];

		if (chg)
			chg[i] = c;
		k += c;
	}
	free(o->h);
	o->h = h;
	o->n = n;
	return k;
}

/* Tag t's metrics without times, a hash of each into *h (allocated); their number, 0 when out of memory. */
static size_t metric_hashes(struct spb *s, const struct gw_tag_out *t, uint64_t **h)
{
	struct gw_spb_how how = { false, false, false };
	size_t n;

	*h = NULL;
	gw_spb_list_reset(&s->scratch);
	if (gw_spb_tag_metrics(&s->scratch, t, 0, &how) < 0 || s->scratch.n == 0 ||
	    !(*h = malloc(s->scratch.n * sizeof **h))) {
		gw_spb_list_reset(&s->scratch);
		return 0;
	}
	n = s->scratch.n;
	for (size_t i = 0; i < n; i++) {
		s->scratch.v[i].timestamp = 0;
		(*h)[i] = gw_spb_encode(&s->tmp, 0, &s->scratch.v[i], 1) == 0 ? fnv1a(&s->tmp) : i;
	}
	gw_spb_list_reset(&s->scratch);
	return n;
}

/* The host is told tag t as it is now (a birth, a refused write's answer). */
static void tell_tag(struct spb *s, const struct gw_tag_out *t)
{
	uint64_t *h;
	size_t n = metric_hashes(s, t, &h);

	tell(s, t->st->id, h, n, NULL);
}

/* DDATA of the metrics of tag t that changed since the host was told them,
 * when its device is born; the change key is then always new (this format
 * keeps its own record). */
static int spb_tag(const struct gw_fmt *f, const struct gw_tag_out *t, struct gw_msg *m, struct gw_buf *key)
{
	struct spb *s = S(f);
	int stn = t->st->config->station;
	struct gw_spb_how how = { false, s->c->aliases, false };
	int64_t ms = tag_ms(t);
	uint64_t *h;
	bool *chg;
	size_t n, j = 0;
	int r;

	if (!s->node_born || stn < 0 || stn >= GW_SPB_STATIONS || !s->dev_born[stn] ||
	    !(t->st->config->access & DF1_ACCESS_READ))
		return -1;
	n = metric_hashes(s, t, &h);
	chg = n ? calloc(n, sizeof *chg) : NULL;
	if (!chg) {
		free(h);
		n = 0;          /* no memory: all of it */
	} else if (tell(s, t->st->id, h, n, chg) == 0) {
		free(chg);
		return -1;      /* the host knows it all */
	}
	gw_spb_list_reset(&s->scratch);
	r = gw_spb_tag_metrics(&s->scratch, t, ms, &how);
	for (size_t i = 0; i < s->scratch.n; i++)
		if (!chg || i >= n || chg[i])
			s->scratch.v[j++] = s->scratch.v[i];
	s->scratch.n = j;
	start(s, m, "DDATA", stn, 0);
	if (r == 0)
		r = gw_spb_encode(&m->body, ms > 0 ? (uint64_t)ms : 0, s->scratch.v, s->scratch.n);
	gw_spb_list_reset(&s->scratch);
	free(chg);
	if (r < 0)
		return -1;
	gw_buf_reset(key);
	gw_buf_printf(key, "%llu", (unsigned long long)++s->sent);
	return key->oom ? -1 : 0;
}

static int spb_nothing(const struct gw_fmt *f, const char *tag, struct gw_msg *m)
{
	(void)f;
	(void)tag;
	(void)m;
	return -1;
}

static int spb_station(const struct gw_fmt *f, const struct gw_station_out *st, struct gw_msg *m,
                       struct gw_buf *key)
{
	(void)f;
	(void)st;
	(void)m;
	(void)key;
	return -1;      /* a station is a device: its births and deaths come from tick */
}

/* A write's end: refused or failed, the metric's true value and quality again. */
static int spb_result(const struct gw_fmt *f, const struct gw_result_out *r, struct gw_msg *m)
{
	struct spb *s = S(f);

	if (r->ok)
		return -1;      /* the new value comes with the next read */
	s->rejected++;
	if (!r->now)
		return -1;
	{
		struct gw_spb_sample one = { r->now, r->now->wall_ms };
		int stn = r->now->st->config->station;

		if (!s->node_born || stn < 0 || stn >= GW_SPB_STATIONS || !s->dev_born[stn])
			return -1;
		tell_tag(s, r->now);
		start(s, m, "DDATA", stn, 0);
		return gw_spb_ddata_encode(&m->body, &s->scratch, &one, 1, false, s->c->aliases, one.ms);
	}
}

/* Store and forward's replay (gw_sfwd.c): the tag as it was read, DDATA with
 * is_historical, stamped with its read time, once its device is born again.
 * QoS 0 as every DDATA (Sparkplug 3.0): a QoS 1 message could be overtaken
 * in the broker by the QoS 0 ones that follow it, and a host would see the
 * seq out of order; the record goes when it is written to the connection. */
static int spb_tag_historical(const struct gw_fmt *f, const struct gw_tag_out *t, uint64_t seq, struct gw_msg *m)
{
	struct spb *s = S(f);
	struct gw_spb_sample one = { t, t->wall_ms };
	int stn = t->st->config->station;

	(void)seq;
	if (!s->node_born || stn < 0 || stn >= GW_SPB_STATIONS || !s->dev_born[stn] ||
	    !(t->st->config->access & DF1_ACCESS_READ))
		return -1;
	start(s, m, "DDATA", stn, 0);
	return gw_spb_ddata_encode(&m->body, &s->scratch, &one, 1, true, s->c->aliases, t->wall_ms);
}

static bool spb_ready(const struct gw_fmt *f)
{
	return S(f)->node_born;
}

/* NDEATH: bdSeq only (the will; said again before a clean disconnect). */
static int ndeath(const struct spb *s, struct gw_msg *m)
{
	struct gw_spb_metric bd;

	start(s, m, "NDEATH", -1, 1);
	gw_spb_metric_init(&bd);
	bd.name = "bdSeq";
	bd.datatype = GW_SPB_INT64;
	bd.kind = GW_SPB_V_LONG;
	bd.v.l = s->bdseq;
	return gw_spb_encode(&m->body, 0, &bd, 1);
}

static int spb_status(const struct gw_fmt *f, bool online, struct gw_msg *m)
{
	struct spb *s = S(f);

	if (online || !s->connected)
		return -1;
	s->deaths++;
	s->node_born = false;
	return ndeath(s, m);
}

static int spb_will(const struct gw_fmt *f, struct gw_msg *m)
{
	(void)f;
	(void)m;
	return -1;      /* will_next: one per connect */
}

static int spb_will_next(const struct gw_fmt *f, unsigned bdseq, struct gw_msg *m)
{
	struct spb *s = S(f);

	s->bdseq = bdseq & 0xFF;
	return ndeath(s, m);
}

static int spb_write_values(const struct gw_fmt *f, const struct gw_write_in *w, const struct df1_tag_config *c,
                            const struct df1_tag_state *cur, struct df1_value *out, size_t cap, size_t *n,
                            char *err, size_t errcap)
{
	const struct spb_wr *x = w->data;

	(void)f;
	return gw_spb_write_values(&x->m, x->member, x->alias_member, c, cur, out, cap, n, err, errcap);
}

static void spb_write_free(struct gw_write_in *w)
{
	free(w->data);
	w->data = NULL;
	w->id[0] = '\0';
}

/* ---- births and deaths ---- */

/* seq 0 on NBIRTH; then one more (0-255) on each DBIRTH, DDATA, DDEATH, NDATA. */
static void stamp(struct spb *s, struct gw_msg *m)
{
	const char *type = m->topic + strlen(NS) + 1;

	type = strchr(type, '/');
	if (!type)
		return;
	type++;
	if (strncmp(type, "NBIRTH/", 7) == 0) {
		gw_spb_append_seq(&m->body, 0);
		s->seq = 1;
	} else if (strncmp(type, "DBIRTH/", 7) == 0 || strncmp(type, "DDATA/", 6) == 0 ||
	           strncmp(type, "DDEATH/", 7) == 0 || strncmp(type, "NDATA/", 6) == 0) {
		gw_spb_append_seq(&m->body, s->seq);
		s->seq = (s->seq + 1) & 0xFF;
	}
}

/* A message of the session out at once, stamped. */
static void out(struct spb *s, const struct gw_node *n, struct gw_msg *m)
{
	stamp(s, m);
	n->emit(n->user, NULL, m);
}


/* The node metrics' values now. */
static void node_values(const struct spb *s, const struct gw_line_out *l, uint64_t v[NM_COUNT])
{
	v[NM_DEVICE] = 0;
	v[NM_UP] = l->up;
	v[NM_SCANS] = l->ps ? l->ps->scans : 0;
	v[NM_TRANSACTIONS] = l->ps ? l->ps->transactions : 0;
	v[NM_READ_FAIL] = l->ps ? l->ps->read_failures : 0;
	v[NM_WRITE_FAIL] = l->ps ? l->ps->write_failures : 0;
	v[NM_RETRIES] = l->ps ? l->ps->retries : 0;
	v[NM_BIRTHS] = s->births;
	v[NM_DEATHS] = s->deaths;
	v[NM_COMMANDS] = s->commands;
	v[NM_REJECTED] = s->rejected;
	v[NM_REBIRTHS] = s->rebirths;
}

/* Node metric i (birth: with its name) into the list. */
static void node_metric(struct spb *s, const struct gw_line_out *l, const uint64_t *v, int i, bool birth)
{
	struct gw_spb_metric *m = gw_spb_list_add(&s->scratch);

	if (!m)
		return;
	if (birth || !s->c->aliases)
		m->name = node_names[i];
	if (s->c->aliases) {
		m->has_alias = true;
		m->alias = (uint64_t)i + 1;
	}
	m->timestamp = (uint64_t)l->wall_ms;
	if (i == NM_DEVICE) {
		m->datatype = GW_SPB_STRING;
		m->kind = GW_SPB_V_STRING;
		m->str = l->device ? l->device : "";
		if (birth) {            /* the line's settings, as properties */
			m->prop_keys = l->setting_keys;
			m->prop_vals = l->setting_vals;
			m->nprops = l->nsettings;
		}
	} else if (i == NM_UP) {
		m->datatype = GW_SPB_BOOLEAN;
		m->kind = GW_SPB_V_BOOL;
		m->v.b = v[i] != 0;
	} else {
		m->datatype = GW_SPB_UINT64;
		m->kind = GW_SPB_V_LONG;
		m->v.l = v[i];
	}
}

static void nbirth(struct spb *s, const struct gw_node *n, const struct gw_line_out *l, struct gw_msg *m)
{
	struct gw_spb_metric *x;

	s->births++;
	gw_spb_list_reset(&s->scratch);
	x = gw_spb_list_add(&s->scratch);
	if (x) {                     /* never aliased: a host may write it before it knows aliases */
		x->name = "Node Control/Rebirth";
		x->datatype = GW_SPB_BOOLEAN;
		x->kind = GW_SPB_V_BOOL;
		x->timestamp = (uint64_t)l->wall_ms;
	}
	x = gw_spb_list_add(&s->scratch);
	if (x) {
		x->name = "bdSeq";
		x->datatype = GW_SPB_INT64;
		x->kind = GW_SPB_V_LONG;
		x->v.l = s->bdseq;
		x->timestamp = (uint64_t)l->wall_ms;
	}
	node_values(s, l, s->node_sent);
	for (int i = 0; i < NM_COUNT; i++)
		node_metric(s, l, s->node_sent, i, true);
	start(s, m, "NBIRTH", -1, 0);
	s->seq = 0;                  /* NBIRTH is seq 0 (stamp) */
	if (!s->scratch.oom && gw_spb_encode(&m->body, (uint64_t)l->wall_ms, s->scratch.v, s->scratch.n) == 0)
		out(s, n, m);
	gw_spb_list_reset(&s->scratch);
	s->node_born = true;
	s->next_ndata_ms = l->now_ms + NDATA_MS;
}

/* After a DBIRTH of station stn: the host knows each of its tags as it is. */
static void tell_all(struct spb *s, const struct gw_node *n, int stn)
{
	struct gw_spb_list keep = s->scratch;   /* the birth's metrics, being made */

	gw_spb_list_init(&s->scratch);
	for (int id = 0; id < n->ntags; id++) {
		struct df1_tag_state st;
		struct gw_tag_out t;
		char err[256];

		if (n->tag(n->user, id, &st, &t, err, sizeof err) && st.config->station == stn)
			tell_tag(s, &t);
	}
	gw_spb_list_free(&s->scratch);
	s->scratch = keep;
}

static void dbirth(struct spb *s, const struct gw_node *n, const struct gw_line_out *l, int stn, struct gw_msg *m)
{
	struct gw_spb_how how = { true, s->c->aliases, false };

	gw_spb_list_reset(&s->scratch);
	for (int id = 0; id < n->ntags; id++) {
		struct df1_tag_state st;
		struct gw_tag_out t;
		char err[256];

		if (n->tag(n->user, id, &st, &t, err, sizeof err) && st.config->station == stn)
			gw_spb_tag_metrics(&s->scratch, &t, tag_ms(&t), &how);
	}
	tell_all(s, n, stn);
	start(s, m, "DBIRTH", stn, 0);
	if (!s->scratch.oom && gw_spb_encode(&m->body, (uint64_t)l->wall_ms, s->scratch.v, s->scratch.n) == 0) {
		s->births++;
		s->dev_born[stn] = true;
		out(s, n, m);
	}
	gw_spb_list_reset(&s->scratch);
}

static void ddeath(struct spb *s, const struct gw_node *n, const struct gw_line_out *l, int stn, struct gw_msg *m)
{
	start(s, m, "DDEATH", stn, 0);
	s->dev_born[stn] = false;
	if (gw_spb_encode(&m->body, (uint64_t)l->wall_ms, NULL, 0) == 0) {
		s->deaths++;
		out(s, n, m);
	}
}

/* Born when it answers; dead when it is offline or the line is lost. */
static int device_wanted(const struct gw_node *n, const struct gw_line_out *l, int stn)
{
	struct gw_station_out so;
	struct df1_station_health sh;

	if (!n->station(n->user, stn, &so, &sh))
		return -1;
	if (!l->up || sh.state == DF1_STATION_OFFLINE || sh.state == DF1_STATION_ABSENT)
		return 0;
	return sh.state == DF1_STATION_OK ? 1 : 2;    /* 2: as it is (failing, not polled yet) */
}

/* NBIRTH, then the DBIRTH of every station that answers: on connect and rebirth. */
static void births(struct spb *s, const struct gw_node *n)
{
	struct df1_poll_stats ps;
	struct gw_line_out l;
	struct gw_msg m;

	n->line(n->user, &l, &ps);
	gw_msg_init(&m);
	memset(s->dev_born, 0, sizeof s->dev_born);
	s->generation = l.generation;
	nbirth(s, n, &l, &m);
	for (int stn = 0; stn < GW_SPB_STATIONS; stn++)
		if (device_wanted(n, &l, stn) == 1)
			dbirth(s, n, &l, stn, &m);
	gw_msg_free(&m);
}

static void spb_connected(const struct gw_fmt *f, const struct gw_node *n)
{
	struct spb *s = S(f);
	char topic[GW_TOPIC_MAX];

	s->connected = true;
	s->node_born = false;
	s->host_online = false;
	memset(s->dev_born, 0, sizeof s->dev_born);
	snprintf(topic, sizeof topic, NS "/%s/NCMD/%s", s->c->group, s->c->edge_node);
	n->subscribe(n->user, topic);
	snprintf(topic, sizeof topic, NS "/%s/DCMD/%s/+", s->c->group, s->c->edge_node);
	n->subscribe(n->user, topic);
	if (s->c->primary_host) {
		snprintf(topic, sizeof topic, NS "/STATE/%s", s->c->primary_host);
		n->subscribe(n->user, topic);
		snprintf(topic, sizeof topic, "STATE/%s", s->c->primary_host);    /* Sparkplug 2.x */
		n->subscribe(n->user, topic);
		return;         /* births when its STATE says online */
	}
	births(s, n);
}

/* NDATA of the node metrics that changed, at most every NDATA_MS. */
static void ndata(struct spb *s, const struct gw_node *n, const struct gw_line_out *l)
{
	uint64_t v[NM_COUNT];
	struct gw_msg m;

	if (l->now_ms < s->next_ndata_ms)
		return;
	s->next_ndata_ms = l->now_ms + NDATA_MS;
	node_values(s, l, v);
	gw_spb_list_reset(&s->scratch);
	for (int i = 0; i < NM_COUNT; i++)
		if (v[i] != s->node_sent[i])
			node_metric(s, l, v, i, false);
	memcpy(s->node_sent, v, sizeof v);
	if (s->scratch.n == 0)
		return;
	gw_msg_init(&m);
	start(s, &m, "NDATA", -1, 0);
	if (!s->scratch.oom && gw_spb_encode(&m.body, (uint64_t)l->wall_ms, s->scratch.v, s->scratch.n) == 0)
		out(s, n, &m);
	gw_spb_list_reset(&s->scratch);
	gw_msg_free(&m);
}

static void spb_tick(const struct gw_fmt *f, const struct gw_node *n)
{
	struct spb *s = S(f);
	struct df1_poll_stats ps;
	struct gw_line_out l;
	struct gw_msg m;

	if (!s->node_born)
		return;
	n->line(n->user, &l, &ps);
	if (l.generation != s->generation) {
		births(s, n);   /* the tags changed (a reload): every birth again */
		return;
	}
	gw_msg_init(&m);
	for (int stn = 0; stn < GW_SPB_STATIONS; stn++) {
		int want = device_wanted(n, &l, stn);

		if (want == 1 && !s->dev_born[stn])
			dbirth(s, n, &l, stn, &m);
		else if (want == 0 && s->dev_born[stn])
			ddeath(s, n, &l, stn, &m);
	}
	gw_msg_free(&m);
	ndata(s, n, &l);
}

/* ---- commands and the primary host ---- */

static void say(const struct gw_node *n, const char *fmt, const char *a, const char *b)
{
	char text[400];

	snprintf(text, sizeof text, fmt, a, b);
	n->log(n->user, text);
}

/* spBv1.0/STATE/HOST: {"online":true|false,"timestamp":...} (3.0); STATE/HOST:
 * ONLINE / OFFLINE (2.x, no timestamp). A STATE whose timestamp is older than
 * the last one taken is a past session's (an old will delivered late): ignored,
 * as tck-id-message-flow-edge-node-birth-publish-phid-wait-timestamp and
 * tck-id-operational-behavior-edge-node-termination-host-offline-timestamp ask. */
static void host_state(struct spb *s, const struct gw_node *n, const char *p, size_t len)
{
	char err[120], *end;
	struct gw_jv *v = gw_json_parse(p, len, err, sizeof err);
	const struct gw_jv *on = v && v->type == GW_JOBJECT ? gw_jv_get(v, "online") : NULL;
	const struct gw_jv *ts = v && v->type == GW_JOBJECT ? gw_jv_get(v, "timestamp") : NULL;
	int online = on && on->type == GW_JBOOL ? on->b : -1;
	bool has_ts = false;
	uint64_t t = 0;

	if (online >= 0 && ts && ts->type == GW_JNUMBER && ts->text[0] != '-') {
		t = strtoull(ts->text, &end, 10);
		has_ts = end != ts->text && *end == '\0';
	}
	gw_jv_free(v);
	if (online < 0 && len == 6 && memcmp(p, "ONLINE", 6) == 0)
		online = 1;
	if (online < 0 && len == 7 && memcmp(p, "OFFLINE", 7) == 0)
		online = 0;
	if (online < 0) {
		say(n, "sparkplug: STATE of %s: not a state payload%s", s->c->primary_host, "");
		return;
	}
	if (has_ts && s->has_host_ts && t < s->host_ts) {
		char a[48];

		snprintf(a, sizeof a, "%llu < %llu", (unsigned long long)t, (unsigned long long)s->host_ts);
		say(n, "sparkplug: STATE of %s older than the last one taken (timestamp %s): ignored",
		    s->c->primary_host, a);
		return;
	}
	if (has_ts) {
		s->has_host_ts = true;
		s->host_ts = t;
	}
	s->host_online = online;
	if (online && !s->node_born) {
		births(s, n);
	} else if (!online && s->node_born) {
		struct gw_msg m;

		/* the primary host is gone: NDEATH, and a new session to wait for it */
		say(n, "sparkplug: primary host %s offline: NDEATH and reconnecting%s", s->c->primary_host, "");
		gw_msg_init(&m);
		if (ndeath(s, &m) == 0) {
			s->deaths++;
			out(s, n, &m);
		}
		gw_msg_free(&m);
		s->node_born = false;
		s->connected = false;
		n->reconnect(n->user);
	}
}

/* NCMD: Node Control/Rebirth = true rebirths; other node controls are ignored. */
static void ncmd(struct spb *s, const struct gw_node *n, const struct gw_spb_in *in)
{
	for (size_t i = 0; i < in->n; i++) {
		struct gw_spb_metric m;

		gw_spb_metric_at(in, i, &m);
		if (m.name && strcmp(m.name, "Node Control/Rebirth") == 0 && m.kind == GW_SPB_V_BOOL && m.v.b) {
			if (!s->node_born)
				continue;
			s->rebirths++;
			births(s, n);   /* same bdSeq, no NDEATH, no disconnect */
		} else {
			say(n, "sparkplug: NCMD %s: not a node control df1gw takes, ignored%s",
			    m.name ? m.name : "(alias)", "");
			s->rejected++;
		}
	}
}

/* The tag a command's metric names, its name into tag: by name, or by alias. */
static bool cmd_tag(const struct gw_node *n, const struct gw_spb_metric *m, struct spb_wr *w, char *tag,
                    size_t cap, int *stn)
{
	const char *member;
	int id;
	struct df1_tag_state st;
	struct gw_tag_out t;
	char err[256];

	if (!gw_spb_metric_target(m, tag, cap, &member, &id, &w->alias_member))
		return false;
	snprintf(w->member, sizeof w->member, "%s", member);
	if (id >= 0) {
		if (!n->tag(n->user, id, &st, &t, err, sizeof err))
			return false;
		snprintf(tag, cap, "%s", st.config->name);
	} else {
		for (id = 0; id < n->ntags; id++)
			if (n->tag(n->user, id, &st, &t, err, sizeof err) && strcmp(st.config->name, tag) == 0)
				break;
		if (id == n->ntags)
			return false;
	}
	*stn = st.config->station;
	return true;
}

/* A DCMD without a payload timestamp (tck-id-payloads-dcmd-timestamp says it
 * has one; Ignition's MQTT Engine always sends it) that is the same bytes to
 * the same device as one taken less than DUP_MS ago: a redelivery (QoS 1 DUP,
 * a publisher's resend), not executed again. Else it is remembered. */
static bool dcmd_again(struct spb *s, const struct gw_node *n, const char *device, const void *p, size_t len)
{
	struct df1_poll_stats ps;
	struct gw_line_out l;
	uint64_t h = fnv1a_more(14695981039346656037ull, device, strlen(device) + 1);

	h = fnv1a_more(h, p, len);
	n->line(n->user, &l, &ps);
	for (unsigned i = 0; i < DUP_RING; i++)
		if (s->dup[i].ms && s->dup[i].h == h && l.now_ms - s->dup[i].ms < DUP_MS)
			return true;
	s->dup[s->dup_next].h = h;
	s->dup[s->dup_next].ms = l.now_ms ? l.now_ms : 1;
	s->dup_next = (s->dup_next + 1) % DUP_RING;
	return false;
}

/* DCMD: each metric a write of its tag, through the gateway's write path, at
 * most once (df1gw(1), SPARKPLUG): with a payload timestamp, each metric's
 * id is device, timestamp, a hash of the payload's bytes and the metric's
 * index, remembered by the gateway's id ring as a JSON write's id is; without
 * one, the same bytes within DUP_MS are taken once (dcmd_again). */
static void dcmd(struct spb *s, const struct gw_fmt *f, const struct gw_node *n, const char *device,
                 const struct gw_spb_in *in, const void *p, size_t len, bool retain)
{
	int want = device_station(s, device);
	uint64_t h = fnv1a_more(14695981039346656037ull, p, len);

	if (!in->has_timestamp && !retain && dcmd_again(s, n, device, p, len)) {
		say(n, "sparkplug: DCMD %s: the same payload again without a timestamp: taken as a redelivery, "
		    "not executed again%s", device, "");
		return;
	}
	for (size_t i = 0; i < in->n; i++) {
		struct gw_write_in w;
		struct spb_wr *x = calloc(1, sizeof *x);
		char tag[80];
		int stn = -1;

		if (!x)
			return;
		gw_spb_metric_at(in, i, &x->m);
		if (!cmd_tag(n, &x->m, x, tag, sizeof tag, &stn) || stn != want) {
			say(n, "sparkplug: DCMD %s: no metric %s of this device, refused", device,
			    x->m.name ? x->m.name : "(alias)");
			s->rejected++;
			free(x);
			continue;
		}
		memset(&w, 0, sizeof w);
		if (in->has_timestamp)
			snprintf(w.id, sizeof w.id, "spb:%s:%llu:%016llx:%zu", device,
			         (unsigned long long)in->timestamp, (unsigned long long)h, i);
		w.data = x;
		n->write(n->user, f, tag, &w, retain);
	}
}

static bool spb_message(const struct gw_fmt *f, const struct gw_node *n, const char *topic, const void *payload,
                        size_t len, bool retain)
{
	struct spb *s = S(f);
	char pre[GW_TOPIC_MAX];
	struct gw_spb_in in;
	size_t pl;

	if (s->c->primary_host) {
		snprintf(pre, sizeof pre, NS "/STATE/%s", s->c->primary_host);
		if (strcmp(topic, pre) == 0 || strcmp(topic, pre + strlen(NS) + 1) == 0) {
			host_state(s, n, payload, len);
			return true;
		}
	}
	snprintf(pre, sizeof pre, NS "/%s/NCMD/%s", s->c->group, s->c->edge_node);
	if (strcmp(topic, pre) != 0) {
		snprintf(pre, sizeof pre, NS "/%s/DCMD/%s/", s->c->group, s->c->edge_node);
		pl = strlen(pre);
		if (strncmp(topic, pre, pl) != 0 || !topic[pl] || strchr(topic + pl, '/'))
			return false;
	}
	s->commands++;
	if (gw_spb_decode(payload, len, &in) < 0) {
		say(n, "sparkplug: %s: not a Sparkplug B payload, refused%s", topic, "");
		s->rejected++;
		return true;
	}
	if (strstr(topic, "/NCMD/"))
		ncmd(s, n, &in);
	else
		dcmd(s, f, n, topic + strlen(pre), &in, payload, len, retain);
	gw_spb_in_free(&in);
	return true;
}

static void spb_stamp(const struct gw_fmt *f, struct gw_msg *m)
{
	stamp(S(f), m);
}

static int spb_counters(const struct gw_fmt *f, char *out, size_t cap)
{
	const struct spb *s = S(f);

	snprintf(out, cap, "sparkplug: %llu births, %llu deaths, %llu commands (%llu rejected), %llu rebirths, "
	         "bdSeq %u", (unsigned long long)s->births, (unsigned long long)s->deaths,
	         (unsigned long long)s->commands, (unsigned long long)s->rejected,
	         (unsigned long long)s->rebirths, s->bdseq);
	return 0;
}

static size_t spb_figures(const struct gw_fmt *f, struct gw_figure *out, size_t cap)
{
	const struct spb *s = S(f);
	const struct gw_figure v[] = {
		{ "births_total", "counter", "Sparkplug NBIRTH and DBIRTH messages published", (double)s->births },
		{ "deaths_total", "counter", "Sparkplug NDEATH and DDEATH messages published", (double)s->deaths },
		{ "commands_total", "counter", "Sparkplug NCMD and DCMD messages taken", (double)s->commands },
		{ "commands_rejected_total", "counter", "Sparkplug commands refused", (double)s->rejected },
		{ "rebirths_total", "counter", "Sparkplug rebirths asked by Node Control/Rebirth", (double)s->rebirths },
		{ "bdseq", "gauge", "the bdSeq of the Sparkplug session", (double)s->bdseq },
	};
	size_t n = sizeof v / sizeof v[0] < cap ? sizeof v / sizeof v[0] : cap;

	memcpy(out, v, n * sizeof *out);
	return n;
}

const struct gw_format gw_format_sparkplug = {
	.name = "sparkplug",
	.open = spb_open,
	.close = spb_close,
	.tag = spb_tag,
	.tag_gone = spb_nothing,
	.station = spb_station,
	.result = spb_result,
	.status = spb_status,
	.will = spb_will,
	.set_pattern = NULL,
	.set_tag = NULL,
	.write_parse = NULL,
	.write_values = spb_write_values,
	.write_free = spb_write_free,
	.session = true,
	.will_next = spb_will_next,
	.connected = spb_connected,
	.tick = spb_tick,
	.message = spb_message,
	.stamp = spb_stamp,
	.counters = spb_counters,
	.figures = spb_figures,
	.tag_historical = spb_tag_historical,
	.ready = spb_ready,
};
