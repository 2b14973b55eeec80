/* SPDX-License-Identifier: MPL-2.0 */
/*
 * elements.c - spans of elements dispatched to the PLC type's commands, bit
 * reads and masked bit writes, reads and writes of element values.
 */
#include "client/client_int.h"

static int span_check(struct df1 *h, int station, const char *what, const struct span *s)
{
	size_t last = (s->by_sub ? (size_t)s->a.sub : (size_t)s->a.element) + s->count - 1;

	if (s->count == 0 || s->count > 0xFFFF || last > 0xFFFF)
		return client_fail(h, DF1_E_ADDR_RANGE, station, what, "%zu elements go beyond the address range", s->count);
	return 0;
}

static int rd_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd)
{
	memset(rd, 0, sizeof *rd);
	switch (s->plc) {
	case DF1_PLC_PLC5:
		return plc5_read_begin(h, station, what, s, rd);
	case DF1_PLC_PLC2:
		return plc2_read_begin(h, station, what, s, rd);
	case DF1_PLC_PLC3:
		return plc3_read_begin(h, station, what, s, rd);
	default:
		return slc_read_begin(h, station, what, s, rd);
	}
}

static int rd_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                  uint8_t *cmd, size_t cap)
{
	switch (s->plc) {
	case DF1_PLC_PLC5:
		return plc5_read_cmd(h, station, what, s, rd, cmd, cap);
	case DF1_PLC_PLC2:
		return plc2_read_cmd(h, station, what, s, rd, cmd, cap);
	case DF1_PLC_PLC3:
		return plc3_read_cmd(h, station, what, s, rd, cmd, cap);
	default:
		return slc_read_cmd(h, station, what, s, rd, cmd, cap);
	}
}

static int rd_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                   struct rd *rd, const uint8_t *d, size_t dlen)
{
	switch (s->plc) {
	case DF1_PLC_PLC5:
		return plc5_read_take(h, station, what, s, io, rd, d, dlen);
	case DF1_PLC_PLC2:
		return plc2_read_take(h, station, what, s, io, rd, d, dlen);
	case DF1_PLC_PLC3:
		return plc3_read_take(h, station, what, s, io, rd, d, dlen);
	default:
		return slc_read_take(h, station, what, s, io, rd, d, dlen);
	}
}

/* A span read, packet by packet: each command built, sent, its reply taken.
 * first (NULL: none) says how the caller runs the first packet: RD_BUILD
 * returns its command's length there; RD_TAKE takes its outcome. */
static int span_read_first(struct df1 *h, int station, const char *what, const struct span *s,
                           struct io *io, const struct rd_first *first)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA];
	struct rd rd;
	int rc = span_check(h, station, what, s);

	if (rc < 0)
		return rc;
	rc = rd_begin(h, station, what, s, &rd);
	if (rc < 0)
		return rc;
	while (rd.done < s->count) {
		const uint8_t *d;
		size_t dlen;
		int n = rd_cmd(h, station, what, s, &rd, cmd, sizeof cmd);

		if (n < 0)
			return n;
		if (first && first->mode == RD_BUILD) {
			if ((size_t)n > first->cap)
				return client_fail(h, DF1_E_NOSPACE, station, what, "command of %d bytes", n);
			memcpy(first->cmd, cmd, (size_t)n);
			return n;
		}
		if (first)
			rc = client_reply(h, station, what, cmd, first->rc, first->reply, &d, &dlen);
		else
			rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		first = NULL;
		/* a PLC-5 that refuses a T/C/R packet planned at 3 words: again at 5 */
		if (rc < 0 && s->plc == DF1_PLC_PLC5 && plc5_read_refused(h, station, s, &rd))
			continue;
		if (rc < 0)
			return rc;
		rc = rd_take(h, station, what, s, io, &rd, d, dlen);
		if (rc < 0)
			return rc;
	}
	return 0;
}

static int span_read(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	return span_read_first(h, station, what, s, io, NULL);
}

static int span_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	int rc = span_check(h, station, what, s);

	if (rc < 0)
		return rc;
	switch (s->plc) {
	case DF1_PLC_PLC5:
		return plc5_write(h, station, what, s, io);
	case DF1_PLC_PLC2:
		return plc2_write(h, station, what, s, io);
	case DF1_PLC_PLC3:
		return plc3_write(h, station, what, s, io);
	default:
		return slc_write(h, station, what, s, io);
	}
}

/* ------------------------------------------------------------------------
 * Bits
 * ------------------------------------------------------------------------ */

/* The words that hold a run of bits: span of 16-bit (32 for L) words, first bit. */
static int bits_span(struct df1 *h, int station, const char *what, enum df1_plc plc,
                     const struct df1_addr *a, size_t n, struct span *s, unsigned *wbits)
{
	size_t bit = (size_t)a->bit;

	memset(s, 0, sizeof *s);
	s->plc = plc;
	if (a->type == DF1_FT_L) {
		*wbits = 32;
		s->esize = 4;
	} else if (client_is_word_type(a->type) || client_is_tcr(a->type)) {
		*wbits = 16;
		s->esize = 2;
	} else {
		return client_fail(h, DF1_E_TYPE, station, what, "no bits in this file type");
	}
	if (client_is_tcr(a->type)) {
		/* a T/C/R bit lives in one word of its element (word 0 unless given) */
		if (bit + n > 16)
			return client_fail(h, DF1_E_ADDR_RANGE, station, what, "%zu bits run past the word", n);
		client_derive(a, a->element, a->sub == DF1_ADDR_NONE ? 0 : a->sub, &s->a);
		s->count = 1;
		return 0;
	}
	s->by_sub = a->sub != DF1_ADDR_NONE;    /* I1:0.1/3: words of the slot */
	client_derive(a, a->element, a->sub, &s->a);
	s->count = (bit + n - 1) / *wbits + 1;
	return 0;
}

/* Bit sink: the words arrive through io_put as raw bytes; bits are picked afterwards. */
int client_read_bits(struct df1 *h, int station, const char *what, enum df1_plc plc,
                     const struct df1_addr *a, size_t n, bool *bits, struct df1_value *vals)
{
	uint8_t words[FRAME_MAX_DATA];
	struct span s;
	struct io io = { .kind = IO_RAW, .t = DF1_FT_N, .word = -1, .fo = VALUE_FLOAT_LE };
	unsigned wbits;
	size_t first = (size_t)a->bit, done = 0;
	int rc = bits_span(h, station, what, plc, a, n, &s, &wbits);

	if (rc < 0)
		return rc;
	/* read the words in chunks that fit the stack buffer */
	while (done < s.count) {
		struct span c = s;
		size_t per = sizeof words / s.esize;

		c.count = s.count - done < per ? s.count - done : per;
		span_at(&s, done, &c.a);
		io.out = words;
		rc = span_read(h, station, what, &c, &io);
		if (rc < 0)
			return rc;
		/* g: bit number from bit 0 of the span's first word */
		for (size_t g = done * wbits; g < (done + c.count) * wbits; g++) {
			bool on;

			if (g < first || g >= first + n)
				continue;
			on = value_get_bit(words, s.esize, g - done * wbits);
			if (bits)
				bits[g - first] = on;
			if (vals) {
				memset(&vals[g - first], 0, sizeof vals[0]);
				vals[g - first].kind = DF1_VAL_BIT;
				vals[g - first].v.bit = on;
			}
		}
		done += c.count;
	}
	return (int)n;
}

/* PLC-2 05 unprotected bit write: {ADDR(2) SET(1) RESET(1)} per byte. */
static int plc2_bit_write(struct df1 *h, int station, const char *what, const struct df1_addr *w,
                          uint16_t mask, uint16_t data)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA];
	const uint8_t *d;
	size_t n = PCCC_HDR_LEN, dlen;

	if (!client_is_word_type(w->type) || w->sub != DF1_ADDR_NONE)
		return client_fail(h, DF1_E_NOTSUP, station, what,
		                "PLC-2 commands reach 16-bit words only (N B S I O A)");
	if (h->cfg.plc2_word_addr)
		return client_fail(h, DF1_E_NOTSUP, station, what,
		                "PLC-2 bit writes (05) address bytes, not words (word addresses are set)");
	if (w->element > 0x7FFF)
		return client_fail(h, DF1_E_ADDR_RANGE, station, what, "beyond the PLC-2 byte address range");
	memset(cmd, 0, PCCC_HDR_LEN);
	cmd[2] = PCCC_CMD_UNPROT_BIT_WRITE;
	for (unsigned b = 0; b < 2; b++) {
		uint8_t m = (uint8_t)(mask >> (8 * b)), v = (uint8_t)(data >> (8 * b));

		if (!m)
			continue;
		put_le16(cmd + n, (uint16_t)(w->element * 2 + (int)b));
		cmd[n + 2] = (uint8_t)(v & m);          /* SET */
		cmd[n + 3] = (uint8_t)(m & (uint8_t)~v); /* RESET */
		n += 4;
	}
	return client_transact(h, station, what, cmd, n, reply, sizeof reply, &d, &dlen);
}

/* Change the bits of mask in word w to those of data; the other bits stay. */
static int client_mask_word(struct df1 *h, int station, const char *what, enum df1_plc plc,
                            const struct df1_addr *w, size_t wsize, uint32_t mask, uint32_t data)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], addr[DF1_ADDR_ASCII_MAX + 8];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	const uint8_t *d;
	size_t dlen;
	int n, alen, code;

	data &= mask;
	switch (plc) {
	case DF1_PLC_PLC5:
		if (wsize != 2)
			return client_fail(h, DF1_E_NOTSUP, station, what, "PLC-5 bit writes reach 16-bit words");
		alen = plc5_addr(h, station, what, w, addr, sizeof addr);
		if (alen < 0)
			return alen;
		/* new = (old AND and) OR or: set AND FFFF OR bit, clear AND ~bit OR 0 */
		n = pccc_enc_plc5_rmw(cmd, sizeof cmd, &hd, addr, (size_t)alen,
		                      (uint16_t)(~mask | data), (uint16_t)data);
		break;
	case DF1_PLC_PLC2:
		return plc2_bit_write(h, station, what, w, (uint16_t)mask, (uint16_t)data);
	case DF1_PLC_PLC3:
		if (wsize != 2)
			return client_fail(h, DF1_E_NOTSUP, station, what, "PLC-3 bit writes reach 16-bit words");
		alen = plc3_addr(h, station, what, w, addr, sizeof addr);
		if (alen < 0)
			return alen;
		/* 0F/02: SET mask, then RESET mask (doc/PROTOCOL.md 4.2a) */
		n = pccc_enc_plc5_bit_write(cmd, sizeof cmd, &hd, addr, (size_t)alen, (uint16_t)data,
		                            (uint16_t)(mask & ~data));
		break;
	default: {
		uint8_t m[4], v[4];

		code = slc_type_code(h, station, what, w->type);
		if (code < 0)
			return code;
		put_le32(m, mask);
		put_le32(v, data);
		n = pccc_enc_slc_masked_write(cmd, sizeof cmd, &hd, (unsigned)w->file, (uint8_t)code,
		                              (unsigned)w->element,
		                              w->sub == DF1_ADDR_NONE ? 0u : (unsigned)w->sub, m, v,
		                              (uint8_t)wsize);
		break;
	}
	}
	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the bit write (%s)", df1_strerror(n));
	return client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
}

/* Write n bits from bits[] or vals[] (kind BIT), one masked write per word touched. */
int client_write_bits(struct df1 *h, int station, const char *what, enum df1_plc plc,
                      const struct df1_addr *a, size_t n, const bool *bits, const struct df1_value *vals)
{
	struct span s;
	unsigned wbits;
	size_t first = (size_t)a->bit;
	int rc = bits_span(h, station, what, plc, a, n, &s, &wbits);

	if (rc < 0)
		return rc;
	if (vals)
		for (size_t i = 0; i < n; i++)
			if (vals[i].kind != DF1_VAL_BIT)
				return client_fail(h, DF1_E_TYPE, station, what, "value %zu is not a bit", i);
	rc = span_check(h, station, what, &s);
	if (rc < 0)
		return rc;
	for (size_t w = 0; w < s.count; w++) {
		struct df1_addr wa;
		uint32_t mask = 0, data = 0;

		for (size_t b = 0; b < wbits; b++) {
			size_t g = w * wbits + b;
			bool on;

			if (g < first || g >= first + n)
				continue;
			on = bits ? bits[g - first] : vals[g - first].v.bit;
			value_mask_bit(&mask, &data, (unsigned)b, on);
		}
		span_at(&s, w, &wa);
		rc = client_mask_word(h, station, what, plc, &wa, s.esize, mask, data);
		if (rc < 0)
			return rc;
	}
	return (int)n;
}

/* ------------------------------------------------------------------------
 * Reads and writes of element values (not bits)
 * ------------------------------------------------------------------------ */

/* The span for n elements at a, and how io picks values; a has no bit. */
static int client_plan(struct df1 *h, int station, const char *what, enum df1_plc plc,
                       const struct df1_addr *a, size_t n, bool write, struct span *s, struct io *io, bool *per_element)
{
	int es = df1_file_type_element_size(a->type);

	memset(s, 0, sizeof *s);
	s->plc = plc;
	*per_element = false;
	io->word = -1;
	io->t = a->type;
	io->fo = value_typed_float_order(plc, h->cfg.plc5_float_swapped);
	if (es <= 0)
		return client_fail(h, DF1_E_ADDR_SYNTAX, station, what, "no file type");
	s->count = n;
	if (a->sub == DF1_ADDR_NONE) {
		client_derive(a, a->element, DF1_ADDR_NONE, &s->a);
		s->esize = (size_t)es;
		return 0;
	}
	io->t = DF1_FT_N;       /* one 16-bit word per element */
	if (client_is_tcr(a->type)) {
		if (n == 1 || write) {
			/* that word of each element: one element per command */
			client_derive(a, a->element, a->sub, &s->a);
			s->esize = 2;
			s->count = 1;
			*per_element = n > 1;
			return 0;
		}
		/* reads of several: whole elements, keep the one word */
		client_derive(a, a->element, DF1_ADDR_NONE, &s->a);
		s->esize = (size_t)es;
		io->word = a->sub;
		return 0;
	}
	if (client_is_word_type(a->type)) {
		client_derive(a, a->element, a->sub, &s->a);
		s->esize = 2;
		s->by_sub = true;
		return 0;
	}
	return client_fail(h, DF1_E_ADDR_SYNTAX, station, what, "no sub-elements in this file type");
}

int client_read_elems_first(struct df1 *h, int station, const char *what, enum df1_plc plc,
                            const struct df1_addr *a, size_t n, struct io *io,
                            const struct rd_first *first)
{
	struct span s;
	bool per_element;
	int rc = client_plan(h, station, what, plc, a, n, false, &s, io, &per_element);

	if (rc < 0)
		return rc;
	io->base = 0;
	rc = span_read_first(h, station, what, &s, io, first);
	if (rc < 0 || (first && first->mode == RD_BUILD))
		return rc;
	return (int)n;
}

int client_read_elems(struct df1 *h, int station, const char *what, enum df1_plc plc,
                      const struct df1_addr *a, size_t n, struct io *io)
{
	return client_read_elems_first(h, station, what, plc, a, n, io, NULL);
}

/* Check every value before anything is sent. */
static int client_check_values(struct df1 *h, int station, const char *what, struct io *io, size_t n,
                               size_t esize)
{
	uint8_t scratch[84];

	if (io->kind != IO_VALUE && io->kind != IO_STRING)
		return 0;
	if (esize > sizeof scratch)
		return client_fail(h, DF1_E_INVAL, station, what, "element too large");
	for (size_t i = 0; i < n; i++) {
		int rc;

		io->base = 0;
		rc = io_get(io, i, scratch, esize);
		if (rc < 0)
			return client_fail(h, rc, station, what, "value %zu: %s", i, df1_strerror(rc));
	}
	return 0;
}

int client_write_elems(struct df1 *h, int station, const char *what, enum df1_plc plc,
                       const struct df1_addr *a, size_t n, struct io *io)
{
	struct span s;
	bool per_element;
	int rc = client_plan(h, station, what, plc, a, n, true, &s, io, &per_element);

	if (rc < 0)
		return rc;
	rc = client_check_values(h, station, what, io, n, s.esize);
	if (rc < 0)
		return rc;
	if (!per_element) {
		io->base = 0;
		rc = span_write(h, station, what, &s, io);
		return rc < 0 ? rc : (int)n;
	}
	for (size_t i = 0; i < n; i++) {
		struct span one = s;

		client_derive(a, a->element + (int)i, a->sub, &one.a);
		io->base = i;
		rc = span_write(h, station, what, &one, io);
		if (rc < 0)
			return rc;
	}
	return (int)n;
}
