/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_notify - the service manager's notification protocol, by hand (see
 * gw_notify.h): the datagram format is sd_notify(3)'s, documented as a
 * stable interface (systemd.service(5) NotifyAccess=, sd_notify(3) NOTES).
 */
#include "df1gw/gw_notify.h"

#include <errno.h>
#include <stddef.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

bool gw_notify_on(const struct gw_notify *n)
{
	return n->fd >= 0;
}

/* WATCHDOG_USEC for this process (WATCHDOG_PID, when set, must be ours). */
static int64_t notify_watchdog_usec(void)
{
	const char *us = getenv("WATCHDOG_USEC"), *pid = getenv("WATCHDOG_PID");
	char *end;
	long long v;

	if (!us)
		return 0;
	if (pid && strtol(pid, &end, 10) != (long)getpid())
		return 0;
	errno = 0;
	v = strtoll(us, &end, 10);
	if (errno || *end || v <= 0)
		return 0;
	return v;
}

int gw_notify_open(struct gw_notify *n, int64_t now, char *err, size_t errcap)
{
	const char *path = getenv("NOTIFY_SOCKET");
	size_t len;
	int64_t usec;

	memset(n, 0, sizeof *n);
	n->fd = -1;
	usec = notify_watchdog_usec();
	unsetenv("WATCHDOG_USEC");
	unsetenv("WATCHDOG_PID");
	if (!path || !*path) {
		unsetenv("NOTIFY_SOCKET");
		return 0;
	}
	len = strlen(path);
	if ((path[0] != '/' && path[0] != '@') || len >= sizeof n->addr.sun_path) {
		snprintf(err, errcap, "NOTIFY_SOCKET '%s': not a socket path or @name", path);
		unsetenv("NOTIFY_SOCKET");
		return -1;
	}
	n->addr.sun_family = AF_UNIX;
	memcpy(n->addr.sun_path, path, len);
	if (path[0] == '@')
		n->addr.sun_path[0] = '\0';     /* abstract: no terminating NUL counted */
	n->addr_len = (socklen_t)(offsetof(struct sockaddr_un, sun_path) + len + (path[0] == '/'));
	unsetenv("NOTIFY_SOCKET");      /* children (none) do not talk to it */
	n->fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
	if (n->fd < 0) {
		snprintf(err, errcap, "NOTIFY_SOCKET: socket: %s", strerror(errno));
		return -1;
	}
	/* half the period, as sd_watchdog_enabled(3) advises */
	n->wd_period_ms = usec / 2000;
	if (usec > 0 && n->wd_period_ms < 1)
		n->wd_period_ms = 1;
	n->wd_next_ms = now;
	return 0;
}

void gw_notify_close(struct gw_notify *n)
{
	if (n->fd >= 0)
		close(n->fd);
	n->fd = -1;
}

int gw_notify_send(struct gw_notify *n, const char *msg)
{
	if (n->fd < 0)
		return 0;
	/* a full queue at the manager drops one message; the next turn sends again */
	if (sendto(n->fd, msg, strlen(msg), MSG_NOSIGNAL, (const struct sockaddr *)&n->addr, n->addr_len) < 0)
		return -1;
	return 0;
}

void gw_notify_status(struct gw_notify *n, const char *text)
{
	char msg[sizeof n->status + 8];

	if (n->fd < 0 || strcmp(n->status, text) == 0)
		return;
	snprintf(msg, sizeof msg, "STATUS=%s", text);
	if (gw_notify_send(n, msg) == 0)
		snprintf(n->status, sizeof n->status, "%s", text);
}

void gw_notify_ready(struct gw_notify *n)
{
	if (n->fd < 0 || n->ready)
		return;
	if (gw_notify_send(n, "READY=1") == 0)
		n->ready = true;
}

void gw_notify_reloading(struct gw_notify *n)
{
	struct timespec ts;
	char msg[64];

	if (n->fd < 0)
		return;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	snprintf(msg, sizeof msg, "RELOADING=1\nMONOTONIC_USEC=%llu",
	         (unsigned long long)ts.tv_sec * 1000000ull + (unsigned long long)ts.tv_nsec / 1000u);
	gw_notify_send(n, msg);
	n->ready = false;
}

int gw_notify_wait_ms(const struct gw_notify *n, int64_t now)
{
	int64_t d;

	if (n->fd < 0 || n->wd_period_ms <= 0)
		return INT32_MAX;
	d = n->wd_next_ms - now;
	return d <= 0 ? 0 : d > INT32_MAX ? INT32_MAX : (int)d;
}

void gw_notify_tick(struct gw_notify *n, int64_t now)
{
	if (n->fd < 0 || n->wd_period_ms <= 0 || now < n->wd_next_ms)
		return;
	gw_notify_send(n, "WATCHDOG=1");
	n->wd_next_ms = now + n->wd_period_ms;
}
