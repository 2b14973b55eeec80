/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_mqtt - df1gw's broker side on libmosquitto, driven by the daemon's own
 * poll() loop (no libmosquitto thread): the socket and the events it waits
 * for, loop_read / loop_write / loop_misc when poll() says so, connecting
 * without blocking the loop, reconnecting with an exponential backoff
 * (0.5 s doubling to 30 s), the last will it is given. It carries bytes:
 * what they say is the payload formats' (gw_format.h).
 *
 * Faults: a try that fails in any way (TCP refused or reset, the TLS
 * handshake, no CONNACK in time, a refusal) ends in DOWN, and the next try
 * gets a new libmosquitto handle (df1gw(1), BROKER CONNECTION).
 * What went wrong is said once per outage and reason, and when it recovers;
 * -v says every try.
 */
#ifndef DF1_TOOLS_GW_MQTT_H
#define DF1_TOOLS_GW_MQTT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

struct mosquitto;

struct gw_mqtt_config {
	const char *prog;          /* message prefix: "df1gw" */
	const char *url;           /* as given, for messages */
	const char *host;
	int port;
	bool tls;
	const char *cafile, *cert, *key;
	const char *client_id;
	const char *username, *password;   /* NULL: none */
	int keepalive;             /* seconds */
	int qos;                   /* 0 or 1 */
	/* the last will as the payload format makes it: topic (NULL: none),
	 * payload bytes, retain flag; sent with qos */
	const char *will_topic;
	const void *will_payload;
	size_t will_len;
	bool will_retain;
	int verbose;
	bool quiet;
};

struct gw_mqtt_events {
	void *user;
	void (*connected)(void *user);          /* the broker accepted us (again) */
	void (*message)(void *user, const char *topic, const void *payload, int len, bool retain);
	void (*connecting)(void *user);         /* before each connect: gw_mqtt_will() may change the will */
	/* store and forward (gw_sfwd.c): the PUBACK of a QoS 1 publication's
	 * mid; the connection gone (what was not acknowledged is lost with
	 * the handle's session). NULL: none. */
	void (*acked)(void *user, int mid);
	void (*lost)(void *user);
};

enum gw_mqtt_state { GW_MQTT_DOWN, GW_MQTT_CONNECTING, GW_MQTT_UP };

struct gw_mqtt {
	struct mosquitto *m;
	struct gw_mqtt_config cfg;
	struct gw_mqtt_events ev;
	enum gw_mqtt_state state;
	bool started;              /* the first connect was tried */
	bool ever_up;
	int refused;               /* the CONNACK code of a refusal, 0 = none */
	char refused_text[160];    /* the broker's reason */
	int backoff_ms;
	int64_t next_try_ms;       /* DOWN: when to try again */
	unsigned inflight;         /* QoS 1 publications not acknowledged yet */
	bool drop;                 /* gw_mqtt_reconnect: leave and connect again, after the loop call */

	/* faults: what the operator is told (gw_mqtt.c, mq_fail / on_connect) */
	int64_t try_ms;            /* CONNECTING: when this try began */
	int64_t down_since_ms;     /* the outage's first failure, 0: none */
	unsigned tries;            /* failed tries in this outage */
	int sock_errno;            /* this try: the socket's error seen under TLS, 0: none */
	char tls_why[200];         /* this try: OpenSSL's reason from libmosquitto's log */
	char said[1024];           /* the reasons printed in this outage, each ending in '\n' */
	bool renew;                /* a new handle before the next try */
};

/* libmosquitto set up from c (copied; its strings must outlive q): TLS files,
 * credentials, the will. Returns 0, or -1 with err (a configuration error). */
int gw_mqtt_init(struct gw_mqtt *q, const struct gw_mqtt_config *c, const struct gw_mqtt_events *ev,
                 char *err, size_t errcap);
/* Disconnect (no will: a clean end) and free. */
void gw_mqtt_close(struct gw_mqtt *q);

/* The socket to poll (-1: none) and the events to wait for. */
int gw_mqtt_fd(const struct gw_mqtt *q);
short gw_mqtt_poll_events(const struct gw_mqtt *q);
/* Milliseconds until gw_mqtt_service() has work without an event. */
int gw_mqtt_wait_ms(const struct gw_mqtt *q, int64_t now);
/* After poll(): read, write, keepalive, (re)connect when due. */
void gw_mqtt_service(struct gw_mqtt *q, short revents, int64_t now);

/* gw_mqtt_service with the socket's events as they are now (no wait): from
 * inside the line's work (a batch of writes, a long scan), so that the broker
 * is served whatever the line is doing. */
void gw_mqtt_turn(struct gw_mqtt *q, int64_t now);

/* Publish (queued by libmosquitto until written). 0, or -1 when not up. */
int gw_mqtt_publish(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, bool retain);
int gw_mqtt_subscribe(struct gw_mqtt *q, const char *pattern);
/* Sparkplug: a publication with its own QoS (-1: the connection's); the
 * will of the next connect (NULL topic: none); leave cleanly (no will) and
 * connect again at once (done by the next gw_mqtt_service: it may be asked
 * from inside a libmosquitto callback). */
int gw_mqtt_publish_qos(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, int qos, bool retain);
/* The same, its message id in *mid (store and forward: the PUBACK names it). */
int gw_mqtt_publish_mid(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, int qos, bool retain,
                        int *mid);
int gw_mqtt_will(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, int qos, bool retain);
void gw_mqtt_reconnect(struct gw_mqtt *q, int64_t now);
bool gw_mqtt_up(const struct gw_mqtt *q);
/* Nothing waits to be written or acknowledged. */
bool gw_mqtt_idle(const struct gw_mqtt *q);

#endif
