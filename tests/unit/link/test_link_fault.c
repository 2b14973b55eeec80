/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_link_fault - fault injection (lib/link/fault.c) seen from the line, and
 * master <-> responder pairs where the responder is a second handle run by the
 * mock while the master waits: clean exchanges in every mode, then each fault
 * (dropped ACK, corrupt or stale reply, noise, NAK, silence, delay) recovered.
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
 * Fault injection, seen from the line
 * ------------------------------------------------------------------------ */

static void test_fault_api_validates(void **state)
{
	struct df1 *h = *state;

	assert_int_equal(df1_server_set_fault(h, (enum df1_fault)0, 10, 0), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, (enum df1_fault)8, 10, 0), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_NOISE, 1001, 0), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_DELAY_REPLY, 10, -5), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 10, 257), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 10, -2), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(NULL, DF1_FAULT_NOISE, 10, 0), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_NOISE, 1000, 0), 0);
	assert_int_equal(server_responder(h)->faults.per_mille[DF1_FAULT_NOISE], 1000);
}

static void test_fault_rng_deterministic(void **state)
{
	struct df1 *h = *state;
	bool a[200], b[200];
	int hits = 0;

	df1_server_set_fault(h, DF1_FAULT_NOISE, 300, 0);
	df1_server_set_seed(h, 42);
	for (int i = 0; i < 200; i++)
		a[i] = link_fault(server_responder(h), DF1_FAULT_NOISE);
	df1_server_set_seed(h, 42);
	for (int i = 0; i < 200; i++) {
		b[i] = link_fault(server_responder(h), DF1_FAULT_NOISE);
		hits += b[i];
	}
	assert_memory_equal(a, b, sizeof a);
	assert_true(hits > 30 && hits < 100); /* about 30 % */
	assert_false(link_fault(server_responder(h), DF1_FAULT_DROP_ACK)); /* off */
}

static void test_fault_drop_ack_full(void **state)
{
	struct df1 *h = *state;

	df1_server_set_fault(h, DF1_FAULT_DROP_ACK, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ENQ, 2); /* the master's ACK timer ran out */
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	/* no ACK before the reply; the ENQ gets the ACK a lost ACK would have been */
	assert_int_equal(mock_port_writes(), 2);
	{
		size_t n;
		const uint8_t *w = mock_port_write_at(0, &n);

		assert_int_equal(w[1], DF1_STX);
	}
	assert_write_bytes(1, ACK, 2);
}

static void test_fault_drop_ack_hd_executed_once(void **state)
{
	struct df1 *h = *state;

	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	df1_server_set_fault(h, DF1_FAULT_DROP_ACK, 1000, 0);
	feed_master_msg(1, 0x77);
	feed_master_msg(1, 0x77); /* the master's retransmission */
	feed_poll(1);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(0, ACK, 2); /* the duplicate is ACKed */
	assert_int_equal(cnt(h, 2549), 1);
}

static void test_fault_nak_command(void **state)
{
	struct df1 *h = *state;

	df1_server_set_fault(h, DF1_FAULT_NAK_COMMAND, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed_hex(A2_FD_CRC);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(0, NAK, 2);
	assert_write_bytes(1, NAK, 2);
}

static void test_fault_corrupt_reply_then_good(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want), n;
	const uint8_t *w;

	df1_server_set_fault(h, DF1_FAULT_CORRUPT_REPLY, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(NAK, 2);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	w = write_after_ack(0, &n);
	assert_int_equal(n, wn);
	assert_memory_equal(w, want, wn - 1);
	assert_int_equal(w[wn - 1], want[wn - 1] ^ 0xFF);
	assert_write_bytes(1, want, wn);
}

static void test_fault_stale_reply_first(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE], stale[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want);
	size_t sn = slave_reply_wire(DF1_CHECK_CRC, 1, 0xFFFF, stale); /* TNS - 2 */

	df1_server_set_fault(h, DF1_FAULT_STALE_REPLY, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ACK, 2);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_ack_and(0, stale, sn);
	assert_write_bytes(1, want, wn);
}

static void test_fault_stale_reply_hd(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE], stale[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 0x100, want);
	size_t sn = slave_reply_wire(DF1_CHECK_CRC, 1, 0xFE, stale); /* TNS - 2 */

	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	df1_server_set_fault(h, DF1_FAULT_STALE_REPLY, 1000, 0);
	feed_master_msg(1, 0x100);
	feed_poll(1);
	mock_port_feed(ACK, 2);
	feed_poll(1);
	mock_port_feed(ACK, 2);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write_bytes(1, stale, sn);
	assert_write_bytes(2, want, wn);
	assert_write_bytes(3, EOT, 2);
}

static void test_fault_noise_before_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want), n;
	const uint8_t *w;

	df1_server_set_fault(h, DF1_FAULT_NOISE, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	w = write_after_ack(0, &n);
	assert_int_equal(n, 3 + wn);
	for (int i = 0; i < 3; i++)
		assert_int_not_equal(w[i], DF1_DLE);
	assert_memory_equal(w + 3, want, wn);
}

static void test_fault_silent_station(void **state)
{
	struct df1 *h = *state;

	df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, 1);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ENQ, 2);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 0);
	/* half duplex: no ACK, no answer to polls */
	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	feed_master_msg(1, 1);
	feed_poll(1);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(handler_calls, 0);
}

/* value 256: every station silent, bare ENQs unanswered too; -1 (or
 * probability 0) answers again. */
static void test_fault_silent_all_stations(void **state)
{
	struct df1 *h = *state;

	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, 257), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, 256), 0);
	mock_port_feed(ENQ, 2);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ENQ, 2);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 0);
	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	assert_int_equal(df1_server_add_station(h, 1), 0);
	assert_int_equal(df1_server_add_station(h, 7), 0);
	feed_master_msg(1, 1);
	feed_poll(1);
	feed_master_msg(7, 2);
	feed_poll(7);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(handler_calls, 0);
	/* back: station 7 answers */
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 0, -1), 0);
	feed_master_msg(7, 3);
	feed_poll(7);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 2); /* ACK, reply */
	/* full duplex: after a silenced frame the ENQs get an answer again as
	 * soon as the fault is off */
	h->cfg.duplex = DF1_FULL_DUPLEX;
	mock_port_clear_written();
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, 256), 0);
	mock_port_feed_hex(A2_FD_CRC);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 0, -1), 0);
	mock_port_feed(ENQ, 2);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 1);
}

static void test_fault_delay_reply(void **state)
{
	struct df1 *h = *state;
	int64_t t0 = df1_now_ms();
	size_t n;
	int total = 0;

	df1_server_set_fault(h, DF1_FAULT_DELAY_REPLY, 1000, 60);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ENQ, 2); /* answered while the reply waits */
	/* no more reads: the mock waits (really) until the reply is due */
	while (mock_port_writes() < 3 && df1_now_ms() - t0 < 2000) {
		int r = link_serve(h, server_responder(h), test_handler, NULL, df1_now_ms() + 200);

		assert_true(r >= 0);
		total += r;
	}
	assert_int_equal(total, 1);
	assert_true(df1_now_ms() - t0 >= 60);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, ACK, 2);
	assert_int_equal(mock_port_write_at(2, &n)[1], DF1_STX);
}

static void test_fault_delay_reply_hd_eot_first(void **state)
{
	struct df1 *h = *state;

	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	df1_server_set_fault(h, DF1_FAULT_DELAY_REPLY, 1000, 5000);
	feed_master_msg(1, 1);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(1, EOT, 2); /* not ready yet */
}

/* ------------------------------------------------------------------------
 * Master <-> responder pairs: the responder is a second handle on an in-test
 * port, run by the mock whenever the master waits for bytes.
 * ------------------------------------------------------------------------ */

struct pair {
	struct df1 *peer;
	uint8_t in[8192];
	size_t in_len, in_pos;
	int served;
};
static struct pair pair;

static ssize_t pair_read(struct df1 *h, uint8_t *buf, size_t cap, int64_t deadline_ms)
{
	(void)h;
	if (pair.in_pos < pair.in_len) {
		size_t n = pair.in_len - pair.in_pos;

		if (n > cap)
			n = cap;
		memcpy(buf, pair.in + pair.in_pos, n);
		pair.in_pos += n;
		return (ssize_t)n;
	}
	{
		int64_t ms = deadline_ms - df1_now_ms();

		if (ms > 0) {
			struct timespec ts = { .tv_sec = ms / 1000, .tv_nsec = (ms % 1000) * 1000000L };

			nanosleep(&ts, NULL);
		}
	}
	return 0;
}

static ssize_t pair_write(struct df1 *h, const uint8_t *buf, size_t n, int64_t deadline_ms)
{
	(void)h;
	(void)deadline_ms;
	mock_port_feed(buf, n); /* to the master */
	return (ssize_t)n;
}

static const struct port_ops pair_ops = {
	.name = "pair",
	.read = pair_read,
	.write = pair_write,
};

static void pair_master_wrote(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (pair.in_pos == pair.in_len)
		pair.in_pos = pair.in_len = 0;
	assert_true(pair.in_len + n <= sizeof pair.in);
	memcpy(pair.in + pair.in_len, buf, n);
	pair.in_len += n;
}

static void pair_idle(int64_t deadline_ms, void *user)
{
	int64_t end = df1_now_ms() + 3;
	int r;

	(void)user;
	if (end > deadline_ms)
		end = deadline_ms;
	r = link_serve(pair.peer, server_responder(pair.peer), test_handler, NULL, end);
	assert_true(r >= 0);
	pair.served += r;
}

static void pair_start(struct df1 *master, enum df1_duplex master_duplex)
{
	memset(&pair, 0, sizeof pair);
	pair.peer = new_handle(master_duplex == DF1_HALF_DUPLEX_MASTER ? DF1_HALF_DUPLEX_SLAVE
	                                                               : DF1_FULL_DUPLEX,
	                       master->cfg.check);
	pair.peer->port = &pair_ops;
	pair.peer->cfg.station = 1;
	pair.peer->cfg.timeout_ms = 100;
	master->cfg.duplex = master_duplex;
	master->cfg.timeout_ms = 150; /* real time here: room for a loaded machine */
	mock_port_on_write(pair_master_wrote, NULL);
	mock_port_on_idle(pair_idle, NULL);
	handler_calls = 0;
}

static void pair_stop(void)
{
	pair.peer->port = NULL;
	pair.peer->fd = -1;
	df1_free(pair.peer);
	pair.peer = NULL;
	mock_port_on_idle(NULL, NULL);
	mock_port_on_write(NULL, NULL);
}

static void assert_pair_reply(int r, const uint8_t *out, uint16_t tns)
{
	assert_int_equal(r, 10);
	assert_int_equal(out[1], 1);
	assert_int_equal(out[2], 0x4F);
	assert_int_equal(out[4], tns & 0xFF);
	assert_int_equal(out[5], tns >> 8);
	assert_int_equal(out[6], 0x11);
}

static void run_pair_clean(struct df1 *h, enum df1_duplex d)
{
	uint8_t out[300];

	pair_start(h, d);
	for (uint16_t i = 1; i <= 5; i++)
		assert_pair_reply(transact_a2(h, out, sizeof out), out, i);
	assert_int_equal(handler_calls, 5);
	assert_int_equal(cnt(h, 2530), 5);
	assert_int_equal(cnt(h, 2548) + cnt(h, 2549), 0);
	pair_stop();
}

static void test_pair_fd_clean(void **state)
{
	run_pair_clean(*state, DF1_FULL_DUPLEX);
}

static void test_pair_hd_clean(void **state)
{
	run_pair_clean(*state, DF1_HALF_DUPLEX_MASTER);
}

static void test_pair_hd_bcc_clean(void **state)
{
	struct df1 *h = *state;

	h->cfg.check = DF1_CHECK_BCC;
	run_pair_clean(h, DF1_HALF_DUPLEX_MASTER);
}

static void test_pair_drop_ack_executed_once(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_DROP_ACK, 1000, 0);
		h->next_tns = (uint16_t)(0x40 + d);
		assert_pair_reply(transact_a2(h, out, sizeof out), out, (uint16_t)(0x40 + d));
		assert_int_equal(handler_calls, 1);
		pair_stop();
	}
	/* half duplex: the master's retransmission was a duplicate for the slave */
	assert_true(cnt(h, 2541) >= 1);
}

static void test_pair_corrupt_reply_recovered(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		df1_counters_reset(h);
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_CORRUPT_REPLY, 1000, 0);
		{
			uint16_t tns = h->next_tns;

			assert_pair_reply(transact_a2(h, out, sizeof out), out, tns);
		}
		assert_int_equal(cnt(h, 2547), 1);
		if (dx == DF1_FULL_DUPLEX)
			assert_int_equal(cnt(h, 2533), 1); /* NAKed, retransmitted */
		else
			assert_true(cnt(h, 2543) >= 1); /* not ACKed, polled again */
		pair_stop();
	}
}

static void test_pair_stale_reply_dropped(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		df1_counters_reset(h);
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_STALE_REPLY, 1000, 0);
		h->next_tns = (uint16_t)(0x2000 + d);
		assert_pair_reply(transact_a2(h, out, sizeof out), out, (uint16_t)(0x2000 + d));
		/* the copy carries TNS - 2: never the last accepted reply (0x2000 in
		 * the second round), so it is stale both times, not a duplicate */
		assert_int_equal(cnt(h, 2548), 1);
		assert_int_equal(cnt(h, 2549), 0);
		assert_int_equal(cnt(h, 2530), 1);
		pair_stop();
	}
}

static void test_pair_noise_tolerated(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_NOISE, 1000, 0);
		{
			uint16_t tns = h->next_tns;

			assert_pair_reply(transact_a2(h, out, sizeof out), out, tns);
		}
		pair_stop();
	}
}

static void test_pair_nak_command_limit(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.nak_retries = 2;
	pair_start(h, DF1_FULL_DUPLEX);
	df1_server_set_fault(pair.peer, DF1_FAULT_NAK_COMMAND, 1000, 0);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NAK_LIMIT);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(cnt(h, 2534), 3);
	pair_stop();
}

static void test_pair_silent_station(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.enq_retries = 1;
	h->cfg.nak_retries = 1;
	pair_start(h, DF1_FULL_DUPLEX);
	df1_server_set_fault(pair.peer, DF1_FAULT_SILENT_STATION, 1000, 1);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_ENQ_LIMIT);
	pair_stop();
	mock_port_reset();
	pair_start(h, DF1_HALF_DUPLEX_MASTER);
	df1_server_set_fault(pair.peer, DF1_FAULT_SILENT_STATION, 1000, 1);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NAK_LIMIT);
	assert_int_equal(df1_station_active(h, 1), 0);
	/* now inactive: the next transaction costs one poll */
	mock_port_clear_written();
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_INACTIVE);
	assert_int_equal(mock_port_writes(), 1);
	assert_int_equal(handler_calls, 0);
	pair_stop();
}

static void test_pair_delay_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	int64_t t0;

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		df1_counters_reset(h);
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_DELAY_REPLY, 1000, 120);
		t0 = df1_now_ms();
		{
			uint16_t tns = h->next_tns;

			assert_pair_reply(transact_a2(h, out, sizeof out), out, tns);
		}
		assert_true(df1_now_ms() - t0 >= 120);
		if (dx == DF1_HALF_DUPLEX_MASTER)
			assert_true(cnt(h, 2538) >= 1); /* EOTs while the reply was held back */
		pair_stop();
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_fault_api_validates, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_rng_deterministic, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_drop_ack_full, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_drop_ack_hd_executed_once, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_nak_command, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_corrupt_reply_then_good, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_stale_reply_first, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_stale_reply_hd, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_noise_before_reply, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_silent_station, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_silent_all_stations, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_delay_reply, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_delay_reply_hd_eot_first, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_pair_fd_clean, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_hd_clean, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_hd_bcc_clean, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_drop_ack_executed_once, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_corrupt_reply_recovered, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_stale_reply_dropped, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_noise_tolerated, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_nak_command_limit, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_silent_station, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_delay_reply, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
