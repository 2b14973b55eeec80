/*
 * frame - DF1 link-layer framing (pure: no I/O, no clock, no allocation).
 * DLE stuffing, BCC, CRC-16/ARC, encoders for every frame kind, and an
 * incremental decoder fed any number of bytes at a time (spec/protocol.md 1-2).
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
#define DF1_NAK_OLD 0x0F /* the 1996 manual's tables print NAK as 0F (spec 1.1) */

/* Link-layer data limit: 6 header bytes + FNC + 250 bytes of data, with margin (spec 6). */
#define FRAME_MAX_DATA 264
#define FRAME_MIN_DATA 6
/* Worst case on the wire: SOH STN(2) STX + every byte stuffed + ETX + CRC(2) */
#define FRAME_MAX_WIRE (2 + 2 + 2 + 2 * FRAME_MAX_DATA + 2 + 2)

uint8_t  frame_bcc(const uint8_t *data, size_t n);              /* (-sum) & 0xFF */
uint16_t frame_crc16(uint16_t crc, const uint8_t *data, size_t n); /* CRC-16/ARC step, init 0 */

/* Encoders return the number of wire bytes written, or 0 if cap is too small. */
size_t frame_encode_full(enum df1_check check, const uint8_t *app, size_t n, uint8_t *out, size_t cap);
/* Half-duplex master message DLE SOH STN DLE STX app DLE ETX check.
 * CRC over STN STX data ETX; BCC over STN + data (+ STX when bcc_includes_stx). */
size_t frame_encode_master(enum df1_check check, uint8_t stn, bool bcc_includes_stx,
                           const uint8_t *app, size_t n, uint8_t *out, size_t cap);
/* Half-duplex slave message: identical to the full-duplex frame. */
#define frame_encode_slave frame_encode_full
size_t frame_encode_poll(uint8_t stn, uint8_t *out, size_t cap);   /* DLE ENQ STN BCC */
/* Two-byte symbols: DLE ACK / NAK / ENQ / EOT. */
size_t frame_encode_symbol(uint8_t sym, uint8_t *out, size_t cap);

/* Decoder options */
#define FRAME_OPT_ACCEPT_NAK_0F   0x01u /* DLE 0F is NAK too */
#define FRAME_OPT_HD_BCC_STX      0x02u /* master-message BCC includes STX */
#define FRAME_OPT_EOT_TRAILER     0x04u /* ignore one byte after DLE EOT */
#define FRAME_OPT_NO_EMBEDDED     0x08u /* ACK/NAK inside a frame aborts it (2514) */

struct frame_decoder {
	enum df1_check check;      /* configured (may be AUTO) */
	enum df1_check locked;     /* AUTO: resolved after the first good frame */
	bool auto_locked;
	unsigned opts;
	size_t max_len;            /* app bytes limit (default FRAME_MAX_DATA) */
	int state;
	bool in_master;            /* frame began with DLE SOH STN */
	uint8_t stn;
	uint8_t chk[2];
	int nchk;
	size_t wire;               /* wire bytes of the current symbol */
	bool overflow;
	size_t len;
	uint8_t buf[FRAME_MAX_DATA];
	uint8_t out[FRAME_MAX_DATA]; /* the completed frame handed to the caller */
};

void frame_decoder_init(struct frame_decoder *d, enum df1_check check, unsigned opts);
void frame_decoder_reset(struct frame_decoder *d);   /* back to idle, keeps config */
/* Feed bytes; stops as soon as one symbol is complete. Returns bytes consumed;
 * sym->kind is DF1_SYM_NONE if the input ran out first. sym->data points into
 * the decoder and stays valid until the next feed. */
size_t frame_decoder_feed(struct frame_decoder *d, const uint8_t *in, size_t n, struct df1_symbol *sym);
/* True while the decoder is inside a frame (a deadline for its end applies). */
bool frame_decoder_busy(const struct frame_decoder *d);

#endif
