/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_msink - where gw_metrics' samples go (gw_metrics.h): the Prometheus text
 * exposition format (version 0.0.4: HELP and label values escaped, NaN and
 * +Inf as the format spells them) or the JSON of /api/status (strings through
 * gw_json_text; a number that is not finite as null). Pure: gw_json only.
 */
#include "df1gw/gw_metrics.h"

#include <math.h>
#include <string.h>

/* A label value in the text format: backslash, quote and newline escaped. */
static void prom_label_value(struct gw_buf *b, const char *v)
{
	for (; *v; v++) {
		if (*v == '\\')
			gw_buf_puts(b, "\\\\");
		else if (*v == '"')
			gw_buf_puts(b, "\\\"");
		else if (*v == '\n')
			gw_buf_puts(b, "\\n");
		else
			gw_buf_add(b, v, 1);
	}
}

/* HELP text: backslash and newline escaped. */
static void prom_help(struct gw_buf *b, const char *h)
{
	for (; *h; h++) {
		if (*h == '\\')
			gw_buf_puts(b, "\\\\");
		else if (*h == '\n')
			gw_buf_puts(b, "\\n");
		else
			gw_buf_add(b, h, 1);
	}
}

static void number(struct gw_buf *b, double v, bool json)
{
	if (isnan(v))
		gw_buf_puts(b, json ? "null" : "NaN");
	else if (isinf(v))
		gw_buf_puts(b, json ? "null" : v > 0 ? "+Inf" : "-Inf");
	else if (v == floor(v) && fabs(v) < 9007199254740992.0)
		gw_buf_printf(b, "%.0f", v);
	else
		gw_buf_printf(b, "%.17g", v);
}

void gw_msink_family(struct gw_msink *s, const char *name, const char *type, const char *help)
{
	if (s->json) {
		if (s->families)
			gw_buf_puts(s->b, "]},");
		else
			gw_buf_puts(s->b, "[");
		gw_buf_printf(s->b, "{\"name\":\"%s\",\"type\":\"%s\",\"help\":", name, type);
		gw_json_text(s->b, help, strlen(help));
		gw_buf_puts(s->b, ",\"samples\":[");
	} else {
		gw_buf_printf(s->b, "# HELP %s ", name);
		prom_help(s->b, help);
		gw_buf_printf(s->b, "\n# TYPE %s %s\n", name, type);
	}
	s->families++;
	s->samples = 0;
}

void gw_msink_sample(struct gw_msink *s, const char *name, const char *const *labels, double v)
{
	if (s->json) {
		gw_buf_printf(s->b, "%s{\"name\":\"%s\",\"labels\":{", s->samples ? "," : "", name);
		for (int i = 0; labels && labels[i]; i += 2) {
			gw_buf_printf(s->b, "%s\"%s\":", i ? "," : "", labels[i]);
			gw_json_text(s->b, labels[i + 1], strlen(labels[i + 1]));
		}
		gw_buf_puts(s->b, "},\"value\":");
		number(s->b, v, true);
		gw_buf_puts(s->b, "}");
	} else {
		gw_buf_puts(s->b, name);
		for (int i = 0; labels && labels[i]; i += 2) {
			gw_buf_printf(s->b, "%s%s=\"", i ? "," : "{", labels[i]);
			prom_label_value(s->b, labels[i + 1]);
			gw_buf_puts(s->b, "\"");
		}
		if (labels && labels[0])
			gw_buf_puts(s->b, "}");
		gw_buf_puts(s->b, " ");
		number(s->b, v, false);
		gw_buf_puts(s->b, "\n");
	}
	s->samples++;
}

void gw_msink_end(struct gw_msink *s)
{
	if (s->json)
		gw_buf_puts(s->b, s->families ? "]}]" : "[]");
}

