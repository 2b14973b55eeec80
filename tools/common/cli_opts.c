/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_opts - the common options of the tools: their table, defaults, --help,
 * and the parsing of each one (see cli.h).
 */
#include "common/cli_int.h"

#include <errno.h>
#include <getopt.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define LONG_ONLY(id) (CLI_KEY_COMMON + (id))

const struct cli_common_opt cli_common_opts[] = {
	{ CLI_OPT_DEVICE, "device", required_argument, 'd', "DEV",
	  "serial device, tcp://HOST:PORT, rfc2217://HOST:PORT or eip://HOST (env DF1_DEVICE)" },
	{ CLI_OPT_NET, "net", required_argument, 'N', "FILE", "network configuration CSV" },
	{ CLI_OPT_STATION, "station", required_argument, 'a', "N", "destination station 0-254, 255 = broadcast with --duplex radio (default 1)" },
	{ CLI_OPT_SRC, "src", required_argument, LONG_ONLY(CLI_OPT_SRC), "N",
	  "own station 0-254 (default 0)" },
	{ CLI_OPT_BAUD, "baud", required_argument, 'b', "N", "baud rate 1200-115200 (default 19200)" },
	{ CLI_OPT_PARITY, "parity", required_argument, 'P', "none|even|odd", "parity (default none)" },
	{ CLI_OPT_DATA_BITS, "data-bits", required_argument, LONG_ONLY(CLI_OPT_DATA_BITS), "7|8",
	  "data bits (default 8)" },
	{ CLI_OPT_STOP_BITS, "stop-bits", required_argument, LONG_ONLY(CLI_OPT_STOP_BITS), "1|2",
	  "stop bits (default 1)" },
	{ CLI_OPT_HANDSHAKE, "handshake", optional_argument, LONG_ONLY(CLI_OPT_HANDSHAKE), "[=yes|no]",
	  "RTS/CTS hardware handshake (default no)" },
	{ CLI_OPT_DUPLEX, "duplex", required_argument, LONG_ONLY(CLI_OPT_DUPLEX), "full|half|radio",
	  "link mode (default full; half = half-duplex master; radio = DF1 Radio Modem)" },
	{ CLI_OPT_CHECK, "check", required_argument, LONG_ONLY(CLI_OPT_CHECK), "crc|bcc",
	  "error check (default crc)" },
	{ CLI_OPT_PLC, "plc", required_argument, LONG_ONLY(CLI_OPT_PLC), "TYPE",
	  "the controller family" /* --help: the families the tool accepts, plc_list() */ },
	{ CLI_OPT_TIMEOUT, "timeout", required_argument, 'o', "MS",
	  "ACK and reply timeout 0-360000 (default 1000)" },
	{ CLI_OPT_CMD_TIMEOUT, "cmd-timeout", required_argument, LONG_ONLY(CLI_OPT_CMD_TIMEOUT), "MS",
	  "whole transaction 500-5000 (default 1000)" },
	{ CLI_OPT_NAK_RETRIES, "nak-retries", required_argument, LONG_ONLY(CLI_OPT_NAK_RETRIES), "N",
	  "retransmissions after NAK 0-10 (default 3)" },
	{ CLI_OPT_ENQ_RETRIES, "enq-retries", required_argument, LONG_ONLY(CLI_OPT_ENQ_RETRIES), "N",
	  "ENQs (polls) after a timeout 0-10 (default 3)" },
	{ CLI_OPT_TX_DELAY, "tx-delay", required_argument, LONG_ONLY(CLI_OPT_TX_DELAY), "MS",
	  "delay before each transmission 0-65535 (default 0)" },
	{ CLI_OPT_RS485, "rs485", no_argument, LONG_ONLY(CLI_OPT_RS485), NULL,
	  "kernel RS-485 mode (TIOCSRS485)" },
	{ CLI_OPT_FORMAT, "format", required_argument, 'f', "FMT", "output format" },
	{ CLI_OPT_VERBOSE, "verbose", no_argument, 'v', NULL,
	  "link events on stderr; -vv also every frame" },
	{ CLI_OPT_QUIET, "quiet", no_argument, 'q', NULL, "no messages on stderr but errors" },
	{ CLI_OPT_HD_BCC, "hd-bcc", required_argument, LONG_ONLY(CLI_OPT_HD_BCC), "stn|stx",
	  "half-duplex master BCC: STN+data or +STX (default stn)" },
	{ CLI_OPT_PLC5_FLOAT, "plc5-float", required_argument, LONG_ONLY(CLI_OPT_PLC5_FLOAT),
	  "plain|swapped", "PLC-5 typed read/write floats (default plain)" },
	{ CLI_OPT_PLC5_TIMER_WORDS, "plc5-timer-words", required_argument,
	  LONG_ONLY(CLI_OPT_PLC5_TIMER_WORDS), "3|5", "words of a PLC-5 typed-read timer (default 3)" },
	{ CLI_OPT_PLC2_ADDR, "plc2-addr", required_argument, LONG_ONLY(CLI_OPT_PLC2_ADDR), "bytes|words",
	  "--plc plc2 address unit (default bytes)" },
	{ CLI_OPT_SLC_IO_CODES, "slc-io-codes", required_argument, LONG_ONLY(CLI_OPT_SLC_IO_CODES), "8b|82",
	  "SLC codes of O and I: 8B 8C or 82 83 (default 8b)" },
	{ CLI_OPT_MAX_PACKET, "max-packet", required_argument, LONG_ONLY(CLI_OPT_MAX_PACKET), "BYTES",
	  "data bytes per packet, 0 = per PLC (default 0)" },
	{ CLI_OPT_DUP_DETECT, "duplicate-detect", required_argument, LONG_ONLY(CLI_OPT_DUP_DETECT),
	  "yes|no", "drop duplicate messages (default yes)" },
	{ CLI_OPT_EMBEDDED, "embedded-responses", required_argument, LONG_ONLY(CLI_OPT_EMBEDDED), "yes|no",
	  "accept DLE ACK/NAK inside a frame (default yes)" },
	{ CLI_OPT_NAK_0F, "nak-0f", required_argument, LONG_ONLY(CLI_OPT_NAK_0F), "yes|no",
	  "take DLE 0F as NAK too (default yes)" },
	{ CLI_OPT_EOT_BCC, "eot-bcc", required_argument, LONG_ONLY(CLI_OPT_EOT_BCC), "yes|no",
	  "ignore one byte after DLE EOT (default no)" },
	{ CLI_OPT_ECHO_DISCARD, "echo-discard", no_argument, LONG_ONLY(CLI_OPT_ECHO_DISCARD), NULL,
	  "2-wire line: drop the echo of our own bytes" },
	{ CLI_OPT_POLL_TIMEOUT, "poll-timeout", required_argument, LONG_ONLY(CLI_OPT_POLL_TIMEOUT), "MS",
	  "half duplex: poll again when a poll's answer has not begun (0 = auto)" },
	{ CLI_OPT_OUTSTANDING, "outstanding", required_argument, LONG_ONLY(CLI_OPT_OUTSTANDING), "N",
	  "full duplex: commands awaiting replies 1-16 (default 1)" },
	{ CLI_OPT_EIP_CONNECTED, "eip-connected", no_argument, LONG_ONLY(CLI_OPT_EIP_CONNECTED), NULL,
	  "eip:// target: connected messaging (Forward Open)" },
	{ CLI_OPT_LOW_LATENCY, "low-latency", required_argument, LONG_ONLY(CLI_OPT_LOW_LATENCY), "yes|no",
	  "USB serial adapter in low latency mode (default yes)" },
	{ CLI_OPT_ROUTE, "route", required_argument, LONG_ONLY(CLI_OPT_ROUTE), "yes|no",
	  "half-duplex master: forward a slave's messages for other slaves (default yes)" },
	{ CLI_OPT_APP_RETRIES, "app-retries", required_argument, LONG_ONLY(CLI_OPT_APP_RETRIES), "N",
	  "radio: send a command again after no reply 0-10 (default 0)" },
	{ CLI_OPT_RADIO_DUP, "dup-detect", required_argument, LONG_ONLY(CLI_OPT_RADIO_DUP), "yes|no|auto",
	  "radio: drop repeats of the last 20 packets (default auto: a relay or a node that serves)" },
	{ CLI_OPT_RADIO_RTS, "radio-rts", required_argument, LONG_ONLY(CLI_OPT_RADIO_RTS), "yes|no",
	  "radio: key with RTS, send once CTS is up (default no)" },
	{ CLI_OPT_RTS_SEND, "rts-send-delay", required_argument, LONG_ONLY(CLI_OPT_RTS_SEND), "MS",
	  "radio: from RTS up to the frame 0-65535 (default 0)" },
	{ CLI_OPT_RTS_OFF, "rts-off-delay", required_argument, LONG_ONLY(CLI_OPT_RTS_OFF), "MS",
	  "radio: from the frame's end to RTS down 0-65535 (default 0)" },
	{ CLI_OPT_DCD_WAIT, "dcd-wait", required_argument, LONG_ONLY(CLI_OPT_DCD_WAIT), "MS",
	  "radio: wait up to MS for DCD to drop before sending (default 0 = no)" },
	{ CLI_OPT_FORWARD, "forward", required_argument, LONG_ONLY(CLI_OPT_FORWARD), "LIST",
	  "radio: relay packets for these stations, e.g. 1,3-5,255 (default none)" },
};

const size_t cli_n_common = sizeof cli_common_opts / sizeof cli_common_opts[0];

static const int std_bauds[] = { 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200 };

void cli_init(struct cli *c, const struct cli_tool *t)
{
	memset(c, 0, sizeof *c);
	c->tool = t;
	c->name = t->name;
	c->station = 1;
	c->src = 0;
	c->baud = 19200;
	c->data_bits = 8;
	c->stop_bits = 1;
	c->parity = 'N';
	c->handshake = false;
	c->half_duplex = false;
	c->check = DF1_CHECK_CRC;
	c->plc = DF1_PLC_SLC;
	c->timeout_ms = 1000;
	c->cmd_timeout_ms = 1000;
	c->nak_retries = 3;
	c->enq_retries = 3;
	c->tx_delay_ms = 0;
	c->format = CLI_FMT_PLAIN;
}

bool cli_accepts(const struct cli *c, enum cli_opt_id id)
{
	return (c->tool->accepts & CLI_ACCEPT(id)) != 0;
}

static bool format_ok(const struct cli *c, enum cli_format f)
{
	return f == CLI_FMT_PLAIN || (c->tool->formats & CLI_FMT_BIT(f));
}

static const char *const plc_names[] = { "slc", "micrologix", "slc502", "plc5", "plc2", "plc3" };
#define N_PLCS ((int)(sizeof plc_names / sizeof plc_names[0]))

static bool plc_ok(const struct cli *c, int p)
{
	return p >= 0 && p < N_PLCS && (!c->tool->plcs || (c->tool->plcs & CLI_PLC_BIT(p)));
}

/* "slc, micrologix, slc502, plc5, plc2 or plc3": the families --plc accepts. */
static void plc_list(const struct cli *c, char *buf, size_t cap)
{
	int n = 0, k = 0;
	size_t len = 0;

	buf[0] = '\0';
	for (int p = 0; p < N_PLCS; p++)
		n += plc_ok(c, p);
	for (int p = 0; p < N_PLCS && len < cap; p++) {
		if (!plc_ok(c, p))
			continue;
		k++;
		len += (size_t)snprintf(buf + len, cap - len, "%s%s",
		                        k == 1 ? "" : k == n ? " or " : ", ", plc_names[p]);
	}
}

static const char *const format_names[] = { "plain", "csv", "json", "influx", "prometheus" };

/* The formats this tool takes: "plain|csv|json" (sep "|") or "plain, csv or json". */
static const char *format_list_sep(const struct cli *c, bool prose)
{
	static char buf[64];
	size_t len = 0, n = 0, k = 0;

	for (size_t f = 0; f < sizeof format_names / sizeof format_names[0]; f++)
		n += format_ok(c, (enum cli_format)f);
	buf[0] = '\0';
	for (size_t f = 0; f < sizeof format_names / sizeof format_names[0]; f++) {
		if (!format_ok(c, (enum cli_format)f))
			continue;
		k++;
		len += (size_t)snprintf(buf + len, sizeof buf - len, "%s%s",
		                        k == 1 ? "" : !prose ? "|" : k == n ? " or " : ", ",
		                        format_names[f]);
	}
	return buf;
}

static const char *format_list(const struct cli *c)
{
	return format_list_sep(c, false);
}

int cli_usage_error(const struct cli *c, const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, "%s: ", c->name);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fprintf(stderr, "\nTry '%s --help'.\n", c->name);
	return CLI_EXIT_USAGE;
}

static void usage_line(FILE *f, int key, const char *name, const char *arg, int has_arg,
                       const char *help)
{
	char left[64];
	int n;

	if (key > 0 && key < 256)
		n = snprintf(left, sizeof left, "  -%c, --%s", key, name);
	else
		n = snprintf(left, sizeof left, "      --%s", name);
	if (arg && n > 0 && (size_t)n < sizeof left)
		snprintf(left + n, sizeof left - (size_t)n, "%s%s",
		         has_arg == optional_argument ? "" : " ", arg);
	if (strlen(left) > 29)
		fprintf(f, "%s\n%31s%s\n", left, "", help);
	else
		fprintf(f, "%-29s  %s\n", left, help);
}

void cli_usage(const struct cli *c, FILE *f)
{
	const struct cli_tool *t = c->tool;
	const char *p = t->synopsis ? t->synopsis : "[OPTIONS]";
	const char *nl;

	/* one "Usage:" line per synopsis line */
	for (bool first = true; *p; first = false) {
		nl = strchr(p, '\n');
		fprintf(f, "%s %s %.*s\n", first ? "Usage:" : "      ", t->name,
		        (int)(nl ? (size_t)(nl - p) : strlen(p)), p);
		p = nl ? nl + 1 : p + strlen(p);
	}
	if (t->summary)
		fprintf(f, "%s\n", t->summary);
	if (t->extra && t->extra[0].name) {
		fprintf(f, "\n%s options:\n", t->name);
		for (const struct cli_extra_opt *e = t->extra; e->name; e++)
			usage_line(f, e->key, e->name, e->arg, e->has_arg, e->help);
	}
	fprintf(f, "\nCommon options:\n");
	for (size_t i = 0; i < cli_n_common; i++) {
		const struct cli_common_opt *o = &cli_common_opts[i];
		char help[160];
		const char *arg = o->arg;
		if (!cli_accepts(c, o->id))
			continue;
		snprintf(help, sizeof help, "%s", o->help);
		if (o->id == CLI_OPT_PLC) {
			char list[80];
			plc_list(c, list, sizeof list);
			snprintf(help, sizeof help, "%s (default %s)", list,
			         plc_ok(c, c->plc) ? plc_names[c->plc] : "slc");
		} else if (o->id == CLI_OPT_FORMAT) {
			arg = format_list(c);
			snprintf(help, sizeof help, "output format (default plain)");
		} else if (o->id == CLI_OPT_CHECK && t->check_auto) {
			arg = "crc|bcc|auto";
			snprintf(help, sizeof help, "error check (default %s)",
			         c->check == DF1_CHECK_AUTO ? "auto" : c->check == DF1_CHECK_BCC ? "bcc" : "crc");
		}
		if (t->common_help[o->id])
			snprintf(help, sizeof help, "%s", t->common_help[o->id]);
		usage_line(f, o->key, o->name, arg, o->has_arg, help);
	}
	usage_line(f, CLI_KEY_HELP, "help", NULL, no_argument, "print this help and exit");
	usage_line(f, CLI_KEY_VERSION, "version", NULL, no_argument, "print the version and exit");
	fprintf(f, "\nExit status: %s\n",
	        t->exit_text ? t->exit_text : "0 success, 1 communication or PLC error, 2 usage or configuration error.");
	if (t->help_tail)
		fprintf(f, "%s", t->help_tail);
}

int cli_number_base(const char *s)
{
	const char *p = s + (*s == '-' || *s == '+');

	return p[0] == '0' && (p[1] == 'x' || p[1] == 'X') ? 16 : 10;
}

bool cli_long_in(const char *s, long lo, long hi, long *out)
{
	char *end;
	long v;

	if (!s || !*s)
		return false;
	errno = 0;
	v = strtol(s, &end, cli_number_base(s));
	if (*end || errno || v < lo || v > hi)
		return false;
	*out = v;
	return true;
}

int cli_parse_int(const struct cli *c, const char *opt, const char *arg, long lo, long hi, int *out)
{
	long v;

	if (!cli_long_in(arg, lo, hi, &v)) {
		fprintf(stderr, "%s: %s: invalid value '%s' (expected %ld-%ld)\n", c->name, opt, arg, lo, hi);
		return CLI_EXIT_USAGE;
	}
	*out = (int)v;
	return CLI_CONTINUE;
}

int cli_bad_value(const struct cli *c, const char *opt, const char *arg, const char *expected)
{
	fprintf(stderr, "%s: %s: invalid value '%s' (expected %s)\n", c->name, opt, arg, expected);
	return CLI_EXIT_USAGE;
}

static bool word_in(const char *s, const char *const *words)
{
	for (; *words; words++)
		if (strcasecmp(s, *words) == 0)
			return true;
	return false;
}

static int parse_baud(struct cli *c, const char *arg)
{
	int v, r = cli_parse_int(c, "--baud", arg, 1200, 115200, &v);

	if (r != CLI_CONTINUE)
		return r;
	for (size_t i = 0; i < sizeof std_bauds / sizeof std_bauds[0]; i++) {
		if (std_bauds[i] == v) {
			c->baud = v;
			return CLI_CONTINUE;
		}
	}
	return cli_bad_value(c, "--baud", arg, "1200, 2400, 4800, 9600, 19200, 38400, 57600 or 115200");
}

static int parse_parity(struct cli *c, const char *arg)
{
	if (strcasecmp(arg, "none") == 0 || strcasecmp(arg, "n") == 0)
		c->parity = 'N';
	else if (strcasecmp(arg, "even") == 0 || strcasecmp(arg, "e") == 0)
		c->parity = 'E';
	else if (strcasecmp(arg, "odd") == 0 || strcasecmp(arg, "o") == 0)
		c->parity = 'O';
	else
		return cli_bad_value(c, "--parity", arg, "none, even or odd");
	return CLI_CONTINUE;
}

/* --handshake alone is yes. */
static int parse_handshake(struct cli *c, const char *arg)
{
	static const char *const yes[] = { "yes", "y", "on", "1", "true", "rtscts", "rts/cts", NULL };
	static const char *const no[] = { "no", "n", "off", "0", "false", "none", NULL };

	if (!arg || word_in(arg, yes))
		c->handshake = true;
	else if (word_in(arg, no))
		c->handshake = false;
	else
		return cli_bad_value(c, "--handshake", arg, "yes or no");
	return CLI_CONTINUE;
}

static int parse_duplex(struct cli *c, const char *arg)
{
	c->half_duplex = c->half_slave = c->radio = false;
	if (strcasecmp(arg, "full") == 0)
		c->half_duplex = false;
	else if (strcasecmp(arg, "half") == 0)
		c->half_duplex = true;
	else if (strcasecmp(arg, "half-slave") == 0 && c->tool->half_slave)
		c->half_duplex = c->half_slave = true;
	else if (strcasecmp(arg, "radio") == 0)
		c->radio = true;
	else
		return cli_bad_value(c, "--duplex", arg, c->tool->half_slave
		                                         ? "full, half, half-slave or radio"
		                                         : "full, half or radio");
	return CLI_CONTINUE;
}

/* auto only for the tools that read both checks (check_auto). */
static int parse_check(struct cli *c, const char *arg)
{
	if (strcasecmp(arg, "crc") == 0)
		c->check = DF1_CHECK_CRC;
	else if (strcasecmp(arg, "bcc") == 0)
		c->check = DF1_CHECK_BCC;
	else if (c->tool->check_auto && strcasecmp(arg, "auto") == 0)
		c->check = DF1_CHECK_AUTO;
	else
		return cli_bad_value(c, "--check", arg, c->tool->check_auto ? "crc, bcc or auto" : "crc or bcc");
	return CLI_CONTINUE;
}

/* A PLC family by any of its names, among those the tool takes (plc_ok). */
static int parse_plc(struct cli *c, const char *arg)
{
	static const char *const slc[] = { "slc", "slc500", "slc503", "slc504", "slc505", "slc5/03",
	                                   "slc5/04", "slc5/05", NULL };
	static const char *const ml[] = { "micrologix", "ml", NULL };
	static const char *const slc502[] = { "slc502", "slc501", "slc5/02", "slc5/01", NULL };
	static const char *const plc5[] = { "plc5", "plc-5", NULL };
	static const char *const plc2[] = { "plc2", "plc-2", NULL };
	static const char *const plc3[] = { "plc3", "plc-3", NULL };
	char list[80];
	int v;

	if (word_in(arg, slc))
		v = DF1_PLC_SLC;
	else if (word_in(arg, ml))
		v = DF1_PLC_MICROLOGIX;
	else if (word_in(arg, slc502))
		v = DF1_PLC_SLC502;
	else if (word_in(arg, plc5))
		v = DF1_PLC_PLC5;
	else if (word_in(arg, plc2))
		v = DF1_PLC_PLC2;
	else if (word_in(arg, plc3))
		v = DF1_PLC_PLC3;
	else
		v = -1;
	if (v < 0 || !plc_ok(c, v)) {
		plc_list(c, list, sizeof list);
		return cli_bad_value(c, "--plc", arg, list);
	}
	c->plc = (enum df1_plc)v;
	return CLI_CONTINUE;
}

/* An output format among those the tool takes (format_ok). */
static int parse_format(struct cli *c, const char *arg)
{
	int v;

	if (strcasecmp(arg, "plain") == 0)
		v = CLI_FMT_PLAIN;
	else if (strcasecmp(arg, "csv") == 0)
		v = CLI_FMT_CSV;
	else if (strcasecmp(arg, "json") == 0)
		v = CLI_FMT_JSON;
	else if (strcasecmp(arg, "influx") == 0)
		v = CLI_FMT_INFLUX;
	else if (strcasecmp(arg, "prometheus") == 0)
		v = CLI_FMT_PROMETHEUS;
	else
		v = -1;
	if (v < 0 || !format_ok(c, (enum cli_format)v))
		return cli_bad_value(c, "--format", arg, format_list_sep(c, true));
	c->format = (enum cli_format)v;
	return CLI_CONTINUE;
}

/* One common option. */
int cli_common_option(struct cli *c, enum cli_opt_id id, const char *arg)
{
	c->given |= CLI_ACCEPT(id);
	switch (id) {
	case CLI_OPT_DEVICE:
		if (!*arg)
			return cli_bad_value(c, "--device", arg, "a device path, tcp://HOST:PORT or rfc2217://HOST:PORT");
		c->device = arg;
		return CLI_CONTINUE;
	case CLI_OPT_NET:
		c->net_file = arg;
		return CLI_CONTINUE;
	case CLI_OPT_STATION:
		/* 255, a broadcast, with --duplex radio only (checked after the options) */
		return cli_parse_int(c, "--station", arg, 0, 255, &c->station);
	case CLI_OPT_SRC:
		return cli_parse_int(c, "--src", arg, 0, 254, &c->src);
	case CLI_OPT_BAUD:
		return parse_baud(c, arg);
	case CLI_OPT_PARITY:
		return parse_parity(c, arg);
	case CLI_OPT_DATA_BITS:
		return cli_parse_int(c, "--data-bits", arg, 7, 8, &c->data_bits);
	case CLI_OPT_STOP_BITS:
		return cli_parse_int(c, "--stop-bits", arg, 1, 2, &c->stop_bits);
	case CLI_OPT_HANDSHAKE:
		return parse_handshake(c, arg);
	case CLI_OPT_DUPLEX:
		return parse_duplex(c, arg);
	case CLI_OPT_FORWARD:
		if (df1_forward_parse(arg, c->forward) < 0)
			return cli_bad_value(c, "--forward", arg,
			                     "stations 0-255 and ranges A-B separated by commas, or none");
		c->have_forward = true;
		return CLI_CONTINUE;
	case CLI_OPT_CHECK:
		return parse_check(c, arg);
	case CLI_OPT_PLC:
		return parse_plc(c, arg);
	case CLI_OPT_TIMEOUT:
		return cli_parse_int(c, "--timeout", arg, 0, 360000, &c->timeout_ms);
	case CLI_OPT_CMD_TIMEOUT:
		return cli_parse_int(c, "--cmd-timeout", arg, 500, 5000, &c->cmd_timeout_ms);
	case CLI_OPT_NAK_RETRIES:
		return cli_parse_int(c, "--nak-retries", arg, 0, 10, &c->nak_retries);
	case CLI_OPT_ENQ_RETRIES:
		return cli_parse_int(c, "--enq-retries", arg, 0, 10, &c->enq_retries);
	case CLI_OPT_TX_DELAY:
		return cli_parse_int(c, "--tx-delay", arg, 0, 65535, &c->tx_delay_ms);
	case CLI_OPT_RS485:
		c->rs485 = true;
		return CLI_CONTINUE;
	case CLI_OPT_FORMAT:
		return parse_format(c, arg);
	case CLI_OPT_VERBOSE:
		c->verbose++;
		return CLI_CONTINUE;
	case CLI_OPT_QUIET:
		c->quiet = true;
		return CLI_CONTINUE;
	case CLI_OPT_COUNT_:
		break;
	default:        /* df1_set_option()'s: cli_libopts.c */
		break;
	}
	return CLI_EXIT_USAGE;
}
