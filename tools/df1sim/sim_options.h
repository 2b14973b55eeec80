/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_options - df1sim's command line: what the options set (struct sim_opts)
 * and the parsing with its checks (sim_options.c). df1sim.c builds and serves
 * the simulated PLC from the result.
 */
#ifndef DF1_TOOLS_SIM_OPTIONS_H
#define DF1_TOOLS_SIM_OPTIONS_H

#include <stdbool.h>
#include <stdint.h>

#include "df1.h"
#include "common/cli.h"
#include "common/cli_eip.h"
#include "df1sim/sim_line.h"
#include "df1sim/sim_ramp.h"
#include "df1sim/sim_msg.h"

struct fault_opt {
	enum df1_fault kind;
	int per_mille;
	int value;
	bool given;
};

struct sim_opts {
	struct cli cli;                 /* --parity, --stop-bits, --duplex, --check, --plc, -v */
	const char *pty, *device, *listen;
	int where;                      /* how many of --pty, -d, --listen */
	int stations[256];
	int nstations;
	const char *processor;
	const char *data;
	struct fault_opt faults[8];     /* by enum df1_fault */
	uint64_t seed;
	int line_baud;
	int scan_time;                  /* --scan-time MS: replies at the end of the scan */
	bool no_eot;                    /* --no-eot: half duplex, silence instead of DLE EOT */
	bool plc5_refuse_large;         /* --plc5-refuse-large: F0/09 for a typed read too large */
	int max_queue;                  /* full duplex: commands held before NAK */
	const char *log;
	int baud, data_bits;            /* -d only; the library checks them when it opens DEV */
	const char *eip;                /* --eip ADDR */
	struct cli_eip eip_opts;        /* --eip-allow, --eip-read-only and the limits (tools/common/cli_eip.h) */
	/* --line-settings, --listen rfc2217:// (tools/df1sim/sim_line.h) */
	struct sim_uart line;
	bool rfc2217;
	struct sim_ramps ramps;         /* --ramp (tools/df1sim/sim_ramp.c) */
	struct sim_msg msgs[SIM_MSG_MAX]; /* --msg (tools/df1sim/sim_msg.c) */
	int nmsgs;
};

/* CLI_CONTINUE to go on, else the exit status (having said why). */
int sim_options_parse(int argc, char **argv, struct sim_opts *o);

#endif
