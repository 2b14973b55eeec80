/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz.h - what the libFuzzer targets of tests/fuzz share: a cursor over the
 * fuzz input, a file holding bytes (for the loaders, which take a path), and
 * the assertion that turns a violated property into a finding (abort).
 * See tests/fuzz/README.
 */
#ifndef LIBDF1_FUZZ_H
#define LIBDF1_FUZZ_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

/* Where findings are reported: the process's standard error as it was at
 * start, even when a target has silenced the code's own stderr messages. */
FILE *fuzz_log(void);

/* A property the code must keep: print what broke and abort (libFuzzer saves the input). */
#define FUZZ_CHECK(cond, ...)                                                   \
	do {                                                                        \
		if (!(cond)) {                                                          \
			fprintf(fuzz_log(), "fuzz: %s:%d: property violated: ", __FILE__, __LINE__); \
			fprintf(fuzz_log(), __VA_ARGS__);                                   \
			fputc('\n', fuzz_log());                                            \
			fflush(fuzz_log());                                                 \
			abort();                                                            \
		}                                                                       \
	} while (0)

/* The input, consumed from the front. */
struct fuzz_in {
	const uint8_t *p;
	size_t n;
};

/* The next byte, 0 once the input is used up. */
static inline uint8_t fuzz_byte(struct fuzz_in *in)
{
	if (in->n == 0)
		return 0;
	in->n--;
	return *in->p++;
}

/* Up to k bytes from the front; *len says how many there were. */
static inline const uint8_t *fuzz_take(struct fuzz_in *in, size_t k, size_t *len)
{
	const uint8_t *p = in->p;

	if (k > in->n)
		k = in->n;
	in->p += k;
	in->n -= k;
	*len = k;
	return p;
}

/* A path to a file that holds exactly these bytes (a memfd reused between
 * runs: the loaders take a path and open it themselves). NULL on failure. */
const char *fuzz_file(const uint8_t *data, size_t n);

#endif
