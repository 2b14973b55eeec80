/* SPDX-License-Identifier: MPL-2.0 */
/*
 * bench_spb - df1gw's payload formats on the same 1000-tag workload (run by
 * bench/bench_gw.sh, `make bench`): 1000 Int16 tags (N10:0..999), every tag
 * changing at every round; per format, the tag message each change makes
 * (JSON: PREFIX/tag/NAME; Sparkplug: one DDATA per tag, as df1gw sends
 * them) and, for Sparkplug, one DDATA carrying a whole scan's changes (what
 * gw_spb_ddata_encode makes for a replay). Reported: bytes per update
 * (payload + topic) and updates encoded per second. A benchmark reports
 * numbers; it asserts nothing.
 *
 * usage: bench_spb [ROUNDS]
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "df1.h"
#include "df1gw/gw_format.h"
#include "df1gw/gw_format_sparkplug.h"
#include "df1gw/gw_spb_metrics.h"

#define NTAGS 1000

static double now_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec + ts.tv_nsec / 1e9;
}

static struct df1_tag_config cfg[NTAGS];
static struct df1_value val[NTAGS];
static struct df1_tag_state st[NTAGS];
static struct gw_tag_out out[NTAGS];

static void workload(void)
{
	for (int i = 0; i < NTAGS; i++) {
		char addr[32];

		snprintf(cfg[i].name, sizeof cfg[i].name, "T%d", i);
		cfg[i].access = DF1_ACCESS_READ;
		cfg[i].station = 1;
		cfg[i].count = 1;
		snprintf(addr, sizeof addr, "N10:%d", i);
		df1_addr_parse(addr, &cfg[i].addr);
		val[i].kind = DF1_VAL_INT16;
		st[i].id = i;
		st[i].config = &cfg[i];
		st[i].count = 1;
		st[i].values = &val[i];
		st[i].has_value = true;
		st[i].quality = DF1_QUALITY_GOOD;
		out[i] = (struct gw_tag_out){ &st[i], NULL, -1, NULL, 0 };
	}
}

static void round_values(int r)
{
	for (int i = 0; i < NTAGS; i++) {
		val[i].v.i16 = (int16_t)(r * 7 + i);
		st[i].value = val[i];
		st[i].last_good_wall_ms = 1796166900123LL + r * 100;
		out[i].wall_ms = st[i].last_good_wall_ms;
	}
}

/* Every tag's message by format f for rounds rounds: bytes and seconds. */
static void per_tag(const struct gw_fmt *f, int rounds, const char *label)
{
	struct gw_msg m;
	struct gw_buf key;
	double bytes = 0, t0, el;
	long n = 0;

	gw_msg_init(&m);
	gw_buf_init(&key);
	t0 = now_s();
	for (int r = 0; r < rounds; r++) {
		round_values(r);
		for (int i = 0; i < NTAGS; i++) {
			if (f->ops->tag(f, &out[i], &m, &key) != 0)
				continue;
			if (f->ops->stamp)
				f->ops->stamp(f, &m);
			bytes += m.body.len + strlen(m.topic);
			n++;
		}
	}
	el = now_s() - t0;
	printf("bench_spb: %-22s %ld updates, %.1f bytes per update (payload + topic), %.0f updates/s encoded\n",
	       label, n, n ? bytes / n : 0, n / el);
	gw_msg_free(&m);
	gw_buf_free(&key);
}

static void one_ddata(int rounds)
{
	struct gw_spb_sample s[NTAGS];
	struct gw_spb_list l;
	struct gw_buf b;
	double bytes = 0, t0, el;
	const char *topic = "spBv1.0/Bench/DDATA/B1/station1";

	gw_spb_list_init(&l);
	gw_buf_init(&b);
	t0 = now_s();
	for (int r = 0; r < rounds; r++) {
		round_values(r);
		for (int i = 0; i < NTAGS; i++)
			s[i] = (struct gw_spb_sample){ &out[i], st[i].last_good_wall_ms };
		gw_spb_ddata_encode(&b, &l, s, NTAGS, false, false, s[0].ms);
		bytes += b.len + strlen(topic);
	}
	el = now_s() - t0;
	printf("bench_spb: %-22s %d updates, %.1f bytes per update (payload + topic), %.0f updates/s encoded\n",
	       "sparkplug, scan DDATA", rounds * NTAGS, bytes / (rounds * NTAGS), rounds * NTAGS / el);
	gw_spb_list_free(&l);
	gw_buf_free(&b);
}

/* The Sparkplug format with every device born (its connected op is given a node). */
static bool node_tag(void *u, int id, struct df1_tag_state *s, struct gw_tag_out *t, char *e, size_t c)
{
	(void)u; (void)e; (void)c;
	if (id < 0 || id >= NTAGS)
		return false;
	*s = st[id];
	*t = out[id];
	t->st = s;
	return true;
}

static bool node_station(void *u, int stn, struct gw_station_out *s, struct df1_station_health *sh)
{
	(void)u;
	if (stn != 1)
		return false;
	memset(sh, 0, sizeof *sh);
	sh->state = DF1_STATION_OK;
	*s = (struct gw_station_out){ stn, "ok", NULL, sh, 0 };
	return true;
}

static void node_line(void *u, struct gw_line_out *l, struct df1_poll_stats *ps)
{
	(void)u;
	memset(ps, 0, sizeof *ps);
	*l = (struct gw_line_out){ true, "bench", ps, 1, 1796166900123LL, 0, NULL, NULL, 0 };
}

static void node_emit(void *u, const struct gw_fmt *f, struct gw_msg *m)
{
	(void)f;
	if (strstr(m->topic, "/DBIRTH/"))
		printf("bench_spb: DBIRTH of 1000 tags: %zu bytes\n", m->body.len);
	(void)u;
}

static int node_sub(void *u, const char *p)
{
	(void)u; (void)p;
	return 0;
}

int main(int argc, char **argv)
{
	int rounds = argc > 1 ? atoi(argv[1]) : 200;
	static struct gw_spb_conf conf = { "Bench", "B1", NULL, false, { NULL } };
	struct gw_node node = { NULL, NTAGS, node_tag, node_station, node_line, node_emit, node_sub, NULL, NULL, NULL };
	struct gw_fmts fmts;
	char err[200];

	memset(&fmts, 0, sizeof fmts);
	workload();
	round_values(-1);
	if (gw_fmts_enable(&fmts, "json", "bench/json", err, sizeof err) < 0 ||
	    gw_fmts_enable_conf(&fmts, "sparkplug", "bench", &conf, err, sizeof err) < 0) {
		fprintf(stderr, "bench_spb: %s\n", err);
		return 1;
	}
	fmts.v[1].ops->connected(&fmts.v[1], &node);
	per_tag(&fmts.v[0], rounds, "json, per tag");
	per_tag(&fmts.v[1], rounds, "sparkplug, per tag");
	one_ddata(rounds);
	gw_fmts_close(&fmts);
	return 0;
}
