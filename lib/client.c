/*
 * client.c - the master side: df1_read / df1_write and friends (DESIGN.md 3).
 * address + values -> PCCC command(s) -> link_transact -> reply -> values.
 *
 * The PLC type (h->cfg.plc) picks the command set (spec/protocol.md 4):
 *
 *   SLC 5/03+, MicroLogix, SLC 5/01-5/02:
 *     read 0F/A2, write 0F/AA (three address fields: file, type, element, sub);
 *     bit writes 0F/AB (mask + data: only the masked bits change). O and I go
 *     as type codes 8B/8C (spec 4.11), or 82/83 with DF1_OPT_SLC_IO_CODES_82
 *     [SRC-CONFLICT, spec 8 item 10].
 *   PLC-5:
 *     read 0F/68, write 0F/67 (typed, counts in elements) with a logical binary
 *     address (06 file element, 0E with a sub-element) or, for "$N7:0", the
 *     logical ASCII form; bit writes 0F/26 read-modify-write
 *     (set: AND FFFF OR bit; clear: AND ~bit OR 0000). Typed writes send an
 *     array (99 09 LL desc data, as RTA and the spec 7.3 vectors); a reply may
 *     be an array or a single element. Strings (ST) go one per packet as a
 *     string parameter and the characters in text order (39 LEN chars, RTA).
 *     T/C/R elements are taken as their 3 data-table words; a PLC that answers
 *     with another element size (KF2: "timer elements return five words") is
 *     refused with DF1_E_BAD_REPLY rather than guessed at [UNCERTAIN, spec 8.8].
 *     Floats go plain little-endian in typed reads and writes, the spec 5
 *     recommendation (RTA); DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED word-swaps them
 *     ([2,3,0,1], as word range 0F/00/01 always has them; the client does not
 *     use word range). [UNCERTAIN, spec 8 item 7] Raw reads and writes pass
 *     the wire bytes either way.
 *   PLC-2 (01 unprotected read, 08 unprotected write, 05 unprotected bit write):
 *     PLC-2 commands carry a 16-bit byte address and no file. The address's
 *     element is taken as the WORD offset into the target's PLC-2 area (a PLC-2's
 *     data table; the PLC-2 compatibility file of a PLC-5; the Common Interface
 *     File N9 of an SLC; N7 of a MicroLogix 1000), byte address = 2 * element;
 *     the file number is ignored. "N7:8" = PLC-2 word 010 (octal). Only 16-bit
 *     word files (N B S I O A) and their bits; no sub-elements.
 *
 * Splitting (spec 6). Requests larger than one packet are split on element
 * boundaries. Data bytes per packet:
 *   SLC 5/03+ and MicroLogix: read 236, write 234; SLC 5/01-5/02: 82 / 82;
 *   PLC-2: 244 / 244;
 *   PLC-5: typed read reply <= 240 bytes including the address, the type/data
 *     parameter and element descriptor (counted as 8 bytes, the worst case);
 *     timers/counters/controls are counted as 10 bytes (KF2 "five words") to
 *     stay inside the limit whatever the PLC returns; typed write data
 *     <= 240 - address - type/data bytes. Multi-packet PLC-5 transfers repeat
 *     the start address and count PKT_OFFSET / TOTAL_TRANS in elements.
 *   DF1_OPT_MAX_PACKET (h->cfg.max_packet) replaces the per-type limits with
 *     that many bytes of element data per packet (at most 244).
 *
 * Address forms:
 *   whole elements          N7:0 x n, F8:0, L10:0, ST9:0 (84 bytes), T4:0 (6 bytes)
 *   T/C/R sub-element       T4:0.ACC: one 16-bit word per element. n == 1 reads and
 *                           writes that word (SUBELEMENT 1/2, or PLC-5 level 4);
 *                           n > 1 means the same word of n consecutive elements: reads
 *                           fetch whole elements and pick the word, writes go one
 *                           element at a time (never touching the other words).
 *   I/O word                I1:0.1 x n: element = slot, sub = word; n > 1 advances the
 *                           word (SUBELEMENT) across the image.
 *   bits                    B3:0/5 x n: n consecutive bits, crossing into the next
 *                           word after bit 15 (31 for L); a T/C/R bit stays in its word.
 *                           Reads fetch the word(s) and extract; writes are masked per
 *                           word (AB, 26 or 05), never clobbering the other bits.
 *                           An L bit on SLC/MicroLogix is an AB with a 4-byte mask and
 *                           data (BYTE_SIZE 4) [UNCERTAIN: spec 4.6, NPC found AB on L
 *                           files unreliable]; PLC-5 has no L files.
 *
 * Returns: element reads/writes return n; raw ones the byte count; df1_read_string
 * and df1_write_string the string length; df1_read_bit, df1_write_bit,
 * df1_diag_status, df1_change_mode and df1_link_test 0; df1_echo the length echoed.
 * A reply whose STS is not 0 is DF1_E_REMOTE (df1_last_error: sts, ext_sts); a
 * reply with fewer or more data bytes or elements than asked, or with the wrong
 * PLC-5 element type or size, is DF1_E_BAD_REPLY (counted as 2550); a typed
 * helper on a file that does not hold its type is DF1_E_TYPE, before any I/O.
 *
 * Errors: every failure is recorded with client_fail() / df1_fail_remote(); the
 * detail's address field names the address ("N7:0") and station the station,
 * and the message does not repeat the address. Buffers live on the stack (FRAME_MAX_DATA): no
 * allocation per packet.
 */
#include "df1_int.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "client.h"
#include "link.h"
#include "plc_limits.h"
#include "pccc.h"
#include "value.h"

#define ATEXT_MAX 64

/* A contiguous run of `count` elements of `esize` bytes starting at `a`. */
struct span {
	struct df1_addr a;      /* the first element; bit is always DF1_ADDR_NONE */
	size_t esize;           /* bytes per element on the wire */
	size_t count;
	bool by_sub;            /* I/O words: advance SUBELEMENT, not ELEMENT */
	enum df1_plc plc;       /* the command set: the call's PLC type */
};

/* Where element values go (reads) or come from (writes). */
enum io_kind { IO_RAW, IO_VALUE, IO_I16, IO_I32, IO_F32, IO_TCR, IO_STRING };

struct io {
	enum io_kind kind;
	enum df1_file_type t;   /* value type of one element: DF1_FT_N for single words */
	int word;               /* >= 0: only this 16-bit word of each wire element */
	size_t base;            /* index of the first element of the current span */
	enum value_float_order fo;
	void *out;
	const void *in;
	size_t cap;             /* IO_STRING: bytes at out */
	int len;                /* IO_STRING: length read */
};

/* ------------------------------------------------------------------------
 * Helpers: classification, address text, errors
 * ------------------------------------------------------------------------ */

static bool client_is_word_type(enum df1_file_type t)
{
	return t == DF1_FT_O || t == DF1_FT_I || t == DF1_FT_S || t == DF1_FT_B ||
	       t == DF1_FT_N || t == DF1_FT_A;
}

static bool client_is_tcr(enum df1_file_type t)
{
	return t == DF1_FT_T || t == DF1_FT_C || t == DF1_FT_R;
}

static void client_atext(const struct df1_addr *a, char *buf, size_t cap)
{
	if (df1_addr_format(a, buf, cap) < 0)
		snprintf(buf, cap, "%s%d:%d", df1_file_type_name(a->type), a->file, a->element);
}

/* The error detail names the address the error concerns. */
static void client_set_address(struct df1 *h, const char *what)
{
	snprintf(h->err.address, sizeof h->err.address, "%s", what ? what : "");
}

/* df1_fail() for address what: the message, and what in the detail's address. */
static int client_fail(struct df1 *h, int code, int station, const char *what, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));

static int client_fail(struct df1 *h, int code, int station, const char *what, const char *fmt, ...)
{
	char buf[sizeof h->err.message];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	df1_fail(h, code, station, "%s", buf);
	client_set_address(h, what);
	return code;
}

/* The link / df1_fail_remote recorded the failure: add the address to it. */
static int client_fail_at(struct df1 *h, int rc, int station, const char *what)
{
	if (h->err.code != rc)
		return client_fail(h, rc, station, what, "%s", df1_strerror(rc));
	client_set_address(h, what);
	if (h->err.station < 0)
		h->err.station = station;
	return rc;
}

/* A reply the link accepted whose content is wrong: DF1_E_BAD_REPLY, counted as an
 * invalid message (2550, seeds/004: "bad data, incorrect addressing"). */
static int client_bad_reply(struct df1 *h, int station, const char *what, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

static int client_bad_reply(struct df1 *h, int station, const char *what, const char *fmt, ...)
{
	char buf[sizeof h->err.message];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	df1_count(h, 2550);     /* CNT_INVALID_MSGS_RCVD */
	return client_fail(h, DF1_E_BAD_REPLY, station, what, "%s", buf);
}

static int client_check(struct df1 *h, int station)
{
	if (!h)
		return DF1_E_INVAL;
	if (station < 0 || station > 254)
		return df1_fail(h, DF1_E_INVAL, station, "station %d out of range 0-254", station);
	return 0;
}

/* A copy of a with other element / sub and no bit; a "$" text is rebuilt to match. */
static void client_derive(const struct df1_addr *a, int element, int sub, struct df1_addr *out)
{
	char buf[ATEXT_MAX];
	bool same = element == a->element && sub == a->sub && a->bit == DF1_ADDR_NONE;

	*out = *a;
	out->element = element;
	out->sub = sub;
	out->bit = DF1_ADDR_NONE;
	if (out->ascii[0] && !same) {
		out->ascii[0] = '\0';
		if (df1_addr_format(out, buf, sizeof buf) > 0 && strlen(buf) < sizeof out->ascii)
			memcpy(out->ascii, buf, strlen(buf) + 1);
	}
}

/* Address of element i of a span. */
static void span_at(const struct span *s, size_t i, struct df1_addr *out)
{
	if (s->by_sub)
		client_derive(&s->a, s->a.element, s->a.sub + (int)i, out);
	else
		client_derive(&s->a, s->a.element + (int)i, s->a.sub, out);
}

/* Data bytes per packet of a span's PLC type, for the SLC and PLC-2 commands. */
static size_t client_limit(const struct df1 *h, const struct span *s, bool write)
{
	return plc_packet_max(s->plc, write, h->cfg.max_packet);
}

/* ------------------------------------------------------------------------
 * One transaction
 * ------------------------------------------------------------------------ */

/* Send an app message, check the reply (CMD|40h, STS); data/dlen point into reply. */
static int client_transact(struct df1 *h, int station, const char *what, uint8_t *cmd, size_t clen,
                           uint8_t *reply, size_t rcap, const uint8_t **data, size_t *dlen)
{
	struct pccc_msg m;
	int rc;

	cmd[0] = (uint8_t)station;
	cmd[1] = (uint8_t)h->cfg.station;
	df1_clear_error(h);     /* so client_fail_at can tell whether the link recorded one */
	rc = link_transact(h, cmd, clen, reply, rcap);
	if (rc < 0)
		return client_fail_at(h, rc, station, what);
	rc = pccc_decode(reply, (size_t)rc, &m);
	if (rc < 0)
		return client_bad_reply(h, station, what, "malformed reply");
	if (m.cmd != (cmd[2] | PCCC_REPLY_BIT))
		return client_fail(h, DF1_E_BAD_FUNCTION, station, what, "reply CMD %02X to command %02X", m.cmd, cmd[2]);
	if (m.sts != 0) {
		rc = df1_fail_remote(h, station, m.sts, m.ext_sts, m.has_ext);
		return client_fail_at(h, rc < 0 ? rc : DF1_E_REMOTE, station, what);
	}
	*data = m.data;
	*dlen = m.len;
	return 0;
}

/* client_transact for an operation that has no address (echo, diagnostic
 * status, change mode): the message starts with the operation's name
 * ("echo: ...") and the detail's address stays empty. */
static int client_op_transact(struct df1 *h, int station, const char *op, uint8_t *cmd, size_t clen,
                              uint8_t *reply, size_t rcap, const uint8_t **data, size_t *dlen)
{
	int rc = client_transact(h, station, op, cmd, clen, reply, rcap, data, dlen);
	char *msg = h->err.message;
	size_t cap = sizeof h->err.message, ol = strlen(op), ml;

	if (rc >= 0 || strcmp(h->err.address, op) != 0)
		return rc;
	h->err.address[0] = '\0';
	ml = strnlen(msg, cap - 1);
	if (ol + 2 < cap) {
		if (ml > cap - 1 - ol - 2)
			ml = cap - 1 - ol - 2;
		memmove(msg + ol + 2, msg, ml);
		memcpy(msg, op, ol);
		msg[ol] = ':';
		msg[ol + 1] = ' ';
		msg[ol + 2 + ml] = '\0';
	}
	return rc;
}

/* ------------------------------------------------------------------------
 * Element sinks and sources
 * ------------------------------------------------------------------------ */

/* Element i (of the span) arrived: esize wire bytes at p. */
static int io_put(struct df1 *h, int station, const char *what, struct io *io, size_t i,
                  const uint8_t *p, size_t esize)
{
	int rc = 0;

	i += io->base;
	if (io->word >= 0) {
		p += 2 * (size_t)io->word;
		esize = 2;
	}
	switch (io->kind) {
	case IO_RAW:
		memcpy((uint8_t *)io->out + i * esize, p, esize);
		break;
	case IO_VALUE:
		rc = value_decode_element(io->t, p, esize, (struct df1_value *)io->out + i, io->fo);
		break;
	case IO_I16:
		((int16_t *)io->out)[i] = (int16_t)le16(p);
		break;
	case IO_I32:
		((int32_t *)io->out)[i] = (int32_t)le32(p);
		break;
	case IO_F32:
		((float *)io->out)[i] = value_get_float(p, io->fo);
		break;
	case IO_TCR: {
		struct df1_tcr *t = (struct df1_tcr *)io->out + i;

		t->ctl = le16(p);
		t->pre = (int16_t)le16(p + 2);
		t->acc = (int16_t)le16(p + 4);
		break;
	}
	case IO_STRING:
		rc = value_get_string(p, io->out, io->cap);
		if (rc >= 0)
			io->len = rc;
		break;
	}
	if (rc < 0) {
		if (rc == DF1_E_NOSPACE)
			return client_fail(h, rc, station, what, "string does not fit the buffer");
		return client_bad_reply(h, station, what, "element %zu cannot be decoded (%s)", i, df1_strerror(rc));
	}
	return 0;
}

/* Fill esize wire bytes at p with element i of the span. */
static int io_get(struct io *io, size_t i, uint8_t *p, size_t esize)
{
	i += io->base;
	switch (io->kind) {
	case IO_RAW:
		memcpy(p, (const uint8_t *)io->in + i * esize, esize);
		return 0;
	case IO_VALUE: {
		int rc = value_encode_element(io->t, (const struct df1_value *)io->in + i, p, esize, io->fo);

		return rc < 0 ? rc : 0;
	}
	case IO_I16:
		put_le16(p, (uint16_t)((const int16_t *)io->in)[i]);
		return 0;
	case IO_I32:
		put_le32(p, (uint32_t)((const int32_t *)io->in)[i]);
		return 0;
	case IO_F32:
		value_put_float(p, ((const float *)io->in)[i], io->fo);
		return 0;
	case IO_TCR: {
		const struct df1_tcr *t = (const struct df1_tcr *)io->in + i;

		put_le16(p, t->ctl);
		put_le16(p + 2, (uint16_t)t->pre);
		put_le16(p + 4, (uint16_t)t->acc);
		return 0;
	}
	case IO_STRING: {
		int rc = value_put_string(p, io->in);

		return rc < 0 ? rc : 0;
	}
	}
	return DF1_E_INVAL;
}

/* Fill out with elements first .. first+k-1 of the span for one write packet;
 * a value that does not encode fails naming its index. */
static int io_gather(struct df1 *h, int station, const char *what, struct io *io, size_t first,
                     size_t k, uint8_t *out, size_t esize)
{
	for (size_t i = 0; i < k; i++) {
		int rc = io_get(io, first + i, out + i * esize, esize);

		if (rc < 0)
			return client_fail(h, rc, station, what, "value %zu: %s", io->base + first + i,
			                df1_strerror(rc));
	}
	return 0;
}

/* ------------------------------------------------------------------------
 * SLC: 0F/A2, 0F/AA
 * ------------------------------------------------------------------------ */

static int slc_type_code(struct df1 *h, int station, const char *what, enum df1_file_type t)
{
	int code = df1_file_type_slc_code(t);

	if (code <= 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "file type has no SLC code");
	if (h->cfg.slc_io_82 && (t == DF1_FT_O || t == DF1_FT_I))
		code = t == DF1_FT_O ? 0x82 : 0x83;     /* F2E p.47 (spec 4.11) */
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

static int slc_read(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	size_t per, done = 0;
	int code = slc_begin(h, station, what, s, false, &per);

	if (code < 0)
		return code;
	while (done < s->count) {
		size_t k = s->count - done < per ? s->count - done : per;
		size_t want = k * s->esize, dlen;
		const uint8_t *d;
		unsigned elem, sub;
		int n, rc;

		slc_fields(s, done, &elem, &sub);
		n = pccc_enc_slc_read(cmd, sizeof cmd, &hd, PCCC_FNC_SLC_READ3, (uint8_t)want,
		                      (unsigned)s->a.file, (uint8_t)code, elem, sub);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the read (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
		if (dlen != want)
			return client_bad_reply(h, station, what, "reply has %zu data bytes, asked %zu", dlen, want);
		for (size_t i = 0; i < k; i++) {
			rc = io_put(h, station, what, io, done + i, d + i * s->esize, s->esize);
			if (rc < 0)
				return rc;
		}
		done += k;
	}
	return 0;
}

static int slc_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
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

/* ------------------------------------------------------------------------
 * PLC-5: 0F/68, 0F/67
 * ------------------------------------------------------------------------ */

/* Type/data element type for a span: single words are integers. */
static unsigned plc5_elem_type(const struct span *s)
{
	if (s->esize == 2)
		return PCCC_TD_INTEGER;
	switch (s->a.type) {
	case DF1_FT_F: return PCCC_TD_FLOAT;
	case DF1_FT_T: return PCCC_TD_TIMER;
	case DF1_FT_C: return PCCC_TD_COUNTER;
	case DF1_FT_R: return PCCC_TD_CONTROL;
	case DF1_FT_ST: return PCCC_TD_STRING;
	default: return PCCC_TD_INTEGER;        /* L */
	}
}

/* Does a reply's element type fit what was asked? */
static bool plc5_type_ok(const struct span *s, unsigned type_id)
{
	unsigned want = plc5_elem_type(s);

	if (want == PCCC_TD_INTEGER && s->esize == 2)
		return type_id == PCCC_TD_INTEGER || type_id == PCCC_TD_BITSTR || type_id == PCCC_TD_BCD;
	return type_id == want;
}

static int plc5_addr(struct df1 *h, int station, const char *what, const struct df1_addr *a,
                     uint8_t *out, size_t cap)
{
	int n = pccc_enc_plc5_addr(out, cap, a);

	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the PLC-5 address (%s)",
		                df1_strerror(n));
	return n;
}

/* Bytes of element data per typed packet. */
static size_t plc5_budget(const struct df1 *h, size_t alen, size_t overhead, size_t frame_room)
{
	size_t b;

	if (h->cfg.max_packet > 0)
		b = h->cfg.max_packet < PLC_PACKET_HARD_MAX ? (size_t)h->cfg.max_packet : PLC_PACKET_HARD_MAX;
	else
		b = PLC_PLC5_PACKET_MAX > alen + overhead ? PLC_PLC5_PACKET_MAX - alen - overhead : 0;
	return b < frame_room ? b : frame_room;
}

static int plc5_read(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], addr[DF1_ADDR_ASCII_MAX + 8];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	size_t rsize = client_is_tcr(s->a.type) && s->esize == 6 ? PLC_PLC5_TCR_READ : s->esize;
	size_t per, done = 0, budget;
	int alen = plc5_addr(h, station, what, &s->a, addr, sizeof addr);

	if (alen < 0)
		return alen;
	/* the reply: header, type/data and descriptor, data */
	budget = plc5_budget(h, (size_t)alen, PLC_PLC5_TD_MARGIN,
	                     FRAME_MAX_DATA - PCCC_HDR_LEN - PLC_PLC5_TD_MARGIN);
	per = budget / rsize;
	if (s->a.type == DF1_FT_ST && s->esize == 84)
		per = 1;        /* one string per packet: the reply is 3x LEN characters (RTA) */
	if (per == 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "a %zu-byte element exceeds the packet size", s->esize);
	while (done < s->count) {
		size_t k = s->count - done < per ? s->count - done : per, dlen;
		struct pccc_typed td;
		const uint8_t *d;
		int n, rc;

		n = pccc_enc_plc5_typed_read(cmd, sizeof cmd, &hd, (uint16_t)done, (uint16_t)s->count,
		                             addr, (size_t)alen, (uint16_t)k);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the read (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
		rc = pccc_dec_typed(d, dlen, &td);
		if (rc < 0)
			return client_bad_reply(h, station, what, "bad type/data parameter (%s)", df1_strerror(rc));
		if (!plc5_type_ok(s, td.type_id))
			return client_bad_reply(h, station, what, "reply holds type %u, asked type %u", td.type_id, plc5_elem_type(s));
		if (s->a.type == DF1_FT_ST && s->esize == 84 && td.elem_size != 84 && !td.is_array &&
		    k == 1 && td.elem_size <= DF1_STRING_MAX) {
			/* RTA's form of one string: 39 LEN characters -> the 84-byte element */
			uint8_t el[84];
			char text[DF1_STRING_MAX + 1];

			memcpy(text, td.data, td.elem_size);
			text[td.elem_size] = '\0';
			if (value_put_string(el, text) < 0)
				return client_bad_reply(h, station, what, "bad string reply");
			put_le16(el, (uint16_t)td.elem_size);
			rc = io_put(h, station, what, io, done, el, sizeof el);
			if (rc < 0)
				return rc;
			done += k;
			continue;
		}
		if (td.elem_size != s->esize)
			return client_bad_reply(h, station, what,
			                "reply elements have %u bytes, expected %zu",
			                (unsigned)td.elem_size, s->esize);
		if (td.count != k)
			return client_bad_reply(h, station, what, "reply has %zu elements, asked %zu", td.count, k);
		for (size_t i = 0; i < k; i++) {
			rc = io_put(h, station, what, io, done + i, td.data + i * s->esize, s->esize);
			if (rc < 0)
				return rc;
		}
		done += k;
	}
	return 0;
}

/* PLC-5 strings go one per packet as a string type/data parameter (3x LEN) and the
 * characters in text order, as RTA does (spec 5); PKT_OFFSET counts strings. */
static int plc5_write_strings(struct df1 *h, int station, const char *what, const struct span *s,
                              struct io *io, const uint8_t *addr, size_t alen)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], typed[FRAME_MAX_DATA], el[84];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };

	for (size_t i = 0; i < s->count; i++) {
		const uint8_t *d;
		size_t len, dlen;
		int n, rc;

		rc = io_get(io, i, el, sizeof el);
		if (rc < 0)
			return client_fail(h, rc, station, what, "value %zu: %s", io->base + i,
			                df1_strerror(rc));
		len = le16(el);
		n = pccc_enc_typedata(typed, sizeof typed, PCCC_TD_STRING, (uint32_t)len);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the type/data parameter");
		for (size_t c = 0; c < len; c++)
			typed[(size_t)n + c] = el[2 + (c ^ 1u)];
		n = pccc_enc_plc5_typed_write(cmd, sizeof cmd, &hd, (uint16_t)i, (uint16_t)s->count, addr,
		                              alen, typed, (size_t)n + len);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the write (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
	}
	return 0;
}

static int plc5_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], addr[DF1_ADDR_ASCII_MAX + 8];
	uint8_t typed[FRAME_MAX_DATA];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	unsigned etype = plc5_elem_type(s);
	size_t per, done = 0, budget, hlen;
	int alen = plc5_addr(h, station, what, &s->a, addr, sizeof addr);
	int r;

	if (alen < 0)
		return alen;
	if (s->a.type == DF1_FT_ST && s->esize == 84)
		return plc5_write_strings(h, station, what, s, io, addr, (size_t)alen);
	/* the array header for one element tells its length (99 09 LL + descriptor) */
	r = pccc_enc_typed_array(typed, sizeof typed, etype, (uint32_t)s->esize, 1);
	if (r < 0)
		return client_fail(h, r, station, what, "cannot encode the type/data parameter");
	hlen = (size_t)r;
	budget = plc5_budget(h, (size_t)alen, hlen,
	                     FRAME_MAX_DATA - PCCC_HDR_LEN - 5 - (size_t)alen - hlen);
	per = budget / s->esize;
	if (per == 0)
		return client_fail(h, DF1_E_NOTSUP, station, what, "a %zu-byte element exceeds the packet size", s->esize);
	while (done < s->count) {
		size_t k = s->count - done < per ? s->count - done : per, dlen;
		const uint8_t *d;
		int n, rc;

		r = pccc_enc_typed_array(typed, sizeof typed, etype, (uint32_t)s->esize, k);
		if (r < 0 || (size_t)r != hlen)
			return client_fail(h, DF1_E_NOTSUP, station, what, "cannot encode the type/data parameter");
		rc = io_gather(h, station, what, io, done, k, typed + hlen, s->esize);
		if (rc < 0)
			return rc;
		n = pccc_enc_plc5_typed_write(cmd, sizeof cmd, &hd, (uint16_t)done, (uint16_t)s->count,
		                              addr, (size_t)alen, typed, hlen + k * s->esize);
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the write (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
		done += k;
	}
	return 0;
}

/* ------------------------------------------------------------------------
 * PLC-2: 01, 08 (byte address = 2 * element)
 * ------------------------------------------------------------------------ */

static int plc2_check(struct df1 *h, int station, const char *what, const struct span *s)
{
	if (!client_is_word_type(s->a.type) || s->esize != 2 || s->by_sub)
		return client_fail(h, DF1_E_NOTSUP, station, what,
		                "PLC-2 commands reach 16-bit words only (N B S I O A, no sub-element)");
	if (((size_t)s->a.element + s->count) * 2 > 0x10000)
		return client_fail(h, DF1_E_ADDR_RANGE, station, what, "beyond the PLC-2 byte address range");
	return 0;
}

static int plc2_read(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	size_t per = client_limit(h, s, false) / 2, done = 0;
	int rc = plc2_check(h, station, what, s);

	if (rc < 0)
		return rc;
	while (done < s->count) {
		size_t k = s->count - done < per ? s->count - done : per, dlen;
		const uint8_t *d;
		int n;

		n = pccc_enc_plc2_read(cmd, sizeof cmd, &hd, (uint16_t)((s->a.element + done) * 2),
		                       (uint8_t)(k * 2));
		if (n < 0)
			return client_fail(h, n, station, what, "cannot encode the read (%s)", df1_strerror(n));
		rc = client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
		if (rc < 0)
			return rc;
		if (dlen != k * 2)
			return client_bad_reply(h, station, what, "reply has %zu data bytes, asked %zu", dlen, k * 2);
		for (size_t i = 0; i < k; i++) {
			rc = io_put(h, station, what, io, done + i, d + i * 2, 2);
			if (rc < 0)
				return rc;
		}
		done += k;
	}
	return 0;
}

static int plc2_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
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
		n = pccc_enc_plc2_write(cmd, sizeof cmd, &hd, (uint16_t)((s->a.element + done) * 2),
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

/* ------------------------------------------------------------------------
 * Spans: dispatch by PLC type
 * ------------------------------------------------------------------------ */

static int span_check(struct df1 *h, int station, const char *what, const struct span *s)
{
	size_t last = (s->by_sub ? (size_t)s->a.sub : (size_t)s->a.element) + s->count - 1;

	if (s->count == 0 || s->count > 0xFFFF || last > 0xFFFF)
		return client_fail(h, DF1_E_ADDR_RANGE, station, what, "%zu elements go beyond the address range", s->count);
	return 0;
}

static int span_read(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	int rc = span_check(h, station, what, s);

	if (rc < 0)
		return rc;
	switch (s->plc) {
	case DF1_PLC_PLC5:
		return plc5_read(h, station, what, s, io);
	case DF1_PLC_PLC2:
		return plc2_read(h, station, what, s, io);
	default:
		return slc_read(h, station, what, s, io);
	}
}

static int span_write(struct df1 *h, int station, const char *what, const struct span *s, struct io *io)
{
	int rc = span_check(h, station, what, s);

	if (rc < 0)
		return rc;
	switch (s->plc) {
	case DF1_PLC_PLC5:
		return plc5_write(h, station, what, s, io);
	case DF1_PLC_PLC2:
		return plc2_write(h, station, what, s, io);
	default:
		return slc_write(h, station, what, s, io);
	}
}

/* ------------------------------------------------------------------------
 * Bits
 * ------------------------------------------------------------------------ */

/* The words that hold a run of bits: span of 16-bit (32 for L) words, first bit. */
static int bits_span(struct df1 *h, int station, const char *what, enum df1_plc plc,
                     const struct df1_addr *a, size_t n, struct span *s, unsigned *wbits)
{
	size_t bit = (size_t)a->bit;

	memset(s, 0, sizeof *s);
	s->plc = plc;
	if (a->type == DF1_FT_L) {
		*wbits = 32;
		s->esize = 4;
	} else if (client_is_word_type(a->type) || client_is_tcr(a->type)) {
		*wbits = 16;
		s->esize = 2;
	} else {
		return client_fail(h, DF1_E_TYPE, station, what, "no bits in this file type");
	}
	if (client_is_tcr(a->type)) {
		/* a T/C/R bit lives in one word of its element (word 0 unless given) */
		if (bit + n > 16)
			return client_fail(h, DF1_E_ADDR_RANGE, station, what, "%zu bits run past the word", n);
		client_derive(a, a->element, a->sub == DF1_ADDR_NONE ? 0 : a->sub, &s->a);
		s->count = 1;
		return 0;
	}
	s->by_sub = a->sub != DF1_ADDR_NONE;    /* I1:0.1/3: words of the slot */
	client_derive(a, a->element, a->sub, &s->a);
	s->count = (bit + n - 1) / *wbits + 1;
	return 0;
}

/* Bit sink: the words arrive through io_put as raw bytes; bits are picked afterwards. */
static int client_read_bits(struct df1 *h, int station, const char *what, enum df1_plc plc,
                            const struct df1_addr *a, size_t n, bool *bits, struct df1_value *vals)
{
	uint8_t words[FRAME_MAX_DATA];
	struct span s;
	struct io io = { .kind = IO_RAW, .t = DF1_FT_N, .word = -1, .fo = VALUE_FLOAT_LE };
	unsigned wbits;
	size_t first = (size_t)a->bit, done = 0;
	int rc = bits_span(h, station, what, plc, a, n, &s, &wbits);

	if (rc < 0)
		return rc;
	/* read the words in chunks that fit the stack buffer */
	while (done < s.count) {
		struct span c = s;
		size_t per = sizeof words / s.esize;

		c.count = s.count - done < per ? s.count - done : per;
		span_at(&s, done, &c.a);
		io.out = words;
		rc = span_read(h, station, what, &c, &io);
		if (rc < 0)
			return rc;
		/* g: bit number from bit 0 of the span's first word */
		for (size_t g = done * wbits; g < (done + c.count) * wbits; g++) {
			bool on;

			if (g < first || g >= first + n)
				continue;
			on = value_get_bit(words, s.esize, g - done * wbits);
			if (bits)
				bits[g - first] = on;
			if (vals) {
				memset(&vals[g - first], 0, sizeof vals[0]);
				vals[g - first].kind = DF1_VAL_BIT;
				vals[g - first].v.bit = on;
			}
		}
		done += c.count;
	}
	return (int)n;
}

/* PLC-2 05 unprotected bit write: {ADDR(2) SET(1) RESET(1)} per byte. */
static int plc2_bit_write(struct df1 *h, int station, const char *what, const struct df1_addr *w,
                          uint16_t mask, uint16_t data)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA];
	const uint8_t *d;
	size_t n = PCCC_HDR_LEN, dlen;

	if (!client_is_word_type(w->type) || w->sub != DF1_ADDR_NONE)
		return client_fail(h, DF1_E_NOTSUP, station, what,
		                "PLC-2 commands reach 16-bit words only (N B S I O A)");
	if (w->element > 0x7FFF)
		return client_fail(h, DF1_E_ADDR_RANGE, station, what, "beyond the PLC-2 byte address range");
	memset(cmd, 0, PCCC_HDR_LEN);
	cmd[2] = PCCC_CMD_UNPROT_BIT_WRITE;
	for (unsigned b = 0; b < 2; b++) {
		uint8_t m = (uint8_t)(mask >> (8 * b)), v = (uint8_t)(data >> (8 * b));

		if (!m)
			continue;
		put_le16(cmd + n, (uint16_t)(w->element * 2 + (int)b));
		cmd[n + 2] = (uint8_t)(v & m);          /* SET */
		cmd[n + 3] = (uint8_t)(m & (uint8_t)~v); /* RESET */
		n += 4;
	}
	return client_transact(h, station, what, cmd, n, reply, sizeof reply, &d, &dlen);
}

/* Change the bits of mask in word w to those of data; the other bits stay. */
static int client_mask_word(struct df1 *h, int station, const char *what, enum df1_plc plc,
                            const struct df1_addr *w, size_t wsize, uint32_t mask, uint32_t data)
{
	uint8_t cmd[FRAME_MAX_DATA], reply[FRAME_MAX_DATA], addr[DF1_ADDR_ASCII_MAX + 8];
	struct pccc_hdr hd = { (uint8_t)station, (uint8_t)h->cfg.station, 0 };
	const uint8_t *d;
	size_t dlen;
	int n, alen, code;

	data &= mask;
	switch (plc) {
	case DF1_PLC_PLC5:
		if (wsize != 2)
			return client_fail(h, DF1_E_NOTSUP, station, what, "PLC-5 bit writes reach 16-bit words");
		alen = plc5_addr(h, station, what, w, addr, sizeof addr);
		if (alen < 0)
			return alen;
		/* new = (old AND and) OR or: set AND FFFF OR bit, clear AND ~bit OR 0 */
		n = pccc_enc_plc5_rmw(cmd, sizeof cmd, &hd, addr, (size_t)alen,
		                      (uint16_t)(~mask | data), (uint16_t)data);
		break;
	case DF1_PLC_PLC2:
		return plc2_bit_write(h, station, what, w, (uint16_t)mask, (uint16_t)data);
	default: {
		uint8_t m[4], v[4];

		code = slc_type_code(h, station, what, w->type);
		if (code < 0)
			return code;
		put_le32(m, mask);
		put_le32(v, data);
		n = pccc_enc_slc_masked_write(cmd, sizeof cmd, &hd, (unsigned)w->file, (uint8_t)code,
		                              (unsigned)w->element,
		                              w->sub == DF1_ADDR_NONE ? 0u : (unsigned)w->sub, m, v,
		                              (uint8_t)wsize);
		break;
	}
	}
	if (n < 0)
		return client_fail(h, n, station, what, "cannot encode the bit write (%s)", df1_strerror(n));
	return client_transact(h, station, what, cmd, (size_t)n, reply, sizeof reply, &d, &dlen);
}

/* Write n bits from bits[] or vals[] (kind BIT), one masked write per word touched. */
static int client_write_bits(struct df1 *h, int station, const char *what, enum df1_plc plc,
                             const struct df1_addr *a, size_t n, const bool *bits, const struct df1_value *vals)
{
	struct span s;
	unsigned wbits;
	size_t first = (size_t)a->bit;
	int rc = bits_span(h, station, what, plc, a, n, &s, &wbits);

	if (rc < 0)
		return rc;
	if (vals)
		for (size_t i = 0; i < n; i++)
			if (vals[i].kind != DF1_VAL_BIT)
				return client_fail(h, DF1_E_TYPE, station, what, "value %zu is not a bit", i);
	rc = span_check(h, station, what, &s);
	if (rc < 0)
		return rc;
	for (size_t w = 0; w < s.count; w++) {
		struct df1_addr wa;
		uint32_t mask = 0, data = 0;

		for (size_t b = 0; b < wbits; b++) {
			size_t g = w * wbits + b;
			bool on;

			if (g < first || g >= first + n)
				continue;
			on = bits ? bits[g - first] : vals[g - first].v.bit;
			value_mask_bit(&mask, &data, (unsigned)b, on);
		}
		span_at(&s, w, &wa);
		rc = client_mask_word(h, station, what, plc, &wa, s.esize, mask, data);
		if (rc < 0)
			return rc;
	}
	return (int)n;
}

/* ------------------------------------------------------------------------
 * Reads and writes of element values (not bits)
 * ------------------------------------------------------------------------ */

/* The span for n elements at a, and how io picks values; a has no bit. */
static int client_plan(struct df1 *h, int station, const char *what, enum df1_plc plc,
                       const struct df1_addr *a, size_t n, bool write, struct span *s, struct io *io, bool *per_element)
{
	int es = df1_file_type_element_size(a->type);

	memset(s, 0, sizeof *s);
	s->plc = plc;
	*per_element = false;
	io->word = -1;
	io->t = a->type;
	io->fo = value_typed_float_order(plc, h->cfg.plc5_float_swapped);
	if (es <= 0)
		return client_fail(h, DF1_E_ADDR_SYNTAX, station, what, "no file type");
	s->count = n;
	if (a->sub == DF1_ADDR_NONE) {
		client_derive(a, a->element, DF1_ADDR_NONE, &s->a);
		s->esize = (size_t)es;
		return 0;
	}
	io->t = DF1_FT_N;       /* one 16-bit word per element */
	if (client_is_tcr(a->type)) {
		if (n == 1 || write) {
			/* that word of each element: one element per command */
			client_derive(a, a->element, a->sub, &s->a);
			s->esize = 2;
			s->count = 1;
			*per_element = n > 1;
			return 0;
		}
		/* reads of several: whole elements, keep the one word */
		client_derive(a, a->element, DF1_ADDR_NONE, &s->a);
		s->esize = (size_t)es;
		io->word = a->sub;
		return 0;
	}
	if (client_is_word_type(a->type)) {
		client_derive(a, a->element, a->sub, &s->a);
		s->esize = 2;
		s->by_sub = true;
		return 0;
	}
	return client_fail(h, DF1_E_ADDR_SYNTAX, station, what, "no sub-elements in this file type");
}

static int client_read_elems(struct df1 *h, int station, const char *what, enum df1_plc plc,
                             const struct df1_addr *a, size_t n, struct io *io)
{
	struct span s;
	bool per_element;
	int rc = client_plan(h, station, what, plc, a, n, false, &s, io, &per_element);

	if (rc < 0)
		return rc;
	io->base = 0;
	rc = span_read(h, station, what, &s, io);
	return rc < 0 ? rc : (int)n;
}

/* Check every value before anything is sent. */
static int client_check_values(struct df1 *h, int station, const char *what, struct io *io, size_t n,
                               size_t esize)
{
	uint8_t scratch[84];

	if (io->kind != IO_VALUE && io->kind != IO_STRING)
		return 0;
	if (esize > sizeof scratch)
		return client_fail(h, DF1_E_INVAL, station, what, "element too large");
	for (size_t i = 0; i < n; i++) {
		int rc;

		io->base = 0;
		rc = io_get(io, i, scratch, esize);
		if (rc < 0)
			return client_fail(h, rc, station, what, "value %zu: %s", i, df1_strerror(rc));
	}
	return 0;
}

static int client_write_elems(struct df1 *h, int station, const char *what, enum df1_plc plc,
                              const struct df1_addr *a, size_t n, struct io *io)
{
	struct span s;
	bool per_element;
	int rc = client_plan(h, station, what, plc, a, n, true, &s, io, &per_element);

	if (rc < 0)
		return rc;
	rc = client_check_values(h, station, what, io, n, s.esize);
	if (rc < 0)
		return rc;
	if (!per_element) {
		io->base = 0;
		rc = span_write(h, station, what, &s, io);
		return rc < 0 ? rc : (int)n;
	}
	for (size_t i = 0; i < n; i++) {
		struct span one = s;

		client_derive(a, a->element + (int)i, a->sub, &one.a);
		io->base = i;
		rc = span_write(h, station, what, &one, io);
		if (rc < 0)
			return rc;
	}
	return (int)n;
}

/* ------------------------------------------------------------------------
 * Public API
 * ------------------------------------------------------------------------ */

/* Parse addr for an API call; records the error on failure. */
static int client_parse(struct df1 *h, int station, const char *text, struct df1_addr *a)
{
	int rc;

	if (!text)
		return df1_fail(h, DF1_E_INVAL, station, "no address");
	rc = df1_addr_parse(text, a);
	if (rc < 0)
		return client_fail(h, rc, station, text, "%s", df1_strerror(rc));
	return 0;
}

/* Common start of a call with an address text: station check, parse, the
 * address's text for messages in what. */
static int client_begin(struct df1 *h, int station, const char *text, struct df1_addr *a,
                        char *what, size_t wcap)
{
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	rc = client_parse(h, station, text, a);
	if (rc < 0)
		return rc;
	client_atext(a, what, wcap);
	return 0;
}

static int client_count_check(struct df1 *h, int station, const char *what, const void *p, size_t n)
{
	if (!p || n == 0)
		return client_fail(h, DF1_E_INVAL, station, what, "no values");
	if (n > 0xFFFF)
		return client_fail(h, DF1_E_INVAL, station, what, "%zu elements is too many", n);
	return 0;
}

/* Common start of df1_read_addr / df1_write_addr: checks, and the address's
 * text for messages in what. */
static int client_addr_begin(struct df1 *h, int station, const struct df1_addr *a, const void *p,
                             size_t n, char *what, size_t wcap)
{
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	if (!a)
		return df1_fail(h, DF1_E_INVAL, station, "no address");
	client_atext(a, what, wcap);
	return client_count_check(h, station, what, p, n);
}

int client_read_at(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                   struct df1_value *out, size_t n)
{
	char what[ATEXT_MAX];
	struct io io = { .kind = IO_VALUE, .out = out };
	int rc = client_addr_begin(h, station, a, out, n, what, sizeof what);

	if (rc < 0)
		return rc;
	if (a->bit != DF1_ADDR_NONE)
		return client_read_bits(h, station, what, plc, a, n, NULL, out);
	return client_read_elems(h, station, what, plc, a, n, &io);
}

int client_write_at(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                    const struct df1_value *in, size_t n)
{
	char what[ATEXT_MAX];
	struct io io = { .kind = IO_VALUE, .in = in };
	int rc = client_addr_begin(h, station, a, in, n, what, sizeof what);

	if (rc < 0)
		return rc;
	if (a->bit != DF1_ADDR_NONE)
		return client_write_bits(h, station, what, plc, a, n, NULL, in);
	return client_write_elems(h, station, what, plc, a, n, &io);
}

int df1_read_addr(df1_t *h, int station, const struct df1_addr *a, struct df1_value *out, size_t n)
{
	return client_read_at(h, station, h ? h->cfg.plc : DF1_PLC_SLC, a, out, n);
}

int df1_write_addr(df1_t *h, int station, const struct df1_addr *a, const struct df1_value *in, size_t n)
{
	return client_write_at(h, station, h ? h->cfg.plc : DF1_PLC_SLC, a, in, n);
}

int df1_read(df1_t *h, int station, const char *addr, struct df1_value *out, size_t n)
{
	struct df1_addr a;
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	rc = client_parse(h, station, addr, &a);
	return rc < 0 ? rc : df1_read_addr(h, station, &a, out, n);
}

int df1_write(df1_t *h, int station, const char *addr, const struct df1_value *in, size_t n)
{
	struct df1_addr a;
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	rc = client_parse(h, station, addr, &a);
	return rc < 0 ? rc : df1_write_addr(h, station, &a, in, n);
}

/* Typed helpers: which addresses hold which C type. */
enum client_ctype { CT_I16, CT_I32, CT_F32, CT_TCR, CT_STRING };

static bool client_type_fits(const struct df1_addr *a, enum client_ctype ct)
{
	if (a->bit != DF1_ADDR_NONE)
		return false;
	switch (ct) {
	case CT_I16:
		return client_is_word_type(a->type) || (client_is_tcr(a->type) && a->sub != DF1_ADDR_NONE);
	case CT_I32:
		return a->type == DF1_FT_L;
	case CT_F32:
		return a->type == DF1_FT_F;
	case CT_TCR:
		return client_is_tcr(a->type) && a->sub == DF1_ADDR_NONE;
	case CT_STRING:
		return a->type == DF1_FT_ST;
	}
	return false;
}

static const char *const client_ctype_names[] = {
	[CT_I16] = "16-bit integer", [CT_I32] = "32-bit integer", [CT_F32] = "float",
	[CT_TCR] = "timer/counter/control element", [CT_STRING] = "string",
};

static const enum io_kind client_ctype_io[] = {
	[CT_I16] = IO_I16, [CT_I32] = IO_I32, [CT_F32] = IO_F32, [CT_TCR] = IO_TCR, [CT_STRING] = IO_STRING,
};

/* Common start of the typed helpers: check, parse, type check. */
static int client_typed(struct df1 *h, int station, const char *addr, enum client_ctype ct,
                        const void *p, size_t n, struct df1_addr *a, char *what, size_t wcap)
{
	int rc = client_begin(h, station, addr, a, what, wcap);

	if (rc < 0)
		return rc;
	rc = client_count_check(h, station, what, p, n);
	if (rc < 0)
		return rc;
	if (!client_type_fits(a, ct))
		return client_fail(h, DF1_E_TYPE, station, what, "does not hold a %s",
		                client_ctype_names[ct]);
	return 0;
}

static int client_typed_read(df1_t *h, int station, const char *addr, enum client_ctype ct,
                             void *out, size_t n)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	struct io io = { .kind = client_ctype_io[ct], .out = out };
	int rc = client_typed(h, station, addr, ct, out, n, &a, what, sizeof what);

	return rc < 0 ? rc : client_read_elems(h, station, what, h->cfg.plc, &a, n, &io);
}

static int client_typed_write(df1_t *h, int station, const char *addr, enum client_ctype ct,
                              const void *in, size_t n)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	struct io io = { .kind = client_ctype_io[ct], .in = in };
	int rc = client_typed(h, station, addr, ct, in, n, &a, what, sizeof what);

	return rc < 0 ? rc : client_write_elems(h, station, what, h->cfg.plc, &a, n, &io);
}

int df1_read_int16(df1_t *h, int station, const char *addr, int16_t *out, size_t n)
{
	return client_typed_read(h, station, addr, CT_I16, out, n);
}

int df1_read_int32(df1_t *h, int station, const char *addr, int32_t *out, size_t n)
{
	return client_typed_read(h, station, addr, CT_I32, out, n);
}

int df1_read_float(df1_t *h, int station, const char *addr, float *out, size_t n)
{
	return client_typed_read(h, station, addr, CT_F32, out, n);
}

int df1_read_tcr(df1_t *h, int station, const char *addr, struct df1_tcr *out, size_t n)
{
	return client_typed_read(h, station, addr, CT_TCR, out, n);
}

int df1_write_int16(df1_t *h, int station, const char *addr, const int16_t *in, size_t n)
{
	return client_typed_write(h, station, addr, CT_I16, in, n);
}

int df1_write_int32(df1_t *h, int station, const char *addr, const int32_t *in, size_t n)
{
	return client_typed_write(h, station, addr, CT_I32, in, n);
}

int df1_write_float(df1_t *h, int station, const char *addr, const float *in, size_t n)
{
	return client_typed_write(h, station, addr, CT_F32, in, n);
}

int df1_write_tcr(df1_t *h, int station, const char *addr, const struct df1_tcr *in, size_t n)
{
	return client_typed_write(h, station, addr, CT_TCR, in, n);
}

/* One string element; returns its length. */
int df1_read_string(df1_t *h, int station, const char *addr, char *out, size_t cap)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	struct io io = { .kind = IO_STRING, .out = out, .cap = cap };
	int rc = client_typed(h, station, addr, CT_STRING, out, cap ? 1 : 0, &a, what, sizeof what);

	if (rc < 0)
		return rc;
	rc = client_read_elems(h, station, what, h->cfg.plc, &a, 1, &io);
	return rc < 0 ? rc : io.len;
}

/* One string element; returns its length. */
int df1_write_string(df1_t *h, int station, const char *addr, const char *text)
{
	int rc = client_typed_write(h, station, addr, CT_STRING, text, 1);

	return rc < 0 ? rc : (int)strlen(text);
}

static int client_bit_addr(df1_t *h, int station, const char *addr, struct df1_addr *a, char *what,
                           size_t wcap)
{
	int rc = client_begin(h, station, addr, a, what, wcap);

	if (rc < 0)
		return rc;
	if (a->bit == DF1_ADDR_NONE)
		return client_fail(h, DF1_E_TYPE, station, what, "not a bit address");
	return 0;
}

int df1_read_bit(df1_t *h, int station, const char *addr, bool *out)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	int rc = client_bit_addr(h, station, addr, &a, what, sizeof what);

	if (rc < 0)
		return rc;
	if (!out)
		return client_fail(h, DF1_E_INVAL, station, what, "no output");
	rc = client_read_bits(h, station, what, h->cfg.plc, &a, 1, out, NULL);
	return rc < 0 ? rc : 0;
}

int df1_write_bit(df1_t *h, int station, const char *addr, bool value)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	int rc = client_bit_addr(h, station, addr, &a, what, sizeof what);

	if (rc < 0)
		return rc;
	rc = client_write_bits(h, station, what, h->cfg.plc, &a, 1, &value, NULL);
	return rc < 0 ? rc : 0;
}

/* Raw: nbytes = whole elements as on the wire (2 bytes per element for a sub-element). */
static int client_raw_parsed(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *ap,
                             const char *what, const uint8_t *in, uint8_t *out, size_t nbytes)
{
	struct df1_addr a = *ap;
	struct io io = { .kind = IO_RAW, .in = in, .out = out };
	size_t esize;
	int rc;

	if (a.bit != DF1_ADDR_NONE)
		return client_fail(h, DF1_E_TYPE, station, what, "raw access takes a word or element address");
	esize = a.sub != DF1_ADDR_NONE ? 2 : (size_t)df1_file_type_element_size(a.type);
	if ((!in && !out) || nbytes == 0 || nbytes % esize)
		return client_fail(h, DF1_E_INVAL, station, what, "%zu bytes is not a whole number of %zu-byte "
		                "elements", nbytes, esize);
	rc = client_count_check(h, station, what, what, nbytes / esize);
	if (rc < 0)
		return rc;
	if (in)
		rc = client_write_elems(h, station, what, plc, &a, nbytes / esize, &io);
	else
		rc = client_read_elems(h, station, what, plc, &a, nbytes / esize, &io);
	return rc < 0 ? rc : (int)nbytes;
}

static int client_raw(df1_t *h, int station, const char *addr, const uint8_t *in, uint8_t *out,
                      size_t nbytes)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	int rc = client_begin(h, station, addr, &a, what, sizeof what);

	if (rc < 0)
		return rc;
	return client_raw_parsed(h, station, h->cfg.plc, &a, what, in, out, nbytes);
}

int client_read_raw_at(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                       uint8_t *buf, size_t nbytes)
{
	char what[ATEXT_MAX];
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	if (!a)
		return df1_fail(h, DF1_E_INVAL, station, "no address");
	client_atext(a, what, sizeof what);
	return client_raw_parsed(h, station, plc, a, what, NULL, buf, nbytes);
}

int df1_read_raw(df1_t *h, int station, const char *addr, uint8_t *buf, size_t nbytes)
{
	return client_raw(h, station, addr, NULL, buf, nbytes);
}

int df1_write_raw(df1_t *h, int station, const char *addr, const uint8_t *buf, size_t nbytes)
{
	return client_raw(h, station, addr, buf, NULL, nbytes);
}

/* ------------------------------------------------------------------------
 * Commands and diagnostics
 * ------------------------------------------------------------------------ */

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
 * 6 run, 7 test continuous, 8 test single scan; spec 4.8 [UNCERTAIN] for 7/8).
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
