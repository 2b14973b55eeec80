/*
 * cli_signals - SIGINT/SIGTERM through a self-pipe, SIGUSR1/SIGUSR2 to mute and
 * restore a responder, --duration's timer, the stop signal re-raised at exit
 * (see cli.h).
 */
#include "cli_int.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

volatile sig_atomic_t cli_stop;
volatile sig_atomic_t cli_mute;
static volatile sig_atomic_t stop_signal;
static int sig_pipe[2] = { -1, -1 };

static void on_signal(int sig)
{
	int saved = errno;

	if (sig == SIGUSR1) {
		cli_mute = 1;
	} else if (sig == SIGUSR2) {
		cli_mute = 0;
	} else {
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
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	/* no SA_RESTART: blocking calls return EINTR; a second signal kills as usual */
	sa.sa_flags = SA_RESETHAND;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	sa.sa_flags = 0;
	if (mute) {
		sigaction(SIGUSR1, &sa, NULL);
		sigaction(SIGUSR2, &sa, NULL);
	}
	sa.sa_handler = SIG_IGN;
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
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	if (sigaction(SIGALRM, &sa, NULL) < 0)
		return -1;
	memset(&it, 0, sizeof it);
	it.it_value.tv_sec = ms / 1000;
	it.it_value.tv_usec = (ms % 1000) * 1000;
	return setitimer(ITIMER_REAL, &it, NULL);
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
	return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal";
}

void cli_raise_stop_signal(void)
{
	int sig = cli_stop ? cli_stop_signal() : 0;

	if (sig) {
		fflush(stderr);
		raise(sig);
	}
}
