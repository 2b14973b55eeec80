/* SPDX-License-Identifier: MPL-2.0 */
/*
 * valuefmt.c - values as text for people and scripts: df1_value_format,
 * df1_value_parse, df1_tcr_bit, df1_addr_value_kind (public, df1.h).
 *
 * Text forms (df1read prints them, df1write reads them):
 *   INT16, INT32  signed decimal ("-32768"); parse also takes 0x hex, as the
 *                 raw bit pattern (0xFFFF into N is -1)
 *   FLOAT         the shortest text that reads back to the same float, laid out
 *                 like %g with precision 9: "0.1", "1.5", "100", "1e-45",
 *                 "3.4028235e+38"; "inf", "-inf", "nan". Parse takes any finite
 *                 float and +-inf (a PLC can hold them, and format prints them);
 *                 nan is rejected (DF1_E_TYPE), values beyond the float range are
 *                 DF1_E_RANGE, values below the smallest subnormal round to 0.
 *   BIT           "0" or "1"
 *   STRING        the characters as they are (no quoting, no trimming)
 *   TCR           the status bits by name, high bit first, then the two words:
 *                   T  "EN=1 TT=0 DN=1 PRE=100 ACC=42"
 *                   C  "CU=1 CD=0 DN=0 OV=0 UN=0 UA=0 PRE=10 ACC=3"
 *                   R  "EN=0 EU=0 DN=0 EM=0 ER=0 UL=0 IN=0 FD=0 LEN=8 POS=2"
 *                 and " CTL=0xWORD" after them when a bit without a name is set;
 *                 other file types: "CTL=0x8000 PRE=1 ACC=2". Parse takes the
 *                 same NAME=VALUE items in any order, separated by spaces or
 *                 commas, plus CTL=word; names not given are 0.
 * Numbers use '.' as written by the C locale; a program that sets LC_NUMERIC
 * to another locale gets that locale's strtof().
 */
#include "df1.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

struct bit_name {
	const char *name;
	int bit;
};

/* RM001 p.29-30 (T, C); R from common use, doc/PROTOCOL.md 5 [UNCERTAIN] */
static const struct bit_name t_bits[] = { { "EN", 15 }, { "TT", 14 }, { "DN", 13 }, { NULL, 0 } };
static const struct bit_name c_bits[] = {
	{ "CU", 15 }, { "CD", 14 }, { "DN", 13 }, { "OV", 12 }, { "UN", 11 }, { "UA", 10 }, { NULL, 0 }
};
static const struct bit_name r_bits[] = {
	{ "EN", 15 }, { "EU", 14 }, { "DN", 13 }, { "EM", 12 }, { "ER", 11 }, { "UL", 10 },
	{ "IN", 9 }, { "FD", 8 }, { NULL, 0 }
};

static const struct bit_name *valuefmt_tcr_bits(enum df1_file_type t)
{
	switch (t) {
	case DF1_FT_T: return t_bits;
	case DF1_FT_C: return c_bits;
	case DF1_FT_R: return r_bits;
	default: return NULL;
	}
}

/* Word 1 and 2 names: PRE/ACC for timers and counters, LEN/POS for control. */
static void valuefmt_tcr_word_names(enum df1_file_type t, const char **w1, const char **w2)
{
	*w1 = t == DF1_FT_R ? "LEN" : "PRE";
	*w2 = t == DF1_FT_R ? "POS" : "ACC";
}

int df1_tcr_bit(enum df1_file_type t, const char *name)
{
	const struct bit_name *b = valuefmt_tcr_bits(t);

	if (!b || !name)
		return -1;
	for (; b->name; b++)
		if (strcasecmp(b->name, name) == 0)
			return b->bit;
	return -1;
}

enum df1_value_kind df1_addr_value_kind(const struct df1_addr *a)
{
	if (!a)
		return DF1_VAL_INT16;
	if (a->bit != DF1_ADDR_NONE)
		return DF1_VAL_BIT;
	switch (a->type) {
	case DF1_FT_L:
		return DF1_VAL_INT32;
	case DF1_FT_F:
		return DF1_VAL_FLOAT;
	case DF1_FT_ST:
		return DF1_VAL_STRING;
	case DF1_FT_T: case DF1_FT_C: case DF1_FT_R:
		return a->sub == DF1_ADDR_NONE ? DF1_VAL_TCR : DF1_VAL_INT16;
	default:
		return DF1_VAL_INT16;   /* O I S B N A words, and addresses of unknown type */
	}
}

/* ------------------------------------------------------------------------
 * Formatting
 * ------------------------------------------------------------------------ */

/* Copy text of length len into buf: the length, or DF1_E_NOSPACE. */
static int valuefmt_emit(char *buf, size_t cap, const char *text, size_t len)
{
	if (len >= cap)
		return DF1_E_NOSPACE;
	memcpy(buf, text, len);
	buf[len] = '\0';
	return (int)len;
}

static bool valuefmt_same_float(float a, float b)
{
	return memcmp(&a, &b, sizeof a) == 0;
}

/* Shortest round-trip digits: the fewest significant digits p (1..9; 9 always
 * suffices for binary32) whose "%.{p-1}e" text strtof reads back to f exactly.
 * Then lay them out like %g (fixed for exponents -4..8) without trailing zeros. */
static int valuefmt_format_float(float f, char *out, size_t cap)
{
	char sci[32], digits[16];
	const char *p;
	int nd = 0, exp10, len = 0;
	bool neg;

	if (isnan(f))
		return snprintf(out, cap, "nan");
	if (isinf(f))
		return snprintf(out, cap, "%s", f < 0 ? "-inf" : "inf");
	for (int prec = 1; prec <= 9; prec++) {
		snprintf(sci, sizeof sci, "%.*e", prec - 1, (double)f);
		if (valuefmt_same_float(strtof(sci, NULL), f))
			break;
	}
	/* sci is "[-]d[.ddd]e[+-]XX"; the point may be a locale's character */
	p = sci;
	neg = *p == '-';
	if (neg)
		p++;
	for (; *p && *p != 'e'; p++)
		if (isdigit((unsigned char)*p) && nd < (int)sizeof digits - 1)
			digits[nd++] = *p;
	exp10 = *p == 'e' ? atoi(p + 1) : 0;
	while (nd > 1 && digits[nd - 1] == '0')
		nd--;
	digits[nd] = '\0';

	if (neg)
		out[len++] = '-';
	if (exp10 < -4 || exp10 >= 9) {
		out[len++] = digits[0];
		if (nd > 1) {
			out[len++] = '.';
			memcpy(out + len, digits + 1, (size_t)nd - 1);
			len += nd - 1;
		}
		len += snprintf(out + len, cap - (size_t)len, "e%c%02d", exp10 < 0 ? '-' : '+',
		                exp10 < 0 ? -exp10 : exp10);
	} else if (exp10 < 0) {
		out[len++] = '0';
		out[len++] = '.';
		for (int i = 0; i < -exp10 - 1; i++)
			out[len++] = '0';
		memcpy(out + len, digits, (size_t)nd);
		len += nd;
	} else {
		for (int i = 0; i <= exp10; i++)
			out[len++] = i < nd ? digits[i] : '0';
		if (nd > exp10 + 1) {
			out[len++] = '.';
			memcpy(out + len, digits + exp10 + 1, (size_t)(nd - exp10 - 1));
			len += nd - exp10 - 1;
		}
	}
	out[len] = '\0';
	return len;
}

static int valuefmt_format_tcr(const struct df1_tcr *x, enum df1_file_type t, char *out, size_t cap)
{
	const struct bit_name *b = valuefmt_tcr_bits(t);
	const char *w1, *w2;
	unsigned named = 0;
	int len = 0;

	if (!b)
		return snprintf(out, cap, "CTL=0x%04X PRE=%d ACC=%d", (unsigned)x->ctl, x->pre, x->acc);
	for (; b->name; b++) {
		len += snprintf(out + len, cap - (size_t)len, "%s=%d ", b->name, (x->ctl >> b->bit) & 1);
		named |= 1u << b->bit;
	}
	valuefmt_tcr_word_names(t, &w1, &w2);
	len += snprintf(out + len, cap - (size_t)len, "%s=%d %s=%d", w1, x->pre, w2, x->acc);
	/* bits without a name would be lost when the text is parsed back */
	if (x->ctl & ~named)
		len += snprintf(out + len, cap - (size_t)len, " CTL=0x%04X", (unsigned)x->ctl);
	return len;
}

int df1_value_format(const struct df1_value *v, enum df1_file_type t, char *buf, size_t cap)
{
	char tmp[160];  /* longest: R's 8 bits + LEN + POS + CTL, about 80 */
	int len;

	if (!v || !buf)
		return DF1_E_INVAL;
	switch (v->kind) {
	case DF1_VAL_INT16:
		len = snprintf(tmp, sizeof tmp, "%d", v->v.i16);
		break;
	case DF1_VAL_INT32:
		len = snprintf(tmp, sizeof tmp, "%ld", (long)v->v.i32);
		break;
	case DF1_VAL_FLOAT:
		len = valuefmt_format_float(v->v.f, tmp, sizeof tmp);
		break;
	case DF1_VAL_BIT:
		len = snprintf(tmp, sizeof tmp, "%d", v->v.bit ? 1 : 0);
		break;
	case DF1_VAL_STRING: {
		size_t n = v->v.str.len;

		if (n > DF1_STRING_MAX)
			return DF1_E_RANGE;
		n = strnlen(v->v.str.text, n);
		return valuefmt_emit(buf, cap, v->v.str.text, n);
	}
	case DF1_VAL_TCR:
		len = valuefmt_format_tcr(&v->v.tcr, t, tmp, sizeof tmp);
		break;
	default:
		return DF1_E_INVAL;
	}
	if (len < 0)
		return DF1_E_INVAL;
	return valuefmt_emit(buf, cap, tmp, (size_t)len);
}

/* ------------------------------------------------------------------------
 * Parsing
 * ------------------------------------------------------------------------ */

/* Integer text: [+-] decimal or [+-]0x hex (one prefix, then hex digits only),
 * nothing else. Hex up to max_pattern
 * is a raw bit pattern (0xFFFF into 16 bits is -1). DF1_E_TYPE if not an integer
 * (a float such as "1.5" included), DF1_E_RANGE outside [lo, hi]. */
static int valuefmt_parse_int(const char *s, size_t n, int64_t lo, int64_t hi, uint64_t max_pattern,
                              int64_t *out)
{
	char tmp[64];
	const char *p;
	char *end;
	bool neg = false, hex;
	unsigned long long u;

	if (n == 0 || n >= sizeof tmp)
		return n == 0 ? DF1_E_TYPE : DF1_E_RANGE;
	memcpy(tmp, s, n);
	tmp[n] = '\0';
	p = tmp;
	if (*p == '+' || *p == '-')
		neg = *p++ == '-';
	hex = p[0] == '0' && (p[1] == 'x' || p[1] == 'X');
	if (hex)
		p += 2;
	/* digits of the base and nothing else: strtoull would take a second sign,
	 * blanks, or (base 16) a second "0x" ("0x0x12" would be 18) */
	if (!*p || strspn(p, hex ? "0123456789abcdefABCDEF" : "0123456789") != strlen(p))
		return DF1_E_TYPE;
	errno = 0;
	u = strtoull(p, &end, hex ? 16 : 10);
	if (*end != '\0')
		return DF1_E_TYPE;
	if (errno == ERANGE)
		return DF1_E_RANGE;
	if (hex && !neg && u <= max_pattern && (int64_t)u > hi) {
		/* the bit pattern of a negative value */
		*out = (int64_t)u - (int64_t)max_pattern - 1;
		return 0;
	}
	if (neg) {
		if (u > (unsigned long long)-lo)
			return DF1_E_RANGE;
		*out = -(int64_t)u;
	} else {
		if (u > (unsigned long long)hi)
			return DF1_E_RANGE;
		*out = (int64_t)u;
	}
	return *out < lo ? DF1_E_RANGE : 0;
}

static int valuefmt_parse_float(const char *s, size_t n, float *out)
{
	char tmp[128];
	char *end;
	float f;

	if (n == 0 || n >= sizeof tmp)
		return n == 0 ? DF1_E_TYPE : DF1_E_RANGE;
	memcpy(tmp, s, n);
	tmp[n] = '\0';
	errno = 0;
	f = strtof(tmp, &end);
	if (end == tmp || *end != '\0' || isnan(f))
		return DF1_E_TYPE;
	/* overflow gives HUGE_VALF; literal "inf" does not set ERANGE */
	if (errno == ERANGE && isinf(f))
		return DF1_E_RANGE;
	*out = f;
	return 0;
}

/* A whitespace-trimmed view of s. */
static void valuefmt_trim(const char *s, const char **b, size_t *n)
{
	size_t len = strlen(s);

	while (len && isspace((unsigned char)*s)) {
		s++;
		len--;
	}
	while (len && isspace((unsigned char)s[len - 1]))
		len--;
	*b = s;
	*n = len;
}

static int valuefmt_parse_tcr(enum df1_file_type t, const char *s, struct df1_tcr *x)
{
	const char *w1, *w2;

	valuefmt_tcr_word_names(t, &w1, &w2);
	memset(x, 0, sizeof *x);
	while (*s) {
		const char *name, *val, *eq;
		size_t nlen, vlen;
		char nm[8];
		int64_t i;
		int r, bit;

		while (*s && (isspace((unsigned char)*s) || *s == ','))
			s++;
		if (!*s)
			break;
		name = s;
		while (*s && !isspace((unsigned char)*s) && *s != ',')
			s++;
		eq = memchr(name, '=', (size_t)(s - name));
		if (!eq)
			return DF1_E_TYPE;
		nlen = (size_t)(eq - name);
		val = eq + 1;
		vlen = (size_t)(s - val);
		if (nlen == 0 || nlen >= sizeof nm)
			return DF1_E_TYPE;
		memcpy(nm, name, nlen);
		nm[nlen] = '\0';
		if (strcasecmp(nm, "CTL") == 0) {
			r = valuefmt_parse_int(val, vlen, 0, UINT16_MAX, UINT16_MAX, &i);
			if (r < 0)
				return r;
			x->ctl = (uint16_t)i;
		} else if (strcasecmp(nm, w1) == 0 || strcasecmp(nm, w2) == 0) {
			r = valuefmt_parse_int(val, vlen, INT16_MIN, INT16_MAX, UINT16_MAX, &i);
			if (r < 0)
				return r;
			if (strcasecmp(nm, w1) == 0)
				x->pre = (int16_t)i;
			else
				x->acc = (int16_t)i;
		} else if ((bit = df1_tcr_bit(t, nm)) >= 0) {
			r = valuefmt_parse_int(val, vlen, 0, 1, 1, &i);
			if (r < 0)
				return r;
			x->ctl = (uint16_t)((x->ctl & ~(1u << bit)) | ((unsigned)i << bit));
		} else {
			return DF1_E_TYPE;
		}
	}
	return 0;
}

int df1_value_parse(const struct df1_addr *a, const char *text, struct df1_value *v)
{
	const char *s;
	size_t n;
	int64_t i;
	int r;

	if (!a || !text || !v)
		return DF1_E_INVAL;
	memset(v, 0, sizeof *v);
	v->kind = df1_addr_value_kind(a);
	if (v->kind == DF1_VAL_STRING) {
		n = strlen(text);
		if (n > DF1_STRING_MAX)
			return DF1_E_RANGE;
		memcpy(v->v.str.text, text, n + 1);
		v->v.str.len = (uint16_t)n;
		return 0;
	}
	valuefmt_trim(text, &s, &n);
	switch (v->kind) {
	case DF1_VAL_INT16:
		r = valuefmt_parse_int(s, n, INT16_MIN, INT16_MAX, UINT16_MAX, &i);
		if (r == 0)
			v->v.i16 = (int16_t)i;
		break;
	case DF1_VAL_INT32:
		r = valuefmt_parse_int(s, n, INT32_MIN, INT32_MAX, UINT32_MAX, &i);
		if (r == 0)
			v->v.i32 = (int32_t)i;
		break;
	case DF1_VAL_BIT:
		r = valuefmt_parse_int(s, n, 0, 1, 1, &i);
		if (r == 0)
			v->v.bit = i != 0;
		break;
	case DF1_VAL_FLOAT:
		r = valuefmt_parse_float(s, n, &v->v.f);
		break;
	case DF1_VAL_TCR: {
		char tmp[256];

		if (n >= sizeof tmp)
			return DF1_E_RANGE;
		memcpy(tmp, s, n);
		tmp[n] = '\0';
		r = valuefmt_parse_tcr(a->type, tmp, &v->v.tcr);
		break;
	}
	default:
		r = DF1_E_INVAL;
	}
	return r;
}
