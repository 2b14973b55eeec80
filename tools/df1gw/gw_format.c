/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_format - the table of df1gw's payload formats, the list of those
 * enabled, and the change test every format's messages go through (see
 * gw_format.h).
 */
#include "df1gw/gw_format.h"

#include <stdio.h>
#include <string.h>

/*
 * The table: one line X(NAME) \ per format, for the file gw_format_NAME.c
 * that defines `const struct gw_format gw_format_NAME`.
 */
#define GW_FORMAT_TABLE(X) \
	X(json) \
	X(sparkplug) \
	/* the end of the table */

#define GW_FORMAT_DECLARE(name) extern const struct gw_format gw_format_##name;
#define GW_FORMAT_ENTRY(name) &gw_format_##name,

GW_FORMAT_TABLE(GW_FORMAT_DECLARE)

static const struct gw_format *const gw_format_table[] = { GW_FORMAT_TABLE(GW_FORMAT_ENTRY) };

const struct gw_format *gw_format_at(size_t i)
{
	return i < sizeof gw_format_table / sizeof gw_format_table[0] ? gw_format_table[i] : NULL;
}

const struct gw_format *gw_format_find(const char *name)
{
	const struct gw_format *f;

	for (size_t i = 0; (f = gw_format_at(i)) != NULL; i++)
		if (strcmp(f->name, name) == 0)
			return f;
	return NULL;
}

int gw_fmts_enable(struct gw_fmts *l, const char *name, const char *prefix, char *err, size_t errcap)
{
	return gw_fmts_enable_conf(l, name, prefix, NULL, err, errcap);
}

int gw_fmts_enable_conf(struct gw_fmts *l, const char *name, const char *prefix, const void *conf, char *err,
                        size_t errcap)
{
	const struct gw_format *ops = gw_format_find(name);
	struct gw_fmt *f;

	if (!ops) {
		snprintf(err, errcap, "no payload format \"%s\"", name);
		return -1;
	}
	for (int i = 0; i < l->n; i++) {
		if (l->v[i].ops == ops) {
			snprintf(err, errcap, "payload format \"%s\" given twice", name);
			return -1;
		}
	}
	if (l->n >= GW_FORMATS_MAX) {
		snprintf(err, errcap, "at most %d payload formats at once", GW_FORMATS_MAX);
		return -1;
	}
	f = &l->v[l->n];
	*f = (struct gw_fmt){ ops, prefix, l->n, NULL, conf };
	if (ops->open && ops->open(f, err, errcap) < 0)
		return -1;
	l->n++;
	return 0;
}

int gw_fmts_enable_list(struct gw_fmts *l, const char *names, const char *prefix, char *err, size_t errcap)
{
	char name[64];

	if (!*names) {
		snprintf(err, errcap, "no payload format");
		return -1;
	}
	for (const char *p = names; *p;) {
		size_t n = strcspn(p, ",");

		if (n == 0 || n >= sizeof name) {
			snprintf(err, errcap, "payload formats \"%s\": a list of names, comma-separated", names);
			return -1;
		}
		memcpy(name, p, n);
		name[n] = '\0';
		if (gw_fmts_enable(l, name, prefix, err, errcap) < 0)
			return -1;
		p += n;
		if (*p == ',' && *++p == '\0') {
			snprintf(err, errcap, "payload formats \"%s\": a list of names, comma-separated", names);
			return -1;
		}
	}
	return 0;
}

void gw_fmts_close(struct gw_fmts *l)
{
	for (int i = 0; i < l->n; i++)
		if (l->v[i].ops->close)
			l->v[i].ops->close(&l->v[i]);
	l->n = 0;
}

bool gw_fmt_tag_changed(const struct gw_fmt *f, struct gw_pub *e, const struct gw_tag_out *t, struct gw_msg *m,
                        struct gw_buf *key, int64_t now, bool force)
{
	/* a session format's births say everything again: no forced repetition */
	return f->ops->tag(f, t, m, key) == 0 &&
	       gw_pub_update(e, f->slot, key->p ? key->p : "", now, force && !f->ops->session);
}

bool gw_fmt_station_changed(const struct gw_fmt *f, struct gw_pub *e, const struct gw_station_out *s,
                            struct gw_msg *m, struct gw_buf *key, int64_t now, bool force)
{
	return f->ops->station(f, s, m, key) == 0 &&
	       gw_pub_update(e, f->slot, key->p ? key->p : "", now, force && !f->ops->session);
}
