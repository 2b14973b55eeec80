/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_bdseq - where Sparkplug's bdSeq is kept across restarts (df1gw(1),
 * SPARKPLUG and FILES), so that a df1gw started again (kill -9, a reboot,
 * systemd's Restart=) births with the next bdSeq and a host can tell the new
 * session from the old one whose will (NDEATH) may arrive late.
 *
 * By default one file per group and edge node in the state folder:
 * $STATE_DIRECTORY (systemd's StateDirectory=, the first of its list), else
 * $XDG_STATE_HOME/df1gw, else $HOME/.local/state/df1gw; --sparkplug-state
 * FILE names the file instead. The file holds one line "bdSeq N", the
 * bdSeq of the last connect; it is replaced whole (a temporary file beside
 * it, fsync, rename, fsync of the folder) before the CONNECT that uses N.
 * Pure: files only, no struct gw (gw_pub.c wires it).
 */
#ifndef DF1_TOOLS_GW_BDSEQ_H
#define DF1_TOOLS_GW_BDSEQ_H

#include <stdbool.h>
#include <stddef.h>

#define GW_BDSEQ_SUFFIX ".bdseq"

/* The default state folder into out, from the environment as above; 0, or
 * -1 when none can be named (no HOME either), out then empty. */
int gw_bdseq_dir(char *out, size_t cap);

/* The file of group and edge node in dir: dir/GROUP@EDGE.bdseq, where every
 * byte of the ids but A-Z a-z 0-9 '-' '_' '.' is %XX (so '@' parts them,
 * and no two pairs share a file). 0, or -1 (it does not fit cap, or the
 * name is longer than a file name may be). */
int gw_bdseq_path(const char *dir, const char *group, const char *edge, char *out, size_t cap);

/* dir and its missing parents made (mode 0700), and dir writable. 0, or
 * -1 with errno (of the part that failed). */
int gw_bdseq_mkdir(const char *dir);

/* The bdSeq in path into *last: 1 read, 0 no such file, -1 with errno
 * (EINVAL: not a "bdSeq N" line with N 0-255). */
int gw_bdseq_read(const char *path, unsigned *last);

/* path replaced by "bdSeq N" atomically and durably. 0, or -1 with errno. */
int gw_bdseq_write(const char *path, unsigned bdseq);

#endif
