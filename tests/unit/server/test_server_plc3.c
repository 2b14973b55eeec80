/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_server_plc3.c - the responder serving as a PLC-3 (lib/server/server_plc3.c)
 * over a PLC-3 data table (lib/table: a file per section and number), through
 * df1_serve_pccc: commands and replies written out by hand (CMD STS TNS FNC
 * data; doc/PROTOCOL.md 4.2a; tests/data/plc3_vectors.txt without DST SRC), and
 * the refusals: too few levels (EXT STS 02), a level the data table does not
 * have or out of its section's range (03), no such file (06), short bodies (STS 10).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "df1.h"

struct fix {
	df1_t *h;
	struct df1_table *t;
};

static struct fix fx;

static int setup(void **state)
{
	(void)state;
	assert_int_equal(df1_new(&fx.h), 0);
	assert_int_equal(df1_set_plc(fx.h, DF1_PLC_PLC3), 0);
	assert_int_equal(df1_table_new(&fx.t, DF1_PLC_PLC3), 0);
	assert_int_equal(df1_table_add_default_files(fx.t), 0);
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	df1_table_free(fx.t);
	df1_free(fx.h);
	return 0;
}

static size_t hex(const char *s, uint8_t *out, size_t cap)
{
	size_t n = 0;
	unsigned v;
	int k;

	while (sscanf(s, " %2x%n", &v, &k) == 1 && n < cap) {
		out[n++] = (uint8_t)v;
		s += k;
	}
	return n;
}

/* The reply to command `cmd` must be `want` (both hex). */
static void exchange(const char *cmd, const char *want)
{
	uint8_t c[300], w[300], r[300];
	size_t cn = hex(cmd, c, sizeof c), wn = hex(want, w, sizeof w);
	int n = df1_serve_pccc(fx.h, df1_table_server_ops(fx.t), fx.t, 1, c, cn, r, sizeof r);

	if (n != (int)wn || memcmp(r, w, wn) != 0) {
		char got[900] = "";

		for (int i = 0; i < n && i < 290; i++)
			snprintf(got + 3 * i, sizeof got - 3 * (size_t)i, "%02X ", r[i]);
		fail_msg("command %s: reply %s, want %s", cmd, got, want);
	}
}

static int16_t word(const char *addr)
{
	struct df1_value v;

	assert_int_equal(df1_table_read(fx.t, addr, &v, 1), 1);
	return v.v.i16;
}

static void test_server_plc3_vectors(void **state)
{
	struct df1_value v = { .kind = DF1_VAL_INT16, .v.i16 = 42 };

	(void)state;
	assert_int_equal(df1_table_write(fx.t, "N3:173", &v, 1), 1);
	/* tests/data/plc3_vectors.txt, without DST SRC */
	exchange("0F 00 01 03 01 00 00 01 00 2C 05 03 AD 02", "4F 00 01 03 2A 00");
	exchange("0F 00 02 03 00 00 00 01 00 2C 05 03 AD FB FF", "4F 00 02 03");
	assert_int_equal(word("N3:173"), -5);
	exchange("0F 00 03 03 02 2C 08 05 AD 00 20 00 00", "4F 00 03 03");
	assert_int_equal((uint16_t)word("B5:173"), 0x2000);
	exchange("0F 00 07 03 01 00 00 01 00 2C 08 FF 04 01 00 02", "4F F0 07 03 06");
}

static void test_server_plc3_sections(void **state)
{
	struct df1_value v;

	(void)state;
	/* a timer from word 0: CTL PRE ACC (3 words); its ACC alone */
	exchange("0F 00 10 00 01 00 00 03 00 34 03 04 00 06", "4F 00 10 00 00 00 64 00 00 00");
	exchange("0F 00 11 00 00 00 00 01 00 34 03 04 02 07 00", "4F 00 11 00");
	exchange("0F 00 12 00 01 00 00 01 00 34 03 04 02 02", "4F 00 12 00 07 00");
	/* F2:10 is 10.5 (a new table's float n + 0.5): 00 00 28 41, word 0 the low half */
	exchange("0F 00 13 00 01 00 00 02 00 3C 06 02 0A 00 04", "4F 00 13 00 00 00 28 41");
	exchange("0F 00 14 00 01 00 00 01 00 3C 06 02 0A 01 02", "4F 00 14 00 28 41");
	/* H8:99 = 99 * 65536 + 99, low word first */
	exchange("0F 00 15 00 01 00 00 02 00 3C 0A 08 63 00 04", "4F 00 15 00 63 00 63 00");
	/* output words 376-377 (octal): file 0 sent although the default, 377 = 255 takes
	 * the FF escape, and packet offset 1 of a 2-word transaction starts one word on */
	exchange("0F 00 16 00 00 00 00 02 00 2C 01 00 FE 11 00 22 00", "4F 00 16 00");
	exchange("0F 00 17 00 01 00 00 01 00 24 01 FF FF 00 02", "4F 00 17 00 22 00");
	exchange("0F 00 18 00 01 01 00 02 00 24 01 FE 02", "4F 00 18 00 22 00");
	exchange("0F 00 19 00 01 00 00 02 00 24 01 FF FF 00 04", "4F F0 19 00 0A");
	assert_int_equal(df1_table_read(fx.t, "O0:377", &v, 1), 1);
	assert_int_equal(v.v.i16, 0x22);
	/* bit write: RESET wins over SET for a bit in both (set first, then reset) */
	exchange("0F 00 1A 00 02 24 05 03 FF 00 0F 00", "4F F0 1A 00 06");
	exchange("0F 00 1B 00 02 2C 05 03 03 FF 00 0F 00", "4F 00 1B 00");
	assert_int_equal(word("N3:3"), 0xF0);
}

static void test_server_plc3_refusals(void **state)
{
	(void)state;
	/* no word level (mask 0C): 02; area 5 (mask 25): 03; pointers: 03; T file 2: 03 */
	exchange("0F 00 20 00 01 00 00 01 00 0C 05 03 02", "4F F0 20 00 02");
	exchange("0F 00 21 00 01 00 00 01 00 25 05 05 03 02", "4F F0 21 00 03");
	exchange("0F 00 22 00 01 00 00 01 00 34 0C 01 00 02", "4F F0 22 00 03");
	exchange("0F 00 23 00 01 00 00 01 00 3C 03 02 04 00 02", "4F F0 23 00 03");
	/* a word section with a structure: 03; a level below the word: 03 */
	exchange("0F 00 24 00 01 00 00 01 00 3C 05 03 01 00 02", "4F F0 24 00 03");
	exchange("0F 00 25 00 01 00 00 01 00 64 05 03 01 02", "4F F0 25 00 03");
	/* SIZE odd, SIZE past TOTAL_TRANS, no SIZE, an odd write: STS 10 */
	exchange("0F 00 26 00 01 00 00 01 00 2C 05 03 00 03", "4F 10 26 00");
	exchange("0F 00 27 00 01 00 00 01 00 2C 05 03 00 04", "4F 10 27 00");
	exchange("0F 00 28 00 01 00 00 01 00 2C 05 03 00", "4F 10 28 00");
	exchange("0F 00 29 00 00 00 00 01 00 2C 05 03 00 01", "4F 10 29 00");
	/* beyond the file (256 words): 07 */
	exchange("0F 00 2A 00 01 00 00 01 00 2C 05 03 FF 00 01 02", "4F F0 2A 00 07");
	/* a bit write without its masks: STS 10 */
	exchange("0F 00 2B 00 02 2C 05 03 03 FF 00", "4F 10 2B 00");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_server_plc3_vectors, setup, teardown),
		cmocka_unit_test_setup_teardown(test_server_plc3_sections, setup, teardown),
		cmocka_unit_test_setup_teardown(test_server_plc3_refusals, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
