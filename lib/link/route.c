/* SPDX-License-Identifier: MPL-2.0 */
/*
 * route.c - what a half-duplex master does with the messages its slaves send
 * it when polled (doc/PROTOCOL.md 2.5, libdf1(7) UNSOLICITED MESSAGES), and
 * the queue of what the master sends on (lib/link/route_round.c sends it).
 *
 * Decisions (relied on by tests/unit/link/test_route.c and
 * tests/integration/it_route.sh):
 *  - A command for our own station (cfg.station) is run by the responder
 *    (df1_serve's ops, else df1_set_responder's, else STS 10h as
 *    lib/link/peer.c answers) and its reply goes to the sender as a master
 *    message before the sender's next poll ("polled report by exception").
 *    One that comes outside a round (in the polls of our own command) with
 *    no df1_set_responder ops waits for the next round, where df1_serve's
 *    may run it.
 *  - A command for another station is sent on to it as a master message
 *    (DF1_OPT_ROUTE, default on); the reply that station gives when polled
 *    (DST = the sender, SRC = it, the sender's TNS) is sent on to the sender.
 *    A target that does not ACK (the NAK retry limit) makes the master answer
 *    the sender itself with STS 02h, "delivery not guaranteed, the remote
 *    node did not ACK"; one that ACKs but has no reply within Cmd_Timeout
 *    gets STS 05h, "application layer timed out waiting for a response"
 *    (the local-error STS of doc/PROTOCOL.md 3.2: the master is the sender's
 *    interface to the other station). Both are counted undeliverable.
 *  - A broadcast (DST 255) is sent once as a master message to 255, not
 *    ACKed (doc/PROTOCOL.md 2.3), and nobody replies.
 *  - DF1_OPT_ROUTE 0: commands for other stations and broadcasts are ACKed
 *    and dropped (counted undeliverable): the sender's MSG times out, as
 *    under a master that does not route.
 *  - The rounds of polls that deliver them are lib/link/route_round.c's.
 */
#include "link/link.h"

#include <stdlib.h>
#include <string.h>

#include "link/link_int.h"

/* The local-error STS the master answers with when a reply does not come (doc/PROTOCOL.md 3.2). */
#define ROUTE_STS_NO_REPLY 0x05


struct link_route *route_state(struct df1 *h)
{
	if (!h->route)
		h->route = calloc(1, sizeof *h->route); /* once per handle */
	return h->route;
}

DF1_API int df1_route_stats(const df1_t *h, struct df1_route_stats *out)
{
	if (!h || !out)
		return DF1_E_INVAL;
	if (h->route)
		*out = h->route->st;
	else
		memset(out, 0, sizeof *out);
	return 0;
}

void route_seen(struct df1 *h, uint8_t stn)
{
	struct link_route *r = route_state(h);

	if (r && stn != 255)
		r->poll[stn] = true;
}

bool route_is_ours(const struct df1 *h, const uint8_t *d)
{
	return (d[2] & 0x40) && d[0] == (uint8_t)h->cfg.station;
}

static struct route_msg *route_queue(struct link_route *r, enum route_kind kind, uint8_t dst,
                                     const uint8_t *app, size_t n)
{
	for (int i = 0; i < ROUTE_SLOTS; i++) {
		struct route_msg *m = &r->q[i];

		if (m->used)
			continue;
		memset(m, 0, sizeof *m);
		m->used = true;
		m->kind = kind;
		m->dst = dst;
		m->seq = ++r->seq;
		m->len = n;
		memcpy(m->app, app, n);
		return m;
	}
	return NULL;
}

/* The reply to a command (cmd) that the master gives in the target's name. */
void route_error_reply(struct route_msg *m, uint8_t sts)
{
	uint8_t sender = m->app[1], target = m->app[0], cmdb = m->app[2];

	m->kind = ROUTE_REPLY;
	m->waiting = false;
	m->dst = sender;
	m->app[0] = sender;
	m->app[1] = target;
	m->app[2] = (uint8_t)(cmdb | 0x40);
	m->app[3] = sts;
	m->len = 6;
}

/* A command for our own station, run: its reply in m (which held the command)
 * for the sender, or m freed when there is none. 0 or DF1_E_*. */
static int route_run(struct df1 *h, struct link_route *r, struct route_msg *m)
{
	uint8_t out[FRAME_MAX_DATA];
	uint8_t sender = m->app[1];
	int len = r->fn ? r->fn(h, r->ctx, m->app, m->len, out, sizeof out)
	                : peer_answer(h, m->app, m->len, out, sizeof out);

	m->used = false;
	if (len < 0)
		return len;
	r->st.executed++;
	if (len > 0 && (size_t)len <= sizeof out) {
		m->used = true;
		m->kind = ROUTE_REPLY;
		m->dst = sender;
		m->len = (size_t)len;
		memcpy(m->app, out, (size_t)len);
	}
	return 0;
}

/* A command for our own station: run now in a round or with df1_set_responder's
 * ops; else kept for the next round, where df1_serve's ops may run it. */
static int route_exec(struct df1 *h, struct link_route *r, const uint8_t *d, size_t n)
{
	struct route_msg *m = route_queue(r, ROUTE_EXEC, d[1], d, n);

	if (!m)
		return df1_fail(h, DF1_E_NOSPACE, d[1], "no room for the command of station %d", d[1]);
	return r->in_round || h->peer_fn ? route_run(h, r, m) : 0;
}

int route_run_kept(struct df1 *h, struct link_route *r)
{
	for (int i = 0; i < ROUTE_SLOTS; i++) {
		int rc = r->q[i].used && r->q[i].kind == ROUTE_EXEC ? route_run(h, r, &r->q[i]) : 0;

		if (rc < 0)
			return rc;
	}
	return 0;
}

/* A reply from a slave for another station: the one a routed command waits for? */
static void route_reply_back(struct df1 *h, struct link_route *r, const uint8_t *d, size_t n)
{
	for (int i = 0; i < ROUTE_SLOTS; i++) {
		struct route_msg *m = &r->q[i];

		if (!m->used || m->kind != ROUTE_CMD || !m->waiting || m->app[0] != d[1] ||
		    m->app[1] != d[0] || m->app[4] != d[4] || m->app[5] != d[5])
			continue;
		m->kind = ROUTE_REPLY;
		m->waiting = false;
		m->dst = d[0];
		m->len = n;
		memcpy(m->app, d, n);
		r->st.route_replies++;
		df1_count(h, DF1_ID_CNT_REPLY_MSGS_RCVD);
		return;
	}
	df1_count(h, DF1_ID_CNT_STALE_MSGS_RCVD);
	df1_log(h, DF1_ID_ERR_WRONG_MESSAGE, (int)d[1], (int)d[0], (int)(d[4] | d[5] << 8));
}

int route_take(struct df1 *h, const struct df1_symbol *s)
{
	const uint8_t *d = s->data;
	struct link_route *r = route_state(h);

	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	if (!r)
		return df1_fail(h, DF1_E_NOMEM, d[1], "no memory for a message from station %d", d[1]);
	route_seen(h, d[1]);
	if (d[2] & 0x40) {
		route_reply_back(h, r, d, s->len);
		return 0;
	}
	df1_count(h, DF1_ID_CNT_CMD_MSGS_RCVD);
	if (d[0] == (uint8_t)h->cfg.station)
		return route_exec(h, r, d, s->len);
	if (!h->cfg.route || d[0] == d[1]) {
		r->st.undeliverable++;
		return 0;
	}
	if (!route_queue(r, d[0] == 255 ? ROUTE_BCAST : ROUTE_CMD, d[0], d, s->len)) {
		r->st.undeliverable++; /* the sender's MSG times out */
		return 0;
	}
	if (d[0] == 255) {
		r->st.broadcasts++;
	} else {
		r->st.routed++;
		route_seen(h, d[0]);
	}
	return 0;
}

/* The oldest message to send to stn now. */
struct route_msg *route_next(struct link_route *r, uint8_t stn)
{
	struct route_msg *best = NULL;

	for (int i = 0; i < ROUTE_SLOTS; i++) {
		struct route_msg *m = &r->q[i];

		if (!m->used || m->waiting || m->dst != stn || m->kind == ROUTE_EXEC)
			continue;
		if (!best || (int32_t)(m->seq - best->seq) < 0)
			best = m;
	}
	return best;
}

/* Routed commands whose reply did not come within Cmd_Timeout: STS 05h to their senders. */
void route_expire(struct df1 *h, struct link_route *r)
{
	int64_t now = df1_now_ms();

	for (int i = 0; i < ROUTE_SLOTS; i++) {
		struct route_msg *m = &r->q[i];

		if (m->used && m->kind == ROUTE_CMD && m->waiting && m->deadline_ms <= now) {
			r->st.undeliverable++;
			df1_count(h, DF1_ID_CNT_COMMAND_TIMEOUTS);
			route_error_reply(m, ROUTE_STS_NO_REPLY);
		}
	}
}
