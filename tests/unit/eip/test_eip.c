/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_eip.c - the EtherNet/IP / CIP codec (lib/eip/eip_codec.c) against byte
 * vectors written by hand from the layouts of df1-eip(7) (ODVA Vol. 2 ch. 2-3
 * encapsulation and CPF, Vol. 1 ch. 3 Connection Manager and appendix C EPATH,
 * Rockwell 1756-PM020 for Execute PCCC), both directions.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "df1.h"
#include "eip/eip_codec.h"
#include "eip/eip_session.h"

/* "65 00 04" -> bytes */
static size_t hex(const char *s, uint8_t *out, size_t cap)
{
	size_t n = 0;

	while (*s) {
		char *end;
		unsigned long v;

		if (*s == ' ' || *s == '|') {
			s++;
			continue;
		}
		v = strtoul(s, &end, 16);
		assert_true(end == s + 2 && v <= 0xFF && n < cap);
		out[n++] = (uint8_t)v;
		s = end;
	}
	return n;
}

static void assert_bytes(const uint8_t *got, int got_len, const char *expect_hex)
{
	uint8_t e[600];
	size_t n = hex(expect_hex, e, sizeof e);

	assert_int_equal(got_len, (int)n);
	assert_memory_equal(got, e, n);
}

static uint32_t le32_of(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static const uint8_t ctx[8] = { 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88 };

/* ------------------------------------------------------------------------
 * Header, RegisterSession
 * ------------------------------------------------------------------------ */

static void test_eip_register_session_request_both_ways(void **state)
{
	uint8_t out[64], in[64];
	struct eip_hdr h = { EIP_CMD_REGISTER_SESSION, 4, 0, 0, { 0 }, 0 }, p;
	uint16_t ver, opt;
	size_t n;
	(void)state;

	memcpy(h.context, ctx, 8);
	assert_int_equal(eip_hdr_build(out, sizeof out, &h), 24);
	assert_int_equal(eip_register_build(out + 24, sizeof out - 24, EIP_PROTOCOL_VERSION, 0), 4);
	assert_bytes(out, 28, "65 00 04 00 | 00 00 00 00 | 00 00 00 00 | 11 22 33 44 55 66 77 88 | 00 00 00 00"
	                      " | 01 00 00 00");
	/* a reply with session handle 0x0102ABCD and status 0 */
	n = hex("65 00 04 00 CD AB 02 01 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 01 00 00 00", in,
	        sizeof in);
	assert_int_equal(eip_msg_len(in, n), 28);
	assert_int_equal(eip_hdr_parse(&p, in, n), 0);
	assert_int_equal(p.command, EIP_CMD_REGISTER_SESSION);
	assert_int_equal(p.length, 4);
	assert_int_equal(p.session, 0x0102ABCD);
	assert_int_equal(p.status, 0);
	assert_memory_equal(p.context, ctx, 8);
	assert_int_equal(eip_register_parse(&ver, &opt, in + 24, 4), 0);
	assert_int_equal(ver, 1);
	assert_int_equal(opt, 0);
	assert_int_equal(eip_register_parse(&ver, &opt, in + 24, 3), DF1_E_TOO_SHORT);
	assert_int_equal(eip_register_parse(&ver, &opt, in + 24, 5), DF1_E_TOO_LONG);
	assert_int_equal(eip_hdr_parse(&p, in, 23), DF1_E_TOO_SHORT);
	assert_int_equal(eip_msg_len(in, 23), 0);
	assert_int_equal(eip_hdr_build(out, 23, &h), DF1_E_NOSPACE);
	/* the length field is little-endian: FF FF = 65535 data bytes */
	in[2] = 0xFF;
	in[3] = 0xFF;
	assert_int_equal(eip_msg_len(in, 24), 24 + 65535);
}

/* ------------------------------------------------------------------------
 * CPF, SendRRData, SendUnitData
 * ------------------------------------------------------------------------ */

/* Execute PCCC of an SLC read of N7:0, 2 words (0F A2), in SendRRData:
 * interface 0, timeout 10, 2 items (null, B2 of 25 bytes). */
#define RR_PCCC_READ \
	"6F 00 27 00 | 04 03 02 01 | 00 00 00 00 | 11 22 33 44 55 66 77 88 | 00 00 00 00 |" \
	" 00 00 00 00 | 0A 00 | 02 00 | 00 00 00 00 | B2 00 17 00 |" \
	" 4B 02 20 67 24 01 | 07 4D 00 78 56 34 12 | 0F 00 34 12 A2 04 07 89 00 00"

static void test_eip_send_rr_data_pccc_both_ways(void **state)
{
	uint8_t in[128], out[128], cip[64];
	struct eip_hdr h;
	struct eip_cpf c;
	struct eip_packet pk;
	struct cip_req r;
	struct cip_path path;
	struct eip_pccc pc;
	uint16_t timeout;
	size_t n = hex(RR_PCCC_READ, in, sizeof in);
	int cl;
	(void)state;

	assert_int_equal(n, 24 + 0x27);
	assert_int_equal(eip_hdr_parse(&h, in, n), 0);
	assert_int_equal(h.command, EIP_CMD_SEND_RR_DATA);
	assert_int_equal(eip_rr_parse(&timeout, &c, in + 24, h.length), 0);
	assert_int_equal(timeout, 10);
	assert_int_equal(c.count, 2);
	assert_int_equal(eip_packet_parse(&pk, &c), 0);
	assert_false(pk.connected);
	assert_int_equal(pk.len, 23);
	assert_int_equal(cip_req_parse(&r, pk.data, pk.len), 0);
	assert_int_equal(r.service, CIP_SVC_EXECUTE_PCCC);
	assert_int_equal(r.path_len, 4);
	assert_int_equal(cip_path_parse(&path, r.path, r.path_len), 0);
	assert_int_equal(path.class_id, CIP_CLASS_PCCC);
	assert_int_equal(path.instance, 1);
	assert_int_equal(path.port, CIP_NONE);
	assert_int_equal(eip_pccc_parse(&pc, r.data, r.len), 0);
	assert_int_equal(pc.reqid_len, 7);
	assert_bytes(pc.pccc, (int)pc.len, "0F 00 34 12 A2 04 07 89 00 00");

	/* the same message built */
	cl = eip_pccc_request_build(cip, sizeof cip, 0x004D, 0x12345678, pc.pccc, pc.len);
	assert_bytes(cip, cl, "4B 02 20 67 24 01 07 4D 00 78 56 34 12 0F 00 34 12 A2 04 07 89 00 00");
	pk.data = cip;
	pk.len = (size_t)cl;
	assert_int_equal(eip_packet_build(out, sizeof out, 0x01020304, ctx, 10, &pk), (int)n);
	assert_memory_equal(out, in, n);
	assert_int_equal(eip_packet_build(out, n - 1, 0x01020304, ctx, 10, &pk), DF1_E_NOSPACE);
}

static void test_eip_send_unit_data_both_ways(void **state)
{
	uint8_t in[128], out[128];
	struct eip_cpf c;
	struct eip_packet pk;
	uint16_t timeout;
	size_t n = hex("70 00 1A 00 04 03 02 01 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 |"
	               " 00 00 00 00 00 00 02 00 | A1 00 04 00 EF BE AD DE | B1 00 06 00 05 00 |"
	               " 4B 02 20 67", in, sizeof in);
	(void)state;

	assert_int_equal(eip_rr_parse(&timeout, &c, in + 24, n - 24), 0);
	assert_int_equal(eip_packet_parse(&pk, &c), 0);
	assert_true(pk.connected);
	assert_int_equal(pk.conn_id, 0xDEADBEEF);
	assert_int_equal(pk.seq, 5);
	assert_bytes(pk.data, (int)pk.len, "4B 02 20 67");
	assert_int_equal(eip_packet_build(out, sizeof out, 0x01020304, ctx, 0, &pk), (int)n);
	assert_memory_equal(out, in, n);
}

static void test_eip_cpf_bounds(void **state)
{
	uint8_t in[64];
	struct eip_cpf c;
	struct eip_packet pk;
	uint16_t t;
	size_t n;
	(void)state;

	/* an item length past the end */
	n = hex("02 00 00 00 00 00 B2 00 09 00 01 02", in, sizeof in);
	assert_int_equal(eip_cpf_parse(&c, in, n), DF1_E_TOO_SHORT);
	/* a byte after the last item */
	n = hex("02 00 00 00 00 00 B2 00 01 00 01 02", in, sizeof in);
	assert_int_equal(eip_cpf_parse(&c, in, n), DF1_E_TOO_LONG);
	/* an item header cut */
	n = hex("02 00 00 00 00 00 B2 00", in, sizeof in);
	assert_int_equal(eip_cpf_parse(&c, in, n), DF1_E_TOO_SHORT);
	/* too many items */
	n = hex("05 00", in, sizeof in);
	assert_int_equal(eip_cpf_parse(&c, in, n), DF1_E_TOO_LONG);
	assert_int_equal(eip_cpf_parse(&c, in, 1), DF1_E_TOO_SHORT);
	/* one item only: no packet */
	n = hex("01 00 B2 00 00 00", in, sizeof in);
	assert_int_equal(eip_cpf_parse(&c, in, n), 0);
	assert_int_equal(eip_packet_parse(&pk, &c), DF1_E_TOO_SHORT);
	/* A1 with B2: not a pair the specification allows */
	n = hex("02 00 A1 00 04 00 01 00 00 00 B2 00 00 00", in, sizeof in);
	assert_int_equal(eip_cpf_parse(&c, in, n), 0);
	assert_int_equal(eip_packet_parse(&pk, &c), DF1_E_INVAL);
	/* a sockaddr item after the pair is allowed */
	n = hex("03 00 00 00 00 00 B2 00 01 00 AA 00 80 10 00 00 02 AF 12 7F 00 00 01 00 00 00 00 00 00 00 00",
	        in, sizeof in);
	assert_int_equal(eip_cpf_parse(&c, in, n), 0);
	assert_int_equal(eip_packet_parse(&pk, &c), 0);
	assert_int_equal(pk.len, 1);
	/* interface handle must be 0 */
	n = hex("01 00 00 00 00 00 00 00", in, sizeof in);
	assert_int_equal(eip_rr_parse(&t, &c, in, n), DF1_E_INVAL);
	assert_int_equal(eip_rr_parse(&t, &c, in, 5), DF1_E_TOO_SHORT);
}

/* ------------------------------------------------------------------------
 * ListIdentity, ListServices
 * ------------------------------------------------------------------------ */

static void test_eip_list_identity_both_ways(void **state)
{
	struct eip_identity id, back;
	uint8_t out[128];
	int n;
	(void)state;

	memset(&id, 0, sizeof id);
	id.encap_version = 1;
	id.sin_family = 2;
	id.sin_port = 44818;
	id.sin_addr = 0x7F000001;
	id.vendor_id = 0xFFFF;
	id.device_type = 0x0E;
	id.product_code = 0x0102;
	id.rev_major = 0;
	id.rev_minor = 4;
	id.status = 0x0030;
	id.serial = 0x01020304;
	strcpy(id.product_name, "ABC");
	id.state = 3;
	n = eip_identity_build(out, sizeof out, &id);
	assert_bytes(out, n, "01 00 | 0C 00 25 00 | 01 00 | 00 02 AF 12 7F 00 00 01 00 00 00 00 00 00 00 00 |"
	                     " FF FF 0E 00 02 01 00 04 30 00 04 03 02 01 | 03 41 42 43 | 03");
	assert_int_equal(eip_identity_parse(&back, out + 6, (size_t)n - 6), 0);
	assert_memory_equal(&back, &id, sizeof id);
	assert_int_equal(eip_identity_parse(&back, out + 6, (size_t)n - 7), DF1_E_TOO_SHORT);
	assert_int_equal(eip_identity_build(out, (size_t)n - 1, &id), DF1_E_NOSPACE);
	/* a name of 33 characters is sent as its first 32 */
	memset(id.product_name, 'x', 32);
	id.product_name[32] = '\0';
	n = eip_identity_build(out, sizeof out, &id);
	assert_int_equal(n, 6 + 34 + 32);
	assert_int_equal(out[6 + 32], 32);

	n = eip_services_build(out, sizeof out, EIP_SERVICE_CIP_TCP);
	assert_bytes(out, n, "01 00 00 01 14 00 01 00 20 00 43 6F 6D 6D 75 6E 69 63 61 74 69 6F 6E 73 00 00");
}

/* ------------------------------------------------------------------------
 * EPATH, message router request/response
 * ------------------------------------------------------------------------ */

static void test_cip_path_segments(void **state)
{
	struct cip_path p;
	uint8_t in[64], out[64];
	size_t n;
	(void)state;

	/* port 2 link 5, class 0x67, instance 1 */
	n = hex("02 05 20 67 24 01", in, sizeof in);
	assert_int_equal(cip_path_parse(&p, in, n), 0);
	assert_int_equal(p.port, 2);
	assert_int_equal(p.link, 5);
	assert_int_equal(p.class_id, 0x67);
	assert_int_equal(p.instance, 1);
	assert_int_equal(p.attribute, CIP_NONE);
	assert_bytes(out, cip_path_build(out, sizeof out, &p), "02 05 20 67 24 01");
	/* 16-bit class and instance (padded), attribute 8-bit */
	n = hex("21 00 34 12 25 00 00 01 30 07", in, sizeof in);
	assert_int_equal(cip_path_parse(&p, in, n), 0);
	assert_int_equal(p.class_id, 0x1234);
	assert_int_equal(p.instance, 0x100);
	assert_int_equal(p.attribute, 7);
	assert_bytes(out, cip_path_build(out, sizeof out, &p), "21 00 34 12 25 00 00 01 30 07");
	/* extended link address (an IP address text) then pad */
	n = hex("12 09 31 30 2E 30 2E 30 2E 31 30 00 20 02 24 01", in, sizeof in);
	assert_int_equal(cip_path_parse(&p, in, n), 0);
	assert_int_equal(p.port, 2);
	assert_int_equal(p.link, CIP_NONE);
	assert_int_equal(p.class_id, 2);
	/* electronic key then connection point */
	n = hex("34 04 00 00 00 00 00 00 00 00 20 02 24 01 2C 01", in, sizeof in);
	assert_int_equal(cip_path_parse(&p, in, n), 0);
	assert_int_equal(p.point, 1);
	/* errors: cut segment, unknown segment, two ports */
	n = hex("21 00 34", in, sizeof in);
	assert_int_equal(cip_path_parse(&p, in, n), DF1_E_TOO_SHORT);
	n = hex("E0 00", in, sizeof in);
	assert_int_equal(cip_path_parse(&p, in, n), DF1_E_INVAL);
	n = hex("01 00 02 05", in, sizeof in);
	assert_int_equal(cip_path_parse(&p, in, n), DF1_E_INVAL);
	n = hex("12 09 31", in, sizeof in);
	assert_int_equal(cip_path_parse(&p, in, n), DF1_E_TOO_SHORT);
}

static void test_cip_request_response(void **state)
{
	uint8_t in[64], out[64];
	struct cip_req r;
	struct cip_resp s;
	struct cip_path p;
	uint16_t ext = CIP_EXT_UNCONNECTED_TIMEOUT;
	size_t n;
	(void)state;

	cip_path_init(&p);
	p.class_id = 1;
	p.instance = 1;
	p.attribute = 7;
	assert_bytes(out, cip_req_build(out, sizeof out, CIP_SVC_GET_ATTRIBUTE_SINGLE, &p, NULL, 0),
	             "0E 03 20 01 24 01 30 07");
	n = hex("0E 03 20 01 24 01 30 07 AA", in, sizeof in);
	assert_int_equal(cip_req_parse(&r, in, n), 0);
	assert_int_equal(r.path_len, 6);
	assert_int_equal(r.len, 1);
	assert_int_equal(cip_req_parse(&r, in, 7), DF1_E_TOO_SHORT);
	assert_int_equal(cip_req_parse(&r, in, 1), DF1_E_TOO_SHORT);

	assert_bytes(out, cip_resp_build(out, sizeof out, CIP_SVC_UNCONNECTED_SEND, CIP_ST_CONNECTION_FAILURE,
	                                 &ext, 1, NULL, 0),
	             "D2 00 01 01 04 02");
	n = hex("D2 00 01 01 04 02", in, sizeof in);
	assert_int_equal(cip_resp_parse(&s, in, n), 0);
	assert_int_equal(s.service, 0xD2);
	assert_int_equal(s.status, 1);
	assert_int_equal(s.ext_words, 1);
	assert_int_equal(s.ext0, 0x0204);
	assert_int_equal(s.len, 0);
	assert_int_equal(cip_resp_parse(&s, in, 5), DF1_E_TOO_SHORT);
	in[0] = 0x52;
	assert_int_equal(cip_resp_parse(&s, in, n), DF1_E_INVAL);
}

/* ------------------------------------------------------------------------
 * Execute PCCC
 * ------------------------------------------------------------------------ */

static void test_eip_pccc_reply_and_requester_id(void **state)
{
	uint8_t in[64], out[64];
	struct cip_resp s;
	struct eip_pccc pc;
	size_t n;
	(void)state;

	/* the reply: CB 00 00 00, requester ID echoed, 4F 00 TNS data */
	n = hex("CB 00 00 00 07 4D 00 78 56 34 12 4F 00 34 12 01 00 02 00", in, sizeof in);
	assert_int_equal(cip_resp_parse(&s, in, n), 0);
	assert_int_equal(s.service, 0xCB);
	assert_int_equal(eip_pccc_parse(&pc, s.data, s.len), 0);
	assert_bytes(pc.pccc, (int)pc.len, "4F 00 34 12 01 00 02 00");
	/* built from its parts */
	n = (size_t)eip_pccc_build(out + 4, sizeof out - 4, 0x004D, 0x12345678, pc.pccc, pc.len);
	assert_bytes(out, cip_resp_build(out, sizeof out, CIP_SVC_EXECUTE_PCCC, 0, NULL, 0, out + 4, n),
	             "CB 00 00 00 07 4D 00 78 56 34 12 4F 00 34 12 01 00 02 00");
	/* a longer requester ID (9 bytes) is kept whole */
	n = hex("09 4D 00 78 56 34 12 AA BB 06 00 01 00 03", in, sizeof in);
	assert_int_equal(eip_pccc_parse(&pc, in, n), 0);
	assert_int_equal(pc.reqid_len, 9);
	assert_bytes(pc.pccc, (int)pc.len, "06 00 01 00 03");
	/* requester ID length under 7, or no room for CMD STS TNS */
	n = hex("06 4D 00 78 56 34 06 00 01 00", in, sizeof in);
	assert_int_equal(eip_pccc_parse(&pc, in, n), DF1_E_INVAL);
	n = hex("07 4D 00 78 56 34 12 06 00 01", in, sizeof in);
	assert_int_equal(eip_pccc_parse(&pc, in, n), DF1_E_TOO_SHORT);
	assert_int_equal(eip_pccc_parse(&pc, in, 0), DF1_E_TOO_SHORT);
}

/* ------------------------------------------------------------------------
 * Connection Manager
 * ------------------------------------------------------------------------ */

#define FWD_OPEN_REQ \
	"54 02 20 06 24 01 | 0A 0E | 00 00 00 00 | 78 56 34 12 | 01 00 | 4D 00 | 21 43 65 87 | 03 | 00 00 00 |" \
	" 40 42 0F 00 | F4 43 | 40 42 0F 00 | F4 43 | A3 | 03 | 01 00 20 02 24 01"

static void test_cip_forward_open_both_ways(void **state)
{
	uint8_t in[128], out[128];
	struct cip_req r;
	struct cip_fwd_open f, g;
	size_t n = hex(FWD_OPEN_REQ, in, sizeof in);
	(void)state;

	assert_int_equal(cip_req_parse(&r, in, n), 0);
	assert_int_equal(r.service, CIP_SVC_FORWARD_OPEN);
	assert_int_equal(cip_fwd_open_parse(&f, false, r.data, r.len), 0);
	assert_int_equal(f.tick, 0x0A);
	assert_int_equal(f.timeout_ticks, 0x0E);
	assert_int_equal(f.ot_conn_id, 0);
	assert_int_equal(f.to_conn_id, 0x12345678);
	assert_int_equal(f.conn_serial, 1);
	assert_int_equal(f.vendor_id, 0x4D);
	assert_int_equal(f.orig_serial, 0x87654321);
	assert_int_equal(f.timeout_mult, 3);
	assert_int_equal(f.ot_rpi, 1000000);
	assert_int_equal(f.ot_params, 0x43F4);
	assert_int_equal(f.to_params, 0x43F4);
	assert_int_equal(f.transport, 0xA3);
	assert_bytes(f.path, (int)f.path_len, "01 00 20 02 24 01");
	assert_int_equal(cip_fwd_open_build(out, sizeof out, &f), (int)n);
	assert_memory_equal(out, in, n);
	assert_int_equal(cip_fwd_open_parse(&f, false, r.data, r.len - 1), DF1_E_TOO_SHORT);
	assert_int_equal(cip_fwd_open_parse(&f, false, r.data, 10), DF1_E_TOO_SHORT);

	/* the Large Forward Open: 32-bit network parameters */
	assert_int_equal(cip_fwd_open_parse(&f, false, r.data, r.len), 0);
	f.large = true;
	f.ot_params = 0x42000FA2;
	f.to_params = 0x42000FA2;
	n = (size_t)cip_fwd_open_build(out, sizeof out, &f);
	assert_int_equal(n, 6 + 40 + 6);
	assert_int_equal(out[0], CIP_SVC_LARGE_FORWARD_OPEN);
	assert_bytes(out + 6 + 26, 4, "A2 0F 00 42");
	assert_int_equal(cip_fwd_open_parse(&g, true, out + 6, n - 6), 0);
	assert_int_equal(g.ot_params, 0x42000FA2);
	assert_int_equal(g.to_rpi, 1000000);
	assert_int_equal(g.transport, 0xA3);

	/* the reply: the target chose O->T id 0xCAFE0001 */
	f.ot_conn_id = 0xCAFE0001;
	assert_bytes(out, cip_fwd_open_reply_build(out, sizeof out, &f),
	             "01 00 FE CA 78 56 34 12 01 00 4D 00 21 43 65 87 40 42 0F 00 40 42 0F 00 00 00");
	assert_int_equal(cip_fwd_open_reply_parse(&g, out, 26), 0);
	assert_int_equal(g.ot_conn_id, 0xCAFE0001);
	assert_int_equal(g.to_conn_id, 0x12345678);
	assert_int_equal(g.orig_serial, 0x87654321);
	assert_int_equal(cip_fwd_open_reply_parse(&g, out, 25), DF1_E_TOO_SHORT);
	assert_bytes(out, cip_fwd_fail_build(out, sizeof out, 1, 0x4D, 0x87654321),
	             "01 00 4D 00 21 43 65 87 00 00");
}

static void test_cip_forward_close_both_ways(void **state)
{
	uint8_t in[64], out[64];
	struct cip_req r;
	struct cip_fwd_close f;
	size_t n = hex("4E 02 20 06 24 01 | 0A 0E | 01 00 | 4D 00 | 21 43 65 87 | 03 00 | 01 00 20 02 24 01",
	               in, sizeof in);
	(void)state;

	assert_int_equal(cip_req_parse(&r, in, n), 0);
	assert_int_equal(cip_fwd_close_parse(&f, r.data, r.len), 0);
	assert_int_equal(f.conn_serial, 1);
	assert_int_equal(f.vendor_id, 0x4D);
	assert_int_equal(f.orig_serial, 0x87654321);
	assert_int_equal(f.path_len, 6);
	assert_int_equal(cip_fwd_close_build(out, sizeof out, &f), (int)n);
	assert_memory_equal(out, in, n);
	assert_bytes(out, cip_fwd_close_reply_build(out, sizeof out, &f), "01 00 4D 00 21 43 65 87 00 00");
	assert_int_equal(cip_fwd_close_parse(&f, r.data, r.len - 2), DF1_E_TOO_SHORT);
	assert_int_equal(cip_fwd_close_parse(&f, r.data, 11), DF1_E_TOO_SHORT);
}

static void test_cip_unconnected_send_both_ways(void **state)
{
	uint8_t in[96], out[96], pccc[64];
	struct cip_req r;
	struct cip_unconnected u;
	struct cip_path p;
	int pl;
	/* an embedded request of 17 bytes (odd: a pad byte follows), route port 2 link 3 */
	size_t n = hex("52 02 20 06 24 01 | 0A 0E | 11 00 |"
	               " 4B 02 20 67 24 01 07 4D 00 78 56 34 12 01 00 01 00 | 00 | 01 00 | 02 03",
	               in, sizeof in);
	(void)state;

	assert_int_equal(cip_req_parse(&r, in, n), 0);
	assert_int_equal(r.service, CIP_SVC_UNCONNECTED_SEND);
	assert_int_equal(cip_unconnected_parse(&u, r.data, r.len), 0);
	assert_int_equal(u.req_len, 17);
	assert_int_equal(u.req[0], CIP_SVC_EXECUTE_PCCC);
	assert_int_equal(cip_path_parse(&p, u.route, u.route_len), 0);
	assert_int_equal(p.port, 2);
	assert_int_equal(p.link, 3);
	pl = eip_pccc_request_build(pccc, sizeof pccc, 0x4D, 0x12345678, (const uint8_t *)"\x06\x00\x01\x00\x03", 5);
	assert_int_equal(pl, 18);
	/* rebuild with an 18-byte embedded request: no pad then */
	assert_int_equal(cip_unconnected_build(out, sizeof out, 0x0A, 0x0E, pccc, (size_t)pl, u.route, u.route_len),
	                 6 + 4 + 18 + 2 + 2);
	assert_int_equal(cip_req_parse(&r, out, 32), 0);
	assert_int_equal(cip_unconnected_parse(&u, r.data, r.len), 0);
	assert_int_equal(u.req_len, 18);
	assert_bytes(u.route, (int)u.route_len, "02 03");
	/* the odd one built matches the vector */
	assert_int_equal(cip_unconnected_build(out, sizeof out, 0x0A, 0x0E, in + 10, 17, (const uint8_t *)"\x02\x03", 2),
	                 (int)n);
	assert_memory_equal(out, in, n);
	assert_int_equal(cip_unconnected_parse(&u, in + 6, n - 7), DF1_E_TOO_SHORT);
	assert_int_equal(cip_unconnected_parse(&u, in + 6, 20), DF1_E_TOO_SHORT);
}

static void test_cip_identity_attributes(void **state)
{
	struct eip_identity id;
	uint8_t out[64];
	(void)state;

	memset(&id, 0, sizeof id);
	id.vendor_id = 0xFFFF;
	id.device_type = 0x0E;
	id.product_code = 0x0102;
	id.rev_major = 0;
	id.rev_minor = 4;
	id.status = 0x0030;
	id.serial = 0x01020304;
	strcpy(id.product_name, "AB");
	assert_bytes(out, cip_identity_all_build(out, sizeof out, &id),
	             "FF FF 0E 00 02 01 00 04 30 00 04 03 02 01 02 41 42");
	assert_bytes(out, cip_identity_attr_build(out, sizeof out, &id, 6), "04 03 02 01");
	assert_bytes(out, cip_identity_attr_build(out, sizeof out, &id, 7), "02 41 42");
	assert_int_equal(cip_identity_attr_build(out, sizeof out, &id, 8), DF1_E_NOTSUP);
	assert_int_equal(cip_identity_all_build(out, 16, &id), DF1_E_NOSPACE);
}

/* ------------------------------------------------------------------------
 * The server connection's state machine (eip_session.c)
 * ------------------------------------------------------------------------ */

static const struct eip_identity sess_id = { 1, 2, 44818, 0x7F000001, 0, 0x0E, 0, 0, 4, 0, 9, "sim", 3 };

static enum eip_verdict feed(struct eip_session *s, const char *msg_hex, uint8_t *out, size_t *n,
                             struct eip_pending *p)
{
	uint8_t in[256];
	size_t len = hex(msg_hex, in, sizeof in);

	return eip_session_input(s, &sess_id, false, in, len, out, 512, n, p);
}

static void test_eip_session_register_and_pccc(void **state)
{
	struct eip_session s;
	struct eip_pending p;
	uint8_t out[512], in[256];
	size_t n;
	int len;
	(void)state;

	eip_session_init(&s, 0x01020304);
	/* SendRRData before RegisterSession: 0x0064 */
	assert_int_equal(feed(&s, "6F 00 00 00 04 03 02 01 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00", out, &n,
	                      &p), EIP_SEND);
	assert_bytes(out, (int)n, "6F 00 00 00 04 03 02 01 64 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00");
	assert_int_equal(feed(&s, "65 00 04 00 00 00 00 00 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 01 00 00 00",
	                      out, &n, &p), EIP_SEND);
	assert_bytes(out, (int)n,
	             "65 00 04 00 04 03 02 01 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 01 00 00 00");
	assert_true(s.registered);
	/* Execute PCCC (the vector of test_eip_send_rr_data_pccc_both_ways) */
	len = (int)hex(RR_PCCC_READ, in, sizeof in);
	assert_int_equal(eip_session_input(&s, &sess_id, false, in, (size_t)len, out, sizeof out, &n, &p), EIP_PCCC);
	assert_int_equal(p.station, -1);
	assert_false(p.connected);
	assert_false(p.routed);
	assert_bytes(p.reqid, (int)p.reqid_len, "07 4D 00 78 56 34 12");
	assert_bytes(p.pccc, (int)p.len, "0F 00 34 12 A2 04 07 89 00 00");
	/* its reply: CB 00 00 00, requester ID, the PCCC reply */
	len = eip_session_reply(&p, 0, 0, (const uint8_t *)"\x4F\x00\x34\x12\x05\x00\x06\x00", 8, out, sizeof out);
	assert_bytes(out, len,
	             "6F 00 23 00 04 03 02 01 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 |"
	             " 00 00 00 00 00 00 02 00 00 00 00 00 B2 00 13 00 |"
	             " CB 00 00 00 07 4D 00 78 56 34 12 4F 00 34 12 05 00 06 00");
	/* or a CIP error: 01 with extended status 0204 */
	len = eip_session_reply(&p, 0x01, 0x0204, NULL, 0, out, sizeof out);
	assert_bytes(out + 40, len - 40, "CB 00 01 01 04 02");
	/* UnRegisterSession: close, no reply */
	assert_int_equal(feed(&s, "66 00 00 00 04 03 02 01 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00", out, &n,
	                      &p), EIP_CLOSE);
}

static void test_eip_session_errors(void **state)
{
	struct eip_session s;
	struct eip_pending p;
	uint8_t out[512], in[64];
	size_t n, len;
	(void)state;

	eip_session_init(&s, 7);
	/* unknown command: 0x0001, the connection stays */
	assert_int_equal(feed(&s, "99 00 00 00 00 00 00 00 00 00 00 00 01 02 03 04 05 06 07 08 00 00 00 00", out, &n,
	                      &p), EIP_SEND);
	assert_bytes(out, (int)n, "99 00 00 00 00 00 00 00 01 00 00 00 01 02 03 04 05 06 07 08 00 00 00 00");
	/* NOP and a request with options: nothing */
	assert_int_equal(feed(&s, "00 00 01 00 00 00 00 00 00 00 00 00 01 02 03 04 05 06 07 08 00 00 00 00 AA", out, &n,
	                      &p), EIP_SILENT);
	assert_int_equal(feed(&s, "04 00 00 00 00 00 00 00 00 00 00 00 01 02 03 04 05 06 07 08 01 00 00 00", out, &n,
	                      &p), EIP_SILENT);
	/* RegisterSession of 3 bytes: 0x0065; version 2: 0x0069 naming version 1 */
	assert_int_equal(feed(&s, "65 00 03 00 00 00 00 00 00 00 00 00 01 02 03 04 05 06 07 08 00 00 00 00 01 00 00",
	                      out, &n, &p), EIP_SEND);
	assert_int_equal(out[8], 0x65);
	assert_int_equal(feed(&s, "65 00 04 00 00 00 00 00 00 00 00 00 01 02 03 04 05 06 07 08 00 00 00 00 02 00 00 00",
	                      out, &n, &p), EIP_SEND);
	assert_bytes(out + 8, 4, "69 00 00 00");
	assert_bytes(out + 24, (int)n - 24, "01 00 00 00");
	assert_false(s.registered);
	/* a length over the limit (only the header given): 0x0065 and close */
	len = hex("6F 00 F0 FF 07 00 00 00 00 00 00 00 01 02 03 04 05 06 07 08 00 00 00 00", in, sizeof in);
	assert_int_equal(eip_session_input(&s, &sess_id, false, in, len, out, sizeof out, &n, &p), EIP_SEND_CLOSE);
	assert_int_equal(out[8], 0x65);
	/* over UDP only ListIdentity / ListServices are answered */
	len = hex("65 00 04 00 00 00 00 00 00 00 00 00 01 02 03 04 05 06 07 08 00 00 00 00 01 00 00 00", in, sizeof in);
	assert_int_equal(eip_session_input(&s, &sess_id, true, in, len, out, sizeof out, &n, &p), EIP_SILENT);
	len = hex("63 00 00 00 00 00 00 00 00 00 00 00 01 02 03 04 05 06 07 08 00 00 00 00", in, sizeof in);
	assert_int_equal(eip_session_input(&s, &sess_id, true, in, len, out, sizeof out, &n, &p), EIP_SEND);
	assert_int_equal(out[24 + 6 + 32], 3);     /* the name "sim" */
}

/* SendRRData (session 01020304h) carrying an Unconnected Send whose embedded
 * request, claimed and given, is req_len bytes: Execute PCCC with a 7-byte
 * requester ID and a read, zeros after it; route port 2 link 3. Returns the
 * message's length in out. Laid out by hand from df1-eip(7). */
static size_t unconnected_rr(uint8_t *out, size_t cap, size_t req_len)
{
	static const uint8_t head[] = { 0x4B, 0x02, 0x20, 0x67, 0x24, 0x01, 0x07, 0x4D, 0x00, 0x78, 0x56,
	                                0x34, 0x12, 0x0F, 0x00, 0x34, 0x12, 0xA2, 0x04, 0x07, 0x89, 0x00, 0x00 };
	size_t cip = 6 + 4 + req_len + (req_len & 1) + 2 + 2, n;

	assert_true(24 + 16 + cip <= cap && req_len >= sizeof head);
	memset(out, 0, 24 + 16 + cip);
	n = hex("6F 00 00 00 | 04 03 02 01 | 00 00 00 00 | 11 22 33 44 55 66 77 88 | 00 00 00 00 |"
	        " 00 00 00 00 | 0A 00 | 02 00 | 00 00 00 00 | B2 00 00 00 |"
	        " 52 02 20 06 24 01 | 05 0A", out, cap);
	out[2] = (uint8_t)((16 + cip) & 0xFF);
	out[3] = (uint8_t)((16 + cip) >> 8);
	out[38] = (uint8_t)(cip & 0xFF);
	out[39] = (uint8_t)(cip >> 8);
	out[n++] = (uint8_t)(req_len & 0xFF);
	out[n++] = (uint8_t)(req_len >> 8);
	memcpy(out + n, head, sizeof head);
	n += req_len + (req_len & 1);
	out[n++] = 0x01;                 /* route path: one word, reserved */
	out[n++] = 0x00;
	out[n++] = 0x02;                 /* port 2, link 3 */
	out[n++] = 0x03;
	assert_int_equal(n, 24 + 16 + cip);
	return n;
}

/* An Unconnected Send's embedded request is at most 504 bytes
 * (CIP_UNCONNECTED_REQ_MAX, df1-eip(7) CONNECTION MANAGER): 504 is taken,
 * 505 and more are refused by the parser (DF1_E_TOO_LONG, whatever follows),
 * never built, and answered by the session with 0x15 (too much data). The
 * 2290-byte one is what fuzz_eip found parsed (tests/fuzz/found). */
static void test_cip_unconnected_send_request_bound(void **state)
{
	static const size_t over[] = { 505, 506, 2290 };
	static uint8_t in[2400], out[2400];
	struct cip_unconnected u;
	struct cip_req r;
	struct eip_session s;
	struct eip_pending p;
	size_t n, len;
	(void)state;

	len = unconnected_rr(in, sizeof in, 504);
	assert_int_equal(cip_req_parse(&r, in + 40, len - 40), 0);
	assert_int_equal(cip_unconnected_parse(&u, r.data, r.len), 0);
	assert_int_equal(u.req_len, 504);
	assert_int_equal(u.route_len, 2);
	assert_int_equal(cip_unconnected_build(out, sizeof out, 5, 10, u.req, u.req_len, u.route, u.route_len),
	                 (int)(len - 40));
	assert_memory_equal(out, in + 40, len - 40);
	assert_int_equal(cip_unconnected_build(out, sizeof out, 5, 10, u.req, 505, u.route, u.route_len), DF1_E_INVAL);
	eip_session_init(&s, 0x01020304);
	assert_int_equal(feed(&s, "65 00 04 00 00 00 00 00 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 01 00 00 00",
	                      out, &n, &p), EIP_SEND);
	assert_int_equal(eip_session_input(&s, &sess_id, false, in, len, out, sizeof out, &n, &p), EIP_PCCC);
	assert_true(p.routed);
	assert_int_equal(p.station, 3);
	assert_int_equal(p.len, 504 - 6 - 7);
	assert_bytes(p.pccc, 10, "0F 00 34 12 A2 04 07 89 00 00");

	for (size_t i = 0; i < sizeof over / sizeof over[0]; i++) {
		len = unconnected_rr(in, sizeof in, over[i]);
		assert_int_equal(cip_req_parse(&r, in + 40, len - 40), 0);
		assert_int_equal(cip_unconnected_parse(&u, r.data, r.len), DF1_E_TOO_LONG);
		/* claimed but not there: refused as too long all the same */
		assert_int_equal(cip_unconnected_parse(&u, r.data, 30), DF1_E_TOO_LONG);
		assert_int_equal(eip_session_input(&s, &sess_id, false, in, len, out, sizeof out, &n, &p), EIP_SEND);
		assert_int_equal(n, 24 + 16 + 4);
		assert_bytes(out + 40, 4, "D2 00 15 00");
	}
}

static void test_eip_pccc_writes_by_command(void **state)
{
	(void)state;
	assert_false(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00\xA2", 5));
	assert_false(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00\xA1", 5));
	assert_false(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00\x68", 5));
	assert_false(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00\x01", 5));
	assert_false(df1_pccc_is_write((const uint8_t *)"\x06\x00\x01\x00\x03", 5));
	assert_false(df1_pccc_is_write((const uint8_t *)"\x01\x00\x01\x00", 4));
	assert_true(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00\xAA", 5));
	assert_true(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00\xAB", 5));
	assert_true(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00\x80", 5));
	assert_true(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00\x26", 5));
	assert_true(df1_pccc_is_write((const uint8_t *)"\x06\x00\x01\x00\x07", 5));
	assert_true(df1_pccc_is_write((const uint8_t *)"\x08\x00\x01\x00", 4));
	assert_true(df1_pccc_is_write((const uint8_t *)"\x0F\x00\x01\x00", 4));   /* no FNC */
}

/* ------------------------------------------------------------------------
 * The server (lib/eip/eip_server.c) on real loopback sockets: a request
 * answered later, a client gone before its answer, the counters
 * ------------------------------------------------------------------------ */

struct srv_seen {
	int calls;
	uint32_t request;
	int station;
	uint8_t pccc[64];
	size_t n;
};

static void srv_on_pccc(void *user, df1_eip_server_t *s, uint32_t request, int station, const uint8_t *pccc,
                        size_t n)
{
	struct srv_seen *seen = user;

	(void)s;
	seen->calls++;
	seen->request = request;
	seen->station = station;
	seen->n = n < sizeof seen->pccc ? n : sizeof seen->pccc;
	memcpy(seen->pccc, pccc, seen->n);
}

/* Process until cond or 5 s (bounded; no sleep). */
static void srv_run(df1_eip_server_t *s, const int *counter, int want)
{
	for (int i = 0; i < 500 && *counter < want; i++) {
		struct pollfd p = { df1_eip_server_fd(s), POLLIN, 0 };

		(void)poll(&p, 1, 10);
		assert_true(df1_eip_server_process(s) >= 0);
	}
	assert_int_equal(*counter, want);
}

static int srv_connect(df1_eip_server_t *s)
{
	struct sockaddr_in a;
	const char *addr = df1_eip_server_address(s);
	int fd = socket(AF_INET, SOCK_STREAM, 0);

	assert_true(fd >= 0);
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_port = htons((uint16_t)atoi(strchr(addr, ':') + 1));
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(connect(fd, (struct sockaddr *)&a, sizeof a), 0);
	return fd;
}

/* Read one whole message (bounded by the server's processing). */
static size_t srv_recv(df1_eip_server_t *s, int fd, uint8_t *buf, size_t cap)
{
	size_t got = 0;

	for (int i = 0; i < 500; i++) {
		struct pollfd p[2] = { { df1_eip_server_fd(s), POLLIN, 0 }, { fd, POLLIN, 0 } };
		ssize_t r;

		(void)poll(p, 2, 10);
		(void)df1_eip_server_process(s);
		r = recv(fd, buf + got, cap - got, MSG_DONTWAIT);
		if (r > 0)
			got += (size_t)r;
		if (got >= 24 && got >= eip_msg_len(buf, got))
			return got;
	}
	fail_msg("no whole reply from the server (%zu bytes)", got);
	return 0;
}

static void test_eip_server_deferred_reply_and_counters(void **state)
{
	struct df1_eip_server_config c;
	struct df1_eip_server_stats st;
	struct srv_seen seen = { 0 };
	df1_eip_server_t *s;
	uint8_t msg[256], in[256];
	size_t n;
	int fd, fd2;
	(void)state;

	memset(&c, 0, sizeof c);
	c.listen = "0";
	strcpy(c.identity.product_name, "test");
	assert_int_equal(df1_eip_server_new(&s, &c, srv_on_pccc, &seen), 0);
	assert_int_equal(strncmp(df1_eip_server_address(s), "127.0.0.1:", 10), 0);
	fd = srv_connect(s);
	n = hex("65 00 04 00 00 00 00 00 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 01 00 00 00", msg, sizeof msg);
	assert_int_equal(send(fd, msg, n, 0), (ssize_t)n);
	n = srv_recv(s, fd, in, sizeof in);
	assert_int_equal(n, 28);
	assert_int_equal(le32_of(in + 8), 0);
	/* the PCCC read, in the session the server gave */
	n = hex(RR_PCCC_READ, msg, sizeof msg);
	memcpy(msg + 4, in + 4, 4);
	assert_int_equal(send(fd, msg, n, 0), (ssize_t)n);
	srv_run(s, &seen.calls, 1);
	assert_int_equal(seen.station, -1);
	assert_bytes(seen.pccc, (int)seen.n, "0F 00 34 12 A2 04 07 89 00 00");
	/* answered later, from outside the callback */
	assert_int_equal(df1_eip_server_reply(s, seen.request, (const uint8_t *)"\x4F\x00\x34\x12\x07\x00\x08\x00",
	                                      8), 0);
	n = srv_recv(s, fd, in, sizeof in);
	assert_bytes(in + 40, (int)n - 40, "CB 00 00 00 07 4D 00 78 56 34 12 4F 00 34 12 07 00 08 00");
	/* twice: not waiting any more */
	assert_int_equal(df1_eip_server_reply(s, seen.request, (const uint8_t *)"\x4F\x00\x34\x12", 4), DF1_E_INVAL);
	/* a second client asks, then goes away before the answer */
	fd2 = srv_connect(s);
	n = hex("65 00 04 00 00 00 00 00 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 01 00 00 00", msg, sizeof msg);
	assert_int_equal(send(fd2, msg, n, 0), (ssize_t)n);
	n = srv_recv(s, fd2, in, sizeof in);
	n = hex(RR_PCCC_READ, msg, sizeof msg);
	memcpy(msg + 4, in + 4, 4);
	assert_int_equal(send(fd2, msg, n, 0), (ssize_t)n);
	srv_run(s, &seen.calls, 2);
	close(fd2);
	for (int i = 0; i < 100; i++) {
		df1_eip_server_stats(s, &st);
		if (st.sessions_open == 1)
			break;
		struct pollfd p = { df1_eip_server_fd(s), POLLIN, 0 };
		(void)poll(&p, 1, 10);
		(void)df1_eip_server_process(s);
	}
	assert_int_equal(df1_eip_server_fail(s, seen.request, 0x01 | 0x0204 << 8), DF1_E_CLOSED);
	df1_eip_server_stats(s, &st);
	assert_int_equal(st.sessions, 2);
	assert_int_equal(st.sessions_open, 1);
	assert_int_equal(st.requests, 4);
	assert_int_equal(st.errors, 0);
	assert_int_equal(st.refused_clients, 0);
	close(fd);
	df1_eip_server_free(s);
	/* what df1_eip_server_new refuses, and says why */
	c.listen = "127.0.0.1:x";
	assert_int_equal(df1_eip_server_new(&s, &c, srv_on_pccc, &seen), DF1_E_INVAL);
	assert_non_null(strstr(df1_eip_server_error(NULL), "127.0.0.1:x"));
	c.listen = "0";
	c.allow = "10.0.0.0/8,nonsense";
	assert_int_equal(df1_eip_server_new(&s, &c, srv_on_pccc, &seen), DF1_E_INVAL);
	assert_non_null(strstr(df1_eip_server_error(NULL), "nonsense"));
	c.allow = NULL;
	c.max_clients = 256;
	assert_int_equal(df1_eip_server_new(&s, &c, srv_on_pccc, &seen), DF1_E_INVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_eip_register_session_request_both_ways),
		cmocka_unit_test(test_eip_send_rr_data_pccc_both_ways),
		cmocka_unit_test(test_eip_send_unit_data_both_ways),
		cmocka_unit_test(test_eip_cpf_bounds),
		cmocka_unit_test(test_eip_list_identity_both_ways),
		cmocka_unit_test(test_cip_path_segments),
		cmocka_unit_test(test_cip_request_response),
		cmocka_unit_test(test_eip_pccc_reply_and_requester_id),
		cmocka_unit_test(test_cip_forward_open_both_ways),
		cmocka_unit_test(test_cip_forward_close_both_ways),
		cmocka_unit_test(test_cip_unconnected_send_both_ways),
		cmocka_unit_test(test_cip_identity_attributes),
		cmocka_unit_test(test_eip_session_register_and_pccc),
		cmocka_unit_test(test_eip_session_errors),
		cmocka_unit_test(test_cip_unconnected_send_request_bound),
		cmocka_unit_test(test_eip_pccc_writes_by_command),
		cmocka_unit_test(test_eip_server_deferred_reply_and_counters),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
