/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_line - df1sim playing a serial line with fixed settings (--line-settings
 * 9600,8E1): a UART model that turns what a sender at one rate, data size and
 * parity puts on the wire into what a receiver at other settings reads, and
 * the relay (a thread) that puts the model between the simulated PLC's handle
 * and the master: on a pseudo-terminal the master's settings are the pty's
 * termios as the master set them; on an RFC 2217 listener (sim_rfc2217.c)
 * the settings its client sent.
 */
#ifndef DF1_TOOLS_SIM_LINE_H
#define DF1_TOOLS_SIM_LINE_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "df1.h"

struct sim_uart {
	int baud;       /* 0: not set (the line takes whatever the master uses) */
	int data_bits;  /* 5..8 */
	char parity;    /* 'N' 'E' 'O' */
	int stop_bits;  /* 1, 2 */
};

/* "9600,8E1", "19200" (8N1), "9600,8N2". true if s is one. */
bool sim_uart_parse(const char *s, struct sim_uart *u);
/* "9600 8E1" into buf. */
const char *sim_uart_text(const struct sim_uart *u, char *buf, size_t cap);

/* What a receiver at rx reads when a sender at tx sends in[0..n): each byte
 * as if alone on an idle line (so the result depends on the byte and the two
 * settings only, never on timing). At equal rate, size and parity the bytes
 * come through; otherwise the receiver samples the sender's bits at its own
 * rate, and a character with a parity or framing error reads as 0x00 (a
 * Linux tty without IGNPAR/PARMRK). Stop bits: a receiver checks one.
 * Returns the bytes written to out (at most cap). */
size_t sim_uart_garble(const struct sim_uart *tx, const struct sim_uart *rx, const uint8_t *in,
                       size_t n, uint8_t *out, size_t cap);

enum sim_relay_kind { SIM_RELAY_PTY, SIM_RELAY_RFC2217 };

/* One direction of a full-duplex UART (--line-baud in full duplex): the bytes
 * read and not yet delivered, each with the time its last bit is in
 * (tools/df1sim/sim_pace.c). Each direction keeps its own account, so a
 * command comes in while a reply goes out, as on a controller's UART. */
#define SIM_PACE_MAX 4096
struct sim_pace {
	uint8_t b[SIM_PACE_MAX];
	int64_t due_us[SIM_PACE_MAX];
	size_t head, len;
	int64_t last_due_us;        /* the last byte queued leaves the line then */
};

/* The relay between wire (the pty master or an RFC 2217 client's socket) and
 * lib (a socket pair's end the handle serves on). */
struct sim_relay {
	enum sim_relay_kind kind;
	int wire, lib;
	bool own_wire;              /* close wire when the relay ends */
	struct sim_uart line;       /* the PLC's settings; baud 0: the master's, whatever they are */
	struct sim_uart master;     /* the master's, as last seen */
	int verbose;
	void *rfc;                  /* sim_rfc2217.c's state (SIM_RELAY_RFC2217) */
	int64_t char_us;            /* > 0: paced, a character's time at --line-baud */
	struct sim_pace to_lib, to_wire;
	pthread_t thread;
	bool started;
};

/* Make the socket pair (*lib_fd for the handle) and start the relay thread.
 * 0, or -1 with errno. */
int sim_relay_start(struct sim_relay *r, int *lib_fd);
/* After the handle's end was closed: wait for the thread; close what it owns. */
void sim_relay_join(struct sim_relay *r);
/* h served on a relay of kind over wire, the line's settings line: the relay
 * started, h opened on its end. The relay owns wire from then on, failure
 * included (closed). 0 or DF1_E_* (said on stderr when the relay failed). */
int sim_relay_open(df1_t *h, struct sim_relay *r, enum sim_relay_kind kind, int wire,
                   const struct sim_uart *line, int verbose);

/* sim_pace.c: the paced queues. Queue n bytes for delivery at the line's rate
 * (false: no room, nothing queued); write what is due to fd (emit: the
 * relay's writer for that direction); the microseconds until the next byte
 * is due, -1 when empty. */
bool sim_pace_put(struct sim_pace *q, int64_t char_us, const uint8_t *b, size_t n);
int sim_pace_flush(struct sim_relay *r, struct sim_pace *q,
                   int (*emit)(struct sim_relay *r, const uint8_t *b, size_t n));
int64_t sim_pace_wait_us(const struct sim_pace *q);
/* Bytes to each side as the relay writes them (sim_line.c). */
int sim_relay_emit_lib(struct sim_relay *r, const uint8_t *b, size_t n);
int sim_relay_emit_wire(struct sim_relay *r, const uint8_t *b, size_t n);
/* sim_rfc2217.c: the RFC 2217 server side of a relay. new: the state (NULL:
 * no memory); input: bytes from the client, data out into out (returns how
 * many), the negotiation answered on r->wire, r->master updated; output:
 * escape data for the client. */
void *sim_rfc2217_new(void);
size_t sim_rfc2217_input(struct sim_relay *r, const uint8_t *in, size_t n, uint8_t *out, size_t cap);
size_t sim_rfc2217_output(const uint8_t *in, size_t n, uint8_t *out, size_t cap, size_t *used);

/* df1sim's message function (df1sim.c), for the relay's -v lines. */
void sim_msg(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif
