/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_options - df1gw's command line: the option table, what each option sets
 * in struct gw, the checks between options, and what follows from them (the
 * password read from its file, the client id, the topic prefix). df1gw.c's
 * gw_setup() calls gw_options_parse() first and then opens what they name.
 * A new concern adds its options here and its state to struct gw (gw.h).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "df1gw/gw.h"

enum {
	OPT_MAP = CLI_KEY_EXTRA, OPT_MQTT, OPT_CAFILE, OPT_CERT, OPT_KEY, OPT_CLIENT_ID, OPT_USERNAME,
	OPT_PASSWORD_FILE, OPT_PASSWORD, OPT_PREFIX, OPT_QOS, OPT_KEEPALIVE, OPT_REFRESH, OPT_ONCE,
	OPT_WATCHDOG, OPT_EIP, OPT_EIP_STATION, OPT_COUNTERS,
	OPT_EIP_SHARED, /* the CLI_EIP_OPT_COUNT_ keys of tools/common/cli_eip.h from here */
	OPT_EIP_SHARED_END_ = OPT_EIP_SHARED + CLI_EIP_OPT_COUNT_ - 1,
	/* Sparkplug B */
	OPT_SPARKPLUG, OPT_EDGE_NODE, OPT_JSON, OPT_PRIMARY_HOST, OPT_SPB_ALIASES, OPT_DEVICE_NAME, OPT_SPB_STATE,
	/* the write policy (gw_wqueue.h) */
	OPT_WRITE_OPTIMIZE, OPT_DUTY_CYCLE, OPT_WRITE_TIMEOUT, OPT_MAX_PENDING,
	OPT_HTTP,
	/* store and forward (gw_sfwd.h) */
	OPT_BUFFER, OPT_BUFFER_MAX, OPT_BUFFER_MAX_AGE, OPT_REPLAY_RATE,
};

static const struct cli_extra_opt gw_opts[] = {
	{ "map", required_argument, OPT_MAP, "FILE.csv", "the tags: a mapping CSV (required without --eip)" },
	{ "mqtt", required_argument, OPT_MQTT, "URL", "broker mqtt://HOST[:PORT] or mqtts://HOST[:PORT] (required without --eip, and by --once)" },
	{ "cafile", required_argument, OPT_CAFILE, "FILE", "mqtts: CA certificates (default: the system's)" },
	{ "cert", required_argument, OPT_CERT, "FILE", "mqtts: client certificate (PEM)" },
	{ "key", required_argument, OPT_KEY, "FILE", "mqtts: client private key (PEM)" },
	{ "client-id", required_argument, OPT_CLIENT_ID, "ID", "MQTT client id (default df1gw-HOSTNAME-LINE)" },
	{ "username", required_argument, OPT_USERNAME, "NAME", "broker user name" },
	{ "password-file", required_argument, OPT_PASSWORD_FILE, "FILE",
	  "broker password: the file's first line (or env DF1GW_PASSWORD)" },
	{ "password", optional_argument, OPT_PASSWORD, NULL,
	  "refused: a command line is visible to every user" },
	{ "prefix", required_argument, OPT_PREFIX, "TOPIC", "topic prefix (default df1/CLIENT-ID)" },
	{ "qos", required_argument, OPT_QOS, "0|1", "QoS of publications and subscriptions (default 1)" },
	{ "keepalive", required_argument, OPT_KEEPALIVE, "S", "MQTT keepalive 5-65535 s (default 60)" },
	{ "refresh", required_argument, OPT_REFRESH, "S",
	  "republish every tag every S s (default 0: only on change)" },
	{ "watchdog", required_argument, OPT_WATCHDOG, "MS",
	  "station offline after MS ms without an answer (default 10000)" },
	{ "once", no_argument, OPT_ONCE, NULL, "one scan, publish, exit (cron, tests)" },
	{ "eip", required_argument, OPT_EIP, "[ADDR:]PORT",
	  "also an EtherNet/IP bridge (PCCC), on 127.0.0.1 unless ADDR is given (44818 is the standard port)" },
	{ "eip-station", required_argument, OPT_EIP_STATION, "N",
	  "--eip: the station of requests without a route path (default 1)" },
	CLI_EIP_OPTS(OPT_EIP_SHARED),
	{ "sparkplug", required_argument, OPT_SPARKPLUG, "GROUP_ID",
	  "also Sparkplug B: the line an edge node of group GROUP_ID, stations its devices" },
	{ "edge-node", required_argument, OPT_EDGE_NODE, "ID", "--sparkplug: the edge node id (default: the client id)" },
	{ "json", required_argument, OPT_JSON, "yes|no", "--sparkplug: also the JSON topics (default yes)" },
	{ "primary-host", required_argument, OPT_PRIMARY_HOST, "ID",
	  "--sparkplug: no birth until spBv1.0/STATE/ID says online" },
	{ "sparkplug-aliases", no_argument, OPT_SPB_ALIASES, NULL,
	  "--sparkplug: births name and alias each metric, DATA and CMD use aliases" },
	{ "device-name", required_argument, OPT_DEVICE_NAME, "N=NAME",
	  "--sparkplug: station N's device id (default stationN; repeatable)" },
	{ "sparkplug-state", required_argument, OPT_SPB_STATE, "FILE",
	  "--sparkplug: the file that keeps bdSeq across restarts (default: GROUP_ID@EDGE.bdseq in the state "
	  "folder, $STATE_DIRECTORY, else $XDG_STATE_HOME/df1gw, else ~/.local/state/df1gw)" },
	{ "counters", no_argument, OPT_COUNTERS, NULL,
	  "the line's, the writes' and EtherNet/IP counters on stdout at exit" },
	{ "write-optimize", required_argument, OPT_WRITE_OPTIMIZE, "all|latest|latest-non-bool",
	  "a waiting write replaced by a later one to its tag (default latest-non-bool: not bits)" },
	{ "duty-cycle", required_argument, OPT_DUTY_CYCLE, "N",
	  "MQTT writes go N at a time, a due poll read after each N (default 10)" },
	{ "write-timeout", required_argument, OPT_WRITE_TIMEOUT, "MS",
	  "a write not started within MS ms: expired, not written (default 30000; \"timeout_ms\" in /set)" },
	{ "max-pending-writes", required_argument, OPT_MAX_PENDING, "N",
	  "more writes waiting: answered busy, not written (default 1000)" },
	{ "http", required_argument, OPT_HTTP, "[ADDR:]PORT",
	  "read-only status page, /metrics (Prometheus) and /api/status, on 127.0.0.1 unless ADDR is given" },
	{ "buffer", required_argument, OPT_BUFFER, "FILE",
	  "store and forward on FILE (SQLite): changes while the broker is away survive a restart "
	  "(default: in memory, lost on exit)" },
	{ "buffer-max", required_argument, OPT_BUFFER_MAX, "SIZE",
	  "the buffer's bound, bytes (64k, 512M, 1G) or records (100000r); the oldest go first "
	  "(default 1G on a file, 100000r and 64M in memory)" },
	{ "buffer-max-age", required_argument, OPT_BUFFER_MAX_AGE, "DURATION",
	  "records older than DURATION (90s, 15m, 12h, 7d) are dropped (default: no bound)" },
	{ "replay-rate", required_argument, OPT_REPLAY_RATE, "N/s",
	  "the backlog replayed at most N records a second after a reconnect (default 500/s)" },
	{ NULL, 0, 0, NULL, NULL },
};

/* --buffer-max, --buffer-max-age, --replay-rate */
static int buffer_opt(struct cli *c, struct gw *g, int key, const char *arg)
{
	char err[200];

	if (key == OPT_BUFFER_MAX && gw_buffer_parse_max(arg, &g->sfwd.lim, err, sizeof err) < 0)
		return cli_usage_error(c, "--buffer-max %s: %s", arg, err);
	if (key == OPT_BUFFER_MAX_AGE && gw_buffer_parse_age(arg, &g->sfwd.lim.max_age_ms, err, sizeof err) < 0)
		return cli_usage_error(c, "--buffer-max-age %s: %s", arg, err);
	if (key == OPT_REPLAY_RATE && gw_replay_parse_rate(arg, &g->sfwd.rate) < 0)
		return cli_usage_error(c, "--replay-rate %s: records a second, 1-%u (\"500\" or \"500/s\")", arg,
		                       GW_REPLAY_RATE_MAX);
	return CLI_CONTINUE;
}

/* --device-name N=NAME */
static int device_name_opt(struct cli *c, struct gw *g, const char *arg)
{
	char *end;
	long n = strtol(arg, &end, 10);

	if (end == arg || *end != '=' || n < 0 || n > 254 || !end[1])
		return cli_usage_error(c, "--device-name %s: N=NAME, N a station 0-254", arg);
	g->spb.device_name[n] = end + 1;
	return CLI_CONTINUE;
}

static int gw_extra(struct cli *c, int key, const char *arg, void *user)
{
	struct gw *g = user;

	if (cli_eip_is_option(key, OPT_EIP_SHARED))
		return cli_eip_option(c, &g->eip.opts, key, OPT_EIP_SHARED, arg);
	switch (key) {
	case OPT_MAP: g->map_path = arg; break;
	case OPT_MQTT: g->mqtt_url = arg; break;
	case OPT_CAFILE: g->cafile = arg; break;
	case OPT_CERT: g->cert = arg; break;
	case OPT_KEY: g->keyfile = arg; break;
	case OPT_CLIENT_ID: g->client_id_opt = arg; break;
	case OPT_USERNAME: g->username = arg; break;
	case OPT_PASSWORD_FILE: g->password_file = arg; break;
	case OPT_PASSWORD:
		fprintf(stderr, "%s: --password: refused: a password on the command line is visible to every "
		        "user (ps, /proc); use --password-file FILE or the environment variable DF1GW_PASSWORD\n",
		        c->name);
		return CLI_EXIT_USAGE;
	case OPT_PREFIX: g->prefix_opt = arg; break;
	case OPT_QOS: return cli_parse_int(c, "--qos", arg, 0, 1, &g->qos);
	case OPT_KEEPALIVE: return cli_parse_int(c, "--keepalive", arg, 5, 65535, &g->keepalive_s);
	case OPT_REFRESH: return cli_parse_int(c, "--refresh", arg, 0, 86400, &g->refresh_s);
	case OPT_WATCHDOG: return cli_parse_int(c, "--watchdog", arg, 0, 86400000, &g->watchdog_ms);
	case OPT_ONCE: g->once = true; break;
	case OPT_EIP: g->eip.listen = arg; break;
	case OPT_EIP_STATION: return cli_parse_int(c, "--eip-station", arg, 0, 254, &g->eip.station);
	case OPT_COUNTERS: g->counters = true; break;
	case OPT_SPARKPLUG: g->spb.group = arg; break;
	case OPT_EDGE_NODE: g->spb.edge_node = arg; break;
	case OPT_JSON:
		if (strcmp(arg, "yes") != 0 && strcmp(arg, "no") != 0)
			return cli_usage_error(c, "--json %s: yes or no", arg);
		g->json_off = strcmp(arg, "no") == 0;
		break;
	case OPT_PRIMARY_HOST: g->spb.primary_host = arg; break;
	case OPT_SPB_ALIASES: g->spb.aliases = true; break;
	case OPT_DEVICE_NAME: return device_name_opt(c, g, arg);
	case OPT_SPB_STATE: g->spb_state_path = arg; break;
	case OPT_WRITE_OPTIMIZE:
		if (gw_wopt_parse(arg, &g->write_optimize) < 0)
			return cli_usage_error(c, "--write-optimize '%s': all, latest or latest-non-bool", arg);
		break;
	case OPT_DUTY_CYCLE: return cli_parse_int(c, "--duty-cycle", arg, 1, 1000, &g->duty_cycle);
	case OPT_WRITE_TIMEOUT: return cli_parse_int(c, "--write-timeout", arg, 1, (int)GW_TIMEOUT_MS_MAX,
	                                             &g->write_timeout_ms);
	case OPT_MAX_PENDING:
		return cli_parse_int(c, "--max-pending-writes", arg, 1, GW_WQ_MAX_LIMIT, &g->max_pending);
	case OPT_HTTP: g->health.http_listen = arg; break;
	case OPT_BUFFER: g->sfwd.path = arg; break;
	case OPT_BUFFER_MAX:
	case OPT_BUFFER_MAX_AGE:
	case OPT_REPLAY_RATE: return buffer_opt(c, g, key, arg);
	default: return CLI_EXIT_USAGE;
	}
	return CLI_CONTINUE;
}

static const struct cli_tool gw_tool = {
	.name = GW_PROG,
	.synopsis = "-d DEV (--map FILE.csv --mqtt mqtt://HOST[:PORT] | --eip [ADDR:]PORT) [OPTIONS]",
	.summary = "Keep a DF1 line's tags in an MQTT broker, and take writes back; bridge EtherNet/IP to it.",
	.accepts = (CLI_ACCEPT_LINK & ~CLI_ACCEPT(CLI_OPT_STATION)) | CLI_ACCEPT(CLI_OPT_VERBOSE) |
	           CLI_ACCEPT(CLI_OPT_QUIET) | CLI_ACCEPT(CLI_OPT_FORWARD),
	.common_help = { [CLI_OPT_VERBOSE] = "what is published and received; -vv link events, -vvv frames",
	                 [CLI_OPT_DUPLEX] = "full (default), half (master), half-slave (Receive rows at --src), "
	                                    "radio (DF1 Radio Modem)" },
	.half_slave = true,
	.extra = gw_opts,
	.on_extra = gw_extra,
	.help_tail = "\nTopics: PREFIX/tag/NAME (retained JSON), PREFIX/tag/NAME/set (a write),\n"
	             "PREFIX/tag/NAME/result, PREFIX/station/N, PREFIX/status (online/offline),\n"
	             "PREFIX/status/buffer (store and forward's counters).\n"
	             "Sparkplug B: spBv1.0/GROUP/{NBIRTH,NDATA,NDEATH,NCMD}/EDGE[/DEVICE], DBIRTH, DDATA, DDEATH, DCMD.\n"
	             "Rows with Command Receive: df1gw's own table, written by PLCs' MSG and published.\n"
	             "SIGTERM/SIGINT: offline, line closed, exit 0; SIGHUP: reload the mapping file.\n"
	             "See df1gw(1).\n",
	.exit_text = "0 stopped by SIGTERM or SIGINT (--once: published, no tag BAD), 1 the broker refused\n"
	             "the credentials (--once: no broker, no line, a tag BAD), 2 usage or configuration error.",
};

static int read_password(struct gw *g)
{
	const char *env = getenv("DF1GW_PASSWORD");
	char line[1024];
	FILE *f;

	if (g->password_file) {
		f = fopen(g->password_file, "r");
		if (!f) {
			fprintf(stderr, "%s: --password-file %s: %s\n", GW_PROG, g->password_file, strerror(errno));
			return CLI_EXIT_USAGE;
		}
		if (!fgets(line, sizeof line, f))
			line[0] = '\0';
		fclose(f);
		line[strcspn(line, "\r\n")] = '\0';
		g->password = strdup(line);
	} else if (env) {
		g->password = strdup(env);
	}
	if ((g->password_file || env) && !g->password) {
		fprintf(stderr, "%s: out of memory\n", GW_PROG);
		return CLI_EXIT_FAIL;
	}
	if (g->password && !g->username) {
		fprintf(stderr, "%s: a password (%s) needs --username\n", GW_PROG,
		        g->password_file ? "--password-file" : "DF1GW_PASSWORD");
		return CLI_EXIT_USAGE;
	}
	return 0;
}

/* df1gw-HOSTNAME-LINE: LINE the device's basename, or HOST_PORT for tcp://. */
static void default_client_id(struct gw *g)
{
	char host[128] = "localhost", line[160];
	const char *d = g->cli.device, *b;

	if (gethostname(host, sizeof host) < 0 || !host[0])
		snprintf(host, sizeof host, "localhost");
	host[sizeof host - 1] = '\0';
	if (strncasecmp(d, "tcp://", 6) == 0) {
		snprintf(line, sizeof line, "%s", d + 6);
		for (char *p = line; *p; p++)
			if (*p == ':' || *p == '/' || *p == '[' || *p == ']')
				*p = '_';
	} else {
		b = strrchr(d, '/');
		snprintf(line, sizeof line, "%s", b && b[1] ? b + 1 : d);
	}
	snprintf(g->client_id, sizeof g->client_id, "df1gw-%s-%s", host, line);
}

static int check_prefix(struct gw *g)
{
	size_t l;

	if (g->prefix_opt)
		snprintf(g->prefix, sizeof g->prefix, "%s", g->prefix_opt);
	else
		snprintf(g->prefix, sizeof g->prefix, "df1/%s", g->client_id);
	l = strlen(g->prefix);
	while (l > 1 && g->prefix[l - 1] == '/')
		g->prefix[--l] = '\0';
	if (!l || strpbrk(g->prefix, "+#")) {
		fprintf(stderr, "%s: --prefix '%s': a topic without '+' or '#'%s\n", GW_PROG, g->prefix,
		        g->prefix_opt ? "" : " (it comes from the client id: give --prefix)");
		return CLI_EXIT_USAGE;
	}
	return 0;
}

/* The Sparkplug options go with --sparkplug (and a broker); the edge node id
 * defaults to the client id. */
static int check_sparkplug(struct gw *g)
{
	bool any = g->spb.edge_node || g->json_off || g->spb.primary_host || g->spb.aliases || g->spb_state_path;

	for (int i = 0; i < GW_SPB_STATIONS; i++)
		any = any || g->spb.device_name[i];
	if (!g->spb.group && any)
		return cli_usage_error(&g->cli, "--edge-node, --json, --primary-host, --sparkplug-aliases, "
		                       "--device-name and --sparkplug-state go with --sparkplug GROUP_ID");
	if (g->spb.group && !g->mqtt_url)
		return cli_usage_error(&g->cli, "--sparkplug publishes: it needs --mqtt");
	if (g->spb.group && g->once)
		return cli_usage_error(&g->cli, "--sparkplug is a session (births, a will): not with --once");
	if (g->spb.group && !g->spb.edge_node)
		g->spb.edge_node = g->client_id;
	return CLI_CONTINUE;
}

/* The options: parsed, checked against each other, the password read, the
 * client id and prefix made. CLI_CONTINUE or the exit status, having said why. */
int gw_options_parse(struct gw *g, int argc, char **argv)
{
	char err[256];
	int r;

	cli_init(&g->cli, &gw_tool);
	g->qos = 1;
	g->keepalive_s = 60;
	g->watchdog_ms = -1;
	cli_eip_init(&g->eip.opts);
	g->write_optimize = GW_WOPT_LATEST_NON_BOOL;
	g->duty_cycle = 10;
	g->write_timeout_ms = 30000;
	g->max_pending = 1000;
	r = cli_parse(&g->cli, argc, argv, g);
	if (r != CLI_CONTINUE)
		return r;
	if (g->cli.argc > 0)
		return cli_usage_error(&g->cli, "unexpected operand '%s'", g->cli.argv[0]);
	if (!g->eip.listen && g->eip.station >= 0)
		return cli_usage_error(&g->cli, "--eip-station goes with --eip");
	if ((r = cli_eip_check(&g->cli, &g->eip.opts, g->eip.listen != NULL)) != CLI_CONTINUE)
		return r;
	if (!g->map_path && !g->eip.listen)
		return cli_usage_error(&g->cli, "no tags: give --map FILE.csv (or --eip PORT for a bridge)");
	if (!g->mqtt_url && !g->eip.listen)
		return cli_usage_error(&g->cli, "no broker: give --mqtt mqtt://HOST[:PORT] (or --eip PORT for a bridge)");
	if (g->once && !g->mqtt_url)
		return cli_usage_error(&g->cli, "--once publishes: it needs --mqtt");
	if (g->eip.station < 0)
		g->eip.station = 1;     /* -a is not df1gw's: tags name their stations */
	if (g->mqtt_url && gw_url_parse(g->mqtt_url, &g->url, err, sizeof err) < 0) {
		fprintf(stderr, "%s: --mqtt %s: %s\n", GW_PROG, g->mqtt_url, err);
		return CLI_EXIT_USAGE;
	}
	if (!g->mqtt_url && (g->cafile || g->cert || g->keyfile || g->username || g->password_file)) {
		fprintf(stderr, "%s: --cafile, --cert, --key, --username and --password-file go with --mqtt\n", GW_PROG);
		return CLI_EXIT_USAGE;
	}
	if (g->mqtt_url && !g->url.tls && (g->cafile || g->cert || g->keyfile)) {
		fprintf(stderr, "%s: --cafile, --cert and --key are for mqtts:// (TLS)\n", GW_PROG);
		return CLI_EXIT_USAGE;
	}
	if (!g->cert != !g->keyfile) {
		fprintf(stderr, "%s: --cert and --key go together\n", GW_PROG);
		return CLI_EXIT_USAGE;
	}
	if (!g->cli.device || !*g->cli.device) {
		fprintf(stderr, "%s: no device: use -d DEV, -N FILE or set DF1_DEVICE\n", GW_PROG);
		return CLI_EXIT_USAGE;
	}
	if ((r = read_password(g)) != 0)
		return r;
	if (g->client_id_opt)
		snprintf(g->client_id, sizeof g->client_id, "%s", g->client_id_opt);
	else
		default_client_id(g);
	if ((r = check_prefix(g)) != 0)
		return r;
	if ((g->sfwd.path || g->sfwd.lim.max_records || g->sfwd.lim.max_bytes || g->sfwd.lim.max_age_ms ||
	     g->sfwd.rate) && (!g->mqtt_url || g->once))
		return cli_usage_error(&g->cli, "--buffer, --buffer-max, --buffer-max-age and --replay-rate store "
		                       "for a broker: they need --mqtt, and not --once");
	return check_sparkplug(g);
}
