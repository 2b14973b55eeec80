/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_argv - cli_parse(): argv through getopt_long, built from the common
 * options the tool accepts and its own; --help, --version (see cli.h).
 */
#include "common/cli_int.h"

#include <getopt.h>
#include <stdlib.h>
#include <string.h>

/* A short option `k` into shorts (sp: its length so far), with ':' for its
 * argument and '::' for an optional one. */
static void add_short(char *shorts, size_t *sp, size_t cap, int k, int ha)
{
	if (k > 0 && k < 256 && *sp + 3 < cap) {
		shorts[(*sp)++] = (char)k;
		if (ha != no_argument) shorts[(*sp)++] = ':';
		if (ha == optional_argument) shorts[(*sp)++] = ':';
	}
}

/* getopt_long's tables: lo (room for the common options, n_extra of the
 * tool's and --help, --version, and the end) and shorts. */
static void build_options(const struct cli *c, size_t n_extra, struct option *lo, char *shorts,
                          size_t cap)
{
	const struct cli_tool *t = c->tool;
	size_t n = 0, sp = 0;

	shorts[sp++] = ':';   /* report a missing argument as ':' */
	for (size_t i = 0; i < cli_n_common; i++) {
		const struct cli_common_opt *o = &cli_common_opts[i];
		if (!cli_accepts(c, o->id))
			continue;
		lo[n++] = (struct option){ o->name, o->has_arg, NULL, o->key };
		add_short(shorts, &sp, cap, o->key, o->has_arg);
	}
	for (size_t i = 0; i < n_extra; i++) {
		const struct cli_extra_opt *e = &t->extra[i];
		lo[n++] = (struct option){ e->name, e->has_arg, NULL, e->key };
		add_short(shorts, &sp, cap, e->key, e->has_arg);
	}
	lo[n++] = (struct option){ "help", no_argument, NULL, CLI_KEY_HELP };
	lo[n++] = (struct option){ "version", no_argument, NULL, CLI_KEY_VERSION };
	add_short(shorts, &sp, cap, CLI_KEY_HELP, no_argument);
	add_short(shorts, &sp, cap, CLI_KEY_VERSION, no_argument);
	shorts[sp] = 0;
}

/* One option getopt_long() returned (key; opt_text: as given): CLI_CONTINUE,
 * or the exit status (a usage error, --help, --version). */
static int one_option(struct cli *c, int key, const char *opt_text, void *user)
{
	const struct cli_tool *t = c->tool;

	if (key == '?') {
		if (optopt > 0 && optopt < 256)
			return cli_usage_error(c, "unknown option '-%c'", optopt);
		return cli_usage_error(c, "unknown option '%s'", opt_text);
	}
	if (key == ':') {
		if (optopt > 0 && optopt < 256 && opt_text[1] != '-')
			return cli_usage_error(c, "option '-%c' needs a value", optopt);
		return cli_usage_error(c, "option '%s' needs a value", opt_text);
	}
	if (key == CLI_KEY_HELP) {
		cli_usage(c, stdout);
		return fflush(stdout) == 0 ? CLI_EXIT_OK : CLI_EXIT_FAIL;
	}
	if (key == CLI_KEY_VERSION) {
		cli_print_version(stdout, c->name);
		return fflush(stdout) == 0 ? CLI_EXIT_OK : CLI_EXIT_FAIL;
	}
	for (size_t i = 0; i < cli_n_common; i++) {
		if (cli_common_opts[i].key == key && cli_accepts(c, cli_common_opts[i].id)) {
			enum cli_opt_id id = cli_common_opts[i].id;

			return cli_is_lib_option(id) ? cli_lib_option(c, id, optarg)
			                             : cli_common_option(c, id, optarg);
		}
	}
	if (t->on_extra)
		return t->on_extra(c, key, optarg, user);
	return cli_usage_error(c, "unknown option '%s'", opt_text);
}

/* After the options: the checks across them, the network file, the device. */
static int after_options(struct cli *c)
{
	int r;

	if (c->quiet && c->verbose)
		return cli_usage_error(c, "-q and -v cannot be used together");
	if (c->station == 255 && !c->radio)
		return cli_usage_error(c, "--station 255 (broadcast) needs --duplex radio; else 0-254");
	if (c->have_forward && !c->radio)
		return cli_usage_error(c, "--forward needs --duplex radio");
	if (c->net_file && (r = cli_load_net(c)) != CLI_CONTINUE)
		return r;
	if (cli_accepts(c, CLI_OPT_DEVICE) && !c->device) {
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

int cli_parse(struct cli *c, int argc, char **argv, void *user)
{
	const struct cli_tool *t = c->tool;
	size_t n_extra = 0;
	struct option *lo;
	char shorts[256];
	int r = CLI_CONTINUE, key, idx;

	if (t->extra)
		while (t->extra[n_extra].name)
			n_extra++;
	lo = calloc(cli_n_common + n_extra + 3, sizeof *lo);
	if (!lo) {
		fprintf(stderr, "%s: out of memory\n", c->name);
		return CLI_EXIT_FAIL;
	}
	build_options(c, n_extra, lo, shorts, sizeof shorts);
	opterr = 0;
	optind = 1;
	while (r == CLI_CONTINUE && (key = getopt_long(argc, argv, shorts, lo, &idx)) != -1)
		r = one_option(c, key, argv[optind - 1], user);
	free(lo);
	if (r != CLI_CONTINUE)
		return r;
	c->argc = argc - optind;
	c->argv = argv + optind;
	return after_options(c);
}

void cli_cleanup(struct cli *c)
{
	df1_decoder_free(c->trace_dec[0]);
	df1_decoder_free(c->trace_dec[1]);
	c->trace_dec[0] = c->trace_dec[1] = NULL;
	free(c->trace_ctx);
	c->trace_ctx = NULL;
}

void cli_print_version(FILE *f, const char *tool)
{
	const struct df1_version *v = df1_version();

	/* the tool's own version: the header it was built with */
	fprintf(f, "%s (libdf1) %s\n", tool, DF1_VERSION_STRING);
	/* the library it runs with (the shared library may be newer) */
	fprintf(f, "library: libdf1 %s\n", v->string);
}
