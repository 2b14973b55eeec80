/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_eip - the EtherNet/IP server's options that df1gw --eip and df1sim
 * --eip share (df1-eip(7), df1gw(1) and df1sim(1) EtherNet/IP): who may
 * connect, read-only, and the connection limits. Each tool keeps its own
 * --eip (what the server is for differs) and puts CLI_EIP_OPTS in its table
 * of extra options; the values become the library's server configuration
 * (include/df1_eip.h) here, so both tools mean the same by each option.
 */
#ifndef DF1_TOOLS_CLI_EIP_H
#define DF1_TOOLS_CLI_EIP_H

#include <stdbool.h>

#include "common/cli.h"
#include "df1_eip.h"

/* The options, by their offset from the first key the tool gives them. */
enum cli_eip_opt {
	CLI_EIP_ALLOW,
	CLI_EIP_READ_ONLY,
	CLI_EIP_MAX_CLIENTS,
	CLI_EIP_REGISTER_TIMEOUT,
	CLI_EIP_IDLE_TIMEOUT,
	CLI_EIP_OPT_COUNT_
};

/* The entries of a tool's struct cli_extra_opt table, keys KEY to
 * KEY + CLI_EIP_OPT_COUNT_ - 1. */
#define CLI_EIP_OPTS(key)                                                                                    \
	{ "eip-allow", required_argument, (key) + CLI_EIP_ALLOW, "CIDR[,CIDR]",                                  \
	  "--eip: only these clients (default any)" },                                                           \
	{ "eip-read-only", no_argument, (key) + CLI_EIP_READ_ONLY, NULL,                                         \
	  "--eip: refuse commands that write or change mode (STS 60h)" },                                        \
	{ "eip-max-clients", required_argument, (key) + CLI_EIP_MAX_CLIENTS, "N",                                \
	  "--eip: connections at once, 1-255 (default 32; full: the longest idle makes room)" },                \
	{ "eip-register-timeout", required_argument, (key) + CLI_EIP_REGISTER_TIMEOUT, "S",                      \
	  "--eip: close a connection without a session after S s (default 5, 0: never)" },                     \
	{ "eip-idle-timeout", required_argument, (key) + CLI_EIP_IDLE_TIMEOUT, "S",                              \
	  "--eip: close a session idle for S s (default 120, 0: never)" }

/* What they set; cli_eip_init() gives "not given" to each. */
struct cli_eip {
	const char *allow;       /* --eip-allow CIDR[,CIDR] (NULL: any client) */
	bool read_only;          /* --eip-read-only */
	int max_clients;         /* --eip-max-clients N (0: the library's 32) */
	int register_s, idle_s;  /* --eip-register-timeout S, --eip-idle-timeout S (-1: default, 0: never) */
};

/* The defaults the options' help and the log lines name. */
#define CLI_EIP_REGISTER_S_DEFAULT 5
#define CLI_EIP_IDLE_S_DEFAULT 120

void cli_eip_init(struct cli_eip *e);
/* Whether key is one of the options of a table whose CLI_EIP_OPTS start at first. */
bool cli_eip_is_option(int key, int first);
/* Option key (of CLI_EIP_OPTS(first)) with its argument into e: CLI_CONTINUE, or the exit status having said why. */
int cli_eip_option(struct cli *c, struct cli_eip *e, int key, int first, const char *arg);
/* Without --eip (have_eip false) none of them may be given: CLI_CONTINUE, or
 * the usage error naming them. */
int cli_eip_check(struct cli *c, const struct cli_eip *e, bool have_eip);
/* Into the library's server configuration (allow, read_only, max_clients)
 * and limits (register_ms, idle_ms; on_close and user are the caller's). */
void cli_eip_server_config(const struct cli_eip *e, struct df1_eip_server_config *c,
                           struct df1_eip_server_limits *lim);
/* The seconds a limit closed a connection after, for the log line. */
int cli_eip_register_s(const struct cli_eip *e);
int cli_eip_idle_s(const struct cli_eip *e);

#endif
