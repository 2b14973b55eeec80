/* SPDX-License-Identifier: MPL-2.0 */
/*
 * probe_line.c - df1_probe_line(): auto-configure an unknown line in stages
 * (the link, the error check, identity), most likely settings first, with
 * short answer windows and early stops (include/df1.h, df1_probe_line(3)).
 *
 * Only link tests (DLE ENQ, polls), echoes (06/00) and the diagnostic status
 * (06/03) go out: nothing that writes to a controller. A setting counts only
 * when an echo with a check came back intact, since a UART at the wrong rate
 * or parity can turn bytes into a valid DLE NAK but not a whole frame with
 * its CRC or BCC (doc/PROTOCOL.md 9.3).
 */
#include "client/client_int.h"

#include "port/port.h"

static const int probe_bauds[] = { 19200, 9600, 38400, 57600, 115200, 4800, 2400, 1200 };
static const char probe_parities[] = { 'N', 'E', 'O' };
#define PROBE_NBAUD ((int)(sizeof probe_bauds / sizeof probe_bauds[0]))
#define PROBE_NPAR ((int)sizeof probe_parities)

/* Echo data no misread survives: 0xFF (the Telnet IAC), DLE, both parities. */
static const uint8_t probe_echo_data[] = { 0xFF, 0x10, 0x55, 0xAA, 0x00, 0x81, 0x7E, 0x03 };

struct probe {
	df1_t *h;
	df1_probe_fn fn;
	void *user;
	struct df1_probe_result *out;
	int lo, hi;
};

/* The answer window at baud: 30 ms turnaround + 6 characters of 11 bits,
 * + 50 ms when a network lies between us and the line; or the poll timeout
 * the caller set (DF1_OPT_POLL_TIMEOUT_MS), for a slow slave or a loaded host. */
static int probe_window_ms(const df1_t *h, int baud)
{
	int ms = 30 + (6 * 11 * 1000 + baud - 1) / baud;

	if (h->cfg.poll_timeout_ms > 0)
		return h->cfg.poll_timeout_ms;

	if (h->port && h->port->net_slack)
		ms += 50;
	return ms;
}

/* An attempt of stage 1 from start to end: sending it (a poll is up to 5
 * characters, DLE doubled in the station), its window, and 5 ms for the
 * host (a settings change, the system calls). */
static int probe_attempt_ms(const df1_t *h, int baud)
{
	return (5 * 11 * 1000 + baud - 1) / baud + probe_window_ms(h, baud) + 5;
}

int64_t df1_probe_line_bound_ms(const df1_t *h, int lo, int hi)
{
	int64_t ms = 0;

	if (!h || lo < 0 || hi > 254 || lo > hi)
		return DF1_E_INVAL;
	for (int b = 0; b < PROBE_NBAUD; b++)   /* an ENQ, the first poll twice, the others once */
		ms += (int64_t)PROBE_NPAR * (2 + (hi - lo + 1)) * probe_attempt_ms(h, probe_bauds[b]);
	return ms;
}

/* Report an attempt; non-zero from the callback stops the search. */
static int probe_report(struct probe *p, enum df1_probe_stage stage, const char *what, int r)
{
	struct df1_probe_attempt a;

	p->out->attempts++;
	if (!p->fn)
		return 0;
	memset(&a, 0, sizeof a);
	a.stage = stage;
	a.tried.baud = p->h->cfg.baud;
	a.tried.data_bits = p->h->cfg.data_bits;
	a.tried.stop_bits = p->h->cfg.stop_bits;
	a.tried.parity = p->h->cfg.parity;
	a.tried.duplex = p->h->cfg.duplex;
	a.tried.check = p->h->cfg.check;
	a.tried.hd_bcc_stx = p->h->cfg.hd_bcc_stx;
	a.tried.station = p->out->found.station;
	a.what = what;
	a.answered = r >= 0;
	a.error = r >= 0 ? DF1_OK : r;
	return p->fn(p->user, &a) ? df1_fail(p->h, DF1_E_INTR, -1, "line probe stopped") : 0;
}

/* An error that ends the search: the port is gone or the caller stopped it. */
static bool probe_fatal(int r)
{
	return r == DF1_E_INTR || r == DF1_E_CLOSED || r == DF1_E_SYS || r == DF1_E_NOT_OPEN ||
	       r == DF1_E_NOMEM || r == DF1_E_NOTSUP || r == DF1_E_CONFIG;
}

/* Stage 2 at the settings in force: an echo with each check. 1 found, 0 none. */
static int probe_check(struct probe *p, int station)
{
	static const struct { enum df1_check c; bool stx; bool half_only; } checks[] = {
		{ DF1_CHECK_CRC, false, false }, { DF1_CHECK_BCC, false, false }, { DF1_CHECK_BCC, true, true },
	};
	df1_t *h = p->h;

	for (size_t i = 0; i < sizeof checks / sizeof checks[0]; i++) {
		int r;

		if (checks[i].half_only && h->cfg.duplex != DF1_HALF_DUPLEX_MASTER)
			continue;
		(void)df1_set_check(h, checks[i].c);
		(void)df1_set_option(h, DF1_OPT_HD_BCC_INCLUDES_STX, checks[i].stx);
		/* an echo's frames take line time: 80 characters more than a poll */
		(void)df1_set_timeout_ms(h, probe_window_ms(h, h->cfg.baud) +
		                            80 * 11 * 1000 / h->cfg.baud);
		r = df1_echo(h, station, probe_echo_data, sizeof probe_echo_data);
		if (probe_report(p, DF1_PROBE_CHECK, "echo 06/00", r) < 0)
			return DF1_E_INTR;
		if (r >= 0)
			return 1;
		if (probe_fatal(r))
			return r;
	}
	return 0;
}

static int probe_set(struct probe *p, int baud, char parity, enum df1_duplex d)
{
	df1_t *h = p->h;
	int w = probe_window_ms(h, baud);
	int r = df1_set_serial(h, baud, 8, parity, 1);

	if (r < 0)
		return r;
	(void)df1_set_duplex(h, d);
	(void)df1_set_check(h, DF1_CHECK_CRC);
	(void)df1_set_timeout_ms(h, w);
	(void)df1_set_retries(h, 0, 0);
	return 0;
}

/* Stage 1 and 2 at one baud and parity: full duplex, then half. 1 found, 0 not. */
static int probe_setting(struct probe *p, int baud, char parity)
{
	int r = probe_set(p, baud, parity, DF1_FULL_DUPLEX);

	if (r < 0)
		return r;
	p->out->found.station = -1;
	r = df1_link_test(p->h, 0);
	if (probe_report(p, DF1_PROBE_LINK, "DLE ENQ", r) < 0)
		return DF1_E_INTR;
	if (r >= 0) {
		(void)df1_set_retries(p->h, 1, 1);
		r = probe_check(p, 1);
		if (r != 0)
			return r;
	} else if (probe_fatal(r)) {
		return r;
	}
	r = probe_set(p, baud, parity, DF1_HALF_DUPLEX_MASTER);
	/* st = lo - 1 polls lo once more: a half-duplex slave may take the DLE
	 * ENQ just sent for the start of a poll and our first poll's bytes for its
	 * station and BCC, and so miss that poll */
	for (int st = p->lo - 1; r >= 0 && st <= p->hi; st++) {
		int poll_st = st < p->lo ? p->lo : st;

		p->out->found.station = poll_st;
		r = df1_link_test(p->h, poll_st);
		if (probe_report(p, DF1_PROBE_LINK, "poll", r) < 0)
			return DF1_E_INTR;
		if (r < 0) {
			if (probe_fatal(r))
				return r;
			r = 0;
			continue;
		}
		(void)df1_set_retries(p->h, 1, 1);
		r = probe_check(p, poll_st);
		if (r != 0)
			return r;
		(void)df1_set_retries(p->h, 0, 0);
	}
	p->out->found.station = -1;
	return r < 0 ? r : 0;
}

static int probe_on_station(void *user, const struct df1_discover_result *r)
{
	struct probe *p = user;

	if (r->answered)
		p->out->stations[p->out->nstations++] = (uint8_t)r->station;
	if (r->identified && !p->out->identified && (r->station == p->out->found.station)) {
		p->out->identified = true;
		p->out->status = r->status;
	}
	{
		int found = p->out->found.station, stop;

		p->out->found.station = r->station;   /* the attempt names the station polled */
		stop = probe_report(p, DF1_PROBE_IDENTITY, "poll", r->answered ? 0 : r->error) < 0;
		p->out->found.station = found;
		return stop;
	}
}

/* Stage 3 at the settings found. */
static int probe_identify(struct probe *p)
{
	df1_t *h = p->h;
	struct df1_probe_result *o = p->out;
	int r;

	(void)df1_set_retries(h, 1, 1);
	(void)df1_set_timeout_ms(h, 2 * probe_window_ms(h, h->cfg.baud) + 200);
	if (h->cfg.duplex == DF1_FULL_DUPLEX) {
		r = df1_diag_status(h, 1, &o->status);
		o->identified = r >= 0;
		if (probe_report(p, DF1_PROBE_IDENTITY, "diagnostic status", r) < 0)
			return DF1_E_INTR;
		return probe_fatal(r) ? r : 0;
	}
	r = df1_discover(h, p->lo, p->hi, probe_on_station, p);
	if (r == DF1_E_INTR || h->err.code == DF1_E_INTR)
		return DF1_E_INTR;
	return probe_fatal(r) ? r : 0;
}

static void probe_found(struct probe *p)
{
	struct df1_line_settings *f = &p->out->found;
	const struct df1_config *c = &p->h->cfg;

	f->baud = c->baud;
	f->data_bits = c->data_bits;
	f->stop_bits = c->stop_bits;
	f->parity = c->parity;
	f->duplex = c->duplex;
	f->check = c->check;
	f->hd_bcc_stx = c->duplex == DF1_HALF_DUPLEX_MASTER && c->hd_bcc_stx;
}

int df1_probe_line(df1_t *h, int lo, int hi, df1_probe_fn fn, void *user,
                   struct df1_probe_result *out)
{
	struct df1_probe_result local;
	struct df1_config saved;
	struct probe p;
	int64_t t0 = df1_now_ms();
	int r = 0;

	if (!h)
		return DF1_E_INVAL;
	if (lo < 0 || hi > 254 || lo > hi)
		return df1_fail(h, DF1_E_INVAL, -1, "line probe: stations %d-%d (0-254)", lo, hi);
	if (!h->port)
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "handle is not open");
	if (h->own_link || !h->port->configure)
		return df1_fail(h, DF1_E_NOTSUP, -1, "line probe: %s has no serial settings to find "
		                "(a serial port or an rfc2217:// target has)", h->port_name);
	if (!out)
		out = &local;
	memset(out, 0, sizeof *out);
	p = (struct probe){ h, fn, user, out, lo, hi };
	saved = h->cfg;
	for (int par = 0; r == 0 && par < PROBE_NPAR; par++)
		for (int b = 0; r == 0 && b < PROBE_NBAUD; b++)
			r = probe_setting(&p, probe_bauds[b], probe_parities[par]);
	if (r > 0) {
		probe_found(&p);
		r = probe_identify(&p);
		if (r == 0)
			r = 1;
	}
	out->elapsed_ms = df1_now_ms() - t0;
	if (r <= 0) {
		struct df1_error_detail e = h->err;

		(void)df1_set_serial(h, saved.baud, saved.data_bits, saved.parity, saved.stop_bits);
		h->cfg = saved;
		h->err = e;
	} else {
		h->cfg.timeout_ms = saved.timeout_ms;
		h->cfg.poll_timeout_ms = saved.poll_timeout_ms;
		h->cfg.nak_retries = saved.nak_retries;
		h->cfg.enq_retries = saved.enq_retries;
	}
	return r;
}
