/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_radio - df1mon's decoding modes (--decode, --read, --sniff) with
 * --duplex radio: what a DF1 Radio Modem channel carries (doc/PROTOCOL.md
 * 2.6, libdf1(7) RADIO MODEM). The framing is full duplex's (mon_stream.c
 * gives the decoder no poll reading); no ACK is expected, so none is missed.
 *
 * A store-and-forward relay sends a packet again unchanged, so a listener
 * hears the same packet more than once. Like a node's duplicate detection,
 * the last MON_RADIO_DEPTH good packets are remembered by DST, SRC, CMD, STS
 * and TNS; a packet that repeats one of them is marked a relayed copy of
 * the first (decode_where.copy_of: the symbol number of that one), and a
 * second or later copy of it a duplicate (what a node with duplicate
 * detection drops after taking one). A relay changes no byte: who sent a copy
 * is known only when the capture says (the rx/tx direction of two taps or of
 * an RTAC record, printed in its column); then a packet the tx side sends
 * again is its own retry (--app-retries), a duplicate but not a relay.
 *
 * The tallies, printed after the decoding summary: packets sent (tx side)
 * and received (good check), relayed copies, duplicates, bad packets (bad
 * check or framing). Packets not delivered (no CTS, carrier up) happen inside
 * a sender and never reach the air: only a live handle counts them
 * (df1_radio_stats, df1mon --counters).
 */
#include "df1mon/mon.h"

#include <string.h>

/* The key of a packet: DST SRC CMD STS TNS (two bytes), as the data begins. */
#define KEY_LEN 6

static bool is_tx(const char *dir)
{
	return dir && strcmp(dir, "tx") == 0;
}

/* The remembered packet with this key, or NULL. */
static struct mon_radio_pkt *radio_find(struct mon_radio *r, const uint8_t *key)
{
	for (unsigned i = 0; i < r->n; i++) {
		struct mon_radio_pkt *p = &r->last[i];
		if (memcmp(p->key, key, KEY_LEN) == 0)
			return p;
	}
	return NULL;
}

void mon_radio_seen(struct mon *m, const char *dir, const struct df1_symbol *sym,
                    struct decode_where *w)
{
	struct mon_radio *r = &m->radio;
	struct mon_radio_pkt *p;

	if (sym->kind == DF1_SYM_ERROR) {
		r->bad++;   /* a bad check, a frame cut short, a DLE pair inside one: dropped */
		return;
	}
	if (sym->kind != DF1_SYM_FRAME)
		return;
	if (!sym->check_ok || sym->len < KEY_LEN) {
		r->bad++;
		return;
	}
	if (is_tx(dir))
		r->sent++;
	else
		r->received++;
	p = radio_find(r, sym->data);
	if (p) {
		w->copy_of = p->first;
		if (is_tx(dir) && is_tx(p->dir)) {
			w->copy_duplicate = true;  /* the tx side sent it again: a retry */
			r->duplicates++;
		} else {
			w->copy_relay = true;
			r->relayed++;
			if (p->relayed) {
				w->copy_duplicate = true;  /* one more copy of a packet relayed already */
				r->duplicates++;
			}
			p->relayed = true;
		}
		return;
	}
	/* a new packet: it takes the place of the oldest when the table is full */
	if (r->n < MON_RADIO_DEPTH) {
		p = &r->last[r->n++];
	} else {
		p = &r->last[r->head];
		r->head = (r->head + 1) % MON_RADIO_DEPTH;
	}
	memcpy(p->key, sym->data, KEY_LEN);
	p->first = w->index;
	p->dir = dir;
	p->relayed = false;
}

void mon_radio_summary(const struct mon *m, FILE *f)
{
	const struct mon_radio *r = &m->radio;

	fprintf(f, "%s: radio: packets sent %lu, received %lu, relayed %lu, duplicates %lu, bad %lu\n",
	        m->cli.name, r->sent, r->received, r->relayed, r->duplicates, r->bad);
}
