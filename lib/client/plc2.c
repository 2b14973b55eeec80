/* SPDX-License-Identifier: MPL-2.0 */
/*
 * plc2.c - PLC-2: unprotected reads and writes (01, 08), byte address = 2 * element,
 * or the element itself with DF1_OPT_PLC2_WORD_ADDR (doc/PROTOCOL.md 4.7).
 */
#include "client/client_int.h"

/* The command's address of word `element` of the PLC-2 area. */
static uint16_t plc2_address(const struct df1 *h, size_t element)
{
	return (uint16_t)(h->cfg.plc2_word_addr ? element : element * 2);
}

static int plc2_check(struct df1 *h, int station, const char *what, const struct span *s)
{
	if (!client_is_word_type(s->a.type) || s->esize != 2 || s->by_sub)
		return client_fail(h, DF1_E_NOTSUP, station, what,
		                "PLC-2 commands reach 16-bit words only (N B S I O A, no sub-element)");
	if (((size_t)s->a.element + s->count) * (h->cfg.plc2_word_addr ? 1 : 2) > 0x10000)
		return client_fail(h, DF1_E_ADDR_RANGE, station, what, "beyond the PLC-2 address range");
	return 0;
}

int plc2_read_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd)
{
	rd->per = client_limit(h, s, false) / 2;
	return plc2_check(h, station, what, s);
}

/* The next packet: 01 for as many words as fit. */
int plc2_read_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                  uint8_t *cmd, size_t cap)
{
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	int n;

	rd->k = s->count - rd->done < rd->per ? s->count - rd->done : rd->per;
	n = pccc_enc_plc2_read(cmd, cap, &hd, plc2_address(h, (size_t)s->a.element + rd->done),
	                       (uint8_t)(rd->k * 2));
	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the read (%s)", df1_strerror(n));
	return n;
}

/* Its reply's data: exactly the words asked. */
int plc2_read_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                   struct rd *rd, const uint8_t *d, size_t dlen)
{
	(void)s;
	if (dlen != rd->k * 2)
		return client_bad_reply(h, station, what, "reply has %zu data bytes, asked %zu", dlen, rd->k * 2);
	for (size_t i = 0; i < rd->k; i++) {
		int rc = io_put(h, station, what, io, rd->done + i, d + i * 2, 2);

		if (rc < 0)
			return rc;
	}
	rd->done += rd->k;
	return 0;
}

int plc2_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], data[FRAME_MAX_DATA];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	size_t per = client_limit(h, s, true) / 2, done = 0;
	int rc = plc2_check(h, station, what, s);

	if (rc < 0)
		return rc;
	while (done < s->count) {
		size_t k = s->count - done < per ? s->count - done : per, dlen;
		const uint8_t *d;
		int n;

		rc = io_gather(h, station, what, io, done, k, data, 2);
		if (rc < 0)
			return rc;
		n = pccc_enc_plc2_write(cmd, sizeof cmd, &hd, plc2_address(h, (size_t)s->a.element + done),
		                        data, k * 2);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the write (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
		done += k;
	}
	return 0;
}
