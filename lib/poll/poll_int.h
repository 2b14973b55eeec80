/* SPDX-License-Identifier: MPL-2.0 */
/*
 * poll_int.h - the poll engine's state and internal calls, shared by the files
 * of lib/poll (doc/ARCHITECTURE.md 9; doc/REQUIREMENTS.md 000, 002, 004): a scan list of tags, block
 * coalescing, point quality, station health and queued writes. Not installed.
 *
 * Files (each calls only files listed before it, never back):
 *   engine.c    the engine's allocation and teardown, names, settings, stats
 *   tags.c      tags, their layout and quality, the mapping CSV
 *   plan.c      the scan list planned into blocks (lib/client/block_plan.c), splits
 *   health.c    outcomes of a transaction, tag updates, station health
 *   writeq.c    the write queue: df1_tag_write() and its runs between transactions
 *   probe.c     station discovery: probes of addresses without tags, when due
 *   scan.c      block reads, the scan of a station, one scan of all stations
 *   poll.c      df1_poll(), its wait, df1_poll_next_ms(), df1_poll_fd()
 * The user-facing rules are in df1_poll(3); the decisions behind them:
 *
 * Scan list. Readable tags are planned into block reads (lib/client/block_plan.c):
 * per station, PLC type and file, elements are packed greedily up to the
 * packet limit of the PLC type (lib/plc_limits.h), bridging a gap when its
 * bytes cost no more than one more read transaction (POLL_TX_OVERHEAD_*).
 * Bits, T/C/R sub-elements and T/C/R bits read their whole element(s) and are
 * picked out of the block; I/O words with a sub-element ("I1:0.1") and PLC-5
 * ASCII addresses ("$N7:0") are read on their own with df1_read_addr(). The
 * plan is rebuilt (allocation happens only here) when tags are added; a scan
 * allocates nothing. A block is due when any member is due: it is read with
 * the shortest period of its members.
 *
 * A scan visits the stations in address order (doc/REQUIREMENTS.md 002) and reads what is due
 * at its start. Between any two transactions, queued writes go first (seed
 * 002: "the command will be next"). df1_poll() runs at most one scan per call.
 *
 * Errors of a block read:
 *  - the station answered with STS 50h or an addressing EXT STS (01-07, 09,
 *    0A, 11, 13), or the client refused the address locally: a block of
 *    several tags is split in two halves (binary split), both read at once;
 *    the split stays in the plan. A tag alone that fails this way is BAD
 *    (PLC_ERROR, or CONFIG for a local refusal) and is marked isolated; the
 *    next df1_poll() re-plans (once per bad tag), so the tag stays alone and
 *    the good tags around it merge again into the fewest blocks. The station
 *    counts as answering.
 *  - another PLC error (STS): the block's tags are BAD PLC_ERROR; no split.
 *  - no answer / a link error (timeout, NAK or ENQ limit, inactive station,
 *    bad reply, port error): a station failure, below.
 *  - DF1_E_INTR, DF1_E_NOMEM, DF1_E_NOT_OPEN end df1_poll() with that code;
 *    what was not read stays due.
 *
 * Station health:
 *  - UNKNOWN (not yet polled) and OK stations get two retries of a failing
 *    transaction in a scan (doc/REQUIREMENTS.md 002: it answered last scan, or, at start, every
 *    station is assumed active, doc/REQUIREMENTS.md 004); a FAILING station gets a single
 *    attempt per scan. When a station fails its other due blocks are skipped for
 *    this scan. Retries of a half-duplex station cost one poll each, as the link
 *    layer's active station list probes an inactive station first (doc/REQUIREMENTS.md 004).
 *  - Failing tags: UNCERTAIN (COMM_FAILURE) keeping their last value; a tag
 *    without a value (never read) is BAD (COMM_FAILURE).
 *  - Offline (doc/REQUIREMENTS.md 000): absolute_retries > 0: when more than that many
 *    attempts in a row failed; else when watchdog_ms passed since the last
 *    answer (since the first attempt if it never answered), checked at each
 *    failed attempt. Every tag of the station becomes BAD (STATION_OFFLINE).
 *    An offline station gets one attempt (its first block, or its probe) every
 *    watchdog_ms / 2. The interface of doc/REQUIREMENTS.md 000 resets its
 *    watchdog on every character; here an answer is a whole transaction (the
 *    link layer owns the characters), which only matters for a station that
 *    keeps sending garbage.
 *  - Recovery (the first answer after FAILING or OFFLINE): each tag gets back
 *    the quality it had before the failure, and every block of the station is
 *    read at once, in this scan (doc/REQUIREMENTS.md 000's one-time poll of every point).
 *  - Writes count for health too (an answer or a failure) but are never retried.
 *
 * Discovery (doc/REQUIREMENTS.md 002, df1_poll_set_station_range): addresses in the range
 * without tags are probed with a link test (half duplex: a poll, DLE ENQ STN
 * BCC) or an empty echo (full duplex, 06/00). Probe scans run once per
 * POLL_PROBE_MS: stations that answered are probed each time, absent addresses
 * one per probe scan in turn, so discovery costs a known station's scan at
 * most one timeout per second.
 *
 * Pipelining (full duplex, DF1_OPT_MAX_OUTSTANDING N > 1): before a block's
 * transaction the scan submits it and the due blocks after it (in scan order,
 * across stations) until N are on the link's pipeline; the client builds each
 * command (client_read_raw_cmd) and the link puts it in a slot (link_pipe_put);
 * the read that follows waits for its slot's reply (link_pipe_wait) and the
 * client decodes it as its own read does (client_read_raw_reply). Only whole-element block reads of stations that are not
 * FAILING or OFFLINE go ahead; reads alone, retries, writes and probes are
 * ordinary transactions, queued behind what is already submitted. A station
 * that fails still has its other blocks skipped: what was sent ahead for them
 * is abandoned, and the scan waits for it at its end (link_pipe_flush). The
 * results are those of N = 1; only the order on the line differs.
 *
 * Writes: df1_tag_write() (any thread) checks the values, appends a node to a
 * mutex-protected FIFO and signals an eventfd; df1_poll() waits on that fd and
 * runs the queue between transactions. Each write is one df1_write_addr() (the
 * link layer's ENQ/NAK retries and the slave's duplicate detection make a lost
 * ACK or reply safe); its result goes to the callback once; the engine never
 * sends a failed write again. A good write makes the tag's block due so the
 * value is read back.
 *
 * Raw PCCC commands (df1_poll_submit_pccc) join the same FIFO, so writes and
 * every bridge client are served in the order they came, none starved. Each is
 * one link_transact() with the line's TNS; the requester's TNS is put back in
 * the reply. A command that may write (df1_pccc_is_write) gets one attempt
 * unless the failure says it never executed; read commands get the station's
 * tries as block reads do. The queue holds at most DF1_PCCC_QUEUE_MAX raw
 * commands (DF1_E_BUSY beyond): a bridge's clients cannot grow it without end.
 */
#ifndef LIBDF1_POLL_INT_H
#define LIBDF1_POLL_INT_H

#include "df1_int.h"

#include <errno.h>
#include <limits.h>
#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/eventfd.h>
#include <time.h>
#include <unistd.h>

#include "client/client.h"
#include "link/link.h"
#include "proto/plc_limits.h"
#include "client/block_plan.h"
#include "proto/value.h"

#define POLL_WATCHDOG_DEFAULT_MS 10000
#define POLL_WATCHDOG_MAX_MS 86400000
#define POLL_RETRIES_MAX 1000
#define POLL_RETRIES_OK 2               /* doc/REQUIREMENTS.md 002: "will retry twice" */
#define POLL_PROBE_MS 1000
#define POLL_COUNT_MAX 1000
#define POLL_STATIONS 255               /* 0..254 */
#define POLL_NEVER INT64_MAX

/* ------------------------------------------------------------------------
 * Engine state
 * ------------------------------------------------------------------------ */

enum tag_how {
	HOW_ELEM,       /* whole elements: N7:0 x n, F8:0, T4:0, ST9:0 */
	HOW_WORD,       /* one word of T/C/R elements: T4:0.ACC x n */
	HOW_BITS,       /* bits of words (B3:0/5 x n) or of one T/C/R word (T4:0/DN) */
	HOW_ALONE,      /* read with df1_read_addr on its own */
};

struct ptag {
	struct df1_tag_config cfg;
	int id;
	bool readable, writable;
	enum tag_how how;
	int e0, ecount;         /* elements of the file this tag needs */
	size_t esize;           /* wire bytes per element of the file */
	int wbits;              /* HOW_BITS: bits per word */
	int word;               /* HOW_WORD / T/C/R bits: word of the element */
	enum df1_value_kind kind; /* of its values: its Type's (proto/value_type.h) */
	bool isolated;          /* an address error was seen: planned alone */
	int64_t next_due_ms;
	struct df1_value *values;
	bool has_value;
	enum df1_quality q;
	enum df1_quality_reason r;
	bool saved;             /* q/r before the station failure (restored on recovery) */
	enum df1_quality sq;
	enum df1_quality_reason sr;
	int64_t last_good_ms, last_good_wall_ms;
	int last_error;
	uint8_t sts, ext;
	uint64_t reads;
	int block;              /* index into blocks, -1: none */
};

struct pblock {
	int station;
	enum df1_plc plc;
	enum df1_file_type type;
	int file;
	int first, count;
	size_t esize;
	bool alone;
	int period_ms;
	size_t m0, nm;          /* members: e->members[m0 .. m0 + nm) (tag indexes) */
	int64_t due_ms;
	uint64_t scan_read;     /* scan number of its last read attempt */
	uint64_t pipe_scan;     /* scan number in which its read was submitted ahead */
	int pipe_slot;          /* ... into this link pipeline slot, -1: taken or none */
};

struct pstation {
	enum df1_station_state state;
	bool in_range;
	int tags;
	int b0, nb;             /* its blocks: blocks[b0 .. b0 + nb) */
	int64_t first_attempt_ms, last_good_ms, last_attempt_ms, next_retry_ms;
	int fails;              /* consecutive failed attempts */
	bool recovered;         /* answered after FAILING/OFFLINE: the scan restarts its blocks */
	uint64_t attempts, failures;
	int last_error;
};

/* A queued write (df1_tag_write) or a raw PCCC command (df1_poll_submit_pccc,
 * pdone set: station, n bytes at pccc); one FIFO keeps them in order. */
struct wnode {
	struct wnode *next;
	int tag, wid;
	df1_write_done_fn done;
	df1_pccc_done_fn pdone;
	int station;
	void *user;
	size_t n;
	uint8_t *pccc;
	struct df1_value v[];
};

struct poll_engine {
	pthread_mutex_t mu;     /* tags[] (growth) and the write queue */
	int wake_fd;

	struct ptag **tags;
	size_t ntags, tags_cap;
	int *names;             /* index of the tag names (tags.c): open addressing, */
	size_t names_cap;       /* names_cap slots (a power of two), tag id or -1 */

	/* plan */
	bool dirty;
	struct pblock *blocks;
	size_t nblocks, blocks_cap;
	int *members;
	uint8_t *raw;           /* one block's bytes */
	size_t raw_cap;
	struct df1_value *vals; /* one tag's decoded values */
	size_t vals_cap;

	struct pstation st[POLL_STATIONS];
	int wd_ms, abs_retries;
	int lo, hi;             /* discovery range, lo < 0: off */
	int probe_next;         /* round-robin cursor for absent addresses */
	int64_t probe_due_ms;

	/* write queue (mu) */
	struct wnode *wq_head, *wq_tail;
	unsigned wq_len;
	unsigned pccc_len;      /* raw PCCC commands of them (DF1_PCCC_QUEUE_MAX) */
	int next_wid;

	df1_tag_fn cb;
	void *cb_user;

	uint64_t scan_no;
	unsigned scan_tx;
	struct df1_poll_stats stats;
};

enum outcome {
	OUT_OK,         /* the station answered with data */
	OUT_ADDR,       /* answered: an addressing error (split / isolate) */
	OUT_PLC,        /* answered: another PLC error */
	OUT_LOCAL,      /* refused before or without a transaction (address, type, size) */
	OUT_LINK,       /* no usable answer: station failure */
	OUT_ABORT,      /* end df1_poll with the code */
};

/* One scan's discovery state (probe.c). */
struct poll_probe_scan {
	bool probe;             /* a probe scan: stations that answered are probed */
	int cand;               /* the absent address probed in this scan, -1: none */
};

static inline int64_t poll_wall_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* engine.c */
struct poll_engine *poll_engine(struct df1 *h);

/* tags.c */
void poll_set_quality(struct poll_engine *e, struct ptag *t, enum df1_quality q,
                      enum df1_quality_reason r, bool value_changed);

/* plan.c */
int poll_replan(struct df1 *h, struct poll_engine *e);
void poll_split(struct poll_engine *e, size_t b);

/* health.c */
enum outcome poll_outcome(const struct df1 *h, int rc);
void poll_tag_comm(struct poll_engine *e, struct ptag *t, int err);
void poll_tag_good(struct poll_engine *e, struct ptag *t, const struct df1_value *v,
                   int64_t now, int64_t wall);
void poll_tag_bad(struct poll_engine *e, struct ptag *t, enum df1_quality_reason r, int err,
                  const struct df1_error_detail *d);
int poll_decode(struct poll_engine *e, const struct ptag *t, const struct pblock *b,
                enum value_float_order fo);
void poll_attempt(struct poll_engine *e, int stn, int64_t now);
void poll_station_answer(struct poll_engine *e, int stn, int64_t now);
void poll_station_fail(struct poll_engine *e, int stn, int err, int64_t now);
void poll_block_done(struct poll_engine *e, struct pblock *b, int64_t start);
int poll_tries(const struct pstation *s);

/* writeq.c */
int poll_run_writes(struct df1 *h, struct poll_engine *e);

/* probe.c */
int poll_discover(struct df1 *h, struct poll_engine *e, int stn, int64_t start,
                  struct poll_probe_scan *ps);
int64_t poll_discover_due(const struct poll_engine *e, int64_t due);

/* scan.c */
int64_t poll_next_scan(const struct poll_engine *e);
int poll_scan(struct df1 *h, struct poll_engine *e, int64_t start);

#endif
