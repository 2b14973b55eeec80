/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_health.c - df1gw's pure health parts: the notification protocol
 * (tools/df1gw/gw_notify.c) against a real AF_UNIX datagram socket, as
 * sd_notify(3) and systemd.service(5) describe it (a path or an @abstract
 * NOTIFY_SOCKET, nothing without one, WATCHDOG_USEC halved, WATCHDOG_PID of
 * another process ignored, STATUS= only when it changes, READY=1 once per
 * start or reload); the metrics sink (gw_msink.c) against the Prometheus
 * text exposition format 0.0.4 (escapes of HELP and label values, NaN,
 * +Inf) and its JSON; the status page's files (gw_page.c).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "df1gw/gw_metrics.h"
#include "df1gw/gw_notify.h"
#include "df1gw/gw_page.h"

/* ---- the notification socket: the service manager's end ---- */

struct mgr {
	int fd;
	char env[108];
	char path[108];
};

static void mgr_open(struct mgr *m, bool abstract)
{
	struct sockaddr_un a = { .sun_family = AF_UNIX };
	socklen_t len;

	m->fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_NONBLOCK, 0);
	assert_true(m->fd >= 0);
	if (abstract) {
		snprintf(m->env, sizeof m->env, "@df1test-notify-%ld", (long)getpid());
		memcpy(a.sun_path + 1, m->env + 1, strlen(m->env) - 1);
		len = (socklen_t)(offsetof(struct sockaddr_un, sun_path) + strlen(m->env));
		m->path[0] = '\0';
	} else {
		snprintf(m->path, sizeof m->path, "/tmp/df1test-notify-%ld", (long)getpid());
		unlink(m->path);
		snprintf(m->env, sizeof m->env, "%s", m->path);
		snprintf(a.sun_path, sizeof a.sun_path, "%s", m->path);
		len = sizeof a;
	}
	assert_int_equal(bind(m->fd, (struct sockaddr *)&a, len), 0);
}

static void mgr_close(struct mgr *m)
{
	close(m->fd);
	if (m->path[0])
		unlink(m->path);
}

/* The next datagram, "" when none is there. */
static const char *mgr_recv(struct mgr *m)
{
	static char buf[512];
	ssize_t n = recv(m->fd, buf, sizeof buf - 1, 0);

	buf[n > 0 ? n : 0] = '\0';
	return buf;
}

static void test_notify_without_socket_sends_nothing(void **state)
{
	struct gw_notify n;
	char err[128];

	(void)state;
	unsetenv("NOTIFY_SOCKET");
	setenv("WATCHDOG_USEC", "1000000", 1);
	assert_int_equal(gw_notify_open(&n, 0, err, sizeof err), 0);
	assert_false(gw_notify_on(&n));
	assert_int_equal(n.fd, -1);
	assert_int_equal(gw_notify_send(&n, "READY=1"), 0);
	assert_int_equal(gw_notify_wait_ms(&n, 0), INT32_MAX);
	assert_null(getenv("WATCHDOG_USEC"));   /* taken out, as sd_notify does */
	gw_notify_close(&n);
}

static void run_protocol(bool abstract)
{
	struct mgr m;
	struct gw_notify n;
	char err[128];

	mgr_open(&m, abstract);
	setenv("NOTIFY_SOCKET", m.env, 1);
	setenv("WATCHDOG_USEC", "3000000", 1);
	unsetenv("WATCHDOG_PID");
	assert_int_equal(gw_notify_open(&n, 1000, err, sizeof err), 0);
	assert_true(gw_notify_on(&n));
	assert_null(getenv("NOTIFY_SOCKET"));
	/* half of WATCHDOG_USEC: first ping due at once, then every 1.5 s */
	assert_int_equal(gw_notify_wait_ms(&n, 1000), 0);
	gw_notify_tick(&n, 1000);
	assert_string_equal(mgr_recv(&m), "WATCHDOG=1");
	assert_int_equal(gw_notify_wait_ms(&n, 1000), 1500);
	gw_notify_tick(&n, 2499);
	assert_string_equal(mgr_recv(&m), "");
	gw_notify_tick(&n, 2500);
	assert_string_equal(mgr_recv(&m), "WATCHDOG=1");
	/* STATUS= only when it changes */
	gw_notify_status(&n, "line ok");
	assert_string_equal(mgr_recv(&m), "STATUS=line ok");
	gw_notify_status(&n, "line ok");
	assert_string_equal(mgr_recv(&m), "");
	gw_notify_status(&n, "line down");
	assert_string_equal(mgr_recv(&m), "STATUS=line down");
	/* READY=1 once; again after RELOADING=1 */
	gw_notify_ready(&n);
	assert_string_equal(mgr_recv(&m), "READY=1");
	gw_notify_ready(&n);
	assert_string_equal(mgr_recv(&m), "");
	gw_notify_reloading(&n);
	assert_memory_equal(mgr_recv(&m), "RELOADING=1\nMONOTONIC_USEC=", 27);
	gw_notify_ready(&n);
	assert_string_equal(mgr_recv(&m), "READY=1");
	assert_int_equal(gw_notify_send(&n, "STOPPING=1"), 0);
	assert_string_equal(mgr_recv(&m), "STOPPING=1");
	gw_notify_close(&n);
	mgr_close(&m);
}

static void test_notify_path_socket(void **state)
{
	(void)state;
	run_protocol(false);
}

static void test_notify_abstract_socket(void **state)
{
	(void)state;
	run_protocol(true);
}

static void test_notify_watchdog_of_another_pid_ignored(void **state)
{
	struct mgr m;
	struct gw_notify n;
	char err[128], pid[16];

	(void)state;
	mgr_open(&m, true);
	snprintf(pid, sizeof pid, "%ld", (long)getpid() + 1);
	setenv("NOTIFY_SOCKET", m.env, 1);
	setenv("WATCHDOG_USEC", "3000000", 1);
	setenv("WATCHDOG_PID", pid, 1);
	assert_int_equal(gw_notify_open(&n, 0, err, sizeof err), 0);
	assert_int_equal(gw_notify_wait_ms(&n, 0), INT32_MAX);
	gw_notify_tick(&n, 10000);
	assert_string_equal(mgr_recv(&m), "");
	gw_notify_close(&n);
	mgr_close(&m);
}

static void test_notify_bad_socket_refused(void **state)
{
	struct gw_notify n;
	char err[128];

	(void)state;
	setenv("NOTIFY_SOCKET", "relative/path", 1);
	assert_int_equal(gw_notify_open(&n, 0, err, sizeof err), -1);
	assert_non_null(strstr(err, "NOTIFY_SOCKET"));
	assert_false(gw_notify_on(&n));
}

/* ---- the metrics sink ---- */

static void test_msink_text_escapes(void **state)
{
	struct gw_buf b;
	struct gw_msink s;
	const char *l[] = { "tag", "a\"b\\c\nd", "q", "GOOD", NULL };

	(void)state;
	gw_buf_init(&b);
	s = (struct gw_msink){ .b = &b, .json = false };
	gw_msink_family(&s, "df1_x_total", "counter", "help with \\ and\nnewline");
	gw_msink_sample(&s, "df1_x_total", l, 42);
	gw_msink_sample(&s, "df1_x_total", NULL, 0.25);
	gw_msink_family(&s, "df1_y", "gauge", "y");
	gw_msink_sample(&s, "df1_y", NULL, NAN);
	gw_msink_sample(&s, "df1_y", NULL, INFINITY);
	gw_msink_end(&s);
	/* the exposition format 0.0.4: HELP escapes \\ and \n; label values \\ \" \n */
	assert_string_equal(b.p,
	                    "# HELP df1_x_total help with \\\\ and\\nnewline\n"
	                    "# TYPE df1_x_total counter\n"
	                    "df1_x_total{tag=\"a\\\"b\\\\c\\nd\",q=\"GOOD\"} 42\n"
	                    "df1_x_total 0.25\n"
	                    "# HELP df1_y y\n"
	                    "# TYPE df1_y gauge\n"
	                    "df1_y NaN\n"
	                    "df1_y +Inf\n");
	gw_buf_free(&b);
}

static void test_msink_json(void **state)
{
	struct gw_buf b;
	struct gw_msink s;
	const char *l[] = { "tag", "<b>\"x\"", NULL };

	(void)state;
	gw_buf_init(&b);
	s = (struct gw_msink){ .b = &b, .json = true };
	gw_msink_end(&s);
	assert_string_equal(b.p, "[]");
	gw_buf_reset(&b);
	s = (struct gw_msink){ .b = &b, .json = true };
	gw_msink_family(&s, "df1_a", "gauge", "a \"quoted\" help");
	gw_msink_sample(&s, "df1_a", l, 1);
	gw_msink_family(&s, "df1_b", "gauge", "b");
	gw_msink_sample(&s, "df1_b", NULL, NAN);
	gw_msink_end(&s);
	assert_string_equal(b.p,
	                    "[{\"name\":\"df1_a\",\"type\":\"gauge\",\"help\":\"a \\\"quoted\\\" help\",\"samples\":["
	                    "{\"name\":\"df1_a\",\"labels\":{\"tag\":\"<b>\\\"x\\\"\"},\"value\":1}]},"
	                    "{\"name\":\"df1_b\",\"type\":\"gauge\",\"help\":\"b\",\"samples\":["
	                    "{\"name\":\"df1_b\",\"labels\":{},\"value\":null}]}]");
	gw_buf_free(&b);
}

/* ---- the page ---- */

static void test_page_files(void **state)
{
	const struct gw_page_file *f;

	(void)state;
	f = gw_page_find("/");
	assert_non_null(f);
	assert_non_null(strstr(f->type, "text/html"));
	/* no inline script or style (the content policy allows neither), nothing from elsewhere */
	assert_null(strstr(f->body, "<script>"));
	assert_null(strstr(f->body, "<style"));
	assert_null(strstr(f->body, "http://"));
	assert_null(strstr(f->body, "https://"));
	assert_non_null(strstr(f->body, "src=\"/chart.js\""));
	assert_non_null(gw_page_find("/app.js"));
	assert_non_null(gw_page_find("/app.css"));
	f = gw_page_find("/chart.js");
	assert_non_null(f);
	assert_non_null(strstr(f->type, "text/javascript"));
	assert_int_equal(f->len, strlen(f->body));
	/* the scripts write text, never markup; the charts are SVG made
	 * element by element, each with a title and a desc */
	assert_null(strstr(gw_page_find("/app.js")->body, "innerHTML"));
	assert_null(strstr(f->body, "innerHTML"));
	assert_null(strstr(f->body, "insertAdjacentHTML"));
	assert_non_null(strstr(f->body, "createElementNS"));
	assert_non_null(strstr(f->body, "'title'"));
	assert_non_null(strstr(f->body, "'desc'"));
	assert_null(gw_page_find("/metrics"));
	assert_null(gw_page_find("/../etc/passwd"));
	assert_non_null(strstr(GW_PAGE_CSP, "frame-ancestors 'none'"));
	assert_null(strstr(GW_PAGE_CSP, "unsafe-inline"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_notify_without_socket_sends_nothing),
		cmocka_unit_test(test_notify_path_socket),
		cmocka_unit_test(test_notify_abstract_socket),
		cmocka_unit_test(test_notify_watchdog_of_another_pid_ignored),
		cmocka_unit_test(test_notify_bad_socket_refused),
		cmocka_unit_test(test_msink_text_escapes),
		cmocka_unit_test(test_msink_json),
		cmocka_unit_test(test_page_files),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
