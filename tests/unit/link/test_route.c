/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_route - messages half-duplex slaves send on their own (lib/link/route.c,
 * lib/link/half_msg.c), both roles on the scripted port
 * (tests/support/mock_port.c): the master that runs, forwards and answers
 * them, and the slave whose MSG leaves on a poll. The frames were written by
 * hand from doc/PROTOCOL.md 2.2 and 3.1 (the CRC over the application bytes
 * and ETX, for a master message over STN, STX, them and ETX; the calculator
 * checked against derived-hd-master-A2-stn1 of tests/data/vectors.txt), and
 * the same frames are what one role writes and the other reads.
 */

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>

#include "df1_int.h"
#include "link/link.h"
#include "link/link_int.h"
#include "server/server.h"
#include "support/mock_port.h"
#include "support/link_fixture.h"

/* Station 1's MSG to station 2: an SLC read of N7:0, 2 bytes, TNS 0005. */
static const char CMD_S[] = "10 02 02 01 0F 00 05 00 A2 02 07 89 00 00 10 03 A8 70";
/* ... forwarded by the master as a master message to station 2 */
static const char CMD_M2[] = "10 01 02 10 02 02 01 0F 00 05 00 A2 02 07 89 00 00 10 03 29 B3";
/* station 2's reply to station 1 (data 11 22), and the master's forward of it */
static const char REP_S[] = "10 02 01 02 4F 00 05 00 11 22 10 03 F6 29";
static const char REP_M1[] = "10 01 01 10 02 01 02 4F 00 05 00 11 22 10 03 53 1F";
/* the master's answer in station 2's name when station 2 does not ACK: STS 02 */
static const char ERR02_M1[] = "10 01 01 10 02 01 02 4F 02 05 00 10 03 99 1D";
/* station 1's MSG to the master (station 0), TNS 0006; the master without a
 * responder answers STS 10 (the 10h data byte doubled) */
static const char C0_S[] = "10 02 00 01 0F 00 06 00 A2 02 07 89 00 00 10 03 BB C2";
static const char R0_M1[] = "10 01 01 10 02 01 00 4F 10 10 06 00 10 03 6D 87";
/* station 1's broadcast (DST FF), a 0F/AA write of 34 12 to N7:0, TNS 0007, and its forward */
static const char BC_S[] = "10 02 FF 01 0F 00 07 00 AA 02 07 89 00 00 34 12 10 03 D2 72";
static const char BC_M[] = "10 01 FF 10 02 FF 01 0F 00 07 00 AA 02 07 89 00 00 34 12 10 03 22 D3";
static const char POLL1[] = "10 05 01 FF";
static const char POLL2[] = "10 05 02 FE";

/* ------------------------------------------------------------------------
 * The master: a conversation, each write of the master answered in turn
 * ------------------------------------------------------------------------ */

struct turn {
	const char *want;   /* what the master writes */
	const char *answer; /* what the slaves answer: hex, "EXP" (no answer in time), NULL nothing */
};
static const struct turn *conv;
static size_t conv_n, conv_i;

static void conv_hook(const uint8_t *buf, size_t n, void *user)
{
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn;

	(void)user;
	assert_true(conv_i < conv_n);
	wn = hex(conv[conv_i].want, want);
	if (n != wn || memcmp(buf, want, n) != 0) {
		fprintf(stderr, "write %zu: ", conv_i);
		for (size_t i = 0; i < n; i++)
			fprintf(stderr, "%02X ", buf[i]);
		fprintf(stderr, "\n   wanted: %s\n", conv[conv_i].want);
		fail();
	}
	if (conv[conv_i].answer && !strcmp(conv[conv_i].answer, "EXP"))
		mock_port_expire();
	else if (conv[conv_i].answer)
		mock_port_feed_hex(conv[conv_i].answer);
	conv_i++;
}

static void talk(const struct turn *t, size_t n)
{
	conv = t;
	conv_n = n;
	conv_i = 0;
	mock_port_on_write(conv_hook, NULL);
}

static int setup_master(void **state)
{
	struct df1 *h;

	setup(state);
	h = *state;
	h->cfg.duplex = DF1_HALF_DUPLEX_MASTER;
	return 0;
}

static struct df1_route_stats stats(struct df1 *h)
{
	struct df1_route_stats st;

	assert_int_equal(df1_route_stats(h, &st), 0);
	return st;
}

static void test_master_routes_command_and_reply(void **state)
{
	static const struct turn t[] = {
		/* round 1: station 1's MSG for station 2, ACKed, then its EOT */
		{ POLL1, CMD_S }, { "10 06", NULL }, { POLL1, "10 04" },
		/* station 2: the forward, its ACK; its reply, ACKed; its EOT */
		{ CMD_M2, "10 06" }, { POLL2, REP_S }, { "10 06", NULL }, { POLL2, "10 04" },
		/* round 2: the reply to station 1 before its poll */
		{ REP_M1, "10 06" }, { POLL1, "10 04" }, { POLL2, "10 04" },
	};
	struct df1 *h = *state;
	bool list[256] = { [1] = true, [2] = true };

	talk(t, sizeof t / sizeof t[0]);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(conv_i, conv_n);
	assert_int_equal(stats(h).routed, 1);
	assert_int_equal(stats(h).route_replies, 1);
	assert_int_equal(stats(h).undeliverable, 0);
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_RCVD), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_REPLY_MSGS_SENT), 1);
}

static void test_master_silent_target_sts02(void **state)
{
	static const struct turn t[] = {
		{ POLL1, CMD_S }, { "10 06", NULL }, { POLL1, "10 04" },
		/* station 2 never ACKs: the message and nak_retries (3) more */
		{ CMD_M2, "EXP" }, { CMD_M2, "EXP" }, { CMD_M2, "EXP" }, { CMD_M2, "EXP" },
		{ POLL2, "EXP" },
		/* round 2: the master answers station 1 with STS 02h in station 2's name */
		{ ERR02_M1, "10 06" }, { POLL1, "10 04" }, { POLL2, "EXP" },
	};
	struct df1 *h = *state;
	bool list[256] = { [1] = true };

	talk(t, sizeof t / sizeof t[0]);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(conv_i, conv_n);
	assert_int_equal(stats(h).routed, 1);
	assert_int_equal(stats(h).undeliverable, 1);
	assert_int_equal(df1_station_active(h, 2), 0);
}

static void test_master_own_station_sts10(void **state)
{
	static const struct turn t[] = {
		{ POLL1, C0_S }, { "10 06", NULL }, { R0_M1, "10 06" }, { POLL1, "10 04" },
		{ POLL1, "10 04" },
	};
	struct df1 *h = *state;
	bool list[256] = { [1] = true };

	talk(t, sizeof t / sizeof t[0]);
	/* the reply goes before the sender's next poll, within the same round */
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(conv_i, 4);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(conv_i, conv_n);
	assert_int_equal(stats(h).executed, 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_INVALID_MSGS_RCVD), 1);
}

static void test_master_own_station_handler(void **state)
{
	/* df1_serve's handler answers: the fixture's reply with data 11 22 33 44 */
	static const struct turn t[] = {
		{ POLL1, C0_S }, { "10 06", NULL },
		{ "10 01 01 10 02 01 00 4F 00 06 00 11 22 33 44 10 03 9C FC", "10 06" }, { POLL1, "10 04" },
		{ POLL1, "10 04" },
	};
	struct df1 *h = *state;
	bool list[256] = { [1] = true };

	handler_calls = 0;
	handler_sts = 0;
	talk(t, sizeof t / sizeof t[0]);
	assert_int_equal(link_route_round(h, list, test_handler, NULL), 0);
	assert_int_equal(link_route_round(h, list, test_handler, NULL), 0);
	assert_int_equal(conv_i, conv_n);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(stats(h).executed, 1);
}

static void test_master_broadcast(void **state)
{
	static const struct turn t[] = {
		{ POLL1, BC_S }, { "10 06", NULL }, { POLL1, "10 04" }, { POLL2, "10 04" },
		/* round 2: the broadcast first, not ACKed by anyone */
		{ BC_M, NULL }, { POLL1, "10 04" }, { POLL2, "10 04" },
	};
	struct df1 *h = *state;
	bool list[256] = { [1] = true, [2] = true };

	talk(t, sizeof t / sizeof t[0]);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(conv_i, conv_n);
	assert_int_equal(stats(h).broadcasts, 1);
}

static void test_master_route_off(void **state)
{
	static const struct turn t[] = {
		{ POLL1, CMD_S }, { "10 06", NULL }, { POLL1, "10 04" },
		{ POLL1, "10 04" }, /* round 2: nothing for anyone, station 2 not polled */
	};
	struct df1 *h = *state;
	bool list[256] = { [1] = true };

	assert_int_equal(df1_set_option(h, DF1_OPT_ROUTE, 0), 0);
	talk(t, sizeof t / sizeof t[0]);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(link_route_round(h, list, NULL, NULL), 0);
	assert_int_equal(conv_i, conv_n);
	assert_int_equal(stats(h).routed, 0);
	assert_int_equal(stats(h).undeliverable, 1);
}

/* ------------------------------------------------------------------------
 * The slave: its MSG on the next poll, the master's frames of above
 * ------------------------------------------------------------------------ */

static const char CMD_APP[] = "02 00 0F 00 00 00 A2 02 07 89 00 00"; /* SRC, TNS: the link's */

static int slave_msg(struct df1 *h, uint8_t *out, size_t cap)
{
	uint8_t cmd[FRAME_MAX_DATA];
	size_t n = hex(CMD_APP, cmd);

	h->next_tns = 5;
	return link_transact(h, cmd, n, out, cap);
}

static void test_slave_msg_on_poll(void **state)
{
	static const uint8_t want[] = { 0x01, 0x02, 0x4F, 0x00, 0x05, 0x00, 0x11, 0x22 };
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	mock_port_feed_hex(POLL1);
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(REP_M1);
	r = slave_msg(h, out, sizeof out);
	assert_int_equal(r, (int)sizeof want);
	assert_memory_equal(out, want, sizeof want);
	assert_int_equal(mock_port_writes(), 2);
	assert_write(0, CMD_S);
	assert_write_bytes(1, ACK, 2);
	/* not queued any more: the next poll gets EOT */
	mock_port_clear_written();
	mock_port_feed_hex(POLL1);
	assert_true(serve_script(h) >= 0);
	assert_write_bytes(0, EOT, 2);
}

static void test_slave_msg_error_from_master(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	mock_port_feed_hex(POLL1);
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(ERR02_M1);
	assert_int_equal(slave_msg(h, out, sizeof out), 6);
	assert_int_equal(out[3], 0x02);
	assert_int_equal(cnt(h, DF1_ID_CNT_ERROR_MSGS_RCVD), 1);
}

static void test_slave_msg_not_acked_nak_limit(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	/* the message, nak_retries (3) more on the next polls, then dropped: EOT */
	for (int i = 0; i < 5; i++)
		mock_port_feed_hex(POLL1);
	assert_int_equal(slave_msg(h, out, sizeof out), DF1_E_NAK_LIMIT);
	assert_int_equal(mock_port_writes(), 5);
	for (size_t i = 0; i < 4; i++)
		assert_write(i, CMD_S);
	assert_write_bytes(4, EOT, 2);
}

static void test_slave_master_command_served_meanwhile(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	/* the master's echo command (06/00) while our MSG waits: answered as
	 * df1_set_responder(3) would, STS 10h without ops */
	mock_port_feed_hex("10 01 01 10 02 01 00 06 00 09 00 00 10 03 CA 92");
	mock_port_feed_hex(POLL1);
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(POLL1);
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(REP_M1);
	assert_int_equal(slave_msg(h, out, sizeof out), 8);
	/* ACK of its command; our MSG, queued first, on the first poll; its
	 * STS 10h reply on the next; the ACK of our MSG's reply */
	assert_int_equal(mock_port_writes(), 4);
	assert_write_bytes(0, ACK, 2);
	assert_write(1, CMD_S);
	assert_write(2, "10 02 00 01 46 10 10 09 00 10 03 1C DD");
	assert_write_bytes(3, ACK, 2);
}

static void test_slave_broadcast_run_not_acked(void **state)
{
	struct df1 *h = *state;

	h->cfg.station = 2;
	mock_port_feed_hex(BC_M);
	assert_true(serve_script(h) >= 0);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_master_routes_command_and_reply, setup_master, teardown),
		cmocka_unit_test_setup_teardown(test_master_silent_target_sts02, setup_master, teardown),
		cmocka_unit_test_setup_teardown(test_master_own_station_sts10, setup_master, teardown),
		cmocka_unit_test_setup_teardown(test_master_own_station_handler, setup_master, teardown),
		cmocka_unit_test_setup_teardown(test_master_broadcast, setup_master, teardown),
		cmocka_unit_test_setup_teardown(test_master_route_off, setup_master, teardown),
		cmocka_unit_test_setup_teardown(test_slave_msg_on_poll, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_msg_error_from_master, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_msg_not_acked_nak_limit, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_master_command_served_meanwhile, setup_slave,
		                                teardown),
		cmocka_unit_test_setup_teardown(test_slave_broadcast_run_not_acked, setup_slave, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
