/* SPDX-License-Identifier: MPL-2.0 */
/*
 * config_csv.c - what both configuration loaders (config_net.c, config_map.c)
 * stand on: reading the CSV file with libcsv, the header row and its columns,
 * the cell parsers, and the issue callback.
 *
 * File format (doc/ARCHITECTURE.md 6): spreadsheet-exported CSV, RFC 4180 quoting. The
 * first row that is not blank and not a comment is the header: field identifiers,
 * case-insensitive, in any order, surrounding spaces trimmed; '_', '-' and spaces
 * inside an identifier are ignored ("NAK_Retries" = "nak retries" = "NAKRETRIES").
 * Then one row per item. Ignored: blank rows (every cell empty, e.g. ",,,," from a
 * spreadsheet) and comment rows (a line whose first non-blank character is '#',
 * or a row whose first cell, trimmed, starts with '#'; a tag cannot start with
 * '#'). A UTF-8 byte order mark at the start of the file is skipped. Values are
 * trimmed of spaces and tabs; an empty cell means "not given". A NUL byte in a
 * cell is an error naming the row (in the header: the load fails); the row is
 * skipped.
 *
 * Columns: an unknown column name is an error naming it (a mistyped field silently
 * taking its default would be worse), as is a column given twice or a value
 * under a column with no name. A column with an empty name and no values is
 * ignored (spreadsheets export trailing empty columns).
 *
 * Both loaders: an unreadable file is DF1_E_SYS (errno kept) with an issue naming
 * the path; malformed CSV (a quote inside an unquoted field, text after a closing
 * quote, end of file inside quotes) is DF1_E_CONFIG with the line number, and so
 * is a field longer than CFG_FIELD_LIMIT (64 KiB) bytes in the file (a cell
 * holds 255 characters; longer ones are the row's error, up to that limit).
 * The library never prints: every problem goes to the issue callback.
 */
#include "config/config_int.h"

#include <csv.h>
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* ---- issues ------------------------------------------------------------- */

static void cfg_vreport(struct cfg_load *l, int id, int item, int line, const char *fmt, va_list ap)
{
	struct df1_config_issue is;

	l->issues++;
	if (!l->issue_fn)
		return;
	memset(&is, 0, sizeof is);
	is.catalog_id = id;
	is.item = item;
	is.line = line;
	vsnprintf(is.text, sizeof is.text, fmt, ap);
	l->issue_fn(l->issue_user, &is);
}

__attribute__((format(printf, 5, 6)))
void cfg_report(struct cfg_load *l, int id, int item, int line, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	cfg_vreport(l, id, item, line, fmt, ap);
	va_end(ap);
}

/* Conversion letters of a printf format ("%d %s" -> "ds"); false if too many. */
static bool cfg_format_signature(const char *fmt, char *sig, size_t cap)
{
	size_t n = 0;

	for (; *fmt; fmt++) {
		if (*fmt != '%')
			continue;
		fmt++;
		if (*fmt == '%')
			continue;
		while (*fmt && strchr("-+ #0123456789.hlzjtL", *fmt))
			fmt++;
		if (!*fmt || n + 1 >= cap)
			return false;
		sig[n++] = *fmt;
	}
	sig[n] = '\0';
	return true;
}

/*
 * Report catalog message id. The format comes from the catalog (lib/errors.c) when
 * its conversions are exactly sig, else the seed's text given here as fallback.
 * as_text >= 0: that conversion is a %d in the seed but the value was not a
 * number, so it is printed with %s (the caller passes a string there).
 */
void cfg_catalog(struct cfg_load *l, int id, int item, int line, const char *fallback,
                 const char *sig, int as_text, ...)
{
	const struct df1_catalog_entry *e = df1_catalog_by_id(id);
	const char *fmt = fallback;
	char got[16], fmt2[160];
	va_list ap;

	if (e && e->format && cfg_format_signature(e->format, got, sizeof got) &&
	    strcmp(got, sig) == 0 && strlen(e->format) < sizeof fmt2)
		fmt = e->format;
	if (as_text >= 0) {
		/* rewrite conversion number as_text from d to s */
		const char *p;
		int k = -1;
		size_t i = 0;

		for (p = fmt; *p && i + 1 < sizeof fmt2; p++) {
			fmt2[i++] = *p;
			if (*p != '%')
				continue;
			if (p[1] == '%') {
				fmt2[i++] = *++p;
				continue;
			}
			k++;
			while (p[1] && strchr("-+ #0123456789.", p[1]) && i + 1 < sizeof fmt2)
				fmt2[i++] = *++p;
			if (p[1] && i + 1 < sizeof fmt2) {
				p++;
				fmt2[i++] = (k == as_text && *p == 'd') ? 's' : *p;
			}
		}
		fmt2[i] = '\0';
		fmt = fmt2;
	}
	va_start(ap, as_text);
	cfg_vreport(l, id, item, line, fmt, ap);
	va_end(ap);
}

/* ---- small parsers -------------------------------------------------------- */

static char cfg_upper(char c)
{
	return (c >= 'a' && c <= 'z') ? (char)(c - 'a' + 'A') : c;
}

/* Upper case without the characters in drop; false if it does not fit. */
bool cfg_squash(const char *s, const char *drop, char *out, size_t cap)
{
	size_t n = 0;

	for (; *s; s++) {
		if (strchr(drop, *s))
			continue;
		if (n + 1 >= cap)
			return false;
		out[n++] = cfg_upper(*s);
	}
	out[n] = '\0';
	return true;
}

bool cfg_ieq(const char *a, const char *b)
{
	for (; *a && *b; a++, b++)
		if (cfg_upper(*a) != cfg_upper(*b))
			return false;
	return *a == *b;
}

/* s starts with prefix, ignoring case */
bool cfg_istarts(const char *s, const char *prefix)
{
	for (; *prefix; s++, prefix++)
		if (cfg_upper(*s) != cfg_upper(*prefix))
			return false;
	return true;
}

bool cfg_all_digits(const char *s)
{
	if (!*s)
		return false;
	for (; *s; s++)
		if (*s < '0' || *s > '9')
			return false;
	return true;
}

/* Decimal integer with an optional sign, nothing else; false if not one or beyond long. */
bool cfg_long(const char *s, long *out)
{
	bool neg = false;
	long v = 0;

	if (*s == '+' || *s == '-')
		neg = *s++ == '-';
	if (!cfg_all_digits(s))
		return false;
	for (; *s; s++) {
		if (v > (LONG_MAX - (*s - '0')) / 10)
			return false;
		v = v * 10 + (*s - '0');
	}
	*out = neg ? -v : v;
	return true;
}

bool cfg_int(const char *s, int *out)
{
	long v;

	if (!cfg_long(s, &v) || v < INT_MIN || v > INT_MAX)
		return false;
	*out = (int)v;
	return true;
}

static void cfg_trim(char *s)
{
	size_t n = strlen(s), i = 0;

	while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t'))
		n--;
	while (i < n && (s[i] == ' ' || s[i] == '\t'))
		i++;
	memmove(s, s + i, n - i);
	s[n - i] = '\0';
}

/* 0: ok; DF1_E_CONFIG: unknown. */
int cfg_plc(const char *s, enum df1_plc *plc)
{
	char u[32];
	const char *digits = NULL;

	if (!cfg_squash(s, " -_/.", u, sizeof u))
		return DF1_E_CONFIG;
	if (strcmp(u, "PLC2") == 0) {
		*plc = DF1_PLC_PLC2;
	} else if (strcmp(u, "PLC5") == 0) {
		*plc = DF1_PLC_PLC5;
	} else if (strcmp(u, "PLC3") == 0) {
		*plc = DF1_PLC_PLC3;
	} else if (strcmp(u, "SLC") == 0 || strcmp(u, "SLC500") == 0 || strcmp(u, "SLC503") == 0 ||
	           strcmp(u, "SLC504") == 0 || strcmp(u, "SLC505") == 0) {
		*plc = DF1_PLC_SLC;
	} else if (strcmp(u, "SLC501") == 0 || strcmp(u, "SLC502") == 0) {
		*plc = DF1_PLC_SLC502;
	} else {
		if (strncmp(u, "MICROLOGIX", 10) == 0)
			digits = u + 10;
		else if (strncmp(u, "ML", 2) == 0)
			digits = u + 2;
		if (!digits || (*digits && !cfg_all_digits(digits)))
			return DF1_E_CONFIG;
		*plc = DF1_PLC_MICROLOGIX;
	}
	return 0;
}


/* ---- the CSV reader --------------------------------------------------------- */

static void cfg_row_reset(struct cfg_row *row)
{
	row->nfields = 0;
	row->line = 0;
	row->overflow = false;
}

static void cfg_on_field(void *s, size_t len, void *data)
{
	struct cfg_load *l = data;
	struct cfg_row *row = &l->row;
	int i = row->nfields;

	if (i == 0)
		row->line = l->line;
	if (i >= CFG_MAX_COLS) {
		row->overflow = true;
		return;
	}
	row->has_nul[i] = len > 0 && s && memchr(s, '\0', len) != NULL;
	row->too_long[i] = len >= CFG_FIELD_MAX;
	if (row->too_long[i])
		len = CFG_FIELD_MAX - 1;
	if (len > 0 && s)
		memcpy(row->field[i], s, len);
	row->field[i][len] = '\0';
	cfg_trim(row->field[i]);
	row->nfields++;
}

static bool cfg_row_is_blank(const struct cfg_row *row)
{
	int i;

	for (i = 0; i < row->nfields; i++)
		if (row->field[i][0] != '\0' || row->has_nul[i])
			return false;
	return !row->overflow;
}

static int cfg_field_index(const struct cfg_load *l, const char *name)
{
	char want[CFG_FIELD_MAX], have[64];
	int i;

	if (!cfg_squash(name, " _-", want, sizeof want))
		return -1;
	for (i = 0; i < l->nnames; i++)
		if (cfg_squash(l->names[i], " _-", have, sizeof have) && strcmp(want, have) == 0)
			return i;
	return -1;
}

static void cfg_header(struct cfg_load *l, struct cfg_row *row)
{
	int i, j, errors = l->issues;
	size_t k;

	l->have_header = true;
	l->header_line = row->line;
	l->ncols = row->nfields;
	if (row->overflow)
		cfg_report(l, 0, 0, row->line, "Too many columns (more than %d)", CFG_MAX_COLS);
	for (i = 0; i < row->nfields; i++) {
		l->colmap[i] = -1;
		if (row->has_nul[i]) {
			cfg_report(l, 0, 0, row->line, "Column %d of the header (%.64s) holds a NUL byte",
			           i + 1, row->field[i]);
			continue;
		}
		if (row->field[i][0] == '\0')
			continue;
		l->colmap[i] = cfg_field_index(l, row->field[i]);
		if (l->colmap[i] < 0) {
			char list[256];
			size_t n = 0;

			list[0] = '\0';
			for (j = 0; j < l->nnames; j++)
				n += (size_t)snprintf(list + n, n < sizeof list ? sizeof list - n : 0,
				                      "%s%s", j ? ", " : "", l->names[j]);
			cfg_report(l, 0, 0, row->line, "Unknown column (%.64s), should be one of %s",
			           row->field[i], list);
			continue;
		}
		for (j = 0; j < i; j++)
			if (l->colmap[j] == l->colmap[i])
				cfg_report(l, 0, 0, row->line, "Column %s given twice",
				           l->names[l->colmap[i]]);
	}
	for (k = 0; k < l->nrequired; k++) {
		bool found = false;

		for (i = 0; i < l->ncols; i++)
			found = found || l->colmap[i] == l->required[k];
		if (!found)
			cfg_report(l, 0, 0, row->line, "Missing column %s", l->names[l->required[k]]);
	}
	if (l->issues != errors)
		l->stop = DF1_E_CONFIG;
}

/* Value of field f in row ("" if the column is absent or the row is short). */
const char *cfg_value(const struct cfg_load *l, const struct cfg_row *row, int f)
{
	int i;

	for (i = 0; i < l->ncols && i < row->nfields; i++)
		if (l->colmap[i] == f)
			return row->field[i];
	return "";
}

/* Cells the header does not name, overlong cells, cells with a NUL byte (C
 * would see them cut at it); reported with the row's item. Returns the number
 * of cells with a NUL byte. */
int cfg_check_cells(struct cfg_load *l, const struct cfg_row *row, bool with_item)
{
	int i, nul = 0;
	const char *prefix = with_item ? "Item: " : "Row ";

	if (row->overflow)
		cfg_report(l, 0, l->item, row->line, "%s%d, too many cells (more than %d)", prefix,
		           l->item, CFG_MAX_COLS);
	for (i = 0; i < row->nfields; i++) {
		if (row->has_nul[i]) {
			nul++;
			if (i >= l->ncols || l->colmap[i] < 0)
				cfg_report(l, 0, l->item, row->line,
				           "%s%d, the value in column %d holds a NUL byte", prefix,
				           l->item, i + 1);
			else
				cfg_report(l, 0, l->item, row->line, "%s%d, %s holds a NUL byte", prefix,
				           l->item, l->names[l->colmap[i]]);
			continue;
		}
		if (row->field[i][0] == '\0')
			continue;
		if (i >= l->ncols || l->colmap[i] < 0)
			cfg_report(l, 0, l->item, row->line,
			           "%s%d, value (%.64s) in column %d, which has no name in the header",
			           prefix, l->item, row->field[i], i + 1);
		else if (row->too_long[i])
			cfg_report(l, 0, l->item, row->line, "%s%d, %s is too long (max %d characters)",
			           prefix, l->item, l->names[l->colmap[i]], CFG_FIELD_MAX - 1);
	}
	return nul;
}

static void cfg_on_row(int c, void *data)
{
	struct cfg_load *l = data;
	struct cfg_row *row = &l->row;

	(void)c;
	if (l->stop < 0 || cfg_row_is_blank(row) || (row->nfields > 0 && row->field[0][0] == '#')) {
		cfg_row_reset(row);
		return;
	}
	if (!l->have_header) {
		cfg_header(l, row);
	} else {
		l->item++;
		l->on_data(l, row);
	}
	cfg_row_reset(row);
}

static int cfg_flush(struct cfg_load *l)
{
	size_t n = l->seg_len;

	l->seg_len = 0;
	l->seg_line_start = 0;
	if (n == 0)
		return 0;
	if (csv_parse(&l->parser, l->seg, n, cfg_on_field, cfg_on_row, l) != n) {
		int e = csv_error(&l->parser);

		cfg_report(l, 0, 0, l->line, "Malformed CSV at line %d: %s", l->line,
		           e == CSV_EPARSE ? "stray quote (a quote inside an unquoted field, "
		                             "or text after a closing quote)"
		                           : csv_strerror(e));
		return csv_error(&l->parser) == CSV_ENOMEM ? DF1_E_NOMEM : DF1_E_CONFIG;
	}
	return 0;
}

/* Feed raw file bytes: comment lines are dropped here, the rest goes to libcsv
 * one line at a time, so that l->line is right in the callbacks. */
static int cfg_feed(struct cfg_load *l, const char *buf, size_t n)
{
	size_t i;
	int rc;

	for (i = 0; i < n; i++) {
		char c = buf[i];
		bool nl = c == '\n' || c == '\r';

		/* a field ends at a comma or a line end outside quotes (comments are
		 * not fields) */
		if (!l->in_quotes && (c == ',' || nl)) {
			l->field_len = 0;
		} else if (!l->in_comment && !(l->line_start && c == '#') &&
		           ++l->field_len > CFG_FIELD_LIMIT) {
			cfg_report(l, 0, 0, l->line, "Field too long at line %d: longer than %d bytes "
			           "(a cell holds at most %d characters)", l->line, CFG_FIELD_LIMIT,
			           CFG_FIELD_MAX - 1);
			return DF1_E_CONFIG;
		}
		if (l->in_comment) {
			if (nl)
				l->in_comment = false;
		} else if (l->line_start && (c == ' ' || c == '\t')) {
			l->seg[l->seg_len++] = c;
		} else if (l->line_start && c == '#') {
			l->seg_len = l->seg_line_start;
			l->in_comment = true;
			l->line_start = false;
		} else {
			l->line_start = false;
			l->seg[l->seg_len++] = c;
			if (c == '"')
				l->in_quotes = !l->in_quotes;
			if (nl) {
				rc = cfg_flush(l);
				if (rc < 0)
					return rc;
			}
		}
		if (nl) {
			if (c == '\r' || !l->prev_cr)
				l->line++;
			l->prev_cr = c == '\r';
			if (!l->in_quotes && !l->in_comment) {
				l->line_start = true;
				l->seg_line_start = l->seg_len;
			}
		} else {
			l->prev_cr = false;
		}
		if (l->seg_len == sizeof l->seg) {
			/* a very long line: hand it over; comment detection falls back to the
			 * first cell of the parsed row */
			rc = cfg_flush(l);
			if (rc < 0)
				return rc;
			l->line_start = false;
		}
	}
	return 0;
}

/* Read the whole file through libcsv. 0, DF1_E_SYS, DF1_E_CONFIG or DF1_E_NOMEM. */
int cfg_read(struct cfg_load *l, FILE *f, const char *path)
{
	char buf[CFG_READ_CHUNK];
	bool first = true;
	size_t n;
	int rc = 0;

	l->line = 1;
	l->in_quotes = l->in_comment = l->prev_cr = false;
	l->line_start = true;
	l->seg_len = l->seg_line_start = 0;
	l->field_len = 0;
	l->have_header = false;
	l->item = 0;
	l->stop = 0;
	cfg_row_reset(&l->row);
	if (csv_init(&l->parser, CSV_STRICT | CSV_STRICT_FINI | CSV_APPEND_NULL) != 0)
		return DF1_E_NOMEM;
	/* libcsv grows its field buffer by a block at a time (128 bytes by default:
	 * a long field meant a realloc every 128 bytes); fields stop at
	 * CFG_FIELD_LIMIT (cfg_feed), so a few blocks at most */
	csv_set_blk_size(&l->parser, CFG_CSV_BLOCK);
	while (rc == 0 && (n = fread(buf, 1, sizeof buf, f)) > 0) {
		const char *p = buf;

		if (first && n >= 3 && memcmp(buf, "\xEF\xBB\xBF", 3) == 0) {
			p += 3;
			n -= 3;
		}
		first = false;
		rc = cfg_feed(l, p, n);
	}
	if (rc == 0 && ferror(f)) {
		int e = errno;
		char eb[80];

		cfg_report(l, 0, 0, l->line, "Cannot read %.120s: %s", path,
		           strerror_r(e, eb, sizeof eb));
		errno = e;
		rc = DF1_E_SYS;
	}
	if (rc == 0)
		rc = cfg_flush(l);
	if (rc == 0 && csv_fini(&l->parser, cfg_on_field, cfg_on_row, l) != 0) {
		cfg_report(l, 0, 0, l->line, "Malformed CSV: end of file inside a quoted field");
		rc = DF1_E_CONFIG;
	}
	csv_free(&l->parser);
	if (rc == 0 && !l->have_header) {
		cfg_report(l, 0, 0, l->line, "%.150s: no header row", path);
		rc = DF1_E_CONFIG;
	}
	return rc;
}

FILE *cfg_open(struct cfg_load *l, const char *path)
{
	FILE *f = fopen(path, "rb");

	if (!f) {
		int e = errno;
		char eb[80];

		cfg_report(l, 0, 0, 0, "Cannot open %.120s: %s", path, strerror_r(e, eb, sizeof eb));
		errno = e;
	}
	return f;
}

void cfg_init(struct cfg_load *l, df1_config_issue_fn fn, void *user,
              const char *const *names, int nnames, const int *required,
              size_t nrequired, cfg_row_fn on_data, void *ctx)
{
	memset(l, 0, sizeof *l);
	l->issue_fn = fn;
	l->issue_user = user;
	l->names = names;
	l->nnames = nnames;
	l->required = required;
	l->nrequired = nrequired;
	l->on_data = on_data;
	l->ctx = ctx;
}
