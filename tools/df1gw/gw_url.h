/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_url - df1gw's broker URL: mqtt://HOST[:PORT] (1883) or mqtts://HOST[:PORT]
 * (8883, TLS); an IPv6 address in brackets. Pure.
 */
#ifndef DF1_TOOLS_GW_URL_H
#define DF1_TOOLS_GW_URL_H

#include <stdbool.h>
#include <stddef.h>

struct gw_url {
	bool tls;
	char host[256];
	int port;
};

/* Parse text into *u. Returns 0, or -1 with err saying what is wrong (a
 * password in the URL is refused: it would be on the command line). */
int gw_url_parse(const char *text, struct gw_url *u, char *err, size_t errcap);

#endif
