/* SPDX-License-Identifier: MPL-2.0 */
/*
 * link.c - the link layer's entry points (lib/link/link.h): check the handle,
 * bring the decoder in line with the settings (link_setup), assign SRC and TNS,
 * and hand the work to the mode: full.c (full-duplex peer), half.c
 * (half-duplex master and slave) or radio.c (radio modem). They sit on core.c. A handle whose
 * scheme brings its own link (h->own_link: eip://, lib/scheme.c) goes to that
 * instead (EtherNet/IP: no duplex, no line).
 */
#include "link/link.h"

#include <string.h>

#include "link/link_int.h"

/* Our SRC and the next TNS in a command (bytes 1, 4-5). */
static void link_stamp(struct df1 *h, uint8_t *cmd)
{
	cmd[1] = (uint8_t)h->cfg.station;
	cmd[4] = (uint8_t)(h->next_tns & 0xFF);
	cmd[5] = (uint8_t)(h->next_tns >> 8);
	h->next_tns++;
}

/* ------------------------------------------------------------------------
 * Entry points
 * ------------------------------------------------------------------------ */

int link_transact(struct df1 *h, uint8_t *cmd, size_t cmd_len, uint8_t *reply, size_t reply_cap)
{
	int r;

	if (!h || !cmd || cmd_len < FRAME_MIN_DATA || cmd_len > FRAME_MAX_DATA || (!reply && reply_cap))
		return h ? df1_fail(h, DF1_E_INVAL, -1, "invalid command (%zu bytes)", cmd_len)
		         : DF1_E_INVAL;
	r = link_setup(h);
	if (r < 0)
		return r;
	link_stamp(h, cmd);
	if (h->cfg.duplex == DF1_HALF_DUPLEX_SLAVE && !h->own_link)
		return half_slave_transact(h, cmd, cmd_len, reply, reply_cap); /* our own MSG */
	if (h->own_link)
		return h->own_link->transact(h, cmd, cmd_len, reply, reply_cap);
	if (h->cfg.duplex == DF1_HALF_DUPLEX_MASTER)
		return half_transact(h, cmd, cmd_len, reply, reply_cap);
	if (h->cfg.duplex == DF1_RADIO_MODEM)
		return radio_transact(h, cmd, cmd_len, reply, reply_cap);
	if (h->pipe.used > 0)
		return pipe_transact(h, cmd, cmd_len, reply, reply_cap);
	return full_transact(h, cmd, cmd_len, reply, reply_cap);
}

/* ------------------------------------------------------------------------
 * Pipelining (full duplex): see pipe.c
 * ------------------------------------------------------------------------ */

int link_pipe_put(struct df1 *h, uint8_t *cmd, size_t cmd_len)
{
	int r;

	if (!h || !cmd || cmd_len < FRAME_MIN_DATA || cmd_len > FRAME_MAX_DATA)
		return h ? df1_fail(h, DF1_E_INVAL, -1, "invalid command (%zu bytes)", cmd_len)
		         : DF1_E_INVAL;
	r = link_setup(h);
	if (r < 0)
		return r;
	if (link_pipe_depth(h) <= 1)
		return df1_fail(h, DF1_E_NOTSUP, cmd[0], "no pipeline: one command at a time");
	link_stamp(h, cmd);
	return link_pipe_submit(h, cmd, cmd_len);
}

int link_test(struct df1 *h, int station)
{
	int r;

	if (!h)
		return DF1_E_INVAL;
	r = link_setup(h);
	if (r < 0)
		return r;
	if (h->own_link)
		return h->own_link->test(h);
	switch (h->cfg.duplex) {
	case DF1_HALF_DUPLEX_MASTER:
		if (station < 0 || station > 254)
			return df1_fail(h, DF1_E_INVAL, station, "invalid station %d", station);
		return half_test(h, (uint8_t)station);
	case DF1_HALF_DUPLEX_SLAVE:
		return df1_fail(h, DF1_E_NOTSUP, station, "a half-duplex slave only answers polls");
	case DF1_RADIO_MODEM: {
		/* no link symbols to test with (doc/PROTOCOL.md 2.6): an empty diagnostic
		 * echo (06/00) instead; any reply, even with an error STS, is an answer */
		uint8_t cmd[7] = { 0, 0, 0x06, 0, 0, 0, 0x00 }, rep[FRAME_MAX_DATA];

		if (station < 0 || station > 254)
			return df1_fail(h, DF1_E_INVAL, station, "invalid station %d", station);
		cmd[0] = (uint8_t)station;
		link_stamp(h, cmd);
		r = radio_transact(h, cmd, sizeof cmd, rep, sizeof rep);
		return r < 0 ? r : 0;
	}
	case DF1_FULL_DUPLEX:
	default:
		return full_test(h);
	}
}

int link_serve(struct df1 *h, struct link_responder *resp, link_handler_fn fn, void *ctx,
               int64_t deadline_ms)
{
	int r;

	if (!h || !fn || !resp)
		return DF1_E_INVAL;
	r = link_setup(h);
	if (r < 0)
		return r;
	if (h->own_link)
		return df1_fail(h, DF1_E_NOTSUP, -1, "%s: an %s target is a client: it does not "
		                "serve", h->port_name, h->own_link->scheme);
	/* a half-duplex master serves by polling: its slaves' messages (route.c) */
	if (h->cfg.duplex == DF1_HALF_DUPLEX_MASTER)
		return link_master_serve(h, resp, fn, ctx, deadline_ms);
	h->resp = resp; /* lent for this call: the modes reach it as h->resp */
	if (h->cfg.duplex == DF1_HALF_DUPLEX_SLAVE)
		r = half_serve(h, fn, ctx, deadline_ms);
	else if (h->cfg.duplex == DF1_RADIO_MODEM)
		r = radio_serve(h, fn, ctx, deadline_ms);
	else
		r = full_serve(h, fn, ctx, deadline_ms);
	h->resp = NULL;
	/* an ACK held for a reply that did not follow goes out before we return */
	if (h->tx_hold_len) {
		int f = link_tx_flush(h);

		if (r >= 0 && f < 0)
			r = f;
	}
	return r;
}

