/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1write - write data-table values to a DF1 controller, for shell scripts
 * (doc/ARCHITECTURE.md 8, df1write(1)).
 *
 *   df1write [OPTIONS] ADDRESS=VALUE[,VALUE...]...
 *
 * Every operand is parsed and every value checked against its file type
 * (df1_value_parse) before the device is opened: one bad value and nothing is
 * written (exit 2). Then the operands are written in the order given, each with
 * one library call (split into packets by the library); a bit address changes
 * only its bits (masked writes).
 *
 * Values: a comma-separated list goes to consecutive elements (consecutive bits
 * for a bit address), except for two kinds of element whose value is the whole
 * text after the first '=': an ST string (commas, quotes and '=' included, as
 * given; no quoting rule of our own) and a whole T/C/R element
 * ("PRE=100,ACC=0" or "EN=1 PRE=100 ACC=0").
 *
 * On a failure part-way, the error is reported and then which operands were
 * written, which were sent without a confirmation (no reply, interrupted) and
 * which were not written:
 *   df1write: written: N7:0 N7:1; not written: F8:0 ST9:0
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cli.h"
#include "df1.h"

/* the smallest packet of any controller (SLC 5/01, 5/02), from the library's table */
#define SMALL_PACKET ((size_t)df1_packet_max(DF1_PLC_SLC502, true))

enum wstate {
	W_PENDING = 0,          /* not attempted */
	W_WRITTEN,              /* the PLC confirmed it */
	W_REFUSED,              /* the PLC refused it, or it failed before it was sent */
	W_UNCONFIRMED,          /* sent, but no confirmation: it may or may not have been written */
};

struct witem {
	const char *arg;            /* the operand as typed */
	char text[CLI_ADDR_TEXT_MAX];   /* its address part, as typed */
	struct df1_addr a;
	size_t n;
	struct df1_value *vals;
	enum wstate state;
};

struct wr {
	struct cli cli;
	struct witem *items;
	size_t nitems;
};

static const struct cli_tool write_tool = {
	.name = "df1write",
	.synopsis = "[OPTIONS] ADDRESS=VALUE[,VALUE...]...",
	.summary = "Write data-table values to a DF1 controller (PLC-5, SLC 500, MicroLogix).",
	/* -f takes only "plain": df1write prints nothing on stdout; the option is accepted
	 * so that an option list shared with df1read ("-f plain") works */
	.accepts = CLI_ACCEPT_ALL,
	.formats = CLI_FMT_BIT(CLI_FMT_PLAIN),
	.check_auto = false,
	.extra = NULL,
	.on_extra = NULL,
	.help_tail =
		"\nValues: N/A/B/S words -32768..32767 (or 0x0000..0xFFFF), L 32-bit, F floats,\n"
		"bits 0|1. VALUE,VALUE... goes to consecutive elements (bits for a bit address).\n"
		"ST9:0=TEXT: everything after '=' is the string (commas included), 82 chars max.\n"
		"T4:0=PRE=100,ACC=0 (or \"EN=1 PRE=100 ACC=0\"): a whole T/C/R element, in one\n"
		"operand; members not given are 0. Negative values need no '--': N7:0=-5.\n"
		"Every value is checked before anything is sent; operands are written in order.\n"
		"See df1write(1).\n",
	.exit_text = "0 all written, 1 communication or PLC error (stderr lists what was\n"
	             "written and what was not), 2 usage, address or value error (nothing sent).",
};

/* ------------------------------------------------------------------------
 * Addresses and values
 * ------------------------------------------------------------------------ */

/* What a value of this kind must look like, for messages. */
static const char *value_hint(const struct df1_addr *a, enum df1_value_kind k)
{
	switch (k) {
	case DF1_VAL_INT16: return "an integer -32768..32767 or 0x0000..0xFFFF";
	case DF1_VAL_INT32: return "an integer -2147483648..2147483647";
	case DF1_VAL_FLOAT: return "a number";
	case DF1_VAL_BIT: return "0 or 1";
	case DF1_VAL_STRING: return "at most 82 characters";
	case DF1_VAL_TCR:
		return a->type == DF1_FT_T ? "NAME=VALUE items of EN TT DN PRE ACC"
		     : a->type == DF1_FT_C ? "NAME=VALUE items of CU CD DN OV UN UA PRE ACC"
		                           : "NAME=VALUE items of EN EU DN EM ER UL IN FD LEN POS";
	}
	return "a value";
}

/* Whole rest after '=' is one value: strings and whole T/C/R elements. */
static bool one_value(const struct df1_addr *a)
{
	enum df1_value_kind k = df1_addr_value_kind(a);
	return k == DF1_VAL_STRING || k == DF1_VAL_TCR;
}

/* One operand ADDRESS=VALUE[,VALUE...]: parse the address and every value. */
static int parse_operand(struct wr *w, size_t idx, const char *arg)
{
	struct witem *it = &w->items[idx];
	const char *eq = strchr(arg, '='), *v;
	size_t alen, cap;
	struct df1_addr last;
	int rc;

	it->arg = arg;
	if (!eq)
		return cli_usage_error(&w->cli, "%s: expected ADDRESS=VALUE[,VALUE...]", arg);
	alen = (size_t)(eq - arg);
	if (alen >= sizeof it->text)
		return cli_address_error(&w->cli, (int)idx + 1, arg, DF1_E_ADDR_SYNTAX, 1);
	memcpy(it->text, arg, alen);
	it->text[alen] = '\0';
	rc = df1_addr_parse_plc(w->cli.plc, it->text, &it->a);
	if (rc < 0)
		return cli_address_error(&w->cli, (int)idx + 1, it->text, rc, 1);
	v = eq + 1;

	/* count the values */
	if (one_value(&it->a)) {
		cap = 1;
	} else {
		cap = 1;
		for (const char *p = v; *p; p++)
			if (*p == ',')
				cap++;
	}
	if (!cli_addr_step(w->cli.plc, &it->a, cap - 1, &last))
		return cli_address_error(&w->cli, (int)idx + 1, it->text, DF1_E_ADDR_RANGE, cap);
	it->vals = calloc(cap, sizeof *it->vals);
	if (!it->vals) {
		fprintf(stderr, "%s: out of memory\n", w->cli.name);
		return CLI_EXIT_FAIL;
	}
	it->n = cap;

	for (size_t i = 0; i < cap; i++) {
		const char *end = one_value(&it->a) ? v + strlen(v) : strchr(v, ',');
		size_t len = end ? (size_t)(end - v) : strlen(v);
		char *text = malloc(len + 1);
		struct df1_addr ai;
		char tag[96];

		if (!text) {
			fprintf(stderr, "%s: out of memory\n", w->cli.name);
			return CLI_EXIT_FAIL;
		}
		memcpy(text, v, len);
		text[len] = '\0';
		cli_addr_step(w->cli.plc, &it->a, i, &ai);
		rc = df1_value_parse(&ai, text, &it->vals[i]);
		if (rc == 0 && it->vals[i].kind != DF1_VAL_STRING && strspn(text, " \t") == len)
			rc = DF1_E_TYPE;        /* an empty item: "N7:0=1,,3" */
		if (rc < 0) {
			cli_error_tag(rc, df1_error_catalog_id(rc), tag, sizeof tag);
			fprintf(stderr, "%s: %s: ", w->cli.name, it->text);
			if (cap > 1)
				fprintf(stderr, "value %zu ", i + 1);
			if (len > 40)
				fprintf(stderr, "'%.32s...' (%zu characters)", text, len);
			else
				fprintf(stderr, "'%s'", text);
			fprintf(stderr, ": %s: %s (expected %s)\n", tag, df1_strerror(rc),
			        value_hint(&ai, df1_addr_value_kind(&ai)));
			free(text);
			return CLI_EXIT_USAGE;
		}
		free(text);
		v = end ? end + 1 : v + len;
	}
	return CLI_CONTINUE;
}

/* ------------------------------------------------------------------------
 * Writing
 * ------------------------------------------------------------------------ */

/* Whether an operand goes in one command (so a refusal means nothing of it was written). */
static bool one_packet(const struct witem *it)
{
	const struct df1_addr *a = &it->a;

	if (it->n == 1)
		return true;
	if (a->bit != DF1_ADDR_NONE) {
		int nb = a->type == DF1_FT_L && a->sub == DF1_ADDR_NONE ? 32 : 16;
		return cli_is_tcr(a->type) || (a->bit + (int)it->n - 1) / nb == 0;
	}
	if (cli_is_tcr(a->type) && a->sub != DF1_ADDR_NONE)
		return false;           /* one command per element */
	return it->n * (size_t)df1_file_type_element_size(a->type) <= SMALL_PACKET;
}

/* Errors after which nothing of the operand can have been written. */
static bool surely_unwritten(const struct witem *it, int err)
{
	switch (err) {
	case DF1_E_REMOTE:
	case DF1_E_NAK:
		/* the failed command was not executed, but those before it in the
		 * same operand were */
		return one_packet(it);
	default:
		return df1_error_unexecuted(err);
	}
}

static int write_item(struct wr *w, df1_t *h, struct witem *it)
{
	if (it->a.bit != DF1_ADDR_NONE && it->n == 1)
		return df1_write_bit(h, w->cli.station, it->text, it->vals[0].v.bit);
	return df1_write_addr(h, w->cli.station, &it->a, it->vals, it->n);
}

/* One part of the progress report: "; not written: F8:0 ST9:0". */
static void report_part(const struct wr *w, enum wstate state, const char *label, bool always,
                        bool *first)
{
	size_t count = 0;

	for (size_t i = 0; i < w->nitems; i++) {
		enum wstate s = w->items[i].state == W_REFUSED ? W_PENDING : w->items[i].state;
		count += s == state;
	}
	if (count == 0 && !always)
		return;
	fprintf(stderr, "%s %s:", *first ? "" : ";", label);
	if (count == 0)
		fputs(" none", stderr);
	for (size_t i = 0; i < w->nitems; i++) {
		enum wstate s = w->items[i].state == W_REFUSED ? W_PENDING : w->items[i].state;
		if (s == state)
			fprintf(stderr, " %s", w->items[i].text);
	}
	*first = false;
}

/* "df1write: written: N7:0 N7:1; unconfirmed: N7:2; not written: F8:0 ST9:0" */
static void report_progress(const struct wr *w)
{
	bool first = true;

	fprintf(stderr, "%s:", w->cli.name);
	report_part(w, W_WRITTEN, "written", true, &first);
	report_part(w, W_UNCONFIRMED, "unconfirmed", false, &first);
	report_part(w, W_PENDING, "not written", false, &first);
	fputc('\n', stderr);
}

static void free_all(struct wr *w)
{
	for (size_t i = 0; i < w->nitems; i++)
		free(w->items[i].vals);
	free(w->items);
	w->items = NULL;
}

int main(int argc, char **argv)
{
	static struct wr w;
	df1_t *h = NULL;
	int status = CLI_EXIT_OK, rc = 0;
	size_t done = 0;
	struct witem *failed = NULL;

	cli_init(&w.cli, &write_tool);
	status = cli_parse(&w.cli, argc, argv, &w);
	if (status != CLI_CONTINUE)
		return status;
	if (w.cli.argc < 1)
		return cli_usage_error(&w.cli, "nothing to write: give ADDRESS=VALUE[,VALUE...]");
	w.nitems = (size_t)w.cli.argc;
	w.items = calloc(w.nitems, sizeof *w.items);
	if (!w.items) {
		fprintf(stderr, "%s: out of memory\n", w.cli.name);
		return CLI_EXIT_FAIL;
	}
	for (size_t i = 0; i < w.nitems; i++) {
		status = parse_operand(&w, i, w.cli.argv[i]);
		if (status != CLI_CONTINUE) {
			free_all(&w);
			cli_cleanup(&w.cli);
			return status;
		}
	}
	if (!w.cli.device || !*w.cli.device) {
		free_all(&w);
		cli_cleanup(&w.cli);
		return cli_usage_error(&w.cli, "no device: use -d DEV, -N FILE or set DF1_DEVICE");
	}

	cli_signals_install();
	status = cli_open(&w.cli, &h);
	if (status != CLI_EXIT_OK) {
		free_all(&w);
		cli_cleanup(&w.cli);
		return status;
	}
	for (done = 0; done < w.nitems && !cli_stop; done++) {
		struct witem *it = &w.items[done];

		rc = write_item(&w, h, it);
		if (rc < 0) {
			it->state = surely_unwritten(it, rc) ? W_REFUSED : W_UNCONFIRMED;
			failed = it;
			break;
		}
		it->state = W_WRITTEN;
		if (w.cli.verbose >= 1)
			fprintf(stderr, "%s: %s: written (%zu value%s)\n", w.cli.name, it->text, it->n,
			        it->n == 1 ? "" : "s");
	}
	if (cli_stop && (!failed || rc == DF1_E_INTR || rc == DF1_E_SYS)) {
		if (failed)
			fprintf(stderr, "%s: %s: interrupted by %s\n", w.cli.name, failed->text,
			        cli_signal_name(cli_stop_signal()));
		else
			fprintf(stderr, "%s: interrupted by %s\n", w.cli.name, cli_signal_name(cli_stop_signal()));
		report_progress(&w);
		status = CLI_EXIT_FAIL;
	} else if (failed) {
		status = cli_report(w.cli.name, failed->text, w.cli.station, h, rc);
		report_progress(&w);
	} else if (w.cli.verbose >= 1) {
		uint64_t cmds = 0;
		df1_counter(h, DF1_ID_CNT_CMD_MSGS_SENT, &cmds);
		fprintf(stderr, "%s: %zu operand%s written, %llu command%s sent\n", w.cli.name, w.nitems,
		        w.nitems == 1 ? "" : "s", (unsigned long long)cmds, cmds == 1 ? "" : "s");
	}
	cli_close(&w.cli, h);   /* restores the port's settings */
	free_all(&w);
	cli_raise_stop_signal();
	return status;
}
