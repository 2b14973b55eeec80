/* SPDX-License-Identifier: MPL-2.0 */
/*
 * table_file.c - df1_table_load() and df1_table_save(): a data table as text,
 * the format of df1sim's --data (df1sim(1) DATA TABLE, df1_table(3)):
 *
 *   # comment                       blank lines and text after '#' are ignored
 *   N7:0=1,2,3                      ADDRESS=VALUE[,VALUE...]: consecutive elements
 *   B3:1/5=1,0                      consecutive bits
 *   T4:0=PRE=500 ACC=0 EN=1         a whole T/C/R element (df1_value_parse's text)
 *   ST9:0="a, \"quoted\" string"    quotes keep commas, blanks and '#'; \" \\ \xHH
 *
 * A UTF-8 byte order mark at the start of the file is skipped; a NUL byte in a
 * line is an error naming the line (a quoted string gets one with \x00).
 *
 * A load is all or nothing: the lines go into a copy that replaces the table's
 * contents only when every line was good. A save writes a temporary file in
 * the same directory and renames it over the target.
 */
#include "table/table.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

/* ------------------------------------------------------------------------
 * Load
 * ------------------------------------------------------------------------ */

static int table_hex_digit(int c)
{
	if (c >= '0' && c <= '9')
		return c - '0';
	c = tolower(c);
	return c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

/* Split the values at commas outside double quotes; strip blanks and quotes
 * (\" \\ \xHH inside quotes). Lengths in len[] (a quoted value may hold NUL).
 * Returns the count, -1 on an unterminated quote, -2 on more than max values. */
static int table_split_values(char *s, char **out, size_t *len, int max)
{
	int n = 0;

	for (;;) {
		char *w, *start;
		int hi, lo;

		while (*s == ' ' || *s == '\t')
			s++;
		if (n == max)
			return -2;
		start = w = s;
		if (*s == '"') {
			s++;
			while (*s && *s != '"') {
				if (*s == '\\' && (s[1] == '"' || s[1] == '\\')) {
					s++;
				} else if (*s == '\\' && s[1] == 'x' && (hi = table_hex_digit((unsigned char)s[2])) >= 0 &&
				           (lo = table_hex_digit((unsigned char)s[3])) >= 0) {
					*w++ = (char)(hi * 16 + lo);
					s += 4;
					continue;
				}
				*w++ = *s++;
			}
			if (*s != '"')
				return -1;
			s++;
			while (*s == ' ' || *s == '\t')
				s++;
			if (*s && *s != ',')
				return -1;
		} else {
			while (*s && *s != ',')
				s++;
			w = s;
			while (w > start && (w[-1] == ' ' || w[-1] == '\t'))
				w--;
		}
		len[n] = (size_t)(w - start);
		out[n++] = start;
		if (*s == ',') {
			*w = '\0';
			s++;
			continue;
		}
		*w = '\0';
		return n;
	}
}

/* One value's text for address a. */
static int table_parse_value(const struct df1_addr *a, const char *text, size_t len, struct df1_value *v)
{
	if (df1_addr_value_kind(a) == DF1_VAL_STRING && len != strlen(text)) {
		/* a string with NUL characters (\x00) */
		if (len > DF1_STRING_MAX)
			return DF1_E_RANGE;
		memset(v, 0, sizeof *v);
		v->kind = DF1_VAL_STRING;
		memcpy(v->v.str.text, text, len);
		v->v.str.len = (uint16_t)len;
		return 0;
	}
	if (df1_addr_value_kind(a) == DF1_VAL_FLOAT && strcasecmp(text, "nan") == 0) {
		memset(v, 0, sizeof *v);
		v->kind = DF1_VAL_FLOAT;
		v->v.f = NAN;           /* what df1_table_save() writes for a NaN */
		return 0;
	}
	return df1_value_parse(a, text, v);
}

/* One line "ADDRESS=VALUE[,VALUE...]"; false with the reason in err. */
static bool table_line(struct df1_table *t, char *line, char *err, size_t cap)
{
	char *vals[DF1_TABLE_ELEMENTS_MAX];
	size_t lens[DF1_TABLE_ELEMENTS_MAX];
	char *eq = strchr(line, '='), *addr_text = line, *e;
	struct table_file *f;
	struct df1_addr a;
	int n, rc, sub_words, slot;

	if (!eq) {
		snprintf(err, cap, "expected ADDRESS=VALUE[,VALUE...]");
		return false;
	}
	*eq = '\0';
	e = eq;
	while (e > addr_text && (e[-1] == ' ' || e[-1] == '\t'))
		*--e = '\0';
	rc = df1_addr_parse_plc(t->plc, addr_text, &a);
	if (rc < 0) {
		snprintf(err, cap, "%s: %s", addr_text, df1_strerror(rc));
		return false;
	}
	if (a.ascii[0] || a.type == DF1_FT_NONE || a.file < 0 || a.file >= DF1_TABLE_FILES_MAX) {
		snprintf(err, cap, "%s: not a data-table address", addr_text);
		return false;
	}
	n = table_split_values(eq + 1, vals, lens, DF1_TABLE_ELEMENTS_MAX);
	if (n == -1) {
		snprintf(err, cap, "%s: unterminated quote", addr_text);
		return false;
	}
	if (n < 0) {
		snprintf(err, cap, "%s: more than %d values", addr_text, DF1_TABLE_ELEMENTS_MAX);
		return false;
	}
	slot = table_slot(t, a.type, a.file);
	if (slot < 0) {
		snprintf(err, cap, "%s: not a data-table address", addr_text);
		return false;
	}
	f = t->files[slot];
	if (f && f->type != a.type && f->provisional) {
		/* e.g. N9, the SLC's common interface file for PLC-2 commands */
		table_file_free(f);
		f = t->files[slot] = NULL;
	}
	if (f && f->type != a.type) {
		snprintf(err, cap, "%s: file %d already holds type %s", addr_text, a.file,
		         df1_file_type_name(f->type));
		return false;
	}
	sub_words = df1_file_type_element_size(a.type) / 2;
	if (a.sub != DF1_ADDR_NONE && a.sub >= sub_words) {
		snprintf(err, cap, "%s: sub-element beyond the element's %d words", addr_text, sub_words);
		return false;
	}
	if (!f) {
		f = t->files[slot] = table_file_new(a.type, DF1_TABLE_ELEMENTS_DEFAULT);
		if (!f) {
			snprintf(err, cap, "out of memory");
			return false;
		}
	}
	for (int i = 0; i < n; i++) {
		struct df1_addr ai;
		struct df1_value v;

		table_addr_step(&a, i, &ai);
		if (ai.element >= DF1_TABLE_ELEMENTS_MAX) {
			snprintf(err, cap, "%s: value %d lands beyond element %d", addr_text, i + 1,
			         DF1_TABLE_ELEMENTS_MAX - 1);
			return false;
		}
		rc = table_parse_value(&ai, vals[i], lens[i], &v);
		if (rc < 0) {
			snprintf(err, cap, "%s: '%s': %s", addr_text, vals[i], df1_strerror(rc));
			return false;
		}
		if (!table_file_grow(f, ai.element)) {
			snprintf(err, cap, "out of memory");
			return false;
		}
		table_put_value(f, &ai, &v);
	}
	return true;
}

/* Cut a line at a '#' outside quotes and trim it; returns its start. */
static char *table_strip(char *s)
{
	bool inq = false;
	char *p;
	size_t len;

	for (p = s; *p; p++) {
		if (inq && *p == '\\' && (p[1] == '"' || p[1] == '\\'))
			p++;                    /* an escaped quote or backslash */
		else if (*p == '"' && (inq || p == s || p[-1] != '\\'))
			inq = !inq;
		else if (*p == '#' && !inq)
			break;
	}
	*p = '\0';
	while (*s && isspace((unsigned char)*s))
		s++;
	len = strlen(s);
	while (len > 0 && isspace((unsigned char)s[len - 1]))
		s[--len] = '\0';
	return s;
}

static void table_swap(struct df1_table *a, struct df1_table *b)
{
	for (int i = 0; i < TABLE_SLOTS; i++) {
		struct table_file *f = a->files[i];

		a->files[i] = b->files[i];
		b->files[i] = f;
	}
}

int df1_table_load(struct df1_table *t, const char *path)
{
	struct df1_table *work = NULL;
	char *line = NULL, err[256];
	size_t cap = 0;
	int lineno = 0, rc = 0, saved;
	ssize_t len;
	FILE *fp;

	if (!t)
		return DF1_E_INVAL;
	if (!path)
		return table_fail(t, DF1_E_INVAL, "invalid argument");
	fp = fopen(path, "r");
	if (!fp) {
		saved = errno;
		table_fail(t, DF1_E_SYS, "%s: %s", path, strerror(saved));
		errno = saved;
		return DF1_E_SYS;
	}
	if (df1_table_clone(&work, t) < 0) {
		fclose(fp);
		return table_fail(t, DF1_E_NOMEM, "out of memory");
	}
	errno = 0;
	while ((len = getline(&line, &cap, fp)) >= 0) {
		char *s = line;

		lineno++;
		if (memchr(line, '\0', (size_t)len)) {
			/* C would see the line cut there ("N7:0=5\0junk" as N7:0=5) */
			rc = table_fail(t, DF1_E_CONFIG, "%s:%d: a NUL byte in the line", path, lineno);
			break;
		}
		if (lineno == 1 && strncmp(s, "\xEF\xBB\xBF", 3) == 0)
			s += 3;         /* a UTF-8 byte order mark, as the CSV loaders skip it */
		s = table_strip(s);
		if (!*s)
			continue;
		if (!table_line(work, s, err, sizeof err)) {
			rc = table_fail(t, strcmp(err, "out of memory") == 0 ? DF1_E_NOMEM : DF1_E_CONFIG,
			                "%s:%d: %s", path, lineno, err);
			break;
		}
	}
	if (rc == 0 && ferror(fp)) {
		saved = errno;
		rc = table_fail(t, DF1_E_SYS, "%s: %s", path, strerror(saved));
		errno = saved;
	}
	free(line);
	fclose(fp);
	if (rc == 0)
		table_swap(t, work);
	df1_table_free(work);
	return rc;
}

/* ------------------------------------------------------------------------
 * Save
 * ------------------------------------------------------------------------ */

static void table_save_string(FILE *fp, const struct df1_value *v)
{
	fputc('"', fp);
	for (size_t i = 0; i < v->v.str.len; i++) {
		unsigned char c = (unsigned char)v->v.str.text[i];

		if (c == '"' || c == '\\')
			fprintf(fp, "\\%c", c);
		else if (c < 0x20 || c >= 0x7F)
			fprintf(fp, "\\x%02X", c);
		else
			fputc(c, fp);
	}
	fputc('"', fp);
}

static void table_save_value(FILE *fp, enum df1_file_type type, const struct df1_value *v)
{
	char text[160];

	switch (v->kind) {
	case DF1_VAL_STRING:
		table_save_string(fp, v);
		break;
	case DF1_VAL_TCR:
		/* every control bit, named or not */
		fprintf(fp, "CTL=0x%04X %s=%d %s=%d", (unsigned)v->v.tcr.ctl, type == DF1_FT_R ? "LEN" : "PRE",
		        v->v.tcr.pre, type == DF1_FT_R ? "POS" : "ACC", v->v.tcr.acc);
		break;
	default:
		if (df1_value_format(v, type, text, sizeof text) < 0)
			snprintf(text, sizeof text, "0");
		fputs(text, fp);
		break;
	}
}

static void table_save_file(FILE *fp, enum df1_plc plc, int number, const struct table_file *f)
{
	int per_line = f->type == DF1_FT_ST || f->type == DF1_FT_T || f->type == DF1_FT_C ||
	               f->type == DF1_FT_R ? 1 : 10;

	fprintf(fp, "\n# %s%d: %d elements\n", df1_file_type_name(f->type), number, f->nelem);
	for (int e = 0; e < f->nelem; e++) {
		struct df1_addr a = { .type = f->type, .file = number, .element = e,
		                      .sub = DF1_ADDR_NONE, .bit = DF1_ADDR_NONE };
		struct df1_value v;
		char text[DF1_ADDR_ASCII_MAX + 16];

		if (e % per_line == 0) {
			if (df1_addr_format_plc(plc, &a, text, sizeof text) < 0)
				snprintf(text, sizeof text, "%s%d:%d", df1_file_type_name(f->type), number, e);
			fprintf(fp, "%s%s=", e ? "\n" : "", text);
		} else {
			fputc(',', fp);
		}
		table_get_value(f, &a, &v);
		table_save_value(fp, f->type, &v);
	}
	fputc('\n', fp);
}

int df1_table_save(struct df1_table *t, const char *path)
{
	static unsigned counter;
	char tmp[4096];
	FILE *fp = NULL;
	int fd = -1, saved;

	if (!t)
		return DF1_E_INVAL;
	if (!path || !*path)
		return table_fail(t, DF1_E_INVAL, "invalid argument");
	/* a new file of our own beside the target (the umask applies, as to any file) */
	for (int tries = 0; fd < 0 && tries < 100; tries++) {
		if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp%ld.%u", path, (long)getpid(), counter++) >= sizeof tmp) {
			errno = ENAMETOOLONG;
			break;
		}
		fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
		if (fd < 0 && errno != EEXIST)
			break;
	}
	if (fd < 0 || !(fp = fdopen(fd, "w"))) {
		saved = errno;
		if (fd >= 0) {
			close(fd);
			unlink(tmp);
		}
		table_fail(t, DF1_E_SYS, "%s: %s", path, strerror(saved));
		errno = saved;
		return DF1_E_SYS;
	}
	fprintf(fp, "# libdf1 data table (df1_table_save): ADDRESS=VALUE[,VALUE...] per line,\n"
	            "# as df1_table_load() and df1sim --data read it\n");
	for (int i = 0; i < TABLE_SLOTS; i++)
		if (t->files[i])
			table_save_file(fp, t->plc, i % DF1_TABLE_FILES_MAX, t->files[i]);
	errno = 0;
	if (fflush(fp) != 0 || ferror(fp) || fsync(fileno(fp)) != 0) {
		saved = errno ? errno : EIO;
		fclose(fp);
		unlink(tmp);
		table_fail(t, DF1_E_SYS, "%s: %s", path, strerror(saved));
		errno = saved;
		return DF1_E_SYS;
	}
	if (fclose(fp) != 0 || rename(tmp, path) != 0) {
		saved = errno;
		unlink(tmp);
		table_fail(t, DF1_E_SYS, "%s: %s", path, strerror(saved));
		errno = saved;
		return DF1_E_SYS;
	}
	return 0;
}
