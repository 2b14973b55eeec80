/* SPDX-License-Identifier: MPL-2.0 */
/*
 * slc.c - SLC 5/03+, MicroLogix and SLC 5/01-5/02: protected typed logical
 * reads and writes with three address fields (0F/A2, 0F/AA), split into packets.
 */
#include "client/client_int.h"

int slc_type_code(struct df1 *h, int station, const char *what, enum df1_file_type t)
{
	int code = df1_file_type_slc_code(t);

	if (code <= 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "file type has no SLC code");
	if (h->cfg.slc_io_82 && (t == DF1_FT_O || t == DF1_FT_I))
		code = t == DF1_FT_O ? 0x82 : 0x83;     /* F2E p.47 (doc/PROTOCOL.md 4.11) */
	return code;
}

static void slc_fields(const struct span *s, size_t i, unsigned *elem, unsigned *sub)
{
	if (s->by_sub) {
		*elem = (unsigned)s->a.element;
		*sub = (unsigned)s->a.sub + (unsigned)i;
	} else {
		*elem = (unsigned)s->a.element + (unsigned)i;
		*sub = s->a.sub == DF1_ADDR_NONE ? 0u : (unsigned)s->a.sub;
	}
}

/* The SLC file type code of a span and how many of its elements fit one packet. */
static int slc_begin(struct df1 *h, int station, const char *what, const struct span *s,
                     bool write, size_t *per)
{
	int code = slc_type_code(h, station, what, s->a.type);

	if (code < 0)
		return code;
	*per = client_limit(h, s, write) / s->esize;
	if (*per == 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "a %zu-byte element exceeds the packet size", s->esize);
	return code;
}

int slc_read_begin(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd)
{
	int code = slc_begin(h, station, what, s, false, &rd->per);

	if (code < 0)
		return code;
	rd->code = code;
	return 0;
}

/* The next packet: 0F/A2 for as many elements as fit. */
int slc_read_cmd(struct df1 *h, int station, const char *what, const struct span *s, struct rd *rd,
                 uint8_t *cmd, size_t cap)
{
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	unsigned elem, sub;
	int n;

	rd->k = s->count - rd->done < rd->per ? s->count - rd->done : rd->per;
	slc_fields(s, rd->done, &elem, &sub);
	n = pccc_enc_slc_read(cmd, cap, &hd, PCCC_FNC_SLC_READ3, (uint8_t)(rd->k * s->esize),
	                      (unsigned)s->a.file, (uint8_t)rd->code, elem, sub);
	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the read (%s)", df1_strerror(n));
	return n;
}

/* Its reply's data: exactly the bytes asked, element by element. */
int slc_read_take(struct df1 *h, int station, const char *what, const struct span *s, struct io *io,
                  struct rd *rd, const uint8_t *d, size_t dlen)
{
	size_t want = rd->k * s->esize;

	if (dlen != want)
		return client_bad_reply(h, station, what, "reply has %zu data bytes, asked %zu", dlen, want);
	for (size_t i = 0; i < rd->k; i++) {
		int rc = io_put(h, station, what, io, rd->done + i, d + i * s->esize, s->esize);

		if (rc < 0)
			return rc;
	}
	rd->done += rd->k;
	return 0;
}

int slc_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], data[FRAME_MAX_DATA];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	size_t per, done = 0;
	int code = slc_begin(h, station, what, s, true, &per);

	if (code < 0)
		return code;
	while (done < s->count) {
		size_t k = s->count - done < per ? s->count - done : per;
		size_t nbytes = k * s->esize, dlen;
		const uint8_t *d;
		unsigned elem, sub;
		int n, rc;

		rc = io_gather(h, station, what, io, done, k, data, s->esize);
		if (rc < 0)
			return rc;
		slc_fields(s, done, &elem, &sub);
		n = pccc_enc_slc_write(cmd, sizeof cmd, &hd, PCCC_FNC_SLC_WRITE3, (unsigned)s->a.file,
		                       (uint8_t)code, elem, sub, data, (uint8_t)nbytes);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the write (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
		done += k;
	}
	return 0;
}
