/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server_dispatch.c - the responder: a decoded PCCC command -> its family's
 * handler (server_plc5.c, server_slc.c, server_plc2.c) or the diagnostics,
 * echo and mode changes here, or the `command` callback -> the reply; and the
 * responder's state lent to link_serve(). See server.h for the data-table
 * contract.
 *
 * Status rules (doc/PROTOCOL.md 3.2, 3.3):
 *  - a command this responder does not know, and no `command` callback: STS 10;
 *  - a malformed command (short or extra bytes, zero or odd sizes, counts past
 *    TOTAL_TRANS): STS 10;
 *  - CMD 0F / 06: STS F0 + EXT STS: 02/03 bad PLC-5 address levels, 05 a logical
 *    ASCII address that does not parse, 09 more data than one packet holds,
 *    11 a type/data parameter (or SLC file type code) that is not the file's type,
 *    and whatever the data table reports (06 no such file, 07 past the end ...);
 *  - PLC-2 commands (no EXT STS): STS 10 format, 80 no compatibility file
 *    (N9 / N7, server.h), 50 an address the data table refuses.
 */
#include "server/server_int.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "link/link.h"

/* ------------------------------------------------------------------------
 * Diagnostics, modes, anything else
 * ------------------------------------------------------------------------ */

int server_default_diag(uint8_t *buf, size_t cap)
{
	/* an SLC 5/04 series C release 5 (44h) in Run mode, 16 KB of RAM, no owner */
	static const struct pccc_diag_info slc504 = {
		.type_code = 0x5B, .interface_type = 0x1F, .series_rev = 0x44,
		.bulletin = "5/04", .mode = 0x06, .ram_kb = 0x10, .owner = 0x3F,
	};

	if (!buf)
		return DF1_E_NOSPACE;
	return pccc_enc_diag_reply(buf, cap, &slc504);
}

static int apply_mode(struct srv *s, int mode)
{
	int rc;

	if (s->ops->change_mode) {
		rc = s->ops->change_mode(s->user, s->station, mode);
		return rc ? srv_fail_rc(s, rc) : 0;
	}
	if (mode != 1 && mode != 6 && mode != 7 && mode != 8)
		return srv_fail_ext(s, 0x01);      /* a field has an illegal value */
	return 0;
}

static int srv_other(struct srv *s, const uint8_t *cmd)
{
	struct df1_msg dm;
	int rc;

	if (!s->ops->command)
		return srv_fail_sts(s, 0x10);
	memset(&dm, 0, sizeof dm);
	dm.dst = s->m->dst;
	dm.src = s->m->src;
	dm.cmd = s->m->cmd;
	dm.sts = s->m->sts;
	dm.fnc = s->m->fnc;
	dm.tns = s->m->tns;
	dm.has_fnc = s->m->has_fnc;
	dm.name = pccc_command_name(s->m->cmd, s->m->has_fnc, s->m->fnc);
	dm.size = -1;
	dm.data = s->m->data;
	dm.data_len = s->m->len;
	(void)cmd;
	rc = s->ops->command(s->user, s->station, &dm, s->data, SERVER_WORD_READ_MAX);
	if (rc < 0) {
		int v = -rc;

		s->sts = (uint8_t)(v & 0xFF) ? (uint8_t)(v & 0xFF) : 0x10;
		s->ext = (uint8_t)((v >> 8) & 0xFF);
		s->len = 0;
		return -1;
	}
	s->len = (size_t)rc > SERVER_WORD_READ_MAX ? SERVER_WORD_READ_MAX : (size_t)rc;
	return 0;
}

/* CMD 06: echo and diagnostic status here, the rest to the command callback. */
static void dispatch_diag(struct srv *s, const uint8_t *cmd)
{
	const struct pccc_msg *m = s->m;
	int rc;

	switch (m->fnc) {
	case PCCC_FNC_ECHO:
		if (m->len > PLC_ECHO_MAX) {
			srv_fail_sts(s, 0x10);
			return;
		}
		memcpy(s->data, m->data, m->len);
		s->len = m->len;
		return;
	case PCCC_FNC_DIAG_STATUS:
		if (s->ops->diag_status)
			rc = s->ops->diag_status(s->user, s->station, s->data, SERVER_WORD_READ_MAX);
		else
			rc = server_default_diag(s->data, SERVER_WORD_READ_MAX);
		if (rc < 0) {
			srv_fail_sts(s, (uint8_t)((-rc) & 0xFF));
			return;
		}
		s->len = (size_t)rc > SERVER_WORD_READ_MAX ? SERVER_WORD_READ_MAX : (size_t)rc;
		return;
	default:
		srv_other(s, cmd);
		return;
	}
}

/* 0F/80 change mode and 0F/3A set CPU mode: one byte of data. */
static void dispatch_mode(struct srv *s)
{
	/* 0F/3A bits 1-0: 0 program, 1 remote test, 2 run, 3 no change (M p.113) */
	static const int modes[4] = { 1, 7, 6, 0 };
	const struct pccc_msg *m = s->m;

	if (m->len != 1) {
		srv_fail_sts(s, 0x10);
		return;
	}
	if (m->fnc == PCCC_FNC_CHANGE_MODE)
		apply_mode(s, m->data[0]);
	else if (modes[m->data[0] & 3])
		apply_mode(s, modes[m->data[0] & 3]);
}

/* CMD 0F: the SLC and PLC-5 families' commands, the mode changes, the rest
 * to the command callback. */
static void dispatch_typed(struct srv *s, const uint8_t *cmd)
{
	const struct pccc_msg *m = s->m;

	switch (m->fnc) {
	case PCCC_FNC_SLC_READ2: case PCCC_FNC_SLC_READ3:
	case PCCC_FNC_SLC_WRITE2: case PCCC_FNC_SLC_WRITE3: case PCCC_FNC_SLC_MASKED:
		srv_slc(s, m->fnc);
		return;
	case PCCC_FNC_TYPED_READ:
		srv_plc5_typed_read(s);
		return;
	case PCCC_FNC_TYPED_WRITE:
		srv_plc5_typed_write(s);
		return;
	case PCCC_FNC_WORD_READ:
		if (s->h->cfg.plc == DF1_PLC_PLC3)
			srv_plc3_word_read(s);
		else
			srv_plc5_word_read(s);
		return;
	case PCCC_FNC_WORD_WRITE:
		if (s->h->cfg.plc == DF1_PLC_PLC3)
			srv_plc3_word_write(s);
		else
			srv_plc5_word_write(s);
		return;
	case PCCC_FNC_RMW:
		srv_plc5_word_masks(s, true);
		return;
	case PCCC_FNC_BIT_WRITE:
		if (s->h->cfg.plc == DF1_PLC_PLC3)
			srv_plc3_bit_write(s);
		else
			srv_plc5_word_masks(s, false);
		return;
	case PCCC_FNC_CHANGE_MODE: case PCCC_FNC_SET_CPU_MODE:
		dispatch_mode(s);
		return;
	default:
		srv_other(s, cmd);
		return;
	}
}

static void dispatch(struct srv *s, const uint8_t *cmd)
{
	switch (s->m->cmd) {
	case PCCC_CMD_UNPROT_READ: case PCCC_CMD_UNPROT_WRITE: case PCCC_CMD_PROT_WRITE:
	case PCCC_CMD_UNPROT_BIT_WRITE: case PCCC_CMD_PROT_BIT_WRITE:
		srv_plc2(s);
		return;
	case PCCC_CMD_DIAG:
		dispatch_diag(s, cmd);
		return;
	case PCCC_CMD_TYPED:
		dispatch_typed(s, cmd);
		return;
	default:
		srv_other(s, cmd);
		return;
	}
}

/* The responder's state: the server's, lent to link_serve() (below). */
struct server_state {
	struct link_responder resp;  /* reply slots, faults, stations served */
	struct server_ctx peer;      /* df1_set_responder: a master answering its peer */
	int src;                     /* df1_server_source(): SRC of the command being answered + 1, 0 none */
};

int server_handle(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap)
{
	static const struct df1_server_ops no_ops;
	struct server_ctx *c = ctx;
	struct pccc_msg m;
	struct srv *s;
	struct srv stack;
	int rc;

	if (!cmd || !reply)
		return DF1_E_INVAL;
	if (n < PCCC_HDR_LEN)
		return 0;                       /* nothing to answer to */
	rc = pccc_decode(cmd, n, &m);
	if (rc < 0) {
		/* a 06 / 0F command without its FNC: answer STS 10 */
		memset(&m, 0, sizeof m);
		m.dst = cmd[0];
		m.src = cmd[1];
		m.cmd = cmd[2];
		m.tns = le16(cmd + 4);
		return pccc_encode_reply(reply, cap, &m, 0x10, 0, NULL, 0);
	}
	if (m.is_reply)
		return 0;                       /* a reply is not ours to answer */
	s = &stack;
	memset(s, 0, offsetof(struct srv, data));
	s->h = h;
	s->ops = c && c->ops ? c->ops : &no_ops;
	s->user = c ? c->user : NULL;
	s->station = m.dst;
	s->m = &m;
	if (h && h->srv)
		h->srv->src = m.src + 1;        /* df1_server_source() in the callbacks */
	dispatch(s, cmd);
	if (h && h->srv)
		h->srv->src = 0;
	if (s->sts == 0xF0 && !pccc_cmd_has_ext_sts(m.cmd))
		s->sts = 0x10;
	rc = pccc_encode_reply(reply, cap, &m, s->sts, s->ext, s->sts ? NULL : s->data, s->sts ? 0 : s->len);
	if (rc == DF1_E_NOSPACE && s->sts == 0)
		rc = pccc_encode_reply(reply, cap, &m, 0xF0, 0x09, NULL, 0);
	return rc;
}

/* ------------------------------------------------------------------------
 * The responder's state: the server's, lent to link_serve()
 * ------------------------------------------------------------------------ */

static void server_free(struct df1 *h)
{
	free(h->srv);
	h->srv = NULL;
}

struct link_responder *server_responder(struct df1 *h)
{
	if (!h->srv) {
		h->srv = calloc(1, sizeof *h->srv);
		if (!h->srv)
			return NULL;
		h->srv_free = server_free;
	}
	return &h->srv->resp;
}

/* A full-duplex master answers its peer with ops (lib/link/peer.c); the reply
 * slots and faults are df1_serve's, so both answer alike on one handle. */
DF1_API int df1_set_responder(df1_t *h, const struct df1_server_ops *ops, void *user)
{
	struct link_responder *resp;

	if (!h)
		return DF1_E_INVAL;
	if (!ops) {
		h->peer_fn = NULL;
		h->peer_ctx = NULL;
		return 0; /* commands from the peer get STS 10h again */
	}
	resp = server_responder(h);
	if (!resp)
		return df1_fail(h, DF1_E_NOMEM, -1, "df1_set_responder: out of memory");
	h->srv->peer.ops = ops;
	h->srv->peer.user = user;
	h->peer_resp = resp;
	h->peer_ctx = &h->srv->peer;
	h->peer_fn = server_handle;
	return 0;
}

DF1_API int df1_server_source(const df1_t *h)
{
	return h && h->srv ? h->srv->src - 1 : -1;
}
