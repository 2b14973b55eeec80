/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_format.c - df1gw's payload format interface (tools/df1gw/gw_format.c)
 * with the JSON format (gw_format_json.c) behind it: every message kind, its
 * topic and retain flag as df1gw(1) TOPICS AND PAYLOADS gives them (the
 * page's examples, byte for byte); the change key made once per change, in
 * the same call as the message, and kept per format; writes: the
 * subscription, which topics are writes, payloads parsed into values.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "df1.h"
#include "df1gw/gw_format.h"

#define PREFIX "df1/df1gw-pi-ttyUSB0"
#define T_2026 1796166900123LL          /* 2026-12-01T23:15:00.123Z */

static struct gw_fmts fmts;

static int setup_json(void **state)
{
	char err[128];

	(void)state;
	memset(&fmts, 0, sizeof fmts);
	assert_int_equal(gw_fmts_enable(&fmts, "json", PREFIX, err, sizeof err), 0);
	return 0;
}

static int teardown_json(void **state)
{
	(void)state;
	gw_fmts_close(&fmts);
	return 0;
}

static const struct gw_fmt *json(void)
{
	return &fmts.v[0];
}

static struct df1_tag_config tag(const char *name, const char *addr, int count)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "%s", name);
	c.access = DF1_ACCESS_READWRITE;
	c.station = 1;
	c.count = count;
	assert_int_equal(df1_addr_parse(addr, &c.addr), 0);
	return c;
}

/* A state of one INT value, read at T_2026. */
static struct df1_tag_state int_state(const struct df1_tag_config *c, struct df1_value *v, int16_t x)
{
	struct df1_tag_state st;

	memset(&st, 0, sizeof st);
	memset(v, 0, sizeof *v);
	v->kind = DF1_VAL_INT16;
	v->v.i16 = x;
	st.config = c;
	st.count = 1;
	st.values = v;
	st.value = *v;
	st.has_value = true;
	st.quality = DF1_QUALITY_GOOD;
	st.reason = DF1_REASON_NONE;
	st.last_good_wall_ms = T_2026;
	return st;
}

static void test_table_and_list(void **state)
{
	struct gw_fmts l;
	char err[128];

	(void)state;
	assert_non_null(gw_format_find("json"));
	assert_ptr_equal(gw_format_at(0), gw_format_find("json"));
	assert_null(gw_format_find("xml"));
	assert_string_equal(json()->ops->name, "json");
	assert_int_equal(json()->slot, 0);
	assert_string_equal(json()->prefix, PREFIX);
	memset(&l, 0, sizeof l);
	assert_int_equal(gw_fmts_enable(&l, "xml", "p", err, sizeof err), -1);
	assert_non_null(strstr(err, "xml"));
	assert_int_equal(gw_fmts_enable(&l, "json", "p", err, sizeof err), 0);
	assert_int_equal(gw_fmts_enable(&l, "json", "p", err, sizeof err), -1);   /* once */
	assert_int_equal(l.n, 1);
	gw_fmts_close(&l);
	assert_int_equal(l.n, 0);
	/* a comma-separated list, as an option would give it */
	assert_int_equal(gw_fmts_enable_list(&l, "json", "p", err, sizeof err), 0);
	assert_int_equal(l.n, 1);
	gw_fmts_close(&l);
	assert_int_equal(gw_fmts_enable_list(&l, "json,json", "p", err, sizeof err), -1);
	gw_fmts_close(&l);
	assert_int_equal(gw_fmts_enable_list(&l, "json,", "p", err, sizeof err), -1);
	gw_fmts_close(&l);
	assert_int_equal(gw_fmts_enable_list(&l, ",json", "p", err, sizeof err), -1);
	assert_int_equal(gw_fmts_enable_list(&l, "", "p", err, sizeof err), -1);
	assert_int_equal(gw_fmts_enable_list(&l, "json,xml", "p", err, sizeof err), -1);
	assert_non_null(strstr(err, "xml"));
	gw_fmts_close(&l);
}

/* The tag message of df1gw(1): the topic, retained, the "ts" out of the key. */
static void test_tag_message(void **state)
{
	struct df1_tag_config c = tag("Speed", "N7:0", 1);
	struct df1_value v;
	struct df1_tag_state st = int_state(&c, &v, 123);
	struct gw_tag_out t = { &st, NULL, -1, NULL, 0 };
	struct gw_msg m;
	struct gw_buf key;

	(void)state;
	gw_msg_init(&m);
	gw_buf_init(&key);
	assert_int_equal(json()->ops->tag(json(), &t, &m, &key), 0);
	assert_string_equal(m.topic, PREFIX "/tag/Speed");
	assert_true(m.retain);
	assert_string_equal(m.body.p, "{\"value\":123,\"quality\":\"GOOD\",\"reason\":\"none\","
	                              "\"ts\":\"2026-12-01T23:15:00.123Z\",\"address\":\"N7:0\",\"station\":1}");
	assert_int_equal(m.body.len, strlen(m.body.p));
	assert_string_equal(key.p, "{\"value\":123,\"quality\":\"GOOD\",\"reason\":\"none\","
	                           "\"address\":\"N7:0\",\"station\":1}");
	/* not GOOD: the error in the catalog's form, after the reason */
	st.quality = DF1_QUALITY_UNCERTAIN;
	st.reason = DF1_REASON_COMM_FAILURE;
	t.error = "[2508] ERR_COMMAND_TIMEOUT: command timed out";
	assert_int_equal(json()->ops->tag(json(), &t, &m, &key), 0);
	assert_string_equal(m.body.p, "{\"value\":123,\"quality\":\"UNCERTAIN\",\"reason\":\"comm_failure\","
	                              "\"error\":\"[2508] ERR_COMMAND_TIMEOUT: command timed out\","
	                              "\"ts\":\"2026-12-01T23:15:00.123Z\",\"address\":\"N7:0\",\"station\":1}");
	assert_string_equal(key.p, "{\"value\":123,\"quality\":\"UNCERTAIN\",\"reason\":\"comm_failure\","
	                           "\"error\":\"[2508] ERR_COMMAND_TIMEOUT: command timed out\","
	                           "\"address\":\"N7:0\",\"station\":1}");
	/* the line lost before any read: BAD line_lost, value and ts null */
	st.has_value = false;
	st.last_good_wall_ms = 0;
	t = (struct gw_tag_out){ &st, "line_lost", DF1_QUALITY_BAD, NULL, 0 };
	assert_int_equal(json()->ops->tag(json(), &t, &m, &key), 0);
	assert_string_equal(m.body.p, "{\"value\":null,\"quality\":\"BAD\",\"reason\":\"line_lost\",\"ts\":null,"
	                              "\"address\":\"N7:0\",\"station\":1}");
	assert_string_equal(key.p, "{\"value\":null,\"quality\":\"BAD\",\"reason\":\"line_lost\","
	                           "\"address\":\"N7:0\",\"station\":1}");
	/* a removed tag: its retained topic cleared by an empty retained message */
	assert_int_equal(json()->ops->tag_gone(json(), "Speed", &m), 0);
	assert_string_equal(m.topic, PREFIX "/tag/Speed");
	assert_int_equal(m.body.len, 0);
	assert_true(m.retain);
	gw_msg_free(&m);
	gw_buf_free(&key);
}

/* A format that counts its tag calls, and makes JSON's messages. */
static int tag_calls;

static int counting_tag(const struct gw_fmt *f, const struct gw_tag_out *t, struct gw_msg *m, struct gw_buf *key)
{
	tag_calls++;
	return gw_format_find("json")->tag(f, t, m, key);
}

/* Published when the value, quality, reason or error changes: not for a new
 * time alone; every time when forced (--refresh, a reconnect). One call of
 * the format per update makes both the message and its key. */
static void test_change_key_once_per_change(void **state)
{
	struct df1_tag_config c = tag("Speed", "N7:0", 1);
	struct df1_value v;
	struct df1_tag_state st = int_state(&c, &v, 123);
	struct gw_tag_out t = { &st, NULL, -1, NULL, 0 };
	struct gw_format counting = *gw_format_find("json");
	struct gw_fmt f = { &counting, PREFIX, 0, NULL, NULL };
	struct gw_pubs pubs;
	struct gw_pub *e;
	struct gw_msg m;
	struct gw_buf key;

	(void)state;
	counting.tag = counting_tag;
	gw_pubs_init(&pubs);
	e = gw_pubs_get(&pubs, "tag/Speed", true);
	gw_msg_init(&m);
	gw_buf_init(&key);
	tag_calls = 0;
	assert_true(gw_fmt_tag_changed(&f, e, &t, &m, &key, 100, false));     /* the first */
	assert_int_equal(tag_calls, 1);
	assert_non_null(strstr(m.body.p, "\"ts\":\"2026-12-01T23:15:00.123Z\""));
	st.last_good_wall_ms = T_2026 + 1000;                                  /* read again, same value */
	assert_false(gw_fmt_tag_changed(&f, e, &t, &m, &key, 200, false));
	assert_int_equal(tag_calls, 2);
	assert_true(gw_fmt_tag_changed(&f, e, &t, &m, &key, 300, true));      /* forced */
	assert_int_equal(tag_calls, 3);
	assert_non_null(strstr(m.body.p, "\"ts\":\"2026-12-01T23:15:01.123Z\""));
	v.v.i16 = 124;                                                         /* the value */
	assert_true(gw_fmt_tag_changed(&f, e, &t, &m, &key, 400, false));
	assert_int_equal(tag_calls, 4);
	assert_string_equal(m.body.p, "{\"value\":124,\"quality\":\"GOOD\",\"reason\":\"none\","
	                              "\"ts\":\"2026-12-01T23:15:01.123Z\",\"address\":\"N7:0\",\"station\":1}");
	st.reason = DF1_REASON_COMM_FAILURE;                                   /* the reason */
	assert_true(gw_fmt_tag_changed(&f, e, &t, &m, &key, 500, false));
	t.error = "[2508] ERR_COMMAND_TIMEOUT: command timed out";             /* the error */
	assert_true(gw_fmt_tag_changed(&f, e, &t, &m, &key, 600, false));
	st.quality = DF1_QUALITY_UNCERTAIN;                                    /* the quality */
	assert_true(gw_fmt_tag_changed(&f, e, &t, &m, &key, 700, false));
	assert_false(gw_fmt_tag_changed(&f, e, &t, &m, &key, 800, false));
	assert_int_equal(tag_calls, 8);
	/* a second format enabled beside it keeps its own key: its first message goes out */
	f.slot = 1;
	assert_true(gw_fmt_tag_changed(&f, e, &t, &m, &key, 900, false));
	assert_false(gw_fmt_tag_changed(&f, e, &t, &m, &key, 1000, false));
	gw_msg_free(&m);
	gw_buf_free(&key);
	gw_pubs_free(&pubs);
}

/* The station message of df1gw(1); published when the state or the error changes. */
static void test_station_message(void **state)
{
	struct df1_station_health sh;
	struct gw_station_out s = { 1, "ok", NULL, &sh, T_2026 };
	struct gw_pubs pubs;
	struct gw_pub *e;
	struct gw_msg m;
	struct gw_buf key;

	(void)state;
	memset(&sh, 0, sizeof sh);
	sh.station = 1;
	sh.state = DF1_STATION_OK;
	sh.tags = 8;
	sh.attempts = 1021;
	sh.failures = 3;
	gw_msg_init(&m);
	gw_buf_init(&key);
	assert_int_equal(json()->ops->station(json(), &s, &m, &key), 0);
	assert_string_equal(m.topic, PREFIX "/station/1");
	assert_true(m.retain);
	assert_string_equal(m.body.p, "{\"station\":1,\"state\":\"ok\",\"error\":null,\"tags\":8,\"attempts\":1021,"
	                              "\"failures\":3,\"consecutive_failures\":0,"
	                              "\"last_good\":\"2026-12-01T23:15:00.123Z\"}");
	gw_pubs_init(&pubs);
	e = gw_pubs_get(&pubs, "station/1", true);
	assert_true(gw_fmt_station_changed(json(), e, &s, &m, &key, 1, false));
	sh.attempts = 1022;                     /* counters move: not a change */
	s.last_good_wall_ms = T_2026 + 500;
	assert_false(gw_fmt_station_changed(json(), e, &s, &m, &key, 2, false));
	s.state = "offline";                    /* the line lost, never answered */
	s.error = "/dev/ttyUSB0: DF1_E_NODEV: no such device";
	s.last_good_wall_ms = 0;
	assert_true(gw_fmt_station_changed(json(), e, &s, &m, &key, 3, false));
	assert_string_equal(m.body.p, "{\"station\":1,\"state\":\"offline\","
	                              "\"error\":\"/dev/ttyUSB0: DF1_E_NODEV: no such device\",\"tags\":8,"
	                              "\"attempts\":1022,\"failures\":3,\"consecutive_failures\":0,\"last_good\":null}");
	gw_pubs_free(&pubs);
	gw_msg_free(&m);
	gw_buf_free(&key);
}

/* Results (not retained), the status (retained), the last will. */
static void test_result_status_will(void **state)
{
	struct gw_result_out ok = { "Speed", "\"w-17\"", true, NULL, false, NULL };
	struct gw_result_out bad = { "Speed", "", false,
	                             "DF1_E_RANGE: value out of range: 70000 does not fit a 16-bit integer", false, NULL };
	struct gw_result_out lost = { "Speed", "\"w-18\"", false, "[2508] ERR_COMMAND_TIMEOUT: command timed out",
	                              true, NULL };
	struct gw_msg m;

	(void)state;
	gw_msg_init(&m);
	assert_int_equal(json()->ops->result(json(), &ok, &m), 0);
	assert_string_equal(m.topic, PREFIX "/tag/Speed/result");
	assert_false(m.retain);
	assert_string_equal(m.body.p, "{\"id\":\"w-17\",\"ok\":true,\"error\":null,\"unconfirmed\":false}");
	assert_int_equal(json()->ops->result(json(), &bad, &m), 0);
	assert_string_equal(m.body.p, "{\"id\":null,\"ok\":false,\"error\":\"DF1_E_RANGE: value out of range: "
	                              "70000 does not fit a 16-bit integer\",\"unconfirmed\":false}");
	assert_int_equal(json()->ops->result(json(), &lost, &m), 0);
	assert_string_equal(m.body.p, "{\"id\":\"w-18\",\"ok\":false,\"error\":\"[2508] ERR_COMMAND_TIMEOUT: "
	                              "command timed out\",\"unconfirmed\":true}");
	assert_int_equal(json()->ops->status(json(), true, &m), 0);
	assert_string_equal(m.topic, PREFIX "/status");
	assert_true(m.retain);
	assert_int_equal(m.body.len, 6);
	assert_memory_equal(m.body.p, "online", 6);
	assert_int_equal(json()->ops->status(json(), false, &m), 0);
	assert_string_equal(m.topic, PREFIX "/status");
	assert_true(m.retain);
	assert_int_equal(m.body.len, 7);
	assert_memory_equal(m.body.p, "offline", 7);
	gw_msg_reset(&m);
	assert_int_equal(json()->ops->will(json(), &m), 0);
	assert_string_equal(m.topic, PREFIX "/status");
	assert_true(m.retain);
	assert_int_equal(m.body.len, 7);
	assert_memory_equal(m.body.p, "offline", 7);
	gw_msg_free(&m);
}

static void test_write_topics(void **state)
{
	char topic[GW_TOPIC_MAX], name[80];

	(void)state;
	json()->ops->set_pattern(json(), topic, sizeof topic);
	assert_string_equal(topic, PREFIX "/tag/+/set");
	assert_true(json()->ops->set_tag(json(), PREFIX "/tag/Speed/set", name, sizeof name));
	assert_string_equal(name, "Speed");
	assert_false(json()->ops->set_tag(json(), PREFIX "/tag/Speed/result", name, sizeof name));
	assert_false(json()->ops->set_tag(json(), PREFIX "/tag/Speed", name, sizeof name));
	assert_false(json()->ops->set_tag(json(), PREFIX "/tag//set", name, sizeof name));
	assert_false(json()->ops->set_tag(json(), PREFIX "/tag/a/b/set", name, sizeof name));
	assert_false(json()->ops->set_tag(json(), "df1/other/tag/Speed/set", name, sizeof name));
	assert_false(json()->ops->set_tag(json(), PREFIX "/station/1/set", name, sizeof name));
}

/* payload for tag c: its parse code, then (when 0) its values' code. */
static int write_in(const char *payload, const struct df1_tag_config *c, const struct df1_tag_state *cur,
                    char *id, struct df1_value *out, size_t *n, char *err, size_t cap)
{
	struct gw_write_in w;
	int r;

	if (json()->ops->write_parse(json(), payload, strlen(payload), &w, err, cap) < 0) {
		assert_string_equal(w.id, "");
		json()->ops->write_free(&w);
		return -100;
	}
	strcpy(id, w.id);
	r = json()->ops->write_values(json(), &w, c, cur, out, (size_t)c->count, n, err, cap);
	json()->ops->write_free(&w);
	return r;
}

static void test_write_payloads(void **state)
{
	struct df1_tag_config n7 = tag("Speed", "N7:0", 1), arr = tag("Level", "N7:10", 3), t4 = tag("Cycle", "T4:0", 1);
	struct df1_value out[3], cur;
	struct df1_tag_state st;
	char id[GW_WRITE_ID_MAX + 1], err[200];
	size_t n;

	(void)state;
	/* the page's example: {"value": 1500, "id": "op-4711"} */
	assert_int_equal(write_in("{\"value\": 1500, \"id\": \"op-4711\"}", &n7, NULL, id, out, &n, err, sizeof err), 0);
	assert_string_equal(id, "\"op-4711\"");
	assert_int_equal(n, 1);
	assert_int_equal(out[0].v.i16, 1500);
	/* a bare value, a number id */
	assert_int_equal(write_in("-7", &n7, NULL, id, out, &n, err, sizeof err), 0);
	assert_string_equal(id, "");
	assert_int_equal(out[0].v.i16, -7);
	assert_int_equal(write_in("{\"value\":1,\"id\":17}", &n7, NULL, id, out, &n, err, sizeof err), 0);
	assert_string_equal(id, "17");
	/* checked against the file type before anything is sent */
	assert_int_equal(write_in("70000", &n7, NULL, id, out, &n, err, sizeof err), DF1_E_RANGE);
	assert_string_equal(err, "70000 does not fit a 16-bit integer");
	assert_int_equal(write_in("\"fast\"", &n7, NULL, id, out, &n, err, sizeof err), DF1_E_TYPE);
	/* not JSON: refused at parsing, no id */
	assert_int_equal(write_in("{\"value\": 1,", &n7, NULL, id, out, &n, err, sizeof err), -100);
	assert_non_null(strstr(err, "not JSON: at byte"));
	/* Count > 1: 1 to Count values from the first element */
	assert_int_equal(write_in("[4,5]", &arr, NULL, id, out, &n, err, sizeof err), 0);
	assert_int_equal(n, 2);
	assert_int_equal(out[1].v.i16, 5);
	assert_int_equal(write_in("[1,2,3,4]", &arr, NULL, id, out, &n, err, sizeof err), DF1_E_RANGE);
	/* a timer object: members not given keep the value last read */
	memset(&cur, 0, sizeof cur);
	cur.kind = DF1_VAL_TCR;
	cur.v.tcr.pre = 500;
	cur.v.tcr.acc = 7;
	memset(&st, 0, sizeof st);
	st.config = &t4;
	st.count = 1;
	st.values = &cur;
	st.has_value = true;
	assert_int_equal(write_in("{\"PRE\": 900}", &t4, &st, id, out, &n, err, sizeof err), 0);
	assert_int_equal(out[0].v.tcr.pre, 900);
	assert_int_equal(out[0].v.tcr.acc, 7);
}

/* Store and forward's replay (df1gw(1), STORE AND FORWARD): the tag's and
 * the station's usual payloads on their topics, not retained, with
 * "historical", the record's "seq" and "read", the read time. */
static void test_historical(void **state)
{
	struct df1_tag_config c = tag("Speed", "N7:0", 1);
	struct df1_value v;
	struct df1_tag_state st = int_state(&c, &v, 123);
	struct gw_tag_out t = { &st, NULL, -1, NULL, T_2026 + 1000 };
	struct df1_station_health sh = { .tags = 2, .attempts = 9 };
	struct gw_station_out s = { 1, "ok", NULL, &sh, T_2026 };
	struct gw_msg m;

	(void)state;
	gw_msg_init(&m);
	assert_non_null(json()->ops->tag_historical);
	assert_int_equal(json()->ops->tag_historical(json(), &t, 42, &m), 0);
	assert_string_equal(m.topic, PREFIX "/tag/Speed");
	assert_false(m.retain);
	assert_string_equal(m.body.p, "{\"value\":123,\"quality\":\"GOOD\",\"reason\":\"none\","
	                              "\"ts\":\"2026-12-01T23:15:00.123Z\",\"address\":\"N7:0\",\"station\":1,"
	                              "\"historical\":true,\"seq\":42,\"read\":\"2026-12-01T23:15:01.123Z\"}");
	assert_int_equal(json()->ops->station_historical(json(), &s, 43, T_2026 + 2000, &m), 0);
	assert_string_equal(m.topic, PREFIX "/station/1");
	assert_false(m.retain);
	assert_string_equal(m.body.p, "{\"station\":1,\"state\":\"ok\",\"error\":null,\"tags\":2,\"attempts\":9,"
	                              "\"failures\":0,\"consecutive_failures\":0,\"last_good\":\"2026-12-01T23:15:00.123Z\","
	                              "\"historical\":true,\"seq\":43,\"read\":\"2026-12-01T23:15:02.123Z\"}");
	assert_null(json()->ops->ready);        /* not a session: always ready */
	gw_msg_free(&m);
}

/* A Receive tag's "from" joins a JSON object as its last member, and
 * nothing else is taken for one. */
static void test_json_add_member(void **state)
{
	struct gw_msg m;

	(void)state;
	gw_msg_init(&m);
	gw_buf_puts(&m.body, "{}");
	assert_int_equal(gw_msg_json_add_int(&m, "from", 3), 0);
	assert_memory_equal(m.body.p, "{\"from\":3}", m.body.len);
	assert_int_equal(m.body.len, strlen("{\"from\":3}"));
	gw_msg_reset(&m);
	gw_buf_puts(&m.body, "{\"value\":[1,2]}");
	assert_int_equal(gw_msg_json_add_int(&m, "from", 254), 0);
	assert_memory_equal(m.body.p, "{\"value\":[1,2],\"from\":254}", m.body.len);
	gw_msg_reset(&m);
	gw_buf_puts(&m.body, "[1]");
	assert_int_equal(gw_msg_json_add_int(&m, "from", 1), -1);
	gw_msg_reset(&m);
	assert_int_equal(gw_msg_json_add_int(&m, "from", 1), -1);
	gw_msg_free(&m);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_table_and_list),
		cmocka_unit_test(test_tag_message),
		cmocka_unit_test(test_change_key_once_per_change),
		cmocka_unit_test(test_station_message),
		cmocka_unit_test(test_result_status_will),
		cmocka_unit_test(test_write_topics),
		cmocka_unit_test(test_write_payloads),
		cmocka_unit_test(test_historical),
		cmocka_unit_test(test_json_add_member),
	};

	return cmocka_run_group_tests(tests, setup_json, teardown_json);
}
