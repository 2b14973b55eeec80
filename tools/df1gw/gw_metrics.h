/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_metrics - df1gw's figures as one table (gw_metrics.c), written either
 * in Prometheus' text exposition format (version 0.0.4: # HELP, # TYPE, one
 * sample a line) for /metrics, or as the same families in JSON for
 * /api/status, which adds the line, stations, tags, broker and EtherNet/IP
 * state the status page shows. Reads struct gw only: never the PLC.
 */
#ifndef DF1_TOOLS_GW_METRICS_H
#define DF1_TOOLS_GW_METRICS_H

#include <stdbool.h>

#include "df1gw/gw_json.h"

struct gw;

/* Where samples go: Prometheus text or the JSON "metrics" array. */
struct gw_msink {
	struct gw_buf *b;
	bool json;
	int families;                /* begun so far */
	int samples;                 /* in the current family */
};

/* A family: its name (df1_..., units in the name, _total for counters), type
 * ("counter", "gauge", "histogram") and help text. */
void gw_msink_family(struct gw_msink *s, const char *name, const char *type, const char *help);
/* A sample of the current family: name (the family's, or with _bucket, _sum,
 * _count), labels as NULL-terminated key, value pairs (NULL: none), value. */
void gw_msink_sample(struct gw_msink *s, const char *name, const char *const *labels, double v);
/* Close the JSON array (nothing for text). */
void gw_msink_end(struct gw_msink *s);

/* Every metric of the table into b: Prometheus text (json false) or a JSON
 * array of {"name","type","help","samples":[{"name","labels","value"}]}. */
void gw_metrics_write(const struct gw *g, struct gw_buf *b, bool json);
/* /api/status: {"summary", "version", "start_time", "line", "stations",
 * "tags", "broker", "eip", "http", "metrics"}. */
void gw_status_json(const struct gw *g, struct gw_buf *b);

#endif
