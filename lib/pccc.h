/*
 * pccc - PCCC application layer (pure: no I/O, no clock, no allocation).
 * Command encoders for every supported CMD/FNC with the exact layouts of
 * spec/protocol.md 4, reply decoding (CMD|40h, TNS, STS, EXT STS), PLC-5
 * system addresses, typed-data descriptors and diagnostic status.
 *
 * Encoders write the whole app message (DST SRC CMD STS TNS_lo TNS_hi FNC data)
 * into out and return its length, or DF1_E_NOSPACE / DF1_E_INVAL / DF1_E_ADDR_RANGE.
 */
#ifndef LIBDF1_PCCC_H
#define LIBDF1_PCCC_H

#include "df1.h"

#define PCCC_HDR_LEN 6

/* Command codes */
#define PCCC_CMD_PROT_WRITE   0x00
#define PCCC_CMD_UNPROT_READ  0x01   /* PLC-2 */
#define PCCC_CMD_PROT_BIT_WRITE 0x02
#define PCCC_CMD_UNPROT_BIT_WRITE 0x05
#define PCCC_CMD_DIAG         0x06
#define PCCC_CMD_UNPROT_WRITE 0x08   /* PLC-2 */
#define PCCC_CMD_TYPED        0x0F
#define PCCC_REPLY_BIT        0x40

/* FNC for CMD 06 */
#define PCCC_FNC_ECHO         0x00
#define PCCC_FNC_DIAG_READ    0x01
#define PCCC_FNC_DIAG_STATUS  0x03
/* FNC for CMD 0F */
#define PCCC_FNC_WORD_WRITE   0x00
#define PCCC_FNC_WORD_READ    0x01
#define PCCC_FNC_BIT_WRITE    0x02
#define PCCC_FNC_RMW          0x26
#define PCCC_FNC_SET_CPU_MODE 0x3A
#define PCCC_FNC_TYPED_WRITE  0x67
#define PCCC_FNC_TYPED_READ   0x68
#define PCCC_FNC_CHANGE_MODE  0x80
#define PCCC_FNC_SLC_READ2    0xA1
#define PCCC_FNC_SLC_READ3    0xA2
#define PCCC_FNC_SLC_WRITE2   0xA9
#define PCCC_FNC_SLC_WRITE3   0xAA
#define PCCC_FNC_SLC_MASKED   0xAB

/* Typed-data type IDs (M p.116) */
#define PCCC_TD_BIT      1
#define PCCC_TD_BITSTR   2
#define PCCC_TD_STRING   3
#define PCCC_TD_INTEGER  4
#define PCCC_TD_TIMER    5
#define PCCC_TD_COUNTER  6
#define PCCC_TD_CONTROL  7
#define PCCC_TD_FLOAT    8
#define PCCC_TD_ARRAY    9
#define PCCC_TD_ADDRESS  15
#define PCCC_TD_BCD      16

struct pccc_hdr {
	uint8_t dst, src;
	uint16_t tns;
};

/* A decoded message header (command or reply). */
struct pccc_msg {
	uint8_t dst, src, cmd, sts;
	uint16_t tns;
	bool is_reply;
	bool has_fnc;           /* commands 06 and 0F carry FNC */
	uint8_t fnc;
	bool has_ext;           /* reply with STS F0 */
	uint8_t ext_sts;
	bool has_owner;         /* EXT STS 1A/1B for CMD 0B/1A/1B: owner node follows */
	uint8_t owner;
	const uint8_t *data;    /* command data after FNC, or reply data after STS/EXT */
	size_t len;
};

/* Header: DST SRC CMD STS TNS; FNC for CMD 06/0F; EXT STS (+owner) on replies. */
int pccc_decode(const uint8_t *app, size_t n, struct pccc_msg *m);
/* Build a reply header (dst/src swapped, CMD|40h, same TNS) + data. */
int pccc_encode_reply(uint8_t *out, size_t cap, const struct pccc_msg *cmd,
                      uint8_t sts, uint8_t ext_sts, const uint8_t *data, size_t n);

/* SLC logical address fields: 1 byte for 0..254, FF + LE16 above (M p.104). */
int pccc_put_field(uint8_t *out, size_t cap, unsigned v);
int pccc_get_field(const uint8_t *in, size_t n, unsigned *v);   /* bytes consumed */

/* SLC 0F/A1 A2 (read), A9 AA (write), AB (masked write). type_code = SLC file type. */
int pccc_enc_slc_read(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t fnc,
                      uint8_t nbytes, unsigned file, uint8_t type_code, unsigned elem, unsigned sub);
int pccc_enc_slc_write(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t fnc,
                       unsigned file, uint8_t type_code, unsigned elem, unsigned sub,
                       const uint8_t *data, uint8_t nbytes);
int pccc_enc_slc_masked_write(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                              unsigned file, uint8_t type_code, unsigned elem, unsigned sub,
                              const uint8_t *mask, const uint8_t *data, uint8_t nbytes);
/* Decode SLC address fields after FNC: BYTE_SIZE FILE TYPE ELEM [SUB]. Returns bytes consumed. */
int pccc_dec_slc_fields(const uint8_t *in, size_t n, bool three_fields, uint8_t *nbytes,
                        unsigned *file, uint8_t *type_code, unsigned *elem, unsigned *sub);

/* PLC-5 system address, logical binary: mask byte + levels (area 0, file, element, sub). */
int pccc_enc_plc5_addr(uint8_t *out, size_t cap, const struct df1_addr *a);
/* Logical ASCII: 00 '$' text 00. */
int pccc_enc_plc5_ascii(uint8_t *out, size_t cap, const char *text_without_dollar);
/* Decode either form into a (file type from the ASCII text; binary gives file/elem/sub only,
 * type left DF1_FT_NONE). Returns bytes consumed. */
int pccc_dec_plc5_addr(const uint8_t *in, size_t n, struct df1_addr *a);

/* PLC-5 0F/68 typed read, 0F/67 typed write (counts in elements), 0F/01 0F/00 word range,
 * 0F/26 read-modify-write, 0F/02 bit write. addr/alen = an encoded PLC-5 address. */
int pccc_enc_plc5_typed_read(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                             uint16_t pkt_offset, uint16_t total, const uint8_t *addr, size_t alen,
                             uint16_t nelem);
int pccc_enc_plc5_typed_write(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                              uint16_t pkt_offset, uint16_t total, const uint8_t *addr, size_t alen,
                              const uint8_t *typed, size_t tlen);   /* type/data param + data */
int pccc_enc_plc5_word_read(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                            uint16_t pkt_offset, uint16_t total_words, const uint8_t *addr,
                            size_t alen, uint8_t nbytes);
int pccc_enc_plc5_word_write(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                             uint16_t pkt_offset, uint16_t total_words, const uint8_t *addr,
                             size_t alen, const uint8_t *data, size_t n);
int pccc_enc_plc5_rmw(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                      const uint8_t *addr, size_t alen, uint16_t and_mask, uint16_t or_mask);
int pccc_enc_plc5_bit_write(uint8_t *out, size_t cap, const struct pccc_hdr *h,
                            const uint8_t *addr, size_t alen, uint16_t set, uint16_t reset);

/* PLC-2: 01 unprotected read (byte address, even size), 08 unprotected write. */
int pccc_enc_plc2_read(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint16_t byte_addr, uint8_t size);
int pccc_enc_plc2_write(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint16_t byte_addr,
                        const uint8_t *data, size_t n);

/* 06/00 echo, 06/03 diagnostic status, 0F/80 change mode. */
int pccc_enc_echo(uint8_t *out, size_t cap, const struct pccc_hdr *h, const uint8_t *data, size_t n);
int pccc_enc_diag_status(uint8_t *out, size_t cap, const struct pccc_hdr *h);
int pccc_enc_change_mode(uint8_t *out, size_t cap, const struct pccc_hdr *h, uint8_t mode);

/* Typed-data descriptor (M p.123): writes the shortest form; decoder accepts all
 * (43 == 49 03 == 4A 03 00). Returns bytes. */
int pccc_enc_typedata(uint8_t *out, size_t cap, unsigned type_id, uint32_t size);
int pccc_dec_typedata(const uint8_t *in, size_t n, unsigned *type_id, uint32_t *size);

/* Diagnostic status reply data (after the header) -> processor type, series, revision, mode. */
int pccc_dec_diag_status(const uint8_t *data, size_t n, struct df1_diag_status *out);
/* Name of a processor type code ("SLC 5/04"), or NULL. */
const char *pccc_processor_name(uint8_t type_code);
/* Short command name for display: "SLC typed read (A2)", "echo (06/00)". */
const char *pccc_command_name(uint8_t cmd, bool has_fnc, uint8_t fnc);

#endif
