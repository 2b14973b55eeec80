/*
 * fuzz_table_file - df1sim's data file, the table file loader
 * (lib/table_file.c, df1_table_load). Input: byte 0 picks the PLC type, the
 * rest is the file.
 * Properties: a failed load leaves the table as it was (all or nothing) and
 * says why.
 */
#include "fuzz.h"

#include <string.h>

#include "df1.h"

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
	}
	df1_table_free(t);
	return 0;
}
