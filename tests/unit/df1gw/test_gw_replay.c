/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_replay.c - the pace of store and forward's replay
 * (tools/df1gw/gw_replay.c): the token bucket gives rate records a second
 * (a twentieth of a second's worth at once, at least one), the window of
 * unacknowledged publications bounds it whatever the rate, a record with a
 * message per format is acknowledged with its last PUBACK only, a PUBACK not
 * of the replay is ignored, a lost connection empties the window; the
 * --replay-rate text.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "df1gw/gw_replay.h"

static void test_rate(void **state)
{
	struct gw_replay r;
	size_t total = 0;

	(void)state;
	gw_replay_init(&r, 100);                /* 100/s: a burst of 5 */
	assert_int_equal(gw_replay_budget(&r, 1000, 1), 5);
	gw_replay_spent(&r, 5);
	assert_int_equal(gw_replay_budget(&r, 1000, 1), 0);
	assert_int_equal(gw_replay_wait_ms(&r, 1000), 11);  /* 10 ms a record, rounded up */
	assert_int_equal(gw_replay_budget(&r, 1010, 1), 1);
	/* over a second, acknowledged at once: about 100, never more than 100 + the burst */
	gw_replay_init(&r, 100);
	for (int64_t t = 2000; t <= 3000; t += 7) {
		size_t k = gw_replay_budget(&r, t, 1);

		gw_replay_spent(&r, k);
		total += k;
	}
	assert_true(total >= 95 && total <= 105);
	/* a slow rate still sends one */
	gw_replay_init(&r, 1);
	assert_int_equal(gw_replay_budget(&r, 5, 1), 1);
	gw_replay_init(&r, 0);
	assert_int_equal(r.rate, GW_REPLAY_RATE_DEFAULT);
}

static void test_window(void **state)
{
	struct gw_replay r;
	uint64_t seq;

	(void)state;
	gw_replay_init(&r, GW_REPLAY_RATE_MAX);
	for (int i = 0; i < (int)GW_REPLAY_WINDOW; i++)
		assert_int_equal(gw_replay_sent(&r, 100 + i, (uint64_t)i + 1), 0);
	assert_int_equal(gw_replay_sent(&r, 999, 999), -1);
	assert_int_equal(gw_replay_budget(&r, 10000, 1), 0);      /* full: however fast */
	assert_true(gw_replay_acked(&r, 100, &seq));
	assert_true(seq == 1);
	assert_int_equal(gw_replay_budget(&r, 10000, 1), 1);
	assert_int_equal(gw_replay_budget(&r, 10000, 2), 0);      /* two formats: two messages a record */
	assert_false(gw_replay_acked(&r, 5, &seq));               /* a live publication's PUBACK */
	gw_replay_reset(&r);
	assert_int_equal(r.n, 0);
	assert_false(gw_replay_acked(&r, 101, &seq));
	assert_true(r.replayed == 1);
}

static void test_two_formats(void **state)
{
	struct gw_replay r;
	uint64_t seq = 0;

	(void)state;
	gw_replay_init(&r, 10);
	gw_replay_sent(&r, 1, 42);              /* JSON */
	gw_replay_sent(&r, 2, 42);              /* Sparkplug */
	gw_replay_sent(&r, 3, 43);
	assert_false(gw_replay_acked(&r, 2, &seq));     /* the other still in flight */
	assert_true(gw_replay_acked(&r, 3, &seq));
	assert_true(seq == 43);
	assert_true(gw_replay_acked(&r, 1, &seq));
	assert_true(seq == 42);
	assert_true(r.replayed == 2);
}

static void test_parse_rate(void **state)
{
	unsigned v = 0;

	(void)state;
	assert_int_equal(gw_replay_parse_rate("500", &v), 0);
	assert_int_equal(v, 500);
	assert_int_equal(gw_replay_parse_rate("20/s", &v), 0);
	assert_int_equal(v, 20);
	assert_int_equal(gw_replay_parse_rate("0", &v), -1);
	assert_int_equal(gw_replay_parse_rate("100001", &v), -1);
	assert_int_equal(gw_replay_parse_rate("5/m", &v), -1);
	assert_int_equal(gw_replay_parse_rate("-5", &v), -1);
	assert_int_equal(gw_replay_parse_rate("", &v), -1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_rate),
		cmocka_unit_test(test_window),
		cmocka_unit_test(test_two_formats),
		cmocka_unit_test(test_parse_rate),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
