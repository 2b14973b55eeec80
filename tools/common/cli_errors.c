/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_errors - exit status and error reports in the catalog format
 * ("[2508] ERR_COMMAND_TIMEOUT: text", see cli.h).
 */
#include "common/cli_int.h"

#include <string.h>

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
void cli_error_parts(const df1_t *h, int err, char *tag, size_t tcap, char *text, size_t xcap)
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

int cli_report(const char *tool, const char *address, int station, const df1_t *h, int err)
{
	const struct df1_error_detail *d = h ? df1_last_error(h) : NULL;
	char tag[96], text[256];

	cli_error_parts(h, err, tag, sizeof tag, text, sizeof text);
	/* the library names the address an error concerns in its own field */
	if (!address && d && d->code == err && d->address[0])
		address = d->address;
	fprintf(stderr, "%s: ", tool);
	if (address)
		fprintf(stderr, "%s: ", address);
	if (station >= 0)
		fprintf(stderr, "station %d: ", station);
	fprintf(stderr, "%s: %s\n", tag, text);
	return cli_exit_status(err);
}

void cli_error_text(const df1_t *h, int err, char *buf, size_t cap)
{
	char tag[96], text[256];

	cli_error_parts(h, err, tag, sizeof tag, text, sizeof text);
	snprintf(buf, cap, "%s: %s", tag, text);
}
