/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_wqueue.c - df1gw's write queue policy (tools/df1gw/gw_wqueue.c)
 * against the rules of df1gw(1), WRITE POLICY: a waiting write replaced by a
 * later one to its tag (latest), bits kept (latest-non-bool), nothing
 * replaced (all); expiry at the deadline; the busy bound; exactly one end for
 * every write that is not handed to the line; the counters; the outbox of
 * results kept while the broker is away. And "timeout_ms" in a /set payload
 * (gw_write.c).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1.h"
#include "df1gw/gw_write.h"
#include "df1gw/gw_wqueue.h"

/* Each write is a number; its ends are recorded in order. */
struct rec {
	int n;
	int who[64];
	enum gw_wend why[64];
	int by[64];
};

static void on_end(void *ctx, struct gw_witem *it, enum gw_wend why, const struct gw_witem *by)
{
	struct rec *r = ctx;
	int *w = it->user;

	assert_true(r->n < 64);
	r->who[r->n] = *w;
	r->why[r->n] = why;
	r->by[r->n] = by ? *(const int *)by->user : -1;
	r->n++;
}

static int ids[64];

static struct gw_witem *item(int who, int tag, bool keep, int64_t deadline, int value)
{
	struct df1_value v = { .kind = DF1_VAL_INT32 };

	v.v.i32 = value;
	ids[who] = who;
	return gw_witem_new(tag, keep, deadline, &v, 1, &ids[who]);
}

/* pop and check: write who, tag, value; freed */
static void pop_is(struct gw_wq *q, int64_t now, int who, int tag, int value)
{
	struct gw_witem *it = gw_wq_pop(q, now);

	assert_non_null(it);
	assert_int_equal(*(int *)it->user, who);
	assert_int_equal(it->tag, tag);
	assert_int_equal(it->v[0].v.i32, value);
	free(it);
}

static void test_latest_replaces(void **state)
{
	struct gw_wq q;
	struct rec r = { 0 };

	(void)state;
	assert_int_equal(gw_wq_init(&q, GW_WOPT_LATEST, 100, on_end, &r), 0);
	assert_int_equal(gw_wq_push(&q, item(1, 7, false, 1000, 10)), 0);
	assert_int_equal(gw_wq_push(&q, item(2, 8, false, 1000, 20)), 0);
	assert_int_equal(gw_wq_push(&q, item(3, 7, false, 1000, 11)), 0);
	assert_int_equal(gw_wq_push(&q, item(4, 7, true, 1000, 1)), 0);   /* latest: bits replaced too */
	/* 1 then 3 replaced at once, each told which write replaced it */
	assert_int_equal(r.n, 2);
	assert_int_equal(r.who[0], 1);
	assert_int_equal(r.why[0], GW_WEND_SUPERSEDED);
	assert_int_equal(r.by[0], 3);
	assert_int_equal(r.who[1], 3);
	assert_int_equal(r.by[1], 4);
	assert_int_equal(q.c.superseded, 2);
	assert_int_equal(q.c.depth, 2);
	/* the later write takes the earlier one's place: tag 7 before tag 8 */
	pop_is(&q, 0, 4, 7, 1);
	pop_is(&q, 0, 2, 8, 20);
	assert_null(gw_wq_pop(&q, 0));
	gw_wq_free(&q);
	assert_int_equal(r.n, 2);
}

static void test_latest_non_bool_keeps_bits(void **state)
{
	struct gw_wq q;
	struct rec r = { 0 };

	(void)state;
	assert_int_equal(gw_wq_init(&q, GW_WOPT_LATEST_NON_BOOL, 100, on_end, &r), 0);
	/* a push button: 1 then 0, both written in order */
	assert_int_equal(gw_wq_push(&q, item(1, 3, true, 1000, 1)), 0);
	assert_int_equal(gw_wq_push(&q, item(2, 3, true, 1000, 0)), 0);
	/* a word: the second replaces the first */
	assert_int_equal(gw_wq_push(&q, item(3, 5, false, 1000, 100)), 0);
	assert_int_equal(gw_wq_push(&q, item(4, 5, false, 1000, 200)), 0);
	assert_int_equal(r.n, 1);
	assert_int_equal(r.who[0], 3);
	assert_int_equal(r.by[0], 4);
	pop_is(&q, 0, 1, 3, 1);
	pop_is(&q, 0, 2, 3, 0);
	pop_is(&q, 0, 4, 5, 200);
	gw_wq_free(&q);
}

static void test_all_keeps_every_write(void **state)
{
	struct gw_wq q;
	struct rec r = { 0 };

	(void)state;
	assert_int_equal(gw_wq_init(&q, GW_WOPT_ALL, 100, on_end, &r), 0);
	for (int i = 1; i <= 5; i++)
		assert_int_equal(gw_wq_push(&q, item(i, 9, false, 1000, i * 10)), 0);
	assert_int_equal(r.n, 0);
	assert_int_equal(q.c.high_water, 5);
	for (int i = 1; i <= 5; i++)
		pop_is(&q, 0, i, 9, i * 10);
	gw_wq_free(&q);
	assert_int_equal(q.c.superseded, 0);
}

static void test_expire(void **state)
{
	struct gw_wq q;
	struct rec r = { 0 };

	(void)state;
	assert_int_equal(gw_wq_init(&q, GW_WOPT_ALL, 100, on_end, &r), 0);
	assert_int_equal(gw_wq_push(&q, item(1, 1, false, 500, 1)), 0);
	assert_int_equal(gw_wq_push(&q, item(2, 2, false, 2000, 2)), 0);
	assert_int_equal(gw_wq_push(&q, item(3, 3, false, 300, 3)), 0);
	assert_int_equal(gw_wq_next_deadline(&q), 300);
	gw_wq_expire(&q, 299);
	assert_int_equal(r.n, 0);
	/* at 500: 1 and 3 are past (a deadline is the last moment it may start) */
	pop_is(&q, 500, 2, 2, 2);
	assert_int_equal(r.n, 2);
	assert_int_equal(r.who[0], 1);
	assert_int_equal(r.why[0], GW_WEND_EXPIRED);
	assert_int_equal(r.who[1], 3);
	assert_int_equal(r.why[1], GW_WEND_EXPIRED);
	assert_int_equal(q.c.expired, 2);
	assert_int_equal(gw_wq_next_deadline(&q), INT64_MAX);
	gw_wq_free(&q);
}

static void test_busy_bound(void **state)
{
	struct gw_wq q;
	struct rec r = { 0 };
	struct gw_witem *it;

	(void)state;
	assert_int_equal(gw_wq_init(&q, GW_WOPT_LATEST_NON_BOOL, 3, on_end, &r), 0);
	for (int i = 1; i <= 3; i++)
		assert_int_equal(gw_wq_push(&q, item(i, i, false, 1000, i)), 0);
	it = item(4, 4, false, 1000, 4);
	assert_int_equal(gw_wq_push(&q, it), -1);    /* busy: the caller answers it */
	free(it);
	assert_int_equal(q.c.refused_busy, 1);
	/* a replacement is not one more waiting: taken while full */
	assert_int_equal(gw_wq_push(&q, item(5, 2, false, 1000, 50)), 0);
	assert_int_equal(r.n, 1);
	assert_int_equal(r.who[0], 2);
	assert_int_equal(q.c.high_water, 3);
	pop_is(&q, 0, 1, 1, 1);
	assert_int_equal(gw_wq_push(&q, item(6, 6, false, 1000, 6)), 0);
	gw_wq_free(&q);
}

/* Every write ends once: written (popped), or one callback. */
static void test_one_end_each(void **state)
{
	struct gw_wq q;
	struct rec r = { 0 };
	int popped = 0, busy = 0;

	(void)state;
	assert_int_equal(gw_wq_init(&q, GW_WOPT_LATEST_NON_BOOL, 4, on_end, &r), 0);
	for (int i = 0; i < 40; i++) {
		struct gw_witem *it = item(i, i % 6, i % 6 == 0, 100 + i * 10, i);

		if (gw_wq_push(&q, it) < 0) {
			free(it);
			busy++;
		}
		if (i % 5 == 4) {
			struct gw_witem *p = gw_wq_pop(&q, 150 + i * 8);

			if (p) {
				popped++;
				free(p);
			}
		}
	}
	gw_wq_drop_all(&q);
	assert_int_equal(q.c.depth, 0);
	assert_int_equal(popped + busy + r.n, 40);
	assert_int_equal(q.c.superseded + q.c.expired + q.c.dropped, (uint64_t)r.n);
	assert_int_equal(q.c.refused_busy, (uint64_t)busy);
	for (int i = 0; i < r.n; i++)
		for (int j = i + 1; j < r.n; j++)
			assert_int_not_equal(r.who[i], r.who[j]);
	gw_wq_free(&q);
}

static void test_options(void **state)
{
	enum gw_wopt o;

	(void)state;
	assert_int_equal(gw_wopt_parse("all", &o), 0);
	assert_int_equal(o, GW_WOPT_ALL);
	assert_int_equal(gw_wopt_parse("latest", &o), 0);
	assert_int_equal(o, GW_WOPT_LATEST);
	assert_int_equal(gw_wopt_parse("latest-non-bool", &o), 0);
	assert_int_equal(o, GW_WOPT_LATEST_NON_BOOL);
	assert_int_equal(gw_wopt_parse("newest", &o), -1);
	assert_string_equal(gw_wopt_name(GW_WOPT_LATEST_NON_BOOL), "latest-non-bool");
}

static void test_set_timeout_ms(void **state)
{
	struct gw_set s;
	char err[200];
	const char *ok = "{\"value\": 5, \"id\": \"a\", \"timeout_ms\": 1500}";
	const char *bad[] = {
		"{\"value\": 5, \"timeout_ms\": 0}",
		"{\"value\": 5, \"timeout_ms\": -3}",
		"{\"value\": 5, \"timeout_ms\": 1.5}",
		"{\"value\": 5, \"timeout_ms\": \"100\"}",
		"{\"value\": 5, \"timeout_ms\": 86400001}",
	};

	(void)state;
	assert_int_equal(gw_set_parse(ok, strlen(ok), &s, err, sizeof err), 0);
	assert_int_equal(s.timeout_ms, 1500);
	assert_string_equal(s.id, "\"a\"");
	gw_set_free(&s);
	assert_int_equal(gw_set_parse("7", 1, &s, err, sizeof err), 0);
	assert_int_equal(s.timeout_ms, -1);
	gw_set_free(&s);
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		assert_int_equal(gw_set_parse(bad[i], strlen(bad[i]), &s, err, sizeof err), -1);
		assert_non_null(strstr(err, "timeout_ms"));
	}
}

/* The outbox keeps copies, at most cap, and counts the rest as lost. */
static void test_outbox(void **state)
{
	struct gw_outbox o;
	struct gw_msg m;

	(void)state;
	gw_msg_init(&m);
	assert_int_equal(gw_outbox_init(&o, 2), 0);
	snprintf(m.topic, sizeof m.topic, "p/tag/A/result");
	gw_buf_puts(&m.body, "{\"id\":1}");
	assert_true(gw_outbox_add(&o, &m));
	gw_buf_reset(&m.body);
	gw_buf_puts(&m.body, "{\"id\":2}");
	assert_true(gw_outbox_add(&o, &m));
	assert_false(gw_outbox_add(&o, &m));
	assert_int_equal(o.n, 2);
	assert_int_equal(o.lost, 1);
	assert_string_equal(o.v[0].topic, "p/tag/A/result");
	assert_int_equal(o.v[0].body.len, 8);
	assert_memory_equal(o.v[0].body.p, "{\"id\":1}", 8);
	assert_memory_equal(o.v[1].body.p, "{\"id\":2}", 8);
	gw_outbox_free(&o);
	gw_msg_free(&m);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_latest_replaces),
		cmocka_unit_test(test_latest_non_bool_keeps_bits),
		cmocka_unit_test(test_all_keeps_every_write),
		cmocka_unit_test(test_expire),
		cmocka_unit_test(test_busy_bound),
		cmocka_unit_test(test_one_end_each),
		cmocka_unit_test(test_options),
		cmocka_unit_test(test_set_timeout_ms),
		cmocka_unit_test(test_outbox),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
