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
 * lists them); --sniff and its pcap writer are here.
 *
 * Decoding modes print one line per symbol on stdout (tools/common/decode.c) and a
 * summary on stderr unless -q. SIGINT/SIGTERM (and --duration) end a live mode
 * normally: the port's settings are restored and what was done is printed.
 * Exit: 0 success, 1 a communication error, a bad check or a malformed symbol,
 * no answer; 2 usage, unreadable input or bad hex. Per mode in df1mon(1).
 */
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <math.h>
#include <netdb.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "df1mon/mon.h"
#include "df1mon/mon_map.h"   /* --map: the poll engine's live table */

/* ---- --map ---- */

/* The table is mon_map.c's: it also prints the counters (every interval and at
 * exit) when asked, so main does not print them again. */
static int run_map(struct mon *m)
{
	int fmt = m->cli.format == CLI_FMT_CSV      ? MON_MAP_CSV
	        : m->cli.format == CLI_FMT_JSON   ? MON_MAP_JSON
	        : m->cli.format == CLI_FMT_INFLUX ? MON_MAP_INFLUX
	                                          : MON_MAP_PLAIN;
	int interval_ms = (m->given & GIVEN_INTERVAL) ? (int)ms_of(m->interval_s) : 1000;

	return mon_map_run(m->h, m->map_file, fmt, m->once, m->counters, interval_ms, &cli_stop);
}

/* ---- --sniff: a passive port ---- */

/*
 * A tap is a listen-only libdf1 handle (DF1_OPT_LISTEN_ONLY): a serial device
 * is opened read only (nothing can be transmitted), locked like every libdf1
 * port (so a libdf1 program and df1mon do not steal each other's bytes) and set
 * raw at the line settings, its termios restored when the handle closes, on
 * every exit path; an unknown baud rate is an error, never a fallback.
 * tcp://HOST:PORT is connected with the handle's deadline and shut for sending.
 * Anything else (a FIFO, a file, a character device that is no terminal) goes
 * to the handle with df1_open_fd() and is read as it is; its end ends the sniff. Bytes come from df1_recv_raw() with their
 * time; the taps' descriptors (df1_port_fd) are watched in one poll() with the
 * signal pipe, and used for TIOCMGET (the control lines of a pcap record).
 */
struct tap {
	const char *dev;
	const char *dir;       /* "rx"/"tx" with two taps, else NULL */
	uint8_t event;         /* RTAC event type of its records */
	df1_t *h;              /* the listen-only handle, NULL until made */
	int fd;                /* df1_port_fd(h) once open, else -1 */
	bool file;             /* a FIFO or a file: its end is the end of the input */
	bool modem;            /* TIOCMGET works */
	bool eof;
	struct stream st;
	unsigned long long bytes;
};

#define RTAC_DATA_TX_END 0x03
#define RTAC_DATA_RX_END 0x04

/* A failed library call on tap t: the usual "tool: DEV: [tag] text" line. */
static int tap_fail(const struct mon *m, const struct tap *t, int r)
{
	return cli_report(m->cli.name, t->dev, -1, t->h, r);
}

static int tap_open(struct mon *m, struct tap *t)
{
	const struct cli *c = &m->cli;
	struct stat st;
	bool plain;
	int r, fd;

	t->fd = -1;
	r = df1_new(&t->h);
	if (r < 0) {
		t->h = NULL;
		fprintf(stderr, "%s: %s: %s\n", c->name, df1_errname(r), df1_strerror(r));
		return CLI_EXIT_FAIL;
	}
	if ((r = df1_set_option(t->h, DF1_OPT_LISTEN_ONLY, 1)) < 0 ||
	    (r = df1_set_serial(t->h, c->baud, c->data_bits, c->parity, c->stop_bits)) < 0 ||
	    (r = df1_set_timeout_ms(t->h, c->timeout_ms)) < 0)
		return tap_fail(m, t, r);
	fd = cli_signal_fd();
	if (fd >= 0 && (r = df1_set_cancel_fd(t->h, fd)) < 0) /* Ctrl-C ends a TCP connect */
		return tap_fail(m, t, r);
	/* a terminal (or tcp://) is the library's port; anything else that exists
	 * (a FIFO, a file, a character device that is no terminal) is read as it is */
	plain = strncmp(t->dev, "tcp:", 4) != 0 && stat(t->dev, &st) == 0 && !S_ISCHR(st.st_mode);
	if (!plain) {
		r = df1_open(t->h, t->dev);
		if (r == DF1_E_NODEV && strncmp(t->dev, "tcp:", 4) != 0 && stat(t->dev, &st) == 0)
			plain = true;  /* it is there, but not a serial port */
		else if (r < 0)
			return tap_fail(m, t, r);
	}
	if (plain) {
		fd = open(t->dev, O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
		if (fd < 0) {
			fprintf(stderr, "%s: %s: %s\n", c->name, t->dev, strerror(errno));
			return CLI_EXIT_FAIL;
		}
		r = df1_open_fd(t->h, fd, true);
		if (r < 0) {
			close(fd);
			return tap_fail(m, t, r);
		}
		t->file = true;
	}
	t->fd = df1_port_fd(t->h);
	if (t->fd < 0)
		return tap_fail(m, t, t->fd);
	t->modem = !t->file && isatty(t->fd);
	return CLI_CONTINUE;
}

static void tap_close(struct tap *t)
{
	df1_free(t->h); /* closes the port: a serial device gets its termios back */
	t->h = NULL;
	t->fd = -1;
}

/* RTAC control-line bits from the modem lines (0 when unknown). */
static uint8_t tap_lines(struct tap *t)
{
	int bits = 0;
	uint8_t v = 0;

	if (!t->modem)
		return 0;
	if (ioctl(t->fd, TIOCMGET, &bits) < 0) {
		t->modem = false;
		return 0;
	}
	if (bits & TIOCM_CTS) v |= 0x01;
	if (bits & TIOCM_CD) v |= 0x02;
	if (bits & TIOCM_DSR) v |= 0x04;
	if (bits & TIOCM_RTS) v |= 0x08;
	if (bits & TIOCM_DTR) v |= 0x10;
	if (bits & TIOCM_RI) v |= 0x20;
	return v;
}

/* ---- pcap writer: link type 250, a 12-byte RTAC header per record ---- */

static void put_le32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
	p[2] = (uint8_t)(v >> 16);
	p[3] = (uint8_t)(v >> 24);
}

static void put_be32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)(v >> 24);
	p[1] = (uint8_t)(v >> 16);
	p[2] = (uint8_t)(v >> 8);
	p[3] = (uint8_t)v;
}

#define PCAP_SNAPLEN 65535
#define SNIFF_CHUNK 4096

static bool pcap_header(FILE *f)
{
	uint8_t h[24];

	put_le32(h, 0xA1B2C3D4);               /* microsecond timestamps */
	h[4] = 2; h[5] = 0; h[6] = 4; h[7] = 0; /* version 2.4 */
	put_le32(h + 8, 0);                    /* thiszone */
	put_le32(h + 12, 0);                   /* sigfigs */
	put_le32(h + 16, PCAP_SNAPLEN);
	put_le32(h + 20, LINKTYPE_RTAC_SERIAL);
	return fwrite(h, 1, sizeof h, f) == sizeof h && fflush(f) == 0;
}

/* One record: pcap record header, RTAC header (BE seconds, BE microseconds,
 * event type, control lines, 2 footer bytes), the bytes; flushed at once so an
 * interrupted capture is a valid file. */
static bool pcap_record(FILE *f, int64_t sec, int32_t usec, uint8_t event, uint8_t lines,
                        const uint8_t *b, size_t n)
{
	uint8_t rec[16 + RTAC_HDR + SNIFF_CHUNK];
	size_t len = RTAC_HDR + n;

	if (n > SNIFF_CHUNK)
		return false;
	put_le32(rec, (uint32_t)sec);
	put_le32(rec + 4, (uint32_t)usec);
	put_le32(rec + 8, (uint32_t)len);
	put_le32(rec + 12, (uint32_t)len);
	put_be32(rec + 16, (uint32_t)sec);
	put_be32(rec + 20, (uint32_t)usec);
	rec[24] = event;
	rec[25] = lines;
	rec[26] = 0;
	rec[27] = 0;
	memcpy(rec + 28, b, n);
	return fwrite(rec, 1, 16 + len, f) == 16 + len && fflush(f) == 0;
}

/* -vv: the bytes of each chunk on stderr with the time since the start. */
static void sniff_trace(const struct mon *m, const struct tap *t, const uint8_t *b, size_t n)
{
	double el = mon_elapsed(m);
	char hex[3 * 32 + 1];

	for (size_t i = 0; i < n; i += 32) {
		size_t k = n - i < 32 ? n - i : 32;
		cli_hex(b + i, k, hex, sizeof hex);
		fprintf(stderr, "%s: %.6f %s %s\n", m->cli.name, el, t->dir ? t->dir : "rx", hex);
	}
}

static int run_sniff(struct mon *m)
{
	struct tap taps[2];
	int ntaps = m->sniff_b ? 2 : 1, status = CLI_CONTINUE;
	FILE *pcap = NULL;
	bool pcap_stdout = m->pcap_path && strcmp(m->pcap_path, "-") == 0;
	struct timebase tb = { 0 };
	unsigned long records = 0;
	unsigned long long bytes = 0;
	int64_t s0;
	int32_t u0;

	memset(taps, 0, sizeof taps);
	taps[0].fd = taps[1].fd = -1;
	taps[0].h = taps[1].h = NULL;
	if (!m->cli.device || !*m->cli.device)
		return cli_usage_error(&m->cli, "no device: use -d DEV, -N FILE or set DF1_DEVICE");
	taps[0].dev = m->cli.device;
	taps[0].event = RTAC_DATA_RX_END;
	if (ntaps == 2) {
		taps[0].dir = "rx";
		taps[1].dev = m->sniff_b;
		taps[1].dir = "tx";
		taps[1].event = RTAC_DATA_TX_END;
		m->dx.show_dir = true;
	}
	m->dx.show_time = true;
	for (int i = 0; i < ntaps && status == CLI_CONTINUE; i++) {
		status = tap_open(m, &taps[i]);
		if (status == CLI_CONTINUE)
			status = stream_init(m, &taps[i].st, taps[i].dir);
	}
	if (status == CLI_CONTINUE && m->pcap_path) {
		pcap = pcap_stdout ? stdout : fopen(m->pcap_path, "wb");
		if (!pcap || !pcap_header(pcap)) {
			fprintf(stderr, "%s: %s: %s\n", m->cli.name, m->pcap_path, strerror(errno));
			status = CLI_EXIT_FAIL;
		}
	}
	if (status == CLI_CONTINUE && pcap_stdout) {
		/* stdout carries the capture: the symbol lines go nowhere */
		m->out = fopen("/dev/null", "w");
		if (!m->out) {
			fprintf(stderr, "%s: /dev/null: %s\n", m->cli.name, strerror(errno));
			status = CLI_EXIT_FAIL;
		}
	}
	wall_now(&s0, &u0);
	tb.set = true;
	tb.sec = s0;
	tb.usec = u0;
	if (status == CLI_CONTINUE && m->cli.verbose >= 1) {
		for (int i = 0; i < ntaps; i++)
			fprintf(stderr, "%s: sniffing %s%s%s at %d %d%c%d, listen only; Ctrl-C to stop\n",
			        m->cli.name, taps[i].dev, taps[i].dir ? " as " : "",
			        taps[i].dir ? taps[i].dir : "", m->cli.baud, m->cli.data_bits, m->cli.parity,
			        m->cli.stop_bits);
		if (m->pcap_path)
			fprintf(stderr, "%s: writing %s\n", m->cli.name,
			        pcap_stdout ? "the capture to stdout" : m->pcap_path);
	}

	while (status == CLI_CONTINUE && !cli_stop) {
		struct pollfd p[3];
		int np = 0, idx[3], sfd = cli_signal_fd(), open_taps = 0;

		for (int i = 0; i < ntaps; i++) {
			if (taps[i].eof)
				continue;
			open_taps++;
			idx[np] = i;
			p[np++] = (struct pollfd){ .fd = taps[i].fd, .events = POLLIN };
		}
		if (!open_taps)
			break;
		if (sfd >= 0) {
			idx[np] = -1;
			p[np++] = (struct pollfd){ .fd = sfd, .events = POLLIN };
		}
		if (poll(p, (nfds_t)np, -1) < 0) {
			if (errno == EINTR)
				continue;
			fprintf(stderr, "%s: poll: %s\n", m->cli.name, strerror(errno));
			status = CLI_EXIT_FAIL;
			break;
		}
		for (int k = 0; k < np && status == CLI_CONTINUE && !cli_stop; k++) {
			struct tap *t;
			uint8_t buf[SNIFF_CHUNK];
			struct timespec when;
			int n;
			int64_t sec;
			int32_t usec;

			if (idx[k] < 0 || !(p[k].revents & (POLLIN | POLLHUP | POLLERR)))
				continue;
			t = &taps[idx[k]];
			n = df1_recv_raw(t->h, buf, sizeof buf, 0, &when);
			if (n == 0 || n == DF1_E_INTR)
				continue;   /* nothing after all, or a signal: the loop looks at cli_stop */
			if (n < 0) {
				if (n == DF1_E_CLOSED && t->file) {
					t->eof = true;   /* the end of a FIFO or file */
					if (m->cli.verbose >= 1)
						fprintf(stderr, "%s: %s: end of input\n", m->cli.name, t->dev);
					continue;
				}
				tap_fail(m, t, n);
				status = CLI_EXIT_FAIL;
				break;
			}
			sec = (int64_t)when.tv_sec;
			usec = (int32_t)(when.tv_nsec / 1000);
			records++;
			bytes += (unsigned long long)n;
			t->bytes += (unsigned long long)n;
			if (pcap && !pcap_record(pcap, sec, usec, t->event, tap_lines(t), buf, (size_t)n)) {
				fprintf(stderr, "%s: %s: %s\n", m->cli.name, pcap_stdout ? "stdout" : m->pcap_path,
				        strerror(errno ? errno : EIO));
				status = CLI_EXIT_FAIL;
				break;
			}
			if (m->cli.verbose >= 2 && !m->cli.quiet)
				sniff_trace(m, t, buf, (size_t)n);
			stream_mark(&t->st, sec, usec);
			stream_feed(m, &t->st, &tb, buf, (size_t)n);
			if (fflush(m->out ? m->out : stdout) != 0 || ferror(m->out ? m->out : stdout)) {
				/* a closed pipe: stop; main reports stdout's error (exit 1) */
				goto done;
			}
			if (m->frame_limit && m->dx.frames >= m->frame_limit)
				goto done;
		}
	}
done:
	for (int i = 0; i < ntaps; i++) {
		/* the end of a FIFO or file is the end of the input, as for --read */
		if (taps[i].st.dec && !(m->frame_limit && m->dx.frames >= m->frame_limit))
			stream_finish_cut(m, &taps[i].st, &tb, !taps[i].eof);
		tap_close(&taps[i]);
		stream_free(&taps[i].st);
	}
	if (pcap && !pcap_stdout && fclose(pcap) != 0 && status == CLI_CONTINUE) {
		fprintf(stderr, "%s: %s: %s\n", m->cli.name, m->pcap_path, strerror(errno));
		status = CLI_EXIT_FAIL;
	}
	if (m->out && m->out != stdout) {
		fclose(m->out);
		m->out = NULL;
	}
	if (!m->cli.quiet && records) {
		if (interrupted())
			fprintf(stderr, "%s: stopped by %s\n", m->cli.name, signal_name(cli_stop_signal()));
		if (pcap)
			fprintf(stderr, "%s: %llu bytes in %lu record%s written to %s\n", m->cli.name, bytes,
			        records, records == 1 ? "" : "s", pcap_stdout ? "stdout" : m->pcap_path);
	} else if (!m->cli.quiet && interrupted()) {
		fprintf(stderr, "%s: stopped by %s; nothing received\n", m->cli.name,
		        signal_name(cli_stop_signal()));
	}
	return status;
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
	[MODE_DECODE] = { "--decode", run_decode, 0 },
	[MODE_READ] = { "--read", run_read, 0 },
	[MODE_SNIFF] = { "--sniff", run_sniff, LIVE | TAKES_COUNT },
	[MODE_PING] = { "--ping", run_ping, LIVE | TALKS | TAKES_COUNT | TAKES_INTERVAL | TAKES_COUNTERS | TAKES_CSV },
	[MODE_WHO] = { "--who", run_who, LIVE | TALKS | TAKES_COUNTERS | TAKES_CSV },
	[MODE_MAP] = { "--map", run_map, LIVE | TALKS | TAKES_INTERVAL | TAKES_COUNTERS | TAKES_CSV },
	[MODE_COUNTERS] = { "--counters", run_counters, LIVE | TALKS | TAKES_COUNT | TAKES_INTERVAL | TAKES_CSV },
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
	{ "count", required_argument, 'c', "N", "probes (--ping, 4), frames (--sniff), tables; 0: no limit" },
	{ "interval", required_argument, 'i', "SECONDS", "between probes, tables or scans (default 1; fractions allowed)" },
	{ "duration", required_argument, KEY_DURATION, "SECONDS", "stop a live mode after this time" },
	{ "once", no_argument, '1', NULL, "--map: one scan, then exit" },
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
	case KEY_WHO:
		m->who_range = arg;
		return set_mode(m, MODE_WHO);
	case KEY_MAP:
		m->map_file = arg;
		return set_mode(m, MODE_MAP);
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
	if ((m->given & (GIVEN_WRITE | GIVEN_SNIFF_B)) && m->mode != MODE_SNIFF)
		return cli_usage_error(&m->cli, "%s needs --sniff",
		                       (m->given & GIVEN_WRITE) ? "-w/--write" : "--sniff-b");
	if ((m->given & GIVEN_ONCE) && m->mode != MODE_MAP)
		return cli_usage_error(&m->cli, "-1/--once needs --map");
	if (m->cli.format == CLI_FMT_INFLUX && m->mode != MODE_MAP)
		return cli_usage_error(&m->cli, "-f influx needs --map (tags as InfluxDB lines)");
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
			r = parse_range(m, m->who_range);
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
	            "--map FILE.csv [-1] [-i SECONDS] [--counters] [OPTIONS]\n"
	            "--counters [-i SECONDS] [-c COUNT] [OPTIONS]",
	.summary = "DF1 diagnostics: decode frames, captures or a tap; ping, find stations, "
	           "poll tags, show counters.",
	.accepts = CLI_ACCEPT_ALL,
	.formats = CLI_FMT_BIT(CLI_FMT_PLAIN) | CLI_FMT_BIT(CLI_FMT_CSV) | CLI_FMT_BIT(CLI_FMT_JSON) |
	           CLI_FMT_BIT(CLI_FMT_INFLUX),
	.check_auto = true,
	.extra = mon_opts,
	.on_extra = on_option,
	.exit_text = "0 success (decoding: every frame good; --ping: every probe answered;\n"
	             "--who: a station answered), 1 a bad frame, a communication error or no\n"
	             "answer, 2 usage error, bad hex or unreadable input.",
	.help_tail = "\nDecoding modes (--decode, --read, --sniff) take --check crc|bcc|auto (default\n"
	             "auto) and -f plain|json; --ping, --who, --map and --counters take -f csv too.\n"
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
		cli_signals_install();
		m.t0_us = mono_us();
		if ((m.given & GIVEN_DURATION) && cli_stop_after_ms(ms_of(m.duration_s) > 0 ? ms_of(m.duration_s) : 1) < 0) {
			fprintf(stderr, "%s: --duration: %s\n", m.cli.name, strerror(errno));
			cli_cleanup(&m.cli);
			return CLI_EXIT_FAIL;
		}
	}
	if (d->flags & TALKS) {
		/* --who over eip:// asks ListIdentity on a socket of its own */
		if (m.mode == MODE_WHO && who_is_eip(&m))
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
			        m.cli.half_duplex ? "half" : "full", m.cli.station);
	}
	r = d->run(&m);
	/* --counters with another talking mode: the table at exit (--map prints its own) */
	if (m.h && m.counters && m.mode != MODE_COUNTERS && m.mode != MODE_MAP)
		print_counters(&m, true);
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
