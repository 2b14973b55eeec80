/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1gw - a gateway daemon: one DF1 line's tags (a mapping CSV, polled by the
 * poll engine) kept in an MQTT broker as retained JSON, and writes taken back
 * from <prefix>/tag/<name>/set (doc/ARCHITECTURE.md 11; df1gw(1)). What the messages
 * hold is the payload formats' (gw_format.h); gw_pub.c says when.
 *
 * One loop, no threads: poll() on the signal self-pipe (stop), a signalfd
 * (SIGHUP: reload), the broker's socket (gw_mqtt.c) and the poll engine's
 * wake descriptor, with the timeout of whatever is due next (df1_poll_next_ms,
 * keepalive, reconnect, reopen, --refresh); due line work runs with
 * df1_poll(h, 0). The EtherNet/IP side (--eip, gw_eip.c) is one more
 * descriptor; its requests join the poll engine's queue. With --eip, --map
 * and --mqtt are optional: without a broker df1gw is a pure bridge.
 *
 * The line: a handle configured once from the options (cli_configure) with
 * the tags loaded; opened, closed when it is lost (tags BAD "line_lost") and
 * opened again with a backoff, keeping its tags and their last values. A
 * reload builds a new handle from the new mapping file and replaces the old
 * one (the public API has no way to remove a tag), so the line is closed and
 * opened again once; the broker connection stays.
 */
#include <errno.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include "df1gw/gw.h"

#define LINE_BACKOFF_MIN 500
#define LINE_BACKOFF_MAX 30000
#define ONCE_CONNECT_MS 10000        /* --once: the broker must answer within this */
#define FLUSH_MS 2000                /* at exit: what is queued for the broker */
#define GW_FORMATS_DEFAULT "json"    /* the payload formats enabled (gw_format.h), a comma list */

/* ---- configuration ---- */

/* A tag name is one topic level: UTF-8 without '/', '+' or '#'. */
static bool topic_level_ok(const char *s)
{
	return *s && !strpbrk(s, "/+#") && gw_utf8_valid(s, strlen(s));
}

struct map_check {
	const char *path;
	int issues;
};

static void map_issue(void *user, const struct df1_config_issue *is)
{
	struct map_check *m = user;
	const struct df1_catalog_entry *e = is->catalog_id ? df1_catalog_by_id(is->catalog_id) : NULL;

	m->issues++;
	fprintf(stderr, "%s: %s: ", GW_PROG, m->path);
	if (is->line > 0)
		fprintf(stderr, "line %d: ", is->line);
	if (e)
		fprintf(stderr, "[%d] %s: %s\n", e->id, e->mnemonic, is->text);
	else
		fprintf(stderr, "%s\n", is->text);
}

#define LINE_TICK_MS 20               /* the broker and the bridge served this often while the line works */

/* Every byte the line sends or takes (df1_set_trace): a transaction on a slow
 * line lasts long, a scan or a batch of writes many of them, and all run
 * inside df1_poll(); the broker is served meanwhile (its keepalive, the
 * PUBACKs that let it send the next /set), not only between two calls, and so
 * is the EtherNet/IP bridge: a client connects, registers its session and
 * sends its request while a batch is on the line, and the request joins the
 * line's queue at the bridge's turn (gw_line_turns), behind that batch, not
 * one df1_poll() per round trip later. */
static void line_tick(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us)
{
	static int64_t last;
	struct gw *g = user;
	int64_t now = gw_now_ms();

	if (g->cli.verbose >= 3 && !g->cli.quiet)
		cli_trace(&g->cli, dir, bytes, n, t_us);
	if (now - last < LINE_TICK_MS)
		return;
	last = now;
	if (g->mq_configured)
		gw_mqtt_turn(&g->mq, now);
	if (g->in_line_work && g->eip.s && g->eip.h == g->h) {
		gw_eip_process(&g->eip);
		gw_line_turns(g, now, true);
	}
}

/* The Receive rows (read once: a reload keeps them) and their table on h;
 * n polled tags. 0 or the exit status, having said why. */
static int line_receive(struct gw *g, df1_t *h, int n)
{
	int r = g->rx.t ? 0 : gw_rx_load(g, h);

	if (r)
		return r;
	if (n == 0 && !g->rx.n) {
		fprintf(stderr, "%s: %s: no tags\n", GW_PROG, g->map_path);
		return CLI_EXIT_USAGE;
	}
	if (g->cli.half_slave && n > 0) {
		fprintf(stderr, "%s: %s: %d Read/Write rows: a half-duplex slave station (--duplex half-slave, "
		        "Mode Slave) polls nothing and only serves its Receive rows\n", GW_PROG, g->map_path, n);
		return CLI_EXIT_USAGE;
	}
	if (g->cli.half_slave && g->eip.listen) {
		fprintf(stderr, "%s: --eip bridges to a line df1gw is the master of; a slave station "
		        "(--duplex half-slave, Mode Slave) sends nothing of its own\n", GW_PROG);
		return CLI_EXIT_USAGE;
	}
	if (g->once && n == 0) {
		fprintf(stderr, "%s: --once ends after the first scan: it needs Read rows (Receive rows "
		        "wait for the PLCs)\n", GW_PROG);
		return CLI_EXIT_USAGE;
	}
	if ((r = gw_rx_attach(g, h)) < 0) {
		fprintf(stderr, "%s: Receive rows: %s\n", GW_PROG, df1_strerror(r));
		return CLI_EXIT_FAIL;
	}
	return 0;
}

/* A configured handle with the mapping file's tags (strict: any bad row is an
 * error). Returns 0 or the exit status, having said why. */
static int line_build(struct gw *g, df1_t **out)
{
	struct map_check m = { g->map_path, 0 };
	df1_t *h;
	int r, n;

	*out = NULL;
	r = cli_configure(&g->cli, &h);
	if (r != CLI_EXIT_OK)
		return r;
	/* -v is the broker side; -vv adds the link's events, -vvv every frame */
	if (g->cli.verbose < 2)
		df1_set_log(h, NULL, NULL);
	/* the line's bytes tick the broker (line_tick); -vvv prints them too */
	df1_set_trace(h, line_tick, g);
	if (df1_poll_fd(h) < 0) {       /* the engine, for --eip's requests before any tag */
		fprintf(stderr, "%s: out of memory\n", GW_PROG);
		df1_free(h);
		return CLI_EXIT_FAIL;
	}
	if (!g->map_path && g->cli.half_slave) {
		fprintf(stderr, "%s: a slave station (--duplex half-slave, Mode Slave) serves the Receive rows "
		        "of --map\n", GW_PROG);
		df1_free(h);
		return CLI_EXIT_USAGE;
	}
	if (!g->map_path) {             /* --eip alone: a pure bridge */
		*out = h;
		return 0;
	}
	n = df1_tag_load_map(h, g->map_path, true, map_issue, &m);
	if (n < 0) {
		if (!m.issues) {
			const struct df1_error_detail *d = df1_last_error(h);
			char tag[64];

			cli_error_tag(n, df1_error_catalog_id(n), tag, sizeof tag);
			fprintf(stderr, "%s: %s: %s: %s\n", GW_PROG, g->map_path, tag,
			        d && d->message[0] ? d->message : df1_strerror(n));
		}
		df1_free(h);
		return CLI_EXIT_USAGE;
	}
	if ((r = line_receive(g, h, n)) != 0) {
		df1_free(h);
		return r;
	}
	for (int id = 0; id < n; id++) {
		struct df1_tag_state st;

		if (df1_tag_get(h, id, &st) == 0 && !topic_level_ok(st.config->name)) {
			fprintf(stderr, "%s: %s: tag \"%s\": a name cannot hold '/', '+' or '#' and must be "
			        "UTF-8 (it is one level of the topic PREFIX/tag/NAME)\n", GW_PROG, g->map_path, st.config->name);
			df1_free(h);
			return CLI_EXIT_USAGE;
		}
	}
	if (g->watchdog_ms >= 0 && (r = df1_poll_set_watchdog(h, g->watchdog_ms, 0)) < 0) {
		fprintf(stderr, "%s: --watchdog: %s\n", GW_PROG, df1_strerror(r));
		df1_free(h);
		return CLI_EXIT_USAGE;
	}
	*out = h;
	return 0;
}

/* Take handle h as the line: tag ids, stations, publication entries (tags no
 * longer there are cleared from the broker; changed ones published anew). */
static int line_adopt(struct gw *g, df1_t *h)
{
	int n = df1_tag_count(h);
	unsigned char *dirty = calloc((size_t)n, 1);
	int *pub_of = calloc((size_t)n, sizeof *pub_of);

	if (!dirty || !pub_of) {
		free(dirty);
		free(pub_of);
		return -1;
	}
	for (size_t i = 0; i < g->pubs.n; i++)
		g->pubs.v[i].live = strncmp(g->pubs.v[i].name, "tag/", 4) != 0;
	memset(g->stations, 0, sizeof g->stations);
	for (int id = 0; id < n; id++) {
		struct df1_tag_state st;
		struct gw_pub *e;
		char name[80], conf[256];

		df1_tag_get(h, id, &st);
		snprintf(name, sizeof name, "tag/%s", st.config->name);
		gw_tag_config_text(st.config, conf, sizeof conf);
		e = gw_pubs_get(&g->pubs, name, true);
		if (!e) {
			free(dirty);
			free(pub_of);
			return -1;
		}
		if (e->config && strcmp(e->config, conf) != 0)
			gw_pub_forget(e);               /* changed: published at its first read */
		gw_pub_set(&e->config, conf);
		e->live = true;
		if (st.config->station >= 0 && st.config->station < 255)
			g->stations[st.config->station] = true;
	}
	/* tags removed: their retained topics go */
	for (size_t i = 0; i < g->pubs.n;) {
		if (!g->pubs.v[i].live) {
			gw_publish_gone(g, &g->pubs.v[i]);
			gw_pubs_remove(&g->pubs, &g->pubs.v[i]);
			continue;
		}
		i++;
	}
	for (int id = 0; id < n; id++) {
		struct df1_tag_state st;
		char name[80];

		df1_tag_get(h, id, &st);
		snprintf(name, sizeof name, "tag/%s", st.config->name);
		pub_of[id] = (int)(gw_pubs_get(&g->pubs, name, false) - g->pubs.v);
	}
	free(g->dirty);
	free(g->pub_of);
	g->h = h;
	g->dirty = dirty;
	g->pub_of = pub_of;
	g->ntags = n;
	g->generation++;        /* Sparkplug: new births */
	df1_set_tag_callback(h, gw_on_tag, g);
	return 0;
}

/* ---- the line ---- */

static void line_error_set(struct gw *g, int err)
{
	char tag[96];
	const struct df1_error_detail *d = df1_last_error(g->h);

	cli_error_tag(err, df1_error_catalog_id(err), tag, sizeof tag);
	snprintf(g->line_error, sizeof g->line_error, "%s: %s: %s", g->cli.device, tag,
	         d && d->code == err && d->message[0] ? d->message : df1_strerror(err));
}

static int line_open(struct gw *g)
{
	int r = df1_open(g->h, g->cli.device);

	if (r < 0) {
		char before[sizeof g->line_error];
		bool news;

		/* said once per new reason, not at every try */
		memcpy(before, g->line_error, sizeof before);
		if (!before[0])
			g->line_down_ms = gw_now_ms();
		line_error_set(g, r);
		news = strcmp(before, g->line_error) != 0;
		if (news && !g->cli.quiet)
			fprintf(stderr, "%s: %s; trying again\n", GW_PROG, g->line_error);
		g->line_next_try_ms = gw_now_ms() + g->line_backoff_ms;
		g->line_backoff_ms = g->line_backoff_ms * 2 > LINE_BACKOFF_MAX ? LINE_BACKOFF_MAX
		                                                              : g->line_backoff_ms * 2;
		return r;
	}
	if (g->line_error[0] && !g->cli.quiet)        /* the recovery of what was said */
		fprintf(stderr, "%s: %s: open%s after %lld s\n", GW_PROG, g->cli.device, g->line_ever_up ? " again" : "",
		        (long long)((gw_now_ms() - g->line_down_ms + 500) / 1000));
	else if (g->line_ever_up && !g->cli.quiet)
		fprintf(stderr, "%s: %s: open again\n", GW_PROG, g->cli.device);
	g->line_up = true;
	g->line_ever_up = true;
	g->line_opened_ms = gw_now_ms();
	g->line_error[0] = '\0';
	g->line_backoff_ms = LINE_BACKOFF_MIN;
	g->republish = true;
	gw_eip_identify(&g->eip, g->h);        /* the controller's type in ListIdentity */
	return 0;
}

static void line_lost(struct gw *g, int err)
{
	line_error_set(g, err);
	g->line_down_ms = gw_now_ms();
	if (!g->cli.quiet)
		fprintf(stderr, "%s: %s: line lost; reopening\n", GW_PROG, g->line_error);
	gw_writes_drop(g);      /* the writes waiting: answered "not written", not kept for later */
	gw_eip_drop(&g->eip);   /* and the bridged requests waiting for their turn: STS 30h */
	df1_close(g->h);        /* the port's settings restored; tags kept */
	/* and those already handed to the poll engine (at most --duty-cycle,
	 * and bridged EtherNet/IP requests): ended "not written" now, never
	 * written late after the reopen */
	df1_poll_cancel_queued(g->h);
	g->line_up = false;
	g->line_next_try_ms = gw_now_ms() + g->line_backoff_ms;
	g->republish = true;
}

/* A station's last error that means the port itself is gone. */
static int line_gone(struct gw *g)
{
	if (!df1_is_open(g->h))
		return DF1_E_NOT_OPEN;
	if (g->eip.line_gone) {
		int r = g->eip.line_gone;

		g->eip.line_gone = 0;
		return r;
	}
	for (int stn = 0; stn < 255; stn++) {
		struct df1_station_health sh;

		/* only attempts on this opening: an offline station keeps the old error */
		if (g->stations[stn] && df1_station_health(g->h, stn, &sh) == 0 &&
		    (sh.last_error == DF1_E_CLOSED || sh.last_error == DF1_E_NODEV) &&
		    sh.state != DF1_STATION_OK && sh.last_attempt_ms >= g->line_opened_ms)
			return sh.last_error;
	}
	return 0;
}

static void line_work(struct gw *g)
{
	int r;

	g->in_line_work = true;
	r = df1_poll(g->h, 0);
	g->in_line_work = false;

	if (r == DF1_E_INTR)
		return;         /* a signal: the loop looks at it */
	if (r < 0) {
		line_lost(g, r);
		return;
	}
	if ((r = line_gone(g)) != 0)
		line_lost(g, r);
}

/* The Receive table's side of the line between two polls (the only side of
 * a slave station). */
static void line_serve(struct gw *g, bool readable)
{
	int r = gw_rx_serve(g, readable);

	if (r < 0 && r != DF1_E_INTR)
		line_lost(g, r);
}

/* SIGHUP: the mapping file again. A bad file is reported and the old one kept. */
static void reload(struct gw *g)
{
	df1_t *nh, *old = g->h;

	if (!g->map_path) {
		if (!g->cli.quiet)
			fprintf(stderr, "%s: SIGHUP: no --map to reload\n", GW_PROG);
		return;
	}
	if (!g->cli.quiet)
		fprintf(stderr, "%s: SIGHUP: reloading %s\n", GW_PROG, g->map_path);
	if (line_build(g, &nh) != 0) {
		if (!g->cli.quiet)
			fprintf(stderr, "%s: %s: not reloaded, the tags stay as they were\n", GW_PROG, g->map_path);
		return;
	}
	snprintf(g->line_error, sizeof g->line_error, "%s: SIGHUP: the mapping file reloaded", g->cli.device);
	gw_writes_drop(g);      /* their tag ids are the old handle's */
	g->line_error[0] = '\0';
	g->h = NULL;
	df1_free(old);          /* its queued writes end (results published); the port is restored */
	if (line_adopt(g, nh) < 0) {
		fprintf(stderr, "%s: out of memory\n", GW_PROG);
		exit(CLI_EXIT_FAIL);
	}
	g->line_up = false;
	g->line_backoff_ms = LINE_BACKOFF_MIN;
	line_open(g);
	g->republish = false;   /* only what changed: kept tags keep their topics */
	for (int id = 0; id < g->ntags; id++)
		g->dirty[id] = 1;
	gw_publish_changes(g, false);
}

/* The payload formats, each under the prefix; the broker's client with the
 * first format's last will (none with --once). 0 or the exit status. */
static int broker_setup(struct gw *g)
{
	const struct gw_url *url = &g->url;
	struct gw_mqtt_config mc = {
		.prog = GW_PROG, .url = g->mqtt_url, .host = url->host, .port = url->port, .tls = url->tls,
		.cafile = g->cafile, .cert = g->cert, .key = g->keyfile, .client_id = g->client_id,
		.username = g->username, .password = g->password, .keepalive = g->keepalive_s,
		.qos = g->qos, .will_topic = NULL, .verbose = g->cli.verbose, .quiet = g->cli.quiet,
	};
	struct gw_mqtt_events ev = { g, gw_on_connected, g->once ? NULL : gw_on_message,
	                             g->once ? NULL : gw_on_connecting, NULL, NULL };
	bool will_per_connect = false;
	char err[256];

	ev.acked = gw_sfwd_acked;       /* store and forward: PUBACKs, a lost connection */
	ev.lost = gw_sfwd_lost;

	if ((!g->json_off && gw_fmts_enable_list(&g->fmts, GW_FORMATS_DEFAULT, g->prefix, err, sizeof err) < 0) ||
	    (g->spb.group && gw_fmts_enable_conf(&g->fmts, "sparkplug", g->prefix, &g->spb, err, sizeof err) < 0)) {
		fprintf(stderr, "%s: %s\n", GW_PROG, err);
		return CLI_EXIT_USAGE;
	}
	/* Sparkplug's NDEATH is the will (a new one per connect, gw_on_connecting) */
	for (int i = 0; i < g->fmts.n; i++)
		will_per_connect = will_per_connect || g->fmts.v[i].ops->will_next;
	gw_bdseq_load(g);
	for (int i = 0; i < g->fmts.n && !g->once && !mc.will_topic && !will_per_connect; i++) {
		const struct gw_fmt *f = &g->fmts.v[i];

		if (f->ops->will(f, &g->will) == 0) {
			mc.will_topic = g->will.topic;
			mc.will_payload = g->will.body.p;
			mc.will_len = g->will.body.len;
			mc.will_retain = g->will.retain;
		}
	}
	if (gw_mqtt_init(&g->mq, &mc, &ev, err, sizeof err) < 0) {
		fprintf(stderr, "%s: --mqtt %s: %s\n", GW_PROG, g->mqtt_url, err);
		return CLI_EXIT_USAGE;
	}
	g->mq_configured = true;
	return 0;
}

int gw_setup(struct gw *g, int argc, char **argv)
{
	int r;

	g->eip.station = -1;
	g->health.notify.fd = -1;
	gw_pubs_init(&g->pubs);
	gw_msg_init(&g->msg);
	gw_msg_init(&g->will);
	gw_buf_init(&g->key);
	r = gw_options_parse(g, argc, argv);
	if (r != CLI_CONTINUE)
		return r;
	if (cli_signals_install() < 0) {
		fprintf(stderr, "%s: signals: %s\n", GW_PROG, strerror(errno));
		return CLI_EXIT_FAIL;
	}
	{
		df1_t *h;

		if ((r = line_build(g, &h)) != 0)
			return r;
		if (line_adopt(g, h) < 0) {
			fprintf(stderr, "%s: out of memory\n", GW_PROG);
			return CLI_EXIT_FAIL;
		}
	}
	if (g->mqtt_url && (r = broker_setup(g)) != 0)
		return r;
	if ((r = gw_sfwd_open(g)) != 0)         /* --buffer: exit 2 when another df1gw has it */
		return r;
	if (g->eip.listen && (r = gw_eip_open(&g->eip, GW_PROG, g->cli.quiet)) != 0)
		return r;
	if ((r = gw_health_open(g)) != 0)       /* systemd's socket, --http */
		return r;
	if (gw_ids_init(&g->ids, GW_IDS_DEFAULT) < 0 || gw_writes_init(g) < 0) {
		fprintf(stderr, "%s: out of memory\n", GW_PROG);
		return CLI_EXIT_FAIL;
	}
	return CLI_CONTINUE;
}

/* ---- the loop ---- */

/* Any readable tag BAD (--once's exit status). */
static bool any_bad(const struct gw *g)
{
	for (int id = 0; id < g->ntags; id++) {
		struct df1_tag_state st;

		if (df1_tag_get(g->h, id, &st) == 0 && (st.config->access & DF1_ACCESS_READ) &&
		    st.quality == DF1_QUALITY_BAD)
			return true;
	}
	return !g->line_up;
}

static int hup_fd_open(void)
{
	sigset_t set;

	sigemptyset(&set);
	sigaddset(&set, SIGHUP);
	if (sigprocmask(SIG_BLOCK, &set, NULL) < 0)
		return -1;
	return signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC);
}

/* Let the broker take what is queued, for at most ms. */
static void flush_broker(struct gw *g, int ms)
{
	int64_t end = gw_now_ms() + ms;

	while (gw_mqtt_up(&g->mq) && !gw_mqtt_idle(&g->mq) && gw_now_ms() < end) {
		struct pollfd p = { gw_mqtt_fd(&g->mq), gw_mqtt_poll_events(&g->mq), 0 };

		if (p.fd < 0 || poll(&p, 1, 100) < 0)
			break;
		gw_mqtt_service(&g->mq, p.revents, gw_now_ms());
	}
}

/* What the loop waits on: each one's place in p, -1 when it is not there. */
struct gw_wait {
	struct pollfd p[7];
	int n, sig, hup, mq, line, eip, http, rx;
};

static void wait_add(struct gw_wait *w, int *at, int fd, short events)
{
	*at = -1;
	if (fd < 0)
		return;
	w->p[w->n] = (struct pollfd){ fd, events, 0 };
	*at = w->n++;
}

static bool wait_ready(const struct gw_wait *w, int at)
{
	return at >= 0 && w->p[at].revents;
}

/* The signals, SIGHUP, the broker, the line's poll engine, EtherNet/IP. */
static void wait_set(const struct gw *g, int hup, struct gw_wait *w)
{
	w->n = 0;
	wait_add(w, &w->sig, cli_signal_fd(), POLLIN);
	wait_add(w, &w->hup, hup, POLLIN);
	wait_add(w, &w->mq, gw_mqtt_fd(&g->mq), gw_mqtt_poll_events(&g->mq));
	wait_add(w, &w->line, g->line_up ? df1_poll_fd(g->h) : -1, POLLIN);
	wait_add(w, &w->eip, gw_eip_fd(&g->eip), POLLIN);
	wait_add(w, &w->http, gw_health_fd(g), POLLIN);
	wait_add(w, &w->rx, gw_rx_fd(g), POLLIN);       /* a PLC's MSG between two polls */
}

/* Milliseconds until whatever is due next: the broker, the line's work or
 * its reopening, --refresh; at most 1 s. */
static int wait_timeout(const struct gw *g, int64_t now)
{
	int timeout = 1000, t;

	t = g->mq_configured ? gw_mqtt_wait_ms(&g->mq, now) : timeout;
	if (t < timeout)
		timeout = t;
	if (g->line_up) {
		t = df1_poll_next_ms(g->h);
		if (t >= 0 && t < timeout)
			timeout = t;
	} else {
		int64_t d = g->line_next_try_ms - now;
		if (d < timeout)
			timeout = d < 0 ? 0 : (int)d;
	}
	if (g->rx.n && g->line_up && timeout > GW_RX_TICK_MS)
		timeout = GW_RX_TICK_MS;        /* the responder's ACK timer and retries */
	t = gw_sfwd_wait_ms(g, now);            /* store and forward's replay */
	if (t < timeout)
		timeout = t;
	t = gw_health_wait_ms(g, now);          /* the watchdog's ping, HTTP's timers */
	if (t < timeout)
		timeout = t;
	if (g->refresh_s > 0 && g->next_refresh_ms - now < timeout)
		timeout = g->next_refresh_ms - now < 0 ? 0 : (int)(g->next_refresh_ms - now);
	if (g->wq.n && gw_wq_next_deadline(&g->wq) - now < timeout)      /* an expiry answered on time */
		timeout = gw_wq_next_deadline(&g->wq) - now < 0 ? 0 : (int)(gw_wq_next_deadline(&g->wq) - now);
	return timeout;
}

/* --once: when it started, whether everything went out after the first scan. */
struct gw_once {
	int64_t started;
	uint64_t scans_seen;
	bool published;
};

/* The broker refused us for good (the first connection; any with --once),
 * or --once has none: the exit status, else CLI_CONTINUE. */
static int broker_verdict(const struct gw *g, const struct gw_once *o, int64_t now)
{
	if (g->mq.refused && (!g->mq.ever_up || g->once)) {
		fprintf(stderr, "%s: broker %s: refused the connection: %s\n", GW_PROG, g->mqtt_url,
		        g->mq.refused_text);
		return CLI_EXIT_FAIL;
	}
	if (g->once && !gw_mqtt_up(&g->mq) && (g->mq.next_try_ms > 0 || now - o->started > ONCE_CONNECT_MS)) {
		fprintf(stderr, "%s: broker %s: cannot connect\n", GW_PROG, g->mqtt_url);
		return CLI_EXIT_FAIL;
	}
	return CLI_CONTINUE;
}

/* --once after a pass: everything published after the first scan, then the
 * end once the broker has it; a line that is not open ends it at once.
 * CLI_CONTINUE, or the exit status. */
static int once_step(struct gw *g, struct gw_once *o)
{
	struct df1_poll_stats ps;

	if (!g->line_up) {
		fprintf(stderr, "%s: %s\n", GW_PROG, g->line_error);
		return CLI_EXIT_FAIL;
	}
	if (!gw_mqtt_up(&g->mq))
		return CLI_CONTINUE;
	df1_poll_stats(g->h, &ps);
	if (!o->published && ps.scans > o->scans_seen) {
		gw_publish_changes(g, true);
		o->published = true;
	}
	return o->published && gw_mqtt_idle(&g->mq) ? CLI_EXIT_OK : CLI_CONTINUE;
}

/* The EtherNet/IP side forwards to the line as it is now (a reload replaces
 * the handle; a lost line is answered at once). */
static void eip_mirror(struct gw *g)
{
	g->eip.h = g->h;
	g->eip.line_up = g->line_up;
}

/* One pass after poll(): a reload, EtherNet/IP's requests, the line's work
 * (or its reopening), --refresh, what changed published. */
static void loop_work(struct gw *g, const struct gw_wait *w, int hup, int64_t now)
{
	if (wait_ready(w, w->hup)) {
		struct signalfd_siginfo si;

		while (read(hup, &si, sizeof si) == (ssize_t)sizeof si)
			;
		if (!g->once) {
			gw_health_reloading(g);
			reload(g);
		}
	}
	eip_mirror(g);
	if (wait_ready(w, w->eip))
		gw_eip_process(&g->eip);       /* requests wait for the bridge's turn */
	gw_line_turns(g, now, false);          /* it and a batch of MQTT writes join the line's queue in turn */
	if (g->line_up && g->rx.n)
		line_serve(g, wait_ready(w, w->rx));
	if (g->line_up && !g->rx.slave && (df1_poll_next_ms(g->h) == 0 || wait_ready(w, w->line)))
		line_work(g);
	else if (!g->line_up && now >= g->line_next_try_ms)
		line_open(g);
	if (g->refresh_s > 0 && now >= g->next_refresh_ms) {
		g->republish = true;
		g->next_refresh_ms = now + (int64_t)g->refresh_s * 1000;
	}
	gw_publish_changes(g, false);
}

/* Until a signal stops it (or --once is done): the exit status. */
static int loop(struct gw *g, int hup, struct gw_once *o)
{
	struct gw_wait w;
	int status = CLI_CONTINUE;

	while (!cli_stop && status == CLI_CONTINUE) {
		int64_t now = gw_now_ms();

		wait_set(g, hup, &w);
		if (poll(w.p, (nfds_t)w.n, wait_timeout(g, now)) < 0 && errno != EINTR) {
			fprintf(stderr, "%s: poll: %s\n", GW_PROG, strerror(errno));
			return CLI_EXIT_FAIL;
		}
		if (cli_stop)
			break;
		if (wait_ready(&w, w.sig))
			cli_signal_drain();
		now = gw_now_ms();
		if (g->mq_configured)
			gw_mqtt_service(&g->mq, w.mq >= 0 ? w.p[w.mq].revents : 0, now);
		status = broker_verdict(g, o, now);
		if (status != CLI_CONTINUE)
			break;
		loop_work(g, &w, hup, now);
		gw_sfwd_turn(g, gw_now_ms());           /* store and forward: the replay */
		gw_health_turn(g, gw_now_ms());         /* HTTP, READY, STATUS, WATCHDOG */
		if (g->once)
			status = once_step(g, o);
	}
	return status == CLI_CONTINUE ? CLI_EXIT_OK : status;
}

/* Before the loop: the line opened (with --once it must be), the first
 * connect to the broker. CLI_CONTINUE, or the exit status. */
static int loop_start(struct gw *g)
{
	g->line_backoff_ms = LINE_BACKOFF_MIN;
	if (line_open(g) < 0 && g->once) {
		fprintf(stderr, "%s: %s\n", GW_PROG, g->line_error);
		return CLI_EXIT_FAIL;
	}
	if (!g->cli.quiet && g->cli.verbose && g->mq_configured)
		fprintf(stderr, "%s: %s: %d tags; broker %s, topics %s/...\n", GW_PROG, g->cli.device, g->ntags,
		        g->mqtt_url, g->prefix);
	if (g->mq_configured)
		gw_mqtt_service(&g->mq, 0, gw_now_ms());        /* the first connect */
	if (g->refresh_s > 0)
		g->next_refresh_ms = gw_now_ms() + (int64_t)g->refresh_s * 1000;
	return CLI_CONTINUE;
}

static int run(struct gw *g)
{
	int hup = hup_fd_open();
	struct gw_once once = { gw_now_ms(), 0, false };
	int status;

	if (hup < 0 && !g->once)
		fprintf(stderr, "%s: SIGHUP: %s (no reload)\n", GW_PROG, strerror(errno));
	status = loop_start(g);
	if (status == CLI_CONTINUE) {
		status = loop(g, hup, &once);
		/* --once: published, and no readable tag BAD */
		if (g->once && status == CLI_EXIT_OK && (!once.published || any_bad(g)))
			status = CLI_EXIT_FAIL;
	}
	if (hup >= 0)
		close(hup);
	return status;
}

/* --counters: the poll engine's figures, EtherNet/IP's, the line's catalog counters. */
static void gw_print_counters(const struct gw *g)
{
	struct df1_poll_stats ps;

	if (!g->h)
		return;
	df1_poll_stats(g->h, &ps);
	printf("scans %llu, %llu transactions (%llu reads, %llu failed, %llu writes, %llu failed, "
	       "%llu retries)\n", (unsigned long long)ps.scans, (unsigned long long)ps.transactions,
	       (unsigned long long)ps.reads, (unsigned long long)ps.read_failures,
	       (unsigned long long)ps.writes, (unsigned long long)ps.write_failures,
	       (unsigned long long)ps.retries);
	gw_writes_counters(g, stdout);
	gw_eip_counters(&g->eip, stdout);
	if (g->rx.n)
		printf("receive: %llu writes from the line landed\n", (unsigned long long)g->rx.received);
	gw_publish_counters(g, stdout);
	if (*df1_port_note(g->h))
		printf("port note: %s\n", df1_port_note(g->h));
	gw_sfwd_counters(g, stdout);
	cli_print_counters(stdout, g->h, CLI_FMT_PLAIN, 0);
	if (g->cli.radio)
		cli_print_radio(stdout, g->h, CLI_FMT_PLAIN, 0, false);
	fflush(stdout);
}

void gw_shutdown(struct gw *g)
{
	gw_health_stopping(g);
	/* the writes waiting: answered "not written" while the broker is there */
	snprintf(g->line_error, sizeof g->line_error, "%s stopping", GW_PROG);
	gw_wq_free(&g->wq);
	if (g->counters)
		gw_print_counters(g);
	/* queued writes and EtherNet/IP requests end first (their results go
	 * out), then the line closes, then the EtherNet/IP server */
	df1_free(g->h);
	g->h = NULL;
	g->eip.h = NULL;
	gw_eip_close(&g->eip);
	if (g->mq_configured) {
		if (!g->once && gw_mqtt_up(&g->mq))
			gw_publish_offline(g);
		flush_broker(g, FLUSH_MS);
		gw_mqtt_close(&g->mq);
	}
	gw_sfwd_close(g);       /* what is not acknowledged stays in --buffer's file */
	gw_fmts_close(&g->fmts);
	gw_pubs_free(&g->pubs);
	gw_ids_free(&g->ids);
	gw_outbox_free(&g->outbox);
	gw_msg_free(&g->msg);
	gw_msg_free(&g->will);
	gw_buf_free(&g->key);
	free(g->dirty);
	free(g->pub_of);
	gw_rx_free(&g->rx);
	if (g->password) {
		memset(g->password, 0, strlen(g->password));
		free(g->password);
	}
	gw_health_close(g);
	cli_cleanup(&g->cli);
}

int main(int argc, char **argv)
{
	static struct gw g;
	int r;

	r = gw_setup(&g, argc, argv);
	if (r != CLI_CONTINUE) {
		gw_shutdown(&g);
		return r;
	}
	r = run(&g);
	if (cli_stop && !g.cli.quiet && g.cli.verbose)
		fprintf(stderr, "%s: %s: stopping\n", GW_PROG, cli_signal_name(cli_stop_signal()));
	gw_shutdown(&g);
	return r;
}
