/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_buffer_tag - a tag's state as the blob of a store and forward record
 * (gw_buffer.h), and back: what any payload format needs to make the tag's
 * message later (struct gw_tag_out over a struct df1_tag_state), without the
 * tag's configuration (the record's tag id finds it). Pure: no I/O, no
 * allocation.
 *
 * The blob, version 1, integers little-endian:
 *   u8 1 (version), u8 quality, u8 reason, u8 has_value, i16 the view's
 *   quality (-1: the state's), i32 last_error, u8 sts, u8 ext_sts,
 *   i64 last_good_wall_ms, i64 wall_ms (when it was read), u16 count, then
 *   count values: u8 kind (enum df1_value_kind) and INT16 2 bytes, INT32 4,
 *   FLOAT 4 (IEEE 754 single), BIT 1 (0 or 1), STRING u8 length and the
 *   bytes, TCR 6 (ctl, pre, acc); then u8 length and text of the view's
 *   reason and of its error (length 255: none, NULL).
 */
#ifndef DF1_TOOLS_GW_BUFFER_TAG_H
#define DF1_TOOLS_GW_BUFFER_TAG_H

#include <stddef.h>
#include <stdint.h>

#include "df1.h"
#include "df1gw/gw_format.h"

/* The largest blob: 1000 strings of 82 bytes with their texts. */
#define GW_BUFFER_TAG_MAX (32 + 1000 * (2 + DF1_STRING_MAX) + 2 * 256)

/* t's blob into buf (cap bytes): its length, or -1 when it does not fit
 * (or a text is over 254 bytes, cut at 254). */
int gw_buffer_tag_pack(const struct gw_tag_out *t, uint8_t *buf, size_t cap);

/* Where an unpacked blob goes: st (its config NULL, the caller sets it),
 * values (cap of them), out pointing at them, texts for the reason and error. */
struct gw_buffer_tag_out {
	struct df1_tag_state st;
	struct df1_value *values;
	size_t cap;
	struct gw_tag_out out;
	char reason[256], error[256];
};

/* Blob b of len bytes into o (o->values and o->cap set by the caller).
 * 0, or -1 when it is not a blob of version 1 (cut short, a kind unknown,
 * more values than cap). */
int gw_buffer_tag_unpack(const void *b, size_t len, struct gw_buffer_tag_out *o);

#endif
