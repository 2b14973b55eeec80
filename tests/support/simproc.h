/* SPDX-License-Identifier: MPL-2.0 */
/*
 * simproc - df1sim as a separate process for integration tests: fork/exec of
 * $DF1_BIN/df1sim (default build/bin), its ready line read from a pipe with a
 * poll() deadline, SIGTERM + waitpid at the end. Each simulator gets a private
 * temporary directory for its pty link, its --data file and its --log file.
 * Plain libc, no cmocka: it is linked into every test binary.
 */
#ifndef LIBDF1_TESTS_SIMPROC_H
#define LIBDF1_TESTS_SIMPROC_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

struct simproc {
	pid_t pid;              /* 0 when not running */
	char dir[64];           /* private temporary directory */
	char target[300];       /* what df1sim printed: the pty link or tcp://HOST:PORT */
	char log[128];          /* DIR/log when a log was asked for, else "" */
	char data[128];         /* DIR/data when data was given, else "" */
	char err[128];          /* DIR/stderr: df1sim's standard error */
	bool tcp;
};

/* Start df1sim serving a pty (tcp false: --pty DIR/tty) or TCP (tcp true:
 * --listen tcp://127.0.0.1:0), with --data DIR/data holding `data` (NULL: none),
 * --log DIR/log if `log`, and the NULL-terminated extra options `args` (may be
 * NULL). Waits up to 10 s for the ready line. Returns 0, or -1 with a message on
 * stderr (nothing left running). */
int simproc_start(struct simproc *sp, bool tcp, const char *data, bool log, const char *const *args);

/* The same serving a device that exists already (-d DEV: df1sim opens it with
 * df1_open, the termios backend for a tty). */
int simproc_start_device(struct simproc *sp, const char *dev, const char *data, bool log,
                         const char *const *args);

/* SIGTERM, wait (up to 5 s, then SIGKILL) and remove the directory unless
 * keep_dir (the log and df1sim's stderr stay readable until simproc_cleanup).
 * df1sim's stderr is copied to ours when it did not exit 0. Returns the exit
 * status (0 = stopped cleanly by the signal), or -1 if it had to be killed or
 * was not running. */
int simproc_stop(struct simproc *sp, bool keep_dir);
/* Remove the directory and its files (after simproc_stop(sp, true)). */
void simproc_cleanup(struct simproc *sp);

/* Lines of df1sim's --log (one per command answered) holding n1 and, if not NULL,
 * n2 (n1 NULL: every line); -1 if the log cannot be read. */
int simproc_log_count(const struct simproc *sp, const char *n1, const char *n2);
/* df1sim logs a command after its reply went out, so a line may come a moment
 * after the reply reached the test: wait (inotify on the log, until timeout_ms)
 * for at least `want` such lines. Returns the count then. */
int simproc_log_wait(const struct simproc *sp, const char *n1, const char *n2, int want,
                     int timeout_ms);

/* Read a whole file into a NUL-terminated malloc'd buffer; NULL on error. */
char *simproc_slurp(const char *path, size_t *len);

#endif
