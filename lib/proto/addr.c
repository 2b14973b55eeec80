/* SPDX-License-Identifier: MPL-2.0 */
/*
 * addr.c - data-table addresses: text <-> struct df1_addr (pure: no I/O,
 * no clock, no allocation, no global mutable state).
 *
 * Grammar (doc/ARCHITECTURE.md 7, doc/REQUIREMENTS.md 004 "Mapping Address Formatting Rules"):
 *
 *   address  = [ "$" ] type [ file ] ( ":" element [ sub ] [ bit ] | "/" bitnum )
 *   type     = O I S B T C R N F ST A L          (any case)
 *   file     = decimal digits                    (may be omitted for O I S B T C R N F)
 *   element  = decimal digits
 *   sub      = "." ( digits | PRE ACC (T, C) | LEN POS (R) | a T/C/R bit name )
 *   bit      = "/" ( digits | a T/C/R bit name )
 *   bitnum   = digits                            (B files only: B3/21 = B3:1/5)
 *
 * Accepted forms and their fields:
 *   N7:0 N10:255 F8:3 L10:0 ST9:0 A11:0   element; L bits 0-31, N/S/B/A/I/O bits 0-15
 *   B3:0/5, B3/21                        B3/n is bit n of the file: element n/16, bit n%16
 *   T4:0.PRE .ACC (sub 1, 2), C5:1.PRE .ACC, R6:0.LEN .POS (sub 1, 2); numeric .0 .1 .2
 *   T4:0/DN, and the PLC-5 spelling T4:0.DN: sub 0 (control word), named bit
 *     T: EN 15 TT 14 DN 13; C: CU 15 CD 14 DN 13 OV 12 UN 11 UA 10;
 *     R: EN 15 EU 14 DN 13 EM 12 ER 11 UL 10 IN 9 FD 8
 *   T4:0/3 (bit of the control word, sub 0), T4:0.ACC/3 (bit of a T/C/R word)
 *   I:0/3, I1:0.1/3, O:0: element = slot, sub = word (0-255), bit 0-15.
 *     Numbers are decimal, as on SLC and MicroLogix; PLC-5 octal I/O addresses
 *     (I:012/17) must be given as "$I:012/17" and are only sent, not re-based.
 *   $N7:0                                 PLC-5 logical ASCII: ascii = text after '$',
 *                                         kept as written; the fields are parsed as well.
 *
 * Files. O, I and S are fixed at files 0, 1 and 2 (all controllers). Every other
 * type may use files 3-999 (doc/REQUIREMENTS.md 004: 0-8 reserved for the default files, 9-999
 * user files; PLC-5 lets files 3-8 be re-created as other types, so libdf1 does not
 * pin them; a controller without the file answers with an EXT STS). Files 0-2 are
 * never valid for B T C R N F ST A L. Elements 0-999 (PLC-5 range; SLC stops at 255
 * and answers with an error).
 *
 * Errors. DF1_E_ADDR_SYNTAX (2503) when the text does not follow the grammar or asks
 * for something the type does not have: unknown type letters, a missing number, a
 * user type (ST A L) without a file number, a sub-element on N B F S ST A L, a bit
 * on F or ST, an unknown or wrong-type mnemonic (T4:0.LEN, C5:0/EN), a named bit
 * after a sub-element (T4:0.ACC/DN), B-style "/n" on other types, signs, spaces,
 * trailing text. DF1_E_ADDR_RANGE (2504) when the text is well formed but a number is
 * out of range: file above 999, O/I/S not in their file (O1:0, S3:0), a user type in
 * files 0-2 (N1:0), element above 999, sub above 2 (T/C/R) or 255 (I/O), bit above 15
 * (31 for L), B3/n above 15999, a "$" text longer than DF1_ADDR_ASCII_MAX - 1.
 *
 * Canonical text (df1_addr_format): always with the file number ("S2:1/5",
 * "I1:0/3", "O0:0", "N7:0"); B bits as "B3:1/5"; T/C/R words 1 and 2 by name
 * (".PRE" ".ACC", ".LEN" ".POS"), word 0 as ".0"; bits of word 0 by name when they
 * have one ("T4:0/DN"), else by number ("T4:0/3"); upper case. A "$" address
 * formats as "$" + ascii. parse(format(a)) == a for every address parse accepts.
 */
#include "df1.h"

#include <string.h>

#define NUM_CAP 1000000L /* digit strings saturate here: any larger number is out of range */
#define MAX_FILE 999
#define MAX_ELEMENT 999
#define MAX_IO_SUB 255
#define MAX_TCR_SUB 2
#define MAX_B_BITNUM (MAX_ELEMENT * 16 + 15)

struct ft_info {
	const char *name;
	int default_file; /* -1: a number is required */
	int fixed_file;   /* -1: any of 3..999 */
	int element_size; /* bytes on the wire */
	int slc_code;     /* SLC file type code (doc/PROTOCOL.md 4.11) */
	int max_bit;      /* -1: no bit addressing */
	int max_sub;      /* -1: no sub-elements */
};

static const struct ft_info ft_table[DF1_FT_D + 1] = {
	[DF1_FT_NONE] = { "?", -1, -1, 0, 0, -1, -1 },
	[DF1_FT_O] = { "O", 0, 0, 2, 0x8B, 15, MAX_IO_SUB },
	[DF1_FT_I] = { "I", 1, 1, 2, 0x8C, 15, MAX_IO_SUB },
	[DF1_FT_S] = { "S", 2, 2, 2, 0x84, 15, -1 },
	[DF1_FT_B] = { "B", 3, -1, 2, 0x85, 15, -1 },
	[DF1_FT_T] = { "T", 4, -1, 6, 0x86, 15, MAX_TCR_SUB },
	[DF1_FT_C] = { "C", 5, -1, 6, 0x87, 15, MAX_TCR_SUB },
	[DF1_FT_R] = { "R", 6, -1, 6, 0x88, 15, MAX_TCR_SUB },
	[DF1_FT_N] = { "N", 7, -1, 2, 0x89, 15, -1 },
	[DF1_FT_F] = { "F", 8, -1, 4, 0x8A, -1, -1 },
	[DF1_FT_ST] = { "ST", -1, -1, 84, 0x8D, -1, -1 },
	[DF1_FT_A] = { "A", -1, -1, 2, 0x8E, 15, -1 },
	[DF1_FT_L] = { "L", -1, -1, 4, 0x91, 31, -1 },
	/* a PLC-3's decimal section only (lib/proto/addr_plc3.c): this grammar refuses it */
	[DF1_FT_D] = { "D", -1, -1, 2, 0, 15, -1 },
};

struct name_num {
	const char *name;
	int num;
};

/* Named words of T/C/R elements (doc/PROTOCOL.md 5). */
static const struct name_num tc_words[] = { { "PRE", 1 }, { "ACC", 2 }, { NULL, 0 } };
static const struct name_num r_words[] = { { "LEN", 1 }, { "POS", 2 }, { NULL, 0 } };

/* Named bits of word 0 (doc/PROTOCOL.md 5; R positions per the common EN 15 .. FD 8 layout). */
static const struct name_num t_bits[] = {
	{ "EN", 15 }, { "TT", 14 }, { "DN", 13 }, { NULL, 0 }
};
static const struct name_num c_bits[] = {
	{ "CU", 15 }, { "CD", 14 }, { "DN", 13 }, { "OV", 12 }, { "UN", 11 }, { "UA", 10 },
	{ NULL, 0 }
};
static const struct name_num r_bits[] = {
	{ "EN", 15 }, { "EU", 14 }, { "DN", 13 }, { "EM", 12 }, { "ER", 11 }, { "UL", 10 },
	{ "IN", 9 }, { "FD", 8 }, { NULL, 0 }
};

static bool addr_valid_type(enum df1_file_type t)
{
	return (t > DF1_FT_NONE && t < DF1_FT_COUNT_) || t == DF1_FT_D;
}

/* Types of this grammar: all but the PLC-3's decimal section. */
static bool addr_slc_type(enum df1_file_type t)
{
	return addr_valid_type(t) && t != DF1_FT_D;
}

static bool addr_is_tcr(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R;
}

static const struct name_num *addr_word_names(enum df1_file_type t)
{
	if (t == DF1_FT_T || t == DF1_FT_C)
		return tc_words;
	if (t == DF1_FT_R)
		return r_words;
	return NULL;
}

static const struct name_num *addr_bit_names(enum df1_file_type t)
{
	switch (t) {
	case DF1_FT_T: return t_bits;
	case DF1_FT_C: return c_bits;
	case DF1_FT_R: return r_bits;
	default: return NULL;
	}
}

static char addr_upper(char c)
{
	return (c >= 'a' && c <= 'z') ? (char)(c - 'a' + 'A') : c;
}

static bool addr_is_digit(char c)
{
	return c >= '0' && c <= '9';
}

static bool addr_is_alpha(char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

/* Case-insensitive match of the token [s, s+n) against an upper-case name. */
static bool addr_token_is(const char *s, size_t n, const char *name)
{
	size_t i;

	if (strlen(name) != n)
		return false;
	for (i = 0; i < n; i++)
		if (addr_upper(s[i]) != name[i])
			return false;
	return true;
}

static int addr_lookup(const struct name_num *tab, const char *s, size_t n)
{
	if (!tab)
		return -1;
	for (; tab->name; tab++)
		if (addr_token_is(s, n, tab->name))
			return tab->num;
	return -1;
}

static const char *addr_name_of(const struct name_num *tab, int num)
{
	if (!tab)
		return NULL;
	for (; tab->name; tab++)
		if (tab->num == num)
			return tab->name;
	return NULL;
}

/* Decimal digits at *pp (at least one), saturating at NUM_CAP; -1 if none. */
static long addr_digits(const char **pp)
{
	const char *p = *pp;
	long v = 0;

	if (!addr_is_digit(*p))
		return -1;
	while (addr_is_digit(*p)) {
		if (v < NUM_CAP)
			v = v * 10 + (*p - '0');
		p++;
	}
	if (v > NUM_CAP)
		v = NUM_CAP;
	*pp = p;
	return v;
}

/* A token after '.' or '/': digits only, or letters only. */
struct addr_token {
	const char *s;
	size_t n;
	bool numeric;
	long value;
};

static int addr_token(const char **pp, struct addr_token *t)
{
	const char *p = *pp;

	t->s = p;
	if (addr_is_digit(*p)) {
		t->numeric = true;
		t->value = addr_digits(&p);
	} else if (addr_is_alpha(*p)) {
		t->numeric = false;
		t->value = -1;
		while (addr_is_alpha(*p))
			p++;
	} else {
		return DF1_E_ADDR_SYNTAX;
	}
	t->n = (size_t)(p - t->s);
	*pp = p;
	return 0;
}

/* Range and shape rules shared by parse (after tokenising) and format. */
static int addr_check_fields(const struct df1_addr *a)
{
	const struct ft_info *fi;

	if (!addr_slc_type(a->type))
		return DF1_E_ADDR_SYNTAX;
	fi = &ft_table[a->type];
	if (a->sub != DF1_ADDR_NONE && (a->sub < 0 || fi->max_sub < 0))
		return a->sub < 0 ? DF1_E_ADDR_RANGE : DF1_E_ADDR_SYNTAX;
	if (a->bit != DF1_ADDR_NONE && (a->bit < 0 || fi->max_bit < 0))
		return a->bit < 0 ? DF1_E_ADDR_RANGE : DF1_E_ADDR_SYNTAX;
	/* a bit of a T/C/R element always names its word (parse gives sub 0 for "/DN") */
	if (addr_is_tcr(a->type) && a->bit != DF1_ADDR_NONE && a->sub == DF1_ADDR_NONE)
		return DF1_E_ADDR_SYNTAX;
	if (a->file < 0 || a->file > MAX_FILE)
		return DF1_E_ADDR_RANGE;
	if (fi->fixed_file >= 0 ? a->file != fi->fixed_file : a->file < 3)
		return DF1_E_ADDR_RANGE;
	if (a->element < 0 || a->element > MAX_ELEMENT)
		return DF1_E_ADDR_RANGE;
	if (a->sub != DF1_ADDR_NONE && a->sub > fi->max_sub)
		return DF1_E_ADDR_RANGE;
	if (a->bit != DF1_ADDR_NONE && a->bit > fi->max_bit)
		return DF1_E_ADDR_RANGE;
	return 0;
}

/* The file type letters and the file number at *pp (a default file when the
 * type has one): a->type, *file. 0 or DF1_E_ADDR_SYNTAX. */
static int addr_type_file(const char **pp, struct df1_addr *a, long *file)
{
	const char *p = *pp, *type_s = p;
	size_t type_n;
	int t;

	while (addr_is_alpha(*p))
		p++;
	type_n = (size_t)(p - type_s);
	a->type = DF1_FT_NONE;
	for (t = DF1_FT_NONE + 1; t < DF1_FT_COUNT_; t++)
		if (addr_slc_type((enum df1_file_type)t) && addr_token_is(type_s, type_n, ft_table[t].name))
			a->type = (enum df1_file_type)t;
	if (a->type == DF1_FT_NONE)
		return DF1_E_ADDR_SYNTAX;

	*file = addr_digits(&p);
	if (*file < 0) {
		if (ft_table[a->type].default_file < 0)
			return DF1_E_ADDR_SYNTAX;
		*file = ft_table[a->type].default_file;
	}
	*pp = p;
	return 0;
}

/* What follows the file: ":element[.sub][/bit]" or, for B, "/bitnum". */
struct addr_rest {
	long element, bitnum;
	struct addr_token sub_tok, bit_tok;
	bool has_sub, has_bit;
};

/* Tokenise the rest of the text (p after the file) into *r. 0 or DF1_E_*. */
static int addr_rest_tokens(const char *p, enum df1_file_type type, struct addr_rest *r)
{
	int rc;

	if (*p == ':') {
		p++;
		r->element = addr_digits(&p);
		if (r->element < 0)
			return DF1_E_ADDR_SYNTAX;
		if (*p == '.') {
			p++;
			rc = addr_token(&p, &r->sub_tok);
			if (rc < 0)
				return rc;
			r->has_sub = true;
		}
		if (*p == '/') {
			p++;
			rc = addr_token(&p, &r->bit_tok);
			if (rc < 0)
				return rc;
			r->has_bit = true;
		}
	} else if (*p == '/' && type == DF1_FT_B) {
		p++;
		r->bitnum = addr_digits(&p);
		if (r->bitnum < 0)
			return DF1_E_ADDR_SYNTAX;
	} else {
		return DF1_E_ADDR_SYNTAX;
	}
	if (*p != '\0')
		return DF1_E_ADDR_SYNTAX;
	return 0;
}

/* ".sub": a number or a word name, or (PLC-5 spelling) a bit name. 0 or DF1_E_*. */
static int addr_set_sub(struct df1_addr *a, const struct addr_rest *r)
{
	int w, b;

	if (ft_table[a->type].max_sub < 0)
		return DF1_E_ADDR_SYNTAX;
	if (r->sub_tok.numeric) {
		a->sub = (int)r->sub_tok.value;
		return 0;
	}
	w = addr_lookup(addr_word_names(a->type), r->sub_tok.s, r->sub_tok.n);
	b = addr_lookup(addr_bit_names(a->type), r->sub_tok.s, r->sub_tok.n);
	if (w >= 0) {
		a->sub = w;
	} else if (b >= 0) {
		/* PLC-5 spelling T4:0.DN: a bit of the control word, nothing may follow */
		if (r->has_bit)
			return DF1_E_ADDR_SYNTAX;
		a->sub = 0;
		a->bit = b;
	} else {
		return DF1_E_ADDR_SYNTAX;
	}
	return 0;
}

/* "/bit": a number or a bit name. 0 or DF1_E_*. */
static int addr_set_bit(struct df1_addr *a, const struct addr_rest *r)
{
	if (ft_table[a->type].max_bit < 0)
		return DF1_E_ADDR_SYNTAX;
	if (r->bit_tok.numeric) {
		a->bit = (int)r->bit_tok.value;
	} else {
		int b = addr_lookup(addr_bit_names(a->type), r->bit_tok.s, r->bit_tok.n);

		/* names live in word 0: "T4:0/DN", not "T4:0.ACC/DN" */
		if (b < 0 || r->has_sub)
			return DF1_E_ADDR_SYNTAX;
		a->bit = b;
	}
	if (addr_is_tcr(a->type) && a->sub == DF1_ADDR_NONE)
		a->sub = 0;
	return 0;
}

/* Parse without the '$' and without touching ascii. */
static int addr_parse_fields(const char *p, struct df1_addr *a)
{
	struct addr_rest r = { .element = -1, .bitnum = -1 };
	long file;
	int rc;

	rc = addr_type_file(&p, a, &file);
	if (rc < 0)
		return rc;
	rc = addr_rest_tokens(p, a->type, &r);
	if (rc < 0)
		return rc;

	a->file = (int)file;
	a->sub = DF1_ADDR_NONE;
	a->bit = DF1_ADDR_NONE;
	if (r.bitnum >= 0) {
		if (r.bitnum > MAX_B_BITNUM)
			return DF1_E_ADDR_RANGE;
		a->element = (int)(r.bitnum / 16);
		a->bit = (int)(r.bitnum % 16);
		return addr_check_fields(a);
	}
	a->element = (int)r.element;
	if (r.has_sub) {
		rc = addr_set_sub(a, &r);
		if (rc < 0)
			return rc;
	}
	if (r.has_bit) {
		rc = addr_set_bit(a, &r);
		if (rc < 0)
			return rc;
	}
	return addr_check_fields(a);
}

int df1_addr_parse(const char *text, struct df1_addr *a)
{
	struct df1_addr tmp;
	const char *p;
	size_t n;
	int rc;

	if (!text || !a)
		return DF1_E_INVAL;
	memset(&tmp, 0, sizeof tmp);
	p = text;
	if (*p == '$')
		p++;
	rc = addr_parse_fields(p, &tmp);
	if (rc < 0)
		return rc;
	if (p != text) {
		n = strlen(p);
		if (n >= sizeof tmp.ascii)
			return DF1_E_ADDR_RANGE;
		memcpy(tmp.ascii, p, n + 1);
	}
	*a = tmp;
	return 0;
}

static int addr_append(char *out, size_t cap, size_t *len, const char *s)
{
	size_t n = strlen(s);

	if (*len + n >= cap)
		return DF1_E_NOSPACE;
	memcpy(out + *len, s, n + 1);
	*len += n;
	return 0;
}

static int addr_append_num(char *out, size_t cap, size_t *len, int v)
{
	char digits[12];
	char s[12];
	int n = 0, i;

	do {
		digits[n++] = (char)('0' + v % 10);
		v /= 10;
	} while (v > 0 && n < 11);
	for (i = 0; i < n; i++)
		s[i] = digits[n - 1 - i];
	s[n] = '\0';
	return addr_append(out, cap, len, s);
}

/* Canonical text into out (big enough for any valid address). */
static int addr_canonical(const struct df1_addr *a, char *out, size_t cap)
{
	size_t len = 0;
	const char *name;
	int rc;

	out[0] = '\0';
	rc = addr_append(out, cap, &len, ft_table[a->type].name);
	rc = rc ? rc : addr_append_num(out, cap, &len, a->file);
	rc = rc ? rc : addr_append(out, cap, &len, ":");
	rc = rc ? rc : addr_append_num(out, cap, &len, a->element);
	if (rc)
		return rc;
	if (addr_is_tcr(a->type) && a->sub == 0 && a->bit != DF1_ADDR_NONE) {
		/* bit of the control word: "/DN" or "/3" */
		rc = addr_append(out, cap, &len, "/");
		name = addr_name_of(addr_bit_names(a->type), a->bit);
		rc = rc ? rc : (name ? addr_append(out, cap, &len, name)
		                     : addr_append_num(out, cap, &len, a->bit));
		return rc ? rc : (int)len;
	}
	if (a->sub != DF1_ADDR_NONE) {
		rc = addr_append(out, cap, &len, ".");
		name = addr_name_of(addr_word_names(a->type), a->sub);
		rc = rc ? rc : (name ? addr_append(out, cap, &len, name)
		                     : addr_append_num(out, cap, &len, a->sub));
	}
	if (!rc && a->bit != DF1_ADDR_NONE) {
		rc = addr_append(out, cap, &len, "/");
		rc = rc ? rc : addr_append_num(out, cap, &len, a->bit);
	}
	return rc ? rc : (int)len;
}

static bool addr_equal(const struct df1_addr *x, const struct df1_addr *y)
{
	return x->type == y->type && x->file == y->file && x->element == y->element &&
	       x->sub == y->sub && x->bit == y->bit && strcmp(x->ascii, y->ascii) == 0;
}

int df1_addr_format(const struct df1_addr *a, char *buf, size_t cap)
{
	char tmp[DF1_ADDR_ASCII_MAX + 8];
	int len;

	if (!a || (!buf && cap > 0))
		return DF1_E_INVAL;
	if (!memchr(a->ascii, '\0', sizeof a->ascii) || addr_check_fields(a) < 0)
		return DF1_E_INVAL;
	if (a->ascii[0] != '\0') {
		struct df1_addr back;

		tmp[0] = '$';
		memcpy(tmp + 1, a->ascii, strlen(a->ascii) + 1);
		/* the fields must be those of the text, or the round trip would break */
		if (df1_addr_parse(tmp, &back) < 0 || !addr_equal(&back, a))
			return DF1_E_INVAL;
		len = (int)strlen(tmp);
	} else {
		len = addr_canonical(a, tmp, sizeof tmp);
		if (len < 0)
			return DF1_E_INVAL;
	}
	if ((size_t)len >= cap)
		return DF1_E_NOSPACE;
	memcpy(buf, tmp, (size_t)len + 1);
	return len;
}

const char *df1_file_type_name(enum df1_file_type t)
{
	return addr_valid_type(t) ? ft_table[t].name : "?";
}

int df1_file_type_element_size(enum df1_file_type t)
{
	return addr_valid_type(t) ? ft_table[t].element_size : DF1_E_INVAL;
}

int df1_file_type_slc_code(enum df1_file_type t)
{
	return addr_valid_type(t) ? ft_table[t].slc_code : DF1_E_INVAL;
}
