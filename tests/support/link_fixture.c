/* SPDX-License-Identifier: MPL-2.0 */
/*
 * link_fixture - the link tests' shared fixture and helpers (link_fixture.h).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>

#include "df1_int.h"
#include "link/link.h"
#include "link/link_int.h"
#include "server/server.h"
#include "support/mock_port.h"
#include "support/link_fixture.h"

/* ------------------------------------------------------------------------
 * Fixture, log capture, helpers
 * ------------------------------------------------------------------------ */

int log_ids[LOG_MAX];
size_t log_n;
char log_last[LOG_MAX][160];

void log_cb(void *user, int id, enum df1_severity sev, const char *text)
{
	(void)user;
	(void)sev;
	if (log_n < LOG_MAX) {
		snprintf(log_last[log_n], sizeof log_last[0], "%s", text);
		log_ids[log_n++] = id;
	}
}

size_t logged(int id)
{
	size_t c = 0;

	for (size_t i = 0; i < log_n; i++)
		c += log_ids[i] == id;
	return c;
}

const char *log_text(int id)
{
	for (size_t i = 0; i < log_n; i++)
		if (log_ids[i] == id)
			return log_last[i];
	return "";
}

struct df1 *new_handle(enum df1_duplex duplex, enum df1_check check)
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

int setup(void **state)
{
	mock_port_reset();
	log_n = 0;
	*state = new_handle(DF1_FULL_DUPLEX, DF1_CHECK_CRC);
	return 0;
}

int teardown(void **state)
{
	struct df1 *h = *state;

	h->port = NULL; /* the mock is not a real port: nothing to close */
	h->fd = -1;
	df1_free(h);
	mock_port_reset();
	return 0;
}

uint64_t cnt(struct df1 *h, int id)
{
	uint64_t v = 0;

	assert_int_equal(df1_counter(h, id, &v), 0);
	return v;
}

size_t hex(const char *text, uint8_t *buf)
{
	return mock_hex(text, buf, FRAME_MAX_WIRE);
}

/* Write call i equals the hex text. */
void assert_write(size_t i, const char *text)
{
	uint8_t want[FRAME_MAX_WIRE];
	size_t n = hex(text, want), got_n;
	const uint8_t *got = mock_port_write_at(i, &got_n);

	assert_int_equal(got_n, n);
	assert_memory_equal(got, want, n);
}

void assert_write_bytes(size_t i, const uint8_t *want, size_t n)
{
	size_t got_n;
	const uint8_t *got = mock_port_write_at(i, &got_n);

	assert_int_equal(got_n, n);
	assert_memory_equal(got, want, n);
}

/* Write i of a responder: its DLE ACK and the reply after it, in one write
 * (the ACK held for the reply that follows at once). The reply's bytes. */
const uint8_t *write_after_ack(size_t i, size_t *n)
{
	size_t got_n;
	const uint8_t *got = mock_port_write_at(i, &got_n);

	assert_true(got_n > 2);
	assert_memory_equal(got, ACK, 2);
	*n = got_n - 2;
	return got + 2;
}

void assert_ack_and(size_t i, const uint8_t *want, size_t n)
{
	size_t got_n;
	const uint8_t *got = write_after_ack(i, &got_n);

	assert_int_equal(got_n, n);
	assert_memory_equal(got, want, n);
}

/* App bytes of a reply: DST SRC CMD STS TNS, then data. */
size_t make_reply(uint8_t *app, uint8_t dst, uint8_t src, uint8_t cmd, uint8_t sts,
                         uint16_t tns, const uint8_t *data, size_t dn)
{
	app[0] = dst;
	app[1] = src;
	app[2] = cmd;
	app[3] = sts;
	app[4] = (uint8_t)(tns & 0xFF);
	app[5] = (uint8_t)(tns >> 8);
	if (dn)                 /* no data: data may be NULL, which memcpy may not take */
		memcpy(app + 6, data, dn);
	return 6 + dn;
}

/* Queue one read with the slave/full-duplex frame of a reply. */
size_t feed_reply(enum df1_check c, uint8_t dst, uint8_t src, uint8_t cmdb, uint8_t sts,
                         uint16_t tns)
{
	uint8_t app[64], wire[FRAME_MAX_WIRE];
	size_t an = make_reply(app, dst, src, cmdb, sts, tns, DATA20, sizeof DATA20);
	size_t wn = frame_encode_full(c, app, an, wire, sizeof wire);

	assert_true(wn > 0);
	mock_port_feed(wire, wn);
	return wn;
}

size_t reply_wire(enum df1_check c, uint16_t tns, uint8_t *wire)
{
	uint8_t app[64];
	size_t an = make_reply(app, 0x00, 0x01, 0x4F, 0, tns, DATA20, sizeof DATA20);

	return frame_encode_full(c, app, an, wire, FRAME_MAX_WIRE);
}

/* The A2 command transacted; returns link_transact's result, reply in out. */
int transact_a2(struct df1 *h, uint8_t *out, size_t cap)
{
	uint8_t cmd[32];
	size_t n = hex(A2_CMD, cmd);

	return link_transact(h, cmd, n, out, cap);
}

void assert_reply_ok(int r, const uint8_t *out, uint16_t tns)
{
	assert_int_equal(r, 26);
	assert_int_equal(out[0], 0x00);
	assert_int_equal(out[1], 0x01);
	assert_int_equal(out[2], 0x4F);
	assert_int_equal(out[4], tns & 0xFF);
	assert_int_equal(out[5], tns >> 8);
	assert_memory_equal(out + 6, DATA20, sizeof DATA20);
}

int handler_calls;
uint8_t handler_sts;     /* STS of the handler's replies (0 unless a test sets it) */
uint8_t handler_last[FRAME_MAX_DATA];
size_t handler_last_len;

/* Reply to anything: DST/SRC swapped, CMD | 40, STS 0, same TNS, 4 data bytes. */
int test_handler(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *reply,
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

int setup_slave(void **state)
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
int serve_script(struct df1 *h)
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
size_t slave_reply_wire(enum df1_check c, uint8_t stn, uint16_t tns, uint8_t *wire)
{
	static const uint8_t data[4] = { 0x11, 0x22, 0x33, 0x44 };
	uint8_t app[16];
	size_t an = make_reply(app, 0, stn, 0x4F, 0, tns, data, sizeof data);

	return frame_encode_full(c, app, an, wire, FRAME_MAX_WIRE);
}

void feed_master_msg(uint8_t stn, uint16_t tns)
{
	uint8_t app[32], wire[FRAME_MAX_WIRE];
	size_t an = hex(A2_CMD, app), wn;

	app[0] = stn;
	app[4] = (uint8_t)(tns & 0xFF);
	app[5] = (uint8_t)(tns >> 8);
	wn = frame_encode_master(DF1_CHECK_CRC, stn, false, app, an, wire, sizeof wire);
	mock_port_feed(wire, wn);
}

void feed_poll(uint8_t stn)
{
	uint8_t wire[8];
	size_t n = frame_encode_poll(stn, wire, sizeof wire);

	mock_port_feed(wire, n);
}

int setup_peer(void **state)
{
	struct df1 *h;

	setup(state);
	h = *state;
	h->cfg.station = 1;
	handler_calls = 0;
	handler_sts = 0;
	return 0;
}
