/* SPDX-License-Identifier: MPL-2.0 */
/*
 * plc5.c - PLC-5: typed reads and writes (0F/68, 0F/67) with a logical binary
 * or ASCII address, split into packets.
 */
#include "client/client_int.h"

/* Type/data element type for a span: single words are integers. */
static unsigned plc5_elem_type(const struct span *s)
{
	return plc5_td_type(s->a.type, s->esize);
}

/* Does a reply's element type fit what was asked? */
static bool plc5_type_ok(const struct span *s, unsigned type_id)
{
	unsigned want = plc5_elem_type(s);

	if (want == PCCC_TD_INTEGER && s->esize == 2)
		return type_id == PCCC_TD_INTEGER || type_id == PCCC_TD_BITSTR || type_id == PCCC_TD_BCD;
	return type_id == want;
}

int plc5_addr(struct df1 *h, int station, const char *what, const struct df1_addr *a,
              uint8_t *out, size_t cap)
{
	int n = pccc_enc_plc5_addr(out, cap, a);

	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the PLC-5 address (%s)",
		                df1_strerror(n));
	return n;
}

/* Whole T/C/R elements: a reply's element holds the 3 data-table words or the 5
 * of KF2 p.130 / VME p.81 (timer 59 0A); words 0-2 are CTL, PRE/LEN, ACC/POS either
 * way and the rest is ignored (doc/PROTOCOL.md 4.3, 5). */
static bool plc5_whole_tcr(const struct span *s)
{
	return client_is_tcr(s->a.type) && s->esize == PCCC_TCR_BYTES;
}

/* Elements of the size a reply's descriptor gives that fill one reply: a PLC
 * that cuts its reply to 240 bytes sends that many when asked for more. */
static size_t plc5_reply_full(size_t alen, const struct pccc_typed *td)
{
	return plc5_typed_per_packet(alen, td->type_id, td->elem_size);
}

/* The station's entry, or NULL outside 0..254 (broadcast 255 answers nothing). */
static struct station_state *plc5_station(struct df1 *h, int station)
{
	return station >= 0 && station < 255 ? &h->stations[station] : NULL;
}

/* The words of a timer to plan a typed read with: the option when it was set
 * (DF1_OPT_PLC5_TIMER_WORDS forces a size), else what this station's timers
 * came back as, else the data table's 3. */
static int plc5_timer_words(struct df1 *h, int station)
{
	const struct station_state *st = plc5_station(h, station);

	if (h->cfg.plc5_timer_forced || !st || st->plc5_timer_words == 0)
		return h->cfg.plc5_timer_words;
	return st->plc5_timer_words;
}

/* Remember the size a station's timers came back as (not when the option forces one). */
static void plc5_timer_learn(struct df1 *h, int station, const struct span *s, size_t elem_size)
{
	struct station_state *st = plc5_station(h, station);

	if (!st || h->cfg.plc5_timer_forced || s->a.type != DF1_FT_T || !plc5_whole_tcr(s))
		return;
	if (elem_size == PCCC_TCR5_BYTES)
		st->plc5_timer_words = 5;
	else if (elem_size == PCCC_TCR_BYTES)
		st->plc5_timer_words = 3;
}

int plc5_read_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd)
{
	size_t plan = s->esize;

	rd->alen = plc5_addr(h, station, what, &s->a, rd->addr, sizeof rd->addr);
	if (rd->alen < 0)
		return rd->alen;
	/* the reply: address + type/data + data <= 240 (plc_limits.h); strings
	 * one per packet: the reply is 3x LEN characters (RTA); timers of a PLC-5
	 * said to send 5 words, or known to, are planned at that size */
	if (s->a.type == DF1_FT_T && plc5_whole_tcr(s) && plc5_timer_words(h, station) == 5)
		plan = PCCC_TCR5_BYTES;
	rd->per = plc_per_packet(DF1_PLC_PLC5, false, s->a.type, plan, (size_t)rd->alen, h->cfg.max_packet);
	if (rd->per == 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "a %zu-byte element exceeds the packet size", s->esize);
	return 0;
}

/* EXT STS 09, "data or file is too large" (lib/proto/errors.c): a controller with
 * 5-word timers that will not cut its reply answers so a read planned at 3
 * words. The packet goes again with as many 5-word elements as fit; a timer
 * file's station is then known to send 5. Not when the option forces a size. */
bool plc5_read_refused(struct df1 *h, int station, const struct span *s, struct rd *rd)
{
	size_t per5;

	if (!plc5_whole_tcr(s) || rd->replanned || h->cfg.plc5_timer_forced ||
	    h->err.code != DF1_E_REMOTE || h->err.sts != 0xF0 || !h->err.has_ext_sts ||
	    h->err.ext_sts != 0x09)
		return false;
	per5 = plc_per_packet(DF1_PLC_PLC5, false, s->a.type, PCCC_TCR5_BYTES, (size_t)rd->alen,
	                      h->cfg.max_packet);
	if (per5 == 0 || per5 >= rd->k)
		return false;   /* the packet was no larger than a 5-word plan: a real refusal */
	rd->per = per5;
	rd->replanned = true;
	plc5_timer_learn(h, station, s, PCCC_TCR5_BYTES);
	df1_clear_error(h);
	return true;
}

/* The next packet: 0F/68 for as many elements as fit. */
int plc5_read_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                  uint8_t *cmd, size_t cap)
{
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	int n;

	rd->k = s->count - rd->done < rd->per ? s->count - rd->done : rd->per;
	n = pccc_enc_plc5_typed_read(cmd, cap, &hd, (uint16_t)rd->done, (uint16_t)s->count, rd->addr,
	                             (size_t)rd->alen, (uint16_t)rd->k);
	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the read (%s)", df1_strerror(n));
	return n;
}

/* RTA's form of one string: 39 LEN characters -> the 84-byte element. */
static int plc5_take_string(struct df1 *h, int station, const char *what, struct io *io,
                            struct rd *rd, const struct pccc_typed *td)
{
	uint8_t el[84];
	char text[DF1_STRING_MAX + 1];
	int rc;

	memcpy(text, td->data, td->elem_size);
	text[td->elem_size] = '\0';
	if (value_put_string(el, text) < 0)
		return client_bad_reply(h, station, what, "bad string reply");
	put_le16(el, (uint16_t)td->elem_size);
	rc = io_put(h, station, what, io, rd->done, el, sizeof el);
	if (rc < 0)
		return rc;
	rd->done += rd->k;
	return 0;
}

/* The reply's element size and count against what was asked: fewer than asked
 * only as a full reply of larger elements (5-word timers); then the next
 * packets ask for what such a reply holds. */
static int plc5_take_size(struct df1 *h, int station, const char *what, const struct span *s,
                          struct rd *rd, const struct pccc_typed *td)
{
	if (td->elem_size != s->esize && !(plc5_whole_tcr(s) && td->elem_size == PCCC_TCR5_BYTES))
		return client_bad_reply(h, station, what,
		                plc5_whole_tcr(s) ? "reply elements have %u bytes, expected %zu or %d"
		                                  : "reply elements have %u bytes, expected %zu",
		                (unsigned)td->elem_size, s->esize, PCCC_TCR5_BYTES);
	if (td->count != rd->k) {
		size_t full = plc5_reply_full((size_t)rd->alen, td);

		if (td->count == 0 || td->count > rd->k || td->elem_size == s->esize || td->count != full)
			return client_bad_reply(h, station, what, "reply has %zu elements, asked %zu",
			                        td->count, rd->k);
		rd->k = td->count;
	}
	if (td->elem_size != s->esize) {
		size_t full = plc5_reply_full((size_t)rd->alen, td);

		if (full > 0 && full < rd->per)
			rd->per = full;
	}
	return 0;
}

/* Its reply's data: a type/data parameter and the elements it describes. */
int plc5_read_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                   struct rd *rd, const uint8_t *d, size_t dlen)
{
	struct pccc_typed td;
	int rc = pccc_dec_typed(d, dlen, &td);

	if (rc < 0)
		return client_bad_reply(h, station, what, "bad type/data parameter (%s)", df1_strerror(rc));
	if (!plc5_type_ok(s, td.type_id))
		return client_bad_reply(h, station, what, "reply holds type %u, asked type %u", td.type_id, plc5_elem_type(s));
	if (s->a.type == DF1_FT_ST && s->esize == 84 && td.elem_size != 84 && !td.is_array &&
	    rd->k == 1 && td.elem_size <= DF1_STRING_MAX)
		return plc5_take_string(h, station, what, io, rd, &td);
	rc = plc5_take_size(h, station, what, s, rd, &td);
	if (rc < 0)
		return rc;
	plc5_timer_learn(h, station, s, td.elem_size);
	for (size_t i = 0; i < rd->k; i++) {
		rc = io_put(h, station, what, io, rd->done + i, td.data + i * td.elem_size, s->esize);
		if (rc < 0)
			return rc;
	}
	rd->done += rd->k;
	return 0;
}

/* PLC-5 strings go one per packet as a string type/data parameter (3x LEN) and the
 * characters in text order, as RTA does (doc/PROTOCOL.md 5); PKT_OFFSET counts strings. */
static int plc5_write_strings(struct df1 *h, int station, const char *what, const struct span *s,
                              struct io *io, const uint8_t *addr, size_t alen)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], typed[FRAME_MAX_DATA], el[84];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };

	for (size_t i = 0; i < s->count; i++) {
		const uint8_t *d;
		size_t len, dlen;
		int n, rc;

		rc = io_get(io, i, el, sizeof el);
		if (rc < 0)
			return client_fail(h, rc, station, what, "value %zu: %s", io->base + i,
			                df1_strerror(rc));
		len = le16(el);
		n = pccc_enc_typedata(typed, sizeof typed, PCCC_TD_STRING, (uint32_t)len);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the type/data parameter");
		for (size_t c = 0; c < len; c++)
			typed[(size_t)n + c] = el[2 + (c ^ 1u)];
		n = pccc_enc_plc5_typed_write(cmd, sizeof cmd, &hd, (uint16_t)i, (uint16_t)s->count, addr,
		                              alen, typed, (size_t)n + len);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the write (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
	}
	return 0;
}

int plc5_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], addr[DF1_ADDR_ASCII_MAX + 8];
	uint8_t typed[FRAME_MAX_DATA];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	unsigned etype = plc5_elem_type(s);
	size_t per, done = 0;
	int alen = plc5_addr(h, station, what, &s->a, addr, sizeof addr);
	int r;

	if (alen < 0)
		return alen;
	if (s->a.type == DF1_FT_ST && s->esize == 84)
		return plc5_write_strings(h, station, what, s, io, addr, (size_t)alen);
	/* address + type/data (99 09 LL + descriptor) + data <= 240 (plc_limits.h) */
	per = plc_per_packet(DF1_PLC_PLC5, true, s->a.type, s->esize, (size_t)alen, h->cfg.max_packet);
	if (per == 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "a %zu-byte element exceeds the packet size", s->esize);
	while (done < s->count) {
		size_t k = s->count - done < per ? s->count - done : per, dlen;
		const uint8_t *d;
		int n, rc;

		r = pccc_enc_typed_array(typed, sizeof typed, etype, (uint32_t)s->esize, k);
		if (r < 0)
			return client_fail(h, DF1_E_NOTSUP, station, what, "cannot encode the type/data parameter");
		rc = io_gather(h, station, what, io, done, k, typed + r, s->esize);
		if (rc < 0)
			return rc;
		n = pccc_enc_plc5_typed_write(cmd, sizeof cmd, &hd, (uint16_t)done, (uint16_t)s->count,
		                              addr, (size_t)alen, typed, (size_t)r + k * s->esize);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the write (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
		done += k;
	}
	return 0;
}
