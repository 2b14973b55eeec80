/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_http - df1gw --http as anyone who reaches its port meets it
 * (tools/df1gw/gw_http.c on libmicrohttpd, df1gw(1) HEALTH). Once: a df1gw
 * made by gw_setup() from a command line (a mapping file of every kind of
 * row, JSON and Sparkplug, a broker that is never connected, a line that is
 * never opened) with its HTTP server on a loopback port. Each input is the
 * bytes of one client connection, sent whole, then the write side shut; the
 * server is run until it has closed the connection. Properties:
 *  - it closes a connection whose request it has taken whole as soon as
 *    the client has ended (FUZZ_CLOSE_MS); one that stays open waits for the
 *    rest of a request (libmicrohttpd holds an unfinished request line until
 *    the idle timeout, GW_HTTP_IDLE_S), and the client resets it after
 *    FUZZ_HOLD_MS without an answer, as a client that gives up does;
 *  - whatever comes back starts as an HTTP/1.x status line;
 *  - every answer df1gw makes (200, 404, 405) carries the headers of
 *    tools/df1gw/gw_http.c's common_headers(): no caching, no sniffing, the
 *    page's Content-Security-Policy;
 *  - an answer 200, 404 or 405 is the one df1gw's handler queued for the
 *    first request it served, and a 200 only for a request it served as GET
 *    or HEAD (the server is read-only): judged by what the handler recorded
 *    of the method libmicrohttpd handed it (gw_http_served, compiled in
 *    with DF1_FUZZ_HOOKS), never by re-reading the input's bytes, since
 *    libmicrohttpd decides what the request is (it skips what precedes a
 *    request line, takes the method up to the first NUL, ...).
 * Input: any bytes.
 */
#include "fuzz.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "df1gw/gw.h"
#include "df1gw/gw_http.h"

/* How long the server may take to close a connection whose client has
 * finished sending (libmicrohttpd closes on the client's end of stream at
 * once; a slow run under the sanitizers stays far below). */
#define FUZZ_CLOSE_MS 5000
/* How long a client waits for the first byte of an answer before it gives
 * up on a connection the server holds open. */
#define FUZZ_HOLD_MS 50
/* What is kept of an answer to check it. */
#define FUZZ_ANSWER_MAX 65536

static struct gw gw;
static struct sockaddr_in server;
static char answer[FUZZ_ANSWER_MAX + 1];

static const char map_csv[] =
	"Tag,Command,Type,Station,PLC_Type,Address,Count,Scan_Ms\n"
	"Speed,Read,INT,1,SLC,N7:0,1,500\n"
	"Level,ReadWrite,FLOAT,2,MicroLogix,F8:3,4,\n"
	"\"Valve <&> \"\"main\"\"\",Write,BOOL,1,SLC,B3/21,,\n"
	"Recipe,ReadWrite,STRING,1,SLC,ST9:0,1,1000\n"
	"Timer,Read,,1,SLC,T4:0,1,250\n";

static int64_t now_ms(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return (int64_t)t.tv_sec * 1000 + t.tv_nsec / 1000000;
}

/* The mapping file in a folder of its own; its path in out. */
static void write_map(char *out, size_t cap)
{
	char dir[] = "/tmp/fuzz-http-XXXXXX";
	FILE *f;

	FUZZ_CHECK(mkdtemp(dir) != NULL, "mkdtemp: %s", strerror(errno));
	snprintf(out, cap, "%s/map.csv", dir);
	f = fopen(out, "w");
	FUZZ_CHECK(f && fputs(map_csv, f) >= 0 && fclose(f) == 0, "%s: %s", out, strerror(errno));
}

/* "127.0.0.1:PORT" as gw_http_address() says it, into server. */
static void server_address(void)
{
	const char *a = gw_http_address(gw.health.http), *colon = strrchr(a, ':');

	FUZZ_CHECK(colon != NULL, "HTTP address '%s'", a);
	server.sin_family = AF_INET;
	server.sin_port = htons((uint16_t)atoi(colon + 1));
	server.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	static char map[128];
	char *args[] = { "df1gw", "-q", "-d", "tcp://127.0.0.1:1", "--map", map, "--mqtt", "mqtt://127.0.0.1:1",
	                 "--sparkplug", "Plant", "--http", "127.0.0.1:0", NULL };

	struct sigaction fuzzer_sa[NSIG];

	(void)argc, (void)argv;
	fuzz_log();
	write_map(map, sizeof map);
	/* df1gw catches the signals that end a tool (tools/common/cli_signals.c);
	 * libFuzzer's own (SIGALRM for -timeout, SIGINT, ...) are put back */
	for (int sig = 1; sig < NSIG; sig++)
		sigaction(sig, NULL, &fuzzer_sa[sig]);
	FUZZ_CHECK(gw_setup(&gw, (int)(sizeof args / sizeof args[0]) - 1, args) == CLI_CONTINUE,
	           "df1gw did not set up from its command line");
	for (int sig = 1; sig < NSIG; sig++)
		sigaction(sig, &fuzzer_sa[sig], NULL);
	FUZZ_CHECK(gw.health.http != NULL, "no HTTP server");
	server_address();
	return 0;
}

static int client_connect(void)
{
	int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
	int r;

	FUZZ_CHECK(fd >= 0, "socket: %s", strerror(errno));
	r = connect(fd, (const struct sockaddr *)&server, sizeof server);
	FUZZ_CHECK(r == 0 || errno == EINPROGRESS, "connect: %s", strerror(errno));
	return fd;
}

/* The client gives up: its connection reset (SO_LINGER 0), and the server
 * run a few turns to see it. */
static void client_reset(int fd)
{
	struct linger l = { 1, 0 };

	setsockopt(fd, SOL_SOCKET, SO_LINGER, &l, sizeof l);
	close(fd);
	for (int i = 0; i < 5; i++) {
		struct pollfd p = { gw_http_fd(gw.health.http), POLLIN, 0 };

		poll(&p, 1, 2);
		gw_http_run(gw.health.http);
	}
}

/* Runs the server and moves the input to it and its answer back, until the
 * server closes (or, answering nothing, holds the connection FUZZ_HOLD_MS
 * after the client's end: *held). Returns the answer's length (kept up to
 * FUZZ_ANSWER_MAX). */
static size_t converse(int fd, const uint8_t *data, size_t size, bool *held)
{
	size_t sent = 0, got = 0;
	bool shut = false;
	int64_t end = now_ms() + FUZZ_CLOSE_MS, hold_end = INT64_MAX;

	*held = false;
	for (;;) {
		struct pollfd p[2] = { { gw_http_fd(gw.health.http), POLLIN, 0 },
		                       { fd, (short)(POLLIN | (shut ? 0 : POLLOUT)), 0 } };
		int wait = gw_http_wait_ms(gw.health.http);
		char buf[4096];
		ssize_t n;

		if (got == 0 && now_ms() >= hold_end) {
			*held = true;
			break;
		}
		FUZZ_CHECK(now_ms() < end, "the server answered and kept the connection %d ms after the client's end",
		           FUZZ_CLOSE_MS);
		poll(p, 2, wait < 20 ? wait : 20);
		gw_http_run(gw.health.http);
		if (!shut && (p[1].revents & POLLOUT)) {
			n = sent < size ? send(fd, data + sent, size - sent, MSG_NOSIGNAL) : 0;
			if (n > 0)
				sent += (size_t)n;
			if (sent == size || (n < 0 && errno != EAGAIN)) {
				shutdown(fd, SHUT_WR);
				shut = true;
				hold_end = now_ms() + FUZZ_HOLD_MS;
			}
		}
		while ((n = recv(fd, buf, sizeof buf, 0)) > 0) {
			size_t k = got + (size_t)n > FUZZ_ANSWER_MAX ? FUZZ_ANSWER_MAX - got : (size_t)n;

			memcpy(answer + got, buf, k);
			got += k;
		}
		if (n == 0 || (n < 0 && errno != EAGAIN))
			break;          /* closed (or reset) by the server */
	}
	answer[got] = '\0';
	return got;
}

/* The status code of an answer's status line ("HTTP/1.1 200 OK"). */
static int status_code(const char *a, size_t len)
{
	FUZZ_CHECK(len >= 12 && memcmp(a, "HTTP/1.", 7) == 0 && a[8] == ' ', "not a status line: '%.40s'", a);
	return atoi(a + 9);
}

static bool has_header(const char *head_end, const char *h)
{
	const char *f = strstr(answer, h);

	return f && f < head_end;
}

static void check_answer(size_t len)
{
	const char *head_end;
	int code;
	bool read_method;

	if (len == 0)
		return;         /* closed without a word: a request it could not take */
	code = status_code(answer, len);
	if (code != 200 && code != 404 && code != 405)
		return;         /* libmicrohttpd's own answers (400, 413, 505, ...) */
	head_end = strstr(answer, "\r\n\r\n");
	FUZZ_CHECK(head_end != NULL || len == FUZZ_ANSWER_MAX, "an answer %d without the end of its headers", code);
	if (!head_end)
		return;
	FUZZ_CHECK(has_header(head_end, "\r\nX-Content-Type-Options: nosniff\r\n"), "answer %d without nosniff", code);
	FUZZ_CHECK(has_header(head_end, "\r\nCache-Control: no-store\r\n"), "answer %d cached", code);
	FUZZ_CHECK(has_header(head_end, "\r\nContent-Security-Policy: "), "answer %d without its policy", code);
	/* df1gw's own view, not the raw bytes (libmicrohttpd skips what comes
	 * before a request line, takes the method as a C string, ...): the
	 * answer is the one df1gw queued for the first request it served, and a
	 * 200 went to a request df1gw was handed as GET or HEAD */
	FUZZ_CHECK(gw_http_served.count > 0 && gw_http_served.status == (unsigned)code,
	           "answer %d, but df1gw served %u requests (the first answered %u)", code, gw_http_served.count,
	           gw_http_served.status);
	read_method = (gw_http_served.method_len == 3 && strcmp(gw_http_served.method, "GET") == 0) ||
	              (gw_http_served.method_len == 4 && strcmp(gw_http_served.method, "HEAD") == 0);
	FUZZ_CHECK(code != 200 || read_method, "200 for a request df1gw served as '%s' (%zu bytes), not GET or HEAD",
	           gw_http_served.method, gw_http_served.method_len);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	int fd;
	bool held;
	size_t len;

	gw_http_served.count = 0;
	fd = client_connect();
	len = converse(fd, data, size, &held);

	if (held)
		client_reset(fd);
	else
		close(fd);
	check_answer(len);
	return 0;
}
