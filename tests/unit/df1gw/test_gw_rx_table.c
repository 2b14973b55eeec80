/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_rx_table.c - df1gw's Receive rows as data (tools/df1gw/gw_rx_table.c;
 * df1gw(1), RECEIVE): the regions start at zero (the table's own initial
 * pattern, element n holding n, is gone); before a row's first write it is
 * told as no value, UNCERTAIN, "no_message_yet" (the JSON payload written out
 * by hand below; Sparkplug a null metric of its datatype with the Quality
 * Uncertain, 0x40000000 | 256), while a write sees the zeros the table
 * holds; after a write it is GOOD with the values written; a row is found
 * by name with its tag id after the polled ones.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "df1_server.h"
#include "df1gw/gw_json.h"
#include "df1gw/gw_rx_table.h"
#include "df1gw/gw_spb_metrics.h"
#include "df1gw/gw_value.h"

#define NTAGS 7         /* polled tags before the Receive rows */

struct fixture {
	struct gw_rx rx;
	struct gw_rx_tag rows[3];
};

static void row(struct gw_rx_tag *e, const char *name, const char *addr, int count, int last, int esize)
{
	memset(e, 0, sizeof *e);
	snprintf(e->c.name, sizeof e->c.name, "%s", name);
	e->c.access = DF1_ACCESS_RECEIVE;
	e->c.station = 0;
	e->c.plc = DF1_PLC_SLC;
	e->c.count = count;
	assert_int_equal(df1_addr_parse(addr, &e->c.addr), 0);
	e->shown = e->c;
	e->shown.access = DF1_ACCESS_READWRITE;
	e->lo = (size_t)e->c.addr.element * (size_t)esize;
	e->hi = (size_t)(last + 1) * (size_t)esize;
	e->from = -1;
}

/* N50:0,5 and N50:6,2 (one file, a gap at N50:5), B53:0/2 x3 (word 0) */
static int setup(void **state)
{
	static struct fixture f;

	memset(&f, 0, sizeof f);
	row(&f.rows[0], "Batch", "N50:0", 5, 4, 2);
	row(&f.rows[1], "Tail", "N50:6", 2, 7, 2);
	row(&f.rows[2], "Flags", "B53:0/2", 3, 0, 2);
	f.rx.v = f.rows;
	f.rx.n = 3;
	f.rx.station = 0;
	assert_int_equal(df1_table_new(&f.rx.t, DF1_PLC_SLC), 0);
	assert_int_equal(df1_table_add_file(f.rx.t, DF1_FT_N, 50, 8), 0);
	assert_int_equal(df1_table_add_file(f.rx.t, DF1_FT_B, 53, 1), 0);
	*state = &f;
	return 0;
}

static int teardown(void **state)
{
	struct fixture *f = *state;

	df1_table_free(f->rx.t);
	return 0;
}

static void test_regions_start_at_zero(void **state)
{
	struct fixture *f = *state;
	struct df1_value v[8];

	/* the table's initial pattern first (df1_table_add_file(3)): N50:n = n */
	assert_int_equal(df1_table_read(f->rx.t, "N50:0", v, 8), 8);
	assert_int_equal(v[3].v.i16, 3);
	assert_int_equal(gw_rx_zero(&f->rx), 0);
	assert_int_equal(df1_table_read(f->rx.t, "N50:0", v, 5), 5);
	for (int i = 0; i < 5; i++)
		assert_int_equal(v[i].v.i16, 0);
	assert_int_equal(df1_table_read(f->rx.t, "N50:6", v, 2), 2);
	assert_int_equal(v[0].v.i16, 0);
	assert_int_equal(v[1].v.i16, 0);
	assert_int_equal(df1_table_read(f->rx.t, "B53:0", v, 1), 1);
	assert_int_equal(v[0].v.i16, 0);
}

static void test_unwritten_row_told_as_no_message(void **state)
{
	struct fixture *f = *state;
	static struct df1_value vals[DF1_TABLE_ELEMENTS_MAX];
	struct df1_tag_state st;
	const char *reason = "x";
	struct gw_buf b;

	assert_int_equal(gw_rx_zero(&f->rx), 0);
	assert_int_equal(gw_rx_row_state(&f->rx, NTAGS, &f->rows[0], true, &st, vals, &reason), 0);
	assert_false(st.has_value);
	assert_int_equal(st.quality, DF1_QUALITY_UNCERTAIN);
	assert_int_equal(st.id, NTAGS + 0);
	assert_string_equal(reason, "no_message_yet");

	struct gw_tag_view view = { reason, -1, NULL, true };

	gw_buf_init(&b);
	gw_tag_json(&b, &st, &view);
	assert_false(b.oom);
	assert_string_equal(b.p, "{\"value\":null,\"quality\":\"UNCERTAIN\",\"reason\":\"no_message_yet\","
	                         "\"ts\":null,\"address\":\"N50:0\",\"station\":0}");
	gw_buf_free(&b);

	/* what a write starts from: the zeros the table holds, as a value */
	assert_int_equal(gw_rx_row_state(&f->rx, NTAGS, &f->rows[0], false, &st, vals, &reason), 0);
	assert_true(st.has_value);
	assert_null(reason);
	assert_int_equal(st.count, 5);
	for (int i = 0; i < 5; i++)
		assert_int_equal(vals[i].v.i16, 0);
}

static void test_unwritten_row_in_sparkplug(void **state)
{
	struct fixture *f = *state;
	static struct df1_value vals[DF1_TABLE_ELEMENTS_MAX];
	struct df1_tag_state st;
	const char *reason;
	struct gw_spb_how birth = { true, false, false };
	struct gw_spb_list l;

	assert_int_equal(gw_rx_zero(&f->rx), 0);
	assert_int_equal(gw_rx_row_state(&f->rx, NTAGS, &f->rows[0], true, &st, vals, &reason), 0);

	struct gw_tag_out t = { &st, reason, -1, NULL, 0 };

	gw_spb_list_init(&l);
	assert_int_equal(gw_spb_tag_metrics(&l, &t, 0, &birth), 0);
	assert_int_equal(l.n, 1);
	assert_string_equal(l.v[0].name, "Batch");
	assert_int_equal(l.v[0].datatype, 23);   /* Int16Array: Sparkplug B's datatype number */
	assert_true(l.v[0].is_null);
	assert_true(l.v[0].has_quality);
	assert_int_equal(l.v[0].quality, (int32_t)0x40000100);
	assert_string_equal(l.v[0].reason, "no_message_yet");
	gw_spb_list_free(&l);
}

static void test_written_row_is_good(void **state)
{
	struct fixture *f = *state;
	static struct df1_value vals[DF1_TABLE_ELEMENTS_MAX];
	struct df1_value in[5];
	struct df1_tag_state st;
	const char *reason = "x";
	struct gw_buf b;

	assert_int_equal(gw_rx_zero(&f->rx), 0);
	for (int i = 0; i < 5; i++)
		in[i] = (struct df1_value){ .kind = DF1_VAL_INT16, .v.i16 = (int16_t)(100 + i) };
	assert_int_equal(df1_table_write_addr(f->rx.t, &f->rows[0].c.addr, in, 5), 5);
	f->rows[0].written = true;
	f->rows[0].from = 1;
	f->rows[0].wall_ms = 1796400000123;         /* 2026-12-04T16:00:00.123Z */
	assert_int_equal(gw_rx_row_state(&f->rx, NTAGS, &f->rows[0], true, &st, vals, &reason), 0);
	assert_true(st.has_value);
	assert_null(reason);
	assert_int_equal(st.quality, DF1_QUALITY_GOOD);
	gw_buf_init(&b);
	gw_tag_json(&b, &st, NULL);
	assert_string_equal(b.p, "{\"value\":[100,101,102,103,104],\"quality\":\"GOOD\",\"reason\":\"none\","
	                         "\"ts\":\"2026-12-04T16:00:00.123Z\",\"address\":\"N50:0\",\"station\":0}");
	gw_buf_free(&b);
	/* the other rows are still unwritten */
	assert_int_equal(gw_rx_row_state(&f->rx, NTAGS, &f->rows[2], true, &st, vals, &reason), 0);
	assert_false(st.has_value);
	assert_string_equal(reason, "no_message_yet");
}

static void test_row_by_name(void **state)
{
	struct fixture *f = *state;
	struct df1_tag_state cur;

	assert_true(gw_rx_tag_state(&f->rx, NTAGS, "Flags", &cur));
	assert_int_equal(cur.id, NTAGS + 2);
	assert_int_equal(cur.count, 3);
	assert_ptr_equal(cur.config, &f->rows[2].shown);
	assert_int_equal(cur.config->access, DF1_ACCESS_READWRITE);
	assert_false(cur.has_value);
	assert_false(gw_rx_tag_state(&f->rx, NTAGS, "flags", &cur));
	assert_false(gw_rx_tag_state(&f->rx, NTAGS, "Speed", &cur));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_regions_start_at_zero, setup, teardown),
		cmocka_unit_test_setup_teardown(test_unwritten_row_told_as_no_message, setup, teardown),
		cmocka_unit_test_setup_teardown(test_unwritten_row_in_sparkplug, setup, teardown),
		cmocka_unit_test_setup_teardown(test_written_row_is_good, setup, teardown),
		cmocka_unit_test_setup_teardown(test_row_by_name, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
