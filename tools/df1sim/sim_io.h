/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_io - df1sim's input and output beside the simulated PLC of df1sim.c:
 * the transports it serves on (a pseudo-terminal behind a symbolic link, a
 * TCP listener), its --log command log (one line per command answered, from
 * the frame trace) and the fault probabilities of its options (numbers are
 * cli.h's cli_long_in, cli_parse_int; its signals cli.h's
 * cli_signals_install_mute). Uses only include/df1.h and tools/common/cli.h.
 */
#ifndef DF1_TOOLS_SIM_IO_H
#define DF1_TOOLS_SIM_IO_H

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include "df1.h"

/* A probability in percent, "0".."100", decimals allowed ("0.5", "2.5%"), as per
 * mille (the library's unit), rounded. */
bool sim_parse_percent(const char *s, int *per_mille);

/* A pseudo-terminal with a symbolic link to its slave side. The tool keeps its
 * own raw descriptor on the slave side, so the master never sees a hangup
 * between clients; a stale link from an earlier run is replaced, any other
 * file at the path is refused. Returns 0, or an exit status (1 system, 2 the
 * path) with the message in err. */
struct sim_pty {
	int master, slave;
	char slave_name[128];
	const char *link;
	bool linked;
};
int sim_pty_create(struct sim_pty *p, const char *path, char *err, size_t cap);
/* Close the slave descriptor and remove the link if it is still ours (not the master). */
void sim_pty_destroy(struct sim_pty *p);

/* Listen on "tcp://HOST:PORT", "HOST:PORT", ":PORT", "PORT", "[::1]:PORT"
 * (loopback unless HOST is given; port 0 picks one). Every interface only when
 * HOST is written 0.0.0.0 or ::, never for inet_aton's other spellings of it
 * ("0", "0.0", "0x0": a usage error). Returns the socket with the address as
 * bound in shown ("tcp://127.0.0.1:40001") and, if scope is not NULL, what it
 * reaches in *scope; or -(exit status) with the message in err. */
enum sim_listen_scope { SIM_LISTEN_LOOPBACK, SIM_LISTEN_OTHER, SIM_LISTEN_ALL };
int sim_listen_open(const char *spec, char *shown, size_t cap, enum sim_listen_scope *scope,
                    char *err, size_t ecap);

/* The command log: one line per command answered,
 *   2026-12-01T21:02:28.123 station=1 cmd=0F/A2 addr=N7:0 count=10 tns=0001 name="..."
 * fed with the bytes of the frame trace both ways; a command is logged when its
 * reply goes out (once, however often the link repeats it). tables[station] is
 * the table of each station served (NULL: not served; with by_station, half
 * duplex and radio modem, a command to another station is not logged),
 * tables[first_station] the one of other DSTs (full duplex); they give the
 * type of a PLC-5 binary address's file. */
struct sim_cmdlog {
	FILE *fp;
	int error;                      /* errno of the first line not written, else 0 */
	struct df1_decoder *dec[2];     /* by enum df1_dir */
	bool half;
	bool by_station;                /* only commands to the stations served */
	struct df1_table *const *tables;
	int first_station;
	enum df1_plc plc;               /* the address text of the log (PLC-3's own) */
	struct {
		bool used, logged;
		int station;
		uint8_t app[300];
		size_t n;
	} ring[16];
	int next;
};
/* Open path (truncated). 0, -1 (fopen failed, errno set) or -2 (no memory). */
int sim_cmdlog_open(struct sim_cmdlog *l, const char *path, enum df1_check check, bool half,
                    bool by_station, struct df1_table *const *tables, int first_station);
void sim_cmdlog_close(struct sim_cmdlog *l);    /* a log never opened is fine */
void sim_cmdlog_feed(struct sim_cmdlog *l, enum df1_dir dir, const uint8_t *bytes, size_t n);
/* Log a command answered without a link (EtherNet/IP): app = DST SRC CMD STS
 * TNS [FNC] data. A log never opened is fine. */
void sim_cmdlog_command(struct sim_cmdlog *l, int station, const uint8_t *app, size_t n);

#endif
