/* SPDX-License-Identifier: MPL-2.0 */
/*
 * config_net.c - the network configuration file (one row: the line's settings)
 * and applying it to a handle. The CSV rules are config_csv.c's.
 *
 * Network file (doc/REQUIREMENTS.md 004, "Network Configuration Parameters"): the first data
 * row is used, later rows are ignored. A file with a header and no data row
 * (blank and comment rows do not count) is an error naming the file, catalog
 * ID 0 (none of 2552-2559 fits): the module does not start. Every invalid
 * value is reported, then the load fails with DF1_E_CONFIG and *c is left
 * untouched:
 *   Station      0-254, default 5                     2552 CRT_BAD_STATION_ID
 *   Mode         Master | Slave | Peer, default Master 2553 CRT_BAD_DRIVER_MODE
 *                (2554 CRT_UNSUPPORTED_MODE never fires: libdf1 supports all three)
 *   PLC_Type     PLC2 | PLC3 | PLC5 | SLC | MicroLogix, default PLC5
 *                                                     2555 CRT_BAD_PLC_TYPE
 *                also accepted: "PLC-5" and the like ('-', '_', '/', '.' and spaces
 *                are ignored), SLC500, SLC503-505 (SLC), SLC501/SLC502 ("SLC 5/02":
 *                82-byte packets), ML, MicroLogix1400, ML1100 ... (MicroLogix).
 *                PLC3 (since 0.5): word range commands, doc/PROTOCOL.md 4.2a. The
 *                2555 message still lists the four of the catalog's format.
 *   Error_Code   BCC | CRC, default CRC                2556 CRT_BAD_ERROR_CODE
 *   NAK_Retries  0-10, default 3                       2557 CRT_BAD_NAK_RETRIES
 *   ENQ_Retries  0-10, default 3                       2558 CRT_BAD_ENQ_RETRIES
 *   Cmd_Timeout  500-5000 ms, default 1000             2559 CRT_BAD_CMD_TIMEOUT
 *   Com_Port     n (1 -> /dev/ttyS0, n -> /dev/ttyS(n-1), 1-256), COMn (the same),
 *                an absolute device path, or tcp://host:port (a scheme of lib/scheme.c
 *                whose port the DF1 link runs on, its target checked by the backend);
 *                default 1
 *   Baud         1200 2400 4800 9600 19200 38400 57600 115200, default 9600
 *   Data_Bits    5-8, default 8;  Stop_Bits 1-2, default 1
 *   Parity       None | Even | Odd (or N E O), default None
 *   Timeout      0-360000 ms, default 1000;  TX_Delay 0-65535 ms, default 0
 *   Handshake    Yes | No (or Y N), default No
 * Two columns beyond the seed's table (extensions, since 0.5; libdf1(7)):
 *   Link         Full | Half | Radio, default from Mode: the link mode, Radio
 *                the DF1 Radio Modem (doc/PROTOCOL.md 2.6); Half needs Mode
 *                Master or Slave
 *   Store_Forward a station list (1,3-5,255; none), Link Radio only: the
 *                stations whose packets this node relays (df1_forward_parse)
 * The last nine have no catalog ID: they are reported with catalog_id 0 and a
 * text in the seed's style naming the field and the valid values. Mode Master or
 * Slave sets duplex_half (half duplex, multidrop), Peer clears it (full duplex);
 * Link, when given, decides instead.
 */
#include "config/config_int.h"
#include "scheme.h"

#include <stdio.h>
#include <string.h>

/* ---- network file ----------------------------------------------------------- */

enum cfg_net_field {
	NF_STATION, NF_MODE, NF_PLC_TYPE, NF_ERROR_CODE, NF_NAK_RETRIES, NF_ENQ_RETRIES,
	NF_CMD_TIMEOUT, NF_COM_PORT, NF_BAUD, NF_DATA_BITS, NF_STOP_BITS, NF_PARITY,
	NF_TIMEOUT, NF_TX_DELAY, NF_HANDSHAKE, NF_LINK, NF_STORE_FORWARD, NF_COUNT
};

static const char *const cfg_net_names[NF_COUNT] = {
	"Station", "Mode", "PLC_Type", "Error_Code", "NAK_Retries", "ENQ_Retries",
	"Cmd_Timeout", "Com_Port", "Baud", "Data_Bits", "Stop_Bits", "Parity",
	"Timeout", "TX_Delay", "Handshake", "Link", "Store_Forward",
};

void df1_net_config_defaults(struct df1_net_config *c)
{
	if (!c)
		return;
	memset(c, 0, sizeof *c);
	c->station = 5;
	c->mode = DF1_MODE_MASTER;
	c->plc = DF1_PLC_PLC5;
	c->check = DF1_CHECK_CRC;
	c->nak_retries = 3;
	c->enq_retries = 3;
	c->cmd_timeout_ms = 1000;
	strcpy(c->port, "/dev/ttyS0");
	c->baud = 9600;
	c->data_bits = 8;
	c->stop_bits = 1;
	c->parity = 'N';
	c->timeout_ms = 1000;
	c->tx_delay_ms = 0;
	c->handshake = false;
	c->duplex_half = true;
}

struct cfg_net_ctx {
	struct df1_net_config cfg;
};

/* An integer in [lo, hi] for a field without a catalog ID. */
static bool cfg_net_range(struct cfg_load *l, int line, const char *label, const char *v, int lo,
                      int hi, int *out)
{
	int x;

	if (cfg_int(v, &x) && x >= lo && x <= hi) {
		*out = x;
		return true;
	}
	cfg_report(l, 0, l->item, line, "Invalid %s (%.64s) should be in range [%d, %d]", label, v,
	           lo, hi);
	return false;
}

/* Catalog fields "(%d) ... [0, %d]" style: value, then the limits in args. */
static void cfg_net_bad_int(struct cfg_load *l, int id, int line, const char *v,
                            const char *fallback, const char *sig, int a1, int a2)
{
	int x;

	if (cfg_int(v, &x)) {
		if (sig[2])
			cfg_catalog(l, id, l->item, line, fallback, sig, -1, x, a1, a2);
		else
			cfg_catalog(l, id, l->item, line, fallback, sig, -1, x, a1);
	} else {
		if (sig[2])
			cfg_catalog(l, id, l->item, line, fallback, sig, 0, v, a1, a2);
		else
			cfg_catalog(l, id, l->item, line, fallback, sig, 0, v, a1);
	}
}

/* A scheme's target, as df1_open() reads it (lib/scheme.c): "name://rest" for
 * a scheme whose port the DF1 link runs on and whose backend finds rest well
 * formed (port_ops.config_ok); written back with the scheme in lower case. */
static bool cfg_net_scheme(const struct scheme_row *s, const char *v, char *out, size_t cap)
{
	size_t n = strlen(s->name);

	if (s->link || !s->port->config_ok || strncmp(v + n, "://", 3) != 0 ||
	    !s->port->config_ok(v + n + 3) || strlen(v) >= cap)
		return false;
	snprintf(out, cap, "%s://%s", s->name, v + n + 3);
	return true;
}

static bool cfg_net_port(const char *v, char *out, size_t cap)
{
	const struct scheme_row *s;
	int n;

	if (cfg_all_digits(v) || (cfg_istarts(v, "COM") && cfg_all_digits(v + 3))) {
		if (!cfg_int(cfg_all_digits(v) ? v : v + 3, &n) || n < 1 || n > COM_PORT_MAX)
			return false;
		snprintf(out, cap, "/dev/ttyS%d", n - 1);
		return true;
	}
	s = scheme_find(v);
	if (s->name)
		return cfg_net_scheme(s, v, out, cap);
	/* the default row, a device path: an absolute one here */
	if (v[0] != '/' || strlen(v) >= cap)
		return false;
	strcpy(out, v);
	return true;
}

/* Station, Mode, PLC_Type, Error_Code: what the driver is (catalog IDs 2552-2556). */
static void cfg_net_driver(struct cfg_load *l, struct cfg_row *row, struct df1_net_config *c)
{
	const char *v;
	int x, line = row->line;

	v = cfg_value(l, row, NF_STATION);
	if (*v) {
		if (cfg_int(v, &x) && x >= 0 && x < STATION_LIMIT)
			c->station = x;
		else
			cfg_net_bad_int(l, DF1_ID_CRT_BAD_STATION_ID, line, v,
			                "Invalid station number (%d) must be less than %d",
			            "dd", STATION_LIMIT, 0);
	}
	v = cfg_value(l, row, NF_MODE);
	if (*v) {
		if (cfg_ieq(v, "Master"))
			c->mode = DF1_MODE_MASTER;
		else if (cfg_ieq(v, "Slave"))
			c->mode = DF1_MODE_SLAVE;
		else if (cfg_ieq(v, "Peer"))
			c->mode = DF1_MODE_PEER;
		else
			cfg_catalog(l, DF1_ID_CRT_BAD_DRIVER_MODE, l->item, line,
			            "Invalid Driver Mode (%s), should be one of %s, %s, or %s", "ssss", -1,
			            v, "Master", "Slave", "Peer");
		c->duplex_half = c->mode != DF1_MODE_PEER;
	}
	v = cfg_value(l, row, NF_PLC_TYPE);
	if (*v && cfg_plc(v, &c->plc) < 0)
		cfg_catalog(l, DF1_ID_CRT_BAD_PLC_TYPE, l->item, line,
		            "Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s",
		            "sssss", -1, v, PLC_CHOICES);
	v = cfg_value(l, row, NF_ERROR_CODE);
	if (*v) {
		if (cfg_ieq(v, "CRC"))
			c->check = DF1_CHECK_CRC;
		else if (cfg_ieq(v, "BCC"))
			c->check = DF1_CHECK_BCC;
		else
			cfg_catalog(l, DF1_ID_CRT_BAD_ERROR_CODE, l->item, line,
			            "Invalid Error Code (%s), should be either %s, or %s", "sss", -1, v,
			            "BCC", "CRC");
	}
}

/* NAK_Retries, ENQ_Retries, Cmd_Timeout: how hard it tries (catalog IDs 2557-2559). */
static void cfg_net_retries(struct cfg_load *l, struct cfg_row *row, struct df1_net_config *c)
{
	const char *v;
	int x, line = row->line;

	v = cfg_value(l, row, NF_NAK_RETRIES);
	if (*v) {
		if (cfg_int(v, &x) && x >= 0 && x <= RETRIES_MAX)
			c->nak_retries = x;
		else
			cfg_net_bad_int(l, DF1_ID_CRT_BAD_NAK_RETRIES, line, v,
			                "Invalid NAK Retries (%d) should be in range [0, %d]",
			            "dd", RETRIES_MAX, 0);
	}
	v = cfg_value(l, row, NF_ENQ_RETRIES);
	if (*v) {
		if (cfg_int(v, &x) && x >= 0 && x <= RETRIES_MAX)
			c->enq_retries = x;
		else
			cfg_net_bad_int(l, DF1_ID_CRT_BAD_ENQ_RETRIES, line, v,
			                "Invalid ENQ Retries (%d) should be in range [0, %d]",
			            "dd", RETRIES_MAX, 0);
	}
	v = cfg_value(l, row, NF_CMD_TIMEOUT);
	if (*v) {
		if (cfg_int(v, &x) && x >= CMD_TIMEOUT_MIN && x <= CMD_TIMEOUT_MAX)
			c->cmd_timeout_ms = x;
		else
			cfg_net_bad_int(l, DF1_ID_CRT_BAD_CMD_TIMEOUT, line, v,
			            "Invalid Cmd Timeout (%d) should be in range [%d, %d]", "ddd",
			            CMD_TIMEOUT_MIN, CMD_TIMEOUT_MAX);
	}
}

/* Com_Port and Baud: where the line is and its rate (no catalog IDs). */
static void cfg_net_where(struct cfg_load *l, struct cfg_row *row, struct df1_net_config *c)
{
	static const int bauds[] = { 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200 };
	const char *v;
	int x, line = row->line;
	bool ok = false;

	v = cfg_value(l, row, NF_COM_PORT);
	c->port_given = *v != '\0';
	if (*v && !cfg_net_port(v, c->port, sizeof c->port))
		cfg_report(l, 0, l->item, line,
		           "Invalid Com Port (%.64s) should be a port number [1, %d], COMn, a device "
		           "path (/dev/...) or tcp://host:port", v, COM_PORT_MAX);
	v = cfg_value(l, row, NF_BAUD);
	if (!*v)
		return;
	if (cfg_int(v, &x))
		for (size_t i = 0; i < sizeof bauds / sizeof bauds[0]; i++)
			ok = ok || x == bauds[i];
	if (ok)
		c->baud = x;
	else
		cfg_report(l, 0, l->item, line, "Invalid Baud (%.64s) should be one of 1200, 2400, "
		           "4800, 9600, 19200, 38400, 57600, or 115200", v);
}

/* Data_Bits, Stop_Bits, Parity, Timeout, TX_Delay, Handshake: the character
 * frame and the line's timing (no catalog IDs). */
static void cfg_net_line(struct cfg_load *l, struct cfg_row *row, struct df1_net_config *c)
{
	const char *v;
	int line = row->line;

	v = cfg_value(l, row, NF_DATA_BITS);
	if (*v)
		cfg_net_range(l, line, "Data Bits", v, 5, 8, &c->data_bits);
	v = cfg_value(l, row, NF_STOP_BITS);
	if (*v)
		cfg_net_range(l, line, "Stop Bits", v, 1, 2, &c->stop_bits);
	v = cfg_value(l, row, NF_PARITY);
	if (*v) {
		if (cfg_ieq(v, "None") || cfg_ieq(v, "N"))
			c->parity = 'N';
		else if (cfg_ieq(v, "Even") || cfg_ieq(v, "E"))
			c->parity = 'E';
		else if (cfg_ieq(v, "Odd") || cfg_ieq(v, "O"))
			c->parity = 'O';
		else
			cfg_report(l, 0, l->item, line,
			           "Invalid Parity (%.64s), should be one of Odd, Even, or None", v);
	}
	v = cfg_value(l, row, NF_TIMEOUT);
	if (*v)
		cfg_net_range(l, line, "Timeout", v, 0, TIMEOUT_MAX, &c->timeout_ms);
	v = cfg_value(l, row, NF_TX_DELAY);
	if (*v)
		cfg_net_range(l, line, "TX Delay", v, 0, TX_DELAY_MAX, &c->tx_delay_ms);
	v = cfg_value(l, row, NF_HANDSHAKE);
	if (*v) {
		if (cfg_ieq(v, "Yes") || cfg_ieq(v, "Y"))
			c->handshake = true;
		else if (cfg_ieq(v, "No") || cfg_ieq(v, "N"))
			c->handshake = false;
		else
			cfg_report(l, 0, l->item, line,
			           "Invalid Handshake (%.64s), should be either Yes, or No", v);
	}
}

/* Link, Store_Forward: the link mode, and a radio node's relaying (the
 * extension columns, after Mode has set its default). */
static void cfg_net_link(struct cfg_load *l, struct cfg_row *row, struct df1_net_config *c)
{
	const char *v = cfg_value(l, row, NF_LINK);
	int line = row->line;

	if (*v) {
		if (cfg_ieq(v, "Full")) {
			c->duplex_half = false;
		} else if (cfg_ieq(v, "Radio")) {
			c->duplex_half = false;
			c->radio = true;
		} else if (cfg_ieq(v, "Half")) {
			c->duplex_half = true;
			if (c->mode == DF1_MODE_PEER)
				cfg_report(l, 0, l->item, line, "Link Half needs Mode Master or Slave (a "
				           "half-duplex line has one master and its slaves), not Peer");
		} else {
			cfg_report(l, 0, l->item, line,
			           "Invalid Link (%.64s), should be one of Full, Half, or Radio", v);
		}
	}
	v = cfg_value(l, row, NF_STORE_FORWARD);
	if (!*v)
		return;
	if (df1_forward_parse(v, c->forward) < 0)
		cfg_report(l, 0, l->item, line, "Invalid Store_Forward (%.64s), should be a list of "
		           "stations 0-255 such as 1,3-5,255, or none", v);
	else if (!c->radio)
		cfg_report(l, 0, l->item, line, "Store_Forward (%.64s) needs Link Radio (store and "
		           "forward is the radio modem's)", v);
	else
		c->forward_set = true;
}

/* The first data row configures the module; every invalid value is reported,
 * in the order of the fields. */
static void cfg_net_row(struct cfg_load *l, struct cfg_row *row)
{
	struct df1_net_config *c = &((struct cfg_net_ctx *)l->ctx)->cfg;

	if (l->item > 1)
		return;
	cfg_check_cells(l, row, false);
	cfg_net_driver(l, row, c);
	cfg_net_retries(l, row, c);
	cfg_net_where(l, row, c);
	cfg_net_line(l, row, c);
	cfg_net_link(l, row, c);
}

int df1_net_config_load(const char *path, struct df1_net_config *c, df1_config_issue_fn fn,
                        void *user)
{
	struct cfg_load l;
	struct cfg_net_ctx ctx;
	FILE *f;
	int rc;

	if (!path || !c)
		return DF1_E_INVAL;
	df1_net_config_defaults(&ctx.cfg);
	cfg_init(&l, fn, user, cfg_net_names, NF_COUNT, NULL, 0, cfg_net_row, &ctx);
	f = cfg_open(&l, path);
	if (!f)
		return DF1_E_SYS;
	rc = cfg_read(&l, f, path);
	fclose(f);
	if (rc == 0 && l.stop < 0)
		rc = l.stop;
	if (rc == 0 && l.item == 0) {
		/* a header alone would configure every default (Com_Port 1, /dev/ttyS0)
		 * without a word; no seed ID names this, so catalog ID 0 */
		cfg_report(&l, 0, 0, 0, "%.150s: no data row (a network file holds one row of "
		           "settings under its header)", path);
		rc = DF1_E_CONFIG;
	}
	if (rc == 0 && l.issues > 0)
		rc = DF1_E_CONFIG;
	if (rc == 0)
		*c = ctx.cfg;
	return rc;
}

int df1_apply_net_config(df1_t *h, const struct df1_net_config *c)
{
	enum df1_duplex duplex;
	int rc;

	if (!h || !c)
		return DF1_E_INVAL;
	if (c->radio)
		duplex = DF1_RADIO_MODEM;
	else if (c->mode == DF1_MODE_PEER || !c->duplex_half)
		duplex = DF1_FULL_DUPLEX;
	else if (c->mode == DF1_MODE_SLAVE)
		duplex = DF1_HALF_DUPLEX_SLAVE;
	else
		duplex = DF1_HALF_DUPLEX_MASTER;
	rc = df1_set_serial(h, c->baud, c->data_bits, c->parity, c->stop_bits);
	if (rc >= 0)
		rc = df1_set_handshake(h, c->handshake);
	if (rc >= 0)
		rc = df1_set_duplex(h, duplex);
	if (rc >= 0)
		rc = df1_set_check(h, c->check);
	if (rc >= 0)
		rc = df1_set_station(h, c->station);
	if (rc >= 0)
		rc = df1_set_plc(h, c->plc);
	if (rc >= 0)
		rc = df1_set_timeout_ms(h, c->timeout_ms);
	if (rc >= 0)
		rc = df1_set_cmd_timeout_ms(h, c->cmd_timeout_ms);
	if (rc >= 0)
		rc = df1_set_retries(h, c->nak_retries, c->enq_retries);
	if (rc >= 0)
		rc = df1_set_tx_delay_ms(h, c->tx_delay_ms);
	if (rc >= 0 && c->radio)
		rc = df1_set_forward(h, c->forward_set ? c->forward : NULL);
	return rc < 0 ? rc : 0;
}
