/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_ping - df1mon --ping: link test and 06/00 echo per probe, round-trip
 * times, a summary.
 */
#include "df1mon/mon.h"

struct rtt {
	unsigned long n;
	double min, max, sum;
};

static void rtt_add(struct rtt *t, double ms)
{
	if (t->n == 0 || ms < t->min)
		t->min = ms;
	if (t->n == 0 || ms > t->max)
		t->max = ms;
	t->sum += ms;
	t->n++;
}

#define PING_BYTES 8

static void ping_line_ok(const struct mon *m, long seq, double link_ms, double echo_ms)
{
	switch (m->cli.format) {
	case CLI_FMT_INFLUX: /* refused without --map */
	case CLI_FMT_PROMETHEUS: /* refused without --counters */
	case CLI_FMT_PLAIN:
		printf("station %d: seq=%ld link=%.3f ms echo=%.3f ms (%d bytes)\n", m->cli.station, seq,
		       link_ms, echo_ms, PING_BYTES);
		break;
	case CLI_FMT_CSV:
		printf("%ld,%d,ok,%.3f,%.3f,\n", seq, m->cli.station, link_ms, echo_ms);
		break;
	case CLI_FMT_JSON:
		printf("{\"seq\":%ld,\"station\":%d,\"ok\":true,\"link_ms\":%.3f,\"echo_ms\":%.3f,\"bytes\":%d}\n",
		       seq, m->cli.station, link_ms, echo_ms, PING_BYTES);
		break;
	}
}

static void ping_line_fail(const struct mon *m, long seq, const char *stage, int err)
{
	char text[320];
	const struct df1_error_detail *d = df1_last_error(m->h);
	int id = d && d->code == err && d->catalog_id ? d->catalog_id : df1_error_catalog_id(err);

	cli_error_text(m->h, err, text, sizeof text);
	switch (m->cli.format) {
	case CLI_FMT_INFLUX: /* refused without --map */
	case CLI_FMT_PROMETHEUS: /* refused without --counters */
	case CLI_FMT_PLAIN:
		printf("station %d: seq=%ld no answer (%s): %s\n", m->cli.station, seq, stage, text);
		break;
	case CLI_FMT_CSV:
		printf("%ld,%d,%s,,,", seq, m->cli.station, stage);
		cli_csv_field(stdout, text);
		putchar('\n');
		break;
	case CLI_FMT_JSON:
		printf("{\"seq\":%ld,\"station\":%d,\"ok\":false,\"stage\":\"%s\"", seq, m->cli.station, stage);
		if (id)
			printf(",\"error_id\":%d", id);
		fputs(",\"error\":", stdout);
		cli_json_string(stdout, text);
		fputs("}\n", stdout);
		break;
	}
}

static void ping_summary(const struct mon *m, unsigned long sent, unsigned long recvd,
                         const struct rtt *lk, const struct rtt *ec)
{
	double loss = sent ? 100.0 * (double)(sent - recvd) / (double)sent : 0.0;

	switch (m->cli.format) {
	case CLI_FMT_INFLUX: /* refused without --map */
	case CLI_FMT_PROMETHEUS: /* refused without --counters */
	case CLI_FMT_PLAIN:
		printf("--- station %d: %lu probe%s sent, %lu answered, %.0f%% loss\n", m->cli.station, sent,
		       sent == 1 ? "" : "s", recvd, loss);
		if (lk->n)
			printf("link rtt min/avg/max = %.3f/%.3f/%.3f ms\n", lk->min, lk->sum / (double)lk->n,
			       lk->max);
		if (ec->n)
			printf("echo rtt min/avg/max = %.3f/%.3f/%.3f ms\n", ec->min, ec->sum / (double)ec->n,
			       ec->max);
		break;
	case CLI_FMT_CSV:
		/* the table on stdout holds probes only */
		if (m->cli.quiet)
			break;
		fprintf(stderr, "%s: station %d: %lu probe%s sent, %lu answered, %.0f%% loss", m->cli.name,
		        m->cli.station, sent, sent == 1 ? "" : "s", recvd, loss);
		if (ec->n)
			fprintf(stderr, ", echo rtt min/avg/max = %.3f/%.3f/%.3f ms", ec->min,
			        ec->sum / (double)ec->n, ec->max);
		fputc('\n', stderr);
		break;
	case CLI_FMT_JSON:
		printf("{\"summary\":true,\"station\":%d,\"sent\":%lu,\"received\":%lu,\"loss_pct\":%.1f",
		       m->cli.station, sent, recvd, loss);
		if (lk->n)
			printf(",\"link_ms\":{\"min\":%.3f,\"avg\":%.3f,\"max\":%.3f}", lk->min,
			       lk->sum / (double)lk->n, lk->max);
		if (ec->n)
			printf(",\"echo_ms\":{\"min\":%.3f,\"avg\":%.3f,\"max\":%.3f}", ec->min,
			       ec->sum / (double)ec->n, ec->max);
		fputs("}\n", stdout);
		break;
	}
}

/* Each probe: df1_link_test (DLE ENQ, or a poll in half duplex), then a 06/00
 * echo of PING_BYTES bytes; a probe is answered when both are. */
int mon_run_ping(struct mon *m)
{
	long count = (m->given & GIVEN_COUNT) ? m->count : 4;
	double interval = (m->given & GIVEN_INTERVAL) ? m->interval_s : 1.0;
	unsigned long sent = 0, recvd = 0;
	struct rtt lk = { 0 }, ec = { 0 };

	if (m->cli.format == CLI_FMT_CSV)
		puts("seq,station,status,link_ms,echo_ms,error");
	for (long seq = 1; count == 0 || seq <= count; seq++) {
		uint8_t data[PING_BYTES] = { 'D', 'F', '1', 'M', 'O', 'N', (uint8_t)(seq & 0xFF),
		                             (uint8_t)((seq >> 8) & 0xFF) };
		int64_t t0, t1, t2;
		int r;

		if (seq > 1 && (mon_out_broken() || !mon_sleep(mon_ms_of(interval))))
			break;
		t0 = mon_mono_us();
		r = df1_link_test(m->h, m->cli.station);
		t1 = mon_mono_us();
		if (r == DF1_E_INTR || cli_stop)
			break;
		sent++;
		if (r < 0) {
			ping_line_fail(m, seq, "link", r);
			fflush(stdout);
			continue;
		}
		r = df1_echo(m->h, m->cli.station, data, sizeof data);
		t2 = mon_mono_us();
		if (r == DF1_E_INTR || cli_stop) {
			sent--;
			break;
		}
		if (r < 0) {
			ping_line_fail(m, seq, "echo", r);
		} else {
			recvd++;
			rtt_add(&lk, (double)(t1 - t0) / 1000.0);
			rtt_add(&ec, (double)(t2 - t1) / 1000.0);
			ping_line_ok(m, seq, (double)(t1 - t0) / 1000.0, (double)(t2 - t1) / 1000.0);
		}
		fflush(stdout);
	}
	ping_summary(m, sent, recvd, &lk, &ec);
	if (mon_interrupted() && !m->cli.quiet)
		fprintf(stderr, "%s: stopped by %s\n", m->cli.name, mon_signal_name(cli_stop_signal()));
	return (sent > 0 && recvd == sent) ? CLI_EXIT_OK : CLI_EXIT_FAIL;
}
