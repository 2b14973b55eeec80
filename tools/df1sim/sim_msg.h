/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_msg - df1sim's MSG instructions (--msg, df1sim(1)): messages the
 * simulated controller sends on its own, in full duplex or as a half-duplex
 * slave, and what each got back (DN, or ER with the code), as a ladder's MSG
 * block shows it.
 */
#ifndef DF1_TOOLS_SIM_MSG_H
#define DF1_TOOLS_SIM_MSG_H
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include "df1.h"

#define SIM_MSG_MAX 8
struct sim_msg {
	bool write;             /* write: local -> remote; read: remote -> local */
	bool seq;               /* add 1 to the first local word before each write */
	char local[32], remote[32];
	int count, station, every_ms;
	int64_t next_ms;        /* df1_now_ms clock; 0: at once */
	unsigned long sent, done, errors;
};

/* Parse KIND,LOCAL,COUNT,STATION,REMOTE[,MS][,seq]; 0, or -1 with why in err. */
int sim_msg_parse(const char *spec, struct sim_msg *m, char *err, size_t cap);
/* Run the MSGs that are due on h (responder set); what each got
 * back goes to stderr and to log when not NULL. Returns ms until the next
 * one is due (at most max_ms). */
int sim_msg_run(df1_t *h, struct df1_table *t, struct sim_msg *m, int n, FILE *log, int max_ms);
#endif
