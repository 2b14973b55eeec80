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

/* The radio modem's statistics (df1_radio_stats), after the catalog's counters:
 * ID 0, as they have no catalog ID (doc/REQUIREMENTS.md 004 is closed). */
int cli_print_radio(FILE *f, const df1_t *h, enum cli_format fmt, double t, bool comma)
{
	struct df1_radio_stats st;
	const struct { const char *name, *help; uint64_t v; } *r, rows[] = {
		{ "RADIO_PACKETS_SENT", "radio: packets sent (commands, replies, relayed copies)", 0 },
		{ "RADIO_PACKETS_RCVD", "radio: packets received with a good check", 0 },
		{ "RADIO_PACKETS_RELAYED", "radio: packets relayed (store and forward)", 0 },
		{ "RADIO_DUPLICATES", "radio: duplicate packets dropped", 0 },
		{ "RADIO_BAD_PACKETS", "radio: bad packets dropped (check, framing)", 0 },
		{ "RADIO_UNDELIVERED", "radio: packets not sent (no CTS, carrier up)", 0 },
	};
	uint64_t v[6];
	int n = 0;

	if (df1_radio_stats(h, &st) < 0)
		return 0;
	v[0] = st.sent, v[1] = st.received, v[2] = st.relayed;
	v[3] = st.duplicates, v[4] = st.bad_packets, v[5] = st.undelivered;
	for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++, n++) {
		struct df1_catalog_entry e = { .id = 0, .severity = DF1_SEV_COUNTER };
		unsigned long long x = (unsigned long long)v[i];

		r = &rows[i];
		e.mnemonic = r->name;
		e.description = r->help;
		switch (fmt) {
		case CLI_FMT_CSV:
			fprintf(f, "%.3f,0,%s,%llu\n", t, r->name, x);
			break;
		case CLI_FMT_JSON:
			fprintf(f, "%s{\"id\":0,\"mnemonic\":\"%s\",\"value\":%llu}", comma || n ? "," : "",
			        r->name, x);
			break;
		case CLI_FMT_PROMETHEUS:
			prom_counter(f, &e, x);
			break;
		case CLI_FMT_PLAIN:
		case CLI_FMT_INFLUX:
		default:
			fprintf(f, "0 %s %llu\n", r->name, x);
			break;
		}
	}
	return n;
}
