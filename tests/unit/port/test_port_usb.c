/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_port_usb.c - USB serial adapters under the termios backend
 * (lib/port/port_usb.c): a pseudo-terminal stands for the adapter, a fake
 * sysfs tree (DF1_TEST_SYSFS_ROOT, the test-only root) lists it as a
 * usb-serial port with a latency_timer file. On a plain pty TIOCGSERIAL does
 * not apply and nothing may fail; to check that low latency is asked for and
 * undone at close, ioctl() is interposed (defined here, the real one found
 * with RTLD_NEXT) as a driver that, like ftdi_sio, runs its timer at 1 ms
 * while ASYNC_LOW_LATENCY is set.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dlfcn.h>
#include <fcntl.h>
#include <linux/serial.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include "df1_int.h"

/* ---- a driver with TIOCGSERIAL / TIOCSSERIAL, when fake_driver is on ---- */

static bool fake_driver;
static int drv_flags;           /* the driver's serial_struct flags */
static int n_sserial;           /* TIOCSSERIAL calls */
static char timer_path[512];    /* the fake tree's latency_timer */

static void write_file(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");

	assert_non_null(f);
	fputs(text, f);
	fclose(f);
}

static void read_file(const char *path, char *buf, size_t cap)
{
	FILE *f = fopen(path, "r");
	size_t n;

	assert_non_null(f);
	n = fread(buf, 1, cap - 1, f);
	buf[n] = 0;
	fclose(f);
}

int ioctl(int fd, unsigned long req, ...)
{
	static int (*real)(int, unsigned long, ...);
	va_list ap;
	void *arg;

	va_start(ap, req);
	arg = va_arg(ap, void *);
	va_end(ap);
	if (!real)
		*(void **)&real = dlsym(RTLD_NEXT, "ioctl");
	if (fake_driver && req == TIOCGSERIAL) {
		memset(arg, 0, sizeof(struct serial_struct));
		((struct serial_struct *)arg)->flags = drv_flags;
		return 0;
	}
	if (fake_driver && req == TIOCSSERIAL) {
		drv_flags = ((struct serial_struct *)arg)->flags;
		n_sserial++;
		write_file(timer_path, drv_flags & ASYNC_LOW_LATENCY ? "1\n" : "16\n");
		return 0;
	}
	return real(fd, req, arg);
}

/* ---- the fake tree and the pty ------------------------------------------ */

struct fixture {
	char root[64];
	int master;
	char path[64];
	int n_log;
	int log_id;
	enum df1_severity log_sev;
	char log_text[1024];
};

static struct fixture fx;

static void mkdirs(const char *root, const char *rel)
{
	char path[512];

	for (const char *p = rel; (p = strchr(p, '/')) != NULL; p++) {
		snprintf(path, sizeof path, "%s/%.*s", root, (int)(p - rel), rel);
		(void)mkdir(path, 0755);
	}
	snprintf(path, sizeof path, "%s/%s", root, rel);
	(void)mkdir(path, 0755);
}

/* The pty listed as usb-serial port ttyUSB9 with latency_timer `timer` (NULL: no file). */
static void tree_make(const char *timer)
{
	char rel[128], path[512], uevent[128];
	struct stat st;

	assert_int_equal(stat(fx.path, &st), 0);
	snprintf(rel, sizeof rel, "dev/char/%u:%u", major(st.st_rdev), minor(st.st_rdev));
	mkdirs(fx.root, rel);
	snprintf(path, sizeof path, "%s/%s/uevent", fx.root, rel);
	snprintf(uevent, sizeof uevent, "MAJOR=%u\nMINOR=%u\nDEVNAME=ttyUSB9\n", major(st.st_rdev),
	         minor(st.st_rdev));
	write_file(path, uevent);
	mkdirs(fx.root, "bus/usb-serial/devices/ttyUSB9");
	snprintf(timer_path, sizeof timer_path, "%s/bus/usb-serial/devices/ttyUSB9/latency_timer",
	         fx.root);
	if (timer)
		write_file(timer_path, timer);
}

static void on_log(void *user, int id, enum df1_severity sev, const char *text)
{
	(void)user;
	fx.n_log++;
	fx.log_id = id;
	fx.log_sev = sev;
	snprintf(fx.log_text, sizeof fx.log_text, "%s", text);
}

static int setup(void **state)
{
	(void)state;
	memset(&fx, 0, sizeof fx);
	snprintf(fx.root, sizeof fx.root, "/tmp/df1-sysfs-XXXXXX");
	assert_non_null(mkdtemp(fx.root));
	setenv("DF1_TEST_SYSFS_ROOT", fx.root, 1);
	fx.master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
	assert_true(fx.master >= 0);
	assert_int_equal(grantpt(fx.master), 0);
	assert_int_equal(unlockpt(fx.master), 0);
	assert_int_equal(ptsname_r(fx.master, fx.path, sizeof fx.path), 0);
	fake_driver = false;
	drv_flags = 0;
	n_sserial = 0;
	return 0;
}

static int teardown(void **state)
{
	char cmd[128];

	(void)state;
	close(fx.master);
	unsetenv("DF1_TEST_SYSFS_ROOT");
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", fx.root);
	assert_int_equal(system(cmd), 0);
	fake_driver = false;
	return 0;
}

static df1_t *open_logged(int low_latency)
{
	df1_t *h = NULL;

	assert_int_equal(df1_new(&h), 0);
	df1_set_log(h, on_log, NULL);
	if (low_latency >= 0)
		assert_int_equal(df1_set_option(h, DF1_OPT_LOW_LATENCY, low_latency), 0);
	assert_int_equal(df1_open(h, fx.path), 0);
	return h;
}

/* ---- tests --------------------------------------------------------------- */

static void test_usb_default_is_low_latency(void **state)
{
	df1_t *h = NULL;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_LOW_LATENCY), 1);
	assert_int_equal(df1_set_option(h, DF1_OPT_LOW_LATENCY, 0), 0);
	assert_int_equal(df1_get_option(h, DF1_OPT_LOW_LATENCY), 0);
	assert_int_equal(df1_set_option(h, DF1_OPT_LOW_LATENCY, 2), DF1_E_CONFIG);
	assert_string_equal(df1_port_note(h), "");
	assert_string_equal(df1_port_note(NULL), "");
	df1_free(h);
}

/* A pty that sysfs does not list: nothing said, nothing fails. */
static void test_usb_plain_pty_is_left_alone(void **state)
{
	df1_t *h;

	(void)state;
	h = open_logged(-1);
	assert_int_equal(fx.n_log, 0);
	assert_string_equal(df1_port_note(h), "");
	df1_free(h);
}

/* A 16 ms timer that TIOCSSERIAL cannot lower (a pty has no TIOCGSERIAL): one
 * notice outside the catalog, the note names the file and the udev rule. */
static void test_usb_high_timer_is_reported_once(void **state)
{
	df1_t *h;

	(void)state;
	tree_make("16\n");
	h = open_logged(-1);
	assert_int_equal(fx.n_log, 1);
	assert_int_equal(fx.log_id, 0);
	assert_int_equal(fx.log_sev, DF1_SEV_NOTICE);
	assert_non_null(strstr(fx.log_text, timer_path));
	assert_non_null(strstr(fx.log_text, "16 ms"));
	assert_non_null(strstr(fx.log_text, "ATTR{latency_timer}=\"1\""));
	assert_non_null(strstr(fx.log_text, fx.path));
	assert_string_equal(df1_port_note(h), fx.log_text);
	/* the line still works: bytes go through */
	assert_int_equal(write(fx.master, "\x10\x06", 2), 2);
	df1_close(h);
	assert_string_equal(df1_port_note(h), "");
	assert_int_equal(fx.n_log, 1);
	df1_free(h);
}

static void test_usb_timer_at_1ms_is_quiet(void **state)
{
	df1_t *h;

	(void)state;
	tree_make("1\n");
	h = open_logged(-1);
	assert_int_equal(fx.n_log, 0);
	assert_string_equal(df1_port_note(h), "");
	df1_free(h);
}

/* Without a latency_timer (pl2303, cp210x): nothing to report. */
static void test_usb_no_timer_file_is_quiet(void **state)
{
	df1_t *h;

	(void)state;
	tree_make(NULL);
	h = open_logged(-1);
	assert_int_equal(fx.n_log, 0);
	df1_free(h);
}

/* --low-latency no: the driver is not touched and nothing is reported. */
static void test_usb_option_off_touches_nothing(void **state)
{
	df1_t *h;

	(void)state;
	tree_make("16\n");
	fake_driver = true;
	h = open_logged(0);
	assert_int_equal(n_sserial, 0);
	assert_int_equal(fx.n_log, 0);
	assert_string_equal(df1_port_note(h), "");
	df1_free(h);
	assert_int_equal(n_sserial, 0);
}

/* A driver that takes ASYNC_LOW_LATENCY: set at open (its timer drops to 1 ms,
 * nothing reported), cleared again at close, other flags kept. */
static void test_usb_low_latency_set_and_restored(void **state)
{
	char text[16];
	df1_t *h;

	(void)state;
	tree_make("16\n");
	fake_driver = true;
	drv_flags = ASYNC_SKIP_TEST;
	h = open_logged(-1);
	assert_int_equal(n_sserial, 1);
	assert_int_equal(drv_flags, ASYNC_SKIP_TEST | ASYNC_LOW_LATENCY);
	assert_int_equal(fx.n_log, 0);
	assert_string_equal(df1_port_note(h), "");
	df1_close(h);
	assert_int_equal(n_sserial, 2);
	assert_int_equal(drv_flags, ASYNC_SKIP_TEST);
	read_file(timer_path, text, sizeof text);
	assert_string_equal(text, "16\n");
	df1_free(h);
}

/* Already in low latency mode: left as found, not cleared at close. */
static void test_usb_already_low_latency_left_as_found(void **state)
{
	df1_t *h;

	(void)state;
	tree_make("1\n");
	fake_driver = true;
	drv_flags = ASYNC_LOW_LATENCY;
	h = open_logged(-1);
	df1_free(h);
	assert_int_equal(n_sserial, 0);
	assert_int_equal(drv_flags, ASYNC_LOW_LATENCY);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_usb_default_is_low_latency),
		cmocka_unit_test_setup_teardown(test_usb_plain_pty_is_left_alone, setup, teardown),
		cmocka_unit_test_setup_teardown(test_usb_high_timer_is_reported_once, setup, teardown),
		cmocka_unit_test_setup_teardown(test_usb_timer_at_1ms_is_quiet, setup, teardown),
		cmocka_unit_test_setup_teardown(test_usb_no_timer_file_is_quiet, setup, teardown),
		cmocka_unit_test_setup_teardown(test_usb_option_off_touches_nothing, setup, teardown),
		cmocka_unit_test_setup_teardown(test_usb_low_latency_set_and_restored, setup, teardown),
		cmocka_unit_test_setup_teardown(test_usb_already_low_latency_left_as_found, setup,
		                                teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
