/* SPDX-License-Identifier: MPL-2.0 */
/*
 * telnet.c - the Telnet framing under RFC 2217 (lib/proto/telnet.h): a byte
 * at a time decoder of data, option commands and subnegotiations, and the
 * encoders. The byte values and the command layout are RFC 854's (IAC 255,
 * SB 250 ... IAC SE 240, WILL/WONT/DO/DONT 251..254), BINARY is RFC 856's
 * option 0 and COM-PORT-OPTION RFC 2217's option 44 (doc/PROTOCOL.md 9).
 */
#include "proto/telnet.h"

#include <string.h>

enum { ST_DATA, ST_IAC, ST_OPT, ST_SB_OPT, ST_SB, ST_SB_IAC };

void telnet_decoder_init(struct telnet_decoder *d)
{
	memset(d, 0, sizeof *d);
}

static enum telnet_ev telnet_sb_byte(struct telnet_decoder *d, uint8_t b)
{
	if (d->sb_len < TELNET_SB_MAX)
		d->sb[d->sb_len++] = b;
	else
		d->sb_long = true;
	return TELNET_EV_NONE;
}

enum telnet_ev telnet_feed(struct telnet_decoder *d, uint8_t b, struct telnet_event *ev)
{
	switch (d->state) {
	case ST_DATA:
		if (b == TELNET_IAC) {
			d->state = ST_IAC;
			return TELNET_EV_NONE;
		}
		ev->byte = b;
		return TELNET_EV_DATA;
	case ST_IAC:
		if (b == TELNET_IAC) {          /* IAC IAC: one data byte 255 */
			d->state = ST_DATA;
			ev->byte = b;
			return TELNET_EV_DATA;
		}
		if (b >= TELNET_WILL) {
			d->cmd_pending = b;
			d->state = ST_OPT;
			return TELNET_EV_NONE;
		}
		if (b == TELNET_SB) {
			d->state = ST_SB_OPT;
			return TELNET_EV_NONE;
		}
		d->state = ST_DATA;             /* NOP, GA, a stray SE ...: two bytes */
		ev->cmd = b;
		return TELNET_EV_OTHER;
	case ST_OPT:
		d->state = ST_DATA;
		ev->cmd = d->cmd_pending;
		ev->opt = b;
		return TELNET_EV_OPTION;
	case ST_SB_OPT:
		d->opt = b;
		d->sb_len = 0;
		d->sb_long = false;
		d->state = ST_SB;
		return TELNET_EV_NONE;
	case ST_SB:
		if (b == TELNET_IAC) {
			d->state = ST_SB_IAC;
			return TELNET_EV_NONE;
		}
		return telnet_sb_byte(d, b);
	default: /* ST_SB_IAC */
		if (b == TELNET_IAC) {          /* a doubled 255 inside the value */
			d->state = ST_SB;
			return telnet_sb_byte(d, b);
		}
		d->state = ST_DATA;
		if (b != TELNET_SE)             /* IAC x inside SB: the SB is cut short */
			return TELNET_EV_NONE;
		ev->opt = d->opt;
		ev->sb = d->sb;
		ev->sb_len = d->sb_len;
		return TELNET_EV_SB;
	}
}

size_t telnet_escape(const uint8_t *in, size_t n, uint8_t *out, size_t cap, size_t *used)
{
	size_t i, o = 0;

	for (i = 0; i < n; i++) {
		size_t need = in[i] == TELNET_IAC ? 2 : 1;

		if (o + need > cap)
			break;
		out[o++] = in[i];
		if (need == 2)
			out[o++] = TELNET_IAC;
	}
	*used = i;
	return o;
}

size_t telnet_option(uint8_t cmd, uint8_t opt, uint8_t *out)
{
	out[0] = TELNET_IAC;
	out[1] = cmd;
	out[2] = opt;
	return 3;
}

size_t telnet_cpc(uint8_t code, const uint8_t *val, size_t n, uint8_t *out)
{
	size_t o = 0;

	out[o++] = TELNET_IAC;
	out[o++] = TELNET_SB;
	out[o++] = TELNET_OPT_COMPORT;
	out[o++] = code;
	if (code == TELNET_IAC)         /* no such code; doubled all the same, as any 255 in SB */
		out[o++] = TELNET_IAC;
	for (size_t i = 0; i < n; i++) {
		out[o++] = val[i];
		if (val[i] == TELNET_IAC)
			out[o++] = TELNET_IAC;
	}
	out[o++] = TELNET_IAC;
	out[o++] = TELNET_SE;
	return o;
}

void telnet_put_baud(uint32_t baud, uint8_t val[4])
{
	val[0] = (uint8_t)(baud >> 24);
	val[1] = (uint8_t)(baud >> 16);
	val[2] = (uint8_t)(baud >> 8);
	val[3] = (uint8_t)baud;
}

uint32_t telnet_get_baud(const uint8_t val[4])
{
	return (uint32_t)val[0] << 24 | (uint32_t)val[1] << 16 | (uint32_t)val[2] << 8 | val[3];
}
