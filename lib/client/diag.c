/* SPDX-License-Identifier: MPL-2.0 */
/*
 * diag.c - any PCCC command, diagnostic status, echo, link test, change mode.
 */
#include "client/client_int.h"

int df1_command(df1_t *h, int station, uint8_t cmd, const uint8_t *body, size_t body_len,
                uint8_t *reply, size_t reply_cap)
{
	uint8_t c[FRAME_MAX_DATA], r[FRAME_MAX_DATA];
	char what[24];
	const uint8_t *d;
	size_t dlen;
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	snprintf(what, sizeof what, "command %02X", cmd);
	if ((body_len && !body) || (reply_cap && !reply))
		return client_fail(h, DF1_E_INVAL, station, what, "NULL buffer");
	if (cmd & PCCC_REPLY_BIT)
		return client_fail(h, DF1_E_INVAL, station, what, "a reply code, not a command");
	if (body_len > sizeof c - PCCC_HDR_LEN)
		return client_fail(h, DF1_E_INVAL, station, what, "%zu bytes of body is too long", body_len);
	memset(c, 0, PCCC_HDR_LEN);
	c[2] = cmd;
	if (body_len)
		memcpy(c + PCCC_HDR_LEN, body, body_len);
	rc = client_transact(h, station, what, c, PCCC_HDR_LEN + body_len, r, sizeof r, &d, &dlen);
	if (rc < 0)
		return rc;
	if (dlen > reply_cap)
		return client_fail(h, DF1_E_NOSPACE, station, what, "%zu reply bytes, room for %zu", dlen,
		                reply_cap);
	if (dlen)
		memcpy(reply, d, dlen);
	return (int)dlen;
}

int df1_diag_status(df1_t *h, int station, struct df1_diag_status *out)
{
	uint8_t c[FRAME_MAX_DATA], r[FRAME_MAX_DATA];
	struct pccc_hdr hd;
	const uint8_t *d;
	size_t dlen;
	int n, rc = client_check(h, station);

	if (rc < 0)
		return rc;
	if (!out)
		return df1_fail(h, DF1_E_INVAL, station, "diagnostic status: no output");
	hd = (struct pccc_hdr){ (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	n = pccc_enc_diag_status(c, sizeof c, &hd);
	if (n < 0)
		return df1_fail(h, n, station, "diagnostic status: cannot encode");
	rc = client_op_transact(h, station, "diagnostic status", c, (size_t)n, r, sizeof r, &d, &dlen);
	if (rc < 0)
		return rc;
	rc = pccc_dec_diag_status(d, dlen, out);
	if (rc < 0)
		return client_bad_reply(h, station, NULL, "diagnostic status: %zu-byte reply too short",
		                dlen);
	return 0;
}

int df1_echo(df1_t *h, int station, const uint8_t *data, size_t n)
{
	uint8_t c[FRAME_MAX_DATA], r[FRAME_MAX_DATA];
	struct pccc_hdr hd;
	const uint8_t *d;
	size_t dlen;
	int len, rc = client_check(h, station);

	if (rc < 0)
		return rc;
	if ((n && !data) || n > PLC_ECHO_MAX)
		return df1_fail(h, DF1_E_INVAL, station, "echo: %zu bytes (0-%d)", n, PLC_ECHO_MAX);
	hd = (struct pccc_hdr){ (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	len = pccc_enc_echo(c, sizeof c, &hd, data, n);
	if (len < 0)
		return df1_fail(h, len, station, "echo: cannot encode");
	rc = client_op_transact(h, station, "echo", c, (size_t)len, r, sizeof r, &d, &dlen);
	if (rc < 0)
		return rc;
	if (dlen != n || (n && memcmp(d, data, n) != 0))
		return client_bad_reply(h, station, NULL, "echo: reply differs from the data sent "
		                "(%zu of %zu bytes)", dlen, n);
	return (int)n;
}

int df1_link_test(df1_t *h, int station)
{
	int rc = client_check(h, station);

	return rc < 0 ? rc : link_test(h, station);
}

/*
 * SLC 5/03+ and MicroLogix: 0F/80 with the mode byte as given (1 program,
 * 6 run, 7 test continuous, 8 test single scan; doc/PROTOCOL.md 4.8 [UNCERTAIN] for 7/8).
 * PLC-5 and SLC 5/01-5/02: 0F/3A set CPU mode, whose flag byte takes the same
 * codes mapped: 1 -> 00 program, 6 -> 02 run, 7 or 8 -> 01 test. PLC-2: not supported.
 */
int df1_change_mode(df1_t *h, int station, int mode)
{
	uint8_t c[FRAME_MAX_DATA], r[FRAME_MAX_DATA];
	struct pccc_hdr hd;
	const uint8_t *d;
	size_t dlen;
	int n, rc = client_check(h, station);

	if (rc < 0)
		return rc;
	hd = (struct pccc_hdr){ (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	switch (h->cfg.plc) {
	case DF1_PLC_PLC2:
		return df1_fail(h, DF1_E_NOTSUP, station, "change mode: not a PLC-2 command");
	case DF1_PLC_PLC3:
		return df1_fail(h, DF1_E_NOTSUP, station, "change mode: not a PLC-3 command");
	case DF1_PLC_PLC5:
	case DF1_PLC_SLC502: {
		uint8_t flag;

		switch (mode) {
		case 1: flag = 0x00; break;
		case 6: flag = 0x02; break;
		case 7: case 8: flag = 0x01; break;
		default:
			return df1_fail(h, DF1_E_INVAL, station,
			                "change mode: mode %d (1 program, 6 run, 7/8 test)", mode);
		}
		memset(c, 0, PCCC_HDR_LEN);
		c[2] = PCCC_CMD_TYPED;
		c[6] = PCCC_FNC_SET_CPU_MODE;
		c[7] = flag;
		n = PCCC_HDR_LEN + 2;
		break;
	}
	default:
		if (mode < 0 || mode > 0xFF)
			return df1_fail(h, DF1_E_INVAL, station, "change mode: mode %d (1 program, 6 run)", mode);
		n = pccc_enc_change_mode(c, sizeof c, &hd, (uint8_t)mode);
		if (n < 0)
			return df1_fail(h, n, station, "change mode: cannot encode");
		break;
	}
	rc = client_op_transact(h, station, "change mode", c, (size_t)n, r, sizeof r, &d, &dlen);
	return rc < 0 ? rc : 0;
}
