/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_eip_limits.c - the EtherNet/IP server's limits (lib/eip/eip_limits.c,
 * df1_eip_server_set_limits(3)): the decisions on a connection's times, then
 * the server on real loopback sockets: a connection without a session and an
 * idle session are closed, a full table evicts for a new client (one without
 * a session first, then the longest idle), no_evict refuses instead; counted
 * and reported. Expectations from df1-eip(7) "Limits"; times are generous.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
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
#include "eip/eip_limits.h"

/* ---- the decisions ---- */

static void test_limits_defaults_and_ranges(void **state)
{
	struct df1_eip_server_limits in = { 0 };
	struct eip_limits l;
	(void)state;

	assert_int_equal(eip_limits_from(&l, &in), 0);
	assert_int_equal(l.register_ms, 5000);
	assert_int_equal(l.idle_ms, 120000);       /* ODVA's inactivity timeout, 120 s */
	assert_false(l.no_evict);
	in.register_ms = -1;
	in.idle_ms = 3600000;
	assert_int_equal(eip_limits_from(&l, &in), 0);
	assert_int_equal(l.register_ms, -1);
	assert_int_equal(l.idle_ms, 3600000);
	in.idle_ms = 3600001;
	assert_int_equal(eip_limits_from(&l, &in), -1);
	in.idle_ms = -2;
	assert_int_equal(eip_limits_from(&l, &in), -1);
}

static void test_limits_due(void **state)
{
	struct eip_limits l = { 1000, 5000, false };
	struct eip_age a = { .opened_ms = 100, .last_ms = 100 };
	int64_t next = EIP_NO_DEADLINE;
	(void)state;

	/* no session: due 1000 ms after it connected, whatever it sent */
	a.last_ms = 1000;
	assert_int_equal(eip_age_due(&l, &a, 1099, &next), -1);
	assert_int_equal(next, 1100);
	assert_int_equal(eip_age_due(&l, &a, 1100, &next), DF1_EIP_CLOSE_NO_SESSION);
	/* a session: due 5000 ms after its last message */
	a.registered = true;
	next = EIP_NO_DEADLINE;
	assert_int_equal(eip_age_due(&l, &a, 5999, &next), -1);
	assert_int_equal(next, 6000);
	assert_int_equal(eip_age_due(&l, &a, 6000, &next), DF1_EIP_CLOSE_IDLE);
	/* a request with the caller: never for time */
	a.busy = true;
	next = EIP_NO_DEADLINE;
	assert_int_equal(eip_age_due(&l, &a, 1000000, &next), -1);
	assert_true(next == EIP_NO_DEADLINE);
	/* limits off */
	a.busy = false;
	l.idle_ms = -1;
	assert_int_equal(eip_age_due(&l, &a, 1000000, &next), -1);
	a.registered = false;
	l.register_ms = -1;
	assert_int_equal(eip_age_due(&l, &a, 1000000, &next), -1);
	assert_true(next == EIP_NO_DEADLINE);
}

static void test_limits_eviction_order(void **state)
{
	struct eip_age fresh_nosess = { .last_ms = 900 }, old_sess = { .last_ms = 100, .registered = true };
	struct eip_age older_sess = { .last_ms = 50, .registered = true }, busy = { .last_ms = 0, .busy = true };
	(void)state;

	assert_true(eip_age_before(&fresh_nosess, &old_sess));     /* no session goes first */
	assert_false(eip_age_before(&old_sess, &fresh_nosess));
	assert_true(eip_age_before(&older_sess, &old_sess));       /* then the longest idle */
	assert_false(eip_age_before(&busy, &old_sess));            /* a busy one never */
	assert_true(eip_age_before(&old_sess, &busy));
}

/* ---- the server on sockets ---- */

#define REGISTER_HEX "65 00 04 00 00 00 00 00 00 00 00 00 11 22 33 44 55 66 77 88 00 00 00 00 01 00 00 00"

struct closed {
	int n[3];
	char peer[64];
};

static void on_close(void *user, const char *peer, enum df1_eip_close_reason why)
{
	struct closed *c = user;

	assert_true(why <= DF1_EIP_CLOSE_EVICTED);
	c->n[why]++;
	snprintf(c->peer, sizeof c->peer, "%s", peer);
}

static void on_pccc(void *user, df1_eip_server_t *s, uint32_t request, int station, const uint8_t *pccc, size_t n)
{
	(void)user, (void)s, (void)request, (void)station, (void)pccc, (void)n;
}

static size_t hex(const char *s, uint8_t *out, size_t cap)
{
	size_t n = 0;

	while (*s && n < cap) {
		if (*s == ' ') {
			s++;
			continue;
		}
		out[n++] = (uint8_t)strtoul((char[3]){ s[0], s[1], 0 }, NULL, 16);
		s += 2;
	}
	return n;
}

static df1_eip_server_t *server(int max_clients, const struct df1_eip_server_limits *l)
{
	struct df1_eip_server_config c;
	df1_eip_server_t *s;

	memset(&c, 0, sizeof c);
	c.listen = "0";
	c.max_clients = max_clients;
	assert_int_equal(df1_eip_server_new(&s, &c, on_pccc, NULL), 0);
	assert_int_equal(df1_eip_server_set_limits(s, l), 0);
	return s;
}

static int connect_to(df1_eip_server_t *s)
{
	struct sockaddr_in a;
	int fd = socket(AF_INET, SOCK_STREAM, 0);

	assert_true(fd >= 0);
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_port = htons((uint16_t)atoi(strchr(df1_eip_server_address(s), ':') + 1));
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(connect(fd, (struct sockaddr *)&a, sizeof a), 0);
	return fd;
}

/* Serve until fd has a whole message (1) or is closed by the server (0); 5 s at most. */
static int serve_until(df1_eip_server_t *s, int fd, uint8_t *buf, size_t cap)
{
	size_t got = 0;

	for (int i = 0; i < 500; i++) {
		struct pollfd p[2] = { { df1_eip_server_fd(s), POLLIN, 0 }, { fd, POLLIN, 0 } };
		ssize_t r;

		(void)poll(p, 2, 10);
		assert_true(df1_eip_server_process(s) >= 0);
		r = recv(fd, buf + got, cap - got, MSG_DONTWAIT);
		if (r == 0)
			return 0;
		if (r > 0)
			got += (size_t)r;
		if (got >= EIP_HDR_LEN && got >= eip_msg_len(buf, got))
			return 1;
	}
	fail_msg("fd %d: neither a reply nor closed in 5 s", fd);
	return -1;
}

static void register_session(df1_eip_server_t *s, int fd)
{
	uint8_t msg[64], in[64];
	size_t n = hex(REGISTER_HEX, msg, sizeof msg);

	assert_int_equal(send(fd, msg, n, 0), (ssize_t)n);
	assert_int_equal(serve_until(s, fd, in, sizeof in), 1);
	assert_int_equal(in[0], 0x65);
	assert_int_equal(in[8] | in[9] << 8, 0);      /* status: success */
}

static void test_server_closes_no_session_and_idle(void **state)
{
	struct closed seen = { { 0 }, "" };
	struct df1_eip_server_limits l = { .register_ms = 100, .idle_ms = 300, .on_close = on_close, .user = &seen };
	struct df1_eip_server_closes cl;
	df1_eip_server_t *s = server(4, &l);
	uint8_t buf[64];
	int silent, idle;
	(void)state;

	silent = connect_to(s);
	idle = connect_to(s);
	register_session(s, idle);
	assert_int_equal(serve_until(s, silent, buf, sizeof buf), 0);
	assert_int_equal(serve_until(s, idle, buf, sizeof buf), 0);
	df1_eip_server_closes(s, &cl);
	assert_int_equal(cl.no_session, 1);
	assert_int_equal(cl.idle, 1);
	assert_int_equal(cl.evicted, 0);
	assert_int_equal(seen.n[DF1_EIP_CLOSE_NO_SESSION], 1);
	assert_int_equal(seen.n[DF1_EIP_CLOSE_IDLE], 1);
	assert_int_equal(strncmp(seen.peer, "127.0.0.1:", 10), 0);
	close(silent);
	close(idle);
	df1_eip_server_free(s);
}

static void test_server_full_table_evicts(void **state)
{
	struct closed seen = { { 0 }, "" };
	struct df1_eip_server_limits l = { .on_close = on_close, .user = &seen };   /* the defaults */
	struct df1_eip_server_closes cl;
	struct df1_eip_server_stats st;
	df1_eip_server_t *s = server(3, &l);
	uint8_t buf[64];
	int sess1, sess2, nosess, fresh, fresh2;
	(void)state;

	sess1 = connect_to(s);
	register_session(s, sess1);
	nosess = connect_to(s);
	sess2 = connect_to(s);
	register_session(s, sess2);
	/* full: the one without a session makes room */
	fresh = connect_to(s);
	register_session(s, fresh);
	assert_int_equal(serve_until(s, nosess, buf, sizeof buf), 0);
	/* full again: the longest idle session (sess1) makes room */
	fresh2 = connect_to(s);
	register_session(s, fresh2);
	assert_int_equal(serve_until(s, sess1, buf, sizeof buf), 0);
	df1_eip_server_closes(s, &cl);
	assert_int_equal(cl.evicted, 2);
	assert_int_equal(cl.no_session + cl.idle, 0);
	assert_int_equal(seen.n[DF1_EIP_CLOSE_EVICTED], 2);
	df1_eip_server_stats(s, &st);
	assert_int_equal(st.refused_clients, 0);
	assert_int_equal(st.sessions_open, 3);
	close(sess1);
	close(sess2);
	close(nosess);
	close(fresh);
	close(fresh2);
	df1_eip_server_free(s);
}

static void test_server_no_evict_refuses(void **state)
{
	struct df1_eip_server_limits l = { .no_evict = true };
	struct df1_eip_server_stats st;
	df1_eip_server_t *s = server(1, &l);
	uint8_t buf[64];
	int first, second;
	(void)state;

	first = connect_to(s);
	register_session(s, first);
	second = connect_to(s);
	assert_int_equal(serve_until(s, second, buf, sizeof buf), 0);
	df1_eip_server_stats(s, &st);
	assert_int_equal(st.refused_clients, 1);
	/* out of range, and NULL */
	l.idle_ms = 3600001;
	assert_int_equal(df1_eip_server_set_limits(s, &l), DF1_E_INVAL);
	assert_non_null(strstr(df1_eip_server_error(s), "idle_ms 3600001"));
	assert_int_equal(df1_eip_server_set_limits(s, NULL), DF1_E_INVAL);
	assert_int_equal(df1_eip_server_set_limits(NULL, &l), DF1_E_INVAL);
	close(first);
	close(second);
	df1_eip_server_free(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_limits_defaults_and_ranges),
		cmocka_unit_test(test_limits_due),
		cmocka_unit_test(test_limits_eviction_order),
		cmocka_unit_test(test_server_closes_no_session_and_idle),
		cmocka_unit_test(test_server_full_table_evicts),
		cmocka_unit_test(test_server_no_evict_refuses),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
