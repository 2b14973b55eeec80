/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_gw_set - an MQTT .../set payload through df1gw's JSON reader: the
 * payload parsed (tools/df1gw/gw_write.c gw_set_parse over gw_json.c's
 * parser), its values converted for a tag (gw_value.c gw_value_from_json),
 * and the result payload written back (gw_result_json), as df1gw's JSON
 * format does for every message on <prefix>/tag/<name>/set.
 * Input: byte 0 picks the tag (fuzz_tag.h: bits 0-3 its address,
 * bits 4-5 its Count 1, 2, 4 or 10, bit 6 a current value for T/C/R members
 * not given, bit 7 a wider Type where one fits: DINT, or REAL for an even
 * address index); the rest is the payload. Properties: the parse gives a value
 * or an error text, never both; an id is at most GW_ID_MAX bytes of the
 * payload as written; converted values are 1..Count of the tag's kind
 * (df1_tag_value_kind),
 * finite floats, strings of at most 82 bytes; a refusal is DF1_E_TYPE,
 * DF1_E_RANGE or DF1_E_INVAL with its text; the result payload is valid JSON
 * to df1gw's own strict parser.
 */
#include "fuzz.h"
#include "fuzz_tag.h"

#include <string.h>

#include "df1gw/gw_json.h"
#include "df1gw/gw_value.h"
#include "df1gw/gw_write.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_log();
	return 0;
}

/* The result payload df1gw would publish must be JSON its own parser takes. */
static void check_result(const char *id, bool ok, const char *error)
{
	struct gw_buf b;
	struct gw_jv *r;
	char jerr[160];

	gw_buf_init(&b);
	gw_result_json(&b, id, ok, error, false);
	if (b.oom) {
		gw_buf_free(&b);
		return;
	}
	r = gw_json_parse(b.p, b.len, jerr, sizeof jerr);
	FUZZ_CHECK(r != NULL, "result payload %s is not JSON: %s", b.p, jerr);
	FUZZ_CHECK(r->type == GW_JOBJECT && gw_jv_get(r, "ok") && gw_jv_get(r, "ok")->b == ok,
	           "result payload %s", b.p);
	gw_jv_free(r);
	gw_buf_free(&b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct df1_tag_config c;
	struct df1_tag_state cur;
	struct df1_value out[FUZZ_TAG_VALUES], curv[FUZZ_TAG_VALUES];
	struct gw_set s;
	char err[256];
	size_t n = 0;
	int r;

	if (size < 1)
		return 0;
	fuzz_tag_of(data[0], true, &c);
	fuzz_tag_state(&c, (data[0] & 64) != 0, &cur, curv);
	err[0] = '\0';
	if (gw_set_parse((const char *)data + 1, size - 1, &s, err, sizeof err) < 0) {
		FUZZ_CHECK(err[0] != '\0', "a refused payload without a reason");
		FUZZ_CHECK(s.root == NULL && s.value == NULL, "a refused payload kept its tree");
		check_result(NULL, false, err);
		return 0;
	}
	FUZZ_CHECK(s.root && s.value, "a payload taken without a value");
	FUZZ_CHECK(strlen(s.id) <= GW_ID_MAX, "an id of %zu bytes", strlen(s.id));
	FUZZ_CHECK(!s.id[0] || memmem(data + 1, size - 1, s.id, strlen(s.id)), "the id %s is not in the payload",
	           s.id);
	r = gw_value_from_json(s.value, &c, &cur, out, 10, &n, err, sizeof err);
	if (r == 0) {
		fuzz_tag_check_values(&c, out, n);
	} else {
		FUZZ_CHECK(r == DF1_E_TYPE || r == DF1_E_RANGE || r == DF1_E_INVAL, "gw_value_from_json returned %d", r);
		FUZZ_CHECK(err[0] != '\0' && n == 0, "a refusal (%d) without a reason", r);
	}
	check_result(s.id, r == 0, r == 0 ? NULL : err);
	gw_set_free(&s);
	return 0;
}
