/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_link_half - the half-duplex link (lib/link/half.c, half_repoll.c) against
 * the scripted port (tests/support/mock_port.c; fixture tests/support/link_fixture.c):
 * the master (polls, EOT, the Active Station List, repolls, limits) and the
 * slave (replies held for the poll, duplicates, several stations, echo).
 */

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "df1_int.h"
#include "link/link.h"
#include "link/link_int.h"
#include "server/server.h"
#include "support/mock_port.h"
#include "support/link_fixture.h"

/* ------------------------------------------------------------------------
 * Half duplex, master
 * ------------------------------------------------------------------------ */

/* A scripted slave: answers by what the master wrote. */
struct hd_script {
	int msg_answers[8];   /* per master message: 1 ACK, 0 nothing */
	int nmsg;
	const char *poll_answers[16]; /* per poll: "EOT", "R<tns>", "X" (bad CRC reply), "ACK",
	                               * "NAK", "BAD" (DLE 07), NULL nothing */
	int npoll;
	uint8_t src;          /* the slave's station */
};
static struct hd_script script;

static void hd_slave_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x01) {
		if (script.msg_answers[script.nmsg++])
			mock_port_feed(ACK, 2);
		return;
	}
	if (n >= 4 && buf[0] == 0x10 && buf[1] == 0x05) {
		/* past the script: nothing, as a slave without EOT (polls repeat) */
		const char *a = script.npoll < 16 ? script.poll_answers[script.npoll] : NULL;

		script.npoll++;

		if (!a)
			return;
		if (strcmp(a, "EOT") == 0) {
			mock_port_feed(EOT, 2);
		} else if (strcmp(a, "ACK") == 0) {
			mock_port_feed(ACK, 2);
		} else if (strcmp(a, "NAK") == 0) {
			mock_port_feed(NAK, 2);
		} else if (strcmp(a, "BAD") == 0) {
			mock_port_feed_hex("10 07");
		} else if (a[0] == 'R' || a[0] == 'X') {
			uint8_t app[64], wire[FRAME_MAX_WIRE];
			unsigned tns = 0;
			size_t an, wn;

			sscanf(a + 1, "%x", &tns);
			an = make_reply(app, 0, script.src, 0x4F, 0, (uint16_t)tns, DATA20, sizeof DATA20);
			wn = frame_encode_full(DF1_CHECK_CRC, app, an, wire, sizeof wire);
			if (a[0] == 'X')
				wire[wn - 2] ^= 0x55;
			mock_port_feed(wire, wn);
		}
	}
}

static int setup_hd(void **state)
{
	struct df1 *h;

	setup(state);
	h = *state;
	h->cfg.duplex = DF1_HALF_DUPLEX_MASTER;
	memset(&script, 0, sizeof script);
	script.src = 1;
	mock_port_on_write(hd_slave_hook, NULL);
	return 0;
}

static void test_hd_five_transmissions_byte_exact(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	script.msg_answers[0] = 1;
	script.poll_answers[0] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	/* master: message, poll, ACK (the slave's two: ACK, reply) */
	assert_int_equal(mock_port_writes(), 3);
	assert_write(0, A2_HD_CRC);
	assert_write(1, "10 05 01 FF");
	assert_write_bytes(2, ACK, 2);
	assert_int_equal(cnt(h, 2525), 1);
	assert_int_equal(cnt(h, 2527), 1);
	assert_int_equal(cnt(h, 2531), 1);
	assert_int_equal(cnt(h, 2536), 1);
	assert_int_equal(cnt(h, 2535), 1);
	assert_int_equal(cnt(h, 2530), 1);
	assert_int_equal(logged(2523), 1);
	assert_string_equal(log_text(2523), "Reply Message received from Slave 1");
	assert_int_equal(df1_station_active(h, 1), 1);
}

static void test_hd_bcc_master_message_byte_exact(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.check = DF1_CHECK_BCC;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = NULL;
	script.poll_answers[1] = NULL;
	h->cfg.enq_retries = 1;
	h->cfg.cmd_timeout_ms = 500;
	/* polls nobody answers are polled again (a slave that sends no EOT),
	 * not ENQ retries, until Cmd_Timeout: DLE NAK, 2545, DF1_E_TIMEOUT */
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_write(0, A2_HD_BCC);
	assert_write(1, "10 05 01 FF");
	assert_write(2, "10 05 01 FF");
	assert_write(mock_port_writes() - 1, "10 15");
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(cnt(h, 2545), 1);
	assert_int_equal(df1_station_active(h, 1), 0);
}

static void test_hd_poll_station_16_stuffed(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], cmd[32];
	size_t n = hex(A2_CMD, cmd);

	cmd[0] = 0x10;
	script.src = 0x10;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "R0001";
	assert_int_equal(link_transact(h, cmd, n, out, sizeof out), 26);
	assert_write(0, "10 01 10 10 10 02 10 10 00 0F 00 01 00 A2 14 07 89 00 00 10 03 4F 99");
	assert_write(1, "10 05 10 10 F0");
}

static void test_hd_eot_then_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	script.msg_answers[0] = 1;
	script.poll_answers[0] = "EOT";
	script.poll_answers[1] = "EOT";
	script.poll_answers[2] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 5);
	assert_write(1, "10 05 01 FF");
	assert_write(2, "10 05 01 FF");
	assert_write(3, "10 05 01 FF");
	assert_write_bytes(4, ACK, 2);
	assert_int_equal(cnt(h, 2538), 2);
	assert_int_equal(cnt(h, 2531), 3);
	assert_int_equal(cnt(h, 2543), 0); /* EOT is not an error */
}

static void eot_forever_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x01)
		mock_port_feed(ACK, 2);
	else if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x05)
		mock_port_feed(EOT, 2);
}

static void test_hd_cmd_timeout_sends_nak(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	size_t nw;
	int64_t t0;

	h->cfg.cmd_timeout_ms = 80;
	mock_port_on_write(eot_forever_hook, NULL);
	t0 = df1_now_ms();
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_true(df1_now_ms() - t0 >= 80);
	nw = mock_port_writes();
	assert_true(nw >= 4);
	assert_write_bytes(nw - 1, NAK, 2); /* "to terminate processing" (doc/REQUIREMENTS.md 004 2545) */
	assert_int_equal(cnt(h, 2545), 1);
	assert_int_equal(cnt(h, 2533), 1);
	assert_int_equal(cnt(h, 2538), cnt(h, 2531));
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(logged(2508), 1);
	assert_int_equal(df1_station_active(h, 1), 0);
	assert_int_equal(df1_last_error(h)->code, DF1_E_TIMEOUT);
}

static void test_hd_no_ack_retransmit_then_nak_limit(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.nak_retries = 2;
	script.msg_answers[0] = 0;
	script.msg_answers[1] = 0;
	script.msg_answers[2] = 0;
	/* the mock waits timeout_ms for each missing ACK */
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NAK_LIMIT);
	assert_int_equal(mock_port_writes(), 3);
	for (size_t i = 0; i < 3; i++)
		assert_write(i, A2_HD_CRC);
	assert_int_equal(cnt(h, 2541), 2);
	assert_int_equal(cnt(h, 2542), 1);
	assert_int_equal(logged(2521), 2);
	assert_string_equal(log_text(2521), "NAK Retry #1, due to error 2508");
	assert_int_equal(df1_station_active(h, 1), 0);
}

static void test_hd_no_ack_then_ack(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	script.msg_answers[0] = 0;
	script.msg_answers[1] = 1;
	script.poll_answers[0] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_write(0, A2_HD_CRC);
	assert_write(1, A2_HD_CRC);
	assert_write(2, "10 05 01 FF");
	assert_int_equal(cnt(h, 2541), 1);
	assert_int_equal(cnt(h, 2527), 1);
	assert_int_equal(cnt(h, 2525), 2);
}

static void test_hd_bad_check_reply_repolled(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	script.msg_answers[0] = 1;
	script.poll_answers[0] = "X0001"; /* bad CRC: no ACK, poll again */
	script.poll_answers[1] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write(1, "10 05 01 FF");
	assert_write(2, "10 05 01 FF");
	assert_write_bytes(3, ACK, 2);
	assert_int_equal(cnt(h, 2547), 1);
	assert_int_equal(cnt(h, 2543), 1);
	assert_int_equal(cnt(h, 2533), 0); /* the half-duplex master never NAKs a frame */
	assert_int_equal(cnt(h, 2535), 1);
}

/* A poll answered with neither DLE EOT nor a frame: 2516 with the symbol
 * byte (doc/REQUIREMENTS.md 004 NTC_EOT_STX_EXPECTED), and polling goes on. */
static void test_hd_poll_answer_not_eot_or_stx_2516(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.enq_retries = 3;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "ACK"; /* stray: ignored, the poll unanswered: polled again */
	script.poll_answers[1] = "NAK";
	script.poll_answers[2] = "BAD";
	script.poll_answers[3] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(logged(2516), 3);
	{
		size_t k = 0;
		static const char *const want[3] = {
			"EOT or STX Expected (last symbol received was 0x06)",
			"EOT or STX Expected (last symbol received was 0x15)",
			"EOT or STX Expected (last symbol received was 0x07)",
		};

		for (size_t i = 0; i < log_n; i++)
			if (log_ids[i] == 2516)
				assert_string_equal(log_last[i], want[k++]);
	}
	assert_int_equal(logged(2517), 1);
	assert_int_equal(logged(2514), 1);
	assert_int_equal(cnt(h, 2543), 2); /* the NAK and the broken symbol; silence is no retry */
	assert_int_equal(cnt(h, 2534), 1);
	assert_int_equal(cnt(h, 2530), 1);
}

static void ack_after_garbage_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x01) {
		mock_port_feed(EOT, 2);
		mock_port_feed_hex("10 07");
		mock_port_feed(ACK, 2);
	} else if (n >= 4 && buf[0] == 0x10 && buf[1] == 0x05) {
		feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	}
}

/* Waiting for the slave's ACK of our master message, other symbols are 2515
 * (a broken one after its own notice) and ignored: the ACK still counts. */
static void test_hd_ack_expected_2515(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	size_t k = 0;

	mock_port_on_write(ack_after_garbage_hook, NULL);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(logged(2515), 2);
	for (size_t i = 0; i < log_n; i++) {
		if (log_ids[i] != 2515)
			continue;
		assert_string_equal(log_last[i], k++ == 0 ? "ACK Expected (last symbol received was 0x04)"
		                                          : "ACK Expected (last symbol received was 0x07)");
	}
	assert_int_equal(logged(2514), 1);
	assert_int_equal(cnt(h, 2541), 0); /* no retransmission */
	assert_int_equal(cnt(h, 2536), 1);
}

static int64_t write_ms[16];
static size_t write_ms_n;

static void timed_hd_slave_hook(const uint8_t *buf, size_t n, void *user)
{
	if (write_ms_n < 16)
		write_ms[write_ms_n++] = df1_now_ms();
	hd_slave_hook(buf, n, user);
}

/* TX_Delay before EVERY transmission (doc/REQUIREMENTS.md 004 "DF1 and TX_Delay"): master
 * message, each poll, the ACK of the reply; each write comes at least TX_Delay
 * after the answer to the previous one was read (the mock answers at once). */
static void test_hd_tx_delay_before_each_write(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	int64_t t0;

	h->cfg.tx_delay_ms = 25;
	write_ms_n = 0;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "EOT";
	script.poll_answers[1] = "R0001";
	mock_port_on_write(timed_hd_slave_hook, NULL);
	t0 = df1_now_ms();
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(write_ms_n, 4); /* message, poll, poll, ACK */
	assert_true(write_ms[0] - t0 >= 25);
	for (size_t i = 1; i < write_ms_n; i++)
		if (write_ms[i] - write_ms[i - 1] < 25)
			fail_msg("write %zu only %lld ms after write %zu", i,
			         (long long)(write_ms[i] - write_ms[i - 1]), i - 1);
}

static void test_hd_enq_limit(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.enq_retries = 2;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "X0001";
	script.poll_answers[1] = NULL;  /* no answer: polled again, not a retry */
	script.poll_answers[2] = "X0001";
	script.poll_answers[3] = "X0001";
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_ENQ_LIMIT);
	assert_int_equal(mock_port_writes(), 5);
	assert_int_equal(cnt(h, 2543), 2);
	assert_int_equal(cnt(h, 2544), 1);
	assert_int_equal(logged(2520), 1);
	assert_int_equal(df1_station_active(h, 1), 0);
}

static void test_hd_stale_reply_acked_and_polled_again(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->next_tns = 0x0101;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "R00FF"; /* left over from a timed-out transaction */
	script.poll_answers[1] = "R0101";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 0x0101);
	assert_int_equal(mock_port_writes(), 5);
	assert_write_bytes(2, ACK, 2);
	assert_write(3, "10 05 01 FF");
	assert_write_bytes(4, ACK, 2);
	assert_int_equal(cnt(h, 2548), 1);
	assert_int_equal(cnt(h, 2543), 0);
}

static void test_hd_inactive_station_fails_after_one_poll(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	assert_int_equal(df1_station_set_active(h, 1, false), 0);
	script.poll_answers[0] = NULL;
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_INACTIVE);
	assert_int_equal(mock_port_writes(), 1);
	assert_write(0, "10 05 01 FF");
	assert_int_equal(cnt(h, 2531), 1);
	assert_int_equal(cnt(h, 2525), 0);
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(logged(2509), 1);
	assert_string_equal(log_text(2509), "Slave Station (1) Inactive");
	assert_int_equal(df1_last_error(h)->code, DF1_E_INACTIVE);
	assert_int_equal(df1_station_active(h, 1), 0);
}

static void test_hd_inactive_station_answers_eot_proceeds(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	assert_int_equal(df1_station_set_active(h, 1, false), 0);
	script.poll_answers[0] = "EOT";
	script.msg_answers[0] = 1;
	script.poll_answers[1] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write(0, "10 05 01 FF");
	assert_write(1, A2_HD_CRC);
	assert_write(2, "10 05 01 FF");
	assert_write_bytes(3, ACK, 2);
	assert_int_equal(df1_station_active(h, 1), 1);
}

static void test_hd_inactive_station_stale_answer_proceeds(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->next_tns = 0x20;
	assert_int_equal(df1_station_set_active(h, 1, false), 0);
	script.poll_answers[0] = "R001F"; /* a stale message also proves it is alive */
	script.msg_answers[0] = 1;
	script.poll_answers[1] = "R0020";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 0x20);
	assert_int_equal(cnt(h, 2548), 1);
	assert_int_equal(df1_station_active(h, 1), 1);
}

static void test_hd_two_stations_per_station_duplicates(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], cmd[32];
	size_t n = hex(A2_CMD, cmd);

	/* station 1, TNS 1 */
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	/* station 2, TNS 2 */
	script.src = 2;
	cmd[0] = 2;
	script.msg_answers[1] = 1;
	script.poll_answers[1] = "R0002";
	assert_int_equal(link_transact(h, cmd, n, out, sizeof out), 26);
	assert_int_equal(out[1], 2);
	/* station 1 again, TNS 3: our ACK of its reply 1 was lost, it sends it again */
	script.src = 1;
	script.msg_answers[2] = 1;
	script.poll_answers[2] = "R0001";
	script.poll_answers[3] = "R0003";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 3);
	assert_int_equal(cnt(h, 2549), 1); /* a duplicate of station 1, not a stale message */
	assert_int_equal(cnt(h, 2548), 0);
	assert_int_equal(cnt(h, 2530), 3);
}

static void test_hd_link_test(void **state)
{
	struct df1 *h = *state;

	script.poll_answers[0] = "EOT";
	script.poll_answers[1] = NULL;
	assert_int_equal(link_test(h, 1), 0);
	assert_write(0, "10 05 01 FF");
	assert_int_equal(link_test(h, 1), DF1_E_TIMEOUT);
	assert_int_equal(link_test(h, 300), DF1_E_INVAL);
}

static void echo_then_slave_hook(const uint8_t *buf, size_t n, void *user)
{
	mock_port_feed(buf, n); /* the 2-wire line gives us our own bytes back first */
	hd_slave_hook(buf, n, user);
}

static void test_hd_echo_discarded(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.echo_discard = true;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "EOT";
	script.poll_answers[1] = "R0001";
	mock_port_on_write(echo_then_slave_hook, NULL);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 4);
	/* the echo of the master message and of the polls was not taken for traffic */
	assert_int_equal(cnt(h, 2526), 1);
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(logged(2515), 0);
	assert_int_equal(h->echo_len - h->echo_pos, 2);
}

/* ------------------------------------------------------------------------
 * Half duplex, slave
 * ------------------------------------------------------------------------ */


static void test_slave_full_exchange(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want);

	mock_port_feed_hex(A2_HD_CRC);
	feed_poll(1);
	mock_port_feed(ACK, 2);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(handler_last_len, 12);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, want, wn);
	assert_write_bytes(2, EOT, 2);
	assert_int_equal(cnt(h, 2528), 1);
	assert_int_equal(cnt(h, 2529), 1);
	assert_int_equal(cnt(h, 2532), 2);
	assert_int_equal(cnt(h, 2537), 1);
	assert_int_equal(cnt(h, 2536), 1);
}

static void test_slave_duplicate_executed_once(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 7, want);

	feed_master_msg(1, 7);
	feed_master_msg(1, 7); /* the master did not see our ACK */
	feed_poll(1);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, ACK, 2);
	assert_write_bytes(2, want, wn);
	assert_int_equal(cnt(h, 2549), 1);
	assert_int_equal(logged(2524), 1);
}

/* Half duplex: a different command under the accepted one's header is ACKed
 * and discarded, and the reply queued for the accepted one is dropped, so the
 * next poll gets DLE EOT, not a reply that is not its own. */
static void test_slave_duplicate_other_command_no_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t app[32], wire[FRAME_MAX_WIRE];
	size_t an = hex(A2_CMD, app), wn;

	app[4] = 7;
	app[10] = 5;                            /* N7:5 instead of N7:0 */
	wn = frame_encode_master(DF1_CHECK_CRC, 1, false, app, an, wire, sizeof wire);
	feed_master_msg(1, 7);
	mock_port_feed(wire, wn);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, ACK, 2);
	assert_write_bytes(2, EOT, 2);
	assert_int_equal(cnt(h, 2549), 1);
}

static void test_slave_reply_resent_until_acked(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 9, want);

	feed_master_msg(1, 9);
	feed_poll(1);
	feed_poll(1); /* the master found a bad check, or lost it: no ACK */
	mock_port_feed(ACK, 2);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write_bytes(1, want, wn);
	assert_write_bytes(2, want, wn);
	assert_write_bytes(3, EOT, 2);
	assert_int_equal(cnt(h, 2541), 1);
	assert_int_equal(cnt(h, 2529), 1);
	assert_int_equal(cnt(h, 2525), 2);
}

static void test_slave_gives_up_after_nak_retries(void **state)
{
	struct df1 *h = *state;

	h->cfg.nak_retries = 1;
	feed_master_msg(1, 9);
	feed_poll(1);
	feed_poll(1);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write_bytes(3, EOT, 2);
	assert_int_equal(cnt(h, 2542), 1);
}

static void test_slave_ignores_other_station(void **state)
{
	struct df1 *h = *state;

	feed_poll(2);
	feed_master_msg(2, 3);
	mock_port_feed(ACK, 2);
	feed_poll(2);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(cnt(h, 2532), 0);
}

static void test_slave_several_stations(void **state)
{
	struct df1 *h = *state;

	assert_int_equal(df1_server_add_station(h, 3), 0);
	assert_int_equal(df1_server_add_station(h, 5), 0);
	feed_poll(1); /* cfg.station is not served once stations were added */
	feed_master_msg(3, 0x30);
	feed_master_msg(5, 0x50);
	feed_poll(5);
	mock_port_feed(ACK, 2);
	feed_poll(3);
	mock_port_feed(ACK, 2);
	feed_poll(3);
	assert_int_equal(serve_script(h), 2);
	assert_int_equal(mock_port_writes(), 5);
	{
		uint8_t w5[FRAME_MAX_WIRE], w3[FRAME_MAX_WIRE];
		size_t n5 = slave_reply_wire(DF1_CHECK_CRC, 5, 0x50, w5);
		size_t n3 = slave_reply_wire(DF1_CHECK_CRC, 3, 0x30, w3);

		assert_write_bytes(2, w5, n5);
		assert_write_bytes(3, w3, n3);
		assert_write_bytes(4, EOT, 2);
	}
}

static void test_slave_nak_resets_link(void **state)
{
	struct df1 *h = *state;

	feed_master_msg(1, 4);
	mock_port_feed(NAK, 2); /* global link reset by the master */
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, EOT, 2);
	assert_int_equal(cnt(h, 2534), 1);
}

static void test_slave_bad_check_no_answer(void **state)
{
	struct df1 *h = *state;
	uint8_t wire[FRAME_MAX_WIRE];
	size_t n = hex(A2_HD_CRC, wire);

	wire[n - 1] ^= 0x01;
	mock_port_feed(wire, n);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(cnt(h, 2547), 1);
}

/* A 2-wire line without echo discard: the slave hears its own bytes; after a
 * frame of ours the master ACKs and polls again. */
static void slave_echo_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	mock_port_feed(buf, n);
	if (n > 2 && buf[1] == DF1_STX) {
		mock_port_feed(ACK, 2);
		feed_poll(1);
	}
}

static void test_slave_own_echo_does_not_hide_ack(void **state)
{
	struct df1 *h = *state;

	mock_port_on_write(slave_echo_hook, NULL);
	feed_master_msg(1, 0x31);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	/* ACK, reply, EOT: the ACK after the echo released the reply */
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(2, EOT, 2);
	assert_int_equal(cnt(h, 2541), 0);
}

static void test_slave_bcc_options(void **state)
{
	struct df1 *h = *state;

	/* BCC over STN + data (default) */
	h->cfg.check = DF1_CHECK_BCC;
	mock_port_feed_hex(A2_HD_BCC);
	assert_int_equal(serve_script(h), 1);
	/* the other reading of doc/PROTOCOL.md 2.2: STX in the sum */
	h->cfg.hd_bcc_stx = true;
	mock_port_feed_hex("10 01 01 10 02 01 00 0F 00 02 00 A2 14 07 89 00 00 10 03 A5");
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 2);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_hd_five_transmissions_byte_exact, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_bcc_master_message_byte_exact, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_poll_station_16_stuffed, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_eot_then_reply, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_cmd_timeout_sends_nak, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_no_ack_retransmit_then_nak_limit, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_no_ack_then_ack, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_bad_check_reply_repolled, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_poll_answer_not_eot_or_stx_2516, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_ack_expected_2515, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_tx_delay_before_each_write, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_enq_limit, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_stale_reply_acked_and_polled_again, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_inactive_station_fails_after_one_poll, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_inactive_station_answers_eot_proceeds, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_inactive_station_stale_answer_proceeds, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_two_stations_per_station_duplicates, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_link_test, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_echo_discarded, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_slave_full_exchange, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_duplicate_executed_once, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_duplicate_other_command_no_reply, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_reply_resent_until_acked, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_gives_up_after_nak_retries, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_ignores_other_station, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_several_stations, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_nak_resets_link, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_bad_check_no_answer, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_own_echo_does_not_hide_ack, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_bcc_options, setup_slave, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
