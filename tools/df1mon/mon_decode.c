/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_decode - df1mon --decode: frames given as hex, each argument (or each
 * stdin line) decoded on its own, with a fresh decoder.
 */
#include "df1mon/mon.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

static int decode_chunk(struct mon *m, const uint8_t *b, size_t n)
{
	struct stream s;
	int r = mon_stream_init(m, &s, NULL);

	if (r != CLI_CONTINUE)
		return r;
	mon_stream_feed(m, &s, NULL, b, n);
	mon_stream_finish(m, &s, NULL);
	mon_stream_free(&s);
	return CLI_CONTINUE;
}

static int bad_hex(const struct mon *m, const char *where, const char *text, size_t at)
{
	fprintf(stderr, "%s: %s: bad hex at character %zu: '%s'\n", m->cli.name, where, at + 1, text);
	return CLI_EXIT_USAGE;
}

#define CHUNK_MAX 65536

int mon_run_decode(struct mon *m)
{
	uint8_t *buf = malloc(CHUNK_MAX);
	char where[64];
	size_t at = 0;
	long n;
	int r = CLI_CONTINUE;

	if (!buf) {
		fprintf(stderr, "%s: out of memory\n", m->cli.name);
		return CLI_EXIT_FAIL;
	}
	if (m->cli.argc > 0) {
		/* check every argument before printing anything */
		for (int i = 0; i < m->cli.argc; i++) {
			if (cli_parse_hex(m->cli.argv[i], buf, CHUNK_MAX, &at) < 0) {
				snprintf(where, sizeof where, "argument %d", i + 1);
				free(buf);
				return bad_hex(m, where, m->cli.argv[i], at);
			}
		}
		for (int i = 0; i < m->cli.argc && r == CLI_CONTINUE; i++) {
			n = cli_parse_hex(m->cli.argv[i], buf, CHUNK_MAX, &at);
			r = decode_chunk(m, buf, (size_t)n);
		}
	} else {
		char *line = NULL;
		size_t cap = 0;
		unsigned long lineno = 0;
		ssize_t len;

		while (r == CLI_CONTINUE && (len = getline(&line, &cap, stdin)) >= 0) {
			char *hash = strchr(line, '#');
			lineno++;
			(void)len;
			if (hash)
				*hash = 0;
			n = cli_parse_hex(line, buf, CHUNK_MAX, &at);
			if (n < 0) {
				line[strcspn(line, "\r\n")] = 0;
				snprintf(where, sizeof where, "stdin: line %lu", lineno);
				r = bad_hex(m, where, line, at);
				break;
			}
			if (n > 0)
				r = decode_chunk(m, buf, (size_t)n);
		}
		if (r == CLI_CONTINUE && ferror(stdin)) {
			fprintf(stderr, "%s: stdin: %s\n", m->cli.name, strerror(errno));
			r = CLI_EXIT_USAGE;
		}
		free(line);
	}
	free(buf);
	return r;
}
