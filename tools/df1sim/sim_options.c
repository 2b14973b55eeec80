/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_options - df1sim's options: the table, what each sets, the checks
 * between them (df1sim(1)). The line options are tools/common's (cli_parse);
 * these are df1sim's own, as extra options: the line options mean the same
 * for a responder as for a master.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "df1sim/sim_io.h"
#include "df1sim/sim_options.h"

#define PROG "df1sim"

enum {
	OPT_PTY = CLI_KEY_EXTRA, OPT_LISTEN, OPT_STATION, OPT_DATA_BITS, OPT_LINE_BAUD, OPT_PROCESSOR,
	OPT_PLC5_FLOAT_SWAPPED, OPT_DATA, OPT_DROP_ACK, OPT_CORRUPT, OPT_NAK, OPT_DELAY, OPT_SILENT,
	OPT_STALE, OPT_NOISE, OPT_SEED, OPT_LOG, OPT_SCAN_TIME, OPT_NO_EOT,
	OPT_PLC5_REFUSE_LARGE,
	OPT_MAX_QUEUE, OPT_EIP,
	OPT_EIP_SHARED, /* the CLI_EIP_OPT_COUNT_ keys of tools/common/cli_eip.h from here */
	OPT_EIP_SHARED_END_ = OPT_EIP_SHARED + CLI_EIP_OPT_COUNT_ - 1,
	OPT_LINE_SETTINGS = CLI_KEY_EXTRA + 100, /* tools/df1sim/sim_line.c */
	OPT_RAMP = CLI_KEY_EXTRA + 110,          /* tools/df1sim/sim_ramp.c */
	OPT_MSG = CLI_KEY_EXTRA + 120,           /* tools/df1sim/sim_msg.c */
};

/* -d, --station and -b are df1sim's own: -d is the device served (never
 * DF1_DEVICE), --station the list of stations served, -b and --data-bits go
 * to the port as given (any rate, 5-8 bits) and are ignored without -d. */
static const struct cli_extra_opt sim_opt_table[] = {
	{ "pty", required_argument, OPT_PTY, "PATH", "create a pseudo-terminal, symlink PATH to it" },
	{ "device", required_argument, 'd', "DEV", "serve a serial port (or tcp://HOST:PORT as a client)" },
	{ "listen", required_argument, OPT_LISTEN, "ADDR", "serve TCP clients one after another on ADDR" },
	{ "eip", required_argument, OPT_EIP, "ADDR", "also serve PCCC over EtherNet/IP on ADDR (TCP and UDP)" },
	CLI_EIP_OPTS(OPT_EIP_SHARED),
	{ "station", required_argument, OPT_STATION, "N[,N...]",
	  "stations served 0-254, ranges A-B allowed (default 1)" },
	{ "baud", required_argument, 'b', "N", "-d only: baud rate (default 19200)" },
	{ "data-bits", required_argument, OPT_DATA_BITS, "N", "-d only: data bits 5-8 (default 8)" },
	{ "line-settings", required_argument, OPT_LINE_SETTINGS, "BAUD[,8E1]",
	  "the PLC's line: what a master at other settings sends is garbled" },
	{ "line-baud", required_argument, OPT_LINE_BAUD, "N",
	  "pace the bytes sent and received as a line at N baud (default 0: off)" },
	{ "scan-time", required_argument, OPT_SCAN_TIME, "MS",
	  "answer at the end of a program scan of MS ms, as a controller does (default 0: at once)" },
	{ "no-eot", no_argument, OPT_NO_EOT, NULL,
	  "half duplex: answer a poll with nothing, not DLE EOT, when no reply is ready" },
	{ "processor", required_argument, OPT_PROCESSOR, "NAME",
	  "the processor of the diagnostic status (default per --plc)" },
	{ "plc5-refuse-large", no_argument, OPT_PLC5_REFUSE_LARGE, NULL,
	  "plc5: refuse a typed read larger than one reply (STS F0 EXT 09), not cut it" },
	{ "plc5-float-swapped", no_argument, OPT_PLC5_FLOAT_SWAPPED, NULL,
	  "the same as --plc5-float swapped" },
	{ "data", required_argument, OPT_DATA, "FILE", "initial values: ADDRESS=VALUE[,VALUE...] per line" },
	{ "drop-ack", required_argument, OPT_DROP_ACK, "P", "fault: do not ACK a received command" },
	{ "corrupt", required_argument, OPT_CORRUPT, "P", "fault: send a reply with a wrong BCC/CRC" },
	{ "nak", required_argument, OPT_NAK, "P", "fault: answer a good command with NAK" },
	{ "delay", required_argument, OPT_DELAY, "MS[:P]", "fault: delay replies by MS ms (P default 100)" },
	{ "silent", required_argument, OPT_SILENT, "STATION", "fault: never answer this station" },
	{ "stale", required_argument, OPT_STALE, "P", "fault: send a reply with an old TNS first" },
	{ "noise", required_argument, OPT_NOISE, "P", "fault: send garbage bytes between frames" },
	{ "seed", required_argument, OPT_SEED, "N", "random seed of the faults (default 1)" },
	{ "max-queue", required_argument, OPT_MAX_QUEUE, "N",
	  "full duplex: commands held unanswered before NAK 0-8 (default 8; 0: one)" },
	{ "log", required_argument, OPT_LOG, "FILE", "one line per command answered" },
	{ "ramp", required_argument, OPT_RAMP, "ADDR[,STEP][@MS]",
	  "add STEP (default 1) to ADDR every MS ms (default 100; a bit toggles); repeatable" },
	{ "msg", required_argument, OPT_MSG, "KIND,LOCAL,COUNT,STATION,REMOTE[,MS][,seq]",
	  "send a MSG every MS ms (default 1000; half duplex: when polled), e.g. write,N7:0,10,0,N50:0,500" },
	{ NULL, 0, 0, NULL, NULL },
};

/* The fault options, OPT_DROP_ACK.. in order. */
static const struct {
	enum df1_fault kind;
	const char *opt;
} fault_opts[] = {
	{ DF1_FAULT_DROP_ACK, "--drop-ack" },     { DF1_FAULT_CORRUPT_REPLY, "--corrupt" },
	{ DF1_FAULT_NAK_COMMAND, "--nak" },       { DF1_FAULT_DELAY_REPLY, "--delay" },
	{ DF1_FAULT_SILENT_STATION, "--silent" }, { DF1_FAULT_STALE_REPLY, "--stale" },
	{ DF1_FAULT_NOISE, "--noise" },
};

static bool parse_stations(const char *s, struct sim_opts *o)
{
	char buf[1024], *tok, *save = NULL;
	bool seen[256] = { false };

	if (strlen(s) >= sizeof buf)
		return false;
	strcpy(buf, s);
	o->nstations = 0;
	for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		char *dash = strchr(tok + 1, '-');
		long lo, hi;

		if (dash) {
			*dash = '\0';
			if (!cli_long_in(tok, 0, 254, &lo) || !cli_long_in(dash + 1, 0, 254, &hi) || hi < lo)
				return false;
		} else {
			if (!cli_long_in(tok, 0, 254, &lo))
				return false;
			hi = lo;
		}
		for (long v = lo; v <= hi; v++) {
			if (!seen[v])
				o->stations[o->nstations++] = (int)v;
			seen[v] = true;
		}
	}
	return o->nstations > 0;
}

static int set_fault(struct sim_opts *o, int i, const char *arg)
{
	struct fault_opt *f = &o->faults[fault_opts[i].kind];
	const char *opt = fault_opts[i].opt;
	char buf[64], *colon;
	long ms;

	f->kind = fault_opts[i].kind;
	f->given = true;
	f->value = 0;
	f->per_mille = 1000;
	switch (f->kind) {
	case DF1_FAULT_SILENT_STATION:
		return cli_parse_int(&o->cli, opt, arg, 0, 254, &f->value);
	case DF1_FAULT_DELAY_REPLY:
		if (strlen(arg) >= sizeof buf)
			return cli_bad_value(&o->cli, opt, arg, "MS[:P]");
		strcpy(buf, arg);
		colon = strchr(buf, ':');
		if (colon)
			*colon++ = '\0';
		if (!cli_long_in(buf, 0, 60000, &ms) || (colon && !sim_parse_percent(colon, &f->per_mille)))
			return cli_bad_value(&o->cli, opt, arg, "MS[:P], MS 0-60000, P 0-100 percent");
		f->value = (int)ms;
		return CLI_CONTINUE;
	default:
		if (!sim_parse_percent(arg, &f->per_mille))
			return cli_bad_value(&o->cli, opt, arg, "0-100 percent");
		return CLI_CONTINUE;
	}
}

static int on_option(struct cli *c, int key, const char *arg, void *user)
{
	struct sim_opts *o = user;
	unsigned long long u;
	char *end;
	char why[120];

	if (cli_eip_is_option(key, OPT_EIP_SHARED))
		return cli_eip_option(c, &o->eip_opts, key, OPT_EIP_SHARED, arg);
	switch (key) {
	case OPT_PTY: o->pty = arg; o->where++; break;
	case 'd': o->device = arg; o->where++; break;
	case OPT_LISTEN: o->listen = arg; o->where++; break;
	case OPT_STATION:
		if (!parse_stations(arg, o))
			return cli_bad_value(c, "--station", arg, "N[,N...] or A-B within 0-254");
		break;
	case 'b': return cli_parse_int(c, "--baud", arg, 50, 4000000, &o->baud);
	case OPT_DATA_BITS: return cli_parse_int(c, "--data-bits", arg, 5, 8, &o->data_bits);
	case OPT_LINE_BAUD: return cli_parse_int(c, "--line-baud", arg, 0, 4000000, &o->line_baud);
	case OPT_SCAN_TIME: return cli_parse_int(c, "--scan-time", arg, 0, 10000, &o->scan_time);
	case OPT_NO_EOT: o->no_eot = true; break;
	case OPT_PLC5_REFUSE_LARGE: o->plc5_refuse_large = true; break;
	case OPT_PROCESSOR: o->processor = arg; break;
	case OPT_PLC5_FLOAT_SWAPPED:
		c->lib_value[CLI_OPT_PLC5_FLOAT] = 1;
		c->lib_set |= CLI_ACCEPT(CLI_OPT_PLC5_FLOAT);
		break;
	case OPT_DATA: o->data = arg; break;
	case OPT_SEED:
		errno = 0;
		u = strtoull(arg, &end, cli_number_base(arg));
		if (errno || !*arg || *end || arg[0] == '-')
			return cli_bad_value(c, "--seed", arg, "an integer 0 or more");
		o->seed = u;
		break;
	case OPT_LOG: o->log = arg; break;
	case OPT_MAX_QUEUE: return cli_parse_int(c, "--max-queue", arg, 0, 8, &o->max_queue);
	case OPT_EIP: o->eip = arg; break;
	case OPT_MSG:
		if (o->nmsgs >= SIM_MSG_MAX)
			return cli_usage_error(c, "at most %d --msg", SIM_MSG_MAX);
		if (sim_msg_parse(arg, &o->msgs[o->nmsgs], why, sizeof why) < 0)
			return cli_bad_value(c, "--msg", arg, why);
		o->nmsgs++;
		break;
	case OPT_LINE_SETTINGS:
		if (!sim_uart_parse(arg, &o->line))
			return cli_bad_value(c, "--line-settings", arg, "BAUD or BAUD,DPS such as 9600,8E1 "
			                     "(data bits 5-8, parity N E O, stop bits 1 or 2)");
		break;
	case OPT_RAMP: {
		char err[160];
		if (!sim_ramp_parse(&o->ramps, arg, err, sizeof err))
			return cli_bad_value(c, "--ramp", arg, err);
		break;
	}
	default:
		if (key >= OPT_DROP_ACK && key <= OPT_NOISE)
			return set_fault(o, key - OPT_DROP_ACK, arg);
		return cli_usage_error(c, "unknown option");
	}
	return CLI_CONTINUE;
}

static const struct cli_tool sim_tool = {
	.name = PROG,
	.synopsis = "(--pty PATH | -d DEV | --listen [tcp://][HOST:]PORT) [--eip ADDR] [OPTIONS] | --eip ADDR [OPTIONS]",
	.summary = "A simulated PLC (DF1 half-duplex slave, full-duplex peer or radio-modem node) with\n"
	           "a data table and fault injection. Prints the device it serves on stdout once ready.",
	.accepts = CLI_ACCEPT(CLI_OPT_PARITY) | CLI_ACCEPT(CLI_OPT_STOP_BITS) | CLI_ACCEPT(CLI_OPT_DUPLEX) |
	           CLI_ACCEPT(CLI_OPT_CHECK) | CLI_ACCEPT(CLI_OPT_PLC) | CLI_ACCEPT(CLI_OPT_VERBOSE) |
	           /* the link and PLC options a responder has a use for */
	           CLI_ACCEPT(CLI_OPT_HD_BCC) | CLI_ACCEPT(CLI_OPT_PLC5_FLOAT) |
	           CLI_ACCEPT(CLI_OPT_PLC5_TIMER_WORDS) | CLI_ACCEPT(CLI_OPT_PLC2_ADDR) |
	           CLI_ACCEPT(CLI_OPT_DUP_DETECT) | CLI_ACCEPT(CLI_OPT_EMBEDDED) | CLI_ACCEPT(CLI_OPT_NAK_0F) |
	           CLI_ACCEPT(CLI_OPT_ECHO_DISCARD) | CLI_ACCEPT(CLI_OPT_LOW_LATENCY) |
	           CLI_ACCEPT(CLI_OPT_CMD_TIMEOUT) |
	           /* a radio-modem PLC or relay (libdf1(7) RADIO MODEM) */
	           CLI_ACCEPT_RADIO | CLI_ACCEPT(CLI_OPT_FORWARD),
	.plcs = CLI_PLC_BIT(DF1_PLC_SLC) | CLI_PLC_BIT(DF1_PLC_MICROLOGIX) | CLI_PLC_BIT(DF1_PLC_SLC502) |
	        CLI_PLC_BIT(DF1_PLC_PLC5) | CLI_PLC_BIT(DF1_PLC_PLC3),
	.common_help = {
		[CLI_OPT_PARITY] = "-d only: parity (default none)",
		[CLI_OPT_STOP_BITS] = "-d only: stop bits (default 1)",
		[CLI_OPT_DUPLEX] = "full-duplex peer, half-duplex slave or radio modem (default full)",
		[CLI_OPT_VERBOSE] = "link events on stderr; -vv also every byte",
		[CLI_OPT_CMD_TIMEOUT] = "--msg: how long a MSG waits for its reply (default 1000)",
		[CLI_OPT_HD_BCC] = "master message BCC: STN+data or +STX (default stn)",
		[CLI_OPT_PLC5_TIMER_WORDS] = "plc5: typed-read timers of 3 or 5 words (default 5)",
		[CLI_OPT_PLC2_ADDR] = "PLC-2 command addresses (default bytes)",
		[CLI_OPT_DUP_DETECT] = "ACK and drop a repeated command (default yes)",
	},
	.extra = sim_opt_table,
	.on_extra = on_option,
	.exit_text = "0 stopped by SIGINT/SIGTERM, 1 communication error, 2 usage.",
	.help_tail = "\nADDR: [tcp://][HOST:]PORT, loopback unless HOST is given; port 0 picks a free port.\n"
	             "NAME: e.g. slc5/04, ml1400, plc5/40, or a type code such as 0x5B.\n"
	             "P: a probability in percent, 0-100, steps of 0.1.\n"
	             "Signals: SIGUSR1 silences every station, SIGUSR2 makes them answer again.\n"
	             "See df1sim(1).\n",
};

/* --listen rfc2217://ADDR and --line-settings: where they apply (-d takes the
 * line's settings as its own serial settings). */
static int sim_line_check(struct sim_opts *o)
{
	if (o->listen && strncasecmp(o->listen, "rfc2217://", 10) == 0) {
		o->rfc2217 = true;
		o->listen += 10;
	}
	if (!o->line.baud)
		return CLI_CONTINUE;
	if (o->listen && !o->rfc2217)
		return cli_usage_error(&o->cli, "--line-settings goes with --pty, -d or "
		                       "--listen rfc2217://ADDR (a raw TCP client has no line settings)");
	if (o->device) {
		o->baud = o->line.baud;
		o->data_bits = o->line.data_bits;
		o->cli.parity = o->line.parity;
		o->cli.stop_bits = o->line.stop_bits;
	}
	return CLI_CONTINUE;
}

/* CLI_CONTINUE to go on, else an exit status. */
int sim_options_parse(int argc, char **argv, struct sim_opts *o)
{
	int r;

	memset(o, 0, sizeof *o);
	cli_init(&o->cli, &sim_tool);
	o->stations[0] = 1;
	o->nstations = 1;
	o->seed = 1;
	o->max_queue = 8;
	o->baud = 19200;
	o->data_bits = 8;
	cli_eip_init(&o->eip_opts);
	r = cli_parse(&o->cli, argc, argv, o);
	if (r != CLI_CONTINUE)
		return r;
	if (o->cli.argc > 0)
		return cli_usage_error(&o->cli, "unexpected argument '%s'", o->cli.argv[0]);
	if (o->where > 1 || (o->where == 0 && !o->eip))
		return cli_usage_error(&o->cli, o->where ? "give only one of --pty, -d and --listen"
		                                         : "one of --pty PATH, -d DEV, --listen ADDR or --eip ADDR is required");
	if (sim_line_check(o) != CLI_CONTINUE)
		return CLI_EXIT_USAGE;
	if ((r = cli_eip_check(&o->cli, &o->eip_opts, o->eip != NULL)) != CLI_CONTINUE)
		return r;
	if (cli_lib_option_set(&o->cli, CLI_OPT_PLC5_FLOAT) && o->cli.lib_value[CLI_OPT_PLC5_FLOAT] &&
	    o->cli.plc != DF1_PLC_PLC5)
		return cli_usage_error(&o->cli, "--plc5-float swapped goes with --plc plc5 only");
	if ((o->cli.given & CLI_ACCEPT(CLI_OPT_PLC5_TIMER_WORDS)) && o->cli.plc != DF1_PLC_PLC5)
		return cli_usage_error(&o->cli, "--plc5-timer-words goes with --plc plc5 only");
	if (o->plc5_refuse_large && o->cli.plc != DF1_PLC_PLC5)
		return cli_usage_error(&o->cli, "--plc5-refuse-large goes with --plc plc5 only");
	/* a PLC-5 answers typed reads of timers with 5 words, as KF2 p.130 and VME
	 * p.81 describe it (doc/PROTOCOL.md 4.3); --plc5-timer-words 3 for the data-table form */
	if (o->cli.plc == DF1_PLC_PLC5 && !(o->cli.given & CLI_ACCEPT(CLI_OPT_PLC5_TIMER_WORDS))) {
		o->cli.lib_value[CLI_OPT_PLC5_TIMER_WORDS] = 5;
		o->cli.lib_set |= CLI_ACCEPT(CLI_OPT_PLC5_TIMER_WORDS);
	}
	return CLI_CONTINUE;
}

