/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_live.c - store and forward's guard of live publications
 * (tools/df1gw/gw_live.c): a record stays until the PUBACK of each of its
 * messages (in any order), a record without a QoS 1 message is forgotten at
 * once, a drop hands over what is not acknowledged oldest first with its
 * key, blob and read time as given, a full ring lets the oldest go
 * (counted), a PUBACK of another message is not taken.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <string.h>

#include "df1gw/gw_live.h"

struct got {
	int n;
	int64_t ms[16];
	char key[16][80];
	uint8_t first[16];
};

static void collect(void *u, struct gw_buffer_rec *r)
{
	struct got *g = u;

	g->ms[g->n] = r->ms;
	strcpy(g->key[g->n], r->key);
	g->first[g->n] = r->len ? ((const uint8_t *)r->data)[0] : 0;
	g->n++;
}

static void pub(struct gw_live *l, int64_t ms, const char *key, uint8_t b, int m1, int m2)
{
	uint8_t data[3] = { b, 2, 3 };
	struct gw_buffer_rec r = { 0, GW_BUFFER_TAG, 1, 192, ms, key, data, sizeof data };

	assert_int_equal(gw_live_open(l, &r), 0);
	data[0] = 99;                   /* copied: the caller's room is its own again */
	if (m1)
		gw_live_mid(l, m1);
	if (m2)
		gw_live_mid(l, m2);
	gw_live_close(l);
}

static void test_acked_and_drained(void **state)
{
	struct gw_live l;
	struct got g = { 0 };

	(void)state;
	assert_int_equal(gw_live_init(&l, 8), 0);
	pub(&l, 100, "A", 1, 11, 12);   /* two formats */
	pub(&l, 200, "B", 2, 13, 0);
	pub(&l, 300, "C", 3, 0, 0);     /* QoS 0 only: nothing to guard */
	pub(&l, 400, "D", 4, 14, 0);
	assert_true(gw_live_acked(&l, 12));
	assert_true(gw_live_acked(&l, 13));
	assert_false(gw_live_acked(&l, 13));    /* twice: no more */
	assert_false(gw_live_acked(&l, 77));    /* not a guarded message */
	gw_live_drain(&l, collect, &g);
	assert_int_equal(g.n, 2);       /* A (11 still out) and D */
	assert_string_equal(g.key[0], "A");
	assert_true(g.ms[0] == 100 && g.first[0] == 1);
	assert_string_equal(g.key[1], "D");
	assert_true(g.ms[1] == 400 && g.first[1] == 4);
	g.n = 0;
	gw_live_drain(&l, collect, &g);
	assert_int_equal(g.n, 0);
	gw_live_free(&l);
}

static void test_full_ring_lets_the_oldest_go(void **state)
{
	struct gw_live l;
	struct got g = { 0 };

	(void)state;
	assert_int_equal(gw_live_init(&l, 4), 0);
	for (int i = 0; i < 6; i++)
		pub(&l, i, "T", (uint8_t)i, 100 + i, 0);
	assert_true(l.let_go == 2);
	assert_false(gw_live_acked(&l, 100));   /* let go */
	assert_true(gw_live_acked(&l, 103));
	gw_live_drain(&l, collect, &g);
	assert_int_equal(g.n, 3);
	assert_true(g.ms[0] == 2 && g.ms[1] == 4 && g.ms[2] == 5);
	gw_live_free(&l);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_acked_and_drained),
		cmocka_unit_test(test_full_ring_lets_the_oldest_go),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
