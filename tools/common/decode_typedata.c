/* SPDX-License-Identifier: MPL-2.0 */
/*
 * decode_typedata - the parts of a command's bytes that say what its data is:
 * the type/data parameter (doc/PROTOCOL.md 4.3) of typed commands, PLC-5 system addresses
 * (doc/PROTOCOL.md 4.1), and the file type the values of an address decode as (see
 * decode_int.h).
 */
#include "common/decode_int.h"

/* ---- type/data parameter (doc/PROTOCOL.md 4.3): flag byte, then ID and size bytes (LE) ---- */

static int typedata_parse(const uint8_t *p, size_t n, unsigned *id, uint32_t *size)
{
	size_t i = 1;
	unsigned tf, sf, k, j;

	if (n < 1)
		return -1;
	tf = p[0] >> 4;
	sf = p[0] & 0x0F;
	if (tf & 8) {
		k = tf & 7;
		if (k == 0 || k > 4 || i + k > n)
			return -1;
		*id = 0;
		for (j = 0; j < k; j++)
			*id |= (unsigned)p[i + j] << (8 * j);
		i += k;
	} else {
		*id = tf;
	}
	if (sf & 8) {
		k = sf & 7;
		if (k == 0 || k > 4 || i + k > n)
			return -1;
		*size = 0;
		for (j = 0; j < k; j++)
			*size |= (uint32_t)p[i + j] << (8 * j);
		i += k;
	} else {
		*size = sf;
	}
	return (int)i;
}

/* File type of a typed-data element (type ID, element size in bytes). */
static enum df1_file_type typedata_file_type(unsigned id, uint32_t size)
{
	switch (id) {
	case 3: return DF1_FT_ST;
	case 4: return size == 4 ? DF1_FT_L : DF1_FT_N;
	case 5: return size == 6 ? DF1_FT_T : DF1_FT_N;
	case 6: return size == 6 ? DF1_FT_C : DF1_FT_N;
	case 7: return size == 6 ? DF1_FT_R : DF1_FT_N;
	case 8: return DF1_FT_F;
	default: return DF1_FT_N;
	}
}

/* Skip the type/data parameter in front of typed data (an array's descriptor
 * too); returns the offset of the element data and sets *ft, or -1. */
int decode_typedata_skip(const uint8_t *p, size_t n, enum df1_file_type *ft)
{
	unsigned id, eid;
	uint32_t size, esize;
	int k = typedata_parse(p, n, &id, &size), k2;

	if (k < 0)
		return -1;
	if (id == 9) {
		k2 = typedata_parse(p + k, n - (size_t)k, &eid, &esize);
		if (k2 < 0)
			return -1;
		*ft = typedata_file_type(eid, esize);
		return k + k2;
	}
	*ft = typedata_file_type(id, size);
	return k;
}

/* Bytes of a PLC-5 system address (doc/PROTOCOL.md 4.1) at p: logical ASCII 00 '$' text 00,
 * or logical binary: a mask (FF + LE16 above 254), then one field per mask bit,
 * each 1 byte or FF + LE16. -1 if it does not fit in n. */
static int plc5_addr_len(const uint8_t *p, size_t n)
{
	size_t i;
	unsigned mask;

	if (n < 1)
		return -1;
	if (p[0] == 0x00) {
		for (i = 1; i < n; i++)
			if (p[i] == 0x00)
				return (int)i + 1;
		return -1;
	}
	if (p[0] == 0xFF) {
		if (n < 3)
			return -1;
		mask = (unsigned)(p[1] | (p[2] << 8));
		i = 3;
	} else {
		mask = p[0];
		i = 1;
	}
	for (; mask; mask >>= 1) {
		if (!(mask & 1))
			continue;
		if (i >= n)
			return -1;
		i += p[i] == 0xFF ? 3 : 1;
	}
	return i <= n ? (int)i : -1;
}

/* 0F/67: df1_msg_decode points data past the type/data parameter; find that
 * parameter after PKT_OFFSET TOTAL ADDRESS (app bytes 7.., doc/PROTOCOL.md 4.3) and read the
 * element type from it. Returns false if it does not end where the data starts. */
bool decode_typedata_before(const uint8_t *app, const uint8_t *data, enum df1_file_type *ft)
{
	size_t start = 7 + 4, end;
	int a, k;

	if (data < app || (size_t)(data - app) <= start)
		return false;
	end = (size_t)(data - app);
	a = plc5_addr_len(app + start, end - start);
	if (a < 0 || start + (size_t)a >= end)
		return false;
	start += (size_t)a;
	k = decode_typedata_skip(app + start, end - start, ft);
	return k > 0 && start + (size_t)k == end;
}

/* The file type element values of an address decode as. */
enum df1_file_type decode_value_file_type(const struct df1_addr *a)
{
	switch (a->type) {
	case DF1_FT_T: case DF1_FT_C: case DF1_FT_R:
		/* one word of the element (.PRE, .ACC, /DN) rather than the whole element */
		return (a->sub != DF1_ADDR_NONE || a->bit != DF1_ADDR_NONE) ? DF1_FT_N : a->type;
	case DF1_FT_NONE:
		return DF1_FT_N;
	default:
		return a->type;
	}
}
