/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_replay - the pace of store and forward's replay (doc/ARCHITECTURE.md
 * 11.5): at most rate records a second (a token bucket holding a twentieth
 * of a second's worth, at least one), never more than window publications
 * handed to libmosquitto and not acknowledged, and which record each of
 * those publications (its MQTT message id) carries, so that a PUBACK
 * acknowledges the record once every message made of it has been
 * acknowledged. Pure: no I/O, no clock (the caller gives now), no allocation
 * after init.
 */
#ifndef DF1_TOOLS_GW_REPLAY_H
#define DF1_TOOLS_GW_REPLAY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GW_REPLAY_RATE_DEFAULT 500u      /* records a second: 100 000 in about 3 minutes */
#define GW_REPLAY_RATE_MAX 100000u
#define GW_REPLAY_WINDOW 64u             /* publications handed and not acknowledged */

struct gw_replay_sent {
	int mid;
	uint64_t seq;
};

struct gw_replay {
	unsigned rate;               /* records a second */
	double tokens, burst;
	int64_t last_ms;             /* the bucket's last fill, 0: never */
	struct gw_replay_sent v[GW_REPLAY_WINDOW];
	size_t n;                    /* publications in flight */
	uint64_t replayed;           /* records whose every message was acknowledged */
};

/* rate records a second (0: the default). */
void gw_replay_init(struct gw_replay *r, unsigned rate);
/* How many records may be handed over at now: what the bucket holds (it
 * fills up to its burst), and no more than the window's room divided by
 * per (the messages a record makes: one per format). */
size_t gw_replay_budget(struct gw_replay *r, int64_t now, size_t per);
/* k records were handed over. */
void gw_replay_spent(struct gw_replay *r, size_t k);
/* Milliseconds until the bucket has a record again (0: now). */
int gw_replay_wait_ms(const struct gw_replay *r, int64_t now);
/* Message mid carries record seq. -1 when the window is full (not noted). */
int gw_replay_sent(struct gw_replay *r, int mid, uint64_t seq);
/* The PUBACK of mid: true with *seq when it was the last message of its
 * record in flight (the record is then to be acknowledged); false for a
 * message not of the replay, or a record with messages still in flight. */
bool gw_replay_acked(struct gw_replay *r, int mid, uint64_t *seq);
/* The connection dropped: nothing is in flight any more (the buffer
 * rewinds: its records are handed out again). */
void gw_replay_reset(struct gw_replay *r);
/* "500", "500/s": records a second, 1 to GW_REPLAY_RATE_MAX. 0, or -1. */
int gw_replay_parse_rate(const char *s, unsigned *rate);

#endif
