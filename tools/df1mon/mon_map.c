/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_map.c - df1mon --map: the poll engine's live table (see mon_map.h).
 * stdout: data only; stderr: "df1mon: ..." messages.
 */
#include "df1mon/mon_map.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "common/cli.h"

#define MM_PROG "df1mon"
#define MM_POLL_MS 200          /* df1_poll() wait: how soon *stop is seen */
#define MM_VALUE_WIDTH 40       /* plain: longer values are cut with "..." */

struct mm {
	df1_t *h;
	const char *path;
	int format;
	bool tty;
	bool counters;
	int64_t t0;
	uint64_t scan;
	int issues;
};

static int64_t mm_now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static double mm_elapsed(const struct mm *m)
{
	return (double)(mm_now_ms() - m->t0) / 1000.0;
}

/* ---- text helpers ---- */

/* The file type a value formats against (names of T/C/R bits; words as N). */
static enum df1_file_type mm_value_type(const struct df1_tag_config *c)
{
	return c->addr.sub != DF1_ADDR_NONE ? DF1_FT_N : c->addr.type;
}

/* Values joined by sep ("-" when there is none yet). */
static void mm_values_text(const struct df1_tag_state *st, const char *sep, char *buf, size_t cap)
{
	size_t len = 0;

	buf[0] = '\0';
	if (!st->has_value) {
		snprintf(buf, cap, "-");
		return;
	}
	for (size_t i = 0; i < st->count && len + 1 < cap; i++) {
		char one[160];

		if (df1_value_format(&st->values[i], mm_value_type(st->config), one, sizeof one) < 0)
			snprintf(one, sizeof one, "?");
		len += (size_t)snprintf(buf + len, cap - len, "%s%s", i ? sep : "", one);
		if (len >= cap)
			len = cap - 1;
	}
}

static void mm_age_text(const struct df1_tag_state *st, char *buf, size_t cap)
{
	if (st->age_ms < 0)
		snprintf(buf, cap, "-");
	else if (st->age_ms < 10000)
		snprintf(buf, cap, "%lldms", (long long)st->age_ms);
	else
		snprintf(buf, cap, "%.1fs", (double)st->age_ms / 1000.0);
}

static void mm_quality_text(const struct df1_tag_state *st, char *buf, size_t cap)
{
	if (!(st->config->access & DF1_ACCESS_READ))
		snprintf(buf, cap, "write-only");
	else if (st->quality == DF1_QUALITY_GOOD)
		snprintf(buf, cap, "GOOD");
	else
		snprintf(buf, cap, "%s %s", df1_quality_name(st->quality), df1_reason_name(st->reason));
}

static void mm_addr_text(const struct df1_tag_state *st, char *buf, size_t cap)
{
	if (df1_addr_format_plc(st->config->plc, &st->config->addr, buf, cap) < 0)
		snprintf(buf, cap, "?");
	if (st->count > 1) {
		size_t l = strlen(buf);

		snprintf(buf + l, cap - l, ",%zu", st->count);
	}
}

/* JSON value: numbers as numbers (non-finite floats null), bits 0/1, text as strings. */
static void mm_json_value(FILE *f, const struct df1_tag_state *st, const struct df1_value *v)
{
	char one[160];

	switch (v->kind) {
	case DF1_VAL_INT16:
	case DF1_VAL_INT32:
	case DF1_VAL_FLOAT:
	case DF1_VAL_BIT:
		if (df1_value_format(v, mm_value_type(st->config), one, sizeof one) < 0 ||
		    strchr(one, 'n') || strchr(one, 'i'))
			fputs("null", f);       /* nan, inf */
		else
			fputs(one, f);
		break;
	default:
		if (df1_value_format(v, mm_value_type(st->config), one, sizeof one) < 0)
			one[0] = '\0';
		cli_json_string(f, one);
		break;
	}
}

/* ---- output ---- */

/* CLOCK_REALTIME in ns: InfluxDB's default precision. */
static int64_t mm_wall_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static void mm_counters(struct mm *m)
{
	FILE *f = stdout;
	struct df1_poll_stats ps;
	bool first = true;

	if (m->format == MON_MAP_INFLUX) {
		mon_influx_counters(f, m->h, mm_wall_ns());
		return;
	}
	df1_poll_stats(m->h, &ps);
	if (m->format == MON_MAP_JSON)
		fprintf(f, "{\"t\":%.3f,\"scans\":%llu,\"scan_ms\":%lld,\"transactions_per_scan\":%u,"
		        "\"counters\":[", mm_elapsed(m), (unsigned long long)ps.scans,
		        (long long)ps.last_scan_ms, ps.last_scan_transactions);
	else
		fprintf(f, "%sscans %llu, last scan %lld ms, %u transactions per scan (%u blocks, "
		        "%llu reads, %llu failed, %llu writes, %llu retries)\n",
		        m->format == MON_MAP_CSV ? "# " : "", (unsigned long long)ps.scans,
		        (long long)ps.last_scan_ms, ps.last_scan_transactions, ps.blocks,
		        (unsigned long long)ps.reads, (unsigned long long)ps.read_failures,
		        (unsigned long long)ps.writes, (unsigned long long)ps.retries);
	for (size_t i = 0;; i++) {
		const struct df1_catalog_entry *e = df1_catalog_at(i);
		uint64_t v = 0;

		if (!e)
			break;
		if (e->severity != DF1_SEV_COUNTER || df1_counter(m->h, e->id, &v) < 0)
			continue;
		if (m->format == MON_MAP_JSON)
			fprintf(f, "%s{\"id\":%d,\"mnemonic\":\"%s\",\"value\":%llu}", first ? "" : ",",
			        e->id, e->mnemonic, (unsigned long long)v);
		else
			fprintf(f, "%s%d %s %llu\n", m->format == MON_MAP_CSV ? "# " : "", e->id,
			        e->mnemonic, (unsigned long long)v);
		first = false;
	}
	if (m->format == MON_MAP_JSON)
		fputs("]}\n", f);
}

static void mm_plain(struct mm *m)
{
	FILE *f = stdout;
	int n = df1_tag_count(m->h);
	int wname = 3, waddr = 7;
	struct df1_poll_stats ps;

	for (int id = 0; id < n; id++) {
		struct df1_tag_state st;
		char a[80];
		int l;

		if (df1_tag_get(m->h, id, &st) < 0)
			continue;
		l = (int)strlen(st.config->name);
		if (l > wname)
			wname = l;
		mm_addr_text(&st, a, sizeof a);
		l = (int)strlen(a);
		if (l > waddr)
			waddr = l;
	}
	if (m->tty)
		fputs("\033[H\033[2J", f);
	fprintf(f, "%-*s %3s %-*s %-*s %-26s %s\n", wname, "TAG", "STN", waddr, "ADDRESS",
	        MM_VALUE_WIDTH, "VALUE", "QUALITY", "AGE");
	for (int id = 0; id < n; id++) {
		struct df1_tag_state st;
		char a[80], v[1024], q[64], age[32];

		if (df1_tag_get(m->h, id, &st) < 0)
			continue;
		mm_addr_text(&st, a, sizeof a);
		mm_values_text(&st, ",", v, sizeof v);
		if (strlen(v) > MM_VALUE_WIDTH)
			memcpy(v + MM_VALUE_WIDTH - 3, "...", 4);
		mm_quality_text(&st, q, sizeof q);
		mm_age_text(&st, age, sizeof age);
		fprintf(f, "%-*s %3d %-*s %-*s %-26s %s\n", wname, st.config->name, st.config->station,
		        waddr, a, MM_VALUE_WIDTH, v, q, age);
	}
	df1_poll_stats(m->h, &ps);
	fprintf(f, "scan %llu: %lld ms, %u transactions, %u blocks for %u tags, %u station%s offline\n",
	        (unsigned long long)m->scan, (long long)ps.last_scan_ms, ps.last_scan_transactions,
	        ps.blocks, ps.tags, ps.stations_offline, ps.stations_offline == 1 ? "" : "s");
	if (m->tty && m->counters)
		mm_counters(m);
	if (!m->tty)
		fputc('\n', f);
}

static void mm_records(struct mm *m)
{
	FILE *f = stdout;
	int n = df1_tag_count(m->h);
	int64_t now_ns = mm_wall_ns();

	for (int id = 0; id < n; id++) {
		struct df1_tag_state st;
		char a[80], v[2048];

		if (df1_tag_get(m->h, id, &st) < 0)
			continue;
		if (m->format == MON_MAP_INFLUX) {
			mon_influx_tag(f, &st, now_ns);
			continue;
		}
		if (df1_addr_format_plc(st.config->plc, &st.config->addr, a, sizeof a) < 0)
			snprintf(a, sizeof a, "?");
		if (m->format == MON_MAP_CSV) {
			mm_values_text(&st, " ", v, sizeof v);
			fprintf(f, "%.3f,%llu,", mm_elapsed(m), (unsigned long long)m->scan);
			cli_csv_field(f, st.config->name);
			fprintf(f, ",%d,", st.config->station);
			cli_csv_field(f, a);
			fputc(',', f);
			cli_csv_field(f, st.has_value ? v : "");
			fprintf(f, ",%s,%s,", df1_quality_name(st.quality), df1_reason_name(st.reason));
			if (st.age_ms >= 0)
				fprintf(f, "%lld", (long long)st.age_ms);
			fputc('\n', f);
			continue;
		}
		fprintf(f, "{\"t\":%.3f,\"scan\":%llu,\"tag\":", mm_elapsed(m), (unsigned long long)m->scan);
		cli_json_string(f, st.config->name);
		fprintf(f, ",\"station\":%d,\"address\":", st.config->station);
		cli_json_string(f, a);
		fputs(",\"value\":", f);
		if (!st.has_value) {
			fputs("null", f);
		} else if (st.count == 1) {
			mm_json_value(f, &st, &st.values[0]);
		} else {
			fputc('[', f);
			for (size_t i = 0; i < st.count; i++) {
				if (i)
					fputc(',', f);
				mm_json_value(f, &st, &st.values[i]);
			}
			fputc(']', f);
		}
		fprintf(f, ",\"quality\":\"%s\",\"reason\":\"%s\",\"age_ms\":",
		        df1_quality_name(st.quality), df1_reason_name(st.reason));
		if (st.age_ms >= 0)
			fprintf(f, "%lld}\n", (long long)st.age_ms);
		else
			fputs("null}\n", f);
	}
}

/* ---- loading ---- */

static void mm_issue(void *user, const struct df1_config_issue *is)
{
	struct mm *m = user;
	const struct df1_catalog_entry *e = is->catalog_id ? df1_catalog_by_id(is->catalog_id) : NULL;

	m->issues++;
	if (e)
		fprintf(stderr, "%s: %s: line %d: [%d] %s: %s\n", MM_PROG, m->path, is->line, e->id,
		        e->mnemonic, is->text);
	else if (is->line > 0)
		fprintf(stderr, "%s: %s: line %d: %s\n", MM_PROG, m->path, is->line, is->text);
	else
		fprintf(stderr, "%s: %s: %s\n", MM_PROG, m->path, is->text);
}

/* Any readable tag BAD? */
static bool mm_any_bad(df1_t *h)
{
	int n = df1_tag_count(h);

	for (int id = 0; id < n; id++) {
		struct df1_tag_state st;

		if (df1_tag_get(h, id, &st) == 0 && (st.config->access & DF1_ACCESS_READ) &&
		    st.quality == DF1_QUALITY_BAD)
			return true;
	}
	return false;
}

int mon_map_run(df1_t *h, const char *csv_path, bool skip_bad_rows, int format, bool once, bool counters,
                int interval_ms, volatile sig_atomic_t *stop)
{
	struct mm m;
	int64_t last_counters;
	uint64_t seen = 0;
	int rc, status = 0;

	memset(&m, 0, sizeof m);
	m.h = h;
	m.path = csv_path;
	m.format = format == MON_MAP_CSV || format == MON_MAP_JSON || format == MON_MAP_INFLUX
	           ? format : MON_MAP_PLAIN;
	m.tty = m.format == MON_MAP_PLAIN && isatty(STDOUT_FILENO);
	m.counters = counters;
	m.t0 = mm_now_ms();
	last_counters = m.t0;
	if (!h || !csv_path)
		return 2;
	rc = df1_tag_load_map(h, csv_path, !skip_bad_rows, mm_issue, &m);
	if (rc < 0) {
		const struct df1_error_detail *d = df1_last_error(h);

		if (m.issues == 0)      /* else the issues said it already */
			fprintf(stderr, "%s: %s: %s\n", MM_PROG, csv_path,
			        d && d->message[0] ? d->message : df1_strerror(rc));
		return 2;
	}
	if (df1_tag_count(h) == 0) {
		fprintf(stderr, "%s: %s: no valid tag to poll\n", MM_PROG, csv_path);
		return 2;
	}
	if (m.format == MON_MAP_CSV)
		fputs("t,scan,tag,station,address,value,quality,reason,age_ms\n", stdout);
	while (!stop || !*stop) {
		struct df1_poll_stats ps;

		rc = df1_poll(h, MM_POLL_MS);
		if (rc == DF1_E_INTR)
			break;
		if (rc < 0) {
			const struct df1_error_detail *d = df1_last_error(h);

			fprintf(stderr, "%s: poll: %s: %s\n", MM_PROG, df1_errname(rc),
			        d && d->message[0] ? d->message : df1_strerror(rc));
			status = 1;
			break;
		}
		df1_poll_stats(h, &ps);
		if (ps.scans == seen)
			continue;
		seen = ps.scans;
		m.scan++;
		if (m.format == MON_MAP_PLAIN)
			mm_plain(&m);
		else
			mm_records(&m);
		if (counters && !m.tty && !once && interval_ms > 0 &&
		    mm_now_ms() - last_counters >= interval_ms) {
			mm_counters(&m);
			last_counters = mm_now_ms();
		}
		fflush(stdout);
		if (once)
			break;
	}
	if (counters && !m.tty)
		mm_counters(&m);
	fflush(stdout);
	if (status == 0 && once && (m.scan == 0 || mm_any_bad(h)))
		status = 1;
	return status;
}
