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

/* pipelining (pipe.c) */
int link_pipe_submit(struct df1 *h, const uint8_t *cmd, size_t n);
int pipe_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);

/* half duplex (half.c) */
int half_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);
int half_test(struct df1 *h, uint8_t station);
int half_serve(struct df1 *h, link_handler_fn fn, void *ctx, int64_t deadline_ms);

#endif
