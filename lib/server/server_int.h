/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server_int.h - what the responder's files share (private to lib/server):
 * the state of one command being answered (struct srv), the status helpers and
 * the data-table access by byte offset (server_access.c), and each PLC
 * family's commands, called by the dispatch (server_dispatch.c):
 * server_plc5.c (doc/PROTOCOL.md 4.2-4.4), server_slc.c (4.5, 4.6),
 * server_plc2.c (4.7), server_plc3.c (4.2a). The wing's interface is server.h.
 */
#ifndef LIBDF1_SERVER_INT_H
#define LIBDF1_SERVER_INT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "server/server.h"
#include "proto/pccc.h"
#include "proto/value.h"

/* One command being answered: the reply's STS, EXT STS and data. */
struct srv {
	struct df1 *h;
	const struct df1_server_ops *ops;
	void *user;
	int station;
	const struct pccc_msg *m;
	uint8_t sts, ext;
	size_t len;
	uint8_t data[FRAME_MAX_DATA];   /* reply data; last: not cleared per command */
};

/* Status helpers (server_access.c): all return -1 so handlers can
 * `return srv_fail_...(s, ...)`. */
int srv_fail_sts(struct srv *s, uint8_t sts);
int srv_fail_ext(struct srv *s, uint8_t ext);
/* A callback's result: > 0 EXT STS, < 0 -STS. */
int srv_fail_rc(struct srv *s, int rc);
/* PLC-2 commands have no EXT STS: a refused address is STS 50. */
int srv_fail_plc2(struct srv *s, int rc);

/* Data-table access by byte offset inside a file (server_access.c); each
 * returns 0 or the data table's result (server.h). */
size_t srv_elem_size(enum df1_file_type t);
/* Byte offset of an address (element + sub-element word) in its file. */
size_t srv_addr_off(const struct df1_addr *a);
int srv_tbl_read(struct srv *s, enum df1_file_type t, int file, size_t off, uint8_t *buf, size_t n);
int srv_tbl_write(struct srv *s, enum df1_file_type t, int file, size_t off, const uint8_t *buf,
                  const uint8_t *mask, size_t n);
/* Does file `file` exist with type t? 0 or the data table's EXT STS. */
int srv_tbl_probe(struct srv *s, enum df1_file_type t, int file);

/* The commands of each family: they set s->sts/ext/len and the reply data;
 * 0, or -1 when the reply is a failure status. */
int srv_plc5_typed_read(struct srv *s);          /* 0F/68 */
int srv_plc5_typed_write(struct srv *s);         /* 0F/67 */
int srv_plc5_word_read(struct srv *s);           /* 0F/01 */
int srv_plc5_word_write(struct srv *s);          /* 0F/00 */
int srv_plc5_word_masks(struct srv *s, bool rmw); /* 0F/26 (rmw), 0F/02 */
int srv_slc(struct srv *s, uint8_t fnc);         /* 0F/A1 A2 A9 AA AB */
int srv_plc2(struct srv *s);                     /* 01 08 00 05 02 */
int srv_plc3_word_read(struct srv *s);           /* 0F/01 serving as a PLC-3 */
int srv_plc3_word_write(struct srv *s);          /* 0F/00 serving as a PLC-3 */
int srv_plc3_bit_write(struct srv *s);           /* 0F/02 serving as a PLC-3 */

#endif
