/* SPDX-License-Identifier: MPL-2.0 */
/* repoll.c - the half-duplex master's poll timing (lib/link/half_repoll.h). */
#include "link/half_repoll.h"

void repoll_learn(struct repoll_est *e, int64_t sample_us)
{
	if (sample_us < 0)
		sample_us = 0;
	if (e->samples == 0)
		e->latency_us = sample_us;
	else
		e->latency_us += (sample_us - e->latency_us) / 4;
	if (e->samples < UINT32_MAX)
		e->samples++;
}

int64_t repoll_first_us(const struct repoll_est *e)
{
	return e->samples ? e->latency_us - e->latency_us / 8 : 0;
}

int64_t repoll_next_us(const struct repoll_est *e, int64_t since_ack_us, int64_t min_gap_us,
                       int64_t max_gap_us)
{
	int64_t gap;

	if (e->samples && since_ack_us < e->latency_us) {
		gap = e->latency_us - since_ack_us;     /* not due yet: wait for it */
	} else {
		gap = (since_ack_us - (e->samples ? e->latency_us : 0)) / 8;
		if (gap > max_gap_us)
			gap = max_gap_us;
	}
	return gap < min_gap_us ? min_gap_us : gap;
}
