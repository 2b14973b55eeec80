/*
 * df1mon - DF1 diagnostics (DESIGN.md 8).
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
 *   --map FILE.csv     poll a tag list (tools/mon_map.c, the poll engine)
 *   --counters         the seed counter table at exit (alone: a link test
 *                      every -i interval, counters after each)
 * A mode is an enum mon_mode value, an entry in modes[] (what it accepts), an
 * option in mon_opts[] and its run function.
 *
 * Decoding modes print one line per symbol on stdout (tools/decode.c) and a
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

#include "cli.h"
#include "decode.h"
#include "df1.h"
#include "mon_map.h"   /* --map: the poll engine's live table */

enum mon_mode {
	MODE_NONE = 0,
	MODE_DECODE,
	MODE_READ,
	MODE_SNIFF,
	MODE_PING,
	MODE_WHO,
	MODE_MAP,
	MODE_COUNTERS,   /* --counters alone */
	MODE_COUNT_
};

enum {
	KEY_DECODE = CLI_KEY_EXTRA,
	KEY_SNIFF,
	KEY_SNIFF_B,
	KEY_PING,
	KEY_WHO,
	KEY_MAP,
	KEY_COUNTERS,
	KEY_DURATION,
};

/* Options given, for the checks of what goes with which mode. */
enum {
	GIVEN_COUNT = 1 << 0,
	GIVEN_INTERVAL = 1 << 1,
	GIVEN_DURATION = 1 << 2,
	GIVEN_WRITE = 1 << 3,
	GIVEN_SNIFF_B = 1 << 4,
	GIVEN_ONCE = 1 << 5,
	GIVEN_COUNTERS = 1 << 6,
};

struct mon {
	struct cli cli;
	enum mon_mode mode;
	const char *read_file;
	struct decode_ctx dx;
	FILE *out;                 /* where symbol lines go (stdout, or /dev/null with -w -) */
	unsigned long index;       /* symbols printed */
	unsigned long long fed;    /* bytes fed to decoders */
	unsigned long long used;   /* bytes that belonged to a symbol */
	unsigned long frame_limit; /* --sniff -c N: stop after N frames (0: no limit) */

	/* live options */
	unsigned given;            /* GIVEN_* */
	bool counters;             /* --counters */
	long count;                /* -c */
	double interval_s;         /* -i */
	double duration_s;         /* --duration */
	bool once;                 /* -1 */
	const char *sniff_b;       /* --sniff-b DEV2 */
	const char *pcap_path;     /* -w FILE */
	const char *map_file;      /* --map FILE */
	const char *who_range;     /* --who=LO-HI or the operand */
	int who_lo, who_hi;
	df1_t *h;                  /* the handle of a talking mode */
	int64_t t0_us;             /* monotonic start of a live mode */
	unsigned counter_prints;   /* counter tables printed */
};

/* ---- one byte stream (one direction of a capture, or one --decode chunk) ---- */

#define RING 256

struct stream {
	struct df1_decoder *dec;
	const char *dir;            /* "tx"/"rx" when a capture has both, else NULL */
	unsigned long long off;     /* bytes fed so far */
	/* where each recent record began in the stream, and its time */
	struct {
		unsigned long long off;
		int64_t sec;
		int32_t usec;
	} ring[RING];
	unsigned nring, head;
	bool timed;
};

static int stream_init(struct mon *m, struct stream *s, const char *dir)
{
	int r;

	memset(s, 0, sizeof *s);
	s->dir = dir;
	r = df1_decoder_new(&s->dec, m->cli.check);
	if (r < 0) {
		fprintf(stderr, "%s: decoder: %s\n", m->cli.name, df1_strerror(r));
		return CLI_EXIT_FAIL;
	}
	df1_decoder_set_half_duplex(s->dec, m->cli.half_duplex);
	return CLI_CONTINUE;
}

static void stream_free(struct stream *s)
{
	df1_decoder_free(s->dec);
	s->dec = NULL;
}

static void stream_mark(struct stream *s, int64_t sec, int32_t usec)
{
	unsigned i = (s->head + s->nring) % RING;

	if (s->nring == RING) {
		s->head = (s->head + 1) % RING;
		i = (s->head + RING - 1) % RING;
	} else {
		s->nring++;
	}
	s->ring[i].off = s->off;
	s->ring[i].sec = sec;
	s->ring[i].usec = usec;
	s->timed = true;
}

/* Time of the record holding stream offset `at` (the newest one starting at or before it). */
static void stream_time(const struct stream *s, unsigned long long at, int64_t *sec, int32_t *usec)
{
	unsigned best = s->head;

	for (unsigned k = 0; k < s->nring; k++) {
		unsigned i = (s->head + k) % RING;
		if (s->ring[i].off <= at)
			best = i;
		else
			break;
	}
	*sec = s->ring[best].sec;
	*usec = s->ring[best].usec;
}

/* Time base of a capture: the first record's time. */
struct timebase {
	bool set;
	int64_t sec;
	int32_t usec;
};

static void print_symbol(struct mon *m, struct stream *s, const struct timebase *tb,
                         const struct df1_symbol *sym, unsigned long long end)
{
	struct decode_where w;

	memset(&w, 0, sizeof w);
	w.index = ++m->index;
	w.dir = s->dir;
	if (s->timed && tb && tb->set) {
		int64_t sec;
		int32_t usec;
		long long rel;
		stream_time(s, end >= sym->wire_len ? end - sym->wire_len : 0, &sec, &usec);
		w.has_epoch = true;
		w.epoch_sec = sec;
		w.epoch_usec = usec;
		rel = (sec - tb->sec) * 1000000LL + (usec - tb->usec);
		if (rel < 0)
			rel = 0;
		w.has_time = true;
		w.rel_sec = rel / 1000000;
		w.rel_usec = (int32_t)(rel % 1000000);
	}
	m->used += sym->wire_len;
	decode_print(&m->dx, m->out ? m->out : stdout, NULL, &w, sym);
}

static void stream_feed(struct mon *m, struct stream *s, const struct timebase *tb,
                        const uint8_t *p, size_t n)
{
	size_t pos = 0;

	m->fed += n;
	while (pos < n) {
		struct df1_symbol sym;
		size_t k = df1_decoder_feed(s->dec, p + pos, n - pos, &sym);
		pos += k;
		s->off += k;
		if (sym.kind != DF1_SYM_NONE)
			print_symbol(m, s, tb, &sym, s->off);
		if (k == 0 || (m->frame_limit && m->dx.frames >= m->frame_limit))
			break;
	}
}

/* End of the input: a symbol still under way is reported. Feeding DLE STX ends any
 * frame in progress as "no ETX" (2518); in AUTO mode a frame waiting after its one
 * check byte (a BCC that did not match, or the first byte of a CRC) is taken as a
 * frame with a bad BCC, as it would be if a DLE followed. With cut (a sniff
 * stopped by a signal, -c or --duration) only that BCC verdict is given: a symbol
 * the stop cut short is not an error of the line. */
static void stream_finish_cut(struct mon *m, struct stream *s, const struct timebase *tb, bool cut)
{
	static const uint8_t probe[2] = { 0x10, 0x02 };

	for (size_t i = 0; i < sizeof probe; i++) {
		struct df1_symbol sym;
		size_t k = df1_decoder_feed(s->dec, probe + i, 1, &sym);
		(void)k;
		if (sym.kind == DF1_SYM_NONE)
			continue;
		if ((i == 0 && sym.kind == DF1_SYM_FRAME && m->cli.check == DF1_CHECK_AUTO &&
		     sym.check == DF1_CHECK_BCC && !sym.check_ok) ||
		    (i == 1 && sym.kind == DF1_SYM_ERROR && sym.error == 2518)) {
			/* a true verdict on the bytes that were there */
			if (!cut || i == 0)
				print_symbol(m, s, tb, &sym, s->off);
		} else if (!cut) {
			struct decode_where w;
			/* the bytes of the symbol that were real input, not the probe */
			bool probe_kept = sym.kind == DF1_SYM_ERROR && i == 1;
			m->used += probe_kept ? sym.wire_len
			                      : (sym.wire_len > i + 1 ? sym.wire_len - (i + 1) : 0);
			memset(&w, 0, sizeof w);
			w.index = ++m->index;
			w.dir = s->dir;
			decode_print_error(&m->dx, stdout, NULL, &w, 2518,
			                   "input ended inside a symbol");
		}
		break;
	}
	df1_decoder_reset(s->dec);
}

static void stream_finish(struct mon *m, struct stream *s, const struct timebase *tb)
{
	stream_finish_cut(m, s, tb, false);
}

/* ---- --decode ---- */

static int decode_chunk(struct mon *m, const uint8_t *b, size_t n)
{
	struct stream s;
	int r = stream_init(m, &s, NULL);

	if (r != CLI_CONTINUE)
		return r;
	stream_feed(m, &s, NULL, b, n);
	stream_finish(m, &s, NULL);
	stream_free(&s);
	return CLI_CONTINUE;
}

static int bad_hex(const struct mon *m, const char *where, const char *text, size_t at)
{
	fprintf(stderr, "%s: %s: bad hex at character %zu: '%s'\n", m->cli.name, where, at + 1, text);
	return CLI_EXIT_USAGE;
}

#define CHUNK_MAX 65536

static int run_decode(struct mon *m)
{
	uint8_t *buf = malloc(CHUNK_MAX);
	char where[64];
	size_t at = 0;
	long n;
	int r = CLI_CONTINUE;

	if (!buf) {
		fprintf(stderr, "%s: out of memory\n", m->cli.name);
		return CLI_EXIT_FAIL;
	}
	if (m->cli.argc > 0) {
		/* check every argument before printing anything */
		for (int i = 0; i < m->cli.argc; i++) {
			if (cli_parse_hex(m->cli.argv[i], buf, CHUNK_MAX, &at) < 0) {
				snprintf(where, sizeof where, "argument %d", i + 1);
				free(buf);
				return bad_hex(m, where, m->cli.argv[i], at);
			}
		}
		for (int i = 0; i < m->cli.argc && r == CLI_CONTINUE; i++) {
			n = cli_parse_hex(m->cli.argv[i], buf, CHUNK_MAX, &at);
			r = decode_chunk(m, buf, (size_t)n);
		}
	} else {
		char *line = NULL;
		size_t cap = 0;
		unsigned long lineno = 0;
		ssize_t len;

		while (r == CLI_CONTINUE && (len = getline(&line, &cap, stdin)) >= 0) {
			char *hash = strchr(line, '#');
			lineno++;
			(void)len;
			if (hash)
				*hash = 0;
			n = cli_parse_hex(line, buf, CHUNK_MAX, &at);
			if (n < 0) {
				line[strcspn(line, "\r\n")] = 0;
				snprintf(where, sizeof where, "stdin: line %lu", lineno);
				r = bad_hex(m, where, line, at);
				break;
			}
			if (n > 0)
				r = decode_chunk(m, buf, (size_t)n);
		}
		if (r == CLI_CONTINUE && ferror(stdin)) {
			fprintf(stderr, "%s: stdin: %s\n", m->cli.name, strerror(errno));
			r = CLI_EXIT_USAGE;
		}
		free(line);
	}
	free(buf);
	return r;
}

/* ---- --read ---- */

static int slurp(struct mon *m, const char *path, uint8_t **out, size_t *len)
{
	FILE *f = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
	uint8_t *b = NULL;
	size_t n = 0, cap = 0;

	if (!f) {
		fprintf(stderr, "%s: %s: %s\n", m->cli.name, path, strerror(errno));
		return CLI_EXIT_USAGE;
	}
	for (;;) {
		size_t k;
		if (cap - n < 65536) {
			uint8_t *nb;
			cap = cap ? cap * 2 : 262144;
			nb = realloc(b, cap);
			if (!nb) {
				fprintf(stderr, "%s: %s: out of memory\n", m->cli.name, path);
				free(b);
				if (f != stdin)
					fclose(f);
				return CLI_EXIT_FAIL;
			}
			b = nb;
		}
		k = fread(b + n, 1, cap - n, f);
		n += k;
		if (k == 0)
			break;
	}
	if (ferror(f)) {
		fprintf(stderr, "%s: %s: %s\n", m->cli.name, path, strerror(errno));
		free(b);
		if (f != stdin)
			fclose(f);
		return CLI_EXIT_USAGE;
	}
	if (f != stdin)
		fclose(f);
	*out = b;
	*len = n;
	return CLI_CONTINUE;
}

struct pcap_fmt {
	bool swapped;   /* fields are big-endian */
	bool nsec;      /* nanosecond timestamps */
	uint32_t linktype;
};

static uint32_t rd32(const uint8_t *p, bool be)
{
	if (be)
		return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
	return (uint32_t)p[3] << 24 | (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
}

/* 1 pcap, 0 not a pcap (a raw dump), -1 pcapng */
static int pcap_detect(const uint8_t *b, size_t n, struct pcap_fmt *f)
{
	uint32_t le, be;

	if (n < 4)
		return 0;
	le = rd32(b, false);
	be = rd32(b, true);
	memset(f, 0, sizeof *f);
	if (le == 0x0A0D0D0A)
		return -1;
	if (le == 0xA1B2C3D4 || le == 0xA1B23C4D) {
		f->nsec = le == 0xA1B23C4D;
		return 1;
	}
	if (be == 0xA1B2C3D4 || be == 0xA1B23C4D) {
		f->swapped = true;
		f->nsec = be == 0xA1B23C4D;
		return 1;
	}
	return 0;
}

#define LINKTYPE_RTAC_SERIAL 250
#define RTAC_HDR 12

/* RTAC serial event types (the byte after the 8-byte timestamp): 01/03 transmit
 * start/end, 02/04 receive start/end; anything else goes with receive. */
static int rtac_dir(uint8_t event)
{
	return (event == 0x01 || event == 0x03) ? 1 : 0;
}

static int run_read_pcap(struct mon *m, const char *path, const uint8_t *b, size_t n,
                         const struct pcap_fmt *pf)
{
	struct stream st[2];
	struct timebase tb = { 0 };
	bool rtac = pf->linktype == LINKTYPE_RTAC_SERIAL;
	bool seen[2] = { false, false };
	size_t pos = 24;
	int status = CLI_CONTINUE;
	unsigned long rec = 0, short_recs = 0;

	if (!rtac && !m->cli.quiet)
		fprintf(stderr, "%s: %s: link type %u is not RTAC serial (250): record data taken as serial bytes\n",
		        m->cli.name, path, (unsigned)pf->linktype);
	/* directions: both present -> a column */
	if (rtac) {
		for (size_t p = 24; p + 16 <= n;) {
			uint32_t incl = rd32(b + p + 8, pf->swapped);
			if (incl > n - p - 16)
				break;
			if (incl >= RTAC_HDR)
				seen[rtac_dir(b[p + 16 + 8])] = true;
			p += 16 + incl;
		}
	}
	if (stream_init(m, &st[0], seen[0] && seen[1] ? "rx" : NULL) != CLI_CONTINUE)
		return CLI_EXIT_FAIL;
	if (stream_init(m, &st[1], seen[0] && seen[1] ? "tx" : NULL) != CLI_CONTINUE) {
		stream_free(&st[0]);
		return CLI_EXIT_FAIL;
	}
	if (seen[0] && seen[1])
		m->dx.show_dir = true;
	m->dx.show_time = true;

	while (pos < n) {
		uint32_t sec, frac, incl;
		int32_t usec;
		const uint8_t *data;
		size_t len;
		struct stream *s = &st[0];

		if (n - pos < 16) {
			fprintf(stderr, "%s: %s: truncated record header at byte %zu\n", m->cli.name, path, pos);
			status = CLI_EXIT_USAGE;
			break;
		}
		rec++;
		sec = rd32(b + pos, pf->swapped);
		frac = rd32(b + pos + 4, pf->swapped);
		incl = rd32(b + pos + 8, pf->swapped);
		usec = (int32_t)(pf->nsec ? frac / 1000 : frac);
		if (usec < 0 || usec > 999999)
			usec = 0;
		pos += 16;
		if (incl > n - pos) {
			fprintf(stderr, "%s: %s: record %lu truncated (%u bytes, %zu in the file)\n",
			        m->cli.name, path, rec, (unsigned)incl, n - pos);
			status = CLI_EXIT_USAGE;
			incl = (uint32_t)(n - pos);
		}
		data = b + pos;
		len = incl;
		pos += incl;
		if (rtac) {
			if (len < RTAC_HDR) {
				short_recs++;
				continue;
			}
			s = &st[rtac_dir(data[8])];
			data += RTAC_HDR;
			len -= RTAC_HDR;
		}
		if (!tb.set) {
			tb.set = true;
			tb.sec = sec;
			tb.usec = usec;
		}
		if (len == 0)
			continue;
		stream_mark(s, sec, usec);
		stream_feed(m, s, &tb, data, len);
	}
	stream_finish(m, &st[0], &tb);
	stream_finish(m, &st[1], &tb);
	stream_free(&st[0]);
	stream_free(&st[1]);
	if (short_recs && !m->cli.quiet)
		fprintf(stderr, "%s: %s: %lu records shorter than the RTAC header skipped\n", m->cli.name,
		        path, short_recs);
	return status;
}

static int run_read(struct mon *m)
{
	const char *path = m->read_file;
	uint8_t *b = NULL;
	size_t n = 0;
	struct pcap_fmt pf;
	int r = slurp(m, path, &b, &n), kind;

	if (r != CLI_CONTINUE)
		return r;
	kind = pcap_detect(b, n, &pf);
	if (kind < 0) {
		fprintf(stderr, "%s: %s: pcapng is not supported; convert it with: editcap -F pcap %s OUT.pcap\n",
		        m->cli.name, path, path);
		r = CLI_EXIT_USAGE;
	} else if (kind == 1) {
		if (n < 24) {
			fprintf(stderr, "%s: %s: truncated pcap header\n", m->cli.name, path);
			r = CLI_EXIT_USAGE;
		} else {
			pf.linktype = rd32(b + 20, pf.swapped) & 0x0FFFFFFF;
			r = run_read_pcap(m, path, b, n, &pf);
		}
	} else {
		struct stream s;
		r = stream_init(m, &s, NULL);
		if (r == CLI_CONTINUE) {
			stream_feed(m, &s, NULL, b, n);
			stream_finish(m, &s, NULL);
			stream_free(&s);
		}
	}
	free(b);
	return r;
}

/* ======================================================================
 * Live modes
 * ====================================================================== */

static int64_t mono_us(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static void wall_now(int64_t *sec, int32_t *usec)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	*sec = (int64_t)ts.tv_sec;
	*usec = (int32_t)(ts.tv_nsec / 1000);
}

/* stdout cannot take more (a closed pipe: SIGPIPE is ignored): end the loop;
 * main reports it and exits 1. */
static bool out_broken(void)
{
	return fflush(stdout) != 0 || ferror(stdout);
}

/* Seconds since the live mode started. */
static double mon_elapsed(const struct mon *m)
{
	return (double)(mono_us() - m->t0_us) / 1e6;
}

/* Wait ms milliseconds, or until a signal (or --duration) stops us: false then. */
static bool mon_sleep(long ms)
{
	int64_t end = mono_us() + (int64_t)ms * 1000;
	int fd = cli_signal_fd();

	while (!cli_stop) {
		int64_t left = end - mono_us();
		struct pollfd p = { .fd = fd, .events = POLLIN };

		if (left <= 0)
			return true;
		poll(fd >= 0 ? &p : NULL, fd >= 0 ? 1 : 0, (int)((left + 999) / 1000));
	}
	return false;
}

static const char *signal_name(int sig)
{
	return sig == SIGALRM ? "--duration" : cli_signal_name(sig);
}

/* A stop by a signal (not by --duration's timer): reported as an interruption. */
static bool interrupted(void)
{
	return cli_stop && cli_stop_signal() != SIGALRM;
}

static long ms_of(double seconds)
{
	return (long)llround(seconds * 1000.0);
}

/* ---- counters: ID MNEMONIC VALUE ---- */

/* Every counter of the seed table in ID order (2525-2551, 2560, 2561). */
static void print_counters(struct mon *m, bool final)
{
	FILE *f = stdout;
	bool first = true;

	if (!m->h)
		return;
	switch (m->cli.format) {
	case CLI_FMT_PLAIN:
		if (m->counter_prints)
			fputc('\n', f);   /* blocks are separated by a blank line */
		break;
	case CLI_FMT_CSV:
		if (!m->counter_prints)
			fputs("t,id,mnemonic,value\n", f);
		break;
	case CLI_FMT_JSON:
		fprintf(f, "{\"t\":%.3f,\"final\":%s,\"counters\":[", mon_elapsed(m), final ? "true" : "false");
		break;
	}
	for (int id = 2501; id <= 2561; id++) {
		const struct df1_catalog_entry *e = df1_catalog_by_id(id);
		uint64_t v = 0;

		if (!e || e->severity != DF1_SEV_COUNTER || df1_counter(m->h, id, &v) < 0)
			continue;
		switch (m->cli.format) {
		case CLI_FMT_PLAIN:
			fprintf(f, "%d %s %llu\n", id, e->mnemonic, (unsigned long long)v);
			break;
		case CLI_FMT_CSV:
			fprintf(f, "%.3f,%d,%s,%llu\n", mon_elapsed(m), id, e->mnemonic, (unsigned long long)v);
			break;
		case CLI_FMT_JSON:
			fprintf(f, "%s{\"id\":%d,\"mnemonic\":\"%s\",\"value\":%llu}", first ? "" : ",", id,
			        e->mnemonic, (unsigned long long)v);
			break;
		}
		first = false;
	}
	if (m->cli.format == CLI_FMT_JSON)
		fputs("]}\n", f);
	m->counter_prints++;
	fflush(f);
}

/* --counters alone: a link test, then the counters; with -i or -c, again every
 * interval until -c N tables, --duration or a signal. Exit 0 if every link test
 * was answered. */
static int run_counters(struct mon *m)
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
		print_counters(m, false);
		if (out_broken() || !mon_sleep(ms_of(interval)))
			break;
	}
	print_counters(m, true);
	if (interrupted() && !m->cli.quiet)
		fprintf(stderr, "%s: stopped by %s after %lu link test%s\n", m->cli.name,
		        signal_name(cli_stop_signal()), tests, tests == 1 ? "" : "s");
	return (tests > 0 && failed == 0) ? CLI_EXIT_OK : CLI_EXIT_FAIL;
}

/* ---- --ping ---- */

struct rtt {
	unsigned long n;
	double min, max, sum;
};

static void rtt_add(struct rtt *t, double ms)
{
	if (t->n == 0 || ms < t->min)
		t->min = ms;
	if (t->n == 0 || ms > t->max)
		t->max = ms;
	t->sum += ms;
	t->n++;
}

#define PING_BYTES 8

static void ping_line_ok(const struct mon *m, long seq, double link_ms, double echo_ms)
{
	switch (m->cli.format) {
	case CLI_FMT_PLAIN:
		printf("station %d: seq=%ld link=%.3f ms echo=%.3f ms (%d bytes)\n", m->cli.station, seq,
		       link_ms, echo_ms, PING_BYTES);
		break;
	case CLI_FMT_CSV:
		printf("%ld,%d,ok,%.3f,%.3f,\n", seq, m->cli.station, link_ms, echo_ms);
		break;
	case CLI_FMT_JSON:
		printf("{\"seq\":%ld,\"station\":%d,\"ok\":true,\"link_ms\":%.3f,\"echo_ms\":%.3f,\"bytes\":%d}\n",
		       seq, m->cli.station, link_ms, echo_ms, PING_BYTES);
		break;
	}
}

static void ping_line_fail(const struct mon *m, long seq, const char *stage, int err)
{
	char text[320];
	const struct df1_error_detail *d = df1_last_error(m->h);
	int id = d && d->code == err && d->catalog_id ? d->catalog_id : df1_error_catalog_id(err);

	cli_error_text(m->h, err, text, sizeof text);
	switch (m->cli.format) {
	case CLI_FMT_PLAIN:
		printf("station %d: seq=%ld no answer (%s): %s\n", m->cli.station, seq, stage, text);
		break;
	case CLI_FMT_CSV:
		printf("%ld,%d,%s,,,", seq, m->cli.station, stage);
		cli_csv_field(stdout, text);
		putchar('\n');
		break;
	case CLI_FMT_JSON:
		printf("{\"seq\":%ld,\"station\":%d,\"ok\":false,\"stage\":\"%s\"", seq, m->cli.station, stage);
		if (id)
			printf(",\"error_id\":%d", id);
		fputs(",\"error\":", stdout);
		cli_json_string(stdout, text);
		fputs("}\n", stdout);
		break;
	}
}

static void ping_summary(const struct mon *m, unsigned long sent, unsigned long recvd,
                         const struct rtt *lk, const struct rtt *ec)
{
	double loss = sent ? 100.0 * (double)(sent - recvd) / (double)sent : 0.0;

	switch (m->cli.format) {
	case CLI_FMT_PLAIN:
		printf("--- station %d: %lu probe%s sent, %lu answered, %.0f%% loss\n", m->cli.station, sent,
		       sent == 1 ? "" : "s", recvd, loss);
		if (lk->n)
			printf("link rtt min/avg/max = %.3f/%.3f/%.3f ms\n", lk->min, lk->sum / (double)lk->n,
			       lk->max);
		if (ec->n)
			printf("echo rtt min/avg/max = %.3f/%.3f/%.3f ms\n", ec->min, ec->sum / (double)ec->n,
			       ec->max);
		break;
	case CLI_FMT_CSV:
		/* the table on stdout holds probes only */
		if (m->cli.quiet)
			break;
		fprintf(stderr, "%s: station %d: %lu probe%s sent, %lu answered, %.0f%% loss", m->cli.name,
		        m->cli.station, sent, sent == 1 ? "" : "s", recvd, loss);
		if (ec->n)
			fprintf(stderr, ", echo rtt min/avg/max = %.3f/%.3f/%.3f ms", ec->min,
			        ec->sum / (double)ec->n, ec->max);
		fputc('\n', stderr);
		break;
	case CLI_FMT_JSON:
		printf("{\"summary\":true,\"station\":%d,\"sent\":%lu,\"received\":%lu,\"loss_pct\":%.1f",
		       m->cli.station, sent, recvd, loss);
		if (lk->n)
			printf(",\"link_ms\":{\"min\":%.3f,\"avg\":%.3f,\"max\":%.3f}", lk->min,
			       lk->sum / (double)lk->n, lk->max);
		if (ec->n)
			printf(",\"echo_ms\":{\"min\":%.3f,\"avg\":%.3f,\"max\":%.3f}", ec->min,
			       ec->sum / (double)ec->n, ec->max);
		fputs("}\n", stdout);
		break;
	}
}

/* Each probe: df1_link_test (DLE ENQ, or a poll in half duplex), then a 06/00
 * echo of PING_BYTES bytes; a probe is answered when both are. */
static int run_ping(struct mon *m)
{
	long count = (m->given & GIVEN_COUNT) ? m->count : 4;
	double interval = (m->given & GIVEN_INTERVAL) ? m->interval_s : 1.0;
	unsigned long sent = 0, recvd = 0;
	struct rtt lk = { 0 }, ec = { 0 };

	if (m->cli.format == CLI_FMT_CSV)
		puts("seq,station,status,link_ms,echo_ms,error");
	for (long seq = 1; count == 0 || seq <= count; seq++) {
		uint8_t data[PING_BYTES] = { 'D', 'F', '1', 'M', 'O', 'N', (uint8_t)(seq & 0xFF),
		                             (uint8_t)((seq >> 8) & 0xFF) };
		int64_t t0, t1, t2;
		int r;

		if (seq > 1 && (out_broken() || !mon_sleep(ms_of(interval))))
			break;
		t0 = mono_us();
		r = df1_link_test(m->h, m->cli.station);
		t1 = mono_us();
		if (r == DF1_E_INTR || cli_stop)
			break;
		sent++;
		if (r < 0) {
			ping_line_fail(m, seq, "link", r);
			fflush(stdout);
			continue;
		}
		r = df1_echo(m->h, m->cli.station, data, sizeof data);
		t2 = mono_us();
		if (r == DF1_E_INTR || cli_stop) {
			sent--;
			break;
		}
		if (r < 0) {
			ping_line_fail(m, seq, "echo", r);
		} else {
			recvd++;
			rtt_add(&lk, (double)(t1 - t0) / 1000.0);
			rtt_add(&ec, (double)(t2 - t1) / 1000.0);
			ping_line_ok(m, seq, (double)(t1 - t0) / 1000.0, (double)(t2 - t1) / 1000.0);
		}
		fflush(stdout);
	}
	ping_summary(m, sent, recvd, &lk, &ec);
	if (interrupted() && !m->cli.quiet)
		fprintf(stderr, "%s: stopped by %s\n", m->cli.name, signal_name(cli_stop_signal()));
	return (sent > 0 && recvd == sent) ? CLI_EXIT_OK : CLI_EXIT_FAIL;
}

/* ---- --who ---- */

/* "N" or "LO-HI", 0..254. */
static int parse_range(struct mon *m, const char *arg)
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
static int run_who(struct mon *m)
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

/* ---- --map ---- */

/* The table is mon_map.c's: it also prints the counters (every interval and at
 * exit) when asked, so main does not print them again. */
static int run_map(struct mon *m)
{
	int fmt = m->cli.format == CLI_FMT_CSV ? MON_MAP_CSV
	        : m->cli.format == CLI_FMT_JSON ? MON_MAP_JSON : MON_MAP_PLAIN;
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
	.formats = CLI_FMT_BIT(CLI_FMT_PLAIN) | CLI_FMT_BIT(CLI_FMT_CSV) | CLI_FMT_BIT(CLI_FMT_JSON),
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
