/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_json.c - df1gw's JSON (tools/df1gw/gw_json.c) against RFC 8259: what a
 * strict parser must take and refuse, string escapes and UTF-8, the writers'
 * escaping; RFC 3339 times against known instants; the broker URL
 * (tools/df1gw/gw_url.c).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "df1gw/gw_json.h"
#include "df1gw/gw_url.h"

static struct gw_jv *parse(const char *s, char *err, size_t cap)
{
	return gw_json_parse(s, strlen(s), err, cap);
}

static void test_json_accepts_rfc8259(void **state)
{
	static const char *const ok[] = {
		"0", "-0", "12", "-3.25", "1e5", "1E+5", "2.5e-3", "true", "false", "null", "\"\"",
		"\"a\\\"b\\\\c\\/d\\b\\f\\n\\r\\t\"", "\"\\u00e9\\uD83D\\uDE00\"", "[]", "{}", " [1, 2 ,3] ",
		"{\"a\":{\"b\":[true,null]}}", "\"caf\xc3\xa9\"", "\t\r\n7\n",
	};
	char err[160];

	(void)state;
	for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
		struct gw_jv *v = parse(ok[i], err, sizeof err);
		if (!v)
			fail_msg("refused %s: %s", ok[i], err);
		gw_jv_free(v);
	}
}

static void test_json_refuses_what_rfc8259_does_not_allow(void **state)
{
	static const char *const bad[] = {
		"", " ", "01", "+1", ".5", "1.", "1e", "-", "0x10", "NaN", "Infinity", "tru", "nul",
		"'a'", "\"a", "\"\\x41\"", "\"\\u12\"", "\"\\uD800\"", "\"\\uDC00x\"", "\"a\x01\"",
		"\"\xff\"", "\"\xc0\xaf\"", "\"\xed\xa0\x80\"", "[1,]", "[,1]", "{\"a\":1,}", "{a:1}",
		"{\"a\" 1}", "{\"a\":1,\"a\":2}", "[1 2]", "1 2", "[", "{", "]", "\"a\"x", "[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]",
	};
	char err[160];

	(void)state;
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		struct gw_jv *v = parse(bad[i], err, sizeof err);
		if (v)
			fail_msg("took %s", bad[i]);
		assert_true(strncmp(err, "at byte", 7) == 0 || strstr(err, "bytes"));
	}
}

static void test_json_tree_and_spans(void **state)
{
	const char *s = "{\"value\": [1, -2.5e3], \"id\" : \"x\\u0041\"}";
	char err[160];
	struct gw_jv *v = parse(s, err, sizeof err);
	const struct gw_jv *val, *id;

	(void)state;
	assert_non_null(v);
	assert_int_equal(v->type, GW_JOBJECT);
	assert_int_equal(v->n, 2);
	val = gw_jv_get(v, "value");
	assert_non_null(val);
	assert_int_equal(val->type, GW_JARRAY);
	assert_int_equal(val->n, 2);
	assert_string_equal(val->items[1]->text, "-2.5e3");
	id = gw_jv_get(v, "id");
	assert_non_null(id);
	assert_string_equal(id->text, "xA");
	/* the id as it was written, for echoing it back */
	assert_int_equal(id->end - id->start, strlen("\"x\\u0041\""));
	assert_memory_equal(s + id->start, "\"x\\u0041\"", id->end - id->start);
	assert_null(gw_jv_get(v, "nope"));
	gw_jv_free(v);
}

static void test_json_error_says_where(void **state)
{
	char err[160];

	(void)state;
	assert_null(parse("[1,,2]", err, sizeof err));
	assert_string_equal(err, "at byte 3: expected a value");
	assert_null(parse("{\"a\":1 \"b\":2}", err, sizeof err));
	assert_string_equal(err, "at byte 7: expected ',' or '}'");
}

static void test_json_latin1(void **state)
{
	char err[160];
	uint8_t out[8];
	size_t n;
	struct gw_jv *v = parse("\"A\\u00ff\\u0000\xc3\xa9\"", err, sizeof err);

	(void)state;
	assert_non_null(v);
	assert_true(gw_jv_latin1(v, out, sizeof out, &n));
	assert_int_equal(n, 4);
	assert_memory_equal(out, "A\xff\0\xe9", 4);
	assert_false(gw_jv_latin1(v, out, 3, &n));        /* does not fit */
	gw_jv_free(v);
	v = parse("\"\\u20ac\"", err, sizeof err);
	assert_non_null(v);
	assert_false(gw_jv_latin1(v, out, sizeof out, &n)); /* above U+00FF */
	gw_jv_free(v);
}

static void test_json_writers_escape(void **state)
{
	struct gw_buf b;
	const uint8_t bytes[] = { 'a', '"', '\\', '\n', 0x01, 0x7f, 0xe9, 0xff };

	(void)state;
	gw_buf_init(&b);
	gw_json_text(&b, "x\"\\\t\x02 caf\xc3\xa9 \xff", strlen("x\"\\\t\x02 caf\xc3\xa9 \xff"));
	assert_string_equal(b.p, "\"x\\\"\\\\\\t\\u0002 caf\xc3\xa9 \\u00ff\"");
	gw_buf_reset(&b);
	gw_json_bytes(&b, bytes, sizeof bytes);
	assert_string_equal(b.p, "\"a\\\"\\\\\\n\\u0001\\u007f\\u00e9\\u00ff\"");
	/* what gw_json_bytes writes parses back to the same bytes */
	{
		char err[160];
		uint8_t out[16];
		size_t n;
		struct gw_jv *v = gw_json_parse(b.p, b.len, err, sizeof err);

		assert_non_null(v);
		assert_true(gw_jv_latin1(v, out, sizeof out, &n));
		assert_int_equal(n, sizeof bytes);
		assert_memory_equal(out, bytes, n);
		gw_jv_free(v);
	}
	gw_buf_reset(&b);
	gw_buf_printf(&b, "%d-%s", 42, "x");
	assert_string_equal(b.p, "42-x");
	gw_buf_free(&b);
}

static void test_utf8_valid(void **state)
{
	(void)state;
	assert_true(gw_utf8_valid("Pump 1 caf\xc3\xa9", 13));
	assert_false(gw_utf8_valid("caf\xe9", 4));         /* ISO 8859-1, no UTF-8 */
	assert_false(gw_utf8_valid("\xc3", 1));             /* cut short */
}

static void test_rfc3339(void **state)
{
	char ts[40];

	(void)state;
	gw_rfc3339(0, ts, sizeof ts);
	assert_string_equal(ts, "1970-01-01T00:00:00.000Z");
	gw_rfc3339(1700000000123LL, ts, sizeof ts);    /* date -u -d @1700000000 */
	assert_string_equal(ts, "2023-11-14T22:13:20.123Z");
	gw_rfc3339(951782400999LL, ts, sizeof ts);     /* 2000-02-29, a leap day */
	assert_string_equal(ts, "2000-02-29T00:00:00.999Z");
}

static void test_url(void **state)
{
	struct gw_url u;
	char err[200];

	(void)state;
	assert_int_equal(gw_url_parse("mqtt://broker", &u, err, sizeof err), 0);
	assert_string_equal(u.host, "broker");
	assert_int_equal(u.port, 1883);
	assert_false(u.tls);
	assert_int_equal(gw_url_parse("MQTTS://10.0.0.5:8884/", &u, err, sizeof err), 0);
	assert_string_equal(u.host, "10.0.0.5");
	assert_int_equal(u.port, 8884);
	assert_true(u.tls);
	assert_int_equal(gw_url_parse("mqtts://h.example", &u, err, sizeof err), 0);
	assert_int_equal(u.port, 8883);
	assert_int_equal(gw_url_parse("mqtt://[::1]:1884", &u, err, sizeof err), 0);
	assert_string_equal(u.host, "::1");
	assert_int_equal(u.port, 1884);
	static const char *const bad[] = {
		"broker", "tcp://broker", "mqtt://", "mqtt://:1883", "mqtt://h:0", "mqtt://h:65536",
		"mqtt://h:x", "mqtt://h:1883x", "mqtt://h/path", "mqtt://[::1", "mqtt://u@h", "mqtt://h h",
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		if (gw_url_parse(bad[i], &u, err, sizeof err) != -1 || !err[0])
			fail_msg("took %s", bad[i]);
	assert_int_equal(gw_url_parse("mqtt://user:pw@h", &u, err, sizeof err), -1);
	assert_non_null(strstr(err, "--password-file"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_json_accepts_rfc8259),
		cmocka_unit_test(test_json_refuses_what_rfc8259_does_not_allow),
		cmocka_unit_test(test_json_tree_and_spans),
		cmocka_unit_test(test_json_error_says_where),
		cmocka_unit_test(test_json_latin1),
		cmocka_unit_test(test_json_writers_escape),
		cmocka_unit_test(test_utf8_valid),
		cmocka_unit_test(test_rfc3339),
		cmocka_unit_test(test_url),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
