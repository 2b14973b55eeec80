/* SPDX-License-Identifier: MPL-2.0 */
/*
 * addr_plc3.c - a PLC-3's address text <-> struct df1_addr (pure: no I/O, no
 * clock, no allocation), and df1_addr_parse_plc / df1_addr_format_plc, which
 * pick this grammar or addr.c's by PLC type (doc/PROTOCOL.md 4.2a).
 *
 * Grammar (the data-table form of PLC-3 software, doc/PROTOCOL.md 4.2a):
 *
 *   word     = sect file ":" word [ "/" obit ]     sect: O I N F D B A H S
 *   tc       = ( "T" | "C" ) [ "0:" ] struct [ "." member ] [ "/" ( obit | name ) ]
 *            | ( "T" | "C" ) [ "0:" ] struct "." name
 *   member   = CTL PRE ACC                          (words 0, 1, 2)
 *   name     = T: EN TT DN; C: CU CD DN OV UF       (bits 15 14 13 ...; of CTL)
 *
 *   file 0-999 decimal and required (T and C: file 0 only, so it is left out:
 *   "T4.ACC" is timer 4); word 0-9999 decimal, but octal 0-7777 in O and I;
 *   struct 0-9999; obit octal 0-17 (no bit in F and H). Any letter case.
 *
 * Fields: type O I T C N F D B A S, H = DF1_FT_L; file; element = the word, or
 * for T C F H the structure (F and H: one 32-bit value is the structure's words
 * 0-1); sub = the T/C word (DF1_ADDR_NONE: the whole 3-word structure); bit
 * 0-15. Errors: DF1_E_ADDR_SYNTAX when the text is not of this grammar,
 * DF1_E_ADDR_RANGE when a number is beyond its level's range (timers and
 * counters outside file 0 included).
 *
 * Canonical text: "N3:173", "I0:17" (octal word), "B5:173/15" (octal bit),
 * "T4" (whole), "T4.ACC", "T4.CTL", "T4/DN" (a named CTL bit), "T4/7",
 * "T4.PRE/3"; parse(format(a)) == a.
 */
#include "df1.h"

#include <string.h>

#define P3_MAX_FILE 999
#define P3_MAX_WORD 9999
#define P3_MAX_IO_WORD 07777
#define P3_MAX_STRUCT 9999
#define P3_NUM_CAP 100000L

struct p3_name {
	const char *name;
	int num;
};

static const struct p3_name p3_members[] = { { "CTL", 0 }, { "PRE", 1 }, { "ACC", 2 }, { NULL, 0 } };
static const struct p3_name p3_t_bits[] = { { "EN", 15 }, { "TT", 14 }, { "DN", 13 }, { NULL, 0 } };
static const struct p3_name p3_c_bits[] = {
	{ "CU", 15 }, { "CD", 14 }, { "DN", 13 }, { "OV", 12 }, { "UF", 11 }, { NULL, 0 }
};

/* The section letters and their types (H is the 32-bit high-order integer). */
static const struct { char letter; enum df1_file_type type; } p3_sections[] = {
	{ 'O', DF1_FT_O }, { 'I', DF1_FT_I }, { 'T', DF1_FT_T }, { 'C', DF1_FT_C },
	{ 'N', DF1_FT_N }, { 'F', DF1_FT_F }, { 'D', DF1_FT_D }, { 'B', DF1_FT_B },
	{ 'A', DF1_FT_A }, { 'H', DF1_FT_L }, { 'S', DF1_FT_S },
};

static char p3_upper(char c)
{
	return (c >= 'a' && c <= 'z') ? (char)(c - 'a' + 'A') : c;
}

static bool p3_alpha(char c)
{
	c = p3_upper(c);
	return c >= 'A' && c <= 'Z';
}

static enum df1_file_type p3_type_of(char c)
{
	for (size_t i = 0; i < sizeof p3_sections / sizeof p3_sections[0]; i++)
		if (p3_sections[i].letter == p3_upper(c))
			return p3_sections[i].type;
	return DF1_FT_NONE;
}

static char p3_letter_of(enum df1_file_type t)
{
	for (size_t i = 0; i < sizeof p3_sections / sizeof p3_sections[0]; i++)
		if (p3_sections[i].type == t)
			return p3_sections[i].letter;
	return '?';
}

static bool p3_is_tc(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C;
}

/* Digits in base 8 or 10 at *pp: the value (saturated), -1 when there are none,
 * -2 for a digit 8 or 9 in an octal number. */
static long p3_number(const char **pp, int base)
{
	const char *p = *pp;
	long v = 0;

	if (*p < '0' || *p > '9')
		return -1;
	for (; *p >= '0' && *p <= '9'; p++) {
		if (*p - '0' >= base)
			return -2;
		if (v < P3_NUM_CAP)
			v = v * base + (*p - '0');
	}
	*pp = p;
	return v;
}

/* A name of tab of n letters at s, or -1. */
static int p3_lookup(const struct p3_name *tab, const char *s, size_t n)
{
	for (; tab && tab->name; tab++) {
		size_t k = strlen(tab->name), i;

		if (k != n)
			continue;
		for (i = 0; i < n && p3_upper(s[i]) == tab->name[i]; i++)
			;
		if (i == n)
			return tab->num;
	}
	return -1;
}

static const char *p3_name_of(const struct p3_name *tab, int num)
{
	for (; tab && tab->name; tab++)
		if (tab->num == num)
			return tab->name;
	return NULL;
}

static const struct p3_name *p3_bits(enum df1_file_type t)
{
	return t == DF1_FT_T ? p3_t_bits : t == DF1_FT_C ? p3_c_bits : NULL;
}

/* "/" obit at *pp (or a named bit when names): the bit, or DF1_E_*. */
static int p3_bit(const char **pp, const struct p3_name *names, int *is_named)
{
	const char *p = *pp, *s;
	long v;

	*is_named = 0;
	if (p3_alpha(*p) && names) {
		for (s = p; p3_alpha(*p); p++)
			;
		v = p3_lookup(names, s, (size_t)(p - s));
		if (v < 0)
			return DF1_E_ADDR_SYNTAX;
		*is_named = 1;
		*pp = p;
		return (int)v;
	}
	v = p3_number(&p, 8);
	if (v == -1 || v == -2)
		return DF1_E_ADDR_SYNTAX;
	if (v > 017)
		return DF1_E_ADDR_RANGE;
	*pp = p;
	return (int)v;
}

/* T or C after the letter: [0:]struct[.member|.name][/bit]. */
static int p3_parse_tc(const char *p, struct df1_addr *a)
{
	const char *s;
	long v = p3_number(&p, 10);
	int named, b;

	if (v < 0)
		return DF1_E_ADDR_SYNTAX;
	if (*p == ':') {        /* the file level, written out: timers and counters are file 0 */
		p++;
		a->file = (int)v;
		v = p3_number(&p, 10);
		if (v < 0)
			return DF1_E_ADDR_SYNTAX;
		if (a->file != 0)
			return DF1_E_ADDR_RANGE;
	}
	if (v > P3_MAX_STRUCT)
		return DF1_E_ADDR_RANGE;
	a->element = (int)v;
	if (*p == '.') {
		for (s = ++p; p3_alpha(*p); p++)
			;
		if (p == s)
			return DF1_E_ADDR_SYNTAX;
		a->sub = p3_lookup(p3_members, s, (size_t)(p - s));
		if (a->sub < 0) {       /* T4.DN: a named bit of CTL, PLC-5 spelling */
			b = p3_lookup(p3_bits(a->type), s, (size_t)(p - s));
			if (b < 0)
				return DF1_E_ADDR_SYNTAX;
			a->sub = 0;
			a->bit = b;
			return *p ? DF1_E_ADDR_SYNTAX : 0;
		}
	}
	if (*p == '/') {
		p++;
		if (a->sub == DF1_ADDR_NONE)
			a->sub = 0;
		b = p3_bit(&p, a->sub == 0 ? p3_bits(a->type) : NULL, &named);
		if (b < 0)
			return b;
		a->bit = b;
	}
	return *p ? DF1_E_ADDR_SYNTAX : 0;
}

/* A word section after the letter: file:word[/bit]. */
static int p3_parse_word(const char *p, struct df1_addr *a)
{
	bool io = a->type == DF1_FT_O || a->type == DF1_FT_I;
	long file = p3_number(&p, 10), w;
	int named, b;

	if (file < 0 || *p != ':')
		return DF1_E_ADDR_SYNTAX;
	p++;
	w = p3_number(&p, io ? 8 : 10);
	if (w < 0)
		return DF1_E_ADDR_SYNTAX;
	if (file > P3_MAX_FILE || w > (io ? P3_MAX_IO_WORD : P3_MAX_WORD))
		return DF1_E_ADDR_RANGE;
	a->file = (int)file;
	a->element = (int)w;
	if (*p == '/') {
		p++;
		if (a->type == DF1_FT_F || a->type == DF1_FT_L)
			return DF1_E_ADDR_SYNTAX;   /* no bit in F and H */
		b = p3_bit(&p, NULL, &named);
		if (b < 0)
			return b;
		a->bit = b;
	}
	return *p ? DF1_E_ADDR_SYNTAX : 0;
}

static int p3_parse(const char *text, struct df1_addr *a)
{
	struct df1_addr tmp;
	int rc;

	if (!text || !a)
		return DF1_E_INVAL;
	memset(&tmp, 0, sizeof tmp);
	tmp.sub = DF1_ADDR_NONE;
	tmp.bit = DF1_ADDR_NONE;
	tmp.type = p3_type_of(text[0]);
	if (tmp.type == DF1_FT_NONE || p3_alpha(text[1]))
		return DF1_E_ADDR_SYNTAX;
	rc = p3_is_tc(tmp.type) ? p3_parse_tc(text + 1, &tmp) : p3_parse_word(text + 1, &tmp);
	if (rc < 0)
		return rc;
	*a = tmp;
	return 0;
}

/* Are a's fields a PLC-3 address (what p3_parse can give)? */
static bool p3_valid(const struct df1_addr *a)
{
	bool io = a->type == DF1_FT_O || a->type == DF1_FT_I;

	if (p3_letter_of(a->type) == '?' || a->ascii[0] != '\0')
		return false;
	if (a->bit != DF1_ADDR_NONE && (a->bit < 0 || a->bit > 15))
		return false;
	if (p3_is_tc(a->type))
		return a->file == 0 && a->element >= 0 && a->element <= P3_MAX_STRUCT &&
		       (a->sub == DF1_ADDR_NONE ? a->bit == DF1_ADDR_NONE : a->sub >= 0 && a->sub <= 2);
	if (a->sub != DF1_ADDR_NONE || a->file < 0 || a->file > P3_MAX_FILE || a->element < 0)
		return false;
	if ((a->type == DF1_FT_F || a->type == DF1_FT_L) && a->bit != DF1_ADDR_NONE)
		return false;
	return a->element <= (io ? P3_MAX_IO_WORD : P3_MAX_WORD);
}

static size_t p3_put(char *out, size_t len, const char *fmt_base, long v)
{
	char digits[16];
	int n = 0, base = fmt_base[0] == 'o' ? 8 : 10;

	do {
		digits[n++] = (char)('0' + v % base);
		v /= base;
	} while (v > 0 && n < 15);
	while (n > 0)
		out[len++] = digits[--n];
	out[len] = '\0';
	return len;
}

static size_t p3_put_s(char *out, size_t len, const char *s)
{
	size_t n = strlen(s);

	memcpy(out + len, s, n + 1);
	return len + n;
}

static int p3_format(const struct df1_addr *a, char *buf, size_t cap)
{
	char tmp[48];
	size_t len = 0;
	const char *name;

	if (!a || (!buf && cap > 0) || !p3_valid(a))
		return DF1_E_INVAL;
	tmp[len++] = p3_letter_of(a->type);
	tmp[len] = '\0';
	if (p3_is_tc(a->type)) {
		len = p3_put(tmp, len, "d", a->element);
		name = a->bit != DF1_ADDR_NONE && a->sub == 0 ? p3_name_of(p3_bits(a->type), a->bit) : NULL;
		if (a->sub != DF1_ADDR_NONE && (a->sub != 0 || a->bit == DF1_ADDR_NONE)) {
			len = p3_put_s(tmp, len, ".");
			len = p3_put_s(tmp, len, p3_name_of(p3_members, a->sub));
		}
		if (a->bit != DF1_ADDR_NONE) {
			len = p3_put_s(tmp, len, "/");
			len = name ? p3_put_s(tmp, len, name) : p3_put(tmp, len, "o", a->bit);
		}
	} else {
		len = p3_put(tmp, len, "d", a->file);
		len = p3_put_s(tmp, len, ":");
		len = p3_put(tmp, len, a->type == DF1_FT_O || a->type == DF1_FT_I ? "o" : "d", a->element);
		if (a->bit != DF1_ADDR_NONE) {
			len = p3_put_s(tmp, len, "/");
			len = p3_put(tmp, len, "o", a->bit);
		}
	}
	if (len >= cap)
		return DF1_E_NOSPACE;
	memcpy(buf, tmp, len + 1);
	return (int)len;
}

int df1_addr_parse_plc(enum df1_plc plc, const char *text, struct df1_addr *a)
{
	if (plc == DF1_PLC_PLC3)
		return p3_parse(text, a);
	return df1_addr_parse(text, a);
}

int df1_addr_format_plc(enum df1_plc plc, const struct df1_addr *a, char *buf, size_t cap)
{
	if (plc == DF1_PLC_PLC3)
		return p3_format(a, buf, cap);
	return df1_addr_format(a, buf, cap);
}
