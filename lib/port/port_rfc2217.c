/* SPDX-License-Identifier: MPL-2.0 */
/*
 * port_rfc2217.c - a serial port on a device server that speaks RFC 2217
 * (Telnet COM-PORT-OPTION: Moxa NPort, Lantronix, Sealevel, ser2net):
 * "rfc2217://host:port", "rfc2217:host:port", the scheme in any case.
 *
 * The connection is port_tcp.c's (its connect, its deadline, TCP_NODELAY).
 * At open the client offers what device servers wait for (IAC WILL
 * COM-PORT-OPTION, IAC WILL BINARY, IAC DO BINARY), waits for the server's DO
 * COM-PORT-OPTION, then configure sends the line's settings (SET-BAUDRATE,
 * SET-DATASIZE, SET-PARITY, SET-STOPSIZE, SET-CONTROL for RTS/CTS) and
 * PURGE-DATA, and checks every answer: a server that answers another value,
 * or none within the timeout, is an error naming the setting. Data bytes of
 * 255 are doubled going out and undoubled coming in; the server's other
 * option requests are refused (DONT/WONT) once each. The Telnet codec is
 * lib/proto/telnet.c; the facts and their sources doc/PROTOCOL.md 9.
 *
 * For the link this is a serial line behind a network: paced at the line's
 * baud like a local UART, with network slack on the answer timers.
 */
#include "port/port.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "df1_int.h"
#include "proto/telnet.h"

#define RFC_MIN_WAIT_MS 1000
#define RFC_CODES 13              /* SET-BAUDRATE .. PURGE-DATA */

/* The backend's state (h->port_data). */
struct rfc_port {
	struct telnet_decoder dec;
	uint8_t raw[512];             /* bytes read from the socket, not yet decoded */
	size_t raw_len, raw_pos;
	uint8_t data[512];            /* data bytes decoded while no read was waiting */
	size_t data_len, data_pos;
	int comport;                  /* the server's word on COM-PORT-OPTION: 0 none yet, 1 DO, -1 DONT */
	bool answered[RFC_CODES];     /* the server's answer to each command since it was sent */
	uint8_t answer[RFC_CODES][4];
	size_t answer_len[RFC_CODES];
	uint8_t refused[2][32];       /* options refused once: [0] DONT sent, [1] WONT sent */
};

static const char *const rfc_code_name[RFC_CODES] = {
	"SIGNATURE", "SET-BAUDRATE", "SET-DATASIZE", "SET-PARITY", "SET-STOPSIZE", "SET-CONTROL",
	"NOTIFY-LINESTATE", "NOTIFY-MODEMSTATE", "FLOWCONTROL-SUSPEND", "FLOWCONTROL-RESUME",
	"SET-LINESTATE-MASK", "SET-MODEMSTATE-MASK", "PURGE-DATA",
};

static int rfc_send(struct df1 *h, const uint8_t *b, size_t n)
{
	ssize_t r = port_send_fd(h, b, n, df1_now_ms() + RFC_MIN_WAIT_MS);

	return r < 0 ? (int)r : 0;
}

/* The server asks us to use (DO) or offers (WILL) an option: BINARY and
 * COM-PORT-OPTION are what we offered; anything else is refused once. */
static int rfc_option(struct df1 *h, struct rfc_port *rp, uint8_t cmd, uint8_t opt)
{
	uint8_t out[3];
	int k;

	if (opt == TELNET_OPT_COMPORT && (cmd == TELNET_DO || cmd == TELNET_DONT)) {
		rp->comport = cmd == TELNET_DO ? 1 : -1;
		return 0;
	}
	if (opt == TELNET_OPT_BINARY || cmd == TELNET_WONT || cmd == TELNET_DONT)
		return 0;
	k = cmd == TELNET_WILL ? 0 : 1;
	if (rp->refused[k][opt / 8] & (1u << (opt % 8)))
		return 0;
	rp->refused[k][opt / 8] |= (uint8_t)(1u << (opt % 8));
	return rfc_send(h, out, telnet_option(k == 0 ? TELNET_DONT : TELNET_WONT, opt, out));
}

static void rfc_sb(struct rfc_port *rp, const struct telnet_event *ev)
{
	unsigned code;

	if (ev->opt != TELNET_OPT_COMPORT || ev->sb_len < 1 || ev->sb[0] < TELNET_CPC_SERVER)
		return;
	code = ev->sb[0] - TELNET_CPC_SERVER;
	if (code >= RFC_CODES)
		return;                 /* a notification (line or modem state): not asked for */
	rp->answered[code] = true;
	rp->answer_len[code] = ev->sb_len - 1 > 4 ? 4 : ev->sb_len - 1;
	memcpy(rp->answer[code], ev->sb + 1, rp->answer_len[code]);
}

/* Decode the raw bytes read so far: data into out (up to cap), the rest
 * handled. Returns the data bytes, or DF1_E_* of a reply that failed. */
static ssize_t rfc_decode(struct df1 *h, struct rfc_port *rp, uint8_t *out, size_t cap)
{
	size_t n = 0;

	while (rp->raw_pos < rp->raw_len && n < cap) {
		struct telnet_event ev;
		int r;

		switch (telnet_feed(&rp->dec, rp->raw[rp->raw_pos++], &ev)) {
		case TELNET_EV_DATA:
			out[n++] = ev.byte;
			break;
		case TELNET_EV_OPTION:
			r = rfc_option(h, rp, ev.cmd, ev.opt);
			if (r < 0)
				return r;
			break;
		case TELNET_EV_SB:
			rfc_sb(rp, &ev);
			break;
		default:
			break;
		}
	}
	return (ssize_t)n;
}

/* Read and decode until done(rp) or the deadline: data meanwhile is kept for
 * the link's next read. 1 done, 0 deadline, DF1_E_*. */
static int rfc_wait(struct df1 *h, bool (*done)(const struct rfc_port *), int64_t deadline_ms)
{
	struct rfc_port *rp = h->port_data;

	for (;;) {
		ssize_t r;

		if (rp->data_pos == rp->data_len)
			rp->data_pos = rp->data_len = 0;
		r = rfc_decode(h, rp, rp->data + rp->data_len, sizeof rp->data - rp->data_len);
		if (r < 0)
			return (int)r;
		rp->data_len += (size_t)r;
		if (done(rp))
			return 1;
		if (rp->raw_pos < rp->raw_len)
			rp->raw_pos = rp->raw_len; /* data buffer full: a server talking to nobody */
		r = port_read_fd(h, rp->raw, sizeof rp->raw, deadline_ms);
		if (r <= 0)
			return (int)r;
		rp->raw_len = (size_t)r;
		rp->raw_pos = 0;
	}
}

static bool rfc_comport_known(const struct rfc_port *rp)
{
	return rp->comport != 0;
}

static bool rfc_all_answered(const struct rfc_port *rp)
{
	static const int want[] = { TELNET_CPC_SET_BAUDRATE, TELNET_CPC_SET_DATASIZE,
	                            TELNET_CPC_SET_PARITY, TELNET_CPC_SET_STOPSIZE,
	                            TELNET_CPC_SET_CONTROL, TELNET_CPC_PURGE_DATA };

	for (size_t i = 0; i < sizeof want / sizeof want[0]; i++)
		if (!rp->answered[want[i]])
			return false;
	return true;
}

static int rfc_deadline_ms(const struct df1 *h)
{
	return h->cfg.timeout_ms > RFC_MIN_WAIT_MS ? h->cfg.timeout_ms : RFC_MIN_WAIT_MS;
}

/* The answer to code must be want (n bytes): else the error naming it. */
static int rfc_check(struct df1 *h, int code, const uint8_t *want, size_t n, const char *what)
{
	struct rfc_port *rp = h->port_data;
	uint32_t got = 0;

	if (!rp->answered[code])
		return df1_fail(h, DF1_E_NOTSUP, -1, "device server %s did not answer %s (%s) within "
		                "%d ms", h->port_name, rfc_code_name[code], what, rfc_deadline_ms(h));
	if (rp->answer_len[code] == n && memcmp(rp->answer[code], want, n) == 0)
		return 0;
	for (size_t i = 0; i < rp->answer_len[code]; i++)
		got = got << 8 | rp->answer[code][i];
	return df1_fail(h, DF1_E_NOTSUP, -1, "device server %s refused %s %s (it answered %lu)",
	                h->port_name, rfc_code_name[code], what, (unsigned long)got);
}

static int rfc_configure(struct df1 *h)
{
	struct rfc_port *rp = h->port_data;
	uint8_t out[6 * 14], baud[4], size, par, stop, ctl, purge = TELNET_PURGE_BOTH;
	char what[32];
	size_t n = 0;
	int r;

	if (h->fd < 0 || !rp)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "port is not open");
	if (h->cfg.rs485)
		return df1_fail(h, DF1_E_NOTSUP, -1, "RS-485 mode on %s: RFC 2217 has no command for "
		                "the driver's direction; set the device server's port to RS-485 itself",
		                h->port_name);
	telnet_put_baud((uint32_t)h->cfg.baud, baud);
	size = (uint8_t)h->cfg.data_bits;
	par = h->cfg.parity == 'E' ? TELNET_PARITY_EVEN
	    : h->cfg.parity == 'O' ? TELNET_PARITY_ODD : TELNET_PARITY_NONE;
	stop = (uint8_t)h->cfg.stop_bits;
	ctl = h->cfg.rts_cts ? TELNET_CONTROL_HW_FLOW : TELNET_CONTROL_NO_FLOW;
	n += telnet_cpc(TELNET_CPC_SET_BAUDRATE, baud, 4, out + n);
	n += telnet_cpc(TELNET_CPC_SET_DATASIZE, &size, 1, out + n);
	n += telnet_cpc(TELNET_CPC_SET_PARITY, &par, 1, out + n);
	n += telnet_cpc(TELNET_CPC_SET_STOPSIZE, &stop, 1, out + n);
	n += telnet_cpc(TELNET_CPC_SET_CONTROL, &ctl, 1, out + n);
	n += telnet_cpc(TELNET_CPC_PURGE_DATA, &purge, 1, out + n);
	memset(rp->answered, 0, sizeof rp->answered);
	r = rfc_send(h, out, n);
	if (r < 0)
		return r;
	r = rfc_wait(h, rfc_all_answered, df1_now_ms() + rfc_deadline_ms(h));
	if (r < 0)
		return r;
	snprintf(what, sizeof what, "%d baud", h->cfg.baud);
	r = rfc_check(h, TELNET_CPC_SET_BAUDRATE, baud, 4, what);
	snprintf(what, sizeof what, "%d data bits", h->cfg.data_bits);
	r = r < 0 ? r : rfc_check(h, TELNET_CPC_SET_DATASIZE, &size, 1, what);
	r = r < 0 ? r : rfc_check(h, TELNET_CPC_SET_PARITY, &par, 1,
	                          par == TELNET_PARITY_EVEN ? "even parity"
	                          : par == TELNET_PARITY_ODD ? "odd parity" : "no parity");
	snprintf(what, sizeof what, "%d stop bits", h->cfg.stop_bits);
	r = r < 0 ? r : rfc_check(h, TELNET_CPC_SET_STOPSIZE, &stop, 1, what);
	r = r < 0 ? r : rfc_check(h, TELNET_CPC_SET_CONTROL, &ctl, 1,
	                          h->cfg.rts_cts ? "RTS/CTS handshake" : "no flow control");
	if (r < 0)
		return r;
	rp->data_len = rp->data_pos = 0; /* purged: what came before belongs to the old settings */
	return 0;
}

static void rfc_close(struct df1 *h)
{
	port_tcp_ops.close(h);
	free(h->port_data);
	h->port_data = NULL;
}

/* Open the connection, negotiate COM-PORT-OPTION and BINARY, set the line. */
static int rfc_open(struct df1 *h, const char *target)
{
	static const uint8_t offer[] = {
		TELNET_IAC, TELNET_WILL, TELNET_OPT_COMPORT,
		TELNET_IAC, TELNET_WILL, TELNET_OPT_BINARY,
		TELNET_IAC, TELNET_DO, TELNET_OPT_BINARY,
	};
	const char *rest = target + 8; /* "rfc2217:" */
	char tcp[300];
	int r;

	if (strncmp(rest, "//", 2) == 0)
		rest += 2;
	snprintf(h->port_name, sizeof h->port_name, "%s", target);
	if (!port_tcp_ops.config_ok(rest) || strlen(rest) + 7 > sizeof tcp)
		return df1_fail(h, DF1_E_INVAL, -1, "invalid RFC 2217 target \"%s\": expected "
		                "rfc2217://HOST:PORT or rfc2217://[IPv6]:PORT (port 1..65535)", target);
	if (h->cfg.listen_only)
		return df1_fail(h, DF1_E_NOTSUP, -1, "%s: an RFC 2217 connection cannot be listen "
		                "only (the device server's negotiation needs answers)", target);
	snprintf(tcp, sizeof tcp, "tcp://%s", rest);
	r = port_tcp_ops.open(h, tcp);
	if (r < 0)
		return r;
	h->port_data = calloc(1, sizeof(struct rfc_port));
	if (!h->port_data) {
		port_tcp_ops.close(h);
		return df1_fail(h, DF1_E_NOMEM, -1, "%s: out of memory", target);
	}
	telnet_decoder_init(&((struct rfc_port *)h->port_data)->dec);
	r = rfc_send(h, offer, sizeof offer);
	if (r >= 0)
		r = rfc_wait(h, rfc_comport_known, df1_now_ms() + rfc_deadline_ms(h));
	if (r == 0 || (r > 0 && ((struct rfc_port *)h->port_data)->comport < 0))
		r = df1_fail(h, DF1_E_NOTSUP, -1, "%s does not speak RFC 2217: %s COM-PORT-OPTION",
		             h->port_name, r == 0 ? "no answer to WILL" : "it refused (DONT)");
	if (r >= 0)
		r = rfc_configure(h);
	if (r < 0) {
		rfc_close(h);
		return r;
	}
	return 0;
}

static ssize_t rfc_read(struct df1 *h, uint8_t *buf, size_t cap, int64_t deadline_ms)
{
	struct rfc_port *rp = h->port_data;

	if (h->fd < 0 || !rp)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "port is not open");
	if (cap == 0)
		return 0;
	for (;;) {
		ssize_t r;

		if (rp->data_pos < rp->data_len) {
			size_t n = rp->data_len - rp->data_pos;

			n = n < cap ? n : cap;
			memcpy(buf, rp->data + rp->data_pos, n);
			rp->data_pos += n;
			return (ssize_t)n;
		}
		r = rfc_decode(h, rp, buf, cap);
		if (r != 0)
			return r;
		r = port_read_fd(h, rp->raw, sizeof rp->raw, deadline_ms);
		if (r <= 0)
			return r;
		rp->raw_len = (size_t)r;
		rp->raw_pos = 0;
	}
}

static ssize_t rfc_write(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms)
{
	uint8_t out[256];
	size_t done = 0;

	while (done < len) {
		size_t used, n = telnet_escape(buf + done, len - done, out, sizeof out, &used);
		ssize_t r = port_send_fd(h, out, n, deadline_ms);

		if (r < 0)
			return r;
		done += used;
	}
	return (ssize_t)len;
}

static bool rfc_config_ok(const char *rest)
{
	return port_tcp_ops.config_ok(rest);
}

const struct port_ops port_rfc2217_ops = {
	.name = "rfc2217",
	.paced = true,              /* the line behind the server runs at the baud we set */
	.net_slack = true,          /* and a network lies before it: lib/link/half.c */
	.serial_behind_net = true,
	.open = rfc_open,
	.close = rfc_close,
	.read = rfc_read,
	.write = rfc_write,
	.configure = rfc_configure,
	.drain = NULL,
	.config_ok = rfc_config_ok,
};
