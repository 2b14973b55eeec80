/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_eip.c - df1gw --eip: Execute PCCC requests of EtherNet/IP clients
 * forwarded over the DF1 line (gw_eip.h).
 *
 * A request names its station through the route path (df1-eip(7)) or gets
 * --eip-station. It waits here until the bridge's turn (gw_turn.h: the
 * bridge and the MQTT write batches take turns), then joins the poll
 * engine's queue (gw_eip_hand); its completion answers
 * the client: the controller's reply with the client's TNS, error replies as
 * they are, or, when the controller gave no reply, the PCCC reply a NET-ENI
 * generates for a node that is not there (STS 30h). A write is never sent
 * twice by the engine (df1_poll_submit_pccc). --eip-read-only is the server's
 * refusal (STS 60h) before anything reaches the line.
 */
#include "df1gw/gw_eip.h"

#include <stdlib.h>
#include <string.h>

#include "common/cli.h"

/* A request, waiting for its turn, then what its completion needs to answer. */
struct gw_eip_req {
	struct gw_eip *e;
	uint32_t request;
	int station;
	uint8_t cmd, tns[2];
	size_t n;
	uint8_t pccc[];              /* the command as the client sent it (n bytes) */
};

static const struct df1_eip_identity gw_identity = {
	.vendor_id = 0,              /* vendor 1 is Rockwell's: none is ours to claim */
	.device_type = 0x0C,         /* communications adapter (ODVA Vol. 1 table 5-1.1) */
	.product_code = 0,
	.rev_major = 0,
	.rev_minor = 4,
	.status = 0,
	.serial = 0x0DF10002,
	.product_name = "libdf1 DF1 bridge",
};

/* CMD|40 30 TNS: no controller behind the bridge answered. */
static void gw_eip_no_answer(struct gw_eip *e, uint32_t request, uint8_t cmd, const uint8_t *tns)
{
	uint8_t r[4] = { (uint8_t)(cmd | 0x40), GW_EIP_STS_NO_ANSWER, tns[0], tns[1] };

	e->no_answer++;
	df1_eip_server_reply(e->s, request, r, sizeof r);   /* DF1_E_CLOSED: the client left */
}

static void gw_eip_done(void *user, int result, const uint8_t *reply, size_t n)
{
	struct gw_eip_req *q = user;
	struct gw_eip *e = q->e;

	if (result == 0) {
		e->answered++;
		df1_eip_server_reply(e->s, q->request, reply, n);
	} else {
		if (result == DF1_E_CLOSED || result == DF1_E_NODEV)
			e->line_gone = result;
		gw_eip_no_answer(e, q->request, q->cmd, q->tns);
	}
	free(q);
}

static void gw_eip_pccc(void *user, df1_eip_server_t *s, uint32_t request, int station,
                        const uint8_t *pccc, size_t n)
{
	struct gw_eip *e = user;
	struct gw_eip_req *q;

	(void)s;
	if (n < 4) {
		df1_eip_server_fail(e->s, request, 0x13);   /* not enough data (the server checks too) */
		return;
	}
	if (!e->h || !e->line_up) {
		gw_eip_no_answer(e, request, pccc[0], pccc + 2);
		return;
	}
	q = e->nheld < GW_EIP_HELD_MAX && n <= DF1_PCCC_MAX ? malloc(sizeof *q + n) : NULL;
	if (!q) {
		e->busy++;
		df1_eip_server_fail(e->s, request, GW_EIP_CIP_BUSY);
		return;
	}
	q->e = e;
	q->request = request;
	q->station = station >= 0 ? station : e->station;
	q->cmd = pccc[0];
	memcpy(q->tns, pccc + 2, 2);
	q->n = n;
	memcpy(q->pccc, pccc, n);
	e->held[e->nheld++] = q;
}

unsigned gw_eip_waiting(const struct gw_eip *e)
{
	return e->nheld;
}

unsigned gw_eip_hand(struct gw_eip *e)
{
	unsigned handed = 0;

	for (unsigned i = 0; i < e->nheld; i++) {
		struct gw_eip_req *q = e->held[i];
		int r = DF1_E_NOT_OPEN;

		if (e->h && e->line_up)
			r = df1_poll_submit_pccc(e->h, q->station, q->pccc, q->n, gw_eip_done, q);
		if (r == 0) {
			e->forwarded++;
			handed++;
			continue;
		}
		if (r == DF1_E_BUSY) {
			e->busy++;
			df1_eip_server_fail(e->s, q->request, GW_EIP_CIP_BUSY);
		} else {
			gw_eip_no_answer(e, q->request, q->cmd, q->tns);
		}
		free(q);
	}
	e->nheld = 0;
	return handed;
}

void gw_eip_drop(struct gw_eip *e)
{
	for (unsigned i = 0; i < e->nheld; i++) {
		struct gw_eip_req *q = e->held[i];

		if (e->s)
			gw_eip_no_answer(e, q->request, q->cmd, q->tns);
		free(q);
	}
	e->nheld = 0;
}

void gw_eip_identify(struct gw_eip *e, df1_t *h)
{
	struct df1_eip_identity id = gw_identity;
	struct df1_diag_status ds;

	if (!e->s || !h)
		return;
	if (df1_diag_status(h, e->station, &ds) == 0 && ds.name[0]) {
		/* 32 characters at most: a long name loses "libdf1 " first */
		const char *base = gw_identity.product_name;
		size_t n = strnlen(ds.name, sizeof ds.name), room = sizeof id.product_name - 1;

		if (strlen(base) + 1 + n > room)
			base = "DF1 bridge";
		if (strlen(base) + 1 + n > room)
			n = room - strlen(base) - 1;
		memset(id.product_name, 0, sizeof id.product_name);
		memcpy(id.product_name, base, strlen(base));
		id.product_name[strlen(base)] = ' ';
		memcpy(id.product_name + strlen(base) + 1, ds.name, n);
		id.product_code = ds.type_code;
	}
	df1_eip_server_set_identity(e->s, &id);
}

/* Each connection a limit closed: logged (df1gw(1) EtherNet/IP, "Limits"). */
static void gw_eip_closed(void *user, const char *peer, enum df1_eip_close_reason why)
{
	struct gw_eip *e = user;

	if (e->quiet)
		return;
	if (why == DF1_EIP_CLOSE_NO_SESSION)
		fprintf(stderr, "df1gw: eip: closed %s: no RegisterSession within %d s\n", peer,
		        cli_eip_register_s(&e->opts));
	else if (why == DF1_EIP_CLOSE_IDLE)
		fprintf(stderr, "df1gw: eip: closed %s: session idle for %d s\n", peer, cli_eip_idle_s(&e->opts));
	else
		fprintf(stderr, "df1gw: eip: closed %s: the longest idle of a full table, for a new client\n", peer);
}

static bool gw_eip_loopback(const char *a)
{
	return strncmp(a, "127.", 4) == 0 || strncmp(a, "[::1]", 5) == 0 ||
	       strncmp(a, "localhost", 9) == 0;
}

int gw_eip_open(struct gw_eip *e, const char *prog, bool quiet)
{
	struct df1_eip_server_config c;
	struct df1_eip_server_limits lim = { 0 };
	const char *a;
	int r;

	memset(&c, 0, sizeof c);
	c.listen = strncmp(e->listen, "tcp://", 6) == 0 ? e->listen + 6 : e->listen;
	cli_eip_server_config(&e->opts, &c, &lim);
	c.identity = gw_identity;
	r = df1_eip_server_new(&e->s, &c, gw_eip_pccc, e);
	if (r < 0) {
		fprintf(stderr, "%s: --eip %s: %s\n", prog, e->listen, df1_eip_server_error(NULL));
		return r == DF1_E_INVAL ? CLI_EXIT_USAGE : CLI_EXIT_FAIL;
	}
	e->quiet = quiet;
	lim.on_close = gw_eip_closed;
	lim.user = e;
	if (df1_eip_server_set_limits(e->s, &lim) < 0) {
		fprintf(stderr, "%s: --eip: %s\n", prog, df1_eip_server_error(e->s));
		gw_eip_close(e);
		return CLI_EXIT_USAGE;
	}
	a = df1_eip_server_address(e->s);
	if (!gw_eip_loopback(a))
		fprintf(stderr, "%s: EtherNet/IP on %s: listening on a network, reachable from other "
		        "hosts (no authentication: see --eip-allow, --eip-read-only)\n", prog, a);
	else if (!quiet)
		fprintf(stderr, "%s: EtherNet/IP on %s\n", prog, a);
	return 0;
}

int gw_eip_fd(const struct gw_eip *e)
{
	return e->s ? df1_eip_server_fd(e->s) : -1;
}

void gw_eip_process(struct gw_eip *e)
{
	if (e->s)
		df1_eip_server_process(e->s);
}

void gw_eip_counters(const struct gw_eip *e, FILE *f)
{
	struct df1_eip_server_stats st;
	struct df1_eip_server_closes cl;

	if (!e->s)
		return;
	df1_eip_server_stats(e->s, &st);
	df1_eip_server_closes(e->s, &cl);
	fprintf(f, "eip sessions %llu, open %llu, requests %llu, errors %llu, refused clients %llu, "
	        "read-only refusals %llu, forwarded %llu, answered %llu, no answer %llu, busy %llu\n",
	        (unsigned long long)st.sessions, (unsigned long long)st.sessions_open,
	        (unsigned long long)st.requests, (unsigned long long)st.errors,
	        (unsigned long long)st.refused_clients, (unsigned long long)st.read_only_refusals,
	        (unsigned long long)e->forwarded, (unsigned long long)e->answered,
	        (unsigned long long)e->no_answer, (unsigned long long)e->busy);
	fprintf(f, "eip closed without session %llu, idle %llu, evicted %llu\n", (unsigned long long)cl.no_session,
	        (unsigned long long)cl.idle, (unsigned long long)cl.evicted);
}

void gw_eip_close(struct gw_eip *e)
{
	gw_eip_drop(e);
	df1_eip_server_free(e->s);
	e->s = NULL;
}
