/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_spb_session.c - the Sparkplug B format's session rules
 * (tools/df1gw/gw_format_sparkplug.c) against a node played by the test: a
 * DCMD executed at most once (df1gw(1), SPARKPLUG, Commands: with a payload
 * timestamp, an id of device, timestamp and payload; without one, the same
 * bytes within 10 s are one command), and the primary host's STATE taken in
 * timestamp order (Sparkplug 3.0 tck-id-message-flow-edge-node-birth-publish-
 * phid-wait-timestamp and tck-id-operational-behavior-edge-node-termination-
 * host-offline-timestamp: an older STATE is ignored). The commands are built
 * with the codec (gw_spb_codec.c), whose bytes test_gw_sparkplug.c checks by hand.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1.h"
#include "df1gw/gw_format.h"
#include "df1gw/gw_format_sparkplug.h"
#include "df1gw/gw_spb_codec.h"

/* The node: one tag, Speed (N7:0, ReadWrite, station 1), always answering. */
static struct node {
	struct df1_tag_config cfg;
	struct df1_value val;
	int64_t now_ms;
	int writes, nbirths, ndeaths, reconnects;
	char ids[8][GW_WRITE_ID_MAX + 1];
} N;

static bool n_tag(void *u, int id, struct df1_tag_state *st, struct gw_tag_out *t, char *e, size_t c)
{
	(void)u; (void)e; (void)c;
	if (id != 0)
		return false;
	memset(st, 0, sizeof *st);
	st->config = &N.cfg;
	st->count = 1;
	st->values = &N.val;
	st->value = N.val;
	st->has_value = true;
	st->quality = DF1_QUALITY_GOOD;
	*t = (struct gw_tag_out){ st, NULL, -1, NULL, 0 };
	t->wall_ms = 1796166900000LL;
	return true;
}

static bool n_station(void *u, int stn, struct gw_station_out *s, struct df1_station_health *sh)
{
	(void)u;
	if (stn != 1)
		return false;
	memset(sh, 0, sizeof *sh);
	sh->state = DF1_STATION_OK;
	*s = (struct gw_station_out){ stn, "ok", NULL, sh, 0 };
	return true;
}

static void n_line(void *u, struct gw_line_out *l, struct df1_poll_stats *ps)
{
	(void)u;
	memset(ps, 0, sizeof *ps);
	*l = (struct gw_line_out){ true, "test", ps, 1, 1796166900000LL + N.now_ms, N.now_ms, NULL, NULL, 0 };
}

static void n_emit(void *u, const struct gw_fmt *f, struct gw_msg *m)
{
	(void)u; (void)f;
	N.nbirths += strstr(m->topic, "/NBIRTH/") != NULL;
	N.ndeaths += strstr(m->topic, "/NDEATH/") != NULL;
}

static int n_sub(void *u, const char *p)
{
	(void)u; (void)p;
	return 0;
}

static void n_write(void *u, const struct gw_fmt *f, const char *tag, struct gw_write_in *w, bool retain)
{
	(void)u; (void)retain;
	assert_string_equal(tag, "Speed");
	if (N.writes < 8)
		snprintf(N.ids[N.writes], sizeof N.ids[0], "%s", w->id);
	N.writes++;
	f->ops->write_free(w);
}

static void n_reconnect(void *u)
{
	(void)u;
	N.reconnects++;
}

static void n_log(void *u, const char *text)
{
	(void)u; (void)text;
}

static const struct gw_node node = { NULL, 1, n_tag, n_station, n_line, n_emit, n_sub, n_write, n_reconnect, n_log };

static struct gw_spb_conf conf;
static struct gw_fmts fmts;

static const struct gw_fmt *open_fmt(const char *primary)
{
	char err[200];

	memset(&N, 0, sizeof N);
	snprintf(N.cfg.name, sizeof N.cfg.name, "Speed");
	N.cfg.access = DF1_ACCESS_READ | DF1_ACCESS_WRITE;
	N.cfg.station = 1;
	N.cfg.count = 1;
	assert_int_equal(df1_addr_parse("N7:0", &N.cfg.addr), 0);
	N.val.kind = DF1_VAL_INT16;
	memset(&conf, 0, sizeof conf);
	conf.group = "G";
	conf.edge_node = "E";
	conf.primary_host = primary;
	memset(&fmts, 0, sizeof fmts);
	assert_int_equal(gw_fmts_enable_conf(&fmts, "sparkplug", "p", &conf, err, sizeof err), 0);
	fmts.v[0].ops->connected(&fmts.v[0], &node);
	return &fmts.v[0];
}

/* A DCMD of Speed = v, with payload timestamp ts (0: none, nor on the metric). */
static void dcmd(const struct gw_fmt *f, int v, uint64_t ts)
{
	struct gw_spb_metric m;
	struct gw_buf b;

	gw_spb_metric_init(&m);
	m.name = "Speed";
	m.datatype = GW_SPB_INT16;
	m.kind = GW_SPB_V_INT;
	m.v.i = (uint16_t)v;
	m.timestamp = ts;
	gw_buf_init(&b);
	assert_int_equal(gw_spb_encode(&b, ts, &m, 1), 0);
	assert_true(f->ops->message(f, &node, "spBv1.0/G/DCMD/E/station1", b.p, b.len, false));
	gw_buf_free(&b);
}

static void test_dcmd_with_timestamp(void **state)
{
	const struct gw_fmt *f = open_fmt(NULL);

	(void)state;
	dcmd(f, 77, 1796166901000ull);
	dcmd(f, 77, 1796166901000ull);                  /* redelivered: the same id */
	dcmd(f, 78, 1796166901000ull);                  /* another command, same ms */
	assert_int_equal(N.writes, 3);                  /* all given on: the gateway drops an id it has seen */
	assert_string_equal(N.ids[0], N.ids[1]);
	assert_string_not_equal(N.ids[0], N.ids[2]);
	assert_non_null(strstr(N.ids[0], "station1:1796166901000:"));
	gw_fmts_close(&fmts);
}

static void test_dcmd_without_timestamp(void **state)
{
	const struct gw_fmt *f = open_fmt(NULL);

	(void)state;
	N.now_ms = 1000;
	dcmd(f, 77, 0);
	N.now_ms = 1500;
	dcmd(f, 77, 0);                                 /* the same bytes within 10 s: taken once */
	dcmd(f, 78, 0);                                 /* other bytes: a command */
	assert_int_equal(N.writes, 2);
	assert_string_equal(N.ids[0], "");              /* no id: the format decided */
	N.now_ms = 11001;
	dcmd(f, 77, 0);                                 /* 10 s on: a new command */
	assert_int_equal(N.writes, 3);
	gw_fmts_close(&fmts);
}

static void state_msg(const struct gw_fmt *f, const char *json)
{
	assert_true(f->ops->message(f, &node, "spBv1.0/STATE/Host", json, strlen(json), true));
}

static void test_state_order(void **state)
{
	const struct gw_fmt *f = open_fmt("Host");

	(void)state;
	assert_int_equal(N.nbirths, 0);                 /* no birth before the host is online */
	state_msg(f, "{\"online\":true,\"timestamp\":2000}");
	assert_int_equal(N.nbirths, 1);
	state_msg(f, "{\"online\":false,\"timestamp\":1999}");      /* a past session's will */
	assert_int_equal(N.ndeaths, 0);
	assert_int_equal(N.reconnects, 0);
	state_msg(f, "{\"online\":false,\"timestamp\":2000}");      /* as new as the online: taken */
	assert_int_equal(N.ndeaths, 1);
	assert_int_equal(N.reconnects, 1);
	fmts.v[0].ops->connected(&fmts.v[0], &node);    /* connected again: waits */
	state_msg(f, "{\"online\":true,\"timestamp\":1500}");       /* older than the last taken */
	assert_int_equal(N.nbirths, 1);
	state_msg(f, "ONLINE");                         /* 2.x: no timestamp, taken */
	assert_int_equal(N.nbirths, 2);
	gw_fmts_close(&fmts);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_dcmd_with_timestamp),
		cmocka_unit_test(test_dcmd_without_timestamp),
		cmocka_unit_test(test_state_order),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
