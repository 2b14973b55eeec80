/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip_link.c - the link over EtherNet/IP, for an "eip://HOST[:PORT][/2]" target
 * (libdf1(7), df1-eip(7)): each PCCC command goes in a CIP Execute PCCC
 * request (class 67h instance 1), carried by SendRRData, or with
 * DF1_OPT_EIP_CONNECTED by SendUnitData over a Forward Open connection. The
 * serial rules of DF1 (ACK, NAK, ENQ, DLE stuffing, BCC/CRC) do not apply.
 *
 * A reply is matched on the sender context (unconnected) or the connection id
 * and sequence count (connected), then on the TNS; anything else is stale,
 * counted (2548) and dropped. A session found broken before a command is sent
 * (the peer closed it while idle, or answered 0064h invalid session) is
 * opened again and registered again, and the command sent; a connection lost
 * after the whole command went out is retried only for a command that only
 * reads (df1_pccc_is_write(), the rule the server's read-only mode uses): any
 * other may have executed, and is reported, never sent twice.
 *
 * The eip:// row of the scheme table (lib/scheme.c) names it as that
 * scheme's own link (eip_link_ops) over the TCP backend, which df1_open() sets
 * in h->port. Self-contained over that port: no call into lib/link, so tests
 * that replace the DF1 link (tests/unit/client/test_client.c) still link the handle with it.
 */
#include "df1_int.h"

#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/random.h>
#include <unistd.h>

#include "eip/eip_codec.h"
#include "eip/eip_session.h"
#include "eip/eip_link.h"

/* The requester ID of our Execute PCCC requests and the originator of a
 * Forward Open: the project has no ODVA vendor ID and claims none (0, as the
 * server's identity, df1-eip(7)), with a random serial per handle. */
#define EIP_OUR_VENDOR 0x0000u
#define EIP_MSG_CAP 1024          /* one encapsulated message in or out */
#define EIP_CONNECT_MIN_MS 1000
/* Unconnected Send: 2^5 = 32 ms a tick */
#define EIP_TICK 5
#define EIP_TICK_MS 32
/* Forward Open: point to point, low priority, variable size, 504 bytes (16-bit
 * network parameters); class 3 server transport, application triggered */
#define EIP_NET_PARAMS 0x43F8u
#define EIP_TRANSPORT 0xA3
#define EIP_RPI_US 2000000u

struct link_eip {
	char target[160];            /* "eip://host:port" without the route, for reopening */
	bool route;                  /* "/2": Unconnected Send, route path port 2, link = DST */
	bool connected;              /* Forward Open made at open */
	bool conn_open;
	bool broken;                 /* the stream lost its place: reopen before the next send */
	uint32_t session;
	uint64_t context;            /* the sender context of the next request */
	uint32_t serial;
	uint32_t ot_id, to_id;       /* connection ids: we send on ot_id, the target on to_id */
	uint16_t conn_serial, seq;
	uint8_t out[EIP_MSG_CAP];
	uint8_t in[EIP_MSG_CAP];
};

/* ------------------------------------------------------------------------
 * Status texts (df1-eip(7))
 * ------------------------------------------------------------------------ */

const char *link_eip_status_text(uint32_t st)
{
	switch (st) {
	case EIP_ST_SUCCESS: return "success";
	case EIP_ST_INVALID_COMMAND: return "invalid or unsupported command";
	case EIP_ST_NO_MEMORY: return "insufficient memory";
	case EIP_ST_INCORRECT_DATA: return "incorrect data";
	case EIP_ST_INVALID_SESSION: return "invalid session handle";
	case EIP_ST_INVALID_LENGTH: return "invalid length";
	case EIP_ST_UNSUPPORTED_VERSION: return "unsupported protocol version";
	default: return "unknown status";
	}
}

const char *link_cip_status_text(uint8_t st)
{
	switch (st) {
	case CIP_ST_SUCCESS: return "success";
	case CIP_ST_CONNECTION_FAILURE: return "connection failure";
	case CIP_ST_RESOURCE_UNAVAILABLE: return "resource unavailable";
	case CIP_ST_INVALID_PARAMETER: return "invalid parameter value";
	case CIP_ST_PATH_SEGMENT: return "path segment error";
	case CIP_ST_PATH_DESTINATION: return "path destination unknown";
	case CIP_ST_SERVICE_NOT_SUPPORTED: return "service not supported";
	case CIP_ST_PRIVILEGE_VIOLATION: return "privilege violation";
	case CIP_ST_REPLY_TOO_LARGE: return "reply data too large";
	case CIP_ST_NOT_ENOUGH_DATA: return "not enough data";
	case CIP_ST_ATTRIBUTE_NOT_SUPPORTED: return "attribute not supported";
	case CIP_ST_TOO_MUCH_DATA: return "too much data";
	case CIP_ST_OBJECT_DOES_NOT_EXIST: return "object does not exist";
	case CIP_ST_PATH_SIZE_INVALID: return "path size invalid";
	default: return "unknown status";
	}
}

/* ------------------------------------------------------------------------
 * Bytes in and out
 * ------------------------------------------------------------------------ */

/* The reply wait of one request: the handle's timeout or command timeout,
 * the longer. */
static int64_t eip_wait_ms(const struct df1 *h)
{
	int64_t t = h->cfg.timeout_ms;

	return h->cfg.cmd_timeout_ms > t ? h->cfg.cmd_timeout_ms : t;
}

/* The deadline of a wait that starts now: the one place that adds to the clock. */
static int64_t eip_deadline(const struct df1 *h)
{
	return df1_now_ms() + eip_wait_ms(h);
}

static int eip_write(struct df1 *h, const uint8_t *buf, size_t n, int64_t deadline_ms)
{
	size_t off = 0;

	while (off < n) {
		ssize_t w = h->port->write(h, buf + off, n - off, deadline_ms);

		if (w < 0)
			return (int)w;
		if (w == 0)
			return df1_fail(h, DF1_E_SYS, -1, "write to %s made no progress", h->port_name);
		if (h->trace_fn)
			h->trace_fn(h->trace_user, DF1_DIR_TX, buf + off, (size_t)w, df1_now_us());
		off += (size_t)w;
	}
	df1_count_n(h, DF1_ID_CRD_CHAR_SENT, n);
	return 0;
}

/* Exactly n bytes: 1, 0 (deadline, nothing read), DF1_E_*. Cut off after
 * the first byte: DF1_E_TIMEOUT, and the stream has lost its place. */
static int eip_read_exact(struct df1 *h, struct link_eip *e, uint8_t *buf, size_t n,
                          int64_t deadline_ms)
{
	size_t got = 0;

	while (got < n) {
		ssize_t r = h->port->read(h, buf + got, n - got, deadline_ms);

		if (r < 0) {
			e->broken = true;
			return (int)r;
		}
		if (r == 0) {
			if (got == 0)
				return 0;
			e->broken = true;
			return df1_fail(h, DF1_E_TIMEOUT, -1, "%s: a message was cut off after %zu bytes",
			                h->port_name, got);
		}
		if (h->trace_fn)
			h->trace_fn(h->trace_user, DF1_DIR_RX, buf + got, (size_t)r, df1_now_us());
		df1_count_n(h, DF1_ID_CRD_CHAR_RECV, (uint64_t)r);
		got += (size_t)r;
	}
	return 1;
}

/* One whole message into e->in: 1 (hdr filled, its data at e->in + 24),
 * 0 (deadline, nothing arrived), DF1_E_*. */
static int eip_recv(struct df1 *h, struct link_eip *e, int64_t deadline_ms, struct eip_hdr *hdr)
{
	int r = eip_read_exact(h, e, e->in, EIP_HDR_LEN, deadline_ms);

	if (r <= 0)
		return r;
	(void)eip_hdr_parse(hdr, e->in, EIP_HDR_LEN);
	if (hdr->length > sizeof e->in - EIP_HDR_LEN) {
		e->broken = true;
		return df1_fail(h, DF1_E_EIP, -1,
		                "%s sent a message of %u bytes (command 0x%04X), more than %zu",
		                h->port_name, (unsigned)hdr->length, (unsigned)hdr->command,
		                sizeof e->in - EIP_HDR_LEN);
	}
	if (hdr->length == 0)
		return 1;
	r = eip_read_exact(h, e, e->in + EIP_HDR_LEN, hdr->length, deadline_ms);
	if (r == 0) {
		e->broken = true;
		return df1_fail(h, DF1_E_TIMEOUT, -1, "%s: a message was cut off after its header",
		                h->port_name);
	}
	return r;
}

static void eip_next_context(struct link_eip *e, uint8_t ctx[8])
{
	uint64_t c = ++e->context;

	for (int i = 0; i < 8; i++)
		ctx[i] = (uint8_t)(c >> (8 * i));
}

/* A message of header and data into e->out, sent. */
static int eip_send_msg(struct df1 *h, struct link_eip *e, uint16_t command, const uint8_t ctx[8],
                        const uint8_t *data, size_t n, int64_t deadline_ms)
{
	struct eip_hdr hd;

	memset(&hd, 0, sizeof hd);
	hd.command = command;
	hd.length = (uint16_t)n;
	hd.session = e->session;
	memcpy(hd.context, ctx, 8);
	if (n > sizeof e->out - EIP_HDR_LEN || eip_hdr_build(e->out, sizeof e->out, &hd) < 0)
		return df1_fail(h, DF1_E_INVAL, -1, "an EtherNet/IP message of %zu bytes", n);
	if (n)
		memcpy(e->out + EIP_HDR_LEN, data, n);
	return eip_write(h, e->out, EIP_HDR_LEN + n, deadline_ms);
}

/* The reply to a request of ours (command, ctx) until the deadline: 1, or
 * DF1_E_TIMEOUT, DF1_E_EIP (a status), DF1_E_*. Others are stale. */
static int eip_await(struct df1 *h, struct link_eip *e, uint16_t command, const uint8_t ctx[8],
                     const char *what, struct eip_hdr *hd)
{
	int64_t deadline = eip_deadline(h);

	for (;;) {
		int r = eip_recv(h, e, deadline, hd);

		if (r < 0)
			return r;
		if (r == 0)
			return df1_fail(h, DF1_E_TIMEOUT, -1, "%s: no %s reply within %lld ms",
			                h->port_name, what, (long long)eip_wait_ms(h));
		if (hd->command != command || memcmp(hd->context, ctx, 8) != 0) {
			df1_count(h, DF1_ID_CNT_STALE_MSGS_RCVD);
			continue;
		}
		if (hd->status != EIP_ST_SUCCESS)
			return df1_fail(h, DF1_E_EIP, -1, "%s: %s refused: encapsulation status 0x%04X (%s)",
			                h->port_name, what, (unsigned)hd->status,
			                link_eip_status_text(hd->status));
		return 1;
	}
}

/* ------------------------------------------------------------------------
 * Session and connection
 * ------------------------------------------------------------------------ */

static int eip_register(struct df1 *h, struct link_eip *e)
{
	uint8_t data[4], ctx[8];
	struct eip_hdr hd;
	int r;

	e->session = 0;
	(void)eip_register_build(data, sizeof data, EIP_PROTOCOL_VERSION, 0);
	eip_next_context(e, ctx);
	r = eip_send_msg(h, e, EIP_CMD_REGISTER_SESSION, ctx, data, sizeof data,
	                 eip_deadline(h));
	if (r < 0)
		return r;
	r = eip_await(h, e, EIP_CMD_REGISTER_SESSION, ctx, "RegisterSession", &hd);
	if (r < 0)
		return r;
	if (hd.session == 0)
		return df1_fail(h, DF1_E_EIP, -1, "%s: RegisterSession answered with session handle 0",
		                h->port_name);
	e->session = hd.session;
	return 0;
}

/* A CIP request sent in SendRRData and its reply until the deadline: the
 * response parsed into *cr. DF1_E_CIP for a general status other than 0. */
static int eip_rr_call(struct df1 *h, struct link_eip *e, const uint8_t *cip, size_t n,
                       const char *what, struct cip_resp *cr)
{
	struct eip_packet p = { .connected = false, .data = cip, .len = n };
	struct eip_packet rp;
	struct eip_cpf cpf;
	struct eip_hdr hd;
	uint16_t tmo;
	uint8_t ctx[8];
	int r, len;

	eip_next_context(e, ctx);
	len = eip_packet_build(e->out, sizeof e->out, e->session, ctx, 0, &p);
	if (len < 0)
		return df1_fail(h, DF1_E_INVAL, -1, "%s: request of %zu bytes does not fit", what, n);
	r = eip_write(h, e->out, (size_t)len, eip_deadline(h));
	if (r < 0)
		return r;
	r = eip_await(h, e, EIP_CMD_SEND_RR_DATA, ctx, what, &hd);
	if (r < 0)
		return r;
	if (eip_rr_parse(&tmo, &cpf, e->in + EIP_HDR_LEN, hd.length) < 0 ||
	    eip_packet_parse(&rp, &cpf) < 0 || rp.connected ||
	    cip_resp_parse(cr, rp.data, rp.len) < 0)
		return df1_fail(h, DF1_E_BAD_REPLY, -1, "%s: malformed %s reply", h->port_name, what);
	if (cr->status != CIP_ST_SUCCESS)
		return df1_fail(h, DF1_E_CIP, -1,
		                "%s: %s failed: CIP general status 0x%02X (%s), extended 0x%04X",
		                h->port_name, what, cr->status, link_cip_status_text(cr->status),
		                cr->ext0);
	return 0;
}

/* The Message Router, the far end of our connection (20 02 24 01). */
static int eip_router_path(uint8_t *out, size_t cap)
{
	struct cip_path p;

	cip_path_init(&p);
	p.class_id = CIP_CLASS_MESSAGE_ROUTER;
	p.instance = 1;
	return cip_path_build(out, cap, &p);
}

static int eip_forward_open(struct df1 *h, struct link_eip *e)
{
	uint8_t req[128], path[16];
	struct cip_fwd_open f, rf;
	struct cip_resp cr;
	uint32_t rnd = 0;
	int pl, n, r;

	pl = eip_router_path(path, sizeof path);
	if (getrandom(&rnd, sizeof rnd, GRND_NONBLOCK) != (ssize_t)sizeof rnd)
		rnd = (uint32_t)df1_now_us() ^ (uint32_t)getpid() << 16;
	memset(&f, 0, sizeof f);
	f.tick = EIP_TICK;
	f.timeout_ticks = (uint8_t)(eip_wait_ms(h) / EIP_TICK_MS > 255 ? 255
	                                                               : eip_wait_ms(h) / EIP_TICK_MS);
	f.ot_conn_id = 0;                      /* the target chooses */
	f.to_conn_id = rnd | 1u;
	f.conn_serial = (uint16_t)(rnd >> 16) ^ (uint16_t)e->context;
	f.vendor_id = EIP_OUR_VENDOR;
	f.orig_serial = e->serial;
	f.timeout_mult = 1;                    /* x8 of the RPI */
	f.ot_rpi = f.to_rpi = EIP_RPI_US;
	f.ot_params = f.to_params = EIP_NET_PARAMS;
	f.transport = EIP_TRANSPORT;
	f.path = path;
	f.path_len = pl > 0 ? (size_t)pl : 0;
	n = cip_fwd_open_build(req, sizeof req, &f);
	if (n < 0)
		return df1_fail(h, DF1_E_INVAL, -1, "Forward Open request does not fit");
	r = eip_rr_call(h, e, req, (size_t)n, "Forward Open", &cr);
	if (r < 0)
		return r;
	if (cr.service != (CIP_SVC_FORWARD_OPEN | CIP_SVC_REPLY) ||
	    cip_fwd_open_reply_parse(&rf, cr.data, cr.len) < 0 || rf.to_conn_id != f.to_conn_id ||
	    rf.conn_serial != f.conn_serial)
		return df1_fail(h, DF1_E_BAD_REPLY, -1, "%s: malformed Forward Open reply",
		                h->port_name);
	e->ot_id = rf.ot_conn_id;
	e->to_id = rf.to_conn_id;
	e->conn_serial = f.conn_serial;
	e->seq = 0;
	e->conn_open = true;
	return 0;
}

static void eip_forward_close(struct df1 *h, struct link_eip *e)
{
	uint8_t req[64], path[16];
	struct cip_fwd_close f;
	struct cip_resp cr;
	int pl, n;

	e->conn_open = false;
	pl = eip_router_path(path, sizeof path);
	memset(&f, 0, sizeof f);
	f.tick = EIP_TICK;
	f.timeout_ticks = (uint8_t)(eip_wait_ms(h) / EIP_TICK_MS > 255 ? 255
	                                                               : eip_wait_ms(h) / EIP_TICK_MS);
	f.conn_serial = e->conn_serial;
	f.vendor_id = EIP_OUR_VENDOR;
	f.orig_serial = e->serial;
	f.path = path;
	f.path_len = pl > 0 ? (size_t)pl : 0;
	n = cip_fwd_close_build(req, sizeof req, &f);
	if (n > 0)
		(void)eip_rr_call(h, e, req, (size_t)n, "Forward Close", &cr); /* closing anyway */
}

static int eip_start(struct df1 *h, struct link_eip *e)
{
	int r = eip_register(h, e);

	if (r >= 0 && e->connected)
		r = eip_forward_open(h, e);
	return r;
}

/* The TCP connection again, a session, a connection. */
static int eip_reopen(struct df1 *h, struct link_eip *e)
{
	int r;

	h->port->close(h);
	e->broken = false;
	e->conn_open = false;
	r = h->port->open(h, e->target);
	if (r < 0) {
		h->fd = -1;
		e->broken = true;
		return r;
	}
	r = eip_start(h, e);
	if (r < 0)
		e->broken = true;
	else
		df1_clear_error(h); /* what broke the old session is no error of this command */
	return r;
}

/* "eip://host[:port][/2]": the TCP part into e->target, the route flag. */
static int eip_parse_target(struct df1 *h, struct link_eip *e, const char *target)
{
	const char *rest = target + 4, *slash;
	size_t n;

	if (strncmp(rest, "//", 2) == 0)
		rest += 2;
	slash = *rest == '[' ? strchr(rest, ']') : rest;
	slash = slash ? strchr(slash, '/') : NULL;
	if (slash && slash[1] != '\0') {
		if (strcmp(slash + 1, "2") != 0 && strcmp(slash + 1, "2/") != 0)
			return df1_fail(h, DF1_E_INVAL, -1,
			                "invalid EtherNet/IP route \"%s\" in \"%s\": only /2 (the DF1 port "
			                "of a bridge, the station as link address)", slash, target);
		e->route = true;
	}
	n = slash ? (size_t)(slash - target) : strlen(target);
	if (n >= sizeof e->target)
		return df1_fail(h, DF1_E_INVAL, -1, "EtherNet/IP target too long: \"%s\"", target);
	memcpy(e->target, target, n);
	e->target[n] = '\0';
	return 0;
}

static int eip_link_open(struct df1 *h, const char *target)
{
	struct link_eip *e;
	int r;

	snprintf(h->port_name, sizeof h->port_name, "%s", target);
	if (h->cfg.listen_only)
		return df1_fail(h, DF1_E_NOTSUP, -1, "%s: an eip:// target cannot be listen only",
		                target);
	e = calloc(1, sizeof *e);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "out of memory");
	r = eip_parse_target(h, e, target);
	if (r >= 0 && e->route && h->cfg.eip_connected)
		r = df1_fail(h, DF1_E_NOTSUP, -1, "%s: a routed target (/2) is reached unconnected "
		             "only: leave out DF1_OPT_EIP_CONNECTED (--eip-connected)", target);
	if (r < 0) {
		free(e);
		return r;
	}
	e->connected = h->cfg.eip_connected;
	if (getrandom(&e->serial, sizeof e->serial, GRND_NONBLOCK) != (ssize_t)sizeof e->serial)
		e->serial = (uint32_t)df1_now_us() ^ (uint32_t)getpid();
	e->context = (uint64_t)e->serial << 24;
	r = h->port->open(h, e->target);
	if (r < 0) {
		free(e);
		return r;
	}
	h->own_link_data = e;
	r = eip_start(h, e);
	if (r < 0) {
		h->port->close(h);
		h->own_link_data = NULL;
		free(e);
		return r;
	}
	return 0;
}

static void eip_link_close(struct df1 *h)
{
	struct link_eip *e = h->own_link_data;
	uint8_t ctx[8];

	if (!e)
		return;
	if (!e->broken && h->fd >= 0) {
		if (e->conn_open)
			eip_forward_close(h, e);
		eip_next_context(e, ctx);
		(void)eip_send_msg(h, e, EIP_CMD_UNREGISTER_SESSION, ctx, NULL, 0,
		                   eip_deadline(h));
	}
	h->own_link_data = NULL;
	free(e);
}

/* ------------------------------------------------------------------------
 * Transactions
 * ------------------------------------------------------------------------ */

/* The CIP request of one command into buf: Execute PCCC, wrapped in an
 * Unconnected Send to port 2, link address station, for a routed target. */
static int eip_pccc_cip(struct df1 *h, struct link_eip *e, int station, const uint8_t *pccc,
                        size_t n, uint8_t *buf, size_t cap)
{
	uint8_t inner[EIP_MSG_CAP / 2], route[2];
	int64_t ticks = eip_wait_ms(h) / EIP_TICK_MS;
	int len;

	if (!e->route)
		return eip_pccc_request_build(buf, cap, EIP_OUR_VENDOR, e->serial, pccc, n);
	len = eip_pccc_request_build(inner, sizeof inner, EIP_OUR_VENDOR, e->serial, pccc, n);
	if (len < 0)
		return len;
	route[0] = EIP_ROUTE_PORT_DF1;
	route[1] = (uint8_t)station;
	return cip_unconnected_build(buf, cap, EIP_TICK, (uint8_t)(ticks < 1 ? 1 : ticks > 255 ? 255
	                                                                               : ticks),
	                             inner, (size_t)len, route, sizeof route);
}

/* What the wait for one reply ended with. */
enum eip_outcome {
	EIP_GOT_REPLY,               /* reply filled */
	EIP_SESSION_REFUSED,         /* status 0064h: the target did not take the command */
	EIP_FAILED,                  /* the handle's error (DF1_E_*) */
};

/* A reply message in e->in for our request (hdr): the PCCC reply into
 * *pccc / *plen. 1 it is ours, 0 stale, DF1_E_*. */
static int eip_take(struct df1 *h, struct link_eip *e, const struct eip_hdr *hd, int station,
                    const uint8_t *cmd, uint16_t seq, const uint8_t **pccc, size_t *plen)
{
	struct eip_packet p;
	struct eip_cpf cpf;
	struct cip_resp cr;
	struct eip_pccc pc;
	uint16_t tmo;

	if (eip_rr_parse(&tmo, &cpf, e->in + EIP_HDR_LEN, hd->length) < 0 ||
	    eip_packet_parse(&p, &cpf) < 0 || p.connected != e->connected)
		return df1_fail(h, DF1_E_BAD_REPLY, station, "%s: malformed %s", h->port_name,
		                e->connected ? "SendUnitData" : "SendRRData reply");
	if (e->connected && (p.conn_id != e->to_id || p.seq != seq))
		return 0;
	if (cip_resp_parse(&cr, p.data, p.len) < 0)
		return df1_fail(h, DF1_E_BAD_REPLY, station, "%s: malformed CIP reply", h->port_name);
	if (cr.status != CIP_ST_SUCCESS) {
		if (cr.ext_words)
			return df1_fail(h, DF1_E_CIP, station,
			                "%s: CIP general status 0x%02X (%s), extended status 0x%04X, "
			                "to Execute PCCC for station %d", h->port_name, cr.status,
			                link_cip_status_text(cr.status), cr.ext0, station);
		return df1_fail(h, DF1_E_CIP, station,
		                "%s: CIP general status 0x%02X (%s) to Execute PCCC for station %d",
		                h->port_name, cr.status, link_cip_status_text(cr.status), station);
	}
	if (cr.service != (CIP_SVC_EXECUTE_PCCC | CIP_SVC_REPLY) ||
	    eip_pccc_parse(&pc, cr.data, cr.len) < 0)
		return df1_fail(h, DF1_E_BAD_REPLY, station, "%s: malformed Execute PCCC reply "
		                "(service 0x%02X)", h->port_name, cr.service);
	if (pc.pccc[2] != cmd[4] || pc.pccc[3] != cmd[5])
		return 0;                        /* an older command's reply */
	*pccc = pc.pccc;
	*plen = pc.len;
	return 1;
}

/* Send one command and wait for its reply. *sent: the whole request went out. */
static enum eip_outcome eip_exchange(struct df1 *h, struct link_eip *e, const uint8_t *cmd,
                                     size_t n, uint8_t *reply, size_t cap, int *result,
                                     bool *sent)
{
	struct eip_packet p;
	uint8_t cip[EIP_MSG_CAP / 2], ctx[8];
	int station = cmd[0], len, r;
	int64_t deadline;

	*sent = false;
	len = eip_pccc_cip(h, e, station, cmd + 2, n - 2, cip, sizeof cip);
	if (len < 0) {
		*result = df1_fail(h, DF1_E_INVAL, station, "command of %zu bytes does not fit", n);
		return EIP_FAILED;
	}
	memset(&p, 0, sizeof p);
	p.connected = e->connected;
	p.conn_id = e->ot_id;
	p.seq = e->connected ? ++e->seq : 0;
	p.data = cip;
	p.len = (size_t)len;
	eip_next_context(e, ctx);
	len = eip_packet_build(e->out, sizeof e->out, e->session, ctx, 0, &p);
	if (len < 0) {
		*result = df1_fail(h, DF1_E_INVAL, station, "command of %zu bytes does not fit", n);
		return EIP_FAILED;
	}
	deadline = eip_deadline(h);
	r = eip_write(h, e->out, (size_t)len, deadline);
	if (r < 0) {
		e->broken = true;
		*result = r;
		return EIP_FAILED;
	}
	*sent = true;
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_SENT);
	df1_count(h, DF1_ID_CNT_CMD_MSGS_SENT);
	for (;;) {
		struct eip_hdr hd;
		const uint8_t *pccc = NULL;
		size_t plen = 0;

		r = eip_recv(h, e, deadline, &hd);
		if (r < 0) {
			*result = r;
			return EIP_FAILED;
		}
		if (r == 0) {
			df1_count(h, DF1_ID_CNT_COMMAND_TIMEOUTS);
			df1_log(h, DF1_ID_ERR_COMMAND_TIMEOUT);
			*result = df1_fail(h, DF1_E_TIMEOUT, station, "no reply from %s within %lld ms",
			                   h->port_name, (long long)eip_wait_ms(h));
			return EIP_FAILED;
		}
		df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
		if (hd.command != (e->connected ? EIP_CMD_SEND_UNIT_DATA : EIP_CMD_SEND_RR_DATA) ||
		    (!e->connected && memcmp(hd.context, ctx, 8) != 0)) {
			df1_count(h, DF1_ID_CNT_STALE_MSGS_RCVD);
			continue;
		}
		if (hd.status == EIP_ST_INVALID_SESSION)
			return EIP_SESSION_REFUSED;
		if (hd.status != EIP_ST_SUCCESS) {
			*result = df1_fail(h, DF1_E_EIP, station,
			                   "%s: encapsulation status 0x%04X (%s) to the command for "
			                   "station %d", h->port_name, (unsigned)hd.status,
			                   link_eip_status_text(hd.status), station);
			return EIP_FAILED;
		}
		r = eip_take(h, e, &hd, station, cmd, p.seq, &pccc, &plen);
		if (r < 0) {
			*result = r;
			return EIP_FAILED;
		}
		if (r == 0) {
			df1_count(h, DF1_ID_CNT_STALE_MSGS_RCVD);
			continue;
		}
		if (plen + 2 > cap) {
			*result = df1_fail(h, DF1_E_NOSPACE, station, "reply of %zu bytes, buffer holds %zu",
			                   plen + 2, cap);
			return EIP_FAILED;
		}
		/* the DF1 view of it: DST (us) SRC (the station) then the PCCC reply */
		reply[0] = (uint8_t)h->cfg.station;
		reply[1] = (uint8_t)station;
		memcpy(reply + 2, pccc, plen);
		df1_count(h, DF1_ID_CNT_REPLY_MSGS_RCVD);
		if (pccc[1] != 0)
			df1_count(h, DF1_ID_CNT_ERROR_MSGS_RCVD);
		*result = (int)(plen + 2);
		return EIP_GOT_REPLY;
	}
}

/* Before a command: a session the peer closed while we were idle, or bytes
 * left over from a command that timed out, are found now, not after sending. */
static void eip_idle_check(struct df1 *h, struct link_eip *e)
{
	while (!e->broken && h->fd >= 0) {
		struct eip_hdr hd;
		int r = port_wait(h, h->fd, POLLIN, df1_now_ms());

		if (r <= 0)
			return;
		r = eip_recv(h, e, eip_deadline(h), &hd);
		if (r < 0) {
			e->broken = true;
			return;
		}
		if (r == 0)
			return;
		df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
		df1_count(h, DF1_ID_CNT_STALE_MSGS_RCVD);
	}
}

static int eip_link_transact(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply,
                             size_t cap)
{
	struct link_eip *e = h->own_link_data;
	bool sent = false, retried = false, reads = !df1_pccc_is_write(cmd + 2, n - 2);
	int station = cmd[0], result = 0;

	if (e->route && station > 254)
		return df1_fail(h, DF1_E_INVAL, station, "invalid station %d", station);
	for (;;) {
		enum eip_outcome o;

		eip_idle_check(h, e);
		if (e->broken) {
			int r = eip_reopen(h, e);

			if (r < 0)
				return r;
		}
		o = eip_exchange(h, e, cmd, n, reply, cap, &result, &sent);
		if (o == EIP_GOT_REPLY)
			return result;
		if (o == EIP_SESSION_REFUSED) {
			/* refused by the encapsulation layer: not executed, any command may go again */
			e->broken = true;
			if (retried)
				return df1_fail(h, DF1_E_EIP, station, "%s: encapsulation status 0x%04X "
				                "(invalid session handle) again after registering anew",
				                h->port_name, EIP_ST_INVALID_SESSION);
			retried = true;
			continue;
		}
		/* lost connection: a command not wholly sent cannot have executed;
		 * one that was may have, unless it only reads */
		if ((result == DF1_E_CLOSED || result == DF1_E_SYS) && e->broken && !retried &&
		    (!sent || reads)) {
			retried = true;
			continue;
		}
		if ((result == DF1_E_CLOSED || result == DF1_E_SYS) && sent && !reads)
			return df1_fail(h, result, station, "%s: connection lost after the command to "
			                "station %d was sent: it may have executed, not sent again (%s)",
			                h->port_name, station, h->err.message);
		return result;
	}
}

/* The peer's liveness: a ListServices request and its reply (df1_link_test). */
static int eip_link_test(struct df1 *h)
{
	struct link_eip *e = h->own_link_data;
	struct eip_hdr hd;
	uint8_t ctx[8];
	int r;

	eip_idle_check(h, e);
	if (e->broken && (r = eip_reopen(h, e)) < 0)
		return r;
	eip_next_context(e, ctx);
	r = eip_send_msg(h, e, EIP_CMD_LIST_SERVICES, ctx, NULL, 0, eip_deadline(h));
	if (r < 0) {
		e->broken = true;
		return r;
	}
	r = eip_await(h, e, EIP_CMD_LIST_SERVICES, ctx, "ListServices", &hd);
	return r < 0 ? r : 0;
}

/* The eip:// scheme's own link (lib/scheme.c): the link layer hands it each command. */
const struct own_link_ops eip_link_ops = {
	.scheme = "eip://",
	.open = eip_link_open,
	.close = eip_link_close,
	.transact = eip_link_transact,
	.test = eip_link_test,
};
