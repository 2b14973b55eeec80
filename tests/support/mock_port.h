/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mock_port - a scripted struct port_ops for link-level tests (doc/HACKING.md 7.10:
 * the link is mocked at the transport vtable, never at read(2)).
 *
 * Reads come from a queue of scripted entries:
 *  - bytes: one read returns them (up to the caller's cap; the rest stays queued);
 *  - expire: one read returns 0 at once, i.e. "the deadline passed" (virtual time:
 *    the link trusts the port contract, so timeout paths run without waiting);
 *  - error: one read returns a DF1_E_* code.
 * With the queue empty a read waits (really, up to 5 s) until its deadline and
 * returns 0, as a quiet line would.
 *
 * Writes are captured (all bytes, in order, plus per-write boundaries), and an
 * optional hook sees each write and may queue reads: an emulated peer that
 * answers what the link just sent.
 *
 * Usage: after df1_new(), set h->port = &mock_port_ops and h->fd = 0.
 */
#ifndef LIBDF1_TESTS_MOCK_PORT_H
#define LIBDF1_TESTS_MOCK_PORT_H

#include <stddef.h>
#include <stdint.h>
#include "port/port.h"

extern const struct port_ops mock_port_ops;

/* Forget every queued read, captured write and hook. */
void mock_port_reset(void);

/* Queue one read returning these bytes. */
void mock_port_feed(const uint8_t *bytes, size_t n);
/* The same from hex text: "10 02 01 00 ..." (spaces optional). */
void mock_port_feed_hex(const char *hex);
/* Queue one read that reports its deadline as expired (returns 0 at once). */
void mock_port_expire(void);
/* Queue one read that fails with code (DF1_E_SYS, DF1_E_CLOSED ...). */
void mock_port_fail(int code);
/* Reads still queued. */
size_t mock_port_pending(void);
/* Reads served so far (including expiries and failures). */
size_t mock_port_reads(void);

/* Called after every write with the bytes written; it may queue reads. */
typedef void (*mock_port_hook)(const uint8_t *buf, size_t n, void *user);
void mock_port_on_write(mock_port_hook fn, void *user);

/* Called when a read finds the queue empty, again and again until it queues
 * something or the read's deadline passes (it should block a little: an
 * emulated peer running its own link with a short deadline). */
typedef void (*mock_port_idle)(int64_t deadline_ms, void *user);
void mock_port_on_idle(mock_port_idle fn, void *user);

/* Everything written so far, concatenated (capture is capped at 64 KiB). */
const uint8_t *mock_port_written(size_t *n);
/* Number of write calls, and the bytes of write call i (0-based). */
size_t mock_port_writes(void);
const uint8_t *mock_port_write_at(size_t i, size_t *n);
/* Forget the captured writes (queued reads stay). */
void mock_port_clear_written(void);
/* Count occurrences of a byte sequence in the captured writes. */
size_t mock_port_count_written(const uint8_t *seq, size_t n);

/* Fake modem lines (the port's modem op; without this call it has none:
 * DF1_E_NOTSUP, as a pty). CTS rises cts_lag ms after RTS (-1: never), DCD is
 * up for dcd_ms from now. Starts the event record over. */
void mock_port_lines(int cts_lag, int dcd_ms);
/* The events since: 'R' RTS raised, 'r' RTS dropped, 'W' a write; as a
 * string into out, their number; and the time (df1_now_ms) of event i. */
size_t mock_port_events(char *out, size_t cap);
int64_t mock_port_event_ms(size_t i);

/* Parse hex text into buf; returns the number of bytes (asserts on bad text). */
size_t mock_hex(const char *hex, uint8_t *buf, size_t cap);

#endif
