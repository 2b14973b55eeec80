/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_port_rfc2217 - the rfc2217:// backend (lib/port/port_rfc2217.c)
 * against a scripted device server on a loopback socket (a thread here).
 * Every byte string the server expects or sends is written by hand from RFC
 * 854 (IAC FF, SB FA, SE F0, WILL FB, DO FD, DONT FE; a data byte FF doubled),
 * RFC 856 (BINARY = 00) and RFC 2217 (COM-PORT-OPTION = 2C; SET-BAUDRATE 01
 * with four bytes in network order, SET-DATASIZE 02, SET-PARITY 03 with 01
 * none 02 odd 03 even, SET-STOPSIZE 04, SET-CONTROL 05 with 01 no flow
 * control, PURGE-DATA 0C with 03 both; answers carry the code + 100 = 0x64).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "df1_int.h"

enum script { S_OK, S_REFUSE_PARITY, S_DONT, S_SILENT_CONTROL };

struct server {
	int lfd, port;
	enum script script;
	pthread_t th;
	uint8_t got[1024];          /* everything the client sent, in order */
	size_t n;
	int fd;                     /* the accepted connection, kept open for the test */
};

/* Read until the client has sent at least want bytes in all, or 2 s pass. */
static void srv_read(struct server *s, size_t want)
{
	while (s->n < want) {
		struct pollfd p = { s->fd, POLLIN, 0 };
		ssize_t r;

		if (poll(&p, 1, 2000) <= 0)
			return;
		r = read(s->fd, s->got + s->n, sizeof s->got - s->n);
		if (r <= 0)
			return;
		s->n += (size_t)r;
	}
}

static void srv_send(struct server *s, const uint8_t *b, size_t n)
{
	assert_int_equal(write(s->fd, b, n), (ssize_t)n);
}

/* What the client sends at open with the defaults (19200 8N1, no handshake). */
static const uint8_t offer[] = { 0xFF, 0xFB, 0x2C, 0xFF, 0xFB, 0x00, 0xFF, 0xFD, 0x00 };
static const uint8_t dont_echo[] = { 0xFF, 0xFE, 0x01 };
static const uint8_t sets_19200_8n1[] = {
	0xFF, 0xFA, 0x2C, 0x01, 0x00, 0x00, 0x4B, 0x00, 0xFF, 0xF0,
	0xFF, 0xFA, 0x2C, 0x02, 0x08, 0xFF, 0xF0,
	0xFF, 0xFA, 0x2C, 0x03, 0x01, 0xFF, 0xF0,
	0xFF, 0xFA, 0x2C, 0x04, 0x01, 0xFF, 0xF0,
	0xFF, 0xFA, 0x2C, 0x05, 0x01, 0xFF, 0xF0,
	0xFF, 0xFA, 0x2C, 0x0C, 0x03, 0xFF, 0xF0,
};

static void *srv_main(void *arg)
{
	struct server *s = arg;
	static const uint8_t do_comport[] = { 0xFF, 0xFD, 0x2C, 0xFF, 0xFB, 0x01 }; /* + WILL ECHO */
	static const uint8_t dont_comport[] = { 0xFF, 0xFE, 0x2C };
	uint8_t ans[sizeof sets_19200_8n1];

	s->fd = accept(s->lfd, NULL, NULL);
	if (s->fd < 0)
		return NULL;
	srv_read(s, sizeof offer);
	if (s->script == S_DONT) {
		srv_send(s, dont_comport, sizeof dont_comport);
		return NULL;
	}
	srv_send(s, do_comport, sizeof do_comport);
	srv_read(s, sizeof offer + sizeof dont_echo + sizeof sets_19200_8n1);
	/* the answers: each command + 0x64 with the value asked (or another one) */
	memcpy(ans, sets_19200_8n1, sizeof ans);
	for (size_t i = 0; i + 3 < sizeof ans; i++)
		if (ans[i] == 0xFF && ans[i + 1] == 0xFA && ans[i + 2] == 0x2C)
			ans[i + 3] += 0x64;
	if (s->script == S_REFUSE_PARITY)
		ans[17 + 4] = 0x02;                     /* "odd" instead of none */
	if (s->script == S_SILENT_CONTROL) {
		srv_send(s, ans, 31);                  /* baud .. stop size, nothing after */
		return NULL;
	}
	srv_send(s, ans, sizeof ans);
	return NULL;
}

static void srv_start(struct server *s, enum script sc)
{
	struct sockaddr_in a = { .sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK) };
	socklen_t len = sizeof a;

	memset(s, 0, sizeof *s);
	s->fd = -1;
	s->script = sc;
	s->lfd = socket(AF_INET, SOCK_STREAM, 0);
	assert_true(s->lfd >= 0);
	assert_int_equal(bind(s->lfd, (struct sockaddr *)&a, sizeof a), 0);
	assert_int_equal(listen(s->lfd, 1), 0);
	assert_int_equal(getsockname(s->lfd, (struct sockaddr *)&a, &len), 0);
	s->port = ntohs(a.sin_port);
	assert_int_equal(pthread_create(&s->th, NULL, srv_main, s), 0);
}

static void srv_stop(struct server *s)
{
	pthread_join(s->th, NULL);
	if (s->fd >= 0)
		close(s->fd);
	close(s->lfd);
}

static int open_on(df1_t *h, const struct server *s)
{
	char target[64];

	snprintf(target, sizeof target, "rfc2217://127.0.0.1:%d", s->port);
	return df1_open(h, target);
}

static void test_negotiation_and_settings(void **state)
{
	struct server s;
	df1_t *h;

	(void)state;
	srv_start(&s, S_OK);
	assert_int_equal(df1_new(&h), 0);
	df1_set_timeout_ms(h, 1000);
	assert_int_equal(open_on(h, &s), 0);
	srv_stop(&s);
	/* the offer, the refusal of the server's WILL ECHO, the settings in order */
	assert_int_equal(s.n, sizeof offer + sizeof dont_echo + sizeof sets_19200_8n1);
	assert_memory_equal(s.got, offer, sizeof offer);
	assert_memory_equal(s.got + sizeof offer, dont_echo, sizeof dont_echo);
	assert_memory_equal(s.got + sizeof offer + sizeof dont_echo, sets_19200_8n1,
	                    sizeof sets_19200_8n1);
	assert_true(df1_is_open(h));
	df1_free(h);
}

static void test_data_iac_both_ways(void **state)
{
	static const uint8_t from_server[] = { 0x10, 0x02, 0xFF, 0xFF, 0x10, 0x03, 0xFF, 0xFF };
	static const uint8_t data_in[] = { 0x10, 0x02, 0xFF, 0x10, 0x03, 0xFF };
	static const uint8_t data_out[] = { 0xFF, 0x10, 0x06, 0xFF };
	static const uint8_t on_wire[] = { 0xFF, 0xFF, 0x10, 0x06, 0xFF, 0xFF };
	uint8_t buf[64];
	size_t n = 0;
	struct server s;
	df1_t *h;

	(void)state;
	srv_start(&s, S_OK);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(open_on(h, &s), 0);
	pthread_join(s.th, NULL);   /* the server's script is done; s.fd stays open */
	srv_send(&s, from_server, sizeof from_server);
	while (n < sizeof data_in) {
		ssize_t r = h->port->read(h, buf + n, sizeof buf - n, df1_now_ms() + 2000);

		assert_true(r > 0);
		n += (size_t)r;
	}
	assert_int_equal(n, sizeof data_in);
	assert_memory_equal(buf, data_in, sizeof data_in);
	assert_int_equal(h->port->write(h, data_out, sizeof data_out, df1_now_ms() + 2000),
	                 sizeof data_out);
	s.n = 0;
	srv_read(&s, sizeof on_wire);
	assert_int_equal(s.n, sizeof on_wire);
	assert_memory_equal(s.got, on_wire, sizeof on_wire);
	df1_free(h);
	close(s.fd);
	close(s.lfd);
}

static void test_refused_setting_is_named(void **state)
{
	struct server s;
	df1_t *h;

	(void)state;
	srv_start(&s, S_REFUSE_PARITY);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(open_on(h, &s), DF1_E_NOTSUP);
	srv_stop(&s);
	assert_non_null(strstr(df1_last_error(h)->message, "SET-PARITY"));
	assert_non_null(strstr(df1_last_error(h)->message, "no parity"));
	assert_false(df1_is_open(h));
	df1_free(h);
}

static void test_unanswered_setting_is_named(void **state)
{
	struct server s;
	df1_t *h;

	(void)state;
	srv_start(&s, S_SILENT_CONTROL);
	assert_int_equal(df1_new(&h), 0);
	df1_set_timeout_ms(h, 200);   /* the wait is at least 1 s */
	assert_int_equal(open_on(h, &s), DF1_E_NOTSUP);
	srv_stop(&s);
	assert_non_null(strstr(df1_last_error(h)->message, "did not answer SET-CONTROL"));
	df1_free(h);
}

static void test_server_refusing_the_option(void **state)
{
	struct server s;
	df1_t *h;

	(void)state;
	srv_start(&s, S_DONT);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(open_on(h, &s), DF1_E_NOTSUP);
	srv_stop(&s);
	assert_non_null(strstr(df1_last_error(h)->message, "does not speak RFC 2217"));
	df1_free(h);
}

static void test_bad_targets(void **state)
{
	static const char *const bad[] = { "rfc2217://", "rfc2217://host", "rfc2217://host:0",
	                                   "rfc2217://host:70000", "rfc2217:host:1/x" };
	df1_t *h;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		assert_int_equal(df1_open(h, bad[i]), DF1_E_INVAL);
		assert_non_null(strstr(df1_last_error(h)->message, "RFC 2217 target"));
	}
	df1_free(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_negotiation_and_settings),
		cmocka_unit_test(test_data_iac_both_ways),
		cmocka_unit_test(test_refused_setting_is_named),
		cmocka_unit_test(test_unanswered_setting_is_named),
		cmocka_unit_test(test_server_refusing_the_option),
		cmocka_unit_test(test_bad_targets),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
