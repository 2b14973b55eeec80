/* SPDX-License-Identifier: MPL-2.0 */
/*
 * port - the byte transport under the link layer: termios serial, TCP client,
 * pseudo-terminal / any fd. One small vtable; waits are poll() against an
 * absolute monotonic deadline (never sleep, EINTR never restarts a full timeout).
 */
#ifndef LIBDF1_PORT_H
#define LIBDF1_PORT_H

#include <sys/types.h>
#include "df1.h"
#include "base/base.h"

struct df1;

/* A backend's vtable and what the link layer needs to know about it: its
 * capabilities are fields here, so lib/link tests a capability, never which
 * backend it is (a new scheme: doc/HACKING.md). */
struct port_ops {
	const char *name;
	/* Its bytes take line time: a local UART sends what it was handed at the
	 * configured baud after what it still holds, so the link keeps its own
	 * account of when our last byte has left the line (lib/link/core.c
	 * link_tx_account). */
	bool paced;
	/* A network lies between us and the line: answer timers that are sized
	 * from the line's rate get network slack (lib/link/half.c half_poll_answer_ms). */
	bool net_slack;
	/* A serial line behind a network (a device server): the far end is a DF1
	 * line with its own baud, which the link cannot see. Nothing in lib/ tests
	 * it yet; it tells such a port from a local line and from a plain
	 * descriptor. A scheme with a link of its own (lib/scheme.c) never reads
	 * the capabilities of the port under it. */
	bool serial_behind_net;
	/* Open target (device path or "tcp://host:port"); 0 or DF1_E_*. The backend
	 * keeps its own state behind h->port_data; on failure it has closed and
	 * freed everything itself. NULL for the fd backend (port_fd_open). */
	int (*open)(struct df1 *h, const char *target);
	/* Close; restores termios settings saved at open, frees h->port_data. */
	void (*close)(struct df1 *h);
	/* Read up to cap bytes, waiting until deadline_ms (df1_now_ms() clock).
	 * Returns bytes (> 0), 0 on deadline, DF1_E_CLOSED, DF1_E_INTR or DF1_E_SYS. */
	ssize_t (*read)(struct df1 *h, uint8_t *buf, size_t cap, int64_t deadline_ms);
	/* Write all len bytes (waits for writability up to deadline); len or DF1_E_*. */
	ssize_t (*write)(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms);
	/* Apply serial settings to an open port; NULL if not a serial port. */
	int (*configure)(struct df1 *h);
	/* Wait until all output is transmitted (tcdrain); optional. */
	int (*drain)(struct df1 *h);
	/* A configuration file's target (lib/config/config_net.c Com_Port): whether
	 * rest, what follows "scheme://", is well formed; NULL: such targets are
	 * not accepted there. The default row (a device path) is checked by its caller. */
	bool (*config_ok)(const char *rest);
	/* The descriptor of a pty's other side the backend holds, else -1; NULL: none. */
	int (*peer)(const struct df1 *h);
	/* The modem lines (PORT_LINE_*): raise the bits of set, drop those of
	 * clear (RTS), then read them all into *state (may be NULL). 0,
	 * DF1_E_NOTSUP (the descriptor has none: a pty, a socket), DF1_E_SYS.
	 * NULL: the backend never has any (TCP). The radio modem keys with them
	 * (lib/link/radio.c). */
	int (*modem)(struct df1 *h, unsigned set, unsigned clear, unsigned *state);
};

#define PORT_LINE_RTS 1u
#define PORT_LINE_CTS 2u
#define PORT_LINE_DCD 4u

extern const struct port_ops port_termios_ops;
extern const struct port_ops port_tcp_ops;
extern const struct port_ops port_rfc2217_ops; /* a serial port on an RFC 2217 device server */
extern const struct port_ops port_fd_ops;   /* an fd given by df1_open_fd (pty, socket, pipe) */

/* Helpers for backends: wait for fd readable/writable (and the cancel fd) until deadline.
 * Returns 1 ready, 0 deadline, DF1_E_INTR (cancel fd readable), DF1_E_SYS.
 * fd < 0: a pause only the cancel fd can end. */
int port_wait(struct df1 *h, int fd, short events, int64_t deadline_ms);
/* The same against a deadline in microseconds (df1_now_us() clock): pacing. */
int port_wait_us(struct df1 *h, int fd, short events, int64_t deadline_us);
/* Generic descriptor I/O on h->fd with the read/write contracts above (lib/port/port.c);
 * the backends' read/write use them. port_send_fd writes with send(MSG_NOSIGNAL)
 * (sockets: no SIGPIPE). Both refuse a listen-only handle (port_refuse_tx). */
ssize_t port_read_fd(struct df1 *h, uint8_t *buf, size_t cap, int64_t deadline_ms);
ssize_t port_write_fd(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms);
ssize_t port_send_fd(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms);
/* The modem op on h->fd (TIOCMBIS, TIOCMBIC, TIOCMGET): termios and fd backends. */
int port_modem_fd(struct df1 *h, unsigned set, unsigned clear, unsigned *state);
/* DF1_E_NOTSUP "... is listen only" for any transmission on a listen-only handle. */
int port_refuse_tx(struct df1 *h);

/* The fd backend opens on a descriptor, not a target: h->fd = fd, its state in
 * h->port_data; own: close fd at close. 0 or DF1_E_* (fd left as it was). */
int port_fd_open(struct df1 *h, int fd, bool own);
/* fd backend on a pty master: the slave-side descriptor it holds, else -1
 * (any backend: its peer op, lib/port/port.c). */
int port_fd_peer(const struct df1 *h);
/* Record a failed system call: df1_fail(h, code, ...) with the message
 * "<what> <h->port_name>: <strerror(err)>" (sys_errno = err for DF1_E_SYS); returns code. */
int port_fail_sys(struct df1 *h, int code, int err, const char *what);

#endif
