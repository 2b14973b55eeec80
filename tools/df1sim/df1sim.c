/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1sim - a simulated PLC: a DF1 half-duplex slave or full-duplex peer with a
 * data table and fault injection, served on a pseudo-terminal, a serial port
 * or TCP (doc/ARCHITECTURE.md 8, man/man1/df1sim.1). Options and transport set-up on
 * the library's data table (df1_table(3): files, --data, the processor of the
 * diagnostic status, the serving callbacks) and df1_serve(); the shared code
 * is tools/common/cli.h (cli_parse: the line options, df1sim's own as extra options;
 * signals) and tools/df1sim/sim_io.h (pty and TCP, --log, fault probabilities).
 *
 * With --eip it also answers PCCC over EtherNet/IP (df1_eip_server(3)) from
 * the same data table, on the same thread: the server's descriptor is watched
 * with the signal pipe through one epoll set, the link's cancel descriptor, so
 * an EtherNet/IP request cuts a link wait short and the link resumes after it.
 *
 * stdout: the device served, one line, once ready (then the EtherNet/IP
 * address as eip://ADDR:PORT; that line alone with --eip only). stderr: messages.
 * SIGUSR1 silences every station (no ACK, no reply, no answer to polls or
 * ENQs), SIGUSR2 makes them answer again (--silent still applies).
 * Exit status: 0 (stopped by SIGINT/SIGTERM), 1 (communication / system error),
 * 2 (usage or configuration error).
 */
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/epoll.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "df1.h"
#include "common/cli.h"
#include "df1sim/sim_io.h"
#include "df1sim/sim_line.h"   /* --line-settings, --listen rfc2217:// */
#include "df1sim/sim_options.h"

#define PROG "df1sim"

static void msg(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void msg(const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, "%s: ", PROG);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
}

/* ------------------------------------------------------------------------
 * The simulator
 * ------------------------------------------------------------------------ */

struct sim {
	struct df1_table *tables[256];  /* per served station */
	int stations[256];
	int nstations;
	enum df1_plc plc;
	bool half;
	int verbose;
	struct sim_cmdlog log;          /* --log */
	int silent_pm, silent_station;  /* --silent, put back by SIGUSR2 (0: none) */
	bool muted;                     /* SIGUSR1 applied: every station silent */
	df1_t *h;                       /* for df1_serve_pccc (PLC type, options) */
	df1_eip_server_t *eip;          /* --eip */
	int wait_fd;                    /* epoll of the signal pipe and the server, or -1 */
	/* --line-settings and --listen rfc2217:// (tools/df1sim/sim_line.c) */
	struct sim_uart line;           /* baud 0: none given */
	bool rfc2217;
	struct sim_ramps ramps;         /* --ramp (tools/df1sim/sim_ramp.c) */
	struct sim_msg msgs[SIM_MSG_MAX]; /* --msg (tools/df1sim/sim_msg.c) */
	int nmsgs;
};

static struct df1_table *sim_table_for(struct sim *s, int station)
{
	if (station >= 0 && station < 256 && s->tables[station])
		return s->tables[station];
	return s->tables[s->stations[0]];       /* full duplex: DST is not checked */
}

/* Each station its own table, served by the data table's own callbacks. */
static int sim_read(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes)
{
	struct sim *s = user;
	struct df1_table *t = sim_table_for(s, station);

	sim_ramp_apply(&s->ramps, s->tables, s->stations, s->nstations);
	return df1_table_server_ops(t)->read(t, station, a, buf, nbytes);
}

static int sim_write(void *user, int station, const struct df1_addr *a, const uint8_t *buf,
                     const uint8_t *mask, size_t nbytes)
{
	struct df1_table *t = sim_table_for(user, station);

	return df1_table_server_ops(t)->write(t, station, a, buf, mask, nbytes);
}

static int sim_change_mode(void *user, int station, int mode)
{
	struct df1_table *t = sim_table_for(user, station);

	return df1_table_server_ops(t)->change_mode(t, station, mode);
}

static int sim_diag_status(void *user, int station, uint8_t *buf, size_t cap)
{
	struct df1_table *t = sim_table_for(user, station);

	return df1_table_server_ops(t)->diag_status(t, station, buf, cap);
}

static const struct df1_server_ops sim_ops = {
	.read = sim_read,
	.write = sim_write,
	.diag_status = sim_diag_status,
	.change_mode = sim_change_mode,
};

/* ------------------------------------------------------------------------
 * EtherNet/IP (--eip): PCCC answered from the same tables
 * ------------------------------------------------------------------------ */

/* A simulated MicroLogix 1400 that says what it is: no vendor ID is ours to
 * claim (vendor 1 is Rockwell's), so 0; device type 0x0E, programmable
 * logic controller (ODVA Vol. 1 table 5-1.1); revision = libdf1's 0.4. */
static const struct df1_eip_identity sim_identity = {
	.vendor_id = 0,
	.device_type = 0x0E,
	.product_code = 0,
	.rev_major = 0,
	.rev_minor = 4,
	.status = 0,
	.serial = 0x0DF10001,
	.product_name = "libdf1 df1sim MicroLogix 1400",
};

/* CIP status of a station that does not answer: connection failure,
 * unconnected request timed out (what a bridge reports for a silent node). */
#define SIM_EIP_NO_ANSWER (0x01 | 0x0204 << 8)

static void sim_eip_pccc(void *user, df1_eip_server_t *srv, uint32_t request, int station,
                         const uint8_t *pccc, size_t n)
{
	struct sim *s = user;
	uint8_t reply[300], app[300];
	int r;

	if (station < 0)
		station = s->stations[0];
	if (s->muted || (station != s->stations[0] && !s->tables[station]) ||
	    (s->silent_pm && (s->silent_station == station || s->silent_station == DF1_SILENT_ALL))) {
		(void)df1_eip_server_fail(srv, request, SIM_EIP_NO_ANSWER);
		return;
	}
	r = df1_serve_pccc(s->h, &sim_ops, s, station, pccc, n, reply, sizeof reply);
	if (r > 0) {
		if (n + 2 <= sizeof app) {
			app[0] = (uint8_t)station;
			app[1] = (uint8_t)station;
			memcpy(app + 2, pccc, n);
			sim_cmdlog_command(&s->log, station, app, n + 2);
		}
		if (s->verbose)
			msg("eip: station %d: CMD %02X TNS %04X answered, STS %02X", station, pccc[0],
			    pccc[2] | pccc[3] << 8, reply[1]);
		(void)df1_eip_server_reply(srv, request, reply, (size_t)r);
	} else {
		(void)df1_eip_server_fail(srv, request, 0x03);     /* a reply, not a command */
	}
}

static void sim_eip_process(struct sim *s)
{
	if (s->eip)
		(void)df1_eip_server_process(s->eip);
}

/* -vv: the bytes; -vvv: also when the handle took or handed them, in seconds
 * of CLOCK_MONOTONIC (the clock of df1_set_trace(3)), to line them up with a
 * master's trace (bench/bench_poll.c --trace) */
static void hexdump(enum df1_dir dir, const uint8_t *b, size_t n, int verbose, uint64_t t_us)
{
	char line[64 + 3 * 256];
	int k = snprintf(line, sizeof line, "%s: %s", PROG, dir == DF1_DIR_TX ? "TX" : "RX");

	if (verbose >= 3)
		k += snprintf(line + k, sizeof line - (size_t)k, " @%llu.%06llu",
		              (unsigned long long)(t_us / 1000000), (unsigned long long)(t_us % 1000000));
	/* one write per chunk (stderr is unbuffered): a trace that costs little
	 * time changes the timing it shows little */
	for (size_t i = 0; i < n; i++) {
		if ((size_t)k + 5 > sizeof line) {
			fputs(line, stderr);
			k = 0;
		}
		k += snprintf(line + k, sizeof line - (size_t)k, " %02X", b[i]);
	}
	line[k++] = '\n';
	fwrite(line, 1, (size_t)k, stderr);
}

static void on_trace(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us)
{
	struct sim *s = user;

	if (s->verbose >= 2)
		hexdump(dir, bytes, n, s->verbose, t_us);
	sim_cmdlog_feed(&s->log, dir, bytes, n);
}

static void on_log(void *user, int catalog_id, enum df1_severity sev, const char *text)
{
	const struct df1_catalog_entry *e = df1_catalog_by_id(catalog_id);

	(void)user;
	(void)sev;
	if (e)
		fprintf(stderr, "%s: [%d] %s: %s\n", PROG, catalog_id, e->mnemonic, text);
	else
		fprintf(stderr, "%s: %s\n", PROG, text);
}

/* ------------------------------------------------------------------------
 * Serving
 * ------------------------------------------------------------------------ */

static int report(df1_t *h, const char *where, int err)
{
	const struct df1_error_detail *d = df1_last_error(h);
	int id = df1_error_catalog_id(err);

	if (id)
		msg("%s: [%d] %s: %s", where, id, df1_catalog_by_id(id) ? df1_catalog_by_id(id)->mnemonic : "",
		    d && d->message[0] ? d->message : df1_strerror(err));
	else
		msg("%s: %s: %s", where, df1_errname(err), d && d->message[0] ? d->message : df1_strerror(err));
	return CLI_EXIT_FAIL;
}

/* Empty the self-pipe and apply SIGUSR1 / SIGUSR2 if one came. A wait that a
 * mute signal cut short is simply resumed by the next df1_serve(): the link
 * keeps its state (with --line-baud a frame being paced out may be cut, which
 * the master sees as a broken frame and recovers from). */
static void sim_wakeup(df1_t *h, struct sim *s)
{
	bool mute;

	cli_signal_drain();
	mute = cli_mute != 0;
	if (mute == s->muted)
		return;
	if (mute)
		(void)df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, 1000, DF1_SILENT_ALL);
	else
		(void)df1_server_set_fault(h, DF1_FAULT_SILENT_STATION, s->silent_pm,
		                           s->silent_pm ? s->silent_station : -1);
	s->muted = mute;
	if (s->verbose)
		msg(mute ? "SIGUSR1: every station silent" : "SIGUSR2: stations answer again");
}

/* Serve an open handle until a signal (0), the peer leaves (DF1_E_CLOSED) or an error. */
static int serve_open(df1_t *h, struct sim *s)
{
	int r;

	while (!cli_stop && !s->log.error) {
		sim_wakeup(h, s);
		sim_eip_process(s);
		/* the MSGs that are due go out first, as the ladder's MSG blocks */
		r = s->nmsgs ? sim_msg_run(h, s->tables[s->stations[0]], s->msgs, s->nmsgs, s->log.fp, 1000)
		             : 1000;
		r = df1_serve(h, &sim_ops, s, r);
		if (r >= 0 || (r == DF1_E_INTR && !cli_stop))
			continue;
		if (r == DF1_E_INTR || cli_stop)
			return 0;
		return r;
	}
	return 0;
}

/* A TCP client on the handle: as it is, or an RFC 2217 client through the
 * relay (tools/df1sim/sim_line.c). 0 or DF1_E_* (cfd closed). */
static int sim_open_client(df1_t *h, struct sim *s, int cfd, struct sim_relay *relay)
{
	int r;

	memset(relay, 0, sizeof *relay);
	if (s->rfc2217)
		return sim_relay_open(h, relay, SIM_RELAY_RFC2217, cfd, &s->line, s->verbose);
	r = df1_open_fd(h, cfd, true);
	if (r < 0)
		close(cfd);
	return r;
}

static int serve_tcp(df1_t *h, struct sim *s, int lfd, const char *shown)
{
	struct sim_relay relay;

	for (;;) {
		struct pollfd pfd[3] = { { lfd, POLLIN, 0 }, { cli_signal_fd(), POLLIN, 0 },
		                         { s->eip ? df1_eip_server_fd(s->eip) : -1, POLLIN, 0 } };
		int cfd, r, one = 1;

		if (cli_stop || s->log.error)
			return 0;
		r = poll(pfd, 3, -1);
		if (r < 0) {
			if (errno == EINTR)
				continue;
			msg("%s: poll: %s", shown, strerror(errno));
			return CLI_EXIT_FAIL;
		}
		if (cli_stop)
			return 0;
		if (pfd[2].revents)
			sim_eip_process(s);
		if (pfd[1].revents) {
			sim_wakeup(h, s);       /* SIGUSR1 / SIGUSR2 */
			continue;
		}
		if (!(pfd[0].revents & POLLIN))
			continue;
		cfd = accept4(lfd, NULL, NULL, SOCK_CLOEXEC);
		if (cfd < 0) {
			if (errno == EINTR || errno == ECONNABORTED || errno == EAGAIN)
				continue;
			msg("%s: accept: %s", shown, strerror(errno));
			return CLI_EXIT_FAIL;
		}
		setsockopt(cfd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
		if (s->verbose)
			msg("%s: client connected", shown);
		r = sim_open_client(h, s, cfd, &relay);
		if (r < 0)
			return report(h, shown, r);
		r = serve_open(h, s);
		df1_close(h);
		sim_relay_join(&relay);
		if (r == DF1_E_CLOSED || (r < 0 && r != DF1_E_INTR)) {
			/* the client went away (or broke the connection): wait for the next */
			if (s->verbose)
				msg("%s: client disconnected (%s)", shown, df1_strerror(r));
			continue;
		}
		return 0;
	}
}

/* --eip only: the server and the signals until a stop signal. */
static int serve_eip_only(df1_t *h, struct sim *s)
{
	while (!cli_stop && !s->log.error) {
		struct pollfd pfd[2] = { { df1_eip_server_fd(s->eip), POLLIN, 0 }, { cli_signal_fd(), POLLIN, 0 } };

		if (poll(pfd, 2, -1) < 0 && errno != EINTR) {
			msg("poll: %s", strerror(errno));
			return CLI_EXIT_FAIL;
		}
		if (pfd[1].revents)
			sim_wakeup(h, s);
		if (pfd[0].revents)
			sim_eip_process(s);
	}
	return 0;
}

/* Each connection an --eip limit closed (df1sim(1) --eip-idle-timeout). */
static void sim_eip_closed(void *user, const char *peer, enum df1_eip_close_reason why)
{
	(void)user;
	msg("eip: closed %s: %s", peer, why == DF1_EIP_CLOSE_NO_SESSION ? "no RegisterSession in time"
	                                : why == DF1_EIP_CLOSE_IDLE ? "session idle past --eip-idle-timeout"
	                                : "the longest idle of a full table, for a new client");
}

/* The EtherNet/IP server of --eip [tcp://]ADDR, and the one descriptor the
 * link waits on: the signal pipe and the server's. Prints nothing yet. */
static int sim_eip_open(struct sim *s, const struct sim_opts *o, df1_t *h)
{
	struct df1_eip_server_config c;
	struct df1_eip_server_limits lim = { 0 };
	struct epoll_event ev;
	const char *a;
	int r;

	const char *spec = o->eip;

	memset(&c, 0, sizeof c);
	c.listen = strncmp(spec, "tcp://", 6) == 0 ? spec + 6 : spec;
	cli_eip_server_config(&o->eip_opts, &c, &lim);
	c.identity = sim_identity;
	r = df1_eip_server_new(&s->eip, &c, sim_eip_pccc, s);
	if (r < 0) {
		msg("--eip %s: %s", spec, df1_eip_server_error(NULL));
		return r == DF1_E_INVAL ? CLI_EXIT_USAGE : CLI_EXIT_FAIL;
	}
	lim.on_close = sim_eip_closed;
	if (df1_eip_server_set_limits(s->eip, &lim) < 0) {
		msg("--eip: %s", df1_eip_server_error(s->eip));
		return CLI_EXIT_USAGE;
	}
	a = df1_eip_server_address(s->eip);
	if (strncmp(a, "0.0.0.0:", 8) == 0 || strncmp(a, "[::]:", 5) == 0)
		msg("EtherNet/IP on %s: every interface, reachable from other hosts", a);
	else if (strncmp(a, "127.", 4) != 0 && strncmp(a, "[::1]:", 6) != 0)
		msg("EtherNet/IP on %s: not loopback, reachable from other hosts", a);
	s->wait_fd = epoll_create1(EPOLL_CLOEXEC);
	if (s->wait_fd < 0) {
		msg("epoll: %s", strerror(errno));
		return CLI_EXIT_FAIL;
	}
	memset(&ev, 0, sizeof ev);
	ev.events = EPOLLIN;
	if (epoll_ctl(s->wait_fd, EPOLL_CTL_ADD, cli_signal_fd(), &ev) != 0 ||
	    epoll_ctl(s->wait_fd, EPOLL_CTL_ADD, df1_eip_server_fd(s->eip), &ev) != 0) {
		msg("epoll: %s", strerror(errno));
		return CLI_EXIT_FAIL;
	}
	df1_set_cancel_fd(h, s->wait_fd);
	return 0;
}

/* --line-baud in full duplex on a pty: the line's relay is a full-duplex UART
 * (tools/df1sim/sim_pace.c), each direction paced on its own, and the handle runs
 * unpaced. Half duplex (one talker at a time), -d and --listen keep the
 * library's pacing (df1_set_line_baud), which is one thread for both directions. */
static bool sim_full_duplex_uart(const struct sim_opts *o)
{
	return o->line_baud > 0 && !o->cli.half_duplex && o->pty;
}

static int setup_handle(df1_t *h, const struct sim_opts *o, struct sim *s)
{
	int r = 0;

	r = r < 0 ? r : df1_set_duplex(h, o->cli.radio ? DF1_RADIO_MODEM
	                                  : o->cli.half_duplex ? DF1_HALF_DUPLEX_SLAVE : DF1_FULL_DUPLEX);
	if (r >= 0 && o->cli.have_forward)
		r = df1_set_forward(h, o->cli.forward); /* a radio relay (libdf1(7) RADIO MODEM) */
	r = r < 0 ? r : df1_set_check(h, o->cli.check);
	r = r < 0 ? r : df1_set_plc(h, o->cli.plc);
	r = r < 0 ? r : df1_set_station(h, o->stations[0]);
	r = r < 0 ? r : df1_set_cmd_timeout_ms(h, o->cli.cmd_timeout_ms); /* a MSG's timeout */
	for (int i = 0; r >= 0 && i < o->nstations; i++)
		r = df1_server_add_station(h, o->stations[i]);
	if (r >= 0 && o->device)
		r = df1_set_serial(h, o->baud, o->data_bits, o->cli.parity, o->cli.stop_bits);
	for (int k = 0; r >= 0 && k < 8; k++)
		if (o->faults[k].given)
			r = df1_server_set_fault(h, o->faults[k].kind, o->faults[k].per_mille, o->faults[k].value);
	if (r >= 0 && o->line_baud && !sim_full_duplex_uart(o))
		r = df1_set_line_baud(h, o->line_baud);
	if (r >= 0 && o->scan_time)
		r = df1_set_option(h, DF1_OPT_SCAN_TIME_MS, o->scan_time);
	if (r >= 0 && o->no_eot)
		r = df1_set_option(h, DF1_OPT_NO_EOT, 1);
	if (r >= 0 && o->plc5_refuse_large)
		r = df1_set_option(h, DF1_OPT_PLC5_REFUSE_LARGE, 1);
	if (r >= 0)
		r = df1_server_set_max_queue(h, o->max_queue);
	if (r >= 0 && o->nmsgs) {
		/* our MSGs wait for their replies while the master's commands are answered */
		memcpy(s->msgs, o->msgs, sizeof s->msgs);
		s->nmsgs = o->nmsgs;
		r = df1_set_responder(h, &sim_ops, s);
	}
	if (r < 0) {
		const struct df1_error_detail *d = df1_last_error(h);

		msg("invalid setting: %s", d && d->message[0] ? d->message : df1_strerror(r));
		return CLI_EXIT_USAGE;
	}
	if (cli_apply_lib_options(&o->cli, h) != 0)
		return CLI_EXIT_USAGE;
	df1_server_set_seed(h, o->seed);
	if (o->cli.verbose)
		df1_set_log(h, on_log, s);
	if (o->cli.verbose >= 2 || s->log.fp)
		df1_set_trace(h, on_trace, s);
	return 0;
}

static void sim_free(struct sim *s)
{
	df1_eip_server_free(s->eip);
	if (s->wait_fd >= 0)
		close(s->wait_fd);
	for (int i = 0; i < 256; i++)
		df1_table_free(s->tables[i]);
	sim_cmdlog_close(&s->log);
}

static int sim_build(struct sim *s, const struct sim_opts *o)
{
	struct df1_table *tmpl = NULL;
	int r;

	memset(s, 0, sizeof *s);
	s->wait_fd = -1;
	s->plc = o->cli.plc;
	s->half = o->cli.half_duplex;
	s->verbose = o->cli.verbose;
	s->line = o->line;
	s->rfc2217 = o->rfc2217;
	s->nstations = o->nstations;
	memcpy(s->stations, o->stations, sizeof s->stations);
	if (o->faults[DF1_FAULT_SILENT_STATION].given) {
		s->silent_pm = o->faults[DF1_FAULT_SILENT_STATION].per_mille;
		s->silent_station = o->faults[DF1_FAULT_SILENT_STATION].value;
	}
	if (df1_table_new(&tmpl, o->cli.plc) < 0 || df1_table_add_default_files(tmpl) < 0) {
		df1_table_free(tmpl);
		msg("out of memory");
		return CLI_EXIT_FAIL;
	}
	s->tables[s->stations[0]] = tmpl;       /* sim_free() frees it from here on */
	/* --eip simulates a MicroLogix 1400 (its identity): its diagnostic status
	 * too, unless --processor or a --plc other than the default says otherwise */
	if (o->eip && !o->processor && o->cli.plc == DF1_PLC_SLC &&
	    df1_table_set_processor(tmpl, "ml1400") < 0) {
		msg("out of memory");
		return CLI_EXIT_FAIL;
	}
	if (o->processor && df1_table_set_processor(tmpl, o->processor) < 0) {
		cli_usage_error(&o->cli, "--processor: unknown processor '%s' (e.g. slc5/04, ml1400, plc5/40, 0x5B)",
		            o->processor);
		return CLI_EXIT_USAGE;
	}
	if (o->data && df1_table_load(tmpl, o->data) < 0) {
		msg("%s", df1_table_error_text(tmpl));
		return CLI_EXIT_USAGE;
	}
	s->ramps = o->ramps;
	if (s->ramps.n) {
		char err[200];
		if (sim_ramp_start(&s->ramps, o->cli.plc, tmpl, err, sizeof err) < 0) {
			cli_usage_error(&o->cli, "%s", err);
			return CLI_EXIT_USAGE;
		}
	}
	for (int i = 1; i < s->nstations; i++) {
		if (df1_table_clone(&s->tables[s->stations[i]], tmpl) < 0) {
			msg("out of memory");
			return CLI_EXIT_FAIL;
		}
	}
	if (o->log) {
		r = sim_cmdlog_open(&s->log, o->log, o->cli.check, o->cli.half_duplex,
		                     o->cli.half_duplex || o->cli.radio, s->tables, s->stations[0]);
		s->log.plc = o->cli.plc;
		if (r == -1) {
			msg("--log %s: %s", o->log, strerror(errno));
			return CLI_EXIT_USAGE;
		}
		if (r < 0) {
			msg("out of memory");
			return CLI_EXIT_FAIL;
		}
		/* the log reads the frames as the responder does (--hd-bcc stx ...) */
		cli_decoder_options(&o->cli, s->log.dec[0]);
		cli_decoder_options(&o->cli, s->log.dec[1]);
	}
	return 0;
}

/* The handle: its settings, the signals (its cancel descriptor), --eip's
 * server. *hp is set once made, for main to free. 0 or an exit status. */
static int sim_start(struct sim *s, const struct sim_opts *o, df1_t **hp)
{
	df1_t *h;
	int status, r;

	r = df1_new(hp);
	if (r < 0) {
		msg("%s", df1_strerror(r));
		return CLI_EXIT_FAIL;
	}
	h = *hp;
	status = setup_handle(h, o, s);
	if (status)
		return status;
	if (cli_signals_install_mute() < 0) {
		msg("pipe: %s", strerror(errno));
		return CLI_EXIT_FAIL;
	}
	df1_set_cancel_fd(h, cli_signal_fd());
	s->h = h;
	if (o->eip)
		return sim_eip_open(s, o, h);
	return 0;
}

static struct sim_relay sim_pty_relay;

/* The pty on the handle: as it is, or with --line-settings through the line's
 * relay (tools/df1sim/sim_line.c), which reads the master's termios and
 * then owns the master descriptor. */
static int sim_open_pty(df1_t *h, const struct sim_opts *o, struct sim_pty *pty)
{
	int master = pty->master;

	if (!o->line.baud && !sim_full_duplex_uart(o))
		return df1_open_fd(h, master, true);
	if (sim_full_duplex_uart(o))    /* 8N1: 10 bits a character, as the library counts them */
		sim_pty_relay.char_us = (int64_t)10 * 1000000 / o->line_baud;
	pty->master = -1;
	return sim_relay_open(h, &sim_pty_relay, SIM_RELAY_PTY, master, &o->line, o->cli.verbose);
}

/* Where the link is served: the pty (--pty), the device or the TCP listener
 * (--listen: its socket in *lfd); its name for the messages and the ready line
 * in shown. Nothing with --eip alone. 0 or an exit status. */
static int sim_open_where(df1_t *h, const struct sim_opts *o, struct sim_pty *pty, char *shown, size_t cap,
                          int *lfd)
{
	char err[600];
	int status, r;

	if (o->pty) {
		status = sim_pty_create(pty, o->pty, err, sizeof err);
		if (status) {
			msg("%s", err);
			return status;
		}
		r = sim_open_pty(h, o, pty);
		if (r < 0)
			return report(h, o->pty, r);
		pty->master = -1;       /* the handle (or the line's relay) owns it now */
		snprintf(shown, cap, "%s", o->pty);
	} else if (o->device) {
		r = df1_open(h, o->device);
		if (r < 0)
			return report(h, o->device, r);
		snprintf(shown, cap, "%s", o->device);
	} else if (o->listen) {
		enum sim_listen_scope scope;

		*lfd = sim_listen_open(o->listen, shown, cap, &scope, err, sizeof err);
		if (*lfd < 0) {
			msg("%s", err);
			return -*lfd;
		}
		if (o->rfc2217 && strncmp(shown, "tcp://", 6) == 0) { /* the ready line names the scheme */
			memmove(shown + 10, shown + 6, strlen(shown + 6) + 1);
			memcpy(shown, "rfc2217://", 10);
		}
		/* a listener other hosts can reach is what the user asked for: say so */
		if (scope == SIM_LISTEN_ALL)
			msg("listening on %s: every interface, reachable from other hosts", shown);
		else if (scope == SIM_LISTEN_OTHER)
			msg("listening on %s: not loopback, reachable from other hosts", shown);
	}
	return 0;
}

/* Serve until a stop signal (or the end of the device's input): the TCP
 * listener's clients, --eip alone, or the open link. The exit status. */
static int sim_serve(df1_t *h, struct sim *s, const struct sim_opts *o, int lfd, const char *shown)
{
	int status, r;

	if (lfd >= 0) {
		status = serve_tcp(h, s, lfd, shown);
	} else if (!o->where) {
		status = serve_eip_only(h, s);
	} else {
		r = serve_open(h, s);
		status = r < 0 ? report(h, shown, r) : 0;
	}
	if (s->log.error) {
		msg("--log %s: a command could not be logged: %s", o->log, strerror(s->log.error));
		status = CLI_EXIT_FAIL;
	} else if (status == 0 && cli_stop && o->cli.verbose) {
		msg("stopped by signal");
	}
	return status;
}

int main(int argc, char **argv)
{
	static struct sim sim;
	struct sim_opts o;
	struct sim_pty pty = { -1, -1, "", NULL, false };
	char shown[300];
	df1_t *h = NULL;
	int status, lfd = -1;

	status = sim_options_parse(argc, argv, &o);
	if (status != CLI_CONTINUE)
		return status;
	/* a closed stdout: the device line could not be printed, and the next file
	 * opened (the pty, a data file) would become descriptor 1 */
	if (fcntl(STDOUT_FILENO, F_GETFD) < 0) {
		msg("stdout is closed: df1sim prints the device it serves there");
		return CLI_EXIT_FAIL;
	}
	/* --line-baud paces to the microsecond: the kernel's default timer slack
	 * (50 us) would make each frame's last chunk late, and every turnaround
	 * after it (bench/README.md) */
	if (o.line_baud)
		prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0);
	status = sim_build(&sim, &o);
	if (!status)
		status = sim_start(&sim, &o, &h);
	if (!status)
		status = sim_open_where(h, &o, &pty, shown, sizeof shown, &lfd);
	if (status)
		goto out;
	/* the ready line a script waits for: one that cannot be written is an error */
	errno = 0;
	if ((o.where && printf("%s\n", shown) < 0) ||
	    (sim.eip && printf("eip://%s\n", df1_eip_server_address(sim.eip)) < 0) || fflush(stdout) != 0) {
		msg("stdout: the device line could not be written: %s", strerror(errno ? errno : EIO));
		status = CLI_EXIT_FAIL;
		goto out;
	}
	status = sim_serve(h, &sim, &o, lfd, shown);
out:
	if (h) {
		df1_close(h);
		df1_free(h);
	}
	sim_relay_join(&sim_pty_relay);
	if (lfd >= 0)
		close(lfd);
	if (pty.master >= 0)
		close(pty.master);
	sim_pty_destroy(&pty);
	sim_free(&sim);
	return status;
}
