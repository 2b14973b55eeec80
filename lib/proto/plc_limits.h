/*
 * plc_limits.h - data bytes per packet by PLC type (spec/protocol.md 6), one
 * table for every layer that plans or checks packets: the client splits
 * requests with it, the poll engine sizes its block reads with it, the server
 * refuses what exceeds it. Pure, header only.
 */
#ifndef LIBDF1_PLC_LIMITS_H
#define LIBDF1_PLC_LIMITS_H

#include <stdbool.h>
#include <stddef.h>
#include "df1.h"

#define PLC_SLC_READ_MAX 236    /* SLC 5/03+, MicroLogix A2 read data (M p.104) */
#define PLC_SLC_WRITE_MAX 234   /* AA write data (M p.105) */
#define PLC_SLC502_MAX 82       /* SLC 5/01, 5/02 reads and writes */
#define PLC_PLC2_MAX 244        /* PLC-2 01 SIZE / 08 data (M p.134, p.119) */
#define PLC_PLC5_PACKET_MAX 240 /* typed read reply incl. address and type/data (KF2 p.129) */
#define PLC_PLC5_TD_MARGIN 8    /* worst-case type/data parameter + element descriptor */
#define PLC_PLC5_ADDR_MAX 7     /* logical binary address: mask + file and element with FF escapes */
#define PLC_PLC5_TCR_READ 10    /* a PLC-5 timer/counter/control is budgeted as five words (KF2 p.130) */
#define PLC_PACKET_HARD_MAX 244 /* DF1_OPT_MAX_PACKET is clamped here */
#define PLC_ECHO_MAX 243        /* 06/00 echo data (KF2 p.89) */

/* The table: data bytes per read or write packet (lib/client/transact.c's client_limit());
 * max_packet > 0 (DF1_OPT_MAX_PACKET) replaces it. PLC-5: the whole typed
 * packet, address and type/data included. */
static inline size_t plc_packet_max(enum df1_plc plc, bool write, int max_packet)
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
	case DF1_PLC_SLC:
	case DF1_PLC_MICROLOGIX:
	default:
		return write ? PLC_SLC_WRITE_MAX : PLC_SLC_READ_MAX;
	}
}

/* Element data bytes one read packet carries for this PLC type (the poll
 * engine's block budget). PLC-5: what is left after the longest logical
 * binary address and the type/data margin. */
static inline size_t plc_read_limit(enum df1_plc plc, int max_packet)
{
	if (plc == DF1_PLC_PLC5 && max_packet <= 0)
		return PLC_PLC5_PACKET_MAX - PLC_PLC5_ADDR_MAX - PLC_PLC5_TD_MARGIN;
	return plc_packet_max(plc, false, max_packet);
}

/* Bytes one element of file type t takes out of that budget (PLC-5 T/C/R: 10;
 * a PLC-5 string goes one per packet, so it takes the whole budget). */
static inline size_t plc_read_elem_cost(enum df1_plc plc, enum df1_file_type t, size_t esize,
                                        int max_packet)
{
	if (plc == DF1_PLC_PLC5 && (t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R) && esize == 6)
		return PLC_PLC5_TCR_READ;
	if (plc == DF1_PLC_PLC5 && t == DF1_FT_ST)
		return plc_read_limit(plc, max_packet);
	return esize;
}

#endif
