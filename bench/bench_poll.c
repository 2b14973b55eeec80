/* SPDX-License-Identifier: MPL-2.0 */
/*
 * bench_poll - the poll engine on a simulated 19200-baud line with five
 * stations (bench/run.sh starts df1sim --line-baud 19200 for each case). In
 * half duplex both ends pace what they send (df1_set_line_baud); in full
 * duplex df1sim's relay is the line, a UART per direction
 * (tools/df1sim/sim_pace.c), and the master writes its frames at once as into
 * a real UART's buffer (pacing them here too would put each frame on the line
 * twice, a chunk's time late). 200
 * tags, the scan time measured against the wire-time bounds computed from the
 * bytes the scan sends and receives (the link counters 2560/2561, 10 bits per
 * character):
 *   - serial bound: every byte of the scan one after the other;
 *   - one-direction bound (full duplex): the busier direction alone, the limit
 *     when both directions carry bytes at once (pipelining).
 * With --scan-time MS (df1sim --scan-time: a reply is ready at the end of the
 * slave's program scan) the bound adds the waits the workload cannot avoid:
 * one transaction at a time per line, each command lands at a random point of
 * its station's scan, so it waits MS/2 on average (df1sim(1)).
 * The half-duplex case also runs a naive poller (one read per tag) to compare.
 * A benchmark reports numbers; it asserts nothing. Its last output line is
 *   case NAME ratio R [one-direction R1]
 * for bench/run.sh, R = measured / the bound that applies (see above), R1 (full
 * duplex) = measured / the one-direction bound.
 *
 * With --trace FILE every chunk the master writes and reads goes to FILE, one
 * line each: seconds of CLOCK_MONOTONIC, tx or rx, the bytes in hex (df1sim
 * -vvv prints its side with the same clock): bench/README.md says how the two
 * line up into each frame's first and last byte.
 *
 * usage: bench_poll DEVICE half|full [SCANS] [--outstanding N] [--scan-time MS]
 *                   [--name NAME] [--trace FILE] [--no-naive]
 * (--no-naive: without the naive poller, for the rounds after the first)
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <time.h>

#include "df1.h"

#define BAUD 19200
#define BITS_PER_CHAR 10
#define STATIONS 5
#define TAGS_PER_STATION 40

static int64_t now_us(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

struct bytes {
	uint64_t tx, rx;
};

static struct bytes chars(df1_t *h)
{
	struct bytes b = { 0, 0 };

	df1_counter(h, 2560, &b.tx);    /* CRD_CHAR_SENT */
	df1_counter(h, 2561, &b.rx);    /* CRD_CHAR_RCVD */
	return b;
}

static double wire_ms(double bytes)
{
	return bytes * BITS_PER_CHAR * 1000.0 / BAUD;
}

static void on_trace(void *user, enum df1_dir dir, const uint8_t *b, size_t n, uint64_t t_us)
{
	FILE *fp = user;

	fprintf(fp, "%llu.%06llu %s", (unsigned long long)(t_us / 1000000),
	        (unsigned long long)(t_us % 1000000), dir == DF1_DIR_TX ? "tx" : "rx");
	for (size_t i = 0; i < n; i++)
		fprintf(fp, " %02X", b[i]);
	fputc('\n', fp);
}

static uint64_t transactions(df1_t *h)
{
	uint64_t v = 0;

	df1_counter(h, 2527, &v);       /* CNT_CMD_MSGS_SENT */
	return v;
}

/* Per station: 20 words every third element (N7:0 .. N7:57), 10 floats, 8 bits
 * of one word, 2 timer accumulators: 40 tags. */
static int add_tags(df1_t *h, struct df1_tag_config *all, int *n)
{
	for (int s = 1; s <= STATIONS; s++) {
		for (int i = 0; i < TAGS_PER_STATION; i++) {
			struct df1_tag_config c;
			char addr[32];
			int rc;

			memset(&c, 0, sizeof c);
			if (i < 20)
				snprintf(addr, sizeof addr, "N7:%d", 3 * i);
			else if (i < 30)
				snprintf(addr, sizeof addr, "F8:%d", i - 20);
			else if (i < 38)
				snprintf(addr, sizeof addr, "B3:0/%d", i - 30);
			else
				snprintf(addr, sizeof addr, "T4:%d.ACC", i - 38);
			snprintf(c.name, sizeof c.name, "s%d_%d", s, i);
			c.access = DF1_ACCESS_READ;
			c.station = s;
			c.plc = DF1_PLC_SLC;
			c.count = 1;
			c.scan_ms = 0;          /* as fast as the line allows */
			if (df1_addr_parse(addr, &c.addr) < 0)
				return -1;
			rc = df1_tag_add(h, &c);
			if (rc < 0) {
				fprintf(stderr, "bench_poll: tag %s: %s\n", c.name, df1_last_error(h)->message);
				return -1;
			}
			all[(*n)++] = c;
		}
	}
	return 0;
}

static int scan_n(df1_t *h, int scans, struct df1_poll_stats *ps)
{
	uint64_t scans0;

	if (df1_poll_stats(h, ps) < 0)
		return -1;
	scans0 = ps->scans;
	while (df1_poll_stats(h, ps) == 0 && ps->scans < scans0 + (uint64_t)scans)
		if (df1_poll(h, 1000) < 0)
			return -1;
	return 0;
}

int main(int argc, char **argv)
{
	static struct df1_tag_config tags[STATIONS * TAGS_PER_STATION];
	struct df1_value v[4];
	struct df1_poll_stats ps;
	struct bytes b0, b1;
	df1_t *h;
	int n = 0, scans = 10, naive_scans = 2, naive = 1, outstanding = 1, scan_time = 0;
	bool full;
	const char *name = NULL, *trace = NULL;
	FILE *trace_fp = NULL;
	uint64_t t0tx;
	int64_t t0;
	double scan_ms, tx, rx, serial, one_dir, waits, trans, bound, ratio;

	if (argc < 3 || (strcmp(argv[2], "half") && strcmp(argv[2], "full"))) {
		fprintf(stderr, "usage: bench_poll DEVICE half|full [SCANS] [--outstanding N] "
		        "[--scan-time MS] [--name NAME] [--trace FILE] [--no-naive]\n");
		return 2;
	}
	full = strcmp(argv[2], "full") == 0;
	/* a paced write is due to the microsecond: without this the kernel may
	 * wake the pause up to 50 us late (timer slack), and the last chunk of
	 * each frame, late, delays the turnaround after it (bench/README.md) */
	prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0);
	for (int i = 3; i < argc; i++) {
		if (!strcmp(argv[i], "--outstanding") && i + 1 < argc)
			outstanding = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--scan-time") && i + 1 < argc)
			scan_time = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--name") && i + 1 < argc)
			name = argv[++i];
		else if (!strcmp(argv[i], "--no-naive"))
			naive = 0;
		else if (!strcmp(argv[i], "--trace") && i + 1 < argc)
			trace = argv[++i];
		else
			scans = atoi(argv[i]);
	}
	if (scans < 1)
		scans = 1;
	if (!name)
		name = argv[2];
	if (df1_new(&h) < 0 ||
	    df1_set_duplex(h, full ? DF1_FULL_DUPLEX : DF1_HALF_DUPLEX_MASTER) < 0 ||
	    (!full && df1_set_line_baud(h, BAUD) < 0) ||
	    (outstanding > 1 && df1_set_option(h, DF1_OPT_MAX_OUTSTANDING, outstanding) < 0) ||
	    df1_open(h, argv[1]) < 0) {
		fprintf(stderr, "bench_poll: %s: %s\n", argv[1], h ? df1_last_error(h)->message : "no memory");
		return 1;
	}
	if (add_tags(h, tags, &n) < 0)
		return 1;
	if (trace) {
		trace_fp = fopen(trace, "w");
		if (!trace_fp) {
			perror(trace);
			return 1;
		}
		df1_set_trace(h, on_trace, trace_fp);
	}

	/* the poll engine: one warm-up scan, then `scans` scans */
	if (scan_n(h, 1, &ps) < 0)
		goto fail;
	b0 = chars(h);
	t0tx = transactions(h);
	t0 = now_us();
	if (scan_n(h, scans, &ps) < 0)
		goto fail;
	scan_ms = (double)(now_us() - t0) / 1000.0 / scans;
	b1 = chars(h);
	tx = (double)(b1.tx - b0.tx) / scans;
	rx = (double)(b1.rx - b0.rx) / scans;
	trans = (double)(transactions(h) - t0tx) / scans;
	if (ps.read_failures)
		fprintf(stderr, "bench_poll: %llu failed reads\n", (unsigned long long)ps.read_failures);

	serial = wire_ms(tx + rx);
	one_dir = wire_ms(tx > rx ? tx : rx);
	waits = trans * scan_time / 2.0;
	printf("poll bench, case %s: %d tags, %d stations, %s duplex, %d baud (df1sim --line-baud %d)",
	       name, n, STATIONS, full ? "full" : "half", BAUD, BAUD);
	if (outstanding > 1)
		printf(", --outstanding %d", outstanding);
	if (scan_time)
		printf(", stations with --scan-time %d", scan_time);
	printf("\n  transactions/scan %.1f; bytes/scan sent %.0f, received %.0f; blocks %u\n", trans,
	       tx, rx, ps.blocks);
	printf("  serial wire-time bound %.1f ms", serial);
	if (full)
		printf("; one-direction bound %.1f ms", one_dir);
	if (scan_time)
		printf("; scan-time waits %.1f ms", waits);
	printf("\n  measured scan %.1f ms: %.2f x serial bound", scan_ms, scan_ms / serial);
	if (full)
		printf(", %.2f x one-direction bound", scan_ms / one_dir);
	if (scan_time)
		printf(", %.2f x (serial bound + waits)", scan_ms / (serial + waits));
	printf("\n");

	if (!full && !scan_time && naive) {
		/* the naive poller: one read per tag */
		double naive_ms, naive_bytes, naive_tx;

		b0 = chars(h);
		t0tx = transactions(h);
		t0 = now_us();
		for (int k = 0; k < naive_scans; k++) {
			for (int i = 0; i < n; i++) {
				int rc = df1_read_addr(h, tags[i].station, &tags[i].addr, v, 1);

				if (rc < 0) {
					fprintf(stderr, "bench_poll: %s: %s\n", tags[i].name,
					        df1_last_error(h)->message);
					goto fail;
				}
			}
		}
		naive_ms = (double)(now_us() - t0) / 1000.0 / naive_scans;
		b1 = chars(h);
		naive_bytes = (double)(b1.tx + b1.rx - b0.tx - b0.rx) / naive_scans;
		naive_tx = (double)(transactions(h) - t0tx) / naive_scans;
		printf("  naive poller (1 tag per read): transactions/scan %.1f, bytes/scan %.0f, "
		       "bound %.1f ms, measured %.1f ms (%.2f x); the engine is %.1fx faster\n",
		       naive_tx, naive_bytes, wire_ms(naive_bytes), naive_ms,
		       naive_ms / wire_ms(naive_bytes), naive_ms / scan_ms);
	}
	/* the ratio for the summary line: pipelining is measured against the serial
	 * bound too, so that below 1.00 shows both directions at work at once */
	bound = scan_time ? serial + waits : serial;
	ratio = scan_ms / bound;
	if (full)
		printf("case %s ratio %.3f one-direction %.3f\n", name, ratio, scan_ms / one_dir);
	else
		printf("case %s ratio %.3f\n", name, ratio);
	df1_free(h);
	if (trace_fp)
		fclose(trace_fp);
	return 0;
fail:
	fprintf(stderr, "bench_poll: %s\n", df1_last_error(h)->message);
	df1_free(h);
	return 1;
}
