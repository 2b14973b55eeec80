/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_link_core - the link rules every mode shares (lib/link/core.c, link.c):
 * a transaction in the wrong mode and the flush, TX_Delay before every
 * transmission, --line-baud pacing, the trace hook and echo discarding, against
 * the scripted port (tests/support/mock_port.c; fixture tests/support/link_fixture.c).
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

static void test_mode_mismatch_and_flush(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	/* a slave's own command waits for a poll that never comes (lib/link/half_msg.c) */
	h->cfg.cmd_timeout_ms = 50;
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_TIMEOUT);
	h->cfg.cmd_timeout_ms = 1000;
	assert_int_equal(link_test(h, 1), DF1_E_NOTSUP);
	h->cfg.duplex = DF1_HALF_DUPLEX_MASTER;
	assert_int_equal(link_serve(h, server_responder(h), NULL, NULL, df1_now_ms()), DF1_E_INVAL);
	h->cfg.duplex = DF1_FULL_DUPLEX;
	/* half a frame in the decoder and unread bytes, then a flush */
	{
		static const uint8_t part[4] = { 0x10, 0x02, 0x00, 0x01 };
		struct df1_symbol sym;

		assert_int_equal(link_setup(h), 0);
		frame_decoder_feed(&h->dec, part, sizeof part, &sym);
		memcpy(h->rxbuf, part, sizeof part);
		h->rx_pos = 0;
		h->rx_len = sizeof part;
	}
	assert_true(frame_decoder_busy(&h->dec));
	link_flush(h);
	assert_false(frame_decoder_busy(&h->dec));
	assert_int_equal(h->rx_pos, h->rx_len);
}

/* ------------------------------------------------------------------------
 * Transmission: TX_Delay, pacing, trace, echo
 * ------------------------------------------------------------------------ */

static void test_tx_delay_before_every_transmission(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	int64_t t0;

	h->cfg.tx_delay_ms = 25;
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	t0 = df1_now_ms();
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_true(df1_now_ms() - t0 >= 2 * 25); /* the command and the ACK */
}

static void test_line_baud_paces_bytes(void **state)
{
	struct df1 *h = *state;
	uint8_t buf[120];
	int64_t t0;

	memset(buf, 0x41, sizeof buf);
	h->cfg.line_baud = 9600; /* 960 characters a second: 120 take 125 ms */
	t0 = df1_now_ms();
	assert_int_equal(link_send_raw(h, buf, sizeof buf), 0);
	assert_true(df1_now_ms() - t0 >= 120);
	assert_true(mock_port_writes() > 1); /* written as the line would carry them */
	{
		size_t n;

		mock_port_written(&n);
		assert_int_equal(n, sizeof buf);
	}
	assert_int_equal(cnt(h, 2560), sizeof buf);
}

struct trace_rec {
	uint8_t tx[512], rx[512];
	size_t ntx, nrx;
	uint64_t last_us;
	bool monotonic;
};

static void trace_cb(void *user, enum df1_dir dir, const uint8_t *b, size_t n, uint64_t t_us)
{
	struct trace_rec *t = user;

	if (t_us < t->last_us)
		t->monotonic = false;
	t->last_us = t_us;
	if (dir == DF1_DIR_TX) {
		memcpy(t->tx + t->ntx, b, n);
		t->ntx += n;
	} else {
		memcpy(t->rx + t->nrx, b, n);
		t->nrx += n;
	}
}

static void test_trace_sees_every_chunk(void **state)
{
	struct df1 *h = *state;
	struct trace_rec t = { .monotonic = true };
	uint8_t out[300], rx[FRAME_MAX_WIRE];
	size_t n = reply_wire(DF1_CHECK_CRC, 1, rx + 2), wn;

	memcpy(rx, ACK, 2);
	df1_set_trace(h, trace_cb, &t);
	mock_port_feed(rx, 2 + n);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(t.nrx, 2 + n);
	assert_memory_equal(t.rx, rx, 2 + n);
	const uint8_t *w = mock_port_written(&wn);
	assert_int_equal(t.ntx, wn);
	assert_memory_equal(t.tx, w, wn);
	assert_true(t.monotonic);
}

/* Echo: every write comes back first, then the peer's answer. */
static const uint8_t *echo_answer;
static size_t echo_answer_len;

static void echo_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	mock_port_feed(buf, n);
	if (echo_answer_len) {
		mock_port_feed(echo_answer, echo_answer_len);
		echo_answer_len = 0;
	}
}

static void test_echo_discarded(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], ans[FRAME_MAX_WIRE];

	h->cfg.echo_discard = true;
	memcpy(ans, ACK, 2);
	echo_answer_len = 2 + reply_wire(DF1_CHECK_CRC, 1, ans + 2);
	echo_answer = ans;
	mock_port_on_write(echo_hook, NULL);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	/* our own frame coming back was not taken for a (bad) frame or a command */
	assert_int_equal(cnt(h, 2533), 0);
	assert_int_equal(cnt(h, 2550), 0);
	assert_int_equal(mock_port_writes(), 2);
	/* the echo of our last ACK is still on its way */
	assert_int_equal(h->echo_len - h->echo_pos, 2);
	assert_int_equal(mock_port_pending(), 1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_mode_mismatch_and_flush, setup, teardown),
		cmocka_unit_test_setup_teardown(test_tx_delay_before_every_transmission, setup, teardown),
		cmocka_unit_test_setup_teardown(test_line_baud_paces_bytes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_trace_sees_every_chunk, setup, teardown),
		cmocka_unit_test_setup_teardown(test_echo_discarded, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
