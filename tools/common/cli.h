/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli - the command-line code shared by df1read, df1write, df1mon and df1sim
 * (doc/ARCHITECTURE.md 8, doc/HACKING.md 7.9): the common options, parsed with getopt_long
 * from one table; per-tool option sets and extra options; building and
 * opening the handle; error reports in the catalog format; -v logging and
 * -vv frame traces on stderr; SIGINT/SIGTERM through a self-pipe; operand
 * addresses (value i of an operand, address errors); and, through cli_text.h,
 * JSON and CSV quoting and hex. The code is in tools/common/cli_*.c, one file per
 * part (cli_int.h lists them); cli_handle.c's -vv trace is the one user of
 * tools/common/decode.h, which itself needs only cli_text.h.
 *
 * Tools use only include/df1.h. Messages go to stderr as "tool: ...";
 * stdout carries data only. Exit status: 0 success, 1 communication or PLC
 * error, 2 usage, address or configuration error.
 */
#ifndef DF1_TOOLS_CLI_H
#define DF1_TOOLS_CLI_H

#include <getopt.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include "df1.h"
#include "common/cli_text.h"

struct decode_ctx; /* tools/common/decode.h */

#define CLI_EXIT_OK 0
#define CLI_EXIT_FAIL 1    /* communication or PLC error, bad check */
#define CLI_EXIT_USAGE 2   /* usage, address, configuration, unreadable input */
#define CLI_CONTINUE (-1)  /* cli_parse: go on and run the tool */

/* The common options. A tool accepts a set of them (bit (1u << id)). */
enum cli_opt_id {
	CLI_OPT_DEVICE = 0,  /* -d/--device DEV (env DF1_DEVICE) */
	CLI_OPT_NET,         /* -N/--net FILE */
	CLI_OPT_STATION,     /* -a/--station N */
	CLI_OPT_SRC,         /* --src N */
	CLI_OPT_BAUD,        /* -b/--baud N */
	CLI_OPT_PARITY,      /* -P/--parity none|even|odd */
	CLI_OPT_DATA_BITS,   /* --data-bits N */
	CLI_OPT_STOP_BITS,   /* --stop-bits N */
	CLI_OPT_HANDSHAKE,   /* --handshake[=yes|no] */
	CLI_OPT_DUPLEX,      /* --duplex full|half */
	CLI_OPT_CHECK,       /* --check crc|bcc (|auto when the tool allows it) */
	CLI_OPT_PLC,         /* --plc slc|micrologix|slc502|plc5|plc2|plc3 */
	CLI_OPT_TIMEOUT,     /* -o/--timeout MS */
	CLI_OPT_CMD_TIMEOUT, /* --cmd-timeout MS */
	CLI_OPT_NAK_RETRIES, /* --nak-retries N */
	CLI_OPT_ENQ_RETRIES, /* --enq-retries N */
	CLI_OPT_TX_DELAY,    /* --tx-delay MS */
	CLI_OPT_RS485,       /* --rs485 */
	CLI_OPT_FORMAT,      /* -f/--format plain|csv|json */
	CLI_OPT_VERBOSE,     /* -v (repeatable) */
	CLI_OPT_QUIET,       /* -q */
	/* the link and PLC options of df1_set_option(3) (cli_opts.c's table maps them) */
	CLI_OPT_HD_BCC,           /* --hd-bcc stn|stx            DF1_OPT_HD_BCC_INCLUDES_STX */
	CLI_OPT_PLC5_FLOAT,       /* --plc5-float plain|swapped  DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED */
	CLI_OPT_PLC5_TIMER_WORDS, /* --plc5-timer-words 3|5      DF1_OPT_PLC5_TIMER_WORDS */
	CLI_OPT_PLC2_ADDR,        /* --plc2-addr bytes|words     DF1_OPT_PLC2_WORD_ADDR */
	CLI_OPT_SLC_IO_CODES,     /* --slc-io-codes 8b|82        DF1_OPT_SLC_IO_CODES_82 */
	CLI_OPT_MAX_PACKET,       /* --max-packet BYTES          DF1_OPT_MAX_PACKET */
	CLI_OPT_DUP_DETECT,       /* --duplicate-detect yes|no   DF1_OPT_DUPLICATE_DETECT */
	CLI_OPT_EMBEDDED,         /* --embedded-responses yes|no DF1_OPT_EMBEDDED_RESPONSES */
	CLI_OPT_NAK_0F,           /* --nak-0f yes|no             DF1_OPT_ACCEPT_NAK_0F */
	CLI_OPT_EOT_BCC,          /* --eot-bcc yes|no            DF1_OPT_EOT_WITH_BCC */
	CLI_OPT_ECHO_DISCARD,     /* --echo-discard              DF1_OPT_ECHO_DISCARD */
	CLI_OPT_POLL_TIMEOUT,     /* --poll-timeout MS           DF1_OPT_POLL_TIMEOUT_MS */
	CLI_OPT_OUTSTANDING,      /* --outstanding N             DF1_OPT_MAX_OUTSTANDING */
	CLI_OPT_EIP_CONNECTED,    /* --eip-connected             DF1_OPT_EIP_CONNECTED */
	CLI_OPT_LOW_LATENCY,      /* --low-latency yes|no        DF1_OPT_LOW_LATENCY */
	CLI_OPT_ROUTE,            /* --route yes|no              DF1_OPT_ROUTE */
	CLI_OPT_APP_RETRIES,      /* --app-retries N             DF1_OPT_APP_RETRIES */
	CLI_OPT_RADIO_DUP,        /* --dup-detect yes|no|auto    DF1_OPT_RADIO_DUP_DETECT */
	CLI_OPT_RADIO_RTS,        /* --radio-rts yes|no          DF1_OPT_RADIO_RTS_CTS */
	CLI_OPT_RTS_SEND,         /* --rts-send-delay MS         DF1_OPT_RTS_SEND_DELAY_MS */
	CLI_OPT_RTS_OFF,          /* --rts-off-delay MS          DF1_OPT_RTS_OFF_DELAY_MS */
	CLI_OPT_DCD_WAIT,         /* --dcd-wait MS               DF1_OPT_DCD_WAIT_MS */
	/* not in CLI_ACCEPT_LINK: the tools where a node listens take it */
	CLI_OPT_FORWARD,          /* --forward LIST              df1_set_forward(3) */
	CLI_OPT_COUNT_
};

/* 64 bits, whatever long is: there are more than 32 common options */
#define CLI_ACCEPT(id) (UINT64_C(1) << (id))
_Static_assert(CLI_OPT_COUNT_ <= 64, "CLI_ACCEPT bits are a uint64_t");
/* Everything that configures a line, for tools that open a device. */
#define CLI_ACCEPT_LINK                                                              \
	(CLI_ACCEPT(CLI_OPT_DEVICE) | CLI_ACCEPT(CLI_OPT_NET) | CLI_ACCEPT(CLI_OPT_STATION) |  \
	 CLI_ACCEPT(CLI_OPT_SRC) | CLI_ACCEPT(CLI_OPT_BAUD) | CLI_ACCEPT(CLI_OPT_PARITY) |    \
	 CLI_ACCEPT(CLI_OPT_DATA_BITS) | CLI_ACCEPT(CLI_OPT_STOP_BITS) |                       \
	 CLI_ACCEPT(CLI_OPT_HANDSHAKE) | CLI_ACCEPT(CLI_OPT_DUPLEX) | CLI_ACCEPT(CLI_OPT_CHECK) | \
	 CLI_ACCEPT(CLI_OPT_PLC) | CLI_ACCEPT(CLI_OPT_TIMEOUT) | CLI_ACCEPT(CLI_OPT_CMD_TIMEOUT) | \
	 CLI_ACCEPT(CLI_OPT_NAK_RETRIES) | CLI_ACCEPT(CLI_OPT_ENQ_RETRIES) |                   \
	 CLI_ACCEPT(CLI_OPT_TX_DELAY) | CLI_ACCEPT(CLI_OPT_RS485) | CLI_ACCEPT_LIBOPTS)
/* The options of df1_set_option(3): part of CLI_ACCEPT_LINK; a responder takes
 * those that mean something to it one by one. */
#define CLI_ACCEPT_LIBOPTS                                                                 \
	(CLI_ACCEPT(CLI_OPT_HD_BCC) | CLI_ACCEPT(CLI_OPT_PLC5_FLOAT) |                            \
	 CLI_ACCEPT(CLI_OPT_PLC5_TIMER_WORDS) | CLI_ACCEPT(CLI_OPT_PLC2_ADDR) |                   \
	 CLI_ACCEPT(CLI_OPT_SLC_IO_CODES) | CLI_ACCEPT(CLI_OPT_MAX_PACKET) |                      \
	 CLI_ACCEPT(CLI_OPT_DUP_DETECT) | CLI_ACCEPT(CLI_OPT_EMBEDDED) | CLI_ACCEPT(CLI_OPT_NAK_0F) | \
	 CLI_ACCEPT(CLI_OPT_EOT_BCC) | CLI_ACCEPT(CLI_OPT_ECHO_DISCARD) |                           \
	 CLI_ACCEPT(CLI_OPT_POLL_TIMEOUT) | CLI_ACCEPT(CLI_OPT_OUTSTANDING) |                       \
	 CLI_ACCEPT(CLI_OPT_EIP_CONNECTED) | CLI_ACCEPT(CLI_OPT_LOW_LATENCY) |                      \
	 CLI_ACCEPT(CLI_OPT_ROUTE) | CLI_ACCEPT_RADIO)
/* the radio modem's options (--duplex radio) */
#define CLI_ACCEPT_RADIO \
	(CLI_ACCEPT(CLI_OPT_APP_RETRIES) | CLI_ACCEPT(CLI_OPT_RADIO_DUP) | CLI_ACCEPT(CLI_OPT_RADIO_RTS) | \
	 CLI_ACCEPT(CLI_OPT_RTS_SEND) | CLI_ACCEPT(CLI_OPT_RTS_OFF) | CLI_ACCEPT(CLI_OPT_DCD_WAIT))
#define CLI_ACCEPT_OUTPUT \
	(CLI_ACCEPT(CLI_OPT_FORMAT) | CLI_ACCEPT(CLI_OPT_VERBOSE) | CLI_ACCEPT(CLI_OPT_QUIET))
#define CLI_ACCEPT_ALL (CLI_ACCEPT_LINK | CLI_ACCEPT_OUTPUT)

#define CLI_FMT_BIT(f) (1u << (f))   /* enum cli_format: cli_text.h */
#define CLI_PLC_BIT(p) (1u << (p))   /* enum df1_plc */

/* Keys of a tool's own long-only options start here (short ones use the letter). */
#define CLI_KEY_EXTRA 1000

/* A tool's own option. */
struct cli_extra_opt {
	const char *name;    /* long name without "--" */
	int has_arg;         /* no_argument, required_argument, optional_argument */
	int key;             /* a short letter ('w'), or CLI_KEY_EXTRA + n for long-only */
	const char *arg;     /* metavariable for --help ("FILE"), NULL without argument */
	const char *help;    /* one line */
};

struct cli;
/* Called for each of the tool's own options; returns CLI_CONTINUE, or an exit status
 * (having printed the reason). */
typedef int (*cli_extra_fn)(struct cli *c, int key, const char *arg, void *user);

struct cli_tool {
	const char *name;                  /* "df1mon": the prefix of every message */
	const char *synopsis;              /* after "Usage: NAME ", may hold '\n' */
	const char *summary;               /* one line for --help */
	uint64_t accepts;                  /* CLI_ACCEPT(...) bits */
	unsigned formats;                  /* CLI_FMT_BIT(...); plain is always accepted */
	bool check_auto;                   /* --check auto is allowed (decoders) */
	bool half_slave;                   /* --duplex half-slave and Mode Slave: a slave station (df1gw) */
	unsigned plcs;                     /* CLI_PLC_BIT(...) --plc accepts; 0: every one */
	/* --help text of a common option where the tool's meaning differs (a responder's
	 * --duplex half); NULL: the common text */
	const char *common_help[CLI_OPT_COUNT_];
	const struct cli_extra_opt *extra; /* terminated by { NULL }, or NULL */
	cli_extra_fn on_extra;
	const char *help_tail;             /* extra text at the end of --help, or NULL */
	const char *exit_text;             /* the "Exit status:" line of --help, or NULL */
};

struct cli {
	const struct cli_tool *tool;
	const char *name;                  /* tool->name */

	/* line settings; defaults: 19200 8N1 CRC full duplex, station 1, src 0, 1000 ms */
	const char *device;                /* -d, else DF1_DEVICE, else the network file's port */
	const char *net_file;
	bool have_net;
	struct df1_net_config net;
	int station;                       /* destination */
	int src;                           /* our own station */
	int baud, data_bits, stop_bits;
	char parity;                       /* 'N' 'E' 'O' */
	bool handshake;
	bool half_duplex;
	bool half_slave;                   /* --duplex half-slave (tool->half_slave only) */
	bool radio;                        /* --duplex radio: DF1_RADIO_MODEM */
	bool have_forward;                 /* --forward given */
	uint8_t forward[32];               /* its table (df1_set_forward) */
	enum df1_check check;
	enum df1_plc plc;
	int timeout_ms, cmd_timeout_ms;
	int nak_retries, enq_retries;
	int tx_delay_ms;
	bool rs485;
	/* df1_set_option values of the link and PLC options, by enum cli_opt_id; only
	 * those given (c->given) or set by the tool (c->lib_set) are applied */
	int lib_value[CLI_OPT_COUNT_];
	uint64_t lib_set;                  /* CLI_ACCEPT(id): a tool's own default in lib_value */

	/* output */
	enum cli_format format;
	int verbose;                       /* -v count */
	bool quiet;

	uint64_t given;                    /* CLI_ACCEPT(id) bits of options given on the command line */

	/* operands left after the options */
	int argc;
	char **argv;

	/* runtime: trace decoders (one per direction), the trace clock origin */
	struct df1_decoder *trace_dec[2];
	struct decode_ctx *trace_ctx;
	unsigned long trace_n;             /* symbols traced */
	uint64_t trace_t0;
	bool trace_have_t0;
};

/* Set the defaults (tools may change them before cli_parse, e.g. check = AUTO). */
void cli_init(struct cli *c, const struct cli_tool *t);
/* Parse argv. Prints --help / --version to stdout (returns 0), usage errors to
 * stderr (returns 2); loads -N FILE (each issue reported, returns 2 if any).
 * Returns CLI_CONTINUE when the tool should run; c->argc/argv are the operands. */
int cli_parse(struct cli *c, int argc, char **argv, void *user);
void cli_usage(const struct cli *c, FILE *f);
/* --version: "TOOL (libdf1) X.Y.Z", the version the tool was built with, then
 * "library: libdf1 X.Y.Z", the library it runs with (df1_version()). */
void cli_print_version(FILE *f, const char *tool);
/* "Try 'NAME --help'." after a usage error; returns CLI_EXIT_USAGE. */
int cli_usage_error(const struct cli *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Release what cli_parse / cli_open allocated (not the handle). */
void cli_cleanup(struct cli *c);

/* Numbers as a person types them: decimal, leading zeros included ("010" is 10,
 * never octal 8), or hex only with an explicit 0x; the strtol base for s. */
int cli_number_base(const char *s);
/* Numbers: decimal (or 0x hex) integer in [lo, hi]; on error prints
 * "NAME: --OPT: invalid value 'x' (expected LO-HI)" and returns CLI_EXIT_USAGE. */
int cli_parse_int(const struct cli *c, const char *opt, const char *arg, long lo, long hi, int *out);
/* The same number without a message (parts of a value: a list, MS:P): true if s is one. */
bool cli_long_in(const char *s, long lo, long hi, long *out);
/* A bad option value: prints "NAME: --OPT: invalid value 'x' (expected WHAT)" and
 * returns CLI_EXIT_USAGE. */
int cli_bad_value(const struct cli *c, const char *opt, const char *arg, const char *expected);

/* The link and PLC options (--hd-bcc ... --echo-discard) given or set by the tool:
 * df1_set_option() on h (each failure printed as "NAME: --OPT: ..." and returned as
 * CLI_EXIT_USAGE, else 0). cli_open calls it; a responder calls it on its handle. */
int cli_apply_lib_options(const struct cli *c, df1_t *h);
/* Those that change how bytes decode (--hd-bcc, --nak-0f, --embedded-responses,
 * --eot-bcc) on a decoder, so that a trace, a log or a decode reads the line as the
 * handle does. */
void cli_decoder_options(const struct cli *c, struct df1_decoder *d);
/* Is this option's value set (given, or a tool default)? */
bool cli_lib_option_set(const struct cli *c, enum cli_opt_id id);

/* Build the handle from the options (df1_new, setters or the network file, logging
 * and tracing by -v), then df1_open the device. On error prints
 * "NAME: DEVICE: [ID] MNEMONIC: text" and returns 1 (open failed) or 2 (configuration);
 * else 0 with *out set. */
int cli_open(struct cli *c, df1_t **out);
/* cli_open without the df1_open: the handle configured (a daemon opens it, and
 * opens it again after the line is lost). The same messages and statuses. */
int cli_configure(struct cli *c, df1_t **out);
/* df1_close + df1_free + cli_cleanup; NULL handle is fine. */
void cli_close(struct cli *c, df1_t *h);

/* Report a failed operation:
 *   "df1read: N7:0: station 1: [2508] ERR_COMMAND_TIMEOUT: command timed out"
 * address may be NULL: then the address the handle's last error names (its
 * address field), if any; station < 0 leaves it out. Returns the exit status for err. */
int cli_report(const char *tool, const char *address, int station, const df1_t *h, int err);
/* The same "[2508] ERR_COMMAND_TIMEOUT: text" as cli_report, into buf (for data lines). */
void cli_error_text(const df1_t *h, int err, char *buf, size_t cap);
/* Exit status for a DF1_E_* code: 2 for address/type/value/configuration errors, else 1. */
int cli_exit_status(int err);
/* "[2508] ERR_COMMAND_TIMEOUT" for a catalog ID, else the error name ("DF1_E_REMOTE"). */
void cli_error_tag(int err, int catalog_id, char *buf, size_t cap);
/* The line's counters of the message catalog in ID order (cli_counters.c):
 * "ID MNEMONIC VALUE" lines (CLI_FMT_PLAIN, and INFLUX), "T,ID,MNEMONIC,VALUE"
 * rows with t the seconds given (CSV), or {"id":..,"mnemonic":..,"value":..}
 * objects joined by commas (JSON). Returns how many. */
int cli_print_counters(FILE *f, const df1_t *h, enum cli_format fmt, double t);
/* The radio modem's statistics as rows of ID 0 in the same formats, after
 * those (comma: JSON rows came before); their number. */
int cli_print_radio(FILE *f, const df1_t *h, enum cli_format fmt, double t, bool comma);
/* The Prometheus name of catalog counter e: "df1_link_" + its mnemonic in
 * lower case + "_total" (df1_link_cnt_msg_packets_sent_total), the name
 * df1gw's /metrics and df1mon -f prometheus share. */
void cli_counter_metric_name(const struct df1_catalog_entry *e, char *buf, size_t cap);

/* Logging (-v) and tracing (-vv) callbacks; user = struct cli *. */
void cli_log(void *user, int catalog_id, enum df1_severity sev, const char *text);
void cli_trace(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us);

/* Signals: every signal that would end the tool (SIGHUP SIGINT SIGQUIT SIGTERM
 * SIGUSR1 SIGUSR2 SIGALRM SIGVTALRM SIGPROF SIGIO SIGPWR SIGXCPU SIGXFSZ) sets cli_stop
 * and writes a byte to a self-pipe whose read end is returned (and handed to
 * df1_set_cancel_fd by cli_open), so waits end at once and the tool ends as on
 * SIGINT: port restored, lock released, its report printed; a second one kills.
 * SIGPIPE is ignored so a closed stdout shows as a write error. Returns the fd or -1. */
extern volatile sig_atomic_t cli_stop;
int cli_signals_install(void);
/* A responder (df1sim): also SIGUSR1, which sets cli_mute, and SIGUSR2, which
 * clears it, through the same self-pipe; cli_signal_drain() empties the pipe
 * once the flags are read. */
extern volatile sig_atomic_t cli_mute;
int cli_signals_install_mute(void);
void cli_signal_drain(void);
int cli_signal_fd(void);       /* read end of the self-pipe, or -1 */
int cli_stop_signal(void);     /* the signal that stopped us, or 0 */
/* Stop after ms milliseconds as a signal would (SIGALRM through the same handler and
 * self-pipe; cli_stop_signal() then returns SIGALRM). Call after cli_signals_install.
 * Returns 0 or -1 (errno set). */
int cli_stop_after_ms(long ms);
/* The stop was that timer's SIGALRM (not a SIGALRM sent with kill). */
bool cli_stopped_by_timer(void);

/* Addresses of operands (df1read, df1write). */
#define CLI_ADDR_TEXT_MAX 80                /* an address's text with its NUL */
bool cli_is_tcr(enum df1_file_type t);   /* T, C, R */
bool cli_is_io(enum df1_file_type t);    /* I, O */
/* The address of value i of an operand starting at a, as the library counts:
 * elements; bits run on into the next word, except T/C/R bits; I/O words with a
 * word number advance the word. out's ascii is cleared. false if it leaves the
 * address space. */
bool cli_addr_step(enum df1_plc plc, const struct df1_addr *a, size_t i, struct df1_addr *out);
/* A bad operand address, item counted from 1; err DF1_E_ADDR_RANGE (n values) or
 * any other for syntax:
 *   "df1read: N7:x: [2503] ERR_ADDRESS_SYNTAX: Item: 2, Invalid Address Syntax (N7:x)"
 * Returns CLI_EXIT_USAGE. */
int cli_address_error(const struct cli *c, int item, const char *text, int err, size_t n);

/* "SIGINT", "SIGHUP", ... for the signals above, else "a signal". */
const char *cli_signal_name(int sig);
/* When a signal stopped us (cli_stop), end as that signal would have (its default
 * action), so that a calling shell script stops too and sees 128 + N; SIGQUIT,
 * SIGXCPU and SIGXFSZ, whose default dumps core, exit with 128 + N instead.
 * Returns only when there was none, or it was --duration's timer. */
void cli_raise_stop_signal(void);

/* JSON, CSV and hex: cli_text.h (included above). */

#endif
