/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_receive - df1gw's own data table (df1gw(1), RECEIVE): the mapping rows
 * whose Command is Receive are regions of it that PLCs write (and read) with
 * MSG. The table answers on the line as df1gw's station: through
 * df1_set_responder() on a master handle (full duplex, Mode Peer), or
 * through df1_serve() on a half-duplex slave handle (--duplex half-slave,
 * Mode Slave). Each write a PLC makes into a region is published on its
 * tag's topic at once, with the sending station; a write from MQTT to such a
 * tag changes the table only, never the line. The rows as data (struct
 * gw_rx, a row's state as told) are gw_rx_table.h's.
 */
#ifndef DF1_TOOLS_GW_RECEIVE_H
#define DF1_TOOLS_GW_RECEIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "df1.h"
#include "df1gw/gw_rx_table.h"

#define GW_RX_TICK_MS 50     /* the loop's longest wait while the table serves */

struct gw;
struct gw_fmt;
struct gw_tag_out;
struct gw_station_out;
struct gw_write_in;

/* The Receive rows of the mapping file into g->rx, checked (Station is our
 * own, names are topic levels and not also polled tags of h), and the table
 * made. 0, or the exit status having said why. */
int gw_rx_load(struct gw *g, df1_t *h);
/* The table answers on h (open or not): its responder, or its station. */
int gw_rx_attach(struct gw *g, df1_t *h);
/* Is name a Receive tag? */
bool gw_rx_has(const struct gw *g, const char *name);
/* The line's descriptor when the table must be served between polls, or -1. */
int gw_rx_fd(const struct gw *g);
/* Serve what waits on the line (readable: bytes came; else the reply's
 * timers only). 0 or DF1_E_*. */
int gw_rx_serve(struct gw *g, bool readable);
/* Every Receive tag as it is now (a connect, --refresh). */
void gw_rx_publish_all(struct gw *g);
/* Sparkplug (a session format) sees Receive tag i as tag id g->ntags + i of
 * the device of df1gw's own station: its state (false: no such tag), and
 * that station's health (false: not the Receive station, or it is polled). */
bool gw_rx_node_tag(struct gw *g, int i, struct df1_tag_state *st, struct gw_tag_out *t);
bool gw_rx_node_station(struct gw *g, int stn, struct gw_station_out *s, struct df1_station_health *sh);
/* A write from format f's topic to Receive tag name: into the table, one
 * result. false when name is not a Receive tag (nothing done, in kept). */
bool gw_rx_write(struct gw *g, const struct gw_fmt *f, const char *name, struct gw_write_in *in, bool retain);
void gw_rx_free(struct gw_rx *rx);

#endif
