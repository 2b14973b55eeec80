/* SPDX-License-Identifier: MPL-2.0 */
/*
 * config_map.c - the mapping file (one row per tag). The CSV rules are
 * config_csv.c's.
 *
 * Mapping file (doc/REQUIREMENTS.md 004, "Mapping Parameters"): columns Tag, Station, PLC_Type,
 * Address are required (a missing column fails the load); Command (Read, Write,
 * ReadWrite; also RW and "Read/Write"; Receive: a region of the loader's own
 * data table, df1gw(1) RECEIVE; default Read), Type (the kind of the tag's
 * values, lib/proto/value_type.h: INT, DINT or LONG, REAL or FLOAT, BOOL, STRING,
 * TIMER, COUNTER, CONTROL, any case; empty: the address's own; one that is not a
 * Type or cannot hold the address's values is a bad row), Count (elements, 1-1000,
 * default 1), Scan_Ms (0-86400000,
 * 0 = every scan as df1_tag_add() takes it, default 1000) are optional. Item
 * numbers are 1-based data rows (blank and comment rows not counted). Per row:
 *   Station not 0-254 (or not a number)      2501 ERR_BAD_STATION
 *   PLC_Type invalid or unsupported          2502 ERR_BAD_PLC_TYPE
 *   Address malformed                        2503 ERR_ADDRESS_SYNTAX
 *   Address out of range, Count below 1, or element + Count - 1 above 999
 *                                            2504 ERR_ADDRESS_RANGE (len = Count)
 *   Tag missing or longer than 63, Command, Type (unknown, too long, or not
 *   fitting the Address), Count not a number, Scan_Ms,
 *   a NUL byte in any cell                   catalog 0, "Item: n, ..." text
 * Bad rows are reported and skipped. In strict mode the file is checked first and
 * row_fn is called only when every row is valid. A row_fn returning a negative
 * value stops the load, which returns that value. On any failure the caller should
 * discard the rows it received.
 */
#include "config/config_int.h"

#include "proto/value_type.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

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

/* Tag, Command, Type: what the tag is called and what it does (no catalog IDs). */
static void cfg_map_name(struct cfg_load *l, struct cfg_row *row, struct df1_tag_config *t)
{
	const char *v;
	char u[16];
	int item = l->item, line = row->line;

	v = cfg_value(l, row, MF_TAG);
	if (!*v)
		cfg_report(l, 0, item, line, "Item: %d, missing Tag", item);
	else if (strlen(v) >= sizeof t->name)
		cfg_report(l, 0, item, line, "Item: %d, Tag (%.64s) is too long (max %d characters)",
		           item, v, (int)sizeof t->name - 1);
	else
		strcpy(t->name, v);

	v = cfg_value(l, row, MF_COMMAND);
	t->access = DF1_ACCESS_READ;
	if (*v) {
		if (!cfg_squash(v, " _-/", u, sizeof u))
			u[0] = '\0';
		if (strcmp(u, "READ") == 0)
			t->access = DF1_ACCESS_READ;
		else if (strcmp(u, "WRITE") == 0)
			t->access = DF1_ACCESS_WRITE;
		else if (strcmp(u, "READWRITE") == 0 || strcmp(u, "RW") == 0)
			t->access = DF1_ACCESS_READWRITE;
		else if (strcmp(u, "RECEIVE") == 0)
			t->access = DF1_ACCESS_RECEIVE;
		else
			cfg_report(l, 0, item, line,
			           "Item: %d, Invalid Command (%.64s) should be one of Read, Write, "
			           "ReadWrite, or Receive", item, v);
	}

	v = cfg_value(l, row, MF_TYPE);
	if (strlen(v) >= sizeof t->type)
		cfg_report(l, 0, item, line, "Item: %d, Type (%.64s) is too long (max %d characters)",
		           item, v, (int)sizeof t->type - 1);
	else
		strcpy(t->type, v);
}

/* Station, PLC_Type: which PLC (catalog IDs 2501, 2502). */
static void cfg_map_plc(struct cfg_load *l, struct cfg_row *row, struct df1_tag_config *t)
{
	const char *v;
	int item = l->item, line = row->line, x;

	v = cfg_value(l, row, MF_STATION);
	if (cfg_int(v, &x) && x >= 0 && x < STATION_LIMIT)
		t->station = x;
	else if (cfg_int(v, &x))
		cfg_catalog(l, DF1_ID_ERR_BAD_STATION, item, line,
		            "Item: %d, Invalid station number (%d) must be less than %d", "ddd", -1, item,
		            x, STATION_LIMIT);
	else
		cfg_catalog(l, DF1_ID_ERR_BAD_STATION, item, line,
		            "Item: %d, Invalid station number (%d) must be less than %d", "ddd", 1, item,
		            v, STATION_LIMIT);

	v = cfg_value(l, row, MF_PLC_TYPE);
	if (cfg_plc(v, &t->plc) < 0)
		cfg_catalog(l, DF1_ID_ERR_BAD_PLC_TYPE, item, line,
		            "Item: %d, Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s",
		            "dsssss", -1, item, v, PLC_CHOICES);
}

/* Count, Address: which elements (catalog IDs 2503, 2504). */
static void cfg_map_where(struct cfg_load *l, struct cfg_row *row, struct df1_tag_config *t)
{
	const char *v, *addr;
	int item = l->item, line = row->line, rc;
	long lv;

	v = cfg_value(l, row, MF_COUNT);
	t->count = 1;
	if (*v && !cfg_long(v, &lv))
		cfg_report(l, 0, item, line, "Item: %d, Invalid Count (%.64s) should be a number of "
		           "elements [1, %d]", item, v, COUNT_MAX);
	else if (*v)
		t->count = lv < INT_MIN ? INT_MIN : lv > INT_MAX ? INT_MAX : (int)lv;

	addr = cfg_value(l, row, MF_ADDRESS);
	/* the row's PLC type picks the address text (a PLC-3's own, doc/PROTOCOL.md 4.2a) */
	rc = df1_addr_parse_plc(t->plc, addr, &t->addr);
	if (rc == DF1_E_ADDR_SYNTAX || rc == DF1_E_INVAL)
		cfg_catalog(l, DF1_ID_ERR_ADDRESS_SYNTAX, item, line,
		            "Item: %d, Invalid Address Syntax (%s)", "ds", -1, item,
		            addr);
	else if (rc < 0 || t->count < 1 || t->count > COUNT_MAX ||
	         t->addr.element + t->count - 1 > (t->plc == DF1_PLC_PLC3 ? ELEMENT_MAX_PLC3 : ELEMENT_MAX))
		cfg_catalog(l, DF1_ID_ERR_ADDRESS_RANGE, item, line,
		            "Item: %d, Address is out of range (%s, len=%d)", "dsd",
		            -1, item, addr, t->count);
}

/* Type against the Address (no catalog ID; after a valid Address only). */
static void cfg_map_type(struct cfg_load *l, struct cfg_row *row, const struct df1_tag_config *t)
{
	enum df1_value_kind k;
	const char *why, *addr = cfg_value(l, row, MF_ADDRESS);
	int rc = value_type_check(t->type, &t->addr, &k, &why);

	if (rc == DF1_E_INVAL)
		cfg_report(l, 0, l->item, row->line, "Item: %d, Invalid Type (%.64s) should be one of %s, "
		           "or empty (the address's own)", l->item, t->type, VALUE_TYPE_NAMES);
	else if (rc < 0)
		cfg_report(l, 0, l->item, row->line, "Item: %d, Type %.64s does not fit %.64s: %s", l->item,
		           t->type, addr, why);
}

/* Scan_Ms: how often (no catalog ID). */
static void cfg_map_scan(struct cfg_load *l, struct cfg_row *row, struct df1_tag_config *t)
{
	const char *v = cfg_value(l, row, MF_SCAN_MS);
	long lv;

	t->scan_ms = 1000;
	if (!*v)
		return;
	/* 0: every scan (df1_tag_add) */
	if (cfg_long(v, &lv) && lv >= 0 && lv <= SCAN_MS_MAX)
		t->scan_ms = (int)lv;
	else
		cfg_report(l, 0, l->item, row->line, "Item: %d, Invalid Scan_Ms (%.64s) should be "
		           "in range [0, %ld]", l->item, v, SCAN_MS_MAX);
}

/* One data row: every invalid value is reported, in the order of the fields;
 * a valid row goes to row_fn (not in strict mode's checking pass). */
static void cfg_map_row(struct cfg_load *l, struct cfg_row *row)
{
	struct cfg_map_ctx *m = l->ctx;
	struct df1_tag_config t;
	int before = l->issues, where, rc;

	memset(&t, 0, sizeof t);
	if (cfg_check_cells(l, row, true) > 0)
		return;         /* a NUL byte: the cells are not what they seem */
	cfg_map_name(l, row, &t);
	cfg_map_plc(l, row, &t);
	where = l->issues;
	cfg_map_where(l, row, &t);
	if (l->issues == where)
		cfg_map_type(l, row, &t);
	cfg_map_scan(l, row, &t);

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
