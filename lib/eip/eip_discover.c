/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip_list.c - df1_eip_list_identity(): who is there at an eip:// target
 * (df1mon --who). ListIdentity (encapsulation command 63h) needs no session:
 * over TCP to the host, or, when the host is a broadcast address, in one UDP
 * datagram to port 44818 (or the one given) and every answer until the
 * timeout (df1-eip(7)).
 */
#include "df1_int.h"

#include <arpa/inet.h>
#include <errno.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <unistd.h>

#include "eip/eip_codec.h"

/* "eip://host[:port][/...]" -> host, port text. 0 or DF1_E_INVAL. */
static int list_parse(struct df1 *h, const char *target, char *host, size_t hcap, char *port,
                      size_t pcap)
{
	const char *p = target, *hs, *he, *colon = NULL, *end;
	size_t n;

	if (strncasecmp(p, "eip:", 4) != 0)
		goto bad;
	p += 4;
	if (strncmp(p, "//", 2) == 0)
		p += 2;
	if (*p == '[') {
		hs = p + 1;
		he = strchr(hs, ']');
		if (!he)
			goto bad;
		end = he + 1;
		if (*end == ':')
			colon = end;
	} else {
		hs = p;
		he = hs + strcspn(hs, ":/");
		end = he;
		if (*he == ':')
			colon = he;
	}
	n = (size_t)(he - hs);
	if (n == 0 || n >= hcap)
		goto bad;
	memcpy(host, hs, n);
	host[n] = '\0';
	snprintf(port, pcap, "%d", EIP_PORT);
	if (colon) {
		char *e;
		long v = strtol(colon + 1, &e, 10);

		if (colon[1] < '0' || colon[1] > '9' || v < 1 || v > 65535 || (*e && *e != '/'))
			goto bad;
		snprintf(port, pcap, "%ld", v);
	} else if (*end && *end != '/') {
		goto bad;
	}
	return 0;
bad:
	return df1_fail(h, DF1_E_INVAL, -1, "invalid EtherNet/IP target \"%s\": expected "
	                "eip://HOST[:PORT]", target);
}

/* 255.255.255.255, or the broadcast address of a local interface. */
static bool list_is_broadcast(struct in_addr a)
{
	struct ifaddrs *ifs, *i;
	bool yes = a.s_addr == htonl(INADDR_BROADCAST);

	if (yes || getifaddrs(&ifs) < 0)
		return yes;
	for (i = ifs; i && !yes; i = i->ifa_next)
		if ((i->ifa_flags & IFF_BROADCAST) && i->ifa_broadaddr &&
		    i->ifa_broadaddr->sa_family == AF_INET &&
		    ((struct sockaddr_in *)(void *)i->ifa_broadaddr)->sin_addr.s_addr == a.s_addr)
			yes = true;
	freeifaddrs(ifs);
	return yes;
}

static void list_request(uint8_t req[EIP_HDR_LEN])
{
	struct eip_hdr hd;

	memset(&hd, 0, sizeof hd);
	hd.command = EIP_CMD_LIST_IDENTITY;
	memcpy(hd.context, "df1who\0\0", 8);
	(void)eip_hdr_build(req, EIP_HDR_LEN, &hd);
}

/* The identity items of one reply; from = who sent it. Returns the number
 * reported, 0 for a message that is not a good ListIdentity reply. */
static int list_report(const uint8_t *msg, size_t n, const char *from_ip, const char *port,
                       df1_eip_device_fn fn, void *user)
{
	struct eip_hdr hd;
	struct eip_cpf cpf;
	int found = 0;

	if (eip_hdr_parse(&hd, msg, n) < 0 || hd.command != EIP_CMD_LIST_IDENTITY ||
	    hd.status != EIP_ST_SUCCESS || (size_t)hd.length + EIP_HDR_LEN != n ||
	    eip_cpf_parse(&cpf, msg + EIP_HDR_LEN, hd.length) < 0)
		return 0;
	for (unsigned i = 0; i < cpf.count && i < EIP_CPF_ITEMS_MAX; i++) {
		struct eip_identity id;
		struct df1_eip_device d;

		if (cpf.item[i].type != EIP_ITEM_LIST_IDENTITY ||
		    eip_identity_parse(&id, cpf.item[i].data, cpf.item[i].len) < 0)
			continue;
		memset(&d, 0, sizeof d);
		if (id.sin_port)
			snprintf(d.address, sizeof d.address, "%s:%u", from_ip, (unsigned)id.sin_port);
		else
			snprintf(d.address, sizeof d.address, "%s:%s", from_ip, port);
		d.vendor_id = id.vendor_id;
		d.device_type = id.device_type;
		d.product_code = id.product_code;
		d.rev_major = id.rev_major;
		d.rev_minor = id.rev_minor;
		d.status = id.status;
		d.serial = id.serial;
		memcpy(d.product_name, id.product_name, sizeof d.product_name);
		d.product_name[sizeof d.product_name - 1] = '\0';
		d.state = id.state;
		if (fn)
			fn(user, &d);
		found++;
	}
	return found;
}

/* UDP broadcast: every answer until the deadline. */
static int list_udp(struct df1 *h, struct in_addr a, const char *port, int64_t deadline_ms,
                    df1_eip_device_fn fn, void *user)
{
	struct sockaddr_in to;
	uint8_t req[EIP_HDR_LEN], msg[600];
	int fd, one = 1, found = 0, r;

	fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
	if (fd < 0)
		return port_fail_sys(h, DF1_E_SYS, errno, "socket for");
	(void)setsockopt(fd, SOL_SOCKET, SO_BROADCAST, &one, sizeof one);
	memset(&to, 0, sizeof to);
	to.sin_family = AF_INET;
	to.sin_addr = a;
	to.sin_port = htons((uint16_t)atoi(port));
	list_request(req);
	if (sendto(fd, req, sizeof req, 0, (struct sockaddr *)&to, sizeof to) < 0) {
		r = port_fail_sys(h, DF1_E_SYS, errno, "ListIdentity broadcast to");
		close(fd);
		return r;
	}
	df1_count_n(h, DF1_ID_CRD_CHAR_SENT, sizeof req);
	for (;;) {
		struct sockaddr_in from;
		socklen_t fl = sizeof from;
		char ip[INET_ADDRSTRLEN];
		ssize_t n;

		r = port_wait(h, fd, POLLIN, deadline_ms);
		if (r <= 0)
			break;
		n = recvfrom(fd, msg, sizeof msg, 0, (struct sockaddr *)&from, &fl);
		if (n < 0) {
			if (errno == EAGAIN || errno == EINTR || errno == ECONNREFUSED)
				continue;
			r = port_fail_sys(h, DF1_E_SYS, errno, "recvfrom on");
			break;
		}
		df1_count_n(h, DF1_ID_CRD_CHAR_RECV, (uint64_t)n);
		inet_ntop(AF_INET, &from.sin_addr, ip, sizeof ip);
		found += list_report(msg, (size_t)n, ip, port, fn, user);
	}
	close(fd);
	return r < 0 ? r : found;
}

/* TCP: one request, one reply. */
static int list_tcp(struct df1 *h, const char *host, const char *port, int timeout_ms,
                    df1_eip_device_fn fn, void *user)
{
	int64_t deadline_ms;
	char t[280];
	uint8_t req[EIP_HDR_LEN], msg[600];
	size_t got = 0, want = EIP_HDR_LEN;
	int r;

	snprintf(t, sizeof t, strchr(host, ':') ? "eip://[%s]:%s" : "eip://%s:%s", host, port);
	r = port_tcp_ops.open(h, t);
	if (r < 0)
		return r;
	deadline_ms = df1_now_ms() + timeout_ms; /* the reply's wait starts once connected */
	list_request(req);
	r = (int)port_send_fd(h, req, sizeof req, deadline_ms);
	while (r >= 0 && got < want) {
		ssize_t n = port_read_fd(h, msg + got, want - got, deadline_ms);

		if (n <= 0) {
			r = n < 0 ? (int)n
			          : df1_fail(h, DF1_E_TIMEOUT, -1, "%s: no ListIdentity reply",
			                     h->port_name);
			break;
		}
		got += (size_t)n;
		if (got == EIP_HDR_LEN) {
			want = eip_msg_len(msg, got);
			if (want > sizeof msg)
				r = df1_fail(h, DF1_E_EIP, -1, "%s: ListIdentity reply of %zu bytes",
				             h->port_name, want);
		}
	}
	if (r >= 0) {
		r = list_report(msg, got, host, port, fn, user);
		if (r == 0)
			r = df1_fail(h, DF1_E_BAD_REPLY, -1, "%s: malformed ListIdentity reply",
			             h->port_name);
	}
	port_tcp_ops.close(h);
	h->fd = -1;
	return r;
}

int df1_eip_list_identity(df1_t *h, const char *target, int timeout_ms, df1_eip_device_fn fn,
                          void *user)
{
	char host[256], port[8];
	struct in_addr a;
	int r;

	if (!h)
		return DF1_E_INVAL;
	if (!target)
		return df1_fail(h, DF1_E_INVAL, -1, "no EtherNet/IP target given");
	if (h->port)
		return df1_fail(h, DF1_E_INVAL, -1, "df1_eip_list_identity: the handle is open on %s",
		                h->port_name);
	if (timeout_ms < 0)
		return df1_fail(h, DF1_E_INVAL, -1, "invalid timeout %d ms", timeout_ms);
	r = list_parse(h, target, host, sizeof host, port, sizeof port);
	if (r < 0)
		return r;
	df1_clear_error(h);
	snprintf(h->port_name, sizeof h->port_name, "%.100s:%s", host, port);
	if (inet_pton(AF_INET, host, &a) == 1 && list_is_broadcast(a))
		return list_udp(h, a, port, df1_now_ms() + timeout_ms, fn, user);
	return list_tcp(h, host, port, timeout_ms, fn, user);
}
