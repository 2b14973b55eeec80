/* SPDX-License-Identifier: MPL-2.0 */
/*
 * opts.c - the frame decoder options (FRAME_OPT_*) that the link settings
 * imply. Its own file: the handle sets up its decoder with it at df1_new()
 * without pulling in the link layer's code (tests/unit/client/test_client.c replaces all
 * of link.h but this).
 */
#include "link/link.h"

unsigned link_decoder_opts(const struct df1 *h)
{
	unsigned opts = 0;

	if (h->cfg.nak_0f)
		opts |= FRAME_OPT_ACCEPT_NAK_0F;
	if (h->cfg.hd_bcc_stx)
		opts |= FRAME_OPT_HD_BCC_STX;
	if (h->cfg.eot_bcc)
		opts |= FRAME_OPT_EOT_TRAILER;
	/* a radio modem sends no ACK or NAK: a DLE pair inside a frame breaks it
	 * (doc/PROTOCOL.md 2.6) */
	if (!h->cfg.embedded || h->cfg.duplex == DF1_RADIO_MODEM)
		opts |= FRAME_OPT_NO_EMBEDDED;
	if (h->cfg.duplex == DF1_HALF_DUPLEX_MASTER || h->cfg.duplex == DF1_HALF_DUPLEX_SLAVE)
		opts |= FRAME_OPT_HALF_DUPLEX;
	return opts;
}
