/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_poll - the poll engine (lib/poll/): the pure block planner, the API
 * without I/O, and the engine against df1sim as a separate process
 * (tests/support/simproc.c) over pseudo-terminals:
 *  - coalescing: 40 tags in two files take two reads (df1sim --log), the SLC
 *    5/02 82-byte limit;
 *  - a tag on a missing element / file is isolated by splitting, the others
 *    stay GOOD and merge again around it (re-plan), the bad tag stays alone;
 *  - a station silenced (df1sim --silent, by restarting df1sim) gets two
 *    retries, then one attempt per scan, goes offline after the absolute retry
 *    count, is retried once per half watchdog, and on recovery gets back its
 *    tags' states with a one-time read of every block; the same in full
 *    duplex with the port kept open (df1sim's SIGUSR1 / SIGUSR2);
 *  - queued writes under --drop-ack and --corrupt end exactly once each, are
 *    executed at most once (exactly once when reported written) and read back;
 *  - a write from another thread wakes a df1_poll() that waits; with nothing
 *    due df1_poll(h, 0) returns at once;
 *  - writes to an offline station, across df1_close() and at df1_free() end
 *    once each and are never sent twice;
 *  - the change callback fires on a change of value, quality or reason only;
 *  - PLC-5 packet limits and stations in address order (frame log); PLC-5
 *    typed floats word-swapped (DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED) in a block;
 *  - scans allocate nothing once the plan is built;
 *  - station discovery over a range.
 * Deadlines, never sleeps; counts are asserted, durations only as lower bounds
 * the engine guarantees (the half-watchdog retry spacing, a df1_poll timeout),
 * besides a generous 1 s for a df1_poll(h, 0) that has nothing to do.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "df1.h"
#include "proto/plc_limits.h"
#include "client/block_plan.h"
#include "support/simproc.h"

/* Allocation counter (test_scans_allocate_nothing): the process's malloc,
 * calloc and realloc come here, glibc's allocator behind them. Not under
 * AddressSanitizer, which owns them. */
#if defined(__SANITIZE_ADDRESS__)
#define COUNT_ALLOCS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define COUNT_ALLOCS 0
#endif
#endif
#ifndef COUNT_ALLOCS
#define COUNT_ALLOCS 1
#endif

static atomic_long allocs;

#if COUNT_ALLOCS

extern void *__libc_malloc(size_t n);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t n);

void *malloc(size_t n)
{
	atomic_fetch_add(&allocs, 1);
	return __libc_malloc(n);
}

void *calloc(size_t n, size_t size)
{
	atomic_fetch_add(&allocs, 1);
	return __libc_calloc(n, size);
}

void *realloc(void *p, size_t n)
{
	atomic_fetch_add(&allocs, 1);
	return __libc_realloc(p, n);
}
#endif

static int64_t now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* ------------------------------------------------------------------------
 * The planner (pure)
 * ------------------------------------------------------------------------ */

static struct poll_item item(int station, enum df1_plc plc, enum df1_file_type t, int file, int first,
                             int count, int tag)
{
	struct poll_item it;
	int es = df1_file_type_element_size(t);

	memset(&it, 0, sizeof it);
	it.station = station;
	it.plc = plc;
	it.type = t;
	it.file = file;
	it.first = first;
	it.count = count;
	it.cost = es;
	it.limit = plc_read_limit(plc, t, (size_t)es, file, first, 0);
	it.period_ms = 1000;
	it.tag = tag;
	return it;
}

static void test_plan_contiguous_one_block(void **state)
{
	struct poll_item it[20];
	struct poll_block b[20];

	(void)state;
	for (int i = 0; i < 20; i++)    /* given in reverse: the planner sorts */
		it[i] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 19 - i, 1, i);
	assert_int_equal(poll_plan(it, 20, POLL_TX_OVERHEAD_FULL, b, 20), 1);
	assert_int_equal(b[0].first, 0);
	assert_int_equal(b[0].count, 20);
	assert_int_equal(b[0].nmembers, 20);
	assert_int_equal(poll_block_packets(&b[0], it), 1);
}

static void test_plan_gap_rule(void **state)
{
	struct poll_item it[2];
	struct poll_block b[2];

	(void)state;
	/* gap 17 words = 34 bytes = the full-duplex transaction overhead: bridged */
	it[0] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 18, 1, 1);
	assert_int_equal(poll_plan(it, 2, POLL_TX_OVERHEAD_FULL, b, 2), 1);
	assert_int_equal(b[0].count, 19);
	/* gap 18 words = 36 bytes: two reads are cheaper */
	it[0] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 19, 1, 1);
	assert_int_equal(poll_plan(it, 2, POLL_TX_OVERHEAD_FULL, b, 2), 2);
	/* half duplex costs more per transaction: 20 words (40 bytes) still bridged */
	it[0] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 21, 1, 1);
	assert_int_equal(poll_plan(it, 2, POLL_TX_OVERHEAD_HALF, b, 2), 1);
	/* floats: a gap of 9 elements is 36 bytes */
	it[0] = item(1, DF1_PLC_SLC, DF1_FT_F, 8, 0, 1, 0);
	it[1] = item(1, DF1_PLC_SLC, DF1_FT_F, 8, 10, 1, 1);
	assert_int_equal(poll_plan(it, 2, POLL_TX_OVERHEAD_FULL, b, 2), 2);
	/* overlapping items are one block */
	it[0] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 0, 10, 0);
	it[1] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 5, 2, 1);
	assert_int_equal(poll_plan(it, 2, POLL_TX_OVERHEAD_FULL, b, 2), 1);
	assert_int_equal(b[0].count, 10);
}

static void test_plan_packet_limits(void **state)
{
	struct poll_item it[200];
	struct poll_block b[200];
	int n;

	(void)state;
	/* SLC 5/03+: 236 bytes = 118 words per read */
	for (int i = 0; i < 200; i++)
		it[i] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, i, 1, i);
	assert_int_equal(poll_plan(it, 200, POLL_TX_OVERHEAD_FULL, b, 200), 2);
	assert_int_equal(b[0].count, 118);
	assert_int_equal(b[1].first, 118);
	assert_int_equal(b[1].count, 82);
	/* SLC 5/01-5/02: 82 bytes = 41 words */
	for (int i = 0; i < 200; i++)
		it[i] = item(1, DF1_PLC_SLC502, DF1_FT_N, 7, i, 1, i);
	assert_int_equal(poll_plan(it, 200, POLL_TX_OVERHEAD_FULL, b, 200), 5);
	for (int k = 0; k < 4; k++)
		assert_int_equal(b[k].count, 41);
	/* floats: 59 per read */
	for (int i = 0; i < 100; i++)
		it[i] = item(1, DF1_PLC_MICROLOGIX, DF1_FT_F, 8, i, 1, i);
	assert_int_equal(poll_plan(it, 100, POLL_TX_OVERHEAD_FULL, b, 100), 2);
	assert_int_equal(b[0].count, 59);
	/* PLC-5 timers: 3 address + 4 type/data + 6 * 38 = 235 <= 240 (39: 241),
	 * 38 per read (doc/PROTOCOL.md 6) */
	for (int i = 0; i < 40; i++)
		it[i] = item(1, DF1_PLC_PLC5, DF1_FT_T, 4, i, 1, i);
	assert_int_equal(poll_plan(it, 40, POLL_TX_OVERHEAD_FULL, b, 40), 2);
	assert_int_equal(b[0].count, 38);
	/* PLC-5 integers: 3 + 4 + 2 * 116 = 239, 116 per read; from N7:255 on the
	 * address is 5 bytes (06 07 FF FF 00): 115 */
	for (int i = 0; i < 117; i++)
		it[i] = item(1, DF1_PLC_PLC5, DF1_FT_N, 7, i, 1, i);
	assert_int_equal(poll_plan(it, 117, POLL_TX_OVERHEAD_FULL, b, 117), 2);
	assert_int_equal(b[0].count, 116);
	for (int i = 0; i < 116; i++)
		it[i] = item(1, DF1_PLC_PLC5, DF1_FT_N, 7, 255 + i, 1, i);
	assert_int_equal(poll_plan(it, 116, POLL_TX_OVERHEAD_FULL, b, 116), 2);
	assert_int_equal(b[0].count, 115);
	/* PLC-5 floats: 3 + 5 (99 09 EA 94 08) + 4 * 58 = 240 */
	for (int i = 0; i < 59; i++)
		it[i] = item(1, DF1_PLC_PLC5, DF1_FT_F, 8, i, 1, i);
	assert_int_equal(poll_plan(it, 59, POLL_TX_OVERHEAD_FULL, b, 59), 2);
	assert_int_equal(b[0].count, 58);
	/* a PLC-5 string goes one per packet */
	for (int i = 0; i < 3; i++)
		it[i] = item(1, DF1_PLC_PLC5, DF1_FT_ST, 9, i, 1, i);
	assert_int_equal(poll_plan(it, 3, POLL_TX_OVERHEAD_FULL, b, 3), 3);
	/* a tag bigger than a packet is one block of several packets; a neighbour
	 * that does not add a packet joins it */
	it[0] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 0, 200, 0);
	it[1] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 200, 1, 1);
	n = poll_plan(it, 2, POLL_TX_OVERHEAD_FULL, b, 2);
	assert_int_equal(n, 1);
	assert_int_equal(poll_block_packets(&b[0], it), 2);
	/* the cap is honoured */
	for (int i = 0; i < 3; i++)
		it[i] = item(i, DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, i);
	assert_int_equal(poll_plan(it, 3, POLL_TX_OVERHEAD_FULL, b, 2), DF1_E_NOSPACE);
}

static void test_plan_keys_and_alone(void **state)
{
	struct poll_item it[8];
	struct poll_block b[8];

	(void)state;
	it[0] = item(2, DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 1, 1, 1);
	it[2] = item(1, DF1_PLC_SLC, DF1_FT_N, 10, 2, 1, 2);
	it[3] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 2, 1, 3);
	it[4] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 3, 1, 4);
	it[4].alone = true;     /* e.g. isolated after an address error */
	it[5] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 4, 1, 5);
	assert_int_equal(poll_plan(it, 6, POLL_TX_OVERHEAD_FULL, b, 8), 5);
	/* station 1 N7:1..2, N7:3 alone, N7:4, N10:2, station 2 N7:0 */
	assert_int_equal(b[0].station, 1);
	assert_int_equal(b[0].first, 1);
	assert_int_equal(b[0].count, 2);
	assert_int_equal(b[0].nmembers, 2);
	assert_true(b[1].alone);
	assert_int_equal(b[1].first, 3);
	assert_int_equal(b[2].first, 4);
	assert_int_equal(b[3].file, 10);
	assert_int_equal(b[4].station, 2);
	/* members are the sorted items, in place */
	assert_int_equal(it[b[1].member0].tag, 4);
	/* the block takes the shortest period of its members */
	it[0] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(1, DF1_PLC_SLC, DF1_FT_N, 7, 1, 1, 1);
	it[1].period_ms = 100;
	assert_int_equal(poll_plan(it, 2, POLL_TX_OVERHEAD_FULL, b, 8), 1);
	assert_int_equal(b[0].period_ms, 100);
}

/* The fewest blocks for sorted single-file items under the same two rules
 * (dynamic programming over contiguous runs), to check the greedy planner. */
static int plan_minimum(const struct poll_item *it, int n, int gap_max)
{
	int best[256];

	best[0] = 0;
	for (int j = 1; j <= n; j++) {
		best[j] = 1 << 20;
		for (int i = j - 1; i >= 0; i--) {
			long first = it[i].first, end = 0;
			bool ok = true;

			for (int k = i; k < j; k++) {
				long e = (long)it[k].first + it[k].count;

				if (k > i && (long)it[k].first - end > 0 &&
				    ((long)it[k].first - end) * it[k].cost > gap_max)
					ok = false;
				if (e > end)
					end = e;
			}
			if ((end - first) * it[i].cost > it[i].limit)
				ok = false;
			if (ok && best[i] + 1 < best[j])
				best[j] = best[i] + 1;
		}
	}
	return best[n];
}

static void test_plan_greedy_is_minimal(void **state)
{
	unsigned seed = (unsigned)time(NULL);
	struct poll_item it[64];
	struct poll_block b[64];

	(void)state;
	print_message("seed %u\n", seed);
	for (int round = 0; round < 500; round++) {
		int n = 1 + (int)(rand_r(&seed) % 60), maxc = 1 + (int)(rand_r(&seed) % 30);

		for (int i = 0; i < n; i++)
			it[i] = item(1, DF1_PLC_SLC502, DF1_FT_N, 7, (int)(rand_r(&seed) % 300),
			             1 + (int)(rand_r(&seed) % (unsigned)maxc), i);
		int got = poll_plan(it, (size_t)n, POLL_TX_OVERHEAD_FULL, b, 64);
		/* it[] is sorted now */
		int want = plan_minimum(it, n, POLL_TX_OVERHEAD_FULL);

		if (got != want)
			fail_msg("seed %u round %d: %d blocks, minimum %d", seed, round, got, want);
		for (int k = 0; k < got; k++)
			assert_true(b[k].count * 2 <= 82 || b[k].nmembers == 1);
	}
}

/* ------------------------------------------------------------------------
 * The API without I/O
 * ------------------------------------------------------------------------ */

static struct df1_tag_config tagcfg(const char *name, int station, const char *addr, int count,
                                    int scan_ms, enum df1_access acc, enum df1_plc plc)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "%s", name);
	c.access = acc;
	c.station = station;
	c.plc = plc;
	assert_int_equal(df1_addr_parse(addr, &c.addr), 0);
	c.count = count;
	c.scan_ms = scan_ms;
	return c;
}

static int add(df1_t *h, const char *name, int station, const char *addr, int count, int scan_ms,
               enum df1_access acc)
{
	struct df1_tag_config c = tagcfg(name, station, addr, count, scan_ms, acc, DF1_PLC_SLC);
	int id = df1_tag_add(h, &c);

	if (id < 0)
		fail_msg("df1_tag_add %s %s: %s: %s", name, addr, df1_errname(id),
		         df1_last_error(h)->message);
	return id;
}

static struct {
	int calls;
	int result;
	int wid;
} done_rec;

static void on_done_rec(void *user, int tag, int wid, int result)
{
	(void)user;
	(void)tag;
	done_rec.calls++;
	done_rec.result = result;
	done_rec.wid = wid;
}

static void test_api_tags(void **state)
{
	df1_t *h;
	struct df1_tag_config c;
	struct df1_tag_state st;
	struct df1_value v;
	int a, b, w;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_tag_count(h), 0);
	a = add(h, "A", 1, "N7:0", 2, 100, DF1_ACCESS_READ);
	b = add(h, "B", 2, "B3:0/3", 1, 0, DF1_ACCESS_READWRITE);
	w = add(h, "W", 2, "F8:1", 1, 100, DF1_ACCESS_WRITE);
	assert_int_equal(a, 0);
	assert_int_equal(b, 1);
	assert_int_equal(df1_tag_count(h), 3);
	assert_int_equal(df1_tag_find(h, "B"), 1);
	assert_int_equal(df1_tag_find(h, "nope"), DF1_E_INVAL);
	/* invalid configurations */
	c = tagcfg("A", 1, "N7:5", 1, 100, DF1_ACCESS_READ, DF1_PLC_SLC);
	assert_int_equal(df1_tag_add(h, &c), DF1_E_CONFIG);            /* duplicate name */
	c = tagcfg("C", 255, "N7:5", 1, 100, DF1_ACCESS_READ, DF1_PLC_SLC);
	assert_int_equal(df1_tag_add(h, &c), DF1_E_INVAL);
	c = tagcfg("C", 1, "N7:5", 0, 100, DF1_ACCESS_READ, DF1_PLC_SLC);
	assert_int_equal(df1_tag_add(h, &c), DF1_E_INVAL);
	c = tagcfg("C", 1, "F8:0", 1, 100, DF1_ACCESS_READ, DF1_PLC_SLC);
	c.addr.bit = 3;
	assert_int_equal(df1_tag_add(h, &c), DF1_E_TYPE);              /* no bits in F */
	assert_int_equal(df1_tag_count(h), 3);
	/* initial state */
	assert_int_equal(df1_tag_get(h, a, &st), 0);
	assert_int_equal(st.quality, DF1_QUALITY_BAD);
	assert_int_equal(st.reason, DF1_REASON_NOT_YET_READ);
	assert_false(st.has_value);
	assert_int_equal(st.age_ms, -1);
	assert_int_equal(st.count, 2);
	assert_string_equal(st.config->name, "A");
	assert_int_equal(st.value.kind, DF1_VAL_INT16);
	assert_int_equal(df1_tag_get(h, 3, &st), DF1_E_INVAL);
	assert_string_equal(df1_quality_name(DF1_QUALITY_UNCERTAIN), "UNCERTAIN");
	assert_string_equal(df1_reason_name(DF1_REASON_STATION_OFFLINE), "station_offline");
	assert_string_equal(df1_station_state_name(DF1_STATION_OFFLINE), "offline");
	/* writes: checked at once */
	memset(&v, 0, sizeof v);
	v.kind = DF1_VAL_INT16;
	assert_int_equal(df1_tag_write(h, a, &v, 1, NULL, NULL), DF1_E_INVAL);   /* read-only */
	assert_int_equal(df1_tag_write(h, b, &v, 1, NULL, NULL), DF1_E_TYPE);    /* a bit */
	assert_int_equal(df1_tag_write(h, 99, &v, 1, NULL, NULL), DF1_E_INVAL);
	v.kind = DF1_VAL_STRING;
	assert_int_equal(df1_tag_write(h, w, &v, 1, NULL, NULL), DF1_E_TYPE);
	v.kind = DF1_VAL_FLOAT;
	v.v.f = 2.5f;
	assert_int_equal(df1_tag_write(h, w, &v, 2, NULL, NULL), DF1_E_INVAL);   /* count 1 */
	/* not open: df1_poll refuses, the write stays queued and fails once at df1_free */
	done_rec.calls = 0;
	assert_true(df1_tag_write(h, w, &v, 1, on_done_rec, NULL) > 0);
	assert_int_equal(df1_poll(h, 0), DF1_E_NOT_OPEN);
	assert_int_equal(done_rec.calls, 0);
	assert_int_equal(df1_poll_set_watchdog(h, -1, 0), DF1_E_INVAL);
	assert_int_equal(df1_poll_set_watchdog(h, 1000, 1001), DF1_E_INVAL);
	assert_int_equal(df1_poll_set_station_range(h, 5, 3), DF1_E_INVAL);
	assert_int_equal(df1_poll_set_station_range(h, -1, 0), 0);
	assert_int_equal(df1_poll_next_ms(h), 0);   /* a write is queued */
	assert_true(df1_poll_fd(h) >= 0);
	/* df1_poll_cancel_queued ends it now, unsent, once */
	assert_int_equal(df1_poll_cancel_queued(h), 1);
	assert_int_equal(done_rec.calls, 1);
	assert_int_equal(done_rec.result, DF1_E_NOT_OPEN);
	assert_int_equal(df1_poll_cancel_queued(h), 0);
	assert_int_equal(df1_poll_cancel_queued(NULL), DF1_E_INVAL);
	/* one queued again ends at df1_free */
	assert_true(df1_tag_write(h, w, &v, 1, on_done_rec, NULL) > 0);
	df1_free(h);
	assert_int_equal(done_rec.calls, 2);
	assert_int_equal(done_rec.result, DF1_E_NOT_OPEN);
}

static int issues_seen;

static void on_issue(void *user, const struct df1_config_issue *is)
{
	(void)user;
	(void)is;
	issues_seen++;
}

static void test_api_load_map(void **state)
{
	const char *dir = getenv("DF1_TEST_DATA") ? getenv("DF1_TEST_DATA") : "tests/data";
	char valid[256], invalid[256];
	df1_t *h;
	int n;

	(void)state;
	snprintf(valid, sizeof valid, "%s/map_valid.csv", dir);
	snprintf(invalid, sizeof invalid, "%s/map_invalid.csv", dir);
	assert_int_equal(df1_new(&h), 0);
	issues_seen = 0;
	n = df1_tag_load_map(h, valid, true, on_issue, NULL);
	assert_true(n > 0);
	assert_int_equal(issues_seen, 0);
	assert_int_equal(df1_tag_count(h), n);
	assert_true(df1_tag_find(h, "Pump1_Speed") >= 0);
	/* the same file again: every name is a duplicate; strict adds nothing */
	issues_seen = 0;
	assert_int_equal(df1_tag_load_map(h, valid, true, on_issue, NULL), DF1_E_CONFIG);
	assert_int_equal(issues_seen, n);
	assert_int_equal(df1_tag_count(h), n);
	/* strict with bad rows: nothing added */
	issues_seen = 0;
	assert_int_equal(df1_tag_load_map(h, invalid, true, on_issue, NULL), DF1_E_CONFIG);
	assert_true(issues_seen > 0);
	assert_int_equal(df1_tag_count(h), n);
	assert_true(df1_tag_load_map(h, "/nonexistent/map.csv", false, NULL, NULL) < 0);
	df1_free(h);
}

/* A big mapping file loads whole and right: every row a tag with its own
 * values, found by name, duplicates still caught (the load is linear in the
 * rows; no timing is asserted here, bench/ measures it). */
static void test_api_load_map_40000_tags(void **state)
{
	enum { N = 40000 };
	static const char *const cmd[] = { "Read", "Write", "ReadWrite" };
	static const enum df1_access acc[] = { DF1_ACCESS_READ, DF1_ACCESS_WRITE, DF1_ACCESS_READWRITE };
	char path[] = "/tmp/df1_test_poll_map_XXXXXX", name[16], want[32], got[32];
	int fd = mkstemp(path), i;
	FILE *f;
	df1_t *h;

	(void)state;
	assert_true(fd >= 0);
	f = fdopen(fd, "w");
	assert_non_null(f);
	fprintf(f, "Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\n");
	for (i = 0; i < N; i++)
		fprintf(f, "t%05d,%s,INT,%d,SLC,N%d:%d,%d,%d\n", i, cmd[i % 3], 1 + i % 5,
		        10 + i / 1000, i % 1000, i % 1000 == 999 ? 1 : 1 + i % 2, 100 * (i % 7));
	/* the same names again further down: reported, the first kept */
	fprintf(f, "t00000,Read,INT,9,SLC,N7:0,1,1000\nt%05d,Read,INT,9,SLC,N7:0,1,1000\n", N - 1);
	assert_int_equal(fclose(f), 0);

	assert_int_equal(df1_new(&h), 0);
	issues_seen = 0;
	assert_int_equal(df1_tag_load_map(h, path, false, on_issue, NULL), N);
	assert_int_equal(issues_seen, 2);
	assert_int_equal(df1_tag_count(h), N);
	for (i = 0; i < N; i++) {
		struct df1_tag_state st;

		snprintf(name, sizeof name, "t%05d", i);
		assert_int_equal(df1_tag_find(h, name), i);
		assert_int_equal(df1_tag_get(h, i, &st), 0);
		assert_string_equal(st.config->name, name);
		assert_int_equal(st.config->access, acc[i % 3]);
		assert_int_equal(st.config->station, 1 + i % 5);
		assert_int_equal(st.config->plc, DF1_PLC_SLC);
		assert_int_equal(st.config->count, i % 1000 == 999 ? 1 : 1 + i % 2);
		assert_int_equal(st.config->scan_ms, 100 * (i % 7));
		snprintf(want, sizeof want, "N%d:%d", 10 + i / 1000, i % 1000);
		assert_true(df1_addr_format(&st.config->addr, got, sizeof got) > 0);
		assert_string_equal(got, want);
	}
	assert_int_equal(df1_tag_find(h, "t40000"), DF1_E_INVAL);
	assert_int_equal(df1_tag_find(h, "t0000"), DF1_E_INVAL);
	/* the whole file again, strict: every name is taken, nothing added */
	issues_seen = 0;
	assert_int_equal(df1_tag_load_map(h, path, true, on_issue, NULL), DF1_E_CONFIG);
	assert_int_equal(issues_seen, N + 2);
	assert_int_equal(df1_tag_count(h), N);
	/* df1_tag_add after it: a new name gets the next id, a taken one is refused */
	{
		struct df1_tag_config c = { .access = DF1_ACCESS_READ, .station = 1, .plc = DF1_PLC_SLC,
		                            .count = 1, .scan_ms = 1000 };

		assert_int_equal(df1_addr_parse("N7:0", &c.addr), 0);
		snprintf(c.name, sizeof c.name, "t%05d", 123);
		assert_int_equal(df1_tag_add(h, &c), DF1_E_CONFIG);
		snprintf(c.name, sizeof c.name, "extra");
		assert_int_equal(df1_tag_add(h, &c), N);
		assert_int_equal(df1_tag_find(h, "extra"), N);
	}
	df1_free(h);
	unlink(path);
}

/* ------------------------------------------------------------------------
 * Against df1sim
 * ------------------------------------------------------------------------ */

struct fix {
	struct simproc sim;
	df1_t *h;
};

static int fix_setup(void **state)
{
	struct fix *f = calloc(1, sizeof *f);

	if (!f)
		return -1;
	*state = f;
	return 0;
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

static void sim_start(struct fix *f, const char *const *args)
{
	if (simproc_start(&f->sim, false, NULL, true, args) != 0)
		fail_msg("df1sim did not start");
}

static void client_open(struct fix *f, bool half, int timeout_ms, int nak, int enq)
{
	int rc;

	if (!f->h) {
		assert_int_equal(df1_new(&f->h), 0);
		assert_int_equal(df1_set_duplex(f->h, half ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX), 0);
		assert_int_equal(df1_set_timeout_ms(f->h, timeout_ms), 0);
		assert_int_equal(df1_set_retries(f->h, nak, enq), 0);
	}
	rc = df1_open(f->h, f->sim.target);
	if (rc < 0)
		fail_msg("df1_open %s: %s", f->sim.target, df1_last_error(f->h)->message);
}

/* Restart df1sim (a new pty) with other options; the handle is reopened on it. */
static void sim_restart(struct fix *f, const char *const *args)
{
	df1_close(f->h);
	simproc_stop(&f->sim, false);
	sim_start(f, args);
	if (df1_open(f->h, f->sim.target) < 0)
		fail_msg("df1_open %s: %s", f->sim.target, df1_last_error(f->h)->message);
}

/* Lines of df1sim's --log that hold every needle (NULL-terminated). */
static int log_count(struct fix *f, const char *n1, const char *n2)
{
	return simproc_log_count(&f->sim, n1, n2);
}

static int log_wait(struct fix *f, const char *n1, const char *n2, int want)
{
	return simproc_log_wait(&f->sim, n1, n2, want, 5000);
}

static void poll_ok(struct fix *f, int timeout_ms)
{
	int rc = df1_poll(f->h, timeout_ms);

	if (rc < 0)
		fail_msg("df1_poll: %s: %s", df1_errname(rc), df1_last_error(f->h)->message);
}

/* Poll until pred holds or ms pass (then fail with what). */
#define POLL_UNTIL(f, ms, cond, what)                                                \
	do {                                                                          \
		int64_t dl_ = now_ms() + (ms);                                        \
		while (!(cond)) {                                                     \
			if (now_ms() > dl_)                                           \
				fail_msg("timed out waiting for %s", what);           \
			poll_ok((f), 100);                                            \
		}                                                                     \
	} while (0)

static struct df1_tag_state tagst(df1_t *h, int id)
{
	struct df1_tag_state st;

	assert_int_equal(df1_tag_get(h, id, &st), 0);
	return st;
}

static struct df1_station_health sth(df1_t *h, int station)
{
	struct df1_station_health s;

	assert_int_equal(df1_station_health(h, station, &s), 0);
	return s;
}

static struct df1_poll_stats pstats(df1_t *h)
{
	struct df1_poll_stats s;

	assert_int_equal(df1_poll_stats(h, &s), 0);
	return s;
}

static bool all_good(df1_t *h, int first, int n)
{
	for (int id = first; id < first + n; id++)
		if (tagst(h, id).quality != DF1_QUALITY_GOOD)
			return false;
	return true;
}

/* Run exactly one scan (and whatever writes are queued). */
static void one_scan(struct fix *f)
{
	uint64_t s0 = pstats(f->h).scans;

	POLL_UNTIL(f, 10000, pstats(f->h).scans > s0, "a scan");
}

static void test_coalesce_two_files(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { NULL };
	char name[16], addr[16];
	struct df1_poll_stats ps;
	int id0;

	sim_start(f, args);
	client_open(f, false, 500, 3, 3);
	id0 = df1_tag_count(f->h);
	for (int i = 0; i < 20; i++) {
		snprintf(name, sizeof name, "n%d", i);
		snprintf(addr, sizeof addr, "N7:%d", 2 * i);      /* every other word: gaps of 1 */
		add(f->h, name, 1, addr, 1, 1000, DF1_ACCESS_READ);
		snprintf(name, sizeof name, "f%d", i);
		snprintf(addr, sizeof addr, "F8:%d", 19 - i);
		add(f->h, name, 1, addr, 1, 1000, DF1_ACCESS_READ);
	}
	one_scan(f);
	ps = pstats(f->h);
	assert_int_equal(ps.blocks, 2);
	assert_int_equal(ps.last_scan_transactions, 2);
	assert_int_equal(ps.reads, 2);
	assert_int_equal(ps.read_failures, 0);
	/* the frame log: one read per file, nothing else */
	assert_int_equal(log_wait(f, "cmd=0F/A2", NULL, 2), 2);
	assert_int_equal(log_wait(f, "cmd=0F/A2 addr=N7:0 count=39", NULL, 1), 1);
	assert_int_equal(log_wait(f, "cmd=0F/A2 addr=F8:0 count=20", NULL, 1), 1);
	/* df1sim's table: N n = n, F n = n + 0.5 */
	for (int i = 0; i < 20; i++) {
		struct df1_tag_state n = tagst(f->h, id0 + 2 * i), fl = tagst(f->h, id0 + 2 * i + 1);

		assert_int_equal(n.quality, DF1_QUALITY_GOOD);
		assert_int_equal(n.value.kind, DF1_VAL_INT16);
		assert_int_equal(n.value.v.i16, 2 * i);
		assert_int_equal(fl.quality, DF1_QUALITY_GOOD);
		assert_true(fl.value.v.f == (float)(19 - i) + 0.5f);
		assert_true(n.last_good_wall_ms > 0 && n.age_ms >= 0);
	}
}

static void test_coalesce_slc502_limit(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--duplex", "half", "--plc", "slc502", NULL };
	char name[16], addr[16];

	sim_start(f, args);
	client_open(f, true, 500, 3, 3);
	for (int i = 0; i < 60; i++) {
		struct df1_tag_config c;

		snprintf(name, sizeof name, "t%d", i);
		snprintf(addr, sizeof addr, "N7:%d", i);
		c = tagcfg(name, 1, addr, 1, 1000, DF1_ACCESS_READ, DF1_PLC_SLC502);
		assert_true(df1_tag_add(f->h, &c) >= 0);
	}
	one_scan(f);
	/* 120 bytes at 82 per packet: 41 + 19 words */
	assert_int_equal(pstats(f->h).last_scan_transactions, 2);
	assert_int_equal(log_wait(f, "cmd=0F/A2", NULL, 2), 2);
	assert_int_equal(log_wait(f, "addr=N7:0 count=41", NULL, 1), 1);
	assert_int_equal(log_wait(f, "addr=N7:41 count=19", NULL, 1), 1);
	assert_true(all_good(f->h, 0, 60));
	assert_int_equal(tagst(f->h, 59).value.v.i16, 59);
}

/* PLC-5 typed reads (doc/PROTOCOL.md 6: address + type/data + data <= 240 bytes: 58
 * floats, 38 timers, 116 integers after a 3-byte address, see test_client's
 * boundaries) and stations in address order (doc/REQUIREMENTS.md 002),
 * whatever order the tags were added in: df1sim's frame log. */
static void test_coalesce_plc5_station_order(void **state)
{
	struct fix *f = *state;
	/* timers in the data-table form (3 words): 38 a packet */
	static const char *const args[] = { "--plc", "plc5", "--plc5-timer-words", "3", "--station", "1-3",
		                            NULL };
	static const char *const want[] = {
		"station=1 cmd=0F/68 addr=F8:0 count=58", "station=1 cmd=0F/68 addr=F8:58 count=12",
		"station=2 cmd=0F/68 addr=T4:0 count=30",
		"station=3 cmd=0F/68 addr=N7:0 count=116", "station=3 cmd=0F/68 addr=N7:116 count=34",
	};
	char name[16], addr[24], *text, *line, *save = NULL;
	struct df1_tag_config c;
	size_t k = 0;

	sim_start(f, args);
	client_open(f, false, 500, 3, 3);
	for (int i = 0; i < 150; i++) {         /* station 3 first, added from the top */
		snprintf(name, sizeof name, "n%d", i);
		snprintf(addr, sizeof addr, "N7:%d", 149 - i);
		c = tagcfg(name, 3, addr, 1, 1000, DF1_ACCESS_READ, DF1_PLC_PLC5);
		assert_true(df1_tag_add(f->h, &c) >= 0);
	}
	for (int i = 0; i < 30; i++) {
		snprintf(name, sizeof name, "t%d", i);
		snprintf(addr, sizeof addr, "T4:%d.ACC", i);
		c = tagcfg(name, 2, addr, 1, 1000, DF1_ACCESS_READ, DF1_PLC_PLC5);
		assert_true(df1_tag_add(f->h, &c) >= 0);
	}
	for (int i = 0; i < 70; i++) {
		snprintf(name, sizeof name, "f%d", i);
		snprintf(addr, sizeof addr, "F8:%d", i);
		c = tagcfg(name, 1, addr, 1, 1000, DF1_ACCESS_READ, DF1_PLC_PLC5);
		assert_true(df1_tag_add(f->h, &c) >= 0);
	}
	one_scan(f);
	assert_int_equal(pstats(f->h).blocks, 5);
	assert_int_equal(pstats(f->h).last_scan_transactions, 5);
	assert_true(all_good(f->h, 0, 250));
	assert_int_equal(tagst(f->h, 0).value.v.i16, 149);
	assert_true(tagst(f->h, 249).value.v.f == 69.5f);
	/* the five reads, in this order, and nothing else */
	assert_int_equal(log_wait(f, "cmd=0F/68", NULL, 5), 5);
	text = simproc_slurp(f->sim.log, NULL);
	assert_non_null(text);
	for (line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
		if (k >= sizeof want / sizeof *want || !strstr(line, want[k]))
			fail_msg("frame log line %zu: %s", k, line);
		k++;
	}
	free(text);
	assert_int_equal(k, 5);
}

/* DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED: a block of F tags is read as raw wire bytes
 * and decoded by the engine, which takes the handle's float order (df1sim
 * --plc5-float-swapped; F8:n = n + 0.5). */
static void test_plc5_typed_float_swapped_block(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--plc", "plc5", "--plc5-float-swapped", NULL };
	struct df1_tag_config c;
	char name[16], addr[16];

	sim_start(f, args);
	client_open(f, false, 500, 3, 3);
	assert_int_equal(df1_set_option(f->h, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED, 1), 0);
	for (int i = 0; i < 10; i++) {
		snprintf(name, sizeof name, "f%d", i);
		snprintf(addr, sizeof addr, "F8:%d", i);
		c = tagcfg(name, 1, addr, 1, 1000, DF1_ACCESS_READ, DF1_PLC_PLC5);
		assert_true(df1_tag_add(f->h, &c) >= 0);
	}
	one_scan(f);
	assert_int_equal(pstats(f->h).blocks, 1);
	assert_true(all_good(f->h, 0, 10));
	for (int i = 0; i < 10; i++)
		assert_true(tagst(f->h, i).value.v.f == (float)i + 0.5f);
}

static void test_bad_tag_isolated(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { NULL };
	struct df1_poll_stats ps;
	struct df1_tag_state bad, nofile;
	char name[16], addr[16];
	int ids[6], idbad, idnofile;

	sim_start(f, args);
	client_open(f, false, 500, 3, 3);
	for (int i = 0; i < 6; i++) {
		snprintf(name, sizeof name, "g%d", i);
		snprintf(addr, sizeof addr, "N7:%d", 250 + i);
		ids[i] = add(f->h, name, 1, addr, 1, 1000, DF1_ACCESS_READ);
	}
	/* df1sim's N7 has 256 elements: N7:258 is past the end, 2 words after the
	 * last good tag, so the planner bridges to it */
	idbad = add(f->h, "bad", 1, "N7:258", 1, 1000, DF1_ACCESS_READ);
	idnofile = add(f->h, "nofile", 1, "N77:0", 1, 1000, DF1_ACCESS_READ);
	one_scan(f);
	ps = pstats(f->h);
	/* [250..258] fails -> [250..252] ok, [253..258] fails -> [253..254] ok,
	 * [255..258] fails -> [255] ok, [258] fails; N77:0 fails */
	assert_int_equal(ps.splits, 3);
	assert_int_equal(ps.reads, 8);
	assert_int_equal(ps.read_failures, 5);
	for (int i = 0; i < 6; i++) {
		struct df1_tag_state st = tagst(f->h, ids[i]);

		assert_int_equal(st.quality, DF1_QUALITY_GOOD);
		assert_int_equal(st.value.v.i16, 250 + i);
	}
	bad = tagst(f->h, idbad);
	assert_int_equal(bad.quality, DF1_QUALITY_BAD);
	assert_int_equal(bad.reason, DF1_REASON_PLC_ERROR);
	assert_int_equal(bad.last_error, DF1_E_REMOTE);
	assert_int_equal(bad.sts, 0xF0);
	assert_true(bad.ext_sts == 0x07 || bad.ext_sts == 0x0A);
	nofile = tagst(f->h, idnofile);
	assert_int_equal(nofile.quality, DF1_QUALITY_BAD);
	assert_int_equal(nofile.reason, DF1_REASON_PLC_ERROR);
	/* the station answered all along */
	assert_int_equal(sth(f->h, 1).state, DF1_STATION_OK);

	/* the bad tags stay alone and the good ones merge again: the next scan
	 * reads N7:250..255, N7:258 and N77:0, no new split */
	one_scan(f);
	ps = pstats(f->h);
	assert_int_equal(ps.splits, 3);
	assert_int_equal(ps.blocks, 3);
	assert_int_equal(ps.last_scan_transactions, 3);
	assert_int_equal(ps.read_failures, 7);
	assert_int_equal(log_wait(f, "cmd=0F/A2 addr=N7:250 count=6", NULL, 1), 1);
	assert_true(all_good(f->h, ids[0], 6));
	assert_int_equal(tagst(f->h, idbad).reason, DF1_REASON_PLC_ERROR);

	/* a new tag re-plans: the bad tag stays alone, the good ones merge again */
	add(f->h, "g6", 1, "N7:249", 1, 1000, DF1_ACCESS_READ);
	one_scan(f);
	ps = pstats(f->h);
	assert_int_equal(ps.splits, 3);
	assert_int_equal(ps.blocks, 3);                 /* N7:249..255, N7:258, N77:0 */
	/* only the block with the new tag was due: one read of N7:249..255 */
	assert_int_equal(ps.last_scan_transactions, 1);
	assert_int_equal(log_wait(f, "cmd=0F/A2 addr=N7:249 count=7", NULL, 1), 1);
	assert_true(all_good(f->h, ids[0], 6));
	assert_int_equal(tagst(f->h, idbad).quality, DF1_QUALITY_BAD);
}

/* Station 2 silenced, offline, retried slowly, restored (doc/REQUIREMENTS.md 000, 002, 004). */
static void test_station_silenced_and_restored(void **state)
{
	struct fix *f = *state;
	static const char *const normal[] = { "--duplex", "half", "--station", "1,2", NULL };
	static const char *const silent[] = { "--duplex", "half", "--station", "1,2", "--silent", "2", NULL };
	int s1, s2, slow, bad;
	struct df1_station_health a, b;
	struct df1_poll_stats p0, p1;
	struct df1_tag_state st;
	int64_t t_restore, prev_attempt;
	uint64_t s1_reads;
	int offline_tries = 0;

	sim_start(f, normal);
	client_open(f, true, 100, 1, 1);
	/* offline after more than 3 failed attempts in a row; slow retry every 1000 ms */
	assert_int_equal(df1_poll_set_watchdog(f->h, 2000, 3), 0);
	s1 = add(f->h, "s1", 1, "N7:0", 5, 100, DF1_ACCESS_READ);
	s2 = add(f->h, "s2", 2, "N7:10", 5, 100, DF1_ACCESS_READ);
	slow = add(f->h, "slow", 2, "F8:0", 1, 600000, DF1_ACCESS_READ);
	bad = add(f->h, "bad", 2, "N77:0", 1, 100, DF1_ACCESS_READ);
	POLL_UNTIL(f, 10000, all_good(f->h, s1, 3) && tagst(f->h, bad).reason == DF1_REASON_PLC_ERROR,
	           "every tag read");
	assert_int_equal(sth(f->h, 2).state, DF1_STATION_OK);

	/* silence station 2 */
	sim_restart(f, silent);
	a = sth(f->h, 2);
	p0 = pstats(f->h);
	POLL_UNTIL(f, 10000, sth(f->h, 2).attempts > a.attempts, "an attempt at station 2");
	b = sth(f->h, 2);
	p1 = pstats(f->h);
	/* it answered last scan: the attempt and two retries (doc/REQUIREMENTS.md 002) */
	assert_int_equal(b.attempts - a.attempts, 3);
	assert_int_equal(p1.retries - p0.retries, 2);
	assert_int_equal(b.state, DF1_STATION_FAILING);
	assert_int_equal(b.consecutive_failures, 3);
	st = tagst(f->h, s2);
	assert_int_equal(st.quality, DF1_QUALITY_UNCERTAIN);
	assert_int_equal(st.reason, DF1_REASON_COMM_FAILURE);
	assert_true(st.has_value);
	assert_int_equal(st.values[4].v.i16, 14);               /* the last good value is kept */
	assert_int_equal(tagst(f->h, slow).quality, DF1_QUALITY_GOOD);  /* not due yet */
	assert_int_equal(tagst(f->h, s1).quality, DF1_QUALITY_GOOD);

	/* the next scan: a single attempt, and 4 > 3 failures: offline */
	a = b;
	POLL_UNTIL(f, 10000, sth(f->h, 2).attempts > a.attempts, "the next attempt at station 2");
	b = sth(f->h, 2);
	assert_int_equal(b.attempts - a.attempts, 1);
	assert_int_equal(b.state, DF1_STATION_OFFLINE);
	assert_int_equal(pstats(f->h).stations_offline, 1);
	for (int id = s2; id <= bad; id++) {
		st = tagst(f->h, id);
		assert_int_equal(st.quality, DF1_QUALITY_BAD);
		assert_int_equal(st.reason, DF1_REASON_STATION_OFFLINE);
	}

	/* offline: one attempt per half watchdog (1000 ms), station 1 unaffected */
	prev_attempt = b.last_attempt_ms;
	s1_reads = tagst(f->h, s1).reads;
	a = b;
	while (offline_tries < 2) {
		POLL_UNTIL(f, 15000, sth(f->h, 2).attempts > a.attempts, "a slow retry");
		b = sth(f->h, 2);
		assert_int_equal(b.attempts - a.attempts, 1);
		assert_int_equal(b.state, DF1_STATION_OFFLINE);
		if (b.last_attempt_ms - prev_attempt < 1000)
			fail_msg("slow retry %lld ms after the previous attempt (half watchdog 1000)",
			         (long long)(b.last_attempt_ms - prev_attempt));
		prev_attempt = b.last_attempt_ms;
		a = b;
		offline_tries++;
	}
	assert_true(tagst(f->h, s1).reads > s1_reads);
	assert_int_equal(tagst(f->h, s1).quality, DF1_QUALITY_GOOD);

	/* restore: the station answers its next slow retry */
	sim_restart(f, normal);
	t_restore = now_ms();
	POLL_UNTIL(f, 15000, sth(f->h, 2).state == DF1_STATION_OK, "station 2 back");
	/* the one-time poll: every block read at once, the 10-minute one too */
	st = tagst(f->h, s2);
	assert_int_equal(st.quality, DF1_QUALITY_GOOD);
	assert_true(st.last_good_ms >= t_restore);
	st = tagst(f->h, slow);
	assert_int_equal(st.quality, DF1_QUALITY_GOOD);
	assert_true(st.last_good_ms >= t_restore);
	assert_true(st.value.v.f == 0.5f);
	/* the bad tag is back to what it was before the failure */
	st = tagst(f->h, bad);
	assert_int_equal(st.quality, DF1_QUALITY_BAD);
	assert_int_equal(st.reason, DF1_REASON_PLC_ERROR);
	assert_int_equal(pstats(f->h).stations_offline, 0);
	assert_int_equal(sth(f->h, 2).consecutive_failures, 0);
}

/* The time watchdog: a station that never answers is BAD COMM_FAILURE while it
 * fails, and offline (BAD STATION_OFFLINE) only once watchdog_ms have passed
 * since the first attempt. */
static void test_watchdog_time(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--duplex", "half", "--station", "1,2", "--silent", "2", NULL };
	struct df1_tag_state st;
	int64_t t0;
	int s1, s2;

	sim_start(f, args);
	client_open(f, true, 100, 1, 1);
	assert_int_equal(df1_poll_set_watchdog(f->h, 1500, 0), 0);
	s1 = add(f->h, "s1", 1, "N7:0", 1, 100, DF1_ACCESS_READ);
	s2 = add(f->h, "s2", 2, "N7:0", 1, 100, DF1_ACCESS_READ);
	t0 = now_ms();
	POLL_UNTIL(f, 10000, sth(f->h, 2).state == DF1_STATION_FAILING, "station 2 failing");
	st = tagst(f->h, s2);
	assert_int_equal(st.quality, DF1_QUALITY_BAD);          /* never read: no value */
	assert_int_equal(st.reason, DF1_REASON_COMM_FAILURE);
	assert_int_equal(st.last_error == DF1_E_NAK_LIMIT || st.last_error == DF1_E_INACTIVE ||
	                 st.last_error == DF1_E_TIMEOUT, 1);
	POLL_UNTIL(f, 15000, sth(f->h, 2).state == DF1_STATION_OFFLINE, "station 2 offline");
	if (now_ms() - t0 < 1500)
		fail_msg("offline %lld ms after the first attempt (watchdog 1500)",
		         (long long)(now_ms() - t0));
	assert_true(sth(f->h, 2).consecutive_failures >= 2);
	st = tagst(f->h, s2);
	assert_int_equal(st.quality, DF1_QUALITY_BAD);
	assert_int_equal(st.reason, DF1_REASON_STATION_OFFLINE);
	assert_int_equal(tagst(f->h, s1).quality, DF1_QUALITY_GOOD);
	assert_int_equal(sth(f->h, 1).state, DF1_STATION_OK);
}

/* ---- queued writes ---- */

#define NWRITES 40

struct wctx {
	df1_t *h;
	int ids[NWRITES];
	int wid[NWRITES];
	int got_wid[NWRITES];   /* the callback may run before df1_tag_write returns */
	atomic_int calls[NWRITES];
	int result[NWRITES];
	atomic_int done;
	int delay_ms;
};

static void on_write(void *user, int tag, int wid, int result)
{
	struct wctx *w = user;

	for (int i = 0; i < NWRITES; i++) {
		if (w->ids[i] == tag) {
			w->got_wid[i] = wid;
			atomic_fetch_add(&w->calls[i], 1);
			w->result[i] = result;
		}
	}
	atomic_fetch_add(&w->done, 1);
}

static void *writer(void *arg)
{
	struct wctx *w = arg;

	for (int i = 0; i < NWRITES; i++) {
		struct df1_value v;

		memset(&v, 0, sizeof v);
		v.kind = DF1_VAL_INT16;
		v.v.i16 = (int16_t)(1000 + i);
		if (i == 0 && w->delay_ms > 0) {
			/* wake-up test: write while the poll thread waits */
			struct timespec ts = { 0, (long)w->delay_ms * 1000000L };

			nanosleep(&ts, NULL);
		}
		w->wid[i] = df1_tag_write(w->h, w->ids[i], &v, 1, on_write, w);
		if (w->wid[i] <= 0)
			atomic_fetch_add(&w->done, 1);  /* counted: the test then fails on it */
	}
	return NULL;
}

static bool link_err(int rc)
{
	return rc == DF1_E_TIMEOUT || rc == DF1_E_NAK_LIMIT || rc == DF1_E_ENQ_LIMIT ||
	       rc == DF1_E_INACTIVE || rc == DF1_E_BAD_REPLY;
}

/* Every write reported written shows in its tag. */
static bool read_back(df1_t *h, const struct wctx *w)
{
	for (int i = 0; i < NWRITES; i++)
		if (w->result[i] == 0 && tagst(h, w->ids[i]).value.v.i16 != 1000 + i)
			return false;
	return true;
}

static void test_writes_under_faults_exactly_once(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--drop-ack", "15", "--corrupt", "15", "--seed", "7", NULL };
	static struct wctx w;
	pthread_t th;
	char name[16], addr[16], needle[48];
	int written = 0;

	sim_start(f, args);
	client_open(f, false, 200, 3, 3);
	memset(&w, 0, sizeof w);
	w.h = f->h;
	for (int i = 0; i < NWRITES; i++) {
		snprintf(name, sizeof name, "w%d", i);
		snprintf(addr, sizeof addr, "N7:%d", 100 + i);
		w.ids[i] = add(f->h, name, 1, addr, 1, 300, DF1_ACCESS_READWRITE);
	}
	POLL_UNTIL(f, 20000, all_good(f->h, w.ids[0], NWRITES), "the first read");
	assert_int_equal(pthread_create(&th, NULL, writer, &w), 0);
	{
		int64_t dl = now_ms() + 60000;

		while (atomic_load(&w.done) < NWRITES) {
			if (now_ms() > dl)
				fail_msg("only %d of %d writes ended", atomic_load(&w.done), NWRITES);
			poll_ok(f, 100);
		}
	}
	pthread_join(th, NULL);
	for (int i = 0; i < NWRITES; i++) {
		assert_true(w.wid[i] > 0);
		assert_int_equal(w.got_wid[i], w.wid[i]);
		assert_int_equal(atomic_load(&w.calls[i]), 1);         /* reported once */
		if (w.result[i] == 0)
			written++;
		else if (!link_err(w.result[i]))
			fail_msg("write %d ended with %s", i, df1_errname(w.result[i]));
	}
	assert_true(written >= NWRITES / 2);
	assert_int_equal(pstats(f->h).writes, NWRITES);
	/* read back: the tags show the values written */
	POLL_UNTIL(f, 20000, read_back(f->h, &w), "the values read back");
	/* df1sim executed each write once at most, exactly once when reported written */
	for (int i = 0; i < NWRITES; i++) {
		int n;

		snprintf(needle, sizeof needle, "cmd=0F/AA addr=N7:%d count", 100 + i);
		n = log_wait(f, needle, NULL, w.result[i] == 0 ? 1 : 0);
		if (w.result[i] == 0)
			assert_int_equal(n, 1);
		else
			assert_true(n <= 1);
	}
}

static void test_write_wakes_poll(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { NULL };
	static struct wctx w;
	pthread_t th;
	int64_t t0, took;
	int n = 0;

	sim_start(f, args);
	client_open(f, false, 500, 3, 3);
	memset(&w, 0, sizeof w);
	w.h = f->h;
	for (int i = 0; i < NWRITES; i++)
		w.ids[i] = -1;
	w.ids[0] = add(f->h, "x", 1, "N7:50", 1, 600000, DF1_ACCESS_READWRITE);
	POLL_UNTIL(f, 10000, all_good(f->h, w.ids[0], 1), "the first read");
	assert_true(df1_poll_next_ms(f->h) > 1000);     /* nothing due for 10 minutes */
	/* nothing due: df1_poll(h, 0) returns at once; df1_poll(h, 150) waits 150 ms */
	t0 = now_ms();
	assert_int_equal(df1_poll(f->h, 0), 0);
	if (now_ms() - t0 >= 1000)
		fail_msg("df1_poll(h, 0) took %lld ms with nothing due", (long long)(now_ms() - t0));
	t0 = now_ms();
	assert_int_equal(df1_poll(f->h, 150), 0);
	assert_true(now_ms() - t0 >= 150);
	/* a writer thread queues one write 200 ms from now; df1_poll waits up to 20 s */
	w.delay_ms = 200;
	{
		/* only one write: the other ids are -1 and are refused at once */
		assert_int_equal(pthread_create(&th, NULL, writer, &w), 0);
		t0 = now_ms();
		while (atomic_load(&w.calls[0]) == 0 && now_ms() - t0 < 20000) {
			int r = df1_poll(f->h, 20000);

			assert_true(r >= 0);
			n += r;
		}
		took = now_ms() - t0;
		pthread_join(th, NULL);
	}
	assert_int_equal(atomic_load(&w.calls[0]), 1);
	assert_int_equal(w.result[0], 0);
	assert_int_equal(w.got_wid[0], w.wid[0]);
	assert_true(n >= 1);
	if (took >= 15000)
		fail_msg("the queued write did not wake df1_poll (%lld ms)", (long long)took);
	/* and the value is read back at once (its block was made due) */
	POLL_UNTIL(f, 10000, tagst(f->h, w.ids[0]).value.v.i16 == 1000, "the read back");
}

/* ---- change callback ---- */

#define CB_TAGS 3

static struct {
	int calls[CB_TAGS];
	struct df1_tag_state last[CB_TAGS];
} cbrec;

static void on_tag(void *user, int id, const struct df1_tag_state *st)
{
	assert_ptr_equal(user, &cbrec);
	assert_true(id >= 0 && id < CB_TAGS);
	assert_int_equal(st->id, id);
	cbrec.calls[id]++;
	cbrec.last[id] = *st;
}

/* The callback fires on a change of value, quality or reason, and only then. */
static void test_change_callback(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--duplex", "half", "--station", "1", NULL };
	int16_t v77 = 77;
	int a, b, c;

	sim_start(f, args);
	client_open(f, true, 100, 1, 1);
	memset(&cbrec, 0, sizeof cbrec);
	assert_int_equal(df1_set_tag_callback(f->h, on_tag, &cbrec), 0);
	assert_int_equal(df1_poll_set_watchdog(f->h, 600000, 3), 0);
	a = add(f->h, "a", 1, "N7:5", 1, 0, DF1_ACCESS_READ);
	b = add(f->h, "b", 1, "F8:0", 1, 0, DF1_ACCESS_READ);
	c = add(f->h, "c", 2, "N7:0", 1, 0, DF1_ACCESS_READ);     /* nobody at station 2 */
	assert_int_equal(c, CB_TAGS - 1);
	/* scan 1: a and b read (BAD not_yet_read -> GOOD with a value); station 2
	 * fails its attempt and two retries: c BAD not_yet_read -> BAD comm_failure */
	one_scan(f);
	assert_int_equal(cbrec.calls[a], 1);
	assert_int_equal(cbrec.last[a].quality, DF1_QUALITY_GOOD);
	assert_true(cbrec.last[a].has_value);
	assert_int_equal(cbrec.last[a].value.v.i16, 5);
	assert_int_equal(cbrec.calls[b], 1);
	assert_true(cbrec.last[b].value.v.f == 0.5f);
	assert_int_equal(cbrec.calls[c], 1);
	assert_int_equal(cbrec.last[c].quality, DF1_QUALITY_BAD);
	assert_int_equal(cbrec.last[c].reason, DF1_REASON_COMM_FAILURE);
	/* scan 2: the same values: no call for a and b; station 2 fails a fourth
	 * time (> 3): offline, c BAD station_offline */
	one_scan(f);
	assert_int_equal(cbrec.calls[a], 1);
	assert_int_equal(cbrec.calls[b], 1);
	assert_int_equal(cbrec.calls[c], 2);
	assert_int_equal(cbrec.last[c].reason, DF1_REASON_STATION_OFFLINE);
	/* scan 3: nothing changed, no call at all */
	one_scan(f);
	assert_int_equal(cbrec.calls[a] + cbrec.calls[b] + cbrec.calls[c], 4);
	/* a new value in the PLC: one call for a, with it */
	assert_int_equal(df1_write_int16(f->h, 1, "N7:5", &v77, 1), 1);
	one_scan(f);
	assert_int_equal(cbrec.calls[a], 2);
	assert_int_equal(cbrec.last[a].value.v.i16, 77);
	assert_int_equal(cbrec.last[a].quality, DF1_QUALITY_GOOD);
	assert_int_equal(cbrec.calls[b], 1);
	assert_int_equal(cbrec.calls[c], 2);
}

static struct {
	int calls, result, wid;
} offrec[4];

static void on_off_write(void *user, int tag, int wid, int result)
{
	int k = (int)(intptr_t)user;

	(void)tag;
	assert_true(k >= 0 && k < 4);
	offrec[k].calls++;
	offrec[k].result = result;
	offrec[k].wid = wid;
}

static int queue_write(df1_t *h, int id, int16_t value, int k)
{
	struct df1_value v;
	int wid;

	memset(&v, 0, sizeof v);
	v.kind = DF1_VAL_INT16;
	v.v.i16 = value;
	wid = df1_tag_write(h, id, &v, 1, on_off_write, (void *)(intptr_t)k);
	assert_true(wid > 0);
	return wid;
}

/* Writes queued to an offline station end once (failed) and are never sent
 * again; a write queued before df1_close() stays queued and is sent once
 * after df1_open(); one still queued at df1_free() ends with DF1_E_NOT_OPEN. */
static void test_writes_offline_close_free(void **state)
{
	struct fix *f = *state;
	static const char *const silent[] = { "--duplex", "half", "--station", "1,2", "--silent", "2", NULL };
	static const char *const normal[] = { "--duplex", "half", "--station", "1,2", NULL };
	int x, y, w0, w1, w2, w3;

	sim_start(f, silent);
	client_open(f, true, 100, 1, 1);
	memset(offrec, 0, sizeof offrec);
	assert_int_equal(df1_poll_set_watchdog(f->h, 600000, 1), 0);
	x = add(f->h, "x", 2, "N7:20", 1, 100, DF1_ACCESS_READWRITE);
	y = add(f->h, "y", 1, "N7:21", 1, 100, DF1_ACCESS_READWRITE);
	POLL_UNTIL(f, 10000, sth(f->h, 2).state == DF1_STATION_OFFLINE, "station 2 offline");

	/* offline: each write is tried once and fails once */
	w0 = queue_write(f->h, x, 500, 0);
	w1 = queue_write(f->h, x, 501, 1);
	POLL_UNTIL(f, 10000, offrec[0].calls && offrec[1].calls, "the writes to the offline station");
	for (int k = 0; k < 2; k++) {
		assert_int_equal(offrec[k].calls, 1);
		if (!link_err(offrec[k].result))
			fail_msg("write %d ended with %s", k, df1_errname(offrec[k].result));
	}
	assert_int_equal(offrec[0].wid, w0);
	assert_int_equal(offrec[1].wid, w1);
	assert_int_equal(pstats(f->h).writes, 2);
	assert_int_equal(pstats(f->h).write_failures, 2);
	assert_int_equal(sth(f->h, 2).state, DF1_STATION_OFFLINE);

	/* queued, then the handle closed: df1_poll refuses, the write waits */
	w2 = queue_write(f->h, x, 502, 2);
	df1_close(f->h);
	assert_int_equal(df1_poll(f->h, 0), DF1_E_NOT_OPEN);
	assert_int_equal(offrec[2].calls, 0);
	assert_int_equal(pstats(f->h).writes_queued, 1);
	/* the station answers again and the handle is reopened: sent once, written */
	sim_restart(f, normal);
	POLL_UNTIL(f, 10000, offrec[2].calls > 0, "the write queued across df1_close");
	assert_int_equal(offrec[2].calls, 1);
	assert_int_equal(offrec[2].result, 0);
	assert_int_equal(offrec[2].wid, w2);
	/* the write's answer is the station's recovery: its tag is read back at once */
	POLL_UNTIL(f, 10000, tagst(f->h, x).quality == DF1_QUALITY_GOOD &&
	           tagst(f->h, x).value.v.i16 == 502, "the value read back");
	assert_int_equal(sth(f->h, 2).state, DF1_STATION_OK);
	/* exactly one write reached the PLC: the two failed ones were not resent */
	assert_int_equal(log_wait(f, "station=2 cmd=0F/AA addr=N7:20", NULL, 1), 1);
	assert_int_equal(log_count(f, "cmd=0F/AA", NULL), 1);

	/* still queued at df1_free(): ends once with DF1_E_NOT_OPEN, never sent */
	w3 = queue_write(f->h, y, 503, 3);
	df1_free(f->h);
	f->h = NULL;
	assert_int_equal(offrec[3].calls, 1);
	assert_int_equal(offrec[3].result, DF1_E_NOT_OPEN);
	assert_int_equal(offrec[3].wid, w3);
	assert_int_equal(log_count(f, "addr=N7:21", "0F/AA"), 0);
	for (int k = 0; k < 3; k++)
		assert_int_equal(offrec[k].calls, 1);
}

/* Full duplex, the port kept open: df1sim's SIGUSR1 silences it, SIGUSR2 brings
 * it back. Two retries, one attempt per scan, offline (BAD) after more than 3
 * failures, one attempt per half watchdog, then recovery with every tag read. */
static void test_silenced_by_signal(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { NULL };
	struct df1_station_health a, b;
	struct df1_tag_state st;
	int64_t t_restore, prev;
	int n, slow;

	sim_start(f, args);
	client_open(f, false, 100, 1, 1);
	assert_int_equal(df1_poll_set_watchdog(f->h, 1000, 3), 0);
	n = add(f->h, "n", 1, "N7:3", 2, 100, DF1_ACCESS_READ);
	slow = add(f->h, "slow", 1, "F8:1", 1, 600000, DF1_ACCESS_READ);
	POLL_UNTIL(f, 10000, all_good(f->h, n, 2), "the first read");
	a = sth(f->h, 1);
	assert_int_equal(kill(f->sim.pid, SIGUSR1), 0);
	/* df1sim takes the signal between two commands: wait for the first failure */
	POLL_UNTIL(f, 10000, sth(f->h, 1).failures > a.failures, "a failure");
	b = sth(f->h, 1);
	assert_int_equal(b.state, DF1_STATION_FAILING);
	assert_int_equal(b.consecutive_failures, 3);            /* the attempt and two retries */
	st = tagst(f->h, n);
	assert_int_equal(st.quality, DF1_QUALITY_UNCERTAIN);
	assert_int_equal(st.values[1].v.i16, 4);
	a = b;
	POLL_UNTIL(f, 10000, sth(f->h, 1).attempts > a.attempts, "the next scan's attempt");
	b = sth(f->h, 1);
	assert_int_equal(b.attempts - a.attempts, 1);
	assert_int_equal(b.state, DF1_STATION_OFFLINE);
	assert_int_equal(tagst(f->h, n).reason, DF1_REASON_STATION_OFFLINE);
	assert_int_equal(tagst(f->h, slow).quality, DF1_QUALITY_BAD);
	prev = b.last_attempt_ms;
	a = b;
	POLL_UNTIL(f, 10000, sth(f->h, 1).attempts > a.attempts, "a slow retry");
	b = sth(f->h, 1);
	assert_int_equal(b.attempts - a.attempts, 1);
	if (b.last_attempt_ms - prev < 500)
		fail_msg("slow retry %lld ms after the previous attempt (half watchdog 500)",
		         (long long)(b.last_attempt_ms - prev));
	assert_int_equal(kill(f->sim.pid, SIGUSR2), 0);
	t_restore = now_ms();
	POLL_UNTIL(f, 10000, sth(f->h, 1).state == DF1_STATION_OK, "station 1 back");
	assert_true(all_good(f->h, n, 2));
	assert_true(tagst(f->h, n).last_good_ms >= t_restore);
	assert_true(tagst(f->h, slow).last_good_ms >= t_restore);   /* the one-time read */
}

static void on_tag_quiet(void *user, int id, const struct df1_tag_state *st)
{
	(void)id;
	(void)st;
	(*(int *)user)++;
}

/* No allocation per scan: once the plan is built, scans of answering, failing,
 * offline (slow retry) stations and a bad tag allocate nothing. */
static void test_scans_allocate_nothing(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--duplex", "half", "--station", "1,2", "--silent", "2", NULL };
	uint64_t s0, attempts0;
	long a0;
	int calls = 0;

	if (!COUNT_ALLOCS)
		skip();
	sim_start(f, args);
	client_open(f, true, 50, 1, 1);
	assert_int_equal(df1_set_tag_callback(f->h, on_tag_quiet, &calls), 0);
	assert_int_equal(df1_poll_set_watchdog(f->h, 400, 1), 0);  /* slow retry every 200 ms */
	add(f->h, "n", 1, "N7:0", 10, 0, DF1_ACCESS_READ);
	add(f->h, "b", 1, "B3:0/4", 3, 0, DF1_ACCESS_READ);
	add(f->h, "t", 1, "T4:0.ACC", 2, 0, DF1_ACCESS_READ);
	add(f->h, "f", 1, "F8:2", 1, 0, DF1_ACCESS_READ);
	add(f->h, "bad", 1, "N7:300", 1, 0, DF1_ACCESS_READ);
	add(f->h, "io", 1, "I1:0.1", 1, 0, DF1_ACCESS_READ);
	add(f->h, "gone", 2, "N7:0", 1, 0, DF1_ACCESS_READ);
	/* warm up: the plan, the split and re-plan around the bad tag, station 2 offline */
	POLL_UNTIL(f, 10000, sth(f->h, 2).state == DF1_STATION_OFFLINE && pstats(f->h).scans >= 3,
	           "station 2 offline");
	one_scan(f);
	s0 = pstats(f->h).scans;
	attempts0 = sth(f->h, 2).attempts;
	a0 = atomic_load(&allocs);
	POLL_UNTIL(f, 10000, pstats(f->h).scans >= s0 + 20 && sth(f->h, 2).attempts >= attempts0 + 2,
	           "20 scans and two slow retries");
	if (atomic_load(&allocs) != a0)
		fail_msg("%ld allocations in %llu scans", atomic_load(&allocs) - a0,
		         (unsigned long long)(pstats(f->h).scans - s0));
	assert_true(calls > 0);
}

static void test_discovery(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--duplex", "half", "--station", "1,3,5", NULL };
	int64_t dl;
	int id;

	sim_start(f, args);
	client_open(f, true, 100, 1, 1);
	id = add(f->h, "s1", 1, "N7:0", 1, 100, DF1_ACCESS_READ);
	assert_int_equal(df1_poll_set_station_range(f->h, 1, 6), 0);
	dl = now_ms() + 30000;
	while (sth(f->h, 3).state != DF1_STATION_OK || sth(f->h, 5).state != DF1_STATION_OK) {
		struct df1_poll_stats a = pstats(f->h), b;
		int present = (sth(f->h, 3).state == DF1_STATION_OK) + (sth(f->h, 5).state == DF1_STATION_OK);

		if (now_ms() > dl)
			fail_msg("stations 3 and 5 not found");
		poll_ok(f, 100);
		b = pstats(f->h);
		/* a scan probes the stations found so far and at most one other address */
		assert_true(b.probes - a.probes <= 3 * (uint64_t)present + 1);
	}
	assert_int_equal(sth(f->h, 2).state, DF1_STATION_ABSENT);
	assert_int_equal(sth(f->h, 4).state, DF1_STATION_ABSENT);
	assert_int_equal(sth(f->h, 3).tags, 0);
	assert_int_equal(tagst(f->h, id).quality, DF1_QUALITY_GOOD);
	assert_int_equal(sth(f->h, 1).consecutive_failures, 0);
}

/* df1_poll_station(), deprecated since 0.2, still links and answers as
 * df1_station_health() does. */
static void test_api_station_health_alias(void **state)
{
	struct df1_station_health a, b;
	df1_t *h;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_station_health(h, 3, &a), 0);
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
	assert_int_equal(df1_poll_station(h, 3, &b), 0);
	assert_int_equal(df1_poll_station(h, 255, &b), DF1_E_INVAL);
	assert_int_equal(df1_poll_station(NULL, 3, &b), DF1_E_INVAL);
#pragma GCC diagnostic pop
	assert_int_equal(df1_station_health(h, 3, &b), 0);
	assert_memory_equal(&a, &b, sizeof a);
	assert_int_equal(a.station, 3);
	assert_int_equal(a.state, DF1_STATION_UNKNOWN);
	assert_int_equal(df1_station_health(h, 255, &b), DF1_E_INVAL);
	assert_int_equal(df1_station_health(h, 3, NULL), DF1_E_INVAL);
	df1_free(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_plan_contiguous_one_block),
		cmocka_unit_test(test_plan_gap_rule),
		cmocka_unit_test(test_plan_packet_limits),
		cmocka_unit_test(test_plan_keys_and_alone),
		cmocka_unit_test(test_plan_greedy_is_minimal),
		cmocka_unit_test(test_api_tags),
		cmocka_unit_test(test_api_load_map),
		cmocka_unit_test(test_api_load_map_40000_tags),
		cmocka_unit_test(test_api_station_health_alias),
		cmocka_unit_test_setup_teardown(test_coalesce_two_files, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_coalesce_slc502_limit, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_coalesce_plc5_station_order, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_plc5_typed_float_swapped_block, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_bad_tag_isolated, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_station_silenced_and_restored, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_watchdog_time, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_silenced_by_signal, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_writes_under_faults_exactly_once, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_write_wakes_poll, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_writes_offline_close_free, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_change_callback, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_scans_allocate_nothing, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_discovery, fix_setup, fix_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
