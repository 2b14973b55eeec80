/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_poll_pccc - df1_pccc_is_write() over the command list of
 * doc/PROTOCOL.md 4, and df1_poll_submit_pccc() against df1sim as a separate
 * process (tests/support/simproc.c) over a pseudo-terminal:
 *  - the argument checks, and the bounded queue (DF1_E_BUSY at
 *    DF1_PCCC_QUEUE_MAX waiting commands);
 *  - a diagnostic status (06/03) comes back with the requester's TNS, CMD 46,
 *    STS 00, and the processor type df1sim was given (doc/PROTOCOL.md 4.9: SLC 5/04 5B);
 *  - a raw SLC write (0F/AA) is executed once (df1sim --log) and reads back;
 *  - an error reply (a read of a file df1sim does not have) is passed through
 *    with its STS F0 and EXT STS as the controller sent them, result 0;
 *  - a station that does not answer ends the command with a DF1_E_* code;
 *  - writes under --drop-ack and --nak: each reported done is in the log
 *    exactly once, none more than once;
 *  - tag writes and raw commands from one queue come out in FIFO order;
 *  - commands still queued at df1_free() end once with DF1_E_NOT_OPEN.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "df1.h"
#include "support/simproc.h"

static int64_t now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* ------------------------------------------------------------------------
 * The classifier (pure), with doc/PROTOCOL.md 4's command list
 * ------------------------------------------------------------------------ */

static bool is_write(uint8_t cmd, int fnc)
{
	uint8_t b[8] = { cmd, 0x00, 0x34, 0x12, (uint8_t)fnc, 0, 0, 0 };

	return df1_pccc_is_write(b, fnc < 0 ? 4 : sizeof b);
}

static void test_classify_command_list(void **state)
{
	(void)state;
	/* PLC-2 style: no FNC; 00 protected write, 02 / 05 bit writes, 08 write; 01 read */
	assert_true(is_write(0x00, -1));
	assert_false(is_write(0x01, -1));
	assert_true(is_write(0x02, -1));
	assert_true(is_write(0x05, -1));
	assert_true(is_write(0x08, -1));
	/* 06: echo, diagnostic read, diagnostic status read; 02, 04-07 change the interface */
	assert_false(is_write(0x06, 0x00));
	assert_false(is_write(0x06, 0x01));
	assert_false(is_write(0x06, 0x03));
	assert_true(is_write(0x06, 0x02));
	assert_true(is_write(0x06, 0x04));
	assert_true(is_write(0x06, 0x05));
	assert_true(is_write(0x06, 0x06));
	assert_true(is_write(0x06, 0x07));
	/* 0F reads: word range, typed, SLC 2 and 3 address fields */
	assert_false(is_write(0x0F, 0x01));
	assert_false(is_write(0x0F, 0x68));
	assert_false(is_write(0x0F, 0xA1));
	assert_false(is_write(0x0F, 0xA2));
	/* 0F writes: word range, bit, read-modify-write, typed, SLC, masked; modes */
	static const uint8_t w0f[] = { 0x00, 0x02, 0x26, 0x67, 0xA9, 0xAA, 0xAB, 0x3A, 0x80,
		                       0x50, 0x52, 0x53, 0x55, 0x5E, 0x17, 0x18, 0x11, 0xFF };
	for (size_t i = 0; i < sizeof w0f; i++)
		assert_true(is_write(0x0F, w0f[i]));
	/* DH-485 and unknown commands: not known to only read */
	assert_true(is_write(0x0B, 0x00));
	assert_true(is_write(0x1A, 0x00));
	assert_true(is_write(0x77, 0x01));
	/* too short to tell */
	{
		static const uint8_t d[] = { 0x06, 0x00, 0x01, 0x00, 0x03 };

		assert_false(df1_pccc_is_write(d, 5));
		assert_true(df1_pccc_is_write(d, 4));   /* 06 without its FNC */
		assert_true(df1_pccc_is_write(d, 3));
		assert_true(df1_pccc_is_write(NULL, 5));
	}
}

/* ------------------------------------------------------------------------
 * Against df1sim
 * ------------------------------------------------------------------------ */

#define MAXDONE 80

struct done {
	int calls, result;
	uint8_t reply[300];
	size_t n;
	int order;
};

static int order_next;
static struct done dn[MAXDONE];

static void on_done(void *user, int result, const uint8_t *reply, size_t n)
{
	struct done *d = user;

	d->calls++;
	d->result = result;
	d->n = n;
	d->order = ++order_next;
	if (n && n <= sizeof d->reply)
		memcpy(d->reply, reply, n);
	else if (n)
		fail_msg("reply of %zu bytes", n);
	if ((n == 0) != (reply == NULL || result != 0))
		fail_msg("reply %p n %zu for result %d", (const void *)reply, n, result);
}

struct fix {
	struct simproc sim;
	df1_t *h;
};

static int fix_setup(void **state)
{
	struct fix *f = calloc(1, sizeof *f);

	memset(dn, 0, sizeof dn);
	order_next = 0;
	*state = f;
	return f ? 0 : -1;
}

static int fix_teardown(void **state)
{
	struct fix *f = *state;

	if (f->h)
		df1_free(f->h);
	simproc_stop(&f->sim, false);
	free(f);
	return 0;
}

static void start(struct fix *f, bool half, const char *data, const char *const *args, int timeout_ms)
{
	if (simproc_start(&f->sim, false, data, true, args) != 0)
		fail_msg("df1sim did not start");
	assert_int_equal(df1_new(&f->h), 0);
	assert_int_equal(df1_set_duplex(f->h, half ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX), 0);
	assert_int_equal(df1_set_timeout_ms(f->h, timeout_ms), 0);
	assert_int_equal(df1_set_retries(f->h, 3, 3), 0);
	if (df1_open(f->h, f->sim.target) < 0)
		fail_msg("df1_open %s: %s", f->sim.target, df1_last_error(f->h)->message);
	assert_true(df1_poll_fd(f->h) >= 0);    /* makes the engine */
}

static void poll_until_calls(struct fix *f, struct done *d, int want_calls, int ms)
{
	int64_t dl = now_ms() + ms;

	while (d->calls < want_calls) {
		int rc;

		if (now_ms() > dl)
			fail_msg("command not ended after %d ms", ms);
		rc = df1_poll(f->h, 100);
		if (rc < 0)
			fail_msg("df1_poll: %s", df1_errname(rc));
	}
}

static void test_submit_checks_and_bound(void **state)
{
	struct fix *f = *state;
	static const uint8_t diag[] = { 0x06, 0x00, 0x11, 0x22, 0x03 };
	static const uint8_t reply[] = { 0x46, 0x00, 0x11, 0x22 };
	df1_t *h;

	assert_int_equal(df1_new(&h), 0);
	/* no engine yet */
	assert_int_equal(df1_poll_submit_pccc(h, 1, diag, sizeof diag, on_done, &dn[0]), DF1_E_INVAL);
	assert_true(df1_poll_fd(h) >= 0);
	assert_int_equal(df1_poll_submit_pccc(NULL, 1, diag, sizeof diag, on_done, &dn[0]), DF1_E_INVAL);
	assert_int_equal(df1_poll_submit_pccc(h, 255, diag, sizeof diag, on_done, &dn[0]), DF1_E_INVAL);
	assert_int_equal(df1_poll_submit_pccc(h, -1, diag, sizeof diag, on_done, &dn[0]), DF1_E_INVAL);
	assert_int_equal(df1_poll_submit_pccc(h, 1, diag, 3, on_done, &dn[0]), DF1_E_INVAL);
	assert_int_equal(df1_poll_submit_pccc(h, 1, diag, DF1_PCCC_MAX + 1, on_done, &dn[0]), DF1_E_INVAL);
	assert_int_equal(df1_poll_submit_pccc(h, 1, NULL, 5, on_done, &dn[0]), DF1_E_INVAL);
	assert_int_equal(df1_poll_submit_pccc(h, 1, diag, sizeof diag, NULL, &dn[0]), DF1_E_INVAL);
	assert_int_equal(df1_poll_submit_pccc(h, 1, reply, sizeof reply, on_done, &dn[0]), DF1_E_INVAL);
	/* bounded: DF1_PCCC_QUEUE_MAX wait, the next is refused with DF1_E_BUSY */
	for (int i = 0; i < DF1_PCCC_QUEUE_MAX; i++)
		assert_int_equal(df1_poll_submit_pccc(h, 1, diag, sizeof diag, on_done, &dn[i]), 0);
	assert_int_equal(df1_poll_submit_pccc(h, 1, diag, sizeof diag, on_done, &dn[MAXDONE - 1]),
	                 DF1_E_BUSY);
	assert_int_equal(dn[MAXDONE - 1].calls, 0);
	/* never sent (not open): each ends once at df1_free */
	df1_free(h);
	for (int i = 0; i < DF1_PCCC_QUEUE_MAX; i++) {
		assert_int_equal(dn[i].calls, 1);
		assert_int_equal(dn[i].result, DF1_E_NOT_OPEN);
	}
	(void)f;
}

/* 06/03 with TNS 1234: the reply carries TNS 1234 and SLC 5/04's type code */
static void test_diag_status_raw(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--processor", "slc5/04", NULL };
	static const uint8_t diag[] = { 0x06, 0x00, 0x34, 0x12, 0x03 };

	start(f, false, NULL, args, 300);
	assert_int_equal(df1_poll_submit_pccc(f->h, 1, diag, sizeof diag, on_done, &dn[0]), 0);
	poll_until_calls(f, &dn[0], 1, 10000);
	assert_int_equal(dn[0].calls, 1);
	assert_int_equal(dn[0].result, 0);
	assert_true(dn[0].n >= 4 + 4);
	assert_int_equal(dn[0].reply[0], 0x46);
	assert_int_equal(dn[0].reply[1], 0x00);
	assert_int_equal(dn[0].reply[2], 0x34);
	assert_int_equal(dn[0].reply[3], 0x12);
	/* doc/PROTOCOL.md 4.9: SLC 5/03+ replies EE at data byte 1, the type at byte 3 */
	assert_int_equal(dn[0].reply[4 + 1], 0xEE);
	assert_int_equal(dn[0].reply[4 + 3], 0x5B);
	assert_int_equal(simproc_log_wait(&f->sim, "cmd=06/03", NULL, 1, 5000), 1);
}

/* 0F/AA N7:5 = 4660 (file 7, type 89 N, element 5, sub 0), then 0F/A2 reads it */
static void test_raw_write_once_and_error_passed(void **state)
{
	struct fix *f = *state;
	static const uint8_t wr[] = { 0x0F, 0x00, 0x01, 0x00, 0xAA, 0x02, 0x07, 0x89, 0x05, 0x00, 0x34, 0x12 };
	static const uint8_t rd[] = { 0x0F, 0x00, 0x02, 0x00, 0xA2, 0x02, 0x07, 0x89, 0x05, 0x00 };
	/* N40 does not exist in df1sim's table */
	static const uint8_t bad[] = { 0x0F, 0x00, 0x03, 0x00, 0xA2, 0x02, 0x28, 0x89, 0x00, 0x00 };

	start(f, false, NULL, NULL, 300);
	assert_int_equal(df1_poll_submit_pccc(f->h, 1, wr, sizeof wr, on_done, &dn[0]), 0);
	assert_int_equal(df1_poll_submit_pccc(f->h, 1, rd, sizeof rd, on_done, &dn[1]), 0);
	assert_int_equal(df1_poll_submit_pccc(f->h, 1, bad, sizeof bad, on_done, &dn[2]), 0);
	poll_until_calls(f, &dn[2], 1, 10000);
	for (int i = 0; i < 3; i++) {
		assert_int_equal(dn[i].calls, 1);
		assert_int_equal(dn[i].result, 0);
		assert_int_equal(dn[i].order, i + 1);   /* FIFO */
	}
	/* the write: 4F 00 TNS 0001 */
	assert_int_equal(dn[0].n, 4);
	assert_memory_equal(dn[0].reply, ((uint8_t[]){ 0x4F, 0x00, 0x01, 0x00 }), 4);
	/* the read back: 4F 00 TNS 0002 34 12 */
	assert_int_equal(dn[1].n, 6);
	assert_memory_equal(dn[1].reply, ((uint8_t[]){ 0x4F, 0x00, 0x02, 0x00, 0x34, 0x12 }), 6);
	/* the error: STS F0 and an EXT STS, passed through as the simulator sent them */
	assert_true(dn[2].n >= 5);
	assert_int_equal(dn[2].reply[0], 0x4F);
	assert_int_equal(dn[2].reply[1], 0xF0);
	assert_int_equal(dn[2].reply[2], 0x03);
	assert_int_equal(dn[2].reply[3], 0x00);
	assert_true(dn[2].reply[4] != 0);
	assert_int_equal(simproc_log_wait(&f->sim, "cmd=0F/AA addr=N7:5", NULL, 1, 5000), 1);
}

/* A station nobody serves: an error code, no reply */
static void test_no_answer(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--silent", "1", NULL };
	static const uint8_t diag[] = { 0x06, 0x00, 0x34, 0x12, 0x03 };

	start(f, false, NULL, args, 100);
	assert_int_equal(df1_poll_submit_pccc(f->h, 1, diag, sizeof diag, on_done, &dn[0]), 0);
	poll_until_calls(f, &dn[0], 1, 20000);
	assert_int_equal(dn[0].calls, 1);
	assert_true(dn[0].result < 0);
	assert_int_equal(dn[0].n, 0);
}

/* Writes under lost ACKs and NAKs: each ends once, is executed at most once,
 * exactly once when reported done; half duplex, two stations. */
static void run_faults(struct fix *f, bool half)
{
	static const char *const full[] = { "--station", "1,2", "--drop-ack", "15", "--nak", "15",
		                            "--seed", "5", NULL };
	static const char *const hd[] = { "--duplex", "half", "--station", "1,2", "--drop-ack", "15",
		                          "--nak", "15", "--seed", "5", NULL };
	enum { N = 30 };
	int ok = 0;

	start(f, half, NULL, half ? hd : full, 200);
	for (int i = 0; i < N; i++) {
		uint8_t wr[] = { 0x0F, 0x00, (uint8_t)i, 0x77, 0xAA, 0x02, 0x07, 0x89, (uint8_t)(20 + i), 0x00,
			         (uint8_t)i, 0x00 };

		assert_int_equal(df1_poll_submit_pccc(f->h, 1 + (i & 1), wr, sizeof wr, on_done, &dn[i]), 0);
	}
	poll_until_calls(f, &dn[N - 1], 1, 60000);
	for (int i = 0; i < N; i++) {
		char needle[48];
		int n;

		assert_int_equal(dn[i].calls, 1);
		snprintf(needle, sizeof needle, "cmd=0F/AA addr=N7:%d ", 20 + i);
		if (dn[i].result == 0) {
			ok++;
			assert_int_equal(dn[i].reply[2], (uint8_t)i);     /* the requester's TNS */
			assert_int_equal(dn[i].reply[3], 0x77);
			n = simproc_log_wait(&f->sim, needle, NULL, 1, 5000);
			assert_int_equal(n, 1);
		} else {
			n = simproc_log_count(&f->sim, needle, NULL);
			assert_true(n <= 1);
		}
	}
	assert_true(ok >= N / 2);
}

static void test_faults_full(void **state)
{
	run_faults(*state, false);
}

static void test_faults_half(void **state)
{
	run_faults(*state, true);
}

/* One FIFO: a tag write, a raw read, a tag write, a raw write end in that order */
static int wdone_order[2];

static void on_wdone(void *user, int tag, int wid, int result)
{
	(void)tag;
	(void)wid;
	assert_int_equal(result, 0);
	*(int *)user = ++order_next;
}

static void test_fifo_with_tag_writes(void **state)
{
	struct fix *f = *state;
	static const uint8_t rd[] = { 0x0F, 0x00, 0x09, 0x00, 0xA2, 0x02, 0x07, 0x89, 0x0A, 0x00 };
	static const uint8_t wr[] = { 0x0F, 0x00, 0x0A, 0x00, 0xAA, 0x02, 0x07, 0x89, 0x0B, 0x00, 0x05, 0x00 };
	struct df1_tag_config c = { .access = DF1_ACCESS_READWRITE, .station = 1, .plc = DF1_PLC_SLC,
		                    .count = 1, .scan_ms = 60000 };
	struct df1_value v = { .kind = DF1_VAL_INT16, .v.i16 = 42 };
	int id;

	start(f, false, NULL, NULL, 300);
	assert_int_equal(df1_addr_parse("N7:12", &c.addr), 0);
	snprintf(c.name, sizeof c.name, "t");
	id = df1_tag_add(f->h, &c);
	assert_true(id >= 0);
	assert_true(df1_tag_write(f->h, id, &v, 1, on_wdone, &wdone_order[0]) > 0);
	assert_int_equal(df1_poll_submit_pccc(f->h, 1, rd, sizeof rd, on_done, &dn[0]), 0);
	assert_true(df1_tag_write(f->h, id, &v, 1, on_wdone, &wdone_order[1]) > 0);
	assert_int_equal(df1_poll_submit_pccc(f->h, 1, wr, sizeof wr, on_done, &dn[1]), 0);
	poll_until_calls(f, &dn[1], 1, 10000);
	assert_int_equal(wdone_order[0], 1);
	assert_int_equal(dn[0].order, 2);
	assert_int_equal(wdone_order[1], 3);
	assert_int_equal(dn[1].order, 4);
	/* N7:10 = 10 (df1sim's default table), the requester's TNS 0009 */
	assert_int_equal(dn[0].n, 6);
	assert_memory_equal(dn[0].reply, ((uint8_t[]){ 0x4F, 0x00, 0x09, 0x00, 0x0A, 0x00 }), 6);
	assert_int_equal(simproc_log_wait(&f->sim, "cmd=0F/AA addr=N7:11 ", NULL, 1, 5000), 1);
	assert_int_equal(simproc_log_wait(&f->sim, "cmd=0F/AA addr=N7:12 ", NULL, 2, 5000), 2);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_classify_command_list),
		cmocka_unit_test_setup_teardown(test_submit_checks_and_bound, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_diag_status_raw, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_raw_write_once_and_error_passed, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_no_answer, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_fifo_with_tag_writes, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_faults_full, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_faults_half, fix_setup, fix_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
