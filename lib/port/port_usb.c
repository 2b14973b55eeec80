/* SPDX-License-Identifier: MPL-2.0 */
/*
 * port_usb.c - USB serial adapters under the termios backend.
 *
 * A USB serial adapter holds received bytes until its latency timer runs out
 * before it sends a short packet to the host (16 ms by default for ftdi_sio),
 * so a DF1 ACK or a short reply can wait that long at every turnaround. Linux
 * drivers take ASYNC_LOW_LATENCY (TIOCSSERIAL, as `setserial low_latency`);
 * ftdi_sio then runs its timer at 1 ms. Where the driver shows a latency_timer
 * in sysfs that is still above 1 ms afterwards (an old kernel, another
 * driver), the library says so once: a log line (catalog ID 0: the catalog
 * of doc/REQUIREMENTS.md 004 is closed) and the open-time note df1_port_note()
 * returns, naming the file and the udev rule that fixes it (contrib/udev).
 *
 * A tty is a usb-serial port when sysfs lists it under bus/usb-serial/devices;
 * its name comes from the character device's uevent (dev/char/MAJ:MIN). The
 * sysfs root is /sys; a test points it at a fake tree through the environment
 * variable DF1_TEST_SYSFS_ROOT, which only port_usb_sysfs_root() reads and which
 * is meant for tests alone (libdf1(7) USB ADAPTERS). Nothing here fails an open:
 * a pty or a driver without TIOCGSERIAL is left as it is.
 */
#include "port/port_usb.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/serial.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include "df1_int.h"

#define USB_RULE "ACTION==\"add\", SUBSYSTEM==\"usb-serial\", DRIVER==\"ftdi_sio\", " \
                 "ATTR{latency_timer}=\"1\""

/* The sysfs root: /sys, or a test's fake tree (DF1_TEST_SYSFS_ROOT, tests only). */
static const char *port_usb_sysfs_root(void)
{
	const char *r = getenv("DF1_TEST_SYSFS_ROOT");

	return r && *r ? r : "/sys";
}

/* The first line of a small sysfs file into buf (newline dropped); false if unreadable. */
static bool port_usb_read(const char *path, char *buf, size_t cap)
{
	ssize_t n;
	int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);

	if (fd < 0)
		return false;
	n = read(fd, buf, cap - 1);
	close(fd);
	if (n <= 0)
		return false;
	buf[n] = 0;
	buf[strcspn(buf, "\n")] = 0;
	return true;
}

/* The kernel name of the tty behind fd ("ttyUSB0") when it is a usb-serial port. */
static bool port_usb_name(int fd, const char *root, char *name, size_t cap)
{
	char path[256], text[256];
	struct stat st;
	const char *p;
	int fdir;

	if (fstat(fd, &st) < 0 || !S_ISCHR(st.st_mode))
		return false;
	snprintf(path, sizeof path, "%s/dev/char/%u:%u/uevent", root, major(st.st_rdev),
	         minor(st.st_rdev));
	fdir = open(path, O_RDONLY | O_CLOEXEC);
	if (fdir < 0)
		return false;
	memset(text, 0, sizeof text);
	if (read(fdir, text, sizeof text - 1) <= 0) {
		close(fdir);
		return false;
	}
	close(fdir);
	p = strstr(text, "DEVNAME=");
	if (!p)
		return false;
	p += strlen("DEVNAME=");
	snprintf(name, cap, "%.*s", (int)strcspn(p, "\n/"), p);
	snprintf(path, sizeof path, "%s/bus/usb-serial/devices/%s", root, name);
	return *name && stat(path, &st) == 0;
}

/* Ask the driver for low latency; remember whether we changed the flag. */
static void port_usb_low_latency(struct df1 *h, struct port_usb *u)
{
	struct serial_struct ss;

	memset(&ss, 0, sizeof ss);
	if (ioctl(h->fd, TIOCGSERIAL, &ss) < 0 || (ss.flags & ASYNC_LOW_LATENCY))
		return;
	ss.flags |= ASYNC_LOW_LATENCY;
	if (ioctl(h->fd, TIOCSSERIAL, &ss) == 0)
		u->flags_changed = true;
}

/* The latency timer still above 1 ms: the note and its log line, once per open. */
static void port_usb_report(struct df1 *h, const char *name, const char *path, int ms)
{
	snprintf(h->port_note, sizeof h->port_note,
	         "%s: USB adapter %s holds received bytes up to %d ms (latency timer %s, not "
	         "lowered by low latency mode): every turnaround can wait that long; "
	         "a udev rule fixes it: %s (contrib/udev/60-df1-serial.rules)",
	         h->port_name, name, ms, path, USB_RULE);
	if (h->log_fn)
		h->log_fn(h->log_user, 0, DF1_SEV_NOTICE, h->port_note);
}

void port_usb_open(struct df1 *h, struct port_usb *u)
{
	const char *root = port_usb_sysfs_root();
	char name[64], path[384], text[32];
	char *end;
	long ms;

	memset(u, 0, sizeof *u);
	h->port_note[0] = 0;
	if (!h->cfg.low_latency || h->fd < 0 || !port_usb_name(h->fd, root, name, sizeof name))
		return;
	port_usb_low_latency(h, u);
	snprintf(path, sizeof path, "%s/bus/usb-serial/devices/%s/latency_timer", root, name);
	if (!port_usb_read(path, text, sizeof text))
		return;         /* no timer in sysfs (pl2303, cp210x, ...) */
	ms = strtol(text, &end, 10);
	if (end != text && ms > 1)
		port_usb_report(h, name, path, (int)ms);
}

void port_usb_close(struct df1 *h, struct port_usb *u)
{
	struct serial_struct ss;

	h->port_note[0] = 0;
	if (!u->flags_changed || h->fd < 0)
		return;
	memset(&ss, 0, sizeof ss);
	if (ioctl(h->fd, TIOCGSERIAL, &ss) == 0) {
		ss.flags &= ~ASYNC_LOW_LATENCY;
		(void)ioctl(h->fd, TIOCSSERIAL, &ss);
	}
	u->flags_changed = false;
}

DF1_API const char *df1_port_note(const df1_t *h)
{
	return h && h->port ? h->port_note : "";
}
