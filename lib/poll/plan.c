/* SPDX-License-Identifier: MPL-2.0 */
/*
 * plan.c - the scan list planned into block reads (lib/client/block_plan.c)
 * when tags were added or a bad tag was isolated; a block split in two after
 * an address error. The only place the engine allocates after setup.
 */
#include "poll/poll_int.h"

/* The planner's items: one per readable tag. Every tag loses its block; the
 * largest tag's element count goes to *vals_need. Returns the number of items. */
static size_t replan_items(const struct df1 *h, struct poll_engine *e, struct poll_item *items,
                           size_t *vals_need)
{
	size_t n = 0;

	for (size_t i = 0; i < e->ntags; i++) {
		struct ptag *t = e->tags[i];
		struct poll_item *it;

		t->block = -1;
		if ((size_t)t->cfg.count > *vals_need)
			*vals_need = (size_t)t->cfg.count;
		if (!t->readable)
			continue;
		it = &items[n++];
		it->station = t->cfg.station;
		it->plc = t->cfg.plc;
		it->type = t->cfg.addr.type;
		it->file = t->cfg.addr.file;
		it->first = t->e0;
		it->count = t->ecount;
		it->cost = (int)t->esize;
		it->limit = plc_read_limit(t->cfg.plc, t->cfg.addr.type, t->esize, t->cfg.addr.file,
		                           t->e0, h->cfg.max_packet);
		it->alone = t->how == HOW_ALONE || t->isolated;
		it->period_ms = t->cfg.scan_ms;
		it->tag = (int)i;
	}
	return n;
}

/* Room for n blocks and n members. */
static int replan_room(struct poll_engine *e, size_t n)
{
	struct pblock *nbk;
	int *nm;

	if (n <= e->blocks_cap && e->ntags == 0)
		return 0;
	nbk = realloc(e->blocks, (n ? n : 1) * sizeof *nbk);
	nm = realloc(e->members, (n ? n : 1) * sizeof *nm);
	if (nbk)
		e->blocks = nbk;
	if (nm)
		e->members = nm;
	if (!nbk || !nm)
		return DF1_E_NOMEM;
	e->blocks_cap = n ? n : 1;
	return 0;
}

/* The engine's blocks from the planner's nb blocks pb over items; the largest
 * raw block read in bytes goes to *raw_need. */
static void replan_fill(struct poll_engine *e, const struct poll_item *items, size_t n,
                        const struct poll_block *pb, int nb, size_t *raw_need)
{
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
		if (!bk->alone && (size_t)bk->count * bk->esize > *raw_need)
			*raw_need = (size_t)bk->count * bk->esize;
	}
}

/* Plan the n items (poll_plan sorts them) into the engine's blocks; DF1_E_* when it cannot. */
static int replan_blocks(struct df1 *h, struct poll_engine *e, struct poll_item *items, size_t n,
                         size_t *raw_need)
{
	int gap = h->cfg.duplex == DF1_HALF_DUPLEX_MASTER ? POLL_TX_OVERHEAD_HALF : POLL_TX_OVERHEAD_FULL;
	struct poll_block *pb = calloc(n ? n : 1, sizeof *pb);
	int nb;

	if (!pb)
		return DF1_E_NOMEM;
	nb = poll_plan(items, n, gap, pb, n);
	if (nb >= 0) {
		replan_fill(e, items, n, pb, nb, raw_need);
		e->nblocks = (size_t)nb;
	}
	free(pb);
	return nb < 0 ? nb : 0;
}

/* A block's bytes and the largest tag's values fit the scan buffers. */
static int replan_buffers(struct poll_engine *e, size_t raw_need, size_t vals_need)
{
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
	return 0;
}

/* Each station's first block, block count and readable tags. */
static void replan_stations(struct poll_engine *e)
{
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
}

int poll_replan(struct df1 *h, struct poll_engine *e)
{
	struct poll_item *items;
	size_t n, raw_need = 0, vals_need = 1;
	int r;

	items = calloc(e->ntags ? e->ntags : 1, sizeof *items);
	if (!items)
		return DF1_E_NOMEM;
	n = replan_items(h, e, items, &vals_need);
	r = replan_room(e, n);
	if (r == 0)
		r = replan_blocks(h, e, items, n, &raw_need);
	free(items);
	if (r < 0)
		return r;
	r = replan_buffers(e, raw_need, vals_need);
	if (r < 0)
		return r;
	replan_stations(e);
	e->stats.tags = (unsigned)e->ntags;
	e->stats.blocks = (unsigned)e->nblocks;
	e->dirty = false;
	return 0;
}

/* Split block b in two halves of its members (sorted by element). */
void poll_split(struct poll_engine *e, size_t b)
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
