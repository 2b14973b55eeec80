/* SPDX-License-Identifier: MPL-2.0 */
/*
 * bench_load.c - configuration loading on big input (make bench; never make check):
 *   - df1_tag_load_map() of a mapping file of N tags (default 40 000): the
 *     tags' name index keeps it linear (it was quadratic: 10 s for 40 000);
 *   - df1_map_load() of a file with one field of 10 MB: refused at the field
 *     limit (64 KiB) as soon as it is passed, not buffered first;
 *   - df1_tag_add() of 100 000 named tags (TAGS_BIG): load time, and the heap
 *     bytes per tag (mallinfo2: what the handle holds per tag, name index
 *     and block plan included once the first df1_poll planned them).
 * Usage: bench_load DIR [N]; prints one line per case with the time taken.
 */
#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "df1.h"

static double now_s(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + (double)t.tv_nsec / 1e9;
}

#define TAGS_BIG 100000

/* TAGS_BIG named tags on 5 stations, 1000 words per file: a plant-sized list. */
static int load_big(void)
{
	struct mallinfo2 m0, m1;
	struct df1_tag_config c;
	char addr[32];
	df1_t *h;
	double t0, t;

	m0 = mallinfo2();
	if (df1_new(&h) < 0)
		return 1;
	t0 = now_s();
	for (int i = 0; i < TAGS_BIG; i++) {
		memset(&c, 0, sizeof c);
		snprintf(c.name, sizeof c.name, "line3/cell%d/tag%d", i / 1000, i);
		c.access = DF1_ACCESS_READ;
		c.station = 1 + i % 5;
		c.plc = DF1_PLC_SLC;
		c.count = 1;
		c.scan_ms = 1000;
		snprintf(addr, sizeof addr, "N%d:%d", 10 + i / 1000 % 200, i % 1000);
		if (df1_addr_parse(addr, &c.addr) < 0 || df1_tag_add(h, &c) < 0) {
			fprintf(stderr, "bench_load: %s: %s\n", c.name, df1_last_error(h)->message);
			df1_free(h);
			return 1;
		}
	}
	t = now_s() - t0;
	m1 = mallinfo2();
	printf("df1_tag_add: %d named tags in %.3f s; %.0f heap bytes per tag\n", TAGS_BIG, t,
	       (double)(m1.uordblks - m0.uordblks) / TAGS_BIG);
	/* every name found again through the index */
	t0 = now_s();
	for (int i = 0; i < TAGS_BIG; i++) {
		snprintf(c.name, sizeof c.name, "line3/cell%d/tag%d", i / 1000, i);
		if (df1_tag_find(h, c.name) != i) {
			fprintf(stderr, "bench_load: %s not found at %d\n", c.name, i);
			df1_free(h);
			return 1;
		}
	}
	printf("df1_tag_find: %d names in %.3f s\n", TAGS_BIG, now_s() - t0);
	df1_free(h);
	return 0;
}

static int count_row(void *user, const struct df1_tag_config *t)
{
	(void)t;
	++*(int *)user;
	return 0;
}

int main(int argc, char **argv)
{
	char map[4096], big[4096];
	int n = argc > 2 ? atoi(argv[2]) : 40000, rows = 0, rc;
	FILE *f;
	df1_t *h;
	double t0;

	if (argc < 2 || n < 1) {
		fprintf(stderr, "usage: bench_load DIR [N]\n");
		return 2;
	}
	snprintf(map, sizeof map, "%s/map_big.csv", argv[1]);
	snprintf(big, sizeof big, "%s/field_10mb.csv", argv[1]);
	f = fopen(map, "w");
	if (!f)
		return 1;
	fprintf(f, "Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\n");
	for (int i = 0; i < n; i++)
		fprintf(f, "tag%d,Read,INT,%d,SLC,N%d:%d,1,%d\n", i, 1 + i % 5, 10 + i / 1000 % 990,
		        i % 1000, 100 + i % 7);
	fclose(f);
	f = fopen(big, "w");
	if (!f)
		return 1;
	fprintf(f, "Tag,Station,PLC_Type,Address\n");
	for (int i = 0; i < 10 * 1000 * 1000; i++)
		fputc('x', f);
	fprintf(f, ",1,SLC,N7:0\n");
	fclose(f);

	if (df1_new(&h) < 0)
		return 1;
	t0 = now_s();
	rc = df1_tag_load_map(h, map, false, NULL, NULL);
	printf("df1_tag_load_map: %d tags: %d loaded in %.3f s\n", n, rc, now_s() - t0);
	df1_free(h);
	t0 = now_s();
	rc = df1_map_load(map, false, count_row, NULL, &rows);
	printf("df1_map_load: %d rows: %d read in %.3f s\n", n, rc, now_s() - t0);
	t0 = now_s();
	rc = df1_map_load(big, false, NULL, NULL, NULL);
	printf("df1_map_load: one 10 MB field: %s in %.3f s\n", df1_errname(rc), now_s() - t0);
	remove(map);
	remove(big);
	return load_big();
}
