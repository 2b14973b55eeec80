/* SPDX-License-Identifier: MPL-2.0 */
/*
 * decode - one decoded DF1 symbol as one line of text (plain or JSON), shared by
 * df1mon (--decode, --read, --sniff) and the -vv frame trace of every tool.
 *
 * It remembers the last commands by (station, TNS) so that a reply, which
 * carries no address, is shown with the address of its command and its values
 * are decoded with the command's file type. Uses only include/df1.h.
 */
#ifndef DF1_TOOLS_DECODE_H
#define DF1_TOOLS_DECODE_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include "df1.h"
#include "common/cli_text.h"   /* enum cli_format; decode does not use cli */

#define DECODE_CMDS 64

/* A remembered command. */
struct decode_cmd {
	bool used;
	uint8_t dst, src, cmd, fnc;
	bool has_fnc;
	uint16_t tns;
	char label[96];           /* its name, for "reply to ..." */
	bool has_addr;
	struct df1_addr addr;
	int size;
	enum df1_file_type ft;    /* file type the reply's values decode as */
	unsigned long age;        /* larger = newer */
};

struct decode_ctx {
	enum cli_format format;   /* CLI_FMT_PLAIN or CLI_FMT_JSON */
	bool show_time;           /* plain: a time column */
	bool show_dir;            /* plain: a direction column */
	int verbose;              /* plain: >= 1 prints the frame's bytes on a second line */
	struct decode_cmd cmds[DECODE_CMDS];
	unsigned long clock;
	/* tallies */
	unsigned long frames, good, bad, symbols, errors;
};

/* Where a symbol was seen. */
struct decode_where {
	unsigned long index;      /* 1-based symbol number */
	bool has_time;
	int64_t rel_sec;          /* time since the first record / trace start */
	int32_t rel_usec;
	bool has_epoch;           /* absolute time (pcap record) */
	int64_t epoch_sec;
	int32_t epoch_usec;
	const char *dir;          /* "tx", "rx" or NULL */
	/* radio modem (df1mon --duplex radio): a good packet that repeats an
	 * earlier one, symbol number copy_of (0: none): a relay's copy
	 * (copy_relay) or its sender's retry; copy_duplicate: one more copy of
	 * a packet heard twice already, or the retry, which a node drops */
	unsigned long copy_of;
	bool copy_relay;
	bool copy_duplicate;
};

void decode_ctx_init(struct decode_ctx *x, enum cli_format format);
/* Print one symbol as one line (plus the bytes line at verbose >= 1 in plain) to f,
 * each line starting with prefix (may be NULL). Updates the tallies and the command
 * memory. Returns true when the symbol is bad (a frame with a bad check, a
 * malformation). */
bool decode_print(struct decode_ctx *x, FILE *f, const char *prefix, const struct decode_where *w,
                  const struct df1_symbol *s);
/* An ERROR line for a problem found outside the decoder (e.g. an incomplete frame
 * at the end of the input): catalog ID and text. Counted as an error. */
void decode_print_error(struct decode_ctx *x, FILE *f, const char *prefix,
                        const struct decode_where *w, int catalog_id, const char *text);
/* Forget remembered commands (keeps the tallies). */
void decode_forget(struct decode_ctx *x);

#endif
