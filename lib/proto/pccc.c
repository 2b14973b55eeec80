/* SPDX-License-Identifier: MPL-2.0 */
/*
 * pccc.c - PCCC application layer: command encoders, header/reply decoding,
 * SLC address fields, PLC-5 system addresses, typed-data descriptors and
 * command names (doc/PROTOCOL.md 3-4); the diagnostic status is in
 * pccc_diag.c. Pure: no I/O, clock or allocation.
 */
#include "proto/pccc.h"

#include <stdio.h>
#include <string.h>

#include "proto/value.h"

#define PLC5_ASCII_MAX (DF1_ADDR_ASCII_MAX - 1) /* KF2 p.130: up to 51 bytes of specification */
#define PLC5_LEVELS 4                           /* area, file, element, sub-element */

/* ------------------------------------------------------------------------
 * Header and replies
 * ------------------------------------------------------------------------ */

/* DST SRC CMD STS TNS_lo TNS_hi [FNC]: returns bytes written or DF1_E_NOSPACE. */
static int pccc_put_hdr(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t cmd, int fnc)
{
	size_t need = PCCC_HDR_LEN + (fnc >= 0 ? 1 : 0);

	if (!out || !h)
		return DF1_E_INVAL;
	if (cap < need)
		return DF1_E_NOSPACE;
	out[0] = h->dst;
	out[1] = h->src;
	out[2] = cmd;
	out[3] = 0;     /* STS is 00 in every command (M p.236) */
	put_le16(out + 4, h->tns);
	if (fnc >= 0)
		out[6] = (uint8_t)fnc;
	return (int)need;
}

/* Append n bytes at out[pos]; keeps the running length or returns DF1_E_NOSPACE. */
static int pccc_put_bytes(uint8_t *out, size_t cap, int pos, const void *src, size_t n)
{
	if (pos < 0)
		return pos;
	if (n > cap || (size_t)pos > cap - n)
		return DF1_E_NOSPACE;
	if (n)
		memcpy(out + pos, src, n);
	return pos + (int)n;
}

static int pccc_put_u8(uint8_t *out, size_t cap, int pos, uint8_t v)
{
	return pccc_put_bytes(out, cap, pos, &v, 1);
}

static int pccc_put_u16(uint8_t *out, size_t cap, int pos, uint16_t v)
{
	uint8_t b[2];

	put_le16(b, v);
	return pccc_put_bytes(out, cap, pos, b, 2);
}

static int pccc_put_fld(uint8_t *out, size_t cap, int pos, unsigned v)
{
	int r;

	if (pos < 0)
		return pos;
	r = pccc_put_field(out + pos, cap - (size_t)pos, v);
	return r < 0 ? r : pos + r;
}

bool pccc_cmd_has_ext_sts(uint8_t cmd)
{
	return (cmd & (uint8_t)~PCCC_REPLY_BIT) > 0x08;
}

/* DH-485 codes whose EXT STS 1A/1B is followed by the owner's node (doc/PROTOCOL.md 3.4). */
static bool pccc_has_owner_byte(uint8_t cmd, uint8_t ext)
{
	cmd &= (uint8_t)~PCCC_REPLY_BIT;
	return (cmd == 0x0B || cmd == 0x1A || cmd == 0x1B) && (ext == 0x1A || ext == 0x1B);
}

int pccc_decode(const uint8_t *app, size_t n, struct pccc_msg *m)
{
	size_t pos = PCCC_HDR_LEN;

	if (!app || !m)
		return DF1_E_INVAL;
	memset(m, 0, sizeof *m);
	if (n < PCCC_HDR_LEN)
		return DF1_E_TOO_SHORT;
	m->dst = app[0];
	m->src = app[1];
	m->cmd = app[2];
	m->sts = app[3];
	m->tns = le16(app + 4);
	m->is_reply = (m->cmd & PCCC_REPLY_BIT) != 0;
	if (!m->is_reply) {
		uint8_t c = m->cmd;

		if (c == PCCC_CMD_DIAG || c == PCCC_CMD_TYPED) {
			if (n < pos + 1)
				return DF1_E_TOO_SHORT;
			m->has_fnc = true;
			m->fnc = app[pos++];
		}
	} else if (m->sts == 0xF0 && pccc_cmd_has_ext_sts(m->cmd)) {
		if (n < pos + 1)
			return DF1_E_BAD_REPLY;
		m->has_ext = true;
		m->ext_sts = app[pos++];
		if (pccc_has_owner_byte(m->cmd, m->ext_sts)) {
			if (n < pos + 1)
				return DF1_E_BAD_REPLY;
			m->has_owner = true;
			m->owner = app[pos++];
		}
	}
	m->data = app + pos;
	m->len = n - pos;
	return 0;
}

int pccc_encode_reply(uint8_t *out, size_t cap, const struct pccc_msg *cmd,
                      uint8_t sts, uint8_t ext_sts, const uint8_t *data, size_t n)
{
	struct pccc_hdr h;
	int pos;

	if (!cmd || (n && !data))
		return DF1_E_INVAL;
	h.dst = cmd->src;
	h.src = cmd->dst;
	h.tns = cmd->tns;
	pos = pccc_put_hdr(out, cap, &h, (uint8_t)(cmd->cmd | PCCC_REPLY_BIT), -1);
	if (pos < 0)
		return pos;
	out[3] = sts;
	if (sts == 0xF0 && pccc_cmd_has_ext_sts(cmd->cmd))
		pos = pccc_put_u8(out, cap, pos, ext_sts);
	return pccc_put_bytes(out, cap, pos, data, n);
}

/* ------------------------------------------------------------------------
 * SLC logical addresses (0F/A1 A2 A9 AA AB)
 * ------------------------------------------------------------------------ */

int pccc_put_field(uint8_t *out, size_t cap, unsigned v)
{
	if (!out)
		return DF1_E_INVAL;
	if (v > 0xFFFF)
		return DF1_E_ADDR_RANGE;
	if (v <= 254) {
		if (cap < 1)
			return DF1_E_NOSPACE;
		out[0] = (uint8_t)v;
		return 1;
	}
	/* FF says "2 bytes LE follow" (M p.104), so 255 itself needs the escape */
	if (cap < 3)
		return DF1_E_NOSPACE;
	out[0] = 0xFF;
	put_le16(out + 1, (uint16_t)v);
	return 3;
}

int pccc_get_field(const uint8_t *in, size_t n, unsigned *v)
{
	if (!in || !v)
		return DF1_E_INVAL;
	if (n < 1)
		return DF1_E_TOO_SHORT;
	if (in[0] != 0xFF) {
		*v = in[0];
		return 1;
	}
	if (n < 3)
		return DF1_E_TOO_SHORT;
	*v = le16(in + 1);
	return 3;
}

/* BYTE_SIZE FILE_NO FILE_TYPE ELEMENT [SUBELEMENT] after the header and FNC. */
static int pccc_put_slc_fields(uint8_t *out, size_t cap, int pos, uint8_t nbytes, unsigned file,
                          uint8_t type_code, unsigned elem, bool with_sub, unsigned sub)
{
	pos = pccc_put_u8(out, cap, pos, nbytes);
	pos = pccc_put_fld(out, cap, pos, file);
	pos = pccc_put_u8(out, cap, pos, type_code);
	pos = pccc_put_fld(out, cap, pos, elem);
	if (with_sub)
		pos = pccc_put_fld(out, cap, pos, sub);
	return pos;
}

int pccc_enc_slc_read(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t fnc,
                      uint8_t nbytes, unsigned file, uint8_t type_code, unsigned elem, unsigned sub)
{
	int pos;

	if (fnc != PCCC_FNC_SLC_READ2 && fnc != PCCC_FNC_SLC_READ3)
		return DF1_E_INVAL;
	pos = pccc_put_hdr(out, cap, h, PCCC_CMD_TYPED, fnc);
	return pccc_put_slc_fields(out, cap, pos, nbytes, file, type_code, elem,
	                      fnc == PCCC_FNC_SLC_READ3, sub);
}

int pccc_enc_slc_write(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t fnc,
                       unsigned file, uint8_t type_code, unsigned elem, unsigned sub,
                       const uint8_t *data, uint8_t nbytes)
{
	int pos;

	if ((fnc != PCCC_FNC_SLC_WRITE2 && fnc != PCCC_FNC_SLC_WRITE3) || (nbytes && !data))
		return DF1_E_INVAL;
	pos = pccc_put_hdr(out, cap, h, PCCC_CMD_TYPED, fnc);
	pos = pccc_put_slc_fields(out, cap, pos, nbytes, file, type_code, elem,
	                     fnc == PCCC_FNC_SLC_WRITE3, sub);
	return pccc_put_bytes(out, cap, pos, data, nbytes);
}

int pccc_enc_slc_masked_write(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                              unsigned file, uint8_t type_code, unsigned elem, unsigned sub,
                              const uint8_t *mask, const uint8_t *data, uint8_t nbytes)
{
	int pos;

	if (nbytes && (!mask || !data))
		return DF1_E_INVAL;
	pos = pccc_put_hdr(out, cap, h, PCCC_CMD_TYPED, PCCC_FNC_SLC_MASKED);
	pos = pccc_put_slc_fields(out, cap, pos, nbytes, file, type_code, elem, true, sub);
	pos = pccc_put_bytes(out, cap, pos, mask, nbytes);   /* MASK then DATA (doc/PROTOCOL.md 4.6) */
	return pccc_put_bytes(out, cap, pos, data, nbytes);
}

int pccc_dec_slc_fields(const uint8_t *in, size_t n, bool three_fields, uint8_t *nbytes,
                        unsigned *file, uint8_t *type_code, unsigned *elem, unsigned *sub)
{
	size_t pos = 0;
	unsigned f, e, s = 0;
	int r;

	if (!in || !nbytes || !file || !type_code || !elem || !sub)
		return DF1_E_INVAL;
	if (n < 1)
		return DF1_E_TOO_SHORT;
	*nbytes = in[pos++];
	r = pccc_get_field(in + pos, n - pos, &f);
	if (r < 0)
		return r;
	pos += (size_t)r;
	if (n < pos + 1)
		return DF1_E_TOO_SHORT;
	*type_code = in[pos++];
	r = pccc_get_field(in + pos, n - pos, &e);
	if (r < 0)
		return r;
	pos += (size_t)r;
	if (three_fields) {
		r = pccc_get_field(in + pos, n - pos, &s);
		if (r < 0)
			return r;
		pos += (size_t)r;
	}
	*file = f;
	*elem = e;
	*sub = s;
	return (int)pos;
}

enum df1_file_type pccc_slc_code_file_type(uint8_t code)
{
	switch (code) {
	case 0x82: case 0x8B: return DF1_FT_O;   /* 82/83: F2E; 8B/8C: M p.104 (doc/PROTOCOL.md 4.11) */
	case 0x83: case 0x8C: return DF1_FT_I;
	case 0x84: return DF1_FT_S;
	case 0x85: return DF1_FT_B;
	case 0x86: return DF1_FT_T;
	case 0x87: return DF1_FT_C;
	case 0x88: return DF1_FT_R;
	case 0x89: return DF1_FT_N;
	case 0x8A: return DF1_FT_F;
	case 0x8D: return DF1_FT_ST;
	case 0x8E: return DF1_FT_A;
	case 0x91: return DF1_FT_L;
	default: return DF1_FT_NONE;
	}
}

/* ------------------------------------------------------------------------
 * PLC-5 system addresses (doc/PROTOCOL.md 4.1)
 * ------------------------------------------------------------------------ */

static int pccc_enc_plc5_levels(uint8_t *out, size_t cap, unsigned mask, const unsigned *lv)
{
	int pos = pccc_put_fld(out, cap, 0, mask);   /* the mask takes the FF escape too (M p.229) */

	for (int i = 0; i < PLC5_LEVELS; i++)
		if (mask & (1u << i))
			pos = pccc_put_fld(out, cap, pos, lv[i]);
	return pos;
}

int pccc_enc_plc5_addr_form(uint8_t *out, size_t cap, const struct df1_addr *a, enum pccc_plc5_form form)
{
	unsigned lv[PLC5_LEVELS], mask;
	bool has_sub;

	if (!out || !a)
		return DF1_E_INVAL;
	if (a->ascii[0])
		return pccc_enc_plc5_ascii(out, cap, a->ascii);
	has_sub = a->sub != DF1_ADDR_NONE;
	if (a->file < 0 || a->file > 0xFFFF || a->element < 0 || a->element > 0xFFFF ||
	    (has_sub && (a->sub < 0 || a->sub > 0xFFFF)))
		return DF1_E_ADDR_RANGE;
	lv[0] = 0;      /* data table area */
	lv[1] = (unsigned)a->file;
	lv[2] = (unsigned)a->element;
	lv[3] = has_sub ? (unsigned)a->sub : 0;
	switch (form) {
	case PCCC_PLC5_FILE_ELEM:
		mask = has_sub ? 0x0E : 0x06;
		break;
	case PCCC_PLC5_ALL_LEVELS:
		mask = has_sub ? 0x0F : 0x07;
		break;
	case PCCC_PLC5_FOUR_LEVELS:
		mask = 0x0F;
		break;
	default:
		return DF1_E_INVAL;
	}
	return pccc_enc_plc5_levels(out, cap, mask, lv);
}

int pccc_enc_plc5_addr(uint8_t *out, size_t cap, const struct df1_addr *a)
{
	return pccc_enc_plc5_addr_form(out, cap, a, PCCC_PLC5_FILE_ELEM);
}

int pccc_enc_plc5_ascii(uint8_t *out, size_t cap, const char *text)
{
	size_t len;

	if (!out || !text)
		return DF1_E_INVAL;
	if (text[0] == '$')
		text++;
	len = strlen(text);
	if (len == 0)
		return DF1_E_ADDR_SYNTAX;
	if (len > PLC5_ASCII_MAX)
		return DF1_E_ADDR_RANGE;
	if (cap < len + 3)
		return DF1_E_NOSPACE;
	out[0] = 0x00;  /* a mask of 0 cannot start a binary address: marks the ASCII form */
	out[1] = '$';
	memcpy(out + 2, text, len);
	out[len + 2] = 0x00;
	return (int)len + 3;
}

static int pccc_dec_plc5_ascii(const uint8_t *in, size_t n, struct df1_addr *a)
{
	char text[DF1_ADDR_ASCII_MAX];
	size_t len = 0;

	if (n < 2)
		return DF1_E_TOO_SHORT;
	if (in[1] != '$')
		return DF1_E_ADDR_SYNTAX;
	while (2 + len < n && in[2 + len] != 0x00) {
		if (len >= PLC5_ASCII_MAX)
			return DF1_E_ADDR_RANGE;
		text[len] = (char)in[2 + len];
		len++;
	}
	if (2 + len >= n)
		return DF1_E_TOO_SHORT;         /* no terminating 00 */
	text[len] = '\0';
	if (df1_addr_parse(text, a) < 0) {
		memset(a, 0, sizeof *a);
		a->type = DF1_FT_NONE;
		a->file = a->element = DF1_ADDR_NONE;
		a->sub = a->bit = DF1_ADDR_NONE;
	}
	memcpy(a->ascii, text, len + 1);
	return (int)len + 3;
}

int pccc_dec_plc5_addr(const uint8_t *in, size_t n, struct df1_addr *a)
{
	unsigned mask, lv[PLC5_LEVELS] = { 0, 1, 0, 0 };  /* defaults: file level 1 (M p.226) */
	int r, pos;

	if (!in || !a)
		return DF1_E_INVAL;
	if (n < 1)
		return DF1_E_TOO_SHORT;
	if (in[0] == 0x00)
		return pccc_dec_plc5_ascii(in, n, a);
	r = pccc_get_field(in, n, &mask);
	if (r < 0)
		return r;
	pos = r;
	if (mask >> PLC5_LEVELS)
		return DF1_E_ADDR_RANGE;        /* EXT STS 03: more levels than supported */
	for (int i = 0; i < PLC5_LEVELS; i++) {
		if (!(mask & (1u << i)))
			continue;
		r = pccc_get_field(in + pos, n - (size_t)pos, &lv[i]);
		if (r < 0)
			return r;
		pos += r;
	}
	if (lv[0] != 0)
		return DF1_E_ADDR_RANGE;        /* only the data table area is served */
	memset(a, 0, sizeof *a);
	a->type = DF1_FT_NONE;
	a->file = (int)lv[1];
	a->element = (int)lv[2];
	a->sub = (mask & 0x08) ? (int)lv[3] : DF1_ADDR_NONE;
	a->bit = DF1_ADDR_NONE;
	return pos;
}

int pccc_dec_plc5_req(uint8_t fnc, const uint8_t *in, size_t n, struct pccc_plc5_req *r)
{
	size_t pos = 0;
	int k;

	if (!in || !r)
		return DF1_E_INVAL;
	memset(r, 0, sizeof *r);
	r->size = -1;
	switch (fnc) {
	case PCCC_FNC_WORD_WRITE: case PCCC_FNC_WORD_READ:
	case PCCC_FNC_TYPED_WRITE: case PCCC_FNC_TYPED_READ:
		if (n < 4)
			return DF1_E_TOO_SHORT;
		r->pkt_offset = le16(in);
		r->total = le16(in + 2);
		pos = 4;
		break;
	case PCCC_FNC_BIT_WRITE: case PCCC_FNC_RMW:
		break;
	default:
		return DF1_E_NOTSUP;
	}
	k = pccc_dec_plc5_addr(in + pos, n - pos, &r->addr);
	if (k < 0)
		return k;
	pos += (size_t)k;
	if (fnc == PCCC_FNC_TYPED_READ) {
		if (n < pos + 2)
			return DF1_E_TOO_SHORT;
		r->size = le16(in + pos);
		pos += 2;
	} else if (fnc == PCCC_FNC_WORD_READ) {
		if (n < pos + 1)
			return DF1_E_TOO_SHORT;
		r->size = in[pos++];
	} else if ((fnc == PCCC_FNC_BIT_WRITE || fnc == PCCC_FNC_RMW) && n < pos + 4) {
		return DF1_E_TOO_SHORT;        /* SET RESET / AND OR, 2 bytes each */
	}
	r->data = in + pos;
	r->len = n - pos;
	return 0;
}

/* ------------------------------------------------------------------------
 * PLC-5 commands (doc/PROTOCOL.md 4.2-4.4)
 * ------------------------------------------------------------------------ */

/* FNC PKT_OFFSET TOTAL ADDRESS: the common start of 00 01 67 68. */
static int pccc_plc5_start(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t fnc,
                      uint16_t off, uint16_t total, const uint8_t *addr, size_t alen)
{
	int pos;

	if (!addr || alen == 0)
		return DF1_E_INVAL;
	pos = pccc_put_hdr(out, cap, h, PCCC_CMD_TYPED, fnc);
	pos = pccc_put_u16(out, cap, pos, off);
	pos = pccc_put_u16(out, cap, pos, total);
	return pccc_put_bytes(out, cap, pos, addr, alen);
}

int pccc_enc_plc5_typed_read(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                             uint16_t pkt_offset, uint16_t total, const uint8_t *addr, size_t alen,
                             uint16_t nelem)
{
	int pos = pccc_plc5_start(out, cap, h, PCCC_FNC_TYPED_READ, pkt_offset, total, addr, alen);

	return pccc_put_u16(out, cap, pos, nelem);   /* SIZE in elements, LE (M p.117) */
}

int pccc_enc_plc5_typed_write(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                              uint16_t pkt_offset, uint16_t total, const uint8_t *addr, size_t alen,
                              const uint8_t *typed, size_t tlen)
{
	int pos;

	if (!typed || tlen == 0)
		return DF1_E_INVAL;
	pos = pccc_plc5_start(out, cap, h, PCCC_FNC_TYPED_WRITE, pkt_offset, total, addr, alen);
	return pccc_put_bytes(out, cap, pos, typed, tlen);
}

int pccc_enc_plc5_word_read(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                            uint16_t pkt_offset, uint16_t total_words, const uint8_t *addr,
                            size_t alen, uint8_t nbytes)
{
	int pos;

	if (nbytes & 1)
		return DF1_E_INVAL;             /* SIZE counts bytes of whole words (PM020 p.89) */
	pos = pccc_plc5_start(out, cap, h, PCCC_FNC_WORD_READ, pkt_offset, total_words, addr, alen);
	return pccc_put_u8(out, cap, pos, nbytes);   /* address before SIZE (KE p.51) */
}

int pccc_enc_plc5_word_write(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                             uint16_t pkt_offset, uint16_t total_words, const uint8_t *addr,
                             size_t alen, const uint8_t *data, size_t n)
{
	int pos;

	if ((n & 1) || (n && !data))
		return DF1_E_INVAL;
	pos = pccc_plc5_start(out, cap, h, PCCC_FNC_WORD_WRITE, pkt_offset, total_words, addr, alen);
	return pccc_put_bytes(out, cap, pos, data, n);
}

/* ADDRESS + two LE words after FNC: 26 (AND OR) and 02 (SET RESET). */
static int pccc_plc5_addr_2words(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t fnc,
                            const uint8_t *addr, size_t alen, uint16_t w1, uint16_t w2)
{
	int pos;

	if (!addr || alen == 0)
		return DF1_E_INVAL;
	pos = pccc_put_hdr(out, cap, h, PCCC_CMD_TYPED, fnc);
	pos = pccc_put_bytes(out, cap, pos, addr, alen);
	pos = pccc_put_u16(out, cap, pos, w1);
	return pccc_put_u16(out, cap, pos, w2);
}

int pccc_enc_plc5_rmw(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                      const uint8_t *addr, size_t alen, uint16_t and_mask, uint16_t or_mask)
{
	return pccc_plc5_addr_2words(out, cap, h, PCCC_FNC_RMW, addr, alen, and_mask, or_mask);
}

int pccc_enc_plc5_bit_write(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                            const uint8_t *addr, size_t alen, uint16_t set, uint16_t reset)
{
	return pccc_plc5_addr_2words(out, cap, h, PCCC_FNC_BIT_WRITE, addr, alen, set, reset);
}

/* ------------------------------------------------------------------------
 * PLC-2, diagnostics, mode (doc/PROTOCOL.md 4.7-4.9)
 * ------------------------------------------------------------------------ */

int pccc_enc_plc2_read(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint16_t byte_addr,
                       uint8_t size)
{
	int pos = pccc_put_hdr(out, cap, h, PCCC_CMD_UNPROT_READ, -1);   /* PLC-2 commands have no FNC */

	pos = pccc_put_u16(out, cap, pos, byte_addr);
	return pccc_put_u8(out, cap, pos, size);
}

int pccc_enc_plc2_write(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint16_t byte_addr,
                        const uint8_t *data, size_t n)
{
	int pos;

	if (n && !data)
		return DF1_E_INVAL;
	pos = pccc_put_hdr(out, cap, h, PCCC_CMD_UNPROT_WRITE, -1);
	pos = pccc_put_u16(out, cap, pos, byte_addr);
	return pccc_put_bytes(out, cap, pos, data, n);
}

int pccc_enc_echo(uint8_t *out, size_t cap, const struct pccc_hdr *h, const uint8_t *data, size_t n)
{
	int pos;

	if (n && !data)
		return DF1_E_INVAL;
	pos = pccc_put_hdr(out, cap, h, PCCC_CMD_DIAG, PCCC_FNC_ECHO);
	return pccc_put_bytes(out, cap, pos, data, n);
}

int pccc_enc_diag_status(uint8_t *out, size_t cap, const struct pccc_hdr *h)
{
	return pccc_put_hdr(out, cap, h, PCCC_CMD_DIAG, PCCC_FNC_DIAG_STATUS);
}

int pccc_enc_change_mode(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t mode)
{
	int pos = pccc_put_hdr(out, cap, h, PCCC_CMD_TYPED, PCCC_FNC_CHANGE_MODE);

	return pccc_put_u8(out, cap, pos, mode);
}

/* ------------------------------------------------------------------------
 * Typed-data descriptors (M p.116, 123-124)
 * ------------------------------------------------------------------------ */

static unsigned pccc_le_bytes_needed(uint32_t v)
{
	unsigned k = 1;

	while (k < 4 && (v >> (8 * k)))
		k++;
	return k;
}

/* Flag byte: type in bits 6-4 or (bit 7) in k following bytes; size in bits 2-0 or
 * (bit 3) in m bytes after those. size_ext forces the size into extension bytes. */
static int pccc_enc_td(uint8_t *out, size_t cap, unsigned type_id, uint32_t size, bool size_ext)
{
	uint8_t b[9];
	size_t n = 1;
	unsigned k;

	if (!out)
		return DF1_E_INVAL;
	if (type_id <= 7) {
		b[0] = (uint8_t)(type_id << 4);
	} else {
		k = pccc_le_bytes_needed(type_id);
		b[0] = (uint8_t)(0x80 | (k << 4));
		put_le32(b + n, type_id);
		n += k;
	}
	if (size <= 7 && !size_ext) {
		b[0] |= (uint8_t)size;
	} else {
		k = pccc_le_bytes_needed(size);
		b[0] |= (uint8_t)(0x08 | k);
		put_le32(b + n, size);  /* only k bytes are kept */
		n += k;
	}
	if (cap < n)
		return DF1_E_NOSPACE;
	memcpy(out, b, n);
	return (int)n;
}

int pccc_enc_typedata(uint8_t *out, size_t cap, unsigned type_id, uint32_t size)
{
	return pccc_enc_td(out, cap, type_id, size, false);
}

int pccc_dec_typedata(const uint8_t *in, size_t n, unsigned *type_id, uint32_t *size)
{
	uint32_t v[2] = { 0, 0 };
	unsigned cnt[2];
	size_t pos = 1;
	uint8_t flag;

	if (!in || !type_id || !size)
		return DF1_E_INVAL;
	if (n < 1)
		return DF1_E_TOO_SHORT;
	flag = in[0];
	cnt[0] = (flag & 0x80) ? (flag >> 4) & 7u : 0;
	cnt[1] = (flag & 0x08) ? flag & 7u : 0;
	v[0] = (flag >> 4) & 7u;
	v[1] = flag & 7u;
	for (int f = 0; f < 2; f++) {
		if (cnt[f] == 0)
			continue;
		v[f] = 0;
		if (n < pos + cnt[f])
			return DF1_E_TOO_SHORT;
		/* LE, least significant first (M p.123); zero high bytes are allowed */
		for (unsigned i = 0; i < cnt[f]; i++, pos++) {
			if (i < 4)
				v[f] |= (uint32_t)in[pos] << (8 * i);
			else if (in[pos] != 0)
				return DF1_E_BAD_REPLY;
		}
	}
	*type_id = v[0];
	*size = v[1];
	return (int)pos;
}

int pccc_enc_typed_array(uint8_t *out, size_t cap, unsigned elem_type, uint32_t elem_size, size_t count)
{
	uint8_t desc[9];
	int dlen, hlen;
	uint64_t total;

	if (!out || elem_type == PCCC_TD_ARRAY)
		return DF1_E_INVAL;
	dlen = pccc_enc_td(desc, sizeof desc, elem_type, elem_size, false);
	if (dlen < 0)
		return dlen;
	/* the array's size counts its element descriptor plus the data (M p.124) */
	total = (uint64_t)dlen + (uint64_t)elem_size * count;
	if (total > 0xFFFFFFFFu)
		return DF1_E_RANGE;
	hlen = pccc_enc_td(out, cap, PCCC_TD_ARRAY, (uint32_t)total, true);
	if (hlen < 0)
		return hlen;
	return pccc_put_bytes(out, cap, hlen, desc, (size_t)dlen);
}

int pccc_dec_typed(const uint8_t *in, size_t n, struct pccc_typed *t)
{
	unsigned type;
	uint32_t size;
	int r;

	if (!in || !t)
		return DF1_E_INVAL;
	memset(t, 0, sizeof *t);
	r = pccc_dec_typedata(in, n, &type, &size);
	if (r < 0)
		return r;
	if (type != PCCC_TD_ARRAY) {
		if (n - (size_t)r < size)
			return DF1_E_TOO_SHORT;
		t->type_id = type;
		t->elem_size = size;
		t->count = 1;
		t->data = in + r;
		t->len = size;
		t->consumed = (size_t)r + size;
		return 0;
	}
	{
		size_t pos = (size_t)r, end;
		unsigned etype;
		uint32_t esize;
		int d;

		if (n - pos < size)
			return DF1_E_TOO_SHORT;
		end = pos + size;
		d = pccc_dec_typedata(in + pos, size, &etype, &esize);
		if (d < 0)
			return d == DF1_E_TOO_SHORT ? DF1_E_BAD_REPLY : d;
		pos += (size_t)d;
		if (etype == PCCC_TD_ARRAY || esize == 0 || (end - pos) % esize)
			return DF1_E_BAD_REPLY;
		t->type_id = etype;
		t->elem_size = esize;
		t->is_array = true;
		t->count = (end - pos) / esize;
		t->data = in + pos;
		t->len = end - pos;
		t->consumed = end;
	}
	return 0;
}

const char *pccc_command_name(uint8_t cmd, bool has_fnc, uint8_t fnc)
{
	if (cmd & PCCC_REPLY_BIT) {
		switch (cmd) {
		case 0x40: return "reply (40)";
		case 0x41: return "reply (41)";
		case 0x42: return "reply (42)";
		case 0x45: return "reply (45)";
		case 0x46: return "reply (46)";
		case 0x48: return "reply (48)";
		case 0x4F: return "reply (4F)";
		default: return "reply";
		}
	}
	switch (cmd) {
	case PCCC_CMD_PROT_WRITE: return "protected write (00)";
	case PCCC_CMD_UNPROT_READ: return "unprotected read (01)";
	case PCCC_CMD_PROT_BIT_WRITE: return "protected bit write (02)";
	case PCCC_CMD_UNPROT_BIT_WRITE: return "unprotected bit write (05)";
	case PCCC_CMD_UNPROT_WRITE: return "unprotected write (08)";
	case PCCC_CMD_DIAG:
		if (!has_fnc)
			return "diagnostic (06)";
		switch (fnc) {
		case PCCC_FNC_ECHO: return "echo (06/00)";
		case PCCC_FNC_DIAG_READ: return "diagnostic read (06/01)";
		case 0x02: return "set variables (06/02)";
		case PCCC_FNC_DIAG_STATUS: return "diagnostic status (06/03)";
		case 0x04: return "set timeout (06/04)";
		case 0x05: return "set NAKs (06/05)";
		case 0x06: return "set ENQs (06/06)";
		case 0x07: return "diagnostic counter reset (06/07)";
		default: return "diagnostic, unknown function (06)";
		}
	case PCCC_CMD_TYPED:
		if (!has_fnc)
			return "command (0F)";
		switch (fnc) {
		case PCCC_FNC_WORD_WRITE: return "word range write (0F/00)";
		case PCCC_FNC_WORD_READ: return "word range read (0F/01)";
		case PCCC_FNC_BIT_WRITE: return "bit write (0F/02)";
		case PCCC_FNC_RMW: return "read-modify-write (0F/26)";
		case PCCC_FNC_SET_CPU_MODE: return "set CPU mode (0F/3A)";
		case PCCC_FNC_TYPED_WRITE: return "typed write (0F/67)";
		case PCCC_FNC_TYPED_READ: return "typed read (0F/68)";
		case PCCC_FNC_CHANGE_MODE: return "change mode (0F/80)";
		case PCCC_FNC_SLC_READ2: return "SLC typed read, 2 fields (0F/A1)";
		case PCCC_FNC_SLC_READ3: return "SLC typed read, 3 fields (0F/A2)";
		case PCCC_FNC_SLC_WRITE2: return "SLC typed write, 2 fields (0F/A9)";
		case PCCC_FNC_SLC_WRITE3: return "SLC typed write, 3 fields (0F/AA)";
		case PCCC_FNC_SLC_MASKED: return "SLC masked write (0F/AB)";
		default: return "unknown function (0F)";
		}
	default:
		return "unknown command";
	}
}
