/*
 * cli - the command-line code shared by df1read, df1write and df1mon (see cli.h).
 */
#include "cli.h"

#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <limits.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/time.h>
#include <unistd.h>

#include "decode.h"

/* Keys of the long-only common options. */
#define KEY_COMMON 256

struct common_opt {
	enum cli_opt_id id;
	const char *name;
	int has_arg;
	int key;               /* short letter, or KEY_COMMON + id */
	const char *arg;
	const char *help;
};

#define LONG_ONLY(id) (KEY_COMMON + (id))

static const struct common_opt common_opts[] = {
	{ CLI_OPT_DEVICE, "device", required_argument, 'd', "DEV",
	  "serial device or tcp://HOST:PORT (env DF1_DEVICE)" },
	{ CLI_OPT_NET, "net", required_argument, 'N', "FILE", "network configuration CSV" },
	{ CLI_OPT_STATION, "station", required_argument, 'a', "N", "destination station 0-254 (default 1)" },
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
	{ CLI_OPT_DUPLEX, "duplex", required_argument, LONG_ONLY(CLI_OPT_DUPLEX), "full|half",
	  "link mode (default full; half = half-duplex master)" },
	{ CLI_OPT_CHECK, "check", required_argument, LONG_ONLY(CLI_OPT_CHECK), "crc|bcc",
	  "error check (default crc)" },
	{ CLI_OPT_PLC, "plc", required_argument, LONG_ONLY(CLI_OPT_PLC), "TYPE",
	  "slc, micrologix, slc502, plc5 or plc2 (default slc)" },
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
};

#define N_COMMON (sizeof common_opts / sizeof common_opts[0])
#define KEY_HELP 'h'
#define KEY_VERSION 'V'

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

static bool accepts(const struct cli *c, enum cli_opt_id id)
{
	return (c->tool->accepts & CLI_ACCEPT(id)) != 0;
}

static bool format_ok(const struct cli *c, enum cli_format f)
{
	return f == CLI_FMT_PLAIN || (c->tool->formats & CLI_FMT_BIT(f));
}

static const char *format_list(const struct cli *c)
{
	bool csv = format_ok(c, CLI_FMT_CSV), json = format_ok(c, CLI_FMT_JSON);

	if (csv && json)
		return "plain|csv|json";
	if (json)
		return "plain|json";
	if (csv)
		return "plain|csv";
	return "plain";
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
	for (size_t i = 0; i < N_COMMON; i++) {
		const struct common_opt *o = &common_opts[i];
		char help[160];
		const char *arg = o->arg;
		if (!accepts(c, o->id))
			continue;
		snprintf(help, sizeof help, "%s", o->help);
		if (o->id == CLI_OPT_FORMAT) {
			arg = format_list(c);
			snprintf(help, sizeof help, "output format (default plain)");
		} else if (o->id == CLI_OPT_CHECK && t->check_auto) {
			arg = "crc|bcc|auto";
			snprintf(help, sizeof help, "error check (default %s)",
			         c->check == DF1_CHECK_AUTO ? "auto" : c->check == DF1_CHECK_BCC ? "bcc" : "crc");
		}
		usage_line(f, o->key, o->name, arg, o->has_arg, help);
	}
	usage_line(f, KEY_HELP, "help", NULL, no_argument, "print this help and exit");
	usage_line(f, KEY_VERSION, "version", NULL, no_argument, "print the version and exit");
	fprintf(f, "\nExit status: %s\n",
	        t->exit_text ? t->exit_text : "0 success, 1 communication or PLC error, 2 usage or configuration error.");
	if (t->help_tail)
		fprintf(f, "%s", t->help_tail);
}

int cli_parse_int(const struct cli *c, const char *opt, const char *arg, long lo, long hi, int *out)
{
	char *end;
	long v;

	errno = 0;
	v = strtol(arg, &end, 0);
	if (!*arg || *end || errno || v < lo || v > hi) {
		fprintf(stderr, "%s: %s: invalid value '%s' (expected %ld-%ld)\n", c->name, opt, arg, lo, hi);
		return CLI_EXIT_USAGE;
	}
	*out = (int)v;
	return CLI_CONTINUE;
}

static int bad_choice(const struct cli *c, const char *opt, const char *arg, const char *choices)
{
	fprintf(stderr, "%s: %s: invalid value '%s' (expected %s)\n", c->name, opt, arg, choices);
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
	return bad_choice(c, "--baud", arg, "1200, 2400, 4800, 9600, 19200, 38400, 57600 or 115200");
}

/* One common option. */
static int common_option(struct cli *c, enum cli_opt_id id, const char *arg)
{
	static const char *const yes[] = { "yes", "y", "on", "1", "true", "rtscts", "rts/cts", NULL };
	static const char *const no[] = { "no", "n", "off", "0", "false", "none", NULL };
	int v;

	c->given |= CLI_ACCEPT(id);
	switch (id) {
	case CLI_OPT_DEVICE:
		if (!*arg)
			return bad_choice(c, "--device", arg, "a device path or tcp://HOST:PORT");
		c->device = arg;
		return CLI_CONTINUE;
	case CLI_OPT_NET:
		c->net_file = arg;
		return CLI_CONTINUE;
	case CLI_OPT_STATION:
		return cli_parse_int(c, "--station", arg, 0, 254, &c->station);
	case CLI_OPT_SRC:
		return cli_parse_int(c, "--src", arg, 0, 254, &c->src);
	case CLI_OPT_BAUD:
		return parse_baud(c, arg);
	case CLI_OPT_PARITY:
		if (strcasecmp(arg, "none") == 0 || strcasecmp(arg, "n") == 0)
			c->parity = 'N';
		else if (strcasecmp(arg, "even") == 0 || strcasecmp(arg, "e") == 0)
			c->parity = 'E';
		else if (strcasecmp(arg, "odd") == 0 || strcasecmp(arg, "o") == 0)
			c->parity = 'O';
		else
			return bad_choice(c, "--parity", arg, "none, even or odd");
		return CLI_CONTINUE;
	case CLI_OPT_DATA_BITS:
		return cli_parse_int(c, "--data-bits", arg, 7, 8, &c->data_bits);
	case CLI_OPT_STOP_BITS:
		return cli_parse_int(c, "--stop-bits", arg, 1, 2, &c->stop_bits);
	case CLI_OPT_HANDSHAKE:
		if (!arg || word_in(arg, yes))
			c->handshake = true;
		else if (word_in(arg, no))
			c->handshake = false;
		else
			return bad_choice(c, "--handshake", arg, "yes or no");
		return CLI_CONTINUE;
	case CLI_OPT_DUPLEX:
		if (strcasecmp(arg, "full") == 0)
			c->half_duplex = false;
		else if (strcasecmp(arg, "half") == 0)
			c->half_duplex = true;
		else
			return bad_choice(c, "--duplex", arg, "full or half");
		return CLI_CONTINUE;
	case CLI_OPT_CHECK:
		if (strcasecmp(arg, "crc") == 0)
			c->check = DF1_CHECK_CRC;
		else if (strcasecmp(arg, "bcc") == 0)
			c->check = DF1_CHECK_BCC;
		else if (c->tool->check_auto && strcasecmp(arg, "auto") == 0)
			c->check = DF1_CHECK_AUTO;
		else
			return bad_choice(c, "--check", arg, c->tool->check_auto ? "crc, bcc or auto" : "crc or bcc");
		return CLI_CONTINUE;
	case CLI_OPT_PLC: {
		static const char *const slc[] = { "slc", "slc500", "slc503", "slc504", "slc505", "slc5/03",
		                                   "slc5/04", "slc5/05", NULL };
		static const char *const ml[] = { "micrologix", "ml", NULL };
		static const char *const slc502[] = { "slc502", "slc501", "slc5/02", "slc5/01", NULL };
		static const char *const plc5[] = { "plc5", "plc-5", NULL };
		static const char *const plc2[] = { "plc2", "plc-2", NULL };
		if (word_in(arg, slc))
			c->plc = DF1_PLC_SLC;
		else if (word_in(arg, ml))
			c->plc = DF1_PLC_MICROLOGIX;
		else if (word_in(arg, slc502))
			c->plc = DF1_PLC_SLC502;
		else if (word_in(arg, plc5))
			c->plc = DF1_PLC_PLC5;
		else if (word_in(arg, plc2))
			c->plc = DF1_PLC_PLC2;
		else
			return bad_choice(c, "--plc", arg, "slc, micrologix, slc502, plc5 or plc2");
		return CLI_CONTINUE;
	}
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
		if (strcasecmp(arg, "plain") == 0)
			v = CLI_FMT_PLAIN;
		else if (strcasecmp(arg, "csv") == 0)
			v = CLI_FMT_CSV;
		else if (strcasecmp(arg, "json") == 0)
			v = CLI_FMT_JSON;
		else
			v = -1;
		if (v < 0 || !format_ok(c, (enum cli_format)v)) {
			const char *list = format_list(c);
			return bad_choice(c, "--format", arg,
			                  strcmp(list, "plain|csv|json") == 0 ? "plain, csv or json"
			                  : strcmp(list, "plain|json") == 0   ? "plain or json"
			                  : strcmp(list, "plain|csv") == 0    ? "plain or csv"
			                                                      : "plain");
		}
		c->format = (enum cli_format)v;
		return CLI_CONTINUE;
	case CLI_OPT_VERBOSE:
		c->verbose++;
		return CLI_CONTINUE;
	case CLI_OPT_QUIET:
		c->quiet = true;
		return CLI_CONTINUE;
	case CLI_OPT_COUNT_:
		break;
	}
	return CLI_EXIT_USAGE;
}

/* ---- network file ---- */

struct net_issue_ctx {
	const struct cli *c;
	int count;
};

static void net_issue(void *user, const struct df1_config_issue *issue)
{
	struct net_issue_ctx *n = user;
	const struct df1_catalog_entry *e = df1_catalog_by_id(issue->catalog_id);

	n->count++;
	fprintf(stderr, "%s: %s: ", n->c->name, n->c->net_file);
	if (issue->line > 0)
		fprintf(stderr, "line %d: ", issue->line);
	if (e)
		fprintf(stderr, "[%d] %s: %s\n", issue->catalog_id, e->mnemonic, issue->text);
	else if (issue->catalog_id)
		fprintf(stderr, "[%d]: %s\n", issue->catalog_id, issue->text);
	else
		fprintf(stderr, "%s\n", issue->text);
}

/* Load -N FILE and take its values for every option not given on the command line. */
static int load_net(struct cli *c)
{
	struct net_issue_ctx n = { c, 0 };
	const struct df1_net_config *k = &c->net;
	int r;

	df1_net_config_defaults(&c->net);
	r = df1_net_config_load(c->net_file, &c->net, net_issue, &n);
	if (r < 0 || n.count) {
		if (!n.count) {
			char tag[64];
			cli_error_tag(r, df1_error_catalog_id(r), tag, sizeof tag);
			fprintf(stderr, "%s: %s: %s: %s%s%s\n", c->name, c->net_file, tag, df1_strerror(r),
			        r == DF1_E_SYS && errno ? ": " : "", r == DF1_E_SYS && errno ? strerror(errno) : "");
		}
		return CLI_EXIT_USAGE;
	}
	c->have_net = true;
#define TAKE(id, field, value) do { if (!(c->given & CLI_ACCEPT(id))) c->field = (value); } while (0)
	TAKE(CLI_OPT_SRC, src, k->station);
	TAKE(CLI_OPT_BAUD, baud, k->baud);
	TAKE(CLI_OPT_DATA_BITS, data_bits, k->data_bits);
	TAKE(CLI_OPT_STOP_BITS, stop_bits, k->stop_bits);
	TAKE(CLI_OPT_PARITY, parity, k->parity);
	TAKE(CLI_OPT_HANDSHAKE, handshake, k->handshake);
	TAKE(CLI_OPT_DUPLEX, half_duplex, k->duplex_half);
	TAKE(CLI_OPT_PLC, plc, k->plc);
	TAKE(CLI_OPT_TIMEOUT, timeout_ms, k->timeout_ms);
	TAKE(CLI_OPT_CMD_TIMEOUT, cmd_timeout_ms, k->cmd_timeout_ms);
	TAKE(CLI_OPT_NAK_RETRIES, nak_retries, k->nak_retries);
	TAKE(CLI_OPT_ENQ_RETRIES, enq_retries, k->enq_retries);
	TAKE(CLI_OPT_TX_DELAY, tx_delay_ms, k->tx_delay_ms);
	/* a decoder's AUTO default is kept: the file's check only replaces a link default */
	if (!(c->given & CLI_ACCEPT(CLI_OPT_CHECK)) && c->check != DF1_CHECK_AUTO)
		c->check = k->check;
#undef TAKE
	return CLI_CONTINUE;
}

/* ---- argv ---- */

int cli_parse(struct cli *c, int argc, char **argv, void *user)
{
	const struct cli_tool *t = c->tool;
	size_t n_extra = 0, n = 0;
	struct option *lo;
	char shorts[256];
	size_t sp = 0;
	int r = CLI_CONTINUE, key, idx;

	if (t->extra)
		while (t->extra[n_extra].name)
			n_extra++;
	lo = calloc(N_COMMON + n_extra + 3, sizeof *lo);
	if (!lo) {
		fprintf(stderr, "%s: out of memory\n", c->name);
		return CLI_EXIT_FAIL;
	}
	shorts[sp++] = ':';   /* report a missing argument as ':' */
#define ADD_SHORT(k, ha) do {                                                       \
		if ((k) > 0 && (k) < 256 && sp + 3 < sizeof shorts) {                   \
			shorts[sp++] = (char)(k);                                       \
			if ((ha) != no_argument) shorts[sp++] = ':';                    \
			if ((ha) == optional_argument) shorts[sp++] = ':';              \
		}                                                                       \
	} while (0)
	for (size_t i = 0; i < N_COMMON; i++) {
		const struct common_opt *o = &common_opts[i];
		if (!accepts(c, o->id))
			continue;
		lo[n++] = (struct option){ o->name, o->has_arg, NULL, o->key };
		ADD_SHORT(o->key, o->has_arg);
	}
	for (size_t i = 0; i < n_extra; i++) {
		const struct cli_extra_opt *e = &t->extra[i];
		lo[n++] = (struct option){ e->name, e->has_arg, NULL, e->key };
		ADD_SHORT(e->key, e->has_arg);
	}
	lo[n++] = (struct option){ "help", no_argument, NULL, KEY_HELP };
	lo[n++] = (struct option){ "version", no_argument, NULL, KEY_VERSION };
	ADD_SHORT(KEY_HELP, no_argument);
	ADD_SHORT(KEY_VERSION, no_argument);
	shorts[sp] = 0;
#undef ADD_SHORT

	opterr = 0;
	optind = 1;
	while (r == CLI_CONTINUE && (key = getopt_long(argc, argv, shorts, lo, &idx)) != -1) {
		const char *opt_text = argv[optind - 1];
		bool done = false;

		if (key == '?') {
			if (optopt > 0 && optopt < 256)
				r = cli_usage_error(c, "unknown option '-%c'", optopt);
			else
				r = cli_usage_error(c, "unknown option '%s'", opt_text);
			break;
		}
		if (key == ':') {
			if (optopt > 0 && optopt < 256 && opt_text[1] != '-')
				r = cli_usage_error(c, "option '-%c' needs a value", optopt);
			else
				r = cli_usage_error(c, "option '%s' needs a value", opt_text);
			break;
		}
		if (key == KEY_HELP) {
			cli_usage(c, stdout);
			r = fflush(stdout) == 0 ? CLI_EXIT_OK : CLI_EXIT_FAIL;
			break;
		}
		if (key == KEY_VERSION) {
			printf("%s (libdf1) %s\n", c->name, DF1_VERSION_STRING);
			r = fflush(stdout) == 0 ? CLI_EXIT_OK : CLI_EXIT_FAIL;
			break;
		}
		for (size_t i = 0; i < N_COMMON && !done; i++) {
			if (common_opts[i].key == key && accepts(c, common_opts[i].id)) {
				r = common_option(c, common_opts[i].id, optarg);
				done = true;
			}
		}
		if (!done) {
			if (t->on_extra)
				r = t->on_extra(c, key, optarg, user);
			else
				r = cli_usage_error(c, "unknown option '%s'", opt_text);
		}
	}
	free(lo);
	if (r != CLI_CONTINUE)
		return r;
	c->argc = argc - optind;
	c->argv = argv + optind;
	if (c->quiet && c->verbose)
		return cli_usage_error(c, "-q and -v cannot be used together");
	if (c->net_file && (r = load_net(c)) != CLI_CONTINUE)
		return r;
	if (accepts(c, CLI_OPT_DEVICE) && !c->device) {
		/* -d, then a Com_Port the file names, then DF1_DEVICE, then the
		 * file's default port (Com_Port 1, /dev/ttyS0) */
		const char *env = getenv("DF1_DEVICE");
		if (c->have_net && c->net.port_given)
			c->device = c->net.port;
		else if (env && *env)
			c->device = env;
		else if (c->have_net && c->net.port[0])
			c->device = c->net.port;
	}
	return CLI_CONTINUE;
}

void cli_cleanup(struct cli *c)
{
	df1_decoder_free(c->trace_dec[0]);
	df1_decoder_free(c->trace_dec[1]);
	c->trace_dec[0] = c->trace_dec[1] = NULL;
	free(c->trace_ctx);
	c->trace_ctx = NULL;
}

/* ---- errors ---- */

int cli_exit_status(int err)
{
	switch (err) {
	case DF1_OK:
		return CLI_EXIT_OK;
	case DF1_E_INVAL:
	case DF1_E_ADDR_SYNTAX:
	case DF1_E_ADDR_RANGE:
	case DF1_E_TYPE:
	case DF1_E_RANGE:
	case DF1_E_CONFIG:
		return CLI_EXIT_USAGE;
	default:
		return CLI_EXIT_FAIL;
	}
}

void cli_error_tag(int err, int catalog_id, char *buf, size_t cap)
{
	const struct df1_catalog_entry *e = catalog_id ? df1_catalog_by_id(catalog_id) : NULL;

	if (e)
		snprintf(buf, cap, "[%d] %s", catalog_id, e->mnemonic);
	else
		snprintf(buf, cap, "%s", df1_errname(err));
}

/* Tag and text of err, with the handle's detail when it describes the same error. */
static void error_parts(const df1_t *h, int err, char *tag, size_t tcap, char *text, size_t xcap)
{
	const struct df1_error_detail *d = h ? df1_last_error(h) : NULL;
	bool same = d && d->code == err;
	int id = same && d->catalog_id ? d->catalog_id : df1_error_catalog_id(err);

	cli_error_tag(err, id, tag, tcap);
	if (same && d->message[0])
		snprintf(text, xcap, "%s", d->message);
	else
		snprintf(text, xcap, "%s", df1_strerror(err));
	if (same && d->sys_errno) {
		const char *sys = strerror(d->sys_errno);
		size_t len = strlen(text);
		if (!strstr(text, sys) && len < xcap)
			snprintf(text + len, xcap - len, ": %s", sys);
	}
}

/* Length of the "ADDR: " the library puts in front of a message about an address
 * of the same file as address (as typed: any case, "B3/21" for "B3:1/5"; or the
 * start of the block a tool read it with), or 0. */
static size_t address_prefix(const char *text, const char *address)
{
	const char *colon = text;
	char head[CLI_ADDR_TEXT_MAX];
	struct df1_addr a, b;
	size_t len;

	/* the address's own ':' (N7:0) is followed by a digit, the prefix's by a blank */
	while ((colon = strchr(colon, ':')) != NULL && colon[1] != ' ')
		colon++;
	if (!colon)
		return 0;
	len = (size_t)(colon - text);
	if (len == 0 || len >= sizeof head)
		return 0;
	memcpy(head, text, len);
	head[len] = '\0';
	if (strcasecmp(head, address) == 0)
		return len + 2;
	if (df1_addr_parse(head, &a) < 0 || df1_addr_parse(address, &b) < 0)
		return 0;
	if (a.type != b.type || a.file != b.file || a.ascii[0] || b.ascii[0])
		return 0;
	return len + 2;
}

int cli_report(const char *tool, const char *address, int station, const df1_t *h, int err)
{
	char tag[96], text[256];

	const char *t = text;

	error_parts(h, err, tag, sizeof tag, text, sizeof text);
	/* the detail may start with the address we print anyway */
	if (address && *address)
		t += address_prefix(t, address);
	fprintf(stderr, "%s: ", tool);
	if (address)
		fprintf(stderr, "%s: ", address);
	if (station >= 0)
		fprintf(stderr, "station %d: ", station);
	fprintf(stderr, "%s: %s\n", tag, t);
	return cli_exit_status(err);
}

void cli_error_text(const df1_t *h, int err, char *buf, size_t cap)
{
	char tag[96], text[256];

	error_parts(h, err, tag, sizeof tag, text, sizeof text);
	snprintf(buf, cap, "%s: %s", tag, text);
}

/* ---- the handle ---- */

void cli_log(void *user, int catalog_id, enum df1_severity sev, const char *text)
{
	const struct cli *c = user;
	const struct df1_catalog_entry *e = df1_catalog_by_id(catalog_id);

	if (sev == DF1_SEV_COUNTER || c->quiet || c->verbose < 1)
		return;
	if (e)
		fprintf(stderr, "%s: [%d] %s: %s\n", c->name, catalog_id, e->mnemonic, text ? text : "");
	else
		fprintf(stderr, "%s: %s\n", c->name, text ? text : "");
}

void cli_trace(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us)
{
	struct cli *c = user;
	const char *dname = dir == DF1_DIR_TX ? "tx" : "rx";
	char prefix[64], hex[3 * 32 + 1];
	uint64_t rel;
	struct decode_where w;
	struct df1_decoder *d;
	size_t pos = 0;

	if (c->verbose < 2 || !bytes)
		return;
	if (!c->trace_have_t0) {
		c->trace_t0 = t_us;
		c->trace_have_t0 = true;
	}
	rel = t_us >= c->trace_t0 ? t_us - c->trace_t0 : 0;
	/* the bytes, 32 a line */
	for (size_t i = 0; i < n; i += 32) {
		size_t k = n - i < 32 ? n - i : 32;
		cli_hex(bytes + i, k, hex, sizeof hex);
		fprintf(stderr, "%s: %llu.%06llu %s %s\n", c->name, (unsigned long long)(rel / 1000000),
		        (unsigned long long)(rel % 1000000), dname, hex);
	}
	/* and every symbol they complete */
	if (!c->trace_ctx) {
		c->trace_ctx = malloc(sizeof *c->trace_ctx);
		if (!c->trace_ctx)
			return;
		decode_ctx_init(c->trace_ctx, CLI_FMT_PLAIN);
		c->trace_ctx->show_time = true;
		c->trace_ctx->show_dir = true;
	}
	d = c->trace_dec[dir == DF1_DIR_TX];
	if (!d) {
		if (df1_decoder_new(&d, c->check) < 0)
			return;
		df1_decoder_set_half_duplex(d, c->half_duplex);
		c->trace_dec[dir == DF1_DIR_TX] = d;
	}
	memset(&w, 0, sizeof w);
	w.index = c->trace_n;
	w.has_time = true;
	w.rel_sec = (int64_t)(rel / 1000000);
	w.rel_usec = (int32_t)(rel % 1000000);
	w.dir = dname;
	snprintf(prefix, sizeof prefix, "%s: ", c->name);
	while (pos < n) {
		struct df1_symbol s;
		size_t used = df1_decoder_feed(d, bytes + pos, n - pos, &s);
		pos += used;
		if (s.kind != DF1_SYM_NONE) {
			w.index = ++c->trace_n;
			decode_print(c->trace_ctx, stderr, prefix, &w, &s);
		}
		if (used == 0)
			break;
	}
}

/* Report a setter's failure as a configuration error. */
static int set_failed(const struct cli *c, df1_t *h, const char *what, int r)
{
	char tag[96], text[256];

	error_parts(h, r, tag, sizeof tag, text, sizeof text);
	fprintf(stderr, "%s: %s: %s: %s\n", c->name, what, tag, text);
	return CLI_EXIT_USAGE;
}

int cli_open(struct cli *c, df1_t **out)
{
	df1_t *h = NULL;
	int r, fd;

	*out = NULL;
	if (!c->device || !*c->device) {
		fprintf(stderr, "%s: no device: use -d DEV, -N FILE or set DF1_DEVICE\n", c->name);
		return CLI_EXIT_USAGE;
	}
	/* the tools that talk are masters (or peers): a network file for a slave
	 * module does not describe them, unless --duplex says how to run */
	if (c->have_net && c->net.mode == DF1_MODE_SLAVE && !(c->given & CLI_ACCEPT(CLI_OPT_DUPLEX))) {
		const struct df1_catalog_entry *e = df1_catalog_by_id(2554);
		fprintf(stderr, "%s: %s: [2554] %s: Unsupported Driver Mode (Slave), Supported Mode(s): "
		        "Master, Peer (or give --duplex)\n", c->name, c->net_file,
		        e ? e->mnemonic : "CRT_UNSUPPORTED_MODE");
		return CLI_EXIT_USAGE;
	}
	r = df1_new(&h);
	if (r < 0) {
		fprintf(stderr, "%s: %s: %s\n", c->name, df1_errname(r), df1_strerror(r));
		return CLI_EXIT_FAIL;
	}
	if (c->have_net && (r = df1_apply_net_config(h, &c->net)) < 0) {
		set_failed(c, h, c->net_file, r);
		df1_free(h);
		return CLI_EXIT_USAGE;
	}
#define SET(what, call) do { if ((r = (call)) < 0) { set_failed(c, h, what, r); df1_free(h); return CLI_EXIT_USAGE; } } while (0)
	SET("serial settings", df1_set_serial(h, c->baud, c->data_bits, c->parity, c->stop_bits));
	SET("--handshake", df1_set_handshake(h, c->handshake));
	SET("--duplex", df1_set_duplex(h, c->half_duplex ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX));
	if (c->check != DF1_CHECK_AUTO)
		SET("--check", df1_set_check(h, c->check));
	SET("--src", df1_set_station(h, c->src));
	SET("--plc", df1_set_plc(h, c->plc));
	SET("--timeout", df1_set_timeout_ms(h, c->timeout_ms));
	SET("--cmd-timeout", df1_set_cmd_timeout_ms(h, c->cmd_timeout_ms));
	SET("--nak-retries/--enq-retries", df1_set_retries(h, c->nak_retries, c->enq_retries));
	SET("--tx-delay", df1_set_tx_delay_ms(h, c->tx_delay_ms));
	if (c->rs485)
		SET("--rs485", df1_set_option(h, DF1_OPT_RS485, 1));
#undef SET
	if (!c->quiet && c->verbose >= 1)
		df1_set_log(h, cli_log, c);
	if (!c->quiet && c->verbose >= 2)
		df1_set_trace(h, cli_trace, c);
	fd = cli_signal_fd();
	if (fd >= 0)
		df1_set_cancel_fd(h, fd);
	r = df1_open(h, c->device);
	if (r < 0) {
		char tag[96], text[256];
		size_t tl, dl = strlen(c->device);
		error_parts(h, r, tag, sizeof tag, text, sizeof text);
		/* "no such device: /dev/x" after "/dev/x: " says it twice */
		tl = strlen(text);
		if (tl > dl + 2 && strcmp(text + tl - dl, c->device) == 0 && text[tl - dl - 2] == ':')
			text[tl - dl - 2] = 0;
		fprintf(stderr, "%s: %s: %s: %s\n", c->name, c->device, tag, text);
		df1_free(h);
		return r == DF1_E_INVAL || r == DF1_E_CONFIG ? CLI_EXIT_USAGE : CLI_EXIT_FAIL;
	}
	*out = h;
	return CLI_EXIT_OK;
}

void cli_close(struct cli *c, df1_t *h)
{
	if (h) {
		df1_close(h);
		df1_free(h);
	}
	cli_cleanup(c);
}

/* ---- addresses ---- */

bool cli_is_tcr(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R;
}

bool cli_is_io(enum df1_file_type t)
{
	return t == DF1_FT_I || t == DF1_FT_O;
}

bool cli_addr_step(const struct df1_addr *a, size_t i, struct df1_addr *out)
{
	char buf[CLI_ADDR_TEXT_MAX];

	*out = *a;
	out->ascii[0] = '\0';
	if (i > 1000000)
		return false;
	if (a->bit != DF1_ADDR_NONE) {
		long g = (long)a->bit + (long)i;
		long nb = a->type == DF1_FT_L ? 32 : 16;

		if (cli_is_tcr(a->type)) {
			out->bit = (int)g;
		} else if (cli_is_io(a->type) && a->sub != DF1_ADDR_NONE) {
			out->sub = a->sub + (int)(g / nb);
			out->bit = (int)(g % nb);
		} else {
			out->element = a->element + (int)(g / nb);
			out->bit = (int)(g % nb);
		}
	} else if (cli_is_io(a->type) && a->sub != DF1_ADDR_NONE) {
		out->sub = a->sub + (int)i;
	} else {
		out->element = a->element + (int)i;
	}
	return df1_addr_format(out, buf, sizeof buf) > 0;
}

int cli_address_error(const struct cli *c, int item, const char *text, int err, size_t n)
{
	int id = err == DF1_E_ADDR_RANGE ? 2504 : 2503;
	const struct df1_catalog_entry *e = df1_catalog_by_id(id);

	fprintf(stderr, "%s: %s: [%d] %s: Item: %d, ", c->name, text, id, e ? e->mnemonic : "?", item);
	if (id == 2504)
		fprintf(stderr, "Address is out of range (%s, len=%zu)\n", text, n);
	else
		fprintf(stderr, "Invalid Address Syntax (%s)\n", text);
	return CLI_EXIT_USAGE;
}

/* ---- signals ---- */

volatile sig_atomic_t cli_stop;
static volatile sig_atomic_t stop_signal;
static int sig_pipe[2] = { -1, -1 };

static void on_signal(int sig)
{
	int saved = errno;

	cli_stop = 1;
	stop_signal = sig;
	if (sig_pipe[1] >= 0) {
		ssize_t w = write(sig_pipe[1], "s", 1);
		(void)w;
	}
	errno = saved;
}

int cli_signals_install(void)
{
	struct sigaction sa;

	if (sig_pipe[0] < 0 && pipe2(sig_pipe, O_CLOEXEC | O_NONBLOCK) < 0) {
		sig_pipe[0] = sig_pipe[1] = -1;
		return -1;
	}
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	/* no SA_RESTART: blocking calls return EINTR; a second signal kills as usual */
	sa.sa_flags = SA_RESETHAND;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	sa.sa_handler = SIG_IGN;
	sa.sa_flags = 0;
	sigaction(SIGPIPE, &sa, NULL);
	return sig_pipe[0];
}

int cli_stop_after_ms(long ms)
{
	struct sigaction sa;
	struct itimerval it;

	if (ms <= 0) {
		errno = EINVAL;
		return -1;
	}
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	if (sigaction(SIGALRM, &sa, NULL) < 0)
		return -1;
	memset(&it, 0, sizeof it);
	it.it_value.tv_sec = ms / 1000;
	it.it_value.tv_usec = (ms % 1000) * 1000;
	return setitimer(ITIMER_REAL, &it, NULL);
}

int cli_signal_fd(void)
{
	return sig_pipe[0];
}

int cli_stop_signal(void)
{
	return (int)stop_signal;
}

const char *cli_signal_name(int sig)
{
	return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal";
}

void cli_raise_stop_signal(void)
{
	int sig = cli_stop ? cli_stop_signal() : 0;

	if (sig) {
		fflush(stderr);
		raise(sig);
	}
}

/* ---- JSON, CSV, hex ---- */

/* Length of a valid UTF-8 sequence at s (at most n bytes), or 0. */
static size_t utf8_len(const unsigned char *s, size_t n)
{
	size_t len;
	uint32_t cp;

	if (s[0] < 0x80)
		return 1;
	if (s[0] >= 0xC2 && s[0] <= 0xDF) {
		len = 2;
		cp = s[0] & 0x1F;
	} else if (s[0] >= 0xE0 && s[0] <= 0xEF) {
		len = 3;
		cp = s[0] & 0x0F;
	} else if (s[0] >= 0xF0 && s[0] <= 0xF4) {
		len = 4;
		cp = s[0] & 0x07;
	} else {
		return 0;
	}
	if (len > n)
		return 0;
	for (size_t i = 1; i < len; i++) {
		if ((s[i] & 0xC0) != 0x80)
			return 0;
		cp = (cp << 6) | (s[i] & 0x3F);
	}
	if ((len == 3 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
	    (len == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
		return 0;
	return len;
}

void cli_json_string_n(FILE *f, const char *s, size_t n)
{
	const unsigned char *p = (const unsigned char *)s;
	size_t i = 0, k;

	fputc('"', f);
	while (i < n) {
		unsigned char ch = p[i];
		switch (ch) {
		case '"': fputs("\\\"", f); i++; continue;
		case '\\': fputs("\\\\", f); i++; continue;
		case '\n': fputs("\\n", f); i++; continue;
		case '\r': fputs("\\r", f); i++; continue;
		case '\t': fputs("\\t", f); i++; continue;
		case '\b': fputs("\\b", f); i++; continue;
		case '\f': fputs("\\f", f); i++; continue;
		default: break;
		}
		if (ch < 0x20 || ch == 0x7F) {
			fprintf(f, "\\u%04x", ch);
			i++;
			continue;
		}
		k = utf8_len(p + i, n - i);
		if (k == 0) {
			/* not UTF-8: take the byte as Latin-1 */
			fprintf(f, "\\u%04x", ch);
			i++;
			continue;
		}
		fwrite(p + i, 1, k, f);
		i += k;
	}
	fputc('"', f);
}

void cli_json_string(FILE *f, const char *s)
{
	cli_json_string_n(f, s ? s : "", s ? strlen(s) : 0);
}

void cli_csv_quoted(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		if (*s == '"')
			fputc('"', f);
		fputc(*s, f);
	}
	fputc('"', f);
}

void cli_csv_field(FILE *f, const char *s)
{
	size_t n;

	if (!s)
		s = "";
	n = strlen(s);
	if (!strpbrk(s, ",\"\r\n") && !(n && (s[0] == ' ' || s[n - 1] == ' ')))
		fputs(s, f);
	else
		cli_csv_quoted(f, s);
}

size_t cli_hex(const uint8_t *b, size_t n, char *buf, size_t cap)
{
	static const char digits[] = "0123456789ABCDEF";
	size_t o = 0;

	if (cap == 0)
		return 0;
	for (size_t i = 0; i < n && o + 3 <= cap; i++) {
		if (i) {
			if (o + 4 > cap)
				break;
			buf[o++] = ' ';
		}
		buf[o++] = digits[b[i] >> 4];
		buf[o++] = digits[b[i] & 15];
	}
	buf[o] = 0;
	return o;
}

static int hexval(int ch)
{
	if (ch >= '0' && ch <= '9')
		return ch - '0';
	if (ch >= 'a' && ch <= 'f')
		return ch - 'a' + 10;
	if (ch >= 'A' && ch <= 'F')
		return ch - 'A' + 10;
	return -1;
}

long cli_parse_hex(const char *text, uint8_t *out, size_t cap, size_t *bad_at)
{
	size_t i = 0, n = 0;

	while (text[i]) {
		size_t start, digits;

		if (strchr(" \t\r\n:,-", text[i])) {
			i++;
			continue;
		}
		/* one token: [0x]HEXHEX... */
		start = i;
		if (text[i] == '0' && (text[i + 1] == 'x' || text[i + 1] == 'X') && hexval(text[i + 2]) >= 0)
			i += 2;
		digits = i;
		while (text[i] && hexval((unsigned char)text[i]) >= 0)
			i++;
		if (text[i] && !strchr(" \t\r\n:,-", text[i])) {
			if (bad_at)
				*bad_at = i;
			return -1;
		}
		if ((i - digits) % 2 != 0 || i == digits) {
			if (bad_at)
				*bad_at = start;
			return -1;
		}
		for (size_t k = digits; k < i; k += 2) {
			if (n >= cap) {
				if (bad_at)
					*bad_at = k;
				return -1;
			}
			out[n++] = (uint8_t)(hexval((unsigned char)text[k]) << 4 | hexval((unsigned char)text[k + 1]));
		}
	}
	return (long)n;
}
