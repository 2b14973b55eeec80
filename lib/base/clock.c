/*
 * clock.c - the library's only clock: CLOCK_MONOTONIC, in milliseconds for
 * deadlines and in microseconds for trace timestamps (lib/base/base.h).
 */
#include "base.h"

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
