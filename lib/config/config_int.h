/* SPDX-License-Identifier: MPL-2.0 */
/*
 * config_int.h - what the configuration loaders share (lib/config/config_csv.c: the
 * CSV reader, issue reporting and cell parsers; lib/config/config_net.c: the network
 * file; lib/config/config_map.c: the mapping file). Not installed, not used outside
 * them.
 */
#ifndef LIBDF1_CONFIG_INT_H
#define LIBDF1_CONFIG_INT_H

#include <csv.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "df1.h"

#define CFG_MAX_COLS 32
#define CFG_FIELD_MAX 256          /* bytes per cell, with the NUL (Com_Port is 255 max) */
#define CFG_SEG_MAX 4096           /* bytes handed to libcsv at a time */
#define CFG_READ_CHUNK 4096
#define CFG_FIELD_LIMIT 65536      /* bytes of one field in the file: more fails the load */
#define CFG_CSV_BLOCK 4096         /* libcsv's field buffer grows by this much */
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
#define ELEMENT_MAX_PLC3 9999     /* a PLC-3's words and structures */
#define PLC_CHOICES "PLC2", "PLC5", "SLC", "MicroLogix"

struct cfg_row {
	int nfields;
	int line;                           /* line of the row's first field */
	bool overflow;                      /* more than CFG_MAX_COLS cells */
	bool too_long[CFG_MAX_COLS];
	bool has_nul[CFG_MAX_COLS];         /* a NUL byte inside the cell */
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
	size_t field_len;                   /* bytes of the field being read */
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

/* issues (config_csv.c): counted, passed to the issue callback */
void cfg_report(struct cfg_load *l, int id, int item, int line, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));
void cfg_catalog(struct cfg_load *l, int id, int item, int line, const char *fallback,
                 const char *sig, int as_text, ...);
/* cell parsers */
bool cfg_squash(const char *s, const char *drop, char *out, size_t cap);
bool cfg_ieq(const char *a, const char *b);
bool cfg_istarts(const char *s, const char *prefix);
bool cfg_all_digits(const char *s);
bool cfg_long(const char *s, long *out);
bool cfg_int(const char *s, int *out);
int cfg_plc(const char *s, enum df1_plc *plc);
/* the reader: a row's cell by field, the per-row checks, reading a file */
const char *cfg_value(const struct cfg_load *l, const struct cfg_row *row, int f);
int cfg_check_cells(struct cfg_load *l, const struct cfg_row *row, bool with_item);
int cfg_read(struct cfg_load *l, FILE *f, const char *path);
FILE *cfg_open(struct cfg_load *l, const char *path);
void cfg_init(struct cfg_load *l, df1_config_issue_fn fn, void *user,
              const char *const *names, int nnames, const int *required,
              size_t nrequired, cfg_row_fn on_data, void *ctx);

#endif
