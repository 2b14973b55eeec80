/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_net - -N FILE: the network configuration CSV, its issues reported in
 * the catalog format, its values taken for options not given (see cli.h).
 */
#include "common/cli_int.h"

#include <errno.h>
#include <string.h>

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
int cli_load_net(struct cli *c)
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
	TAKE(CLI_OPT_DUPLEX, radio, k->radio);
	/* Mode Slave: the tool is a slave station where it can be one (df1gw) */
	TAKE(CLI_OPT_DUPLEX, half_slave, c->tool->half_slave && k->mode == DF1_MODE_SLAVE);
	TAKE(CLI_OPT_PLC, plc, k->plc);
	TAKE(CLI_OPT_TIMEOUT, timeout_ms, k->timeout_ms);
	TAKE(CLI_OPT_CMD_TIMEOUT, cmd_timeout_ms, k->cmd_timeout_ms);
	TAKE(CLI_OPT_NAK_RETRIES, nak_retries, k->nak_retries);
	TAKE(CLI_OPT_ENQ_RETRIES, enq_retries, k->enq_retries);
	TAKE(CLI_OPT_TX_DELAY, tx_delay_ms, k->tx_delay_ms);
	/* Store_Forward (Link Radio): the --forward of the file, unless given */
	if (!(c->given & CLI_ACCEPT(CLI_OPT_FORWARD)) && k->forward_set && c->radio) {
		memcpy(c->forward, k->forward, sizeof c->forward);
		c->have_forward = true;
	}
	/* a decoder's AUTO default is kept: the file's check only replaces a link default */
	if (!(c->given & CLI_ACCEPT(CLI_OPT_CHECK)) && c->check != DF1_CHECK_AUTO)
		c->check = k->check;
#undef TAKE
	return CLI_CONTINUE;
}
