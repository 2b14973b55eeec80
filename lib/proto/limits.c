/* SPDX-License-Identifier: MPL-2.0 */
/*
 * limits.c - the packet-limit table (plc_limits.h): the bytes per PLC type
 * (df1_packet_max()) and the elements per packet for each command, derived
 * here once from doc/PROTOCOL.md 6. Pure.
 */
#include "proto/plc_limits.h"

#include "proto/frame.h"
#include "proto/pccc.h"

size_t plc_packet_max(enum df1_plc plc, bool write, int max_packet)
{
	if (max_packet > 0)
		return max_packet < PLC_PACKET_HARD_MAX ? (size_t)max_packet : PLC_PACKET_HARD_MAX;
	switch (plc) {
	case DF1_PLC_SLC502:
		return PLC_SLC502_MAX;
	case DF1_PLC_PLC2:
		return PLC_PLC2_MAX;
	case DF1_PLC_PLC5:
		return PLC_PLC5_PACKET_MAX;
	case DF1_PLC_PLC3:
		return write ? PLC_PLC3_WRITE_MAX : PLC_PLC3_READ_MAX;
	case DF1_PLC_SLC:
	case DF1_PLC_MICROLOGIX:
	default:
		return write ? PLC_SLC_WRITE_MAX : PLC_SLC_READ_MAX;
	}
}

int df1_packet_max(enum df1_plc plc, bool write)
{
	if ((int)plc < DF1_PLC_SLC || (int)plc > DF1_PLC_PLC3)
		return DF1_E_INVAL;
	return (int)plc_packet_max(plc, write, 0);
}

unsigned plc5_td_type(enum df1_file_type t, size_t esize)
{
	if (esize == 2)
		return PCCC_TD_INTEGER;
	switch (t) {
	case DF1_FT_F: return PCCC_TD_FLOAT;
	case DF1_FT_T: return PCCC_TD_TIMER;
	case DF1_FT_C: return PCCC_TD_COUNTER;
	case DF1_FT_R: return PCCC_TD_CONTROL;
	case DF1_FT_ST: return PCCC_TD_STRING;
	default: return PCCC_TD_INTEGER;        /* L */
	}
}

/* Bytes of the type/data parameter of an array of n elements, as the client and
 * the responder encode it (pccc_enc_typed_array: 99 09 LL + descriptor). */
static size_t plc5_td_len(unsigned td, size_t esize, size_t n)
{
	uint8_t b[32];
	int r = pccc_enc_typed_array(b, sizeof b, td, (uint32_t)esize, n);

	return r < 0 ? FRAME_MAX_DATA : (size_t)r;
}

/* Largest n whose packet passes: at most data_max data bytes (0: no such
 * limit), with whole, address + type/data + data <= 240, and the frame's
 * room. The type/data size grows with n (a byte more past an array size of
 * 255), so count up: at most a few hundred steps. */
static size_t plc5_per(size_t alen, unsigned td, size_t esize, size_t data_max, bool whole,
                       size_t room)
{
	size_t n = 0;

	for (;;) {
		size_t k = n + 1, data = k * esize, tl = plc5_td_len(td, esize, k);

		if ((data_max && data > data_max) || tl + data > room ||
		    (whole && alen + tl + data > PLC_PLC5_PACKET_MAX))
			return n;
		n = k;
	}
}

size_t plc5_typed_per_packet(size_t alen, unsigned td, size_t esize)
{
	if (td == PCCC_TD_STRING)
		return 1;
	if (esize == 0)
		return 0;
	return plc5_per(alen, td, esize, 0, true, FRAME_MAX_DATA - PCCC_HDR_LEN);
}

size_t plc_per_packet(enum df1_plc plc, bool write, enum df1_file_type t, size_t esize,
                      size_t alen, int max_packet)
{
	size_t room;
	unsigned td;

	if (esize == 0)
		return 0;
	if (plc != DF1_PLC_PLC5)
		return plc_packet_max(plc, write, max_packet) / esize;
	td = plc5_td_type(t, esize);
	if (td == PCCC_TD_STRING)
		return 1;       /* one string per packet, whatever the limit */
	if (alen + PCCC_HDR_LEN + 5 >= FRAME_MAX_DATA)
		return 0;
	/* the frame: a write command's header, FNC, PKT_OFFSET, TOTAL_TRANS and
	 * address; a read reply's header */
	room = write ? FRAME_MAX_DATA - PCCC_HDR_LEN - 5 - alen : FRAME_MAX_DATA - PCCC_HDR_LEN;
	if (max_packet > 0)
		return plc5_per(alen, td, esize, plc_packet_max(plc, write, max_packet), false, room);
	return plc5_per(alen, td, esize, 0, true, room);
}

int plc_read_limit(enum df1_plc plc, enum df1_file_type t, size_t esize, int file, int first,
                   int max_packet)
{
	size_t alen = 0;

	if (plc == DF1_PLC_PLC5) {
		struct df1_addr a = { .type = t, .file = file, .element = first, .sub = DF1_ADDR_NONE,
		                      .bit = DF1_ADDR_NONE };
		uint8_t b[16];
		int r = pccc_enc_plc5_addr(b, sizeof b, &a);

		alen = r < 0 ? 7 : (size_t)r;   /* the longest binary address */
	}
	return (int)(plc_per_packet(plc, false, t, esize, alen, max_packet) * esize);
}
