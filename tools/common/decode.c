/* SPDX-License-Identifier: MPL-2.0 */
/*
 * decode - one decoded DF1 symbol as one line of text (see decode.h).
 *
 * Plain line (columns separated by two spaces, trailing blanks trimmed):
 *   INDEX [TIME] [DIR] KIND  CHECK  dst D  src S  tns XXXX  CMD[/FNC]  NAME  DETAIL...
 * JSON: one object per line with the same fields.
 */
#include "common/decode.h"
#include "common/decode_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_VALUES 160
#define NAME_WIDTH 26

static const char *kind_name(enum df1_sym k)
{
	switch (k) {
	case DF1_SYM_ACK: return "ACK";
	case DF1_SYM_NAK: return "NAK";
	case DF1_SYM_ENQ: return "ENQ";
	case DF1_SYM_EOT: return "EOT";
	case DF1_SYM_POLL: return "POLL";
	case DF1_SYM_FRAME: return "FRAME";
	case DF1_SYM_ERROR: return "ERROR";
	default: return "NONE";
	}
}

void decode_ctx_init(struct decode_ctx *x, enum cli_format format)
{
	memset(x, 0, sizeof *x);
	x->format = format == CLI_FMT_JSON ? CLI_FMT_JSON : CLI_FMT_PLAIN;
}

void decode_forget(struct decode_ctx *x)
{
	memset(x->cmds, 0, sizeof x->cmds);
}

/* "SLC typed read, 3 fields (0F/A2)" -> "SLC typed read, 3 fields": the code has
 * its own column. */
static void strip_code(const char *name, char *buf, size_t cap)
{
	size_t n = strlen(name);
	const char *open = strrchr(name, '(');

	snprintf(buf, cap, "%s", name);
	if (!open || n < 4 || name[n - 1] != ')' || open == name || open[-1] != ' ')
		return;
	for (const char *p = open + 1; p < name + n - 1; p++)
		if (!strchr("0123456789ABCDEFabcdef/", *p))
			return;
	if ((size_t)(open - 1 - name) < cap)
		buf[open - 1 - name] = 0;
}

/* ---- output helpers ---- */

static void put_hex(FILE *f, const uint8_t *b, size_t n)
{
	for (size_t i = 0; i < n; i++)
		fprintf(f, i ? " %02X" : "%02X", b[i]);
}

/* A value in plain text: "13385", "1.5", "\"text\"", "{EN=1 TT=0 DN=1 PRE=10 ACC=3}". */
static void put_value_plain(FILE *f, const struct df1_value *v, enum df1_file_type ft)
{
	char buf[256];

	if (df1_value_format(v, ft, buf, sizeof buf) < 0)
		snprintf(buf, sizeof buf, "?");
	if (v->kind == DF1_VAL_STRING)
		cli_json_string(f, buf);
	else if (v->kind == DF1_VAL_TCR)
		fprintf(f, "{%s}", buf);
	else
		fputs(buf, f);
}

static void put_value_json(FILE *f, const struct df1_value *v, enum df1_file_type ft)
{
	char buf[256];

	switch (v->kind) {
	case DF1_VAL_STRING:
		if (df1_value_format(v, ft, buf, sizeof buf) < 0)
			buf[0] = 0;
		cli_json_string(f, buf);
		return;
	case DF1_VAL_TCR:
		fprintf(f, "{\"ctl\":%u,\"pre\":%d,\"acc\":%d}", (unsigned)v->v.tcr.ctl, v->v.tcr.pre,
		        v->v.tcr.acc);
		return;
	case DF1_VAL_FLOAT:
		if (!isfinite(v->v.f) || df1_value_format(v, ft, buf, sizeof buf) < 0)
			fputs("null", f);
		else
			fputs(buf, f);
		return;
	case DF1_VAL_BIT:
		fputs(v->v.bit ? "1" : "0", f);
		return;
	case DF1_VAL_INT16:
		fprintf(f, "%d", v->v.i16);
		return;
	case DF1_VAL_INT32:
		fprintf(f, "%ld", (long)v->v.i32);
		return;
	}
	fputs("null", f);
}

/* ---- the decoded content of one frame ---- */

struct frame_view {
	bool ok;                       /* df1_msg_decode succeeded */
	struct df1_msg m;
	const struct decode_cmd *orig; /* for a reply: the command it answers */
	char name[112];
	char cmdtext[8];               /* "0F/A2", "4F" */
	bool has_addr;
	char addr[64];
	int size;
	/* values */
	enum df1_file_type ft;
	struct df1_value vals[MAX_VALUES];
	int nvals;
	/* masks: AB masked write (mask then data), 26 read-modify-write (AND, OR) */
	const char *mask_kind;
	const uint8_t *masks;
	size_t masks_len;
	/* data not decoded as values */
	const uint8_t *raw;
	size_t raw_len;
	bool has_sts;                  /* a reply */
	bool bad_reply;                /* a reply df1_msg_decode found malformed */
	bool has_owner;                /* EXT STS 1A/1B of CMD 0B/1A/1B: the owner's node */
	uint8_t owner;
	char error[256];
	uint8_t swapped[256];          /* PLC-5 word-range floats with their words put back */
	bool has_bit_addr;             /* a one-bit write: the address with its bit */
	struct df1_addr bit_addr;
};

static struct decode_cmd *cmd_find(struct decode_ctx *x, const struct df1_msg *reply)
{
	struct decode_cmd *best = NULL;

	for (int i = 0; i < DECODE_CMDS; i++) {
		struct decode_cmd *c = &x->cmds[i];
		if (!c->used || c->tns != reply->tns || (c->cmd | 0x40) != reply->cmd)
			continue;
		/* exact: the reply's DST/SRC are the command's SRC/DST */
		if (c->dst == reply->src && c->src == reply->dst)
			return c;
		/* else the newest with that TNS (a bridge may rewrite SRC, doc/PROTOCOL.md 1.9) */
		if (!best || c->age > best->age)
			best = c;
	}
	return best;
}

static void cmd_remember(struct decode_ctx *x, const struct df1_msg *m, const struct df1_addr *addr,
                         const char *label, enum df1_file_type ft)
{
	struct decode_cmd *slot = NULL;
	int i;

	/* the same command again (a retransmission) replaces itself */
	for (i = 0; i < DECODE_CMDS && !slot; i++) {
		struct decode_cmd *c = &x->cmds[i];
		if (c->used && c->tns == m->tns && c->dst == m->dst && c->src == m->src)
			slot = c;
	}
	/* else a free slot, else the oldest */
	for (i = 0; i < DECODE_CMDS && !slot; i++)
		if (!x->cmds[i].used)
			slot = &x->cmds[i];
	if (!slot) {
		slot = &x->cmds[0];
		for (i = 1; i < DECODE_CMDS; i++)
			if (x->cmds[i].age < slot->age)
				slot = &x->cmds[i];
	}
	memset(slot, 0, sizeof *slot);
	slot->used = true;
	slot->dst = m->dst;
	slot->src = m->src;
	slot->cmd = m->cmd;
	slot->fnc = m->fnc;
	slot->has_fnc = m->has_fnc;
	slot->tns = m->tns;
	snprintf(slot->label, sizeof slot->label, "%.95s", label);
	slot->has_addr = m->has_addr;
	slot->addr = *addr;
	slot->size = m->size;
	slot->ft = ft;
	slot->age = ++x->clock;
}

/* A PLC-3 command (df1_msg_decode names them "PLC-3 ..."): its address is in
 * a PLC-3's text and its floats go low word first (doc/PROTOCOL.md 4.2a). */
static bool is_plc3(const char *name)
{
	return name && strncmp(name, "PLC-3", 5) == 0;
}

static void format_addr(const struct df1_addr *a, bool plc3, char *buf, size_t cap)
{
	if (a->ascii[0]) {
		snprintf(buf, cap, "$%s", a->ascii);
		return;
	}
	if (plc3 && df1_addr_format_plc(DF1_PLC_PLC3, a, buf, cap) >= 0)
		return;
	if (a->type != DF1_FT_NONE && df1_addr_format(a, buf, cap) >= 0)
		return;
	/* a PLC-5 binary address carries no file type */
	if (a->sub != DF1_ADDR_NONE && a->bit != DF1_ADDR_NONE)
		snprintf(buf, cap, "file %d:%d.%d/%d", a->file, a->element, a->sub, a->bit);
	else if (a->sub != DF1_ADDR_NONE)
		snprintf(buf, cap, "file %d:%d.%d", a->file, a->element, a->sub);
	else if (a->bit != DF1_ADDR_NONE)
		snprintf(buf, cap, "file %d:%d/%d", a->file, a->element, a->bit);
	else
		snprintf(buf, cap, "file %d:%d", a->file, a->element);
}

static void decode_values(struct frame_view *v, enum df1_file_type ft, const uint8_t *p, size_t n)
{
	int k;

	v->ft = ft;
	if (n == 0)
		return;
	k = df1_values_decode(ft, p, n, v->vals, MAX_VALUES);
	if (k <= 0 && ft != DF1_FT_N && n % 2 == 0) {
		/* not whole elements of that type: show the words */
		v->ft = DF1_FT_N;
		k = df1_values_decode(DF1_FT_N, p, n, v->vals, MAX_VALUES);
	}
	if (k <= 0) {
		v->raw = p;
		v->raw_len = n;
		return;
	}
	v->nvals = k;
}

/* PLC-5 word range read / write (0F/01, 0F/00): a float goes high-order word
 * first, each word LE (doc/PROTOCOL.md 5): 1.5 is C0 3F 00 00. Other types are plain words. */
static void decode_word_range(struct frame_view *v, enum df1_file_type ft, const uint8_t *p, size_t n,
                              bool plc3)
{
	if (!plc3 && ft == DF1_FT_F && n >= 4 && n % 4 == 0 && n <= sizeof v->swapped) {
		for (size_t i = 0; i < n; i += 4) {
			v->swapped[i] = p[i + 2];
			v->swapped[i + 1] = p[i + 3];
			v->swapped[i + 2] = p[i];
			v->swapped[i + 3] = p[i + 1];
		}
		p = v->swapped;
	}
	decode_values(v, ft, p, n);
}

/* The one bit a masked write changes: mask (and data) of 2 or 4 bytes, LE, with a
 * single bit set. Returns the bit number or -1. */
static int single_bit(const uint8_t *mask, size_t n)
{
	uint32_t m = 0;
	int bit = -1;

	if (n != 2 && n != 4)
		return -1;
	for (size_t i = 0; i < n; i++)
		m |= (uint32_t)mask[i] << (8 * i);
	if (m == 0 || (m & (m - 1)) != 0)
		return -1;
	while (m) {
		m >>= 1;
		bit++;
	}
	return bit;
}

/* A write of one bit (SLC 0F/AB with a one-bit mask, PLC-5 0F/26 AND FFFF OR bit
 * or AND ~bit OR 0, 0F/02 SET bit or RESET bit): the bit joins the address, as the
 * user wrote it (B3:0/5, T4:0/DN), and its value is shown. The masks stay too. */
static void view_bit_write(struct frame_view *v)
{
	const struct df1_msg *m = &v->m;
	const uint8_t *d = m->data;
	struct df1_addr a = m->addr;
	char buf[64];
	int bit = -1, on = 0;

	if (!m->has_addr || m->addr.ascii[0] || m->addr.bit != DF1_ADDR_NONE)
		return;
	if (m->fnc == 0xAB && m->size > 0 && m->data_len == 2 * (size_t)m->size) {
		bit = single_bit(d, (size_t)m->size);
		if (bit >= 0)
			on = (d[m->size + bit / 8] >> (bit % 8)) & 1;
	} else if ((m->fnc == 0x26 || m->fnc == 0x02) && m->data_len == 4) {
		uint16_t w1 = (uint16_t)(d[0] | (d[1] << 8)), w2 = (uint16_t)(d[2] | (d[3] << 8));
		int b1 = single_bit(d, 2), b2 = single_bit(d + 2, 2);

		if (m->fnc == 0x26) {           /* AND, OR */
			uint8_t inv[2] = { (uint8_t)~d[0], (uint8_t)~d[1] };
			int b0 = single_bit(inv, 2);

			if (w1 == 0xFFFF && b2 >= 0) {
				bit = b2;
				on = 1;
			} else if (w2 == 0 && b0 >= 0) {
				bit = b0;
			}
		} else if (b1 >= 0 && w2 == 0) {   /* SET, RESET */
			bit = b1;
			on = 1;
		} else if (w1 == 0 && b2 >= 0) {
			bit = b2;
		}
	}
	if (bit < 0)
		return;
	/* a T/C/R bit lives in a word of the element: the control word unless named */
	if ((a.type == DF1_FT_T || a.type == DF1_FT_C || a.type == DF1_FT_R) && a.sub == DF1_ADDR_NONE)
		a.sub = 0;
	a.bit = bit;
	if (a.type != DF1_FT_NONE &&
	    df1_addr_format_plc(is_plc3(m->name) ? DF1_PLC_PLC3 : DF1_PLC_SLC, &a, buf, sizeof buf) < 0)
		return;                         /* a type without bits (F, ST): leave it */
	format_addr(&a, is_plc3(m->name), v->addr, sizeof v->addr);
	v->bit_addr = a;
	v->has_bit_addr = true;
	memset(&v->vals[0], 0, sizeof v->vals[0]);
	v->vals[0].kind = DF1_VAL_BIT;
	v->vals[0].v.bit = on != 0;
	v->nvals = 1;
	v->ft = a.type;
}

/* Command data: the values written, masks, or raw bytes. */
static void view_command_data(struct frame_view *v, const uint8_t *app)
{
	const struct df1_msg *m = &v->m;
	const uint8_t *d = m->data;
	size_t n = m->data_len;
	enum df1_file_type ft = m->has_addr ? decode_value_file_type(&m->addr) : DF1_FT_N;

	if (!d || n == 0)
		return;
	if (m->cmd == 0x0F && m->has_fnc) {
		switch (m->fnc) {
		case 0xA9: case 0xAA:              /* SLC writes */
			decode_values(v, ft, d, n);
			return;
		case 0x00:                         /* word range write */
			decode_word_range(v, ft, d, n, is_plc3(m->name));
			return;
		case 0x67:                         /* typed write */
			if (decode_typedata_before(app, d, &ft)) {
				decode_values(v, ft, d, n);
				return;
			}
			break;
		case 0xAB:
			v->mask_kind = "mask/data";
			v->masks = d;
			v->masks_len = n;
			view_bit_write(v);
			return;
		case 0x26:
			v->mask_kind = "and/or";
			v->masks = d;
			v->masks_len = n;
			view_bit_write(v);
			return;
		case 0x02:
			v->mask_kind = "set/reset";
			v->masks = d;
			v->masks_len = n;
			view_bit_write(v);
			return;
		default:
			break;
		}
	} else if (m->cmd == 0x08 || m->cmd == 0x00) {  /* PLC-2 writes: words */
		decode_values(v, DF1_FT_N, d, n);
		return;
	}
	v->raw = d;
	v->raw_len = n;
}

/* Reply data: the values read (with the command's file type), or raw bytes. */
static void view_reply_data(struct frame_view *v)
{
	const struct df1_msg *m = &v->m;
	const struct decode_cmd *c = v->orig;
	const uint8_t *d = m->data;
	size_t n = m->data_len;
	enum df1_file_type ft;
	int k;

	if (!d || n == 0 || m->sts != 0)
		return;
	if (c && c->cmd == 0x0F && c->has_fnc) {
		switch (c->fnc) {
		case 0xA1: case 0xA2:
			decode_values(v, c->ft, d, n);
			return;
		case 0x01:                          /* word range read */
			decode_word_range(v, c->ft, d, n, is_plc3(c->label));
			return;
		case 0x68:
			k = decode_typedata_skip(d, n, &ft);
			if (k > 0 && (size_t)k <= n) {
				decode_values(v, ft, d + k, n - (size_t)k);
				return;
			}
			break;
		default:
			break;
		}
	} else if (c && c->cmd == 0x01) {   /* PLC-2 unprotected read: words */
		decode_values(v, DF1_FT_N, d, n);
		return;
	}
	v->raw = d;
	v->raw_len = n;
}

static void build_view(struct decode_ctx *x, const struct df1_symbol *s, bool remember,
                       struct frame_view *v)
{
	struct df1_msg *m = &v->m;
	int r;

	memset(v, 0, sizeof *v);
	v->size = -1;
	r = df1_msg_decode(s->data, s->len, m);
	if (r < 0 && s->len < 6) {
		snprintf(v->error, sizeof v->error, "message too short (%zu bytes)", s->len);
		return;
	}
	v->ok = true;
	strip_code(m->name ? m->name : "unknown command", v->name, sizeof v->name);
	if (r < 0)
		snprintf(v->error, sizeof v->error, "%s: %s", df1_errname(r), df1_strerror(r));
	if (!m->is_reply) {
		if (m->has_fnc)
			snprintf(v->cmdtext, sizeof v->cmdtext, "%02X/%02X", m->cmd, m->fnc);
		else
			snprintf(v->cmdtext, sizeof v->cmdtext, "%02X", m->cmd);
		if (m->has_addr) {
			v->has_addr = true;
			format_addr(&m->addr, is_plc3(m->name), v->addr, sizeof v->addr);
		} else if ((m->cmd == 0x01 || m->cmd == 0x08 || m->cmd == 0x00) && s->len >= 8) {
			/* PLC-2: a byte address, not a data-table address */
			v->has_addr = true;
			snprintf(v->addr, sizeof v->addr, "byte 0x%04X",
			         (unsigned)(s->data[6] | (s->data[7] << 8)));
		}
		v->size = m->size;
		if (r >= 0) {
			view_command_data(v, s->data);
			if (remember)
				cmd_remember(x, m, v->has_bit_addr ? &v->bit_addr : &m->addr, v->name,
				             m->has_addr ? decode_value_file_type(&m->addr) : DF1_FT_N);
		} else if (m->data && m->data_len) {
			v->raw = m->data;
			v->raw_len = m->data_len;
		}
		return;
	}

	snprintf(v->cmdtext, sizeof v->cmdtext, "%02X", m->cmd);
	v->has_sts = true;
	v->orig = cmd_find(x, m);
	if (v->orig) {
		if (v->orig->has_fnc)
			snprintf(v->name, sizeof v->name, "reply to %02X/%02X", v->orig->cmd, v->orig->fnc);
		else
			snprintf(v->name, sizeof v->name, "reply to %02X", v->orig->cmd);
		if (v->orig->has_addr) {
			v->has_addr = true;
			format_addr(&v->orig->addr, is_plc3(v->orig->label), v->addr, sizeof v->addr);
			v->size = v->orig->size;
		}
	} else {
		snprintf(v->name, sizeof v->name, "reply");
	}
	if (m->sts != 0) {
		char bad[96];

		/* a reply that cannot be what it claims (STS F0 without its EXT STS byte,
		 * EXT STS 1A/1B without the owner byte) says so after the PLC's texts */
		if (r < 0)
			snprintf(bad, sizeof bad, "; %s: %s", df1_errname(r), df1_strerror(r));
		else
			bad[0] = 0;
		if (m->has_ext_sts) {
			uint8_t c = (uint8_t)(m->cmd & ~0x40);
			bool dh485 = c == 0x0B || c == 0x1A || c == 0x1B;
			const char *ext = dh485 ? df1_ext_sts_text_dh485(m->ext_sts)
			                        : df1_ext_sts_text(m->ext_sts);
			char owner[32] = "";

			/* DH-485 EXT STS 1A/1B: the owner's node follows (doc/PROTOCOL.md 3.4) */
			if (r >= 0 && dh485 && (m->ext_sts == 0x1A || m->ext_sts == 0x1B) && s->len > 7) {
				v->has_owner = true;
				v->owner = s->data[7];
				snprintf(owner, sizeof owner, " (owner: node %u)", v->owner);
			}
			snprintf(v->error, sizeof v->error, "STS %02X: %s; EXT STS %02X: %s%s%s", m->sts,
			         df1_sts_text(m->sts), m->ext_sts, ext, owner, bad);
		} else {
			snprintf(v->error, sizeof v->error, "STS %02X: %s%s", m->sts, df1_sts_text(m->sts),
			         bad);
		}
	}
	v->bad_reply = r < 0;
	if (r >= 0)
		view_reply_data(v);
}

static const char *check_name(const struct df1_symbol *s)
{
	return (s->check == DF1_CHECK_BCC || s->kind == DF1_SYM_POLL) ? "BCC" : "CRC";
}

static void fmt_check_value(const struct df1_symbol *s, uint16_t v, char *buf, size_t cap)
{
	if (s->check == DF1_CHECK_BCC || s->kind == DF1_SYM_POLL)
		snprintf(buf, cap, "0x%02X", (unsigned)(v & 0xFF));
	else
		snprintf(buf, cap, "0x%04X", (unsigned)v);
}

/* "BCC ok" or "CRC bad expected 0x1234 actual 0x4321" */
static void fmt_check(const struct df1_symbol *s, char *buf, size_t cap)
{
	char e[16], a[16];

	if (s->check_ok) {
		snprintf(buf, cap, "%s ok", check_name(s));
		return;
	}
	fmt_check_value(s, s->check_expected, e, sizeof e);
	fmt_check_value(s, s->check_actual, a, sizeof a);
	snprintf(buf, cap, "%s bad expected %s actual %s", check_name(s), e, a);
}

static const char *error_text(int id, uint8_t bad_byte, char *buf, size_t cap)
{
	switch (id) {
	case DF1_ID_ERR_BAD_BCC: return "poll with wrong BCC";
	case DF1_ID_NTC_RCVD_MSG_TOO_LONG: return "received message too long";
	case DF1_ID_NTC_RCVD_MSG_TOO_SHORT: return "received message too short";
	case DF1_ID_NTC_INVALID_SYMBOL:
		snprintf(buf, cap, "invalid symbol received after DLE (0x%02X)", bad_byte);
		return buf;
	case DF1_ID_NTC_NO_ETX_RCVD: return "incomplete message, no ETX received";
	default: {
		const struct df1_catalog_entry *e = df1_catalog_by_id(id);
		return e && e->description ? e->description : "malformed input";
	}
	}
}

static void error_tag(int id, char *buf, size_t cap)
{
	const struct df1_catalog_entry *e = id ? df1_catalog_by_id(id) : NULL;

	if (e)
		snprintf(buf, cap, "[%d] %s", id, e->mnemonic);
	else if (id)
		snprintf(buf, cap, "[%d]", id);
	else
		snprintf(buf, cap, "error");
}

/* ---- the two line formats ---- */

static void plain_lead(struct decode_ctx *x, FILE *f, const struct decode_where *w, const char *kind)
{
	fprintf(f, "%5lu", w->index);
	if (x->show_time || w->has_time) {
		char t[32];
		if (w->has_time)
			snprintf(t, sizeof t, "%lld.%06d", (long long)w->rel_sec, (int)w->rel_usec);
		else
			t[0] = 0;
		fprintf(f, "  %11s", t);
	}
	if (x->show_dir || w->dir)
		fprintf(f, "  %-2s", w->dir ? w->dir : "");
	fprintf(f, "  %-5s", kind);
}

static void plain_values(FILE *f, const struct frame_view *v)
{
	if (v->nvals > 0) {
		fputs("  =", f);
		for (int i = 0; i < v->nvals; i++) {
			fputc(' ', f);
			put_value_plain(f, &v->vals[i], v->ft);
		}
	}
	if (v->masks) {
		size_t half = v->masks_len / 2;
		fprintf(f, "  %s ", v->mask_kind);
		if (v->m.fnc == 0xAB && v->masks_len % 2 == 0) {
			put_hex(f, v->masks, half);
			fputs(" / ", f);
			put_hex(f, v->masks + half, half);
		} else {
			put_hex(f, v->masks, v->masks_len);
		}
	}
	if (v->raw && v->raw_len) {
		fputs("  data ", f);
		put_hex(f, v->raw, v->raw_len);
	}
}

static void plain_frame(struct decode_ctx *x, FILE *f, const struct decode_where *w,
                        const struct df1_symbol *s, const struct frame_view *v)
{
	char chk[64];

	plain_lead(x, f, w, "FRAME");
	fmt_check(s, chk, sizeof chk);
	fprintf(f, "  %-6s", chk);
	if (!v->ok) {
		fprintf(f, "  error: %s  bytes ", v->error);
		put_hex(f, s->data, s->len);
		return;
	}
	fprintf(f, "  dst %3u  src %3u  tns %04X  %-5s  %-*s", v->m.dst, v->m.src, v->m.tns,
	        v->cmdtext, NAME_WIDTH, v->name);
	if (v->has_addr) {
		fprintf(f, "  %s", v->addr);
		if (v->size >= 0)
			fprintf(f, " size %d", v->size);
	}
	if (v->has_sts) {
		fprintf(f, "  sts %02X", v->m.sts);
		if (v->m.sts == 0)
			fprintf(f, " (%s)", df1_sts_text(0));  /* else error: gives the texts */
		if (v->m.has_ext_sts)
			fprintf(f, " ext %02X", v->m.ext_sts);
		if (v->has_owner)
			fprintf(f, " owner %u", v->owner);
	}
	if (v->error[0])
		fprintf(f, "  error: %s", v->error);
	plain_values(f, v);
	if (s->master_msg && s->has_station)
		fprintf(f, "  (master message to stn %u)", s->station);
	if (w->copy_of)
		fprintf(f, "  %s of #%lu%s", w->copy_relay ? "relay" : "repeat", w->copy_of,
		        w->copy_duplicate ? " (duplicate)" : "");
}

static void json_lead(FILE *f, const struct decode_where *w, const char *kind)
{
	fprintf(f, "{\"n\":%lu", w->index);
	if (w->has_time)
		fprintf(f, ",\"t\":%lld.%06d", (long long)w->rel_sec, (int)w->rel_usec);
	if (w->has_epoch)
		fprintf(f, ",\"epoch\":%lld.%06d", (long long)w->epoch_sec, (int)w->epoch_usec);
	if (w->dir)
		fprintf(f, ",\"dir\":\"%s\"", w->dir);
	fprintf(f, ",\"kind\":\"%s\"", kind);
}

static void json_check(FILE *f, const struct df1_symbol *s)
{
	char e[16], a[16];

	fprintf(f, ",\"check\":\"%s\",\"check_ok\":%s", check_name(s), s->check_ok ? "true" : "false");
	if (!s->check_ok) {
		fmt_check_value(s, s->check_expected, e, sizeof e);
		fmt_check_value(s, s->check_actual, a, sizeof a);
		fprintf(f, ",\"expected\":\"%s\",\"actual\":\"%s\"", e, a);
	}
}

static void json_hex(FILE *f, const char *key, const uint8_t *b, size_t n)
{
	fprintf(f, ",\"%s\":\"", key);
	put_hex(f, b, n);
	fputc('"', f);
}

static void json_frame(FILE *f, const struct decode_where *w, const struct df1_symbol *s,
                       const struct frame_view *v)
{
	const struct df1_msg *m = &v->m;

	json_lead(f, w, "FRAME");
	json_check(f, s);
	if (s->master_msg && s->has_station)
		fprintf(f, ",\"master\":true,\"station\":%u", s->station);
	if (v->ok) {
		fprintf(f, ",\"dst\":%u,\"src\":%u,\"cmd\":\"%02X\"", m->dst, m->src, m->cmd);
		if (m->has_fnc)
			fprintf(f, ",\"fnc\":\"%02X\"", m->fnc);
		fprintf(f, ",\"reply\":%s,\"name\":", m->is_reply ? "true" : "false");
		cli_json_string(f, v->name);
		fprintf(f, ",\"tns\":\"%04X\"", m->tns);
		if (v->orig) {
			fputs(",\"reply_to\":", f);
			cli_json_string(f, v->orig->label);
		}
		if (v->has_sts) {
			fprintf(f, ",\"sts\":\"%02X\",\"sts_text\":", m->sts);
			cli_json_string(f, df1_sts_text(m->sts));
			if (m->has_ext_sts) {
				uint8_t c = (uint8_t)(m->cmd & ~0x40);
				fprintf(f, ",\"ext_sts\":\"%02X\",\"ext_sts_text\":", m->ext_sts);
				cli_json_string(f, (c == 0x0B || c == 0x1A || c == 0x1B)
				                           ? df1_ext_sts_text_dh485(m->ext_sts)
				                           : df1_ext_sts_text(m->ext_sts));
			}
			if (v->has_owner)
				fprintf(f, ",\"owner\":%u", v->owner);
		}
		if (v->has_addr) {
			fputs(",\"address\":", f);
			cli_json_string(f, v->addr);
		}
		if (v->size >= 0)
			fprintf(f, ",\"size\":%d", v->size);
		if (v->nvals > 0) {
			fputs(",\"values\":[", f);
			for (int i = 0; i < v->nvals; i++) {
				if (i)
					fputc(',', f);
				put_value_json(f, &v->vals[i], v->ft);
			}
			fputc(']', f);
		}
		if (v->masks) {
			size_t half = v->masks_len / 2;
			if (m->fnc == 0xAB && v->masks_len % 2 == 0) {
				json_hex(f, "mask", v->masks, half);
				json_hex(f, "data", v->masks + half, half);
			} else {
				json_hex(f, "masks", v->masks, v->masks_len);
			}
		}
		if (v->raw && v->raw_len)
			json_hex(f, "data", v->raw, v->raw_len);
	}
	if (v->error[0]) {
		fputs(",\"error\":", f);
		cli_json_string(f, v->error);
	}
	if (w->copy_of)
		fprintf(f, ",\"copy_of\":%lu,\"relay\":%s,\"duplicate\":%s", w->copy_of,
		        w->copy_relay ? "true" : "false", w->copy_duplicate ? "true" : "false");
	json_hex(f, "bytes", s->data, s->len);
	fputc('}', f);
}

/* Write the buffered line(s) to out, each prefixed, trailing blanks trimmed. */
static void emit(FILE *out, const char *prefix, const char *text, size_t len)
{
	const char *p = text, *end = text + len;

	while (p < end) {
		const char *nl = memchr(p, '\n', (size_t)(end - p));
		const char *e = nl ? nl : end;
		while (e > p && (e[-1] == ' ' || e[-1] == '\t'))
			e--;
		if (prefix)
			fputs(prefix, out);
		fwrite(p, 1, (size_t)(e - p), out);
		fputc('\n', out);
		p = nl ? nl + 1 : end;
	}
}

static void print_error(struct decode_ctx *x, FILE *f, const struct decode_where *w, int id,
                        const char *text, const struct df1_symbol *s)
{
	char tag[64], full[320], chk[64];
	bool has_check = s && (id == DF1_ID_ERR_BAD_BCC || id == DF1_ID_NTC_RCVD_MSG_TOO_LONG ||
	                       id == DF1_ID_NTC_RCVD_MSG_TOO_SHORT);

	error_tag(id, tag, sizeof tag);
	snprintf(full, sizeof full, "%s: %s", tag, text);
	if (x->format == CLI_FMT_JSON) {
		json_lead(f, w, "ERROR");
		if (has_check)
			json_check(f, s);
		if (s && s->has_station)
			fprintf(f, ",\"station\":%u", s->station);
		fprintf(f, ",\"error_id\":%d,\"error\":", id);
		cli_json_string(f, full);
		if (s && s->data && s->len)
			json_hex(f, "bytes", s->data, s->len);
		fputc('}', f);
		return;
	}
	plain_lead(x, f, w, "ERROR");
	if (has_check)
		fmt_check(s, chk, sizeof chk);
	else
		chk[0] = 0;
	fprintf(f, "  %-6s  %s", chk, full);
	if (s && s->has_station)
		fprintf(f, "  stn %u", s->station);
	if (s && s->data && s->len) {
		fputs("  bytes ", f);
		put_hex(f, s->data, s->len);
	}
}

bool decode_print(struct decode_ctx *x, FILE *out, const char *prefix, const struct decode_where *w,
                  const struct df1_symbol *s)
{
	char *text = NULL, buf[160], chk[64];
	size_t len = 0;
	FILE *f;
	bool bad = false;
	struct frame_view *v;

	if (s->kind == DF1_SYM_NONE)
		return false;
	f = open_memstream(&text, &len);
	if (!f)
		return false;
	switch (s->kind) {
	case DF1_SYM_FRAME:
		x->frames++;
		v = malloc(sizeof *v);
		if (!v)
			break;
		build_view(x, s, s->check_ok, v);
		if (!s->check_ok) {
			x->bad++;
			bad = true;
		} else if (!v->ok || (v->error[0] && !v->has_sts) || v->bad_reply) {
			x->errors++;  /* a good check around a malformed message */
			bad = true;
		} else {
			x->good++;
		}
		if (x->format == CLI_FMT_JSON) {
			json_frame(f, w, s, v);
		} else {
			plain_frame(x, f, w, s, v);
			if (x->verbose > 0) {
				fputs("\n       bytes ", f);
				put_hex(f, s->data, s->len);
			}
		}
		free(v);
		break;
	case DF1_SYM_ERROR:
		if (s->error == DF1_ID_ERR_BAD_BCC) {
			x->symbols++;
			x->bad++;
		} else if (s->error == DF1_ID_NTC_RCVD_MSG_TOO_LONG ||
		           s->error == DF1_ID_NTC_RCVD_MSG_TOO_SHORT) {
			x->frames++;
			if (s->check_ok) {
				x->errors++;
			} else {
				x->bad++;
			}
		} else {
			x->errors++;
		}
		bad = true;
		print_error(x, f, w, s->error, error_text(s->error, s->bad_byte, buf, sizeof buf), s);
		break;
	case DF1_SYM_POLL:
		x->symbols++;
		if (x->format == CLI_FMT_JSON) {
			json_lead(f, w, "POLL");
			json_check(f, s);
			fprintf(f, ",\"station\":%u}", s->station);
		} else {
			plain_lead(x, f, w, "POLL");
			fmt_check(s, chk, sizeof chk);
			fprintf(f, "  %-6s  stn %3u", chk, s->station);
		}
		break;
	case DF1_SYM_ACK: case DF1_SYM_NAK: case DF1_SYM_ENQ: case DF1_SYM_EOT:
		x->symbols++;
		if (x->format == CLI_FMT_JSON) {
			json_lead(f, w, kind_name(s->kind));
			if (s->embedded)
				fputs(",\"embedded\":true", f);
			fputc('}', f);
		} else {
			plain_lead(x, f, w, kind_name(s->kind));
			if (s->embedded)
				fprintf(f, "  %-6s  (embedded in a frame)", "");
		}
		break;
	default:
		break;
	}
	fclose(f);
	if (text && len)
		emit(out, prefix, text, len);
	free(text);
	return bad;
}

void decode_print_error(struct decode_ctx *x, FILE *out, const char *prefix,
                        const struct decode_where *w, int catalog_id, const char *text)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);

	x->errors++;
	if (!f)
		return;
	print_error(x, f, w, catalog_id, text, NULL);
	fclose(f);
	if (buf && len)
		emit(out, prefix, buf, len);
	free(buf);
}
