/* SPDX-License-Identifier: MPL-2.0 */
/*
 * ledger.c - every command the soak's handle sends, by TNS, and how often
 * df1sim's --log says it ran (soak.h).
 *
 * The handle's trace gives the bytes sent; a frame with a TNS not seen just
 * before is a new transaction (the link keeps the TNS for its own
 * retransmissions). df1sim logs a command once when its reply goes out, with
 * its CMD/FNC, address and TNS (df1sim(1) OUTPUT), so a line is matched to the
 * record of that TNS, checked by command and address. A TNS comes round after
 * 65536 transactions: the record it held is closed first, long after its log
 * line was due. A write told "written" with no line is lost; a write with two
 * lines ran twice; a write told "failed" may have run once or not at all.
 */
#include "soak.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int ledger_init(struct ledger *l, enum df1_check check, bool half)
{
	memset(l, 0, sizeof *l);
	l->last_tns = -1;
	l->log_fd = -1;
	l->recs = calloc(65536, sizeof *l->recs);
	if (!l->recs)
		return -1;
	/* touched now, so that the resident size at the start already holds it */
	for (size_t i = 0; i < 65536 * sizeof *l->recs; i += 512)
		((volatile char *)l->recs)[i] = 0;
	if (df1_decoder_new(&l->dec, check) < 0)
		return -1;
	df1_decoder_set_half_duplex(l->dec, half);
	return 0;
}

void ledger_free(struct ledger *l)
{
	free(l->recs);
	l->recs = NULL;
	df1_decoder_free(l->dec);
	l->dec = NULL;
	if (l->log_fd >= 0)
		close(l->log_fd);
	l->log_fd = -1;
}

/* The data-table writes of every command set (doc/PROTOCOL.md 4-6). */
static bool is_write_cmd(const struct df1_msg *m)
{
	if (m->cmd == 0x0F && m->has_fnc)
		return m->fnc == 0xAA || m->fnc == 0xAB || m->fnc == 0xA9 || m->fnc == 0x67 ||
		       m->fnc == 0x26 || m->fnc == 0x00 || m->fnc == 0x02;
	return m->cmd == 0x08 || m->cmd == 0x00 || m->cmd == 0x05 || m->cmd == 0x02;
}

static void rec_close(struct ledger *l, struct rec *r)
{
	if (r->gen == 0 || !r->is_write)
		return;
	if (r->execs >= 2)
		l->fig.executed_twice++;
	if (r->result == REC_OK && r->execs == 0)
		l->fig.lost++;
	if (r->result != REC_OK && r->execs == 1)
		l->fig.failed_executed++;
}

/* The command and address as df1sim's log writes them. */
static void describe(const struct df1_msg *m, char *cmd, size_t ccap, char *addr, size_t acap)
{
	if (m->has_fnc)
		snprintf(cmd, ccap, "%02X/%02X", m->cmd, m->fnc);
	else
		snprintf(cmd, ccap, "%02X", m->cmd);
	snprintf(addr, acap, "-");
	if (m->has_addr && (m->addr.type == DF1_FT_NONE || df1_addr_format(&m->addr, addr, acap) < 0))
		snprintf(addr, acap, "#%d:%d", m->addr.file, m->addr.element);
}

static void on_command(struct ledger *l, const uint8_t *app, size_t n)
{
	struct df1_msg m;
	struct rec *r;
	int tns;

	if (n < 6 || (app[2] & 0x40))
		return;
	tns = app[4] | app[5] << 8;
	if (tns == l->last_tns)
		return;         /* the link sends it again: the same transaction */
	l->last_tns = tns;
	r = &l->recs[tns];
	rec_close(l, r);
	memset(r, 0, sizeof *r);
	r->gen = ++l->gen ? l->gen : ++l->gen;
	if (df1_msg_decode(app, n, &m) == 0) {
		describe(&m, r->cmd, sizeof r->cmd, r->addr, sizeof r->addr);
		r->is_write = is_write_cmd(&m);
	}
	if (r->is_write)
		l->fig.writes_sent++;
	if (l->call_n < (int)(sizeof l->call_tns / sizeof l->call_tns[0]))
		l->call_tns[l->call_n++] = tns;
}

void ledger_trace(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us)
{
	struct ledger *l = user;

	(void)t_us;
	if (dir != DF1_DIR_TX)
		return;
	while (n > 0) {
		struct df1_symbol s;
		size_t used = df1_decoder_feed(l->dec, bytes, n, &s);

		if (used == 0 && s.kind == DF1_SYM_NONE)
			break;
		bytes += used;
		n -= used;
		if (s.kind == DF1_SYM_FRAME && s.check_ok)
			on_command(l, s.data, s.len);
	}
}

void ledger_call_begin(struct ledger *l)
{
	l->call_n = 0;
}

void ledger_set_result(struct ledger *l, int tns, bool ok)
{
	struct rec *r = &l->recs[tns & 0xFFFF];

	if (r->gen == 0 || !r->is_write || r->result != REC_PENDING)
		return;
	r->result = ok ? REC_OK : REC_FAILED;
	if (ok)
		l->fig.writes_ok++;
	else
		l->fig.writes_failed++;
}

void ledger_call_result(struct ledger *l, bool ok)
{
	for (int i = 0; i < l->call_n; i++)
		ledger_set_result(l, l->call_tns[i], ok);
	l->call_n = 0;
}

int ledger_call_sent(const struct ledger *l)
{
	return l->call_n;
}

int ledger_call_write_tns(const struct ledger *l)
{
	for (int i = 0; i < l->call_n; i++) {
		const struct rec *r = &l->recs[l->call_tns[i]];

		if (r->is_write && r->result == REC_PENDING)
			return l->call_tns[i];
	}
	return -1;
}

/* The value of " key=" in a log line, up to the next blank. */
static bool field(const char *line, const char *key, char *out, size_t cap)
{
	const char *p = strstr(line, key);
	size_t k = 0;

	if (!p)
		return false;
	p += strlen(key);
	while (p[k] && p[k] != ' ' && k + 1 < cap) {
		out[k] = p[k];
		k++;
	}
	out[k] = '\0';
	return k > 0;
}

static void on_log_line(struct ledger *l, const char *line)
{
	char tns[8], cmd[8], addr[24];
	struct rec *r;
	char *end;
	unsigned long t;

	l->fig.log_lines++;
	if (!field(line, " tns=", tns, sizeof tns) || !field(line, " cmd=", cmd, sizeof cmd) ||
	    !field(line, " addr=", addr, sizeof addr)) {
		l->fig.log_unmatched++;
		return;
	}
	t = strtoul(tns, &end, 16);
	r = t <= 0xFFFF && !*end ? &l->recs[t] : NULL;
	if (!r || r->gen == 0 || strcmp(r->cmd, cmd) != 0 || strcmp(r->addr, addr) != 0) {
		l->fig.log_unmatched++;
		return;
	}
	r->execs++;
}

int ledger_follow(struct ledger *l, const char *path)
{
	for (;;) {
		ssize_t n;
		char *nl;

		if (l->log_fd < 0) {
			l->log_fd = open(path, O_RDONLY | O_CLOEXEC);
			if (l->log_fd < 0)
				return errno == ENOENT ? 0 : -1;
		}
		n = read(l->log_fd, l->buf + l->buf_len, sizeof l->buf - 1 - l->buf_len);
		if (n < 0)
			return errno == EINTR ? 0 : -1;
		if (n == 0)
			return 0;
		l->buf_len += (size_t)n;
		l->buf[l->buf_len] = '\0';
		while ((nl = strchr(l->buf, '\n')) != NULL) {
			size_t used = (size_t)(nl - l->buf) + 1;

			*nl = '\0';
			on_log_line(l, l->buf);
			memmove(l->buf, l->buf + used, l->buf_len - used + 1);
			l->buf_len -= used;
		}
		if (l->buf_len == sizeof l->buf - 1) {
			l->fig.log_unmatched++;         /* a line longer than any df1sim writes */
			l->buf_len = 0;
		}
	}
}

void ledger_close_all(struct ledger *l)
{
	for (int i = 0; i < 65536; i++) {
		rec_close(l, &l->recs[i]);
		l->recs[i].gen = 0;
	}
}
