/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_sniff - df1mon --sniff: listen only, never transmit; decode what one
 * tap (or two, --sniff-b: rx and tx) shows, and with -w save it as a pcap
 * (link type 250, RTAC serial; the format is mon_pcap.c's).
 *
 * A tap is a listen-only libdf1 handle (DF1_OPT_LISTEN_ONLY): a serial device
 * is opened read only (nothing can be transmitted), locked like every libdf1
 * port (so a libdf1 program and df1mon do not steal each other's bytes) and set
 * raw at the line settings, its termios restored when the handle closes, on
 * every exit path; an unknown baud rate is an error, never a fallback.
 * tcp://HOST:PORT is connected with the handle's deadline and shut for sending.
 * Anything else (a FIFO, a file, a character device that is no terminal) goes
 * to the handle with df1_open_fd() and is read as it is; its end ends the
 * sniff. Bytes come from df1_recv_raw() with their time; the taps' descriptors
 * (df1_port_fd) are watched in one poll() with the signal pipe, and used for
 * TIOCMGET (the control lines of a pcap record).
 */
#include "df1mon/mon.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

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

#define SNIFF_CHUNK MON_PCAP_DATA_MAX

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

/* A sniff under way: its taps, the capture written, the tallies. */
struct sniff {
	struct mon *m;
	struct tap taps[2];
	int ntaps;
	int status;                /* CLI_CONTINUE, or the exit status */
	FILE *pcap;                /* -w: the capture, or NULL */
	bool pcap_stdout;          /* -w -: the capture goes to stdout */
	struct timebase tb;
	unsigned long records;
	unsigned long long bytes;
};

/* The taps (one, or two with --sniff-b), their streams and the capture file;
 * a failure leaves its exit status in sn->status. */
static void sniff_open(struct sniff *sn)
{
	struct mon *m = sn->m;
	struct tap *taps = sn->taps;
	int64_t s0;
	int32_t u0;

	taps[0].dev = m->cli.device;
	taps[0].event = RTAC_DATA_RX_END;
	if (sn->ntaps == 2) {
		taps[0].dir = "rx";
		taps[1].dev = m->sniff_b;
		taps[1].dir = "tx";
		taps[1].event = RTAC_DATA_TX_END;
		m->dx.show_dir = true;
	}
	m->dx.show_time = true;
	for (int i = 0; i < sn->ntaps && sn->status == CLI_CONTINUE; i++) {
		sn->status = tap_open(m, &taps[i]);
		if (sn->status == CLI_CONTINUE)
			sn->status = mon_stream_init(m, &taps[i].st, taps[i].dir);
	}
	if (sn->status == CLI_CONTINUE && m->pcap_path) {
		sn->pcap = sn->pcap_stdout ? stdout : fopen(m->pcap_path, "wb");
		if (!sn->pcap || !mon_pcap_write_header(sn->pcap)) {
			fprintf(stderr, "%s: %s: %s\n", m->cli.name, m->pcap_path, strerror(errno));
			sn->status = CLI_EXIT_FAIL;
		}
	}
	if (sn->status == CLI_CONTINUE && sn->pcap_stdout) {
		/* stdout carries the capture: the symbol lines go nowhere */
		m->out = fopen("/dev/null", "w");
		if (!m->out) {
			fprintf(stderr, "%s: /dev/null: %s\n", m->cli.name, strerror(errno));
			sn->status = CLI_EXIT_FAIL;
		}
	}
	mon_wall_now(&s0, &u0);
	sn->tb.set = true;
	sn->tb.sec = s0;
	sn->tb.usec = u0;
}

/* -v: what is sniffed, and where the capture goes. */
static void sniff_announce(const struct sniff *sn)
{
	const struct mon *m = sn->m;

	for (int i = 0; i < sn->ntaps; i++)
		fprintf(stderr, "%s: sniffing %s%s%s at %d %d%c%d, listen only; Ctrl-C to stop\n",
		        m->cli.name, sn->taps[i].dev, sn->taps[i].dir ? " as " : "",
		        sn->taps[i].dir ? sn->taps[i].dir : "", m->cli.baud, m->cli.data_bits, m->cli.parity,
		        m->cli.stop_bits);
	if (m->pcap_path)
		fprintf(stderr, "%s: writing %s\n", m->cli.name,
		        sn->pcap_stdout ? "the capture to stdout" : m->pcap_path);
}

/* The bytes tap t has: into the capture and its stream's decoder. false ends
 * the sniff: a failure (sn->status), a closed stdout or -c frames reached. */
static bool sniff_chunk(struct sniff *sn, struct tap *t)
{
	struct mon *m = sn->m;
	uint8_t buf[SNIFF_CHUNK];
	struct timespec when;
	int n;
	int64_t sec;
	int32_t usec;

	n = df1_recv_raw(t->h, buf, sizeof buf, 0, &when);
	if (n == 0 || n == DF1_E_INTR)
		return true;   /* nothing after all, or a signal: the loop looks at cli_stop */
	if (n < 0) {
		if (n == DF1_E_CLOSED && t->file) {
			t->eof = true;   /* the end of a FIFO or file */
			if (m->cli.verbose >= 1)
				fprintf(stderr, "%s: %s: end of input\n", m->cli.name, t->dev);
			return true;
		}
		tap_fail(m, t, n);
		sn->status = CLI_EXIT_FAIL;
		return false;
	}
	sec = (int64_t)when.tv_sec;
	usec = (int32_t)(when.tv_nsec / 1000);
	sn->records++;
	sn->bytes += (unsigned long long)n;
	t->bytes += (unsigned long long)n;
	if (sn->pcap && !mon_pcap_write_record(sn->pcap, sec, usec, t->event, tap_lines(t), buf, (size_t)n)) {
		fprintf(stderr, "%s: %s: %s\n", m->cli.name, sn->pcap_stdout ? "stdout" : m->pcap_path,
		        strerror(errno ? errno : EIO));
		sn->status = CLI_EXIT_FAIL;
		return false;
	}
	if (m->cli.verbose >= 2 && !m->cli.quiet)
		sniff_trace(m, t, buf, (size_t)n);
	mon_stream_mark(&t->st, sec, usec);
	mon_stream_feed(m, &t->st, &sn->tb, buf, (size_t)n);
	if (fflush(m->out ? m->out : stdout) != 0 || ferror(m->out ? m->out : stdout))
		return false;   /* a closed pipe: stop; main reports stdout's error (exit 1) */
	return !(m->frame_limit && m->dx.frames >= m->frame_limit);
}

/* The taps' descriptors and the signal pipe in one poll(), until a signal,
 * the end of every tap's input, a failure or sniff_chunk() says stop. */
static void sniff_loop(struct sniff *sn)
{
	while (sn->status == CLI_CONTINUE && !cli_stop) {
		struct pollfd p[3];
		int np = 0, idx[3], sfd = cli_signal_fd(), open_taps = 0;

		for (int i = 0; i < sn->ntaps; i++) {
			if (sn->taps[i].eof)
				continue;
			open_taps++;
			idx[np] = i;
			p[np++] = (struct pollfd){ .fd = sn->taps[i].fd, .events = POLLIN };
		}
		if (!open_taps)
			return;
		if (sfd >= 0) {
			idx[np] = -1;
			p[np++] = (struct pollfd){ .fd = sfd, .events = POLLIN };
		}
		if (poll(p, (nfds_t)np, -1) < 0) {
			if (errno == EINTR)
				continue;
			fprintf(stderr, "%s: poll: %s\n", sn->m->cli.name, strerror(errno));
			sn->status = CLI_EXIT_FAIL;
			return;
		}
		for (int k = 0; k < np && sn->status == CLI_CONTINUE && !cli_stop; k++) {
			if (idx[k] < 0 || !(p[k].revents & (POLLIN | POLLHUP | POLLERR)))
				continue;
			if (!sniff_chunk(sn, &sn->taps[idx[k]]))
				return;
		}
	}
}

/* The end: a symbol under way reported, the taps and the capture closed. */
static void sniff_close(struct sniff *sn)
{
	struct mon *m = sn->m;

	for (int i = 0; i < sn->ntaps; i++) {
		/* the end of a FIFO or file is the end of the input, as for --read */
		if (sn->taps[i].st.dec && !(m->frame_limit && m->dx.frames >= m->frame_limit))
			mon_stream_finish_cut(m, &sn->taps[i].st, &sn->tb, !sn->taps[i].eof);
		tap_close(&sn->taps[i]);
		mon_stream_free(&sn->taps[i].st);
	}
	if (sn->pcap && !sn->pcap_stdout && fclose(sn->pcap) != 0 && sn->status == CLI_CONTINUE) {
		fprintf(stderr, "%s: %s: %s\n", m->cli.name, m->pcap_path, strerror(errno));
		sn->status = CLI_EXIT_FAIL;
	}
	if (m->out && m->out != stdout) {
		fclose(m->out);
		m->out = NULL;
	}
}

/* Why the sniff stopped and what the capture holds, unless -q. */
static void sniff_summary(const struct sniff *sn)
{
	const struct mon *m = sn->m;

	if (!m->cli.quiet && sn->records) {
		if (mon_interrupted())
			fprintf(stderr, "%s: stopped by %s\n", m->cli.name, mon_signal_name(cli_stop_signal()));
		if (sn->pcap)
			fprintf(stderr, "%s: %llu bytes in %lu record%s written to %s\n", m->cli.name, sn->bytes,
			        sn->records, sn->records == 1 ? "" : "s",
			        sn->pcap_stdout ? "stdout" : m->pcap_path);
	} else if (!m->cli.quiet && mon_interrupted()) {
		fprintf(stderr, "%s: stopped by %s; nothing received\n", m->cli.name,
		        mon_signal_name(cli_stop_signal()));
	}
}

int mon_run_sniff(struct mon *m)
{
	static struct sniff sn;   /* holds two streams' rings: not on the stack */

	memset(&sn, 0, sizeof sn);
	sn.m = m;
	sn.ntaps = m->sniff_b ? 2 : 1;
	sn.status = CLI_CONTINUE;
	sn.pcap_stdout = m->pcap_path && strcmp(m->pcap_path, "-") == 0;
	sn.taps[0].fd = sn.taps[1].fd = -1;
	if (!m->cli.device || !*m->cli.device)
		return cli_usage_error(&m->cli, "no device: use -d DEV, -N FILE or set DF1_DEVICE");
	sniff_open(&sn);
	if (sn.status == CLI_CONTINUE && m->cli.verbose >= 1)
		sniff_announce(&sn);
	sniff_loop(&sn);
	sniff_close(&sn);
	sniff_summary(&sn);
	return sn.status;
}
