/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_buffer.c - df1gw's store and forward buffer (tools/df1gw/gw_buffer.c,
 * gw_buffer_sql.c) on real SQLite files in a temporary folder and in memory:
 * order, acknowledgement, restart and a crash (a child that appends and
 * _exit()s without closing), the bounds with exact drop counts, a full disk
 * (RLIMIT_FSIZE in a child), records in flight (handed over, awaiting their
 * PUBACK) outside the bounds and never dropped, an unusable path, a corrupt and a foreign file
 * moved aside, a second opener refused; the parsers of --buffer-max and
 * --buffer-max-age.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sqlite3.h>

#include "df1gw/gw_buffer.h"

static char dir[256];

static int setup(void **state)
{
	(void)state;
	snprintf(dir, sizeof dir, "%s/gwbufXXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
	char cmd[300];

	(void)state;
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	return system(cmd) == 0 ? 0 : -1;
}

static const char *file(const char *name)
{
	static char p[400];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	return p;
}

/* Record i: tag "T<i>", data "v<i>" (so that its size is known), read at ms. */
static int put(struct gw_buffer *b, int i, int64_t ms)
{
	char key[16], data[16];
	snprintf(key, sizeof key, "T%d", i % 10);
	snprintf(data, sizeof data, "v%06d", i);
	struct gw_buffer_rec r = { .kind = GW_BUFFER_TAG, .id = i, .quality = 192, .ms = ms, .key = key,
	                           .data = data, .len = strlen(data) };
	return gw_buffer_append(b, &r, ms);
}

static struct gw_buffer *open_ok(const char *path, const struct gw_buffer_limits *lim)
{
	struct gw_buffer *b;
	char err[400];
	int rc = gw_buffer_open(&b, path, lim, err, sizeof err);
	if (rc != 0)
		fail_msg("open %s: %s", path ? path : "(memory)", err);
	return b;
}

/* The ids peeked (up to 64), without handing them over. */
static int ids(struct gw_buffer *b, int *out, size_t max)
{
	const struct gw_buffer_rec *r;
	int n = gw_buffer_peek(b, max, &r);
	for (int i = 0; i < n; i++)
		out[i] = r[i].id;
	return n;
}

static void order_and_ack(const char *path)
{
	struct gw_buffer_limits lim = { 0 };
	struct gw_buffer *b = open_ok(path, &lim);
	const struct gw_buffer_rec *r;
	struct gw_buffer_stats s;

	for (int i = 0; i < 10; i++)
		assert_int_equal(put(b, i, 1000 + i), 0);
	assert_int_equal(gw_buffer_peek(b, 4, &r), 4);
	for (int i = 0; i < 4; i++) {
		assert_int_equal(r[i].id, i);
		assert_int_equal(r[i].seq, (uint64_t)i + 1);
		assert_int_equal(r[i].ms, 1000 + i);
		assert_int_equal(r[i].kind, GW_BUFFER_TAG);
		assert_int_equal(r[i].quality, 192);
		assert_int_equal(r[i].len, 7);
		char want[16];
		snprintf(want, sizeof want, "v%06d", i);
		assert_memory_equal(r[i].data, want, 7);
	}
	gw_buffer_handed(b, r[3].seq);
	assert_int_equal(gw_buffer_peek(b, 100, &r), 6);
	assert_int_equal(r[0].id, 4);
	/* PUBACKs for 1, 3 (out of order is fine), 2 */
	assert_int_equal(gw_buffer_ack(b, 1), 0);
	assert_int_equal(gw_buffer_ack(b, 3), 0);
	assert_int_equal(gw_buffer_ack(b, 3), 0);
	assert_int_equal(gw_buffer_ack(b, 2), 0);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.records, 7);
	assert_int_equal(s.acked, 3);
	assert_int_equal(s.bytes, 7 * (7 + 2 + GW_BUFFER_REC_OVERHEAD));
	assert_int_equal(s.oldest_ms, 1003);
	/* the connection dropped: 4 (handed, not acked) comes again first */
	gw_buffer_rewind(b);
	int got[16];
	assert_int_equal(ids(b, got, 16), 7);
	for (int i = 0; i < 7; i++)
		assert_int_equal(got[i], 3 + i);
	assert_int_equal(s.in_memory, path == NULL);
	gw_buffer_close(b);
}

static void test_order_ack_file(void **state)
{
	(void)state;
	order_and_ack(file("order.db"));
}

static void test_order_ack_memory(void **state)
{
	(void)state;
	order_and_ack(NULL);
}

static void test_restart_keeps_unacked(void **state)
{
	struct gw_buffer_limits lim = { 0 };
	const char *p = file("restart.db");
	struct gw_buffer *b = open_ok(p, &lim);
	int got[16];

	(void)state;
	for (int i = 0; i < 5; i++)
		put(b, i, 10 + i);
	gw_buffer_ack(b, 1);
	gw_buffer_close(b);
	b = open_ok(p, &lim);
	assert_int_equal(ids(b, got, 16), 4);
	assert_int_equal(got[0], 1);
	/* seq goes on, and is not reused once the file was emptied */
	for (uint64_t s = 2; s <= 5; s++)
		gw_buffer_ack(b, s);
	gw_buffer_close(b);
	b = open_ok(p, &lim);
	put(b, 99, 50);
	const struct gw_buffer_rec *r;
	assert_int_equal(gw_buffer_peek(b, 4, &r), 1);
	assert_int_equal(r[0].seq, 6);
	gw_buffer_close(b);
}

static void test_crash_keeps_records(void **state)
{
	struct gw_buffer_limits lim = { 0 };
	const char *p = file("crash.db");
	int st, got[64];

	(void)state;
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		struct gw_buffer *b;
		char err[400];
		if (gw_buffer_open(&b, p, &lim, err, sizeof err) != 0)
			_exit(3);
		for (int i = 0; i < 50; i++)
			if (put(b, i, i) != 0)
				_exit(4);
		gw_buffer_ack(b, 1);
		_exit(0); /* no close: as kill -9 */
	}
	assert_int_equal(waitpid(pid, &st, 0), pid);
	assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	struct gw_buffer *b = open_ok(p, &lim);
	assert_int_equal(ids(b, got, 64), 49);
	for (int i = 0; i < 49; i++)
		assert_int_equal(got[i], i + 1);
	gw_buffer_close(b);
}

static void bounds_records(const char *path)
{
	struct gw_buffer_limits lim = { .max_records = 5 };
	struct gw_buffer *b = open_ok(path, &lim);
	struct gw_buffer_stats s;
	int got[16];

	for (int i = 0; i < 12; i++)
		assert_int_equal(put(b, i, 100), 0);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.records, 5);
	assert_int_equal(s.dropped_size, 7);
	assert_int_equal(gw_buffer_take_dropped(b), 7);
	assert_int_equal(gw_buffer_take_dropped(b), 0);
	assert_int_equal(ids(b, got, 16), 5);
	for (int i = 0; i < 5; i++)
		assert_int_equal(got[i], 7 + i);
	gw_buffer_close(b);
}

static void test_bounds_records(void **state)
{
	(void)state;
	bounds_records(file("brec.db"));
	bounds_records(NULL);
}

/* In memory without bounds: the defaults hold it (100 000 records). */
static void test_memory_default_bound(void **state)
{
	struct gw_buffer_limits lim = { 0 };
	struct gw_buffer *b = open_ok(NULL, &lim);
	struct gw_buffer_stats s;
	const struct gw_buffer_rec *r;

	(void)state;
	for (int i = 0; i < 100003; i++)
		put(b, i, 1);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.records, 100000);
	assert_int_equal(s.dropped_size, 3);
	assert_int_equal(gw_buffer_peek(b, 1, &r), 1);
	assert_int_equal(r[0].id, 3);
	gw_buffer_close(b);
}

static void bounds_bytes(const char *path)
{
	/* a record is 7 + 2 + 32 = 41 bytes: 200 bytes hold 4 */
	struct gw_buffer_limits lim = { .max_bytes = 200 };
	struct gw_buffer *b = open_ok(path, &lim);
	struct gw_buffer_stats s;
	int got[16];

	for (int i = 0; i < 10; i++)
		put(b, i, 100);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.records, 4);
	assert_int_equal(s.bytes, 4 * 41);
	assert_int_equal(s.dropped_size, 6);
	assert_int_equal(ids(b, got, 16), 4);
	assert_int_equal(got[0], 6);
	gw_buffer_close(b);
}

static void test_bounds_bytes(void **state)
{
	(void)state;
	bounds_bytes(file("bbytes.db"));
	bounds_bytes(NULL);
}

static void bounds_age(const char *path)
{
	struct gw_buffer_limits lim = { .max_age_ms = 1000 };
	struct gw_buffer *b = open_ok(path, &lim);
	struct gw_buffer_stats s;
	int got[16];

	/* read at 0, 100, ... 900 ms */
	for (int i = 0; i < 10; i++)
		put(b, i, i * 100);
	/* at 1450 ms, those read before 450 ms are too old: 0..400 (5) */
	assert_int_equal(gw_buffer_expire(b, 1450), 0);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.dropped_age, 5);
	assert_int_equal(s.dropped_size, 0);
	assert_int_equal(s.records, 5);
	assert_int_equal(s.oldest_ms, 500);
	assert_int_equal(ids(b, got, 16), 5);
	assert_int_equal(got[0], 5);
	/* an append expires too */
	put(b, 10, 1800);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.dropped_age, 8);
	assert_int_equal(gw_buffer_take_dropped(b), 8);
	gw_buffer_close(b);
}

static void test_bounds_age(void **state)
{
	(void)state;
	bounds_age(file("bage.db"));
	bounds_age(NULL);
}

/* In a child limited to 256 KiB of file (RLIMIT_FSIZE, SIGXFSZ ignored so a
 * write fails with EFBIG): the buffer falls back to memory and says so, with
 * the path; nothing appended is lost. The exit status says what failed. */
static int disk_full_child(const char *p)
{
	struct gw_buffer_limits lim = { 0 };
	struct gw_buffer *b;
	struct rlimit rl = { 256 * 1024, 256 * 1024 };
	char err[400], big[2000];
	const char *note = NULL;

	signal(SIGXFSZ, SIG_IGN);
	if (setrlimit(RLIMIT_FSIZE, &rl) < 0 || gw_buffer_open(&b, p, &lim, err, sizeof err) != 0)
		return 10;
	memset(big, 'x', sizeof big);
	int i;
	for (i = 0; i < 400 && !note; i++) {
		struct gw_buffer_rec r = { .kind = GW_BUFFER_TAG, .id = i, .ms = i, .key = "big", .data = big,
		                           .len = sizeof big };
		if (gw_buffer_append(b, &r, i) != 0)
			return 11;
		note = gw_buffer_note(b);
	}
	if (!note)
		return 12;
	fprintf(stderr, "note: %s\n", note);
	if (!strstr(note, p) || !strstr(note, "File too large") || !strstr(note, "memory"))
		return 13;
	struct gw_buffer_stats s;
	gw_buffer_stats(b, &s);
	if (!s.in_memory || s.records != (uint64_t)i)
		return 14;
	/* it goes on in memory, all in order */
	for (int k = 0; k < 10; k++, i++) {
		struct gw_buffer_rec r = { .kind = GW_BUFFER_TAG, .id = i, .ms = i, .key = "big", .data = big,
		                           .len = 10 };
		if (gw_buffer_append(b, &r, i) != 0)
			return 15;
	}
	const struct gw_buffer_rec *out;
	int n = gw_buffer_peek(b, 1000, &out);
	if (n != i)
		return 16;
	for (int k = 0; k < n; k++)
		if (out[k].id != k || out[k].seq != (uint64_t)k + 1)
			return 17;
	gw_buffer_close(b);
	return 0;
}

static void test_disk_full_falls_back(void **state)
{
	int st;

	(void)state;
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0)
		_exit(disk_full_child(file("full.db")));
	assert_int_equal(waitpid(pid, &st, 0), pid);
	assert_true(WIFEXITED(st));
	assert_int_equal(WEXITSTATUS(st), 0);
}

/* A record handed over is in flight until its PUBACK: the bounds (records,
 * bytes, age) neither count nor drop it, so that a drop is always a record
 * that never went to the broker. 20 records at most, 7 handed over (the
 * window of this test): appends while they wait drop only records not
 * handed over; the acknowledgements find every handed record still there. */
static void inflight_kept(const char *path, const struct gw_buffer_limits *lim)
{
	struct gw_buffer *b = open_ok(path, lim);
	struct gw_buffer_stats s;
	const struct gw_buffer_rec *r;
	uint64_t handed[7];

	for (int i = 0; i < 30; i++)
		assert_int_equal(put(b, i, 100), 0);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.records, 20);
	assert_int_equal(s.dropped_size, 10);
	assert_int_equal(gw_buffer_take_dropped(b), 10);
	/* the replay hands over 11..17; the PUBACKs are slow */
	assert_int_equal(gw_buffer_peek(b, 7, &r), 7);
	for (int i = 0; i < 7; i++)
		handed[i] = r[i].seq;
	assert_int_equal(handed[0], 11);
	gw_buffer_handed(b, handed[6]);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.handed, 7);
	/* live changes join the backlog meanwhile: 7 fit beside those in
	 * flight (13 + 7 = 20 not handed over), the 8th drops 18, the oldest
	 * not handed over, not 11 */
	for (int i = 30; i < 38; i++)
		assert_int_equal(put(b, i, 100), 0);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.records, 27);
	assert_int_equal(s.handed, 7);
	assert_int_equal(s.dropped_size, 11);
	assert_int_equal(gw_buffer_take_dropped(b), 1);
	const struct gw_buffer_rec *next;
	assert_int_equal(gw_buffer_peek(b, 1, &next), 1);
	assert_int_equal(next->seq, 19);
	/* each PUBACK finds its record: deleted, acknowledged, not dropped */
	for (int i = 0; i < 7; i++) {
		assert_int_equal(gw_buffer_ack(b, handed[i]), 0);
		gw_buffer_stats(b, &s);
		assert_int_equal(s.acked, (uint64_t)i + 1);
		assert_int_equal(s.records, 26 - (uint64_t)i);
		assert_int_equal(s.handed, 6 - (uint64_t)i);
	}
	/* nothing in flight: 20 held, the bound's; the next append drops 19 */
	assert_int_equal(put(b, 38, 100), 0);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.records, 20);
	assert_int_equal(s.dropped_size, 12);
	assert_int_equal(gw_buffer_peek(b, 1, &next), 1);
	assert_int_equal(next->seq, 20);
	gw_buffer_close(b);
}

static void test_inflight_kept(void **state)
{
	/* a record is 7 + 2 + 32 = 41 bytes: 820 bytes hold 20 */
	struct gw_buffer_limits recs = { .max_records = 20 }, bytes = { .max_bytes = 820 };

	(void)state;
	inflight_kept(file("flight-r.db"), &recs);
	inflight_kept(NULL, &recs);
	inflight_kept(file("flight-b.db"), &bytes);
	inflight_kept(NULL, &bytes);
}

/* Too old while in flight: kept until its PUBACK; after a rewind (the
 * connection dropped, nothing in flight) the bounds hold it again. */
static void inflight_age_rewind(const char *path)
{
	struct gw_buffer_limits lim = { .max_records = 4, .max_age_ms = 1000 };
	struct gw_buffer *b = open_ok(path, &lim);
	struct gw_buffer_stats s;
	const struct gw_buffer_rec *r;
	int got[16];

	for (int i = 0; i < 4; i++)
		put(b, i, i * 100);
	assert_int_equal(gw_buffer_peek(b, 2, &r), 2);
	gw_buffer_handed(b, r[1].seq);
	/* at 1250 ms 0..200 are too old: 1 and 2 are in flight, 3 goes */
	assert_int_equal(gw_buffer_expire(b, 1250), 0);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.dropped_age, 1);
	assert_int_equal(s.records, 3);
	assert_int_equal(gw_buffer_ack(b, 1), 0);
	/* the connection drops with 2 in flight: handed out again, bounded again */
	gw_buffer_rewind(b);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.handed, 0);
	for (int i = 4; i < 8; i++)
		put(b, i, 2000);
	gw_buffer_stats(b, &s);
	/* 2 (read at 100 ms) and 4 (at 300 ms) expired by the appends at 2000 ms */
	assert_int_equal(s.dropped_age, 3);
	assert_int_equal(s.dropped_size, 0);
	assert_int_equal(ids(b, got, 16), 4);
	assert_int_equal(got[0], 4);
	put(b, 8, 2000);
	gw_buffer_stats(b, &s);
	assert_int_equal(s.dropped_size, 1);
	assert_int_equal(ids(b, got, 16), 4);
	assert_int_equal(got[0], 5);
	gw_buffer_close(b);
}

static void test_inflight_age_rewind(void **state)
{
	(void)state;
	inflight_age_rewind(file("flight-a.db"));
	inflight_age_rewind(NULL);
}

/* A replay against a slow broker: an append every step, a window of 8
 * records handed over every third step, each PUBACK 7 steps later, the
 * connection dropped twice (what is in flight handed out again). Every
 * acknowledgement finds its record (never dropped while in flight), and at
 * the end the drops are exactly the records that never reached the broker:
 * appended = acknowledged + dropped, no record acknowledged twice. */
static void slow_replay(const char *path)
{
	struct gw_buffer_limits lim = { .max_records = 20 };
	struct gw_buffer *b = open_ok(path, &lim);
	struct gw_buffer_stats s;
	const struct gw_buffer_rec *r;
	static unsigned char seen[2000];
	struct { uint64_t seq; int due; } fl[64];
	int nfl = 0, delivered = 0, appended = 0;

	memset(seen, 0, sizeof seen);
	for (int step = 0; step < 1200 || nfl || (gw_buffer_stats(b, &s), s.records); step++) {
		if (step == 400 || step == 800) {
			gw_buffer_rewind(b);
			nfl = 0;
		}
		if (step < 1200 && put(b, step, 100) == 0)
			appended++;
		for (int i = 0; i < nfl;) {
			if (fl[i].due > step) {
				i++;
				continue;
			}
			gw_buffer_stats(b, &s);
			uint64_t before = s.records;
			assert_int_equal(gw_buffer_ack(b, fl[i].seq), 0);
			gw_buffer_stats(b, &s);
			assert_int_equal(s.records, before - 1);
			assert_int_equal(seen[fl[i].seq], 0);
			seen[fl[i].seq] = 1;
			delivered++;
			fl[i] = fl[--nfl];
		}
		if (step % 3 == 0 && nfl < 8) {
			int n = gw_buffer_peek(b, (size_t)(8 - nfl), &r);
			for (int i = 0; i < n; i++, nfl++) {
				fl[nfl].seq = r[i].seq;
				fl[nfl].due = step + 7;
			}
			if (n > 0)
				gw_buffer_handed(b, r[n - 1].seq);
		}
		gw_buffer_stats(b, &s);
		assert_true(s.records - s.handed <= 20);
		assert_true(s.handed <= 8);
	}
	gw_buffer_stats(b, &s);
	assert_int_equal(appended, 1200);
	assert_true(s.dropped_size > 0);
	assert_int_equal(s.dropped_size + (uint64_t)delivered, (uint64_t)appended);
	assert_int_equal(s.acked, (uint64_t)delivered);
	gw_buffer_close(b);
}

static void test_slow_replay_counts_exact(void **state)
{
	(void)state;
	slow_replay(file("slow.db"));
	slow_replay(NULL);
}

static void test_unwritable_path(void **state)
{
	struct gw_buffer_limits lim = { .max_records = 3 };
	struct gw_buffer *b = open_ok(file("no/such/dir/buf.db"), &lim);
	struct gw_buffer_stats s;
	const char *note = gw_buffer_note(b);

	(void)state;
	assert_non_null(note);
	assert_non_null(strstr(note, "no/such/dir/buf.db"));
	assert_non_null(strstr(note, "No such file or directory"));
	assert_non_null(strstr(note, "memory"));
	assert_null(gw_buffer_note(b));
	/* the same rules in memory */
	for (int i = 0; i < 5; i++)
		put(b, i, 1);
	gw_buffer_stats(b, &s);
	assert_true(s.in_memory);
	assert_int_equal(s.records, 3);
	assert_int_equal(s.dropped_size, 2);
	gw_buffer_close(b);
}

/* How many entries of dir start with prefix. */
static int count_prefixed(const char *prefix)
{
	DIR *d = opendir(dir);
	struct dirent *e;
	int n = 0;

	while ((e = readdir(d)))
		n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
	closedir(d);
	return n;
}

static void moved_aside(const char *name)
{
	struct gw_buffer_limits lim = { 0 };
	struct gw_buffer *b = open_ok(file(name), &lim);
	struct gw_buffer_stats s;
	char prefix[64];
	const char *note = gw_buffer_note(b);

	assert_non_null(note);
	assert_non_null(strstr(note, "moved aside"));
	assert_non_null(strstr(note, name));
	snprintf(prefix, sizeof prefix, "%s.corrupt-", name);
	assert_int_equal(count_prefixed(prefix), 1);
	/* the new one works, on the file */
	put(b, 1, 1);
	gw_buffer_stats(b, &s);
	assert_false(s.in_memory);
	assert_int_equal(s.records, 1);
	gw_buffer_close(b);
	b = open_ok(file(name), &lim);
	assert_null(gw_buffer_note(b));
	gw_buffer_stats(b, &s);
	assert_int_equal(s.records, 1);
	gw_buffer_close(b);
}

static void test_corrupt_moved_aside(void **state)
{
	FILE *f = fopen(file("garbage.db"), "w");

	(void)state;
	for (int i = 0; i < 4096; i++)
		fputc((i * 7919) & 0xff, f);
	fclose(f);
	moved_aside("garbage.db");
}

static void test_foreign_moved_aside(void **state)
{
	sqlite3 *db;

	(void)state;
	assert_int_equal(sqlite3_open(file("foreign.db"), &db), SQLITE_OK);
	assert_int_equal(sqlite3_exec(db, "CREATE TABLE t(a,b); INSERT INTO t VALUES(1,2);", NULL, NULL, NULL),
	                 SQLITE_OK);
	sqlite3_close(db);
	moved_aside("foreign.db");
}

static void test_second_opener_refused(void **state)
{
	struct gw_buffer_limits lim = { 0 };
	const char *p = file("locked.db");
	struct gw_buffer *b = open_ok(p, &lim), *b2 = NULL;
	char err[400];
	int st;

	(void)state;
	put(b, 1, 1);
	/* another process */
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		int rc = gw_buffer_open(&b2, p, &lim, err, sizeof err);
		_exit(rc == GW_BUFFER_LOCKED && strstr(err, "in use") && strstr(err, p) ? 0 : 1);
	}
	assert_int_equal(waitpid(pid, &st, 0), pid);
	assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	/* a second opener in this process too (the lock is per open file) */
	assert_int_equal(gw_buffer_open(&b2, p, &lim, err, sizeof err), GW_BUFFER_LOCKED);
	assert_null(b2);
	gw_buffer_close(b);
	/* free again once closed */
	b = open_ok(p, &lim);
	gw_buffer_close(b);
}

static void test_parse_max_and_age(void **state)
{
	struct gw_buffer_limits l = { 0 };
	int64_t ms;
	char err[200];

	(void)state;
	assert_int_equal(gw_buffer_parse_max("64M", &l, err, sizeof err), 0);
	assert_int_equal(l.max_bytes, 64ull << 20);
	assert_int_equal(l.max_records, 0);
	assert_int_equal(gw_buffer_parse_max("2G", &l, err, sizeof err), 0);
	assert_int_equal(l.max_bytes, 2ull << 30);
	assert_int_equal(gw_buffer_parse_max("512k", &l, err, sizeof err), 0);
	assert_int_equal(l.max_bytes, 512 * 1024);
	assert_int_equal(gw_buffer_parse_max("1000", &l, err, sizeof err), 0);
	assert_int_equal(l.max_bytes, 1000);
	assert_int_equal(gw_buffer_parse_max("100000r", &l, err, sizeof err), 0);
	assert_int_equal(l.max_records, 100000);
	assert_int_equal(l.max_bytes, 0);
	assert_int_equal(gw_buffer_parse_max("7records", &l, err, sizeof err), 0);
	assert_int_equal(l.max_records, 7);
	static const char *const bad[] = { "", "0", "-1", "12x", "M", "1.5M", "99999999999999999999", "20000000000G" };
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		err[0] = 0;
		assert_int_equal(gw_buffer_parse_max(bad[i], &l, err, sizeof err), -1);
		assert_non_null(strstr(err, "not a size"));
	}
	assert_int_equal(gw_buffer_parse_age("90s", &ms, err, sizeof err), 0);
	assert_int_equal(ms, 90000);
	assert_int_equal(gw_buffer_parse_age("15m", &ms, err, sizeof err), 0);
	assert_int_equal(ms, 900000);
	assert_int_equal(gw_buffer_parse_age("12h", &ms, err, sizeof err), 0);
	assert_int_equal(ms, 43200000);
	assert_int_equal(gw_buffer_parse_age("7d", &ms, err, sizeof err), 0);
	assert_int_equal(ms, 604800000);
	assert_int_equal(gw_buffer_parse_age("30", &ms, err, sizeof err), 0);
	assert_int_equal(ms, 30000);
	assert_int_equal(gw_buffer_parse_age("3w", &ms, err, sizeof err), -1);
	assert_non_null(strstr(err, "not a duration"));
	assert_int_equal(gw_buffer_parse_age("0s", &ms, err, sizeof err), -1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_order_ack_file),
		cmocka_unit_test(test_order_ack_memory),
		cmocka_unit_test(test_restart_keeps_unacked),
		cmocka_unit_test(test_crash_keeps_records),
		cmocka_unit_test(test_bounds_records),
		cmocka_unit_test(test_bounds_bytes),
		cmocka_unit_test(test_memory_default_bound),
		cmocka_unit_test(test_bounds_age),
		cmocka_unit_test(test_disk_full_falls_back),
		cmocka_unit_test(test_inflight_kept),
		cmocka_unit_test(test_inflight_age_rewind),
		cmocka_unit_test(test_slow_replay_counts_exact),
		cmocka_unit_test(test_unwritable_path),
		cmocka_unit_test(test_corrupt_moved_aside),
		cmocka_unit_test(test_foreign_moved_aside),
		cmocka_unit_test(test_second_opener_refused),
		cmocka_unit_test(test_parse_max_and_age),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
