/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_write - .../set payloads, remembered ids, results (see gw_write.h).
 */
#include "df1gw/gw_write.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1.h"

void gw_set_free(struct gw_set *s)
{
	gw_jv_free(s->root);
	s->root = NULL;
	s->value = NULL;
	s->id[0] = '\0';
	s->timeout_ms = -1;
}

/* "timeout_ms": an integer of milliseconds, 1..GW_TIMEOUT_MS_MAX. */
static int set_timeout(struct gw_set *s, char *err, size_t errcap)
{
	const struct gw_jv *t = gw_jv_get(s->root, "timeout_ms");
	char *end;
	long v;

	if (!t)
		return 0;
	if (t->type != GW_JNUMBER || strpbrk(t->text, ".eE-")) {
		snprintf(err, errcap, "\"timeout_ms\" must be a whole number of milliseconds");
		return -1;
	}
	v = strtol(t->text, &end, 10);
	if (*end || v < 1 || v > GW_TIMEOUT_MS_MAX) {
		snprintf(err, errcap, "\"timeout_ms\" %s: must be 1..%ld", t->text, GW_TIMEOUT_MS_MAX);
		return -1;
	}
	s->timeout_ms = v;
	return 0;
}

int gw_set_parse(const char *payload, size_t n, struct gw_set *s, char *err, size_t errcap)
{
	const struct gw_jv *id;
	char jerr[160];

	memset(s, 0, sizeof *s);
	s->root = gw_json_parse(payload, n, jerr, sizeof jerr);
	if (!s->root) {
		snprintf(err, errcap, "not JSON: %s", jerr);
		return -1;
	}
	s->value = s->root;
	s->timeout_ms = -1;
	if (s->root->type != GW_JOBJECT || !gw_jv_get(s->root, "value"))
		return 0;
	/* the wrapper: {"value": ..., "id": ..., "timeout_ms": ...} and nothing else */
	for (size_t i = 0; i < s->root->n; i++) {
		if (strcmp(s->root->keys[i], "value") != 0 && strcmp(s->root->keys[i], "id") != 0 &&
		    strcmp(s->root->keys[i], "timeout_ms") != 0) {
			snprintf(err, errcap, "unknown member \"%s\" beside \"value\" (only \"id\" and \"timeout_ms\" "
			         "may be there)", s->root->keys[i]);
			gw_set_free(s);
			return -1;
		}
	}
	if (set_timeout(s, err, errcap) < 0) {
		gw_set_free(s);
		return -1;
	}
	s->value = gw_jv_get(s->root, "value");
	id = gw_jv_get(s->root, "id");
	if (id) {
		size_t len = id->end - id->start;

		if (id->type != GW_JSTRING && id->type != GW_JNUMBER) {
			snprintf(err, errcap, "\"id\" must be a string or a number");
			gw_set_free(s);
			return -1;
		}
		if (len > GW_ID_MAX) {
			snprintf(err, errcap, "\"id\" longer than %d bytes", GW_ID_MAX);
			gw_set_free(s);
			return -1;
		}
		memcpy(s->id, payload + id->start, len);
		s->id[len] = '\0';
	}
	return 0;
}

int gw_ids_init(struct gw_ids *ids, size_t cap)
{
	memset(ids, 0, sizeof *ids);
	ids->ring = calloc(cap ? cap : 1, sizeof *ids->ring);
	if (!ids->ring)
		return -1;
	ids->cap = cap ? cap : 1;
	return 0;
}

void gw_ids_free(struct gw_ids *ids)
{
	for (size_t i = 0; ids->ring && i < ids->cap; i++)
		free(ids->ring[i]);
	free(ids->ring);
	memset(ids, 0, sizeof *ids);
}

bool gw_ids_seen(const struct gw_ids *ids, const char *id)
{
	for (size_t i = 0; i < ids->n; i++)
		if (strcmp(ids->ring[i], id) == 0)
			return true;
	return false;
}

int gw_ids_add(struct gw_ids *ids, const char *id)
{
	char *copy = strdup(id);

	if (!copy)
		return -1;
	free(ids->ring[ids->next]);
	ids->ring[ids->next] = copy;
	ids->next = (ids->next + 1) % ids->cap;
	if (ids->n < ids->cap)
		ids->n++;
	return 0;
}

void gw_result_json(struct gw_buf *b, const char *id, bool ok, const char *error, bool unconfirmed)
{
	gw_buf_printf(b, "{\"id\":%s,\"ok\":%s,\"error\":", id && *id ? id : "null", ok ? "true" : "false");
	if (error)
		gw_json_text(b, error, strlen(error));
	else
		gw_buf_puts(b, "null");
	gw_buf_printf(b, ",\"unconfirmed\":%s}", unconfirmed ? "true" : "false");
}

bool gw_write_unconfirmed(int err)
{
	/* a tag write is one command (one tag's elements in one packet) */
	return err != DF1_OK && !df1_error_unexecuted(err);
}
