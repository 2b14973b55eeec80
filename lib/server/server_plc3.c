/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server_plc3.c - the responder's PLC-3 commands (doc/PROTOCOL.md 4.2a), when the
 * handle serves as a PLC-3 (df1_set_plc DF1_PLC_PLC3): word range read 0F/01
 * { PKT_OFFSET TOTAL_TRANS ADDR SIZE }, word range write 0F/00 { PKT_OFFSET
 * TOTAL_TRANS ADDR DATA }, bit write 0F/02 { ADDR SET RESET }, ADDR in the
 * PLC-3 logical binary form. The data table sees the levels as lib/server/server.h's
 * contract: type from the section, the file, and the byte offset of the
 * structure and word (pccc_plc3_to_addr), F and H values low word first.
 *
 * Refusals: a malformed or short body STS 10; an address of too few levels
 * (no word level) EXT STS 02, of a level the data table does not have (another
 * area, below the word) or out of its section's range EXT STS 03 (the PLC-5
 * responder's codes, doc/PROTOCOL.md 3.3); the data table's own EXT STS (06 no
 * such file, 11 other type, 07 beyond the file) as it gives them.
 */
#include "server/server_int.h"

#include <string.h>

static int plc3_fail(struct srv *s, int rc)
{
	if (rc == DF1_E_ADDR_SYNTAX)
		return srv_fail_ext(s, 0x02);
	if (rc == DF1_E_ADDR_RANGE)
		return srv_fail_ext(s, 0x03);
	return srv_fail_sts(s, 0x10);
}

/* ADDR at in[0..n): the data table's address; returns bytes consumed or -1 (failed). */
static int plc3_addr_at(struct srv *s, const uint8_t *in, size_t n, struct df1_addr *a)
{
	struct pccc_plc3_addr l;
	int k = pccc_dec_plc3_addr(in, n, &l), rc;

	if (k < 0)
		return plc3_fail(s, k);
	rc = pccc_plc3_to_addr(&l, a);
	if (rc < 0)
		return plc3_fail(s, rc);
	return k;
}

/* PKT_OFFSET TOTAL_TRANS ADDR: the address and the byte offset of the packet. */
static int plc3_head(struct srv *s, struct df1_addr *a, size_t *off, size_t *pos, unsigned *total)
{
	const uint8_t *d = s->m->data;
	size_t n = s->m->len;
	unsigned offset;
	int k;

	if (n < 5)
		return srv_fail_sts(s, 0x10);
	offset = le16(d);
	*total = le16(d + 2);
	k = plc3_addr_at(s, d + 4, n - 4, a);
	if (k < 0)
		return -1;
	*pos = 4 + (size_t)k;
	*off = srv_addr_off(a) + (size_t)offset * 2;
	return (int)offset;
}

int srv_plc3_word_read(struct srv *s)
{
	struct df1_addr a;
	size_t off, pos, size;
	unsigned total;
	int offset = plc3_head(s, &a, &off, &pos, &total), rc;

	if (offset < 0)
		return -1;
	if (s->m->len != pos + 1)
		return srv_fail_sts(s, 0x10);
	size = s->m->data[pos];
	if (size == 0 || (size & 1) || (unsigned)offset + size / 2 > total)
		return srv_fail_sts(s, 0x10);
	if (size > PLC_PLC3_READ_MAX)
		return srv_fail_ext(s, 0x09);
	rc = srv_tbl_read(s, a.type, a.file, off, s->data, size);
	if (rc)
		return srv_fail_rc(s, rc);
	s->len = size;
	return 0;
}

int srv_plc3_word_write(struct srv *s)
{
	struct df1_addr a;
	size_t off, pos, n;
	unsigned total;
	int offset = plc3_head(s, &a, &off, &pos, &total), rc;

	if (offset < 0)
		return -1;
	n = s->m->len - pos;
	if (n == 0 || (n & 1) || (unsigned)offset + n / 2 > total)
		return srv_fail_sts(s, 0x10);
	rc = srv_tbl_write(s, a.type, a.file, off, s->m->data + pos, NULL, n);
	if (rc)
		return srv_fail_rc(s, rc);
	return 0;
}

/* One word: the SET bits become 1, then the RESET bits 0 (1775-KA app. A). */
int srv_plc3_bit_write(struct srv *s)
{
	const uint8_t *d = s->m->data;
	size_t n = s->m->len;
	uint16_t set, reset, mask, val;
	uint8_t b[2], mb[2];
	struct df1_addr a;
	int k, rc;

	if (n == 0)
		return srv_fail_sts(s, 0x10);
	k = plc3_addr_at(s, d, n, &a);
	if (k < 0)
		return -1;
	if (n != (size_t)k + 4)
		return srv_fail_sts(s, 0x10);
	set = le16(d + k);
	reset = le16(d + k + 2);
	mask = (uint16_t)(set | reset);
	val = (uint16_t)(set & ~reset);
	put_le16(b, val);
	put_le16(mb, mask);
	rc = srv_tbl_write(s, a.type, a.file, srv_addr_off(&a), b, mb, 2);
	if (rc)
		return srv_fail_rc(s, rc);
	return 0;
}
