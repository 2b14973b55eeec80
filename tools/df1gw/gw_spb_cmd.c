/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_spb_cmd - a Sparkplug command's metric (DCMD) back into the values of a
 * df1_tag_write(): which tag and member it names (by name or by the alias of
 * gw_spb_metrics.c), its value checked against the tag's type and range
 * (declared in gw_spb_metrics.h). Pure.
 */
#include "df1gw/gw_spb_metrics.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bool gw_spb_metric_target(const struct gw_spb_metric *m, char *tag, size_t cap, const char **member,
                          int *alias_id, unsigned *alias_member)
{
	*member = "";
	*alias_id = -1;
	*alias_member = 0;
	if (m->name && *m->name) {
		size_t n = strcspn(m->name, "/");

		if (n == 0 || n >= cap)
			return false;
		memcpy(tag, m->name, n);
		tag[n] = '\0';
		*member = m->name[n] ? m->name + n + 1 : "";
		return true;
	}
	if (!m->has_alias || (m->alias >> 16) == 0 || (m->alias >> 16) > 0x7FFFFFFF)
		return false;
	tag[0] = '\0';
	*alias_id = (int)((m->alias >> 16) - 1);
	*alias_member = (unsigned)(m->alias & 0xFFFF);
	return true;
}

/* The metric's number, whatever member of the value holds it. */
static bool metric_number(const struct gw_spb_metric *m, double *x, bool *integral)
{
	*integral = true;
	switch (m->kind) {
	case GW_SPB_V_INT:
		/* Int8-32 in two's complement of their width; unsigned as they are */
		if (m->datatype == GW_SPB_INT16)
			*x = (int16_t)(uint16_t)m->v.i;
		else if (m->datatype == GW_SPB_INT8)
			*x = (int8_t)(uint8_t)m->v.i;
		else if (m->datatype == GW_SPB_INT32)
			*x = (int32_t)m->v.i;
		else
			*x = m->v.i;
		return true;
	case GW_SPB_V_LONG:
		*x = m->datatype == GW_SPB_INT64 ? (double)(int64_t)m->v.l : (double)m->v.l;
		return true;
	case GW_SPB_V_FLOAT: *x = m->v.f; *integral = false; return true;
	case GW_SPB_V_DOUBLE: *x = m->v.d; *integral = false; return true;
	case GW_SPB_V_BOOL: *x = m->v.b; return true;
	default: return false;
	}
}

/* A number for an integer of [lo, hi]. */
static int int_in(const struct gw_spb_metric *m, double lo, double hi, long *out, char *err, size_t errcap)
{
	double x;
	bool integral;

	if (!metric_number(m, &x, &integral)) {
		snprintf(err, errcap, "a number is needed (datatype %s)", gw_spb_type_name(m->datatype));
		return DF1_E_TYPE;
	}
	if (!integral && x != floor(x)) {
		snprintf(err, errcap, "%g is not an integer", x);
		return DF1_E_TYPE;
	}
	if (x < lo || x > hi) {
		snprintf(err, errcap, "%.0f is out of range %.0f..%.0f", x, lo, hi);
		return DF1_E_RANGE;
	}
	*out = (long)x;
	return 0;
}

/* Metric m as one value of kind k. */
static int scalar_from(const struct gw_spb_metric *m, enum df1_value_kind k, struct df1_value *v, char *err,
                       size_t errcap)
{
	double x;
	bool integral;
	long i;
	int r;

	memset(v, 0, sizeof *v);
	v->kind = k;
	switch (k) {
	case DF1_VAL_INT16:
		if ((r = int_in(m, -32768, 32767, &i, err, errcap)) < 0)
			return r;
		v->v.i16 = (int16_t)i;
		return 0;
	case DF1_VAL_INT32:
		if ((r = int_in(m, -2147483648.0, 2147483647.0, &i, err, errcap)) < 0)
			return r;
		v->v.i32 = (int32_t)i;
		return 0;
	case DF1_VAL_BIT:
		if ((r = int_in(m, 0, 1, &i, err, errcap)) < 0)
			return r;
		v->v.bit = i != 0;
		return 0;
	case DF1_VAL_FLOAT:
		if (!metric_number(m, &x, &integral)) {
			snprintf(err, errcap, "a number is needed (datatype %s)", gw_spb_type_name(m->datatype));
			return DF1_E_TYPE;
		}
		/* NaN, an infinity or beyond a float's range: refused as /set
		 * refuses them (gw_value.c through df1_value_parse) */
		if (!isfinite(x) || fabs(x) > FLT_MAX) {
			snprintf(err, errcap, "%g does not fit a float", x);
			return DF1_E_RANGE;
		}
		v->v.f = (float)x;
		return 0;
	case DF1_VAL_STRING:
		if (m->kind != GW_SPB_V_STRING || !m->str) {
			snprintf(err, errcap, "a String is needed");
			return DF1_E_TYPE;
		}
		if (strlen(m->str) > DF1_STRING_MAX) {
			snprintf(err, errcap, "longer than %d bytes", DF1_STRING_MAX);
			return DF1_E_RANGE;
		}
		v->v.str.len = (uint16_t)strlen(m->str);
		memcpy(v->v.str.text, m->str, v->v.str.len);
		return 0;
	default:
		snprintf(err, errcap, "a timer, counter or control is written by its members (Name/PRE)");
		return DF1_E_TYPE;
	}
}

/* An array metric (numbers little-endian, booleans count + bits) as up to cap values. */
static int array_from(const struct gw_spb_metric *m, enum df1_value_kind k, size_t count, struct df1_value *out,
                      size_t *n, char *err, size_t errcap)
{
	const uint8_t *b = m->bytes;
	size_t size = k == DF1_VAL_INT16 ? 2 : 4, want;

	if (m->kind != GW_SPB_V_BYTES || k == DF1_VAL_STRING) {
		snprintf(err, errcap, "an array of %zu elements is written with its array datatype", count);
		return DF1_E_TYPE;
	}
	if (k == DF1_VAL_BIT) {
		if (m->nbytes < 4)
			goto bad;
		want = (size_t)b[0] | (size_t)b[1] << 8 | (size_t)b[2] << 16 | (size_t)b[3] << 24;
		if (m->nbytes < 4 + (want + 7) / 8)
			goto bad;
	} else {
		if (m->nbytes % size)
			goto bad;
		want = m->nbytes / size;
	}
	if (want == 0 || want > count) {
		snprintf(err, errcap, "%zu elements for a tag of %zu", want, count);
		return DF1_E_RANGE;
	}
	for (size_t i = 0; i < want; i++) {
		memset(&out[i], 0, sizeof out[i]);
		out[i].kind = k;
		if (k == DF1_VAL_INT16)
			out[i].v.i16 = (int16_t)(b[2 * i] | b[2 * i + 1] << 8);
		else if (k == DF1_VAL_INT32)
			out[i].v.i32 = (int32_t)((uint32_t)b[4 * i] | (uint32_t)b[4 * i + 1] << 8 |
			                         (uint32_t)b[4 * i + 2] << 16 | (uint32_t)b[4 * i + 3] << 24);
		else if (k == DF1_VAL_FLOAT) {
			/* the IEEE 754 bits, little-endian like the integers (not the host's order) */
			uint32_t u = (uint32_t)b[4 * i] | (uint32_t)b[4 * i + 1] << 8 |
			             (uint32_t)b[4 * i + 2] << 16 | (uint32_t)b[4 * i + 3] << 24;

			memcpy(&out[i].v.f, &u, 4);
		} else
			out[i].v.bit = (b[4 + i / 8] >> (7 - i % 8)) & 1;
		if (k == DF1_VAL_FLOAT && !isfinite(out[i].v.f)) {
			snprintf(err, errcap, "element %zu is not a finite float", i);
			return DF1_E_RANGE;
		}
	}
	*n = want;
	return 0;
bad:
	snprintf(err, errcap, "a %s of %zu bytes is not whole", gw_spb_type_name(m->datatype), m->nbytes);
	return DF1_E_TYPE;
}

/* Member text ("ACC", "3/DN") or alias member number into element and member name. */
static const char *tcr_target(enum df1_file_type t, int count, const char *member, unsigned am, size_t *elem)
{
	static const char *const names[3][11] = {
		{ "EN", "TT", "DN", "PRE", "ACC", NULL },
		{ "CU", "CD", "DN", "OV", "UN", "UA", "PRE", "ACC", NULL },
		{ "EN", "EU", "DN", "EM", "ER", "UL", "IN", "FD", "LEN", "POS", NULL },
	};
	const char *const *mem = names[t == DF1_FT_T ? 0 : t == DF1_FT_C ? 1 : 2];
	char *end;

	*elem = 0;
	if (!*member) {
		unsigned j;

		if (am == 0)
			return NULL;
		*elem = (am - 1) / 16;
		j = (am - 1) % 16;
		for (unsigned i = 0; mem[i]; i++)
			if (i == j)
				return mem[i];
		return NULL;
	}
	if (count > 1) {
		*elem = strtoul(member, &end, 10);
		if (end == member || *end != '/')
			return NULL;
		member = end + 1;
	}
	for (unsigned i = 0; mem[i]; i++)
		if (strcmp(mem[i], member) == 0)
			return mem[i];
	return NULL;
}

/* A member of element elem of a T/C/R tag: the current elements up to it, that one changed. */
static int tcr_from(const struct gw_spb_metric *m, const char *member, unsigned am, const struct df1_tag_config *c,
                    const struct df1_tag_state *cur, struct df1_value *out, size_t cap, size_t *n, char *err,
                    size_t errcap)
{
	size_t elem;
	const char *name = tcr_target(c->addr.type, c->count, member, am, &elem);
	struct df1_value one;
	int bit, r;

	if (!name || elem >= (size_t)c->count || elem >= cap) {
		snprintf(err, errcap, "no member \"%s\" of %s", *member ? member : "(alias)", c->name);
		return DF1_E_INVAL;
	}
	if (!cur || !cur->has_value || cur->count <= elem) {
		snprintf(err, errcap, "%s not read yet: a member is written into the element's current value", c->name);
		return DF1_E_INVAL;
	}
	memcpy(out, cur->values, (elem + 1) * sizeof *out);
	bit = df1_tcr_bit(c->addr.type, name);
	if ((r = scalar_from(m, bit >= 0 ? DF1_VAL_BIT : DF1_VAL_INT16, &one, err, errcap)) < 0)
		return r;
	if (bit >= 0)
		out[elem].v.tcr.ctl = (uint16_t)(one.v.bit ? out[elem].v.tcr.ctl | 1u << bit
		                                           : out[elem].v.tcr.ctl & ~(1u << bit));
	else if (strcmp(name, "PRE") == 0 || strcmp(name, "LEN") == 0)
		out[elem].v.tcr.pre = one.v.i16;
	else
		out[elem].v.tcr.acc = one.v.i16;
	*n = elem + 1;
	return 0;
}

int gw_spb_write_values(const struct gw_spb_metric *m, const char *member, unsigned alias_member,
                        const struct df1_tag_config *c, const struct df1_tag_state *cur,
                        struct df1_value *out, size_t cap, size_t *n, char *err, size_t errcap)
{
	enum df1_value_kind k = df1_addr_value_kind(&c->addr);
	int r;

	*n = 0;
	if (m->is_null) {
		snprintf(err, errcap, "a null value writes nothing");
		return DF1_E_TYPE;
	}
	if (k == DF1_VAL_TCR)
		return tcr_from(m, member, alias_member, c, cur, out, cap, n, err, errcap);
	if (*member || alias_member) {
		snprintf(err, errcap, "%s has no members", c->name);
		return DF1_E_INVAL;
	}
	if (c->count > 1)
		return array_from(m, k, (size_t)c->count < cap ? (size_t)c->count : cap, out, n, err, errcap);
	if ((r = scalar_from(m, k, &out[0], err, errcap)) < 0)
		return r;
	*n = 1;
	return 0;
}
