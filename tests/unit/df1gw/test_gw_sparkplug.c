/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_sparkplug.c - df1gw's Sparkplug B codec (tools/df1gw/gw_spb_codec.c)
 * and tag metrics (gw_spb_metrics.c, gw_spb_cmd.c): payloads compared byte
 * for byte with vectors written by hand from the protobuf wire format
 * (varint keys field << 3 | wire type; 0 varint, 2 length-delimited, 5 32-bit)
 * and the Sparkplug 3.0 Payload message's field numbers (Payload: timestamp 1,
 * metrics 2, seq 3; Metric: name 1, alias 2, timestamp 3, datatype 4,
 * properties 9, int_value 10, long_value 11, float_value 12, double_value 13,
 * boolean_value 14, string_value 15, bytes_value 16; PropertySet: keys 1,
 * values 2; PropertyValue: type 1, int_value 3, string_value 8); a decode
 * round trip of every datatype; the array layouts the specification gives
 * (numbers little-endian, a Boolean array's 4-byte count then bits from each
 * byte's high bit, strings NUL-terminated); commands back into values.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1.h"
#include "df1gw/gw_spb_codec.h"
#include "df1gw/gw_spb_metrics.h"

static void bytes_equal(const struct gw_buf *b, const uint8_t *want, size_t n)
{
	assert_int_equal(b->len, n);
	assert_memory_equal(b->p, want, n);
}

/* {timestamp 1, metrics [{name "A", datatype Int16, int_value 5}]}, seq 0 appended */
static void test_int16_vector(void **state)
{
	static const uint8_t want[] = { 0x08, 0x01, 0x12, 0x07, 0x0a, 0x01, 'A', 0x20, 0x02, 0x50, 0x05, 0x18, 0x00 };
	struct gw_spb_metric m;
	struct gw_buf b;

	(void)state;
	gw_buf_init(&b);
	gw_spb_metric_init(&m);
	m.name = "A";
	m.datatype = GW_SPB_INT16;
	m.kind = GW_SPB_V_INT;
	m.v.i = 5;
	assert_int_equal(gw_spb_encode(&b, 1, &m, 1), 0);
	gw_spb_append_seq(&b, 0);
	bytes_equal(&b, want, sizeof want);
	gw_buf_free(&b);
}

/* a Float 1.5 (fixed32 0x3FC00000, little-endian) with alias 300 and no
 * name, metric timestamp 2; no payload timestamp; seq 300 (varint AC 02) */
static void test_float_alias_vector(void **state)
{
	static const uint8_t want[] = { 0x12, 0x0c, 0x10, 0xac, 0x02, 0x18, 0x02, 0x20, 0x09, 0x65, 0x00, 0x00, 0xc0,
	                                0x3f, 0x18, 0xac, 0x02 };
	struct gw_spb_metric m;
	struct gw_buf b;

	(void)state;
	gw_buf_init(&b);
	gw_spb_metric_init(&m);
	m.has_alias = true;
	m.alias = 300;
	m.timestamp = 2;
	m.datatype = GW_SPB_FLOAT;
	m.kind = GW_SPB_V_FLOAT;
	m.v.f = 1.5f;
	assert_int_equal(gw_spb_encode(&b, 0, &m, 1), 0);
	gw_spb_append_seq(&b, 300);
	bytes_equal(&b, want, sizeof want);
	gw_buf_free(&b);
}

/* a Boolean false that is not good: properties {Quality: Int32 Bad, Reason: String "x"};
 * Bad is Ignition 8's 0x80000200, an Int32 carried in the uint32 int_value:
 * the varint 80 84 80 80 08 */
static void test_quality_vector(void **state)
{
	static const uint8_t want[] = {
		0x12, 0x2b,                                     /* metrics, 43 bytes */
		0x0a, 0x01, 'B', 0x20, 0x0b,                    /* name "B", datatype 11 */
		0x4a, 0x22,                                     /* properties, 34 bytes */
		0x0a, 0x07, 'Q', 'u', 'a', 'l', 'i', 't', 'y',
		0x0a, 0x06, 'R', 'e', 'a', 's', 'o', 'n',
		0x12, 0x08, 0x08, 0x03,                         /* {type Int32, */
		0x18, 0x80, 0x84, 0x80, 0x80, 0x08,             /*  int_value 0x80000200} */
		0x12, 0x05, 0x08, 0x0c, 0x42, 0x01, 'x',        /* {type String, string_value "x"} */
		0x70, 0x00,                                     /* boolean_value false */
	};
	struct gw_spb_metric m;
	struct gw_buf b;

	(void)state;
	gw_buf_init(&b);
	gw_spb_metric_init(&m);
	m.name = "B";
	m.datatype = GW_SPB_BOOLEAN;
	m.kind = GW_SPB_V_BOOL;
	m.has_quality = true;
	m.quality = GW_SPB_Q_BAD;
	m.reason = "x";
	assert_int_equal(gw_spb_encode(&b, 0, &m, 1), 0);
	bytes_equal(&b, want, sizeof want);
	gw_buf_free(&b);
}

/* NDEATH as the specification shows it: one metric bdSeq, Int64, long_value */
static void test_ndeath_vector(void **state)
{
	static const uint8_t want[] = { 0x12, 0x0b, 0x0a, 0x05, 'b', 'd', 'S', 'e', 'q', 0x20, 0x04, 0x58, 0x07 };
	struct gw_spb_metric m;
	struct gw_buf b;

	(void)state;
	gw_buf_init(&b);
	gw_spb_metric_init(&m);
	m.name = "bdSeq";
	m.datatype = GW_SPB_INT64;
	m.kind = GW_SPB_V_LONG;
	m.v.l = 7;
	assert_int_equal(gw_spb_encode(&b, 0, &m, 1), 0);
	bytes_equal(&b, want, sizeof want);
	gw_buf_free(&b);
}

/* Every datatype encoded and decoded again: the same metric back. */
static void test_round_trip(void **state)
{
	static const uint8_t raw[] = { 1, 2, 3, 0, 255 };
	struct gw_spb_metric in[16], out;
	struct gw_spb_in d;
	struct gw_buf b;
	size_t n = 0;

	(void)state;
	for (uint32_t t = GW_SPB_INT8; t <= GW_SPB_UINT32; t++) {
		gw_spb_metric_init(&in[n]);
		in[n].datatype = t;
		in[n].kind = GW_SPB_V_INT;
		in[n].v.i = t == GW_SPB_INT16 ? 0xFFFFu : 0x7Fu + t;
		n++;
	}
	gw_spb_metric_init(&in[n]);
	in[n].datatype = GW_SPB_INT64;
	in[n].kind = GW_SPB_V_LONG;
	in[n++].v.l = (uint64_t)-2;
	gw_spb_metric_init(&in[n]);
	in[n].datatype = GW_SPB_UINT64;
	in[n].kind = GW_SPB_V_LONG;
	in[n++].v.l = UINT64_MAX;
	gw_spb_metric_init(&in[n]);
	in[n].datatype = GW_SPB_FLOAT;
	in[n].kind = GW_SPB_V_FLOAT;
	in[n++].v.f = -3.25f;
	gw_spb_metric_init(&in[n]);
	in[n].datatype = GW_SPB_DOUBLE;
	in[n].kind = GW_SPB_V_DOUBLE;
	in[n++].v.d = 1e300;
	gw_spb_metric_init(&in[n]);
	in[n].datatype = GW_SPB_BOOLEAN;
	in[n].kind = GW_SPB_V_BOOL;
	in[n++].v.b = true;
	gw_spb_metric_init(&in[n]);
	in[n].datatype = GW_SPB_STRING;
	in[n].kind = GW_SPB_V_STRING;
	in[n++].str = "h\xc3\xa9llo";
	gw_spb_metric_init(&in[n]);
	in[n].datatype = GW_SPB_BYTES;
	in[n].kind = GW_SPB_V_BYTES;
	in[n].bytes = raw;
	in[n++].nbytes = sizeof raw;
	gw_spb_metric_init(&in[n]);
	in[n].datatype = GW_SPB_INT32;
	in[n].is_null = true;
	in[n].has_quality = true;
	in[n].quality = GW_SPB_Q_BAD_NOT_CONNECTED;
	in[n++].reason = "station_offline";
	for (size_t i = 0; i < n; i++) {
		char name[8];

		snprintf(name, sizeof name, "m%zu", i);
		in[i].name = strdup(name);
		in[i].timestamp = 1000 + i;
	}
	gw_buf_init(&b);
	assert_int_equal(gw_spb_encode(&b, 42, in, n), 0);
	gw_spb_append_seq(&b, 255);
	assert_int_equal(gw_spb_decode(b.p, b.len, &d), 0);
	assert_true(d.has_timestamp && d.timestamp == 42 && d.has_seq && d.seq == 255);
	assert_int_equal(d.n, n);
	for (size_t i = 0; i < n; i++) {
		gw_spb_metric_at(&d, i, &out);
		assert_string_equal(out.name, in[i].name);
		assert_int_equal(out.timestamp, in[i].timestamp);
		assert_int_equal(out.datatype, in[i].datatype);
		assert_int_equal(out.is_null, in[i].is_null);
		assert_int_equal(out.has_quality, in[i].has_quality);
		assert_int_equal(out.quality, in[i].quality);
		if (in[i].reason)
			assert_string_equal(out.reason, in[i].reason);
		if (in[i].is_null)
			continue;
		assert_int_equal(out.kind, in[i].kind);
		switch (in[i].kind) {
		case GW_SPB_V_INT: assert_int_equal(out.v.i, in[i].v.i); break;
		case GW_SPB_V_LONG: assert_true(out.v.l == in[i].v.l); break;
		case GW_SPB_V_FLOAT: assert_true(out.v.f == in[i].v.f); break;
		case GW_SPB_V_DOUBLE: assert_true(out.v.d == in[i].v.d); break;
		case GW_SPB_V_BOOL: assert_int_equal(out.v.b, in[i].v.b); break;
		case GW_SPB_V_STRING: assert_string_equal(out.str, in[i].str); break;
		case GW_SPB_V_BYTES:
			assert_int_equal(out.nbytes, in[i].nbytes);
			assert_memory_equal(out.bytes, in[i].bytes, in[i].nbytes);
			break;
		default: fail();
		}
	}
	gw_spb_in_free(&d);
	for (size_t i = 0; i < n; i++)
		free((void *)in[i].name);
	gw_buf_free(&b);
	assert_int_equal(gw_spb_decode("\x12\x05\x0a", 3, &d), -1);       /* cut short */
}

/* ---- tags as metrics ---- */

static struct df1_tag_config cfg(const char *name, const char *addr, int count)
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

static struct df1_tag_state good(const struct df1_tag_config *c, const struct df1_value *v, size_t n)
{
	struct df1_tag_state st;

	memset(&st, 0, sizeof st);
	st.id = 4;
	st.config = c;
	st.count = n;
	st.values = v;
	st.value = v[0];
	st.has_value = true;
	st.quality = DF1_QUALITY_GOOD;
	st.last_good_wall_ms = 5000;
	return st;
}

static void test_tag_arrays(void **state)
{
	struct df1_tag_config ci = cfg("Words", "N7:0", 3), cb = cfg("Bits", "B3:0/0", 1),
	                      cf = cfg("Level", "F8:0", 2);
	struct df1_value vi[3] = { { .kind = DF1_VAL_INT16, .v.i16 = 1 }, { .kind = DF1_VAL_INT16, .v.i16 = -2 },
	                           { .kind = DF1_VAL_INT16, .v.i16 = 0x1234 } };
	struct df1_value vf[2] = { { .kind = DF1_VAL_FLOAT, .v.f = 1.5f }, { .kind = DF1_VAL_FLOAT, .v.f = -2.0f } };
	struct df1_value vb[1] = { { .kind = DF1_VAL_BIT, .v.bit = true } };
	struct df1_tag_state si = good(&ci, vi, 3), sf = good(&cf, vf, 2), sb = good(&cb, vb, 1);
	struct gw_tag_out ti = { &si, NULL, -1, NULL, 0 }, tf = { &sf, NULL, -1, NULL, 0 },
	                  tb = { &sb, NULL, -1, NULL, 0 };
	struct gw_spb_how birth = { true, true, false };
	static const uint8_t wi[] = { 0x01, 0x00, 0xfe, 0xff, 0x34, 0x12 };
	static const uint8_t wf[] = { 0x00, 0x00, 0xc0, 0x3f, 0x00, 0x00, 0x00, 0xc0 };
	struct gw_spb_list l;

	(void)state;
	gw_spb_list_init(&l);
	assert_int_equal(gw_spb_tag_metrics(&l, &ti, 5000, &birth), 0);
	assert_int_equal(gw_spb_tag_metrics(&l, &tf, 5000, &birth), 0);
	assert_int_equal(gw_spb_tag_metrics(&l, &tb, 5000, &birth), 0);
	assert_int_equal(l.n, 3);
	assert_string_equal(l.v[0].name, "Words");
	assert_int_equal(l.v[0].datatype, GW_SPB_INT16_ARRAY);
	assert_true(l.v[0].has_alias && l.v[0].alias == gw_spb_alias(4, 0));
	assert_int_equal(l.v[0].nbytes, sizeof wi);
	assert_memory_equal(l.v[0].bytes, wi, sizeof wi);
	assert_int_equal(l.v[1].datatype, GW_SPB_FLOAT_ARRAY);
	assert_memory_equal(l.v[1].bytes, wf, sizeof wf);
	assert_int_equal(l.v[2].datatype, GW_SPB_BOOLEAN);
	assert_true(l.v[2].v.b);
	assert_false(l.v[2].has_quality);                /* GOOD: no property */
	gw_spb_list_free(&l);
}

static void test_tag_timer_and_quality(void **state)
{
	struct df1_tag_config c = cfg("Fill_Timer", "T4:0", 1);
	struct df1_value v = { .kind = DF1_VAL_TCR, .v.tcr = { 0xA000, 500, 7 } };   /* EN, DN */
	struct df1_tag_state st = good(&c, &v, 1);
	struct gw_tag_out t = { &st, NULL, -1, NULL, 0 };
	struct gw_spb_how data = { false, true, false };
	struct gw_spb_list l;

	(void)state;
	gw_spb_list_init(&l);
	st.quality = DF1_QUALITY_UNCERTAIN;
	st.reason = DF1_REASON_COMM_FAILURE;
	assert_int_equal(gw_spb_tag_metrics(&l, &t, 0, &data), 0);
	assert_int_equal(l.n, 5);                        /* EN TT DN PRE ACC */
	assert_null(l.v[0].name);                        /* DATA with aliases: no names */
	assert_true(l.v[0].alias == gw_spb_alias(4, 1) && l.v[4].alias == gw_spb_alias(4, 5));
	assert_true(l.v[0].v.b && !l.v[1].v.b && l.v[2].v.b);
	assert_int_equal(l.v[3].v.i, 500);
	assert_int_equal(l.v[4].v.i, 7);
	assert_true(l.v[0].has_quality);
	assert_int_equal(l.v[0].quality, GW_SPB_Q_UNCERTAIN_LAST_KNOWN);
	assert_string_equal(l.v[0].reason, "comm_failure");
	gw_spb_list_free(&l);
}

/* BooleanArray: count 10 (little-endian), then bits from each byte's high bit */
static void test_boolean_array_layout(void **state)
{
	struct df1_tag_config c = cfg("Flags", "B3:0/0", 10);
	struct df1_value v[10];
	struct df1_tag_state st;
	struct gw_tag_out t = { &st, NULL, -1, NULL, 0 };
	struct gw_spb_how birth = { true, false, false };
	static const uint8_t want[] = { 10, 0, 0, 0, 0xA0, 0x40 };   /* bits 0, 2, 9 */
	struct gw_spb_list l;
	struct gw_spb_metric back;
	struct df1_value out[10];
	size_t n;
	char err[128];

	(void)state;
	for (int i = 0; i < 10; i++)
		v[i] = (struct df1_value){ .kind = DF1_VAL_BIT, .v.bit = i == 0 || i == 2 || i == 9 };
	st = good(&c, v, 10);
	gw_spb_list_init(&l);
	assert_int_equal(gw_spb_tag_metrics(&l, &t, 0, &birth), 0);
	assert_int_equal(l.v[0].datatype, GW_SPB_BOOLEAN_ARRAY);
	assert_int_equal(l.v[0].nbytes, sizeof want);
	assert_memory_equal(l.v[0].bytes, want, sizeof want);
	back = l.v[0];                                   /* the same bytes as a command */
	assert_int_equal(gw_spb_write_values(&back, "", 0, &c, &st, out, 10, &n, err, sizeof err), 0);
	assert_int_equal(n, 10);
	for (int i = 0; i < 10; i++)
		assert_int_equal(out[i].v.bit, v[i].v.bit);
	gw_spb_list_free(&l);
}

static void test_commands(void **state)
{
	struct df1_tag_config cn = cfg("Speed", "N7:0", 1), ct = cfg("Fill_Timer", "T4:0", 1);
	struct df1_value tv = { .kind = DF1_VAL_TCR, .v.tcr = { 0x8000, 500, 7 } };
	struct df1_tag_state st = good(&ct, &tv, 1);
	struct gw_spb_metric m;
	struct df1_value out[4];
	const char *member;
	char tag[80], err[128];
	unsigned am;
	size_t n;
	int id;

	(void)state;
	gw_spb_metric_init(&m);
	m.name = "Fill_Timer/PRE";
	m.datatype = GW_SPB_INT16;
	m.kind = GW_SPB_V_INT;
	m.v.i = 0xFFFF;                                  /* -1 as Int16 */
	assert_true(gw_spb_metric_target(&m, tag, sizeof tag, &member, &id, &am));
	assert_string_equal(tag, "Fill_Timer");
	assert_string_equal(member, "PRE");
	assert_int_equal(gw_spb_write_values(&m, member, am, &ct, &st, out, 4, &n, err, sizeof err), 0);
	assert_int_equal(n, 1);
	assert_int_equal(out[0].v.tcr.pre, -1);
	assert_int_equal(out[0].v.tcr.acc, 7);           /* the rest as it is */
	/* by alias: Fill_Timer's DN (member 3) */
	gw_spb_metric_init(&m);
	m.has_alias = true;
	m.alias = gw_spb_alias(4, 3);
	m.datatype = GW_SPB_BOOLEAN;
	m.kind = GW_SPB_V_BOOL;
	m.v.b = true;
	assert_true(gw_spb_metric_target(&m, tag, sizeof tag, &member, &id, &am));
	assert_int_equal(id, 4);
	assert_int_equal(am, 3);
	assert_int_equal(gw_spb_write_values(&m, member, am, &ct, &st, out, 4, &n, err, sizeof err), 0);
	assert_int_equal(out[0].v.tcr.ctl, 0xA000);
	/* a 16-bit word: a value beyond Int16 refused */
	gw_spb_metric_init(&m);
	m.datatype = GW_SPB_INT32;
	m.kind = GW_SPB_V_INT;
	m.v.i = 70000;
	assert_int_equal(gw_spb_write_values(&m, "", 0, &cn, NULL, out, 4, &n, err, sizeof err), DF1_E_RANGE);
	m.kind = GW_SPB_V_STRING;
	m.str = "x";
	assert_int_equal(gw_spb_write_values(&m, "", 0, &cn, NULL, out, 4, &n, err, sizeof err), DF1_E_TYPE);
}

/* A float tag takes no NaN, infinity or number beyond a float's range, as
 * /set refuses them (found by tests/fuzz/fuzz_spb_cmd.c) */
static void test_command_floats(void **state)
{
	struct df1_tag_config cf = cfg("Level", "F8:0", 1), cf2 = cfg("Levels", "F8:0", 2);
	static const uint8_t nan_array[8] = { 0, 0, 0x80, 0x3f, 0xff, 0xff, 0xff, 0xff };  /* 1.0, NaN */
	struct gw_spb_metric m;
	struct df1_value out[4];
	char err[128];
	size_t n;

	(void)state;
	gw_spb_metric_init(&m);
	m.name = "Level";
	m.datatype = GW_SPB_FLOAT;
	m.kind = GW_SPB_V_FLOAT;
	m.v.f = NAN;
	assert_int_equal(gw_spb_write_values(&m, "", 0, &cf, NULL, out, 4, &n, err, sizeof err), DF1_E_RANGE);
	m.datatype = GW_SPB_DOUBLE;
	m.kind = GW_SPB_V_DOUBLE;
	m.v.d = 1e300;
	assert_int_equal(gw_spb_write_values(&m, "", 0, &cf, NULL, out, 4, &n, err, sizeof err), DF1_E_RANGE);
	m.v.d = 2.5;
	assert_int_equal(gw_spb_write_values(&m, "", 0, &cf, NULL, out, 4, &n, err, sizeof err), 0);
	assert_true(n == 1 && out[0].v.f == 2.5f);
	m.datatype = GW_SPB_FLOAT_ARRAY;
	m.kind = GW_SPB_V_BYTES;
	m.bytes = nan_array;
	m.nbytes = sizeof nan_array;
	assert_int_equal(gw_spb_write_values(&m, "", 0, &cf2, NULL, out, 4, &n, err, sizeof err), DF1_E_RANGE);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_int16_vector),
		cmocka_unit_test(test_float_alias_vector),
		cmocka_unit_test(test_quality_vector),
		cmocka_unit_test(test_ndeath_vector),
		cmocka_unit_test(test_round_trip),
		cmocka_unit_test(test_tag_arrays),
		cmocka_unit_test(test_tag_timer_and_quality),
		cmocka_unit_test(test_boolean_array_layout),
		cmocka_unit_test(test_commands),
		cmocka_unit_test(test_command_floats),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
