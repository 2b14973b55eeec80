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

const struct scheme_row scheme_rows[] = {
	{ "tcp", &port_tcp_ops, NULL },         /* raw DF1 to a device server */
	{ "eip", &port_tcp_ops, &eip_link_ops }, /* PCCC in EtherNet/IP (df1-eip(7)) */
	{ NULL, &port_termios_ops, NULL },       /* the default: a device path */
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
