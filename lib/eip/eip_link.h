/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip_link.h - the link over EtherNet/IP (lib/eip/eip_link.c): an eip:// target's
 * own link, named by the scheme table (lib/scheme.c); df1_open() opens it and the
 * link layer's entry points (lib/link/link.c) call it through h->own_link.
 */
#ifndef LIBDF1_EIP_LINK_H
#define LIBDF1_EIP_LINK_H

#include "df1_int.h"

/* open: connect (h->port, TCP), RegisterSession, with h->cfg.eip_connected a
 * Forward Open; its session in h->own_link_data. close: Forward Close,
 * UnRegisterSession, frees the session (the socket stays to the port).
 * transact: one command in a CIP Execute PCCC request. test: a ListServices
 * round trip. */
extern const struct own_link_ops eip_link_ops;

/* pure helpers, for tests */
const char *link_eip_status_text(uint32_t status);
const char *link_cip_status_text(uint8_t status);

#endif
