/* SPDX-License-Identifier: MPL-2.0 */
/*
 * probe.c - station discovery in the poll engine (doc/REQUIREMENTS.md 002,
 * df1_poll_set_station_range): the addresses of the range without tags are
 * probed with discover_probe(), the probe of df1_discover() (lib/client/discover.c):
 * a link test (half duplex) or an empty echo (full duplex). poll_discover() is
 * the one entry point the scan calls to probe, poll_discover_due() when
 * discovery wants the next scan.
 */
#include "poll/poll_int.h"

/* A station without tags: discovery's probe, a link test (half duplex) or an
 * empty echo (full duplex). */
static int poll_probe(struct df1 *h, struct poll_engine *e, int stn, int tries)
{
	int done = 0;

	for (;;) {
		struct pstation *s = &e->st[stn];
		int rc, w;
		enum outcome o;
		int64_t now;

		w = poll_run_writes(h, e);
		if (w < 0)
			return w;
		done += w;
		now = df1_now_ms();
		poll_attempt(e, stn, now);
		e->stats.probes++;
		e->scan_tx++;
		done++;
		rc = discover_probe(h, stn, 0, NULL);
		o = poll_outcome(h, rc);
		now = df1_now_ms();
		if (o == OUT_ABORT)
			return rc;
		if (o == OUT_LOCAL)
			return done;
		if (o != OUT_LINK) {
			poll_station_answer(e, stn, now);
			s->recovered = false;
			return done;
		}
		e->stats.probe_failures++;
		poll_station_fail(e, stn, rc, now);
		if (s->state == DF1_STATION_OFFLINE || s->state == DF1_STATION_ABSENT || --tries <= 0)
			return done;
		e->stats.retries++;
	}
}

static bool poll_in_range(const struct poll_engine *e, int stn)
{
	return e->lo >= 0 && stn >= e->lo && stn <= e->hi;
}

/* The next absent (or never probed) address of the range, in turn. */
static int poll_probe_candidate(struct poll_engine *e)
{
	int span = e->hi - e->lo + 1;

	for (int k = 0; k < span; k++) {
		int stn = e->lo + (e->probe_next - e->lo + k) % span;
		const struct pstation *s = &e->st[stn];

		if (stn < e->lo || stn > e->hi)
			continue;
		if (s->nb == 0 && (s->state == DF1_STATION_UNKNOWN || s->state == DF1_STATION_ABSENT)) {
			e->probe_next = stn + 1 > e->hi ? e->lo : stn + 1;
			return stn;
		}
	}
	return -1;
}

/* Discovery for station stn (no tags) in the scan that started at start; stn
 * < 0 begins the scan (is it a probe scan, which absent address is probed in
 * it). Returns transactions done (>= 0) or a code that ends df1_poll. */
int poll_discover(struct df1 *h, struct poll_engine *e, int stn, int64_t start,
                  struct poll_probe_scan *ps)
{
	struct pstation *s;

	if (stn < 0) {
		ps->probe = e->lo >= 0 && start >= e->probe_due_ms;
		ps->cand = -1;
		if (ps->probe) {
			e->probe_due_ms = start + POLL_PROBE_MS;
			ps->cand = poll_probe_candidate(e);
		}
		return 0;
	}
	if (!poll_in_range(e, stn))
		return 0;
	s = &e->st[stn];
	if (s->state == DF1_STATION_OFFLINE) {
		if (start < s->next_retry_ms)
			return 0;
		s->next_retry_ms = start + e->wd_ms / 2;
		return poll_probe(h, e, stn, 1);
	}
	if (s->state == DF1_STATION_OK || s->state == DF1_STATION_FAILING)
		return ps->probe ? poll_probe(h, e, stn, poll_tries(s)) : 0;
	return stn == ps->cand ? poll_probe(h, e, stn, 1) : 0;
}

/* When discovery is due next (the next probe scan, an offline address's slow
 * retry), or due if that is sooner. */
int64_t poll_discover_due(const struct poll_engine *e, int64_t due)
{
	if (e->lo < 0)
		return due;
	if (e->probe_due_ms < due)
		due = e->probe_due_ms;
	for (int stn = e->lo; stn <= e->hi; stn++) {
		const struct pstation *s = &e->st[stn];

		if (s->nb == 0 && s->state == DF1_STATION_OFFLINE && s->next_retry_ms < due)
			due = s->next_retry_ms;
	}
	return due;
}
