/* SPDX-License-Identifier: MPL-2.0 */
/*
 * read_multi.c - df1_read_multi(): many addresses of one station in the fewest
 * transactions (df1_read_multi(3)).
 *
 * Every request is checked first (parse, count, buffer). Requests of one file
 * are planned into block reads by the poll engine's planner (lib/proto/
 * poll_plan.c) with POLL_GAP_FEWEST_TX and the packet-limit table
 * (lib/proto/plc_limits.h): ranges that overlap or touch are one block, a gap
 * is bridged when the joined block takes fewer packets than the two apart
 * (not on a PLC-5: POLL_GAP_TOUCH_ONLY).
 * Bits, T/C/R words and T/C/R bits are taken from the elements (words) a
 * block reads, as the poll engine does. I/O addresses, PLC-5 "$" addresses
 * and sub-elements of other files are read on their own. Blocks are read in
 * the order of their first request, the addresses read alone after them, in
 * request order.
 *
 * A block the PLC refuses (DF1_E_REMOTE) that serves several requests is read
 * again request by request, so that each gets its own result and one bad
 * address does not hide the others' values. A failure without a usable answer
 * (timeout, retry limits, port error, interrupt) ends the call: the requests
 * not read yet keep result 0. The error detail is that of the first failure
 * in reading order, its address field the request's address.
 *
 * Allocation: two per call (the plan; one block's values); none per packet.
 */
#include "df1_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "client/client.h"
#include "proto/plc_limits.h"
#include "client/block_plan.h"

/* How a request's values come out of its block. */
enum rm_how {
	RM_ALONE = 0,   /* not in a block: read on its own */
	RM_ELEM,        /* whole elements */
	RM_TCR_WORD,    /* one word (.0 .PRE .ACC ...) of consecutive T/C/R elements */
	RM_TCR_BITS,    /* bits of one word of one T/C/R element */
	RM_WORD_BITS,   /* bits of consecutive 16-bit words (32-bit for L) */
};

static bool rm_is_tcr(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R;
}

/* How request r is read and the elements lo..hi of its file it needs. */
static enum rm_how rm_layout(const struct df1_read_req *r, int *lo, int *hi)
{
	const struct df1_addr *a = &r->addr;
	int n = (int)r->count;

	if (a->ascii[0] || a->type == DF1_FT_I || a->type == DF1_FT_O || a->type == DF1_FT_NONE ||
	    df1_file_type_element_size(a->type) <= 0)
		return RM_ALONE;
	*lo = a->element;
	if (a->bit == DF1_ADDR_NONE) {
		if (a->sub == DF1_ADDR_NONE) {
			*hi = a->element + n - 1;
			return RM_ELEM;
		}
		if (!rm_is_tcr(a->type))
			return RM_ALONE;
		*hi = a->element + n - 1;
		return RM_TCR_WORD;
	}
	if (rm_is_tcr(a->type)) {
		*hi = a->element;
		return RM_TCR_BITS;
	}
	if (a->sub != DF1_ADDR_NONE)
		return RM_ALONE;
	*hi = a->element + (a->bit + n - 1) / (a->type == DF1_FT_L ? 32 : 16);
	return RM_WORD_BITS;
}

static int16_t rm_tcr_word(const struct df1_tcr *t, int sub)
{
	return sub == 0 ? (int16_t)t->ctl : sub == 1 ? t->pre : t->acc;
}

/* Request r's values out of a block of elements starting at element first. */
static void rm_extract(struct df1_read_req *r, const struct df1_value *bvals, int first)
{
	const struct df1_addr *a = &r->addr;
	int lo = 0, hi = 0;
	enum rm_how how = rm_layout(r, &lo, &hi);
	const struct df1_value *bv = bvals + (lo - first);

	for (size_t i = 0; i < r->count; i++) {
		struct df1_value *v = &r->values[i];

		memset(v, 0, sizeof *v);
		switch (how) {
		case RM_ELEM:
			*v = bv[i];
			break;
		case RM_TCR_WORD:
			v->kind = DF1_VAL_INT16;
			v->v.i16 = rm_tcr_word(&bv[i].v.tcr, a->sub);
			break;
		case RM_TCR_BITS: {
			int sub = a->sub == DF1_ADDR_NONE ? 0 : a->sub;
			uint16_t w = (uint16_t)rm_tcr_word(&bv[0].v.tcr, sub);

			v->kind = DF1_VAL_BIT;
			v->v.bit = (w >> (a->bit + (int)i)) & 1u;
			break;
		}
		case RM_WORD_BITS: {
			bool l = a->type == DF1_FT_L;
			size_t nb = l ? 32 : 16, g = (size_t)a->bit + i;
			uint32_t w = l ? (uint32_t)bv[g / nb].v.i32 : (uint16_t)bv[g / nb].v.i16;

			v->kind = DF1_VAL_BIT;
			v->v.bit = (w >> (g % nb)) & 1u;
			break;
		}
		case RM_ALONE:
			break;
		}
	}
}

/* A failure that leaves the rest of the call worth trying: the station
 * answered (a PLC error, a wrong reply) or the request was refused locally. */
static bool rm_goes_on(int rc)
{
	switch (rc) {
	case DF1_E_REMOTE: case DF1_E_BAD_REPLY: case DF1_E_BAD_FUNCTION:
	case DF1_E_INVAL: case DF1_E_NOTSUP: case DF1_E_ADDR_RANGE: case DF1_E_ADDR_SYNTAX:
	case DF1_E_TYPE: case DF1_E_RANGE: case DF1_E_NOSPACE:
		return true;
	default:
		return false;
	}
}

struct rm_call {
	struct df1 *h;
	int station;
	struct df1_read_req *reqs;
	bool stop;                      /* DF1_READ_MULTI_STOP */
	unsigned reads;
	int first_rc;                   /* 0, or the first failure in reading order */
	struct df1_error_detail first;  /* its detail */
};

/* Request i failed with rc: its result, and the call's first failure. */
static void rm_fail(struct rm_call *c, size_t i, int rc)
{
	struct df1_read_req *r = &c->reqs[i];

	r->result = rc;
	if (c->first_rc < 0)
		return;
	c->first_rc = rc;
	c->first = c->h->err;
	if (c->first.code != rc) {
		memset(&c->first, 0, sizeof c->first);
		c->first.code = rc;
		c->first.station = c->station;
		c->first.catalog_id = df1_error_catalog_id(rc);
		snprintf(c->first.message, sizeof c->first.message, "%s", df1_strerror(rc));
	}
	if (r->text)
		snprintf(c->first.address, sizeof c->first.address, "%s", r->text);
	else if (r->addr.ascii[0])
		snprintf(c->first.address, sizeof c->first.address, "$%s", r->addr.ascii);
	else if (df1_addr_format_plc(c->h->cfg.plc, &r->addr, c->first.address, sizeof c->first.address) < 0)
		c->first.address[0] = '\0';
}

/* Read request i on its own. Returns false when the call ends. */
static bool rm_read_alone(struct rm_call *c, size_t i)
{
	struct df1_read_req *r = &c->reqs[i];
	int rc;

	c->reads++;
	rc = client_read_at(c->h, c->station, c->h->cfg.plc, &r->addr, r->values, r->count);
	if (rc >= 0) {
		r->result = (int)r->count;
		return true;
	}
	rm_fail(c, i, rc);
	return rm_goes_on(rc) && !c->stop;
}

/* Read block b (members items[b->member0 ..]) into vals. Returns false when the call ends. */
static bool rm_read_block(struct rm_call *c, const struct poll_block *b, const struct poll_item *items,
                          struct df1_value *vals)
{
	struct df1_addr ba;
	size_t m0 = b->member0, m1 = b->member0 + b->nmembers, earliest = (size_t)items[m0].tag;
	int rc;

	memset(&ba, 0, sizeof ba);
	ba.type = b->type;
	ba.file = b->file;
	ba.element = b->first;
	ba.sub = DF1_ADDR_NONE;
	ba.bit = DF1_ADDR_NONE;
	memset(vals, 0, (size_t)b->count * sizeof *vals);
	c->reads++;
	rc = client_read_at(c->h, c->station, c->h->cfg.plc, &ba, vals, (size_t)b->count);
	if (rc >= 0) {
		for (size_t m = m0; m < m1; m++) {
			struct df1_read_req *r = &c->reqs[items[m].tag];

			rm_extract(r, vals, b->first);
			r->result = (int)r->count;
		}
		return true;
	}
	for (size_t m = m0; m < m1; m++)
		if ((size_t)items[m].tag < earliest)
			earliest = (size_t)items[m].tag;
	if (rc != DF1_E_REMOTE || b->nmembers < 2) {
		/* the failure concerns the block: its earliest request names it */
		rm_fail(c, earliest, rc);
		for (size_t m = m0; m < m1; m++)
			c->reqs[items[m].tag].result = rc;
		return rm_goes_on(rc) && !c->stop;
	}
	/* the PLC refused the block: each request on its own, in request order */
	for (size_t i = earliest; i < SIZE_MAX; ) {
		size_t next = SIZE_MAX;

		if (!rm_read_alone(c, i))
			return false;
		for (size_t m = m0; m < m1; m++)
			if ((size_t)items[m].tag > i && (size_t)items[m].tag < next)
				next = (size_t)items[m].tag;
		i = next;
	}
	return true;
}

/* Check request i; 0 or the DF1_E_* code (its result). */
static int rm_check(struct df1 *h, struct df1_read_req *r)
{
	int rc;

	r->result = 0;
	if (r->text) {
		rc = df1_addr_parse_plc(h->cfg.plc, r->text, &r->addr);
		if (rc < 0)
			return rc;
	}
	if (!r->values || r->count == 0 || r->count > 0xFFFF)
		return DF1_E_INVAL;
	(void)h;
	return 0;
}

/* Block order: by the earliest request each serves. */
static size_t rm_block_key(const struct poll_block *b, const struct poll_item *items)
{
	size_t k = (size_t)items[b->member0].tag;

	for (size_t m = b->member0; m < b->member0 + b->nmembers; m++)
		if ((size_t)items[m].tag < k)
			k = (size_t)items[m].tag;
	return k;
}

static int rm_finish(struct rm_call *c, size_t n)
{
	if (c->first_rc < 0) {
		c->h->err = c->first;
		return c->first_rc;
	}
	return (int)n;
}

/* Check every request (a bad one gets its result and the error detail). */
static void rm_check_all(struct rm_call *c, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		int rc = rm_check(c->h, &c->reqs[i]);

		if (rc < 0) {
			df1_fail(c->h, rc, c->station, "%s", df1_strerror(rc));
			rm_fail(c, i, rc);
		}
	}
}

/* The planner's items: one per valid request a block can serve (its tag the
 * request's index). Returns how many. */
static size_t rm_items(const struct rm_call *c, size_t n, struct poll_item *items)
{
	struct df1 *h = c->h;
	size_t k = 0;

	for (size_t i = 0; i < n; i++) {
		const struct df1_read_req *r = &c->reqs[i];
		const struct df1_addr *a = &r->addr;
		struct poll_item *it;
		int lo = 0, hi = 0;
		size_t es;

		if (r->result < 0 || rm_layout(r, &lo, &hi) == RM_ALONE || hi > 999)
			continue;       /* past element 999: the client refuses it alone */
		es = (size_t)df1_file_type_element_size(a->type);
		it = &items[k++];
		it->station = c->station;
		it->plc = h->cfg.plc;
		it->type = a->type;
		it->file = a->file;
		it->first = lo;
		it->count = hi - lo + 1;
		it->cost = (int)es;
		it->limit = plc_read_limit(h->cfg.plc, a->type, es, a->file, lo, h->cfg.max_packet);
		it->tag = (int)i;
	}
	return k;
}

/* The nb blocks in the order of their first request (insertion sort: few)
 * into order[]. Returns the largest block's count (at least 1). */
static size_t rm_order(const struct poll_block *blocks, size_t nb, const struct poll_item *items,
                       size_t *order)
{
	size_t maxcount = 1;

	for (size_t b = 0; b < nb; b++) {
		size_t j = b, key = rm_block_key(&blocks[b], items);

		while (j > 0 && rm_block_key(&blocks[order[j - 1]], items) > key) {
			order[j] = order[j - 1];
			j--;
		}
		order[j] = b;
		if ((size_t)blocks[b].count > maxcount)
			maxcount = (size_t)blocks[b].count;
	}
	return maxcount;
}

/* The blocks in order, then the addresses read alone (every planned one has
 * its result by then), until a failure that ends the call. */
static void rm_read_all(struct rm_call *c, size_t n, const struct poll_block *blocks, size_t nb,
                        const size_t *order, const struct poll_item *items, struct df1_value *vals)
{
	for (size_t b = 0; b < nb; b++)
		if (!rm_read_block(c, &blocks[order[b]], items, vals))
			return;
	for (size_t i = 0; i < n; i++)
		if (c->reqs[i].result == 0 && !rm_read_alone(c, i))
			return;
}

int df1_read_multi(df1_t *h, int station, struct df1_read_req *reqs, size_t n, unsigned flags,
                   unsigned *reads)
{
	struct rm_call c;
	struct poll_item *items;
	struct poll_block *blocks;
	size_t *order, k, maxcount;
	struct df1_value *vals;
	void *mem;
	int nb;

	if (reads)
		*reads = 0;
	if (!h)
		return DF1_E_INVAL;
	if (station == 255)
		return df1_fail(h, DF1_E_INVAL, station, "station 255 is a broadcast: nobody answers "
		                "a read there (0-254)");
	if (station < 0 || station > 254)
		return df1_fail(h, DF1_E_INVAL, station, "station %d out of range 0-254", station);
	if (!reqs || n == 0 || n > 0xFFFF || (flags & ~(unsigned)DF1_READ_MULTI_STOP))
		return df1_fail(h, DF1_E_INVAL, station, "no requests");
	memset(&c, 0, sizeof c);
	c.h = h;
	c.station = station;
	c.reqs = reqs;
	c.stop = flags & DF1_READ_MULTI_STOP;
	rm_check_all(&c, n);
	if (c.stop && c.first_rc < 0)
		return rm_finish(&c, n);        /* nothing sent */

	/* the plan: blocks, their order and the items in one allocation */
	mem = calloc(n, sizeof *blocks + sizeof *order + sizeof *items);
	if (!mem)
		return df1_fail(h, DF1_E_NOMEM, station, "%s", df1_strerror(DF1_E_NOMEM));
	blocks = mem;
	order = (size_t *)(blocks + n);
	items = (struct poll_item *)(order + n);
	k = rm_items(&c, n, items);
	/* a PLC-5 typed packet carries an address and a type/data parameter whose
	 * sizes vary: what a gap would save is not known, so only ranges that
	 * overlap or touch are joined there */
	nb = poll_plan(items, k, h->cfg.plc == DF1_PLC_PLC5 ? POLL_GAP_TOUCH_ONLY : POLL_GAP_FEWEST_TX,
	               blocks, k ? k : 1);
	if (nb < 0)
		nb = 0;         /* cannot happen: one block per item at most */
	maxcount = rm_order(blocks, (size_t)nb, items, order);
	/* one block's values at a time */
	vals = calloc(maxcount, sizeof *vals);
	if (!vals) {
		free(mem);
		return df1_fail(h, DF1_E_NOMEM, station, "%s", df1_strerror(DF1_E_NOMEM));
	}
	rm_read_all(&c, n, blocks, (size_t)nb, order, items, vals);
	free(vals);
	free(mem);
	if (reads)
		*reads = c.reads;
	return rm_finish(&c, n);
}
