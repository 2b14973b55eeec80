/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_ramp.c - df1sim's --ramp (sim_ramp.h, df1sim(1)): the option's parsing
 * and checks, and the steps applied to the data tables as commands read.
 */
#include "df1sim/sim_ramp.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int64_t ramp_now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

bool sim_ramp_parse(struct sim_ramps *rs, const char *arg, char *err, size_t cap)
{
	struct sim_ramp *r;
	char buf[128], *at, *comma, *end;

	if (rs->n >= SIM_RAMP_MAX) {
		snprintf(err, cap, "at most %d ramps", SIM_RAMP_MAX);
		return false;
	}
	r = &rs->r[rs->n];
	memset(r, 0, sizeof *r);
	r->step = 1;
	r->ms = SIM_RAMP_DEFAULT_MS;
	if (strlen(arg) >= sizeof buf)
		goto bad;
	strcpy(buf, arg);
	at = strchr(buf, '@');
	if (at) {
		*at++ = '\0';
		errno = 0;
		long ms = strtol(at, &end, 10);
		if (errno || end == at || *end || ms < 1 || ms > 3600000)
			goto bad;
		r->ms = (int)ms;
	}
	comma = strchr(buf, ',');
	if (comma) {
		*comma++ = '\0';
		errno = 0;
		r->step = strtod(comma, &end);
		if (errno || end == comma || *end || !isfinite(r->step))
			goto bad;
	}
	if (!buf[0] || strlen(buf) >= sizeof r->text)
		goto bad;
	strcpy(r->text, buf);
	rs->n++;
	return true;
bad:
	snprintf(err, cap, "ADDR[,STEP][@MS]: an address, a number, 1-3600000 ms (e.g. N7:0,1@100)");
	return false;
}

int sim_ramp_start(struct sim_ramps *rs, enum df1_plc plc, struct df1_table *t, char *err, size_t cap)
{
	int64_t now = ramp_now_ms();

	for (int i = 0; i < rs->n; i++) {
		struct sim_ramp *r = &rs->r[i];
		struct df1_value v;
		if (df1_addr_parse_plc(plc, r->text, &r->a) < 0) {
			snprintf(err, cap, "--ramp %s: not an address", r->text);
			return -1;
		}
		enum df1_value_kind k = df1_addr_value_kind(&r->a);
		if (k != DF1_VAL_INT16 && k != DF1_VAL_INT32 && k != DF1_VAL_FLOAT && k != DF1_VAL_BIT) {
			snprintf(err, cap, "--ramp %s: a word, an L, an F or a bit only", r->text);
			return -1;
		}
		if ((k == DF1_VAL_INT16 || k == DF1_VAL_INT32) && r->step != floor(r->step)) {
			snprintf(err, cap, "--ramp %s: an integer STEP for an integer address", r->text);
			return -1;
		}
		if (df1_table_read_addr(t, &r->a, &v, 1) < 0) {
			snprintf(err, cap, "--ramp %s: %s", r->text, df1_table_error_text(t));
			return -1;
		}
		r->last_ms = now;
	}
	return 0;
}

/* Value v after ticks steps of r (an integer word wraps as a PLC's does). */
static void ramp_step(const struct sim_ramp *r, struct df1_value *v, int64_t ticks)
{
	switch (v->kind) {
	case DF1_VAL_INT16:
		v->v.i16 = (int16_t)(uint16_t)((uint64_t)(uint16_t)v->v.i16 + (uint64_t)((int64_t)r->step * ticks));
		break;
	case DF1_VAL_INT32:
		v->v.i32 = (int32_t)(uint32_t)((uint64_t)(uint32_t)v->v.i32 + (uint64_t)((int64_t)r->step * ticks));
		break;
	case DF1_VAL_FLOAT:
		v->v.f = (float)(v->v.f + r->step * (double)ticks);
		break;
	case DF1_VAL_BIT:
		v->v.bit = (ticks & 1) ? !v->v.bit : v->v.bit;
		break;
	default:
		break;
	}
}

void sim_ramp_apply(struct sim_ramps *rs, struct df1_table *const *tables, const int *stations, int n)
{
	if (!rs->n)
		return;
	int64_t now = ramp_now_ms();
	for (int i = 0; i < rs->n; i++) {
		struct sim_ramp *r = &rs->r[i];
		int64_t ticks = (now - r->last_ms) / r->ms;
		if (ticks <= 0)
			continue;
		r->last_ms += ticks * r->ms;
		for (int s = 0; s < n; s++) {
			struct df1_table *t = tables[stations[s]];
			struct df1_value v;
			if (!t || df1_table_read_addr(t, &r->a, &v, 1) < 0)
				continue;
			ramp_step(r, &v, ticks);
			(void)df1_table_write_addr(t, &r->a, &v, 1);
		}
	}
}
