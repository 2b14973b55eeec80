/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer_sql.c - the store and forward buffer on a SQLite file
 * (gw_buffer.h, df1gw(1) STORE AND FORWARD).
 *
 * One table, rec, a row per record with seq as its INTEGER PRIMARY KEY
 * (AUTOINCREMENT: sqlite_sequence remembers the highest ever, so a seq is
 * never reused in a file, even once it was emptied). The file says it is
 * ours by PRAGMA application_id; a file that SQLite cannot read, that fails
 * quick_check, or that holds other tables is moved aside (FILE.corrupt-TIME)
 * and a new one started.
 *
 * Durability: WAL with synchronous=NORMAL, a transaction per append and per
 * acknowledgement. A crash of the process (kill -9) loses nothing committed;
 * a power loss or a crash of the system may roll back the transactions since
 * the WAL was last synced, which SQLite does at each checkpoint (every 1000
 * pages of WAL, about 4 MiB, by default): the newest records appended in
 * that window may be lost and the newest acknowledgements undone (those records are sent again, as
 * duplicates with their seq and read time). The file is never corrupted.
 *
 * One process per file: an open file description lock (F_OFD_SETLK) on
 * FILE.lock, taken before the file is touched, and locking_mode=EXCLUSIVE.
 */
#include "df1gw/gw_buffer_int.h"

#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <sqlite3.h>

/* "DF1B": the application_id of our files */
#define SQL_APP_ID 0x44463142
#define SQL_VERSION 1

struct gw_buffer_sql {
	sqlite3 *db;
	char *path;
	int lockfd;
	sqlite3_stmt *ins, *peek, *del, *drop, *expire, *oldest, *span;
};

/* err: what failed on path, with the errno text when SQLite has one. */
static int sql_fail(struct gw_buffer_sql *q, const char *what, char *err, size_t errcap)
{
	/* errno as the failed call left it: SQLite's own record of it
	 * (sqlite3_system_errno) misses a write cut short (EFBIG, ENOSPC) */
	int e0 = errno;
	int e = q->db ? sqlite3_system_errno(q->db) : 0;

	if (!e)
		e = e0;
	const char *m = q->db ? sqlite3_errmsg(q->db) : "no database";

	if (e)
		snprintf(err, errcap, "buffer %s: %s: %s (SQLite: %s)", q->path, what, strerror(e), m);
	else
		snprintf(err, errcap, "buffer %s: %s: %s", q->path, what, m);
	return GW_BUFFER_ERR;
}

static int lock_file(struct gw_buffer_sql *q, char *err, size_t errcap)
{
	size_t n = strlen(q->path) + sizeof ".lock";
	char *lp = malloc(n);

	if (!lp)
		return GW_BUFFER_ERR;
	snprintf(lp, n, "%s.lock", q->path);
	q->lockfd = open(lp, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
	if (q->lockfd < 0) {
		snprintf(err, errcap, "buffer %s: cannot create %s: %s", q->path, lp, strerror(errno));
		free(lp);
		return GW_BUFFER_ERR;
	}
	struct flock fl = { .l_type = F_WRLCK, .l_whence = SEEK_SET };
	if (fcntl(q->lockfd, F_OFD_SETLK, &fl) < 0) {
		int e = errno;
		if (e == EAGAIN || e == EACCES)
			snprintf(err, errcap, "buffer %s is in use by another process (lock %s)", q->path, lp);
		else
			snprintf(err, errcap, "buffer %s: cannot lock %s: %s", q->path, lp, strerror(e));
		free(lp);
		return e == EAGAIN || e == EACCES ? GW_BUFFER_LOCKED : GW_BUFFER_ERR;
	}
	free(lp);
	return 0;
}

/* One row of an int, or -1 with rc in *rc. */
static int64_t sql_int(sqlite3 *db, const char *sql, int *rc)
{
	sqlite3_stmt *st;
	int64_t v = -1;

	*rc = sqlite3_prepare_v2(db, sql, -1, &st, NULL);
	if (*rc != SQLITE_OK)
		return -1;
	*rc = sqlite3_step(st);
	if (*rc == SQLITE_ROW) {
		v = sqlite3_column_int64(st, 0);
		*rc = SQLITE_OK;
	} else if (*rc == SQLITE_DONE) {
		*rc = SQLITE_OK;
	}
	sqlite3_finalize(st);
	return v;
}

/* 0: ours or new; 1: not a database of ours (corrupt or foreign, *why says);
 * GW_BUFFER_ERR: it cannot be used (err). */
static int sql_check(struct gw_buffer_sql *q, const char **why, char *err, size_t errcap)
{
	int rc = sqlite3_exec(q->db, "PRAGMA locking_mode=EXCLUSIVE; PRAGMA journal_mode=WAL;", NULL, NULL, NULL);

	if (rc == SQLITE_NOTADB || rc == SQLITE_CORRUPT) {
		*why = "not a SQLite database, or a damaged one";
		return 1;
	}
	if (rc != SQLITE_OK)
		return sql_fail(q, "cannot open", err, errcap);
	sqlite3_stmt *st;
	rc = sqlite3_prepare_v2(q->db, "PRAGMA quick_check", -1, &st, NULL);
	if (rc == SQLITE_OK) {
		rc = sqlite3_step(st);
		bool ok = rc == SQLITE_ROW && strcmp((const char *)sqlite3_column_text(st, 0), "ok") == 0;
		sqlite3_finalize(st);
		if (!ok && (rc == SQLITE_ROW || rc == SQLITE_CORRUPT || rc == SQLITE_NOTADB)) {
			*why = "damaged (quick_check)";
			return 1;
		}
	}
	if (rc != SQLITE_OK && rc != SQLITE_ROW && rc != SQLITE_DONE)
		return sql_fail(q, "cannot read", err, errcap);
	int64_t app = sql_int(q->db, "PRAGMA application_id", &rc);
	int64_t tables = sql_int(q->db, "SELECT count(*) FROM sqlite_master", &rc);
	if (rc == SQLITE_NOTADB || rc == SQLITE_CORRUPT) {
		*why = "damaged";
		return 1;
	}
	if (rc != SQLITE_OK)
		return sql_fail(q, "cannot read", err, errcap);
	if (app != SQL_APP_ID && tables > 0) {
		*why = "a SQLite database of another program";
		return 1;
	}
	return 0;
}

static int sql_schema(struct gw_buffer_sql *q, char *err, size_t errcap)
{
	static const char schema[] =
		"PRAGMA synchronous=NORMAL;"
		"CREATE TABLE IF NOT EXISTS rec(seq INTEGER PRIMARY KEY AUTOINCREMENT, kind INTEGER NOT NULL,"
		" id INTEGER NOT NULL, quality INTEGER NOT NULL, ms INTEGER NOT NULL, key TEXT NOT NULL,"
		" data BLOB, size INTEGER NOT NULL);"
		"PRAGMA application_id=1145450818;"
		"PRAGMA user_version=1;";
	_Static_assert(SQL_APP_ID == 1145450818, "application_id in the schema");

	if (sqlite3_exec(q->db, schema, NULL, NULL, NULL) != SQLITE_OK)
		return sql_fail(q, "cannot write", err, errcap);
	static const struct { size_t off; const char *sql; } stmts[] = {
		{ offsetof(struct gw_buffer_sql, ins),
		  "INSERT INTO rec(seq,kind,id,quality,ms,key,data,size) VALUES(?,?,?,?,?,?,?,?)" },
		{ offsetof(struct gw_buffer_sql, peek),
		  "SELECT seq,kind,id,quality,ms,key,data FROM rec WHERE seq>? ORDER BY seq LIMIT ?" },
		{ offsetof(struct gw_buffer_sql, del), "DELETE FROM rec WHERE seq=? RETURNING size" },
		/* drops and expiry leave what is handed over (seq up to b->handed) */
		{ offsetof(struct gw_buffer_sql, drop),
		  "DELETE FROM rec WHERE seq=(SELECT min(seq) FROM rec WHERE seq>?) RETURNING size" },
		{ offsetof(struct gw_buffer_sql, expire), "DELETE FROM rec WHERE ms<? AND seq>? RETURNING size" },
		{ offsetof(struct gw_buffer_sql, oldest), "SELECT ms FROM rec ORDER BY seq LIMIT 1" },
		{ offsetof(struct gw_buffer_sql, span),
		  "SELECT count(*),coalesce(sum(size),0) FROM rec WHERE seq>? AND seq<=?" },
	};
	for (size_t i = 0; i < sizeof stmts / sizeof stmts[0]; i++) {
		sqlite3_stmt **st = (sqlite3_stmt **)((char *)q + stmts[i].off);
		if (sqlite3_prepare_v3(q->db, stmts[i].sql, -1, SQLITE_PREPARE_PERSISTENT, st, NULL) != SQLITE_OK)
			return sql_fail(q, "cannot prepare", err, errcap);
	}
	return 0;
}

/* The counts of what the file holds, and the next seq. */
static int sql_load(struct gw_buffer *b, char *err, size_t errcap)
{
	struct gw_buffer_sql *q = b->sql;
	int rc;
	int64_t n = sql_int(q->db, "SELECT count(*) FROM rec", &rc);
	int64_t bytes = rc == SQLITE_OK ? sql_int(q->db, "SELECT coalesce(sum(size),0) FROM rec", &rc) : 0;
	int64_t top = rc == SQLITE_OK ?
		sql_int(q->db, "SELECT coalesce(max(seq),0) FROM sqlite_sequence WHERE name='rec'", &rc) : 0;

	if (rc != SQLITE_OK)
		return sql_fail(q, "cannot read", err, errcap);
	b->records = (uint64_t)n;
	b->bytes = (uint64_t)bytes;
	b->next_seq = (uint64_t)(top < 0 ? 0 : top) + 1;
	return 0;
}

static void sql_db_close(struct gw_buffer_sql *q)
{
	sqlite3_stmt *all[] = { q->ins, q->peek, q->del, q->drop, q->expire, q->oldest, q->span };

	for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
		sqlite3_finalize(all[i]);
	q->ins = q->peek = q->del = q->drop = q->expire = q->oldest = q->span = NULL;
	sqlite3_close(q->db);
	q->db = NULL;
}

/* path, path-wal and path-shm renamed to path.corrupt-TIME...: err says so. */
static int move_aside(struct gw_buffer_sql *q, const char *why, char *note, size_t cap)
{
	char stamp[32], to[4096], from[4096];
	time_t now = time(NULL);
	struct tm tm;

	gmtime_r(&now, &tm);
	strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &tm);
	snprintf(to, sizeof to, "%s.corrupt-%s", q->path, stamp);
	if (rename(q->path, to) < 0) {
		snprintf(note, cap, "buffer %s is %s and cannot be moved aside: %s", q->path, why, strerror(errno));
		return GW_BUFFER_ERR;
	}
	static const char *const side[] = { "-wal", "-shm" };
	for (size_t i = 0; i < 2; i++) {
		snprintf(from, sizeof from, "%s%s", q->path, side[i]);
		char to2[4200];
		snprintf(to2, sizeof to2, "%s%s", to, side[i]);
		(void)rename(from, to2);
	}
	snprintf(note, cap, "buffer %.200s is %s: moved aside to %.240s, a new one started", q->path, why, to);
	return 0;
}

static int sql_open_db(struct gw_buffer_sql *q, char *err, size_t errcap)
{
	int rc = sqlite3_open_v2(q->path, &q->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX,
	                         NULL);
	if (rc != SQLITE_OK)
		return sql_fail(q, "cannot open", err, errcap);
	sqlite3_extended_result_codes(q->db, 0);
	return 0;
}

int gw_buffer_sql_open(struct gw_buffer *b, const char *path, char *err, size_t errcap)
{
	struct gw_buffer_sql *q = calloc(1, sizeof *q);
	const char *why = NULL;
	char note[sizeof b->note] = "";

	if (!q || !(q->path = strdup(path))) {
		free(q);
		snprintf(err, errcap, "out of memory");
		return GW_BUFFER_ERR;
	}
	q->lockfd = -1;
	b->sql = q;
	int rc = lock_file(q, err, errcap);
	if (rc < 0)
		goto fail;
	rc = sql_open_db(q, err, errcap);
	if (rc == 0)
		rc = sql_check(q, &why, err, errcap);
	if (rc == 1) {
		sql_db_close(q);
		if (move_aside(q, why, note, sizeof note) < 0) {
			snprintf(err, errcap, "%s", note);
			rc = GW_BUFFER_ERR;
			goto fail;
		}
		rc = sql_open_db(q, err, errcap);
		if (rc == 0)
			rc = sql_check(q, &why, err, errcap);
		if (rc == 1) {
			snprintf(err, errcap, "buffer %s: a new file is %s", path, why);
			rc = GW_BUFFER_ERR;
		}
	}
	if (rc == 0)
		rc = sql_schema(q, err, errcap);
	if (rc == 0)
		rc = sql_load(b, err, errcap);
	if (rc == 0) {
		if (note[0])
			gw_buffer_set_note(b, "%s", note);
		return 0;
	}
fail:
	gw_buffer_sql_close(b);
	if (note[0] && rc != GW_BUFFER_LOCKED) {
		char e2[400];
		snprintf(e2, sizeof e2, "%s", err);
		snprintf(err, errcap, "%s; %s", note, e2);
	}
	return rc;
}

void gw_buffer_sql_close(struct gw_buffer *b)
{
	struct gw_buffer_sql *q = b->sql;

	if (!q)
		return;
	sql_db_close(q);
	if (q->lockfd >= 0)
		close(q->lockfd);
	free(q->path);
	free(q);
	b->sql = NULL;
}

int gw_buffer_sql_append(struct gw_buffer *b, const struct gw_buffer_rec *r, char *err, size_t errcap)
{
	struct gw_buffer_sql *q = b->sql;
	sqlite3_stmt *st = q->ins;
	uint64_t sz = gw_buffer_rec_size(r);

	sqlite3_bind_int64(st, 1, (sqlite3_int64)r->seq);
	sqlite3_bind_int(st, 2, r->kind);
	sqlite3_bind_int(st, 3, r->id);
	sqlite3_bind_int(st, 4, r->quality);
	sqlite3_bind_int64(st, 5, r->ms);
	sqlite3_bind_text(st, 6, r->key ? r->key : "", -1, SQLITE_STATIC);
	sqlite3_bind_blob(st, 7, r->len ? r->data : "", (int)r->len, SQLITE_STATIC);
	sqlite3_bind_int64(st, 8, (sqlite3_int64)sz);
	errno = 0;
	int rc = sqlite3_step(st);
	int e = errno;
	sqlite3_reset(st);
	sqlite3_clear_bindings(st);
	if (rc != SQLITE_DONE) {
		errno = e;
		return sql_fail(q, "cannot write", err, errcap);
	}
	b->records++;
	b->bytes += sz;
	return 0;
}

/* Steps a DELETE ... RETURNING size: the rows and sizes it took off b. */
static int sql_delete(struct gw_buffer *b, sqlite3_stmt *st, uint64_t *rows, uint64_t *size, char *err,
                      size_t errcap)
{
	int rc;

	*rows = 0;
	*size = 0;
	errno = 0;
	while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
		(*rows)++;
		*size += (uint64_t)sqlite3_column_int64(st, 0);
	}
	int e = errno;
	sqlite3_reset(st);
	if (rc != SQLITE_DONE) {
		errno = e;
		return sql_fail(b->sql, "cannot delete", err, errcap);
	}
	b->records -= *rows;
	b->bytes -= *size;
	return 0;
}

int gw_buffer_sql_drop_oldest(struct gw_buffer *b, uint64_t *size, char *err, size_t errcap)
{
	uint64_t rows;

	sqlite3_bind_int64(b->sql->drop, 1, (sqlite3_int64)b->handed);
	if (sql_delete(b, b->sql->drop, &rows, size, err, errcap) < 0)
		return GW_BUFFER_ERR;
	return rows ? 0 : 1;
}

int gw_buffer_sql_expire(struct gw_buffer *b, int64_t cutoff_ms, char *err, size_t errcap)
{
	uint64_t rows, size;

	sqlite3_bind_int64(b->sql->expire, 1, cutoff_ms);
	sqlite3_bind_int64(b->sql->expire, 2, (sqlite3_int64)b->handed);
	return sql_delete(b, b->sql->expire, &rows, &size, err, errcap);
}

int gw_buffer_sql_span(struct gw_buffer *b, uint64_t lo, uint64_t hi, uint64_t *n, uint64_t *bytes, char *err,
                       size_t errcap)
{
	sqlite3_stmt *st = b->sql->span;

	sqlite3_bind_int64(st, 1, (sqlite3_int64)lo);
	sqlite3_bind_int64(st, 2, (sqlite3_int64)hi);
	errno = 0;
	int rc = sqlite3_step(st);
	int e = errno;
	if (rc == SQLITE_ROW) {
		*n = (uint64_t)sqlite3_column_int64(st, 0);
		*bytes = (uint64_t)sqlite3_column_int64(st, 1);
	}
	sqlite3_reset(st);
	if (rc != SQLITE_ROW) {
		errno = e;
		return sql_fail(b->sql, "cannot read", err, errcap);
	}
	return 0;
}

int gw_buffer_sql_ack(struct gw_buffer *b, uint64_t seq, char *err, size_t errcap)
{
	uint64_t rows, size;

	sqlite3_bind_int64(b->sql->del, 1, (sqlite3_int64)seq);
	if (sql_delete(b, b->sql->del, &rows, &size, err, errcap) < 0)
		return GW_BUFFER_ERR;
	b->acked += rows;
	return 0;
}

/* The row st stands on into r (its storage in s). */
static int sql_row(sqlite3_stmt *st, struct gw_buffer_slot *s)
{
	struct gw_buffer_rec r = {
		.seq = (uint64_t)sqlite3_column_int64(st, 0),
		.kind = sqlite3_column_int(st, 1),
		.id = sqlite3_column_int(st, 2),
		.quality = sqlite3_column_int(st, 3),
		.ms = sqlite3_column_int64(st, 4),
		.key = (const char *)sqlite3_column_text(st, 5),
		.data = sqlite3_column_blob(st, 6),
		.len = (size_t)sqlite3_column_bytes(st, 6),
	};
	return gw_buffer_slot_set(s, &r);
}

int gw_buffer_sql_peek(struct gw_buffer *b, size_t max, char *err, size_t errcap)
{
	sqlite3_stmt *st = b->sql->peek;
	int rc, n = 0;

	sqlite3_bind_int64(st, 1, (sqlite3_int64)b->handed);
	sqlite3_bind_int64(st, 2, (sqlite3_int64)max);
	while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
		if (sql_row(st, &b->rows[n]) < 0) {
			sqlite3_reset(st);
			return GW_BUFFER_ERR;
		}
		b->out[n] = b->rows[n].r;
		n++;
	}
	sqlite3_reset(st);
	if (rc != SQLITE_DONE)
		return sql_fail(b->sql, "cannot read", err, errcap);
	return n;
}

int64_t gw_buffer_sql_oldest_ms(const struct gw_buffer *b)
{
	sqlite3_stmt *st = b->sql->oldest;
	int64_t ms = 0;

	if (sqlite3_step(st) == SQLITE_ROW)
		ms = sqlite3_column_int64(st, 0);
	sqlite3_reset(st);
	return ms;
}

int gw_buffer_sql_to_mem(struct gw_buffer *b, char *err, size_t errcap)
{
	sqlite3_stmt *st;
	struct gw_buffer_slot s = { 0 };
	int rc = sqlite3_prepare_v2(b->sql->db, "SELECT seq,kind,id,quality,ms,key,data FROM rec ORDER BY seq", -1,
	                            &st, NULL);

	if (rc != SQLITE_OK)
		return sql_fail(b->sql, "cannot read", err, errcap);
	while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
		if (sql_row(st, &s) < 0 || gw_buffer_mem_push(b, &s.r) < 0) {
			rc = SQLITE_NOMEM;
			break;
		}
	}
	sqlite3_finalize(st);
	free(s.key);
	free(s.data);
	if (rc != SQLITE_DONE)
		return sql_fail(b->sql, "cannot read", err, errcap);
	return 0;
}
