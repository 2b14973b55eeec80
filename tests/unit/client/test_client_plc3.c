/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_client_plc3.c - the client's PLC-3 commands (lib/client/plc3.c, the bit
 * write of elements.c) byte for byte: df1_read / df1_write on a PLC-3 handle
 * against df1sim --plc plc3 (tests/support/simproc), every frame sent and
 * received captured by the trace callback and compared with the hand-written
 * frames of tests/data/plc3_vectors.txt (doc/PROTOCOL.md 4.2a). The replies are
 * df1sim's, so its PLC-3 responder is held to the same bytes.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1_int.h"
#include "support/simproc.h"

#define CAP 8192

struct cap {
	uint8_t b[2][CAP];      /* by enum df1_dir */
	size_t n[2];
};

static void on_trace(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us)
{
	struct cap *c = user;

	(void)t_us;
	if (c->n[dir] + n <= CAP) {
		memcpy(c->b[dir] + c->n[dir], bytes, n);
		c->n[dir] += n;
	}
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

static bool contains(const uint8_t *hay, size_t hn, const uint8_t *needle, size_t nn)
{
	for (size_t i = 0; nn && i + nn <= hn; i++)
		if (memcmp(hay + i, needle, nn) == 0)
			return true;
	return false;
}

static void test_client_plc3_frames_match_the_vectors(void **state)
{
	static const char *const args[] = { "--plc", "plc3", "--check", "bcc", NULL };
	struct simproc sp;
	struct cap *c = calloc(1, sizeof *c);
	df1_t *h = NULL;
	char line[512];
	int16_t v16;
	float f;
	FILE *fp;
	int rows = 0;

	(void)state;
	assert_non_null(c);
	if (simproc_start(&sp, false, "N3:173=42\nT4=PRE=500 ACC=7 EN=1\nF2:10=1.5\n", true, args) != 0)
		fail_msg("df1sim did not start");
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_check(h, DF1_CHECK_BCC), 0);
	assert_int_equal(df1_set_plc(h, DF1_PLC_PLC3), 0);
	df1_set_trace(h, on_trace, c);
	if (df1_open(h, sp.target) < 0)
		fail_msg("df1_open: %s", df1_last_error(h)->message);
	h->next_tns = 0x0301;   /* the vectors' first TNS */

	assert_int_equal(df1_read_int16(h, 1, "N3:173", &v16, 1), 1);                 /* 0301 */
	assert_int_equal(v16, 42);
	v16 = -5;
	assert_int_equal(df1_write_int16(h, 1, "N3:173", &v16, 1), 1);                /* 0302 */
	assert_int_equal(df1_write_bit(h, 1, "B5:173/15", true), 0);                  /* 0303 */
	assert_int_equal(df1_read_int16(h, 1, "T4.ACC", &v16, 1), 1);                 /* 0304 */
	assert_int_equal(v16, 7);
	assert_int_equal(df1_read_float(h, 1, "F2:10", &f, 1), 1);                    /* 0305 */
	assert_true(f == 1.5f);
	assert_int_equal(df1_write_bit(h, 1, "T4/EN", false), 0);                     /* 0306 */
	assert_int_equal(df1_read_int16(h, 1, "B260:0", &v16, 1), DF1_E_REMOTE);      /* 0307 */
	assert_int_equal(df1_last_error(h)->ext_sts, 0x06);
	df1_close(h);

	fp = fopen("tests/data/plc3_vectors.txt", "r");
	assert_non_null(fp);
	while (fgets(line, sizeof line, fp)) {
		char *f1, *f2, *f3;
		uint8_t want[300];
		size_t n;
		bool reply;

		if (line[0] == '#' || !(f1 = strstr(line, " | ")) || !(f2 = strstr(f1 + 3, " | ")) ||
		    !(f3 = strstr(f2 + 3, " | ")))
			continue;
		if (strncmp(f1 + 3, "bcc", 3) != 0)
			continue;
		*f3 = '\0';
		n = hex(f2 + 3, want, sizeof want);
		reply = want[4] & 0x40;        /* CMD: 4F replies, from df1sim */
		if (!contains(c->b[reply ? DF1_DIR_RX : DF1_DIR_TX], c->n[reply ? DF1_DIR_RX : DF1_DIR_TX],
		              want, n)) {
			*f1 = '\0';
			fail_msg("%s: not on the line", line);
		}
		rows++;
	}
	fclose(fp);
	assert_int_equal(rows, 14);
	df1_free(h);
	simproc_stop(&sp, false);
	free(c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_client_plc3_frames_match_the_vectors),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
