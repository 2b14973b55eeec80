/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server_api.c - the responder's public calls (df1_serve(3)): faults, the
 * command queue, the stations served, df1_serve() on the link layer and
 * df1_serve_pccc() without it. The responder itself is lib/server/server_dispatch.c.
 */
#include "server/server.h"

#include <stdlib.h>
#include <string.h>

#include "proto/pccc.h"

DF1_API int df1_server_set_fault(df1_t *h, enum df1_fault f, int per_mille, int value)
{
	struct link_responder *r;

	if (!h)
		return DF1_E_INVAL;
	if ((int)f < 1 || (int)f >= FAULT_KINDS)
		return df1_fail(h, DF1_E_INVAL, -1, "unknown fault kind %d", (int)f);
	if (per_mille < 0 || per_mille > 1000)
		return df1_fail(h, DF1_E_INVAL, -1, "fault probability %d: must be 0..1000 per mille",
		                per_mille);
	if (f == DF1_FAULT_DELAY_REPLY && (value < 0 || value > 3600000))
		return df1_fail(h, DF1_E_INVAL, -1, "reply delay %d ms: must be 0..3600000", value);
	if (f == DF1_FAULT_SILENT_STATION && (value < -1 || value > FAULT_SILENT_ALL))
		return df1_fail(h, DF1_E_INVAL, -1,
		                "silent station %d: must be -1 (none), 0..255, or %d (every station)",
		                value, FAULT_SILENT_ALL);
	r = server_responder(h);
	if (!r)
		return df1_fail(h, DF1_E_NOMEM, -1, "responder: out of memory");
	r->faults.per_mille[f] = per_mille;
	r->faults.value[f] = value;
	if (f == DF1_FAULT_SILENT_STATION)
		r->silenced = false; /* the ENQs after a silenced frame: answered again */
	return 0;
}

DF1_API int df1_server_set_max_queue(df1_t *h, int max_queue)
{
	struct link_responder *r;

	if (!h)
		return DF1_E_INVAL;
	if (max_queue < 0 || max_queue > LINK_REPLY_SLOTS)
		return df1_fail(h, DF1_E_INVAL, -1, "queue of %d commands: must be 0..%d", max_queue,
		                LINK_REPLY_SLOTS);
	r = server_responder(h);
	if (!r)
		return df1_fail(h, DF1_E_NOMEM, -1, "responder: out of memory");
	r->max_queue = max_queue;
	return 0;
}

DF1_API void df1_server_set_seed(df1_t *h, uint64_t seed)
{
	struct link_responder *r = h ? server_responder(h) : NULL;

	if (r)
		r->faults.rng = seed ? seed : 0x9E3779B97F4A7C15ull;
}


DF1_API int df1_server_add_station(df1_t *h, int station)
{
	struct link_responder *r;

	if (!h)
		return DF1_E_INVAL;
	if (station < 0 || station > 254)   /* 255 is the broadcast address (doc/PROTOCOL.md 2.3) */
		return df1_fail(h, DF1_E_INVAL, station, "station %d out of range 0-254", station);
	r = server_responder(h);
	if (!r)
		return df1_fail(h, DF1_E_NOMEM, station, "responder: out of memory");
	r->serve_station[station] = true;
	return 0;
}

DF1_API int df1_serve(df1_t *h, const struct df1_server_ops *ops, void *user, int timeout_ms)
{
	struct link_responder *resp;
	struct server_ctx c;

	if (!h)
		return DF1_E_INVAL;
	if (!ops || timeout_ms < 0)
		return df1_fail(h, DF1_E_INVAL, -1, "df1_serve: %s",
		                ops ? "negative timeout" : "no server callbacks");
	if (!df1_is_open(h))
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "df1_serve: handle is not open");
	resp = server_responder(h);
	if (!resp)
		return df1_fail(h, DF1_E_NOMEM, -1, "df1_serve: out of memory");
	c.ops = ops;
	c.user = user;
	return link_serve(h, resp, server_handle, &c, df1_now_ms() + timeout_ms);
}

DF1_API int df1_serve_pccc(df1_t *h, const struct df1_server_ops *ops, void *user, int station,
                           const uint8_t *pccc, size_t n, uint8_t *reply, size_t cap)
{
	uint8_t cmd[FRAME_MAX_DATA], rep[FRAME_MAX_DATA + 2];
	struct server_ctx c = { ops, user };
	int rc;

	if (!h || !ops || !pccc || !reply || station < 0 || station > 254)
		return h ? df1_fail(h, DF1_E_INVAL, station, "df1_serve_pccc: %s",
		                    !ops ? "no server callbacks" : station < 0 || station > 254
		                    ? "station out of range 0-254" : "no command or reply buffer")
		         : DF1_E_INVAL;
	if (n < 4 || (pccc[0] & PCCC_REPLY_BIT))
		return 0;
	if (n + 2 > sizeof cmd) {       /* longer than a DF1 message: illegal format */
		if (cap < 4)
			return df1_fail(h, DF1_E_NOSPACE, station, "df1_serve_pccc: reply buffer of %zu bytes", cap);
		reply[0] = (uint8_t)(pccc[0] | PCCC_REPLY_BIT);
		reply[1] = 0x10;
		reply[2] = pccc[2];
		reply[3] = pccc[3];
		return 4;
	}
	cmd[0] = (uint8_t)station;
	cmd[1] = (uint8_t)station;      /* no link: the source is not used */
	memcpy(cmd + 2, pccc, n);
	rc = server_handle(h, &c, cmd, n + 2, rep, sizeof rep);
	if (rc <= 2)
		return rc < 0 ? rc : 0;
	if ((size_t)rc - 2 > cap)
		return df1_fail(h, DF1_E_NOSPACE, station, "df1_serve_pccc: reply of %d bytes, buffer of %zu",
		                rc - 2, cap);
	memcpy(reply, rep + 2, (size_t)rc - 2);
	return rc - 2;
}
