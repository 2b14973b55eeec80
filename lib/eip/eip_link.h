/* SPDX-License-Identifier: MPL-2.0 */
/*
 * link_eip.h - the link over EtherNet/IP (lib/eip/eip_link.c): an eip:// target's
 * session, opened by df1_open() and used by the link's dispatcher (link.c).
 */
#ifndef LIBDF1_LINK_EIP_H
#define LIBDF1_LINK_EIP_H

#include "df1_int.h"

/* Connect (TCP), RegisterSession, with h->cfg.eip_connected a Forward Open;
 * sets h->eip and h->fd. 0 or DF1_E_* (nothing left open). */
int link_eip_open(struct df1 *h, const char *target);
/* Forward Close, UnRegisterSession; frees h->eip (the socket stays to the port). */
void link_eip_close(struct df1 *h);
/* One command (DST SRC CMD STS TNS FNC ...): the reply's app bytes as the DF1
 * link gives them (DST SRC CMD STS TNS ...), length, or DF1_E_*. */
int link_eip_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);
/* ListServices round trip: 0 or DF1_E_*. */
int link_eip_test(struct df1 *h);

/* pure helpers, for tests */
const char *link_eip_status_text(uint32_t status);
const char *link_cip_status_text(uint8_t status);

#endif
