/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_buffer_tag.c - a tag's state as a store and forward blob
 * (tools/df1gw/gw_buffer_tag.c): the bytes of a known state written by hand
 * from the layout in gw_buffer_tag.h; every value kind back as it was, so
 * that the tag's JSON (gw_value.c) made from the blob is the JSON made from
 * the state, read time included; blobs cut short, too long, of an unknown
 * kind or version refused; a buffer too small refused.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "df1gw/gw_buffer_tag.h"
#include "df1gw/gw_value.h"

static struct df1_tag_config tag(const char *addr, int count)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "t");
	c.access = DF1_ACCESS_READWRITE;
	c.station = 3;
	c.count = count;
	assert_int_equal(df1_addr_parse(addr, &c.addr), 0);
	return c;
}

static void test_bytes_of_a_known_state(void **state)
{
	struct df1_tag_config c = tag("N7:0", 1);
	struct df1_value v = { .kind = DF1_VAL_INT16, .v.i16 = 42 };
	struct df1_tag_state st = { .config = &c, .count = 1, .values = &v, .has_value = true,
	                            .quality = DF1_QUALITY_GOOD, .reason = DF1_REASON_NONE,
	                            .last_good_wall_ms = 1700000000000LL };
	struct gw_tag_out t = { .st = &st, .quality = -1, .wall_ms = 1700000000123LL };
	/* version 1, GOOD 2, reason 0, has_value 1, view quality -1, last_error 0,
	 * sts 0, ext_sts 0, 1700000000000 = 0x18BCFE56800, 1700000000123 =
	 * 0x18BCFE5687B, 1 value: INT16 (0) 42, no reason text, no error */
	static const uint8_t want[] = {
		0x01, 0x02, 0x00, 0x01, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
		0x00, 0x68, 0xe5, 0xcf, 0x8b, 0x01, 0x00, 0x00,
		0x7b, 0x68, 0xe5, 0xcf, 0x8b, 0x01, 0x00, 0x00,
		0x01, 0x00, 0x00, 0x2a, 0x00, 0xff, 0xff,
	};
	uint8_t buf[64];

	(void)state;
	int n = gw_buffer_tag_pack(&t, buf, sizeof buf);
	assert_int_equal(n, sizeof want);
	assert_memory_equal(buf, want, sizeof want);
	/* exactly as long as needed fits; one byte less does not */
	assert_int_equal(gw_buffer_tag_pack(&t, buf, sizeof want), sizeof want);
	assert_int_equal(gw_buffer_tag_pack(&t, buf, sizeof want - 1), -1);
}

/* The JSON of a tag, with its time. */
static void json(char *out, size_t cap, const struct gw_tag_out *t)
{
	struct gw_tag_view view = { t->reason, t->quality, t->error, true };
	struct gw_buf b;

	gw_buf_init(&b);
	gw_tag_json(&b, t->st, &view);
	assert_false(b.oom);
	snprintf(out, cap, "%s", b.p);
	gw_buf_free(&b);
}

/* st packed, unpacked, given its config again: the same JSON as st's. */
static void round_trip(const struct gw_tag_out *t, const char *want)
{
	static uint8_t blob[GW_BUFFER_TAG_MAX];
	struct df1_value vals[8];
	struct gw_buffer_tag_out o = { .values = vals, .cap = 8 };
	char a[1024], b[1024];

	int n = gw_buffer_tag_pack(t, blob, sizeof blob);
	assert_true(n > 0);
	assert_int_equal(gw_buffer_tag_unpack(blob, (size_t)n, &o), 0);
	o.st.config = t->st->config;
	assert_int_equal(o.out.wall_ms, t->wall_ms);
	json(a, sizeof a, t);
	json(b, sizeof b, &o.out);
	assert_string_equal(b, a);
	if (want)
		assert_string_equal(b, want);
	/* every blob cut short, and one with a byte more, refused */
	for (int k = 0; k < n; k++)
		assert_int_equal(gw_buffer_tag_unpack(blob, (size_t)k, &o), -1);
	blob[n] = 0;
	assert_int_equal(gw_buffer_tag_unpack(blob, (size_t)n + 1, &o), -1);
	/* no room for the values */
	o.cap = t->st->count - 1;
	if (t->st->count)
		assert_int_equal(gw_buffer_tag_unpack(blob, (size_t)n, &o), -1);
}

static void test_every_kind_back_as_it_was(void **state)
{
	struct df1_tag_config cn = tag("N7:0", 2), cl = tag("L10:0", 1), cf = tag("F8:1", 1), cb = tag("B3:0/4", 1),
	                      cs = tag("ST9:0", 1), ct = tag("T4:0", 1);
	struct df1_value n[2] = { { .kind = DF1_VAL_INT16, .v.i16 = -32768 }, { .kind = DF1_VAL_INT16, .v.i16 = 7 } };
	struct df1_value l = { .kind = DF1_VAL_INT32, .v.i32 = -70000 };
	struct df1_value f = { .kind = DF1_VAL_FLOAT, .v.f = -0.1f };
	struct df1_value bit = { .kind = DF1_VAL_BIT, .v.bit = true };
	struct df1_value s = { .kind = DF1_VAL_STRING };
	struct df1_value tm = { .kind = DF1_VAL_TCR, .v.tcr = { .ctl = 0xa000, .pre = 100, .acc = 42 } };
	struct df1_tag_state st = { .has_value = true, .quality = DF1_QUALITY_GOOD,
	                            .last_good_wall_ms = 1700000000123LL };
	struct gw_tag_out t = { .st = &st, .quality = -1, .wall_ms = 1700000000200LL };

	(void)state;
	s.v.str.len = 12;
	memcpy(s.v.str.text, "say \"hi\"\\\x01z", 12);
	st.config = &cn; st.count = 2; st.values = n; st.value = n[0];
	round_trip(&t, "{\"value\":[-32768,7],\"quality\":\"GOOD\",\"reason\":\"none\","
	               "\"ts\":\"2023-11-14T22:13:20.123Z\",\"address\":\"N7:0\",\"station\":3}");
	st.config = &cl; st.count = 1; st.values = &l;
	round_trip(&t, NULL);
	st.config = &cf; st.values = &f;
	round_trip(&t, "{\"value\":-0.1,\"quality\":\"GOOD\",\"reason\":\"none\","
	               "\"ts\":\"2023-11-14T22:13:20.123Z\",\"address\":\"F8:1\",\"station\":3}");
	st.config = &cb; st.values = &bit;
	round_trip(&t, NULL);
	st.config = &cs; st.values = &s;
	round_trip(&t, NULL);
	st.config = &ct; st.values = &tm;
	round_trip(&t, "{\"value\":{\"EN\":true,\"TT\":false,\"DN\":true,\"PRE\":100,\"ACC\":42},"
	               "\"quality\":\"GOOD\",\"reason\":\"none\",\"ts\":\"2023-11-14T22:13:20.123Z\","
	               "\"address\":\"T4:0\",\"station\":3}");
	/* a bad tag: the view's quality, reason and error, the PLC's STS */
	st.config = &cn; st.count = 2; st.values = n;
	st.quality = DF1_QUALITY_UNCERTAIN;
	st.reason = DF1_REASON_COMM_FAILURE;
	st.last_error = DF1_E_TIMEOUT;
	st.sts = 0x10;
	st.ext_sts = 0x07;
	t.quality = DF1_QUALITY_BAD;
	t.reason = "stale";
	t.error = "[2508] ERR_COMMAND_TIMEOUT: no reply";
	round_trip(&t, NULL);
	/* before the first read: no values */
	st.has_value = false;
	st.count = 0;
	st.values = NULL;
	t.reason = NULL;
	t.error = NULL;
	t.quality = -1;
	round_trip(&t, NULL);
}

static void test_unknown_kind_and_version_refused(void **state)
{
	struct df1_tag_config c = tag("N7:0", 1);
	struct df1_value v = { .kind = DF1_VAL_INT16, .v.i16 = 1 };
	struct df1_tag_state st = { .config = &c, .count = 1, .values = &v, .has_value = true };
	struct gw_tag_out t = { .st = &st, .quality = -1 };
	struct df1_value vals[1];
	struct gw_buffer_tag_out o = { .values = vals, .cap = 1 };
	uint8_t blob[64];

	(void)state;
	int n = gw_buffer_tag_pack(&t, blob, sizeof blob);
	assert_int_equal(gw_buffer_tag_unpack(blob, (size_t)n, &o), 0);
	blob[30] = 9;           /* the value's kind */
	assert_int_equal(gw_buffer_tag_unpack(blob, (size_t)n, &o), -1);
	blob[30] = 0;
	blob[0] = 2;            /* a later version */
	assert_int_equal(gw_buffer_tag_unpack(blob, (size_t)n, &o), -1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_bytes_of_a_known_state),
		cmocka_unit_test(test_every_kind_back_as_it_was),
		cmocka_unit_test(test_unknown_kind_and_version_refused),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
