/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_live - store and forward's guard of the live publications (df1gw(1),
 * STORE AND FORWARD): a tag's change published while the broker is
 * connected is kept here, as the record the buffer would have held, until
 * the broker has acknowledged every message made of it (one per format,
 * QoS 1). When the connection drops, what is not acknowledged goes into the
 * buffer, oldest first, and is replayed as historical: a message handed to
 * libmosquitto and cut off by the drop is not lost. A ring of cap entries:
 * when more are in flight the oldest is let go (counted). Pure: no I/O; a
 * blob's room grows only when a larger one comes.
 */
#ifndef DF1_TOOLS_GW_LIVE_H
#define DF1_TOOLS_GW_LIVE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1gw/gw_buffer.h"

#define GW_LIVE_MIDS 4               /* messages of one record: one per format */
#define GW_LIVE_DEFAULT 256

struct gw_live_ent {
	bool used;                   /* in flight: mids not all acknowledged */
	int mids[GW_LIVE_MIDS];
	int nmids;
	struct gw_buffer_rec r;      /* key and data point at the room below */
	char key[80];
	uint8_t *blob;
	size_t cap;
};

struct gw_live {
	struct gw_live_ent *v;
	size_t cap, head, n;         /* the entries from head, n of them (some done) */
	struct gw_live_ent *open;    /* the publication being made, or NULL */
	uint64_t let_go;             /* entries overwritten while in flight */
};

/* 0, or -1 (no memory). */
int gw_live_init(struct gw_live *l, size_t cap);
void gw_live_free(struct gw_live *l);
/* A publication of record r begins (r's key and data copied). -1: no memory
 * (then it is not guarded). */
int gw_live_open(struct gw_live *l, const struct gw_buffer_rec *r);
/* One of its messages went with QoS 1 as mid. */
void gw_live_mid(struct gw_live *l, int mid);
/* Its messages are out: an entry without any is forgotten. */
void gw_live_close(struct gw_live *l);
/* A PUBACK: true when mid was one of the guarded messages. */
bool gw_live_acked(struct gw_live *l, int mid);
/* The connection dropped: each entry not acknowledged, oldest first, to fn
 * (r valid during the call); then none. */
void gw_live_drain(struct gw_live *l, void (*fn)(void *u, struct gw_buffer_rec *r), void *u);

#endif
