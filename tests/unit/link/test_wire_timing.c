/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_wire_timing - timers that match a real UART, and half-duplex polling of
 * slaves that take their time (issue: wire speed), against df1sim as a
 * process on a pseudo-terminal through the real termios backend:
 *  - df1sim --line-baud 1200 reads no faster than a 1200-baud line delivers:
 *    the master's write() returns at once, the frame takes 1.8 s to cross.
 *    With the line's baud set (df1_set_serial), the ACK timer starts when
 *    the last byte has left, so a 100-word write succeeds at the default
 *    timeouts with no ENQ retry (2543) and no command timeout (2545); the
 *    same handle told 19200 baud starts its timer too early and must ENQ
 *    (the test's own check that the line really is slow).
 *  - a half-duplex slave that answers polls with nothing at all (--no-eot)
 *    and replies 150 ms after a command: reads and writes succeed at the
 *    default timeouts (a poll without an answer is polled again within the
 *    poll-answer time, not after a whole ACK timeout).
 *  - on a pseudo-terminal, which carries bytes at once, the account of when
 *    they leave does not run ahead of the clock (a timeout stays a timeout);
 *  - adaptive polling: against a slave with a 150 ms reply delay the master
 *    learns the latency and needs a handful of polls per transaction, not
 *    one every few ms (counted, not timed).
 * And the pure poll timing of lib/link/half_repoll.c.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "df1.h"
#include "link/half_repoll.h"
#include "support/simproc.h"

static uint64_t cnt(df1_t *h, int id)
{
	uint64_t v = 0;

	assert_int_equal(df1_counter(h, id, &v), 0);
	return v;
}

#define OK(h, expr) ok_rc((h), (expr), #expr, __LINE__)

static int ok_rc(df1_t *h, int rc, const char *what, int line)
{
	if (rc < 0)
		fail_msg("line %d: %s -> %s: %s", line, what, df1_errname(rc), df1_last_error(h)->message);
	return rc;
}

static df1_t *open_master(const char *dev, int baud, enum df1_duplex duplex)
{
	df1_t *h = NULL;

	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_serial(h, baud, 8, 'N', 1), 0);
	assert_int_equal(df1_set_duplex(h, duplex), 0);
	OK(h, df1_open(h, dev));
	return h;
}

/* ---- pure: lib/link/half_repoll.c ---- */

static void test_repoll_learns_and_times_polls(void **state)
{
	struct repoll_est e = { 0, 0 };

	(void)state;
	/* nothing learned: poll at once, then at the minimum gap */
	assert_int_equal(repoll_first_us(&e), 0);
	assert_int_equal(repoll_next_us(&e, 0, 1000, 20000), 1000);
	/* the first sample is taken as it is; the first poll 7/8 of it */
	repoll_learn(&e, 160000);
	assert_int_equal(e.latency_us, 160000);
	assert_int_equal(repoll_first_us(&e), 140000);
	/* after an early EOT: wait for the rest of the latency */
	assert_int_equal(repoll_next_us(&e, 140000, 1000, 20000), 20000);
	assert_int_equal(repoll_next_us(&e, 159500, 1000, 20000), 1000); /* never below the gap */
	/* overdue: an eighth of how late it is, at most the maximum gap */
	assert_int_equal(repoll_next_us(&e, 240000, 1000, 20000), 10000);
	assert_int_equal(repoll_next_us(&e, 960000, 1000, 20000), 20000);
	/* a quarter of each new sample */
	repoll_learn(&e, 80000);
	assert_int_equal(e.latency_us, 140000);
	repoll_learn(&e, -5);                    /* a clock step back counts as 0 */
	assert_int_equal(e.latency_us, 105000);
	assert_int_equal(e.samples, 3);
}

/* ---- 1200 baud: the ACK timer starts when the last byte has left ---- */

static void write_100_words_at_1200(enum df1_duplex duplex, const char *const *args)
{
	struct simproc sp;
	int16_t v[100], back[100];
	df1_t *h;

	for (int i = 0; i < 100; i++)
		v[i] = (int16_t)(1000 + i);
	assert_int_equal(simproc_start(&sp, false, NULL, true, args), 0);
	h = open_master(sp.target, 1200, duplex);
	OK(h, df1_write_int16(h, 1, "N7:0", v, 100));
	assert_int_equal(cnt(h, 2543), 0);      /* CNT_ENQ_RETRIES */
	assert_int_equal(cnt(h, 2545), 0);      /* CNT_COMMAND_TIMEOUTS */
	assert_int_equal(cnt(h, 2541), 0);      /* CNT_NAK_RETRIES: no retransmission either */
	OK(h, df1_read_int16(h, 1, "N7:0", back, 100));
	assert_memory_equal(back, v, sizeof v);
	df1_free(h);
	/* executed once (df1sim's frame log: one line per command answered) */
	assert_int_equal(simproc_log_wait(&sp, "cmd=0F/AA", NULL, 1, 5000), 1);
	assert_int_equal(simproc_stop(&sp, false), 0);
}

static void test_1200_baud_full_duplex_write_100_words(void **state)
{
	static const char *const args[] = { "--line-baud", "1200", NULL };

	(void)state;
	write_100_words_at_1200(DF1_FULL_DUPLEX, args);
}

static void test_1200_baud_half_duplex_write_100_words(void **state)
{
	static const char *const args[] = { "--duplex", "half", "--line-baud", "1200", NULL };

	(void)state;
	write_100_words_at_1200(DF1_HALF_DUPLEX_MASTER, args);
}

/* The same line with the master told 19200 baud: its ACK timer starts 1.7 s
 * too early, so it asks with ENQ: the slowness the test above relies on is
 * real (and the write still ends exactly once). */
static void test_1200_baud_line_master_at_19200_enqs(void **state)
{
	static const char *const args[] = { "--line-baud", "1200", NULL };
	struct simproc sp;
	int16_t v[100] = { 0 };
	df1_t *h;

	(void)state;
	assert_int_equal(simproc_start(&sp, false, NULL, true, args), 0);
	h = open_master(sp.target, 19200, DF1_FULL_DUPLEX);
	OK(h, df1_write_int16(h, 1, "N7:0", v, 100));
	assert_true(cnt(h, 2543) >= 1);
	df1_free(h);
	assert_int_equal(simproc_log_wait(&sp, "cmd=0F/AA", NULL, 1, 5000), 1);
	assert_int_equal(simproc_stop(&sp, false), 0);
}

/* A pseudo-terminal carries bytes at once, far faster than the 19200 baud the
 * handle is set to: the account of when our bytes leave must not run ahead of
 * the clock over many transactions (it ends when the peer answers), or every
 * timeout after them would grow by seconds. 1000 reads would put it 10 s
 * ahead; a station that never answers must still fail after its 100 ms
 * timeout, not after 10 s (a bound 25 times the timeout, for slow machines). */
static void test_tx_account_does_not_run_ahead_on_a_pty(void **state)
{
	static const char *const args[] = { "--station", "1,2", "--silent", "2", NULL };
	struct simproc sp;
	struct timespec t0, t1;
	int16_t v;
	df1_t *h;
	double s;

	(void)state;
	assert_int_equal(simproc_start(&sp, false, NULL, false, args), 0);
	h = open_master(sp.target, 19200, DF1_FULL_DUPLEX);
	assert_int_equal(df1_set_timeout_ms(h, 100), 0);
	assert_int_equal(df1_set_retries(h, 0, 0), 0);
	for (int k = 0; k < 1000; k++)
		OK(h, df1_read_int16(h, 1, "N7:0", &v, 1));
	clock_gettime(CLOCK_MONOTONIC, &t0);
	assert_int_equal(df1_read_int16(h, 2, "N7:0", &v, 1), DF1_E_ENQ_LIMIT);
	clock_gettime(CLOCK_MONOTONIC, &t1);
	s = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) / 1e9;
	if (s > 2.5)
		fail_msg("a 100 ms timeout took %.1f s after 1000 transactions", s);
	df1_free(h);
	assert_int_equal(simproc_stop(&sp, false), 0);
}

/* ---- half duplex: a slave without EOT, a slave that takes 150 ms ---- */

static void test_half_duplex_slave_without_eot(void **state)
{
	static const char *const args[] = { "--duplex", "half", "--no-eot", "--delay", "150:100", NULL };
	struct simproc sp;
	int16_t v[3] = { 7, -8, 9 }, back[3];
	df1_t *h;

	(void)state;
	assert_int_equal(simproc_start(&sp, false, NULL, true, args), 0);
	h = open_master(sp.target, 19200, DF1_HALF_DUPLEX_MASTER);
	for (int k = 0; k < 3; k++) {
		v[0] = (int16_t)(7 + k);
		OK(h, df1_write_int16(h, 1, "N7:10", v, 3));
		OK(h, df1_read_int16(h, 1, "N7:10", back, 3));
		assert_memory_equal(back, v, sizeof v);
	}
	assert_int_equal(cnt(h, 2545), 0);      /* no command timeout */
	assert_int_equal(cnt(h, 2538), 0);      /* CNT_EOTS_RCVD: it really sends none */
	df1_free(h);
	assert_int_equal(simproc_log_wait(&sp, "cmd=0F/AA", NULL, 3, 5000), 3);
	assert_int_equal(simproc_stop(&sp, false), 0);
}

static void test_half_duplex_polls_learn_the_reply_latency(void **state)
{
	static const char *const args[] = { "--duplex", "half", "--delay", "150:100", NULL };
	struct simproc sp;
	uint64_t polls;
	int16_t v;
	df1_t *h;

	(void)state;
	assert_int_equal(simproc_start(&sp, false, NULL, false, args), 0);
	h = open_master(sp.target, 19200, DF1_HALF_DUPLEX_MASTER);
	OK(h, df1_read_int16(h, 1, "N7:1", &v, 1));         /* learns */
	df1_counters_reset(h);
	for (int k = 0; k < 8; k++)
		OK(h, df1_read_int16(h, 1, "N7:1", &v, 1));
	polls = cnt(h, 2531);                               /* CNT_POLL_MSGS_SENT */
	/* a poll every 10 ms for 150 ms would be 15 a transaction; learned, the
	 * first goes out shortly before the reply is due (generous bound: the
	 * machine may be slow, the count stays small) */
	if (polls > 8 * 5)
		fail_msg("%llu polls for 8 transactions", (unsigned long long)polls);
	assert_int_equal(cnt(h, 2527), 8);
	df1_free(h);
	assert_int_equal(simproc_stop(&sp, false), 0);
}

/* The poll engine: the ACK of a block's reply goes out with the next block's
 * command in one write (DLE ACK DLE SOH ... in half duplex, DLE ACK DLE STX ...
 * in full duplex), and every reply is still ACKed (ACKs sent = replies
 * received + duplicates). */
struct tx_seen {
	int writes, merged;
};

static void on_trace(void *user, enum df1_dir dir, const uint8_t *b, size_t n, uint64_t t_us)
{
	struct tx_seen *t = user;

	(void)t_us;
	if (dir != DF1_DIR_TX)
		return;
	t->writes++;
	if (n > 4 && b[0] == 0x10 && b[1] == 0x06 && b[2] == 0x10 && (b[3] == 0x01 || b[3] == 0x02))
		t->merged++;
}

static void scan_ack_with_next_command(bool half)
{
	static const char *const half_args[] = { "--duplex", "half", NULL };
	static const char *const addrs[] = { "N7:0", "F8:0", "B3:0", "T4:0.ACC" };
	struct tx_seen seen = { 0, 0 };
	struct df1_poll_stats ps;
	struct simproc sp;
	df1_t *h;

	assert_int_equal(simproc_start(&sp, false, NULL, false, half ? half_args : NULL), 0);
	h = open_master(sp.target, 19200, half ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX);
	for (size_t i = 0; i < 4; i++) {
		struct df1_tag_config c;

		memset(&c, 0, sizeof c);
		snprintf(c.name, sizeof c.name, "t%zu", i);
		c.access = DF1_ACCESS_READ;
		c.station = 1;
		c.plc = DF1_PLC_SLC;
		c.count = 1;
		c.scan_ms = 0;
		assert_int_equal(df1_addr_parse(addrs[i], &c.addr), 0);
		assert_true(df1_tag_add(h, &c) >= 0);
	}
	df1_set_trace(h, on_trace, &seen);
	do
		OK(h, df1_poll(h, 1000));
	while (df1_poll_stats(h, &ps) == 0 && ps.scans < 3);
	/* 4 blocks a scan: at least the 3 between them go with an ACK */
	if (seen.merged < 3)
		fail_msg("%d of %d writes carried an ACK and the next message", seen.merged, seen.writes);
	assert_int_equal(cnt(h, 2535), cnt(h, 2530) + cnt(h, 2549)); /* ACKS_SENT */
	assert_int_equal(cnt(h, 2543), 0);
	df1_free(h);
	assert_int_equal(simproc_stop(&sp, false), 0);
}

static void test_half_duplex_scan_ack_with_next_message(void **state)
{
	(void)state;
	scan_ack_with_next_command(true);
}

static void test_full_duplex_scan_ack_with_next_command(void **state)
{
	(void)state;
	scan_ack_with_next_command(false);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_repoll_learns_and_times_polls),
		cmocka_unit_test(test_1200_baud_full_duplex_write_100_words),
		cmocka_unit_test(test_1200_baud_half_duplex_write_100_words),
		cmocka_unit_test(test_1200_baud_line_master_at_19200_enqs),
		cmocka_unit_test(test_tx_account_does_not_run_ahead_on_a_pty),
		cmocka_unit_test(test_half_duplex_slave_without_eot),
		cmocka_unit_test(test_half_duplex_polls_learn_the_reply_latency),
		cmocka_unit_test(test_half_duplex_scan_ack_with_next_message),
		cmocka_unit_test(test_full_duplex_scan_ack_with_next_command),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
