/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_route_pair - both roles running at once on two handles joined by a
 * socketpair (df1_open_fd): a half-duplex slave whose MSG leaves when polled
 * (lib/link/half_msg.c) on one thread, the master that serves by polling
 * (df1_serve, lib/link/route_round.c) on the other; each handle on one
 * thread, as the one-thread rule asks. The expectations are the data the
 * MSG carried, in the master's table, and the slave's data the master reads
 * while the MSG waits.
 */

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <pthread.h>
#include <stdatomic.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "df1.h"

struct slave {
	df1_t *h;
	struct df1_table *t;
	int rc;                /* the MSG's result */
	const char *remote;
	int station;
	atomic_int done;       /* set by the slave thread, read by the master's */
};

static void *slave_run(void *arg)
{
	struct slave *s = arg;
	int16_t v[2] = { 1234, -5 };

	s->rc = df1_write_int16(s->h, s->station, s->remote, v, 2);
	s->done = 1;
	return NULL;
}

static df1_t *open_end(int fd, enum df1_duplex d, int station)
{
	df1_t *h = NULL;

	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_set_duplex(h, d), 0);
	assert_int_equal(df1_set_station(h, station), 0);
	assert_int_equal(df1_set_timeout_ms(h, 200), 0);
	assert_int_equal(df1_set_cmd_timeout_ms(h, 3000), 0);
	assert_int_equal(df1_open_fd(h, fd, true), 0);
	return h;
}

static struct df1_table *table_n(int file, int n)
{
	struct df1_table *t = NULL;

	assert_int_equal(df1_table_new(&t, DF1_PLC_SLC), 0);
	assert_int_equal(df1_table_add_file(t, DF1_FT_N, file, n), 0);
	return t;
}

/* The master reads station 1 once, then serves until the slave's MSG is over. */
static void master_serve(df1_t *m, struct df1_table *mt, struct slave *s, int16_t *read_back)
{
	/* the slave answers while its own MSG waits; the MSG, queued first, is
	 * its answer to the read's first poll, and the read's reply comes next */
	if (read_back)
		assert_int_equal(df1_read_int16(m, 1, "N7:0", read_back, 1), 1);
	for (int i = 0; i < 400 && !s->done; i++)
		assert_true(df1_serve(m, df1_table_server_ops(mt), mt, 20) >= 0);
}

static void test_slave_msg_to_master(void **state)
{
	struct df1_table *mt = table_n(50, 10), *st = table_n(7, 10);
	struct slave s = { .remote = "N50:2", .station = 0 };
	struct df1_value got[2], seven;
	int16_t slave_n7 = 0;
	struct df1_route_stats rs;
	pthread_t th;
	int sv[2];
	df1_t *m;

	(void)state;
	memset(got, 0, sizeof got);
	memset(&seven, 0, sizeof seven);
	seven.v.i16 = 77;
	assert_true(df1_table_write(st, "N7:0", &seven, 1) >= 0);
	assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
	m = open_end(sv[0], DF1_HALF_DUPLEX_MASTER, 0);
	s.h = open_end(sv[1], DF1_HALF_DUPLEX_SLAVE, 1);
	s.t = st;
	assert_int_equal(df1_set_responder(s.h, df1_table_server_ops(st), st), 0);
	assert_int_equal(df1_server_add_station(m, 1), 0);
	assert_int_equal(pthread_create(&th, NULL, slave_run, &s), 0);
	master_serve(m, mt, &s, &slave_n7);
	assert_int_equal(pthread_join(th, NULL), 0);
	assert_int_equal(s.rc, 2); /* the elements written */
	assert_true(df1_table_read(mt, "N50:2", got, 2) >= 0);
	assert_int_equal(got[0].v.i16, 1234);
	assert_int_equal(got[1].v.i16, -5);
	assert_int_equal(slave_n7, 77);
	assert_int_equal(df1_route_stats(m, &rs), 0);
	assert_int_equal(rs.executed, 1);
	df1_free(s.h);
	df1_free(m);
	df1_table_free(mt);
	df1_table_free(st);
}

static void test_slave_msg_error_sts(void **state)
{
	/* a file the master does not serve: the master's STS, seen by the slave */
	struct df1_table *mt = table_n(50, 10), *st = table_n(7, 10);
	struct slave s = { .remote = "N51:0", .station = 0 };
	pthread_t th;
	int sv[2];
	df1_t *m;

	(void)state;
	assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
	m = open_end(sv[0], DF1_HALF_DUPLEX_MASTER, 0);
	s.h = open_end(sv[1], DF1_HALF_DUPLEX_SLAVE, 1);
	assert_int_equal(df1_server_add_station(m, 1), 0);
	assert_int_equal(pthread_create(&th, NULL, slave_run, &s), 0);
	master_serve(m, mt, &s, NULL);
	assert_int_equal(pthread_join(th, NULL), 0);
	assert_int_equal(s.rc, DF1_E_REMOTE);
	assert_int_equal(df1_last_error(s.h)->sts, 0xF0);
	df1_free(s.h);
	df1_free(m);
	df1_table_free(mt);
	df1_table_free(st);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_slave_msg_to_master),
		cmocka_unit_test(test_slave_msg_error_sts),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
