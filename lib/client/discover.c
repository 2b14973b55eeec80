/* SPDX-License-Identifier: MPL-2.0 */
/*
 * discover.c - station discovery: df1_discover() and the per-station probe it
 * shares with the poll engine (discover_probe, df1_int.h).
 *
 * The probe. A half-duplex master polls the station (DLE ENQ STN BCC,
 * df1_link_test): a DLE EOT or a message means it is there; a station that
 * answers is then asked its diagnostic status (06/03) when identifying. In full
 * duplex nothing addresses a station but a command: the probe is the empty
 * 06/00 echo (the poll engine), or the 06/03 diagnostic status itself when
 * identifying, which answers both questions in one transaction. A reply with
 * an error STS (DF1_E_REMOTE) is an answer: the station is there.
 *
 * df1_discover. Full duplex first sends one DLE ENQ (df1_link_test): no answer
 * means nothing is on the line, and probing 255 stations would only repeat
 * that. Then each station of lo..hi in turn, the cancel fd looked at before
 * each one; the callback sees every station probed. A scan ends early on the
 * codes after which every further probe would fail the same way (DF1_E_INTR,
 * DF1_E_NOMEM, DF1_E_NOT_OPEN, DF1_E_NOTSUP, DF1_E_INVAL); any other failure
 * is that station's.
 */
#include "df1_int.h"

#include <poll.h>
#include <string.h>

/* Codes after which the scan stops: the next station would fail the same way. */
static bool discover_abort(int rc)
{
	switch (rc) {
	case DF1_E_INTR: case DF1_E_NOMEM: case DF1_E_NOT_OPEN: case DF1_E_NOTSUP: case DF1_E_INVAL:
		return true;
	default:
		return false;
	}
}

/* A reply came: the station is there (an error STS is still a reply). */
static bool discover_answered(int rc)
{
	return rc >= 0 || rc == DF1_E_REMOTE;
}

int discover_probe(struct df1 *h, int station, unsigned flags, struct df1_discover_result *out)
{
	struct df1_discover_result r;
	bool identify = (flags & DISCOVER_IDENTIFY) != 0;
	uint64_t t0;
	int rc, s;

	memset(&r, 0, sizeof r);
	r.station = station;
	if (!h)
		return DF1_E_INVAL;
	t0 = df1_now_us();
	if (h->cfg.duplex == DF1_HALF_DUPLEX_MASTER) {
		rc = df1_link_test(h, station);
		r.answered = discover_answered(rc);
		r.error = rc < 0 ? rc : DF1_OK;
		if (r.answered)
			r.rtt_us = df1_now_us() - t0;
		if (rc >= 0 && identify) {
			s = df1_diag_status(h, station, &r.status);
			r.identified = s >= 0;
			r.error = s < 0 ? s : DF1_OK;
			if (s < 0 && discover_abort(s))
				rc = s;
		}
	} else {
		if (identify)
			rc = df1_diag_status(h, station, &r.status);
		else
			rc = df1_echo(h, station, NULL, 0);
		r.answered = discover_answered(rc);
		r.identified = identify && rc >= 0;
		r.error = rc < 0 ? rc : DF1_OK;
		if (r.answered)
			r.rtt_us = df1_now_us() - t0;
	}
	if (!r.identified)
		memset(&r.status, 0, sizeof r.status);
	if (out)
		*out = r;
	return rc;
}

/* The cancel fd readable now: DF1_E_INTR (a wait that ends at once). */
static int discover_cancelled(struct df1 *h)
{
	int r;

	if (h->cancel_fd < 0)
		return 0;
	r = port_wait(h, -1, POLLIN, df1_now_ms());
	if (r == DF1_E_INTR)
		return df1_fail(h, DF1_E_INTR, -1, "discovery cancelled");
	return r < 0 ? r : 0;
}

int df1_discover(df1_t *h, int lo, int hi, df1_discover_fn fn, void *user)
{
	int found = 0, rc;

	if (!h)
		return DF1_E_INVAL;
	if (lo < 0 || hi > 254 || lo > hi)
		return df1_fail(h, DF1_E_INVAL, -1, "discovery: station range %d-%d (expected within 0-254)",
		                lo, hi);
	if (!df1_is_open(h))
		return df1_fail(h, DF1_E_NOT_OPEN, -1, "discovery: the handle is not open");
	if (h->cfg.duplex == DF1_HALF_DUPLEX_SLAVE)
		return df1_fail(h, DF1_E_NOTSUP, -1, "discovery: a half-duplex slave does not poll");
	rc = discover_cancelled(h);
	if (rc < 0)
		return rc;
	if (h->cfg.duplex != DF1_HALF_DUPLEX_MASTER) {
		/* is anybody on the line at all: DLE ENQ, the peer repeats its last response */
		rc = df1_link_test(h, lo);
		if (rc < 0)
			return rc;
	}
	for (int stn = lo; stn <= hi; stn++) {
		struct df1_discover_result r;

		rc = discover_cancelled(h);
		if (rc < 0)
			return rc;
		rc = discover_probe(h, stn, DISCOVER_IDENTIFY, &r);
		if (rc < 0 && discover_abort(rc))
			return rc;
		if (r.answered)
			found++;
		if (fn && fn(user, &r) != 0)
			break;
	}
	return found;
}
