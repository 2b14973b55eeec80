/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_libopts - the common options that set df1_set_option(3)'s link and PLC
 * options (see cli.h): their values, words and defaults, applied to a handle
 * and to the tools' own decoders. Where the spec leaves a doubt (doc/PROTOCOL.md 8), the
 * default is its recommendation and the other reading is one option away.
 */
#include "common/cli_int.h"

#include <string.h>
#include <strings.h>

struct lib_word {
	const char *word;
	int value;
};

struct lib_opt {
	enum cli_opt_id id;
	enum df1_option opt;
	const char *name;               /* "--hd-bcc" */
	const struct lib_word *words;   /* NULL: a number lo..hi, or no argument (value 1) */
	const char *expected;           /* the accepted values, for the message */
	int lo, hi;
	bool decoder;                   /* also changes how bytes decode */
};

static const struct lib_word w_hd_bcc[] = { { "stn", 0 }, { "stx", 1 }, { NULL, 0 } };
static const struct lib_word w_float[] = { { "plain", 0 }, { "swapped", 1 }, { NULL, 0 } };
static const struct lib_word w_timer[] = { { "3", 3 }, { "5", 5 }, { NULL, 0 } };
static const struct lib_word w_plc2[] = { { "bytes", 0 }, { "words", 1 }, { NULL, 0 } };
static const struct lib_word w_io[] = { { "8b", 0 }, { "82", 1 }, { NULL, 0 } };
static const struct lib_word w_yes_no[] = {
	{ "yes", 1 }, { "y", 1 }, { "on", 1 }, { "1", 1 }, { "true", 1 },
	{ "no", 0 }, { "n", 0 }, { "off", 0 }, { "0", 0 }, { "false", 0 }, { NULL, 0 },
};

static const struct lib_word w_yes_no_auto[] = {
	{ "yes", 1 }, { "y", 1 }, { "on", 1 }, { "1", 1 }, { "true", 1 },
	{ "no", 0 }, { "n", 0 }, { "off", 0 }, { "0", 0 }, { "false", 0 }, { "auto", DF1_DUP_AUTO },
	{ NULL, 0 },
};

static const struct lib_opt lib_opts[] = {
	{ CLI_OPT_HD_BCC, DF1_OPT_HD_BCC_INCLUDES_STX, "--hd-bcc", w_hd_bcc, "stn or stx", 0, 0, true },
	{ CLI_OPT_PLC5_FLOAT, DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED, "--plc5-float", w_float, "plain or swapped",
	  0, 0, false },
	{ CLI_OPT_PLC5_TIMER_WORDS, DF1_OPT_PLC5_TIMER_WORDS, "--plc5-timer-words", w_timer, "3 or 5", 0, 0,
	  false },
	{ CLI_OPT_PLC2_ADDR, DF1_OPT_PLC2_WORD_ADDR, "--plc2-addr", w_plc2, "bytes or words", 0, 0, false },
	{ CLI_OPT_SLC_IO_CODES, DF1_OPT_SLC_IO_CODES_82, "--slc-io-codes", w_io, "8b or 82", 0, 0, false },
	{ CLI_OPT_MAX_PACKET, DF1_OPT_MAX_PACKET, "--max-packet", NULL, NULL, 0, 244, false },
	{ CLI_OPT_DUP_DETECT, DF1_OPT_DUPLICATE_DETECT, "--duplicate-detect", w_yes_no, "yes or no", 0, 0,
	  false },
	{ CLI_OPT_EMBEDDED, DF1_OPT_EMBEDDED_RESPONSES, "--embedded-responses", w_yes_no, "yes or no", 0, 0,
	  true },
	{ CLI_OPT_NAK_0F, DF1_OPT_ACCEPT_NAK_0F, "--nak-0f", w_yes_no, "yes or no", 0, 0, true },
	{ CLI_OPT_EOT_BCC, DF1_OPT_EOT_WITH_BCC, "--eot-bcc", w_yes_no, "yes or no", 0, 0, true },
	{ CLI_OPT_ECHO_DISCARD, DF1_OPT_ECHO_DISCARD, "--echo-discard", NULL, NULL, 1, 1, false },
	{ CLI_OPT_POLL_TIMEOUT, DF1_OPT_POLL_TIMEOUT_MS, "--poll-timeout", NULL, NULL, 0, 60000, false },
	{ CLI_OPT_OUTSTANDING, DF1_OPT_MAX_OUTSTANDING, "--outstanding", NULL, NULL, 1, 16, false },
	{ CLI_OPT_EIP_CONNECTED, DF1_OPT_EIP_CONNECTED, "--eip-connected", NULL, NULL, 1, 1, false },
	{ CLI_OPT_LOW_LATENCY, DF1_OPT_LOW_LATENCY, "--low-latency", w_yes_no, "yes or no", 0, 0, false },
	{ CLI_OPT_ROUTE, DF1_OPT_ROUTE, "--route", w_yes_no, "yes or no", 0, 0, false },
	{ CLI_OPT_APP_RETRIES, DF1_OPT_APP_RETRIES, "--app-retries", NULL, NULL, 0, 10, false },
	{ CLI_OPT_RADIO_DUP, DF1_OPT_RADIO_DUP_DETECT, "--dup-detect", w_yes_no_auto, "yes, no or auto",
	  0, 0, false },
	{ CLI_OPT_RADIO_RTS, DF1_OPT_RADIO_RTS_CTS, "--radio-rts", w_yes_no, "yes or no", 0, 0, false },
	{ CLI_OPT_RTS_SEND, DF1_OPT_RTS_SEND_DELAY_MS, "--rts-send-delay", NULL, NULL, 0, 65535, false },
	{ CLI_OPT_RTS_OFF, DF1_OPT_RTS_OFF_DELAY_MS, "--rts-off-delay", NULL, NULL, 0, 65535, false },
	{ CLI_OPT_DCD_WAIT, DF1_OPT_DCD_WAIT_MS, "--dcd-wait", NULL, NULL, 0, 65535, false },
};

#define N_LIB_OPTS (sizeof lib_opts / sizeof lib_opts[0])

static const struct lib_opt *lib_opt_of(enum cli_opt_id id)
{
	for (size_t i = 0; i < N_LIB_OPTS; i++)
		if (lib_opts[i].id == id)
			return &lib_opts[i];
	return NULL;
}

bool cli_is_lib_option(enum cli_opt_id id)
{
	return lib_opt_of(id) != NULL;
}

int cli_lib_option(struct cli *c, enum cli_opt_id id, const char *arg)
{
	const struct lib_opt *o = lib_opt_of(id);

	if (!o)
		return CLI_EXIT_USAGE;
	c->given |= CLI_ACCEPT(id);
	if (!o->words && o->lo == o->hi) {             /* a flag */
		c->lib_value[id] = o->lo;
		return CLI_CONTINUE;
	}
	if (!o->words)
		return cli_parse_int(c, o->name, arg, o->lo, o->hi, &c->lib_value[id]);
	for (const struct lib_word *w = o->words; w->word; w++) {
		if (strcasecmp(arg, w->word) == 0) {
			c->lib_value[id] = w->value;
			return CLI_CONTINUE;
		}
	}
	return cli_bad_value(c, o->name, arg, o->expected);
}

bool cli_lib_option_set(const struct cli *c, enum cli_opt_id id)
{
	return ((c->given | c->lib_set) & CLI_ACCEPT(id)) != 0;
}

int cli_apply_lib_options(const struct cli *c, df1_t *h)
{
	for (size_t i = 0; i < N_LIB_OPTS; i++) {
		const struct lib_opt *o = &lib_opts[i];
		char tag[96], text[256];
		int r;

		if (!cli_lib_option_set(c, o->id))
			continue;
		r = df1_set_option(h, o->opt, c->lib_value[o->id]);
		if (r < 0) {
			cli_error_parts(h, r, tag, sizeof tag, text, sizeof text);
			fprintf(stderr, "%s: %s: %s: %s\n", c->name, o->name, tag, text);
			return CLI_EXIT_USAGE;
		}
	}
	return 0;
}

void cli_decoder_options(const struct cli *c, struct df1_decoder *d)
{
	for (size_t i = 0; i < N_LIB_OPTS && d; i++)
		if (lib_opts[i].decoder && cli_lib_option_set(c, lib_opts[i].id))
			(void)df1_decoder_set_option(d, lib_opts[i].opt, c->lib_value[lib_opts[i].id]);
}
