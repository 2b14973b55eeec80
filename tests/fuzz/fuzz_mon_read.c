/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_mon_read - df1mon --read (tools/df1mon/mon_read.c, mon_stream.c and the
 * decoded lines of tools/decode*.c): a pcap (RTAC serial or another link
 * type) or a raw byte dump, from a regular file (read twice: the direction
 * scan) or from a pipe.
 * Input: byte 0 the options (bits 0-1 check CRC/BCC/auto, bit 2 --duplex given,
 * bit 3 half duplex, bit 4 JSON, bit 5 -v, bit 6 through a pipe); the rest is
 * the file. Properties: mon_run_read returns an exit status (0, 1, 2) or goes on,
 * and never feeds the decoders more bytes than the file holds.
 */
#include "fuzz.h"

#include <fcntl.h>
#include <string.h>
#include <unistd.h>

#include "df1mon/mon.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_log();
	/* the decoded lines and df1mon's messages: not wanted in the fuzzer's log */
	if (!freopen("/dev/null", "w", stdout))
		return 0;
	FILE *null = fopen("/dev/null", "w");
	if (null)
		stderr = null;
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const enum df1_check checks[4] = { DF1_CHECK_CRC, DF1_CHECK_BCC, DF1_CHECK_AUTO,
	                                          DF1_CHECK_AUTO };
	static struct mon m;
	char path[64];
	int pfd[2] = { -1, -1 };
	uint8_t o;
	int r;

	if (size < 1)
		return 0;
	o = data[0];
	data++;
	size--;
	memset(&m, 0, sizeof m);
	m.cli.name = "df1mon";
	m.cli.check = checks[o & 3];
	if (o & 4)
		m.cli.given |= CLI_ACCEPT(CLI_OPT_DUPLEX);
	m.cli.half_duplex = (o & 8) != 0;
	m.cli.format = (o & 16) ? CLI_FMT_JSON : CLI_FMT_PLAIN;
	m.cli.quiet = true;
	m.mode = MODE_READ;
	decode_ctx_init(&m.dx, m.cli.format);
	m.dx.verbose = (o & 32) ? 1 : 0;
	m.out = stdout;
	if ((o & 64) && size <= 60000 && pipe(pfd) == 0) {
		fcntl(pfd[1], F_SETPIPE_SZ, 65536);
		if (write(pfd[1], data, size) != (ssize_t)size) {
			close(pfd[0]);
			close(pfd[1]);
			return 0;
		}
		close(pfd[1]);
		snprintf(path, sizeof path, "/proc/self/fd/%d", pfd[0]);
		m.read_file = path;
	} else {
		m.read_file = fuzz_file(data, size);
		if (!m.read_file)
			return 0;
	}
	r = mon_run_read(&m);
	if (pfd[0] >= 0)
		close(pfd[0]);
	FUZZ_CHECK(r == CLI_CONTINUE || r == CLI_EXIT_OK || r == CLI_EXIT_FAIL || r == CLI_EXIT_USAGE,
	           "mon_run_read returned %d", r);
	FUZZ_CHECK(m.fed <= size, "fed %llu bytes of a %zu-byte file", m.fed, size);
	FUZZ_CHECK(m.used <= m.fed, "%llu bytes in symbols of %llu fed", m.used, m.fed);
	return 0;
}
