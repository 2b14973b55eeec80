/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_link_radio - the DF1 Radio Modem link (lib/link/radio.c, radio_dup.c;
 * doc/PROTOCOL.md 2.6) on the scripted port: byte-exact exchanges, the
 * duplicate table, the store and forward rule (the AG-UM008 chain of
 * doc/PROTOCOL.md 2.6 hop by hop) and keying against the mock's fake modem
 * lines. Frames come from tests/data/vectors.txt (derived-slc-A2-read-F8:0,
 * derived-slc-reply-F8:0=1.5, derived-slc-AA-write-N7:5) and, for the others,
 * from the rules of doc/PROTOCOL.md 1.3-1.5 (CRC-16/ARC over the data and
 * ETX, low byte first), computed by hand outside the library.
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
#include "link/radio_dup.h"
#include "server/server.h"
#include "df1_server.h"
#include "support/mock_port.h"
#include "support/link_fixture.h"

/* derived-slc-A2-read-F8:0 (crc): DST 01 SRC 00 TNS 0004 */
static const char RD_CMD[] = "01 00 0F 00 00 00 A2 04 08 8A 00 00";
static const char RD_WIRE[] = "10 02 01 00 0F 00 04 00 A2 04 08 8A 00 00 10 03 09 C3";
static const char RD_WIRE_BCC[] = "10 02 01 00 0F 00 04 00 A2 04 08 8A 00 00 10 03 B4";
/* derived-slc-reply-F8:0=1.5: DST 00 SRC 01 4F TNS 0004 */
static const char RD_REPLY[] = "10 02 00 01 4F 00 04 00 00 00 C0 3F 10 03 35 FB";
static const char RD_REPLY_BCC[] = "10 02 00 01 4F 00 04 00 00 00 C0 3F 10 03 AD";
/* the same reply with its CRC's high byte wrong */
static const char RD_REPLY_BAD[] = "10 02 00 01 4F 00 04 00 00 00 C0 3F 10 03 35 FA";
/* the same reply to TNS 0003 (an earlier command) */
static const char RD_REPLY_T3[] = "10 02 00 01 4F 00 03 00 00 00 C0 3F 10 03 43 3B";
/* addressed to station 02, not us */
static const char RD_REPLY_TO2[] = "10 02 02 01 4F 00 04 00 00 00 C0 3F 10 03 3E 43";
/* derived-slc-AA-write-N7:5 (crc), TNS 0002, and its reply (no data) */
static const char WR_CMD[] = "01 00 0F 00 00 00 AA 02 07 89 05 00 34 12";
static const char WR_WIRE[] = "10 02 01 00 0F 00 02 00 AA 02 07 89 05 00 34 12 10 03 71 3F";
static const char WR_REPLY[] = "10 02 00 01 4F 00 02 00 10 03 B5 DE";
/* the write as a broadcast (DST FF) */
static const char BC_CMD[] = "FF 00 0F 00 00 00 AA 02 07 89 05 00 34 12";
static const char BC_WIRE[] = "10 02 FF 00 0F 00 02 00 AA 02 07 89 05 00 34 12 10 03 0F 7F";
/* test_handler's reply to RD_WIRE as station 1: 00 01 4F 00 0400 11 22 33 44 */
static const char RD_ANSWER[] = "10 02 00 01 4F 00 04 00 11 22 33 44 10 03 11 43";
/* the chain of doc/PROTOCOL.md 2.6: 1's read to 4 (TNS 0004) and 4's reply */
static const char CH_CMD[] = "10 02 04 01 0F 00 04 00 A2 04 08 8A 00 00 10 03 F8 05";
static const char CH_REPLY[] = "10 02 01 04 4F 00 04 00 00 00 C0 3F 10 03 21 17";
/* station 2's own read of station 4 relayed back to it: SRC 02 */
static const char OWN_CMD_2[] = "10 02 04 02 0F 00 04 00 A2 04 08 8A 00 00 10 03 FC 01";

static int radio_setup(void **state)
{
	struct df1 *h;

	setup(state);
	h = *state;
	h->cfg.duplex = DF1_RADIO_MODEM;
	h->next_tns = 4;
	handler_calls = 0;
	handler_sts = 0;
	return 0;
}

static int radio_read(struct df1 *h, uint8_t *out, size_t cap)
{
	uint8_t cmd[32];
	size_t n = hex(RD_CMD, cmd);

	return link_transact(h, cmd, n, out, cap);
}

static void assert_f8_reply(int r, const uint8_t *out)
{
	static const uint8_t want[] = { 0x00, 0x01, 0x4F, 0x00, 0x04, 0x00, 0x00, 0x00, 0xC0, 0x3F };

	assert_int_equal(r, (int)sizeof want);
	assert_memory_equal(out, want, sizeof want);
}

static struct df1_radio_stats stats(struct df1 *h)
{
	struct df1_radio_stats st;

	assert_int_equal(df1_radio_stats(h, &st), 0);
	return st;
}

/* ------------------------------------------------------------------------
 * A master's transactions
 * ------------------------------------------------------------------------ */

static void test_read(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	mock_port_feed_hex(RD_REPLY);
	r = radio_read(h, out, sizeof out);
	assert_f8_reply(r, out);
	assert_int_equal(mock_port_writes(), 1); /* the command alone: no ACK of the reply */
	assert_write(0, RD_WIRE);
	assert_int_equal(cnt(h, DF1_ID_CNT_MSG_PACKETS_SENT), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_SENT), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_REPLY_MSGS_RCVD), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_ACKS_SENT), 0);
	assert_int_equal(stats(h).sent, 1);
	assert_int_equal(stats(h).received, 1);
}

static void test_read_bcc(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	h->cfg.check = DF1_CHECK_BCC;
	mock_port_feed_hex(RD_REPLY_BCC);
	assert_f8_reply(radio_read(h, out, sizeof out), out);
	assert_int_equal(mock_port_writes(), 1);
	assert_write(0, RD_WIRE_BCC);
}

static void test_write(void **state)
{
	struct df1 *h = *state;
	uint8_t cmd[32], out[64];
	size_t n = hex(WR_CMD, cmd);
	int r;

	h->next_tns = 2;
	mock_port_feed_hex(WR_REPLY);
	r = link_transact(h, cmd, n, out, sizeof out);
	assert_int_equal(r, 6);
	assert_int_equal(out[2], 0x4F);
	assert_int_equal(out[3], 0);
	assert_int_equal(mock_port_writes(), 1);
	assert_write(0, WR_WIRE);
}

static void test_broadcast(void **state)
{
	struct df1 *h = *state;
	uint8_t cmd[32], out[64];
	size_t n = hex(BC_CMD, cmd);
	int r;

	h->next_tns = 2;
	r = link_transact(h, cmd, n, out, sizeof out);
	assert_int_equal(r, 6); /* done at once: an empty STS 0 "reply" */
	assert_int_equal(out[3], 0);
	assert_int_equal(mock_port_writes(), 1);
	assert_write(0, BC_WIRE);
	assert_int_equal(mock_port_reads(), 0); /* nothing awaited */
}

static void test_timeout(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	mock_port_expire();
	r = radio_read(h, out, sizeof out);
	assert_int_equal(r, DF1_E_TIMEOUT);
	assert_int_equal(df1_error_catalog_id(r), DF1_ID_ERR_COMMAND_TIMEOUT);
	assert_int_equal(mock_port_writes(), 1); /* no ENQ, no retransmission by default */
	assert_int_equal(cnt(h, DF1_ID_CNT_COMMAND_TIMEOUTS), 1);
	assert_int_equal(logged(DF1_ID_ERR_COMMAND_TIMEOUT), 1);
	assert_int_equal(mock_port_count_written(ENQ, 2), 0);
}

static void test_app_retries(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	assert_int_equal(df1_set_option(h, DF1_OPT_APP_RETRIES, 2), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_APP_RETRIES), 2);
	mock_port_expire();
	mock_port_expire();
	mock_port_feed_hex(RD_REPLY); /* the third copy is answered */
	r = radio_read(h, out, sizeof out);
	assert_f8_reply(r, out);
	assert_int_equal(mock_port_writes(), 3);
	for (size_t i = 0; i < 3; i++)
		assert_write(i, RD_WIRE); /* the same frame, the same TNS */
	assert_int_equal(cnt(h, DF1_ID_CNT_NAK_RETRIES), 2);

	/* retries run out: the timeout error */
	mock_port_clear_written();
	h->next_tns = 4;
	for (int i = 0; i < 3; i++)
		mock_port_expire();
	assert_int_equal(radio_read(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_int_equal(mock_port_writes(), 3);
	assert_int_equal(df1_set_option(h, DF1_OPT_APP_RETRIES, 11), DF1_E_CONFIG);
}

static void test_bad_check_dropped(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	mock_port_feed_hex(RD_REPLY_BAD);
	mock_port_expire();
	assert_int_equal(radio_read(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_int_equal(mock_port_writes(), 1); /* no NAK */
	assert_int_equal(cnt(h, DF1_ID_CNT_CRC_ERRORS), 1);
	assert_int_equal(logged(DF1_ID_ERR_BAD_CRC), 1);
	assert_int_equal(stats(h).bad_packets, 1);
	assert_int_equal(stats(h).received, 0);
}

static void test_own_command_relayed_back(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	/* a relay repeats our command, then the reply comes */
	mock_port_feed_hex(RD_WIRE);
	mock_port_feed_hex(RD_REPLY);
	assert_f8_reply(radio_read(h, out, sizeof out), out);
	assert_int_equal(mock_port_writes(), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_RCVD), 0); /* not run as a command */
}

static void test_others_ignored(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	mock_port_feed_hex(RD_REPLY_TO2);  /* another station's reply */
	mock_port_feed_hex(CH_CMD);        /* other stations' command */
	mock_port_feed_hex(RD_REPLY_T3);   /* for us, an old TNS */
	mock_port_feed_hex(RD_REPLY);
	assert_f8_reply(radio_read(h, out, sizeof out), out);
	assert_int_equal(mock_port_writes(), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_STALE_MSGS_RCVD), 1);
	assert_int_equal(stats(h).received, 4);
	assert_int_equal(stats(h).relayed, 0); /* no forward table */
}

static void test_duplicated_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	/* two copies of the reply (a relay repeated it); then the next read's reply */
	mock_port_feed_hex(RD_REPLY);
	mock_port_feed_hex(RD_REPLY);
	r = radio_read(h, out, sizeof out);
	assert_f8_reply(r, out);
	/* the next read (TNS 0005) hears the copy first: not its reply */
	mock_port_expire();
	assert_int_equal(radio_read(h, out, sizeof out), DF1_E_TIMEOUT);
	/* detection off (no table, auto): the copy is a stale reply */
	assert_int_equal(cnt(h, DF1_ID_CNT_STALE_MSGS_RCVD), 1);
	assert_int_equal(stats(h).duplicates, 0);
}

static void test_duplicated_reply_detected(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_DUP_DETECT, 1), 0);
	mock_port_feed_hex(RD_REPLY);
	assert_f8_reply(radio_read(h, out, sizeof out), out);
	/* next command, TNS 0005: the copy of the first reply comes first */
	mock_port_feed_hex(RD_REPLY);
	mock_port_expire();
	assert_int_equal(radio_read(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_int_equal(stats(h).duplicates, 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_DUPLICATE_MSGS_RCVD), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_STALE_MSGS_RCVD), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_DUP_DETECT, 3), DF1_E_CONFIG);
	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_DUP_DETECT, DF1_DUP_AUTO), 0);
}

static void test_stray_symbols(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	mock_port_feed_hex("10 06 10 05 10 15 10 04 55");
	mock_port_feed_hex(RD_REPLY);
	assert_f8_reply(radio_read(h, out, sizeof out), out);
	assert_int_equal(mock_port_writes(), 1); /* nothing answers them */
	assert_int_equal(stats(h).bad_packets, 0);
}

static void test_dle_pair_in_frame(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];

	/* an ACK inside a frame is no embedded response here: the frame is broken */
	mock_port_feed_hex("10 02 00 01 4F 00 10 06 04 00 00 00 C0 3F 10 03 35 FB");
	mock_port_expire();
	assert_int_equal(radio_read(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_int_equal(mock_port_writes(), 1);
	assert_int_equal(stats(h).bad_packets, 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_ACKS_RCVD), 0);
}

/* the link test: an empty diagnostic echo (06/00, doc/PROTOCOL.md 4), any reply */
static void test_link_test_echo(void **state)
{
	struct df1 *h = *state;

	mock_port_feed_hex("10 02 00 01 46 10 10 04 00 10 03 8D 1E"); /* STS 10h: still an answer */
	assert_int_equal(link_test(h, 1), 0);
	assert_int_equal(mock_port_writes(), 1);
	assert_write(0, "10 02 01 00 06 00 04 00 00 10 03 80 9B");
	mock_port_expire();
	assert_int_equal(link_test(h, 1), DF1_E_TIMEOUT);
	assert_int_equal(link_test(h, 255), DF1_E_INVAL);
}

/* ------------------------------------------------------------------------
 * The responder
 * ------------------------------------------------------------------------ */

static int radio_setup_resp(void **state)
{
	radio_setup(state);
	((struct df1 *)*state)->cfg.station = 1;
	return 0;
}

static void test_serve_answers(void **state)
{
	struct df1 *h = *state;

	mock_port_feed_hex(RD_WIRE);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 1); /* the reply, no ACK before it */
	assert_write(0, RD_ANSWER);
	assert_int_equal(cnt(h, DF1_ID_CNT_REPLY_MSGS_SENT), 1);
}

static void test_serve_broadcast_no_reply(void **state)
{
	struct df1 *h = *state;

	mock_port_feed_hex(BC_WIRE);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1); /* executed */
	assert_int_equal(mock_port_writes(), 0);
}

static void test_serve_ignores_others(void **state)
{
	struct df1 *h = *state;

	mock_port_feed_hex(CH_CMD);            /* for station 4 */
	mock_port_feed_hex(RD_REPLY);          /* a reply: we sent nothing */
	mock_port_feed_hex("10 05 10 06");     /* strays */
	mock_port_feed_hex("10 02 01 00 0F 00 04 00 A2 04 08 8A 00 00 10 03 09 C4"); /* bad CRC */
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(stats(h).bad_packets, 1);
}

static void test_serve_duplicate_command(void **state)
{
	struct df1 *h = *state;

	/* the default (auto) on a node that serves, no forward table: on, so
	 * two relays in parallel cannot make it run a command twice */
	mock_port_feed_hex(RD_WIRE);
	mock_port_feed_hex(RD_WIRE); /* a relayed copy: not run, not answered */
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 1);
	assert_int_equal(stats(h).duplicates, 1);
	/* forced off (the manuals' node without a table): each copy runs */
	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_DUP_DETECT, 0), 0);
	mock_port_clear_written();
	mock_port_feed_hex(RD_WIRE);
	mock_port_feed_hex(RD_WIRE);
	assert_int_equal(serve_script(h), 2);
	assert_int_equal(handler_calls, 3);
	assert_int_equal(mock_port_writes(), 2);
}

static void test_serve_delayed_reply(void **state)
{
	struct df1 *h = *state;
	char ev[8];
	int64_t t0;

	/* a reply held 60 ms (df1sim --delay): sent then, the line read meanwhile */
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_DELAY_REPLY, 1000, 60), 0);
	mock_port_lines(0, 0); /* no keying asked: only to time the write */
	mock_port_feed_hex(RD_WIRE);
	t0 = df1_now_ms();
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 1);
	assert_write(0, RD_ANSWER);
	mock_port_events(ev, sizeof ev);
	assert_string_equal(ev, "W");
	assert_true(mock_port_event_ms(0) - t0 >= 60);
}

static void test_serve_reply_faults(void **state)
{
	struct df1 *h = *state;

	/* a bad check on the reply; then a copy with TNS - 2 before the reply
	 * (the same command twice: duplicate detection off, so each is run) */
	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_DUP_DETECT, 0), 0);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_CORRUPT_REPLY, 1000, 0), 0);
	mock_port_feed_hex(RD_WIRE);
	assert_int_equal(serve_script(h), 1);
	assert_write(0, "10 02 00 01 4F 00 04 00 11 22 33 44 10 03 11 BC");
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_CORRUPT_REPLY, 0, 0), 0);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_STALE_REPLY, 1000, 0), 0);
	mock_port_clear_written();
	mock_port_feed_hex(RD_WIRE);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write(0, "10 02 00 01 4F 00 02 00 11 22 33 44 10 03 77 43");
	assert_write(1, RD_ANSWER);
}

/* ------------------------------------------------------------------------
 * Store and forward on a handle: node 2 of the chain, table {1, 3, 4}
 * ------------------------------------------------------------------------ */

static int radio_setup_node2(void **state)
{
	uint8_t t[32];

	radio_setup(state);
	((struct df1 *)*state)->cfg.station = 2;
	assert_int_equal(df1_forward_parse("1,3-4", t), 0);
	assert_int_equal(df1_set_forward(*state, t), 0);
	return 0;
}

static void test_relay(void **state)
{
	struct df1 *h = *state;

	mock_port_feed_hex(CH_CMD);   /* from 1: relayed unchanged */
	mock_port_feed_hex(CH_CMD);   /* 3's copy of it: a duplicate, dropped */
	mock_port_feed_hex(CH_REPLY); /* 3's copy of 4's reply to 1: relayed */
	mock_port_feed_hex(OWN_CMD_2); /* SRC = 2 (DST 4, bit set): never relayed */
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(mock_port_writes(), 2);
	assert_write(0, CH_CMD);
	assert_write(1, CH_REPLY);
	assert_int_equal(stats(h).relayed, 2);
	assert_int_equal(stats(h).duplicates, 1);
}

static void test_relay_while_waiting(void **state)
{
	struct df1 *h = *state;
	uint8_t cmd[32], out[64];
	size_t n = hex(RD_CMD, cmd);
	static const char reply_to_2[] = "10 02 02 01 4F 00 04 00 00 00 C0 3F 10 03 3E 43";

	/* node 2 reads station 1; 1's command to 4 passes by meanwhile */
	mock_port_feed_hex(CH_CMD);
	mock_port_feed_hex(reply_to_2);
	assert_int_equal(link_transact(h, cmd, n, out, sizeof out), 10);
	assert_int_equal(mock_port_writes(), 2);
	assert_write(0, "10 02 01 02 0F 00 04 00 A2 04 08 8A 00 00 10 03 F0 04");
	assert_write(1, CH_CMD);
}

static void test_relay_broadcast(void **state)
{
	struct df1 *h = *state;
	uint8_t t[32];

	/* bit 255 clear: executed, not relayed */
	mock_port_feed_hex(BC_WIRE);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 0);
	/* bit 255 set: relayed and executed */
	assert_int_equal(df1_forward_parse("255", t), 0);
	assert_int_equal(df1_set_forward(h, t), 0);
	radio_dup_clear(&h->radio_dups);
	mock_port_feed_hex(BC_WIRE);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 2);
	assert_int_equal(mock_port_writes(), 1);
	assert_write(0, BC_WIRE);
}

/* ------------------------------------------------------------------------
 * The pure pieces
 * ------------------------------------------------------------------------ */

static void key(uint8_t *app, uint8_t dst, uint8_t src, uint8_t cmd, uint8_t sts, uint16_t tns)
{
	app[0] = dst, app[1] = src, app[2] = cmd, app[3] = sts;
	app[4] = (uint8_t)(tns & 0xFF), app[5] = (uint8_t)(tns >> 8);
	app[6] = 0xA2;
}

static void test_dup_table(void **state)
{
	struct radio_dup d;
	uint8_t a[8], b[8];

	(void)state;
	radio_dup_clear(&d);
	for (int i = 0; i < 20; i++) {
		key(a, 1, 0, 0x0F, 0, (uint16_t)(100 + i));
		assert_false(radio_dup_seen(&d, a, 7));
		radio_dup_add(&d, a, 7);
	}
	for (int i = 0; i < 20; i++) {
		key(a, 1, 0, 0x0F, 0, (uint16_t)(100 + i));
		assert_true(radio_dup_seen(&d, a, 7));
	}
	/* the key: each of DST SRC CMD STS TNS TNS counts, the data does not */
	key(a, 1, 0, 0x0F, 0, 100);
	a[6] = 0x55;
	assert_true(radio_dup_seen(&d, a, 7));
	for (int i = 0; i < 6; i++) {
		key(b, 1, 0, 0x0F, 0, 100);
		b[i] ^= 0x80;
		assert_false(radio_dup_seen(&d, b, 7));
	}
	assert_false(radio_dup_seen(&d, a, 5)); /* too short to have a key */
	/* a 21st packet pushes out the oldest only */
	key(a, 1, 0, 0x0F, 0, 200);
	radio_dup_add(&d, a, 7);
	key(a, 1, 0, 0x0F, 0, 100);
	assert_false(radio_dup_seen(&d, a, 7));
	key(a, 1, 0, 0x0F, 0, 101);
	assert_true(radio_dup_seen(&d, a, 7));
	key(a, 1, 0, 0x0F, 0, 119);
	assert_true(radio_dup_seen(&d, a, 7));
}

static void test_forward_rule(void **state)
{
	uint8_t t[32], a[8];

	(void)state;
	assert_int_equal(radio_fwd_parse("1,3-5", t), 0);
	key(a, 4, 1, 0x0F, 0, 1);
	assert_true(radio_fwd_rule(t, 2, a, 7));   /* DST bit set, not ours */
	key(a, 2, 1, 0x0F, 0, 1);
	assert_false(radio_fwd_rule(t, 2, a, 7));  /* DST is own (bit clear too) */
	assert_int_equal(radio_fwd_parse("1-5", t), 0);
	assert_false(radio_fwd_rule(t, 2, a, 7));  /* DST own even with its bit set */
	key(a, 4, 2, 0x0F, 0, 1);
	assert_false(radio_fwd_rule(t, 2, a, 7));  /* SRC own */
	key(a, 6, 1, 0x0F, 0, 1);
	assert_false(radio_fwd_rule(t, 2, a, 7));  /* DST bit clear */
	key(a, 255, 1, 0x0F, 0, 1);
	assert_false(radio_fwd_rule(t, 2, a, 7));  /* broadcast, bit 255 clear */
	assert_int_equal(radio_fwd_parse("255", t), 0);
	assert_true(radio_fwd_rule(t, 2, a, 7));
}

/* The chain 1-2-3-4 of doc/PROTOCOL.md 2.6 (AG-UM008 4-32): each node hears its
 * neighbours only; node 2 forwards {1,3,4}, node 3 {1,2,4}, 1 and 4 nothing
 * (so their duplicate detection, auto, is off). Each transmission is heard,
 * hop by hop, and what every node does is checked. */
struct chain_node {
	uint8_t table[32];
	bool dup_on;
	struct radio_dup dups;
	int executed, taken, relayed, dups_dropped;
};

static struct chain_node chain[5];
static char chain_log[256];

/* Node n transmits app; its neighbours hear it. Returns nothing; recursion is the air. */
static void chain_send(int n, const uint8_t *app);

static void chain_hear(int n, const uint8_t *app)
{
	struct chain_node *c = &chain[n];
	char ev[16];

	if (c->dup_on) {
		if (radio_dup_seen(&c->dups, app, 7)) {
			c->dups_dropped++;
			return;
		}
		radio_dup_add(&c->dups, app, 7);
	}
	if (app[0] != n && radio_fwd_rule(c->table, (uint8_t)n, app, 7)) {
		c->relayed++;
		snprintf(ev, sizeof ev, "%d>", n);
		strcat(chain_log, ev);
		chain_send(n, app);
	}
	if (app[1] == n || app[0] != n)
		return;
	if (app[2] & 0x40) {
		c->taken++;
		snprintf(ev, sizeof ev, "%d!", n);
		strcat(chain_log, ev);
	} else {
		uint8_t r[8];

		c->executed++;
		snprintf(ev, sizeof ev, "%d*", n);
		strcat(chain_log, ev);
		key(r, app[1], (uint8_t)n, (uint8_t)(app[2] | 0x40), 0, (uint16_t)(app[4] | app[5] << 8));
		chain_send(n, r);
	}
}

static void chain_send(int n, const uint8_t *app)
{
	uint8_t copy[8];

	memcpy(copy, app, 7);
	if (n > 1)
		chain_hear(n - 1, copy);
	if (n < 4)
		chain_hear(n + 1, copy);
}

static void test_forward_chain(void **state)
{
	uint8_t cmd[8];

	(void)state;
	memset(chain, 0, sizeof chain);
	chain_log[0] = '\0';
	assert_int_equal(radio_fwd_parse("1,3,4", chain[2].table), 0);
	assert_int_equal(radio_fwd_parse("1,2,4", chain[3].table), 0);
	chain[2].dup_on = chain[3].dup_on = true;
	key(cmd, 4, 1, 0x0F, 0, 7);
	chain_send(1, cmd);
	/* 2 relays 1's command; 3 relays 2's copy; 4 runs it and replies; 3 relays
	 * the reply, 2 relays 3's copy, 1 takes it */
	assert_string_equal(chain_log, "2>3>4*3>2>1!");
	assert_int_equal(chain[4].executed, 1);
	assert_int_equal(chain[1].taken, 1);
	/* 2 drops 3's copy of the command, 3 drops 2's copy of the reply */
	assert_int_equal(chain[2].dups_dropped, 1);
	assert_int_equal(chain[3].dups_dropped, 1);
	assert_int_equal(chain[2].relayed, 2);
	assert_int_equal(chain[3].relayed, 2);
}

static void test_forward_parse(void **state)
{
	uint8_t t[32];

	(void)state;
	assert_int_equal(df1_forward_parse("1,3-5,255", t), 0);
	assert_int_equal(t[0], 0x3A); /* 1, 3, 4, 5 */
	assert_int_equal(t[31], 0x80);
	for (int i = 1; i < 31; i++)
		assert_int_equal(t[i], 0);
	assert_int_equal(df1_forward_parse(" 0 - 7 , 8", t), 0);
	assert_int_equal(t[0], 0xFF);
	assert_int_equal(t[1], 0x01);
	assert_int_equal(df1_forward_parse("none", t), 0);
	assert_int_equal(t[0], 0);
	assert_int_equal(df1_forward_parse("", t), 0);
	static const char *bad[] = { "256", "5-3", "1,,2", "a", "1-", "-1", "1;2", "1,", "3 4" };
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		assert_int_equal(df1_forward_parse(bad[i], t), DF1_E_INVAL);
}

static void test_forward_setter(void **state)
{
	struct df1 *h = *state;
	uint8_t t[32] = { 0 }, got[32];

	assert_int_equal(df1_get_forward(h, got), 0);
	t[0] = 0x02;
	assert_int_equal(df1_set_forward(h, t), 0);
	assert_int_equal(df1_get_forward(h, got), 1);
	assert_memory_equal(got, t, 32);
	assert_int_equal(df1_set_forward(h, NULL), 0);
	assert_int_equal(df1_get_forward(h, got), 0);
}

/* ------------------------------------------------------------------------
 * Keying: RTS/CTS and DCD against the mock's fake lines
 * ------------------------------------------------------------------------ */

static int send_broadcast(struct df1 *h)
{
	uint8_t cmd[32], out[64];
	size_t n = hex(BC_CMD, cmd);

	return link_transact(h, cmd, n, out, sizeof out);
}

static void test_rts_cts(void **state)
{
	struct df1 *h = *state;
	char ev[16];

	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_RTS_CTS, 1), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_RTS_SEND_DELAY_MS, 10), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_RTS_OFF_DELAY_MS, 20), 0);
	mock_port_lines(30, 0); /* CTS 30 ms after RTS */
	assert_int_equal(send_broadcast(h), 6);
	mock_port_events(ev, sizeof ev);
	assert_string_equal(ev, "RWr");
	/* the frame waited for CTS; RTS stayed up the off delay after it */
	assert_true(mock_port_event_ms(1) - mock_port_event_ms(0) >= 30);
	assert_true(mock_port_event_ms(2) - mock_port_event_ms(1) >= 20);
	assert_int_equal(stats(h).undelivered, 0);
}

static void test_no_cts(void **state)
{
	struct df1 *h = *state;
	char ev[16];

	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_RTS_CTS, 1), 0);
	mock_port_lines(-1, 0); /* CTS never */
	assert_int_equal(send_broadcast(h), DF1_E_TIMEOUT);
	mock_port_events(ev, sizeof ev);
	assert_string_equal(ev, "Rr"); /* discarded: RTS down, nothing written */
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(stats(h).undelivered, 1);
	assert_int_equal(stats(h).sent, 0);
	assert_non_null(strstr(df1_last_error(h)->message, "CTS"));
}

static void test_dcd_wait(void **state)
{
	struct df1 *h = *state;
	char ev[16];
	int64_t t0 = df1_now_ms();

	assert_int_equal(df1_set_option(h, DF1_OPT_DCD_WAIT_MS, 500), 0);
	mock_port_lines(-1, 40); /* carrier up 40 ms more */
	assert_int_equal(send_broadcast(h), 6);
	mock_port_events(ev, sizeof ev);
	assert_string_equal(ev, "W"); /* no RTS/CTS asked: DCD only */
	assert_true(mock_port_event_ms(0) - t0 >= 40);

	mock_port_clear_written();
	mock_port_lines(-1, 5000); /* carrier stays up past the wait */
	assert_int_equal(df1_set_option(h, DF1_OPT_DCD_WAIT_MS, 50), 0);
	assert_int_equal(send_broadcast(h), DF1_E_TIMEOUT);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(stats(h).undelivered, 1);
}

static void test_no_modem_lines(void **state)
{
	struct df1 *h = *state;
	size_t notes = 0;

	/* the mock without lines answers as a pty: sent unkeyed, said once */
	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_RTS_CTS, 1), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_DCD_WAIT_MS, 100), 0);
	assert_int_equal(send_broadcast(h), 6);
	assert_int_equal(send_broadcast(h), 6);
	assert_int_equal(mock_port_writes(), 2);
	for (size_t i = 0; i < log_n; i++)
		notes += log_ids[i] == 0 && strstr(log_last[i], "no modem lines") != NULL;
	assert_int_equal(notes, 1);
	assert_int_equal(df1_set_option(h, DF1_OPT_RTS_SEND_DELAY_MS, 65536), DF1_E_CONFIG);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_read, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_read_bcc, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_write, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_broadcast, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_timeout, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_app_retries, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_bad_check_dropped, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_own_command_relayed_back, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_others_ignored, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_duplicated_reply, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_duplicated_reply_detected, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_stray_symbols, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_dle_pair_in_frame, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_link_test_echo, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_serve_answers, radio_setup_resp, teardown),
		cmocka_unit_test_setup_teardown(test_serve_broadcast_no_reply, radio_setup_resp, teardown),
		cmocka_unit_test_setup_teardown(test_serve_ignores_others, radio_setup_resp, teardown),
		cmocka_unit_test_setup_teardown(test_serve_duplicate_command, radio_setup_resp, teardown),
		cmocka_unit_test_setup_teardown(test_serve_delayed_reply, radio_setup_resp, teardown),
		cmocka_unit_test_setup_teardown(test_serve_reply_faults, radio_setup_resp, teardown),
		cmocka_unit_test_setup_teardown(test_relay, radio_setup_node2, teardown),
		cmocka_unit_test_setup_teardown(test_relay_while_waiting, radio_setup_node2, teardown),
		cmocka_unit_test_setup_teardown(test_relay_broadcast, radio_setup_node2, teardown),
		cmocka_unit_test(test_dup_table),
		cmocka_unit_test(test_forward_rule),
		cmocka_unit_test(test_forward_chain),
		cmocka_unit_test(test_forward_parse),
		cmocka_unit_test_setup_teardown(test_forward_setter, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_rts_cts, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_no_cts, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_dcd_wait, radio_setup, teardown),
		cmocka_unit_test_setup_teardown(test_no_modem_lines, radio_setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
