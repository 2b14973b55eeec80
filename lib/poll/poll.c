/* SPDX-License-Identifier: MPL-2.0 */
/*
 * poll.c - df1_poll(): queued writes, one scan of what is due, the wait for
 * due work or a queued write; df1_poll_next_ms(), df1_poll_fd().
 */
#include "poll/poll_int.h"

#include "link/link.h"

/* ms between a half-duplex master's rounds of polls while no scan is due */
#define POLL_SERVICE_GAP_MS 10

static void poll_drain_wake(struct poll_engine *e)
{
	uint64_t v;

	while (read(e->wake_fd, &v, sizeof v) > 0)
		;
}

static int poll_work(struct df1 *h, struct poll_engine *e)
{
	int n, r;
	int64_t now;

	if (e->dirty) {
		r = poll_replan(h, e);
		if (r < 0)
			return df1_fail(h, r, -1, "poll engine: cannot plan the scan list (%s)",
			                df1_strerror(r));
	}
	poll_drain_wake(e);
	n = poll_run_writes(h, e);
	if (n < 0)
		return n;
	now = df1_now_ms();
	if (poll_next_scan(e) <= now) {
		r = poll_scan(h, e, now);
		if (r < 0)
			return r;
		n += r;
	}
	return n;
}

static bool poll_queue_empty(struct poll_engine *e)
{
	bool empty;

	pthread_mutex_lock(&e->mu);
	empty = e->wq_head == NULL;
	pthread_mutex_unlock(&e->mu);
	return empty;
}

/* Wait until `until` for a queued write or the cancel fd. 1 woken, 0 time is
 * up, 2 a signal interrupted the wait, DF1_E_INTR, DF1_E_SYS. */
static int poll_wait(struct df1 *h, struct poll_engine *e, int64_t until)
{
	struct pollfd p[2] = { { e->wake_fd, POLLIN, 0 }, { h->cancel_fd, POLLIN, 0 } };
	nfds_t n = h->cancel_fd >= 0 ? 2 : 1;
	int64_t left = until == POLL_NEVER ? -1 : until - df1_now_ms();
	int ms = left < 0 ? -1 : left > INT_MAX ? INT_MAX : (int)left;
	int r;

	if (until != POLL_NEVER && left <= 0)
		return 0;
	r = poll(p, n, ms);
	if (r < 0) {
		if (errno == EINTR)
			return 2;
		return df1_fail(h, DF1_E_SYS, -1, "poll engine: poll: %s", strerror(errno));
	}
	if (n == 2 && p[1].revents)
		return df1_fail(h, DF1_E_INTR, -1, "poll engine: wait cancelled");
	return p[0].revents ? 1 : 0;
}

/* The wait between scans. A half-duplex master polls its slaves meanwhile
 * (lib/link/route.c): their own messages leave only when they are polled,
 * and what is queued for them goes out. As poll_wait. */
static int poll_service(struct df1 *h, struct poll_engine *e, int64_t until)
{
	int64_t now, step;
	int r;

	if (h->cfg.duplex != DF1_HALF_DUPLEX_MASTER || h->own_link)
		return poll_wait(h, e, until);
	r = link_route_round(h, NULL, NULL, NULL);
	if (r < 0)
		return r;
	now = df1_now_ms();
	step = now + POLL_SERVICE_GAP_MS;
	r = poll_wait(h, e, until == POLL_NEVER || step < until ? step : until);
	return r;
}

/* poll_work with the ACKs of replies held for our next frame (one write: the
 * ACK and the next block's command); none is left held on return. */
static int poll_work_merged(struct df1 *h, struct poll_engine *e)
{
	int n, f;

	h->hold_reply_ack = true;
	n = poll_work(h, e);
	h->hold_reply_ack = false;
	f = link_tx_flush(h);
	return n >= 0 && f < 0 ? f : n;
}

int df1_poll(df1_t *h, int timeout_ms)
{
	struct poll_engine *e;
	int64_t deadline;
	int n;

	if (!h)
		return DF1_E_INVAL;
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	if (!df1_is_open(h))
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "poll: the handle is not open");
	n = poll_work_merged(h, e);
	if (n != 0 || timeout_ms == 0)
		return n;
	deadline = timeout_ms < 0 ? POLL_NEVER : df1_now_ms() + timeout_ms;
	for (;;) {
		int64_t next = poll_queue_empty(e) ? poll_next_scan(e) : 0;
		int64_t until = next < deadline ? next : deadline;
		int r;

		if (until <= df1_now_ms())
			break;
		r = poll_service(h, e, until);
		if (r < 0)
			return r;
		if (r == 2)
			return 0;       /* a signal: let the caller look at its flags */
		if (r == 1)
			break;
	}
	return poll_work_merged(h, e);
}

int df1_poll_next_ms(const df1_t *h)
{
	struct poll_engine *e;
	int64_t next, now;

	if (!h)
		return DF1_E_INVAL;
	e = h->poll;
	if (!e)
		return -1;
	if (e->dirty || !poll_queue_empty(e))
		return 0;
	next = poll_next_scan(e);
	if (next == POLL_NEVER)
		return -1;
	now = df1_now_ms();
	return next <= now ? 0 : next - now > INT_MAX ? INT_MAX : (int)(next - now);
}

int df1_poll_fd(df1_t *h)
{
	struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	return e->wake_fd;
}
