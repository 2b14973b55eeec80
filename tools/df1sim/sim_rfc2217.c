/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_rfc2217.c - df1sim --listen rfc2217://ADDR:PORT: the device server's
 * side of RFC 2217 in the relay of tools/df1sim/sim_line.c. It agrees to
 * COM-PORT-OPTION and BINARY when the client offers them and refuses other
 * options once; it takes the client's SET-BAUDRATE, SET-DATASIZE,
 * SET-PARITY and SET-STOPSIZE as the master's settings (so the line model
 * garbles when they differ from --line-settings) and answers each command as
 * RFC 2217 says (the command + 100, the value now in force; a value of 0 asks
 * for it). MARK and SPACE parity and 1.5 stop bits are refused: it answers
 * the value in force. A tool uses only the public API, so the library's codec
 * (lib/proto/telnet.c) is not reachable here: the few codes this side needs
 * are written from RFC 854 and RFC 2217 again (doc/PROTOCOL.md 9).
 */
#include "df1sim/sim_line.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum {
	IAC = 255, DONT = 254, DO = 253, WONT = 252, WILL = 251, SB = 250, SE = 240,
	OPT_BINARY = 0, OPT_COMPORT = 44,
};
enum { ST_DATA, ST_IAC, ST_OPT, ST_SB_OPT, ST_SB, ST_SB_IAC };

struct sim_rfc {
	int state;
	uint8_t cmd, opt;
	uint8_t sb[16];
	size_t sb_len;
	uint8_t answered[2][32];       /* options answered once: [0] as WILL, [1] as DO */
};

void *sim_rfc2217_new(void)
{
	return calloc(1, sizeof(struct sim_rfc));
}

static void sim_rfc_send(struct sim_relay *r, const uint8_t *b, size_t n)
{
	(void)!write(r->wire, b, n);
}

/* The client's WILL / DO: BINARY and COM-PORT-OPTION agreed, the rest refused. */
static void sim_rfc_option(struct sim_relay *r, struct sim_rfc *s, uint8_t cmd, uint8_t opt)
{
	int k = cmd == WILL || cmd == WONT ? 0 : 1;
	bool ok = opt == OPT_BINARY || (opt == OPT_COMPORT && k == 0);
	uint8_t out[3] = { IAC, 0, opt };

	if (cmd == WONT || cmd == DONT || (s->answered[k][opt / 8] & (1u << (opt % 8))))
		return;
	s->answered[k][opt / 8] |= (uint8_t)(1u << (opt % 8));
	out[1] = k == 0 ? (ok ? DO : DONT) : (ok ? WILL : WONT);
	sim_rfc_send(r, out, 3);
}

/* Answer a COM-PORT-OPTION command with the value in force. */
static void sim_rfc_answer(struct sim_relay *r, uint8_t code, const uint8_t *val, size_t n)
{
	uint8_t out[16];
	size_t o = 0;

	out[o++] = IAC;
	out[o++] = SB;
	out[o++] = OPT_COMPORT;
	out[o++] = (uint8_t)(code + 100);
	for (size_t i = 0; i < n; i++) {
		out[o++] = val[i];
		if (val[i] == IAC)
			out[o++] = IAC;
	}
	out[o++] = IAC;
	out[o++] = SE;
	sim_rfc_send(r, out, o);
}

static void sim_rfc_command(struct sim_relay *r, const uint8_t *sb, size_t n)
{
	struct sim_uart *m = &r->master, before = r->master;
	uint8_t code = sb[0], v = n > 1 ? sb[1] : 0, val[4];
	char a[32], b[32];

	switch (code) {
	case 1:                         /* SET-BAUDRATE */
		if (n >= 5) {
			uint32_t baud = (uint32_t)sb[1] << 24 | (uint32_t)sb[2] << 16 | (uint32_t)sb[3] << 8 | sb[4];

			if (baud)
				m->baud = (int)baud;
		}
		val[0] = (uint8_t)((uint32_t)m->baud >> 24);
		val[1] = (uint8_t)((uint32_t)m->baud >> 16);
		val[2] = (uint8_t)((uint32_t)m->baud >> 8);
		val[3] = (uint8_t)m->baud;
		sim_rfc_answer(r, code, val, 4);
		break;
	case 2:                         /* SET-DATASIZE */
		if (v >= 5 && v <= 8)
			m->data_bits = v;
		val[0] = (uint8_t)m->data_bits;
		sim_rfc_answer(r, code, val, 1);
		break;
	case 3:                         /* SET-PARITY: 1 none, 2 odd, 3 even */
		if (v >= 1 && v <= 3)
			m->parity = v == 1 ? 'N' : v == 2 ? 'O' : 'E';
		val[0] = m->parity == 'N' ? 1 : m->parity == 'O' ? 2 : 3;
		sim_rfc_answer(r, code, val, 1);
		break;
	case 4:                         /* SET-STOPSIZE: 1, 2 */
		if (v == 1 || v == 2)
			m->stop_bits = v;
		val[0] = (uint8_t)m->stop_bits;
		sim_rfc_answer(r, code, val, 1);
		break;
	case 0:                         /* SIGNATURE */
		sim_rfc_answer(r, code, (const uint8_t *)"df1sim", 6);
		break;
	default:                        /* SET-CONTROL, PURGE-DATA, masks ...: as asked */
		sim_rfc_answer(r, code, sb + 1, n > 5 ? 4 : n - 1);
		break;
	}
	/* said here, not through sim_line.c: the two files would call each other */
	if (r->verbose && memcmp(&before, m, sizeof before) != 0 && m->baud) {
		snprintf(a, sizeof a, "%d %d%c%d", m->baud, m->data_bits, m->parity, m->stop_bits);
		snprintf(b, sizeof b, "%d %d%c%d", r->line.baud, r->line.data_bits, r->line.parity,
		         r->line.stop_bits);
		fprintf(stderr, "df1sim: rfc2217: the client set %s (the line: %s)\n", a,
		        r->line.baud ? b : "any");
	}
}

size_t sim_rfc2217_input(struct sim_relay *r, const uint8_t *in, size_t n, uint8_t *out, size_t cap)
{
	struct sim_rfc *s = r->rfc;
	size_t o = 0;

	for (size_t i = 0; i < n; i++) {
		uint8_t b = in[i];

		switch (s->state) {
		case ST_DATA:
			if (b == IAC)
				s->state = ST_IAC;
			else if (o < cap)
				out[o++] = b;
			break;
		case ST_IAC:
			s->state = ST_DATA;
			if (b == IAC && o < cap)
				out[o++] = b;
			else if (b >= WILL)
				s->cmd = b, s->state = ST_OPT;
			else if (b == SB)
				s->state = ST_SB_OPT;
			break;
		case ST_OPT:
			s->state = ST_DATA;
			sim_rfc_option(r, s, s->cmd, b);
			break;
		case ST_SB_OPT:
			s->opt = b;
			s->sb_len = 0;
			s->state = ST_SB;
			break;
		case ST_SB:
			if (b == IAC)
				s->state = ST_SB_IAC;
			else if (s->sb_len < sizeof s->sb)
				s->sb[s->sb_len++] = b;
			break;
		default:                /* ST_SB_IAC */
			if (b == IAC) {
				s->state = ST_SB;
				if (s->sb_len < sizeof s->sb)
					s->sb[s->sb_len++] = b;
				break;
			}
			s->state = ST_DATA;
			if (b == SE && s->opt == OPT_COMPORT && s->sb_len > 0)
				sim_rfc_command(r, s->sb, s->sb_len);
			break;
		}
	}
	return o;
}

size_t sim_rfc2217_output(const uint8_t *in, size_t n, uint8_t *out, size_t cap, size_t *used)
{
	size_t i, o = 0;

	for (i = 0; i < n; i++) {
		size_t need = in[i] == IAC ? 2 : 1;

		if (o + need > cap)
			break;
		out[o++] = in[i];
		if (need == 2)
			out[o++] = IAC;
	}
	*used = i;
	return o;
}
