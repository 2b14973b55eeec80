/* SPDX-License-Identifier: MPL-2.0 */
/*
 * pccc_diag.c - the diagnostic status (06/03) reply: its decoder and, beside
 * it, the encoder a responder answers with; processor type codes and names
 * (doc/PROTOCOL.md 4.9). Pure: no I/O, clock or allocation.
 */
#include "proto/pccc.h"

#include <stdio.h>
#include <string.h>

#include "proto/value.h"

/* ------------------------------------------------------------------------
 * Diagnostic status (doc/PROTOCOL.md 4.9) and names
 * ------------------------------------------------------------------------ */

struct code_name {
	uint8_t code;
	const char *name;
};

/* AHMI's list and M p.192-193's PLC-5 list; where they differ M wins (28h, 29h). */
static const struct code_name processors[] = {
	{ 0x13, "PLC-5/12" },
	{ 0x14, "PLC-5/25" },
	{ 0x15, "PLC-5/40" },
	{ 0x18, "SLC 5/01" },
	{ 0x1A, "SLC 500 (fixed)" },
	{ 0x21, "PLC-5/60" },
	{ 0x22, "PLC-5/10" },
	{ 0x23, "PLC-5/60" },
	{ 0x25, "SLC 5/02" },
	{ 0x28, "PLC-5/40L" },
	{ 0x29, "PLC-5/60L" },
	{ 0x31, "PLC-5/11" },
	{ 0x32, "PLC-5/20" },
	{ 0x33, "PLC-5/30" },
	{ 0x49, "SLC 5/03" },
	{ 0x4A, "PLC-5/20E" },
	{ 0x4B, "PLC-5/40E" },
	{ 0x55, "PLC-5/80E" },  /* M's list reads "55, 59 PLC-5/80E" */
	{ 0x58, "MicroLogix 1000" },
	{ 0x59, "PLC-5/80E" },
	{ 0x5B, "SLC 5/04" },
	{ 0x6F, "SLC 5/04 (L541)" },
	{ 0x78, "SLC 5/05" },
	{ 0x83, "PLC-5/30E" },
	{ 0x86, "PLC-5/80E" },
	{ 0x88, "MicroLogix 1200" },
	{ 0x89, "MicroLogix 1500 LSP" },
	{ 0x8C, "MicroLogix 1500 LRP" },
	{ 0x95, "CompactLogix L35E" },
	{ 0x9C, "MicroLogix 1100" },
	{ 0x9F, "MicroLogix 1400" },
};

/* Interface modules answering with FE at byte 2 (F2E p.52). */
static const struct code_name interfaces[] = {
	{ 0x2C, "1770-KF3" },
	{ 0x5F, "1747-KFC15" },
};

static const char *pccc_find_name(const struct code_name *t, size_t n, uint8_t code)
{
	for (size_t i = 0; i < n; i++)
		if (t[i].code == code)
			return t[i].name;
	return NULL;
}

const char *pccc_processor_name(uint8_t type_code)
{
	return pccc_find_name(processors, sizeof processors / sizeof processors[0], type_code);
}

/* SLC/MicroLogix mode/status bits 0-4 (M p.174, 177). */
static const char *pccc_slc_mode_text(int mode)
{
	switch (mode) {
	case 0: return "download";
	case 1: return "program";
	case 3: return "idle";
	case 6: return "run";
	case 7: return "test continuous";
	case 8: return "test single scan";
	default: return "unknown";
	}
}

/* PLC-5 byte 1 bits 0-2 (M p.192). */
static const char *pccc_plc5_mode_text(int mode)
{
	switch (mode) {
	case 0: return "program load";
	case 2: return "run";
	case 4: return "remote program";
	case 5: return "remote test";
	case 6: return "remote run";
	default: return "unknown";
	}
}

static void pccc_set_series(struct df1_diag_status *o, uint8_t b)
{
	o->series = (char)('A' + ((b >> 5) & 7));      /* bits 5-7: 0 = series A */
	o->revision = (b & 0x1F) + 1;                   /* bits 0-4: 0 = release 1 (M p.174) */
}

int pccc_dec_diag_status(const uint8_t *d, size_t n, struct df1_diag_status *o)
{
	const char *name = NULL;
	size_t t;       /* index of the type byte */

	if (!d || !o)
		return DF1_E_INVAL;
	memset(o, 0, sizeof *o);
	o->series = '?';
	o->mode = -1;
	snprintf(o->mode_text, sizeof o->mode_text, "unknown");
	o->raw_len = n < sizeof o->raw ? n : sizeof o->raw;
	memcpy(o->raw, d, o->raw_len);
	if (n < 2)
		return DF1_E_TOO_SHORT;
	/* which byte holds the type: AHMI's rule (doc/PROTOCOL.md 4.9) */
	if (d[1] == 0xEE)
		t = 3;
	else if (d[1] == 0xEB || d[1] == 0xFE)
		t = 2;
	else
		t = 7;
	if (n <= t)
		return DF1_E_TOO_SHORT;
	o->type_code = d[t];

	if (d[1] == 0xEE) {
		/* SLC 500, 5/01, 5/02, MicroLogix (M p.174, 177) */
		if (n > 4)
			pccc_set_series(o, d[4]);
		if (n > 5) {
			size_t len = 0, end = n < 16 ? n : 16;  /* bytes 6-16: bulletin name */

			for (size_t i = 5; i < end && len < sizeof o->bulletin - 1; i++)
				if (d[i] >= 0x20 && d[i] < 0x7F)
					o->bulletin[len++] = (char)d[i];
			while (len && o->bulletin[len - 1] == ' ')
				len--;
			o->bulletin[len] = '\0';
		}
		if (n > 18) {
			o->mode = d[18] & 0x1F;
			snprintf(o->mode_text, sizeof o->mode_text, "%s", pccc_slc_mode_text(o->mode));
		}
		name = pccc_processor_name(o->type_code);
	} else if (d[1] == 0xEB) {
		/* PLC-5 (M p.192-193) */
		o->mode = d[0] & 0x07;
		snprintf(o->mode_text, sizeof o->mode_text, "%s", pccc_plc5_mode_text(o->mode));
		if (n > 7)
			pccc_set_series(o, d[7]);
		name = pccc_processor_name(o->type_code);
	} else if (d[1] == 0xFE) {
		name = pccc_find_name(interfaces, sizeof interfaces / sizeof interfaces[0], o->type_code);
	} else {
		name = pccc_processor_name(o->type_code);
	}
	if (name)
		snprintf(o->name, sizeof o->name, "%s", name);
	else
		snprintf(o->name, sizeof o->name, "unknown (0x%02X)", o->type_code);
	return 0;
}

int pccc_enc_diag_reply(uint8_t *out, size_t cap, const struct pccc_diag_info *d)
{
	size_t blen;

	if (!out || !d)
		return DF1_E_INVAL;
	if (d->plc5) {
		/* M p.192-193 (1-based): 1 mode, 2 EB, 3 type, 4-7 memory, 8 series/revision,
		 * 9 DH+ node, 10 I/O address, 11 flags, 12-13 data files, 14-15 program
		 * files, 16 forcing, 17 memory protect, 18 bad RAM */
		if (cap < 18)
			return DF1_E_NOSPACE;
		memset(out, 0, 18);
		out[0] = (uint8_t)(d->mode & 0x07);
		out[1] = 0xEB;
		out[2] = d->type_code;
		put_le16(out + 3, (uint16_t)d->memory_words);
		put_le16(out + 5, (uint16_t)(d->memory_words >> 16));
		out[7] = d->series_rev;
		out[8] = d->node;
		put_le16(out + 11, d->data_files);
		put_le16(out + 13, d->program_files);
		return 18;
	}
	/* M p.174: 1 mode/status, 2 EE, 3 interface type, 4 processor type,
	 * 5 series/revision, 6-16 bulletin, 17-18 major error, 19-20 mode/status
	 * word, 21-22 program ID, 23 RAM KB, 24 program owner */
	if (cap < 24)
		return DF1_E_NOSPACE;
	memset(out, 0, 24);
	out[1] = 0xEE;
	out[2] = d->interface_type;
	out[3] = d->type_code;
	out[4] = d->series_rev;
	memset(out + 5, ' ', 11);
	blen = d->bulletin ? strlen(d->bulletin) : 0;
	if (blen)
		memcpy(out + 5, d->bulletin, blen < 11 ? blen : 11);
	out[18] = (uint8_t)(d->mode & 0x1F);
	out[22] = d->ram_kb;
	out[23] = d->owner;
	return 24;
}
