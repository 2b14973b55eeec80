/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_gw_set - an MQTT .../set payload through df1gw's JSON reader: the
 * payload parsed (tools/df1gw/gw_write.c gw_set_parse over gw_json.c's
 * parser), its values converted for a tag (gw_value.c gw_value_from_json),
 * and the result payload written back (gw_result_json), as df1gw's JSON
 * format does for every message on <prefix>/tag/<name>/set.
 * Input: byte 0 picks the tag (bits 0-3 its address from the table below,
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

#include <math.h>
#include <string.h>

#include "df1gw/gw_json.h"
#include "df1gw/gw_value.h"
#include "df1gw/gw_write.h"

static const char *const addrs[16] = {
	"N7:0", "F8:0", "B3:0/5", "ST9:0", "T4:0", "C5:0", "R6:0", "L10:0",
	"T4:0.ACC", "C5:0/DN", "S2:1", "O:0", "I:1", "A11:0", "B3/17", "N7:0/15",
};

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_log();
	return 0;
}

static void tag_of(uint8_t o, struct df1_tag_config *c)
{
	static const int counts[4] = { 1, 2, 4, 10 };

	memset(c, 0, sizeof *c);
	snprintf(c->name, sizeof c->name, "t");
	c->access = DF1_ACCESS_READWRITE;
	c->station = 1;
	c->plc = DF1_PLC_SLC;
	if (df1_addr_parse(addrs[o & 15], &c->addr) < 0)
		abort();
	c->count = df1_addr_value_kind(&c->addr) == DF1_VAL_BIT ? 1 : counts[(o >> 4) & 3];
	c->scan_ms = 1000;
	if (o & 128) {
		snprintf(c->type, sizeof c->type, "%s", (o & 1) ? "DINT" : "REAL");
		if (df1_tag_value_kind(c) < 0)
			c->type[0] = '\0';
	}
}

static void check_values(const struct df1_tag_config *c, const struct df1_value *v, size_t n)
{
	int kind = df1_tag_value_kind(c);

	FUZZ_CHECK(kind >= 0, "a tag whose Type does not fit reached the conversion");
	FUZZ_CHECK(n >= 1 && n <= (size_t)c->count, "%zu values for Count %d", n, c->count);
	for (size_t i = 0; i < n; i++) {
		FUZZ_CHECK((int)v[i].kind == kind, "value %zu of kind %d, the tag's is %d", i, v[i].kind, kind);
		if (kind == DF1_VAL_FLOAT)
			FUZZ_CHECK(isfinite(v[i].v.f), "value %zu: a float that is not finite", i);
		if (kind == DF1_VAL_STRING)
			FUZZ_CHECK(v[i].v.str.len <= DF1_STRING_MAX && v[i].v.str.text[v[i].v.str.len] == '\0',
			           "value %zu: a string of %u bytes", i, v[i].v.str.len);
	}
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
	struct df1_value out[10], curv[10];
	struct gw_set s;
	char err[256];
	size_t n = 0;
	int r;

	if (size < 1)
		return 0;
	tag_of(data[0], &c);
	memset(&cur, 0, sizeof cur);
	memset(curv, 0, sizeof curv);
	for (int i = 0; i < 10; i++)
		curv[i].kind = (enum df1_value_kind)df1_tag_value_kind(&c);
	cur.config = &c;
	cur.count = (size_t)c.count;
	cur.values = curv;
	cur.has_value = (data[0] & 64) != 0;
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
		check_values(&c, out, n);
	} else {
		FUZZ_CHECK(r == DF1_E_TYPE || r == DF1_E_RANGE || r == DF1_E_INVAL, "gw_value_from_json returned %d", r);
		FUZZ_CHECK(err[0] != '\0' && n == 0, "a refusal (%d) without a reason", r);
	}
	check_result(s.id, r == 0, r == 0 ? NULL : err);
	gw_set_free(&s);
	return 0;
}
