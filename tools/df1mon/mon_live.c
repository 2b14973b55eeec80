/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_live - df1mon: the clocks, waits and stop reasons of the live modes.
 */
#include "df1mon/mon.h"

#include <math.h>
#include <poll.h>
#include <signal.h>
#include <time.h>

int64_t mon_mono_us(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

void mon_wall_now(int64_t *sec, int32_t *usec)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	*sec = (int64_t)ts.tv_sec;
	*usec = (int32_t)(ts.tv_nsec / 1000);
}

/* stdout cannot take more (a closed pipe: SIGPIPE is ignored): end the loop;
 * main reports it and exits 1. */
bool mon_out_broken(void)
{
	return fflush(stdout) != 0 || ferror(stdout);
}

/* Seconds since the live mode started. */
double mon_elapsed(const struct mon *m)
{
	return (double)(mon_mono_us() - m->t0_us) / 1e6;
}

/* Wait ms milliseconds, or until a signal (or --duration) stops us: false then. */
bool mon_sleep(long ms)
{
	int64_t end = mon_mono_us() + (int64_t)ms * 1000;
	int fd = cli_signal_fd();

	while (!cli_stop) {
		int64_t left = end - mon_mono_us();
		struct pollfd p = { .fd = fd, .events = POLLIN };

		if (left <= 0)
			return true;
		poll(fd >= 0 ? &p : NULL, fd >= 0 ? 1 : 0, (int)((left + 999) / 1000));
	}
	return false;
}

const char *mon_signal_name(int sig)
{
	return sig == SIGALRM && cli_stopped_by_timer() ? "--duration" : cli_signal_name(sig);
}

/* A stop by a signal (not by --duration's timer): reported as an interruption. */
bool mon_interrupted(void)
{
	return cli_stop && !cli_stopped_by_timer();
}

long mon_ms_of(double seconds)
{
	return (long)llround(seconds * 1000.0);
}
