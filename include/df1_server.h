/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1_server.h - the serving side of libdf1: a slave or peer that answers PCCC
 * commands through struct df1_server_ops (df1_serve(3)), a master that also
 * answers its peer or its slaves (df1_set_responder(3), df1_route_stats(3)),
 * fault injection for simulators, and the data table whose ops serve a
 * simulated or real slave's files (df1_table(3)). Installed beside df1.h,
 * which includes it; include df1.h.
 */
#ifndef LIBDF1_DF1_SERVER_H
#define LIBDF1_DF1_SERVER_H

#include "df1.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------
 * Serving (slave / peer side; df1sim is built on it)
 * ------------------------------------------------------------------------ */
struct df1_server_ops {
	/* Read nbytes of element data starting at a (whole elements, LE words).
	 * Return 0, or an EXT STS code (e.g. 0x06) to send STS F0. */
	int (*read)(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes);
	/* Write nbytes; mask is NULL, or per-byte mask for masked / bit writes. */
	int (*write)(void *user, int station, const struct df1_addr *a, const uint8_t *buf,
	             const uint8_t *mask, size_t nbytes);
	/* Diagnostic status reply bytes; return length. Optional (NULL: a generic SLC 5/04). */
	int (*diag_status)(void *user, int station, uint8_t *buf, size_t cap);
	/* Change mode; optional. */
	int (*change_mode)(void *user, int station, int mode);
	/* Any command not handled above: fill reply data, return length, or -STS. Optional. */
	int (*command)(void *user, int station, const struct df1_msg *cmd, uint8_t *reply, size_t cap);
};

/* Which stations this handle answers as (half-duplex slave may serve several). */
DF1_API int df1_server_add_station(df1_t *h, int station);
/* Run one step of the responder: wait up to timeout_ms for bytes, handle what
 * arrived (ACK, poll, command -> reply). Returns commands served (>= 0) or DF1_E_*
 * (DF1_E_CLOSED when a TCP client went away). */
DF1_API int df1_serve(df1_t *h, const struct df1_server_ops *ops, void *user, int timeout_ms);

/* Fault injection for simulators and tests (off by default). */
enum df1_fault {
	DF1_FAULT_DROP_ACK = 1,   /* do not ACK a received command */
	DF1_FAULT_CORRUPT_REPLY,  /* send a reply with a wrong BCC/CRC */
	DF1_FAULT_NAK_COMMAND,    /* answer a good command with NAK */
	DF1_FAULT_DELAY_REPLY,    /* delay the reply by value ms */
	DF1_FAULT_SILENT_STATION, /* value = station that does not answer at all,
	                           * DF1_SILENT_ALL for every station */
	DF1_FAULT_STALE_REPLY,    /* send a reply with an old TNS first */
	DF1_FAULT_NOISE,          /* garbage bytes between frames */
};
/* Probability per event in 1/1000 (0 = off); for DELAY the delay is `value` ms;
 * for SILENT_STATION `value` is the station number (-1 = none, DF1_SILENT_ALL = all). */
#define DF1_SILENT_ALL 256
DF1_API int df1_server_set_fault(df1_t *h, enum df1_fault f, int per_mille, int value);
DF1_API void df1_server_set_seed(df1_t *h, uint64_t seed);
/* Full duplex: the commands the responder accepts and has not answered yet (reply
 * queued or waiting for its ACK), answered in order; a new one beyond that is NAKed,
 * as a controller with full buffers does (doc/PROTOCOL.md 1.7). 0 (the default): one reply in
 * flight, a new command supersedes it. 0..8. @since 0.4 */
DF1_API int df1_server_set_max_queue(df1_t *h, int max_queue);
/* Full duplex: a master handle also answers its peer's commands (a PLC's MSG)
 * with ops (a df1_table's or the caller's), interleaved with its own; NULL
 * ops: STS 10h (df1_set_responder(3)). 0 or DF1_E_*. @since 0.5 */
DF1_API int df1_set_responder(df1_t *h, const struct df1_server_ops *ops, void *user);
/* Inside a struct df1_server_ops callback: the SRC of the command being answered (the
 * PLC whose MSG writes); -1 outside one (df1_server_source(3)). @since 0.5 */
DF1_API int df1_server_source(const df1_t *h);
/* A half-duplex master's slave commands run, forwarded, broadcast, replies forwarded, not
 * delivered (df1_route_stats(3); fields are only added at the end). @since 0.5 */
struct df1_route_stats { uint64_t executed, routed, broadcasts, route_replies, undeliverable; };
DF1_API int df1_route_stats(const df1_t *h, struct df1_route_stats *out);
/* Pace transmitted bytes as a line at this baud rate (0 = off). */
DF1_API int df1_set_line_baud(df1_t *h, int baud);
/* Answer one PCCC command without a link, as df1_serve() would (EtherNet/IP
 * servers, df1sim --eip): pccc[0..n) is CMD STS TNS(2) [FNC] data (no DST SRC),
 * station the station it is for (the callbacks' station argument). Writes the
 * reply CMD|40 STS TNS [EXT STS] data to reply[0..cap) and returns its length,
 * 0 when there is nothing to answer (fewer than 4 bytes, or a reply), or
 * DF1_E_INVAL / DF1_E_NOSPACE. Statuses as df1_serve(). @since 0.4 */
DF1_API int df1_serve_pccc(df1_t *h, const struct df1_server_ops *ops, void *user, int station,
                           const uint8_t *pccc, size_t n, uint8_t *reply, size_t cap);

/* The EtherNet/IP server (df1_eip_server(3)) and the client's discovery
 * (df1_eip_list_identity(3)) are declared in df1_eip.h, which this header
 * includes at its end. */

/* ------------------------------------------------------------------------
 * Data table (df1_table(3)): the files of a simulated or real slave, served
 * with df1_serve(h, df1_table_server_ops(t), t, ms) as libmodbus serves a
 * modbus_mapping_new() table. Elements are kept in the SLC wire layout of
 * df1_serve's contract (LE words and floats, ST as LEN + 82 characters, T/C/R
 * as 3 words). One table is used by one thread at a time. df1sim is built on it.
 * ------------------------------------------------------------------------ */
struct df1_table;

#define DF1_TABLE_FILES_MAX 1000        /* file numbers 0..999 */
#define DF1_TABLE_ELEMENTS_MAX 1000     /* elements 0..999 per file */
#define DF1_TABLE_ELEMENTS_DEFAULT 256  /* a file that df1_table_load() creates */

/* A new empty table (no files) for a PLC type: mode run (6), the processor of the
 * diagnostic status SLC 5/04 (slc, plc2), MicroLogix 1400, SLC 5/02 or PLC-5/40.
 * *out is owned by the caller, freed with df1_table_free(). Returns 0, DF1_E_INVAL
 * (out NULL, unknown plc) or DF1_E_NOMEM. @since 0.2 */
DF1_API int  df1_table_new(struct df1_table **out, enum df1_plc plc);
DF1_API void df1_table_free(struct df1_table *t);      /* NULL is a no-op. @since 0.2 */
/* A deep copy (files, contents, mode, processor) into a new table *out, freed with
 * df1_table_free(). 0, DF1_E_INVAL or DF1_E_NOMEM. @since 0.2 */
DF1_API int  df1_table_clone(struct df1_table **out, const struct df1_table *t);
/* Add file `number` (0..999) of `type` (O I S B T C R N F ST A L) with `elements`
 * (1..1000) elements holding their initial values (N: n, F: n + 0.5, L: n * 65536
 * + n, T/C: PRE 100, ST: "STRING n", the rest 0; element n). A file that exists
 * with this type grows to `elements` (never shrinks, contents kept); with another
 * type it is DF1_E_TYPE, unless it is a provisional file of
 * df1_table_add_default_files(), which is replaced. Returns 0, DF1_E_INVAL,
 * DF1_E_TYPE or DF1_E_NOMEM. @since 0.2 */
DF1_API int  df1_table_add_file(struct df1_table *t, enum df1_file_type type, int number, int elements);
/* The files every SLC has, O0 I1 S2 B3 T4 C5 R6 N7 F8, plus ST9 L10 A11, of 256
 * elements each (df1sim's table); ST9 L10 A11 are provisional: a file of another
 * type given to df1_table_add_file() or df1_table_load() replaces them (N9, the
 * SLC's common interface file for PLC-2 commands). 0 or as df1_table_add_file().
 * @since 0.2 */
DF1_API int  df1_table_add_default_files(struct df1_table *t);
/* Elements of file `number` (> 0) and, if type is not NULL, its type; DF1_E_ADDR_RANGE
 * if the table has no such file, DF1_E_INVAL. @since 0.2 */
DF1_API int  df1_table_file(const struct df1_table *t, int number, enum df1_file_type *type);
/* n values from address addr on ("N7:0", "B3:0/5", "T4:1.ACC", "ST9:0"), as
 * df1_value kinds of df1_addr_value_kind(); several go to consecutive elements
 * (consecutive bits for a bit address, into the next element after bit 15, 31 for
 * L; the same sub-element of consecutive elements). The file must exist with the
 * address's type and hold every element; a write checks every value before it
 * stores any (kind DF1_E_TYPE, string length DF1_E_RANGE). Returns n, or
 * DF1_E_ADDR_SYNTAX, DF1_E_ADDR_RANGE (no such file or element), DF1_E_TYPE,
 * DF1_E_RANGE, DF1_E_INVAL; df1_table_error_text() tells what. @since 0.2 */
DF1_API int  df1_table_read(struct df1_table *t, const char *addr, struct df1_value *out, size_t n);
DF1_API int  df1_table_write(struct df1_table *t, const char *addr, const struct df1_value *in, size_t n);
DF1_API int  df1_table_read_addr(struct df1_table *t, const struct df1_addr *a, struct df1_value *out, size_t n);
DF1_API int  df1_table_write_addr(struct df1_table *t, const struct df1_addr *a, const struct df1_value *in,
                                  size_t n);
/* The processor the diagnostic status reply names: "slc500", "slc5/01" .. "slc5/05",
 * "slc5/04l541", "ml1000" .. "ml1500", "ml1500lrp" ("MicroLogix 1400" too), "plc5/10"
 * .. "plc5/80e" (case, blanks, '-' and '_' ignored), or a type code 0..255 ("0x5B";
 * the EB form for a PLC-5 table, else EE). 0 or DF1_E_INVAL. @since 0.2 */
DF1_API int  df1_table_set_processor(struct df1_table *t, const char *name);
/* The mode: 1 program, 6 run, 7 test continuous, 8 test single scan (what 0F/80
 * sets and the diagnostic status reports). set: 0 or DF1_E_INVAL. @since 0.2 */
DF1_API int  df1_table_mode(const struct df1_table *t);
DF1_API int  df1_table_set_mode(struct df1_table *t, int mode);
/* Load values from a text file, df1sim's --data format: ADDRESS=VALUE[,VALUE...]
 * per line, '#' comments, strings in double quotes (\" \\ \xHH inside). A file
 * a line names that does not exist is created with 256 elements; files grow to
 * the highest element assigned (at most 999). All or nothing: on error the table
 * is unchanged and df1_table_error_text() says "PATH:LINE: what is wrong".
 * Returns 0, DF1_E_SYS (cannot open or read: errno is kept), DF1_E_CONFIG (a bad
 * line), DF1_E_NOMEM, DF1_E_INVAL. @since 0.2 */
DF1_API int  df1_table_load(struct df1_table *t, const char *path);
/* Write every element of every file in that format, so that df1_table_load()
 * restores them. Through a temporary file in the same directory, renamed over
 * path: path is never left half written. 0, DF1_E_SYS (errno kept), DF1_E_INVAL.
 * @since 0.2 */
DF1_API int  df1_table_save(struct df1_table *t, const char *path);
/* The detail of the last failure of a df1_table_* call on t ("" if none). Owned by
 * t, valid until the next call on it. @since 0.2 */
DF1_API const char *df1_table_error_text(const struct df1_table *t);
/* The callbacks that serve t: pass t as df1_serve()'s user pointer. Reads, writes,
 * masked and bit writes of every command set, the diagnostic status of the chosen
 * processor (PLC-5 EB form: the station as DH+ node), change mode. Static, never
 * to be freed; NULL if t is NULL. @since 0.2 */
DF1_API const struct df1_server_ops *df1_table_server_ops(const struct df1_table *t);

#ifdef __cplusplus
}
#endif

#endif /* LIBDF1_DF1_SERVER_H */
