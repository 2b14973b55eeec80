/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_http - the HTTP side of df1gw --http on libmicrohttpd (gw_http.h).
 *
 * libmicrohttpd runs without threads of its own (no MHD_USE_INTERNAL_POLLING_THREAD):
 * MHD_USE_EPOLL gives one descriptor for df1gw's poll(), and MHD_run()
 * reads, answers and times out connections without blocking, so a flood of
 * requests or a slow client costs the loop a turn's work, never a wait.
 * Connections are limited (GW_HTTP_MAX_CONN, per address GW_HTTP_PER_IP) and
 * idle ones closed after GW_HTTP_IDLE_S. Every answer is made whole from
 * df1gw's state at the moment of the request (struct gw, read only).
 */
#include "df1gw/gw_http.h"

#include <arpa/inet.h>
#include <microhttpd.h>
#include <netdb.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#include "df1gw/gw.h"
#include "df1gw/gw_metrics.h"
#include "df1gw/gw_page.h"

#define GW_HTTP_MAX_CONN 64
#define GW_HTTP_PER_IP 32
#define GW_HTTP_IDLE_S 10

struct gw_http {
	struct MHD_Daemon *d;
	const struct gw *g;
	char addr[80];
	bool loopback;
	uint64_t *requests;          /* struct gw_health's: the metrics read it there */
	struct gw_buf body;          /* the answer being made (copied by libmicrohttpd) */
};

/* What every answer carries: nothing cached, no type guessing, no referrer. */
static void common_headers(struct MHD_Response *r)
{
	MHD_add_response_header(r, "Cache-Control", "no-store");
	MHD_add_response_header(r, "X-Content-Type-Options", "nosniff");
	MHD_add_response_header(r, "Referrer-Policy", "no-referrer");
	MHD_add_response_header(r, "X-Frame-Options", "DENY");
	MHD_add_response_header(r, "Content-Security-Policy", GW_PAGE_CSP);
}

#ifdef DF1_FUZZ_HOOKS
struct gw_http_served gw_http_served;

/* The fuzz build's record of what df1gw served (gw_http.h): the first
 * request's method as libmicrohttpd handed it over and the status queued. */
static void served(const char *method, unsigned status)
{
	if (gw_http_served.count++ == 0) {
		snprintf(gw_http_served.method, sizeof gw_http_served.method, "%s", method);
		gw_http_served.method_len = strlen(method);
		gw_http_served.status = status;
	}
}
#else
#define served(method, status) ((void)(method), (void)(status))
#endif

static enum MHD_Result answer(struct MHD_Connection *c, const char *method, unsigned status, const char *type,
                              const char *body, size_t len)
{
	struct MHD_Response *r = MHD_create_response_from_buffer(len, (void *)body, MHD_RESPMEM_MUST_COPY);
	enum MHD_Result ret;

	served(method, status);
	if (!r)
		return MHD_NO;
	common_headers(r);
	MHD_add_response_header(r, "Content-Type", type);
	if (status == MHD_HTTP_METHOD_NOT_ALLOWED)
		MHD_add_response_header(r, "Allow", "GET, HEAD");
	ret = MHD_queue_response(c, status, r);
	MHD_destroy_response(r);
	return ret;
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                                  const char *version, const char *upload, size_t *upload_len, void **state)
{
	struct gw_http *s = cls;
	const struct gw_page_file *f;

	(void)version, (void)upload, (void)upload_len, (void)state;
	(*s->requests)++;
	if (strcmp(method, MHD_HTTP_METHOD_GET) != 0 && strcmp(method, MHD_HTTP_METHOD_HEAD) != 0) {
		static const char msg[] = "read-only: GET and HEAD only\n";

		return answer(c, method, MHD_HTTP_METHOD_NOT_ALLOWED, "text/plain; charset=utf-8", msg, sizeof msg - 1);
	}
	gw_buf_reset(&s->body);
	if (strcmp(url, "/metrics") == 0) {
		gw_metrics_write(s->g, &s->body, false);
		return answer(c, method, MHD_HTTP_OK, "text/plain; version=0.0.4; charset=utf-8",
		              s->body.p ? s->body.p : "", s->body.len);
	}
	if (strcmp(url, "/api/status") == 0) {
		gw_status_json(s->g, &s->body);
		return answer(c, method, MHD_HTTP_OK, "application/json", s->body.p ? s->body.p : "", s->body.len);
	}
	if ((f = gw_page_find(url)) != NULL)
		return answer(c, method, MHD_HTTP_OK, f->type, f->body, f->len);
	{
		static const char msg[] = "not found: /, /metrics, /api/status\n";

		return answer(c, method, MHD_HTTP_NOT_FOUND, "text/plain; charset=utf-8", msg, sizeof msg - 1);
	}
}

/* listen "[ADDR:]PORT" resolved into *ss. 0, or -1 with err. */
static int parse_listen(const char *listen, struct sockaddr_storage *ss, socklen_t *len, char *err, size_t errcap)
{
	char host[256] = "127.0.0.1";
	const char *colon = strrchr(listen, ':'), *port = colon ? colon + 1 : listen;
	struct addrinfo hints = { .ai_family = AF_UNSPEC, .ai_socktype = SOCK_STREAM,
	                          .ai_flags = AI_PASSIVE | AI_NUMERICSERV }, *ai;
	char *end;
	long p = strtol(port, &end, 10);
	int r;

	if (!*port || *end || p < 0 || p > 65535) {
		snprintf(err, errcap, "'%s': not [ADDR:]PORT (a port 0-65535)", listen);
		return -1;
	}
	if (colon) {
		size_t n = (size_t)(colon - listen);

		if (n >= 2 && listen[0] == '[' && listen[n - 1] == ']') {
			listen++;
			n -= 2;
		}
		if (n == 0 || n >= sizeof host) {
			snprintf(err, errcap, "'%s': no address before the port", listen);
			return -1;
		}
		memcpy(host, listen, n);
		host[n] = '\0';
	}
	r = getaddrinfo(host, port, &hints, &ai);
	if (r != 0) {
		snprintf(err, errcap, "%s: %s", host, gai_strerror(r));
		return -1;
	}
	memcpy(ss, ai->ai_addr, ai->ai_addrlen);
	*len = ai->ai_addrlen;
	freeaddrinfo(ai);
	return 0;
}

/* The address bound, as text, and whether only this host can reach it. */
static void bound_address(struct gw_http *s)
{
	const union MHD_DaemonInfo *i = MHD_get_daemon_info(s->d, MHD_DAEMON_INFO_LISTEN_FD);
	struct sockaddr_storage ss;
	socklen_t len = sizeof ss;
	char host[INET6_ADDRSTRLEN] = "?";
	int port = 0;

	if (!i || getsockname(i->listen_fd, (struct sockaddr *)&ss, &len) < 0)
		return;
	if (ss.ss_family == AF_INET) {
		const struct sockaddr_in *a = (const struct sockaddr_in *)&ss;

		inet_ntop(AF_INET, &a->sin_addr, host, sizeof host);
		port = ntohs(a->sin_port);
		s->loopback = (ntohl(a->sin_addr.s_addr) >> 24) == 127;
		snprintf(s->addr, sizeof s->addr, "%s:%d", host, port);
	} else if (ss.ss_family == AF_INET6) {
		const struct sockaddr_in6 *a = (const struct sockaddr_in6 *)&ss;

		inet_ntop(AF_INET6, &a->sin6_addr, host, sizeof host);
		port = ntohs(a->sin6_port);
		s->loopback = IN6_IS_ADDR_LOOPBACK(&a->sin6_addr);
		snprintf(s->addr, sizeof s->addr, "[%s]:%d", host, port);
	}
}

int gw_http_open(struct gw_http **out, const char *listen, const struct gw *g, uint64_t *requests, char *err,
                 size_t errcap)
{
	struct sockaddr_storage ss;
	socklen_t len;
	struct gw_http *s;
	unsigned flags = MHD_USE_EPOLL;

	*out = NULL;
	if (parse_listen(listen, &ss, &len, err, errcap) < 0)
		return -1;
	s = calloc(1, sizeof *s);
	if (!s) {
		snprintf(err, errcap, "out of memory");
		return -1;
	}
	s->g = g;
	s->requests = requests;
	gw_buf_init(&s->body);
	if (ss.ss_family == AF_INET6)
		flags |= MHD_USE_IPv6;
	s->d = MHD_start_daemon(flags, 0, NULL, NULL, on_request, s,
	                        MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&ss,
	                        MHD_OPTION_CONNECTION_LIMIT, (unsigned)GW_HTTP_MAX_CONN,
	                        MHD_OPTION_PER_IP_CONNECTION_LIMIT, (unsigned)GW_HTTP_PER_IP,
	                        MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)GW_HTTP_IDLE_S,
	                        MHD_OPTION_END);
	if (!s->d) {
		snprintf(err, errcap, "cannot listen (address in use, or not this host's)");
		gw_buf_free(&s->body);
		free(s);
		return -1;
	}
	bound_address(s);
	*out = s;
	return 0;
}

void gw_http_close(struct gw_http *s)
{
	if (!s)
		return;
	MHD_stop_daemon(s->d);
	gw_buf_free(&s->body);
	free(s);
}

const char *gw_http_address(const struct gw_http *s)
{
	return s->addr;
}

bool gw_http_loopback(const struct gw_http *s)
{
	return s->loopback;
}

int gw_http_fd(const struct gw_http *s)
{
	const union MHD_DaemonInfo *i;

	if (!s)
		return -1;
	i = MHD_get_daemon_info(s->d, MHD_DAEMON_INFO_EPOLL_FD);
	return i ? i->epoll_fd : -1;
}

int gw_http_wait_ms(const struct gw_http *s)
{
	MHD_UNSIGNED_LONG_LONG t;

	if (!s || MHD_get_timeout(s->d, &t) != MHD_YES)
		return INT32_MAX;
	return t > INT32_MAX ? INT32_MAX : (int)t;
}

void gw_http_run(struct gw_http *s)
{
	if (s)
		MHD_run(s->d);
}
