/* SPDX-License-Identifier: MPL-2.0 */
/*
 * route_round.c - a half-duplex master's rounds of polls (libdf1(7)
 * UNSOLICITED MESSAGES): what lib/link/route.c queued for each slave is sent,
 * then the slave is polled so that its own messages come in. df1_serve on a
 * master handle (link_master_serve) and the poll engine between its scans
 * (link_route_round) run them.
 *
 * Decisions (relied on by tests/unit/link/test_route.c):
 *  - Stations polled in a round: those given (df1_server_add_station for
 *    df1_serve), those the master has sent commands to (the poll engine's
 *    scan list among them), and those a routed command went to; our own
 *    station never.
 *  - A broadcast goes first in the round; then each station in order: what
 *    is queued for it, a poll, and again while it answers with a message
 *    (at most ROUTE_POLLS_PER_TURN polls: "multiple messages per node
 *    scan", doc/PROTOCOL.md 2.4), so that a reply to its command goes out
 *    before its next poll.
 *  - A poll waits the poll-answer time (DF1_OPT_POLL_TIMEOUT_MS), not the
 *    ACK timeout: a silent station costs little in every round.
 *  - A routed command its target ACKed waits for the reply until
 *    Cmd_Timeout; a target that does not ACK gets the sender STS 02h
 *    (route.c).
 */
#include "link/link.h"

#include "link/link_int.h"

/* The local-error STS the master answers a routed command with (doc/PROTOCOL.md 3.2). */
#define ROUTE_STS_NO_ACK 0x02
/* Messages a slave may send in a row when polled before the next station's turn. */
#define ROUTE_POLLS_PER_TURN 4
/* ms between df1_serve's rounds of polls (a master polls on and on; this
 * keeps an idle line from being a busy loop) */
#define ROUTE_ROUND_GAP_MS 10

/* Send what is queued for stn: 0 or DF1_E_*. */
static int route_deliver(struct df1 *h, struct link_route *r, uint8_t stn)
{
	struct route_msg *m;

	while ((m = route_next(r, stn)) != NULL) {
		int rc = half_send_msg(h, stn, m->app, m->len);

		if (rc < 0)
			return rc;
		if (m->kind == ROUTE_CMD && rc == 1) {
			m->waiting = true;
			m->deadline_ms = df1_now_ms() + (h->cfg.cmd_timeout_ms > 0 ? h->cfg.cmd_timeout_ms
			                                                          : link_timeout_ms(h));
		} else if (m->kind == ROUTE_CMD) {
			r->st.undeliverable++; /* the target did not ACK: the sender hears STS 02h */
			route_error_reply(m, ROUTE_STS_NO_ACK);
		} else {
			if (rc == 0 && m->kind == ROUTE_REPLY)
				r->st.undeliverable++;
			m->used = false;
		}
	}
	return 0;
}

/* stn's turn: what is queued for it, then polls while it has messages. */
static int route_turn(struct df1 *h, struct link_route *r, uint8_t stn)
{
	for (int k = 0; k < ROUTE_POLLS_PER_TURN; k++) {
		int rc = route_deliver(h, r, stn);

		if (rc < 0)
			return rc;
		rc = half_poll_station(h, stn);
		if (rc <= 0)
			return rc;
	}
	return route_deliver(h, r, stn);
}

int link_route_round(struct df1 *h, const bool *stations, link_handler_fn fn, void *ctx)
{
	struct link_route *r = route_state(h);
	int rc = 0;

	if (!r)
		return df1_fail(h, DF1_E_NOMEM, -1, "no memory for the routing state");
	r->fn = fn;
	r->ctx = ctx;
	r->in_round = true;
	route_expire(h, r);
	rc = route_run_kept(h, r);
	if (rc >= 0)
		rc = route_deliver(h, r, 255);
	for (int stn = 0; stn < 255 && rc >= 0; stn++) {
		if (stn == h->cfg.station)
			continue; /* ourselves */
		if ((stations && stations[stn]) || r->poll[stn])
			rc = route_turn(h, r, (uint8_t)stn);
	}
	r->fn = NULL;
	r->ctx = NULL;
	r->in_round = false;
	return rc;
}

static uint64_t route_handled(const struct link_route *r)
{
	return r->st.executed + r->st.routed + r->st.broadcasts + r->st.route_replies;
}

int link_master_serve(struct df1 *h, struct link_responder *resp, link_handler_fn fn, void *ctx,
                      int64_t deadline_ms)
{
	struct link_route *r = route_state(h);
	uint64_t before;

	if (!r)
		return df1_fail(h, DF1_E_NOMEM, -1, "no memory for the routing state");
	before = route_handled(r);
	for (;;) {
		struct df1_symbol s;
		int64_t now, dl;
		int rc = link_route_round(h, resp->serve_station, fn, ctx);

		if (rc < 0)
			return rc;
		now = df1_now_ms();
		if (route_handled(r) != before || now >= deadline_ms)
			return (int)(route_handled(r) - before);
		/* the pause between rounds is a read: a quiet line, anything is noise */
		dl = now + ROUTE_ROUND_GAP_MS < deadline_ms ? now + ROUTE_ROUND_GAP_MS : deadline_ms;
		rc = link_read_symbol(h, dl, &s);
		if (rc < 0)
			return rc;
	}
}
