/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_client - lib/client/: the command bytes the client builds, packet
 * splitting, reply checks and value decoding, without the real link.
 *
 * This file defines link_transact() and link_test() (and the rest of link.h),
 * so the linker resolves client.o's references here and never pulls link.o
 * out of libdf1.a (nothing else this test uses refers to link.o: checked with
 * nm). Should handle.o or another member this test needs ever call a function
 * only link.o defines, the link fails with "multiple definition of
 * link_transact"; then mock at the port instead (tests/support/mock_port.h).
 * The mock link assigns SRC and TNS (from h->next_tns) like the real one,
 * records every command, and answers either from a script (canned replies,
 * link errors) or from a small simulated data table (SLC A2/AA/AB, PLC-5
 * 68/67/26, PLC-2 01/08/05, echo, change mode).
 *
 * Frames are compared with tests/data/vectors.txt: the recorded app bytes are framed
 * with frame_encode_full() and must equal the vector's wire bytes exactly (the
 * test sets h->next_tns to the vector's TNS).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "df1_int.h"
#include "proto/frame.h"
#include "link/link.h"
#include "support/mock_port.h"
#include "proto/pccc.h"
#include "proto/value.h"

/* ------------------------------------------------------------------------
 * The mock link
 * ------------------------------------------------------------------------ */

#define MAX_CMDS 64
#define MAX_SCRIPT 16

struct rec {
	uint8_t b[FRAME_MAX_DATA];
	size_t n;
};

enum script_kind { SC_DATA, SC_RAW, SC_LINK_ERROR };

struct script {
	enum script_kind kind;
	uint8_t sts, ext;
	bool has_ext;
	uint8_t b[FRAME_MAX_DATA];  /* SC_DATA: reply data; SC_RAW: whole reply app bytes */
	size_t n;
	int err;                    /* SC_LINK_ERROR */
};

static struct rec cmds[MAX_CMDS];
static size_t ncmds;
static struct script script[MAX_SCRIPT];
static size_t nscript, script_pos;
static int link_test_calls;

/* Simulated data tables: SLC/PLC-5 files by number (mod 32), PLC-2 words. */
#define FILES 32
#define FILE_BYTES 8192
static uint8_t mem[FILES][FILE_BYTES];
static uint8_t plc2_mem[0x10000];
static char plc5_ftype[FILES];     /* 'N' (default) 'F' 'T' 'C' 'R' 'L' 'S' (string) */

static void mock_reset(void)
{
	memset(cmds, 0, sizeof cmds);
	ncmds = 0;
	memset(script, 0, sizeof script);
	nscript = script_pos = 0;
	link_test_calls = 0;
	memset(mem, 0, sizeof mem);
	memset(plc2_mem, 0, sizeof plc2_mem);
	memset(plc5_ftype, 'N', sizeof plc5_ftype);
}

static struct script *script_add(enum script_kind k)
{
	struct script *s;

	assert_true(nscript < MAX_SCRIPT);
	s = &script[nscript++];
	memset(s, 0, sizeof *s);
	s->kind = k;
	return s;
}

static void script_data_hex(const char *hex)
{
	struct script *s = script_add(SC_DATA);

	s->n = mock_hex(hex, s->b, sizeof s->b);
}

static void script_sts(uint8_t sts, uint8_t ext, bool has_ext)
{
	struct script *s = script_add(SC_DATA);

	s->sts = sts;
	s->ext = ext;
	s->has_ext = has_ext;
}

static void script_raw_hex(const char *hex)
{
	struct script *s = script_add(SC_RAW);

	s->n = mock_hex(hex, s->b, sizeof s->b);
}

static void script_link_error(int err)
{
	script_add(SC_LINK_ERROR)->err = err;
}

/* Reply header for cmd + data. */
static size_t reply_build(const uint8_t *cmd, uint8_t sts, uint8_t ext, bool has_ext,
                          const uint8_t *data, size_t n, uint8_t *out, size_t cap)
{
	size_t len = PCCC_HDR_LEN + (has_ext ? 1 : 0) + n;

	assert_true(len <= cap);
	out[0] = cmd[1];
	out[1] = cmd[0];
	out[2] = (uint8_t)(cmd[2] | 0x40);
	out[3] = sts;
	out[4] = cmd[4];
	out[5] = cmd[5];
	if (has_ext)
		out[6] = ext;
	if (n)
		memcpy(out + PCCC_HDR_LEN + (has_ext ? 1 : 0), data, n);
	return len;
}

/* A field: 1 byte, or FF + LE16. */
static unsigned get_field(const uint8_t *p, size_t *pos)
{
	unsigned v = p[(*pos)++];

	if (v == 0xFF) {
		v = le16(p + *pos);
		*pos += 2;
	}
	return v;
}

static size_t slc_esize(uint8_t code)
{
	switch (code) {
	case 0x8D: return 84;
	case 0x86: case 0x87: case 0x88: return 6;
	case 0x8A: case 0x91: return 4;
	default: return 2;
	}
}

static size_t plc5_esize(unsigned file)
{
	switch (plc5_ftype[file % FILES]) {
	case 'F': case 'L': return 4;
	case 'T': case 'C': case 'R': return 6;
	case 'S': return 84;
	default: return 2;
	}
}

static uint8_t *mem_at(unsigned file, size_t off, size_t n)
{
	assert_true(off + n <= FILE_BYTES);
	return &mem[file % FILES][off];
}

/* PLC-5 logical binary address: mask + levels (1 area, 2 file, 3 element, 4 sub). */
static void plc5_parse_addr(const uint8_t *p, size_t *pos, unsigned *file, unsigned *elem, int *sub)
{
	unsigned mask = get_field(p, pos), lv[4] = { 0, 1, 0, 0 };

	assert_int_not_equal(p[*pos - 1], 0x00);        /* the sim speaks binary only */
	for (int i = 0; i < 4; i++)
		if (mask & (1u << i))
			lv[i] = get_field(p, pos);
	*file = lv[1];
	*elem = lv[2];
	*sub = (mask & 8) ? (int)lv[3] : -1;
}

/* Type/data flag: returns bytes used. */
static size_t td_parse(const uint8_t *p, unsigned *type, unsigned *size)
{
	uint8_t f = p[0];
	size_t pos = 1;

	*type = (f >> 4) & 7;
	*size = f & 7;
	if (f & 0x80) {
		unsigned k = (f >> 4) & 7;

		*type = 0;
		for (unsigned i = 0; i < k; i++)
			*type |= (unsigned)p[pos++] << (8 * i);
	}
	if (f & 0x08) {
		unsigned k = f & 7;

		*size = 0;
		for (unsigned i = 0; i < k; i++)
			*size |= (unsigned)p[pos++] << (8 * i);
	}
	return pos;
}

/* Simulated controller: returns the reply data length written to data, or -1 to answer
 * STS 10 (illegal command). */
static int sim(const uint8_t *c, size_t n, uint8_t *data)
{
	size_t pos = 7;

	if (c[2] == 0x0F) {
		uint8_t fnc = c[6];

		if (fnc == 0xA2 || fnc == 0xAA || fnc == 0xAB) {
			unsigned nb = c[pos++], file, elem, sub;
			uint8_t code;
			size_t off;

			file = get_field(c, &pos);
			code = c[pos++];
			elem = get_field(c, &pos);
			sub = get_field(c, &pos);
			off = elem * slc_esize(code) + sub * 2;
			if (fnc == 0xA2) {
				memcpy(data, mem_at(file, off, nb), nb);
				return (int)nb;
			}
			if (fnc == 0xAA) {
				assert_int_equal(n - pos, nb);
				memcpy(mem_at(file, off, nb), c + pos, nb);
				return 0;
			}
			assert_int_equal(n - pos, 2 * nb);
			for (unsigned i = 0; i < nb; i++) {
				uint8_t *m = mem_at(file, off + i, 1), mask = c[pos + i], v = c[pos + nb + i];

				*m = (uint8_t)((*m & ~mask) | (v & mask));
			}
			return 0;
		}
		if (fnc == 0x68 || fnc == 0x67) {
			unsigned off = le16(c + pos), file, elem;
			int sub;
			size_t es, o;

			pos += 4;       /* offset, total */
			plc5_parse_addr(c, &pos, &file, &elem, &sub);
			es = sub >= 0 ? 2 : plc5_esize(file);
			o = (elem + off) * (sub >= 0 ? 6 : es) + (sub >= 0 ? (size_t)sub * 2 : 0);
			if (fnc == 0x68 && sub < 0 && plc5_ftype[file % FILES] == 'S') {
				/* one string per packet: 3x LEN characters (RTA) */
				const uint8_t *el = mem_at(file, o, 84);
				unsigned len = le16(el);

				assert_int_equal(le16(c + pos), 1);
				data[0] = 0x39;
				data[1] = (uint8_t)len;
				for (unsigned i = 0; i < len; i++)
					data[2 + i] = el[2 + (i ^ 1u)];
				return (int)(2 + len);
			}
			if (fnc == 0x68) {
				unsigned k = le16(c + pos);
				uint8_t desc[2];
				size_t dl = 1, dpos;

				switch (sub >= 0 ? 'N' : plc5_ftype[file % FILES]) {
				case 'F': desc[0] = 0x94; desc[1] = 0x08; dl = 2; break;
				case 'T': desc[0] = 0x56; break;
				case 'C': desc[0] = 0x66; break;
				case 'R': desc[0] = 0x76; break;
				case 'L': desc[0] = 0x44; break;
				default: desc[0] = 0x42; break;
				}
				data[0] = 0x99;
				data[1] = 0x09;
				data[2] = (uint8_t)(dl + k * es);
				memcpy(data + 3, desc, dl);
				dpos = 3 + dl;
				memcpy(data + dpos, mem_at(file, o, k * es), k * es);
				return (int)(dpos + k * es);
			} else {
				unsigned t, sz, et, esz;

				pos += td_parse(c + pos, &t, &sz);
				if (t == 3) {
					uint8_t *el = mem_at(file, o, 84);

					assert_int_equal(n - pos, sz);
					memset(el, 0, 84);
					put_le16(el, (uint16_t)sz);
					for (unsigned i = 0; i < sz; i++)
						el[2 + (i ^ 1u)] = c[pos + i];
					return 0;
				}
				assert_int_equal(t, 9);
				assert_int_equal(n - pos, sz);
				pos += td_parse(c + pos, &et, &esz);
				assert_int_equal(esz, es);
				memcpy(mem_at(file, o, n - pos), c + pos, n - pos);
				return 0;
			}
		}
		if (fnc == 0x26) {
			unsigned file, elem;
			int sub;
			uint16_t w;
			uint8_t *m;

			plc5_parse_addr(c, &pos, &file, &elem, &sub);
			m = mem_at(file, elem * (sub >= 0 ? 6 : plc5_esize(file)) + (sub >= 0 ? (size_t)sub * 2 : 0), 2);
			w = (uint16_t)((le16(m) & le16(c + pos)) | le16(c + pos + 2));
			put_le16(m, w);
			return 0;
		}
		if (fnc == 0x80 || fnc == 0x3A)
			return 0;
		return -1;
	}
	if (c[2] == 0x06 && c[6] == 0x00) {
		memcpy(data, c + 7, n - 7);
		return (int)(n - 7);
	}
	if (c[2] == 0x01) {
		unsigned a = le16(c + 6), sz = c[8];

		memcpy(data, plc2_mem + a, sz);
		return (int)sz;
	}
	if (c[2] == 0x08) {
		memcpy(plc2_mem + le16(c + 6), c + 8, n - 8);
		return 0;
	}
	if (c[2] == 0x05) {
		for (pos = 6; pos + 4 <= n; pos += 4) {
			uint8_t *m = plc2_mem + le16(c + pos);

			*m = (uint8_t)((*m | c[pos + 2]) & ~c[pos + 3]);
		}
		return 0;
	}
	return -1;
}

int link_transact(struct df1 *h, uint8_t *cmd, size_t cmd_len, uint8_t *reply, size_t reply_cap)
{
	uint8_t data[FRAME_MAX_DATA];
	int n;

	assert_true(cmd_len >= PCCC_HDR_LEN && cmd_len <= FRAME_MAX_DATA);
	cmd[1] = (uint8_t)h->cfg.station;
	put_le16(cmd + 4, h->next_tns);
	h->next_tns++;
	assert_true(ncmds < MAX_CMDS);
	memcpy(cmds[ncmds].b, cmd, cmd_len);
	cmds[ncmds++].n = cmd_len;
	if (script_pos < nscript) {
		struct script *s = &script[script_pos++];

		switch (s->kind) {
		case SC_LINK_ERROR:
			return df1_fail(h, s->err, cmd[0], "%s", df1_strerror(s->err));
		case SC_RAW:
			assert_true(s->n <= reply_cap);
			memcpy(reply, s->b, s->n);
			return (int)s->n;
		case SC_DATA:
			return (int)reply_build(cmd, s->sts, s->ext, s->has_ext, s->b, s->n, reply, reply_cap);
		}
	}
	n = sim(cmd, cmd_len, data);
	if (n < 0)
		return (int)reply_build(cmd, 0x10, 0, false, NULL, 0, reply, reply_cap);
	return (int)reply_build(cmd, 0, 0, false, data, (size_t)n, reply, reply_cap);
}

int link_test(struct df1 *h, int station)
{
	(void)h;
	(void)station;
	link_test_calls++;
	return 0;
}

/* The rest of link.h, so that nothing can pull link.o into this binary. */
int link_serve(struct df1 *h, struct link_responder *r, link_handler_fn fn, void *ctx,
               int64_t deadline_ms)
{
	(void)h; (void)r; (void)fn; (void)ctx; (void)deadline_ms;
	return DF1_E_NOTSUP;
}

int link_send_raw(struct df1 *h, const uint8_t *buf, size_t n)
{
	(void)h; (void)buf; (void)n;
	return DF1_E_NOTSUP;
}

void link_flush(struct df1 *h)
{
	(void)h;
}

/* ------------------------------------------------------------------------
 * Helpers
 * ------------------------------------------------------------------------ */

static int setup(void **state)
{
	df1_t *h = NULL;

	mock_reset();
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_station(h, 0), 0);
	h->next_tns = 1;
	*state = h;
	return 0;
}

static int teardown(void **state)
{
	df1_free(*state);
	return 0;
}

/* Command i's app bytes must equal hex, TNS bytes excepted. */
static void assert_cmd(size_t i, const char *hex)
{
	uint8_t want[FRAME_MAX_DATA];
	size_t n = mock_hex(hex, want, sizeof want);

	assert_true(i < ncmds);
	assert_int_equal(cmds[i].n, n);
	want[4] = cmds[i].b[4];
	want[5] = cmds[i].b[5];
	assert_memory_equal(cmds[i].b, want, n);
}

/* Command i framed with check must be exactly the wire frame of a tests/data/vectors.txt line. */
static void assert_wire(size_t i, enum df1_check check, const char *hex)
{
	uint8_t want[FRAME_MAX_WIRE], got[FRAME_MAX_WIRE];
	size_t n = mock_hex(hex, want, sizeof want);
	size_t g;

	assert_true(i < ncmds);
	g = frame_encode_full(check, cmds[i].b, cmds[i].n, got, sizeof got);
	assert_int_equal(g, n);
	assert_memory_equal(got, want, n);
}

static void set_plc(df1_t *h, enum df1_plc plc)
{
	assert_int_equal(df1_set_plc(h, plc), 0);
}

static void fill_words(unsigned file, size_t n)
{
	for (size_t i = 0; i < n; i++)
		put_le16(mem_at(file, i * 2, 2), (uint16_t)i);
}

/* ------------------------------------------------------------------------
 * SLC: exact commands (doc/PROTOCOL.md 7.3 vectors)
 * ------------------------------------------------------------------------ */

static void test_client_slc_read_n7_vector(void **state)
{
	df1_t *h = *state;
	int16_t v[10];

	fill_words(7, 10);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", v, 10), 10);
	assert_int_equal(ncmds, 1);
	assert_cmd(0, "01 00 0F 00 01 00 A2 14 07 89 00 00");
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 A9");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 60 46");
	for (int i = 0; i < 10; i++)
		assert_int_equal(v[i], i);
}

static void test_client_slc_write_n7_5_vector(void **state)
{
	df1_t *h = *state;
	int16_t v = 0x1234;

	h->next_tns = 2;
	assert_int_equal(df1_write_int16(h, 1, "N7:5", &v, 1), 1);
	assert_int_equal(ncmds, 1);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 02 00 AA 02 07 89 05 00 34 12 10 03 67");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 02 00 AA 02 07 89 05 00 34 12 10 03 71 3F");
	assert_int_equal(le16(mem_at(7, 10, 2)), 0x1234);
}

static void test_client_slc_capture_frames(void **state)
{
	df1_t *h = *state;
	int16_t v = 0x3449, r;

	/* serial-tap capture: DST 00 SRC 00, TNS 3901 and 3911 */
	h->next_tns = 0x3901;
	assert_int_equal(df1_write_int16(h, 0, "N7:5", &v, 1), 1);
	assert_wire(0, DF1_CHECK_BCC, "10 02 00 00 0F 00 01 39 AA 02 07 89 05 00 49 34 10 03 F9");
	h->next_tns = 0x3911;
	assert_int_equal(df1_read_int16(h, 0, "N7:1", &r, 1), 1);
	assert_wire(1, DF1_CHECK_BCC, "10 02 00 00 0F 00 11 39 A2 02 07 89 01 00 10 03 72");
}

static void test_client_slc_bit_set_vector_keeps_other_bits(void **state)
{
	df1_t *h = *state;
	bool b;

	put_le16(mem_at(3, 0, 2), 0x8001);
	h->next_tns = 3;
	assert_int_equal(df1_write_bit(h, 1, "B3:0/5", true), 0);
	assert_int_equal(ncmds, 1);
	assert_wire(0, DF1_CHECK_BCC,
	            "10 02 01 00 0F 00 03 00 AB 02 03 85 00 00 20 00 20 00 10 03 78");
	assert_wire(0, DF1_CHECK_CRC,
	            "10 02 01 00 0F 00 03 00 AB 02 03 85 00 00 20 00 20 00 10 03 81 18");
	assert_int_equal(le16(mem_at(3, 0, 2)), 0x8021);
	/* clear: mask 0020, data 0000 */
	assert_int_equal(df1_write_bit(h, 1, "B3:0/5", false), 0);
	assert_cmd(1, "01 00 0F 00 00 00 AB 02 03 85 00 00 20 00 00 00");
	assert_int_equal(le16(mem_at(3, 0, 2)), 0x8001);
	/* B3/21 = B3:1/5 */
	assert_int_equal(df1_write_bit(h, 1, "B3/21", true), 0);
	assert_cmd(2, "01 00 0F 00 00 00 AB 02 03 85 01 00 20 00 20 00");
	assert_int_equal(df1_read_bit(h, 1, "B3:1/5", &b), 0);
	assert_true(b);
	assert_cmd(3, "01 00 0F 00 00 00 A2 02 03 85 01 00");
}

static void test_client_slc_float_decodes_1_5(void **state)
{
	df1_t *h = *state;
	float f = 0;

	h->next_tns = 4;
	script_data_hex("00 00 C0 3F");
	assert_int_equal(df1_read_float(h, 1, "F8:0", &f, 1), 1);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 04 00 A2 04 08 8A 00 00 10 03 B4");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 04 00 A2 04 08 8A 00 00 10 03 09 C3");
	assert_true(f == 1.5f);
}

static void test_client_float_reply_vector_through_generic_read(void **state)
{
	df1_t *h = *state;
	struct df1_value v;

	/* the whole reply of the vector "reply: F8:0 = 1.5" (TNS 0004) */
	h->next_tns = 4;
	script_raw_hex("00 01 4F 00 04 00 00 00 C0 3F");
	assert_int_equal(df1_read(h, 1, "F8:0", &v, 1), 1);
	assert_int_equal(v.kind, DF1_VAL_FLOAT);
	assert_true(v.v.f == 1.5f);
}

static void test_client_remote_error_sts_f0_ext_06(void **state)
{
	df1_t *h = *state;
	int16_t v;
	const struct df1_error_detail *e;

	script_sts(0xF0, 0x06, true);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), DF1_E_REMOTE);
	e = df1_last_error(h);
	assert_int_equal(e->code, DF1_E_REMOTE);
	assert_int_equal(e->sts, 0xF0);
	assert_true(e->has_ext_sts);
	assert_int_equal(e->ext_sts, 0x06);
	assert_int_equal(e->station, 1);
	/* the address is in its own field (0.2), not in front of the message */
	assert_string_equal(e->address, "N7:0");
	assert_null(strstr(e->message, "N7:0"));
	assert_int_equal(strncmp(e->message, "PLC error: ", 11), 0);
	assert_non_null(strstr(e->message, "06"));
	/* the vector's whole reply, TNS 0005 */
	h->next_tns = 5;
	script_raw_hex("00 01 4F F0 05 00 06");
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), DF1_E_REMOTE);
	assert_int_equal(df1_last_error(h)->ext_sts, 0x06);
	/* a local STS without EXT */
	script_sts(0x10, 0, false);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), DF1_E_REMOTE);
	assert_int_equal(df1_last_error(h)->sts, 0x10);
	assert_false(df1_last_error(h)->has_ext_sts);
}

static void test_client_short_reply_is_bad_reply(void **state)
{
	df1_t *h = *state;
	int16_t v[10];

	script_data_hex("00 00 01 00");
	assert_int_equal(df1_read_int16(h, 1, "N7:0", v, 10), DF1_E_BAD_REPLY);
	assert_int_equal(df1_last_error(h)->code, DF1_E_BAD_REPLY);
	assert_int_equal(df1_last_error(h)->station, 1);
	assert_string_equal(df1_last_error(h)->address, "N7:0");
	assert_null(strstr(df1_last_error(h)->message, "N7:0"));
	/* longer than asked: also refused */
	script_data_hex("00 00 01 00 02 00");
	assert_int_equal(df1_read_int16(h, 1, "N7:0", v, 2), DF1_E_BAD_REPLY);
}

static void test_client_wrong_reply_cmd_is_bad_function(void **state)
{
	df1_t *h = *state;
	int16_t v;

	script_raw_hex("00 01 46 00 01 00 00 00");
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), DF1_E_BAD_FUNCTION);
}

static void test_client_link_error_names_address(void **state)
{
	df1_t *h = *state;
	int16_t v;
	const struct df1_error_detail *e;

	script_link_error(DF1_E_TIMEOUT);
	assert_int_equal(df1_read_int16(h, 3, "N7:9", &v, 1), DF1_E_TIMEOUT);
	e = df1_last_error(h);
	assert_int_equal(e->code, DF1_E_TIMEOUT);
	assert_int_equal(e->station, 3);
	assert_int_equal(e->catalog_id, 2508);
	assert_string_equal(e->address, "N7:9");
	assert_null(strstr(e->message, "N7:9"));
}

static void test_client_type_errors_send_nothing(void **state)
{
	df1_t *h = *state;
	float f;
	int16_t i;
	int32_t l;
	struct df1_tcr t;
	char s[90];
	bool b;

	assert_int_equal(df1_read_float(h, 1, "N7:0", &f, 1), DF1_E_TYPE);
	assert_string_equal(df1_last_error(h)->address, "N7:0");
	assert_null(strstr(df1_last_error(h)->message, "N7:0"));
	assert_int_equal(df1_read_int16(h, 1, "F8:0", &i, 1), DF1_E_TYPE);
	assert_int_equal(df1_read_int16(h, 1, "T4:0", &i, 1), DF1_E_TYPE);
	assert_int_equal(df1_read_int32(h, 1, "N7:0", &l, 1), DF1_E_TYPE);
	assert_int_equal(df1_read_tcr(h, 1, "T4:0.ACC", &t, 1), DF1_E_TYPE);
	assert_int_equal(df1_read_string(h, 1, "N7:0", s, sizeof s), DF1_E_TYPE);
	assert_int_equal(df1_read_bit(h, 1, "N7:0", &b), DF1_E_TYPE);
	assert_int_equal(df1_write_float(h, 1, "B3:0", &f, 1), DF1_E_TYPE);
	assert_int_equal(df1_read_raw(h, 1, "B3:0/1", (uint8_t *)s, 2), DF1_E_TYPE);
	assert_int_equal(df1_read_raw(h, 1, "F8:0", (uint8_t *)s, 6), DF1_E_INVAL);
	assert_int_equal(df1_read_int16(h, 1, "N7:x", &i, 1), DF1_E_ADDR_SYNTAX);
	assert_int_equal(df1_read_int16(h, 255, "N7:0", &i, 1), DF1_E_INVAL);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &i, 0), DF1_E_INVAL);
	assert_int_equal(ncmds, 0);
}

static void test_client_write_value_checked_before_sending(void **state)
{
	df1_t *h = *state;
	struct df1_value v[3];

	memset(v, 0, sizeof v);
	v[0].kind = DF1_VAL_INT16;
	v[1].kind = DF1_VAL_INT16;
	v[2].kind = DF1_VAL_FLOAT;      /* wrong for an N file */
	assert_int_equal(df1_write(h, 1, "N7:0", v, 3), DF1_E_TYPE);
	assert_int_equal(ncmds, 0);
	v[2].kind = DF1_VAL_INT32;
	v[2].v.i32 = 70000;             /* out of int16 range */
	assert_int_equal(df1_write(h, 1, "N7:0", v, 3), DF1_E_RANGE);
	assert_int_equal(ncmds, 0);
}

/* ------------------------------------------------------------------------
 * SLC: splitting
 * ------------------------------------------------------------------------ */

static void test_client_slc_300_words_split_236(void **state)
{
	df1_t *h = *state;
	int16_t v[300];

	fill_words(7, 300);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", v, 300), 300);
	assert_int_equal(ncmds, 3);
	assert_cmd(0, "01 00 0F 00 00 00 A2 EC 07 89 00 00");   /* 118 words at 0 */
	assert_cmd(1, "01 00 0F 00 00 00 A2 EC 07 89 76 00");   /* 118 words at 118 */
	assert_cmd(2, "01 00 0F 00 00 00 A2 80 07 89 EC 00");   /* 64 words at 236 */
	for (int i = 0; i < 300; i++)
		assert_int_equal(v[i], i);
}

static void test_client_slc_write_300_words_split_234(void **state)
{
	df1_t *h = *state;
	int16_t v[300];

	for (int i = 0; i < 300; i++)
		v[i] = (int16_t)(1000 + i);
	assert_int_equal(df1_write_int16(h, 1, "N7:0", v, 300), 300);
	assert_int_equal(ncmds, 3);
	assert_int_equal(cmds[0].n, 12 + 234);
	assert_memory_equal(cmds[0].b + 6, "\xAA\xEA\x07\x89\x00\x00", 6);  /* 117 words at 0 */
	assert_memory_equal(cmds[1].b + 6, "\xAA\xEA\x07\x89\x75\x00", 6);  /* at 117 */
	assert_memory_equal(cmds[2].b + 6, "\xAA\x84\x07\x89\xEA\x00", 6);  /* 66 at 234 */
	assert_int_equal(cmds[2].n, 12 + 132);
	for (int i = 0; i < 300; i++)
		assert_int_equal((int16_t)le16(mem_at(7, (size_t)i * 2, 2)), 1000 + i);
}

static void test_client_slc_split_on_element_boundaries(void **state)
{
	df1_t *h = *state;
	struct df1_tcr t[50];
	float f[100];
	struct df1_value s[5];

	/* T: 6 bytes, 39 per packet (234 bytes) */
	for (int i = 0; i < 50; i++)
		put_le16(mem_at(4, (size_t)i * 6 + 4, 2), (uint16_t)i);
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 50), 50);
	assert_int_equal(ncmds, 2);
	assert_cmd(0, "01 00 0F 00 00 00 A2 EA 04 86 00 00");
	assert_cmd(1, "01 00 0F 00 00 00 A2 42 04 86 27 00");
	for (int i = 0; i < 50; i++)
		assert_int_equal(t[i].acc, i);
	/* F: 4 bytes, 59 per packet */
	for (int i = 0; i < 100; i++)
		value_put_float(mem_at(8, (size_t)i * 4, 4), (float)i + 0.25f, VALUE_FLOAT_LE);
	assert_int_equal(df1_read_float(h, 1, "F8:0", f, 100), 100);
	assert_int_equal(ncmds, 4);
	assert_cmd(2, "01 00 0F 00 00 00 A2 EC 08 8A 00 00");
	assert_cmd(3, "01 00 0F 00 00 00 A2 A4 08 8A 3B 00");
	for (int i = 0; i < 100; i++)
		assert_true(f[i] == (float)i + 0.25f);
	/* ST: 84 bytes, two per read */
	for (int i = 0; i < 5; i++) {
		char txt[8] = "str0";

		txt[3] = (char)('0' + i);
		assert_int_equal(value_put_string(mem_at(9, (size_t)i * 84, 84), txt), 4);
	}
	assert_int_equal(df1_read(h, 1, "ST9:0", s, 5), 5);
	assert_int_equal(ncmds, 7);
	assert_cmd(4, "01 00 0F 00 00 00 A2 A8 09 8D 00 00");
	assert_cmd(5, "01 00 0F 00 00 00 A2 A8 09 8D 02 00");
	assert_cmd(6, "01 00 0F 00 00 00 A2 54 09 8D 04 00");
	assert_int_equal(s[4].kind, DF1_VAL_STRING);
	assert_string_equal(s[4].v.str.text, "str4");
}

static void test_client_slc_element_above_254_uses_ff_escape(void **state)
{
	df1_t *h = *state;
	int16_t v[200];

	assert_int_equal(df1_read_int16(h, 1, "N10:200", v, 200), 200);
	assert_int_equal(ncmds, 2);
	assert_cmd(0, "01 00 0F 00 00 00 A2 EC 0A 89 C8 00");
	assert_cmd(1, "01 00 0F 00 00 00 A2 A4 0A 89 FF 3E 01 00");     /* element 318 */
}

static void test_client_slc502_and_max_packet_limits(void **state)
{
	df1_t *h = *state;
	int16_t v[50];

	set_plc(h, DF1_PLC_SLC502);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", v, 50), 50);
	assert_int_equal(ncmds, 2);
	assert_cmd(0, "01 00 0F 00 00 00 A2 52 07 89 00 00");   /* 82 bytes = 41 words */
	assert_cmd(1, "01 00 0F 00 00 00 A2 12 07 89 29 00");
	assert_int_equal(df1_write_int16(h, 1, "N7:0", v, 50), 50);
	assert_int_equal(ncmds, 4);
	assert_int_equal(cmds[2].b[7], 82);
	set_plc(h, DF1_PLC_SLC);
	assert_int_equal(df1_set_option(h, DF1_OPT_MAX_PACKET, 20), 0);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", v, 25), 25);
	assert_int_equal(ncmds, 7);
	assert_cmd(4, "01 00 0F 00 00 00 A2 14 07 89 00 00");
	assert_cmd(5, "01 00 0F 00 00 00 A2 14 07 89 0A 00");
	assert_cmd(6, "01 00 0F 00 00 00 A2 0A 07 89 14 00");
}

/* ------------------------------------------------------------------------
 * SLC: sub-elements, bits, strings, longs
 * ------------------------------------------------------------------------ */

static void test_client_slc_tcr_subelements(void **state)
{
	df1_t *h = *state;
	int16_t acc[3], pre[2] = { 100, 200 };
	bool dn;

	for (int i = 0; i < 3; i++) {
		put_le16(mem_at(4, (size_t)i * 6, 2), 0x2000);         /* DN */
		put_le16(mem_at(4, (size_t)i * 6 + 4, 2), (uint16_t)(10 + i));
	}
	assert_int_equal(df1_read_int16(h, 1, "T4:0.ACC", acc, 1), 1);
	assert_cmd(0, "01 00 0F 00 00 00 A2 02 04 86 00 02");
	assert_int_equal(acc[0], 10);
	/* several: whole elements, the ACC word of each */
	assert_int_equal(df1_read_int16(h, 1, "T4:0.ACC", acc, 3), 3);
	assert_cmd(1, "01 00 0F 00 00 00 A2 12 04 86 00 00");
	assert_int_equal(acc[1], 11);
	assert_int_equal(acc[2], 12);
	/* writes: one word per element, never the others */
	assert_int_equal(df1_write_int16(h, 1, "T4:0.PRE", pre, 2), 2);
	assert_int_equal(ncmds, 4);
	assert_cmd(2, "01 00 0F 00 00 00 AA 02 04 86 00 01 64 00");
	assert_cmd(3, "01 00 0F 00 00 00 AA 02 04 86 01 01 C8 00");
	assert_int_equal(le16(mem_at(4, 6 + 2, 2)), 200);
	assert_int_equal(le16(mem_at(4, 6 + 4, 2)), 11);
	/* T4:0/DN: word 0, bit 13 */
	assert_int_equal(df1_read_bit(h, 1, "T4:1/DN", &dn), 0);
	assert_cmd(4, "01 00 0F 00 00 00 A2 02 04 86 01 00");
	assert_true(dn);
	assert_int_equal(df1_write_bit(h, 1, "T4:1/DN", false), 0);
	assert_cmd(5, "01 00 0F 00 00 00 AB 02 04 86 01 00 00 20 00 00");
	assert_int_equal(le16(mem_at(4, 6, 2)), 0x0000);
}

static void test_client_slc_bits_across_words(void **state)
{
	df1_t *h = *state;
	struct df1_value v[4];
	bool want[4] = { true, false, true, true };

	put_le16(mem_at(3, 0, 2), 0x4000);      /* B3:0/14 */
	put_le16(mem_at(3, 2, 2), 0x0003);      /* B3:1/0, /1 */
	assert_int_equal(df1_read(h, 1, "B3:0/14", v, 4), 4);
	assert_int_equal(ncmds, 1);
	assert_cmd(0, "01 00 0F 00 00 00 A2 04 03 85 00 00");
	for (int i = 0; i < 4; i++) {
		assert_int_equal(v[i].kind, DF1_VAL_BIT);
		assert_int_equal(v[i].v.bit, i == 0 || i >= 2);
	}
	/* write 4 bits: one masked write per word */
	for (int i = 0; i < 4; i++)
		v[i].v.bit = want[i];
	put_le16(mem_at(3, 0, 2), 0x1234);
	put_le16(mem_at(3, 2, 2), 0x00F0);
	assert_int_equal(df1_write(h, 1, "B3:0/14", v, 4), 4);
	assert_int_equal(ncmds, 3);
	assert_cmd(1, "01 00 0F 00 00 00 AB 02 03 85 00 00 00 C0 00 40");
	assert_cmd(2, "01 00 0F 00 00 00 AB 02 03 85 01 00 03 00 03 00");
	assert_int_equal(le16(mem_at(3, 0, 2)), 0x5234);
	assert_int_equal(le16(mem_at(3, 2, 2)), 0x00F3);
}

static void test_client_slc_long_and_string(void **state)
{
	df1_t *h = *state;
	int32_t l[2] = { -2, 0x12345678 }, r[2];
	char s[DF1_STRING_MAX + 1];

	assert_int_equal(df1_write_int32(h, 1, "L10:0", l, 2), 2);
	assert_cmd(0, "01 00 0F 00 00 00 AA 08 0A 91 00 00 FE FF FF FF 78 56 34 12");
	assert_int_equal(df1_read_int32(h, 1, "L10:0", r, 2), 2);
	assert_int_equal(r[0], -2);
	assert_int_equal(r[1], 0x12345678);
	/* bit 20 of a long: 4-byte mask and data */
	assert_int_equal(df1_write_bit(h, 1, "L10:0/20", false), 0);
	assert_cmd(2, "01 00 0F 00 00 00 AB 04 0A 91 00 00 00 00 10 00 00 00 00 00");
	assert_int_equal((int32_t)le32(mem_at(10, 0, 4)), -2 & ~(1 << 20));
	/* strings: 84-byte element, characters swapped per word */
	assert_int_equal(df1_write_string(h, 1, "ST9:1", "ABC"), 3);
	assert_int_equal(cmds[3].n, 12 + 84);
	assert_memory_equal(cmds[3].b + 6, "\xAA\x54\x09\x8D\x01\x00\x03\x00\x42\x41\x00\x43", 12);
	assert_int_equal(df1_read_string(h, 1, "ST9:1", s, sizeof s), 3);
	assert_string_equal(s, "ABC");
	assert_int_equal(df1_read_string(h, 1, "ST9:1", s, 3), DF1_E_NOSPACE);
	{
		char big[DF1_STRING_MAX + 2];

		memset(big, 'x', sizeof big - 1);
		big[sizeof big - 1] = '\0';
		assert_int_equal(df1_write_string(h, 1, "ST9:1", big), DF1_E_RANGE);
	}
}

static void test_client_raw(void **state)
{
	df1_t *h = *state;
	uint8_t b[8] = { 1, 2, 3, 4, 5, 6, 7, 8 }, r[8];

	assert_int_equal(df1_write_raw(h, 1, "N7:2", b, 8), 8);
	assert_cmd(0, "01 00 0F 00 00 00 AA 08 07 89 02 00 01 02 03 04 05 06 07 08");
	assert_int_equal(df1_read_raw(h, 1, "N7:2", r, 8), 8);
	assert_memory_equal(r, b, 8);
	assert_int_equal(df1_read_raw(h, 1, "N7:2", r, 3), DF1_E_INVAL);
}

/* O and I files: type codes 8B/8C (doc/PROTOCOL.md 4.11 recommendation), 82/83 with
 * DF1_OPT_SLC_IO_CODES_82 (F2E p.47). Frames checked with an independent
 * CRC-16/ARC and BCC computation (the doc/PROTOCOL.md 7.5 rules). */
static void test_client_slc_io_codes_8b_default_82_option(void **state)
{
	df1_t *h = *state;
	int16_t v = 0;
	int16_t w = 0x00F0;
	bool b;

	put_le16(mem_at(0, 0, 2), 0x1234);
	put_le16(mem_at(1, 0, 2), 0x5678);
	assert_int_equal(df1_get_option(h, DF1_OPT_SLC_IO_CODES_82), 0);
	h->next_tns = 0x20;
	assert_int_equal(df1_read_int16(h, 1, "O0:0", &v, 1), 1);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 20 00 A2 02 00 8B 00 00 10 03 A1");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 20 00 A2 02 00 8B 00 00 10 03 42 99");
	assert_int_equal(v, 0x1234);
	h->next_tns = 0x22;
	assert_int_equal(df1_read_int16(h, 1, "I1:0", &v, 1), 1);
	assert_wire(1, DF1_CHECK_BCC, "10 02 01 00 0F 00 22 00 A2 02 01 8C 00 00 10 03 9D");
	assert_wire(1, DF1_CHECK_CRC, "10 02 01 00 0F 00 22 00 A2 02 01 8C 00 00 10 03 67 4D");
	assert_int_equal(v, 0x5678);

	assert_int_equal(df1_set_option(h, DF1_OPT_SLC_IO_CODES_82, 1), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_SLC_IO_CODES_82), 1);
	h->next_tns = 0x21;
	assert_int_equal(df1_read_int16(h, 1, "O0:0", &v, 1), 1);
	assert_wire(2, DF1_CHECK_BCC, "10 02 01 00 0F 00 21 00 A2 02 00 82 00 00 10 03 A9");
	assert_wire(2, DF1_CHECK_CRC, "10 02 01 00 0F 00 21 00 A2 02 00 82 00 00 10 03 4C 95");
	assert_int_equal(v, 0x1234);
	h->next_tns = 0x23;
	assert_int_equal(df1_read_int16(h, 1, "I1:0", &v, 1), 1);
	assert_wire(3, DF1_CHECK_BCC, "10 02 01 00 0F 00 23 00 A2 02 01 83 00 00 10 03 A5");
	assert_wire(3, DF1_CHECK_CRC, "10 02 01 00 0F 00 23 00 A2 02 01 83 00 00 10 03 69 C9");
	/* writes, bit writes and I/O words (SUBELEMENT) too */
	assert_int_equal(df1_write_int16(h, 1, "O0:1", &w, 1), 1);
	assert_cmd(4, "01 00 0F 00 00 00 AA 02 00 82 01 00 F0 00");
	assert_int_equal(df1_write_bit(h, 1, "O0:0/3", true), 0);
	assert_cmd(5, "01 00 0F 00 00 00 AB 02 00 82 00 00 08 00 08 00");
	assert_int_equal(df1_read_bit(h, 1, "I1:0.1/2", &b), 0);
	assert_cmd(6, "01 00 0F 00 00 00 A2 02 01 83 00 01");
	/* other files keep their codes; the public code table is the recommendation */
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), 1);
	assert_cmd(7, "01 00 0F 00 00 00 A2 02 07 89 00 00");
	assert_int_equal(df1_read_int16(h, 1, "S2:1", &v, 1), 1);
	assert_cmd(8, "01 00 0F 00 00 00 A2 02 02 84 01 00");
	assert_int_equal(df1_file_type_slc_code(DF1_FT_O), 0x8B);
	assert_int_equal(df1_file_type_slc_code(DF1_FT_I), 0x8C);
	/* and back */
	assert_int_equal(df1_set_option(h, DF1_OPT_SLC_IO_CODES_82, 0), 0);
	assert_int_equal(df1_read_int16(h, 1, "O0:0", &v, 1), 1);
	assert_cmd(9, "01 00 0F 00 00 00 A2 02 00 8B 00 00");
}

/* ------------------------------------------------------------------------
 * PLC-5
 * ------------------------------------------------------------------------ */

static void test_client_plc5_typed_read_vector(void **state)
{
	df1_t *h = *state;
	int16_t v[10];

	set_plc(h, DF1_PLC_PLC5);
	h->next_tns = 6;
	script_raw_hex("00 01 4F 00 06 00 99 09 15 42 00 00 01 00 02 00 03 00 04 00 05 00 06 00 "
	               "07 00 08 00 09 00");
	assert_int_equal(df1_read_int16(h, 1, "N7:0", v, 10), 10);
	assert_wire(0, DF1_CHECK_BCC,
	            "10 02 01 00 0F 00 06 00 68 00 00 0A 00 06 07 00 0A 00 10 03 61");
	assert_wire(0, DF1_CHECK_CRC,
	            "10 02 01 00 0F 00 06 00 68 00 00 0A 00 06 07 00 0A 00 10 03 96 E9");
	for (int i = 0; i < 10; i++)
		assert_int_equal(v[i], i);
}

static void test_client_plc5_typed_read_ascii_vector(void **state)
{
	df1_t *h = *state;
	int16_t v;

	set_plc(h, DF1_PLC_PLC5);
	h->next_tns = 7;
	script_data_hex("42 2A 00");        /* a single integer, not an array */
	assert_int_equal(df1_read_int16(h, 1, "$N7:0", &v, 1), 1);
	assert_wire(0, DF1_CHECK_BCC,
	            "10 02 01 00 0F 00 07 00 68 00 00 01 00 00 24 4E 37 3A 30 00 01 00 10 03 6C");
	assert_wire(0, DF1_CHECK_CRC,
	            "10 02 01 00 0F 00 07 00 68 00 00 01 00 00 24 4E 37 3A 30 00 01 00 10 03 5C F9");
	assert_int_equal(v, 42);
}

static void test_client_plc5_typed_write_vector(void **state)
{
	df1_t *h = *state;
	int16_t v[2] = { 1, 2 };

	set_plc(h, DF1_PLC_PLC5);
	h->next_tns = 8;
	assert_int_equal(df1_write_int16(h, 1, "N7:0", v, 2), 2);
	assert_wire(0, DF1_CHECK_BCC,
	            "10 02 01 00 0F 00 08 00 67 00 00 02 00 06 07 00 99 09 05 42 01 00 02 00 10 03 86");
	assert_wire(0, DF1_CHECK_CRC,
	            "10 02 01 00 0F 00 08 00 67 00 00 02 00 06 07 00 99 09 05 42 01 00 02 00 10 03 DB 8C");
	assert_int_equal(le16(mem_at(7, 2, 2)), 2);
}

static void test_client_plc5_rmw_bits_vector(void **state)
{
	df1_t *h = *state;
	bool b;

	set_plc(h, DF1_PLC_PLC5);
	put_le16(mem_at(7, 0, 2), 0x8100);
	h->next_tns = 0x0A;
	assert_int_equal(df1_write_bit(h, 1, "N7:0/3", true), 0);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 0A 00 26 06 07 00 FF FF 08 00 10 03 AD");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 0A 00 26 06 07 00 FF FF 08 00 10 03 55 9F");
	assert_int_equal(le16(mem_at(7, 0, 2)), 0x8108);
	assert_int_equal(df1_write_bit(h, 1, "N7:0/15", false), 0);
	assert_cmd(1, "01 00 0F 00 00 00 26 06 07 00 FF 7F 00 00");
	assert_int_equal(le16(mem_at(7, 0, 2)), 0x0108);
	assert_int_equal(df1_read_bit(h, 1, "N7:0/8", &b), 0);
	assert_cmd(2, "01 00 0F 00 00 00 68 00 00 01 00 06 07 00 01 00");
	assert_true(b);
	/* T4:1/DN on a PLC-5: the control word is sub-element 0 (level 4) */
	assert_int_equal(df1_write_bit(h, 1, "T4:1/DN", true), 0);
	assert_cmd(3, "01 00 0F 00 00 00 26 0E 04 01 00 FF FF 00 20");
}

/* PLC-5 typed-read T/C/R elements of 5 words (KF2 p.130, VME p.81; doc/PROTOCOL.md 4.3).
 * The type/data flag byte (doc/PROTOCOL.md 4.3): bits 7-4 the type ID, bits 3-0 the size;
 * size field 1001b = one size byte follows. So a 10-byte timer (ID 5) is
 * 0101 1001 = 59, then 0A; a counter (ID 6) 69 0A, a control (ID 7) 79 0A.
 * An array of n of them: 99 09 LL 59 0A with LL = 2 + 10n (the descriptor's
 * two bytes and the data). Words 0-2 are CTL, PRE/LEN, ACC/POS; words 3-4 are
 * set to 1234h 5678h here to show they are ignored. Commands: T4:1 = logical
 * binary 06 04 01 (doc/PROTOCOL.md 4.1), PKT_OFFSET TOTAL_TRANS SIZE LE; the wire frames'
 * BCC and CRC worked out with doc/PROTOCOL.md 7.5's rules. */
static void test_client_plc5_tcr_5_words_vector(void **state)
{
	df1_t *h = *state;
	struct df1_tcr t[2];
	struct df1_value v;
	int16_t w[2];
	bool b;

	set_plc(h, DF1_PLC_PLC5);
	/* T4:1, one element, the reply a single 5-word timer (no array) */
	h->next_tns = 0x31;
	script_raw_hex("00 01 4F 00 31 00 59 0A 00 E0 64 00 2A 00 34 12 78 56");
	assert_int_equal(df1_read_tcr(h, 1, "T4:1", t, 1), 1);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 31 00 68 00 00 01 00 06 04 01 01 00 10 03 4A");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 31 00 68 00 00 01 00 06 04 01 01 00 10 03 A9 D3");
	assert_int_equal(t[0].ctl, 0xE000);
	assert_int_equal(t[0].pre, 100);
	assert_int_equal(t[0].acc, 42);
	/* T4:0 x 2 as an array: 99 09 16 59 0A (LL = 2 + 20 = 22) */
	h->next_tns = 0x32;
	script_raw_hex("00 01 4F 00 32 00 99 09 16 59 0A "
	               "00 20 0A 00 05 00 34 12 78 56 "         /* T4:0: DN, PRE 10, ACC 5 */
	               "00 80 F4 01 FF FF 34 12 78 56");        /* T4:1: EN, PRE 500, ACC -1 */
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 2), 2);
	assert_wire(1, DF1_CHECK_BCC, "10 02 01 00 0F 00 32 00 68 00 00 02 00 06 04 00 02 00 10 03 48");
	assert_wire(1, DF1_CHECK_CRC, "10 02 01 00 0F 00 32 00 68 00 00 02 00 06 04 00 02 00 10 03 1D F9");
	assert_int_equal(t[0].ctl, 0x2000);
	assert_int_equal(t[0].pre, 10);
	assert_int_equal(t[0].acc, 5);
	assert_int_equal(t[1].ctl, 0x8000);
	assert_int_equal(t[1].pre, 500);
	assert_int_equal(t[1].acc, -1);
	/* a whole element as a value: members and named bits */
	script_raw_hex("00 01 4F 00 00 00 59 0A 00 60 64 00 2A 00 34 12 78 56");
	assert_int_equal(df1_read(h, 1, "T4:1", &v, 1), 1);
	assert_int_equal(v.kind, DF1_VAL_TCR);
	assert_int_equal(v.v.tcr.ctl, 0x6000);      /* TT DN, not EN */
	assert_int_equal(v.v.tcr.pre, 100);
	assert_int_equal(v.v.tcr.acc, 42);
	/* .ACC of two timers: whole elements read, word 2 of each kept */
	script_raw_hex("00 01 4F 00 00 00 99 09 16 59 0A "
	               "00 20 0A 00 05 00 34 12 78 56 00 80 F4 01 FF FF 34 12 78 56");
	assert_int_equal(df1_read_int16(h, 1, "T4:0.ACC", w, 2), 2);
	assert_cmd(3, "01 00 0F 00 00 00 68 00 00 02 00 06 04 00 02 00");
	assert_int_equal(w[0], 5);
	assert_int_equal(w[1], -1);
	script_raw_hex("00 01 4F 00 00 00 99 09 16 59 0A "
	               "00 20 0A 00 05 00 34 12 78 56 00 80 F4 01 FF FF 34 12 78 56");
	assert_int_equal(df1_read_int16(h, 1, "T4:0.PRE", w, 2), 2);
	assert_int_equal(w[0], 10);
	assert_int_equal(w[1], 500);
	/* counter C5:0 (69 0A): CU OV, PRE 7, ACC -3; control R6:2 (79 0A): DN, LEN 9, POS 4 */
	script_raw_hex("00 01 4F 00 00 00 69 0A 00 90 07 00 FD FF 34 12 78 56");
	assert_int_equal(df1_read_tcr(h, 1, "C5:0", t, 1), 1);
	assert_cmd(5, "01 00 0F 00 00 00 68 00 00 01 00 06 05 00 01 00");
	assert_int_equal(t[0].ctl, 0x9000);
	assert_int_equal(t[0].pre, 7);
	assert_int_equal(t[0].acc, -3);
	script_raw_hex("00 01 4F 00 00 00 79 0A 00 20 09 00 04 00 34 12 78 56");
	assert_int_equal(df1_read(h, 1, "R6:2", &v, 1), 1);
	assert_int_equal(v.v.tcr.ctl, 0x2000);
	assert_int_equal(v.v.tcr.pre, 9);
	assert_int_equal(v.v.tcr.acc, 4);
	/* C5:0/OV of a 5-word counter: the whole element is not needed, the bit
	 * read asks for the control word (level 4 = 0) and gets an integer */
	script_raw_hex("00 01 4F 00 00 00 42 00 90");
	assert_int_equal(df1_read_bit(h, 1, "C5:0/OV", &b), 0);
	assert_cmd(7, "01 00 0F 00 00 00 68 00 00 01 00 0E 05 00 00 01 00");
	assert_true(b);
	/* 4 words (59 08) is neither form */
	script_raw_hex("00 01 4F 00 00 00 59 08 00 E0 64 00 2A 00 00 00");
	assert_int_equal(df1_read_tcr(h, 1, "T4:1", t, 1), DF1_E_BAD_REPLY);
	assert_non_null(strstr(df1_last_error(h)->message, "8 bytes, expected 6 or 10"));
}

/* A PLC-5 cuts a typed-read reply to 240 bytes (doc/PROTOCOL.md 6): 38 timers asked after
 * T4:0's 3-byte address, 23 five-word timers come (3 + 5 + 230 = 238; 24: 248):
 * the client takes them and asks for the other 15 at PKT_OFFSET 23 (17h),
 * TOTAL_TRANS 38 (26h). A reply of fewer that is not full is refused. */
static void test_client_plc5_timer_5_words_full_reply(void **state)
{
	df1_t *h = *state;
	static struct df1_tcr t[38];
	struct script *sc;

	set_plc(h, DF1_PLC_PLC5);
	h->next_tns = 0x35;
	for (int part = 0; part < 2; part++) {
		size_t n = part ? 15 : 23, k = 0;

		sc = script_add(SC_RAW);
		sc->b[k++] = 0x00; sc->b[k++] = 0x01; sc->b[k++] = 0x4F; sc->b[k++] = 0x00;
		sc->b[k++] = (uint8_t)(0x35 + part); sc->b[k++] = 0x00;
		sc->b[k++] = 0x99; sc->b[k++] = 0x09; sc->b[k++] = (uint8_t)(2 + 10 * n);
		sc->b[k++] = 0x59; sc->b[k++] = 0x0A;
		for (size_t i = 0; i < n; i++) {
			size_t e = (part ? 23 : 0) + i;

			put_le16(sc->b + k, 0x2000);            /* DN */
			put_le16(sc->b + k + 2, (uint16_t)(1000 + e));
			put_le16(sc->b + k + 4, (uint16_t)e);
			put_le16(sc->b + k + 6, 0x1234);
			put_le16(sc->b + k + 8, 0x5678);
			k += 10;
		}
		sc->n = k;
	}
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 38), 38);
	assert_int_equal(ncmds, 2);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 35 00 68 00 00 26 00 06 04 00 26 00 10 03 FD");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 35 00 68 00 00 26 00 06 04 00 26 00 10 03 55 5E");
	assert_wire(1, DF1_CHECK_BCC, "10 02 01 00 0F 00 36 00 68 17 00 26 00 06 04 00 0F 00 10 03 FC");
	assert_wire(1, DF1_CHECK_CRC, "10 02 01 00 0F 00 36 00 68 17 00 26 00 06 04 00 0F 00 10 03 31 1A");
	for (int e = 0; e < 38; e++) {
		assert_int_equal(t[e].ctl, 0x2000);
		assert_int_equal(t[e].pre, 1000 + e);
		assert_int_equal(t[e].acc, e);
	}
	/* 10 five-word timers when asked: not a full reply (station 1 is now known to
	 * send 5-word timers, so 23 were asked) */
	mock_reset();
	script_raw_hex("00 01 4F 00 00 00 99 09 66 59 0A "
	               "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 "
	               "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 "
	               "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 "
	               "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 "
	               "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00");
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 38), DF1_E_BAD_REPLY);
	assert_non_null(strstr(df1_last_error(h)->message, "reply has 10 elements, asked 23"));
	/* told the PLC sends 5 words (DF1_OPT_PLC5_TIMER_WORDS), it asks for 23 at once */
	mock_reset();
	assert_int_equal(df1_set_option(h, DF1_OPT_PLC5_TIMER_WORDS, 5), 0);
	plc5_ftype[4] = 'T';
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 38), 38);
	assert_int_equal(ncmds, 2);
	assert_cmd(0, "01 00 0F 00 00 00 68 00 00 26 00 06 04 00 17 00");
	assert_cmd(1, "01 00 0F 00 00 00 68 17 00 26 00 06 04 00 0F 00");
	/* counters and controls stay planned at 3 words: 38 in one */
	plc5_ftype[5] = 'C';
	assert_int_equal(df1_read_tcr(h, 1, "C5:0", t, 38), 38);
	assert_cmd(2, "01 00 0F 00 00 00 68 00 00 26 00 06 05 00 26 00");
}

/* One reply of n five-word timers (59 0A, KF2 p.130) from element first on:
 * CTL DN, PRE 1000 + e, ACC e, two more words. */
static void script_timers5(size_t first, size_t n)
{
	struct script *sc = script_add(SC_DATA);
	size_t k = 0;

	sc->b[k++] = 0x99; sc->b[k++] = 0x09; sc->b[k++] = (uint8_t)(2 + 10 * n);
	sc->b[k++] = 0x59; sc->b[k++] = 0x0A;
	for (size_t i = 0; i < n; i++) {
		size_t e = first + i;

		put_le16(sc->b + k, 0x2000);
		put_le16(sc->b + k + 2, (uint16_t)(1000 + e));
		put_le16(sc->b + k + 4, (uint16_t)e);
		put_le16(sc->b + k + 6, 0x1234);
		put_le16(sc->b + k + 8, 0x5678);
		k += 10;
	}
	sc->n = k;
}

static void assert_timers(const struct df1_tcr *t, size_t n)
{
	for (size_t e = 0; e < n; e++) {
		assert_int_equal(t[e].ctl, 0x2000);
		assert_int_equal(t[e].pre, 1000 + e);
		assert_int_equal(t[e].acc, e);
	}
}

/* A PLC-5 with 5-word timers that refuses, rather than cuts, a reply too large:
 * 38 timers planned at 3 words get STS F0 EXT STS 09 (data too large); the
 * packet goes again asking for 23 (5-word plan: 3 + 5 + 230 = 238), then the
 * other 15 at PKT_OFFSET 17h. Frames worked out by hand from doc/PROTOCOL.md 4.2
 * (BCC: two's complement of the sum; CRC-16 over the bytes and ETX). Station 1
 * is then known to send 5 words: its next read asks for 23 at once; station 2
 * still starts at 38. */
static void test_client_plc5_timer_refused_planned_again(void **state)
{
	df1_t *h = *state;
	static struct df1_tcr t[38];

	set_plc(h, DF1_PLC_PLC5);
	plc5_ftype[4] = 'T';
	h->next_tns = 0x40;
	script_sts(0xF0, 0x09, true);
	script_timers5(0, 23);
	script_timers5(23, 15);
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 38), 38);
	assert_int_equal(ncmds, 3);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 40 00 68 00 00 26 00 06 04 00 26 00 10 03 F2");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 40 00 68 00 00 26 00 06 04 00 26 00 10 03 E6 6B");
	assert_wire(1, DF1_CHECK_BCC, "10 02 01 00 0F 00 41 00 68 00 00 26 00 06 04 00 17 00 10 03 00");
	assert_wire(1, DF1_CHECK_CRC, "10 02 01 00 0F 00 41 00 68 00 00 26 00 06 04 00 17 00 10 03 B5 25");
	assert_wire(2, DF1_CHECK_BCC, "10 02 01 00 0F 00 42 00 68 17 00 26 00 06 04 00 0F 00 10 03 F0");
	assert_wire(2, DF1_CHECK_CRC, "10 02 01 00 0F 00 42 00 68 17 00 26 00 06 04 00 0F 00 10 03 80 AE");
	assert_timers(t, 38);
	assert_int_equal(df1_get_option(h, DF1_OPT_PLC5_TIMER_WORDS), 3);   /* the option is not changed */

	/* learned for station 1: 23 at once, no refusal needed */
	memset(t, 0, sizeof t);
	script_timers5(0, 23);
	script_timers5(23, 15);
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 38), 38);
	assert_int_equal(ncmds, 5);
	assert_cmd(3, "01 00 0F 00 00 00 68 00 00 26 00 06 04 00 17 00");
	assert_cmd(4, "01 00 0F 00 00 00 68 17 00 26 00 06 04 00 0F 00");
	assert_timers(t, 38);

	/* station 2 has told nothing yet: 38 asked (from the mock's 3-word table) */
	assert_int_equal(df1_read_tcr(h, 2, "T4:0", t, 38), 38);
	assert_int_equal(ncmds, 6);
	assert_cmd(5, "02 00 0F 00 00 00 68 00 00 26 00 06 04 00 26 00");
}

/* The refusal is final when the option forces the size, and when the refused
 * packet asked no more than a 5-word plan would (then it is not the timer size). */
static void test_client_plc5_timer_refused_final(void **state)
{
	df1_t *h = *state;
	static struct df1_tcr t[38];

	set_plc(h, DF1_PLC_PLC5);
	plc5_ftype[4] = 'T';
	/* 10 timers: one packet either way */
	script_sts(0xF0, 0x09, true);
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 10), DF1_E_REMOTE);
	assert_int_equal(ncmds, 1);
	assert_int_equal(df1_last_error(h)->ext_sts, 0x09);
	/* another EXT STS is not about the size */
	script_sts(0xF0, 0x06, true);
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 38), DF1_E_REMOTE);
	assert_int_equal(ncmds, 2);
	/* --plc5-timer-words 3 given: no second try */
	assert_int_equal(df1_set_option(h, DF1_OPT_PLC5_TIMER_WORDS, 3), 0);
	script_sts(0xF0, 0x09, true);
	assert_int_equal(df1_read_tcr(h, 1, "T4:0", t, 38), DF1_E_REMOTE);
	assert_int_equal(ncmds, 3);
	assert_cmd(2, "01 00 0F 00 00 00 68 00 00 26 00 06 04 00 26 00");
}

/* ------------------------------------------------------------------------
 * Packet boundaries (doc/PROTOCOL.md 6): for every PLC type and file type, the largest
 * count goes in one packet and one more in two. The counts are worked out
 * here from the spec's rules, not taken from the library:
 *   SLC 5/03+ and MicroLogix: A2 read data <= 236, AA write data <= 234;
 *   SLC 5/01-5/02: 82 both ways; PLC-2: 01 SIZE <= 244, 08 data <= 244;
 *   PLC-5 typed read reply / typed write: address + type/data + data <= 240.
 *     Address (doc/PROTOCOL.md 4.1): N7:0 = 06 07 00 (3 bytes), N7:300 = 06 07 FF 2C 01
 *     (5), N300:0 = 06 FF 2C 01 00 (5). Type/data of an array (doc/PROTOCOL.md 4.3):
 *     99 09 LL (3 bytes: the array size LL = descriptor + data <= 255) + the
 *     element descriptor: 42 integer, 44 long, 56 timer, 66 counter, 76
 *     control (1 byte), 94 08 float (2 bytes).
 *     N7:0   3 + 4 + 2n <= 240: n <= 116   (117: 241)
 *     N7:300 5 + 4 + 2n <= 240: n <= 115
 *     F8:0   3 + 5 + 4n <= 240: n <= 58    (59: 244)
 *     L9:0   3 + 4 + 4n <= 240: n <= 58
 *     T4:0   3 + 4 + 6n <= 240: n <= 38    (39: 241); C and R the same
 *     ST: one string per packet.
 * ------------------------------------------------------------------------ */

struct bound {
	enum df1_plc plc;
	const char *addr;
	char ftype;             /* the mock PLC-5's file type (0: N) */
	unsigned file;
	size_t rmax, wmax;      /* elements in one read / write packet */
};

static const struct bound bounds[] = {
	{ DF1_PLC_SLC, "N7:0", 0, 7, 118, 117 },
	{ DF1_PLC_SLC, "B3:0", 0, 3, 118, 117 },
	{ DF1_PLC_SLC, "F8:0", 0, 8, 59, 58 },
	{ DF1_PLC_SLC, "L10:0", 0, 10, 59, 58 },
	{ DF1_PLC_SLC, "T4:0", 0, 4, 39, 39 },
	{ DF1_PLC_SLC, "C5:0", 0, 5, 39, 39 },
	{ DF1_PLC_SLC, "R6:0", 0, 6, 39, 39 },
	{ DF1_PLC_SLC, "ST9:0", 0, 9, 2, 2 },
	{ DF1_PLC_MICROLOGIX, "N7:0", 0, 7, 118, 117 },
	{ DF1_PLC_MICROLOGIX, "F8:0", 0, 8, 59, 58 },
	{ DF1_PLC_MICROLOGIX, "T4:0", 0, 4, 39, 39 },
	{ DF1_PLC_SLC502, "N7:0", 0, 7, 41, 41 },
	{ DF1_PLC_SLC502, "F8:0", 0, 8, 20, 20 },
	{ DF1_PLC_SLC502, "T4:0", 0, 4, 13, 13 },
	{ DF1_PLC_PLC2, "N7:0", 0, 7, 122, 122 },
	{ DF1_PLC_PLC5, "N7:0", 'N', 7, 116, 116 },
	{ DF1_PLC_PLC5, "N7:300", 'N', 7, 115, 115 },
	{ DF1_PLC_PLC5, "N300:0", 'N', 300, 115, 115 },
	{ DF1_PLC_PLC5, "B3:0", 'N', 3, 116, 116 },
	{ DF1_PLC_PLC5, "F8:0", 'F', 8, 58, 58 },
	{ DF1_PLC_PLC5, "L9:0", 'L', 9, 58, 58 },
	{ DF1_PLC_PLC5, "T4:0", 'T', 4, 38, 38 },
	{ DF1_PLC_PLC5, "C5:0", 'C', 5, 38, 38 },
	{ DF1_PLC_PLC5, "R6:0", 'R', 6, 38, 38 },
	{ DF1_PLC_PLC5, "ST9:0", 'S', 9, 1, 1 },
};

/* PLC-5 command i: address + type/data + data of a 0F/67 within 240 bytes. */
static void assert_plc5_write_fits(size_t i)
{
	assert_true(i < ncmds);
	assert_int_equal(cmds[i].b[6], 0x67);
	/* header 6, FNC 1, PKT_OFFSET 2, TOTAL_TRANS 2 */
	assert_true(cmds[i].n - PCCC_HDR_LEN - 5 <= 240);
}

static void test_client_packet_boundaries(void **state)
{
	df1_t *h = *state;
	static struct df1_value v[130];

	for (size_t b = 0; b < sizeof bounds / sizeof bounds[0]; b++) {
		const struct bound *c = &bounds[b];

		print_message("%s %s: read %zu, write %zu per packet\n",
		              c->plc == DF1_PLC_PLC5 ? "plc5" : c->plc == DF1_PLC_PLC2 ? "plc2" :
		              c->plc == DF1_PLC_SLC502 ? "slc502" : "slc", c->addr, c->rmax, c->wmax);
		set_plc(h, c->plc);
		if (c->ftype)
			plc5_ftype[c->file % FILES] = c->ftype;
		for (size_t extra = 0; extra < 2; extra++) {
			size_t n = c->rmax + extra, w = c->wmax + extra;

			ncmds = 0;
			assert_int_equal(df1_read(h, 1, c->addr, v, n), (int)n);
			if (ncmds != 1 + extra)
				fail_msg("%s read of %zu: %zu commands, want %zu", c->addr, n, ncmds, 1 + extra);
			if (c->plc == DF1_PLC_PLC5 && c->ftype != 'S')
				/* ELEMENTS of the first packet, after the 3- or 5-byte address */
				assert_int_equal(le16(cmds[0].b + cmds[0].n - 2), c->rmax);
			ncmds = 0;
			assert_int_equal(df1_write(h, 1, c->addr, v, w), (int)w);
			if (ncmds != 1 + extra)
				fail_msg("%s write of %zu: %zu commands, want %zu", c->addr, w, ncmds, 1 + extra);
			if (c->plc == DF1_PLC_PLC5)
				for (size_t i = 0; i < ncmds; i++)
					assert_plc5_write_fits(i);
		}
		plc5_ftype[c->file % FILES] = 'N';
	}
}

static void test_client_plc5_split_300(void **state)
{
	df1_t *h = *state;
	int16_t v[300];

	set_plc(h, DF1_PLC_PLC5);
	fill_words(7, 300);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", v, 300), 300);
	/* 3 address + 4 type/data (99 09 E9 42) + 2 * 116 = 239 <= 240: 116 per
	 * packet (doc/PROTOCOL.md 6), offsets in elements */
	assert_int_equal(ncmds, 3);
	assert_cmd(0, "01 00 0F 00 00 00 68 00 00 2C 01 06 07 00 74 00");
	assert_cmd(1, "01 00 0F 00 00 00 68 74 00 2C 01 06 07 00 74 00");
	assert_cmd(2, "01 00 0F 00 00 00 68 E8 00 2C 01 06 07 00 44 00");
	for (int i = 0; i < 300; i++)
		assert_int_equal(v[i], i);
	/* write: (240 - 3 - 4 type/data) / 2 = 116 */
	for (int i = 0; i < 300; i++)
		v[i] = (int16_t)(-i);
	assert_int_equal(df1_write_int16(h, 1, "N7:0", v, 300), 300);
	assert_int_equal(ncmds, 6);
	assert_memory_equal(cmds[3].b + 6, "\x67\x00\x00\x2C\x01\x06\x07\x00\x99\x09\xE9\x42", 12);
	assert_memory_equal(cmds[4].b + 6, "\x67\x74\x00\x2C\x01\x06\x07\x00\x99\x09\xE9\x42", 12);
	assert_memory_equal(cmds[5].b + 6, "\x67\xE8\x00\x2C\x01\x06\x07\x00\x99\x09\x89\x42", 12);
	assert_true(cmds[3].n - PCCC_HDR_LEN - 5 <= 240);   /* address + type/data + data */
	for (int i = 0; i < 300; i++)
		assert_int_equal((int16_t)le16(mem_at(7, (size_t)i * 2, 2)), -i);
}

static void test_client_plc5_float_and_timer(void **state)
{
	df1_t *h = *state;
	float f[2] = { 1.5f, -2.0f }, r[2];
	struct df1_tcr t;
	int16_t w[2];

	set_plc(h, DF1_PLC_PLC5);
	plc5_ftype[8] = 'F';
	plc5_ftype[4] = 'T';
	assert_int_equal(df1_write_float(h, 1, "F8:0", f, 2), 2);
	/* plain LE floats after 94 08 (doc/PROTOCOL.md 5) */
	assert_cmd(0, "01 00 0F 00 00 00 67 00 00 02 00 06 08 00 99 09 0A 94 08 00 00 C0 3F 00 00 00 C0");
	assert_int_equal(df1_read_float(h, 1, "F8:0", r, 2), 2);
	assert_true(r[0] == 1.5f && r[1] == -2.0f);
	put_le16(mem_at(4, 6, 2), 0xE000);
	put_le16(mem_at(4, 8, 2), 500);
	put_le16(mem_at(4, 10, 2), 123);
	assert_int_equal(df1_read_tcr(h, 1, "T4:1", &t, 1), 1);
	assert_cmd(2, "01 00 0F 00 00 00 68 00 00 01 00 06 04 01 01 00");
	assert_int_equal(t.ctl, 0xE000);
	assert_int_equal(t.pre, 500);
	assert_int_equal(t.acc, 123);
	/* a reply of the wrong type is refused */
	script_data_hex("99 09 05 94 08 00 00 C0 3F");
	assert_int_equal(df1_read_int16(h, 1, "N7:0", w, 1), DF1_E_BAD_REPLY);
	/* fewer elements than asked */
	script_data_hex("99 09 03 42 01 00");
	assert_int_equal(df1_read_int16(h, 1, "N7:0", w, 2), DF1_E_BAD_REPLY);
}

/* PLC-5 typed floats: plain LE by default (doc/PROTOCOL.md 5: 1.5 = 00 00 C0 3F),
 * word-swapped C0 3F 00 00 with DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED. */
static void test_client_plc5_typed_float_swapped_option(void **state)
{
	df1_t *h = *state;
	float f = 1.5f, r = 0;
	float two[2] = { 1.5f, -2.0f };
	struct df1_value v;
	uint8_t raw[4];

	set_plc(h, DF1_PLC_PLC5);
	plc5_ftype[8] = 'F';
	assert_int_equal(df1_get_option(h, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED), 0);
	h->next_tns = 0x30;
	assert_int_equal(df1_write_float(h, 1, "F8:0", &f, 1), 1);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 0F 00 30 00 67 00 00 01 00 06 08 00 99 09 06 94 08 "
	                              "00 00 C0 3F 10 03 07");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 0F 00 30 00 67 00 00 01 00 06 08 00 99 09 06 94 08 "
	                              "00 00 C0 3F 10 03 98 37");
	script_data_hex("99 09 06 94 08 00 00 C0 3F");
	assert_int_equal(df1_read_float(h, 1, "F8:0", &r, 1), 1);
	assert_true(r == 1.5f);

	assert_int_equal(df1_set_option(h, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED, 1), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED), 1);
	h->next_tns = 0x31;
	assert_int_equal(df1_write_float(h, 1, "F8:0", &f, 1), 1);
	assert_wire(2, DF1_CHECK_BCC, "10 02 01 00 0F 00 31 00 67 00 00 01 00 06 08 00 99 09 06 94 08 "
	                              "C0 3F 00 00 10 03 06");
	assert_wire(2, DF1_CHECK_CRC, "10 02 01 00 0F 00 31 00 67 00 00 01 00 06 08 00 99 09 06 94 08 "
	                              "C0 3F 00 00 10 03 B8 2F");
	assert_memory_equal(mem_at(8, 0, 4), "\xC0\x3F\x00\x00", 4);
	/* reads take the swapped order: the typed helper and the generic read */
	script_data_hex("99 09 06 94 08 C0 3F 00 00");
	r = 0;
	assert_int_equal(df1_read_float(h, 1, "F8:0", &r, 1), 1);
	assert_true(r == 1.5f);
	script_data_hex("99 09 06 94 08 00 C0 00 00");           /* -2.0 = C0000000h */
	memset(&v, 0, sizeof v);
	assert_int_equal(df1_read(h, 1, "F8:1", &v, 1), 1);
	assert_int_equal(v.kind, DF1_VAL_FLOAT);
	assert_true(v.v.f == -2.0f);
	/* the plain LE reply now reads as the swapped value: 00 00 C0 3F -> C03F0000h */
	script_data_hex("99 09 06 94 08 00 00 C0 3F");
	assert_int_equal(df1_read_float(h, 1, "F8:0", &r, 1), 1);
	assert_true(r != 1.5f);
	/* two elements, each swapped on its own */
	assert_int_equal(df1_write_float(h, 1, "F8:0", two, 2), 2);
	assert_cmd(6, "01 00 0F 00 00 00 67 00 00 02 00 06 08 00 99 09 0A 94 08 C0 3F 00 00 00 C0 00 00");
	/* raw bytes are the wire bytes either way */
	assert_int_equal(df1_read_raw(h, 1, "F8:1", raw, 4), 4);
	assert_memory_equal(raw, "\x00\xC0\x00\x00", 4);
	/* integers are untouched */
	assert_int_equal(df1_write_int16(h, 1, "N7:0", (const int16_t[]){ 0x1234 }, 1), 1);
	assert_cmd(8, "01 00 0F 00 00 00 67 00 00 01 00 06 07 00 99 09 03 42 34 12");
	/* SLC A2/AA floats stay plain LE whatever the option says */
	set_plc(h, DF1_PLC_SLC);
	assert_int_equal(df1_write_float(h, 1, "F8:0", &f, 1), 1);
	assert_cmd(9, "01 00 0F 00 00 00 AA 04 08 8A 00 00 00 00 C0 3F");
}

static void test_client_plc5_strings_one_per_packet(void **state)
{
	df1_t *h = *state;
	struct df1_value v[3];
	char s[DF1_STRING_MAX + 1];

	set_plc(h, DF1_PLC_PLC5);
	plc5_ftype[9] = 'S';
	memset(v, 0, sizeof v);
	for (int i = 0; i < 3; i++) {
		v[i].kind = DF1_VAL_STRING;
		v[i].v.str.len = 3;
		memcpy(v[i].v.str.text, "AB0", 4);
		v[i].v.str.text[2] = (char)('0' + i);
	}
	assert_int_equal(df1_write(h, 1, "ST9:0", v, 3), 3);
	assert_int_equal(ncmds, 3);
	assert_cmd(0, "01 00 0F 00 00 00 67 00 00 03 00 06 09 00 33 41 42 30");
	assert_cmd(2, "01 00 0F 00 00 00 67 02 00 03 00 06 09 00 33 41 42 32");
	/* stored as the 84-byte element */
	assert_memory_equal(mem_at(9, 84, 6), "\x03\x00\x42\x41\x00\x31", 6);
	memset(v, 0, sizeof v);
	assert_int_equal(df1_read(h, 1, "ST9:0", v, 3), 3);
	assert_int_equal(ncmds, 6);
	assert_cmd(3, "01 00 0F 00 00 00 68 00 00 03 00 06 09 00 01 00");
	assert_cmd(5, "01 00 0F 00 00 00 68 02 00 03 00 06 09 00 01 00");
	assert_string_equal(v[2].v.str.text, "AB2");
	assert_int_equal(v[2].v.str.len, 3);
	assert_int_equal(df1_read_string(h, 1, "ST9:1", s, sizeof s), 3);
	assert_string_equal(s, "AB1");
}

/* ------------------------------------------------------------------------
 * PLC-2
 * ------------------------------------------------------------------------ */

static void test_client_plc2_ke_vectors(void **state)
{
	df1_t *h = *state;
	int16_t w[4] = { 0x1122, 0x3344, 0x5566, 0x7788 }, r[4];

	set_plc(h, DF1_PLC_PLC2);
	assert_int_equal(df1_set_station(h, 0x20), 0);
	/* KE p.48: unprotected write, byte address 0028 = word 20 */
	h->next_tns = 0x0144;
	assert_int_equal(df1_write_int16(h, 0x29, "N7:20", w, 4), 4);
	assert_wire(0, DF1_CHECK_BCC,
	            "10 02 29 20 08 00 44 01 28 00 22 11 44 33 66 55 88 77 10 03 DE");
	/* KE p.49: unprotected read of 8 bytes, and its reply */
	h->next_tns = 0x0145;
	script_raw_hex("20 29 41 00 45 01 22 11 44 33 66 55 88 77");
	assert_int_equal(df1_read_int16(h, 0x29, "N7:20", r, 4), 4);
	assert_wire(1, DF1_CHECK_BCC, "10 02 29 20 01 00 45 01 28 00 08 10 03 40");
	assert_wire(1, DF1_CHECK_CRC, "10 02 29 20 01 00 45 01 28 00 08 10 03 F4 7C");
	assert_memory_equal(r, w, sizeof w);
	/* bit 9 of word 20 = bit 1 of byte 0029: 05 ADDR SET RESET */
	assert_int_equal(df1_write_bit(h, 0x29, "N7:20/9", true), 0);
	assert_cmd(2, "29 20 05 00 00 00 29 00 02 00");
	assert_int_equal(plc2_mem[0x29], 0x13);
	assert_int_equal(plc2_mem[0x28], 0x22);
	assert_int_equal(df1_write_bit(h, 0x29, "N7:20/1", false), 0);
	assert_cmd(3, "29 20 05 00 00 00 28 00 00 02");
	assert_int_equal(plc2_mem[0x28], 0x20);
	/* only words */
	assert_int_equal(df1_read_float(h, 0x29, "F8:0", (float *)r, 1), DF1_E_NOTSUP);
	/* 244 bytes per packet */
	{
		int16_t big[130];

		assert_int_equal(df1_read_int16(h, 0x29, "N7:0", big, 130), 130);
		assert_int_equal(ncmds, 6);
		assert_cmd(4, "29 20 01 00 00 00 00 00 F4");
		assert_cmd(5, "29 20 01 00 00 00 F4 00 10");
	}
}

/* DF1_OPT_PLC2_WORD_ADDR (doc/PROTOCOL.md 4.7: the common interface file of an SLC or a
 * MicroLogix with S:2/8 = 0 takes the word offset): the KE vectors with word
 * 20 = 0014h where the byte address was 0028h (frames' BCC/CRC per doc/PROTOCOL.md 7.5);
 * SIZE stays in bytes; N7:5 is address 0005h, not 000Ah; the 05 bit write,
 * whose blocks address bytes, is refused before anything is sent. */
static void test_client_plc2_word_addresses(void **state)
{
	df1_t *h = *state;
	int16_t w[4] = { 0x1122, 0x3344, 0x5566, 0x7788 }, r[4];

	set_plc(h, DF1_PLC_PLC2);
	assert_int_equal(df1_set_station(h, 0x20), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_PLC2_WORD_ADDR, 1), 0);
	h->next_tns = 0x0144;
	assert_int_equal(df1_write_int16(h, 0x29, "N7:20", w, 4), 4);
	assert_wire(0, DF1_CHECK_BCC,
	            "10 02 29 20 08 00 44 01 14 00 22 11 44 33 66 55 88 77 10 03 F2");
	assert_wire(0, DF1_CHECK_CRC,
	            "10 02 29 20 08 00 44 01 14 00 22 11 44 33 66 55 88 77 10 03 2D 88");
	h->next_tns = 0x0145;
	script_raw_hex("20 29 41 00 45 01 22 11 44 33 66 55 88 77");
	assert_int_equal(df1_read_int16(h, 0x29, "N7:20", r, 4), 4);
	assert_wire(1, DF1_CHECK_BCC, "10 02 29 20 01 00 45 01 14 00 08 10 03 54");
	assert_wire(1, DF1_CHECK_CRC, "10 02 29 20 01 00 45 01 14 00 08 10 03 F8 2C");
	assert_memory_equal(r, w, sizeof w);
	script_raw_hex("20 29 41 00 00 00 2B 02");
	assert_int_equal(df1_read_int16(h, 0x29, "N7:5", r, 1), 1);
	assert_cmd(2, "29 20 01 00 00 00 05 00 02");
	assert_int_equal(r[0], 555);
	assert_int_equal(df1_write_bit(h, 0x29, "N7:20/9", true), DF1_E_NOTSUP);
	assert_int_equal(ncmds, 3);
	/* word offsets reach 65535; bytes stop at word 32767 */
	script_raw_hex("20 29 41 00 00 00 01 00");
	assert_int_equal(df1_read_int16(h, 0x29, "N7:999", r, 1), 1);
	assert_cmd(3, "29 20 01 00 00 00 E7 03 02");
	/* and bytes again (the default): N7:5 = 000Ah */
	assert_int_equal(df1_set_option(h, DF1_OPT_PLC2_WORD_ADDR, 0), 0);
	script_raw_hex("20 29 41 00 00 00 2B 02");
	assert_int_equal(df1_read_int16(h, 0x29, "N7:5", r, 1), 1);
	assert_cmd(4, "29 20 01 00 00 00 0A 00 02");
}

/* ------------------------------------------------------------------------
 * Diagnostics and generic commands
 * ------------------------------------------------------------------------ */

static void test_client_diag_echo_mode(void **state)
{
	df1_t *h = *state;
	struct df1_diag_status ds;
	uint8_t a = 'A', rep[8];

	h->next_tns = 0x0B;
	/* SLC layout (M p.174): mode, EE, 1F, type 5B, series/rev, bulletin (11), major
	 * error word, mode/status word (mode 6 = run) */
	script_data_hex("00 EE 1F 5B 25 35 2F 30 34 20 20 20 20 20 20 20 00 00 06 00");
	assert_int_equal(df1_diag_status(h, 1, &ds), 0);
	assert_wire(0, DF1_CHECK_BCC, "10 02 01 00 06 00 0B 00 03 10 03 EB");
	assert_wire(0, DF1_CHECK_CRC, "10 02 01 00 06 00 0B 00 03 10 03 83 7F");
	assert_int_equal(ds.type_code, 0x5B);
	assert_int_equal(ds.mode, 6);

	h->next_tns = 0x0C;
	assert_int_equal(df1_echo(h, 1, &a, 1), 1);
	assert_wire(1, DF1_CHECK_BCC, "10 02 01 00 06 00 0C 00 00 41 10 03 AC");
	assert_wire(1, DF1_CHECK_CRC, "10 02 01 00 06 00 0C 00 00 41 10 03 0B C0");
	script_data_hex("42");
	assert_int_equal(df1_echo(h, 1, &a, 1), DF1_E_BAD_REPLY);
	/* no address: the message names the operation, the address field is empty */
	assert_string_equal(df1_last_error(h)->address, "");
	assert_int_equal(strncmp(df1_last_error(h)->message, "echo: ", 6), 0);

	h->next_tns = 0x0D;
	assert_int_equal(df1_change_mode(h, 1, 6), 0);
	assert_wire(3, DF1_CHECK_BCC, "10 02 01 00 0F 00 0D 00 80 06 10 03 5D");
	assert_wire(3, DF1_CHECK_CRC, "10 02 01 00 0F 00 0D 00 80 06 10 03 9D 18");
	set_plc(h, DF1_PLC_PLC5);
	assert_int_equal(df1_change_mode(h, 1, 1), 0);
	assert_cmd(4, "01 00 0F 00 00 00 3A 00");
	assert_int_equal(df1_change_mode(h, 1, 6), 0);
	assert_cmd(5, "01 00 0F 00 00 00 3A 02");
	assert_int_equal(df1_change_mode(h, 1, 3), DF1_E_INVAL);

	assert_int_equal(df1_link_test(h, 1), 0);
	assert_int_equal(link_test_calls, 1);

	/* generic: 06/03 with the reply data handed back */
	script_data_hex("01 02 03");
	assert_int_equal(df1_command(h, 1, 0x06, (const uint8_t *)"\x03", 1, rep, sizeof rep), 3);
	assert_cmd(6, "01 00 06 00 00 00 03");
	assert_memory_equal(rep, "\x01\x02\x03", 3);
	script_data_hex("01 02 03");
	assert_int_equal(df1_command(h, 1, 0x06, (const uint8_t *)"\x03", 1, rep, 2), DF1_E_NOSPACE);
	/* a link failure of an operation without an address */
	script_link_error(DF1_E_TIMEOUT);
	assert_int_equal(df1_echo(h, 1, &a, 1), DF1_E_TIMEOUT);
	assert_string_equal(df1_last_error(h)->address, "");
	assert_int_equal(strncmp(df1_last_error(h)->message, "echo: ", 6), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_client_slc_read_n7_vector, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_write_n7_5_vector, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_capture_frames, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_bit_set_vector_keeps_other_bits, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_float_decodes_1_5, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_float_reply_vector_through_generic_read, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_remote_error_sts_f0_ext_06, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_short_reply_is_bad_reply, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_wrong_reply_cmd_is_bad_function, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_link_error_names_address, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_type_errors_send_nothing, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_write_value_checked_before_sending, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_300_words_split_236, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_write_300_words_split_234, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_split_on_element_boundaries, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_element_above_254_uses_ff_escape, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc502_and_max_packet_limits, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_tcr_subelements, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_bits_across_words, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_long_and_string, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_raw, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_slc_io_codes_8b_default_82_option, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_typed_read_vector, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_typed_read_ascii_vector, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_typed_write_vector, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_rmw_bits_vector, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_tcr_5_words_vector, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_timer_5_words_full_reply, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_timer_refused_planned_again, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_timer_refused_final, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_split_300, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_packet_boundaries, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_float_and_timer, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_typed_float_swapped_option, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc5_strings_one_per_packet, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc2_ke_vectors, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_plc2_word_addresses, setup, teardown),
		cmocka_unit_test_setup_teardown(test_client_diag_echo_mode, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
