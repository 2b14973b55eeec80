/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_read - df1mon --read FILE: a pcap (link type 250, RTAC serial, or any
 * other taken as serial bytes) or a raw byte dump.
 *
 * Decoded as it is read: read(2) in chunks of READ_CHUNK bytes into one fixed
 * buffer, pcap records parsed by a state machine that keeps only the header
 * bytes it has not finished (a header may straddle reads), record data fed to
 * the decoders straight from the buffer, stdout flushed after every chunk. The
 * memory is bounded whatever the input (--read /dev/zero runs in constant
 * memory) and a live stream (--read - from a tap's pipe) shows each frame as
 * soon as its bytes are in.
 *
 * Direction columns (rx/tx) appear when a capture holds both directions. For a
 * regular file a first pass over the record headers decides, so the output is
 * the same from the first line; on a pipe they appear from the record where
 * the second direction is first seen. The pcap format itself (headers, RTAC
 * event types) is mon_pcap.c's.
 */
#include "df1mon/mon.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define READ_CHUNK 65536

/* The input: a file descriptor read in chunks. */
struct input {
	struct mon *m;
	const char *path;
	int fd;
	bool regular;          /* a regular file: it can be read twice */
	unsigned long long at; /* bytes read so far */
	uint8_t buf[READ_CHUNK];
};

/* Up to READ_CHUNK bytes into in->buf: > 0, 0 at the end, < 0 on an error (reported). */
static ssize_t input_read(struct input *in)
{
	ssize_t k;

	do
		k = read(in->fd, in->buf, sizeof in->buf);
	while (k < 0 && errno == EINTR);
	if (k < 0)
		fprintf(stderr, "%s: %s: %s\n", in->m->cli.name, in->path, strerror(errno));
	else
		in->at += (unsigned long long)k;
	return k;
}

/* Where a pcap record's parse stands. */
enum rec_state { R_HDR, R_RTAC, R_DATA };

struct pcap_run {
	struct pcap_fmt pf;
	bool rtac;
	bool scan;               /* the first pass of a regular file: directions only */
	bool seen[2];            /* directions in complete records (the scan's verdict) */
	bool live_seen[2];       /* directions met so far (a pipe) */
	bool fixed_dirs;         /* a regular file: the scan decided the columns */
	struct stream st[2];
	struct timebase tb;
	enum rec_state rs;
	uint8_t hdr[PCAP_REC_HDR]; /* the record header so far */
	uint8_t rt[RTAC_HDR];    /* the RTAC header so far */
	size_t nhdr, nrt;
	unsigned long long hdr_at; /* file offset of the record header under way */
	uint32_t sec, incl;
	int32_t usec;
	uint32_t left;           /* record bytes not yet read */
	uint32_t got;            /* record bytes read */
	int dir;                 /* the record's direction, once known */
	bool marked;             /* the record's payload has its stream mark */
	unsigned long rec, short_recs;
};

/* Both directions met on a pipe: show the columns from here on. */
static void live_dir(struct mon *m, struct pcap_run *r, int dir)
{
	if (r->fixed_dirs)
		return;
	r->live_seen[dir] = true;
	if (r->live_seen[0] && r->live_seen[1] && !m->dx.show_dir) {
		m->dx.show_dir = true;
		r->st[0].dir = "rx";
		r->st[1].dir = "tx";
	}
}

/* Record payload bytes (after the RTAC header, if any). */
static void rec_payload(struct mon *m, struct pcap_run *r, const uint8_t *p, size_t n)
{
	struct stream *s = &r->st[r->rtac ? r->dir : 0];

	if (r->scan || n == 0)
		return;
	if (!r->marked) {
		r->marked = true;
		mon_stream_mark(s, r->sec, r->usec);
	}
	mon_stream_feed(m, s, &r->tb, p, n);
}

/* The record's data starts (its RTAC header, if any, is complete). */
static void rec_begin_payload(struct mon *m, struct pcap_run *r)
{
	if (r->rtac) {
		r->dir = mon_rtac_dir(r->rt[8]);
		if (!r->scan)
			live_dir(m, r, r->dir);
	}
	if (!r->scan && !r->tb.set) {
		r->tb.set = true;
		r->tb.sec = r->sec;
		r->tb.usec = r->usec;
	}
	r->rs = R_DATA;
}

static void rec_end(struct pcap_run *r)
{
	if (r->rtac && r->incl >= RTAC_HDR)
		r->seen[r->dir] = true;
	if (r->rtac && r->incl < RTAC_HDR)
		r->short_recs++;
	r->rs = R_HDR;
	r->nhdr = 0;
}

/* A chunk of the records' bytes. */
static void pcap_chunk(struct mon *m, struct pcap_run *r, const uint8_t *p, size_t n,
                       unsigned long long off)
{
	while (n > 0) {
		size_t k;

		switch (r->rs) {
		case R_HDR:
			if (r->nhdr == 0)
				r->hdr_at = off;
			k = PCAP_REC_HDR - r->nhdr < n ? PCAP_REC_HDR - r->nhdr : n;
			memcpy(r->hdr + r->nhdr, p, k);
			r->nhdr += k;
			if (r->nhdr == PCAP_REC_HDR) {
				r->rec++;
				mon_pcap_rec_hdr(r->hdr, &r->pf, &r->sec, &r->usec, &r->incl);
				r->left = r->incl;
				r->got = 0;
				r->nrt = 0;
				r->marked = false;
				r->dir = 0;
				if (r->rtac)
					r->rs = r->incl >= RTAC_HDR ? R_RTAC : R_DATA;
				else
					rec_begin_payload(m, r);
				if (r->left == 0)
					rec_end(r);
			}
			break;
		case R_RTAC:
			k = RTAC_HDR - r->nrt < n ? RTAC_HDR - r->nrt : n;
			memcpy(r->rt + r->nrt, p, k);
			r->nrt += k;
			r->left -= (uint32_t)k;
			r->got += (uint32_t)k;
			if (r->nrt == RTAC_HDR)
				rec_begin_payload(m, r);
			if (r->left == 0)
				rec_end(r);
			break;
		case R_DATA:
		default:
			k = r->left < n ? r->left : n;
			/* a record shorter than the RTAC header is skipped */
			if (!r->rtac || r->incl >= RTAC_HDR)
				rec_payload(m, r, p, k);
			r->left -= (uint32_t)k;
			r->got += (uint32_t)k;
			if (r->left == 0)
				rec_end(r);
			break;
		}
		p += k;
		n -= k;
		off += k;
	}
}

/* The end of the input: a record cut short is reported (exit 2). */
static int pcap_eof(struct mon *m, const char *path, struct pcap_run *r)
{
	if (r->rs == R_HDR && r->nhdr > 0) {
		fprintf(stderr, "%s: %s: truncated record header at byte %llu\n", m->cli.name, path,
		        r->hdr_at);
		return CLI_EXIT_USAGE;
	}
	if (r->rs != R_HDR) {
		fprintf(stderr, "%s: %s: record %lu truncated (%u bytes, %u in the file)\n", m->cli.name,
		        path, r->rec, (unsigned)r->incl, (unsigned)r->got);
		/* cut inside the RTAC header or with none: too short, skipped */
		if (r->rtac && r->nrt < RTAC_HDR)
			r->short_recs++;
		return CLI_EXIT_USAGE;
	}
	return CLI_CONTINUE;
}

/* The first pass over a regular file: which directions complete records hold.
 * Both files offsets end just after the pcap header. */
static int pcap_scan(struct input *in, struct pcap_run *r)
{
	ssize_t k = 0;

	r->scan = true;
	if (lseek(in->fd, PCAP_HDR, SEEK_SET) == PCAP_HDR) {
		in->at = PCAP_HDR;
		while (!(r->seen[0] && r->seen[1]) && (k = input_read(in)) > 0)
			pcap_chunk(in->m, r, in->buf, (size_t)k, in->at - (unsigned long long)k);
		if (k < 0)
			return CLI_EXIT_USAGE;
		if (lseek(in->fd, PCAP_HDR, SEEK_SET) == PCAP_HDR) {
			in->at = PCAP_HDR;
			return CLI_CONTINUE;
		}
	}
	fprintf(stderr, "%s: %s: %s\n", in->m->cli.name, in->path, strerror(errno));
	return CLI_EXIT_USAGE;
}

/* A pcap whose first `have` bytes (at least the 24 of its header) are in in->buf. */
static int run_read_pcap(struct mon *m, struct input *in, size_t have, const struct pcap_fmt *pf)
{
	static struct pcap_run r;   /* holds two streams' rings: not on the stack */
	int status = CLI_CONTINUE;
	bool both;
	ssize_t k;

	memset(&r, 0, sizeof r);
	r.pf = *pf;
	r.rtac = pf->linktype == LINKTYPE_RTAC_SERIAL;
	if (!r.rtac && !m->cli.quiet)
		fprintf(stderr, "%s: %s: link type %u is not RTAC serial (250): record data taken as serial bytes\n",
		        m->cli.name, in->path, (unsigned)pf->linktype);
	if (r.rtac && in->regular) {
		status = pcap_scan(in, &r);
		if (status != CLI_CONTINUE)
			return status;
		r.fixed_dirs = true;
		have = PCAP_HDR;   /* the records again, from the first */
	}
	both = r.seen[0] && r.seen[1];
	memcpy(r.live_seen, r.seen, sizeof r.seen);
	memset(r.seen, 0, sizeof r.seen);
	r.scan = false;
	r.rs = R_HDR;
	r.nhdr = 0;
	r.rec = 0;
	r.short_recs = 0;
	if (mon_stream_init(m, &r.st[0], both ? "rx" : NULL) != CLI_CONTINUE)
		return CLI_EXIT_FAIL;
	if (mon_stream_init(m, &r.st[1], both ? "tx" : NULL) != CLI_CONTINUE) {
		mon_stream_free(&r.st[0]);
		return CLI_EXIT_FAIL;
	}
	if (both)
		m->dx.show_dir = true;
	m->dx.show_time = true;

	pcap_chunk(m, &r, in->buf + PCAP_HDR, have - PCAP_HDR, PCAP_HDR);
	for (;;) {
		if (fflush(stdout) != 0 || ferror(stdout))
			break;   /* main reports stdout's error */
		k = input_read(in);
		if (k <= 0) {
			if (k < 0)
				status = CLI_EXIT_USAGE;
			break;
		}
		pcap_chunk(m, &r, in->buf, (size_t)k, in->at - (unsigned long long)k);
	}
	if (status == CLI_CONTINUE)
		status = pcap_eof(m, in->path, &r);
	mon_stream_finish(m, &r.st[0], &r.tb);
	mon_stream_finish(m, &r.st[1], &r.tb);
	mon_stream_free(&r.st[0]);
	mon_stream_free(&r.st[1]);
	if (r.short_recs && !m->cli.quiet)
		fprintf(stderr, "%s: %s: %lu records shorter than the RTAC header skipped\n", m->cli.name,
		        in->path, r.short_recs);
	return status;
}

/* A raw dump: every byte to one decoder, the first `have` already in in->buf. */
static int run_read_raw(struct mon *m, struct input *in, size_t have)
{
	struct stream s;
	int r = mon_stream_init(m, &s, NULL);
	ssize_t k = (ssize_t)have;

	if (r != CLI_CONTINUE)
		return r;
	while (k > 0) {
		mon_stream_feed(m, &s, NULL, in->buf, (size_t)k);
		if (fflush(stdout) != 0 || ferror(stdout))
			break;
		k = input_read(in);
	}
	if (k < 0)
		r = CLI_EXIT_USAGE;
	mon_stream_finish(m, &s, NULL);
	mon_stream_free(&s);
	return r;
}

int mon_run_read(struct mon *m)
{
	static struct input in;
	struct pcap_fmt pf;
	struct stat sb;
	size_t have = 0;
	bool std_in = strcmp(m->read_file, "-") == 0;
	int r = CLI_CONTINUE, kind;

	memset(&in, 0, sizeof in);
	in.m = m;
	in.path = m->read_file;
	in.fd = std_in ? STDIN_FILENO : open(in.path, O_RDONLY | O_CLOEXEC);
	if (in.fd < 0) {
		fprintf(stderr, "%s: %s: %s\n", m->cli.name, in.path, strerror(errno));
		return CLI_EXIT_USAGE;
	}
	in.regular = fstat(in.fd, &sb) == 0 && S_ISREG(sb.st_mode) &&
	             lseek(in.fd, 0, SEEK_CUR) == 0;
	/* enough bytes to tell a pcap (its 24-byte header) from a raw dump */
	for (;;) {
		ssize_t k;
		do
			k = read(in.fd, in.buf + have, sizeof in.buf - have);
		while (k < 0 && errno == EINTR);
		if (k < 0) {
			fprintf(stderr, "%s: %s: %s\n", m->cli.name, in.path, strerror(errno));
			r = CLI_EXIT_USAGE;
			break;
		}
		have += (size_t)k;
		in.at += (unsigned long long)k;
		if (k == 0 || have >= PCAP_HDR || (have >= 4 && mon_pcap_detect(in.buf, have, &pf) == 0))
			break;
	}
	if (r == CLI_CONTINUE) {
		kind = mon_pcap_detect(in.buf, have, &pf);
		if (kind < 0) {
			fprintf(stderr, "%s: %s: pcapng is not supported; convert it with: editcap -F pcap %s OUT.pcap\n",
			        m->cli.name, in.path, in.path);
			r = CLI_EXIT_USAGE;
		} else if (kind == 1) {
			if (have < PCAP_HDR) {
				fprintf(stderr, "%s: %s: truncated pcap header\n", m->cli.name, in.path);
				r = CLI_EXIT_USAGE;
			} else {
				pf.linktype = mon_pcap_linktype(in.buf, &pf);
				r = run_read_pcap(m, &in, have, &pf);
			}
		} else {
			r = run_read_raw(m, &in, have);
		}
	}
	if (!std_in)
		close(in.fd);
	return r;
}
