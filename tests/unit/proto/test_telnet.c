/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_telnet - the Telnet / COM-PORT-OPTION codec (lib/proto/telnet.c).
 * Every expected byte string is written here by hand from the RFCs: RFC 854
 * (IAC 255, WILL 251, WONT 252, DO 253, DONT 254, SB 250, SE 240; a data byte
 * 255 sent as IAC IAC), RFC 856 (TRANSMIT-BINARY is option 0) and RFC 2217
 * (COM-PORT-OPTION is option 44; SET-BAUDRATE 1 with four bytes in network
 * order, SET-DATASIZE 2, SET-PARITY 3 with NONE 1 ODD 2 EVEN 3, SET-STOPSIZE
 * 4, SET-CONTROL 5 with 1 no flow control and 3 hardware, PURGE-DATA 12 with
 * 3 both; the server answers the same command plus 100).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "proto/telnet.h"

static void test_option_bytes(void **state)
{
	uint8_t b[3];

	(void)state;
	/* RFC 856: "IAC WILL TRANSMIT-BINARY" is FF FB 00; RFC 2217: WILL COM-PORT-OPTION FF FB 2C */
	assert_int_equal(telnet_option(TELNET_WILL, TELNET_OPT_BINARY, b), 3);
	assert_memory_equal(b, ((uint8_t[]){ 0xFF, 0xFB, 0x00 }), 3);
	telnet_option(TELNET_DO, TELNET_OPT_COMPORT, b);
	assert_memory_equal(b, ((uint8_t[]){ 0xFF, 0xFD, 0x2C }), 3);
	telnet_option(TELNET_DONT, 3, b);
	assert_memory_equal(b, ((uint8_t[]){ 0xFF, 0xFE, 0x03 }), 3);
}

static void test_cpc_encode(void **state)
{
	uint8_t out[16], v[4];
	const uint8_t baud9600[] = { 0xFF, 0xFA, 0x2C, 0x01, 0x00, 0x00, 0x25, 0x80, 0xFF, 0xF0 };
	const uint8_t parity_even[] = { 0xFF, 0xFA, 0x2C, 0x03, 0x03, 0xFF, 0xF0 };
	const uint8_t purge[] = { 0xFF, 0xFA, 0x2C, 0x0C, 0x03, 0xFF, 0xF0 };
	/* 16777215 baud = 00 FF FF FF: each FF of the value doubled (RFC 854 IAC IAC) */
	const uint8_t baud_ff[] = { 0xFF, 0xFA, 0x2C, 0x01, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
	                            0xFF, 0xFF, 0xF0 };

	(void)state;
	telnet_put_baud(9600, v);
	assert_int_equal(telnet_cpc(TELNET_CPC_SET_BAUDRATE, v, 4, out), sizeof baud9600);
	assert_memory_equal(out, baud9600, sizeof baud9600);
	assert_int_equal(telnet_get_baud(v), 9600);
	v[0] = TELNET_PARITY_EVEN;
	assert_int_equal(telnet_cpc(TELNET_CPC_SET_PARITY, v, 1, out), sizeof parity_even);
	assert_memory_equal(out, parity_even, sizeof parity_even);
	v[0] = TELNET_PURGE_BOTH;
	assert_int_equal(telnet_cpc(TELNET_CPC_PURGE_DATA, v, 1, out), sizeof purge);
	assert_memory_equal(out, purge, sizeof purge);
	telnet_put_baud(0x00FFFFFF, v);
	assert_int_equal(telnet_cpc(TELNET_CPC_SET_BAUDRATE, v, 4, out), sizeof baud_ff);
	assert_memory_equal(out, baud_ff, sizeof baud_ff);
}

static void test_escape(void **state)
{
	const uint8_t in[] = { 0x10, 0x02, 0xFF, 0x00, 0xFF, 0xFF };
	const uint8_t want[] = { 0x10, 0x02, 0xFF, 0xFF, 0x00, 0xFF, 0xFF, 0xFF, 0xFF };
	uint8_t out[16];
	size_t used;

	(void)state;
	assert_int_equal(telnet_escape(in, sizeof in, out, sizeof out, &used), sizeof want);
	assert_int_equal(used, sizeof in);
	assert_memory_equal(out, want, sizeof want);
	/* room for 3: the IAC and its double are never split */
	assert_int_equal(telnet_escape(in, sizeof in, out, 3, &used), 2);
	assert_int_equal(used, 2);
}

/* Feed a whole string; collect data, and the events other than data. */
struct got {
	uint8_t data[64];
	size_t n;
	int kinds[8], cmds[8], opts[8];
	uint8_t sb[8][TELNET_SB_MAX];
	size_t sb_len[8];
	int nev;
};

static void feed_all(const uint8_t *in, size_t n, struct got *g)
{
	struct telnet_decoder d;

	memset(g, 0, sizeof *g);
	telnet_decoder_init(&d);
	for (size_t i = 0; i < n; i++) {
		struct telnet_event ev;
		enum telnet_ev k = telnet_feed(&d, in[i], &ev);

		if (k == TELNET_EV_DATA) {
			g->data[g->n++] = ev.byte;
		} else if (k != TELNET_EV_NONE && g->nev < 8) {
			g->kinds[g->nev] = k;
			g->cmds[g->nev] = ev.cmd;
			g->opts[g->nev] = ev.opt;
			if (k == TELNET_EV_SB) {
				memcpy(g->sb[g->nev], ev.sb, ev.sb_len);
				g->sb_len[g->nev] = ev.sb_len;
			}
			g->nev++;
		}
	}
}

static void test_decode(void **state)
{
	/* data 10 02, DO COM-PORT-OPTION, data FF (IAC IAC), server's answer to
	 * SET-BAUDRATE 19200 (101 = 0x65, 00 00 4B 00), NOP (F1), data 03, WILL ECHO */
	const uint8_t in[] = { 0x10, 0x02, 0xFF, 0xFD, 0x2C, 0xFF, 0xFF,
	                       0xFF, 0xFA, 0x2C, 0x65, 0x00, 0x00, 0x4B, 0x00, 0xFF, 0xF0,
	                       0xFF, 0xF1, 0x03, 0xFF, 0xFB, 0x01 };
	struct got g;

	(void)state;
	feed_all(in, sizeof in, &g);
	assert_int_equal(g.n, 4);
	assert_memory_equal(g.data, ((uint8_t[]){ 0x10, 0x02, 0xFF, 0x03 }), 4);
	assert_int_equal(g.nev, 4);
	assert_int_equal(g.kinds[0], TELNET_EV_OPTION);
	assert_int_equal(g.cmds[0], TELNET_DO);
	assert_int_equal(g.opts[0], TELNET_OPT_COMPORT);
	assert_int_equal(g.kinds[1], TELNET_EV_SB);
	assert_int_equal(g.opts[1], TELNET_OPT_COMPORT);
	assert_int_equal(g.sb_len[1], 5);
	assert_int_equal(g.sb[1][0], TELNET_CPC_SERVER + TELNET_CPC_SET_BAUDRATE);
	assert_int_equal(telnet_get_baud(&g.sb[1][1]), 19200);
	assert_int_equal(g.kinds[2], TELNET_EV_OTHER);
	assert_int_equal(g.cmds[2], 0xF1);
	assert_int_equal(g.kinds[3], TELNET_EV_OPTION);
	assert_int_equal(g.cmds[3], TELNET_WILL);
	assert_int_equal(g.opts[3], 1);
}

static void test_decode_sb_doubled(void **state)
{
	/* a value byte 255 inside SB comes doubled (RFC 854) */
	const uint8_t in[] = { 0xFF, 0xFA, 0x2C, 0x65, 0x00, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
	                       0xFF, 0xF0, 0x41 };
	struct got g;

	(void)state;
	feed_all(in, sizeof in, &g);
	assert_int_equal(g.nev, 1);
	assert_int_equal(g.sb_len[0], 5);
	assert_int_equal(telnet_get_baud(&g.sb[0][1]), 0x00FFFFFF);
	assert_int_equal(g.n, 1);
	assert_int_equal(g.data[0], 0x41);
}

/* Round trip: any bytes escaped then decoded are the bytes (CRC bytes, data). */
static void test_round_trip(void **state)
{
	uint8_t in[256], out[512];
	struct got g;
	size_t used, n;

	(void)state;
	for (int i = 0; i < 64; i++)
		in[i] = (uint8_t)(i % 3 == 0 ? 0xFF : i * 37);
	n = telnet_escape(in, 64, out, sizeof out, &used);
	assert_int_equal(used, 64);
	feed_all(out, n, &g);
	assert_int_equal(g.n, 64);
	assert_memory_equal(g.data, in, 64);
	assert_int_equal(g.nev, 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_option_bytes),
		cmocka_unit_test(test_cpc_encode),
		cmocka_unit_test(test_escape),
		cmocka_unit_test(test_decode),
		cmocka_unit_test(test_decode_sb_doubled),
		cmocka_unit_test(test_round_trip),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
