/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_net_csv - the network CSV loader (lib/config/config_net.c, lib/config/config_csv.c)
 * and applying what it loaded to a handle. Input: the file.
 * Properties: every issue has a network catalog ID (2552-2559, or 0) and a text; a
 * load that reports no issue returns 0 and its settings apply to a handle.
 */
#include "fuzz.h"

#include <string.h>

#include "df1.h"

static void on_issue(void *user, const struct df1_config_issue *is)
{
	int *n = user;

	(*n)++;
	/* 2552-2559, or 0 for the fields the seed gives no ID (config_net.c) */
	FUZZ_CHECK(is->catalog_id == 0 || (is->catalog_id >= DF1_ID_CRT_BAD_STATION_ID &&
	                                   is->catalog_id <= DF1_ID_CRT_BAD_CMD_TIMEOUT),
	           "network issue with catalog ID %d: %s", is->catalog_id, is->text);
	FUZZ_CHECK(is->text[0] != '\0', "an issue without a text (ID %d)", is->catalog_id);
	FUZZ_CHECK(memchr(is->text, '\0', sizeof is->text) != NULL, "issue text not terminated");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct df1_net_config c;
	const char *path = fuzz_file(data, size);
	int issues = 0, r;

	if (!path)
		return 0;
	df1_net_config_defaults(&c);
	r = df1_net_config_load(path, &c, on_issue, &issues);
	FUZZ_CHECK(r < 0 || issues == 0, "load returned %d with %d issues", r, issues);
	FUZZ_CHECK(r != DF1_E_CONFIG || issues > 0, "DF1_E_CONFIG without an issue reported");
	FUZZ_CHECK(memchr(c.port, '\0', sizeof c.port) != NULL, "Com_Port not terminated");
	if (r >= 0) {
		df1_t *h;
		if (df1_new(&h) == 0) {
			r = df1_apply_net_config(h, &c);
			FUZZ_CHECK(r >= 0, "a network file loaded without an issue does not apply: %s",
			           df1_errname(r));
			df1_free(h);
		}
	}
	return 0;
}
