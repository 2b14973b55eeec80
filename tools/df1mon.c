/*
 * df1mon - DF1 diagnostics (DESIGN.md 8).
 *
 * Offline modes (no device):
 *   --decode [HEX...]  frames given as hex: each argument (or each stdin line) is
 *                      decoded on its own, with a fresh decoder
 *   --read FILE        a pcap (link type 250, RTAC serial) or a raw byte dump
 * Live modes (--sniff, --ping, --who, --counters, --map) plug into the same
 * dispatch: add an enum mon_mode value, an entry in modes[], an option in
 * mon_opts[] and its run function.
 *
 * One line per symbol on stdout (tools/decode.c); a summary on stderr unless -q.
 * Exit: 0 all decoded and good, 1 a frame with a bad check or a malformed
 * symbol, 2 usage, unreadable input or bad hex.
 */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "decode.h"
#include "df1.h"

enum mon_mode {
	MODE_NONE = 0,
	MODE_DECODE,
	MODE_READ,
	MODE_COUNT_
};

enum {
	KEY_DECODE = CLI_KEY_EXTRA,
};

struct mon {
	struct cli cli;
	enum mon_mode mode;
	const char *read_file;
	struct decode_ctx dx;
	unsigned long index;       /* symbols printed */
	unsigned long long fed;    /* bytes fed to decoders */
	unsigned long long used;   /* bytes that belonged to a symbol */
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
	decode_print(&m->dx, stdout, NULL, &w, sym);
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
		if (k == 0)
			break;
	}
}

/* End of the input: a symbol still under way is reported. Feeding DLE STX ends any
 * frame in progress as "no ETX" (2518); in AUTO mode a frame waiting after its one
 * check byte (a BCC that did not match, or the first byte of a CRC) is taken as a
 * frame with a bad BCC, as it would be if a DLE followed. */
static void stream_finish(struct mon *m, struct stream *s, const struct timebase *tb)
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
			print_symbol(m, s, tb, &sym, s->off);
		} else {
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

/* ---- modes, options, main ---- */

struct mon_mode_def {
	const char *option;            /* for messages */
	int (*run)(struct mon *m);     /* CLI_CONTINUE when done, or an exit status */
	bool offline;                  /* decodes and summarises; no device */
};

static const struct mon_mode_def modes[MODE_COUNT_] = {
	[MODE_DECODE] = { "--decode", run_decode, true },
	[MODE_READ] = { "--read", run_read, true },
};

static const struct cli_extra_opt mon_opts[] = {
	{ "decode", no_argument, KEY_DECODE, NULL,
	  "decode HEX arguments, or stdin lines, one chunk each" },
	{ "read", required_argument, 'r', "FILE", "decode a pcap (RTAC serial) or raw dump; - for stdin" },
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

static int on_option(struct cli *c, int key, const char *arg, void *user)
{
	struct mon *m = user;

	switch (key) {
	case KEY_DECODE:
		return set_mode(m, MODE_DECODE);
	case 'r':
		m->read_file = arg;
		return set_mode(m, MODE_READ);
	default:
		return cli_usage_error(c, "unknown option");
	}
}

static const struct cli_tool mon_tool = {
	.name = "df1mon",
	.synopsis = "--decode [OPTIONS] [HEX...]\n--read FILE [OPTIONS]",
	.summary = "Decode DF1 traffic: frames given as hex, or a capture (pcap, RTAC serial) or raw dump.",
	.accepts = CLI_ACCEPT_ALL,
	.formats = CLI_FMT_BIT(CLI_FMT_PLAIN) | CLI_FMT_BIT(CLI_FMT_JSON),
	.check_auto = true,
	.extra = mon_opts,
	.on_extra = on_option,
	.exit_text = "0 all decoded and good, 1 a bad check or a malformed symbol,\n"
	             "2 usage error, bad hex or unreadable input.",
	.help_tail = "\nOffline modes take --check crc|bcc|auto (default auto) and --duplex full|half.\n"
	             "See df1mon(1).\n",
};

int main(int argc, char **argv)
{
	static struct mon m;
	int r;

	cli_init(&m.cli, &mon_tool);
	m.cli.check = DF1_CHECK_AUTO;
	r = cli_parse(&m.cli, argc, argv, &m);
	if (r != CLI_CONTINUE)
		return r;
	if (m.mode == MODE_NONE)
		return cli_usage_error(&m.cli, "no mode given: use --decode or --read FILE");
	if (m.mode != MODE_DECODE && m.cli.argc > 0)
		return cli_usage_error(&m.cli, "unexpected argument '%s'", m.cli.argv[0]);

	decode_ctx_init(&m.dx, m.cli.format);
	m.dx.verbose = m.cli.verbose;
	r = modes[m.mode].run(&m);
	if (fflush(stdout) != 0 || ferror(stdout)) {
		fprintf(stderr, "%s: stdout: %s\n", m.cli.name, strerror(errno));
		return CLI_EXIT_FAIL;
	}
	if (modes[m.mode].offline && !m.cli.quiet && (r == CLI_CONTINUE || m.fed > 0)) {
		unsigned long long noise = m.fed > m.used ? m.fed - m.used : 0;
		fprintf(stderr, "%s: %lu frames, %lu good, %lu bad, %lu symbols", m.cli.name, m.dx.frames,
		        m.dx.good, m.dx.bad, m.dx.symbols);
		if (m.dx.errors)
			fprintf(stderr, ", %lu errors", m.dx.errors);
		if (noise)
			fprintf(stderr, ", %llu bytes of noise", noise);
		fputc('\n', stderr);
	}
	cli_cleanup(&m.cli);
	if (r != CLI_CONTINUE)
		return r;
	return (m.dx.bad || m.dx.errors) ? CLI_EXIT_FAIL : CLI_EXIT_OK;
}
