/* SPDX-License-Identifier: MPL-2.0 */
/*
 * shadow.c - the values a data-table element may hold (soak.h). A write whose
 * result is unknown (it failed: timed out, NAK limit ...) may have run or not;
 * both are honest, so both values stay possible until a read settles it.
 */
#include "soak.h"

void shadow_set(struct shadow_cell *c, int32_t v)
{
	c->n = 1;
	c->v[0] = v;
}

void shadow_maybe(struct shadow_cell *c, int32_t v)
{
	if (c->n == 0)
		return;                 /* anything already */
	for (int i = 0; i < c->n; i++)
		if (c->v[i] == v)
			return;
	if (c->n == SHADOW_MAX) {
		c->n = 0;               /* too many unknowns: accept the next read */
		return;
	}
	c->v[c->n++] = v;
}

bool shadow_possible(const struct shadow_cell *c, int32_t v)
{
	if (c->n == 0)
		return true;
	for (int i = 0; i < c->n; i++)
		if (c->v[i] == v)
			return true;
	return false;
}

bool shadow_seen(struct shadow_cell *c, int32_t v)
{
	bool ok = shadow_possible(c, v);

	shadow_set(c, v);       /* what the PLC holds now, right or wrong */
	return ok;
}
