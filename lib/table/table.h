/* SPDX-License-Identifier: MPL-2.0 */
/*
 * table - the data table of a slave (struct df1_table, df1_table(3)): files of
 * elements in the SLC wire layout (lib/server/server.h's data-table contract), their
 * initial contents, address stepping, values in and out, the processor table
 * and the diagnostic status it answers with (doc/PROTOCOL.md 4.9, 5).
 * No I/O and no clock; memory is allocated only when files are added or grown.
 * lib/table/table_file.c loads and saves it, lib/table/table_serve.c serves it.
 */
#ifndef LIBDF1_TABLE_H
#define LIBDF1_TABLE_H

#include "df1.h"

#define TABLE_MODE_PROGRAM 1
#define TABLE_MODE_RUN 6

struct table_file {
	enum df1_file_type type;
	int nelem;
	size_t esize;
	uint8_t *data;          /* nelem * esize bytes, SLC wire layout */
	bool provisional;       /* ST9 L10 A11 of the default files: another type replaces it */
};

/* A processor of the diagnostic status (doc/PROTOCOL.md 4.9). */
struct table_processor {
	const char *key;        /* normalised name: lower case, no blanks, '-' or '_' */
	const char *bulletin;   /* EE form: bytes 6-16 */
	uint8_t code;
	bool plc5;              /* EB form */
};

/* A PLC-3's sections each have their own files 0-999 (its O0, I0, T0, C0 and S0,
 * its N3 and B3 are different files: doc/PROTOCOL.md 4.2a), so a PLC-3 table keeps
 * a slot per section and number (table_slot); other tables use slots 0-999. */
#define TABLE_SECTIONS 12
#define TABLE_SLOTS (DF1_TABLE_FILES_MAX * TABLE_SECTIONS)

struct df1_table {
	enum df1_plc plc;
	int mode;               /* 1 program, 6 run, 7/8 test */
	struct table_processor proc;
	struct table_file *files[TABLE_SLOTS];
	char err[512];          /* df1_table_error_text() */
};

/* Record the detail of a failure; returns err. */
int table_fail(struct df1_table *t, int err, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* The slot in t->files of file `number` of type `type`: the number, or on a
 * PLC-3 table section index * DF1_TABLE_FILES_MAX + number; -1 when the number
 * is out of range or a PLC-3 has no such section (R, ST). */
int table_slot(const struct df1_table *t, enum df1_file_type type, int number);
/* The file of a's type and number in t, or NULL. */
struct table_file *table_find(const struct df1_table *t, const struct df1_addr *a);

/* A file with elements 0..nelem-1 at their initial values, or NULL (no memory). */
struct table_file *table_file_new(enum df1_file_type type, int nelem);
void table_file_free(struct table_file *f);
/* Grow f to hold element `elem` (< DF1_TABLE_ELEMENTS_MAX), new elements initialised. */
bool table_file_grow(struct table_file *f, int elem);

/* The address of value i of a run starting at a (df1_table_read's rule). */
void table_addr_step(const struct df1_addr *a, int i, struct df1_addr *out);
/* Store v at a / fetch the value at a: the file exists, a's element is inside it
 * and v has a's value kind; a string is cut at DF1_STRING_MAX characters. */
void table_put_value(struct table_file *f, const struct df1_addr *a, const struct df1_value *v);
void table_get_value(const struct table_file *f, const struct df1_addr *a, struct df1_value *v);

/* The data-table contract of lib/server/server.h: where nbytes at a start, or an EXT STS
 * (06 no such file, 11 other type, 07 element beyond the file, 0A runs past it). */
int table_locate(struct df1_table *t, const struct df1_addr *a, size_t nbytes, uint8_t **p);
/* The diagnostic status reply data of t as station `station`: bytes or DF1_E_NOSPACE. */
int table_diag_status(const struct df1_table *t, int station, uint8_t *buf, size_t cap);

#endif
