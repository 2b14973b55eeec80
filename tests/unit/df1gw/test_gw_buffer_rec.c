/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_buffer_rec.c - station health and write results as store and
 * forward blobs (tools/df1gw/gw_buffer_rec.c): the bytes of a known station
 * and a known result written by hand from the layouts in gw_buffer_rec.h,
 * both back as they were (texts absent stay absent), blobs cut short, too
 * long or of another version refused, a buffer too small refused.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <string.h>

#include "df1gw/gw_buffer_rec.h"

static void test_station_bytes_and_back(void **state)
{
	struct df1_station_health sh = { .station = 7, .tags = 3, .consecutive_failures = 2, .attempts = 0x0102,
	                                 .failures = 5 };
	struct gw_station_out s = { 7, "failing", "E", &sh, 0x1122334455LL };
	static const uint8_t want[] = {
		1,                                                      /* version */
		7, 0, 'f', 'a', 'i', 'l', 'i', 'n', 'g',                /* state */
		1, 0, 'E',                                              /* error */
		0x55, 0x44, 0x33, 0x22, 0x11, 0, 0, 0,                  /* last good */
		3, 0, 0, 0,                                             /* tags */
		2, 0, 0, 0,                                             /* consecutive failures */
		0x02, 0x01, 0, 0, 0, 0, 0, 0,                           /* attempts */
		5, 0, 0, 0, 0, 0, 0, 0,                                 /* failures */
	};
	static struct gw_buffer_station_out o;
	uint8_t b[GW_BUFFER_REC_MAX];
	int n;

	(void)state;
	n = gw_buffer_station_pack(&s, b, sizeof b);
	assert_int_equal(n, (int)sizeof want);
	assert_memory_equal(b, want, sizeof want);
	assert_int_equal(gw_buffer_station_unpack(b, (size_t)n, 7, &o), 0);
	assert_int_equal(o.out.station, 7);
	assert_string_equal(o.out.state, "failing");
	assert_string_equal(o.out.error, "E");
	assert_true(o.out.last_good_wall_ms == 0x1122334455LL);
	assert_ptr_equal(o.out.sh, &o.sh);
	assert_int_equal(o.sh.tags, 3);
	assert_int_equal(o.sh.consecutive_failures, 2);
	assert_true(o.sh.attempts == 0x0102 && o.sh.failures == 5);
	/* no error: none again */
	s.error = NULL;
	n = gw_buffer_station_pack(&s, b, sizeof b);
	assert_int_equal(b[10], 0xFF);
	assert_int_equal(b[11], 0xFF);
	assert_int_equal(gw_buffer_station_unpack(b, (size_t)n, 7, &o), 0);
	assert_null(o.out.error);
	/* cut short, one byte too many, another version, too small a buffer */
	assert_int_equal(gw_buffer_station_unpack(b, (size_t)n - 1, 7, &o), -1);
	assert_int_equal(gw_buffer_station_unpack(b, (size_t)n + 1, 7, &o), -1);
	b[0] = 2;
	assert_int_equal(gw_buffer_station_unpack(b, (size_t)n, 7, &o), -1);
	assert_int_equal(gw_buffer_station_pack(&s, b, 10), -1);
}

static void test_result_bytes_and_back(void **state)
{
	struct gw_result_out r = { "Speed", "a1", false, "bad", true, NULL };
	static const uint8_t want[] = {
		1, 2,                                   /* version; flags: unconfirmed, not ok */
		5, 0, 'S', 'p', 'e', 'e', 'd',
		2, 0, 'a', '1',
		3, 0, 'b', 'a', 'd',
	};
	static struct gw_buffer_result_out o;
	uint8_t b[GW_BUFFER_REC_MAX];
	int n;

	(void)state;
	n = gw_buffer_result_pack(&r, b, sizeof b);
	assert_int_equal(n, (int)sizeof want);
	assert_memory_equal(b, want, sizeof want);
	assert_int_equal(gw_buffer_result_unpack(b, (size_t)n, &o), 0);
	assert_string_equal(o.out.tag, "Speed");
	assert_string_equal(o.out.id, "a1");
	assert_false(o.out.ok);
	assert_true(o.out.unconfirmed);
	assert_string_equal(o.out.error, "bad");
	assert_null(o.out.now);
	/* ok: flags 1, no error (a NULL text) */
	r = (struct gw_result_out){ "Speed", "", true, NULL, false, NULL };
	n = gw_buffer_result_pack(&r, b, sizeof b);
	assert_int_equal(b[1], 1);
	assert_int_equal(gw_buffer_result_unpack(b, (size_t)n, &o), 0);
	assert_true(o.out.ok);
	assert_null(o.out.error);
	assert_string_equal(o.out.id, "");
	assert_int_equal(gw_buffer_result_unpack(b, (size_t)n - 1, &o), -1);
	b[1] = 9;               /* unknown flags */
	assert_int_equal(gw_buffer_result_unpack(b, (size_t)n, &o), -1);
}

static void test_long_text_cut(void **state)
{
	static char big[3000];
	struct gw_result_out r = { "T", "", false, big, false, NULL };
	static struct gw_buffer_result_out o;
	static uint8_t b[GW_BUFFER_REC_MAX];
	int n;

	(void)state;
	memset(big, 'x', sizeof big - 1);
	n = gw_buffer_result_pack(&r, b, sizeof b);
	assert_true(n > 0);
	assert_int_equal(gw_buffer_result_unpack(b, (size_t)n, &o), 0);
	assert_int_equal(strlen(o.out.error), GW_BUFFER_TEXT_MAX);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_station_bytes_and_back),
		cmocka_unit_test(test_result_bytes_and_back),
		cmocka_unit_test(test_long_text_cut),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
