/* SPDX-License-Identifier: MPL-2.0 */
/*
 * bench_buffer - df1gw's store and forward buffer (tools/df1gw/gw_buffer.c):
 * records a second appended (a transaction each, as df1gw buffers them) and
 * replayed (peek 100, handed, an ack each, as PUBACKs arrive), and the bytes
 * of file per record (the database once closed, its WAL checkpointed), on a
 * SQLite file and in memory.
 *
 *   bench_buffer DIR [RECORDS]      (make bench: bench/run.sh)
 *
 * A record is a tag's value as df1gw would keep it: a 12-character tag name,
 * 8 bytes of value.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "df1gw/gw_buffer.h"

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

static long long fsize(const char *p)
{
	struct stat st;
	return stat(p, &st) == 0 ? (long long)st.st_size : 0;
}

/* One run on path (NULL: memory): prints its line; 0 or 1. */
static int run(const char *path, const char *name, long n)
{
	struct gw_buffer_limits lim = { 0 };
	struct gw_buffer *b;
	char err[400], key[32];
	int64_t value = 0;

	if (gw_buffer_open(&b, path, &lim, err, sizeof err) != 0) {
		fprintf(stderr, "bench_buffer: %s\n", err);
		return 1;
	}
	double t0 = now_s();
	for (long i = 0; i < n; i++) {
		snprintf(key, sizeof key, "Tank%03ld_Level", i % 100);
		value = i * 3;
		struct gw_buffer_rec r = { .kind = GW_BUFFER_TAG, .id = (int)(i % 100), .quality = 192,
		                           .ms = 1700000000000 + i, .key = key, .data = &value, .len = sizeof value };
		if (gw_buffer_append(b, &r, r.ms) != 0) {
			fprintf(stderr, "bench_buffer: append failed\n");
			return 1;
		}
	}
	double t1 = now_s();
	long long bytes = 0;
	if (path) {
		/* closed and opened again: the WAL checkpointed into the file */
		gw_buffer_close(b);
		char wal[600];
		snprintf(wal, sizeof wal, "%s-wal", path);
		bytes = fsize(path) + fsize(wal);
		if (gw_buffer_open(&b, path, &lim, err, sizeof err) != 0) {
			fprintf(stderr, "bench_buffer: %s\n", err);
			return 1;
		}
	}
	double t2 = now_s();
	long got = 0;
	for (;;) {
		const struct gw_buffer_rec *r;
		int k = gw_buffer_peek(b, 100, &r);
		if (k <= 0)
			break;
		uint64_t last = r[k - 1].seq;
		gw_buffer_handed(b, last);
		for (uint64_t s = r[0].seq; s <= last; s++)
			gw_buffer_ack(b, s);
		got += k;
	}
	double t3 = now_s();
	gw_buffer_close(b);
	if (got != n) {
		fprintf(stderr, "bench_buffer: replayed %ld of %ld\n", got, n);
		return 1;
	}
	printf("buffer %-6s %ld records: append %.0f records/s, replay %.0f records/s", name, n,
	       (double)n / (t1 - t0), (double)n / (t3 - t2));
	if (path)
		printf(", %.1f bytes of file per record", (double)bytes / (double)n);
	printf("\n");
	return 0;
}

int main(int argc, char **argv)
{
	char path[512];

	if (argc < 2) {
		fprintf(stderr, "usage: bench_buffer DIR [RECORDS]\n");
		return 2;
	}
	long n = argc > 2 ? atol(argv[2]) : 100000;
	snprintf(path, sizeof path, "%s/bench_buffer.db", argv[1]);
	remove(path);
	return run(path, "sqlite", n) || run(NULL, "memory", n);
}
