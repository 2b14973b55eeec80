/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_msg - one message for the broker: its topic, its payload's bytes, and
 * how it goes (retain, QoS). The formats make them (gw_format.h), gw_pub.c,
 * gw_receive.c and gw_sfwd.c hand them to the carrier (gw_mqtt.h). A leaf:
 * it calls nothing of df1gw but the byte buffer (gw_json.h), so that the
 * formats and the table of formats (gw_format.c) both use it without
 * calling each other.
 */
#ifndef DF1_TOOLS_GW_MSG_H
#define DF1_TOOLS_GW_MSG_H

#include <stdbool.h>

#include "df1gw/gw_json.h"

#define GW_TOPIC_MAX 512

/* One message for the carrier. */
struct gw_msg {
	char topic[GW_TOPIC_MAX];
	struct gw_buf body;          /* the payload's bytes */
	bool retain;
	int qos;                     /* -1: the connection's (--qos) */
};

/* Empty, not retained, the connection's QoS; gw_msg_free() ends it. */
void gw_msg_init(struct gw_msg *m);
void gw_msg_free(struct gw_msg *m);
/* Empty topic and body, not retained; keeps the memory. */
void gw_msg_reset(struct gw_msg *m);

/* A JSON object payload with one more member, "name": v, as its last (a
 * Receive tag's "from", gw_receive.c and gw_sfwd.c). 0, or -1 (not an
 * object, no memory). */
int gw_msg_json_add_int(struct gw_msg *m, const char *name, long v);

#endif
