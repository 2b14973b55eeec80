/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_frame - the pure frame module and the public decoder wrapper.
 * Expectations come from tests/data/vectors.txt (frames from the manuals, the
 * serial-tap capture and frames derived from the spec's rules) and from the
 * spec's rules, re-implemented here in the simplest form (bitwise CRC, sum
 * BCC, byte-by-byte de-stuffing), never from output captured from the code.
 *
 * The vector file is the first argument, else $DF1_VECTORS, else
 * tests/data/vectors.txt (tests run from the repository root).
 * Random round trips use $DF1_TEST_SEED when set; the seed is printed.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "proto/frame.h"

/* ------------------------------------------------------------------------
 * Vectors
 * ------------------------------------------------------------------------ */

#define MAX_VECTORS 128
#define MAX_WIRE 600

enum vkind { V_FRAME, V_MASTER, V_POLL, V_ENQ, V_EOT, V_ACK, V_NAK };

struct vec {
	char name[96];
	int check;              /* DF1_CHECK_BCC / DF1_CHECK_CRC, -1 for '-' */
	uint8_t wire[MAX_WIRE];
	size_t n;
	enum vkind kind;
	/* expectations worked out here from the wire bytes */
	uint8_t app[MAX_WIRE];
	size_t app_len;
	uint8_t stn;
	uint16_t check_value;   /* BCC byte, or CRC as lo | hi << 8 */
};

static struct vec vecs[MAX_VECTORS];
static size_t nvecs;
static const char *vec_path = "tests/data/vectors.txt";

static char *trim(char *s)
{
	char *e;

	while (*s == ' ' || *s == '\t')
		s++;
	e = s + strlen(s);
	while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\n' || e[-1] == '\r'))
		*--e = '\0';
	return s;
}

/* De-stuff a frame by the spec's rules (1.3, 2.2); false if it is not one. */
static bool vec_analyse(struct vec *v)
{
	const uint8_t *w = v->wire;
	size_t i, nchk = v->check == DF1_CHECK_BCC ? 1 : 2;

	if (v->n == 2 && w[0] == 0x10) {
		switch (w[1]) {
		case 0x05: v->kind = V_ENQ; return true;
		case 0x04: v->kind = V_EOT; return true;
		case 0x06: v->kind = V_ACK; return true;
		case 0x15: v->kind = V_NAK; return true;
		default: return false;
		}
	}
	if (w[0] != 0x10)
		return false;
	if (w[1] == 0x05) {
		v->kind = V_POLL;
		v->stn = w[2];
		i = w[2] == 0x10 ? 4 : 3;
		if (i + 1 != v->n)
			return false;
		v->check_value = w[i];
		return true;
	}
	if (w[1] == 0x01) {
		v->kind = V_MASTER;
		v->stn = w[2];
		i = w[2] == 0x10 ? 4 : 3;
		if (w[i] != 0x10 || w[i + 1] != 0x02)
			return false;
		i += 2;
	} else if (w[1] == 0x02) {
		v->kind = V_FRAME;
		i = 2;
	} else {
		return false;
	}
	v->app_len = 0;
	for (;;) {
		if (i + 1 >= v->n)
			return false;
		if (w[i] == 0x10 && w[i + 1] == 0x10) {
			v->app[v->app_len++] = 0x10;
			i += 2;
		} else if (w[i] == 0x10 && w[i + 1] == 0x03) {
			i += 2;
			break;
		} else if (w[i] == 0x10) {
			return false;
		} else {
			v->app[v->app_len++] = w[i++];
		}
	}
	if (i + nchk != v->n)
		return false;
	v->check_value = nchk == 1 ? w[i] : (uint16_t)(w[i] | (w[i + 1] << 8));
	return true;
}

static int load_vectors(void **state)
{
	char line[2048];
	FILE *f = fopen(vec_path, "r");

	(void)state;
	if (!f) {
		print_error("cannot open %s (run from the repository root)\n", vec_path);
		return -1;
	}
	nvecs = 0;
	while (fgets(line, sizeof line, f)) {
		char *fields[4], *p = line, *bar;
		struct vec *v;
		int nf = 0;

		if (line[0] == '#' || trim(line)[0] == '\0')
			continue;
		while (nf < 3 && (bar = strstr(p, " | ")) != NULL) {
			*bar = '\0';
			fields[nf++] = trim(p);
			p = bar + 3;
		}
		fields[nf++] = trim(p);
		if (nf != 4 || nvecs == MAX_VECTORS) {
			print_error("bad vector line: %s\n", line);
			fclose(f);
			return -1;
		}
		v = &vecs[nvecs++];
		memset(v, 0, sizeof *v);
		snprintf(v->name, sizeof v->name, "%s/%s", fields[0], fields[1]);
		v->check = !strcmp(fields[1], "bcc") ? DF1_CHECK_BCC
		         : !strcmp(fields[1], "crc") ? DF1_CHECK_CRC : -1;
		for (char *h = fields[2]; *h;) {
			char *end;
			unsigned long b = strtoul(h, &end, 16);

			if (end == h || b > 0xFF || v->n == MAX_WIRE) {
				print_error("bad hex in %s\n", v->name);
				fclose(f);
				return -1;
			}
			v->wire[v->n++] = (uint8_t)b;
			h = end;
			while (*h == ' ')
				h++;
		}
		if (!vec_analyse(v)) {
			print_error("cannot analyse vector %s\n", v->name);
			fclose(f);
			return -1;
		}
	}
	fclose(f);
	/* 47 frames and polls plus 4 symbols in the spec's file */
	if (nvecs < 50) {
		print_error("only %zu vectors in %s\n", nvecs, vec_path);
		return -1;
	}
	return 0;
}

/* ------------------------------------------------------------------------
 * Helpers
 * ------------------------------------------------------------------------ */

struct rec {
	struct df1_symbol s;
	uint8_t data[FRAME_MAX_DATA];
};

#define MAX_RECS 64

struct run {
	struct rec recs[MAX_RECS];
	size_t nrecs;
	size_t consumed;
};

static void feed_segment(struct frame_decoder *d, const uint8_t *in, size_t n, struct run *r)
{
	while (n) {
		struct df1_symbol s;
		size_t used = frame_decoder_feed(d, in, n, &s);

		/* 0 only for the ENQ of FRAME_OPT_DUPLEX_AUTO, decided by in[0] */
		assert_true(used > 0 || (s.kind == DF1_SYM_ENQ && (d->opts & FRAME_OPT_DUPLEX_AUTO)));
		assert_true(used <= n);
		in += used;
		n -= used;
		r->consumed += used;
		if (s.kind == DF1_SYM_NONE) {
			assert_int_equal(n, 0);
			continue;
		}
		assert_true(r->nrecs < MAX_RECS);
		struct rec *rec = &r->recs[r->nrecs++];
		rec->s = s;
		if (s.data) {
			assert_true(s.len <= FRAME_MAX_DATA);
			memcpy(rec->data, s.data, s.len);
		}
	}
}

/* Feed in chunks of `chunk` bytes (0: all at once). */
static void run_chunks(struct frame_decoder *d, const uint8_t *in, size_t n, size_t chunk, struct run *r)
{
	memset(r, 0, sizeof *r);
	if (chunk == 0)
		chunk = n;
	for (size_t off = 0; off < n; off += chunk)
		feed_segment(d, in + off, n - off < chunk ? n - off : chunk, r);
}

static void run_split(struct frame_decoder *d, const uint8_t *in, size_t n, size_t pos, struct run *r)
{
	memset(r, 0, sizeof *r);
	feed_segment(d, in, pos, r);
	feed_segment(d, in + pos, n - pos, r);
}

static void assert_same_runs(const struct run *a, const struct run *b)
{
	assert_int_equal(a->nrecs, b->nrecs);
	assert_int_equal(a->consumed, b->consumed);
	for (size_t i = 0; i < a->nrecs; i++) {
		const struct df1_symbol *x = &a->recs[i].s, *y = &b->recs[i].s;

		assert_int_equal(x->kind, y->kind);
		assert_int_equal(x->master_msg, y->master_msg);
		assert_int_equal(x->has_station, y->has_station);
		assert_int_equal(x->station, y->station);
		assert_int_equal(x->len, y->len);
		assert_int_equal(x->data != NULL, y->data != NULL);
		if (x->data)
			assert_memory_equal(a->recs[i].data, b->recs[i].data, x->len);
		assert_int_equal(x->check, y->check);
		assert_int_equal(x->check_ok, y->check_ok);
		assert_int_equal(x->check_expected, y->check_expected);
		assert_int_equal(x->check_actual, y->check_actual);
		assert_int_equal(x->embedded, y->embedded);
		assert_int_equal(x->error, y->error);
		assert_int_equal(x->bad_byte, y->bad_byte);
		assert_int_equal(x->wire_len, y->wire_len);
	}
}

static void vec_decoder(const struct vec *v, struct frame_decoder *d)
{
	unsigned opts = v->kind == V_POLL ? FRAME_OPT_HALF_DUPLEX : 0;

	frame_decoder_init(d, v->check == DF1_CHECK_BCC ? DF1_CHECK_BCC : DF1_CHECK_CRC, opts);
}

static bool is_message(const struct vec *v)
{
	return v->kind == V_FRAME || v->kind == V_MASTER;
}

/* Bitwise CRC-16/ARC exactly as doc/PROTOCOL.md 7.5 describes it. */
static uint16_t ref_crc(uint16_t crc, const uint8_t *p, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		crc ^= p[i];
		for (int k = 0; k < 8; k++)
			crc = (crc & 1) ? (uint16_t)((crc >> 1) ^ 0xA001) : (uint16_t)(crc >> 1);
	}
	return crc;
}

static uint8_t ref_bcc(const uint8_t *p, size_t n)
{
	unsigned sum = 0;

	for (size_t i = 0; i < n; i++)
		sum += p[i];
	return (uint8_t)((256 - (sum & 0xFF)) & 0xFF);
}

static const struct vec *vec_named(const char *name)
{
	for (size_t i = 0; i < nvecs; i++)
		if (!strcmp(vecs[i].name, name))
			return &vecs[i];
	fail_msg("no vector %s", name);
	return NULL;
}

/* ------------------------------------------------------------------------
 * Checks
 * ------------------------------------------------------------------------ */

static void test_frame_crc16_check_value_bb3d(void **state)
{
	static const uint8_t s[] = "123456789";

	(void)state;
	assert_int_equal(frame_crc16(0, s, 9), 0xBB3D);
	/* one call or byte by byte: the same */
	uint16_t c = 0;
	for (size_t i = 0; i < 9; i++)
		c = frame_crc16(c, &s[i], 1);
	assert_int_equal(c, 0xBB3D);
	/* every table entry against the bitwise definition */
	for (unsigned b = 0; b < 256; b++) {
		uint8_t byte = (uint8_t)b;

		assert_int_equal(frame_crc16(0, &byte, 1), ref_crc(0, &byte, 1));
		assert_int_equal(frame_crc16(0x1234, &byte, 1), ref_crc(0x1234, &byte, 1));
	}
	/* M p.5-7: data + ETX -> 4C6B */
	static const uint8_t m57[] = { 0x07, 0x11, 0x41, 0x00, 0x53, 0xB9, 0, 0, 0, 0, 0, 0,
	                               0, 0, 0, 0, 0, 0, 0x03 };
	assert_int_equal(frame_crc16(0, m57, sizeof m57), 0x4C6B);
}

static void test_frame_bcc_manual_examples(void **state)
{
	static const uint8_t kf2[] = { 0x08, 0x09, 0x06, 0x00, 0x02, 0x04, 0x03 };
	static const uint8_t kf2_dle[] = { 0x08, 0x09, 0x06, 0x00, 0x10, 0x04, 0x03 };

	(void)state;
	assert_int_equal(frame_bcc(kf2, sizeof kf2), 0xE0);         /* sum 20h */
	assert_int_equal(frame_bcc(kf2_dle, sizeof kf2_dle), 0xD2); /* sum 2Eh, one DLE */
	assert_int_equal(frame_bcc(NULL, 0), 0x00);
}

static void test_frame_vectors_decode_one_good_symbol(void **state)
{
	(void)state;
	for (size_t i = 0; i < nvecs; i++) {
		const struct vec *v = &vecs[i];
		struct frame_decoder d;
		struct run r;

		print_message("vector %s\n", v->name);
		vec_decoder(v, &d);
		run_chunks(&d, v->wire, v->n, 0, &r);
		assert_int_equal(r.consumed, v->n);
		assert_int_equal(r.nrecs, 1);
		assert_false(frame_decoder_busy(&d));
		assert_int_equal(d.noise, 0);

		const struct df1_symbol *s = &r.recs[0].s;
		assert_int_equal(s->wire_len, v->n);
		assert_false(s->embedded);
		switch (v->kind) {
		case V_FRAME:
		case V_MASTER:
			assert_int_equal(s->kind, DF1_SYM_FRAME);
			assert_int_equal(s->check, v->check);
			assert_true(s->check_ok);
			assert_int_equal(s->check_actual, v->check_value);
			assert_int_equal(s->check_expected, v->check_value);
			assert_int_equal(s->len, v->app_len);
			assert_memory_equal(r.recs[0].data, v->app, v->app_len);
			assert_int_equal(s->master_msg, v->kind == V_MASTER);
			assert_int_equal(s->has_station, v->kind == V_MASTER);
			if (v->kind == V_MASTER)
				assert_int_equal(s->station, v->stn);
			/* and the checks computed here agree with the vector */
			if (v->check == DF1_CHECK_BCC) {
				uint8_t tmp[MAX_WIRE + 1];

				tmp[0] = v->stn;
				memcpy(tmp + 1, v->app, v->app_len);
				if (v->kind == V_MASTER)
					assert_int_equal(ref_bcc(tmp, v->app_len + 1), v->check_value);
				else
					assert_int_equal(ref_bcc(v->app, v->app_len), v->check_value);
			} else {
				uint16_t c = 0;
				uint8_t stx = 0x02, etx = 0x03;

				if (v->kind == V_MASTER) {
					c = ref_crc(c, &v->stn, 1);
					c = ref_crc(c, &stx, 1);
				}
				c = ref_crc(c, v->app, v->app_len);
				c = ref_crc(c, &etx, 1);
				assert_int_equal(c, v->check_value);
			}
			break;
		case V_POLL:
			assert_int_equal(s->kind, DF1_SYM_POLL);
			assert_true(s->has_station);
			assert_int_equal(s->station, v->stn);
			assert_true(s->check_ok);
			assert_int_equal(s->check_actual, v->check_value);
			assert_int_equal((uint8_t)(v->stn + v->check_value), 0);
			break;
		case V_ENQ: assert_int_equal(s->kind, DF1_SYM_ENQ); break;
		case V_EOT: assert_int_equal(s->kind, DF1_SYM_EOT); break;
		case V_ACK: assert_int_equal(s->kind, DF1_SYM_ACK); break;
		case V_NAK: assert_int_equal(s->kind, DF1_SYM_NAK); break;
		}
	}
}

static void test_frame_vectors_reencode_byte_for_byte(void **state)
{
	(void)state;
	for (size_t i = 0; i < nvecs; i++) {
		const struct vec *v = &vecs[i];
		uint8_t out[FRAME_MAX_WIRE];
		size_t n = 0;

		print_message("vector %s\n", v->name);
		switch (v->kind) {
		case V_FRAME:
			n = frame_encode_full((enum df1_check)v->check, v->app, v->app_len, out, sizeof out);
			/* one byte short of room: nothing */
			assert_int_equal(frame_encode_full((enum df1_check)v->check, v->app, v->app_len,
			                                   out, v->n - 1), 0);
			break;
		case V_MASTER:
			n = frame_encode_master((enum df1_check)v->check, v->stn, false, v->app, v->app_len,
			                        out, sizeof out);
			assert_int_equal(frame_encode_master((enum df1_check)v->check, v->stn, false, v->app,
			                                     v->app_len, out, v->n - 1), 0);
			break;
		case V_POLL:
			n = frame_encode_poll(v->stn, out, sizeof out);
			assert_int_equal(frame_encode_poll(v->stn, out, v->n - 1), 0);
			break;
		case V_ENQ: n = frame_encode_symbol(DF1_ENQ, out, sizeof out); break;
		case V_EOT: n = frame_encode_symbol(DF1_EOT, out, sizeof out); break;
		case V_ACK: n = frame_encode_symbol(DF1_ACK, out, sizeof out); break;
		case V_NAK: n = frame_encode_symbol(DF1_NAK, out, sizeof out); break;
		}
		assert_int_equal(n, v->n);
		assert_memory_equal(out, v->wire, v->n);
	}
}

static void test_frame_vectors_split_anywhere_same_result(void **state)
{
	(void)state;
	for (size_t i = 0; i < nvecs; i++) {
		const struct vec *v = &vecs[i];
		struct frame_decoder d;
		static struct run whole, part;

		vec_decoder(v, &d);
		run_chunks(&d, v->wire, v->n, 0, &whole);
		vec_decoder(v, &d);
		run_chunks(&d, v->wire, v->n, 1, &part);
		assert_same_runs(&whole, &part);
		for (size_t pos = 0; pos <= v->n; pos++) {
			vec_decoder(v, &d);
			run_split(&d, v->wire, v->n, pos, &part);
			assert_same_runs(&whole, &part);
		}
	}
}

/* Every byte of every frame and poll replaced by each of the 255 other values:
 * the decoder (with the vector's check) never reports a good frame or poll.
 * One corruption is a good poll by construction and is allowed: in the poll of
 * station 10h (10 05 10 10 F0) the first DLE of the stuffed STN turned into F0
 * reads as the poll of station F0, whose BCC is 10h (10 05 F0 10), then one
 * noise byte. A 1-byte BCC over a 1-byte STN cannot tell them apart. */
static void test_frame_vectors_corrupted_byte_never_accepted(void **state)
{
	unsigned long tried = 0;

	(void)state;
	for (size_t i = 0; i < nvecs; i++) {
		const struct vec *v = &vecs[i];

		if (!is_message(v) && v->kind != V_POLL)
			continue;
		for (size_t pos = 0; pos < v->n; pos++) {
			for (unsigned x = 1; x < 256; x++) {
				uint8_t bad[MAX_WIRE];
				struct frame_decoder d;
				static struct run r;

				memcpy(bad, v->wire, v->n);
				bad[pos] ^= (uint8_t)x;
				vec_decoder(v, &d);
				run_chunks(&d, bad, v->n, 0, &r);
				tried++;
				for (size_t j = 0; j < r.nrecs; j++) {
					const struct df1_symbol *s = &r.recs[j].s;

					if (s->kind == DF1_SYM_POLL && s->check_ok && v->stn == 0x10 && pos == 2 &&
					    bad[pos] == 0xF0 && s->station == 0xF0 && s->wire_len == 4)
						continue;       /* the poll of station F0, see above */
					if ((s->kind == DF1_SYM_FRAME || s->kind == DF1_SYM_POLL) && s->check_ok)
						fail_msg("%s: byte %zu ^ %02x accepted as a good %s", v->name, pos, x,
						         s->kind == DF1_SYM_FRAME ? "frame" : "poll");
				}
			}
		}
	}
	assert_true(tried > 200000);
}

/* ------------------------------------------------------------------------
 * Random round trips
 * ------------------------------------------------------------------------ */

static uint64_t rng;

static uint64_t rnd(void)
{
	/* xorshift64* */
	rng ^= rng >> 12;
	rng ^= rng << 25;
	rng ^= rng >> 27;
	return rng * 0x2545F4914F6CDD1DULL;
}

static unsigned rnd_below(unsigned n)
{
	return (unsigned)(rnd() % n);
}

/* Payload bytes rich in DLE and the other control values. */
static uint8_t rnd_byte(void)
{
	static const uint8_t special[] = { 0x10, 0x10, 0x10, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06,
	                                   0x15, 0x0F };

	if (rnd_below(3) == 0)
		return special[rnd_below(sizeof special)];
	return (uint8_t)rnd();
}

#define RT_CHECK(cond)                                                                      \
	do {                                                                                    \
		if (!(cond))                                                                        \
			fail_msg("seed %llu (DF1_TEST_SEED), iteration %d: %s", (unsigned long long)seed, \
			         iter, #cond);                                                          \
	} while (0)

static void test_frame_random_round_trips(void **state)
{
	const char *env = getenv("DF1_TEST_SEED");
	unsigned long long seed;

	(void)state;
	seed = env ? strtoull(env, NULL, 0) : (unsigned long long)time(NULL) ^ ((unsigned long long)getpid() << 20);
	if (seed == 0)
		seed = 1;
	print_message("random round trips: DF1_TEST_SEED=%llu\n", seed);
	rng = seed;
	for (int iter = 0; iter < 3000; iter++) {
		uint8_t app[FRAME_MAX_DATA], wire[FRAME_MAX_WIRE + 64];
		size_t len = FRAME_MIN_DATA + rnd_below(FRAME_MAX_DATA - FRAME_MIN_DATA + 1);
		enum df1_check check = rnd_below(2) ? DF1_CHECK_CRC : DF1_CHECK_BCC;
		bool master = rnd_below(2);
		bool bcc_stx = rnd_below(2);
		uint8_t stn = rnd_below(4) == 0 ? 0x10 : (uint8_t)rnd();
		size_t noise = rnd_below(4), n, chunk;
		struct frame_decoder d;
		static struct run r;

		for (size_t i = 0; i < len; i++)
			app[i] = rnd_byte();
		/* leading noise: anything but DLE */
		for (size_t i = 0; i < noise; i++) {
			wire[i] = (uint8_t)rnd();
			if (wire[i] == 0x10)
				wire[i] = 0x11;
		}
		if (master)
			n = frame_encode_master(check, stn, bcc_stx, app, len, wire + noise, FRAME_MAX_WIRE);
		else
			n = frame_encode_full(check, app, len, wire + noise, FRAME_MAX_WIRE);
		RT_CHECK(n > 0 && n <= FRAME_MAX_WIRE);

		/* AUTO too, unless the frame is ambiguous: a CRC whose low byte happens
		 * to be the right BCC reads as a BCC frame (the documented AUTO rule) */
		enum df1_check dcheck = rnd_below(4) == 0 ? DF1_CHECK_AUTO : check;
		if (dcheck == DF1_CHECK_AUTO && check == DF1_CHECK_CRC) {
			uint8_t hdr[2] = { stn, 0x02 }, etx = 0x03;
			unsigned sum = master ? stn + (bcc_stx ? 0x02u : 0u) : 0u;
			uint16_t c = master ? ref_crc(0, hdr, 2) : 0;

			c = ref_crc(ref_crc(c, app, len), &etx, 1);
			for (size_t i = 0; i < len; i++)
				sum += app[i];
			if ((c & 0xFF) == ((256 - (sum & 0xFF)) & 0xFF))
				dcheck = DF1_CHECK_CRC;
		}
		frame_decoder_init(&d, dcheck, master && bcc_stx ? FRAME_OPT_HD_BCC_STX : 0);
		chunk = rnd_below(3) == 0 ? 0 : 1 + rnd_below(17);
		run_chunks(&d, wire, noise + n, chunk, &r);
		RT_CHECK(r.nrecs == 1);
		RT_CHECK(r.consumed == noise + n);
		RT_CHECK(d.noise == noise);
		const struct df1_symbol *s = &r.recs[0].s;
		RT_CHECK(s->kind == DF1_SYM_FRAME);
		RT_CHECK(s->check_ok);
		RT_CHECK(s->check == check);
		RT_CHECK(s->len == len);
		RT_CHECK(memcmp(r.recs[0].data, app, len) == 0);
		RT_CHECK(s->wire_len == n);
		RT_CHECK(s->master_msg == master);
		RT_CHECK(!master || s->station == stn);

		/* the encoded form by the spec's rules: count the DLEs that must be doubled */
		size_t dles = 0;
		for (size_t i = 0; i < len; i++)
			dles += app[i] == 0x10;
		size_t expect = 2 + len + dles + 2 + (check == DF1_CHECK_CRC ? 2 : 1);
		if (master)
			expect += 2 + 1 + (stn == 0x10);
		RT_CHECK(n == expect);
	}
}

/* ------------------------------------------------------------------------
 * Behaviours
 * ------------------------------------------------------------------------ */

static void test_frame_embedded_ack_nak_inside_frame(void **state)
{
	const struct vec *v = vec_named("derived-slc-A2-read-N7:0-20B/crc");
	static const uint8_t inserts[][2] = { { 0x10, 0x06 }, { 0x10, 0x15 }, { 0x10, 0x0F } };

	(void)state;
	for (size_t k = 0; k < 3; k++) {
		/* after DLE STX + 3 app bytes, and just before DLE ETX */
		size_t places[] = { 5, v->n - 4 };

		for (size_t p = 0; p < 2; p++) {
			uint8_t w[MAX_WIRE];
			struct frame_decoder d;
			static struct run r;
			size_t at = places[p];

			memcpy(w, v->wire, at);
			memcpy(w + at, inserts[k], 2);
			memcpy(w + at + 2, v->wire + at, v->n - at);
			frame_decoder_init(&d, DF1_CHECK_CRC, FRAME_OPT_ACCEPT_NAK_0F);
			run_chunks(&d, w, v->n + 2, 0, &r);
			assert_int_equal(r.nrecs, 2);
			assert_int_equal(r.recs[0].s.kind, k == 0 ? DF1_SYM_ACK : DF1_SYM_NAK);
			assert_true(r.recs[0].s.embedded);
			assert_int_equal(r.recs[0].s.wire_len, 2);
			assert_int_equal(r.recs[1].s.kind, DF1_SYM_FRAME);
			assert_true(r.recs[1].s.check_ok);
			assert_int_equal(r.recs[1].s.len, v->app_len);
			assert_memory_equal(r.recs[1].data, v->app, v->app_len);
			assert_int_equal(r.recs[1].s.wire_len, v->n);

			/* embedded responses off: the frame is aborted with 2514 */
			frame_decoder_init(&d, DF1_CHECK_CRC, FRAME_OPT_ACCEPT_NAK_0F | FRAME_OPT_NO_EMBEDDED);
			run_chunks(&d, w, v->n + 2, 0, &r);
			assert_int_equal(r.nrecs, 1);
			assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
			assert_int_equal(r.recs[0].s.error, 2514);
			assert_int_equal(r.recs[0].s.bad_byte, inserts[k][1]);
		}
	}
}

static void test_frame_noise_between_frames_skipped(void **state)
{
	const struct vec *a = vec_named("KF2-bcc-example-dle/bcc");
	const struct vec *b = vec_named("tap-A2-read-N7:1/bcc");
	/* noise: plain bytes, a stray DLE DLE and a DLE ETX outside any frame */
	static const uint8_t n1[] = { 0xFF, 0x00, 0x02, 0x03, 0x55 };
	static const uint8_t n2[] = { 0x10, 0x10, 0x10, 0x03, 0x7E };
	static const uint8_t ack[] = { 0x10, 0x06 };
	uint8_t w[MAX_WIRE];
	size_t n = 0;
	struct frame_decoder d;
	static struct run r;

	(void)state;
	memcpy(w + n, n1, sizeof n1); n += sizeof n1;
	memcpy(w + n, a->wire, a->n); n += a->n;
	memcpy(w + n, n2, sizeof n2); n += sizeof n2;
	memcpy(w + n, ack, sizeof ack); n += sizeof ack;
	memcpy(w + n, n1, sizeof n1); n += sizeof n1;
	w[n++] = 0x10; /* a noise DLE right before the frame's DLE STX */
	memcpy(w + n, b->wire, b->n); n += b->n;

	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	run_chunks(&d, w, n, 0, &r);
	assert_int_equal(r.nrecs, 3);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_FRAME);
	assert_true(r.recs[0].s.check_ok);
	assert_memory_equal(r.recs[0].data, a->app, a->app_len);
	assert_int_equal(r.recs[0].s.wire_len, a->n);
	assert_int_equal(r.recs[1].s.kind, DF1_SYM_ACK);
	assert_false(r.recs[1].s.embedded);
	assert_int_equal(r.recs[2].s.kind, DF1_SYM_FRAME);
	assert_true(r.recs[2].s.check_ok);
	assert_memory_equal(r.recs[2].data, b->app, b->app_len);
	assert_int_equal(r.recs[2].s.wire_len, b->n);
	/* every byte not in a symbol counted as noise */
	assert_int_equal(d.noise, n - a->n - 2 - b->n);

	/* the same one byte at a time */
	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	static struct run r1;
	run_chunks(&d, w, n, 1, &r1);
	assert_same_runs(&r, &r1);
}

static void test_frame_too_long_is_2512_after_check(void **state)
{
	static uint8_t app[FRAME_MAX_DATA + 1];
	uint8_t w[FRAME_MAX_WIRE + 8];
	const struct vec *good = vec_named("derived-echo-A/crc");
	struct frame_decoder d;
	static struct run r;
	size_t n;

	(void)state;
	for (size_t i = 0; i < sizeof app; i++)
		app[i] = (uint8_t)i;
	n = frame_encode_full(DF1_CHECK_CRC, app, sizeof app, w, sizeof w);
	assert_true(n > 0);
	memcpy(w + n, good->wire, good->n);
	frame_decoder_init(&d, DF1_CHECK_CRC, 0);
	run_chunks(&d, w, n + good->n, 0, &r);
	assert_int_equal(r.nrecs, 2);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
	assert_int_equal(r.recs[0].s.error, 2512);
	assert_int_equal(r.recs[0].s.wire_len, n);
	assert_true(r.recs[0].s.check_ok); /* the check still covers every byte */
	assert_int_equal(r.recs[0].s.len, FRAME_MAX_DATA);
	assert_int_equal(r.recs[1].s.kind, DF1_SYM_FRAME);
	assert_true(r.recs[1].s.check_ok);

	/* a smaller limit: max_len bytes pass, one more does not */
	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	d.max_len = 10;
	n = frame_encode_full(DF1_CHECK_BCC, app, 10, w, sizeof w);
	run_chunks(&d, w, n, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_FRAME);
	n = frame_encode_full(DF1_CHECK_BCC, app, 11, w, sizeof w);
	run_chunks(&d, w, n, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
	assert_int_equal(r.recs[0].s.error, 2512);
}

static void test_frame_too_short_is_2513(void **state)
{
	static const uint8_t app[] = { 0x01, 0x00, 0x06, 0x00, 0x0B };
	uint8_t w[32];
	struct frame_decoder d;
	static struct run r;

	(void)state;
	for (size_t len = 0; len < FRAME_MIN_DATA; len++) {
		size_t n = frame_encode_full(DF1_CHECK_CRC, app, len, w, sizeof w);

		frame_decoder_init(&d, DF1_CHECK_CRC, 0);
		run_chunks(&d, w, n, 0, &r);
		assert_int_equal(r.nrecs, 1);
		assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
		assert_int_equal(r.recs[0].s.error, 2513);
		assert_int_equal(r.recs[0].s.len, len);
		assert_int_equal(r.recs[0].s.wire_len, n);
	}
}

static void test_frame_invalid_symbol_after_dle_is_2514(void **state)
{
	/* inside a frame: DLE 07 aborts it; the rest is noise; the next frame is fine */
	const struct vec *good = vec_named("derived-diag-status/bcc");
	static const uint8_t head[] = { 0x10, 0x02, 0x01, 0x00, 0x0F, 0x10, 0x07, 0x44, 0x10, 0x03, 0x99 };
	static const uint8_t outside[] = { 0x10, 0x07 };
	static const uint8_t enq_inside[] = { 0x10, 0x02, 0x01, 0x02, 0x10, 0x05 };
	static const uint8_t nak0f[] = { 0x10, 0x0F };
	uint8_t w[MAX_WIRE];
	struct frame_decoder d;
	static struct run r;

	(void)state;
	memcpy(w, head, sizeof head);
	memcpy(w + sizeof head, good->wire, good->n);
	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	run_chunks(&d, w, sizeof head + good->n, 0, &r);
	assert_int_equal(r.nrecs, 2);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
	assert_int_equal(r.recs[0].s.error, 2514);
	assert_int_equal(r.recs[0].s.bad_byte, 0x07);
	assert_int_equal(r.recs[0].s.len, 3);
	assert_int_equal(r.recs[0].s.wire_len, 7);
	assert_int_equal(r.recs[1].s.kind, DF1_SYM_FRAME);
	assert_true(r.recs[1].s.check_ok);

	/* outside a frame */
	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	run_chunks(&d, outside, sizeof outside, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.error, 2514);
	assert_int_equal(r.recs[0].s.bad_byte, 0x07);
	assert_int_equal(r.recs[0].s.wire_len, 2);
	assert_null(r.recs[0].s.data);

	/* DLE ENQ is not allowed inside a frame */
	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	run_chunks(&d, enq_inside, sizeof enq_inside, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.error, 2514);
	assert_int_equal(r.recs[0].s.bad_byte, 0x05);

	/* DLE 0F: NAK only with the 1996-manual option */
	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	run_chunks(&d, nak0f, 2, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
	assert_int_equal(r.recs[0].s.error, 2514);
	assert_int_equal(r.recs[0].s.bad_byte, 0x0F);
	frame_decoder_init(&d, DF1_CHECK_BCC, FRAME_OPT_ACCEPT_NAK_0F);
	run_chunks(&d, nak0f, 2, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_NAK);

	/* after DLE SOH STN only DLE STX may follow */
	static const uint8_t soh_bad[] = { 0x10, 0x01, 0x05, 0x02 };
	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	run_chunks(&d, soh_bad, sizeof soh_bad, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.error, 2514);
	assert_int_equal(r.recs[0].s.bad_byte, 0x02);
	assert_true(r.recs[0].s.master_msg);
	assert_int_equal(r.recs[0].s.station, 5);
}

static void test_frame_new_start_inside_frame_is_2518(void **state)
{
	static const uint8_t partial[] = { 0x10, 0x02, 0x01, 0x00, 0x0F };
	static const uint8_t partial_soh[] = { 0x10, 0x01, 0x01, 0x10, 0x02, 0x01, 0x10, 0x10 };
	const struct vec *full = vec_named("derived-slc-AA-write-N7:5/crc");
	const struct vec *master = vec_named("derived-hd-master-A2-stn1/crc");
	uint8_t w[MAX_WIRE];
	struct frame_decoder d;
	static struct run r, r1;

	(void)state;
	memcpy(w, partial, sizeof partial);
	memcpy(w + sizeof partial, full->wire, full->n);
	frame_decoder_init(&d, DF1_CHECK_CRC, 0);
	run_chunks(&d, w, sizeof partial + full->n, 0, &r);
	assert_int_equal(r.nrecs, 2);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
	assert_int_equal(r.recs[0].s.error, 2518);
	assert_int_equal(r.recs[0].s.wire_len, sizeof partial);
	assert_int_equal(r.recs[0].s.len, 3);
	assert_int_equal(r.recs[1].s.kind, DF1_SYM_FRAME);
	assert_true(r.recs[1].s.check_ok);
	assert_int_equal(r.recs[1].s.wire_len, full->n);
	frame_decoder_init(&d, DF1_CHECK_CRC, 0);
	run_chunks(&d, w, sizeof partial + full->n, 1, &r1);
	assert_same_runs(&r, &r1);

	/* a master message cut by another master message */
	memcpy(w, partial_soh, sizeof partial_soh);
	memcpy(w + sizeof partial_soh, master->wire, master->n);
	frame_decoder_init(&d, DF1_CHECK_CRC, 0);
	run_chunks(&d, w, sizeof partial_soh + master->n, 0, &r);
	assert_int_equal(r.nrecs, 2);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
	assert_int_equal(r.recs[0].s.error, 2518);
	assert_true(r.recs[0].s.master_msg);
	assert_int_equal(r.recs[0].s.wire_len, sizeof partial_soh);
	assert_int_equal(r.recs[1].s.kind, DF1_SYM_FRAME);
	assert_true(r.recs[1].s.master_msg);
	assert_true(r.recs[1].s.check_ok);
	assert_int_equal(r.recs[1].s.station, 1);
}

static void test_frame_poll_bad_bcc_is_error(void **state)
{
	static const uint8_t bad[] = { 0x10, 0x05, 0x01, 0xFE };
	struct frame_decoder d;
	static struct run r;

	(void)state;
	frame_decoder_init(&d, DF1_CHECK_CRC, FRAME_OPT_HALF_DUPLEX);
	run_chunks(&d, bad, sizeof bad, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_ERROR);
	assert_int_equal(r.recs[0].s.error, 2507);
	assert_true(r.recs[0].s.has_station);
	assert_int_equal(r.recs[0].s.station, 1);
	assert_false(r.recs[0].s.check_ok);
	assert_int_equal(r.recs[0].s.check_expected, 0xFF);
	assert_int_equal(r.recs[0].s.check_actual, 0xFE);
	assert_int_equal(r.recs[0].s.wire_len, 4);
}

static void test_frame_enq_full_duplex_poll_half_duplex(void **state)
{
	static const uint8_t w[] = { 0x10, 0x05, 0x01, 0xFF };
	struct frame_decoder d;
	static struct run r;

	(void)state;
	/* full duplex: DLE ENQ alone, then two noise bytes */
	frame_decoder_init(&d, DF1_CHECK_CRC, 0);
	run_chunks(&d, w, sizeof w, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_ENQ);
	assert_int_equal(r.recs[0].s.wire_len, 2);
	assert_int_equal(d.noise, 2);
	/* half duplex: a poll of station 1, BCC one byte even on a CRC line */
	frame_decoder_init(&d, DF1_CHECK_CRC, FRAME_OPT_HALF_DUPLEX);
	run_chunks(&d, w, sizeof w, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_POLL);
	assert_int_equal(r.recs[0].s.station, 1);
	assert_int_equal(r.recs[0].s.check, DF1_CHECK_BCC);
}

static void test_frame_eot_trailer_option(void **state)
{
	static const uint8_t w[] = { 0x10, 0x04, 0x7F, 0x10, 0x06 };
	struct frame_decoder d;
	static struct run r;

	(void)state;
	frame_decoder_init(&d, DF1_CHECK_BCC, FRAME_OPT_EOT_TRAILER);
	run_chunks(&d, w, sizeof w, 0, &r);
	assert_int_equal(r.nrecs, 2);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_EOT);
	assert_int_equal(r.recs[1].s.kind, DF1_SYM_ACK);
	assert_int_equal(d.noise, 0);

	frame_decoder_init(&d, DF1_CHECK_BCC, 0);
	run_chunks(&d, w, sizeof w, 0, &r);
	assert_int_equal(r.nrecs, 2);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_EOT);
	assert_int_equal(r.recs[1].s.kind, DF1_SYM_ACK);
	assert_int_equal(d.noise, 1);

	/* EOT is reported at once, not after the optional trailer */
	struct df1_symbol s;
	frame_decoder_init(&d, DF1_CHECK_BCC, FRAME_OPT_EOT_TRAILER);
	assert_int_equal(frame_decoder_feed(&d, w, 2, &s), 2);
	assert_int_equal(s.kind, DF1_SYM_EOT);
	assert_false(frame_decoder_busy(&d));
}

static void test_frame_auto_check_on_vectors(void **state)
{
	(void)state;
	for (size_t i = 0; i < nvecs; i++) {
		const struct vec *v = &vecs[i];
		struct frame_decoder d;
		static struct run r, r1;

		if (!is_message(v))
			continue;
		frame_decoder_init(&d, DF1_CHECK_AUTO, 0);
		run_chunks(&d, v->wire, v->n, 0, &r);
		assert_int_equal(r.nrecs, 1);
		assert_int_equal(r.recs[0].s.kind, DF1_SYM_FRAME);
		assert_int_equal(r.recs[0].s.check, v->check);
		assert_true(r.recs[0].s.check_ok);
		assert_int_equal(r.recs[0].s.wire_len, v->n);
		assert_false(frame_decoder_busy(&d));
		frame_decoder_init(&d, DF1_CHECK_AUTO, 0);
		run_chunks(&d, v->wire, v->n, 1, &r1);
		assert_same_runs(&r, &r1);
	}

	/* a BCC line then a CRC line: locks BCC, then relocks CRC */
	const struct vec *b = vec_named("derived-echo-A/bcc");
	const struct vec *c = vec_named("derived-echo-A/crc");
	uint8_t w[MAX_WIRE];
	struct frame_decoder d;
	static struct run r;

	memcpy(w, b->wire, b->n);
	memcpy(w + b->n, c->wire, c->n);
	frame_decoder_init(&d, DF1_CHECK_AUTO, 0);
	run_chunks(&d, w, b->n + c->n, 0, &r);
	assert_int_equal(r.nrecs, 2);
	assert_int_equal(r.recs[0].s.check, DF1_CHECK_BCC);
	assert_true(r.recs[0].s.check_ok);
	assert_int_equal(r.recs[1].s.check, DF1_CHECK_CRC);
	assert_true(r.recs[1].s.check_ok);

	/* a bad BCC frame followed by DLE ACK: the DLE is not a CRC byte */
	memcpy(w, b->wire, b->n);
	w[4] ^= 0x01;
	w[b->n] = 0x10;
	w[b->n + 1] = 0x06;
	frame_decoder_init(&d, DF1_CHECK_AUTO, 0);
	run_chunks(&d, w, b->n + 2, 0, &r);
	assert_int_equal(r.nrecs, 2);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_FRAME);
	assert_int_equal(r.recs[0].s.check, DF1_CHECK_BCC);
	assert_false(r.recs[0].s.check_ok);
	assert_int_equal(r.recs[0].s.check_actual, b->check_value);
	assert_int_equal(r.recs[0].s.wire_len, b->n);
	assert_int_equal(r.recs[1].s.kind, DF1_SYM_ACK);
	assert_int_equal(r.recs[1].s.wire_len, 2);
}

static void test_frame_hd_bcc_includes_stx_gives_a6(void **state)
{
	const struct vec *v = vec_named("derived-hd-master-A2-stn1/bcc");
	uint8_t out[MAX_WIRE];
	struct frame_decoder d;
	static struct run r;
	size_t n;

	(void)state;
	assert_int_equal(v->wire[v->n - 1], 0xA8);
	n = frame_encode_master(DF1_CHECK_BCC, v->stn, true, v->app, v->app_len, out, sizeof out);
	assert_int_equal(n, v->n);
	assert_memory_equal(out, v->wire, v->n - 1);
	assert_int_equal(out[n - 1], 0xA6);

	/* decoder with the option: A6 is good, the literal-text A8 is not */
	frame_decoder_init(&d, DF1_CHECK_BCC, FRAME_OPT_HD_BCC_STX);
	run_chunks(&d, out, n, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_FRAME);
	assert_true(r.recs[0].s.check_ok);
	frame_decoder_init(&d, DF1_CHECK_BCC, FRAME_OPT_HD_BCC_STX);
	run_chunks(&d, v->wire, v->n, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_false(r.recs[0].s.check_ok);
	assert_int_equal(r.recs[0].s.check_expected, 0xA6);
	assert_int_equal(r.recs[0].s.check_actual, 0xA8);
}

static void test_frame_bad_check_reports_expected_and_actual(void **state)
{
	const struct vec *v = vec_named("M-5-7-crc-example/crc");
	uint8_t w[MAX_WIRE];
	struct frame_decoder d;
	static struct run r;

	(void)state;
	memcpy(w, v->wire, v->n);
	w[v->n - 1] = 0x00; /* 6B 00 instead of 6B 4C */
	frame_decoder_init(&d, DF1_CHECK_CRC, 0);
	run_chunks(&d, w, v->n, 0, &r);
	assert_int_equal(r.nrecs, 1);
	assert_int_equal(r.recs[0].s.kind, DF1_SYM_FRAME);
	assert_false(r.recs[0].s.check_ok);
	assert_int_equal(r.recs[0].s.check, DF1_CHECK_CRC);
	assert_int_equal(r.recs[0].s.check_expected, 0x4C6B);
	assert_int_equal(r.recs[0].s.check_actual, 0x006B);
}

static void test_frame_busy_inside_symbol_only(void **state)
{
	const struct vec *v = vec_named("derived-hd-master-A2-stn16/crc");
	struct frame_decoder d;
	struct df1_symbol s;

	(void)state;
	frame_decoder_init(&d, DF1_CHECK_CRC, 0);
	assert_false(frame_decoder_busy(&d));
	for (size_t i = 0; i + 1 < v->n; i++) {
		assert_int_equal(frame_decoder_feed(&d, &v->wire[i], 1, &s), 1);
		assert_int_equal(s.kind, DF1_SYM_NONE);
		assert_true(frame_decoder_busy(&d));
	}
	assert_int_equal(frame_decoder_feed(&d, &v->wire[v->n - 1], 1, &s), 1);
	assert_int_equal(s.kind, DF1_SYM_FRAME);
	assert_int_equal(s.station, 0x10);
	assert_false(frame_decoder_busy(&d));

	/* reset mid-frame: back to idle */
	frame_decoder_feed(&d, v->wire, 5, &s);
	assert_true(frame_decoder_busy(&d));
	frame_decoder_reset(&d);
	assert_false(frame_decoder_busy(&d));
	assert_int_equal(d.check, DF1_CHECK_CRC);
}

static void test_frame_encoders_reject_bad_arguments(void **state)
{
	static const uint8_t app[] = { 1, 0, 6, 0, 1, 0, 3 };
	uint8_t out[64];

	(void)state;
	assert_int_equal(frame_encode_full(DF1_CHECK_AUTO, app, sizeof app, out, sizeof out), 0);
	assert_int_equal(frame_encode_master(DF1_CHECK_AUTO, 1, false, app, sizeof app, out, sizeof out), 0);
	assert_int_equal(frame_encode_full(DF1_CHECK_CRC, NULL, 3, out, sizeof out), 0);
	assert_int_equal(frame_encode_full(DF1_CHECK_CRC, app, sizeof app, NULL, 64), 0);
	assert_int_equal(frame_encode_symbol(DF1_STX, out, sizeof out), 0);
	assert_int_equal(frame_encode_symbol(DF1_ACK, out, 1), 0);
	assert_int_equal(frame_encode_poll(1, out, 3), 0);
	/* poll of station F0: the BCC 10h is not stuffed */
	assert_int_equal(frame_encode_poll(0xF0, out, sizeof out), 4);
	assert_int_equal(out[3], 0x10);
}

static void test_frame_public_decoder(void **state)
{
	const struct vec *v = vec_named("derived-hd-poll-16/bcc");
	const struct vec *f = vec_named("KE-plc2-read-cmd/bcc");
	struct df1_decoder *d = NULL;
	struct df1_symbol s;
	size_t used;

	(void)state;
	assert_int_equal(df1_decoder_new(NULL, DF1_CHECK_CRC), DF1_E_INVAL);
	assert_int_equal(df1_decoder_new(&d, (enum df1_check)7), DF1_E_INVAL);
	assert_null(d);
	assert_int_equal(df1_decoder_set_half_duplex(NULL, true), DF1_E_INVAL);
	assert_int_equal(df1_decoder_feed(NULL, f->wire, f->n, &s), 0);
	assert_int_equal(s.kind, DF1_SYM_NONE);
	df1_decoder_free(NULL);
	df1_decoder_reset(NULL);

	assert_int_equal(df1_decoder_new(&d, DF1_CHECK_AUTO), DF1_OK);
	assert_non_null(d);
	used = df1_decoder_feed(d, f->wire, f->n, &s);
	assert_int_equal(used, f->n);
	assert_int_equal(s.kind, DF1_SYM_FRAME);
	assert_int_equal(s.check, DF1_CHECK_BCC);
	assert_true(s.check_ok);
	assert_memory_equal(s.data, f->app, f->app_len);

	/* full duplex by default: DLE ENQ; half duplex: a poll */
	used = df1_decoder_feed(d, v->wire, v->n, &s);
	assert_int_equal(used, 2);
	assert_int_equal(s.kind, DF1_SYM_ENQ);
	df1_decoder_reset(d);
	assert_int_equal(df1_decoder_set_half_duplex(d, true), DF1_OK);
	used = df1_decoder_feed(d, v->wire, v->n, &s);
	assert_int_equal(used, v->n);
	assert_int_equal(s.kind, DF1_SYM_POLL);
	assert_int_equal(s.station, 0x10);
	assert_int_equal(df1_decoder_set_half_duplex(d, false), DF1_OK);
	/* DLE 0F is NAK by default, as on a handle */
	static const uint8_t nak0f[] = { 0x10, 0x0F };
	used = df1_decoder_feed(d, nak0f, 2, &s);
	assert_int_equal(s.kind, DF1_SYM_NAK);
	df1_decoder_free(d);
}

/* df1_decoder_set_option: the master message of doc/PROTOCOL.md 7.3 to station 1 ends in
 * A8 (BCC over STN + data, derived-hd-master-A2-stn1) and would end in A6 with
 * STX summed too (doc/PROTOCOL.md 2.2, [UNCERTAIN]); each reading takes its own and
 * reports the other as a bad BCC. DLE 0F, embedded responses, the EOT trailer
 * follow their options; others are refused. */
static void test_frame_public_decoder_options(void **state)
{
	const struct vec *v = vec_named("derived-hd-master-A2-stn1/bcc");
	uint8_t stx[64];
	struct df1_decoder *d = NULL;
	struct df1_symbol s;
	static const uint8_t nak0f[] = { 0x10, 0x0F }, eot_bcc[] = { 0x10, 0x04, 0xFC, 0x10, 0x06 };

	(void)state;
	assert_non_null(v);
	assert_int_equal(v->wire[v->n - 1], 0xA8);
	memcpy(stx, v->wire, v->n);
	stx[v->n - 1] = 0xA6;
	assert_int_equal(df1_decoder_new(&d, DF1_CHECK_BCC), DF1_OK);
	/* default: STN + data */
	assert_int_equal(df1_decoder_feed(d, v->wire, v->n, &s), v->n);
	assert_true(s.kind == DF1_SYM_FRAME && s.master_msg && s.check_ok);
	assert_int_equal(df1_decoder_feed(d, stx, v->n, &s), v->n);
	assert_true(s.kind == DF1_SYM_FRAME && !s.check_ok);
	assert_int_equal(s.check_expected, 0xA8);
	assert_int_equal(s.check_actual, 0xA6);
	/* STX summed too */
	assert_int_equal(df1_decoder_set_option(d, DF1_OPT_HD_BCC_INCLUDES_STX, 1), DF1_OK);
	assert_int_equal(df1_decoder_feed(d, stx, v->n, &s), v->n);
	assert_true(s.kind == DF1_SYM_FRAME && s.master_msg && s.check_ok);
	assert_memory_equal(s.data, v->app, v->app_len);
	assert_int_equal(df1_decoder_feed(d, v->wire, v->n, &s), v->n);
	assert_true(s.kind == DF1_SYM_FRAME && !s.check_ok);
	assert_int_equal(s.check_expected, 0xA6);
	assert_int_equal(df1_decoder_set_option(d, DF1_OPT_HD_BCC_INCLUDES_STX, 0), DF1_OK);
	assert_int_equal(df1_decoder_feed(d, v->wire, v->n, &s), v->n);
	assert_true(s.check_ok);
	/* DLE 0F: NAK by default, an invalid DLE sequence without the option */
	assert_int_equal(df1_decoder_set_option(d, DF1_OPT_ACCEPT_NAK_0F, 0), DF1_OK);
	df1_decoder_feed(d, nak0f, 2, &s);
	assert_int_equal(s.kind, DF1_SYM_ERROR);
	assert_int_equal(df1_decoder_set_option(d, DF1_OPT_ACCEPT_NAK_0F, 1), DF1_OK);
	df1_decoder_feed(d, nak0f, 2, &s);
	assert_int_equal(s.kind, DF1_SYM_NAK);
	/* a byte after DLE EOT skipped with DF1_OPT_EOT_WITH_BCC */
	assert_int_equal(df1_decoder_set_option(d, DF1_OPT_EOT_WITH_BCC, 1), DF1_OK);
	{
		size_t pos = 0, k;
		enum df1_sym got[4];
		int ng = 0;

		while (pos < sizeof eot_bcc && ng < 4) {
			k = df1_decoder_feed(d, eot_bcc + pos, sizeof eot_bcc - pos, &s);
			pos += k;
			if (s.kind != DF1_SYM_NONE)
				got[ng++] = s.kind;
		}
		assert_int_equal(ng, 2);
		assert_int_equal(got[0], DF1_SYM_EOT);
		assert_int_equal(got[1], DF1_SYM_ACK);
	}
	/* not decoding options, not a value */
	assert_int_equal(df1_decoder_set_option(d, DF1_OPT_RS485, 1), DF1_E_INVAL);
	assert_int_equal(df1_decoder_set_option(d, DF1_OPT_HD_BCC_INCLUDES_STX, 2), DF1_E_INVAL);
	assert_int_equal(df1_decoder_set_option(NULL, DF1_OPT_HD_BCC_INCLUDES_STX, 1), DF1_E_INVAL);
	assert_int_equal(df1_decoder_set_option(d, DF1_OPT_EMBEDDED_RESPONSES, 0), DF1_OK);
	df1_decoder_free(d);
}

/* Auto duplex (doc/PROTOCOL.md 2.1 poll DLE ENQ STN BCC, BCC = two's complement of STN,
 * STN 10h stuffed; doc/PROTOCOL.md 1.3 full-duplex DLE ENQ): the same symbols whatever the
 * pieces the bytes come in. */
static void expect_auto(const uint8_t *in, size_t n, const enum df1_sym *kinds, size_t nk,
                        int station)
{
	struct frame_decoder d;
	struct run whole, part;

	frame_decoder_init(&d, DF1_CHECK_AUTO, FRAME_OPT_DUPLEX_AUTO);
	run_chunks(&d, in, n, 0, &whole);
	assert_int_equal(whole.nrecs, nk);
	assert_int_equal(whole.consumed, n);
	for (size_t i = 0; i < nk; i++)
		assert_int_equal(whole.recs[i].s.kind, kinds[i]);
	if (station >= 0) {
		assert_true(whole.recs[0].s.has_station);
		assert_int_equal(whole.recs[0].s.station, station);
		assert_int_equal(whole.recs[0].s.wire_len, n);
	}
	frame_decoder_reset(&d);
	run_chunks(&d, in, n, 1, &part);
	assert_same_runs(&whole, &part);
	for (size_t pos = 1; pos < n; pos++) {
		frame_decoder_reset(&d);
		run_split(&d, in, n, pos, &part);
		assert_same_runs(&whole, &part);
	}
}

static void test_frame_auto_duplex_poll_or_enq(void **state)
{
	static const enum df1_sym poll[] = { DF1_SYM_POLL };
	static const enum df1_sym enq_frame[] = { DF1_SYM_ENQ, DF1_SYM_FRAME };
	static const enum df1_sym enq_ack[] = { DF1_SYM_ENQ, DF1_SYM_ACK };
	static const enum df1_sym enq_enq_poll[] = { DF1_SYM_ENQ, DF1_SYM_ENQ, DF1_SYM_POLL };
	static const enum df1_sym poll_frame[] = { DF1_SYM_POLL, DF1_SYM_FRAME };
	const char *names[] = { "derived-hd-poll-01/bcc", "derived-hd-poll-16/bcc",
	                        "derived-hd-poll-255/bcc" };
	const int stations[] = { 1, 0x10, 0xFF };
	const struct vec *f = vec_named("KE-plc2-read-cmd/bcc");
	const struct vec *m = vec_named("derived-hd-master-A2-stn1/bcc");
	uint8_t buf[MAX_WIRE + 8];
	struct frame_decoder d;
	struct df1_symbol s;

	(void)state;
	for (size_t i = 0; i < 3; i++) {
		const struct vec *v = vec_named(names[i]);
		expect_auto(v->wire, v->n, poll, 1, stations[i]);
	}
	/* DLE ENQ then a frame (DLE STX): the ENQ, then the frame */
	buf[0] = 0x10;
	buf[1] = 0x05;
	memcpy(buf + 2, f->wire, f->n);
	expect_auto(buf, f->n + 2, enq_frame, 2, -1);
	/* DLE ENQ, DLE DLE (noise), the frame */
	buf[2] = 0x10;
	buf[3] = 0x10;
	memcpy(buf + 4, f->wire, f->n);
	expect_auto(buf, f->n + 4, enq_frame, 2, -1);
	/* DLE ENQ, a non-poll byte (noise), the frame */
	buf[2] = 0x33;
	memcpy(buf + 3, f->wire, f->n);
	expect_auto(buf, f->n + 3, enq_frame, 2, -1);
	/* a master message after DLE ENQ */
	memcpy(buf + 2, m->wire, m->n);
	expect_auto(buf, m->n + 2, enq_frame, 2, -1);
	/* DLE ENQ DLE ACK; DLE ENQ DLE ENQ then a poll of 1 */
	static const uint8_t ea[] = { 0x10, 0x05, 0x10, 0x06 };
	expect_auto(ea, sizeof ea, enq_ack, 2, -1);
	static const uint8_t eep[] = { 0x10, 0x05, 0x10, 0x05, 0x10, 0x05, 0x01, 0xFF };
	expect_auto(eep, sizeof eep, enq_enq_poll, 3, -1);
	/* a poll then the slave's message */
	memcpy(buf, vec_named("derived-hd-poll-01/bcc")->wire, 4);
	memcpy(buf + 4, f->wire, f->n);
	expect_auto(buf, f->n + 4, poll_frame, 2, -1);

	/* a poll's shape with a bad BCC: ENQ; the STN byte is noise */
	static const uint8_t bad[] = { 0x10, 0x05, 0x01, 0xFE };
	frame_decoder_init(&d, DF1_CHECK_AUTO, FRAME_OPT_DUPLEX_AUTO);
	assert_int_equal(frame_decoder_feed(&d, bad, 3, &s), 3);
	assert_int_equal(s.kind, DF1_SYM_NONE);
	assert_true(frame_decoder_busy(&d));
	/* the BCC byte decides and is left for the next call */
	assert_int_equal(frame_decoder_feed(&d, bad + 3, 1, &s), 0);
	assert_int_equal(s.kind, DF1_SYM_ENQ);
	assert_int_equal(s.wire_len, 2);
	assert_int_equal(d.noise, 1);
	assert_int_equal(frame_decoder_feed(&d, bad + 3, 1, &s), 1);
	assert_int_equal(s.kind, DF1_SYM_NONE);
	assert_int_equal(d.noise, 2);
	assert_false(frame_decoder_busy(&d));

	/* the public decoder: either setter replaces the other */
	struct df1_decoder *pd = NULL;
	assert_int_equal(df1_decoder_set_duplex_auto(NULL, true), DF1_E_INVAL);
	assert_int_equal(df1_decoder_new(&pd, DF1_CHECK_AUTO), DF1_OK);
	assert_int_equal(df1_decoder_set_duplex_auto(pd, true), DF1_OK);
	assert_int_equal(df1_decoder_feed(pd, bad, 3, &s), 3);
	assert_int_equal(df1_decoder_feed(pd, bad + 3, 1, &s), 0);
	assert_int_equal(s.kind, DF1_SYM_ENQ);
	assert_int_equal(df1_decoder_feed(pd, bad + 3, 1, &s), 1);
	assert_int_equal(df1_decoder_feed(pd, eep + 4, 4, &s), 4);
	assert_int_equal(s.kind, DF1_SYM_POLL);
	assert_int_equal(s.station, 1);
	assert_int_equal(df1_decoder_set_half_duplex(pd, true), DF1_OK);
	assert_int_equal(df1_decoder_feed(pd, bad, 4, &s), 4);
	assert_int_equal(s.kind, DF1_SYM_ERROR);
	assert_int_equal(s.error, DF1_ID_ERR_BAD_BCC);
	assert_int_equal(df1_decoder_set_half_duplex(pd, false), DF1_OK);
	assert_int_equal(df1_decoder_feed(pd, eep + 4, 4, &s), 2);
	assert_int_equal(s.kind, DF1_SYM_ENQ);
	df1_decoder_free(pd);
}

/* df1_decoder_dle_pending: a DLE still waiting for its second byte, in a frame
 * or outside; DLE DLE (a data 10) is none. */
static void test_frame_public_decoder_dle_pending(void **state)
{
	static const uint8_t open_dle[] = { 0x10, 0x02, 0x01, 0x00, 0x10 };
	static const uint8_t data_10[] = { 0x10, 0x02, 0x01, 0x00, 0x10, 0x10 };
	static const uint8_t lone[] = { 0x10 };
	static const uint8_t stx[] = { 0x02 };
	struct df1_decoder *d = NULL;
	struct df1_symbol s;

	(void)state;
	assert_false(df1_decoder_dle_pending(NULL));
	assert_int_equal(df1_decoder_new(&d, DF1_CHECK_BCC), DF1_OK);
	assert_false(df1_decoder_dle_pending(d));
	assert_int_equal(df1_decoder_feed(d, open_dle, sizeof open_dle, &s), sizeof open_dle);
	assert_int_equal(s.kind, DF1_SYM_NONE);
	assert_true(df1_decoder_dle_pending(d));
	/* the STX alone ends the frame as no ETX (2518), its data as far as it went */
	df1_decoder_feed(d, stx, 1, &s);
	assert_int_equal(s.kind, DF1_SYM_ERROR);
	assert_int_equal(s.error, DF1_ID_NTC_NO_ETX_RCVD);
	assert_int_equal(s.len, 2);
	df1_decoder_reset(d);
	assert_int_equal(df1_decoder_feed(d, data_10, sizeof data_10, &s), sizeof data_10);
	assert_false(df1_decoder_dle_pending(d));
	df1_decoder_reset(d);
	df1_decoder_feed(d, lone, 1, &s);
	assert_true(df1_decoder_dle_pending(d));
	df1_decoder_free(d);
}

int main(int argc, char **argv)
{
	const char *env = getenv("DF1_VECTORS");
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_frame_crc16_check_value_bb3d),
		cmocka_unit_test(test_frame_public_decoder_options),
		cmocka_unit_test(test_frame_public_decoder_dle_pending),
		cmocka_unit_test(test_frame_bcc_manual_examples),
		cmocka_unit_test(test_frame_vectors_decode_one_good_symbol),
		cmocka_unit_test(test_frame_vectors_reencode_byte_for_byte),
		cmocka_unit_test(test_frame_vectors_split_anywhere_same_result),
		cmocka_unit_test(test_frame_vectors_corrupted_byte_never_accepted),
		cmocka_unit_test(test_frame_random_round_trips),
		cmocka_unit_test(test_frame_embedded_ack_nak_inside_frame),
		cmocka_unit_test(test_frame_noise_between_frames_skipped),
		cmocka_unit_test(test_frame_too_long_is_2512_after_check),
		cmocka_unit_test(test_frame_too_short_is_2513),
		cmocka_unit_test(test_frame_invalid_symbol_after_dle_is_2514),
		cmocka_unit_test(test_frame_new_start_inside_frame_is_2518),
		cmocka_unit_test(test_frame_poll_bad_bcc_is_error),
		cmocka_unit_test(test_frame_enq_full_duplex_poll_half_duplex),
		cmocka_unit_test(test_frame_eot_trailer_option),
		cmocka_unit_test(test_frame_auto_check_on_vectors),
		cmocka_unit_test(test_frame_hd_bcc_includes_stx_gives_a6),
		cmocka_unit_test(test_frame_bad_check_reports_expected_and_actual),
		cmocka_unit_test(test_frame_busy_inside_symbol_only),
		cmocka_unit_test(test_frame_encoders_reject_bad_arguments),
		cmocka_unit_test(test_frame_public_decoder),
		cmocka_unit_test(test_frame_auto_duplex_poll_or_enq),
	};

	if (argc > 1)
		vec_path = argv[1];
	else if (env && *env)
		vec_path = env;
	return cmocka_run_group_tests(tests, load_vectors, NULL);
}
