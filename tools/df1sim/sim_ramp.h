/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_ramp - df1sim's --ramp ADDR[,STEP][@MS] (df1sim(1)): values that change
 * on their own, so that a poller or df1gw sees changes without a second
 * master. A ramp adds STEP to ADDR every MS ms (a bit toggles); it is applied
 * when a command reads, by the steps due since the last time, so no timer is
 * needed and a value written by a master goes on from what was written.
 */
#ifndef DF1_TOOLS_SIM_RAMP_H
#define DF1_TOOLS_SIM_RAMP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1.h"

#define SIM_RAMP_MAX 16
#define SIM_RAMP_DEFAULT_MS 100

struct sim_ramp {
	char text[48];            /* ADDR as given */
	struct df1_addr a;
	double step;              /* default 1 */
	int ms;                   /* default SIM_RAMP_DEFAULT_MS */
	int64_t last_ms;          /* the clock of the last step applied */
};

struct sim_ramps {
	struct sim_ramp r[SIM_RAMP_MAX];
	int n;
};

/* Adds ramp arg ("N7:0", "N7:0,5", "F8:1,0.5@250", "B3:0/2@1000"). true, or
 * false with err saying what is wrong. */
bool sim_ramp_parse(struct sim_ramps *rs, const char *arg, char *err, size_t cap);
/* Checks each ramp against table t of PLC plc (an existing word, L, F or
 * bit; an integer STEP for words and L) and starts its clock. 0, or -1 with
 * err. */
int sim_ramp_start(struct sim_ramps *rs, enum df1_plc plc, struct df1_table *t, char *err, size_t cap);
/* The steps due by now on tables[stations[0..n)]. */
void sim_ramp_apply(struct sim_ramps *rs, struct df1_table *const *tables, const int *stations, int n);

#endif
