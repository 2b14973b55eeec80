/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_discover.c - station discovery: df1_discover() and the per-station probe
 * it shares with the poll engine (discover_probe, lib/client/discover.c).
 *
 * Unit tests on the mock port: argument checks, a handle that is not open or a
 * half-duplex slave, the cancel fd readable before the scan (nothing sent), a
 * full-duplex line where nobody answers the first DLE ENQ (the error, no
 * callback), and what the presence probe sends: an empty 06/00 echo in full
 * duplex, a poll (DLE ENQ STN BCC) in half duplex, a DLE EOT to it an answer;
 * a reply with an error STS is an answer without an identification.
 *
 * Integration against df1sim over a pty: several stations on a half-duplex
 * line, some absent, one silenced (--silent), in order, identified
 * (MicroLogix 1400, type 9Fh), with round-trip times; a callback that stops
 * the scan; the cancel fd written from the callback (DF1_E_INTR before the
 * next station); every station muted by SIGUSR1 and back after SIGUSR2; full
 * duplex, where the peer answers any DST, and a muted peer (the DLE ENQ's
 * error, no callback).
 *
 * No timing assertions: short timeouts keep absent stations cheap.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "df1_int.h"
#include "support/mock_port.h"
#include "support/simproc.h"

/* What the callback saw. */
#define SEEN_MAX 256
struct seen {
	int calls;
	struct df1_discover_result r[SEEN_MAX];
	int stop_at;            /* return 1 after this station (-1: never) */
	int cancel_at;          /* write to cancel_wr after this station (-1: never) */
	int cancel_wr;
	df1_t *h;
	int last_error_code[SEEN_MAX]; /* df1_last_error(h)->code during the call */
};

static int on_station(void *user, const struct df1_discover_result *r)
{
	struct seen *s = user;

	if (s->calls < SEEN_MAX) {
		s->r[s->calls] = *r;
		s->last_error_code[s->calls] = s->h ? df1_last_error(s->h)->code : 0;
	}
	s->calls++;
	if (s->cancel_at == r->station) {
		ssize_t w = write(s->cancel_wr, "x", 1);
		assert_int_equal(w, 1);
	}
	return s->stop_at == r->station ? 1 : 0;
}

static void seen_init(struct seen *s, df1_t *h)
{
	memset(s, 0, sizeof *s);
	s->stop_at = -1;
	s->cancel_at = -1;
	s->cancel_wr = -1;
	s->h = h;
}

/* ------------------------------------------------------------------------
 * Unit tests on the mock port
 * ------------------------------------------------------------------------ */

static df1_t *mock_handle(enum df1_duplex d)
{
	df1_t *h = NULL;

	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_duplex(h, d), 0);
	assert_int_equal(df1_set_timeout_ms(h, 50), 0);
	assert_int_equal(df1_set_retries(h, 0, 0), 0);
	mock_port_reset();
	h->port = &mock_port_ops;
	h->fd = 0;
	return h;
}

static void mock_handle_free(df1_t *h)
{
	h->port = NULL;
	h->fd = -1;
	df1_free(h);
	mock_port_reset();
}

static void test_discover_bad_arguments_inval(void **state)
{
	df1_t *h = mock_handle(DF1_FULL_DUPLEX);
	struct seen s;

	(void)state;
	seen_init(&s, h);
	assert_int_equal(df1_discover(NULL, 0, 254, on_station, &s), DF1_E_INVAL);
	assert_int_equal(df1_discover(h, -1, 3, on_station, &s), DF1_E_INVAL);
	assert_int_equal(df1_discover(h, 0, 255, on_station, &s), DF1_E_INVAL);
	assert_int_equal(df1_discover(h, 5, 4, on_station, &s), DF1_E_INVAL);
	assert_int_equal(df1_last_error(h)->code, DF1_E_INVAL);
	assert_int_equal(s.calls, 0);
	assert_int_equal(mock_port_writes(), 0);
	mock_handle_free(h);
}

static void test_discover_not_open_fails(void **state)
{
	df1_t *h = NULL;
	struct seen s;

	(void)state;
	seen_init(&s, NULL);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_discover(h, 1, 2, on_station, &s), DF1_E_NOT_OPEN);
	assert_int_equal(s.calls, 0);
	df1_free(h);
}

static void test_discover_half_duplex_slave_notsup(void **state)
{
	df1_t *h = mock_handle(DF1_HALF_DUPLEX_SLAVE);
	struct seen s;

	(void)state;
	seen_init(&s, h);
	assert_int_equal(df1_discover(h, 1, 2, on_station, &s), DF1_E_NOTSUP);
	assert_int_equal(s.calls, 0);
	assert_int_equal(mock_port_writes(), 0);
	mock_handle_free(h);
}

static void test_discover_cancel_fd_readable_intr_nothing_sent(void **state)
{
	df1_t *h = mock_handle(DF1_HALF_DUPLEX_MASTER);
	struct seen s;
	int p[2];

	(void)state;
	seen_init(&s, h);
	assert_int_equal(pipe(p), 0);
	assert_int_equal(write(p[1], "x", 1), 1);
	assert_int_equal(df1_set_cancel_fd(h, p[0]), 0);
	assert_int_equal(df1_discover(h, 0, 254, on_station, &s), DF1_E_INTR);
	assert_int_equal(df1_last_error(h)->code, DF1_E_INTR);
	assert_int_equal(s.calls, 0);
	assert_int_equal(mock_port_writes(), 0);
	df1_set_cancel_fd(h, -1);
	close(p[0]);
	close(p[1]);
	mock_handle_free(h);
}

/* Full duplex: nobody answers the DLE ENQ: that error, no station probed. */
static void test_discover_full_line_silent_error_no_callback(void **state)
{
	df1_t *h = mock_handle(DF1_FULL_DUPLEX);
	static const uint8_t enq[] = { 0x10, 0x05 };
	struct seen s;

	(void)state;
	seen_init(&s, h);
	for (int i = 0; i < 8; i++)
		mock_port_expire();
	assert_int_equal(df1_discover(h, 1, 254, on_station, &s), DF1_E_TIMEOUT);
	assert_int_equal(s.calls, 0);
	assert_true(mock_port_count_written(enq, sizeof enq) >= 1);
	mock_handle_free(h);
}

/* The first symbol the handle wrote. */
static struct df1_symbol first_written(bool half, uint8_t *app, size_t cap, size_t *app_len)
{
	struct df1_decoder *d = NULL;
	struct df1_symbol sym;
	size_t n, pos = 0;
	const uint8_t *w = mock_port_written(&n);

	memset(&sym, 0, sizeof sym);
	assert_int_equal(df1_decoder_new(&d, DF1_CHECK_CRC), 0);
	df1_decoder_set_half_duplex(d, half);
	while (pos < n) {
		size_t k = df1_decoder_feed(d, w + pos, n - pos, &sym);
		pos += k;
		if (sym.kind != DF1_SYM_NONE || k == 0)
			break;
	}
	*app_len = 0;
	if (sym.kind == DF1_SYM_FRAME && sym.len <= cap) {
		memcpy(app, sym.data, sym.len);
		*app_len = sym.len;
	}
	df1_decoder_free(d);
	return sym;
}

/* Full duplex presence probe (the poll engine's): an empty 06/00 echo to the station. */
static void test_discover_probe_full_sends_empty_echo(void **state)
{
	df1_t *h = mock_handle(DF1_FULL_DUPLEX);
	struct df1_discover_result r;
	struct df1_symbol sym;
	uint8_t app[64];
	size_t len;
	int rc;

	(void)state;
	rc = discover_probe(h, 9, 0, &r);
	assert_true(rc < 0);                    /* nobody answers the mock */
	assert_false(r.answered);
	assert_false(r.identified);
	assert_int_equal(r.station, 9);
	assert_int_equal(r.error, rc);
	assert_int_equal(r.rtt_us, 0);
	sym = first_written(false, app, sizeof app, &len);
	assert_int_equal(sym.kind, DF1_SYM_FRAME);
	assert_int_equal(len, 7);               /* DST SRC CMD STS TNS TNS FNC, no data */
	assert_int_equal(app[0], 9);
	assert_int_equal(app[2], 0x06);
	assert_int_equal(app[6], 0x00);
	mock_handle_free(h);
}

static void eot_to_polls(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	if (n >= 2 && buf[0] == 0x10 && buf[1] == 0x05)
		mock_port_feed_hex("10 04");
}

/* Half duplex presence probe: a poll of the station; a DLE EOT is an answer. */
static void test_discover_probe_half_polls_eot_answers(void **state)
{
	df1_t *h = mock_handle(DF1_HALF_DUPLEX_MASTER);
	struct df1_discover_result r;
	struct df1_symbol sym;
	uint8_t app[64];
	size_t len;

	(void)state;
	mock_port_on_write(eot_to_polls, NULL);
	assert_int_equal(discover_probe(h, 7, 0, &r), 0);
	assert_true(r.answered);
	assert_false(r.identified);
	assert_int_equal(r.error, DF1_OK);
	assert_int_equal(r.station, 7);
	sym = first_written(true, app, sizeof app, &len);
	assert_int_equal(sym.kind, DF1_SYM_POLL);
	assert_true(sym.has_station);
	assert_int_equal(sym.station, 7);
	/* out may be NULL (the poll engine) */
	mock_port_clear_written();
	assert_int_equal(discover_probe(h, 7, 0, NULL), 0);
	assert_int_equal(mock_port_writes(), 1);
	mock_handle_free(h);
}

/* A full-duplex peer that is there but refuses every command: ACK to a DLE ENQ
 * or a frame, then a reply with STS 10h (illegal command or format). */
static void refusing_peer(const uint8_t *buf, size_t n, void *user)
{
	struct df1_decoder *d = NULL;
	struct df1_symbol sym;
	size_t pos = 0;

	(void)user;
	if (n == 2 && buf[0] == 0x10 && buf[1] == 0x05) {
		mock_port_feed_hex("10 06");
		return;
	}
	assert_int_equal(df1_decoder_new(&d, DF1_CHECK_CRC), 0);
	while (pos < n) {
		size_t k = df1_decoder_feed(d, buf + pos, n - pos, &sym);
		pos += k;
		if (sym.kind == DF1_SYM_FRAME && sym.len >= 6 && !(sym.data[2] & 0x40)) {
			uint8_t app[6] = { sym.data[1], sym.data[0], (uint8_t)(sym.data[2] | 0x40), 0x10,
			                   sym.data[4], sym.data[5] };
			uint8_t wire[64];
			size_t w = frame_encode_full(DF1_CHECK_CRC, app, sizeof app, wire, sizeof wire);

			mock_port_feed_hex("10 06");
			mock_port_feed(wire, w);
			break;
		}
		if (k == 0)
			break;
	}
	df1_decoder_free(d);
}

/* A reply with an error STS is an answer: the station is there, not identified. */
static void test_discover_remote_error_answered_not_identified(void **state)
{
	df1_t *h = mock_handle(DF1_FULL_DUPLEX);
	struct seen s;

	(void)state;
	seen_init(&s, h);
	mock_port_on_write(refusing_peer, NULL);
	assert_int_equal(df1_discover(h, 3, 4, on_station, &s), 2);
	assert_int_equal(s.calls, 2);
	for (int i = 0; i < 2; i++) {
		assert_int_equal(s.r[i].station, 3 + i);
		assert_true(s.r[i].answered);
		assert_false(s.r[i].identified);
		assert_int_equal(s.r[i].error, DF1_E_REMOTE);
		assert_int_equal(s.last_error_code[i], DF1_E_REMOTE);
		assert_int_equal(s.r[i].status.name[0], '\0');
	}
	assert_int_equal(df1_last_error(h)->sts, 0x10);
	mock_handle_free(h);
}

/* ------------------------------------------------------------------------
 * Integration: df1sim on a pty
 * ------------------------------------------------------------------------ */

struct sim_env {
	struct simproc sim;
	df1_t *h;
};

static df1_t *sim_client(struct sim_env *e, enum df1_duplex d)
{
	df1_t *h = NULL;
	int rc;

	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_duplex(h, d), 0);
	assert_int_equal(df1_set_timeout_ms(h, 100), 0);
	assert_int_equal(df1_set_cmd_timeout_ms(h, 500), 0);
	assert_int_equal(df1_set_retries(h, 1, 1), 0);
	rc = df1_open(h, e->sim.target);
	if (rc < 0)
		fail_msg("df1_open(%s): %s: %s", e->sim.target, df1_errname(rc), df1_last_error(h)->message);
	e->h = h;
	return h;
}

static int sim_setup(void **state, const char *const *args)
{
	static struct sim_env env;

	memset(&env, 0, sizeof env);
	*state = &env;
	return simproc_start(&env.sim, false, NULL, false, args) < 0 ? -1 : 0;
}

static int setup_half(void **state)
{
	/* stations 2, 3 and 4 are served, 3 never answers; 1 and 5 are absent */
	static const char *const args[] = { "--duplex", "half", "--station", "2-4", "--silent", "3",
	                                    "--processor", "ml1400", NULL };
	return sim_setup(state, args);
}

static int setup_full(void **state)
{
	static const char *const args[] = { "--duplex", "full", NULL };
	return sim_setup(state, args);
}

static int sim_teardown(void **state)
{
	struct sim_env *e = *state;

	if (!e)
		return 0;
	df1_free(e->h);
	e->h = NULL;
	if (e->sim.pid > 0 && simproc_stop(&e->sim, false) != 0) {
		fprintf(stderr, "df1sim did not stop cleanly\n");
		return -1;
	}
	return 0;
}

static void test_it_discover_half_several_stations(void **state)
{
	struct sim_env *e = *state;
	df1_t *h = sim_client(e, DF1_HALF_DUPLEX_MASTER);
	struct seen s;
	int n;

	seen_init(&s, h);
	n = df1_discover(h, 1, 5, on_station, &s);
	assert_int_equal(n, 2);
	assert_int_equal(s.calls, 5);
	for (int i = 0; i < 5; i++) {
		const struct df1_discover_result *r = &s.r[i];
		bool there = r->station == 2 || r->station == 4;

		assert_int_equal(r->station, 1 + i);          /* in order */
		assert_int_equal(r->answered, there);
		assert_int_equal(r->identified, there);
		if (there) {
			assert_int_equal(r->error, DF1_OK);
			assert_int_equal(r->status.type_code, 0x9F);
			assert_string_equal(r->status.name, "MicroLogix 1400");
			assert_true(r->rtt_us > 0);
		} else {
			/* absent (1, 5) or silent (3): a link error, described by the handle */
			assert_true(r->error < 0);
			assert_int_equal(s.last_error_code[i], r->error);
			assert_int_equal(r->rtt_us, 0);
			assert_int_equal(r->status.name[0], '\0');
		}
	}
	/* without a callback: only the count */
	assert_int_equal(df1_discover(h, 2, 2, NULL, NULL), 1);
}

static void test_it_discover_callback_stops(void **state)
{
	struct sim_env *e = *state;
	df1_t *h = sim_client(e, DF1_HALF_DUPLEX_MASTER);
	struct seen s;

	seen_init(&s, h);
	s.stop_at = 2;
	assert_int_equal(df1_discover(h, 1, 5, on_station, &s), 1);
	assert_int_equal(s.calls, 2);
	assert_int_equal(s.r[1].station, 2);
	assert_true(s.r[1].answered);
}

/* The cancel fd, readable from the callback on: DF1_E_INTR before the next station. */
static void test_it_discover_cancel_between_stations(void **state)
{
	struct sim_env *e = *state;
	df1_t *h = sim_client(e, DF1_HALF_DUPLEX_MASTER);
	struct seen s;
	int p[2];

	assert_int_equal(pipe(p), 0);
	assert_int_equal(df1_set_cancel_fd(h, p[0]), 0);
	seen_init(&s, h);
	s.cancel_at = 2;
	s.cancel_wr = p[1];
	assert_int_equal(df1_discover(h, 1, 5, on_station, &s), DF1_E_INTR);
	assert_int_equal(s.calls, 2);
	assert_int_equal(df1_last_error(h)->code, DF1_E_INTR);
	df1_set_cancel_fd(h, -1);
	close(p[0]);
	close(p[1]);
}

/* Discover 1..5 until it finds `want` stations, at most `tries` times (df1sim
 * takes a signal at its next wait). Returns the last count. */
static int discover_until(df1_t *h, int want, int tries)
{
	int n = -1;

	for (int i = 0; i < tries && n != want; i++) {
		n = df1_discover(h, 1, 5, NULL, NULL);
		if (n != want)
			usleep(50 * 1000);
	}
	return n;
}

/* SIGUSR1 mutes every station of df1sim: nobody answers; SIGUSR2: back. */
static void test_it_discover_half_all_muted(void **state)
{
	struct sim_env *e = *state;
	df1_t *h = sim_client(e, DF1_HALF_DUPLEX_MASTER);
	struct seen s;

	assert_int_equal(kill(e->sim.pid, SIGUSR1), 0);
	assert_int_equal(discover_until(h, 0, 40), 0);
	seen_init(&s, h);
	assert_int_equal(df1_discover(h, 1, 5, on_station, &s), 0);
	assert_int_equal(s.calls, 5);
	for (int i = 0; i < 5; i++)
		assert_false(s.r[i].answered);
	assert_int_equal(kill(e->sim.pid, SIGUSR2), 0);
	assert_int_equal(discover_until(h, 2, 40), 2);
}

/* Full duplex: the point-to-point peer answers whatever the DST. */
static void test_it_discover_full_peer_any_dst(void **state)
{
	struct sim_env *e = *state;
	df1_t *h = sim_client(e, DF1_FULL_DUPLEX);
	struct seen s;

	seen_init(&s, h);
	assert_int_equal(df1_discover(h, 1, 3, on_station, &s), 3);
	assert_int_equal(s.calls, 3);
	for (int i = 0; i < 3; i++) {
		assert_int_equal(s.r[i].station, 1 + i);
		assert_true(s.r[i].answered);
		assert_true(s.r[i].identified);
		assert_int_equal(s.r[i].status.type_code, 0x5B);
		assert_string_equal(s.r[i].status.name, "SLC 5/04");
		assert_true(s.r[i].rtt_us > 0);
	}
}

/* Full duplex, the peer muted: the DLE ENQ goes unanswered, nothing is probed. */
static void test_it_discover_full_muted_line_error(void **state)
{
	struct sim_env *e = *state;
	df1_t *h = sim_client(e, DF1_FULL_DUPLEX);
	struct seen s;
	int rc = 0;

	assert_int_equal(kill(e->sim.pid, SIGUSR1), 0);
	for (int i = 0; i < 40; i++) {
		seen_init(&s, h);
		rc = df1_discover(h, 1, 3, on_station, &s);
		if (rc < 0)
			break;
		usleep(50 * 1000);
	}
	assert_int_equal(rc, DF1_E_TIMEOUT);
	assert_int_equal(s.calls, 0);
	assert_int_equal(kill(e->sim.pid, SIGUSR2), 0);
	for (int i = 0; i < 40 && rc != 1; i++) {
		rc = df1_discover(h, 1, 1, NULL, NULL);
		if (rc != 1)
			usleep(50 * 1000);
	}
	assert_int_equal(rc, 1);
}

static int it_test_teardown(void **state)
{
	struct sim_env *e = *state;

	if (e) {
		df1_free(e->h);
		e->h = NULL;
	}
	return 0;
}

int main(void)
{
	const struct CMUnitTest unit[] = {
		cmocka_unit_test(test_discover_bad_arguments_inval),
		cmocka_unit_test(test_discover_not_open_fails),
		cmocka_unit_test(test_discover_half_duplex_slave_notsup),
		cmocka_unit_test(test_discover_cancel_fd_readable_intr_nothing_sent),
		cmocka_unit_test(test_discover_full_line_silent_error_no_callback),
		cmocka_unit_test(test_discover_probe_full_sends_empty_echo),
		cmocka_unit_test(test_discover_probe_half_polls_eot_answers),
		cmocka_unit_test(test_discover_remote_error_answered_not_identified),
	};
	const struct CMUnitTest half[] = {
		cmocka_unit_test_teardown(test_it_discover_half_several_stations, it_test_teardown),
		cmocka_unit_test_teardown(test_it_discover_callback_stops, it_test_teardown),
		cmocka_unit_test_teardown(test_it_discover_cancel_between_stations, it_test_teardown),
		cmocka_unit_test_teardown(test_it_discover_half_all_muted, it_test_teardown),
	};
	const struct CMUnitTest full[] = {
		cmocka_unit_test_teardown(test_it_discover_full_peer_any_dst, it_test_teardown),
		cmocka_unit_test_teardown(test_it_discover_full_muted_line_error, it_test_teardown),
	};
	int r = 0;

	r |= cmocka_run_group_tests_name("discover_unit", unit, NULL, NULL);
	r |= cmocka_run_group_tests_name("discover_half", half, setup_half, sim_teardown);
	r |= cmocka_run_group_tests_name("discover_full", full, setup_full, sim_teardown);
	return r;
}
