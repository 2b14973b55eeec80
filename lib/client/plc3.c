/* SPDX-License-Identifier: MPL-2.0 */
/*
 * plc3.c - PLC-3: word range read (0F/01) and write (0F/00) with a PLC-3
 * logical binary address (doc/PROTOCOL.md 4.2a). Each packet is a transaction
 * of its own: its start address is the packet's first element, packet offset
 * 0 and total transaction the packet's words (the 1775-KA's single-packet
 * form), so no packet relies on the PLC keeping a transaction's state. Bit
 * writes (0F/02) are in elements.c's client_mask_word.
 */
#include "client/client_int.h"

int plc3_addr(struct df1 *h, int station, const char *what, const struct df1_addr *a,
              uint8_t *out, size_t cap)
{
	int n = pccc_enc_plc3_addr(out, cap, a);

	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the PLC-3 address (%s)",
		                   df1_strerror(n));
	return n;
}

/* The types a PLC-3 data table has (R and ST are not among them). */
static int plc3_check(struct df1 *h, int station, const char *what, const struct span *s)
{
	if (s->a.type == DF1_FT_R || s->a.type == DF1_FT_ST || s->by_sub)
		return client_fail(h, DF1_E_NOTSUP, station, what,
		                   "a PLC-3 has no such section (O I T C N F D B A H S)");
	if ((s->esize & 1) || s->esize == 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "PLC-3 commands move whole words");
	return 0;
}

int plc3_read_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd)
{
	rd->per = client_limit(h, s, false) / s->esize;
	if (rd->per == 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "one element does not fit a packet");
	return plc3_check(h, station, what, s);
}

/* The next packet: 0F/01 from element done on, as many elements as fit. */
int plc3_read_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                  uint8_t *cmd, size_t cap)
{
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	struct df1_addr at;
	size_t bytes;
	int n;

	rd->k = s->count - rd->done < rd->per ? s->count - rd->done : rd->per;
	bytes = rd->k * s->esize;
	span_at(s, rd->done, &at);
	rd->alen = plc3_addr(h, station, what, &at, rd->addr, sizeof rd->addr);
	if (rd->alen < 0)
		return rd->alen;
	n = pccc_enc_plc5_word_read(cmd, cap, &hd, 0, (uint16_t)(bytes / 2), rd->addr, (size_t)rd->alen,
	                            (uint8_t)bytes);
	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the read (%s)", df1_strerror(n));
	return n;
}

/* Its reply's data: exactly the words asked, elements in order. */
int plc3_read_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                   struct rd *rd, const uint8_t *d, size_t dlen)
{
	if (dlen != rd->k * s->esize)
		return client_bad_reply(h, station, what, "reply has %zu data bytes, asked %zu", dlen,
		                        rd->k * s->esize);
	for (size_t i = 0; i < rd->k; i++) {
		int rc = io_put(h, station, what, io, rd->done + i, d + i * s->esize, s->esize);

		if (rc < 0)
			return rc;
	}
	rd->done += rd->k;
	return 0;
}

int plc3_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], data[FRAME_MAX_DATA];
	uint8_t addr[DF1_ADDR_ASCII_MAX + 8];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	size_t per = client_limit(h, s, true) / s->esize, done = 0;
	int rc = plc3_check(h, station, what, s);

	if (rc < 0)
		return rc;
	if (per == 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "one element does not fit a packet");
	while (done < s->count) {
		size_t k = s->count - done < per ? s->count - done : per, dlen;
		struct df1_addr at;
		const uint8_t *d;
		int n, alen;

		rc = io_gather(h, station, what, io, done, k, data, s->esize);
		if (rc < 0)
			return rc;
		span_at(s, done, &at);
		alen = plc3_addr(h, station, what, &at, addr, sizeof addr);
		if (alen < 0)
			return alen;
		n = pccc_enc_plc5_word_write(cmd, sizeof cmd, &hd, 0, (uint16_t)(k * s->esize / 2), addr,
		                             (size_t)alen, data, k * s->esize);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the write (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
		done += k;
	}
	return 0;
}
