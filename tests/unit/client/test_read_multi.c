/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_read_multi - df1_read_multi(): the planner's fewest-transactions rule
 * (pure), the argument checks, and reads against df1sim as a separate process
 * (tests/support/simproc.c) over a pseudo-terminal, transactions counted in df1sim's
 * --log (one line per command it answered). Expectations come from the spec's
 * packet limits (doc/PROTOCOL.md 6: SLC 5/03+ 236 data bytes a read = 118
 * words, SLC 5/01-5/02 82 bytes = 41 words) and df1sim's documented initial
 * data table (df1sim(1): N n = n, F n = n + 0.5, T/C PRE 100, 256 elements a
 * file), not from the library's own tables.
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
#include <unistd.h>

#include "df1.h"
#include "proto/plc_limits.h"
#include "client/block_plan.h"
#include "support/simproc.h"

/* ------------------------------------------------------------------------
 * The planner's fewest-transactions rule (pure)
 * ------------------------------------------------------------------------ */

static struct poll_item item(enum df1_plc plc, enum df1_file_type t, int file, int first, int count,
                             int tag)
{
	struct poll_item it;

	memset(&it, 0, sizeof it);
	it.station = 1;
	it.plc = plc;
	it.type = t;
	it.file = file;
	it.first = first;
	it.count = count;
	it.cost = df1_file_type_element_size(t);
	it.limit = plc_read_limit(plc, t, (size_t)it.cost, file, first, 0);
	it.tag = tag;
	return it;
}

static void test_plan_fewest_tx(void **state)
{
	struct poll_item it[4];
	struct poll_block b[4];

	(void)state;
	/* a gap far wider than a transaction's overhead is read through when the
	 * joined block still fits one 236-byte packet (118 words) */
	it[0] = item(DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(DF1_PLC_SLC, DF1_FT_N, 7, 117, 1, 1);
	assert_int_equal(poll_plan(it, 2, POLL_GAP_FEWEST_TX, b, 4), 1);
	assert_int_equal(b[0].count, 118);
	/* the poll engine's rule does not bridge it */
	it[0] = item(DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(DF1_PLC_SLC, DF1_FT_N, 7, 117, 1, 1);
	assert_int_equal(poll_plan(it, 2, POLL_TX_OVERHEAD_FULL, b, 4), 2);
	/* one word more and the joined block takes two packets: no saving */
	it[0] = item(DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(DF1_PLC_SLC, DF1_FT_N, 7, 118, 1, 1);
	assert_int_equal(poll_plan(it, 2, POLL_GAP_FEWEST_TX, b, 4), 2);
	/* ranges that touch are one block even when it takes more packets */
	it[0] = item(DF1_PLC_SLC, DF1_FT_N, 7, 0, 118, 0);
	it[1] = item(DF1_PLC_SLC, DF1_FT_N, 7, 118, 1, 1);
	assert_int_equal(poll_plan(it, 2, POLL_GAP_FEWEST_TX, b, 4), 1);
	assert_int_equal(poll_block_packets(&b[0], it), 2);
	/* 1 + 2 packets apart, 2 joined: the gap is read through */
	it[0] = item(DF1_PLC_SLC, DF1_FT_N, 7, 0, 100, 0);
	it[1] = item(DF1_PLC_SLC, DF1_FT_N, 7, 102, 120, 1);
	assert_int_equal(poll_plan(it, 2, POLL_GAP_FEWEST_TX, b, 4), 1);
	assert_int_equal(poll_block_packets(&b[0], it), 2);
	/* SLC 5/02: 41 words a packet */
	it[0] = item(DF1_PLC_SLC502, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(DF1_PLC_SLC502, DF1_FT_N, 7, 40, 1, 1);
	it[2] = item(DF1_PLC_SLC502, DF1_FT_N, 7, 41, 1, 2);
	assert_int_equal(poll_plan(it, 3, POLL_GAP_FEWEST_TX, b, 4), 1);    /* touching: joined */
	assert_int_equal(poll_block_packets(&b[0], it), 2);
	/* PLC-5: ranges that touch are joined, gaps never (POLL_GAP_TOUCH_ONLY) */
	it[0] = item(DF1_PLC_PLC5, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(DF1_PLC_PLC5, DF1_FT_N, 7, 1, 1, 1);
	it[2] = item(DF1_PLC_PLC5, DF1_FT_N, 7, 3, 1, 2);
	assert_int_equal(poll_plan(it, 3, POLL_GAP_TOUCH_ONLY, b, 4), 2);
	assert_int_equal(b[0].count, 2);
	/* other files and file types are never joined */
	it[0] = item(DF1_PLC_SLC, DF1_FT_N, 7, 0, 1, 0);
	it[1] = item(DF1_PLC_SLC, DF1_FT_N, 10, 1, 1, 1);
	it[2] = item(DF1_PLC_SLC, DF1_FT_B, 7, 2, 1, 2);
	assert_int_equal(poll_plan(it, 3, POLL_GAP_FEWEST_TX, b, 4), 3);
}

/* Packets count whole elements, as the client splits: an 84-byte string goes
 * two to a 236-byte packet, so five take three packets (not 420 / 236 = 2). */
static void test_plan_packets_whole_elements(void **state)
{
	struct poll_item it[1];
	struct poll_block b[1];

	(void)state;
	it[0] = item(DF1_PLC_SLC, DF1_FT_ST, 9, 0, 5, 0);
	assert_int_equal(poll_plan(it, 1, POLL_GAP_FEWEST_TX, b, 1), 1);
	assert_int_equal(poll_block_packets(&b[0], it), 3);
	/* timers: 6 bytes, 39 to a packet */
	it[0] = item(DF1_PLC_SLC, DF1_FT_T, 4, 0, 40, 0);
	assert_int_equal(poll_plan(it, 1, POLL_GAP_FEWEST_TX, b, 1), 1);
	assert_int_equal(poll_block_packets(&b[0], it), 2);
}

/* The table as doc/PROTOCOL.md 6 gives it. */
static void test_packet_max(void **state)
{
	(void)state;
	assert_int_equal(df1_packet_max(DF1_PLC_SLC, false), 236);
	assert_int_equal(df1_packet_max(DF1_PLC_SLC, true), 234);
	assert_int_equal(df1_packet_max(DF1_PLC_MICROLOGIX, false), 236);
	assert_int_equal(df1_packet_max(DF1_PLC_MICROLOGIX, true), 234);
	assert_int_equal(df1_packet_max(DF1_PLC_SLC502, false), 82);
	assert_int_equal(df1_packet_max(DF1_PLC_SLC502, true), 82);
	assert_int_equal(df1_packet_max(DF1_PLC_PLC2, false), 244);
	assert_int_equal(df1_packet_max(DF1_PLC_PLC2, true), 244);
	assert_int_equal(df1_packet_max(DF1_PLC_PLC5, false), 240);
	assert_int_equal(df1_packet_max(DF1_PLC_PLC5, true), 240);
	/* PLC-3 (doc/PROTOCOL.md 4.2a): 244 a read, 239 less the longest address a write */
	assert_int_equal(df1_packet_max(DF1_PLC_PLC3, false), 244);
	assert_int_equal(df1_packet_max(DF1_PLC_PLC3, true), 228);
	assert_int_equal(df1_packet_max((enum df1_plc)6, false), DF1_E_INVAL);
	assert_int_equal(df1_packet_max((enum df1_plc)-1, true), DF1_E_INVAL);
}

/* ------------------------------------------------------------------------
 * Arguments (no I/O)
 * ------------------------------------------------------------------------ */

/* Elements per packet, each command at its limit and one past it (doc/PROTOCOL.md 6,
 * worked out as in test_client's boundaries): SLC A2 236 / AA 234 data bytes,
 * SLC 5/02 82, PLC-2 244; PLC-5 typed address + 99 09 LL + descriptor + data
 * <= 240, the address 3 bytes for N7:0 (06 07 00), 5 for N7:300, 7 for the
 * logical ASCII $N7:0 (00 24 4E 37 3A 30 00). */
static void test_per_packet(void **state)
{
	static const struct {
		enum df1_plc plc;
		bool write;
		enum df1_file_type t;
		size_t esize, alen, want;
	} c[] = {
		{ DF1_PLC_SLC, false, DF1_FT_N, 2, 0, 118 },
		{ DF1_PLC_SLC, true, DF1_FT_N, 2, 0, 117 },
		{ DF1_PLC_SLC, false, DF1_FT_F, 4, 0, 59 },
		{ DF1_PLC_SLC, true, DF1_FT_F, 4, 0, 58 },
		{ DF1_PLC_SLC, false, DF1_FT_T, 6, 0, 39 },
		{ DF1_PLC_SLC, true, DF1_FT_T, 6, 0, 39 },
		{ DF1_PLC_SLC, false, DF1_FT_ST, 84, 0, 2 },
		{ DF1_PLC_MICROLOGIX, false, DF1_FT_L, 4, 0, 59 },
		{ DF1_PLC_MICROLOGIX, true, DF1_FT_L, 4, 0, 58 },
		{ DF1_PLC_SLC502, false, DF1_FT_N, 2, 0, 41 },
		{ DF1_PLC_SLC502, true, DF1_FT_T, 6, 0, 13 },
		{ DF1_PLC_SLC502, false, DF1_FT_ST, 84, 0, 0 },
		{ DF1_PLC_PLC2, false, DF1_FT_N, 2, 0, 122 },
		{ DF1_PLC_PLC2, true, DF1_FT_N, 2, 0, 122 },
		{ DF1_PLC_PLC5, false, DF1_FT_N, 2, 3, 116 },   /* 3 + 4 + 232 = 239 */
		{ DF1_PLC_PLC5, true, DF1_FT_N, 2, 3, 116 },
		{ DF1_PLC_PLC5, false, DF1_FT_N, 2, 5, 115 },   /* 5 + 4 + 230 = 239 */
		{ DF1_PLC_PLC5, false, DF1_FT_N, 2, 7, 114 },   /* 7 + 4 + 228 = 239 */
		{ DF1_PLC_PLC5, false, DF1_FT_B, 2, 3, 116 },
		{ DF1_PLC_PLC5, false, DF1_FT_F, 4, 3, 58 },    /* 3 + 5 + 232 = 240 */
		{ DF1_PLC_PLC5, true, DF1_FT_F, 4, 3, 58 },
		{ DF1_PLC_PLC5, false, DF1_FT_F, 4, 5, 57 },    /* 5 + 5 + 228 = 238 */
		{ DF1_PLC_PLC5, false, DF1_FT_L, 4, 3, 58 },    /* 3 + 4 + 232 = 239 */
		{ DF1_PLC_PLC5, false, DF1_FT_T, 6, 3, 38 },    /* 3 + 4 + 228 = 235 */
		{ DF1_PLC_PLC5, true, DF1_FT_C, 6, 3, 38 },
		{ DF1_PLC_PLC5, false, DF1_FT_R, 6, 5, 38 },    /* 5 + 4 + 228 = 237 */
		{ DF1_PLC_PLC5, false, DF1_FT_ST, 84, 3, 1 },
		{ DF1_PLC_PLC5, true, DF1_FT_ST, 84, 3, 1 },
	};

	(void)state;
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		size_t got = plc_per_packet(c[i].plc, c[i].write, c[i].t, c[i].esize, c[i].alen, 0);

		if (got != c[i].want)
			fail_msg("case %zu: %zu per packet, want %zu", i, got, c[i].want);
	}
	/* the responder's cut of a typed reply is the same rule */
	assert_int_equal(plc5_typed_per_packet(3, plc5_td_type(DF1_FT_N, 2), 2), 116);
	assert_int_equal(plc5_typed_per_packet(3, plc5_td_type(DF1_FT_F, 4), 4), 58);
	assert_int_equal(plc5_typed_per_packet(3, plc5_td_type(DF1_FT_T, 6), 6), 38);
	/* the planner's limit: whole elements from the block's first element */
	assert_int_equal(plc_read_limit(DF1_PLC_PLC5, DF1_FT_N, 2, 7, 0, 0), 232);
	assert_int_equal(plc_read_limit(DF1_PLC_PLC5, DF1_FT_N, 2, 7, 300, 0), 230);
	assert_int_equal(plc_read_limit(DF1_PLC_PLC5, DF1_FT_F, 4, 8, 0, 0), 232);
	assert_int_equal(plc_read_limit(DF1_PLC_SLC, DF1_FT_T, 6, 4, 0, 0), 234);
	/* DF1_OPT_MAX_PACKET: that many bytes of element data */
	assert_int_equal(plc_per_packet(DF1_PLC_PLC5, false, DF1_FT_N, 2, 3, 20), 10);
	assert_int_equal(plc_per_packet(DF1_PLC_SLC, false, DF1_FT_N, 2, 0, 20), 10);
}

static void test_args(void **state)
{
	df1_t *h;
	struct df1_value v[2];
	struct df1_read_req r[2];
	unsigned reads = 99;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	memset(r, 0, sizeof r);
	r[0].text = "N7:0";
	r[0].count = 1;
	r[0].values = &v[0];
	assert_int_equal(df1_read_multi(NULL, 1, r, 1, 0, &reads), DF1_E_INVAL);
	assert_int_equal(reads, 0);
	assert_int_equal(df1_read_multi(h, 1, NULL, 1, 0, NULL), DF1_E_INVAL);
	assert_int_equal(df1_read_multi(h, 1, r, 0, 0, NULL), DF1_E_INVAL);
	assert_int_equal(df1_read_multi(h, 255, r, 1, 0, NULL), DF1_E_INVAL);
	assert_int_equal(df1_read_multi(h, 1, r, 1, 0x80, NULL), DF1_E_INVAL);
	/* a bad request with DF1_READ_MULTI_STOP: nothing is sent (the handle is
	 * not even open), its own result and the detail name it */
	r[1].text = "N7:x";
	r[1].count = 1;
	r[1].values = &v[1];
	assert_int_equal(df1_read_multi(h, 1, r, 2, DF1_READ_MULTI_STOP, &reads), DF1_E_ADDR_SYNTAX);
	assert_int_equal(reads, 0);
	assert_int_equal(r[0].result, 0);
	assert_int_equal(r[1].result, DF1_E_ADDR_SYNTAX);
	assert_string_equal(df1_last_error(h)->address, "N7:x");
	assert_int_equal(df1_last_error(h)->code, DF1_E_ADDR_SYNTAX);
	/* no buffer, count 0 */
	r[1].text = "N7:1";
	r[1].values = NULL;
	assert_int_equal(df1_read_multi(h, 1, r, 2, DF1_READ_MULTI_STOP, NULL), DF1_E_INVAL);
	assert_int_equal(r[1].result, DF1_E_INVAL);
	r[1].values = &v[1];
	r[1].count = 0;
	assert_int_equal(df1_read_multi(h, 1, r, 2, DF1_READ_MULTI_STOP, NULL), DF1_E_INVAL);
	/* without the flag the good request is tried: not open */
	assert_int_equal(df1_read_multi(h, 1, r, 2, 0, &reads), DF1_E_INVAL);
	assert_int_equal(r[0].result, DF1_E_NOT_OPEN);
	assert_int_equal(reads, 1);
	df1_free(h);
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

static void start_data(struct fix *f, const char *data, const char *const *args,
                       enum df1_plc plc, bool half)
{
	if (simproc_start(&f->sim, false, data, true, args) != 0)
		fail_msg("df1sim did not start");
	assert_int_equal(df1_new(&f->h), 0);
	assert_int_equal(df1_set_plc(f->h, plc), 0);
	assert_int_equal(df1_set_timeout_ms(f->h, 300), 0);
	assert_int_equal(df1_set_retries(f->h, 1, 1), 0);
	if (half)
		assert_int_equal(df1_set_duplex(f->h, DF1_HALF_DUPLEX_MASTER), 0);
	if (df1_open(f->h, f->sim.target) < 0)
		fail_msg("df1_open %s: %s", f->sim.target, df1_last_error(f->h)->message);
}

static void start_as(struct fix *f, const char *const *args, enum df1_plc plc, bool half)
{
	start_data(f, NULL, args, plc, half);
}

static void start(struct fix *f, const char *const *args, enum df1_plc plc)
{
	start_as(f, args, plc, false);
}

static int log_count(struct fix *f, const char *needle)
{
	int n = simproc_log_count(&f->sim, needle, NULL);

	return n < 0 ? 0 : n;
}

static int log_wait(struct fix *f, int want)
{
	return simproc_log_wait(&f->sim, NULL, NULL, want, 5000);
}

#define NSCAT 30

/* 30 scattered words N7:0, N7:8, ... N7:232: one per address would be 30
 * transactions; they span 233 words = 466 bytes, two 236-byte packets. */
static void test_thirty_scattered(void **state)
{
	struct fix *f = *state;
	struct df1_value v[NSCAT];
	struct df1_read_req r[NSCAT];
	char text[NSCAT][16];
	unsigned reads;
	int before;

	start(f, NULL, DF1_PLC_SLC);
	memset(r, 0, sizeof r);
	for (int i = 0; i < NSCAT; i++) {
		snprintf(text[i], sizeof text[i], "N7:%d", i * 8);
		r[i].text = text[i];
		r[i].count = 1;
		r[i].values = &v[i];
	}
	assert_int_equal(df1_read_multi(f->h, 1, r, NSCAT, 0, &reads), NSCAT);
	/* N7:0..112 and N7:120..232, one packet each: joining them would still
	 * take two */
	assert_int_equal(reads, 2);
	for (int i = 0; i < NSCAT; i++) {
		assert_int_equal(r[i].result, 1);
		assert_int_equal(v[i].kind, DF1_VAL_INT16);
		assert_int_equal(v[i].v.i16, i * 8);
	}
	assert_int_equal(log_wait(f, 2), 2);
	assert_int_equal(log_count(f, "addr=N7:0 "), 1);
	/* the same addresses one by one: 30 */
	before = log_count(f, NULL);
	for (int i = 0; i < NSCAT; i++)
		assert_int_equal(df1_read(f->h, 1, text[i], &v[i], 1), 1);
	assert_int_equal(log_wait(f, before + NSCAT), before + NSCAT);
}

/* Words, floats, bits of words, T/C/R words and bits out of their blocks:
 * the values equal df1_read's of each address; N7, F8, B3 and T4 take one
 * transaction each, the I/O word is read on its own. */
static void test_mixed_values(void **state)
{
	struct fix *f = *state;
	static const char *const addr[] = {
		"N7:3", "F8:2", "N7:1/1", "B3/21", "T4:1.PRE", "T4:1/DN", "N7:0,3", "F8:0,2",
		"B3:0/14,4", "T4:0", "S:1/5", "C5:0.PRE",
	};
	enum { N = sizeof addr / sizeof addr[0] };
	struct df1_value v[N][4], w[4];
	struct df1_read_req r[N];
	unsigned reads;

	start(f, NULL, DF1_PLC_SLC);
	memset(r, 0, sizeof r);
	for (int i = 0; i < N; i++) {
		const char *comma = strchr(addr[i], ',');
		static char buf[N][16];

		snprintf(buf[i], sizeof buf[i], "%.*s", comma ? (int)(comma - addr[i]) : 15, addr[i]);
		r[i].text = buf[i];
		r[i].count = comma ? (size_t)atoi(comma + 1) : 1;
		r[i].values = v[i];
	}
	assert_int_equal(df1_read_multi(f->h, 1, r, N, 0, &reads), N);
	/* N7, F8, B3, T4, S, C5: one block each */
	assert_int_equal(reads, 6);
	assert_int_equal(log_wait(f, 6), 6);
	for (int i = 0; i < N; i++) {
		assert_int_equal(r[i].result, (int)r[i].count);
		memset(w, 0, sizeof w);
		assert_int_equal(df1_read(f->h, 1, r[i].text, w, r[i].count), (int)r[i].count);
		for (size_t k = 0; k < r[i].count; k++) {
			char a[100], b[100];

			assert_true(df1_value_format(&v[i][k], r[i].addr.type, a, sizeof a) >= 0);
			assert_true(df1_value_format(&w[k], r[i].addr.type, b, sizeof b) >= 0);
			if (strcmp(a, b) != 0)
				fail_msg("%s value %zu: %s, df1_read: %s", r[i].text, k, a, b);
		}
	}
	/* df1sim's table, independently: N7:3 = 3, F8:2 = 2.5, T4:1.PRE = 100 */
	assert_int_equal(v[0][0].v.i16, 3);
	assert_true(v[1][0].v.f == 2.5f);
	assert_int_equal(v[4][0].v.i16, 100);
	assert_int_equal(v[2][0].kind, DF1_VAL_BIT);
	assert_int_equal(v[2][0].v.bit, 0);     /* N7:1 = 1: bit 1 clear */
}

/* A block the PLC refuses is read again request by request: the bad address
 * gets its own error, its neighbours their values. df1sim's N7 has 256
 * elements: N7:250,5 and N7:256 touch (one block), N7:256 does not exist. */
static void test_bad_address_keeps_others(void **state)
{
	struct fix *f = *state;
	struct df1_value a[5], b, c, d;
	struct df1_read_req r[4];
	unsigned reads;

	start(f, NULL, DF1_PLC_SLC);
	memset(r, 0, sizeof r);
	r[0] = (struct df1_read_req){ .text = "N7:250", .count = 5, .values = a };
	r[1] = (struct df1_read_req){ .text = "N7:256", .count = 1, .values = &b };
	r[2] = (struct df1_read_req){ .text = "N20:0", .count = 1, .values = &c };
	r[3] = (struct df1_read_req){ .text = "F8:1", .count = 1, .values = &d };
	assert_int_equal(df1_read_multi(f->h, 1, r, 4, 0, &reads), DF1_E_REMOTE);
	/* blocks N7:250..256 (refused, then 2 alone), N20:0 (refused), F8:1 */
	assert_int_equal(reads, 5);
	assert_int_equal(r[0].result, 5);
	for (int i = 0; i < 5; i++)
		assert_int_equal(a[i].v.i16, 250 + i);
	assert_int_equal(r[1].result, DF1_E_REMOTE);
	assert_int_equal(r[2].result, DF1_E_REMOTE);
	assert_int_equal(r[3].result, 1);
	assert_true(d.v.f == 1.5f);
	/* the first failure in reading order, named by its request */
	assert_string_equal(df1_last_error(f->h)->address, "N7:256");
	assert_int_equal(df1_last_error(f->h)->code, DF1_E_REMOTE);
	assert_null(strstr(df1_last_error(f->h)->message, "N7:"));
	assert_int_equal(log_wait(f, 5), 5);

	/* all or nothing: the call stops at the first failure */
	memset(&d, 0, sizeof d);
	assert_int_equal(df1_read_multi(f->h, 1, r, 4, DF1_READ_MULTI_STOP, &reads), DF1_E_REMOTE);
	assert_int_equal(r[0].result, 5);
	assert_int_equal(r[1].result, DF1_E_REMOTE);
	assert_int_equal(r[2].result, 0);
	assert_int_equal(r[3].result, 0);
	assert_int_equal(reads, 3);
	assert_string_equal(df1_last_error(f->h)->address, "N7:256");
}

/* SLC 5/02: 82 bytes = 41 words a packet; 30 words spread over N7:0..N7:87
 * (88 words) take three packets. */
static void test_slc502_limit(void **state)
{
	struct fix *f = *state;
	static const char *const args[] = { "--plc", "slc502", NULL };
	struct df1_value v[NSCAT];
	struct df1_read_req r[NSCAT];
	char text[NSCAT][16];
	unsigned reads;

	start(f, args, DF1_PLC_SLC502);
	memset(r, 0, sizeof r);
	for (int i = 0; i < NSCAT; i++) {
		snprintf(text[i], sizeof text[i], "N7:%d", i * 3);
		r[i].text = text[i];
		r[i].count = 1;
		r[i].values = &v[i];
	}
	assert_int_equal(df1_read_multi(f->h, 1, r, NSCAT, 0, &reads), NSCAT);
	for (int i = 0; i < NSCAT; i++)
		assert_int_equal(v[i].v.i16, i * 3);
	assert_int_equal(log_wait(f, 3), 3);
	assert_int_equal(log_count(f, NULL), 3);
}

/* PLC-5 typed packets (doc/PROTOCOL.md 6: address + type/data + data <= 240 bytes; doc/PROTOCOL.md
 * 4.1 address N7:0 = 06 07 00, N7:300 = 06 07 FF 2C 01; doc/PROTOCOL.md 4.3 type/data
 * 99 09 LL + descriptor 42 / 44 / 56 / 66 / 76 (1 byte) or 94 08 (float)):
 * the largest count goes in one 0F/68 or 0F/67, one more in two, counted
 * in df1sim's frame log; the values read are df1sim's initial ones. */
/* PLC-5 timers in the 5-word form of KF2 p.130 (df1sim's default for --plc plc5:
 * type/data 99 09 LL 59 0A, doc/PROTOCOL.md 4.3): 3 + 5 + 10 * 23 = 238 <= 240, 24: 248.
 * A client told so (DF1_OPT_PLC5_TIMER_WORDS 5) asks for 23 and 24 goes in two; one
 * that plans 3-word timers asks for 38, takes the full reply of 23 and asks for the
 * other 15; either way every member is df1sim's, counted in its frame log. */
static void test_plc5_timer_words_5_packets(void **state)
{
	static const char *const args[] = { "--plc", "plc5", NULL };
	struct fix *f = *state;
	static struct df1_tcr t[40];
	int seen = 0;

	start_data(f, "T4:22=PRE=122 ACC=22 DN=1\nT4:23=PRE=123 ACC=23 EN=1\nT4:37=PRE=137 ACC=37 TT=1\n",
	           args, DF1_PLC_PLC5, false);
	assert_int_equal(df1_set_option(f->h, DF1_OPT_PLC5_TIMER_WORDS, 5), 0);
	assert_int_equal(df1_read_tcr(f->h, 1, "T4:0", t, 23), 23);
	seen++;
	assert_int_equal(log_wait(f, seen), seen);
	assert_int_equal(log_count(f, "addr=T4:0 count=23 "), 1);
	assert_int_equal(t[22].pre, 122);
	assert_int_equal(t[22].acc, 22);
	assert_int_equal(t[22].ctl, 0x2000);
	assert_int_equal(df1_read_tcr(f->h, 1, "T4:0", t, 24), 24);
	seen += 2;
	assert_int_equal(log_wait(f, seen), seen);
	/* the log names each packet by the start address and its own count */
	assert_int_equal(log_count(f, "addr=T4:0 count=23 "), 2);
	assert_int_equal(log_count(f, "addr=T4:0 count=1 "), 1);
	assert_int_equal(t[23].pre, 123);
	assert_int_equal(t[23].ctl, 0x8000);
	/* planned as 3-word timers: 38 asked, 23 come, the next packet asks for 15 */
	assert_int_equal(df1_set_option(f->h, DF1_OPT_PLC5_TIMER_WORDS, 3), 0);
	memset(t, 0, sizeof t);
	assert_int_equal(df1_read_tcr(f->h, 1, "T4:0", t, 38), 38);
	seen += 2;
	assert_int_equal(log_wait(f, seen), seen);
	assert_int_equal(log_count(f, "addr=T4:0 count=38 "), 1);
	assert_int_equal(log_count(f, "addr=T4:0 count=15 "), 1);
	assert_int_equal(log_count(f, NULL), seen);
	assert_int_equal(t[22].acc, 22);
	assert_int_equal(t[23].acc, 23);
	assert_int_equal(t[37].pre, 137);
	assert_int_equal(t[37].ctl, 0x4000);
	assert_int_equal(t[36].pre, 100);   /* df1sim's initial timers: PRE 100 */
}

static void test_plc5_packet_boundaries(void **state)
{
	/* the data-table form of T/C/R (3 words); the 5-word timers: below */
	static const char *const args[] = { "--plc", "plc5", "--plc5-timer-words", "3", NULL };
	static const struct { const char *addr; int max; } c[] = {
		{ "N7:0", 116 },        /* 3 + 4 + 2 * 116 = 239 */
		{ "N7:130", 116 },
		{ "F8:0", 58 },         /* 3 + 5 + 4 * 58 = 240 */
		{ "L10:0", 58 },        /* 3 + 4 + 4 * 58 = 239 */
		{ "T4:0", 38 },         /* 3 + 4 + 6 * 38 = 235; 39: 241 */
		{ "C5:0", 38 },
		{ "R6:0", 38 },
	};
	struct fix *f = *state;
	static struct df1_value v[128];
	struct df1_read_req r[2];
	unsigned reads;
	int seen = 0, nr = 0, nw = 0;

	start_data(f, "N7:499=499\n", args, DF1_PLC_PLC5, false);      /* N7: 500 elements */
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		for (int extra = 0; extra < 2; extra++) {
			int n = c[i].max + extra;

			assert_int_equal(df1_read(f->h, 1, c[i].addr, v, (size_t)n), n);
			seen += 1 + extra;
			nr += 1 + extra;
			assert_int_equal(log_wait(f, seen), seen);
			if (log_count(f, "cmd=0F/68") != nr)
				fail_msg("read %s x %d: %d reads logged, want %d in all", c[i].addr, n,
				         log_count(f, "cmd=0F/68"), nr);
			if (!strcmp(c[i].addr, "N7:0"))
				for (int k = 0; k < n; k++)
					assert_int_equal(v[k].v.i16, k);
			if (!strcmp(c[i].addr, "F8:0"))
				for (int k = 0; k < n; k++)
					assert_true(v[k].v.f == (float)k + 0.5f);
			assert_int_equal(df1_write(f->h, 1, c[i].addr, v, (size_t)n), n);
			seen += 1 + extra;
			nw += 1 + extra;
			assert_int_equal(log_wait(f, seen), seen);
			if (log_count(f, "cmd=0F/67") != nw)
				fail_msg("write %s x %d: %d writes logged, want %d in all", c[i].addr, n,
				         log_count(f, "cmd=0F/67"), nw);
		}
	}
	/* N7:300: a 5-byte address (06 07 FF 2C 01), 5 + 4 + 2 * 115 = 239; 116: 241 */
	assert_int_equal(df1_read(f->h, 1, "N7:300", v, 115), 115);
	assert_int_equal(v[0].v.i16, 300);
	assert_int_equal(v[114].v.i16, 414);
	assert_int_equal(df1_read(f->h, 1, "N7:300", v, 116), 116);
	seen += 3;
	assert_int_equal(log_wait(f, seen), seen);
	assert_int_equal(log_count(f, NULL), seen);
	assert_int_equal(log_count(f, "addr=N7:300 count=115"), 2);
	/* df1_read_multi: N7:0 x 60 and N7:60 x 56 touch, one block, one packet */
	memset(r, 0, sizeof r);
	r[0].text = "N7:0";
	r[0].count = 60;
	r[0].values = v;
	r[1].text = "N7:60";
	r[1].count = 56;
	r[1].values = v + 60;
	assert_int_equal(df1_read_multi(f->h, 1, r, 2, 0, &reads), 2);
	assert_int_equal(reads, 1);
	seen++;
	assert_int_equal(log_wait(f, seen), seen);
	assert_int_equal(log_count(f, NULL), seen);
	/* the reads of 116 and 117 and this one */
	assert_int_equal(log_count(f, "cmd=0F/68 addr=N7:0 count=116"), 3);
}

/* No answer ends the call: the requests not read keep result 0; station 1
 * still answers the same call. */
static void test_no_answer_ends_call(void **state)
{
	struct fix *f = *state;
	struct df1_value a, b;
	struct df1_read_req r[2];
	static const char *const args[] = { "--duplex", "half", "--station", "1", NULL };
	unsigned reads;
	int rc;

	start_as(f, args, DF1_PLC_SLC, true);
	memset(r, 0, sizeof r);
	r[0] = (struct df1_read_req){ .text = "N7:0", .count = 1, .values = &a };
	r[1] = (struct df1_read_req){ .text = "F8:0", .count = 1, .values = &b };
	/* half duplex, station 9 is not served: no answer to the polls */
	rc = df1_read_multi(f->h, 9, r, 2, 0, &reads);
	print_message("station 9: %s\n", df1_errname(rc));
	assert_true(rc < 0 && rc != DF1_E_REMOTE);
	assert_int_equal(reads, 1);
	assert_int_equal(r[0].result, rc);
	assert_int_equal(r[1].result, 0);
	assert_string_equal(df1_last_error(f->h)->address, "N7:0");
	assert_int_equal(df1_last_error(f->h)->station, 9);
	assert_int_equal(df1_read_multi(f->h, 1, r, 2, 0, &reads), 2);
	assert_int_equal(a.v.i16, 0);
	assert_true(b.v.f == 0.5f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_plan_fewest_tx),
		cmocka_unit_test(test_plan_packets_whole_elements),
		cmocka_unit_test(test_packet_max),
		cmocka_unit_test(test_per_packet),
		cmocka_unit_test(test_args),
		cmocka_unit_test_setup_teardown(test_thirty_scattered, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_mixed_values, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_bad_address_keeps_others, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_slc502_limit, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_plc5_packet_boundaries, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_plc5_timer_words_5_packets, fix_setup, fix_teardown),
		cmocka_unit_test_setup_teardown(test_no_answer_ends_call, fix_setup, fix_teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
