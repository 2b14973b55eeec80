/*
 * bench_poll - the poll engine on a simulated 19200-baud half-duplex line with
 * five stations (bench/run.sh starts df1sim --line-baud 19200): 200 tags, scan
 * time measured against the wire-time bound (the bytes the scan sends and
 * receives, from the link counters 2560/2561, at 10 bits per character), and
 * transactions per scan against a naive poller that reads one tag per
 * transaction. A benchmark reports numbers; it asserts nothing.
 *
 * usage: bench_poll DEVICE [SCANS]
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "df1.h"

#define BAUD 19200
#define STATIONS 5
#define TAGS_PER_STATION 40

static int64_t now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static uint64_t chars(df1_t *h)
{
	uint64_t tx = 0, rx = 0;

	df1_counter(h, 2560, &tx);      /* CRD_CHAR_SENT */
	df1_counter(h, 2561, &rx);      /* CRD_CHAR_RCVD */
	return tx + rx;
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

int main(int argc, char **argv)
{
	static struct df1_tag_config tags[STATIONS * TAGS_PER_STATION];
	struct df1_value v[4];
	struct df1_poll_stats ps;
	df1_t *h;
	int n = 0, scans = argc > 2 ? atoi(argv[2]) : 10, naive_scans = 2;
	uint64_t c0, t0tx, scans0;
	int64_t t0, engine_ms, naive_ms;
	double engine_bytes, engine_tx, naive_bytes, naive_tx, eb, nb;

	if (argc < 2) {
		fprintf(stderr, "usage: bench_poll DEVICE [SCANS]\n");
		return 2;
	}
	if (scans < 1)
		scans = 1;
	if (df1_new(&h) < 0 || df1_set_duplex(h, DF1_HALF_DUPLEX_MASTER) < 0 ||
	    df1_set_line_baud(h, BAUD) < 0 || df1_open(h, argv[1]) < 0) {
		fprintf(stderr, "bench_poll: %s: %s\n", argv[1], h ? df1_last_error(h)->message : "no memory");
		return 1;
	}
	if (add_tags(h, tags, &n) < 0)
		return 1;

	/* the poll engine: one warm-up scan, then `scans` scans */
	while (df1_poll_stats(h, &ps) == 0 && ps.scans < 1)
		if (df1_poll(h, 1000) < 0)
			goto fail;
	c0 = chars(h);
	t0tx = transactions(h);
	scans0 = ps.scans;
	t0 = now_ms();
	while (df1_poll_stats(h, &ps) == 0 && ps.scans < scans0 + (uint64_t)scans)
		if (df1_poll(h, 1000) < 0)
			goto fail;
	engine_ms = now_ms() - t0;
	engine_bytes = (double)(chars(h) - c0) / scans;
	engine_tx = (double)(transactions(h) - t0tx) / scans;
	if (ps.read_failures)
		fprintf(stderr, "bench_poll: %llu failed reads\n", (unsigned long long)ps.read_failures);

	/* the naive poller: one read per tag */
	c0 = chars(h);
	t0tx = transactions(h);
	t0 = now_ms();
	for (int k = 0; k < naive_scans; k++) {
		for (int i = 0; i < n; i++) {
			int rc = df1_read_addr(h, tags[i].station, &tags[i].addr, v, 1);

			if (rc < 0) {
				fprintf(stderr, "bench_poll: %s: %s\n", tags[i].name, df1_last_error(h)->message);
				goto fail;
			}
		}
	}
	naive_ms = now_ms() - t0;
	naive_bytes = (double)(chars(h) - c0) / naive_scans;
	naive_tx = (double)(transactions(h) - t0tx) / naive_scans;

	eb = engine_bytes * 10.0 * 1000.0 / BAUD;
	nb = naive_bytes * 10.0 * 1000.0 / BAUD;
	printf("poll bench: %d tags, %d stations, half duplex, %d baud (df1sim --line-baud %d)\n",
	       n, STATIONS, BAUD, BAUD);
	printf("%-22s %12s %12s %14s %13s %7s\n", "", "trans/scan", "bytes/scan", "wire bound ms",
	       "measured ms", "ratio");
	printf("%-22s %12.1f %12.0f %14.1f %13.1f %7.2f\n", "poll engine", engine_tx, engine_bytes, eb,
	       (double)engine_ms / scans, (double)engine_ms / scans / eb);
	printf("%-22s %12.1f %12.0f %14.1f %13.1f %7.2f\n", "naive (1 tag per read)", naive_tx,
	       naive_bytes, nb, (double)naive_ms / naive_scans, (double)naive_ms / naive_scans / nb);
	printf("blocks per scan %u; scans measured %d (naive %d); speed-up %.1fx\n", ps.blocks, scans,
	       naive_scans, ((double)naive_ms / naive_scans) / ((double)engine_ms / scans));
	printf("ratio = measured / wire bound (1.00 = the wire is the limit). Both ends pace their\n"
	       "bytes as a %d-baud line (df1sim --line-baud, df1_set_line_baud): a chunk is handed\n"
	       "over when its last character would have arrived; the rest is turnaround time.\n", BAUD);
	df1_free(h);
	return 0;
fail:
	fprintf(stderr, "bench_poll: %s\n", df1_last_error(h)->message);
	df1_free(h);
	return 1;
}
