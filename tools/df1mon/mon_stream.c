/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_stream - df1mon: one byte stream through a decoder (one direction of a
 * capture, or one --decode chunk); each symbol printed with its time (see mon.h).
 */
#include "df1mon/mon.h"

#include <string.h>

int mon_stream_init(struct mon *m, struct stream *s, const char *dir)
{
	int r;

	memset(s, 0, sizeof *s);
	s->dir = dir;
	r = df1_decoder_new(&s->dec, m->cli.check);
	if (r < 0) {
		fprintf(stderr, "%s: decoder: %s\n", m->cli.name, df1_strerror(r));
		return CLI_EXIT_FAIL;
	}
	/* --duplex forces a reading; without it the offline modes know a poll by its
	 * shape. Not --sniff: the ENQ would wait for the line's next byte. */
	if ((m->cli.given & CLI_ACCEPT(CLI_OPT_DUPLEX)) || m->mode == MODE_SNIFF)
		df1_decoder_set_half_duplex(s->dec, m->cli.half_duplex);
	else
		s->duplex_auto = df1_decoder_set_duplex_auto(s->dec, true) == DF1_OK;
	cli_decoder_options(&m->cli, s->dec);   /* --hd-bcc stx, --nak-0f no ... */
	/* a radio modem sends no ACK or NAK: a DLE pair inside a frame breaks it,
	 * as a radio node reads it (doc/PROTOCOL.md 2.6) */
	if (m->cli.radio)
		(void)df1_decoder_set_option(s->dec, DF1_OPT_EMBEDDED_RESPONSES, 0);
	return CLI_CONTINUE;
}

void mon_stream_free(struct stream *s)
{
	df1_decoder_free(s->dec);
	s->dec = NULL;
}

void mon_stream_mark(struct stream *s, int64_t sec, int32_t usec)
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

/* Keep the last 4 bytes consumed (n of them at p). */
static void keep_tail(struct stream *s, const uint8_t *p, size_t n)
{
	if (n >= sizeof s->tail) {
		memcpy(s->tail, p + n - sizeof s->tail, sizeof s->tail);
	} else if (n > 0) {
		memmove(s->tail, s->tail + n, sizeof s->tail - n);
		memcpy(s->tail + sizeof s->tail - n, p, n);
	}
}

/* An auto-duplex ENQ is reported once the bytes after it are known not to be a
 * poll: the STN byte, a DLE, or DLE DLE were consumed after it (frame.h). Those
 * of the input, to find where the ENQ ended (its time is its record's). */
static unsigned long long enq_after(const struct stream *s)
{
	const uint8_t *t = s->tail;

	if (t[0] == 0x10 && t[1] == 0x05 && t[2] == 0x10 && t[3] == 0x10)
		return 2;   /* DLE ENQ, DLE DLE */
	if (t[1] == 0x10 && t[2] == 0x05)
		return 1;   /* DLE ENQ, one byte */
	return 0;       /* DLE ENQ last (the end of the input decided) */
}

static void print_symbol(struct mon *m, struct stream *s, const struct timebase *tb,
                         const struct df1_symbol *sym, unsigned long long end)
{
	struct decode_where w;

	if (s->duplex_auto && sym->kind == DF1_SYM_ENQ && !sym->embedded) {
		unsigned long long after = enq_after(s);
		end = end >= after ? end - after : 0;
	}

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
	if (m->cli.radio)
		mon_radio_seen(m, s->dir, sym, &w);
	m->used += sym->wire_len;
	decode_print(&m->dx, m->out ? m->out : stdout, NULL, &w, sym);
}

void mon_stream_feed(struct mon *m, struct stream *s, const struct timebase *tb,
                 const uint8_t *p, size_t n)
{
	size_t pos = 0;

	m->fed += n;
	while (pos < n) {
		struct df1_symbol sym;
		size_t k = df1_decoder_feed(s->dec, p + pos, n - pos, &sym);
		keep_tail(s, p + pos, k);
		pos += k;
		s->off += k;
		if (sym.kind != DF1_SYM_NONE)
			print_symbol(m, s, tb, &sym, s->off);
		/* 0 bytes with a symbol: an auto-duplex ENQ, the byte is fed again */
		if ((k == 0 && sym.kind == DF1_SYM_NONE) ||
		    (m->frame_limit && m->dx.frames >= m->frame_limit))
			break;
	}
}

/* End of the input: a symbol still under way is reported. Feeding DLE STX ends any
 * frame in progress as "no ETX" (2518); in AUTO mode a frame waiting after its one
 * check byte (a BCC that did not match, or the first byte of a CRC) is taken as a
 * frame with a bad BCC, as it would be if a DLE followed. With cut (a sniff
 * stopped by a signal, -c or --duration) only that BCC verdict is given: a symbol
 * the stop cut short is not an error of the line. */
void mon_stream_finish_cut(struct mon *m, struct stream *s, const struct timebase *tb, bool cut)
{
	static const uint8_t probe[2] = { 0x10, 0x02 };
	/* a DLE the input ended on is the probe's DLE already: DLE DLE would be a
	 * data byte and leave the frame open */
	bool dle_last = df1_decoder_dle_pending(s->dec);

	for (size_t i = dle_last ? 1 : 0; i < sizeof probe; i++) {
		struct df1_symbol sym;
		size_t k;

		/* 0 bytes with a symbol: one of the input alone (an auto-duplex ENQ);
		 * the same probe byte goes on */
		while ((k = df1_decoder_feed(s->dec, probe + i, 1, &sym)) == 0 && sym.kind != DF1_SYM_NONE)
			print_symbol(m, s, tb, &sym, s->off);
		if (sym.kind == DF1_SYM_NONE)
			continue;
		if ((i == 0 && sym.kind == DF1_SYM_FRAME && m->cli.check == DF1_CHECK_AUTO &&
		     sym.check == DF1_CHECK_BCC && !sym.check_ok) ||
		    (i == 1 && sym.kind == DF1_SYM_ERROR && sym.error == DF1_ID_NTC_NO_ETX_RCVD)) {
			/* a true verdict on the bytes that were there (the DLE the
			 * input ended on among them, though the error leaves it out) */
			if (!cut || i == 0) {
				print_symbol(m, s, tb, &sym, s->off);
				m->used += dle_last;
			}
		} else if (!cut) {
			struct decode_where w;
			/* the bytes of the symbol that were real input, not the probe: an
			 * error the probe's DLE STX began anew leaves it out of wire_len; a
			 * message too short or too long ends at the check, probe bytes and all */
			bool probe_kept = sym.kind == DF1_SYM_ERROR && i == 1 &&
			                  sym.error != DF1_ID_NTC_RCVD_MSG_TOO_SHORT &&
			                  sym.error != DF1_ID_NTC_RCVD_MSG_TOO_LONG;
			m->used += probe_kept ? sym.wire_len
			                      : (sym.wire_len > i + 1 ? sym.wire_len - (i + 1) : 0);
			memset(&w, 0, sizeof w);
			w.index = ++m->index;
			w.dir = s->dir;
			decode_print_error(&m->dx, stdout, NULL, &w, DF1_ID_NTC_NO_ETX_RCVD,
			                   "input ended inside a symbol");
		}
		break;
	}
	df1_decoder_reset(s->dec);
}

void mon_stream_finish(struct mon *m, struct stream *s, const struct timebase *tb)
{
	mon_stream_finish_cut(m, s, tb, false);
}
