/*
 * config.c - network and mapping configuration files (CSV, read with libcsv).
 *
 * File format (DESIGN.md 6): spreadsheet-exported CSV, RFC 4180 quoting. The
 * first row that is not blank and not a comment is the header: field identifiers,
 * case-insensitive, in any order, surrounding spaces trimmed; '_', '-' and spaces
 * inside an identifier are ignored ("NAK_Retries" = "nak retries" = "NAKRETRIES").
 * Then one row per item. Ignored: blank rows (every cell empty, e.g. ",,,," from a
 * spreadsheet) and comment rows (a line whose first non-blank character is '#',
 * or a row whose first cell, trimmed, starts with '#'; a tag cannot start with
 * '#'). A UTF-8 byte order mark at the start of the file is skipped. Values are
 * trimmed of spaces and tabs; an empty cell means "not given".
 *
 * Columns: an unknown column name is an error naming it (a mistyped field silently
 * taking its default would be worse), as is a column given twice or a value
 * under a column with no name. A column with an empty name and no values is
 * ignored (spreadsheets export trailing empty columns).
 *
 * Network file (seeds/004, "Network Configuration Parameters"): the first data
 * row is used, later rows are ignored; a file with a header and no data row gives
 * the defaults. Every invalid value is reported, then the load fails with
 * DF1_E_CONFIG and *c is left untouched:
 *   Station      0-254, default 5                     2552 CRT_BAD_STATION_ID
 *   Mode         Master | Slave | Peer, default Master 2553 CRT_BAD_DRIVER_MODE
 *                (2554 CRT_UNSUPPORTED_MODE never fires: libdf1 supports all three)
 *   PLC_Type     PLC2 | PLC5 | SLC | MicroLogix, default PLC5
 *                                                     2555 CRT_BAD_PLC_TYPE
 *                also accepted: "PLC-5" and the like ('-', '_', '/', '.' and spaces
 *                are ignored), SLC500, SLC503-505 (SLC), SLC501/SLC502 ("SLC 5/02":
 *                82-byte packets), ML, MicroLogix1400, ML1100 ... (MicroLogix).
 *                PLC3 is recognised but not supported by libdf1: 2555 too.
 *   Error_Code   BCC | CRC, default CRC                2556 CRT_BAD_ERROR_CODE
 *   NAK_Retries  0-10, default 3                       2557 CRT_BAD_NAK_RETRIES
 *   ENQ_Retries  0-10, default 3                       2558 CRT_BAD_ENQ_RETRIES
 *   Cmd_Timeout  500-5000 ms, default 1000             2559 CRT_BAD_CMD_TIMEOUT
 *   Com_Port     n (1 -> /dev/ttyS0, n -> /dev/ttyS(n-1), 1-256), COMn (the same),
 *                an absolute device path, or tcp://host:port; default 1
 *   Baud         1200 2400 4800 9600 19200 38400 57600 115200, default 9600
 *   Data_Bits    5-8, default 8;  Stop_Bits 1-2, default 1
 *   Parity       None | Even | Odd (or N E O), default None
 *   Timeout      0-360000 ms, default 1000;  TX_Delay 0-65535 ms, default 0
 *   Handshake    Yes | No (or Y N), default No
 * The last seven have no catalog ID: they are reported with catalog_id 0 and a
 * text in the seed's style naming the field and the valid values. Mode Master or
 * Slave sets duplex_half (half duplex, multidrop), Peer clears it (full duplex).
 *
 * Mapping file (seeds/004, "Mapping Parameters"): columns Tag, Station, PLC_Type,
 * Address are required (a missing column fails the load); Command (Read, Write,
 * ReadWrite; also RW and "Read/Write"; default Read), Type (informational, up to
 * 15 characters), Count (elements, 1-1000, default 1), Scan_Ms (1-86400000,
 * default 1000) are optional. Item numbers are 1-based data rows (blank and comment
 * rows not counted). Per row:
 *   Station not 0-254 (or not a number)      2501 ERR_BAD_STATION
 *   PLC_Type invalid or unsupported          2502 ERR_BAD_PLC_TYPE
 *   Address malformed                        2503 ERR_ADDRESS_SYNTAX
 *   Address out of range, Count below 1, or element + Count - 1 above 999
 *                                            2504 ERR_ADDRESS_RANGE (len = Count)
 *   Tag missing or longer than 63, Command, Type, Count not a number, Scan_Ms
 *                                            catalog 0, "Item: n, ..." text
 * Bad rows are reported and skipped. In strict mode the file is checked first and
 * row_fn is called only when every row is valid. A row_fn returning a negative
 * value stops the load, which returns that value. On any failure the caller should
 * discard the rows it received.
 *
 * Both loaders: an unreadable file is DF1_E_SYS (errno kept) with an issue naming
 * the path; malformed CSV (a quote inside an unquoted field, text after a closing
 * quote, end of file inside quotes) is DF1_E_CONFIG with the line number.
 * The library never prints: every problem goes to the issue callback.
 */
#include "df1.h"

#include <csv.h>
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#define CFG_MAX_COLS 32
#define CFG_FIELD_MAX 256          /* bytes per cell, with the NUL (Com_Port is 255 max) */
#define CFG_SEG_MAX 4096           /* bytes handed to libcsv at a time */
#define CFG_READ_CHUNK 4096

#define STATION_LIMIT 255          /* "must be less than %d" */
#define RETRIES_MAX 10
#define CMD_TIMEOUT_MIN 500
#define CMD_TIMEOUT_MAX 5000
#define TIMEOUT_MAX 360000
#define TX_DELAY_MAX 65535
#define COM_PORT_MAX 256
#define COUNT_MAX 1000
#define SCAN_MS_MAX 86400000L
#define ELEMENT_MAX 999

/* ---- issues ------------------------------------------------------------- */

struct cfg_row {
	int nfields;
	int line;                           /* line of the row's first field */
	bool overflow;                      /* more than CFG_MAX_COLS cells */
	bool too_long[CFG_MAX_COLS];
	char field[CFG_MAX_COLS][CFG_FIELD_MAX];
};

struct cfg_load;
typedef void (*cfg_row_fn)(struct cfg_load *l, struct cfg_row *row);

struct cfg_load {
	/* issues */
	df1_config_issue_fn issue_fn;
	void *issue_user;
	int issues;

	/* reader */
	struct csv_parser parser;
	int line;
	bool in_quotes, line_start, in_comment, prev_cr;
	size_t seg_len, seg_line_start;
	char seg[CFG_SEG_MAX];
	struct cfg_row row;
	int stop;                           /* < 0: stop handling rows, return this */

	/* header */
	const char *const *names;           /* field identifiers of this file kind */
	int nnames;
	const int *required;                /* fields whose column must be present */
	size_t nrequired;
	bool have_header;
	int ncols;
	int colmap[CFG_MAX_COLS];           /* column -> field index, -1 = unnamed */
	int header_line;

	/* data */
	int item;                           /* data rows seen */
	cfg_row_fn on_data;
	void *ctx;
};

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
static void cfg_report(struct cfg_load *l, int id, int item, int line, const char *fmt, ...)
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
static void cfg_catalog(struct cfg_load *l, int id, int item, int line, const char *fallback,
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
static bool cfg_squash(const char *s, const char *drop, char *out, size_t cap)
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

static bool cfg_ieq(const char *a, const char *b)
{
	for (; *a && *b; a++, b++)
		if (cfg_upper(*a) != cfg_upper(*b))
			return false;
	return *a == *b;
}

/* s starts with prefix, ignoring case */
static bool cfg_istarts(const char *s, const char *prefix)
{
	for (; *prefix; s++, prefix++)
		if (cfg_upper(*s) != cfg_upper(*prefix))
			return false;
	return true;
}

static bool cfg_all_digits(const char *s)
{
	if (!*s)
		return false;
	for (; *s; s++)
		if (*s < '0' || *s > '9')
			return false;
	return true;
}

/* Decimal integer with an optional sign, nothing else; false if not one or beyond long. */
static bool cfg_long(const char *s, long *out)
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

static bool cfg_int(const char *s, int *out)
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

/* 0: ok; DF1_E_NOTSUP: recognised, not supported (PLC-3); DF1_E_CONFIG: unknown. */
static int cfg_plc(const char *s, enum df1_plc *plc)
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
		return DF1_E_NOTSUP;
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

#define PLC_CHOICES "PLC2", "PLC5", "SLC", "MicroLogix"

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
		if (row->field[i][0] != '\0')
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
static const char *cfg_value(const struct cfg_load *l, const struct cfg_row *row, int f)
{
	int i;

	for (i = 0; i < l->ncols && i < row->nfields; i++)
		if (l->colmap[i] == f)
			return row->field[i];
	return "";
}

/* Cells the header does not name, overlong cells; reported with the row's item. */
static void cfg_check_cells(struct cfg_load *l, const struct cfg_row *row, bool with_item)
{
	int i;
	const char *prefix = with_item ? "Item: " : "Row ";

	if (row->overflow)
		cfg_report(l, 0, l->item, row->line, "%s%d, too many cells (more than %d)", prefix,
		           l->item, CFG_MAX_COLS);
	for (i = 0; i < row->nfields; i++) {
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
static int cfg_read(struct cfg_load *l, FILE *f, const char *path)
{
	char buf[CFG_READ_CHUNK];
	bool first = true;
	size_t n;
	int rc = 0;

	l->line = 1;
	l->in_quotes = l->in_comment = l->prev_cr = false;
	l->line_start = true;
	l->seg_len = l->seg_line_start = 0;
	l->have_header = false;
	l->item = 0;
	l->stop = 0;
	cfg_row_reset(&l->row);
	if (csv_init(&l->parser, CSV_STRICT | CSV_STRICT_FINI | CSV_APPEND_NULL) != 0)
		return DF1_E_NOMEM;
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

static FILE *cfg_open(struct cfg_load *l, const char *path)
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

static void cfg_init(struct cfg_load *l, df1_config_issue_fn fn, void *user,
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

/* ---- network file ----------------------------------------------------------- */

enum cfg_net_field {
	NF_STATION, NF_MODE, NF_PLC_TYPE, NF_ERROR_CODE, NF_NAK_RETRIES, NF_ENQ_RETRIES,
	NF_CMD_TIMEOUT, NF_COM_PORT, NF_BAUD, NF_DATA_BITS, NF_STOP_BITS, NF_PARITY,
	NF_TIMEOUT, NF_TX_DELAY, NF_HANDSHAKE, NF_COUNT
};

static const char *const cfg_net_names[NF_COUNT] = {
	"Station", "Mode", "PLC_Type", "Error_Code", "NAK_Retries", "ENQ_Retries",
	"Cmd_Timeout", "Com_Port", "Baud", "Data_Bits", "Stop_Bits", "Parity",
	"Timeout", "TX_Delay", "Handshake",
};

void df1_net_config_defaults(struct df1_net_config *c)
{
	if (!c)
		return;
	memset(c, 0, sizeof *c);
	c->station = 5;
	c->mode = DF1_MODE_MASTER;
	c->plc = DF1_PLC_PLC5;
	c->check = DF1_CHECK_CRC;
	c->nak_retries = 3;
	c->enq_retries = 3;
	c->cmd_timeout_ms = 1000;
	strcpy(c->port, "/dev/ttyS0");
	c->baud = 9600;
	c->data_bits = 8;
	c->stop_bits = 1;
	c->parity = 'N';
	c->timeout_ms = 1000;
	c->tx_delay_ms = 0;
	c->handshake = false;
	c->duplex_half = true;
}

struct cfg_net_ctx {
	struct df1_net_config cfg;
};

/* An integer in [lo, hi] for a field without a catalog ID. */
static bool cfg_net_range(struct cfg_load *l, int line, const char *label, const char *v, int lo,
                      int hi, int *out)
{
	int x;

	if (cfg_int(v, &x) && x >= lo && x <= hi) {
		*out = x;
		return true;
	}
	cfg_report(l, 0, l->item, line, "Invalid %s (%.64s) should be in range [%d, %d]", label, v,
	           lo, hi);
	return false;
}

/* Catalog fields "(%d) ... [0, %d]" style: value, then the limits in args. */
static void cfg_net_bad_int(struct cfg_load *l, int id, int line, const char *v,
                            const char *fallback, const char *sig, int a1, int a2)
{
	int x;

	if (cfg_int(v, &x)) {
		if (sig[2])
			cfg_catalog(l, id, l->item, line, fallback, sig, -1, x, a1, a2);
		else
			cfg_catalog(l, id, l->item, line, fallback, sig, -1, x, a1);
	} else {
		if (sig[2])
			cfg_catalog(l, id, l->item, line, fallback, sig, 0, v, a1, a2);
		else
			cfg_catalog(l, id, l->item, line, fallback, sig, 0, v, a1);
	}
}

static bool cfg_net_port(const char *v, char *out, size_t cap)
{
	int n;

	if (cfg_all_digits(v) || (cfg_istarts(v, "COM") && cfg_all_digits(v + 3))) {
		if (!cfg_int(cfg_all_digits(v) ? v : v + 3, &n) || n < 1 || n > COM_PORT_MAX)
			return false;
		snprintf(out, cap, "/dev/ttyS%d", n - 1);
		return true;
	}
	if (v[0] == '/') {
		if (strlen(v) >= cap)
			return false;
		strcpy(out, v);
		return true;
	}
	if (cfg_istarts(v, "tcp://")) {
		const char *host = v + 6, *colon = strrchr(host, ':');
		int port;

		if (!colon || colon == host || strchr(host, '/') || !cfg_all_digits(colon + 1) ||
		    !cfg_int(colon + 1, &port) || port < 1 || port > 65535 || strlen(v) >= cap)
			return false;
		snprintf(out, cap, "tcp://%s", host);
		return true;
	}
	return false;
}

static void cfg_net_row(struct cfg_load *l, struct cfg_row *row)
{
	struct df1_net_config *c = &((struct cfg_net_ctx *)l->ctx)->cfg;
	const char *v;
	int x, line = row->line;

	if (l->item > 1)
		return; /* the first data row configures the module */
	cfg_check_cells(l, row, false);

	v = cfg_value(l, row, NF_STATION);
	if (*v) {
		if (cfg_int(v, &x) && x >= 0 && x < STATION_LIMIT)
			c->station = x;
		else
			cfg_net_bad_int(l, 2552, line, v, "Invalid station number (%d) must be less than %d",
			            "dd", STATION_LIMIT, 0);
	}
	v = cfg_value(l, row, NF_MODE);
	if (*v) {
		if (cfg_ieq(v, "Master"))
			c->mode = DF1_MODE_MASTER;
		else if (cfg_ieq(v, "Slave"))
			c->mode = DF1_MODE_SLAVE;
		else if (cfg_ieq(v, "Peer"))
			c->mode = DF1_MODE_PEER;
		else
			cfg_catalog(l, 2553, l->item, line,
			            "Invalid Driver Mode (%s), should be one of %s, %s, or %s", "ssss", -1,
			            v, "Master", "Slave", "Peer");
		c->duplex_half = c->mode != DF1_MODE_PEER;
	}
	v = cfg_value(l, row, NF_PLC_TYPE);
	if (*v && cfg_plc(v, &c->plc) < 0)
		cfg_catalog(l, 2555, l->item, line,
		            "Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s",
		            "sssss", -1, v, PLC_CHOICES);
	v = cfg_value(l, row, NF_ERROR_CODE);
	if (*v) {
		if (cfg_ieq(v, "CRC"))
			c->check = DF1_CHECK_CRC;
		else if (cfg_ieq(v, "BCC"))
			c->check = DF1_CHECK_BCC;
		else
			cfg_catalog(l, 2556, l->item, line,
			            "Invalid Error Code (%s), should be either %s, or %s", "sss", -1, v,
			            "BCC", "CRC");
	}
	v = cfg_value(l, row, NF_NAK_RETRIES);
	if (*v) {
		if (cfg_int(v, &x) && x >= 0 && x <= RETRIES_MAX)
			c->nak_retries = x;
		else
			cfg_net_bad_int(l, 2557, line, v, "Invalid NAK Retries (%d) should be in range [0, %d]",
			            "dd", RETRIES_MAX, 0);
	}
	v = cfg_value(l, row, NF_ENQ_RETRIES);
	if (*v) {
		if (cfg_int(v, &x) && x >= 0 && x <= RETRIES_MAX)
			c->enq_retries = x;
		else
			cfg_net_bad_int(l, 2558, line, v, "Invalid ENQ Retries (%d) should be in range [0, %d]",
			            "dd", RETRIES_MAX, 0);
	}
	v = cfg_value(l, row, NF_CMD_TIMEOUT);
	if (*v) {
		if (cfg_int(v, &x) && x >= CMD_TIMEOUT_MIN && x <= CMD_TIMEOUT_MAX)
			c->cmd_timeout_ms = x;
		else
			cfg_net_bad_int(l, 2559, line, v,
			            "Invalid Cmd Timeout (%d) should be in range [%d, %d]", "ddd",
			            CMD_TIMEOUT_MIN, CMD_TIMEOUT_MAX);
	}
	v = cfg_value(l, row, NF_COM_PORT);
	c->port_given = *v != '\0';
	if (*v && !cfg_net_port(v, c->port, sizeof c->port))
		cfg_report(l, 0, l->item, line,
		           "Invalid Com Port (%.64s) should be a port number [1, %d], COMn, a device "
		           "path (/dev/...) or tcp://host:port", v, COM_PORT_MAX);
	v = cfg_value(l, row, NF_BAUD);
	if (*v) {
		static const int bauds[] = { 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200 };
		size_t i;
		bool ok = false;

		if (cfg_int(v, &x))
			for (i = 0; i < sizeof bauds / sizeof bauds[0]; i++)
				ok = ok || x == bauds[i];
		if (ok)
			c->baud = x;
		else
			cfg_report(l, 0, l->item, line, "Invalid Baud (%.64s) should be one of 1200, 2400, "
			           "4800, 9600, 19200, 38400, 57600, or 115200", v);
	}
	v = cfg_value(l, row, NF_DATA_BITS);
	if (*v)
		cfg_net_range(l, line, "Data Bits", v, 5, 8, &c->data_bits);
	v = cfg_value(l, row, NF_STOP_BITS);
	if (*v)
		cfg_net_range(l, line, "Stop Bits", v, 1, 2, &c->stop_bits);
	v = cfg_value(l, row, NF_PARITY);
	if (*v) {
		if (cfg_ieq(v, "None") || cfg_ieq(v, "N"))
			c->parity = 'N';
		else if (cfg_ieq(v, "Even") || cfg_ieq(v, "E"))
			c->parity = 'E';
		else if (cfg_ieq(v, "Odd") || cfg_ieq(v, "O"))
			c->parity = 'O';
		else
			cfg_report(l, 0, l->item, line,
			           "Invalid Parity (%.64s), should be one of Odd, Even, or None", v);
	}
	v = cfg_value(l, row, NF_TIMEOUT);
	if (*v)
		cfg_net_range(l, line, "Timeout", v, 0, TIMEOUT_MAX, &c->timeout_ms);
	v = cfg_value(l, row, NF_TX_DELAY);
	if (*v)
		cfg_net_range(l, line, "TX Delay", v, 0, TX_DELAY_MAX, &c->tx_delay_ms);
	v = cfg_value(l, row, NF_HANDSHAKE);
	if (*v) {
		if (cfg_ieq(v, "Yes") || cfg_ieq(v, "Y"))
			c->handshake = true;
		else if (cfg_ieq(v, "No") || cfg_ieq(v, "N"))
			c->handshake = false;
		else
			cfg_report(l, 0, l->item, line,
			           "Invalid Handshake (%.64s), should be either Yes, or No", v);
	}
}

int df1_net_config_load(const char *path, struct df1_net_config *c, df1_config_issue_fn fn,
                        void *user)
{
	struct cfg_load l;
	struct cfg_net_ctx ctx;
	FILE *f;
	int rc;

	if (!path || !c)
		return DF1_E_INVAL;
	df1_net_config_defaults(&ctx.cfg);
	cfg_init(&l, fn, user, cfg_net_names, NF_COUNT, NULL, 0, cfg_net_row, &ctx);
	f = cfg_open(&l, path);
	if (!f)
		return DF1_E_SYS;
	rc = cfg_read(&l, f, path);
	fclose(f);
	if (rc == 0 && l.stop < 0)
		rc = l.stop;
	if (rc == 0 && l.issues > 0)
		rc = DF1_E_CONFIG;
	if (rc == 0)
		*c = ctx.cfg;
	return rc;
}

int df1_apply_net_config(df1_t *h, const struct df1_net_config *c)
{
	enum df1_duplex duplex;
	int rc;

	if (!h || !c)
		return DF1_E_INVAL;
	if (c->mode == DF1_MODE_PEER || !c->duplex_half)
		duplex = DF1_FULL_DUPLEX;
	else if (c->mode == DF1_MODE_SLAVE)
		duplex = DF1_HALF_DUPLEX_SLAVE;
	else
		duplex = DF1_HALF_DUPLEX_MASTER;
	rc = df1_set_serial(h, c->baud, c->data_bits, c->parity, c->stop_bits);
	if (rc >= 0)
		rc = df1_set_handshake(h, c->handshake);
	if (rc >= 0)
		rc = df1_set_duplex(h, duplex);
	if (rc >= 0)
		rc = df1_set_check(h, c->check);
	if (rc >= 0)
		rc = df1_set_station(h, c->station);
	if (rc >= 0)
		rc = df1_set_plc(h, c->plc);
	if (rc >= 0)
		rc = df1_set_timeout_ms(h, c->timeout_ms);
	if (rc >= 0)
		rc = df1_set_cmd_timeout_ms(h, c->cmd_timeout_ms);
	if (rc >= 0)
		rc = df1_set_retries(h, c->nak_retries, c->enq_retries);
	if (rc >= 0)
		rc = df1_set_tx_delay_ms(h, c->tx_delay_ms);
	return rc < 0 ? rc : 0;
}

/* ---- mapping file ------------------------------------------------------------- */

enum cfg_map_field {
	MF_TAG, MF_COMMAND, MF_TYPE, MF_STATION, MF_PLC_TYPE, MF_ADDRESS, MF_COUNT, MF_SCAN_MS,
	MF_COUNT_
};

static const char *const cfg_map_names[MF_COUNT_] = {
	"Tag", "Command", "Type", "Station", "PLC_Type", "Address", "Count", "Scan_Ms",
};

static const int cfg_map_required[] = { MF_TAG, MF_STATION, MF_PLC_TYPE, MF_ADDRESS };

struct cfg_map_ctx {
	bool deliver;               /* call row_fn (false: strict mode's checking pass) */
	df1_tag_row_fn row_fn;
	void *user;
	int loaded;
};

static void cfg_map_row(struct cfg_load *l, struct cfg_row *row)
{
	struct cfg_map_ctx *m = l->ctx;
	struct df1_tag_config t;
	const char *v, *addr;
	char u[16];
	int item = l->item, line = row->line, before = l->issues, rc, x;
	long lv;

	memset(&t, 0, sizeof t);
	cfg_check_cells(l, row, true);

	v = cfg_value(l, row, MF_TAG);
	if (!*v)
		cfg_report(l, 0, item, line, "Item: %d, missing Tag", item);
	else if (strlen(v) >= sizeof t.name)
		cfg_report(l, 0, item, line, "Item: %d, Tag (%.64s) is too long (max %d characters)",
		           item, v, (int)sizeof t.name - 1);
	else
		strcpy(t.name, v);

	v = cfg_value(l, row, MF_COMMAND);
	t.access = DF1_ACCESS_READ;
	if (*v) {
		if (!cfg_squash(v, " _-/", u, sizeof u))
			u[0] = '\0';
		if (strcmp(u, "READ") == 0)
			t.access = DF1_ACCESS_READ;
		else if (strcmp(u, "WRITE") == 0)
			t.access = DF1_ACCESS_WRITE;
		else if (strcmp(u, "READWRITE") == 0 || strcmp(u, "RW") == 0)
			t.access = DF1_ACCESS_READWRITE;
		else
			cfg_report(l, 0, item, line,
			           "Item: %d, Invalid Command (%.64s) should be one of Read, Write, or "
			           "ReadWrite", item, v);
	}

	v = cfg_value(l, row, MF_TYPE);
	if (strlen(v) >= sizeof t.type)
		cfg_report(l, 0, item, line, "Item: %d, Type (%.64s) is too long (max %d characters)",
		           item, v, (int)sizeof t.type - 1);
	else
		strcpy(t.type, v);

	v = cfg_value(l, row, MF_STATION);
	if (cfg_int(v, &x) && x >= 0 && x < STATION_LIMIT)
		t.station = x;
	else if (cfg_int(v, &x))
		cfg_catalog(l, 2501, item, line,
		            "Item: %d, Invalid station number (%d) must be less than %d", "ddd", -1, item,
		            x, STATION_LIMIT);
	else
		cfg_catalog(l, 2501, item, line,
		            "Item: %d, Invalid station number (%d) must be less than %d", "ddd", 1, item,
		            v, STATION_LIMIT);

	v = cfg_value(l, row, MF_PLC_TYPE);
	if (cfg_plc(v, &t.plc) < 0)
		cfg_catalog(l, 2502, item, line,
		            "Item: %d, Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s",
		            "dsssss", -1, item, v, PLC_CHOICES);

	v = cfg_value(l, row, MF_COUNT);
	t.count = 1;
	if (*v && !cfg_long(v, &lv))
		cfg_report(l, 0, item, line, "Item: %d, Invalid Count (%.64s) should be a number of "
		           "elements [1, %d]", item, v, COUNT_MAX);
	else if (*v)
		t.count = lv < INT_MIN ? INT_MIN : lv > INT_MAX ? INT_MAX : (int)lv;

	addr = cfg_value(l, row, MF_ADDRESS);
	rc = df1_addr_parse(addr, &t.addr);
	if (rc == DF1_E_ADDR_SYNTAX || rc == DF1_E_INVAL)
		cfg_catalog(l, 2503, item, line, "Item: %d, Invalid Address Syntax (%s)", "ds", -1, item,
		            addr);
	else if (rc < 0 || t.count < 1 || t.count > COUNT_MAX ||
	         t.addr.element + t.count - 1 > ELEMENT_MAX)
		cfg_catalog(l, 2504, item, line, "Item: %d, Address is out of range (%s, len=%d)", "dsd",
		            -1, item, addr, t.count);

	v = cfg_value(l, row, MF_SCAN_MS);
	t.scan_ms = 1000;
	if (*v) {
		if (cfg_long(v, &lv) && lv >= 1 && lv <= SCAN_MS_MAX)
			t.scan_ms = (int)lv;
		else
			cfg_report(l, 0, item, line, "Item: %d, Invalid Scan_Ms (%.64s) should be in range "
			           "[1, %ld]", item, v, SCAN_MS_MAX);
	}

	if (l->issues != before || !m->deliver)
		return;
	if (m->row_fn) {
		rc = m->row_fn(m->user, &t);
		if (rc < 0) {
			l->stop = rc;
			return;
		}
	}
	m->loaded++;
}

int df1_map_load(const char *path, bool strict, df1_tag_row_fn row_fn,
                 df1_config_issue_fn issue_fn, void *user)
{
	struct cfg_load l;
	struct cfg_map_ctx m;
	FILE *f;
	int rc;

	if (!path)
		return DF1_E_INVAL;
	memset(&m, 0, sizeof m);
	m.row_fn = row_fn;
	m.user = user;
	m.deliver = !strict;
	cfg_init(&l, issue_fn, user, cfg_map_names, MF_COUNT_, cfg_map_required,
	         sizeof cfg_map_required / sizeof cfg_map_required[0], cfg_map_row, &m);
	f = cfg_open(&l, path);
	if (!f)
		return DF1_E_SYS;
	rc = cfg_read(&l, f, path);
	if (rc == 0 && l.stop < 0)
		rc = l.stop;
	if (rc == 0 && strict) {
		/* strict: the checking pass found nothing; now deliver the rows */
		if (l.issues > 0) {
			rc = DF1_E_CONFIG;
		} else {
			rewind(f);
			m.deliver = true;
			rc = cfg_read(&l, f, path);
			if (rc == 0 && l.stop < 0)
				rc = l.stop;
			if (rc == 0 && l.issues > 0)
				rc = DF1_E_CONFIG;
		}
	}
	fclose(f);
	return rc < 0 ? rc : m.loaded;
}
