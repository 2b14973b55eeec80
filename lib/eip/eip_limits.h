/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip_limits - when the EtherNet/IP server closes a connection on its own
 * (df1_eip_server_set_limits(3), df1-eip(7) "Limits"): a connection without a
 * session past register_ms, a session idle past idle_ms, and which connection
 * makes room when the table is full. Pure: the caller gives the times (ms of
 * one monotonic clock); lib/eip/eip_server.c keeps the clock and the sockets.
 */
#ifndef LIBDF1_EIP_LIMITS_H
#define LIBDF1_EIP_LIMITS_H

#include <stdbool.h>
#include <stdint.h>

#include "df1.h"

#define EIP_REGISTER_MS_DEFAULT 5000
#define EIP_IDLE_MS_DEFAULT 120000      /* ODVA's encapsulation inactivity timeout, 120 s */
#define EIP_LIMIT_MS_MAX 3600000        /* the attribute's range ends at 3600 s */
#define EIP_NO_DEADLINE INT64_MAX

struct eip_limits {
	int register_ms, idle_ms;       /* -1: no limit */
	bool no_evict;
};

/* What the limits look at in one connection. */
struct eip_age {
	int64_t opened_ms;              /* accepted */
	int64_t last_ms;                /* its last message, or its last answer */
	bool registered;
	bool busy;                      /* a request of it is with the caller: never closed for time */
};

/* l from the caller's (0: default); -1 if a value is out of range. */
int eip_limits_from(struct eip_limits *l, const struct df1_eip_server_limits *in);
/* The reason a is due to close at now (DF1_EIP_CLOSE_NO_SESSION, _IDLE) or -1;
 * when -1, *next is lowered to a's deadline (EIP_NO_DEADLINE: none). */
int eip_age_due(const struct eip_limits *l, const struct eip_age *a, int64_t now, int64_t *next);
/* Is a to be evicted before b? A connection without a session goes first,
 * then the one idle the longest; a busy one never (false). */
bool eip_age_before(const struct eip_age *a, const struct eip_age *b);

#endif
