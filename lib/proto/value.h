/* SPDX-License-Identifier: MPL-2.0 */
/*
 * value - wire bytes <-> typed values (pure). Integers are little-endian;
 * SLC floats little-endian, PLC-5 word-range floats word-swapped (doc/PROTOCOL.md 5);
 * ST strings: LEN(2) + 82 characters, bytes swapped per word.
 */
#ifndef LIBDF1_VALUE_H
#define LIBDF1_VALUE_H

#include "df1.h"

static inline uint16_t le16(const uint8_t *p) { return (uint16_t)(p[0] | (p[1] << 8)); }
static inline uint32_t le32(const uint8_t *p)
{
	return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
static inline void put_le16(uint8_t *p, uint16_t v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); }
static inline void put_le32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); p[2] = (uint8_t)(v >> 16); p[3] = (uint8_t)(v >> 24);
}

/* Bit bitno of a run of elements esize bytes wide (2: 16-bit words, 4: L), counted
 * from bit 0 of the first element, as B3/21 counts (element 1, bit 5). */
static inline bool value_get_bit(const uint8_t *p, size_t esize, size_t bitno)
{
	size_t wbits = esize * 8;
	const uint8_t *q = p + bitno / wbits * esize;
	uint32_t w = esize == 4 ? le32(q) : le16(q);

	return (w >> (bitno % wbits)) & 1u;
}

/* A masked write of one bit (SLC 0F/AB, PLC-5 0F/26, PLC-2 05): set it in the
 * mask, and in the data when on; other bits stay untouched on the PLC. */
static inline void value_mask_bit(uint32_t *mask, uint32_t *data, unsigned bit, bool on)
{
	*mask |= 1u << bit;
	if (on)
		*data |= 1u << bit;
}

enum value_float_order { VALUE_FLOAT_LE = 0, VALUE_FLOAT_WORD_SWAPPED = 1 };

/* The float order of the element commands of a PLC type: plain LE (SLC A2/AA, and
 * PLC-5 typed 0F/68 67 as doc/PROTOCOL.md 5 recommends), word-swapped for a PLC-5 when
 * DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED is set (the doc/PROTOCOL.md 8 item 7 alternative). */
static inline enum value_float_order value_typed_float_order(enum df1_plc plc, bool plc5_swapped)
{
	return plc == DF1_PLC_PLC5 && plc5_swapped ? VALUE_FLOAT_WORD_SWAPPED : VALUE_FLOAT_LE;
}

float value_get_float(const uint8_t *p, enum value_float_order o);
void value_put_float(uint8_t *p, float f, enum value_float_order o);
/* ST element (84 bytes) <-> text; put fails with DF1_E_RANGE above 82 characters. */
int value_get_string(const uint8_t *p84, char *out, size_t cap);
int value_put_string(uint8_t *p84, const char *text);
/* One value of kind k from / to the wire bytes at p, the caller having checked that
 * they are there (an element, or a sub-element word): the codec of the two below.
 * Returns 0, or DF1_E_TYPE / DF1_E_RANGE (encode), DF1_E_RANGE (a string's LEN over
 * 82), DF1_E_INVAL (a kind without bytes, such as a bit). */
int value_decode_kind(enum df1_value_kind k, const uint8_t *p, struct df1_value *v,
                      enum value_float_order o);
int value_encode_kind(enum df1_value_kind k, const struct df1_value *v, uint8_t *p,
                      enum value_float_order o);
/* One element of file type t from / to wire bytes (element size per type). */
int value_decode_element(enum df1_file_type t, const uint8_t *p, size_t n, struct df1_value *v,
                         enum value_float_order o);
int value_encode_element(enum df1_file_type t, const struct df1_value *v, uint8_t *p, size_t cap,
                         enum value_float_order o);

#endif
