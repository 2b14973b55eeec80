/* SPDX-License-Identifier: MPL-2.0 */
/*
 * bench_read - the C side of python/bench.py: single-word reads per second
 * (df1_read_int16 of N7:0, one at a time) against the df1sim bench.py started.
 *
 *   bench_read TARGET COUNT     prints "C reads/s: N"
 */
#define _POSIX_C_SOURCE 200809L
#include <df1.h>

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

int main(int argc, char **argv)
{
	df1_t *h;
	int16_t v;
	long n;
	double t0, dt;

	if (argc != 3 || (n = strtol(argv[2], NULL, 10)) <= 0) {
		fprintf(stderr, "usage: bench_read TARGET COUNT\n");
		return 2;
	}
	if (df1_new(&h) < 0 || df1_open(h, argv[1]) < 0) {
		fprintf(stderr, "bench_read: %s: %s\n", argv[1], h ? df1_last_error(h)->message : "out of memory");
		return 1;
	}
	if (df1_read_int16(h, 1, "N7:0", &v, 1) < 0) {          /* as the Python loop: one first */
		fprintf(stderr, "bench_read: N7:0: %s\n", df1_last_error(h)->message);
		return 1;
	}
	t0 = now_s();
	for (long i = 0; i < n; i++) {
		if (df1_read_int16(h, 1, "N7:0", &v, 1) < 0) {
			fprintf(stderr, "bench_read: N7:0: %s\n", df1_last_error(h)->message);
			return 1;
		}
	}
	dt = now_s() - t0;
	printf("C reads/s: %.0f\n", (double)n / dt);
	df1_free(h);
	return 0;
}
