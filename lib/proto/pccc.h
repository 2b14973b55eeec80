/* SPDX-License-Identifier: MPL-2.0 */
/*
 * pccc - PCCC application layer (pure: no I/O, no clock, no allocation).
 * Command encoders for every supported CMD/FNC with the exact layouts of
 * doc/PROTOCOL.md 4, reply decoding (CMD|40h, TNS, STS, EXT STS), PLC-5
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

/* Bytes of a whole T/C/R element in a PLC-5 typed reply: the 3 data-table words
 * (type/data 56 66 76), or 5 (timer 59 0A: KF2 p.130, VME p.81), of which words
 * 0-2 are CTL, PRE/LEN, ACC/POS and the rest is ignored (doc/PROTOCOL.md 4.3, 5, 8 item 8). */
#define PCCC_TCR_BYTES 6
#define PCCC_TCR5_BYTES 10

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

/* Header: DST SRC CMD STS TNS; FNC for CMD 06/0F; on replies with STS F0 the EXT STS
 * byte (only for CMD above 08, doc/PROTOCOL.md 3.2) and the owner byte after EXT 1A/1B for CMD
 * 0B/1A/1B (doc/PROTOCOL.md 3.4). DF1_E_TOO_SHORT below 6 bytes or a command missing its FNC;
 * DF1_E_BAD_REPLY for a reply missing its EXT STS or owner byte. */
int pccc_decode(const uint8_t *app, size_t n, struct pccc_msg *m);
/* Build a reply header (dst/src swapped, CMD|40h, same TNS) + data. ext_sts is written
 * when sts is F0 and the CMD carries EXT STS; an owner byte (EXT 1A/1B) goes first in data. */
int pccc_encode_reply(uint8_t *out, size_t cap, const struct pccc_msg *cmd,
                      uint8_t sts, uint8_t ext_sts, const uint8_t *data, size_t n);
/* Does a reply to this CMD carry EXT STS when STS is F0? (CMD 00-08 do not, doc/PROTOCOL.md 3.2) */
bool pccc_cmd_has_ext_sts(uint8_t cmd);

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

/* SLC file type code (89h ...) -> file type; 82h/83h (F2E) read as O/I too. DF1_FT_NONE if unknown. */
enum df1_file_type pccc_slc_code_file_type(uint8_t code);

/* PLC-5 system address, logical binary (doc/PROTOCOL.md 4.1): a mask byte (bit n set = level n+1
 * follows), then the encoded levels: 1 area (0 = data table), 2 file, 3 element,
 * 4 sub-element. Values and the mask above 254 take the FF + LE16 escape.
 * Which levels to send is a choice; all forms mean the same address: */
enum pccc_plc5_form {
	PCCC_PLC5_FILE_ELEM = 0, /* LPT: 06 file elem, 0E with a sub-element ("N7:0" -> 06 07 00) */
	PCCC_PLC5_ALL_LEVELS,    /* area too: 07, 0F with a sub (M p.227 "N7:30" -> 07 00 07 1E) */
	PCCC_PLC5_FOUR_LEVELS,   /* always 0F, sub 0 when none (KE p.50 "N10:15" -> 0F 00 0A 0F 00) */
};
/* a->ascii non-empty: the logical ASCII form; else binary in the FILE_ELEM form.
 * The bit of a /bit address is not part of a PLC-5 address (it goes in masks). */
int pccc_enc_plc5_addr(uint8_t *out, size_t cap, const struct df1_addr *a);
int pccc_enc_plc5_addr_form(uint8_t *out, size_t cap, const struct df1_addr *a,
                            enum pccc_plc5_form form);
/* Logical ASCII: 00 '$' text 00 (a leading '$' in text is not doubled; <= 51 characters). */
int pccc_enc_plc5_ascii(uint8_t *out, size_t cap, const char *text_without_dollar);
/* Decode either form into a; returns bytes consumed.
 * Binary: file/element/sub as encoded (sub DF1_ADDR_NONE when level 4 is absent; an absent
 * file level is 1, M p.226), type DF1_FT_NONE (the address carries no file type); a mask
 * of 0 is DF1_E_ADDR_SYNTAX, a 5th level or an area other than 0 DF1_E_ADDR_RANGE.
 * ASCII: ascii = the text, other fields from df1_addr_parse(); text it rejects still
 * decodes, with type DF1_FT_NONE and file = element = DF1_ADDR_NONE (answer EXT STS 05).
 * Truncated input: DF1_E_TOO_SHORT. */
int pccc_dec_plc5_addr(const uint8_t *in, size_t n, struct df1_addr *a);

/* The body (after FNC) of a PLC-5 command that carries an address. */
struct pccc_plc5_req {
	uint16_t pkt_offset;    /* 00 01 67 68: packet offset (words / elements) */
	uint16_t total;         /* 00 01 67 68: total transaction (words / elements) */
	struct df1_addr addr;
	int size;               /* 68: elements (2 bytes); 01: bytes (1 byte); else -1 */
	const uint8_t *data;    /* 00: words; 67: type/data parameter + data; 26: AND OR; 02: SET RESET */
	size_t len;
};
/* fnc one of 00 01 02 26 67 68; DF1_E_NOTSUP for others. */
int pccc_dec_plc5_req(uint8_t fnc, const uint8_t *in, size_t n, struct pccc_plc5_req *r);

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

/* PLC-3 logical binary address (doc/PROTOCOL.md 4.2a; lib/proto/pccc_plc3.c): a mask
 * byte (bit n set = level n+1 follows, M p.13-6), then the levels present, each as
 * pccc_put_field(): 1 area (3 = the data table, the default), 2 context (default:
 * the current one), 3 section, 4 file, 5 structure, 6 word. */
struct pccc_plc3_addr {
	unsigned section;       /* 1 O, 2 I, 3 T, 4 C, 5 N, 6 F, 7 D, 8 B, 9 A, 10 H, 12 pointers, 13 S */
	unsigned file, structure, word;
};
#define PCCC_PLC3_AREA_DATA 3
/* A df1_addr of the PLC-3 grammar (lib/proto/addr_plc3.c) -> its levels: T C F H
 * (DF1_FT_L) element = structure (T/C word = sub, 0 for a whole structure; F H word
 * 0), other sections structure 0, word = element. DF1_E_ADDR_RANGE for a type a
 * PLC-3 does not have (R ST). */
int pccc_plc3_levels(const struct df1_addr *a, struct pccc_plc3_addr *l);
/* The encoded levels: section and word always (the last level is always sent,
 * M p.13-6), file and structure when not 0 (their default). Returns bytes. */
int pccc_enc_plc3_levels(uint8_t *out, size_t cap, const struct pccc_plc3_addr *l);
int pccc_enc_plc3_addr(uint8_t *out, size_t cap, const struct df1_addr *a);
/* Decode; returns bytes consumed. A mask of 0 or without level 6 (the word):
 * DF1_E_ADDR_SYNTAX; levels 7-8, or an area other than 3: DF1_E_ADDR_RANGE;
 * truncated: DF1_E_TOO_SHORT. */
int pccc_dec_plc3_addr(const uint8_t *in, size_t n, struct pccc_plc3_addr *l);
/* Levels -> the server's view: type, file, element, sub such that the data
 * starts at element * element_size + sub * 2 (lib/server/server.h): T/C sub =
 * word 0-2, F/H sub = word 0-1 (1: the upper half). DF1_E_ADDR_RANGE for a
 * section the data table does not hold (pointers, 11, above 13) or a level out
 * of its section's range (T/C file not 0, word sections' structure not 0). */
int pccc_plc3_to_addr(const struct pccc_plc3_addr *l, struct df1_addr *a);

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
/* Array header: 9x 09 SIZE.. + element descriptor (shortest). The array size always
 * goes in extension bytes (99 09 05 42), the form of RTA and of the doc/PROTOCOL.md 7.3 vectors;
 * M's short form (97 09 42) is decoded as well. Returns bytes. */
int pccc_enc_typed_array(uint8_t *out, size_t cap, unsigned elem_type, uint32_t elem_size, size_t count);

/* A type/data parameter and the data it describes; an array is unwrapped to its elements. */
struct pccc_typed {
	unsigned type_id;       /* element type (PCCC_TD_*) */
	uint32_t elem_size;     /* bytes per element */
	bool is_array;
	size_t count;           /* elements: 1 unless is_array */
	const uint8_t *data;
	size_t len;             /* count * elem_size */
	size_t consumed;        /* descriptor(s) + data */
};
/* DF1_E_TOO_SHORT if the data is shorter than declared; DF1_E_BAD_REPLY if malformed. */
int pccc_dec_typed(const uint8_t *in, size_t n, struct pccc_typed *t);

/* Diagnostic status reply data (after the header) -> processor type, series, revision, mode.
 * Type byte per AHMI: d[1] EE (SLC, M p.174) -> d[3]; EB (PLC-5, M p.192) or FE (interface
 * module) -> d[2]; else d[7]. Series letter = bits 5-7 of the series/revision byte (0 = A),
 * revision = bits 0-4 plus 1 (M p.174: "0 = release 1"). DF1_E_TOO_SHORT without the type. */
int pccc_dec_diag_status(const uint8_t *data, size_t n, struct df1_diag_status *out);
/* What a diagnostic status reply (06/03, doc/PROTOCOL.md 4.9) says about a processor. */
struct pccc_diag_info {
	bool plc5;              /* the PLC-5 EB form (M p.192-193), else the EE form (M p.174) */
	uint8_t type_code;      /* EE byte 4 / EB byte 3: processor (expansion) type */
	uint8_t interface_type; /* EE byte 3: 1F, 34 (MicroLogix, DF1 full duplex on port 0) */
	uint8_t series_rev;     /* EE byte 5 / EB byte 8: bits 5-7 series (0 = A), 0-4 revision */
	const char *bulletin;   /* EE bytes 6-16, blank-padded ASCII; NULL = blanks */
	uint8_t mode;           /* EE byte 19 (bits 0-4) / EB byte 1 (bits 0-2): mode as coded */
	uint8_t node;           /* EB byte 9: DH+ node */
	uint32_t memory_words;  /* EB bytes 4-7: user memory, low word first */
	uint16_t data_files;    /* EB bytes 12-13 */
	uint16_t program_files; /* EB bytes 14-15 */
	uint8_t ram_kb;         /* EE byte 23 */
	uint8_t owner;          /* EE byte 24: program owner node, 3F = none */
};
/* The reply data after the header (the inverse of pccc_dec_diag_status): 24 bytes
 * in the EE form, 18 in the EB form, the fields not in info zero. Returns the
 * length, DF1_E_NOSPACE, or DF1_E_INVAL. */
int pccc_enc_diag_reply(uint8_t *out, size_t cap, const struct pccc_diag_info *info);
/* Name of a processor type code ("SLC 5/04"), or NULL. */
const char *pccc_processor_name(uint8_t type_code);
/* Short command name for display: "SLC typed read, 3 fields (0F/A2)", "echo (06/00)";
 * a reply CMD (bit 6 set) gives "reply (4F)". Never NULL. */
const char *pccc_command_name(uint8_t cmd, bool has_fnc, uint8_t fnc);

#endif
