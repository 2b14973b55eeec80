/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_write - the write side of df1gw, pure parts: a .../set payload taken
 * apart (a bare JSON value, or {"value": ..., "id": ..., "timeout_ms": ...}), the ring of write
 * ids seen lately (at most once per id), and the result payload
 * {"id":..,"ok":..,"error":..,"unconfirmed":..}.
 */
#ifndef DF1_TOOLS_GW_WRITE_H
#define DF1_TOOLS_GW_WRITE_H

#include <stdbool.h>
#include <stddef.h>

#include "df1gw/gw_json.h"

#define GW_ID_MAX 128            /* bytes of an id's JSON text */
#define GW_IDS_DEFAULT 1024      /* ids remembered */

/* A .../set payload: root owns the tree; value points into it; id is the
 * id's JSON text as written ("\"a1\"", "17"), "" when there is none. */
struct gw_set {
	struct gw_jv *root;
	const struct gw_jv *value;
	char id[GW_ID_MAX + 1];
	long timeout_ms;             /* "timeout_ms": this write's --write-timeout; -1: none given */
};

#define GW_TIMEOUT_MS_MAX 86400000L  /* "timeout_ms" at most (a day) */

/* Parse payload into *s. Returns 0, or -1 with err (bad JSON, an id that is
 * not a string or a number or is too long, a timeout_ms that is not an
 * integer 1..GW_TIMEOUT_MS_MAX, members other than value, id and timeout_ms
 * beside "value"). gw_set_free() in both cases. */
int gw_set_parse(const char *payload, size_t n, struct gw_set *s, char *err, size_t errcap);
void gw_set_free(struct gw_set *s);

/* The ids seen lately, a ring of cap entries: the oldest is forgotten first. */
struct gw_ids {
	char **ring;
	size_t cap, next, n;
};
int gw_ids_init(struct gw_ids *ids, size_t cap);      /* 0 or -1 (no memory) */
void gw_ids_free(struct gw_ids *ids);
bool gw_ids_seen(const struct gw_ids *ids, const char *id);
/* Remember id (a copy); 0 or -1 (no memory: not remembered). */
int gw_ids_add(struct gw_ids *ids, const char *id);

/* {"id":ID|null,"ok":true|false,"error":TEXT|null,"unconfirmed":true|false} */
void gw_result_json(struct gw_buf *b, const char *id, bool ok, const char *error, bool unconfirmed);
/* A failed write's DF1_E_* code: may the PLC have executed it anyway? True
 * when the command may have left and no answer said what became of it
 * (timeouts, lost replies, a line that went away); false for a PLC's refusal,
 * a NAK, or a write that was never sent. */
bool gw_write_unconfirmed(int err);

#endif
