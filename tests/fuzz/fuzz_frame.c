/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_frame - the byte-fed frame/symbol decoder (lib/proto/frame.c) in every
 * mode (full duplex, half duplex as master or slave sees it, auto duplex) and
 * check (BCC, CRC, auto), with every decoder option.
 *
 * Input: byte 0 the mode and check, byte 1 the decoder options, byte 2 the
 * chunk sizes of the third pass; the rest is the line.
 * Properties (frame.h): the same symbols whether the bytes come all at once,
 * one at a time or in chunks; every call makes progress; a frame with a good
 * check is exactly what the encoder writes for its data, and it is its last
 * wire_len bytes of the line.
 */
#include "fuzz.h"

#include <string.h>

#include "proto/frame.h"

#define MAX_SYMS 4096

struct rec {
	enum df1_sym kind;
	bool master_msg, check_ok, embedded;
	uint8_t station, bad_byte;
	int error;
	size_t len, wire_len, end;   /* end: line offset just after the symbol */
	uint32_t sum;                /* of the data, to compare runs cheaply */
};

struct run {
	size_t n;
	struct rec r[MAX_SYMS];
};

static struct run runs[3];

static uint32_t data_sum(const uint8_t *p, size_t n)
{
	uint32_t h = 2166136261u;
	for (size_t i = 0; i < n; i++)
		h = (h ^ p[i]) * 16777619u;
	return h;
}

/* The encoder's frame for a decoded one, compared with the line's bytes before end. */
static void check_frame(const struct df1_symbol *s, unsigned opts, const uint8_t *line, size_t end)
{
	uint8_t wire[FRAME_MAX_WIRE + 8];
	size_t n;

	if (s->master_msg)
		n = frame_encode_master(s->check, s->station, (opts & FRAME_OPT_HD_BCC_STX) != 0, s->data,
		                        s->len, wire, sizeof wire);
	else
		n = frame_encode_full(s->check, s->data, s->len, wire, sizeof wire);
	FUZZ_CHECK(n > 0, "a good frame of %zu bytes does not encode", s->len);
	FUZZ_CHECK(n == s->wire_len, "good frame: wire_len %zu, encoder %zu", s->wire_len, n);
	FUZZ_CHECK(end >= n && memcmp(line + end - n, wire, n) == 0,
	           "good frame at %zu: its bytes are not the encoder's", end);
}

static void decode(struct run *run, const uint8_t *line, size_t n, enum df1_check check,
                   unsigned opts, int pass, uint8_t chunks)
{
	struct frame_decoder d;
	size_t pos = 0;
	unsigned step = 0;
	bool embedded_in_frame = false;

	frame_decoder_init(&d, check, opts);
	run->n = 0;
	while (pos < n) {
		struct df1_symbol s;
		size_t k = n - pos, used;

		if (pass == 1)
			k = 1;
		else if (pass == 2) {
			size_t c = 1 + ((chunks >> (step++ % 8)) & 7u) * 3;
			k = c < k ? c : k;
		}
		memset(&s, 0, sizeof s);
		used = frame_decoder_feed(&d, line + pos, k, &s);
		FUZZ_CHECK(used <= k, "feed consumed %zu of %zu bytes", used, k);
		FUZZ_CHECK(used > 0 || s.kind != DF1_SYM_NONE, "feed made no progress at %zu", pos);
		pos += used;
		if (s.kind == DF1_SYM_NONE)
			continue;
		FUZZ_CHECK(s.kind <= DF1_SYM_ERROR, "symbol kind %d", (int)s.kind);
		FUZZ_CHECK(s.len <= FRAME_MAX_DATA, "symbol of %zu data bytes", s.len);
		FUZZ_CHECK(s.wire_len <= pos, "wire_len %zu after %zu bytes", s.wire_len, pos);
		if (s.kind == DF1_SYM_FRAME && s.check_ok && !embedded_in_frame)
			check_frame(&s, opts, line, pos);
		if (s.embedded)
			embedded_in_frame = true;
		else if (s.kind == DF1_SYM_FRAME || s.kind == DF1_SYM_ERROR)
			embedded_in_frame = false;
		if (run->n < MAX_SYMS) {
			struct rec *r = &run->r[run->n++];
			memset(r, 0, sizeof *r);
			r->kind = s.kind;
			r->master_msg = s.master_msg;
			r->check_ok = s.check_ok;
			r->embedded = s.embedded;
			r->station = s.has_station ? s.station : 0;
			r->bad_byte = s.kind == DF1_SYM_ERROR ? s.bad_byte : 0;
			r->error = s.kind == DF1_SYM_ERROR ? s.error : 0;
			r->len = s.len;
			r->wire_len = s.wire_len;
			r->end = pos;
			r->sum = s.data ? data_sum(s.data, s.len) : 0;
		}
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const enum df1_check checks[4] = { DF1_CHECK_CRC, DF1_CHECK_BCC, DF1_CHECK_AUTO,
	                                          DF1_CHECK_AUTO };
	enum df1_check check;
	unsigned opts;
	uint8_t chunks;

	if (size < 3)
		return 0;
	check = checks[data[0] & 3];
	opts = data[1] & (FRAME_OPT_ACCEPT_NAK_0F | FRAME_OPT_HD_BCC_STX | FRAME_OPT_EOT_TRAILER |
	                  FRAME_OPT_NO_EMBEDDED | FRAME_OPT_HALF_DUPLEX | FRAME_OPT_DUPLEX_AUTO);
	chunks = data[2];
	data += 3;
	size -= 3;
	for (int pass = 0; pass < 3; pass++)
		decode(&runs[pass], data, size, check, opts, pass, chunks);
	for (int pass = 1; pass < 3; pass++) {
		FUZZ_CHECK(runs[pass].n == runs[0].n, "pass %d: %zu symbols, all at once %zu", pass,
		           runs[pass].n, runs[0].n);
		for (size_t i = 0; i < runs[0].n; i++)
			FUZZ_CHECK(memcmp(&runs[pass].r[i], &runs[0].r[i], sizeof(struct rec)) == 0,
			           "pass %d: symbol %zu differs from the all-at-once decoding", pass, i);
	}
	return 0;
}
