/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_counters - df1mon: the counter table (ID MNEMONIC VALUE) and --counters
 * alone; with -f prometheus one snapshot in the text exposition format, at
 * the end (node-exporter's textfile collector reads whole files).
 */
#include "df1mon/mon.h"

/* Every counter of the seed table in ID order (2525-2551, 2560, 2561). */
void mon_print_counters(struct mon *m, bool final)
{
	FILE *f = stdout;
	int n;

	if (!m->h)
		return;
	if (m->cli.format == CLI_FMT_PROMETHEUS && !final)
		return;         /* one snapshot: a family appears once in a file */
	switch (m->cli.format) {
	case CLI_FMT_INFLUX: /* refused without --map */
	case CLI_FMT_PLAIN:
		if (m->counter_prints)
			fputc('\n', f);   /* blocks are separated by a blank line */
		break;
	case CLI_FMT_CSV:
		if (!m->counter_prints)
			fputs("t,id,mnemonic,value\n", f);
		break;
	case CLI_FMT_PROMETHEUS:
		break;
	case CLI_FMT_JSON:
		fprintf(f, "{\"t\":%.3f,\"final\":%s,\"counters\":[", mon_elapsed(m), final ? "true" : "false");
		break;
	}
	n = cli_print_counters(f, m->h, m->cli.format, mon_elapsed(m));
	if (m->cli.radio) /* then the radio modem's: relayed, duplicates, ... (ID 0) */
		cli_print_radio(f, m->h, m->cli.format, mon_elapsed(m), n > 0);
	if (m->cli.format == CLI_FMT_JSON)
		fputs("]}\n", f);
	m->counter_prints++;
	fflush(f);
}

/* --counters alone: a link test, then the counters; with -i or -c, again every
 * interval until -c N tables, --duration or a signal. Exit 0 if every link test
 * was answered. */
int mon_run_counters(struct mon *m)
{
	long count = (m->given & GIVEN_COUNT) ? m->count : (m->given & GIVEN_INTERVAL) ? 0 : 1;
	double interval = (m->given & GIVEN_INTERVAL) ? m->interval_s : 1.0;
	unsigned long tests = 0, failed = 0;
	char text[320];

	for (long k = 1;; k++) {
		int r = df1_link_test(m->h, m->cli.station);

		if (r == DF1_E_INTR || cli_stop)
			break;
		tests++;
		if (r < 0) {
			failed++;
			if (!m->cli.quiet) {
				cli_error_text(m->h, r, text, sizeof text);
				fprintf(stderr, "%s: link test: station %d: %s\n", m->cli.name, m->cli.station, text);
			}
		}
		if (count && k >= count)
			break;
		mon_print_counters(m, false);
		if (mon_out_broken() || !mon_sleep(mon_ms_of(interval)))
			break;
	}
	mon_print_counters(m, true);
	if (mon_interrupted() && !m->cli.quiet)
		fprintf(stderr, "%s: stopped by %s after %lu link test%s\n", m->cli.name,
		        mon_signal_name(cli_stop_signal()), tests, tests == 1 ? "" : "s");
	return (tests > 0 && failed == 0) ? CLI_EXIT_OK : CLI_EXIT_FAIL;
}
