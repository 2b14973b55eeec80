/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon_pcap - the pcap format as df1mon reads and writes it: the file header
 * (byte order, micro- or nanosecond timestamps, link type), the record header,
 * the RTAC serial header of link type 250 (its event type gives the
 * direction), and the writer of --sniff -w (link type 250, microseconds,
 * little-endian). --read's streaming parse of the records is mon_read.c's.
 */
#include "df1mon/mon.h"

#include <string.h>

#define PCAP_SNAPLEN 65535

static uint32_t rd32(const uint8_t *p, bool be)
{
	if (be)
		return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
	return (uint32_t)p[3] << 24 | (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
}

/* ---- reading ---- */

int mon_pcap_detect(const uint8_t *b, size_t n, struct pcap_fmt *f)
{
	uint32_t le, be;

	if (n < 4)
		return 0;
	le = rd32(b, false);
	be = rd32(b, true);
	memset(f, 0, sizeof *f);
	if (le == 0x0A0D0D0A)
		return -1;
	if (le == 0xA1B2C3D4 || le == 0xA1B23C4D) {
		f->nsec = le == 0xA1B23C4D;
		return 1;
	}
	if (be == 0xA1B2C3D4 || be == 0xA1B23C4D) {
		f->swapped = true;
		f->nsec = be == 0xA1B23C4D;
		return 1;
	}
	return 0;
}

uint32_t mon_pcap_linktype(const uint8_t *hdr, const struct pcap_fmt *f)
{
	return rd32(hdr + 20, f->swapped) & 0x0FFFFFFF;
}

void mon_pcap_rec_hdr(const uint8_t *hdr, const struct pcap_fmt *f, uint32_t *sec, int32_t *usec,
                      uint32_t *incl)
{
	uint32_t frac = rd32(hdr + 4, f->swapped);

	*sec = rd32(hdr, f->swapped);
	*incl = rd32(hdr + 8, f->swapped);
	*usec = (int32_t)(f->nsec ? frac / 1000 : frac);
	if (*usec < 0 || *usec > 999999)
		*usec = 0;
}

/* RTAC serial event types (the byte after the 8-byte timestamp): 01/03 transmit
 * start/end, 02/04 receive start/end; anything else goes with receive. */
int mon_rtac_dir(uint8_t event)
{
	return (event == 0x01 || event == 0x03) ? 1 : 0;
}

/* ---- writing: link type 250, a 12-byte RTAC header per record ---- */

static void put_le32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
	p[2] = (uint8_t)(v >> 16);
	p[3] = (uint8_t)(v >> 24);
}

static void put_be32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)(v >> 24);
	p[1] = (uint8_t)(v >> 16);
	p[2] = (uint8_t)(v >> 8);
	p[3] = (uint8_t)v;
}

bool mon_pcap_write_header(FILE *f)
{
	uint8_t h[PCAP_HDR];

	put_le32(h, 0xA1B2C3D4);               /* microsecond timestamps */
	h[4] = 2; h[5] = 0; h[6] = 4; h[7] = 0; /* version 2.4 */
	put_le32(h + 8, 0);                    /* thiszone */
	put_le32(h + 12, 0);                   /* sigfigs */
	put_le32(h + 16, PCAP_SNAPLEN);
	put_le32(h + 20, LINKTYPE_RTAC_SERIAL);
	return fwrite(h, 1, sizeof h, f) == sizeof h && fflush(f) == 0;
}

bool mon_pcap_write_record(FILE *f, int64_t sec, int32_t usec, uint8_t event, uint8_t lines,
                           const uint8_t *b, size_t n)
{
	uint8_t rec[PCAP_REC_HDR + RTAC_HDR + MON_PCAP_DATA_MAX];
	size_t len = RTAC_HDR + n;

	if (n > MON_PCAP_DATA_MAX)
		return false;
	put_le32(rec, (uint32_t)sec);
	put_le32(rec + 4, (uint32_t)usec);
	put_le32(rec + 8, (uint32_t)len);
	put_le32(rec + 12, (uint32_t)len);
	put_be32(rec + 16, (uint32_t)sec);
	put_be32(rec + 20, (uint32_t)usec);
	rec[24] = event;
	rec[25] = lines;
	rec[26] = 0;
	rec[27] = 0;
	memcpy(rec + 28, b, n);
	return fwrite(rec, 1, PCAP_REC_HDR + len, f) == PCAP_REC_HDR + len && fflush(f) == 0;
}
