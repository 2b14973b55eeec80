/* SPDX-License-Identifier: MPL-2.0 */
/*
 * link - the DF1 link layer over a port: full-duplex peer, half-duplex master,
 * half-duplex slave (doc/PROTOCOL.md 1-2, doc/ARCHITECTURE.md 4, doc/REQUIREMENTS.md 004).
 */
#ifndef LIBDF1_LINK_H
#define LIBDF1_LINK_H

#include "df1_int.h"

/* Responder (core.c): replies waiting to be sent or acknowledged. Full duplex
 * keeps one in flight; a half-duplex slave queues them per station until polled. */
#define LINK_REPLY_SLOTS 8
struct link_reply {
	bool used;
	bool sent;                   /* transmitted, its ACK not seen yet */
	bool stale_first;            /* DF1_FAULT_STALE_REPLY: an old-TNS copy goes out first */
	bool stale_now;              /* full duplex: the frame in flight is that copy */
	bool corrupt;                /* DF1_FAULT_CORRUPT_REPLY: next transmission has a bad check */
	uint8_t stn;                 /* half duplex: the station that owes it */
	uint32_t seq;                /* queue order */
	int naks, enqs;              /* retries of this reply */
	int64_t due_ms;              /* DF1_FAULT_DELAY_REPLY: not before this time */
	int64_t ack_deadline_ms;     /* full duplex: ACK timer */
	size_t len;
	uint8_t app[FRAME_MAX_DATA];
};

/* Fault injection on the slave/peer side (df1_server_set_fault), indexed by enum df1_fault. */
#define FAULT_KINDS 8
struct link_faults {
	int per_mille[FAULT_KINDS];
	int value[FAULT_KINDS];
	uint64_t rng;                /* xorshift64* state, from df1_server_set_seed */
};

/* DF1_FAULT_SILENT_STATION value that silences every station (df1_serve(3)) */
#define FAULT_SILENT_ALL DF1_SILENT_ALL

/* Everything a responder keeps between link_serve() calls. The server owns it
 * (lib/server/server_dispatch.c, server_responder()) and passes it to link_serve(). */
struct link_responder {
	struct link_reply replies[LINK_REPLY_SLOTS];
	uint32_t seq;
	int awaiting;                /* half-duplex slave: slot + 1 sent on the last poll, 0 none */
	bool awaiting_stale;         /* ... and it was the stale copy */
	bool silenced;               /* full duplex: last frame ignored (SILENT_STATION) */
	int max_queue;               /* full duplex: commands not yet answered before NAK, 0: one */
	bool serve_station[256];     /* stations we answer as (half-duplex slave) */
	struct link_faults faults;
};

/* Master side: one transaction. cmd holds the app bytes (DST SRC CMD STS TNS ...);
 * the link assigns the TNS (bytes 4-5) and SRC, sends, handles ACK/NAK/ENQ/polls,
 * and returns the matching reply's app bytes (length) in reply, or DF1_E_*.
 * Replies are matched on source and full TNS; stale/duplicate ones are dropped. */
int link_transact(struct df1 *h, uint8_t *cmd, size_t cmd_len, uint8_t *reply, size_t reply_cap);

/* Pipelining (full duplex, DF1_OPT_MAX_OUTSTANDING; lib/link/pipe.c). A caller
 * that knows its next commands (the poll engine's scan) puts each one on the
 * pipeline: link_pipe_put gives it SRC and the next TNS (written into cmd, as
 * link_transact does) and a slot (>= 0, or DF1_E_*; DF1_E_NOTSUP when the
 * handle has no pipeline: link_pipe_depth 1), and the link sends it when the
 * line allows. link_pipe_wait waits for the slot's outcome: the reply's
 * length (its app bytes in reply) or DF1_E_* with the slot's error detail;
 * the slot is free again. Other link_transact calls go through the pipeline
 * while slots are in use. */
int link_pipe_depth(const struct df1 *h);      /* commands outstanding: 1 unless full duplex */
int link_pipe_pending(const struct df1 *h);    /* slots queued or on the line */
int link_pipe_used(const struct df1 *h);       /* slots in use (results not taken included) */
int link_pipe_put(struct df1 *h, uint8_t *cmd, size_t cmd_len);
int link_pipe_wait(struct df1 *h, int slot, uint8_t *reply, size_t cap);
/* Send at once what is held to go out with our next transmission (an ACK:
 * link_int.h's link_send_sym_held); 0 or DF1_E_*. The poll engine calls it when
 * df1_poll() returns: a master holds the ACK of a block's reply for the next
 * block's command while h->hold_reply_ack is set. */
int link_tx_flush(struct df1 *h);
/* The result of slot is not wanted: dropped when it is in. */
void link_pipe_abandon(struct df1 *h, int slot);
/* Every slot abandoned, and their outcomes waited for. */
int link_pipe_flush(struct df1 *h);
void link_pipe_reset(struct df1 *h);

/* Link test: full duplex DLE ENQ -> any response symbol; half duplex poll -> EOT or frame. */
int link_test(struct df1 *h, int station);

/* Slave / peer side. The handler gets a received command (app bytes) and writes
 * the reply app bytes; it returns the reply length, 0 for no reply, or DF1_E_*. */
typedef int (*link_handler_fn)(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n,
                               uint8_t *reply, size_t cap);
/* Receive and answer until deadline_ms, keeping the replies and faults in r
 * (lent for the call: h->resp); returns the number of commands handled
 * (>= 0), or DF1_E_CLOSED / DF1_E_INTR / DF1_E_SYS. */
int link_serve(struct df1 *h, struct link_responder *r, link_handler_fn fn, void *ctx,
               int64_t deadline_ms);

/* Half-duplex master (lib/link/route.c): one round of the line's service:
 * what is queued for the slaves (replies, routed messages) sent, and each
 * station polled (those marked in stations, may be NULL, and those the
 * master already talks to) so that their own messages come in; commands for
 * our station run through fn (NULL: df1_set_responder's). 0 or DF1_E_*. */
int link_route_round(struct df1 *h, const bool *stations, link_handler_fn fn, void *ctx);

/* The frame decoder's FRAME_OPT_* for the handle's configuration. */
unsigned link_decoder_opts(const struct df1 *h);

/* Send raw bytes: TX_Delay, trace callback, character counter, echo bookkeeping. */
int link_send_raw(struct df1 *h, const uint8_t *buf, size_t n);
/* Drop everything buffered (decoder state and unread bytes). */
void link_flush(struct df1 *h);

#endif
