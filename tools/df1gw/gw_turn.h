/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_turn - whose turn the line is: df1gw's two sources of work for the poll
 * engine's queue, the EtherNet/IP bridge's requests and the batches of MQTT
 * writes, take turns (round robin), and after a full batch a due poll read
 * goes before the next one (--duty-cycle; df1gw(1), ETHERNET/IP and WRITE
 * POLICY). Pure: the caller says what waits and acts on the answer
 * (gw_pub.c, gw_line_turns). A turn handed joins the engine's queue behind
 * what is on it, which is served in order before the next transaction of the
 * line; so a bridged request waits behind at most one batch of writes (the
 * one on the line, or the one whose turn came first), or the poll read on
 * the line when it came during a scan, never behind the rest of a backlog.
 */
#ifndef DF1_TOOLS_GW_TURN_H
#define DF1_TOOLS_GW_TURN_H

#include <stdbool.h>
#include <stddef.h>

enum gw_turn {
	GW_TURN_NONE,                /* nothing to hand to the line now */
	GW_TURN_BRIDGE,              /* every bridged request waiting */
	GW_TURN_WRITES,              /* a batch: at most duty MQTT writes */
	GW_TURN_POLL,                /* a batch waits, but a due poll read goes first: hand nothing */
};

/* What waits, as the caller sees it. */
struct gw_turn_state {
	unsigned bridge;             /* EtherNet/IP requests received, not handed yet */
	size_t backlog;              /* MQTT writes waiting (gw_wq) */
	unsigned batch;              /* writes of the last batch handed, not ended yet */
	unsigned since_read;         /* writes handed since the engine's last poll read */
	unsigned duty;               /* --duty-cycle */
	bool poll_due;               /* a poll read (or other engine work) is due */
	bool in_line;                /* asked from inside the line's work (df1_poll): no batch starts there */
	enum gw_turn last;           /* the source of the last turn handed: BRIDGE, WRITES, or NONE */
};

/* The turn to hand now. Asked again after each turn handed, until NONE or POLL. */
enum gw_turn gw_turn_next(const struct gw_turn_state *s);
/* "none", "bridge", "writes", "poll". */
const char *gw_turn_name(enum gw_turn t);

#endif
