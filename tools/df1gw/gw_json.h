/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_json - df1gw's JSON (RFC 8259): a growing text buffer with the writers
 * the payloads need, and a strict small parser for what arrives on
 * <prefix>/tag/<name>/set. Pure: no I/O, no clock; uses only the C library.
 */
#ifndef DF1_TOOLS_GW_JSON_H
#define DF1_TOOLS_GW_JSON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* A text buffer that grows; oom is set (and the text left as it was) when it
 * cannot. p is always NUL-terminated once anything was added. */
struct gw_buf {
	char *p;
	size_t len, cap;
	bool oom;
};

void gw_buf_init(struct gw_buf *b);
void gw_buf_free(struct gw_buf *b);
void gw_buf_reset(struct gw_buf *b);           /* empty, keeps the memory */
void gw_buf_add(struct gw_buf *b, const char *s, size_t n);
void gw_buf_puts(struct gw_buf *b, const char *s);
void gw_buf_printf(struct gw_buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Where a piece went in a buffer: [at, at + len). */
struct gw_span {
	size_t at, len;
};

/* A JSON string of UTF-8 text: quotes, backslash and control characters
 * escaped; a byte that is not part of valid UTF-8 as \u00XX. */
void gw_json_text(struct gw_buf *b, const char *s, size_t n);
/* A JSON string of PLC bytes: every byte is one character (ISO 8859-1), bytes
 * 0x80-0xFF and control characters as \u00XX, so gw_json's parser and
 * gw_jv_latin1() give the same bytes back. */
void gw_json_bytes(struct gw_buf *b, const uint8_t *s, size_t n);
/* s[0..n) is valid UTF-8 (as MQTT topics must be). */
bool gw_utf8_valid(const char *s, size_t n);
/* "2026-12-01T23:15:00.123Z" for ms since the epoch (UTC). cap >= 25. */
void gw_rfc3339(int64_t wall_ms, char *out, size_t cap);

/* ---- parsing ---- */

enum gw_jtype { GW_JNULL, GW_JBOOL, GW_JNUMBER, GW_JSTRING, GW_JARRAY, GW_JOBJECT };

struct gw_jv {
	enum gw_jtype type;
	bool b;                  /* BOOL */
	char *text;              /* NUMBER: its text as written; STRING: UTF-8, NUL-terminated */
	size_t len;              /* STRING: bytes of text (it may hold \u0000) */
	size_t n;                /* ARRAY, OBJECT: items */
	struct gw_jv **items;    /* ARRAY, OBJECT: values */
	char **keys;             /* OBJECT: member names (UTF-8) */
	size_t start, end;       /* where it is in the input: [start, end) */
};

#define GW_JSON_MAX_DEPTH 16
#define GW_JSON_MAX_BYTES 65536

/* Parse exactly one JSON value (blanks around it allowed) from in[0..n).
 * Strict: RFC 8259 grammar, valid UTF-8, no duplicate member names, depth and
 * size limits. Returns the tree (free with gw_jv_free) or NULL with err
 * ("at byte 7: expected ',' or '}'"). */
struct gw_jv *gw_json_parse(const char *in, size_t n, char *err, size_t errcap);
void gw_jv_free(struct gw_jv *v);
/* The member of an object named key, or NULL. */
const struct gw_jv *gw_jv_get(const struct gw_jv *obj, const char *key);
/* A string's characters as bytes 0-255 (the inverse of gw_json_bytes) into
 * out; false if one is above U+00FF or it does not fit in cap. */
bool gw_jv_latin1(const struct gw_jv *s, uint8_t *out, size_t cap, size_t *len);

#endif
