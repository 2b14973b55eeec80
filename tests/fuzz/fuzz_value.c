/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_value - value parsing (lib/proto/value.c, valuefmt.c) with the
 * round-trip property: text that parses for an address formats, that text
 * parses to the same value, and formats to the same text.
 * Input: byte 0 picks the address (every value kind and file type), the rest
 * is the value text (up to the first NUL).
 */
#include "fuzz.h"

#include <math.h>
#include <string.h>

#include "df1.h"

static const char *const addrs[] = {
	"N7:0", "B3:0", "B3:0/5", "F8:0", "L10:0", "L10:0/31", "ST9:0", "A11:0",
	"T4:0", "T4:0.ACC", "T4:0.PRE", "T4:0/DN", "C5:0", "C5:0/OV", "C5:0.ACC", "R6:0",
	"R6:0.LEN", "R6:0/ER", "S2:1/5", "S:0", "I1:0", "I1:0.1/3", "O0:0", "O:0/15",
	"$N7:0", "$F8:2", "N7:0/15", "T4:0.ACC/3",
};
#define NADDRS (sizeof addrs / sizeof addrs[0])

static bool value_equal(const struct df1_value *a, const struct df1_value *b)
{
	if (a->kind != b->kind)
		return false;
	switch (a->kind) {
	case DF1_VAL_INT16:
		return a->v.i16 == b->v.i16;
	case DF1_VAL_INT32:
		return a->v.i32 == b->v.i32;
	case DF1_VAL_FLOAT:
		if (isnan(a->v.f) || isnan(b->v.f))
			return isnan(a->v.f) && isnan(b->v.f);
		return memcmp(&a->v.f, &b->v.f, sizeof a->v.f) == 0;   /* -0 is not 0 */
	case DF1_VAL_BIT:
		return a->v.bit == b->v.bit;
	case DF1_VAL_STRING:
		return a->v.str.len == b->v.str.len &&
		       memcmp(a->v.str.text, b->v.str.text, a->v.str.len) == 0;
	case DF1_VAL_TCR:
		return a->v.tcr.ctl == b->v.tcr.ctl && a->v.tcr.pre == b->v.tcr.pre &&
		       a->v.tcr.acc == b->v.tcr.acc;
	default:
		return false;
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char text[512], s1[512], s2[512];
	struct df1_addr a;
	struct df1_value v1, v2;
	int r, n1, n2;

	if (size < 1 || size > sizeof text)
		return 0;
	FUZZ_CHECK(df1_addr_parse(addrs[data[0] % NADDRS], &a) == 0, "address %s",
	           addrs[data[0] % NADDRS]);
	memcpy(text, data + 1, size - 1);
	text[size - 1] = '\0';
	memset(&v1, 0, sizeof v1);
	r = df1_value_parse(&a, text, &v1);
	if (r < 0)
		return 0;
	FUZZ_CHECK(v1.kind != DF1_VAL_STRING || v1.v.str.len <= DF1_STRING_MAX,
	           "string of %u characters", (unsigned)v1.v.str.len);
	n1 = df1_value_format(&v1, a.type, s1, sizeof s1);
	FUZZ_CHECK(n1 >= 0 && (size_t)n1 < sizeof s1, "%s=\"%s\" parses but formats to %d",
	           addrs[data[0] % NADDRS], text, n1);
	memset(&v2, 0, sizeof v2);
	r = df1_value_parse(&a, s1, &v2);
	FUZZ_CHECK(r >= 0, "%s: \"%s\" formats as \"%s\", which does not parse (%s)",
	           addrs[data[0] % NADDRS], text, s1, df1_errname(r));
	FUZZ_CHECK(value_equal(&v1, &v2), "%s: \"%s\" -> \"%s\" parses to another value",
	           addrs[data[0] % NADDRS], text, s1);
	n2 = df1_value_format(&v2, a.type, s2, sizeof s2);
	FUZZ_CHECK(n2 == n1 && strcmp(s1, s2) == 0, "%s: \"%s\" -> \"%s\" -> \"%s\"",
	           addrs[data[0] % NADDRS], text, s1, s2);
	return 0;
}
