/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_spb_codec - Sparkplug B payloads through protobuf-c (see gw_spb_codec.h;
 * the message is tools/df1gw/spb.proto).
 */
#include "df1gw/gw_spb_codec.h"

#include <stdlib.h>
#include <string.h>

#include "spb.pb-c.h"

typedef Df1spb__Payload Pb;
typedef Df1spb__Payload__Metric PbMetric;
typedef Df1spb__Payload__PropertySet PbProps;
typedef Df1spb__Payload__PropertyValue PbProp;

/* What one metric needs beside its message: its properties. */
struct enc_metric {
	PbMetric m;
	PbProps props;
	char *keys[2];
	PbProp vals[2];
	PbProp *valp[2];
};

void gw_spb_metric_init(struct gw_spb_metric *m)
{
	memset(m, 0, sizeof *m);
	m->quality = -1;
}

/* Quality (Int32) and Reason (String): the properties a host reads a tag's quality from. */
static void enc_props(struct enc_metric *e, const struct gw_spb_metric *s)
{
	size_t k = 0;

	if (s->quality < 0 && !s->reason)
		return;
	df1spb__payload__property_set__init(&e->props);
	if (s->quality >= 0) {
		df1spb__payload__property_value__init(&e->vals[k]);
		e->vals[k].has_type = true;
		e->vals[k].type = GW_SPB_INT32;
		e->vals[k].value_case = DF1SPB__PAYLOAD__PROPERTY_VALUE__VALUE_INT_VALUE;
		e->vals[k].int_value = (uint32_t)s->quality;
		e->keys[k] = (char *)"Quality";
		e->valp[k] = &e->vals[k];
		k++;
	}
	if (s->reason) {
		df1spb__payload__property_value__init(&e->vals[k]);
		e->vals[k].has_type = true;
		e->vals[k].type = GW_SPB_STRING;
		e->vals[k].value_case = DF1SPB__PAYLOAD__PROPERTY_VALUE__VALUE_STRING_VALUE;
		e->vals[k].string_value = (char *)s->reason;
		e->keys[k] = (char *)"Reason";
		e->valp[k] = &e->vals[k];
		k++;
	}
	e->props.n_keys = k;
	e->props.keys = e->keys;
	e->props.n_values = k;
	e->props.values = e->valp;
	e->m.properties = &e->props;
}

static void enc_value(PbMetric *m, const struct gw_spb_metric *s)
{
	switch (s->kind) {
	case GW_SPB_V_INT:
		m->value_case = DF1SPB__PAYLOAD__METRIC__VALUE_INT_VALUE;
		m->int_value = s->v.i;
		break;
	case GW_SPB_V_LONG:
		m->value_case = DF1SPB__PAYLOAD__METRIC__VALUE_LONG_VALUE;
		m->long_value = s->v.l;
		break;
	case GW_SPB_V_FLOAT:
		m->value_case = DF1SPB__PAYLOAD__METRIC__VALUE_FLOAT_VALUE;
		m->float_value = s->v.f;
		break;
	case GW_SPB_V_DOUBLE:
		m->value_case = DF1SPB__PAYLOAD__METRIC__VALUE_DOUBLE_VALUE;
		m->double_value = s->v.d;
		break;
	case GW_SPB_V_BOOL:
		m->value_case = DF1SPB__PAYLOAD__METRIC__VALUE_BOOLEAN_VALUE;
		m->boolean_value = s->v.b;
		break;
	case GW_SPB_V_STRING:
		m->value_case = DF1SPB__PAYLOAD__METRIC__VALUE_STRING_VALUE;
		m->string_value = (char *)(s->str ? s->str : "");
		break;
	case GW_SPB_V_BYTES:
		m->value_case = DF1SPB__PAYLOAD__METRIC__VALUE_BYTES_VALUE;
		m->bytes_value.data = (uint8_t *)s->bytes;
		m->bytes_value.len = s->nbytes;
		break;
	case GW_SPB_V_NONE:
		break;
	}
}

static void enc_metric(struct enc_metric *e, const struct gw_spb_metric *s)
{
	PbMetric *m = &e->m;

	df1spb__payload__metric__init(m);
	m->name = (char *)s->name;
	m->has_alias = s->has_alias;
	m->alias = s->alias;
	m->has_timestamp = s->timestamp != 0;
	m->timestamp = s->timestamp;
	m->has_datatype = true;
	m->datatype = s->datatype;
	m->has_is_historical = s->is_historical;
	m->is_historical = s->is_historical;
	m->has_is_null = s->is_null;
	m->is_null = s->is_null;
	if (!s->is_null)
		enc_value(m, s);
	enc_props(e, s);
}

static void buf_room(struct gw_buf *b, size_t need)
{
	char *p;

	if (b->oom || b->cap >= need)
		return;
	p = realloc(b->p, need);
	if (!p) {
		b->oom = true;
		return;
	}
	b->p = p;
	b->cap = need;
}

int gw_spb_encode(struct gw_buf *out, uint64_t timestamp, const struct gw_spb_metric *m, size_t n)
{
	struct enc_metric *e = n ? calloc(n, sizeof *e) : NULL;
	PbMetric **mp = n ? calloc(n, sizeof *mp) : NULL;
	Pb pb;
	size_t len;

	gw_buf_reset(out);
	if (n && (!e || !mp)) {
		free(e);
		free(mp);
		return -1;
	}
	df1spb__payload__init(&pb);
	pb.has_timestamp = timestamp != 0;
	pb.timestamp = timestamp;
	for (size_t i = 0; i < n; i++) {
		enc_metric(&e[i], &m[i]);
		mp[i] = &e[i].m;
	}
	pb.n_metrics = n;
	pb.metrics = mp;
	len = df1spb__payload__get_packed_size(&pb);
	buf_room(out, len + 12);        /* + the seq field, + the NUL gw_buf keeps */
	if (!out->oom) {
		out->len = df1spb__payload__pack(&pb, (uint8_t *)out->p);
		out->p[out->len] = '\0';
	}
	free(e);
	free(mp);
	return out->oom ? -1 : 0;
}

void gw_spb_append_seq(struct gw_buf *out, uint64_t seq)
{
	char v[11];
	size_t k = 0;

	v[k++] = 0x18;                  /* field 3, varint */
	do {
		uint8_t byte = seq & 0x7F;

		seq >>= 7;
		v[k++] = (char)(byte | (seq ? 0x80 : 0));
	} while (seq);
	gw_buf_add(out, v, k);
}

int gw_spb_decode(const void *p, size_t n, struct gw_spb_in *in)
{
	Pb *pb = df1spb__payload__unpack(NULL, n, p);

	memset(in, 0, sizeof *in);
	if (!pb)
		return -1;
	in->pb = pb;
	in->has_timestamp = pb->has_timestamp;
	in->timestamp = pb->timestamp;
	in->has_seq = pb->has_seq;
	in->seq = pb->seq;
	in->n = pb->n_metrics;
	return 0;
}

static void dec_value(const PbMetric *pm, struct gw_spb_metric *m)
{
	switch (pm->value_case) {
	case DF1SPB__PAYLOAD__METRIC__VALUE_INT_VALUE:
		m->kind = GW_SPB_V_INT;
		m->v.i = pm->int_value;
		break;
	case DF1SPB__PAYLOAD__METRIC__VALUE_LONG_VALUE:
		m->kind = GW_SPB_V_LONG;
		m->v.l = pm->long_value;
		break;
	case DF1SPB__PAYLOAD__METRIC__VALUE_FLOAT_VALUE:
		m->kind = GW_SPB_V_FLOAT;
		m->v.f = pm->float_value;
		break;
	case DF1SPB__PAYLOAD__METRIC__VALUE_DOUBLE_VALUE:
		m->kind = GW_SPB_V_DOUBLE;
		m->v.d = pm->double_value;
		break;
	case DF1SPB__PAYLOAD__METRIC__VALUE_BOOLEAN_VALUE:
		m->kind = GW_SPB_V_BOOL;
		m->v.b = pm->boolean_value;
		break;
	case DF1SPB__PAYLOAD__METRIC__VALUE_STRING_VALUE:
		m->kind = GW_SPB_V_STRING;
		m->str = pm->string_value;
		break;
	case DF1SPB__PAYLOAD__METRIC__VALUE_BYTES_VALUE:
		m->kind = GW_SPB_V_BYTES;
		m->bytes = pm->bytes_value.data;
		m->nbytes = pm->bytes_value.len;
		break;
	default:
		m->kind = GW_SPB_V_NONE;
		break;
	}
}

/* The Quality and Reason properties, when there. */
static void dec_props(const PbProps *ps, struct gw_spb_metric *m)
{
	for (size_t k = 0; ps && k < ps->n_keys && k < ps->n_values; k++) {
		const PbProp *v = ps->values[k];

		if (strcmp(ps->keys[k], "Quality") == 0 &&
		    v->value_case == DF1SPB__PAYLOAD__PROPERTY_VALUE__VALUE_INT_VALUE)
			m->quality = (int)v->int_value;
		else if (strcmp(ps->keys[k], "Reason") == 0 &&
		         v->value_case == DF1SPB__PAYLOAD__PROPERTY_VALUE__VALUE_STRING_VALUE)
			m->reason = v->string_value;
	}
}

void gw_spb_metric_at(const struct gw_spb_in *in, size_t i, struct gw_spb_metric *m)
{
	const Pb *pb = in->pb;
	const PbMetric *pm = pb->metrics[i];

	gw_spb_metric_init(m);
	m->name = pm->name;
	m->has_alias = pm->has_alias;
	m->alias = pm->alias;
	m->timestamp = pm->has_timestamp ? pm->timestamp : 0;
	m->datatype = pm->has_datatype ? pm->datatype : GW_SPB_UNKNOWN;
	m->is_historical = pm->has_is_historical && pm->is_historical;
	m->is_null = pm->has_is_null && pm->is_null;
	dec_value(pm, m);
	dec_props(pm->properties, m);
}

void gw_spb_in_free(struct gw_spb_in *in)
{
	if (in->pb)
		df1spb__payload__free_unpacked(in->pb, NULL);
	memset(in, 0, sizeof *in);
}

const char *gw_spb_type_name(uint32_t t)
{
	static const char *const names[] = {
		"Unknown", "Int8", "Int16", "Int32", "Int64", "UInt8", "UInt16", "UInt32", "UInt64", "Float",
		"Double", "Boolean", "String", "DateTime", "Text", "UUID", "DataSet", "Bytes", "File",
		"Template", "PropertySet", "PropertySetList", "Int8Array", "Int16Array", "Int32Array",
		"Int64Array", "UInt8Array", "UInt16Array", "UInt32Array", "UInt64Array", "FloatArray",
		"DoubleArray", "BooleanArray", "StringArray", "DateTimeArray",
	};

	return t < sizeof names / sizeof names[0] ? names[t] : "Unknown";
}
