/* SPDX-License-Identifier: MPL-2.0 */
/*
 * pccc_plc3.c - a PLC-3's logical binary address (pure): the levels of a data
 * table address (area, context, section, file, structure, word) to and from
 * their bytes, and to and from struct df1_addr (doc/PROTOCOL.md 4.2a; the
 * commands that carry it, 0F/01 0F/00 0F/02, have the PLC-5's layouts and
 * encoders in pccc.c).
 */
#include "proto/pccc.h"

#include <string.h>

#define P3_LEVELS 6

/* Section numbers (doc/PROTOCOL.md 4.2a) by file type; 0 = none. */
static unsigned p3_section(enum df1_file_type t)
{
	switch (t) {
	case DF1_FT_O: return 1;
	case DF1_FT_I: return 2;
	case DF1_FT_T: return 3;
	case DF1_FT_C: return 4;
	case DF1_FT_N: return 5;
	case DF1_FT_F: return 6;
	case DF1_FT_D: return 7;
	case DF1_FT_B: return 8;
	case DF1_FT_A: return 9;
	case DF1_FT_L: return 10;
	case DF1_FT_S: return 13;
	default: return 0;
	}
}

static enum df1_file_type p3_type(unsigned section)
{
	static const enum df1_file_type types[14] = {
		DF1_FT_NONE, DF1_FT_O, DF1_FT_I, DF1_FT_T, DF1_FT_C, DF1_FT_N, DF1_FT_F,
		DF1_FT_D, DF1_FT_B, DF1_FT_A, DF1_FT_L, DF1_FT_NONE, DF1_FT_NONE, DF1_FT_S,
	};

	return section < 14 ? types[section] : DF1_FT_NONE;
}

int pccc_plc3_levels(const struct df1_addr *a, struct pccc_plc3_addr *l)
{
	if (!a || !l)
		return DF1_E_INVAL;
	memset(l, 0, sizeof *l);
	l->section = p3_section(a->type);
	if (l->section == 0 || a->file < 0 || a->element < 0)
		return DF1_E_ADDR_RANGE;
	l->file = (unsigned)a->file;
	switch (a->type) {
	case DF1_FT_T: case DF1_FT_C:
		l->structure = (unsigned)a->element;
		l->word = a->sub == DF1_ADDR_NONE ? 0 : (unsigned)a->sub;
		break;
	case DF1_FT_F: case DF1_FT_L:
		l->structure = (unsigned)a->element;
		break;
	default:
		l->word = (unsigned)a->element;
		break;
	}
	return 0;
}

int pccc_enc_plc3_levels(uint8_t *out, size_t cap, const struct pccc_plc3_addr *l)
{
	unsigned v[P3_LEVELS];
	uint8_t mask = 0;
	size_t pos = 1;

	if (!out || !l)
		return DF1_E_INVAL;
	v[0] = PCCC_PLC3_AREA_DATA;
	v[1] = 0;
	v[2] = l->section;
	v[3] = l->file;
	v[4] = l->structure;
	v[5] = l->word;
	mask = (uint8_t)(1u << 2 | 1u << 5 | (l->file ? 1u << 3 : 0) | (l->structure ? 1u << 4 : 0));
	if (cap < 1)
		return DF1_E_NOSPACE;
	out[0] = mask;
	for (int i = 0; i < P3_LEVELS; i++) {
		int r;

		if (!(mask & (1u << i)))
			continue;
		r = pccc_put_field(out + pos, cap - pos, v[i]);
		if (r < 0)
			return r;
		pos += (size_t)r;
	}
	return (int)pos;
}

int pccc_enc_plc3_addr(uint8_t *out, size_t cap, const struct df1_addr *a)
{
	struct pccc_plc3_addr l;
	int rc = pccc_plc3_levels(a, &l);

	return rc < 0 ? rc : pccc_enc_plc3_levels(out, cap, &l);
}

int pccc_dec_plc3_addr(const uint8_t *in, size_t n, struct pccc_plc3_addr *l)
{
	unsigned v[P3_LEVELS] = { PCCC_PLC3_AREA_DATA, 0, 0, 0, 0, 0 };
	size_t pos = 1;
	uint8_t mask;

	if (!in || !l)
		return DF1_E_INVAL;
	if (n < 1)
		return DF1_E_TOO_SHORT;
	mask = in[0];
	if (mask == 0 || mask == 0xFF)
		return DF1_E_ADDR_SYNTAX;       /* FF would be the escape: no PLC-3 mask needs it */
	if (mask & 0xC0)
		return DF1_E_ADDR_RANGE;        /* below the word: not data-table levels */
	if (!(mask & 0x20))
		return DF1_E_ADDR_SYNTAX;       /* the last level is always sent (M p.13-6) */
	for (int i = 0; i < P3_LEVELS; i++) {
		int r;

		if (!(mask & (1u << i)))
			continue;
		r = pccc_get_field(in + pos, n - pos, &v[i]);
		if (r < 0)
			return r;
		pos += (size_t)r;
	}
	if (v[0] != PCCC_PLC3_AREA_DATA)
		return DF1_E_ADDR_RANGE;
	l->section = v[2];
	l->file = v[3];
	l->structure = v[4];
	l->word = v[5];
	return (int)pos;
}

int pccc_plc3_to_addr(const struct pccc_plc3_addr *l, struct df1_addr *a)
{
	enum df1_file_type t;

	if (!l || !a)
		return DF1_E_INVAL;
	t = p3_type(l->section);
	if (t == DF1_FT_NONE || l->file > 999)
		return DF1_E_ADDR_RANGE;
	memset(a, 0, sizeof *a);
	a->type = t;
	a->file = (int)l->file;
	a->bit = DF1_ADDR_NONE;
	a->sub = DF1_ADDR_NONE;
	switch (t) {
	case DF1_FT_T: case DF1_FT_C:
		if (l->file != 0 || l->structure > 9999 || l->word > 2)
			return DF1_E_ADDR_RANGE;
		a->element = (int)l->structure;
		a->sub = (int)l->word;
		return 0;
	case DF1_FT_F: case DF1_FT_L:
		if (l->structure > 9999 || l->word > 1)
			return DF1_E_ADDR_RANGE;
		a->element = (int)l->structure;
		a->sub = l->word ? 1 : DF1_ADDR_NONE;
		return 0;
	default:
		if (l->structure != 0 || l->word > ((t == DF1_FT_O || t == DF1_FT_I) ? 07777u : 9999u))
			return DF1_E_ADDR_RANGE;
		a->element = (int)l->word;
		return 0;
	}
}
