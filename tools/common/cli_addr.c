/* SPDX-License-Identifier: MPL-2.0 */
/*
 * cli_addr - operand addresses: value i of an operand, address errors (see cli.h).
 */
#include "common/cli_int.h"

bool cli_is_tcr(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R;
}

bool cli_is_io(enum df1_file_type t)
{
	return t == DF1_FT_I || t == DF1_FT_O;
}

bool cli_addr_step(enum df1_plc plc, const struct df1_addr *a, size_t i, struct df1_addr *out)
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
	return df1_addr_format_plc(plc, out, buf, sizeof buf) > 0;
}

int cli_address_error(const struct cli *c, int item, const char *text, int err, size_t n)
{
	int id = err == DF1_E_ADDR_RANGE ? DF1_ID_ERR_ADDRESS_RANGE : DF1_ID_ERR_ADDRESS_SYNTAX;
	const struct df1_catalog_entry *e = df1_catalog_by_id(id);

	fprintf(stderr, "%s: %s: [%d] %s: Item: %d, ", c->name, text, id, e ? e->mnemonic : "?", item);
	if (id == DF1_ID_ERR_ADDRESS_RANGE)
		fprintf(stderr, "Address is out of range (%s, len=%zu)\n", text, n);
	else
		fprintf(stderr, "Invalid Address Syntax (%s)\n", text);
	return CLI_EXIT_USAGE;
}
