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

#endif
