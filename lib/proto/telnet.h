/* SPDX-License-Identifier: MPL-2.0 */
/*
 * telnet - the Telnet framing of an RFC 2217 device server connection (pure:
 * no I/O, no clock, no allocation): IAC doubling of data, option negotiation
 * (RFC 854, BINARY of RFC 856) and the COM-PORT-OPTION subnegotiations of
 * RFC 2217, both the client's and the server's side (doc/PROTOCOL.md 9).
 */
#ifndef LIBDF1_TELNET_H
#define LIBDF1_TELNET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define TELNET_SE   240
#define TELNET_SB   250
#define TELNET_WILL 251
#define TELNET_WONT 252
#define TELNET_DO   253
#define TELNET_DONT 254
#define TELNET_IAC  255

#define TELNET_OPT_BINARY  0   /* RFC 856 */
#define TELNET_OPT_ECHO    1
#define TELNET_OPT_SGA     3
#define TELNET_OPT_COMPORT 44  /* RFC 2217 */

/* COM-PORT-OPTION commands, client to server; the server answers with the
 * same command + TELNET_CPC_SERVER (RFC 2217, "Com Port Configuration"). */
enum telnet_cpc {
	TELNET_CPC_SIGNATURE = 0,
	TELNET_CPC_SET_BAUDRATE = 1,    /* 4 bytes, network order; 0 asks */
	TELNET_CPC_SET_DATASIZE = 2,    /* 5..8; 0 asks */
	TELNET_CPC_SET_PARITY = 3,      /* TELNET_PARITY_*; 0 asks */
	TELNET_CPC_SET_STOPSIZE = 4,    /* 1, 2, 3 (1.5); 0 asks */
	TELNET_CPC_SET_CONTROL = 5,     /* TELNET_CONTROL_* */
	TELNET_CPC_NOTIFY_LINESTATE = 6,
	TELNET_CPC_NOTIFY_MODEMSTATE = 7,
	TELNET_CPC_FLOWCONTROL_SUSPEND = 8,
	TELNET_CPC_FLOWCONTROL_RESUME = 9,
	TELNET_CPC_SET_LINESTATE_MASK = 10,
	TELNET_CPC_SET_MODEMSTATE_MASK = 11,
	TELNET_CPC_PURGE_DATA = 12,     /* TELNET_PURGE_* */
};
#define TELNET_CPC_SERVER 100

#define TELNET_PARITY_NONE 1
#define TELNET_PARITY_ODD  2
#define TELNET_PARITY_EVEN 3
#define TELNET_CONTROL_NO_FLOW 1
#define TELNET_CONTROL_HW_FLOW 3
#define TELNET_PURGE_BOTH 3

/* What telnet_feed() found in the byte it was given. */
enum telnet_ev {
	TELNET_EV_NONE,     /* inside a command: nothing yet */
	TELNET_EV_DATA,     /* ev->byte is a data byte (an IAC IAC pair gives one 255) */
	TELNET_EV_OPTION,   /* ev->cmd (WILL WONT DO DONT) ev->opt */
	TELNET_EV_SB,       /* a whole subnegotiation: ev->opt, ev->sb[0..sb_len) undoubled */
	TELNET_EV_OTHER,    /* another command (NOP, GA, ...): ev->cmd */
};

#define TELNET_SB_MAX 16

struct telnet_decoder {
	int state;
	uint8_t opt, cmd_pending;
	uint8_t sb[TELNET_SB_MAX];
	size_t sb_len;
	bool sb_long;       /* the subnegotiation did not fit: reported cut to TELNET_SB_MAX */
};

struct telnet_event {
	uint8_t byte, cmd, opt;
	const uint8_t *sb;  /* into the decoder: valid until the next telnet_feed() */
	size_t sb_len;
};

void telnet_decoder_init(struct telnet_decoder *d);
/* One byte of the connection. */
enum telnet_ev telnet_feed(struct telnet_decoder *d, uint8_t b, struct telnet_event *ev);

/* Data with every 255 doubled, as much of in as fits cap; *used gets how many
 * bytes of in went out (an IAC is never split from its double). Returns the
 * bytes written to out. */
size_t telnet_escape(const uint8_t *in, size_t n, uint8_t *out, size_t cap, size_t *used);
/* IAC cmd opt. out needs 3 bytes; returns 3. */
size_t telnet_option(uint8_t cmd, uint8_t opt, uint8_t *out);
/* IAC SB COM-PORT-OPTION code value... IAC SE, value bytes doubled where 255.
 * out needs 7 + 2 * n bytes (n <= 4); returns the bytes written. */
size_t telnet_cpc(uint8_t code, const uint8_t *val, size_t n, uint8_t *out);
/* SET-BAUDRATE's value: 4 bytes, network order. */
void telnet_put_baud(uint32_t baud, uint8_t val[4]);
uint32_t telnet_get_baud(const uint8_t val[4]);

#endif
