/*
 * mon_who - df1mon --who: station discovery with processor type.
 */
#include <errno.h>
#include <stdlib.h>

#include "mon.h"

/* ---- --who ---- */

/* "N" or "LO-HI", 0..254. */
int parse_range(struct mon *m, const char *arg)
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

/*
 * Half duplex: a poll (df1_link_test) per station, bounded by -o (200 ms by
 * default for --who); a station that answers is asked its diagnostic status.
 * Full duplex: a DLE ENQ first (no answer: nothing on the line), then a
 * diagnostic status with DST = each station of the range; a point-to-point
 * peer may answer whatever the DST, which the summary says.
 */
int run_who(struct mon *m)
{
	bool half = m->cli.half_duplex;
	int found = 0, last = -1, r;
	char text[320], list[1024];
	size_t ll = 0;

	list[0] = 0;
	if (m->cli.format == CLI_FMT_CSV)
		puts("station,type_code,processor,series,revision,mode,mode_text,bulletin,error");
	if (!half) {
		r = df1_link_test(m->h, m->who_lo);
		if (r < 0 && r != DF1_E_INTR && !cli_stop) {
			if (!m->cli.quiet) {
				cli_error_text(m->h, r, text, sizeof text);
				fprintf(stderr, "%s: no answer to DLE ENQ, nothing on the line: %s\n", m->cli.name, text);
			}
			return CLI_EXIT_FAIL;
		}
	}
	for (int stn = m->who_lo; stn <= m->who_hi && !cli_stop && !out_broken(); stn++) {
		struct df1_diag_status d;

		if (half) {
			r = df1_link_test(m->h, stn);
			if (r == DF1_E_INTR || cli_stop)
				break;
			if (r < 0) {
				if (m->cli.verbose >= 1) {
					cli_error_text(m->h, r, text, sizeof text);
					fprintf(stderr, "%s: station %d: %s\n", m->cli.name, stn, text);
				}
				last = stn;
				continue;
			}
		}
		r = df1_diag_status(m->h, stn, &d);
		if (r == DF1_E_INTR || cli_stop)
			break;
		last = stn;
		if (r < 0) {
			cli_error_text(m->h, r, text, sizeof text);
			if (!half) {
				/* full duplex: no reply to this DST */
				if (m->cli.verbose >= 1)
					fprintf(stderr, "%s: station %d: %s\n", m->cli.name, stn, text);
				continue;
			}
			who_line(m, stn, NULL, text);
		} else {
			who_line(m, stn, &d, NULL);
		}
		found++;
		if (ll + 8 < sizeof list)
			ll += (size_t)snprintf(list + ll, sizeof list - ll, " %d", stn);
	}
	if (!m->cli.quiet) {
		if (interrupted())
			fprintf(stderr, "%s: stopped by %s after station %d\n", m->cli.name,
			        signal_name(cli_stop_signal()), last);
		fprintf(stderr, "%s: stations %d-%d (%s duplex): %d answered%s%s\n", m->cli.name, m->who_lo,
		        m->who_hi, half ? "half" : "full", found, found ? ":" : "", list);
		if (!half && found > 1)
			fprintf(stderr, "%s: full duplex: a point-to-point peer answers whatever the DST; "
			        "these may all be one device\n", m->cli.name);
	}
	return found > 0 ? CLI_EXIT_OK : CLI_EXIT_FAIL;
}
