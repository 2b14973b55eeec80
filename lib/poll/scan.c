/* SPDX-License-Identifier: MPL-2.0 */
/*
 * scan.c - block reads and their errors (split, isolate, station failure),
 * the scan of one station, when the next scan is due, and one scan of every
 * station in address order.
 */
#include "poll/poll_int.h"

#include "proto/value_type.h"

enum read_result { R_DONE, R_SPLIT, R_FAILED };

/* The address of a block read: its first element, whole elements. */
static void poll_block_addr(const struct pblock *b, struct df1_addr *a)
{
	memset(a, 0, sizeof *a);
	a->type = b->type;
	a->file = b->file;
	a->element = b->first;
	a->sub = DF1_ADDR_NONE;
	a->bit = DF1_ADDR_NONE;
}

static int poll_block_io(struct df1 *h, struct poll_engine *e, const struct pblock *b)
{
	struct df1_addr a;

	if (b->alone) {
		const struct ptag *t = e->tags[e->members[b->m0]];

		memset(e->vals, 0, (size_t)t->cfg.count * sizeof *e->vals);
		return client_read_at(h, b->station, b->plc, &t->cfg.addr, e->vals, (size_t)t->cfg.count);
	}
	poll_block_addr(b, &a);
	return client_read_raw_at(h, b->station, b->plc, &a, e->raw, (size_t)b->count * b->esize);
}

/* ------------------------------------------------------------------------
 * Pipelining: block reads submitted ahead (poll_int.h)
 * ------------------------------------------------------------------------ */

static bool poll_pipe_candidate(const struct poll_engine *e, const struct pblock *b, int64_t start)
{
	const struct pstation *s = &e->st[b->station];

	if (b->alone || b->pipe_scan == e->scan_no || s->state == DF1_STATION_FAILING ||
	    s->state == DF1_STATION_OFFLINE)
		return false;
	return b->scan_read != e->scan_no && b->due_ms <= start;
}

/* The client builds the block's command, the link's pipeline takes it. A
 * command that cannot be built or put goes nowhere: the block's read then
 * runs as an ordinary transaction and meets the same failure itself. */
static void poll_pipe_put(struct df1 *h, struct poll_engine *e, struct pblock *b)
{
	uint8_t cmd[FRAME_MAX_DATA];
	struct df1_addr a;
	int n;

	poll_block_addr(b, &a);
	n = client_read_raw_cmd(h, b->station, b->plc, &a, (size_t)b->count * b->esize, cmd, sizeof cmd);
	b->pipe_slot = n < 0 ? -1 : link_pipe_put(h, cmd, (size_t)n);
	if (b->pipe_slot < 0)
		b->pipe_slot = -1;
	b->pipe_scan = e->scan_no;
}

/* Before block bi's transaction: it and the due blocks after it, up to the depth. */
static void poll_pipe_fill(struct df1 *h, struct poll_engine *e, size_t bi, int64_t start)
{
	int depth = link_pipe_depth(h);
	struct pblock *b = &e->blocks[bi];

	if (depth <= 1)
		return;
	if (!b->alone && b->pipe_scan != e->scan_no && link_pipe_used(h) < LINK_PIPE_MAX - 1)
		poll_pipe_put(h, e, b);
	for (size_t i = bi + 1; i < e->nblocks; i++) {
		if (link_pipe_pending(h) >= depth || link_pipe_used(h) >= LINK_PIPE_MAX - 1)
			break;
		if (poll_pipe_candidate(e, &e->blocks[i], start))
			poll_pipe_put(h, e, &e->blocks[i]);
	}
}

/* The read of block b takes the reply of what was submitted for it, if anything. */
static int poll_block_read(struct df1 *h, struct poll_engine *e, struct pblock *b)
{
	uint8_t reply[FRAME_MAX_DATA];
	struct df1_addr a;
	int slot = b->pipe_slot, rc;

	if (b->pipe_scan != e->scan_no || slot < 0)
		return poll_block_io(h, e, b);
	b->pipe_slot = -1;
	df1_clear_error(h);     /* as client_transact before link_transact */
	rc = link_pipe_wait(h, slot, reply, sizeof reply);
	poll_block_addr(b, &a);
	return client_read_raw_reply(h, b->station, b->plc, &a, e->raw, (size_t)b->count * b->esize, rc,
	                             reply);
}

/* The end of a scan (or its abort): nothing submitted ahead is left behind. */
static int poll_pipe_end(struct df1 *h, int rc)
{
	if (rc < 0) {
		link_pipe_reset(h);
		return rc;
	}
	if (link_pipe_used(h) > 0) {
		int r = link_pipe_flush(h);

		if (r < 0)
			return r;
	}
	return rc;
}

/* The block answered with data: every member gets its values. */
static void poll_block_good(struct df1 *h, struct poll_engine *e, struct pblock *b)
{
	int64_t now = df1_now_ms(), wall = poll_wall_ms();
	enum value_float_order fo = value_typed_float_order(b->plc, h->cfg.plc5_float_swapped);

	for (size_t m = b->m0; m < b->m0 + b->nm; m++) {
		struct ptag *t = e->tags[e->members[m]];
		int r = b->alone ? 0 : poll_decode(e, t, b, fo);

		if (r < 0) {
			poll_tag_bad(e, t, DF1_REASON_PLC_ERROR, r, &h->err);
			continue;
		}
		for (int i = 0; i < t->cfg.count; i++)
			value_type_widen(&e->vals[i], t->kind);     /* as its Type declares */
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
		poll_pipe_fill(h, e, bi, start);
		b = &e->blocks[bi];
		rc = poll_block_read(h, e, b);
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

static int poll_scan_station(struct df1 *h, struct poll_engine *e, int stn, int64_t start)
{
	struct pstation *s = &e->st[stn];
	bool offline_try = false;
	int done = 0;

	if (s->state == DF1_STATION_OFFLINE) {
		if (start < s->next_retry_ms)
			return 0;
		offline_try = true;     /* one attempt every half watchdog (doc/REQUIREMENTS.md 000) */
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

/* When the next scan is due (blocks, slow retries, probes); POLL_NEVER if nothing. */
int64_t poll_next_scan(const struct poll_engine *e)
{
	int64_t due = POLL_NEVER;

	for (size_t i = 0; i < e->nblocks; i++) {
		const struct pblock *b = &e->blocks[i];
		const struct pstation *s = &e->st[b->station];
		int64_t d = s->state == DF1_STATION_OFFLINE ? s->next_retry_ms : b->due_ms;

		if (d < due)
			due = d;
	}
	return poll_discover_due(e, due);
}

int poll_scan(struct df1 *h, struct poll_engine *e, int64_t start)
{
	struct poll_probe_scan ps;
	int done = 0, r;
	int64_t end;

	e->scan_no++;
	e->scan_tx = 0;
	poll_discover(h, e, -1, start, &ps);
	for (int stn = 0; stn < POLL_STATIONS; stn++) {
		if (e->st[stn].nb > 0)
			r = poll_scan_station(h, e, stn, start);
		else
			r = poll_discover(h, e, stn, start, &ps);   /* stations without tags */
		if (r < 0)
			return poll_pipe_end(h, r);
		done += r;
	}
	r = poll_pipe_end(h, poll_run_writes(h, e));
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
