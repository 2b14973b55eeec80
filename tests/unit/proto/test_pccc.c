/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_pccc.c - PCCC encoders/decoders and df1_msg_decode against the byte
 * vectors of doc/PROTOCOL.md 7 and tests/data/vectors.txt (app bytes between DLE STX
 * and DLE ETX, de-stuffed), and the manual's examples (M p.123-124, p.227).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include <stdio.h>

#include "df1.h"
#include "proto/frame.h"
#include "proto/pccc.h"
#include "proto/value.h"

/* "01 00 0F" -> bytes; the expected values are typed in from the spec. */
static size_t hex(const char *s, uint8_t *out, size_t cap)
{
	size_t n = 0;

	while (*s) {
		char *end;
		unsigned long v;

		if (*s == ' ') {
			s++;
			continue;
		}
		v = strtoul(s, &end, 16);
		assert_true(end == s + 2 && v <= 0xFF && n < cap);
		out[n++] = (uint8_t)v;
		s = end;
	}
	return n;
}

static void assert_bytes(const uint8_t *got, int got_len, const char *expect_hex)
{
	uint8_t e[300];
	size_t n = hex(expect_hex, e, sizeof e);

	assert_int_equal(got_len, (int)n);
	assert_memory_equal(got, e, n);
}

static struct df1_addr mk_addr(enum df1_file_type t, int file, int elem, int sub)
{
	struct df1_addr a;

	memset(&a, 0, sizeof a);
	a.type = t;
	a.file = file;
	a.element = elem;
	a.sub = sub;
	a.bit = DF1_ADDR_NONE;
	return a;
}

/* ------------------------------------------------------------------------
 * SLC commands (doc/PROTOCOL.md 4.5, 4.6; vectors 7.2, 7.3)
 * ------------------------------------------------------------------------ */

static void test_pccc_slc_a2_read_matches_vectors(void **state)
{
	uint8_t out[64];
	struct pccc_hdr h = { 0x01, 0x00, 0x0001 };
	struct pccc_hdr tap = { 0x00, 0x00, 0x3911 };
	struct pccc_hdr f8 = { 0x01, 0x00, 0x0004 };
	struct pccc_hdr dle = { 0x01, 0x00, 0x1010 };
	(void)state;

	/* derived-slc-A2-read-N7:0-20B */
	assert_bytes(out, pccc_enc_slc_read(out, sizeof out, &h, 0xA2, 20, 7, 0x89, 0, 0),
	             "01 00 0F 00 01 00 A2 14 07 89 00 00");
	/* tap-A2-read-N7:1 (serial-tap capture) */
	assert_bytes(out, pccc_enc_slc_read(out, sizeof out, &tap, 0xA2, 2, 7, 0x89, 1, 0),
	             "00 00 0F 00 11 39 A2 02 07 89 01 00");
	/* derived-slc-A2-read-F8:0 */
	assert_bytes(out, pccc_enc_slc_read(out, sizeof out, &f8, 0xA2, 4, 8, 0x8A, 0, 0),
	             "01 00 0F 00 04 00 A2 04 08 8A 00 00");
	/* derived-dle-stuffing: the app bytes before stuffing */
	assert_bytes(out, pccc_enc_slc_read(out, sizeof out, &dle, 0xA2, 2, 7, 0x89, 0x10, 0),
	             "01 00 0F 00 10 10 A2 02 07 89 10 00");
}

static void test_pccc_slc_a1_two_fields_has_no_sub(void **state)
{
	uint8_t out[64];
	struct pccc_hdr h = { 0x01, 0x00, 0x0001 };
	(void)state;

	/* PM020 p.92: A1 = BYTE_SIZE FILE TYPE ELEMENT */
	assert_bytes(out, pccc_enc_slc_read(out, sizeof out, &h, 0xA1, 2, 7, 0x89, 3, 9),
	             "01 00 0F 00 01 00 A1 02 07 89 03");
	assert_int_equal(pccc_enc_slc_read(out, sizeof out, &h, 0xAA, 2, 7, 0x89, 3, 0), DF1_E_INVAL);
}

static void test_pccc_slc_aa_write_matches_vectors(void **state)
{
	uint8_t out[64];
	static const uint8_t d1[] = { 0x34, 0x12 }, d2[] = { 0x49, 0x34 };
	struct pccc_hdr h = { 0x01, 0x00, 0x0002 };
	struct pccc_hdr tap = { 0x00, 0x00, 0x3901 };
	(void)state;

	assert_bytes(out, pccc_enc_slc_write(out, sizeof out, &h, 0xAA, 7, 0x89, 5, 0, d1, 2),
	             "01 00 0F 00 02 00 AA 02 07 89 05 00 34 12");
	assert_bytes(out, pccc_enc_slc_write(out, sizeof out, &tap, 0xAA, 7, 0x89, 5, 0, d2, 2),
	             "00 00 0F 00 01 39 AA 02 07 89 05 00 49 34");
	/* A9: two fields */
	assert_bytes(out, pccc_enc_slc_write(out, sizeof out, &h, 0xA9, 7, 0x89, 5, 0, d1, 2),
	             "01 00 0F 00 02 00 A9 02 07 89 05 34 12");
}

static void test_pccc_slc_ab_masked_write_matches_vector(void **state)
{
	uint8_t out[64];
	static const uint8_t mask[] = { 0x20, 0x00 }, data[] = { 0x20, 0x00 };
	static const uint8_t s2mask[] = { 0xFF, 0xFC }, s2data[] = { 0x00, 0x00 };
	struct pccc_hdr h = { 0x01, 0x00, 0x0003 };
	(void)state;

	/* B3:0/5 := 1 */
	assert_bytes(out, pccc_enc_slc_masked_write(out, sizeof out, &h, 3, 0x85, 0, 0, mask, data, 2),
	             "01 00 0F 00 03 00 AB 02 03 85 00 00 20 00 20 00");
	/* AHMI's clear of S2:5 minor fault bits (doc/PROTOCOL.md 4.6): AB 02 02 84 05 00 FF FC 00 00 */
	assert_bytes(out, pccc_enc_slc_masked_write(out, sizeof out, &h, 2, 0x84, 5, 0, s2mask, s2data, 2),
	             "01 00 0F 00 03 00 AB 02 02 84 05 00 FF FC 00 00");
}

static void test_pccc_field_escape_above_254(void **state)
{
	uint8_t out[64];
	unsigned v;
	struct pccc_hdr h = { 0x01, 0x00, 0x0001 };
	(void)state;

	assert_bytes(out, pccc_put_field(out, sizeof out, 0), "00");
	assert_bytes(out, pccc_put_field(out, sizeof out, 254), "FE");
	assert_bytes(out, pccc_put_field(out, sizeof out, 255), "FF FF 00");
	assert_bytes(out, pccc_put_field(out, sizeof out, 256), "FF 00 01");
	assert_bytes(out, pccc_put_field(out, sizeof out, 999), "FF E7 03");
	assert_bytes(out, pccc_put_field(out, sizeof out, 65535), "FF FF FF");
	assert_int_equal(pccc_put_field(out, sizeof out, 65536), DF1_E_ADDR_RANGE);
	assert_int_equal(pccc_put_field(out, 2, 300), DF1_E_NOSPACE);

	assert_int_equal(pccc_get_field((const uint8_t *)"\xFE", 1, &v), 1);
	assert_int_equal(v, 254);
	assert_int_equal(pccc_get_field((const uint8_t *)"\xFF\x2C\x01", 3, &v), 3);
	assert_int_equal(v, 300);
	assert_int_equal(pccc_get_field((const uint8_t *)"\xFF\x2C", 2, &v), DF1_E_TOO_SHORT);

	/* N255:300.0: file and element both escaped */
	assert_bytes(out, pccc_enc_slc_read(out, sizeof out, &h, 0xA2, 2, 255, 0x89, 300, 0),
	             "01 00 0F 00 01 00 A2 02 FF FF 00 89 FF 2C 01 00");
	assert_int_equal(pccc_enc_slc_read(out, 12, &h, 0xA2, 2, 255, 0x89, 300, 0), DF1_E_NOSPACE);
}

static void test_pccc_dec_slc_fields_reads_vectors(void **state)
{
	uint8_t b[32];
	size_t n;
	uint8_t nbytes, code;
	unsigned file, elem, sub;
	(void)state;

	n = hex("14 07 89 00 00", b, sizeof b);
	assert_int_equal(pccc_dec_slc_fields(b, n, true, &nbytes, &file, &code, &elem, &sub), 5);
	assert_int_equal(nbytes, 20);
	assert_int_equal(file, 7);
	assert_int_equal(code, 0x89);
	assert_int_equal(elem, 0);
	assert_int_equal(sub, 0);

	n = hex("02 FF FF 00 89 FF 2C 01 02 34 12", b, sizeof b);
	assert_int_equal(pccc_dec_slc_fields(b, n, true, &nbytes, &file, &code, &elem, &sub), 9);
	assert_int_equal(file, 255);
	assert_int_equal(elem, 300);
	assert_int_equal(sub, 2);

	n = hex("02 07 89 05 34 12", b, sizeof b);     /* A9: two fields */
	assert_int_equal(pccc_dec_slc_fields(b, n, false, &nbytes, &file, &code, &elem, &sub), 4);
	assert_int_equal(elem, 5);

	n = hex("02 07 89", b, sizeof b);
	assert_int_equal(pccc_dec_slc_fields(b, n, true, &nbytes, &file, &code, &elem, &sub),
	                 DF1_E_TOO_SHORT);
}

static void test_pccc_slc_codes_map_to_file_types(void **state)
{
	(void)state;
	assert_int_equal(pccc_slc_code_file_type(0x84), DF1_FT_S);
	assert_int_equal(pccc_slc_code_file_type(0x85), DF1_FT_B);
	assert_int_equal(pccc_slc_code_file_type(0x86), DF1_FT_T);
	assert_int_equal(pccc_slc_code_file_type(0x87), DF1_FT_C);
	assert_int_equal(pccc_slc_code_file_type(0x88), DF1_FT_R);
	assert_int_equal(pccc_slc_code_file_type(0x89), DF1_FT_N);
	assert_int_equal(pccc_slc_code_file_type(0x8A), DF1_FT_F);
	assert_int_equal(pccc_slc_code_file_type(0x8B), DF1_FT_O);
	assert_int_equal(pccc_slc_code_file_type(0x8C), DF1_FT_I);
	assert_int_equal(pccc_slc_code_file_type(0x82), DF1_FT_O);
	assert_int_equal(pccc_slc_code_file_type(0x83), DF1_FT_I);
	assert_int_equal(pccc_slc_code_file_type(0x8D), DF1_FT_ST);
	assert_int_equal(pccc_slc_code_file_type(0x8E), DF1_FT_A);
	assert_int_equal(pccc_slc_code_file_type(0x91), DF1_FT_L);
	assert_int_equal(pccc_slc_code_file_type(0x92), DF1_FT_NONE);
}

/* ------------------------------------------------------------------------
 * PLC-5 addresses (doc/PROTOCOL.md 4.1, M p.226-229)
 * ------------------------------------------------------------------------ */

static void test_pccc_plc5_addr_forms_match_manual(void **state)
{
	uint8_t out[64];
	struct df1_addr n7_30 = mk_addr(DF1_FT_N, 7, 30, DF1_ADDR_NONE);
	struct df1_addr b3_300 = mk_addr(DF1_FT_B, 3, 300, DF1_ADDR_NONE);
	struct df1_addr t4_2acc = mk_addr(DF1_FT_T, 4, 2, 2);
	struct df1_addr n10_15 = mk_addr(DF1_FT_N, 10, 15, DF1_ADDR_NONE);
	struct df1_addr n7_0 = mk_addr(DF1_FT_N, 7, 0, DF1_ADDR_NONE);
	(void)state;

	/* M p.227 with every level encoded */
	assert_bytes(out, pccc_enc_plc5_addr_form(out, sizeof out, &n7_30, PCCC_PLC5_ALL_LEVELS),
	             "07 00 07 1E");
	assert_bytes(out, pccc_enc_plc5_addr_form(out, sizeof out, &t4_2acc, PCCC_PLC5_ALL_LEVELS),
	             "0F 00 04 02 02");
	/* M p.227 B3:300 leaves level 1 to its default: the LPT form */
	assert_bytes(out, pccc_enc_plc5_addr(out, sizeof out, &b3_300), "06 03 FF 2C 01");
	/* LPT: 06 file element; 0E with a sub-element */
	assert_bytes(out, pccc_enc_plc5_addr(out, sizeof out, &n7_0), "06 07 00");
	assert_bytes(out, pccc_enc_plc5_addr(out, sizeof out, &n7_30), "06 07 1E");
	assert_bytes(out, pccc_enc_plc5_addr(out, sizeof out, &t4_2acc), "0E 04 02 02");
	/* KE p.50: four levels, sub 0 */
	assert_bytes(out, pccc_enc_plc5_addr_form(out, sizeof out, &n10_15, PCCC_PLC5_FOUR_LEVELS),
	             "0F 00 0A 0F 00");
	assert_int_equal(pccc_enc_plc5_addr(out, 2, &n7_0), DF1_E_NOSPACE);
	n7_0.file = -1;
	assert_int_equal(pccc_enc_plc5_addr(out, sizeof out, &n7_0), DF1_E_ADDR_RANGE);
}

static void test_pccc_plc5_addr_ascii_form(void **state)
{
	uint8_t out[64];
	struct df1_addr a = mk_addr(DF1_FT_N, 10, 15, DF1_ADDR_NONE);
	char big[60];
	(void)state;

	/* KE p.51 */
	assert_bytes(out, pccc_enc_plc5_ascii(out, sizeof out, "N10:15"),
	             "00 24 4E 31 30 3A 31 35 00");
	assert_bytes(out, pccc_enc_plc5_ascii(out, sizeof out, "$N10:15"),
	             "00 24 4E 31 30 3A 31 35 00");
	/* an address with ascii set goes out in the ASCII form */
	strcpy(a.ascii, "N10:15");
	assert_bytes(out, pccc_enc_plc5_addr(out, sizeof out, &a), "00 24 4E 31 30 3A 31 35 00");
	assert_int_equal(pccc_enc_plc5_ascii(out, sizeof out, ""), DF1_E_ADDR_SYNTAX);
	memset(big, 'N', 52);
	big[52] = '\0';
	assert_int_equal(pccc_enc_plc5_ascii(out, sizeof out, big), DF1_E_ADDR_RANGE);
	big[51] = '\0';
	assert_int_equal(pccc_enc_plc5_ascii(out, sizeof out, big), 54);
}

static void test_pccc_plc5_addr_decoder_accepts_all_forms(void **state)
{
	uint8_t b[32];
	size_t n;
	struct df1_addr a;
	(void)state;

	n = hex("07 00 07 1E", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 4);
	assert_int_equal(a.type, DF1_FT_NONE);
	assert_int_equal(a.file, 7);
	assert_int_equal(a.element, 30);
	assert_int_equal(a.sub, DF1_ADDR_NONE);
	assert_int_equal(a.bit, DF1_ADDR_NONE);

	n = hex("06 03 FF 2C 01", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 5);
	assert_int_equal(a.file, 3);
	assert_int_equal(a.element, 300);

	n = hex("0F 00 04 02 02", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 5);
	assert_int_equal(a.file, 4);
	assert_int_equal(a.element, 2);
	assert_int_equal(a.sub, 2);

	n = hex("0E 04 02 02", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 4);
	assert_int_equal(a.file, 4);
	assert_int_equal(a.element, 2);
	assert_int_equal(a.sub, 2);

	n = hex("0F 00 0C 0A 02", b, sizeof b);     /* PD12:10.SP */
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 5);
	assert_int_equal(a.file, 12);
	assert_int_equal(a.element, 10);
	assert_int_equal(a.sub, 2);

	n = hex("0F 00 0A 0F 00 22 11", b, sizeof b);   /* KE p.50, data follows */
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 5);
	assert_int_equal(a.file, 10);
	assert_int_equal(a.element, 15);
	assert_int_equal(a.sub, 0);

	n = hex("06 07 00", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 3);
	assert_int_equal(a.file, 7);
	assert_int_equal(a.element, 0);

	/* the mask itself may take the FF escape (M p.229) */
	n = hex("FF 06 00 07 00", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 5);
	assert_int_equal(a.file, 7);
	assert_int_equal(a.element, 0);

	/* only the element encoded: the file level defaults to 1 (M p.226) */
	n = hex("04 05", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 2);
	assert_int_equal(a.file, 1);
	assert_int_equal(a.element, 5);

	n = hex("1F 00 07 00 00 00", b, sizeof b);      /* a 5th level */
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), DF1_E_ADDR_RANGE);
	n = hex("07 01 07 00", b, sizeof b);            /* area 1: not the data table */
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), DF1_E_ADDR_RANGE);
	n = hex("06 07", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), DF1_E_TOO_SHORT);
	n = hex("06 FF 2C", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), DF1_E_TOO_SHORT);
	n = hex("00 41", b, sizeof b);                  /* 00 not followed by '$' */
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), DF1_E_ADDR_SYNTAX);
}

static void test_pccc_plc5_addr_ascii_decodes_and_parses(void **state)
{
	uint8_t b[64];
	size_t n;
	struct df1_addr a;
	(void)state;

	n = hex("00 24 4E 31 30 3A 31 35 00 08", b, sizeof b);   /* KE p.51 + SIZE */
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 9);
	assert_string_equal(a.ascii, "N10:15");
	assert_int_equal(a.type, DF1_FT_N);
	assert_int_equal(a.file, 10);
	assert_int_equal(a.element, 15);

	/* text our parser does not know still decodes */
	n = hex("00 24 50 44 31 32 3A 31 30 2E 53 50 00", b, sizeof b);  /* $PD12:10.SP */
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), 13);
	assert_string_equal(a.ascii, "PD12:10.SP");
	assert_int_equal(a.type, DF1_FT_NONE);
	assert_int_equal(a.file, DF1_ADDR_NONE);

	n = hex("00 24 4E 37 3A 30", b, sizeof b);      /* no terminating 00 */
	assert_int_equal(pccc_dec_plc5_addr(b, n, &a), DF1_E_TOO_SHORT);
}

/* ------------------------------------------------------------------------
 * PLC-5 commands (doc/PROTOCOL.md 4.2-4.4; KE p.50-51; 7.3)
 * ------------------------------------------------------------------------ */

static void test_pccc_plc5_typed_read_matches_vectors(void **state)
{
	uint8_t out[64], addr[32];
	int alen;
	struct df1_addr a;
	struct pccc_hdr h6 = { 0x01, 0x00, 0x0006 }, h7 = { 0x01, 0x00, 0x0007 };
	(void)state;

	a = mk_addr(DF1_FT_N, 7, 0, DF1_ADDR_NONE);
	alen = pccc_enc_plc5_addr(addr, sizeof addr, &a);
	assert_int_equal(alen, 3);
	assert_bytes(out, pccc_enc_plc5_typed_read(out, sizeof out, &h6, 0, 10, addr, (size_t)alen, 10),
	             "01 00 0F 00 06 00 68 00 00 0A 00 06 07 00 0A 00");

	/* "$N7:0" through the address parser */
	assert_int_equal(df1_addr_parse("$N7:0", &a), 0);
	alen = pccc_enc_plc5_addr(addr, sizeof addr, &a);
	assert_int_equal(alen, 7);
	assert_bytes(out, pccc_enc_plc5_typed_read(out, sizeof out, &h7, 0, 1, addr, (size_t)alen, 1),
	             "01 00 0F 00 07 00 68 00 00 01 00 00 24 4E 37 3A 30 00 01 00");
}

static void test_pccc_plc5_typed_write_matches_vector(void **state)
{
	uint8_t out[64], addr[8], typed[32];
	int alen, tlen;
	struct df1_addr a = mk_addr(DF1_FT_N, 7, 0, DF1_ADDR_NONE);
	struct pccc_hdr h = { 0x01, 0x00, 0x0008 };
	(void)state;

	alen = pccc_enc_plc5_addr(addr, sizeof addr, &a);
	tlen = pccc_enc_typed_array(typed, sizeof typed, PCCC_TD_INTEGER, 2, 2);
	assert_bytes(typed, tlen, "99 09 05 42");
	put_le16(typed + tlen, 1);
	put_le16(typed + tlen + 2, 2);
	assert_bytes(out, pccc_enc_plc5_typed_write(out, sizeof out, &h, 0, 2, addr, (size_t)alen,
	                                            typed, (size_t)tlen + 4),
	             "01 00 0F 00 08 00 67 00 00 02 00 06 07 00 99 09 05 42 01 00 02 00");
}

static void test_pccc_plc5_word_range_matches_vectors(void **state)
{
	uint8_t out[64], addr[64];
	int alen;
	struct df1_addr a = mk_addr(DF1_FT_N, 7, 0, DF1_ADDR_NONE);
	struct df1_addr n10 = mk_addr(DF1_FT_N, 10, 15, DF1_ADDR_NONE);
	struct pccc_hdr h9 = { 0x01, 0x00, 0x0009 };
	struct pccc_hdr ke46 = { 0x29, 0x20, 0x0146 }, ke47 = { 0x29, 0x20, 0x0147 };
	static const uint8_t words[] = { 0x22, 0x11, 0x44, 0x33, 0x66, 0x55, 0x88, 0x77 };
	(void)state;

	alen = pccc_enc_plc5_addr(addr, sizeof addr, &a);
	assert_bytes(out, pccc_enc_plc5_word_read(out, sizeof out, &h9, 0, 10, addr, (size_t)alen, 20),
	             "01 00 0F 00 09 00 01 00 00 0A 00 06 07 00 14");

	/* KE p.50: word range write N10:15, 4 words, four-level address */
	alen = pccc_enc_plc5_addr_form(addr, sizeof addr, &n10, PCCC_PLC5_FOUR_LEVELS);
	assert_bytes(out, pccc_enc_plc5_word_write(out, sizeof out, &ke46, 0, 4, addr, (size_t)alen,
	                                           words, sizeof words),
	             "29 20 0F 00 46 01 00 00 00 04 00 0F 00 0A 0F 00 22 11 44 33 66 55 88 77");

	/* KE p.51: word range read $N10:15, 4 words, SIZE 8 */
	alen = pccc_enc_plc5_ascii(addr, sizeof addr, "N10:15");
	assert_bytes(out, pccc_enc_plc5_word_read(out, sizeof out, &ke47, 0, 4, addr, (size_t)alen, 8),
	             "29 20 0F 00 47 01 01 00 00 04 00 00 24 4E 31 30 3A 31 35 00 08");

	assert_int_equal(pccc_enc_plc5_word_read(out, sizeof out, &h9, 0, 10, addr, (size_t)alen, 7),
	                 DF1_E_INVAL);
	assert_int_equal(pccc_enc_plc5_word_write(out, sizeof out, &h9, 0, 1, addr, (size_t)alen, words, 3),
	                 DF1_E_INVAL);
}

static void test_pccc_plc5_rmw_and_bit_write(void **state)
{
	uint8_t out[64], addr[8];
	int alen;
	struct df1_addr a = mk_addr(DF1_FT_N, 7, 0, DF1_ADDR_NONE);
	struct pccc_hdr h = { 0x01, 0x00, 0x000A };
	(void)state;

	alen = pccc_enc_plc5_addr(addr, sizeof addr, &a);
	assert_bytes(out, pccc_enc_plc5_rmw(out, sizeof out, &h, addr, (size_t)alen, 0xFFFF, 0x0008),
	             "01 00 0F 00 0A 00 26 06 07 00 FF FF 08 00");
	/* PM020 p.89: 0F/02 ADDRESS SET(2) RESET(2) */
	assert_bytes(out, pccc_enc_plc5_bit_write(out, sizeof out, &h, addr, (size_t)alen, 0x0008, 0x0001),
	             "01 00 0F 00 0A 00 02 06 07 00 08 00 01 00");
}

static void test_pccc_dec_plc5_req_reads_command_bodies(void **state)
{
	uint8_t b[64];
	size_t n;
	struct pccc_plc5_req r;
	(void)state;

	/* body of derived-plc5-68-typed-read-N7:0x10 after FNC */
	n = hex("00 00 0A 00 06 07 00 0A 00", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_req(0x68, b, n, &r), 0);
	assert_int_equal(r.pkt_offset, 0);
	assert_int_equal(r.total, 10);
	assert_int_equal(r.addr.file, 7);
	assert_int_equal(r.addr.element, 0);
	assert_int_equal(r.size, 10);
	assert_int_equal(r.len, 0);

	/* KE p.51 body */
	n = hex("00 00 04 00 00 24 4E 31 30 3A 31 35 00 08", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_req(0x01, b, n, &r), 0);
	assert_int_equal(r.total, 4);
	assert_string_equal(r.addr.ascii, "N10:15");
	assert_int_equal(r.size, 8);

	/* KE p.50 body */
	n = hex("00 00 04 00 0F 00 0A 0F 00 22 11 44 33 66 55 88 77", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_req(0x00, b, n, &r), 0);
	assert_int_equal(r.addr.file, 10);
	assert_int_equal(r.addr.element, 15);
	assert_int_equal(r.size, -1);
	assert_int_equal(r.len, 8);
	assert_int_equal(r.data[0], 0x22);

	/* RMW body */
	n = hex("06 07 00 FF FF 08 00", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_req(0x26, b, n, &r), 0);
	assert_int_equal(r.len, 4);
	assert_int_equal(le16(r.data), 0xFFFF);
	assert_int_equal(le16(r.data + 2), 0x0008);
	assert_int_equal(pccc_dec_plc5_req(0x26, b, 5, &r), DF1_E_TOO_SHORT);

	n = hex("00 00 0A 00 06 07 00 0A", b, sizeof b);
	assert_int_equal(pccc_dec_plc5_req(0x68, b, n, &r), DF1_E_TOO_SHORT);
	assert_int_equal(pccc_dec_plc5_req(0xA2, b, n, &r), DF1_E_NOTSUP);
}

/* ------------------------------------------------------------------------
 * PLC-2, diagnostics, mode (doc/PROTOCOL.md 4.7-4.9)
 * ------------------------------------------------------------------------ */

static void test_pccc_plc2_matches_manual_vectors(void **state)
{
	uint8_t out[64];
	static const uint8_t words[] = { 0x22, 0x11, 0x44, 0x33, 0x66, 0x55, 0x88, 0x77 };
	struct pccc_hdr m235 = { 0x09, 0x00, 0x0001 };
	struct pccc_hdr ke44 = { 0x29, 0x20, 0x0144 }, ke45 = { 0x29, 0x20, 0x0145 };
	(void)state;

	/* M p.235 (14-3) */
	assert_bytes(out, pccc_enc_plc2_read(out, sizeof out, &m235, 0x0011, 2),
	             "09 00 01 00 01 00 11 00 02");
	/* KE p.48 */
	assert_bytes(out, pccc_enc_plc2_write(out, sizeof out, &ke44, 0x0028, words, sizeof words),
	             "29 20 08 00 44 01 28 00 22 11 44 33 66 55 88 77");
	/* KE p.49 */
	assert_bytes(out, pccc_enc_plc2_read(out, sizeof out, &ke45, 0x0028, 8),
	             "29 20 01 00 45 01 28 00 08");
}

static void test_pccc_diag_echo_mode_match_vectors(void **state)
{
	uint8_t out[64];
	struct pccc_hdr hb = { 0x01, 0x00, 0x000B }, hc = { 0x01, 0x00, 0x000C };
	struct pccc_hdr hd = { 0x01, 0x00, 0x000D };
	struct pccc_hdr kf2a = { 0x08, 0x09, 0x0402 }, kf2b = { 0x08, 0x09, 0x0410 };
	(void)state;

	assert_bytes(out, pccc_enc_diag_status(out, sizeof out, &hb), "01 00 06 00 0B 00 03");
	/* KF2 p.48 BCC examples are diagnostic status commands too */
	assert_bytes(out, pccc_enc_diag_status(out, sizeof out, &kf2a), "08 09 06 00 02 04 03");
	assert_bytes(out, pccc_enc_diag_status(out, sizeof out, &kf2b), "08 09 06 00 10 04 03");
	assert_bytes(out, pccc_enc_echo(out, sizeof out, &hc, (const uint8_t *)"A", 1),
	             "01 00 06 00 0C 00 00 41");
	assert_bytes(out, pccc_enc_change_mode(out, sizeof out, &hd, 0x06), "01 00 0F 00 0D 00 80 06");
	assert_int_equal(pccc_enc_diag_status(out, 6, &hb), DF1_E_NOSPACE);
}

/* ------------------------------------------------------------------------
 * Header / reply decoding (doc/PROTOCOL.md 3)
 * ------------------------------------------------------------------------ */

static void test_pccc_decode_replies_from_vectors(void **state)
{
	uint8_t b[64];
	size_t n;
	struct pccc_msg m;
	(void)state;

	/* M p.235 reply */
	n = hex("0A 09 41 00 01 00 FF FF", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_true(m.is_reply);
	assert_int_equal(m.dst, 0x0A);
	assert_int_equal(m.src, 0x09);
	assert_int_equal(m.cmd, 0x41);
	assert_int_equal(m.sts, 0);
	assert_int_equal(m.tns, 0x0001);
	assert_false(m.has_fnc);
	assert_false(m.has_ext);
	assert_int_equal(m.len, 2);
	assert_int_equal(le16(m.data), 0xFFFF);

	/* KE p.48 write reply: no data */
	n = hex("20 29 48 00 44 01", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_int_equal(m.cmd, 0x48);
	assert_int_equal(m.tns, 0x0144);
	assert_int_equal(m.len, 0);

	/* KE p.50 word range write reply */
	n = hex("20 29 4F 00 46 01", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_int_equal(m.cmd, 0x4F);
	assert_int_equal(m.tns, 0x0146);
	assert_false(m.has_ext);
	assert_int_equal(m.len, 0);

	/* KE p.51 word range read reply: words LE */
	n = hex("20 29 4F 00 47 01 22 11 44 33 66 55 88 77", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_int_equal(m.tns, 0x0147);
	assert_int_equal(m.len, 8);
	assert_int_equal(le16(m.data), 0x1122);
	assert_int_equal(le16(m.data + 6), 0x7788);

	/* M p.5-7 CRC frame: a reply 41 with 12 zero bytes */
	n = hex("07 11 41 00 53 B9 00 00 00 00 00 00 00 00 00 00 00 00", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_int_equal(m.tns, 0xB953);
	assert_int_equal(m.len, 12);

	/* F8:0 = 1.5, plain LE float */
	n = hex("00 01 4F 00 04 00 00 00 C0 3F", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_int_equal(m.len, 4);
	assert_true(value_get_float(m.data, VALUE_FLOAT_LE) == 1.5f);

	/* STS F0, EXT STS 06 */
	n = hex("00 01 4F F0 05 00 06", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_int_equal(m.sts, 0xF0);
	assert_true(m.has_ext);
	assert_int_equal(m.ext_sts, 0x06);
	assert_false(m.has_owner);
	assert_int_equal(m.len, 0);
}

static void test_pccc_decode_ext_sts_rules(void **state)
{
	uint8_t b[32];
	size_t n;
	struct pccc_msg m;
	(void)state;

	/* CMD 00-08 have no EXT STS byte (doc/PROTOCOL.md 3.2) */
	n = hex("00 01 41 F0 05 00 06", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_false(m.has_ext);
	assert_int_equal(m.len, 1);

	/* DH-485 0B/1A/1B: EXT 1A/1B is followed by the owner node (doc/PROTOCOL.md 3.4) */
	n = hex("00 01 4B F0 05 00 1A 07", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_true(m.has_ext);
	assert_int_equal(m.ext_sts, 0x1A);
	assert_true(m.has_owner);
	assert_int_equal(m.owner, 0x07);
	assert_int_equal(m.len, 0);
	n = hex("00 01 5B F0 05 00 1B 03 AA", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_true(m.has_owner);
	assert_int_equal(m.owner, 0x03);
	assert_int_equal(m.len, 1);
	n = hex("00 01 4B F0 05 00 1A", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), DF1_E_BAD_REPLY);
	/* 0F's 1A has no owner byte */
	n = hex("00 01 4F F0 05 00 1A 07", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_false(m.has_owner);
	assert_int_equal(m.len, 1);

	n = hex("00 01 4F F0 05 00", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), DF1_E_BAD_REPLY);
	assert_int_equal(pccc_decode(b, 5, &m), DF1_E_TOO_SHORT);
}

static void test_pccc_decode_commands(void **state)
{
	uint8_t b[64];
	size_t n;
	struct pccc_msg m;
	(void)state;

	n = hex("01 00 0F 00 01 00 A2 14 07 89 00 00", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_false(m.is_reply);
	assert_int_equal(m.dst, 1);
	assert_int_equal(m.src, 0);
	assert_int_equal(m.cmd, 0x0F);
	assert_int_equal(m.tns, 1);
	assert_true(m.has_fnc);
	assert_int_equal(m.fnc, 0xA2);
	assert_int_equal(m.len, 5);
	assert_int_equal(m.data[0], 0x14);

	n = hex("01 00 06 00 0C 00 00 41", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_true(m.has_fnc);
	assert_int_equal(m.fnc, 0x00);
	assert_int_equal(m.len, 1);

	/* PLC-2 commands have no FNC */
	n = hex("29 20 01 00 45 01 28 00 08", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &m), 0);
	assert_false(m.has_fnc);
	assert_int_equal(m.tns, 0x0145);
	assert_int_equal(m.len, 3);

	n = hex("01 00 0F 00 01 00", b, sizeof b);       /* 0F without FNC */
	assert_int_equal(pccc_decode(b, n, &m), DF1_E_TOO_SHORT);
}

static void test_pccc_encode_reply_swaps_and_echoes_tns(void **state)
{
	uint8_t b[64], out[64];
	size_t n;
	struct pccc_msg cmd;
	static const uint8_t words[] = { 0x22, 0x11, 0x44, 0x33, 0x66, 0x55, 0x88, 0x77 };
	static const uint8_t f15[] = { 0x00, 0x00, 0xC0, 0x3F };
	(void)state;

	n = hex("29 20 08 00 44 01 28 00 22 11 44 33 66 55 88 77", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &cmd), 0);
	assert_bytes(out, pccc_encode_reply(out, sizeof out, &cmd, 0, 0, NULL, 0), "20 29 48 00 44 01");

	n = hex("29 20 01 00 45 01 28 00 08", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &cmd), 0);
	assert_bytes(out, pccc_encode_reply(out, sizeof out, &cmd, 0, 0, words, sizeof words),
	             "20 29 41 00 45 01 22 11 44 33 66 55 88 77");

	n = hex("01 00 0F 00 04 00 A2 04 08 8A 00 00", b, sizeof b);
	assert_int_equal(pccc_decode(b, n, &cmd), 0);
	assert_bytes(out, pccc_encode_reply(out, sizeof out, &cmd, 0, 0, f15, sizeof f15),
	             "00 01 4F 00 04 00 00 00 C0 3F");
	cmd.tns = 5;
	assert_bytes(out, pccc_encode_reply(out, sizeof out, &cmd, 0xF0, 0x06, NULL, 0),
	             "00 01 4F F0 05 00 06");
	assert_int_equal(pccc_encode_reply(out, 6, &cmd, 0xF0, 0x06, NULL, 0), DF1_E_NOSPACE);
}

/* ------------------------------------------------------------------------
 * Typed data (M p.116, 123-124)
 * ------------------------------------------------------------------------ */

static void test_pccc_typedata_decodes_all_forms(void **state)
{
	uint8_t b[16];
	size_t n;
	unsigned id;
	uint32_t size;
	(void)state;

	n = hex("42", b, sizeof b);
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), 1);
	assert_int_equal(id, 4);
	assert_int_equal(size, 2);
	n = hex("43", b, sizeof b);
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), 1);
	assert_int_equal(id, 4);
	assert_int_equal(size, 3);
	n = hex("49 03", b, sizeof b);
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), 2);
	assert_int_equal(id, 4);
	assert_int_equal(size, 3);
	n = hex("4A 03 00", b, sizeof b);
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), 3);
	assert_int_equal(id, 4);
	assert_int_equal(size, 3);
	n = hex("97 09", b, sizeof b);
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), 2);
	assert_int_equal(id, 9);
	assert_int_equal(size, 7);
	n = hex("9A 09 15 00", b, sizeof b);
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), 4);
	assert_int_equal(id, 9);
	assert_int_equal(size, 0x15);
	n = hex("94 08", b, sizeof b);                  /* float, 4 bytes (RTA) */
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), 2);
	assert_int_equal(id, 8);
	assert_int_equal(size, 4);
	n = hex("A1 10 00", b, sizeof b);               /* type in 2 bytes LE: 0010h = BCD */
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), 3);
	assert_int_equal(id, 16);
	assert_int_equal(size, 1);

	n = hex("49", b, sizeof b);
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), DF1_E_TOO_SHORT);
	n = hex("9A 09 15", b, sizeof b);
	assert_int_equal(pccc_dec_typedata(b, n, &id, &size), DF1_E_TOO_SHORT);
}

static void test_pccc_typedata_encodes_shortest(void **state)
{
	uint8_t out[16];
	(void)state;

	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_INTEGER, 2), "42");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_INTEGER, 3), "43");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_STRING, 7), "37");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_STRING, 8), "39 08");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_FLOAT, 4), "94 08");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_ARRAY, 7), "97 09");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_ARRAY, 0x15), "99 09 15");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_INTEGER, 300), "4A 2C 01");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_BCD, 2), "92 10");
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, 0x123, 0x10000), "AB 23 01 00 00 01");
	assert_int_equal(pccc_enc_typedata(out, 1, PCCC_TD_FLOAT, 4), DF1_E_NOSPACE);

	/* arrays: the size always in extension bytes, as in the doc/PROTOCOL.md 7.3 vectors */
	assert_bytes(out, pccc_enc_typed_array(out, sizeof out, PCCC_TD_INTEGER, 2, 10), "99 09 15 42");
	assert_bytes(out, pccc_enc_typed_array(out, sizeof out, PCCC_TD_INTEGER, 2, 3), "99 09 07 42");
	assert_bytes(out, pccc_enc_typed_array(out, sizeof out, PCCC_TD_FLOAT, 4, 2), "99 09 0A 94 08");
	assert_bytes(out, pccc_enc_typed_array(out, sizeof out, PCCC_TD_INTEGER, 2, 200),
	             "9A 09 91 01 42");
	/* 5-word timers (KF2 p.130): type 5, size 10 in one extra byte: 59 0A; 23 of
	 * them make an array of 2 + 230 = E8h bytes */
	assert_bytes(out, pccc_enc_typedata(out, sizeof out, PCCC_TD_TIMER, 10), "59 0A");
	assert_bytes(out, pccc_enc_typed_array(out, sizeof out, PCCC_TD_TIMER, 10, 23), "99 09 E8 59 0A");
	assert_bytes(out, pccc_enc_typed_array(out, sizeof out, PCCC_TD_TIMER, 6, 38), "99 09 E5 56");
}

/* T/C/R elements of 5 words as a typed reply brings them: one element, or an
 * array whose descriptor is 59 0A / 69 0A / 79 0A (doc/PROTOCOL.md 4.3 flag byte rules). */
static void test_pccc_typed_tcr_5_words(void **state)
{
	uint8_t b[64];
	size_t n;
	struct pccc_typed t;
	(void)state;

	n = hex("59 0A 00 E0 64 00 2A 00 34 12 78 56", b, sizeof b);
	assert_int_equal(pccc_dec_typed(b, n, &t), 0);
	assert_int_equal(t.type_id, PCCC_TD_TIMER);
	assert_int_equal(t.elem_size, 10);
	assert_false(t.is_array);
	assert_int_equal(t.count, 1);
	assert_int_equal(t.consumed, n);
	assert_ptr_equal(t.data, b + 2);
	n = hex("99 09 16 69 0A 00 90 07 00 FD FF 00 00 00 00 00 10 09 00 03 00 00 00 00 00", b, sizeof b);
	assert_int_equal(pccc_dec_typed(b, n, &t), 0);
	assert_int_equal(t.type_id, PCCC_TD_COUNTER);
	assert_int_equal(t.elem_size, 10);
	assert_true(t.is_array);
	assert_int_equal(t.count, 2);
	assert_ptr_equal(t.data, b + 5);
	n = hex("99 09 0C 79 0A 00 20 09 00 04 00 00 00 00 00", b, sizeof b);
	assert_int_equal(pccc_dec_typed(b, n, &t), 0);
	assert_int_equal(t.type_id, PCCC_TD_CONTROL);
	assert_int_equal(t.elem_size, 10);
	assert_int_equal(t.count, 1);
}

static void test_pccc_typed_arrays_from_manual_and_vector(void **state)
{
	uint8_t b[64];
	size_t n;
	struct pccc_typed t;
	(void)state;

	/* M p.124: 3-integer array 0, -2, 255 */
	n = hex("97 09 42 00 00 FE FF FF 00", b, sizeof b);
	assert_int_equal(pccc_dec_typed(b, n, &t), 0);
	assert_true(t.is_array);
	assert_int_equal(t.type_id, PCCC_TD_INTEGER);
	assert_int_equal(t.elem_size, 2);
	assert_int_equal(t.count, 3);
	assert_int_equal(t.consumed, 9);
	assert_int_equal((int16_t)le16(t.data), 0);
	assert_int_equal((int16_t)le16(t.data + 2), -2);
	assert_int_equal((int16_t)le16(t.data + 4), 255);

	/* M p.124: 10-integer array, size in two bytes */
	n = hex("9A 09 15 00 42 00 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 09 00", b, sizeof b);
	assert_int_equal(pccc_dec_typed(b, n, &t), 0);
	assert_int_equal(t.count, 10);
	assert_int_equal(t.len, 20);
	assert_int_equal(le16(t.data + 18), 9);

	/* derived-plc5-68-reply-0..9: reply data after the header */
	n = hex("99 09 15 42 00 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 09 00", b, sizeof b);
	assert_int_equal(pccc_dec_typed(b, n, &t), 0);
	assert_int_equal(t.type_id, PCCC_TD_INTEGER);
	assert_int_equal(t.count, 10);
	for (int i = 0; i < 10; i++)
		assert_int_equal((int16_t)le16(t.data + 2 * i), i);

	/* not an array: integer 2 bytes */
	n = hex("42 34 12", b, sizeof b);
	assert_int_equal(pccc_dec_typed(b, n, &t), 0);
	assert_false(t.is_array);
	assert_int_equal(t.count, 1);
	assert_int_equal(le16(t.data), 0x1234);

	/* RTA string "39 <len> <bytes>" */
	n = hex("39 03 41 42 43", b, sizeof b);
	assert_int_equal(pccc_dec_typed(b, n, &t), 0);
	assert_int_equal(t.type_id, PCCC_TD_STRING);
	assert_int_equal(t.len, 3);
	assert_memory_equal(t.data, "ABC", 3);

	n = hex("99 09 15 42 00 00", b, sizeof b);      /* declared longer than present */
	assert_int_equal(pccc_dec_typed(b, n, &t), DF1_E_TOO_SHORT);
	n = hex("99 09 04 42 00 00 00", b, sizeof b);   /* 3 data bytes of 2-byte ints */
	assert_int_equal(pccc_dec_typed(b, n, &t), DF1_E_BAD_REPLY);
	n = hex("99 09 03 40 00 00", b, sizeof b);      /* element size 0 */
	assert_int_equal(pccc_dec_typed(b, n, &t), DF1_E_BAD_REPLY);
}

/* ------------------------------------------------------------------------
 * Diagnostic status (doc/PROTOCOL.md 4.9)
 * ------------------------------------------------------------------------ */

static void test_pccc_diag_status_slc_form(void **state)
{
	uint8_t d[32];
	struct df1_diag_status s;
	(void)state;

	/* M p.174 layout: 00 EE 1F type ser/rev "bulletin" err(2) mode(2) ... */
	memset(d, 0, sizeof d);
	d[0] = 0x00;
	d[1] = 0xEE;
	d[2] = 0x1F;
	d[3] = 0x25;                    /* SLC 5/02 */
	d[4] = (1 << 5) | 2;            /* series B, revision bits 2 = release 3 */
	memcpy(d + 5, "5/02       ", 11);
	d[18] = 0x06;                   /* run */
	assert_int_equal(pccc_dec_diag_status(d, 24, &s), 0);
	assert_int_equal(s.type_code, 0x25);
	assert_string_equal(s.name, "SLC 5/02");
	assert_int_equal(s.series, 'B');
	assert_int_equal(s.revision, 3);
	assert_string_equal(s.bulletin, "5/02");
	assert_int_equal(s.mode, 6);
	assert_string_equal(s.mode_text, "run");
	assert_int_equal(s.raw_len, 24);
	assert_memory_equal(s.raw, d, 24);

	d[3] = 0x58;                    /* MicroLogix 1000 (M p.177) */
	d[4] = 0;
	d[18] = 0x01;
	assert_int_equal(pccc_dec_diag_status(d, 24, &s), 0);
	assert_string_equal(s.name, "MicroLogix 1000");
	assert_int_equal(s.series, 'A');
	assert_int_equal(s.revision, 1);
	assert_string_equal(s.mode_text, "program");
}

static void test_pccc_diag_status_plc5_interface_and_other(void **state)
{
	uint8_t d[32];
	struct df1_diag_status s;
	(void)state;

	/* M p.192: mode, EB, expansion type, memory(4), series/revision ... */
	memset(d, 0, sizeof d);
	d[0] = 0x06;                    /* remote run */
	d[1] = 0xEB;
	d[2] = 0x15;                    /* PLC-5/40 */
	d[7] = (2 << 5) | 1;            /* series C */
	assert_int_equal(pccc_dec_diag_status(d, 18, &s), 0);
	assert_int_equal(s.type_code, 0x15);
	assert_string_equal(s.name, "PLC-5/40");
	assert_int_equal(s.mode, 6);
	assert_string_equal(s.mode_text, "remote run");
	assert_int_equal(s.series, 'C');
	assert_int_equal(s.revision, 2);

	d[0] = 0x02;
	d[2] = 0x28;
	assert_int_equal(pccc_dec_diag_status(d, 18, &s), 0);
	assert_string_equal(s.name, "PLC-5/40L");
	assert_string_equal(s.mode_text, "run");

	/* interface module (F2E p.52) */
	memset(d, 0, sizeof d);
	d[1] = 0xFE;
	d[2] = 0x2C;
	assert_int_equal(pccc_dec_diag_status(d, 3, &s), 0);
	assert_string_equal(s.name, "1770-KF3");

	/* anything else: type at d[7] */
	memset(d, 0, sizeof d);
	d[1] = 0x30;
	d[7] = 0x9F;
	assert_int_equal(pccc_dec_diag_status(d, 8, &s), 0);
	assert_int_equal(s.type_code, 0x9F);
	assert_string_equal(s.name, "MicroLogix 1400");
	d[7] = 0x77;
	assert_int_equal(pccc_dec_diag_status(d, 8, &s), 0);
	assert_string_equal(s.name, "unknown (0x77)");

	assert_int_equal(pccc_dec_diag_status(d, 7, &s), DF1_E_TOO_SHORT);
	assert_int_equal(pccc_dec_diag_status(d, 1, &s), DF1_E_TOO_SHORT);
	d[1] = 0xEE;
	assert_int_equal(pccc_dec_diag_status(d, 3, &s), DF1_E_TOO_SHORT);
}

static void test_pccc_processor_names_cover_both_lists(void **state)
{
	static const struct { uint8_t code; const char *name; } want[] = {
		{ 0x13, "PLC-5/12" }, { 0x14, "PLC-5/25" }, { 0x15, "PLC-5/40" },
		{ 0x18, "SLC 5/01" }, { 0x1A, "SLC 500 (fixed)" }, { 0x21, "PLC-5/60" },
		{ 0x22, "PLC-5/10" }, { 0x23, "PLC-5/60" }, { 0x25, "SLC 5/02" },
		{ 0x28, "PLC-5/40L" }, { 0x29, "PLC-5/60L" }, { 0x31, "PLC-5/11" },
		{ 0x32, "PLC-5/20" }, { 0x33, "PLC-5/30" }, { 0x49, "SLC 5/03" },
		{ 0x4A, "PLC-5/20E" }, { 0x4B, "PLC-5/40E" }, { 0x58, "MicroLogix 1000" },
		{ 0x59, "PLC-5/80E" }, { 0x5B, "SLC 5/04" }, { 0x6F, "SLC 5/04 (L541)" },
		{ 0x78, "SLC 5/05" }, { 0x83, "PLC-5/30E" }, { 0x86, "PLC-5/80E" },
		{ 0x88, "MicroLogix 1200" }, { 0x89, "MicroLogix 1500 LSP" },
		{ 0x8C, "MicroLogix 1500 LRP" }, { 0x95, "CompactLogix L35E" },
		{ 0x9C, "MicroLogix 1100" }, { 0x9F, "MicroLogix 1400" },
	};
	(void)state;

	for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
		const char *n = pccc_processor_name(want[i].code);

		assert_non_null(n);
		assert_string_equal(n, want[i].name);
	}
	assert_null(pccc_processor_name(0x00));
}

static void test_pccc_command_names(void **state)
{
	(void)state;
	assert_string_equal(pccc_command_name(0x0F, true, 0xA2), "SLC typed read, 3 fields (0F/A2)");
	assert_string_equal(pccc_command_name(0x0F, true, 0xAB), "SLC masked write (0F/AB)");
	assert_string_equal(pccc_command_name(0x0F, true, 0x68), "typed read (0F/68)");
	assert_string_equal(pccc_command_name(0x0F, true, 0x80), "change mode (0F/80)");
	assert_string_equal(pccc_command_name(0x06, true, 0x00), "echo (06/00)");
	assert_string_equal(pccc_command_name(0x06, true, 0x03), "diagnostic status (06/03)");
	assert_string_equal(pccc_command_name(0x01, false, 0), "unprotected read (01)");
	assert_string_equal(pccc_command_name(0x08, false, 0), "unprotected write (08)");
	assert_string_equal(pccc_command_name(0x4F, false, 0), "reply (4F)");
	assert_string_equal(pccc_command_name(0x0F, true, 0x99), "unknown function (0F)");
	assert_string_equal(pccc_command_name(0x3E, false, 0), "unknown command");
}

/* ------------------------------------------------------------------------
 * Every message frame of tests/data/vectors.txt (doc/PROTOCOL.md 7):
 * its fields decoded, then the message re-encoded from those fields with the
 * encoder of its command and framed again, byte for byte the vector's wire bytes.
 * ------------------------------------------------------------------------ */

/* The fields of a command, decoded; then the command built from them. */
static int reencode_command(const uint8_t *app, size_t n, uint8_t *out, size_t cap)
{
	struct pccc_msg m;
	struct pccc_hdr h;
	int r = pccc_decode(app, n, &m);

	assert_int_equal(r, 0);
	h.dst = m.dst;
	h.src = m.src;
	h.tns = m.tns;
	if (m.cmd == PCCC_CMD_UNPROT_READ) {
		assert_int_equal(m.len, 3);
		return pccc_enc_plc2_read(out, cap, &h, le16(m.data), m.data[2]);
	}
	if (m.cmd == PCCC_CMD_UNPROT_WRITE)
		return pccc_enc_plc2_write(out, cap, &h, le16(m.data), m.data + 2, m.len - 2);
	if (m.cmd == PCCC_CMD_DIAG && m.fnc == PCCC_FNC_ECHO)
		return pccc_enc_echo(out, cap, &h, m.data, m.len);
	if (m.cmd == PCCC_CMD_DIAG && m.fnc == PCCC_FNC_DIAG_STATUS) {
		assert_int_equal(m.len, 0);
		return pccc_enc_diag_status(out, cap, &h);
	}
	assert_int_equal(m.cmd, PCCC_CMD_TYPED);
	switch (m.fnc) {
	case PCCC_FNC_CHANGE_MODE:
		assert_int_equal(m.len, 1);
		return pccc_enc_change_mode(out, cap, &h, m.data[0]);
	case PCCC_FNC_SLC_READ2: case PCCC_FNC_SLC_READ3:
	case PCCC_FNC_SLC_WRITE2: case PCCC_FNC_SLC_WRITE3: case PCCC_FNC_SLC_MASKED: {
		bool three = m.fnc != PCCC_FNC_SLC_READ2 && m.fnc != PCCC_FNC_SLC_WRITE2;
		uint8_t nbytes, code;
		unsigned file, elem, sub;
		int k = pccc_dec_slc_fields(m.data, m.len, three, &nbytes, &file, &code, &elem, &sub);
		const uint8_t *d = m.data + k;

		assert_true(k > 0);
		if (m.fnc == PCCC_FNC_SLC_READ2 || m.fnc == PCCC_FNC_SLC_READ3) {
			assert_int_equal((size_t)k, m.len);
			return pccc_enc_slc_read(out, cap, &h, m.fnc, nbytes, file, code, elem, sub);
		}
		if (m.fnc == PCCC_FNC_SLC_MASKED) {
			assert_int_equal(m.len - (size_t)k, 2u * nbytes);
			return pccc_enc_slc_masked_write(out, cap, &h, file, code, elem, sub, d, d + nbytes,
			                                 nbytes);
		}
		assert_int_equal(m.len - (size_t)k, nbytes);
		return pccc_enc_slc_write(out, cap, &h, m.fnc, file, code, elem, sub, d, nbytes);
	}
	default:
		break;
	}
	{
		struct pccc_plc5_req q;
		enum pccc_plc5_form form;
		uint8_t addr[64];
		int alen;

		assert_int_equal(pccc_dec_plc5_req(m.fnc, m.data, m.len, &q), 0);
		/* which levels the sender encoded is part of the address field: its mask */
		{
			size_t at = (m.fnc == PCCC_FNC_RMW || m.fnc == PCCC_FNC_BIT_WRITE) ? 0 : 4;
			uint8_t mask = m.data[at];

			form = (mask & 0x01) == 0 ? PCCC_PLC5_FILE_ELEM
			     : (mask == 0x0F && q.addr.sub == 0) ? PCCC_PLC5_FOUR_LEVELS : PCCC_PLC5_ALL_LEVELS;
		}
		alen = pccc_enc_plc5_addr_form(addr, sizeof addr, &q.addr, form);
		assert_true(alen > 0);
		switch (m.fnc) {
		case PCCC_FNC_TYPED_READ:
			assert_int_equal(q.len, 0);
			return pccc_enc_plc5_typed_read(out, cap, &h, q.pkt_offset, q.total, addr, (size_t)alen,
			                                (uint16_t)q.size);
		case PCCC_FNC_TYPED_WRITE: {
			struct pccc_typed t;
			uint8_t typed[256];
			int tl;

			assert_int_equal(pccc_dec_typed(q.data, q.len, &t), 0);
			assert_int_equal(t.consumed, q.len);
			tl = t.is_array ? pccc_enc_typed_array(typed, sizeof typed, t.type_id, t.elem_size, t.count)
			                : pccc_enc_typedata(typed, sizeof typed, t.type_id, t.elem_size);
			assert_true(tl > 0 && (size_t)tl + t.len <= sizeof typed);
			memcpy(typed + tl, t.data, t.len);
			return pccc_enc_plc5_typed_write(out, cap, &h, q.pkt_offset, q.total, addr, (size_t)alen,
			                                 typed, (size_t)tl + t.len);
		}
		case PCCC_FNC_WORD_READ:
			assert_int_equal(q.len, 0);
			return pccc_enc_plc5_word_read(out, cap, &h, q.pkt_offset, q.total, addr, (size_t)alen,
			                               (uint8_t)q.size);
		case PCCC_FNC_WORD_WRITE:
			return pccc_enc_plc5_word_write(out, cap, &h, q.pkt_offset, q.total, addr, (size_t)alen,
			                                q.data, q.len);
		case PCCC_FNC_RMW:
			assert_int_equal(q.len, 4);
			return pccc_enc_plc5_rmw(out, cap, &h, addr, (size_t)alen, le16(q.data), le16(q.data + 2));
		case PCCC_FNC_BIT_WRITE:
			assert_int_equal(q.len, 4);
			return pccc_enc_plc5_bit_write(out, cap, &h, addr, (size_t)alen, le16(q.data),
			                               le16(q.data + 2));
		default:
			fail_msg("no encoder for 0F/%02X", m.fnc);
			return -1;
		}
	}
}

/* A reply: its header fields, STS, EXT STS and data, through pccc_encode_reply. */
static int reencode_reply(const uint8_t *app, size_t n, uint8_t *out, size_t cap)
{
	struct pccc_msg m, cmd;

	assert_int_equal(pccc_decode(app, n, &m), 0);
	memset(&cmd, 0, sizeof cmd);
	cmd.dst = m.src;
	cmd.src = m.dst;
	cmd.cmd = (uint8_t)(m.cmd & ~PCCC_REPLY_BIT);
	cmd.tns = m.tns;
	return pccc_encode_reply(out, cap, &cmd, m.sts, m.ext_sts, m.data, m.len);
}

static void test_pccc_vectors_reencoded_from_their_fields(void **state)
{
	FILE *f = fopen("tests/data/vectors.txt", "r");
	char line[2048];
	int commands = 0, replies = 0;
	(void)state;

	if (!f)
		fail_msg("cannot open tests/data/vectors.txt (run from the repository root)");
	while (fgets(line, sizeof line, f)) {
		char *name = line, *chk, *hexs, *end;
		uint8_t wire[600], app[300], enc[300], frame[700];
		size_t nw = 0, na = 0, i, nf;
		bool master = false;
		uint8_t stn = 0;
		enum df1_check check;
		int ne;

		if (line[0] == '#' || line[0] == '\n')
			continue;
		chk = strstr(name, " | ");
		assert_non_null(chk);
		*chk = 0;
		chk += 3;
		hexs = strstr(chk, " | ");
		assert_non_null(hexs);
		*hexs = 0;
		hexs += 3;
		end = strstr(hexs, " | ");
		assert_non_null(end);
		*end = 0;
		if (strcmp(chk, "bcc") && strcmp(chk, "crc"))
			continue;               /* link symbols */
		check = strcmp(chk, "bcc") == 0 ? DF1_CHECK_BCC : DF1_CHECK_CRC;
		nw = hex(hexs, wire, sizeof wire);
		if (wire[1] == 0x05)
			continue;               /* a poll: no message */
		/* de-stuff by the spec's rules (1.3, 2.2) */
		i = 2;
		if (wire[1] == 0x01) {
			master = true;
			stn = wire[2];
			i = stn == 0x10 ? 4 : 3;
			assert_true(wire[i] == 0x10 && wire[i + 1] == 0x02);
			i += 2;
		}
		while (!(wire[i] == 0x10 && wire[i + 1] == 0x03)) {
			if (wire[i] == 0x10)
				i++;
			app[na++] = wire[i++];
		}
		print_message("vector %s/%s\n", name, chk);
		if (app[2] & PCCC_REPLY_BIT) {
			ne = reencode_reply(app, na, enc, sizeof enc);
			replies++;
		} else {
			ne = reencode_command(app, na, enc, sizeof enc);
			commands++;
		}
		assert_int_equal(ne, (int)na);
		assert_memory_equal(enc, app, na);
		nf = master ? frame_encode_master(check, stn, false, enc, (size_t)ne, frame, sizeof frame)
		            : frame_encode_full(check, enc, (size_t)ne, frame, sizeof frame);
		assert_int_equal(nf, nw);
		assert_memory_equal(frame, wire, nw);
	}
	fclose(f);
	/* tests/data/vectors.txt: 38 command frames and 12 replies */
	assert_true(commands >= 38);
	assert_true(replies >= 12);
}

/* ------------------------------------------------------------------------
 * df1_msg_decode (public)
 * ------------------------------------------------------------------------ */

static void test_msg_decode_slc_commands(void **state)
{
	uint8_t b[64];
	size_t n;
	struct df1_msg m;
	char text[32];
	(void)state;

	n = hex("01 00 0F 00 01 00 A2 14 07 89 00 00", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_false(m.is_reply);
	assert_true(m.has_fnc);
	assert_int_equal(m.fnc, 0xA2);
	assert_string_equal(m.name, "SLC typed read, 3 fields (0F/A2)");
	assert_true(m.has_addr);
	assert_int_equal(m.addr.type, DF1_FT_N);
	assert_int_equal(m.addr.file, 7);
	assert_int_equal(m.addr.element, 0);
	assert_int_equal(m.addr.sub, DF1_ADDR_NONE);
	assert_int_equal(m.addr.bit, DF1_ADDR_NONE);
	assert_int_equal(m.size, 20);
	assert_int_equal(m.data_len, 0);
	assert_int_equal(df1_addr_format(&m.addr, text, sizeof text), 4);
	assert_string_equal(text, "N7:0");

	n = hex("00 00 0F 00 01 39 AA 02 07 89 05 00 49 34", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_int_equal(m.tns, 0x3901);
	assert_int_equal(m.addr.element, 5);
	assert_int_equal(m.size, 2);
	assert_int_equal(m.data_len, 2);
	assert_int_equal(le16(m.data), 0x3449);

	n = hex("01 00 0F 00 03 00 AB 02 03 85 00 00 20 00 20 00", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_int_equal(m.addr.type, DF1_FT_B);
	assert_int_equal(m.addr.file, 3);
	assert_int_equal(m.size, 2);
	assert_int_equal(m.data_len, 4);        /* MASK then DATA */

	/* T4:2.ACC read: a non-zero sub-element stays */
	n = hex("01 00 0F 00 01 00 A2 02 04 86 02 02", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_int_equal(m.addr.type, DF1_FT_T);
	assert_int_equal(m.addr.sub, 2);
	assert_int_equal(df1_addr_format(&m.addr, text, sizeof text), 8);
	assert_string_equal(text, "T4:2.ACC");

	/* truncated fields: header and name are there, no address */
	n = hex("01 00 0F 00 01 00 A2 14 07", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), DF1_E_TOO_SHORT);
	assert_string_equal(m.name, "SLC typed read, 3 fields (0F/A2)");
	assert_false(m.has_addr);
	assert_int_equal(m.data_len, 2);
	n = hex("01 00 0F 00 02 00 AA 02 07 89 05 00 34", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), DF1_E_TOO_SHORT);
}

static void test_msg_decode_plc5_commands(void **state)
{
	uint8_t b[64];
	size_t n;
	struct df1_msg m;
	(void)state;

	n = hex("01 00 0F 00 06 00 68 00 00 0A 00 06 07 00 0A 00", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_string_equal(m.name, "typed read (0F/68)");
	assert_true(m.has_addr);
	assert_int_equal(m.addr.type, DF1_FT_NONE);
	assert_int_equal(m.addr.file, 7);
	assert_int_equal(m.addr.element, 0);
	assert_int_equal(m.size, 10);

	n = hex("01 00 0F 00 07 00 68 00 00 01 00 00 24 4E 37 3A 30 00 01 00", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_string_equal(m.addr.ascii, "N7:0");
	assert_int_equal(m.addr.type, DF1_FT_N);
	assert_int_equal(m.size, 1);

	n = hex("01 00 0F 00 08 00 67 00 00 02 00 06 07 00 99 09 05 42 01 00 02 00", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_int_equal(m.size, 2);
	assert_int_equal(m.data_len, 4);
	assert_int_equal(le16(m.data), 1);
	assert_int_equal(le16(m.data + 2), 2);

	n = hex("29 20 0F 00 46 01 00 00 00 04 00 0F 00 0A 0F 00 22 11 44 33 66 55 88 77", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_string_equal(m.name, "word range write (0F/00)");
	assert_int_equal(m.addr.file, 10);
	assert_int_equal(m.addr.element, 15);
	assert_int_equal(m.size, 8);
	assert_int_equal(m.data_len, 8);

	n = hex("29 20 0F 00 47 01 01 00 00 04 00 00 24 4E 31 30 3A 31 35 00 08", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_string_equal(m.addr.ascii, "N10:15");
	assert_int_equal(m.size, 8);

	n = hex("01 00 0F 00 0A 00 26 06 07 00 FF FF 08 00", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_int_equal(m.addr.file, 7);
	assert_int_equal(m.data_len, 4);
}

static void test_msg_decode_other_commands_and_replies(void **state)
{
	uint8_t b[64];
	size_t n;
	struct df1_msg m;
	(void)state;

	n = hex("09 00 01 00 01 00 11 00 02", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_false(m.has_fnc);
	assert_false(m.has_addr);
	assert_int_equal(m.size, 2);

	n = hex("29 20 08 00 44 01 28 00 22 11 44 33 66 55 88 77", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_int_equal(m.size, 8);
	assert_int_equal(m.data_len, 8);

	n = hex("01 00 06 00 0C 00 00 41", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_string_equal(m.name, "echo (06/00)");
	assert_int_equal(m.size, -1);
	assert_int_equal(m.data_len, 1);
	assert_int_equal(m.data[0], 'A');

	n = hex("01 00 0F 00 0D 00 80 06", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_string_equal(m.name, "change mode (0F/80)");
	assert_int_equal(m.data_len, 1);
	assert_int_equal(m.data[0], 6);

	n = hex("00 01 4F F0 05 00 06", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_true(m.is_reply);
	assert_string_equal(m.name, "reply (4F)");
	assert_true(m.has_ext_sts);
	assert_int_equal(m.ext_sts, 6);
	assert_int_equal(m.data_len, 0);

	n = hex("00 01 4F 00 04 00 00 00 C0 3F", b, sizeof b);
	assert_int_equal(df1_msg_decode(b, n, &m), 0);
	assert_false(m.has_addr);
	assert_int_equal(m.data_len, 4);
	assert_true(value_get_float(m.data, VALUE_FLOAT_LE) == 1.5f);

	assert_int_equal(df1_msg_decode(b, 5, &m), DF1_E_TOO_SHORT);
	assert_non_null(m.name);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_pccc_slc_a2_read_matches_vectors),
		cmocka_unit_test(test_pccc_slc_a1_two_fields_has_no_sub),
		cmocka_unit_test(test_pccc_slc_aa_write_matches_vectors),
		cmocka_unit_test(test_pccc_slc_ab_masked_write_matches_vector),
		cmocka_unit_test(test_pccc_field_escape_above_254),
		cmocka_unit_test(test_pccc_dec_slc_fields_reads_vectors),
		cmocka_unit_test(test_pccc_slc_codes_map_to_file_types),
		cmocka_unit_test(test_pccc_plc5_addr_forms_match_manual),
		cmocka_unit_test(test_pccc_plc5_addr_ascii_form),
		cmocka_unit_test(test_pccc_plc5_addr_decoder_accepts_all_forms),
		cmocka_unit_test(test_pccc_plc5_addr_ascii_decodes_and_parses),
		cmocka_unit_test(test_pccc_plc5_typed_read_matches_vectors),
		cmocka_unit_test(test_pccc_plc5_typed_write_matches_vector),
		cmocka_unit_test(test_pccc_plc5_word_range_matches_vectors),
		cmocka_unit_test(test_pccc_plc5_rmw_and_bit_write),
		cmocka_unit_test(test_pccc_dec_plc5_req_reads_command_bodies),
		cmocka_unit_test(test_pccc_plc2_matches_manual_vectors),
		cmocka_unit_test(test_pccc_diag_echo_mode_match_vectors),
		cmocka_unit_test(test_pccc_decode_replies_from_vectors),
		cmocka_unit_test(test_pccc_decode_ext_sts_rules),
		cmocka_unit_test(test_pccc_decode_commands),
		cmocka_unit_test(test_pccc_encode_reply_swaps_and_echoes_tns),
		cmocka_unit_test(test_pccc_typedata_decodes_all_forms),
		cmocka_unit_test(test_pccc_typedata_encodes_shortest),
		cmocka_unit_test(test_pccc_typed_tcr_5_words),
		cmocka_unit_test(test_pccc_typed_arrays_from_manual_and_vector),
		cmocka_unit_test(test_pccc_diag_status_slc_form),
		cmocka_unit_test(test_pccc_diag_status_plc5_interface_and_other),
		cmocka_unit_test(test_pccc_processor_names_cover_both_lists),
		cmocka_unit_test(test_pccc_command_names),
		cmocka_unit_test(test_pccc_vectors_reencoded_from_their_fields),
		cmocka_unit_test(test_msg_decode_slc_commands),
		cmocka_unit_test(test_msg_decode_plc5_commands),
		cmocka_unit_test(test_msg_decode_other_commands_and_replies),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
