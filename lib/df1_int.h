/*
 * df1_int.h - the handle (struct df1) and internal prototypes shared by the
 * non-pure layers (port, link, client, server, poll). Not installed.
 */
#ifndef LIBDF1_DF1_INT_H
#define LIBDF1_DF1_INT_H

#include <termios.h>
#include "df1.h"
#include "base.h"
#include "frame.h"
#include "port.h"

#define DF1_LOCAL __attribute__((visibility("hidden")))

/* Counters of seeds/004, indexed by ID - CNT_BASE (2525..2561). */
#define CNT_BASE 2525
#define CNT_COUNT (2561 - 2525 + 1)

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

/* Link responder (lib/link/core.c): replies waiting to be sent or acknowledged. Full duplex
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
	struct link_state link;      /* lib/link/core.c */

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
	void *poll;                  /* poll engine state (lib/poll.c) */
	/* Destructors of the state above, set by the module that allocates it; df1_free()
	 * calls them (or plain free() when NULL). */
	void (*srv_free)(struct df1 *h);
	void (*poll_free)(struct df1 *h);
};

#endif
