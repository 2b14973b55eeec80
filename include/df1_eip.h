/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1_eip.h - libdf1's EtherNet/IP server: PCCC over CIP for SCADA and HMI
 * clients (df1_eip_server(3), df1-eip(7)), and the client's discovery
 * (df1_eip_list_identity(3); eip:// targets are df1_open(3)'s). Installed
 * beside df1.h, which includes it; include df1.h.
 */
#ifndef LIBDF1_DF1_EIP_H
#define LIBDF1_DF1_EIP_H

#include "df1.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------
 * EtherNet/IP server (df1_eip_server(3), df1-eip(7)): RegisterSession,
 * ListIdentity (TCP and UDP), ListServices, SendRRData and SendUnitData with
 * Forward Open / Forward Close, Unconnected Send with a route path, the
 * Identity object, and CIP Execute PCCC handed to the caller. One descriptor
 * for the caller's poll loop; nothing blocks. One thread at a time per server.
 * ------------------------------------------------------------------------ */
typedef struct df1_eip_server df1_eip_server_t;

/* What ListIdentity and the Identity object (class 01) report. @since 0.4 */
struct df1_eip_identity {
	uint16_t vendor_id, device_type, product_code;
	uint8_t rev_major, rev_minor;
	uint16_t status;
	uint32_t serial;
	char product_name[33];      /* up to 32 characters */
};

/* @since 0.4 */
struct df1_eip_server_config {
	const char *listen;         /* "[ADDR:]PORT" (TCP and UDP); no ADDR = 127.0.0.1;
	                             * PORT 0: an ephemeral port (df1_eip_server_address) */
	const char *allow;          /* "CIDR[,CIDR]" (1.2.3.0/24, ::1, 10.0.0.5) or NULL = any client */
	bool read_only;             /* refuse PCCC commands that write or change mode */
	int max_clients;            /* 0 = default (32); at most 255 */
	struct df1_eip_identity identity;
};

/* A PCCC command from a client: pccc = CMD STS TNS(2) FNC data as the client
 * sent it (valid during the call only); station = the DF1 station the route
 * path names (Unconnected Send to port 2, link address N; or the Forward Open
 * connection path), or -1 if none. Answer now or later, at most once, with
 * df1_eip_server_reply() or df1_eip_server_fail(); the client sends nothing
 * else until then. @since 0.4 */
typedef void (*df1_eip_pccc_fn)(void *user, df1_eip_server_t *s, uint32_t request, int station,
                                const uint8_t *pccc, size_t n);

/* A server listening on c->listen (TCP and UDP). *out is freed with
 * df1_eip_server_free(). Returns 0, DF1_E_INVAL (bad listen, allow, max_clients,
 * no fn), DF1_E_NOMEM or DF1_E_SYS (socket, bind: errno kept);
 * df1_eip_server_error(NULL) says why. @since 0.4 */
DF1_API int df1_eip_server_new(df1_eip_server_t **out, const struct df1_eip_server_config *c,
                               df1_eip_pccc_fn fn, void *user);
/* "ADDR:PORT" as bound ("[ADDR]:PORT" for IPv6). @since 0.4 */
DF1_API const char *df1_eip_server_address(const df1_eip_server_t *s);
/* The one descriptor to watch: when it is readable, call df1_eip_server_process(). @since 0.4 */
DF1_API int df1_eip_server_fd(const df1_eip_server_t *s);
/* Accept, read, answer, write what is ready; never blocks. Returns the PCCC
 * requests handed to fn (>= 0) or DF1_E_INVAL. @since 0.4 */
DF1_API int df1_eip_server_process(df1_eip_server_t *s);
/* Answer request with a PCCC reply (CMD|40 STS TNS [EXT STS] data; its TNS is
 * the client's). Returns 0, DF1_E_CLOSED (the client went away: nothing sent),
 * DF1_E_INVAL (no such request, n 0 or over 4000 bytes). @since 0.4 */
DF1_API int df1_eip_server_reply(df1_eip_server_t *s, uint32_t request, const uint8_t *pccc_reply,
                                 size_t n);
/* Answer request with a CIP error instead: cip_status = general status
 * (0x01-0xFF) | extended status << 8 (e.g. 0x01 | 0x0204 << 8: connection
 * failure, unconnected request timed out). Returns as df1_eip_server_reply(). @since 0.4 */
DF1_API int df1_eip_server_fail(df1_eip_server_t *s, uint32_t request, int cip_status);

/* @since 0.4 */
struct df1_eip_server_stats {
	uint64_t sessions;           /* sessions registered, in all */
	uint64_t sessions_open;      /* sessions registered now */
	uint64_t requests;           /* encapsulation messages received (TCP and UDP) */
	uint64_t errors;             /* replies with an error status, and connections closed for one */
	uint64_t refused_clients;    /* outside the allow list, or over max_clients with none to
	                              * evict (df1_eip_server_set_limits) */
	uint64_t read_only_refusals; /* PCCC commands refused by read_only */
};
DF1_API void df1_eip_server_stats(const df1_eip_server_t *s, struct df1_eip_server_stats *st);
/* Why the server closed a connection on its own (df1_eip_server_set_limits). @since 0.5 */
enum df1_eip_close_reason {
	DF1_EIP_CLOSE_NO_SESSION,    /* no RegisterSession within register_ms of connecting */
	DF1_EIP_CLOSE_IDLE,          /* its session sent nothing for idle_ms */
	DF1_EIP_CLOSE_EVICTED        /* the table was full: the longest idle, for a new client */
};
/* peer: "ADDR:PORT" of the client closed. @since 0.5 */
typedef void (*df1_eip_close_fn)(void *user, const char *peer, enum df1_eip_close_reason why);
/* How long a connection may stay without a session or idle, and what a full
 * table does (df1-eip(7) "Limits"). @since 0.5 */
struct df1_eip_server_limits {
	int register_ms;             /* 0 = default 5000; -1 = no limit; at most 3600000 */
	int idle_ms;                 /* 0 = default 120000 (ODVA's encapsulation inactivity
	                              * timeout); -1 = no limit; at most 3600000 */
	bool no_evict;               /* a full table refuses the new client instead */
	df1_eip_close_fn on_close;   /* each connection a limit closed, or NULL */
	void *user;
};
/* Replace the limits (the server starts with the defaults). 0, or DF1_E_INVAL
 * (s or l NULL, a value out of range). @since 0.5 */
DF1_API int df1_eip_server_set_limits(df1_eip_server_t *s, const struct df1_eip_server_limits *l);
/* Connections the limits closed, by reason. @since 0.5 */
struct df1_eip_server_closes {
	uint64_t no_session, idle, evicted;
};
DF1_API void df1_eip_server_closes(const df1_eip_server_t *s, struct df1_eip_server_closes *c);
/* Replace what ListIdentity and the Identity object report from now on (a bridge
 * that learned its controller's processor type); the socket address stays the
 * server's. 0, or DF1_E_INVAL (s or id NULL). @since 0.4 */
DF1_API int df1_eip_server_set_identity(df1_eip_server_t *s, const struct df1_eip_identity *id);
/* The text of s's last failure, or with s NULL the calling thread's last
 * df1_eip_server_new() failure ("" if none). @since 0.4 */
DF1_API const char *df1_eip_server_error(const df1_eip_server_t *s);
/* Closes every connection; pending requests are dropped. NULL is a no-op. @since 0.4 */
DF1_API void df1_eip_server_free(df1_eip_server_t *s);

/* ------------------------------------------------------------------------
 * EtherNet/IP client: eip:// targets (libdf1(7)), discovery. @since 0.4
 * ------------------------------------------------------------------------ */
/* One device that answered ListIdentity (df1mon --who over eip://). */
struct df1_eip_device {
	char address[64];               /* "ADDR:PORT" that answered */
	uint16_t vendor_id, device_type, product_code;
	uint8_t rev_major, rev_minor;
	uint16_t status;                /* the Identity object's status word */
	uint32_t serial;
	char product_name[33];
	uint8_t state;
};
typedef void (*df1_eip_device_fn)(void *user, const struct df1_eip_device *d);
/* ListIdentity to target "eip://HOST[:PORT]" (port default 44818; a route such as
 * "/2" is ignored): over TCP to that host, one answer; when HOST is a broadcast
 * address (255.255.255.255 or a local interface's), one UDP datagram and every
 * answer within timeout_ms. fn (may be NULL) is called for each device. h must not
 * be open: it gives the cancel fd and keeps the error detail. Returns the number of
 * devices, or DF1_E_INVAL (bad target, h open), DF1_E_NODEV (unknown host),
 * DF1_E_SYS (refused, no route), DF1_E_TIMEOUT (TCP: no reply), DF1_E_BAD_REPLY,
 * DF1_E_EIP, DF1_E_INTR. @since 0.4 */
DF1_API int df1_eip_list_identity(df1_t *h, const char *target, int timeout_ms,
                                  df1_eip_device_fn fn, void *user);

#ifdef __cplusplus
}
#endif

#endif /* LIBDF1_DF1_EIP_H */
