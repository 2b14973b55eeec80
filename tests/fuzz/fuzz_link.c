/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_link - the link layer as master (lib/link: full duplex, half-duplex
 * master, radio modem) and the client above it (lib/client: every PLC type's commands and
 * reply decoding) fed hostile bytes by a responder on the mock port
 * (fuzz_peer.h).
 *
 * Input: byte 0 the line (bit 0 half duplex, bit 1 BCC, bits 2-4 PLC type,
 * bit 5 half-duplex BCC with STX, bit 6 no embedded responses, bit 7 no
 * duplicate detection); byte 1 the operation; byte 2 its count; byte 3 the
 * station and more options (bit 7: the radio modem, then bit 0 of byte 0 a
 * forward table of every station and bit 7 of byte 0 duplicate detection off);
 * then the responder's chunks.
 * Properties: a call returns what it was asked for or a DF1_E_* code with a
 * name, never more values than asked, strings within their bounds, and the
 * handle's last error is a terminated text. An SLC read of N7:0 that succeeds
 * returns, for every element, the word that a reply to the command asking for
 * it carried (matching station and TNS, good check): no wrong value as success.
 */
#include "fuzz_peer.h"

#include <string.h>

#include "proto/pccc.h"

#define OPS 20

static const uint8_t stations[4] = { 1, 2, 16, 254 };
static struct df1_value vals[1000];

static void check_values(const struct df1_value *v, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (v[i].kind == DF1_VAL_STRING)
			FUZZ_CHECK(v[i].v.str.len <= DF1_STRING_MAX &&
			           memchr(v[i].v.str.text, '\0', sizeof v[i].v.str.text) != NULL,
			           "value %zu: string of %u characters", i, (unsigned)v[i].v.str.len);
}

/* Each of the n values of N7:0 read from station st came from a reply. */
static void check_slc_words(int st, size_t n)
{
	const struct fuzz_peer_frame *cmds, *reps;
	size_t ncmds = fuzz_peer_commands(&cmds), nreps = fuzz_peer_replies(&reps);

	for (size_t i = 0; i < n; i++) {
		bool asked = false, found = false;

		FUZZ_CHECK(vals[i].kind == DF1_VAL_INT16, "N7:%zu: value kind %d", i, vals[i].kind);
		for (size_t c = 0; c < ncmds && !found; c++) {
			const uint8_t *q = cmds[c].app;
			uint8_t nbytes, code;
			unsigned file, elem, sub;

			if (cmds[c].len < 8 || q[0] != st || q[2] != 0x0F || q[6] != 0xA2 ||
			    pccc_dec_slc_fields(q + 7, cmds[c].len - 7, true, &nbytes, &file, &code, &elem,
			                        &sub) < 0 ||
			    file != 7 || sub != 0 || i < elem || i >= elem + nbytes / 2u)
				continue;
			asked = true;
			for (size_t k = 0; k < nreps && !found; k++) {
				const uint8_t *p = reps[k].app;
				size_t off = 6 + 2 * (i - elem);
				if (reps[k].len == 6u + nbytes && p[0] == q[1] && p[1] == q[0] && p[2] == 0x4F &&
				    p[3] == 0 && p[4] == q[4] && p[5] == q[5] &&
				    (int16_t)(p[off] | p[off + 1] << 8) == vals[i].v.i16)
					found = true;
			}
		}
		FUZZ_CHECK(asked, "N7:%zu returned, but no command asked for it", i);
		FUZZ_CHECK(found, "N7:%zu = %d returned as success, but no reply carried it", i,
		           vals[i].v.i16);
	}
}

static int run_op(df1_t *h, int op, size_t count, int st, struct fuzz_in *in)
{
	static uint8_t buf[1024];
	char text[100];
	int r;

	switch (op) {
	case 0: return df1_read(h, st, "N7:0", vals, count);
	case 1: return df1_read(h, st, "F8:0", vals, count);
	case 2: return df1_read(h, st, "T4:0", vals, count % 50 + 1);
	case 3: return df1_read(h, st, "ST9:0", vals, count % 4 + 1);
	case 4: return df1_read(h, st, "B3:0/5", vals, count);
	case 5: return df1_read(h, st, "L10:0", vals, count);
	case 6:
		for (size_t i = 0; i < count; i++) {
			vals[i].kind = DF1_VAL_INT16;
			vals[i].v.i16 = (int16_t)(i * 257);
		}
		return df1_write(h, st, "N7:0", vals, count);
	case 7: return df1_write_bit(h, st, "B3:0/5", count & 1);
	case 8:
		memset(text, 'A' + (int)(count % 26), sizeof text);
		text[count % 90] = '\0';
		return df1_write_string(h, st, "ST9:1", text);
	case 9: return df1_read(h, st, "T4:0.ACC", vals, count % 40 + 1);
	case 10: {
		struct df1_diag_status ds;
		r = df1_diag_status(h, st, &ds);
		if (r >= 0)
			FUZZ_CHECK(memchr(ds.name, '\0', sizeof ds.name) != NULL, "processor name");
		return r;
	}
	case 11: return df1_echo(h, st, (const uint8_t *)"echo-echo", count % 10);
	case 12: return df1_link_test(h, st);
	case 13: {
		struct df1_read_req reqs[4] = {
			{ .text = "N7:0", .count = count % 20 + 1, .values = vals },
			{ .text = "N7:30", .count = 2, .values = vals + 100 },
			{ .text = "B3:0/3", .count = 3, .values = vals + 200 },
			{ .text = "T4:1.PRE", .count = 1, .values = vals + 300 },
		};
		unsigned reads = 0;
		r = df1_read_multi(h, st, reqs, 4, count & 0x80 ? DF1_READ_MULTI_STOP : 0, &reads);
		for (int i = 0; i < 4; i++)
			FUZZ_CHECK(reqs[i].result <= (int)reqs[i].count, "read_multi %d: %d of %zu", i,
			           reqs[i].result, reqs[i].count);
		return r;
	}
	case 14: return df1_read_raw(h, st, "N7:0", buf, count * 2);
	case 15:
		for (size_t i = 0; i < count; i++) {
			vals[i].kind = DF1_VAL_FLOAT;
			vals[i].v.f = (float)i / 3.0f;
		}
		return df1_write(h, st, "F8:0", vals, count);
	case 16: return df1_read(h, st, (count & 1) ? "I1:0.1" : "O0:0", vals, count % 8 + 1);
	case 17: return df1_change_mode(h, st, (int)(count % 8));
	case 18: return df1_read(h, st, "$N7:0", vals, count % 20 + 1);
	default: {
		size_t len;
		const uint8_t *body = fuzz_take(in, count % 32, &len);
		return df1_command(h, st, (uint8_t)(count & 0x0F), body, len, buf, sizeof buf);
	}
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct fuzz_in in = { data, size };
	uint8_t line, op, cnt, opt;
	size_t count;
	df1_t *h;
	int r;

	if (size < 4)
		return 0;
	line = fuzz_byte(&in);
	op = fuzz_byte(&in);
	cnt = fuzz_byte(&in);
	opt = fuzz_byte(&in);
	if (df1_new(&h) != 0)
		return 0;
	h->cfg.duplex = (line & 1) ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;
	h->cfg.check = (line & 2) ? DF1_CHECK_BCC : DF1_CHECK_CRC;
	h->cfg.plc = (enum df1_plc)((line >> 2 & 7) % 5);
	h->cfg.hd_bcc_stx = (line & 0x20) != 0;
	h->cfg.embedded = !(line & 0x40);
	h->cfg.dup_detect = !(line & 0x80);
	h->cfg.plc5_float_swapped = (opt & 0x04) != 0;
	h->cfg.nak_0f = !(opt & 0x08);
	h->cfg.eot_bcc = (opt & 0x10) != 0;
	h->cfg.slc_io_82 = (opt & 0x20) != 0;
	h->cfg.max_packet = (opt & 0x40) ? 20 : 0;
	if (opt & 0x80) {
		/* the radio modem: a relay of every station, or a plain master */
		uint8_t all[32];

		memset(all, 0xFF, sizeof all);
		h->cfg.duplex = DF1_RADIO_MODEM;
		df1_set_option(h, DF1_OPT_RADIO_DUP_DETECT, (line & 0x80) ? 0 : DF1_DUP_AUTO);
		if (line & 1)
			df1_set_forward(h, all);
	}
	h->cfg.timeout_ms = 50;
	h->cfg.cmd_timeout_ms = 500;
	h->next_tns = (uint16_t)(cnt * 0x0101);   /* 1010h among them: a stuffed TNS */
	fuzz_peer_start(h, &in);
	count = (size_t)cnt % 120 + 1;
	r = run_op(h, op % OPS, count, stations[opt & 3], &in);
	if (r < 0) {
		FUZZ_CHECK(strcmp(df1_errname(r), "DF1_E_UNKNOWN") != 0,
		           "operation %d returned %d, not a DF1_E_* code", op % OPS, r);
	}
	FUZZ_CHECK(memchr(df1_last_error(h)->message, '\0', sizeof df1_last_error(h)->message) != NULL,
	           "last error message not terminated");
	if (r > 0 && op % OPS <= 5) {
		size_t asked = op % OPS == 2 ? count % 50 + 1 : op % OPS == 3 ? count % 4 + 1 : count;
		FUZZ_CHECK((size_t)r <= asked, "%d values for %zu asked", r, asked);
		check_values(vals, (size_t)r);
	}
	if (r > 0 && op % OPS == 0 && h->cfg.plc != DF1_PLC_PLC5 && h->cfg.plc != DF1_PLC_PLC2)
		check_slc_words(stations[opt & 3], (size_t)r);
	fuzz_peer_stop();
	df1_free(h);
	return 0;
}
