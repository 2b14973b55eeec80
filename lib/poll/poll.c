/*
 * poll.c - the poll engine (DESIGN.md 9; seeds 000, 002, 004): a scan list of
 * tags, block coalescing, point quality, station health and queued writes.
 * The user-facing rules are in df1_poll(3); the decisions behind them:
 *
 * Scan list. Readable tags are planned into block reads (lib/proto/poll_plan.c):
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
 * A scan visits the stations in address order (seed 002) and reads what is due
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
 *    transaction in a scan (seed 002: it answered last scan, or, at start, every
 *    station is assumed active, seed 004); a FAILING station gets a single
 *    attempt per scan. When a station fails its other due blocks are skipped for
 *    this scan. Retries of a half-duplex station cost one poll each, as the link
 *    layer's active station list probes an inactive station first (seed 004).
 *  - Failing tags: UNCERTAIN (COMM_FAILURE) keeping their last value; a tag
 *    without a value (never read) is BAD (COMM_FAILURE).
 *  - Offline (seed 000): absolute_retries > 0: when more than that many
 *    attempts in a row failed; else when watchdog_ms passed since the last
 *    answer (since the first attempt if it never answered), checked at each
 *    failed attempt. Every tag of the station becomes BAD (STATION_OFFLINE).
 *    An offline station gets one attempt (its first block, or its probe) every
 *    watchdog_ms / 2. Seed 000 resets its watchdog on every character; here an
 *    answer is a whole transaction (the link layer owns the characters), which
 *    only matters for a station that keeps sending garbage.
 *  - Recovery (the first answer after FAILING or OFFLINE): each tag gets back
 *    the quality it had before the failure, and every block of the station is
 *    read at once, in this scan (seed 000's one-time poll of every point).
 *  - Writes count for health too (an answer or a failure) but are never retried.
 *
 * Discovery (seed 002, df1_poll_set_station_range): addresses in the range
 * without tags are probed with a link test (half duplex: a poll, DLE ENQ STN
 * BCC) or an empty echo (full duplex, 06/00). Probe scans run once per
 * POLL_PROBE_MS: stations that answered are probed each time, absent addresses
 * one per probe scan in turn, so discovery costs a known station's scan at
 * most one timeout per second.
 *
 * Writes: df1_tag_write() (any thread) checks the values, appends a node to a
 * mutex-protected FIFO and signals an eventfd; df1_poll() waits on that fd and
 * runs the queue between transactions. Each write is one df1_write_addr() (the
 * link layer's ENQ/NAK retries and the slave's duplicate detection make a lost
 * ACK or reply safe); its result goes to the callback once; the engine never
 * sends a failed write again. A good write makes the tag's block due so the
 * value is read back.
 */
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

#include "client.h"
#include "plc_limits.h"
#include "poll_plan.h"
#include "value.h"

#define POLL_WATCHDOG_DEFAULT_MS 10000
#define POLL_WATCHDOG_MAX_MS 86400000
#define POLL_RETRIES_MAX 1000
#define POLL_RETRIES_OK 2               /* seed 002: "will retry twice" */
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

struct wnode {
	struct wnode *next;
	int tag, wid;
	df1_write_done_fn done;
	void *user;
	size_t n;
	struct df1_value v[];
};

struct poll_engine {
	pthread_mutex_t mu;     /* tags[] (growth) and the write queue */
	int wake_fd;

	struct ptag **tags;
	size_t ntags, tags_cap;

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

static void poll_free_engine(struct df1 *h);

static struct poll_engine *poll_engine(struct df1 *h)
{
	struct poll_engine *e = h->poll;

	if (e)
		return e;
	e = calloc(1, sizeof *e);
	if (!e)
		return NULL;
	if (pthread_mutex_init(&e->mu, NULL) != 0) {
		free(e);
		return NULL;
	}
	e->wake_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
	if (e->wake_fd < 0) {
		pthread_mutex_destroy(&e->mu);
		free(e);
		return NULL;
	}
	e->wd_ms = POLL_WATCHDOG_DEFAULT_MS;
	e->lo = e->hi = -1;
	e->next_wid = 1;
	h->poll = e;
	h->poll_free = poll_free_engine;
	return e;
}

static int64_t poll_wall_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* ------------------------------------------------------------------------
 * Names
 * ------------------------------------------------------------------------ */

const char *df1_quality_name(enum df1_quality q)
{
	switch (q) {
	case DF1_QUALITY_GOOD: return "GOOD";
	case DF1_QUALITY_UNCERTAIN: return "UNCERTAIN";
	case DF1_QUALITY_BAD: return "BAD";
	}
	return "?";
}

const char *df1_reason_name(enum df1_quality_reason r)
{
	switch (r) {
	case DF1_REASON_NONE: return "none";
	case DF1_REASON_NOT_YET_READ: return "not_yet_read";
	case DF1_REASON_COMM_FAILURE: return "comm_failure";
	case DF1_REASON_STATION_OFFLINE: return "station_offline";
	case DF1_REASON_PLC_ERROR: return "plc_error";
	case DF1_REASON_CONFIG: return "config";
	}
	return "?";
}

const char *df1_station_state_name(enum df1_station_state s)
{
	switch (s) {
	case DF1_STATION_UNKNOWN: return "unknown";
	case DF1_STATION_OK: return "ok";
	case DF1_STATION_FAILING: return "failing";
	case DF1_STATION_OFFLINE: return "offline";
	case DF1_STATION_ABSENT: return "absent";
	}
	return "?";
}

/* ------------------------------------------------------------------------
 * Tags
 * ------------------------------------------------------------------------ */

static bool poll_is_tcr(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R;
}

/* Elements a tag needs and how its values come out of them. */
static int poll_tag_layout(struct ptag *t)
{
	const struct df1_addr *a = &t->cfg.addr;
	int es = df1_file_type_element_size(a->type);

	if (es <= 0)
		return DF1_E_INVAL;
	t->esize = (size_t)es;
	t->e0 = a->element;
	t->ecount = t->cfg.count;
	t->word = -1;
	t->wbits = 0;
	if (a->ascii[0] || (a->sub != DF1_ADDR_NONE && !poll_is_tcr(a->type))) {
		t->how = HOW_ALONE;     /* "$N7:0", I/O words "I1:0.1": the client's own forms */
		return 0;
	}
	if (a->bit != DF1_ADDR_NONE) {
		t->how = HOW_BITS;
		if (poll_is_tcr(a->type)) {
			t->wbits = 16;
			t->word = a->sub == DF1_ADDR_NONE ? 0 : a->sub;
			if (a->bit + t->cfg.count > 16)
				return DF1_E_ADDR_RANGE;
			t->ecount = 1;
		} else {
			t->wbits = a->type == DF1_FT_L ? 32 : 16;
			if ((size_t)t->wbits != t->esize * 8)
				return DF1_E_TYPE;      /* no bits in F / ST */
			t->ecount = (a->bit + t->cfg.count - 1) / t->wbits + 1;
		}
		return 0;
	}
	if (a->sub != DF1_ADDR_NONE) {
		t->how = HOW_WORD;      /* T/C/R word */
		t->word = a->sub;
		if ((size_t)(a->sub * 2 + 2) > t->esize)
			return DF1_E_ADDR_RANGE;
		return 0;
	}
	t->how = HOW_ELEM;
	return 0;
}

static void poll_tag_state(const struct ptag *t, int64_t now, struct df1_tag_state *st)
{
	memset(st, 0, sizeof *st);
	st->id = t->id;
	st->config = &t->cfg;
	st->count = (size_t)t->cfg.count;
	st->values = t->values;
	st->value = t->values[0];
	st->has_value = t->has_value;
	st->quality = t->q;
	st->reason = t->r;
	st->last_good_ms = t->last_good_ms;
	st->last_good_wall_ms = t->last_good_wall_ms;
	st->age_ms = t->last_good_ms ? now - t->last_good_ms : -1;
	st->last_error = t->last_error;
	st->sts = t->sts;
	st->ext_sts = t->ext;
	st->reads = t->reads;
}

static void poll_notify(struct poll_engine *e, const struct ptag *t)
{
	struct df1_tag_state st;

	if (!e->cb)
		return;
	poll_tag_state(t, df1_now_ms(), &st);
	e->cb(e->cb_user, t->id, &st);
}

/* Set quality and reason; fires the callback on a change (or when forced by a value change). */
static void poll_set_quality(struct poll_engine *e, struct ptag *t, enum df1_quality q,
                             enum df1_quality_reason r, bool value_changed)
{
	bool changed = value_changed || t->q != q || t->r != r;

	t->q = q;
	t->r = r;
	if (changed)
		poll_notify(e, t);
}

/* Check a tag configuration and work out its layout into *t (t->cfg = *c). */
static int poll_tag_check(struct df1 *h, const struct df1_tag_config *c, struct ptag *t)
{
	char at[64];
	int rc;

	if (c->station < 0 || c->station > 254)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag %s: station %d out of range 0-254",
		                c->name, c->station);
	if (c->count < 1 || c->count > POLL_COUNT_MAX)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag %s: count %d out of range 1-%d",
		                c->name, c->count, POLL_COUNT_MAX);
	if (c->scan_ms < 0)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag %s: negative scan period", c->name);
	if (!(c->access & DF1_ACCESS_READWRITE) || c->plc < DF1_PLC_SLC || c->plc > DF1_PLC_PLC2)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag %s: invalid access or PLC type", c->name);
	t->cfg = *c;
	rc = poll_tag_layout(t);
	if (rc < 0) {
		if (df1_addr_format(&c->addr, at, sizeof at) < 0)
			snprintf(at, sizeof at, "?");
		return df1_fail(h, rc, c->station, "tag %s: %s: %s", c->name, at, df1_strerror(rc));
	}
	return 0;
}

int df1_tag_add(df1_t *h, const struct df1_tag_config *c)
{
	struct poll_engine *e;
	struct ptag *t;
	int rc;

	if (!h || !c)
		return DF1_E_INVAL;
	if (memchr(c->name, '\0', sizeof c->name) == NULL)
		return df1_fail(h, DF1_E_INVAL, c->station, "tag name not terminated");
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	if (c->name[0] && df1_tag_find(h, c->name) >= 0)
		return df1_fail(h, DF1_E_CONFIG, c->station, "tag %s is defined twice", c->name);
	t = calloc(1, sizeof *t);
	if (!t)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	rc = poll_tag_check(h, c, t);
	if (rc < 0) {
		free(t);
		return rc;
	}
	t->values = calloc((size_t)c->count, sizeof *t->values);
	if (!t->values) {
		free(t);
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	}
	for (int i = 0; i < c->count; i++)
		t->values[i].kind = df1_addr_value_kind(&c->addr);
	t->readable = (c->access & DF1_ACCESS_READ) != 0;
	t->writable = (c->access & DF1_ACCESS_WRITE) != 0;
	t->q = DF1_QUALITY_BAD;
	t->r = DF1_REASON_NOT_YET_READ;
	t->block = -1;

	pthread_mutex_lock(&e->mu);
	if (e->ntags == e->tags_cap) {
		size_t ncap = e->tags_cap ? e->tags_cap * 2 : 16;
		struct ptag **nt = realloc(e->tags, ncap * sizeof *nt);

		if (!nt) {
			pthread_mutex_unlock(&e->mu);
			free(t->values);
			free(t);
			return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
		}
		e->tags = nt;
		e->tags_cap = ncap;
	}
	t->id = (int)e->ntags;
	e->tags[e->ntags++] = t;
	pthread_mutex_unlock(&e->mu);
	if (t->readable)
		e->dirty = true;
	return t->id;
}

int df1_tag_count(const df1_t *h)
{
	const struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	e = h->poll;
	return e ? (int)e->ntags : 0;
}

int df1_tag_find(const df1_t *h, const char *name)
{
	const struct poll_engine *e;

	if (!h || !name || !*name)
		return DF1_E_INVAL;
	e = h->poll;
	for (size_t i = 0; e && i < e->ntags; i++)
		if (strcmp(e->tags[i]->cfg.name, name) == 0)
			return (int)i;
	return DF1_E_INVAL;
}

int df1_tag_get(const df1_t *h, int id, struct df1_tag_state *st)
{
	const struct poll_engine *e;

	if (!h || !st)
		return DF1_E_INVAL;
	e = h->poll;
	if (!e || id < 0 || (size_t)id >= e->ntags)
		return DF1_E_INVAL;
	poll_tag_state(e->tags[id], df1_now_ms(), st);
	return 0;
}

int df1_set_tag_callback(df1_t *h, df1_tag_fn fn, void *user)
{
	struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	e->cb = fn;
	e->cb_user = user;
	return 0;
}

/* ---- mapping CSV ---- */

/* df1_map_load hands one user pointer to both callbacks: this one, which
 * forwards issues to the caller's. */
struct poll_load {
	struct df1_tag_config *rows;
	size_t n, cap;
	df1_config_issue_fn issue_fn;
	void *user;
};

static void poll_load_forward(void *user, const struct df1_config_issue *issue)
{
	struct poll_load *l = user;

	if (l->issue_fn)
		l->issue_fn(l->user, issue);
}

static int poll_load_row(void *user, const struct df1_tag_config *tag)
{
	struct poll_load *l = user;

	if (l->n == l->cap) {
		size_t ncap = l->cap ? l->cap * 2 : 64;
		struct df1_tag_config *nr = realloc(l->rows, ncap * sizeof *nr);

		if (!nr)
			return DF1_E_NOMEM;
		l->rows = nr;
		l->cap = ncap;
	}
	l->rows[l->n++] = *tag;
	return 0;
}

static void poll_load_issue(df1_config_issue_fn fn, void *user, const char *name, const char *why)
{
	struct df1_config_issue is;

	if (!fn)
		return;
	memset(&is, 0, sizeof is);
	snprintf(is.text, sizeof is.text, "Tag %.63s: %.120s", name, why);
	fn(user, &is);
}

int df1_tag_load_map(df1_t *h, const char *path, bool strict, df1_config_issue_fn issue_fn, void *user)
{
	struct poll_load l = { NULL, 0, 0, issue_fn, user };
	bool *skip, bad = false;
	int rc, added = 0;

	if (!h || !path)
		return DF1_E_INVAL;
	if (!poll_engine(h))
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	/* the rows are collected first: on any failure nothing is added */
	rc = df1_map_load(path, strict, poll_load_row, poll_load_forward, &l);
	if (rc < 0) {
		free(l.rows);
		if (rc == DF1_E_NOMEM)
			return df1_fail(h, rc, -1, "%s: out of memory", path);
		return df1_fail(h, rc, -1, "%s: %s", path, df1_strerror(rc));
	}
	skip = calloc(l.n ? l.n : 1, sizeof *skip);
	if (!skip) {
		free(l.rows);
		return df1_fail(h, DF1_E_NOMEM, -1, "%s: out of memory", path);
	}
	/* duplicate names (in the file, or tags already added), and rows the engine
	 * cannot poll (bits of an F file...): reported, skipped */
	for (size_t i = 0; i < l.n; i++) {
		struct ptag scratch;
		bool dup = l.rows[i].name[0] && df1_tag_find(h, l.rows[i].name) >= 0;

		for (size_t j = 0; !dup && j < i; j++)
			dup = !skip[j] && l.rows[i].name[0] && strcmp(l.rows[i].name, l.rows[j].name) == 0;
		if (dup) {
			poll_load_issue(issue_fn, user, l.rows[i].name,
			                "defined twice, the first definition is kept");
			skip[i] = bad = true;
			continue;
		}
		memset(&scratch, 0, sizeof scratch);
		if (poll_tag_check(h, &l.rows[i], &scratch) < 0) {
			poll_load_issue(issue_fn, user, l.rows[i].name, df1_last_error(h)->message);
			skip[i] = bad = true;
		}
	}
	if (bad && strict) {
		free(skip);
		free(l.rows);
		return df1_fail(h, DF1_E_CONFIG, -1, "%s: tags that cannot be added", path);
	}
	for (size_t i = 0; i < l.n; i++) {
		if (skip[i])
			continue;
		rc = df1_tag_add(h, &l.rows[i]);
		if (rc < 0) {
			/* only out of memory is left */
			free(skip);
			free(l.rows);
			return rc;
		}
		added++;
	}
	free(skip);
	free(l.rows);
	return added;
}

/* ------------------------------------------------------------------------
 * Planning
 * ------------------------------------------------------------------------ */

static int poll_replan(struct df1 *h, struct poll_engine *e)
{
	struct poll_item *items;
	size_t n = 0, raw_need = 0, vals_need = 1;
	int gap = h->cfg.duplex == DF1_HALF_DUPLEX_MASTER ? POLL_TX_OVERHEAD_HALF : POLL_TX_OVERHEAD_FULL;
	int nb;

	items = calloc(e->ntags ? e->ntags : 1, sizeof *items);
	if (!items)
		return DF1_E_NOMEM;
	for (size_t i = 0; i < e->ntags; i++) {
		struct ptag *t = e->tags[i];
		struct poll_item *it;

		t->block = -1;
		if ((size_t)t->cfg.count > vals_need)
			vals_need = (size_t)t->cfg.count;
		if (!t->readable)
			continue;
		it = &items[n++];
		it->station = t->cfg.station;
		it->plc = t->cfg.plc;
		it->type = t->cfg.addr.type;
		it->file = t->cfg.addr.file;
		it->first = t->e0;
		it->count = t->ecount;
		it->cost = (int)plc_read_elem_cost(t->cfg.plc, t->cfg.addr.type, t->esize,
		                                   h->cfg.max_packet);
		it->limit = (int)plc_read_limit(t->cfg.plc, h->cfg.max_packet);
		it->alone = t->how == HOW_ALONE || t->isolated;
		it->period_ms = t->cfg.scan_ms;
		it->tag = (int)i;
	}
	if (n > e->blocks_cap || e->ntags > 0) {
		struct pblock *nbk = realloc(e->blocks, (n ? n : 1) * sizeof *nbk);
		int *nm = realloc(e->members, (n ? n : 1) * sizeof *nm);

		if (nbk)
			e->blocks = nbk;
		if (nm)
			e->members = nm;
		if (!nbk || !nm) {
			free(items);
			return DF1_E_NOMEM;
		}
		e->blocks_cap = n ? n : 1;
	}
	{
		struct poll_block *pb = calloc(n ? n : 1, sizeof *pb);

		if (!pb) {
			free(items);
			return DF1_E_NOMEM;
		}
		nb = poll_plan(items, n, gap, pb, n);
		if (nb < 0) {
			free(pb);
			free(items);
			return nb;
		}
		for (size_t k = 0; k < n; k++)
			e->members[k] = items[k].tag;
		for (int b = 0; b < nb; b++) {
			struct pblock *bk = &e->blocks[b];
			const struct ptag *t0 = e->tags[items[pb[b].member0].tag];

			memset(bk, 0, sizeof *bk);
			bk->station = pb[b].station;
			bk->plc = pb[b].plc;
			bk->type = pb[b].type;
			bk->file = pb[b].file;
			bk->first = pb[b].first;
			bk->count = pb[b].count;
			bk->esize = t0->esize;
			bk->alone = pb[b].alone;
			bk->period_ms = pb[b].period_ms;
			bk->m0 = pb[b].member0;
			bk->nm = pb[b].nmembers;
			bk->due_ms = POLL_NEVER;
			for (size_t k = bk->m0; k < bk->m0 + bk->nm; k++) {
				struct ptag *t = e->tags[e->members[k]];

				t->block = b;
				if (t->next_due_ms < bk->due_ms)
					bk->due_ms = t->next_due_ms;
			}
			if (!bk->alone && (size_t)bk->count * bk->esize > raw_need)
				raw_need = (size_t)bk->count * bk->esize;
		}
		free(pb);
	}
	free(items);
	e->nblocks = (size_t)nb;
	if (raw_need > e->raw_cap) {
		uint8_t *nr = realloc(e->raw, raw_need);

		if (!nr)
			return DF1_E_NOMEM;
		e->raw = nr;
		e->raw_cap = raw_need;
	}
	if (vals_need > e->vals_cap) {
		struct df1_value *nv = realloc(e->vals, vals_need * sizeof *nv);

		if (!nv)
			return DF1_E_NOMEM;
		e->vals = nv;
		e->vals_cap = vals_need;
	}
	for (int s = 0; s < POLL_STATIONS; s++) {
		e->st[s].b0 = 0;
		e->st[s].nb = 0;
		e->st[s].tags = 0;
	}
	for (size_t b = e->nblocks; b-- > 0;) {
		struct pstation *s = &e->st[e->blocks[b].station];

		s->b0 = (int)b;
		s->nb++;
	}
	for (size_t i = 0; i < e->ntags; i++)
		if (e->tags[i]->readable)
			e->st[e->tags[i]->cfg.station].tags++;
	e->stats.tags = (unsigned)e->ntags;
	e->stats.blocks = (unsigned)e->nblocks;
	e->dirty = false;
	return 0;
}

/* Split block b in two halves of its members (sorted by element). */
static void poll_split(struct poll_engine *e, size_t b)
{
	struct pblock *bk, *b2;
	size_t half;

	/* capacity: one block per readable tag at most, so this always fits */
	memmove(&e->blocks[b + 1], &e->blocks[b], (e->nblocks - b) * sizeof *e->blocks);
	e->nblocks++;
	bk = &e->blocks[b];
	b2 = &e->blocks[b + 1];
	half = bk->nm / 2;
	b2->m0 = bk->m0 + half;
	b2->nm = bk->nm - half;
	bk->nm = half;
	for (int k = 0; k < 2; k++) {
		struct pblock *x = k ? b2 : bk;
		long lo = LONG_MAX, hi = LONG_MIN;

		x->period_ms = INT_MAX;
		for (size_t m = x->m0; m < x->m0 + x->nm; m++) {
			const struct ptag *t = e->tags[e->members[m]];

			if (t->e0 < lo)
				lo = t->e0;
			if ((long)t->e0 + t->ecount > hi)
				hi = (long)t->e0 + t->ecount;
			if (t->cfg.scan_ms < x->period_ms)
				x->period_ms = t->cfg.scan_ms;
		}
		x->first = (int)lo;
		x->count = (int)(hi - lo);
		x->alone = false;
	}
	for (size_t i = b; i < e->nblocks; i++)
		for (size_t m = e->blocks[i].m0; m < e->blocks[i].m0 + e->blocks[i].nm; m++)
			e->tags[e->members[m]]->block = (int)i;
	e->st[bk->station].nb++;
	for (int s = bk->station + 1; s < POLL_STATIONS; s++)
		if (e->st[s].nb)
			e->st[s].b0++;
	e->stats.blocks = (unsigned)e->nblocks;
	e->stats.splits++;
}

/* ------------------------------------------------------------------------
 * Outcomes, tag updates, station health
 * ------------------------------------------------------------------------ */

static bool poll_addr_ext(uint8_t ext)
{
	switch (ext) {
	case 0x01: case 0x02: case 0x03: case 0x04: case 0x05: case 0x06: case 0x07:
	case 0x09: case 0x0A: case 0x11: case 0x13:
		return true;
	default:
		return false;
	}
}

static enum outcome poll_outcome(const struct df1 *h, int rc)
{
	const struct df1_error_detail *d = &h->err;

	if (rc >= 0)
		return OUT_OK;
	switch (rc) {
	case DF1_E_REMOTE:
		if (d->sts == 0x50 || (d->sts == 0xF0 && d->has_ext_sts && poll_addr_ext(d->ext_sts)))
			return OUT_ADDR;
		return OUT_PLC;
	case DF1_E_INVAL: case DF1_E_NOTSUP: case DF1_E_ADDR_RANGE: case DF1_E_ADDR_SYNTAX:
	case DF1_E_TYPE: case DF1_E_RANGE: case DF1_E_NOSPACE:
		return OUT_LOCAL;
	case DF1_E_INTR: case DF1_E_NOMEM: case DF1_E_NOT_OPEN:
		return OUT_ABORT;
	default:
		return OUT_LINK;
	}
}

/* Tag failure without an answer: UNCERTAIN with a value, else BAD. */
static void poll_tag_comm(struct poll_engine *e, struct ptag *t, int err)
{
	enum df1_quality q = DF1_QUALITY_BAD;

	t->last_error = err;
	if (t->r == DF1_REASON_STATION_OFFLINE)
		return;                 /* stays BAD offline until the station answers */
	if (t->has_value && (t->q == DF1_QUALITY_GOOD || t->q == DF1_QUALITY_UNCERTAIN))
		q = DF1_QUALITY_UNCERTAIN;
	poll_set_quality(e, t, q, DF1_REASON_COMM_FAILURE, false);
}

static void poll_tag_good(struct poll_engine *e, struct ptag *t, const struct df1_value *v,
                          int64_t now, int64_t wall)
{
	size_t bytes = (size_t)t->cfg.count * sizeof *v;
	bool changed = !t->has_value || memcmp(t->values, v, bytes) != 0;

	if (changed)
		memcpy(t->values, v, bytes);
	t->has_value = true;
	t->last_good_ms = now;
	t->last_good_wall_ms = wall;
	t->last_error = 0;
	t->sts = t->ext = 0;
	t->saved = false;
	t->reads++;
	poll_set_quality(e, t, DF1_QUALITY_GOOD, DF1_REASON_NONE, changed);
}

static void poll_tag_bad(struct poll_engine *e, struct ptag *t, enum df1_quality_reason r, int err,
                         const struct df1_error_detail *d)
{
	t->last_error = err;
	t->sts = d && err == DF1_E_REMOTE ? d->sts : 0;
	t->ext = d && err == DF1_E_REMOTE && d->has_ext_sts ? d->ext_sts : 0;
	t->saved = false;
	poll_set_quality(e, t, DF1_QUALITY_BAD, r, false);
}

/* The values of tag t out of block b's bytes (as on the wire: floats in order fo),
 * into e->vals. */
static int poll_decode(struct poll_engine *e, const struct ptag *t, const struct pblock *b,
                       enum value_float_order fo)
{
	const uint8_t *p = e->raw + (size_t)(t->e0 - b->first) * b->esize;
	const struct df1_addr *a = &t->cfg.addr;
	size_t es = b->esize;

	memset(e->vals, 0, (size_t)t->cfg.count * sizeof *e->vals);
	for (int i = 0; i < t->cfg.count; i++) {
		struct df1_value *v = &e->vals[i];

		switch (t->how) {
		case HOW_ELEM:
			if (value_decode_element(a->type, p + (size_t)i * es, es, v, fo) < 0)
				return DF1_E_BAD_REPLY;
			break;
		case HOW_WORD:
			v->kind = DF1_VAL_INT16;
			v->v.i16 = (int16_t)le16(p + (size_t)i * es + (size_t)t->word * 2);
			break;
		case HOW_BITS: {
			size_t g = (size_t)(a->bit + i);

			v->kind = DF1_VAL_BIT;
			if (t->word >= 0)               /* T/C/R: one word of the element */
				v->v.bit = value_get_bit(p + (size_t)t->word * 2, 2, g);
			else
				v->v.bit = value_get_bit(p, es, g);
			break;
		}
		case HOW_ALONE:
		default:
			return DF1_E_INVAL;
		}
	}
	return 0;
}

static void poll_attempt(struct poll_engine *e, int stn, int64_t now)
{
	struct pstation *s = &e->st[stn];

	s->attempts++;
	s->last_attempt_ms = now;
	if (!s->first_attempt_ms)
		s->first_attempt_ms = now;
	e->stats.transactions++;
}

/* The tags of a station, through its blocks. */
#define FOR_STATION_TAGS(e, stn, t)                                                          \
	for (int b_ = (e)->st[stn].b0; b_ < (e)->st[stn].b0 + (e)->st[stn].nb; b_++)        \
		for (size_t m_ = (e)->blocks[b_].m0; m_ < (e)->blocks[b_].m0 + (e)->blocks[b_].nm; m_++) \
			if (((t) = (e)->tags[(e)->members[m_]]) != NULL)

/* The station answered (data, or a PLC error status). */
static void poll_station_answer(struct poll_engine *e, int stn, int64_t now)
{
	struct pstation *s = &e->st[stn];
	struct ptag *t;

	s->fails = 0;
	s->last_good_ms = now;
	if (s->state == DF1_STATION_FAILING || s->state == DF1_STATION_OFFLINE) {
		/* seed 000: points back to their state before the failure, then a one-time
		 * poll of every point (the scan reads every block of the station now) */
		FOR_STATION_TAGS(e, stn, t) {
			if (t->saved) {
				t->saved = false;
				poll_set_quality(e, t, t->sq, t->sr, false);
			}
		}
		for (int b = s->b0; b < s->b0 + s->nb; b++)
			e->blocks[b].due_ms = 0;
		s->recovered = true;
	}
	s->state = DF1_STATION_OK;
}

/* An attempt to reach the station failed on the link. */
static void poll_station_fail(struct poll_engine *e, int stn, int err, int64_t now)
{
	struct pstation *s = &e->st[stn];
	struct ptag *t;
	int64_t ref;
	bool expired;

	s->fails++;
	s->failures++;
	s->last_error = err;
	if (s->nb == 0 && s->last_good_ms == 0) {
		s->state = DF1_STATION_ABSENT;  /* discovery: nobody there (yet) */
		return;
	}
	if (s->state == DF1_STATION_OFFLINE) {
		s->next_retry_ms = now + e->wd_ms / 2;
		return;
	}
	if (s->state != DF1_STATION_FAILING) {
		s->state = DF1_STATION_FAILING;
		FOR_STATION_TAGS(e, stn, t) {
			if (!t->saved) {
				t->saved = true;
				t->sq = t->q;
				t->sr = t->r;
			}
		}
	}
	ref = s->last_good_ms ? s->last_good_ms : s->first_attempt_ms;
	expired = e->abs_retries > 0 ? s->fails > e->abs_retries : now - ref >= e->wd_ms;
	if (!expired)
		return;
	s->state = DF1_STATION_OFFLINE;
	s->next_retry_ms = now + e->wd_ms / 2;
	FOR_STATION_TAGS(e, stn, t) {
		t->last_error = err;
		poll_set_quality(e, t, DF1_QUALITY_BAD, DF1_REASON_STATION_OFFLINE, false);
	}
}

static void poll_block_done(struct poll_engine *e, struct pblock *b, int64_t start)
{
	b->due_ms = start + b->period_ms;
	for (size_t m = b->m0; m < b->m0 + b->nm; m++) {
		struct ptag *t = e->tags[e->members[m]];

		t->next_due_ms = start + t->cfg.scan_ms;
	}
}

/* ------------------------------------------------------------------------
 * Writes
 * ------------------------------------------------------------------------ */

static int poll_write_one(struct df1 *h, struct poll_engine *e, struct wnode *w)
{
	struct ptag *t = e->tags[w->tag];
	int stn = t->cfg.station, rc;
	enum outcome o;
	int64_t now = df1_now_ms();

	poll_attempt(e, stn, now);
	e->stats.writes++;
	rc = client_write_at(h, stn, t->cfg.plc, &t->cfg.addr, w->v, w->n);
	o = poll_outcome(h, rc);
	now = df1_now_ms();
	if (o == OUT_OK || o == OUT_ADDR || o == OUT_PLC) {
		poll_station_answer(e, stn, now);
	} else if (o == OUT_LINK) {
		e->st[stn].last_error = rc;
		poll_station_fail(e, stn, rc, now);
	}
	if (rc >= 0) {
		if (t->readable) {
			t->next_due_ms = 0;             /* read the value back */
			if (t->block >= 0 && (size_t)t->block < e->nblocks)
				e->blocks[t->block].due_ms = 0;
		}
	} else {
		e->stats.write_failures++;
	}
	if (w->done)
		w->done(w->user, w->tag, w->wid, rc >= 0 ? 0 : rc);
	free(w);
	return o == OUT_ABORT ? rc : 1;
}

static struct wnode *poll_wq_pop(struct poll_engine *e)
{
	struct wnode *w;

	pthread_mutex_lock(&e->mu);
	w = e->wq_head;
	if (w) {
		e->wq_head = w->next;
		if (!e->wq_head)
			e->wq_tail = NULL;
		e->wq_len--;
	}
	pthread_mutex_unlock(&e->mu);
	return w;
}

/* The writes queued now, in order: the free slot between two transactions. */
static int poll_run_writes(struct df1 *h, struct poll_engine *e)
{
	unsigned limit;
	int done = 0;

	pthread_mutex_lock(&e->mu);
	limit = e->wq_len;
	pthread_mutex_unlock(&e->mu);
	while (limit-- > 0) {
		struct wnode *w = poll_wq_pop(e);
		int r;

		if (!w)
			break;
		r = poll_write_one(h, e, w);
		if (r < 0)
			return r;
		done += r;
	}
	return done;
}

int df1_tag_write(df1_t *h, int id, const struct df1_value *v, size_t n, df1_write_done_fn done,
                  void *user)
{
	struct poll_engine *e = h ? h->poll : NULL;
	struct ptag *t = NULL;
	struct wnode *w;
	enum df1_file_type vt;
	uint64_t one = 1;
	ssize_t wr;
	int wid;

	/* any thread: no df1_fail() here (the error detail belongs to the poll thread) */
	if (!e || !v || n == 0)
		return DF1_E_INVAL;
	pthread_mutex_lock(&e->mu);
	if (id >= 0 && (size_t)id < e->ntags)
		t = e->tags[id];
	pthread_mutex_unlock(&e->mu);
	if (!t || !t->writable || n > (size_t)t->cfg.count)
		return DF1_E_INVAL;
	vt = t->cfg.addr.sub != DF1_ADDR_NONE ? DF1_FT_N : t->cfg.addr.type;
	for (size_t i = 0; i < n; i++) {
		uint8_t scratch[96];
		int r;

		if (t->cfg.addr.bit != DF1_ADDR_NONE) {
			if (v[i].kind != DF1_VAL_BIT)
				return DF1_E_TYPE;
			continue;
		}
		r = value_encode_element(vt, &v[i], scratch, sizeof scratch, VALUE_FLOAT_LE);
		if (r < 0)
			return r;
	}
	w = malloc(sizeof *w + n * sizeof *v);
	if (!w)
		return DF1_E_NOMEM;
	w->next = NULL;
	w->tag = id;
	w->done = done;
	w->user = user;
	w->n = n;
	memcpy(w->v, v, n * sizeof *v);
	pthread_mutex_lock(&e->mu);
	w->wid = wid = e->next_wid;
	e->next_wid = e->next_wid == INT_MAX ? 1 : e->next_wid + 1;
	if (e->wq_tail)
		e->wq_tail->next = w;
	else
		e->wq_head = w;
	e->wq_tail = w;
	e->wq_len++;
	wr = write(e->wake_fd, &one, sizeof one);   /* under the lock: the fd outlives it */
	pthread_mutex_unlock(&e->mu);
	(void)wr;                                   /* EAGAIN: the counter is full, still readable */
	return wid;                                 /* w may be gone already */
}

/* ------------------------------------------------------------------------
 * Reads and probes
 * ------------------------------------------------------------------------ */

enum read_result { R_DONE, R_SPLIT, R_FAILED };

static int poll_block_io(struct df1 *h, struct poll_engine *e, const struct pblock *b)
{
	struct df1_addr a;

	if (b->alone) {
		const struct ptag *t = e->tags[e->members[b->m0]];

		memset(e->vals, 0, (size_t)t->cfg.count * sizeof *e->vals);
		return client_read_at(h, b->station, b->plc, &t->cfg.addr, e->vals, (size_t)t->cfg.count);
	}
	memset(&a, 0, sizeof a);
	a.type = b->type;
	a.file = b->file;
	a.element = b->first;
	a.sub = DF1_ADDR_NONE;
	a.bit = DF1_ADDR_NONE;
	return client_read_raw_at(h, b->station, b->plc, &a, e->raw, (size_t)b->count * b->esize);
}

/* The block answered with data: every member gets its values. */
static void poll_block_good(struct df1 *h, struct poll_engine *e, struct pblock *b)
{
	int64_t now = df1_now_ms(), wall = poll_wall_ms();
	enum value_float_order fo = value_typed_float_order(b->plc, h->cfg.plc5_float_swapped);

	for (size_t m = b->m0; m < b->m0 + b->nm; m++) {
		struct ptag *t = e->tags[e->members[m]];
		int r = b->alone ? 0 : poll_decode(e, t, b, fo);

		if (r < 0)
			poll_tag_bad(e, t, DF1_REASON_PLC_ERROR, r, &h->err);
		else
			poll_tag_good(e, t, e->vals, now, wall);
	}
}

/* One block, with `tries` attempts while the link fails. Returns transactions
 * done (>= 0) or a code that ends df1_poll; *res tells what became of it. */
static int poll_read_block(struct df1 *h, struct poll_engine *e, size_t bi, int tries, int64_t start,
                           enum read_result *res)
{
	int done = 0;

	for (;;) {
		struct pblock *b = &e->blocks[bi];
		int stn = b->station, rc, w;
		enum outcome o;
		int64_t now;

		w = poll_run_writes(h, e);      /* the free slot before this transaction */
		if (w < 0)
			return w;
		done += w;
		b = &e->blocks[bi];
		now = df1_now_ms();
		poll_attempt(e, stn, now);
		b->scan_read = e->scan_no;
		e->stats.reads++;
		e->scan_tx++;
		done++;
		rc = poll_block_io(h, e, b);
		o = poll_outcome(h, rc);
		now = df1_now_ms();
		if (o != OUT_OK && o != OUT_ABORT)     /* an interrupted read did not fail */
			e->stats.read_failures++;
		switch (o) {
		case OUT_OK:
			poll_station_answer(e, stn, now);
			poll_block_good(h, e, b);
			poll_block_done(e, b, start);
			*res = R_DONE;
			return done;
		case OUT_PLC:
			poll_station_answer(e, stn, now);
			for (size_t m = b->m0; m < b->m0 + b->nm; m++)
				poll_tag_bad(e, e->tags[e->members[m]], DF1_REASON_PLC_ERROR, rc, &h->err);
			poll_block_done(e, b, start);
			*res = R_DONE;
			return done;
		case OUT_ADDR:
		case OUT_LOCAL:
			if (o == OUT_ADDR)
				poll_station_answer(e, stn, now);
			if (b->nm > 1) {
				/* binary split: the halves are read at once, the split is kept */
				poll_split(e, bi);
				for (int k = 0; k < 2; k++) {
					e->blocks[bi + (size_t)k].due_ms = 0;
					e->blocks[bi + (size_t)k].scan_read = 0;
				}
				*res = R_SPLIT;
				return done;
			}
			{
				struct ptag *t = e->tags[e->members[b->m0]];

				if (!t->isolated && !b->alone) {
					/* a new bad tag: the next df1_poll() re-plans, so
					 * its neighbours merge again around it */
					t->isolated = true;
					e->dirty = true;
				}
				poll_tag_bad(e, t, o == OUT_ADDR ? DF1_REASON_PLC_ERROR : DF1_REASON_CONFIG, rc,
				             &h->err);
			}
			poll_block_done(e, b, start);
			*res = R_DONE;
			return done;
		case OUT_LINK:
			poll_station_fail(e, stn, rc, now);
			if (e->st[stn].state != DF1_STATION_OFFLINE && --tries > 0) {
				e->stats.retries++;
				continue;
			}
			*res = R_FAILED;
			return done;
		case OUT_ABORT:
		default:
			return rc;
		}
	}
}

/* After a failure: the failed block and the station's other due blocks wait for
 * their next period; their tags are UNCERTAIN (or BAD) COMM_FAILURE. */
static void poll_station_skip(struct poll_engine *e, int stn, size_t failed, int64_t start)
{
	struct pstation *s = &e->st[stn];
	int err = s->last_error;

	for (int i = s->b0; i < s->b0 + s->nb; i++) {
		struct pblock *b = &e->blocks[i];

		if ((size_t)i != failed && (b->scan_read == e->scan_no || b->due_ms > start))
			continue;
		for (size_t m = b->m0; m < b->m0 + b->nm; m++)
			poll_tag_comm(e, e->tags[e->members[m]], err);
		poll_block_done(e, b, start);
	}
}

static int poll_tries(const struct pstation *s)
{
	return s->state == DF1_STATION_OK || s->state == DF1_STATION_UNKNOWN ? 1 + POLL_RETRIES_OK : 1;
}

static int poll_scan_station(struct df1 *h, struct poll_engine *e, int stn, int64_t start)
{
	struct pstation *s = &e->st[stn];
	bool offline_try = false;
	int done = 0;

	if (s->state == DF1_STATION_OFFLINE) {
		if (start < s->next_retry_ms)
			return 0;
		offline_try = true;     /* one attempt every half watchdog (seed 000) */
		s->next_retry_ms = start + e->wd_ms / 2;
	}
	s->recovered = false;
	for (int i = s->b0; i < s->b0 + s->nb;) {
		struct pblock *b = &e->blocks[i];
		enum read_result res = R_DONE;
		int r;

		if (!offline_try && (b->scan_read == e->scan_no || b->due_ms > start)) {
			i++;
			continue;
		}
		r = poll_read_block(h, e, (size_t)i, offline_try ? 1 : poll_tries(s), start, &res);
		if (r < 0)
			return r;
		done += r;
		offline_try = false;
		if (res == R_SPLIT)
			continue;               /* the first half is at i now */
		if (res == R_FAILED) {
			if (s->state != DF1_STATION_OFFLINE)
				poll_station_skip(e, stn, (size_t)i, start);
			break;
		}
		if (s->state == DF1_STATION_OFFLINE)
			break;
		if (s->recovered) {
			s->recovered = false;
			i = s->b0;              /* the one-time poll of every block */
			continue;
		}
		i++;
	}
	return done;
}

/* A station without tags: link test (half duplex) or empty echo (full duplex). */
static int poll_probe(struct df1 *h, struct poll_engine *e, int stn, int tries)
{
	int done = 0;

	for (;;) {
		struct pstation *s = &e->st[stn];
		int rc, w;
		enum outcome o;
		int64_t now;

		w = poll_run_writes(h, e);
		if (w < 0)
			return w;
		done += w;
		now = df1_now_ms();
		poll_attempt(e, stn, now);
		e->stats.probes++;
		e->scan_tx++;
		done++;
		if (h->cfg.duplex == DF1_HALF_DUPLEX_MASTER)
			rc = df1_link_test(h, stn);
		else
			rc = df1_echo(h, stn, NULL, 0);
		o = poll_outcome(h, rc);
		now = df1_now_ms();
		if (o == OUT_ABORT)
			return rc;
		if (o == OUT_LOCAL)
			return done;
		if (o != OUT_LINK) {
			poll_station_answer(e, stn, now);
			s->recovered = false;
			return done;
		}
		e->stats.probe_failures++;
		poll_station_fail(e, stn, rc, now);
		if (s->state == DF1_STATION_OFFLINE || s->state == DF1_STATION_ABSENT || --tries <= 0)
			return done;
		e->stats.retries++;
	}
}

static bool poll_in_range(const struct poll_engine *e, int stn)
{
	return e->lo >= 0 && stn >= e->lo && stn <= e->hi;
}

/* The next absent (or never probed) address of the range, in turn. */
static int poll_probe_candidate(struct poll_engine *e)
{
	int span = e->hi - e->lo + 1;

	for (int k = 0; k < span; k++) {
		int stn = e->lo + (e->probe_next - e->lo + k) % span;
		const struct pstation *s = &e->st[stn];

		if (stn < e->lo || stn > e->hi)
			continue;
		if (s->nb == 0 && (s->state == DF1_STATION_UNKNOWN || s->state == DF1_STATION_ABSENT)) {
			e->probe_next = stn + 1 > e->hi ? e->lo : stn + 1;
			return stn;
		}
	}
	return -1;
}

/* When the next scan is due (blocks, slow retries, probes); POLL_NEVER if nothing. */
static int64_t poll_next_scan(const struct poll_engine *e)
{
	int64_t due = POLL_NEVER;

	for (size_t i = 0; i < e->nblocks; i++) {
		const struct pblock *b = &e->blocks[i];
		const struct pstation *s = &e->st[b->station];
		int64_t d = s->state == DF1_STATION_OFFLINE ? s->next_retry_ms : b->due_ms;

		if (d < due)
			due = d;
	}
	if (e->lo >= 0) {
		if (e->probe_due_ms < due)
			due = e->probe_due_ms;
		for (int stn = e->lo; stn <= e->hi; stn++) {
			const struct pstation *s = &e->st[stn];

			if (s->nb == 0 && s->state == DF1_STATION_OFFLINE && s->next_retry_ms < due)
				due = s->next_retry_ms;
		}
	}
	return due;
}

static int poll_scan(struct df1 *h, struct poll_engine *e, int64_t start)
{
	bool probe = e->lo >= 0 && start >= e->probe_due_ms;
	int done = 0, cand = -1, r;
	int64_t end;

	e->scan_no++;
	e->scan_tx = 0;
	if (probe) {
		e->probe_due_ms = start + POLL_PROBE_MS;
		cand = poll_probe_candidate(e);
	}
	for (int stn = 0; stn < POLL_STATIONS; stn++) {
		struct pstation *s = &e->st[stn];

		r = 0;
		if (s->nb > 0) {
			r = poll_scan_station(h, e, stn, start);
		} else if (poll_in_range(e, stn)) {
			if (s->state == DF1_STATION_OFFLINE) {
				if (start >= s->next_retry_ms) {
					s->next_retry_ms = start + e->wd_ms / 2;
					r = poll_probe(h, e, stn, 1);
				}
			} else if (s->state == DF1_STATION_OK || s->state == DF1_STATION_FAILING) {
				if (probe)
					r = poll_probe(h, e, stn, poll_tries(s));
			} else if (stn == cand) {
				r = poll_probe(h, e, stn, 1);
			}
		}
		if (r < 0)
			return r;
		done += r;
	}
	r = poll_run_writes(h, e);
	if (r < 0)
		return r;
	done += r;
	end = df1_now_ms();
	e->stats.scans++;
	e->stats.last_scan_ms = end - start;
	if (end - start > e->stats.max_scan_ms)
		e->stats.max_scan_ms = end - start;
	e->stats.last_scan_transactions = e->scan_tx;
	return done;
}

/* ------------------------------------------------------------------------
 * df1_poll
 * ------------------------------------------------------------------------ */

static void poll_drain_wake(struct poll_engine *e)
{
	uint64_t v;

	while (read(e->wake_fd, &v, sizeof v) > 0)
		;
}

static int poll_work(struct df1 *h, struct poll_engine *e)
{
	int n, r;
	int64_t now;

	if (e->dirty) {
		r = poll_replan(h, e);
		if (r < 0)
			return df1_fail(h, r, -1, "poll engine: cannot plan the scan list (%s)",
			                df1_strerror(r));
	}
	poll_drain_wake(e);
	n = poll_run_writes(h, e);
	if (n < 0)
		return n;
	now = df1_now_ms();
	if (poll_next_scan(e) <= now) {
		r = poll_scan(h, e, now);
		if (r < 0)
			return r;
		n += r;
	}
	return n;
}

static bool poll_queue_empty(struct poll_engine *e)
{
	bool empty;

	pthread_mutex_lock(&e->mu);
	empty = e->wq_head == NULL;
	pthread_mutex_unlock(&e->mu);
	return empty;
}

/* Wait until `until` for a queued write or the cancel fd. 1 woken, 0 time is
 * up, 2 a signal interrupted the wait, DF1_E_INTR, DF1_E_SYS. */
static int poll_wait(struct df1 *h, struct poll_engine *e, int64_t until)
{
	struct pollfd p[2] = { { e->wake_fd, POLLIN, 0 }, { h->cancel_fd, POLLIN, 0 } };
	nfds_t n = h->cancel_fd >= 0 ? 2 : 1;
	int64_t left = until == POLL_NEVER ? -1 : until - df1_now_ms();
	int ms = left < 0 ? -1 : left > INT_MAX ? INT_MAX : (int)left;
	int r;

	if (until != POLL_NEVER && left <= 0)
		return 0;
	r = poll(p, n, ms);
	if (r < 0) {
		if (errno == EINTR)
			return 2;
		return df1_fail(h, DF1_E_SYS, -1, "poll engine: poll: %s", strerror(errno));
	}
	if (n == 2 && p[1].revents)
		return df1_fail(h, DF1_E_INTR, -1, "poll engine: wait cancelled");
	return p[0].revents ? 1 : 0;
}

int df1_poll(df1_t *h, int timeout_ms)
{
	struct poll_engine *e;
	int64_t deadline;
	int n;

	if (!h)
		return DF1_E_INVAL;
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	if (!df1_is_open(h))
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "poll: the handle is not open");
	n = poll_work(h, e);
	if (n != 0 || timeout_ms == 0)
		return n;
	deadline = timeout_ms < 0 ? POLL_NEVER : df1_now_ms() + timeout_ms;
	for (;;) {
		int64_t next = poll_queue_empty(e) ? poll_next_scan(e) : 0;
		int64_t until = next < deadline ? next : deadline;
		int r;

		if (until <= df1_now_ms())
			break;
		r = poll_wait(h, e, until);
		if (r < 0)
			return r;
		if (r == 2)
			return 0;       /* a signal: let the caller look at its flags */
		if (r == 1)
			break;
	}
	return poll_work(h, e);
}

int df1_poll_next_ms(const df1_t *h)
{
	struct poll_engine *e;
	int64_t next, now;

	if (!h)
		return DF1_E_INVAL;
	e = h->poll;
	if (!e)
		return -1;
	if (e->dirty || !poll_queue_empty(e))
		return 0;
	next = poll_next_scan(e);
	if (next == POLL_NEVER)
		return -1;
	now = df1_now_ms();
	return next <= now ? 0 : next - now > INT_MAX ? INT_MAX : (int)(next - now);
}

int df1_poll_fd(df1_t *h)
{
	struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	return e->wake_fd;
}

/* ------------------------------------------------------------------------
 * Settings and statistics
 * ------------------------------------------------------------------------ */

int df1_poll_set_watchdog(df1_t *h, int watchdog_ms, int absolute_retries)
{
	struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	if (watchdog_ms < 0 || watchdog_ms > POLL_WATCHDOG_MAX_MS || absolute_retries < 0 ||
	    absolute_retries > POLL_RETRIES_MAX)
		return df1_fail(h, DF1_E_INVAL, -1,
		                "watchdog %d ms / retries %d: must be 0..%d ms and 0..%d", watchdog_ms,
		                absolute_retries, POLL_WATCHDOG_MAX_MS, POLL_RETRIES_MAX);
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	e->wd_ms = watchdog_ms;
	e->abs_retries = absolute_retries;
	return 0;
}

int df1_poll_set_station_range(df1_t *h, int lo, int hi)
{
	struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	if (lo >= 0 && (lo > 254 || hi < lo || hi > 254))
		return df1_fail(h, DF1_E_INVAL, -1, "station range %d-%d: must be within 0-254", lo, hi);
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	if (lo < 0) {
		e->lo = e->hi = -1;
		return 0;
	}
	e->lo = lo;
	e->hi = hi;
	e->probe_next = lo;
	e->probe_due_ms = 0;
	for (int s = 0; s < POLL_STATIONS; s++)
		e->st[s].in_range = s >= lo && s <= hi;
	return 0;
}

int df1_poll_stats(const df1_t *h, struct df1_poll_stats *out)
{
	struct poll_engine *e;

	if (!h || !out)
		return DF1_E_INVAL;
	memset(out, 0, sizeof *out);
	e = h->poll;
	if (!e)
		return 0;
	*out = e->stats;
	out->tags = (unsigned)e->ntags;
	out->blocks = (unsigned)e->nblocks;
	out->stations_offline = 0;
	for (int s = 0; s < POLL_STATIONS; s++)
		out->stations_offline += e->st[s].state == DF1_STATION_OFFLINE;
	pthread_mutex_lock(&e->mu);
	out->writes_queued = e->wq_len;
	pthread_mutex_unlock(&e->mu);
	return 0;
}

int df1_station_health(const df1_t *h, int station, struct df1_station_health *out)
{
	const struct poll_engine *e;
	const struct pstation *s;

	if (!h || !out || station < 0 || station > 254)
		return DF1_E_INVAL;
	memset(out, 0, sizeof *out);
	out->station = station;
	e = h->poll;
	if (!e)
		return 0;
	s = &e->st[station];
	out->state = s->state;
	out->tags = s->tags;
	out->blocks = s->nb;
	out->last_good_ms = s->last_good_ms;
	out->last_attempt_ms = s->last_attempt_ms;
	out->next_retry_ms = s->state == DF1_STATION_OFFLINE ? s->next_retry_ms : 0;
	out->consecutive_failures = s->fails;
	out->attempts = s->attempts;
	out->failures = s->failures;
	out->last_error = s->last_error;
	return 0;
}

/* Deprecated since 0.2: the old name, kept so that existing programs link. */
int df1_poll_station(const df1_t *h, int station, struct df1_station_health *out)
{
	return df1_station_health(h, station, out);
}

/* ------------------------------------------------------------------------
 * Teardown (df1_free)
 * ------------------------------------------------------------------------ */

static void poll_free_engine(struct df1 *h)
{
	struct poll_engine *e = h->poll;
	struct wnode *w;

	if (!e)
		return;
	/* every accepted write ends once: those never sent fail now */
	while ((w = poll_wq_pop(e)) != NULL) {
		if (w->done)
			w->done(w->user, w->tag, w->wid, DF1_E_NOT_OPEN);
		free(w);
	}
	for (size_t i = 0; i < e->ntags; i++) {
		free(e->tags[i]->values);
		free(e->tags[i]);
	}
	free(e->tags);
	free(e->blocks);
	free(e->members);
	free(e->raw);
	free(e->vals);
	close(e->wake_fd);
	pthread_mutex_destroy(&e->mu);
	free(e);
	h->poll = NULL;
}
