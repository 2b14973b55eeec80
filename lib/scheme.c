/* SPDX-License-Identifier: MPL-2.0 */
/*
 * scheme.c - the table of target schemes: a target's scheme picks its port
 * backend and, for a scheme whose peer does not speak DF1 frames, the link of
 * its own. A new scheme is its backend's file (lib/port/port_NAME.c, its
 * capabilities in its struct port_ops) plus a row here (doc/HACKING.md).
 *
 * The table lives at the hub, not in lib/port: a row names lib/eip's link,
 * and lib/eip sits on lib/port, so lib/port naming it would close a loop of
 * layers (tests/lint/lint-layers.sh).
 */
#include "scheme.h"

#include <string.h>
#include <strings.h>

#include "eip/eip_link.h"

/* One line a scheme: X(its name, its port backend, the link of its own or
 * NULL). The line declares the backend too (port_NAME_ops, in its own file
 * lib/port/port_NAME.c), so a new scheme is that file plus one line here. */
#define SCHEME_TABLE(X) \
	X("tcp", port_tcp, NULL)          /* raw DF1 to a device server */ \
	X("eip", port_tcp, &eip_link_ops) /* PCCC in EtherNet/IP (df1-eip(7)) */ \
	X("rfc2217", port_rfc2217, NULL)  /* a serial port on an RFC 2217 device server */ \
	/* (a new scheme's line goes above this one) */

#define SCHEME_DECLARE(name, port, link) extern const struct port_ops port##_ops;
#define SCHEME_ROW(name, port, link) { name, &port##_ops, link },
SCHEME_TABLE(SCHEME_DECLARE)

const struct scheme_row scheme_rows[] = {
	SCHEME_TABLE(SCHEME_ROW)
	{ NULL, &port_termios_ops, NULL }, /* the default: a device path */
};

const struct scheme_row *scheme_find(const char *target)
{
	const struct scheme_row *s;

	for (s = scheme_rows; s->name; s++) {
		size_t n = strlen(s->name);

		if (strncasecmp(target, s->name, n) == 0 && target[n] == ':')
			return s;
	}
	return s;
}
