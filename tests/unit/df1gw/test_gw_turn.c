/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_gw_turn.c - whose turn the line is (tools/df1gw/gw_turn.c) against
 * df1gw(1), ETHERNET/IP and WRITE POLICY: the bridge's requests and the MQTT
 * write batches take turns; one batch on the line at a time, none started
 * inside the line's work; after a full batch a due poll read goes first; a
 * bridged request waits behind at most one batch of writes, or the poll read
 * on the line. The decisions one by one, then the order of service they give on a
 * model of the line (the poll engine's queue served in order before each
 * transaction, lib/poll/poll_int.h), written out by hand.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <string.h>

#include "df1gw/gw_turn.h"

static struct gw_turn_state st(unsigned bridge, size_t backlog, unsigned batch, enum gw_turn last)
{
	struct gw_turn_state s = { .bridge = bridge, .backlog = backlog, .batch = batch, .duty = 10,
		                   .last = last };

	return s;
}

static void test_one_source(void **state)
{
	struct gw_turn_state s = st(0, 0, 0, GW_TURN_NONE);

	(void)state;
	assert_int_equal(gw_turn_next(&s), GW_TURN_NONE);
	s.poll_due = true;
	assert_int_equal(gw_turn_next(&s), GW_TURN_NONE);
	/* the bridge alone: at once, also behind a batch on the line, also inside the line's work */
	s = st(1, 0, 0, GW_TURN_BRIDGE);
	assert_int_equal(gw_turn_next(&s), GW_TURN_BRIDGE);
	s = st(3, 40, 7, GW_TURN_WRITES);
	assert_int_equal(gw_turn_next(&s), GW_TURN_BRIDGE);
	s.in_line = true;
	assert_int_equal(gw_turn_next(&s), GW_TURN_BRIDGE);
	/* writes alone: a batch when none is on the line, between two df1_poll calls */
	s = st(0, 40, 0, GW_TURN_WRITES);
	assert_int_equal(gw_turn_next(&s), GW_TURN_WRITES);
	s.batch = 1;
	assert_int_equal(gw_turn_next(&s), GW_TURN_NONE);
	s.batch = 0;
	s.in_line = true;
	assert_int_equal(gw_turn_next(&s), GW_TURN_NONE);
}

static void test_duty_cycle(void **state)
{
	struct gw_turn_state s = st(0, 40, 0, GW_TURN_WRITES);

	(void)state;
	s.since_read = 10;
	assert_int_equal(gw_turn_next(&s), GW_TURN_WRITES);     /* no read due: the line is the writes' */
	s.poll_due = true;
	assert_int_equal(gw_turn_next(&s), GW_TURN_POLL);       /* a full batch ran: the read first */
	s.since_read = 9;
	assert_int_equal(gw_turn_next(&s), GW_TURN_WRITES);     /* a short batch: the next one may go */
	/* a bridged request does not wait for the read */
	s.since_read = 10;
	s.bridge = 1;
	s.last = GW_TURN_BRIDGE;
	assert_int_equal(gw_turn_next(&s), GW_TURN_BRIDGE);
}

static void test_round_robin(void **state)
{
	struct gw_turn_state s = st(2, 40, 0, GW_TURN_WRITES);

	(void)state;
	assert_int_equal(gw_turn_next(&s), GW_TURN_BRIDGE);
	s.last = GW_TURN_BRIDGE;
	assert_int_equal(gw_turn_next(&s), GW_TURN_WRITES);
	s.last = GW_TURN_NONE;          /* nobody went yet: the bridge */
	assert_int_equal(gw_turn_next(&s), GW_TURN_BRIDGE);
	assert_string_equal(gw_turn_name(GW_TURN_WRITES), "writes");
	assert_string_equal(gw_turn_name(GW_TURN_POLL), "poll");
}

/* ---- the order of service on a model of the line ----
 * A pass of df1gw's loop asks for turns (in_line false), then df1_poll serves
 * the queued work that was there when it began, then, a read being due, what
 * was queued meanwhile and the read. During each transaction the bridge may
 * get a request (line_tick: turns asked with in_line). Out: W a write, B a
 * bridged request, R a poll read. */
struct sim {
	struct gw_turn_state s;
	char q[128];
	int qn;
	char out[256];
	int on, tx;
	int arrive_tx[4];               /* a bridged request comes during these transactions */
	int arrive_pass[4];             /* ... or before these passes (between two df1_poll calls) */
	int pass;
};

static void sim_turns(struct sim *m, bool in_line)
{
	m->s.in_line = in_line;
	for (int i = 0; i < 4; i++) {
		enum gw_turn t = gw_turn_next(&m->s);

		if (t == GW_TURN_BRIDGE) {
			while (m->s.bridge > 0) {
				m->q[m->qn++] = 'B';
				m->s.bridge--;
			}
		} else if (t == GW_TURN_WRITES) {
			size_t n = m->s.backlog < m->s.duty ? m->s.backlog : m->s.duty;

			for (size_t k = 0; k < n; k++)
				m->q[m->qn++] = 'W';
			m->s.backlog -= n;
			m->s.batch = (unsigned)n;
			m->s.since_read += (unsigned)n;
		} else {
			return;
		}
		m->s.last = t;
	}
}

static void sim_tx(struct sim *m, char c)
{
	assert_true(m->on < (int)sizeof m->out - 1);
	m->out[m->on++] = c;
	for (int i = 0; i < 4; i++)
		if (m->arrive_tx[i] == m->tx)
			m->s.bridge++;
	m->tx++;
	sim_turns(m, true);             /* line_tick while its bytes go */
	if (c == 'W')
		m->s.batch--;
	if (c == 'R')
		m->s.since_read = 0;
}

static void sim_pop(struct sim *m)
{
	char c = m->q[0];

	memmove(m->q, m->q + 1, (size_t)--m->qn);
	sim_tx(m, c);
}

static const char *sim_run(struct sim *m, size_t backlog)
{
	m->s.backlog = backlog;
	m->s.duty = 10;
	m->s.poll_due = true;           /* the tags' scan is shorter than a batch */
	for (m->pass = 0; m->pass < 40 && (m->s.backlog || m->s.bridge || m->qn); m->pass++) {
		for (int i = 0; i < 4; i++)
			if (m->arrive_pass[i] == m->pass)
				m->s.bridge++;
		sim_turns(m, false);
		for (int limit = m->qn; limit > 0; limit--)
			sim_pop(m);
		while (m->qn > 0)       /* the scan: queued work before its read */
			sim_pop(m);
		sim_tx(m, 'R');
	}
	m->out[m->on] = '\0';
	return m->out;
}

static struct sim sim_new(void)
{
	struct sim m;

	memset(&m, 0, sizeof m);
	for (int i = 0; i < 4; i++)
		m.arrive_tx[i] = m.arrive_pass[i] = -1;
	return m;
}

#define W10 "WWWWWWWWWW"

static void test_order_of_service(void **state)
{
	struct sim m;

	(void)state;
	/* no bridge: batches of 10 and a read after each */
	m = sim_new();
	assert_string_equal(sim_run(&m, 40), W10 "R" W10 "R" W10 "R" W10 "R");
	/* the issue's case: a request comes during the third write of the first
	 * batch: after that batch, before its read, 3 batches still waiting */
	m = sim_new();
	m.arrive_tx[0] = 2;
	assert_string_equal(sim_run(&m, 40), W10 "BR" W10 "R" W10 "R" W10 "R");
	/* during a read: it goes before the next batch */
	m = sim_new();
	m.arrive_tx[0] = 10;
	assert_string_equal(sim_run(&m, 40), W10 "R" "B" W10 "R" W10 "R" W10 "R");
	/* between two passes, the writes having had the last turn: the bridge first */
	m = sim_new();
	m.arrive_pass[0] = 1;
	assert_string_equal(sim_run(&m, 40), W10 "R" "B" W10 "R" W10 "R" W10 "R");
	/* both at a pass, the bridge having had the last turn (a request handed
	 * during the read): the next batch first, then the new request, behind
	 * that one batch and not behind the backlog */
	m = sim_new();
	m.arrive_tx[0] = 10;
	m.arrive_pass[0] = 1;
	assert_string_equal(sim_run(&m, 30), W10 "R" "B" W10 "B" "R" W10 "R");
	/* requests in every batch and at every pass: each after at most the
	 * batch it came during, or the one whose turn came first */
	m = sim_new();
	m.arrive_tx[0] = 0;
	m.arrive_tx[1] = 13;
	m.arrive_pass[0] = 2;
	m.arrive_pass[1] = 3;
	assert_string_equal(sim_run(&m, 40), W10 "BR" W10 "BR" W10 "BR" W10 "BR");
	/* the same on one pass's order: nobody had a turn yet, the bridge first */
	m = sim_new();
	m.arrive_pass[0] = 0;
	assert_string_equal(sim_run(&m, 20), "B" W10 "R" W10 "R");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_one_source),
		cmocka_unit_test(test_duty_cycle),
		cmocka_unit_test(test_round_robin),
		cmocka_unit_test(test_order_of_service),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
