/* SPDX-License-Identifier: MPL-2.0 */
/*
 * route_master - a half-duplex master that keeps its slaves polled, so that
 * the MSGs they send leave: those for its own station (0) write into the
 * integer file N50 it serves (printed as "recv STATION N50:E FIRST_VALUE
 * COUNT"), those for another slave are forwarded to it and its reply sent
 * back (DF1_OPT_ROUTE; libdf1(7) UNSOLICITED MESSAGES).
 *
 *   route_master DEVICE SECONDS ROUTE serve|poll|both STATION... [-- STATION ADDR...]
 *
 * serve: df1_serve() with the stations added (df1_server_add_station);
 * poll: the poll engine reads N7:0 of each station every 500 ms and polls the
 * slaves between its scans; both: df1_poll and df1_serve in turn on the one
 * handle. ROUTE is 1 or 0. At the end it prints, for each
 * pair after "--", "read STATION ADDR VALUE" (the word read there), then
 * "stats EXECUTED ROUTED BROADCASTS ROUTE_REPLIES UNDELIVERABLE".
 * tests/integration/it_route.sh runs it against three df1sim slaves.
 */
#include <df1.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static struct df1_table *table;

static long long now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (long long)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static int rx_read(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes)
{
	(void)user;
	return df1_table_server_ops(table)->read(table, station, a, buf, nbytes);
}

/* The table's own write, with each write printed before it is stored. */
static int rx_write(void *user, int station, const struct df1_addr *a, const uint8_t *buf,
                    const uint8_t *mask, size_t nbytes)
{
	int rc = df1_table_server_ops(table)->write(table, station, a, buf, mask, nbytes);

	(void)user;
	if (rc == 0 && nbytes >= 2)
		printf("recv %d N%d:%d %d %zu\n", station, a->file, a->element,
		       (int16_t)(buf[0] | buf[1] << 8), nbytes / 2);
	fflush(stdout);
	return rc;
}

static const struct df1_server_ops rx_ops = { .read = rx_read, .write = rx_write };

static int add_tag(df1_t *h, int station)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "N7:0@%d", station);
	c.access = DF1_ACCESS_READ;
	c.station = station;
	c.plc = DF1_PLC_SLC;
	c.count = 1;
	c.scan_ms = 500;
	if (df1_addr_parse("N7:0", &c.addr) < 0)
		return -1;
	return df1_tag_add(h, &c);
}

static int setup(df1_t *h, int argc, char **argv, int first, int last, int route)
{
	bool poll = strcmp(argv[4], "serve") != 0;

	df1_set_duplex(h, DF1_HALF_DUPLEX_MASTER);
	df1_set_station(h, 0);
	df1_set_timeout_ms(h, 200);
	df1_set_cmd_timeout_ms(h, 1000);
	if (df1_set_option(h, DF1_OPT_ROUTE, route) < 0 || df1_set_responder(h, &rx_ops, NULL) < 0)
		return -1;
	for (int i = first; i < last; i++) {
		int stn = atoi(argv[i]);

		if ((poll ? add_tag(h, stn) : df1_server_add_station(h, stn)) < 0)
			return -1;
	}
	(void)argc;
	return 0;
}

/* mode: 1 df1_poll, 0 df1_serve, 2 both in turn on the one handle (one thread) */
static void run(df1_t *h, int mode, int seconds)
{
	int i = 0;

	for (long long end = now_ms() + (long long)seconds * 1000; now_ms() < end; i++) {
		bool poll = mode == 1 || (mode == 2 && i % 2);
		int rc = poll ? df1_poll(h, 50) : df1_serve(h, &rx_ops, NULL, 50);

		if (rc < 0 && rc != DF1_E_TIMEOUT) {
			fprintf(stderr, "route_master: %s\n", df1_last_error(h)->message);
			break;
		}
	}
}

int main(int argc, char **argv)
{
	struct df1_route_stats st;
	df1_t *h = NULL;
	int last = argc, rc;

	if (argc < 6) {
		fprintf(stderr, "usage: %s DEVICE SECONDS ROUTE serve|poll|both STATION... [-- STATION ADDR...]\n",
		        argv[0]);
		return 2;
	}
	for (int i = 5; i < argc; i++)
		if (!strcmp(argv[i], "--"))
			last = i;
	if (df1_new(&h) < 0 || df1_table_new(&table, DF1_PLC_SLC) < 0 ||
	    df1_table_add_file(table, DF1_FT_N, 50, 20) < 0 ||
	    setup(h, argc, argv, 5, last, atoi(argv[3])) < 0)
		return 1;
	rc = df1_open(h, argv[1]);
	if (rc < 0) {
		fprintf(stderr, "route_master: %s\n", df1_last_error(h)->message);
		return 1;
	}
	run(h, !strcmp(argv[4], "poll") ? 1 : !strcmp(argv[4], "both") ? 2 : 0, atoi(argv[2]));
	for (int i = last + 1; i + 1 < argc; i += 2) {
		int16_t v = 0;

		rc = df1_read_int16(h, atoi(argv[i]), argv[i + 1], &v, 1);
		if (rc < 0)
			printf("read %s %s error\n", argv[i], argv[i + 1]);
		else
			printf("read %s %s %d\n", argv[i], argv[i + 1], v);
	}
	/* after the reads: their polls may have brought more */
	df1_route_stats(h, &st);
	printf("stats %llu %llu %llu %llu %llu\n", (unsigned long long)st.executed,
	       (unsigned long long)st.routed, (unsigned long long)st.broadcasts,
	       (unsigned long long)st.route_replies, (unsigned long long)st.undeliverable);
	fflush(stdout);
	df1_close(h);
	df1_free(h);
	df1_table_free(table);
	return 0;
}
