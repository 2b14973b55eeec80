/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_http - df1gw --http: a read-only HTTP server on libmicrohttpd, run from
 * df1gw's own loop (no thread of libmicrohttpd's: its epoll descriptor joins
 * df1gw's poll() and MHD_run answers what is ready). GET and HEAD only:
 * /metrics (Prometheus text), /api/status (JSON), / and its script and style
 * (the status page, gw_page.c). Nothing it serves writes to a PLC.
 */
#ifndef DF1_TOOLS_GW_HTTP_H
#define DF1_TOOLS_GW_HTTP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

struct gw;
struct gw_http;

/* Listen on [ADDR:]PORT (127.0.0.1 without ADDR; [V6]:PORT; PORT 0: one the
 * kernel picks) for g, counting requests in *requests. Returns 0 with *out, or -1 with err. */
int gw_http_open(struct gw_http **out, const char *listen, const struct gw *g, uint64_t *requests, char *err,
                 size_t errcap);
void gw_http_close(struct gw_http *s);
/* "127.0.0.1:8080" as bound; whether that is loopback only. */
const char *gw_http_address(const struct gw_http *s);
bool gw_http_loopback(const struct gw_http *s);
/* The descriptor to poll for POLLIN. */
int gw_http_fd(const struct gw_http *s);
/* Milliseconds until its timers need a run (INT32_MAX: none). */
int gw_http_wait_ms(const struct gw_http *s);
/* Answer what is ready (never blocks). */
void gw_http_run(struct gw_http *s);

#ifdef DF1_FUZZ_HOOKS
/* Only in the fuzz build (tests/fuzz/fuzz.mk): the first request df1gw
 * served since count was last set to 0, as its handler saw it: the method
 * libmicrohttpd handed over (cut to fit, with its whole length) and the
 * status df1gw queued. tests/fuzz/fuzz_http.c judges the answers on the
 * wire by it. */
struct gw_http_served {
	unsigned count;              /* requests served */
	char method[32];
	size_t method_len;
	unsigned status;
};
extern struct gw_http_served gw_http_served;
#endif

#endif
