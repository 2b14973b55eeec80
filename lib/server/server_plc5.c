/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server_plc5.c - the responder's PLC-5 commands (doc/PROTOCOL.md 4.2-4.4):
 * 0F/68 typed read, 0F/67 typed write, 0F/01 and 0F/00 word range read and
 * write, 0F/26 read-modify-write and 0F/02 bit write; the file type of a
 * binary address comes from the data table (its probe, server.h).
 *
 * Where the spec flags a doubt (doc/PROTOCOL.md 8):
 *  - typed read/write floats: plain LE, or word-swapped [2,3,0,1] when the
 *    handle serves a PLC-5 with DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED (doc/PROTOCOL.md 5);
 *    word range 0F/00/01 always word-swaps them;
 *  - typed-read timers: 3 words, or 5 (59 0A, words 3-4 zero) with
 *    DF1_OPT_PLC5_TIMER_WORDS 5 (KF2 p.130, doc/PROTOCOL.md 8 item 8); typed writes take
 *    3- and 5-word T/C/R elements either way (words 3-4 ignored).
 */
#include "server/server_int.h"

#include <string.h>

/* ------------------------------------------------------------------------
 * Word ranges (0F/00, 0F/01)
 * ------------------------------------------------------------------------ */

/* Words of a file as a PLC-5 word range command sees them: F files word-swapped
 * (doc/PROTOCOL.md 5: 1.5 goes as C0 3F 00 00), everything else as stored. */
static int read_words(struct srv *s, enum df1_file_type t, int file, size_t off, uint8_t *out, size_t n)
{
	uint8_t tmp[2 * FRAME_MAX_DATA];
	size_t c0, c1;
	int rc;

	if (t != DF1_FT_F)
		return srv_tbl_read(s, t, file, off, out, n);
	c0 = off & ~(size_t)3;
	c1 = (off + n + 3) & ~(size_t)3;
	if (c1 - c0 > sizeof tmp)
		return 0x09;
	rc = srv_tbl_read(s, t, file, c0, tmp, c1 - c0);
	if (rc)
		return rc;
	for (size_t i = 0; i < n; i += 2) {
		size_t src = ((off + i) ^ 2) - c0;

		out[i] = tmp[src];
		out[i + 1] = tmp[src + 1];
	}
	return 0;
}

static int write_words(struct srv *s, enum df1_file_type t, int file, size_t off, const uint8_t *in, size_t n)
{
	uint8_t tmp[2 * FRAME_MAX_DATA], mask[2 * FRAME_MAX_DATA];
	size_t c0, c1;

	if (t != DF1_FT_F)
		return srv_tbl_write(s, t, file, off, in, NULL, n);
	c0 = off & ~(size_t)3;
	c1 = (off + n + 3) & ~(size_t)3;
	if (c1 - c0 > sizeof tmp)
		return 0x09;
	memset(tmp, 0, c1 - c0);
	memset(mask, 0, c1 - c0);
	for (size_t i = 0; i < n; i += 2) {
		size_t dst = ((off + i) ^ 2) - c0;

		tmp[dst] = in[i];
		tmp[dst + 1] = in[i + 1];
		mask[dst] = mask[dst + 1] = 0xFF;
	}
	return srv_tbl_write(s, t, file, c0, tmp, mask, c1 - c0);
}

/* ------------------------------------------------------------------------
 * PLC-5 addresses: the file type of a binary address comes from the data table
 * ------------------------------------------------------------------------ */

static int resolve_type(struct srv *s, struct df1_addr *a)
{
	static const enum df1_file_type defaults[9] = {
		DF1_FT_O, DF1_FT_I, DF1_FT_S, DF1_FT_B, DF1_FT_T, DF1_FT_C, DF1_FT_R, DF1_FT_N, DF1_FT_F,
	};
	static const enum df1_file_type order[] = {
		DF1_FT_N, DF1_FT_F, DF1_FT_B, DF1_FT_T, DF1_FT_C, DF1_FT_R, DF1_FT_ST,
		DF1_FT_A, DF1_FT_L, DF1_FT_S, DF1_FT_I, DF1_FT_O,
	};
	int first = 0, rc;

	if (a->type != DF1_FT_NONE)
		return srv_tbl_probe(s, a->type, a->file);
	if (a->file >= 0 && a->file <= 8) {
		rc = srv_tbl_probe(s, defaults[a->file], a->file);
		if (rc == 0) {
			a->type = defaults[a->file];
			return 0;
		}
		first = rc;
	}
	for (size_t i = 0; i < sizeof order / sizeof order[0]; i++) {
		if (a->file >= 0 && a->file <= 8 && order[i] == defaults[a->file])
			continue;
		rc = srv_tbl_probe(s, order[i], a->file);
		if (rc == 0) {
			a->type = order[i];
			return 0;
		}
		if (!first)
			first = rc;
	}
	return first ? first : 0x06;
}

/* Decoding failures of a PLC-5 request. */
static int plc5_req_fail(struct srv *s, int rc)
{
	if (rc == DF1_E_ADDR_SYNTAX)
		return srv_fail_ext(s, 0x02);      /* fewer levels than any address needs */
	if (rc == DF1_E_ADDR_RANGE)
		return srv_fail_ext(s, 0x03);      /* more levels than supported / other area */
	return srv_fail_sts(s, 0x10);
}

/* A decoded PLC-5 address -> one the data table holds (type resolved). */
static int plc5_addr_check(struct srv *s, struct df1_addr *a)
{
	int rc;

	if (a->ascii[0] && (a->type == DF1_FT_NONE || a->file < 0 || a->element < 0))
		return srv_fail_ext(s, 0x05);      /* symbol is of improper format */
	if (a->file < 0 || a->element < 0)
		return srv_fail_ext(s, 0x06);
	rc = resolve_type(s, a);
	if (rc)
		return srv_fail_rc(s, rc);
	return 0;
}

/* The typed-data element of an address: a sub-element (T4:0.ACC) is an integer
 * word; T/C/R elements go whole as their 3 data-table words. */
static void typed_layout(const struct df1_addr *a, unsigned *td, size_t *es)
{
	*td = PCCC_TD_INTEGER;
	*es = 2;
	if (a->sub != DF1_ADDR_NONE)
		return;
	switch (a->type) {
	case DF1_FT_L: *es = 4; break;
	case DF1_FT_F: *td = PCCC_TD_FLOAT; *es = 4; break;
	case DF1_FT_T: *td = PCCC_TD_TIMER; *es = 6; break;
	case DF1_FT_C: *td = PCCC_TD_COUNTER; *es = 6; break;
	case DF1_FT_R: *td = PCCC_TD_CONTROL; *es = 6; break;
	case DF1_FT_ST: *td = PCCC_TD_STRING; *es = 84; break;
	default: break;
	}
}

/* Typed read/write floats word-swapped? Plain LE by default (doc/PROTOCOL.md 5); a handle
 * serving a PLC-5 with DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED swaps them (doc/PROTOCOL.md 8 item 7). */
static bool typed_float_swapped(const struct srv *s, unsigned td)
{
	return td == PCCC_TD_FLOAT && s->h &&
	       value_typed_float_order(s->h->cfg.plc, s->h->cfg.plc5_float_swapped) ==
	               VALUE_FLOAT_WORD_SWAPPED;
}

/* Swap the 16-bit words of each 4-byte float: stored LE <-> [2,3,0,1]. */
static void swap_float_words(uint8_t *p, size_t n)
{
	for (size_t i = 0; i + 4 <= n; i += 4) {
		uint8_t a = p[i], b = p[i + 1];

		p[i] = p[i + 2];
		p[i + 1] = p[i + 3];
		p[i + 2] = a;
		p[i + 3] = b;
	}
}

/* ------------------------------------------------------------------------
 * PLC-5 commands (doc/PROTOCOL.md 4.2-4.4)
 * ------------------------------------------------------------------------ */

/* Bytes of an element on the wire in a typed reply: a timer of a PLC-5 served with
 * DF1_OPT_PLC5_TIMER_WORDS 5 goes as 5 words (59 0A, KF2 p.130), else as stored. */
static size_t typed_wire_size(const struct srv *s, unsigned td, size_t es)
{
	if (td == PCCC_TD_TIMER && es == PCCC_TCR_BYTES && s->h && s->h->cfg.plc == DF1_PLC_PLC5 &&
	    s->h->cfg.plc5_timer_words == 5)
		return PCCC_TCR5_BYTES;
	return es;
}

/* A typed read of an ST element at byte `off` of file `file`: one string per
 * packet, as `39 LEN chars` (RTA); the requester asks for the next one with
 * PKT_OFFSET. */
static int typed_read_string(struct srv *s, int file, size_t off)
{
	uint8_t el[84];
	unsigned len;
	int rc, hl;

	rc = srv_tbl_read(s, DF1_FT_ST, file, off, el, sizeof el);
	if (rc)
		return srv_fail_rc(s, rc);
	len = le16(el);
	if (len > DF1_STRING_MAX)
		len = DF1_STRING_MAX;
	hl = pccc_enc_typedata(s->data, sizeof s->data, PCCC_TD_STRING, len);
	if (hl < 0)
		return srv_fail_sts(s, 0x10);
	for (unsigned i = 0; i < len; i++)
		s->data[(size_t)hl + i] = el[2 + (i ^ 1u)];
	s->len = (size_t)hl + len;
	return 0;
}

int srv_plc5_typed_read(struct srv *s)
{
	struct pccc_plc5_req r;
	unsigned td;
	size_t es, wes, base, count, off;
	int rc, hl;

	rc = pccc_dec_plc5_req(PCCC_FNC_TYPED_READ, s->m->data, s->m->len, &r);
	if (rc < 0)
		return plc5_req_fail(s, rc);
	if (r.len != 0 || r.size <= 0 || (unsigned)r.pkt_offset + (unsigned)r.size > r.total)
		return srv_fail_sts(s, 0x10);
	if (plc5_addr_check(s, &r.addr))
		return -1;
	typed_layout(&r.addr, &td, &es);
	base = srv_addr_off(&r.addr);
	if (td == PCCC_TD_STRING)
		return typed_read_string(s, r.addr.file, base + (size_t)r.pkt_offset * 84);
	/* as many whole elements as one reply holds: the command's address + the
	 * reply's type/data + data <= 240 (doc/PROTOCOL.md 6, plc_limits.h); the address is
	 * what the command holds between TOTAL_TRANS and SIZE */
	wes = typed_wire_size(s, td, es);
	count = plc5_typed_per_packet(s->m->len - 6, td, wes);
	/* asked more than fits: a controller that does not cut says "too large" */
	if ((size_t)r.size > count && s->h && s->h->cfg.plc5_refuse_large)
		return srv_fail_ext(s, 0x09);
	if ((size_t)r.size < count)
		count = (size_t)r.size;
	hl = pccc_enc_typed_array(s->data, sizeof s->data, td, (uint32_t)wes, count);
	if (hl < 0)
		return srv_fail_sts(s, 0x10);
	off = base + (size_t)r.pkt_offset * es;
	rc = srv_tbl_read(s, r.addr.type, r.addr.file, off, s->data + hl, count * es);
	if (rc)
		return srv_fail_rc(s, rc);
	if (typed_float_swapped(s, td))
		swap_float_words(s->data + hl, count * es);
	if (wes != es) {
		/* 5-word timers: the 3 data-table words, then two zero words; from the
		 * last element back, so that nothing is overwritten before it moves */
		for (size_t i = count; i-- > 0;) {
			memmove(s->data + hl + i * wes, s->data + hl + i * es, es);
			memset(s->data + hl + i * wes + es, 0, wes - es);
		}
	}
	s->len = (size_t)hl + count * wes;
	return 0;
}

static bool typed_matches(unsigned want, size_t es, const struct pccc_typed *t)
{
	if (want == PCCC_TD_STRING)
		return t->type_id == PCCC_TD_STRING && !t->is_array && t->elem_size <= DF1_STRING_MAX;
	if (t->type_id == want && es == PCCC_TCR_BYTES && t->elem_size == PCCC_TCR5_BYTES &&
	    (want == PCCC_TD_TIMER || want == PCCC_TD_COUNTER || want == PCCC_TD_CONTROL))
		return true;    /* the 5-word form: words 0-2 are kept, the rest ignored */
	if (t->elem_size != es)
		return false;
	if (t->type_id == want)
		return true;
	/* a bit string of one word fits an integer word (B files) */
	return want == PCCC_TD_INTEGER && es == 2 && t->type_id == PCCC_TD_BITSTR;
}

/* A typed write of one string into the ST element at byte `off` of file
 * `file`: LEN, then the characters byte-swapped per word (server.h). */
static int typed_write_string(struct srv *s, int file, size_t off, const struct pccc_typed *t)
{
	uint8_t el[84];

	memset(el, 0, sizeof el);
	put_le16(el, (uint16_t)t->elem_size);
	for (size_t i = 0; i < t->elem_size; i++)
		el[2 + (i ^ 1u)] = t->data[i];
	return srv_tbl_write(s, DF1_FT_ST, file, off, el, NULL, sizeof el);
}

int srv_plc5_typed_write(struct srv *s)
{
	struct pccc_plc5_req r;
	struct pccc_typed t;
	unsigned td;
	size_t es, base;
	int rc;

	rc = pccc_dec_plc5_req(PCCC_FNC_TYPED_WRITE, s->m->data, s->m->len, &r);
	if (rc < 0)
		return plc5_req_fail(s, rc);
	rc = pccc_dec_typed(r.data, r.len, &t);
	if (rc < 0 || t.consumed != r.len || t.count == 0)
		return srv_fail_sts(s, 0x10);
	if ((unsigned)r.pkt_offset + (unsigned)t.count > r.total)
		return srv_fail_sts(s, 0x10);
	if (plc5_addr_check(s, &r.addr))
		return -1;
	typed_layout(&r.addr, &td, &es);
	if (!typed_matches(td, es, &t))
		return srv_fail_ext(s, 0x11);      /* the data type must match the file (M p.117) */
	base = srv_addr_off(&r.addr);
	if (td == PCCC_TD_STRING) {
		rc = typed_write_string(s, r.addr.file, base + (size_t)r.pkt_offset * 84, &t);
	} else if (typed_float_swapped(s, td)) {
		uint8_t buf[FRAME_MAX_DATA];

		if (t.count * es > sizeof buf)
			return srv_fail_sts(s, 0x10);
		memcpy(buf, t.data, t.count * es);
		swap_float_words(buf, t.count * es);
		rc = srv_tbl_write(s, r.addr.type, r.addr.file, base + (size_t)r.pkt_offset * es, buf, NULL,
		               t.count * es);
	} else if (t.elem_size != es) {
		uint8_t buf[FRAME_MAX_DATA];

		/* 5-word T/C/R elements: their first 3 words */
		if (t.count * es > sizeof buf)
			return srv_fail_sts(s, 0x10);
		for (size_t i = 0; i < t.count; i++)
			memcpy(buf + i * es, t.data + i * t.elem_size, es);
		rc = srv_tbl_write(s, r.addr.type, r.addr.file, base + (size_t)r.pkt_offset * es, buf, NULL,
		               t.count * es);
	} else {
		rc = srv_tbl_write(s, r.addr.type, r.addr.file, base + (size_t)r.pkt_offset * es, t.data, NULL,
		               t.count * es);
	}
	if (rc)
		return srv_fail_rc(s, rc);
	return 0;
}

int srv_plc5_word_read(struct srv *s)
{
	struct pccc_plc5_req r;
	size_t off;
	int rc;

	rc = pccc_dec_plc5_req(PCCC_FNC_WORD_READ, s->m->data, s->m->len, &r);
	if (rc < 0)
		return plc5_req_fail(s, rc);
	if (r.len != 0 || r.size <= 0 || (r.size & 1))
		return srv_fail_sts(s, 0x10);
	if ((unsigned)r.pkt_offset + (unsigned)r.size / 2 > r.total)
		return srv_fail_sts(s, 0x10);
	if (r.size > SERVER_WORD_READ_MAX)
		return srv_fail_ext(s, 0x09);
	if (plc5_addr_check(s, &r.addr))
		return -1;
	off = srv_addr_off(&r.addr) + (size_t)r.pkt_offset * 2;
	rc = read_words(s, r.addr.type, r.addr.file, off, s->data, (size_t)r.size);
	if (rc)
		return srv_fail_rc(s, rc);
	s->len = (size_t)r.size;
	return 0;
}

int srv_plc5_word_write(struct srv *s)
{
	struct pccc_plc5_req r;
	size_t off;
	int rc;

	rc = pccc_dec_plc5_req(PCCC_FNC_WORD_WRITE, s->m->data, s->m->len, &r);
	if (rc < 0)
		return plc5_req_fail(s, rc);
	if (r.len == 0 || (r.len & 1) || (unsigned)r.pkt_offset + r.len / 2 > r.total)
		return srv_fail_sts(s, 0x10);
	if (plc5_addr_check(s, &r.addr))
		return -1;
	off = srv_addr_off(&r.addr) + (size_t)r.pkt_offset * 2;
	rc = write_words(s, r.addr.type, r.addr.file, off, r.data, r.len);
	if (rc)
		return srv_fail_rc(s, rc);
	return 0;
}

/* 0F/26 read-modify-write { ADDR AND OR }... and 0F/02 bit write { ADDR SET RESET }...:
 * one word each. The whole body is checked before the first word changes. */
int srv_plc5_word_masks(struct srv *s, bool rmw)
{
	const uint8_t *d = s->m->data;
	size_t n = s->m->len, pos = 0;
	struct df1_addr a;
	int k, rc;

	if (n == 0)
		return srv_fail_sts(s, 0x10);
	while (pos < n) {
		k = pccc_dec_plc5_addr(d + pos, n - pos, &a);
		if (k < 0)
			return plc5_req_fail(s, k);
		pos += (size_t)k;
		if (n - pos < 4)
			return srv_fail_sts(s, 0x10);
		pos += 4;
	}
	for (pos = 0; pos < n; pos += 4) {
		uint16_t v1, v2, mask, val;
		uint8_t b[2], mb[2];

		k = pccc_dec_plc5_addr(d + pos, n - pos, &a);
		pos += (size_t)k;
		v1 = le16(d + pos);
		v2 = le16(d + pos + 2);
		if (plc5_addr_check(s, &a))
			return -1;
		if (a.type == DF1_FT_F && a.sub == DF1_ADDR_NONE)
			return srv_fail_ext(s, 0x11);  /* not a word of bits */
		if (rmw) {                      /* new = (old AND and) OR or */
			mask = (uint16_t)(~v1 | v2);
			val = v2;
		} else {                        /* set bits, then reset bits */
			mask = (uint16_t)(v1 | v2);
			val = (uint16_t)(v1 & ~v2);
		}
		put_le16(b, val);
		put_le16(mb, mask);
		rc = srv_tbl_write(s, a.type, a.file, srv_addr_off(&a), b, mb, 2);
		if (rc)
			return srv_fail_rc(s, rc);
	}
	return 0;
}
