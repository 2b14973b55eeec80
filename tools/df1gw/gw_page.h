/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_page - the status page of df1gw --http: one HTML file, its script and
 * its style, compiled in (no CDN, no framework: it works on a plant network
 * without the Internet). The script reads /api/status every 2 s and builds
 * the page with textContent only, so whatever a tag name or an error holds
 * is shown as text; a second script keeps the answers of the last minutes
 * and draws them as inline SVG charts.
 */
#ifndef DF1_TOOLS_GW_PAGE_H
#define DF1_TOOLS_GW_PAGE_H

#include <stddef.h>

/* The content policy of every answer: only this server's script, style and
 * data; no inline script, no framing, no forms. */
#define GW_PAGE_CSP \
	"default-src 'none'; script-src 'self'; style-src 'self'; connect-src 'self'; img-src 'self'; " \
	"base-uri 'none'; form-action 'none'; frame-ancestors 'none'"

struct gw_page_file {
	const char *path;            /* "/", "/app.js", "/chart.js", "/app.css" */
	const char *type;            /* its Content-Type */
	const char *body;
	size_t len;
};

/* The charts' script, /chart.js (gw_page_chart.c). */
extern const struct gw_page_file gw_page_chart;

/* The file served at url, or NULL. */
const struct gw_page_file *gw_page_find(const char *url);

#endif
