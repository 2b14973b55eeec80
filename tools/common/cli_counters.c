/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_counters - the line's counters of the message catalog, as df1mon
 * --counters and df1gw --counters print them (see cli.h), and their names
 * in Prometheus' text format (df1mon -f prometheus, df1gw's /metrics).
 */
#include "common/cli.h"

void cli_counter_metric_name(const struct df1_catalog_entry *e, char *buf, size_t cap)
{
	snprintf(buf, cap, "df1_link_%s_total", e->mnemonic);
	for (char *p = buf; *p; p++)
		if (*p >= 'A' && *p <= 'Z')
			*p = (char)(*p - 'A' + 'a');
}

/* One family of the text exposition format (version 0.0.4): HELP, TYPE, the
 * sample with the catalog ID as a label. */
static void prom_counter(FILE *f, const struct df1_catalog_entry *e, unsigned long long v)
{
	char name[80];

	cli_counter_metric_name(e, name, sizeof name);
	fprintf(f, "# HELP %s [%d] %s: %s\n# TYPE %s counter\n%s{id=\"%d\"} %llu\n", name, e->id, e->mnemonic,
	        e->description ? e->description : "", name, name, e->id, v);
}

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
		case CLI_FMT_PROMETHEUS:
			prom_counter(f, e, v);
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
