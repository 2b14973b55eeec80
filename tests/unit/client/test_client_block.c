/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_client_block - a block read in two halves (lib/client/client.h:
 * client_read_raw_cmd builds the command, client_read_raw_reply decodes the
 * reply), as the poll engine pipelines it (lib/poll/scan.c).
 *
 * Expected bytes come from tests/data/vectors.txt (a copy of the project's
 * protocol vectors; tests run from the repository root), looked up by name:
 * the command built must be the vector's app bytes (its TNS is the link's, 0
 * until link_pipe_put stamps it), and put on the line (mock port, full duplex,
 * a pipeline of 3) it must be the vector's wire frame exactly. Replies are the
 * vectors' reply frames. The decode half must fail as the ordinary read does:
 * the same code, error detail and counters (compared with df1_read_raw on a
 * handle of its own fed the same reply).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "df1_int.h"
#include "client/client.h"
#include "link/link.h"
#include "support/mock_port.h"
#include "proto/frame.h"

static const uint8_t ACK[2] = { 0x10, 0x06 };

/* ------------------------------------------------------------------------
 * Vectors
 * ------------------------------------------------------------------------ */

struct vec {
	uint8_t wire[FRAME_MAX_WIRE];
	size_t nw;
	uint8_t app[FRAME_MAX_DATA];   /* between DLE STX and DLE ETX, de-stuffed */
	size_t na;
};

/* The vector called name with check chk ("bcc" or "crc"). */
static void vec_load(const char *name, const char *chk, struct vec *v)
{
	FILE *f = fopen("tests/data/vectors.txt", "r");
	char line[2048], want[256];
	bool found = false;

	if (!f)
		fail_msg("cannot open tests/data/vectors.txt (run from the repository root)");
	snprintf(want, sizeof want, "%s | %s | ", name, chk);
	memset(v, 0, sizeof *v);
	while (!found && fgets(line, sizeof line, f)) {
		char *hex, *end;

		if (strncmp(line, want, strlen(want)) != 0)
			continue;
		hex = line + strlen(want);
		end = strstr(hex, " | ");
		assert_non_null(end);
		*end = '\0';
		v->nw = mock_hex(hex, v->wire, sizeof v->wire);
		found = true;
	}
	fclose(f);
	if (!found)
		fail_msg("vector %s (%s) not found", name, chk);
	assert_true(v->nw > 6 && v->wire[0] == 0x10 && v->wire[1] == 0x02);
	for (size_t i = 2; !(v->wire[i] == 0x10 && v->wire[i + 1] == 0x03); i++) {
		if (v->wire[i] == 0x10)
			i++;        /* DLE DLE: one data byte */
		v->app[v->na++] = v->wire[i];
	}
}

/* ------------------------------------------------------------------------
 * Fixture: a full-duplex handle on the mock port
 * ------------------------------------------------------------------------ */

static struct df1 *handle_new(void)
{
	struct df1 *h = NULL;

	assert_int_equal(df1_new(&h), 0);
	h->port = &mock_port_ops;
	h->fd = 0;
	h->cfg.duplex = DF1_FULL_DUPLEX;
	h->cfg.check = DF1_CHECK_CRC;
	h->cfg.timeout_ms = 50;
	h->cfg.cmd_timeout_ms = 500;
	h->cfg.max_outstanding = 3;
	h->cfg.station = 0;
	h->next_tns = 1;
	return h;
}

static void handle_free(struct df1 *h)
{
	h->port = NULL;
	h->fd = -1;
	df1_free(h);
}

static int setup(void **state)
{
	mock_port_reset();
	*state = handle_new();
	return 0;
}

static int teardown(void **state)
{
	handle_free(*state);
	mock_port_reset();
	return 0;
}

static struct df1_addr addr(const char *text)
{
	struct df1_addr a;

	assert_int_equal(df1_addr_parse(text, &a), 0);
	return a;
}

static uint64_t cnt(struct df1 *h, int id)
{
	uint64_t v = 0;

	assert_int_equal(df1_counter(h, id, &v), 0);
	return v;
}

/* The command built for nbytes at text must be vector name's app bytes, TNS 0. */
static void assert_built(struct df1 *h, int station, enum df1_plc plc, const char *text,
                         size_t nbytes, const char *name)
{
	struct df1_addr a = addr(text);
	uint8_t cmd[FRAME_MAX_DATA];
	struct vec v;
	int n;

	vec_load(name, "bcc", &v);
	n = client_read_raw_cmd(h, station, plc, &a, nbytes, cmd, sizeof cmd);
	assert_int_equal(n, (int)v.na);
	assert_int_equal(cmd[4], 0);
	assert_int_equal(cmd[5], 0);
	v.app[4] = v.app[5] = 0;
	assert_memory_equal(cmd, v.app, v.na);
	assert_int_equal(mock_port_writes(), 0); /* built, not sent */
}

/* The reply of vector name decoded for the read of nbytes at text. */
static int decode(struct df1 *h, int station, enum df1_plc plc, const char *text, size_t nbytes,
                  const char *name, uint8_t *buf)
{
	struct df1_addr a = addr(text);
	struct vec v;

	vec_load(name, "bcc", &v);     /* the app bytes: the same under either check */
	return client_read_raw_reply(h, station, plc, &a, buf, nbytes, (int)v.na, v.app);
}

/* ------------------------------------------------------------------------
 * Build: each family's command
 * ------------------------------------------------------------------------ */

static void test_build_slc(void **state)
{
	struct df1 *h = *state;

	assert_built(h, 1, DF1_PLC_SLC, "N7:0", 20, "derived-slc-A2-read-N7:0-20B");
	assert_built(h, 1, DF1_PLC_SLC, "F8:0", 4, "derived-slc-A2-read-F8:0");
	assert_built(h, 0, DF1_PLC_MICROLOGIX, "N7:1", 2, "tap-A2-read-N7:1");
	assert_int_equal(h->next_tns, 1); /* no TNS taken */
}

static void test_build_plc5(void **state)
{
	struct df1 *h = *state;

	assert_built(h, 1, DF1_PLC_PLC5, "N7:0", 20, "derived-plc5-68-typed-read-N7:0x10");
}

static void test_build_plc2(void **state)
{
	struct df1 *h = *state;

	/* byte address 2 * element (0x28 = word 20), then word addresses */
	h->cfg.station = 0x20;
	assert_built(h, 0x29, DF1_PLC_PLC2, "N7:20", 8, "KE-plc2-read-cmd");
	h->cfg.station = 0;
	h->cfg.plc2_word_addr = true;
	assert_built(h, 9, DF1_PLC_PLC2, "N7:17", 2, "M-14-3-plc2-read-cmd");
}

/* What the read would refuse is refused when building, recorded the same way. */
static void test_build_refused(void **state)
{
	struct df1 *h = *state;
	struct df1_addr a = addr("N7:0");
	uint8_t cmd[FRAME_MAX_DATA], buf[4];

	assert_int_equal(client_read_raw_cmd(h, 1, DF1_PLC_SLC, &a, 3, cmd, sizeof cmd), DF1_E_INVAL);
	assert_int_equal(h->err.code, DF1_E_INVAL);
	assert_string_equal(h->err.address, "N7:0");
	assert_int_equal(client_read_raw_at(h, 1, DF1_PLC_SLC, &a, buf, 3), DF1_E_INVAL);
	assert_int_equal(client_read_raw_cmd(h, 1, DF1_PLC_SLC, &a, 2, cmd, 4), DF1_E_NOSPACE);
	assert_int_equal(mock_port_writes(), 0);
}

/* ------------------------------------------------------------------------
 * Decode: each family's reply
 * ------------------------------------------------------------------------ */

static void test_decode_slc_float(void **state)
{
	struct df1 *h = *state;
	const uint8_t want[4] = { 0x00, 0x00, 0xC0, 0x3F }; /* 1.5 */
	uint8_t buf[4];

	assert_int_equal(decode(h, 1, DF1_PLC_SLC, "F8:0", 4, "derived-slc-reply-F8:0=1.5", buf), 4);
	assert_memory_equal(buf, want, 4);
}

static void test_decode_plc5_array(void **state)
{
	struct df1 *h = *state;
	uint8_t buf[20];

	assert_int_equal(decode(h, 1, DF1_PLC_PLC5, "N7:0", 20, "derived-plc5-68-reply-0..9", buf), 20);
	for (int i = 0; i < 10; i++)
		assert_int_equal(buf[2 * i] | buf[2 * i + 1] << 8, i);
}

static void test_decode_plc2(void **state)
{
	struct df1 *h = *state;
	const uint8_t want[8] = { 0x22, 0x11, 0x44, 0x33, 0x66, 0x55, 0x88, 0x77 };
	uint8_t buf[8];

	h->cfg.station = 0x20;
	assert_int_equal(decode(h, 0x29, DF1_PLC_PLC2, "N7:20", 8, "KE-plc2-read-reply", buf), 8);
	assert_memory_equal(buf, want, 8);
	h->cfg.station = 0;
	h->cfg.plc2_word_addr = true;
	assert_int_equal(decode(h, 9, DF1_PLC_PLC2, "N7:17", 2, "M-14-3-plc2-read-reply", buf), 2);
	assert_int_equal(buf[0], 0xFF);
	assert_int_equal(buf[1], 0xFF);
}

/* A reply with fewer bytes than asked: DF1_E_BAD_REPLY, counted as invalid. */
static void test_decode_short_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t buf[8];

	assert_int_equal(decode(h, 1, DF1_PLC_SLC, "F8:0", 8, "derived-slc-reply-F8:0=1.5", buf),
	                 DF1_E_BAD_REPLY);
	assert_int_equal(cnt(h, DF1_ID_CNT_INVALID_MSGS_RCVD), 1);
	assert_string_equal(h->err.address, "F8:0");
}

/* A link failure handed to the decode half keeps the link's detail and gets the address. */
static void test_decode_link_error(void **state)
{
	struct df1 *h = *state;
	struct df1_addr a = addr("N7:0");
	uint8_t buf[2];

	df1_fail(h, DF1_E_TIMEOUT, 1, "no reply from station 1");
	assert_int_equal(client_read_raw_reply(h, 1, DF1_PLC_SLC, &a, buf, 2, DF1_E_TIMEOUT, NULL),
	                 DF1_E_TIMEOUT);
	assert_int_equal(h->err.code, DF1_E_TIMEOUT);
	assert_string_equal(h->err.message, "no reply from station 1");
	assert_string_equal(h->err.address, "N7:0");
	assert_int_equal(h->err.station, 1);
}

/* A read of two packets (DF1_OPT_MAX_PACKET 10): the first reply is decoded,
 * the second packet goes as an ordinary transaction, as in the ordinary read. */
static void test_decode_continues(void **state)
{
	struct df1 *h = *state;
	struct df1_addr a = addr("N7:0");
	uint8_t cmd[FRAME_MAX_DATA], first[16] = { 0x00, 0x01, 0x4F, 0x00, 0x09, 0x00 };
	uint8_t second[16] = { 0x00, 0x01, 0x4F, 0x00, 0x01, 0x00 }, wire[FRAME_MAX_WIRE], buf[20];
	const uint8_t want2[] = { 0x01, 0x00, 0x0F, 0x00, 0x01, 0x00, 0xA2, 0x0A, 0x07, 0x89, 0x05, 0x00 };
	struct vec sent;
	const uint8_t *w;
	size_t wn;

	h->cfg.max_packet = 10;
	assert_int_equal(client_read_raw_cmd(h, 1, DF1_PLC_SLC, &a, 20, cmd, sizeof cmd), 12);
	assert_int_equal(cmd[7], 10);           /* the first packet asks 10 bytes */
	for (int i = 0; i < 10; i++) {
		first[6 + i] = (uint8_t)i;
		second[6 + i] = (uint8_t)(10 + i);
	}
	mock_port_feed(ACK, 2);
	wn = frame_encode_full(DF1_CHECK_CRC, second, sizeof second, wire, sizeof wire);
	mock_port_feed(wire, wn);
	assert_int_equal(client_read_raw_reply(h, 1, DF1_PLC_SLC, &a, buf, 20, (int)sizeof first, first),
	                 20);
	for (int i = 0; i < 20; i++)
		assert_int_equal(buf[i], i);
	/* the second packet on the wire: N7:5, 10 bytes, TNS 1 */
	w = mock_port_write_at(0, &wn);
	memset(&sent, 0, sizeof sent);
	for (size_t i = 2; !(w[i] == 0x10 && w[i + 1] == 0x03); i++) {
		if (w[i] == 0x10)
			i++;
		sent.app[sent.na++] = w[i];
	}
	assert_int_equal(sent.na, sizeof want2);
	assert_memory_equal(sent.app, want2, sizeof want2);
}

/* ------------------------------------------------------------------------
 * Through the link: put, wait, decode as the poll engine does
 * ------------------------------------------------------------------------ */

/* Build F8:0, put it with TNS 4: on the wire it is the vector's frame; the
 * vector's reply comes back decoded. */
static int pipelined_f8(struct df1 *h, const char *reply_name, uint8_t *buf)
{
	struct df1_addr a = addr("F8:0");
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA];
	struct vec want, rep;
	const uint8_t *w;
	size_t wn;
	int n, slot, rc;

	vec_load("derived-slc-A2-read-F8:0", "crc", &want);
	vec_load(reply_name, "crc", &rep);
	h->next_tns = 4;
	n = client_read_raw_cmd(h, 1, DF1_PLC_SLC, &a, 4, cmd, sizeof cmd);
	assert_true(n > 0);
	slot = link_pipe_put(h, cmd, (size_t)n);
	assert_true(slot >= 0);
	mock_port_feed(ACK, 2);
	rep.app[4] = 4;         /* the reply answers TNS 4 (an error vector may carry another) */
	rep.nw = frame_encode_full(DF1_CHECK_CRC, rep.app, rep.na, rep.wire, sizeof rep.wire);
	mock_port_feed(rep.wire, rep.nw);
	df1_clear_error(h);
	rc = link_pipe_wait(h, slot, reply, sizeof reply);
	w = mock_port_write_at(0, &wn);
	assert_int_equal(wn, want.nw);
	assert_memory_equal(w, want.wire, wn);
	return client_read_raw_reply(h, 1, DF1_PLC_SLC, &a, buf, 4, rc, reply);
}

static void test_pipelined_read(void **state)
{
	struct df1 *h = *state;
	const uint8_t want[4] = { 0x00, 0x00, 0xC0, 0x3F };
	uint8_t buf[4];

	assert_int_equal(pipelined_f8(h, "derived-slc-reply-F8:0=1.5", buf), 4);
	assert_memory_equal(buf, want, 4);
	assert_int_equal(h->err.code, 0);
	assert_int_equal(link_pipe_used(h), 0);
}

/* A PLC error: the same result, detail and counters as the ordinary read. */
static void test_pipelined_error_as_ordinary(void **state)
{
	struct df1 *h = *state, *o;
	struct df1_error_detail pe;
	struct vec rep;
	uint8_t buf[4];
	int rc;

	assert_int_equal(pipelined_f8(h, "derived-reply-ext-sts-06", buf), DF1_E_REMOTE);
	pe = h->err;
	assert_int_equal(pe.sts, 0xF0);
	assert_int_equal(pe.ext_sts, 0x06);
	assert_true(pe.has_ext_sts);
	assert_string_equal(pe.address, "F8:0");
	/* the ordinary read on a handle of its own, fed the same reply */
	mock_port_reset();
	o = handle_new();
	o->next_tns = 4;
	vec_load("derived-reply-ext-sts-06", "crc", &rep);
	rep.app[4] = 4;
	rep.nw = frame_encode_full(DF1_CHECK_CRC, rep.app, rep.na, rep.wire, sizeof rep.wire);
	mock_port_feed(ACK, 2);
	mock_port_feed(rep.wire, rep.nw);
	{
		struct df1_addr a = addr("F8:0");

		rc = client_read_raw_at(o, 1, DF1_PLC_SLC, &a, buf, 4);
	}
	assert_int_equal(rc, DF1_E_REMOTE);
	assert_int_equal(o->err.code, pe.code);
	assert_int_equal(o->err.station, pe.station);
	assert_int_equal(o->err.sts, pe.sts);
	assert_int_equal(o->err.ext_sts, pe.ext_sts);
	assert_int_equal(o->err.has_ext_sts, pe.has_ext_sts);
	assert_int_equal(o->err.catalog_id, pe.catalog_id);
	assert_string_equal(o->err.message, pe.message);
	assert_string_equal(o->err.address, pe.address);
	/* the same bytes both ways: every counter the same */
	for (int id = 2500; id < 2600; id++) {
		uint64_t a = 0, b = 0;

		if (df1_counter(h, id, &a) == 0 && df1_counter(o, id, &b) == 0)
			assert_int_equal(a, b);
	}
	handle_free(o);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_build_slc, setup, teardown),
		cmocka_unit_test_setup_teardown(test_build_plc5, setup, teardown),
		cmocka_unit_test_setup_teardown(test_build_plc2, setup, teardown),
		cmocka_unit_test_setup_teardown(test_build_refused, setup, teardown),
		cmocka_unit_test_setup_teardown(test_decode_slc_float, setup, teardown),
		cmocka_unit_test_setup_teardown(test_decode_plc5_array, setup, teardown),
		cmocka_unit_test_setup_teardown(test_decode_plc2, setup, teardown),
		cmocka_unit_test_setup_teardown(test_decode_short_reply, setup, teardown),
		cmocka_unit_test_setup_teardown(test_decode_link_error, setup, teardown),
		cmocka_unit_test_setup_teardown(test_decode_continues, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pipelined_read, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pipelined_error_as_ordinary, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
