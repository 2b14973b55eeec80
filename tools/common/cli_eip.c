/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_eip - the EtherNet/IP server's shared options (cli_eip.h): parsed,
 * checked, and made into the library's server configuration and limits.
 */
#include "common/cli_eip.h"

#include <string.h>

void cli_eip_init(struct cli_eip *e)
{
	memset(e, 0, sizeof *e);
	e->register_s = e->idle_s = -1;
}

bool cli_eip_is_option(int key, int first)
{
	return key >= first && key < first + CLI_EIP_OPT_COUNT_;
}

int cli_eip_option(struct cli *c, struct cli_eip *e, int key, int first, const char *arg)
{
	switch ((enum cli_eip_opt)(key - first)) {
	case CLI_EIP_ALLOW: e->allow = arg; break;
	case CLI_EIP_READ_ONLY: e->read_only = true; break;
	case CLI_EIP_MAX_CLIENTS: return cli_parse_int(c, "--eip-max-clients", arg, 1, 255, &e->max_clients);
	case CLI_EIP_REGISTER_TIMEOUT: return cli_parse_int(c, "--eip-register-timeout", arg, 0, 3600, &e->register_s);
	case CLI_EIP_IDLE_TIMEOUT: return cli_parse_int(c, "--eip-idle-timeout", arg, 0, 3600, &e->idle_s);
	case CLI_EIP_OPT_COUNT_: break;
	}
	return CLI_CONTINUE;
}

int cli_eip_check(struct cli *c, const struct cli_eip *e, bool have_eip)
{
	if (have_eip || (!e->allow && !e->read_only && !e->max_clients && e->register_s < 0 && e->idle_s < 0))
		return CLI_CONTINUE;
	return cli_usage_error(c, "--eip-allow, --eip-read-only, --eip-max-clients, --eip-register-timeout and "
	                       "--eip-idle-timeout go with --eip");
}

/* The library's milliseconds for S seconds: 0 its default, -1 never. */
static int limit_ms(int seconds)
{
	return seconds < 0 ? 0 : seconds == 0 ? -1 : seconds * 1000;
}

void cli_eip_server_config(const struct cli_eip *e, struct df1_eip_server_config *c,
                           struct df1_eip_server_limits *lim)
{
	c->allow = e->allow;
	c->read_only = e->read_only;
	c->max_clients = e->max_clients;
	lim->register_ms = limit_ms(e->register_s);
	lim->idle_ms = limit_ms(e->idle_s);
}

int cli_eip_register_s(const struct cli_eip *e)
{
	return e->register_s < 0 ? CLI_EIP_REGISTER_S_DEFAULT : e->register_s;
}

int cli_eip_idle_s(const struct cli_eip *e)
{
	return e->idle_s < 0 ? CLI_EIP_IDLE_S_DEFAULT : e->idle_s;
}
