/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server - the responder (slave / peer side): a received PCCC command ->
 * data-table callbacks (struct df1_server_ops) -> reply (doc/ARCHITECTURE.md 2, 3;
 * doc/PROTOCOL.md 3-5). df1_serve() runs the link layer's link_serve() with
 * server_handle() as its handler; tests call server_handle() directly.
 *
 * The data-table contract (what the callbacks of struct df1_server_ops see):
 *  - a->type is the file type, a->file the file number. The data starts at byte
 *    element * element_size + sub * 2 of the file (a->sub DF1_ADDR_NONE = 0: the
 *    start of the element; else the word inside it, e.g. T4:1.ACC = element 1,
 *    sub 2) and runs for nbytes, into the following elements if need be. a->bit
 *    is always DF1_ADDR_NONE (bits travel in masks) and a->ascii is "".
 *  - Element data is in the SLC wire layout: LE words, LE floats, L as LE32,
 *    ST as LEN(2) + 82 characters byte-swapped per word, T/C/R as 3 words.
 *  - write(): mask NULL writes every bit; else mask[i] selects the bits of
 *    buf[i] that replace the stored ones (the 0F/AB rule); the others stay.
 *  - read() with nbytes == 0 is a probe: return 0 if file a->file exists and
 *    holds type a->type, else an EXT STS (06 no such file, 11 other type). The
 *    responder uses it to learn the type of a PLC-5 file from a binary address.
 *  - Return 0, an EXT STS code (> 0: the reply is STS F0 + that code; for
 *    PLC-2 commands, which carry no EXT STS, STS 50), or -STS (< 0).
 */
#ifndef LIBDF1_SERVER_H
#define LIBDF1_SERVER_H

#include "df1_int.h"
#include "link/link.h"
#include "proto/plc_limits.h"

/* ctx of server_handle(): the callbacks and their user pointer. */
struct server_ctx {
	const struct df1_server_ops *ops;
	void *user;
};

/* PLC-2 commands (01, 08, 00, 05, 02) address this integer file, as a byte
 * address (even for 01/08/00): the SLC 500 common interface file N9 (M p.119),
 * MicroLogix N7, and N9 as the PLC-5 compatibility file. */
#define SERVER_PLC2_FILE_SLC 9
#define SERVER_PLC2_FILE_MICROLOGIX 7
#define SERVER_PLC2_FILE_PLC5 9

/* Data limits per reply / write (doc/PROTOCOL.md 6): lib/proto/plc_limits.h's
 * PLC_SLC_READ_MAX (A1/A2), PLC_SLC_WRITE_MAX (A9/AA/AB), PLC_SLC502_MAX,
 * PLC_PLC2_MAX (01 SIZE, 08 data), PLC_ECHO_MAX (06/00), plc5_typed_per_packet()
 * (0F/68 reply: the command's address + type/data + data <= 240), and: */
#define SERVER_WORD_READ_MAX PLC_WORD_READ_MAX   /* 0F/01 reply data (KF2 p.136) */

/* The link handler (link_handler_fn): decode the command in cmd[0..n), run it
 * through ctx (a struct server_ctx *), write the reply app bytes. Returns the
 * reply length, 0 for no reply (too short to answer, or not a command), or DF1_E_*. */
int server_handle(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);

/* The responder state of h (reply slots, faults, stations served), allocated
 * on first use and freed by df1_free(); NULL when out of memory. */
struct link_responder *server_responder(struct df1 *h);

/* The default 06/03 diagnostic status (no diag_status callback): a generic
 * SLC 5/04 (type 5Bh) in the EE form of doc/PROTOCOL.md 4.9, in run mode. Returns bytes. */
int server_default_diag(uint8_t *buf, size_t cap);

#endif
