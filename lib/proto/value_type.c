/* SPDX-License-Identifier: MPL-2.0 */
/*
 * value_type.c - the mapping file's Type column: names, fit, conversions
 * (value_type.h).
 */
#include "proto/value_type.h"

#include <ctype.h>
#include <string.h>
#include <strings.h>

static const struct {
	const char *name;
	enum df1_value_kind kind;
	enum df1_file_type tcr;         /* TCR: the file type it names */
} vtypes[] = {
	{ "INT", DF1_VAL_INT16, DF1_FT_N },
	{ "DINT", DF1_VAL_INT32, DF1_FT_N },
	{ "LONG", DF1_VAL_INT32, DF1_FT_N },
	{ "REAL", DF1_VAL_FLOAT, DF1_FT_N },
	{ "FLOAT", DF1_VAL_FLOAT, DF1_FT_N },
	{ "BOOL", DF1_VAL_BIT, DF1_FT_N },
	{ "STRING", DF1_VAL_STRING, DF1_FT_N },
	{ "TIMER", DF1_VAL_TCR, DF1_FT_T },
	{ "COUNTER", DF1_VAL_TCR, DF1_FT_C },
	{ "CONTROL", DF1_VAL_TCR, DF1_FT_R },
};

/* What does fit the address, for the message of a Type that does not. */
static const char *vtype_hint(const struct df1_addr *a, enum df1_value_kind ak)
{
	switch (ak) {
	case DF1_VAL_BIT: return "a bit is BOOL";
	case DF1_VAL_INT32: return "an L element is DINT (LONG)";
	case DF1_VAL_FLOAT: return "an F element is REAL (FLOAT)";
	case DF1_VAL_STRING: return "an ST element is STRING";
	case DF1_VAL_TCR:
		return a->type == DF1_FT_T ? "a whole timer is TIMER; its words are INT (T4:0.ACC)"
		     : a->type == DF1_FT_C ? "a whole counter is COUNTER; its words are INT (C5:0.ACC)"
		                           : "a whole control is CONTROL; its words are INT (R6:0.POS)";
	default: return "a word is INT, DINT or REAL (a bit of it is BOOL)";
	}
}

int value_type_check(const char *type, const struct df1_addr *a, enum df1_value_kind *kind, const char **why)
{
	enum df1_value_kind ak = df1_addr_value_kind(a);
	size_t n;
	size_t i;

	*why = NULL;
	*kind = ak;
	if (!type)
		return 0;
	while (isspace((unsigned char)*type))
		type++;
	n = strlen(type);
	while (n && isspace((unsigned char)type[n - 1]))
		n--;
	if (n == 0)
		return 0;
	for (i = 0; i < sizeof vtypes / sizeof vtypes[0]; i++)
		if (strlen(vtypes[i].name) == n && strncasecmp(vtypes[i].name, type, n) == 0)
			break;
	if (i == sizeof vtypes / sizeof vtypes[0]) {
		*why = "not a Type: " VALUE_TYPE_NAMES;
		return DF1_E_INVAL;
	}
	*kind = vtypes[i].kind;
	if (vtypes[i].kind == ak && (ak != DF1_VAL_TCR || vtypes[i].tcr == a->type))
		return 0;
	if (ak == DF1_VAL_INT16 && (vtypes[i].kind == DF1_VAL_INT32 || vtypes[i].kind == DF1_VAL_FLOAT))
		return 0;       /* every 16-bit value is a DINT and a REAL exactly */
	*why = vtype_hint(a, ak);
	return DF1_E_TYPE;
}

void value_type_widen(struct df1_value *v, enum df1_value_kind kind)
{
	if (v->kind != DF1_VAL_INT16 || kind == DF1_VAL_INT16)
		return;
	if (kind == DF1_VAL_INT32) {
		int32_t x = v->v.i16;

		v->v.i32 = x;
		v->kind = DF1_VAL_INT32;
	} else if (kind == DF1_VAL_FLOAT) {
		float f = (float)v->v.i16;

		v->v.f = f;
		v->kind = DF1_VAL_FLOAT;
	}
}

int value_type_narrow(struct df1_value *v, enum df1_value_kind ak)
{
	int16_t x;

	if (v->kind == ak)
		return 0;
	if (ak != DF1_VAL_INT16)
		return DF1_E_TYPE;
	if (v->kind == DF1_VAL_INT32) {
		if (v->v.i32 < INT16_MIN || v->v.i32 > INT16_MAX)
			return DF1_E_RANGE;
		x = (int16_t)v->v.i32;
	} else if (v->kind == DF1_VAL_FLOAT) {
		/* NaN fails both comparisons */
		if (!(v->v.f >= (float)INT16_MIN && v->v.f <= (float)INT16_MAX) || (float)(int)v->v.f != v->v.f)
			return DF1_E_RANGE;
		x = (int16_t)v->v.f;
	} else {
		return DF1_E_TYPE;
	}
	v->v.i16 = x;
	v->kind = DF1_VAL_INT16;
	return 0;
}
