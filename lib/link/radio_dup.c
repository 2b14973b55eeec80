/* SPDX-License-Identifier: MPL-2.0 */
/*
 * radio_dup.c - the radio modem's duplicate table, forward rule and station
 * lists (radio_dup.h; doc/PROTOCOL.md 2.6). Pure.
 *
 * Decisions: the key is the first six application bytes (DST SRC CMD STS
 * TNS), the recommendation of doc/PROTOCOL.md 2.6 (the manuals do not name
 * it): a relayed copy carries the same bytes, and a new message has a new TNS
 * or another header, so it is never taken for a repeat.
 */
#include "link/radio_dup.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

void radio_dup_clear(struct radio_dup *d)
{
	memset(d, 0, sizeof *d);
}

bool radio_dup_seen(const struct radio_dup *d, const uint8_t *app, size_t n)
{
	if (n < RADIO_DUP_KEY)
		return false;
	for (unsigned i = 0; i < d->n && i < RADIO_DUP_DEPTH; i++)
		if (memcmp(d->key[i], app, RADIO_DUP_KEY) == 0)
			return true;
	return false;
}

void radio_dup_add(struct radio_dup *d, const uint8_t *app, size_t n)
{
	if (n < RADIO_DUP_KEY)
		return;
	memcpy(d->key[d->next % RADIO_DUP_DEPTH], app, RADIO_DUP_KEY);
	d->next = (d->next + 1) % RADIO_DUP_DEPTH;
	if (d->n < RADIO_DUP_DEPTH)
		d->n++;
}

bool radio_fwd_bit(const uint8_t *table, unsigned stn)
{
	return stn < 256 && (table[stn / 8] >> (stn % 8)) & 1;
}

bool radio_fwd_rule(const uint8_t *table, uint8_t own, const uint8_t *app, size_t n)
{
	if (n < RADIO_DUP_KEY || app[1] == own)
		return false;
	if (app[0] == 255)
		return radio_fwd_bit(table, 255);
	return app[0] != own && radio_fwd_bit(table, app[0]);
}

/* One number 0-255 at *p, blanks before it skipped; -1 when there is none. */
static long radio_fwd_num(const char **p)
{
	char *end;
	long v;

	while (**p == ' ' || **p == '\t')
		(*p)++;
	if (!isdigit((unsigned char)**p))
		return -1;
	v = strtol(*p, &end, 10);
	if (v < 0 || v > 255)
		return -1;
	*p = end;
	while (**p == ' ' || **p == '\t')
		(*p)++;
	return v;
}

int radio_fwd_parse(const char *list, uint8_t *table)
{
	const char *p = list;

	memset(table, 0, 32);
	if (!list)
		return -1;
	while (*p == ' ' || *p == '\t')
		p++;
	if (*p == '\0' || strcmp(p, "none") == 0)
		return 0;
	for (;;) {
		long a = radio_fwd_num(&p), b;

		if (a < 0)
			goto bad;
		b = a;
		if (*p == '-') {
			p++;
			b = radio_fwd_num(&p);
			if (b < a)
				goto bad;
		}
		for (long s = a; s <= b; s++)
			table[s / 8] |= (uint8_t)(1u << (s % 8));
		if (*p == '\0')
			return 0;
		if (*p != ',')
			goto bad;
		p++;
	}
bad:
	memset(table, 0, 32);
	return -1;
}
