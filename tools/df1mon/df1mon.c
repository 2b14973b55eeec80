/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1mon - DF1 diagnostics (doc/ARCHITECTURE.md 8).
 *
 * Offline modes (no device):
 *   --decode [HEX...]  frames given as hex: each argument (or each stdin line) is
 *                      decoded on its own, with a fresh decoder
 *   --read FILE        a pcap (link type 250, RTAC serial) or a raw byte dump
 * Live modes (a device: -d DEV, DF1_DEVICE or -N FILE):
 *   --sniff            listen only, never transmit: decode what a tap shows
 *                      (--sniff-b DEV2 for a second tap, -w FILE.pcap to save)
 *   --ping             link test + 06/00 echo per probe, round-trip times
 *   --who [LO-HI]      station discovery with diagnostic status
 *   --map FILE.csv     poll a tag list (tools/df1mon/mon_map.c, the poll engine)
 *   --counters         the seed counter table at exit (alone: a link test
 *                      every -i interval, counters after each)
 * A mode is an enum mon_mode value, an entry in modes[] (what it accepts), an
 * option in mon_opts[] and its run function, in a file of its own (mon.h
 * lists them).
 *
 * Decoding modes print one line per symbol on stdout (tools/common/decode.c) and a
 * summary on stderr unless -q. SIGINT/SIGTERM (and --duration) end a live mode
 * normally: the port's settings are restored and what was done is printed.
 * Exit: 0 success, 1 a communication error, a bad check or a malformed symbol,
 * no answer; 2 usage, unreadable input or bad hex. Per mode in df1mon(1).
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1mon/mon.h"
#include "df1mon/mon_map.h"   /* --map: the poll engine's live table */

/* ---- --map ---- */

/* The table is mon_map.c's: it also prints the counters (every interval and at
 * exit) when asked, so main does not print them again. */
static int mon_run_map(struct mon *m)
{
	int fmt = m->cli.format == CLI_FMT_CSV      ? MON_MAP_CSV
	        : m->cli.format == CLI_FMT_JSON   ? MON_MAP_JSON
	        : m->cli.format == CLI_FMT_INFLUX ? MON_MAP_INFLUX
	                                          : MON_MAP_PLAIN;
	int interval_ms = (m->given & GIVEN_INTERVAL) ? (int)mon_ms_of(m->interval_s) : 1000;

	return mon_map_run(m->h, m->map_file, m->skip_bad_rows, fmt, m->once, m->counters, interval_ms,
	                   &cli_stop);
}

/* ======================================================================
 * Modes, options, main
 * ====================================================================== */

enum {
	LIVE = 1 << 0,        /* needs a device */
	TALKS = 1 << 1,       /* opens a libdf1 handle and transmits */
	TAKES_COUNT = 1 << 2,
	TAKES_INTERVAL = 1 << 3,
	TAKES_COUNTERS = 1 << 4,
	TAKES_CSV = 1 << 5,
};

struct mon_mode_def {
	const char *option;            /* for messages */
	int (*run)(struct mon *m);     /* CLI_CONTINUE: status from the decode tallies; else an exit status */
	unsigned flags;
};

static const struct mon_mode_def modes[MODE_COUNT_] = {
	[MODE_DECODE] = { "--decode", mon_run_decode, 0 },
	[MODE_READ] = { "--read", mon_run_read, 0 },
	[MODE_SNIFF] = { "--sniff", mon_run_sniff, LIVE | TAKES_COUNT },
	[MODE_PING] = { "--ping", mon_run_ping, LIVE | TALKS | TAKES_COUNT | TAKES_INTERVAL | TAKES_COUNTERS | TAKES_CSV },
	[MODE_WHO] = { "--who", mon_run_who, LIVE | TALKS | TAKES_COUNTERS | TAKES_CSV },
	[MODE_MAP] = { "--map", mon_run_map, LIVE | TALKS | TAKES_INTERVAL | TAKES_COUNTERS | TAKES_CSV },
	[MODE_COUNTERS] = { "--counters", mon_run_counters, LIVE | TALKS | TAKES_COUNT | TAKES_INTERVAL | TAKES_CSV },
	[MODE_AUTOCONF] = { "--autoconf", mon_run_autoconf, LIVE | TALKS },
	[MODE_SERVE] = { "--serve", mon_run_serve, LIVE | TALKS },
};

static const struct cli_extra_opt mon_opts[] = {
	{ "decode", no_argument, KEY_DECODE, NULL,
	  "decode HEX arguments, or stdin lines, one chunk each" },
	{ "read", required_argument, 'r', "FILE", "decode a pcap (RTAC serial) or raw dump; - for stdin" },
	{ "sniff", no_argument, KEY_SNIFF, NULL, "listen to the device (a tap), never transmit" },
	{ "sniff-b", required_argument, KEY_SNIFF_B, "DEV2",
	  "--sniff: a second tap for the other direction" },
	{ "write", required_argument, 'w', "FILE", "--sniff: save a pcap (RTAC serial); - for stdout" },
	{ "ping", no_argument, KEY_PING, NULL, "link test and 06/00 echo per probe, with times" },
	{ "who", optional_argument, KEY_WHO, "[=LO-HI]",
	  "stations that answer, with processor type (half duplex: 0-254)" },
	{ "map", required_argument, KEY_MAP, "FILE", "poll the tags of a mapping CSV, live table" },
	{ "counters", no_argument, KEY_COUNTERS, NULL,
	  "counter table (IDs 2525-2561) at exit; alone: link test each -i" },
	{ "autoconf", no_argument, KEY_AUTOCONF, NULL,
	  "find the line's settings; prints them as options (-w: a network CSV)" },
	{ "stations", required_argument, KEY_STATIONS, "LO-HI",
	  "--autoconf: half-duplex stations to poll (default 0-31)" },
	{ "serve", required_argument, KEY_SERVE, "REGION[,..]",
	  "answer a PLC's MSG from a table of ADDR[,COUNT] regions; print each write" },
	{ "count", required_argument, 'c', "N", "probes (--ping, 4), frames (--sniff), tables; 0: no limit" },
	{ "interval", required_argument, 'i', "SECONDS", "between probes, tables or scans (default 1; fractions allowed)" },
	{ "duration", required_argument, KEY_DURATION, "SECONDS", "stop a live mode after this time" },
	{ "once", no_argument, '1', NULL, "--map: one scan, then exit" },
	{ "skip-bad-rows", no_argument, KEY_SKIP_BAD_ROWS, NULL,
	  "--map: poll the good rows of a file with bad ones (default: refuse the file)" },
	{ NULL, 0, 0, NULL, NULL }
};

static int set_mode(struct mon *m, enum mon_mode mode)
{
	if (m->mode != MODE_NONE && m->mode != mode)
		return cli_usage_error(&m->cli, "%s and %s cannot be used together", modes[m->mode].option,
		                       modes[mode].option);
	m->mode = mode;
	return CLI_CONTINUE;
}

static int parse_seconds(struct mon *m, const char *opt, const char *arg, double lo, double hi,
                         double *out)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(arg, &end);
	if (!*arg || *end || errno || !isfinite(v) || v < lo || v > hi) {
		fprintf(stderr, "%s: %s: invalid value '%s' (expected seconds, %.10g-%.10g)\n", m->cli.name,
		        opt, arg, lo, hi);
		return CLI_EXIT_USAGE;
	}
	*out = v;
	return CLI_CONTINUE;
}

static int on_option(struct cli *c, int key, const char *arg, void *user)
{
	struct mon *m = user;
	int v, r;

	switch (key) {
	case KEY_DECODE:
		return set_mode(m, MODE_DECODE);
	case 'r':
		m->read_file = arg;
		return set_mode(m, MODE_READ);
	case KEY_SNIFF:
		return set_mode(m, MODE_SNIFF);
	case KEY_SNIFF_B:
		if (!*arg)
			return cli_usage_error(c, "--sniff-b: empty device");
		m->sniff_b = arg;
		m->given |= GIVEN_SNIFF_B;
		return CLI_CONTINUE;
	case 'w':
		if (!*arg)
			return cli_usage_error(c, "--write: empty file name");
		m->pcap_path = arg;
		m->given |= GIVEN_WRITE;
		return CLI_CONTINUE;
	case KEY_PING:
		return set_mode(m, MODE_PING);
	case KEY_AUTOCONF:
		return set_mode(m, MODE_AUTOCONF);
	case KEY_STATIONS:
		m->who_range = arg;
		m->given |= GIVEN_STATIONS;
		return CLI_CONTINUE;
	case KEY_WHO:
		m->who_range = arg;
		return set_mode(m, MODE_WHO);
	case KEY_MAP:
		m->map_file = arg;
		return set_mode(m, MODE_MAP);
	case KEY_SERVE:
		m->serve_spec = arg;
		return set_mode(m, MODE_SERVE);
	case KEY_COUNTERS:
		m->counters = true;
		m->given |= GIVEN_COUNTERS;
		return CLI_CONTINUE;
	case 'c':
		r = cli_parse_int(c, "--count", arg, 0, 1000000000, &v);
		m->count = v;
		m->given |= GIVEN_COUNT;
		return r;
	case 'i':
		m->given |= GIVEN_INTERVAL;
		return parse_seconds(m, "--interval", arg, 0, 86400, &m->interval_s);
	case KEY_DURATION:
		m->given |= GIVEN_DURATION;
		r = parse_seconds(m, "--duration", arg, 0.001, 31536000, &m->duration_s);
		return r;
	case '1':
		m->once = true;
		m->given |= GIVEN_ONCE;
		return CLI_CONTINUE;
	case KEY_SKIP_BAD_ROWS:
		m->skip_bad_rows = true;
		m->given |= GIVEN_SKIP_BAD_ROWS;
		return CLI_CONTINUE;
	default:
		return cli_usage_error(c, "unknown option");
	}
}

/* What goes with which mode; exit 2 with a message when something does not. */
static int check_combination(struct mon *m)
{
	const struct mon_mode_def *d;
	unsigned f;

	if (m->mode == MODE_NONE && m->counters)
		m->mode = MODE_COUNTERS;
	if (m->mode == MODE_NONE)
		return cli_usage_error(&m->cli, "no mode given: use --decode, --read FILE, --sniff, --ping, "
		                       "--who, --map FILE or --counters");
	d = &modes[m->mode];
	f = d->flags;
	if (m->counters && m->mode != MODE_COUNTERS && !(f & TAKES_COUNTERS))
		return cli_usage_error(&m->cli, "--counters does not go with %s%s", d->option,
		                       m->mode == MODE_SNIFF ? " (a sniffer never transmits, so has no "
		                       "link counters; its summary counts what it saw)" : "");
	if ((m->given & GIVEN_COUNT) && !(f & TAKES_COUNT))
		return cli_usage_error(&m->cli, "-c/--count does not go with %s", d->option);
	if ((m->given & GIVEN_INTERVAL) && !(f & TAKES_INTERVAL))
		return cli_usage_error(&m->cli, "-i/--interval does not go with %s", d->option);
	if ((m->given & GIVEN_DURATION) && !(f & LIVE))
		return cli_usage_error(&m->cli, "--duration does not go with %s", d->option);
	if ((m->given & GIVEN_STATIONS) && m->mode != MODE_AUTOCONF)
		return cli_usage_error(&m->cli, "--stations needs --autoconf (--who takes LO-HI itself)");
	if (m->mode == MODE_AUTOCONF) {
		int r = m->who_range ? mon_parse_range(m, m->who_range) : CLI_CONTINUE;

		if (!m->who_range) {
			m->who_lo = 0;
			m->who_hi = 31;
		}
		if (r != CLI_CONTINUE || (m->given & GIVEN_SNIFF_B))
			return r != CLI_CONTINUE ? r : cli_usage_error(&m->cli, "--sniff-b needs --sniff");
		m->given &= ~(unsigned)GIVEN_WRITE;     /* -w FILE: the network CSV */
	}
	if ((m->given & (GIVEN_WRITE | GIVEN_SNIFF_B)) && m->mode != MODE_SNIFF)
		return cli_usage_error(&m->cli, "%s needs --sniff",
		                       (m->given & GIVEN_WRITE) ? "-w/--write" : "--sniff-b");
	if (m->cli.half_slave && m->mode != MODE_SERVE) {
		if (m->cli.given & CLI_ACCEPT(CLI_OPT_DUPLEX))
			return cli_usage_error(&m->cli, "--duplex half-slave needs --serve");
		m->cli.half_slave = false;      /* -N's Mode Slave: refused (2554) at the open */
	}
	if ((m->cli.given & CLI_ACCEPT(CLI_OPT_FORWARD)) && m->mode != MODE_SERVE)
		return cli_usage_error(&m->cli, "--forward needs --serve (a radio-modem node that relays)");
	if (m->mode == MODE_SERVE && m->cli.half_duplex && !m->cli.half_slave)
		return cli_usage_error(&m->cli, "--serve: a half-duplex master does not serve; use --duplex "
		                       "half-slave (a slave station at --src), full or radio");
	if (m->mode == MODE_SERVE && mon_serve_check(m) != CLI_CONTINUE)
		return CLI_EXIT_USAGE;
	if ((m->given & GIVEN_ONCE) && m->mode != MODE_MAP)
		return cli_usage_error(&m->cli, "-1/--once needs --map");
	if ((m->given & GIVEN_SKIP_BAD_ROWS) && m->mode != MODE_MAP)
		return cli_usage_error(&m->cli, "--skip-bad-rows needs --map");
	if (m->cli.format == CLI_FMT_INFLUX && m->mode != MODE_MAP)
		return cli_usage_error(&m->cli, "-f influx needs --map (tags as InfluxDB lines)");
	if (m->cli.format == CLI_FMT_PROMETHEUS && m->mode != MODE_COUNTERS)
		return cli_usage_error(&m->cli, "-f prometheus goes with --counters alone (the line's counters "
		                       "for node-exporter's textfile collector)");
	if (m->cli.format == CLI_FMT_CSV && !(f & TAKES_CSV))
		return cli_usage_error(&m->cli, "-f csv does not go with %s (plain or json)", d->option);
	/* operands: hex for --decode, a station range for --who */
	if (m->mode == MODE_WHO && !m->who_range && m->cli.argc >= 1) {
		m->who_range = m->cli.argv[0];
		m->cli.argc--;
		m->cli.argv++;
	}
	if (m->mode != MODE_DECODE && m->cli.argc > 0)
		return cli_usage_error(&m->cli, "unexpected argument '%s'", m->cli.argv[0]);
	if (m->mode == MODE_SNIFF && m->sniff_b && m->cli.device && strcmp(m->sniff_b, m->cli.device) == 0)
		return cli_usage_error(&m->cli, "--sniff-b: the same device as -d");
	if (m->mode == MODE_SNIFF && m->count > 0)
		m->frame_limit = (unsigned long)m->count;
	if (f & TALKS) {
		/* the link's own check: --check auto is for decoding only */
		if (m->cli.check == DF1_CHECK_AUTO) {
			if (m->cli.given & CLI_ACCEPT(CLI_OPT_CHECK))
				return cli_usage_error(&m->cli, "--check auto is only for --decode, --read and "
				                       "--sniff; %s needs crc or bcc", d->option);
			m->cli.check = m->cli.have_net ? m->cli.net.check : DF1_CHECK_CRC;
		}
	}
	if (m->mode == MODE_WHO) {
		int r;
		if (m->who_range) {
			r = mon_parse_range(m, m->who_range);
			if (r != CLI_CONTINUE)
				return r;
		} else if (m->cli.half_duplex) {
			m->who_lo = 0;
			m->who_hi = 254;
		} else {
			/* full duplex: one peer; the -a station unless a range is given */
			m->who_lo = m->who_hi = m->cli.station;
		}
		/* a short wait per station bounds a scan of 255 of them */
		if (!(m->cli.given & CLI_ACCEPT(CLI_OPT_TIMEOUT)) && !m->cli.have_net)
			m->cli.timeout_ms = 200;
	}
	return CLI_CONTINUE;
}

static const struct cli_tool mon_tool = {
	.name = "df1mon",
	.synopsis = "--decode [OPTIONS] [HEX...]\n"
	            "--read FILE [OPTIONS]\n"
	            "--sniff [-w FILE.pcap] [--sniff-b DEV2] [-c FRAMES] [OPTIONS]\n"
	            "--ping [-c COUNT] [-i SECONDS] [--counters] [OPTIONS]\n"
	            "--who [LO-HI] [--counters] [OPTIONS]\n"
	            "--map FILE.csv [-1] [--skip-bad-rows] [-i SECONDS] [--counters] [OPTIONS]\n"
	            "--counters [-i SECONDS] [-c COUNT] [OPTIONS]\n"
	            "--autoconf [--stations LO-HI] [-w NET.csv] [OPTIONS]\n"
	            "--serve REGION[,REGION...] [--duplex full|half-slave|radio] [--src STATION] [--forward LIST] [OPTIONS]",
	.summary = "DF1 diagnostics: decode frames, captures or a tap; ping, find stations, "
	           "poll tags, show counters.",
	.accepts = CLI_ACCEPT_ALL | CLI_ACCEPT(CLI_OPT_FORWARD), /* --forward: --serve only */
	.formats = CLI_FMT_BIT(CLI_FMT_PLAIN) | CLI_FMT_BIT(CLI_FMT_CSV) | CLI_FMT_BIT(CLI_FMT_JSON) |
	           CLI_FMT_BIT(CLI_FMT_INFLUX) | CLI_FMT_BIT(CLI_FMT_PROMETHEUS),
	.check_auto = true,
	.half_slave = true,             /* --serve as a slave station */
	.common_help = { [CLI_OPT_DUPLEX] = "full (default), half (master), half-slave (--serve at --src)" },
	.extra = mon_opts,
	.on_extra = on_option,
	.exit_text = "0 success (decoding: every frame good; --ping: every probe answered;\n"
	             "--who: a station answered), 1 a bad frame, a communication error or no\n"
	             "answer, 2 usage error, bad hex or unreadable input.",
	.help_tail = "\nDecoding modes (--decode, --read, --sniff) take --check crc|bcc|auto (default\n"
	             "auto) and -f plain|json; --ping, --who, --map and --counters take -f csv too;\n"
	             "--counters alone takes -f prometheus (one snapshot at the end).\n"
	             "--who waits 200 ms per station unless -o is given. SIGINT, SIGTERM and\n"
	             "--duration end a live mode normally: port settings restored, results printed.\n"
	             "See df1mon(1).\n",
};

int main(int argc, char **argv)
{
	static struct mon m;
	const struct mon_mode_def *d;
	int r;

	cli_init(&m.cli, &mon_tool);
	m.cli.check = DF1_CHECK_AUTO;
	r = cli_parse(&m.cli, argc, argv, &m);
	if (r != CLI_CONTINUE)
		return r;
	r = check_combination(&m);
	if (r != CLI_CONTINUE) {
		cli_cleanup(&m.cli);
		return r;
	}
	d = &modes[m.mode];

	decode_ctx_init(&m.dx, m.cli.format);
	m.dx.verbose = m.cli.verbose;
	if (d->flags & LIVE) {
		long dur_ms = mon_ms_of(m.duration_s) > 0 ? mon_ms_of(m.duration_s) : 1;

		cli_signals_install();
		m.t0_us = mon_mono_us();
		if ((m.given & GIVEN_DURATION) && cli_stop_after_ms(dur_ms) < 0) {
			fprintf(stderr, "%s: --duration: %s\n", m.cli.name, strerror(errno));
			cli_cleanup(&m.cli);
			return CLI_EXIT_FAIL;
		}
	}
	if (d->flags & TALKS) {
		/* --who over eip:// asks ListIdentity on a socket of its own */
		if (m.mode == MODE_WHO && mon_who_is_eip(&m))
			r = cli_configure(&m.cli, &m.h);
		else
			r = cli_open(&m.cli, &m.h);
		if (r != CLI_EXIT_OK) {
			cli_cleanup(&m.cli);
			return r;
		}
		if (m.cli.verbose >= 1)
			fprintf(stderr, "%s: %s open: %d %d%c%d, %s, %s duplex, station %d\n", m.cli.name,
			        m.cli.device, m.cli.baud, m.cli.data_bits, m.cli.parity, m.cli.stop_bits,
			        m.cli.check == DF1_CHECK_BCC ? "BCC" : "CRC",
			        m.cli.radio ? "radio" : m.cli.half_duplex ? "half" : "full", m.cli.station);
	}
	r = d->run(&m);
	/* --counters with another talking mode: the table at exit (--map prints its own) */
	if (m.h && m.counters && m.mode != MODE_COUNTERS && m.mode != MODE_MAP)
		mon_print_counters(&m, true);
	if (m.h) {
		cli_close(&m.cli, m.h);   /* restores the port's settings */
		m.h = NULL;
	}
	if (fflush(stdout) != 0 || ferror(stdout)) {
		fprintf(stderr, "%s: stdout: %s\n", m.cli.name, strerror(errno));
		cli_cleanup(&m.cli);
		return CLI_EXIT_FAIL;
	}
	if ((m.mode == MODE_DECODE || m.mode == MODE_READ || m.mode == MODE_SNIFF) && !m.cli.quiet &&
	    (r == CLI_CONTINUE || m.fed > 0)) {
		unsigned long long noise = m.fed > m.used ? m.fed - m.used : 0;
		/* "frames N" rather than "N frames": no "1 frames" */
		fprintf(stderr, "%s: frames %lu (good %lu, bad %lu), link symbols %lu", m.cli.name,
		        m.dx.frames, m.dx.good, m.dx.bad, m.dx.symbols);
		if (m.dx.errors)
			fprintf(stderr, ", errors %lu", m.dx.errors);
		if (noise)
			fprintf(stderr, ", %llu bytes %s", noise,
			        m.mode == MODE_SNIFF ? "of noise or an unfinished symbol" : "of noise");
		fputc('\n', stderr);
	}
	cli_cleanup(&m.cli);
	if (r != CLI_CONTINUE)
		return r;
	return (m.dx.bad || m.dx.errors) ? CLI_EXIT_FAIL : CLI_EXIT_OK;
}
