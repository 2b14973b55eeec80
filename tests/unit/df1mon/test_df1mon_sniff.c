/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_df1mon_sniff - df1mon --sniff as a process on real pseudo-terminals.
 *
 * A tap needs a third party on a line, which a pty pair cannot give; here the
 * test is the line: it opens a pty pair (posix_openpt), sets the slave to
 * known settings (raw, 9600 baud), starts `df1mon --sniff -d SLAVE -w FILE`,
 * waits until df1mon has put the port at 19200 (its tcsetattr shows through
 * our own slave descriptor: the ready signal, no sleeps), writes frames of
 * doc/PROTOCOL.md 7 into the master (one split across two writes), waits for
 * the decoded lines, stops df1mon with SIGINT and checks:
 *   - exit 0 and one line per symbol, decoded as doc/PROTOCOL.md 7.3 says;
 *   - the slave's settings are back at 9600 (termios restored on a signal);
 *   - the pcap: libpcap header, link type 250, 12-byte RTAC headers (BE time
 *     equal to the record's time, event DATA_RX_END), payloads = the bytes
 *     written, in order;
 *   - `df1mon --read FILE` decodes the same symbols.
 * Also: -c N ends the sniff by itself; two taps (--sniff-b) give an rx and a tx
 * column and records of both event types, which --read splits the same way.
 *
 * df1mon is $DF1_BIN/df1mon (tests/run-tests.sh exports it), else build/bin.
 * Every wait has a deadline; nothing asserts on timing.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#define DEADLINE_MS 10000

struct line {
	int master, slave;
	char name[64];
};

struct fixture {
	char dir[64];
	struct line a, b;
	pid_t pid;
};

static long long now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (long long)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static void pause_ms(int ms)
{
	poll(NULL, 0, ms);
}

static const char *mon_path(void)
{
	static char path[512];
	const char *bin = getenv("DF1_BIN");

	snprintf(path, sizeof path, "%s/df1mon", bin && *bin ? bin : "build/bin");
	return path;
}

/* A pty pair; the slave raw at 9600 baud: the settings df1mon must restore. */
static void line_open(struct line *l)
{
	struct termios t;
	const char *name;

	l->master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
	assert_true(l->master >= 0);
	assert_int_equal(grantpt(l->master), 0);
	assert_int_equal(unlockpt(l->master), 0);
	name = ptsname(l->master);
	assert_non_null(name);
	snprintf(l->name, sizeof l->name, "%s", name);
	l->slave = open(l->name, O_RDWR | O_NOCTTY | O_CLOEXEC);
	assert_true(l->slave >= 0);
	assert_int_equal(tcgetattr(l->slave, &t), 0);
	cfmakeraw(&t);
	cfsetispeed(&t, B9600);
	cfsetospeed(&t, B9600);
	assert_int_equal(tcsetattr(l->slave, TCSANOW, &t), 0);
}

static void line_close(struct line *l)
{
	if (l->master >= 0)
		close(l->master);
	if (l->slave >= 0)
		close(l->slave);
	l->master = l->slave = -1;
}

static speed_t line_speed(const struct line *l)
{
	struct termios t;

	if (tcgetattr(l->slave, &t) < 0)
		return B0;
	return cfgetospeed(&t);
}

static void line_write(const struct line *l, const char *hex)
{
	uint8_t b[256];
	size_t n = 0;

	for (const char *p = hex; *p;) {
		unsigned v;
		int used;
		if (sscanf(p, " %2x%n", &v, &used) != 1)
			break;
		b[n++] = (uint8_t)v;
		p += used;
	}
	assert_int_equal(write(l->master, b, n), (ssize_t)n);
}

static int setup(void **state)
{
	struct fixture *f = calloc(1, sizeof *f);

	if (!f)
		return -1;
	snprintf(f->dir, sizeof f->dir, "%s/df1mon_sniff.XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (!mkdtemp(f->dir)) {
		free(f);
		return -1;
	}
	f->a.master = f->a.slave = f->b.master = f->b.slave = -1;
	*state = f;
	return 0;
}

static void rm_dir(const char *dir)
{
	static const char *const names[] = { "out", "err", "cap.pcap", "read.out", "read.err" };
	char path[160];

	for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
		snprintf(path, sizeof path, "%s/%s", dir, names[i]);
		unlink(path);
	}
	rmdir(dir);
}

static int teardown(void **state)
{
	struct fixture *f = *state;

	if (f->pid > 0) {
		kill(f->pid, SIGKILL);
		waitpid(f->pid, NULL, 0);
	}
	line_close(&f->a);
	line_close(&f->b);
	rm_dir(f->dir);
	free(f);
	return 0;
}

/* Start df1mon with args (NULL-terminated), stdout/stderr into DIR/<out>, DIR/<err>. */
static pid_t spawn(const struct fixture *f, const char *out, const char *err, const char *const *args)
{
	char po[160], pe[160];
	const char *argv[32];
	size_t n = 0;
	pid_t pid;

	snprintf(po, sizeof po, "%s/%s", f->dir, out);
	snprintf(pe, sizeof pe, "%s/%s", f->dir, err);
	argv[n++] = mon_path();
	for (; *args && n < 31; args++)
		argv[n++] = *args;
	argv[n] = NULL;
	fflush(NULL);
	pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		int o = open(po, O_WRONLY | O_CREAT | O_TRUNC, 0644);
		int e = open(pe, O_WRONLY | O_CREAT | O_TRUNC, 0644);
		if (o < 0 || e < 0)
			_exit(127);
		dup2(o, 1);
		dup2(e, 2);
		signal(SIGINT, SIG_DFL);
		execv(argv[0], (char *const *)argv);
		_exit(127);
	}
	return pid;
}

/* Exit status of pid, waiting up to the deadline (then SIGKILL: -1). */
static int reap(pid_t pid)
{
	long long end = now_ms() + DEADLINE_MS;
	int st;

	while (now_ms() < end) {
		pid_t r = waitpid(pid, &st, WNOHANG);
		if (r == pid)
			return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
		pause_ms(10);
	}
	kill(pid, SIGKILL);
	waitpid(pid, &st, 0);
	return -1;
}

static char *slurp(const struct fixture *f, const char *name, size_t *len)
{
	char path[160];
	FILE *fp;
	char *buf;
	long n;

	snprintf(path, sizeof path, "%s/%s", f->dir, name);
	fp = fopen(path, "rb");
	if (!fp)
		return NULL;
	fseek(fp, 0, SEEK_END);
	n = ftell(fp);
	fseek(fp, 0, SEEK_SET);
	buf = malloc((size_t)n + 1);
	if (buf && fread(buf, 1, (size_t)n, fp) != (size_t)n) {
		free(buf);
		buf = NULL;
	}
	fclose(fp);
	if (buf) {
		buf[n] = 0;
		if (len)
			*len = (size_t)n;
	}
	return buf;
}

static int count_lines(const char *s)
{
	int n = 0;

	for (; s && *s; s++)
		n += *s == '\n';
	return n;
}

/* Wait until DIR/name holds at least n lines. */
static bool wait_lines(const struct fixture *f, const char *name, int n)
{
	long long end = now_ms() + DEADLINE_MS;

	while (now_ms() < end) {
		char *s = slurp(f, name, NULL);
		int k = count_lines(s);
		free(s);
		if (k >= n)
			return true;
		pause_ms(10);
	}
	return false;
}

/* Wait until df1mon has set the line to 19200: it has the port open and raw. */
static bool wait_configured(const struct line *l, pid_t pid)
{
	long long end = now_ms() + DEADLINE_MS;

	while (now_ms() < end) {
		if (line_speed(l) == B19200)
			return true;
		if (waitpid(pid, NULL, WNOHANG) == pid)
			return false;
		pause_ms(5);
	}
	return false;
}

/* Line k (0-based) of text, without the index and time columns: from the
 * column after the time (direction or kind). */
static bool symbol_part(const char *text, int k, char *buf, size_t cap)
{
	const char *p = text;
	const char *e;
	int col = 0;

	for (int i = 0; i < k && p; i++) {
		p = strchr(p, '\n');
		if (p)
			p++;
	}
	if (!p || !*p)
		return false;
	e = strchr(p, '\n');
	if (!e)
		e = p + strlen(p);
	/* skip two blank-separated columns: the index and the time */
	while (p < e && col < 2) {
		while (p < e && *p == ' ')
			p++;
		while (p < e && *p != ' ')
			p++;
		col++;
	}
	while (p < e && *p == ' ')
		p++;
	snprintf(buf, cap, "%.*s", (int)(e - p), p);
	return true;
}

static uint32_t le32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint32_t be32(const uint8_t *p)
{
	return (uint32_t)p[3] | (uint32_t)p[2] << 8 | (uint32_t)p[1] << 16 | (uint32_t)p[0] << 24;
}

/* Walk the capture: check every record and return the payload bytes (and per
 * event type counts). */
static size_t pcap_payload(const uint8_t *b, size_t n, uint8_t *out, size_t cap, int *ev03, int *ev04)
{
	size_t pos = 24, o = 0;

	assert_true(n >= 24);
	assert_int_equal(le32(b), 0xA1B2C3D4);
	assert_int_equal(b[4] | b[5] << 8, 2);
	assert_int_equal(b[6] | b[7] << 8, 4);
	assert_int_equal(le32(b + 20), 250);
	*ev03 = *ev04 = 0;
	while (pos < n) {
		uint32_t incl, orig;
		assert_true(n - pos >= 16);
		incl = le32(b + pos + 8);
		orig = le32(b + pos + 12);
		assert_int_equal(incl, orig);
		assert_true(incl > 12);
		assert_true(incl <= n - pos - 16);
		/* RTAC header: BE seconds and microseconds = the record's time */
		assert_int_equal(be32(b + pos + 16), le32(b + pos));
		assert_int_equal(be32(b + pos + 20), le32(b + pos + 4));
		assert_true(le32(b + pos + 4) < 1000000);
		if (b[pos + 24] == 0x03)
			(*ev03)++;
		else if (b[pos + 24] == 0x04)
			(*ev04)++;
		else
			fail_msg("record event type %02X", b[pos + 24]);
		assert_int_equal(b[pos + 26], 0);
		assert_int_equal(b[pos + 27], 0);
		assert_true(o + incl - 12 <= cap);
		memcpy(out + o, b + pos + 28, incl - 12);
		o += incl - 12;
		pos += 16 + incl;
	}
	assert_int_equal(pos, n);
	return o;
}

/* Spec 7.3: SLC A2 read F8:0 (BCC), its reply F8:0 = 1.5. */
#define CMD_A "10 02 01 00 0F 00 04 00 A2 04"
#define CMD_B "08 8A 00 00 10 03 B4"
#define ACK "10 06"
#define REPLY "10 02 00 01 4F 00 04 00 00 00 C0 3F 10 03 AD"
#define ENQ "10 05"

static void test_df1mon_sniff_pty_decodes_saves_and_restores(void **state)
{
	struct fixture *f = *state;
	char cap[192], want[512], got[512];
	static const char *const want_hex = CMD_A " " CMD_B " " ACK " " REPLY " " ENQ;
	uint8_t wbytes[128], pbytes[256];
	size_t wn = 0, pn, len;
	uint8_t *pc;
	char *out, *err, *rd;
	int ev03, ev04, rc;

	line_open(&f->a);
	snprintf(cap, sizeof cap, "%s/cap.pcap", f->dir);
	f->pid = spawn(f, "out", "err",
	               (const char *const[]){ "--sniff", "-d", f->a.name, "-w", cap, "-b", "19200", NULL });
	assert_true(wait_configured(&f->a, f->pid));

	line_write(&f->a, CMD_A);       /* a frame split across two writes */
	pause_ms(20);                   /* (likely two reads; not asserted) */
	line_write(&f->a, CMD_B);
	assert_true(wait_lines(f, "out", 1));
	line_write(&f->a, ACK);
	line_write(&f->a, REPLY);
	line_write(&f->a, ENQ);
	assert_true(wait_lines(f, "out", 4));

	assert_int_equal(kill(f->pid, SIGINT), 0);
	rc = reap(f->pid);
	f->pid = 0;
	assert_int_equal(rc, 0);
	/* the port's settings are what they were before df1mon */
	assert_true(line_speed(&f->a) == B9600);

	out = slurp(f, "out", NULL);
	err = slurp(f, "err", NULL);
	assert_non_null(out);
	assert_non_null(err);
	assert_int_equal(count_lines(out), 4);
	assert_true(symbol_part(out, 0, got, sizeof got));
	assert_non_null(strstr(got, "FRAME  BCC ok  dst   1  src   0  tns 0004  0F/A2"));
	assert_non_null(strstr(got, "F8:0 size 4"));
	assert_true(symbol_part(out, 1, got, sizeof got));
	assert_string_equal(got, "ACK");
	assert_true(symbol_part(out, 2, got, sizeof got));
	assert_non_null(strstr(got, "reply to 0F/A2"));
	assert_non_null(strstr(got, "= 1.5"));
	assert_true(symbol_part(out, 3, got, sizeof got));
	assert_string_equal(got, "ENQ");
	assert_non_null(strstr(err, "frames 2 (good 2, bad 0), link symbols 2"));
	assert_non_null(strstr(err, "written to"));

	/* the capture holds exactly the bytes of the line, in order */
	pc = (uint8_t *)slurp(f, "cap.pcap", &len);
	assert_non_null(pc);
	pn = pcap_payload(pc, len, pbytes, sizeof pbytes, &ev03, &ev04);
	for (const char *p = want_hex; *p;) {
		unsigned v;
		int used;
		if (sscanf(p, " %2x%n", &v, &used) != 1)
			break;
		wbytes[wn++] = (uint8_t)v;
		p += used;
	}
	assert_int_equal(pn, wn);
	assert_memory_equal(pbytes, wbytes, wn);
	assert_int_equal(ev03, 0);
	assert_true(ev04 >= 2);   /* at least the two halves of the split frame */

	/* df1mon --read decodes it to the same symbols */
	rc = reap(spawn(f, "read.out", "read.err", (const char *const[]){ "--read", cap, NULL }));
	assert_int_equal(rc, 0);
	rd = slurp(f, "read.out", NULL);
	assert_non_null(rd);
	assert_int_equal(count_lines(rd), 4);
	for (int k = 0; k < 4; k++) {
		assert_true(symbol_part(out, k, want, sizeof want));
		assert_true(symbol_part(rd, k, got, sizeof got));
		assert_string_equal(got, want);
	}
	free(out);
	free(err);
	free(rd);
	free(pc);
}

static void test_df1mon_sniff_count_stops_by_itself(void **state)
{
	struct fixture *f = *state;
	char *out;
	int rc;

	line_open(&f->a);
	f->pid = spawn(f, "out", "err",
	               (const char *const[]){ "--sniff", "-d", f->a.name, "-c", "2", "-q", "-f", "json", NULL });
	assert_true(wait_configured(&f->a, f->pid));
	line_write(&f->a, CMD_A " " CMD_B);
	line_write(&f->a, ACK);
	line_write(&f->a, REPLY);
	rc = reap(f->pid);
	f->pid = 0;
	assert_int_equal(rc, 0);
	assert_true(line_speed(&f->a) == B9600);
	out = slurp(f, "out", NULL);
	assert_non_null(out);
	assert_non_null(strstr(out, "\"kind\":\"FRAME\""));
	assert_non_null(strstr(out, "\"values\":[1.5]"));
	assert_null(strstr(out, "\"dir\""));
	free(out);
}

static void test_df1mon_sniff_two_taps_give_rx_and_tx(void **state)
{
	struct fixture *f = *state;
	char cap[192], *out, *rd;
	uint8_t *pc, pbytes[256];
	size_t len;
	int ev03, ev04, rc;

	line_open(&f->a);
	line_open(&f->b);
	snprintf(cap, sizeof cap, "%s/cap.pcap", f->dir);
	f->pid = spawn(f, "out", "err",
	               (const char *const[]){ "--sniff", "-d", f->a.name, "--sniff-b", f->b.name, "-w", cap, NULL });
	assert_true(wait_configured(&f->a, f->pid));
	assert_true(wait_configured(&f->b, f->pid));
	line_write(&f->b, CMD_A " " CMD_B);     /* the host's transmissions on tap B */
	assert_true(wait_lines(f, "out", 1));
	line_write(&f->a, ACK " " REPLY);       /* the PLC's on tap A */
	assert_true(wait_lines(f, "out", 3));
	kill(f->pid, SIGTERM);
	rc = reap(f->pid);
	f->pid = 0;
	assert_int_equal(rc, 0);
	assert_true(line_speed(&f->a) == B9600 && line_speed(&f->b) == B9600);

	out = slurp(f, "out", NULL);
	assert_non_null(out);
	assert_int_equal(count_lines(out), 3);
	assert_non_null(strstr(out, "  tx  FRAME "));
	assert_non_null(strstr(out, "  rx  ACK"));
	assert_non_null(strstr(out, "  rx  FRAME "));
	assert_non_null(strstr(out, "= 1.5"));   /* the reply matched to its command across taps */

	pc = (uint8_t *)slurp(f, "cap.pcap", &len);
	assert_non_null(pc);
	pcap_payload(pc, len, pbytes, sizeof pbytes, &ev03, &ev04);
	assert_true(ev03 >= 1 && ev04 >= 1);
	rc = reap(spawn(f, "read.out", "read.err", (const char *const[]){ "--read", cap, NULL }));
	assert_int_equal(rc, 0);
	rd = slurp(f, "read.out", NULL);
	assert_non_null(rd);
	assert_non_null(strstr(rd, "  tx  FRAME "));
	assert_non_null(strstr(rd, "  rx  FRAME "));
	free(out);
	free(rd);
	free(pc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_df1mon_sniff_pty_decodes_saves_and_restores, setup, teardown),
		cmocka_unit_test_setup_teardown(test_df1mon_sniff_count_stops_by_itself, setup, teardown),
		cmocka_unit_test_setup_teardown(test_df1mon_sniff_two_taps_give_rx_and_tx, setup, teardown),
	};

	signal(SIGPIPE, SIG_IGN);
	return cmocka_run_group_tests(tests, NULL, NULL);
}
