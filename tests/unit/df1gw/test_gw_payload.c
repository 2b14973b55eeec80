/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_payload.c - df1gw's payloads (tools/df1gw/gw_value.c, gw_write.c,
 * gw_state.c): tag JSON by file type as the issue gives it; .../set values
 * checked against the file type's range before anything is sent; the
 * {"value","id"} wrapper; the ring of ids (at most once, bounded); results;
 * which failures leave a write unconfirmed; the change key of a topic.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "df1.h"
#include "df1gw/gw_state.h"
#include "df1gw/gw_value.h"
#include "df1gw/gw_write.h"

static struct df1_tag_config tag(const char *addr, int count)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "t");
	c.access = DF1_ACCESS_READWRITE;
	c.station = 1;
	c.count = count;
	assert_int_equal(df1_addr_parse(addr, &c.addr), 0);
	return c;
}

/* JSON of one value of kind k at address addr, written from text as df1write takes it. */
static void value_is(const char *addr, const char *text, const char *want)
{
	struct df1_tag_config c = tag(addr, 1);
	struct df1_value v;
	struct gw_buf b;

	assert_int_equal(df1_value_parse(&c.addr, text, &v), 0);
	gw_buf_init(&b);
	gw_value_json(&b, &v, c.addr.sub != DF1_ADDR_NONE ? DF1_FT_N : c.addr.type);
	assert_string_equal(b.p, want);
	gw_buf_free(&b);
}

static void test_values_by_file_type(void **state)
{
	(void)state;
	value_is("N7:0", "-32768", "-32768");
	value_is("N7:0", "0xFFFF", "-1");             /* N is signed */
	value_is("L10:0", "-2147483648", "-2147483648");
	value_is("F8:0", "0.1", "0.1");               /* shortest round-trip */
	value_is("F8:0", "3.4028235e38", "3.4028235e+38");
	value_is("F8:0", "inf", "null");              /* JSON has no inf */
	value_is("B3:0/5", "1", "true");
	value_is("T4:0/DN", "0", "false");
	value_is("T4:0.ACC", "42", "42");
	value_is("ST9:0", "say \"hi\"", "\"say \\\"hi\\\"\"");
	value_is("T4:0", "EN=1 TT=0 DN=1 PRE=100 ACC=42",
	         "{\"EN\":true,\"TT\":false,\"DN\":true,\"PRE\":100,\"ACC\":42}");
	value_is("C5:0", "CU=1 OV=1 PRE=10 ACC=-3",
	         "{\"CU\":true,\"CD\":false,\"DN\":false,\"OV\":true,\"UN\":false,\"UA\":false,\"PRE\":10,\"ACC\":-3}");
	value_is("R6:0", "EN=1 FD=1 LEN=8 POS=2",
	         "{\"EN\":true,\"EU\":false,\"DN\":false,\"EM\":false,\"ER\":false,\"UL\":false,\"IN\":false,"
	         "\"FD\":true,\"LEN\":8,\"POS\":2}");
}

static void test_tag_json(void **state)
{
	struct df1_tag_config c = tag("F8:3", 2);
	struct df1_value vals[2];
	struct df1_tag_state st;
	struct gw_tag_view view = { NULL, -1, NULL, true };
	struct gw_buf b;

	(void)state;
	memset(&st, 0, sizeof st);
	memset(vals, 0, sizeof vals);
	vals[0].kind = vals[1].kind = DF1_VAL_FLOAT;
	vals[0].v.f = 1.5f;
	vals[1].v.f = -2.0f;
	st.config = &c;
	st.count = 2;
	st.values = vals;
	st.has_value = true;
	st.quality = DF1_QUALITY_GOOD;
	st.reason = DF1_REASON_NONE;
	st.last_good_wall_ms = 1700000000123LL;
	gw_buf_init(&b);
	gw_tag_json(&b, &st, &view);
	assert_string_equal(b.p, "{\"value\":[1.5,-2],\"quality\":\"GOOD\",\"reason\":\"none\","
	                         "\"ts\":\"2023-11-14T22:13:20.123Z\",\"address\":\"F8:3\",\"station\":1}");
	/* the change key: no time */
	gw_buf_reset(&b);
	view.with_ts = false;
	st.quality = DF1_QUALITY_UNCERTAIN;
	st.reason = DF1_REASON_COMM_FAILURE;
	view.error = "[2508] ERR_COMMAND_TIMEOUT: command timed out";
	gw_tag_json(&b, &st, &view);
	assert_string_equal(b.p, "{\"value\":[1.5,-2],\"quality\":\"UNCERTAIN\",\"reason\":\"comm_failure\","
	                         "\"error\":\"[2508] ERR_COMMAND_TIMEOUT: command timed out\","
	                         "\"address\":\"F8:3\",\"station\":1}");
	/* never read: null, and no time */
	gw_buf_reset(&b);
	st.has_value = false;
	st.last_good_wall_ms = 0;
	view = (struct gw_tag_view){ "line_lost", DF1_QUALITY_BAD, NULL, true };
	gw_tag_json(&b, &st, &view);
	assert_string_equal(b.p, "{\"value\":null,\"quality\":\"BAD\",\"reason\":\"line_lost\",\"ts\":null,"
	                         "\"address\":\"F8:3\",\"station\":1}");
	gw_buf_free(&b);
}

/* Convert payload for a tag at addr (count n); returns the code, values in out. */
static int set_values(const char *addr, int count, const char *payload, struct df1_value *out, size_t *n,
                      char *err, size_t cap)
{
	struct df1_tag_config c = tag(addr, count);
	struct gw_set s;
	int r;

	if (gw_set_parse(payload, strlen(payload), &s, err, cap) < 0)
		return -100;
	r = gw_value_from_json(s.value, &c, NULL, out, 16, n, err, cap);
	gw_set_free(&s);
	return r;
}

static void test_set_values_checked_against_the_file_type(void **state)
{
	struct df1_value v[16];
	size_t n;
	char err[200];

	(void)state;
	assert_int_equal(set_values("N7:0", 1, "32767", v, &n, err, sizeof err), 0);
	assert_int_equal(n, 1);
	assert_int_equal(v[0].v.i16, 32767);
	assert_int_equal(set_values("N7:0", 1, "-32768", v, &n, err, sizeof err), 0);
	assert_int_equal(set_values("N7:0", 1, "70000", v, &n, err, sizeof err), DF1_E_RANGE);
	assert_string_equal(err, "70000 does not fit a 16-bit integer");
	assert_int_equal(set_values("N7:0", 1, "1.5", v, &n, err, sizeof err), DF1_E_TYPE);
	assert_int_equal(set_values("N7:0", 1, "\"7\"", v, &n, err, sizeof err), DF1_E_TYPE);
	assert_string_equal(err, "expected a number, got a string");
	assert_int_equal(set_values("N7:0", 1, "true", v, &n, err, sizeof err), DF1_E_TYPE);
	assert_int_equal(set_values("N7:0", 1, "null", v, &n, err, sizeof err), DF1_E_TYPE);
	assert_int_equal(set_values("L10:0", 1, "2147483647", v, &n, err, sizeof err), 0);
	assert_int_equal(v[0].v.i32, 2147483647);
	assert_int_equal(set_values("L10:0", 1, "2147483648", v, &n, err, sizeof err), DF1_E_RANGE);
	assert_int_equal(set_values("F8:0", 1, "-2.5e3", v, &n, err, sizeof err), 0);
	assert_true(v[0].v.f == -2500.0f);
	assert_int_equal(set_values("F8:0", 1, "1e39", v, &n, err, sizeof err), DF1_E_RANGE);
	assert_int_equal(set_values("B3:0/5", 1, "true", v, &n, err, sizeof err), 0);
	assert_true(v[0].v.bit);
	assert_int_equal(set_values("B3:0/5", 1, "0", v, &n, err, sizeof err), 0);
	assert_false(v[0].v.bit);
	assert_int_equal(set_values("B3:0/5", 1, "2", v, &n, err, sizeof err), DF1_E_RANGE);
	assert_int_equal(set_values("ST9:0", 1, "\"caf\\u00e9\"", v, &n, err, sizeof err), 0);
	assert_int_equal(v[0].v.str.len, 4);
	assert_memory_equal(v[0].v.str.text, "caf\xe9", 4);
	assert_int_equal(set_values("ST9:0", 1,
	                            "\"0123456789012345678901234567890123456789012345678901234567890123456789012345678901\"",
	                            v, &n, err, sizeof err), 0);    /* 82 characters */
	assert_int_equal(set_values("ST9:0", 1,
	                            "\"01234567890123456789012345678901234567890123456789012345678901234567890123456789012\"",
	                            v, &n, err, sizeof err), DF1_E_RANGE);
	assert_int_equal(set_values("ST9:0", 1, "12", v, &n, err, sizeof err), DF1_E_TYPE);
}

static void test_set_arrays_and_elements(void **state)
{
	struct df1_value v[16];
	size_t n;
	char err[200];

	(void)state;
	assert_int_equal(set_values("N7:0", 4, "[1,2,3]", v, &n, err, sizeof err), 0);
	assert_int_equal(n, 3);
	assert_int_equal(v[2].v.i16, 3);
	assert_int_equal(set_values("N7:0", 4, "9", v, &n, err, sizeof err), 0);   /* element 0 */
	assert_int_equal(n, 1);
	assert_int_equal(set_values("N7:0", 2, "[1,2,3]", v, &n, err, sizeof err), DF1_E_RANGE);
	assert_int_equal(set_values("N7:0", 2, "[]", v, &n, err, sizeof err), DF1_E_RANGE);
	assert_int_equal(set_values("N7:0", 2, "[1,\"x\"]", v, &n, err, sizeof err), DF1_E_TYPE);
	assert_string_equal(err, "value 2: expected a number, got a string");
	assert_int_equal(set_values("N7:0", 1, "[1]", v, &n, err, sizeof err), DF1_E_TYPE);
	assert_int_equal(set_values("T4:0", 1, "{\"PRE\":500,\"EN\":true,\"dn\":1}", v, &n, err, sizeof err), 0);
	assert_int_equal(v[0].v.tcr.pre, 500);
	assert_int_equal(v[0].v.tcr.ctl, (1u << df1_tcr_bit(DF1_FT_T, "EN")) | (1u << df1_tcr_bit(DF1_FT_T, "DN")));
	assert_int_equal(set_values("T4:0", 1, "{\"LEN\":5}", v, &n, err, sizeof err), DF1_E_TYPE);
	assert_string_equal(err, "LEN: no such member of a T element");
	assert_int_equal(set_values("R6:0", 1, "{\"LEN\":5,\"POS\":40000}", v, &n, err, sizeof err), DF1_E_RANGE);
	assert_int_equal(set_values("T4:0", 1, "{\"EN\":2}", v, &n, err, sizeof err), DF1_E_TYPE);
}

static void test_set_tcr_members_not_given_are_kept(void **state)
{
	struct df1_tag_config c = tag("C5:1", 1);
	struct df1_value cur, out[1];
	struct df1_tag_state st;
	char err[200];
	size_t n;
	struct gw_jv *v = gw_json_parse("{\"ACC\":3}", 9, err, sizeof err);

	(void)state;
	memset(&cur, 0, sizeof cur);
	cur.kind = DF1_VAL_TCR;
	cur.v.tcr.ctl = 0x8000;
	cur.v.tcr.pre = 10;
	cur.v.tcr.acc = 9;
	memset(&st, 0, sizeof st);
	st.config = &c;
	st.count = 1;
	st.values = &cur;
	st.has_value = true;
	assert_int_equal(gw_value_from_json(v, &c, &st, out, 1, &n, err, sizeof err), 0);
	assert_int_equal(out[0].v.tcr.ctl, 0x8000);
	assert_int_equal(out[0].v.tcr.pre, 10);
	assert_int_equal(out[0].v.tcr.acc, 3);
	gw_jv_free(v);
}

static void test_set_wrapper_and_ids(void **state)
{
	struct gw_set s;
	char err[200];

	(void)state;
	assert_int_equal(gw_set_parse("{\"value\": 5, \"id\": \"abc\"}", 25, &s, err, sizeof err), 0);
	assert_string_equal(s.id, "\"abc\"");
	assert_string_equal(s.value->text, "5");
	gw_set_free(&s);
	assert_int_equal(gw_set_parse("{\"id\":17,\"value\":[1]}", 21, &s, err, sizeof err), 0);
	assert_string_equal(s.id, "17");
	assert_int_equal(s.value->type, GW_JARRAY);
	gw_set_free(&s);
	/* a T/C/R object is the value itself: it has no "value" member */
	assert_int_equal(gw_set_parse("{\"PRE\":1}", 9, &s, err, sizeof err), 0);
	assert_string_equal(s.id, "");
	assert_ptr_equal(s.value, s.root);
	gw_set_free(&s);
	assert_int_equal(gw_set_parse("{\"value\":1,\"idx\":2}", 19, &s, err, sizeof err), -1);
	assert_non_null(strstr(err, "idx"));
	assert_int_equal(gw_set_parse("{\"value\":1,\"id\":[1]}", 20, &s, err, sizeof err), -1);
	assert_int_equal(gw_set_parse("{\"value\":1,\"id\":null}", 21, &s, err, sizeof err), -1);
	assert_int_equal(gw_set_parse("5 6", 3, &s, err, sizeof err), -1);
	assert_non_null(strstr(err, "not JSON"));
}

static void test_ids_ring(void **state)
{
	struct gw_ids ids;
	char id[16];

	(void)state;
	assert_int_equal(gw_ids_init(&ids, 4), 0);
	assert_false(gw_ids_seen(&ids, "\"a\""));
	for (int i = 0; i < 4; i++) {
		snprintf(id, sizeof id, "%d", i);
		assert_int_equal(gw_ids_add(&ids, id), 0);
	}
	assert_true(gw_ids_seen(&ids, "0"));
	assert_true(gw_ids_seen(&ids, "3"));
	assert_int_equal(gw_ids_add(&ids, "4"), 0);    /* the oldest goes */
	assert_false(gw_ids_seen(&ids, "0"));
	assert_true(gw_ids_seen(&ids, "1"));
	assert_true(gw_ids_seen(&ids, "4"));
	assert_false(gw_ids_seen(&ids, "\"4\""));      /* the string "4" is another id */
	gw_ids_free(&ids);
}

static void test_results(void **state)
{
	struct gw_buf b;

	(void)state;
	gw_buf_init(&b);
	gw_result_json(&b, "\"w1\"", true, NULL, false);
	assert_string_equal(b.p, "{\"id\":\"w1\",\"ok\":true,\"error\":null,\"unconfirmed\":false}");
	gw_buf_reset(&b);
	gw_result_json(&b, "", false, "[2508] ERR_COMMAND_TIMEOUT: command timed out", true);
	assert_string_equal(b.p, "{\"id\":null,\"ok\":false,\"error\":\"[2508] ERR_COMMAND_TIMEOUT: command timed "
	                         "out\",\"unconfirmed\":true}");
	gw_buf_free(&b);
	/* the PLC may have executed it: no answer came */
	assert_true(gw_write_unconfirmed(DF1_E_TIMEOUT));
	assert_true(gw_write_unconfirmed(DF1_E_ENQ_LIMIT));
	assert_true(gw_write_unconfirmed(DF1_E_CLOSED));
	/* it did not: refused, NAKed, or never sent */
	assert_false(gw_write_unconfirmed(DF1_E_REMOTE));
	/* half duplex: the tries may have had no ACK at all, one of them taken */
	assert_true(gw_write_unconfirmed(DF1_E_NAK_LIMIT));
	assert_false(gw_write_unconfirmed(DF1_E_NOT_OPEN));
	assert_false(gw_write_unconfirmed(DF1_E_TYPE));
	assert_false(gw_write_unconfirmed(DF1_E_INACTIVE));
}

static void test_change_key(void **state)
{
	struct gw_pubs p;
	struct gw_pub *e;

	(void)state;
	gw_pubs_init(&p);
	e = gw_pubs_get(&p, "tag/a", true);
	assert_non_null(e);
	assert_true(gw_pub_update(e, 0, "{1}", 10, false));     /* first: published */
	assert_false(gw_pub_update(e, 0, "{1}", 20, false));    /* same: not again */
	assert_int_equal(e->last_ms, 10);
	assert_true(gw_pub_update(e, 0, "{1}", 30, true));      /* forced (reconnect, --refresh) */
	assert_true(gw_pub_update(e, 0, "{2}", 40, false));     /* changed */
	/* each payload format has its own key: another slot has published nothing */
	assert_true(gw_pub_update(e, 1, "{2}", 50, false));
	assert_false(gw_pub_update(e, 1, "{2}", 60, false));
	assert_false(gw_pub_update(e, 0, "{2}", 70, false));
	/* a tag whose row changed at a reload: every format publishes it again */
	gw_pub_forget(e);
	assert_null(e->key[0]);
	assert_true(gw_pub_update(e, 0, "{2}", 80, false));
	assert_true(gw_pub_update(e, 1, "{2}", 90, false));
	assert_ptr_equal(gw_pubs_get(&p, "tag/a", false), e);
	assert_null(gw_pubs_get(&p, "tag/b", false));
	gw_pubs_get(&p, "tag/b", true);
	gw_pubs_remove(&p, gw_pubs_get(&p, "tag/a", false));
	assert_null(gw_pubs_get(&p, "tag/a", false));
	assert_non_null(gw_pubs_get(&p, "tag/b", false));
	gw_pubs_free(&p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_values_by_file_type),
		cmocka_unit_test(test_tag_json),
		cmocka_unit_test(test_set_values_checked_against_the_file_type),
		cmocka_unit_test(test_set_arrays_and_elements),
		cmocka_unit_test(test_set_tcr_members_not_given_are_kept),
		cmocka_unit_test(test_set_wrapper_and_ids),
		cmocka_unit_test(test_ids_ring),
		cmocka_unit_test(test_results),
		cmocka_unit_test(test_change_key),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
