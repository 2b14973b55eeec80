/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_plc3_addr.c - PLC-3 addresses: the address text (df1_addr_parse_plc with
 * DF1_PLC_PLC3) and the logical binary form (lib/proto/pccc_plc3.c), against the
 * hand-written vectors of tests/data/plc3_addr_vectors.txt and
 * tests/data/plc3_addr_invalid.txt (doc/PROTOCOL.md 4.2a). Tests run from the
 * repository root.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "df1.h"
#include "proto/pccc.h"

#define NO DF1_ADDR_NONE

/* One "a | b | c" line into its trimmed fields; false for comments and blanks. */
static bool split_line(char *line, char **f, int nf)
{
	char *p = line;

	if (line[0] == '#' || line[0] == '\n' || line[0] == '\0')
		return false;
	for (int i = 0; i < nf; i++) {
		char *end = i < nf - 1 ? strstr(p, " | ") : p + strcspn(p, "\n");

		assert_non_null(end);
		f[i] = p;
		p = end + (i < nf - 1 ? 3 : 0);
		*end = '\0';
	}
	return true;
}

static size_t parse_hex(const char *s, uint8_t *out, size_t cap)
{
	size_t n = 0;
	unsigned v;
	int k;

	while (sscanf(s, " %2x%n", &v, &k) == 1) {
		assert_true(n < cap);
		out[n++] = (uint8_t)v;
		s += k;
	}
	return n;
}

static void test_plc3_vectors_encode_decode_and_round_trip(void **state)
{
	FILE *fp = fopen("tests/data/plc3_addr_vectors.txt", "r");
	char line[512], *f[3];
	int rows = 0;

	(void)state;
	assert_non_null(fp);
	while (fgets(line, sizeof line, fp)) {
		struct df1_addr a, back;
		struct pccc_plc3_addr l;
		uint8_t want[16], got[16];
		char text[64];
		size_t n;
		int k;

		if (!split_line(line, f, 3))
			continue;
		n = parse_hex(f[1], want, sizeof want);
		assert_int_equal(df1_addr_parse_plc(DF1_PLC_PLC3, f[0], &a), 0);
		k = pccc_enc_plc3_addr(got, sizeof got, &a);
		if (k != (int)n || memcmp(got, want, n) != 0)
			fail_msg("%s: encoded %d bytes, want %s", f[0], k, f[1]);
		assert_int_equal(df1_addr_format_plc(DF1_PLC_PLC3, &a, text, sizeof text), (int)strlen(f[0]));
		assert_string_equal(text, f[0]);
		assert_int_equal(pccc_dec_plc3_addr(want, n, &l), (int)n);
		assert_int_equal(pccc_plc3_to_addr(&l, &back), 0);
		assert_int_equal(back.type, a.type);
		assert_int_equal(back.file, a.file);
		assert_int_equal(back.element, a.element);
		/* the server's view: a T/C word, never the bit (bits go in masks) */
		if (a.type == DF1_FT_T || a.type == DF1_FT_C)
			assert_int_equal(back.sub, a.sub == NO ? 0 : a.sub);
		else
			assert_int_equal(back.sub, NO);
		rows++;
	}
	fclose(fp);
	assert_true(rows >= 20);
}

static void test_plc3_invalid_text_is_refused(void **state)
{
	FILE *fp = fopen("tests/data/plc3_addr_invalid.txt", "r");
	char line[512], *f[3];
	int rows = 0;

	(void)state;
	assert_non_null(fp);
	while (fgets(line, sizeof line, fp)) {
		struct df1_addr a;
		int want, rc;

		if (!split_line(line, f, 3))
			continue;
		want = strcmp(f[1], "range") == 0 ? DF1_E_ADDR_RANGE : DF1_E_ADDR_SYNTAX;
		rc = df1_addr_parse_plc(DF1_PLC_PLC3, f[0], &a);
		if (rc != want)
			fail_msg("%s: got %d, want %d (%s)", f[0], rc, want, f[2]);
		rows++;
	}
	fclose(fp);
	assert_true(rows >= 15);
}

/* The fields of the text forms (the grammar of lib/proto/addr_plc3.c), by hand. */
static void test_plc3_fields(void **state)
{
	static const struct {
		const char *text;
		enum df1_file_type type;
		int file, element, sub, bit;
		const char *canonical;
	} cases[] = {
		{ "N3:173", DF1_FT_N, 3, 173, NO, NO, "N3:173" },
		{ "b5:173/15", DF1_FT_B, 5, 173, NO, 13, "B5:173/15" },
		{ "I0:17", DF1_FT_I, 0, 15, NO, NO, "I0:17" },
		{ "I0:17/7", DF1_FT_I, 0, 15, NO, 7, "I0:17/7" },
		{ "F2:10", DF1_FT_F, 2, 10, NO, NO, "F2:10" },
		{ "H8:99", DF1_FT_L, 8, 99, NO, NO, "H8:99" },
		{ "D7:12/3", DF1_FT_D, 7, 12, NO, 3, "D7:12/3" },
		{ "T4.ACC", DF1_FT_T, 0, 4, 2, NO, "T4.ACC" },
		{ "T0:4.ACC", DF1_FT_T, 0, 4, 2, NO, "T4.ACC" },
		{ "T4", DF1_FT_T, 0, 4, NO, NO, "T4" },
		{ "T4.DN", DF1_FT_T, 0, 4, 0, 13, "T4/DN" },
		{ "T4/15", DF1_FT_T, 0, 4, 0, 13, "T4/DN" },
		{ "T4/7", DF1_FT_T, 0, 4, 0, 7, "T4/7" },
		{ "T4.CTL/EN", DF1_FT_T, 0, 4, 0, 15, "T4/EN" },
		{ "T4.PRE/3", DF1_FT_T, 0, 4, 1, 3, "T4.PRE/3" },
		{ "C2/UF", DF1_FT_C, 0, 2, 0, 11, "C2/UF" },
		{ "S0:3", DF1_FT_S, 0, 3, NO, NO, "S0:3" },
		{ "A1:126", DF1_FT_A, 1, 126, NO, NO, "A1:126" },
	};

	(void)state;
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		struct df1_addr a;
		char text[64];

		if (df1_addr_parse_plc(DF1_PLC_PLC3, cases[i].text, &a) != 0)
			fail_msg("%s refused", cases[i].text);
		assert_int_equal(a.type, cases[i].type);
		assert_int_equal(a.file, cases[i].file);
		assert_int_equal(a.element, cases[i].element);
		assert_int_equal(a.sub, cases[i].sub);
		assert_int_equal(a.bit, cases[i].bit);
		assert_true(df1_addr_format_plc(DF1_PLC_PLC3, &a, text, sizeof text) > 0);
		assert_string_equal(text, cases[i].canonical);
	}
}

/* Other PLC types keep their own grammar; D is a PLC-3 section only. */
static void test_plc3_other_types_unchanged(void **state)
{
	struct df1_addr a;
	char text[32];

	(void)state;
	assert_int_equal(df1_addr_parse_plc(DF1_PLC_SLC, "B3:0/15", &a), 0);
	assert_int_equal(a.bit, 15);
	assert_int_equal(df1_addr_parse_plc(DF1_PLC_PLC5, "T4:2.ACC", &a), 0);
	assert_int_equal(a.file, 4);
	assert_int_equal(df1_addr_parse("D7:12", &a), DF1_E_ADDR_SYNTAX);
	assert_int_equal(df1_addr_parse_plc(DF1_PLC_PLC3, "D7:12", &a), 0);
	assert_int_equal(df1_addr_format(&a, text, sizeof text), DF1_E_INVAL);
	assert_int_equal(df1_addr_format_plc(DF1_PLC_PLC3, &a, text, 3), DF1_E_NOSPACE);
}

/* Decoder edges: the manual's rules (M p.13-6) by hand. */
static void test_plc3_decode_edges(void **state)
{
	static const uint8_t no_word[] = { 0x0C, 0x05, 0x03 };          /* levels 3 4: no last level */
	static const uint8_t area5[] = { 0x25, 0x05, 0x05, 0x03 };      /* area 5: messages */
	static const uint8_t area3[] = { 0x27, 0x03, 0x01, 0x05, 0x03 }; /* area 3 context 1: N0:3 */
	static const uint8_t bit_level[] = { 0x64, 0x05, 0x03, 0x01 };
	static const uint8_t cut[] = { 0x2C, 0x05, 0xFF, 0x04 };
	static const uint8_t pointers[] = { 0x34, 0x0C, 0x01, 0x00 };
	struct pccc_plc3_addr l;
	struct df1_addr a;

	(void)state;
	assert_int_equal(pccc_dec_plc3_addr(no_word, sizeof no_word, &l), DF1_E_ADDR_SYNTAX);
	assert_int_equal(pccc_dec_plc3_addr(area5, sizeof area5, &l), DF1_E_ADDR_RANGE);
	assert_int_equal(pccc_dec_plc3_addr(area3, sizeof area3, &l), 5);
	assert_int_equal(pccc_plc3_to_addr(&l, &a), 0);
	assert_int_equal(a.type, DF1_FT_N);
	assert_int_equal(a.element, 3);
	assert_int_equal(pccc_dec_plc3_addr(bit_level, sizeof bit_level, &l), DF1_E_ADDR_RANGE);
	assert_int_equal(pccc_dec_plc3_addr(cut, sizeof cut, &l), DF1_E_TOO_SHORT);
	assert_int_equal(pccc_dec_plc3_addr(pointers, sizeof pointers, &l), 4);
	assert_int_equal(pccc_plc3_to_addr(&l, &a), DF1_E_ADDR_RANGE);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_plc3_vectors_encode_decode_and_round_trip),
		cmocka_unit_test(test_plc3_invalid_text_is_refused),
		cmocka_unit_test(test_plc3_fields),
		cmocka_unit_test(test_plc3_other_types_unchanged),
		cmocka_unit_test(test_plc3_decode_edges),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
