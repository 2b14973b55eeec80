/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_table - the data table (lib/table/table.c, lib/table/table_file.c,
 * lib/table/table_serve.c; df1_table(3)). Expectations come from the documents, not
 * from the code: initial contents from df1sim(1) DATA TABLE, the wire layout
 * from doc/PROTOCOL.md 5 (LE words and floats, ST as LEN + byte-swapped
 * characters), EXT STS codes from M p.8-4 as lib/server/server.h lists them, the
 * masked write rule of doc/PROTOCOL.md 4.6, the diagnostic status layouts of doc/PROTOCOL.md 4.9
 * (M p.174 EE form, M p.192-193 EB form), and the spec's SLC vectors for
 * commands served through server_handle().
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "df1_int.h"
#include "proto/pccc.h"
#include "server/server.h"
#include "table/table.h"

static char tmpdir[256];

static int setup_dir(void **state)
{
	(void)state;
	snprintf(tmpdir, sizeof tmpdir, "%s/test_table.XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	assert_non_null(mkdtemp(tmpdir));
	return 0;
}

static int teardown_dir(void **state)
{
	DIR *d = opendir(tmpdir);
	struct dirent *e;
	char p[512];

	(void)state;
	while (d && (e = readdir(d)) != NULL) {
		if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
			continue;
		snprintf(p, sizeof p, "%s/%s", tmpdir, e->d_name);
		unlink(p);
	}
	if (d)
		closedir(d);
	rmdir(tmpdir);
	return 0;
}

static void write_file(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");

	assert_non_null(f);
	fputs(text, f);
	assert_int_equal(fclose(f), 0);
}

static struct df1_table *default_table(enum df1_plc plc)
{
	struct df1_table *t = NULL;

	assert_int_equal(df1_table_new(&t, plc), 0);
	assert_non_null(t);
	assert_int_equal(df1_table_add_default_files(t), 0);
	return t;
}

/* Raw bytes through the serving callbacks (the contract of lib/server/server.h). */
static int raw_read(struct df1_table *t, const char *addr, uint8_t *buf, size_t n)
{
	struct df1_addr a;

	assert_int_equal(df1_addr_parse(addr, &a), 0);
	a.bit = DF1_ADDR_NONE;
	return df1_table_server_ops(t)->read(t, 1, &a, buf, n);
}

static struct df1_value int16_value(int16_t v)
{
	struct df1_value x = { .kind = DF1_VAL_INT16 };

	x.v.i16 = v;
	return x;
}

/* ------------------------------------------------------------------------
 * Files and initial contents
 * ------------------------------------------------------------------------ */

static void test_table_new_invalid_arguments(void **state)
{
	struct df1_table *t = (struct df1_table *)1;

	(void)state;
	assert_int_equal(df1_table_new(NULL, DF1_PLC_SLC), DF1_E_INVAL);
	assert_int_equal(df1_table_new(&t, (enum df1_plc)99), DF1_E_INVAL);
	assert_null(t);
	df1_table_free(NULL);
	assert_int_equal(df1_table_add_file(NULL, DF1_FT_N, 7, 10), DF1_E_INVAL);
	assert_int_equal(df1_table_mode(NULL), DF1_E_INVAL);
	assert_null(df1_table_server_ops(NULL));
	assert_string_equal(df1_table_error_text(NULL), "");
	assert_int_equal(df1_table_load(NULL, "x"), DF1_E_INVAL);
	assert_int_equal(df1_table_save(NULL, "x"), DF1_E_INVAL);
}

static void test_table_new_is_empty_in_run_mode(void **state)
{
	struct df1_table *t = NULL;

	(void)state;
	assert_int_equal(df1_table_new(&t, DF1_PLC_SLC), 0);
	for (int i = 0; i < DF1_TABLE_FILES_MAX; i++)
		assert_int_equal(df1_table_file(t, i, NULL), DF1_E_ADDR_RANGE);
	assert_int_equal(df1_table_mode(t), 6);
	df1_table_free(t);
}

static void test_table_default_files_shape(void **state)
{
	static const enum df1_file_type want[12] = {
		DF1_FT_O, DF1_FT_I, DF1_FT_S, DF1_FT_B, DF1_FT_T, DF1_FT_C, DF1_FT_R, DF1_FT_N, DF1_FT_F,
		DF1_FT_ST, DF1_FT_L, DF1_FT_A,
	};
	struct df1_table *t = default_table(DF1_PLC_SLC);
	enum df1_file_type type;

	(void)state;
	for (int i = 0; i < 12; i++) {
		assert_int_equal(df1_table_file(t, i, &type), 256);
		assert_int_equal(type, want[i]);
	}
	assert_int_equal(df1_table_file(t, 12, &type), DF1_E_ADDR_RANGE);
	assert_int_equal(df1_table_file(t, -1, &type), DF1_E_ADDR_RANGE);
	assert_int_equal(df1_table_file(t, 1000, &type), DF1_E_ADDR_RANGE);
	df1_table_free(t);
}

static void test_table_initial_contents_as_documented(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v[3];

	(void)state;
	/* df1sim(1): N7:5 = 5, F8:2 = 2.5, L10:1 = 65537, T/C PRE 100 ACC 0, "STRING n" */
	assert_int_equal(df1_table_read(t, "N7:5", v, 1), 1);
	assert_int_equal(v[0].kind, DF1_VAL_INT16);
	assert_int_equal(v[0].v.i16, 5);
	assert_int_equal(df1_table_read(t, "F8:2", v, 1), 1);
	assert_int_equal(v[0].kind, DF1_VAL_FLOAT);
	assert_true(v[0].v.f == 2.5f);
	assert_int_equal(df1_table_read(t, "L10:1", v, 1), 1);
	assert_int_equal(v[0].v.i32, 65537);
	assert_int_equal(df1_table_read(t, "T4:3", v, 1), 1);
	assert_int_equal(v[0].kind, DF1_VAL_TCR);
	assert_int_equal(v[0].v.tcr.ctl, 0);
	assert_int_equal(v[0].v.tcr.pre, 100);
	assert_int_equal(v[0].v.tcr.acc, 0);
	assert_int_equal(df1_table_read(t, "C5:0.PRE", v, 1), 1);
	assert_int_equal(v[0].v.i16, 100);
	assert_int_equal(df1_table_read(t, "R6:0", v, 1), 1);
	assert_int_equal(v[0].v.tcr.pre, 0);
	assert_int_equal(df1_table_read(t, "ST9:12", v, 1), 1);
	assert_int_equal(v[0].kind, DF1_VAL_STRING);
	assert_string_equal(v[0].v.str.text, "STRING 12");
	assert_int_equal(v[0].v.str.len, 9);
	assert_int_equal(df1_table_read(t, "B3:0", v, 3), 3);
	assert_int_equal(v[0].v.i16 | v[1].v.i16 | v[2].v.i16, 0);
	assert_int_equal(df1_table_read(t, "N7:255", v, 1), 1);
	assert_int_equal(v[0].v.i16, 255);
	df1_table_free(t);
}

static void test_table_wire_layout_spec_5(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v = { .kind = DF1_VAL_STRING };
	uint8_t b[84];

	(void)state;
	/* N7:1 = 1, LE */
	assert_int_equal(raw_read(t, "N7:1", b, 2), 0);
	assert_int_equal(b[0], 0x01);
	assert_int_equal(b[1], 0x00);
	/* F8:1 = 1.5 = 3FC00000h, LE 00 00 C0 3F */
	assert_int_equal(raw_read(t, "F8:1", b, 4), 0);
	assert_int_equal(b[0], 0x00);
	assert_int_equal(b[1], 0x00);
	assert_int_equal(b[2], 0xC0);
	assert_int_equal(b[3], 0x3F);
	/* L10:1 = 65537 = 00010001h, LE */
	assert_int_equal(raw_read(t, "L10:1", b, 4), 0);
	assert_int_equal(b[0], 0x01);
	assert_int_equal(b[1], 0x00);
	assert_int_equal(b[2], 0x01);
	assert_int_equal(b[3], 0x00);
	/* "ABC" -> 03 00 42 41 00 43 (doc/PROTOCOL.md 5) */
	snprintf(v.v.str.text, sizeof v.v.str.text, "ABC");
	v.v.str.len = 3;
	assert_int_equal(df1_table_write(t, "ST9:0", &v, 1), 1);
	assert_int_equal(raw_read(t, "ST9:0", b, 84), 0);
	assert_int_equal(b[0], 0x03);
	assert_int_equal(b[1], 0x00);
	assert_int_equal(b[2], 0x42);
	assert_int_equal(b[3], 0x41);
	assert_int_equal(b[4], 0x00);
	assert_int_equal(b[5], 0x43);
	/* T4:0: control, PRE 100 = 64h, ACC */
	assert_int_equal(raw_read(t, "T4:0", b, 6), 0);
	assert_int_equal(b[2], 100);
	assert_int_equal(b[3], 0);
	df1_table_free(t);
}

static void test_table_add_file_grows_and_refuses_other_type(void **state)
{
	struct df1_table *t = NULL;
	struct df1_value v;
	enum df1_file_type type;

	(void)state;
	assert_int_equal(df1_table_new(&t, DF1_PLC_SLC), 0);
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 7, 10), 0);
	assert_int_equal(df1_table_file(t, 7, &type), 10);
	assert_int_equal(type, DF1_FT_N);
	v = int16_value(-7);
	assert_int_equal(df1_table_write(t, "N7:9", &v, 1), 1);
	/* grows, keeps what is there, new elements initialised; never shrinks */
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 7, 20), 0);
	assert_int_equal(df1_table_file(t, 7, NULL), 20);
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 7, 5), 0);
	assert_int_equal(df1_table_file(t, 7, NULL), 20);
	assert_int_equal(df1_table_read(t, "N7:9", &v, 1), 1);
	assert_int_equal(v.v.i16, -7);
	assert_int_equal(df1_table_read(t, "N7:19", &v, 1), 1);
	assert_int_equal(v.v.i16, 19);
	/* a file number holds one type */
	assert_int_equal(df1_table_add_file(t, DF1_FT_F, 7, 10), DF1_E_TYPE);
	assert_non_null(strstr(df1_table_error_text(t), "file 7 already holds type N"));
	/* ranges: file 0..999, elements 1..1000, a data-table type */
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 1000, 10), DF1_E_INVAL);
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, -1, 10), DF1_E_INVAL);
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 20, 0), DF1_E_INVAL);
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 20, 1001), DF1_E_INVAL);
	assert_int_equal(df1_table_add_file(t, DF1_FT_NONE, 20, 10), DF1_E_INVAL);
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 999, 1000), 0);
	assert_int_equal(df1_table_read(t, "N999:999", &v, 1), 1);
	assert_int_equal(v.v.i16, 999);
	df1_table_free(t);
}

static void test_table_provisional_default_files_give_way(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	enum df1_file_type type;

	(void)state;
	/* N9, the common interface file of PLC-2 commands, replaces ST9 */
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 9, 32), 0);
	assert_int_equal(df1_table_file(t, 9, &type), 32);
	assert_int_equal(type, DF1_FT_N);
	/* and is no longer provisional itself */
	assert_int_equal(df1_table_add_file(t, DF1_FT_F, 9, 32), DF1_E_TYPE);
	/* O0..F8 are not provisional */
	assert_int_equal(df1_table_add_file(t, DF1_FT_F, 7, 32), DF1_E_TYPE);
	df1_table_free(t);
}

/* ------------------------------------------------------------------------
 * Values
 * ------------------------------------------------------------------------ */

static void test_table_bits_run_into_the_next_word(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_MICROLOGIX);
	struct df1_value v[4], got[4];
	uint8_t b[8];

	(void)state;
	for (int i = 0; i < 4; i++) {
		v[i].kind = DF1_VAL_BIT;
		v[i].v.bit = true;
	}
	/* B3:0/14 x 4 = B3:0/14 B3:0/15 B3:1/0 B3:1/1 (B3/14 .. B3/17) */
	assert_int_equal(df1_table_write(t, "B3:0/14", v, 4), 4);
	assert_int_equal(raw_read(t, "B3:0", b, 4), 0);
	assert_int_equal(b[0], 0x00);
	assert_int_equal(b[1], 0xC0);
	assert_int_equal(b[2], 0x03);
	assert_int_equal(b[3], 0x00);
	assert_int_equal(df1_table_read(t, "B3/15", got, 3), 3);
	assert_true(got[0].v.bit && got[1].v.bit && got[2].v.bit);
	assert_int_equal(got[0].kind, DF1_VAL_BIT);
	/* L bits: 32 per element, L10:0/31 then L10:1/0 */
	assert_int_equal(df1_table_write(t, "L10:0/31", v, 2), 2);
	assert_int_equal(raw_read(t, "L10:0", b, 8), 0);
	assert_int_equal(b[3], 0x80);   /* L10:0 = 0 + bit 31 */
	assert_int_equal(b[4], 0x01 | 0x01);    /* L10:1 = 00010001h, bit 0 already set */
	/* clearing a bit leaves the others */
	v[0].v.bit = false;
	assert_int_equal(df1_table_write(t, "B3:0/15", v, 1), 1);
	assert_int_equal(raw_read(t, "B3:0", b, 2), 0);
	assert_int_equal(b[1], 0x40);
	df1_table_free(t);
}

static void test_table_sub_element_of_consecutive_elements(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v[2] = { int16_value(7), int16_value(8) }, got[3];

	(void)state;
	assert_int_equal(df1_table_write(t, "T4:1.ACC", v, 2), 2);
	assert_int_equal(df1_table_read(t, "T4:1", got, 3), 3);
	assert_int_equal(got[0].v.tcr.acc, 7);
	assert_int_equal(got[1].v.tcr.acc, 8);
	assert_int_equal(got[2].v.tcr.acc, 0);
	assert_int_equal(got[0].v.tcr.pre, 100);        /* PRE untouched */
	/* named control bit: DN is bit 13 of word 0 (doc/PROTOCOL.md 5) */
	got[0].kind = DF1_VAL_BIT;
	got[0].v.bit = true;
	assert_int_equal(df1_table_write(t, "T4:2/DN", got, 1), 1);
	assert_int_equal(df1_table_read(t, "T4:2", got, 1), 1);
	assert_int_equal(got[0].v.tcr.ctl, 1u << 13);
	df1_table_free(t);
}

static void test_table_write_checks_everything_first(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v[3] = { int16_value(-1), int16_value(-2), { .kind = DF1_VAL_FLOAT } }, got[2];

	(void)state;
	/* the third value is of another kind: nothing is stored */
	assert_int_equal(df1_table_write(t, "N7:0", v, 3), DF1_E_TYPE);
	assert_int_equal(df1_table_read(t, "N7:0", got, 2), 2);
	assert_int_equal(got[0].v.i16, 0);
	assert_int_equal(got[1].v.i16, 1);
	/* running past the end of the file: nothing is stored */
	assert_int_equal(df1_table_write(t, "N7:254", v, 3), DF1_E_ADDR_RANGE);
	assert_non_null(strstr(df1_table_error_text(t), "N7:254"));
	assert_int_equal(df1_table_read(t, "N7:254", got, 1), 1);
	assert_int_equal(got[0].v.i16, 254);
	/* a string longer than 82 characters */
	v[2].kind = DF1_VAL_STRING;
	v[2].v.str.len = 83;
	assert_int_equal(df1_table_write(t, "ST9:0", &v[2], 1), DF1_E_RANGE);
	df1_table_free(t);
}

static void test_table_read_write_errors(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v[2];

	(void)state;
	assert_int_equal(df1_table_read(t, "N20:0", v, 1), DF1_E_ADDR_RANGE);
	assert_non_null(strstr(df1_table_error_text(t), "no file 20"));
	assert_int_equal(df1_table_read(t, "N7:256", v, 1), DF1_E_ADDR_RANGE);
	assert_int_equal(df1_table_read(t, "N7:255", v, 2), DF1_E_ADDR_RANGE);
	assert_int_equal(df1_table_read(t, "F7:0", v, 1), DF1_E_TYPE);
	assert_non_null(strstr(df1_table_error_text(t), "holds type N"));
	assert_int_equal(df1_table_read(t, "N7:x", v, 1), DF1_E_ADDR_SYNTAX);
	assert_int_equal(df1_table_read(t, "$N7:0", v, 1), DF1_E_INVAL);
	assert_int_equal(df1_table_read(t, NULL, v, 1), DF1_E_INVAL);
	assert_int_equal(df1_table_read(t, "N7:0", NULL, 1), DF1_E_INVAL);
	assert_int_equal(df1_table_read(t, "N7:0", v, 0), 0);
	df1_table_free(t);
}

static void test_table_clone_is_independent(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC), *c = NULL;
	struct df1_value v = int16_value(1234);

	(void)state;
	assert_int_equal(df1_table_set_mode(t, 1), 0);
	assert_int_equal(df1_table_clone(&c, t), 0);
	assert_int_equal(df1_table_mode(c), 1);
	assert_int_equal(df1_table_write(c, "N7:0", &v, 1), 1);
	assert_int_equal(df1_table_read(t, "N7:0", &v, 1), 1);
	assert_int_equal(v.v.i16, 0);
	assert_int_equal(df1_table_read(c, "N7:0", &v, 1), 1);
	assert_int_equal(v.v.i16, 1234);
	df1_table_free(c);
	assert_int_equal(df1_table_clone(NULL, t), DF1_E_INVAL);
	assert_int_equal(df1_table_clone(&c, NULL), DF1_E_INVAL);
	assert_null(c);
	df1_table_free(t);
}

/* ------------------------------------------------------------------------
 * Serving: the data-table contract and commands through the responder
 * ------------------------------------------------------------------------ */

static void test_table_ops_ext_sts_codes(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	const struct df1_server_ops *ops = df1_table_server_ops(t);
	struct df1_addr a = { .type = DF1_FT_N, .file = 7, .element = 0, .sub = DF1_ADDR_NONE,
	                      .bit = DF1_ADDR_NONE };
	uint8_t b[600];

	(void)state;
	assert_non_null(ops->read);
	assert_non_null(ops->write);
	assert_non_null(ops->diag_status);
	assert_non_null(ops->change_mode);
	assert_int_equal(ops->read(t, 1, &a, b, 0), 0);                 /* a probe */
	a.file = 20;
	assert_int_equal(ops->read(t, 1, &a, b, 2), 0x06);              /* no such file */
	a.file = 7;
	a.type = DF1_FT_F;
	assert_int_equal(ops->read(t, 1, &a, b, 0), 0x11);              /* another type */
	a.type = DF1_FT_NONE;
	assert_int_equal(ops->read(t, 1, &a, b, 2), 0);                 /* type unknown: any */
	a.type = DF1_FT_N;
	a.element = 256;
	assert_int_equal(ops->read(t, 1, &a, b, 2), 0x07);              /* beyond the file */
	a.element = 250;
	assert_int_equal(ops->read(t, 1, &a, b, 14), 0x0A);             /* runs past it */
	assert_int_equal(ops->read(t, 1, &a, b, 12), 0);
	assert_int_equal(ops->write(t, 1, &a, b, NULL, 14), 0x0A);
	df1_table_free(t);
}

static void test_table_ops_masked_write_rule(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	const struct df1_server_ops *ops = df1_table_server_ops(t);
	struct df1_addr a = { .type = DF1_FT_N, .file = 7, .element = 2, .sub = DF1_ADDR_NONE,
	                      .bit = DF1_ADDR_NONE };
	const uint8_t data[2] = { 0x00, 0x00 }, mask[2] = { 0xFF, 0xFC };
	struct df1_value v = int16_value(-1);
	uint8_t b[2];

	(void)state;
	/* doc/PROTOCOL.md 4.6: the masked bits take the data's, the others stay (FFFF, mask FCFF, data 0 -> 0300) */
	assert_int_equal(df1_table_write(t, "N7:2", &v, 1), 1);
	assert_int_equal(ops->write(t, 1, &a, data, mask, 2), 0);
	assert_int_equal(ops->read(t, 1, &a, b, 2), 0);
	assert_int_equal(b[0], 0x00);
	assert_int_equal(b[1], 0x03);
	df1_table_free(t);
}

static struct df1 handle;

static size_t hex(const char *s, uint8_t *out, size_t cap)
{
	size_t n = 0;
	unsigned v;

	while (*s) {
		if (*s == ' ') {
			s++;
			continue;
		}
		assert_int_equal(sscanf(s, "%2x", &v), 1);
		assert_true(n < cap);
		out[n++] = (uint8_t)v;
		s += 2;
	}
	return n;
}

/* A command through the responder with the table's callbacks; the reply must be reply_hex. */
static void expect_reply(struct df1_table *t, const char *cmd_hex, const char *reply_hex)
{
	struct server_ctx ctx = { df1_table_server_ops(t), t };
	uint8_t cmd[300], want[300], got[300];
	size_t n = hex(cmd_hex, cmd, sizeof cmd), wn = hex(reply_hex, want, sizeof want);
	int r = server_handle(&handle, &ctx, cmd, n, got, sizeof got);

	assert_int_equal(r, (int)wn);
	assert_memory_equal(got, want, wn);
}

static void test_table_served_slc_spec_vectors(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v = { .kind = DF1_VAL_FLOAT }, got[2];

	(void)state;
	memset(&handle, 0, sizeof handle);
	handle.cfg.plc = DF1_PLC_SLC;
	/* derived-slc-A2-read-F8:0 -> derived-slc-reply-F8:0=1.5 */
	v.v.f = 1.5f;
	assert_int_equal(df1_table_write(t, "F8:0", &v, 1), 1);
	expect_reply(t, "01 00 0F 00 04 00 A2 04 08 8A 00 00", "00 01 4F 00 04 00 00 00 C0 3F");
	/* derived-slc-AA-write-N7:5 = 1234h */
	expect_reply(t, "01 00 0F 00 02 00 AA 02 07 89 05 00 34 12", "00 01 4F 00 02 00");
	assert_int_equal(df1_table_read(t, "N7:4", got, 2), 2);
	assert_int_equal(got[0].v.i16, 4);
	assert_int_equal(got[1].v.i16, 0x1234);
	/* derived-slc-AB-B3:0/5-set */
	expect_reply(t, "01 00 0F 00 03 00 AB 02 03 85 00 00 20 00 20 00", "00 01 4F 00 03 00");
	assert_int_equal(df1_table_read(t, "B3:0/5", got, 1), 1);
	assert_true(got[0].v.bit);
	/* no such file: STS F0, EXT STS 06 */
	expect_reply(t, "01 00 0F 00 05 00 A2 02 14 89 00 00", "00 01 4F F0 05 00 06");
	df1_table_free(t);
}

static void test_table_served_plc5_and_plc2_vectors(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_PLC5);
	struct df1_value got[4];

	(void)state;
	memset(&handle, 0, sizeof handle);
	handle.cfg.plc = DF1_PLC_PLC5;
	/* derived-plc5-68-typed-read-N7:0x10 -> derived-plc5-68-reply-0..9: the
	 * initial N7:n = n of df1sim(1) is the spec's reply */
	expect_reply(t, "01 00 0F 00 06 00 68 00 00 0A 00 06 07 00 0A 00",
	             "00 01 4F 00 06 00 99 09 15 42 00 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 09 00");
	/* derived-plc5-68-typed-read-ascii: $N7:0 x1 */
	expect_reply(t, "01 00 0F 00 07 00 68 00 00 01 00 00 24 4E 37 3A 30 00 01 00",
	             "00 01 4F 00 07 00 99 09 03 42 00 00");
	/* PLC-2 commands without the compatibility file N9: STS 80 (M p.119) */
	expect_reply(t, "29 20 01 00 45 01 28 00 08", "20 29 41 80 45 01");
	/* with N9 (replacing the provisional ST9): KE-plc2-write-cmd / reply, byte
	 * address 28h = N9:20, then KE-plc2-read-cmd / reply */
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 9, 32), 0);
	expect_reply(t, "29 20 08 00 44 01 28 00 22 11 44 33 66 55 88 77", "20 29 48 00 44 01");
	assert_int_equal(df1_table_read(t, "N9:20", got, 4), 4);
	assert_int_equal((uint16_t)got[0].v.i16, 0x1122);
	assert_int_equal((uint16_t)got[3].v.i16, 0x7788);
	expect_reply(t, "29 20 01 00 45 01 28 00 08", "20 29 41 00 45 01 22 11 44 33 66 55 88 77");
	/* 05 unprotected bit write: byte 29h (high byte of N9:20): set 80, reset 01 */
	expect_reply(t, "29 20 05 00 46 01 29 00 80 01", "20 29 45 00 46 01");
	assert_int_equal(df1_table_read(t, "N9:20", got, 1), 1);
	assert_int_equal((uint16_t)got[0].v.i16, 0x9022);
	df1_table_free(t);
}

/* ------------------------------------------------------------------------
 * Diagnostic status and mode
 * ------------------------------------------------------------------------ */

static void test_table_diag_status_slc_ee_form(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	const struct df1_server_ops *ops = df1_table_server_ops(t);
	struct df1_diag_status d;
	uint8_t b[64];
	int n;

	(void)state;
	n = ops->diag_status(t, 3, b, sizeof b);
	/* M p.174: 24 bytes, byte 2 EE, byte 3 interface 1F, byte 4 type (5Bh SLC 5/04),
	 * bytes 6-16 bulletin, byte 19 mode (6 run), byte 24 owner 3F */
	assert_int_equal(n, 24);
	assert_int_equal(b[1], 0xEE);
	assert_int_equal(b[2], 0x1F);
	assert_int_equal(b[3], 0x5B);
	assert_memory_equal(b + 5, "5/04       ", 11);
	assert_int_equal(b[18] & 0x1F, 6);
	assert_int_equal(b[23], 0x3F);
	assert_int_equal(pccc_dec_diag_status(b, (size_t)n, &d), 0);
	assert_string_equal(d.name, "SLC 5/04");
	assert_string_equal(d.mode_text, "run");
	assert_string_equal(d.bulletin, "5/04");
	/* 0F/80 to program (1): the status says so */
	assert_int_equal(ops->change_mode(t, 3, 1), 0);
	assert_int_equal(df1_table_mode(t), 1);
	n = ops->diag_status(t, 3, b, sizeof b);
	assert_int_equal(b[18] & 0x1F, 1);
	assert_int_equal(ops->change_mode(t, 3, 5), 0x01);      /* illegal field value */
	assert_int_equal(df1_table_mode(t), 1);
	assert_int_equal(ops->diag_status(t, 3, b, 10), -0x10);
	/* other processors by name */
	assert_int_equal(df1_table_set_processor(t, "SLC 5/01"), 0);
	assert_int_equal(ops->diag_status(t, 3, b, sizeof b), 24);
	assert_int_equal(b[3], 0x18);
	assert_memory_equal(b + 5, "5/01", 4);
	assert_int_equal(df1_table_set_processor(t, "slc500"), 0);
	ops->diag_status(t, 3, b, sizeof b);
	assert_int_equal(b[3], 0x1A);
	assert_memory_equal(b + 5, "500 - 20   ", 11);
	assert_int_equal(df1_table_set_processor(t, "0x42"), 0);
	ops->diag_status(t, 3, b, sizeof b);
	assert_int_equal(b[1], 0xEE);
	assert_int_equal(b[3], 0x42);
	assert_int_equal(df1_table_set_processor(t, "slc9/99"), DF1_E_INVAL);
	assert_non_null(strstr(df1_table_error_text(t), "slc9/99"));
	assert_int_equal(df1_table_set_processor(t, "256"), DF1_E_INVAL);
	df1_table_free(t);
}

static void test_table_diag_status_micrologix(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_MICROLOGIX);
	uint8_t b[64];

	(void)state;
	/* default MicroLogix 1400 (9Fh, doc/PROTOCOL.md 4.9 AHMI list); interface type 34 (M p.177) */
	assert_int_equal(df1_table_server_ops(t)->diag_status(t, 1, b, sizeof b), 24);
	assert_int_equal(b[2], 0x34);
	assert_int_equal(b[3], 0x9F);
	assert_int_equal(df1_table_set_processor(t, "MicroLogix 1000"), 0);
	df1_table_server_ops(t)->diag_status(t, 1, b, sizeof b);
	assert_int_equal(b[3], 0x58);
	df1_table_free(t);
}

static void test_table_diag_status_plc5_eb_form(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_PLC5);
	const struct df1_server_ops *ops = df1_table_server_ops(t);
	struct df1_diag_status d;
	uint8_t b[64];
	int n;

	(void)state;
	/* M p.192-193: byte 1 mode (6 remote run), byte 2 EB, byte 3 type (15h PLC-5/40),
	 * byte 9 DH+ node, bytes 12-13 data table files */
	n = ops->diag_status(t, 9, b, sizeof b);
	assert_int_equal(n, 18);
	assert_int_equal(b[0] & 0x07, 6);
	assert_int_equal(b[1], 0xEB);
	assert_int_equal(b[2], 0x15);
	assert_int_equal(b[8], 9);
	assert_int_equal(b[11] | (b[12] << 8), 12);
	assert_int_equal(pccc_dec_diag_status(b, (size_t)n, &d), 0);
	assert_string_equal(d.name, "PLC-5/40");
	assert_string_equal(d.mode_text, "remote run");
	assert_int_equal(df1_table_set_mode(t, 1), 0);
	ops->diag_status(t, 9, b, sizeof b);
	assert_int_equal(b[0] & 0x07, 4);                       /* remote program */
	assert_int_equal(df1_table_set_mode(t, 7), 0);
	ops->diag_status(t, 9, b, sizeof b);
	assert_int_equal(b[0] & 0x07, 5);                       /* remote test */
	assert_int_equal(df1_table_set_mode(t, 2), DF1_E_INVAL);
	/* a type code in a PLC-5 table answers in the EB form */
	assert_int_equal(df1_table_set_processor(t, "0x33"), 0);
	assert_int_equal(ops->diag_status(t, 9, b, sizeof b), 18);
	assert_int_equal(b[1], 0xEB);
	assert_int_equal(b[2], 0x33);
	assert_int_equal(df1_table_set_processor(t, "plc5/80e"), 0);
	ops->diag_status(t, 9, b, sizeof b);
	assert_int_equal(b[2], 0x59);
	df1_table_free(t);
}

static void test_table_diag_encoder_round_trips(void **state)
{
	struct pccc_diag_info info = { .plc5 = false, .type_code = 0x78, .interface_type = 0x1F,
	                               .series_rev = (uint8_t)((1u << 5) | 3u), .bulletin = "5/05",
	                               .mode = 8, .ram_kb = 0x10, .owner = 0x3F };
	struct df1_diag_status d;
	uint8_t b[24];

	(void)state;
	assert_int_equal(pccc_enc_diag_reply(b, sizeof b, &info), 24);
	assert_int_equal(pccc_dec_diag_status(b, sizeof b, &d), 0);
	assert_int_equal(d.type_code, 0x78);
	assert_string_equal(d.name, "SLC 5/05");
	assert_int_equal(d.series, 'B');
	assert_int_equal(d.revision, 4);                        /* 0 = release 1 */
	assert_int_equal(d.mode, 8);
	assert_string_equal(d.mode_text, "test single scan");
	assert_int_equal(pccc_enc_diag_reply(b, 23, &info), DF1_E_NOSPACE);
	info.plc5 = true;
	assert_int_equal(pccc_enc_diag_reply(b, 17, &info), DF1_E_NOSPACE);
	assert_int_equal(pccc_enc_diag_reply(NULL, 24, &info), DF1_E_INVAL);
}

/* ------------------------------------------------------------------------
 * Load and save
 * ------------------------------------------------------------------------ */

static void test_table_load_data_file(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v[4];
	enum df1_file_type type;
	char path[512];

	(void)state;
	snprintf(path, sizeof path, "%s/data.txt", tmpdir);
	write_file(path,
	           "# a comment\n"
	           "\n"
	           "N7:0 = 10, 11 ,12   # three values\n"
	           "B3:0/15=1,1\n"
	           "T4:0=PRE=500 ACC=7 EN=1\n"
	           "T4:1.ACC=42\n"
	           "ST9:0=\"a, #b\",\"q\\\"\\\\\"\n"
	           "ST9:2=\"\\x41\\x42\"\n"
	           "F8:0=-1.25,inf\n"
	           "N20:300=5\n");
	assert_int_equal(df1_table_load(t, path), 0);
	assert_int_equal(df1_table_read(t, "N7:0", v, 4), 4);
	assert_int_equal(v[0].v.i16, 10);
	assert_int_equal(v[1].v.i16, 11);
	assert_int_equal(v[2].v.i16, 12);
	assert_int_equal(v[3].v.i16, 3);
	assert_int_equal(df1_table_read(t, "B3:0/15", v, 2), 2);
	assert_true(v[0].v.bit && v[1].v.bit);
	assert_int_equal(df1_table_read(t, "T4:0", v, 2), 2);
	assert_int_equal(v[0].v.tcr.pre, 500);
	assert_int_equal(v[0].v.tcr.acc, 7);
	assert_int_equal(v[0].v.tcr.ctl, 0x8000);
	assert_int_equal(v[1].v.tcr.acc, 42);
	assert_int_equal(df1_table_read(t, "ST9:0", v, 3), 3);
	assert_string_equal(v[0].v.str.text, "a, #b");
	assert_string_equal(v[1].v.str.text, "q\"\\");
	assert_string_equal(v[2].v.str.text, "AB");
	assert_int_equal(df1_table_read(t, "F8:0", v, 2), 2);
	assert_true(v[0].v.f == -1.25f);
	assert_true(isinf(v[1].v.f));
	/* N20: created with 256 elements, grown to hold element 300 */
	assert_int_equal(df1_table_file(t, 20, &type), 301);
	assert_int_equal(type, DF1_FT_N);
	assert_int_equal(df1_table_read(t, "N20:300", v, 1), 1);
	assert_int_equal(v[0].v.i16, 5);
	assert_int_equal(df1_table_read(t, "N20:299", v, 1), 1);
	assert_int_equal(v[0].v.i16, 299);
	/* a line for N9 replaces the provisional ST9 */
	write_file(path, "N9:0=77\n");
	assert_int_equal(df1_table_load(t, path), 0);
	assert_int_equal(df1_table_file(t, 9, &type), 256);
	assert_int_equal(type, DF1_FT_N);
	df1_table_free(t);
}

/* A UTF-8 byte order mark at the start of the file is skipped, as the CSV
 * loaders skip it (df1sim(1) DATA TABLE); anywhere else it is text. A NUL byte
 * is refused, as the CSV loaders refuse it. */
static void test_table_load_skips_utf8_bom(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v[2];
	char path[512], want[768];

	(void)state;
	snprintf(path, sizeof path, "%s/bom.txt", tmpdir);
	write_file(path, "\xEF\xBB\xBFN7:0=41,42\n");
	assert_int_equal(df1_table_load(t, path), 0);
	assert_int_equal(df1_table_read(t, "N7:0", v, 2), 2);
	assert_int_equal(v[0].v.i16, 41);
	assert_int_equal(v[1].v.i16, 42);
	/* a mark before a comment line, then data */
	write_file(path, "\xEF\xBB\xBF# saved by an editor\nN7:1=7\n");
	assert_int_equal(df1_table_load(t, path), 0);
	assert_int_equal(df1_table_read(t, "N7:1", v, 1), 1);
	assert_int_equal(v[0].v.i16, 7);
	/* a NUL byte would cut the line ("N7:0=5\0junk" read as N7:0=5): an error
	 * naming the line, nothing stored */
	{
		static const char nul[] = "N7:0=9\nN7:1=5\0junk\n";
		FILE *f = fopen(path, "wb");

		assert_non_null(f);
		assert_int_equal(fwrite(nul, 1, sizeof nul - 1, f), sizeof nul - 1);
		assert_int_equal(fclose(f), 0);
		assert_int_equal(df1_table_load(t, path), DF1_E_CONFIG);
		snprintf(want, sizeof want, "%s:2: a NUL byte in the line", path);
		assert_string_equal(df1_table_error_text(t), want);
		assert_int_equal(df1_table_read(t, "N7:0", v, 1), 1);
		assert_int_equal(v[0].v.i16, 41);
	}
	/* only the first line's: on line 2 it is part of the address */
	write_file(path, "N7:0=1\n\xEF\xBB\xBFN7:1=2\n");
	assert_int_equal(df1_table_load(t, path), DF1_E_CONFIG);
	snprintf(want, sizeof want, "%s:2: ", path);
	assert_memory_equal(df1_table_error_text(t), want, strlen(want));
	df1_table_free(t);
}

static void test_table_load_errors_name_file_and_line(void **state)
{
	static const struct {
		const char *text;
		const char *want;       /* after "PATH:" */
	} cases[] = {
		{ "N7:0=1\nnonsense\n", "2: expected ADDRESS=VALUE[,VALUE...]" },
		{ "N7:x=1\n", "1: N7:x: invalid address syntax" },
		{ "\n\nN7:0=70000\n", "3: N7:0: '70000': value out of range" },
		{ "F7:0=1.5\n", "1: F7:0: file 7 already holds type N" },
		{ "ST9:0=\"open\n", "1: ST9:0: unterminated quote" },
		{ "N7:999=1,2\n", "1: N7:999: value 2 lands beyond element 999" },
		{ "T4:0.ACC=1\nN7:0=abc\n", "2: N7:0: 'abc': value does not fit the file type" },
		{ "$N7:0=1\n", "1: $N7:0: not a data-table address" },
	};
	struct df1_table *t = default_table(DF1_PLC_SLC);
	struct df1_value v;
	char path[512], want[768];

	(void)state;
	snprintf(path, sizeof path, "%s/bad.txt", tmpdir);
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		write_file(path, cases[i].text);
		assert_int_equal(df1_table_load(t, path), DF1_E_CONFIG);
		snprintf(want, sizeof want, "%s:%s", path, cases[i].want);
		assert_string_equal(df1_table_error_text(t), want);
	}
	/* all or nothing: N7:0 of the first case's good line is not stored */
	assert_int_equal(df1_table_read(t, "N7:0", &v, 1), 1);
	assert_int_equal(v.v.i16, 0);
	assert_int_equal(df1_table_read(t, "T4:0.ACC", &v, 1), 1);
	assert_int_equal(v.v.i16, 0);
	/* a file that cannot be opened */
	snprintf(path, sizeof path, "%s/none.txt", tmpdir);
	assert_int_equal(df1_table_load(t, path), DF1_E_SYS);
	snprintf(want, sizeof want, "%s: %s", path, strerror(ENOENT));
	assert_string_equal(df1_table_error_text(t), want);
	df1_table_free(t);
}

static void test_table_save_load_round_trip(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_MICROLOGIX), *u = NULL;
	struct df1_value v[4];
	uint8_t a[84 * 256], b[84 * 256];
	char path[512];

	(void)state;
	/* contents the text format must carry exactly */
	v[0].kind = DF1_VAL_STRING;
	snprintf(v[0].v.str.text, sizeof v[0].v.str.text, "x, \"y\" #z \\");
	v[0].v.str.len = (uint16_t)strlen(v[0].v.str.text);
	v[1] = v[0];
	memcpy(v[1].v.str.text, "a\0b\n\x7F\xFF", 7);
	v[1].v.str.len = 6;
	assert_int_equal(df1_table_write(t, "ST9:0", v, 2), 2);
	v[0].kind = v[1].kind = v[2].kind = DF1_VAL_FLOAT;
	v[0].v.f = 0.1f;
	v[1].v.f = -INFINITY;
	v[2].v.f = 1e-45f;
	assert_int_equal(df1_table_write(t, "F8:10", v, 3), 3);
	v[0] = int16_value(-32768);
	assert_int_equal(df1_table_write(t, "N7:3", v, 1), 1);
	v[0].kind = DF1_VAL_TCR;
	v[0].v.tcr.ctl = 0xA5A5;        /* named and unnamed control bits */
	v[0].v.tcr.pre = -5;
	v[0].v.tcr.acc = 32767;
	assert_int_equal(df1_table_write(t, "R6:4", v, 1), 1);
	assert_int_equal(df1_table_write(t, "C5:4", v, 1), 1);
	v[0].kind = DF1_VAL_INT32;
	v[0].v.i32 = INT32_MIN;
	assert_int_equal(df1_table_write(t, "L10:0", v, 1), 1);
	assert_int_equal(df1_table_add_file(t, DF1_FT_A, 40, 300), 0);

	snprintf(path, sizeof path, "%s/saved.txt", tmpdir);
	assert_int_equal(df1_table_save(t, path), 0);
	assert_int_equal(df1_table_new(&u, DF1_PLC_MICROLOGIX), 0);
	assert_int_equal(df1_table_add_default_files(u), 0);
	assert_int_equal(df1_table_load(u, path), 0);
	for (int f = 0; f < DF1_TABLE_FILES_MAX; f++) {
		enum df1_file_type ta, tb;
		int na = df1_table_file(t, f, &ta), nb = df1_table_file(u, f, &tb);
		struct df1_addr ad = { .file = f, .element = 0, .sub = DF1_ADDR_NONE, .bit = DF1_ADDR_NONE };

		assert_int_equal(na, nb);
		if (na < 0)
			continue;
		assert_int_equal(ta, tb);
		ad.type = ta;
		assert_int_equal(df1_table_server_ops(t)->read(t, 1, &ad, a, (size_t)na * (size_t)df1_file_type_element_size(ta)), 0);
		assert_int_equal(df1_table_server_ops(u)->read(u, 1, &ad, b, (size_t)na * (size_t)df1_file_type_element_size(ta)), 0);
		if (ta == DF1_FT_ST) {
			/* the characters up to LEN are the string; the rest is not kept */
			for (int e = 0; e < na; e++) {
				struct df1_value x, y;
				struct df1_addr ae = ad;

				ae.element = e;
				assert_int_equal(df1_table_read_addr(t, &ae, &x, 1), 1);
				assert_int_equal(df1_table_read_addr(u, &ae, &y, 1), 1);
				assert_int_equal(x.v.str.len, y.v.str.len);
				assert_memory_equal(x.v.str.text, y.v.str.text, x.v.str.len);
			}
		} else {
			assert_memory_equal(a, b, (size_t)na * (size_t)df1_file_type_element_size(ta));
		}
	}
	df1_table_free(u);
	df1_table_free(t);
}

static void test_table_save_is_atomic_and_leaves_no_temporary(void **state)
{
	struct df1_table *t = default_table(DF1_PLC_SLC);
	char path[512], line[128];
	struct dirent *e;
	FILE *f;
	DIR *d;
	int n = 0;

	(void)state;
	snprintf(path, sizeof path, "%s/atomic.txt", tmpdir);
	write_file(path, "old contents\n");
	assert_int_equal(df1_table_save(t, path), 0);
	f = fopen(path, "r");
	assert_non_null(f);
	assert_non_null(fgets(line, sizeof line, f));
	fclose(f);
	assert_true(line[0] == '#');
	/* the directory holds the saved files and nothing else */
	d = opendir(tmpdir);
	assert_non_null(d);
	while ((e = readdir(d)) != NULL)
		if (strstr(e->d_name, ".tmp"))
			n++;
	closedir(d);
	assert_int_equal(n, 0);
	/* a directory that does not exist: an error naming the path, nothing written */
	snprintf(path, sizeof path, "%s/no/such/dir/x.txt", tmpdir);
	assert_int_equal(df1_table_save(t, path), DF1_E_SYS);
	assert_non_null(strstr(df1_table_error_text(t), path));
	/* the target is a directory: rename fails, the temporary is removed */
	snprintf(path, sizeof path, "%s/adir", tmpdir);
	assert_int_equal(mkdir(path, 0755), 0);
	assert_int_equal(df1_table_save(t, path), DF1_E_SYS);
	rmdir(path);
	d = opendir(tmpdir);
	n = 0;
	while ((e = readdir(d)) != NULL)
		if (strstr(e->d_name, ".tmp"))
			n++;
	closedir(d);
	assert_int_equal(n, 0);
	df1_table_free(t);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_table_new_invalid_arguments),
		cmocka_unit_test(test_table_new_is_empty_in_run_mode),
		cmocka_unit_test(test_table_default_files_shape),
		cmocka_unit_test(test_table_initial_contents_as_documented),
		cmocka_unit_test(test_table_wire_layout_spec_5),
		cmocka_unit_test(test_table_add_file_grows_and_refuses_other_type),
		cmocka_unit_test(test_table_provisional_default_files_give_way),
		cmocka_unit_test(test_table_bits_run_into_the_next_word),
		cmocka_unit_test(test_table_sub_element_of_consecutive_elements),
		cmocka_unit_test(test_table_write_checks_everything_first),
		cmocka_unit_test(test_table_read_write_errors),
		cmocka_unit_test(test_table_clone_is_independent),
		cmocka_unit_test(test_table_ops_ext_sts_codes),
		cmocka_unit_test(test_table_ops_masked_write_rule),
		cmocka_unit_test(test_table_served_slc_spec_vectors),
		cmocka_unit_test(test_table_served_plc5_and_plc2_vectors),
		cmocka_unit_test(test_table_diag_status_slc_ee_form),
		cmocka_unit_test(test_table_diag_status_micrologix),
		cmocka_unit_test(test_table_diag_status_plc5_eb_form),
		cmocka_unit_test(test_table_diag_encoder_round_trips),
		cmocka_unit_test(test_table_load_data_file),
		cmocka_unit_test(test_table_load_skips_utf8_bom),
		cmocka_unit_test(test_table_load_errors_name_file_and_line),
		cmocka_unit_test(test_table_save_load_round_trip),
		cmocka_unit_test(test_table_save_is_atomic_and_leaves_no_temporary),
	};

	return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
