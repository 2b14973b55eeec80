/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_value - tag payloads out and .../set values in (see gw_value.h).
 */
#include "df1gw/gw_value.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

/* The named status bits of a whole element, high bit first, as df1read prints them. */
static const char *const t_bits[] = { "EN", "TT", "DN", NULL };
static const char *const c_bits[] = { "CU", "CD", "DN", "OV", "UN", "UA", NULL };
static const char *const r_bits[] = { "EN", "EU", "DN", "EM", "ER", "UL", "IN", "FD", NULL };

static const char *const *tcr_bits(enum df1_file_type t)
{
	return t == DF1_FT_T ? t_bits : t == DF1_FT_C ? c_bits : t == DF1_FT_R ? r_bits : NULL;
}

/* The names of word 1 and word 2. */
static void tcr_words(enum df1_file_type t, const char **w1, const char **w2)
{
	*w1 = t == DF1_FT_R ? "LEN" : "PRE";
	*w2 = t == DF1_FT_R ? "POS" : "ACC";
}

void gw_value_json(struct gw_buf *b, const struct df1_value *v, enum df1_file_type t)
{
	char one[64];

	switch (v->kind) {
	case DF1_VAL_INT16:
		gw_buf_printf(b, "%d", v->v.i16);
		break;
	case DF1_VAL_INT32:
		gw_buf_printf(b, "%ld", (long)v->v.i32);
		break;
	case DF1_VAL_FLOAT:
		/* the library's shortest round-trip text; JSON has no nan or inf */
		if (df1_value_format(v, DF1_FT_F, one, sizeof one) < 0 || strchr(one, 'n'))
			gw_buf_puts(b, "null");
		else
			gw_buf_puts(b, one);
		break;
	case DF1_VAL_BIT:
		gw_buf_puts(b, v->v.bit ? "true" : "false");
		break;
	case DF1_VAL_STRING: {
		size_t n = v->v.str.len > DF1_STRING_MAX ? DF1_STRING_MAX : v->v.str.len;

		gw_json_bytes(b, (const uint8_t *)v->v.str.text, strnlen(v->v.str.text, n));
		break;
	}
	case DF1_VAL_TCR: {
		const char *const *names = tcr_bits(t);
		const char *w1, *w2;

		tcr_words(t, &w1, &w2);
		gw_buf_puts(b, "{");
		if (names) {
			for (size_t i = 0; names[i]; i++) {
				int bit = df1_tcr_bit(t, names[i]);

				gw_buf_printf(b, "\"%s\":%s,", names[i],
				              bit >= 0 && (v->v.tcr.ctl >> bit) & 1 ? "true" : "false");
			}
		} else {
			gw_buf_printf(b, "\"CTL\":%u,", v->v.tcr.ctl);
		}
		gw_buf_printf(b, "\"%s\":%d,\"%s\":%d}", w1, v->v.tcr.pre, w2, v->v.tcr.acc);
		break;
	}
	default:
		gw_buf_puts(b, "null");
		break;
	}
}

/* The file type a value is shown against: a T/C/R word is a plain integer. */
static enum df1_file_type value_type(const struct df1_tag_config *c)
{
	return c->addr.sub != DF1_ADDR_NONE ? DF1_FT_N : c->addr.type;
}

struct gw_span gw_tag_json(struct gw_buf *b, const struct df1_tag_state *st, const struct gw_tag_view *view)
{
	struct gw_span ts_at = { 0, 0 };
	const struct df1_tag_config *c = st->config;
	int q = view && view->quality >= 0 ? view->quality : (int)st->quality;
	const char *reason = view && view->reason ? view->reason : df1_reason_name(st->reason);
	char addr[80], ts[40];

	gw_buf_puts(b, "{\"value\":");
	if (!st->has_value) {
		gw_buf_puts(b, "null");
	} else if (st->count == 1) {
		gw_value_json(b, &st->values[0], value_type(c));
	} else {
		gw_buf_puts(b, "[");
		for (size_t i = 0; i < st->count; i++) {
			if (i)
				gw_buf_puts(b, ",");
			gw_value_json(b, &st->values[i], value_type(c));
		}
		gw_buf_puts(b, "]");
	}
	gw_buf_printf(b, ",\"quality\":\"%s\",\"reason\":", df1_quality_name((enum df1_quality)q));
	gw_json_text(b, reason, strlen(reason));
	if (view && view->error) {
		gw_buf_puts(b, ",\"error\":");
		gw_json_text(b, view->error, strlen(view->error));
	}
	if (!view || view->with_ts) {
		ts_at.at = b->len;
		if (st->last_good_wall_ms > 0) {
			gw_rfc3339(st->last_good_wall_ms, ts, sizeof ts);
			gw_buf_printf(b, ",\"ts\":\"%s\"", ts);
		} else {
			gw_buf_puts(b, ",\"ts\":null");
		}
		ts_at.len = b->len - ts_at.at;
	}
	if (df1_addr_format_plc(c->plc, &c->addr, addr, sizeof addr) < 0)
		snprintf(addr, sizeof addr, "?");
	gw_buf_puts(b, ",\"address\":");
	gw_json_text(b, addr, strlen(addr));
	gw_buf_printf(b, ",\"station\":%d}", c->station);
	return ts_at;
}

/* ---- .../set ---- */

static const char *jtype_name(enum gw_jtype t)
{
	switch (t) {
	case GW_JNULL: return "null";
	case GW_JBOOL: return "a boolean";
	case GW_JNUMBER: return "a number";
	case GW_JSTRING: return "a string";
	case GW_JARRAY: return "an array";
	case GW_JOBJECT: return "an object";
	}
	return "?";
}

static int type_error(char *err, size_t cap, const char *want, const struct gw_jv *v)
{
	snprintf(err, cap, "expected %s, got %s", want, jtype_name(v->type));
	return DF1_E_TYPE;
}

/* An integer member of a T/C/R object into a word. */
static int tcr_word(const struct gw_jv *v, const char *name, int16_t *out, char *err, size_t cap)
{
	struct df1_addr a;
	struct df1_value w;
	int r;

	if (v->type != GW_JNUMBER) {
		snprintf(err, cap, "%s: expected a number, got %s", name, jtype_name(v->type));
		return DF1_E_TYPE;
	}
	memset(&a, 0, sizeof a);
	a.type = DF1_FT_N;
	a.file = 7;
	a.sub = DF1_ADDR_NONE;
	a.bit = DF1_ADDR_NONE;
	r = df1_value_parse(&a, v->text, &w);
	if (r < 0) {
		snprintf(err, cap, "%s: %s does not fit a 16-bit word", name, v->text);
		return r == DF1_E_RANGE ? DF1_E_RANGE : DF1_E_TYPE;
	}
	*out = w.v.i16;
	return 0;
}

static int tcr_from_json(const struct gw_jv *v, enum df1_file_type t, struct df1_value *out,
                         char *err, size_t cap)
{
	const char *w1, *w2;

	if (v->type != GW_JOBJECT)
		return type_error(err, cap, "an object of the element's members", v);
	tcr_words(t, &w1, &w2);
	for (size_t i = 0; i < v->n; i++) {
		const char *k = v->keys[i];
		const struct gw_jv *m = v->items[i];
		int bit, r;

		if (strcasecmp(k, w1) == 0) {
			r = tcr_word(m, w1, &out->v.tcr.pre, err, cap);
		} else if (strcasecmp(k, w2) == 0) {
			r = tcr_word(m, w2, &out->v.tcr.acc, err, cap);
		} else if ((bit = df1_tcr_bit(t, k)) >= 0) {
			if (m->type == GW_JBOOL || (m->type == GW_JNUMBER && (!strcmp(m->text, "0") ||
			                                                     !strcmp(m->text, "1")))) {
				bool on = m->type == GW_JBOOL ? m->b : m->text[0] == '1';

				out->v.tcr.ctl = (uint16_t)(on ? out->v.tcr.ctl | (1u << bit)
				                               : out->v.tcr.ctl & ~(1u << bit));
				r = 0;
			} else {
				snprintf(err, cap, "%s: expected true or false, got %s", k, jtype_name(m->type));
				r = DF1_E_TYPE;
			}
		} else {
			snprintf(err, cap, "%s: no such member of a %s element", k, df1_file_type_name(t));
			r = DF1_E_TYPE;
		}
		if (r < 0)
			return r;
	}
	return 0;
}

/* The address numbers of kind are parsed as: the tag's own, or for a Type
 * wider than its word (DINT, REAL on N7:0) one of that kind (L, F). */
static struct df1_addr number_addr(const struct df1_tag_config *c, enum df1_value_kind kind)
{
	struct df1_addr a = c->addr;

	if (kind == df1_addr_value_kind(&c->addr))
		return a;
	memset(&a, 0, sizeof a);
	a.type = kind == DF1_VAL_INT32 ? DF1_FT_L : kind == DF1_VAL_FLOAT ? DF1_FT_F : DF1_FT_N;
	a.file = 9;
	a.sub = DF1_ADDR_NONE;
	a.bit = DF1_ADDR_NONE;
	return a;
}

static int one_from_json(const struct gw_jv *v, const struct df1_tag_config *c,
                         const struct df1_value *cur, struct df1_value *out, char *err, size_t cap)
{
	int tk = df1_tag_value_kind(c);     /* its Type's (df1gw(1) Tags: Type) */
	enum df1_value_kind kind = tk >= 0 ? (enum df1_value_kind)tk : df1_addr_value_kind(&c->addr);
	struct df1_addr na;
	size_t len;
	int r;

	memset(out, 0, sizeof *out);
	out->kind = kind;
	switch (kind) {
	case DF1_VAL_INT16:
	case DF1_VAL_INT32:
	case DF1_VAL_FLOAT:
		if (v->type != GW_JNUMBER)
			return type_error(err, cap, "a number", v);
		na = number_addr(c, kind);
		r = df1_value_parse(&na, v->text, out);
		if (r < 0) {
			snprintf(err, cap, "%s does not fit %s", v->text,
			         kind == DF1_VAL_FLOAT ? "a float" : kind == DF1_VAL_INT32 ? "a 32-bit integer"
			                                                                   : "a 16-bit integer");
			return r == DF1_E_RANGE ? DF1_E_RANGE : DF1_E_TYPE;
		}
		return 0;
	case DF1_VAL_BIT:
		if (v->type == GW_JBOOL) {
			out->v.bit = v->b;
			return 0;
		}
		if (v->type == GW_JNUMBER && (!strcmp(v->text, "0") || !strcmp(v->text, "1"))) {
			out->v.bit = v->text[0] == '1';
			return 0;
		}
		if (v->type == GW_JNUMBER) {
			snprintf(err, cap, "%s does not fit a bit (true, false, 0 or 1)", v->text);
			return DF1_E_RANGE;
		}
		return type_error(err, cap, "true or false", v);
	case DF1_VAL_STRING:
		if (v->type != GW_JSTRING)
			return type_error(err, cap, "a string", v);
		if (!gw_jv_latin1(v, (uint8_t *)out->v.str.text, DF1_STRING_MAX, &len)) {
			snprintf(err, cap, "the string has more than %d characters or one above U+00FF",
			         DF1_STRING_MAX);
			return DF1_E_RANGE;
		}
		out->v.str.text[len] = '\0';
		out->v.str.len = (uint16_t)len;
		return 0;
	case DF1_VAL_TCR:
		if (cur && cur->kind == DF1_VAL_TCR)
			out->v.tcr = cur->v.tcr;
		return tcr_from_json(v, c->addr.type, out, err, cap);
	}
	snprintf(err, cap, "values of this address cannot be written");
	return DF1_E_TYPE;
}

int gw_value_from_json(const struct gw_jv *v, const struct df1_tag_config *c,
                       const struct df1_tag_state *cur, struct df1_value *out, size_t cap,
                       size_t *n, char *err, size_t errcap)
{
	size_t want = (size_t)(c->count > 0 ? c->count : 1);
	int r;

	*n = 0;
	err[0] = '\0';
	if (cap < want) {
		snprintf(err, errcap, "too many values");
		return DF1_E_INVAL;
	}
	if (v->type == GW_JARRAY) {
		if (want == 1)
			return type_error(err, errcap, "one value (the tag has Count 1)", v);
		if (v->n == 0 || v->n > want) {
			snprintf(err, errcap, "%zu values: the tag takes 1 to %zu", v->n, want);
			return DF1_E_RANGE;
		}
		for (size_t i = 0; i < v->n; i++) {
			char one[200];
			const struct df1_value *cv = cur && cur->has_value && i < cur->count ? &cur->values[i] : NULL;

			r = one_from_json(v->items[i], c, cv, &out[i], one, sizeof one);
			if (r < 0) {
				snprintf(err, errcap, "value %zu: %s", i + 1, one);
				return r;
			}
		}
		*n = v->n;
		return 0;
	}
	r = one_from_json(v, c, cur && cur->has_value && cur->count ? &cur->values[0] : NULL, &out[0],
	                  err, errcap);
	if (r < 0)
		return r;
	*n = 1;
	return 0;
}
