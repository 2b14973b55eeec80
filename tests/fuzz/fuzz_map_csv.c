/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_map_csv - the mapping CSV loader (lib/config/config_map.c, lib/config/config_csv.c),
 * alone and into a handle's poll engine (df1_tag_load_map). Input: byte 0
 * bit 0 strict mode, the rest the file.
 * Properties: every issue has a mapping catalog ID (2501-2504, or 0) and a
 * text; each row handed over holds a valid tag (station 0-254, count 1-1000,
 * scan_ms >= 0, an address that formats); strict mode with an issue loads
 * nothing.
 */
#include "fuzz.h"

#include <string.h>

#include "df1.h"

struct seen {
	int issues, rows;
};

static void on_issue(void *user, const struct df1_config_issue *is)
{
	struct seen *s = user;

	s->issues++;
	FUZZ_CHECK(is->catalog_id == 0 || (is->catalog_id >= DF1_ID_ERR_BAD_STATION &&
	                                   is->catalog_id <= DF1_ID_ERR_ADDRESS_RANGE),
	           "mapping issue with catalog ID %d: %s", is->catalog_id, is->text);
	FUZZ_CHECK(is->text[0] != '\0' && memchr(is->text, '\0', sizeof is->text) != NULL,
	           "issue text empty or not terminated (ID %d)", is->catalog_id);
	FUZZ_CHECK(is->item >= 0, "issue for item %d", is->item);   /* 0: the file, not a row */
}

static int on_row(void *user, const struct df1_tag_config *t)
{
	struct seen *s = user;
	char buf[128];

	s->rows++;
	FUZZ_CHECK(t->station >= 0 && t->station <= 254, "tag station %d", t->station);
	FUZZ_CHECK(t->count >= 1 && t->count <= 1000, "tag count %d", t->count);
	FUZZ_CHECK(t->scan_ms >= 0, "tag scan_ms %d", t->scan_ms);
	FUZZ_CHECK(memchr(t->name, '\0', sizeof t->name) && memchr(t->type, '\0', sizeof t->type),
	           "tag name or type not terminated");
	FUZZ_CHECK(df1_addr_format(&t->addr, buf, sizeof buf) > 0, "tag %s: address does not format",
	           t->name);
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct seen s = { 0, 0 };
	const char *path;
	bool strict;
	df1_t *h;
	int r;

	if (size < 1)
		return 0;
	strict = data[0] & 1;
	path = fuzz_file(data + 1, size - 1);
	if (!path)
		return 0;
	r = df1_map_load(path, strict, on_row, on_issue, &s);
	FUZZ_CHECK(r < 0 || r == s.rows, "load returned %d for %d rows", r, s.rows);
	FUZZ_CHECK(!strict || s.issues == 0 || r < 0, "strict load with %d issues returned %d",
	           s.issues, r);
	if (df1_new(&h) == 0) {
		struct seen t = { 0, 0 };
		r = df1_tag_load_map(h, path, strict, on_issue, &t);
		FUZZ_CHECK(r < 0 || r == df1_tag_count(h), "%d tags added, %d in the handle", r,
		           df1_tag_count(h));
		df1_free(h);
	}
	return 0;
}
