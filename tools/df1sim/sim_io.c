/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_io - df1sim's transports (a pseudo-terminal behind a symbolic link, a
 * TCP listener), its --log command log and the fault probabilities of its
 * options (the interface: sim_io.h). The messages and exit statuses are
 * df1sim's (df1sim(1)).
 */
#include "df1sim/sim_io.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <netdb.h>
#include <netinet/in.h>
#include <arpa/inet.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "common/cli.h"

/* ------------------------------------------------------------------------
 * Probabilities
 * ------------------------------------------------------------------------ */

bool sim_parse_percent(const char *s, int *per_mille)
{
	char *end;
	double v;

	if (!s || !*s)
		return false;
	errno = 0;
	v = strtod(s, &end);
	if (*end == '%')
		end++;
	if (errno || *end || !(v >= 0.0 && v <= 100.0))
		return false;
	*per_mille = (int)lround(v * 10.0);
	return true;
}

/* ------------------------------------------------------------------------
 * Transports
 * ------------------------------------------------------------------------ */

int sim_pty_create(struct sim_pty *p, const char *path, char *err, size_t cap)
{
	struct termios tio;
	struct stat st;

	p->master = p->slave = -1;
	p->linked = false;
	p->link = path;
	p->master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
	if (p->master < 0 || grantpt(p->master) < 0 || unlockpt(p->master) < 0 ||
	    ptsname_r(p->master, p->slave_name, sizeof p->slave_name) != 0) {
		snprintf(err, cap, "cannot create a pseudo-terminal: %s", strerror(errno));
		return CLI_EXIT_FAIL;
	}
	/* our own descriptor on the slave side: the master never sees a hangup
	 * between clients; raw, so nothing is echoed or translated meanwhile */
	p->slave = open(p->slave_name, O_RDWR | O_NOCTTY | O_CLOEXEC);
	if (p->slave < 0) {
		snprintf(err, cap, "%s: %s", p->slave_name, strerror(errno));
		return CLI_EXIT_FAIL;
	}
	if (tcgetattr(p->slave, &tio) == 0) {
		cfmakeraw(&tio);
		tcsetattr(p->slave, TCSANOW, &tio);
	}
	if (lstat(path, &st) == 0) {
		if (!S_ISLNK(st.st_mode)) {
			snprintf(err, cap, "%s: exists and is not a symbolic link", path);
			return CLI_EXIT_USAGE;
		}
		unlink(path);   /* a stale link from an earlier run */
	}
	if (symlink(p->slave_name, path) < 0) {
		snprintf(err, cap, "%s: cannot create symbolic link: %s", path, strerror(errno));
		return CLI_EXIT_USAGE;
	}
	p->linked = true;
	return 0;
}

void sim_pty_destroy(struct sim_pty *p)
{
	char target[sizeof p->slave_name];
	ssize_t n;

	if (p->linked) {
		/* remove the link only if it is still ours */
		n = readlink(p->link, target, sizeof target - 1);
		if (n >= 0) {
			target[n] = '\0';
			if (strcmp(target, p->slave_name) == 0)
				unlink(p->link);
		}
		p->linked = false;
	}
	if (p->slave >= 0)
		close(p->slave);
	p->slave = -1;
}

/* "tcp://HOST:PORT" (also "TCP://"), "HOST:PORT", ":PORT", "PORT", "[::1]:PORT". */
static bool parse_listen(const char *spec, char *host, size_t hcap, char *port, size_t pcap)
{
	const char *s = spec, *colon;
	size_t hl;

	if (strncasecmp(s, "tcp://", 6) == 0)       /* the scheme in any case */
		s += 6;
	else if (strncasecmp(s, "tcp:", 4) == 0)
		s += 4;
	if (*s == '[') {
		const char *rb = strchr(s, ']');

		if (!rb || rb[1] != ':')
			return false;
		hl = (size_t)(rb - s - 1);
		if (hl == 0 || hl >= hcap)
			return false;
		memcpy(host, s + 1, hl);
		host[hl] = '\0';
		s = rb + 2;
	} else if ((colon = strrchr(s, ':')) != NULL) {
		hl = (size_t)(colon - s);
		if (hl >= hcap)
			return false;
		memcpy(host, s, hl);
		host[hl] = '\0';
		s = colon + 1;
	} else {
		host[0] = '\0';
	}
	if (!host[0])
		snprintf(host, hcap, "127.0.0.1");      /* loopback unless asked otherwise */
	{
		long v;

		if (!cli_long_in(s, 0, 65535, &v) || strlen(s) >= pcap)
			return false;
		snprintf(port, pcap, "%ld", v);
	}
	return true;
}

static bool listen_is_wildcard(const struct sockaddr_storage *ss)
{
	if (ss->ss_family == AF_INET6)
		return IN6_IS_ADDR_UNSPECIFIED(&((const struct sockaddr_in6 *)ss)->sin6_addr);
	return ((const struct sockaddr_in *)ss)->sin_addr.s_addr == htonl(INADDR_ANY);
}

static bool listen_is_loopback(const struct sockaddr_storage *ss)
{
	if (ss->ss_family == AF_INET6)
		return IN6_IS_ADDR_LOOPBACK(&((const struct sockaddr_in6 *)ss)->sin6_addr);
	return (ntohl(((const struct sockaddr_in *)ss)->sin_addr.s_addr) >> 24) == 127;
}

int sim_listen_open(const char *spec, char *shown, size_t cap, enum sim_listen_scope *scope,
                    char *err, size_t ecap)
{
	char host[256], port[16], hbuf[INET6_ADDRSTRLEN + 8], pbuf[16];
	struct addrinfo hints, *res, *ai;
	struct sockaddr_storage ss;
	socklen_t sl = sizeof ss;
	int fd = -1, rc, one = 1;

	if (!parse_listen(spec, host, sizeof host, port, sizeof port)) {
		snprintf(err, ecap, "--listen: invalid address '%s' (expected tcp://HOST:PORT)", spec);
		return -CLI_EXIT_USAGE;
	}
	memset(&hints, 0, sizeof hints);
	hints.ai_family = AF_UNSPEC;
	hints.ai_socktype = SOCK_STREAM;
	hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
	rc = getaddrinfo(host, port, &hints, &res);
	if (rc != 0) {
		snprintf(err, ecap, "--listen %s: %s", spec, gai_strerror(rc));
		return -CLI_EXIT_USAGE;
	}
	for (ai = res; ai; ai = ai->ai_next) {
		fd = socket(ai->ai_family, ai->ai_socktype | SOCK_CLOEXEC, ai->ai_protocol);
		if (fd < 0)
			continue;
		setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
		if (bind(fd, ai->ai_addr, ai->ai_addrlen) == 0 && listen(fd, 4) == 0)
			break;
		rc = errno;
		close(fd);
		fd = -1;
		errno = rc;
	}
	freeaddrinfo(res);
	if (fd < 0) {
		snprintf(err, ecap, "--listen %s: %s", spec, strerror(errno));
		return -CLI_EXIT_FAIL;
	}
	if (getsockname(fd, (struct sockaddr *)&ss, &sl) < 0 ||
	    getnameinfo((struct sockaddr *)&ss, sl, hbuf, sizeof hbuf, pbuf, sizeof pbuf,
	                NI_NUMERICHOST | NI_NUMERICSERV) != 0) {
		snprintf(err, ecap, "--listen %s: %s", spec, strerror(errno));
		close(fd);
		return -CLI_EXIT_FAIL;
	}
	if (ss.ss_family == AF_INET6)
		snprintf(shown, cap, "tcp://[%s]:%s", hbuf, pbuf);
	else
		snprintf(shown, cap, "tcp://%s:%s", hbuf, pbuf);
	if (listen_is_wildcard(&ss) && strcmp(host, "0.0.0.0") != 0 && strcmp(host, "::") != 0) {
		/* "0", "0.0", "0x0" are inet_aton's spellings of 0.0.0.0: every interface */
		snprintf(err, ecap, "--listen %s: '%s' is the address of every interface: "
		         "write 0.0.0.0 (or ::) to listen on all of them", spec, host);
		close(fd);
		return -CLI_EXIT_USAGE;
	}
	if (scope)
		*scope = listen_is_wildcard(&ss) ? SIM_LISTEN_ALL
		         : listen_is_loopback(&ss) ? SIM_LISTEN_LOOPBACK : SIM_LISTEN_OTHER;
	return fd;
}

/* ------------------------------------------------------------------------
 * The command log (--log)
 * ------------------------------------------------------------------------ */

static struct df1_table *cmdlog_table(const struct sim_cmdlog *l, int station)
{
	if (station >= 0 && station < 256 && l->tables[station])
		return l->tables[station];
	return l->tables[l->first_station];
}

static void cmdlog_command(struct sim_cmdlog *l, int station, const uint8_t *app, size_t n)
{
	struct df1_msg m;
	struct timespec ts;
	struct tm tm;
	char when[40], addr[80], count[16], cmd[8];
	int es;

	if (l->error)
		return;                 /* the log already failed: df1sim is stopping */
	if (df1_msg_decode(app, n, &m) < 0)
		return;
	clock_gettime(CLOCK_REALTIME, &ts);
	localtime_r(&ts.tv_sec, &tm);
	strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%S", &tm);
	snprintf(addr, sizeof addr, "-");
	snprintf(count, sizeof count, "-");
	if (m.has_addr) {
		struct df1_addr a = m.addr;

		if (a.ascii[0]) {
			snprintf(addr, sizeof addr, "$%s", a.ascii);
		} else {
			if (a.type == DF1_FT_NONE)
				(void)df1_table_file(cmdlog_table(l, station), a.file, &a.type);
			if (a.type == DF1_FT_NONE ||
			    df1_addr_format_plc(l->plc, &a, addr, sizeof addr) < 0)
				snprintf(addr, sizeof addr, "#%d:%d", a.file, a.element);
		}
	}
	if (m.size >= 0) {
		int c = m.size;

		if (m.cmd == 0x0F && m.fnc >= 0xA1 && m.fnc <= 0xAB) {
			/* SLC: BYTE_SIZE -> elements (words for a sub-element) */
			es = m.addr.sub != DF1_ADDR_NONE ? 2 : df1_file_type_element_size(m.addr.type);
			if (es <= 0)
				es = 2;
			c = (m.size + es - 1) / es;
		} else if ((m.cmd == 0x0F && (m.fnc == 0x00 || m.fnc == 0x01)) || m.cmd == 0x01 || m.cmd == 0x08) {
			c = (m.size + 1) / 2;   /* word range, PLC-2: words */
		}
		snprintf(count, sizeof count, "%d", c);
	}
	if (m.has_fnc)
		snprintf(cmd, sizeof cmd, "%02X/%02X", m.cmd, m.fnc);
	else
		snprintf(cmd, sizeof cmd, "%02X", m.cmd);
	errno = 0;
	if (fprintf(l->fp, "%s.%03ld station=%d cmd=%s addr=%s count=%s tns=%04X name=\"%s\"\n",
	            when, ts.tv_nsec / 1000000L, station, cmd, addr, count, m.tns,
	            m.name ? m.name : "") < 0 || fflush(l->fp) != 0)
		l->error = errno ? errno : EIO;         /* the tool stops and says so */
}

void sim_cmdlog_command(struct sim_cmdlog *l, int station, const uint8_t *app, size_t n)
{
	if (l->fp)
		cmdlog_command(l, station, app, n);
}

static void cmdlog_rx_frame(struct sim_cmdlog *l, const struct df1_symbol *sym)
{
	const uint8_t *a = sym->data;
	int station;

	if (!sym->check_ok || sym->len < 6 || (a[2] & 0x40))
		return;
	station = sym->master_msg && sym->has_station ? sym->station : a[0];
	if (l->by_station && (station < 0 || station > 255 || !l->tables[station]))
		return;                 /* for another station on the line (a radio relay's too) */
	for (int i = 0; i < 16; i++) {
		/* a repeat of a command already seen: the same bytes again (SRC,
		 * CMD and TNS alone would also match a new master process that
		 * drew a TNS an earlier one used, and leave its command unlogged) */
		if (l->ring[i].used && l->ring[i].n == (sym->len < sizeof l->ring[0].app ? sym->len
		                                                                    : sizeof l->ring[0].app) &&
		    memcmp(l->ring[i].app, a, l->ring[i].n) == 0)
			return;
	}
	l->ring[l->next].used = true;
	l->ring[l->next].logged = false;
	l->ring[l->next].station = station;
	l->ring[l->next].n = sym->len < sizeof l->ring[0].app ? sym->len : sizeof l->ring[0].app;
	memcpy(l->ring[l->next].app, a, l->ring[l->next].n);
	l->next = (l->next + 1) % 16;
}

static void cmdlog_tx_frame(struct sim_cmdlog *l, const struct df1_symbol *sym)
{
	const uint8_t *r = sym->data;

	if (sym->len < 6 || !(r[2] & 0x40))
		return;
	for (int i = 0; i < 16; i++) {
		const uint8_t *c = l->ring[i].app;

		if (!l->ring[i].used || l->ring[i].logged)
			continue;
		if (c[1] == r[0] && (c[2] | 0x40) == r[2] && c[4] == r[4] && c[5] == r[5]) {
			l->ring[i].logged = true;
			cmdlog_command(l, l->ring[i].station, c, l->ring[i].n);
			return;
		}
	}
}

int sim_cmdlog_open(struct sim_cmdlog *l, const char *path, enum df1_check check, bool half,
                    bool by_station, struct df1_table *const *tables, int first_station)
{
	memset(l, 0, sizeof *l);
	l->half = half;
	l->by_station = by_station;
	l->tables = tables;
	l->first_station = first_station;
	l->fp = fopen(path, "w");
	if (!l->fp)
		return -1;
	if (df1_decoder_new(&l->dec[0], check) < 0 || df1_decoder_new(&l->dec[1], check) < 0)
		return -2;
	df1_decoder_set_half_duplex(l->dec[0], half);
	df1_decoder_set_half_duplex(l->dec[1], half);
	return 0;
}

void sim_cmdlog_close(struct sim_cmdlog *l)
{
	if (l->fp)
		fclose(l->fp);
	l->fp = NULL;
	df1_decoder_free(l->dec[0]);
	df1_decoder_free(l->dec[1]);
	l->dec[0] = l->dec[1] = NULL;
}

void sim_cmdlog_feed(struct sim_cmdlog *l, enum df1_dir dir, const uint8_t *bytes, size_t n)
{
	struct df1_decoder *d;

	if (!l->fp)
		return;
	d = l->dec[dir == DF1_DIR_TX ? 1 : 0];
	while (n > 0) {
		struct df1_symbol sym;
		size_t used = df1_decoder_feed(d, bytes, n, &sym);

		if (used == 0)
			break;
		bytes += used;
		n -= used;
		if (sym.kind != DF1_SYM_FRAME)
			continue;
		if (dir == DF1_DIR_RX)
			cmdlog_rx_frame(l, &sym);
		else
			cmdlog_tx_frame(l, &sym);
	}
}
