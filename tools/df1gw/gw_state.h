/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_state - what df1gw last published on each retained topic (a tag's or a
 * station's), kept by name across reopened lines and reloaded mapping files,
 * so that a topic is published again only when its content changes (the
 * payload without its time: the change key, one per enabled payload format,
 * gw_format.h), when --refresh is due, or when everything is republished
 * after a reconnect. Pure.
 */
#ifndef DF1_TOOLS_GW_STATE_H
#define DF1_TOOLS_GW_STATE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GW_PUB_KEYS 4        /* payload formats enabled at once */

struct gw_pub {
	char *name;          /* what it is: "tag/Pump1", "station/1" */
	char *key[GW_PUB_KEYS]; /* per format (its slot): its change key last published; NULL = none */
	int64_t last_ms;     /* monotonic ms of the last publication */
	bool live;           /* in the current configuration */
	int tag_id;          /* the tag's id in the current handle, or -1 */
	char *config;        /* the tag's configuration as text: a reload compares it */
};

struct gw_pubs {
	struct gw_pub *v;
	size_t n, cap;
};

void gw_pubs_init(struct gw_pubs *p);
void gw_pubs_free(struct gw_pubs *p);
/* The entry for name, made (live, no key) when create and missing; NULL if not
 * there or no memory. Pointers stay valid until the next gw_pubs_get(create)
 * or gw_pubs_remove(). */
struct gw_pub *gw_pubs_get(struct gw_pubs *p, const char *name, bool create);
void gw_pubs_remove(struct gw_pubs *p, struct gw_pub *e);
/* Take key as format slot's published at now if it differs from its last one
 * (or force); returns whether to publish. On no memory it says publish and
 * keeps no key. */
bool gw_pub_update(struct gw_pub *e, int slot, const char *key, int64_t now, bool force);
/* Forget every format's key: the next update publishes (a changed tag). */
void gw_pub_forget(struct gw_pub *e);
/* Set a text field (a key, config) to a copy of s (NULL clears). 0 or -1. */
int gw_pub_set(char **field, const char *s);

#endif
