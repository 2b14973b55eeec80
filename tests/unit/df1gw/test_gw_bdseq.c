/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_bdseq.c - where df1gw keeps Sparkplug's bdSeq (tools/df1gw/gw_bdseq.c;
 * df1gw(1), SPARKPLUG, FILES, ENVIRONMENT): the state folder from
 * STATE_DIRECTORY (its first entry), else XDG_STATE_HOME/df1gw (absolute
 * only), else HOME/.local/state/df1gw; one file per group and edge node,
 * GROUP@EDGE.bdseq with every other byte as %XX (so that no id can reach
 * another folder or share a file with another pair); the folder made with
 * its parents; the file written whole ("bdSeq N\n", read back here with
 * plain stdio, no temporary left beside it) and read back, a missing file
 * being no bdSeq yet and a bad one an error.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "df1gw/gw_bdseq.h"

static char tmpdir[256];

static int setup(void **state)
{
	(void)state;
	snprintf(tmpdir, sizeof tmpdir, "%s/test_gw_bdseq.XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	assert_non_null(mkdtemp(tmpdir));
	return 0;
}

static int teardown(void **state)
{
	char cmd[600];

	(void)state;
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
	assert_int_equal(system(cmd), 0);
	return 0;
}

static void test_state_folder_from_the_environment(void **state)
{
	char d[512];

	(void)state;
	setenv("STATE_DIRECTORY", "/var/lib/df1gw:/var/lib/other", 1);
	setenv("XDG_STATE_HOME", "/home/op/.state", 1);
	setenv("HOME", "/home/op", 1);
	assert_int_equal(gw_bdseq_dir(d, sizeof d), 0);
	assert_string_equal(d, "/var/lib/df1gw");
	unsetenv("STATE_DIRECTORY");
	assert_int_equal(gw_bdseq_dir(d, sizeof d), 0);
	assert_string_equal(d, "/home/op/.state/df1gw");
	setenv("XDG_STATE_HOME", "relative/state", 1);      /* the XDG spec: ignored */
	assert_int_equal(gw_bdseq_dir(d, sizeof d), 0);
	assert_string_equal(d, "/home/op/.local/state/df1gw");
	unsetenv("XDG_STATE_HOME");
	assert_int_equal(gw_bdseq_dir(d, sizeof d), 0);
	assert_string_equal(d, "/home/op/.local/state/df1gw");
	assert_int_equal(gw_bdseq_dir(d, 10), -1);          /* no room */
	assert_string_equal(d, "");
	unsetenv("HOME");
	assert_int_equal(gw_bdseq_dir(d, sizeof d), -1);
	assert_string_equal(d, "");
}

static void test_file_name_per_group_and_edge_node(void **state)
{
	char a[600], b[600];
	char longid[300];

	(void)state;
	assert_int_equal(gw_bdseq_path("/s", "Plant1", "Line-1_a.b", a, sizeof a), 0);
	assert_string_equal(a, "/s/Plant1@Line-1_a.b.bdseq");
	/* '@' in an id is escaped: these two pairs do not share a file */
	assert_int_equal(gw_bdseq_path("/s", "a@b", "c", a, sizeof a), 0);
	assert_int_equal(gw_bdseq_path("/s", "a", "b@c", b, sizeof b), 0);
	assert_string_equal(a, "/s/a%40b@c.bdseq");
	assert_string_equal(b, "/s/a@b%40c.bdseq");
	/* no way out of the folder; UTF-8 and spaces as bytes; '%' itself */
	assert_int_equal(gw_bdseq_path("/s", "..", "../../etc/x", a, sizeof a), 0);
	assert_string_equal(a, "/s/..@..%2F..%2Fetc%2Fx.bdseq");
	assert_int_equal(gw_bdseq_path("/s", "Halle \xc3\xbc", "50%", a, sizeof a), 0);
	assert_string_equal(a, "/s/Halle%20%C3%BC@50%25.bdseq");
	/* a file name over 255 bytes is refused, not cut */
	memset(longid, 'x', sizeof longid - 1);
	longid[sizeof longid - 1] = '\0';
	assert_int_equal(gw_bdseq_path("/s", "G", longid, a, sizeof a), -1);
	assert_int_equal(gw_bdseq_path("/s", "G", "E", a, 8), -1);
}

static void test_folder_made_with_its_parents(void **state)
{
	char d[600], f[600];
	struct stat st;

	(void)state;
	snprintf(d, sizeof d, "%s/a/b/df1gw", tmpdir);
	assert_int_equal(gw_bdseq_mkdir(d), 0);
	assert_int_equal(stat(d, &st), 0);
	assert_true(S_ISDIR(st.st_mode));
	assert_int_equal(st.st_mode & 0077, 0);
	assert_int_equal(gw_bdseq_mkdir(d), 0);             /* there already */
	/* under a plain file: refused with the reason */
	snprintf(f, sizeof f, "%s/plain", tmpdir);
	fclose(fopen(f, "w"));
	snprintf(d, sizeof d, "%s/plain/df1gw", tmpdir);
	errno = 0;
	assert_int_equal(gw_bdseq_mkdir(d), -1);
	assert_int_equal(errno, ENOTDIR);
}

static void test_written_whole_and_read_back(void **state)
{
	char p[600], tmp[620], text[64] = "";
	unsigned last = 99;
	FILE *fp;

	(void)state;
	snprintf(p, sizeof p, "%s/Plant@Line1.bdseq", tmpdir);
	assert_int_equal(gw_bdseq_read(p, &last), 0);       /* no file yet */
	assert_int_equal(last, 99);
	assert_int_equal(gw_bdseq_write(p, 7), 0);
	fp = fopen(p, "r");
	assert_non_null(fp);
	assert_int_equal(fread(text, 1, sizeof text - 1, fp), 8);
	fclose(fp);
	assert_string_equal(text, "bdSeq 7\n");
	snprintf(tmp, sizeof tmp, "%s.new", p);
	assert_int_equal(access(tmp, F_OK), -1);            /* renamed, nothing left */
	assert_int_equal(gw_bdseq_read(p, &last), 1);
	assert_int_equal(last, 7);
	assert_int_equal(gw_bdseq_write(p, 255), 0);
	assert_int_equal(gw_bdseq_read(p, &last), 1);
	assert_int_equal(last, 255);
	/* a file that is not "bdSeq N" with N 0-255 */
	fp = fopen(p, "w");
	fputs("bdSeq 300\n", fp);
	fclose(fp);
	errno = 0;
	assert_int_equal(gw_bdseq_read(p, &last), -1);
	assert_int_equal(errno, EINVAL);
	fp = fopen(p, "w");
	fputs("hello\n", fp);
	fclose(fp);
	assert_int_equal(gw_bdseq_read(p, &last), -1);
	assert_int_equal(errno, EINVAL);
	/* a folder that is not there: the reason, nothing made */
	snprintf(p, sizeof p, "%s/missing/x.bdseq", tmpdir);
	errno = 0;
	assert_int_equal(gw_bdseq_write(p, 1), -1);
	assert_int_equal(errno, ENOENT);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_state_folder_from_the_environment),
		cmocka_unit_test(test_file_name_per_group_and_edge_node),
		cmocka_unit_test_setup_teardown(test_folder_made_with_its_parents, setup, teardown),
		cmocka_unit_test_setup_teardown(test_written_whole_and_read_back, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
