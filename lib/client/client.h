/* SPDX-License-Identifier: MPL-2.0 */
/*
 * client.h - the client's internal calls for the rest of the library (the
 * poll engine, df1_read_multi): reads and writes of a parsed address with the
 * PLC type given per call, so the caller neither formats the address as text
 * for it to parse again nor changes the handle's configured PLC type
 * (h->cfg.plc). Same checks, splitting, returns and error detail as
 * df1_read_addr / df1_write_addr / df1_read_raw. Not installed.
 */
#ifndef LIBDF1_CLIENT_H
#define LIBDF1_CLIENT_H

#include "df1_int.h"

/* n values from a (bits for a bit address); returns n or DF1_E_*. */
int client_read_at(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                   struct df1_value *out, size_t n);
int client_write_at(struct df1 *h, int station, enum df1_plc plc,
                              const struct df1_addr *a, const struct df1_value *in, size_t n);
/* nbytes of whole elements from a, as on the wire; returns nbytes or DF1_E_*. */
int client_read_raw_at(struct df1 *h, int station, enum df1_plc plc,
                                 const struct df1_addr *a, uint8_t *buf, size_t nbytes);

/* Pipelining (lib/poll/scan.c): client_read_raw_at in two halves around the
 * link's pipeline (link_pipe_put, link_pipe_wait), one implementation with it.
 * client_read_raw_cmd builds the read's (first) command, DST SRC CMD STS TNS
 * FNC ... as link_transact takes it (the link sets SRC and TNS), and sends
 * nothing; it returns the command's length or DF1_E_* (recorded as
 * client_read_raw_at records it). client_read_raw_reply takes that command's
 * outcome, rc and reply as link_pipe_wait returned them, and finishes the read
 * exactly as client_read_raw_at does: the same checks, error detail and
 * counters, the bytes in buf, and the further packets (if the reply held fewer
 * elements than asked) as ordinary transactions; nbytes or DF1_E_*. */
int client_read_raw_cmd(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                        size_t nbytes, uint8_t *cmd, size_t cap);
int client_read_raw_reply(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                          uint8_t *buf, size_t nbytes, int rc, const uint8_t *reply);

#endif
