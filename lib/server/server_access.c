/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server_access.c - what every command of the responder uses: the status
 * helpers (the reply's STS / EXT STS, doc/PROTOCOL.md 3.2, 3.3) and the
 * data-table access by byte offset inside a file, through the callbacks of
 * struct df1_server_ops (the contract is in server.h).
 */
#include "server/server_int.h"

#include <string.h>

/* ------------------------------------------------------------------------
 * Status helpers: all return -1 so handlers can `return fail_...(s, ...)`.
 * ------------------------------------------------------------------------ */

int srv_fail_sts(struct srv *s, uint8_t sts)
{
	s->sts = sts ? sts : 0x10;
	s->ext = 0;
	s->len = 0;
	return -1;
}

int srv_fail_ext(struct srv *s, uint8_t ext)
{
	s->sts = 0xF0;
	s->ext = ext;
	s->len = 0;
	return -1;
}

/* A callback's result: > 0 EXT STS, < 0 -STS. */
int srv_fail_rc(struct srv *s, int rc)
{
	if (rc > 0)
		return srv_fail_ext(s, (uint8_t)(rc & 0xFF) ? (uint8_t)(rc & 0xFF) : 0x14);
	return srv_fail_sts(s, (uint8_t)((-rc) & 0xFF));
}

/* PLC-2 commands have no EXT STS: a refused address is STS 50. */
int srv_fail_plc2(struct srv *s, int rc)
{
	if (rc > 0)
		return srv_fail_sts(s, 0x50);
	return srv_fail_sts(s, (uint8_t)((-rc) & 0xFF));
}

/* ------------------------------------------------------------------------
 * Data-table access by byte offset inside a file
 * ------------------------------------------------------------------------ */

size_t srv_elem_size(enum df1_file_type t)
{
	int es = df1_file_type_element_size(t);

	return es > 0 ? (size_t)es : 2;
}

/* The address of byte `off` (even) of file `file` of type t. */
static void addr_at(struct df1_addr *a, enum df1_file_type t, int file, size_t off)
{
	size_t es = srv_elem_size(t), rem = off % es;

	memset(a, 0, sizeof *a);
	a->type = t;
	a->file = file;
	a->element = (int)(off / es);
	a->sub = rem ? (int)(rem / 2) : DF1_ADDR_NONE;
	a->bit = DF1_ADDR_NONE;
}

/* Byte offset of an address (element + sub-element word) in its file. */
size_t srv_addr_off(const struct df1_addr *a)
{
	size_t off = (size_t)a->element * srv_elem_size(a->type);

	if (a->sub != DF1_ADDR_NONE && a->sub > 0)
		off += (size_t)a->sub * 2;
	return off;
}

int srv_tbl_read(struct srv *s, enum df1_file_type t, int file, size_t off, uint8_t *buf, size_t n)
{
	struct df1_addr a;

	if (!s->ops->read)
		return 0x0E;    /* command cannot be executed */
	addr_at(&a, t, file, off);
	return s->ops->read(s->user, s->station, &a, buf, n);
}

int srv_tbl_write(struct srv *s, enum df1_file_type t, int file, size_t off, const uint8_t *buf,
                     const uint8_t *mask, size_t n)
{
	struct df1_addr a;

	if (!s->ops->write)
		return 0x0E;
	addr_at(&a, t, file, off);
	return s->ops->write(s->user, s->station, &a, buf, mask, n);
}

/* Does file `file` exist with type t? 0 or the data table's EXT STS. */
int srv_tbl_probe(struct srv *s, enum df1_file_type t, int file)
{
	uint8_t dummy = 0;

	return srv_tbl_read(s, t, file, 0, &dummy, 0);
}
