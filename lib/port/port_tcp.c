/* SPDX-License-Identifier: MPL-2.0 */
/*
 * port_tcp.c - raw DF1 over a TCP connection (a serial device server, df1sim
 * --listen): "tcp://host:port", "tcp://192.168.1.20:2101", "tcp://[::1]:2222";
 * the scheme in any case ("TCP://host:port"), "tcp:host:port" too. The same
 * connection carries EtherNet/IP for an "eip://host[:port]" target (the link's
 * lib/eip/eip_link.c opens it so): there the port may be left out, 44818.
 *
 * The connect is non-blocking and bounded by a deadline of the handle's
 * timeout (at least 1000 ms), trying each address getaddrinfo() returns;
 * name resolution itself is getaddrinfo()'s and not bounded by it. The socket
 * gets TCP_NODELAY (DF1 symbols are tiny and latency-bound) and SO_KEEPALIVE.
 * EOF from the peer is DF1_E_CLOSED. A listen-only handle (DF1_OPT_LISTEN_ONLY)
 * connects the same way, with the same deadline, then shuts down its sending
 * side (shutdown(SHUT_WR)). The backend keeps no state but the descriptor.
 */
#include "port/port.h"

#include <errno.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <unistd.h>

#include "df1_int.h"

#define TCP_MIN_CONNECT_MS 1000
#define EIP_TCP_PORT 44818        /* EtherNet/IP encapsulation (df1-eip(7)) */

/* Split "host:port" / "[v6]:port" (after the scheme); with eip, "host" and
 * "[v6]" alone too (port 44818). 0 or DF1_E_INVAL. */
static int tcp_parse(struct df1 *h, const char *target, const char *rest, bool eip, char *host,
                     size_t hcap, char *port, size_t pcap)
{
	const char *colon, *hs = rest, *he;
	char *end;
	long num;

	if (*rest == '[') {
		hs = rest + 1;
		he = strchr(hs, ']');
		if (!he || (he[1] != ':' && !(eip && (he[1] == '\0' || strcmp(he + 1, "/") == 0))))
			goto bad;
		colon = he + 1;
	} else {
		colon = strrchr(rest, ':');
		if (!colon && eip) {
			colon = rest + strlen(rest);
			if (colon > rest && colon[-1] == '/')
				colon--;
		}
		if (!colon)
			goto bad;
		he = colon;
		if (memchr(hs, ':', (size_t)(he - hs))) /* bare IPv6 literal: needs [] */
			goto bad;
	}
	if (he == hs || (size_t)(he - hs) >= hcap)
		goto bad;
	memcpy(host, hs, (size_t)(he - hs));
	host[he - hs] = '\0';
	if (eip && *colon != ':') {
		snprintf(port, pcap, "%d", EIP_TCP_PORT);
		return 0;
	}
	errno = 0;
	num = strtol(colon + 1, &end, 10);
	if (colon[1] < '0' || colon[1] > '9' || errno || num < 1 || num > 65535 ||
	    (*end != '\0' && strcmp(end, "/") != 0))
		goto bad;
	snprintf(port, pcap, "%ld", num);
	return 0;
bad:
	if (eip)
		return df1_fail(h, DF1_E_INVAL, -1,
		                "invalid EtherNet/IP target \"%s\": expected eip://HOST[:PORT] or "
		                "eip://[IPv6][:PORT] (port 1..65535, default 44818)", target);
	return df1_fail(h, DF1_E_INVAL, -1,
	                "invalid TCP target \"%s\": expected tcp://HOST:PORT or tcp://[IPv6]:PORT "
	                "(port 1..65535)", target);
}

static int tcp_connect_one(struct df1 *h, const struct addrinfo *ai, int64_t deadline_ms,
                           int *fd_out, int *err_out)
{
	int fd, r, soerr = 0;
	socklen_t len = sizeof soerr;

	fd = socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol);
	if (fd < 0) {
		*err_out = errno;
		return 0;
	}
	if (connect(fd, ai->ai_addr, ai->ai_addrlen) == 0) {
		*fd_out = fd;
		return 1;
	}
	if (errno != EINPROGRESS) {
		*err_out = errno;
		close(fd);
		return 0;
	}
	r = port_wait(h, fd, POLLOUT, deadline_ms);
	if (r <= 0) {
		close(fd);
		if (r == 0)
			*err_out = ETIMEDOUT;
		return r; /* 0: deadline; < 0: cancelled or poll failed */
	}
	if (getsockopt(fd, SOL_SOCKET, SO_ERROR, &soerr, &len) < 0)
		soerr = errno;
	if (soerr) {
		*err_out = soerr;
		close(fd);
		return 0;
	}
	*fd_out = fd;
	return 1;
}

static int tcp_open(struct df1 *h, const char *target)
{
	char host[256], port[8];
	struct addrinfo hints, *res = NULL, *ai;
	const char *rest = target;
	bool eip = strncasecmp(target, "eip:", 4) == 0;
	int r, fd = -1, err = ECONNREFUSED, one = 1;
	int wait_ms = h->cfg.timeout_ms > TCP_MIN_CONNECT_MS ? h->cfg.timeout_ms : TCP_MIN_CONNECT_MS;
	int64_t deadline_ms = df1_now_ms() + wait_ms;

	snprintf(h->port_name, sizeof h->port_name, "%s", target);
	if (strncasecmp(rest, "tcp:", 4) == 0 || eip) /* the scheme in any case */
		rest += 4;
	if (strncmp(rest, "//", 2) == 0)
		rest += 2;
	r = tcp_parse(h, target, rest, eip, host, sizeof host, port, sizeof port);
	if (r < 0)
		return r;
	snprintf(h->port_name, sizeof h->port_name, strchr(host, ':') ? "[%s]:%s" : "%s:%s",
	         host, port);

	memset(&hints, 0, sizeof hints);
	hints.ai_family = AF_UNSPEC;
	hints.ai_socktype = SOCK_STREAM;
	hints.ai_flags = AI_NUMERICSERV;
	r = getaddrinfo(host, port, &hints, &res);
	if (r != 0) {
		if (r == EAI_SYSTEM)
			return port_fail_sys(h, DF1_E_SYS, errno, "cannot resolve");
		return df1_fail(h, DF1_E_NODEV, -1, "cannot resolve host %s: %s", host,
		                gai_strerror(r));
	}
	for (ai = res; ai; ai = ai->ai_next) {
		r = tcp_connect_one(h, ai, deadline_ms, &fd, &err);
		if (r != 0 || err == ETIMEDOUT)
			break;
	}
	freeaddrinfo(res);
	if (r < 0)
		return r;
	if (r == 0) {
		if (err == ETIMEDOUT) {
			errno = ETIMEDOUT;
			return df1_fail(h, DF1_E_SYS, -1, "cannot connect to %s: no answer within %d ms",
			                h->port_name, wait_ms);
		}
		return port_fail_sys(h, DF1_E_SYS, err, "cannot connect to");
	}
	(void)setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
	(void)setsockopt(fd, SOL_SOCKET, SO_KEEPALIVE, &one, sizeof one);
	/* listen only: our half of the connection is closed for sending, so not
	 * even a bug could put a byte on the line (the peer sees our FIN). */
	if (h->cfg.listen_only && shutdown(fd, SHUT_WR) < 0) {
		err = errno;
		close(fd);
		return port_fail_sys(h, DF1_E_SYS, err, "shutdown(SHUT_WR) on");
	}
	h->fd = fd;
	return 0;
}

/* A configuration file's target (lib/config/config_net.c Com_Port), what
 * follows "tcp://": HOST:PORT, a decimal port 1..65535, no '/'. Looser than
 * tcp_parse on a bare IPv6 literal ("a:b:502" passes here; opening it fails). */
static bool tcp_config_ok(const char *rest)
{
	const char *colon = strrchr(rest, ':');
	long port = 0;

	if (!colon || colon == rest || strchr(rest, '/') || !colon[1])
		return false;
	for (const char *d = colon + 1; *d; d++) {
		if (*d < '0' || *d > '9' || port > 65535)
			return false;
		port = port * 10 + (*d - '0');
	}
	return port >= 1 && port <= 65535;
}

static void tcp_close(struct df1 *h)
{
	if (h->fd >= 0)
		close(h->fd);
	h->fd = -1;
}

const struct port_ops port_tcp_ops = {
	.name = "tcp",
	.net_slack = true,          /* a device server's network: lib/link/half.c */
	.serial_behind_net = true,  /* raw DF1 to a serial line behind it */
	.open = tcp_open,
	.close = tcp_close,
	.read = port_read_fd,
	.write = port_send_fd,  /* send(MSG_NOSIGNAL): a gone peer is DF1_E_CLOSED, no SIGPIPE */
	.configure = NULL, /* serial settings do not apply */
	.drain = NULL,
	.config_ok = tcp_config_ok,
};
