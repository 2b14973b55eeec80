/* SPDX-License-Identifier: MPL-2.0 */
/*
 * frame - DF1 link-layer framing (pure: no I/O, no clock, no allocation).
 * DLE stuffing, BCC, CRC-16/ARC, encoders for every frame kind, and an
 * incremental decoder fed any number of bytes at a time (doc/PROTOCOL.md 1-2).
 */
#ifndef LIBDF1_FRAME_H
#define LIBDF1_FRAME_H

#include "df1.h"

#define DF1_DLE 0x10
#define DF1_SOH 0x01
#define DF1_STX 0x02
#define DF1_ETX 0x03
#define DF1_EOT 0x04
#define DF1_ENQ 0x05
#define DF1_ACK 0x06
#define DF1_NAK 0x15
#define DF1_NAK_OLD 0x0F /* the 1996 manual's tables print NAK as 0F (doc/PROTOCOL.md 1.1) */

/* Link-layer data limit: 6 header bytes + FNC + 250 bytes of data, with margin (doc/PROTOCOL.md 6). */
#define FRAME_MAX_DATA 264
#define FRAME_MIN_DATA 6
/* Worst case on the wire: SOH STN(2) STX + every byte stuffed + ETX + CRC(2) */
#define FRAME_MAX_WIRE (2 + 2 + 2 + 2 * FRAME_MAX_DATA + 2 + 2)

uint8_t  frame_bcc(const uint8_t *data, size_t n);              /* (-sum) & 0xFF */
uint16_t frame_crc16(uint16_t crc, const uint8_t *data, size_t n); /* CRC-16/ARC step, init 0 */

/* Encoders return the number of wire bytes written, or 0 if cap is too small,
 * out is NULL or check is not CRC/BCC. The check bytes are never stuffed. */
size_t frame_encode_full(enum df1_check check, const uint8_t *app, size_t n, uint8_t *out, size_t cap);
/* Half-duplex master message DLE SOH STN DLE STX app DLE ETX check.
 * CRC over STN STX data ETX; BCC over STN + data (+ STX when bcc_includes_stx). */
size_t frame_encode_master(enum df1_check check, uint8_t stn, bool bcc_includes_stx,
                           const uint8_t *app, size_t n, uint8_t *out, size_t cap);
/* Half-duplex slave message: identical to the full-duplex frame. */
#define frame_encode_slave frame_encode_full
size_t frame_encode_poll(uint8_t stn, uint8_t *out, size_t cap);   /* DLE ENQ STN BCC */
/* Two-byte symbols: sym = DF1_ACK / DF1_NAK / DF1_ENQ / DF1_EOT (others give 0). */
size_t frame_encode_symbol(uint8_t sym, uint8_t *out, size_t cap);

/* Decoder options */
#define FRAME_OPT_ACCEPT_NAK_0F   0x01u /* DLE 0F is NAK too */
#define FRAME_OPT_HD_BCC_STX      0x02u /* master-message BCC includes STX */
#define FRAME_OPT_EOT_TRAILER     0x04u /* ignore one byte after DLE EOT */
#define FRAME_OPT_NO_EMBEDDED     0x08u /* ACK/NAK inside a frame aborts it (2514) */
#define FRAME_OPT_HALF_DUPLEX     0x10u /* DLE ENQ is a poll: DLE ENQ STN BCC */
#define FRAME_OPT_DUPLEX_AUTO     0x20u /* DLE ENQ is a poll when a poll's shape follows */

/*
 * Decoder rules (the ones the spec leaves open):
 *  - FRAME_OPT_DUPLEX_AUTO (without FRAME_OPT_HALF_DUPLEX): DLE ENQ followed by
 *    a poll's shape, STN (DLE DLE for 10h) and a BCC byte that is its two's
 *    complement, is a POLL; followed by anything else it is the full-duplex
 *    ENQ, reported (wire_len 2) when the first byte that breaks the shape
 *    arrives. That byte is not consumed (feed may return 0 with the ENQ); the
 *    bytes read after DLE ENQ are then taken as they would have been without
 *    the option (a plain STN byte is noise; DLE DLE is noise and its second DLE
 *    may start the next symbol; DLE x goes on as DLE x). A poll with a bad BCC
 *    is thus an ENQ and noise, never ERROR 2507.
 *  - Outside a frame, bytes that start no symbol are noise: skipped, added to
 *    `noise`, never part of a symbol's wire_len. DLE DLE and DLE ETX outside a
 *    frame are noise too (the second DLE of DLE DLE may start the next symbol,
 *    so a noise byte 10h cannot swallow the DLE STX that follows it).
 *  - wire_len covers the symbol's own bytes from its first DLE. An embedded
 *    ACK/NAK is reported with wire_len 2 and is not counted in its frame's.
 *    With FRAME_OPT_EOT_TRAILER, DLE EOT is reported at once and one following
 *    non-DLE byte is dropped silently (in neither wire_len nor noise).
 *  - DLE followed by an unexpected byte gives ERROR 2514 (bad_byte); inside a
 *    frame or a header it aborts it. DLE ENQ / DLE EOT inside a frame are such
 *    bytes. After DLE SOH STN anything but DLE STX is 2514 (bad_byte = the
 *    byte found).
 *  - DLE STX or DLE SOH inside a frame reports the old frame as ERROR 2518 and
 *    starts the new one (its DLE STX/SOH counts toward the new frame); inside a
 *    poll header it reports 2514 and likewise starts the new frame.
 *  - A poll (FRAME_OPT_HALF_DUPLEX) whose BCC is wrong is ERROR 2507 with the
 *    station and check fields set.
 *  - At DLE ETX + check: more than max_len app bytes is ERROR 2512, fewer than
 *    FRAME_MIN_DATA is ERROR 2513; else FRAME with its check verdict. The check
 *    fields (check, check_ok, expected, actual) are filled in all three cases:
 *    BCC as the byte, CRC as the 16-bit value (wire bytes lo, hi).
 *  - ERROR symbols of a frame carry the app bytes kept so far in data/len.
 *  - DF1_CHECK_AUTO: one byte after DLE ETX that makes the BCC good is a BCC
 *    (locks BCC); otherwise a second byte is taken and a good CRC locks CRC.
 *    Neither good: if the second byte is DLE (only one check byte plausible:
 *    the DLE starts the next symbol) or the decoder is locked to BCC, a bad BCC
 *    is reported, else a bad CRC. While locked to BCC a bad BCC still tries the
 *    CRC with the next byte, so a chance BCC match on a CRC line does not stick.
 *    Locked to CRC it behaves as DF1_CHECK_CRC. reset clears the lock.
 */
struct frame_decoder {
	enum df1_check check;      /* configured (may be AUTO) */
	enum df1_check locked;     /* AUTO: resolved after the first good frame */
	bool auto_locked;
	unsigned opts;
	size_t max_len;            /* app bytes limit (default FRAME_MAX_DATA, at most that) */
	int state;
	bool in_master;            /* frame began with DLE SOH STN */
	uint8_t stn;
	uint8_t chk[2];
	int nchk;
	size_t wire;               /* wire bytes of the current symbol */
	bool overflow;
	uint8_t sum;               /* running BCC sum of the covered bytes */
	uint16_t crc;              /* running CRC of the covered bytes */
	size_t noise;              /* bytes skipped outside any symbol since init/reset */
	size_t len;
	uint8_t buf[FRAME_MAX_DATA];
};

void frame_decoder_init(struct frame_decoder *d, enum df1_check check, unsigned opts);
void frame_decoder_reset(struct frame_decoder *d);   /* back to idle, keeps config */
/* Feed bytes; stops as soon as one symbol is complete. Returns bytes consumed
 * (> 0 whenever n > 0, but for the ENQ of FRAME_OPT_DUPLEX_AUTO, which may come
 * with 0: the byte that decided it is left for the next call); sym->kind is
 * DF1_SYM_NONE if the input ran out first.
 * sym->data points into the decoder and stays valid until the next feed. */
size_t frame_decoder_feed(struct frame_decoder *d, const uint8_t *in, size_t n, struct df1_symbol *sym);
/* True while the decoder is inside a symbol (a deadline for its end applies). */
bool frame_decoder_busy(const struct frame_decoder *d);
/* True when the last byte fed was a DLE whose second byte has not come (outside a
 * frame, inside its data, or inside a stuffed STN). */
bool frame_decoder_dle_pending(const struct frame_decoder *d);

#endif
