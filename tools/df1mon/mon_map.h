/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_map - df1mon --map: poll the tags of a mapping CSV with the poll engine
 * and show them (tools/df1mon/mon_map.c). Uses only include/df1.h.
 */
#ifndef DF1_TOOLS_MON_MAP_H
#define DF1_TOOLS_MON_MAP_H

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include "df1.h"

#define MON_MAP_PLAIN 0
#define MON_MAP_CSV 1
#define MON_MAP_JSON 2
#define MON_MAP_INFLUX 3

/*
 * Load csv_path into the open handle h (df1_tag_load_map: strict, so a row
 * that cannot be used refuses the file with its line and item on stderr, as
 * df1gw does; skip_bad_rows: such rows are reported and skipped) and poll
 * until *stop:
 *  - format 0 (plain): a table TAG STN ADDRESS VALUE QUALITY AGE after every
 *    scan, the screen cleared first (ANSI) only when stdout is a terminal, then
 *    a line of scan statistics;
 *  - format 1 (csv): "t,scan,tag,station,address,value,quality,reason,age_ms",
 *    one row per tag per scan; format 2 (json): one JSON object per tag per scan;
 *    format 3 (influx): one InfluxDB line per readable tag per scan
 *    (mon_influx.c), stamped with the scan's wall-clock time;
 *  - once: one scan, then exit;
 *  - counters: the seed counter table (ID MNEMONIC VALUE) and the scan statistics
 *    every interval_ms and at exit (on a terminal: with every redraw); in csv
 *    as "# " comment lines, in json as {"t":..,"counters":[...]} objects, in
 *    influx as a "df1_link" line;
 * Returns the exit status: 0; 1 communication error, or a readable tag BAD at
 * the end of a one-shot scan; 2 configuration error (file, no valid tag).
 */
/* mon_influx.c: one tag's line; the scan statistics and counters' line. */
void mon_influx_tag(FILE *f, const struct df1_tag_state *st, int64_t now_ns);
void mon_influx_counters(FILE *f, df1_t *h, int64_t now_ns);

int mon_map_run(df1_t *h, const char *csv_path, bool skip_bad_rows, int format, bool once, bool counters,
                int interval_ms, volatile sig_atomic_t *stop);

#endif
