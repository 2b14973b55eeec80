/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_spb_cmd - a Sparkplug B command (NCMD/DCMD) as df1gw takes it from the
 * broker: the protobuf payload decoded (tools/df1gw/gw_spb_codec.c over
 * protobuf-c), each metric's target read (a tag by name, "Tag/MEMBER", or
 * an alias) and its value converted for a tag (gw_spb_cmd.c
 * gw_spb_write_values), as gw_format_sparkplug.c does for every DCMD.
 * Input: byte 0 picks the tag (fuzz_tag.h: bits 0-3 its address,
 * bits 4-5 its Count 1, 2, 4 or 10, bit 6 a current value for T/C/R members
 * not given); the rest is the payload. Properties: a payload is decoded or
 * refused, never half; each metric's fields stay inside the payload's
 * decoded memory (the sanitizers see it); converted values are 1..Count of
 * the tag's kind, finite floats, strings of at most 82 bytes; a refusal is
 * DF1_E_TYPE, DF1_E_RANGE or DF1_E_INVAL with its text.
 */
#include "fuzz.h"
#include "fuzz_tag.h"

#include <string.h>

#include "df1.h"
#include "df1gw/gw_spb_codec.h"
#include "df1gw/gw_spb_metrics.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_log();
	return 0;
}

/* One metric: its target, then its values for tag c. */
static void one_metric(const struct gw_spb_metric *m, const struct df1_tag_config *c,
                       const struct df1_tag_state *cur)
{
	struct df1_value out[FUZZ_TAG_VALUES];
	char tag[80], err[256];
	const char *member = "";
	unsigned alias_member = 0;
	int alias_id = -1, r;
	size_t n = 0;

	if (m->name)
		FUZZ_CHECK(strlen(m->name) < 1u << 20, "a metric name of %zu bytes", strlen(m->name));
	if (!gw_spb_metric_target(m, tag, sizeof tag, &member, &alias_id, &alias_member))
		return;
	FUZZ_CHECK(strlen(tag) < sizeof tag && member, "a target past its room");
	err[0] = '\0';
	r = gw_spb_write_values(m, member, alias_member, c, cur, out, sizeof out / sizeof out[0], &n, err, sizeof err);
	if (r == 0) {
		fuzz_tag_check_values(c, out, n);
	} else {
		FUZZ_CHECK(r == DF1_E_TYPE || r == DF1_E_RANGE || r == DF1_E_INVAL, "gw_spb_write_values returned %d",
		           r);
		FUZZ_CHECK(err[0] != '\0', "a refusal (%d) without a reason", r);
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct df1_tag_config c;
	struct df1_tag_state cur;
	struct df1_value curv[FUZZ_TAG_VALUES];
	struct gw_spb_in in;

	if (size < 1)
		return 0;
	fuzz_tag_of(data[0], false, &c);
	fuzz_tag_state(&c, (data[0] & 64) != 0, &cur, curv);
	memset(&in, 0, sizeof in);
	if (gw_spb_decode(data + 1, size - 1, &in) < 0) {
		FUZZ_CHECK(in.pb == NULL, "a refused payload kept its message");
		return 0;
	}
	for (size_t i = 0; i < in.n; i++) {
		struct gw_spb_metric m;

		gw_spb_metric_at(&in, i, &m);
		one_metric(&m, &c, &cur);
	}
	gw_spb_in_free(&in);
	return 0;
}
