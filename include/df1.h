/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1.h - libdf1: the Allen-Bradley DF1 serial protocol (PCCC over RS-232/RS-485
 * or raw DF1 over TCP) for PLC-5, SLC 500 and MicroLogix controllers.
 *
 * The installed header (with df1_catalog.h, df1_eip.h and df1_probe.h, which it
 * includes).
 * Conventions (see libdf1(7)):
 *  - every int function returns >= 0 on success (0 or a count) and a negative
 *    DF1_E_* code on failure; df1_strerror()/df1_errname() turn it into text;
 *  - buffers belong to the caller; the library never prints, exits or aborts;
 *  - one handle is used by one thread at a time (the poll engine's write queue
 *    is the one exception, see df1_tag_write()).
 */
#ifndef LIBDF1_DF1_H
#define LIBDF1_DF1_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>

#define DF1_VERSION_MAJOR 0
#define DF1_VERSION_MINOR 5
#define DF1_VERSION_MICRO 0
#define DF1_VERSION_STRING "0.5.0"

/* The version of the library a program runs with (as libusb_get_version()).
 * The macros above are the header a program was compiled against; with the
 * shared library the one loaded at run time may be newer (same major).
 * @since 0.2 */
struct df1_version {
	int major;              /* DF1_VERSION_MAJOR of the library: the soname */
	int minor;              /* added functions */
	int micro;              /* fixes */
	const char *string;     /* "MAJOR.MINOR.MICRO", e.g. "0.1.0" */
};

#if defined(__GNUC__)
#define DF1_API __attribute__((visibility("default")))
#else
#define DF1_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* The runtime version. Returns static storage: never NULL, never freed,
 * constant, thread-safe; no handle needed, no error.
 * @since 0.2 */
DF1_API const struct df1_version *df1_version(void);

/* ------------------------------------------------------------------------
 * Errors. ONE table: name, value, message catalog ID (0 = none), text.
 * The catalog's IDs are the DF1_ID_* names of DF1_CATALOG_TABLE below (a
 * macro expands where it is used, after both tables). The texts of both, and
 * of the STS / EXT STS codes, are served by lib/proto/errors.c;
 * df1_error_catalog_id() links the two.
 * ------------------------------------------------------------------------ */
#define DF1_ERROR_TABLE(X)                                                                                \
	X(DF1_OK,              0, 0,                             "success")                               \
	X(DF1_E_INVAL,        -1, 0,                             "invalid argument")                      \
	X(DF1_E_SYS,          -2, 0,                             "system call failed")                    \
	X(DF1_E_NOMEM,        -3, 0,                             "out of memory")                         \
	X(DF1_E_TIMEOUT,      -4, DF1_ID_ERR_COMMAND_TIMEOUT,    "command timed out")                     \
	X(DF1_E_NAK_LIMIT,    -5, DF1_ID_NTC_NAK_LIMIT_EXCEEDED, "NAK retry limit exceeded")              \
	X(DF1_E_ENQ_LIMIT,    -6, DF1_ID_NTC_ENQ_LIMIT_EXCEEDED, "ENQ retry limit exceeded")              \
	X(DF1_E_REMOTE,       -7, 0,                             "PLC replied with an error status")      \
	X(DF1_E_BCC,          -8, DF1_ID_ERR_BAD_BCC,            "response with wrong BCC")               \
	X(DF1_E_CRC,          -9, DF1_ID_ERR_BAD_CRC,            "response with wrong CRC")               \
	X(DF1_E_TOO_LONG,    -10, DF1_ID_NTC_RCVD_MSG_TOO_LONG,  "received message too long")             \
	X(DF1_E_TOO_SHORT,   -11, DF1_ID_NTC_RCVD_MSG_TOO_SHORT, "received message too short")            \
	X(DF1_E_SYMBOL,      -12, DF1_ID_NTC_INVALID_SYMBOL,     "invalid symbol received after DLE")     \
	X(DF1_E_ADDR_SYNTAX, -13, DF1_ID_ERR_ADDRESS_SYNTAX,     "invalid address syntax")                \
	X(DF1_E_ADDR_RANGE,  -14, DF1_ID_ERR_ADDRESS_RANGE,      "address is out of range")               \
	X(DF1_E_BAD_FUNCTION, -15, DF1_ID_ERR_BAD_FUNCTION_CODE,  "response with wrong command code")     \
	X(DF1_E_INACTIVE,    -16, DF1_ID_ERR_INACTIVE_STATION,   "slave station inactive")                \
	X(DF1_E_WRONG_MSG,   -17, DF1_ID_ERR_WRONG_MESSAGE,      "wrong message received")                \
	X(DF1_E_BUSY,        -18, 0,                             "port busy (in use by another process)") \
	X(DF1_E_NOTSUP,      -19, 0,                             "not supported")                         \
	X(DF1_E_TYPE,        -20, 0,                             "value does not fit the file type")      \
	X(DF1_E_RANGE,       -21, 0,                             "value out of range")                    \
	X(DF1_E_NOT_OPEN,    -22, 0,                             "handle is not open")                    \
	X(DF1_E_CLOSED,      -23, 0,                             "connection closed by peer")             \
	X(DF1_E_CONFIG,      -24, 0,                             "invalid configuration")                 \
	X(DF1_E_INTR,        -25, 0,                             "interrupted")                           \
	X(DF1_E_NOSPACE,     -26, 0,                             "buffer too small")                      \
	X(DF1_E_NAK,         -27, DF1_ID_ERR_RCVD_NAK_SYMBOL,    "received NAK symbol")                   \
	X(DF1_E_BAD_REPLY,   -28, 0,                             "invalid reply message")                 \
	X(DF1_E_NO_ETX,      -29, DF1_ID_NTC_NO_ETX_RCVD,        "incomplete message, no ETX received")   \
	X(DF1_E_NODEV,       -30, 0,                             "no such device")                        \
	X(DF1_E_PERM,        -31, 0,                             "permission denied")                     \
	X(DF1_E_EIP,         -32, 0,                             "EtherNet/IP encapsulation error")       \
	X(DF1_E_CIP,         -33, 0,                             "CIP error status")

#define DF1_ERROR_ENUM_ITEM(name, value, id, text) name = value,
enum df1_error { DF1_ERROR_TABLE(DF1_ERROR_ENUM_ITEM) };
#undef DF1_ERROR_ENUM_ITEM
#define DF1_ERROR_COUNT_ITEM(name, value, id, text) + 1
/* Codes run 0, -1, -2 ... without a gap; DF1_E_LAST_ is one past the last,
 * counted from the table. */
#define DF1_ERROR_COUNT (0 DF1_ERROR_TABLE(DF1_ERROR_COUNT_ITEM))
#define DF1_E_LAST_ (-DF1_ERROR_COUNT)

/* Static strings, never NULL, thread-safe. Unknown codes give "unknown error". */
DF1_API const char *df1_strerror(int err);
DF1_API const char *df1_errname(int err);
/* Catalog ID (2501-2561) that reports this error, or 0. */
DF1_API int df1_error_catalog_id(int err);
/* True when one command that failed with err surely did not execute at the PLC:
 * refused before it was sent (argument, address, value, port errors), a NAK
 * received (DF1_E_NAK), a station that did not answer its poll (DF1_E_INACTIVE),
 * or answered with an error status (DF1_E_REMOTE). False for success and for
 * every failure after which it may have executed (DF1_E_TIMEOUT, DF1_E_ENQ_LIMIT,
 * a lost or corrupt reply, a connection lost; and DF1_E_NAK_LIMIT, which in half
 * duplex also ends tries that got no ACK at all, one of which the slave may have
 * taken): such a write must be reported as unconfirmed, never sent again. For a
 * request the library splits over several commands this holds for the failed one
 * only. @since 0.4 */
DF1_API bool df1_error_unexecuted(int err);
/* True when the PCCC command pccc[0..n) (CMD STS TNS [FNC] data) may change the
 * controller; false only for 01, 06/00 06/01 06/03, 0F/01 0F/68 0F/A1 0F/A2
 * (df1_poll(3)). @since 0.4 */
DF1_API bool df1_pccc_is_write(const uint8_t *pccc, size_t n);

/* STS (M p.8-2/8-3) and EXT STS for CMD 0F (M p.8-4) / DH-485 (M p.8-5). */
DF1_API const char *df1_sts_text(uint8_t sts);
DF1_API const char *df1_ext_sts_text(uint8_t ext);
DF1_API const char *df1_ext_sts_text_dh485(uint8_t ext);

/* ------------------------------------------------------------------------
 * Message catalog (doc/REQUIREMENTS.md 004): IDs, mnemonics, severities, formats.
 * ------------------------------------------------------------------------ */
enum df1_severity {
	DF1_SEV_CRITICAL = 0, /* 2552-2559: configuration, the program does not start */
	DF1_SEV_ERROR = 1,    /* 2501-2511 */
	DF1_SEV_NOTICE = 2,   /* 2512-2524 */
	DF1_SEV_COUNTER = 3,  /* 2525-2551, 2560-2561 */
};

/* The catalog table, DF1_CATALOG_TABLE(X), lives in df1_catalog.h. */
#include "df1_catalog.h"

#define DF1_CATALOG_ENUM_ITEM(mnemonic, id, sev, format, description) DF1_ID_##mnemonic = id,
enum df1_catalog_id { DF1_CATALOG_TABLE(DF1_CATALOG_ENUM_ITEM) };
#undef DF1_CATALOG_ENUM_ITEM
#define DF1_CATALOG_COUNT_ITEM(mnemonic, id, sev, format, description) + 1
/* Rows in the catalog (61), counted from the table. */
#define DF1_CATALOG_COUNT (0 DF1_CATALOG_TABLE(DF1_CATALOG_COUNT_ITEM))

struct df1_catalog_entry {
	int id;                   /* 2501 .. 2561 */
	const char *mnemonic;     /* "ERR_COMMAND_TIMEOUT" */
	enum df1_severity severity;
	const char *format;       /* printf format as the seed gives it, or NULL for counters */
	const char *description;  /* one line: what it means */
};

DF1_API const struct df1_catalog_entry *df1_catalog_by_id(int id);          /* NULL if unknown */
DF1_API const struct df1_catalog_entry *df1_catalog_by_mnemonic(const char *mn); /* case-insensitive */
/* Iterate: index 0.. until NULL. */
DF1_API const struct df1_catalog_entry *df1_catalog_at(size_t index);

/* ------------------------------------------------------------------------
 * Addresses: [File Type][File Number]:[Element][.Sub | /Bit]  (libdf1(7))
 * ------------------------------------------------------------------------ */
enum df1_file_type {
	DF1_FT_NONE = 0,
	DF1_FT_O,  /* output,   default file 0 */
	DF1_FT_I,  /* input,    default file 1 */
	DF1_FT_S,  /* status,   default file 2 */
	DF1_FT_B,  /* bit,      default file 3 */
	DF1_FT_T,  /* timer,    default file 4 */
	DF1_FT_C,  /* counter,  default file 5 */
	DF1_FT_R,  /* control,  default file 6 */
	DF1_FT_N,  /* integer,  default file 7 */
	DF1_FT_F,  /* float,    default file 8 */
	DF1_FT_ST, /* string (84 bytes) */
	DF1_FT_A,  /* ASCII (2 characters per element) */
	DF1_FT_L,  /* long integer, MicroLogix; a PLC-3's high-order integer section (H) */
	DF1_FT_COUNT_,            /* the types of df1_addr_parse()'s grammar end here */
	/* a PLC-3's decimal section, one BCD word a value (@since 0.5): df1_addr_parse_plc()
	 * with DF1_PLC_PLC3 only */
	DF1_FT_D = 16
};

#define DF1_ADDR_NONE (-1)
#define DF1_ADDR_ASCII_MAX 52

struct df1_addr {
	enum df1_file_type type;
	int file;     /* 0..999 */
	int element;  /* 0..999 (I/O: slot) */
	int sub;      /* DF1_ADDR_NONE or 0..255: T/C/R word (0 ctl, 1 PRE/LEN, 2 ACC/POS), I/O word */
	int bit;      /* DF1_ADDR_NONE or 0..15 (32 bits for L) */
	/* PLC-5 logical ASCII pass-through ("$N7:0"): text without '$', else "" */
	char ascii[DF1_ADDR_ASCII_MAX];
};

/* Parse text into *a. DF1_E_ADDR_SYNTAX (2503) or DF1_E_ADDR_RANGE (2504). */
DF1_API int df1_addr_parse(const char *text, struct df1_addr *a);
/* Canonical text ("B3:1/5", "T4:0.ACC", "T4:0/DN"); returns length or DF1_E_NOSPACE. */
DF1_API int df1_addr_format(const struct df1_addr *a, char *buf, size_t cap);
/* Letters of a file type ("N", "ST") or "?". */
DF1_API const char *df1_file_type_name(enum df1_file_type t);
/* Bytes per element on the wire (N 2, F 4, L 4, T/C/R 6, ST 84, A 2 ...). */
DF1_API int df1_file_type_element_size(enum df1_file_type t);
/* SLC file type code for 0F/A2 etc. (N 89h, F 8Ah, ST 8Dh, L 91h, O 8Bh, I 8Ch ...);
 * a handle with DF1_OPT_SLC_IO_CODES_82 sends 82h/83h for O/I instead. */
DF1_API int df1_file_type_slc_code(enum df1_file_type t);

/* ------------------------------------------------------------------------
 * Values
 * ------------------------------------------------------------------------ */
#define DF1_STRING_MAX 82

struct df1_tcr {      /* a whole timer, counter or control element */
	uint16_t ctl;     /* word 0: status bits (EN TT DN / CU CD DN OV UN UA / EN EU DN EM ER UL IN FD) */
	int16_t pre;      /* word 1: PRE (timer, counter) or LEN (control) */
	int16_t acc;      /* word 2: ACC (timer, counter) or POS (control) */
};

enum df1_value_kind {
	DF1_VAL_INT16, DF1_VAL_INT32, DF1_VAL_FLOAT, DF1_VAL_BIT, DF1_VAL_STRING, DF1_VAL_TCR
};

struct df1_value {
	enum df1_value_kind kind;
	union {
		int16_t i16;
		int32_t i32;
		float f;
		bool bit;
		struct { uint16_t len; char text[DF1_STRING_MAX + 1]; } str;
		struct df1_tcr tcr;
	} v;
};

/* The value kind an address reads as: N/B/S/I/O/A words -> INT16 (a /bit -> BIT),
 * L -> INT32, F -> FLOAT, ST -> STRING, a whole T/C/R element -> TCR. */
DF1_API enum df1_value_kind df1_addr_value_kind(const struct df1_addr *a);
/* Named bit positions for T/C/R ("DN" -> 13 for T), or -1. */
DF1_API int df1_tcr_bit(enum df1_file_type t, const char *name);
/* Format a value for humans/scripts: ints in decimal, floats in shortest
 * round-trip form, bits 0/1, strings as text, T/C/R as "PRE=.. ACC=.. EN=1 ...".
 * Returns the length or DF1_E_NOSPACE. */
DF1_API int df1_value_format(const struct df1_value *v, enum df1_file_type t, char *buf, size_t cap);
/* Parse text into a value for address a; checks range/type (DF1_E_TYPE, DF1_E_RANGE). */
DF1_API int df1_value_parse(const struct df1_addr *a, const char *text, struct df1_value *v);

/* ------------------------------------------------------------------------
 * The handle: new -> set_* -> open -> read/write/... -> close -> free
 * ------------------------------------------------------------------------ */
typedef struct df1 df1_t;

/* DF1_RADIO_MODEM (@since 0.5): DF1 Radio Modem, full-duplex frames and no link
 * control at all: no ACK, NAK, ENQ or poll; one transmission per command and per
 * reply; store and forward (df1_set_forward(3)); libdf1(7) RADIO MODEM. */
enum df1_duplex { DF1_FULL_DUPLEX = 0, DF1_HALF_DUPLEX_MASTER = 1, DF1_HALF_DUPLEX_SLAVE = 2,
                  DF1_RADIO_MODEM = 3 };
enum df1_check { DF1_CHECK_CRC = 0, DF1_CHECK_BCC = 1, DF1_CHECK_AUTO = 2 /* decoder only */ };
enum df1_plc {
	DF1_PLC_SLC = 0,        /* SLC 5/03, 5/04, 5/05: 0F/A2 AA AB, 236-byte reads */
	DF1_PLC_MICROLOGIX = 1, /* as SLC, plus L files */
	DF1_PLC_SLC502 = 2,     /* SLC 5/01, 5/02: 82-byte packets */
	DF1_PLC_PLC5 = 3,       /* 0F/68 67 26 */
	DF1_PLC_PLC2 = 4,       /* 01 / 08 */
	DF1_PLC_PLC3 = 5,       /* 0F/01 00 02 word range, PLC-3 logical binary (@since 0.5) */
};

/* The address text of a PLC type (@since 0.5). DF1_PLC_PLC3: a PLC-3's own text
 * (libdf1(7) "PLC-3 addresses": "N3:173", "B5:173/15" with an octal bit, "I0:17"
 * with an octal word, "F2:10", "H8:99", "D7:12", "T4.ACC", "C2/DN"): type O I T C N F
 * D B A S (H = DF1_FT_L), file 0..999 (T and C: 0), element = word 0..9999 (I/O
 * 0..07777) or, for T C F H, the structure 0..9999; sub = the T/C word (0 CTL, 1 PRE,
 * 2 ACC). Any other plc: df1_addr_parse() / df1_addr_format(). Errors as theirs. */
DF1_API int df1_addr_parse_plc(enum df1_plc plc, const char *text, struct df1_addr *a);
/* a as plc's address text, what df1_addr_parse_plc reads back. @since 0.5 */
DF1_API int df1_addr_format_plc(enum df1_plc plc, const struct df1_addr *a, char *buf, size_t cap);

/* Less common link options, set with df1_set_option(). */
enum df1_option {
	DF1_OPT_DUPLICATE_DETECT = 1,   /* bool, default 1: drop duplicate messages (SRC, CMD, TNS) */
	DF1_OPT_EMBEDDED_RESPONSES,     /* bool, default 1: accept DLE ACK/NAK inside a frame */
	DF1_OPT_HD_BCC_INCLUDES_STX,    /* bool, default 0: half-duplex master BCC also sums STX (doc/PROTOCOL.md 2.2) */
	DF1_OPT_ACCEPT_NAK_0F,          /* bool, default 1: also take DLE 0F as NAK (doc/PROTOCOL.md 1.1) */
	DF1_OPT_RS485,                  /* bool, default 0: kernel RS-485 (TIOCSRS485) */
	DF1_OPT_ECHO_DISCARD,           /* bool, default 0: 2-wire line, drop the echo of our own bytes */
	DF1_OPT_MAX_PACKET,             /* bytes of data per read/write packet, 0 = per PLC type */
	DF1_OPT_EOT_WITH_BCC,           /* bool, default 0: tolerate one byte after DLE EOT */
	DF1_OPT_LOCAL_TCP,              /* bool, df1sim: listen on loopback only (default 1) */
	/* bool, default 0: PLC-5 typed read/write (0F/68, 0F/67) floats word-swapped, bytes
	 * [2,3,0,1] as word range 0F/00/01 has them, instead of plain LE (doc/PROTOCOL.md 5, 8 item 7) */
	DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED,
	/* bool, default 0: SLC commands name O/I files by type code 82h/83h (F2E) instead of
	 * 8Bh/8Ch (doc/PROTOCOL.md 4.11, 8 item 10); the responder takes both either way */
	DF1_OPT_SLC_IO_CODES_82,
	/* bool, default 0: listen only (a tap, df1mon --sniff): df1_open() opens the device
	 * read only (O_RDONLY) and a TCP connection shut for sending (SHUT_WR); nothing is
	 * ever transmitted (every send is DF1_E_NOTSUP). Set it before df1_open(). @since 0.2 */
	DF1_OPT_LISTEN_ONLY,
	/* 3 or 5, default 3: the words of a PLC-5 timer in typed reads (0F/68; KF2 p.130 and
	 * VME p.81 give 5, the data table holds 3; doc/PROTOCOL.md 4.3, 8 item 8). A responder serving a
	 * PLC-5 sends its timers so (5: type/data 59 0A, words 3-4 zero). A client decodes
	 * T/C/R replies of 3 and of 5 words whatever this says, by their type/data
	 * descriptor; with 5 it asks for no more timers in a packet than 5-word ones fit.
	 * @since 0.3 */
	DF1_OPT_PLC5_TIMER_WORDS,
	/* bool, default 0: PLC-2 commands (01, 08, 05) carry the word offset (the element)
	 * instead of the byte address 2 * element: the common interface file of an SLC or
	 * MicroLogix with S:2/8 = 0 (doc/PROTOCOL.md 4.7). Client and responder. @since 0.3 */
	DF1_OPT_PLC2_WORD_ADDR,
	/* ms, 0..60000, default 0 = automatic: a half-duplex master that gets no first byte
	 * in answer to a poll within this time polls again (until Cmd_Timeout) instead of
	 * waiting the whole ACK timeout: some slaves answer a poll with nothing at all
	 * when they have no reply yet, instead of DLE EOT. Automatic: 6 character times at
	 * the line's baud + 20 ms turnaround, + 50 ms on TCP; never more than the timeout.
	 * @since 0.4 */
	DF1_OPT_POLL_TIMEOUT_MS,
	/* ms, 0..10000, default 0: a responder (df1_serve) that acts as a controller with
	 * this program scan: a command's reply becomes available at the end of the scan in
	 * progress when it arrived (scans run back to back from df1_open), as an SLC
	 * answers communication at its end of scan. 0: at once. @since 0.4 */
	DF1_OPT_SCAN_TIME_MS,
	/* bool, default 0: a half-duplex slave (df1_serve) answers a poll with nothing at
	 * all, instead of DLE EOT, when it has no reply ready (devices that suppress the
	 * EOT). @since 0.4 */
	DF1_OPT_NO_EOT,
	/* 1..16, default 1: full duplex, the commands that may be outstanding on the line (sent
	 * and ACKed, their reply not yet in; doc/PROTOCOL.md 1.6 rule 6). 1 waits for each reply before
	 * the next command, as before 0.4; more lets the poll engine send a scan's block reads
	 * back to back and match the replies by SRC and TNS as they come (df1_poll(3),
	 * libdf1(7)). Half duplex ignores it (one message per poll). @since 0.4 */
	DF1_OPT_MAX_OUTSTANDING,
	/* bool, default 0: an eip:// target (libdf1(7)) carries PCCC in connected explicit
	 * messages (Forward Open at df1_open(), SendUnitData, Forward Close at df1_close())
	 * instead of unconnected SendRRData. Set it before df1_open(). @since 0.4 */
	DF1_OPT_EIP_CONNECTED,
	/* bool, default 1: a USB serial adapter is put in low latency mode (ASYNC_LOW_LATENCY)
	 * at df1_open() and back at df1_close(); a latency timer still above 1 ms is logged
	 * and kept as df1_port_note() (libdf1(7) USB ADAPTERS). Set it before df1_open(). @since 0.5 */
	DF1_OPT_LOW_LATENCY,
	/* bool, default 0: a responder answers a PLC-5 typed read (0F/68) that asks for more
	 * elements than one reply holds with STS F0 EXT STS 09 (data too large) instead of
	 * sending those that fit (df1sim --plc5-refuse-large). @since 0.5 */
	DF1_OPT_PLC5_REFUSE_LARGE,
	/* bool, default 1: a half-duplex master forwards its slaves' commands for other slaves
	 * and the replies (libdf1(7) UNSOLICITED MESSAGES); 0: dropped. @since 0.5 */
	DF1_OPT_ROUTE,
	/* 0..10, default 0: radio modem, how many times a command with no reply within the
	 * timeout is sent again (same TNS) before the transaction fails with DF1_E_TIMEOUT.
	 * A write sent again may run twice at a responder without duplicate detection.
	 * @since 0.5 */
	DF1_OPT_APP_RETRIES,
	/* DF1_DUP_AUTO (default), 0 or 1: radio modem, drop a packet that repeats one of the
	 * last 20 received (DST SRC CMD STS TNS); auto: on while a forward table is set and on a
	 * node that executes commands (df1_serve, df1_set_responder). @since 0.5 */
	DF1_OPT_RADIO_DUP_DETECT,
	/* bool, default 0: radio modem, key the radio with RTS and send only once CTS is
	 * up (at most 1 s, else the packet is discarded, counted undelivered). @since 0.5 */
	DF1_OPT_RADIO_RTS_CTS,
	/* ms, 0..65535, default 0: radio modem with RTS/CTS: from RTS up to the first byte,
	 * and from the last byte to RTS down. @since 0.5 */
	DF1_OPT_RTS_SEND_DELAY_MS,
	DF1_OPT_RTS_OFF_DELAY_MS,
	/* ms, 0..65535, default 0 = off: radio modem, before keying wait up to this long
	 * for carrier detect (DCD) to drop; still up: the packet is discarded, counted
	 * undelivered. @since 0.5 */
	DF1_OPT_DCD_WAIT_MS,
};
/* DF1_OPT_RADIO_DUP_DETECT's automatic value. @since 0.5 */
#define DF1_DUP_AUTO 2

DF1_API int  df1_new(df1_t **out);      /* defaults: 19200 8N1, full duplex, CRC, station 0 */
DF1_API void df1_free(df1_t *h);        /* closes if open; NULL is a no-op */

/* Settings are stored; setters on an open handle apply at once where they can. */
DF1_API int df1_set_serial(df1_t *h, int baud, int data_bits, char parity /* 'N' 'E' 'O' */, int stop_bits);
DF1_API int df1_set_handshake(df1_t *h, bool rts_cts);
DF1_API int df1_set_duplex(df1_t *h, enum df1_duplex d);
DF1_API int df1_set_check(df1_t *h, enum df1_check c);
DF1_API int df1_set_station(df1_t *h, int own_station);          /* SRC of our commands, 0..254 */
DF1_API int df1_set_plc(df1_t *h, enum df1_plc plc);
DF1_API int df1_set_timeout_ms(df1_t *h, int ms);        /* ACK / response wait ("Timeout"), 0..360000 */
DF1_API int df1_set_cmd_timeout_ms(df1_t *h, int ms);    /* whole transaction ("Cmd_Timeout"), 500..5000 */
DF1_API int df1_set_retries(df1_t *h, int nak_retries, int enq_retries);    /* 0..10 each */
DF1_API int df1_set_tx_delay_ms(df1_t *h, int ms);       /* before every transmission, 0..65535 */
DF1_API int df1_set_option(df1_t *h, enum df1_option opt, int value);
/* Listen-only ports (DF1_OPT_LISTEN_ONLY), @since 0.2.
 * df1_recv_raw: up to cap received bytes as they came off the port, into the caller's
 * buf, waiting up to timeout_ms (0: only what is there; -1: no deadline) for the first
 * of them; the handle's cancel fd ends the wait. Bytes the link layer had read but not
 * decoded come first. *when (may be NULL) gets the wall-clock time (CLOCK_REALTIME)
 * right after the read. Counted as characters received (2561) and passed to the
 * trace callback. Returns the number of bytes (> 0), 0 at the deadline, or
 * DF1_E_INVAL, DF1_E_NOT_OPEN, DF1_E_CLOSED (peer closed, device hung up, end of a
 * FIFO or file), DF1_E_INTR (cancel fd), DF1_E_SYS.
 * df1_port_fd: the descriptor the open port reads, for an application's own poll()
 * loop (readable: df1_recv_raw has bytes) and read-only queries such as TIOCMGET.
 * The handle owns it: never read, write or close it. Returns it, or DF1_E_INVAL,
 * DF1_E_NOT_OPEN. */
DF1_API int df1_recv_raw(df1_t *h, uint8_t *buf, size_t cap, int timeout_ms, struct timespec *when);
DF1_API int df1_port_fd(const df1_t *h);
/* The open port's note ("" when none): a USB adapter's latency timer left above 1 ms. @since 0.5 */
DF1_API const char *df1_port_note(const df1_t *h);
DF1_API int df1_get_option(const df1_t *h, enum df1_option opt);
/* Radio modem store and forward (libdf1(7) RADIO MODEM), @since 0.5. table: 32 bytes,
 * bit s%8 of byte s/8 set = rebroadcast packets for station s (255: broadcasts too);
 * NULL or all clear: forward nothing. */
DF1_API int df1_set_forward(df1_t *h, const uint8_t *table);
/* The table set, into 32 bytes: 1 when a bit is set, 0 when none. @since 0.5 */
DF1_API int df1_get_forward(const df1_t *h, uint8_t *table);
/* A station list "1,3-5,255" (0-255, commas, ranges; "" or "none": empty) into a
 * 32-byte forward table; 0, or DF1_E_INVAL naming nothing (the caller names the text).
 * @since 0.5 */
DF1_API int df1_forward_parse(const char *list, uint8_t *table);
/* What a radio-modem handle did (fields are only added at the end), @since 0.5:
 * packets sent (commands, replies, relayed copies), packets received with a good
 * check, packets relayed, duplicates dropped, bad packets dropped (check, framing),
 * packets not sent (no CTS, DCD stayed up). */
struct df1_radio_stats { uint64_t sent, received, relayed, duplicates, bad_packets, undelivered; };
/* Fills *out (zeros on another link mode). @since 0.5 */
DF1_API int df1_radio_stats(const df1_t *h, struct df1_radio_stats *out);

/* Catalog messages (notices, errors) as they happen. level = enum df1_severity. */
typedef void (*df1_log_fn)(void *user, int catalog_id, enum df1_severity sev, const char *text);
DF1_API void df1_set_log(df1_t *h, df1_log_fn fn, void *user);
/* Every chunk of bytes sent (DF1_DIR_TX) or received (DF1_DIR_RX), with a
 * monotonic timestamp in microseconds. */
enum df1_dir { DF1_DIR_RX = 0, DF1_DIR_TX = 1 };
typedef void (*df1_trace_fn)(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us);
DF1_API void df1_set_trace(df1_t *h, df1_trace_fn fn, void *user);

/* target: "/dev/ttyUSB0" (termios), "tcp://host:port" (raw DF1 over TCP).
 * DF1_E_BUSY if another process holds the port, DF1_E_NODEV, DF1_E_PERM, DF1_E_SYS. */
DF1_API int  df1_open(df1_t *h, const char *target);
/* Serve or talk on an already open descriptor (a pty, a socket); not closed by df1_close
 * unless take_ownership. */
DF1_API int  df1_open_fd(df1_t *h, int fd, bool take_ownership);
DF1_API void df1_close(df1_t *h);       /* restores the port's settings; keeps config */
DF1_API bool df1_is_open(const df1_t *h);
/* A descriptor to watch for cancellation: when it becomes readable, waits end with DF1_E_INTR. */
DF1_API int  df1_set_cancel_fd(df1_t *h, int fd);

/* Detail of the last error on this handle. */
struct df1_error_detail {
	int code;          /* DF1_E_* */
	int sys_errno;     /* errno for DF1_E_SYS, else 0 */
	int station;       /* destination station, -1 if none */
	uint8_t sts;       /* PLC STS byte (DF1_E_REMOTE) */
	uint8_t ext_sts;   /* EXT STS when sts == 0xF0 */
	bool has_ext_sts;
	int catalog_id;    /* the catalog ID reported, or 0 */
	char message[160]; /* formatted text, e.g. "PLC error: STS 0xF0 (...), EXT STS 0x06 (...)";
	                    * since 0.2 without the address in front: that is in address */
	char address[64];  /* @since 0.2: the address the error concerns ("N7:0", as the
	                    * caller wrote it for df1_read_multi), "" when none */
};
DF1_API const struct df1_error_detail *df1_last_error(const df1_t *h);

/* ------------------------------------------------------------------------
 * Reading and writing (master side). station = destination 0..254.
 * Requests larger than one packet are split transparently.
 * ------------------------------------------------------------------------ */
/* Generic: n elements starting at addr, one df1_value per element (or per bit for a /bit). */
DF1_API int df1_read(df1_t *h, int station, const char *addr, struct df1_value *out, size_t n);
DF1_API int df1_write(df1_t *h, int station, const char *addr, const struct df1_value *in, size_t n);
DF1_API int df1_read_addr(df1_t *h, int station, const struct df1_addr *a, struct df1_value *out, size_t n);
DF1_API int df1_write_addr(df1_t *h, int station, const struct df1_addr *a, const struct df1_value *in, size_t n);

/* Typed helpers: return n or DF1_E_*; DF1_E_TYPE if the file does not hold that type. */
DF1_API int df1_read_int16(df1_t *h, int station, const char *addr, int16_t *out, size_t n);
DF1_API int df1_read_int32(df1_t *h, int station, const char *addr, int32_t *out, size_t n);
DF1_API int df1_read_float(df1_t *h, int station, const char *addr, float *out, size_t n);
DF1_API int df1_read_bit(df1_t *h, int station, const char *addr, bool *out);
DF1_API int df1_read_string(df1_t *h, int station, const char *addr, char *out, size_t cap);
DF1_API int df1_read_tcr(df1_t *h, int station, const char *addr, struct df1_tcr *out, size_t n);
DF1_API int df1_write_int16(df1_t *h, int station, const char *addr, const int16_t *in, size_t n);
DF1_API int df1_write_int32(df1_t *h, int station, const char *addr, const int32_t *in, size_t n);
DF1_API int df1_write_float(df1_t *h, int station, const char *addr, const float *in, size_t n);
DF1_API int df1_write_bit(df1_t *h, int station, const char *addr, bool value);  /* one bit only */
DF1_API int df1_write_string(df1_t *h, int station, const char *addr, const char *text);
DF1_API int df1_write_tcr(df1_t *h, int station, const char *addr, const struct df1_tcr *in, size_t n);
/* Raw element bytes as they are on the wire (little-endian words). Returns bytes. */
DF1_API int df1_read_raw(df1_t *h, int station, const char *addr, uint8_t *buf, size_t nbytes);
DF1_API int df1_write_raw(df1_t *h, int station, const char *addr, const uint8_t *buf, size_t nbytes);

/* Any PCCC command: app bytes after the 6-byte header (FNC + data) out, reply data in.
 * The library fills DST SRC CMD STS TNS. Returns reply data length or DF1_E_*. */
DF1_API int df1_command(df1_t *h, int station, uint8_t cmd, const uint8_t *body, size_t body_len,
                        uint8_t *reply, size_t reply_cap);

/* ------------------------------------------------------------------------
 * Diagnostics
 * ------------------------------------------------------------------------ */
struct df1_diag_status {
	uint8_t type_code;      /* processor type code (e.g. 0x5B SLC 5/04, 0x9F ML1400, 0x15 PLC-5/40) */
	char name[32];          /* "SLC 5/04", "MicroLogix 1400", "PLC-5/40", or "unknown (0xNN)" */
	char series;            /* 'A' .. */
	int revision;           /* FRN / revision number */
	int mode;               /* mode code as the controller reports it */
	char mode_text[24];     /* "run", "program", "test", ... */
	char bulletin[16];      /* ASCII bulletin name when present */
	uint8_t raw[64];
	size_t raw_len;
};
DF1_API int df1_diag_status(df1_t *h, int station, struct df1_diag_status *out);

/* 0F/80 change mode (SLC 5/03+, MicroLogix): 1 program, 6 run. */
DF1_API int df1_change_mode(df1_t *h, int station, int mode);

/* Counters of doc/REQUIREMENTS.md 004 by catalog ID (2525-2551, 2560, 2561). */
DF1_API int df1_counter(const df1_t *h, int id, uint64_t *value);
DF1_API void df1_counters_reset(df1_t *h);
/* Active station list: 1 active, 0 inactive. */
DF1_API int df1_station_active(const df1_t *h, int station);
DF1_API int df1_station_set_active(df1_t *h, int station, bool active);

/* ------------------------------------------------------------------------
 * Decoding traffic (df1mon, tests): an incremental decoder fed any bytes.
 * ------------------------------------------------------------------------ */
enum df1_sym {
	DF1_SYM_NONE = 0,
	DF1_SYM_ACK, DF1_SYM_NAK, DF1_SYM_ENQ, DF1_SYM_EOT,
	DF1_SYM_POLL,   /* DLE ENQ STN BCC (half duplex); station set */
	DF1_SYM_FRAME,  /* a message frame; data/len are the de-stuffed app bytes */
	DF1_SYM_ERROR,  /* a malformation: error = catalog ID (2512 2513 2514 2518; 2507 bad poll BCC) */
};

struct df1_symbol {
	enum df1_sym kind;
	bool master_msg;        /* DLE SOH STN DLE STX ... (half-duplex master message) */
	bool has_station;
	uint8_t station;        /* poll STN or master-message STN */
	const uint8_t *data;    /* FRAME: app bytes (DST SRC CMD STS TNS ...); valid until the next feed */
	size_t len;
	enum df1_check check;   /* check used for this frame (resolved when AUTO) */
	bool check_ok;
	uint16_t check_expected, check_actual;
	bool embedded;          /* ACK/NAK found inside a frame (embedded response) */
	int error;              /* ERROR: catalog ID */
	uint8_t bad_byte;       /* ERROR 2514: the byte after DLE */
	size_t wire_len;        /* bytes of the wire this symbol took */
};

struct df1_decoder;
/* check: CRC, BCC or AUTO (the first good frame decides). DLE 0F is taken as NAK
 * and embedded ACK/NAK are accepted, as on a handle's defaults. DF1_E_INVAL, DF1_E_NOMEM. */
DF1_API int  df1_decoder_new(struct df1_decoder **out, enum df1_check check);
DF1_API void df1_decoder_free(struct df1_decoder *d);   /* NULL is a no-op */
DF1_API void df1_decoder_reset(struct df1_decoder *d);  /* back to idle, keeps settings */
/* Half duplex: DLE ENQ is read as a poll (DLE ENQ STN BCC); off (full duplex,
 * DLE ENQ alone) by default. Returns 0 or DF1_E_INVAL. */
DF1_API int  df1_decoder_set_half_duplex(struct df1_decoder *d, bool on);
/* On: DLE ENQ + a poll's shape (STN, stuffed; its two's complement) is a poll, else
 * the full-duplex ENQ. Replaces set_half_duplex's setting (and it this one). */
DF1_API int  df1_decoder_set_duplex_auto(struct df1_decoder *d, bool on);
/* Consume bytes until one symbol is complete; returns bytes consumed (sym->kind
 * NONE when all were consumed without completing one; 0 with a symbol: a duplex
 * auto ENQ that in[0] showed was no poll, in[0] to be fed again). */
/* The link options that change how bytes decode: DF1_OPT_HD_BCC_INCLUDES_STX (default 0),
 * DF1_OPT_ACCEPT_NAK_0F (1), DF1_OPT_EMBEDDED_RESPONSES (1), DF1_OPT_EOT_WITH_BCC (0);
 * value 0 or 1. So a decoder reads a line as a handle with those options does. Returns 0,
 * or DF1_E_INVAL (another option, another value). @since 0.3 */
DF1_API int  df1_decoder_set_option(struct df1_decoder *d, enum df1_option opt, int value);
DF1_API size_t df1_decoder_feed(struct df1_decoder *d, const uint8_t *in, size_t n, struct df1_symbol *sym);
/* True when the last byte fed was a DLE still waiting for its second byte (outside a
 * frame, in a frame's data, in a stuffed STN): at the end of an input, a reader that
 * ends the symbol under way with DLE STX feeds only the STX then. NULL: false. @since 0.4 */
DF1_API bool df1_decoder_dle_pending(const struct df1_decoder *d);

/* An application-layer message, decoded for display. */
struct df1_msg {
	uint8_t dst, src, cmd, sts, fnc;
	uint16_t tns;
	bool is_reply;          /* CMD bit 6 */
	bool has_fnc;
	bool has_ext_sts;
	uint8_t ext_sts;
	const char *name;       /* "SLC typed read (3 fields)", "echo", ... */
	bool has_addr;
	struct df1_addr addr;   /* commands that carry an address */
	int size;               /* byte size / element count the command asks for, -1 if none */
	const uint8_t *data;    /* write data (commands) or reply data (replies) */
	size_t data_len;
};
/* Decode app bytes (DST SRC CMD STS TNS ...). DF1_E_TOO_SHORT / DF1_E_BAD_REPLY. */
DF1_API int df1_msg_decode(const uint8_t *app, size_t n, struct df1_msg *m);
/* Decode element values of a file type from wire bytes (little-endian; the caller
 * word-swaps PLC-5 word-range floats first). */
DF1_API int df1_values_decode(enum df1_file_type t, const uint8_t *bytes, size_t n,
                              struct df1_value *out, size_t max);

/* Serving (slave / peer side: struct df1_server_ops, df1_serve(), the responder of
 * a master, fault injection) and the data table (df1_table(3)): df1_server.h,
 * included at the end. */

/* ------------------------------------------------------------------------
 * Configuration files (CSV, libcsv): network and mapping (libdf1(7))
 * ------------------------------------------------------------------------ */
enum df1_mode { DF1_MODE_MASTER = 0, DF1_MODE_SLAVE = 1, DF1_MODE_PEER = 2 };

struct df1_net_config {
	int station;            /* 0..254, default 5 */
	enum df1_mode mode;     /* default Master */
	enum df1_plc plc;       /* default PLC5 */
	enum df1_check check;   /* default CRC */
	int nak_retries;        /* 0..10, default 3 */
	int enq_retries;        /* 0..10, default 3 */
	int cmd_timeout_ms;     /* 500..5000, default 1000 */
	char port[256];         /* "/dev/ttyS0", "tcp://host:port" (Com_Port 1 -> /dev/ttyS0) */
	int baud;               /* default 9600 */
	int data_bits;          /* 5..8, default 8 */
	int stop_bits;          /* 1..2, default 1 */
	char parity;            /* 'N' 'E' 'O', default 'N' */
	int timeout_ms;         /* 0..360000, default 1000 */
	int tx_delay_ms;        /* 0..65535, default 0 */
	bool handshake;         /* default No */
	bool duplex_half;       /* Mode Master/Slave on a multidrop line: half duplex; Peer: full */
	bool port_given;        /* the file set Com_Port (port[] is not just the default) */
	/* Columns beyond the seed's (@since 0.5; libdf1(7) "Network file"): Link
	 * Full | Half | Radio (empty: from Mode), Store_Forward a station list
	 * (df1_forward_parse; Link Radio only). */
	bool radio;             /* Link Radio: DF1_RADIO_MODEM */
	bool forward_set;       /* Store_Forward given: forward[] is the table */
	uint8_t forward[32];    /* df1_set_forward(3)'s table */
};

/* Report of one problem in a configuration file. */
struct df1_config_issue {
	int catalog_id;         /* 2552-2559 (network), 2501-2504 (mapping) */
	int item;               /* 1-based data row number */
	int line;               /* line in the file */
	char text[200];         /* formatted catalog message */
};
typedef void (*df1_config_issue_fn)(void *user, const struct df1_config_issue *issue);

DF1_API void df1_net_config_defaults(struct df1_net_config *c);
/* Load the first (or only) data row of a network CSV. Every invalid value is
 * reported through fn (may be NULL); returns DF1_E_CONFIG if any. */
DF1_API int df1_net_config_load(const char *path, struct df1_net_config *c, df1_config_issue_fn fn, void *user);
/* Apply a network config to a handle (serial settings, link, timeouts, retries...). */
DF1_API int df1_apply_net_config(df1_t *h, const struct df1_net_config *c);

/* RECEIVE (Command Receive, @since 0.5): a region of the loader's own table that PLCs
 * write with MSG (df1gw(1)); df1_tag_load_map() skips it, df1_tag_add() refuses it. */
enum df1_access { DF1_ACCESS_READ = 1, DF1_ACCESS_WRITE = 2, DF1_ACCESS_READWRITE = 3, DF1_ACCESS_RECEIVE = 4 };

struct df1_tag_config {
	char name[64];
	enum df1_access access;
	char type[16];          /* Type column as written: "" (the address's own), INT, DINT,
	                         * LONG, REAL, FLOAT, BOOL, STRING, TIMER, COUNTER, CONTROL
	                         * (df1_tag_value_kind) */
	int station;            /* 0..254 */
	enum df1_plc plc;
	struct df1_addr addr;
	int count;              /* elements, default 1 */
	int scan_ms;            /* default 1000 */
};
/* Load a mapping CSV. Each valid row calls row_fn; each bad row is reported through
 * issue_fn and skipped (strict: the load fails with DF1_E_CONFIG). Returns rows loaded. */
typedef int (*df1_tag_row_fn)(void *user, const struct df1_tag_config *tag);
DF1_API int df1_map_load(const char *path, bool strict, df1_tag_row_fn row_fn,
                         df1_config_issue_fn issue_fn, void *user);

/* ------------------------------------------------------------------------
 * Poll engine (scan list, block coalescing, quality, station health, write queue)
 * Declarations are added by the poll engine (lib/poll/); see df1_poll(3).
 *
 * Tags (df1_tag_add, df1_tag_load_map) are polled by df1_poll(), which runs the
 * work that is due (one scan of the stations in address order, queued writes in
 * the free slots between its transactions) and returns. Per station and file,
 * tags are coalesced into block reads up to the controller's packet limit; a
 * block that fails with an address error is split until the bad tag is alone.
 * Station health follows doc/REQUIREMENTS.md 000/002/004 (retries, watchdog, offline, slow
 * retry, one-time poll on recovery); see df1_poll(3) for the exact rules.
 * Thread rule: df1_tag_write() may be called from any thread; everything else
 * belongs to the thread that runs df1_poll().
 * ------------------------------------------------------------------------ */
enum df1_quality {
	DF1_QUALITY_BAD = 0,        /* no usable value (see the reason) */
	DF1_QUALITY_UNCERTAIN = 1,  /* the last good value, station not answering (not yet offline) */
	DF1_QUALITY_GOOD = 2,       /* read at the last attempt */
};

enum df1_quality_reason {
	DF1_REASON_NONE = 0,            /* GOOD */
	DF1_REASON_NOT_YET_READ,        /* BAD: no read has completed yet (and write-only tags) */
	DF1_REASON_COMM_FAILURE,        /* UNCERTAIN (BAD if never read): station did not answer */
	DF1_REASON_STATION_OFFLINE,     /* BAD: the station's watchdog expired, it is offline */
	DF1_REASON_PLC_ERROR,           /* BAD: the PLC refused the read (STS / EXT STS kept) */
	DF1_REASON_CONFIG,              /* BAD: the address cannot be read with this PLC type */
};

/* "GOOD" "UNCERTAIN" "BAD"; "none" "not_yet_read" "comm_failure" "station_offline"
 * "plc_error" "config". Static strings, never NULL ("?" when unknown). */
DF1_API const char *df1_quality_name(enum df1_quality q);
DF1_API const char *df1_reason_name(enum df1_quality_reason r);

/* A snapshot of one tag (df1_tag_get). */
struct df1_tag_state {
	int id;
	const struct df1_tag_config *config; /* owned by the handle, valid until df1_free() */
	size_t count;                   /* values (config->count) */
	const struct df1_value *values; /* owned by the handle; changes only inside df1_poll() */
	struct df1_value value;         /* copy of values[0] */
	bool has_value;                 /* a read has completed at least once */
	enum df1_quality quality;
	enum df1_quality_reason reason;
	int64_t last_good_ms;           /* CLOCK_MONOTONIC ms of the last good read, 0 = never */
	int64_t last_good_wall_ms;      /* CLOCK_REALTIME ms since the epoch, 0 = never */
	int64_t age_ms;                 /* now - last_good_ms at df1_tag_get(), -1 = never */
	int last_error;                 /* DF1_E_* of the last failed read, 0 = none */
	uint8_t sts, ext_sts;           /* PLC STS / EXT STS behind DF1_REASON_PLC_ERROR */
	uint64_t reads;                 /* good reads of this tag */
};

/* Add a tag; copies *c. count 1..1000; scan_ms >= 0 (0: every scan), c->name
 * unique when not empty. Returns the tag id (0, 1, ...) or DF1_E_INVAL /
 * DF1_E_CONFIG (duplicate name) / DF1_E_TYPE, DF1_E_ADDR_RANGE (bits that do not
 * fit the file or their word) / DF1_E_NOMEM. Readable tags (DF1_ACCESS_READ
 * bit) are polled; write-only tags only take df1_tag_write(). */
DF1_API int df1_tag_add(df1_t *h, const struct df1_tag_config *c);
/* The kind of a tag's values: its Type's (INT int16, DINT/LONG int32,
 * REAL/FLOAT float, BOOL bit, STRING, TIMER/COUNTER/CONTROL a whole element),
 * the address's own (df1_addr_value_kind) when Type is empty. Returns the
 * enum df1_value_kind, or DF1_E_INVAL (not a Type) / DF1_E_TYPE (a Type that
 * cannot hold the address's values: FLOAT on a bit, INT on L or a whole
 * timer). @since 0.5 */
DF1_API int df1_tag_value_kind(const struct df1_tag_config *c);
/* Add every row of a mapping CSV (df1_map_load). Rows with problems and
 * duplicate names are reported through issue_fn (may be NULL) and skipped; in
 * strict mode any problem adds nothing and returns DF1_E_CONFIG.
 * Returns the number of tags added or DF1_E_*. */
DF1_API int df1_tag_load_map(df1_t *h, const char *path, bool strict,
                             df1_config_issue_fn issue_fn, void *user);
DF1_API int df1_tag_count(const df1_t *h);
/* Id of the tag with this name, or DF1_E_INVAL. */
DF1_API int df1_tag_find(const df1_t *h, const char *name);
/* Fill *st with the tag's current state. 0 or DF1_E_INVAL. */
DF1_API int df1_tag_get(const df1_t *h, int id, struct df1_tag_state *st);

/* Called from df1_poll() when a tag's value(s), quality or reason change. */
typedef void (*df1_tag_fn)(void *user, int id, const struct df1_tag_state *st);
DF1_API int df1_set_tag_callback(df1_t *h, df1_tag_fn fn, void *user);

/* Queued writes. Safe from any thread. n values (1..count of the tag) are
 * checked against the tag's type now (DF1_E_TYPE, DF1_E_RANGE, DF1_E_INVAL for a
 * read-only tag) and sent by df1_poll() in the next free slot. Each accepted
 * write ends exactly once through done(user, tag id, write id, result), called
 * from the df1_poll() thread: result 0 = written, or the DF1_E_* of the failure.
 * A failed write is never resent by the engine (DF1_E_TIMEOUT: the PLC may or
 * may not have executed it). df1_close() keeps the queue: its writes are sent
 * after the next df1_open(). Writes still queued at df1_free() end with
 * DF1_E_NOT_OPEN. Returns the write id (> 0) or DF1_E_*. */
typedef void (*df1_write_done_fn)(void *user, int tag_id, int write_id, int result);
DF1_API int df1_tag_write(df1_t *h, int id, const struct df1_value *v, size_t n,
                          df1_write_done_fn done, void *user);

/* Run the work that is due: queued writes, then one scan of what is due, with
 * writes interleaved between its transactions. If nothing was due, wait up to
 * timeout_ms (-1: until the next due item) for due work or a queued write, run
 * it and return. Never sleeps otherwise. Returns the transactions done (0 if
 * none) or DF1_E_NOT_OPEN, DF1_E_INTR (cancel fd), DF1_E_NOMEM, DF1_E_INVAL,
 * DF1_E_SYS. Communication and PLC errors go to tag quality and station health. */
DF1_API int df1_poll(df1_t *h, int timeout_ms);
/* Milliseconds until df1_poll() has due work (0 = now), or -1 when nothing is
 * scheduled. A descriptor that becomes readable when a write is queued (for an
 * application's own poll loop; df1_poll() drains it), or DF1_E_*. */
DF1_API int df1_poll_next_ms(const df1_t *h);
DF1_API int df1_poll_fd(df1_t *h);

/* Any PCCC command (CMD STS TNS [FNC] data, 4..DF1_PCCC_MAX bytes, copied) to a
 * station, from any thread, queued with df1_tag_write()'s writes (one FIFO) and
 * sent between two transactions with the line's TNS. done() runs once in the
 * df1_poll() thread: result 0 with the reply (CMD|40 STS TNS ...; the caller's
 * TNS; error STS passed through), or DF1_E_* when no reply came. Writes
 * (df1_pccc_is_write) are not resent unless df1_error_unexecuted(). Returns 0,
 * DF1_E_INVAL (also: no engine yet), DF1_E_BUSY (DF1_PCCC_QUEUE_MAX waiting),
 * DF1_E_NOMEM. df1_poll(3). @since 0.4 */
#define DF1_PCCC_MAX 262        /* the link layer's 264 app bytes of a frame less DST SRC */
#define DF1_PCCC_QUEUE_MAX 64
typedef void (*df1_pccc_done_fn)(void *user, int result, const uint8_t *reply, size_t n);
DF1_API int df1_poll_submit_pccc(df1_t *h, int station, const uint8_t *pccc, size_t n,
                                 df1_pccc_done_fn done, void *user);
/* Every write and command queued and not yet started ends now, done() with
 * DF1_E_NOT_OPEN, nothing sent: for a closed line whose queue must not run late
 * after the next df1_open(). Returns how many, or DF1_E_INVAL. @since 0.5 */
DF1_API int df1_poll_cancel_queued(df1_t *h);

/* Station health (doc/REQUIREMENTS.md 000): a station goes offline when absolute_retries > 0
 * and more than that many attempts in a row failed, or else when watchdog_ms
 * passed since its last answer (at a failed attempt). Offline stations are
 * retried once every watchdog_ms / 2. Defaults 10000 ms, 0.
 * watchdog_ms 0..86400000, absolute_retries 0..1000. */
DF1_API int df1_poll_set_watchdog(df1_t *h, int watchdog_ms, int absolute_retries);
/* Station discovery (doc/REQUIREMENTS.md 002): every address lo..hi without tags is polled
 * too (a link test in half duplex, an empty echo in full duplex): stations that
 * answer are probed once per second, absent ones one address per second in
 * turn. lo = -1 turns it off (default). */
DF1_API int df1_poll_set_station_range(df1_t *h, int lo, int hi);

struct df1_poll_stats {
	uint64_t scans;                 /* scans completed */
	int64_t last_scan_ms;           /* duration of the last scan */
	int64_t max_scan_ms;
	unsigned last_scan_transactions; /* reads and probes of the last scan, retries included */
	uint64_t transactions;          /* all: reads, probes, writes */
	uint64_t reads, read_failures;  /* block reads (retries included) */
	uint64_t probes, probe_failures;
	uint64_t writes, write_failures;
	uint64_t retries;               /* doc/REQUIREMENTS.md 002 retries of a station that answered */
	uint64_t splits;                /* blocks split after an address error */
	unsigned tags, blocks;          /* scan list: tags, block reads per full scan */
	unsigned stations_offline;
	unsigned writes_queued;
};
DF1_API int df1_poll_stats(const df1_t *h, struct df1_poll_stats *out);

enum df1_station_state {
	DF1_STATION_UNKNOWN = 0,  /* not polled yet */
	DF1_STATION_OK,           /* answered the last attempt */
	DF1_STATION_FAILING,      /* failed, watchdog not expired: its tags UNCERTAIN */
	DF1_STATION_OFFLINE,      /* watchdog expired: its tags BAD, slow retry */
	DF1_STATION_ABSENT,       /* discovery: never answered */
};
struct df1_station_health {
	int station;
	enum df1_station_state state;
	int tags, blocks;               /* readable tags and block reads of this station */
	int64_t last_good_ms;           /* CLOCK_MONOTONIC ms of its last answer, 0 = never */
	int64_t last_attempt_ms;
	int64_t next_retry_ms;          /* OFFLINE: not before this time */
	int consecutive_failures;
	uint64_t attempts, failures;    /* transactions to it (reads, probes, writes) */
	int last_error;
};
/* "unknown" "ok" "failing" "offline" "absent". */
DF1_API const char *df1_station_state_name(enum df1_station_state s);

/* ------------------------------------------------------------------------
 * Multi-address reads, packet limits and station health (@since 0.2)
 * ------------------------------------------------------------------------ */
/* One address of df1_read_multi(). The caller owns the struct and its buffers. */
struct df1_read_req {
	const char *text;          /* in: address text ("N7:0", "B3/5"), or NULL: addr as given */
	struct df1_addr addr;      /* in when text is NULL, else out: text parsed */
	size_t count;              /* in: values wanted, 1..65535 (bits for a bit address) */
	struct df1_value *values;  /* in: the caller's buffer of count values */
	int result;                /* out: count when read; 0 not read (the call ended
	                            * first); or the DF1_E_* of this address */
};
/* df1_read_multi flag: all or nothing, stop at the first failure (nothing is
 * sent when a request does not pass the checks). */
#define DF1_READ_MULTI_STOP 1u
/* Read n addresses of one station in the fewest transactions, without the
 * poll engine: ranges of one file that overlap or touch are one block read, a
 * gap is read through when that saves packets (the packet limits of the
 * handle's PLC type, doc/PROTOCOL.md 6; not on a PLC-5, whose packet overhead varies);
 * bits, T/C/R words and T/C/R bits come out of the elements read; I/O, PLC-5
 * "$" addresses and other sub-elements are read on their own. A block the PLC
 * refuses is read again address by address, so one bad address does not hide
 * the others' values; a failure without an answer (timeout, retry limit, port,
 * interrupt) ends the call. *reads (may be NULL): the read calls made (one per
 * block or address read alone; each may take several packets). Nothing is
 * kept after the call; it allocates its plan once, nothing per packet.
 * Returns n when every request was read, else the DF1_E_* of the first failure
 * in reading order (checks first, then blocks in the order of their first
 * request, then the addresses read alone); df1_last_error() describes it, its
 * address field naming the request. DF1_E_INVAL: no requests, unknown flags,
 * bad station. @since 0.2 */
DF1_API int df1_read_multi(df1_t *h, int station, struct df1_read_req *reqs, size_t n,
                           unsigned flags, unsigned *reads);
/* Data bytes one read or write packet carries for a PLC type, from the
 * library's one packet-limit table (doc/PROTOCOL.md 6): SLC 5/03+ and MicroLogix read
 * 236, write 234; SLC 5/01-5/02 82; PLC-2 244; PLC-3 244 / 228; PLC-5 240 for the whole typed
 * packet, address and type/data included (116 integers after N7:0's address). DF1_OPT_MAX_PACKET does not apply
 * (no handle). Returns the bytes, or DF1_E_INVAL for an unknown type. Pure,
 * thread-safe. @since 0.2 */
DF1_API int df1_packet_max(enum df1_plc plc, bool write);
/* The health of one station of the poll engine (0..254) into *out.
 * Returns 0, or DF1_E_INVAL (no handle, no out, station out of range). @since 0.2 */
DF1_API int df1_station_health(const df1_t *h, int station, struct df1_station_health *out);
/* Deprecated since 0.2: the old name of df1_station_health(), kept so that
 * existing programs still link. */
#if defined(__GNUC__)
#define DF1_DEPRECATED(msg) __attribute__((deprecated(msg)))
#else
#define DF1_DEPRECATED(msg)
#endif
DF1_API int df1_poll_station(const df1_t *h, int station, struct df1_station_health *out)
	DF1_DEPRECATED("use df1_station_health");

#ifdef __cplusplus
}
#endif

#include "df1_server.h"
#include "df1_eip.h"
#include "df1_probe.h"

#endif /* LIBDF1_DF1_H */
