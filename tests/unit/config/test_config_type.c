/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_config_type.c - the mapping file's Type column (lib/proto/value_type.c,
 * lib/config/config_map.c, df1_tag_value_kind): which Types fit which
 * addresses, the conversions a Type implies, and the bad rows of a mapping
 * file reported with their item numbers. Expectations from the table of
 * libdf1(7) "Mapping file", written out here by hand.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "df1.h"
#include "proto/value_type.h"

/* Type on address: the kind, or the error. */
static int kind_of(const char *type, const char *addr)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	assert_int_equal(df1_addr_parse(addr, &c.addr), 0);
	snprintf(c.type, sizeof c.type, "%s", type);
	return df1_tag_value_kind(&c);
}

static void test_type_fits(void **state)
{
	(void)state;
	/* empty: the address's own */
	assert_int_equal(kind_of("", "N7:0"), DF1_VAL_INT16);
	assert_int_equal(kind_of("", "F8:0"), DF1_VAL_FLOAT);
	assert_int_equal(kind_of("", "T4:0"), DF1_VAL_TCR);
	assert_int_equal(kind_of("  ", "B3:0/5"), DF1_VAL_BIT);
	/* the address's own kind, any case, blanks around */
	assert_int_equal(kind_of("INT", "N7:0"), DF1_VAL_INT16);
	assert_int_equal(kind_of(" int ", "T4:0.ACC"), DF1_VAL_INT16);
	assert_int_equal(kind_of("INT", "B3:0"), DF1_VAL_INT16);
	assert_int_equal(kind_of("INT", "I1:0.1"), DF1_VAL_INT16);
	assert_int_equal(kind_of("DINT", "L10:0"), DF1_VAL_INT32);
	assert_int_equal(kind_of("Long", "L10:0"), DF1_VAL_INT32);
	assert_int_equal(kind_of("REAL", "F8:0"), DF1_VAL_FLOAT);
	assert_int_equal(kind_of("float", "F8:0"), DF1_VAL_FLOAT);
	assert_int_equal(kind_of("BOOL", "B3:0/5"), DF1_VAL_BIT);
	assert_int_equal(kind_of("BOOL", "T4:0/DN"), DF1_VAL_BIT);
	assert_int_equal(kind_of("BOOL", "N7:0/15"), DF1_VAL_BIT);
	assert_int_equal(kind_of("STRING", "ST9:0"), DF1_VAL_STRING);
	assert_int_equal(kind_of("TIMER", "T4:0"), DF1_VAL_TCR);
	assert_int_equal(kind_of("COUNTER", "C5:0"), DF1_VAL_TCR);
	assert_int_equal(kind_of("CONTROL", "R6:0"), DF1_VAL_TCR);
	/* wider numbers hold every 16-bit word */
	assert_int_equal(kind_of("DINT", "N7:0"), DF1_VAL_INT32);
	assert_int_equal(kind_of("REAL", "N7:0"), DF1_VAL_FLOAT);
	assert_int_equal(kind_of("REAL", "C5:0.ACC"), DF1_VAL_FLOAT);
}

static void test_type_does_not_fit(void **state)
{
	(void)state;
	assert_int_equal(kind_of("FLOAT", "B3:0/5"), DF1_E_TYPE);    /* the issue's example */
	assert_int_equal(kind_of("INT", "B3:0/5"), DF1_E_TYPE);      /* a bit is BOOL */
	assert_int_equal(kind_of("INT", "F8:0"), DF1_E_TYPE);        /* an INT cannot hold 1.5 */
	assert_int_equal(kind_of("DINT", "F8:0"), DF1_E_TYPE);
	assert_int_equal(kind_of("INT", "L10:0"), DF1_E_TYPE);       /* nor 70000 */
	assert_int_equal(kind_of("REAL", "L10:0"), DF1_E_TYPE);      /* a float has 24 bits */
	assert_int_equal(kind_of("INT", "T4:0"), DF1_E_TYPE);        /* INT on a timer: refused */
	assert_int_equal(kind_of("DINT", "C5:0"), DF1_E_TYPE);
	assert_int_equal(kind_of("TIMER", "C5:0"), DF1_E_TYPE);
	assert_int_equal(kind_of("COUNTER", "T4:0"), DF1_E_TYPE);
	assert_int_equal(kind_of("TIMER", "T4:0.ACC"), DF1_E_TYPE);
	assert_int_equal(kind_of("BOOL", "N7:0"), DF1_E_TYPE);
	assert_int_equal(kind_of("STRING", "N7:0"), DF1_E_TYPE);
	assert_int_equal(kind_of("INT", "ST9:0"), DF1_E_TYPE);
	/* not Types */
	assert_int_equal(kind_of("WHATEVER", "N7:0"), DF1_E_INVAL);
	assert_int_equal(kind_of("INT16", "N7:0"), DF1_E_INVAL);
	assert_int_equal(kind_of("IN T", "N7:0"), DF1_E_INVAL);
	assert_int_equal(df1_tag_value_kind(NULL), DF1_E_INVAL);
}

static void test_type_conversions(void **state)
{
	struct df1_value v;
	(void)state;

	v.kind = DF1_VAL_INT16;
	v.v.i16 = -32768;
	value_type_widen(&v, DF1_VAL_INT32);
	assert_int_equal(v.kind, DF1_VAL_INT32);
	assert_int_equal(v.v.i32, -32768);
	v.kind = DF1_VAL_INT16;
	v.v.i16 = 1234;
	value_type_widen(&v, DF1_VAL_FLOAT);
	assert_int_equal(v.kind, DF1_VAL_FLOAT);
	assert_true(v.v.f == 1234.0f);
	/* back to a word for a write: whole numbers in range only */
	assert_int_equal(value_type_narrow(&v, DF1_VAL_INT16), 0);
	assert_int_equal(v.kind, DF1_VAL_INT16);
	assert_int_equal(v.v.i16, 1234);
	v.kind = DF1_VAL_FLOAT;
	v.v.f = 2.5f;
	assert_int_equal(value_type_narrow(&v, DF1_VAL_INT16), DF1_E_RANGE);
	v.v.f = 32768.0f;
	assert_int_equal(value_type_narrow(&v, DF1_VAL_INT16), DF1_E_RANGE);
	v.v.f = -32768.0f;
	assert_int_equal(value_type_narrow(&v, DF1_VAL_INT16), 0);
	assert_int_equal(v.v.i16, -32768);
	v.kind = DF1_VAL_INT32;
	v.v.i32 = 40000;
	assert_int_equal(value_type_narrow(&v, DF1_VAL_INT16), DF1_E_RANGE);
	v.v.i32 = -7;
	assert_int_equal(value_type_narrow(&v, DF1_VAL_INT16), 0);
	assert_int_equal(v.v.i16, -7);
	v.kind = DF1_VAL_BIT;
	assert_int_equal(value_type_narrow(&v, DF1_VAL_INT16), DF1_E_TYPE);
}

/* ---- the mapping file ---- */

struct seen {
	int rows;
	char names[16][64];
	int issues;
	int item[16];
	int id[16];
	char text[16][200];
};

static int on_row(void *user, const struct df1_tag_config *t)
{
	struct seen *s = user;

	if (s->rows < 16)
		snprintf(s->names[s->rows], sizeof s->names[0], "%s", t->name);
	s->rows++;
	return 0;
}

static void on_issue(void *user, const struct df1_config_issue *i)
{
	struct seen *s = user;

	if (s->issues < 16) {
		s->item[s->issues] = i->item;
		s->id[s->issues] = i->catalog_id;
		snprintf(s->text[s->issues], sizeof s->text[0], "%s", i->text);
	}
	s->issues++;
}

static int load(const char *text, bool strict, struct seen *s)
{
	char path[] = "/tmp/test_config_type_XXXXXX";
	int fd = mkstemp(path), rc;

	assert_true(fd >= 0);
	assert_int_equal(write(fd, text, strlen(text)), (ssize_t)strlen(text));
	close(fd);
	memset(s, 0, sizeof *s);
	rc = df1_map_load(path, strict, on_row, on_issue, s);
	unlink(path);
	return rc;
}

static const char rows[] =
	"Tag,Command,Type,Station,PLC_Type,Address\n"
	"a,Read,INT,1,SLC,N7:0\n"
	"b,Read,DINT,1,SLC,N7:1\n"
	"c,Read,REAL,1,SLC,N7:2\n"
	"d,Read,FLOAT,1,SLC,F8:0\n"
	"e,Read,BOOL,1,SLC,B3:0/5\n"
	"f,Read,STRING,1,SLC,ST9:0\n"
	"g,Read,TIMER,1,SLC,T4:0\n"
	"h,Read,LONG,1,MicroLogix,L10:0\n"
	"i,Read,,1,SLC,F8:1\n"
	"F1,Read,INT,1,SLC,F8:0\n"              /* item 10: INT cannot hold a float */
	"B1,Read,FLOAT,1,SLC,B3:0/5\n"          /* item 11: a bit is BOOL */
	"W,Read,WHATEVER,1,SLC,N7:0\n"          /* item 12: not a Type */
	"T1,Read,INT,1,SLC,T4:0\n"              /* item 13: INT on a timer: refused */
	"X,Read,FLOAT,1,SLC,N7:x\n";            /* item 14: the address's error only */

static void test_map_rows(void **state)
{
	struct seen s;
	(void)state;

	assert_int_equal(load(rows, false, &s), 9);
	assert_int_equal(s.rows, 9);
	assert_string_equal(s.names[8], "i");
	assert_int_equal(s.issues, 5);
	assert_int_equal(s.item[0], 10);
	assert_int_equal(s.id[0], 0);
	assert_non_null(strstr(s.text[0], "Item: 10, Type INT does not fit F8:0"));
	assert_non_null(strstr(s.text[0], "REAL"));
	assert_int_equal(s.item[1], 11);
	assert_non_null(strstr(s.text[1], "Item: 11, Type FLOAT does not fit B3:0/5: a bit is BOOL"));
	assert_int_equal(s.item[2], 12);
	assert_non_null(strstr(s.text[2], "Item: 12, Invalid Type (WHATEVER) should be one of INT"));
	assert_int_equal(s.item[3], 13);
	assert_non_null(strstr(s.text[3], "Item: 13, Type INT does not fit T4:0: a whole timer is TIMER"));
	assert_int_equal(s.item[4], 14);
	assert_int_equal(s.id[4], 2503);
	/* strict: nothing loaded */
	assert_int_equal(load(rows, true, &s), DF1_E_CONFIG);
	assert_int_equal(s.rows, 0);
	assert_int_equal(s.issues, 5);
}

static void test_tag_add_checks_type(void **state)
{
	struct df1_tag_config c;
	struct df1_tag_state st;
	df1_t *h;
	int id;
	(void)state;

	assert_int_equal(df1_new(&h), 0);
	memset(&c, 0, sizeof c);
	strcpy(c.name, "x");
	c.access = DF1_ACCESS_READWRITE;
	c.station = 1;
	c.plc = DF1_PLC_SLC;
	c.count = 2;
	c.scan_ms = 1000;
	assert_int_equal(df1_addr_parse("B3:0/5", &c.addr), 0);
	c.count = 1;
	strcpy(c.type, "FLOAT");
	assert_int_equal(df1_tag_add(h, &c), DF1_E_TYPE);
	assert_non_null(strstr(df1_last_error(h)->message, "a bit is BOOL"));
	assert_int_equal(df1_addr_parse("N7:0", &c.addr), 0);
	c.count = 2;
	strcpy(c.type, "REAL");
	id = df1_tag_add(h, &c);
	assert_true(id >= 0);
	assert_int_equal(df1_tag_get(h, id, &st), 0);
	assert_int_equal(st.values[0].kind, DF1_VAL_FLOAT);       /* before the first read too */
	/* writes: the Type's values, back to the word, range checked */
	{
		struct df1_value v[2] = { { .kind = DF1_VAL_FLOAT }, { .kind = DF1_VAL_FLOAT } };

		v[0].v.f = 3.0f;
		v[1].v.f = 3.5f;
		assert_int_equal(df1_tag_write(h, id, v, 2, NULL, NULL), DF1_E_RANGE);
		v[1].v.f = -4.0f;
		assert_true(df1_tag_write(h, id, v, 2, NULL, NULL) > 0);
		v[0].kind = DF1_VAL_INT16;              /* the address's own kind is taken too */
		v[0].v.i16 = 9;
		assert_true(df1_tag_write(h, id, v, 1, NULL, NULL) > 0);
	}
	df1_free(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_type_fits),
		cmocka_unit_test(test_type_does_not_fit),
		cmocka_unit_test(test_type_conversions),
		cmocka_unit_test(test_map_rows),
		cmocka_unit_test(test_tag_add_checks_type),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
