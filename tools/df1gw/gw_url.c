/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_url - the broker URL (see gw_url.h).
 */
#include "df1gw/gw_url.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static bool host_char(char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
	       c == '-' || c == '_';
}

int gw_url_parse(const char *text, struct gw_url *u, char *err, size_t errcap)
{
	const char *p, *h, *he, *port = NULL;
	size_t hl;

	memset(u, 0, sizeof *u);
	if (strncasecmp(text, "mqtt://", 7) == 0) {
		p = text + 7;
		u->port = 1883;
	} else if (strncasecmp(text, "mqtts://", 8) == 0) {
		p = text + 8;
		u->tls = true;
		u->port = 8883;
	} else {
		snprintf(err, errcap, "expected mqtt://HOST[:PORT] or mqtts://HOST[:PORT]");
		return -1;
	}
	if (strchr(p, '@')) {
		snprintf(err, errcap, strchr(p, ':') && strchr(p, ':') < strchr(p, '@')
		         ? "no password in the URL (every user can read a command line): use --username "
		           "with --password-file FILE or DF1GW_PASSWORD"
		         : "no user name in the URL: use --username");
		return -1;
	}
	if (*p == '[') {
		h = p + 1;
		he = strchr(h, ']');
		if (!he || he == h) {
			snprintf(err, errcap, "an IPv6 address goes in brackets: mqtt://[::1]:1883");
			return -1;
		}
		for (const char *q = h; q < he; q++)
			if (!(host_char(*q) || *q == ':' || *q == '%')) {
				snprintf(err, errcap, "invalid character '%c' in the IPv6 address", *q);
				return -1;
			}
		p = he + 1;
	} else {
		h = p;
		while (host_char(*p))
			p++;
		he = p;
		if (he == h) {
			snprintf(err, errcap, "no host: expected mqtt://HOST[:PORT]");
			return -1;
		}
	}
	if (*p == ':') {
		char *end;
		long v;

		port = ++p;
		if (*port < '0' || *port > '9') {
			snprintf(err, errcap, "invalid port (expected 1-65535)");
			return -1;
		}
		v = strtol(port, &end, 10);
		if (v < 1 || v > 65535 || (*end && *end != '/')) {
			snprintf(err, errcap, "invalid port (expected 1-65535)");
			return -1;
		}
		u->port = (int)v;
		p = end;
	}
	if (*p == '/' && p[1] == '\0')
		p++;
	if (*p) {
		snprintf(err, errcap, "unexpected '%s' after the host%s", p, port ? " and port" : "");
		return -1;
	}
	hl = (size_t)(he - h);
	if (hl >= sizeof u->host) {
		snprintf(err, errcap, "host name too long");
		return -1;
	}
	memcpy(u->host, h, hl);
	u->host[hl] = '\0';
	return 0;
}
