/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server - the responder: decoded PCCC command -> data-table callbacks ->
 * reply. See server.h for the data-table contract.
 *
 * Status rules (doc/PROTOCOL.md 3.2, 3.3):
 *  - a command this responder does not know, and no `command` callback: STS 10;
 *  - a malformed command (short or extra bytes, zero or odd sizes, counts past
 *    TOTAL_TRANS): STS 10;
 *  - CMD 0F / 06: STS F0 + EXT STS: 02/03 bad PLC-5 address levels, 05 a logical
 *    ASCII address that does not parse, 09 more data than one packet holds,
 *    11 a type/data parameter (or SLC file type code) that is not the file's type,
 *    and whatever the data table reports (06 no such file, 07 past the end ...);
 *  - PLC-2 commands (no EXT STS): STS 10 format, 80 no compatibility file
 *    (N9 / N7, server.h), 50 an address the data table refuses.
 *
 * Where the spec flags a doubt (8):
 *  - SLC O/I file type codes: 8B/8C and 82/83 are both taken, whatever
 *    DF1_OPT_SLC_IO_CODES_82 says (doc/PROTOCOL.md 4.11);
 *  - PLC-5 typed read/write floats: plain LE, or word-swapped [2,3,0,1] when the
 *    handle serves a PLC-5 with DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED (doc/PROTOCOL.md 5); word
 *    range 0F/00/01 always word-swaps them;
 *  - PLC-5 typed-read timers: 3 words, or 5 (59 0A, words 3-4 zero) with
 *    DF1_OPT_PLC5_TIMER_WORDS 5 (KF2 p.130, doc/PROTOCOL.md 8 item 8); typed writes take
 *    3- and 5-word T/C/R elements either way (words 3-4 ignored);
 *  - PLC-2 addresses: bytes, or words with DF1_OPT_PLC2_WORD_ADDR (doc/PROTOCOL.md 4.7;
 *    05/02 bit writes then STS 10: their blocks address bytes).
 */
#include "server/server.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "link/link.h"
#include "proto/pccc.h"
#include "proto/value.h"

struct srv {
	struct df1 *h;
	const struct df1_server_ops *ops;
	void *user;
	int station;
	const struct pccc_msg *m;
	uint8_t sts, ext;
	size_t len;
	uint8_t data[FRAME_MAX_DATA];   /* reply data; last: not cleared per command */
};

/* ------------------------------------------------------------------------
 * Status helpers: all return -1 so handlers can `return fail_...(s, ...)`.
 * ------------------------------------------------------------------------ */

static int srv_fail_sts(struct srv *s, uint8_t sts)
{
	s->sts = sts ? sts : 0x10;
	s->ext = 0;
	s->len = 0;
	return -1;
}

static int srv_fail_ext(struct srv *s, uint8_t ext)
{
	s->sts = 0xF0;
	s->ext = ext;
	s->len = 0;
	return -1;
}

/* A callback's result: > 0 EXT STS, < 0 -STS. */
static int srv_fail_rc(struct srv *s, int rc)
{
	if (rc > 0)
		return srv_fail_ext(s, (uint8_t)(rc & 0xFF) ? (uint8_t)(rc & 0xFF) : 0x14);
	return srv_fail_sts(s, (uint8_t)((-rc) & 0xFF));
}

/* PLC-2 commands have no EXT STS: a refused address is STS 50. */
static int srv_fail_plc2(struct srv *s, int rc)
{
	if (rc > 0)
		return srv_fail_sts(s, 0x50);
	return srv_fail_sts(s, (uint8_t)((-rc) & 0xFF));
}

/* ------------------------------------------------------------------------
 * Data-table access by byte offset inside a file
 * ------------------------------------------------------------------------ */

static size_t elem_size(enum df1_file_type t)
{
	int es = df1_file_type_element_size(t);

	return es > 0 ? (size_t)es : 2;
}

/* The address of byte `off` (even) of file `file` of type t. */
static void addr_at(struct df1_addr *a, enum df1_file_type t, int file, size_t off)
{
	size_t es = elem_size(t), rem = off % es;

	memset(a, 0, sizeof *a);
	a->type = t;
	a->file = file;
	a->element = (int)(off / es);
	a->sub = rem ? (int)(rem / 2) : DF1_ADDR_NONE;
	a->bit = DF1_ADDR_NONE;
}

/* Byte offset of an address (element + sub-element word) in its file. */
static size_t addr_off(const struct df1_addr *a)
{
	size_t off = (size_t)a->element * elem_size(a->type);

	if (a->sub != DF1_ADDR_NONE && a->sub > 0)
		off += (size_t)a->sub * 2;
	return off;
}

static int srv_tbl_read(struct srv *s, enum df1_file_type t, int file, size_t off, uint8_t *buf, size_t n)
{
	struct df1_addr a;

	if (!s->ops->read)
		return 0x0E;    /* command cannot be executed */
	addr_at(&a, t, file, off);
	return s->ops->read(s->user, s->station, &a, buf, n);
}

static int srv_tbl_write(struct srv *s, enum df1_file_type t, int file, size_t off, const uint8_t *buf,
                     const uint8_t *mask, size_t n)
{
	struct df1_addr a;

	if (!s->ops->write)
		return 0x0E;
	addr_at(&a, t, file, off);
	return s->ops->write(s->user, s->station, &a, buf, mask, n);
}

/* Does file `file` exist with type t? 0 or the data table's EXT STS. */
static int srv_tbl_probe(struct srv *s, enum df1_file_type t, int file)
{
	uint8_t dummy = 0;

	return srv_tbl_read(s, t, file, 0, &dummy, 0);
}

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

static int srv_typed_read(struct srv *s)
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
	base = addr_off(&r.addr);
	if (td == PCCC_TD_STRING) {
		/* one string per packet, as `39 LEN chars` (RTA); the requester asks
		 * for the next one with PKT_OFFSET */
		uint8_t el[84];
		unsigned len;

		rc = srv_tbl_read(s, DF1_FT_ST, r.addr.file, base + (size_t)r.pkt_offset * 84, el, sizeof el);
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
	/* as many whole elements as one reply holds: the command's address + the
	 * reply's type/data + data <= 240 (doc/PROTOCOL.md 6, plc_limits.h); the address is
	 * what the command holds between TOTAL_TRANS and SIZE */
	wes = typed_wire_size(s, td, es);
	count = plc5_typed_per_packet(s->m->len - 6, td, wes);
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

static int srv_typed_write(struct srv *s)
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
	base = addr_off(&r.addr);
	if (td == PCCC_TD_STRING) {
		uint8_t el[84];

		memset(el, 0, sizeof el);
		put_le16(el, (uint16_t)t.elem_size);
		for (size_t i = 0; i < t.elem_size; i++)
			el[2 + (i ^ 1u)] = t.data[i];
		rc = srv_tbl_write(s, DF1_FT_ST, r.addr.file, base + (size_t)r.pkt_offset * 84, el, NULL, sizeof el);
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

static int srv_word_read(struct srv *s)
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
	off = addr_off(&r.addr) + (size_t)r.pkt_offset * 2;
	rc = read_words(s, r.addr.type, r.addr.file, off, s->data, (size_t)r.size);
	if (rc)
		return srv_fail_rc(s, rc);
	s->len = (size_t)r.size;
	return 0;
}

static int srv_word_write(struct srv *s)
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
	off = addr_off(&r.addr) + (size_t)r.pkt_offset * 2;
	rc = write_words(s, r.addr.type, r.addr.file, off, r.data, r.len);
	if (rc)
		return srv_fail_rc(s, rc);
	return 0;
}

/* 0F/26 read-modify-write { ADDR AND OR }... and 0F/02 bit write { ADDR SET RESET }...:
 * one word each. The whole body is checked before the first word changes. */
static int srv_word_masks(struct srv *s, bool rmw)
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
		rc = srv_tbl_write(s, a.type, a.file, addr_off(&a), b, mb, 2);
		if (rc)
			return srv_fail_rc(s, rc);
	}
	return 0;
}

/* ------------------------------------------------------------------------
 * SLC commands (doc/PROTOCOL.md 4.5, 4.6)
 * ------------------------------------------------------------------------ */

static int srv_slc(struct srv *s, uint8_t fnc)
{
	bool three = fnc == PCCC_FNC_SLC_READ3 || fnc == PCCC_FNC_SLC_WRITE3 || fnc == PCCC_FNC_SLC_MASKED;
	bool rd = fnc == PCCC_FNC_SLC_READ2 || fnc == PCCC_FNC_SLC_READ3;
	bool masked = fnc == PCCC_FNC_SLC_MASKED;
	unsigned file, elem, sub;
	uint8_t nb, tc;
	enum df1_file_type t;
	const uint8_t *d;
	size_t rest, limit, off;
	int k, rc;

	k = pccc_dec_slc_fields(s->m->data, s->m->len, three, &nb, &file, &tc, &elem, &sub);
	if (k < 0 || nb == 0)
		return srv_fail_sts(s, 0x10);
	d = s->m->data + k;
	rest = s->m->len - (size_t)k;
	/* AB with one mask word for every word of the data (pycomm3 and NPC send
	 * it so for F, L and ST elements: doc/PROTOCOL.md 4.6) or a mask as long as the data */
	bool mask_word = masked && nb > 2 && !(nb & 1) && rest == 2u + nb;
	if (rest != (rd ? 0u : masked ? 2u * nb : nb) && !mask_word)
		return srv_fail_sts(s, 0x10);
	t = pccc_slc_code_file_type(tc);       /* O: 8B or 82, I: 8C or 83 (doc/PROTOCOL.md 4.11) */
	if (t == DF1_FT_NONE)
		return srv_fail_ext(s, 0x11);
	if (s->h && s->h->cfg.plc == DF1_PLC_SLC502)
		limit = PLC_SLC502_MAX;
	else
		limit = rd ? PLC_SLC_READ_MAX : PLC_SLC_WRITE_MAX;
	if (nb > limit)
		return srv_fail_ext(s, 0x09);
	off = (size_t)elem * elem_size(t) + (size_t)sub * 2;
	if (rd)
		rc = srv_tbl_read(s, t, (int)file, off, s->data, nb);
	else if (mask_word) {
		uint8_t mask[255];

		for (size_t i = 0; i < nb; i++)
			mask[i] = d[i & 1];
		rc = srv_tbl_write(s, t, (int)file, off, d + 2, mask, nb);
	} else if (masked)
		rc = srv_tbl_write(s, t, (int)file, off, d + nb, d, nb);
	else
		rc = srv_tbl_write(s, t, (int)file, off, d, NULL, nb);
	if (rc)
		return srv_fail_rc(s, rc);
	s->len = rd ? nb : 0;
	return 0;
}

/* ------------------------------------------------------------------------
 * PLC-2 commands (doc/PROTOCOL.md 4.7): a byte address in the compatibility file
 * ------------------------------------------------------------------------ */

static int plc2_file(const struct srv *s)
{
	if (s->h && s->h->cfg.plc == DF1_PLC_MICROLOGIX)
		return SERVER_PLC2_FILE_MICROLOGIX;
	if (s->h && s->h->cfg.plc == DF1_PLC_PLC5)
		return SERVER_PLC2_FILE_PLC5;
	return SERVER_PLC2_FILE_SLC;
}

static int srv_plc2(struct srv *s)
{
	const uint8_t *d = s->m->data;
	size_t n = s->m->len;
	int file = plc2_file(s), rc;
	/* DF1_OPT_PLC2_WORD_ADDR: the address is a word offset (an SLC common
	 * interface file with S:2/8 = 0, doc/PROTOCOL.md 4.7); else a byte address, even */
	bool words = s->h && s->h->cfg.plc2_word_addr;
	unsigned odd = words ? 0u : 1u;
	size_t addr;

	switch (s->m->cmd) {
	case PCCC_CMD_UNPROT_READ:
		if (n != 3 || (d[0] & odd) || d[2] == 0 || (d[2] & 1) || d[2] > PLC_PLC2_MAX)
			return srv_fail_sts(s, 0x10);
		break;
	case PCCC_CMD_UNPROT_WRITE: case PCCC_CMD_PROT_WRITE:
		if (n < 3 || (d[0] & odd) || n - 2 > PLC_PLC2_MAX)
			return srv_fail_sts(s, 0x10);
		break;
	default:        /* 05, 02: blocks of ADDR(2) SET(1) RESET(1), up to 60; bytes only */
		if (words || n == 0 || n % 4 || n / 4 > 60)
			return srv_fail_sts(s, 0x10);
		break;
	}
	if (srv_tbl_probe(s, DF1_FT_N, file))
		return srv_fail_sts(s, 0x80);      /* compatibility mode file missing */
	switch (s->m->cmd) {
	case PCCC_CMD_UNPROT_READ:
		addr = (size_t)le16(d) * (words ? 2u : 1u);
		rc = srv_tbl_read(s, DF1_FT_N, file, addr, s->data, d[2]);
		if (rc)
			return srv_fail_plc2(s, rc);
		s->len = d[2];
		return 0;
	case PCCC_CMD_UNPROT_WRITE: case PCCC_CMD_PROT_WRITE:
		addr = (size_t)le16(d) * (words ? 2u : 1u);
		rc = srv_tbl_write(s, DF1_FT_N, file, addr, d + 2, NULL, n - 2);
		return rc ? srv_fail_plc2(s, rc) : 0;
	default:
		for (size_t i = 0; i < n; i += 4) {
			uint8_t b[2] = { 0, 0 }, mb[2] = { 0, 0 };
			unsigned idx;

			addr = le16(d + i);
			idx = (unsigned)(addr & 1u);
			mb[idx] = (uint8_t)(d[i + 2] | d[i + 3]);
			b[idx] = (uint8_t)(d[i + 2] & ~d[i + 3]);
			rc = srv_tbl_write(s, DF1_FT_N, file, addr & ~(size_t)1, b, mb, 2);
			if (rc)
				return srv_fail_plc2(s, rc);
		}
		return 0;
	}
}

/* ------------------------------------------------------------------------
 * Diagnostics, modes, anything else
 * ------------------------------------------------------------------------ */

int server_default_diag(uint8_t *buf, size_t cap)
{
	/* an SLC 5/04 series C release 5 (44h) in Run mode, 16 KB of RAM, no owner */
	static const struct pccc_diag_info slc504 = {
		.type_code = 0x5B, .interface_type = 0x1F, .series_rev = 0x44,
		.bulletin = "5/04", .mode = 0x06, .ram_kb = 0x10, .owner = 0x3F,
	};

	if (!buf)
		return DF1_E_NOSPACE;
	return pccc_enc_diag_reply(buf, cap, &slc504);
}

static int apply_mode(struct srv *s, int mode)
{
	int rc;

	if (s->ops->change_mode) {
		rc = s->ops->change_mode(s->user, s->station, mode);
		return rc ? srv_fail_rc(s, rc) : 0;
	}
	if (mode != 1 && mode != 6 && mode != 7 && mode != 8)
		return srv_fail_ext(s, 0x01);      /* a field has an illegal value */
	return 0;
}

static int srv_other(struct srv *s, const uint8_t *cmd)
{
	struct df1_msg dm;
	int rc;

	if (!s->ops->command)
		return srv_fail_sts(s, 0x10);
	memset(&dm, 0, sizeof dm);
	dm.dst = s->m->dst;
	dm.src = s->m->src;
	dm.cmd = s->m->cmd;
	dm.sts = s->m->sts;
	dm.fnc = s->m->fnc;
	dm.tns = s->m->tns;
	dm.has_fnc = s->m->has_fnc;
	dm.name = pccc_command_name(s->m->cmd, s->m->has_fnc, s->m->fnc);
	dm.size = -1;
	dm.data = s->m->data;
	dm.data_len = s->m->len;
	(void)cmd;
	rc = s->ops->command(s->user, s->station, &dm, s->data, SERVER_WORD_READ_MAX);
	if (rc < 0) {
		int v = -rc;

		s->sts = (uint8_t)(v & 0xFF) ? (uint8_t)(v & 0xFF) : 0x10;
		s->ext = (uint8_t)((v >> 8) & 0xFF);
		s->len = 0;
		return -1;
	}
	s->len = (size_t)rc > SERVER_WORD_READ_MAX ? SERVER_WORD_READ_MAX : (size_t)rc;
	return 0;
}

static void dispatch(struct srv *s, const uint8_t *cmd)
{
	const struct pccc_msg *m = s->m;
	int rc;

	switch (m->cmd) {
	case PCCC_CMD_UNPROT_READ: case PCCC_CMD_UNPROT_WRITE: case PCCC_CMD_PROT_WRITE:
	case PCCC_CMD_UNPROT_BIT_WRITE: case PCCC_CMD_PROT_BIT_WRITE:
		srv_plc2(s);
		return;
	case PCCC_CMD_DIAG:
		switch (m->fnc) {
		case PCCC_FNC_ECHO:
			if (m->len > PLC_ECHO_MAX) {
				srv_fail_sts(s, 0x10);
				return;
			}
			memcpy(s->data, m->data, m->len);
			s->len = m->len;
			return;
		case PCCC_FNC_DIAG_STATUS:
			if (s->ops->diag_status)
				rc = s->ops->diag_status(s->user, s->station, s->data, SERVER_WORD_READ_MAX);
			else
				rc = server_default_diag(s->data, SERVER_WORD_READ_MAX);
			if (rc < 0) {
				srv_fail_sts(s, (uint8_t)((-rc) & 0xFF));
				return;
			}
			s->len = (size_t)rc > SERVER_WORD_READ_MAX ? SERVER_WORD_READ_MAX : (size_t)rc;
			return;
		default:
			srv_other(s, cmd);
			return;
		}
	case PCCC_CMD_TYPED:
		switch (m->fnc) {
		case PCCC_FNC_SLC_READ2: case PCCC_FNC_SLC_READ3:
		case PCCC_FNC_SLC_WRITE2: case PCCC_FNC_SLC_WRITE3: case PCCC_FNC_SLC_MASKED:
			srv_slc(s, m->fnc);
			return;
		case PCCC_FNC_TYPED_READ:
			srv_typed_read(s);
			return;
		case PCCC_FNC_TYPED_WRITE:
			srv_typed_write(s);
			return;
		case PCCC_FNC_WORD_READ:
			srv_word_read(s);
			return;
		case PCCC_FNC_WORD_WRITE:
			srv_word_write(s);
			return;
		case PCCC_FNC_RMW:
			srv_word_masks(s, true);
			return;
		case PCCC_FNC_BIT_WRITE:
			srv_word_masks(s, false);
			return;
		case PCCC_FNC_CHANGE_MODE:
			if (m->len != 1) {
				srv_fail_sts(s, 0x10);
				return;
			}
			apply_mode(s, m->data[0]);
			return;
		case PCCC_FNC_SET_CPU_MODE: {
			/* bits 1-0: 0 program, 1 remote test, 2 run, 3 no change (M p.113) */
			static const int modes[4] = { 1, 7, 6, 0 };

			if (m->len != 1) {
				srv_fail_sts(s, 0x10);
				return;
			}
			if (modes[m->data[0] & 3])
				apply_mode(s, modes[m->data[0] & 3]);
			return;
		}
		default:
			srv_other(s, cmd);
			return;
		}
	default:
		srv_other(s, cmd);
		return;
	}
}

int server_handle(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap)
{
	static const struct df1_server_ops no_ops;
	struct server_ctx *c = ctx;
	struct pccc_msg m;
	struct srv *s;
	struct srv stack;
	int rc;

	if (!cmd || !reply)
		return DF1_E_INVAL;
	if (n < PCCC_HDR_LEN)
		return 0;                       /* nothing to answer to */
	rc = pccc_decode(cmd, n, &m);
	if (rc < 0) {
		/* a 06 / 0F command without its FNC: answer STS 10 */
		memset(&m, 0, sizeof m);
		m.dst = cmd[0];
		m.src = cmd[1];
		m.cmd = cmd[2];
		m.tns = le16(cmd + 4);
		return pccc_encode_reply(reply, cap, &m, 0x10, 0, NULL, 0);
	}
	if (m.is_reply)
		return 0;                       /* a reply is not ours to answer */
	s = &stack;
	memset(s, 0, offsetof(struct srv, data));
	s->h = h;
	s->ops = c && c->ops ? c->ops : &no_ops;
	s->user = c ? c->user : NULL;
	s->station = m.dst;
	s->m = &m;
	dispatch(s, cmd);
	if (s->sts == 0xF0 && !pccc_cmd_has_ext_sts(m.cmd))
		s->sts = 0x10;
	rc = pccc_encode_reply(reply, cap, &m, s->sts, s->ext, s->sts ? NULL : s->data, s->sts ? 0 : s->len);
	if (rc == DF1_E_NOSPACE && s->sts == 0)
		rc = pccc_encode_reply(reply, cap, &m, 0xF0, 0x09, NULL, 0);
	return rc;
}

/* ------------------------------------------------------------------------
 * The responder's state: the server's, lent to link_serve()
 * ------------------------------------------------------------------------ */

struct server_state {
	struct link_responder resp;  /* reply slots, faults, stations served */
};

static void server_free(struct df1 *h)
{
	free(h->srv);
	h->srv = NULL;
}

struct link_responder *server_responder(struct df1 *h)
{
	if (!h->srv) {
		h->srv = calloc(1, sizeof *h->srv);
		if (!h->srv)
			return NULL;
		h->srv_free = server_free;
	}
	return &h->srv->resp;
}
