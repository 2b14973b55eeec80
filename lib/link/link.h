/*
 * link - the DF1 link layer over a port: full-duplex peer, half-duplex master,
 * half-duplex slave (spec/protocol.md 1-2, DESIGN.md 4, seeds/004).
 */
#ifndef LIBDF1_LINK_H
#define LIBDF1_LINK_H

#include "df1_int.h"

/* Master side: one transaction. cmd holds the app bytes (DST SRC CMD STS TNS ...);
 * the link assigns the TNS (bytes 4-5) and SRC, sends, handles ACK/NAK/ENQ/polls,
 * and returns the matching reply's app bytes (length) in reply, or DF1_E_*.
 * Replies are matched on source and full TNS; stale/duplicate ones are dropped. */
int link_transact(struct df1 *h, uint8_t *cmd, size_t cmd_len, uint8_t *reply, size_t reply_cap);

/* Link test: full duplex DLE ENQ -> any response symbol; half duplex poll -> EOT or frame. */
int link_test(struct df1 *h, int station);

/* Slave / peer side. The handler gets a received command (app bytes) and writes
 * the reply app bytes; it returns the reply length, 0 for no reply, or DF1_E_*. */
typedef int (*link_handler_fn)(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n,
                               uint8_t *reply, size_t cap);
/* Receive and answer until deadline_ms; returns the number of commands handled
 * (>= 0), or DF1_E_CLOSED / DF1_E_INTR / DF1_E_SYS. */
int link_serve(struct df1 *h, link_handler_fn fn, void *ctx, int64_t deadline_ms);

/* The frame decoder's FRAME_OPT_* for the handle's configuration. */
unsigned link_decoder_opts(const struct df1 *h);

/* Send raw bytes: TX_Delay, trace callback, character counter, echo bookkeeping. */
int link_send_raw(struct df1 *h, const uint8_t *buf, size_t n);
/* Drop everything buffered (decoder state and unread bytes). */
void link_flush(struct df1 *h);

#endif
