/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_integration - the public API against df1sim running as a separate
 * process (tests/support/simproc.c), over real pseudo-terminals (df1_open on the pty
 * path: the termios backend) and over TCP (df1sim --listen).
 *
 * Covered: full and half duplex, CRC and BCC, one and several stations; every
 * data type (N incl. negatives, L, F, ST, B bits, T/C/R whole and .PRE/.ACC,
 * /DN, the word files O I S A); element and file numbers above 254; requests
 * larger than one packet, compared with df1sim's documented initial data table
 * (df1sim(1), DATA TABLE: N n = n, F n = n + 0.5, L n = n * 65537, ST n =
 * "STRING n", T/C PRE 100, the rest 0) plus the --data file below; bit writes
 * that leave the rest of the word alone; PLC-5 typed commands; SLC 5/02
 * 82-byte packets; every fault df1sim injects, with either the right data or a
 * clear error; writes executed exactly once (df1sim --log: one line per write,
 * never a second command for it; df1sim -v: every repeat on the line
 * recognised as a duplicate); the same faults again with the same --seed;
 * --line-baud pacing; SIGUSR1/SIGUSR2 silencing and restoring every station;
 * df1write runs 65.536 ms apart each written exactly once (a random first TNS);
 * df1sim -d on an existing tty (port busy to another process, its settings
 * back at exit); counters by ID; link test, echo, diagnostic status; bad
 * settings on an open handle; a network CSV driving a real connection; port
 * busy; termios restored after df1_close; the spec-doubt options
 * DF1_OPT_SLC_IO_CODES_82 and DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED (df1sim
 * --plc5-float-swapped).
 *
 * No timing assertions but one lower bound (--line-baud: a paced reply cannot
 * arrive early). Fault tests use short timeouts (200 ms) and fixed
 * seeds; where a fault could in principle exhaust the retries, the outcome
 * accepted is "the right data or a clear link error", never wrong data.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "df1.h"
#include "support/simproc.h"

/* ------------------------------------------------------------------------
 * Data table additions (df1sim --data) and what the table then holds
 * ------------------------------------------------------------------------ */

static const char data_std[] =
	"# libdf1 integration test data (df1sim --data)\n"
	"N7:300=-1,-32768,32767,-12345\n"
	"B3:0=0x5A5A\n"
	"B3:2=4660,4660\n"
	"T4:1=EN=1 DN=1 PRE=200 ACC=55\n"
	"C5:1=CU=1 OV=1 PRE=7 ACC=3\n"
	"R6:0=LEN=10 POS=4\n"
	"ST9:0=\"Hello, DF1\"\n"
	"L10:1=-100000\n"
	"N300:5=777\n"
	"F20:299=299.5\n"
	"N7:999=999\n"
	"N999:999=-7\n";

static const int16_t n7_300[4] = { -1, -32768, 32767, -12345 };

static int16_t exp_n7(int n)
{
	return n >= 300 && n < 304 ? n7_300[n - 300] : (int16_t)n;
}

static float exp_f(int n)
{
	return (float)n + 0.5f;
}

static void exp_st(int n, char *buf, size_t cap)
{
	if (n == 0)
		snprintf(buf, cap, "Hello, DF1");
	else
		snprintf(buf, cap, "STRING %d", n);
}

/* ------------------------------------------------------------------------
 * Helpers
 * ------------------------------------------------------------------------ */

/* A call that must succeed: on failure, say what the handle recorded. */
#define OK(h, expr) ok_rc((h), (expr), #expr, __LINE__)

static int ok_rc(df1_t *h, int rc, const char *what, int line)
{
	if (rc < 0) {
		const struct df1_error_detail *e = df1_last_error(h);

		fail_msg("line %d: %s -> %s (%d): %s", line, what, df1_errname(rc), rc,
		         e && e->message[0] ? e->message : df1_strerror(rc));
	}
	return rc;
}

static uint64_t cnt(df1_t *h, int id)
{
	uint64_t v = 0;

	assert_int_equal(df1_counter(h, id, &v), 0);
	return v;
}

/* A link-level failure: what a fault may legitimately end in. */
static bool link_error(int rc)
{
	return rc == DF1_E_TIMEOUT || rc == DF1_E_NAK_LIMIT || rc == DF1_E_ENQ_LIMIT ||
	       rc == DF1_E_INACTIVE;
}

struct client_cfg {
	enum df1_duplex duplex;
	enum df1_check check;
	enum df1_plc plc;
	int timeout_ms;         /* 0: the library's default */
	int cmd_timeout_ms;     /* 0: the library's default */
	int nak_retries, enq_retries;   /* -1: default */
};

static df1_t *client_open(const char *target, const struct client_cfg *c)
{
	df1_t *h = NULL;
	int rc;

	assert_int_equal(df1_new(&h), 0);
	OK(h, df1_set_duplex(h, c->duplex));
	OK(h, df1_set_check(h, c->check));
	OK(h, df1_set_plc(h, c->plc));
	if (c->timeout_ms > 0)
		OK(h, df1_set_timeout_ms(h, c->timeout_ms));
	if (c->cmd_timeout_ms > 0)
		OK(h, df1_set_cmd_timeout_ms(h, c->cmd_timeout_ms));
	if (c->nak_retries >= 0 && c->enq_retries >= 0)
		OK(h, df1_set_retries(h, c->nak_retries, c->enq_retries));
	rc = df1_open(h, target);
	if (rc < 0) {
		fail_msg("df1_open(%s): %s: %s", target, df1_errname(rc), df1_last_error(h)->message);
	}
	return h;
}

/* The log lines of df1sim (--log) that contain every one of the needles. */
static int log_lines(const char *log, const char *n1, const char *n2, unsigned *tns, int max)
{
	const char *p = log;
	int found = 0;

	while (p && *p) {
		const char *e = strchr(p, '\n');
		size_t len = e ? (size_t)(e - p) : strlen(p);
		char line[512];

		if (len >= sizeof line)
			len = sizeof line - 1;
		memcpy(line, p, len);
		line[len] = '\0';
		if (strstr(line, n1) && (!n2 || strstr(line, n2))) {
			const char *t = strstr(line, " tns=");

			if (tns && found < max && t)
				tns[found] = (unsigned)strtoul(t + 5, NULL, 16);
			found++;
		}
		p = e ? e + 1 : NULL;
	}
	return found;
}

/* ------------------------------------------------------------------------
 * Groups: one simulator per group, a fresh client handle per test
 * ------------------------------------------------------------------------ */

struct group {
	struct simproc sim;
	bool tcp;
	const char *data;
	const char *const *args;
	struct client_cfg cfg;
	int station;            /* the station the tests talk to */
	df1_t *h, *h2;          /* closed by the per-test teardown */
};

static int group_start(void **state, struct group *g)
{
	g->h = g->h2 = NULL;
	*state = g;
	return simproc_start(&g->sim, g->tcp, g->data, false, g->args) < 0 ? -1 : 0;
}

static int group_stop(void **state)
{
	struct group *g = *state;
	int st;

	if (!g || g->sim.pid <= 0)
		return 0;       /* it did not start (reported by the setup) */
	st = simproc_stop(&g->sim, false);

	if (st != 0) {
		fprintf(stderr, "df1sim did not stop cleanly (status %d)\n", st);
		return -1;
	}
	return 0;
}

static df1_t *grp_client(void **state)
{
	struct group *g = *state;

	g->h = client_open(g->sim.target, &g->cfg);
	return g->h;
}

static int test_teardown(void **state)
{
	struct group *g = *state;

	if (g) {
		df1_free(g->h);
		df1_free(g->h2);
		g->h = g->h2 = NULL;
	}
	return 0;
}

static const char *const args_slc_crc[] = { "--duplex", "full", "--check", "crc", NULL };
static struct group g_full_crc = {
	.data = data_std, .args = args_slc_crc, .station = 1,
	.cfg = { DF1_FULL_DUPLEX, DF1_CHECK_CRC, DF1_PLC_SLC, 0, 0, -1, -1 },
};
static int setup_full_crc(void **state) { return group_start(state, &g_full_crc); }

static const char *const args_ml_bcc[] = { "--check", "bcc", "--plc", "micrologix", NULL };
static struct group g_full_bcc = {
	.data = data_std, .args = args_ml_bcc, .station = 1,
	.cfg = { DF1_FULL_DUPLEX, DF1_CHECK_BCC, DF1_PLC_MICROLOGIX, 0, 0, -1, -1 },
};
static int setup_full_bcc(void **state) { return group_start(state, &g_full_bcc); }

static const char *const args_half_multi[] = { "--duplex", "half", "--check", "crc",
	                                       "--station", "1,2,3", NULL };
static struct group g_half_multi = {
	.data = data_std, .args = args_half_multi, .station = 2,
	.cfg = { DF1_HALF_DUPLEX_MASTER, DF1_CHECK_CRC, DF1_PLC_SLC, 0, 0, -1, -1 },
};
static int setup_half_multi(void **state) { return group_start(state, &g_half_multi); }

static const char *const args_half_bcc[] = { "--duplex", "half", "--check", "bcc",
	                                     "--station", "16", NULL };
static struct group g_half_bcc = {
	.data = data_std, .args = args_half_bcc, .station = 16,
	.cfg = { DF1_HALF_DUPLEX_MASTER, DF1_CHECK_BCC, DF1_PLC_SLC, 0, 0, -1, -1 },
};
static int setup_half_bcc(void **state) { return group_start(state, &g_half_bcc); }

static const char *const args_plc5[] = { "--plc", "plc5", NULL };
static struct group g_plc5 = {
	.data = data_std, .args = args_plc5, .station = 1,
	.cfg = { DF1_FULL_DUPLEX, DF1_CHECK_CRC, DF1_PLC_PLC5, 0, 0, -1, -1 },
};
static int setup_plc5(void **state) { return group_start(state, &g_plc5); }

static const char *const args_slc502[] = { "--plc", "slc502", NULL };
static struct group g_slc502 = {
	.data = data_std, .args = args_slc502, .station = 1,
	.cfg = { DF1_FULL_DUPLEX, DF1_CHECK_CRC, DF1_PLC_SLC502, 0, 0, -1, -1 },
};
static int setup_slc502(void **state) { return group_start(state, &g_slc502); }

static struct group g_tcp_full = {
	.tcp = true, .data = data_std, .args = args_slc_crc, .station = 1,
	.cfg = { DF1_FULL_DUPLEX, DF1_CHECK_CRC, DF1_PLC_SLC, 0, 0, -1, -1 },
};
static int setup_tcp_full(void **state) { return group_start(state, &g_tcp_full); }

static struct group g_tcp_half = {
	.tcp = true, .data = data_std, .args = args_half_bcc, .station = 16,
	.cfg = { DF1_HALF_DUPLEX_MASTER, DF1_CHECK_BCC, DF1_PLC_SLC, 0, 0, -1, -1 },
};
static int setup_tcp_half(void **state) { return group_start(state, &g_tcp_half); }

/* ------------------------------------------------------------------------
 * Data: reads compared with the documented initial table
 * ------------------------------------------------------------------------ */

/* 300 N words (several packets) from element 0, and N7:300.. (element > 254). */
static void test_it_read_n_300_words_and_negatives_above_254(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	int16_t v[304];

	memset(v, 0x55, sizeof v);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:0", v, 300)), 300);
	for (int i = 0; i < 300; i++)
		assert_int_equal(v[i], exp_n7(i));
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:300", v, 4)), 4);
	for (int i = 0; i < 4; i++)
		assert_int_equal(v[i], n7_300[i]);
	/* a run across the 254/255 boundary, ending in the negatives */
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:250", v, 54)), 54);
	for (int i = 0; i < 54; i++)
		assert_int_equal(v[i], exp_n7(250 + i));
}

/* 150 floats (several packets), and 300 of a file that --data made longer. */
static void test_it_read_floats(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	float f[300];

	assert_int_equal(OK(h, df1_read_float(h, g->station, "F8:0", f, 150)), 150);
	for (int i = 0; i < 150; i++)
		assert_true(f[i] == exp_f(i));
	assert_int_equal(OK(h, df1_read_float(h, g->station, "F20:0", f, 300)), 300);
	for (int i = 0; i < 300; i++)
		assert_true(f[i] == exp_f(i));
}

/* 5 strings (84-byte elements: several packets), one by one too. */
static void test_it_read_strings(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	struct df1_value v[5];
	char want[32], buf[DF1_STRING_MAX + 1];

	assert_int_equal(OK(h, df1_read(h, g->station, "ST9:0", v, 5)), 5);
	for (int i = 0; i < 5; i++) {
		exp_st(i, want, sizeof want);
		assert_int_equal(v[i].kind, DF1_VAL_STRING);
		assert_int_equal(v[i].v.str.len, strlen(want));
		assert_string_equal(v[i].v.str.text, want);
	}
	assert_int_equal(OK(h, df1_read_string(h, g->station, "ST9:3", buf, sizeof buf)), 8);
	assert_string_equal(buf, "STRING 3");
}

/* T/C/R whole elements, .PRE/.ACC/.LEN/.POS, and the named bits. */
static void test_it_read_timer_counter_control(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	struct df1_tcr t[3];
	int16_t w;
	bool b;

	assert_int_equal(OK(h, df1_read_tcr(h, g->station, "T4:0", t, 3)), 3);
	assert_int_equal(t[0].ctl, 0);
	assert_int_equal(t[0].pre, 100);
	assert_int_equal(t[0].acc, 0);
	assert_int_equal(t[1].ctl, 0xA000);     /* EN DN */
	assert_int_equal(t[1].pre, 200);
	assert_int_equal(t[1].acc, 55);
	assert_int_equal(t[2].pre, 100);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "T4:1.ACC", &w, 1)), 1);
	assert_int_equal(w, 55);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "T4:1.PRE", &w, 1)), 1);
	assert_int_equal(w, 200);
	OK(h, df1_read_bit(h, g->station, "T4:1/DN", &b));
	assert_true(b);
	OK(h, df1_read_bit(h, g->station, "T4:1/TT", &b));
	assert_false(b);
	OK(h, df1_read_bit(h, g->station, "T4:0/DN", &b));
	assert_false(b);

	assert_int_equal(OK(h, df1_read_tcr(h, g->station, "C5:1", t, 1)), 1);
	assert_int_equal(t[0].ctl, 0x9000);     /* CU OV */
	assert_int_equal(t[0].pre, 7);
	assert_int_equal(t[0].acc, 3);
	OK(h, df1_read_bit(h, g->station, "C5:1/OV", &b));
	assert_true(b);
	OK(h, df1_read_bit(h, g->station, "C5:1/DN", &b));
	assert_false(b);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "C5:0.PRE", &w, 1)), 1);
	assert_int_equal(w, 100);

	assert_int_equal(OK(h, df1_read_tcr(h, g->station, "R6:0", t, 1)), 1);
	assert_int_equal(t[0].ctl, 0);
	assert_int_equal(t[0].pre, 10);         /* LEN */
	assert_int_equal(t[0].acc, 4);          /* POS */
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "R6:0.POS", &w, 1)), 1);
	assert_int_equal(w, 4);
}

/* A file above 254 (0xFF escape for the file number). */
static void test_it_file_300(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	int16_t v[10], w = -5;

	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N300:0", v, 10)), 10);
	for (int i = 0; i < 10; i++)
		assert_int_equal(v[i], i == 5 ? 777 : i);
	assert_int_equal(OK(h, df1_write_int16(h, g->station, "N300:255", &w, 1)), 1);
	w = 0;
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N300:254", v, 2)), 2);
	assert_int_equal(v[0], 254);
	assert_int_equal(v[1], -5);
	/* the largest file and element df1sim holds (--data N999:999) */
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N999:997", v, 3)), 3);
	assert_int_equal(v[0], 997);
	assert_int_equal(v[1], 998);
	assert_int_equal(v[2], -7);
	/* past the end of the file: the PLC's error, EXT STS 07 */
	assert_int_equal(df1_read_int16(h, g->station, "N300:256", v, 1), DF1_E_REMOTE);
	assert_int_equal(df1_last_error(h)->sts, 0xF0);
	assert_int_equal(df1_last_error(h)->ext_sts, 0x07);
}

/* The word files O, I, S and A: zero at start (df1sim(1)), written and read
 * back as words, through the generic read, and bit by bit. */
static void test_it_o_i_s_a_words(void **state)
{
	static const char *const files[] = { "O:0", "I:0", "S:10", "A11:0" };
	static const char *const bits[] = { "O:0/3", "I:0/3", "S:10/3", "A11:0/3" };
	struct group *g = *state;
	df1_t *h = grp_client(state);
	const int16_t w[4] = { 0x1234, -1, -32768, 0x0010 };
	const int16_t zero[4] = { 0, 0, 0, 0 };

	for (size_t f = 0; f < sizeof files / sizeof files[0]; f++) {
		int16_t r[4] = { 7, 7, 7, 7 };
		struct df1_value v[4];
		bool b;

		assert_int_equal(OK(h, df1_read_int16(h, g->station, files[f], r, 4)), 4);
		assert_memory_equal(r, zero, sizeof r);
		assert_int_equal(OK(h, df1_write_int16(h, g->station, files[f], w, 4)), 4);
		assert_int_equal(OK(h, df1_read_int16(h, g->station, files[f], r, 4)), 4);
		assert_memory_equal(r, w, sizeof r);
		assert_int_equal(OK(h, df1_read(h, g->station, files[f], v, 4)), 4);
		for (int i = 0; i < 4; i++) {
			assert_int_equal(v[i].kind, DF1_VAL_INT16);
			assert_int_equal(v[i].v.i16, w[i]);
		}
		/* bit 3 of 0x1234 is 0: set it, the other bits stay */
		OK(h, df1_read_bit(h, g->station, bits[f], &b));
		assert_false(b);
		OK(h, df1_write_bit(h, g->station, bits[f], true));
		assert_int_equal(OK(h, df1_read_int16(h, g->station, files[f], r, 2)), 2);
		assert_int_equal(r[0], 0x123C);
		assert_int_equal(r[1], -1);
		assert_int_equal(OK(h, df1_write_int16(h, g->station, files[f], zero, 4)), 4);
	}
}

/* DF1_OPT_SLC_IO_CODES_82: O and I named 82/83 (doc/PROTOCOL.md 4.11) reach the same
 * files of df1sim as 8B/8C: written with one, read back with the other. */
static void test_it_slc_io_codes_82(void **state)
{
	static const char *const files[] = { "O:1", "I:1" };
	struct group *g = *state;
	df1_t *h = grp_client(state);
	const int16_t w[2] = { 0x4321, -2 };
	const int16_t zero[2] = { 0, 0 };

	for (size_t f = 0; f < sizeof files / sizeof files[0]; f++) {
		int16_t r[2] = { 7, 7 };

		OK(h, df1_set_option(h, DF1_OPT_SLC_IO_CODES_82, 1));
		assert_int_equal(OK(h, df1_write_int16(h, g->station, files[f], w, 2)), 2);
		assert_int_equal(OK(h, df1_read_int16(h, g->station, files[f], r, 2)), 2);
		assert_memory_equal(r, w, sizeof r);
		OK(h, df1_set_option(h, DF1_OPT_SLC_IO_CODES_82, 0));
		memset(r, 0, sizeof r);
		assert_int_equal(OK(h, df1_read_int16(h, g->station, files[f], r, 2)), 2);
		assert_memory_equal(r, w, sizeof r);
		assert_int_equal(OK(h, df1_write_int16(h, g->station, files[f], zero, 2)), 2);
	}
}

/* ------------------------------------------------------------------------
 * Writes
 * ------------------------------------------------------------------------ */

/* Bit writes change one bit and never the rest of the word. */
static void test_it_bit_write_keeps_other_bits(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	struct df1_value bits[16];
	int16_t w[4];
	bool b;

	assert_int_equal(OK(h, df1_read_int16(h, g->station, "B3:0", w, 1)), 1);
	assert_int_equal((uint16_t)w[0], 0x5A5A);
	OK(h, df1_write_bit(h, g->station, "B3:0/5", true));
	OK(h, df1_write_bit(h, g->station, "B3:0/1", false));
	OK(h, df1_write_bit(h, g->station, "B3:0/15", true));
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "B3:0", w, 2)), 2);
	assert_int_equal((uint16_t)w[0], 0xDA78);
	assert_int_equal(w[1], 0);
	OK(h, df1_read_bit(h, g->station, "B3:0/5", &b));
	assert_true(b);
	/* 16 bits of the word at once */
	assert_int_equal(OK(h, df1_read(h, g->station, "B3:0/0", bits, 16)), 16);
	for (int i = 0; i < 16; i++) {
		assert_int_equal(bits[i].kind, DF1_VAL_BIT);
		assert_int_equal(bits[i].v.bit, (0xDA78 >> i) & 1);
	}
	/* B3/21 = bit 5 of B3:1 */
	OK(h, df1_write_bit(h, g->station, "B3/21", true));
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "B3:0", w, 2)), 2);
	assert_int_equal((uint16_t)w[0], 0xDA78);
	assert_int_equal(w[1], 0x0020);
	/* 4 bits across a word boundary: 14 15 of B3:2, 0 1 of B3:3 */
	for (int i = 0; i < 4; i++) {
		bits[i].kind = DF1_VAL_BIT;
		bits[i].v.bit = true;
	}
	assert_int_equal(OK(h, df1_write(h, g->station, "B3:2/14", bits, 4)), 4);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "B3:2", w, 2)), 2);
	assert_int_equal((uint16_t)w[0], 0x1234 | 0xC000);
	assert_int_equal((uint16_t)w[1], 0x1234 | 0x0003);
	/* a timer bit leaves PRE and ACC and the other status bits alone */
	OK(h, df1_write_bit(h, g->station, "T4:1/TT", true));
	{
		struct df1_tcr t;

		assert_int_equal(OK(h, df1_read_tcr(h, g->station, "T4:1", &t, 1)), 1);
		assert_int_equal(t.ctl, 0xE000);
		assert_int_equal(t.pre, 200);
		assert_int_equal(t.acc, 55);
	}
	OK(h, df1_write_bit(h, g->station, "T4:1/TT", false));
}

/* Multi-packet writes of every kind, read back. */
static void test_it_write_read_back(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	static int16_t n[300], nr[300];
	static float f[150], fr[150];
	struct df1_value s[5], sr[5];
	struct df1_tcr t = { 0x8000, 1234, -2 }, tr;
	int16_t w;

	for (int i = 0; i < 300; i++)
		n[i] = (int16_t)(i * 109 - 16000);
	assert_int_equal(OK(h, df1_write_int16(h, g->station, "N7:400", n, 300)), 300);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:400", nr, 300)), 300);
	assert_memory_equal(n, nr, sizeof n);
	/* the neighbours are untouched */
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:399", &w, 1)), 1);
	assert_int_equal(w, 399);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:700", &w, 1)), 1);
	assert_int_equal(w, 700);

	for (int i = 0; i < 150; i++)
		f[i] = (float)i * -1.25f + 0.1f;
	f[7] = 3.4028235e38f;
	f[8] = -0.0f;
	assert_int_equal(OK(h, df1_write_float(h, g->station, "F20:100", f, 150)), 150);
	assert_int_equal(OK(h, df1_read_float(h, g->station, "F20:100", fr, 150)), 150);
	assert_memory_equal(f, fr, sizeof f);

	for (int i = 0; i < 5; i++) {
		s[i].kind = DF1_VAL_STRING;
		switch (i) {
		case 0: snprintf(s[i].v.str.text, sizeof s[i].v.str.text, "%s", ""); break;
		case 1: snprintf(s[i].v.str.text, sizeof s[i].v.str.text, "odd"); break;
		case 2: memset(s[i].v.str.text, 'x', DF1_STRING_MAX);
			s[i].v.str.text[DF1_STRING_MAX] = '\0'; break;
		case 3: snprintf(s[i].v.str.text, sizeof s[i].v.str.text, "DLE \x10 inside"); break;
		default: snprintf(s[i].v.str.text, sizeof s[i].v.str.text, "the end."); break;
		}
		s[i].v.str.len = (uint16_t)strlen(s[i].v.str.text);
	}
	assert_int_equal(OK(h, df1_write(h, g->station, "ST9:10", s, 5)), 5);
	assert_int_equal(OK(h, df1_read(h, g->station, "ST9:10", sr, 5)), 5);
	for (int i = 0; i < 5; i++) {
		assert_int_equal(sr[i].v.str.len, s[i].v.str.len);
		assert_string_equal(sr[i].v.str.text, s[i].v.str.text);
	}

	assert_int_equal(OK(h, df1_write_tcr(h, g->station, "T4:5", &t, 1)), 1);
	assert_int_equal(OK(h, df1_read_tcr(h, g->station, "T4:5", &tr, 1)), 1);
	assert_int_equal(tr.ctl, t.ctl);
	assert_int_equal(tr.pre, t.pre);
	assert_int_equal(tr.acc, t.acc);
	/* a sub-element write changes only that word */
	w = 77;
	assert_int_equal(OK(h, df1_write_int16(h, g->station, "T4:6.ACC", &w, 1)), 1);
	assert_int_equal(OK(h, df1_read_tcr(h, g->station, "T4:6", &tr, 1)), 1);
	assert_int_equal(tr.ctl, 0);
	assert_int_equal(tr.pre, 100);
	assert_int_equal(tr.acc, 77);
	/* element above 254 */
	w = -321;
	assert_int_equal(OK(h, df1_write_int16(h, g->station, "N7:301", &w, 1)), 1);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:300", nr, 3)), 3);
	assert_int_equal(nr[0], -1);
	assert_int_equal(nr[1], -321);
	assert_int_equal(nr[2], 32767);
	w = -32768;     /* back as it was, for the other tests */
	assert_int_equal(OK(h, df1_write_int16(h, g->station, "N7:301", &w, 1)), 1);
}

/* L (MicroLogix long integers). */
static void test_it_long(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	int32_t l[60], lw[60];

	assert_int_equal(OK(h, df1_read_int32(h, g->station, "L10:0", l, 60)), 60);
	for (int i = 0; i < 60; i++)
		assert_int_equal(l[i], i == 1 ? -100000 : (int32_t)(i * 65537));
	for (int i = 0; i < 60; i++)
		lw[i] = (int32_t)(i * -1000003 + 7);
	lw[0] = INT32_MIN;
	lw[1] = INT32_MAX;
	assert_int_equal(OK(h, df1_write_int32(h, g->station, "L10:100", lw, 60)), 60);
	assert_int_equal(OK(h, df1_read_int32(h, g->station, "L10:100", l, 60)), 60);
	assert_memory_equal(l, lw, sizeof l);
}

/* ------------------------------------------------------------------------
 * Diagnostics
 * ------------------------------------------------------------------------ */

static void test_it_link_test_echo_diag(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	struct df1_diag_status d;
	uint8_t buf[243];

	OK(h, df1_link_test(h, g->station));
	for (size_t i = 0; i < sizeof buf; i++)
		buf[i] = (uint8_t)(i * 7 + 0x10);   /* DLE bytes included */
	buf[0] = buf[1] = 0x10;
	assert_int_equal(OK(h, df1_echo(h, g->station, buf, sizeof buf)), (int)sizeof buf);
	assert_int_equal(OK(h, df1_echo(h, g->station, (const uint8_t *)"A", 1)), 1);
	memset(&d, 0, sizeof d);
	OK(h, df1_diag_status(h, g->station, &d));
	switch (g->cfg.plc) {
	case DF1_PLC_MICROLOGIX:        /* df1sim's default processor per --plc */
		assert_int_equal(d.type_code, 0x9F);
		assert_string_equal(d.name, "MicroLogix 1400");
		break;
	case DF1_PLC_PLC5:
		assert_int_equal(d.type_code, 0x15);
		assert_string_equal(d.name, "PLC-5/40");
		break;
	default:
		assert_int_equal(d.type_code, 0x5B);
		assert_string_equal(d.name, "SLC 5/04");
		break;
	}
	/* change mode is answered; the diag status reports it */
	OK(h, df1_change_mode(h, g->station, 1));
	OK(h, df1_change_mode(h, g->station, 6));
}

/* Counters after known exchanges: one read in full duplex, one in half. */
static void test_it_counters_one_read(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	int16_t v;
	bool half = g->cfg.duplex == DF1_HALF_DUPLEX_MASTER;

	/* A first read takes up what the previous handle may have left: df1_open
	 * flushes both queues (df1_open(3)), which on a pty also drops the last
	 * ACK of the previous handle if df1sim had not read it yet; a half-duplex
	 * slave then sends that reply again on the next poll (counted stale). */
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:8", &v, 1)), 1);
	df1_counters_reset(h);
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:9", &v, 1)), 1);
	assert_int_equal(v, 9);
	assert_int_equal(cnt(h, 2527), 1);      /* CNT_CMD_MSGS_SENT */
	assert_int_equal(cnt(h, 2530), 1);      /* CNT_REPLY_MSGS_RCVD */
	assert_true(cnt(h, 2536) >= 1);         /* CNT_ACKS_RCVD */
	assert_true(cnt(h, 2535) >= 1);         /* CNT_ACKS_SENT */
	assert_true(cnt(h, 2525) >= 1);         /* CNT_MSG_PACKETS_SENT */
	assert_true(cnt(h, 2526) >= 1);         /* CNT_MSG_PACKETS_RCVD */
	assert_true(cnt(h, 2560) > 0);          /* CRD_CHAR_SENT */
	assert_true(cnt(h, 2561) > 0);          /* CRD_CHAR_RECV */
	if (half)
		assert_true(cnt(h, 2531) >= 1); /* CNT_POLL_MSGS_SENT */
	else
		assert_int_equal(cnt(h, 2531), 0);
	/* nothing went wrong */
	for (int id = 2533; id <= 2551; id++) {
		if ((id >= 2533 && id <= 2534) || id >= 2539) {
			if (cnt(h, id) != 0)
				fail_msg("counter %d = %llu after one good read", id,
				         (unsigned long long)cnt(h, id));
		}
	}
	/* a second read: the message counters move by one */
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:10", &v, 1)), 1);
	assert_int_equal(cnt(h, 2527), 2);
	assert_int_equal(cnt(h, 2530), 2);
	/* an error reply is counted as such and is DF1_E_REMOTE with STS/EXT STS */
	assert_int_equal(df1_read_int16(h, g->station, "N77:0", &v, 1), DF1_E_REMOTE);
	assert_int_equal(df1_last_error(h)->sts, 0xF0);
	assert_true(df1_last_error(h)->has_ext_sts);
	assert_int_equal(df1_last_error(h)->ext_sts, 0x06);
	assert_int_equal(cnt(h, 2540), 1);      /* CNT_ERROR_MSGS_RCVD */
	assert_int_equal(cnt(h, 2527), 3);
}

/* Several stations on one half-duplex line: each has its own table. */
static void test_it_half_several_stations(void **state)
{
	df1_t *h = grp_client(state);
	int16_t v[10], w = -2;

	for (int st = 1; st <= 3; st++) {
		assert_int_equal(OK(h, df1_read_int16(h, st, "N7:0", v, 10)), 10);
		for (int i = 0; i < 10; i++)
			assert_int_equal(v[i], i);
		OK(h, df1_link_test(h, st));
		assert_int_equal(df1_station_active(h, st), 1);
	}
	assert_int_equal(OK(h, df1_write_int16(h, 2, "N7:50", &w, 1)), 1);
	for (int st = 1; st <= 3; st++) {
		assert_int_equal(OK(h, df1_read_int16(h, st, "N7:50", v, 1)), 1);
		assert_int_equal(v[0], st == 2 ? -2 : 50);
	}
	w = 50;
	assert_int_equal(OK(h, df1_write_int16(h, 2, "N7:50", &w, 1)), 1);
}

/* ------------------------------------------------------------------------
 * PLC-5 (typed read/write 0F/68 67, read-modify-write 0F/26)
 * ------------------------------------------------------------------------ */

static void test_it_plc5_ascii_address_and_bits(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	int16_t v[2];

	assert_int_equal(OK(h, df1_read_int16(h, g->station, "$N7:5", v, 1)), 1);
	assert_int_equal(v[0], 5);
	OK(h, df1_write_bit(h, g->station, "N7:20/0", false));
	OK(h, df1_write_bit(h, g->station, "N7:20/15", true));
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:19", v, 2)), 2);
	assert_int_equal(v[0], 19);
	assert_int_equal((uint16_t)v[1], 0x8014);
	OK(h, df1_write_bit(h, g->station, "N7:20/15", false));
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:20", v, 1)), 1);
	assert_int_equal(v[0], 20);
}

/* ------------------------------------------------------------------------
 * Handle-level behaviour over a real pty
 * ------------------------------------------------------------------------ */

/* A second df1_open of the same pty is DF1_E_BUSY; after close it works. */
static void test_it_port_busy(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	int16_t v;
	int rc;

	assert_int_equal(df1_new(&g->h2), 0);
	OK(g->h2, df1_set_check(g->h2, g->cfg.check));
	OK(g->h2, df1_set_plc(g->h2, g->cfg.plc));
	rc = df1_open(g->h2, g->sim.target);
	assert_int_equal(rc, DF1_E_BUSY);
	assert_int_equal(df1_last_error(g->h2)->code, DF1_E_BUSY);
	assert_false(df1_is_open(g->h2));
	/* the first handle is not disturbed */
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:3", &v, 1)), 1);
	assert_int_equal(v, 3);
	df1_close(h);
	OK(g->h2, df1_open(g->h2, g->sim.target));
	assert_int_equal(OK(g->h2, df1_read_int16(g->h2, g->station, "N7:4", &v, 1)), 1);
	assert_int_equal(v, 4);
}

static bool tios_equal(const struct termios *a, const struct termios *b)
{
	return a->c_iflag == b->c_iflag && a->c_oflag == b->c_oflag && a->c_cflag == b->c_cflag &&
	       a->c_lflag == b->c_lflag && cfgetispeed(a) == cfgetispeed(b) &&
	       cfgetospeed(a) == cfgetospeed(b) && memcmp(a->c_cc, b->c_cc, sizeof a->c_cc) == 0;
}

/* df1_close puts back the pty's settings as they were before df1_open. */
static void test_it_termios_restored(void **state)
{
	struct group *g = *state;
	struct termios mine, before, during, after;
	int16_t v;
	df1_t *h;
	int fd;

	fd = open(g->sim.target, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
	assert_true(fd >= 0);
	assert_int_equal(tcgetattr(fd, &mine), 0);
	/* something recognisable, harmless to df1sim on the other side: 4800 baud,
	 * 2 stop bits, VMIN 1, VTIME 7 (a pty forces CS8 and no parity) */
	cfsetispeed(&mine, B4800);
	cfsetospeed(&mine, B4800);
	mine.c_cflag |= CSTOPB;
	mine.c_cc[VMIN] = 1;
	mine.c_cc[VTIME] = 7;
	assert_int_equal(tcsetattr(fd, TCSANOW, &mine), 0);
	assert_int_equal(tcgetattr(fd, &before), 0);
	close(fd);

	h = grp_client(state);          /* 19200 8N1 raw */
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:1", &v, 1)), 1);
	fd = open(g->sim.target, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
	if (fd >= 0) {                  /* root passes TIOCEXCL; others get EBUSY */
		assert_int_equal(tcgetattr(fd, &during), 0);
		assert_false(tios_equal(&during, &before));
		assert_int_equal(cfgetospeed(&during), B19200);
		close(fd);
	} else {
		assert_int_equal(errno, EBUSY);
	}
	df1_close(h);
	assert_false(df1_is_open(h));

	fd = open(g->sim.target, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
	assert_true(fd >= 0);           /* TIOCEXCL is gone too */
	assert_int_equal(tcgetattr(fd, &after), 0);
	assert_true(tios_equal(&before, &after));
	/* back to raw, as df1sim set it */
	cfmakeraw(&mine);
	mine.c_cflag &= ~(tcflag_t)CSTOPB;
	mine.c_cc[VMIN] = 0;
	mine.c_cc[VTIME] = 0;
	(void)tcsetattr(fd, TCSANOW, &mine);
	close(fd);

	/* the handle keeps its configuration and opens again */
	OK(h, df1_open(h, g->sim.target));
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:2", &v, 1)), 1);
	assert_int_equal(v, 2);
}

/* Bad values through the setters of an open handle: rejected with their
 * critical IDs, nothing changed, the link keeps working. */
static void test_it_bad_settings_on_open_handle(void **state)
{
	struct group *g = *state;
	df1_t *h = grp_client(state);
	static const int ids[7] = { 2552, 2553, 2555, 2556, 2557, 2558, 2559 };
	int rc[7];
	int16_t v;

	rc[0] = df1_set_station(h, 255);
	assert_int_equal(df1_last_error(h)->catalog_id, ids[0]);
	rc[1] = df1_set_duplex(h, (enum df1_duplex)7);
	assert_int_equal(df1_last_error(h)->catalog_id, ids[1]);
	rc[2] = df1_set_plc(h, (enum df1_plc)9);
	assert_int_equal(df1_last_error(h)->catalog_id, ids[2]);
	rc[3] = df1_set_check(h, (enum df1_check)5);
	assert_int_equal(df1_last_error(h)->catalog_id, ids[3]);
	rc[4] = df1_set_retries(h, 11, 3);
	assert_int_equal(df1_last_error(h)->catalog_id, ids[4]);
	rc[5] = df1_set_retries(h, 3, -1);
	assert_int_equal(df1_last_error(h)->catalog_id, ids[5]);
	rc[6] = df1_set_cmd_timeout_ms(h, 5001);
	assert_int_equal(df1_last_error(h)->catalog_id, ids[6]);
	for (int i = 0; i < 7; i++)
		assert_int_equal(rc[i], DF1_E_CONFIG);
	assert_true(df1_is_open(h));
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:6", &v, 1)), 1);
	assert_int_equal(v, 6);
}

struct issues {
	int n;
	int ids[16];
};

static void collect_issue(void *user, const struct df1_config_issue *is)
{
	struct issues *s = user;

	if (s->n < 16)
		s->ids[s->n] = is->catalog_id;
	s->n++;
}

static bool has_id(const struct issues *s, int id)
{
	for (int i = 0; i < s->n && i < 16; i++)
		if (s->ids[i] == id)
			return true;
	return false;
}

/* A network CSV names the pty: load, apply, open, read. An invalid one does
 * not load. */
static void test_it_net_config_file(void **state)
{
	struct group *g = *state;
	struct df1_net_config c;
	struct issues is = { 0 };
	char path[200];
	FILE *f;
	df1_t *h = NULL;
	int16_t v;

	snprintf(path, sizeof path, "%s/net.csv", g->sim.dir);
	f = fopen(path, "w");
	assert_non_null(f);
	fprintf(f, "Station,Mode,PLC_Type,Error_Code,NAK_Retries,ENQ_Retries,Cmd_Timeout,Com_Port,"
	           "Baud,Parity,Timeout\n"
	           "0,Peer,SLC,%s,3,3,1000,%s,19200,None,1000\n",
	        g->cfg.check == DF1_CHECK_BCC ? "BCC" : "CRC", g->sim.target);
	fclose(f);
	OK(NULL, df1_net_config_load(path, &c, collect_issue, &is));
	assert_int_equal(is.n, 0);
	assert_int_equal(df1_new(&h), 0);
	g->h = h;
	OK(h, df1_apply_net_config(h, &c));
	OK(h, df1_set_plc(h, g->cfg.plc));
	OK(h, df1_open(h, c.port));
	assert_int_equal(OK(h, df1_read_int16(h, g->station, "N7:8", &v, 1)), 1);
	assert_int_equal(v, 8);

	f = fopen(path, "w");
	assert_non_null(f);
	fprintf(f, "Station,Mode,NAK_Retries,Cmd_Timeout,Com_Port\n300,Peer,11,100,%s\n", g->sim.target);
	fclose(f);
	assert_int_equal(df1_net_config_load(path, &c, collect_issue, &is), DF1_E_CONFIG);
	assert_true(has_id(&is, 2552));
	assert_true(has_id(&is, 2557));
	assert_true(has_id(&is, 2559));
	unlink(path);
}

/* ------------------------------------------------------------------------
 * Faults: one simulator per test
 * ------------------------------------------------------------------------ */

struct fault_env {
	struct simproc sim;
	df1_t *h;
	char *log;
};

static struct fault_env fenv;

static int fault_setup(void **state)
{
	memset(&fenv, 0, sizeof fenv);
	*state = &fenv;
	return 0;
}

static int fault_teardown(void **state)
{
	struct fault_env *e = *state;

	df1_free(e->h);
	e->h = NULL;
	if (e->sim.pid > 0)
		simproc_stop(&e->sim, false);
	simproc_cleanup(&e->sim);
	free(e->log);
	e->log = NULL;
	return 0;
}

/* Start a simulator with these options and open a client with short timeouts. */
static df1_t *fault_start(struct fault_env *e, bool half, enum df1_check check, bool log,
                          const char *const *args, int retries)
{
	struct client_cfg c = {
		half ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX, check, DF1_PLC_SLC, 200, 500,
		retries, retries,
	};

	if (simproc_start(&e->sim, false, NULL, log, args) < 0)
		fail_msg("df1sim did not start");
	e->h = client_open(e->sim.target, &c);
	return e->h;
}

/* Stop the simulator (it must exit 0 on SIGTERM) and read its log. */
static const char *fault_stop_log(struct fault_env *e)
{
	assert_int_equal(simproc_stop(&e->sim, true), 0);
	e->log = simproc_slurp(e->sim.log, NULL);
	assert_non_null(e->log);
	return e->log;
}

/* n reads of N7:k; each gives k or a link error (never other data).
 * Returns the number that succeeded. */
static int reads_right_or_clear(df1_t *h, int station, int n)
{
	int good = 0;

	for (int k = 0; k < n; k++) {
		char a[16];
		int16_t v = -999;
		int rc;

		snprintf(a, sizeof a, "N7:%d", 20 + k);
		rc = df1_read_int16(h, station, a, &v, 1);
		if (rc == 1) {
			assert_int_equal(v, 20 + k);
			good++;
		} else if (!link_error(rc)) {
			fail_msg("%s: %s: %s", a, df1_errname(rc), df1_last_error(h)->message);
		}
	}
	return good;
}

/* Writes N7:10 = k for k = 1..20, each read back; then df1sim's log must show
 * every write exactly once (one log line per command, whatever the link did). */
static void writes_exactly_once(struct fault_env *e, int station)
{
	df1_t *h = e->h;
	unsigned tns[64];
	int ok = 0, failed = 0, lines;

	for (int16_t k = 1; k <= 20; k++) {
		int16_t v = 0;
		int rc = df1_write_int16(h, station, "N7:10", &k, 1);

		if (rc == 1) {
			ok++;
		} else {
			assert_true(link_error(rc));
			failed++;
			continue;
		}
		rc = df1_read_int16(h, station, "N7:10", &v, 1);
		if (rc == 1)
			assert_int_equal(v, k);
		else
			assert_true(link_error(rc));
	}
	assert_true(ok >= 15);
	lines = log_lines(fault_stop_log(e), "cmd=0F/AA addr=N7:10 ", NULL, tns, 64);
	/* each successful write once; a failed one at most once; never twice */
	assert_true(lines >= ok);
	assert_true(lines <= ok + failed);
	for (int i = 0; i < lines && i < 64; i++)
		for (int j = i + 1; j < lines && j < 64; j++)
			assert_int_not_equal(tns[i], tns[j]);
}

/* df1sim --plc plc5 --plc5-float-swapped against a client with
 * DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED: the documented F8 values (n + 0.5) read
 * right, and a write lands as the same float in the data table (read back
 * through SLC 0F/A2, which is plain LE either way). Without the option the
 * client reads other values: the two sides must agree. */
static void test_it_plc5_typed_float_swapped(void **state)
{
	static const char *const args[] = { "--plc", "plc5", "--plc5-float-swapped", NULL };
	struct fault_env *e = *state;
	struct client_cfg c = { DF1_FULL_DUPLEX, DF1_CHECK_CRC, DF1_PLC_PLC5, 0, 0, -1, -1 };
	const float w[2] = { 3.25f, -1234.5f };
	float f[150];
	df1_t *h;

	if (simproc_start(&e->sim, false, NULL, false, args) < 0)
		fail_msg("df1sim did not start");
	h = e->h = client_open(e->sim.target, &c);
	OK(h, df1_set_option(h, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED, 1));
	assert_int_equal(OK(h, df1_read_float(h, 1, "F8:0", f, 150)), 150);
	for (int i = 0; i < 150; i++)
		assert_true(f[i] == exp_f(i));
	assert_int_equal(OK(h, df1_write_float(h, 1, "F8:5", w, 2)), 2);
	assert_int_equal(OK(h, df1_read_float(h, 1, "F8:5", f, 2)), 2);
	assert_true(f[0] == w[0] && f[1] == w[1]);
	OK(h, df1_set_plc(h, DF1_PLC_SLC));
	assert_int_equal(OK(h, df1_read_float(h, 1, "F8:4", f, 3)), 3);
	assert_true(f[0] == exp_f(4) && f[1] == w[0] && f[2] == w[1]);
	/* mismatched: the plain LE reading of C0 3F 00 00 is not 1.5 */
	OK(h, df1_set_plc(h, DF1_PLC_PLC5));
	OK(h, df1_set_option(h, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED, 0));
	assert_int_equal(OK(h, df1_read_float(h, 1, "F8:1", f, 1)), 1);
	assert_true(f[0] != exp_f(1));
}

static void test_it_fault_drop_ack_full_writes_once(void **state)
{
	static const char *const args[] = { "--drop-ack", "30", "--seed", "11", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, false, DF1_CHECK_CRC, true, args, 3);

	df1_counters_reset(h);
	writes_exactly_once(e, 1);
	/* some replies came without the ACK before them (and completed the command) */
	assert_true(cnt(h, 2536) < cnt(h, 2527));
	assert_int_equal(cnt(h, 2530), cnt(h, 2527));
}

static void test_it_fault_drop_ack_half_writes_once(void **state)
{
	static const char *const args[] = { "--duplex", "half", "--drop-ack", "30", "--seed", "12",
	                                    "-v", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, true, DF1_CHECK_CRC, true, args, 3);
	char *err;
	int dups = 0;

	df1_counters_reset(h);
	writes_exactly_once(e, 1);
	/* every retransmission after a missing ACK reached df1sim as a duplicate:
	 * ACKed and not run again ([2524] in its -v messages) */
	assert_true(cnt(h, 2541) >= 1);
	err = simproc_slurp(e->sim.err, NULL);
	assert_non_null(err);
	for (const char *p = err; (p = strstr(p, "[2524]")) != NULL; p++)
		dups++;
	free(err);
	assert_int_equal(dups, (int)cnt(h, 2541));
}

static void test_it_fault_combined_full_writes_once(void **state)
{
	static const char *const args[] = { "--check", "bcc", "--drop-ack", "20", "--nak", "20", "--corrupt", "20",
	                                    "--stale", "20", "--noise", "10", "--seed", "5", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, false, DF1_CHECK_BCC, true, args, 5);

	df1_counters_reset(h);
	writes_exactly_once(e, 1);
	assert_true(cnt(h, 2534) >= 1);         /* NAKs received */
	assert_true(cnt(h, 2546) >= 1);         /* BCC errors */
	assert_true(cnt(h, 2533) >= 1);         /* NAKs sent */
}

static void test_it_fault_corrupt(void **state)
{
	static const char *const args_f[] = { "--corrupt", "40", "--seed", "3", NULL };
	static const char *const args_h[] = { "--duplex", "half", "--check", "bcc", "--corrupt", "40",
	                                      "--seed", "4", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, false, DF1_CHECK_CRC, false, args_f, 3);

	df1_counters_reset(h);
	assert_int_equal(reads_right_or_clear(h, 1, 15), 15);  /* the retransmission is good */
	assert_true(cnt(h, 2547) >= 1);         /* CNT_CRC_ERRORS */
	assert_true(cnt(h, 2533) >= 1);         /* CNT_NAKS_SENT */
	assert_int_equal(cnt(h, 2546), 0);
	df1_free(h);
	e->h = NULL;
	assert_int_equal(simproc_stop(&e->sim, false), 0);

	h = fault_start(e, true, DF1_CHECK_BCC, false, args_h, 3);
	df1_counters_reset(h);
	assert_int_equal(reads_right_or_clear(h, 1, 15), 15);
	assert_true(cnt(h, 2546) >= 1);         /* CNT_BCC_ERRORS */
	assert_true(cnt(h, 2543) >= 1);         /* polled again */
}

static void test_it_fault_nak(void **state)
{
	static const char *const args[] = { "--nak", "30", "--seed", "7", NULL };
	static const char *const args_all[] = { "--nak", "100", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, false, DF1_CHECK_CRC, false, args, 5);
	int16_t v;

	df1_counters_reset(h);
	assert_true(reads_right_or_clear(h, 1, 15) >= 13);
	assert_true(cnt(h, 2534) >= 1);         /* CNT_NAKS_RCVD */
	assert_true(cnt(h, 2541) >= 1);         /* CNT_NAK_RETRIES */
	df1_free(h);
	e->h = NULL;
	assert_int_equal(simproc_stop(&e->sim, false), 0);

	/* every command NAKed: the NAK limit, a clear error */
	h = fault_start(e, false, DF1_CHECK_CRC, false, args_all, 2);
	df1_counters_reset(h);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), DF1_E_NAK_LIMIT);
	assert_int_equal(df1_last_error(h)->catalog_id, 2519);
	assert_int_equal(cnt(h, 2534), 3);
	assert_int_equal(cnt(h, 2541), 2);
	assert_int_equal(cnt(h, 2542), 1);      /* CNT_NAK_LIMIT_EXCEEDED */
	assert_int_equal(cnt(h, 2530), 0);
}

/* A reply later than the command timeout is DF1_E_TIMEOUT; within it, data;
 * the late reply is never taken as the answer to the next command. */
static void test_it_fault_delay_full(void **state)
{
	static const char *const args[] = { "--delay", "700", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, false, DF1_CHECK_CRC, false, args, 3);
	int16_t v = 0;

	OK(h, df1_set_cmd_timeout_ms(h, 2000));
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:5", &v, 1)), 1);
	assert_int_equal(v, 5);
	OK(h, df1_set_cmd_timeout_ms(h, 500));
	assert_int_equal(df1_read_int16(h, 1, "N7:6", &v, 1), DF1_E_TIMEOUT);
	assert_int_equal(df1_last_error(h)->catalog_id, 2508);
	assert_true(cnt(h, 2545) >= 1);         /* CNT_COMMAND_TIMEOUTS */
	OK(h, df1_set_cmd_timeout_ms(h, 2000));
	v = 0;
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:7", &v, 1)), 1);
	assert_int_equal(v, 7);
}

static void test_it_fault_delay_half(void **state)
{
	static const char *const args[] = { "--duplex", "half", "--delay", "700", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, true, DF1_CHECK_CRC, false, args, 3);
	int16_t v = 0;
	int rc;

	OK(h, df1_set_cmd_timeout_ms(h, 2000));
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:5", &v, 1)), 1);
	assert_int_equal(v, 5);
	assert_true(cnt(h, 2538) >= 1);         /* EOTs while the reply was held back */
	OK(h, df1_set_cmd_timeout_ms(h, 500));
	rc = df1_read_int16(h, 1, "N7:6", &v, 1);
	assert_true(rc == DF1_E_TIMEOUT || rc == DF1_E_ENQ_LIMIT);
	assert_int_equal(df1_station_active(h, 1), 0);
	OK(h, df1_set_cmd_timeout_ms(h, 2000));
	v = 0;
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:7", &v, 1)), 1);
	assert_int_equal(v, 7);
	assert_int_equal(df1_station_active(h, 1), 1);
}

/* Half duplex: a silent station fails, is marked inactive, and the next
 * transaction fails at once with DF1_E_INACTIVE after one poll. */
static void test_it_fault_silent_half_inactive(void **state)
{
	static const char *const args[] = { "--duplex", "half", "--station", "1,2", "--silent", "2", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, true, DF1_CHECK_CRC, false, args, 2);
	uint64_t polls, sent, cmds;
	int16_t v = 0;
	int rc;

	assert_int_equal(df1_station_active(h, 2), 1);
	rc = df1_read_int16(h, 2, "N7:1", &v, 1);
	assert_true(rc == DF1_E_TIMEOUT || rc == DF1_E_ENQ_LIMIT || rc == DF1_E_NAK_LIMIT);
	assert_int_equal(df1_station_active(h, 2), 0);

	polls = cnt(h, 2531);
	sent = cnt(h, 2525);
	cmds = cnt(h, 2527);
	rc = df1_read_int16(h, 2, "N7:1", &v, 1);
	assert_int_equal(rc, DF1_E_INACTIVE);
	assert_int_equal(df1_error_catalog_id(rc), 2509);
	assert_int_equal(df1_last_error(h)->code, DF1_E_INACTIVE);
	assert_int_equal(df1_last_error(h)->catalog_id, 2509);
	assert_int_equal(df1_last_error(h)->station, 2);
	assert_int_equal(cnt(h, 2531) - polls, 1);      /* one poll */
	assert_int_equal(cnt(h, 2525) - sent, 0);       /* no message sent */
	assert_int_equal(cnt(h, 2527) - cmds, 0);
	assert_int_equal(df1_station_active(h, 2), 0);

	/* the other station on the line is fine */
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:1", &v, 1)), 1);
	assert_int_equal(v, 1);
	assert_int_equal(df1_station_active(h, 1), 1);
}

/* Full duplex has no active station list: silence is the ENQ limit, each time. */
static void test_it_fault_silent_full(void **state)
{
	static const char *const args[] = { "--silent", "1", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, false, DF1_CHECK_CRC, false, args, 2);
	int16_t v;

	df1_counters_reset(h);
	assert_int_equal(df1_read_int16(h, 1, "N7:1", &v, 1), DF1_E_ENQ_LIMIT);
	assert_int_equal(df1_last_error(h)->catalog_id, 2520);
	assert_int_equal(cnt(h, 2543), 2);      /* CNT_ENQ_RETRIES */
	assert_int_equal(cnt(h, 2544), 1);      /* CNT_ENQ_LIMIT_EXCEEDED */
	assert_int_equal(df1_link_test(h, 1), DF1_E_TIMEOUT);
}

/* --seed makes the faults repeatable: two runs of df1sim with the same seed
 * and the same traffic inject the same faults (the same NAKs, corrupted
 * replies, stale copies and noise, seen in the client's counters). */
static void test_it_fault_seed_repeatable(void **state)
{
	static const char *const args[] = { "--nak", "25", "--corrupt", "25", "--stale", "25",
	                                    "--noise", "25", "--seed", "42", NULL };
	/* not 2560/2561: bytes depend on the client's TNS (a 10h byte is doubled) */
	static const int ids[] = { 2534, 2541, 2547, 2548, 2533, 2525, 2526, 2530 };
	struct fault_env *e = *state;
	uint64_t run[2][sizeof ids / sizeof ids[0]];
	int good[2];

	for (int k = 0; k < 2; k++) {
		df1_t *h = fault_start(e, false, DF1_CHECK_CRC, false, args, 5);

		df1_counters_reset(h);
		good[k] = reads_right_or_clear(h, 1, 20);
		for (size_t i = 0; i < sizeof ids / sizeof ids[0]; i++)
			run[k][i] = cnt(h, ids[i]);
		df1_free(h);
		e->h = NULL;
		assert_int_equal(simproc_stop(&e->sim, false), 0);
	}
	assert_int_equal(good[0], good[1]);
	for (size_t i = 0; i < sizeof ids / sizeof ids[0]; i++)
		if (run[0][i] != run[1][i])
			fail_msg("counter %d: %llu then %llu with the same seed", ids[i],
			         (unsigned long long)run[0][i], (unsigned long long)run[1][i]);
	assert_true(run[0][0] >= 1);    /* faults did happen */
	assert_true(run[0][2] >= 1);
	assert_true(run[0][3] >= 1);
}

/* --line-baud: df1sim hands each byte over no earlier than a line at that
 * baud rate would deliver it (10 bits a character), so a read takes at least
 * the reply's time on the wire. A lower bound only: slower is always fine. */
static void test_it_line_baud_paces(void **state)
{
	static const char *const args[] = { "--line-baud", "9600", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, false, DF1_CHECK_CRC, false, args, 3);
	int16_t v[100];
	struct timespec a, b;
	long long ms, min_ms;

	OK(h, df1_set_timeout_ms(h, 2000));
	df1_counters_reset(h);
	clock_gettime(CLOCK_MONOTONIC, &a);
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:0", v, 100)), 100);
	clock_gettime(CLOCK_MONOTONIC, &b);
	for (int i = 0; i < 100; i++)
		assert_int_equal(v[i], i);
	ms = (long long)(b.tv_sec - a.tv_sec) * 1000 + (b.tv_nsec - a.tv_nsec) / 1000000;
	min_ms = (long long)cnt(h, 2561) * 10 * 1000 / 9600;  /* every byte it sent us */
	assert_true(cnt(h, 2561) > 200);
	if (ms + 2 < min_ms)
		fail_msg("%llu bytes at 9600 baud arrived in %lld ms (< %lld ms)",
		         (unsigned long long)cnt(h, 2561), ms, min_ms);
}

/* df1_link_test until it succeeds (want_ok) or fails, at most 20 times: a
 * signal to df1sim takes effect before the next byte it reads, but a poll
 * already on its way may still be answered. */
static bool link_test_until(df1_t *h, int station, bool want_ok)
{
	for (int i = 0; i < 20; i++)
		if ((df1_link_test(h, station) == 0) == want_ok)
			return true;
	return false;
}

/* df1sim SIGUSR1 silences every station, SIGUSR2 brings them back, without a
 * restart (same process, same pty): half duplex with the active station list,
 * then full duplex. */
static void test_it_sim_sigusr_silences_all(void **state)
{
	static const char *const args_h[] = { "--duplex", "half", "--station", "1,2", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, true, DF1_CHECK_CRC, false, args_h, 2);
	pid_t pid = e->sim.pid;
	int16_t v = 0;
	int rc;

	for (int st = 1; st <= 2; st++) {
		assert_int_equal(OK(h, df1_read_int16(h, st, "N7:3", &v, 1)), 1);
		assert_int_equal(v, 3);
	}
	assert_int_equal(kill(pid, SIGUSR1), 0);
	assert_true(link_test_until(h, 1, false));
	for (int st = 1; st <= 2; st++) {
		rc = df1_read_int16(h, st, "N7:3", &v, 1);
		assert_true(link_error(rc));
		assert_int_equal(df1_station_active(h, st), 0);
		/* inactive now: one poll, then DF1_E_INACTIVE at once */
		assert_int_equal(df1_read_int16(h, st, "N7:3", &v, 1), DF1_E_INACTIVE);
	}
	assert_int_equal(kill(pid, SIGUSR2), 0);
	assert_true(link_test_until(h, 1, true));
	for (int st = 1; st <= 2; st++) {
		v = 0;
		assert_int_equal(OK(h, df1_read_int16(h, st, "N7:4", &v, 1)), 1);
		assert_int_equal(v, 4);
		assert_int_equal(df1_station_active(h, st), 1);
	}
	assert_int_equal(e->sim.pid, pid);
	df1_free(h);
	e->h = NULL;
	assert_int_equal(simproc_stop(&e->sim, false), 0);

	/* full duplex: not even the DLE ENQs are answered */
	h = fault_start(e, false, DF1_CHECK_CRC, false, NULL, 2);
	pid = e->sim.pid;
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:5", &v, 1)), 1);
	assert_int_equal(kill(pid, SIGUSR1), 0);
	assert_true(link_test_until(h, 1, false));
	df1_counters_reset(h);
	assert_int_equal(df1_read_int16(h, 1, "N7:5", &v, 1), DF1_E_ENQ_LIMIT);
	assert_int_equal(cnt(h, 2536), 0);      /* no ACK, no response to the ENQs */
	assert_int_equal(cnt(h, 2534), 0);
	assert_int_equal(kill(pid, SIGUSR2), 0);
	assert_true(link_test_until(h, 1, true));
	v = 0;
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:6", &v, 1)), 1);
	assert_int_equal(v, 6);
}

/* df1sim -d DEV: df1sim opens an existing tty with df1_open (termios backend:
 * exclusive, raw, its serial settings) and serves it; another process cannot
 * open the port meanwhile ("port busy"); when df1sim stops, the tty has its
 * settings back. The test holds the pty master and is the half-duplex master. */
static void test_it_sim_serves_device(void **state)
{
	static const char *const args[] = { "--duplex", "half", "--check", "bcc", "--station", "3",
	                                    "-b", "9600", NULL };
	struct fault_env *e = *state;
	struct termios t, before, during, after;
	char path[64];
	df1_t *h = NULL, *h2 = NULL;
	int16_t v = 0;
	int m = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);

	assert_true(m >= 0);
	assert_int_equal(grantpt(m), 0);
	assert_int_equal(unlockpt(m), 0);
	assert_int_equal(ptsname_r(m, path, sizeof path), 0);
	assert_int_equal(tcgetattr(m, &t), 0);
	cfsetispeed(&t, B4800);
	cfsetospeed(&t, B4800);
	t.c_cflag |= CSTOPB;
	assert_int_equal(tcsetattr(m, TCSANOW, &t), 0);

	assert_int_equal(df1_new(&h), 0);
	e->h = h;
	OK(h, df1_set_duplex(h, DF1_HALF_DUPLEX_MASTER));
	OK(h, df1_set_check(h, DF1_CHECK_BCC));
	OK(h, df1_set_timeout_ms(h, 300));
	OK(h, df1_open_fd(h, m, false));        /* raw: the state df1sim will find */
	assert_int_equal(tcgetattr(m, &before), 0);

	if (simproc_start_device(&e->sim, path, NULL, false, args) < 0)
		fail_msg("df1sim -d %s did not start", path);
	assert_string_equal(e->sim.target, path);
	assert_int_equal(tcgetattr(m, &during), 0);
	assert_true(cfgetospeed(&during) == B9600);
	assert_false(during.c_cflag & CSTOPB);
	assert_false(during.c_lflag & (ICANON | ECHO | ISIG));

	assert_int_equal(OK(h, df1_read_int16(h, 3, "N7:5", &v, 1)), 1);
	assert_int_equal(v, 5);
	v = -9;
	assert_int_equal(OK(h, df1_write_int16(h, 3, "N7:6", &v, 1)), 1);
	assert_int_equal(OK(h, df1_read_int16(h, 3, "N7:5", &v, 1)), 1);
	assert_int_equal(v, 5);

	/* a second process's open of the port df1sim serves: port busy */
	assert_int_equal(df1_new(&h2), 0);
	assert_int_equal(df1_open(h2, path), DF1_E_BUSY);
	assert_non_null(strstr(df1_last_error(h2)->message, "port busy"));
	assert_false(df1_is_open(h2));
	df1_free(h2);

	assert_int_equal(simproc_stop(&e->sim, false), 0);
	assert_int_equal(tcgetattr(m, &after), 0);
	assert_true(tios_equal(&before, &after));
	assert_true(cfgetospeed(&after) == B4800);
	df1_free(h);
	e->h = NULL;
	close(m);
}

/* Stale replies: df1sim --stale sends a copy of the reply with TNS - 2 first,
 * never the TNS of the reply the master accepted last, so it is counted as a
 * stale message (2548), not a duplicate (2549): ACKed, dropped and never
 * returned as data. */
static void stale_run(struct fault_env *e, bool half)
{
	struct client_cfg c = {
		half ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX, DF1_CHECK_CRC, DF1_PLC_SLC, 200, 500, 3, 3,
	};
	uint64_t stale = 0, dup = 0;
	df1_t *h;

	/* a fresh handle per read: every stale copy is a stale message */
	for (int k = 0; k < 12; k++) {
		h = e->h = client_open(e->sim.target, &c);
		assert_int_equal(reads_right_or_clear(h, 1, 1), 1);
		stale += cnt(h, 2548);
		assert_int_equal(cnt(h, 2549), 0);
		assert_int_equal(cnt(h, 2530), 1);
		df1_free(h);
		e->h = NULL;
	}
	assert_true(stale >= 1);
	/* one handle, many reads: stale every time, never a duplicate, never data */
	h = e->h = client_open(e->sim.target, &c);
	assert_int_equal(reads_right_or_clear(h, 1, 20), 20);
	stale = cnt(h, 2548);
	dup = cnt(h, 2549);
	assert_true(stale >= 1);
	assert_int_equal(dup, 0);
	assert_int_equal(cnt(h, 2530), 20);
	assert_int_equal(cnt(h, 2527), 20);
}

static void test_it_fault_stale(void **state)
{
	static const char *const args_f[] = { "--stale", "50", "--seed", "9", NULL };
	static const char *const args_h[] = { "--duplex", "half", "--stale", "50", "--seed", "9", NULL };
	struct fault_env *e = *state;

	if (simproc_start(&e->sim, false, NULL, false, args_f) < 0)
		fail_msg("df1sim did not start");
	stale_run(e, false);
	df1_free(e->h);
	e->h = NULL;
	assert_int_equal(simproc_stop(&e->sim, false), 0);
	if (simproc_start(&e->sim, false, NULL, false, args_h) < 0)
		fail_msg("df1sim did not start");
	stale_run(e, true);
}

/* Everything the client received, for the noise test. */
struct rx_capture {
	uint8_t buf[32768];
	size_t n;
};

static void rx_trace(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us)
{
	struct rx_capture *c = user;

	(void)t_us;
	if (dir != DF1_DIR_RX)
		return;
	if (n > sizeof c->buf - c->n)
		n = sizeof c->buf - c->n;
	memcpy(c->buf + c->n, bytes, n);
	c->n += n;
}

/* Bytes of the capture that are not part of any symbol: the noise. */
static size_t rx_noise_bytes(const struct rx_capture *c, enum df1_check check, bool half)
{
	struct df1_decoder *d = NULL;
	size_t pos = 0, in_symbols = 0;

	assert_int_equal(df1_decoder_new(&d, check), 0);
	assert_int_equal(df1_decoder_set_half_duplex(d, half), 0);
	while (pos < c->n) {
		struct df1_symbol sym;
		size_t used = df1_decoder_feed(d, c->buf + pos, c->n - pos, &sym);

		if (used == 0)
			break;
		pos += used;
		if (sym.kind != DF1_SYM_NONE && sym.kind != DF1_SYM_ERROR)
			in_symbols += sym.wire_len;
	}
	df1_decoder_free(d);
	return c->n - in_symbols;
}

static void test_it_fault_noise(void **state)
{
	static const char *const args_f[] = { "--noise", "40", "--seed", "2", NULL };
	static const char *const args_h[] = { "--duplex", "half", "--check", "bcc", "--noise", "40",
	                                      "--seed", "2", NULL };
	struct fault_env *e = *state;
	df1_t *h = fault_start(e, false, DF1_CHECK_CRC, false, args_f, 3);
	static struct rx_capture cap;
	int16_t v[300];

	cap.n = 0;
	df1_set_trace(h, rx_trace, &cap);
	assert_true(reads_right_or_clear(h, 1, 15) >= 14);
	df1_set_trace(h, NULL, NULL);
	assert_true(rx_noise_bytes(&cap, DF1_CHECK_CRC, false) >= 3);   /* noise was there */
	assert_int_equal(OK(h, df1_read_int16(h, 1, "N7:0", v, 256)), 256);
	for (int i = 0; i < 256; i++)
		assert_int_equal(v[i], i);
	df1_free(h);
	e->h = NULL;
	assert_int_equal(simproc_stop(&e->sim, false), 0);

	h = fault_start(e, true, DF1_CHECK_BCC, false, args_h, 3);
	cap.n = 0;
	df1_set_trace(h, rx_trace, &cap);
	assert_true(reads_right_or_clear(h, 1, 15) >= 14);
	df1_set_trace(h, NULL, NULL);
	assert_true(rx_noise_bytes(&cap, DF1_CHECK_BCC, true) >= 3);
}

/* ------------------------------------------------------------------------ */

/* df1write run again and again at exact multiples of 65.536 ms (the period
 * of a microsecond clock modulo 65536) against df1sim with duplicate
 * detection (its default): each run is a new process whose first command
 * must not carry the previous run's TNS, else df1sim ACKs it as a duplicate,
 * drops it and the write is lost. Every run must succeed and df1sim's log must
 * hold each write exactly once. */
#define WRITE_RUNS 24            /* DF1_TNS_RUNS=n (up to 2000) for a longer measurement */

static void test_it_runs_65ms_apart_write_once(void **state)
{
	struct fault_env *e = *state;
	const char *bin = getenv("DF1_BIN"), *env = getenv("DF1_TNS_RUNS");
	int runs = env && atoi(env) > 1 && atoi(env) <= 2000 ? atoi(env) : WRITE_RUNS;
	char exe[512], arg[32], needle[48];
	unsigned *tns = calloc((size_t)runs, sizeof *tns);
	struct timespec t0;
	const char *log;
	int failed = 0, near = 0, same = 0, missing = 0;
	long long late = 0;

	assert_non_null(tns);
	if (!bin || !*bin)
		bin = "build/bin";
	snprintf(exe, sizeof exe, "%s/df1write", bin);
	if (simproc_start(&e->sim, false, NULL, true, NULL) != 0)
		fail_msg("df1sim did not start");
	clock_gettime(CLOCK_MONOTONIC, &t0);
	for (int i = 0; i < runs; i++) {
		long long ns = (long long)t0.tv_nsec + (long long)(i + 1 + late) * 65536000LL;
		struct timespec at = { t0.tv_sec + (time_t)(ns / 1000000000LL), (long)(ns % 1000000000LL) };
		struct timespec now;
		pid_t pid;
		int st;

		/* the value names the run: N7:(20 + i % 230) = i */
		snprintf(arg, sizeof arg, "N7:%d=%d", 20 + i % 230, i % 30000);
		while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, NULL) == EINTR)
			;
		pid = fork();
		assert_true(pid >= 0);
		if (pid == 0) {
			int fd = open("/dev/null", O_WRONLY);

			if (fd >= 0) {
				dup2(fd, 1);
				dup2(fd, 2);
			}
			execl(exe, "df1write", "-d", e->sim.target, arg, (char *)NULL);
			_exit(127);
		}
		assert_int_equal(waitpid(pid, &st, 0), pid);
		if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) {
			print_message("run %d (%s): exit %d\n", i, arg, WIFEXITED(st) ? WEXITSTATUS(st) : -1);
			failed++;
		}
		/* df1sim logs a write after its reply went out: wait for the line
		 * (a write dropped as a duplicate never comes: 300 ms) */
		for (int w = 0; w < 300; w++) {
			char *text = simproc_slurp(e->sim.log, NULL);
			int k = text ? log_lines(text, "cmd=0F/AA", NULL, NULL, 0) : 0;

			free(text);
			if (k >= i + 1 - missing)
				break;
			if (w == 299) {
				print_message("run %d (%s): not in df1sim's log\n", i, arg);
				missing++;
			}
			usleep(1000);
		}
		/* a run that overran its slot (a lost write waits for its timeout):
		 * the next starts on the next multiple of 65.536 ms */
		clock_gettime(CLOCK_MONOTONIC, &now);
		while ((long long)(now.tv_sec - t0.tv_sec) * 1000000000LL + now.tv_nsec - t0.tv_nsec >
		       (long long)(i + 2 + late) * 65536000LL)
			late++;
	}
	log = fault_stop_log(e);
	for (int i = 0; i < runs; i++) {
		int k;

		snprintf(needle, sizeof needle, "cmd=0F/AA addr=N7:%d ", 20 + i % 230);
		k = log_lines(log, needle, NULL, NULL, 0);
		if (runs <= 230 && k != 1)
			fail_msg("%s: %d lines in df1sim's log, want 1", needle, k);
	}
	/* the TNS of each write df1sim took, in order */
	{
		int n = log_lines(log, "cmd=0F/AA", NULL, tns, runs);

		assert_int_equal(n, runs - missing);
		for (int i = 1; i < n && i < runs; i++) {
			unsigned d = (tns[i] - tns[i - 1]) & 0xFFFFu;

			near += (d < 0x8000u ? d : 0x10000u - d) <= 4096;
			same += d == 0;
		}
	}
	print_message("%d df1write runs 65.536 ms apart: %d failed, %d writes missing from df1sim's "
	              "log, %d first TNS within 4096 of the previous run's, %d equal\n", runs, failed,
	              missing, near, same);
	free(tns);
	assert_int_equal(failed, 0);
	assert_int_equal(missing, 0);
	/* random: P(near) = 8193 / 65536, about 2.9 of 23 pairs; 11 or more has
	 * a probability below 4e-5 (a clock's start: most of them) */
	if (runs == WRITE_RUNS)
		assert_true(near <= 10);
}

#define GROUP_TEST(f) cmocka_unit_test_teardown(f, test_teardown)
#define FAULT_TEST(f) cmocka_unit_test_setup_teardown(f, fault_setup, fault_teardown)

int main(void)
{
	const struct CMUnitTest full_crc[] = {
		GROUP_TEST(test_it_read_n_300_words_and_negatives_above_254),
		GROUP_TEST(test_it_read_floats),
		GROUP_TEST(test_it_read_strings),
		GROUP_TEST(test_it_read_timer_counter_control),
		GROUP_TEST(test_it_file_300),
		GROUP_TEST(test_it_o_i_s_a_words),
		GROUP_TEST(test_it_counters_one_read),
		GROUP_TEST(test_it_link_test_echo_diag),
		GROUP_TEST(test_it_bit_write_keeps_other_bits),
		GROUP_TEST(test_it_write_read_back),
		GROUP_TEST(test_it_port_busy),
		GROUP_TEST(test_it_termios_restored),
		GROUP_TEST(test_it_bad_settings_on_open_handle),
		GROUP_TEST(test_it_net_config_file),
		GROUP_TEST(test_it_slc_io_codes_82),
	};
	const struct CMUnitTest full_bcc_micrologix[] = {
		GROUP_TEST(test_it_read_n_300_words_and_negatives_above_254),
		GROUP_TEST(test_it_read_strings),
		GROUP_TEST(test_it_long),
		GROUP_TEST(test_it_bit_write_keeps_other_bits),
		GROUP_TEST(test_it_link_test_echo_diag),
		GROUP_TEST(test_it_net_config_file),
	};
	const struct CMUnitTest half_multi[] = {
		GROUP_TEST(test_it_half_several_stations),
		GROUP_TEST(test_it_counters_one_read),
		GROUP_TEST(test_it_read_n_300_words_and_negatives_above_254),
		GROUP_TEST(test_it_read_floats),
		GROUP_TEST(test_it_read_timer_counter_control),
		GROUP_TEST(test_it_link_test_echo_diag),
		GROUP_TEST(test_it_bit_write_keeps_other_bits),
	};
	const struct CMUnitTest half_bcc[] = {
		GROUP_TEST(test_it_counters_one_read),
		GROUP_TEST(test_it_o_i_s_a_words),
		GROUP_TEST(test_it_read_strings),
		GROUP_TEST(test_it_file_300),
		GROUP_TEST(test_it_write_read_back),
	};
	const struct CMUnitTest plc5[] = {
		GROUP_TEST(test_it_read_n_300_words_and_negatives_above_254),
		GROUP_TEST(test_it_read_floats),
		GROUP_TEST(test_it_read_strings),
		GROUP_TEST(test_it_read_timer_counter_control),
		GROUP_TEST(test_it_file_300),
		GROUP_TEST(test_it_plc5_ascii_address_and_bits),
		GROUP_TEST(test_it_o_i_s_a_words),
		GROUP_TEST(test_it_bit_write_keeps_other_bits),
		GROUP_TEST(test_it_write_read_back),
		GROUP_TEST(test_it_link_test_echo_diag),
	};
	const struct CMUnitTest slc502[] = {   /* 82-byte packets */
		GROUP_TEST(test_it_read_n_300_words_and_negatives_above_254),
		GROUP_TEST(test_it_read_floats),
		GROUP_TEST(test_it_read_timer_counter_control),
		GROUP_TEST(test_it_bit_write_keeps_other_bits),
	};
	const struct CMUnitTest tcp_full[] = {
		GROUP_TEST(test_it_counters_one_read),
		GROUP_TEST(test_it_read_n_300_words_and_negatives_above_254),
		GROUP_TEST(test_it_read_strings),
		GROUP_TEST(test_it_write_read_back),
		GROUP_TEST(test_it_link_test_echo_diag),
	};
	const struct CMUnitTest tcp_half[] = {
		GROUP_TEST(test_it_read_n_300_words_and_negatives_above_254),
		GROUP_TEST(test_it_bit_write_keeps_other_bits),
	};
	const struct CMUnitTest faults[] = {
		FAULT_TEST(test_it_fault_drop_ack_full_writes_once),
		FAULT_TEST(test_it_fault_drop_ack_half_writes_once),
		FAULT_TEST(test_it_fault_combined_full_writes_once),
		FAULT_TEST(test_it_fault_corrupt),
		FAULT_TEST(test_it_fault_nak),
		FAULT_TEST(test_it_fault_delay_full),
		FAULT_TEST(test_it_fault_delay_half),
		FAULT_TEST(test_it_fault_silent_half_inactive),
		FAULT_TEST(test_it_fault_silent_full),
		FAULT_TEST(test_it_fault_seed_repeatable),
		FAULT_TEST(test_it_line_baud_paces),
		FAULT_TEST(test_it_sim_sigusr_silences_all),
		FAULT_TEST(test_it_sim_serves_device),
		FAULT_TEST(test_it_fault_stale),
		FAULT_TEST(test_it_fault_noise),
	};
	const struct CMUnitTest options[] = {    /* a simulator per test, as the faults */
		FAULT_TEST(test_it_plc5_typed_float_swapped),
		FAULT_TEST(test_it_runs_65ms_apart_write_once),
	};
	int failed = 0;

	failed += cmocka_run_group_tests_name("pty full duplex CRC SLC", full_crc, setup_full_crc, group_stop);
	failed += cmocka_run_group_tests_name("pty full duplex BCC MicroLogix", full_bcc_micrologix,
	                                      setup_full_bcc, group_stop);
	failed += cmocka_run_group_tests_name("pty half duplex CRC stations 1,2,3", half_multi,
	                                      setup_half_multi, group_stop);
	failed += cmocka_run_group_tests_name("pty half duplex BCC station 16 (DLE)", half_bcc, setup_half_bcc,
	                                      group_stop);
	failed += cmocka_run_group_tests_name("pty full duplex PLC-5", plc5, setup_plc5, group_stop);
	failed += cmocka_run_group_tests_name("pty full duplex SLC 5/02", slc502, setup_slc502, group_stop);
	failed += cmocka_run_group_tests_name("tcp full duplex CRC", tcp_full, setup_tcp_full, group_stop);
	failed += cmocka_run_group_tests_name("tcp half duplex BCC", tcp_half, setup_tcp_half, group_stop);
	failed += cmocka_run_group_tests_name("faults", faults, NULL, NULL);
	failed += cmocka_run_group_tests_name("options against df1sim", options, NULL, NULL);
	return failed ? 1 : 0;
}
