/* SPDX-License-Identifier: MPL-2.0 */
/*
 * soak - transactions through df1sim (a real process on a pty) with every
 * fault it offers, full and half duplex, BCC and CRC, checked against a
 * shadow of what was written and against df1sim's --log (README "Soak").
 * Only the public API (include/df1.h) and tests/support/simproc.h.
 *
 * One lane per link setting, each a thread with its own df1sim and handle:
 *   lane.c    the mix of operations and their checks;
 *   shadow.c  the values each data-table element may hold;
 *   ledger.c  every command frame by TNS (from the handle's trace) and the
 *             executions df1sim's log shows for it.
 */
#ifndef LIBDF1_TESTS_SOAK_H
#define LIBDF1_TESTS_SOAK_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>

#include "df1.h"
#include "../support/simproc.h"

/* link settings of every lane: short timers so that faults cost little time */
#define SOAK_TIMEOUT_MS 50
#define SOAK_CMD_TIMEOUT_MS 500
#define SOAK_RETRIES 3
#define SOAK_DELAY_MS 600       /* --delay: longer than Cmd_Timeout, the reply comes late */
#define SOAK_HANG_MARGIN_MS 1000
#define SOAK_STATION 1
#define SOAK_SILENT_STATION 9   /* --silent: a station that never answers */

/* ------------------------------------------------------------------------
 * shadow.c: per element, the values it may hold. A confirmed write leaves one
 * value; a write that failed adds its value (it may or may not have run); a
 * good read must return one of them and then leaves that one.
 * ------------------------------------------------------------------------ */
#define SHADOW_MAX 8
struct shadow_cell {
	uint8_t n;              /* values in v; 0: anything (too many unconfirmed) */
	int32_t v[SHADOW_MAX];  /* int16, int32, a float's bits, 0/1 */
};
void shadow_set(struct shadow_cell *c, int32_t v);
void shadow_maybe(struct shadow_cell *c, int32_t v);
/* A value read: true if it is possible; the cell then holds that value only. */
bool shadow_seen(struct shadow_cell *c, int32_t v);
/* A value read while writes of its own values may have run in between: checks
 * against the cell plus those, and narrows nothing. */
bool shadow_possible(const struct shadow_cell *c, int32_t v);

/* ------------------------------------------------------------------------
 * ledger.c: one record per TNS (the handle uses each for one transaction;
 * it comes round after 65536, when the old record is closed).
 * ------------------------------------------------------------------------ */
enum rec_result { REC_PENDING = 0, REC_OK, REC_FAILED };
struct rec {
	uint32_t gen;           /* 0: empty */
	bool is_write;
	uint8_t result;         /* enum rec_result, as the caller was told */
	uint16_t execs;         /* lines in df1sim's log */
	char cmd[8];            /* "0F/AA" as the log writes it */
	char addr[20];
};

struct ledger_figures {
	uint64_t writes_sent, writes_ok, writes_failed;
	uint64_t executed_twice;        /* a write with two or more log lines */
	uint64_t lost;                  /* reported written, no log line */
	uint64_t failed_executed;       /* reported failed, executed once (honest) */
	uint64_t log_lines, log_unmatched;
};

struct ledger {
	struct rec *recs;               /* [65536], by TNS */
	uint32_t gen;
	int last_tns;                   /* of the last command frame sent, -1 none */
	struct df1_decoder *dec;
	/* the TNS of the command frames of the call under way */
	int call_tns[32];
	int call_n;
	/* df1sim's log, followed as it grows */
	int log_fd;
	char buf[4096];
	size_t buf_len;
	struct ledger_figures fig;
};
int ledger_init(struct ledger *l, enum df1_check check, bool half);
void ledger_free(struct ledger *l);
/* The handle's trace callback (df1_set_trace), user = the ledger. */
void ledger_trace(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us);
/* Before a call: forget the TNS of the last one. */
void ledger_call_begin(struct ledger *l);
/* After it: what the caller was told about the writes it sent. */
void ledger_call_result(struct ledger *l, bool ok);
/* Transactions (new TNS) the call sent so far. */
int ledger_call_sent(const struct ledger *l);
/* The TNS of a write the call sent whose result is not known yet, or -1. */
int ledger_call_write_tns(const struct ledger *l);
/* The result of the write sent with this TNS (a queued write's, told later). */
void ledger_set_result(struct ledger *l, int tns, bool ok);
/* Read df1sim's log as far as it is written; 0 or -1. */
int ledger_follow(struct ledger *l, const char *path);
/* At the end (df1sim stopped, its log complete): close every record. */
void ledger_close_all(struct ledger *l);

/* ------------------------------------------------------------------------
 * lane.c
 * ------------------------------------------------------------------------ */
struct lane_figures {
	uint64_t transactions, calls, ok, failed;
	uint64_t wrong;                 /* a value read that no write can explain, or a
	                                 * success from the silent station */
	uint64_t hangs;
	int64_t max_call_ms, elapsed_ms;
	uint64_t silenced, polls, tag_writes;
};

struct lane {
	int id;
	bool half;
	enum df1_check check;
	_Atomic uint64_t *done;         /* transactions of every lane so far */
	uint64_t target;                /* ... to run in all */
	uint64_t seed;
	struct simproc sp;
	df1_t *h;
	struct ledger led;
	struct lane_figures fig;
	const char *error;              /* set when the lane could not run */
	struct lane_state *st;          /* shadow and poll state (lane.c) */
};
int lane_setup(struct lane *ln);        /* starts df1sim, opens the handle */
void *lane_run(void *arg);              /* pthread body */
int lane_finish(struct lane *ln);       /* stops df1sim, closes the ledger */
long soak_rss_kb(pid_t pid);            /* VmRSS of a process (0: self), -1 unknown */

#endif
