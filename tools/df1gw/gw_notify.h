/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_notify - df1gw's word to its service manager: systemd's notification
 * protocol written by hand (one datagram per message on the AF_UNIX socket
 * that NOTIFY_SOCKET names, a path or, with a leading '@', an abstract name),
 * so df1gw needs no libsystemd. Without NOTIFY_SOCKET nothing is sent. The
 * watchdog period is half of WATCHDOG_USEC, pinged from df1gw's loop only
 * (a wedged loop stops the pings and systemd ends the process). df1gw(1)
 * SYSTEMD.
 */
#ifndef DF1_TOOLS_GW_NOTIFY_H
#define DF1_TOOLS_GW_NOTIFY_H

#include <stdbool.h>
#include <stdint.h>
#include <sys/socket.h>
#include <sys/un.h>

struct gw_notify {
	int fd;                      /* -1: no service manager */
	struct sockaddr_un addr;
	socklen_t addr_len;
	int64_t wd_period_ms;        /* ping every this (0: no watchdog) */
	int64_t wd_next_ms;          /* monotonic ms of the next ping */
	bool ready;                  /* READY=1 sent since the start or the last reload */
	char status[256];            /* the last STATUS= sent */
};

/* Read NOTIFY_SOCKET, WATCHDOG_USEC and WATCHDOG_PID (and take them out of
 * the environment, as sd_notify does). Returns 0, or -1 with err when
 * NOTIFY_SOCKET is there but unusable (n is then off). */
int gw_notify_open(struct gw_notify *n, int64_t now, char *err, size_t errcap);
void gw_notify_close(struct gw_notify *n);
bool gw_notify_on(const struct gw_notify *n);
/* One message ("READY=1", "STOPPING=1", lines joined with '\n'). 0 or -1. */
int gw_notify_send(struct gw_notify *n, const char *msg);
/* STATUS=text, only when it differs from the last one sent. */
void gw_notify_status(struct gw_notify *n, const char *text);
/* READY=1 once (again after gw_notify_reloading). */
void gw_notify_ready(struct gw_notify *n);
/* RELOADING=1 with MONOTONIC_USEC (systemd.service(5) Type=notify-reload). */
void gw_notify_reloading(struct gw_notify *n);
/* Milliseconds until the next watchdog ping (INT32_MAX: none). */
int gw_notify_wait_ms(const struct gw_notify *n, int64_t now);
/* The loop turned: WATCHDOG=1 when due. */
void gw_notify_tick(struct gw_notify *n, int64_t now);

#endif
