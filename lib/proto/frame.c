/* SPDX-License-Identifier: MPL-2.0 */
/*
 * frame - DF1 link-layer framing (doc/PROTOCOL.md 1-2). Pure: no I/O, no
 * clock, no allocation, no mutable globals. The decoder rules the spec leaves
 * open are listed in frame.h.
 */
#include "proto/frame.h"

#include <string.h>

/* CRC-16/ARC table: entry i = i shifted out LSB-first through A001h (doc/PROTOCOL.md 1.5). */
static const uint16_t crc_table[256] = {
	0x0000, 0xC0C1, 0xC181, 0x0140, 0xC301, 0x03C0, 0x0280, 0xC241,
	0xC601, 0x06C0, 0x0780, 0xC741, 0x0500, 0xC5C1, 0xC481, 0x0440,
	0xCC01, 0x0CC0, 0x0D80, 0xCD41, 0x0F00, 0xCFC1, 0xCE81, 0x0E40,
	0x0A00, 0xCAC1, 0xCB81, 0x0B40, 0xC901, 0x09C0, 0x0880, 0xC841,
	0xD801, 0x18C0, 0x1980, 0xD941, 0x1B00, 0xDBC1, 0xDA81, 0x1A40,
	0x1E00, 0xDEC1, 0xDF81, 0x1F40, 0xDD01, 0x1DC0, 0x1C80, 0xDC41,
	0x1400, 0xD4C1, 0xD581, 0x1540, 0xD701, 0x17C0, 0x1680, 0xD641,
	0xD201, 0x12C0, 0x1380, 0xD341, 0x1100, 0xD1C1, 0xD081, 0x1040,
	0xF001, 0x30C0, 0x3180, 0xF141, 0x3300, 0xF3C1, 0xF281, 0x3240,
	0x3600, 0xF6C1, 0xF781, 0x3740, 0xF501, 0x35C0, 0x3480, 0xF441,
	0x3C00, 0xFCC1, 0xFD81, 0x3D40, 0xFF01, 0x3FC0, 0x3E80, 0xFE41,
	0xFA01, 0x3AC0, 0x3B80, 0xFB41, 0x3900, 0xF9C1, 0xF881, 0x3840,
	0x2800, 0xE8C1, 0xE981, 0x2940, 0xEB01, 0x2BC0, 0x2A80, 0xEA41,
	0xEE01, 0x2EC0, 0x2F80, 0xEF41, 0x2D00, 0xEDC1, 0xEC81, 0x2C40,
	0xE401, 0x24C0, 0x2580, 0xE541, 0x2700, 0xE7C1, 0xE681, 0x2640,
	0x2200, 0xE2C1, 0xE381, 0x2340, 0xE101, 0x21C0, 0x2080, 0xE041,
	0xA001, 0x60C0, 0x6180, 0xA141, 0x6300, 0xA3C1, 0xA281, 0x6240,
	0x6600, 0xA6C1, 0xA781, 0x6740, 0xA501, 0x65C0, 0x6480, 0xA441,
	0x6C00, 0xACC1, 0xAD81, 0x6D40, 0xAF01, 0x6FC0, 0x6E80, 0xAE41,
	0xAA01, 0x6AC0, 0x6B80, 0xAB41, 0x6900, 0xA9C1, 0xA881, 0x6840,
	0x7800, 0xB8C1, 0xB981, 0x7940, 0xBB01, 0x7BC0, 0x7A80, 0xBA41,
	0xBE01, 0x7EC0, 0x7F80, 0xBF41, 0x7D00, 0xBDC1, 0xBC81, 0x7C40,
	0xB401, 0x74C0, 0x7580, 0xB541, 0x7700, 0xB7C1, 0xB681, 0x7640,
	0x7200, 0xB2C1, 0xB381, 0x7340, 0xB101, 0x71C0, 0x7080, 0xB041,
	0x5000, 0x90C1, 0x9181, 0x5140, 0x9301, 0x53C0, 0x5280, 0x9241,
	0x9601, 0x56C0, 0x5780, 0x9741, 0x5500, 0x95C1, 0x9481, 0x5440,
	0x9C01, 0x5CC0, 0x5D80, 0x9D41, 0x5F00, 0x9FC1, 0x9E81, 0x5E40,
	0x5A00, 0x9AC1, 0x9B81, 0x5B40, 0x9901, 0x59C0, 0x5880, 0x9841,
	0x8801, 0x48C0, 0x4980, 0x8941, 0x4B00, 0x8BC1, 0x8A81, 0x4A40,
	0x4E00, 0x8EC1, 0x8F81, 0x4F40, 0x8D01, 0x4DC0, 0x4C80, 0x8C41,
	0x4400, 0x84C1, 0x8581, 0x4540, 0x8701, 0x47C0, 0x4680, 0x8641,
	0x8201, 0x42C0, 0x4380, 0x8341, 0x4100, 0x81C1, 0x8081, 0x4040,
};

static uint16_t crc_step(uint16_t crc, uint8_t b)
{
	return (uint16_t)((crc >> 8) ^ crc_table[(crc ^ b) & 0xFF]);
}

uint8_t frame_bcc(const uint8_t *data, size_t n)
{
	uint8_t sum = 0;

	for (size_t i = 0; i < n; i++)
		sum = (uint8_t)(sum + data[i]);
	return (uint8_t)(0u - sum);
}

uint16_t frame_crc16(uint16_t crc, const uint8_t *data, size_t n)
{
	for (size_t i = 0; i < n; i++)
		crc = crc_step(crc, data[i]);
	return crc;
}

/* ------------------------------------------------------------------------
 * Encoders
 * ------------------------------------------------------------------------ */

struct writer {
	uint8_t *out;
	size_t cap, pos;
	bool full;
};

static void put(struct writer *w, uint8_t b)
{
	if (w->pos < w->cap)
		w->out[w->pos++] = b;
	else
		w->full = true;
}

/* A data (or STN) byte: 10h goes out as DLE DLE. */
static void put_stuffed(struct writer *w, uint8_t b)
{
	if (b == DF1_DLE)
		put(w, DF1_DLE);
	put(w, b);
}

static size_t writer_done(const struct writer *w)
{
	return w->full ? 0 : w->pos;
}

static bool check_valid(enum df1_check check)
{
	return check == DF1_CHECK_CRC || check == DF1_CHECK_BCC;
}

/* Data, DLE ETX and the check. sum/crc already hold what precedes the data. */
static void put_body(struct writer *w, enum df1_check check, uint8_t sum, uint16_t crc,
                     const uint8_t *app, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		put_stuffed(w, app[i]);
		sum = (uint8_t)(sum + app[i]);
		crc = crc_step(crc, app[i]);
	}
	put(w, DF1_DLE);
	put(w, DF1_ETX);
	if (check == DF1_CHECK_BCC) {
		put(w, (uint8_t)(0u - sum));
	} else {
		crc = crc_step(crc, DF1_ETX);
		put(w, (uint8_t)(crc & 0xFF)); /* low byte first (doc/PROTOCOL.md 1.5) */
		put(w, (uint8_t)(crc >> 8));
	}
}

size_t frame_encode_full(enum df1_check check, const uint8_t *app, size_t n, uint8_t *out, size_t cap)
{
	struct writer w = { out, cap, 0, false };

	if (!out || (!app && n) || !check_valid(check))
		return 0;
	put(&w, DF1_DLE);
	put(&w, DF1_STX);
	put_body(&w, check, 0, 0, app, n);
	return writer_done(&w);
}

size_t frame_encode_master(enum df1_check check, uint8_t stn, bool bcc_includes_stx,
                           const uint8_t *app, size_t n, uint8_t *out, size_t cap)
{
	struct writer w = { out, cap, 0, false };
	uint8_t sum = stn;
	uint16_t crc;

	if (!out || (!app && n) || !check_valid(check))
		return 0;
	put(&w, DF1_DLE);
	put(&w, DF1_SOH);
	put_stuffed(&w, stn);
	put(&w, DF1_DLE);
	put(&w, DF1_STX);
	/* CRC covers STN and STX; the BCC's STX is the doc/PROTOCOL.md 2.2 open question. */
	crc = crc_step(crc_step(0, stn), DF1_STX);
	if (bcc_includes_stx)
		sum = (uint8_t)(sum + DF1_STX);
	put_body(&w, check, sum, crc, app, n);
	return writer_done(&w);
}

size_t frame_encode_poll(uint8_t stn, uint8_t *out, size_t cap)
{
	struct writer w = { out, cap, 0, false };

	if (!out)
		return 0;
	put(&w, DF1_DLE);
	put(&w, DF1_ENQ);
	put_stuffed(&w, stn);
	put(&w, (uint8_t)(0u - stn)); /* always a 1-byte BCC, even on a CRC line */
	return writer_done(&w);
}

size_t frame_encode_symbol(uint8_t sym, uint8_t *out, size_t cap)
{
	struct writer w = { out, cap, 0, false };

	if (!out)
		return 0;
	if (sym != DF1_ACK && sym != DF1_NAK && sym != DF1_ENQ && sym != DF1_EOT)
		return 0;
	put(&w, DF1_DLE);
	put(&w, sym);
	return writer_done(&w);
}

/* ------------------------------------------------------------------------
 * Decoder
 * ------------------------------------------------------------------------ */

enum {
	ST_IDLE = 0,
	ST_EOT_TRAILER,  /* after DLE EOT: one non-DLE byte may follow */
	ST_DLE,          /* DLE outside a frame */
	ST_POLL_STN,     /* DLE ENQ (half duplex): STN next */
	ST_POLL_STN_DLE, /* STN began with DLE: the second DLE next */
	ST_POLL_BCC,
	ST_APOLL_STN,    /* DLE ENQ (auto duplex): a poll if a poll's shape follows */
	ST_APOLL_STN_DLE,
	ST_APOLL_BCC,
	ST_SOH_STN,      /* DLE SOH: STN next */
	ST_SOH_STN_DLE,
	ST_SOH_DLE,      /* DLE SOH STN: DLE next */
	ST_SOH_STX,      /* DLE SOH STN DLE: STX next */
	ST_DATA,
	ST_DATA_DLE,
	ST_CHECK,        /* after DLE ETX: 1 or 2 check bytes */
};

void frame_decoder_init(struct frame_decoder *d, enum df1_check check, unsigned opts)
{
	memset(d, 0, sizeof *d);
	d->check = check;
	d->opts = opts;
	d->max_len = FRAME_MAX_DATA;
	frame_decoder_reset(d);
}

void frame_decoder_reset(struct frame_decoder *d)
{
	d->locked = d->check == DF1_CHECK_BCC ? DF1_CHECK_BCC : DF1_CHECK_CRC;
	d->auto_locked = false;
	d->state = ST_IDLE;
	d->in_master = false;
	d->stn = 0;
	d->nchk = 0;
	d->wire = 0;
	d->overflow = false;
	d->sum = 0;
	d->crc = 0;
	d->noise = 0;
	d->len = 0;
}

bool frame_decoder_busy(const struct frame_decoder *d)
{
	return d->state != ST_IDLE && d->state != ST_EOT_TRAILER;
}

bool frame_decoder_dle_pending(const struct frame_decoder *d)
{
	switch (d->state) {
	case ST_DLE:
	case ST_DATA_DLE:
	case ST_POLL_STN_DLE:
	case ST_APOLL_STN_DLE:
	case ST_SOH_STN_DLE:
		return true;
	default:
		return false;
	}
}

static bool is_nak(const struct frame_decoder *d, uint8_t b)
{
	return b == DF1_NAK || (b == DF1_NAK_OLD && (d->opts & FRAME_OPT_ACCEPT_NAK_0F));
}

static size_t limit(const struct frame_decoder *d)
{
	return d->max_len < FRAME_MAX_DATA ? d->max_len : FRAME_MAX_DATA;
}

static void begin_frame(struct frame_decoder *d, bool master)
{
	d->in_master = master;
	d->stn = 0;
	d->len = 0;
	d->overflow = false;
	d->sum = 0;
	d->crc = 0;
	d->nchk = 0;
	d->wire = 2; /* DLE STX or DLE SOH */
	d->state = master ? ST_SOH_STN : ST_DATA;
}

static void data_byte(struct frame_decoder *d, uint8_t b)
{
	if (d->len < limit(d))
		d->buf[d->len++] = b;
	else
		d->overflow = true; /* keep reading to DLE ETX, then report 2512 */
	d->sum = (uint8_t)(d->sum + b);
	d->crc = crc_step(d->crc, b);
}

static void master_stn(struct frame_decoder *d, uint8_t stn)
{
	d->stn = stn;
	d->sum = stn;
	d->crc = crc_step(0, stn);
	d->state = ST_SOH_DLE;
}

/* Fill the frame-related fields of an ERROR or FRAME symbol. */
static void frame_fields(const struct frame_decoder *d, struct df1_symbol *sym)
{
	sym->master_msg = d->in_master;
	/* the STN is known once the header is past it */
	sym->has_station = d->in_master && d->state != ST_SOH_STN && d->state != ST_SOH_STN_DLE;
	sym->station = sym->has_station ? d->stn : 0;
	sym->data = d->buf;
	sym->len = d->len;
}

/* The current symbol ends in an error; wire_len excludes `keep` bytes that
 * already belong to the next symbol. in_frame: a frame (or its header) was
 * under way, so the frame fields apply. */
static void symbol_error(struct frame_decoder *d, struct df1_symbol *sym, int id, uint8_t bad,
                         size_t keep, bool in_frame)
{
	sym->kind = DF1_SYM_ERROR;
	sym->error = id;
	sym->bad_byte = bad;
	if (in_frame)
		frame_fields(d, sym);
	sym->wire_len = d->wire - keep;
	d->state = ST_IDLE;
	d->wire = 0;
}

/* A DLE STX / DLE SOH cut the current symbol short: report it, start anew. */
static void restart(struct frame_decoder *d, struct df1_symbol *sym, int id, uint8_t b, bool in_frame)
{
	symbol_error(d, sym, id, id == DF1_ID_NTC_INVALID_SYMBOL ? b : 0, 2, in_frame);
	begin_frame(d, b == DF1_SOH);
}

static void simple(struct frame_decoder *d, struct df1_symbol *sym, enum df1_sym kind)
{
	sym->kind = kind;
	sym->wire_len = d->wire;
	d->wire = 0;
	d->state = ST_IDLE;
}

static uint8_t bcc_expected(const struct frame_decoder *d)
{
	return (uint8_t)(0u - d->sum);
}

static uint16_t crc_received(const struct frame_decoder *d)
{
	return (uint16_t)(d->chk[0] | (d->chk[1] << 8));
}

/* End of frame: the check verdict, then size (KA p.118 checks both). */
static void frame_done(struct frame_decoder *d, struct df1_symbol *sym, enum df1_check used,
                       uint16_t expected, uint16_t actual)
{
	frame_fields(d, sym);
	sym->check = used;
	sym->check_expected = expected;
	sym->check_actual = actual;
	sym->check_ok = expected == actual;
	sym->wire_len = d->wire;
	if (d->overflow) {
		sym->kind = DF1_SYM_ERROR;
		sym->error = DF1_ID_NTC_RCVD_MSG_TOO_LONG;
	} else if (d->len < FRAME_MIN_DATA) {
		sym->kind = DF1_SYM_ERROR;
		sym->error = DF1_ID_NTC_RCVD_MSG_TOO_SHORT;
	} else {
		sym->kind = DF1_SYM_FRAME;
	}
	d->state = ST_IDLE;
	d->wire = 0;
}

/* One check byte after DLE ETX. Returns true when the symbol is complete;
 * *to_next is set when the byte belongs to the next symbol (AUTO, see frame.h). */
static bool check_byte(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b, bool *to_next)
{
	enum df1_check mode = d->check;
	uint16_t crc = d->crc;

	d->chk[d->nchk++] = b;
	if (mode == DF1_CHECK_AUTO && d->auto_locked && d->locked == DF1_CHECK_CRC)
		mode = DF1_CHECK_CRC;
	if (mode == DF1_CHECK_BCC) {
		frame_done(d, sym, DF1_CHECK_BCC, bcc_expected(d), b);
		return true;
	}
	if (mode == DF1_CHECK_CRC) {
		if (d->nchk < 2)
			return false;
		frame_done(d, sym, DF1_CHECK_CRC, crc, crc_received(d));
		return true;
	}
	/* AUTO, unlocked or locked to BCC */
	if (d->nchk == 1) {
		if (b != bcc_expected(d))
			return false;
		d->locked = DF1_CHECK_BCC;
		d->auto_locked = true;
		frame_done(d, sym, DF1_CHECK_BCC, bcc_expected(d), b);
		return true;
	}
	if (crc_received(d) == crc) {
		d->locked = DF1_CHECK_CRC;
		d->auto_locked = true;
		frame_done(d, sym, DF1_CHECK_CRC, crc, crc);
		return true;
	}
	if (b == DF1_DLE || d->auto_locked) {
		d->wire--; /* the second byte is not part of this frame */
		if (b == DF1_DLE)
			*to_next = true;
		else
			d->noise++;
		frame_done(d, sym, DF1_CHECK_BCC, bcc_expected(d), d->chk[0]);
		return true;
	}
	frame_done(d, sym, DF1_CHECK_CRC, crc, crc_received(d));
	return true;
}

/* A DLE outside a frame, then b. */
static bool after_dle(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b)
{
	switch (b) {
	case DF1_STX:
		begin_frame(d, false);
		return false;
	case DF1_SOH:
		begin_frame(d, true);
		return false;
	case DF1_ENQ:
		if (d->opts & FRAME_OPT_HALF_DUPLEX) {
			d->state = ST_POLL_STN;
			return false;
		}
		if (d->opts & FRAME_OPT_DUPLEX_AUTO) {
			d->state = ST_APOLL_STN;
			return false;
		}
		simple(d, sym, DF1_SYM_ENQ);
		return true;
	case DF1_EOT:
		simple(d, sym, DF1_SYM_EOT);
		if (d->opts & FRAME_OPT_EOT_TRAILER)
			d->state = ST_EOT_TRAILER;
		return true;
	case DF1_ACK:
		simple(d, sym, DF1_SYM_ACK);
		return true;
	case DF1_DLE:
		/* data 10h outside a frame: noise, but this DLE may start a symbol */
		d->noise++;
		d->wire = 1;
		return false;
	case DF1_ETX:
		/* the end of a frame whose start we missed: noise (doc/PROTOCOL.md 1.7) */
		d->noise += 2;
		d->wire = 0;
		d->state = ST_IDLE;
		return false;
	default:
		if (is_nak(d, b)) {
			simple(d, sym, DF1_SYM_NAK);
			return true;
		}
		symbol_error(d, sym, DF1_ID_NTC_INVALID_SYMBOL, b, 0, false);
		return true;
	}
}

/* A DLE inside a frame's data, then b. */
static bool data_dle(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b)
{
	if (b == DF1_DLE) {
		data_byte(d, DF1_DLE);
		d->state = ST_DATA;
		return false;
	}
	if (b == DF1_ETX) {
		d->crc = crc_step(d->crc, DF1_ETX);
		d->nchk = 0;
		d->state = ST_CHECK;
		return false;
	}
	if ((b == DF1_ACK || is_nak(d, b)) && !(d->opts & FRAME_OPT_NO_EMBEDDED)) {
		/* embedded response (doc/PROTOCOL.md 1.8): out of band, the frame goes on */
		sym->kind = b == DF1_ACK ? DF1_SYM_ACK : DF1_SYM_NAK;
		sym->embedded = true;
		sym->wire_len = 2;
		d->wire -= 2;
		d->state = ST_DATA;
		return true;
	}
	if (b == DF1_STX || b == DF1_SOH) {
		restart(d, sym, DF1_ID_NTC_NO_ETX_RCVD, b, true);
		return true;
	}
	symbol_error(d, sym, DF1_ID_NTC_INVALID_SYMBOL, b, 0, true);
	return true;
}

/* A poll's STN began with DLE but no second DLE followed. */
static bool poll_error(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b)
{
	if (b == DF1_STX || b == DF1_SOH)
		restart(d, sym, DF1_ID_NTC_INVALID_SYMBOL, b, false);
	else
		symbol_error(d, sym, DF1_ID_NTC_INVALID_SYMBOL, b, 0, false);
	return true;
}

/* Auto duplex: the bytes after DLE ENQ are not a poll. The DLE ENQ was the
 * full-duplex ENQ; the decoder goes on as if it had read the bytes since then
 * on their own (noise: the STN byte, or the first DLE of DLE DLE; state: IDLE,
 * or ST_DLE when a DLE may start the next symbol), and the byte that decided
 * is left for the next call (*keep). */
static bool auto_enq(struct frame_decoder *d, struct df1_symbol *sym, size_t noise, int state,
                     bool *keep)
{
	sym->kind = DF1_SYM_ENQ;
	sym->wire_len = 2;
	d->noise += noise;
	d->state = state;
	d->wire = state == ST_DLE ? 1 : 0;
	*keep = true;
	return true;
}

/* The BCC byte of a poll: POLL, or (half duplex) ERROR 2507. */
static bool poll_bcc(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b)
{
	sym->has_station = true;
	sym->station = d->stn;
	sym->check = DF1_CHECK_BCC;
	sym->check_expected = (uint8_t)(0u - d->stn);
	sym->check_actual = b;
	sym->check_ok = sym->check_expected == b;
	if (sym->check_ok) {
		simple(d, sym, DF1_SYM_POLL);
	} else {
		simple(d, sym, DF1_SYM_ERROR);
		sym->error = DF1_ID_ERR_BAD_BCC;
	}
	return true;
}

/* A byte between symbols: a DLE starts one, anything else is noise (or the
 * one tolerated byte after DLE EOT). */
static void idle_byte(struct frame_decoder *d, uint8_t b)
{
	if (b == DF1_DLE) {
		d->state = ST_DLE;
		d->wire = 1;
	} else if (d->state == ST_IDLE) {
		d->noise++;
	} else {
		d->state = ST_IDLE; /* the one tolerated byte after DLE EOT */
	}
}

/* A byte of a half-duplex poll after DLE ENQ (states ST_POLL_*). */
static bool poll_byte(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b)
{
	switch (d->state) {
	case ST_POLL_STN:
		if (b == DF1_DLE) {
			d->state = ST_POLL_STN_DLE;
		} else {
			d->stn = b;
			d->state = ST_POLL_BCC;
		}
		return false;
	case ST_POLL_STN_DLE:
		if (b != DF1_DLE)
			return poll_error(d, sym, b);
		d->stn = DF1_DLE;
		d->state = ST_POLL_BCC;
		return false;
	default: /* ST_POLL_BCC */
		return poll_bcc(d, sym, b);
	}
}

/* A byte after an auto-duplex DLE ENQ, a poll if a poll's shape follows
 * (states ST_APOLL_*; *keep as step's). */
static bool apoll_byte(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b, bool *keep)
{
	switch (d->state) {
	case ST_APOLL_STN:
		if (b == DF1_DLE) {
			d->state = ST_APOLL_STN_DLE;
		} else {
			d->stn = b;
			d->state = ST_APOLL_BCC;
		}
		return false;
	case ST_APOLL_STN_DLE:
		if (b != DF1_DLE)
			return auto_enq(d, sym, 0, ST_DLE, keep); /* DLE b: a symbol of its own */
		d->stn = DF1_DLE;
		d->state = ST_APOLL_BCC;
		return false;
	default: /* ST_APOLL_BCC */
		if (b == (uint8_t)(0u - d->stn))
			return poll_bcc(d, sym, b);
		/* a stuffed STN was DLE DLE: noise, and its second DLE may start a symbol */
		return auto_enq(d, sym, 1, d->stn == DF1_DLE ? ST_DLE : ST_IDLE, keep);
	}
}

/* A byte of a master message's header DLE SOH STN DLE STX (states ST_SOH_*). */
static bool soh_byte(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b)
{
	switch (d->state) {
	case ST_SOH_STN:
		if (b == DF1_DLE)
			d->state = ST_SOH_STN_DLE;
		else
			master_stn(d, b);
		return false;
	case ST_SOH_STN_DLE:
		if (b == DF1_DLE) {
			master_stn(d, DF1_DLE);
			return false;
		}
		if (b == DF1_STX || b == DF1_SOH) {
			restart(d, sym, DF1_ID_NTC_NO_ETX_RCVD, b, true);
			return true;
		}
		symbol_error(d, sym, DF1_ID_NTC_INVALID_SYMBOL, b, 0, true);
		return true;
	case ST_SOH_DLE:
		if (b == DF1_DLE) {
			d->state = ST_SOH_STX;
			return false;
		}
		symbol_error(d, sym, DF1_ID_NTC_INVALID_SYMBOL, b, 0, true);
		return true;
	default: /* ST_SOH_STX */
		if (b == DF1_STX) {
			d->crc = crc_step(d->crc, DF1_STX);
			if (d->opts & FRAME_OPT_HD_BCC_STX)
				d->sum = (uint8_t)(d->sum + DF1_STX);
			d->state = ST_DATA;
			return false;
		}
		if (b == DF1_SOH) {
			restart(d, sym, DF1_ID_NTC_NO_ETX_RCVD, b, true);
			return true;
		}
		symbol_error(d, sym, DF1_ID_NTC_INVALID_SYMBOL, b, 0, true);
		return true;
	}
}

/* One byte; true when a symbol is complete (*keep: b is not consumed). The
 * data states come first: most bytes are a frame's data. */
static bool step(struct frame_decoder *d, struct df1_symbol *sym, uint8_t b, bool *to_next,
                 bool *keep)
{
	if (d->state == ST_IDLE || d->state == ST_EOT_TRAILER) {
		idle_byte(d, b);
		return false;
	}
	d->wire++;
	switch (d->state) {
	case ST_DATA:
		if (b == DF1_DLE)
			d->state = ST_DATA_DLE;
		else
			data_byte(d, b);
		return false;
	case ST_DATA_DLE:
		return data_dle(d, sym, b);
	case ST_CHECK:
		return check_byte(d, sym, b, to_next);
	case ST_DLE:
		return after_dle(d, sym, b);
	case ST_POLL_STN:
	case ST_POLL_STN_DLE:
	case ST_POLL_BCC:
		return poll_byte(d, sym, b);
	case ST_APOLL_STN:
	case ST_APOLL_STN_DLE:
	case ST_APOLL_BCC:
		return apoll_byte(d, sym, b, keep);
	case ST_SOH_STN:
	case ST_SOH_STN_DLE:
	case ST_SOH_DLE:
	case ST_SOH_STX:
		return soh_byte(d, sym, b);
	default:
		/* unreachable; recover rather than trust a corrupted state */
		d->state = ST_IDLE;
		d->wire = 0;
		return false;
	}
}

size_t frame_decoder_feed(struct frame_decoder *d, const uint8_t *in, size_t n, struct df1_symbol *sym)
{
	memset(sym, 0, sizeof *sym);
	sym->kind = DF1_SYM_NONE;
	for (size_t i = 0; i < n; i++) {
		bool to_next = false, keep = false;

		if (step(d, sym, in[i], &to_next, &keep)) {
			if (keep)
				return i;
			if (to_next) {
				d->state = ST_DLE;
				d->wire = 1;
			}
			return i + 1;
		}
	}
	return n;
}
