/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_format_json - df1gw's JSON payloads (df1gw(1), TOPICS AND PAYLOADS), a
 * payload format of gw_format.h: retained PREFIX/tag/NAME and
 * PREFIX/station/N, PREFIX/tag/NAME/result (not retained), PREFIX/status
 * online/offline (retained; offline is the last will too), writes on
 * PREFIX/tag/NAME/set. Built with gw_json.c, gw_value.c and gw_write.c.
 */
#include "df1gw/gw_format.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "df1gw/gw_value.h"
#include "df1gw/gw_write.h"

_Static_assert(GW_ID_MAX <= GW_WRITE_ID_MAX, "a JSON id fits gw_write_in.id");

static void json_start(const struct gw_fmt *f, struct gw_msg *m, bool retain, const char *fmt, const char *a)
{
	gw_msg_reset(m);
	m->retain = retain;
	snprintf(m->topic, sizeof m->topic, fmt, f->prefix, a);
}

/* The message with its "ts" member; the key is the same text without it. */
static int json_tag(const struct gw_fmt *f, const struct gw_tag_out *t, struct gw_msg *m, struct gw_buf *key)
{
	struct gw_tag_view view = { t->reason, t->quality, t->error, true };
	struct gw_span ts;

	json_start(f, m, true, "%s/tag/%s", t->st->config->name);
	ts = gw_tag_json(&m->body, t->st, &view);
	gw_buf_reset(key);
	if (m->body.oom)
		return -1;
	gw_buf_add(key, m->body.p, ts.at);
	gw_buf_add(key, m->body.p + ts.at + ts.len, m->body.len - ts.at - ts.len);
	return key->oom ? -1 : 0;
}

/* An empty retained message clears the topic. */
static int json_tag_gone(const struct gw_fmt *f, const char *tag, struct gw_msg *m)
{
	json_start(f, m, true, "%s/tag/%s", tag);
	return 0;
}

/* The key is the message up to its error: station, state, error. */
static int json_station(const struct gw_fmt *f, const struct gw_station_out *s, struct gw_msg *m,
                        struct gw_buf *key)
{
	const struct df1_station_health *sh = s->sh;
	struct gw_buf *b = &m->body;
	char ts[40];
	size_t keylen;

	gw_msg_reset(m);
	m->retain = true;
	snprintf(m->topic, sizeof m->topic, "%s/station/%d", f->prefix, s->station);
	gw_buf_printf(b, "{\"station\":%d,\"state\":\"%s\",\"error\":", s->station, s->state);
	if (s->error)
		gw_json_text(b, s->error, strlen(s->error));
	else
		gw_buf_puts(b, "null");
	keylen = b->len;
	gw_buf_printf(b, ",\"tags\":%d,\"attempts\":%llu,\"failures\":%llu,\"consecutive_failures\":%d,"
	              "\"last_good\":", sh->tags, (unsigned long long)sh->attempts,
	              (unsigned long long)sh->failures, sh->consecutive_failures);
	if (s->last_good_wall_ms > 0) {
		gw_rfc3339(s->last_good_wall_ms, ts, sizeof ts);
		gw_buf_printf(b, "\"%s\"}", ts);
	} else {
		gw_buf_puts(b, "null}");
	}
	gw_buf_reset(key);
	if (b->oom)
		return -1;
	gw_buf_add(key, b->p, keylen);
	return key->oom ? -1 : 0;
}

/* A message made live turned historical (store and forward, gw_sfwd.c): not
 * retained, and before its closing brace "historical":true, the record's
 * "seq" (a duplicate after a crash has the same) and "read", when it was
 * read. */
static int json_historical(struct gw_msg *m, uint64_t seq, int64_t read_ms)
{
	char ts[40];

	if (m->body.oom || m->body.len < 2 || m->body.p[m->body.len - 1] != '}')
		return -1;
	m->retain = false;
	m->body.len--;
	gw_rfc3339(read_ms, ts, sizeof ts);
	gw_buf_printf(&m->body, ",\"historical\":true,\"seq\":%llu,\"read\":\"%s\"}", (unsigned long long)seq, ts);
	return m->body.oom ? -1 : 0;
}

static int json_tag_historical(const struct gw_fmt *f, const struct gw_tag_out *t, uint64_t seq, struct gw_msg *m)
{
	struct gw_buf key;
	int r;

	gw_buf_init(&key);
	r = json_tag(f, t, m, &key);
	gw_buf_free(&key);
	return r < 0 ? -1 : json_historical(m, seq, t->wall_ms);
}

static int json_station_historical(const struct gw_fmt *f, const struct gw_station_out *s, uint64_t seq,
                                   int64_t read_ms, struct gw_msg *m)
{
	struct gw_buf key;
	int r;

	gw_buf_init(&key);
	r = json_station(f, s, m, &key);
	gw_buf_free(&key);
	return r < 0 ? -1 : json_historical(m, seq, read_ms);
}

static int json_result(const struct gw_fmt *f, const struct gw_result_out *r, struct gw_msg *m)
{
	json_start(f, m, false, "%s/tag/%s/result", r->tag);
	gw_result_json(&m->body, r->id, r->ok, r->ok ? NULL : r->error, r->ok ? false : r->unconfirmed);
	return m->body.oom ? -1 : 0;
}

static int json_status(const struct gw_fmt *f, bool online, struct gw_msg *m)
{
	json_start(f, m, true, "%s/%s", "status");
	gw_buf_puts(&m->body, online ? "online" : "offline");
	return m->body.oom ? -1 : 0;
}

static int json_will(const struct gw_fmt *f, struct gw_msg *m)
{
	return json_status(f, false, m);
}

static void json_set_pattern(const struct gw_fmt *f, char *out, size_t cap)
{
	snprintf(out, cap, "%s/tag/+/set", f->prefix);
}

/* The tag name of PREFIX/tag/NAME/set; false if topic is not one. */
static bool json_set_tag(const struct gw_fmt *f, const char *topic, char *name, size_t cap)
{
	size_t pl = strlen(f->prefix), tl = strlen(topic), nl;

	if (tl < pl + 5 + 4 || strncmp(topic, f->prefix, pl) != 0 || strncmp(topic + pl, "/tag/", 5) != 0 ||
	    strcmp(topic + tl - 4, "/set") != 0)
		return false;
	nl = tl - pl - 5 - 4;
	if (nl == 0 || nl >= cap)
		return false;
	memcpy(name, topic + pl + 5, nl);
	name[nl] = '\0';
	return strchr(name, '/') == NULL;
}

static void json_write_free(struct gw_write_in *w)
{
	struct gw_set *s = w->data;

	if (s) {
		gw_set_free(s);
		free(s);
	}
	w->data = NULL;
	w->id[0] = '\0';
}

/* A bare JSON value, or {"value": ..., "id": ...} (gw_write.h). */
static int json_write_parse(const struct gw_fmt *f, const void *payload, size_t n, struct gw_write_in *w,
                            char *err, size_t errcap)
{
	struct gw_set *s = calloc(1, sizeof *s);

	(void)f;
	memset(w, 0, sizeof *w);
	if (!s) {
		snprintf(err, errcap, "out of memory");
		return -1;
	}
	if (gw_set_parse(payload, n, s, err, errcap) < 0) {
		free(s);
		return -1;
	}
	snprintf(w->id, sizeof w->id, "%s", s->id);
	w->timeout_ms = s->timeout_ms;
	w->data = s;
	return 0;
}

static int json_write_values(const struct gw_fmt *f, const struct gw_write_in *w,
                             const struct df1_tag_config *c, const struct df1_tag_state *cur,
                             struct df1_value *out, size_t cap, size_t *n, char *err, size_t errcap)
{
	const struct gw_set *s = w->data;

	(void)f;
	return gw_value_from_json(s->value, c, cur, out, cap, n, err, errcap);
}

const struct gw_format gw_format_json = {
	.name = "json",
	.open = NULL,
	.close = NULL,
	.tag = json_tag,
	.tag_gone = json_tag_gone,
	.station = json_station,
	.result = json_result,
	.status = json_status,
	.will = json_will,
	.set_pattern = json_set_pattern,
	.set_tag = json_set_tag,
	.write_parse = json_write_parse,
	.write_values = json_write_values,
	.write_free = json_write_free,
	.tag_historical = json_tag_historical,
	.station_historical = json_station_historical,
};
