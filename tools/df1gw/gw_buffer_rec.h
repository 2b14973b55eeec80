/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer_rec - the blobs of the store and forward records that are not a
 * tag's (those are gw_buffer_tag.h's): a station's health and a write's
 * result, as any payload format needs them to make the message later
 * (struct gw_station_out, struct gw_result_out). Pure: no I/O, no allocation.
 *
 * Integers little-endian; a text is u16 length and its bytes (0xFFFF: none,
 * NULL; at most 1023 bytes, longer ones cut).
 *
 * Station health, version 1: u8 1, text state ("ok", "failing", "offline",
 * "unknown"), text error, i64 last_good_wall_ms, i32 tags, i32
 * consecutive_failures, u64 attempts, u64 failures. The station is the
 * record's id.
 *
 * Write result, version 1: u8 1, u8 flags (1: ok, 2: unconfirmed), text tag,
 * text id, text error. The record's id is the slot of the format the write
 * came in (its result goes out the same way).
 */
#ifndef DF1_TOOLS_GW_BUFFER_REC_H
#define DF1_TOOLS_GW_BUFFER_REC_H

#include <stddef.h>
#include <stdint.h>

#include "df1gw/gw_format.h"

#define GW_BUFFER_TEXT_MAX 1023
/* The largest blob of either kind. */
#define GW_BUFFER_REC_MAX (64 + 3 * (2 + GW_BUFFER_TEXT_MAX))

/* s's blob into buf (cap bytes): its length, or -1 when it does not fit. */
int gw_buffer_station_pack(const struct gw_station_out *s, uint8_t *buf, size_t cap);

/* Where an unpacked station blob goes: out points at sh and the texts. */
struct gw_buffer_station_out {
	struct gw_station_out out;
	struct df1_station_health sh;
	char state[GW_BUFFER_TEXT_MAX + 1], error[GW_BUFFER_TEXT_MAX + 1];
};

/* Blob b of len bytes of station stn into o. 0, or -1 when it is not a
 * station blob of version 1 (cut short, too long, no state). */
int gw_buffer_station_unpack(const void *b, size_t len, int stn, struct gw_buffer_station_out *o);

/* r's blob (r->now is not kept: a result replayed tells the tag's value of
 * then no more) into buf. Its length, or -1. */
int gw_buffer_result_pack(const struct gw_result_out *r, uint8_t *buf, size_t cap);

struct gw_buffer_result_out {
	struct gw_result_out out;
	char tag[GW_BUFFER_TEXT_MAX + 1], id[GW_BUFFER_TEXT_MAX + 1], error[GW_BUFFER_TEXT_MAX + 1];
};

/* 0, or -1 when it is not a result blob of version 1 (a tag missing too). */
int gw_buffer_result_unpack(const void *b, size_t len, struct gw_buffer_result_out *o);

#endif
