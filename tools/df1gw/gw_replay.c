/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_replay.c - the pace and the acknowledgements of store and forward's
 * replay (gw_replay.h).
 */
#include "df1gw/gw_replay.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

void gw_replay_init(struct gw_replay *r, unsigned rate)
{
	memset(r, 0, sizeof *r);
	r->rate = rate ? rate : GW_REPLAY_RATE_DEFAULT;
	/* a twentieth of a second's worth at once: the loop wakes every 50 ms
	 * at most for the replay, and a rate under 20 still sends one */
	r->burst = r->rate / 20.0 < 1.0 ? 1.0 : r->rate / 20.0;
	r->tokens = r->burst;
}

static void fill(struct gw_replay *r, int64_t now)
{
	if (r->last_ms && now > r->last_ms) {
		r->tokens += (double)(now - r->last_ms) * r->rate / 1000.0;
		if (r->tokens > r->burst)
			r->tokens = r->burst;
	}
	if (!r->last_ms || now > r->last_ms)
		r->last_ms = now;
}

size_t gw_replay_budget(struct gw_replay *r, int64_t now, size_t per)
{
	size_t room, k;

	fill(r, now);
	if (per == 0)
		per = 1;
	room = (GW_REPLAY_WINDOW - r->n) / per;
	k = r->tokens < 1.0 ? 0 : (size_t)r->tokens;
	return k < room ? k : room;
}

void gw_replay_spent(struct gw_replay *r, size_t k)
{
	r->tokens -= (double)k;
	if (r->tokens < 0)
		r->tokens = 0;
}

int gw_replay_wait_ms(const struct gw_replay *r, int64_t now)
{
	double need = 1.0 - r->tokens;
	int64_t since = r->last_ms && now > r->last_ms ? now - r->last_ms : 0;
	double ms;

	if (need <= 0)
		return 0;
	ms = need * 1000.0 / r->rate - (double)since;
	return ms <= 0 ? 0 : (int)ms + 1;
}

int gw_replay_sent(struct gw_replay *r, int mid, uint64_t seq)
{
	if (r->n >= GW_REPLAY_WINDOW)
		return -1;
	r->v[r->n++] = (struct gw_replay_sent){ mid, seq };
	return 0;
}

bool gw_replay_acked(struct gw_replay *r, int mid, uint64_t *seq)
{
	for (size_t i = 0; i < r->n; i++) {
		if (r->v[i].mid != mid)
			continue;
		*seq = r->v[i].seq;
		memmove(&r->v[i], &r->v[i + 1], (r->n - i - 1) * sizeof r->v[0]);
		r->n--;
		for (size_t j = 0; j < r->n; j++)
			if (r->v[j].seq == *seq)
				return false;   /* another format's message of it is in flight */
		r->replayed++;
		return true;
	}
	return false;
}

void gw_replay_reset(struct gw_replay *r)
{
	r->n = 0;
}

int gw_replay_parse_rate(const char *s, unsigned *rate)
{
	char *end;
	unsigned long v;

	if (!s || *s < '0' || *s > '9')
		return -1;
	errno = 0;
	v = strtoul(s, &end, 10);
	if (errno || (*end && strcmp(end, "/s") != 0) || v < 1 || v > GW_REPLAY_RATE_MAX)
		return -1;
	*rate = (unsigned)v;
	return 0;
}
