/* SPDX-License-Identifier: MPL-2.0 */
/*
 * version.c - df1_version(): the version of the library that runs, taken from
 * the DF1_VERSION_* macros when the library itself was built.
 */
#include "df1_int.h"

static const struct df1_version version = {
	.major = DF1_VERSION_MAJOR,
	.minor = DF1_VERSION_MINOR,
	.micro = DF1_VERSION_MICRO,
	.string = DF1_VERSION_STRING,
};

const struct df1_version *df1_version(void)
{
	return &version;
}
