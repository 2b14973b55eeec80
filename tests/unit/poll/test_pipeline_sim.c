/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_pipeline_sim - the poll engine pipelined (DF1_OPT_MAX_OUTSTANDING 4)
 * against df1sim as a separate process on a real pty (tests/support/simproc.c), full
 * duplex: the values read are the data table's and the same as with N = 1;
 * under NAK, dropped-ACK and corrupt-reply faults every queued write ends once
 * and is executed exactly once when reported done (at most once otherwise, never
 * when reported unexecuted), counted in df1sim's frame log (--log), also on a
 * paced line where df1sim is a full-duplex UART (--line-baud, --max-queue 8,
 * the bench's setting) and no value read is another's; against a
 * controller with one buffer (--max-queue 1) the commands beyond it are NAKed
 * and retried and every read still ends GOOD.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>

#include "df1.h"
#include "support/simproc.h"

#define STATIONS 2
#define READS 6                 /* per station: blocks of their own (far apart) */
#define WRITES 12

struct run {
	int done[WRITES];       /* callbacks per write */
	int result[WRITES];
	int wid[WRITES];
	int16_t values[STATIONS][READS];
	bool good[STATIONS][READS];
	struct df1_poll_stats ps;
	uint64_t naks_rcvd, enqs, crc_errors;
};

static const int read_elem[READS] = { 0, 60, 120, 180, 240, 250 };

static void on_write(void *user, int tag_id, int write_id, int result)
{
	struct run *r = user;

	(void)write_id;
	tag_id -= STATIONS * READS;
	if (tag_id >= 0 && tag_id < WRITES) {
		r->done[tag_id]++;
		r->result[tag_id] = result;
	}
}

static void add_tag(df1_t *h, int station, const char *addr, enum df1_access acc)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	c.access = acc;
	c.station = station;
	c.plc = DF1_PLC_SLC;
	c.count = 1;
	c.scan_ms = 0;
	assert_int_equal(df1_addr_parse(addr, &c.addr), 0);
	assert_true(df1_tag_add(h, &c) >= 0);
}

/* Poll the sim with `outstanding` until every write ended and `scans` more scans ran. */
static void run_poll(const struct simproc *sp, int outstanding, bool writes, int scans, struct run *r)
{
	df1_t *h = NULL;
	char addr[32];

	memset(r, 0, sizeof *r);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_timeout_ms(h, 200), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_MAX_OUTSTANDING, outstanding), 0);
	assert_int_equal(df1_open(h, sp->target), 0);
	for (int s = 0; s < STATIONS; s++) {
		for (int i = 0; i < READS; i++) {
			snprintf(addr, sizeof addr, "N7:%d", read_elem[i]);
			add_tag(h, s + 1, addr, DF1_ACCESS_READ);
		}
	}
	for (int w = 0; w < WRITES; w++) {
		snprintf(addr, sizeof addr, "N7:%d", 4 * w + 2);
		add_tag(h, 1 + w % STATIONS, addr, DF1_ACCESS_WRITE);
	}
	if (writes) {
		for (int w = 0; w < WRITES; w++) {
			struct df1_value v = { .kind = DF1_VAL_INT16, .v.i16 = (int16_t)(1000 + w) };

			r->wid[w] = df1_tag_write(h, STATIONS * READS + w, &v, 1, on_write, r);
			assert_true(r->wid[w] > 0);
		}
	}
	for (int guard = 0; guard < 1000; guard++) {
		bool all = true;

		for (int w = 0; writes && w < WRITES; w++)
			all = all && r->done[w] > 0;
		assert_int_equal(df1_poll_stats(h, &r->ps), 0);
		if (all && r->ps.scans >= (uint64_t)scans)
			break;
		assert_true(df1_poll(h, 100) >= 0);
	}
	for (int s = 0; s < STATIONS; s++) {
		for (int i = 0; i < READS; i++) {
			struct df1_tag_state st;

			assert_int_equal(df1_tag_get(h, s * READS + i, &st), 0);
			r->good[s][i] = st.quality == DF1_QUALITY_GOOD;
			r->values[s][i] = st.has_value ? st.value.v.i16 : -1;
		}
	}
	df1_counter(h, DF1_ID_CNT_NAKS_RCVD, &r->naks_rcvd);
	df1_counter(h, DF1_ID_CNT_ENQ_RETRIES, &r->enqs);
	df1_counter(h, DF1_ID_CNT_CRC_ERRORS, &r->crc_errors);
	df1_free(h);
}

static int start_sim(struct simproc *sp, const char *const *args)
{
	return simproc_start(sp, false, NULL, true, args);
}

/* The data table's values (df1sim's default N7:e = e), the same with N = 1 and 4. */
static void test_values_as_one_at_a_time(void **state)
{
	static const char *const args[] = { "--station", "1-2", NULL };
	struct simproc sp;
	struct run one, four;

	(void)state;
	assert_int_equal(start_sim(&sp, args), 0);
	run_poll(&sp, 1, false, 3, &one);
	run_poll(&sp, 4, false, 3, &four);
	simproc_stop(&sp, false);
	for (int s = 0; s < STATIONS; s++) {
		for (int i = 0; i < READS; i++) {
			assert_true(one.good[s][i]);
			assert_true(four.good[s][i]);
			assert_int_equal(one.values[s][i], read_elem[i]);
			assert_int_equal(four.values[s][i], one.values[s][i]);
		}
	}
	assert_int_equal(four.ps.read_failures, 0);
	assert_int_equal(four.ps.blocks, one.ps.blocks);
}

/* Faults: each write ends once, executed once when done (the frame log). */
static void writes_once_under_faults(const char *const *args)
{
	struct simproc sp;
	struct run r;
	char addr[48];

	assert_int_equal(start_sim(&sp, args), 0);
	run_poll(&sp, 4, true, 5, &r);
	/* df1sim logs a command once its reply went out: wait for the last ones */
	for (int w = 0; w < WRITES; w++) {
		snprintf(addr, sizeof addr, "cmd=0F/AA addr=N7:%d ", 4 * w + 2);
		if (r.result[w] >= 0)
			simproc_log_wait(&sp, addr, NULL, 1, 2000);
	}
	for (int w = 0; w < WRITES; w++) {
		int n;

		snprintf(addr, sizeof addr, "cmd=0F/AA addr=N7:%d ", 4 * w + 2);
		n = simproc_log_count(&sp, addr, NULL);
		assert_int_equal(r.done[w], 1);
		if (r.result[w] >= 0)
			assert_int_equal(n, 1);
		else if (df1_error_unexecuted(r.result[w]))
			assert_int_equal(n, 0);
		else
			assert_true(n <= 1);
	}
	/* the faults did happen, on the pipelined line */
	assert_true(r.naks_rcvd > 0);
	assert_true(r.crc_errors > 0);
	assert_true(simproc_log_count(&sp, "cmd=0F/A2", NULL) > 5 * STATIONS * READS / 2);
	/* a value read is the table's, never another block's or a stale one */
	for (int s = 0; s < STATIONS; s++)
		for (int i = 0; i < READS; i++)
			assert_true(r.values[s][i] == read_elem[i] || r.values[s][i] == -1);
	simproc_stop(&sp, false);
}

static void test_writes_once_under_faults(void **state)
{
	static const char *const args[] = { "--station", "1-2", "--nak", "15", "--drop-ack", "15",
	                                    "--corrupt", "15", "--seed", "11", NULL };

	(void)state;
	writes_once_under_faults(args);
}

/* The same on a paced line with df1sim as a full-duplex UART (both
 * directions at once: tools/df1sim/sim_pace.c) buffering 8 commands, as
 * make bench runs it: the replies of the commands in flight come while the
 * next ones go, and faults hit them there. */
static void test_writes_once_under_faults_paced(void **state)
{
	static const char *const args[] = { "--station", "1-2", "--line-baud", "19200", "--max-queue",
	                                    "8", "--nak", "10", "--drop-ack", "10", "--corrupt", "10",
	                                    "--seed", "5", NULL };

	(void)state;
	writes_once_under_faults(args);
}

/* A controller with one buffer: the extra commands are NAKed, retried, all end GOOD. */
static void test_full_queue_naks(void **state)
{
	static const char *const args[] = { "--station", "1-2", "--max-queue", "1", NULL };
	struct simproc sp;
	struct run r;

	(void)state;
	assert_int_equal(start_sim(&sp, args), 0);
	run_poll(&sp, 4, true, 3, &r);
	simproc_stop(&sp, false);
	assert_true(r.naks_rcvd > 0);
	assert_int_equal(r.ps.read_failures, 0);
	for (int w = 0; w < WRITES; w++) {
		assert_int_equal(r.done[w], 1);
		assert_int_equal(r.result[w], 0);
	}
	for (int s = 0; s < STATIONS; s++) {
		for (int i = 0; i < READS; i++) {
			assert_true(r.good[s][i]);
			assert_int_equal(r.values[s][i], read_elem[i]);
		}
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_values_as_one_at_a_time),
		cmocka_unit_test(test_writes_once_under_faults),
		cmocka_unit_test(test_writes_once_under_faults_paced),
		cmocka_unit_test(test_full_queue_naks),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
