/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1_int.h - the handle (struct df1) and internal prototypes shared by the
 * non-pure layers (port, link, client, server, poll). Not installed.
 */
#ifndef LIBDF1_DF1_INT_H
#define LIBDF1_DF1_INT_H

#include "df1.h"
#include "base/base.h"
#include "proto/frame.h"
#include "port/port.h"
#include "link/half_repoll.h"
#include "link/radio_dup.h"

#define DF1_LOCAL __attribute__((visibility("hidden")))

/* Counters of doc/REQUIREMENTS.md 004, indexed by ID - CNT_BASE: the catalog's IDs from
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
	bool plc5_float_swapped;     /* PLC-5 typed 0F/68 67 floats word-swapped (doc/PROTOCOL.md 5) */
	bool slc_io_82;              /* SLC O/I file type codes 82/83, not 8B/8C (doc/PROTOCOL.md 4.11) */
	int max_packet;              /* 0 = per PLC type */
	int plc5_timer_words;        /* 3 or 5: PLC-5 typed-read timers (DF1_OPT_PLC5_TIMER_WORDS) */
	bool plc5_timer_forced;      /* that option was set: plan with it, learn nothing */
	bool plc2_word_addr;         /* PLC-2 commands address words, not bytes (doc/PROTOCOL.md 4.7) */
	bool listen_only;            /* DF1_OPT_LISTEN_ONLY: open read only, never transmit */
	bool eip_connected;          /* DF1_OPT_EIP_CONNECTED: eip:// over a Forward Open connection */
	int line_baud;               /* pace transmitted bytes (simulator); 0 = off */
	int poll_timeout_ms;         /* DF1_OPT_POLL_TIMEOUT_MS: 0 = automatic */
	int scan_time_ms;            /* DF1_OPT_SCAN_TIME_MS: responder's program scan */
	bool no_eot;                 /* DF1_OPT_NO_EOT: half-duplex slave sends no EOT */
	bool low_latency;            /* DF1_OPT_LOW_LATENCY: USB adapters in low latency mode */
	bool plc5_refuse_large;      /* DF1_OPT_PLC5_REFUSE_LARGE: responder, F0/09, not a cut reply */
	bool route;                  /* DF1_OPT_ROUTE: half-duplex master forwards slave messages */
	int max_outstanding;         /* DF1_OPT_MAX_OUTSTANDING: full-duplex commands in flight */
	/* radio modem (lib/link/radio.c) */
	int app_retries;             /* DF1_OPT_APP_RETRIES: a command sent again with no reply */
	int radio_dup;               /* DF1_OPT_RADIO_DUP_DETECT: 0, 1, DF1_DUP_AUTO */
	bool radio_rts_cts;          /* DF1_OPT_RADIO_RTS_CTS: key with RTS, send on CTS */
	int rts_send_ms, rts_off_ms; /* DF1_OPT_RTS_SEND_DELAY_MS, DF1_OPT_RTS_OFF_DELAY_MS */
	int dcd_wait_ms;             /* DF1_OPT_DCD_WAIT_MS: 0 off */
	bool forward_set;            /* a bit of forward[] is set */
	uint8_t forward[32];         /* df1_set_forward: bit s = rebroadcast packets for s */
};

/* The full-duplex master's pipeline (lib/link/pipe.c): commands submitted and
 * not yet taken back, each matched to its reply by SRC and TNS. One spare slot
 * beyond the option's maximum: a synchronous transaction while a scan's reads
 * are all in flight. */
#define LINK_PIPE_MAX 17
struct link_pipe_slot {
	uint8_t state;               /* PIPE_FREE .. PIPE_DONE (pipe.c) */
	bool abandoned;              /* nobody takes the result: freed when it ends */
	uint32_t seq;                /* submission order */
	int naks, enqs;
	int64_t deadline_ms;         /* ACK timer (sent), reply timer (ACKed) */
	int rc;                      /* DONE: reply length or DF1_E_* */
	struct df1_error_detail err; /* DONE with an error: its detail */
	size_t cmd_len, reply_len;
	uint8_t cmd[FRAME_MAX_DATA];
	uint8_t reply[FRAME_MAX_DATA];
};
struct link_pipe {
	struct link_pipe_slot slot[LINK_PIPE_MAX];
	uint32_t seq;
	int tx;                      /* slot + 1 whose frame waits for its ACK, 0: none */
	int used;                    /* slots not FREE */
};

/* Last message accepted from a station: duplicate and stale detection. */
struct station_state {
	bool active;                 /* active station list (doc/REQUIREMENTS.md 004); all start active */
	struct repoll_est reply_latency; /* half-duplex master: when to poll it (repoll.h) */
	bool have_last;
	uint8_t last_hdr[6];         /* DST SRC CMD STS TNS TNS of the last accepted message */
	size_t last_len;             /* its length and a hash of all of it: a duplicate that */
	uint32_t last_hash;          /* differs is a new command, not a retransmission */
	uint8_t plc5_timer_words;    /* PLC-5 typed-read timers it answered with: 3, 5, 0 = not yet */
};

struct server_state;             /* lib/server/server_dispatch.c */

/* A link of its own, for a scheme whose target does not carry DF1 frames
 * (eip://, lib/eip/eip_link.c): the scheme table (lib/scheme.c) names it, the
 * handle keeps it, and the link layer's entry points (lib/link/link.c) hand
 * each command to it instead of running DF1 over the port. Such a link is a
 * client: it neither serves nor pipelines, and has no duplex. */
struct own_link_ops {
	const char *scheme;          /* "eip://", for messages */
	/* Open target: set up h->own_link_data and open the port h->port (set by
	 * df1_open from the scheme's row). 0 or DF1_E_* (nothing left open). */
	int (*open)(struct df1 *h, const char *target);
	/* Take leave of the peer while the port is still open; free h->own_link_data. */
	void (*close)(struct df1 *h);
	/* One command (DST SRC CMD STS TNS FNC ...), TNS stamped: the reply's app
	 * bytes as the DF1 link gives them, length, or DF1_E_*. */
	int (*transact)(struct df1 *h, const uint8_t *cmd, size_t n, uint8_t *reply, size_t cap);
	/* The peer's liveness (df1_link_test): 0 or DF1_E_*. */
	int (*test)(struct df1 *h);
};

/* The responder's state (lib/link/link.h): owned by the server (lib/server/server_dispatch.c),
 * lent to the link layer for the length of a link_serve() call. */
struct link_responder;

struct df1 {
	struct df1_config cfg;

	/* port: the backend's vtable and its own state; the descriptor every
	 * backend reads and waits on (as libmodbus keeps ctx->s beside backend_data) */
	const struct port_ops *port;
	void *port_data;             /* the backend's (struct termios_port, struct fd_port), NULL */
	int fd;                      /* -1 when closed */
	int cancel_fd;               /* -1: none */
	char port_name[128];         /* device path or host:port, for messages */
	char port_note[1024];         /* open-time note (df1_port_note), "" when none */

	/* link */
	struct frame_decoder dec;
	uint16_t next_tns;
	uint8_t last_response;       /* receiver's last response symbol: DF1_ACK or DF1_NAK */
	struct station_state stations[256];
	uint8_t rxbuf[512];          /* bytes read from the port not yet fed to the decoder */
	size_t rx_len, rx_pos;
	uint8_t echo_buf[FRAME_MAX_WIRE]; /* own transmission to discard on 2-wire lines */
	size_t echo_len, echo_pos;
	int64_t rx_last_ms;          /* time of the last byte read (lib/link/core.c) */
	int64_t tx_end_us;           /* when our last byte has left the line (df1_now_us clock) */
	uint8_t tx_hold[4];          /* DLE symbols to go out with our next transmission */
	bool hold_reply_ack;         /* poll engine: a reply's ACK may wait for our next frame */
	size_t tx_hold_len;
	int64_t rx_due_us;           /* line_baud: when the bytes read so far arrived on the line */
	int64_t scan_epoch_ms;       /* DF1_OPT_SCAN_TIME_MS: the first scan began (df1_open) */
	struct link_pipe pipe;       /* full-duplex commands in flight (lib/link/pipe.c) */
	struct radio_dup radio_dups; /* radio modem: the last packets heard (radio_dup.c) */
	struct df1_radio_stats radio_st;
	bool modem_noted;            /* radio modem: "no modem lines" said once */
	bool radio_served;           /* radio modem: df1_serve ran (this node executes commands) */
	const struct own_link_ops *own_link; /* a scheme's own link (eip://), else NULL */
	void *own_link_data;         /* its state (lib/eip/eip_link.c: the session) */

	uint64_t counters[CNT_COUNT];

	df1_log_fn log_fn;
	void *log_user;
	df1_trace_fn trace_fn;
	void *trace_user;

	struct df1_error_detail err;

	/* slave / peer side */
	struct server_state *srv;    /* the server's (lib/server/server_dispatch.c): allocated on first use */
	struct link_responder *resp; /* the server's responder state while link_serve() runs */
	/* A full-duplex master answering its peer's commands (lib/link/peer.c):
	 * df1_set_responder's handler (lib/server/server_api.c) and the
	 * server's reply slots; without one, the link's own slots, allocated on
	 * the first command, carry the STS 10 answers. */
	int (*peer_fn)(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *reply,
	               size_t cap);
	void *peer_ctx;
	struct link_responder *peer_resp;
	struct link_responder *peer_own;
	/* A half-duplex master's messages from slaves (lib/link/route.c),
	 * allocated on the first; a half-duplex slave's own MSG while it waits
	 * for its reply (lib/link/half_msg.c), on the caller's stack. */
	struct link_route *route;
	struct link_own_msg *own_msg;
	void *poll;                  /* poll engine state (lib/poll/) */
	/* Destructors of the state above, set by the module that allocates it; df1_free()
	 * calls them (or plain free() when NULL). */
	void (*srv_free)(struct df1 *h);
	void (*poll_free)(struct df1 *h);
};

/* Discovery (lib/client/discover.c): the one probe of a station, shared by df1_discover
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
