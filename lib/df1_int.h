/*
 * df1_int.h - the handle (struct df1) and internal prototypes shared by the
 * non-pure layers (port, link, client, server, poll). Not installed.
 */
#ifndef LIBDF1_DF1_INT_H
#define LIBDF1_DF1_INT_H

#include <termios.h>
#include "df1.h"
#include "frame.h"
#include "port.h"

#define DF1_LOCAL __attribute__((visibility("hidden")))

/* Counters of seeds/004, indexed by ID - CNT_BASE: the catalog's IDs from
 * the first counter to the last (2525..2561; 2552-2559 inside that range are
 * configuration messages and never counted). */
#define CNT_BASE DF1_ID_CNT_MSG_PACKETS_SENT
#define CNT_COUNT (DF1_ID_CRD_CHAR_RECV - DF1_ID_CNT_MSG_PACKETS_SENT + 1)

struct df1_config {
	int baud, data_bits, stop_bits;
	char parity;                 /* 'N' 'E' 'O' */
	bool rts_cts;
	enum df1_duplex duplex;
	enum df1_check check;
	int station;                 /* our own station (SRC) */
	enum df1_plc plc;
	int timeout_ms;              /* ACK / response timeout */
	int cmd_timeout_ms;          /* whole half-duplex transaction */
	int nak_retries, enq_retries;
	int tx_delay_ms;
	bool dup_detect, embedded, hd_bcc_stx, nak_0f, rs485, echo_discard, eot_bcc, local_tcp;
	bool plc5_float_swapped;     /* PLC-5 typed 0F/68 67 floats word-swapped (spec 5) */
	bool slc_io_82;              /* SLC O/I file type codes 82/83, not 8B/8C (spec 4.11) */
	int max_packet;              /* 0 = per PLC type */
	int line_baud;               /* pace transmitted bytes (simulator); 0 = off */
};

/* Last message accepted from a station: duplicate and stale detection. */
struct station_state {
	bool active;                 /* active station list (seeds/004); all start active */
	bool have_last;
	uint8_t last_hdr[6];         /* DST SRC CMD STS TNS TNS of the last accepted message */
};

struct server_state;             /* lib/server.c */

/* Link responder (lib/link.c): replies waiting to be sent or acknowledged. Full duplex
 * keeps one in flight; a half-duplex slave queues them per station until polled. */
#define LINK_REPLY_SLOTS 8
struct link_reply {
	bool used;
	bool sent;                   /* transmitted, its ACK not seen yet */
	bool stale_first;            /* DF1_FAULT_STALE_REPLY: an old-TNS copy goes out first */
	bool stale_now;              /* full duplex: the frame in flight is that copy */
	bool corrupt;                /* DF1_FAULT_CORRUPT_REPLY: next transmission has a bad check */
	uint8_t stn;                 /* half duplex: the station that owes it */
	uint32_t seq;                /* queue order */
	int naks, enqs;              /* retries of this reply */
	int64_t due_ms;              /* DF1_FAULT_DELAY_REPLY: not before this time */
	int64_t ack_deadline_ms;     /* full duplex: ACK timer */
	size_t len;
	uint8_t app[FRAME_MAX_DATA];
};
struct link_state {
	struct link_reply replies[LINK_REPLY_SLOTS];
	uint32_t seq;
	int awaiting;                /* half-duplex slave: slot + 1 sent on the last poll, 0 none */
	bool awaiting_stale;         /* ... and it was the stale copy */
	bool silenced;               /* full duplex: last frame ignored (SILENT_STATION) */
	int64_t rx_last_ms;          /* time of the last byte read */
};

/* Fault injection on the slave/peer side (df1_server_set_fault), indexed by enum df1_fault. */
#define FAULT_KINDS 8
struct link_faults {
	int per_mille[FAULT_KINDS];
	int value[FAULT_KINDS];
	uint64_t rng;                /* xorshift64* state, from df1_server_set_seed */
};

struct df1 {
	struct df1_config cfg;

	/* port */
	const struct port_ops *port;
	int fd;                      /* -1 when closed */
	bool own_fd;
	bool have_saved_tios;
	struct termios saved_tios;
	int cancel_fd;               /* -1: none */
	int peer_fd;                 /* fd port on a pty master: our own fd on the slave side, so the
	                              * master never sees POLLHUP when no client has it open (-1) */
	int saved_fl;                /* fd port: file status flags to restore on close (-1: none) */
	bool is_socket;              /* write with send(MSG_NOSIGNAL) */
	bool rs485_changed;          /* termios: restore saved_rs485_flags on close */
	uint32_t saved_rs485_flags;
	char port_name[128];         /* device path or host:port, for messages */

	/* link */
	struct frame_decoder dec;
	uint16_t next_tns;
	uint8_t last_response;       /* receiver's last response symbol: DF1_ACK or DF1_NAK */
	struct station_state stations[256];
	uint8_t rxbuf[512];          /* bytes read from the port not yet fed to the decoder */
	size_t rx_len, rx_pos;
	uint8_t echo_buf[FRAME_MAX_WIRE]; /* own transmission to discard on 2-wire lines */
	size_t echo_len, echo_pos;
	struct link_state link;      /* lib/link.c */

	uint64_t counters[CNT_COUNT];

	df1_log_fn log_fn;
	void *log_user;
	df1_trace_fn trace_fn;
	void *trace_user;

	struct df1_error_detail err;

	/* slave / peer side */
	bool serve_station[256];     /* stations we answer as (half-duplex slave) */
	struct link_faults faults;
	struct server_state *srv;    /* allocated on first df1_serve() */
	void *poll;                  /* poll engine state (lib/poll/) */
	/* Destructors of the state above, set by the module that allocates it; df1_free()
	 * calls them (or plain free() when NULL). */
	void (*srv_free)(struct df1 *h);
	void (*poll_free)(struct df1 *h);
};

/* counters and logging (lib/handle.c) */
void df1_count(struct df1 *h, int id);                 /* ++counter[id] */
void df1_count_n(struct df1 *h, int id, uint64_t n);
/* Log a catalog message: formats the seed's format with the arguments. */
void df1_log(struct df1 *h, int catalog_id, ...);
/* Record the last error and return code (for `return df1_fail(h, ...)`). */
int df1_fail(struct df1 *h, int code, int station, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
int df1_fail_remote(struct df1 *h, int station, uint8_t sts, uint8_t ext, bool has_ext);
void df1_clear_error(struct df1 *h);
/* The frame decoder's FRAME_OPT_* for the handle's configuration (lib/handle.c). */
unsigned handle_decoder_opts(const struct df1 *h);

/* Discovery (lib/discover.c): the one probe of a station, shared by df1_discover
 * and the poll engine. Half-duplex master: a poll (df1_link_test); with
 * DISCOVER_IDENTIFY a station that answers it is then asked its diagnostic
 * status. Full duplex: a command to the station, the empty 06/00 echo, or with
 * DISCOVER_IDENTIFY the 06/03 diagnostic status itself. Fills *out (may be NULL).
 * Returns the presence probe's result: >= 0 it answered, else its DF1_E_* (the
 * handle's last error has the detail; DF1_E_REMOTE: it answered with an error
 * STS); DF1_E_INTR, DF1_E_NOMEM, DF1_E_NOT_OPEN of the identification too. */
#define DISCOVER_IDENTIFY 1u
int discover_probe(struct df1 *h, int station, unsigned flags, struct df1_discover_result *out);

#endif
