/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_receive.c - df1gw's Receive rows (gw_receive.h; df1gw(1), RECEIVE): the
 * data table PLCs write with MSG, served on the line through the table's own
 * callbacks (df1_table_server_ops(3)) wrapped so that a write outside the
 * declared regions is refused as a PLC refuses it, and each write that lands
 * is published with its sender (df1_server_source(3)).
 */
#include "df1gw/gw.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ms since the epoch (gw_pub.c's gw_wall_ms is not called from here: it calls us) */
static int64_t rx_wall_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* ---- the rows ---- */

struct rx_load {
	struct gw *g;
	df1_t *h;
	int bad;
};

/* The elements a row covers: its last element's index. */
static int rx_last_element(const struct df1_tag_config *c)
{
	int bits = c->addr.type == DF1_FT_L ? 32 : 16;

	if (c->addr.bit != DF1_ADDR_NONE)
		return c->addr.element + (c->addr.bit + c->count - 1) / bits;
	return c->addr.element + c->count - 1;
}

static int rx_row_check(struct rx_load *l, const struct df1_tag_config *c)
{
	struct gw *g = l->g;

	if (c->station != g->cli.src) {
		fprintf(stderr, "%s: %s: Receive tag \"%s\": Station %d is not df1gw's own station %d (--src, or the "
		        "network file's Station): a Receive row declares a region of df1gw's data table\n", GW_PROG,
		        g->map_path, c->name, c->station, g->cli.src);
		return -1;
	}
	if (!*c->name || strpbrk(c->name, "/+#") || !gw_utf8_valid(c->name, strlen(c->name))) {
		fprintf(stderr, "%s: %s: tag \"%s\": a name cannot hold '/', '+' or '#' and must be UTF-8 (it is one "
		        "level of the topic PREFIX/tag/NAME)\n", GW_PROG, g->map_path, c->name);
		return -1;
	}
	if (gw_rx_has(g, c->name) || (l->h && df1_tag_find(l->h, c->name) >= 0)) {
		fprintf(stderr, "%s: %s: tag \"%s\" is named twice\n", GW_PROG, g->map_path, c->name);
		return -1;
	}
	if (c->addr.ascii[0] || df1_tag_value_kind(c) < 0) {
		fprintf(stderr, "%s: %s: Receive tag \"%s\": its Type does not fit its Address\n", GW_PROG,
		        g->map_path, c->name);
		return -1;
	}
	return 0;
}

static int rx_row(void *user, const struct df1_tag_config *c)
{
	struct rx_load *l = user;
	struct gw_rx *rx = &l->g->rx;
	struct gw_rx_tag *nv, *e;
	size_t esize = (size_t)df1_file_type_element_size(c->addr.type);

	if (c->access != DF1_ACCESS_RECEIVE)
		return 0;
	if (rx_row_check(l, c) < 0) {
		l->bad++;
		return 0;
	}
	nv = realloc(rx->v, (rx->n + 1) * sizeof *nv);
	if (!nv)
		return DF1_E_NOMEM;
	rx->v = nv;
	e = &rx->v[rx->n++];
	memset(e, 0, sizeof *e);
	e->c = *c;
	e->shown = *c;
	e->shown.access = DF1_ACCESS_READWRITE;
	e->lo = (size_t)c->addr.element * esize;
	e->hi = (size_t)(rx_last_element(c) + 1) * esize;
	e->from = -1;
	return 0;
}

/* The table: each region's file, as long as its last element needs. */
static int rx_table(struct gw *g)
{
	struct gw_rx *rx = &g->rx;
	int r;

	if (df1_table_new(&rx->t, g->cli.plc) < 0)
		return -1;
	for (size_t i = 0; i < rx->n; i++) {
		const struct df1_tag_config *c = &rx->v[i].c;

		r = df1_table_add_file(rx->t, c->addr.type, c->addr.file, rx_last_element(c) + 1);
		if (r < 0) {
			fprintf(stderr, "%s: %s: Receive tag \"%s\": file %s%d: %s\n", GW_PROG, g->map_path, c->name,
			        df1_file_type_name(c->addr.type), c->addr.file,
			        r == DF1_E_TYPE ? "another Receive row gives it another type" : df1_strerror(r));
			return -1;
		}
	}
	return 0;
}

int gw_rx_load(struct gw *g, df1_t *h)
{
	struct rx_load l = { g, h, 0 };
	int r;

	gw_rx_free(&g->rx);
	g->rx.g = g;
	g->rx.station = g->cli.src;
	g->rx.slave = g->cli.half_slave;
	if (!g->map_path)
		return 0;
	r = df1_map_load(g->map_path, true, rx_row, NULL, &l);
	if (r < 0 || l.bad) {
		if (r == DF1_E_NOMEM)
			fprintf(stderr, "%s: out of memory\n", GW_PROG);
		gw_rx_free(&g->rx);
		return CLI_EXIT_USAGE;
	}
	if (g->rx.n && rx_table(g) < 0) {
		gw_rx_free(&g->rx);
		return CLI_EXIT_USAGE;
	}
	/* no PLC has sent a value yet: the regions hold zeros, not the table's
	 * initial pattern, and are told as no message yet (gw_rx_table.h) */
	if (g->rx.n && (r = gw_rx_zero(&g->rx)) < 0) {
		fprintf(stderr, "%s: %s: the Receive rows' table: %s\n", GW_PROG, g->map_path, df1_strerror(r));
		gw_rx_free(&g->rx);
		return CLI_EXIT_USAGE;
	}
	return 0;
}

bool gw_rx_has(const struct gw *g, const char *name)
{
	for (size_t i = 0; i < g->rx.n; i++)
		if (strcmp(g->rx.v[i].c.name, name) == 0)
			return true;
	return false;
}

void gw_rx_free(struct gw_rx *rx)
{
	df1_table_free(rx->t);
	free(rx->v);
	rx->t = NULL;
	rx->v = NULL;
	rx->n = 0;
}

/* ---- publishing ---- */

static void rx_emit(struct gw *g, const struct gw_fmt *f, struct gw_msg *m)
{
	if (f->ops->stamp)
		f->ops->stamp(f, m);
	int mid = 0;

	if (gw_mqtt_publish_mid(&g->mq, m->topic, m->body.p ? m->body.p : "", m->body.len, m->qos, m->retain, &mid) < 0)
		return;
	if ((m->qos < 0 ? g->qos : m->qos) > 0)
		gw_sfwd_live_mid(g, mid);       /* kept until its PUBACK (rx_publish) */
	g->health.published++;
	if (g->cli.verbose && !g->cli.quiet)
		fprintf(stderr, "%s: > %s %.*s\n", GW_PROG, m->topic, (int)m->body.len, m->body.p ? m->body.p : "");
}

/* Tag e by every format (JSON: with "from"; Sparkplug: a DDATA of the
 * metrics that changed, df1gw(1) RECEIVE). */
static void rx_publish(struct gw *g, struct gw_rx_tag *e)
{
	static struct df1_value vals[DF1_TABLE_ELEMENTS_MAX];
	struct df1_tag_state st;
	struct gw_tag_out t;
	const char *reason;

	if (gw_rx_row_state(&g->rx, g->ntags, e, true, &st, vals, &reason) < 0)
		return;
	t = (struct gw_tag_out){ .st = &st, .reason = reason, .quality = -1, .wall_ms = rx_wall_ms() };
	if (gw_sfwd_capturing(g)) {
		/* the broker away, or a backlog before it: in the buffer, in order
		 * (df1gw(1), STORE AND FORWARD) */
		gw_sfwd_receive(g, &t, e->from);
		return;
	}
	if (!gw_mqtt_up(&g->mq))
		return;
	/* store and forward: a message the drop of the connection cuts off
	 * before its PUBACK goes into the buffer, not lost */
	gw_sfwd_live_receive(g, &t, e->from);
	for (int i = 0; i < g->fmts.n; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (f->ops->tag(f, &t, &g->msg, &g->key) < 0)
			continue;       /* Sparkplug: no DDATA when no metric changed */
		if (e->from >= 0 && strcmp(f->ops->name, "json") == 0 && gw_msg_json_add_int(&g->msg, "from", e->from) < 0)
			continue;
		rx_emit(g, f, &g->msg);
	}
	gw_sfwd_live_close(g);
}

bool gw_rx_node_tag(struct gw *g, int i, struct df1_tag_state *st, struct gw_tag_out *t)
{
	static struct df1_value vals[DF1_TABLE_ELEMENTS_MAX];
	const char *reason;

	if (i < 0 || (size_t)i >= g->rx.n || gw_rx_row_state(&g->rx, g->ntags, &g->rx.v[i], true, st, vals, &reason) < 0)
		return false;
	*t = (struct gw_tag_out){ .st = st, .reason = reason, .quality = -1, .wall_ms = rx_wall_ms() };
	return true;
}

bool gw_rx_node_station(struct gw *g, int stn, struct gw_station_out *s, struct df1_station_health *sh)
{
	if (!g->rx.n || stn != g->rx.station || g->stations[stn])
		return false;
	memset(sh, 0, sizeof *sh);
	sh->station = stn;
	sh->state = g->line_up ? DF1_STATION_OK : DF1_STATION_OFFLINE;
	sh->tags = (int)g->rx.n;
	*s = (struct gw_station_out){ stn, g->line_up ? "ok" : "offline", NULL, sh, 0 };
	return true;
}

void gw_rx_publish_all(struct gw *g)
{
	for (size_t i = 0; i < g->rx.n; i++)
		rx_publish(g, &g->rx.v[i]);
}

/* ---- the line's side: the table's callbacks, checked against the regions ---- */

static size_t rx_offset(const struct df1_addr *a)
{
	return (size_t)a->element * (size_t)df1_file_type_element_size(a->type) +
	       (a->sub == DF1_ADDR_NONE ? 0 : (size_t)a->sub * 2);
}

/* Do the regions of a's file cover [lo, hi)? */
static bool rx_covered(const struct gw_rx *rx, const struct df1_addr *a, size_t lo, size_t hi)
{
	bool grew = true;

	while (lo < hi && grew) {
		grew = false;
		for (size_t i = 0; i < rx->n; i++) {
			const struct gw_rx_tag *e = &rx->v[i];

			if (e->c.addr.type == a->type && e->c.addr.file == a->file && e->lo <= lo && e->hi > lo) {
				lo = e->hi;
				grew = true;
			}
		}
	}
	return lo >= hi;
}

/* The table's answer first (06 no such file, 07 beyond it, ...); a gap
 * between regions of one file is refused as an element beyond the file. */
static int rx_check(struct gw_rx *rx, int station, const struct df1_addr *a, size_t nbytes)
{
	static uint8_t scratch[512];    /* more than a DF1 frame's data */
	const struct df1_server_ops *ops = df1_table_server_ops(rx->t);
	int rc = ops->read(rx->t, station, a, scratch, nbytes > sizeof scratch ? 0 : nbytes);
	size_t lo = rx_offset(a);

	if (rc || nbytes == 0)
		return rc;
	return rx_covered(rx, a, lo, lo + nbytes) ? 0 : 0x07;
}

static int rx_op_read(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes)
{
	struct gw_rx *rx = user;
	int rc = rx_check(rx, station, a, nbytes);

	return rc ? rc : df1_table_server_ops(rx->t)->read(rx->t, station, a, buf, nbytes);
}

static int rx_op_write(void *user, int station, const struct df1_addr *a, const uint8_t *buf,
                       const uint8_t *mask, size_t nbytes)
{
	struct gw_rx *rx = user;
	struct gw *g = rx->g;
	size_t lo = rx_offset(a), hi = lo + nbytes;
	int rc = rx_check(rx, station, a, nbytes);

	if (!rc)
		rc = df1_table_server_ops(rx->t)->write(rx->t, station, a, buf, mask, nbytes);
	if (rc)
		return rc;
	for (size_t i = 0; i < rx->n; i++) {
		struct gw_rx_tag *e = &rx->v[i];

		if (e->c.addr.type != a->type || e->c.addr.file != a->file || e->hi <= lo || e->lo >= hi)
			continue;
		e->written = true;
		e->from = df1_server_source(g->h);
		e->wall_ms = rx_wall_ms();
		rx->received++;
		rx_publish(g, e);
	}
	return 0;
}

static int rx_op_diag(void *user, int station, uint8_t *buf, size_t cap)
{
	struct gw_rx *rx = user;

	return df1_table_server_ops(rx->t)->diag_status(rx->t, station, buf, cap);
}

static int rx_op_mode(void *user, int station, int mode)
{
	struct gw_rx *rx = user;

	return df1_table_server_ops(rx->t)->change_mode(rx->t, station, mode);
}

static const struct df1_server_ops rx_ops = {
	.read = rx_op_read,
	.write = rx_op_write,
	.diag_status = rx_op_diag,
	.change_mode = rx_op_mode,
};

int gw_rx_attach(struct gw *g, df1_t *h)
{
	if (!g->rx.n)
		return 0;
	if (g->rx.slave)
		return df1_server_add_station(h, g->rx.station);
	return df1_set_responder(h, &rx_ops, &g->rx);
}

int gw_rx_fd(const struct gw *g)
{
	return g->rx.n && g->line_up ? df1_port_fd(g->h) : -1;
}

int gw_rx_serve(struct gw *g, bool readable)
{
	/* a deadline of now reads nothing: 1 ms drives the reply's timers, 10 ms
	 * takes a frame that is arriving (it returns once one is served) */
	int r = df1_serve(g->h, &rx_ops, &g->rx, readable ? 10 : 1);

	return r == DF1_E_TIMEOUT ? 0 : r < 0 ? r : 0;
}

/* ---- writes from MQTT: the table only ---- */

static void rx_result(struct gw *g, const struct gw_fmt *f, const char *tag, const char *id, const char *error)
{
	struct gw_result_out r = { tag, id, error == NULL, error, false, NULL };

	if (!g->cli.quiet && error && g->cli.verbose)
		fprintf(stderr, "%s: write %s%s%s: %s\n", GW_PROG, tag, *id ? " id " : "", id, error);
	if (f->ops->result(f, &r, &g->msg) == 0 && gw_mqtt_up(&g->mq))
		rx_emit(g, f, &g->msg);
}

/* Write in's values into tag e's region: NULL, or why not (in err's room). */
static const char *rx_set(struct gw *g, const struct gw_fmt *f, struct gw_rx_tag *e, const struct gw_write_in *in,
                          bool retain, char *err, size_t cap)
{
	static struct df1_value cur[DF1_TABLE_ELEMENTS_MAX], vals[DF1_TABLE_ELEMENTS_MAX];
	struct df1_tag_state st;
	const char *reason;
	size_t n = 0;
	int r;

	if (retain)
		return "a retained message is not a write: publish .../set without the retain flag";
	/* the values the table holds (zeros before a first write): a write of
	 * some elements or members keeps the others */
	if ((r = gw_rx_row_state(&g->rx, g->ntags, e, false, &st, cur, &reason)) < 0)
		return df1_strerror(r);
	if (f->ops->write_values(f, in, &e->shown, &st, vals, DF1_TABLE_ELEMENTS_MAX, &n, err, cap) < 0)
		return err;
	if (df1_table_write_addr(g->rx.t, &e->c.addr, vals, n) < 0) {
		snprintf(err, cap, "%s", df1_table_error_text(g->rx.t));
		return err;
	}
	return NULL;
}

bool gw_rx_write(struct gw *g, const struct gw_fmt *f, const char *name, struct gw_write_in *in, bool retain)
{
	struct gw_rx_tag *e = NULL;
	const char *why;
	char err[700];

	for (size_t i = 0; i < g->rx.n && !e; i++)
		if (strcmp(g->rx.v[i].c.name, name) == 0)
			e = &g->rx.v[i];
	if (!e)
		return false;
	why = rx_set(g, f, e, in, retain, err, sizeof err);
	rx_result(g, f, name, in->id, why);
	if (!why) {
		e->written = true;      /* a value someone sent: GOOD from now on */
		e->from = -1;           /* the table's value, not a PLC's message */
		e->wall_ms = rx_wall_ms();
		rx_publish(g, e);
	}
	f->ops->write_free(in);
	return true;
}
