/* SPDX-License-Identifier: MPL-2.0 */
/*
 * table.c - the data table (df1_table(3)): files, initial contents, address
 * stepping, element values, the processor table and the diagnostic status.
 * Layout and rules: lib/table/table.h; the wire layout: lib/server/server.h.
 */
#include "table/table.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "proto/pccc.h"
#include "proto/value.h"

int table_fail(struct df1_table *t, int err, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(t->err, sizeof t->err, fmt, ap);
	va_end(ap);
	return err;
}

/* ------------------------------------------------------------------------
 * Files
 * ------------------------------------------------------------------------ */

/* An ST element: LEN(2) + 82 characters, bytes swapped per word (doc/PROTOCOL.md 5). */
/* Initial contents of element n (df1sim(1), DATA TABLE). */
static void table_elem_init(enum df1_file_type type, int n, uint8_t *p)
{
	char text[32];

	switch (type) {
	case DF1_FT_N:
		put_le16(p, (uint16_t)n);
		break;
	case DF1_FT_F:
		value_put_float(p, (float)n + 0.5f, VALUE_FLOAT_LE);
		break;
	case DF1_FT_L:
		put_le32(p, (uint32_t)n * 65536u + (uint32_t)n);
		break;
	case DF1_FT_T: case DF1_FT_C:
		put_le16(p, 0);
		put_le16(p + 2, 100);
		put_le16(p + 4, 0);
		break;
	case DF1_FT_ST:
		snprintf(text, sizeof text, "STRING %d", n);
		(void)value_put_string(p, text);    /* a few characters: it fits */
		break;
	default:                /* O I S B R A: zero */
		memset(p, 0, (size_t)df1_file_type_element_size(type));
		break;
	}
}

struct table_file *table_file_new(enum df1_file_type type, int nelem)
{
	struct table_file *f = calloc(1, sizeof *f);

	if (!f)
		return NULL;
	f->type = type;
	f->esize = (size_t)df1_file_type_element_size(type);
	f->nelem = nelem;
	f->data = calloc((size_t)nelem, f->esize);
	if (!f->data) {
		free(f);
		return NULL;
	}
	for (int i = 0; i < nelem; i++)
		table_elem_init(type, i, f->data + (size_t)i * f->esize);
	return f;
}

void table_file_free(struct table_file *f)
{
	if (f) {
		free(f->data);
		free(f);
	}
}

bool table_file_grow(struct table_file *f, int elem)
{
	uint8_t *d;

	if (elem < f->nelem)
		return true;
	d = realloc(f->data, (size_t)(elem + 1) * f->esize);
	if (!d)
		return false;
	f->data = d;
	for (int i = f->nelem; i <= elem; i++)
		table_elem_init(f->type, i, d + (size_t)i * f->esize);
	f->nelem = elem + 1;
	return true;
}

static bool table_type_ok(const struct df1_table *t, enum df1_file_type type)
{
	if (t->plc == DF1_PLC_PLC3)
		return table_slot(t, type, 0) >= 0;
	return type > DF1_FT_NONE && type < DF1_FT_COUNT_ && df1_file_type_element_size(type) > 0;
}

/* The sections of a PLC-3 table by file type (H = L), 0 = none (R, ST). */
static int table_plc3_section(enum df1_file_type type)
{
	switch (type) {
	case DF1_FT_O: return 1;
	case DF1_FT_I: return 2;
	case DF1_FT_T: return 3;
	case DF1_FT_C: return 4;
	case DF1_FT_N: return 5;
	case DF1_FT_F: return 6;
	case DF1_FT_D: return 7;
	case DF1_FT_B: return 8;
	case DF1_FT_A: return 9;
	case DF1_FT_L: return 10;
	case DF1_FT_S: return 11;
	default: return 0;
	}
}

int table_slot(const struct df1_table *t, enum df1_file_type type, int number)
{
	int sec;

	if (number < 0 || number >= DF1_TABLE_FILES_MAX)
		return -1;
	if (t->plc != DF1_PLC_PLC3)
		return number;
	sec = table_plc3_section(type);
	return sec ? sec * DF1_TABLE_FILES_MAX + number : -1;
}

struct table_file *table_find(const struct df1_table *t, const struct df1_addr *a)
{
	int i = table_slot(t, a->type, a->file);

	return i < 0 ? NULL : t->files[i];
}

/* ------------------------------------------------------------------------
 * Processors (diagnostic status, doc/PROTOCOL.md 4.9)
 * ------------------------------------------------------------------------ */

static const struct table_processor processors[] = {
	{ "slc500", "500 - 20", 0x1A, false },
	{ "slc5/01", "5/01", 0x18, false },
	{ "slc5/02", "5/02", 0x25, false },
	{ "slc5/03", "5/03", 0x49, false },
	{ "slc5/04", "5/04", 0x5B, false },
	{ "slc5/04l541", "5/04", 0x6F, false },
	{ "slc5/05", "5/05", 0x78, false },
	{ "ml1000", "1761", 0x58, false },
	{ "ml1100", "1763", 0x9C, false },
	{ "ml1200", "1762", 0x88, false },
	{ "ml1400", "1766", 0x9F, false },
	{ "ml1500", "1764", 0x89, false },
	{ "ml1500lrp", "1764", 0x8C, false },
	{ "plc5/10", NULL, 0x22, true },
	{ "plc5/11", NULL, 0x31, true },
	{ "plc5/12", NULL, 0x13, true },
	{ "plc5/20", NULL, 0x32, true },
	{ "plc5/25", NULL, 0x14, true },
	{ "plc5/30", NULL, 0x33, true },
	{ "plc5/40", NULL, 0x15, true },
	{ "plc5/40l", NULL, 0x28, true },
	{ "plc5/60", NULL, 0x23, true },
	{ "plc5/60l", NULL, 0x29, true },
	{ "plc5/20e", NULL, 0x4A, true },
	{ "plc5/40e", NULL, 0x4B, true },
	{ "plc5/80e", NULL, 0x59, true },
};

static bool table_find_processor(const char *name, bool plc5, struct table_processor *out)
{
	char key[32], *end;
	size_t n = 0;
	long code;

	for (const char *s = name; *s && n < sizeof key - 1; s++) {
		if (*s == ' ' || *s == '-' || *s == '_')
			continue;
		key[n++] = (char)tolower((unsigned char)*s);
	}
	key[n] = '\0';
	if (strncmp(key, "micrologix", 10) == 0) {
		memmove(key + 2, key + 10, strlen(key + 10) + 1);
		key[0] = 'm';
		key[1] = 'l';
	}
	for (size_t i = 0; i < sizeof processors / sizeof processors[0]; i++) {
		if (strcmp(processors[i].key, key) == 0) {
			*out = processors[i];
			return true;
		}
	}
	/* a type code: decimal, or hex with 0x ("0x5B"); a leading 0 is not octal */
	errno = 0;
	code = strtol(name, &end, name[0] == '0' && (name[1] == 'x' || name[1] == 'X') ? 16 : 10);
	if (!*name || *end || errno || code < 0 || code > 255)
		return false;
	out->key = "";
	out->bulletin = "";
	out->code = (uint8_t)code;
	out->plc5 = plc5;
	return true;
}

int df1_table_set_processor(struct df1_table *t, const char *name)
{
	struct table_processor p;

	if (!t)
		return DF1_E_INVAL;
	if (!name || !table_find_processor(name, t->plc == DF1_PLC_PLC5, &p))
		return table_fail(t, DF1_E_INVAL, "unknown processor '%s' (e.g. slc5/04, ml1400, plc5/40, 0x5B)",
		                  name ? name : "");
	t->proc = p;
	return 0;
}

int table_diag_status(const struct df1_table *t, int station, uint8_t *buf, size_t cap)
{
	struct pccc_diag_info d;
	int files = 0;

	memset(&d, 0, sizeof d);
	d.plc5 = t->proc.plc5;
	d.type_code = t->proc.code;
	if (d.plc5) {
		for (int i = 0; i < TABLE_SLOTS; i++)
			files += t->files[i] != NULL;
		/* remote run, remote program, remote test (M p.192) */
		d.mode = t->mode == TABLE_MODE_RUN ? 6 : t->mode == TABLE_MODE_PROGRAM ? 4 : 5;
		d.memory_words = 49152;                         /* 48K words */
		d.series_rev = (uint8_t)((4u << 5) | 2u);       /* series E, revision 3 */
		d.node = (uint8_t)station;
		d.data_files = (uint16_t)files;
		d.program_files = 2;
	} else {
		d.interface_type = t->plc == DF1_PLC_MICROLOGIX ? 0x34 : 0x1F;
		d.series_rev = (uint8_t)((2u << 5) | 4u);       /* series C, revision 5 */
		d.bulletin = t->proc.bulletin;
		d.mode = (uint8_t)t->mode;
		d.ram_kb = 0x10;
		d.owner = 0x3F;                                 /* no program owner */
	}
	return pccc_enc_diag_reply(buf, cap, &d);
}

/* ------------------------------------------------------------------------
 * The table
 * ------------------------------------------------------------------------ */

int df1_table_new(struct df1_table **out, enum df1_plc plc)
{
	static const char *const default_proc[] = {
		[DF1_PLC_SLC] = "slc5/04", [DF1_PLC_MICROLOGIX] = "ml1400",
		[DF1_PLC_SLC502] = "slc5/02", [DF1_PLC_PLC5] = "plc5/40", [DF1_PLC_PLC2] = "slc5/04",
		/* no PLC-3 diagnostic status layout in the sources (doc/PROTOCOL.md 4.2a) */
		[DF1_PLC_PLC3] = "slc5/04",
	};
	struct df1_table *t;

	if (!out)
		return DF1_E_INVAL;
	*out = NULL;
	if ((unsigned)plc > DF1_PLC_PLC3)
		return DF1_E_INVAL;
	t = calloc(1, sizeof *t);
	if (!t)
		return DF1_E_NOMEM;
	t->plc = plc;
	t->mode = TABLE_MODE_RUN;
	(void)table_find_processor(default_proc[plc], plc == DF1_PLC_PLC5, &t->proc);
	*out = t;
	return 0;
}

void df1_table_free(struct df1_table *t)
{
	if (!t)
		return;
	for (int i = 0; i < TABLE_SLOTS; i++)
		table_file_free(t->files[i]);
	free(t);
}

int df1_table_clone(struct df1_table **out, const struct df1_table *src)
{
	struct df1_table *t;

	if (!out)
		return DF1_E_INVAL;
	*out = NULL;
	if (!src)
		return DF1_E_INVAL;
	t = calloc(1, sizeof *t);
	if (!t)
		return DF1_E_NOMEM;
	t->plc = src->plc;
	t->mode = src->mode;
	t->proc = src->proc;
	for (int i = 0; i < TABLE_SLOTS; i++) {
		const struct table_file *s = src->files[i];
		struct table_file *f;

		if (!s)
			continue;
		f = malloc(sizeof *f);
		if (f) {
			*f = *s;
			f->data = malloc((size_t)s->nelem * s->esize);
		}
		if (!f || !f->data) {
			free(f);
			df1_table_free(t);
			return DF1_E_NOMEM;
		}
		memcpy(f->data, s->data, (size_t)s->nelem * s->esize);
		t->files[i] = f;
	}
	*out = t;
	return 0;
}

int df1_table_add_file(struct df1_table *t, enum df1_file_type type, int number, int elements)
{
	struct table_file *f;
	int slot;

	if (!t)
		return DF1_E_INVAL;
	if (!table_type_ok(t, type))
		return table_fail(t, DF1_E_INVAL, "file type %d is not a data-table type", (int)type);
	if (number < 0 || number >= DF1_TABLE_FILES_MAX)
		return table_fail(t, DF1_E_INVAL, "file number %d out of range (0-%d)", number,
		                  DF1_TABLE_FILES_MAX - 1);
	slot = table_slot(t, type, number);
	if (elements < 1 || elements > DF1_TABLE_ELEMENTS_MAX)
		return table_fail(t, DF1_E_INVAL, "%d elements out of range (1-%d)", elements,
		                  DF1_TABLE_ELEMENTS_MAX);
	f = t->files[slot];
	if (f && f->type != type && f->provisional) {
		table_file_free(f);
		f = t->files[slot] = NULL;
	}
	if (f && f->type != type)
		return table_fail(t, DF1_E_TYPE, "file %d already holds type %s", number,
		                  df1_file_type_name(f->type));
	if (f) {
		if (!table_file_grow(f, elements - 1))
			return table_fail(t, DF1_E_NOMEM, "out of memory");
		f->provisional = false;
		return 0;
	}
	f = table_file_new(type, elements);
	if (!f)
		return table_fail(t, DF1_E_NOMEM, "out of memory");
	t->files[slot] = f;
	return 0;
}

/* A PLC-3's files: the fixed O0 I0 S0 T0 C0, and a file of each other section
 * holding the manuals' examples (N3:173, B5:173/15, F2:10, A1:126, D7, H8). */
static int table_plc3_defaults(struct df1_table *t)
{
	static const struct { enum df1_file_type type; int number; } files[] = {
		{ DF1_FT_O, 0 }, { DF1_FT_I, 0 }, { DF1_FT_S, 0 }, { DF1_FT_T, 0 }, { DF1_FT_C, 0 },
		{ DF1_FT_N, 3 }, { DF1_FT_B, 5 }, { DF1_FT_F, 2 }, { DF1_FT_A, 1 }, { DF1_FT_D, 7 },
		{ DF1_FT_L, 8 },
	};

	for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
		int r = df1_table_add_file(t, files[i].type, files[i].number, DF1_TABLE_ELEMENTS_DEFAULT);

		if (r < 0)
			return r;
	}
	return 0;
}

int df1_table_add_default_files(struct df1_table *t)
{
	/* O0..F8 as every SLC has them, plus ST9 L10 A11 so that every data
	 * type can be read without more files (file number = index). */
	static const enum df1_file_type defaults[12] = {
		DF1_FT_O, DF1_FT_I, DF1_FT_S, DF1_FT_B, DF1_FT_T, DF1_FT_C, DF1_FT_R, DF1_FT_N, DF1_FT_F,
		DF1_FT_ST, DF1_FT_L, DF1_FT_A,
	};
	int r;

	if (!t)
		return DF1_E_INVAL;
	if (t->plc == DF1_PLC_PLC3)
		return table_plc3_defaults(t);
	for (int i = 0; i < 12; i++) {
		bool fresh = t->files[i] == NULL;

		r = df1_table_add_file(t, defaults[i], i, DF1_TABLE_ELEMENTS_DEFAULT);
		if (r < 0)
			return r;
		if (fresh && i >= 9)
			t->files[i]->provisional = true;
	}
	return 0;
}

int df1_table_file(const struct df1_table *t, int number, enum df1_file_type *type)
{
	const struct table_file *f;

	if (!t)
		return DF1_E_INVAL;
	if (number < 0 || number >= DF1_TABLE_FILES_MAX)
		return DF1_E_ADDR_RANGE;
	f = t->files[number];
	/* a PLC-3 table: the first section that has a file of that number */
	for (int sec = 1; !f && t->plc == DF1_PLC_PLC3 && sec < TABLE_SECTIONS; sec++)
		f = t->files[sec * DF1_TABLE_FILES_MAX + number];
	if (!f)
		return DF1_E_ADDR_RANGE;
	if (type)
		*type = f->type;
	return f->nelem;
}

int df1_table_mode(const struct df1_table *t)
{
	return t ? t->mode : DF1_E_INVAL;
}

int df1_table_set_mode(struct df1_table *t, int mode)
{
	if (!t)
		return DF1_E_INVAL;
	if (mode != 1 && mode != 6 && mode != 7 && mode != 8)
		return table_fail(t, DF1_E_INVAL, "mode %d is not 1 (program), 6 (run), 7 or 8 (test)", mode);
	t->mode = mode;
	return 0;
}

const char *df1_table_error_text(const struct df1_table *t)
{
	return t ? t->err : "";
}

/* ------------------------------------------------------------------------
 * Elements
 * ------------------------------------------------------------------------ */

void table_addr_step(const struct df1_addr *a, int i, struct df1_addr *out)
{
	*out = *a;
	if (a->bit != DF1_ADDR_NONE) {
		int nbits = a->type == DF1_FT_L && a->sub == DF1_ADDR_NONE ? 32 : 16;
		int b = a->bit + i;

		out->element = a->element + b / nbits;
		out->bit = b % nbits;
	} else {
		out->element = a->element + i;
	}
}

static uint8_t *table_elem(const struct table_file *f, const struct df1_addr *a)
{
	uint8_t *p = f->data + (size_t)a->element * f->esize;

	if (a->sub != DF1_ADDR_NONE)
		p += (size_t)a->sub * 2;
	return p;
}

/* The values reaching the table are of the address's kind and checked (a
 * string's length included), so the codec cannot refuse them. */
void table_put_value(struct table_file *f, const struct df1_addr *a, const struct df1_value *v)
{
	uint8_t *p = table_elem(f, a);

	if (v->kind == DF1_VAL_BIT) {
		uint8_t *b = p + a->bit / 8;
		uint8_t m = (uint8_t)(1u << (a->bit % 8));

		*b = v->v.bit ? (uint8_t)(*b | m) : (uint8_t)(*b & ~m);
		return;
	}
	(void)value_encode_kind(v->kind, v, p, VALUE_FLOAT_LE);
}

void table_get_value(const struct table_file *f, const struct df1_addr *a, struct df1_value *v)
{
	const uint8_t *p = table_elem(f, a);
	enum df1_value_kind k = df1_addr_value_kind(a);
	uint8_t st[84];

	if (k == DF1_VAL_BIT) {
		memset(v, 0, sizeof *v);
		v->kind = k;
		v->v.bit = (p[a->bit / 8] >> (a->bit % 8)) & 1u;
		return;
	}
	if (k == DF1_VAL_STRING && le16(p) > DF1_STRING_MAX) {
		/* a raw write may have stored any LEN: serve the characters there are */
		memcpy(st, p, sizeof st);
		put_le16(st, DF1_STRING_MAX);
		p = st;
	}
	(void)value_decode_kind(k, p, v, VALUE_FLOAT_LE);
}

/* An address as text for a message: "N7:0", or "file 7" when it has no text form. */
static const char *table_addr_text(const struct df1_table *t, const struct df1_addr *a, char *buf,
                                   size_t cap)
{
	if (df1_addr_format_plc(t->plc, a, buf, cap) < 0)
		snprintf(buf, cap, "file %d", a->file);
	return buf;
}

/* Check that value i of a run at a lies inside t; its file in *fp, its address in *ai. */
static int table_check_addr(struct df1_table *t, const struct df1_addr *a, size_t i,
                            struct table_file **fp, struct df1_addr *ai)
{
	char text[DF1_ADDR_ASCII_MAX + 32];
	struct table_file *f;
	size_t end;

	if (a->ascii[0] || a->type == DF1_FT_NONE)
		return table_fail(t, DF1_E_INVAL, "%s: not a data-table address",
		                  a->ascii[0] ? a->ascii : table_addr_text(t, a, text, sizeof text));
	if (!(f = table_find(t, a)))
		return table_fail(t, DF1_E_ADDR_RANGE, "%s: no file %d in the table",
		                  table_addr_text(t, a, text, sizeof text), a->file);
	if (f->type != a->type)
		return table_fail(t, DF1_E_TYPE, "%s: file %d holds type %s", table_addr_text(t, a, text, sizeof text),
		                  a->file, df1_file_type_name(f->type));
	if (a->bit != DF1_ADDR_NONE && (a->type == DF1_FT_F || a->type == DF1_FT_ST))
		return table_fail(t, DF1_E_TYPE, "%s: no bits in this file type",
		                  table_addr_text(t, a, text, sizeof text));
	if (i > (size_t)DF1_TABLE_ELEMENTS_MAX * 32)
		return table_fail(t, DF1_E_ADDR_RANGE, "%s: %zu values run past the end of file %d",
		                  table_addr_text(t, a, text, sizeof text), i + 1, a->file);
	table_addr_step(a, (int)i, ai);
	end = (size_t)ai->element * f->esize + (ai->sub != DF1_ADDR_NONE ? (size_t)ai->sub * 2 : 0) +
	      (df1_addr_value_kind(ai) == DF1_VAL_BIT || ai->sub != DF1_ADDR_NONE ? 2 : f->esize);
	if (ai->element < 0 || end > (size_t)f->nelem * f->esize)
		return table_fail(t, DF1_E_ADDR_RANGE, "%s: value %zu lands beyond the end of file %d (%d elements)",
		                  table_addr_text(t, a, text, sizeof text), i + 1, a->file, f->nelem);
	*fp = f;
	return 0;
}

int df1_table_read_addr(struct df1_table *t, const struct df1_addr *a, struct df1_value *out, size_t n)
{
	if (!t)
		return DF1_E_INVAL;
	if (!a || (n && !out) || n > INT32_MAX)
		return table_fail(t, DF1_E_INVAL, "invalid argument");
	for (size_t i = 0; i < n; i++) {
		struct table_file *f;
		struct df1_addr ai;
		int r = table_check_addr(t, a, i, &f, &ai);

		if (r < 0)
			return r;
		table_get_value(f, &ai, &out[i]);
	}
	return (int)n;
}

int df1_table_write_addr(struct df1_table *t, const struct df1_addr *a, const struct df1_value *in, size_t n)
{
	char text[DF1_ADDR_ASCII_MAX + 32];

	if (!t)
		return DF1_E_INVAL;
	if (!a || (n && !in) || n > INT32_MAX)
		return table_fail(t, DF1_E_INVAL, "invalid argument");
	/* every value first, so that a bad one stores nothing */
	for (size_t i = 0; i < n; i++) {
		struct table_file *f;
		struct df1_addr ai;
		int r = table_check_addr(t, a, i, &f, &ai);

		if (r < 0)
			return r;
		if (in[i].kind != df1_addr_value_kind(&ai))
			return table_fail(t, DF1_E_TYPE, "%s: value %zu is of another kind than the address",
			                  table_addr_text(t, &ai, text, sizeof text), i + 1);
		if (in[i].kind == DF1_VAL_STRING && in[i].v.str.len > DF1_STRING_MAX)
			return table_fail(t, DF1_E_RANGE, "%s: value %zu: a string holds at most %d characters",
			                  table_addr_text(t, &ai, text, sizeof text), i + 1, DF1_STRING_MAX);
	}
	for (size_t i = 0; i < n; i++) {
		struct table_file *f;
		struct df1_addr ai;

		(void)table_check_addr(t, a, i, &f, &ai);
		table_put_value(f, &ai, &in[i]);
	}
	return (int)n;
}

static int table_parse(struct df1_table *t, const char *addr, struct df1_addr *a)
{
	int r;

	if (!addr)
		return table_fail(t, DF1_E_INVAL, "invalid argument");
	r = df1_addr_parse_plc(t->plc, addr, a);
	if (r < 0)
		return table_fail(t, r, "%s: %s", addr, df1_strerror(r));
	return 0;
}

int df1_table_read(struct df1_table *t, const char *addr, struct df1_value *out, size_t n)
{
	struct df1_addr a;
	int r;

	if (!t)
		return DF1_E_INVAL;
	r = table_parse(t, addr, &a);
	return r < 0 ? r : df1_table_read_addr(t, &a, out, n);
}

int df1_table_write(struct df1_table *t, const char *addr, const struct df1_value *in, size_t n)
{
	struct df1_addr a;
	int r;

	if (!t)
		return DF1_E_INVAL;
	r = table_parse(t, addr, &a);
	return r < 0 ? r : df1_table_write_addr(t, &a, in, n);
}

/* ------------------------------------------------------------------------
 * Serving (the contract of lib/server/server.h)
 * ------------------------------------------------------------------------ */

int table_locate(struct df1_table *t, const struct df1_addr *a, size_t nbytes, uint8_t **p)
{
	struct table_file *f;
	size_t off, size;

	if (a->type != DF1_FT_NONE ? !(f = table_find(t, a)) :
	    a->file < 0 || a->file >= DF1_TABLE_FILES_MAX || !(f = t->files[a->file]))
		return 0x06;            /* address doesn't point to something usable */
	if (a->type != DF1_FT_NONE && a->type != f->type)
		return 0x11;            /* illegal data type */
	if (a->element < 0 || a->element >= f->nelem)
		return 0x07;            /* beyond the end of the file */
	off = (size_t)a->element * f->esize;
	if (a->sub != DF1_ADDR_NONE && a->sub > 0)
		off += (size_t)a->sub * 2;
	size = (size_t)f->nelem * f->esize;
	if (off >= size)
		return 0x07;
	if (off + nbytes > size)
		return 0x0A;            /* transaction size plus word address is too large */
	*p = f->data + off;
	return 0;
}
