/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip_session.c - an EtherNet/IP server connection's state machine (see
 * eip_session.h). Pure: no I/O, clock or allocation.
 *
 * What is answered how (df1-eip(7) ERRORS has the sources):
 *  - a request with a non-zero status or options field: discarded, no reply;
 *  - a length over EIP_SESSION_MSG_MAX: status 0x0065, then close (the rest of
 *    the message is not read, so the stream cannot be followed any further);
 *  - an unknown command: status 0x0001, the connection stays;
 *  - SendRRData / SendUnitData / UnRegisterSession with a session handle that
 *    is not this connection's (or before RegisterSession): status 0x0064;
 *  - RegisterSession: data not 4 bytes 0x0065; a version other than 1 0x0069
 *    (the reply carries version 1); a second one 0x0001;
 *  - a CPF that does not parse (cut items, bytes left over, items that are
 *    not a packet): status 0x0003;
 *  - CIP errors are CIP replies with a general status (encapsulation status 0).
 */
#include "eip/eip_session.h"

#include <string.h>

#include "proto/value.h"

void eip_session_init(struct eip_session *s, uint32_t handle)
{
	memset(s, 0, sizeof *s);
	s->handle = handle;
}

/* A reply header for h with status and data_len bytes already at out + 24. */
static size_t put_reply(uint8_t *out, const struct eip_hdr *h, uint32_t session, uint32_t status,
                        size_t data_len)
{
	struct eip_hdr r = *h;

	r.length = (uint16_t)data_len;
	r.session = session;
	r.status = status;
	r.options = 0;
	eip_hdr_build(out, EIP_HDR_LEN, &r);
	return EIP_HDR_LEN + data_len;
}

/* ------------------------------------------------------------------------
 * CIP message router
 * ------------------------------------------------------------------------ */

struct cip_call {
	struct eip_session *s;
	const struct eip_identity *id;
	struct eip_pending *pend;
	int station;          /* the connection's or the route path's, else -1 */
	bool routed;
	uint8_t *out;         /* the CIP reply */
	size_t cap;
};

static int cip_error(struct cip_call *c, uint8_t service, uint8_t status, uint16_t ext)
{
	return cip_resp_build(c->out, c->cap, service & 0x7F, status, &ext, ext ? 1 : 0, NULL, 0);
}

static int cm_forward_open(struct cip_call *c, const struct cip_req *r)
{
	struct cip_fwd_open f;
	struct cip_path p;
	struct eip_conn *slot = NULL;
	uint8_t data[32];
	int n;

	if (cip_fwd_open_parse(&f, r->service == CIP_SVC_LARGE_FORWARD_OPEN, r->data, r->len) != 0)
		return cip_error(c, r->service, CIP_ST_NOT_ENOUGH_DATA, 0);
	if (cip_path_parse(&p, f.path, f.path_len) != 0 ||
	    (p.port != CIP_NONE && p.port != EIP_ROUTE_PORT_SELF && p.port != EIP_ROUTE_PORT_DF1) ||
	    (p.class_id != CIP_NONE && p.class_id != CIP_CLASS_MESSAGE_ROUTER)) {
		n = cip_fwd_fail_build(data, sizeof data, f.conn_serial, f.vendor_id, f.orig_serial);
		uint16_t ext = CIP_EXT_INVALID_SEGMENT;
		return cip_resp_build(c->out, c->cap, r->service, CIP_ST_CONNECTION_FAILURE, &ext, 1, data,
		                      (size_t)n);
	}
	for (int i = 0; i < EIP_SESSION_CONNS; i++) {
		struct eip_conn *k = &c->s->conn[i];

		if (k->used && k->conn_serial == f.conn_serial && k->vendor_id == f.vendor_id &&
		    k->orig_serial == f.orig_serial) {
			uint16_t ext = CIP_EXT_DUPLICATE_FORWARD_OPEN;

			n = cip_fwd_fail_build(data, sizeof data, f.conn_serial, f.vendor_id, f.orig_serial);
			return cip_resp_build(c->out, c->cap, r->service, CIP_ST_CONNECTION_FAILURE, &ext, 1, data,
			                      (size_t)n);
		}
		if (!k->used && !slot)
			slot = k;
	}
	if (!slot) {
		uint16_t ext = CIP_EXT_NO_MORE_CONNECTIONS;

		n = cip_fwd_fail_build(data, sizeof data, f.conn_serial, f.vendor_id, f.orig_serial);
		return cip_resp_build(c->out, c->cap, r->service, CIP_ST_CONNECTION_FAILURE, &ext, 1, data,
		                      (size_t)n);
	}
	/* our O->T id: the session handle's low half and a running count, so
	 * two connections of this session never share one */
	c->s->conn_count++;
	f.ot_conn_id = (c->s->handle << 16) ^ (c->s->conn_count & 0xFFFF) ^ 0x80000000u;
	slot->used = true;
	slot->ot_id = f.ot_conn_id;
	slot->to_id = f.to_conn_id;
	slot->conn_serial = f.conn_serial;
	slot->vendor_id = f.vendor_id;
	slot->orig_serial = f.orig_serial;
	slot->station = p.port == EIP_ROUTE_PORT_DF1 && p.link != CIP_NONE && p.link < 255 ? p.link : -1;
	n = cip_fwd_open_reply_build(data, sizeof data, &f);
	return cip_resp_build(c->out, c->cap, r->service, CIP_ST_SUCCESS, NULL, 0, data, (size_t)n);
}

static int cm_forward_close(struct cip_call *c, const struct cip_req *r)
{
	struct cip_fwd_close f;
	uint8_t data[16];
	int n;

	if (cip_fwd_close_parse(&f, r->data, r->len) != 0)
		return cip_error(c, r->service, CIP_ST_NOT_ENOUGH_DATA, 0);
	n = cip_fwd_close_reply_build(data, sizeof data, &f);
	for (int i = 0; i < EIP_SESSION_CONNS; i++) {
		struct eip_conn *k = &c->s->conn[i];

		if (k->used && k->conn_serial == f.conn_serial && k->vendor_id == f.vendor_id &&
		    k->orig_serial == f.orig_serial) {
			k->used = false;
			return cip_resp_build(c->out, c->cap, r->service, CIP_ST_SUCCESS, NULL, 0, data, (size_t)n);
		}
	}
	uint16_t ext = CIP_EXT_CONNECTION_NOT_FOUND;
	return cip_resp_build(c->out, c->cap, r->service, CIP_ST_CONNECTION_FAILURE, &ext, 1, data, (size_t)n);
}

static int cip_dispatch(struct cip_call *c, const uint8_t *msg, size_t n, int depth);

/* Unconnected Send: the route path names the station (port 2, link address)
 * or the bridge itself (port 1); the embedded request's reply is the reply. */
static int cm_unconnected_send(struct cip_call *c, const struct cip_req *r, int depth)
{
	struct cip_unconnected u;
	struct cip_path p;
	int rc;

	if (depth > 0)
		return cip_error(c, r->service, CIP_ST_SERVICE_NOT_SUPPORTED, 0);
	rc = cip_unconnected_parse(&u, r->data, r->len);
	if (rc == DF1_E_TOO_LONG)   /* bytes after the route, or a request over CIP_UNCONNECTED_REQ_MAX */
		return cip_error(c, r->service, CIP_ST_TOO_MUCH_DATA, 0);
	if (rc != 0)
		return cip_error(c, r->service, CIP_ST_NOT_ENOUGH_DATA, 0);
	if (cip_path_parse(&p, u.route, u.route_len) != 0 || p.class_id != CIP_NONE)
		return cip_error(c, r->service, CIP_ST_CONNECTION_FAILURE, CIP_EXT_INVALID_SEGMENT);
	if (p.port != CIP_NONE && p.port != EIP_ROUTE_PORT_SELF && p.port != EIP_ROUTE_PORT_DF1)
		return cip_error(c, r->service, CIP_ST_CONNECTION_FAILURE, CIP_EXT_INVALID_PORT);
	if (p.port == EIP_ROUTE_PORT_DF1) {
		if (p.link == CIP_NONE || p.link > 254)
			return cip_error(c, r->service, CIP_ST_CONNECTION_FAILURE, CIP_EXT_INVALID_LINK);
		c->station = p.link;
	}
	c->routed = true;
	return cip_dispatch(c, u.req, u.req_len, depth + 1);
}

static int identity_service(struct cip_call *c, const struct cip_req *r, const struct cip_path *p)
{
	uint8_t data[64];
	int n;

	if (r->service == CIP_SVC_GET_ATTRIBUTES_ALL) {
		n = cip_identity_all_build(data, sizeof data, c->id);
	} else if (r->service == CIP_SVC_GET_ATTRIBUTE_SINGLE) {
		if (p->attribute == CIP_NONE)
			return cip_error(c, r->service, CIP_ST_PATH_DESTINATION, 0);
		n = cip_identity_attr_build(data, sizeof data, c->id, p->attribute);
		if (n == DF1_E_NOTSUP)
			return cip_error(c, r->service, CIP_ST_ATTRIBUTE_NOT_SUPPORTED, 0);
	} else {
		return cip_error(c, r->service, CIP_ST_SERVICE_NOT_SUPPORTED, 0);
	}
	if (n < 0)
		return n;
	return cip_resp_build(c->out, c->cap, r->service, CIP_ST_SUCCESS, NULL, 0, data, (size_t)n);
}

static int execute_pccc(struct cip_call *c, const struct cip_req *r)
{
	struct eip_pccc pc;
	int rc = eip_pccc_parse(&pc, r->data, r->len);

	if (rc == DF1_E_TOO_SHORT)
		return cip_error(c, r->service, CIP_ST_NOT_ENOUGH_DATA, 0);
	if (rc == DF1_E_TOO_LONG)
		return cip_error(c, r->service, CIP_ST_TOO_MUCH_DATA, 0);
	if (rc != 0)
		return cip_error(c, r->service, CIP_ST_INVALID_PARAMETER, 0);
	memcpy(c->pend->reqid, pc.reqid, pc.reqid_len);
	c->pend->reqid_len = pc.reqid_len;
	c->pend->pccc = pc.pccc;
	c->pend->len = pc.len;
	c->pend->station = c->station;
	c->pend->routed = c->routed;
	return 0;
}

/* A CIP request -> its reply in c->out (length > 0), 0 = a PCCC request in
 * c->pend, < 0 = DF1_E_NOSPACE. */
static int cip_dispatch(struct cip_call *c, const uint8_t *msg, size_t n, int depth)
{
	struct cip_req r;
	struct cip_path p;

	if (n < 2)
		return cip_error(c, n ? msg[0] : 0, CIP_ST_NOT_ENOUGH_DATA, 0);
	if (cip_req_parse(&r, msg, n) != 0)
		return cip_error(c, msg[0], CIP_ST_PATH_SIZE_INVALID, 0);
	if (r.service & CIP_SVC_REPLY)       /* a reply is no request */
		return cip_error(c, r.service, CIP_ST_SERVICE_NOT_SUPPORTED, 0);
	if (cip_path_parse(&p, r.path, r.path_len) != 0 || p.port != CIP_NONE)
		return cip_error(c, r.service, CIP_ST_PATH_SEGMENT, 0);
	if (p.instance != 1 && !(p.instance == CIP_NONE && p.class_id == CIP_CLASS_PCCC))
		return cip_error(c, r.service, CIP_ST_PATH_DESTINATION, 0);
	switch (p.class_id) {
	case CIP_CLASS_PCCC:
		if (r.service != CIP_SVC_EXECUTE_PCCC)
			return cip_error(c, r.service, CIP_ST_SERVICE_NOT_SUPPORTED, 0);
		return execute_pccc(c, &r);
	case CIP_CLASS_CONNECTION_MANAGER:
		if (r.service == CIP_SVC_UNCONNECTED_SEND)
			return cm_unconnected_send(c, &r, depth);
		if (depth > 0)
			return cip_error(c, r.service, CIP_ST_SERVICE_NOT_SUPPORTED, 0);
		if (r.service == CIP_SVC_FORWARD_OPEN || r.service == CIP_SVC_LARGE_FORWARD_OPEN)
			return cm_forward_open(c, &r);
		if (r.service == CIP_SVC_FORWARD_CLOSE)
			return cm_forward_close(c, &r);
		return cip_error(c, r.service, CIP_ST_SERVICE_NOT_SUPPORTED, 0);
	case CIP_CLASS_IDENTITY:
		return identity_service(c, &r, &p);
	case CIP_CLASS_MESSAGE_ROUTER:
		return cip_error(c, r.service, CIP_ST_SERVICE_NOT_SUPPORTED, 0);
	default:
		return cip_error(c, r.service, CIP_ST_PATH_DESTINATION, 0);
	}
}

/* ------------------------------------------------------------------------
 * Encapsulation
 * ------------------------------------------------------------------------ */

static struct eip_conn *conn_by_ot(struct eip_session *s, uint32_t ot_id)
{
	for (int i = 0; i < EIP_SESSION_CONNS; i++)
		if (s->conn[i].used && s->conn[i].ot_id == ot_id)
			return &s->conn[i];
	return NULL;
}

/* SendRRData / SendUnitData: the CIP request inside, its reply around it. */
static enum eip_verdict send_data(struct eip_session *s, const struct eip_identity *id,
                                  const struct eip_hdr *h, const uint8_t *data, uint8_t *out,
                                  size_t cap, size_t *out_len, struct eip_pending *pend)
{
	struct eip_cpf cpf;
	struct eip_packet pk;
	struct eip_conn *k = NULL;
	struct cip_call c;
	uint8_t cip[512];
	uint16_t timeout;
	int n;

	if (eip_rr_parse(&timeout, &cpf, data, h->length) != 0 || eip_packet_parse(&pk, &cpf) != 0 ||
	    pk.connected != (h->command == EIP_CMD_SEND_UNIT_DATA)) {
		*out_len = put_reply(out, h, s->handle, EIP_ST_INCORRECT_DATA, 0);
		return EIP_SEND;
	}
	if (pk.connected) {
		k = conn_by_ot(s, pk.conn_id);
		if (!k)   /* no such connection: nothing to answer on (Vol. 2 3-2.2) */
			return EIP_SILENT;
	}
	memset(pend, 0, sizeof *pend);
	pend->session = s->handle;
	memcpy(pend->context, h->context, 8);
	pend->connected = pk.connected;
	pend->to_id = k ? k->to_id : 0;
	pend->seq = pk.seq;
	c.s = s;
	c.id = id;
	c.pend = pend;
	c.station = k ? k->station : -1;
	c.routed = false;
	c.out = cip;
	c.cap = sizeof cip;
	n = cip_dispatch(&c, pk.data, pk.len, 0);
	if (n == 0)
		return EIP_PCCC;
	if (n < 0) {
		*out_len = put_reply(out, h, s->handle, EIP_ST_NO_MEMORY, 0);
		return EIP_SEND;
	}
	pk.data = cip;
	pk.len = (size_t)n;
	pk.conn_id = pend->to_id;
	n = eip_packet_build(out, cap, s->handle, h->context, 0, &pk);
	if (n < 0) {
		*out_len = put_reply(out, h, s->handle, EIP_ST_NO_MEMORY, 0);
		return EIP_SEND;
	}
	*out_len = (size_t)n;
	return EIP_SEND;
}

static enum eip_verdict register_session(struct eip_session *s, const struct eip_hdr *h,
                                         const uint8_t *data, uint8_t *out, size_t *out_len)
{
	uint16_t version, options;

	if (eip_register_parse(&version, &options, data, h->length) != 0) {
		*out_len = put_reply(out, h, 0, EIP_ST_INVALID_LENGTH, 0);
		return EIP_SEND;
	}
	eip_register_build(out + EIP_HDR_LEN, 4, EIP_PROTOCOL_VERSION, 0);
	if (s->registered) {
		*out_len = put_reply(out, h, s->handle, EIP_ST_INVALID_COMMAND, 4);
		return EIP_SEND;
	}
	if (version != EIP_PROTOCOL_VERSION) {
		*out_len = put_reply(out, h, 0, EIP_ST_UNSUPPORTED_VERSION, 4);
		return EIP_SEND;
	}
	s->registered = true;
	*out_len = put_reply(out, h, s->handle, EIP_ST_SUCCESS, 4);
	return EIP_SEND;
}

enum eip_verdict eip_session_input(struct eip_session *s, const struct eip_identity *id, bool udp,
                                   const uint8_t *msg, size_t n, uint8_t *out, size_t cap,
                                   size_t *out_len, struct eip_pending *pend)
{
	struct eip_hdr h;
	const uint8_t *data = msg + EIP_HDR_LEN;
	int rc;

	*out_len = 0;
	if (!s || !id || !msg || !out || cap < 64 || !pend || eip_hdr_parse(&h, msg, n) != 0)
		return EIP_CLOSE;
	if ((size_t)h.length + EIP_HDR_LEN > EIP_SESSION_MSG_MAX || n != EIP_HDR_LEN + (size_t)h.length) {
		if (udp)
			return EIP_SILENT;
		*out_len = put_reply(out, &h, h.session, EIP_ST_INVALID_LENGTH, 0);
		return EIP_SEND_CLOSE;
	}
	if (h.status != 0 || h.options != 0)
		return EIP_SILENT;
	switch (h.command) {
	case EIP_CMD_LIST_IDENTITY:
		rc = eip_identity_build(out + EIP_HDR_LEN, cap - EIP_HDR_LEN, id);
		break;
	case EIP_CMD_LIST_SERVICES:
		rc = eip_services_build(out + EIP_HDR_LEN, cap - EIP_HDR_LEN, EIP_SERVICE_CIP_TCP);
		break;
	case EIP_CMD_LIST_INTERFACES:
		put_le16(out + EIP_HDR_LEN, 0);     /* no interfaces */
		rc = 2;
		break;
	default:
		rc = -1;
		break;
	}
	if (rc >= 0) {
		*out_len = put_reply(out, &h, h.session, EIP_ST_SUCCESS, (size_t)rc);
		return EIP_SEND;
	}
	if (udp)
		return EIP_SILENT;
	switch (h.command) {
	case EIP_CMD_NOP:
		return EIP_SILENT;
	case EIP_CMD_REGISTER_SESSION:
		return register_session(s, &h, data, out, out_len);
	case EIP_CMD_UNREGISTER_SESSION:
	case EIP_CMD_SEND_RR_DATA:
	case EIP_CMD_SEND_UNIT_DATA:
		if (!s->registered || h.session != s->handle) {
			*out_len = put_reply(out, &h, h.session, EIP_ST_INVALID_SESSION, 0);
			return EIP_SEND;
		}
		if (h.command == EIP_CMD_UNREGISTER_SESSION)
			return EIP_CLOSE;
		return send_data(s, id, &h, data, out, cap, out_len, pend);
	default:
		*out_len = put_reply(out, &h, h.session, EIP_ST_INVALID_COMMAND, 0);
		return EIP_SEND;
	}
}

int eip_session_reply(const struct eip_pending *p, int cip_status, uint16_t ext, const uint8_t *pccc,
                      size_t n, uint8_t *out, size_t cap)
{
	uint8_t cip[EIP_SESSION_MSG_MAX];
	struct eip_packet pk;
	int len;

	if (!p || !out || (!pccc && n) || n > sizeof cip - 4 - EIP_REQID_MAX)
		return DF1_E_INVAL;
	if (cip_status == 0) {
		memcpy(cip + 4, p->reqid, p->reqid_len);
		if (n)
			memcpy(cip + 4 + p->reqid_len, pccc, n);
		len = cip_resp_build(cip, sizeof cip, CIP_SVC_EXECUTE_PCCC, 0, NULL, 0, cip + 4,
		                     p->reqid_len + n);
	} else {
		len = cip_resp_build(cip, sizeof cip, p->routed ? CIP_SVC_UNCONNECTED_SEND : CIP_SVC_EXECUTE_PCCC,
		                     (uint8_t)cip_status, &ext, ext ? 1 : 0, NULL, 0);
	}
	if (len < 0)
		return len;
	memset(&pk, 0, sizeof pk);
	pk.connected = p->connected;
	pk.conn_id = p->to_id;
	pk.seq = p->seq;
	pk.data = cip;
	pk.len = (size_t)len;
	return eip_packet_build(out, cap, p->session, p->context, 0, &pk);
}
