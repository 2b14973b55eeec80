/* SPDX-License-Identifier: MPL-2.0 */
/*
 * scheme.h - the table of target schemes (lib/scheme.c): which port backend
 * (lib/port) a df1_open() target opens, and for a scheme that brings one, its
 * own link instead of DF1 (lib/eip). df1_open() and the network configuration
 * file (lib/config/config_net.c, Com_Port) read targets through it.
 */
#ifndef LIBDF1_SCHEME_H
#define LIBDF1_SCHEME_H

#include "df1_int.h"

struct scheme_row {
	/* "tcp": a target that begins "tcp:" in any case (RFC 3986 3.1), "//" or
	 * not; NULL in the last row, the default: a device path. */
	const char *name;
	const struct port_ops *port;     /* the backend; its capabilities (lib/port/port.h) */
	const struct own_link_ops *link; /* NULL: the DF1 link (lib/link) runs on the port */
};

/* The rows, the default row (name NULL) last. */
extern const struct scheme_row scheme_rows[];

/* The row of target: the scheme it begins with, else the default row: a target
 * of no known scheme ("/dev/ttyS0", "ttyUSB0", "foo://x") is a device path.
 * Never NULL; target must not be NULL. */
const struct scheme_row *scheme_find(const char *target);

#endif
