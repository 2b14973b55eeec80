/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip_session - one EtherNet/IP client connection of a server, as a state
 * machine (pure: no I/O, no clock, no allocation): a whole encapsulation
 * message in -> the reply bytes, a PCCC request for the owner, or "close".
 * The session handle, the connections of Forward Open, the encapsulation and
 * CIP status of every error are here; df1-eip(7) says which and why.
 */
#ifndef LIBDF1_EIP_SESSION_H
#define LIBDF1_EIP_SESSION_H

#include "eip/eip_codec.h"

#define EIP_SESSION_CONNS 4          /* Forward Open connections per session */
#define EIP_SESSION_MSG_MAX 4096     /* longest encapsulation message taken in */

struct eip_conn {
	bool used;
	uint32_t ot_id, to_id;           /* ot_id: ours (the client sends on it) */
	uint16_t conn_serial, vendor_id;
	uint32_t orig_serial;
	int station;                     /* from the connection path, or -1 */
};

struct eip_session {
	uint32_t handle;                 /* given by the owner, non-zero */
	bool registered;
	uint32_t conn_count;             /* connections opened, for their ids */
	struct eip_conn conn[EIP_SESSION_CONNS];
};

/* A PCCC request handed to the owner, and what its reply needs. */
struct eip_pending {
	uint32_t session;
	uint8_t context[8];
	bool connected;
	uint32_t to_id;                  /* connected: the id the reply goes on */
	uint16_t seq;
	bool routed;                     /* inside Unconnected Send */
	int station;                     /* route path's link address, or -1 */
	uint8_t reqid[EIP_REQID_MAX];
	size_t reqid_len;
	const uint8_t *pccc;             /* CMD STS TNS FNC data, in the input */
	size_t len;
};

enum eip_verdict {
	EIP_SEND,         /* send the reply bytes */
	EIP_SEND_CLOSE,   /* send them, then close the connection */
	EIP_SILENT,       /* nothing to send (NOP, a discarded message) */
	EIP_CLOSE,        /* close without a reply (UnRegisterSession) */
	EIP_PCCC,         /* *pend holds a PCCC request: answer with eip_session_reply() */
};

/* s->handle must be set (non-zero) before the first message. */
void eip_session_init(struct eip_session *s, uint32_t handle);

/* One whole message msg[0..n) (n = eip_msg_len(), or n = 24 when its length
 * is over EIP_SESSION_MSG_MAX: then the reply is status 0x0065 and close).
 * udp: ListIdentity / ListServices only, everything else silent. The reply
 * goes to out (*out_len bytes). */
enum eip_verdict eip_session_input(struct eip_session *s, const struct eip_identity *id, bool udp,
                                   const uint8_t *msg, size_t n, uint8_t *out, size_t cap,
                                   size_t *out_len, struct eip_pending *pend);

/* The reply message for a pending request: cip_status 0 with the PCCC reply
 * (CMD|40 STS TNS ...), or a CIP general status (ext: extended status word, 0
 * none) and no PCCC bytes. Returns its length or DF1_E_NOSPACE. */
int eip_session_reply(const struct eip_pending *p, int cip_status, uint16_t ext, const uint8_t *pccc,
                      size_t n, uint8_t *out, size_t cap);


#endif
