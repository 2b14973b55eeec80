/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mock_port - a scripted struct port_ops for link-level tests (see mock_port.h).
 */
#include "support/mock_port.h"

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <string.h>
#include <time.h>

#include "df1_int.h"

#define MOCK_ENTRIES 4096
#define MOCK_POOL (256 * 1024)
#define MOCK_CAPTURE (64 * 1024)
#define MOCK_WRITES 4096

enum mock_kind { MOCK_BYTES, MOCK_EXPIRE, MOCK_FAIL };

struct mock_entry {
	enum mock_kind kind;
	size_t off, len;      /* bytes in pool */
	int code;
};

static struct mock_entry entries[MOCK_ENTRIES];
static size_t head, tail;
static uint8_t pool[MOCK_POOL];
static size_t pool_used;
static size_t reads_served;

static uint8_t captured[MOCK_CAPTURE];
static size_t captured_len;
static size_t write_off[MOCK_WRITES], write_len[MOCK_WRITES];
static size_t nwrites;

/* the fake modem lines (mock_port_lines) and their events */
static bool lines_on;
static int cts_lag_ms;
static int64_t rts_up_ms = -1, dcd_until_ms;
#define MOCK_EVENTS 256
static char ev_kind[MOCK_EVENTS];
static int64_t ev_ms[MOCK_EVENTS];
static size_t nev;

static void mock_event(char k)
{
	if (nev < MOCK_EVENTS) {
		ev_kind[nev] = k;
		ev_ms[nev++] = df1_now_ms();
	}
}

static mock_port_hook hook;
static void *hook_user;
static mock_port_idle idle;
static void *idle_user;

void mock_port_reset(void)
{
	head = tail = 0;
	pool_used = 0;
	reads_served = 0;
	captured_len = 0;
	nwrites = 0;
	hook = NULL;
	hook_user = NULL;
	idle = NULL;
	idle_user = NULL;
	lines_on = false;
	rts_up_ms = -1;
	nev = 0;
}

void mock_port_lines(int cts_lag, int dcd_ms)
{
	lines_on = true;
	cts_lag_ms = cts_lag;
	rts_up_ms = -1;
	dcd_until_ms = df1_now_ms() + dcd_ms;
	nev = 0;
}

size_t mock_port_events(char *out, size_t cap)
{
	size_t n = nev < cap - 1 ? nev : cap - 1;

	memcpy(out, ev_kind, n);
	out[n] = '\0';
	return n;
}

int64_t mock_port_event_ms(size_t i)
{
	assert_true(i < nev);
	return ev_ms[i];
}

static int mock_modem(struct df1 *h, unsigned set, unsigned clear, unsigned *state)
{
	int64_t now = df1_now_ms();

	(void)h;
	if (!lines_on)
		return DF1_E_NOTSUP;
	if ((set & PORT_LINE_RTS) && rts_up_ms < 0) {
		rts_up_ms = now;
		mock_event('R');
	}
	if ((clear & PORT_LINE_RTS) && rts_up_ms >= 0) {
		rts_up_ms = -1;
		mock_event('r');
	}
	if (state) {
		*state = rts_up_ms >= 0 ? PORT_LINE_RTS : 0;
		if (rts_up_ms >= 0 && cts_lag_ms >= 0 && now >= rts_up_ms + cts_lag_ms)
			*state |= PORT_LINE_CTS;
		if (now < dcd_until_ms)
			*state |= PORT_LINE_DCD;
	}
	return 0;
}

static struct mock_entry *mock_push(enum mock_kind kind)
{
	if (head == tail) {   /* queue empty: start over at the beginning */
		head = tail = 0;
		pool_used = 0;
	}
	assert_true(tail < MOCK_ENTRIES);
	struct mock_entry *e = &entries[tail++];
	memset(e, 0, sizeof *e);
	e->kind = kind;
	return e;
}

void mock_port_feed(const uint8_t *bytes, size_t n)
{
	struct mock_entry *e = mock_push(MOCK_BYTES);
	assert_true(pool_used + n <= MOCK_POOL);
	memcpy(pool + pool_used, bytes, n);
	e->off = pool_used;
	e->len = n;
	pool_used += n;
}

size_t mock_hex(const char *hex, uint8_t *buf, size_t cap)
{
	size_t n = 0;
	int nib = -1;
	for (const char *p = hex; *p; p++) {
		int v;
		if (*p >= '0' && *p <= '9')
			v = *p - '0';
		else if (*p >= 'a' && *p <= 'f')
			v = *p - 'a' + 10;
		else if (*p >= 'A' && *p <= 'F')
			v = *p - 'A' + 10;
		else {
			assert_true(*p == ' ' || *p == ':' || *p == '\n');
			continue;
		}
		if (nib < 0) {
			nib = v;
		} else {
			assert_true(n < cap);
			buf[n++] = (uint8_t)(nib << 4 | v);
			nib = -1;
		}
	}
	assert_true(nib < 0);
	return n;
}

void mock_port_feed_hex(const char *hex)
{
	uint8_t buf[2048];
	size_t n = mock_hex(hex, buf, sizeof buf);
	mock_port_feed(buf, n);
}

void mock_port_expire(void)
{
	mock_push(MOCK_EXPIRE);
}

void mock_port_fail(int code)
{
	struct mock_entry *e = mock_push(MOCK_FAIL);
	e->code = code;
}

size_t mock_port_pending(void)
{
	return tail - head;
}

size_t mock_port_reads(void)
{
	return reads_served;
}

void mock_port_on_write(mock_port_hook fn, void *user)
{
	hook = fn;
	hook_user = user;
}

void mock_port_on_idle(mock_port_idle fn, void *user)
{
	idle = fn;
	idle_user = user;
}

const uint8_t *mock_port_written(size_t *n)
{
	*n = captured_len;
	return captured;
}

size_t mock_port_writes(void)
{
	return nwrites;
}

const uint8_t *mock_port_write_at(size_t i, size_t *n)
{
	assert_true(i < nwrites && i < MOCK_WRITES);
	*n = write_len[i];
	return captured + write_off[i];
}

void mock_port_clear_written(void)
{
	captured_len = 0;
	nwrites = 0;
}

size_t mock_port_count_written(const uint8_t *seq, size_t n)
{
	size_t count = 0;
	for (size_t i = 0; n > 0 && i + n <= captured_len; i++)
		if (memcmp(captured + i, seq, n) == 0)
			count++;
	return count;
}

static int mock_open(struct df1 *h, const char *target)
{
	(void)target;
	h->fd = 0;
	return 0;
}

static void mock_close(struct df1 *h)
{
	h->fd = -1;
}

/* Empty queue: a quiet line. Wait (really) until the deadline, at most 5 s. */
static void mock_wait_until(int64_t deadline_ms)
{
	int64_t now = df1_now_ms();
	int64_t ms = deadline_ms - now;
	if (ms <= 0)
		return;
	if (ms > 5000)
		ms = 5000;
	struct timespec ts = { .tv_sec = ms / 1000, .tv_nsec = (ms % 1000) * 1000000L };
	while (nanosleep(&ts, &ts) != 0) {
	}
}

static ssize_t mock_read(struct df1 *h, uint8_t *buf, size_t cap, int64_t deadline_ms)
{
	(void)h;
	while (head == tail && idle && df1_now_ms() < deadline_ms)
		idle(deadline_ms, idle_user);
	if (head == tail) {
		mock_wait_until(deadline_ms);
		reads_served++;
		return 0;
	}
	struct mock_entry *e = &entries[head];
	reads_served++;
	switch (e->kind) {
	case MOCK_EXPIRE:
		head++;
		return 0;
	case MOCK_FAIL:
		head++;
		return e->code;
	case MOCK_BYTES:
	default:
		break;
	}
	size_t n = e->len < cap ? e->len : cap;
	memcpy(buf, pool + e->off, n);
	e->off += n;
	e->len -= n;
	if (e->len == 0)
		head++;
	return (ssize_t)n;
}

static ssize_t mock_write(struct df1 *h, const uint8_t *buf, size_t len, int64_t deadline_ms)
{
	(void)h;
	(void)deadline_ms;
	if (nwrites < MOCK_WRITES && captured_len + len <= MOCK_CAPTURE) {
		write_off[nwrites] = captured_len;
		write_len[nwrites] = len;
		memcpy(captured + captured_len, buf, len);
		captured_len += len;
	}
	nwrites++;
	if (lines_on)
		mock_event('W');
	if (hook)
		hook(buf, len, hook_user);
	return (ssize_t)len;
}

const struct port_ops mock_port_ops = {
	.name = "mock",
	.open = mock_open,
	.close = mock_close,
	.read = mock_read,
	.write = mock_write,
	.configure = NULL,
	.drain = NULL,
	.modem = mock_modem,
};
