/* SPDX-License-Identifier: MPL-2.0 */
/*
 * sim_msg - df1sim's MSG instructions (--msg; df1sim(1)): a controller that
 * speaks first. Each MSG is a write of LOCAL (COUNT elements of the first
 * station's table) to REMOTE at STATION, or a read of REMOTE into LOCAL,
 * every MS ms. It goes out on the handle df1sim serves with, as a master's
 * command (df1_write / df1_read); while it waits, the commands of the
 * station that polls us are still answered (df1_set_responder, lib/link/peer.c).
 * As a half-duplex slave the same calls queue it for the master's next poll
 * and wait for the reply it brings (lib/link/half_msg.c); station 255 is a
 * broadcast.
 * Its outcome is printed as the MSG block shows it: DN, or ER with the STS
 * (and EXT STS) the target answered, or the link error.
 */
#include "df1sim/sim_msg.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int64_t sim_msg_now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static int sim_msg_int(const char *s, int lo, int hi, int *out)
{
	char *end;
	long v;

	errno = 0;
	v = strtol(s, &end, 10);
	if (errno || end == s || *end || v < lo || v > hi)
		return -1;
	*out = (int)v;
	return 0;
}

int sim_msg_parse(const char *spec, struct sim_msg *m, char *err, size_t cap)
{
	char buf[160], *f[8], *save = NULL;
	int n = 0;

	memset(m, 0, sizeof *m);
	m->every_ms = 1000;
	if (strlen(spec) >= sizeof buf) {
		snprintf(err, cap, "too long");
		return -1;
	}
	strcpy(buf, spec);
	for (char *p = strtok_r(buf, ",", &save); p && n < 8; p = strtok_r(NULL, ",", &save))
		f[n++] = p;
	if (n < 5 || n > 7) {
		snprintf(err, cap, "expected KIND,LOCAL,COUNT,STATION,REMOTE[,MS][,seq]");
		return -1;
	}
	if (!strcmp(f[0], "write")) {
		m->write = true;
	} else if (strcmp(f[0], "read")) {
		snprintf(err, cap, "kind '%s' is neither write nor read", f[0]);
		return -1;
	}
	if (strlen(f[1]) >= sizeof m->local || strlen(f[4]) >= sizeof m->remote) {
		snprintf(err, cap, "address too long");
		return -1;
	}
	strcpy(m->local, f[1]);
	strcpy(m->remote, f[4]);
	if (sim_msg_int(f[2], 1, 120, &m->count)) {
		snprintf(err, cap, "count '%s' is not 1-120", f[2]);
		return -1;
	}
	if (sim_msg_int(f[3], 0, 255, &m->station)) {
		snprintf(err, cap, "station '%s' is not 0-255 (255: broadcast)", f[3]);
		return -1;
	}
	for (int i = 5; i < n; i++) {
		if (!strcmp(f[i], "seq") && m->write)
			m->seq = true;
		else if (i == 5 && !sim_msg_int(f[i], 10, 3600000, &m->every_ms))
			continue;
		else {
			snprintf(err, cap, "'%s' is neither a period of 10-3600000 ms nor seq (write only)", f[i]);
			return -1;
		}
	}
	return 0;
}

/* The MSG's outcome, as its control block shows it. */
static void sim_msg_report(df1_t *h, struct sim_msg *m, int rc, int first, FILE *log)
{
	const struct df1_error_detail *d = df1_last_error(h);
	char what[200], res[80];

	snprintf(what, sizeof what, "MSG %s %s,%d %s station %d %s", m->write ? "write" : "read",
	         m->local, m->count, m->write ? "to" : "from", m->station, m->remote);
	if (rc >= 0) {
		m->done++;
		snprintf(res, sizeof res, "DN");
	} else if (rc == DF1_E_REMOTE && d && d->has_ext_sts) {
		m->errors++;
		snprintf(res, sizeof res, "ER STS %02Xh EXT STS %02Xh", d->sts, d->ext_sts);
	} else if (rc == DF1_E_REMOTE && d) {
		m->errors++;
		snprintf(res, sizeof res, "ER STS %02Xh", d->sts);
	} else {
		m->errors++;
		snprintf(res, sizeof res, "ER %s", df1_errname(rc));
	}
	/* the first word sent: with seq, which message this was */
	fprintf(stderr, "df1sim: %s (first %d): %s\n", what, first, res);
	if (log) {
		fprintf(log, "%s first=%d: %s\n", what, first, res);
		fflush(log);
	}
}

static int sim_msg_one(df1_t *h, struct df1_table *t, struct sim_msg *m, FILE *log)
{
	struct df1_value v[120];
	int rc;

	memset(v, 0, sizeof v);
	m->sent++;
	if (m->write) {
		rc = df1_table_read(t, m->local, v, (size_t)m->count);
		if (rc >= 0 && m->seq) {
			v[0].v.i16++;
			rc = df1_table_write(t, m->local, v, 1);
		}
		if (rc < 0) {
			fprintf(stderr, "df1sim: MSG: local %s: %s\n", m->local, df1_table_error_text(t));
			return rc;
		}
		rc = df1_write(h, m->station, m->remote, v, (size_t)m->count);
	} else {
		rc = df1_read(h, m->station, m->remote, v, (size_t)m->count);
		if (rc >= 0 && df1_table_write(t, m->local, v, (size_t)m->count) < 0)
			fprintf(stderr, "df1sim: MSG: local %s: %s\n", m->local, df1_table_error_text(t));
	}
	sim_msg_report(h, m, rc, v[0].v.i16, log);
	return rc;
}

int sim_msg_run(df1_t *h, struct df1_table *t, struct sim_msg *m, int n, FILE *log, int max_ms)
{
	int64_t now = sim_msg_now(), next = now + max_ms;

	for (int i = 0; i < n; i++) {
		if (m[i].next_ms <= now) {
			(void)sim_msg_one(h, t, &m[i], log);
			now = sim_msg_now();
			m[i].next_ms = (m[i].next_ms ? m[i].next_ms : now) + m[i].every_ms;
			if (m[i].next_ms < now)
				m[i].next_ms = now; /* late: the next one at once, no burst */
		}
		if (m[i].next_ms < next)
			next = m[i].next_ms;
	}
	return next > now ? (int)(next - now) : 0;
}
