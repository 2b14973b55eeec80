/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_server - the responder's command handling (lib/server/server_*.c): command app
 * bytes from tests/data/vectors.txt (derived SLC/PLC-5 vectors, KE PLC-2 and word
 * range vectors) go through server_handle() with a small in-test data table;
 * replies are checked byte for byte where the spec has them, and the data
 * table's contents after writes.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1_int.h"
#include "proto/pccc.h"
#include "server/server.h"
#include "proto/value.h"

/* ------------------------------------------------------------------------
 * The in-test data table, following the contract of server.h
 * ------------------------------------------------------------------------ */

struct tfile {
	enum df1_file_type type;
	int nelem;
	uint8_t bytes[2048];
};

struct table {
	struct tfile *files[32];
	int reads, writes, probes;
	int last_station;
	int last_source;          /* df1_server_source() inside the write */
	int mode;
	int diag_calls;
	bool fail_read_with_neg;  /* read returns -0x20 (STS 20) */
};

static struct tfile files[32];
static struct table tbl;
static struct df1 handle;

static void tfile_init(int file, enum df1_file_type t, int nelem)
{
	struct tfile *f = &files[file];
	int es = df1_file_type_element_size(t);

	memset(f, 0, sizeof *f);
	f->type = t;
	f->nelem = nelem;
	assert_true((size_t)(es * nelem) <= sizeof f->bytes);
	tbl.files[file] = f;
}

static uint8_t *elem_ptr(int file, int elem)
{
	struct tfile *f = tbl.files[file];

	return f->bytes + (size_t)elem * (size_t)df1_file_type_element_size(f->type);
}

static int locate(const struct df1_addr *a, size_t nbytes, uint8_t **p)
{
	struct tfile *f;
	size_t es, off, size;

	if (a->file < 0 || a->file >= 32 || !tbl.files[a->file])
		return 0x06;
	f = tbl.files[a->file];
	if (a->type != DF1_FT_NONE && a->type != f->type)
		return 0x11;
	assert_int_equal(a->bit, DF1_ADDR_NONE);
	assert_string_equal(a->ascii, "");
	es = (size_t)df1_file_type_element_size(f->type);
	size = es * (size_t)f->nelem;
	if (a->element < 0 || a->element >= f->nelem)
		return 0x07;
	off = (size_t)a->element * es + (a->sub == DF1_ADDR_NONE ? 0 : (size_t)a->sub * 2);
	if (off + nbytes > size)
		return 0x0A;
	*p = f->bytes + off;
	return 0;
}

static int t_read(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes)
{
	struct table *t = user;
	uint8_t *p = NULL;
	int rc;

	t->last_station = station;
	if (nbytes == 0)
		t->probes++;
	else
		t->reads++;
	if (t->fail_read_with_neg && nbytes)
		return -0x20;
	rc = locate(a, nbytes, &p);
	if (rc)
		return rc;
	memcpy(buf, p, nbytes);
	return 0;
}

static int t_write(void *user, int station, const struct df1_addr *a, const uint8_t *buf,
                   const uint8_t *mask, size_t nbytes)
{
	struct table *t = user;
	uint8_t *p = NULL;
	int rc;

	t->last_station = station;
	t->last_source = df1_server_source(&handle);
	t->writes++;
	rc = locate(a, nbytes, &p);
	if (rc)
		return rc;
	for (size_t i = 0; i < nbytes; i++)
		p[i] = mask ? (uint8_t)((p[i] & ~mask[i]) | (buf[i] & mask[i])) : buf[i];
	return 0;
}

static int t_change_mode(void *user, int station, int mode)
{
	struct table *t = user;

	(void)station;
	if (mode != 1 && mode != 6)
		return 0x01;
	t->mode = mode;
	return 0;
}

static int t_command(void *user, int station, const struct df1_msg *cmd, uint8_t *reply, size_t cap)
{
	(void)user;
	(void)station;
	assert_true(cap >= 2);
	if (cmd->cmd == 0x06 && cmd->fnc == 0x01) {     /* diagnostic read: answer 2 bytes */
		reply[0] = 0xAB;
		reply[1] = 0xCD;
		return 2;
	}
	return -0x10;
}

static const struct df1_server_ops ops = {
	.read = t_read,
	.write = t_write,
	.change_mode = t_change_mode,
	.command = t_command,
};
static struct server_ctx ctx = { &ops, &tbl };

static int setup(void **state)
{
	(void)state;
	memset(&tbl, 0, sizeof tbl);
	memset(&handle, 0, sizeof handle);
	handle.cfg.plc = DF1_PLC_SLC;
	tfile_init(3, DF1_FT_B, 8);
	tfile_init(4, DF1_FT_T, 4);
	tfile_init(7, DF1_FT_N, 40);
	tfile_init(8, DF1_FT_F, 8);
	tfile_init(9, DF1_FT_N, 32);
	tfile_init(10, DF1_FT_N, 200);
	tfile_init(11, DF1_FT_ST, 3);
	tfile_init(12, DF1_FT_L, 4);
	for (int i = 0; i < 40; i++)
		put_le16(elem_ptr(7, i), (uint16_t)i);
	for (int i = 0; i < 8; i++)
		value_put_float(elem_ptr(8, i), 1.5f + (float)i, VALUE_FLOAT_LE);
	for (int i = 0; i < 4; i++) {
		put_le16(elem_ptr(4, i) + 2, 100);
		put_le16(elem_ptr(4, i) + 4, (uint16_t)(10 + i));
	}
	value_put_string(elem_ptr(11, 0), "STRING 0");
	put_le32(elem_ptr(12, 1), 0x00010001u);
	return 0;
}

/* ------------------------------------------------------------------------
 * Helpers
 * ------------------------------------------------------------------------ */

static size_t hex(const char *s, uint8_t *out, size_t cap)
{
	size_t n = 0;

	while (*s) {
		unsigned v;

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

static int run(const char *cmd_hex, uint8_t *reply, size_t cap)
{
	uint8_t cmd[300];
	size_t n = hex(cmd_hex, cmd, sizeof cmd);

	return server_handle(&handle, &ctx, cmd, n, reply, cap);
}

static void expect_reply(const char *cmd_hex, const char *reply_hex)
{
	uint8_t want[300], got[300];
	size_t wn = hex(reply_hex, want, sizeof want);
	int n = run(cmd_hex, got, sizeof got);

	if (n != (int)wn || memcmp(got, want, wn) != 0) {
		fprintf(stderr, "command: %s\nwant:    %s\ngot:    ", cmd_hex, reply_hex);
		for (int i = 0; i < n; i++)
			fprintf(stderr, " %02X", got[i]);
		fprintf(stderr, " (%d)\n", n);
	}
	assert_int_equal(n, (int)wn);
	assert_memory_equal(got, want, wn);
}

/* The STS (and EXT STS) of the reply to a command. */
static void expect_status(const char *cmd_hex, uint8_t sts, int ext)
{
	uint8_t got[300];
	int n = run(cmd_hex, got, sizeof got);

	assert_true(n >= 6);
	assert_int_equal(got[3], sts);
	if (ext >= 0) {
		assert_true(n >= 7);
		assert_int_equal(got[6], ext);
		assert_int_equal(n, 7);
	} else {
		assert_int_equal(n, 6);
	}
}

static uint16_t word(int file, int elem)
{
	return le16(elem_ptr(file, elem));
}

/* ------------------------------------------------------------------------
 * SLC 0F/A1 A2 A9 AA AB
 * ------------------------------------------------------------------------ */

static void test_server_slc_read_float_gives_spec_reply(void **state)
{
	(void)state;
	/* derived-slc-A2-read-F8:0 -> derived-slc-reply-F8:0=1.5 */
	expect_reply("01 00 0F 00 04 00 A2 04 08 8A 00 00", "00 01 4F 00 04 00 00 00 C0 3F");
	assert_int_equal(tbl.last_station, 1);
}

static void test_server_slc_read_20_bytes_gives_words(void **state)
{
	(void)state;
	/* derived-slc-A2-read-N7:0-20B */
	expect_reply("01 00 0F 00 01 00 A2 14 07 89 00 00",
	             "00 01 4F 00 01 00 00 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 09 00");
	/* two address fields (A1), element 5 */
	expect_reply("01 00 0F 00 02 00 A1 04 07 89 05", "00 01 4F 00 02 00 05 00 06 00");
	/* sub-element: T4:1.ACC (word 2) */
	expect_reply("01 00 0F 00 03 00 A2 02 04 86 01 02", "00 01 4F 00 03 00 0B 00");
	/* element above 254 uses the FF escape: out of this file -> EXT 07 */
	expect_status("01 00 0F 00 04 00 A2 02 07 89 FF 2C 01 00", 0xF0, 0x07);
}

static void test_server_slc_write_sets_word(void **state)
{
	(void)state;
	/* derived-slc-AA-write-N7:5 */
	expect_reply("01 00 0F 00 02 00 AA 02 07 89 05 00 34 12", "00 01 4F 00 02 00");
	assert_int_equal(word(7, 5), 0x1234);
	assert_int_equal(word(7, 4), 4);
	assert_int_equal(word(7, 6), 6);
	/* A9: two fields, N7:6..7 */
	expect_reply("01 00 0F 00 03 00 A9 04 07 89 06 11 11 22 22", "00 01 4F 00 03 00");
	assert_int_equal(word(7, 6), 0x1111);
	assert_int_equal(word(7, 7), 0x2222);
}

/* df1_server_source(): inside a callback the command's SRC (the PLC whose MSG
 * writes), not its DST; -1 outside one and on a handle without responder state. */
static void test_server_source_is_the_commands_src(void **state)
{
	(void)state;
	assert_int_equal(df1_server_source(NULL), -1);
	assert_int_equal(df1_server_source(&handle), -1);
	assert_non_null(server_responder(&handle));
	/* derived-slc-AA-write-N7:5, sent by station 3 (SRC 03) to station 1 */
	expect_reply("01 03 0F 00 02 00 AA 02 07 89 05 00 34 12", "03 01 4F 00 02 00");
	assert_int_equal(tbl.last_source, 3);
	assert_int_equal(tbl.last_station, 1);
	assert_int_equal(df1_server_source(&handle), -1);
	handle.srv_free(&handle);
}

static void test_server_slc_masked_write_touches_masked_bits_only(void **state)
{
	(void)state;
	put_le16(elem_ptr(3, 0), 0x8001);
	/* derived-slc-AB-B3:0/5-set */
	expect_reply("01 00 0F 00 03 00 AB 02 03 85 00 00 20 00 20 00", "00 01 4F 00 03 00");
	assert_int_equal(word(3, 0), 0x8021);
	/* clear bit 15 only: mask 8000, data 0000 */
	expect_reply("01 00 0F 00 04 00 AB 02 03 85 00 00 00 80 00 00", "00 01 4F 00 04 00");
	assert_int_equal(word(3, 0), 0x0021);
	/* mask FCFF, data 0000 (the spec's S2:5 example shape) on B3:1 = FFFF */
	put_le16(elem_ptr(3, 1), 0xFFFF);
	expect_reply("01 00 0F 00 05 00 AB 02 03 85 01 00 FF FC 00 00", "00 01 4F 00 05 00");
	assert_int_equal(word(3, 1), 0x0300);
}

static void test_server_slc_errors(void **state)
{
	(void)state;
	/* derived-reply-ext-sts-06: no file 20 */
	expect_reply("01 00 0F 00 05 00 A2 02 14 89 00 00", "00 01 4F F0 05 00 06");
	/* N7 read with the F type code: wrong type (the data table's 11) */
	expect_status("01 00 0F 00 06 00 A2 02 07 8A 00 00", 0xF0, 0x11);
	/* unknown file type code */
	expect_status("01 00 0F 00 06 00 A2 02 07 99 00 00", 0xF0, 0x11);
	/* past the end of the file */
	expect_status("01 00 0F 00 07 00 A2 04 07 89 27 00", 0xF0, 0x0A);
	/* more than one packet */
	expect_status("01 00 0F 00 08 00 A2 F0 07 89 00 00", 0xF0, 0x09);
	handle.cfg.plc = DF1_PLC_SLC502;
	expect_status("01 00 0F 00 08 00 A2 54 07 89 00 00", 0xF0, 0x09);
	expect_status("01 00 0F 00 08 00 A2 52 07 89 00 00", 0xF0, 0x0A);
	handle.cfg.plc = DF1_PLC_SLC;
	/* malformed: extra byte, missing byte, zero size, write data short, masked data short */
	expect_status("01 00 0F 00 09 00 A2 02 07 89 00 00 00", 0x10, -1);
	expect_status("01 00 0F 00 09 00 A2 02 07 89 00", 0x10, -1);
	expect_status("01 00 0F 00 09 00 A2 00 07 89 00 00", 0x10, -1);
	expect_status("01 00 0F 00 09 00 AA 02 07 89 05 00 34", 0x10, -1);
	expect_status("01 00 0F 00 09 00 AB 02 03 85 00 00 20 00 20", 0x10, -1);
	/* a data table error given as -STS */
	tbl.fail_read_with_neg = true;
	expect_status("01 00 0F 00 0A 00 A2 02 07 89 00 00", 0x20, -1);
}

/* O and I: 8B/8C (M p.104) and 82/83 (F2E p.47) both name the file, with or
 * without DF1_OPT_SLC_IO_CODES_82 on the serving handle (doc/PROTOCOL.md 4.11). */
static void test_server_slc_io_codes_82_83_and_8b_8c(void **state)
{
	(void)state;
	tfile_init(0, DF1_FT_O, 4);
	tfile_init(1, DF1_FT_I, 4);
	put_le16(elem_ptr(0, 0), 0x1234);
	put_le16(elem_ptr(1, 1), 0x5678);
	for (int opt = 0; opt <= 1; opt++) {
		handle.cfg.slc_io_82 = opt;
		/* A2 O0:0: 8B, then 82 */
		expect_reply("01 00 0F 00 20 00 A2 02 00 8B 00 00", "00 01 4F 00 20 00 34 12");
		expect_reply("01 00 0F 00 21 00 A2 02 00 82 00 00", "00 01 4F 00 21 00 34 12");
		/* A2 I1:1: 8C, then 83; A1 (two fields) with 83 */
		expect_reply("01 00 0F 00 22 00 A2 02 01 8C 01 00", "00 01 4F 00 22 00 78 56");
		expect_reply("01 00 0F 00 23 00 A2 02 01 83 01 00", "00 01 4F 00 23 00 78 56");
		expect_reply("01 00 0F 00 24 00 A1 02 01 83 01", "00 01 4F 00 24 00 78 56");
	}
	/* AA O0:2 with 82, AB O0:0 bit 3 with 82, AA I1:0 with 83 */
	expect_reply("01 00 0F 00 25 00 AA 02 00 82 02 00 CD AB", "00 01 4F 00 25 00");
	assert_int_equal(word(0, 2), 0xABCD);
	expect_reply("01 00 0F 00 26 00 AB 02 00 82 00 00 08 00 08 00", "00 01 4F 00 26 00");
	assert_int_equal(word(0, 0), 0x123C);
	expect_reply("01 00 0F 00 27 00 AA 02 01 83 00 00 11 00", "00 01 4F 00 27 00");
	assert_int_equal(word(1, 0), 0x0011);
	/* still the file's type that counts: O codes on the I file */
	expect_status("01 00 0F 00 28 00 A2 02 01 82 00 00", 0xF0, 0x11);
	expect_status("01 00 0F 00 29 00 A2 02 01 8B 00 00", 0xF0, 0x11);
	/* 80, 81 stay reserved (M p.104) */
	expect_status("01 00 0F 00 2A 00 A2 02 00 80 00 00", 0xF0, 0x11);
	expect_status("01 00 0F 00 2B 00 A2 02 00 81 00 00", 0xF0, 0x11);
}

/* ------------------------------------------------------------------------
 * PLC-5 0F/68 67 01 00 26 02
 * ------------------------------------------------------------------------ */

static void test_server_plc5_typed_read_gives_spec_reply(void **state)
{
	(void)state;
	/* derived-plc5-68-typed-read-N7:0x10 -> derived-plc5-68-reply-0..9 */
	expect_reply("01 00 0F 00 06 00 68 00 00 0A 00 06 07 00 0A 00",
	             "00 01 4F 00 06 00 99 09 15 42 00 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 09 00");
	/* derived-plc5-68-typed-read-ascii: $N7:0 x1 */
	expect_reply("01 00 0F 00 07 00 68 00 00 01 00 00 24 4E 37 3A 30 00 01 00",
	             "00 01 4F 00 07 00 99 09 03 42 00 00");
	/* second packet of a 10-element transaction: offset 5, size 5 */
	expect_reply("01 00 0F 00 08 00 68 05 00 0A 00 06 07 00 05 00",
	             "00 01 4F 00 08 00 99 09 0B 42 05 00 06 00 07 00 08 00 09 00");
}

static void test_server_plc5_typed_read_types(void **state)
{
	uint8_t r[300];
	int n;

	(void)state;
	/* floats: 99 09 <n*4+2> 94 08, LE */
	expect_reply("01 00 0F 00 01 00 68 00 00 02 00 06 08 00 02 00",
	             "00 01 4F 00 01 00 99 09 0A 94 08 00 00 C0 3F 00 00 20 40");
	/* timers: array of type 5, 6 bytes each (3 data-table words) */
	expect_reply("01 00 0F 00 02 00 68 00 00 01 00 06 04 01 01 00",
	             "00 01 4F 00 02 00 99 09 07 56 00 00 64 00 0B 00");
	/* T4:1.ACC (level 4 given): integer words */
	expect_reply("01 00 0F 00 03 00 68 00 00 01 00 0E 04 01 02 01 00",
	             "00 01 4F 00 03 00 99 09 03 42 0B 00");
	/* a string: 39 LEN chars */
	expect_reply("01 00 0F 00 04 00 68 00 00 01 00 06 0B 00 01 00",
	             "00 01 4F 00 04 00 39 08 53 54 52 49 4E 47 20 30");
	/* long integers: integer elements of 4 bytes */
	expect_reply("01 00 0F 00 05 00 68 00 00 01 00 06 0C 01 01 00",
	             "00 01 4F 00 05 00 99 09 05 44 01 00 01 00");
	/* more than one reply holds: as many whole elements as fit, the command's
	 * address (06 0A 00: 3 bytes) + type/data + data <= 240 (doc/PROTOCOL.md 6):
	 * 3 + 4 (99 09 E9 42) + 2 * 116 = 239; 117 would be 241 */
	n = run("01 00 0F 00 06 00 68 00 00 C8 00 06 0A 00 C8 00", r, sizeof r);
	assert_int_equal(r[3], 0);
	assert_memory_equal(r + 6, "\x99\x09\xE9\x42", 4);   /* 116 elements */
	assert_int_equal(n - 6 - 4, 232);
	/* the largest count is answered whole: 116 asked, 116 sent */
	n = run("01 00 0F 00 07 00 68 00 00 74 00 06 0A 00 74 00", r, sizeof r);
	assert_memory_equal(r + 6, "\x99\x09\xE9\x42", 4);
	assert_int_equal(n - 6 - 4, 232);
	/* floats (F13, 60 elements): 3 + 5 (99 09 EA 94 08) + 4 * 58 = 240 */
	tfile_init(13, DF1_FT_F, 60);
	tfile_init(14, DF1_FT_T, 300);
	n = run("01 00 0F 00 08 00 68 00 00 3B 00 06 0D 00 3B 00", r, sizeof r);
	assert_memory_equal(r + 6, "\x99\x09\xEA\x94\x08", 5);
	assert_int_equal(n - 6 - 5, 232);
	/* timers (T14): 3 + 4 (99 09 E5 56) + 6 * 38 = 235; 39 would be 241 */
	n = run("01 00 0F 00 09 00 68 00 00 27 00 06 0E 00 27 00", r, sizeof r);
	assert_memory_equal(r + 6, "\x99\x09\xE5\x56", 4);
	assert_int_equal(n - 6 - 4, 228);
	/* a 5-byte address (T14:255 = 06 0E FF FF 00) leaves 5 + 4 + 6 * 38 = 237 */
	n = run("01 00 0F 00 0A 00 68 00 00 27 00 06 0E FF FF 00 27 00", r, sizeof r);
	assert_memory_equal(r + 6, "\x99\x09\xE5\x56", 4);
	assert_int_equal(n - 6 - 4, 228);
}

static void test_server_plc5_typed_read_errors(void **state)
{
	(void)state;
	expect_status("01 00 0F 00 01 00 68 00 00 01 00 06 14 00 01 00", 0xF0, 0x06);  /* no N20 */
	expect_status("01 00 0F 00 02 00 68 00 00 01 00 06 07 28 01 00", 0xF0, 0x07);  /* N7:40 */
	expect_status("01 00 0F 00 03 00 68 00 00 02 00 06 07 27 02 00", 0xF0, 0x0A);  /* N7:39 x2 */
	expect_status("01 00 0F 00 04 00 68 00 00 01 00 00 24 5A 5A 00 01 00", 0xF0, 0x05); /* $ZZ */
	expect_status("01 00 0F 00 05 00 68 00 00 01 00 07 01 07 00 01 00", 0xF0, 0x03); /* area 1 */
	expect_status("01 00 0F 00 06 00 68 00 00 01 00 1F 00 07 00 00 00 01 00", 0xF0, 0x03);
	expect_status("01 00 0F 00 07 00 68 00 00 01 00 06 07 00 00 00", 0x10, -1);    /* size 0 */
	expect_status("01 00 0F 00 08 00 68 00 00 01 00 06 07 00 02 00", 0x10, -1);    /* > total */
	expect_status("01 00 0F 00 09 00 68 00 00 01 00 06 07 00 01", 0x10, -1);       /* short */
	expect_status("01 00 0F 00 0A 00 68 00 00 01 00 06 07 00 01 00 00", 0x10, -1); /* extra */
}

static void test_server_plc5_typed_write(void **state)
{
	(void)state;
	/* derived-plc5-67-typed-write-N7:0 */
	expect_reply("01 00 0F 00 08 00 67 00 00 02 00 06 07 00 99 09 05 42 01 00 02 00",
	             "00 01 4F 00 08 00");
	assert_int_equal(word(7, 0), 1);
	assert_int_equal(word(7, 1), 2);
	assert_int_equal(word(7, 2), 2);
	/* M's short array form and a second packet (offset 2 of 4) */
	expect_reply("01 00 0F 00 09 00 67 02 00 04 00 06 07 00 95 09 42 33 33 44 44",
	             "00 01 4F 00 09 00");
	assert_int_equal(word(7, 2), 0x3333);
	assert_int_equal(word(7, 3), 0x4444);
	/* a single integer (42), not an array */
	expect_reply("01 00 0F 00 0A 00 67 00 00 01 00 06 07 05 42 55 00", "00 01 4F 00 0A 00");
	assert_int_equal(word(7, 5), 0x55);
	/* a float to F8:1 */
	expect_reply("01 00 0F 00 0B 00 67 00 00 01 00 06 08 01 99 09 06 94 08 00 00 20 41",
	             "00 01 4F 00 0B 00");
	assert_true(value_get_float(elem_ptr(8, 1), VALUE_FLOAT_LE) == 10.0f);
	/* a string "ABC" to ST11:1: LEN + bytes swapped per word */
	expect_reply("01 00 0F 00 0C 00 67 00 00 01 00 06 0B 01 33 41 42 43", "00 01 4F 00 0C 00");
	assert_memory_equal(elem_ptr(11, 1), "\x03\x00\x42\x41\x00\x43", 6);
}

static void test_server_plc5_typed_write_type_mismatch(void **state)
{
	(void)state;
	/* a float array to N7 */
	expect_status("01 00 0F 00 01 00 67 00 00 01 00 06 07 00 99 09 06 94 08 00 00 20 41", 0xF0, 0x11);
	/* integers to F8 */
	expect_status("01 00 0F 00 02 00 67 00 00 01 00 06 08 00 99 09 03 42 01 00", 0xF0, 0x11);
	assert_int_equal(word(7, 0), 0);
	/* more elements than TOTAL_TRANS, data shorter than declared */
	expect_status("01 00 0F 00 03 00 67 00 00 01 00 06 07 00 99 09 05 42 01 00 02 00", 0x10, -1);
	expect_status("01 00 0F 00 04 00 67 00 00 02 00 06 07 00 99 09 05 42 01 00", 0x10, -1);
	assert_int_equal(word(7, 0), 0);
}

/* A handle serving a PLC-5 with DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED: typed read
 * and write floats go [2,3,0,1] (1.5 = C0 3F 00 00, 2.5 = 20 40 00 00); the data
 * table keeps plain LE; word range stays word-swapped; other types untouched. */
static void test_server_plc5_typed_float_swapped(void **state)
{
	(void)state;
	handle.cfg.plc = DF1_PLC_PLC5;
	/* default: plain LE (doc/PROTOCOL.md 5 recommendation) */
	expect_reply("01 00 0F 00 01 00 68 00 00 02 00 06 08 00 02 00",
	             "00 01 4F 00 01 00 99 09 0A 94 08 00 00 C0 3F 00 00 20 40");
	handle.cfg.plc5_float_swapped = true;
	expect_reply("01 00 0F 00 02 00 68 00 00 02 00 06 08 00 02 00",
	             "00 01 4F 00 02 00 99 09 0A 94 08 C0 3F 00 00 20 40 00 00");
	/* a second packet: F8:1 at offset 1 */
	expect_reply("01 00 0F 00 03 00 68 01 00 02 00 06 08 00 01 00",
	             "00 01 4F 00 03 00 99 09 06 94 08 20 40 00 00");
	/* write F8:3 := 10.0 (41200000h) sent swapped: stored plain LE */
	expect_reply("01 00 0F 00 04 00 67 00 00 01 00 06 08 03 99 09 06 94 08 20 41 00 00",
	             "00 01 4F 00 04 00");
	assert_memory_equal(elem_ptr(8, 3), "\x00\x00\x20\x41", 4);
	assert_true(value_get_float(elem_ptr(8, 3), VALUE_FLOAT_LE) == 10.0f);
	/* two elements, each swapped */
	expect_reply("01 00 0F 00 05 00 67 00 00 02 00 06 08 04 99 09 0A 94 08 C0 3F 00 00 00 C0 00 00",
	             "00 01 4F 00 05 00");
	assert_true(value_get_float(elem_ptr(8, 4), VALUE_FLOAT_LE) == 1.5f);
	assert_true(value_get_float(elem_ptr(8, 5), VALUE_FLOAT_LE) == -2.0f);
	/* word range: word-swapped as always (not swapped twice) */
	expect_reply("01 00 0F 00 06 00 01 00 00 02 00 06 08 00 04",
	             "00 01 4F 00 06 00 C0 3F 00 00");
	/* integers and SLC A2 floats are not affected */
	expect_reply("01 00 0F 00 07 00 68 00 00 01 00 06 07 01 01 00",
	             "00 01 4F 00 07 00 99 09 03 42 01 00");
	expect_reply("01 00 0F 00 08 00 A2 04 08 8A 00 00", "00 01 4F 00 08 00 00 00 C0 3F");
	/* a handle not serving a PLC-5 keeps plain LE even with the option set */
	handle.cfg.plc = DF1_PLC_SLC;
	expect_reply("01 00 0F 00 09 00 68 00 00 01 00 06 08 00 01 00",
	             "00 01 4F 00 09 00 99 09 06 94 08 00 00 C0 3F");
}

/* A handle serving a PLC-5 with DF1_OPT_PLC5_TIMER_WORDS 5: typed-read timers go
 * as the 5 words of KF2 p.130 (doc/PROTOCOL.md 4.3): type/data 99 09 LL 59 0A, LL = 2 + 10n
 * (flag 59: type 5, one size byte 0A follows), words 0-2 from the data table,
 * words 3-4 zero; sub-elements stay integers, counters stay 3 words; the reply
 * limit counts 10 bytes a timer; writes take 3- and 5-word elements either way. */
static void test_server_plc5_timer_words_5(void **state)
{
	uint8_t r[300];
	int n;

	(void)state;
	handle.cfg.plc = DF1_PLC_PLC5;
	handle.cfg.plc5_timer_words = 5;
	/* T4:1 = CTL 0, PRE 100, ACC 11 */
	expect_reply("01 00 0F 00 02 00 68 00 00 01 00 06 04 01 01 00",
	             "00 01 4F 00 02 00 99 09 0C 59 0A 00 00 64 00 0B 00 00 00 00 00");
	/* T4:0 x 2: LL = 2 + 20 = 16h */
	expect_reply("01 00 0F 00 03 00 68 00 00 02 00 06 04 00 02 00",
	             "00 01 4F 00 03 00 99 09 16 59 0A 00 00 64 00 0A 00 00 00 00 00 "
	             "00 00 64 00 0B 00 00 00 00 00");
	/* T4:1.ACC: an integer word, as before */
	expect_reply("01 00 0F 00 04 00 68 00 00 01 00 0E 04 01 02 01 00",
	             "00 01 4F 00 04 00 99 09 03 42 0B 00");
	/* 39 timers asked (T14): 3 + 5 (99 09 E8 59 0A) + 10 * 23 = 238; 24 would be 248 */
	tfile_init(14, DF1_FT_T, 300);
	n = run("01 00 0F 00 05 00 68 00 00 27 00 06 0E 00 27 00", r, sizeof r);
	assert_memory_equal(r + 6, "\x99\x09\xE8\x59\x0A", 5);
	assert_int_equal(n - 6 - 5, 230);
	/* a 5-byte address (T14:255): 5 + 5 + 230 = 240 */
	n = run("01 00 0F 00 06 00 68 00 00 27 00 06 0E FF FF 00 27 00", r, sizeof r);
	assert_memory_equal(r + 6, "\x99\x09\xE8\x59\x0A", 5);
	assert_int_equal(n - 6 - 5, 230);
	/* counters keep their 3 words (KF2: "counter elements return three words") */
	tfile_init(5, DF1_FT_C, 4);
	put_le16(elem_ptr(5, 0) + 2, 7);
	expect_reply("01 00 0F 00 07 00 68 00 00 01 00 06 05 00 01 00",
	             "00 01 4F 00 07 00 99 09 07 66 00 00 07 00 00 00");
	/* a 5-word timer written: words 0-2 kept, 3-4 ignored */
	expect_reply("01 00 0F 00 08 00 67 00 00 01 00 06 04 02 59 0A 00 80 F4 01 05 00 AA AA BB BB",
	             "00 01 4F 00 08 00");
	assert_int_equal(word(4, 2), 0x8000);
	assert_int_equal(le16(elem_ptr(4, 2) + 2), 500);
	assert_int_equal(le16(elem_ptr(4, 2) + 4), 5);
	assert_int_equal(word(4, 3), 0);    /* T4:3 untouched */
	assert_int_equal(le16(elem_ptr(4, 3) + 2), 100);
	/* ... and the 3-word form still */
	expect_reply("01 00 0F 00 09 00 67 00 00 01 00 06 04 03 99 09 07 56 00 20 0A 00 01 00",
	             "00 01 4F 00 09 00");
	assert_int_equal(word(4, 3), 0x2000);
	assert_int_equal(le16(elem_ptr(4, 3) + 4), 1);
	/* a 5-word counter too, in an array: 99 09 0C 69 0A */
	expect_reply("01 00 0F 00 0A 00 67 00 00 01 00 06 05 01 99 09 0C 69 0A 00 10 09 00 03 00 00 00 00 00",
	             "00 01 4F 00 0A 00");
	assert_int_equal(word(5, 1), 0x1000);
	assert_int_equal(le16(elem_ptr(5, 1) + 2), 9);
	/* 4 words is neither form */
	expect_status("01 00 0F 00 0B 00 67 00 00 01 00 06 04 01 59 08 00 80 F4 01 05 00 AA AA", 0xF0, 0x11);
	/* the default, 3 words */
	handle.cfg.plc5_timer_words = 3;
	expect_reply("01 00 0F 00 0C 00 68 00 00 01 00 06 04 01 01 00",
	             "00 01 4F 00 0C 00 99 09 07 56 00 00 64 00 0B 00");
	/* a handle that does not serve a PLC-5 sends 3 words with the option set */
	handle.cfg.plc5_timer_words = 5;
	handle.cfg.plc = DF1_PLC_SLC;
	expect_reply("01 00 0F 00 0D 00 68 00 00 01 00 06 04 01 01 00",
	             "00 01 4F 00 0D 00 99 09 07 56 00 00 64 00 0B 00");
}

static void test_server_plc5_word_range(void **state)
{
	(void)state;
	/* derived-plc5-01-word-range-read */
	expect_reply("01 00 0F 00 09 00 01 00 00 0A 00 06 07 00 14",
	             "00 01 4F 00 09 00 00 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 09 00");
	/* floats are word-swapped: 1.5 -> C0 3F 00 00; a packet at word offset 3 */
	expect_reply("01 00 0F 00 0A 00 01 00 00 04 00 06 08 00 08",
	             "00 01 4F 00 0A 00 C0 3F 00 00 20 40 00 00");
	expect_reply("01 00 0F 00 0B 00 01 03 00 04 00 06 08 00 02", "00 01 4F 00 0B 00 00 00");
	/* KE-word-range-write-cmd / reply, then KE-word-range-read-ascii-cmd / reply */
	expect_reply("29 20 0F 00 46 01 00 00 00 04 00 0F 00 0A 0F 00 22 11 44 33 66 55 88 77",
	             "20 29 4F 00 46 01");
	assert_int_equal(word(10, 15), 0x1122);
	assert_int_equal(word(10, 18), 0x7788);
	expect_reply("29 20 0F 00 47 01 01 00 00 04 00 00 24 4E 31 30 3A 31 35 00 08",
	             "20 29 4F 00 47 01 22 11 44 33 66 55 88 77");
	/* word-swapped float write: F8:2 := 1.5 */
	expect_reply("01 00 0F 00 0C 00 00 00 00 02 00 06 08 02 C0 3F 00 00", "00 01 4F 00 0C 00");
	assert_true(value_get_float(elem_ptr(8, 2), VALUE_FLOAT_LE) == 1.5f);
	/* odd size, packet past TOTAL_TRANS, too large */
	expect_status("01 00 0F 00 0D 00 01 00 00 0A 00 06 07 00 13", 0x10, -1);
	expect_status("01 00 0F 00 0E 00 01 08 00 0A 00 06 07 00 08", 0x10, -1);
	expect_status("01 00 0F 00 0F 00 01 00 00 FF 00 06 07 00 F6", 0xF0, 0x09);
}

static void test_server_plc5_rmw_and_bit_write(void **state)
{
	(void)state;
	/* derived-plc5-26-rmw-set-bit3: N7:0 = 0 -> 8 */
	expect_reply("01 00 0F 00 0A 00 26 06 07 00 FF FF 08 00", "00 01 4F 00 0A 00");
	assert_int_equal(word(7, 0), 0x0008);
	/* two blocks: N7:1 AND 0000 OR 00F0; B3:0 AND FFFE OR 0000 */
	put_le16(elem_ptr(3, 0), 0x0003);
	expect_reply("01 00 0F 00 0B 00 26 06 07 01 00 00 F0 00 06 03 00 FE FF 00 00", "00 01 4F 00 0B 00");
	assert_int_equal(word(7, 1), 0x00F0);
	assert_int_equal(word(3, 0), 0x0002);
	/* 0F/02 bit write: set 0100, reset 0002 */
	expect_reply("01 00 0F 00 0C 00 02 06 03 00 00 01 02 00", "00 01 4F 00 0C 00");
	assert_int_equal(word(3, 0), 0x0100);
	/* a bad second block changes nothing */
	expect_status("01 00 0F 00 0D 00 26 06 07 02 00 00 F0 00 06 03", 0x10, -1);
	assert_int_equal(word(7, 2), 2);
	/* a float word is not a word of bits */
	expect_status("01 00 0F 00 0E 00 26 06 08 00 FF FF 08 00", 0xF0, 0x11);
}

/* ------------------------------------------------------------------------
 * PLC-2
 * ------------------------------------------------------------------------ */

static void test_server_plc2_ke_vectors(void **state)
{
	(void)state;
	/* KE-plc2-write-cmd / reply: byte address 28h = N9:20 */
	expect_reply("29 20 08 00 44 01 28 00 22 11 44 33 66 55 88 77", "20 29 48 00 44 01");
	assert_int_equal(word(9, 20), 0x1122);
	assert_int_equal(word(9, 23), 0x7788);
	/* KE-plc2-read-cmd / reply */
	expect_reply("29 20 01 00 45 01 28 00 08", "20 29 41 00 45 01 22 11 44 33 66 55 88 77");
	/* 05 unprotected bit write: byte 29h (high byte of N9:20): set 80, reset 01 */
	expect_reply("29 20 05 00 46 01 29 00 80 01", "20 29 45 00 46 01");
	assert_int_equal(word(9, 20), 0x9022);
	/* odd address, odd size, past the file (no EXT STS: STS 50) */
	expect_status("29 20 01 00 47 01 11 00 02", 0x10, -1);
	expect_status("29 20 01 00 47 01 10 00 03", 0x10, -1);
	expect_status("29 20 01 00 47 01 40 00 02", 0x50, -1);
	/* MicroLogix: the common interface file is N7 */
	handle.cfg.plc = DF1_PLC_MICROLOGIX;
	expect_reply("29 20 01 00 48 01 06 00 02", "20 29 41 00 48 01 03 00");
	/* no compatibility file */
	handle.cfg.plc = DF1_PLC_PLC5;
	tbl.files[9] = NULL;
	expect_status("29 20 01 00 49 01 00 00 02", 0x80, -1);
}

/* DF1_OPT_PLC2_WORD_ADDR (doc/PROTOCOL.md 4.7: an SLC or MicroLogix common interface file
 * with S:2/8 = 0): the address is the word offset, SIZE still bytes. The KE
 * vectors' byte address 28h is word 14h here; odd word offsets are fine; 05's
 * byte blocks have no meaning with word addresses: STS 10. */
static void test_server_plc2_word_addresses(void **state)
{
	(void)state;
	handle.cfg.plc2_word_addr = true;
	expect_reply("29 20 08 00 44 01 14 00 22 11 44 33 66 55 88 77", "20 29 48 00 44 01");
	assert_int_equal(word(9, 20), 0x1122);
	assert_int_equal(word(9, 23), 0x7788);
	expect_reply("29 20 01 00 45 01 14 00 08", "20 29 41 00 45 01 22 11 44 33 66 55 88 77");
	expect_reply("29 20 01 00 46 01 15 00 02", "20 29 41 00 46 01 44 33");        /* word 21 */
	expect_status("29 20 05 00 47 01 29 00 80 01", 0x10, -1);
	assert_int_equal(word(9, 20), 0x1122);
	expect_status("29 20 01 00 48 01 20 00 02", 0x50, -1);      /* word 32: past N9 */
	expect_status("29 20 01 00 48 01 10 00 03", 0x10, -1);      /* odd size */
	/* MicroLogix: N7, word 6 = 6 */
	handle.cfg.plc = DF1_PLC_MICROLOGIX;
	expect_reply("29 20 01 00 49 01 06 00 02", "20 29 41 00 49 01 06 00");
	/* bytes again: 06 is N7:3 */
	handle.cfg.plc2_word_addr = false;
	expect_reply("29 20 01 00 4A 01 06 00 02", "20 29 41 00 4A 01 03 00");
}

/* ------------------------------------------------------------------------
 * Diagnostics, modes, unknown commands
 * ------------------------------------------------------------------------ */

static void test_server_diag_status_default_is_slc504(void **state)
{
	uint8_t r[300];
	struct df1_diag_status ds;
	int n;

	(void)state;
	n = run("01 00 06 00 0B 00 03", r, sizeof r);
	assert_true(n > 6);
	assert_memory_equal(r, "\x00\x01\x46\x00\x0B\x00", 6);
	assert_int_equal(pccc_dec_diag_status(r + 6, (size_t)n - 6, &ds), 0);
	assert_int_equal(ds.type_code, 0x5B);
	assert_string_equal(ds.mode_text, "run");
}

static int t_diag(void *user, int station, uint8_t *buf, size_t cap)
{
	(void)user;
	assert_true(cap >= 3);
	buf[0] = 0x06;
	buf[1] = 0xEB;
	buf[2] = (uint8_t)station;
	return 3;
}

static void test_server_diag_status_callback(void **state)
{
	static const struct df1_server_ops dops = { .read = t_read, .diag_status = t_diag };
	struct server_ctx dctx = { &dops, &tbl };
	uint8_t cmd[] = { 0x05, 0x00, 0x06, 0x00, 0x0B, 0x00, 0x03 }, r[64];

	(void)state;
	assert_int_equal(server_handle(&handle, &dctx, cmd, sizeof cmd, r, sizeof r), 9);
	assert_memory_equal(r, "\x00\x05\x46\x00\x0B\x00\x06\xEB\x05", 9);
}

static void test_server_echo_mode_and_unknown(void **state)
{
	uint8_t big[300], r[300];
	char hexbuf[1000];
	size_t p = 0;

	(void)state;
	/* derived-echo-A */
	expect_reply("01 00 06 00 0C 00 00 41", "00 01 46 00 0C 00 41");
	/* derived-change-mode-run, through change_mode */
	expect_reply("01 00 0F 00 0D 00 80 06", "00 01 4F 00 0D 00");
	assert_int_equal(tbl.mode, 6);
	expect_status("01 00 0F 00 0E 00 80 07", 0xF0, 0x01);  /* the callback's EXT */
	expect_status("01 00 0F 00 0E 00 80", 0x10, -1);
	/* 0F/3A set CPU mode: 00 = program */
	expect_reply("01 00 0F 00 0F 00 3A 00", "00 01 4F 00 0F 00");
	assert_int_equal(tbl.mode, 1);
	/* 06/01 goes to the command callback; 0F/55 and CMD 1A are refused by it */
	expect_reply("01 00 06 00 10 00 01 00 00 02", "00 01 46 00 10 00 AB CD");
	expect_status("01 00 0F 00 11 00 55", 0x10, -1);
	expect_status("01 00 1A 00 12 00 00", 0x10, -1);
	/* a CMD 0F without its FNC */
	expect_status("01 00 0F 00 13 00", 0x10, -1);
	/* too short to answer; a reply is not answered */
	assert_int_equal(run("01 00 0F 00 13", r, sizeof r), 0);
	assert_int_equal(run("00 01 4F 00 13 00", r, sizeof r), 0);
	/* echo of 244 bytes is one too many */
	memset(big, 0x41, sizeof big);
	p += (size_t)snprintf(hexbuf + p, sizeof hexbuf - p, "01 00 06 00 14 00 00");
	for (int i = 0; i < 244; i++)
		p += (size_t)snprintf(hexbuf + p, sizeof hexbuf - p, "41");
	expect_status(hexbuf, 0x10, -1);
}

static void test_server_no_callbacks(void **state)
{
	static const struct df1_server_ops none;
	struct server_ctx nctx = { &none, NULL };
	uint8_t cmd1[] = { 0x01, 0x00, 0x0F, 0x00, 0x01, 0x00, 0xA2, 0x02, 0x07, 0x89, 0x00, 0x00 };
	uint8_t cmd2[] = { 0x01, 0x00, 0x0F, 0x00, 0x02, 0x00, 0x80, 0x06 };
	uint8_t cmd3[] = { 0x01, 0x00, 0x0F, 0x00, 0x03, 0x00, 0x80, 0x02 };
	uint8_t r[64];

	(void)state;
	assert_int_equal(server_handle(&handle, &nctx, cmd1, sizeof cmd1, r, sizeof r), 7);
	assert_int_equal(r[3], 0xF0);
	assert_int_equal(r[6], 0x0E);
	assert_int_equal(server_handle(&handle, &nctx, cmd2, sizeof cmd2, r, sizeof r), 6);
	assert_int_equal(r[3], 0x00);
	assert_int_equal(server_handle(&handle, &nctx, cmd3, sizeof cmd3, r, sizeof r), 7);
	assert_int_equal(r[6], 0x01);
}

static void test_server_add_station_range(void **state)
{
	df1_t *h = NULL;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_server_add_station(h, 7), 0);
	assert_true(server_responder(h)->serve_station[7]);
	assert_int_equal(df1_server_add_station(h, 255), DF1_E_INVAL);
	assert_int_equal(df1_server_add_station(h, -1), DF1_E_INVAL);
	assert_int_equal(df1_server_add_station(NULL, 1), DF1_E_INVAL);
	/* serving needs an open handle and callbacks */
	assert_int_equal(df1_serve(h, &ops, NULL, 10), DF1_E_NOT_OPEN);
	assert_int_equal(df1_serve(h, NULL, NULL, 10), DF1_E_INVAL);
	df1_free(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup(test_server_slc_read_float_gives_spec_reply, setup),
		cmocka_unit_test_setup(test_server_slc_read_20_bytes_gives_words, setup),
		cmocka_unit_test_setup(test_server_slc_write_sets_word, setup),
		cmocka_unit_test_setup(test_server_source_is_the_commands_src, setup),
		cmocka_unit_test_setup(test_server_slc_masked_write_touches_masked_bits_only, setup),
		cmocka_unit_test_setup(test_server_slc_errors, setup),
		cmocka_unit_test_setup(test_server_slc_io_codes_82_83_and_8b_8c, setup),
		cmocka_unit_test_setup(test_server_plc5_typed_read_gives_spec_reply, setup),
		cmocka_unit_test_setup(test_server_plc5_typed_read_types, setup),
		cmocka_unit_test_setup(test_server_plc5_typed_read_errors, setup),
		cmocka_unit_test_setup(test_server_plc5_typed_write, setup),
		cmocka_unit_test_setup(test_server_plc5_typed_write_type_mismatch, setup),
		cmocka_unit_test_setup(test_server_plc5_typed_float_swapped, setup),
		cmocka_unit_test_setup(test_server_plc5_word_range, setup),
		cmocka_unit_test_setup(test_server_plc5_rmw_and_bit_write, setup),
		cmocka_unit_test_setup(test_server_plc2_ke_vectors, setup),
		cmocka_unit_test_setup(test_server_plc2_word_addresses, setup),
		cmocka_unit_test_setup(test_server_plc5_timer_words_5, setup),
		cmocka_unit_test_setup(test_server_diag_status_default_is_slc504, setup),
		cmocka_unit_test_setup(test_server_diag_status_callback, setup),
		cmocka_unit_test_setup(test_server_echo_mode_and_unknown, setup),
		cmocka_unit_test_setup(test_server_no_callbacks, setup),
		cmocka_unit_test_setup(test_server_add_station_range, setup),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
