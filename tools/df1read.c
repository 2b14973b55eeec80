/*
 * df1read - read data-table values from a DF1 controller, for shell scripts
 * (DESIGN.md 8, df1read(1)).
 *
 *   df1read [OPTIONS] ADDRESS[,COUNT]...
 *
 * Every operand is checked before the device is opened (exit 2). The reads are
 * planned so that they take as few transactions as the packet limits allow:
 * the element ranges of one file that overlap or touch are read as one block
 * (one df1_read_addr call, which the library splits into packets), and on the
 * SLC family and PLC-2, ranges with a gap between them are joined when that
 * saves at least one packet. Bits and T/C/R words are taken from the words or
 * elements read. I/O addresses and PLC-5 "$" addresses are read on their own.
 * When a joined block is refused by the PLC, its operands are read one by one
 * so that the error names the operand at fault.
 *
 * All or nothing: everything is read first, then printed; on any failure
 * stdout stays empty and the exit status is 1.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "df1.h"

#define VALUE_TEXT_MAX 200

/* How an operand's values come out of its block. */
enum extract {
	EX_DIRECT = 0,  /* not in a block: read on its own */
	EX_ELEM,        /* whole elements */
	EX_TCR_WORD,    /* one word (.0 .PRE .ACC ...) of consecutive T/C/R elements */
	EX_TCR_BITS,    /* bits of one word of one T/C/R element */
	EX_WORD_BITS,   /* bits of consecutive 16-bit words (32-bit for L) */
};

struct item {
	const char *text;           /* the address as typed (operand up to ',') */
	char text_buf[CLI_ADDR_TEXT_MAX];
	struct df1_addr a;
	size_t n;                   /* values */
	enum extract ex;
	int lo, hi;                 /* element range of a block operand */
	int block;                  /* index into blocks, -1 for EX_DIRECT */
	struct df1_value *vals;     /* n values, once read */
};

struct block {
	enum df1_file_type type;
	int file;
	int lo, hi;                 /* elements, inclusive */
	int first_item;             /* the earliest operand in it (messages, read order) */
	int nitems;
	int made;                   /* index while planning */
	struct df1_value *vals;     /* hi - lo + 1 */
};

struct rd {
	struct cli cli;
	struct item *items;
	size_t nitems;
	struct block *blocks;
	size_t nblocks;
	unsigned reads;             /* df1_read_addr calls */
};

static const struct cli_tool read_tool = {
	.name = "df1read",
	.synopsis = "[OPTIONS] ADDRESS[,COUNT]...",
	.summary = "Read data-table values from a DF1 controller (PLC-5, SLC 500, MicroLogix).",
	.accepts = CLI_ACCEPT_ALL,
	.formats = CLI_FMT_BIT(CLI_FMT_PLAIN) | CLI_FMT_BIT(CLI_FMT_CSV) | CLI_FMT_BIT(CLI_FMT_JSON),
	.check_auto = false,
	.extra = NULL,
	.on_extra = NULL,
	.help_tail =
		"\nAddresses: N7:0 N7:0,10 F8:3 L10:0 ST9:0 B3:0/5 B3/21 T4:0 T4:0.ACC T4:0/DN\n"
		"C5:1.PRE R6:0.POS S:1/5 I:0/3 O:0 A11:0 $N7:0 (PLC-5). COUNT elements\n"
		"(consecutive bits for a bit address) start at ADDRESS.\n"
		"Output: plain, one value per line; csv, a header and address,value rows;\n"
		"json, an array of {\"address\":..,\"value\":..}. Everything is read before\n"
		"anything is printed: on an error stdout stays empty.\n"
		"See df1read(1).\n",
	.exit_text = "0 success, 1 communication or PLC error (nothing printed),\n"
	             "2 usage, address or configuration error (nothing sent).",
};

/* ------------------------------------------------------------------------
 * Addresses
 * ------------------------------------------------------------------------ */

/* Text of value i's address: canonical, "$" kept for PLC-5 logical ASCII. */
static void addr_text(const struct df1_addr *a, size_t i, char *buf, size_t cap)
{
	struct df1_addr s;

	if (i == 0 && a->ascii[0]) {
		snprintf(buf, cap, "$%s", a->ascii);
		return;
	}
	if (!cli_addr_step(a, i, &s) || df1_addr_format(&s, buf + (a->ascii[0] ? 1 : 0),
	                                               cap - (a->ascii[0] ? 1 : 0)) < 0) {
		snprintf(buf, cap, "?");
		return;
	}
	if (a->ascii[0])
		buf[0] = '$';
}

/* One operand: ADDRESS[,COUNT]. */
static int parse_operand(struct rd *r, size_t idx, const char *arg)
{
	struct item *it = &r->items[idx];
	const char *comma = strchr(arg, ',');
	size_t alen = comma ? (size_t)(comma - arg) : strlen(arg);
	struct df1_addr last;
	int rc;

	memset(it, 0, sizeof *it);
	it->block = -1;
	it->n = 1;
	if (alen >= sizeof it->text_buf)
		return cli_address_error(&r->cli, (int)idx + 1, arg, DF1_E_ADDR_SYNTAX, 1);
	memcpy(it->text_buf, arg, alen);
	it->text_buf[alen] = '\0';
	it->text = it->text_buf;
	if (comma) {
		char *end;
		unsigned long v;

		errno = 0;
		v = strtoul(comma + 1, &end, 10);
		if (comma[1] < '0' || comma[1] > '9' || *end || errno || v == 0 || v > 16000) {
			fprintf(stderr, "%s: %s: invalid count '%s' (expected 1-16000)\n", r->cli.name, arg,
			        comma + 1);
			fprintf(stderr, "Try '%s --help'.\n", r->cli.name);
			return CLI_EXIT_USAGE;
		}
		it->n = v;
	}
	rc = df1_addr_parse(it->text, &it->a);
	if (rc < 0)
		return cli_address_error(&r->cli, (int)idx + 1, it->text, rc, it->n);
	/* every value's address must exist: N7:998,5 runs past element 999 */
	if (!cli_addr_step(&it->a, it->n - 1, &last))
		return cli_address_error(&r->cli, (int)idx + 1, it->text, DF1_E_ADDR_RANGE, it->n);
	return CLI_CONTINUE;
}

/* ------------------------------------------------------------------------
 * Planning: which elements each operand needs, and blocks
 * ------------------------------------------------------------------------ */

static void plan_item(struct item *it)
{
	const struct df1_addr *a = &it->a;

	it->ex = EX_DIRECT;
	if (a->ascii[0] || cli_is_io(a->type) || a->type == DF1_FT_NONE)
		return;
	if (a->bit == DF1_ADDR_NONE) {
		if (a->sub == DF1_ADDR_NONE)
			it->ex = EX_ELEM;
		else if (cli_is_tcr(a->type))
			it->ex = EX_TCR_WORD;
		else
			return;
		it->lo = a->element;
		it->hi = a->element + (int)it->n - 1;
		return;
	}
	if (cli_is_tcr(a->type)) {
		it->ex = EX_TCR_BITS;
		it->lo = it->hi = a->element;
		return;
	}
	if (a->sub != DF1_ADDR_NONE)
		return;
	it->ex = EX_WORD_BITS;
	it->lo = a->element;
	it->hi = a->element + (a->bit + (int)it->n - 1) / (a->type == DF1_FT_L ? 32 : 16);
}

/* Elements of a file type per read packet, for joining ranges across a gap;
 * 0 when not estimated (PLC-5: address and type/data sizes vary). */
static int elems_per_packet(const struct rd *r, df1_t *h, enum df1_file_type t)
{
	int es = df1_file_type_element_size(t), limit, opt;

	if (es <= 0)
		return 0;
	switch (r->cli.plc) {
	case DF1_PLC_SLC:
	case DF1_PLC_MICROLOGIX:
		limit = 236;
		break;
	case DF1_PLC_SLC502:
		limit = 82;
		break;
	case DF1_PLC_PLC2:
		limit = 244;
		break;
	default:
		return 0;
	}
	opt = h ? df1_get_option(h, DF1_OPT_MAX_PACKET) : 0;
	if (opt > 0)
		limit = opt < 244 ? opt : 244;
	return limit / es;
}

static int packets(int elems, int per)
{
	return (elems + per - 1) / per;
}

/* Sort key of a block operand: file type, file, first element. */
static int cmp_range(size_t ia, size_t ib, const struct item *items)
{
	const struct item *a = &items[ia], *b = &items[ib];

	if (a->a.type != b->a.type)
		return a->a.type < b->a.type ? -1 : 1;
	if (a->a.file != b->a.file)
		return a->a.file < b->a.file ? -1 : 1;
	if (a->lo != b->lo)
		return a->lo < b->lo ? -1 : 1;
	return (ia > ib) - (ia < ib);
}

/* insertion sort (operands are few); qsort has no context argument in C11 */
static void sort_ranges(size_t *idx, size_t n, const struct item *items)
{
	for (size_t i = 1; i < n; i++) {
		size_t v = idx[i], j = i;
		while (j > 0 && cmp_range(idx[j - 1], v, items) > 0) {
			idx[j] = idx[j - 1];
			j--;
		}
		idx[j] = v;
	}
}

static int cmp_block_order(const void *pa, const void *pb)
{
	const struct block *a = pa, *b = pb;
	return (a->first_item > b->first_item) - (a->first_item < b->first_item);
}

/* Group the block operands: ranges of one file that overlap or touch become one
 * block; across a gap only when that needs fewer packets. */
static int plan_blocks(struct rd *r, df1_t *h)
{
	size_t *idx = calloc(r->nitems ? r->nitems : 1, sizeof *idx), n = 0;
	int *map;

	if (!idx)
		return -1;
	for (size_t i = 0; i < r->nitems; i++) {
		plan_item(&r->items[i]);
		if (r->items[i].ex != EX_DIRECT)
			idx[n++] = i;
	}
	sort_ranges(idx, n, r->items);
	r->blocks = calloc(n ? n : 1, sizeof *r->blocks);
	if (!r->blocks) {
		free(idx);
		return -1;
	}
	r->nblocks = 0;
	for (size_t k = 0; k < n; k++) {
		struct item *it = &r->items[idx[k]];
		struct block *b = r->nblocks ? &r->blocks[r->nblocks - 1] : NULL;
		bool join = false;

		if (b && b->type == it->a.type && b->file == it->a.file) {
			if (it->lo <= b->hi + 1) {
				join = true;
			} else {
				int per = elems_per_packet(r, h, b->type);
				if (per > 0)
					join = packets(it->hi - b->lo + 1, per) <
					       packets(b->hi - b->lo + 1, per) + packets(it->hi - it->lo + 1, per);
			}
		}
		if (!join) {
			b = &r->blocks[r->nblocks++];
			memset(b, 0, sizeof *b);
			b->type = it->a.type;
			b->file = it->a.file;
			b->lo = it->lo;
			b->hi = it->hi;
			b->first_item = (int)idx[k];
		}
		if (it->hi > b->hi)
			b->hi = it->hi;
		if ((int)idx[k] < b->first_item)
			b->first_item = (int)idx[k];
		b->nitems++;
		it->block = (int)(b - r->blocks);
	}
	free(idx);
	/* read in the order the operands were given; renumber the operands' blocks */
	for (size_t i = 0; i < r->nblocks; i++)
		r->blocks[i].made = (int)i;
	qsort(r->blocks, r->nblocks, sizeof *r->blocks, cmp_block_order);
	map = calloc(r->nblocks ? r->nblocks : 1, sizeof *map);
	if (!map)
		return -1;
	for (size_t i = 0; i < r->nblocks; i++)
		map[r->blocks[i].made] = (int)i;
	for (size_t i = 0; i < r->nitems; i++)
		if (r->items[i].block >= 0)
			r->items[i].block = map[r->items[i].block];
	free(map);
	return 0;
}

/* ------------------------------------------------------------------------
 * Reading
 * ------------------------------------------------------------------------ */

static int16_t tcr_word(const struct df1_tcr *t, int sub)
{
	return sub == 0 ? (int16_t)t->ctl : sub == 1 ? t->pre : t->acc;
}

/* Fill an operand's values from its block. */
static void extract(struct item *it, const struct block *b)
{
	const struct df1_value *bv = b->vals + (it->lo - b->lo);

	for (size_t i = 0; i < it->n; i++) {
		struct df1_value *v = &it->vals[i];

		memset(v, 0, sizeof *v);
		switch (it->ex) {
		case EX_ELEM:
			*v = bv[i];
			break;
		case EX_TCR_WORD:
			v->kind = DF1_VAL_INT16;
			v->v.i16 = tcr_word(&bv[i].v.tcr, it->a.sub);
			break;
		case EX_TCR_BITS: {
			int sub = it->a.sub == DF1_ADDR_NONE ? 0 : it->a.sub;
			uint16_t w = (uint16_t)tcr_word(&bv[0].v.tcr, sub);
			v->kind = DF1_VAL_BIT;
			v->v.bit = (w >> (it->a.bit + (int)i)) & 1u;
			break;
		}
		case EX_WORD_BITS: {
			bool l = it->a.type == DF1_FT_L;
			size_t nb = l ? 32 : 16, g = (size_t)it->a.bit + i;
			uint32_t w = l ? (uint32_t)bv[g / nb].v.i32 : (uint16_t)bv[g / nb].v.i16;
			v->kind = DF1_VAL_BIT;
			v->v.bit = (w >> (g % nb)) & 1u;
			break;
		}
		case EX_DIRECT:
			break;
		}
	}
}

static int read_item(struct rd *r, df1_t *h, struct item *it)
{
	r->reads++;
	return df1_read_addr(h, r->cli.station, &it->a, it->vals, it->n);
}

/* Read everything: 0, or the DF1_E_* code of the first failure (*failed_at: its operand). */
static int read_all(struct rd *r, df1_t *h, const char **failed_at)
{
	int rc;

	for (size_t i = 0; i < r->nitems; i++) {
		r->items[i].vals = calloc(r->items[i].n, sizeof *r->items[i].vals);
		if (!r->items[i].vals)
			return DF1_E_NOMEM;
	}
	for (size_t k = 0; k < r->nblocks; k++) {
		struct block *b = &r->blocks[k];
		struct df1_addr ba;
		size_t n = (size_t)(b->hi - b->lo + 1);

		if (cli_stop)
			return DF1_E_INTR;
		b->vals = calloc(n, sizeof *b->vals);
		if (!b->vals)
			return DF1_E_NOMEM;
		memset(&ba, 0, sizeof ba);
		ba.type = b->type;
		ba.file = b->file;
		ba.element = b->lo;
		ba.sub = DF1_ADDR_NONE;
		ba.bit = DF1_ADDR_NONE;
		r->reads++;
		rc = df1_read_addr(h, r->cli.station, &ba, b->vals, n);
		if (rc >= 0) {
			for (size_t i = 0; i < r->nitems; i++)
				if (r->items[i].block == (int)k)
					extract(&r->items[i], b);
			continue;
		}
		if (rc != DF1_E_REMOTE || b->nitems < 2) {
			*failed_at = r->items[b->first_item].text;
			return rc;
		}
		/* the PLC refused the block: find the operand it refuses */
		for (size_t i = 0; i < r->nitems; i++) {
			if (r->items[i].block != (int)k)
				continue;
			if (cli_stop)
				return DF1_E_INTR;
			rc = read_item(r, h, &r->items[i]);
			if (rc < 0) {
				*failed_at = r->items[i].text;
				return rc;
			}
		}
	}
	for (size_t i = 0; i < r->nitems; i++) {
		struct item *it = &r->items[i];
		if (it->ex != EX_DIRECT)
			continue;
		if (cli_stop)
			return DF1_E_INTR;
		rc = read_item(r, h, it);
		if (rc < 0) {
			*failed_at = it->text;
			return rc;
		}
	}
	return 0;
}

/* ------------------------------------------------------------------------
 * Output
 * ------------------------------------------------------------------------ */

/* A JSON object from "NAME=VALUE NAME=VALUE ..." (a formatted T/C/R element). */
static void json_tcr(FILE *f, const char *text)
{
	const char *p = text;
	bool first = true;

	fputc('{', f);
	while (*p) {
		const char *name, *eq, *val;
		size_t nlen, vlen;
		char num[32];
		long v;

		while (*p == ' ')
			p++;
		if (!*p)
			break;
		name = p;
		while (*p && *p != ' ')
			p++;
		eq = memchr(name, '=', (size_t)(p - name));
		if (!eq)
			continue;
		nlen = (size_t)(eq - name);
		val = eq + 1;
		vlen = (size_t)(p - val);
		if (vlen >= sizeof num)
			vlen = sizeof num - 1;
		memcpy(num, val, vlen);
		num[vlen] = '\0';
		v = strtol(num, NULL, 0);
		fprintf(f, "%s", first ? "" : ",");
		cli_json_string_n(f, name, nlen);
		fprintf(f, ":%ld", v);
		first = false;
	}
	fputc('}', f);
}

static int print_all(struct rd *r)
{
	FILE *f = stdout;
	enum cli_format fmt = r->cli.format;
	bool first = true;

	if (fmt == CLI_FMT_CSV)
		fputs("address,value\n", f);
	else if (fmt == CLI_FMT_JSON)
		fputs("[", f);
	for (size_t k = 0; k < r->nitems; k++) {
		const struct item *it = &r->items[k];

		for (size_t i = 0; i < it->n; i++) {
			const struct df1_value *v = &it->vals[i];
			char text[VALUE_TEXT_MAX], addr[CLI_ADDR_TEXT_MAX];
			int len = df1_value_format(v, it->a.type, text, sizeof text);

			if (len < 0)
				snprintf(text, sizeof text, "?");
			if (fmt == CLI_FMT_PLAIN) {
				fputs(text, f);
				fputc('\n', f);
				continue;
			}
			addr_text(&it->a, i, addr, sizeof addr);
			if (fmt == CLI_FMT_CSV) {
				cli_csv_field(f, addr);
				fputc(',', f);
				if (v->kind == DF1_VAL_STRING || v->kind == DF1_VAL_TCR)
					cli_csv_quoted(f, text);
				else
					fputs(text, f);
				fputc('\n', f);
				continue;
			}
			fputs(first ? "\n" : ",\n", f);
			first = false;
			fputs("{\"address\":", f);
			cli_json_string(f, addr);
			fputs(",\"value\":", f);
			if (v->kind == DF1_VAL_STRING)
				cli_json_string_n(f, text, (size_t)(len > 0 ? len : 0));
			else if (v->kind == DF1_VAL_TCR)
				json_tcr(f, text);
			else if (v->kind == DF1_VAL_FLOAT &&
			         (strcmp(text, "nan") == 0 || strcmp(text, "inf") == 0 || strcmp(text, "-inf") == 0))
				cli_json_string(f, text);   /* not JSON numbers */
			else
				fputs(text, f);
			fputc('}', f);
		}
	}
	if (fmt == CLI_FMT_JSON)
		fputs("\n]\n", f);
	if (fflush(f) != 0 || ferror(f)) {
		fprintf(stderr, "%s: stdout: %s\n", r->cli.name, strerror(errno));
		return CLI_EXIT_FAIL;
	}
	return CLI_EXIT_OK;
}

/* ------------------------------------------------------------------------
 * main
 * ------------------------------------------------------------------------ */

static void free_all(struct rd *r)
{
	for (size_t i = 0; i < r->nitems; i++)
		free(r->items[i].vals);
	for (size_t i = 0; i < r->nblocks; i++)
		free(r->blocks[i].vals);
	free(r->items);
	free(r->blocks);
	r->items = NULL;
	r->blocks = NULL;
}

int main(int argc, char **argv)
{
	static struct rd r;
	const char *failed_at = NULL;
	df1_t *h = NULL;
	int status, rc;

	cli_init(&r.cli, &read_tool);
	status = cli_parse(&r.cli, argc, argv, &r);
	if (status != CLI_CONTINUE)
		return status;
	if (r.cli.argc < 1)
		return cli_usage_error(&r.cli, "no address given");
	r.nitems = (size_t)r.cli.argc;
	r.items = calloc(r.nitems, sizeof *r.items);
	if (!r.items) {
		fprintf(stderr, "%s: out of memory\n", r.cli.name);
		return CLI_EXIT_FAIL;
	}
	for (size_t i = 0; i < r.nitems; i++) {
		status = parse_operand(&r, i, r.cli.argv[i]);
		if (status != CLI_CONTINUE) {
			free_all(&r);
			cli_cleanup(&r.cli);
			return status;
		}
	}
	if (!r.cli.device || !*r.cli.device) {
		free_all(&r);
		cli_cleanup(&r.cli);
		return cli_usage_error(&r.cli, "no device: use -d DEV, -N FILE or set DF1_DEVICE");
	}

	cli_signals_install();
	status = cli_open(&r.cli, &h);
	if (status != CLI_EXIT_OK) {
		free_all(&r);
		cli_cleanup(&r.cli);
		return status;
	}
	if (plan_blocks(&r, h) < 0) {
		fprintf(stderr, "%s: out of memory\n", r.cli.name);
		status = CLI_EXIT_FAIL;
		goto out;
	}
	rc = read_all(&r, h, &failed_at);
	if (rc == DF1_E_INTR || cli_stop) {
		fprintf(stderr, "%s: %s%sinterrupted by %s; nothing printed\n", r.cli.name,
		        failed_at ? failed_at : "", failed_at ? ": " : "", cli_signal_name(cli_stop_signal()));
		status = CLI_EXIT_FAIL;
		goto out;
	}
	if (rc < 0) {
		status = cli_report(r.cli.name, failed_at, r.cli.station, h, rc);
		goto out;
	}
	if (r.cli.verbose >= 1) {
		uint64_t cmds = 0;
		df1_counter(h, 2527, &cmds);
		fprintf(stderr, "%s: %zu address%s, %u read%s, %llu command%s sent\n", r.cli.name,
		        r.nitems, r.nitems == 1 ? "" : "es", r.reads, r.reads == 1 ? "" : "s",
		        (unsigned long long)cmds, cmds == 1 ? "" : "s");
	}
	status = print_all(&r);
out:
	cli_close(&r.cli, h);   /* restores the port's settings */
	free_all(&r);
	cli_raise_stop_signal();
	return status;
}
