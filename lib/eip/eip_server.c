/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip_server - the EtherNet/IP server of df1_eip_server(3): a TCP listener and
 * a UDP socket (ListIdentity) on one port, its clients, the allow list and
 * read-only refusal, all behind one epoll descriptor for the caller's loop.
 * Each connection's protocol is lib/eip/eip_session.c; this file moves
 * bytes and keeps the requests handed to the caller.
 *
 * Fairness: a client has at most one PCCC request outstanding and one message
 * in work; a process() call takes at most one message per client, so clients
 * are served in turn. A client whose replies are not read stops being read
 * (its output is kept, up to EIP_OUT_MAX, then it is closed).
 *
 * Limits (lib/eip/eip_limits.c decides, this file applies): a connection that
 * registers no session in time, or whose session stays idle, is closed, and a
 * full table makes room for a new client; a timerfd in the epoll set wakes the
 * caller at the next deadline.
 */
#include "df1_int.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include "eip/eip_codec.h"
#include "eip/eip_limits.h"
#include "eip/eip_session.h"

#define EIP_CLIENTS_DEFAULT 32
#define EIP_CLIENTS_MAX 255
#define EIP_ALLOW_MAX 16
#define EIP_OUT_MAX (4 * EIP_SESSION_MSG_MAX)
#define EIP_PCCC_REPLY_MAX 4000
/* epoll data: which socket; clients are their slot number */
#define TAG_LISTEN 0x10000u
#define TAG_UDP 0x10001u
#define TAG_KICK 0x10002u
#define TAG_TIMER 0x10003u

struct eip_net {
	int family;
	uint8_t addr[16];
	int bits;
};

struct eip_client {
	int fd;                        /* -1: slot free */
	uint32_t seq;                  /* request ids: seq << 8 | slot, seq counts per slot */
	uint32_t first_seq;            /* the first seq of the client now in the slot */
	struct eip_session sess;
	struct eip_identity id;        /* with this connection's local address */
	uint8_t in[EIP_SESSION_MSG_MAX];
	size_t in_len;
	bool discard;                  /* a length over the limit: answered, closing */
	uint8_t *out;                  /* EIP_OUT_MAX */
	size_t out_len;
	bool close_after;              /* close once out is sent */
	bool waiting;                  /* a PCCC request is with the caller */
	uint32_t request;
	struct eip_pending pend;
	uint32_t events;               /* what epoll watches now */
	struct eip_age age;            /* for the limits */
	char peer[64];                 /* "ADDR:PORT" for on_close */
};

struct df1_eip_server {
	int ep, lfd, ufd, kick, tfd;
	df1_eip_pccc_fn fn;
	void *user;
	bool read_only;
	int max_clients;
	struct eip_net allow[EIP_ALLOW_MAX];
	int allow_n;
	struct eip_identity id;
	struct eip_client *cl;
	uint32_t next_handle;
	struct df1_eip_server_stats st;
	struct eip_limits lim;
	df1_eip_close_fn on_close;
	void *close_user;
	struct df1_eip_server_closes closes;
	int64_t armed;                 /* the timerfd's deadline now (EIP_NO_DEADLINE: disarmed) */
	char addr[64];
	char err[160];
	uint8_t reply[EIP_SESSION_MSG_MAX];
};

static _Thread_local char new_err[160];

static int srv_err(struct df1_eip_server *s, int code, const char *fmt, ...)
{
	char *buf = s ? s->err : new_err;
	size_t cap = s ? sizeof s->err : sizeof new_err;
	int saved = errno;
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(buf, cap, fmt, ap);
	va_end(ap);
	errno = saved;
	return code;
}

/* ------------------------------------------------------------------------
 * Configuration: listen address, allow list
 * ------------------------------------------------------------------------ */

static int parse_net(struct eip_net *n, const char *text, size_t len)
{
	char buf[64], *slash;
	int max;

	if (len == 0 || len >= sizeof buf)
		return -1;
	memcpy(buf, text, len);
	buf[len] = '\0';
	slash = strchr(buf, '/');
	if (slash)
		*slash++ = '\0';
	memset(n, 0, sizeof *n);
	if (inet_pton(AF_INET, buf, n->addr) == 1) {
		n->family = AF_INET;
		max = 32;
	} else if (inet_pton(AF_INET6, buf, n->addr) == 1) {
		n->family = AF_INET6;
		max = 128;
	} else {
		return -1;
	}
	n->bits = max;
	if (slash) {
		char *end;
		long b = strtol(slash, &end, 10);

		if (!*slash || *end || b < 0 || b > max)
			return -1;
		n->bits = (int)b;
	}
	return 0;
}

static int parse_allow(struct df1_eip_server *s, const char *allow)
{
	const char *p = allow;

	while (*p) {
		const char *e = strchr(p, ',');
		size_t len = e ? (size_t)(e - p) : strlen(p);

		if (s->allow_n == EIP_ALLOW_MAX)
			return srv_err(NULL, DF1_E_INVAL, "allow list: more than %d networks", EIP_ALLOW_MAX);
		if (parse_net(&s->allow[s->allow_n], p, len) != 0)
			return srv_err(NULL, DF1_E_INVAL, "allow list: \"%.*s\" is not ADDR or ADDR/BITS", (int)len, p);
		s->allow_n++;
		p += len;
		if (*p == ',')
			p++;
	}
	if (s->allow_n == 0)
		return srv_err(NULL, DF1_E_INVAL, "allow list: empty");
	return 0;
}

static bool net_match(const struct eip_net *n, int family, const uint8_t *a)
{
	int full = n->bits / 8, rest = n->bits % 8;

	if (n->family != family)
		return false;
	if (memcmp(n->addr, a, (size_t)full) != 0)
		return false;
	return !rest || ((n->addr[full] ^ a[full]) & (0xFF << (8 - rest))) == 0;
}

static bool allowed(const struct df1_eip_server *s, const struct sockaddr_storage *ss)
{
	const uint8_t *a;
	int family = ss->ss_family;
	uint8_t v4[4];

	if (s->allow_n == 0)
		return true;
	if (family == AF_INET) {
		a = (const uint8_t *)&((const struct sockaddr_in *)ss)->sin_addr;
	} else if (family == AF_INET6) {
		a = (const uint8_t *)&((const struct sockaddr_in6 *)ss)->sin6_addr;
		if (IN6_IS_ADDR_V4MAPPED((const struct in6_addr *)a)) {
			memcpy(v4, a + 12, 4);
			a = v4;
			family = AF_INET;
		}
	} else {
		return false;
	}
	for (int i = 0; i < s->allow_n; i++)
		if (net_match(&s->allow[i], family, a))
			return true;
	return false;
}

/* "[ADDR:]PORT", "[v6]:PORT": host (or "127.0.0.1") and port text. */
static int split_listen(const char *where, char *host, size_t hcap, char *port, size_t pcap)
{
	const char *colon = strrchr(where, ':');
	const char *h = "127.0.0.1", *p = where;
	size_t hl = strlen(h);

	if (colon) {
		h = where;
		hl = (size_t)(colon - where);
		p = colon + 1;
		if (hl >= 2 && h[0] == '[' && h[hl - 1] == ']') {
			h++;
			hl -= 2;
		}
	}
	if (!*p || strlen(p) >= pcap || hl == 0 || hl >= hcap || strspn(p, "0123456789") != strlen(p) ||
	    atol(p) > 65535)
		return -1;
	memcpy(host, h, hl);
	host[hl] = '\0';
	strcpy(port, p);
	return 0;
}

static int ep_add(struct df1_eip_server *s, int fd, uint32_t tag, uint32_t events)
{
	struct epoll_event ev;

	memset(&ev, 0, sizeof ev);
	ev.events = events;
	ev.data.u32 = tag;
	return epoll_ctl(s->ep, EPOLL_CTL_ADD, fd, &ev);
}

/* 0.0.0.0 or ::, however the resolver was given it (0, 0x0 ...). */
static bool is_wildcard(const struct sockaddr *sa)
{
	if (sa->sa_family == AF_INET)
		return ((const struct sockaddr_in *)sa)->sin_addr.s_addr == htonl(INADDR_ANY);
	return sa->sa_family == AF_INET6 &&
	       IN6_IS_ADDR_UNSPECIFIED(&((const struct sockaddr_in6 *)sa)->sin6_addr);
}

/* TCP listener and UDP socket on the same address and port. */
static int open_sockets(struct df1_eip_server *s, const char *where)
{
	char host[64], port[8];
	struct addrinfo hints, *res = NULL;
	struct sockaddr_storage ss;
	socklen_t sl = sizeof ss;
	int one = 1, rc;

	if (!where || split_listen(where, host, sizeof host, port, sizeof port) != 0)
		return srv_err(NULL, DF1_E_INVAL, "listen address \"%s\": expected [ADDR:]PORT", where ? where : "");
	memset(&hints, 0, sizeof hints);
	hints.ai_family = AF_UNSPEC;
	hints.ai_socktype = SOCK_STREAM;
	hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
	rc = getaddrinfo(host, port, &hints, &res);
	if (rc != 0 || !res)
		return srv_err(NULL, DF1_E_INVAL, "listen address \"%s\": %s", where, gai_strerror(rc));
	if (is_wildcard(res->ai_addr) && strcmp(host, "0.0.0.0") != 0 && strcmp(host, "::") != 0) {
		freeaddrinfo(res);
		return srv_err(NULL, DF1_E_INVAL, "listen address \"%s\": every interface only as 0.0.0.0 or ::"
		               " written out", where);
	}
	s->lfd = socket(res->ai_family, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
	if (s->lfd < 0)
		goto sys;
	(void)setsockopt(s->lfd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
	if (bind(s->lfd, res->ai_addr, res->ai_addrlen) != 0 || listen(s->lfd, 16) != 0)
		goto sys;
	if (getsockname(s->lfd, (struct sockaddr *)&ss, &sl) != 0)
		goto sys;
	/* UDP on the port TCP got (an ephemeral one too) */
	s->ufd = socket(res->ai_family, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
	if (s->ufd < 0 || bind(s->ufd, (struct sockaddr *)&ss, sl) != 0)
		goto sys;
	freeaddrinfo(res);
	if (ss.ss_family == AF_INET) {
		const struct sockaddr_in *in = (const struct sockaddr_in *)&ss;
		char a[INET_ADDRSTRLEN];

		inet_ntop(AF_INET, &in->sin_addr, a, sizeof a);
		snprintf(s->addr, sizeof s->addr, "%s:%u", a, ntohs(in->sin_port));
		s->id.sin_family = AF_INET;
		s->id.sin_port = ntohs(in->sin_port);
		s->id.sin_addr = ntohl(in->sin_addr.s_addr);
	} else {
		const struct sockaddr_in6 *in6 = (const struct sockaddr_in6 *)&ss;
		char a[INET6_ADDRSTRLEN];

		inet_ntop(AF_INET6, &in6->sin6_addr, a, sizeof a);
		snprintf(s->addr, sizeof s->addr, "[%s]:%u", a, ntohs(in6->sin6_port));
		s->id.sin_family = AF_INET;
		s->id.sin_port = ntohs(in6->sin6_port);
	}
	return 0;
sys:
	rc = errno;
	freeaddrinfo(res);
	errno = rc;
	return srv_err(NULL, DF1_E_SYS, "EtherNet/IP server on %s: %s", where, strerror(rc));
}

/* ------------------------------------------------------------------------
 * Clients
 * ------------------------------------------------------------------------ */

static void watch(struct df1_eip_server *s, struct eip_client *c, int slot)
{
	uint32_t ev = 0;
	struct epoll_event e;

	if (c->out_len)
		ev |= EPOLLOUT;
	else if (!c->waiting && !c->close_after)
		ev |= EPOLLIN;
	if (c->waiting)
		ev |= EPOLLRDHUP;     /* a client gone while the caller works: its answer goes nowhere */
	if (ev == c->events)
		return;
	memset(&e, 0, sizeof e);
	e.events = ev;
	e.data.u32 = (uint32_t)slot;
	if (epoll_ctl(s->ep, EPOLL_CTL_MOD, c->fd, &e) == 0)
		c->events = ev;
}

static void client_close(struct df1_eip_server *s, struct eip_client *c)
{
	if (c->fd < 0)
		return;
	if (c->sess.registered && s->st.sessions_open)
		s->st.sessions_open--;
	epoll_ctl(s->ep, EPOLL_CTL_DEL, c->fd, NULL);
	close(c->fd);
	c->fd = -1;
	c->waiting = false;
	c->in_len = c->out_len = 0;
}

/* Send what is queued; false if the client is gone. */
static bool client_flush(struct df1_eip_server *s, struct eip_client *c)
{
	while (c->out_len) {
		ssize_t w = send(c->fd, c->out, c->out_len, MSG_NOSIGNAL | MSG_DONTWAIT);

		if (w < 0 && errno == EINTR)
			continue;
		if (w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
			return true;
		if (w <= 0) {
			client_close(s, c);
			return false;
		}
		memmove(c->out, c->out + w, c->out_len - (size_t)w);
		c->out_len -= (size_t)w;
	}
	if (c->close_after) {
		client_close(s, c);
		return false;
	}
	return true;
}

/* Is this reply an error (encapsulation or CIP status)? For the counters. */
static bool reply_is_error(const uint8_t *msg, size_t n)
{
	struct eip_hdr h;
	struct eip_cpf cpf;
	struct eip_packet pk;
	struct cip_resp r;
	uint16_t t;

	if (eip_hdr_parse(&h, msg, n) != 0 || h.status != 0)
		return true;
	if (h.command != EIP_CMD_SEND_RR_DATA && h.command != EIP_CMD_SEND_UNIT_DATA)
		return false;
	if (eip_rr_parse(&t, &cpf, msg + EIP_HDR_LEN, n - EIP_HDR_LEN) != 0 || eip_packet_parse(&pk, &cpf) != 0 ||
	    cip_resp_parse(&r, pk.data, pk.len) != 0)
		return true;
	return r.status != 0;
}

static void client_queue(struct df1_eip_server *s, struct eip_client *c, const uint8_t *msg, size_t n)
{
	if (reply_is_error(msg, n))
		s->st.errors++;
	if (c->out_len + n > EIP_OUT_MAX) {     /* the client does not read its replies */
		client_close(s, c);
		return;
	}
	memcpy(c->out + c->out_len, msg, n);
	c->out_len += n;
}

/* The PCCC reply a PLC gives for a protected command: STS 60. */
static size_t read_only_reply(uint8_t *out, const uint8_t *pccc)
{
	out[0] = (uint8_t)(pccc[0] | 0x40);
	out[1] = 0x60;
	out[2] = pccc[2];
	out[3] = pccc[3];
	return 4;
}

/* One whole message of client c (at c->in). Returns true if a PCCC request
 * went to the caller. */
static bool client_message(struct df1_eip_server *s, struct eip_client *c, int slot, size_t n)
{
	size_t out_len = 0;
	bool was = c->sess.registered;
	enum eip_verdict v = eip_session_input(&c->sess, &c->id, false, c->in, n, s->reply, sizeof s->reply,
	                                       &out_len, &c->pend);

	s->st.requests++;
	if (c->sess.registered && !was) {
		s->st.sessions++;
		s->st.sessions_open++;
	}
	switch (v) {
	case EIP_SEND_CLOSE:
		c->close_after = true;
		s->st.errors++;
		/* fall through */
	case EIP_SEND:
		client_queue(s, c, s->reply, out_len);
		return false;
	case EIP_SILENT:
		return false;
	case EIP_CLOSE:
		client_close(s, c);
		return false;
	case EIP_PCCC:
		break;
	}
	if (s->read_only && df1_pccc_is_write(c->pend.pccc, c->pend.len)) {
		uint8_t pr[4];
		int len;

		s->st.read_only_refusals++;
		len = eip_session_reply(&c->pend, 0, 0, pr, read_only_reply(pr, c->pend.pccc), s->reply,
		                        sizeof s->reply);
		if (len > 0)
			client_queue(s, c, s->reply, (size_t)len);
		return false;
	}
	c->waiting = true;
	c->seq = (c->seq + 1) & 0xFFFFFF;
	c->request = c->seq << 8 | (uint32_t)slot;
	/* the command stays in c->in until the message is consumed */
	s->fn(s->user, s, c->request, c->pend.station, c->pend.pccc, c->pend.len);
	return true;
}

/* Drop the message handled from the input buffer. */
static void consume(struct eip_client *c, size_t n)
{
	memmove(c->in, c->in + n, c->in_len - n);
	c->in_len -= n;
}

/* Handle one complete message in c->in, if there is one. Returns 1 if one
 * was handled (PCCC request or not), 0 if more bytes are needed. */
static int client_step(struct df1_eip_server *s, struct eip_client *c, int slot, int *handed)
{
	size_t need;

	if (c->fd < 0 || c->waiting || c->close_after || c->out_len || c->in_len < EIP_HDR_LEN)
		return 0;
	need = eip_msg_len(c->in, c->in_len);
	if (need > EIP_SESSION_MSG_MAX) {
		client_message(s, c, slot, EIP_HDR_LEN);   /* status 0x0065 and close */
		c->in_len = 0;
		return 1;
	}
	if (c->in_len < need)
		return 0;
	if (client_message(s, c, slot, need)) {
		(*handed)++;
		/* c->in keeps the command for the callback; dropped when answered */
		return 1;
	}
	if (c->fd >= 0)
		consume(c, need);
	return 1;
}

static void client_read(struct df1_eip_server *s, struct eip_client *c, int slot, int *handed)
{
	ssize_t r;

	if (c->in_len < sizeof c->in) {
		r = recv(c->fd, c->in + c->in_len, sizeof c->in - c->in_len, MSG_DONTWAIT);
		if (r == 0 || (r < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
			client_close(s, c);
			return;
		}
		if (r > 0) {
			c->in_len += (size_t)r;
			c->age.last_ms = df1_now_ms();
		}
	}
	client_step(s, c, slot, handed);
	if (c->fd >= 0 && client_flush(s, c))
		watch(s, c, slot);
}

/* ------------------------------------------------------------------------
 * Limits: closes for time, eviction, the timer (eip_limits.h)
 * ------------------------------------------------------------------------ */

static const struct eip_age *age_of(struct eip_client *c)
{
	c->age.registered = c->sess.registered;
	c->age.busy = c->waiting;
	return &c->age;
}

static void limit_close(struct df1_eip_server *s, struct eip_client *c, enum df1_eip_close_reason why)
{
	if (why == DF1_EIP_CLOSE_NO_SESSION)
		s->closes.no_session++;
	else if (why == DF1_EIP_CLOSE_IDLE)
		s->closes.idle++;
	else
		s->closes.evicted++;
	if (s->on_close)
		s->on_close(s->close_user, c->peer, why);
	client_close(s, c);
}

/* Full table: close the connection eip_age_before() puts first; its slot, or -1. */
static int evict(struct df1_eip_server *s)
{
	int victim = -1;

	if (s->lim.no_evict)
		return -1;
	for (int i = 0; i < s->max_clients; i++) {
		if (s->cl[i].fd < 0 || s->cl[i].waiting)
			continue;
		if (victim < 0 || eip_age_before(age_of(&s->cl[i]), age_of(&s->cl[victim])))
			victim = i;
	}
	if (victim >= 0)
		limit_close(s, &s->cl[victim], DF1_EIP_CLOSE_EVICTED);
	return victim;
}

static void arm(struct df1_eip_server *s, int64_t at)
{
	struct itimerspec t;

	if (at == s->armed)
		return;
	memset(&t, 0, sizeof t);
	if (at != EIP_NO_DEADLINE) {
		t.it_value.tv_sec = (time_t)(at / 1000);
		t.it_value.tv_nsec = (long)(at % 1000) * 1000000L;
	}
	if (timerfd_settime(s->tfd, TFD_TIMER_ABSTIME, &t, NULL) == 0)
		s->armed = at;
}

/* Close what is due; the timer to the next deadline. */
static void sweep(struct df1_eip_server *s)
{
	int64_t now = df1_now_ms(), next = EIP_NO_DEADLINE;

	for (int i = 0; i < s->max_clients; i++) {
		struct eip_client *c = &s->cl[i];
		int why;

		if (c->fd < 0)
			continue;
		why = eip_age_due(&s->lim, age_of(c), now, &next);
		if (why >= 0)
			limit_close(s, c, (enum df1_eip_close_reason)why);
	}
	arm(s, next);
}

static void peer_text(char *buf, size_t cap, const struct sockaddr_storage *ss)
{
	char a[INET6_ADDRSTRLEN] = "?";

	if (ss->ss_family == AF_INET) {
		const struct sockaddr_in *in = (const struct sockaddr_in *)ss;

		inet_ntop(AF_INET, &in->sin_addr, a, sizeof a);
		snprintf(buf, cap, "%s:%u", a, ntohs(in->sin_port));
	} else if (ss->ss_family == AF_INET6) {
		const struct sockaddr_in6 *in6 = (const struct sockaddr_in6 *)ss;

		inet_ntop(AF_INET6, &in6->sin6_addr, a, sizeof a);
		snprintf(buf, cap, "[%s]:%u", a, ntohs(in6->sin6_port));
	} else {
		snprintf(buf, cap, "?");
	}
}

static void accept_clients(struct df1_eip_server *s)
{
	for (;;) {
		struct sockaddr_storage ss, local;
		socklen_t sl = sizeof ss, ll = sizeof local;
		int fd = accept4(s->lfd, (struct sockaddr *)&ss, &sl, SOCK_CLOEXEC | SOCK_NONBLOCK);
		int slot = -1, one = 1;

		if (fd < 0)
			return;
		for (int i = 0; i < s->max_clients; i++)
			if (s->cl[i].fd < 0) {
				slot = i;
				break;
			}
		if (allowed(s, &ss) && slot < 0)
			slot = evict(s);        /* room for the new client before refusing it */
		if (slot < 0 || !allowed(s, &ss)) {
			s->st.refused_clients++;
			close(fd);
			continue;
		}
		struct eip_client *c = &s->cl[slot];
		(void)setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
		c->fd = fd;
		c->in_len = c->out_len = 0;
		c->close_after = c->waiting = false;
		c->first_seq = (c->seq + 1) & 0xFFFFFF;
		/* a handle of the slot and a running count: unique among open sessions */
		s->next_handle++;
		eip_session_init(&c->sess, (s->next_handle << 8) | (uint32_t)(slot + 1));
		c->id = s->id;
		c->age.opened_ms = c->age.last_ms = df1_now_ms();
		peer_text(c->peer, sizeof c->peer, &ss);
		if (getsockname(fd, (struct sockaddr *)&local, &ll) == 0 && local.ss_family == AF_INET)
			c->id.sin_addr = ntohl(((struct sockaddr_in *)&local)->sin_addr.s_addr);
		c->events = EPOLLIN;
		if (ep_add(s, fd, (uint32_t)slot, EPOLLIN) != 0)
			client_close(s, c);
	}
}

static void udp_read(struct df1_eip_server *s)
{
	uint8_t in[EIP_SESSION_MSG_MAX];

	for (;;) {
		struct sockaddr_storage ss;
		socklen_t sl = sizeof ss;
		struct eip_session tmp;
		struct eip_pending pend;
		size_t out_len = 0;
		ssize_t r = recvfrom(s->ufd, in, sizeof in, MSG_DONTWAIT, (struct sockaddr *)&ss, &sl);

		if (r < 0)
			return;
		if ((size_t)r < EIP_HDR_LEN || !allowed(s, &ss))
			continue;
		s->st.requests++;
		eip_session_init(&tmp, 1);
		if (eip_msg_len(in, (size_t)r) != (size_t)r)
			continue;
		if (eip_session_input(&tmp, &s->id, true, in, (size_t)r, s->reply, sizeof s->reply, &out_len, &pend) ==
		    EIP_SEND)
			(void)sendto(s->ufd, s->reply, out_len, MSG_DONTWAIT, (struct sockaddr *)&ss, sl);
	}
}

/* ------------------------------------------------------------------------
 * Public API
 * ------------------------------------------------------------------------ */

static void kick(struct df1_eip_server *s)
{
	uint64_t one = 1;

	(void)!write(s->kick, &one, sizeof one);
}

/* The identity fields the caller chooses (the address, version and state are ours). */
static void srv_identity(struct df1_eip_server *s, const struct df1_eip_identity *id)
{
	s->id.vendor_id = id->vendor_id;
	s->id.device_type = id->device_type;
	s->id.product_code = id->product_code;
	s->id.rev_major = id->rev_major;
	s->id.rev_minor = id->rev_minor;
	s->id.status = id->status;
	s->id.serial = id->serial;
	memcpy(s->id.product_name, id->product_name, 32);
}

DF1_API int df1_eip_server_new(df1_eip_server_t **out, const struct df1_eip_server_config *c,
                               df1_eip_pccc_fn fn, void *user)
{
	struct df1_eip_server *s;
	int rc;

	new_err[0] = '\0';
	if (!out || !c || !fn)
		return srv_err(NULL, DF1_E_INVAL, "df1_eip_server_new: %s", !fn ? "no PCCC callback" : "no config");
	*out = NULL;
	if (c->max_clients < 0 || c->max_clients > EIP_CLIENTS_MAX)
		return srv_err(NULL, DF1_E_INVAL, "max_clients %d: must be 0 (default) to %d", c->max_clients,
		               EIP_CLIENTS_MAX);
	s = calloc(1, sizeof *s);
	if (!s)
		return srv_err(NULL, DF1_E_NOMEM, "EtherNet/IP server: out of memory");
	s->ep = s->lfd = s->ufd = s->kick = s->tfd = -1;
	s->lim.register_ms = EIP_REGISTER_MS_DEFAULT;
	s->lim.idle_ms = EIP_IDLE_MS_DEFAULT;
	s->armed = EIP_NO_DEADLINE;
	s->fn = fn;
	s->user = user;
	s->read_only = c->read_only;
	s->max_clients = c->max_clients ? c->max_clients : EIP_CLIENTS_DEFAULT;
	s->id.encap_version = EIP_PROTOCOL_VERSION;
	srv_identity(s, &c->identity);
	s->id.state = 3;     /* operational */
	rc = c->allow ? parse_allow(s, c->allow) : 0;
	if (rc == 0) {
		s->cl = calloc((size_t)s->max_clients, sizeof *s->cl);
		if (!s->cl)
			rc = srv_err(NULL, DF1_E_NOMEM, "EtherNet/IP server: out of memory");
	}
	for (int i = 0; rc == 0 && i < s->max_clients; i++) {
		s->cl[i].fd = -1;
		s->cl[i].out = malloc(EIP_OUT_MAX);
		if (!s->cl[i].out)
			rc = srv_err(NULL, DF1_E_NOMEM, "EtherNet/IP server: out of memory");
	}
	if (rc == 0)
		rc = open_sockets(s, c->listen);
	if (rc == 0) {
		s->ep = epoll_create1(EPOLL_CLOEXEC);
		s->kick = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
		s->tfd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
		if (s->ep < 0 || s->kick < 0 || s->tfd < 0 || ep_add(s, s->lfd, TAG_LISTEN, EPOLLIN) != 0 ||
		    ep_add(s, s->ufd, TAG_UDP, EPOLLIN) != 0 || ep_add(s, s->kick, TAG_KICK, EPOLLIN) != 0 ||
		    ep_add(s, s->tfd, TAG_TIMER, EPOLLIN) != 0)
			rc = srv_err(NULL, DF1_E_SYS, "EtherNet/IP server: epoll: %s", strerror(errno));
	}
	if (rc != 0) {
		char keep[sizeof new_err];

		memcpy(keep, new_err, sizeof keep);
		df1_eip_server_free(s);
		memcpy(new_err, keep, sizeof keep);
		return rc;
	}
	*out = s;
	return 0;
}

DF1_API const char *df1_eip_server_address(const df1_eip_server_t *s)
{
	return s ? s->addr : "";
}

DF1_API int df1_eip_server_fd(const df1_eip_server_t *s)
{
	return s ? s->ep : DF1_E_INVAL;
}

DF1_API int df1_eip_server_process(df1_eip_server_t *s)
{
	struct epoll_event ev[16];
	int n, handed = 0;

	if (!s)
		return DF1_E_INVAL;
	n = epoll_wait(s->ep, ev, 16, 0);
	for (int i = 0; i < n; i++) {
		uint32_t tag = ev[i].data.u32;

		if (tag == TAG_LISTEN) {
			accept_clients(s);
		} else if (tag == TAG_UDP) {
			udp_read(s);
		} else if (tag == TAG_KICK || tag == TAG_TIMER) {
			uint64_t v;

			(void)!read(tag == TAG_KICK ? s->kick : s->tfd, &v, sizeof v);
		} else if (tag < (uint32_t)s->max_clients && s->cl[tag].fd >= 0) {
			struct eip_client *c = &s->cl[tag];

			if (c->waiting && (ev[i].events & (EPOLLRDHUP | EPOLLHUP | EPOLLERR))) {
				client_close(s, c);
				continue;
			}
			if ((ev[i].events & EPOLLOUT) && !client_flush(s, c))
				continue;
			if (ev[i].events & (EPOLLIN | EPOLLHUP | EPOLLERR))
				client_read(s, c, (int)tag, &handed);
			else
				watch(s, c, (int)tag);
		}
	}
	/* messages already buffered (a client that sent several at once) */
	for (int i = 0; i < s->max_clients; i++) {
		struct eip_client *c = &s->cl[i];

		if (client_step(s, c, i, &handed) && c->fd >= 0 && client_flush(s, c))
			watch(s, c, i);
		if (c->fd >= 0 && !c->waiting && !c->out_len && c->in_len >= EIP_HDR_LEN &&
		    c->in_len >= eip_msg_len(c->in, c->in_len))
			kick(s);      /* one more whole message: come back */
	}
	sweep(s);
	return handed;
}

static struct eip_client *pending(df1_eip_server_t *s, uint32_t request)
{
	uint32_t slot = request & 0xFF;
	struct eip_client *c;

	if (slot >= (uint32_t)s->max_clients)
		return NULL;
	c = &s->cl[slot];
	return c->fd >= 0 && c->waiting && c->request == request ? c : NULL;
}

static int answer(df1_eip_server_t *s, uint32_t request, int status, const uint8_t *pccc, size_t n)
{
	struct eip_client *c;
	size_t msg;
	int len;

	if (!s)
		return DF1_E_INVAL;
	c = pending(s, request);
	if (!c) {
		uint32_t slot = request & 0xFF, seq = request >> 8;

		if (slot < (uint32_t)s->max_clients &&
		    (s->cl[slot].fd < 0 || seq < s->cl[slot].first_seq || seq > s->cl[slot].seq))
			return srv_err(s, DF1_E_CLOSED, "request %u: its client went away", request);
		return srv_err(s, DF1_E_INVAL, "request %u: not waiting for an answer", request);
	}
	len = eip_session_reply(&c->pend, status & 0xFF, (uint16_t)(status >> 8), pccc, n, s->reply,
	                        sizeof s->reply);
	if (len < 0)
		return srv_err(s, len, "request %u: reply does not fit", request);
	c->waiting = false;
	c->age.last_ms = df1_now_ms();     /* a slow line is not the client's idleness */
	msg = eip_msg_len(c->in, c->in_len);
	consume(c, msg <= c->in_len ? msg : c->in_len);
	client_queue(s, c, s->reply, (size_t)len);
	if (c->fd >= 0 && client_flush(s, c))
		watch(s, c, (int)(request & 0xFF));
	kick(s);     /* buffered messages of this client come next */
	return 0;
}

DF1_API int df1_eip_server_reply(df1_eip_server_t *s, uint32_t request, const uint8_t *pccc_reply, size_t n)
{
	if (!s)
		return DF1_E_INVAL;
	if (!pccc_reply || n < 4 || n > EIP_PCCC_REPLY_MAX)
		return srv_err(s, DF1_E_INVAL, "reply of %zu bytes: expected CMD STS TNS [data], at most %d", n,
		               EIP_PCCC_REPLY_MAX);
	return answer(s, request, 0, pccc_reply, n);
}

DF1_API int df1_eip_server_fail(df1_eip_server_t *s, uint32_t request, int cip_status)
{
	if (!s)
		return DF1_E_INVAL;
	if ((cip_status & 0xFF) == 0 || cip_status < 0 || cip_status > 0xFFFFFF)
		return srv_err(s, DF1_E_INVAL, "CIP status 0x%X: expected 0x01-0xFF | extended << 8", cip_status);
	return answer(s, request, cip_status, NULL, 0);
}

DF1_API void df1_eip_server_stats(const df1_eip_server_t *s, struct df1_eip_server_stats *st)
{
	if (!st)
		return;
	if (!s) {
		memset(st, 0, sizeof *st);
		return;
	}
	*st = s->st;
}

DF1_API int df1_eip_server_set_identity(df1_eip_server_t *s, const struct df1_eip_identity *id)
{
	if (!s || !id)
		return DF1_E_INVAL;
	srv_identity(s, id);
	for (int i = 0; i < s->max_clients; i++) {
		struct eip_client *c = &s->cl[i];
		uint32_t addr = c->id.sin_addr;

		if (c->fd < 0)
			continue;
		c->id = s->id;                  /* those connected already: theirs too */
		c->id.sin_addr = addr;
	}
	return 0;
}

DF1_API int df1_eip_server_set_limits(df1_eip_server_t *s, const struct df1_eip_server_limits *l)
{
	if (!s || !l)
		return DF1_E_INVAL;
	if (eip_limits_from(&s->lim, l) != 0)
		return srv_err(s, DF1_E_INVAL, "limits: register_ms %d, idle_ms %d: each 0 (default), -1 (none) "
		               "or 1-%d", l->register_ms, l->idle_ms, EIP_LIMIT_MS_MAX);
	s->on_close = l->on_close;
	s->close_user = l->user;
	sweep(s);
	return 0;
}

DF1_API void df1_eip_server_closes(const df1_eip_server_t *s, struct df1_eip_server_closes *c)
{
	if (!c)
		return;
	if (!s) {
		memset(c, 0, sizeof *c);
		return;
	}
	*c = s->closes;
}

DF1_API const char *df1_eip_server_error(const df1_eip_server_t *s)
{
	return s ? s->err : new_err;
}

DF1_API void df1_eip_server_free(df1_eip_server_t *s)
{
	if (!s)
		return;
	for (int i = 0; s->cl && i < s->max_clients; i++) {
		client_close(s, &s->cl[i]);
		free(s->cl[i].out);
	}
	free(s->cl);
	if (s->lfd >= 0)
		close(s->lfd);
	if (s->ufd >= 0)
		close(s->ufd);
	if (s->kick >= 0)
		close(s->kick);
	if (s->tfd >= 0)
		close(s->tfd);
	if (s->ep >= 0)
		close(s->ep);
	free(s);
}
