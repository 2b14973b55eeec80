/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_file - one in-memory file per fuzzer process for the loaders' input
 * (fuzz.h): no disk writes, and a regular file, so that a loader may seek;
 * and the stream findings are reported on.
 */
#include "fuzz.h"

#include <sys/mman.h>
#include <unistd.h>

FILE *fuzz_log(void)
{
	static FILE *f;

	if (!f) {
		int fd = dup(2);
		f = fd >= 0 ? fdopen(fd, "w") : NULL;
		if (!f)
			f = stderr;
	}
	return f;
}

const char *fuzz_file(const uint8_t *data, size_t n)
{
	static int fd = -1;
	static char path[64];

	if (fd < 0) {
		fd = memfd_create("fuzz-input", MFD_CLOEXEC);
		if (fd < 0)
			return NULL;
		snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
	}
	if (ftruncate(fd, 0) != 0)
		return NULL;
	for (size_t off = 0; off < n;) {
		ssize_t k = pwrite(fd, data + off, n - off, (off_t)off);
		if (k <= 0)
			return NULL;
		off += (size_t)k;
	}
	return path;
}
