/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1read - read data-table values from a DF1 controller, for shell scripts
 * (doc/ARCHITECTURE.md 8, df1read(1)).
 *
 *   df1read [OPTIONS] ADDRESS[,COUNT]...
 *
 * Every operand is checked before the device is opened (exit 2). The reads
 * are one df1_read_multi() call (all or nothing, DF1_READ_MULTI_STOP): the
 * library plans them into the fewest transactions its packet limits allow
 * (ranges of one file that overlap or touch are one block, a gap is read
 * through when that saves a packet), takes bits and T/C/R words out of the
 * elements read, reads I/O and PLC-5 "$" addresses on their own, and reads a
 * block the PLC refuses operand by operand, so that the error names the
 * operand at fault.
 *
 * All or nothing: everything is read first, then printed; on any failure
 * stdout stays empty and the exit status is 1.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cli.h"
#include "df1.h"

#define VALUE_TEXT_MAX 200

struct item {
	const char *text;           /* the address as typed (operand up to ',') */
	char text_buf[CLI_ADDR_TEXT_MAX];
	struct df1_addr a;
	size_t n;                   /* values */
	struct df1_value *vals;     /* n values, once read */
};

struct rd {
	struct cli cli;
	struct item *items;
	size_t nitems;
	unsigned reads;             /* read calls df1_read_multi made */
};

static const struct cli_tool read_tool = {
	.name = "df1read",
	.synopsis = "[OPTIONS] ADDRESS[,COUNT]...",
	.summary = "Read data-table values from a DF1 controller (PLC-5, SLC 500, MicroLogix).",
	.accepts = CLI_ACCEPT_ALL,
	.formats = CLI_FMT_BIT(CLI_FMT_PLAIN) | CLI_FMT_BIT(CLI_FMT_CSV) | CLI_FMT_BIT(CLI_FMT_JSON),
	.check_auto = false,
	.extra = NULL,
	.on_extra = NULL,
	.help_tail =
		"\nAddresses: N7:0 N7:0,10 F8:3 L10:0 ST9:0 B3:0/5 B3/21 T4:0 T4:0.ACC T4:0/DN\n"
		"C5:1.PRE R6:0.POS S:1/5 I:0/3 O:0 A11:0 $N7:0 (PLC-5). COUNT elements\n"
		"(consecutive bits for a bit address) start at ADDRESS.\n"
		"Output: plain, one value per line; csv, a header and address,value rows;\n"
		"json, an array of {\"address\":..,\"value\":..}. Everything is read before\n"
		"anything is printed: on an error stdout stays empty.\n"
		"See df1read(1).\n",
	.exit_text = "0 success, 1 communication or PLC error (nothing printed),\n"
	             "2 usage, address or configuration error (nothing sent).",
};

/* ------------------------------------------------------------------------
 * Addresses
 * ------------------------------------------------------------------------ */

/* Text of value i's address: canonical, "$" kept for PLC-5 logical ASCII. */
static void addr_text(enum df1_plc plc, const struct df1_addr *a, size_t i, char *buf, size_t cap)
{
	struct df1_addr s;

	if (i == 0 && a->ascii[0]) {
		snprintf(buf, cap, "$%s", a->ascii);
		return;
	}
	if (!cli_addr_step(plc, a, i, &s) || df1_addr_format_plc(plc, &s, buf + (a->ascii[0] ? 1 : 0),
	                                                         cap - (a->ascii[0] ? 1 : 0)) < 0) {
		snprintf(buf, cap, "?");
		return;
	}
	if (a->ascii[0])
		buf[0] = '$';
}

/* One operand: ADDRESS[,COUNT]. */
static int parse_operand(struct rd *r, size_t idx, const char *arg)
{
	struct item *it = &r->items[idx];
	const char *comma = strchr(arg, ',');
	size_t alen = comma ? (size_t)(comma - arg) : strlen(arg);
	struct df1_addr last;
	int rc;

	memset(it, 0, sizeof *it);
	it->n = 1;
	if (alen >= sizeof it->text_buf)
		return cli_address_error(&r->cli, (int)idx + 1, arg, DF1_E_ADDR_SYNTAX, 1);
	memcpy(it->text_buf, arg, alen);
	it->text_buf[alen] = '\0';
	it->text = it->text_buf;
	if (comma) {
		char *end;
		unsigned long v;

		errno = 0;
		v = strtoul(comma + 1, &end, 10);
		if (comma[1] < '0' || comma[1] > '9' || *end || errno || v == 0 || v > 16000) {
			fprintf(stderr, "%s: %s: invalid count '%s' (expected 1-16000)\n", r->cli.name, arg,
			        comma + 1);
			fprintf(stderr, "Try '%s --help'.\n", r->cli.name);
			return CLI_EXIT_USAGE;
		}
		it->n = v;
	}
	rc = df1_addr_parse_plc(r->cli.plc, it->text, &it->a);
	if (rc < 0)
		return cli_address_error(&r->cli, (int)idx + 1, it->text, rc, it->n);
	/* every value's address must exist: N7:998,5 runs past element 999 */
	if (!cli_addr_step(r->cli.plc, &it->a, it->n - 1, &last))
		return cli_address_error(&r->cli, (int)idx + 1, it->text, DF1_E_ADDR_RANGE, it->n);
	return CLI_CONTINUE;
}

/* ------------------------------------------------------------------------
 * Reading
 * ------------------------------------------------------------------------ */

/* Read everything: 0, or the DF1_E_* code of the first failure (*failed_at: its operand). */
static int read_all(struct rd *r, df1_t *h, const char **failed_at)
{
	struct df1_read_req *req = calloc(r->nitems, sizeof *req);
	int rc;

	if (!req)
		return DF1_E_NOMEM;
	for (size_t i = 0; i < r->nitems; i++) {
		r->items[i].vals = calloc(r->items[i].n, sizeof *r->items[i].vals);
		if (!r->items[i].vals) {
			free(req);
			return DF1_E_NOMEM;
		}
		req[i].addr = r->items[i].a;
		req[i].count = r->items[i].n;
		req[i].values = r->items[i].vals;
	}
	if (cli_stop) {
		free(req);
		return DF1_E_INTR;
	}
	rc = df1_read_multi(h, r->cli.station, req, r->nitems, DF1_READ_MULTI_STOP, &r->reads);
	for (size_t i = 0; rc < 0 && i < r->nitems; i++)
		if (req[i].result < 0) {
			*failed_at = r->items[i].text;
			break;
		}
	free(req);
	return rc < 0 ? rc : 0;
}

/* ------------------------------------------------------------------------
 * Output
 * ------------------------------------------------------------------------ */

/* A JSON object from "NAME=VALUE NAME=VALUE ..." (a formatted T/C/R element). */
static void json_tcr(FILE *f, const char *text)
{
	const char *p = text;
	bool first = true;

	fputc('{', f);
	while (*p) {
		const char *name, *eq, *val;
		size_t nlen, vlen;
		char num[32];
		long v;

		while (*p == ' ')
			p++;
		if (!*p)
			break;
		name = p;
		while (*p && *p != ' ')
			p++;
		eq = memchr(name, '=', (size_t)(p - name));
		if (!eq)
			continue;
		nlen = (size_t)(eq - name);
		val = eq + 1;
		vlen = (size_t)(p - val);
		if (vlen >= sizeof num)
			vlen = sizeof num - 1;
		memcpy(num, val, vlen);
		num[vlen] = '\0';
		v = strtol(num, NULL, 0);
		fprintf(f, "%s", first ? "" : ",");
		cli_json_string_n(f, name, nlen);
		fprintf(f, ":%ld", v);
		first = false;
	}
	fputc('}', f);
}

static int print_all(struct rd *r)
{
	FILE *f = stdout;
	enum cli_format fmt = r->cli.format;
	bool first = true;

	if (fmt == CLI_FMT_CSV)
		fputs("address,value\n", f);
	else if (fmt == CLI_FMT_JSON)
		fputs("[", f);
	for (size_t k = 0; k < r->nitems; k++) {
		const struct item *it = &r->items[k];

		for (size_t i = 0; i < it->n; i++) {
			const struct df1_value *v = &it->vals[i];
			char text[VALUE_TEXT_MAX], addr[CLI_ADDR_TEXT_MAX];
			int len = df1_value_format(v, it->a.type, text, sizeof text);

			if (len < 0)
				snprintf(text, sizeof text, "?");
			if (fmt == CLI_FMT_PLAIN) {
				fputs(text, f);
				fputc('\n', f);
				continue;
			}
			addr_text(r->cli.plc, &it->a, i, addr, sizeof addr);
			if (fmt == CLI_FMT_CSV) {
				cli_csv_field(f, addr);
				fputc(',', f);
				if (v->kind == DF1_VAL_STRING || v->kind == DF1_VAL_TCR)
					cli_csv_quoted(f, text);
				else
					fputs(text, f);
				fputc('\n', f);
				continue;
			}
			fputs(first ? "\n" : ",\n", f);
			first = false;
			fputs("{\"address\":", f);
			cli_json_string(f, addr);
			fputs(",\"value\":", f);
			if (v->kind == DF1_VAL_STRING)
				cli_json_string_n(f, text, (size_t)(len > 0 ? len : 0));
			else if (v->kind == DF1_VAL_TCR)
				json_tcr(f, text);
			else if (v->kind == DF1_VAL_FLOAT &&
			         (strcmp(text, "nan") == 0 || strcmp(text, "inf") == 0 || strcmp(text, "-inf") == 0))
				cli_json_string(f, text);   /* not JSON numbers */
			else
				fputs(text, f);
			fputc('}', f);
		}
	}
	if (fmt == CLI_FMT_JSON)
		fputs("\n]\n", f);
	if (fflush(f) != 0 || ferror(f)) {
		fprintf(stderr, "%s: stdout: %s\n", r->cli.name, strerror(errno));
		return CLI_EXIT_FAIL;
	}
	return CLI_EXIT_OK;
}

/* ------------------------------------------------------------------------
 * main
 * ------------------------------------------------------------------------ */

static void free_all(struct rd *r)
{
	for (size_t i = 0; i < r->nitems; i++)
		free(r->items[i].vals);
	free(r->items);
	r->items = NULL;
}

int main(int argc, char **argv)
{
	static struct rd r;
	const char *failed_at = NULL;
	df1_t *h = NULL;
	int status, rc;

	cli_init(&r.cli, &read_tool);
	status = cli_parse(&r.cli, argc, argv, &r);
	if (status != CLI_CONTINUE)
		return status;
	if (r.cli.argc < 1)
		return cli_usage_error(&r.cli, "no address given");
	r.nitems = (size_t)r.cli.argc;
	r.items = calloc(r.nitems, sizeof *r.items);
	if (!r.items) {
		fprintf(stderr, "%s: out of memory\n", r.cli.name);
		return CLI_EXIT_FAIL;
	}
	for (size_t i = 0; i < r.nitems; i++) {
		status = parse_operand(&r, i, r.cli.argv[i]);
		if (status != CLI_CONTINUE) {
			free_all(&r);
			cli_cleanup(&r.cli);
			return status;
		}
	}
	if (!r.cli.device || !*r.cli.device) {
		free_all(&r);
		cli_cleanup(&r.cli);
		return cli_usage_error(&r.cli, "no device: use -d DEV, -N FILE or set DF1_DEVICE");
	}

	cli_signals_install();
	status = cli_open(&r.cli, &h);
	if (status != CLI_EXIT_OK) {
		free_all(&r);
		cli_cleanup(&r.cli);
		return status;
	}
	rc = read_all(&r, h, &failed_at);
	if (rc == DF1_E_INTR || cli_stop) {
		fprintf(stderr, "%s: %s%sinterrupted by %s; nothing printed\n", r.cli.name,
		        failed_at ? failed_at : "", failed_at ? ": " : "", cli_signal_name(cli_stop_signal()));
		status = CLI_EXIT_FAIL;
		goto out;
	}
	if (rc < 0) {
		status = cli_report(r.cli.name, failed_at, r.cli.station, h, rc);
		goto out;
	}
	if (r.cli.verbose >= 1) {
		uint64_t cmds = 0;
		df1_counter(h, DF1_ID_CNT_CMD_MSGS_SENT, &cmds);
		fprintf(stderr, "%s: %zu address%s, %u read%s, %llu command%s sent\n", r.cli.name,
		        r.nitems, r.nitems == 1 ? "" : "es", r.reads, r.reads == 1 ? "" : "s",
		        (unsigned long long)cmds, cmds == 1 ? "" : "s");
	}
	status = print_all(&r);
out:
	cli_close(&r.cli, h);   /* restores the port's settings */
	free_all(&r);
	cli_raise_stop_signal();
	return status;
}
