/* SPDX-License-Identifier: MPL-2.0 */
/*
 * handle.c - the df1_t handle: allocation and defaults, settings with range
 * checks (doc/REQUIREMENTS.md 004 network configuration table), open/close over the port
 * backends, last-error detail, counters and the active station list. The
 * internal error, counter and logging helpers are lib/base/base.c's.
 *
 * Invalid settings return DF1_E_CONFIG; the handle keeps the detail: the
 * seed's critical message ID (2552-2559) and its formatted text where the seed
 * has one, else catalog ID 0 and a message naming the field and its range.
 */
#include "df1_int.h"
#include "link/link.h"
#include "scheme.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <time.h>
#include <unistd.h>

#define STATION_MAX 254
#define RETRIES_MAX 10
#define CMD_TIMEOUT_MIN 500
#define CMD_TIMEOUT_MAX 5000
#define TIMEOUT_MAX 360000
#define TX_DELAY_MAX 65535
#define MAX_PACKET_MAX 250
#define LINE_BAUD_MAX 4000000

/* ------------------------------------------------------------------------
 * Last error
 * ------------------------------------------------------------------------ */

static const struct df1_error_detail handle_null_error = {
	.code = DF1_E_INVAL,
	.station = -1,
	.message = "no handle (NULL)",
};

const struct df1_error_detail *df1_last_error(const df1_t *h)
{
	return h ? &h->err : &handle_null_error;
}

/* ------------------------------------------------------------------------
 * Counters and the active station list
 * ------------------------------------------------------------------------ */

static bool handle_counter_valid(int id)
{
	const struct df1_catalog_entry *e = df1_catalog_by_id(id);

	return e && e->severity == DF1_SEV_COUNTER;
}

int df1_counter(const df1_t *h, int id, uint64_t *value)
{
	if (!h || !value || !handle_counter_valid(id))
		return DF1_E_INVAL;
	*value = h->counters[id - CNT_BASE];
	return 0;
}

void df1_counters_reset(df1_t *h)
{
	if (h) {
		memset(h->counters, 0, sizeof h->counters);
		memset(&h->radio_st, 0, sizeof h->radio_st);
	}
}

int df1_station_active(const df1_t *h, int station)
{
	if (!h || station < 0 || station > STATION_MAX)
		return DF1_E_INVAL;
	return h->stations[station].active ? 1 : 0;
}

int df1_station_set_active(df1_t *h, int station, bool active)
{
	if (!h)
		return DF1_E_INVAL;
	if (station < 0 || station > STATION_MAX)
		return df1_fail(h, DF1_E_INVAL, -1, "invalid station %d: must be 0..%d", station,
		                STATION_MAX);
	h->stations[station].active = active;
	return 0;
}

/* ------------------------------------------------------------------------
 * Allocation
 * ------------------------------------------------------------------------ */

/* A valid decoder from the start; the link re-initialises it when the
 * settings it depends on change (link_setup). */
static void handle_decoder_init(struct df1 *h)
{
	frame_decoder_init(&h->dec, h->cfg.check, link_decoder_opts(h));
}

/* Link-side buffers start empty on every new connection. */
static void handle_reset_io(struct df1 *h)
{
	h->rx_len = h->rx_pos = 0;
	h->echo_len = h->echo_pos = 0;
	frame_decoder_reset(&h->dec);
	h->tx_end_us = h->rx_due_us = 0;
	h->tx_hold_len = 0;
	h->scan_epoch_ms = df1_now_ms();
}

/* 16 random bits for a first TNS, never blocking: getrandom(2) without
 * waiting for the entropy pool; where it fails (ENOSYS on an old kernel,
 * EAGAIN before the pool is ready at early boot, a seccomp filter),
 * /dev/urandom; where that cannot be read either, the monotonic and real
 * clocks, the pid and a per-process count mixed by splitmix64's finaliser, so
 * that even then two runs do not start where a clock's period says. */
static uint16_t handle_random16(unsigned int n)
{
	uint16_t v;
	ssize_t r;
	int fd;

	do
		r = getrandom(&v, sizeof v, GRND_NONBLOCK);
	while (r < 0 && errno == EINTR);
	if (r == (ssize_t)sizeof v)
		return v;
	fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC | O_NONBLOCK);
	if (fd >= 0) {
		r = read(fd, &v, sizeof v);
		close(fd);
		if (r == (ssize_t)sizeof v)
			return v;
	}
	{
		struct timespec rt;
		uint64_t x;

		clock_gettime(CLOCK_REALTIME, &rt);
		x = df1_now_us() ^ ((uint64_t)rt.tv_nsec << 20) ^ ((uint64_t)rt.tv_sec << 40) ^
		    ((uint64_t)getpid() << 16) ^ (0x9E3779B97F4A7C15ull * (n + 1u));
		x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
		x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
		return (uint16_t)(x ^ (x >> 31) ^ (x >> 47));
	}
}

/* First TNS of a handle. A DF1 node drops a message with the same SRC, CMD and
 * TNS as the last one it took (duplicate detection), so a handle must not start
 * where the previous one, in this process or the previous run of a tool, ended.
 * A clock does not do: a microsecond clock modulo 65536 comes round every
 * 65.536 ms, and a tool run every second starts within a few hundred of where
 * the last one did. A random start makes the chance that a run's first command
 * repeats the previous run's last TNS 1 in 65536. Two handles made one after
 * the other in a process never start on the same value. Tests that need a
 * known TNS set h->next_tns, or DF1_TEST_FIRST_TNS for a whole process
 * (df1_new(3): tests only). */
static uint16_t handle_tns_seed(void)
{
	static atomic_uint made, last;
	unsigned int n = atomic_fetch_add(&made, 1u);
	const char *force = getenv("DF1_TEST_FIRST_TNS");
	uint16_t v;

	if (force && *force) {
		/* for tests only (df1_new(3)): a run started on the previous
		 * run's last TNS */
		char *end;
		unsigned long t;

		errno = 0;
		t = strtoul(force, &end, force[0] == '0' && (force[1] | 0x20) == 'x' ? 16 : 10);
		if (!errno && !*end && t <= 0xFFFF && force[0] != '-' && force[0] != '+')
			return (uint16_t)t;
	}
	v = handle_random16(n);

	if (n > 0 && v == (uint16_t)atomic_load(&last))
		v = (uint16_t)(v + 40503u);
	atomic_store(&last, v);
	return v;
}

int df1_new(df1_t **out)
{
	struct df1 *h;
	int i;

	if (!out)
		return DF1_E_INVAL;
	*out = NULL;
	h = calloc(1, sizeof *h);
	if (!h)
		return DF1_E_NOMEM;
	h->cfg.baud = 19200;
	h->cfg.data_bits = 8;
	h->cfg.parity = 'N';
	h->cfg.stop_bits = 1;
	h->cfg.rts_cts = false;
	h->cfg.duplex = DF1_FULL_DUPLEX;
	h->cfg.check = DF1_CHECK_CRC;
	h->cfg.station = 0;
	h->cfg.plc = DF1_PLC_SLC;
	h->cfg.timeout_ms = 1000;
	h->cfg.cmd_timeout_ms = 1000;
	h->cfg.nak_retries = 3;
	h->cfg.enq_retries = 3;
	h->cfg.tx_delay_ms = 0;
	h->cfg.dup_detect = true;
	h->cfg.embedded = true;
	h->cfg.hd_bcc_stx = false;
	h->cfg.nak_0f = true;
	h->cfg.rs485 = false;
	h->cfg.low_latency = true;
	h->cfg.route = true;
	h->cfg.echo_discard = false;
	h->cfg.eot_bcc = false;
	h->cfg.local_tcp = true;
	h->cfg.plc5_float_swapped = false;
	h->cfg.slc_io_82 = false;
	h->cfg.max_packet = 0;
	h->cfg.plc5_timer_words = 3;
	h->cfg.max_outstanding = 1;
	h->cfg.app_retries = 0;
	h->cfg.radio_dup = DF1_DUP_AUTO;
	h->cfg.plc2_word_addr = false;
	h->cfg.line_baud = 0;

	h->port = NULL;
	h->fd = -1;
	h->cancel_fd = -1;
	h->next_tns = handle_tns_seed();
	h->last_response = DF1_NAK;
	for (i = 0; i < 256; i++)
		h->stations[i].active = true;
	df1_clear_error(h);
	handle_decoder_init(h);
	*out = h;
	return 0;
}

void df1_free(df1_t *h)
{
	if (!h)
		return;
	df1_close(h);
	if (h->srv_free)
		h->srv_free(h);
	else
		free(h->srv);
	if (h->poll_free)
		h->poll_free(h);
	else
		free(h->poll);
	free(h->peer_own);
	free(h->route);
	free(h);
}

/* ------------------------------------------------------------------------
 * Settings
 * ------------------------------------------------------------------------ */

/* After a change of serial settings: apply them to an open serial port; on
 * failure put the old settings back (port and stored) and keep the error. */
static int handle_apply(struct df1 *h, const struct df1_config *old)
{
	int r;

	if (!h->port || !h->port->configure)
		return 0;
	r = h->port->configure(h);
	if (r < 0) {
		struct df1_error_detail e = h->err;

		h->cfg = *old;
		(void)h->port->configure(h);
		h->err = e;
	}
	return r;
}

int df1_set_serial(df1_t *h, int baud, int data_bits, char parity, int stop_bits)
{
	struct df1_config old;

	if (!h)
		return DF1_E_INVAL;
	switch (baud) {
	case 1200: case 2400: case 4800: case 9600:
	case 19200: case 38400: case 57600: case 115200:
		break;
	default:
		return df1_fail(h, DF1_E_CONFIG, -1,
		                "invalid baud rate %d: must be 1200, 2400, 4800, 9600, 19200, 38400, "
		                "57600 or 115200", baud);
	}
	if (data_bits < 5 || data_bits > 8)
		return df1_fail(h, DF1_E_CONFIG, -1, "invalid data bits %d: must be 5..8", data_bits);
	if (parity >= 'a' && parity <= 'z')
		parity = (char)(parity - 'a' + 'A');
	if (parity != 'N' && parity != 'E' && parity != 'O') {
		if (parity > ' ' && parity < 0x7F)
			return df1_fail(h, DF1_E_CONFIG, -1,
			                "invalid parity '%c': must be N (none), E (even) or O (odd)", parity);
		return df1_fail(h, DF1_E_CONFIG, -1,
		                "invalid parity 0x%02X: must be N (none), E (even) or O (odd)",
		                (unsigned char)parity);
	}
	if (stop_bits < 1 || stop_bits > 2)
		return df1_fail(h, DF1_E_CONFIG, -1, "invalid stop bits %d: must be 1 or 2", stop_bits);
	old = h->cfg;
	h->cfg.baud = baud;
	h->cfg.data_bits = data_bits;
	h->cfg.parity = parity;
	h->cfg.stop_bits = stop_bits;
	return handle_apply(h, &old);
}

int df1_set_handshake(df1_t *h, bool rts_cts)
{
	struct df1_config old;

	if (!h)
		return DF1_E_INVAL;
	old = h->cfg;
	h->cfg.rts_cts = rts_cts;
	return handle_apply(h, &old);
}

int df1_set_duplex(df1_t *h, enum df1_duplex d)
{
	if (!h)
		return DF1_E_INVAL;
	if (d != DF1_FULL_DUPLEX && d != DF1_HALF_DUPLEX_MASTER && d != DF1_HALF_DUPLEX_SLAVE &&
	    d != DF1_RADIO_MODEM) {
		char v[16];

		snprintf(v, sizeof v, "%d", (int)d);
		return df1_fail_catalog(h, DF1_ID_CRT_BAD_DRIVER_MODE, v, "Master", "Slave",
		                        "Peer");
	}
	h->cfg.duplex = d;
	return 0;
}

int df1_set_check(df1_t *h, enum df1_check c)
{
	if (!h)
		return DF1_E_INVAL;
	if (c != DF1_CHECK_CRC && c != DF1_CHECK_BCC) { /* AUTO is for decoders only */
		char v[16];

		snprintf(v, sizeof v, "%d", (int)c);
		return df1_fail_catalog(h, DF1_ID_CRT_BAD_ERROR_CODE, v, "BCC", "CRC");
	}
	h->cfg.check = c;
	return 0;
}

int df1_set_station(df1_t *h, int own_station)
{
	if (!h)
		return DF1_E_INVAL;
	if (own_station < 0 || own_station > STATION_MAX)
		return df1_fail_catalog(h, DF1_ID_CRT_BAD_STATION_ID, own_station, STATION_MAX + 1);
	h->cfg.station = own_station;
	return 0;
}

int df1_set_plc(df1_t *h, enum df1_plc plc)
{
	if (!h)
		return DF1_E_INVAL;
	switch (plc) {
	case DF1_PLC_SLC:
	case DF1_PLC_MICROLOGIX:
	case DF1_PLC_SLC502:
	case DF1_PLC_PLC5:
	case DF1_PLC_PLC2:
	case DF1_PLC_PLC3:
		h->cfg.plc = plc;
		return 0;
	default: {
		char v[16];

		snprintf(v, sizeof v, "%d", (int)plc);
		return df1_fail_catalog(h, DF1_ID_CRT_BAD_PLC_TYPE, v, "SLC", "MicroLogix", "PLC5",
		                        "PLC2");
	}
	}
}

int df1_set_timeout_ms(df1_t *h, int ms)
{
	if (!h)
		return DF1_E_INVAL;
	if (ms < 0 || ms > TIMEOUT_MAX)
		return df1_fail(h, DF1_E_CONFIG, -1, "invalid timeout %d ms: must be 0..%d ms", ms,
		                TIMEOUT_MAX);
	h->cfg.timeout_ms = ms;
	return 0;
}

int df1_set_cmd_timeout_ms(df1_t *h, int ms)
{
	if (!h)
		return DF1_E_INVAL;
	if (ms < CMD_TIMEOUT_MIN || ms > CMD_TIMEOUT_MAX)
		return df1_fail_catalog(h, DF1_ID_CRT_BAD_CMD_TIMEOUT, ms, CMD_TIMEOUT_MIN,
		                        CMD_TIMEOUT_MAX);
	h->cfg.cmd_timeout_ms = ms;
	return 0;
}

int df1_set_retries(df1_t *h, int nak_retries, int enq_retries)
{
	if (!h)
		return DF1_E_INVAL;
	if (nak_retries < 0 || nak_retries > RETRIES_MAX)
		return df1_fail_catalog(h, DF1_ID_CRT_BAD_NAK_RETRIES, nak_retries, RETRIES_MAX);
	if (enq_retries < 0 || enq_retries > RETRIES_MAX)
		return df1_fail_catalog(h, DF1_ID_CRT_BAD_ENQ_RETRIES, enq_retries, RETRIES_MAX);
	h->cfg.nak_retries = nak_retries;
	h->cfg.enq_retries = enq_retries;
	return 0;
}

int df1_set_tx_delay_ms(df1_t *h, int ms)
{
	if (!h)
		return DF1_E_INVAL;
	if (ms < 0 || ms > TX_DELAY_MAX)
		return df1_fail(h, DF1_E_CONFIG, -1, "invalid TX delay %d ms: must be 0..%d ms", ms,
		                TX_DELAY_MAX);
	h->cfg.tx_delay_ms = ms;
	return 0;
}

int df1_set_line_baud(df1_t *h, int baud)
{
	if (!h)
		return DF1_E_INVAL;
	if (baud != 0 && (baud < 50 || baud > LINE_BAUD_MAX))
		return df1_fail(h, DF1_E_CONFIG, -1,
		                "invalid line baud rate %d: must be 0 (off) or 50..%d", baud,
		                LINE_BAUD_MAX);
	h->cfg.line_baud = baud;
	return 0;
}

static const char *handle_option_name(enum df1_option opt)
{
	switch (opt) {
	case DF1_OPT_DUPLICATE_DETECT: return "DUPLICATE_DETECT";
	case DF1_OPT_EMBEDDED_RESPONSES: return "EMBEDDED_RESPONSES";
	case DF1_OPT_HD_BCC_INCLUDES_STX: return "HD_BCC_INCLUDES_STX";
	case DF1_OPT_ACCEPT_NAK_0F: return "ACCEPT_NAK_0F";
	case DF1_OPT_RS485: return "RS485";
	case DF1_OPT_ECHO_DISCARD: return "ECHO_DISCARD";
	case DF1_OPT_MAX_PACKET: return "MAX_PACKET";
	case DF1_OPT_EOT_WITH_BCC: return "EOT_WITH_BCC";
	case DF1_OPT_LOCAL_TCP: return "LOCAL_TCP";
	case DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED: return "PLC5_TYPED_FLOAT_SWAPPED";
	case DF1_OPT_SLC_IO_CODES_82: return "SLC_IO_CODES_82";
	case DF1_OPT_LISTEN_ONLY: return "LISTEN_ONLY";
	case DF1_OPT_PLC5_TIMER_WORDS: return "PLC5_TIMER_WORDS";
	case DF1_OPT_PLC2_WORD_ADDR: return "PLC2_WORD_ADDR";
	case DF1_OPT_POLL_TIMEOUT_MS: return "POLL_TIMEOUT_MS";
	case DF1_OPT_SCAN_TIME_MS: return "SCAN_TIME_MS";
	case DF1_OPT_NO_EOT: return "NO_EOT";
	case DF1_OPT_MAX_OUTSTANDING: return "MAX_OUTSTANDING";
	case DF1_OPT_EIP_CONNECTED: return "EIP_CONNECTED";
	case DF1_OPT_LOW_LATENCY: return "LOW_LATENCY";
	case DF1_OPT_PLC5_REFUSE_LARGE: return "PLC5_REFUSE_LARGE";
	case DF1_OPT_ROUTE: return "ROUTE";
	case DF1_OPT_APP_RETRIES: return "APP_RETRIES";
	case DF1_OPT_RADIO_DUP_DETECT: return "RADIO_DUP_DETECT";
	case DF1_OPT_RADIO_RTS_CTS: return "RADIO_RTS_CTS";
	case DF1_OPT_RTS_SEND_DELAY_MS: return "RTS_SEND_DELAY_MS";
	case DF1_OPT_RTS_OFF_DELAY_MS: return "RTS_OFF_DELAY_MS";
	case DF1_OPT_DCD_WAIT_MS: return "DCD_WAIT_MS";
	}
	return NULL;
}

/* The bool member behind a bool option, or NULL. */
static bool *handle_option_flag(struct df1_config *c, enum df1_option opt)
{
	switch (opt) {
	case DF1_OPT_DUPLICATE_DETECT: return &c->dup_detect;
	case DF1_OPT_EMBEDDED_RESPONSES: return &c->embedded;
	case DF1_OPT_HD_BCC_INCLUDES_STX: return &c->hd_bcc_stx;
	case DF1_OPT_ACCEPT_NAK_0F: return &c->nak_0f;
	case DF1_OPT_RS485: return &c->rs485;
	case DF1_OPT_ECHO_DISCARD: return &c->echo_discard;
	case DF1_OPT_EOT_WITH_BCC: return &c->eot_bcc;
	case DF1_OPT_LOCAL_TCP: return &c->local_tcp;
	case DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED: return &c->plc5_float_swapped;
	case DF1_OPT_SLC_IO_CODES_82: return &c->slc_io_82;
	case DF1_OPT_LISTEN_ONLY: return &c->listen_only;
	case DF1_OPT_PLC2_WORD_ADDR: return &c->plc2_word_addr;
	case DF1_OPT_NO_EOT: return &c->no_eot;
	case DF1_OPT_EIP_CONNECTED: return &c->eip_connected;
	case DF1_OPT_LOW_LATENCY: return &c->low_latency;
	case DF1_OPT_PLC5_REFUSE_LARGE: return &c->plc5_refuse_large;
	case DF1_OPT_ROUTE: return &c->route;
	case DF1_OPT_RADIO_RTS_CTS: return &c->radio_rts_cts;
	case DF1_OPT_APP_RETRIES: case DF1_OPT_RADIO_DUP_DETECT: case DF1_OPT_RTS_SEND_DELAY_MS:
	case DF1_OPT_RTS_OFF_DELAY_MS: case DF1_OPT_DCD_WAIT_MS:
	case DF1_OPT_MAX_PACKET: case DF1_OPT_PLC5_TIMER_WORDS:
	case DF1_OPT_POLL_TIMEOUT_MS: case DF1_OPT_SCAN_TIME_MS: case DF1_OPT_MAX_OUTSTANDING:
		return NULL;
	}
	return NULL;
}

/* The int member behind a radio modem option that is not a bool, or NULL. */
static int *handle_radio_int(df1_t *h, enum df1_option opt)
{
	switch (opt) {
	case DF1_OPT_APP_RETRIES: return &h->cfg.app_retries;
	case DF1_OPT_RADIO_DUP_DETECT: return &h->cfg.radio_dup;
	case DF1_OPT_RTS_SEND_DELAY_MS: return &h->cfg.rts_send_ms;
	case DF1_OPT_RTS_OFF_DELAY_MS: return &h->cfg.rts_off_ms;
	case DF1_OPT_DCD_WAIT_MS: return &h->cfg.dcd_wait_ms;
	default: return NULL;
	}
}

static int handle_set_radio(df1_t *h, enum df1_option opt, const char *name, int value)
{
	if (opt == DF1_OPT_APP_RETRIES && (value < 0 || value > 10))
		return df1_fail(h, DF1_E_CONFIG, -1,
		                "invalid value %d for option APP_RETRIES: must be 0..10", value);
	if (opt == DF1_OPT_RADIO_DUP_DETECT && value != 0 && value != 1 && value != DF1_DUP_AUTO)
		return df1_fail(h, DF1_E_CONFIG, -1, "invalid value %d for option RADIO_DUP_DETECT: "
		                "must be 0 (no), 1 (yes) or %d (auto)", value, DF1_DUP_AUTO);
	if (opt != DF1_OPT_APP_RETRIES && opt != DF1_OPT_RADIO_DUP_DETECT &&
	    (value < 0 || value > 65535))
		return df1_fail(h, DF1_E_CONFIG, -1, "invalid value %d for option %s: must be 0..65535 ms",
		                value, name);
	*handle_radio_int(h, opt) = value;
	return 0;
}

int df1_set_option(df1_t *h, enum df1_option opt, int value)
{
	const char *name;
	struct df1_config old;
	bool *flag;

	if (!h)
		return DF1_E_INVAL;
	name = handle_option_name(opt);
	if (!name)
		return df1_fail(h, DF1_E_INVAL, -1, "unknown option %d", (int)opt);
	old = h->cfg;
	if (opt == DF1_OPT_MAX_PACKET) {
		if (value < 0 || value > MAX_PACKET_MAX)
			return df1_fail(h, DF1_E_CONFIG, -1,
			                "invalid value %d for option MAX_PACKET: must be 0 (per PLC type) "
			                "or 1..%d bytes", value, MAX_PACKET_MAX);
		h->cfg.max_packet = value;
		return 0;
	}
	if (opt == DF1_OPT_PLC5_TIMER_WORDS) {
		if (value != 3 && value != 5)
			return df1_fail(h, DF1_E_CONFIG, -1,
			                "invalid value %d for option PLC5_TIMER_WORDS: must be 3 or 5", value);
		h->cfg.plc5_timer_words = value;
		h->cfg.plc5_timer_forced = true;
		return 0;
	}
	if (opt == DF1_OPT_POLL_TIMEOUT_MS || opt == DF1_OPT_SCAN_TIME_MS) {
		int max = opt == DF1_OPT_POLL_TIMEOUT_MS ? 60000 : 10000;

		if (value < 0 || value > max)
			return df1_fail(h, DF1_E_CONFIG, -1,
			                "invalid value %d for option %s: must be 0..%d ms", value, name, max);
		*(opt == DF1_OPT_POLL_TIMEOUT_MS ? &h->cfg.poll_timeout_ms : &h->cfg.scan_time_ms) = value;
		return 0;
	}
	if (opt == DF1_OPT_MAX_OUTSTANDING) {
		if (value < 1 || value > LINK_PIPE_MAX - 1)
			return df1_fail(h, DF1_E_CONFIG, -1,
			                "invalid value %d for option MAX_OUTSTANDING: must be 1..%d", value,
			                LINK_PIPE_MAX - 1);
		h->cfg.max_outstanding = value;
		return 0;
	}
	if (handle_radio_int(h, opt) != NULL)
		return handle_set_radio(h, opt, name, value);
	if (value != 0 && value != 1)
		return df1_fail(h, DF1_E_CONFIG, -1, "invalid value %d for option %s: must be 0 or 1",
		                value, name);
	flag = handle_option_flag(&h->cfg, opt);
	if (opt == DF1_OPT_LISTEN_ONLY && h->port && *flag != (value != 0))
		return df1_fail(h, DF1_E_INVAL, -1, "option LISTEN_ONLY is set before df1_open(): "
		                "%s is open", h->port_name);
	if (opt == DF1_OPT_EIP_CONNECTED && h->own_link && *flag != (value != 0))
		return df1_fail(h, DF1_E_INVAL, -1, "option EIP_CONNECTED is set before df1_open(): "
		                "%s is open", h->port_name);
	*flag = value != 0;
	if (opt == DF1_OPT_RS485)
		return handle_apply(h, &old);
	return 0;
}

int df1_get_option(const df1_t *h, enum df1_option opt)
{
	struct df1_config c;
	bool *flag;

	if (!h || !handle_option_name(opt))
		return DF1_E_INVAL;
	if (opt == DF1_OPT_MAX_PACKET)
		return h->cfg.max_packet;
	if (opt == DF1_OPT_PLC5_TIMER_WORDS)
		return h->cfg.plc5_timer_words;
	if (opt == DF1_OPT_POLL_TIMEOUT_MS)
		return h->cfg.poll_timeout_ms;
	if (opt == DF1_OPT_SCAN_TIME_MS)
		return h->cfg.scan_time_ms;
	if (opt == DF1_OPT_MAX_OUTSTANDING)
		return h->cfg.max_outstanding;
	if (handle_radio_int((df1_t *)h, opt))
		return *handle_radio_int((df1_t *)h, opt);
	c = h->cfg;
	flag = handle_option_flag(&c, opt);
	return flag && *flag ? 1 : 0;
}

void df1_set_log(df1_t *h, df1_log_fn fn, void *user)
{
	if (!h)
		return;
	h->log_fn = fn;
	h->log_user = user;
}

void df1_set_trace(df1_t *h, df1_trace_fn fn, void *user)
{
	if (!h)
		return;
	h->trace_fn = fn;
	h->trace_user = user;
}

int df1_set_cancel_fd(df1_t *h, int fd)
{
	if (!h)
		return DF1_E_INVAL;
	if (fd < -1 || (fd >= 0 && fcntl(fd, F_GETFD) < 0))
		return df1_fail(h, DF1_E_INVAL, -1, "cancel fd %d is not an open descriptor", fd);
	h->cancel_fd = fd;
	return 0;
}

/* ------------------------------------------------------------------------
 * Open / close
 * ------------------------------------------------------------------------ */

static void handle_port_reset(struct df1 *h)
{
	h->port = NULL;
	h->port_data = NULL;
	h->fd = -1;
	h->own_link = NULL;
	h->own_link_data = NULL;
}

/* After a backend's open: r is its result. A backend that fails has closed
 * and freed what it opened; a descriptor given to df1_open_fd() stays the
 * caller's. */
static int handle_opened(struct df1 *h, const struct port_ops *ops, int r)
{
	if (r < 0) {
		handle_port_reset(h);
		return r;
	}
	h->port = ops;
	handle_reset_io(h);
	return 0;
}

int df1_open(df1_t *h, const char *target)
{
	const struct scheme_row *s;

	if (!h)
		return DF1_E_INVAL;
	if (!target || !*target)
		return df1_fail(h, DF1_E_INVAL, -1, "no device given");
	if (h->port)
		return df1_fail(h, DF1_E_INVAL, -1, "handle is already open on %s", h->port_name);
	df1_clear_error(h);
	handle_port_reset(h);
	s = scheme_find(target); /* lib/scheme.c; "TCP://" too (RFC 3986 3.1) */
	if (s->link) {
		/* the scheme's own link opens its port (h->port) under it */
		h->port = s->port;
		h->own_link = s->link;
		return handle_opened(h, s->port, s->link->open(h, target));
	}
	return handle_opened(h, s->port, s->port->open(h, target));
}

int df1_open_fd(df1_t *h, int fd, bool take_ownership)
{
	if (!h)
		return DF1_E_INVAL;
	if (h->port)
		return df1_fail(h, DF1_E_INVAL, -1, "handle is already open on %s", h->port_name);
	if (fd < 0)
		return df1_fail(h, DF1_E_INVAL, -1, "invalid descriptor %d", fd);
	df1_clear_error(h);
	handle_port_reset(h);
	return handle_opened(h, &port_fd_ops, port_fd_open(h, fd, take_ownership));
}

void df1_close(df1_t *h)
{
	if (!h || !h->port)
		return;
	if (h->own_link)
		h->own_link->close(h); /* eip://: UnRegisterSession while the socket is open */
	h->port->close(h);
	handle_port_reset(h);
	h->rx_len = h->rx_pos = 0;
	h->echo_len = h->echo_pos = 0;
}

bool df1_is_open(const df1_t *h)
{
	return h && h->port != NULL;
}
