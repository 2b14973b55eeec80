/* SPDX-License-Identifier: MPL-2.0 */
/*
 * port_usb - what the termios backend does for a USB serial adapter: asks the
 * driver for low latency (ASYNC_LOW_LATENCY) and reports a latency timer it
 * could not lower (lib/port/port_usb.c, libdf1(7) USB ADAPTERS).
 */
#ifndef LIBDF1_PORT_USB_H
#define LIBDF1_PORT_USB_H

#include <stdbool.h>

struct df1;

/* What open changed, for close to undo. */
struct port_usb {
	bool flags_changed;          /* ASYNC_LOW_LATENCY was set by us: clear it at close */
};

/* After the line is configured: on a usb-serial tty (sysfs), set low latency when
 * the handle asks for it (DF1_OPT_LOW_LATENCY) and check the driver's latency_timer;
 * one log line and h->port_note when it stays above 1 ms. Never fails. */
void port_usb_open(struct df1 *h, struct port_usb *u);
/* Undo what port_usb_open changed; clears h->port_note. */
void port_usb_close(struct df1 *h, struct port_usb *u);

#endif
