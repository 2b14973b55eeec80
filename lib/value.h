/*
 * value - wire bytes <-> typed values (pure). Integers are little-endian;
 * SLC floats little-endian, PLC-5 word-range floats word-swapped (spec 5);
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

enum value_float_order { VALUE_FLOAT_LE = 0, VALUE_FLOAT_WORD_SWAPPED = 1 };

float value_get_float(const uint8_t *p, enum value_float_order o);
void value_put_float(uint8_t *p, float f, enum value_float_order o);
/* ST element (84 bytes) <-> text; put fails with DF1_E_RANGE above 82 characters. */
int value_get_string(const uint8_t *p84, char *out, size_t cap);
int value_put_string(uint8_t *p84, const char *text);
/* One element of file type t from / to wire bytes (element size per type). */
int value_decode_element(enum df1_file_type t, const uint8_t *p, size_t n, struct df1_value *v,
                         enum value_float_order o);
int value_encode_element(enum df1_file_type t, const struct df1_value *v, uint8_t *p, size_t cap,
                         enum value_float_order o);

#endif
