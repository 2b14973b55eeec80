/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_autoconf.c - df1mon --autoconf [--stations A-B] [-w net.csv]: find an
 * unknown line's settings with df1_probe_line() (df1_probe_line(3)). Progress
 * on stderr (what is tried, what answered); at the end one line on stdout,
 * the settings in the tools' own option spelling, so that
 *   df1read -d DEV $(df1mon -d DEV --autoconf) N7:0
 * works; with -w a network CSV (doc/REQUIREMENTS.md 004's fields) of them.
 * Nothing answered: exit 1 with what was tried and the likely causes.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "df1mon/mon.h"

static const char *mon_ac_parity(char p)
{
	return p == 'E' ? "even" : p == 'O' ? "odd" : "none";
}

static int mon_ac_progress(void *user, const struct df1_probe_attempt *a)
{
	struct mon *m = user;
	const struct df1_line_settings *t = &a->tried;

	if (cli_stop)
		return 1;
	/* stage 1 misses are many: shown with -v only; what answered always */
	if (!m->cli.quiet && (a->answered || a->stage != DF1_PROBE_LINK || m->cli.verbose)) {
		fprintf(stderr, "%s: %d %d%c%d %s duplex", m->cli.name, t->baud, t->data_bits,
		        t->parity, t->stop_bits, t->duplex == DF1_FULL_DUPLEX ? "full" : "half");
		if (a->stage == DF1_PROBE_CHECK)
			fprintf(stderr, " %s%s", t->check == DF1_CHECK_BCC ? "BCC" : "CRC",
			        t->hd_bcc_stx ? " (with STX)" : "");
		if (t->station >= 0)
			fprintf(stderr, " station %d", t->station);
		fprintf(stderr, ": %s: %s\n", a->what, a->answered ? "answered" : df1_strerror(a->error));
	}
	return 0;
}

/* The settings as the tools' options, on stdout. */
static void mon_ac_print(const struct df1_line_settings *f)
{
	printf("-b %d -P %s --check %s --duplex %s", f->baud, mon_ac_parity(f->parity),
	       f->check == DF1_CHECK_BCC ? "bcc" : "crc",
	       f->duplex == DF1_FULL_DUPLEX ? "full" : "half");
	if (f->data_bits != 8)
		printf(" --data-bits %d", f->data_bits);
	if (f->hd_bcc_stx)
		printf(" --hd-bcc stx");
	if (f->duplex != DF1_FULL_DUPLEX)
		printf(" -a %d", f->station);
	putchar('\n');
}

static const char *mon_ac_plc(const struct df1_probe_result *r)
{
	if (!r->identified)
		return "SLC";
	if (strncmp(r->status.name, "PLC-5", 5) == 0)
		return "PLC5";
	if (strncmp(r->status.name, "MicroLogix", 10) == 0)
		return "MicroLogix";
	return "SLC";
}

/* -w FILE: a network CSV of the settings found (df1_net_config_load reads it). */
static int mon_ac_write(struct mon *m, const struct df1_probe_result *r)
{
	const struct df1_line_settings *f = &r->found;
	FILE *fp = fopen(m->pcap_path, "w");

	if (!fp) {
		fprintf(stderr, "%s: -w %s: %s\n", m->cli.name, m->pcap_path, strerror(errno));
		return CLI_EXIT_FAIL;
	}
	fprintf(fp, "# found by df1mon --autoconf on %s\n", m->cli.device);
	fprintf(fp, "Station,Mode,PLC_Type,Error_Code,Com_Port,Baud,Data_Bits,Stop_Bits,Parity\n");
	fprintf(fp, "%d,%s,%s,%s,%s,%d,%d,%d,%s\n", f->duplex == DF1_FULL_DUPLEX ? 0 : f->station,
	        f->duplex == DF1_FULL_DUPLEX ? "Peer" : "Master", mon_ac_plc(r),
	        f->check == DF1_CHECK_BCC ? "BCC" : "CRC", m->cli.device, f->baud, f->data_bits,
	        f->stop_bits, f->parity == 'E' ? "Even" : f->parity == 'O' ? "Odd" : "None");
	if (fclose(fp) != 0) {
		fprintf(stderr, "%s: -w %s: %s\n", m->cli.name, m->pcap_path, strerror(errno));
		return CLI_EXIT_FAIL;
	}
	return CLI_EXIT_OK;
}

static void mon_ac_nothing(struct mon *m, const struct df1_probe_result *r)
{
	fprintf(stderr, "%s: nothing answered on %s after %d attempts in %.1f s: every baud rate "
	        "1200-115200, parity none, even and odd (8 data bits), full duplex (DLE ENQ) and "
	        "half duplex (polls of stations %d-%d)\n", m->cli.name, m->cli.device, r->attempts,
	        (double)r->elapsed_ms / 1000.0, m->who_lo, m->who_hi);
	fprintf(stderr, "%s: likely causes: the cable or its wiring (TX/RX crossed? a null-modem "
	        "needed?), the controller's channel in DH-485, ASCII or Modbus mode rather than DF1, "
	        "its station outside %d-%d (--stations), or no power\n", m->cli.name, m->who_lo,
	        m->who_hi);
}

int mon_run_autoconf(struct mon *m)
{
	struct df1_probe_result r;
	int64_t bound = df1_probe_line_bound_ms(m->h, m->who_lo, m->who_hi);
	int rc;

	if (!m->cli.quiet)
		fprintf(stderr, "%s: auto-configuring %s (stations %d-%d): at most %.0f s\n",
		        m->cli.name, m->cli.device, m->who_lo, m->who_hi, (double)bound / 1000.0 + 1);
	rc = df1_probe_line(m->h, m->who_lo, m->who_hi, mon_ac_progress, m, &r);
	if (rc < 0) {
		fprintf(stderr, "%s: %s: %s\n", m->cli.name, m->cli.device,
		        df1_last_error(m->h)->message[0] ? df1_last_error(m->h)->message : df1_strerror(rc));
		return CLI_EXIT_FAIL;
	}
	if (rc == 0) {
		mon_ac_nothing(m, &r);
		return CLI_EXIT_FAIL;
	}
	if (!m->cli.quiet) {
		fprintf(stderr, "%s: found in %.1f s (%d attempts)", m->cli.name,
		        (double)r.elapsed_ms / 1000.0, r.attempts);
		if (r.identified)
			fprintf(stderr, ": %s", r.status.name);
		if (r.nstations) {
			fprintf(stderr, "; stations answering:");
			for (int i = 0; i < r.nstations; i++)
				fprintf(stderr, " %d", r.stations[i]);
		}
		fputc('\n', stderr);
	}
	mon_ac_print(&r.found);
	if (m->pcap_path)
		return mon_ac_write(m, &r);
	return CLI_EXIT_OK;
}
