/* SPDX-License-Identifier: MPL-2.0 */
/*
 * msg.c - application messages decoded for display: df1_msg_decode and
 * df1_values_decode (public, df1.h). df1mon and the tools' -v output use them.
 *
 * What df1_msg_decode puts in struct df1_msg:
 *  - name: pccc_command_name() ("SLC typed read, 3 fields (0F/A2)", "reply (4F)").
 *  - addr (has_addr) for commands that carry one:
 *      SLC A1 A2 A9 AA AB: type from the file type code (DF1_FT_NONE if unknown),
 *        file, element; sub-element 0 is left out (sub DF1_ADDR_NONE), since the
 *        element starts there: A2 N7:0 sub 0 shows as "N7:0", T4:2 sub 2 as "T4:2.2".
 *      PLC-5 00 01 02 26 67 68: as pccc_dec_plc5_addr(). A binary address has no
 *        file type, so type stays DF1_FT_NONE (guessing N from file 7 or from the data
 *        type would mislabel N10 or B3); an ASCII address keeps its text in addr.ascii.
 *      PLC-3 00 01 02 (a logical binary address whose mask has the word level,
 *        bit 5, which no PLC-5 address has: doc/PROTOCOL.md 4.2a): name "PLC-3 word
 *        range read (0F/01)" etc., addr as pccc_plc3_to_addr() (type from the
 *        section; T/C sub = the word, word 0 left out as above), to be shown
 *        with df1_addr_format_plc().
 *      PLC-2 01/08 byte addresses are not data-table addresses: has_addr false.
 *  - size: SLC BYTE_SIZE; 68 elements; 01 bytes; PLC-2 01 SIZE; 06/01 SIZE;
 *    00/08/A9/AA/AB and 67 the bytes / elements written; -1 otherwise.
 *  - data: write data (AB: MASK then DATA; 67: the element bytes after the
 *    type/data parameter; 26: AND OR; 02: SET RESET; other commands: the bytes
 *    after the fields above), or for a reply the bytes after STS / EXT STS.
 * A body too short for its fields gives DF1_E_TOO_SHORT with the header fields,
 * name and data (the whole body) already filled in.
 */
#include "df1.h"

#include <string.h>

#include "proto/pccc.h"
#include "proto/value.h"

static int msg_decode_slc(const struct pccc_msg *p, struct df1_msg *m)
{
	bool three = p->fnc != PCCC_FNC_SLC_READ2 && p->fnc != PCCC_FNC_SLC_WRITE2;
	bool write = p->fnc != PCCC_FNC_SLC_READ2 && p->fnc != PCCC_FNC_SLC_READ3;
	uint8_t nbytes, code;
	unsigned file, elem, sub;
	size_t pos;
	int r;

	r = pccc_dec_slc_fields(p->data, p->len, three, &nbytes, &file, &code, &elem, &sub);
	if (r < 0)
		return r;
	pos = (size_t)r;
	m->has_addr = true;
	m->addr.type = pccc_slc_code_file_type(code);
	m->addr.file = (int)file;
	m->addr.element = (int)elem;
	m->addr.sub = (three && sub != 0) ? (int)sub : DF1_ADDR_NONE;
	m->addr.bit = DF1_ADDR_NONE;
	m->size = nbytes;
	m->data = p->data + pos;
	m->data_len = p->len - pos;
	if (write && m->data_len < (size_t)nbytes * (p->fnc == PCCC_FNC_SLC_MASKED ? 2 : 1))
		return DF1_E_TOO_SHORT;
	return 0;
}

static int msg_decode_plc5(const struct pccc_msg *p, struct df1_msg *m)
{
	struct pccc_plc5_req r;
	struct pccc_typed t;
	int e = pccc_dec_plc5_req(p->fnc, p->data, p->len, &r);

	if (e < 0)
		return e;
	m->has_addr = true;
	m->addr = r.addr;
	m->size = r.size;
	m->data = r.data;
	m->data_len = r.len;
	if (p->fnc == PCCC_FNC_WORD_WRITE) {
		m->size = (int)r.len;
	} else if (p->fnc == PCCC_FNC_TYPED_WRITE) {
		e = pccc_dec_typed(r.data, r.len, &t);
		if (e < 0)
			return e;
		m->size = (int)t.count;
		m->data = t.data;
		m->data_len = t.len;
	}
	return 0;
}

/* Is the body of 0F/00 01 02 a PLC-3 one? Its address's mask has the word level. */
static bool msg_is_plc3(const struct pccc_msg *p)
{
	size_t at = p->fnc == PCCC_FNC_BIT_WRITE ? 0 : 4;

	return p->len > at && (p->data[at] & 0x20) && !(p->data[at] & 0xC0) && p->data[at] != 0xFF;
}

/* 0F/01 { OFFSET TOTAL ADDR SIZE }, 0F/00 { OFFSET TOTAL ADDR DATA }, 0F/02 { ADDR SET RESET }. */
static int msg_decode_plc3(const struct pccc_msg *p, struct df1_msg *m)
{
	static const char *const names[3] = {
		"PLC-3 word range write (0F/00)", "PLC-3 word range read (0F/01)", "PLC-3 bit write (0F/02)",
	};
	size_t at = p->fnc == PCCC_FNC_BIT_WRITE ? 0 : 4;
	struct pccc_plc3_addr l;
	int k, e;

	m->name = names[p->fnc];
	k = pccc_dec_plc3_addr(p->data + at, p->len - at, &l);
	if (k < 0)
		return k;
	e = pccc_plc3_to_addr(&l, &m->addr);
	if (e < 0)
		return e;
	if (m->addr.sub == 0)
		m->addr.sub = DF1_ADDR_NONE;    /* from the structure's start, as SLC word 0 */
	m->has_addr = true;
	m->data = p->data + at + (size_t)k;
	m->data_len = p->len - at - (size_t)k;
	if (p->fnc == PCCC_FNC_WORD_READ) {
		if (m->data_len < 1)
			return DF1_E_TOO_SHORT;
		m->size = m->data[0];
		m->data_len = 0;
	} else if (p->fnc == PCCC_FNC_WORD_WRITE) {
		m->size = (int)m->data_len;
	}
	return 0;
}

static int msg_decode_command(const struct pccc_msg *p, struct df1_msg *m)
{
	switch (p->cmd) {
	case PCCC_CMD_UNPROT_READ:
		if (p->len < 3)
			return DF1_E_TOO_SHORT;
		m->size = p->data[2];
		m->data = p->data + 3;
		m->data_len = p->len - 3;
		return 0;
	case PCCC_CMD_PROT_WRITE:
	case PCCC_CMD_UNPROT_WRITE:
		if (p->len < 2)
			return DF1_E_TOO_SHORT;
		m->data = p->data + 2;
		m->data_len = p->len - 2;
		m->size = (int)m->data_len;
		return 0;
	case PCCC_CMD_DIAG:
		if (p->fnc == PCCC_FNC_DIAG_READ) {
			if (p->len < 3)
				return DF1_E_TOO_SHORT;
			m->size = p->data[2];
		}
		return 0;
	case PCCC_CMD_TYPED:
		switch (p->fnc) {
		case PCCC_FNC_SLC_READ2: case PCCC_FNC_SLC_READ3:
		case PCCC_FNC_SLC_WRITE2: case PCCC_FNC_SLC_WRITE3:
		case PCCC_FNC_SLC_MASKED:
			return msg_decode_slc(p, m);
		case PCCC_FNC_WORD_WRITE: case PCCC_FNC_WORD_READ: case PCCC_FNC_BIT_WRITE:
			return msg_is_plc3(p) ? msg_decode_plc3(p, m) : msg_decode_plc5(p, m);
		case PCCC_FNC_RMW:
		case PCCC_FNC_TYPED_WRITE: case PCCC_FNC_TYPED_READ:
			return msg_decode_plc5(p, m);
		default:
			return 0;
		}
	default:
		return 0;
	}
}

int df1_msg_decode(const uint8_t *app, size_t n, struct df1_msg *m)
{
	struct pccc_msg p;
	int r;

	if (!app || !m)
		return DF1_E_INVAL;
	memset(m, 0, sizeof *m);
	m->size = -1;
	m->name = "message too short";
	m->addr.type = DF1_FT_NONE;
	m->addr.file = m->addr.element = DF1_ADDR_NONE;
	m->addr.sub = m->addr.bit = DF1_ADDR_NONE;
	r = pccc_decode(app, n, &p);
	if (n >= PCCC_HDR_LEN) {
		m->dst = p.dst;
		m->src = p.src;
		m->cmd = p.cmd;
		m->sts = p.sts;
		m->tns = p.tns;
		m->is_reply = p.is_reply;
		m->has_fnc = p.has_fnc;
		m->fnc = p.fnc;
		m->has_ext_sts = p.has_ext;
		m->ext_sts = p.ext_sts;
		m->name = pccc_command_name(p.cmd, p.has_fnc, p.fnc);
	}
	if (r < 0)
		return r;
	m->data = p.data;
	m->data_len = p.len;
	if (p.is_reply)
		return 0;
	r = msg_decode_command(&p, m);
	if (r < 0) {
		/* keep the whole body visible, but no half-decoded address */
		m->has_addr = false;
		m->data = p.data;
		m->data_len = p.len;
	}
	return r;
}

int df1_values_decode(enum df1_file_type t, const uint8_t *bytes, size_t n,
                      struct df1_value *out, size_t max)
{
	size_t count = 0, pos = 0;

	if ((!bytes && n) || (!out && max))
		return DF1_E_INVAL;
	/* data of unknown type (a PLC-5 binary address) shows as words */
	if (t == DF1_FT_NONE)
		t = DF1_FT_N;
	while (count < max && pos < n) {
		int r = value_decode_element(t, bytes + pos, n - pos, &out[count], VALUE_FLOAT_LE);

		if (r == DF1_E_TOO_SHORT)
			break;          /* a partial trailing element is not a value */
		if (r < 0)
			return r;
		pos += (size_t)r;
		count++;
	}
	return (int)count;
}
