/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_json - JSON text out and a strict parser in, for df1gw (see gw_json.h).
 */
#include "df1gw/gw_json.h"
#include "common/cli_text.h"   /* cli_utf8_seq */

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- buffer ---- */

void gw_buf_init(struct gw_buf *b)
{
	memset(b, 0, sizeof *b);
}

void gw_buf_free(struct gw_buf *b)
{
	free(b->p);
	gw_buf_init(b);
}

void gw_buf_reset(struct gw_buf *b)
{
	b->len = 0;
	b->oom = false;
	if (b->p)
		b->p[0] = '\0';
}

static bool buf_room(struct gw_buf *b, size_t more)
{
	size_t want = b->len + more + 1, cap = b->cap ? b->cap : 256;
	char *p;

	if (b->oom)
		return false;
	if (want <= b->cap)
		return true;
	while (cap < want)
		cap *= 2;
	p = realloc(b->p, cap);
	if (!p) {
		b->oom = true;
		return false;
	}
	b->p = p;
	b->cap = cap;
	return true;
}

void gw_buf_add(struct gw_buf *b, const char *s, size_t n)
{
	if (!buf_room(b, n))
		return;
	memcpy(b->p + b->len, s, n);
	b->len += n;
	b->p[b->len] = '\0';
}

void gw_buf_puts(struct gw_buf *b, const char *s)
{
	gw_buf_add(b, s, strlen(s));
}

void gw_buf_printf(struct gw_buf *b, const char *fmt, ...)
{
	va_list ap;
	int n;

	va_start(ap, fmt);
	n = vsnprintf(NULL, 0, fmt, ap);
	va_end(ap);
	if (n < 0 || !buf_room(b, (size_t)n))
		return;
	va_start(ap, fmt);
	vsnprintf(b->p + b->len, (size_t)n + 1, fmt, ap);
	va_end(ap);
	b->len += (size_t)n;
}

/* ---- writing ---- */

/* One ASCII character, escaped as JSON needs; false if it is not plain ASCII. */
static bool json_ascii(struct gw_buf *b, unsigned char ch)
{
	char esc[8];

	switch (ch) {
	case '"': gw_buf_add(b, "\\\"", 2); return true;
	case '\\': gw_buf_add(b, "\\\\", 2); return true;
	case '\n': gw_buf_add(b, "\\n", 2); return true;
	case '\r': gw_buf_add(b, "\\r", 2); return true;
	case '\t': gw_buf_add(b, "\\t", 2); return true;
	default: break;
	}
	if (ch < 0x20 || ch == 0x7F) {
		snprintf(esc, sizeof esc, "\\u%04x", ch);
		gw_buf_add(b, esc, 6);
		return true;
	}
	if (ch < 0x80) {
		gw_buf_add(b, (const char *)&ch, 1);
		return true;
	}
	return false;
}

void gw_json_text(struct gw_buf *b, const char *s, size_t n)
{
	const unsigned char *p = (const unsigned char *)s;
	size_t i = 0;

	gw_buf_add(b, "\"", 1);
	while (i < n) {
		uint32_t cp;
		size_t k;
		char esc[8];

		if (json_ascii(b, p[i])) {
			i++;
			continue;
		}
		k = cli_utf8_seq(p + i, n - i, &cp);
		if (k) {
			gw_buf_add(b, s + i, k);
			i += k;
		} else {
			snprintf(esc, sizeof esc, "\\u%04x", p[i]);
			gw_buf_add(b, esc, 6);
			i++;
		}
	}
	gw_buf_add(b, "\"", 1);
}

void gw_json_bytes(struct gw_buf *b, const uint8_t *s, size_t n)
{
	gw_buf_add(b, "\"", 1);
	for (size_t i = 0; i < n; i++) {
		char esc[8];

		if (!json_ascii(b, s[i])) {
			snprintf(esc, sizeof esc, "\\u%04x", s[i]);
			gw_buf_add(b, esc, 6);
		}
	}
	gw_buf_add(b, "\"", 1);
}

bool gw_utf8_valid(const char *s, size_t n)
{
	const unsigned char *p = (const unsigned char *)s;
	size_t i = 0;

	while (i < n) {
		uint32_t cp;
		size_t k = cli_utf8_seq(p + i, n - i, &cp);

		if (!k)
			return false;
		i += k;
	}
	return true;
}

void gw_rfc3339(int64_t wall_ms, char *out, size_t cap)
{
	time_t t = (time_t)(wall_ms / 1000);
	struct tm tm;

	if (!gmtime_r(&t, &tm)) {
		snprintf(out, cap, "1970-01-01T00:00:00.000Z");
		return;
	}
	snprintf(out, cap, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900, tm.tm_mon + 1,
	         tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, (int)(wall_ms % 1000));
}

/* ---- parsing ---- */

struct jp {
	const char *s;
	size_t n, i;
	char *err;
	size_t errcap;
	bool failed;
};

static void jp_fail(struct jp *p, const char *what)
{
	if (p->failed)
		return;
	p->failed = true;
	if (p->i >= p->n)
		snprintf(p->err, p->errcap, "at byte %zu: %s (the text ends)", p->i, what);
	else
		snprintf(p->err, p->errcap, "at byte %zu: %s", p->i, what);
}

static void jp_blank(struct jp *p)
{
	while (p->i < p->n && (p->s[p->i] == ' ' || p->s[p->i] == '\t' || p->s[p->i] == '\n' ||
	                       p->s[p->i] == '\r'))
		p->i++;
}

static struct gw_jv *jv_new(enum gw_jtype t, size_t start)
{
	struct gw_jv *v = calloc(1, sizeof *v);

	if (v) {
		v->type = t;
		v->start = start;
	}
	return v;
}

void gw_jv_free(struct gw_jv *v)
{
	if (!v)
		return;
	for (size_t i = 0; i < v->n; i++) {
		gw_jv_free(v->items[i]);
		if (v->keys)
			free(v->keys[i]);
	}
	free(v->items);
	free(v->keys);
	free(v->text);
	free(v);
}

static bool jv_push(struct gw_jv *v, struct gw_jv *item, char *key)
{
	struct gw_jv **items = realloc(v->items, (v->n + 1) * sizeof *items);
	char **keys;

	if (!items)
		return false;
	v->items = items;
	if (v->type == GW_JOBJECT) {
		keys = realloc(v->keys, (v->n + 1) * sizeof *keys);
		if (!keys)
			return false;
		v->keys = keys;
		keys[v->n] = key;
	}
	items[v->n++] = item;
	return true;
}

static int hex4(const char *s)
{
	int v = 0;

	for (int k = 0; k < 4; k++) {
		char c = s[k];
		v <<= 4;
		if (c >= '0' && c <= '9')
			v |= c - '0';
		else if (c >= 'a' && c <= 'f')
			v |= c - 'a' + 10;
		else if (c >= 'A' && c <= 'F')
			v |= c - 'A' + 10;
		else
			return -1;
	}
	return v;
}

static void put_utf8(struct gw_buf *b, uint32_t cp)
{
	char u[4];

	if (cp < 0x80) {
		u[0] = (char)cp;
		gw_buf_add(b, u, 1);
	} else if (cp < 0x800) {
		u[0] = (char)(0xC0 | (cp >> 6));
		u[1] = (char)(0x80 | (cp & 0x3F));
		gw_buf_add(b, u, 2);
	} else if (cp < 0x10000) {
		u[0] = (char)(0xE0 | (cp >> 12));
		u[1] = (char)(0x80 | ((cp >> 6) & 0x3F));
		u[2] = (char)(0x80 | (cp & 0x3F));
		gw_buf_add(b, u, 3);
	} else {
		u[0] = (char)(0xF0 | (cp >> 18));
		u[1] = (char)(0x80 | ((cp >> 12) & 0x3F));
		u[2] = (char)(0x80 | ((cp >> 6) & 0x3F));
		u[3] = (char)(0x80 | (cp & 0x3F));
		gw_buf_add(b, u, 4);
	}
}

/* A string at p->i (the opening quote); its UTF-8 text into *b. */
static bool jp_string(struct jp *p, struct gw_buf *b)
{
	p->i++;
	for (;;) {
		unsigned char c;
		uint32_t cp;
		size_t k;

		if (p->i >= p->n) {
			jp_fail(p, "unterminated string");
			return false;
		}
		c = (unsigned char)p->s[p->i];
		if (c == '"') {
			p->i++;
			break;
		}
		if (c < 0x20) {
			jp_fail(p, "control character in a string");
			return false;
		}
		if (c != '\\') {
			k = cli_utf8_seq((const unsigned char *)p->s + p->i, p->n - p->i, &cp);
			if (!k) {
				jp_fail(p, "invalid UTF-8");
				return false;
			}
			gw_buf_add(b, p->s + p->i, k);
			p->i += k;
			continue;
		}
		if (p->i + 1 >= p->n) {
			jp_fail(p, "unterminated string");
			return false;
		}
		c = (unsigned char)p->s[++p->i];
		p->i++;
		switch (c) {
		case '"': gw_buf_add(b, "\"", 1); continue;
		case '\\': gw_buf_add(b, "\\", 1); continue;
		case '/': gw_buf_add(b, "/", 1); continue;
		case 'b': gw_buf_add(b, "\b", 1); continue;
		case 'f': gw_buf_add(b, "\f", 1); continue;
		case 'n': gw_buf_add(b, "\n", 1); continue;
		case 'r': gw_buf_add(b, "\r", 1); continue;
		case 't': gw_buf_add(b, "\t", 1); continue;
		case 'u': break;
		default:
			p->i--;
			jp_fail(p, "invalid escape in a string");
			return false;
		}
		if (p->i + 4 > p->n || hex4(p->s + p->i) < 0) {
			jp_fail(p, "\\u needs four hex digits");
			return false;
		}
		cp = (uint32_t)hex4(p->s + p->i);
		p->i += 4;
		if (cp >= 0xD800 && cp <= 0xDBFF) {
			int lo;

			if (p->i + 6 > p->n || p->s[p->i] != '\\' || p->s[p->i + 1] != 'u' ||
			    (lo = hex4(p->s + p->i + 2)) < 0xDC00 || lo > 0xDFFF) {
				jp_fail(p, "unpaired surrogate");
				return false;
			}
			cp = 0x10000 + ((cp - 0xD800) << 10) + ((uint32_t)lo - 0xDC00);
			p->i += 6;
		} else if (cp >= 0xDC00 && cp <= 0xDFFF) {
			jp_fail(p, "unpaired surrogate");
			return false;
		}
		put_utf8(b, cp);
	}
	if (b->oom) {
		jp_fail(p, "out of memory");
		return false;
	}
	return true;
}

static bool is_digit(char c)
{
	return c >= '0' && c <= '9';
}

static struct gw_jv *jp_number(struct jp *p)
{
	size_t start = p->i;
	struct gw_jv *v;

	if (p->s[p->i] == '-')
		p->i++;
	if (p->i < p->n && p->s[p->i] == '0') {
		p->i++;
	} else if (p->i < p->n && is_digit(p->s[p->i])) {
		while (p->i < p->n && is_digit(p->s[p->i]))
			p->i++;
	} else {
		jp_fail(p, "invalid number");
		return NULL;
	}
	if (p->i < p->n && p->s[p->i] == '.') {
		p->i++;
		if (p->i >= p->n || !is_digit(p->s[p->i])) {
			jp_fail(p, "a digit must follow the decimal point");
			return NULL;
		}
		while (p->i < p->n && is_digit(p->s[p->i]))
			p->i++;
	}
	if (p->i < p->n && (p->s[p->i] == 'e' || p->s[p->i] == 'E')) {
		p->i++;
		if (p->i < p->n && (p->s[p->i] == '+' || p->s[p->i] == '-'))
			p->i++;
		if (p->i >= p->n || !is_digit(p->s[p->i])) {
			jp_fail(p, "a digit must follow the exponent");
			return NULL;
		}
		while (p->i < p->n && is_digit(p->s[p->i]))
			p->i++;
	}
	v = jv_new(GW_JNUMBER, start);
	if (!v || !(v->text = malloc(p->i - start + 1))) {
		free(v);
		jp_fail(p, "out of memory");
		return NULL;
	}
	memcpy(v->text, p->s + start, p->i - start);
	v->text[p->i - start] = '\0';
	v->len = p->i - start;
	return v;
}

static bool jp_word(struct jp *p, const char *w)
{
	size_t l = strlen(w);

	if (p->n - p->i < l || memcmp(p->s + p->i, w, l) != 0)
		return false;
	p->i += l;
	return true;
}

static struct gw_jv *jp_value(struct jp *p, int depth);

static struct gw_jv *jp_container(struct jp *p, int depth, bool object)
{
	struct gw_jv *v = jv_new(object ? GW_JOBJECT : GW_JARRAY, p->i);
	char close = object ? '}' : ']';

	if (!v) {
		jp_fail(p, "out of memory");
		return NULL;
	}
	if (depth >= GW_JSON_MAX_DEPTH) {
		jp_fail(p, "nested too deep");
		free(v);
		return NULL;
	}
	p->i++;
	jp_blank(p);
	if (p->i < p->n && p->s[p->i] == close) {
		p->i++;
		return v;
	}
	for (;;) {
		char *key = NULL;
		struct gw_jv *item;

		jp_blank(p);
		if (object) {
			struct gw_buf k;

			if (p->i >= p->n || p->s[p->i] != '"') {
				jp_fail(p, "expected a member name in double quotes");
				goto bad;
			}
			gw_buf_init(&k);
			if (!jp_string(p, &k)) {
				gw_buf_free(&k);
				goto bad;
			}
			key = k.p ? k.p : strdup("");
			if (!key || strlen(key) != k.len) {
				free(key);
				jp_fail(p, key ? "NUL in a member name" : "out of memory");
				goto bad;
			}
			if (gw_jv_get(v, key)) {
				free(key);
				jp_fail(p, "duplicate member name");
				goto bad;
			}
			jp_blank(p);
			if (p->i >= p->n || p->s[p->i] != ':') {
				free(key);
				jp_fail(p, "expected ':'");
				goto bad;
			}
			p->i++;
		}
		item = jp_value(p, depth + 1);
		if (!item) {
			free(key);
			goto bad;
		}
		if (!jv_push(v, item, key)) {
			gw_jv_free(item);
			free(key);
			jp_fail(p, "out of memory");
			goto bad;
		}
		jp_blank(p);
		if (p->i < p->n && p->s[p->i] == ',') {
			p->i++;
			continue;
		}
		if (p->i < p->n && p->s[p->i] == close) {
			p->i++;
			return v;
		}
		jp_fail(p, object ? "expected ',' or '}'" : "expected ',' or ']'");
		goto bad;
	}
bad:
	gw_jv_free(v);
	return NULL;
}

static struct gw_jv *jp_value(struct jp *p, int depth)
{
	struct gw_jv *v = NULL;
	size_t start;

	jp_blank(p);
	start = p->i;
	if (p->i >= p->n) {
		jp_fail(p, "expected a value");
		return NULL;
	}
	switch (p->s[p->i]) {
	case '{':
		v = jp_container(p, depth, true);
		break;
	case '[':
		v = jp_container(p, depth, false);
		break;
	case '"': {
		struct gw_buf b;

		gw_buf_init(&b);
		if (!jp_string(p, &b)) {
			gw_buf_free(&b);
			return NULL;
		}
		v = jv_new(GW_JSTRING, start);
		if (v) {
			v->text = b.p ? b.p : strdup("");
			v->len = b.len;
		}
		if (!v || !v->text) {
			gw_jv_free(v);
			free(b.p);
			jp_fail(p, "out of memory");
			return NULL;
		}
		break;
	}
	case 't':
	case 'f':
	case 'n':
		if (jp_word(p, "true") || jp_word(p, "false")) {
			v = jv_new(GW_JBOOL, start);
			if (v)
				v->b = p->s[start] == 't';
		} else if (jp_word(p, "null")) {
			v = jv_new(GW_JNULL, start);
		} else {
			jp_fail(p, "expected a value");
			return NULL;
		}
		if (!v)
			jp_fail(p, "out of memory");
		break;
	default:
		if (p->s[p->i] == '-' || is_digit(p->s[p->i]))
			v = jp_number(p);
		else
			jp_fail(p, "expected a value");
		break;
	}
	if (v)
		v->end = p->i;
	return v;
}

struct gw_jv *gw_json_parse(const char *in, size_t n, char *err, size_t errcap)
{
	struct jp p = { in, n, 0, err, errcap, false };
	struct gw_jv *v;

	if (errcap)
		err[0] = '\0';
	if (n > GW_JSON_MAX_BYTES) {
		snprintf(err, errcap, "longer than %d bytes", GW_JSON_MAX_BYTES);
		return NULL;
	}
	v = jp_value(&p, 0);
	if (!v)
		return NULL;
	jp_blank(&p);
	if (p.i != n) {
		jp_fail(&p, "text after the value");
		gw_jv_free(v);
		return NULL;
	}
	return v;
}

const struct gw_jv *gw_jv_get(const struct gw_jv *obj, const char *key)
{
	if (!obj || obj->type != GW_JOBJECT)
		return NULL;
	for (size_t i = 0; i < obj->n; i++)
		if (strcmp(obj->keys[i], key) == 0)
			return obj->items[i];
	return NULL;
}

bool gw_jv_latin1(const struct gw_jv *s, uint8_t *out, size_t cap, size_t *len)
{
	const unsigned char *p = (const unsigned char *)s->text;
	size_t i = 0, k = 0;

	if (s->type != GW_JSTRING)
		return false;
	while (i < s->len) {
		uint32_t cp;
		size_t l = cli_utf8_seq(p + i, s->len - i, &cp);

		if (!l || cp > 0xFF || k >= cap)
			return false;
		out[k++] = (uint8_t)cp;
		i += l;
	}
	*len = k;
	return true;
}
