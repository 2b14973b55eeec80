/*
 * bench_load.c - configuration loading on big input (make bench; never make check):
 *   - df1_tag_load_map() of a mapping file of N tags (default 40 000): the
 *     tags' name index keeps it linear (it was quadratic: 10 s for 40 000);
 *   - df1_map_load() of a file with one field of 10 MB: refused at the field
 *     limit (64 KiB) as soon as it is passed, not buffered first.
 * Usage: bench_load DIR [N]; prints one line per case with the time taken.
 */
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
	return 0;
}
