/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_counters - the line's counters of the message catalog, as df1mon
 * --counters and df1gw --counters print them (see cli.h).
 */
#include "common/cli.h"

int cli_print_counters(FILE *f, const df1_t *h, enum cli_format fmt, double t)
{
	const struct df1_catalog_entry *e;
	int n = 0;

	for (size_t i = 0; (e = df1_catalog_at(i)) != NULL; i++) {
		unsigned long long v;
		uint64_t v64 = 0;

		if (e->severity != DF1_SEV_COUNTER || df1_counter(h, e->id, &v64) < 0)
			continue;
		v = (unsigned long long)v64;
		switch (fmt) {
		case CLI_FMT_CSV:
			fprintf(f, "%.3f,%d,%s,%llu\n", t, e->id, e->mnemonic, v);
			break;
		case CLI_FMT_JSON:
			fprintf(f, "%s{\"id\":%d,\"mnemonic\":\"%s\",\"value\":%llu}", n ? "," : "", e->id,
			        e->mnemonic, v);
			break;
		case CLI_FMT_PLAIN:
		case CLI_FMT_INFLUX:
		default:
			fprintf(f, "%d %s %llu\n", e->id, e->mnemonic, v);
			break;
		}
		n++;
	}
	return n;
}
