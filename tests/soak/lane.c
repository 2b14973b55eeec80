/* SPDX-License-Identifier: MPL-2.0 */
/*
 * lane.c - one link setting of the soak (soak.h): a df1sim on a pty with every
 * fault at about 1 %, a handle on it, and a mix of operations whose results
 * are checked: reads of N7, B3, L10 and F8 against the shadow, writes and bit
 * writes with values unique to each (a counter), poll scans of tags on N20
 * with writes queued to them, a station that never answers (--silent), and
 * every station silenced for a moment (SIGUSR1 ... SIGUSR2).
 */
#include "soak.h"

#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define N7_N 100
#define B3_WORDS 8
#define L10_N 40
#define F8_N 40
#define TAGS 8

struct lane_state {
	uint64_t rng;
	uint32_t wseq;                  /* makes each written value unique */
	struct shadow_cell n7[N7_N], b3[B3_WORDS * 16], l10[L10_N], f8[F8_N], n20[TAGS];
	int tag_ids[TAGS];
	uint64_t tag_reads[TAGS];
	int tagw;                       /* tag with a queued write, -1 none */
	int16_t tagw_value;
	bool tagw_done;
	int tagw_result;
	int tagw_tns;                   /* its command's TNS once sent, -1 */
};

static uint64_t rnd(struct lane_state *s)
{
	/* xorshift64* */
	s->rng ^= s->rng >> 12;
	s->rng ^= s->rng << 25;
	s->rng ^= s->rng >> 27;
	return s->rng * 0x2545F4914F6CDD1Dull;
}

static unsigned below(struct lane_state *s, unsigned n)
{
	return (unsigned)(rnd(s) % n);
}

static int64_t now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static int32_t fbits(float f)
{
	int32_t b;

	memcpy(&b, &f, sizeof b);
	return b;
}

long soak_rss_kb(pid_t pid)
{
	char path[64], line[256];
	long kb = -1;
	FILE *f;

	if (pid > 0)
		snprintf(path, sizeof path, "/proc/%ld/status", (long)pid);
	else
		snprintf(path, sizeof path, "/proc/self/status");
	f = fopen(path, "r");
	if (!f)
		return -1;
	while (fgets(line, sizeof line, f))
		if (sscanf(line, "VmRSS: %ld", &kb) == 1)
			break;
	fclose(f);
	return kb;
}

/* ------------------------------------------------------------------------
 * Set-up
 * ------------------------------------------------------------------------ */

static void on_tag_write_done(void *user, int tag_id, int write_id, int result)
{
	struct lane_state *s = user;

	(void)tag_id;
	(void)write_id;
	s->tagw_done = true;
	s->tagw_result = result;
}

static int add_tags(struct lane *ln)
{
	struct lane_state *s = ln->st;

	for (int i = 0; i < TAGS; i++) {
		struct df1_tag_config c;

		memset(&c, 0, sizeof c);
		snprintf(c.name, sizeof c.name, "t%d", i);
		c.access = DF1_ACCESS_READWRITE;
		c.station = SOAK_STATION;
		c.plc = DF1_PLC_SLC;
		c.count = 1;
		c.scan_ms = 0;          /* every scan */
		if (df1_addr_parse(i == 0 ? "N20:0" : "N20:1", &c.addr) < 0)
			return -1;
		c.addr.element = i;
		s->tag_ids[i] = df1_tag_add(ln->h, &c);
		if (s->tag_ids[i] < 0)
			return -1;
		shadow_set(&s->n20[i], 0);
	}
	/* a station that misses a few scans must not go offline for long */
	return df1_poll_set_watchdog(ln->h, 60000, 0);
}

int lane_setup(struct lane *ln)
{
	char delay[32], seed[32], silent[16];
	const char *args[32];
	int a = 0;
	struct lane_state *s;

	s = calloc(1, sizeof *s);
	if (!s)
		return -1;
	ln->st = s;
	s->rng = ln->seed * 0x9E3779B97F4A7C15ull + 1;
	s->tagw = -1;
	s->tagw_tns = -1;
	for (int i = 0; i < N7_N; i++)
		shadow_set(&s->n7[i], i);               /* df1sim's initial N7:n = n */
	for (int i = 0; i < B3_WORDS * 16; i++)
		shadow_set(&s->b3[i], 0);
	for (int i = 0; i < L10_N; i++)
		shadow_set(&s->l10[i], i * 65536 + i);
	for (int i = 0; i < F8_N; i++)
		shadow_set(&s->f8[i], fbits((float)i + 0.5f));
	snprintf(delay, sizeof delay, "%d:1", SOAK_DELAY_MS);
	snprintf(seed, sizeof seed, "%llu", (unsigned long long)ln->seed);
	snprintf(silent, sizeof silent, "%d", SOAK_SILENT_STATION);
	args[a++] = "--duplex";
	args[a++] = ln->half ? "half" : "full";
	args[a++] = "--check";
	args[a++] = ln->check == DF1_CHECK_BCC ? "bcc" : "crc";
	args[a++] = "--station";
	args[a++] = ln->half ? "1,9" : "1";
	args[a++] = "--silent";
	args[a++] = silent;
	args[a++] = "--drop-ack";
	args[a++] = "1";
	args[a++] = "--corrupt";
	args[a++] = "1";
	args[a++] = "--nak";
	args[a++] = "1";
	args[a++] = "--delay";
	args[a++] = delay;
	args[a++] = "--stale";
	args[a++] = "1";
	args[a++] = "--noise";
	args[a++] = "1";
	args[a++] = "--seed";
	args[a++] = seed;
	args[a] = NULL;
	if (simproc_start(&ln->sp, false, "N20:0=0,0,0,0,0,0,0,0\n", true, args) < 0) {
		ln->error = "df1sim did not start";
		return -1;
	}
	if (ledger_init(&ln->led, ln->check, ln->half) < 0 || df1_new(&ln->h) < 0) {
		ln->error = "out of memory";
		return -1;
	}
	if (df1_set_duplex(ln->h, ln->half ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX) < 0 ||
	    df1_set_check(ln->h, ln->check) < 0 || df1_set_timeout_ms(ln->h, SOAK_TIMEOUT_MS) < 0 ||
	    df1_set_cmd_timeout_ms(ln->h, SOAK_CMD_TIMEOUT_MS) < 0 ||
	    df1_set_retries(ln->h, SOAK_RETRIES, SOAK_RETRIES) < 0 || add_tags(ln) < 0) {
		ln->error = df1_last_error(ln->h)->message;
		return -1;
	}
	df1_set_trace(ln->h, ledger_trace, &ln->led);
	if (df1_open(ln->h, ln->sp.target) < 0) {
		ln->error = df1_last_error(ln->h)->message;
		return -1;
	}
	return 0;
}

/* ------------------------------------------------------------------------
 * Operations
 * ------------------------------------------------------------------------ */

static void wrong(struct lane *ln, const char *what, const char *addr, long got)
{
	ln->fig.wrong++;
	if (ln->fig.wrong <= 20)
		fprintf(stderr, "soak: lane %d: %s %s: %ld, which no write explains\n", ln->id, what,
		        addr, got);
}

static int op_write_n7(struct lane *ln)
{
	struct lane_state *s = ln->st;
	unsigned e = below(s, N7_N - 3), n = 1 + below(s, 4);
	int16_t v[4];
	char addr[16];
	int r;

	for (unsigned i = 0; i < n; i++)
		v[i] = (int16_t)(++s->wseq);
	snprintf(addr, sizeof addr, "N7:%u", e);
	r = df1_write_int16(ln->h, SOAK_STATION, addr, v, n);
	for (unsigned i = 0; i < n; i++) {
		if (r >= 0)
			shadow_set(&s->n7[e + i], v[i]);
		else
			shadow_maybe(&s->n7[e + i], v[i]);
	}
	return r;
}

static int op_read_n7(struct lane *ln)
{
	struct lane_state *s = ln->st;
	unsigned n = 1 + below(s, 30), e = below(s, N7_N - n + 1);
	int16_t v[30];
	char addr[16];
	int r;

	snprintf(addr, sizeof addr, "N7:%u", e);
	r = df1_read_int16(ln->h, SOAK_STATION, addr, v, n);
	for (unsigned i = 0; r >= 0 && i < n; i++)
		if (!shadow_seen(&s->n7[e + i], v[i])) {
			snprintf(addr, sizeof addr, "N7:%u", e + i);
			wrong(ln, "read", addr, v[i]);
		}
	return r;
}

static int op_write_bit(struct lane *ln)
{
	struct lane_state *s = ln->st;
	unsigned w = below(s, B3_WORDS), b = below(s, 16);
	bool v = below(s, 2);
	char addr[16];
	int r;

	snprintf(addr, sizeof addr, "B3:%u/%u", w, b);
	r = df1_write_bit(ln->h, SOAK_STATION, addr, v);
	if (r >= 0)
		shadow_set(&s->b3[w * 16 + b], v);
	else
		shadow_maybe(&s->b3[w * 16 + b], v);
	return r;
}

static int op_read_b3(struct lane *ln)
{
	struct lane_state *s = ln->st;
	unsigned n = 1 + below(s, B3_WORDS), w = below(s, B3_WORDS - n + 1);
	int16_t v[B3_WORDS];
	char addr[16];
	int r;

	snprintf(addr, sizeof addr, "B3:%u", w);
	r = df1_read_int16(ln->h, SOAK_STATION, addr, v, n);
	for (unsigned i = 0; r >= 0 && i < n; i++)
		for (unsigned b = 0; b < 16; b++) {
			int bit = ((uint16_t)v[i] >> b) & 1;

			if (!shadow_seen(&s->b3[(w + i) * 16 + b], bit)) {
				snprintf(addr, sizeof addr, "B3:%u/%u", w + i, b);
				wrong(ln, "read", addr, bit);
			}
		}
	return r;
}

static int op_write_l10(struct lane *ln)
{
	struct lane_state *s = ln->st;
	unsigned e = below(s, L10_N - 1), n = 1 + below(s, 2);
	int32_t v[2];
	char addr[16];
	int r;

	for (unsigned i = 0; i < n; i++)
		v[i] = (int32_t)(++s->wseq * 2654435761u);      /* unique, both halves busy */
	snprintf(addr, sizeof addr, "L10:%u", e);
	r = df1_write_int32(ln->h, SOAK_STATION, addr, v, n);
	for (unsigned i = 0; i < n; i++) {
		if (r >= 0)
			shadow_set(&s->l10[e + i], v[i]);
		else
			shadow_maybe(&s->l10[e + i], v[i]);
	}
	return r;
}

static int op_read_l10(struct lane *ln)
{
	struct lane_state *s = ln->st;
	unsigned n = 1 + below(s, 10), e = below(s, L10_N - n + 1);
	int32_t v[10];
	char addr[16];
	int r;

	snprintf(addr, sizeof addr, "L10:%u", e);
	r = df1_read_int32(ln->h, SOAK_STATION, addr, v, n);
	for (unsigned i = 0; r >= 0 && i < n; i++)
		if (!shadow_seen(&s->l10[e + i], v[i])) {
			snprintf(addr, sizeof addr, "L10:%u", e + i);
			wrong(ln, "read", addr, v[i]);
		}
	return r;
}

static int op_write_f8(struct lane *ln)
{
	struct lane_state *s = ln->st;
	unsigned e = below(s, F8_N - 1), n = 1 + below(s, 2);
	float v[2];
	char addr[16];
	int r;

	for (unsigned i = 0; i < n; i++)
		v[i] = (float)(++s->wseq % 4194304u) + 0.25f;   /* exact in a float */
	snprintf(addr, sizeof addr, "F8:%u", e);
	r = df1_write_float(ln->h, SOAK_STATION, addr, v, n);
	for (unsigned i = 0; i < n; i++) {
		if (r >= 0)
			shadow_set(&s->f8[e + i], fbits(v[i]));
		else
			shadow_maybe(&s->f8[e + i], fbits(v[i]));
	}
	return r;
}

static int op_read_f8(struct lane *ln)
{
	struct lane_state *s = ln->st;
	unsigned n = 1 + below(s, 10), e = below(s, F8_N - n + 1);
	float v[10];
	char addr[16];
	int r;

	snprintf(addr, sizeof addr, "F8:%u", e);
	r = df1_read_float(ln->h, SOAK_STATION, addr, v, n);
	for (unsigned i = 0; r >= 0 && i < n; i++)
		if (!shadow_seen(&s->f8[e + i], fbits(v[i]))) {
			snprintf(addr, sizeof addr, "F8:%u", e + i);
			wrong(ln, "read", addr, (long)v[i]);
		}
	return r;
}

/* The station that never answers: a success from it is a wrong value. */
static int op_silent(struct lane *ln)
{
	int16_t v;
	int r = df1_read_int16(ln->h, SOAK_SILENT_STATION, "N7:0", &v, 1);

	if (r >= 0)
		wrong(ln, "silent station answered", "N7:0", v);
	return r < 0 ? 0 : -1;  /* its failure is the expected outcome */
}

/* One df1_poll: a scan of the N20 tags, maybe with a write queued to one. */
static int op_poll(struct lane *ln)
{
	struct lane_state *s = ln->st;
	int r;

	if (s->tagw < 0 && below(s, 2) == 0) {
		struct df1_value v;
		int t = (int)below(s, TAGS);

		v.kind = DF1_VAL_INT16;
		v.v.i16 = (int16_t)(++s->wseq);
		if (df1_tag_write(ln->h, s->tag_ids[t], &v, 1, on_tag_write_done, s) > 0) {
			s->tagw = t;
			s->tagw_value = v.v.i16;
			s->tagw_done = false;
			s->tagw_tns = -1;
			ln->fig.tag_writes++;
		}
	}
	r = df1_poll(ln->h, 0);
	ln->fig.polls++;
	if (s->tagw >= 0 && s->tagw_tns < 0)
		s->tagw_tns = ledger_call_write_tns(&ln->led);
	for (int i = 0; i < TAGS; i++) {
		struct df1_tag_state st;
		bool writing = i == s->tagw;

		if (df1_tag_get(ln->h, s->tag_ids[i], &st) < 0 || st.reads == s->tag_reads[i])
			continue;
		s->tag_reads[i] = st.reads;
		if (st.quality != DF1_QUALITY_GOOD)
			continue;
		if (writing) {
			/* before or after the write: either value */
			if (!shadow_possible(&s->n20[i], st.value.v.i16) && st.value.v.i16 != s->tagw_value)
				wrong(ln, "poll", st.config->name, st.value.v.i16);
		} else if (!shadow_seen(&s->n20[i], st.value.v.i16)) {
			wrong(ln, "poll", st.config->name, st.value.v.i16);
		}
	}
	if (s->tagw >= 0 && s->tagw_done) {
		if (s->tagw_result == 0)
			shadow_set(&s->n20[s->tagw], s->tagw_value);
		else
			shadow_maybe(&s->n20[s->tagw], s->tagw_value);
		if (s->tagw_tns >= 0)
			ledger_set_result(&ln->led, s->tagw_tns, s->tagw_result == 0);
		s->tagw = -1;
	}
	return r;
}

/* ------------------------------------------------------------------------
 * The loop
 * ------------------------------------------------------------------------ */

static int64_t call_bound_ms(int transactions)
{
	int64_t one = SOAK_CMD_TIMEOUT_MS +
	              (int64_t)(SOAK_RETRIES + 1) * (SOAK_RETRIES + 1) * SOAK_TIMEOUT_MS;

	return one * (transactions > 1 ? transactions : 1) + SOAK_HANG_MARGIN_MS;
}

void *lane_run(void *arg)
{
	struct lane *ln = arg;
	struct lane_state *s = ln->st;
	uint64_t next_report = 100000;
	int64_t start = now_ms();

	while (atomic_load(ln->done) < ln->target) {
		unsigned pick = below(s, 1000);
		bool silence = below(s, 100) == 0;
		int64_t t0, dt;
		int r, sent;

		if (silence) {
			kill(ln->sp.pid, SIGUSR1);
			ln->fig.silenced++;
		}
		ledger_call_begin(&ln->led);
		t0 = now_ms();
		if (pick < 250)
			r = op_write_n7(ln);
		else if (pick < 450)
			r = op_read_n7(ln);
		else if (pick < 550)
			r = op_write_bit(ln);
		else if (pick < 620)
			r = op_read_b3(ln);
		else if (pick < 670)
			r = op_write_l10(ln);
		else if (pick < 700)
			r = op_read_l10(ln);
		else if (pick < 750)
			r = op_write_f8(ln);
		else if (pick < 780)
			r = op_read_f8(ln);
		else if (pick < 990)
			r = op_poll(ln);
		else
			r = op_silent(ln);
		dt = now_ms() - t0;
		sent = ledger_call_sent(&ln->led);
		atomic_fetch_add(ln->done, (uint64_t)sent);
		if (pick < 780)
			ledger_call_result(&ln->led, r >= 0);
		if (silence)
			kill(ln->sp.pid, SIGUSR2);
		ln->fig.calls++;
		if (r >= 0)
			ln->fig.ok++;
		else
			ln->fig.failed++;
		if (dt > ln->fig.max_call_ms)
			ln->fig.max_call_ms = dt;
		if (dt > call_bound_ms(sent)) {
			ln->fig.hangs++;
			fprintf(stderr, "soak: lane %d: a call took %lld ms (bound %lld ms)\n", ln->id,
			        (long long)dt, (long long)call_bound_ms(sent));
		}
		if (ledger_follow(&ln->led, ln->sp.log) < 0) {
			ln->error = "df1sim's log cannot be read";
			break;
		}
		if (ln->id == 0 && atomic_load(ln->done) >= next_report) {
			fprintf(stderr, "soak: %llu transactions, %.0f s\n",
			        (unsigned long long)atomic_load(ln->done), (now_ms() - start) / 1000.0);
			next_report += 100000;
		}
	}
	ln->fig.transactions = ln->led.gen;
	ln->fig.elapsed_ms = now_ms() - start;
	return NULL;
}

int lane_finish(struct lane *ln)
{
	int r = 0;

	if (ln->h)
		df1_close(ln->h);
	if (ln->sp.pid > 0 && simproc_stop(&ln->sp, true) != 0)
		r = -1;
	if (ln->led.recs) {
		if (ledger_follow(&ln->led, ln->sp.log) < 0)
			r = -1;
		ledger_close_all(&ln->led);
	}
	simproc_cleanup(&ln->sp);
	/* queued writes end at df1_free; the shadow needs them no more */
	df1_free(ln->h);
	ln->h = NULL;
	if (ln->led.recs)       /* else never set up: nothing to free */
		ledger_free(&ln->led);
	free(ln->st);
	ln->st = NULL;
	return r;
}
