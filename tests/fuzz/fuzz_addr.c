/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_addr - address parsing (lib/proto/addr.c) with the round-trip property
 * of doc/ARCHITECTURE.md 7: an address that parses formats, its text parses again to the
 * same address, and that formats to the same text.
 * Input: the address text (up to the first NUL).
 */
#include "fuzz.h"

#include <string.h>

#include "df1.h"

static bool addr_equal(const struct df1_addr *a, const struct df1_addr *b)
{
	return a->type == b->type && a->file == b->file && a->element == b->element &&
	       a->sub == b->sub && a->bit == b->bit && strcmp(a->ascii, b->ascii) == 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char text[256], s1[128], s2[128];
	struct df1_addr a, b;
	int r, n1, n2;

	if (size >= sizeof text)
		return 0;
	memcpy(text, data, size);
	text[size] = '\0';
	memset(&a, 0x5A, sizeof a);
	r = df1_addr_parse(text, &a);
	if (r < 0) {
		FUZZ_CHECK(r == DF1_E_ADDR_SYNTAX || r == DF1_E_ADDR_RANGE,
		           "\"%s\": parse error %d (%s) is neither 2503 nor 2504", text, r, df1_errname(r));
		return 0;
	}
	n1 = df1_addr_format(&a, s1, sizeof s1);
	FUZZ_CHECK(n1 > 0 && (size_t)n1 < sizeof s1 && strlen(s1) == (size_t)n1,
	           "\"%s\" parses but formats to %d", text, n1);
	memset(&b, 0xA5, sizeof b);
	r = df1_addr_parse(s1, &b);
	FUZZ_CHECK(r >= 0, "\"%s\" formats as \"%s\", which does not parse (%s)", text, s1,
	           df1_errname(r));
	FUZZ_CHECK(addr_equal(&a, &b),
	           "\"%s\" -> \"%s\" parses to another address (type %d/%d file %d/%d element %d/%d sub %d/%d bit %d/%d)",
	           text, s1, a.type, b.type, a.file, b.file, a.element, b.element, a.sub, b.sub, a.bit, b.bit);
	n2 = df1_addr_format(&b, s2, sizeof s2);
	FUZZ_CHECK(n2 == n1 && strcmp(s1, s2) == 0, "\"%s\" -> \"%s\" -> \"%s\"", text, s1, s2);
	/* a short buffer is refused, never overrun */
	FUZZ_CHECK(df1_addr_format(&a, s2, (size_t)n1) == DF1_E_NOSPACE,
	           "\"%s\" formats into %d bytes", s1, n1);
	return 0;
}
