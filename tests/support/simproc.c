/* SPDX-License-Identifier: MPL-2.0 */
/*
 * simproc - df1sim as a separate process (see simproc.h).
 */
#include "support/simproc.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/inotify.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define SIMPROC_ARGS_MAX 64
#define SIMPROC_READY_MS 10000
#define SIMPROC_STOP_MS 5000

static long long simproc_now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (long long)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static int simproc_write_file(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");

	if (!f)
		return -1;
	fputs(text, f);
	return fclose(f) == 0 ? 0 : -1;
}

char *simproc_slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "r");
	char *buf = NULL;
	size_t n = 0, cap = 0;

	if (!f)
		return NULL;
	for (;;) {
		if (cap - n < 4096) {
			char *nb = realloc(buf, cap + 8192);

			if (!nb) {
				free(buf);
				fclose(f);
				return NULL;
			}
			buf = nb;
			cap += 8192;
		}
		size_t k = fread(buf + n, 1, cap - n - 1, f);

		n += k;
		if (k == 0)
			break;
	}
	fclose(f);
	buf[n] = '\0';
	if (len)
		*len = n;
	return buf;
}

void simproc_cleanup(struct simproc *sp)
{
	char path[160];

	if (!sp->dir[0])
		return;
	if (sp->log[0])
		unlink(sp->log);
	if (sp->data[0])
		unlink(sp->data);
	if (sp->err[0])
		unlink(sp->err);
	snprintf(path, sizeof path, "%s/tty", sp->dir);
	unlink(path);           /* normally removed by df1sim itself */
	rmdir(sp->dir);
	sp->dir[0] = '\0';
}

/* Wait for the child to end, up to ms: pidfd + poll() where the kernel has it,
 * else WNOHANG checks between short poll() waits. Returns the wait status or -1. */
static int simproc_wait(pid_t pid, int ms)
{
	long long deadline = simproc_now_ms() + ms;
	int status = 0, pfd = -1;

#ifdef SYS_pidfd_open
	pfd = (int)syscall(SYS_pidfd_open, pid, 0);
#endif
	for (;;) {
		pid_t r = waitpid(pid, &status, WNOHANG);
		long long left;

		if (r == pid) {
			if (pfd >= 0)
				close(pfd);
			return status;
		}
		if (r < 0 && errno != EINTR) {
			if (pfd >= 0)
				close(pfd);
			return -1;
		}
		left = deadline - simproc_now_ms();
		if (left <= 0) {
			if (pfd >= 0)
				close(pfd);
			return -1;
		}
		if (pfd >= 0) {
			struct pollfd p = { pfd, POLLIN, 0 };

			(void)poll(&p, 1, (int)left);
		} else {
			(void)poll(NULL, 0, left < 10 ? (int)left : 10);
		}
	}
}

static int simproc_spawn(struct simproc *sp, bool tcp, const char *dev, const char *data, bool log,
                         const char *const *args)
{
	const char *bin = getenv("DF1_BIN");
	char exe[512], tty[128], line[sizeof sp->target];
	const char *argv[SIMPROC_ARGS_MAX];
	int argc = 0, pipefd[2];
	size_t got = 0;
	long long deadline;
	pid_t pid, parent;

	memset(sp, 0, sizeof *sp);
	sp->tcp = tcp;
	if (!bin || !*bin)
		bin = "build/bin";
	snprintf(exe, sizeof exe, "%s/df1sim", bin);
	if (access(exe, X_OK) != 0) {
		fprintf(stderr, "simproc: %s: %s\n", exe, strerror(errno));
		return -1;
	}
	snprintf(sp->dir, sizeof sp->dir, "%s/df1it.XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (!mkdtemp(sp->dir)) {
		fprintf(stderr, "simproc: mkdtemp: %s\n", strerror(errno));
		sp->dir[0] = '\0';
		return -1;
	}
	snprintf(sp->err, sizeof sp->err, "%s/stderr", sp->dir);
	argv[argc++] = exe;
	if (dev) {
		argv[argc++] = "-d";
		argv[argc++] = dev;
	} else if (tcp) {
		argv[argc++] = "--listen";
		argv[argc++] = "tcp://127.0.0.1:0";
	} else {
		snprintf(tty, sizeof tty, "%s/tty", sp->dir);
		argv[argc++] = "--pty";
		argv[argc++] = tty;
	}
	if (data) {
		snprintf(sp->data, sizeof sp->data, "%s/data", sp->dir);
		if (simproc_write_file(sp->data, data) < 0) {
			fprintf(stderr, "simproc: %s: %s\n", sp->data, strerror(errno));
			simproc_cleanup(sp);
			return -1;
		}
		argv[argc++] = "--data";
		argv[argc++] = sp->data;
	}
	if (log) {
		snprintf(sp->log, sizeof sp->log, "%s/log", sp->dir);
		argv[argc++] = "--log";
		argv[argc++] = sp->log;
	}
	for (size_t i = 0; args && args[i] && argc < SIMPROC_ARGS_MAX - 1; i++)
		argv[argc++] = args[i];
	argv[argc] = NULL;

	if (pipe2(pipefd, O_CLOEXEC) < 0) {
		fprintf(stderr, "simproc: pipe: %s\n", strerror(errno));
		simproc_cleanup(sp);
		return -1;
	}
	fflush(NULL);
	parent = getpid();
	pid = fork();
	if (pid < 0) {
		fprintf(stderr, "simproc: fork: %s\n", strerror(errno));
		close(pipefd[0]);
		close(pipefd[1]);
		simproc_cleanup(sp);
		return -1;
	}
	if (pid == 0) {
		/* the child: stdout is the pipe (dup2 clears FD_CLOEXEC on the copy);
		 * SIGTERM when the test process dies without stopping it (a crash,
		 * SIGPIPE on a closed output) */
		int efd = open(sp->err, O_WRONLY | O_CREAT | O_TRUNC, 0600);

		if (dup2(pipefd[1], STDOUT_FILENO) < 0 || efd < 0 || dup2(efd, STDERR_FILENO) < 0)
			_exit(127);
		if (prctl(PR_SET_PDEATHSIG, SIGTERM) < 0 || getppid() != parent)
			_exit(127);
		execv(exe, (char *const *)argv);
		_exit(127);
	}
	close(pipefd[1]);
	sp->pid = pid;

	/* the ready line, within the deadline */
	deadline = simproc_now_ms() + SIMPROC_READY_MS;
	for (;;) {
		struct pollfd p = { pipefd[0], POLLIN, 0 };
		long long left = deadline - simproc_now_ms();
		ssize_t k;
		char *nl;

		if (left <= 0) {
			fprintf(stderr, "simproc: df1sim did not get ready within %d ms\n", SIMPROC_READY_MS);
			break;
		}
		if (poll(&p, 1, (int)left) < 0) {
			if (errno == EINTR)
				continue;
			break;
		}
		if (!(p.revents & (POLLIN | POLLHUP)))
			continue;
		k = read(pipefd[0], line + got, sizeof line - 1 - got);
		if (k < 0 && errno == EINTR)
			continue;
		if (k <= 0) {
			fprintf(stderr, "simproc: df1sim exited before it was ready\n");
			break;
		}
		got += (size_t)k;
		line[got] = '\0';
		nl = strchr(line, '\n');
		if (nl) {
			*nl = '\0';
			snprintf(sp->target, sizeof sp->target, "%s", line);
			close(pipefd[0]);
			return 0;
		}
		if (got == sizeof line - 1)
			break;
	}
	close(pipefd[0]);
	simproc_stop(sp, false);
	return -1;
}

int simproc_start(struct simproc *sp, bool tcp, const char *data, bool log, const char *const *args)
{
	return simproc_spawn(sp, tcp, NULL, data, log, args);
}

int simproc_start_device(struct simproc *sp, const char *dev, const char *data, bool log,
                         const char *const *args)
{
	return simproc_spawn(sp, false, dev, data, log, args);
}

/* Copy df1sim's stderr to ours. */
static void simproc_dump_err(const struct simproc *sp)
{
	char *text = sp->err[0] ? simproc_slurp(sp->err, NULL) : NULL;

	if (text && *text)
		fprintf(stderr, "simproc: df1sim %s said:\n%s", sp->target, text);
	free(text);
}

int simproc_stop(struct simproc *sp, bool keep_dir)
{
	int status = -1, ws;

	if (sp->pid > 0) {
		kill(sp->pid, SIGTERM);
		ws = simproc_wait(sp->pid, SIMPROC_STOP_MS);
		if (ws < 0) {
			fprintf(stderr, "simproc: df1sim (pid %d) did not stop on SIGTERM; killing it\n",
			        (int)sp->pid);
			kill(sp->pid, SIGKILL);
			(void)simproc_wait(sp->pid, SIMPROC_STOP_MS);
		} else if (WIFEXITED(ws)) {
			status = WEXITSTATUS(ws);
		}
		sp->pid = 0;
		if (status != 0)
			simproc_dump_err(sp);
	}
	if (!keep_dir)
		simproc_cleanup(sp);
	return status;
}

int simproc_log_count(const struct simproc *sp, const char *n1, const char *n2)
{
	char *text = simproc_slurp(sp->log, NULL), *line, *save = NULL;
	int n = 0;

	if (!text)
		return -1;
	for (line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save))
		if ((!n1 || strstr(line, n1)) && (!n2 || strstr(line, n2)))
			n++;
	free(text);
	return n;
}

int simproc_log_wait(const struct simproc *sp, const char *n1, const char *n2, int want,
                     int timeout_ms)
{
	long long dl = simproc_now_ms() + timeout_ms;
	int fd = inotify_init1(IN_CLOEXEC | IN_NONBLOCK), n;

	if (fd >= 0 && inotify_add_watch(fd, sp->log, IN_MODIFY) < 0) {
		close(fd);
		fd = -1;
	}
	while ((n = simproc_log_count(sp, n1, n2)) < want && simproc_now_ms() < dl) {
		struct pollfd p = { fd, POLLIN, 0 };
		char buf[4096];

		if (fd < 0 || poll(&p, 1, (int)(dl - simproc_now_ms())) <= 0)
			break;
		while (read(fd, buf, sizeof buf) > 0)
			;
	}
	if (fd >= 0)
		close(fd);
	return n;
}
