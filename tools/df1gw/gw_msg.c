/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_msg - one message for the broker (see gw_msg.h).
 */
#include "df1gw/gw_msg.h"

void gw_msg_init(struct gw_msg *m)
{
	m->topic[0] = '\0';
	gw_buf_init(&m->body);
	m->retain = false;
	m->qos = -1;
}

void gw_msg_free(struct gw_msg *m)
{
	gw_buf_free(&m->body);
	gw_msg_init(m);
}

void gw_msg_reset(struct gw_msg *m)
{
	m->topic[0] = '\0';
	gw_buf_reset(&m->body);
	m->retain = false;
	m->qos = -1;
}

int gw_msg_json_add_int(struct gw_msg *m, const char *name, long v)
{
	struct gw_buf *b = &m->body;

	if (b->oom || !b->len || b->p[b->len - 1] != '}')
		return -1;
	b->len--;
	gw_buf_printf(b, "%s\"%s\":%ld}", b->len > 1 ? "," : "", name, v);
	return b->oom ? -1 : 0;
}
