/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_link_full - the full-duplex link (lib/link/full.c) against the scripted
 * port (tests/support/mock_port.c; fixture tests/support/link_fixture.c): the
 * master (byte-exact frames of tests/data/vectors.txt, ACK/NAK/ENQ, duplicates,
 * stale replies, bad checks) and the responder (ACK, reply, retransmission).
 */

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "df1_int.h"
#include "link/link.h"
#include "link/link_int.h"
#include "server/server.h"
#include "support/mock_port.h"
#include "support/link_fixture.h"


/* ------------------------------------------------------------------------
 * Full duplex, master
 * ------------------------------------------------------------------------ */

static void test_full_normal_exchange_byte_exact(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	size_t rn;

	mock_port_feed(ACK, 2);
	rn = feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	int r = transact_a2(h, out, sizeof out);

	assert_reply_ok(r, out, 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write(0, A2_FD_CRC);
	assert_write_bytes(1, ACK, 2);
	assert_int_equal(cnt(h, 2525), 1);
	assert_int_equal(cnt(h, 2527), 1);
	assert_int_equal(cnt(h, 2536), 1);
	assert_int_equal(cnt(h, 2535), 1);
	assert_int_equal(cnt(h, 2526), 1);
	assert_int_equal(cnt(h, 2530), 1);
	assert_int_equal(cnt(h, 2540), 0);
	assert_int_equal(cnt(h, 2560), 18 + 2);
	assert_int_equal(cnt(h, 2561), 2 + rn);
	assert_int_equal(logged(2523), 1);
	assert_int_equal(h->next_tns, 2);
	assert_int_equal(h->last_response, DF1_ACK);
}

static void test_full_bcc_byte_exact(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.check = DF1_CHECK_BCC;
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_BCC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_write(0, A2_FD_BCC);
}

static void test_full_lost_ack_enq_then_ack(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_expire();          /* the ACK is lost */
	mock_port_feed(ACK, 2);      /* the peer repeats its last response */
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 3);
	assert_write(0, A2_FD_CRC);
	assert_write_bytes(1, ENQ, 2);
	assert_write_bytes(2, ACK, 2);
	assert_int_equal(cnt(h, 2543), 1);
	assert_int_equal(cnt(h, 2544), 0);
	assert_int_equal(cnt(h, 2541), 0);
	assert_int_equal(logged(2522), 1);
	assert_string_equal(log_text(2522), "ENQ Retry #1, due to error 2508");
}

static void test_full_nak_then_ack_sends_twice(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_feed(NAK, 2);
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 3);
	assert_write(0, A2_FD_CRC);
	assert_write(1, A2_FD_CRC);
	assert_write_bytes(2, ACK, 2);
	assert_int_equal(cnt(h, 2534), 1);
	assert_int_equal(cnt(h, 2541), 1);
	assert_int_equal(cnt(h, 2525), 2);
	assert_int_equal(cnt(h, 2527), 1);
	assert_int_equal(logged(2517), 1);
	assert_int_equal(logged(2521), 1);
}

static void test_full_nak_accepted_as_0f(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_feed_hex("10 0F"); /* the 1996 manual's NAK (option, default on) */
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(cnt(h, 2534), 1);
	assert_int_equal(mock_port_writes(), 3);
}

static void test_full_enq_answered_nak_retransmits(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_expire();
	mock_port_feed(NAK, 2); /* its last response was NAK: the frame never arrived */
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write(0, A2_FD_CRC);
	assert_write_bytes(1, ENQ, 2);
	assert_write(2, A2_FD_CRC);
	assert_write_bytes(3, ACK, 2);
	assert_int_equal(cnt(h, 2543), 1);
	assert_int_equal(cnt(h, 2541), 1);
}

static void test_full_enq_exhaustion(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.enq_retries = 2;
	for (int i = 0; i < 3; i++)
		mock_port_expire();
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_ENQ_LIMIT);
	assert_int_equal(mock_port_writes(), 3);
	assert_write(0, A2_FD_CRC);
	assert_write_bytes(1, ENQ, 2);
	assert_write_bytes(2, ENQ, 2);
	assert_int_equal(cnt(h, 2543), 2);
	assert_int_equal(cnt(h, 2544), 1);
	assert_int_equal(cnt(h, 2542), 0);
	assert_int_equal(logged(2520), 1);
	assert_string_equal(log_text(2520), "ENQ Retry Limit (2) exceeded");
	assert_int_equal(df1_last_error(h)->code, DF1_E_ENQ_LIMIT);
	assert_int_equal(df1_last_error(h)->station, 1);
	assert_int_equal(mock_port_pending(), 0);
}

static void test_full_nak_exhaustion(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.nak_retries = 2;
	for (int i = 0; i < 3; i++)
		mock_port_feed(NAK, 2);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NAK_LIMIT);
	assert_int_equal(mock_port_writes(), 3);
	for (size_t i = 0; i < 3; i++)
		assert_write(i, A2_FD_CRC);
	assert_int_equal(cnt(h, 2534), 3);
	assert_int_equal(cnt(h, 2541), 2);
	assert_int_equal(cnt(h, 2542), 1);
	assert_int_equal(logged(2519), 1);
	assert_int_equal(df1_last_error(h)->code, DF1_E_NAK_LIMIT);
}

static void test_full_zero_retries_fail_at_once(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.nak_retries = 0;
	h->cfg.enq_retries = 0;
	mock_port_feed(NAK, 2);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NAK_LIMIT);
	mock_port_expire();
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_ENQ_LIMIT);
	assert_int_equal(mock_port_writes(), 2);
}

static void test_full_garbage_between_frames(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], wire[FRAME_MAX_WIRE];
	size_t n = reply_wire(DF1_CHECK_CRC, 1, wire);

	mock_port_feed_hex("55 AA 00 FF");
	mock_port_feed(ACK, 2);
	mock_port_feed_hex("10 03 7E 10 10 33"); /* stray end of a frame, DLE DLE: noise */
	/* the reply split at every byte */
	for (size_t i = 0; i < n; i++)
		mock_port_feed(wire + i, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(1, ACK, 2);
	assert_int_equal(cnt(h, 2533), 0);
}

static void test_full_noise_sets_last_response_nak(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	/* a good exchange leaves the last response at ACK ... */
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(h->last_response, DF1_ACK);
	/* ... noise turns it to NAK, and an ENQ of the peer gets that NAK */
	mock_port_clear_written();
	mock_port_feed(ACK, 2);
	mock_port_feed_hex("01 02 03");
	mock_port_feed(ENQ, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 2);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 2);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(1, NAK, 2);
	assert_write_bytes(2, ACK, 2);
}

static void test_full_initial_enq_gets_nak(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_feed(ENQ, 2); /* nothing was ever received: last response NAK */
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_write_bytes(1, NAK, 2);
	assert_write_bytes(2, ACK, 2);
}

static void test_full_duplicate_reply_dropped(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	/* our ACK of it was lost: the peer sends reply 1 again during transaction 2 */
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 2);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 2);
	assert_int_equal(cnt(h, 2549), 1);
	assert_int_equal(cnt(h, 2548), 0);
	assert_int_equal(cnt(h, 2530), 2);
	assert_int_equal(cnt(h, 2535), 3); /* the duplicate is ACKed too */
	assert_int_equal(logged(2524), 1);
	assert_string_equal(log_text(2524), "Duplicate Message received from Slave 1");
}

static void test_full_stale_tns_dropped(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->next_tns = 0x1234;
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 0x1233);  /* an old transaction's */
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 0x0034);  /* low byte alike */
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 0x1234);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 0x1234);
	assert_int_equal(cnt(h, 2548), 2);
	assert_int_equal(cnt(h, 2530), 1);
	assert_int_equal(logged(2510), 2);
	assert_string_equal(log_text(2510), "Wrong Message Received Src:0x01, Dst:0x00, Tns:0x1233");
	assert_int_equal(mock_port_writes(), 4); /* every good frame is ACKed */
}

static void test_full_stale_never_returned(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->next_tns = 7;
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 6);
	mock_port_expire(); /* the reply wait ends */
	memset(out, 0xEE, sizeof out);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_int_equal(out[0], 0xEE);
	assert_int_equal(cnt(h, 2548), 1);
	assert_int_equal(cnt(h, 2545), 1);
	assert_int_equal(logged(2508), 1);
}

static void test_full_reply_from_wrong_station_dropped(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 2, 0x4F, 0, 1); /* same TNS, SRC 2 */
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(cnt(h, 2548), 1);
}

static void test_full_reply_dst_not_compared(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	/* behind a 1770-KF2 the reply's DST is the KF2's node (doc/PROTOCOL.md 1.9) */
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0x0A, 1, 0x4F, 0, 1);
	assert_int_equal(transact_a2(h, out, sizeof out), 26);
	assert_int_equal(out[0], 0x0A);
}

static void test_full_wrong_command_code(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x46, 0, 1);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_BAD_FUNCTION);
	assert_int_equal(logged(2505), 1);
	assert_string_equal(log_text(2505),
	                    "Response with wrong command code (slv=1, actual=70, expected=79)");
	assert_int_equal(cnt(h, 2550), 1);
}

static void test_full_error_reply_counted(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0xF0, 1);
	assert_int_equal(transact_a2(h, out, sizeof out), 26);
	assert_int_equal(out[3], 0xF0);
	assert_int_equal(cnt(h, 2540), 1);
}

static void test_full_reply_before_ack_completes(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	/* the ACK is lost in noise; the reply proves the command was delivered */
	mock_port_feed_hex("10 99");
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_int_equal(logged(2514), 1);
}

static void test_full_embedded_ack_inside_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], wire[FRAME_MAX_WIRE], emb[FRAME_MAX_WIRE];
	size_t n = reply_wire(DF1_CHECK_CRC, 1, wire);

	/* DLE ACK after the 5th data byte (doc/PROTOCOL.md 1.8), no ACK before the frame */
	memcpy(emb, wire, 7);
	memcpy(emb + 7, ACK, 2);
	memcpy(emb + 9, wire + 7, n - 7);
	mock_port_feed(emb, n + 2);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(cnt(h, 2536), 1);
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(mock_port_writes(), 2);
}

static void test_full_noise_inside_frame_nak_then_good(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], wire[FRAME_MAX_WIRE];
	size_t n = reply_wire(DF1_CHECK_CRC, 1, wire);

	mock_port_feed(ACK, 2);
	/* a control symbol inside the frame: aborted, NAK (doc/PROTOCOL.md 1.7, KA p.118) */
	mock_port_feed(wire, 8);
	mock_port_feed_hex("10 99");
	mock_port_feed(wire + 8, n - 8); /* the rest: noise + a stray DLE ETX */
	mock_port_feed(wire, n);         /* the peer's retransmission */
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(1, NAK, 2);
	assert_write_bytes(2, ACK, 2);
	assert_int_equal(cnt(h, 2533), 1); /* the stray rest of it is noise, not NAKed */
	assert_true(logged(2514) >= 1);
	assert_string_equal(log_text(2514), "Invalid Symbol received after DLE - (0x99)");
}

static void test_full_bad_crc_reply_nak_then_accepted(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], wire[FRAME_MAX_WIRE];
	size_t n = reply_wire(DF1_CHECK_CRC, 1, wire);

	mock_port_feed(ACK, 2);
	wire[10] ^= 0x01; /* a data bit flipped on the line */
	mock_port_feed(wire, n);
	wire[10] ^= 0x01;
	mock_port_feed(wire, n);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_write_bytes(1, NAK, 2);
	assert_write_bytes(2, ACK, 2);
	assert_int_equal(cnt(h, 2547), 1);
	assert_int_equal(cnt(h, 2546), 0);
	assert_int_equal(cnt(h, 2533), 1);
	assert_int_equal(logged(2506), 1);
}

static void test_full_bad_bcc_reply_nak_then_accepted(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], wire[FRAME_MAX_WIRE];
	size_t n;

	h->cfg.check = DF1_CHECK_BCC;
	n = reply_wire(DF1_CHECK_BCC, 1, wire);
	mock_port_feed(ACK, 2);
	wire[n - 1] ^= 0x20;
	mock_port_feed(wire, n);
	wire[n - 1] ^= 0x20;
	mock_port_feed(wire, n);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_write_bytes(1, NAK, 2);
	assert_write_bytes(2, ACK, 2);
	assert_int_equal(cnt(h, 2546), 1);
	assert_int_equal(logged(2507), 1);
	{
		char want[80];

		snprintf(want, sizeof want, "Response with wrong BCC (actual=0x00%02x, expected=0x00%02x)",
		         wire[n - 1] ^ 0x20, wire[n - 1]);
		assert_string_equal(log_text(2507), want);
	}
}

static void test_full_too_short_frame_nak(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_feed(ACK, 2);
	mock_port_feed_hex("10 02 00 01 4F 10 03 C4 41"); /* 3 app bytes */
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_write_bytes(1, NAK, 2);
	assert_int_equal(logged(2513), 1);
}

/* More than FRAME_MAX_DATA app bytes: 2512 with the limit, NAK, then the
 * good reply. */
static void test_full_too_long_frame_nak_2512(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], big[FRAME_MAX_WIRE + 8];
	size_t n = 0;

	big[n++] = DF1_DLE;
	big[n++] = DF1_STX;
	for (int i = 0; i < FRAME_MAX_DATA + 1; i++)
		big[n++] = 0x41;
	big[n++] = DF1_DLE;
	big[n++] = DF1_ETX;
	big[n++] = 0x00;
	big[n++] = 0x00;
	mock_port_feed(ACK, 2);
	mock_port_feed(big, n);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_write_bytes(1, NAK, 2);
	assert_int_equal(logged(2512), 1);
	assert_string_equal(log_text(2512), "Received Message Too Long (> 264 bytes)");
	assert_int_equal(cnt(h, 2533), 1);
}

/* A command of the peer while ours waits, no responder set: ACKed and answered
 * STS 10h (lib/link/peer.c; tests/unit/link/test_peer.c has the rest). */
static void test_full_peer_command_answered_sts10(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], app[32], wire[FRAME_MAX_WIRE], rep[16], rwire[FRAME_MAX_WIRE];
	size_t an = make_reply(app, 0, 1, 0x0F, 0, 0x4444, (const uint8_t *)"\xA2\x02\x07\x89\x00\x00", 6);
	size_t wn = frame_encode_full(DF1_CHECK_CRC, app, an, wire, sizeof wire);
	size_t rn = make_reply(rep, 1, 0, 0x4F, 0x10, 0x4444, NULL, 0);
	size_t rwn = frame_encode_full(DF1_CHECK_CRC, rep, rn, rwire, sizeof rwire);

	mock_port_feed(ACK, 2);
	mock_port_feed(wire, wn); /* the peer's own command, not a reply */
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write_bytes(1, ACK, 2);
	assert_write_bytes(2, rwire, rwn);
	assert_int_equal(cnt(h, 2528), 1);
	assert_int_equal(cnt(h, 2550), 1);
}

static void test_full_incomplete_frame_2518(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], wire[FRAME_MAX_WIRE];
	size_t n = reply_wire(DF1_CHECK_CRC, 1, wire);

	mock_port_feed(ACK, 2);
	mock_port_feed(wire, 10); /* the line goes quiet mid-frame */
	mock_port_expire();       /* ... past the character gap */
	mock_port_feed(wire, n);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(logged(2518), 1);
}

static void test_full_port_error_passes_through(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	mock_port_fail(DF1_E_CLOSED);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_CLOSED);
	mock_port_feed(ACK, 2);
	mock_port_fail(DF1_E_INTR);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_INTR);
}

static void test_full_reply_buffer_too_small(void **state)
{
	struct df1 *h = *state;
	uint8_t out[10];

	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NOSPACE);
}

static void test_full_not_open(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->fd = -1;
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NOT_OPEN);
	h->fd = 0;
	{
		uint8_t cmd[3] = { 1, 0, 0x0F };

		assert_int_equal(link_transact(h, cmd, sizeof cmd, out, sizeof out), DF1_E_INVAL);
	}
}

static void test_full_link_test(void **state)
{
	struct df1 *h = *state;

	mock_port_feed(ACK, 2);
	assert_int_equal(link_test(h, 1), 0);
	assert_write_bytes(0, ENQ, 2);
	mock_port_feed(NAK, 2);
	assert_int_equal(link_test(h, 1), 0);
	mock_port_expire();
	assert_int_equal(link_test(h, 1), DF1_E_TIMEOUT);
}


/* ------------------------------------------------------------------------
 * Full duplex, responder
 * ------------------------------------------------------------------------ */


static void test_peer_command_ack_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want);

	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 1);
	assert_ack_and(0, want, wn);       /* one write: the ACK and the reply */
	assert_int_equal(cnt(h, 2535), 1); /* CNT_ACKS_SENT: counted all the same */
	assert_int_equal(cnt(h, 2560), 2 + wn);
	assert_int_equal(cnt(h, 2529), 1);
	assert_int_equal(cnt(h, 2536), 1);
	assert_int_equal(server_responder(h)->replies[0].used, false);
}

static void test_peer_reply_nak_retransmitted(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want);

	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(NAK, 2);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_ack_and(0, want, wn);
	assert_write_bytes(1, want, wn);
	assert_int_equal(cnt(h, 2541), 1);
	assert_int_equal(cnt(h, 2529), 1);
}

static void test_peer_reply_ack_timeout_enq(void **state)
{
	struct df1 *h = *state;

	mock_port_feed_hex(A2_FD_CRC);
	mock_port_expire(); /* no ACK for the reply */
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(1, ENQ, 2);
	assert_int_equal(cnt(h, 2543), 1);
}

static void test_peer_reply_enq_limit_drops(void **state)
{
	struct df1 *h = *state;

	h->cfg.enq_retries = 1;
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_expire();
	mock_port_expire();
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_int_equal(cnt(h, 2544), 1);
	assert_false(server_responder(h)->replies[0].used);
}

static void test_peer_duplicate_command_not_run(void **state)
{
	struct df1 *h = *state;

	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ACK, 2);
	mock_port_feed_hex(A2_FD_CRC); /* our ACK was lost: the same command again */
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(1, ACK, 2);
	assert_int_equal(cnt(h, 2549), 1);
}

/* A different command under the header of the one accepted (a master that
 * started again on its last TNS): ACKed and discarded like any duplicate, and
 * the reply still in flight is dropped, not sent to it (the NAK that would
 * have made it go again finds no frame waiting). */
static void test_peer_duplicate_other_command_no_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t app[32], wire[FRAME_MAX_WIRE];
	size_t an = hex("01 00 0F 00 01 00 A2 14 07 89 05 00", app); /* N7:5, TNS 1 */
	size_t wn = frame_encode_full(DF1_CHECK_CRC, app, an, wire, sizeof wire);

	mock_port_feed_hex(A2_FD_CRC);          /* N7:0, TNS 1: ACK and its reply */
	mock_port_feed(wire, wn);               /* before the reply's ACK */
	mock_port_feed(NAK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(1, ACK, 2);
	assert_int_equal(cnt(h, 2549), 1);
	assert_int_equal(cnt(h, 2541), 0);      /* the reply was not sent again */
	assert_false(server_responder(h)->replies[0].used);
}

static void test_peer_enq_gets_last_response(void **state)
{
	struct df1 *h = *state;
	uint8_t wire[FRAME_MAX_WIRE];
	size_t n = hex(A2_FD_CRC, wire);

	mock_port_feed(ENQ, 2);  /* nothing received yet: NAK */
	wire[9] ^= 0x40;
	mock_port_feed(wire, n); /* bad CRC: NAK */
	mock_port_feed(ENQ, 2);  /* NAK again */
	wire[9] ^= 0x40;
	mock_port_feed(wire, n); /* good: ACK and the reply */
	mock_port_feed(ACK, 2);
	mock_port_feed(ENQ, 2);  /* ACK */
	assert_int_equal(serve_script(h), 1);
	assert_write_bytes(0, NAK, 2);
	assert_write_bytes(1, NAK, 2);
	assert_write_bytes(2, NAK, 2);
	write_after_ack(3, &n);  /* the ACK and the reply */
	assert_write_bytes(4, ACK, 2);
	assert_int_equal(mock_port_writes(), 5);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(cnt(h, 2547), 1);
}

/* A DLE NAK when no reply of ours waits for a response: 2511, nothing sent. */
static void test_peer_nak_with_nothing_in_flight_2511(void **state)
{
	struct df1 *h = *state;

	mock_port_feed(NAK, 2);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(logged(2511), 1);
	assert_string_equal(log_text(2511), "Received NAK Symbol");
	assert_int_equal(logged(2517), 0);
	assert_int_equal(cnt(h, 2534), 1);
	assert_int_equal(cnt(h, 2541), 0);
	assert_int_equal(mock_port_writes(), 1); /* ACK and reply in one write */
}

/* A reply with STS != 0 is an error message sent (2539), once however often
 * it goes out; half duplex the same. */
static void test_peer_error_reply_counted_2539(void **state)
{
	struct df1 *h = *state;
	uint8_t *w;
	size_t wn;

	handler_sts = 0x10;
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(NAK, 2);         /* the reply once more */
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	w = (uint8_t *)write_after_ack(0, &wn);
	assert_true(wn > 6);
	assert_int_equal(w[5], 0x10);   /* DLE STX DST SRC CMD STS */
	assert_int_equal(cnt(h, 2529), 1);
	assert_int_equal(cnt(h, 2539), 1);
	assert_int_equal(cnt(h, 2525), 2);
	/* the half-duplex slave: the same */
	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	handler_sts = 0xF0;
	feed_master_msg(1, 0x77);
	feed_poll(1);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(cnt(h, 2529), 2);
	assert_int_equal(cnt(h, 2539), 2);
	assert_int_equal(cnt(h, 2532), 1); /* CNT_POLL_MSGS_RCVD */
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_full_normal_exchange_byte_exact, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_bcc_byte_exact, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_lost_ack_enq_then_ack, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_nak_then_ack_sends_twice, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_nak_accepted_as_0f, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_enq_answered_nak_retransmits, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_enq_exhaustion, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_nak_exhaustion, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_zero_retries_fail_at_once, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_garbage_between_frames, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_noise_sets_last_response_nak, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_initial_enq_gets_nak, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_duplicate_reply_dropped, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_stale_tns_dropped, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_stale_never_returned, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_reply_from_wrong_station_dropped, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_reply_dst_not_compared, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_wrong_command_code, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_error_reply_counted, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_reply_before_ack_completes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_embedded_ack_inside_reply, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_noise_inside_frame_nak_then_good, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_bad_crc_reply_nak_then_accepted, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_bad_bcc_reply_nak_then_accepted, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_too_short_frame_nak, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_too_long_frame_nak_2512, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_peer_command_answered_sts10, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_incomplete_frame_2518, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_port_error_passes_through, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_reply_buffer_too_small, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_not_open, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_link_test, setup, teardown),
		cmocka_unit_test_setup_teardown(test_peer_command_ack_reply, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_reply_nak_retransmitted, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_reply_ack_timeout_enq, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_reply_enq_limit_drops, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_duplicate_command_not_run, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_duplicate_other_command_no_reply, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_enq_gets_last_response, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_nak_with_nothing_in_flight_2511, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_error_reply_counted_2539, setup_peer, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
