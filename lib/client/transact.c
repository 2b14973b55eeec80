/* SPDX-License-Identifier: MPL-2.0 */
/*
 * transact.c - the client's common ground: file type classes, address text,
 * error recording (client_fail: the detail's address field), one transaction
 * (command out, reply checked), and where element values go and come from.
 */
#include "client/client_int.h"

bool client_is_word_type(enum df1_file_type t)
{
	return t == DF1_FT_O || t == DF1_FT_I || t == DF1_FT_S || t == DF1_FT_B ||
	       t == DF1_FT_N || t == DF1_FT_A || t == DF1_FT_D;
}

bool client_is_tcr(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R;
}

void client_atext(enum df1_plc plc, const struct df1_addr *a, char *buf, size_t cap)
{
	if (df1_addr_format_plc(plc, a, buf, cap) < 0)
		snprintf(buf, cap, "%s%d:%d", df1_file_type_name(a->type), a->file, a->element);
}

/* The error detail names the address the error concerns. */
static void client_set_address(struct df1 *h, const char *what)
{
	snprintf(h->err.address, sizeof h->err.address, "%s", what ? what : "");
}

/* df1_fail() for address what: the message, and what in the detail's address. */
int client_fail(struct df1 *h, int code, int station, const char *what, const char *fmt, ...)
{
	char buf[sizeof h->err.message];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	df1_fail(h, code, station, "%s", buf);
	client_set_address(h, what);
	return code;
}

/* The link / df1_fail_remote recorded the failure: add the address to it. */
static int client_fail_at(struct df1 *h, int rc, int station, const char *what)
{
	if (h->err.code != rc)
		return client_fail(h, rc, station, what, "%s", df1_strerror(rc));
	client_set_address(h, what);
	if (h->err.station < 0)
		h->err.station = station;
	return rc;
}

/* A reply the link accepted whose content is wrong: DF1_E_BAD_REPLY, counted as an
 * invalid message (2550, doc/REQUIREMENTS.md 004: "bad data, incorrect addressing"). */
int client_bad_reply(struct df1 *h, int station, const char *what, const char *fmt, ...)
{
	char buf[sizeof h->err.message];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	df1_count(h, DF1_ID_CNT_INVALID_MSGS_RCVD);
	return client_fail(h, DF1_E_BAD_REPLY, station, what, "%s", buf);
}

int client_check(struct df1 *h, int station)
{
	if (!h)
		return DF1_E_INVAL;
	/* a half-duplex slave's MSG may be a broadcast (lib/link/half_msg.c), and so may
	 * a radio modem's command (lib/link/radio.c) */
	if (station == 255 && (h->cfg.duplex == DF1_HALF_DUPLEX_SLAVE ||
	                       h->cfg.duplex == DF1_RADIO_MODEM))
		return 0;
	if (station < 0 || station > 254)
		return df1_fail(h, DF1_E_INVAL, station, "station %d out of range 0-254", station);
	return 0;
}

/* A copy of a with other element / sub and no bit; a "$" text is rebuilt to match. */
void client_derive(const struct df1_addr *a, int element, int sub, struct df1_addr *out)
{
	char buf[ATEXT_MAX];
	bool same = element == a->element && sub == a->sub && a->bit == DF1_ADDR_NONE;

	*out = *a;
	out->element = element;
	out->sub = sub;
	out->bit = DF1_ADDR_NONE;
	if (out->ascii[0] && !same) {
		out->ascii[0] = '\0';
		if (df1_addr_format(out, buf, sizeof buf) > 0 && strlen(buf) < sizeof out->ascii)
			memcpy(out->ascii, buf, strlen(buf) + 1);
	}
}

/* Address of element i of a span. */
void span_at(const struct span *s, size_t i, struct df1_addr *out)
{
	if (s->by_sub)
		client_derive(&s->a, s->a.element, s->a.sub + (int)i, out);
	else
		client_derive(&s->a, s->a.element + (int)i, s->a.sub, out);
}

/* Data bytes per packet of a span's PLC type, for the SLC and PLC-2 commands. */
size_t client_limit(const struct df1 *h, const struct span *s, bool write)
{
	return plc_per_packet(s->plc, write, s->a.type, s->esize, 0, h->cfg.max_packet) * s->esize;
}

/* ------------------------------------------------------------------------
 * One transaction
 * ------------------------------------------------------------------------ */

/* The outcome of command cmd as link_transact (or link_pipe_wait) returned
 * it: rc the reply's length (its bytes in reply) or DF1_E_*. Checks the reply
 * (CMD|40h, STS); data/dlen point into reply. */
int client_reply(struct df1 *h, int station, const char *what, const uint8_t *cmd, int rc,
                 const uint8_t *reply, const uint8_t **data, size_t *dlen)
{
	struct pccc_msg m;

	if (rc < 0)
		return client_fail_at(h, rc, station, what);
	rc = pccc_decode(reply, (size_t)rc, &m);
	if (rc < 0)
		return client_bad_reply(h, station, what, "malformed reply");
	if (m.cmd != (cmd[2] | PCCC_REPLY_BIT))
		return client_fail(h, DF1_E_BAD_FUNCTION, station, what, "reply CMD %02X to command %02X", m.cmd, cmd[2]);
	if (m.sts != 0) {
		rc = df1_fail_remote(h, station, m.sts, m.ext_sts, m.has_ext);
		return client_fail_at(h, rc < 0 ? rc : DF1_E_REMOTE, station, what);
	}
	*data = m.data;
	*dlen = m.len;
	return 0;
}

/* Send an app message, check the reply (client_reply). */
int client_transact(struct df1 *h, int station, const char *what, uint8_t *cmd, size_t clen,
                    uint8_t *reply, size_t rcap, const uint8_t **data, size_t *dlen)
{
	int rc;

	cmd[0] = (uint8_t)station;
	cmd[1] = (uint8_t)h->cfg.station;
	df1_clear_error(h);     /* so client_fail_at can tell whether the link recorded one */
	rc = link_transact(h, cmd, clen, reply, rcap);
	return client_reply(h, station, what, cmd, rc, reply, data, dlen);
}

/* client_transact for an operation that has no address (echo, diagnostic
 * status, change mode): the message starts with the operation's name
 * ("echo: ...") and the detail's address stays empty. */
int client_op_transact(struct df1 *h, int station, const char *op, uint8_t *cmd, size_t clen,
                       uint8_t *reply, size_t rcap, const uint8_t **data, size_t *dlen)
{
	int rc = client_transact(h, station, op, cmd, clen, reply, rcap, data, dlen);
	char *msg = h->err.message;
	size_t cap = sizeof h->err.message, ol = strlen(op), ml;

	if (rc >= 0 || strcmp(h->err.address, op) != 0)
		return rc;
	h->err.address[0] = '\0';
	ml = strnlen(msg, cap - 1);
	if (ol + 2 < cap) {
		if (ml > cap - 1 - ol - 2)
			ml = cap - 1 - ol - 2;
		memmove(msg + ol + 2, msg, ml);
		memcpy(msg, op, ol);
		msg[ol] = ':';
		msg[ol + 1] = ' ';
		msg[ol + 2 + ml] = '\0';
	}
	return rc;
}

/* ------------------------------------------------------------------------
 * Element sinks and sources
 * ------------------------------------------------------------------------ */

/* Element i (of the span) arrived: esize wire bytes at p. */
int io_put(struct df1 *h, int station, const char *what, struct io *io, size_t i,
           const uint8_t *p, size_t esize)
{
	int rc = 0;

	i += io->base;
	if (io->word >= 0) {
		p += 2 * (size_t)io->word;
		esize = 2;
	}
	switch (io->kind) {
	case IO_RAW:
		memcpy((uint8_t *)io->out + i * esize, p, esize);
		break;
	case IO_VALUE:
		rc = value_decode_element(io->t, p, esize, (struct df1_value *)io->out + i, io->fo);
		break;
	case IO_I16:
		((int16_t *)io->out)[i] = (int16_t)le16(p);
		break;
	case IO_I32:
		((int32_t *)io->out)[i] = (int32_t)le32(p);
		break;
	case IO_F32:
		((float *)io->out)[i] = value_get_float(p, io->fo);
		break;
	case IO_TCR: {
		struct df1_tcr *t = (struct df1_tcr *)io->out + i;

		t->ctl = le16(p);
		t->pre = (int16_t)le16(p + 2);
		t->acc = (int16_t)le16(p + 4);
		break;
	}
	case IO_STRING:
		rc = value_get_string(p, io->out, io->cap);
		if (rc >= 0)
			io->len = rc;
		break;
	}
	if (rc < 0) {
		if (rc == DF1_E_NOSPACE)
			return client_fail(h, rc, station, what, "string does not fit the buffer");
		return client_bad_reply(h, station, what, "element %zu cannot be decoded (%s)", i, df1_strerror(rc));
	}
	return 0;
}

/* Fill esize wire bytes at p with element i of the span. */
int io_get(struct io *io, size_t i, uint8_t *p, size_t esize)
{
	i += io->base;
	switch (io->kind) {
	case IO_RAW:
		memcpy(p, (const uint8_t *)io->in + i * esize, esize);
		return 0;
	case IO_VALUE: {
		int rc = value_encode_element(io->t, (const struct df1_value *)io->in + i, p, esize, io->fo);

		return rc < 0 ? rc : 0;
	}
	case IO_I16:
		put_le16(p, (uint16_t)((const int16_t *)io->in)[i]);
		return 0;
	case IO_I32:
		put_le32(p, (uint32_t)((const int32_t *)io->in)[i]);
		return 0;
	case IO_F32:
		value_put_float(p, ((const float *)io->in)[i], io->fo);
		return 0;
	case IO_TCR: {
		const struct df1_tcr *t = (const struct df1_tcr *)io->in + i;

		put_le16(p, t->ctl);
		put_le16(p + 2, (uint16_t)t->pre);
		put_le16(p + 4, (uint16_t)t->acc);
		return 0;
	}
	case IO_STRING: {
		int rc = value_put_string(p, io->in);

		return rc < 0 ? rc : 0;
	}
	}
	return DF1_E_INVAL;
}

/* Fill out with elements first .. first+k-1 of the span for one write packet;
 * a value that does not encode fails naming its index. */
int io_gather(struct df1 *h, int station, const char *what, struct io *io, size_t first,
              size_t k, uint8_t *out, size_t esize)
{
	for (size_t i = 0; i < k; i++) {
		int rc = io_get(io, first + i, out + i * esize, esize);

		if (rc < 0)
			return client_fail(h, rc, station, what, "value %zu: %s", io->base + first + i,
			                df1_strerror(rc));
	}
	return 0;
}
