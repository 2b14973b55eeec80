/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_port_scheme.c - the table of target schemes (lib/scheme.c): which
 * backend and link each target opens, in any case of its scheme; the
 * capabilities each backend declares (lib/port/port.h); and the network
 * file's Com_Port (lib/config/config_net.c), which reads targets through the
 * same table and accepts and refuses what it did before the table.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "df1_int.h"
#include "scheme.h"
#include "eip/eip_link.h"

/* ---- the table -------------------------------------------------------------- */

/* Every row has a backend that opens a target, and no name twice; a new
 * scheme is a row more, so the rows are not counted here. */
static void test_scheme_rows(void **state)
{
	const struct scheme_row *s, *t;
	char target[64];

	(void)state;
	for (s = scheme_rows; s->name; s++) {
		assert_non_null(s->port);
		assert_non_null(s->port->open);
		for (t = scheme_rows; t != s; t++)
			assert_true(strcasecmp(t->name, s->name) != 0);
		snprintf(target, sizeof target, "%s://x:1", s->name);
		assert_ptr_equal(scheme_find(target), s);
	}
	/* the default row: a device path on termios, the DF1 link */
	assert_ptr_equal(s->port, &port_termios_ops);
	assert_null(s->link);
}

static void test_scheme_find(void **state)
{
	static const struct {
		const char *target;
		const char *name;            /* NULL: the default row */
		const struct port_ops *port;
		const struct own_link_ops *link;
	} cases[] = {
		{ "tcp://127.0.0.1:2222", "tcp", &port_tcp_ops, NULL },
		{ "tcp:plc-gw:10001", "tcp", &port_tcp_ops, NULL },  /* "//" or not */
		{ "eip://10.0.0.5", "eip", &port_tcp_ops, &eip_link_ops },
		{ "eip://[::1]:44818/2", "eip", &port_tcp_ops, &eip_link_ops },
		{ "rfc2217://127.0.0.1:2217", "rfc2217", &port_rfc2217_ops, NULL },
		{ "RFC2217:moxa:4001", "rfc2217", &port_rfc2217_ops, NULL },
		{ "/dev/ttyS0", NULL, &port_termios_ops, NULL },
		{ "ttyUSB0", NULL, &port_termios_ops, NULL },
		{ "", NULL, &port_termios_ops, NULL },
	};

	(void)state;
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const struct scheme_row *s = scheme_find(cases[i].target);

		if (cases[i].name)
			assert_string_equal(s->name, cases[i].name);
		else
			assert_null(s->name);
		assert_ptr_equal(s->port, cases[i].port);
		assert_ptr_equal(s->link, cases[i].link);
	}
}

/* A URI scheme is case-insensitive (RFC 3986 3.1). */
static void test_scheme_case(void **state)
{
	static const char *const tcp[] = { "TCP://h:1", "Tcp://h:1", "tCP:h:1" };
	static const char *const eip[] = { "EIP://h", "Eip://h:44818", "eIp:h" };

	(void)state;
	for (size_t i = 0; i < 3; i++) {
		assert_ptr_equal(scheme_find(tcp[i])->port, &port_tcp_ops);
		assert_null(scheme_find(tcp[i])->link);
		assert_ptr_equal(scheme_find(eip[i])->link, &eip_link_ops);
	}
}

/* A target of no known scheme is a device path, as df1_open() always read it:
 * "foo://x" opens (and fails) on termios, naming the target. */
static void test_scheme_unknown(void **state)
{
	static const char *const other[] = { "foo://x", "tcpx://h:1", "tcp", "eipx:h", "nosuch://h:1" };
	df1_t *h;
	int r;

	(void)state;
	for (size_t i = 0; i < sizeof other / sizeof other[0]; i++) {
		const struct scheme_row *s = scheme_find(other[i]);

		assert_null(s->name);
		assert_ptr_equal(s->port, &port_termios_ops);
		assert_null(s->link);
	}
	assert_int_equal(df1_new(&h), 0);
	r = df1_open(h, "foo://nowhere");
	assert_int_equal(r, DF1_E_NODEV);
	assert_false(df1_is_open(h));
	assert_non_null(strstr(df1_last_error(h)->message, "foo://nowhere"));
	df1_free(h);
}

/* An own link that fails to open leaves the handle closed, no link kept. */
static void test_scheme_own_link_fails(void **state)
{
	df1_t *h;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_timeout_ms(h, 1000), 0);
	assert_true(df1_open(h, "EIP://127.0.0.1:1") < 0); /* nobody listens on port 1 */
	assert_false(df1_is_open(h));
	assert_null(h->own_link);
	assert_null(h->own_link_data);
	assert_null(h->port);
	df1_free(h);
}

/* ---- capabilities ------------------------------------------------------------- */

static void test_port_capabilities(void **state)
{
	(void)state;
	/* a local UART: its bytes take line time */
	assert_true(port_termios_ops.paced);
	assert_false(port_termios_ops.net_slack);
	assert_false(port_termios_ops.serial_behind_net);
	/* a device server: network slack, a serial line behind it */
	assert_false(port_tcp_ops.paced);
	assert_true(port_tcp_ops.net_slack);
	assert_true(port_tcp_ops.serial_behind_net);
	/* an RFC 2217 device server: a serial line at the baud we set, behind a network */
	assert_true(port_rfc2217_ops.paced);
	assert_true(port_rfc2217_ops.net_slack);
	assert_true(port_rfc2217_ops.serial_behind_net);
	assert_non_null(port_rfc2217_ops.configure);
	assert_non_null(port_rfc2217_ops.config_ok);
	/* a descriptor (pty, socket, pipe): none */
	assert_false(port_fd_ops.paced);
	assert_false(port_fd_ops.net_slack);
	assert_false(port_fd_ops.serial_behind_net);
	/* only tcp targets are written in a network file; only fd holds a peer */
	assert_null(port_termios_ops.config_ok);
	assert_non_null(port_tcp_ops.config_ok);
	assert_null(port_fd_ops.config_ok);
	assert_null(port_termios_ops.peer);
	assert_null(port_tcp_ops.peer);
	assert_non_null(port_fd_ops.peer);
}

static void test_own_link_ops(void **state)
{
	(void)state;
	assert_string_equal(eip_link_ops.scheme, "eip://");
	assert_non_null(eip_link_ops.open);
	assert_non_null(eip_link_ops.close);
	assert_non_null(eip_link_ops.transact);
	assert_non_null(eip_link_ops.test);
}

static void test_tcp_config_ok(void **state)
{
	bool (*ok)(const char *) = port_tcp_ops.config_ok;

	(void)state;
	assert_true(ok("127.0.0.1:2222"));
	assert_true(ok("[::1]:2222"));
	assert_true(ok("h:65535"));
	assert_true(ok("h:00502"));
	assert_false(ok("h"));
	assert_false(ok(":2222"));
	assert_false(ok("h:"));
	assert_false(ok("h:0"));
	assert_false(ok("h:65536"));
	assert_false(ok("h:+502"));
	assert_false(ok("h:502/"));
	assert_false(ok("h:99999999999999999999"));
}

/* ---- the network file's Com_Port ---------------------------------------------- */

static int load_com_port(const char *value, struct df1_net_config *c)
{
	char path[64], text[160];
	int fd, rc, n;

	n = snprintf(text, sizeof text, "Com_Port\n%s\n", value);
	snprintf(path, sizeof path, "/tmp/df1_test_scheme_XXXXXX");
	fd = mkstemp(path);
	assert_true(fd >= 0);
	assert_int_equal(write(fd, text, (size_t)n), n);
	close(fd);
	rc = df1_net_config_load(path, c, NULL, NULL);
	unlink(path);
	return rc;
}

static void test_config_com_port_accepts(void **state)
{
	static const struct {
		const char *value, *want;
	} cases[] = {
		{ "1", "/dev/ttyS0" },
		{ "COM2", "/dev/ttyS1" },
		{ "/dev/ttyUSB0", "/dev/ttyUSB0" },
		{ "tcp://127.0.0.1:2222", "tcp://127.0.0.1:2222" },
		{ "TCP://plc-gw:10001", "tcp://plc-gw:10001" },
		{ "Tcp://H:1", "tcp://H:1" },
		{ "tcp://[::1]:2222", "tcp://[::1]:2222" },
		{ "tcp://h:00502", "tcp://h:00502" },
		{ "tcp://a:b:502", "tcp://a:b:502" }, /* as before: opening it fails */
	};

	(void)state;
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		struct df1_net_config c;

		if (load_com_port(cases[i].value, &c) != 0)
			fail_msg("Com_Port %s refused", cases[i].value);
		assert_string_equal(c.port, cases[i].want);
	}
}

/* Refused with the message and catalog ID 0 of tests/unit/config/test_config.c. */
static void test_config_com_port_refuses(void **state)
{
	static const char *const bad[] = {
		"0", "257", "ttyUSB0", "tcp://host", "tcp://:2222", "tcp://host:0",
		"tcp://host:65536", "tcp://host:", "tcp://host:502/", "tcp:host:502",
		"eip://10.0.0.5", "EIP://10.0.0.5:44818", "foo://host:1", "nosuch://host:1",
		"tcp", "tcp://h:+1",
	};

	(void)state;
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		struct df1_net_config c;

		if (load_com_port(bad[i], &c) != DF1_E_CONFIG)
			fail_msg("Com_Port %s accepted", bad[i]);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_scheme_rows),
		cmocka_unit_test(test_scheme_find),
		cmocka_unit_test(test_scheme_case),
		cmocka_unit_test(test_scheme_unknown),
		cmocka_unit_test(test_scheme_own_link_fails),
		cmocka_unit_test(test_port_capabilities),
		cmocka_unit_test(test_own_link_ops),
		cmocka_unit_test(test_tcp_config_ok),
		cmocka_unit_test(test_config_com_port_accepts),
		cmocka_unit_test(test_config_com_port_refuses),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
