/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_handle - the handle of a tool: built from the options, opened, closed;
 * -v logging and the -vv frame trace (see cli.h).
 */
#include "common/cli_int.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "common/decode.h"

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
	/* and every symbol they complete; EtherNet/IP bytes are no DF1 symbols */
	if (c->device && strncasecmp(c->device, "eip:", 4) == 0)
		return;
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
		cli_decoder_options(c, d);
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

	cli_error_parts(h, r, tag, sizeof tag, text, sizeof text);
	fprintf(stderr, "%s: %s: %s: %s\n", c->name, what, tag, text);
	return CLI_EXIT_USAGE;
}

int cli_configure(struct cli *c, df1_t **out)
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
	if (c->have_net && c->net.mode == DF1_MODE_SLAVE && !(c->given & CLI_ACCEPT(CLI_OPT_DUPLEX)) &&
	    !c->half_slave) {
		const struct df1_catalog_entry *e = df1_catalog_by_id(DF1_ID_CRT_UNSUPPORTED_MODE);
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
	SET("--duplex", df1_set_duplex(h, c->radio ? DF1_RADIO_MODEM
	                                 : c->half_slave ? DF1_HALF_DUPLEX_SLAVE
	                                 : c->half_duplex ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX));
	if (c->have_forward)
		SET("--forward", df1_set_forward(h, c->forward));
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
	if (cli_apply_lib_options(c, h) != 0) {
		df1_free(h);
		return CLI_EXIT_USAGE;
	}
	if (!c->quiet && c->verbose >= 1)
		df1_set_log(h, cli_log, c);
	if (!c->quiet && c->verbose >= 2)
		df1_set_trace(h, cli_trace, c);
	fd = cli_signal_fd();
	if (fd >= 0)
		df1_set_cancel_fd(h, fd);
	*out = h;
	return CLI_EXIT_OK;
}

int cli_open(struct cli *c, df1_t **out)
{
	df1_t *h;
	int r = cli_configure(c, out);

	if (r != CLI_EXIT_OK)
		return r;
	h = *out;
	*out = NULL;
	r = df1_open(h, c->device);
	if (r < 0) {
		char tag[96], text[256];
		size_t tl, dl = strlen(c->device);
		cli_error_parts(h, r, tag, sizeof tag, text, sizeof text);
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
