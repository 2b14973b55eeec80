/* SPDX-License-Identifier: MPL-2.0 */
/*
 * link_int.h - inside the link module: what core.c gives full.c and half.c,
 * and the modes' entry points that link.c dispatches to. Not used outside
 * lib/link/.
 */
#ifndef LIBDF1_LINK_INT_H
#define LIBDF1_LINK_INT_H

#include "df1_int.h"
#include "link/link.h"

/* setup */
int link_setup(struct df1 *h);
enum df1_check link_tx_check(const struct df1 *h);
int64_t link_timeout_ms(const struct df1 *h);
/* Microseconds of one character at baud with the handle's framing (8N1: 10 bits). */
int64_t link_char_us(const struct df1 *h, int baud);
/* A deadline ms after our last transmission has left the line (df1_now_ms
 * clock): timers that wait for an answer start there, not when write()
 * returned (a 220-byte frame needs 1.8 s at 1200 baud). */
int64_t link_after_tx_ms(const struct df1 *h, int64_t ms);

/* The bytes at once, without TX_Delay (what is held goes first, with it):
 * the radio modem's keyed transmission, which waits TX_Delay itself before
 * keying (radio.c). 0 or DF1_E_*. */
int link_send_now(struct df1 *h, const uint8_t *buf, size_t n);
/* A pause until deadline_ms that only the cancel fd ends: 0, DF1_E_INTR, DF1_E_SYS. */
int link_pause_ms(struct df1 *h, int64_t deadline_ms);

/* transmission: DLE sym with its counter (ACK/NAK also set the last response) */
int link_send_sym(struct df1 *h, uint8_t sym);
/* The same, but held to go out in one write with our next transmission (an
 * ACK and the reply that follows it: one write, one wakeup, one TCP segment
 * less per transaction). Counted now. Whatever is held goes out at the latest
 * before the next wait for input (link_read_symbol) or when link_serve
 * returns; link_tx_flush sends it at once. */
int link_send_sym_held(struct df1 *h, uint8_t sym);

/* reception: 1 (sym filled), 0 (deadline passed), DF1_E_* */
/* Noise or a broken symbol: the receiver's last response becomes NAK (doc/PROTOCOL.md 1.7). */
void link_noise(struct df1 *h);
int link_read_symbol(struct df1 *h, int64_t deadline_ms, struct df1_symbol *sym);
int link_wait_input_us(struct df1 *h, int64_t deadline_us);
void link_bad_check(struct df1 *h, const struct df1_symbol *s);
bool link_log_error(struct df1 *h, const struct df1_symbol *s);

/* duplicate detection, per station key */
bool link_is_dup(const struct df1 *h, uint8_t key, const uint8_t *app, size_t n);
void link_remember(struct df1 *h, uint8_t key, const uint8_t *app, size_t n);
/* A duplicate: DLE ACK again, counted (2526, 2549, 2524) even when the ACK
 * fails; returns the ACK's result. */
int link_ack_dup(struct df1 *h, const struct df1_symbol *s);
/* A responder's frame with a good check, keyed for duplicates by key: a
 * duplicate, or a reply (the responder has no command outstanding: stale,
 * 2548, 2510), is ACKed and dropped (0); a new command is 1; DF1_E_*. */
int link_serve_screen(struct df1 *h, uint8_t key, const struct df1_symbol *s);
/* An accepted (ACKed) message on the master side: 1 = the reply to cmd (copied),
 * 0 = stale / unsolicited (counted, dropped; always when cmd is NULL), DF1_E_*. */
int link_take_reply(struct df1 *h, const uint8_t *cmd, const struct df1_symbol *s,
                    uint8_t *reply, size_t cap, size_t *len);
/* The reply to cmd (station and TNS already matched): its CMD checked, counted,
 * copied; its length, or DF1_E_BAD_FUNCTION / DF1_E_NOSPACE. Every mode's. */
int link_reply_copy(struct df1 *h, const uint8_t *cmd, const struct df1_symbol *s, uint8_t *reply,
                    size_t cap);

/* faults */
bool link_fault(struct link_responder *r, enum df1_fault f);
bool link_fault_silent(struct link_responder *r, uint8_t station);
/* Every station silent: not even a bare DLE ENQ is answered (full duplex). */
bool link_fault_silent_all(struct link_responder *r);
size_t link_noise_bytes(struct link_responder *r, uint8_t *out);

/* reply slots */
struct link_reply *link_slot_new(struct df1 *h, uint8_t stn, const uint8_t *app, size_t n);
bool link_slot_free_exists(const struct df1 *h);
struct link_reply *link_slot_oldest(struct df1 *h, bool all, uint8_t stn);
void link_slots_clear(struct df1 *h);
int link_slot_send(struct df1 *h, struct link_reply *r, bool stale, bool first);

/* full duplex (full.c) */
int full_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);
int full_test(struct df1 *h);
int full_serve(struct df1 *h, link_handler_fn fn, void *ctx, int64_t deadline_ms);

/* The full-duplex reply transmitter (peer.c), df1_serve's and the master's:
 * send a queued reply; its ACK, NAK (again, until the limit) and ACK timeout
 * (ENQ, until the limit); 0 or DF1_E_*. */
int peer_tx_start(struct df1 *h, struct link_reply *t);
int peer_tx_acked(struct df1 *h, struct link_reply *t);
int peer_tx_nak(struct df1 *h, struct link_reply *t);
int peer_tx_timeout(struct df1 *h, struct link_reply *t);

/* A full-duplex master answering its peer (peer.c). peer_command takes a
 * command frame (good check, not a duplicate): ACK (held when held) and its
 * reply queued, or NAK when the queue is full; 0 or DF1_E_*. peer_on_line:
 * a reply of ours waits for its ACK (a DLE ACK / NAK is its: peer_acked,
 * peer_nak). peer_start sends the next reply that is due; call it only when
 * no frame of ours waits for an ACK. peer_deadline: the reply's ACK timer or
 * due time (INT64_MAX none); peer_timeout acts on it when the read ran to dl. */
int peer_command(struct df1 *h, const struct df1_symbol *s, bool held);
bool peer_on_line(struct df1 *h);
int peer_start(struct df1 *h);
void peer_acked(struct df1 *h);
int peer_nak(struct df1 *h);
int64_t peer_deadline(struct df1 *h);
int peer_timeout(struct df1 *h, int64_t dl);

/* radio modem (radio.c; doc/PROTOCOL.md 2.6) */
int radio_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);
int radio_serve(struct df1 *h, link_handler_fn fn, void *ctx, int64_t deadline_ms);

/* pipelining (pipe.c) */
int link_pipe_submit(struct df1 *h, const uint8_t *cmd, size_t n);
int pipe_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);

/* The reply a full-duplex master gives its peer's command: df1_set_responder's
 * handler, or STS 10h without one (peer.c). Its length, 0, or DF1_E_*. */
int peer_answer(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *out, size_t cap);
/* Those replies' queue: df1_set_responder's (the server's), else the link's own; NULL: no memory. */
struct link_responder *peer_responder(struct df1 *h);

/* A half-duplex master's messages from slaves (route.c). */
#define ROUTE_SLOTS 16
enum route_kind {
	ROUTE_REPLY = 1,  /* a reply for a slave: ours, a routed one, or our error for it */
	ROUTE_CMD,        /* a slave's command for another slave */
	ROUTE_BCAST,      /* a slave's broadcast (DST 255) */
	ROUTE_EXEC,       /* a command for our station, to run in the next round */
};
struct route_msg {
	bool used;
	bool waiting;                /* ROUTE_CMD: ACKed by its target, the reply not in yet */
	enum route_kind kind;
	uint8_t dst;                 /* the station it goes to, 255 for a broadcast */
	uint32_t seq;                /* queue order */
	int64_t deadline_ms;         /* waiting: Cmd_Timeout */
	size_t len;
	uint8_t app[FRAME_MAX_DATA];
};
struct link_route {
	struct route_msg q[ROUTE_SLOTS];
	uint32_t seq;
	bool poll[256];              /* stations polled in a round */
	struct df1_route_stats st;
	link_handler_fn fn;          /* df1_serve's handler while a round runs, else NULL */
	void *ctx;
	bool in_round;
};
/* The handle's routing state, allocated on first use (NULL: no memory). */
struct link_route *route_state(struct df1 *h);
/* The oldest message queued for stn and not yet sent, or NULL. */
struct route_msg *route_next(struct link_route *r, uint8_t stn);
/* m, a routed command, becomes the master's reply with sts to its sender. */
void route_error_reply(struct route_msg *m, uint8_t sts);
/* Commands for our station kept for a round (ROUTE_EXEC) run now: 0 or DF1_E_*. */
int route_run_kept(struct df1 *h, struct link_route *r);
/* Routed commands whose reply did not come within Cmd_Timeout: STS 05h to their senders. */
void route_expire(struct df1 *h, struct link_route *r);
/* A station the master has a command for: polled in the rounds from now on. */
void route_seen(struct df1 *h, uint8_t stn);
/* A reply for our own station (link_take_reply's), not one to route? */
bool route_is_ours(const struct df1 *h, const uint8_t *d);
/* Any other good slave message the master ACKed: run, queued or dropped; 0 or DF1_E_*. */
int route_take(struct df1 *h, const struct df1_symbol *s);
/* df1_serve on a half-duplex master: rounds (link_route_round) of the
 * stations in resp->serve_station and those the master talks to, until
 * deadline or a round that handled a slave's message; their number. */
int link_master_serve(struct df1 *h, struct link_responder *resp, link_handler_fn fn, void *ctx,
                      int64_t deadline_ms);

/* half duplex (half.c) */
int half_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);
int half_test(struct df1 *h, uint8_t station);
int half_serve(struct df1 *h, link_handler_fn fn, void *ctx, int64_t deadline_ms);
/* A master message to stn with no reply awaited by us (a routed message):
 * 1 ACKed (at once for 255: a broadcast is not ACKed), 0 not ACKed within
 * the NAK retries (the station leaves the active list), DF1_E_*. */
int half_send_msg(struct df1 *h, uint8_t stn, const uint8_t *app, size_t n);
/* One poll of stn with no command of ours outstanding, waiting the poll-answer
 * time: 1 it sent a message (taken: route.c), 0 EOT or nothing, DF1_E_*. */
int half_poll_station(struct df1 *h, uint8_t stn);
/* A half-duplex slave's own command (half_msg.c): queued for the next poll of
 * our station, the polls and the master's commands served meanwhile, until
 * the master brings its reply. Reply length or DF1_E_*. */
int half_slave_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);
/* A half-duplex slave's own command while it waits (half_msg.c; h->own_msg). */
struct link_own_msg {
	const uint8_t *cmd;
	struct link_reply *slot;
	uint32_t seq;                /* the slot's, while it holds our command */
	bool acked, done;
	uint8_t *reply;
	size_t cap, len;
	int rc;
};
/* half_serve's hooks for it (half_msg_rx.c): the master message s (good check, not a
 * duplicate) is the reply our command waits for: ACKed and taken (1), or 0. */
int half_msg_reply(struct df1 *h, const struct df1_symbol *s);
/* ... and our command went out and was ACKed (slot r). */
void half_msg_acked(struct df1 *h, const struct link_reply *r);
/* ... and it is over (its reply in, or a broadcast ACKed): half_serve returns. */
bool half_msg_over(const struct df1 *h);

#endif
