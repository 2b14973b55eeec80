/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_link_eip.c - the link over EtherNet/IP (lib/eip/eip_link.c) and
 * df1_eip_list_identity() against a scripted peer on a loopback TCP socket:
 * a thread that accepts, checks each request byte by byte against the layout
 * of df1-eip(7) (Execute PCCC, Unconnected Send, Forward Open/Close, the
 * requester ID) and answers what the test says, errors included. The peer's
 * replies are built with the codec (lib/eip/eip_codec.c, tested on its own
 * against hand-written vectors in test_eip.c). Every wait is bounded.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "df1_int.h"
#include "eip/eip_codec.h"
#include "eip/eip_link.h"

#define PEER_WAIT_MS 5000
#define SESSION 0x11223344u
#define OT_ID 0x0A0B0C0Du

/* ---- the scripted peer ------------------------------------------------- */

struct msg {
	struct eip_hdr h;
	uint8_t data[1024];
	struct eip_packet p;          /* SendRRData / SendUnitData */
	struct cip_req req;           /* its CIP request */
};

struct peer;
typedef void (*script_fn)(struct peer *p);

struct peer {
	int lfd, fd, port;
	pthread_t t;
	script_fn script;
	int accepts;
	int writes, reads;            /* PCCC commands served */
	int unregisters, forward_closes;
	uint32_t to_id;               /* the client's T->O id from its Forward Open */
	int route_station;            /* -1: no Unconnected Send seen */
	uint8_t last_pccc[256];
	size_t last_pccc_len;
	bool failed;
	char why[200];
	int sync[2];                  /* the peer writes a byte here at a point the test awaits */
	int16_t value;                /* what N7:0 holds */
};

static void peer_fail(struct peer *p, const char *why)
{
	if (!p->failed)
		snprintf(p->why, sizeof p->why, "%s", why);
	p->failed = true;
}

static bool read_n(int fd, uint8_t *b, size_t n)
{
	size_t got = 0;

	while (got < n) {
		struct pollfd pf = { fd, POLLIN, 0 };
		ssize_t r;

		if (poll(&pf, 1, PEER_WAIT_MS) <= 0)
			return false;
		r = read(fd, b + got, n - got);
		if (r <= 0)
			return false;
		got += (size_t)r;
	}
	return true;
}

/* One message; false at EOF or a wait over PEER_WAIT_MS. */
static bool peer_recv(struct peer *p, struct msg *m)
{
	uint8_t hdr[EIP_HDR_LEN];
	struct eip_cpf cpf;
	uint16_t tmo;

	memset(m, 0, sizeof *m);
	if (!read_n(p->fd, hdr, sizeof hdr))
		return false;
	eip_hdr_parse(&m->h, hdr, sizeof hdr);
	if (m->h.length > sizeof m->data || !read_n(p->fd, m->data, m->h.length))
		return false;
	if (m->h.command == EIP_CMD_UNREGISTER_SESSION)
		p->unregisters++;
	if ((m->h.command == EIP_CMD_SEND_RR_DATA || m->h.command == EIP_CMD_SEND_UNIT_DATA) &&
	    (eip_rr_parse(&tmo, &cpf, m->data, m->h.length) < 0 || eip_packet_parse(&m->p, &cpf) < 0 ||
	     cip_req_parse(&m->req, m->p.data, m->p.len) < 0))
		peer_fail(p, "malformed SendRRData/SendUnitData");
	return true;
}

static void peer_send(struct peer *p, const uint8_t *b, size_t n)
{
	if (write(p->fd, b, n) != (ssize_t)n)
		peer_fail(p, "write");
}

/* A header and data of our own making (statuses, odd commands). */
static void peer_send_hdr(struct peer *p, uint16_t cmd, uint32_t session, uint32_t status,
                          const uint8_t ctx[8], const uint8_t *data, size_t n)
{
	uint8_t out[1024];
	struct eip_hdr h;

	memset(&h, 0, sizeof h);
	h.command = cmd;
	h.length = (uint16_t)n;
	h.session = session;
	h.status = status;
	memcpy(h.context, ctx, 8);
	eip_hdr_build(out, sizeof out, &h);
	if (n)
		memcpy(out + EIP_HDR_LEN, data, n);
	peer_send(p, out, EIP_HDR_LEN + n);
}

static bool peer_accept(struct peer *p)
{
	struct pollfd pf = { p->lfd, POLLIN, 0 };

	if (p->fd >= 0)
		close(p->fd);
	p->fd = -1;
	if (poll(&pf, 1, PEER_WAIT_MS) <= 0)
		return false;
	p->fd = accept(p->lfd, NULL, NULL);
	if (p->fd < 0)
		return false;
	p->accepts++;
	return true;
}

/* Accept and answer RegisterSession with SESSION. */
static bool peer_open(struct peer *p)
{
	struct msg m;
	uint8_t d[4];

	if (!peer_accept(p) || !peer_recv(p, &m))
		return false;
	if (m.h.command != EIP_CMD_REGISTER_SESSION || m.h.length != 4 || m.data[0] != 1 ||
	    m.data[1] != 0 || m.h.session != 0) {
		peer_fail(p, "RegisterSession expected (version 1)");
		return false;
	}
	eip_register_build(d, sizeof d, 1, 0);
	peer_send_hdr(p, EIP_CMD_REGISTER_SESSION, SESSION, 0, m.h.context, d, sizeof d);
	return true;
}

/* The Execute PCCC request of m (direct or in an Unconnected Send): its
 * requester ID and PCCC bytes checked and kept. */
static bool peer_pccc_of(struct peer *p, const struct msg *m, struct eip_pccc *pc)
{
	struct cip_req inner = m->req;
	struct cip_path path;

	if (m->req.service == CIP_SVC_UNCONNECTED_SEND) {
		struct cip_unconnected u;
		struct cip_path r;

		if (cip_unconnected_parse(&u, m->req.data, m->req.len) < 0 ||
		    cip_req_parse(&inner, u.req, u.req_len) < 0) {
			peer_fail(p, "malformed Unconnected Send");
			return false;
		}
		cip_path_init(&r);
		if (cip_path_parse(&r, u.route, u.route_len) < 0 || r.port != EIP_ROUTE_PORT_DF1) {
			peer_fail(p, "route path is not port 2");
			return false;
		}
		p->route_station = r.link;
	}
	cip_path_init(&path);
	if (inner.service != CIP_SVC_EXECUTE_PCCC || cip_path_parse(&path, inner.path, inner.path_len) < 0 ||
	    path.class_id != CIP_CLASS_PCCC || path.instance != 1 ||
	    eip_pccc_parse(pc, inner.data, inner.len) < 0) {
		char why[96];

		snprintf(why, sizeof why, "not Execute PCCC to 67/1: service %02X, %zu path bytes %02X",
		         inner.service, inner.path_len, inner.path_len ? inner.path[0] : 0);
		peer_fail(p, why);
		return false;
	}
	/* requester ID: length 7, vendor 0 (none claimed), a serial */
	if (pc->reqid_len != 7 || pc->reqid[0] != 7 || pc->reqid[1] != 0 || pc->reqid[2] != 0) {
		peer_fail(p, "requester ID not 7 bytes with vendor 0");
		return false;
	}
	memcpy(p->last_pccc, pc->pccc, pc->len);
	p->last_pccc_len = pc->len;
	return true;
}

/* The reply to m carrying pccc_reply (CMD|40 STS TNS ...), CIP status st. */
static void peer_reply(struct peer *p, const struct msg *m, const struct eip_pccc *pc, uint8_t st,
                       uint16_t ext, const uint8_t *pccc_reply, size_t n)
{
	uint8_t body[600], cip[700], out[800];
	struct eip_packet rp;
	size_t bl = 0;
	int cl, ol;

	memcpy(body, pc->reqid, pc->reqid_len);
	bl = pc->reqid_len;
	if (n)
		memcpy(body + bl, pccc_reply, n);
	bl += n;
	if (st == 0)
		cl = cip_resp_build(cip, sizeof cip, CIP_SVC_EXECUTE_PCCC, 0, NULL, 0, body, bl);
	else
		cl = cip_resp_build(cip, sizeof cip, m->req.service, st, &ext, ext ? 1 : 0, NULL, 0);
	memset(&rp, 0, sizeof rp);
	rp.connected = m->p.connected;
	rp.conn_id = p->to_id;
	rp.seq = m->p.seq;
	rp.data = cip;
	rp.len = (size_t)cl;
	ol = eip_packet_build(out, sizeof out, SESSION, m->h.context, 0, &rp);
	peer_send(p, out, (size_t)ol);
}

/* A typed-logical reply for the command in pc: reads give p->value. */
static size_t peer_answer(struct peer *p, const struct eip_pccc *pc, uint8_t sts, uint8_t *r)
{
	size_t n = 4;

	r[0] = pc->pccc[0] | 0x40;
	r[1] = sts;
	r[2] = pc->pccc[2];
	r[3] = pc->pccc[3];
	if (sts == 0 && pc->len >= 5 && (pc->pccc[4] == 0xA2 || pc->pccc[4] == 0xA1)) {
		p->reads++;
		r[4] = (uint8_t)p->value;
		r[5] = (uint8_t)((uint16_t)p->value >> 8);
		n = 6;
	} else if (sts == 0) {
		p->writes++;
	}
	return n;
}

/* Receive one PCCC command and answer it normally. */
static bool peer_serve_one(struct peer *p, struct msg *m)
{
	struct eip_pccc pc;
	uint8_t r[16];
	size_t n;

	if (!peer_recv(p, m) || !peer_pccc_of(p, m, &pc))
		return false;
	n = peer_answer(p, &pc, 0, r);
	peer_reply(p, m, &pc, 0, 0, r, n);
	return true;
}

/* Serve until the client goes (EOF); a Forward Close is answered (and
 * counted), so that closing a connected handle waits for nothing. */
static void peer_drain(struct peer *p)
{
	struct msg m;

	while (peer_recv(p, &m)) {
		struct cip_fwd_close f;
		struct eip_packet rp;
		uint8_t data[32], cip[48], out[128];
		int dl, cl, ol;

		if (m.req.service != CIP_SVC_FORWARD_CLOSE || m.p.connected ||
		    cip_fwd_close_parse(&f, m.req.data, m.req.len) < 0)
			continue;
		p->forward_closes++;
		dl = cip_fwd_close_reply_build(data, sizeof data, &f);
		cl = cip_resp_build(cip, sizeof cip, CIP_SVC_FORWARD_CLOSE, 0, NULL, 0, data, (size_t)dl);
		memset(&rp, 0, sizeof rp);
		rp.data = cip;
		rp.len = (size_t)cl;
		ol = eip_packet_build(out, sizeof out, SESSION, m.h.context, 0, &rp);
		peer_send(p, out, (size_t)ol);
	}
}

static void *peer_main(void *arg)
{
	struct peer *p = arg;

	p->script(p);
	if (p->fd >= 0)
		close(p->fd);
	p->fd = -1;
	return NULL;
}

static void peer_start(struct peer *p, script_fn s)
{
	struct sockaddr_in a;
	socklen_t al = sizeof a;

	memset(p, 0, sizeof *p);
	p->fd = -1;
	p->route_station = -1;
	p->script = s;
	p->value = 1234;
	assert_int_equal(pipe(p->sync), 0);
	p->lfd = socket(AF_INET, SOCK_STREAM, 0);
	assert_true(p->lfd >= 0);
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(bind(p->lfd, (struct sockaddr *)&a, sizeof a), 0);
	assert_int_equal(listen(p->lfd, 4), 0);
	assert_int_equal(getsockname(p->lfd, (struct sockaddr *)&a, &al), 0);
	p->port = ntohs(a.sin_port);
	assert_int_equal(pthread_create(&p->t, NULL, peer_main, p), 0);
}

static void peer_join(struct peer *p)
{
	pthread_join(p->t, NULL);
	close(p->lfd);
	close(p->sync[0]);
	close(p->sync[1]);
	if (p->failed)
		fail_msg("peer: %s", p->why);
}

static void peer_signal(struct peer *p)
{
	(void)!write(p->sync[1], "x", 1);
}

static void await_peer(struct peer *p)
{
	struct pollfd pf = { p->sync[0], POLLIN, 0 };
	char c;

	assert_int_equal(poll(&pf, 1, PEER_WAIT_MS), 1);
	assert_int_equal(read(p->sync[0], &c, 1), 1);
}

/* No connection waiting at the listener now (the client did not come back). */
static bool no_new_connection(struct peer *p)
{
	struct pollfd pf = { p->lfd, POLLIN, 0 };

	return poll(&pf, 1, 0) == 0;
}

static df1_t *client(struct peer *p, const char *suffix, bool connected)
{
	char t[96];
	df1_t *h;

	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_timeout_ms(h, 2000), 0);
	if (connected)
		assert_int_equal(df1_set_option(h, DF1_OPT_EIP_CONNECTED, 1), 0);
	snprintf(t, sizeof t, "eip://127.0.0.1:%d%s", p->port, suffix);
	assert_int_equal(df1_open(h, t), 0);
	return h;
}

static uint64_t counter(df1_t *h, int id)
{
	uint64_t v = 0;

	assert_int_equal(df1_counter(h, id, &v), 0);
	return v;
}

/* ---- scripts and tests ------------------------------------------------- */

static void s_read_write(struct peer *p)
{
	struct msg m;

	if (!peer_open(p) || !peer_serve_one(p, &m) || !peer_serve_one(p, &m))
		return;
	peer_drain(p);
}

static void s_read_one(struct peer *p)
{
	struct msg m;

	if (!peer_open(p) || !peer_serve_one(p, &m))
		return;
	peer_drain(p);
}

/* A read and a write: Execute PCCC in SendRRData, our session, the SLC
 * typed logical commands (0F/A2, 0F/AA) inside; UnRegisterSession at close. */
static void test_eip_read_write(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 0;

	(void)state;
	peer_start(&p, s_read_write);
	h = client(&p, "", false);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), 1);
	assert_int_equal(v, 1234);
	assert_int_equal(p.last_pccc[0], 0x0F);
	assert_int_equal(p.last_pccc[4], 0xA2);
	v = -5;
	assert_int_equal(df1_write_int16(h, 1, "N7:3", &v, 1), 1);
	assert_int_equal(p.last_pccc[4], 0xAA);
	assert_int_equal(p.last_pccc[p.last_pccc_len - 2], 0xFB); /* -5 LE */
	assert_int_equal(p.last_pccc[p.last_pccc_len - 1], 0xFF);
	assert_int_equal(counter(h, DF1_ID_CNT_CMD_MSGS_SENT), 2);
	assert_int_equal(counter(h, DF1_ID_CNT_REPLY_MSGS_RCVD), 2);
	df1_free(h);
	peer_join(&p);
	assert_int_equal(p.unregisters, 1);
	assert_int_equal(p.reads, 1);
	assert_int_equal(p.writes, 1);
}

static void s_stale(struct peer *p)
{
	struct msg m;
	struct eip_pccc pc;
	uint8_t r[16], ctx[8];
	size_t n;

	if (!peer_open(p) || !peer_recv(p, &m) || !peer_pccc_of(p, &m, &pc))
		return;
	n = peer_answer(p, &pc, 0, r);
	/* another context first, then the right context with another TNS */
	memcpy(ctx, m.h.context, 8);
	m.h.context[0] ^= 0x55;
	p->value = 1;
	peer_reply(p, &m, &pc, 0, 0, r, n);
	memcpy(m.h.context, ctx, 8);
	r[2] ^= 0x01;
	peer_reply(p, &m, &pc, 0, 0, r, n);
	r[2] ^= 0x01;
	r[4] = 0x39;
	r[5] = 0x30;                  /* 12345 */
	peer_reply(p, &m, &pc, 0, 0, r, n);
	peer_drain(p);
}

static void test_eip_stale_replies_dropped(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 0;

	(void)state;
	peer_start(&p, s_stale);
	h = client(&p, "", false);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), 1);
	assert_int_equal(v, 12345);
	assert_int_equal(counter(h, DF1_ID_CNT_STALE_MSGS_RCVD), 2);
	df1_free(h);
	peer_join(&p);
}

/* Errors: what the peer does to the first command, by a variable the
 * script reads. */
static int error_kind;
enum { ERR_ENCAP, ERR_CIP, ERR_STS, ERR_SILENT, ERR_HUGE, ERR_CUT };

static void s_error(struct peer *p)
{
	struct msg m;
	struct eip_pccc pc;
	uint8_t r[16], big[8] = { 0 };
	size_t n;

	if (!peer_open(p) || !peer_recv(p, &m) || !peer_pccc_of(p, &m, &pc))
		return;
	switch (error_kind) {
	case ERR_ENCAP:
		peer_send_hdr(p, EIP_CMD_SEND_RR_DATA, SESSION, EIP_ST_INCORRECT_DATA, m.h.context, NULL, 0);
		break;
	case ERR_CIP:
		peer_reply(p, &m, &pc, CIP_ST_SERVICE_NOT_SUPPORTED, 0, NULL, 0);
		break;
	case ERR_STS:
		n = peer_answer(p, &pc, 0x10, r);
		peer_reply(p, &m, &pc, 0, 0, r, n);
		break;
	case ERR_SILENT:
		break;
	case ERR_HUGE: {
		uint8_t hdr[EIP_HDR_LEN];
		struct eip_hdr hd;

		memset(&hd, 0, sizeof hd);
		hd.command = EIP_CMD_SEND_RR_DATA;
		hd.length = 60000;
		hd.session = SESSION;
		memcpy(hd.context, m.h.context, 8);
		eip_hdr_build(hdr, sizeof hdr, &hd);
		peer_send(p, hdr, sizeof hdr);
		peer_send(p, big, sizeof big);
		break;
	}
	case ERR_CUT:
		peer_send_hdr(p, EIP_CMD_SEND_RR_DATA, SESSION, 0, m.h.context, big, 4); /* CPF cut */
		break;
	}
	peer_drain(p);
}

static df1_t *error_case(struct peer *p, int kind, int want)
{
	df1_t *h;
	int16_t v = 0;

	error_kind = kind;
	peer_start(p, s_error);
	h = client(p, "", false);
	if (kind == ERR_SILENT) {
		assert_int_equal(df1_set_timeout_ms(h, 300), 0);
		assert_int_equal(df1_set_cmd_timeout_ms(h, 500), 0);
	}
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), want);
	return h;
}

static void test_eip_encapsulation_status(void **state)
{
	struct peer p;
	df1_t *h = error_case(&p, ERR_ENCAP, DF1_E_EIP);

	(void)state;
	assert_non_null(strstr(df1_last_error(h)->message, "0x0003 (incorrect data)"));
	df1_free(h);
	peer_join(&p);
}

static void test_eip_cip_status(void **state)
{
	struct peer p;
	df1_t *h = error_case(&p, ERR_CIP, DF1_E_CIP);

	(void)state;
	assert_non_null(strstr(df1_last_error(h)->message, "0x08 (service not supported)"));
	df1_free(h);
	peer_join(&p);
}

static void test_eip_pccc_sts_is_remote(void **state)
{
	struct peer p;
	df1_t *h = error_case(&p, ERR_STS, DF1_E_REMOTE);

	(void)state;
	assert_int_equal(df1_last_error(h)->sts, 0x10);
	df1_free(h);
	peer_join(&p);
}

static void test_eip_timeout(void **state)
{
	struct peer p;
	df1_t *h = error_case(&p, ERR_SILENT, DF1_E_TIMEOUT);

	(void)state;
	assert_int_equal(counter(h, DF1_ID_CNT_COMMAND_TIMEOUTS), 1);
	df1_free(h);
	peer_join(&p);
}

static void test_eip_oversized_message(void **state)
{
	struct peer p;
	df1_t *h = error_case(&p, ERR_HUGE, DF1_E_EIP);

	(void)state;
	assert_non_null(strstr(df1_last_error(h)->message, "60000 bytes"));
	df1_free(h);
	peer_join(&p);
	assert_int_equal(p.unregisters, 0); /* a stream out of step gets no more requests */
}

static void test_eip_truncated_cpf(void **state)
{
	struct peer p;
	df1_t *h = error_case(&p, ERR_CUT, DF1_E_BAD_REPLY);

	(void)state;
	df1_free(h);
	peer_join(&p);
}

/* 0064h to a write: the target did not take it; a new session, sent again. */
static void s_session_refused(struct peer *p)
{
	struct msg m;

	if (!peer_open(p) || !peer_recv(p, &m))
		return;
	peer_send_hdr(p, EIP_CMD_SEND_RR_DATA, SESSION, EIP_ST_INVALID_SESSION, m.h.context, NULL, 0);
	if (!peer_open(p) || !peer_serve_one(p, &m))
		return;
	peer_drain(p);
}

static void test_eip_invalid_session_reregisters(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 7;

	(void)state;
	peer_start(&p, s_session_refused);
	h = client(&p, "", false);
	assert_int_equal(df1_write_int16(h, 1, "N7:0", &v, 1), 1);
	df1_free(h);
	peer_join(&p);
	assert_int_equal(p.accepts, 2);
	assert_int_equal(p.writes, 1);
}

/* The connection closed with the command out: a read is asked again on a
 * new session; a write is reported and never sent again. */
static void s_close_after_command(struct peer *p)
{
	struct msg m;

	if (!peer_open(p) || !peer_recv(p, &m))
		return;
	close(p->fd);
	p->fd = -1;
	if (error_kind == 0) {         /* the read: it comes again */
		if (!peer_open(p) || !peer_serve_one(p, &m))
			return;
		peer_drain(p);
	}
}

static void test_eip_peer_closes_read_retried(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 0;

	(void)state;
	error_kind = 0;
	peer_start(&p, s_close_after_command);
	h = client(&p, "", false);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), 1);
	assert_int_equal(v, 1234);
	df1_free(h);
	peer_join(&p);
	assert_int_equal(p.accepts, 2);
}

static void test_eip_peer_closes_write_not_resent(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 9;
	int r;

	(void)state;
	error_kind = 1;
	peer_start(&p, s_close_after_command);
	h = client(&p, "", false);
	r = df1_write_int16(h, 1, "N7:0", &v, 1);
	assert_true(r == DF1_E_CLOSED || r == DF1_E_SYS);
	assert_false(df1_error_unexecuted(r));
	assert_non_null(strstr(df1_last_error(h)->message, "may have executed"));
	assert_true(no_new_connection(&p));
	df1_free(h);
	peer_join(&p);
	assert_int_equal(p.accepts, 1);
	assert_int_equal(p.writes, 0);
}

/* Closed while idle: found before the next command, which then goes once. */
static void s_close_idle(struct peer *p)
{
	struct msg m;

	if (!peer_open(p) || !peer_serve_one(p, &m))
		return;
	close(p->fd);
	p->fd = -1;
	peer_signal(p);
	if (!peer_open(p) || !peer_serve_one(p, &m))
		return;
	peer_drain(p);
}

static void test_eip_idle_close_write_once(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 0;

	(void)state;
	peer_start(&p, s_close_idle);
	h = client(&p, "", false);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), 1);
	await_peer(&p);
	v = 3;
	assert_int_equal(df1_write_int16(h, 1, "N7:0", &v, 1), 1);
	df1_free(h);
	peer_join(&p);
	assert_int_equal(p.accepts, 2);
	assert_int_equal(p.writes, 1);
}

/* --eip-connected: Forward Open to the Message Router, SendUnitData with the
 * target's O->T id and a sequence count from 1, Forward Close at close. */
static void s_connected(struct peer *p)
{
	struct msg m;
	struct cip_fwd_open f;
	uint8_t data[64], cip[96], out[200];
	struct eip_packet rp;
	int n, cl, ol;

	if (!peer_open(p) || !peer_recv(p, &m))
		return;
	if (m.p.connected || m.req.service != CIP_SVC_FORWARD_OPEN ||
	    cip_fwd_open_parse(&f, false, m.req.data, m.req.len) < 0 || f.transport != 0xA3 ||
	    f.vendor_id != 0) {
		peer_fail(p, "Forward Open expected");
		return;
	}
	p->to_id = f.to_conn_id;
	f.ot_conn_id = OT_ID;
	n = cip_fwd_open_reply_build(data, sizeof data, &f);
	cl = cip_resp_build(cip, sizeof cip, CIP_SVC_FORWARD_OPEN, 0, NULL, 0, data, (size_t)n);
	memset(&rp, 0, sizeof rp);
	rp.data = cip;
	rp.len = (size_t)cl;
	ol = eip_packet_build(out, sizeof out, SESSION, m.h.context, 0, &rp);
	peer_send(p, out, (size_t)ol);
	for (int i = 1; i <= 2; i++) {
		if (!peer_serve_one(p, &m))
			return;
		if (!m.p.connected || m.p.conn_id != OT_ID || m.p.seq != i)
			peer_fail(p, "SendUnitData on O->T id with sequence 1, 2");
	}
	peer_drain(p);
}

static void test_eip_connected(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 0;

	(void)state;
	peer_start(&p, s_connected);
	h = client(&p, "", true);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), 1);
	assert_int_equal(v, 1234);
	assert_int_equal(df1_write_int16(h, 1, "N7:1", &v, 1), 1);
	df1_free(h);
	peer_join(&p);
	assert_int_equal(p.forward_closes, 1);
	assert_int_equal(p.unregisters, 1);
}

/* Forward Open refused (general status 01, extended 0113h): the open fails
 * with DF1_E_CIP naming both, and nothing is left open. */
static void s_fwd_refused(struct peer *p)
{
	struct msg m;
	uint8_t cip[16], out[96];
	uint16_t ext = CIP_EXT_NO_MORE_CONNECTIONS;
	struct eip_packet rp;
	int cl, ol;

	if (!peer_open(p) || !peer_recv(p, &m))
		return;
	cl = cip_resp_build(cip, sizeof cip, CIP_SVC_FORWARD_OPEN, CIP_ST_CONNECTION_FAILURE, &ext, 1,
	                    NULL, 0);
	memset(&rp, 0, sizeof rp);
	rp.data = cip;
	rp.len = (size_t)cl;
	ol = eip_packet_build(out, sizeof out, SESSION, m.h.context, 0, &rp);
	peer_send(p, out, (size_t)ol);
	peer_drain(p);
}

static void test_eip_forward_open_refused(void **state)
{
	struct peer p;
	df1_t *h;
	char t[64];

	(void)state;
	peer_start(&p, s_fwd_refused);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_EIP_CONNECTED, 1), 0);
	snprintf(t, sizeof t, "eip://127.0.0.1:%d", p.port);
	assert_int_equal(df1_open(h, t), DF1_E_CIP);
	assert_non_null(strstr(df1_last_error(h)->message, "Forward Open failed"));
	assert_non_null(strstr(df1_last_error(h)->message, "0x01 (connection failure), extended 0x0113"));
	assert_false(df1_is_open(h));
	df1_free(h);
	peer_join(&p);
}

/* Connected: a reply on another connection id or with an old sequence count
 * is stale, dropped and counted; the one that matches is taken. */
static void s_connected_stale(struct peer *p)
{
	struct msg m;
	struct cip_fwd_open f;
	struct eip_pccc pc;
	uint8_t data[64], cip[96], out[200], r[16];
	struct eip_packet rp;
	uint32_t to;
	size_t n;
	int dl, cl, ol;

	if (!peer_open(p) || !peer_recv(p, &m) ||
	    cip_fwd_open_parse(&f, false, m.req.data, m.req.len) < 0)
		return;
	p->to_id = f.to_conn_id;
	f.ot_conn_id = OT_ID;
	dl = cip_fwd_open_reply_build(data, sizeof data, &f);
	cl = cip_resp_build(cip, sizeof cip, CIP_SVC_FORWARD_OPEN, 0, NULL, 0, data, (size_t)dl);
	memset(&rp, 0, sizeof rp);
	rp.data = cip;
	rp.len = (size_t)cl;
	ol = eip_packet_build(out, sizeof out, SESSION, m.h.context, 0, &rp);
	peer_send(p, out, (size_t)ol);
	if (!peer_recv(p, &m) || !peer_pccc_of(p, &m, &pc))
		return;
	n = peer_answer(p, &pc, 0, r);
	to = p->to_id;
	p->to_id = to ^ 0x1000u;           /* another connection */
	peer_reply(p, &m, &pc, 0, 0, r, n);
	p->to_id = to;
	m.p.seq = (uint16_t)(m.p.seq - 1); /* an older sequence count */
	peer_reply(p, &m, &pc, 0, 0, r, n);
	m.p.seq = (uint16_t)(m.p.seq + 1);
	peer_reply(p, &m, &pc, 0, 0, r, n);
	peer_drain(p);
}

static void test_eip_connected_stale(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 0;

	(void)state;
	peer_start(&p, s_connected_stale);
	h = client(&p, "", true);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), 1);
	assert_int_equal(v, 1234);
	assert_int_equal(counter(h, DF1_ID_CNT_STALE_MSGS_RCVD), 2);
	df1_free(h);
	peer_join(&p);
}

/* "/2": Unconnected Send, route path port 2 with the station as link address. */
static void s_routed(struct peer *p)
{
	struct msg m;
	struct eip_pccc pc;

	if (!peer_open(p) || !peer_serve_one(p, &m))
		return;
	/* the second: the station is not there (general status 01, 0204h) */
	if (!peer_recv(p, &m) || !peer_pccc_of(p, &m, &pc))
		return;
	peer_reply(p, &m, &pc, CIP_ST_CONNECTION_FAILURE, CIP_EXT_UNCONNECTED_TIMEOUT, NULL, 0);
	peer_drain(p);
}

static void test_eip_route_path(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 0;

	(void)state;
	peer_start(&p, s_routed);
	h = client(&p, "/2", false);
	assert_int_equal(df1_read_int16(h, 5, "N7:0", &v, 1), 1);
	assert_int_equal(v, 1234);
	assert_int_equal(p.route_station, 5);
	assert_int_equal(df1_read_int16(h, 9, "N7:0", &v, 1), DF1_E_CIP);
	assert_int_equal(p.route_station, 9);
	assert_non_null(strstr(df1_last_error(h)->message, "0x01 (connection failure)"));
	assert_non_null(strstr(df1_last_error(h)->message, "0x0204"));
	df1_free(h);
	peer_join(&p);
}

/* df1_link_test: a ListServices round trip. */
static void s_list_services(struct peer *p)
{
	struct msg m;
	uint8_t d[64];
	int n;

	if (!peer_open(p) || !peer_recv(p, &m))
		return;
	if (m.h.command != EIP_CMD_LIST_SERVICES) {
		peer_fail(p, "ListServices expected");
		return;
	}
	n = eip_services_build(d, sizeof d, EIP_SERVICE_CIP_TCP);
	peer_send_hdr(p, EIP_CMD_LIST_SERVICES, SESSION, 0, m.h.context, d, (size_t)n);
	peer_drain(p);
}

static void test_eip_link_test(void **state)
{
	struct peer p;
	df1_t *h;

	(void)state;
	peer_start(&p, s_list_services);
	h = client(&p, "", false);
	assert_int_equal(df1_link_test(h, 1), 0);
	df1_free(h);
	peer_join(&p);
}

static void s_register_refused(struct peer *p)
{
	struct msg m;

	if (!peer_accept(p) || !peer_recv(p, &m))
		return;
	peer_send_hdr(p, EIP_CMD_REGISTER_SESSION, 0, EIP_ST_UNSUPPORTED_VERSION, m.h.context, NULL, 0);
	peer_drain(p);
}

static void test_eip_register_refused(void **state)
{
	struct peer p;
	df1_t *h;
	char t[64];

	(void)state;
	peer_start(&p, s_register_refused);
	assert_int_equal(df1_new(&h), 0);
	snprintf(t, sizeof t, "eip://127.0.0.1:%d", p.port);
	assert_int_equal(df1_open(h, t), DF1_E_EIP);
	assert_non_null(strstr(df1_last_error(h)->message, "0x0069 (unsupported protocol version)"));
	assert_false(df1_is_open(h));
	df1_free(h);
	peer_join(&p);
}

/* ListIdentity over TCP. */
static void s_identity(struct peer *p)
{
	struct msg m;
	struct eip_identity id;
	uint8_t d[128];
	int n;

	if (!peer_accept(p) || !peer_recv(p, &m))
		return;
	if (m.h.command != EIP_CMD_LIST_IDENTITY || m.h.length != 0) {
		peer_fail(p, "ListIdentity expected");
		return;
	}
	memset(&id, 0, sizeof id);
	id.encap_version = 1;
	id.sin_family = AF_INET;
	id.sin_port = (uint16_t)p->port;
	id.sin_addr = 0x7F000001;
	id.vendor_id = 1234;
	id.device_type = 14;
	id.product_code = 90;
	id.rev_major = 2;
	id.rev_minor = 7;
	id.status = 0x0030;
	id.serial = 0xC0FFEE01;
	strcpy(id.product_name, "test device");
	id.state = 3;
	n = eip_identity_build(d, sizeof d, &id);
	peer_send_hdr(p, EIP_CMD_LIST_IDENTITY, 0, 0, m.h.context, d, (size_t)n);
	peer_drain(p);
}

static struct df1_eip_device seen;
static void on_device(void *user, const struct df1_eip_device *d)
{
	(*(int *)user)++;
	seen = *d;
}

static void test_eip_list_identity_tcp(void **state)
{
	struct peer p;
	df1_t *h;
	char t[64], addr[64];
	int calls = 0;

	(void)state;
	peer_start(&p, s_identity);
	assert_int_equal(df1_new(&h), 0);
	snprintf(t, sizeof t, "eip://127.0.0.1:%d", p.port);
	assert_int_equal(df1_eip_list_identity(h, t, 2000, on_device, &calls), 1);
	assert_int_equal(calls, 1);
	snprintf(addr, sizeof addr, "127.0.0.1:%d", p.port);
	assert_string_equal(seen.address, addr);
	assert_int_equal(seen.vendor_id, 1234);
	assert_int_equal(seen.device_type, 14);
	assert_int_equal(seen.product_code, 90);
	assert_int_equal(seen.rev_major, 2);
	assert_int_equal(seen.rev_minor, 7);
	assert_int_equal(seen.serial, 0xC0FFEE01);
	assert_string_equal(seen.product_name, "test device");
	assert_int_equal(seen.state, 3);
	assert_false(df1_is_open(h));
	df1_free(h);
	peer_join(&p);
}

/* ListIdentity by UDP broadcast: a responder bound to a local interface's
 * broadcast address (it listens on no unicast address) answers twice, from
 * loopback, as two devices would; both are reported. The one datagram also
 * goes out on that interface, to an ephemeral port that no EtherNet/IP
 * device listens on. Skipped where no interface has a broadcast address. */
struct udp_peer {
	int rx, tx;
	bool failed;
};

static void *udp_main(void *arg)
{
	struct udp_peer *u = arg;
	struct pollfd pf = { u->rx, POLLIN, 0 };
	struct sockaddr_in from;
	socklen_t fl = sizeof from;
	uint8_t req[64], d[128], out[200];
	struct eip_hdr h;
	struct eip_identity id;
	ssize_t n;

	if (poll(&pf, 1, PEER_WAIT_MS) != 1 ||
	    (n = recvfrom(u->rx, req, sizeof req, 0, (struct sockaddr *)&from, &fl)) != EIP_HDR_LEN ||
	    eip_hdr_parse(&h, req, (size_t)n) < 0 || h.command != EIP_CMD_LIST_IDENTITY) {
		u->failed = true;
		return NULL;
	}
	for (int i = 0; i < 2; i++) {
		int dl;

		memset(&id, 0, sizeof id);
		id.encap_version = 1;
		id.sin_family = AF_INET;
		id.sin_port = 44818;
		id.vendor_id = 77;
		id.serial = 0x100u + (uint32_t)i;
		snprintf(id.product_name, sizeof id.product_name, "device %d", i);
		dl = eip_identity_build(d, sizeof d, &id);
		h.length = (uint16_t)dl;
		eip_hdr_build(out, sizeof out, &h);
		memcpy(out + EIP_HDR_LEN, d, (size_t)dl);
		if (sendto(u->tx, out, EIP_HDR_LEN + (size_t)dl, 0, (struct sockaddr *)&from, fl) < 0)
			u->failed = true;
	}
	return NULL;
}

static int udp_seen;
static uint32_t udp_serials;
static void on_udp_device(void *user, const struct df1_eip_device *d)
{
	(void)user;
	udp_seen++;
	udp_serials |= 1u << (d->serial & 0x1F);
	assert_string_equal(d->address, "127.0.0.1:44818");
}

static void test_eip_list_identity_udp_broadcast(void **state)
{
	struct ifaddrs *ifs, *i;
	struct sockaddr_in brd, lo;
	struct udp_peer u = { -1, -1, false };
	socklen_t al = sizeof brd;
	bool have = false;
	pthread_t t;
	char target[64], ip[INET_ADDRSTRLEN];
	df1_t *h;

	(void)state;
	assert_int_equal(getifaddrs(&ifs), 0);
	for (i = ifs; i && !have; i = i->ifa_next)
		if ((i->ifa_flags & IFF_BROADCAST) && (i->ifa_flags & IFF_UP) && i->ifa_broadaddr &&
		    i->ifa_broadaddr->sa_family == AF_INET) {
			memcpy(&brd, i->ifa_broadaddr, sizeof brd);
			have = true;
		}
	freeifaddrs(ifs);
	if (!have) {
		skip();
		return;
	}
	brd.sin_port = 0;
	u.rx = socket(AF_INET, SOCK_DGRAM, 0);
	u.tx = socket(AF_INET, SOCK_DGRAM, 0);
	if (bind(u.rx, (struct sockaddr *)&brd, sizeof brd) < 0) {
		close(u.rx);
		close(u.tx);
		skip();
		return;
	}
	assert_int_equal(getsockname(u.rx, (struct sockaddr *)&brd, &al), 0);
	memset(&lo, 0, sizeof lo);
	lo.sin_family = AF_INET;
	lo.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(bind(u.tx, (struct sockaddr *)&lo, sizeof lo), 0);
	assert_int_equal(pthread_create(&t, NULL, udp_main, &u), 0);
	inet_ntop(AF_INET, &brd.sin_addr, ip, sizeof ip);
	snprintf(target, sizeof target, "eip://%s:%d", ip, ntohs(brd.sin_port));
	assert_int_equal(df1_new(&h), 0);
	udp_seen = 0;
	udp_serials = 0;
	assert_int_equal(df1_eip_list_identity(h, target, 1000, on_udp_device, NULL), 2);
	pthread_join(t, NULL);
	assert_false(u.failed);
	assert_int_equal(udp_seen, 2);
	assert_int_equal(udp_serials, 3u);
	df1_free(h);
	close(u.rx);
	close(u.tx);
}

/* Targets: syntax, unknown host, refused port, listen only; serial-only
 * settings are ignored (a half-duplex setting does not make it poll). */
static void test_eip_targets(void **state)
{
	df1_t *h;
	int lfd, port;
	struct sockaddr_in a;
	socklen_t al = sizeof a;
	char t[64];

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_open(h, "eip://[::1"), DF1_E_INVAL);
	assert_int_equal(df1_open(h, "eip://host/3"), DF1_E_INVAL);
	assert_non_null(strstr(df1_last_error(h)->message, "only /2"));
	assert_int_equal(df1_open(h, "eip://host:0"), DF1_E_INVAL);
	assert_int_equal(df1_open(h, "eip://no-such-host.invalid"), DF1_E_NODEV);
	/* a port nobody listens on: bound, closed */
	lfd = socket(AF_INET, SOCK_STREAM, 0);
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(bind(lfd, (struct sockaddr *)&a, sizeof a), 0);
	assert_int_equal(getsockname(lfd, (struct sockaddr *)&a, &al), 0);
	port = ntohs(a.sin_port);
	close(lfd);
	snprintf(t, sizeof t, "EIP://127.0.0.1:%d", port);
	assert_int_equal(df1_open(h, t), DF1_E_SYS);
	assert_int_equal(df1_set_option(h, DF1_OPT_EIP_CONNECTED, 1), 0);
	snprintf(t, sizeof t, "eip://127.0.0.1:%d/2", port);
	assert_int_equal(df1_open(h, t), DF1_E_NOTSUP);
	assert_int_equal(df1_set_option(h, DF1_OPT_EIP_CONNECTED, 0), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_LISTEN_ONLY, 1), 0);
	assert_int_equal(df1_open(h, t), DF1_E_NOTSUP);
	assert_int_equal(df1_get_option(h, DF1_OPT_EIP_CONNECTED), 0);
	df1_free(h);
}

static void test_eip_half_duplex_setting_ignored(void **state)
{
	struct peer p;
	df1_t *h;
	int16_t v = 0;
	char t[64];

	(void)state;
	peer_start(&p, s_read_one);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_duplex(h, DF1_HALF_DUPLEX_SLAVE), 0);
	assert_int_equal(df1_set_check(h, DF1_CHECK_BCC), 0);
	snprintf(t, sizeof t, "eip://127.0.0.1:%d/", p.port);
	assert_int_equal(df1_open(h, t), 0);
	assert_int_equal(df1_read_int16(h, 1, "N7:0", &v, 1), 1);
	assert_int_equal(v, 1234);
	df1_free(h);
	peer_join(&p);
}

static void test_eip_status_texts(void **state)
{
	(void)state;
	assert_string_equal(link_eip_status_text(EIP_ST_INVALID_LENGTH), "invalid length");
	assert_string_equal(link_eip_status_text(0x1234), "unknown status");
	assert_string_equal(link_cip_status_text(CIP_ST_PATH_DESTINATION), "path destination unknown");
	assert_string_equal(df1_errname(DF1_E_EIP), "DF1_E_EIP");
	assert_string_equal(df1_strerror(DF1_E_CIP), "CIP error status");
	assert_false(df1_error_unexecuted(DF1_E_EIP));
	assert_false(df1_error_unexecuted(DF1_E_CIP));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_eip_read_write),
		cmocka_unit_test(test_eip_stale_replies_dropped),
		cmocka_unit_test(test_eip_encapsulation_status),
		cmocka_unit_test(test_eip_cip_status),
		cmocka_unit_test(test_eip_pccc_sts_is_remote),
		cmocka_unit_test(test_eip_timeout),
		cmocka_unit_test(test_eip_oversized_message),
		cmocka_unit_test(test_eip_truncated_cpf),
		cmocka_unit_test(test_eip_invalid_session_reregisters),
		cmocka_unit_test(test_eip_peer_closes_read_retried),
		cmocka_unit_test(test_eip_peer_closes_write_not_resent),
		cmocka_unit_test(test_eip_idle_close_write_once),
		cmocka_unit_test(test_eip_connected),
		cmocka_unit_test(test_eip_forward_open_refused),
		cmocka_unit_test(test_eip_connected_stale),
		cmocka_unit_test(test_eip_route_path),
		cmocka_unit_test(test_eip_link_test),
		cmocka_unit_test(test_eip_register_refused),
		cmocka_unit_test(test_eip_list_identity_tcp),
		cmocka_unit_test(test_eip_list_identity_udp_broadcast),
		cmocka_unit_test(test_eip_targets),
		cmocka_unit_test(test_eip_half_duplex_setting_ignored),
		cmocka_unit_test(test_eip_status_texts),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
