/* SPDX-License-Identifier: MPL-2.0 */
/*
 * msg_receiver - a full-duplex master that also takes what the controller
 * sends on its own (a MSG instruction), as df1_set_responder(3) describes:
 * it serves a data table with the integer file N50 (ELEMENTS words) to the
 * peer and polls the peer's N7:0,10, B3:0,4, F8:0,4 and T4:0,2 meanwhile
 * with the poll engine. Each write the controller makes is printed on stdout
 * as "recv STATION N50:E FIRST_VALUE COUNT"; at the end "reads N", the good
 * reads of N7:0,10.
 *
 *   msg_receiver DEVICE STATION ELEMENTS SECONDS [OUTSTANDING]
 *
 * tests/integration/it_unsolicited.sh runs it against df1sim --msg.
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

/* The table's own callbacks, with each write printed before it is stored. */
static int rx_read(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes)
{
	(void)user;
	return df1_table_server_ops(table)->read(table, station, a, buf, nbytes);
}

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

static int add_tag(df1_t *h, int station, const char *addr, int count)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "%s", addr);
	c.access = DF1_ACCESS_READ;
	c.station = station;
	c.plc = DF1_PLC_SLC;
	c.count = count;
	c.scan_ms = 0;
	if (df1_addr_parse(addr, &c.addr) < 0)
		return -1;
	return df1_tag_add(h, &c);
}

int main(int argc, char **argv)
{
	static const char *const tags[] = { "N7:0", "B3:0", "F8:0", "T4:0" };
	static const int counts[] = { 10, 4, 4, 2 };
	df1_t *h = NULL;
	struct df1_tag_state st;
	int station, elements, seconds, outstanding = 1, rc;

	if (argc < 5 || argc > 6) {
		fprintf(stderr, "usage: %s DEVICE STATION ELEMENTS SECONDS [OUTSTANDING]\n", argv[0]);
		return 2;
	}
	station = atoi(argv[2]);
	elements = atoi(argv[3]);
	seconds = atoi(argv[4]);
	if (argc == 6)
		outstanding = atoi(argv[5]);
	if (df1_new(&h) < 0 || df1_table_new(&table, DF1_PLC_SLC) < 0 ||
	    df1_table_add_file(table, DF1_FT_N, 50, elements) < 0)
		return 1;
	df1_set_timeout_ms(h, 1000);
	if (df1_set_option(h, DF1_OPT_MAX_OUTSTANDING, outstanding) < 0 ||
	    df1_set_responder(h, &rx_ops, NULL) < 0)
		return 1;
	for (int i = 0; i < 4; i++)
		if (add_tag(h, station, tags[i], counts[i]) < 0)
			return 1;
	rc = df1_open(h, argv[1]);
	if (rc < 0) {
		fprintf(stderr, "%s: %s\n", argv[0], df1_last_error(h)->message);
		return 1;
	}
	/* the poll engine's scans: the controller's commands are answered inside them */
	for (long long end = now_ms() + (long long)seconds * 1000; now_ms() < end;) {
		rc = df1_poll(h, 50);
		if (rc < 0 && rc != DF1_E_TIMEOUT) {
			fprintf(stderr, "%s: df1_poll: %s\n", argv[0], df1_last_error(h)->message);
			break;
		}
	}
	if (df1_tag_get(h, 0, &st) == 0)
		printf("reads %llu\n", (unsigned long long)st.reads);
	df1_close(h);
	df1_free(h);
	df1_table_free(table);
	return 0;
}
