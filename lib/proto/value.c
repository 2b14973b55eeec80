/* SPDX-License-Identifier: MPL-2.0 */
/*
 * value.c - wire bytes <-> typed values (doc/PROTOCOL.md 5). Pure: no I/O,
 * clock or allocation.
 */
#include "proto/value.h"

#include <string.h>

#define ST_BYTES (2 + DF1_STRING_MAX)   /* LEN word + 82 characters */

float value_get_float(const uint8_t *p, enum value_float_order o)
{
	uint32_t u;
	float f;

	/* PLC-5 word range: high-order word first, each word LE (1.5 -> C0 3F 00 00) */
	if (o == VALUE_FLOAT_WORD_SWAPPED)
		u = ((uint32_t)le16(p) << 16) | le16(p + 2);
	else
		u = le32(p);
	memcpy(&f, &u, sizeof f);
	return f;
}

void value_put_float(uint8_t *p, float f, enum value_float_order o)
{
	uint32_t u;

	memcpy(&u, &f, sizeof u);
	if (o == VALUE_FLOAT_WORD_SWAPPED) {
		put_le16(p, (uint16_t)(u >> 16));
		put_le16(p + 2, (uint16_t)u);
	} else {
		put_le32(p, u);
	}
}

/* Characters are byte-swapped within each word: character i lives at 2 + (i ^ 1). */
int value_get_string(const uint8_t *p84, char *out, size_t cap)
{
	uint16_t len;

	if (!p84 || !out)
		return DF1_E_INVAL;
	len = le16(p84);
	if (len > DF1_STRING_MAX)
		return DF1_E_RANGE;
	if (cap < (size_t)len + 1)
		return DF1_E_NOSPACE;
	for (unsigned i = 0; i < len; i++)
		out[i] = (char)p84[2 + (i ^ 1u)];
	out[len] = '\0';
	return len;
}

static int value_put_string_n(uint8_t *p84, const char *text, size_t len)
{
	if (len > DF1_STRING_MAX)
		return DF1_E_RANGE;
	put_le16(p84, (uint16_t)len);
	memset(p84 + 2, 0, DF1_STRING_MAX);     /* unused characters go out as zeros */
	for (size_t i = 0; i < len; i++)
		p84[2 + (i ^ 1u)] = (uint8_t)text[i];
	return (int)len;
}

int value_put_string(uint8_t *p84, const char *text)
{
	if (!p84 || !text)
		return DF1_E_INVAL;
	return value_put_string_n(p84, text, strlen(text));
}

/* The kind and wire size of one element of file type t (0 when t holds no elements).
 * Sizes come from the one file-type table in addr.c. */
static size_t value_elem_layout(enum df1_file_type t, enum df1_value_kind *k)
{
	int size = df1_file_type_element_size(t);

	if (size <= 0)
		return 0;
	switch (t) {
	case DF1_FT_L:
		*k = DF1_VAL_INT32;
		break;
	case DF1_FT_F:
		*k = DF1_VAL_FLOAT;
		break;
	case DF1_FT_ST:
		*k = DF1_VAL_STRING;
		break;
	case DF1_FT_T: case DF1_FT_C: case DF1_FT_R:
		*k = DF1_VAL_TCR;
		break;
	default:
		*k = DF1_VAL_INT16;
		break;
	}
	return (size_t)size;
}

int value_decode_kind(enum df1_value_kind k, const uint8_t *p, struct df1_value *v,
                      enum value_float_order o)
{
	int r;

	memset(v, 0, sizeof *v);
	v->kind = k;
	switch (k) {
	case DF1_VAL_INT16:
		v->v.i16 = (int16_t)le16(p);
		break;
	case DF1_VAL_INT32:
		v->v.i32 = (int32_t)le32(p);
		break;
	case DF1_VAL_FLOAT:
		v->v.f = value_get_float(p, o);
		break;
	case DF1_VAL_STRING:
		r = value_get_string(p, v->v.str.text, sizeof v->v.str.text);
		if (r < 0)
			return r;
		v->v.str.len = (uint16_t)r;
		break;
	case DF1_VAL_TCR:
		v->v.tcr.ctl = le16(p);
		v->v.tcr.pre = (int16_t)le16(p + 2);
		v->v.tcr.acc = (int16_t)le16(p + 4);
		break;
	default:
		return DF1_E_INVAL;
	}
	return 0;
}

int value_decode_element(enum df1_file_type t, const uint8_t *p, size_t n, struct df1_value *v,
                         enum value_float_order o)
{
	enum df1_value_kind k = DF1_VAL_INT16;
	size_t size = value_elem_layout(t, &k);
	int r;

	if (!p || !v || size == 0)
		return DF1_E_INVAL;
	if (n < size)
		return DF1_E_TOO_SHORT;
	r = value_decode_kind(k, p, v, o);
	return r < 0 ? r : (int)size;
}

/* An integer value of either width, for the lossless int16 <-> int32 conversions. */
static bool value_int(const struct df1_value *v, int64_t *out)
{
	if (v->kind == DF1_VAL_INT16)
		*out = v->v.i16;
	else if (v->kind == DF1_VAL_INT32)
		*out = v->v.i32;
	else
		return false;
	return true;
}

int value_encode_kind(enum df1_value_kind k, const struct df1_value *v, uint8_t *p,
                      enum value_float_order o)
{
	int64_t i;
	int r;

	switch (k) {
	case DF1_VAL_INT16:
		if (!value_int(v, &i))
			return DF1_E_TYPE;
		if (i < INT16_MIN || i > INT16_MAX)
			return DF1_E_RANGE;
		put_le16(p, (uint16_t)(int16_t)i);
		break;
	case DF1_VAL_INT32:
		if (!value_int(v, &i))
			return DF1_E_TYPE;
		put_le32(p, (uint32_t)(int32_t)i);
		break;
	case DF1_VAL_FLOAT:
		if (v->kind != DF1_VAL_FLOAT)
			return DF1_E_TYPE;
		value_put_float(p, v->v.f, o);
		break;
	case DF1_VAL_STRING:
		if (v->kind != DF1_VAL_STRING)
			return DF1_E_TYPE;
		if (v->v.str.len > DF1_STRING_MAX)
			return DF1_E_RANGE;
		r = value_put_string_n(p, v->v.str.text, v->v.str.len);
		if (r < 0)
			return r;
		break;
	case DF1_VAL_TCR:
		if (v->kind != DF1_VAL_TCR)
			return DF1_E_TYPE;
		put_le16(p, v->v.tcr.ctl);
		put_le16(p + 2, (uint16_t)v->v.tcr.pre);
		put_le16(p + 4, (uint16_t)v->v.tcr.acc);
		break;
	default:
		return DF1_E_INVAL;
	}
	return 0;
}

int value_encode_element(enum df1_file_type t, const struct df1_value *v, uint8_t *p, size_t cap,
                         enum value_float_order o)
{
	enum df1_value_kind k = DF1_VAL_INT16;
	size_t size = value_elem_layout(t, &k);
	int r;

	if (!p || !v || size == 0)
		return DF1_E_INVAL;
	if (cap < size)
		return DF1_E_NOSPACE;
	r = value_encode_kind(k, v, p, o);
	return r < 0 ? r : (int)size;
}
