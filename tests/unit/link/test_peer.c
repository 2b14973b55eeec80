/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_peer - a full-duplex master that also answers its peer (lib/link/peer.c,
 * df1_set_responder(3)): byte-exact frames for both roles at once on the
 * mock port. The peer's frames are written by hand from doc/PROTOCOL.md
 * (BCC: the two's complement of the data bytes' sum; a data byte 10h is
 * sent twice): a command of the peer while ours waits for its ACK or its
 * reply, without a responder (STS 10h) and with one, a duplicate, a NAK of
 * our reply, and the pipeline.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <string.h>

#include "df1_int.h"
#include "link/link.h"
#include "link/link_int.h"
#include "support/link_fixture.h"
#include "support/mock_port.h"

/* Station 1's MSG: SLC protected typed logical write N50:0 = 10 to station 0,
 * TNS 0005: 00 01 0F 00 05 00 AA 02 32 89 00 00 0A 00; sum 186h, BCC 7A. */
static const char PEER_CMD[] = "10 02 00 01 0F 00 05 00 AA 02 32 89 00 00 0A 00 10 03 7A";
/* Our answer without a responder: 01 00 4F 10 05 00, STS 10h stuffed; sum 65h, BCC 9B. */
static const char PEER_STS10[] = "10 02 01 00 4F 10 10 05 00 10 03 9B";
/* With test_handler's STS 0 and its 4 data bytes 11 22 33 44: sum FFh, BCC 01. */
static const char PEER_DONE[] = "10 02 01 00 4F 00 05 00 11 22 33 44 10 03 01";

/* The next MSG (TNS 0006) writes N51:0 (no such file in the table): sum 188h,
 * BCC 78; the table answers EXT STS 06 (no such file): 01 00 4F F0 06 00 06,
 * sum 14Ch, BCC B4. */
static const char PEER_CMD_N51[] = "10 02 00 01 0F 00 06 00 AA 02 33 89 00 00 0A 00 10 03 78";
static const char PEER_EXT06[] = "10 02 01 00 4F F0 06 00 06 10 03 B4";

static int setup_bcc(void **state)
{
	mock_port_reset();
	log_n = 0;
	handler_calls = 0;
	handler_sts = 0;
	*state = new_handle(DF1_FULL_DUPLEX, DF1_CHECK_BCC);
	return 0;
}

/* The peer's command after the ACK of ours: ACKed, answered STS 10h at once
 * (no responder), the ACK of that answer taken, then our reply. */
static void test_unsolicited_no_responder(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	mock_port_feed(ACK, 2);
	mock_port_feed_hex(PEER_CMD);
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 1);
	r = transact_a2(h, out, sizeof out);
	assert_reply_ok(r, out, 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write(0, A2_FD_BCC);
	assert_write(1, "10 06");
	assert_write(2, PEER_STS10);
	assert_write(3, "10 06");
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_RCVD), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_INVALID_MSGS_RCVD), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_ERROR_MSGS_SENT), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_STALE_MSGS_RCVD), 0);
}

/* The peer's command before the ACK of ours: our answer waits for that ACK
 * (one frame of ours waits for an ACK at a time). */
static void test_unsolicited_before_our_ack(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	h->peer_fn = test_handler;
	mock_port_feed_hex(PEER_CMD);
	mock_port_feed(ACK, 2);  /* ours */
	mock_port_feed(ACK, 2);  /* our answer's */
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 1);
	r = transact_a2(h, out, sizeof out);
	assert_reply_ok(r, out, 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(handler_last_len, 14);
	assert_int_equal(mock_port_writes(), 4);
	assert_write(0, A2_FD_BCC);
	assert_write(1, "10 06");
	assert_write(2, PEER_DONE);
	assert_write(3, "10 06");
	assert_int_equal(cnt(h, DF1_ID_CNT_INVALID_MSGS_RCVD), 0);
	assert_int_equal(cnt(h, DF1_ID_CNT_ERROR_MSGS_SENT), 0);
}

/* The peer did not see our ACK and sends its command again: ACKed, not run
 * twice (doc/PROTOCOL.md 1.7); our NAKed answer is sent again. */
static void test_unsolicited_duplicate_and_nak(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	h->peer_fn = test_handler;
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(PEER_CMD);
	mock_port_feed_hex(PEER_CMD); /* the same frame again */
	mock_port_feed(NAK, 2);       /* our answer: again */
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 1);
	r = transact_a2(h, out, sizeof out);
	assert_reply_ok(r, out, 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_DUPLICATE_MSGS_RCVD), 1);
	assert_int_equal(mock_port_count_written((const uint8_t *)"\x10\x02\x01\x00\x4F", 5), 2);
	assert_write(0, A2_FD_BCC);
	assert_write(1, "10 06");
	assert_write(2, PEER_DONE);
	assert_write(3, "10 06");
	assert_write(4, PEER_DONE);
	assert_write(5, "10 06");
}

/* Our answer's ACK does not come: ENQ, and the peer's ACK answers it; the
 * transaction still ends with our reply. */
static void test_unsolicited_answer_enq(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int r;

	mock_port_feed(ACK, 2);
	mock_port_feed_hex(PEER_CMD);
	mock_port_expire();
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 1);
	r = transact_a2(h, out, sizeof out);
	assert_reply_ok(r, out, 1);
	assert_write(2, PEER_STS10);
	assert_write(3, "10 05");
	assert_write(4, "10 06");
	assert_int_equal(cnt(h, DF1_ID_CNT_ENQ_RETRIES), 1);
}

/* Pipelined (DF1_OPT_MAX_OUTSTANDING 2): the peer's command between our two
 * replies; its answer goes out before our next command would. */
static void test_unsolicited_pipelined(void **state)
{
	struct df1 *h = *state;
	uint8_t cmd[32], out[64];
	size_t n = hex(A2_CMD, cmd);
	int a, b;

	h->cfg.max_outstanding = 2;
	h->peer_fn = test_handler;
	a = link_pipe_put(h, cmd, n);
	n = hex(A2_CMD, cmd);
	b = link_pipe_put(h, cmd, n);
	assert_true(a >= 0 && b >= 0);
	mock_port_feed(ACK, 2);       /* TNS 1 */
	mock_port_feed(ACK, 2);       /* TNS 2 */
	mock_port_feed_hex(PEER_CMD);
	mock_port_feed(ACK, 2);       /* our answer's */
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 2);
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 1);
	assert_int_equal(link_pipe_wait(h, a, out, sizeof out), 26);
	assert_int_equal(out[4], 1);
	assert_int_equal(link_pipe_wait(h, b, out, sizeof out), 26);
	assert_int_equal(out[4], 2);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_count_written((const uint8_t *)"\x10\x02\x01\x00\x4F\x00\x05", 7), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_STALE_MSGS_RCVD), 0);
}

/* df1_set_responder with a df1_table: the peer's write lands in N50:0 (STS 0),
 * one outside the table gets the table's STS F0 / EXT STS 06. */
static void test_set_responder_table(void **state)
{
	struct df1 *h = *state;
	struct df1_table *t = NULL;
	struct df1_value v[1];
	uint8_t out[64];
	int r;

	assert_int_equal(df1_table_new(&t, DF1_PLC_SLC), 0);
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, 50, 10), 0);
	assert_int_equal(df1_set_responder(h, df1_table_server_ops(t), t), 0);
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(PEER_CMD);
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(PEER_CMD_N51);
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 1);
	r = transact_a2(h, out, sizeof out);
	assert_reply_ok(r, out, 1);
	assert_write(2, "10 02 01 00 4F 00 05 00 10 03 AB"); /* sum 55h */
	assert_write(3, "10 06");
	assert_write(4, PEER_EXT06);
	assert_int_equal(df1_table_read(t, "N50:0", v, 1), 1);
	assert_int_equal(v[0].v.i16, 10);
	assert_int_equal(cnt(h, DF1_ID_CNT_ERROR_MSGS_SENT), 1);
	assert_int_equal(df1_set_responder(h, NULL, NULL), 0);
	df1_table_free(t);
}

/* Pipelined: our answer to the peer is still waiting for its ACK when the
 * next command is put; the command waits for that ACK (it used to be held
 * back without the line being read: a hang), then goes out. */
static void test_pipelined_command_waits_for_answer_ack(void **state)
{
	struct df1 *h = *state;
	uint8_t cmd[32], out[64];
	size_t n = hex(A2_CMD, cmd), wn;
	const uint8_t *w;
	int a, b;

	h->cfg.max_outstanding = 2;
	a = link_pipe_put(h, cmd, n);
	assert_true(a >= 0);
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(PEER_CMD);
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 1);
	assert_int_equal(link_pipe_wait(h, a, out, sizeof out), 26);
	n = hex(A2_CMD, cmd);
	b = link_pipe_put(h, cmd, n);
	assert_true(b >= 0);
	mock_port_feed(ACK, 2);       /* our answer's */
	mock_port_feed(ACK, 2);       /* TNS 2 */
	feed_reply(DF1_CHECK_BCC, 0x00, 0x01, 0x4F, 0, 2);
	assert_int_equal(link_pipe_wait(h, b, out, sizeof out), 26);
	assert_int_equal(out[4], 2);
	/* the answer (after its held ACK), then the next command only after its ACK */
	w = mock_port_written(&wn);
	{
		size_t k = 0;

		for (size_t i = 0; i + 4 < wn; i++)
			if (!memcmp(w + i, "\x10\x02\x01\x00\x4F\x10", 6))
				k = i;
		assert_true(k > 0);
		/* TNS 2's frame comes after the answer */
		for (size_t i = 0; i + 8 < wn; i++)
			if (!memcmp(w + i, "\x10\x02\x01\x00\x0F\x00\x02\x00", 8))
				assert_true(i > k);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_unsolicited_no_responder, setup_bcc, teardown),
		cmocka_unit_test_setup_teardown(test_unsolicited_before_our_ack, setup_bcc, teardown),
		cmocka_unit_test_setup_teardown(test_unsolicited_duplicate_and_nak, setup_bcc, teardown),
		cmocka_unit_test_setup_teardown(test_unsolicited_answer_enq, setup_bcc, teardown),
		cmocka_unit_test_setup_teardown(test_unsolicited_pipelined, setup_bcc, teardown),
		cmocka_unit_test_setup_teardown(test_set_responder_table, setup_bcc, teardown),
		cmocka_unit_test_setup_teardown(test_pipelined_command_waits_for_answer_ack, setup_bcc,
		                                teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
