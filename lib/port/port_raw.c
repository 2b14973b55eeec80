/* SPDX-License-Identifier: MPL-2.0 */
/*
 * raw.c - the port's bytes as they are, for listen-only taps and monitors
 * (DF1_OPT_LISTEN_ONLY, df1mon --sniff): df1_recv_raw() reads through the
 * port backend with the handle's deadline rules (poll() against an absolute
 * monotonic deadline, the cancel fd ends it), df1_port_fd() gives the
 * descriptor for an application's own poll() over several taps. Nothing here
 * transmits, allocates or decodes.
 */
#include "df1_int.h"

#include <limits.h>
#include <string.h>

DF1_API int df1_recv_raw(df1_t *h, uint8_t *buf, size_t cap, int timeout_ms, struct timespec *when)
{
	int64_t deadline_ms;
	ssize_t n;

	if (!h)
		return DF1_E_INVAL;
	if (!buf || cap == 0 || timeout_ms < -1)
		return df1_fail(h, DF1_E_INVAL, -1, "df1_recv_raw: %s",
		                !buf ? "no buffer" : cap == 0 ? "empty buffer" : "timeout below -1");
	if (!h->port || h->fd < 0)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "handle is not open");
	if (cap > INT_MAX)
		cap = INT_MAX;
	if (h->rx_pos < h->rx_len) {
		/* read by the link layer, not decoded yet: those came first */
		n = (ssize_t)(h->rx_len - h->rx_pos < cap ? h->rx_len - h->rx_pos : cap);
		memcpy(buf, h->rxbuf + h->rx_pos, (size_t)n);
		h->rx_pos += (size_t)n;
		if (h->rx_pos == h->rx_len)
			h->rx_pos = h->rx_len = 0;
		if (when)
			df1_wall_clock(when);
		return (int)n;
	}
	deadline_ms = timeout_ms < 0 ? INT64_MAX : df1_now_ms() + timeout_ms;
	n = h->port->read(h, buf, cap, deadline_ms);
	if (n <= 0)
		return (int)n; /* 0 at the deadline, or DF1_E_* (the detail is recorded) */
	if (when)
		df1_wall_clock(when);
	df1_count_n(h, DF1_ID_CRD_CHAR_RECV, (uint64_t)n);
	if (h->trace_fn)
		h->trace_fn(h->trace_user, DF1_DIR_RX, buf, (size_t)n, df1_now_us());
	return (int)n;
}

DF1_API int df1_port_fd(const df1_t *h)
{
	if (!h)
		return DF1_E_INVAL;
	if (!h->port || h->fd < 0)
		return DF1_E_NOT_OPEN;
	return h->fd;
}
