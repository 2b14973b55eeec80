/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_pipe - the full-duplex master's pipeline (lib/link/pipe.c) on the mock
 * port: several commands on the line, each reply matched to its slot by SRC
 * and full TNS whatever the order it comes in, NAK and timeouts ending only
 * their own slot, stale replies dropped, a frame sent only after the previous
 * one was ACKed, and the put / wait calls the poll engine uses.
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
#include "support/mock_port.h"

static const uint8_t ACK[2] = { 0x10, 0x06 };
static const uint8_t NAK[2] = { 0x10, 0x15 };
static const uint8_t ENQ[2] = { 0x10, 0x05 };

static int setup(void **state)
{
	struct df1 *h = NULL;

	mock_port_reset();
	assert_int_equal(df1_new(&h), 0);
	h->port = &mock_port_ops;
	h->fd = 0;
	h->cfg.duplex = DF1_FULL_DUPLEX;
	h->cfg.check = DF1_CHECK_CRC;
	h->cfg.timeout_ms = 50;
	h->cfg.cmd_timeout_ms = 500;
	h->cfg.max_outstanding = 3;
	h->next_tns = 1;
	*state = h;
	return 0;
}

static int teardown(void **state)
{
	struct df1 *h = *state;

	h->port = NULL;
	h->fd = -1;
	df1_free(h);
	mock_port_reset();
	return 0;
}

static uint64_t cnt(struct df1 *h, int id)
{
	uint64_t v = 0;

	assert_int_equal(df1_counter(h, id, &v), 0);
	return v;
}

/* An SLC read of N7:elem (2 bytes) to station stn; the link sets SRC and TNS. */
static size_t read_cmd(uint8_t *cmd, uint8_t stn, uint8_t elem)
{
	const uint8_t c[] = { stn, 0, 0x0F, 0, 0, 0, 0xA2, 2, 7, 0x89, elem, 0 };

	memcpy(cmd, c, sizeof c);
	return sizeof c;
}

static int submit(struct df1 *h, uint8_t stn, uint8_t elem)
{
	uint8_t cmd[16];
	size_t n = read_cmd(cmd, stn, elem);
	int slot;

	slot = link_pipe_put(h, cmd, n); /* queued, not sent yet */
	assert_true(slot >= 0);
	return slot;
}

/* The reply frame of station src to TNS tns, carrying the word value. */
static void feed_reply(uint8_t src, uint16_t tns, uint8_t cmd, uint16_t value)
{
	uint8_t app[8] = { 0, src, cmd, 0, (uint8_t)tns, (uint8_t)(tns >> 8), (uint8_t)value,
	                   (uint8_t)(value >> 8) };
	uint8_t wire[FRAME_MAX_WIRE];
	size_t wn = frame_encode_full(DF1_CHECK_CRC, app, sizeof app, wire, sizeof wire);

	mock_port_feed(wire, wn);
}

static void assert_value(int r, const uint8_t *out, uint16_t tns, uint16_t value)
{
	assert_int_equal(r, 8);
	assert_int_equal(out[4] | out[5] << 8, tns);
	assert_int_equal(out[6] | out[7] << 8, value);
}

/* The TNS of the command frame in write call i. */
static uint16_t written_tns(size_t i)
{
	size_t n;
	const uint8_t *w = mock_port_write_at(i, &n);

	if (n > 2 && w[0] == 0x10 && w[1] == 0x06) {
		w += 2; /* an ACK that went with this command */
		n -= 2;
	}
	assert_true(n > 8);
	assert_int_equal(w[0], 0x10);
	assert_int_equal(w[1], 0x02);
	return (uint16_t)(w[6] | w[7] << 8);
}

/* Write call i begins with DLE ACK and goes on with a command frame. */
static bool written_ack_then_cmd(size_t i)
{
	size_t n;
	const uint8_t *w = mock_port_write_at(i, &n);

	return n > 10 && memcmp(w, ACK, 2) == 0 && w[2] == 0x10 && w[3] == 0x02;
}

static bool written_is(size_t i, const uint8_t *sym)
{
	size_t n;
	const uint8_t *w = mock_port_write_at(i, &n);

	return n == 2 && memcmp(w, sym, 2) == 0;
}

/* Three on the line, replies out of order: each to its own slot. */
static void test_replies_matched_by_tns(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int a = submit(h, 1, 0), b = submit(h, 1, 1), c = submit(h, 2, 2);

	mock_port_feed(ACK, 2);
	mock_port_feed(ACK, 2);
	mock_port_feed(ACK, 2);
	feed_reply(2, 3, 0x4F, 300);
	feed_reply(1, 2, 0x4F, 200);
	feed_reply(1, 1, 0x4F, 100);
	assert_value(link_pipe_wait(h, a, out, sizeof out), out, 1, 100);
	assert_value(link_pipe_wait(h, c, out, sizeof out), out, 3, 300);
	assert_value(link_pipe_wait(h, b, out, sizeof out), out, 2, 200);
	/* each command went after the ACK of the one before, before any reply */
	assert_int_equal(written_tns(0), 1);
	assert_int_equal(written_tns(1), 2);
	assert_int_equal(written_tns(2), 3);
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_SENT), 3);
	assert_int_equal(cnt(h, DF1_ID_CNT_REPLY_MSGS_RCVD), 3);
	assert_int_equal(cnt(h, DF1_ID_CNT_STALE_MSGS_RCVD), 0);
	assert_int_equal(link_pipe_used(h), 0);
}

/* No more than the depth on the line: the fourth waits for a reply. */
static void test_depth_limits_the_line(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int s[4];

	h->cfg.max_outstanding = 2;
	for (int i = 0; i < 4; i++)
		s[i] = submit(h, 1, (uint8_t)i);
	mock_port_feed(ACK, 2);
	mock_port_feed(ACK, 2);
	feed_reply(1, 1, 0x4F, 10);
	mock_port_feed(ACK, 2);
	feed_reply(1, 2, 0x4F, 11);
	mock_port_feed(ACK, 2);
	feed_reply(1, 3, 0x4F, 12);
	feed_reply(1, 4, 0x4F, 13);
	assert_value(link_pipe_wait(h, s[0], out, sizeof out), out, 1, 10);
	/* cmd1, cmd2 (after ACK 1), then the ACK of reply 1 and cmd3 in one write:
	 * two on the line at most */
	assert_int_equal(written_tns(0), 1);
	assert_int_equal(written_tns(1), 2);
	assert_int_equal(mock_port_writes(), 3);
	assert_true(written_ack_then_cmd(2));
	assert_int_equal(written_tns(2), 3);
	for (int i = 1; i < 4; i++)
		assert_value(link_pipe_wait(h, s[i], out, sizeof out), out, (uint16_t)(i + 1),
		             (uint16_t)(10 + i));
	assert_true(written_ack_then_cmd(3));
	assert_int_equal(written_tns(3), 4);
	assert_int_equal(cnt(h, DF1_ID_CNT_ACKS_SENT), 4);
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_SENT), 4);
}

/* A NAK retransmits only the frame waiting for its ACK. */
static void test_nak_only_its_own(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int a = submit(h, 1, 0), b = submit(h, 1, 1);

	mock_port_feed(ACK, 2);      /* cmd 1 */
	mock_port_feed(NAK, 2);      /* cmd 2: sent again */
	mock_port_feed(ACK, 2);
	feed_reply(1, 1, 0x4F, 7);
	feed_reply(1, 2, 0x4F, 8);
	assert_value(link_pipe_wait(h, b, out, sizeof out), out, 2, 8);
	assert_value(link_pipe_wait(h, a, out, sizeof out), out, 1, 7);
	assert_int_equal(written_tns(0), 1);
	assert_int_equal(written_tns(1), 2);
	assert_int_equal(written_tns(2), 2);
	assert_int_equal(cnt(h, DF1_ID_CNT_NAK_RETRIES), 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_SENT), 2);
	assert_int_equal(cnt(h, DF1_ID_CNT_MSG_PACKETS_SENT), 3);
}

/* A lost reply ends its own slot with DF1_E_TIMEOUT; the other still gets its
 * reply, and the error detail is the failed slot's, not the last one seen. */
static void test_lost_reply_only_its_own(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int a = submit(h, 1, 0), b = submit(h, 2, 1);

	mock_port_feed(ACK, 2);
	mock_port_feed(ACK, 2);
	feed_reply(2, 2, 0x4F, 9);
	mock_port_expire();          /* reply timer of slot a */
	df1_clear_error(h);
	assert_value(link_pipe_wait(h, b, out, sizeof out), out, 2, 9);
	assert_int_equal(h->err.code, 0);
	assert_int_equal(link_pipe_wait(h, a, out, sizeof out), DF1_E_TIMEOUT);
	assert_int_equal(h->err.code, DF1_E_TIMEOUT);
	assert_int_equal(h->err.station, 1);
	assert_int_equal(cnt(h, DF1_ID_CNT_COMMAND_TIMEOUTS), 1);
	/* never sent again once ACKed */
	assert_int_equal(cnt(h, DF1_ID_CNT_MSG_PACKETS_SENT), 2);
}

/* No ACK: ENQ for the frame on the line, then its ENQ limit; the next one goes. */
static void test_enq_limit_only_its_own(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int a, b;

	h->cfg.enq_retries = 1;
	a = submit(h, 1, 0);
	b = submit(h, 1, 1);
	mock_port_expire();          /* ACK timer: ENQ */
	mock_port_expire();          /* again: ENQ limit */
	mock_port_feed(ACK, 2);      /* cmd 2 */
	feed_reply(1, 2, 0x4F, 5);
	assert_int_equal(link_pipe_wait(h, a, out, sizeof out), DF1_E_ENQ_LIMIT);
	assert_value(link_pipe_wait(h, b, out, sizeof out), out, 2, 5);
	assert_true(written_is(1, ENQ));
	assert_int_equal(written_tns(2), 2);
}

/* A reply nobody waits for (unknown TNS) is ACKed, counted stale, dropped. */
static void test_stale_dropped(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int a = submit(h, 1, 0);

	mock_port_feed(ACK, 2);
	feed_reply(1, 0x7777, 0x4F, 1);
	feed_reply(1, 1, 0x4F, 2);
	assert_value(link_pipe_wait(h, a, out, sizeof out), out, 1, 2);
	assert_int_equal(cnt(h, DF1_ID_CNT_STALE_MSGS_RCVD), 1);
}

/* The reply before the ACK (ACK lost in noise): delivered, the line is free. */
static void test_reply_before_ack(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int a = submit(h, 1, 0), b = submit(h, 1, 1);

	feed_reply(1, 1, 0x4F, 3);
	mock_port_feed(ACK, 2);
	feed_reply(1, 2, 0x4F, 4);
	assert_value(link_pipe_wait(h, a, out, sizeof out), out, 1, 3);
	assert_value(link_pipe_wait(h, b, out, sizeof out), out, 2, 4);
}

/* A wrong CMD in the matched reply is that slot's DF1_E_BAD_FUNCTION. */
static void test_wrong_cmd_its_own(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int a = submit(h, 1, 0);

	mock_port_feed(ACK, 2);
	feed_reply(1, 1, 0x46, 3);
	assert_int_equal(link_pipe_wait(h, a, out, sizeof out), DF1_E_BAD_FUNCTION);
}

/* Wait: the slot's reply as link_transact would return it (the client's own
 * checks run on it); another command goes through the pipeline behind. */
static void test_wait_and_sync_behind(void **state)
{
	struct df1 *h = *state;
	uint8_t cmd[16], out[64];
	size_t n;
	int a = submit(h, 1, 0);

	mock_port_feed(ACK, 2);
	feed_reply(1, 1, 0x4F, 42);
	assert_value(link_pipe_wait(h, a, out, sizeof out), out, 1, 42);
	assert_int_equal(link_pipe_used(h), 0);
	/* the pipeline empty: the old path, byte for byte as before */
	mock_port_feed(ACK, 2);
	feed_reply(1, 2, 0x4F, 43);
	n = read_cmd(cmd, 1, 5);
	assert_value(link_transact(h, cmd, n, out, sizeof out), out, 2, 43);
	/* a slot in use: an ordinary transaction queues behind it */
	a = submit(h, 1, 0);
	mock_port_feed(ACK, 2);
	mock_port_feed(ACK, 2);
	feed_reply(1, 3, 0x4F, 1);
	feed_reply(1, 4, 0x4F, 2);
	n = read_cmd(cmd, 1, 9);
	assert_value(link_transact(h, cmd, n, out, sizeof out), out, 4, 2);
	link_pipe_abandon(h, a); /* its reply came already: freed */
	assert_int_equal(link_pipe_used(h), 0);
}

/* Abandoned slots on the line: flushed, their replies dropped quietly. */
static void test_flush_abandoned(void **state)
{
	struct df1 *h = *state;
	uint8_t out[64];
	int a = submit(h, 1, 0);

	(void)submit(h, 1, 1);
	(void)submit(h, 1, 2);
	mock_port_feed(ACK, 2);
	mock_port_feed(ACK, 2);
	feed_reply(1, 1, 0x4F, 1);
	assert_value(link_pipe_wait(h, a, out, sizeof out), out, 1, 1);
	/* the second waits for its reply, the third for its ACK */
	mock_port_feed(ACK, 2);
	feed_reply(1, 3, 0x4F, 3);
	feed_reply(1, 2, 0x4F, 2);
	assert_int_equal(link_pipe_flush(h), 0);
	assert_int_equal(link_pipe_used(h), 0);
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_SENT), 3);
	assert_int_equal(cnt(h, DF1_ID_CNT_REPLY_MSGS_RCVD), 3);
	assert_int_equal(cnt(h, DF1_ID_CNT_STALE_MSGS_RCVD), 0);
	/* one not yet sent is dropped unsent */
	(void)submit(h, 1, 4);
	assert_int_equal(link_pipe_flush(h), 0);
	assert_int_equal(cnt(h, DF1_ID_CNT_CMD_MSGS_SENT), 3);
}

/* Half duplex: one at a time whatever the option says. */
static void test_depth_half_duplex(void **state)
{
	struct df1 *h = *state;

	assert_int_equal(link_pipe_depth(h), 3);
	h->cfg.duplex = DF1_HALF_DUPLEX_MASTER;
	assert_int_equal(link_pipe_depth(h), 1);
	assert_int_equal(df1_set_option(h, DF1_OPT_MAX_OUTSTANDING, 0), DF1_E_CONFIG);
	assert_int_equal(df1_set_option(h, DF1_OPT_MAX_OUTSTANDING, 17), DF1_E_CONFIG);
	assert_int_equal(df1_set_option(h, DF1_OPT_MAX_OUTSTANDING, 16), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_MAX_OUTSTANDING), 16);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_replies_matched_by_tns, setup, teardown),
		cmocka_unit_test_setup_teardown(test_depth_limits_the_line, setup, teardown),
		cmocka_unit_test_setup_teardown(test_nak_only_its_own, setup, teardown),
		cmocka_unit_test_setup_teardown(test_lost_reply_only_its_own, setup, teardown),
		cmocka_unit_test_setup_teardown(test_enq_limit_only_its_own, setup, teardown),
		cmocka_unit_test_setup_teardown(test_stale_dropped, setup, teardown),
		cmocka_unit_test_setup_teardown(test_reply_before_ack, setup, teardown),
		cmocka_unit_test_setup_teardown(test_wrong_cmd_its_own, setup, teardown),
		cmocka_unit_test_setup_teardown(test_wait_and_sync_behind, setup, teardown),
		cmocka_unit_test_setup_teardown(test_flush_abandoned, setup, teardown),
		cmocka_unit_test_setup_teardown(test_depth_half_duplex, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
