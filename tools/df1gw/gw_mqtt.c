/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_mqtt - the broker side of df1gw on libmosquitto (see gw_mqtt.h).
 */
#include "df1gw/gw_mqtt.h"

#include <errno.h>
#include <inttypes.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <mosquitto.h>
#ifdef GW_HAVE_OPENSSL
#include <openssl/ssl.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>
#endif

#define GW_MQTT_BACKOFF_MIN 500
#define GW_MQTT_BACKOFF_MAX 30000
#define GW_MQTT_MISC_MS 1000          /* loop_misc: keepalive pings, retries */
#define GW_MQTT_CONNECT_MS 10000      /* a try without CONNACK by then has failed */
#define GW_MQTT_READ_MAX 10000        /* packets read in one turn at most */

static void mq_note(const struct gw_mqtt *q, const char *fmt, const char *a, const char *b)
{
	if (q->cfg.quiet)
		return;
	fprintf(stderr, "%s: broker %s: ", q->cfg.prog, q->cfg.url);
	fprintf(stderr, fmt, a, b);
	fputc('\n', stderr);
}

/* Remember why as said in this outage: true when it is new (a broker that
 * fails in turns for two reasons says each once, not at every try). */
static bool mq_said(struct gw_mqtt *q, const char *why)
{
	size_t have = strlen(q->said), len = strlen(why);
	const char *p = q->said;

	while ((p = strstr(p, why)) != NULL) {
		if ((p == q->said || p[-1] == '\n') && p[len] == '\n')
			return false;
		p++;
	}
	if (have + len + 2 <= sizeof q->said)
		snprintf(q->said + have, sizeof q->said - have, "%s\n", why);
	return true;
}

/* Down: try again after the backoff, which doubles up to its cap. Said at
 * the default verbosity when a connection is lost and when the reason of
 * failing tries is new (once per outage and reason); -v says every try. */
static void mq_down(struct gw_mqtt *q, int64_t now, const char *why)
{
	char after[32];

	snprintf(after, sizeof after, "%.1f s", q->backoff_ms / 1000.0);
	if (q->state == GW_MQTT_UP) {
		mq_note(q, "connection lost (%s), reconnecting in %s", why, after);
		q->said[0] = '\0';
		mq_said(q, why);
		q->down_since_ms = now;
		q->tries = 0;
	} else {
		if (!q->down_since_ms)
			q->down_since_ms = now;
		q->tries++;
		if (q->refused && !q->ever_up)
			;               /* the first connection refused: df1gw.c says it and exits */
		else if (q->cfg.verbose)
			mq_note(q, "cannot connect (%s), next try in %s", why, after);
		else if (mq_said(q, why))
			mq_note(q, "cannot connect: %s; trying again (backoff up to 30 s, -v shows each try)%s", why, "");
	}
	q->renew = true;                /* a fresh handle for the next try (mq_renew) */
	if (q->state == GW_MQTT_UP && q->ev.lost)
		q->ev.lost(q->ev.user);
	q->state = GW_MQTT_DOWN;
	q->inflight = 0;
	q->next_try_ms = now + q->backoff_ms;
	q->backoff_ms = q->backoff_ms * 2 > GW_MQTT_BACKOFF_MAX ? GW_MQTT_BACKOFF_MAX : q->backoff_ms * 2;
}

static const char *mq_errtext(int rc)
{
	return rc == MOSQ_ERR_ERRNO ? strerror(errno) : mosquitto_strerror(rc);
}

/* The monotonic clock of gw_now_ms() (df1gw.c's loop passes its own now;
 * the callbacks have none). */
static int64_t mq_clock_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* "certificate verify failed" says little: the verify result says which
 * check (unable to get local issuer certificate, hostname mismatch,
 * certificate has expired). The handshake's SSL object is still there while
 * libmosquitto logs its failure. */
static void mq_verify_detail(struct gw_mqtt *q)
{
#ifdef GW_HAVE_OPENSSL
	SSL *ssl = q->m ? mosquitto_ssl_get(q->m) : NULL;
	size_t l = strlen(q->tls_why);
	long v;

	if (!ssl || !strstr(q->tls_why, "certificate verify failed") ||
	    (v = SSL_get_verify_result(ssl)) == X509_V_OK)
		return;
	if (v == X509_V_ERR_UNSPECIFIED) {
		/* libmosquitto's own host check refused it without saying why */
		STACK_OF(X509) *chain = SSL_get_peer_cert_chain(ssl);
		X509 *c = chain && sk_X509_num(chain) > 0 ? sk_X509_value(chain, 0) : NULL;

		if (c && X509_check_host(c, q->cfg.host, 0, 0, NULL) != 1 && X509_check_ip_asc(c, q->cfg.host, 0) != 1) {
			snprintf(q->tls_why + l, sizeof q->tls_why - l, " (hostname mismatch: the certificate does not name %s)",
			         q->cfg.host);
			return;
		}
	}
	snprintf(q->tls_why + l, sizeof q->tls_why - l, " (%s)", X509_verify_cert_error_string(v));
#else
	(void)q;
#endif
}

/* libmosquitto's log: OpenSSL's reason for a failed handshake is only there
 * ("OpenSSL Error[0]: error:0A000086:SSL routines::certificate verify
 * failed"); the first of a try is kept. -vv prints every line. */
static void on_log(struct mosquitto *m, void *obj, int level, const char *text)
{
	struct gw_mqtt *q = obj;
	const char *r;

	(void)m;
	if (!text)
		return;
	if (q->cfg.verbose >= 2 && !q->cfg.quiet)
		fprintf(stderr, "%s: broker %s: libmosquitto: %s\n", q->cfg.prog, q->cfg.url, text);
	if (!(level & (MOSQ_LOG_ERR | MOSQ_LOG_WARNING)) || q->tls_why[0] ||
	    strncmp(text, "OpenSSL Error", 13) != 0)
		return;
	r = strrchr(text, ':');        /* the reason is the last field of OpenSSL's error string */
	snprintf(q->tls_why, sizeof q->tls_why, "TLS%s: %s",
	         q->state == GW_MQTT_CONNECTING ? " handshake failed" : "", r && r[1] ? r + 1 : text);
	mq_verify_detail(q);
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
	if (q->said[0]) {
		char after[64];
		int64_t s = q->down_since_ms ? (mq_clock_ms() - q->down_since_ms + 500) / 1000 : 0;

		/* the recovery of an outage that was reported */
		snprintf(after, sizeof after, " after %" PRId64 " s", s);
		mq_note(q, "connected%s%s", q->ever_up ? " again" : "", after);
	} else if (q->cfg.verbose) {
		mq_note(q, "connected%s%s", q->ever_up ? " again" : "", "");
	}
	q->said[0] = '\0';
	q->down_since_ms = 0;
	q->tries = 0;
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
	if (q->inflight)
		q->inflight--;
	if (q->ev.acked)
		q->ev.acked(q->ev.user, mid);
}

static void on_message(struct mosquitto *m, void *obj, const struct mosquitto_message *msg)
{
	struct gw_mqtt *q = obj;

	(void)m;
	if (q->ev.message && msg && msg->topic)
		q->ev.message(q->ev.user, msg->topic, msg->payload, msg->payloadlen, msg->retain);
}

/* A libmosquitto handle made from q->cfg: callbacks, TLS files, credentials,
 * the will. At the start, and before each TLS try after a failure (mq_try). */
static int mq_handle_make(struct gw_mqtt *q, char *err, size_t errcap)
{
	const struct gw_mqtt_config *c = &q->cfg;
	int rc;

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
	mosquitto_log_callback_set(q->m, on_log);
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

int gw_mqtt_init(struct gw_mqtt *q, const struct gw_mqtt_config *c, const struct gw_mqtt_events *ev,
                 char *err, size_t errcap)
{
	memset(q, 0, sizeof *q);
	q->cfg = *c;
	q->ev = *ev;
	q->backoff_ms = GW_MQTT_BACKOFF_MIN;
	mosquitto_lib_init();
	return mq_handle_make(q, err, errcap);
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

/* A socket error met while TLS connects: libmosquitto's handshake takes a
 * refused or reset connection for "try again" (SSL_ERROR_SYSCALL) and would
 * write its ClientHello to the dead socket forever; it is kept as the reason
 * when mq_connecting_check ends the try. */
static void mq_sock_errno(struct gw_mqtt *q, int e)
{
	if (q->sock_errno || !q->cfg.tls)
		return;
	if (e == ECONNREFUSED || e == ECONNRESET || e == EPIPE || e == ETIMEDOUT || e == EHOSTUNREACH ||
	    e == ENETUNREACH || e == ECONNABORTED)
		q->sock_errno = e;
}

/* A fresh handle after a failure: the CA, certificate and key files are
 * read again at each try, so a renewed certificate is taken without a
 * restart; and nothing of the old session is sent again (libmosquitto
 * resends unacknowledged QoS 1 messages on a reconnection, which the
 * broker's clean session delivers a second time: a write's result twice).
 * mosquitto_reconnect_async on the old handle connects again too once
 * mq_connecting_check ends a dead TLS try (tried with the broker of
 * tests/integration/it_df1gw_tls.sh): the old handle was not the fault. */
static int mq_renew(struct gw_mqtt *q, char *err, size_t errcap)
{
	mosquitto_destroy(q->m);
	q->m = NULL;
	q->started = false;
	q->renew = false;
	return mq_handle_make(q, err, errcap);
}

/* Why the try or the connection ended, the most telling first: the broker's
 * refusal, OpenSSL's reason, the socket's error, libmosquitto's code. */
static void mq_why(const struct gw_mqtt *q, int rc, char *out, size_t cap)
{
	if (q->refused)
		snprintf(out, cap, "refused the connection: %s", q->refused_text);
	else if (q->tls_why[0])
		snprintf(out, cap, "%s", q->tls_why);
	else if (q->sock_errno)
		snprintf(out, cap, "%s", strerror(q->sock_errno));
	else if (rc == MOSQ_ERR_TLS)
		snprintf(out, cap, "TLS handshake failed");
	else
		snprintf(out, cap, "%s", mq_errtext(rc));
}

static void mq_try(struct gw_mqtt *q, int64_t now)
{
	char err[200];
	int rc;

	q->refused = 0;
	q->sock_errno = 0;
	q->tls_why[0] = '\0';
	q->try_ms = now;
	if (q->renew && mq_renew(q, err, sizeof err) < 0) {
		q->state = GW_MQTT_CONNECTING;  /* so that mq_down reports it as a failed try */
		mq_down(q, now, err);
		return;
	}
	/* on the handle that connects (a renewed one too): a session format's
	 * will for this try, with its new bdSeq */
	if (q->ev.connecting)
		q->ev.connecting(q->ev.user);
	errno = 0;
	q->state = GW_MQTT_CONNECTING;          /* mq_down reports a failure as a failed try */
	if (!q->started) {
		q->started = true;
		rc = mosquitto_connect_async(q->m, q->cfg.host, q->cfg.port, q->cfg.keepalive);
	} else {
		rc = mosquitto_reconnect_async(q->m);
	}
	mq_sock_errno(q, errno);
	if (rc != 0) {
		char why[256];

		mq_why(q, rc, why, sizeof why);
		mq_down(q, now, why);
	}
}

/* CONNECTING: the try has failed though libmosquitto says nothing (a TLS
 * handshake on a refused or closed socket, no CONNACK in time). */
static int mq_connecting_check(struct gw_mqtt *q, short revents, int64_t now)
{
	if (q->state != GW_MQTT_CONNECTING)
		return 0;
	if (revents & (POLLHUP | POLLERR)) {
		int e = 0;
		socklen_t l = sizeof e;

		if (mosquitto_socket(q->m) >= 0 && getsockopt(mosquitto_socket(q->m), SOL_SOCKET, SO_ERROR, &e, &l) == 0)
			mq_sock_errno(q, e);
		if (!q->sock_errno && !q->tls_why[0])
			snprintf(q->tls_why, sizeof q->tls_why, "the connection was refused or closed while connecting");
		return MOSQ_ERR_CONN_LOST;
	}
	if (now - q->try_ms > GW_MQTT_CONNECT_MS) {
		snprintf(q->tls_why, sizeof q->tls_why, "no answer (CONNACK) within %d s", GW_MQTT_CONNECT_MS / 1000);
		return MOSQ_ERR_CONN_LOST;
	}
	return 0;
}

static bool mq_tls_pending(const struct gw_mqtt *q)
{
#ifdef GW_HAVE_OPENSSL
	SSL *ssl = q->cfg.tls ? mosquitto_ssl_get(q->m) : NULL;

	return ssl && SSL_pending(ssl) > 0;
#else
	(void)q;
	return false;
#endif
}

/* All the socket has, not one packet (libmosquitto's loop_read takes about
 * one a call): a burst of /set messages is taken in one turn. */
static int mq_read_all(struct gw_mqtt *q)
{
	int rc = mosquitto_loop_read(q->m, 1);

	for (int k = 0; rc == 0 && k < GW_MQTT_READ_MAX && q->state == GW_MQTT_UP; k++) {
		struct pollfd p = { mosquitto_socket(q->m), POLLIN, 0 };

		if (p.fd < 0)
			break;
		/* TLS: what OpenSSL has decrypted already, poll() cannot see */
		if (!mq_tls_pending(q) && (poll(&p, 1, 0) <= 0 || !(p.revents & POLLIN)))
			break;
		rc = mosquitto_loop_read(q->m, 1);
	}
	return rc;
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
	errno = 0;
	if (revents & (POLLIN | POLLHUP | POLLERR))
		rc = mq_read_all(q);
	if (rc == 0 && q->m && mosquitto_socket(q->m) >= 0 && (revents & POLLOUT))
		rc = mosquitto_loop_write(q->m, 1);
	if (q->state == GW_MQTT_CONNECTING)
		mq_sock_errno(q, errno);
	if (rc == 0 && q->drop) {
		mq_drop(q, now);
		return;
	}
	if (rc == 0)
		rc = mosquitto_loop_misc(q->m);
	if (rc == 0 && mosquitto_socket(q->m) < 0)
		rc = MOSQ_ERR_NO_CONN;
	if (rc == 0)
		rc = mq_connecting_check(q, revents, now);
	if (rc != 0) {
		char why[256];

		mq_why(q, rc, why, sizeof why);
		mq_down(q, now, why);
	}
}

void gw_mqtt_turn(struct gw_mqtt *q, int64_t now)
{
	struct pollfd p = { gw_mqtt_fd(q), gw_mqtt_poll_events(q), 0 };

	if (!q->m)
		return;
	if (p.fd >= 0 && poll(&p, 1, 0) < 0)
		return;
	gw_mqtt_service(q, p.fd >= 0 ? p.revents : 0, now);
}

int gw_mqtt_publish(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, bool retain)
{
	return gw_mqtt_publish_qos(q, topic, payload, len, -1, retain);
}

int gw_mqtt_publish_qos(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, int qos, bool retain)
{
	int mid;

	return gw_mqtt_publish_mid(q, topic, payload, len, qos, retain, &mid);
}

int gw_mqtt_publish_mid(struct gw_mqtt *q, const char *topic, const void *payload, size_t len, int qos, bool retain,
                        int *mid)
{
	int rc;

	if (q->state != GW_MQTT_UP)
		return -1;
	if (qos < 0)
		qos = q->cfg.qos;
	rc = mosquitto_publish(q->m, mid, topic, (int)len, payload, qos, retain);
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
	if (q->ev.lost)
		q->ev.lost(q->ev.user);
	q->state = GW_MQTT_DOWN;
	q->inflight = 0;
	q->renew = true;        /* nothing of this session is sent again by libmosquitto (mq_renew) */
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
