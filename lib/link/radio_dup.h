/* SPDX-License-Identifier: MPL-2.0 */
/*
 * radio_dup - the DF1 Radio Modem's pure pieces (doc/PROTOCOL.md 2.6): the
 * table of the last packets heard (duplicate detection), the store and
 * forward rule, and the station list syntax of a forward table. No handle,
 * no clock, no I/O; lib/link/radio.c uses them.
 */
#ifndef LIBDF1_RADIO_DUP_H
#define LIBDF1_RADIO_DUP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The last RADIO_DUP_DEPTH packets, each by its key: the first six
 * application bytes, DST SRC CMD STS TNS TNS (doc/PROTOCOL.md 2.6). */
#define RADIO_DUP_DEPTH 20
#define RADIO_DUP_KEY 6
struct radio_dup {
	uint8_t key[RADIO_DUP_DEPTH][RADIO_DUP_KEY];
	unsigned n;                  /* keys held, up to RADIO_DUP_DEPTH */
	unsigned next;               /* where the next key goes (the oldest once full) */
};

void radio_dup_clear(struct radio_dup *d);
/* Whether app (n bytes) repeats a packet held; a packet shorter than a key never does. */
bool radio_dup_seen(const struct radio_dup *d, const uint8_t *app, size_t n);
/* Hold app's key, in place of the oldest when the table is full. */
void radio_dup_add(struct radio_dup *d, const uint8_t *app, size_t n);

/* Bit stn of a 32-byte forward table. */
bool radio_fwd_bit(const uint8_t *table, unsigned stn);
/* The store and forward rule for a packet that is not a duplicate
 * (doc/PROTOCOL.md 2.6): never one whose SRC is own; a broadcast (DST 255)
 * when bit 255 is set; else one whose DST is not own and whose DST bit is set. */
bool radio_fwd_rule(const uint8_t *table, uint8_t own, const uint8_t *app, size_t n);

/* "1,3-5,255" into a 32-byte table (cleared first): numbers 0-255, ranges
 * a-b with a <= b, separated by commas, blanks around them allowed; "" and
 * "none" are the empty table. 0, or -1 for any other text. */
int radio_fwd_parse(const char *list, uint8_t *table);

#endif
