/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_who - df1mon --who: station discovery with processor type; with an
 * eip:// device, what EtherNet/IP ListIdentity reports.
 */
#include "df1mon/mon.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* "N" or "LO-HI", 0..254. */
int mon_parse_range(struct mon *m, const char *arg)
{
	char *end;
	long lo, hi;

	errno = 0;
	lo = strtol(arg, &end, 10);
	hi = lo;
	if (end != arg && *end == '-') {
		const char *p = end + 1;
		hi = strtol(p, &end, 10);
		if (end == p)
			hi = -1;
	}
	if (end == arg || *end || errno || lo < 0 || hi > 254 || lo > hi || hi < 0)
		return cli_usage_error(&m->cli, "--who: invalid station range '%s' (expected LO-HI within 0-254)", arg);
	m->who_lo = (int)lo;
	m->who_hi = (int)hi;
	return CLI_CONTINUE;
}

static void who_line(const struct mon *m, int stn, const struct df1_diag_status *d, const char *err)
{
	switch (m->cli.format) {
	case CLI_FMT_INFLUX: /* refused without --map */
	case CLI_FMT_PROMETHEUS: /* refused without --counters */
	case CLI_FMT_PLAIN:
		if (err)
			printf("station %d: answers; diagnostic status failed: %s\n", stn, err);
		else
			printf("station %d: %s series %c rev %d (type 0x%02X) mode %s\n", stn, d->name,
			       d->series, d->revision, d->type_code, d->mode_text);
		break;
	case CLI_FMT_CSV:
		if (err) {
			printf("%d,,,,,,,,", stn);
			cli_csv_field(stdout, err);
			putchar('\n');
		} else {
			printf("%d,%02X,", stn, d->type_code);
			cli_csv_field(stdout, d->name);
			printf(",%c,%d,%d,", d->series, d->revision, d->mode);
			cli_csv_field(stdout, d->mode_text);
			putchar(',');
			cli_csv_field(stdout, d->bulletin);
			puts(",");
		}
		break;
	case CLI_FMT_JSON:
		printf("{\"station\":%d", stn);
		if (err) {
			fputs(",\"error\":", stdout);
			cli_json_string(stdout, err);
		} else {
			printf(",\"type_code\":\"%02X\",\"processor\":", d->type_code);
			cli_json_string(stdout, d->name);
			printf(",\"series\":\"%c\",\"revision\":%d,\"mode\":%d,\"mode_text\":", d->series,
			       d->revision, d->mode);
			cli_json_string(stdout, d->mode_text);
			fputs(",\"bulletin\":", stdout);
			cli_json_string(stdout, d->bulletin);
		}
		fputs("}\n", stdout);
		break;
	}
	fflush(stdout);
}

/* What mon_run_who gathers from df1_discover's calls. */
struct who_scan {
	struct mon *m;
	int found, last, calls;
	char list[1024];
	size_t ll;
};

/* One station of df1_discover: its line, or (-v) why it did not answer. A stop
 * by a signal drops the station under way, as an interrupted probe would. */
static int who_station(void *user, const struct df1_discover_result *r)
{
	struct who_scan *w = user;
	struct mon *m = w->m;
	char text[320];

	w->calls++;
	if (cli_stop)
		return 1;
	w->last = r->station;
	/* full duplex: a station that is not identified gave no reply to this DST */
	if (!r->answered || (!m->cli.half_duplex && !r->identified)) {
		if (m->cli.verbose >= 1) {
			cli_error_text(m->h, r->error, text, sizeof text);
			fprintf(stderr, "%s: station %d: %s\n", m->cli.name, r->station, text);
		}
		return mon_out_broken();
	}
	if (r->identified) {
		who_line(m, r->station, &r->status, NULL);
	} else {
		cli_error_text(m->h, r->error, text, sizeof text);
		who_line(m, r->station, NULL, text);
	}
	w->found++;
	if (w->ll + 8 < sizeof w->list)
		w->ll += (size_t)snprintf(w->list + w->ll, sizeof w->list - w->ll, " %d", r->station);
	return mon_out_broken();
}

bool mon_who_is_eip(const struct mon *m)
{
	return m->cli.device && strncasecmp(m->cli.device, "eip:", 4) == 0;
}

/* One device of df1_eip_list_identity(3). */
static void who_device(void *user, const struct df1_eip_device *d)
{
	struct who_scan *w = user;

	w->found++;
	switch (w->m->cli.format) {
	case CLI_FMT_CSV:
		printf("%s,%u,%u,%u,%u.%u,%08X,", d->address, d->vendor_id, d->device_type,
		       d->product_code, d->rev_major, d->rev_minor, d->serial);
		cli_csv_field(stdout, d->product_name);
		printf(",%u,%04X\n", d->state, d->status);
		break;
	case CLI_FMT_JSON:
		fputs("{\"address\":", stdout);
		cli_json_string(stdout, d->address);
		printf(",\"vendor_id\":%u,\"device_type\":%u,\"product_code\":%u,"
		       "\"revision\":\"%u.%u\",\"serial\":\"%08X\",\"product_name\":",
		       d->vendor_id, d->device_type, d->product_code, d->rev_major, d->rev_minor,
		       d->serial);
		cli_json_string(stdout, d->product_name);
		printf(",\"state\":%u,\"status\":\"%04X\"}\n", d->state, d->status);
		break;
	default:
		printf("%s: \"%s\" vendor %u device type %u product code %u revision %u.%u "
		       "serial %08X state %u status %04X\n", d->address, d->product_name, d->vendor_id,
		       d->device_type, d->product_code, d->rev_major, d->rev_minor, d->serial, d->state,
		       d->status);
		break;
	}
	fflush(stdout);
}

/* --who with an eip:// device: ListIdentity, TCP to the host or UDP to a
 * broadcast address, answers until -o. The station range does not apply. */
static int run_who_eip(struct mon *m)
{
	struct who_scan w;
	char text[320];
	int r;

	memset(&w, 0, sizeof w);
	w.m = m;
	if (m->cli.format == CLI_FMT_CSV)
		puts("address,vendor_id,device_type,product_code,revision,serial,product_name,state,"
		     "status");
	r = df1_eip_list_identity(m->h, m->cli.device, m->cli.timeout_ms, who_device, &w);
	if (r < 0 && r != DF1_E_INTR && !cli_stop) {
		if (!m->cli.quiet) {
			cli_error_text(m->h, r, text, sizeof text);
			fprintf(stderr, "%s: --who: %s: %s\n", m->cli.name, m->cli.device, text);
		}
		return CLI_EXIT_FAIL;
	}
	if (!m->cli.quiet)
		fprintf(stderr, "%s: %s: %d device%s answered ListIdentity\n", m->cli.name,
		        m->cli.device, w.found, w.found == 1 ? "" : "s");
	return w.found > 0 ? CLI_EXIT_OK : CLI_EXIT_FAIL;
}

/*
 * df1_discover(3) does the probing: half duplex, a poll per station, bounded
 * by -o (200 ms by default for --who), and the diagnostic status of a station
 * that answers; full duplex, one DLE ENQ first (no answer: nothing on the
 * line), then a diagnostic status with DST = each station of the range; a
 * point-to-point peer may answer whatever the DST, which the summary says.
 */
int mon_run_who(struct mon *m)
{
	bool half = m->cli.half_duplex;
	struct who_scan w;
	char text[320];
	int r = 0;

	if (mon_who_is_eip(m))
		return run_who_eip(m);
	memset(&w, 0, sizeof w);
	w.m = m;
	w.last = -1;
	if (m->cli.format == CLI_FMT_CSV)
		puts("station,type_code,processor,series,revision,mode,mode_text,bulletin,error");
	if (!cli_stop && !mon_out_broken())
		r = df1_discover(m->h, m->who_lo, m->who_hi, who_station, &w);
	if (r < 0 && r != DF1_E_INTR && !cli_stop) {
		if (!m->cli.quiet) {
			cli_error_text(m->h, r, text, sizeof text);
			if (!half && w.calls == 0)
				fprintf(stderr, "%s: no answer to DLE ENQ, nothing on the line: %s\n", m->cli.name, text);
			else
				fprintf(stderr, "%s: --who: %s\n", m->cli.name, text);
		}
		if (!half && w.calls == 0)
			return CLI_EXIT_FAIL;
	}
	if (!m->cli.quiet) {
		if (mon_interrupted())
			fprintf(stderr, "%s: stopped by %s after station %d\n", m->cli.name,
			        mon_signal_name(cli_stop_signal()), w.last);
		fprintf(stderr, "%s: stations %d-%d (%s duplex): %d answered%s%s\n", m->cli.name, m->who_lo,
		        m->who_hi, half ? "half" : "full", w.found, w.found ? ":" : "", w.list);
		if (!half && w.found > 1)
			fprintf(stderr, "%s: full duplex: a point-to-point peer answers whatever the DST; "
			        "these may all be one device\n", m->cli.name);
	}
	return w.found > 0 ? CLI_EXIT_OK : CLI_EXIT_FAIL;
}
