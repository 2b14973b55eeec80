/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_eip - the EtherNet/IP server's parsing and its connection's state
 * machine (lib/eip/eip_codec.c, eip_session.c): encapsulation header, CPF, CIP
 * requests and paths, Execute PCCC, Forward Open / Close, Unconnected Send,
 * sessions and connections across messages.
 * Input: byte 0 options (bit 0: the messages came over UDP; bit 1: answer
 * PCCC requests with a CIP error instead of a reply), then encapsulation
 * messages one after another, each cut by its own length field as the server
 * cuts them (a length over EIP_SESSION_MSG_MAX: its header alone, and the end).
 * Properties: every reply is a whole message whose length field is its
 * length, with the request's command and sender context; a SendRRData /
 * SendUnitData reply with status 0 holds a CPF packet with a CIP reply; a
 * PCCC request handed on lies inside its message, with a requester ID of 7 to
 * EIP_REQID_MAX bytes, and its reply parses back to the same requester ID and
 * PCCC bytes; parsed fields lie inside their input and rebuild to the same
 * bytes (Forward Open, Forward Close, Unconnected Send; ListIdentity parses back
 * to the same fields).
 */
#include "fuzz.h"

#include <string.h>

#include "eip/eip_codec.h"
#include "eip/eip_session.h"

static const struct eip_identity fuzz_id = { 1, 2, 44818, 0x7F000001, 0, 0x0E, 0, 0, 4, 0, 1,
                                             "libdf1 fuzz", 3 };

static bool inside(const uint8_t *p, size_t n, const uint8_t *base, size_t len)
{
	return n == 0 || (p >= base && p + n <= base + len);
}

/* The codec on its own: what parses lies inside and rebuilds the same. */
static void codec(const uint8_t *d, size_t n)
{
	struct cip_req r;
	struct cip_path p;
	struct cip_fwd_open fo, fo2;
	struct cip_fwd_close fc;
	struct cip_unconnected u;
	struct eip_identity id;
	struct eip_pccc pc;
	uint8_t out[1200];
	int k;

	if (cip_req_parse(&r, d, n) == 0) {
		FUZZ_CHECK(inside(r.path, r.path_len, d, n) && inside(r.data, r.len, d, n), "request outside input");
		if (cip_path_parse(&p, r.path, r.path_len) == 0) {
			k = cip_path_build(out, sizeof out, &p);
			FUZZ_CHECK(k >= 0 || k == DF1_E_INVAL, "path build %d", k);
		}
		for (int large = 0; large < 2; large++) {
			if (cip_fwd_open_parse(&fo, large, r.data, r.len) != 0)
				continue;
			FUZZ_CHECK(inside(fo.path, fo.path_len, r.data, r.len), "connection path outside");
			k = cip_fwd_open_build(out, sizeof out, &fo);
			FUZZ_CHECK(k > 6 && cip_req_parse(&r, out, (size_t)k) == 0, "forward open rebuild %d", k);
			FUZZ_CHECK(cip_fwd_open_parse(&fo2, large, r.data, r.len) == 0 && fo2.ot_rpi == fo.ot_rpi &&
			           fo2.to_params == fo.to_params && fo2.path_len == fo.path_len &&
			           memcmp(fo2.path, fo.path, fo.path_len) == 0, "forward open round trip");
			return;
		}
		if (cip_fwd_close_parse(&fc, r.data, r.len) == 0) {
			k = cip_fwd_close_build(out, sizeof out, &fc);
			FUZZ_CHECK(k > 0 && (size_t)k == 6 + r.len && memcmp(out + 6, r.data, 10) == 0 &&
			           memcmp(out + 6 + 12, fc.path, fc.path_len) == 0, "forward close rebuild");
		}
		if (cip_unconnected_parse(&u, r.data, r.len) == 0) {
			FUZZ_CHECK(inside(u.req, u.req_len, r.data, r.len) && inside(u.route, u.route_len, r.data, r.len),
			           "unconnected send parts outside");
			k = cip_unconnected_build(out, sizeof out, u.tick, u.timeout_ticks, u.req, u.req_len, u.route,
			                          u.route_len);
			FUZZ_CHECK(k > 0 && (size_t)k == 6 + r.len && memcmp(out + 6 + 4, u.req, u.req_len) == 0,
			           "unconnected send rebuild %d of %zu", k, r.len);
		}
		if (eip_pccc_parse(&pc, r.data, r.len) == 0)
			FUZZ_CHECK(pc.reqid_len >= 7 && pc.len >= 4 && inside(pc.pccc, pc.len, r.data, r.len),
			           "pccc parts");
	}
	if (eip_identity_parse(&id, d, n) == 0) {
		struct eip_identity id2;

		/* the name stops at a NUL and sin_zero is not kept: parse -> build -> parse */
		size_t nl = strlen(id.product_name);

		memset(id.product_name + nl, 0, sizeof id.product_name - nl);
		k = eip_identity_build(out, sizeof out, &id);
		FUZZ_CHECK(k > 6 && (size_t)k - 6 <= n && eip_identity_parse(&id2, out + 6, (size_t)k - 6) == 0 &&
		           memcmp(&id, &id2, sizeof id) == 0, "identity round trip differs");
	}
}

/* A reply message: whole, the request's command and context. */
static void check_reply(const uint8_t *out, size_t n, const struct eip_hdr *req)
{
	struct eip_hdr h;
	struct eip_cpf cpf;
	struct eip_packet pk;
	struct cip_resp r;
	uint16_t t;

	FUZZ_CHECK(n >= EIP_HDR_LEN && eip_hdr_parse(&h, out, n) == 0, "reply of %zu bytes", n);
	FUZZ_CHECK(h.length + (size_t)EIP_HDR_LEN == n, "reply length %u of %zu", h.length, n);
	FUZZ_CHECK(h.command == req->command, "reply command %04X to %04X", h.command, req->command);
	FUZZ_CHECK(memcmp(h.context, req->context, 8) == 0, "sender context not echoed");
	if (h.status != 0 || (h.command != EIP_CMD_SEND_RR_DATA && h.command != EIP_CMD_SEND_UNIT_DATA))
		return;
	FUZZ_CHECK(eip_rr_parse(&t, &cpf, out + EIP_HDR_LEN, h.length) == 0 && eip_packet_parse(&pk, &cpf) == 0,
	           "reply CPF does not parse");
	FUZZ_CHECK(cip_resp_parse(&r, pk.data, pk.len) == 0, "reply CIP does not parse");
}

static void pccc_pending(const struct eip_pending *p, const uint8_t *msg, size_t n, const struct eip_hdr *h,
                         bool fail)
{
	uint8_t out[EIP_SESSION_MSG_MAX + 64], rep[8];
	struct eip_hdr rh;
	struct eip_cpf cpf;
	struct eip_packet pk;
	struct cip_resp r;
	struct eip_pccc pc;
	uint16_t t;
	int k;

	FUZZ_CHECK(inside(p->pccc, p->len, msg, n) && p->len >= 4, "PCCC request outside its message");
	FUZZ_CHECK(p->reqid_len >= 7 && p->reqid_len <= EIP_REQID_MAX, "requester ID of %zu", p->reqid_len);
	FUZZ_CHECK(p->station >= -1 && p->station <= 254, "station %d", p->station);
	rep[0] = (uint8_t)(p->pccc[0] | 0x40);
	rep[1] = 0;
	rep[2] = p->pccc[2];
	rep[3] = p->pccc[3];
	k = eip_session_reply(p, fail ? 0x01 : 0, fail ? 0x0204 : 0, rep, fail ? 0 : 4, out, sizeof out);
	FUZZ_CHECK(k > 0, "PCCC reply build %d", k);
	check_reply(out, (size_t)k, h);
	FUZZ_CHECK(eip_hdr_parse(&rh, out, (size_t)k) == 0 && eip_rr_parse(&t, &cpf, out + 24, rh.length) == 0 &&
	           eip_packet_parse(&pk, &cpf) == 0 && cip_resp_parse(&r, pk.data, pk.len) == 0, "PCCC reply parse");
	FUZZ_CHECK(pk.connected == p->connected, "PCCC reply connected %d", pk.connected);
	if (fail) {
		FUZZ_CHECK(r.status == 0x01 && r.ext0 == 0x0204, "PCCC failure status %02X", r.status);
		return;
	}
	FUZZ_CHECK(r.service == 0xCB && r.status == 0, "PCCC reply service %02X", r.service);
	FUZZ_CHECK(eip_pccc_parse(&pc, r.data, r.len) == 0 && pc.reqid_len == p->reqid_len &&
	           memcmp(pc.reqid, p->reqid, p->reqid_len) == 0 && pc.len == 4 && memcmp(pc.pccc, rep, 4) == 0,
	           "PCCC reply does not carry the requester ID and reply");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static uint8_t out[EIP_SESSION_MSG_MAX + 64];
	struct fuzz_in in = { data, size };
	struct eip_session s;
	uint8_t opt = fuzz_byte(&in);
	bool udp = opt & 1, fail = opt & 2;

	eip_session_init(&s, 0x00010203);
	while (in.n >= EIP_HDR_LEN) {
		struct eip_pending pend;
		struct eip_hdr h;
		size_t need = eip_msg_len(in.p, in.n), got, out_len = 0;
		const uint8_t *msg;
		enum eip_verdict v;
		int conns = 0;

		if (need > EIP_SESSION_MSG_MAX)
			need = EIP_HDR_LEN;     /* the server answers on the header and closes */
		else if (need > in.n)
			break;
		msg = fuzz_take(&in, need, &got);
		FUZZ_CHECK(eip_hdr_parse(&h, msg, got) == 0, "header");
		if (h.length == got - EIP_HDR_LEN)
			codec(msg + EIP_HDR_LEN + (h.length >= 16 ? 16 : 0), h.length >= 16 ? h.length - 16u : h.length);
		v = eip_session_input(&s, &fuzz_id, udp, msg, got, out, sizeof out, &out_len, &pend);
		for (int i = 0; i < EIP_SESSION_CONNS; i++)
			conns += s.conn[i].used;
		FUZZ_CHECK(conns <= EIP_SESSION_CONNS, "connections %d", conns);
		if (v == EIP_SEND || v == EIP_SEND_CLOSE) {
			FUZZ_CHECK(out_len <= sizeof out, "reply of %zu", out_len);
			check_reply(out, out_len, &h);
		} else {
			FUZZ_CHECK(out_len == 0, "no reply but %zu bytes", out_len);
		}
		FUZZ_CHECK(!udp || v == EIP_SEND || v == EIP_SILENT || v == EIP_SEND_CLOSE, "UDP verdict %d", v);
		if (v == EIP_PCCC)
			pccc_pending(&pend, msg, got, &h, fail);
		if (v == EIP_SEND_CLOSE || v == EIP_CLOSE)
			break;
	}
	return 0;
}
