/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_handle.c - the df1_t handle: defaults, every setter's valid and invalid
 * values (DF1_E_CONFIG with the seed's critical IDs 2552-2559 where it has
 * one), options, counters, the active station list, the last-error helpers.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "df1_int.h"

static int setup(void **state)
{
	df1_t *h = NULL;

	if (df1_new(&h) != 0)
		return -1;
	*state = h;
	return 0;
}

static int teardown(void **state)
{
	df1_free(*state);
	return 0;
}

/* The last error is DF1_E_CONFIG with this catalog ID and exactly this text. */
static void expect_config(df1_t *h, int r, int id, const char *text)
{
	const struct df1_error_detail *e = df1_last_error(h);

	assert_int_equal(r, DF1_E_CONFIG);
	assert_int_equal(e->code, DF1_E_CONFIG);
	assert_int_equal(e->catalog_id, id);
	if (text)
		assert_string_equal(e->message, text);
}

/* DF1_E_CONFIG, no catalog message, and the text names the field and its range. */
static void expect_config_range(df1_t *h, int r, const char *field, const char *range)
{
	const struct df1_error_detail *e = df1_last_error(h);

	expect_config(h, r, 0, NULL);
	assert_non_null(strstr(e->message, field));
	assert_non_null(strstr(e->message, range));
}

static void test_handle_defaults(void **state)
{
	df1_t *h = *state;
	const struct df1_error_detail *e = df1_last_error(h);
	uint64_t v = 99;
	int i;

	assert_int_equal(h->cfg.baud, 19200);
	assert_int_equal(h->cfg.data_bits, 8);
	assert_int_equal(h->cfg.parity, 'N');
	assert_int_equal(h->cfg.stop_bits, 1);
	assert_false(h->cfg.rts_cts);
	assert_int_equal(h->cfg.duplex, DF1_FULL_DUPLEX);
	assert_int_equal(h->cfg.check, DF1_CHECK_CRC);
	assert_int_equal(h->cfg.station, 0);
	assert_int_equal(h->cfg.timeout_ms, 1000);
	assert_int_equal(h->cfg.cmd_timeout_ms, 1000);
	assert_int_equal(h->cfg.nak_retries, 3);
	assert_int_equal(h->cfg.enq_retries, 3);
	assert_int_equal(h->cfg.tx_delay_ms, 0);
	assert_int_equal(h->cfg.line_baud, 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_DUPLICATE_DETECT), 1);
	assert_int_equal(df1_get_option(h, DF1_OPT_EMBEDDED_RESPONSES), 1);
	assert_int_equal(df1_get_option(h, DF1_OPT_HD_BCC_INCLUDES_STX), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_ACCEPT_NAK_0F), 1);
	assert_int_equal(df1_get_option(h, DF1_OPT_RS485), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_ECHO_DISCARD), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_MAX_PACKET), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_EOT_WITH_BCC), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_LOCAL_TCP), 1);
	assert_int_equal(df1_get_option(h, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_SLC_IO_CODES_82), 0);
	for (i = 0; i <= 254; i++)
		assert_int_equal(df1_station_active(h, i), 1);
	for (i = 2525; i <= 2551; i++) {
		assert_int_equal(df1_counter(h, i, &v), 0);
		assert_int_equal(v, 0);
	}
	assert_false(df1_is_open(h));
	assert_int_equal(h->fd, -1);
	assert_int_equal(h->cancel_fd, -1);
	assert_int_equal(e->code, 0);
	assert_int_equal(e->station, -1);
	assert_string_equal(e->message, "");
	assert_int_equal(h->dec.check, DF1_CHECK_CRC);
	assert_true(h->dec.opts & FRAME_OPT_ACCEPT_NAK_0F);
	assert_true(h->dec.max_len > 0);
}

static void test_handle_new_free_null(void **state)
{
	(void)state;
	assert_int_equal(df1_new(NULL), DF1_E_INVAL);
	df1_free(NULL);
	df1_close(NULL);
	assert_false(df1_is_open(NULL));
	assert_non_null(df1_last_error(NULL));
	assert_int_equal(df1_last_error(NULL)->code, DF1_E_INVAL);
	assert_int_equal(df1_set_station(NULL, 1), DF1_E_INVAL);
	assert_int_equal(df1_get_option(NULL, DF1_OPT_RS485), DF1_E_INVAL);
	assert_int_equal(df1_counter(NULL, 2525, NULL), DF1_E_INVAL);
	df1_set_log(NULL, NULL, NULL);
	df1_counters_reset(NULL);
}

/* The first TNS of runs started at exact multiples of 65.536 ms (the period of
 * a microsecond clock taken modulo 65536), each a new process as a tool run
 * is: the first TNS values must spread as chance spreads 16-bit values, not
 * cluster where the previous run started. A DF1 node's duplicate detection
 * drops a command with the TNS of the last one it took (doc/PROTOCOL.md 1.7), so a run
 * that starts with the previous run's TNS loses its first command. */
#define TNS_RUNS 30
#define TNS_NEAR 1024           /* "near": within 1024 either side */

static unsigned tns_dist(unsigned a, unsigned b)
{
	unsigned d = (a - b) & 0xFFFFu;

	return d < 0x8000u ? d : 0x10000u - d;
}

static void test_handle_tns_runs_spread(void **state)
{
	unsigned tns[TNS_RUNS], near = 0, same = 0, distinct = 0;
	struct timespec t0;

	(void)state;
	clock_gettime(CLOCK_MONOTONIC, &t0);
	for (int i = 0; i < TNS_RUNS; i++) {
		struct timespec at = t0;
		uint16_t v = 0;
		int fd[2], st;
		long long ns = (long long)t0.tv_nsec + (long long)(i + 1) * 65536000LL;
		pid_t pid;

		at.tv_sec += (time_t)(ns / 1000000000LL);
		at.tv_nsec = (long)(ns % 1000000000LL);
		assert_int_equal(pipe(fd), 0);
		while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, NULL) == EINTR)
			;
		pid = fork();
		assert_true(pid >= 0);
		if (pid == 0) {         /* a new run: a fresh process, its first handle */
			df1_t *h = NULL;

			close(fd[0]);
			if (df1_new(&h) == 0)
				v = h->next_tns;
			_exit(write(fd[1], &v, sizeof v) == (ssize_t)sizeof v ? 0 : 1);
		}
		close(fd[1]);
		assert_int_equal(read(fd[0], &v, sizeof v), (int)sizeof v);
		close(fd[0]);
		assert_int_equal(waitpid(pid, &st, 0), pid);
		assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
		tns[i] = v;
	}
	for (int i = 0; i < TNS_RUNS; i++) {
		bool seen = false;

		for (int j = 0; j < i; j++)
			seen = seen || tns[j] == tns[i];
		distinct += !seen;
		if (i > 0) {
			near += tns_dist(tns[i], tns[i - 1]) <= TNS_NEAR;
			same += tns[i] == tns[i - 1];
		}
	}
	print_message("first TNS of %d runs 65.536 ms apart: %u distinct, %u within %d of the "
	              "previous run's, %u equal to it\n", TNS_RUNS, distinct, near, TNS_NEAR, same);
	/* random: P(near) = 2049 / 65536 per pair, about 0.9 of 29 pairs;
	 * 7 or more has a probability below 1e-4. 30 random values are all
	 * distinct with probability 0.993; two or more repeats below 3e-5. */
	assert_true(near <= 6);
	assert_true(distinct >= TNS_RUNS - 1);
	assert_true(same == 0 || same == 1);
}

static void test_handle_tns_differs_between_handles(void **state)
{
	df1_t *a = NULL, *b = NULL, *c = NULL;

	(void)state;
	assert_int_equal(df1_new(&a), 0);
	assert_int_equal(df1_new(&b), 0);
	assert_int_equal(df1_new(&c), 0);
	assert_int_not_equal(a->next_tns, b->next_tns);
	assert_int_not_equal(b->next_tns, c->next_tns);
	df1_free(a);
	df1_free(b);
	df1_free(c);
}

static void test_handle_station(void **state)
{
	df1_t *h = *state;

	assert_int_equal(df1_set_station(h, 0), 0);
	assert_int_equal(df1_set_station(h, 254), 0);
	assert_int_equal(h->cfg.station, 254);
	expect_config(h, df1_set_station(h, 255), 2552,
	              "Invalid station number (255) must be less than 255");
	expect_config(h, df1_set_station(h, -1), 2552,
	              "Invalid station number (-1) must be less than 255");
	assert_int_equal(h->cfg.station, 254);
	assert_int_equal(df1_last_error(h)->station, -1);
}

static void test_handle_duplex(void **state)
{
	df1_t *h = *state;

	assert_int_equal(df1_set_duplex(h, DF1_HALF_DUPLEX_MASTER), 0);
	assert_int_equal(h->cfg.duplex, DF1_HALF_DUPLEX_MASTER);
	assert_int_equal(df1_set_duplex(h, DF1_HALF_DUPLEX_SLAVE), 0);
	/* 3 is the radio modem since 0.5: 4 is the first value that is none */
	assert_int_equal(DF1_RADIO_MODEM, 3);
	assert_int_equal(df1_set_duplex(h, DF1_RADIO_MODEM), 0);
	assert_int_equal(h->cfg.duplex, DF1_RADIO_MODEM);
	assert_int_equal(df1_set_duplex(h, DF1_FULL_DUPLEX), 0);
	expect_config(h, df1_set_duplex(h, (enum df1_duplex)4), 2553,
	              "Invalid Driver Mode (4), should be one of Master, Slave, or Peer");
	expect_config(h, df1_set_duplex(h, (enum df1_duplex)-1), 2553, NULL);
	assert_int_equal(h->cfg.duplex, DF1_FULL_DUPLEX);
}

static void test_handle_plc(void **state)
{
	df1_t *h = *state;
	int p;

	for (p = DF1_PLC_SLC; p <= DF1_PLC_PLC3; p++) {
		assert_int_equal(df1_set_plc(h, (enum df1_plc)p), 0);
		assert_int_equal(h->cfg.plc, p);
	}
	/* 5 is DF1_PLC_PLC3 since 0.5: 6 is the first value that is none */
	expect_config(h, df1_set_plc(h, (enum df1_plc)6), 2555,
	              "Invalid or Unsupported PLC Type (6) should be one of SLC, MicroLogix, PLC5, PLC2");
	assert_int_equal(h->cfg.plc, DF1_PLC_PLC3);
}

static void test_handle_check(void **state)
{
	df1_t *h = *state;

	assert_int_equal(df1_set_check(h, DF1_CHECK_BCC), 0);
	assert_int_equal(h->cfg.check, DF1_CHECK_BCC);
	assert_int_equal(df1_set_check(h, DF1_CHECK_CRC), 0);
	expect_config(h, df1_set_check(h, DF1_CHECK_AUTO), 2556,
	              "Invalid Error Code (2), should be either BCC, or CRC");
	expect_config(h, df1_set_check(h, (enum df1_check)9), 2556, NULL);
	assert_int_equal(h->cfg.check, DF1_CHECK_CRC);
}

static void test_handle_retries(void **state)
{
	df1_t *h = *state;

	assert_int_equal(df1_set_retries(h, 0, 10), 0);
	assert_int_equal(h->cfg.nak_retries, 0);
	assert_int_equal(h->cfg.enq_retries, 10);
	assert_int_equal(df1_set_retries(h, 10, 0), 0);
	expect_config(h, df1_set_retries(h, 11, 3), 2557,
	              "Invalid NAK Retries (11) should be in range [0, 10]");
	expect_config(h, df1_set_retries(h, -1, 3), 2557, NULL);
	expect_config(h, df1_set_retries(h, 3, 11), 2558,
	              "Invalid ENQ Retries (11) should be in range [0, 10]");
	expect_config(h, df1_set_retries(h, 3, -2), 2558, NULL);
	/* nothing stored from a rejected call, not even the valid half */
	assert_int_equal(h->cfg.nak_retries, 10);
	assert_int_equal(h->cfg.enq_retries, 0);
}

static void test_handle_cmd_timeout(void **state)
{
	df1_t *h = *state;

	assert_int_equal(df1_set_cmd_timeout_ms(h, 500), 0);
	assert_int_equal(df1_set_cmd_timeout_ms(h, 5000), 0);
	assert_int_equal(h->cfg.cmd_timeout_ms, 5000);
	expect_config(h, df1_set_cmd_timeout_ms(h, 499), 2559,
	              "Invalid Cmd Timeout (499) should be in range [500, 5000]");
	expect_config(h, df1_set_cmd_timeout_ms(h, 5001), 2559,
	              "Invalid Cmd Timeout (5001) should be in range [500, 5000]");
	assert_int_equal(h->cfg.cmd_timeout_ms, 5000);
}

static void test_handle_serial(void **state)
{
	static const int bauds[] = { 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200 };
	static const int bad_bauds[] = { 0, -9600, 300, 600, 14400, 28800, 76800, 230400, 1000000 };
	df1_t *h = *state;
	size_t i;

	for (i = 0; i < sizeof bauds / sizeof bauds[0]; i++) {
		assert_int_equal(df1_set_serial(h, bauds[i], 8, 'N', 1), 0);
		assert_int_equal(h->cfg.baud, bauds[i]);
	}
	for (i = 0; i < sizeof bad_bauds / sizeof bad_bauds[0]; i++)
		expect_config_range(h, df1_set_serial(h, bad_bauds[i], 8, 'N', 1), "baud",
		                    "1200, 2400, 4800, 9600, 19200, 38400, 57600 or 115200");
	assert_int_equal(df1_set_serial(h, 9600, 5, 'E', 2), 0);
	assert_int_equal(df1_set_serial(h, 9600, 7, 'o', 1), 0);
	assert_int_equal(h->cfg.parity, 'O');
	assert_int_equal(df1_set_serial(h, 9600, 6, 'n', 1), 0);
	assert_int_equal(h->cfg.parity, 'N');
	expect_config_range(h, df1_set_serial(h, 9600, 4, 'N', 1), "data bits", "5..8");
	expect_config_range(h, df1_set_serial(h, 9600, 9, 'N', 1), "data bits", "5..8");
	expect_config_range(h, df1_set_serial(h, 9600, 8, 'X', 1), "parity", "N (none), E (even) or O (odd)");
	expect_config_range(h, df1_set_serial(h, 9600, 8, 'M', 1), "parity", "'M'");
	expect_config_range(h, df1_set_serial(h, 9600, 8, '\0', 1), "parity", "0x00");
	expect_config_range(h, df1_set_serial(h, 9600, 8, 'N', 0), "stop bits", "1 or 2");
	expect_config_range(h, df1_set_serial(h, 9600, 8, 'N', 3), "stop bits", "1 or 2");
	/* rejected calls change nothing */
	assert_int_equal(h->cfg.baud, 9600);
	assert_int_equal(h->cfg.data_bits, 6);
	assert_int_equal(h->cfg.parity, 'N');
	assert_int_equal(h->cfg.stop_bits, 1);
	/* handshake: stored (no port open) */
	assert_int_equal(df1_set_handshake(h, true), 0);
	assert_true(h->cfg.rts_cts);
	assert_int_equal(df1_set_handshake(h, false), 0);
	assert_false(h->cfg.rts_cts);
}

static void test_handle_timeouts_and_delays(void **state)
{
	df1_t *h = *state;

	assert_int_equal(df1_set_timeout_ms(h, 0), 0);
	assert_int_equal(df1_set_timeout_ms(h, 360000), 0);
	assert_int_equal(h->cfg.timeout_ms, 360000);
	expect_config_range(h, df1_set_timeout_ms(h, -1), "timeout", "0..360000");
	expect_config_range(h, df1_set_timeout_ms(h, 360001), "timeout", "0..360000");
	assert_int_equal(h->cfg.timeout_ms, 360000);

	assert_int_equal(df1_set_tx_delay_ms(h, 0), 0);
	assert_int_equal(df1_set_tx_delay_ms(h, 65535), 0);
	assert_int_equal(h->cfg.tx_delay_ms, 65535);
	expect_config_range(h, df1_set_tx_delay_ms(h, -1), "TX delay", "0..65535");
	expect_config_range(h, df1_set_tx_delay_ms(h, 65536), "TX delay", "0..65535");
	assert_int_equal(h->cfg.tx_delay_ms, 65535);

	assert_int_equal(df1_set_line_baud(h, 9600), 0);
	assert_int_equal(h->cfg.line_baud, 9600);
	assert_int_equal(df1_set_line_baud(h, 0), 0);
	assert_int_equal(h->cfg.line_baud, 0);
	expect_config_range(h, df1_set_line_baud(h, -1), "line baud", "0 (off)");
}

static void test_handle_options(void **state)
{
	static const enum df1_option bools[] = {
		DF1_OPT_DUPLICATE_DETECT, DF1_OPT_EMBEDDED_RESPONSES, DF1_OPT_HD_BCC_INCLUDES_STX,
		DF1_OPT_ACCEPT_NAK_0F, DF1_OPT_RS485, DF1_OPT_ECHO_DISCARD, DF1_OPT_EOT_WITH_BCC,
		DF1_OPT_LOCAL_TCP, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED, DF1_OPT_SLC_IO_CODES_82,
		DF1_OPT_LISTEN_ONLY, DF1_OPT_PLC2_WORD_ADDR, DF1_OPT_EIP_CONNECTED,
		DF1_OPT_LOW_LATENCY, DF1_OPT_PLC5_REFUSE_LARGE,
	};
	df1_t *h = *state;
	size_t i;

	for (i = 0; i < sizeof bools / sizeof bools[0]; i++) {
		int before = df1_get_option(h, bools[i]);

		assert_int_equal(df1_set_option(h, bools[i], 1), 0);
		assert_int_equal(df1_get_option(h, bools[i]), 1);
		assert_int_equal(df1_set_option(h, bools[i], 0), 0);
		assert_int_equal(df1_get_option(h, bools[i]), 0);
		expect_config_range(h, df1_set_option(h, bools[i], 2), "option", "0 or 1");
		expect_config_range(h, df1_set_option(h, bools[i], -1), "option", "0 or 1");
		assert_int_equal(df1_get_option(h, bools[i]), 0);
		assert_int_equal(df1_set_option(h, bools[i], before), 0);
	}
	assert_int_equal(df1_set_option(h, DF1_OPT_MAX_PACKET, 82), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_MAX_PACKET), 82);
	expect_config_range(h, df1_set_option(h, DF1_OPT_MAX_PACKET, -1), "MAX_PACKET", "1..250");
	expect_config_range(h, df1_set_option(h, DF1_OPT_MAX_PACKET, 251), "MAX_PACKET", "1..250");
	assert_int_equal(df1_get_option(h, DF1_OPT_MAX_PACKET), 82);
	/* PLC-5 typed-read timers: 3 words (the data table's) by default, or 5 */
	assert_int_equal(df1_get_option(h, DF1_OPT_PLC5_TIMER_WORDS), 3);
	assert_int_equal(df1_set_option(h, DF1_OPT_PLC5_TIMER_WORDS, 5), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_PLC5_TIMER_WORDS), 5);
	expect_config_range(h, df1_set_option(h, DF1_OPT_PLC5_TIMER_WORDS, 4), "PLC5_TIMER_WORDS", "3 or 5");
	expect_config_range(h, df1_set_option(h, DF1_OPT_PLC5_TIMER_WORDS, 1), "PLC5_TIMER_WORDS", "3 or 5");
	assert_int_equal(df1_get_option(h, DF1_OPT_PLC5_TIMER_WORDS), 5);
	assert_int_equal(df1_set_option(h, DF1_OPT_PLC5_TIMER_WORDS, 3), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_PLC2_WORD_ADDR), 0);  /* bytes by default */
	assert_int_equal(df1_set_option(h, (enum df1_option)0, 1), DF1_E_INVAL);
	assert_int_equal(df1_set_option(h, (enum df1_option)99, 1), DF1_E_INVAL);
	/* the enum only grows at its end: existing values keep their numbers */
	assert_int_equal(DF1_OPT_LOCAL_TCP, 9);
	assert_int_equal(DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED, 10);
	assert_int_equal(DF1_OPT_SLC_IO_CODES_82, 11);
	assert_int_equal(DF1_OPT_LISTEN_ONLY, 12);
	assert_int_equal(DF1_OPT_PLC5_TIMER_WORDS, 13);
	assert_int_equal(DF1_OPT_PLC2_WORD_ADDR, 14);
	assert_int_equal(DF1_OPT_POLL_TIMEOUT_MS, 15);
	assert_int_equal(DF1_OPT_SCAN_TIME_MS, 16);
	assert_int_equal(DF1_OPT_NO_EOT, 17);
	assert_int_equal(DF1_OPT_MAX_OUTSTANDING, 18);
	/* 0.4: the poll-answer time and a responder's scan, in ms; no EOT, a flag */
	assert_int_equal(df1_get_option(h, DF1_OPT_POLL_TIMEOUT_MS), 0);     /* automatic */
	assert_int_equal(df1_set_option(h, DF1_OPT_POLL_TIMEOUT_MS, 60000), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_POLL_TIMEOUT_MS), 60000);
	expect_config_range(h, df1_set_option(h, DF1_OPT_POLL_TIMEOUT_MS, 60001), "POLL_TIMEOUT_MS",
	                    "0..60000 ms");
	expect_config_range(h, df1_set_option(h, DF1_OPT_SCAN_TIME_MS, -1), "SCAN_TIME_MS", "0..10000 ms");
	assert_int_equal(df1_set_option(h, DF1_OPT_SCAN_TIME_MS, 5), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_SCAN_TIME_MS), 5);
	assert_int_equal(df1_get_option(h, DF1_OPT_NO_EOT), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_NO_EOT, 1), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_NO_EOT), 1);
	expect_config_range(h, df1_set_option(h, DF1_OPT_NO_EOT, 2), "NO_EOT", "0 or 1");
	/* 0.4: commands outstanding in full duplex, 1 by default */
	assert_int_equal(df1_get_option(h, DF1_OPT_MAX_OUTSTANDING), 1);
	expect_config_range(h, df1_set_option(h, DF1_OPT_MAX_OUTSTANDING, 0), "MAX_OUTSTANDING", "1..16");
	assert_int_equal(df1_set_option(h, DF1_OPT_MAX_OUTSTANDING, 4), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_MAX_OUTSTANDING), 4);
	assert_int_equal(DF1_OPT_EIP_CONNECTED, 19);
	/* 0.6: USB adapters in low latency mode, on by default */
	assert_int_equal(DF1_OPT_LOW_LATENCY, 20);
	assert_int_equal(DF1_OPT_PLC5_REFUSE_LARGE, 21);
	/* 0.5: a half-duplex master routes its slaves' messages, on by default */
	assert_int_equal(DF1_OPT_ROUTE, 22);
	assert_int_equal(df1_get_option(h, DF1_OPT_ROUTE), 1);
	assert_int_equal(df1_set_option(h, DF1_OPT_ROUTE, 0), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_ROUTE), 0);
	expect_config_range(h, df1_set_option(h, DF1_OPT_ROUTE, 2), "ROUTE", "0 or 1");
	/* 0.5: the radio modem's options (libdf1(7) RADIO MODEM) */
	assert_int_equal(DF1_OPT_APP_RETRIES, 23);
	assert_int_equal(DF1_OPT_DCD_WAIT_MS, 28);
	assert_int_equal(df1_get_option(h, DF1_OPT_APP_RETRIES), 0);
	expect_config_range(h, df1_set_option(h, DF1_OPT_APP_RETRIES, -1), "APP_RETRIES", "0..10");
	assert_int_equal(df1_get_option(h, DF1_OPT_RADIO_DUP_DETECT), DF1_DUP_AUTO);
	assert_int_equal(df1_set_option(h, DF1_OPT_RADIO_DUP_DETECT, 0), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_RADIO_DUP_DETECT), 0);
	expect_config_range(h, df1_set_option(h, DF1_OPT_RADIO_DUP_DETECT, 3), "RADIO_DUP_DETECT",
	                    "(auto)");
	assert_int_equal(df1_get_option(h, DF1_OPT_RADIO_RTS_CTS), 0);
	expect_config_range(h, df1_set_option(h, DF1_OPT_RADIO_RTS_CTS, 2), "RADIO_RTS_CTS", "0 or 1");
	assert_int_equal(df1_set_option(h, DF1_OPT_RTS_OFF_DELAY_MS, 65535), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_RTS_OFF_DELAY_MS), 65535);
	expect_config_range(h, df1_set_option(h, DF1_OPT_DCD_WAIT_MS, 65536), "DCD_WAIT_MS",
	                    "0..65535 ms");
	/* the first value past the end is not an option */
	assert_int_equal(df1_set_option(h, (enum df1_option)29, 1), DF1_E_INVAL);
	assert_int_equal(df1_get_option(h, (enum df1_option)29), DF1_E_INVAL);
	assert_int_equal(df1_get_option(h, (enum df1_option)99), DF1_E_INVAL);
}

struct log_rec {
	int calls, id;
	enum df1_severity sev;
	char text[200];
};

static void log_cb(void *user, int id, enum df1_severity sev, const char *text)
{
	struct log_rec *r = user;

	r->calls++;
	r->id = id;
	r->sev = sev;
	snprintf(r->text, sizeof r->text, "%s", text);
}

static void test_handle_log(void **state)
{
	df1_t *h = *state;
	struct log_rec rec;

	memset(&rec, 0, sizeof rec);
	/* no callback: nothing happens */
	df1_log(h, 2509, 7);
	df1_set_log(h, log_cb, &rec);
	df1_log(h, 2509, 7);
	assert_int_equal(rec.calls, 1);
	assert_int_equal(rec.id, 2509);
	assert_int_equal(rec.sev, DF1_SEV_ERROR);
	assert_string_equal(rec.text, "Slave Station (7) Inactive");
	df1_log(h, 2521, 2, -4);
	assert_string_equal(rec.text, "NAK Retry #2, due to error -4");
	assert_int_equal(rec.sev, DF1_SEV_NOTICE);
	/* a configuration error is reported through the callback too */
	assert_int_equal(df1_set_station(h, 300), DF1_E_CONFIG);
	assert_int_equal(rec.calls, 3);
	assert_int_equal(rec.id, 2552);
	assert_int_equal(rec.sev, DF1_SEV_CRITICAL);
	assert_string_equal(rec.text, "Invalid station number (300) must be less than 255");
	df1_set_log(h, NULL, NULL);
	df1_log(h, 2509, 1);
	assert_int_equal(rec.calls, 3);
}

static void test_handle_fail_helpers(void **state)
{
	df1_t *h = *state;
	const struct df1_error_detail *e = df1_last_error(h);

	errno = ENOENT;
	assert_int_equal(df1_fail(h, DF1_E_SYS, 3, "open %s", "x"), DF1_E_SYS);
	assert_int_equal(e->code, DF1_E_SYS);
	assert_int_equal(e->sys_errno, ENOENT);
	assert_int_equal(e->station, 3);
	assert_int_equal(e->catalog_id, df1_error_catalog_id(DF1_E_SYS));
	assert_string_equal(e->message, "open x");
	assert_int_equal(errno, ENOENT);

	errno = EIO;
	assert_int_equal(df1_fail(h, DF1_E_TIMEOUT, 1, NULL), DF1_E_TIMEOUT);
	assert_int_equal(e->sys_errno, 0);
	assert_int_equal(e->catalog_id, 2508);
	assert_string_equal(e->message, df1_strerror(DF1_E_TIMEOUT));

	assert_int_equal(df1_fail_remote(h, 5, 0x10, 0, false), DF1_E_REMOTE);
	assert_int_equal(e->code, DF1_E_REMOTE);
	assert_int_equal(e->station, 5);
	assert_int_equal(e->sts, 0x10);
	assert_false(e->has_ext_sts);
	assert_non_null(strstr(e->message, "PLC error: STS 0x10 ("));
	assert_null(strstr(e->message, "EXT STS"));

	assert_int_equal(df1_fail_remote(h, 2, 0xF0, 0x06, true), DF1_E_REMOTE);
	assert_int_equal(e->sts, 0xF0);
	assert_int_equal(e->ext_sts, 0x06);
	assert_true(e->has_ext_sts);
	assert_non_null(strstr(e->message, "PLC error: STS 0xF0 ("));
	assert_non_null(strstr(e->message, "), EXT STS 0x06 ("));

	df1_clear_error(h);
	assert_int_equal(e->code, 0);
	assert_int_equal(e->station, -1);
	assert_string_equal(e->message, "");
	/* a NULL handle just returns the code */
	assert_int_equal(df1_fail(NULL, DF1_E_INVAL, -1, "x"), DF1_E_INVAL);
}

static void test_handle_counters(void **state)
{
	static const int bad[] = { 0, -1, 2524, 2552, 2555, 2559, 2562, 9999 };
	df1_t *h = *state;
	uint64_t v;
	size_t i;
	int id;

	for (id = 2525; id <= 2561; id++)
		df1_count(h, id);
	df1_count_n(h, 2560, 100);
	df1_count_n(h, 2561, 7);
	df1_count(h, 2524);  /* out of range: ignored */
	df1_count(h, 2562);
	df1_count_n(h, 0, 5);
	for (id = 2525; id <= 2551; id++) {
		assert_int_equal(df1_counter(h, id, &v), 0);
		assert_int_equal(v, 1);
	}
	assert_int_equal(df1_counter(h, 2560, &v), 0);
	assert_int_equal(v, 101);
	assert_int_equal(df1_counter(h, 2561, &v), 0);
	assert_int_equal(v, 8);
	for (i = 0; i < sizeof bad / sizeof bad[0]; i++)
		assert_int_equal(df1_counter(h, bad[i], &v), DF1_E_INVAL);
	assert_int_equal(df1_counter(h, 2525, NULL), DF1_E_INVAL);
	df1_counters_reset(h);
	for (id = 2525; id <= 2561; id++) {
		if (id >= 2552 && id <= 2559)
			continue;
		assert_int_equal(df1_counter(h, id, &v), 0);
		assert_int_equal(v, 0);
	}
}

static void test_handle_stations(void **state)
{
	df1_t *h = *state;

	assert_int_equal(df1_station_set_active(h, 7, false), 0);
	assert_int_equal(df1_station_active(h, 7), 0);
	assert_int_equal(df1_station_active(h, 8), 1);
	assert_int_equal(df1_station_set_active(h, 7, true), 0);
	assert_int_equal(df1_station_active(h, 7), 1);
	assert_int_equal(df1_station_set_active(h, 254, false), 0);
	assert_int_equal(df1_station_active(h, 254), 0);
	assert_int_equal(df1_station_active(h, -1), DF1_E_INVAL);
	assert_int_equal(df1_station_active(h, 255), DF1_E_INVAL);
	assert_int_equal(df1_station_set_active(h, 255, true), DF1_E_INVAL);
	assert_int_equal(df1_station_set_active(h, -1, true), DF1_E_INVAL);
}

static void test_handle_open_errors(void **state)
{
	df1_t *h = *state;
	int pfd[2];

	assert_int_equal(df1_open(h, NULL), DF1_E_INVAL);
	assert_int_equal(df1_open(h, ""), DF1_E_INVAL);
	assert_int_equal(df1_open(NULL, "/dev/null"), DF1_E_INVAL);
	assert_int_equal(df1_open_fd(h, -1, false), DF1_E_INVAL);
	assert_false(df1_is_open(h));
	assert_int_equal(pipe(pfd), 0);
	assert_int_equal(df1_open_fd(h, pfd[0], true), 0);
	assert_true(df1_is_open(h));
	/* already open: refused, the open port is untouched */
	assert_int_equal(df1_open(h, "/dev/null"), DF1_E_INVAL);
	assert_int_equal(df1_open_fd(h, pfd[1], false), DF1_E_INVAL);
	assert_true(df1_is_open(h));
	assert_int_equal(h->fd, pfd[0]);
	/* settings on an open non-serial port are stored */
	assert_int_equal(df1_set_serial(h, 9600, 7, 'E', 1), 0);
	assert_int_equal(h->cfg.baud, 9600);
	df1_close(h);
	df1_close(h); /* twice is harmless */
	assert_false(df1_is_open(h));
	/* the config survives close */
	assert_int_equal(h->cfg.baud, 9600);
	close(pfd[1]);
}

static void test_handle_cancel_fd(void **state)
{
	df1_t *h = *state;
	int pfd[2];

	assert_int_equal(pipe(pfd), 0);
	assert_int_equal(df1_set_cancel_fd(h, pfd[0]), 0);
	assert_int_equal(h->cancel_fd, pfd[0]);
	assert_int_equal(df1_set_cancel_fd(h, -1), 0);
	assert_int_equal(h->cancel_fd, -1);
	close(pfd[0]);
	close(pfd[1]);
	assert_int_equal(df1_set_cancel_fd(h, pfd[0]), DF1_E_INVAL);
	assert_int_equal(df1_set_cancel_fd(h, -2), DF1_E_INVAL);
	assert_int_equal(h->cancel_fd, -1);
}

static int srv_freed;

static void srv_free_cb(struct df1 *h)
{
	srv_freed++;
	h->srv = NULL;
}

static void test_handle_free_calls_destructors(void **state)
{
	df1_t *h = NULL;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	h->srv_free = srv_free_cb;
	df1_free(h);
	assert_int_equal(srv_freed, 1);
}

#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)

int main(void)
{
	const struct CMUnitTest tests[] = {
		T(test_handle_defaults),
		cmocka_unit_test(test_handle_new_free_null),
		cmocka_unit_test(test_handle_tns_differs_between_handles),
		cmocka_unit_test(test_handle_tns_runs_spread),
		T(test_handle_station),
		T(test_handle_duplex),
		T(test_handle_plc),
		T(test_handle_check),
		T(test_handle_retries),
		T(test_handle_cmd_timeout),
		T(test_handle_serial),
		T(test_handle_timeouts_and_delays),
		T(test_handle_options),
		T(test_handle_log),
		T(test_handle_fail_helpers),
		T(test_handle_counters),
		T(test_handle_stations),
		T(test_handle_open_errors),
		T(test_handle_cancel_fd),
		cmocka_unit_test(test_handle_free_calls_destructors),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
