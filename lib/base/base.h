/* SPDX-License-Identifier: MPL-2.0 */
/*
 * base - what every non-pure layer above it shares and none of them owns: the
 * monotonic clock (clock.c), and the handle's last-error detail, counters and
 * catalog logging (base.c). Everything here looks down only (to proto's
 * catalog); port, link, client, server, poll and the handle look down on it.
 */
#ifndef LIBDF1_BASE_H
#define LIBDF1_BASE_H

#include <stdbool.h>
#include <stdint.h>
#include <time.h>

struct df1;

/* Monotonic clock in milliseconds / microseconds (CLOCK_MONOTONIC). */
int64_t df1_now_ms(void);
uint64_t df1_now_us(void);
/* Wall-clock time (CLOCK_REALTIME): timestamps for the caller, never deadlines. */
void df1_wall_clock(struct timespec *ts);

/* counters and logging */
void df1_count(struct df1 *h, int id);                 /* ++counter[id] */
void df1_count_n(struct df1 *h, int id, uint64_t n);
/* Log a catalog message: formats the seed's format with the arguments. */
void df1_log(struct df1 *h, int catalog_id, ...);
/* Record the last error and return code (for `return df1_fail(h, ...)`). */
int df1_fail(struct df1 *h, int code, int station, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
int df1_fail_remote(struct df1 *h, int station, uint8_t sts, uint8_t ext, bool has_ext);
/* DF1_E_CONFIG with a catalog message (its format filled with the arguments)
 * as the detail, also passed to the log callback; returns DF1_E_CONFIG. */
int df1_fail_catalog(struct df1 *h, int catalog_id, ...);
void df1_clear_error(struct df1 *h);

#endif
