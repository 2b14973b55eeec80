/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_pace.c - df1sim's full-duplex UART (tools/df1sim/sim_line.h): the two
 * paced queues of the relay. A byte read from one side is handed to the
 * other when its last bit would have arrived at the line's rate, counted
 * from the later of its arrival and the previous byte's end in the same
 * direction; the other direction's bytes do not delay it.
 */
#include "df1sim/sim_line.h"

#include <string.h>
#include <time.h>

static int64_t sim_pace_now_us(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

bool sim_pace_put(struct sim_pace *q, int64_t char_us, const uint8_t *b, size_t n)
{
	int64_t now = sim_pace_now_us();

	if (q->len + n > SIM_PACE_MAX)
		return false;
	if (q->head + q->len + n > SIM_PACE_MAX) {      /* compact: the ring is a line */
		memmove(q->b, q->b + q->head, q->len);
		memmove(q->due_us, q->due_us + q->head, q->len * sizeof q->due_us[0]);
		q->head = 0;
	}
	for (size_t i = 0; i < n; i++) {
		int64_t from = q->last_due_us > now ? q->last_due_us : now;

		q->last_due_us = from + char_us;
		q->b[q->head + q->len] = b[i];
		q->due_us[q->head + q->len] = q->last_due_us;
		q->len++;
	}
	return true;
}

int sim_pace_flush(struct sim_relay *r, struct sim_pace *q,
                   int (*emit)(struct sim_relay *r, const uint8_t *b, size_t n))
{
	int64_t now = sim_pace_now_us();
	size_t k = 0;

	while (k < q->len && q->due_us[q->head + k] <= now)
		k++;
	if (k == 0)
		return 0;
	if (emit(r, q->b + q->head, k) < 0)
		return -1;
	q->head += k;
	q->len -= k;
	if (q->len == 0)
		q->head = 0;
	return 0;
}

int64_t sim_pace_wait_us(const struct sim_pace *q)
{
	int64_t d;

	if (q->len == 0)
		return -1;
	d = q->due_us[q->head] - sim_pace_now_us();
	return d > 0 ? d : 0;
}
