/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_text - JSON and CSV quoting, hex dumps and hex parsing (see cli_text.h).
 * Below both cli and decode: it includes neither.
 */
#include "common/cli_text.h"

#include <string.h>

/* Length of a valid UTF-8 sequence at s (at most n bytes), or 0. */
size_t cli_utf8_seq(const unsigned char *s, size_t n, uint32_t *cp_out)
{
	size_t len;
	uint32_t cp;

	if (n == 0)
		return 0;
	if (s[0] < 0x80) {
		if (cp_out)
			*cp_out = s[0];
		return 1;
	}
	if (s[0] >= 0xC2 && s[0] <= 0xDF) {
		len = 2;
		cp = s[0] & 0x1F;
	} else if (s[0] >= 0xE0 && s[0] <= 0xEF) {
		len = 3;
		cp = s[0] & 0x0F;
	} else if (s[0] >= 0xF0 && s[0] <= 0xF4) {
		len = 4;
		cp = s[0] & 0x07;
	} else {
		return 0;
	}
	if (len > n)
		return 0;
	for (size_t i = 1; i < len; i++) {
		if ((s[i] & 0xC0) != 0x80)
			return 0;
		cp = (cp << 6) | (s[i] & 0x3F);
	}
	/* overlong forms, surrogates and code points past U+10FFFF are not UTF-8 */
	if ((len == 3 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
	    (len == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
		return 0;
	if (cp_out)
		*cp_out = cp;
	return len;
}

void cli_json_string_n(FILE *f, const char *s, size_t n)
{
	const unsigned char *p = (const unsigned char *)s;
	size_t i = 0, k;

	fputc('"', f);
	while (i < n) {
		unsigned char ch = p[i];
		switch (ch) {
		case '"': fputs("\\\"", f); i++; continue;
		case '\\': fputs("\\\\", f); i++; continue;
		case '\n': fputs("\\n", f); i++; continue;
		case '\r': fputs("\\r", f); i++; continue;
		case '\t': fputs("\\t", f); i++; continue;
		case '\b': fputs("\\b", f); i++; continue;
		case '\f': fputs("\\f", f); i++; continue;
		default: break;
		}
		if (ch < 0x20 || ch == 0x7F) {
			fprintf(f, "\\u%04x", ch);
			i++;
			continue;
		}
		k = cli_utf8_seq(p + i, n - i, NULL);
		if (k == 0) {
			/* not UTF-8: take the byte as Latin-1 */
			fprintf(f, "\\u%04x", ch);
			i++;
			continue;
		}
		fwrite(p + i, 1, k, f);
		i += k;
	}
	fputc('"', f);
}

void cli_json_string(FILE *f, const char *s)
{
	cli_json_string_n(f, s ? s : "", s ? strlen(s) : 0);
}

void cli_csv_quoted(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		if (*s == '"')
			fputc('"', f);
		fputc(*s, f);
	}
	fputc('"', f);
}

void cli_csv_field(FILE *f, const char *s)
{
	size_t n;

	if (!s)
		s = "";
	n = strlen(s);
	if (!strpbrk(s, ",\"\r\n") && !(n && (s[0] == ' ' || s[n - 1] == ' ')))
		fputs(s, f);
	else
		cli_csv_quoted(f, s);
}

size_t cli_hex(const uint8_t *b, size_t n, char *buf, size_t cap)
{
	static const char digits[] = "0123456789ABCDEF";
	size_t o = 0;

	if (cap == 0)
		return 0;
	for (size_t i = 0; i < n && o + 3 <= cap; i++) {
		if (i) {
			if (o + 4 > cap)
				break;
			buf[o++] = ' ';
		}
		buf[o++] = digits[b[i] >> 4];
		buf[o++] = digits[b[i] & 15];
	}
	buf[o] = 0;
	return o;
}

static int hexval(int ch)
{
	if (ch >= '0' && ch <= '9')
		return ch - '0';
	if (ch >= 'a' && ch <= 'f')
		return ch - 'a' + 10;
	if (ch >= 'A' && ch <= 'F')
		return ch - 'A' + 10;
	return -1;
}

long cli_parse_hex(const char *text, uint8_t *out, size_t cap, size_t *bad_at)
{
	size_t i = 0, n = 0;

	while (text[i]) {
		size_t start, digits;

		if (strchr(" \t\r\n:,-", text[i])) {
			i++;
			continue;
		}
		/* one token: [0x]HEXHEX... */
		start = i;
		if (text[i] == '0' && (text[i + 1] == 'x' || text[i + 1] == 'X') && hexval(text[i + 2]) >= 0)
			i += 2;
		digits = i;
		while (text[i] && hexval((unsigned char)text[i]) >= 0)
			i++;
		if (text[i] && !strchr(" \t\r\n:,-", text[i])) {
			if (bad_at)
				*bad_at = i;
			return -1;
		}
		if ((i - digits) % 2 != 0 || i == digits) {
			if (bad_at)
				*bad_at = start;
			return -1;
		}
		for (size_t k = digits; k < i; k += 2) {
			if (n >= cap) {
				if (bad_at)
					*bad_at = k;
				return -1;
			}
			out[n++] = (uint8_t)(hexval((unsigned char)text[k]) << 4 | hexval((unsigned char)text[k + 1]));
		}
	}
	return (long)n;
}
