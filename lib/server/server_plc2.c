/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server_plc2.c - the responder's PLC-2 commands (doc/PROTOCOL.md 4.7):
 * 01 unprotected read, 08 unprotected write, 00 protected write, 05 and 02
 * bit writes, on the compatibility file (N9 / N7, server.h). They carry no
 * EXT STS: STS 10 format, 80 no compatibility file, 50 a refused address.
 *
 * Where the spec flags a doubt (doc/PROTOCOL.md 8): addresses are bytes, or
 * words with DF1_OPT_PLC2_WORD_ADDR (doc/PROTOCOL.md 4.7; 05/02 bit writes
 * then STS 10: their blocks address bytes).
 */
#include "server/server_int.h"

/* The compatibility file of the PLC served (server.h). */
static int plc2_file(const struct srv *s)
{
	if (s->h && s->h->cfg.plc == DF1_PLC_MICROLOGIX)
		return SERVER_PLC2_FILE_MICROLOGIX;
	if (s->h && s->h->cfg.plc == DF1_PLC_PLC5)
		return SERVER_PLC2_FILE_PLC5;
	return SERVER_PLC2_FILE_SLC;
}

/* Is the command's body well formed? `words`: DF1_OPT_PLC2_WORD_ADDR. */
static bool plc2_format_ok(const struct srv *s, bool words)
{
	const uint8_t *d = s->m->data;
	size_t n = s->m->len;
	unsigned odd = words ? 0u : 1u;

	switch (s->m->cmd) {
	case PCCC_CMD_UNPROT_READ:
		return !(n != 3 || (d[0] & odd) || d[2] == 0 || (d[2] & 1) || d[2] > PLC_PLC2_MAX);
	case PCCC_CMD_UNPROT_WRITE: case PCCC_CMD_PROT_WRITE:
		return !(n < 3 || (d[0] & odd) || n - 2 > PLC_PLC2_MAX);
	default:        /* 05, 02: blocks of ADDR(2) SET(1) RESET(1), up to 60; bytes only */
		return !(words || n == 0 || n % 4 || n / 4 > 60);
	}
}

/* 05, 02: set then reset the bits of each block's byte. */
static int plc2_bit_writes(struct srv *s, int file)
{
	const uint8_t *d = s->m->data;
	size_t n = s->m->len, addr;
	int rc;

	for (size_t i = 0; i < n; i += 4) {
		uint8_t b[2] = { 0, 0 }, mb[2] = { 0, 0 };
		unsigned idx;

		addr = le16(d + i);
		idx = (unsigned)(addr & 1u);
		mb[idx] = (uint8_t)(d[i + 2] | d[i + 3]);
		b[idx] = (uint8_t)(d[i + 2] & ~d[i + 3]);
		rc = srv_tbl_write(s, DF1_FT_N, file, addr & ~(size_t)1, b, mb, 2);
		if (rc)
			return srv_fail_plc2(s, rc);
	}
	return 0;
}

int srv_plc2(struct srv *s)
{
	const uint8_t *d = s->m->data;
	size_t n = s->m->len;
	int file = plc2_file(s), rc;
	/* DF1_OPT_PLC2_WORD_ADDR: the address is a word offset (an SLC common
	 * interface file with S:2/8 = 0, doc/PROTOCOL.md 4.7); else a byte address, even */
	bool words = s->h && s->h->cfg.plc2_word_addr;
	size_t addr;

	if (!plc2_format_ok(s, words))
		return srv_fail_sts(s, 0x10);
	if (srv_tbl_probe(s, DF1_FT_N, file))
		return srv_fail_sts(s, 0x80);      /* compatibility mode file missing */
	switch (s->m->cmd) {
	case PCCC_CMD_UNPROT_READ:
		addr = (size_t)le16(d) * (words ? 2u : 1u);
		rc = srv_tbl_read(s, DF1_FT_N, file, addr, s->data, d[2]);
		if (rc)
			return srv_fail_plc2(s, rc);
		s->len = d[2];
		return 0;
	case PCCC_CMD_UNPROT_WRITE: case PCCC_CMD_PROT_WRITE:
		addr = (size_t)le16(d) * (words ? 2u : 1u);
		rc = srv_tbl_write(s, DF1_FT_N, file, addr, d + 2, NULL, n - 2);
		return rc ? srv_fail_plc2(s, rc) : 0;
	default:
		return plc2_bit_writes(s, file);
	}
}
