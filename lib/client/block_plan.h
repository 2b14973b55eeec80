/* SPDX-License-Identifier: MPL-2.0 */
/*
 * poll_plan.h - the block planner (lib/client/block_plan.c) of the poll engine
 * and of df1_read_multi(), exposed for unit tests. Pure: no I/O, no clock, no
 * allocation.
 *
 * Coalescing rule (df1_poll(3)): items of one station, PLC type, file and file
 * type are sorted by element and packed greedily from the lowest element: an
 * item joins the open block when the block then takes no more packets than
 * before (one packet of `limit` bytes carries limit / cost whole elements, the
 * client's split, unless a single item is already larger; the block's packets
 * are counted with its first item's limit, whose element starts every packet's
 * PLC-5 address) and the gap it
 * bridges costs no more wire bytes than one more read transaction would
 * (gap_max bytes). Greedy packing from the left gives the fewest blocks for
 * these two rules (checked against an exhaustive search in tests/unit/poll/test_poll.c).
 *
 * gap_max = POLL_GAP_FEWEST_TX plans for the fewest transactions instead
 * (df1_read_multi(3)): items that overlap or touch are always one block, and a
 * gap is bridged whenever the joined block takes fewer packets than the open
 * block and the item read apart, whatever the gap's bytes.
 *
 * An item marked alone (isolated after an address error, an I/O word, a PLC-5
 * ASCII address) is a block of its own and is never bridged over.
 */
#ifndef LIBDF1_POLL_PLAN_H
#define LIBDF1_POLL_PLAN_H

#include <stdbool.h>
#include <stddef.h>
#include "df1.h"

/* Wire bytes of one more read transaction, before DLE stuffing: command frame
 * (DLE STX, 6 header bytes, FNC and 5 address bytes, DLE ETX, CRC), reply
 * framing (DLE STX, 6 header bytes, DLE ETX, CRC) and the two DLE ACKs; half
 * duplex adds DLE SOH STN and one poll (DLE ENQ STN BCC). */
#define POLL_TX_OVERHEAD_FULL 34
#define POLL_TX_OVERHEAD_HALF 41
/* gap_max: the fewest transactions (df1_read_multi), see above */
#define POLL_GAP_FEWEST_TX (-1)
/* gap_max: items that overlap or touch are one block, gaps are never bridged
 * (df1_read_multi on a PLC-5, whose packets' overhead varies) */
#define POLL_GAP_TOUCH_ONLY (-2)

struct poll_item {
	int station;
	enum df1_plc plc;
	enum df1_file_type type;
	int file;
	int first, count;       /* elements covered: first .. first + count - 1 */
	int cost;               /* wire bytes per element (its size) */
	int limit;              /* bytes of whole elements one packet carries from this
	                         * item's first element (plc_read_limit): limit / cost
	                         * elements a packet, as the client splits */
	bool alone;
	int period_ms;
	int tag;                /* the caller's index, carried along */
};

struct poll_block {
	int station;
	enum df1_plc plc;
	enum df1_file_type type;
	int file;
	int first, count;       /* elements read */
	bool alone;
	int period_ms;          /* the shortest period of its members */
	size_t member0, nmembers; /* items[member0 .. member0 + nmembers) after sorting */
};

/* Sort items (station, PLC, file, file type, element) and plan blocks into out.
 * Returns the number of blocks (<= n), or DF1_E_NOSPACE if cap is too small. */
int poll_plan(struct poll_item *items, size_t n, int gap_max, struct poll_block *out, size_t cap);

/* Transactions a block takes (packets of its PLC type's limit). */
int poll_block_packets(const struct poll_block *b, const struct poll_item *items);

#endif
