/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_config.c - network and mapping CSV files (lib/config/config_csv.c, config_net.c, config_map.c).
 *
 * Expected ranges, defaults, catalog IDs and message texts are those of
 * doc/REQUIREMENTS.md 004 (network configuration table, catalog 2501-2504 and 2552-2559),
 * written out here by hand. Data files: tests/data/ (DF1_TEST_DATA overrides the
 * directory), examples/ (DF1_EXAMPLES); other cases are written to temp files.
 *
 * df1_apply_net_config() is checked on a real handle through its stored settings
 * (lib/df1_int.h).
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "df1.h"
#include "df1_int.h"

/* ---- helpers ---------------------------------------------------------------- */

#define MAX_ISSUES 64

struct issues {
	int n;
	struct df1_config_issue v[MAX_ISSUES];
};

static void collect_issue(void *user, const struct df1_config_issue *is)
{
	struct issues *s = user;

	if (s->n < MAX_ISSUES)
		s->v[s->n] = *is;
	s->n++;
}

static void dump_issues(const struct issues *s)
{
	int i;

	for (i = 0; i < s->n && i < MAX_ISSUES; i++)
		print_message("  issue %d: id %d item %d line %d: %s\n", i, s->v[i].catalog_id,
		              s->v[i].item, s->v[i].line, s->v[i].text);
}

static const char *data_path(const char *name)
{
	static char buf[512];
	const char *dir = getenv("DF1_TEST_DATA");

	snprintf(buf, sizeof buf, "%s/%s", dir && *dir ? dir : "tests/data", name);
	return buf;
}

static const char *example_path(const char *name)
{
	static char buf[512];
	const char *dir = getenv("DF1_EXAMPLES");

	snprintf(buf, sizeof buf, "%s/%s", dir && *dir ? dir : "examples", name);
	return buf;
}

/* Write text to a new temp file; path in buf. */
static void temp_file(char *buf, size_t cap, const char *text)
{
	int fd;
	size_t n = strlen(text);

	snprintf(buf, cap, "/tmp/df1_test_config_XXXXXX");
	fd = mkstemp(buf);
	assert_true(fd >= 0);
	assert_int_equal(write(fd, text, n), (ssize_t)n);
	close(fd);
}

/* The same with n bytes of text, which may hold NUL bytes. */
static void temp_file_bytes(char *buf, size_t cap, const char *text, size_t n)
{
	int fd;

	snprintf(buf, cap, "/tmp/df1_test_config_XXXXXX");
	fd = mkstemp(buf);
	assert_true(fd >= 0);
	assert_int_equal(write(fd, text, n), (ssize_t)n);
	close(fd);
}

static int net_load_bytes(const char *text, size_t n, struct df1_net_config *c, struct issues *is)
{
	char path[64];
	int rc;

	temp_file_bytes(path, sizeof path, text, n);
	memset(is, 0, sizeof *is);
	rc = df1_net_config_load(path, c, collect_issue, is);
	unlink(path);
	return rc;
}

static int net_load_text(const char *text, struct df1_net_config *c, struct issues *is)
{
	char path[64];
	int rc;

	temp_file(path, sizeof path, text);
	memset(is, 0, sizeof *is);
	rc = df1_net_config_load(path, c, collect_issue, is);
	unlink(path);
	return rc;
}

struct tags {
	int n;
	struct df1_tag_config v[32];
	int stop_after;          /* return DF1_E_INTR from the row callback after this many */
};

static int collect_tag(void *user, const struct df1_tag_config *t)
{
	struct tags *s = user;

	if (s->n < 32)
		s->v[s->n] = *t;
	s->n++;
	if (s->stop_after > 0 && s->n >= s->stop_after)
		return DF1_E_INTR;
	return 0;
}

/* One user pointer for both callbacks of df1_map_load. */
struct map_result {
	struct tags tags;
	struct issues issues;
};

static int map_row(void *user, const struct df1_tag_config *t)
{
	return collect_tag(&((struct map_result *)user)->tags, t);
}

static void map_issue(void *user, const struct df1_config_issue *is)
{
	collect_issue(&((struct map_result *)user)->issues, is);
}

static int map_load_path(const char *path, bool strict, struct map_result *r)
{
	int stop = r->tags.stop_after;

	memset(r, 0, sizeof *r);
	r->tags.stop_after = stop;
	return df1_map_load(path, strict, map_row, map_issue, r);
}

static int map_load_text(const char *text, bool strict, struct map_result *r)
{
	char path[64];
	int rc;

	temp_file(path, sizeof path, text);
	rc = map_load_path(path, strict, r);
	unlink(path);
	return rc;
}

static int map_load_bytes(const char *text, size_t n, bool strict, struct map_result *r)
{
	char path[64];
	int rc;

	temp_file_bytes(path, sizeof path, text, n);
	rc = map_load_path(path, strict, r);
	unlink(path);
	return rc;
}

static void assert_tag_addr(const struct df1_tag_config *t, const char *canonical)
{
	char buf[64];

	assert_true(df1_addr_format(&t->addr, buf, sizeof buf) > 0);
	assert_string_equal(buf, canonical);
}

/* ---- network: defaults and valid files ------------------------------------- */

static void assert_seed_defaults(const struct df1_net_config *c)
{
	/* doc/REQUIREMENTS.md 004 network configuration table */
	assert_int_equal(c->station, 5);
	assert_int_equal(c->mode, DF1_MODE_MASTER);
	assert_int_equal(c->plc, DF1_PLC_PLC5);
	assert_int_equal(c->check, DF1_CHECK_CRC);
	assert_int_equal(c->nak_retries, 3);
	assert_int_equal(c->enq_retries, 3);
	assert_int_equal(c->cmd_timeout_ms, 1000);
	assert_string_equal(c->port, "/dev/ttyS0"); /* Com_Port 1 */
	assert_false(c->port_given);
	assert_int_equal(c->baud, 9600);
	assert_int_equal(c->data_bits, 8);
	assert_int_equal(c->stop_bits, 1);
	assert_int_equal(c->parity, 'N');
	assert_int_equal(c->timeout_ms, 1000);
	assert_int_equal(c->tx_delay_ms, 0);
	assert_false(c->handshake);
	assert_true(c->duplex_half); /* Master: half duplex */
}

static void test_config_net_defaults_match_seed(void **state)
{
	struct df1_net_config c;

	(void)state;
	memset(&c, 0x77, sizeof c);
	df1_net_config_defaults(&c);
	assert_seed_defaults(&c);
	df1_net_config_defaults(NULL); /* no crash */
}

static void test_config_net_valid_file_gives_values(void **state)
{
	struct df1_net_config c;
	struct issues is = { 0 };
	int rc;

	(void)state;
	rc = df1_net_config_load(data_path("net_valid.csv"), &c, collect_issue, &is);
	if (rc != 0)
		dump_issues(&is);
	assert_int_equal(rc, 0);
	assert_int_equal(is.n, 0);
	assert_true(c.handshake);
	assert_int_equal(c.baud, 19200);
	assert_int_equal(c.parity, 'E');
	assert_int_equal(c.data_bits, 7);
	assert_int_equal(c.stop_bits, 2);
	assert_int_equal(c.station, 12);
	assert_int_equal(c.mode, DF1_MODE_SLAVE);
	assert_true(c.duplex_half);
	assert_int_equal(c.plc, DF1_PLC_SLC);
	assert_int_equal(c.check, DF1_CHECK_BCC);
	assert_int_equal(c.nak_retries, 5);
	assert_int_equal(c.enq_retries, 6);
	assert_int_equal(c.cmd_timeout_ms, 2500);
	assert_string_equal(c.port, "/dev/ttyUSB1");
	assert_true(c.port_given);
	assert_int_equal(c.timeout_ms, 1500);
	assert_int_equal(c.tx_delay_ms, 20);
}

/* A network file must hold a data row: a header alone (or with blank and
 * comment rows only) would configure the line with every default, on
 * /dev/ttyS0, without a word. No seed ID (2552-2559) names a missing row:
 * catalog ID 0, a text naming the file, DF1_E_CONFIG, *c untouched. */
static void test_config_net_header_only_is_an_error(void **state)
{
	static const char *const texts[] = {
		"Station,Mode,Baud\n",
		"Station,Mode,Baud",                      /* no final newline */
		"Station,Mode,Baud\n,,\"\"\n",             /* a blank row is no data row */
		"# comment\nStation,Mode,Baud\n\n# more\n",
	};
	struct df1_net_config c;
	struct issues is;
	char path[64];
	size_t i;
	int rc;

	(void)state;
	for (i = 0; i < sizeof texts / sizeof texts[0]; i++) {
		temp_file(path, sizeof path, texts[i]);
		memset(&is, 0, sizeof is);
		memset(&c, 0x5A, sizeof c);
		rc = df1_net_config_load(path, &c, collect_issue, &is);
		if (rc != DF1_E_CONFIG || is.n != 1)
			dump_issues(&is);
		assert_int_equal(rc, DF1_E_CONFIG);
		assert_int_equal(c.station, 0x5A5A5A5A);
		assert_int_equal(is.n, 1);
		assert_int_equal(is.v[0].catalog_id, 0);
		assert_int_equal(is.v[0].item, 0);
		assert_non_null(strstr(is.v[0].text, path));
		assert_non_null(strstr(is.v[0].text, "no data row"));
		unlink(path);
	}
	/* one data row: the cells given, the defaults for the rest */
	assert_int_equal(net_load_text("Station\n7\n", &c, &is), 0);
	assert_int_equal(c.station, 7);
	assert_int_equal(c.baud, 9600);
	assert_int_equal(net_load_text("Station,Mode,Baud\n,Master,\n", &c, &is), 0);
	assert_seed_defaults(&c);
}

struct net_valid_case {
	const char *column;
	const char *value;
	size_t offset;        /* int member of struct df1_net_config */
	int want;
};

#define NET_OFF(m) offsetof(struct df1_net_config, m)

static void test_config_net_boundary_values_accepted(void **state)
{
	static const struct net_valid_case cases[] = {
		{ "Station", "0", NET_OFF(station), 0 },
		{ "Station", "254", NET_OFF(station), 254 },
		{ "Station", "+17", NET_OFF(station), 17 },
		{ "NAK_Retries", "0", NET_OFF(nak_retries), 0 },
		{ "NAK_Retries", "10", NET_OFF(nak_retries), 10 },
		{ "ENQ_Retries", "0", NET_OFF(enq_retries), 0 },
		{ "ENQ_Retries", "10", NET_OFF(enq_retries), 10 },
		{ "Cmd_Timeout", "500", NET_OFF(cmd_timeout_ms), 500 },
		{ "Cmd_Timeout", "5000", NET_OFF(cmd_timeout_ms), 5000 },
		{ "Baud", "1200", NET_OFF(baud), 1200 },
		{ "Baud", "2400", NET_OFF(baud), 2400 },
		{ "Baud", "4800", NET_OFF(baud), 4800 },
		{ "Baud", "9600", NET_OFF(baud), 9600 },
		{ "Baud", "19200", NET_OFF(baud), 19200 },
		{ "Baud", "38400", NET_OFF(baud), 38400 },
		{ "Baud", "57600", NET_OFF(baud), 57600 },
		{ "Baud", "115200", NET_OFF(baud), 115200 },
		{ "Data_Bits", "5", NET_OFF(data_bits), 5 },
		{ "Data_Bits", "8", NET_OFF(data_bits), 8 },
		{ "Stop_Bits", "2", NET_OFF(stop_bits), 2 },
		{ "Timeout", "0", NET_OFF(timeout_ms), 0 },
		{ "Timeout", "360000", NET_OFF(timeout_ms), 360000 },
		{ "TX_Delay", "65535", NET_OFF(tx_delay_ms), 65535 },
		{ "Mode", "master", NET_OFF(mode), DF1_MODE_MASTER },
		{ "Mode", "SLAVE", NET_OFF(mode), DF1_MODE_SLAVE },
		{ "Mode", "Peer", NET_OFF(mode), DF1_MODE_PEER },
		{ "PLC_Type", "PLC2", NET_OFF(plc), DF1_PLC_PLC2 },
		{ "PLC_Type", "PLC5", NET_OFF(plc), DF1_PLC_PLC5 },
		{ "PLC_Type", "PLC3", NET_OFF(plc), DF1_PLC_PLC3 },
		{ "PLC_Type", "PLC-3", NET_OFF(plc), DF1_PLC_PLC3 },
		{ "PLC_Type", "PLC-5", NET_OFF(plc), DF1_PLC_PLC5 },
		{ "PLC_Type", "SLC", NET_OFF(plc), DF1_PLC_SLC },
		{ "PLC_Type", "slc500", NET_OFF(plc), DF1_PLC_SLC },
		{ "PLC_Type", "SLC 5/04", NET_OFF(plc), DF1_PLC_SLC },
		{ "PLC_Type", "SLC 5/02", NET_OFF(plc), DF1_PLC_SLC502 },
		{ "PLC_Type", "SLC502", NET_OFF(plc), DF1_PLC_SLC502 },
		{ "PLC_Type", "MicroLogix", NET_OFF(plc), DF1_PLC_MICROLOGIX },
		{ "PLC_Type", "ML", NET_OFF(plc), DF1_PLC_MICROLOGIX },
		{ "PLC_Type", "MicroLogix 1400", NET_OFF(plc), DF1_PLC_MICROLOGIX },
		{ "PLC_Type", "ML1100", NET_OFF(plc), DF1_PLC_MICROLOGIX },
		{ "Error_Code", "BCC", NET_OFF(check), DF1_CHECK_BCC },
		{ "Error_Code", "crc", NET_OFF(check), DF1_CHECK_CRC },
		{ "Parity", "even", NET_OFF(parity), 'E' },
		{ "Parity", "Odd", NET_OFF(parity), 'O' },
		{ "Parity", "NONE", NET_OFF(parity), 'N' },
		{ "Parity", "E", NET_OFF(parity), 'E' },
	};
	size_t i;

	(void)state;
	for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char text[128];
		struct df1_net_config c;
		struct issues is;
		int got, rc;

		snprintf(text, sizeof text, "%s\n%s\n", cases[i].column, cases[i].value);
		rc = net_load_text(text, &c, &is);
		if (rc != 0) {
			dump_issues(&is);
			fail_msg("%s=%s: rc %d", cases[i].column, cases[i].value, rc);
		}
		if (cases[i].offset == NET_OFF(parity))
			got = c.parity;
		else if (cases[i].offset == NET_OFF(mode))
			got = (int)c.mode;
		else if (cases[i].offset == NET_OFF(plc))
			got = (int)c.plc;
		else if (cases[i].offset == NET_OFF(check))
			got = (int)c.check;
		else
			memcpy(&got, (const char *)&c + cases[i].offset, sizeof got);
		if (got != cases[i].want)
			fail_msg("%s=%s: got %d, want %d", cases[i].column, cases[i].value, got,
			         cases[i].want);
	}
}

static void test_config_net_handshake_and_mode_duplex(void **state)
{
	struct df1_net_config c;
	struct issues is;

	(void)state;
	assert_int_equal(net_load_text("Handshake\nyes\n", &c, &is), 0);
	assert_true(c.handshake);
	assert_int_equal(net_load_text("Handshake\nNo\n", &c, &is), 0);
	assert_false(c.handshake);
	assert_int_equal(net_load_text("Mode\nPeer\n", &c, &is), 0);
	assert_false(c.duplex_half);
	assert_int_equal(net_load_text("Mode\nSlave\n", &c, &is), 0);
	assert_true(c.duplex_half);
	assert_int_equal(net_load_text("Mode\nMaster\n", &c, &is), 0);
	assert_true(c.duplex_half);
}

/* The extension columns Link and Store_Forward (libdf1(7) "Network file"). */
static void test_config_net_link_and_store_forward(void **state)
{
	struct df1_net_config c;
	struct issues is;
	df1_t *h = NULL;
	uint8_t t[32];

	(void)state;
	/* absent: from Mode, as before */
	assert_int_equal(net_load_text("Mode\nMaster\n", &c, &is), 0);
	assert_false(c.radio);
	assert_false(c.forward_set);
	assert_int_equal(net_load_text("Mode,Link\nMaster,Full\n", &c, &is), 0);
	assert_false(c.duplex_half);
	assert_false(c.radio);
	assert_int_equal(net_load_text("Mode,Link\nSlave,half\n", &c, &is), 0);
	assert_true(c.duplex_half);
	assert_int_equal(net_load_text("Mode,Link,Store_Forward\nPeer,Radio,\"1,3-4\"\n", &c, &is), 0);
	assert_true(c.radio);
	assert_false(c.duplex_half);
	assert_true(c.forward_set);
	/* bit s%8 of byte s/8 (df1_set_forward(3)): stations 1, 3 and 4 */
	assert_int_equal(c.forward[0], 0x1A);
	for (int i = 1; i < 32; i++)
		assert_int_equal(c.forward[i], 0);

	/* each bad value named, catalog ID 0 (no seed ID fits) */
	assert_int_equal(net_load_text("Link\nSatellite\n", &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_int_equal(is.v[0].catalog_id, 0);
	assert_non_null(strstr(is.v[0].text, "Invalid Link (Satellite), should be one of Full, Half, or Radio"));
	assert_int_equal(net_load_text("Mode,Link\nPeer,Half\n", &c, &is), DF1_E_CONFIG);
	assert_non_null(strstr(is.v[0].text, "Link Half needs Mode Master or Slave"));
	assert_int_equal(net_load_text("Link,Store_Forward\nRadio,1-300\n", &c, &is), DF1_E_CONFIG);
	assert_non_null(strstr(is.v[0].text, "Invalid Store_Forward (1-300)"));
	assert_int_equal(net_load_text("Link,Store_Forward\nFull,2\n", &c, &is), DF1_E_CONFIG);
	assert_non_null(strstr(is.v[0].text, "Store_Forward (2) needs Link Radio"));

	/* applied: the radio modem and its forward table on the handle */
	assert_int_equal(net_load_text("Link,Store_Forward\nRadio,\"2,255\"\n", &c, &is), 0);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_apply_net_config(h, &c), 0);
	assert_int_equal(h->cfg.duplex, DF1_RADIO_MODEM);
	assert_int_equal(df1_get_forward(h, t), 1);
	assert_int_equal(t[0], 0x04);
	assert_int_equal(t[31], 0x80);
	df1_free(h);
}

static void test_config_net_com_port_forms(void **state)
{
	static const struct {
		const char *value, *want;
	} cases[] = {
		{ "1", "/dev/ttyS0" },
		{ "4", "/dev/ttyS3" },
		{ "COM2", "/dev/ttyS1" },
		{ "com1", "/dev/ttyS0" },
		{ "/dev/ttyUSB0", "/dev/ttyUSB0" },
		{ "\"/dev/serial/by-id/usb-FTDI_a,b\"", "/dev/serial/by-id/usb-FTDI_a,b" },
		{ "tcp://127.0.0.1:2222", "tcp://127.0.0.1:2222" },
		{ "TCP://plc-gw:10001", "tcp://plc-gw:10001" },
		{ "tcp://[::1]:2222", "tcp://[::1]:2222" },
	};
	size_t i;

	(void)state;
	for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char text[128];
		struct df1_net_config c;
		struct issues is;

		snprintf(text, sizeof text, "Com_Port\n%s\n", cases[i].value);
		if (net_load_text(text, &c, &is) != 0) {
			dump_issues(&is);
			fail_msg("Com_Port %s rejected", cases[i].value);
		}
		assert_string_equal(c.port, cases[i].want);
	}
}

/* ---- network: invalid values --------------------------------------------- */

struct net_bad_case {
	const char *column;
	const char *value;
	int id;
	const char *text;     /* exact expected text */
};

static void test_config_net_each_invalid_value_reported_with_id(void **state)
{
	static const struct net_bad_case cases[] = {
		{ "Station", "255", 2552, "Invalid station number (255) must be less than 255" },
		{ "Station", "-1", 2552, "Invalid station number (-1) must be less than 255" },
		{ "Station", "abc", 2552, "Invalid station number (abc) must be less than 255" },
		{ "Station", "99999999999", 2552,
		  "Invalid station number (99999999999) must be less than 255" },
		{ "Mode", "Boss", 2553,
		  "Invalid Driver Mode (Boss), should be one of Master, Slave, or Peer" },
		{ "Mode", "Half", 2553,
		  "Invalid Driver Mode (Half), should be one of Master, Slave, or Peer" },
		{ "PLC_Type", "PLC4", 2555,
		  "Invalid or Unsupported PLC Type (PLC4) should be one of PLC2, PLC5, SLC, MicroLogix" },
		{ "PLC_Type", "PLC6", 2555,
		  "Invalid or Unsupported PLC Type (PLC6) should be one of PLC2, PLC5, SLC, MicroLogix" },
		{ "PLC_Type", "ControlLogix", 2555,
		  "Invalid or Unsupported PLC Type (ControlLogix) should be one of PLC2, PLC5, SLC, "
		  "MicroLogix" },
		{ "Error_Code", "XOR", 2556, "Invalid Error Code (XOR), should be either BCC, or CRC" },
		{ "NAK_Retries", "11", 2557, "Invalid NAK Retries (11) should be in range [0, 10]" },
		{ "NAK_Retries", "-1", 2557, "Invalid NAK Retries (-1) should be in range [0, 10]" },
		{ "NAK_Retries", "3.5", 2557, "Invalid NAK Retries (3.5) should be in range [0, 10]" },
		{ "ENQ_Retries", "11", 2558, "Invalid ENQ Retries (11) should be in range [0, 10]" },
		{ "ENQ_Retries", "x", 2558, "Invalid ENQ Retries (x) should be in range [0, 10]" },
		{ "Cmd_Timeout", "499", 2559, "Invalid Cmd Timeout (499) should be in range [500, 5000]" },
		{ "Cmd_Timeout", "5001", 2559,
		  "Invalid Cmd Timeout (5001) should be in range [500, 5000]" },
		{ "Cmd_Timeout", "1s", 2559, "Invalid Cmd Timeout (1s) should be in range [500, 5000]" },
		{ "Com_Port", "0", 0, "Invalid Com Port (0) should be a port number [1, 256], COMn, a "
		  "device path (/dev/...) or tcp://host:port" },
		{ "Com_Port", "257", 0, NULL },
		{ "Com_Port", "ttyUSB0", 0, NULL },
		{ "Com_Port", "tcp://host", 0, NULL },
		{ "Com_Port", "tcp://:2222", 0, NULL },
		{ "Com_Port", "tcp://host:0", 0, NULL },
		{ "Com_Port", "tcp://host:65536", 0, NULL },
		{ "Baud", "9601", 0, "Invalid Baud (9601) should be one of 1200, 2400, 4800, 9600, "
		  "19200, 38400, 57600, or 115200" },
		{ "Baud", "300", 0, NULL },
		{ "Baud", "fast", 0, NULL },
		{ "Data_Bits", "4", 0, "Invalid Data Bits (4) should be in range [5, 8]" },
		{ "Data_Bits", "9", 0, "Invalid Data Bits (9) should be in range [5, 8]" },
		{ "Stop_Bits", "0", 0, "Invalid Stop Bits (0) should be in range [1, 2]" },
		{ "Stop_Bits", "3", 0, "Invalid Stop Bits (3) should be in range [1, 2]" },
		{ "Parity", "Mark", 0, "Invalid Parity (Mark), should be one of Odd, Even, or None" },
		{ "Timeout", "360001", 0, "Invalid Timeout (360001) should be in range [0, 360000]" },
		{ "Timeout", "-1", 0, "Invalid Timeout (-1) should be in range [0, 360000]" },
		{ "TX_Delay", "65536", 0, "Invalid TX Delay (65536) should be in range [0, 65535]" },
		{ "TX_Delay", "-5", 0, "Invalid TX Delay (-5) should be in range [0, 65535]" },
		{ "Handshake", "Maybe", 0, "Invalid Handshake (Maybe), should be either Yes, or No" },
	};
	size_t i;

	(void)state;
	for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char text[160];
		struct df1_net_config c;
		struct issues is;
		int rc;

		memset(&c, 0x33, sizeof c);
		snprintf(text, sizeof text, "# a comment\n%s\n%s\n", cases[i].column, cases[i].value);
		rc = net_load_text(text, &c, &is);
		if (rc != DF1_E_CONFIG || is.n != 1 || is.v[0].catalog_id != cases[i].id ||
		    (cases[i].text && strcmp(is.v[0].text, cases[i].text) != 0)) {
			dump_issues(&is);
			fail_msg("%s=%s: rc %d, %d issues, want one with id %d '%s'", cases[i].column,
			         cases[i].value, rc, is.n, cases[i].id, cases[i].text ? cases[i].text : "");
		}
		assert_int_equal(is.v[0].item, 1);
		assert_int_equal(is.v[0].line, 3);
		if (cases[i].id == 0) /* texts without an ID name the field */
			assert_non_null(strstr(is.v[0].text, cases[i].value));
		assert_int_equal(c.station, 0x33333333); /* *c untouched on failure */
	}
}

static void test_config_net_all_invalid_all_reported(void **state)
{
	static const int want_ids[] = {
		2552, 2553, 2555, 2556, 2557, 2558, 2559, 0, 0, 0, 0, 0, 0, 0, 0
	};
	struct df1_net_config c;
	struct issues is = { 0 };
	size_t i;
	int rc;

	(void)state;
	rc = df1_net_config_load(data_path("net_invalid.csv"), &c, collect_issue, &is);
	assert_int_equal(rc, DF1_E_CONFIG);
	if (is.n != (int)(sizeof want_ids / sizeof want_ids[0]))
		dump_issues(&is);
	assert_int_equal(is.n, sizeof want_ids / sizeof want_ids[0]);
	for (i = 0; i < sizeof want_ids / sizeof want_ids[0]; i++) {
		assert_int_equal(is.v[i].catalog_id, want_ids[i]);
		assert_int_equal(is.v[i].line, 3);
		assert_int_equal(is.v[i].item, 1);
	}
	assert_string_equal(is.v[0].text, "Invalid station number (300) must be less than 255");
	assert_string_equal(is.v[5].text, "Invalid ENQ Retries (-1) should be in range [0, 10]");
	assert_string_equal(is.v[6].text, "Invalid Cmd Timeout (100) should be in range [500, 5000]");
	/* a NULL callback still fails the load */
	assert_int_equal(df1_net_config_load(data_path("net_invalid.csv"), &c, NULL, NULL),
	                 DF1_E_CONFIG);
}

static void test_config_net_unknown_and_duplicate_columns_fail(void **state)
{
	struct df1_net_config c;
	struct issues is;

	(void)state;
	assert_int_equal(net_load_text("Station,Baudrate\n1,9600\n", &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_int_equal(is.v[0].catalog_id, 0);
	assert_int_equal(is.v[0].line, 1);
	assert_non_null(strstr(is.v[0].text, "Baudrate"));

	assert_int_equal(net_load_text("Station,STATION\n1,2\n", &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_non_null(strstr(is.v[0].text, "Station"));

	/* a value under a column with no name */
	assert_int_equal(net_load_text("Station,\n1,2\n", &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_int_equal(is.v[0].line, 2);
	/* ...but an empty trailing column is fine */
	assert_int_equal(net_load_text("Station,,\n1,,\n", &c, &is), 0);
	assert_int_equal(c.station, 1);
	/* more cells than the header has columns */
	assert_int_equal(net_load_text("Station\n1,2\n", &c, &is), DF1_E_CONFIG);
}

static void test_config_net_csv_forms(void **state)
{
	struct df1_net_config c;
	struct issues is;
	char big[12000];
	size_t n = 0;
	int i;

	(void)state;
	/* CRLF, byte order mark, spaces around names and values, quoted values */
	assert_int_equal(net_load_text("\xEF\xBB\xBF  station  , \"Baud\" ,nak retries\r\n"
	                               " 9 , \"19200\" ,\"1\"\r\n", &c, &is), 0);
	assert_int_equal(c.station, 9);
	assert_int_equal(c.baud, 19200);
	assert_int_equal(c.nak_retries, 1);
	/* old Mac line ends, and comments with quotes that would confuse a CSV parser */
	assert_int_equal(net_load_text("# \"unbalanced\r  # another \" one\rStation\r# x,\"y\r42\r",
	                               &c, &is), 0);
	assert_int_equal(c.station, 42);
	/* a quoted cell starting with # is a comment row too */
	assert_int_equal(net_load_text("\"# note, with a comma\",\nStation\n8\n", &c, &is), 0);
	assert_int_equal(c.station, 8);
	/* long comment lines across the reader's chunks */
	n += (size_t)snprintf(big + n, sizeof big - n, "#");
	for (i = 0; i < 5000; i++)
		big[n++] = i % 7 == 0 ? '"' : 'c';
	n += (size_t)snprintf(big + n, sizeof big - n, "\n");
	for (i = 0; i < 100; i++)
		n += (size_t)snprintf(big + n, sizeof big - n, "   # comment %d, \"quoted\n", i);
	n += (size_t)snprintf(big + n, sizeof big - n, "Station,Timeout\n\n\n77,\"2000\"\n");
	assert_int_equal(net_load_text(big, &c, &is), 0);
	assert_int_equal(c.station, 77);
	assert_int_equal(c.timeout_ms, 2000);
	/* the reported line counts physical lines, comments and blank rows included */
	n = (size_t)snprintf(big, sizeof big, "#1\n\nStation\n# 4\n\n300\n");
	assert_int_equal(net_load_text(big, &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_int_equal(is.v[0].line, 6);
}

static void test_config_net_malformed_csv_fails(void **state)
{
	struct df1_net_config c;
	struct issues is;

	(void)state;
	assert_int_equal(net_load_text("Station,Mode\n1,Ma\"ster\n", &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_int_equal(is.v[0].line, 2);
	assert_non_null(strstr(is.v[0].text, "line 2"));
	assert_int_equal(net_load_text("Station,Mode\n1,\"Master\"x\n", &c, &is), DF1_E_CONFIG);
	assert_int_equal(net_load_text("Station,Mode\n1,\"Master\n", &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_non_null(strstr(is.v[0].text, "quoted"));
	/* nothing but comments: no header */
	assert_int_equal(net_load_text("# only a comment\n\n", &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_int_equal(net_load_text("", &c, &is), DF1_E_CONFIG);
}

static void test_config_net_missing_file_names_path(void **state)
{
	struct df1_net_config c;
	struct issues is = { 0 };
	const char *path = "/nonexistent-dir/df1/network.csv";

	(void)state;
	errno = 0;
	assert_int_equal(df1_net_config_load(path, &c, collect_issue, &is), DF1_E_SYS);
	assert_int_equal(errno, ENOENT);
	assert_int_equal(is.n, 1);
	assert_non_null(strstr(is.v[0].text, path));
	assert_int_equal(df1_net_config_load(NULL, &c, NULL, NULL), DF1_E_INVAL);
	assert_int_equal(df1_net_config_load(path, NULL, NULL, NULL), DF1_E_INVAL);
}

static void test_config_net_example_loads(void **state)
{
	struct df1_net_config c;
	struct issues is = { 0 };
	int rc;

	(void)state;
	rc = df1_net_config_load(example_path("network.csv"), &c, collect_issue, &is);
	if (rc != 0)
		dump_issues(&is);
	assert_int_equal(rc, 0);
	assert_int_equal(c.mode, DF1_MODE_PEER);
	assert_string_equal(c.port, "/dev/ttyUSB0");
	assert_int_equal(c.baud, 19200);
}

/* ---- df1_apply_net_config, on a real handle ---------------------------------- */

static void test_config_apply_sets_handle(void **state)
{
	struct df1_net_config c;
	struct issues is = { 0 };
	df1_t *h = NULL;

	(void)state;
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_net_config_load(data_path("net_valid.csv"), &c, collect_issue, &is), 0);
	assert_int_equal(df1_apply_net_config(h, &c), 0);
	/* the handle's stored settings (lib/df1_int.h) */
	assert_int_equal(h->cfg.baud, 19200);
	assert_int_equal(h->cfg.data_bits, 7);
	assert_int_equal(h->cfg.parity, 'E');
	assert_int_equal(h->cfg.stop_bits, 2);
	assert_true(h->cfg.rts_cts);
	assert_int_equal(h->cfg.duplex, DF1_HALF_DUPLEX_SLAVE);
	assert_int_equal(h->cfg.check, DF1_CHECK_BCC);
	assert_int_equal(h->cfg.station, 12);
	assert_int_equal(h->cfg.plc, DF1_PLC_SLC);
	assert_int_equal(h->cfg.timeout_ms, 1500);
	assert_int_equal(h->cfg.cmd_timeout_ms, 2500);
	assert_int_equal(h->cfg.nak_retries, 5);
	assert_int_equal(h->cfg.enq_retries, 6);
	assert_int_equal(h->cfg.tx_delay_ms, 20);

	/* Mode -> duplex: Master half-duplex master, Peer full, Master without
	 * duplex_half (point to point) full */
	df1_net_config_defaults(&c);
	assert_int_equal(df1_apply_net_config(h, &c), 0);
	assert_int_equal(h->cfg.duplex, DF1_HALF_DUPLEX_MASTER);
	assert_int_equal(h->cfg.station, 5);
	assert_int_equal(h->cfg.plc, DF1_PLC_PLC5);
	assert_int_equal(h->cfg.baud, 9600);
	assert_false(h->cfg.rts_cts);
	c.mode = DF1_MODE_PEER;
	assert_int_equal(df1_apply_net_config(h, &c), 0);
	assert_int_equal(h->cfg.duplex, DF1_FULL_DUPLEX);
	c.mode = DF1_MODE_MASTER;
	c.duplex_half = false;
	assert_int_equal(df1_apply_net_config(h, &c), 0);
	assert_int_equal(h->cfg.duplex, DF1_FULL_DUPLEX);

	/* a value the handle refuses: its error comes back */
	c.cmd_timeout_ms = 100;
	assert_true(df1_apply_net_config(h, &c) < 0);
	assert_int_equal(df1_apply_net_config(NULL, &c), DF1_E_INVAL);
	assert_int_equal(df1_apply_net_config(h, NULL), DF1_E_INVAL);
	df1_free(h);
}

/* ---- mapping file ------------------------------------------------------------ */

static void test_config_map_valid_file_gives_rows(void **state)
{
	struct map_result r = { 0 };
	int rc;

	(void)state;
	rc = map_load_path(data_path("map_valid.csv"), false, &r);
	if (rc != 7)
		dump_issues(&r.issues);
	assert_int_equal(rc, 7);
	assert_int_equal(r.issues.n, 0);
	assert_int_equal(r.tags.n, 7);

	assert_string_equal(r.tags.v[0].name, "Pump1_Speed");
	assert_int_equal(r.tags.v[0].access, DF1_ACCESS_READ);
	assert_string_equal(r.tags.v[0].type, "INT");
	assert_int_equal(r.tags.v[0].station, 1);
	assert_int_equal(r.tags.v[0].plc, DF1_PLC_SLC);
	assert_tag_addr(&r.tags.v[0], "N7:0");
	assert_int_equal(r.tags.v[0].count, 1);
	assert_int_equal(r.tags.v[0].scan_ms, 500);

	assert_string_equal(r.tags.v[1].name, "Tank_Level");
	assert_int_equal(r.tags.v[1].access, DF1_ACCESS_READWRITE);
	assert_int_equal(r.tags.v[1].plc, DF1_PLC_MICROLOGIX);
	assert_tag_addr(&r.tags.v[1], "F8:3");
	assert_int_equal(r.tags.v[1].count, 4);
	assert_int_equal(r.tags.v[1].scan_ms, 1000); /* default */

	assert_string_equal(r.tags.v[2].name, "Valve, main");
	assert_int_equal(r.tags.v[2].access, DF1_ACCESS_WRITE);
	assert_tag_addr(&r.tags.v[2], "B3:1/5");
	assert_int_equal(r.tags.v[2].count, 1);        /* default */

	assert_string_equal(r.tags.v[3].name, "Say \"hi\"");
	assert_int_equal(r.tags.v[3].access, DF1_ACCESS_READ);
	assert_int_equal(r.tags.v[3].station, 10);
	assert_int_equal(r.tags.v[3].plc, DF1_PLC_PLC5);
	assert_tag_addr(&r.tags.v[3], "ST9:0");
	assert_int_equal(r.tags.v[3].scan_ms, 2000);

	assert_string_equal(r.tags.v[4].name, "Timer_Acc");
	assert_string_equal(r.tags.v[4].type, "INT");
	assert_int_equal(r.tags.v[4].station, 254);
	assert_int_equal(r.tags.v[4].plc, DF1_PLC_PLC5);
	assert_tag_addr(&r.tags.v[4], "T4:0.ACC");
	assert_int_equal(r.tags.v[4].scan_ms, 250);

	assert_string_equal(r.tags.v[5].name, "Multi\nline");
	assert_string_equal(r.tags.v[5].type, "");
	assert_int_equal(r.tags.v[5].station, 0);
	assert_int_equal(r.tags.v[5].plc, DF1_PLC_PLC2);
	assert_string_equal(r.tags.v[5].addr.ascii, "N7:0");
	assert_int_equal(r.tags.v[5].count, 10);

	assert_string_equal(r.tags.v[6].name, "Last");
	assert_int_equal(r.tags.v[6].access, DF1_ACCESS_READWRITE);
	assert_int_equal(r.tags.v[6].plc, DF1_PLC_SLC502);
	assert_tag_addr(&r.tags.v[6], "N7:990");
	assert_int_equal(r.tags.v[6].count, 10);       /* N7:990..999: the last element */
	assert_int_equal(r.tags.v[6].scan_ms, 86400000);

	/* strict mode gives the same rows */
	assert_int_equal(map_load_path(data_path("map_valid.csv"), true, &r), 7);
	assert_int_equal(r.tags.n, 7);
	assert_string_equal(r.tags.v[6].name, "Last");
}

struct map_bad_case {
	int item, line, id;
	const char *text;     /* exact text, or NULL: the text contains needle */
	const char *needle;
};

static void test_config_map_each_bad_row_reported_and_skipped(void **state)
{
	static const struct map_bad_case want[] = {
		{ 2, 3, 2501, "Item: 2, Invalid station number (255) must be less than 255", NULL },
		{ 3, 4, 2501, "Item: 3, Invalid station number (x1) must be less than 255", NULL },
		{ 4, 6, 2502, "Item: 4, Invalid or Unsupported PLC Type (PLC4) should be one of PLC2, "
		  "PLC5, SLC, MicroLogix", NULL },
		{ 5, 7, 2503, "Item: 5, Invalid Address Syntax (N7;0)", NULL },
		{ 6, 8, 2504, "Item: 6, Address is out of range (N7:1000, len=1)", NULL },
		{ 7, 9, 2504, "Item: 7, Address is out of range (N7:995, len=10)", NULL },
		{ 8, 10, 2504, "Item: 8, Address is out of range (N7:0, len=0)", NULL },
		{ 9, 11, 0, "Item: 9, missing Tag", NULL },
		{ 10, 12, 0, NULL, "Toggle" },
		{ 11, 13, 0, NULL, "many" },
		{ 12, 14, 0, NULL, "Scan_Ms" },
		{ 13, 15, 2501, "Item: 13, Invalid station number () must be less than 255", NULL },
		{ 15, 17, 2501, "Item: 15, Invalid station number (999) must be less than 255", NULL },
		{ 15, 17, 2502, "Item: 15, Invalid or Unsupported PLC Type (PLC9) should be one of "
		  "PLC2, PLC5, SLC, MicroLogix", NULL },
	};
	struct map_result r = { 0 };
	size_t i;
	int rc;

	(void)state;
	rc = map_load_path(data_path("map_invalid.csv"), false, &r);
	if (r.issues.n != (int)(sizeof want / sizeof want[0]))
		dump_issues(&r.issues);
	assert_int_equal(rc, 2);
	assert_int_equal(r.tags.n, 2);
	assert_string_equal(r.tags.v[0].name, "Good1");
	assert_string_equal(r.tags.v[1].name, "Good2");
	assert_int_equal(r.issues.n, sizeof want / sizeof want[0]);
	for (i = 0; i < sizeof want / sizeof want[0]; i++) {
		const struct df1_config_issue *is = &r.issues.v[i];

		if (is->item != want[i].item || is->line != want[i].line ||
		    is->catalog_id != want[i].id ||
		    (want[i].text && strcmp(is->text, want[i].text) != 0) ||
		    (want[i].needle && !strstr(is->text, want[i].needle)))
			fail_msg("issue %zu: item %d line %d id %d '%s'; want item %d line %d id %d '%s'",
			         i, is->item, is->line, is->catalog_id, is->text, want[i].item,
			         want[i].line, want[i].id, want[i].text ? want[i].text : want[i].needle);
	}

	/* strict: the same issues, no row delivered, the load fails */
	rc = map_load_path(data_path("map_invalid.csv"), true, &r);
	assert_int_equal(rc, DF1_E_CONFIG);
	assert_int_equal(r.tags.n, 0);
	assert_int_equal(r.issues.n, sizeof want / sizeof want[0]);
}

static void test_config_map_address_forms_and_counts(void **state)
{
	struct map_result r = { 0 };
	int rc;

	(void)state;
	rc = map_load_text("Tag,Station,PLC_Type,Address,Count\n"
	                   "a,1,SLC,N7:999,1\n"      /* last element */
	                   "b,1,SLC,N7:999,2\n"      /* one past */
	                   "c,1,SLC,N7:0,1000\n"     /* the whole file */
	                   "d,1,SLC,N7:0,1001\n"
	                   "e,1,SLC,N7:0,-3\n"
	                   "f,1,SLC,X7:0,1\n"
	                   "g,1,SLC,,1\n"            /* empty address: syntax */
	                   "h,1,SLC,T4:0/DN,1\n"
	                   "i,1,SLC,B3:0/16,1\n",
	                   false, &r);
	assert_int_equal(rc, 3);
	assert_string_equal(r.tags.v[0].name, "a");
	assert_string_equal(r.tags.v[1].name, "c");
	assert_int_equal(r.tags.v[1].count, 1000);
	assert_string_equal(r.tags.v[2].name, "h");
	assert_tag_addr(&r.tags.v[2], "T4:0/DN");
	assert_int_equal(r.issues.n, 6);
	assert_int_equal(r.issues.v[0].catalog_id, 2504);
	assert_string_equal(r.issues.v[0].text, "Item: 2, Address is out of range (N7:999, len=2)");
	assert_int_equal(r.issues.v[1].catalog_id, 2504);
	assert_string_equal(r.issues.v[1].text, "Item: 4, Address is out of range (N7:0, len=1001)");
	assert_string_equal(r.issues.v[2].text, "Item: 5, Address is out of range (N7:0, len=-3)");
	assert_int_equal(r.issues.v[3].catalog_id, 2503);
	assert_string_equal(r.issues.v[3].text, "Item: 6, Invalid Address Syntax (X7:0)");
	assert_int_equal(r.issues.v[4].catalog_id, 2503);
	assert_string_equal(r.issues.v[4].text, "Item: 7, Invalid Address Syntax ()");
	assert_int_equal(r.issues.v[5].catalog_id, 2504);
	assert_string_equal(r.issues.v[5].text, "Item: 9, Address is out of range (B3:0/16, len=1)");
}

/* PLC3 rows take a PLC-3's own address text (doc/PROTOCOL.md 4.2a): octal bits,
 * T4.ACC structure members, words up to 9999; other rows keep their grammar. */
static void test_config_map_plc3_rows(void **state)
{
	struct map_result r = { 0 };
	struct df1_addr want;
	int rc;

	(void)state;
	rc = map_load_text("Tag,Station,PLC_Type,Address,Count\n"
	                   "a,1,PLC3,N3:173,1\n"
	                   "b,1,PLC-3,B5:173/15,1\n"
	                   "c,1,PLC3,T4.ACC,1\n"
	                   "d,1,PLC3,N3:9999,1\n"
	                   "e,1,PLC3,N3:9999,2\n"   /* one past the last word */
	                   "f,1,PLC3,B5:0/18,1\n"   /* octal bit: no 8 */
	                   "g,1,SLC,T4.ACC,1\n",    /* not SLC text */
	                   false, &r);
	assert_int_equal(rc, 4);
	assert_int_equal(r.tags.v[0].plc, DF1_PLC_PLC3);
	assert_int_equal(r.tags.v[0].addr.type, DF1_FT_N);
	assert_int_equal(r.tags.v[0].addr.file, 3);
	assert_int_equal(r.tags.v[0].addr.element, 173);
	assert_int_equal(r.tags.v[1].addr.bit, 13);
	assert_int_equal(df1_addr_parse_plc(DF1_PLC_PLC3, "T4.ACC", &want), 0);
	assert_int_equal(r.tags.v[2].addr.type, DF1_FT_T);
	assert_int_equal(r.tags.v[2].addr.file, 0);
	assert_int_equal(r.tags.v[2].addr.element, 4);
	assert_int_equal(r.tags.v[2].addr.sub, 2);
	assert_int_equal(r.tags.v[3].addr.element, 9999);
	assert_int_equal(r.issues.n, 3);
	assert_string_equal(r.issues.v[0].text, "Item: 5, Address is out of range (N3:9999, len=2)");
	assert_string_equal(r.issues.v[1].text, "Item: 6, Invalid Address Syntax (B5:0/18)");
	assert_string_equal(r.issues.v[2].text, "Item: 7, Invalid Address Syntax (T4.ACC)");
}

static void test_config_map_header_problems_fail_the_load(void **state)
{
	struct map_result r = { 0 };

	(void)state;
	/* a required column is missing */
	assert_int_equal(map_load_text("Tag,Station,Address\na,1,N7:0\n", false, &r), DF1_E_CONFIG);
	assert_int_equal(r.tags.n, 0);
	assert_int_equal(r.issues.n, 1);
	assert_non_null(strstr(r.issues.v[0].text, "PLC_Type"));
	/* an unknown column */
	assert_int_equal(map_load_text("Tag,Station,PLC_Type,Adress\na,1,SLC,N7:0\n", false, &r),
	                 DF1_E_CONFIG);
	assert_int_equal(r.tags.n, 0);
	assert_true(r.issues.n >= 1);
	assert_non_null(strstr(r.issues.v[0].text, "Adress"));
	/* header case and order, optional columns left out */
	assert_int_equal(map_load_text("ADDRESS , plc_type,tag,STATION,scan_ms\n"
	                               "F8:1,SLC,x,4,100\n", false, &r), 1);
	assert_string_equal(r.tags.v[0].name, "x");
	assert_int_equal(r.tags.v[0].access, DF1_ACCESS_READ);
	assert_int_equal(r.tags.v[0].count, 1);
	assert_int_equal(r.tags.v[0].scan_ms, 100);
	assert_int_equal(r.tags.v[0].station, 4);
	assert_tag_addr(&r.tags.v[0], "F8:1");
	/* header only: no rows, no error */
	assert_int_equal(map_load_text("Tag,Station,PLC_Type,Address\n", true, &r), 0);
}

static void test_config_map_row_fields_limits(void **state)
{
	struct map_result r = { 0 };
	char text[512];

	(void)state;
	snprintf(text, sizeof text, "Tag,Station,PLC_Type,Address,Type\n"
	         "%063d,1,SLC,N7:0,INT\n"    /* 63 characters: fits */
	         "%064d,1,SLC,N7:0,INT\n"    /* 64: too long */
	         "t,1,SLC,N7:0,ABCDEFGHIJKLMNOP\n", 1, 2);
	assert_int_equal(map_load_text(text, false, &r), 1);
	assert_int_equal(strlen(r.tags.v[0].name), 63);
	assert_int_equal(r.issues.n, 2);
	assert_int_equal(r.issues.v[0].item, 2);
	assert_non_null(strstr(r.issues.v[0].text, "Tag"));
	assert_int_equal(r.issues.v[1].item, 3);
	assert_non_null(strstr(r.issues.v[1].text, "Type"));
}

/* A NUL byte inside a cell would cut it in C ("N7:0\0junk" read as N7:0): the
 * row is an error naming its item, whatever the column (and a header cell or
 * a network file's row fails the load). */
static void test_config_nul_byte_in_a_cell_is_an_error(void **state)
{
	static const char map[] = "Tag,Station,PLC_Type,Address\n"
	                          "good,1,SLC,N7:1\n"
	                          "cut,1,SLC,N7:0\0junk\n"
	                          "\0,,,\n"                 /* a cell of one NUL: not blank */
	                          "\"q\0\",1,SLC,N7:2\n"     /* quoted too */
	                          "also,1,SLC,N7:3\n";
	static const char map_header[] = "Tag,Station,PLC_Type,Address\0x\na,1,SLC,N7:0\n";
	static const char net[] = "Station,Baud\n7\0 junk,19200\n";
	struct map_result r = { 0 };
	struct df1_net_config c;
	struct issues is;

	(void)state;
	assert_int_equal(map_load_bytes(map, sizeof map - 1, false, &r), 2);
	assert_int_equal(r.tags.n, 2);
	assert_string_equal(r.tags.v[0].name, "good");
	assert_string_equal(r.tags.v[1].name, "also");
	if (r.issues.n != 3)
		dump_issues(&r.issues);
	assert_int_equal(r.issues.n, 3);
	assert_int_equal(r.issues.v[0].item, 2);
	assert_int_equal(r.issues.v[0].line, 3);
	assert_non_null(strstr(r.issues.v[0].text, "Item: 2,"));
	assert_non_null(strstr(r.issues.v[0].text, "Address"));
	assert_non_null(strstr(r.issues.v[0].text, "NUL"));
	assert_int_equal(r.issues.v[1].item, 3);
	assert_non_null(strstr(r.issues.v[1].text, "Item: 3,"));
	assert_non_null(strstr(r.issues.v[1].text, "NUL"));
	assert_int_equal(r.issues.v[2].item, 4);
	assert_non_null(strstr(r.issues.v[2].text, "Tag"));
	assert_non_null(strstr(r.issues.v[2].text, "NUL"));
	/* strict: the load fails */
	assert_int_equal(map_load_bytes(map, sizeof map - 1, true, &r), DF1_E_CONFIG);
	assert_int_equal(r.tags.n, 0);
	/* in the header: the load fails */
	assert_int_equal(map_load_bytes(map_header, sizeof map_header - 1, false, &r), DF1_E_CONFIG);
	assert_int_equal(r.tags.n, 0);
	assert_true(r.issues.n >= 1);
	assert_non_null(strstr(r.issues.v[0].text, "NUL"));
	/* the network file: a critical error, *c untouched */
	memset(&c, 0x5A, sizeof c);
	assert_int_equal(net_load_bytes(net, sizeof net - 1, &c, &is), DF1_E_CONFIG);
	assert_int_equal(c.station, 0x5A5A5A5A);
	assert_int_equal(is.n, 1);
	assert_non_null(strstr(is.v[0].text, "Station"));
	assert_non_null(strstr(is.v[0].text, "NUL"));
}

/* A field longer than 65536 bytes (a cell is at most 255 characters; a field
 * that long is not a configuration file) stops the load with an error giving
 * its line, before libcsv buffers megabytes of it. */
static void test_config_field_over_the_limit_is_an_error(void **state)
{
	enum { LIMIT = 65536 };
	const char *head = "Tag,Station,PLC_Type,Address\nok,1,SLC,N7:0\n";
	size_t hn = strlen(head), n;
	char *text = malloc(hn + 3 * LIMIT + 64);
	struct map_result r = { 0 };
	struct df1_net_config c;
	struct issues is;

	(void)state;
	assert_non_null(text);
	/* LIMIT bytes: no more than a cell that is too long, the row is skipped */
	memcpy(text, head, hn);
	memset(text + hn, 'x', LIMIT);
	n = hn + LIMIT;
	n += (size_t)sprintf(text + n, ",1,SLC,N7:1\nlast,1,SLC,N7:2\n");
	assert_int_equal(map_load_bytes(text, n, false, &r), 2);
	assert_int_equal(r.issues.n, 2);
	assert_int_equal(r.issues.v[0].item, 2);
	assert_non_null(strstr(r.issues.v[0].text, "too long"));
	/* one byte more: the load fails, naming the line */
	memset(text + hn, 'x', LIMIT + 1);
	n = hn + LIMIT + 1;
	n += (size_t)sprintf(text + n, ",1,SLC,N7:1\nlast,1,SLC,N7:2\n");
	assert_int_equal(map_load_bytes(text, n, false, &r), DF1_E_CONFIG);
	assert_int_equal(r.issues.n, 1);
	assert_int_equal(r.issues.v[0].line, 3);
	assert_non_null(strstr(r.issues.v[0].text, "line 3"));
	assert_non_null(strstr(r.issues.v[0].text, "longer than 65536 bytes"));
	/* quoted, over several lines, in the last column: the same */
	memcpy(text, head, hn);
	n = hn + (size_t)sprintf(text + hn, "q,1,SLC,\"");
	for (int i = 0; i < 3; i++) {
		memset(text + n, 'y', LIMIT / 2);
		n += LIMIT / 2;
		text[n++] = '\n';
	}
	text[n++] = '"';
	text[n++] = '\n';
	assert_int_equal(map_load_bytes(text, n, false, &r), DF1_E_CONFIG);
	assert_int_equal(r.issues.n, 1);
	assert_non_null(strstr(r.issues.v[0].text, "longer than 65536 bytes"));
	/* the network file too */
	n = (size_t)sprintf(text, "Station,Com_Port\n5,");
	memset(text + n, 'z', LIMIT + 1);
	n += LIMIT + 1;
	text[n++] = '\n';
	assert_int_equal(net_load_bytes(text, n, &c, &is), DF1_E_CONFIG);
	assert_int_equal(is.n, 1);
	assert_non_null(strstr(is.v[0].text, "longer than 65536 bytes"));
	free(text);
}

/* Scan_Ms 0 is df1_tag_add's "every scan" (df1.h); negative is not a period. */
static void test_config_map_scan_ms_zero_is_every_scan(void **state)
{
	struct map_result r = { 0 };

	(void)state;
	assert_int_equal(map_load_text("Tag,Station,PLC_Type,Address,Scan_Ms\n"
	                               "fast,1,SLC,N7:0,0\n"
	                               "neg,1,SLC,N7:1,-1\n"
	                               "max,1,SLC,N7:2,86400000\n"
	                               "over,1,SLC,N7:3,86400001\n", false, &r), 2);
	assert_string_equal(r.tags.v[0].name, "fast");
	assert_int_equal(r.tags.v[0].scan_ms, 0);
	assert_string_equal(r.tags.v[1].name, "max");
	assert_int_equal(r.tags.v[1].scan_ms, 86400000);
	assert_int_equal(r.issues.n, 2);
	assert_int_equal(r.issues.v[0].item, 2);
	assert_non_null(strstr(r.issues.v[0].text, "[0, 86400000]"));
	assert_int_equal(r.issues.v[1].item, 4);
}

/* Command Receive: a row of the loader's own table (df1gw(1) RECEIVE), which
 * the poll engine does not poll. */
static void test_config_map_receive_rows(void **state)
{
	struct map_result r = { 0 };
	char path[] = "/tmp/test_config_receive_XXXXXX";
	int fd = mkstemp(path);
	df1_t *h = NULL;

	(void)state;
	assert_int_equal(map_load_text("Tag,Command,Type,Station,PLC_Type,Address,Count\n"
	                               "Batch_Report,Receive,INT,0,SLC,N50:0,10\n"
	                               "Speed,Read,INT,1,SLC,N7:0,1\n"
	                               "Bad,Send,INT,1,SLC,N7:1,1\n", false, &r), 2);
	assert_int_equal(r.tags.v[0].access, DF1_ACCESS_RECEIVE);
	assert_int_equal(r.tags.v[0].count, 10);
	assert_int_equal(r.tags.v[1].access, DF1_ACCESS_READ);
	assert_int_equal(r.issues.n, 1);
	assert_non_null(strstr(r.issues.v[0].text, "ReadWrite, or Receive"));
	assert_true(fd >= 0);
	assert_true(dprintf(fd, "Tag,Command,Station,PLC_Type,Address\nR,Receive,0,SLC,N50:0\n"
	                    "S,Read,1,SLC,N7:0\n") > 0);
	close(fd);
	assert_int_equal(df1_new(&h), 0);
	assert_int_equal(df1_tag_load_map(h, path, true, NULL, NULL), 1);
	assert_true(df1_tag_find(h, "R") < 0);
	assert_int_equal(df1_tag_find(h, "S"), 0);
	df1_free(h);
	unlink(path);
}

static void test_config_map_row_fn_error_stops(void **state)
{
	struct map_result r = { 0 };
	int rc;

	(void)state;
	memset(&r, 0, sizeof r);
	r.tags.stop_after = 2;
	rc = map_load_path(data_path("map_valid.csv"), false, &r);
	assert_int_equal(rc, DF1_E_INTR);
	assert_int_equal(r.tags.n, 2);
	/* no callbacks at all is fine: rows are counted */
	assert_int_equal(df1_map_load(data_path("map_valid.csv"), false, NULL, NULL, NULL), 7);
	assert_int_equal(df1_map_load(data_path("map_invalid.csv"), true, NULL, NULL, NULL),
	                 DF1_E_CONFIG);
}

static void test_config_map_missing_file_names_path(void **state)
{
	struct map_result r = { 0 };
	const char *path = "/nonexistent-dir/df1/map.csv";

	(void)state;
	errno = 0;
	assert_int_equal(map_load_path(path, false, &r), DF1_E_SYS);
	assert_int_equal(errno, ENOENT);
	assert_int_equal(r.issues.n, 1);
	assert_non_null(strstr(r.issues.v[0].text, path));
	assert_int_equal(df1_map_load(NULL, false, NULL, NULL, NULL), DF1_E_INVAL);
}

static void test_config_map_example_loads(void **state)
{
	struct map_result r = { 0 };
	int rc;

	(void)state;
	rc = map_load_path(example_path("map.csv"), true, &r);
	if (rc < 0)
		dump_issues(&r.issues);
	assert_int_equal(rc, 11);
	assert_string_equal(r.tags.v[9].name, "Line 3, Speed");
	assert_tag_addr(&r.tags.v[4], "T4:0/DN");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_config_net_defaults_match_seed),
		cmocka_unit_test(test_config_net_valid_file_gives_values),
		cmocka_unit_test(test_config_net_header_only_is_an_error),
		cmocka_unit_test(test_config_net_boundary_values_accepted),
		cmocka_unit_test(test_config_net_handshake_and_mode_duplex),
		cmocka_unit_test(test_config_net_link_and_store_forward),
		cmocka_unit_test(test_config_net_com_port_forms),
		cmocka_unit_test(test_config_net_each_invalid_value_reported_with_id),
		cmocka_unit_test(test_config_net_all_invalid_all_reported),
		cmocka_unit_test(test_config_net_unknown_and_duplicate_columns_fail),
		cmocka_unit_test(test_config_net_csv_forms),
		cmocka_unit_test(test_config_net_malformed_csv_fails),
		cmocka_unit_test(test_config_net_missing_file_names_path),
		cmocka_unit_test(test_config_net_example_loads),
		cmocka_unit_test(test_config_apply_sets_handle),
		cmocka_unit_test(test_config_map_valid_file_gives_rows),
		cmocka_unit_test(test_config_map_each_bad_row_reported_and_skipped),
		cmocka_unit_test(test_config_map_address_forms_and_counts),
		cmocka_unit_test(test_config_map_plc3_rows),
		cmocka_unit_test(test_config_map_header_problems_fail_the_load),
		cmocka_unit_test(test_config_map_row_fields_limits),
		cmocka_unit_test(test_config_nul_byte_in_a_cell_is_an_error),
		cmocka_unit_test(test_config_map_scan_ms_zero_is_every_scan),
		cmocka_unit_test(test_config_map_receive_rows),
		cmocka_unit_test(test_config_field_over_the_limit_is_an_error),
		cmocka_unit_test(test_config_map_row_fn_error_stops),
		cmocka_unit_test(test_config_map_missing_file_names_path),
		cmocka_unit_test(test_config_map_example_loads),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
