/* SPDX-License-Identifier: MPL-2.0 */
/*
 * plc_limits.h - data per packet by PLC type and command (doc/PROTOCOL.md 6),
 * one table for every layer that plans or checks packets: the client splits
 * requests with it, the poll engine and df1_read_multi() size their block
 * reads with it, the responder refuses SLC and PLC-2 requests that exceed it
 * and cuts its PLC-5 typed replies to it (it takes PLC-5 typed and word range
 * writes of any size that fits a frame). Pure (lib/proto/limits.c).
 *
 * The rules, per command:
 *   SLC 0F/A2 read: BYTE_SIZE <= 236 (SLC 5/03+, MicroLogix), 82 (5/01, 5/02)
 *   SLC 0F/AA write: data <= 234, 82 (M p.104-105)
 *   PLC-2 01 read: SIZE <= 244 and even; 08 write: data <= 244 (M p.134, p.119)
 *   PLC-5 0F/68 typed read: the reply's type/data parameter + data, plus the
 *     command's address, <= 240 (KF2 p.129: "including the size of the PLC-5
 *     system address"); 0F/67 typed write: address + type/data + data <= 240
 *     (M p.117). The type/data parameter of an array of n elements is
 *     99 09 LL (the array size LL = descriptor + data, 1 byte up to 255, then
 *     9A 09 LL LL) and the element descriptor: one byte for integers, longs,
 *     timers, counters, controls (42 44 56 66 76), two for floats (94 08).
 *     So with N7:0's 3-byte address (06 07 00): 116 integers (3 + 4 + 232 =
 *     239), 58 floats or longs (3 + 5 + 232 = 240, 3 + 4 + 232 = 239), 38
 *     timers, counters or controls (3 + 4 + 228 = 235); a longer address
 *     (element or file >= 255: FF LL HH, doc/PROTOCOL.md 4.1; logical ASCII) leaves less.
 *     Strings go one per packet (39 LEN chars, RTA).
 *   PLC-5 0F/01 word range read: SIZE <= 244 bytes, even; 0F/00 word range
 *     write: address + data <= 239 (KF2 p.136).
 *   PLC-3 0F/01: 244 bytes; 0F/00: 239 less the address (1775-KA app. A), so
 *     228 after the longest logical binary address (mask + 1 + 3 + 3 + 3 bytes);
 *     elements are whole (T/C 6 bytes, F/H 4, the others 2).
 * T/C/R elements count as their 3 data-table words; a PLC-5 that answers
 * 5-word timers (KF2 p.130 [UNCERTAIN, doc/PROTOCOL.md 8 item 8], DF1_OPT_PLC5_TIMER_WORDS)
 * fits fewer: the client and the responder call plc5_typed_per_packet() with
 * 10-byte elements for them (23 after a 3-byte address: 3 + 5 + 230 = 238).
 *
 * DF1_OPT_MAX_PACKET (max_packet > 0) replaces the table with that many bytes
 * of element data per packet (at most PLC_PACKET_HARD_MAX), for every type.
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
#define PLC_PLC5_PACKET_MAX 240 /* typed: address + type/data + data (KF2 p.129, M p.117) */
#define PLC_WORD_READ_MAX 244   /* 0F/01 SIZE, bytes (KF2 p.136) */
#define PLC_WORD_WRITE_MAX 239  /* 0F/00 address + data (KF2 p.136) */
#define PLC_PLC3_READ_MAX 244   /* PLC-3 0F/01 reply data (1775-KA app. A) */
#define PLC_PLC3_WRITE_MAX 228  /* PLC-3 0F/00 data: 239 less the longest binary address (11) */
#define PLC_PACKET_HARD_MAX 244 /* DF1_OPT_MAX_PACKET is clamped here */
#define PLC_ECHO_MAX 243        /* 06/00 echo data (KF2 p.89) */

/* The table's bytes for a PLC type (df1_packet_max()): data bytes per read or
 * write packet; PLC-5: the whole typed packet, address and type/data included.
 * max_packet > 0 (DF1_OPT_MAX_PACKET) replaces it. */
size_t plc_packet_max(enum df1_plc plc, bool write, int max_packet);

/* The type/data element type (PCCC_TD_*) of a PLC-5 typed element of file
 * type t and esize bytes: single words are integers. */
unsigned plc5_td_type(enum df1_file_type t, size_t esize);

/* Elements of esize bytes, type/data element type td, that one PLC-5 typed
 * packet (0F/68 reply or 0F/67 command) carries after an alen-byte address:
 * the largest n with alen + type/data(n) + n * esize <= 240. */
size_t plc5_typed_per_packet(size_t alen, unsigned td, size_t esize);

/* Elements one packet carries for a span of file type t, esize bytes an
 * element, on PLC type plc; alen = the encoded PLC-5 address's bytes (0
 * otherwise). The client splits with it. 0: one element does not fit. */
size_t plc_per_packet(enum df1_plc plc, bool write, enum df1_file_type t, size_t esize,
                      size_t alen, int max_packet);

/* Bytes of whole elements one read packet carries for a block of file type t
 * starting at element `first` of file `file` (the PLC-5 address is that
 * element's logical binary form): plc_per_packet() * esize. The block
 * planner's limit (poll_plan.h), with cost = esize. */
int plc_read_limit(enum df1_plc plc, enum df1_file_type t, size_t esize, int file, int first,
                   int max_packet);

#endif
