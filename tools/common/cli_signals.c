/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_signals - every signal that would end a tool, through a self-pipe, so
 * that it ends as SIGINT does (port restored, lock released, the report of what
 * was done); SIGUSR1/SIGUSR2 to mute and restore a responder; --duration's
 * timer; the stop signal re-raised at exit (see cli.h).
 */
#include "common/cli_int.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

volatile sig_atomic_t cli_stop;
volatile sig_atomic_t cli_mute;
static volatile sig_atomic_t stop_signal;
static volatile sig_atomic_t timer_armed, stopped_by_timer;
static volatile sig_atomic_t muting;     /* SIGUSR1/SIGUSR2 mute (a responder) */
static int sig_pipe[2] = { -1, -1 };

/* The signals whose default action ends the process and that can be caught,
 * but SIGPIPE (ignored, so that a closed stdout shows as a write error). */
static const struct {
	int sig;
	const char *name;
} stop_signals[] = {
	{ SIGHUP, "SIGHUP" },     { SIGINT, "SIGINT" },       { SIGQUIT, "SIGQUIT" },
	{ SIGTERM, "SIGTERM" },   { SIGUSR1, "SIGUSR1" },     { SIGUSR2, "SIGUSR2" },
	{ SIGALRM, "SIGALRM" },   { SIGVTALRM, "SIGVTALRM" }, { SIGPROF, "SIGPROF" },
	{ SIGIO, "SIGIO" },       { SIGPWR, "SIGPWR" },       { SIGXCPU, "SIGXCPU" },
	{ SIGXFSZ, "SIGXFSZ" },
};
#define N_STOP_SIGNALS (sizeof stop_signals / sizeof stop_signals[0])

static void on_signal(int sig, siginfo_t *si, void *ctx)
{
	int saved = errno;

	(void)ctx;
	if (muting && sig == SIGUSR1) {
		cli_mute = 1;
	} else if (muting && sig == SIGUSR2) {
		cli_mute = 0;
	} else {
		/* --duration's timer is the kernel's SIGALRM, not one sent with kill */
		if (sig == SIGALRM && timer_armed && si && si->si_code != SI_USER && si->si_code != SI_QUEUE)
			stopped_by_timer = 1;
		cli_stop = 1;
		stop_signal = sig;
	}
	/* a full pipe already has a byte waiting: the flags say what came */
	if (sig_pipe[1] >= 0) {
		ssize_t w = write(sig_pipe[1], "s", 1);
		(void)w;
	}
	errno = saved;
}

static int signals_install(bool mute)
{
	struct sigaction sa;

	if (sig_pipe[0] < 0 && pipe2(sig_pipe, O_CLOEXEC | O_NONBLOCK) < 0) {
		sig_pipe[0] = sig_pipe[1] = -1;
		return -1;
	}
	muting = mute;
	memset(&sa, 0, sizeof sa);
	sa.sa_sigaction = on_signal;
	sigemptyset(&sa.sa_mask);
	for (size_t i = 0; i < N_STOP_SIGNALS; i++) {
		int sig = stop_signals[i].sig;
		bool mutes = mute && (sig == SIGUSR1 || sig == SIGUSR2);

		/* no SA_RESETHAND on the mute pair (they come again and again); a second
		 * stop signal kills as usual. No SA_RESTART: blocking calls see EINTR. */
		sa.sa_flags = SA_SIGINFO | (mutes ? 0 : SA_RESETHAND);
		sigaction(sig, &sa, NULL);
	}
	sa.sa_handler = SIG_IGN;
	sa.sa_flags = 0;
	sigaction(SIGPIPE, &sa, NULL);
	return sig_pipe[0];
}

int cli_signals_install(void)
{
	return signals_install(false);
}

int cli_signals_install_mute(void)
{
	return signals_install(true);
}

void cli_signal_drain(void)
{
	char buf[64];

	while (sig_pipe[0] >= 0 && read(sig_pipe[0], buf, sizeof buf) > 0) {
		/* the flags say what came */
	}
}

int cli_stop_after_ms(long ms)
{
	struct sigaction sa;
	struct itimerval it;

	if (ms <= 0) {
		errno = EINVAL;
		return -1;
	}
	memset(&sa, 0, sizeof sa);
	sa.sa_sigaction = on_signal;
	sa.sa_flags = SA_SIGINFO;
	sigemptyset(&sa.sa_mask);
	if (sigaction(SIGALRM, &sa, NULL) < 0)
		return -1;
	timer_armed = 1;
	memset(&it, 0, sizeof it);
	it.it_value.tv_sec = ms / 1000;
	it.it_value.tv_usec = (ms % 1000) * 1000;
	return setitimer(ITIMER_REAL, &it, NULL);
}

bool cli_stopped_by_timer(void)
{
	return stopped_by_timer != 0;
}

int cli_signal_fd(void)
{
	return sig_pipe[0];
}

int cli_stop_signal(void)
{
	return (int)stop_signal;
}

const char *cli_signal_name(int sig)
{
	for (size_t i = 0; i < N_STOP_SIGNALS; i++)
		if (stop_signals[i].sig == sig)
			return stop_signals[i].name;
	return "a signal";
}

void cli_raise_stop_signal(void)
{
	int sig = cli_stop ? cli_stop_signal() : 0;

	if (!sig || stopped_by_timer)
		return;
	fflush(stdout);
	fflush(stderr);
	/* these three would dump core by default: end with the shell's 128 + N */
	if (sig == SIGQUIT || sig == SIGXCPU || sig == SIGXFSZ)
		_exit(128 + sig);
	signal(sig, SIG_DFL);
	raise(sig);
}
