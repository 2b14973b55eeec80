/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_rx_table - the Receive rows (df1gw(1), RECEIVE) as data: each row's
 * region of df1gw's data table, and a row's state as the formats see it.
 * No line, no broker: gw_receive.c serves the table on the line and
 * publishes, gw_sfwd.c replays what was buffered of a row; both use this
 * file, and neither calls the other in a cycle (gw_receive.c calls
 * gw_sfwd.c, never the reverse).
 *
 * A row no PLC (or MQTT client) has written yet holds no message: its
 * region reads zero, and it is told as no value, quality UNCERTAIN, reason
 * GW_RX_REASON_UNWRITTEN; the first write makes it GOOD with the values.
 */
#ifndef DF1_TOOLS_GW_RX_TABLE_H
#define DF1_TOOLS_GW_RX_TABLE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1.h"
#include "df1_server.h"

#define GW_RX_REASON_UNWRITTEN "no_message_yet"

struct gw;

/* One Receive row. */
struct gw_rx_tag {
	struct df1_tag_config c;
	struct df1_tag_config shown; /* c as the formats see it: read-write (Sparkplug's metric) */
	size_t lo, hi;               /* its bytes in its file: [lo, hi) */
	bool written;                /* a PLC (or an MQTT write) has written it since the start */
	int from;                    /* the station of the last write, -1: none yet */
	int64_t wall_ms;             /* when it was written (ms since the epoch), 0: never */
};

struct gw_rx {
	struct gw_rx_tag *v;
	size_t n;
	struct df1_table *t;         /* the regions' files; kept across reopens */
	bool slave;                  /* the line is a half-duplex slave: df1_serve, no df1_poll */
	uint64_t received;           /* writes from the line that landed in a region */
	int station;                 /* df1gw's own (--src, the network file's Station) */
	struct gw *g;
};

/* Receive tag name's configuration and id as the formats know it (row i is
 * tag id ntags + i, after the ntags polled ones), in cur (no values); false:
 * no such Receive tag. */
bool gw_rx_tag_state(const struct gw_rx *rx, int ntags, const char *name, struct df1_tag_state *cur);

/* Row e's state (tag id ntags + its index) into *st, its values in vals (room for DF1_TABLE_ELEMENTS_MAX):
 * as the table holds them (told false: a write's current values), or as the
 * formats tell it (told true: before the row's first write no value,
 * UNCERTAIN, *reason GW_RX_REASON_UNWRITTEN; else GOOD, *reason NULL).
 * 0 or DF1_E_*. */
int gw_rx_row_state(struct gw_rx *rx, int ntags, const struct gw_rx_tag *e, bool told, struct df1_tag_state *st,
                    struct df1_value *vals, const char **reason);

/* Every row's region set to zero (the table's files start with a pattern
 * of their own: no PLC sent it). 0 or DF1_E_*. */
int gw_rx_zero(struct gw_rx *rx);

#endif
