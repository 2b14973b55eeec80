/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_tag - the tag a fuzz target converts values for, and the properties
 * of converted values (fuzz_tag.h).
 */
#include "fuzz.h"
#include "fuzz_tag.h"

#include <math.h>
#include <string.h>

static const char *const addrs[16] = {
	"N7:0", "F8:0", "B3:0/5", "ST9:0", "T4:0", "C5:0", "R6:0", "L10:0",
	"T4:0.ACC", "C5:0/DN", "S2:1", "O:0", "I:1", "A11:0", "B3/17", "N7:0/15",
};

void fuzz_tag_of(uint8_t o, bool wider, struct df1_tag_config *c)
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
	if (wider && (o & 128)) {
		snprintf(c->type, sizeof c->type, "%s", (o & 1) ? "DINT" : "REAL");
		if (df1_tag_value_kind(c) < 0)
			c->type[0] = '\0';
	}
}

void fuzz_tag_state(const struct df1_tag_config *c, bool has_value, struct df1_tag_state *cur,
                    struct df1_value curv[FUZZ_TAG_VALUES])
{
	memset(cur, 0, sizeof *cur);
	memset(curv, 0, FUZZ_TAG_VALUES * sizeof curv[0]);
	for (int i = 0; i < FUZZ_TAG_VALUES; i++)
		curv[i].kind = (enum df1_value_kind)df1_tag_value_kind(c);
	cur->config = c;
	cur->count = (size_t)c->count;
	cur->values = curv;
	cur->has_value = has_value;
}

void fuzz_tag_check_values(const struct df1_tag_config *c, const struct df1_value *v, size_t n)
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
