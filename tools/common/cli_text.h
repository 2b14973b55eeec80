/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_text - output text helpers shared by cli and decode (and every tool
 * through cli.h): the output formats, JSON and CSV quoting, hex dumps and hex
 * parsing. It sits below both cli and decode and includes neither, so the two
 * do not depend on each other through it. Uses only the C library.
 */
#ifndef DF1_TOOLS_CLI_TEXT_H
#define DF1_TOOLS_CLI_TEXT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* INFLUX: InfluxDB line protocol (df1mon --map only). */
enum cli_format { CLI_FMT_PLAIN = 0, CLI_FMT_CSV = 1, CLI_FMT_JSON = 2, CLI_FMT_INFLUX = 3,
                  CLI_FMT_PROMETHEUS = 4 /* df1mon --counters: Prometheus text (cli_counters.c) */ };

/* The length of the valid UTF-8 sequence at s (at most n bytes), its code
 * point in *cp_out (may be NULL); 0 if there is none (overlong, surrogate,
 * past U+10FFFF, truncated). */
size_t cli_utf8_seq(const unsigned char *s, size_t n, uint32_t *cp_out);
/* JSON: print s as a JSON string (quotes included), escaping control characters,
 * quotes, backslashes and invalid UTF-8 bytes (as \u00XX). */
void cli_json_string(FILE *f, const char *s);
void cli_json_string_n(FILE *f, const char *s, size_t n);
/* CSV (RFC 4180): print s, quoted when it holds a comma, quote, CR, LF or edge space. */
void cli_csv_field(FILE *f, const char *s);
/* CSV: print s quoted whatever it holds (quotes doubled). */
void cli_csv_quoted(FILE *f, const char *s);

/* Hex: "10 02 0F" into buf; returns length written (always NUL-terminated when cap > 0). */
size_t cli_hex(const uint8_t *b, size_t n, char *buf, size_t cap);
/* Parse hex text: pairs of digits, separated or not by spaces, tabs, ':' ',' '-',
 * an optional 0x before a byte. Returns the byte count, or -1 on bad text (an odd
 * digit count, a non-hex character) with *bad_at set to the offending offset. */
long cli_parse_hex(const char *text, uint8_t *out, size_t cap, size_t *bad_at);

#endif
