/*
 * mon_read - df1mon --read FILE: a pcap (link type 250, RTAC serial, or any
 * other taken as serial bytes) or a raw byte dump.
 */
#include "mon.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

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

int run_read(struct mon *m)
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
