/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_version.c - df1_version(): the runtime version agrees with the
 * DF1_VERSION_* macros the library was built with, and is static storage.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "df1.h"

static void test_version_fields_match_macros(void **state)
{
	const struct df1_version *v = df1_version();

	(void)state;
	assert_non_null(v);
	assert_int_equal(v->major, DF1_VERSION_MAJOR);
	assert_int_equal(v->minor, DF1_VERSION_MINOR);
	assert_int_equal(v->micro, DF1_VERSION_MICRO);
	assert_non_null(v->string);
	assert_string_equal(v->string, DF1_VERSION_STRING);
}

static void test_version_string_is_major_minor_micro(void **state)
{
	const struct df1_version *v = df1_version();
	char buf[64];

	(void)state;
	snprintf(buf, sizeof buf, "%d.%d.%d", v->major, v->minor, v->micro);
	assert_string_equal(v->string, buf);
}

static void test_version_same_storage_every_call(void **state)
{
	(void)state;
	assert_ptr_equal(df1_version(), df1_version());
	assert_ptr_equal(df1_version()->string, df1_version()->string);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_version_fields_match_macros),
		cmocka_unit_test(test_version_string_is_major_minor_micro),
		cmocka_unit_test(test_version_same_storage_every_call),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
