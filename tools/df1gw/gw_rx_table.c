/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_rx_table - the Receive rows as data (see gw_rx_table.h).
 */
#include "df1gw/gw_rx_table.h"

#include <stdlib.h>
#include <string.h>

bool gw_rx_tag_state(const struct gw_rx *rx, int ntags, const char *name, struct df1_tag_state *cur)
{
	for (size_t i = 0; i < rx->n; i++) {
		if (strcmp(rx->v[i].c.name, name) != 0)
			continue;
		memset(cur, 0, sizeof *cur);
		cur->id = ntags + (int)i;
		cur->config = &rx->v[i].shown;
		cur->count = (size_t)rx->v[i].c.count;
		return true;
	}
	return false;
}

int gw_rx_row_state(struct gw_rx *rx, int ntags, const struct gw_rx_tag *e, bool told, struct df1_tag_state *st,
                    struct df1_value *vals, const char **reason)
{
	int n = df1_table_read_addr(rx->t, &e->c.addr, vals, (size_t)e->c.count);

	if (n < 0)
		return n;
	memset(st, 0, sizeof *st);
	st->id = ntags + (int)(e - rx->v);   /* Sparkplug's record of what it told */
	st->config = &e->shown;
	st->count = (size_t)n;
	st->values = vals;
	st->value = vals[0];
	st->last_good_wall_ms = e->wall_ms;
	st->age_ms = -1;
	*reason = NULL;
	if (told && !e->written) {
		/* the zeros of the table, not a controller's message */
		st->has_value = false;
		st->quality = DF1_QUALITY_UNCERTAIN;
		st->reason = DF1_REASON_NONE;
		*reason = GW_RX_REASON_UNWRITTEN;
		return 0;
	}
	st->has_value = true;
	st->quality = DF1_QUALITY_GOOD;
	st->reason = DF1_REASON_NONE;
	return 0;
}

int gw_rx_zero(struct gw_rx *rx)
{
	const struct df1_server_ops *ops = df1_table_server_ops(rx->t);

	for (size_t i = 0; i < rx->n; i++) {
		const struct gw_rx_tag *e = &rx->v[i];
		struct df1_addr a = e->c.addr;
		size_t nbytes = e->hi - e->lo;
		uint8_t *zeros = calloc(nbytes ? nbytes : 1, 1);
		int rc;

		if (!zeros)
			return DF1_E_NOMEM;
		a.element = (int)(e->lo / (size_t)df1_file_type_element_size(a.type));
		a.sub = DF1_ADDR_NONE;
		a.bit = DF1_ADDR_NONE;
		rc = ops->write(rx->t, rx->station, &a, zeros, NULL, nbytes);
		free(zeros);
		if (rc)
			return rc > 0 ? DF1_E_RANGE : rc;
	}
	return 0;
}
