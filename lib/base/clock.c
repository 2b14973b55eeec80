/* SPDX-License-Identifier: MPL-2.0 */
/*
 * clock.c - the library's clocks: CLOCK_MONOTONIC, in milliseconds for
 * deadlines and in microseconds for trace timestamps, and the wall clock
 * (CLOCK_REALTIME) only to stamp received bytes for the caller (lib/base/base.h).
 */
#include "base/base.h"

#include <time.h>

int64_t df1_now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

uint64_t df1_now_us(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

void df1_wall_clock(struct timespec *ts)
{
	clock_gettime(CLOCK_REALTIME, ts);
}
