/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_value.c - wire encodings of values (doc/PROTOCOL.md 5) and the public
 * text helpers: df1_value_format, df1_value_parse, df1_tcr_bit,
 * df1_addr_value_kind, df1_values_decode.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "df1.h"
#include "proto/value.h"

/* A float constant as a float: where FLT_EVAL_METHOD is 1 (gcc -std=c11 on
 * s390x) 0.1f is evaluated as the double 0.1, and a float holding 0.1f
 * compares unequal to it; the cast rounds it to float. */
#define F32(x) ((float)(x))

static struct df1_addr mk(enum df1_file_type t, int file, int elem, int sub, int bit)
{
	struct df1_addr a;

	memset(&a, 0, sizeof a);
	a.type = t;
	a.file = file;
	a.element = elem;
	a.sub = sub;
	a.bit = bit;
	return a;
}

#define NONE DF1_ADDR_NONE

/* ------------------------------------------------------------------------
 * Wire encodings
 * ------------------------------------------------------------------------ */

static void test_value_float_le_and_word_swapped(void **state)
{
	/* 1.5 = 3FC00000h: LE 00 00 C0 3F; PLC-5 word range C0 3F 00 00 (doc/PROTOCOL.md 5) */
	static const uint8_t le[] = { 0x00, 0x00, 0xC0, 0x3F }, sw[] = { 0xC0, 0x3F, 0x00, 0x00 };
	/* -2.25 = C0100000h; 1.0e-3 = 3A83126Fh */
	static const uint8_t le2[] = { 0x6F, 0x12, 0x83, 0x3A }, sw2[] = { 0x83, 0x3A, 0x6F, 0x12 };
	uint8_t b[4];
	(void)state;

	assert_true(value_get_float(le, VALUE_FLOAT_LE) == 1.5f);
	assert_true(value_get_float(sw, VALUE_FLOAT_WORD_SWAPPED) == 1.5f);
	assert_true(value_get_float(le2, VALUE_FLOAT_LE) == F32(1.0e-3f));
	assert_true(value_get_float(sw2, VALUE_FLOAT_WORD_SWAPPED) == F32(1.0e-3f));
	value_put_float(b, 1.5f, VALUE_FLOAT_LE);
	assert_memory_equal(b, le, 4);
	value_put_float(b, 1.5f, VALUE_FLOAT_WORD_SWAPPED);
	assert_memory_equal(b, sw, 4);
	value_put_float(b, -2.25f, VALUE_FLOAT_LE);
	assert_memory_equal(b, "\x00\x00\x10\xC0", 4);
	value_put_float(b, 1.0e-3f, VALUE_FLOAT_WORD_SWAPPED);
	assert_memory_equal(b, sw2, 4);
}

static void test_value_string_pairs_swapped(void **state)
{
	uint8_t b[84], want[84];
	char text[100];
	(void)state;

	/* "ABC" -> 03 00 42 41 00 43 00 ... (doc/PROTOCOL.md 5) */
	memset(want, 0, sizeof want);
	want[0] = 0x03;
	want[2] = 0x42;
	want[3] = 0x41;
	want[5] = 0x43;
	memset(b, 0xEE, sizeof b);
	assert_int_equal(value_put_string(b, "ABC"), 3);
	assert_memory_equal(b, want, 84);
	assert_int_equal(value_get_string(b, text, sizeof text), 3);
	assert_string_equal(text, "ABC");

	/* "ABCD" -> 04 00 42 41 44 43 */
	assert_int_equal(value_put_string(b, "ABCD"), 4);
	assert_memory_equal(b, "\x04\x00\x42\x41\x44\x43\x00\x00", 8);

	/* 82 characters fill the element; the 82nd sits at byte 82, the 81st at 83 */
	memset(text, 0, sizeof text);
	for (int i = 0; i < 82; i++)
		text[i] = (char)('a' + i % 26);
	assert_int_equal(value_put_string(b, text), 82);
	assert_int_equal(b[0], 82);
	assert_int_equal(b[1], 0);
	assert_int_equal(b[82], (uint8_t)text[81]);
	assert_int_equal(b[83], (uint8_t)text[80]);
	{
		char back[100];

		assert_int_equal(value_get_string(b, back, sizeof back), 82);
		assert_string_equal(back, text);
		assert_int_equal(value_get_string(b, back, 82), DF1_E_NOSPACE);
	}
	text[82] = 'x';
	assert_int_equal(value_put_string(b, text), DF1_E_RANGE);

	b[0] = 83;                      /* a LEN the element cannot hold */
	assert_int_equal(value_get_string(b, text, sizeof text), DF1_E_RANGE);
}

static void test_value_decode_elements(void **state)
{
	static const uint8_t n[] = { 0xFF, 0xFF }, l[] = { 0x00, 0x00, 0x00, 0x80 };
	static const uint8_t t[] = { 0x00, 0xA0, 0x64, 0x00, 0x2A, 0x00 };
	static const uint8_t f[] = { 0x00, 0x00, 0xC0, 0x3F };
	struct df1_value v;
	(void)state;

	assert_int_equal(value_decode_element(DF1_FT_N, n, 2, &v, VALUE_FLOAT_LE), 2);
	assert_int_equal(v.kind, DF1_VAL_INT16);
	assert_int_equal(v.v.i16, -1);
	assert_int_equal(value_decode_element(DF1_FT_L, l, 4, &v, VALUE_FLOAT_LE), 4);
	assert_int_equal(v.kind, DF1_VAL_INT32);
	assert_int_equal(v.v.i32, INT32_MIN);
	assert_int_equal(value_decode_element(DF1_FT_F, f, 4, &v, VALUE_FLOAT_LE), 4);
	assert_true(v.v.f == 1.5f);
	assert_int_equal(value_decode_element(DF1_FT_T, t, 6, &v, VALUE_FLOAT_LE), 6);
	assert_int_equal(v.kind, DF1_VAL_TCR);
	assert_int_equal(v.v.tcr.ctl, 0xA000);
	assert_int_equal(v.v.tcr.pre, 100);
	assert_int_equal(v.v.tcr.acc, 42);
	assert_int_equal(value_decode_element(DF1_FT_T, t, 5, &v, VALUE_FLOAT_LE), DF1_E_TOO_SHORT);
	assert_int_equal(value_decode_element(DF1_FT_NONE, t, 6, &v, VALUE_FLOAT_LE), DF1_E_INVAL);
}

static void test_value_encode_elements(void **state)
{
	struct df1_value v;
	uint8_t b[84];
	(void)state;

	memset(&v, 0, sizeof v);
	v.kind = DF1_VAL_INT16;
	v.v.i16 = -2;
	assert_int_equal(value_encode_element(DF1_FT_N, &v, b, sizeof b, VALUE_FLOAT_LE), 2);
	assert_memory_equal(b, "\xFE\xFF", 2);
	/* an int16 widens into L */
	assert_int_equal(value_encode_element(DF1_FT_L, &v, b, sizeof b, VALUE_FLOAT_LE), 4);
	assert_memory_equal(b, "\xFE\xFF\xFF\xFF", 4);
	/* an int32 narrows into N only when it fits */
	v.kind = DF1_VAL_INT32;
	v.v.i32 = 32767;
	assert_int_equal(value_encode_element(DF1_FT_N, &v, b, sizeof b, VALUE_FLOAT_LE), 2);
	assert_memory_equal(b, "\xFF\x7F", 2);
	v.v.i32 = 32768;
	assert_int_equal(value_encode_element(DF1_FT_N, &v, b, sizeof b, VALUE_FLOAT_LE), DF1_E_RANGE);
	assert_int_equal(value_encode_element(DF1_FT_F, &v, b, sizeof b, VALUE_FLOAT_LE), DF1_E_TYPE);

	v.kind = DF1_VAL_FLOAT;
	v.v.f = 1.5f;
	assert_int_equal(value_encode_element(DF1_FT_F, &v, b, sizeof b, VALUE_FLOAT_WORD_SWAPPED), 4);
	assert_memory_equal(b, "\xC0\x3F\x00\x00", 4);
	assert_int_equal(value_encode_element(DF1_FT_N, &v, b, sizeof b, VALUE_FLOAT_LE), DF1_E_TYPE);
	assert_int_equal(value_encode_element(DF1_FT_F, &v, b, 3, VALUE_FLOAT_LE), DF1_E_NOSPACE);

	v.kind = DF1_VAL_TCR;
	v.v.tcr.ctl = 0x8000;
	v.v.tcr.pre = -1;
	v.v.tcr.acc = 258;
	assert_int_equal(value_encode_element(DF1_FT_C, &v, b, sizeof b, VALUE_FLOAT_LE), 6);
	assert_memory_equal(b, "\x00\x80\xFF\xFF\x02\x01", 6);

	v.kind = DF1_VAL_STRING;
	v.v.str.len = 2;
	strcpy(v.v.str.text, "Hi");
	assert_int_equal(value_encode_element(DF1_FT_ST, &v, b, sizeof b, VALUE_FLOAT_LE), 84);
	assert_memory_equal(b, "\x02\x00\x69\x48", 4);
	v.v.str.len = 83;
	assert_int_equal(value_encode_element(DF1_FT_ST, &v, b, sizeof b, VALUE_FLOAT_LE), DF1_E_RANGE);
}

/* ------------------------------------------------------------------------
 * T/C/R bits
 * ------------------------------------------------------------------------ */

struct bit_case {
	enum df1_file_type t;
	const char *name;
	int bit;
};

/* RM001 p.29-30; R per doc/PROTOCOL.md 5 */
static const struct bit_case all_bits[] = {
	{ DF1_FT_T, "EN", 15 }, { DF1_FT_T, "TT", 14 }, { DF1_FT_T, "DN", 13 },
	{ DF1_FT_C, "CU", 15 }, { DF1_FT_C, "CD", 14 }, { DF1_FT_C, "DN", 13 },
	{ DF1_FT_C, "OV", 12 }, { DF1_FT_C, "UN", 11 }, { DF1_FT_C, "UA", 10 },
	{ DF1_FT_R, "EN", 15 }, { DF1_FT_R, "EU", 14 }, { DF1_FT_R, "DN", 13 },
	{ DF1_FT_R, "EM", 12 }, { DF1_FT_R, "ER", 11 }, { DF1_FT_R, "UL", 10 },
	{ DF1_FT_R, "IN", 9 }, { DF1_FT_R, "FD", 8 },
};

static void test_value_tcr_bit_names(void **state)
{
	(void)state;
	for (size_t i = 0; i < sizeof all_bits / sizeof all_bits[0]; i++)
		assert_int_equal(df1_tcr_bit(all_bits[i].t, all_bits[i].name), all_bits[i].bit);
	assert_int_equal(df1_tcr_bit(DF1_FT_T, "dn"), 13);
	assert_int_equal(df1_tcr_bit(DF1_FT_T, "CU"), -1);
	assert_int_equal(df1_tcr_bit(DF1_FT_C, "TT"), -1);
	assert_int_equal(df1_tcr_bit(DF1_FT_R, "TT"), -1);
	assert_int_equal(df1_tcr_bit(DF1_FT_N, "DN"), -1);
	assert_int_equal(df1_tcr_bit(DF1_FT_T, "PRE"), -1);
	assert_int_equal(df1_tcr_bit(DF1_FT_T, NULL), -1);
}

/* Each named bit alone shows as NAME=1 and every other as 0. */
static void test_value_format_every_named_bit(void **state)
{
	struct df1_value v;
	char buf[128], want[16], other[16];
	(void)state;

	memset(&v, 0, sizeof v);
	v.kind = DF1_VAL_TCR;
	for (size_t i = 0; i < sizeof all_bits / sizeof all_bits[0]; i++) {
		v.v.tcr.ctl = (uint16_t)(1u << all_bits[i].bit);
		assert_true(df1_value_format(&v, all_bits[i].t, buf, sizeof buf) > 0);
		snprintf(want, sizeof want, "%s=1", all_bits[i].name);
		assert_non_null(strstr(buf, want));
		for (size_t j = 0; j < sizeof all_bits / sizeof all_bits[0]; j++) {
			if (all_bits[j].t != all_bits[i].t || j == i)
				continue;
			snprintf(other, sizeof other, "%s=0", all_bits[j].name);
			assert_non_null(strstr(buf, other));
		}
	}
}

/* Status bits without a name (a timer's bits 0-12 hold the PLC's own state)
 * are kept: the text of a read, written back, restores the whole word. */
static void test_value_format_tcr_unnamed_bits_round_trip(void **state)
{
	static const struct { enum df1_file_type t; int file; uint16_t ctl; } cases[] = {
		{ DF1_FT_T, 4, 0xA009 }, { DF1_FT_C, 5, 0x0008 }, { DF1_FT_R, 6, 0x0009 },
		{ DF1_FT_T, 4, 0x1FFF }, { DF1_FT_C, 5, 0x8001 }, { DF1_FT_R, 6, 0xFFFF },
	};
	struct df1_value v, back;
	char buf[160];
	(void)state;

	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		struct df1_addr a = mk(cases[i].t, cases[i].file, 0, NONE, NONE);
		memset(&v, 0, sizeof v);
		v.kind = DF1_VAL_TCR;
		v.v.tcr.ctl = cases[i].ctl;
		v.v.tcr.pre = 7;
		v.v.tcr.acc = -2;
		assert_true(df1_value_format(&v, cases[i].t, buf, sizeof buf) > 0);
		assert_int_equal(df1_value_parse(&a, buf, &back), 0);
		assert_int_equal(back.v.tcr.ctl, cases[i].ctl);
		assert_int_equal(back.v.tcr.pre, 7);
		assert_int_equal(back.v.tcr.acc, -2);
	}
	/* the whole word follows the names when a bit has none */
	memset(&v, 0, sizeof v);
	v.kind = DF1_VAL_TCR;
	v.v.tcr.ctl = 0xA009;
	v.v.tcr.pre = 100;
	v.v.tcr.acc = 42;
	df1_value_format(&v, DF1_FT_T, buf, sizeof buf);
	assert_string_equal(buf, "EN=1 TT=0 DN=1 PRE=100 ACC=42 CTL=0xA009");
}

static void test_value_format_tcr_text(void **state)
{
	struct df1_value v;
	char buf[128];
	struct df1_value back;
	struct df1_addr t4 = mk(DF1_FT_T, 4, 0, NONE, NONE);
	(void)state;

	memset(&v, 0, sizeof v);
	v.kind = DF1_VAL_TCR;
	v.v.tcr.ctl = (1u << 15) | (1u << 13);
	v.v.tcr.pre = 100;
	v.v.tcr.acc = 42;
	assert_int_equal(df1_value_format(&v, DF1_FT_T, buf, sizeof buf), 29);
	assert_string_equal(buf, "EN=1 TT=0 DN=1 PRE=100 ACC=42");
	assert_int_equal(df1_value_format(&v, DF1_FT_T, buf, 29), DF1_E_NOSPACE);
	assert_int_equal(df1_value_format(&v, DF1_FT_T, buf, 30), 29);

	v.v.tcr.ctl = 1u << 12;
	v.v.tcr.pre = 10;
	v.v.tcr.acc = -3;
	df1_value_format(&v, DF1_FT_C, buf, sizeof buf);
	assert_string_equal(buf, "CU=0 CD=0 DN=0 OV=1 UN=0 UA=0 PRE=10 ACC=-3");

	v.v.tcr.ctl = (1u << 9) | (1u << 8);
	v.v.tcr.pre = 8;
	v.v.tcr.acc = 2;
	df1_value_format(&v, DF1_FT_R, buf, sizeof buf);
	assert_string_equal(buf, "EN=0 EU=0 DN=0 EM=0 ER=0 UL=0 IN=1 FD=1 LEN=8 POS=2");

	df1_value_format(&v, DF1_FT_N, buf, sizeof buf);
	assert_string_equal(buf, "CTL=0x0300 PRE=8 ACC=2");

	/* parse reads what format writes */
	v.v.tcr.ctl = (1u << 15) | (1u << 13);
	v.v.tcr.pre = 100;
	v.v.tcr.acc = 42;
	df1_value_format(&v, DF1_FT_T, buf, sizeof buf);
	assert_int_equal(df1_value_parse(&t4, buf, &back), 0);
	assert_int_equal(back.kind, DF1_VAL_TCR);
	assert_int_equal(back.v.tcr.ctl, 0xA000);
	assert_int_equal(back.v.tcr.pre, 100);
	assert_int_equal(back.v.tcr.acc, 42);
}

/* ------------------------------------------------------------------------
 * Formatting numbers
 * ------------------------------------------------------------------------ */

static const char *fmt_i16(int16_t x, char *buf, size_t cap)
{
	struct df1_value v = { .kind = DF1_VAL_INT16 };

	v.v.i16 = x;
	assert_true(df1_value_format(&v, DF1_FT_N, buf, cap) > 0);
	return buf;
}

static const char *fmt_f(float f, char *buf, size_t cap)
{
	struct df1_value v = { .kind = DF1_VAL_FLOAT };

	v.v.f = f;
	assert_true(df1_value_format(&v, DF1_FT_F, buf, cap) > 0);
	return buf;
}

static void test_value_format_integers_and_bits(void **state)
{
	char buf[32];
	struct df1_value v = { .kind = DF1_VAL_INT32 };
	(void)state;

	assert_string_equal(fmt_i16(-32768, buf, sizeof buf), "-32768");
	assert_string_equal(fmt_i16(32767, buf, sizeof buf), "32767");
	assert_string_equal(fmt_i16(0, buf, sizeof buf), "0");
	assert_string_equal(fmt_i16(-1, buf, sizeof buf), "-1");
	v.v.i32 = INT32_MIN;
	assert_int_equal(df1_value_format(&v, DF1_FT_L, buf, sizeof buf), 11);
	assert_string_equal(buf, "-2147483648");
	v.kind = DF1_VAL_BIT;
	v.v.bit = true;
	assert_int_equal(df1_value_format(&v, DF1_FT_B, buf, sizeof buf), 1);
	assert_string_equal(buf, "1");
	v.v.bit = false;
	df1_value_format(&v, DF1_FT_B, buf, sizeof buf);
	assert_string_equal(buf, "0");
	v.kind = DF1_VAL_STRING;
	strcpy(v.v.str.text, "Hello, PLC");
	v.v.str.len = 10;
	assert_int_equal(df1_value_format(&v, DF1_FT_ST, buf, sizeof buf), 10);
	assert_string_equal(buf, "Hello, PLC");
	assert_int_equal(df1_value_format(&v, DF1_FT_ST, buf, 10), DF1_E_NOSPACE);
	assert_int_equal(df1_value_format(&v, DF1_FT_ST, buf, 0), DF1_E_NOSPACE);
}

static void test_value_format_float_shortest(void **state)
{
	char buf[32];
	(void)state;

	assert_string_equal(fmt_f(0.1f, buf, sizeof buf), "0.1");
	assert_string_equal(fmt_f(1.5f, buf, sizeof buf), "1.5");
	assert_string_equal(fmt_f(1e-45f, buf, sizeof buf), "1e-45");        /* smallest subnormal */
	assert_string_equal(fmt_f(FLT_MAX, buf, sizeof buf), "3.4028235e+38");
	assert_string_equal(fmt_f(-FLT_MAX, buf, sizeof buf), "-3.4028235e+38");
	assert_string_equal(fmt_f(FLT_MIN, buf, sizeof buf), "1.1754944e-38");
	assert_string_equal(fmt_f(1.0f / 3.0f, buf, sizeof buf), "0.33333334");
	assert_string_equal(fmt_f(100.0f, buf, sizeof buf), "100");
	assert_string_equal(fmt_f(16777216.0f, buf, sizeof buf), "16777216");
	assert_string_equal(fmt_f(123456.7f, buf, sizeof buf), "123456.7");
	assert_string_equal(fmt_f(1e9f, buf, sizeof buf), "1e+09");
	assert_string_equal(fmt_f(0.0001f, buf, sizeof buf), "0.0001");
	assert_string_equal(fmt_f(0.00001f, buf, sizeof buf), "1e-05");
	assert_string_equal(fmt_f(-2.25f, buf, sizeof buf), "-2.25");
	assert_string_equal(fmt_f(0.0f, buf, sizeof buf), "0");
	assert_string_equal(fmt_f(-0.0f, buf, sizeof buf), "-0");
	assert_string_equal(fmt_f(INFINITY, buf, sizeof buf), "inf");
	assert_string_equal(fmt_f(-INFINITY, buf, sizeof buf), "-inf");
	assert_string_equal(fmt_f(NAN, buf, sizeof buf), "nan");
}

/* Count significant digits of a formatted float ("-1.25e+07" -> 3). */
static int sig_digits(const char *s)
{
	int n = 0, lead = 1, trail = 0;

	for (; *s && *s != 'e'; s++) {
		if (*s < '0' || *s > '9')
			continue;
		if (lead && *s == '0')
			continue;
		lead = 0;
		n++;
		trail = *s == '0' ? trail + 1 : 0;
	}
	return n - trail;
}

/* Random bit patterns: the text reads back exactly and no shorter %e text does. */
static void test_value_format_float_round_trip_random(void **state)
{
	unsigned seed = 20240611u;
	(void)state;

	print_message("float round trip seed %u\n", seed);
	srand(seed);
	for (int i = 0; i < 20000; i++) {
		uint32_t u = ((uint32_t)rand() << 16) ^ (uint32_t)rand();
		float f, back;
		char buf[32], shorter[32];
		int nd;

		memcpy(&f, &u, sizeof f);
		if (isnan(f) || isinf(f))
			continue;
		fmt_f(f, buf, sizeof buf);
		back = strtof(buf, NULL);
		assert_memory_equal(&back, &f, sizeof f);
		nd = sig_digits(buf);
		if (nd > 1) {
			snprintf(shorter, sizeof shorter, "%.*e", nd - 2, (double)f);
			back = strtof(shorter, NULL);
			assert_true(memcmp(&back, &f, sizeof f) != 0);
		}
	}
}

/* ------------------------------------------------------------------------
 * Parsing
 * ------------------------------------------------------------------------ */

static void test_value_parse_int16(void **state)
{
	struct df1_addr n7 = mk(DF1_FT_N, 7, 0, NONE, NONE);
	struct df1_value v;
	(void)state;

	assert_int_equal(df1_value_parse(&n7, "-32768", &v), 0);
	assert_int_equal(v.kind, DF1_VAL_INT16);
	assert_int_equal(v.v.i16, -32768);
	assert_int_equal(df1_value_parse(&n7, "32767", &v), 0);
	assert_int_equal(v.v.i16, 32767);
	assert_int_equal(df1_value_parse(&n7, "+5", &v), 0);
	assert_int_equal(v.v.i16, 5);
	assert_int_equal(df1_value_parse(&n7, " 42 ", &v), 0);
	assert_int_equal(v.v.i16, 42);
	assert_int_equal(df1_value_parse(&n7, "0x7FFF", &v), 0);
	assert_int_equal(v.v.i16, 32767);
	assert_int_equal(df1_value_parse(&n7, "0xFFFF", &v), 0);  /* a bit pattern */
	assert_int_equal(v.v.i16, -1);
	assert_int_equal(df1_value_parse(&n7, "0x8000", &v), 0);
	assert_int_equal(v.v.i16, -32768);
	assert_int_equal(df1_value_parse(&n7, "-0x10", &v), 0);
	assert_int_equal(v.v.i16, -16);

	assert_int_equal(df1_value_parse(&n7, "32768", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&n7, "-32769", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&n7, "70000", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&n7, "0x10000", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&n7, "99999999999999999999999", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&n7, "1.5", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "1e3", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "abc", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "4 2", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "--1", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "0x", &v), DF1_E_TYPE);
	/* one 0x prefix, then hex digits only (df1_value_parse(3)): a second
	 * prefix is not a number, whatever strtoull makes of it */
	assert_int_equal(df1_value_parse(&n7, "0x0x12", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "-0x0x1", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "0X0X12", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "+0x0x7", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "0x-1", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "0x 1", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&n7, "0x12", &v), 0);
	assert_int_equal(v.v.i16, 18);
	assert_int_equal(df1_value_parse(&n7, "0X1f", &v), 0);
	assert_int_equal(v.v.i16, 31);

	/* T/C/R words and the other word files are int16 too */
	{
		struct df1_addr acc = mk(DF1_FT_T, 4, 0, 2, NONE);
		struct df1_addr s2 = mk(DF1_FT_S, 2, 1, NONE, NONE);

		assert_int_equal(df1_value_parse(&acc, "-7", &v), 0);
		assert_int_equal(v.kind, DF1_VAL_INT16);
		assert_int_equal(v.v.i16, -7);
		assert_int_equal(df1_value_parse(&s2, "40000", &v), DF1_E_RANGE);
	}
}

static void test_value_parse_int32_float(void **state)
{
	struct df1_addr l = mk(DF1_FT_L, 10, 0, NONE, NONE);
	struct df1_addr f = mk(DF1_FT_F, 8, 0, NONE, NONE);
	struct df1_value v;
	(void)state;

	assert_int_equal(df1_value_parse(&l, "2147483647", &v), 0);
	assert_int_equal(v.kind, DF1_VAL_INT32);
	assert_int_equal(v.v.i32, INT32_MAX);
	assert_int_equal(df1_value_parse(&l, "-2147483648", &v), 0);
	assert_int_equal(v.v.i32, INT32_MIN);
	assert_int_equal(df1_value_parse(&l, "0xFFFFFFFF", &v), 0);
	assert_int_equal(v.v.i32, -1);
	assert_int_equal(df1_value_parse(&l, "2147483648", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&l, "-2147483649", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&l, "2.5", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&l, "0x0x12", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&l, "-0x0x1", &v), DF1_E_TYPE);
	{
		/* the T/C/R items share the integer parser */
		struct df1_addr t4 = mk(DF1_FT_T, 4, 0, NONE, NONE);

		assert_int_equal(df1_value_parse(&t4, "CTL=0x0x8000", &v), DF1_E_TYPE);
		assert_int_equal(df1_value_parse(&t4, "PRE=0x0x5", &v), DF1_E_TYPE);
		assert_int_equal(df1_value_parse(&t4, "PRE=0x10", &v), 0);
		assert_int_equal(v.v.tcr.pre, 16);
	}

	assert_int_equal(df1_value_parse(&f, "1.5", &v), 0);
	assert_int_equal(v.kind, DF1_VAL_FLOAT);
	assert_true(v.v.f == 1.5f);
	assert_int_equal(df1_value_parse(&f, "3", &v), 0);
	assert_true(v.v.f == 3.0f);
	assert_int_equal(df1_value_parse(&f, "-0.1", &v), 0);
	assert_true(v.v.f == F32(-0.1f));
	assert_int_equal(df1_value_parse(&f, "3.4028235e+38", &v), 0);
	assert_true(v.v.f == FLT_MAX);
	assert_int_equal(df1_value_parse(&f, "1e-45", &v), 0);   /* subnormal: kept */
	assert_true(v.v.f > 0.0f && v.v.f < FLT_MIN);
	assert_int_equal(df1_value_parse(&f, "-inf", &v), 0);
	assert_true(isinf(v.v.f) && v.v.f < 0);
	assert_int_equal(df1_value_parse(&f, "1e39", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&f, "-1e39", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&f, "nan", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&f, "1.5x", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&f, "", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&f, "abc", &v), DF1_E_TYPE);
}

static void test_value_parse_bit_string_tcr(void **state)
{
	struct df1_addr b = mk(DF1_FT_B, 3, 0, NONE, 5);
	struct df1_addr dn = mk(DF1_FT_T, 4, 0, 0, 13);
	struct df1_addr st = mk(DF1_FT_ST, 9, 0, NONE, NONE);
	struct df1_addr c5 = mk(DF1_FT_C, 5, 1, NONE, NONE);
	struct df1_value v;
	char text[100];
	(void)state;

	assert_int_equal(df1_value_parse(&b, "1", &v), 0);
	assert_int_equal(v.kind, DF1_VAL_BIT);
	assert_true(v.v.bit);
	assert_int_equal(df1_value_parse(&b, "0", &v), 0);
	assert_false(v.v.bit);
	assert_int_equal(df1_value_parse(&dn, "1", &v), 0);
	assert_int_equal(v.kind, DF1_VAL_BIT);
	assert_int_equal(df1_value_parse(&b, "2", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&b, "-1", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&b, "x", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&b, "0.5", &v), DF1_E_TYPE);

	assert_int_equal(df1_value_parse(&st, "  two spaces  ", &v), 0);
	assert_int_equal(v.kind, DF1_VAL_STRING);
	assert_int_equal(v.v.str.len, 14);
	assert_string_equal(v.v.str.text, "  two spaces  ");
	memset(text, 'z', sizeof text);
	text[82] = '\0';
	assert_int_equal(df1_value_parse(&st, text, &v), 0);
	assert_int_equal(v.v.str.len, 82);
	text[82] = 'z';
	text[83] = '\0';
	assert_int_equal(df1_value_parse(&st, text, &v), DF1_E_RANGE);

	assert_int_equal(df1_value_parse(&c5, "CU=1, OV=1, PRE=10 ACC=-3", &v), 0);
	assert_int_equal(v.kind, DF1_VAL_TCR);
	assert_int_equal(v.v.tcr.ctl, (1u << 15) | (1u << 12));
	assert_int_equal(v.v.tcr.pre, 10);
	assert_int_equal(v.v.tcr.acc, -3);
	assert_int_equal(df1_value_parse(&c5, "ctl=0x8000", &v), 0);
	assert_int_equal(v.v.tcr.ctl, 0x8000);
	assert_int_equal(df1_value_parse(&c5, "TT=1", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&c5, "DN=2", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&c5, "PRE=40000", &v), DF1_E_RANGE);
	assert_int_equal(df1_value_parse(&c5, "PRE", &v), DF1_E_TYPE);
	assert_int_equal(df1_value_parse(&c5, "LEN=1", &v), DF1_E_TYPE);
	{
		struct df1_addr r6 = mk(DF1_FT_R, 6, 0, NONE, NONE);

		assert_int_equal(df1_value_parse(&r6, "FD=1 LEN=8 POS=2", &v), 0);
		assert_int_equal(v.v.tcr.ctl, 1u << 8);
		assert_int_equal(v.v.tcr.pre, 8);
		assert_int_equal(v.v.tcr.acc, 2);
	}
}

/* parse(format(v)) == v for numbers at the edges */
static void test_value_parse_reads_format(void **state)
{
	static const float fs[] = { 0.1f, 1.5f, 1e-45f, FLT_MAX, -FLT_MIN, 123456.7f, 1e9f, -0.0f };
	struct df1_addr f = mk(DF1_FT_F, 8, 0, NONE, NONE);
	struct df1_value v, back;
	char buf[32];
	(void)state;

	for (size_t i = 0; i < sizeof fs / sizeof fs[0]; i++) {
		v.kind = DF1_VAL_FLOAT;
		v.v.f = fs[i];
		assert_true(df1_value_format(&v, DF1_FT_F, buf, sizeof buf) > 0);
		assert_int_equal(df1_value_parse(&f, buf, &back), 0);
		assert_memory_equal(&back.v.f, &fs[i], sizeof(float));
	}
}

/* ------------------------------------------------------------------------
 * Kinds and df1_values_decode
 * ------------------------------------------------------------------------ */

static void test_value_addr_kinds(void **state)
{
	struct df1_addr a;
	(void)state;

	a = mk(DF1_FT_N, 7, 0, NONE, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_INT16);
	a = mk(DF1_FT_N, 7, 0, NONE, 3);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_BIT);
	a = mk(DF1_FT_B, 3, 0, NONE, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_INT16);
	a = mk(DF1_FT_S, 2, 1, NONE, 5);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_BIT);
	a = mk(DF1_FT_I, 1, 0, 1, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_INT16);
	a = mk(DF1_FT_A, 11, 0, NONE, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_INT16);
	a = mk(DF1_FT_L, 10, 0, NONE, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_INT32);
	a = mk(DF1_FT_L, 10, 0, NONE, 31);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_BIT);
	a = mk(DF1_FT_F, 8, 0, NONE, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_FLOAT);
	a = mk(DF1_FT_ST, 9, 0, NONE, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_STRING);
	a = mk(DF1_FT_T, 4, 0, NONE, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_TCR);
	a = mk(DF1_FT_C, 5, 0, 1, NONE);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_INT16);
	a = mk(DF1_FT_R, 6, 0, 0, 13);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_BIT);

	/* through the address parser */
	assert_int_equal(df1_addr_parse("T4:0/DN", &a), 0);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_BIT);
	assert_int_equal(df1_addr_parse("T4:0.ACC", &a), 0);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_INT16);
	assert_int_equal(df1_addr_parse("B3/21", &a), 0);
	assert_int_equal(df1_addr_value_kind(&a), DF1_VAL_BIT);
}

static void test_values_decode_elements(void **state)
{
	static const uint8_t n[] = { 0x00, 0x00, 0x01, 0x00, 0xFF, 0xFF, 0x00, 0x80, 0x7F };
	static const uint8_t f[] = { 0x00, 0x00, 0xC0, 0x3F, 0xCD, 0xCC, 0xCC, 0x3D };
	uint8_t st[168];
	struct df1_value v[8];
	(void)state;

	/* a trailing odd byte is not an element */
	assert_int_equal(df1_values_decode(DF1_FT_N, n, sizeof n, v, 8), 4);
	assert_int_equal(v[0].v.i16, 0);
	assert_int_equal(v[1].v.i16, 1);
	assert_int_equal(v[2].v.i16, -1);
	assert_int_equal(v[3].v.i16, -32768);
	assert_int_equal(df1_values_decode(DF1_FT_N, n, sizeof n, v, 2), 2);
	assert_int_equal(df1_values_decode(DF1_FT_NONE, n, 4, v, 8), 2);

	assert_int_equal(df1_values_decode(DF1_FT_F, f, sizeof f, v, 8), 2);
	assert_true(v[0].v.f == 1.5f);
	assert_true(v[1].v.f == F32(0.1f));

	assert_int_equal(value_put_string(st, "AB"), 2);
	assert_int_equal(value_put_string(st + 84, "xyz"), 3);
	assert_int_equal(df1_values_decode(DF1_FT_ST, st, sizeof st, v, 8), 2);
	assert_string_equal(v[0].v.str.text, "AB");
	assert_string_equal(v[1].v.str.text, "xyz");
	assert_int_equal(v[1].v.str.len, 3);

	assert_int_equal(df1_values_decode(DF1_FT_N, n, 0, v, 8), 0);
	assert_int_equal(df1_values_decode(DF1_FT_N, NULL, 2, v, 8), DF1_E_INVAL);
}

/* Bits count from bit 0 of the first word, 16 per N/B word, 32 per L element:
 * B3/21 is element 1, bit 5 (DESIGN 7, the controllers' B-file notation). */
static void test_value_bits_of_words(void **state)
{
	/* B3:0 = 0x8001, B3:1 = 0x0020: bits 0, 15 and 21 set */
	static const uint8_t words[] = { 0x01, 0x80, 0x20, 0x00 };
	/* L10:0 = 0x80000000, L10:1 = 0x00000001: bits 31 and 32 set */
	static const uint8_t longs[] = { 0x00, 0x00, 0x00, 0x80, 0x01, 0x00, 0x00, 0x00 };
	uint32_t mask = 0, data = 0;

	(void)state;
	for (size_t b = 0; b < 32; b++)
		assert_int_equal(value_get_bit(words, 2, b), b == 0 || b == 15 || b == 21);
	for (size_t b = 0; b < 64; b++)
		assert_int_equal(value_get_bit(longs, 4, b), b == 31 || b == 32);
	/* B3:0/5 := 1 is mask 0020 data 0020; B3:0/3 := 0 adds 0008 to the mask only */
	value_mask_bit(&mask, &data, 5, true);
	value_mask_bit(&mask, &data, 3, false);
	assert_int_equal(mask, 0x0028);
	assert_int_equal(data, 0x0020);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_value_bits_of_words),
		cmocka_unit_test(test_value_float_le_and_word_swapped),
		cmocka_unit_test(test_value_string_pairs_swapped),
		cmocka_unit_test(test_value_decode_elements),
		cmocka_unit_test(test_value_encode_elements),
		cmocka_unit_test(test_value_tcr_bit_names),
		cmocka_unit_test(test_value_format_every_named_bit),
		cmocka_unit_test(test_value_format_tcr_text),
		cmocka_unit_test(test_value_format_tcr_unnamed_bits_round_trip),
		cmocka_unit_test(test_value_format_integers_and_bits),
		cmocka_unit_test(test_value_format_float_shortest),
		cmocka_unit_test(test_value_format_float_round_trip_random),
		cmocka_unit_test(test_value_parse_int16),
		cmocka_unit_test(test_value_parse_int32_float),
		cmocka_unit_test(test_value_parse_bit_string_tcr),
		cmocka_unit_test(test_value_parse_reads_format),
		cmocka_unit_test(test_value_addr_kinds),
		cmocka_unit_test(test_values_decode_elements),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
