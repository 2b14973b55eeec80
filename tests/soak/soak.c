/* SPDX-License-Identifier: MPL-2.0 */
/*
 * soak.c - `make soak`: transactions through df1sim with every fault it
 * offers, in lanes at once (full and half duplex, CRC and BCC), each on its
 * own df1sim process and pty (soak.h, README "Soak").
 *
 *   soak [-n TRANSACTIONS] [-l LANES] [-s SEED]
 *
 * LANES (default 12) run at once, each link setting in turn: most of a lane's
 * time is spent waiting out the faults, so lanes add up on two cores.
 *
 * Prints the figures; exits 1 if any value read was wrong, any write ran
 * twice or was reported written without running, or any call hung (took more
 * than its Cmd_Timeout and link retries allow, plus a margin), or if df1sim
 * logged a command it never sent; 2 if it could not run.
 */
#include "soak.h"

#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define LANES_MAX 16

static void usage(void)
{
	fprintf(stderr, "usage: soak [-n TRANSACTIONS] [-l LANES 1-%d] [-s SEED]\n", LANES_MAX);
	exit(2);
}

static bool number(const char *s, unsigned long long *out)
{
	char *end;

	if (!s || *s < '0' || *s > '9')
		return false;
	errno = 0;
	*out = strtoull(s, &end, 10);
	return !errno && !*end;
}

static double seconds_since(const struct timespec *t0)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)(t.tv_sec - t0->tv_sec) + (double)(t.tv_nsec - t0->tv_nsec) / 1e9;
}

int main(int argc, char **argv)
{
	static struct lane lanes[LANES_MAX];
	static _Atomic uint64_t done;
	pthread_t th[LANES_MAX];
	unsigned long long total = 20000, seed = 1, nl = 12;
	long rss0 = 0, rss1 = 0, sim0 = 0, sim1 = 0;
	struct lane_figures f;
	struct ledger_figures g;
	struct timespec t0;
	bool failed_setup = false;
	int opt, lanes_n;

	while ((opt = getopt(argc, argv, "n:l:s:h")) != -1) {
		switch (opt) {
		case 'n':
			if (!number(optarg, &total) || total == 0)
				usage();
			break;
		case 'l':
			if (!number(optarg, &nl) || nl == 0 || nl > LANES_MAX)
				usage();
			break;
		case 's':
			if (!number(optarg, &seed))
				usage();
			break;
		default:
			usage();
		}
	}
	signal(SIGPIPE, SIG_IGN);
	lanes_n = (int)nl;
	for (int i = 0; i < lanes_n; i++) {
		struct lane *ln = &lanes[i];

		ln->id = i;
		ln->half = i % 4 >= 2;
		ln->check = i % 2 ? DF1_CHECK_BCC : DF1_CHECK_CRC;
		ln->done = &done;
		ln->target = total;
		ln->seed = seed * 16 + (unsigned long long)i + 1;
		if (lane_setup(ln) < 0) {
			fprintf(stderr, "soak: lane %d: %s\n", i, ln->error ? ln->error : "set-up failed");
			failed_setup = true;
			break;
		}
	}
	if (failed_setup) {
		for (int i = 0; i < lanes_n; i++)
			lane_finish(&lanes[i]);
		return 2;
	}
	rss0 = soak_rss_kb(0);
	for (int i = 0; i < lanes_n; i++)
		sim0 += soak_rss_kb(lanes[i].sp.pid);
	clock_gettime(CLOCK_MONOTONIC, &t0);
	for (int i = 0; i < lanes_n; i++)
		if (pthread_create(&th[i], NULL, lane_run, &lanes[i]) != 0) {
			fprintf(stderr, "soak: cannot start lane %d\n", i);
			return 2;
		}
	for (int i = 0; i < lanes_n; i++)
		pthread_join(th[i], NULL);
	rss1 = soak_rss_kb(0);
	for (int i = 0; i < lanes_n; i++)
		sim1 += soak_rss_kb(lanes[i].sp.pid);
	memset(&f, 0, sizeof f);
	memset(&g, 0, sizeof g);
	for (int i = 0; i < lanes_n; i++) {
		struct lane *ln = &lanes[i];

		if (lane_finish(ln) < 0 && !ln->error)
			ln->error = "df1sim did not stop cleanly";
		if (ln->error) {
			fprintf(stderr, "soak: lane %d: %s\n", i, ln->error);
			failed_setup = true;
		}
		f.transactions += ln->fig.transactions;
		f.calls += ln->fig.calls;
		f.ok += ln->fig.ok;
		f.failed += ln->fig.failed;
		f.wrong += ln->fig.wrong;
		f.hangs += ln->fig.hangs;
		f.silenced += ln->fig.silenced;
		f.polls += ln->fig.polls;
		f.tag_writes += ln->fig.tag_writes;
		if (ln->fig.max_call_ms > f.max_call_ms)
			f.max_call_ms = ln->fig.max_call_ms;
		g.writes_sent += ln->led.fig.writes_sent;
		g.writes_ok += ln->led.fig.writes_ok;
		g.writes_failed += ln->led.fig.writes_failed;
		g.executed_twice += ln->led.fig.executed_twice;
		g.lost += ln->led.fig.lost;
		g.failed_executed += ln->led.fig.failed_executed;
		g.log_lines += ln->led.fig.log_lines;
		g.log_unmatched += ln->led.fig.log_unmatched;
	}
	printf("soak: %d lanes (full/half duplex, CRC/BCC), faults drop-ack corrupt nak delay stale "
	       "noise 1%% each, silent station, SIGUSR1 silence 1%%, seed %llu\n", lanes_n, seed);
	printf("elapsed                     %.1f s\n", seconds_since(&t0));
	printf("transactions                %llu\n", (unsigned long long)f.transactions);
	printf("calls                       %llu (%llu ok, %llu failed; %llu poll scans)\n",
	       (unsigned long long)f.calls, (unsigned long long)f.ok, (unsigned long long)f.failed,
	       (unsigned long long)f.polls);
	printf("writes                      %llu (%llu written, %llu failed; %llu queued tag writes)\n",
	       (unsigned long long)g.writes_sent, (unsigned long long)g.writes_ok,
	       (unsigned long long)g.writes_failed, (unsigned long long)f.tag_writes);
	printf("failed writes executed      %llu (honest: a failed write may have run once)\n",
	       (unsigned long long)g.failed_executed);
	printf("df1sim log lines            %llu (%llu not matching a command sent)\n",
	       (unsigned long long)g.log_lines, (unsigned long long)g.log_unmatched);
	printf("longest call                %lld ms\n", (long long)f.max_call_ms);
	for (int i = 0; i < lanes_n; i++)
		printf("lane %2d %s %s            %llu transactions in %.1f s\n", i,
		       lanes[i].half ? "half" : "full", lanes[i].check == DF1_CHECK_BCC ? "BCC" : "CRC",
		       (unsigned long long)lanes[i].fig.transactions, lanes[i].fig.elapsed_ms / 1000.0);
	printf("wrong values as success     %llu\n", (unsigned long long)f.wrong);
	printf("writes executed twice       %llu\n", (unsigned long long)g.executed_twice);
	printf("writes lost                 %llu\n", (unsigned long long)g.lost);
	printf("hangs                       %llu\n", (unsigned long long)f.hangs);
	printf("RSS soak start/end          %ld kB / %ld kB\n", rss0, rss1);
	printf("RSS df1sim start/end        %ld kB / %ld kB (%d processes)\n", sim0, sim1, lanes_n);
	if (failed_setup)
		return 2;
	return f.wrong || g.executed_twice || g.lost || f.hangs || g.log_unmatched ? 1 : 0;
}
