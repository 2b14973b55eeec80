/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_mqtt - the broker side of df1gw on libmosquitto (see gw_mqtt.h).
 */
#include "df1gw/gw_mqtt.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <mosquitto.h>

#define GW_MQTT_BACKOFF_MIN 500
#define GW_MQTT_BACKOFF_MAX 30000
#define GW_MQTT_MISC_MS 1000          /* loop_misc: keepalive pings, retries */

static void mq_note(const struct gw_mqtt *q, const char *fmt, const char *a, const char *b)
{
	if (q->cfg.quiet)
		return;
	fprintf(stderr, "%s: broker %s: ", q->cfg.prog, q->cfg.url);
	fprintf(stderr, fmt, a, b);
	fputc('\n', stderr);
}

/* Down: try again after the backoff, which doubles up to its cap. */
static void mq_down(struct gw_mqtt *q, int64_t now, const char *why)
{
	char after[32];

	if (q->state == GW_MQTT_UP || q->cfg.verbose)
		snprintf(after, sizeof after, "%.1f s", q->backoff_ms / 1000.0);
	if (q->state == GW_MQTT_UP)
		mq_note(q, "connection lost (%s), reconnecting in %s", why, after);
	else if (q->cfg.verbose)
		mq_note(q, "cannot connect (%s), next try in %s", why, after);
	q->state = GW_MQTT_DOWN;
	q->inflight = 0;
	q->next_try_ms = now + q->backoff_ms;
	q->backoff_ms = q->backoff_ms * 2 > GW_MQTT_BACKOFF_MAX ? GW_MQTT_BACKOFF_MAX : q->backoff_ms * 2;
}

static const char *mq_errtext(int rc)
{
	return rc == MOSQ_ERR_ERRNO ? strerror(errno) : mosquitto_strerror(rc);
}

static void on_connect(struct mosquitto *m, void *obj, int rc)
{
	struct gw_mqtt *q = obj;

	(void)m;
	if (rc != 0) {
		q->refused = rc;
		snprintf(q->refused_text, sizeof q->refused_text, "%s", mosquitto_connack_string(rc));
		return;         /* the broker closes the connection: mq_down follows */
	}
	q->refused = 0;
	q->state = GW_MQTT_UP;
	q->backoff_ms = GW_MQTT_BACKOFF_MIN;
	if (!q->cfg.quiet && (q->ever_up || q->cfg.verbose))
		mq_note(q, "connected%s%s", q->ever_up ? " again" : "", "");
	q->ever_up = true;
	if (q->ev.connected)
		q->ev.connected(q->ev.user);
}

static void on_disconnect(struct mosquitto *m, void *obj, int rc)
{
	(void)m;
	(void)obj;
	(void)rc;       /* the loop call that ended the connection reports it */
}

static void on_publish(struct mosquitto *m, void *obj, int mid)
{
	struct gw_mqtt *q = obj;

	(void)m;
	(void)mid;
	if (q->inflight)
		q->inflight--;
}

static void on_message(struct mosquitto *m, void *obj, const struct mosquitto_message *msg)
{
	struct gw_mqtt *q = obj;

	(void)m;
	if (q->ev.message && msg && msg->topic)
		q->ev.message(q->ev.user, msg->topic, msg->payload, msg->payloadlen, msg->retain);
}

int gw_mqtt_init(struct gw_mqtt *q, const struct gw_mqtt_config *c, const struct gw_mqtt_events *ev,
                 char *err, size_t errcap)
{
	int rc;

	memset(q, 0, sizeof *q);
	q->cfg = *c;
	q->ev = *ev;
	q->backoff_ms = GW_MQTT_BACKOFF_MIN;
	mosquitto_lib_init();
	q->m = mosquitto_new(c->client_id, true, q);
	if (!q->m) {
		snprintf(err, errcap, "cannot create the MQTT client: %s", strerror(errno));
		return -1;
	}
	/* a result or a change goes out at once, not after the broker's delayed ACK */
	mosquitto_int_option(q->m, MOSQ_OPT_TCP_NODELAY, 1);
	mosquitto_connect_callback_set(q->m, on_connect);
	mosquitto_disconnect_callback_set(q->m, on_disconnect);
	mosquitto_publish_callback_set(q->m, on_publish);
	mosquitto_message_callback_set(q->m, on_message);
	if (c->username && (rc = mosquitto_username_pw_set(q->m, c->username, c->password)) != 0) {
		snprintf(err, errcap, "--username: %s", mosquitto_strerror(rc));
		return -1;
	}
	if (c->tls) {
		if (c->cafile) {
			rc = mosquitto_tls_set(q->m, c->cafile, NULL, c->cert, c->key, NULL);
		} else {
			rc = mosquitto_int_option(q->m, MOSQ_OPT_TLS_USE_OS_CERTS, 1);
			if (rc == 0 && c->cert)
				rc = mosquitto_tls_set(q->m, NULL, "/etc/ssl/certs", c->cert, c->key, NULL);
		}
		if (rc != 0) {
			snprintf(err, errcap, "TLS (--cafile, --cert, --key): %s", mq_errtext(rc));
			return -1;
		}
	}
	if (c->will_topic && (rc = mosquitto_will_set(q->m, c->will_topic, (int)c->will_len, c->will_payload,
	                                               c->qos, c->will_retain)) != 0) {
		snprintf(err, errcap, "last will on %s: %s", c->will_topic, mosquitto_strerror(rc));
		return -1;
	}
	return 0;
}

void gw_mqtt_close(struct gw_mqtt *q)
{
	if (!q->m)
		return;
	if (q->state != GW_MQTT_DOWN) {
		mosquitto_disconnect(q->m);
		mosquitto_loop_write(q->m, 1);
	}
	mosquitto_destroy(q->m);
	q->m = NULL;
	mosquitto_lib_cleanup();
}

int gw_mqtt_fd(const struct gw_mqtt *q)
{
	return q->m && q->state != GW_MQTT_DOWN ? mosquitto_socket(q->m) : -1;
}

short gw_mqtt_poll_events(const struct gw_mqtt *q)
{
	return (short)(POLLIN | (q->m && mosquitto_want_write(q->m) ? POLLOUT : 0));
}

int gw_mqtt_wait_ms(const struct gw_mqtt *q, int64_t now)
{
	if (q->state == GW_MQTT_DOWN) {
		int64_t d = q->next_try_ms - now;
		return d <= 0 ? 0 : d > GW_MQTT_MISC_MS ? GW_MQTT_MISC_MS : (int)d;
	}
	return GW_MQTT_MISC_MS;
}

static void mq_try(struct gw_mqtt *q, int64_t now)
{
	int rc;

	if (q->ev.connecting)
		q->ev.connecting(q->ev.user);
	q->refused = 0;
	if (!q->started) {
		q->started = true;
		rc = mosquitto_connect_async(q->m, q->cfg.host, q->cfg.port, q->cfg.keepalive);
	} else {
		rc = mosquitto_reconnect_async(q->m);
	}
	if (rc != 0) {
		q->state = GW_MQTT_CONNECTING;  /* so that mq_down reports it as a failed try */
		mq_down(q, now, mq_errtext(rc));
		return;
	}
	q->state = GW_MQTT_CONNECTING;
}

static void mq_drop(struct gw_mqtt *q, int64_t now);

void gw_mqtt_service(struct gw_mqtt *q, short revents, int64_t now)
{
	int rc = 0;

	if (q->state == GW_MQTT_DOWN) {
		if (now >= q->next_try_ms)
			mq_try(q, now);
		return;
	}
	if (revents & (POLLIN | POLLHUP | POLLERR))
		rc = mosquitto_loop_read(q->m, 1);
	if (rc == 0 && q->m && mosquitto_socket(q->m) >= 0 && (revents & POLLOUT))
		rc = mosquitto_loop_write(q->m, 1);
	if (rc == 0 && q->drop) {
		mq_drop(q, now);
		return;
	}
	if (rc == 0)
		rc = mosquitto_loop_misc(q->m);
	if (rc == 0 && mosquitto_socket(q->m) < 0)
		rc = MOSQ_ERR_NO_CONN;
	if (rc != 0) {
		const char *why = q->refused ? q->refused_text : mq_errtext(rc);
		char text[200];

		snprintf(text, sizeof text, "%s", why);
		if (q->refused && q->ever_up)
			mq_note(q, "refused the connection: %s%s", text, "");
		mq_down(q, now, text);
	}
}

int gw_mqtt_publish(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, bool retain)
{
	return gw_mqtt_publish_qos(q, topic, payload, len, -1, retain);
}

int gw_mqtt_publish_qos(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, int qos, bool retain)
{
	int rc;

	if (q->state != GW_MQTT_UP)
		return -1;
	if (qos < 0)
		qos = q->cfg.qos;
	rc = mosquitto_publish(q->m, NULL, topic, (int)len, payload, qos, retain);
	if (rc != 0)
		return -1;
	if (qos > 0)
		q->inflight++;
	return 0;
}

int gw_mqtt_will(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, int qos, bool retain)
{
	if (!topic)
		return mosquitto_will_clear(q->m) == 0 ? 0 : -1;
	return mosquitto_will_set(q->m, topic, (int)len, payload, qos < 0 ? q->cfg.qos : qos, retain) == 0 ? 0 : -1;
}

void gw_mqtt_reconnect(struct gw_mqtt *q, int64_t now)
{
	(void)now;
	if (q->state != GW_MQTT_DOWN)
		q->drop = true;
}

/* The reconnect asked for: what is queued, a clean DISCONNECT, a new try at once. */
static void mq_drop(struct gw_mqtt *q, int64_t now)
{
	q->drop = false;
	mosquitto_loop_write(q->m, 1);          /* what is queued (an NDEATH) goes first */
	mosquitto_disconnect(q->m);
	mosquitto_loop_write(q->m, 1);
	q->state = GW_MQTT_DOWN;
	q->inflight = 0;
	q->backoff_ms = GW_MQTT_BACKOFF_MIN;
	q->next_try_ms = now;
}

int gw_mqtt_subscribe(struct gw_mqtt *q, const char *pattern)
{
	return q->state == GW_MQTT_UP && mosquitto_subscribe(q->m, NULL, pattern, q->cfg.qos) == 0 ? 0 : -1;
}

bool gw_mqtt_up(const struct gw_mqtt *q)
{
	return q->state == GW_MQTT_UP;
}

bool gw_mqtt_idle(const struct gw_mqtt *q)
{
	return q->state != GW_MQTT_UP || (q->inflight == 0 && !mosquitto_want_write(q->m));
}
