/* SPDX-License-Identifier: MPL-2.0 */
/*
 * poll_plan.c - the block planner (poll_plan.h): the poll engine's scan list
 * and df1_read_multi() plan their reads with it. Pure: no I/O, no clock, no
 * allocation.
 */
#include "client/block_plan.h"

#include <stdlib.h>

static int poll_item_cmp(const void *pa, const void *pb)
{
	const struct poll_item *a = pa, *b = pb;

	if (a->station != b->station)
		return a->station < b->station ? -1 : 1;
	if (a->plc != b->plc)
		return a->plc < b->plc ? -1 : 1;
	if (a->file != b->file)
		return a->file < b->file ? -1 : 1;
	if (a->type != b->type)
		return a->type < b->type ? -1 : 1;
	if (a->first != b->first)
		return a->first < b->first ? -1 : 1;
	if (a->count != b->count)
		return a->count > b->count ? -1 : 1;
	if (a->alone != b->alone)
		return a->alone ? 1 : -1;
	return a->tag < b->tag ? -1 : a->tag > b->tag;
}

/* Packets for count elements: the client splits on element boundaries, so a
 * packet carries limit / cost whole elements (at least one). */
static long poll_packets(long count, int cost, int limit)
{
	long per = cost > 0 && limit > 0 ? limit / cost : 1;

	if (per < 1)
		per = 1;
	return count <= 0 ? 1 : (count + per - 1) / per;
}

int poll_block_packets(const struct poll_block *b, const struct poll_item *items)
{
	const struct poll_item *it = &items[b->member0];

	return (int)poll_packets(b->count, it->cost, it->limit);
}

int poll_plan(struct poll_item *items, size_t n, int gap_max, struct poll_block *out, size_t cap)
{
	size_t nb = 0;
	struct poll_block *cur = NULL;

	if (n > 1)
		qsort(items, n, sizeof *items, poll_item_cmp);
	for (size_t i = 0; i < n; i++) {
		const struct poll_item *it = &items[i];

		if (cur && !cur->alone && !it->alone && cur->station == it->station &&
		    cur->plc == it->plc && cur->type == it->type && cur->file == it->file) {
			long end = (long)cur->first + cur->count;           /* exclusive */
			long iend = (long)it->first + it->count;
			long nend = iend > end ? iend : end;
			long gap = (long)it->first - end;                     /* elements */
			const struct poll_item *b0 = &items[cur->member0];
			long before = poll_packets(cur->count, b0->cost, b0->limit);
			long after = poll_packets(nend - cur->first, b0->cost, b0->limit);
			bool join;

			if (gap_max == POLL_GAP_TOUCH_ONLY)
				join = gap <= 0;
			else if (gap_max == POLL_GAP_FEWEST_TX)
				join = gap <= 0 ||
				       after < before + poll_packets(it->count, it->cost, it->limit);
			else
				join = (gap <= 0 || gap * it->cost <= gap_max) && after <= before;
			if (join) {
				cur->count = (int)(nend - cur->first);
				cur->nmembers++;
				if (it->period_ms < cur->period_ms)
					cur->period_ms = it->period_ms;
				continue;
			}
		}
		if (nb == cap)
			return DF1_E_NOSPACE;
		cur = &out[nb++];
		cur->station = it->station;
		cur->plc = it->plc;
		cur->type = it->type;
		cur->file = it->file;
		cur->first = it->first;
		cur->count = it->count;
		cur->alone = it->alone;
		cur->period_ms = it->period_ms;
		cur->member0 = i;
		cur->nmembers = 1;
	}
	return (int)nb;
}
