/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_link - the link layer (lib/link/: core.c, full.c, half.c) against a scripted
 * port (tests/support/mock_port.c): full-duplex master and responder, half-duplex
 * master and slave, the Active Station List, duplicates and stale replies,
 * counters by seed ID, fault injection; and master <-> responder pairs where
 * the responder is a second handle run by the mock while the master waits.
 *
 * Frames on the wire are checked byte for byte against tests/data/vectors.txt where
 * a vector exists (TNS 0001, DST 01, SRC 00).
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

/* SLC 0F/A2 read N7:0, 20 bytes, to station 1 (TNS filled in by the link) */
static const char *A2_CMD = "01 00 0F 00 00 00 A2 14 07 89 00 00";
/* tests/data/vectors.txt derived-slc-A2-read-N7:0-20B, TNS 0001 */
static const char *A2_FD_CRC = "10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 60 46";
static const char *A2_FD_BCC = "10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 A9";
/* derived-hd-master-A2-stn1 */
static const char *A2_HD_CRC = "10 01 01 10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 A2 84";
static const char *A2_HD_BCC = "10 01 01 10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 A8";

static const uint8_t ACK[2] = { 0x10, 0x06 };
static const uint8_t NAK[2] = { 0x10, 0x15 };
static const uint8_t ENQ[2] = { 0x10, 0x05 };
static const uint8_t EOT[2] = { 0x10, 0x04 };

/* ------------------------------------------------------------------------
 * Fixture, log capture, helpers
 * ------------------------------------------------------------------------ */

#define LOG_MAX 256
static int log_ids[LOG_MAX];
static size_t log_n;
static char log_last[LOG_MAX][160];

static void log_cb(void *user, int id, enum df1_severity sev, const char *text)
{
	(void)user;
	(void)sev;
	if (log_n < LOG_MAX) {
		snprintf(log_last[log_n], sizeof log_last[0], "%s", text);
		log_ids[log_n++] = id;
	}
}

static size_t logged(int id)
{
	size_t c = 0;

	for (size_t i = 0; i < log_n; i++)
		c += log_ids[i] == id;
	return c;
}

static const char *log_text(int id)
{
	for (size_t i = 0; i < log_n; i++)
		if (log_ids[i] == id)
			return log_last[i];
	return "";
}

static struct df1 *new_handle(enum df1_duplex duplex, enum df1_check check)
{
	struct df1 *h = NULL;

	assert_int_equal(df1_new(&h), 0);
	h->port = &mock_port_ops;
	h->fd = 0;
	h->cfg.duplex = duplex;
	h->cfg.check = check;
	h->cfg.timeout_ms = 50;
	h->cfg.cmd_timeout_ms = 500;
	h->cfg.station = 0;
	h->next_tns = 1;
	df1_set_log(h, log_cb, NULL);
	return h;
}

static int setup(void **state)
{
	mock_port_reset();
	log_n = 0;
	*state = new_handle(DF1_FULL_DUPLEX, DF1_CHECK_CRC);
	return 0;
}

static int teardown(void **state)
{
	struct df1 *h = *state;

	h->port = NULL; /* the mock is not a real port: nothing to close */
	h->fd = -1;
	df1_free(h);
	mock_port_reset();
	return 0;
}

static uint64_t cnt(struct df1 *h, int id)
{
	uint64_t v = 0;

	assert_int_equal(df1_counter(h, id, &v), 0);
	return v;
}

static size_t hex(const char *text, uint8_t *buf)
{
	return mock_hex(text, buf, FRAME_MAX_WIRE);
}

/* Write call i equals the hex text. */
static void assert_write(size_t i, const char *text)
{
	uint8_t want[FRAME_MAX_WIRE];
	size_t n = hex(text, want), got_n;
	const uint8_t *got = mock_port_write_at(i, &got_n);

	assert_int_equal(got_n, n);
	assert_memory_equal(got, want, n);
}

static void assert_write_bytes(size_t i, const uint8_t *want, size_t n)
{
	size_t got_n;
	const uint8_t *got = mock_port_write_at(i, &got_n);

	assert_int_equal(got_n, n);
	assert_memory_equal(got, want, n);
}

/* Write i of a responder: its DLE ACK and the reply after it, in one write
 * (the ACK held for the reply that follows at once). The reply's bytes. */
static const uint8_t *write_after_ack(size_t i, size_t *n)
{
	size_t got_n;
	const uint8_t *got = mock_port_write_at(i, &got_n);

	assert_true(got_n > 2);
	assert_memory_equal(got, ACK, 2);
	*n = got_n - 2;
	return got + 2;
}

static void assert_ack_and(size_t i, const uint8_t *want, size_t n)
{
	size_t got_n;
	const uint8_t *got = write_after_ack(i, &got_n);

	assert_int_equal(got_n, n);
	assert_memory_equal(got, want, n);
}

/* App bytes of a reply: DST SRC CMD STS TNS, then data. */
static size_t make_reply(uint8_t *app, uint8_t dst, uint8_t src, uint8_t cmd, uint8_t sts,
                         uint16_t tns, const uint8_t *data, size_t dn)
{
	app[0] = dst;
	app[1] = src;
	app[2] = cmd;
	app[3] = sts;
	app[4] = (uint8_t)(tns & 0xFF);
	app[5] = (uint8_t)(tns >> 8);
	memcpy(app + 6, data, dn);
	return 6 + dn;
}

static const uint8_t DATA20[20] = { 1, 0, 2, 0, 3, 0, 4, 0, 5, 0, 6, 0, 7, 0, 8, 0, 9, 0, 0x10, 0 };

/* Queue one read with the slave/full-duplex frame of a reply. */
static size_t feed_reply(enum df1_check c, uint8_t dst, uint8_t src, uint8_t cmdb, uint8_t sts,
                         uint16_t tns)
{
	uint8_t app[64], wire[FRAME_MAX_WIRE];
	size_t an = make_reply(app, dst, src, cmdb, sts, tns, DATA20, sizeof DATA20);
	size_t wn = frame_encode_full(c, app, an, wire, sizeof wire);

	assert_true(wn > 0);
	mock_port_feed(wire, wn);
	return wn;
}

static size_t reply_wire(enum df1_check c, uint16_t tns, uint8_t *wire)
{
	uint8_t app[64];
	size_t an = make_reply(app, 0x00, 0x01, 0x4F, 0, tns, DATA20, sizeof DATA20);

	return frame_encode_full(c, app, an, wire, FRAME_MAX_WIRE);
}

/* The A2 command transacted; returns link_transact's result, reply in out. */
static int transact_a2(struct df1 *h, uint8_t *out, size_t cap)
{
	uint8_t cmd[32];
	size_t n = hex(A2_CMD, cmd);

	return link_transact(h, cmd, n, out, cap);
}

static void assert_reply_ok(int r, const uint8_t *out, uint16_t tns)
{
	assert_int_equal(r, 26);
	assert_int_equal(out[0], 0x00);
	assert_int_equal(out[1], 0x01);
	assert_int_equal(out[2], 0x4F);
	assert_int_equal(out[4], tns & 0xFF);
	assert_int_equal(out[5], tns >> 8);
	assert_memory_equal(out + 6, DATA20, sizeof DATA20);
}

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

static void test_full_peer_command_acked_and_dropped(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], app[32], wire[FRAME_MAX_WIRE];
	size_t an = make_reply(app, 0, 1, 0x0F, 0, 0x4444, (const uint8_t *)"\xA2\x02\x07\x89\x00\x00", 6);
	size_t wn = frame_encode_full(DF1_CHECK_CRC, app, an, wire, sizeof wire);

	mock_port_feed(ACK, 2);
	mock_port_feed(wire, wn); /* the peer's own command, not a reply */
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(1, ACK, 2);
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

static void test_mode_mismatch_and_flush(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NOTSUP);
	assert_int_equal(link_test(h, 1), DF1_E_NOTSUP);
	h->cfg.duplex = DF1_HALF_DUPLEX_MASTER;
	assert_int_equal(link_serve(h, server_responder(h), NULL, NULL, df1_now_ms()), DF1_E_INVAL);
	h->cfg.duplex = DF1_FULL_DUPLEX;
	/* half a frame in the decoder and unread bytes, then a flush */
	{
		static const uint8_t part[4] = { 0x10, 0x02, 0x00, 0x01 };
		struct df1_symbol sym;

		assert_int_equal(link_setup(h), 0);
		frame_decoder_feed(&h->dec, part, sizeof part, &sym);
		memcpy(h->rxbuf, part, sizeof part);
		h->rx_pos = 0;
		h->rx_len = sizeof part;
	}
	assert_true(frame_decoder_busy(&h->dec));
	link_flush(h);
	assert_false(frame_decoder_busy(&h->dec));
	assert_int_equal(h->rx_pos, h->rx_len);
}

/* ------------------------------------------------------------------------
 * Transmission: TX_Delay, pacing, trace, echo
 * ------------------------------------------------------------------------ */

static void test_tx_delay_before_every_transmission(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	int64_t t0;

	h->cfg.tx_delay_ms = 25;
	mock_port_feed(ACK, 2);
	feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	t0 = df1_now_ms();
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_true(df1_now_ms() - t0 >= 2 * 25); /* the command and the ACK */
}

static void test_line_baud_paces_bytes(void **state)
{
	struct df1 *h = *state;
	uint8_t buf[120];
	int64_t t0;

	memset(buf, 0x41, sizeof buf);
	h->cfg.line_baud = 9600; /* 960 characters a second: 120 take 125 ms */
	t0 = df1_now_ms();
	assert_int_equal(link_send_raw(h, buf, sizeof buf), 0);
	assert_true(df1_now_ms() - t0 >= 120);
	assert_true(mock_port_writes() > 1); /* written as the line would carry them */
	{
		size_t n;

		mock_port_written(&n);
		assert_int_equal(n, sizeof buf);
	}
	assert_int_equal(cnt(h, 2560), sizeof buf);
}

struct trace_rec {
	uint8_t tx[512], rx[512];
	size_t ntx, nrx;
	uint64_t last_us;
	bool monotonic;
};

static void trace_cb(void *user, enum df1_dir dir, const uint8_t *b, size_t n, uint64_t t_us)
{
	struct trace_rec *t = user;

	if (t_us < t->last_us)
		t->monotonic = false;
	t->last_us = t_us;
	if (dir == DF1_DIR_TX) {
		memcpy(t->tx + t->ntx, b, n);
		t->ntx += n;
	} else {
		memcpy(t->rx + t->nrx, b, n);
		t->nrx += n;
	}
}

static void test_trace_sees_every_chunk(void **state)
{
	struct df1 *h = *state;
	struct trace_rec t = { .monotonic = true };
	uint8_t out[300], rx[FRAME_MAX_WIRE];
	size_t n = reply_wire(DF1_CHECK_CRC, 1, rx + 2), wn;

	memcpy(rx, ACK, 2);
	df1_set_trace(h, trace_cb, &t);
	mock_port_feed(rx, 2 + n);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(t.nrx, 2 + n);
	assert_memory_equal(t.rx, rx, 2 + n);
	const uint8_t *w = mock_port_written(&wn);
	assert_int_equal(t.ntx, wn);
	assert_memory_equal(t.tx, w, wn);
	assert_true(t.monotonic);
}

/* Echo: every write comes back first, then the peer's answer. */
static const uint8_t *echo_answer;
static size_t echo_answer_len;

static void echo_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	mock_port_feed(buf, n);
	if (echo_answer_len) {
		mock_port_feed(echo_answer, echo_answer_len);
		echo_answer_len = 0;
	}
}

static void test_echo_discarded(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], ans[FRAME_MAX_WIRE];

	h->cfg.echo_discard = true;
	memcpy(ans, ACK, 2);
	echo_answer_len = 2 + reply_wire(DF1_CHECK_CRC, 1, ans + 2);
	echo_answer = ans;
	mock_port_on_write(echo_hook, NULL);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	/* our own frame coming back was not taken for a (bad) frame or a command */
	assert_int_equal(cnt(h, 2533), 0);
	assert_int_equal(cnt(h, 2550), 0);
	assert_int_equal(mock_port_writes(), 2);
	/* the echo of our last ACK is still on its way */
	assert_int_equal(h->echo_len - h->echo_pos, 2);
	assert_int_equal(mock_port_pending(), 1);
}

/* ------------------------------------------------------------------------
 * Half duplex, master
 * ------------------------------------------------------------------------ */

/* A scripted slave: answers by what the master wrote. */
struct hd_script {
	int msg_answers[8];   /* per master message: 1 ACK, 0 nothing */
	int nmsg;
	const char *poll_answers[16]; /* per poll: "EOT", "R<tns>", "X" (bad CRC reply), "ACK",
	                               * "NAK", "BAD" (DLE 07), NULL nothing */
	int npoll;
	uint8_t src;          /* the slave's station */
};
static struct hd_script script;

static void hd_slave_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x01) {
		if (script.msg_answers[script.nmsg++])
			mock_port_feed(ACK, 2);
		return;
	}
	if (n >= 4 && buf[0] == 0x10 && buf[1] == 0x05) {
		/* past the script: nothing, as a slave without EOT (polls repeat) */
		const char *a = script.npoll < 16 ? script.poll_answers[script.npoll] : NULL;

		script.npoll++;

		if (!a)
			return;
		if (strcmp(a, "EOT") == 0) {
			mock_port_feed(EOT, 2);
		} else if (strcmp(a, "ACK") == 0) {
			mock_port_feed(ACK, 2);
		} else if (strcmp(a, "NAK") == 0) {
			mock_port_feed(NAK, 2);
		} else if (strcmp(a, "BAD") == 0) {
			mock_port_feed_hex("10 07");
		} else if (a[0] == 'R' || a[0] == 'X') {
			uint8_t app[64], wire[FRAME_MAX_WIRE];
			unsigned tns = 0;
			size_t an, wn;

			sscanf(a + 1, "%x", &tns);
			an = make_reply(app, 0, script.src, 0x4F, 0, (uint16_t)tns, DATA20, sizeof DATA20);
			wn = frame_encode_full(DF1_CHECK_CRC, app, an, wire, sizeof wire);
			if (a[0] == 'X')
				wire[wn - 2] ^= 0x55;
			mock_port_feed(wire, wn);
		}
	}
}

static int setup_hd(void **state)
{
	struct df1 *h;

	setup(state);
	h = *state;
	h->cfg.duplex = DF1_HALF_DUPLEX_MASTER;
	memset(&script, 0, sizeof script);
	script.src = 1;
	mock_port_on_write(hd_slave_hook, NULL);
	return 0;
}

static void test_hd_five_transmissions_byte_exact(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	script.msg_answers[0] = 1;
	script.poll_answers[0] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	/* master: message, poll, ACK (the slave's two: ACK, reply) */
	assert_int_equal(mock_port_writes(), 3);
	assert_write(0, A2_HD_CRC);
	assert_write(1, "10 05 01 FF");
	assert_write_bytes(2, ACK, 2);
	assert_int_equal(cnt(h, 2525), 1);
	assert_int_equal(cnt(h, 2527), 1);
	assert_int_equal(cnt(h, 2531), 1);
	assert_int_equal(cnt(h, 2536), 1);
	assert_int_equal(cnt(h, 2535), 1);
	assert_int_equal(cnt(h, 2530), 1);
	assert_int_equal(logged(2523), 1);
	assert_string_equal(log_text(2523), "Reply Message received from Slave 1");
	assert_int_equal(df1_station_active(h, 1), 1);
}

static void test_hd_bcc_master_message_byte_exact(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.check = DF1_CHECK_BCC;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = NULL;
	script.poll_answers[1] = NULL;
	h->cfg.enq_retries = 1;
	h->cfg.cmd_timeout_ms = 500;
	/* polls nobody answers are polled again (a slave that sends no EOT),
	 * not ENQ retries, until Cmd_Timeout: DLE NAK, 2545, DF1_E_TIMEOUT */
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_write(0, A2_HD_BCC);
	assert_write(1, "10 05 01 FF");
	assert_write(2, "10 05 01 FF");
	assert_write(mock_port_writes() - 1, "10 15");
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(cnt(h, 2545), 1);
	assert_int_equal(df1_station_active(h, 1), 0);
}

static void test_hd_poll_station_16_stuffed(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], cmd[32];
	size_t n = hex(A2_CMD, cmd);

	cmd[0] = 0x10;
	script.src = 0x10;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "R0001";
	assert_int_equal(link_transact(h, cmd, n, out, sizeof out), 26);
	assert_write(0, "10 01 10 10 10 02 10 10 00 0F 00 01 00 A2 14 07 89 00 00 10 03 4F 99");
	assert_write(1, "10 05 10 10 F0");
}

static void test_hd_eot_then_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	script.msg_answers[0] = 1;
	script.poll_answers[0] = "EOT";
	script.poll_answers[1] = "EOT";
	script.poll_answers[2] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 5);
	assert_write(1, "10 05 01 FF");
	assert_write(2, "10 05 01 FF");
	assert_write(3, "10 05 01 FF");
	assert_write_bytes(4, ACK, 2);
	assert_int_equal(cnt(h, 2538), 2);
	assert_int_equal(cnt(h, 2531), 3);
	assert_int_equal(cnt(h, 2543), 0); /* EOT is not an error */
}

static void eot_forever_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x01)
		mock_port_feed(ACK, 2);
	else if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x05)
		mock_port_feed(EOT, 2);
}

static void test_hd_cmd_timeout_sends_nak(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	size_t nw;
	int64_t t0;

	h->cfg.cmd_timeout_ms = 80;
	mock_port_on_write(eot_forever_hook, NULL);
	t0 = df1_now_ms();
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_TIMEOUT);
	assert_true(df1_now_ms() - t0 >= 80);
	nw = mock_port_writes();
	assert_true(nw >= 4);
	assert_write_bytes(nw - 1, NAK, 2); /* "to terminate processing" (doc/REQUIREMENTS.md 004 2545) */
	assert_int_equal(cnt(h, 2545), 1);
	assert_int_equal(cnt(h, 2533), 1);
	assert_int_equal(cnt(h, 2538), cnt(h, 2531));
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(logged(2508), 1);
	assert_int_equal(df1_station_active(h, 1), 0);
	assert_int_equal(df1_last_error(h)->code, DF1_E_TIMEOUT);
}

static void test_hd_no_ack_retransmit_then_nak_limit(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.nak_retries = 2;
	script.msg_answers[0] = 0;
	script.msg_answers[1] = 0;
	script.msg_answers[2] = 0;
	/* the mock waits timeout_ms for each missing ACK */
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NAK_LIMIT);
	assert_int_equal(mock_port_writes(), 3);
	for (size_t i = 0; i < 3; i++)
		assert_write(i, A2_HD_CRC);
	assert_int_equal(cnt(h, 2541), 2);
	assert_int_equal(cnt(h, 2542), 1);
	assert_int_equal(logged(2521), 2);
	assert_string_equal(log_text(2521), "NAK Retry #1, due to error 2508");
	assert_int_equal(df1_station_active(h, 1), 0);
}

static void test_hd_no_ack_then_ack(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	script.msg_answers[0] = 0;
	script.msg_answers[1] = 1;
	script.poll_answers[0] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_write(0, A2_HD_CRC);
	assert_write(1, A2_HD_CRC);
	assert_write(2, "10 05 01 FF");
	assert_int_equal(cnt(h, 2541), 1);
	assert_int_equal(cnt(h, 2527), 1);
	assert_int_equal(cnt(h, 2525), 2);
}

static void test_hd_bad_check_reply_repolled(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	script.msg_answers[0] = 1;
	script.poll_answers[0] = "X0001"; /* bad CRC: no ACK, poll again */
	script.poll_answers[1] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write(1, "10 05 01 FF");
	assert_write(2, "10 05 01 FF");
	assert_write_bytes(3, ACK, 2);
	assert_int_equal(cnt(h, 2547), 1);
	assert_int_equal(cnt(h, 2543), 1);
	assert_int_equal(cnt(h, 2533), 0); /* the half-duplex master never NAKs a frame */
	assert_int_equal(cnt(h, 2535), 1);
}

/* A poll answered with neither DLE EOT nor a frame: 2516 with the symbol
 * byte (doc/REQUIREMENTS.md 004 NTC_EOT_STX_EXPECTED), and polling goes on. */
static void test_hd_poll_answer_not_eot_or_stx_2516(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.enq_retries = 3;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "ACK"; /* stray: ignored, the poll unanswered: polled again */
	script.poll_answers[1] = "NAK";
	script.poll_answers[2] = "BAD";
	script.poll_answers[3] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(logged(2516), 3);
	{
		size_t k = 0;
		static const char *const want[3] = {
			"EOT or STX Expected (last symbol received was 0x06)",
			"EOT or STX Expected (last symbol received was 0x15)",
			"EOT or STX Expected (last symbol received was 0x07)",
		};

		for (size_t i = 0; i < log_n; i++)
			if (log_ids[i] == 2516)
				assert_string_equal(log_last[i], want[k++]);
	}
	assert_int_equal(logged(2517), 1);
	assert_int_equal(logged(2514), 1);
	assert_int_equal(cnt(h, 2543), 2); /* the NAK and the broken symbol; silence is no retry */
	assert_int_equal(cnt(h, 2534), 1);
	assert_int_equal(cnt(h, 2530), 1);
}

static void ack_after_garbage_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x01) {
		mock_port_feed(EOT, 2);
		mock_port_feed_hex("10 07");
		mock_port_feed(ACK, 2);
	} else if (n >= 4 && buf[0] == 0x10 && buf[1] == 0x05) {
		feed_reply(DF1_CHECK_CRC, 0, 1, 0x4F, 0, 1);
	}
}

/* Waiting for the slave's ACK of our master message, other symbols are 2515
 * (a broken one after its own notice) and ignored: the ACK still counts. */
static void test_hd_ack_expected_2515(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	size_t k = 0;

	mock_port_on_write(ack_after_garbage_hook, NULL);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(logged(2515), 2);
	for (size_t i = 0; i < log_n; i++) {
		if (log_ids[i] != 2515)
			continue;
		assert_string_equal(log_last[i], k++ == 0 ? "ACK Expected (last symbol received was 0x04)"
		                                          : "ACK Expected (last symbol received was 0x07)");
	}
	assert_int_equal(logged(2514), 1);
	assert_int_equal(cnt(h, 2541), 0); /* no retransmission */
	assert_int_equal(cnt(h, 2536), 1);
}

static int64_t write_ms[16];
static size_t write_ms_n;

static void timed_hd_slave_hook(const uint8_t *buf, size_t n, void *user)
{
	if (write_ms_n < 16)
		write_ms[write_ms_n++] = df1_now_ms();
	hd_slave_hook(buf, n, user);
}

/* TX_Delay before EVERY transmission (doc/REQUIREMENTS.md 004 "DF1 and TX_Delay"): master
 * message, each poll, the ACK of the reply; each write comes at least TX_Delay
 * after the answer to the previous one was read (the mock answers at once). */
static void test_hd_tx_delay_before_each_write(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	int64_t t0;

	h->cfg.tx_delay_ms = 25;
	write_ms_n = 0;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "EOT";
	script.poll_answers[1] = "R0001";
	mock_port_on_write(timed_hd_slave_hook, NULL);
	t0 = df1_now_ms();
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(write_ms_n, 4); /* message, poll, poll, ACK */
	assert_true(write_ms[0] - t0 >= 25);
	for (size_t i = 1; i < write_ms_n; i++)
		if (write_ms[i] - write_ms[i - 1] < 25)
			fail_msg("write %zu only %lld ms after write %zu", i,
			         (long long)(write_ms[i] - write_ms[i - 1]), i - 1);
}

static void test_hd_enq_limit(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.enq_retries = 2;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "X0001";
	script.poll_answers[1] = NULL;  /* no answer: polled again, not a retry */
	script.poll_answers[2] = "X0001";
	script.poll_answers[3] = "X0001";
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_ENQ_LIMIT);
	assert_int_equal(mock_port_writes(), 5);
	assert_int_equal(cnt(h, 2543), 2);
	assert_int_equal(cnt(h, 2544), 1);
	assert_int_equal(logged(2520), 1);
	assert_int_equal(df1_station_active(h, 1), 0);
}

static void test_hd_stale_reply_acked_and_polled_again(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->next_tns = 0x0101;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "R00FF"; /* left over from a timed-out transaction */
	script.poll_answers[1] = "R0101";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 0x0101);
	assert_int_equal(mock_port_writes(), 5);
	assert_write_bytes(2, ACK, 2);
	assert_write(3, "10 05 01 FF");
	assert_write_bytes(4, ACK, 2);
	assert_int_equal(cnt(h, 2548), 1);
	assert_int_equal(cnt(h, 2543), 0);
}

static void test_hd_inactive_station_fails_after_one_poll(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	assert_int_equal(df1_station_set_active(h, 1, false), 0);
	script.poll_answers[0] = NULL;
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_INACTIVE);
	assert_int_equal(mock_port_writes(), 1);
	assert_write(0, "10 05 01 FF");
	assert_int_equal(cnt(h, 2531), 1);
	assert_int_equal(cnt(h, 2525), 0);
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(logged(2509), 1);
	assert_string_equal(log_text(2509), "Slave Station (1) Inactive");
	assert_int_equal(df1_last_error(h)->code, DF1_E_INACTIVE);
	assert_int_equal(df1_station_active(h, 1), 0);
}

static void test_hd_inactive_station_answers_eot_proceeds(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	assert_int_equal(df1_station_set_active(h, 1, false), 0);
	script.poll_answers[0] = "EOT";
	script.msg_answers[0] = 1;
	script.poll_answers[1] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write(0, "10 05 01 FF");
	assert_write(1, A2_HD_CRC);
	assert_write(2, "10 05 01 FF");
	assert_write_bytes(3, ACK, 2);
	assert_int_equal(df1_station_active(h, 1), 1);
}

static void test_hd_inactive_station_stale_answer_proceeds(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->next_tns = 0x20;
	assert_int_equal(df1_station_set_active(h, 1, false), 0);
	script.poll_answers[0] = "R001F"; /* a stale message also proves it is alive */
	script.msg_answers[0] = 1;
	script.poll_answers[1] = "R0020";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 0x20);
	assert_int_equal(cnt(h, 2548), 1);
	assert_int_equal(df1_station_active(h, 1), 1);
}

static void test_hd_two_stations_per_station_duplicates(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300], cmd[32];
	size_t n = hex(A2_CMD, cmd);

	/* station 1, TNS 1 */
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "R0001";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	/* station 2, TNS 2 */
	script.src = 2;
	cmd[0] = 2;
	script.msg_answers[1] = 1;
	script.poll_answers[1] = "R0002";
	assert_int_equal(link_transact(h, cmd, n, out, sizeof out), 26);
	assert_int_equal(out[1], 2);
	/* station 1 again, TNS 3: our ACK of its reply 1 was lost, it sends it again */
	script.src = 1;
	script.msg_answers[2] = 1;
	script.poll_answers[2] = "R0001";
	script.poll_answers[3] = "R0003";
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 3);
	assert_int_equal(cnt(h, 2549), 1); /* a duplicate of station 1, not a stale message */
	assert_int_equal(cnt(h, 2548), 0);
	assert_int_equal(cnt(h, 2530), 3);
}

static void test_hd_link_test(void **state)
{
	struct df1 *h = *state;

	script.poll_answers[0] = "EOT";
	script.poll_answers[1] = NULL;
	assert_int_equal(link_test(h, 1), 0);
	assert_write(0, "10 05 01 FF");
	assert_int_equal(link_test(h, 1), DF1_E_TIMEOUT);
	assert_int_equal(link_test(h, 300), DF1_E_INVAL);
}

static void echo_then_slave_hook(const uint8_t *buf, size_t n, void *user)
{
	mock_port_feed(buf, n); /* the 2-wire line gives us our own bytes back first */
	hd_slave_hook(buf, n, user);
}

static void test_hd_echo_discarded(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.echo_discard = true;
	script.msg_answers[0] = 1;
	script.poll_answers[0] = "EOT";
	script.poll_answers[1] = "R0001";
	mock_port_on_write(echo_then_slave_hook, NULL);
	assert_reply_ok(transact_a2(h, out, sizeof out), out, 1);
	assert_int_equal(mock_port_writes(), 4);
	/* the echo of the master message and of the polls was not taken for traffic */
	assert_int_equal(cnt(h, 2526), 1);
	assert_int_equal(cnt(h, 2543), 0);
	assert_int_equal(logged(2515), 0);
	assert_int_equal(h->echo_len - h->echo_pos, 2);
}

/* ------------------------------------------------------------------------
 * Half duplex, slave
 * ------------------------------------------------------------------------ */

static int handler_calls;
static uint8_t handler_sts;     /* STS of the handler's replies (0 unless a test sets it) */
static uint8_t handler_last[FRAME_MAX_DATA];
static size_t handler_last_len;

/* Reply to anything: DST/SRC swapped, CMD | 40, STS 0, same TNS, 4 data bytes. */
static int test_handler(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *reply,
                        size_t cap)
{
	static const uint8_t data[4] = { 0x11, 0x22, 0x33, 0x44 };

	(void)h;
	(void)ctx;
	assert_true(cap >= 10);
	handler_calls++;
	memcpy(handler_last, cmd, n);
	handler_last_len = n;
	return (int)make_reply(reply, cmd[1], cmd[0], (uint8_t)(cmd[2] | 0x40), handler_sts,
	                       (uint16_t)(cmd[4] | cmd[5] << 8), data, handler_sts ? 0 : sizeof data);
}

static int setup_slave(void **state)
{
	struct df1 *h;

	setup(state);
	h = *state;
	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	h->cfg.station = 1;
	handler_calls = 0;
	handler_sts = 0;
	return 0;
}

/* Run link_serve until every queued read is consumed. */
static int serve_script(struct df1 *h)
{
	int total = 0;

	mock_port_expire();
	while (mock_port_pending() > 0) {
		int r = link_serve(h, server_responder(h), test_handler, NULL, df1_now_ms() + 2000);

		if (r < 0)
			return r;
		total += r;
	}
	return total;
}

/* The frame the slave must send for a master message (via the handler). */
static size_t slave_reply_wire(enum df1_check c, uint8_t stn, uint16_t tns, uint8_t *wire)
{
	static const uint8_t data[4] = { 0x11, 0x22, 0x33, 0x44 };
	uint8_t app[16];
	size_t an = make_reply(app, 0, stn, 0x4F, 0, tns, data, sizeof data);

	return frame_encode_full(c, app, an, wire, FRAME_MAX_WIRE);
}

static void feed_master_msg(uint8_t stn, uint16_t tns)
{
	uint8_t app[32], wire[FRAME_MAX_WIRE];
	size_t an = hex(A2_CMD, app), wn;

	app[0] = stn;
	app[4] = (uint8_t)(tns & 0xFF);
	app[5] = (uint8_t)(tns >> 8);
	wn = frame_encode_master(DF1_CHECK_CRC, stn, false, app, an, wire, sizeof wire);
	mock_port_feed(wire, wn);
}

static void feed_poll(uint8_t stn)
{
	uint8_t wire[8];
	size_t n = frame_encode_poll(stn, wire, sizeof wire);

	mock_port_feed(wire, n);
}

static void test_slave_full_exchange(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want);

	mock_port_feed_hex(A2_HD_CRC);
	feed_poll(1);
	mock_port_feed(ACK, 2);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(handler_last_len, 12);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, want, wn);
	assert_write_bytes(2, EOT, 2);
	assert_int_equal(cnt(h, 2528), 1);
	assert_int_equal(cnt(h, 2529), 1);
	assert_int_equal(cnt(h, 2532), 2);
	assert_int_equal(cnt(h, 2537), 1);
	assert_int_equal(cnt(h, 2536), 1);
}

static void test_slave_duplicate_executed_once(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 7, want);

	feed_master_msg(1, 7);
	feed_master_msg(1, 7); /* the master did not see our ACK */
	feed_poll(1);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, ACK, 2);
	assert_write_bytes(2, want, wn);
	assert_int_equal(cnt(h, 2549), 1);
	assert_int_equal(logged(2524), 1);
}

/* Half duplex: a different command under the accepted one's header is ACKed
 * and discarded, and the reply queued for the accepted one is dropped, so the
 * next poll gets DLE EOT, not a reply that is not its own. */
static void test_slave_duplicate_other_command_no_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t app[32], wire[FRAME_MAX_WIRE];
	size_t an = hex(A2_CMD, app), wn;

	app[4] = 7;
	app[10] = 5;                            /* N7:5 instead of N7:0 */
	wn = frame_encode_master(DF1_CHECK_CRC, 1, false, app, an, wire, sizeof wire);
	feed_master_msg(1, 7);
	mock_port_feed(wire, wn);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, ACK, 2);
	assert_write_bytes(2, EOT, 2);
	assert_int_equal(cnt(h, 2549), 1);
}

static void test_slave_reply_resent_until_acked(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 9, want);

	feed_master_msg(1, 9);
	feed_poll(1);
	feed_poll(1); /* the master found a bad check, or lost it: no ACK */
	mock_port_feed(ACK, 2);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write_bytes(1, want, wn);
	assert_write_bytes(2, want, wn);
	assert_write_bytes(3, EOT, 2);
	assert_int_equal(cnt(h, 2541), 1);
	assert_int_equal(cnt(h, 2529), 1);
	assert_int_equal(cnt(h, 2525), 2);
}

static void test_slave_gives_up_after_nak_retries(void **state)
{
	struct df1 *h = *state;

	h->cfg.nak_retries = 1;
	feed_master_msg(1, 9);
	feed_poll(1);
	feed_poll(1);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write_bytes(3, EOT, 2);
	assert_int_equal(cnt(h, 2542), 1);
}

static void test_slave_ignores_other_station(void **state)
{
	struct df1 *h = *state;

	feed_poll(2);
	feed_master_msg(2, 3);
	mock_port_feed(ACK, 2);
	feed_poll(2);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(cnt(h, 2532), 0);
}

static void test_slave_several_stations(void **state)
{
	struct df1 *h = *state;

	assert_int_equal(df1_server_add_station(h, 3), 0);
	assert_int_equal(df1_server_add_station(h, 5), 0);
	feed_poll(1); /* cfg.station is not served once stations were added */
	feed_master_msg(3, 0x30);
	feed_master_msg(5, 0x50);
	feed_poll(5);
	mock_port_feed(ACK, 2);
	feed_poll(3);
	mock_port_feed(ACK, 2);
	feed_poll(3);
	assert_int_equal(serve_script(h), 2);
	assert_int_equal(mock_port_writes(), 5);
	{
		uint8_t w5[FRAME_MAX_WIRE], w3[FRAME_MAX_WIRE];
		size_t n5 = slave_reply_wire(DF1_CHECK_CRC, 5, 0x50, w5);
		size_t n3 = slave_reply_wire(DF1_CHECK_CRC, 3, 0x30, w3);

		assert_write_bytes(2, w5, n5);
		assert_write_bytes(3, w3, n3);
		assert_write_bytes(4, EOT, 2);
	}
}

static void test_slave_nak_resets_link(void **state)
{
	struct df1 *h = *state;

	feed_master_msg(1, 4);
	mock_port_feed(NAK, 2); /* global link reset by the master */
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, EOT, 2);
	assert_int_equal(cnt(h, 2534), 1);
}

static void test_slave_bad_check_no_answer(void **state)
{
	struct df1 *h = *state;
	uint8_t wire[FRAME_MAX_WIRE];
	size_t n = hex(A2_HD_CRC, wire);

	wire[n - 1] ^= 0x01;
	mock_port_feed(wire, n);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(cnt(h, 2547), 1);
}

/* A 2-wire line without echo discard: the slave hears its own bytes; after a
 * frame of ours the master ACKs and polls again. */
static void slave_echo_hook(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	mock_port_feed(buf, n);
	if (n > 2 && buf[1] == DF1_STX) {
		mock_port_feed(ACK, 2);
		feed_poll(1);
	}
}

static void test_slave_own_echo_does_not_hide_ack(void **state)
{
	struct df1 *h = *state;

	mock_port_on_write(slave_echo_hook, NULL);
	feed_master_msg(1, 0x31);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	/* ACK, reply, EOT: the ACK after the echo released the reply */
	assert_int_equal(mock_port_writes(), 3);
	assert_write_bytes(2, EOT, 2);
	assert_int_equal(cnt(h, 2541), 0);
}

static void test_slave_bcc_options(void **state)
{
	struct df1 *h = *state;

	/* BCC over STN + data (default) */
	h->cfg.check = DF1_CHECK_BCC;
	mock_port_feed_hex(A2_HD_BCC);
	assert_int_equal(serve_script(h), 1);
	/* the other reading of doc/PROTOCOL.md 2.2: STX in the sum */
	h->cfg.hd_bcc_stx = true;
	mock_port_feed_hex("10 01 01 10 02 01 00 0F 00 02 00 A2 14 07 89 00 00 10 03 A5");
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 2);
}

/* ------------------------------------------------------------------------
 * Full duplex, responder
 * ------------------------------------------------------------------------ */

static int setup_peer(void **state)
{
	struct df1 *h;

	setup(state);
	h = *state;
	h->cfg.station = 1;
	handler_calls = 0;
	handler_sts = 0;
	return 0;
}

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

/* ------------------------------------------------------------------------
 * Fault injection, seen from the line
 * ------------------------------------------------------------------------ */

static void test_fault_api_validates(void **state)
{
	struct df1 *h = *state;

	assert_int_equal(df1_server_set_fault(h, (enum df1_fault)0, 10, 0), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, (enum df1_fault)8, 10, 0), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_NOISE, 1001, 0), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_DELAY_REPLY, 10, -5), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 10, 257), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 10, -2), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(NULL, DF1_FAULT_NOISE, 10, 0), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_NOISE, 1000, 0), 0);
	assert_int_equal(server_responder(h)->faults.per_mille[DF1_FAULT_NOISE], 1000);
}

static void test_fault_rng_deterministic(void **state)
{
	struct df1 *h = *state;
	bool a[200], b[200];
	int hits = 0;

	df1_server_set_fault(h, DF1_FAULT_NOISE, 300, 0);
	df1_server_set_seed(h, 42);
	for (int i = 0; i < 200; i++)
		a[i] = link_fault(server_responder(h), DF1_FAULT_NOISE);
	df1_server_set_seed(h, 42);
	for (int i = 0; i < 200; i++) {
		b[i] = link_fault(server_responder(h), DF1_FAULT_NOISE);
		hits += b[i];
	}
	assert_memory_equal(a, b, sizeof a);
	assert_true(hits > 30 && hits < 100); /* about 30 % */
	assert_false(link_fault(server_responder(h), DF1_FAULT_DROP_ACK)); /* off */
}

static void test_fault_drop_ack_full(void **state)
{
	struct df1 *h = *state;

	df1_server_set_fault(h, DF1_FAULT_DROP_ACK, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ENQ, 2); /* the master's ACK timer ran out */
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	/* no ACK before the reply; the ENQ gets the ACK a lost ACK would have been */
	assert_int_equal(mock_port_writes(), 2);
	{
		size_t n;
		const uint8_t *w = mock_port_write_at(0, &n);

		assert_int_equal(w[1], DF1_STX);
	}
	assert_write_bytes(1, ACK, 2);
}

static void test_fault_drop_ack_hd_executed_once(void **state)
{
	struct df1 *h = *state;

	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	df1_server_set_fault(h, DF1_FAULT_DROP_ACK, 1000, 0);
	feed_master_msg(1, 0x77);
	feed_master_msg(1, 0x77); /* the master's retransmission */
	feed_poll(1);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(0, ACK, 2); /* the duplicate is ACKed */
	assert_int_equal(cnt(h, 2549), 1);
}

static void test_fault_nak_command(void **state)
{
	struct df1 *h = *state;

	df1_server_set_fault(h, DF1_FAULT_NAK_COMMAND, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed_hex(A2_FD_CRC);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(0, NAK, 2);
	assert_write_bytes(1, NAK, 2);
}

static void test_fault_corrupt_reply_then_good(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want), n;
	const uint8_t *w;

	df1_server_set_fault(h, DF1_FAULT_CORRUPT_REPLY, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(NAK, 2);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	w = write_after_ack(0, &n);
	assert_int_equal(n, wn);
	assert_memory_equal(w, want, wn - 1);
	assert_int_equal(w[wn - 1], want[wn - 1] ^ 0xFF);
	assert_write_bytes(1, want, wn);
}

static void test_fault_stale_reply_first(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE], stale[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want);
	size_t sn = slave_reply_wire(DF1_CHECK_CRC, 1, 0xFFFF, stale); /* TNS - 2 */

	df1_server_set_fault(h, DF1_FAULT_STALE_REPLY, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ACK, 2);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_ack_and(0, stale, sn);
	assert_write_bytes(1, want, wn);
}

static void test_fault_stale_reply_hd(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE], stale[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 0x100, want);
	size_t sn = slave_reply_wire(DF1_CHECK_CRC, 1, 0xFE, stale); /* TNS - 2 */

	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	df1_server_set_fault(h, DF1_FAULT_STALE_REPLY, 1000, 0);
	feed_master_msg(1, 0x100);
	feed_poll(1);
	mock_port_feed(ACK, 2);
	feed_poll(1);
	mock_port_feed(ACK, 2);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 4);
	assert_write_bytes(1, stale, sn);
	assert_write_bytes(2, want, wn);
	assert_write_bytes(3, EOT, 2);
}

static void test_fault_noise_before_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t want[FRAME_MAX_WIRE];
	size_t wn = slave_reply_wire(DF1_CHECK_CRC, 1, 1, want), n;
	const uint8_t *w;

	df1_server_set_fault(h, DF1_FAULT_NOISE, 1000, 0);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	w = write_after_ack(0, &n);
	assert_int_equal(n, 3 + wn);
	for (int i = 0; i < 3; i++)
		assert_int_not_equal(w[i], DF1_DLE);
	assert_memory_equal(w + 3, want, wn);
}

static void test_fault_silent_station(void **state)
{
	struct df1 *h = *state;

	df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, 1);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ENQ, 2);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 0);
	/* half duplex: no ACK, no answer to polls */
	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	feed_master_msg(1, 1);
	feed_poll(1);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(handler_calls, 0);
}

/* value 256: every station silent, bare ENQs unanswered too; -1 (or
 * probability 0) answers again. */
static void test_fault_silent_all_stations(void **state)
{
	struct df1 *h = *state;

	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, 257), DF1_E_INVAL);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, 256), 0);
	mock_port_feed(ENQ, 2);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ENQ, 2);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 0);
	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	assert_int_equal(df1_server_add_station(h, 1), 0);
	assert_int_equal(df1_server_add_station(h, 7), 0);
	feed_master_msg(1, 1);
	feed_poll(1);
	feed_master_msg(7, 2);
	feed_poll(7);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 0);
	assert_int_equal(handler_calls, 0);
	/* back: station 7 answers */
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 0, -1), 0);
	feed_master_msg(7, 3);
	feed_poll(7);
	mock_port_feed(ACK, 2);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(handler_calls, 1);
	assert_int_equal(mock_port_writes(), 2); /* ACK, reply */
	/* full duplex: after a silenced frame the ENQs get an answer again as
	 * soon as the fault is off */
	h->cfg.duplex = DF1_FULL_DUPLEX;
	mock_port_clear_written();
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, 256), 0);
	mock_port_feed_hex(A2_FD_CRC);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 0, -1), 0);
	mock_port_feed(ENQ, 2);
	assert_int_equal(serve_script(h), 0);
	assert_int_equal(mock_port_writes(), 1);
}

static void test_fault_delay_reply(void **state)
{
	struct df1 *h = *state;
	int64_t t0 = df1_now_ms();
	size_t n;
	int total = 0;

	df1_server_set_fault(h, DF1_FAULT_DELAY_REPLY, 1000, 60);
	mock_port_feed_hex(A2_FD_CRC);
	mock_port_feed(ENQ, 2); /* answered while the reply waits */
	/* no more reads: the mock waits (really) until the reply is due */
	while (mock_port_writes() < 3 && df1_now_ms() - t0 < 2000) {
		int r = link_serve(h, server_responder(h), test_handler, NULL, df1_now_ms() + 200);

		assert_true(r >= 0);
		total += r;
	}
	assert_int_equal(total, 1);
	assert_true(df1_now_ms() - t0 >= 60);
	assert_write_bytes(0, ACK, 2);
	assert_write_bytes(1, ACK, 2);
	assert_int_equal(mock_port_write_at(2, &n)[1], DF1_STX);
}

static void test_fault_delay_reply_hd_eot_first(void **state)
{
	struct df1 *h = *state;

	h->cfg.duplex = DF1_HALF_DUPLEX_SLAVE;
	df1_server_set_fault(h, DF1_FAULT_DELAY_REPLY, 1000, 5000);
	feed_master_msg(1, 1);
	feed_poll(1);
	assert_int_equal(serve_script(h), 1);
	assert_int_equal(mock_port_writes(), 2);
	assert_write_bytes(1, EOT, 2); /* not ready yet */
}

/* ------------------------------------------------------------------------
 * Master <-> responder pairs: the responder is a second handle on an in-test
 * port, run by the mock whenever the master waits for bytes.
 * ------------------------------------------------------------------------ */

struct pair {
	struct df1 *peer;
	uint8_t in[8192];
	size_t in_len, in_pos;
	int served;
};
static struct pair pair;

static ssize_t pair_read(struct df1 *h, uint8_t *buf, size_t cap, int64_t deadline_ms)
{
	(void)h;
	if (pair.in_pos < pair.in_len) {
		size_t n = pair.in_len - pair.in_pos;

		if (n > cap)
			n = cap;
		memcpy(buf, pair.in + pair.in_pos, n);
		pair.in_pos += n;
		return (ssize_t)n;
	}
	{
		int64_t ms = deadline_ms - df1_now_ms();

		if (ms > 0) {
			struct timespec ts = { .tv_sec = ms / 1000, .tv_nsec = (ms % 1000) * 1000000L };

			nanosleep(&ts, NULL);
		}
	}
	return 0;
}

static ssize_t pair_write(struct df1 *h, const uint8_t *buf, size_t n, int64_t deadline_ms)
{
	(void)h;
	(void)deadline_ms;
	mock_port_feed(buf, n); /* to the master */
	return (ssize_t)n;
}

static const struct port_ops pair_ops = {
	.name = "pair",
	.read = pair_read,
	.write = pair_write,
};

static void pair_master_wrote(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (pair.in_pos == pair.in_len)
		pair.in_pos = pair.in_len = 0;
	assert_true(pair.in_len + n <= sizeof pair.in);
	memcpy(pair.in + pair.in_len, buf, n);
	pair.in_len += n;
}

static void pair_idle(int64_t deadline_ms, void *user)
{
	int64_t end = df1_now_ms() + 3;
	int r;

	(void)user;
	if (end > deadline_ms)
		end = deadline_ms;
	r = link_serve(pair.peer, server_responder(pair.peer), test_handler, NULL, end);
	assert_true(r >= 0);
	pair.served += r;
}

static void pair_start(struct df1 *master, enum df1_duplex master_duplex)
{
	memset(&pair, 0, sizeof pair);
	pair.peer = new_handle(master_duplex == DF1_HALF_DUPLEX_MASTER ? DF1_HALF_DUPLEX_SLAVE
	                                                               : DF1_FULL_DUPLEX,
	                       master->cfg.check);
	pair.peer->port = &pair_ops;
	pair.peer->cfg.station = 1;
	pair.peer->cfg.timeout_ms = 100;
	master->cfg.duplex = master_duplex;
	master->cfg.timeout_ms = 150; /* real time here: room for a loaded machine */
	mock_port_on_write(pair_master_wrote, NULL);
	mock_port_on_idle(pair_idle, NULL);
	handler_calls = 0;
}

static void pair_stop(void)
{
	pair.peer->port = NULL;
	pair.peer->fd = -1;
	df1_free(pair.peer);
	pair.peer = NULL;
	mock_port_on_idle(NULL, NULL);
	mock_port_on_write(NULL, NULL);
}

static void assert_pair_reply(int r, const uint8_t *out, uint16_t tns)
{
	assert_int_equal(r, 10);
	assert_int_equal(out[1], 1);
	assert_int_equal(out[2], 0x4F);
	assert_int_equal(out[4], tns & 0xFF);
	assert_int_equal(out[5], tns >> 8);
	assert_int_equal(out[6], 0x11);
}

static void run_pair_clean(struct df1 *h, enum df1_duplex d)
{
	uint8_t out[300];

	pair_start(h, d);
	for (uint16_t i = 1; i <= 5; i++)
		assert_pair_reply(transact_a2(h, out, sizeof out), out, i);
	assert_int_equal(handler_calls, 5);
	assert_int_equal(cnt(h, 2530), 5);
	assert_int_equal(cnt(h, 2548) + cnt(h, 2549), 0);
	pair_stop();
}

static void test_pair_fd_clean(void **state)
{
	run_pair_clean(*state, DF1_FULL_DUPLEX);
}

static void test_pair_hd_clean(void **state)
{
	run_pair_clean(*state, DF1_HALF_DUPLEX_MASTER);
}

static void test_pair_hd_bcc_clean(void **state)
{
	struct df1 *h = *state;

	h->cfg.check = DF1_CHECK_BCC;
	run_pair_clean(h, DF1_HALF_DUPLEX_MASTER);
}

static void test_pair_drop_ack_executed_once(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_DROP_ACK, 1000, 0);
		h->next_tns = (uint16_t)(0x40 + d);
		assert_pair_reply(transact_a2(h, out, sizeof out), out, (uint16_t)(0x40 + d));
		assert_int_equal(handler_calls, 1);
		pair_stop();
	}
	/* half duplex: the master's retransmission was a duplicate for the slave */
	assert_true(cnt(h, 2541) >= 1);
}

static void test_pair_corrupt_reply_recovered(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		df1_counters_reset(h);
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_CORRUPT_REPLY, 1000, 0);
		{
			uint16_t tns = h->next_tns;

			assert_pair_reply(transact_a2(h, out, sizeof out), out, tns);
		}
		assert_int_equal(cnt(h, 2547), 1);
		if (dx == DF1_FULL_DUPLEX)
			assert_int_equal(cnt(h, 2533), 1); /* NAKed, retransmitted */
		else
			assert_true(cnt(h, 2543) >= 1); /* not ACKed, polled again */
		pair_stop();
	}
}

static void test_pair_stale_reply_dropped(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		df1_counters_reset(h);
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_STALE_REPLY, 1000, 0);
		h->next_tns = (uint16_t)(0x2000 + d);
		assert_pair_reply(transact_a2(h, out, sizeof out), out, (uint16_t)(0x2000 + d));
		/* the copy carries TNS - 2: never the last accepted reply (0x2000 in
		 * the second round), so it is stale both times, not a duplicate */
		assert_int_equal(cnt(h, 2548), 1);
		assert_int_equal(cnt(h, 2549), 0);
		assert_int_equal(cnt(h, 2530), 1);
		pair_stop();
	}
}

static void test_pair_noise_tolerated(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_NOISE, 1000, 0);
		{
			uint16_t tns = h->next_tns;

			assert_pair_reply(transact_a2(h, out, sizeof out), out, tns);
		}
		pair_stop();
	}
}

static void test_pair_nak_command_limit(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.nak_retries = 2;
	pair_start(h, DF1_FULL_DUPLEX);
	df1_server_set_fault(pair.peer, DF1_FAULT_NAK_COMMAND, 1000, 0);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NAK_LIMIT);
	assert_int_equal(handler_calls, 0);
	assert_int_equal(cnt(h, 2534), 3);
	pair_stop();
}

static void test_pair_silent_station(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];

	h->cfg.enq_retries = 1;
	h->cfg.nak_retries = 1;
	pair_start(h, DF1_FULL_DUPLEX);
	df1_server_set_fault(pair.peer, DF1_FAULT_SILENT_STATION, 1000, 1);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_ENQ_LIMIT);
	pair_stop();
	mock_port_reset();
	pair_start(h, DF1_HALF_DUPLEX_MASTER);
	df1_server_set_fault(pair.peer, DF1_FAULT_SILENT_STATION, 1000, 1);
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_NAK_LIMIT);
	assert_int_equal(df1_station_active(h, 1), 0);
	/* now inactive: the next transaction costs one poll */
	mock_port_clear_written();
	assert_int_equal(transact_a2(h, out, sizeof out), DF1_E_INACTIVE);
	assert_int_equal(mock_port_writes(), 1);
	assert_int_equal(handler_calls, 0);
	pair_stop();
}

static void test_pair_delay_reply(void **state)
{
	struct df1 *h = *state;
	uint8_t out[300];
	int64_t t0;

	for (int d = 0; d < 2; d++) {
		enum df1_duplex dx = d ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;

		mock_port_reset();
		df1_counters_reset(h);
		pair_start(h, dx);
		df1_server_set_fault(pair.peer, DF1_FAULT_DELAY_REPLY, 1000, 120);
		t0 = df1_now_ms();
		{
			uint16_t tns = h->next_tns;

			assert_pair_reply(transact_a2(h, out, sizeof out), out, tns);
		}
		assert_true(df1_now_ms() - t0 >= 120);
		if (dx == DF1_HALF_DUPLEX_MASTER)
			assert_true(cnt(h, 2538) >= 1); /* EOTs while the reply was held back */
		pair_stop();
	}
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
		cmocka_unit_test_setup_teardown(test_full_peer_command_acked_and_dropped, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_incomplete_frame_2518, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_port_error_passes_through, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_reply_buffer_too_small, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_not_open, setup, teardown),
		cmocka_unit_test_setup_teardown(test_full_link_test, setup, teardown),
		cmocka_unit_test_setup_teardown(test_mode_mismatch_and_flush, setup, teardown),
		cmocka_unit_test_setup_teardown(test_tx_delay_before_every_transmission, setup, teardown),
		cmocka_unit_test_setup_teardown(test_line_baud_paces_bytes, setup, teardown),
		cmocka_unit_test_setup_teardown(test_trace_sees_every_chunk, setup, teardown),
		cmocka_unit_test_setup_teardown(test_echo_discarded, setup, teardown),
		cmocka_unit_test_setup_teardown(test_hd_five_transmissions_byte_exact, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_bcc_master_message_byte_exact, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_poll_station_16_stuffed, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_eot_then_reply, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_cmd_timeout_sends_nak, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_no_ack_retransmit_then_nak_limit, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_no_ack_then_ack, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_bad_check_reply_repolled, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_poll_answer_not_eot_or_stx_2516, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_ack_expected_2515, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_tx_delay_before_each_write, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_enq_limit, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_stale_reply_acked_and_polled_again, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_inactive_station_fails_after_one_poll, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_inactive_station_answers_eot_proceeds, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_inactive_station_stale_answer_proceeds, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_two_stations_per_station_duplicates, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_link_test, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_hd_echo_discarded, setup_hd, teardown),
		cmocka_unit_test_setup_teardown(test_slave_full_exchange, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_duplicate_executed_once, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_duplicate_other_command_no_reply, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_reply_resent_until_acked, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_gives_up_after_nak_retries, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_ignores_other_station, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_several_stations, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_nak_resets_link, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_bad_check_no_answer, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_own_echo_does_not_hide_ack, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_slave_bcc_options, setup_slave, teardown),
		cmocka_unit_test_setup_teardown(test_peer_command_ack_reply, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_reply_nak_retransmitted, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_reply_ack_timeout_enq, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_reply_enq_limit_drops, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_duplicate_command_not_run, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_duplicate_other_command_no_reply, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_enq_gets_last_response, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_nak_with_nothing_in_flight_2511, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_peer_error_reply_counted_2539, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_api_validates, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_rng_deterministic, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_drop_ack_full, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_drop_ack_hd_executed_once, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_nak_command, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_corrupt_reply_then_good, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_stale_reply_first, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_stale_reply_hd, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_noise_before_reply, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_silent_station, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_silent_all_stations, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_delay_reply, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_fault_delay_reply_hd_eot_first, setup_peer, teardown),
		cmocka_unit_test_setup_teardown(test_pair_fd_clean, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_hd_clean, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_hd_bcc_clean, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_drop_ack_executed_once, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_corrupt_reply_recovered, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_stale_reply_dropped, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_noise_tolerated, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_nak_command_limit, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_silent_station, setup, teardown),
		cmocka_unit_test_setup_teardown(test_pair_delay_reply, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
