/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_serve.c - df1mon --serve REGION[,REGION...] (df1mon(1)): a data table
 * of those regions answers what a PLC sends on its own (a MSG write or read)
 * on the device, as a full-duplex peer or as a half-duplex slave station
 * (--duplex half-slave at --src), and each write that lands is printed with
 * its sender (df1_server_source(3)), so that a technician sees what a PLC
 * sends without a gateway. A region is ADDRESS[,COUNT] ("N50:0,10"); writes
 * and reads outside the regions get the STS a PLC gives (the table's answer,
 * EXT STS 07h for a gap between two regions of one file).
 */
#include "df1mon/mon.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define SERVE_REGIONS_MAX 32

struct serve_region {
	struct df1_addr a;
	int count;
	size_t lo, hi;              /* its bytes in its file */
};

struct serve {
	struct mon *m;
	struct df1_table *t;
	struct serve_region r[SERVE_REGIONS_MAX];
	int n;
	unsigned long writes, reads;
};

/* "N50:0,10,B3:0,N51:5,2": an address starts a region, a number after it is its count. */
static int serve_parse(struct serve *s, const char *spec)
{
	char buf[1024], *save = NULL, *tok;
	int plc = s->m->cli.plc;

	if (snprintf(buf, sizeof buf, "%s", spec) >= (int)sizeof buf)
		return cli_usage_error(&s->m->cli, "--serve: too long");
	for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		struct serve_region *r = &s->r[s->n];
		char *end;
		long v;

		errno = 0;
		v = strtol(tok, &end, 10);
		if (*tok && !*end && !errno && s->n > 0 && s->r[s->n - 1].count == 0) {
			if (v < 1 || v > DF1_TABLE_ELEMENTS_MAX)
				return cli_usage_error(&s->m->cli, "--serve: count %s is not 1-%d", tok,
				                       DF1_TABLE_ELEMENTS_MAX);
			s->r[s->n - 1].count = (int)v;
			continue;
		}
		if (s->n == SERVE_REGIONS_MAX)
			return cli_usage_error(&s->m->cli, "--serve: at most %d regions", SERVE_REGIONS_MAX);
		if (df1_addr_parse_plc((enum df1_plc)plc, tok, &r->a) < 0 || r->a.ascii[0] || r->a.file <= 0)
			return cli_usage_error(&s->m->cli, "--serve: '%s' is not a data-table address (expected "
			                       "ADDRESS[,COUNT][,ADDRESS[,COUNT]...], e.g. N50:0,10)", tok);
		if (r->a.bit != DF1_ADDR_NONE || r->a.sub != DF1_ADDR_NONE)
			return cli_usage_error(&s->m->cli, "--serve: '%s': a region is whole elements "
			                       "(no /bit or .member)", tok);
		r->count = 0;
		s->n++;
	}
	if (!s->n)
		return cli_usage_error(&s->m->cli, "--serve: no region (e.g. --serve N50:0,10)");
	return CLI_CONTINUE;
}

/* The table: each region's file, as long as the region needs. */
static int serve_table(struct serve *s)
{
	if (df1_table_new(&s->t, s->m->cli.plc) < 0)
		return CLI_EXIT_FAIL;
	for (int i = 0; i < s->n; i++) {
		struct serve_region *r = &s->r[i];
		size_t esize = (size_t)df1_file_type_element_size(r->a.type);
		int rc;

		if (!r->count)
			r->count = 1;
		if (r->a.element + r->count > DF1_TABLE_ELEMENTS_MAX)
			return cli_usage_error(&s->m->cli, "--serve: region %d runs past element %d", i + 1,
			                       DF1_TABLE_ELEMENTS_MAX - 1);
		r->lo = (size_t)r->a.element * esize;
		r->hi = (size_t)(r->a.element + r->count) * esize;
		rc = df1_table_add_file(s->t, r->a.type, r->a.file, r->a.element + r->count);
		if (rc < 0)
			return cli_usage_error(&s->m->cli, "--serve: region %d: file %d: %s", i + 1, r->a.file,
			                       rc == DF1_E_TYPE ? "given with two types" : df1_strerror(rc));
	}
	return CLI_CONTINUE;
}

/* Do the regions of a's file cover its nbytes? */
static bool serve_covered(const struct serve *s, const struct df1_addr *a, size_t nbytes)
{
	size_t lo = (size_t)a->element * (size_t)df1_file_type_element_size(a->type) +
	            (a->sub == DF1_ADDR_NONE ? 0 : (size_t)a->sub * 2), hi = lo + nbytes;
	bool grew = true;

	while (lo < hi && grew) {
		grew = false;
		for (int i = 0; i < s->n; i++)
			if (s->r[i].a.type == a->type && s->r[i].a.file == a->file && s->r[i].lo <= lo &&
			    s->r[i].hi > lo) {
				lo = s->r[i].hi;
				grew = true;
			}
	}
	return lo >= hi;
}

static int serve_check(struct serve *s, int station, const struct df1_addr *a, size_t nbytes)
{
	static uint8_t scratch[512];    /* more than a DF1 frame's data */
	int rc = df1_table_server_ops(s->t)->read(s->t, station, a, scratch, nbytes > sizeof scratch ? 0 : nbytes);

	if (rc || nbytes == 0)
		return rc;
	return serve_covered(s, a, nbytes) ? 0 : 0x07;
}

/* One write that landed: "HH:MM:SS.mmm from 3 to 0: N50:0 = 1 2 3 (3 elements)". */
static void serve_print(struct serve *s, int station, const struct df1_addr *a, size_t nbytes)
{
	static struct df1_value v[DF1_TABLE_ELEMENTS_MAX];
	struct df1_addr at = *a;
	int esize = df1_file_type_element_size(a->type), n;
	char text[160], when[32];
	int64_t sec;
	int32_t usec;

	n = esize > 0 ? (int)((nbytes + (size_t)esize - 1) / (size_t)esize) : 0;
	mon_wall_now(&sec, &usec);
	strftime(when, sizeof when, "%H:%M:%S", localtime(&(time_t){ (time_t)sec }));
	if (df1_addr_format(&at, text, sizeof text) < 0)
		snprintf(text, sizeof text, "?");
	printf("%s.%03d from %d to %d: %s =", when, (int)(usec / 1000), df1_server_source(s->m->h), station, text);
	n = n > 0 ? df1_table_read_addr(s->t, &at, v, (size_t)n) : 0;
	for (int i = 0; i < n; i++) {
		if (df1_value_format(&v[i], a->type, text, sizeof text) < 0)
			snprintf(text, sizeof text, "?");
		printf(" %s", text);
	}
	printf(" (%zu bytes)\n", nbytes);
	fflush(stdout);
}

static int serve_op_read(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes)
{
	struct serve *s = user;
	int rc = serve_check(s, station, a, nbytes);

	if (!rc && nbytes)
		s->reads++;
	return rc ? rc : df1_table_server_ops(s->t)->read(s->t, station, a, buf, nbytes);
}

static int serve_op_write(void *user, int station, const struct df1_addr *a, const uint8_t *buf,
                          const uint8_t *mask, size_t nbytes)
{
	struct serve *s = user;
	int rc = serve_check(s, station, a, nbytes);

	if (!rc)
		rc = df1_table_server_ops(s->t)->write(s->t, station, a, buf, mask, nbytes);
	if (!rc) {
		s->writes++;
		serve_print(s, station, a, nbytes);
	}
	return rc;
}

static int serve_op_diag(void *user, int station, uint8_t *buf, size_t cap)
{
	struct serve *s = user;

	return df1_table_server_ops(s->t)->diag_status(s->t, station, buf, cap);
}

static const struct df1_server_ops serve_ops = {
	.read = serve_op_read,
	.write = serve_op_write,
	.diag_status = serve_op_diag,
};

int mon_serve_check(struct mon *m)
{
	static struct serve s;          /* a scratch parse: the regions are read again by the run */

	memset(&s, 0, sizeof s);
	s.m = m;
	return serve_parse(&s, m->serve_spec);
}

int mon_run_serve(struct mon *m)
{
	struct serve s;
	int r;

	memset(&s, 0, sizeof s);
	s.m = m;
	r = serve_parse(&s, m->serve_spec);
	if (r == CLI_CONTINUE)
		r = serve_table(&s);
	if (r == CLI_CONTINUE && m->cli.half_slave && df1_server_add_station(m->h, m->cli.src) < 0) {
		fprintf(stderr, "%s: --serve: cannot serve station %d\n", m->cli.name, m->cli.src);
		r = CLI_EXIT_FAIL;
	}
	if (r == CLI_CONTINUE && !m->cli.quiet) {
		fprintf(stderr, "%s: serving %d region%s on %s as station %d (%s); Ctrl-C ends\n", m->cli.name,
		        s.n, s.n == 1 ? "" : "s", m->cli.device, m->cli.src,
		        m->cli.half_slave ? "half-duplex slave" : m->cli.radio ? "radio modem"
		                                                : "full-duplex peer");
	}
	while (r == CLI_CONTINUE && !cli_stop) {
		int rc = df1_serve(m->h, &serve_ops, &s, 200);

		if (rc < 0 && rc != DF1_E_TIMEOUT && rc != DF1_E_INTR) {
			fprintf(stderr, "%s: %s: %s\n", m->cli.name, m->cli.device, df1_strerror(rc));
			r = CLI_EXIT_FAIL;
		}
	}
	if (!m->cli.quiet && s.t)
		fprintf(stderr, "%s: %lu writes, %lu reads served\n", m->cli.name, s.writes, s.reads);
	df1_table_free(s.t);
	return r == CLI_CONTINUE ? CLI_EXIT_OK : r;
}
