/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_spb_codec - Sparkplug B payloads (tools/df1gw/spb.proto, the protobuf
 * message of the Sparkplug 3.0 specification) in df1gw's own terms: metrics
 * encoded into a gw_buf, a received payload decoded into metrics, the
 * datatype codes, the seq field appended at publication. The only file that
 * sees protobuf-c's generated code. Pure: no I/O, no clock.
 */
#ifndef DF1_TOOLS_GW_SPB_CODEC_H
#define DF1_TOOLS_GW_SPB_CODEC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1gw/gw_json.h"

/* Sparkplug datatypes (the specification's DataType enumeration). */
enum gw_spb_type {
	GW_SPB_UNKNOWN = 0, GW_SPB_INT8 = 1, GW_SPB_INT16 = 2, GW_SPB_INT32 = 3, GW_SPB_INT64 = 4,
	GW_SPB_UINT8 = 5, GW_SPB_UINT16 = 6, GW_SPB_UINT32 = 7, GW_SPB_UINT64 = 8, GW_SPB_FLOAT = 9,
	GW_SPB_DOUBLE = 10, GW_SPB_BOOLEAN = 11, GW_SPB_STRING = 12, GW_SPB_DATETIME = 13, GW_SPB_TEXT = 14,
	GW_SPB_BYTES = 17,
	GW_SPB_INT8_ARRAY = 22, GW_SPB_INT16_ARRAY = 23, GW_SPB_INT32_ARRAY = 24, GW_SPB_INT64_ARRAY = 25,
	GW_SPB_UINT8_ARRAY = 26, GW_SPB_UINT16_ARRAY = 27, GW_SPB_UINT32_ARRAY = 28, GW_SPB_UINT64_ARRAY = 29,
	GW_SPB_FLOAT_ARRAY = 30, GW_SPB_DOUBLE_ARRAY = 31, GW_SPB_BOOLEAN_ARRAY = 32,
	GW_SPB_STRING_ARRAY = 33, GW_SPB_DATETIME_ARRAY = 34,
};

/* Which member of a metric's value is set. */
enum gw_spb_kind { GW_SPB_V_NONE, GW_SPB_V_INT, GW_SPB_V_LONG, GW_SPB_V_FLOAT, GW_SPB_V_DOUBLE,
	GW_SPB_V_BOOL, GW_SPB_V_STRING, GW_SPB_V_BYTES };

/* One metric. Encoding: the strings and bytes are the caller's; a name NULL
 * is left out (aliases only), has_alias adds the alias; timestamp 0 is left
 * out. has_quality adds the property "Quality" (Int32), reason (not NULL)
 * the property "Reason" (String): Ignition's way of a tag's quality.
 * Decoding: the pointers point into the decoded payload. */
struct gw_spb_metric {
	const char *name;
	bool has_alias;
	uint64_t alias;
	uint64_t timestamp;
	uint32_t datatype;            /* enum gw_spb_type */
	bool is_historical;
	bool is_null;
	enum gw_spb_kind kind;
	union {
		uint32_t i;           /* Int8-32, UInt8-32: two's complement in the type's width */
		uint64_t l;           /* Int64, UInt64, DateTime */
		float f;
		double d;
		bool b;
	} v;
	const char *str;
	const uint8_t *bytes;
	size_t nbytes;
	bool has_quality;
	int32_t quality;              /* gw_spb_metrics.h GW_SPB_Q_* */
	const char *reason;           /* NULL: none */
	/* encoding only: more properties, Strings (the line's settings) */
	const char *const *prop_keys;
	const char *const *prop_vals;
	size_t nprops;                /* at most GW_SPB_PROPS_MAX */
};

#define GW_SPB_PROPS_MAX 8

/* A metric with nothing set. */
void gw_spb_metric_init(struct gw_spb_metric *m);

/* The payload {timestamp, metrics} (no seq: gw_spb_append_seq adds it) into
 * out, reset first. 0, or -1 when out of memory. */
int gw_spb_encode(struct gw_buf *out, uint64_t timestamp, const struct gw_spb_metric *m, size_t n);
/* The seq field at the end of an encoded payload (protobuf fields may come
 * in any order). */
void gw_spb_append_seq(struct gw_buf *out, uint64_t seq);

/* A decoded payload. */
struct gw_spb_in {
	void *pb;                     /* protobuf-c's message */
	bool has_timestamp;
	uint64_t timestamp;
	bool has_seq;
	uint64_t seq;
	size_t n;                     /* metrics */
};

/* p[0..n) decoded into *in. 0, or -1 (not a Sparkplug payload). */
int gw_spb_decode(const void *p, size_t n, struct gw_spb_in *in);
/* Metric i of in into *m (pointing into in). */
void gw_spb_metric_at(const struct gw_spb_in *in, size_t i, struct gw_spb_metric *m);
void gw_spb_in_free(struct gw_spb_in *in);

/* The datatype's name as the specification writes it ("Int16"), or "Unknown". */
const char *gw_spb_type_name(uint32_t t);

#endif
