/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_value - df1gw's payloads of a tag: its state as the JSON of
 * <prefix>/tag/<name>, and the JSON of a .../set message as the values of a
 * df1_tag_write(). Pure: df1.h's value helpers and gw_json only.
 *
 * Values by file type: integers (N B S I O A words, L, T/C/R words), floats
 * in shortest round-trip form (nan and inf as null), booleans for bits,
 * strings (ST; one byte per character, ISO 8859-1), objects of the members
 * of a whole timer, counter or control ({"EN":true,"TT":false,"DN":false,
 * "PRE":100,"ACC":42}); an array of them when Count > 1.
 */
#ifndef DF1_TOOLS_GW_VALUE_H
#define DF1_TOOLS_GW_VALUE_H

#include "df1.h"
#include "df1gw/gw_json.h"

/* What a tag's payload says beyond the library's state. */
struct gw_tag_view {
	const char *reason;     /* NULL: df1_reason_name() of the state's */
	int quality;            /* -1: the state's */
	const char *error;      /* text of the last error ("[2508] ERR_COMMAND_TIMEOUT: ..."), or NULL */
	bool with_ts;           /* false: leave "ts" out (the change key) */
};

/* One value of kind v->kind for file type t (T/C/R members by t's names). */
void gw_value_json(struct gw_buf *b, const struct df1_value *v, enum df1_file_type t);
/* {"value":...,"quality":"GOOD","reason":"none","ts":"2026-...Z","address":"N7:0",
 *  "station":1}, "error" after "reason" when view->error is set; "value" null
 * before the first read, an array when count > 1. Returns where ,"ts":...
 * went in b (len 0: left out): the rest is the change key. */
struct gw_span gw_tag_json(struct gw_buf *b, const struct df1_tag_state *st, const struct gw_tag_view *view);

/* The values a .../set payload v (without its {"value":..,"id":..} wrapper)
 * asks to write to tag c: a scalar (element 0) or, for Count > 1, an array of
 * 1..Count values from element 0. A T/C/R object's members not given keep
 * their value of cur (the tag's state, may be NULL: 0). Writes *n values to
 * out (cap >= c->count). Returns 0, or DF1_E_TYPE (wrong JSON type, a member
 * that does not exist), DF1_E_RANGE (does not fit the file type), with err
 * saying what. */
int gw_value_from_json(const struct gw_jv *v, const struct df1_tag_config *c,
                       const struct df1_tag_state *cur, struct df1_value *out, size_t cap,
                       size_t *n, char *err, size_t errcap);

#endif
