/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_spb_metrics - a tag as Sparkplug metrics (df1gw(1), SPARKPLUG): its
 * name, datatype from the file type (N Int16, L Int32, F Float, bits
 * Boolean, ST String; several elements as the matching array type; a timer,
 * counter or control as its members "Name/ACC", "Name/DN"), its value, its
 * quality as the properties Quality and Reason when it is not GOOD; the alias
 * of each metric; a command's metric back into values for df1_tag_write().
 * Pure: no I/O, no clock.
 */
#ifndef DF1_TOOLS_GW_SPB_METRICS_H
#define DF1_TOOLS_GW_SPB_METRICS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1.h"
#include "df1gw/gw_format.h"
#include "df1gw/gw_spb_codec.h"

/* Quality codes of the property "Quality": Ignition 8's QualityCode as Int32,
 * as Cirrus Link's modules send it (df1gw(1) SPARKPLUG): the level in the top
 * two bits (Bad 0x80000000, Uncertain 0x40000000) over the subcode (Bad 512,
 * Bad_Stale 516, Bad_NotConnected 522, Uncertain 256, Uncertain_LastKnownValue
 * 257). Good, 192, is never sent: a metric without the property is good. */
#define GW_SPB_Q_BAD ((int32_t)(0x80000000u | 512u))
#define GW_SPB_Q_BAD_STALE ((int32_t)(0x80000000u | 516u))
#define GW_SPB_Q_BAD_NOT_CONNECTED ((int32_t)(0x80000000u | 522u))
#define GW_SPB_Q_UNCERTAIN ((int32_t)(0x40000000u | 256u))
#define GW_SPB_Q_UNCERTAIN_LAST_KNOWN ((int32_t)(0x40000000u | 257u))

/* Metrics being made, with the text and bytes they point to. */
struct gw_spb_list {
	struct gw_spb_metric *v;
	size_t n, cap;
	void **own;                  /* what the metrics point to, freed with the list */
	size_t nown, capown;
	bool oom;
};

void gw_spb_list_init(struct gw_spb_list *l);
void gw_spb_list_reset(struct gw_spb_list *l);       /* empty; frees what it owned */
void gw_spb_list_free(struct gw_spb_list *l);
/* A new metric at the end (gw_spb_metric_init'ed), or NULL when out of memory. */
struct gw_spb_metric *gw_spb_list_add(struct gw_spb_list *l);
/* A copy of s kept by the list, or NULL. */
const char *gw_spb_list_text(struct gw_spb_list *l, const char *s);

/* How the metrics of a tag are made. */
struct gw_spb_how {
	bool birth;                  /* names always; datatypes; aliases too when aliases */
	bool aliases;                /* --sparkplug-aliases: DATA carries the alias only */
	bool historical;             /* is_historical (store and forward's replay) */
};

/* The alias of tag id's metric member (0: the tag itself). */
uint64_t gw_spb_alias(int id, unsigned member);

/* Tag t's metrics, stamped ms (0: none), appended to l. 0, or -1 (no memory). */
int gw_spb_tag_metrics(struct gw_spb_list *l, const struct gw_tag_out *t, int64_t ms, const struct gw_spb_how *how);

/* A tag's value at a time, as store and forward keeps it. */
struct gw_spb_sample {
	const struct gw_tag_out *t;
	int64_t ms;                  /* when it was read (ms since the epoch) */
};

/* The DDATA payload of samples s[0..n), historical or not (no seq). 0 or -1. */
int gw_spb_ddata_encode(struct gw_buf *out, struct gw_spb_list *scratch, const struct gw_spb_sample *s, size_t n,
                        bool historical, bool aliases, int64_t payload_ms);

/* A command's metric m names which tag and member: by name "Tag" or
 * "Tag/MEMBER" (tag's name into tag), or by alias (id). true when it names one. */
bool gw_spb_metric_target(const struct gw_spb_metric *m, char *tag, size_t cap, const char **member,
                          int *alias_id, unsigned *alias_member);
/* The values a write of metric m (member: "" or "ACC", "DN", "3/ACC"; or by
 * alias member number) asks of tag c with current state cur. 0, or DF1_E_TYPE
 * / DF1_E_RANGE / DF1_E_INVAL with err. */
int gw_spb_write_values(const struct gw_spb_metric *m, const char *member, unsigned alias_member,
                        const struct df1_tag_config *c, const struct df1_tag_state *cur,
                        struct df1_value *out, size_t cap, size_t *n, char *err, size_t errcap);

#endif
