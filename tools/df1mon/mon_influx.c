/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_influx.c - df1mon --map -f influx: InfluxDB line protocol (see mon_map.h).
 *
 * One line per readable tag per scan, in the shape Telegraf's own inputs use
 * (the OPC UA input names its fields after the nodes):
 *
 *   df1,tag=Level,station=1,address=N7:0 Level=123i,quality="GOOD",reason="none",age_ms=12i 17...ns
 *
 * The field is named after the tag, so each field keeps one type for its life
 * (InfluxDB refuses a field whose type changes within a measurement: one
 * "value" field for integers, floats and booleans would clash). Count > 1 gives
 * Name_0, Name_1 ...; a whole T/C/R element Name.PRE, Name.ACC (Name.LEN,
 * Name.POS for R) and its bits as booleans. The value fields are written only
 * while the quality is GOOD, so a stale value never reads as fresh; quality,
 * reason and (once read) age_ms are always there.
 */
#include "df1mon/mon_map.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cli.h"

/* Tag keys, tag values and field keys: comma, equals sign and space are
 * escaped; a newline cannot be carried at all, so it becomes a space. */
static void influx_key(FILE *f, const char *s, size_t n)
{
	for (size_t i = 0; i < n && s[i]; i++) {
		char c = s[i];

		if (c == '\n' || c == '\r' || c == '\t')
			c = ' ';
		if (c == ',' || c == '=' || c == ' ')
			fputc('\\', f);
		fputc(c, f);
	}
}

/* String field values: double quote and backslash escaped, newlines as spaces. */
static void influx_string(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		char c = *s;

		if (c == '\n' || c == '\r')
			c = ' ';
		if (c == '"' || c == '\\')
			fputc('\\', f);
		fputc(c, f);
	}
	fputc('"', f);
}

/* Field keys that InfluxDB reserves (time, _*) or that this format uses for
 * itself are written with a "tag_" prefix. */
static bool influx_reserved(const char *name)
{
	return name[0] == '_' || strcmp(name, "time") == 0 || strcmp(name, "quality") == 0 ||
	       strcmp(name, "reason") == 0 || strcmp(name, "age_ms") == 0;
}

static void influx_field_key(FILE *f, const char *name, const char *suffix)
{
	if (influx_reserved(name))
		fputs("tag_", f);
	influx_key(f, name, strlen(name));
	if (suffix)
		influx_key(f, suffix, strlen(suffix));
}

/* "PRE=10 ACC=3 EN=1 TT=0 DN=0" (df1_value_format of a whole element): the
 * words as integers, the bits as booleans. The names come from the library. */
static void influx_tcr(FILE *f, const char *name, const char *text, bool *first)
{
	const char *p = text;

	while (*p) {
		const char *item, *eq;
		char suffix[40];
		long v;

		while (*p == ' ')
			p++;
		item = p;
		while (*p && *p != ' ')
			p++;
		eq = memchr(item, '=', (size_t)(p - item));
		if (!eq || (size_t)(eq - item) + 2 > sizeof suffix)
			continue;
		suffix[0] = '.';
		memcpy(suffix + 1, item, (size_t)(eq - item));
		suffix[1 + (eq - item)] = '\0';
		v = strtol(eq + 1, NULL, 10);
		fputs(*first ? "" : ",", f);
		influx_field_key(f, name, suffix);
		/* PRE/ACC/LEN/POS are words; the rest are one-bit flags */
		if (strcmp(suffix, ".PRE") == 0 || strcmp(suffix, ".ACC") == 0 ||
		    strcmp(suffix, ".LEN") == 0 || strcmp(suffix, ".POS") == 0)
			fprintf(f, "=%ldi", v);
		else
			fputs(v ? "=true" : "=false", f);
		*first = false;
	}
}

/* One value as a field: integers with the i suffix, floats in shortest
 * round-trip form (NaN and infinities cannot be written: the field is left
 * out), bits as booleans, text as strings. */
static void influx_value(FILE *f, const struct df1_tag_state *st, const struct df1_value *v,
                         const char *suffix, bool *first)
{
	enum df1_file_type t = st->config->addr.sub != DF1_ADDR_NONE ? DF1_FT_N : st->config->addr.type;
	char text[256];

	if (df1_value_format(v, t, text, sizeof text) < 0)
		return;
	if (v->kind == DF1_VAL_TCR) {
		influx_tcr(f, st->config->name, text, first);
		return;
	}
	if (v->kind == DF1_VAL_FLOAT && strpbrk(text, "ni"))
		return;         /* nan, inf */
	fputs(*first ? "" : ",", f);
	influx_field_key(f, st->config->name, suffix);
	fputc('=', f);
	switch (v->kind) {
	case DF1_VAL_INT16:
	case DF1_VAL_INT32:
		fprintf(f, "%si", text);
		break;
	case DF1_VAL_FLOAT:
		fputs(text, f);
		break;
	case DF1_VAL_BIT:
		fputs(v->v.bit ? "true" : "false", f);
		break;
	default:
		influx_string(f, text);
		break;
	}
	*first = false;
}

void mon_influx_tag(FILE *f, const struct df1_tag_state *st, int64_t now_ns)
{
	char addr[80];
	bool first = true;

	if (!(st->config->access & DF1_ACCESS_READ))
		return;         /* write-only: nothing is read */
	if (df1_addr_format_plc(st->config->plc, &st->config->addr, addr, sizeof addr) < 0)
		snprintf(addr, sizeof addr, "?");
	fputs("df1", f);
	if (st->config->name[0]) {
		fputs(",tag=", f);
		influx_key(f, st->config->name, strlen(st->config->name));
	}
	fprintf(f, ",station=%d,address=", st->config->station);
	influx_key(f, addr, strlen(addr));
	fputc(' ', f);
	if (st->has_value && st->quality == DF1_QUALITY_GOOD) {
		if (st->count == 1) {
			influx_value(f, st, &st->values[0], NULL, &first);
		} else {
			for (size_t i = 0; i < st->count; i++) {
				char suffix[24];

				snprintf(suffix, sizeof suffix, "_%zu", i);
				influx_value(f, st, &st->values[i], suffix, &first);
			}
		}
	}
	fprintf(f, "%squality=", first ? "" : ",");
	influx_string(f, df1_quality_name(st->quality));
	fputs(",reason=", f);
	influx_string(f, df1_reason_name(st->reason));
	if (st->age_ms >= 0)
		fprintf(f, ",age_ms=%lldi", (long long)st->age_ms);
	fprintf(f, " %lld\n", (long long)now_ns);
}

void mon_influx_counters(FILE *f, df1_t *h, int64_t now_ns)
{
	struct df1_poll_stats ps;

	df1_poll_stats(h, &ps);
	fprintf(f, "df1_link scans=%llui,scan_ms=%lldi,transactions_per_scan=%ui,blocks=%ui,"
	        "reads=%llui,read_failures=%llui,writes=%llui,retries=%llui,stations_offline=%ui",
	        (unsigned long long)ps.scans, (long long)ps.last_scan_ms, ps.last_scan_transactions,
	        ps.blocks, (unsigned long long)ps.reads, (unsigned long long)ps.read_failures,
	        (unsigned long long)ps.writes, (unsigned long long)ps.retries, ps.stations_offline);
	for (size_t i = 0;; i++) {
		const struct df1_catalog_entry *e = df1_catalog_at(i);
		uint64_t v = 0;

		if (!e)
			break;
		if (e->severity != DF1_SEV_COUNTER || df1_counter(h, e->id, &v) < 0)
			continue;
		fprintf(f, ",%s=%llui", e->mnemonic, (unsigned long long)v);
	}
	fprintf(f, " %lld\n", (long long)now_ns);
}
