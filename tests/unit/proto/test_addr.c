/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_addr.c - addresses: parse, format, round trips, file type tables.
 *
 * Expected fields come from the controllers' notation (SLC / MicroLogix / PLC-5
 * programming manuals as summarised in doc/PROTOCOL.md 4.11 and 5) and the
 * address rules of doc/REQUIREMENTS.md 004, written out by hand, not computed by the module.
 * Random tests: DF1_TEST_SEED=<n> replays a run; the seed is printed on failure.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <cmocka.h>

#include "df1.h"

#define NO DF1_ADDR_NONE

struct valid_case {
	const char *text;
	enum df1_file_type type;
	int file, element, sub, bit;
	const char *ascii;     /* expected ascii ("" unless "$") */
	const char *canonical; /* expected df1_addr_format text */
};

static const struct valid_case valid_cases[] = {
	/* integer, float, default and user files */
	{ "N7:0", DF1_FT_N, 7, 0, NO, NO, "", "N7:0" },
	{ "N7:1", DF1_FT_N, 7, 1, NO, NO, "", "N7:1" },
	{ "N10:255", DF1_FT_N, 10, 255, NO, NO, "", "N10:255" },
	{ "N:5", DF1_FT_N, 7, 5, NO, NO, "", "N7:5" },
	{ "N999:999", DF1_FT_N, 999, 999, NO, NO, "", "N999:999" },
	{ "N7:0/0", DF1_FT_N, 7, 0, NO, 0, "", "N7:0/0" },
	{ "N7:10/15", DF1_FT_N, 7, 10, NO, 15, "", "N7:10/15" },
	{ "N3:0", DF1_FT_N, 3, 0, NO, NO, "", "N3:0" },
	{ "n7:2", DF1_FT_N, 7, 2, NO, NO, "", "N7:2" },
	{ "N007:0003", DF1_FT_N, 7, 3, NO, NO, "", "N7:3" },
	{ "F8:3", DF1_FT_F, 8, 3, NO, NO, "", "F8:3" },
	{ "F:0", DF1_FT_F, 8, 0, NO, NO, "", "F8:0" },
	{ "F20:7", DF1_FT_F, 20, 7, NO, NO, "", "F20:7" },
	{ "f8:1", DF1_FT_F, 8, 1, NO, NO, "", "F8:1" },
	/* bit files */
	{ "B3:0/5", DF1_FT_B, 3, 0, NO, 5, "", "B3:0/5" },
	{ "B3:0", DF1_FT_B, 3, 0, NO, NO, "", "B3:0" },
	{ "B3/21", DF1_FT_B, 3, 1, NO, 5, "", "B3:1/5" },
	{ "B3/0", DF1_FT_B, 3, 0, NO, 0, "", "B3:0/0" },
	{ "B3/15", DF1_FT_B, 3, 0, NO, 15, "", "B3:0/15" },
	{ "B3/16", DF1_FT_B, 3, 1, NO, 0, "", "B3:1/0" },
	{ "B3/15999", DF1_FT_B, 3, 999, NO, 15, "", "B3:999/15" },
	{ "B10/37", DF1_FT_B, 10, 2, NO, 5, "", "B10:2/5" },
	{ "B/21", DF1_FT_B, 3, 1, NO, 5, "", "B3:1/5" },
	{ "B:4/15", DF1_FT_B, 3, 4, NO, 15, "", "B3:4/15" },
	{ "b3:2/7", DF1_FT_B, 3, 2, NO, 7, "", "B3:2/7" },
	/* timers */
	{ "T4:0", DF1_FT_T, 4, 0, NO, NO, "", "T4:0" },
	{ "T4:0.ACC", DF1_FT_T, 4, 0, 2, NO, "", "T4:0.ACC" },
	{ "T4:0.PRE", DF1_FT_T, 4, 0, 1, NO, "", "T4:0.PRE" },
	{ "T4:0/DN", DF1_FT_T, 4, 0, 0, 13, "", "T4:0/DN" },
	{ "T4:0/EN", DF1_FT_T, 4, 0, 0, 15, "", "T4:0/EN" },
	{ "T4:0/TT", DF1_FT_T, 4, 0, 0, 14, "", "T4:0/TT" },
	{ "T4:0.DN", DF1_FT_T, 4, 0, 0, 13, "", "T4:0/DN" },   /* PLC-5 spelling */
	{ "T4:0.0", DF1_FT_T, 4, 0, 0, NO, "", "T4:0.0" },
	{ "T4:0.1", DF1_FT_T, 4, 0, 1, NO, "", "T4:0.PRE" },
	{ "T4:0.2", DF1_FT_T, 4, 0, 2, NO, "", "T4:0.ACC" },
	{ "T4:0/13", DF1_FT_T, 4, 0, 0, 13, "", "T4:0/DN" },
	{ "T4:0.0/13", DF1_FT_T, 4, 0, 0, 13, "", "T4:0/DN" },
	{ "T4:0/3", DF1_FT_T, 4, 0, 0, 3, "", "T4:0/3" },
	{ "T4:5.ACC/3", DF1_FT_T, 4, 5, 2, 3, "", "T4:5.ACC/3" },
	{ "T4:1.2/15", DF1_FT_T, 4, 1, 2, 15, "", "T4:1.ACC/15" },
	{ "t4:0.acc", DF1_FT_T, 4, 0, 2, NO, "", "T4:0.ACC" },
	{ "t4:0/dn", DF1_FT_T, 4, 0, 0, 13, "", "T4:0/DN" },
	{ "T:3.Pre", DF1_FT_T, 4, 3, 1, NO, "", "T4:3.PRE" },
	{ "T12:7/EN", DF1_FT_T, 12, 7, 0, 15, "", "T12:7/EN" },
	/* counters */
	{ "C5:1.ACC", DF1_FT_C, 5, 1, 2, NO, "", "C5:1.ACC" },
	{ "C5:1.PRE", DF1_FT_C, 5, 1, 1, NO, "", "C5:1.PRE" },
	{ "C5:1/OV", DF1_FT_C, 5, 1, 0, 12, "", "C5:1/OV" },
	{ "C5:1/CU", DF1_FT_C, 5, 1, 0, 15, "", "C5:1/CU" },
	{ "C5:1/CD", DF1_FT_C, 5, 1, 0, 14, "", "C5:1/CD" },
	{ "C5:1/DN", DF1_FT_C, 5, 1, 0, 13, "", "C5:1/DN" },
	{ "C5:1/UN", DF1_FT_C, 5, 1, 0, 11, "", "C5:1/UN" },
	{ "C5:1/UA", DF1_FT_C, 5, 1, 0, 10, "", "C5:1/UA" },
	{ "C5:0", DF1_FT_C, 5, 0, NO, NO, "", "C5:0" },
	{ "C:2.CU", DF1_FT_C, 5, 2, 0, 15, "", "C5:2/CU" },
	/* control */
	{ "R6:0.LEN", DF1_FT_R, 6, 0, 1, NO, "", "R6:0.LEN" },
	{ "R6:0.POS", DF1_FT_R, 6, 0, 2, NO, "", "R6:0.POS" },
	{ "R6:0/EN", DF1_FT_R, 6, 0, 0, 15, "", "R6:0/EN" },
	{ "R6:0/EU", DF1_FT_R, 6, 0, 0, 14, "", "R6:0/EU" },
	{ "R6:0/DN", DF1_FT_R, 6, 0, 0, 13, "", "R6:0/DN" },
	{ "R6:0/EM", DF1_FT_R, 6, 0, 0, 12, "", "R6:0/EM" },
	{ "R6:0/ER", DF1_FT_R, 6, 0, 0, 11, "", "R6:0/ER" },
	{ "R6:0/UL", DF1_FT_R, 6, 0, 0, 10, "", "R6:0/UL" },
	{ "R6:0/IN", DF1_FT_R, 6, 0, 0, 9, "", "R6:0/IN" },
	{ "R6:0/FD", DF1_FT_R, 6, 0, 0, 8, "", "R6:0/FD" },
	{ "R6:3.1", DF1_FT_R, 6, 3, 1, NO, "", "R6:3.LEN" },
	/* status, I/O */
	{ "S:1/5", DF1_FT_S, 2, 1, NO, 5, "", "S2:1/5" },
	{ "S2:0", DF1_FT_S, 2, 0, NO, NO, "", "S2:0" },
	{ "S:37", DF1_FT_S, 2, 37, NO, NO, "", "S2:37" },
	{ "I:0/3", DF1_FT_I, 1, 0, NO, 3, "", "I1:0/3" },
	{ "I1:0.1/3", DF1_FT_I, 1, 0, 1, 3, "", "I1:0.1/3" },
	{ "I:2.0", DF1_FT_I, 1, 2, 0, NO, "", "I1:2.0" },
	{ "I:1", DF1_FT_I, 1, 1, NO, NO, "", "I1:1" },
	{ "O:0", DF1_FT_O, 0, 0, NO, NO, "", "O0:0" },
	{ "O0:3/15", DF1_FT_O, 0, 3, NO, 15, "", "O0:3/15" },
	{ "O:1.255/0", DF1_FT_O, 0, 1, 255, 0, "", "O0:1.255/0" },
	/* string, long, ASCII */
	{ "ST9:0", DF1_FT_ST, 9, 0, NO, NO, "", "ST9:0" },
	{ "st10:3", DF1_FT_ST, 10, 3, NO, NO, "", "ST10:3" },
	{ "L10:0", DF1_FT_L, 10, 0, NO, NO, "", "L10:0" },
	{ "L10:0/31", DF1_FT_L, 10, 0, NO, 31, "", "L10:0/31" },
	{ "L10:4/16", DF1_FT_L, 10, 4, NO, 16, "", "L10:4/16" },
	{ "A11:0", DF1_FT_A, 11, 0, NO, NO, "", "A11:0" },
	{ "A11:2/7", DF1_FT_A, 11, 2, NO, 7, "", "A11:2/7" },
	/* PLC-5 logical ASCII pass-through */
	{ "$N7:0", DF1_FT_N, 7, 0, NO, NO, "N7:0", "$N7:0" },
	{ "$N10:15", DF1_FT_N, 10, 15, NO, NO, "N10:15", "$N10:15" },
	{ "$T4:0.ACC", DF1_FT_T, 4, 0, 2, NO, "T4:0.ACC", "$T4:0.ACC" },
	{ "$B3/21", DF1_FT_B, 3, 1, NO, 5, "B3/21", "$B3/21" },
	{ "$n7:0", DF1_FT_N, 7, 0, NO, NO, "n7:0", "$n7:0" },
	{ "$S:1/5", DF1_FT_S, 2, 1, NO, 5, "S:1/5", "$S:1/5" },
};

struct invalid_case {
	const char *text;
	int id;         /* the seed catalog ID the rejection reports (doc/REQUIREMENTS.md 004) */
};

#define SYN 2503        /* ERR_ADDRESS_SYNTAX */
#define RNG 2504        /* ERR_ADDRESS_RANGE */

static const struct invalid_case invalid_cases[] = {
	/* syntax: not the grammar */
	{ "", SYN },
	{ "$", SYN },
	{ "7:0", SYN },
	{ ":0", SYN },
	{ "N7", SYN },
	{ "N7:", SYN },
	{ "N7:x", SYN },
	{ "N7::0", SYN },
	{ "N7:0:1", SYN },
	{ "N7:-1", SYN },
	{ "N-7:0", SYN },
	{ "N+7:0", SYN },
	{ " N7:0", SYN },
	{ "N7:0 ", SYN },
	{ "N 7:0", SYN },
	{ "N7;0", SYN },  /* doc/REQUIREMENTS.md 004 prints ';' but the controllers use ':' */
	{ "X7:0", SYN },
	{ "NN7:0", SYN },
	{ "D9:0", SYN },  /* BCD: not a libdf1 file type */
	{ "MG9:0", SYN },
	{ "$$N7:0", SYN },
	{ "N7:0.", SYN },
	{ "N7:0/", SYN },
	{ "N7:0/x", SYN },
	{ "N7:0/1/2", SYN },
	{ "N7:0.1", SYN },  /* N has no sub-elements */
	{ "B3:0.1", SYN },
	{ "F8:0/3", SYN },  /* no bits in a float */
	{ "ST9:0/1", SYN }, /* nor in a string */
	{ "ST9:0.1", SYN },
	{ "L10:0.1", SYN },
	{ "ST:0", SYN },    /* user types need a file number */
	{ "L:0", SYN },
	{ "A:0", SYN },
	{ "N7/21", SYN },   /* "/n" bit numbering is B only */
	{ "T4/3", SYN },
	{ "B3/", SYN },
	{ "B3/x", SYN },
	{ "T4:0.FOO", SYN },
	{ "T4:0.LEN", SYN }, /* a control word name on a timer */
	{ "R6:0.ACC", SYN },
	{ "C5:0/EN", SYN },  /* EN is not a counter bit */
	{ "T4:0/OV", SYN },
	{ "T4:0.ACC/DN", SYN },
	{ "T4:0.DN/3", SYN },
	{ "T4:0.1A", SYN },
	{ "N7:0/DN", SYN },
	{ "N7:0x", SYN },
	{ "N7:0/3a", SYN },
	{ "$N7:0 ", SYN },
	/* range: well formed, numbers out of range */
	{ "N7:1000", RNG },
	{ "N1000:0", RNG },
	{ "N7:99999999999999999999", RNG },
	{ "N1:0", RNG },     /* files 0-2 are O, I, S */
	{ "N0:0", RNG },
	{ "B2:0", RNG },
	{ "O1:0", RNG },     /* O, I, S are fixed */
	{ "I0:0", RNG },
	{ "S3:0", RNG },
	{ "B3:0/16", RNG },
	{ "B3/16000", RNG },
	{ "N7:0/16", RNG },
	{ "S:1/16", RNG },
	{ "I:0/16", RNG },
	{ "L10:0/32", RNG },
	{ "T4:0.3", RNG },
	{ "C5:0.99", RNG },
	{ "T4:0.ACC/16", RNG },
	{ "I:0.256", RNG },
	{ "T1000:0.ACC", RNG },
	{ "T4:1000/DN", RNG },
	{ "$N7:1000", RNG },
	{ "$N000000000000000000000000000000000000000000000000007:0", RNG }, /* ascii too long */
};

static uint64_t test_seed;

static void assert_fields(const struct df1_addr *a, const struct valid_case *c)
{
	if (a->type != c->type || a->file != c->file || a->element != c->element ||
	    a->sub != c->sub || a->bit != c->bit || strcmp(a->ascii, c->ascii) != 0)
		fail_msg("%s: got type %d file %d element %d sub %d bit %d ascii '%s'; "
		         "want type %d file %d element %d sub %d bit %d ascii '%s'",
		         c->text, a->type, a->file, a->element, a->sub, a->bit, a->ascii,
		         c->type, c->file, c->element, c->sub, c->bit, c->ascii);
}

static void test_addr_parse_valid_table_gives_fields(void **state)
{
	size_t i;

	(void)state;
	assert_true(sizeof valid_cases / sizeof valid_cases[0] >= 60);
	for (i = 0; i < sizeof valid_cases / sizeof valid_cases[0]; i++) {
		struct df1_addr a;
		int rc = df1_addr_parse(valid_cases[i].text, &a);

		if (rc != 0)
			fail_msg("%s: parse returned %d (%s)", valid_cases[i].text, rc, df1_errname(rc));
		assert_fields(&a, &valid_cases[i]);
	}
}

static void test_addr_format_valid_table_gives_canonical(void **state)
{
	size_t i;

	(void)state;
	for (i = 0; i < sizeof valid_cases / sizeof valid_cases[0]; i++) {
		const struct valid_case *c = &valid_cases[i];
		struct df1_addr a, b;
		char buf[64];
		int n;

		assert_int_equal(df1_addr_parse(c->text, &a), 0);
		n = df1_addr_format(&a, buf, sizeof buf);
		if (n < 0 || strcmp(buf, c->canonical) != 0)
			fail_msg("%s: format gave %d '%s', want '%s'", c->text, n, n < 0 ? "" : buf,
			         c->canonical);
		assert_int_equal(n, (int)strlen(c->canonical));
		/* the canonical text parses back to the same address */
		assert_int_equal(df1_addr_parse(buf, &b), 0);
		assert_fields(&b, c);
	}
}

static void test_addr_parse_invalid_table_gives_code(void **state)
{
	size_t i;

	(void)state;
	assert_true(sizeof invalid_cases / sizeof invalid_cases[0] >= 40);
	for (i = 0; i < sizeof invalid_cases / sizeof invalid_cases[0]; i++) {
		struct df1_addr a;
		int rc;

		memset(&a, 0x5A, sizeof a);
		rc = df1_addr_parse(invalid_cases[i].text, &a);
		if (rc >= 0 || df1_error_catalog_id(rc) != invalid_cases[i].id)
			fail_msg("'%s': got %d (%s, catalog ID %d), want catalog ID %d (%s)",
			         invalid_cases[i].text, rc, df1_errname(rc), df1_error_catalog_id(rc),
			         invalid_cases[i].id, df1_catalog_by_id(invalid_cases[i].id)->mnemonic);
		/* the error code is the one of the library that maps to that ID */
		assert_int_equal(rc, invalid_cases[i].id == SYN ? DF1_E_ADDR_SYNTAX : DF1_E_ADDR_RANGE);
		/* *a is untouched on failure */
		assert_int_equal(a.file, 0x5A5A5A5A);
	}
}

static void test_addr_error_codes_map_to_catalog(void **state)
{
	(void)state;
	/* 2503 ERR_ADDRESS_SYNTAX, 2504 ERR_ADDRESS_RANGE (doc/REQUIREMENTS.md 004) */
	assert_int_equal(df1_error_catalog_id(DF1_E_ADDR_SYNTAX), 2503);
	assert_int_equal(df1_error_catalog_id(DF1_E_ADDR_RANGE), 2504);
}

static void test_addr_parse_null_gives_inval(void **state)
{
	struct df1_addr a;

	(void)state;
	assert_int_equal(df1_addr_parse(NULL, &a), DF1_E_INVAL);
	assert_int_equal(df1_addr_parse("N7:0", NULL), DF1_E_INVAL);
}

static void test_addr_format_small_buffer_gives_nospace(void **state)
{
	struct df1_addr a;
	char buf[16];

	(void)state;
	assert_int_equal(df1_addr_parse("T4:10.ACC", &a), 0);
	assert_int_equal(df1_addr_format(&a, buf, 9), DF1_E_NOSPACE); /* needs 10 with NUL */
	assert_int_equal(df1_addr_format(&a, buf, 10), 9);
	assert_string_equal(buf, "T4:10.ACC");
	assert_int_equal(df1_addr_format(&a, NULL, 0), DF1_E_NOSPACE);
	assert_int_equal(df1_addr_parse("$N7:0", &a), 0);
	assert_int_equal(df1_addr_format(&a, buf, 5), DF1_E_NOSPACE);
	assert_int_equal(df1_addr_format(&a, buf, 6), 5);
	assert_string_equal(buf, "$N7:0");
}

static void test_addr_format_invalid_struct_gives_inval(void **state)
{
	struct df1_addr a, ok;
	char buf[64];

	(void)state;
	assert_int_equal(df1_addr_format(NULL, buf, sizeof buf), DF1_E_INVAL);
	assert_int_equal(df1_addr_parse("N7:0", &ok), 0);

	a = ok; a.type = DF1_FT_NONE;
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; a.type = DF1_FT_COUNT_;
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; a.element = 1000;
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; a.element = -2;
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; a.file = 2;
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; a.sub = 1;          /* N has no sub-elements */
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; a.bit = 16;
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; a.type = DF1_FT_T; a.file = 4; a.bit = 13; /* T bit without its word */
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; strcpy(a.ascii, "N7:1");   /* ascii and fields disagree */
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; memset(a.ascii, 'N', sizeof a.ascii); /* not terminated */
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), DF1_E_INVAL);
	a = ok; strcpy(a.ascii, "N7:0");
	assert_int_equal(df1_addr_format(&a, buf, sizeof buf), 5);
	assert_string_equal(buf, "$N7:0");
}

static void test_addr_file_type_tables_match_spec(void **state)
{
	static const struct {
		enum df1_file_type t;
		const char *name;
		int size;
		int slc;
	} want[] = {
		/* element bytes and SLC codes: doc/PROTOCOL.md 4.11 (O 8B, I 8C recommended) */
		{ DF1_FT_O, "O", 2, 0x8B }, { DF1_FT_I, "I", 2, 0x8C }, { DF1_FT_S, "S", 2, 0x84 },
		{ DF1_FT_B, "B", 2, 0x85 }, { DF1_FT_T, "T", 6, 0x86 }, { DF1_FT_C, "C", 6, 0x87 },
		{ DF1_FT_R, "R", 6, 0x88 }, { DF1_FT_N, "N", 2, 0x89 }, { DF1_FT_F, "F", 4, 0x8A },
		{ DF1_FT_ST, "ST", 84, 0x8D }, { DF1_FT_A, "A", 2, 0x8E }, { DF1_FT_L, "L", 4, 0x91 },
	};
	size_t i;

	(void)state;
	assert_int_equal(sizeof want / sizeof want[0], DF1_FT_COUNT_ - 1);
	for (i = 0; i < sizeof want / sizeof want[0]; i++) {
		assert_string_equal(df1_file_type_name(want[i].t), want[i].name);
		assert_int_equal(df1_file_type_element_size(want[i].t), want[i].size);
		assert_int_equal(df1_file_type_slc_code(want[i].t), want[i].slc);
	}
	assert_string_equal(df1_file_type_name(DF1_FT_NONE), "?");
	assert_string_equal(df1_file_type_name(DF1_FT_COUNT_), "?");
	assert_string_equal(df1_file_type_name((enum df1_file_type)-5), "?");
	assert_int_equal(df1_file_type_element_size(DF1_FT_NONE), DF1_E_INVAL);
	assert_int_equal(df1_file_type_slc_code(DF1_FT_COUNT_), DF1_E_INVAL);
}

/* ---- seeded random round trips ------------------------------------------ */

static uint64_t rng_state;

static uint64_t rng_next(void)
{
	/* xorshift64* */
	rng_state ^= rng_state >> 12;
	rng_state ^= rng_state << 25;
	rng_state ^= rng_state >> 27;
	return rng_state * 2685821657736338717ULL;
}

static int rng_below(int n)
{
	return (int)(rng_next() % (uint64_t)n);
}

/* A random valid address, built from the rules (not from the parser). */
static void random_addr(struct df1_addr *a)
{
	static const int tcr_bits[][8] = {
		{ 15, 14, 13, -1 }, { 15, 14, 13, 12, 11, 10, -1 }, { 15, 14, 13, 12, 11, 10, 9, 8 },
	};
	enum df1_file_type t = (enum df1_file_type)(1 + rng_below(DF1_FT_COUNT_ - 1));

	memset(a, 0, sizeof *a);
	a->type = t;
	a->sub = NO;
	a->bit = NO;
	a->element = rng_below(4) == 0 ? 999 : rng_below(1000);
	switch (t) {
	case DF1_FT_O: a->file = 0; break;
	case DF1_FT_I: a->file = 1; break;
	case DF1_FT_S: a->file = 2; break;
	default: a->file = rng_below(4) == 0 ? 999 : 3 + rng_below(997); break;
	}
	switch (t) {
	case DF1_FT_O:
	case DF1_FT_I:
		if (rng_below(2))
			a->sub = rng_below(256);
		if (rng_below(2))
			a->bit = rng_below(16);
		break;
	case DF1_FT_T:
	case DF1_FT_C:
	case DF1_FT_R:
		switch (rng_below(4)) {
		case 0: break;                               /* whole element */
		case 1: a->sub = rng_below(3); break;        /* a word */
		case 2: a->sub = rng_below(3); a->bit = rng_below(16); break;
		default: {                                   /* a named bit */
			const int *bits = tcr_bits[t == DF1_FT_T ? 0 : t == DF1_FT_C ? 1 : 2];
			int n = 0;

			while (n < 8 && bits[n] >= 0)
				n++;
			a->sub = 0;
			a->bit = bits[rng_below(n)];
			break;
		}
		}
		break;
	case DF1_FT_S:
	case DF1_FT_B:
	case DF1_FT_N:
	case DF1_FT_A:
		if (rng_below(2))
			a->bit = rng_below(16);
		break;
	case DF1_FT_L:
		if (rng_below(2))
			a->bit = rng_below(32);
		break;
	default:
		break;
	}
}

static void test_addr_random_round_trip(void **state)
{
	int i;

	(void)state;
	rng_state = test_seed ? test_seed : 1;
	for (i = 0; i < 20000; i++) {
		struct df1_addr a, b;
		char text[64], text2[64];
		int n, rc;

		random_addr(&a);
		n = df1_addr_format(&a, text, sizeof text);
		if (n <= 0)
			fail_msg("seed %llu iteration %d: format of type %d file %d elem %d sub %d bit %d "
			         "gave %d", (unsigned long long)test_seed, i, a.type, a.file, a.element,
			         a.sub, a.bit, n);
		rc = df1_addr_parse(text, &b);
		if (rc != 0 || memcmp(&a, &b, sizeof a) != 0)
			fail_msg("seed %llu iteration %d: '%s' parsed back as rc %d type %d file %d elem %d "
			         "sub %d bit %d", (unsigned long long)test_seed, i, text, rc, b.type, b.file,
			         b.element, b.sub, b.bit);
		/* the "$" form keeps the text and the same fields */
		text2[0] = '$';
		memcpy(text2 + 1, text, (size_t)n + 1);
		rc = df1_addr_parse(text2, &b);
		if (rc != 0 || strcmp(b.ascii, text) != 0 || b.type != a.type || b.file != a.file ||
		    b.element != a.element || b.sub != a.sub || b.bit != a.bit)
			fail_msg("seed %llu iteration %d: '%s' failed", (unsigned long long)test_seed, i,
			         text2);
		n = df1_addr_format(&b, text, sizeof text);
		if (n < 0 || strcmp(text, text2) != 0)
			fail_msg("seed %llu iteration %d: '%s' formatted as '%s'",
			         (unsigned long long)test_seed, i, text2, n < 0 ? "(error)" : text);
	}
}

/* Random strings from the address alphabet: parse never fails oddly, and whatever
 * it accepts formats and parses back to the same fields. */
static void test_addr_random_text_is_accepted_or_rejected_cleanly(void **state)
{
	static const char alphabet[] = "NBFTCRSIOLASTnbt0123456789:./$ACCPREDNENLENPOS-x ";
	int i, accepted = 0;

	(void)state;
	rng_state = (test_seed ? test_seed : 1) ^ 0x9E3779B97F4A7C15ULL;
	for (i = 0; i < 50000; i++) {
		char text[24];
		int len = rng_below((int)sizeof text - 1), j, rc;
		struct df1_addr a, b;
		char out[64];

		if (i % 2 == 0) {
			for (j = 0; j < len; j++)
				text[j] = alphabet[rng_below((int)sizeof alphabet - 1)];
			text[len] = '\0';
		} else {
			/* one edit (replace, insert, delete) of a valid canonical address */
			random_addr(&a);
			len = df1_addr_format(&a, text, sizeof text - 1);
			assert_true(len > 0);
			j = rng_below(len + 1);
			switch (rng_below(3)) {
			case 0:
				if (j < len)
					text[j] = alphabet[rng_below((int)sizeof alphabet - 1)];
				break;
			case 1:
				memmove(text + j + 1, text + j, (size_t)(len - j) + 1);
				text[j] = alphabet[rng_below((int)sizeof alphabet - 1)];
				break;
			default:
				if (j < len)
					memmove(text + j, text + j + 1, (size_t)(len - j));
				break;
			}
		}
		rc = df1_addr_parse(text, &a);
		if (rc != 0 && rc != DF1_E_ADDR_SYNTAX && rc != DF1_E_ADDR_RANGE)
			fail_msg("seed %llu: '%s' gave %d", (unsigned long long)test_seed, text, rc);
		if (rc != 0)
			continue;
		accepted++;
		if (df1_addr_format(&a, out, sizeof out) < 0 || df1_addr_parse(out, &b) != 0 ||
		    memcmp(&a, &b, sizeof a) != 0)
			fail_msg("seed %llu: '%s' accepted but did not round-trip ('%s')",
			         (unsigned long long)test_seed, text, out);
	}
	/* the mutations keep a fair share valid, so the round trip is really exercised */
	assert_true(accepted > 5000);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_addr_parse_valid_table_gives_fields),
		cmocka_unit_test(test_addr_format_valid_table_gives_canonical),
		cmocka_unit_test(test_addr_parse_invalid_table_gives_code),
		cmocka_unit_test(test_addr_error_codes_map_to_catalog),
		cmocka_unit_test(test_addr_parse_null_gives_inval),
		cmocka_unit_test(test_addr_format_small_buffer_gives_nospace),
		cmocka_unit_test(test_addr_format_invalid_struct_gives_inval),
		cmocka_unit_test(test_addr_file_type_tables_match_spec),
		cmocka_unit_test(test_addr_random_round_trip),
		cmocka_unit_test(test_addr_random_text_is_accepted_or_rejected_cleanly),
	};
	const char *env = getenv("DF1_TEST_SEED");

	test_seed = env && *env ? strtoull(env, NULL, 0) : (uint64_t)time(NULL);
	if (test_seed == 0)
		test_seed = 1;
	print_message("test_addr: seed %llu (DF1_TEST_SEED to replay)\n",
	              (unsigned long long)test_seed);
	return cmocka_run_group_tests(tests, NULL, NULL);
}
