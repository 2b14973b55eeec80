/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip_limits.c - the EtherNet/IP server's time limits and eviction order
 * (eip_limits.h): decisions only; the server applies them.
 */
#include "eip/eip_limits.h"

static int limit_ms(int v, int dflt)
{
	if (v == 0)
		return dflt;
	if (v == -1)
		return -1;
	return v > 0 && v <= EIP_LIMIT_MS_MAX ? v : -2;
}

int eip_limits_from(struct eip_limits *l, const struct df1_eip_server_limits *in)
{
	int r = limit_ms(in->register_ms, EIP_REGISTER_MS_DEFAULT);
	int i = limit_ms(in->idle_ms, EIP_IDLE_MS_DEFAULT);

	if (r == -2 || i == -2)
		return -1;
	l->register_ms = r;
	l->idle_ms = i;
	l->no_evict = in->no_evict;
	return 0;
}

int eip_age_due(const struct eip_limits *l, const struct eip_age *a, int64_t now, int64_t *next)
{
	int64_t at;
	int why;

	if (a->busy)
		return -1;
	if (!a->registered && l->register_ms >= 0) {
		at = a->opened_ms + l->register_ms;
		why = DF1_EIP_CLOSE_NO_SESSION;
	} else if (a->registered && l->idle_ms >= 0) {
		at = a->last_ms + l->idle_ms;
		why = DF1_EIP_CLOSE_IDLE;
	} else {
		return -1;
	}
	if (now >= at)
		return why;
	if (at < *next)
		*next = at;
	return -1;
}

bool eip_age_before(const struct eip_age *a, const struct eip_age *b)
{
	if (a->busy)
		return false;
	if (b->busy)
		return true;
	if (a->registered != b->registered)
		return !a->registered;
	return a->last_ms < b->last_ms;
}
