/* SPDX-License-Identifier: MPL-2.0 */
/*
 * client_int.h - the client's internals, shared by the files of lib/client
 * (doc/ARCHITECTURE.md 3): the master side, df1_read / df1_write and friends.
 * address + values -> PCCC command(s) -> link_transact -> reply -> values.
 * Not installed.
 *
 * Files (each calls only files listed before it, never back):
 *   transact.c    classification, error recording, one transaction, element
 *                 sinks and sources
 *   slc.c         SLC 5/03+, MicroLogix, SLC 5/01-5/02 reads and writes (0F/A2, 0F/AA)
 *   plc5.c        PLC-5 typed reads and writes (0F/68, 0F/67)
 *   plc2.c        PLC-2 reads and writes (01, 08)
 *   plc3.c        PLC-3 word range reads and writes (0F/01, 0F/00)
 *   elements.c    spans dispatched by PLC type (a read packet by packet: the
 *                 family builds each command, one transaction, the family takes
 *                 its reply; the first packet may be the caller's: client.h's
 *                 client_read_raw_cmd / client_read_raw_reply), bits, element
 *                 reads and writes
 *   api.c         the public read and write calls, and client.h's internal ones
 *   diag.c        any PCCC command, diagnostic status, echo, link test, change mode
 *   read_multi.c  df1_read_multi()
 *
 * The PLC type (h->cfg.plc) picks the command set (doc/PROTOCOL.md 4):
 *
 *   SLC 5/03+, MicroLogix, SLC 5/01-5/02:
 *     read 0F/A2, write 0F/AA (three address fields: file, type, element, sub);
 *     bit writes 0F/AB (mask + data: only the masked bits change). O and I go
 *     as type codes 8B/8C (doc/PROTOCOL.md 4.11), or 82/83 with DF1_OPT_SLC_IO_CODES_82
 *     [SRC-CONFLICT, doc/PROTOCOL.md 8 item 10].
 *   PLC-5:
 *     read 0F/68, write 0F/67 (typed, counts in elements) with a logical binary
 *     address (06 file element, 0E with a sub-element) or, for "$N7:0", the
 *     logical ASCII form; bit writes 0F/26 read-modify-write
 *     (set: AND FFFF OR bit; clear: AND ~bit OR 0000). Typed writes send an
 *     array (99 09 LL desc data, as RTA and the doc/PROTOCOL.md 7.3 vectors); a reply may
 *     be an array or a single element. Strings (ST) go one per packet as a
 *     string parameter and the characters in text order (39 LEN chars, RTA).
 *     T/C/R replies are decoded by their type/data descriptor: 3 words (the data
 *     table's, 56 66 76) or 5 (KF2 p.130 "timer elements return five words", VME
 *     p.81: 59 0A), words 0-2 CTL, PRE/LEN, ACC/POS, the rest ignored
 *     [UNCERTAIN, doc/PROTOCOL.md 8 item 8]; any other size is DF1_E_BAD_REPLY. A reply of
 *     5-word elements that holds fewer than asked is taken when it is full (the
 *     PLC cut it to 240 bytes), and the next packets ask for that many;
 *     DF1_OPT_PLC5_TIMER_WORDS 5 plans timer reads at 5 words from the start.
 *     Writes send the 3-word form.
 *     Floats go plain little-endian in typed reads and writes, the doc/PROTOCOL.md 5
 *     recommendation (RTA); DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED word-swaps them
 *     ([2,3,0,1], as word range 0F/00/01 always has them; the client does not
 *     use word range). [UNCERTAIN, doc/PROTOCOL.md 8 item 7] Raw reads and writes pass
 *     the wire bytes either way.
 *   PLC-2 (01 unprotected read, 08 unprotected write, 05 unprotected bit write):
 *     PLC-2 commands carry a 16-bit address and no file. The address's element
 *     is taken as the WORD offset into the target's PLC-2 area (a PLC-2's data
 *     table; the PLC-2 compatibility file of a PLC-5; the Common Interface File
 *     N9 of an SLC; N7 of a MicroLogix 1000); the file number is ignored. "N7:8"
 *     = PLC-2 word 010 (octal). The command carries byte address 2 * element
 *     (doc/PROTOCOL.md 4.7: a PLC-2, a PLC-5's compatibility file, an SLC with S:2/8 = 1),
 *     or with DF1_OPT_PLC2_WORD_ADDR the element itself (an SLC or MicroLogix
 *     common interface file, S:2/8 = 0); 05's blocks address bytes, so bit
 *     writes are refused in word mode. Only 16-bit word files (N B S I O A) and
 *     their bits; no sub-elements.
 *   PLC-3 (doc/PROTOCOL.md 4.2a): word range read 0F/01 and write 0F/00 with a
 *     PLC-3 logical binary address (section, file, structure, word), one
 *     transaction per packet (packet offset 0); bit writes 0F/02 (SET and
 *     RESET masks, one word). Addresses are the PLC-3 grammar's (T/C: element
 *     = structure, sub = word; F and H (L) 32-bit values low word first, plain
 *     little-endian). Read 244 bytes a packet, write 228 (1775-KA).
 *
 * Splitting (doc/PROTOCOL.md 6). Requests larger than one packet are split on element
 * boundaries. Data bytes per packet:
 *   SLC 5/03+ and MicroLogix: read 236, write 234; SLC 5/01-5/02: 82 / 82;
 *   PLC-2: 244 / 244;
 *   PLC-5: address + type/data parameter (99 09 LL + element descriptor) +
 *     data <= 240 bytes, for the typed read's reply and the typed write
 *     (lib/proto/plc_limits.h derives the count: 116 integers, 58 floats, 38
 *     timers/counters/controls after a 3-byte address). Multi-packet PLC-5
 *     transfers repeat the start address and count PKT_OFFSET / TOTAL_TRANS in
 *     elements.
 *   DF1_OPT_MAX_PACKET (h->cfg.max_packet) replaces the per-type limits with
 *     that many bytes of element data per packet (at most 244).
 *
 * Address forms:
 *   whole elements          N7:0 x n, F8:0, L10:0, ST9:0 (84 bytes), T4:0 (6 bytes)
 *   T/C/R sub-element       T4:0.ACC: one 16-bit word per element. n == 1 reads and
 *                           writes that word (SUBELEMENT 1/2, or PLC-5 level 4);
 *                           n > 1 means the same word of n consecutive elements: reads
 *                           fetch whole elements and pick the word, writes go one
 *                           element at a time (never touching the other words).
 *   I/O word                I1:0.1 x n: element = slot, sub = word; n > 1 advances the
 *                           word (SUBELEMENT) across the image.
 *   bits                    B3:0/5 x n: n consecutive bits, crossing into the next
 *                           word after bit 15 (31 for L); a T/C/R bit stays in its word.
 *                           Reads fetch the word(s) and extract; writes are masked per
 *                           word (AB, 26 or 05), never clobbering the other bits.
 *                           An L bit on SLC/MicroLogix is an AB with a 4-byte mask and
 *                           data (BYTE_SIZE 4) [UNCERTAIN: doc/PROTOCOL.md 4.6, NPC found AB on L
 *                           files unreliable]; PLC-5 has no L files.
 *
 * Returns: element reads/writes return n; raw ones the byte count; df1_read_string
 * and df1_write_string the string length; df1_read_bit, df1_write_bit,
 * df1_diag_status, df1_change_mode and df1_link_test 0; df1_echo the length echoed.
 * A reply whose STS is not 0 is DF1_E_REMOTE (df1_last_error: sts, ext_sts); a
 * reply with fewer or more data bytes or elements than asked, or with the wrong
 * PLC-5 element type or size, is DF1_E_BAD_REPLY (counted as 2550); a typed
 * helper on a file that does not hold its type is DF1_E_TYPE, before any I/O.
 *
 * Errors: every failure is recorded with client_fail() / df1_fail_remote(); the
 * detail's address field names the address ("N7:0") and station the station,
 * and the message does not repeat the address. Buffers live on the stack (FRAME_MAX_DATA): no
 * allocation per packet.
 */
#ifndef LIBDF1_CLIENT_INT_H
#define LIBDF1_CLIENT_INT_H

#include "df1_int.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "client/client.h"
#include "link/link.h"
#include "proto/plc_limits.h"
#include "proto/pccc.h"
#include "proto/value.h"

#define ATEXT_MAX 64

/* A contiguous run of `count` elements of `esize` bytes starting at `a`. */
struct span {
	struct df1_addr a;      /* the first element; bit is always DF1_ADDR_NONE */
	size_t esize;           /* bytes per element on the wire */
	size_t count;
	bool by_sub;            /* I/O words: advance SUBELEMENT, not ELEMENT */
	enum df1_plc plc;       /* the command set: the call's PLC type */
};

/* Where element values go (reads) or come from (writes). */
enum io_kind { IO_RAW, IO_VALUE, IO_I16, IO_I32, IO_F32, IO_TCR, IO_STRING };

struct io {
	enum io_kind kind;
	enum df1_file_type t;   /* value type of one element: DF1_FT_N for single words */
	int word;               /* >= 0: only this 16-bit word of each wire element */
	size_t base;            /* index of the first element of the current span */
	enum value_float_order fo;
	void *out;
	const void *in;
	size_t cap;             /* IO_STRING: bytes at out */
	int len;                /* IO_STRING: length read */
};

/* A span read in progress, packet by packet: the family's *_read_cmd builds
 * the next packet's command, *_read_take decodes its reply (elements.c runs
 * them around one transaction each). */
struct rd {
	size_t per;             /* elements per packet */
	size_t done;            /* elements read so far */
	size_t k;               /* elements asked by the packet built last */
	int code;               /* SLC: the file type code */
	int alen;               /* PLC-5: bytes of the address at addr */
	bool replanned;         /* PLC-5 T/C/R: planned again at 5 words after a refusal */
	uint8_t addr[DF1_ADDR_ASCII_MAX + 8];
};

/* A read whose first packet the caller runs itself (pipelining, client.h):
 * RD_BUILD stops once that packet's command is in cmd; RD_TAKE takes rc and
 * reply (what the link returned for it) instead of sending it. */
enum rd_first_mode { RD_BUILD = 1, RD_TAKE };
struct rd_first {
	enum rd_first_mode mode;
	uint8_t *cmd;           /* RD_BUILD: cap bytes */
	size_t cap;
	int rc;                 /* RD_TAKE: reply length or DF1_E_* */
	const uint8_t *reply;
};

/* transact.c */
bool client_is_word_type(enum df1_file_type t);
bool client_is_tcr(enum df1_file_type t);
void client_atext(enum df1_plc plc, const struct df1_addr *a, char *buf, size_t cap);
int client_fail(struct df1 *h, int code, int station, const char *what, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));
int client_bad_reply(struct df1 *h, int station, const char *what, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
int client_check(struct df1 *h, int station);
void client_derive(const struct df1_addr *a, int element, int sub, struct df1_addr *out);
void span_at(const struct span *s, size_t i, struct df1_addr *out);
size_t client_limit(const struct df1 *h, const struct span *s, bool write);
int client_reply(struct df1 *h, int station, const char *what, const uint8_t *cmd, int rc,
                 const uint8_t *reply, const uint8_t **data, size_t *dlen);
int client_transact(struct df1 *h, int station, const char *what, uint8_t *cmd, size_t clen,
                    uint8_t *reply, size_t rcap, const uint8_t **data, size_t *dlen);
int client_op_transact(struct df1 *h, int station, const char *op, uint8_t *cmd, size_t clen,
                       uint8_t *reply, size_t rcap, const uint8_t **data, size_t *dlen);
int io_put(struct df1 *h, int station, const char *what, struct io *io, size_t i,
           const uint8_t *p, size_t esize);
int io_get(struct io *io, size_t i, uint8_t *p, size_t esize);
int io_gather(struct df1 *h, int station, const char *what, struct io *io, size_t first,
              size_t k, uint8_t *out, size_t esize);

/* slc.c */
int slc_type_code(struct df1 *h, int station, const char *what, enum df1_file_type t);
int slc_read_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd);
int slc_read_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                 uint8_t *cmd, size_t cap);
int slc_read_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                  struct rd *rd, const uint8_t *d, size_t dlen);
int slc_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io);

/* plc5.c */
int plc5_addr(struct df1 *h, int station, const char *what, const struct df1_addr *a,
              uint8_t *out, size_t cap);
int plc5_read_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd);
/* A packet refused as too large (STS F0, EXT STS 09) with whole T/C/R elements planned
 * at 3 words: planned again at 5 (true: send it again), else false. */
bool plc5_read_refused(struct df1 *h, int station, const struct span *s, struct rd *rd);
int plc5_read_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                  uint8_t *cmd, size_t cap);
int plc5_read_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                   struct rd *rd, const uint8_t *d, size_t dlen);
int plc5_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io);

/* plc2.c */
int plc2_read_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd);
int plc2_read_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                  uint8_t *cmd, size_t cap);
int plc2_read_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                   struct rd *rd, const uint8_t *d, size_t dlen);
int plc2_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io);

/* plc3.c */
int plc3_addr(struct df1 *h, int station, const char *what, const struct df1_addr *a,
              uint8_t *out, size_t cap);
int plc3_read_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd);
int plc3_read_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                  uint8_t *cmd, size_t cap);
int plc3_read_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                   struct rd *rd, const uint8_t *d, size_t dlen);
int plc3_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io);

/* elements.c */
int client_read_bits(struct df1 *h, int station, const char *what, enum df1_plc plc,
                     const struct df1_addr *a, size_t n, bool *bits, struct df1_value *vals);
int client_write_bits(struct df1 *h, int station, const char *what, enum df1_plc plc,
                      const struct df1_addr *a, size_t n, const bool *bits, const struct df1_value *vals);
int client_read_elems(struct df1 *h, int station, const char *what, enum df1_plc plc,
                      const struct df1_addr *a, size_t n, struct io *io);
/* client_read_elems with its first packet run by the caller (first); RD_BUILD
 * returns the command's length. */
int client_read_elems_first(struct df1 *h, int station, const char *what, enum df1_plc plc,
                            const struct df1_addr *a, size_t n, struct io *io,
                            const struct rd_first *first);
int client_write_elems(struct df1 *h, int station, const char *what, enum df1_plc plc,
                       const struct df1_addr *a, size_t n, struct io *io);

#endif
