/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_table_file - df1sim's data file, the table file loader
 * (lib/table/table_file.c, df1_table_load). Input: byte 0 picks the PLC type, the
 * rest is the file.
 * Properties: a failed load leaves the table as it was (all or nothing) and
 * says why; after a good one, save -> load -> save writes the same text
 * (df1_table_save's promise that df1_table_load restores what it wrote).
 */
#include "fuzz.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "df1.h"

static char dir[64], path_a[96], path_b[96];

static void cleanup(void)
{
	unlink(path_a);
	unlink(path_b);
	rmdir(dir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	/* the saves go to a private directory, in memory where there is one */
	snprintf(dir, sizeof dir, "%s/fuzz-table-XXXXXX", access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
	if (!mkdtemp(dir))
		abort();
	snprintf(path_a, sizeof path_a, "%s/a.txt", dir);
	snprintf(path_b, sizeof path_b, "%s/b.txt", dir);
	atexit(cleanup);
	return 0;
}

static char *slurp(const char *path, size_t *n)
{
	FILE *f = fopen(path, "rb");
	char *buf = NULL;
	size_t cap = 0, len = 0, k;

	if (!f)
		return NULL;
	do {
		if (len == cap) {
			char *nb = realloc(buf, cap = cap ? 2 * cap : 65536);
			if (!nb)
				break;
			buf = nb;
		}
		k = fread(buf + len, 1, cap - len, f);
		len += k;
	} while (k > 0);
	fclose(f);
	*n = len;
	return buf;
}

/* save -> load into a fresh table -> save: the same text. */
static void round_trip(struct df1_table *t, enum df1_plc plc)
{
	struct df1_table *u;
	char *a, *b;
	size_t na = 0, nb = 0;
	int r;

	r = df1_table_save(t, path_a);
	FUZZ_CHECK(r == 0, "save after a good load: %s (%s)", df1_errname(r), df1_table_error_text(t));
	if (df1_table_new(&u, plc) < 0)
		return;
	FUZZ_CHECK(df1_table_add_default_files(u) == 0, "default files");
	r = df1_table_load(u, path_a);
	FUZZ_CHECK(r == 0, "what df1_table_save wrote does not load: %s", df1_table_error_text(u));
	FUZZ_CHECK(df1_table_save(u, path_b) == 0, "second save");
	a = slurp(path_a, &na);
	b = slurp(path_b, &nb);
	FUZZ_CHECK(a && b, "saved files do not read back");
	if (na != nb || memcmp(a, b, na) != 0) {
		size_t i = 0;
		while (i < na && i < nb && a[i] == b[i])
			i++;
		FUZZ_CHECK(0, "save -> load -> save differs at byte %zu (%zu, %zu bytes): \"%.40s\" / \"%.40s\"",
		           i, na, nb, a + (i > 20 ? i - 20 : 0), b + (i > 20 ? i - 20 : 0));
	}
	free(a);
	free(b);
	df1_table_free(u);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const enum df1_plc plcs[] = { DF1_PLC_SLC, DF1_PLC_MICROLOGIX, DF1_PLC_SLC502,
	                                     DF1_PLC_PLC5, DF1_PLC_PLC2 };
	struct df1_table *t;
	struct df1_value before[4], after[4];
	const char *path;
	int r;

	if (size < 1)
		return 0;
	path = fuzz_file(data + 1, size - 1);
	if (!path || df1_table_new(&t, plcs[data[0] % 5]) < 0)
		return 0;
	if (df1_table_add_default_files(t) < 0) {
		df1_table_free(t);
		return 0;
	}
	memset(before, 0, sizeof before);
	memset(after, 0, sizeof after);
	FUZZ_CHECK(df1_table_read(t, "N7:0", before, 4) == 4, "N7:0 does not read");
	r = df1_table_load(t, path);
	if (r < 0) {
		FUZZ_CHECK(df1_table_error_text(t)[0] != '\0', "load failed (%s) without a text",
		           df1_errname(r));
		FUZZ_CHECK(df1_table_read(t, "N7:0", after, 4) == 4 &&
		           memcmp(before, after, sizeof before) == 0,
		           "a failed load changed N7:0");
	} else {
		round_trip(t, plcs[data[0] % 5]);
	}
	df1_table_free(t);
	return 0;
}
