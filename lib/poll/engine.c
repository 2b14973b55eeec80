/* SPDX-License-Identifier: MPL-2.0 */
/*
 * engine.c - the poll engine's allocation (on first use) and teardown (df1_free),
 * the names of qualities, reasons and station states, the settings, the
 * statistics and df1_station_health(); the queue's end (df1_poll_cancel_queued).
 */
#include "poll/poll_int.h"

static void poll_free_engine(struct df1 *h);

struct poll_engine *poll_engine(struct df1 *h)
{
	struct poll_engine *e = h->poll;

	if (e)
		return e;
	e = calloc(1, sizeof *e);
	if (!e)
		return NULL;
	if (pthread_mutex_init(&e->mu, NULL) != 0) {
		free(e);
		return NULL;
	}
	e->wake_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
	if (e->wake_fd < 0) {
		pthread_mutex_destroy(&e->mu);
		free(e);
		return NULL;
	}
	e->wd_ms = POLL_WATCHDOG_DEFAULT_MS;
	e->lo = e->hi = -1;
	e->next_wid = 1;
	h->poll = e;
	h->poll_free = poll_free_engine;
	return e;
}

/* ------------------------------------------------------------------------
 * Names
 * ------------------------------------------------------------------------ */

const char *df1_quality_name(enum df1_quality q)
{
	switch (q) {
	case DF1_QUALITY_GOOD: return "GOOD";
	case DF1_QUALITY_UNCERTAIN: return "UNCERTAIN";
	case DF1_QUALITY_BAD: return "BAD";
	}
	return "?";
}

const char *df1_reason_name(enum df1_quality_reason r)
{
	switch (r) {
	case DF1_REASON_NONE: return "none";
	case DF1_REASON_NOT_YET_READ: return "not_yet_read";
	case DF1_REASON_COMM_FAILURE: return "comm_failure";
	case DF1_REASON_STATION_OFFLINE: return "station_offline";
	case DF1_REASON_PLC_ERROR: return "plc_error";
	case DF1_REASON_CONFIG: return "config";
	}
	return "?";
}

const char *df1_station_state_name(enum df1_station_state s)
{
	switch (s) {
	case DF1_STATION_UNKNOWN: return "unknown";
	case DF1_STATION_OK: return "ok";
	case DF1_STATION_FAILING: return "failing";
	case DF1_STATION_OFFLINE: return "offline";
	case DF1_STATION_ABSENT: return "absent";
	}
	return "?";
}

/* ------------------------------------------------------------------------
 * Settings and statistics
 * ------------------------------------------------------------------------ */

int df1_poll_set_watchdog(df1_t *h, int watchdog_ms, int absolute_retries)
{
	struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	if (watchdog_ms < 0 || watchdog_ms > POLL_WATCHDOG_MAX_MS || absolute_retries < 0 ||
	    absolute_retries > POLL_RETRIES_MAX)
		return df1_fail(h, DF1_E_INVAL, -1,
		                "watchdog %d ms / retries %d: must be 0..%d ms and 0..%d", watchdog_ms,
		                absolute_retries, POLL_WATCHDOG_MAX_MS, POLL_RETRIES_MAX);
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	e->wd_ms = watchdog_ms;
	e->abs_retries = absolute_retries;
	return 0;
}

int df1_poll_set_station_range(df1_t *h, int lo, int hi)
{
	struct poll_engine *e;

	if (!h)
		return DF1_E_INVAL;
	if (lo >= 0 && (lo > 254 || hi < lo || hi > 254))
		return df1_fail(h, DF1_E_INVAL, -1, "station range %d-%d: must be within 0-254", lo, hi);
	e = poll_engine(h);
	if (!e)
		return df1_fail(h, DF1_E_NOMEM, -1, "poll engine: out of memory");
	if (lo < 0) {
		e->lo = e->hi = -1;
		return 0;
	}
	e->lo = lo;
	e->hi = hi;
	e->probe_next = lo;
	e->probe_due_ms = 0;
	for (int s = 0; s < POLL_STATIONS; s++)
		e->st[s].in_range = s >= lo && s <= hi;
	return 0;
}

int df1_poll_stats(const df1_t *h, struct df1_poll_stats *out)
{
	struct poll_engine *e;

	if (!h || !out)
		return DF1_E_INVAL;
	memset(out, 0, sizeof *out);
	e = h->poll;
	if (!e)
		return 0;
	*out = e->stats;
	out->tags = (unsigned)e->ntags;
	out->blocks = (unsigned)e->nblocks;
	out->stations_offline = 0;
	for (int s = 0; s < POLL_STATIONS; s++)
		out->stations_offline += e->st[s].state == DF1_STATION_OFFLINE;
	pthread_mutex_lock(&e->mu);
	out->writes_queued = e->wq_len;
	pthread_mutex_unlock(&e->mu);
	return 0;
}

int df1_station_health(const df1_t *h, int station, struct df1_station_health *out)
{
	const struct poll_engine *e;
	const struct pstation *s;

	if (!h || !out || station < 0 || station > 254)
		return DF1_E_INVAL;
	memset(out, 0, sizeof *out);
	out->station = station;
	e = h->poll;
	if (!e)
		return 0;
	s = &e->st[station];
	out->state = s->state;
	out->tags = s->tags;
	out->blocks = s->nb;
	out->last_good_ms = s->last_good_ms;
	out->last_attempt_ms = s->last_attempt_ms;
	out->next_retry_ms = s->state == DF1_STATION_OFFLINE ? s->next_retry_ms : 0;
	out->consecutive_failures = s->fails;
	out->attempts = s->attempts;
	out->failures = s->failures;
	out->last_error = s->last_error;
	return 0;
}

/* Deprecated since 0.2: the old name, kept so that existing programs link. */
int df1_poll_station(const df1_t *h, int station, struct df1_station_health *out)
{
	return df1_station_health(h, station, out);
}

/* ------------------------------------------------------------------------
 * Teardown (df1_free)
 * ------------------------------------------------------------------------ */

/* Everything queued ends with DF1_E_NOT_OPEN, unsent; how many. */
static int poll_wq_cancel(struct poll_engine *e)
{
	struct wnode *w;
	int n = 0;

	pthread_mutex_lock(&e->mu);
	w = e->wq_head;
	e->wq_head = e->wq_tail = NULL;
	e->wq_len = 0;
	e->pccc_len = 0;
	pthread_mutex_unlock(&e->mu);
	while (w) {
		struct wnode *next = w->next;

		if (w->pdone)
			w->pdone(w->user, DF1_E_NOT_OPEN, NULL, 0);
		else if (w->done)
			w->done(w->user, w->tag, w->wid, DF1_E_NOT_OPEN);
		free(w);
		w = next;
		n++;
	}
	return n;
}

int df1_poll_cancel_queued(df1_t *h)
{
	if (!h)
		return DF1_E_INVAL;
	return h->poll ? poll_wq_cancel(h->poll) : 0;
}

static void poll_free_engine(struct df1 *h)
{
	struct poll_engine *e = h->poll;

	if (!e)
		return;
	/* every accepted write ends once: those never sent fail now */
	poll_wq_cancel(e);
	for (size_t i = 0; i < e->ntags; i++) {
		free(e->tags[i]->values);
		free(e->tags[i]);
	}
	free(e->tags);
	free(e->names);
	free(e->blocks);
	free(e->members);
	free(e->raw);
	free(e->vals);
	close(e->wake_fd);
	pthread_mutex_destroy(&e->mu);
	free(e);
	h->poll = NULL;
}
