/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_int - what the cli_*.c files share and the tools do not see: the table
 * of common options, and helpers one cli file defines for another.
 *
 *   cli_opts.c     the common options: table, defaults, --help, each option
 *   cli_libopts.c  the common options that set df1_set_option()'s link and PLC
 *                  options: their values, applied to a handle and to decoders
 *   cli_net.c      -N FILE, the network configuration CSV
 *   cli_argv.c     cli_parse: argv, --help, --version
 *   cli_errors.c   exit status, error reports in the catalog format
 *   cli_handle.c   building, opening and closing the handle; -v log, -vv trace
 *   cli_addr.c     operand addresses
 *   cli_signals.c  SIGINT/SIGTERM, the self-pipe, --duration
 *   cli_text.c     JSON, CSV, hex (below cli and decode: cli_text.h)
 */
#ifndef DF1_TOOLS_CLI_INT_H
#define DF1_TOOLS_CLI_INT_H

#include "common/cli.h"

/* Keys of the long-only common options: CLI_KEY_COMMON + id. */
#define CLI_KEY_COMMON 256
#define CLI_KEY_HELP 'h'
#define CLI_KEY_VERSION 'V'

struct cli_common_opt {
	enum cli_opt_id id;
	const char *name;
	int has_arg;
	int key;               /* short letter, or CLI_KEY_COMMON + id */
	const char *arg;
	const char *help;
};

/* cli_opts.c */
extern const struct cli_common_opt cli_common_opts[];
extern const size_t cli_n_common;
bool cli_accepts(const struct cli *c, enum cli_opt_id id);
/* One common option given on the command line: CLI_CONTINUE or an exit status. */
int cli_common_option(struct cli *c, enum cli_opt_id id, const char *arg);

/* cli_libopts.c: is id one of df1_set_option()'s; parse its value */
bool cli_is_lib_option(enum cli_opt_id id);
int cli_lib_option(struct cli *c, enum cli_opt_id id, const char *arg);

/* cli_net.c: load -N FILE and take its values for every option not given. */
int cli_load_net(struct cli *c);

/* cli_errors.c: tag and text of err, with the handle's detail when it describes
 * the same error. */
void cli_error_parts(const df1_t *h, int err, char *tag, size_t tcap, char *text, size_t xcap);

#endif
