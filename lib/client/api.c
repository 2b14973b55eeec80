/* SPDX-License-Identifier: MPL-2.0 */
/*
 * api.c - the public read and write calls (df1_read, df1_read_addr, the typed
 * helpers, bits, raw) and the internal ones of client.h (parsed address, PLC
 * type per call).
 */
#include "client/client_int.h"

/* Parse addr for an API call; records the error on failure. */
static int client_parse(struct df1 *h, int station, const char *text, struct df1_addr *a)
{
	int rc;

	if (!text)
		return df1_fail(h, DF1_E_INVAL, station, "no address");
	rc = df1_addr_parse_plc(h->cfg.plc, text, a);
	if (rc < 0)
		return client_fail(h, rc, station, text, "%s", df1_strerror(rc));
	return 0;
}

/* Common start of a call with an address text: station check, parse, the
 * address's text for messages in what. */
static int client_begin(struct df1 *h, int station, const char *text, struct df1_addr *a,
                        char *what, size_t wcap)
{
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	rc = client_parse(h, station, text, a);
	if (rc < 0)
		return rc;
	client_atext(h->cfg.plc, a, what, wcap);
	return 0;
}

static int client_count_check(struct df1 *h, int station, const char *what, const void *p, size_t n)
{
	if (!p || n == 0)
		return client_fail(h, DF1_E_INVAL, station, what, "no values");
	if (n > 0xFFFF)
		return client_fail(h, DF1_E_INVAL, station, what, "%zu elements is too many", n);
	return 0;
}

/* Common start of df1_read_addr / df1_write_addr: checks, and the address's
 * text for messages in what. */
static int client_addr_begin(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                             const void *p, size_t n, char *what, size_t wcap)
{
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	if (!a)
		return df1_fail(h, DF1_E_INVAL, station, "no address");
	client_atext(plc, a, what, wcap);
	return client_count_check(h, station, what, p, n);
}

int client_read_at(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                   struct df1_value *out, size_t n)
{
	char what[ATEXT_MAX];
	struct io io = { .kind = IO_VALUE, .out = out };
	int rc = client_addr_begin(h, station, plc, a, out, n, what, sizeof what);

	if (rc < 0)
		return rc;
	if (a->bit != DF1_ADDR_NONE)
		return client_read_bits(h, station, what, plc, a, n, NULL, out);
	return client_read_elems(h, station, what, plc, a, n, &io);
}

int client_write_at(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                    const struct df1_value *in, size_t n)
{
	char what[ATEXT_MAX];
	struct io io = { .kind = IO_VALUE, .in = in };
	int rc = client_addr_begin(h, station, plc, a, in, n, what, sizeof what);

	if (rc < 0)
		return rc;
	if (a->bit != DF1_ADDR_NONE)
		return client_write_bits(h, station, what, plc, a, n, NULL, in);
	return client_write_elems(h, station, what, plc, a, n, &io);
}

int df1_read_addr(df1_t *h, int station, const struct df1_addr *a, struct df1_value *out, size_t n)
{
	return client_read_at(h, station, h ? h->cfg.plc : DF1_PLC_SLC, a, out, n);
}

int df1_write_addr(df1_t *h, int station, const struct df1_addr *a, const struct df1_value *in, size_t n)
{
	return client_write_at(h, station, h ? h->cfg.plc : DF1_PLC_SLC, a, in, n);
}

int df1_read(df1_t *h, int station, const char *addr, struct df1_value *out, size_t n)
{
	struct df1_addr a;
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	rc = client_parse(h, station, addr, &a);
	return rc < 0 ? rc : df1_read_addr(h, station, &a, out, n);
}

int df1_write(df1_t *h, int station, const char *addr, const struct df1_value *in, size_t n)
{
	struct df1_addr a;
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	rc = client_parse(h, station, addr, &a);
	return rc < 0 ? rc : df1_write_addr(h, station, &a, in, n);
}

/* Typed helpers: which addresses hold which C type. */
enum client_ctype { CT_I16, CT_I32, CT_F32, CT_TCR, CT_STRING };

static bool client_type_fits(const struct df1_addr *a, enum client_ctype ct)
{
	if (a->bit != DF1_ADDR_NONE)
		return false;
	switch (ct) {
	case CT_I16:
		return client_is_word_type(a->type) || (client_is_tcr(a->type) && a->sub != DF1_ADDR_NONE);
	case CT_I32:
		return a->type == DF1_FT_L;
	case CT_F32:
		return a->type == DF1_FT_F;
	case CT_TCR:
		return client_is_tcr(a->type) && a->sub == DF1_ADDR_NONE;
	case CT_STRING:
		return a->type == DF1_FT_ST;
	}
	return false;
}

static const char *const client_ctype_names[] = {
	[CT_I16] = "16-bit integer", [CT_I32] = "32-bit integer", [CT_F32] = "float",
	[CT_TCR] = "timer/counter/control element", [CT_STRING] = "string",
};

static const enum io_kind client_ctype_io[] = {
	[CT_I16] = IO_I16, [CT_I32] = IO_I32, [CT_F32] = IO_F32, [CT_TCR] = IO_TCR, [CT_STRING] = IO_STRING,
};

/* Common start of the typed helpers: check, parse, type check. */
static int client_typed(struct df1 *h, int station, const char *addr, enum client_ctype ct,
                        const void *p, size_t n, struct df1_addr *a, char *what, size_t wcap)
{
	int rc = client_begin(h, station, addr, a, what, wcap);

	if (rc < 0)
		return rc;
	rc = client_count_check(h, station, what, p, n);
	if (rc < 0)
		return rc;
	if (!client_type_fits(a, ct))
		return client_fail(h, DF1_E_TYPE, station, what, "does not hold a %s",
		                client_ctype_names[ct]);
	return 0;
}

static int client_typed_read(df1_t *h, int station, const char *addr, enum client_ctype ct,
                             void *out, size_t n)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	struct io io = { .kind = client_ctype_io[ct], .out = out };
	int rc = client_typed(h, station, addr, ct, out, n, &a, what, sizeof what);

	return rc < 0 ? rc : client_read_elems(h, station, what, h->cfg.plc, &a, n, &io);
}

static int client_typed_write(df1_t *h, int station, const char *addr, enum client_ctype ct,
                              const void *in, size_t n)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	struct io io = { .kind = client_ctype_io[ct], .in = in };
	int rc = client_typed(h, station, addr, ct, in, n, &a, what, sizeof what);

	return rc < 0 ? rc : client_write_elems(h, station, what, h->cfg.plc, &a, n, &io);
}

int df1_read_int16(df1_t *h, int station, const char *addr, int16_t *out, size_t n)
{
	return client_typed_read(h, station, addr, CT_I16, out, n);
}

int df1_read_int32(df1_t *h, int station, const char *addr, int32_t *out, size_t n)
{
	return client_typed_read(h, station, addr, CT_I32, out, n);
}

int df1_read_float(df1_t *h, int station, const char *addr, float *out, size_t n)
{
	return client_typed_read(h, station, addr, CT_F32, out, n);
}

int df1_read_tcr(df1_t *h, int station, const char *addr, struct df1_tcr *out, size_t n)
{
	return client_typed_read(h, station, addr, CT_TCR, out, n);
}

int df1_write_int16(df1_t *h, int station, const char *addr, const int16_t *in, size_t n)
{
	return client_typed_write(h, station, addr, CT_I16, in, n);
}

int df1_write_int32(df1_t *h, int station, const char *addr, const int32_t *in, size_t n)
{
	return client_typed_write(h, station, addr, CT_I32, in, n);
}

int df1_write_float(df1_t *h, int station, const char *addr, const float *in, size_t n)
{
	return client_typed_write(h, station, addr, CT_F32, in, n);
}

int df1_write_tcr(df1_t *h, int station, const char *addr, const struct df1_tcr *in, size_t n)
{
	return client_typed_write(h, station, addr, CT_TCR, in, n);
}

/* One string element; returns its length. */
int df1_read_string(df1_t *h, int station, const char *addr, char *out, size_t cap)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	struct io io = { .kind = IO_STRING, .out = out, .cap = cap };
	int rc = client_typed(h, station, addr, CT_STRING, out, cap ? 1 : 0, &a, what, sizeof what);

	if (rc < 0)
		return rc;
	rc = client_read_elems(h, station, what, h->cfg.plc, &a, 1, &io);
	return rc < 0 ? rc : io.len;
}

/* One string element; returns its length. */
int df1_write_string(df1_t *h, int station, const char *addr, const char *text)
{
	int rc = client_typed_write(h, station, addr, CT_STRING, text, 1);

	return rc < 0 ? rc : (int)strlen(text);
}

static int client_bit_addr(df1_t *h, int station, const char *addr, struct df1_addr *a, char *what,
                           size_t wcap)
{
	int rc = client_begin(h, station, addr, a, what, wcap);

	if (rc < 0)
		return rc;
	if (a->bit == DF1_ADDR_NONE)
		return client_fail(h, DF1_E_TYPE, station, what, "not a bit address");
	return 0;
}

int df1_read_bit(df1_t *h, int station, const char *addr, bool *out)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	int rc = client_bit_addr(h, station, addr, &a, what, sizeof what);

	if (rc < 0)
		return rc;
	if (!out)
		return client_fail(h, DF1_E_INVAL, station, what, "no output");
	rc = client_read_bits(h, station, what, h->cfg.plc, &a, 1, out, NULL);
	return rc < 0 ? rc : 0;
}

int df1_write_bit(df1_t *h, int station, const char *addr, bool value)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	int rc = client_bit_addr(h, station, addr, &a, what, sizeof what);

	if (rc < 0)
		return rc;
	rc = client_write_bits(h, station, what, h->cfg.plc, &a, 1, &value, NULL);
	return rc < 0 ? rc : 0;
}

/* Raw: nbytes = whole elements as on the wire (2 bytes per element for a
 * sub-element). A read may have its first packet run by the caller (first). */
static int client_raw_parsed(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *ap,
                             const char *what, const uint8_t *in, uint8_t *out, size_t nbytes,
                             const struct rd_first *first)
{
	struct df1_addr a = *ap;
	struct io io = { .kind = IO_RAW, .in = in, .out = out };
	size_t esize;
	int rc;

	if (a.bit != DF1_ADDR_NONE)
		return client_fail(h, DF1_E_TYPE, station, what, "raw access takes a word or element address");
	esize = a.sub != DF1_ADDR_NONE ? 2 : (size_t)df1_file_type_element_size(a.type);
	if ((!in && !out) || nbytes == 0 || nbytes % esize)
		return client_fail(h, DF1_E_INVAL, station, what, "%zu bytes is not a whole number of %zu-byte "
		                "elements", nbytes, esize);
	rc = client_count_check(h, station, what, what, nbytes / esize);
	if (rc < 0)
		return rc;
	if (in)
		rc = client_write_elems(h, station, what, plc, &a, nbytes / esize, &io);
	else
		rc = client_read_elems_first(h, station, what, plc, &a, nbytes / esize, &io, first);
	if (rc < 0 || (first && first->mode == RD_BUILD))
		return rc;
	return (int)nbytes;
}

static int client_raw(df1_t *h, int station, const char *addr, const uint8_t *in, uint8_t *out,
                      size_t nbytes)
{
	char what[ATEXT_MAX];
	struct df1_addr a;
	int rc = client_begin(h, station, addr, &a, what, sizeof what);

	if (rc < 0)
		return rc;
	return client_raw_parsed(h, station, h->cfg.plc, &a, what, in, out, nbytes, NULL);
}

/* client_read_raw_at with its first packet run by the caller (first: NULL none). */
static int client_read_raw_first(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                                 uint8_t *buf, size_t nbytes, const struct rd_first *first)
{
	char what[ATEXT_MAX];
	int rc = client_check(h, station);

	if (rc < 0)
		return rc;
	if (!a)
		return df1_fail(h, DF1_E_INVAL, station, "no address");
	client_atext(plc, a, what, sizeof what);
	return client_raw_parsed(h, station, plc, a, what, NULL, buf, nbytes, first);
}

int client_read_raw_at(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                       uint8_t *buf, size_t nbytes)
{
	return client_read_raw_first(h, station, plc, a, buf, nbytes, NULL);
}

int client_read_raw_cmd(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                        size_t nbytes, uint8_t *cmd, size_t cap)
{
	uint8_t scratch[1];     /* not written: nothing is read */
	struct rd_first f = { .mode = RD_BUILD, .cmd = cmd, .cap = cap };

	if (!cmd)
		return h ? df1_fail(h, DF1_E_INVAL, station, "no command buffer") : DF1_E_INVAL;
	return client_read_raw_first(h, station, plc, a, scratch, nbytes, &f);
}

int client_read_raw_reply(struct df1 *h, int station, enum df1_plc plc, const struct df1_addr *a,
                          uint8_t *buf, size_t nbytes, int rc, const uint8_t *reply)
{
	struct rd_first f = { .mode = RD_TAKE, .rc = rc, .reply = reply };

	return client_read_raw_first(h, station, plc, a, buf, nbytes, &f);
}

int df1_read_raw(df1_t *h, int station, const char *addr, uint8_t *buf, size_t nbytes)
{
	return client_raw(h, station, addr, NULL, buf, nbytes);
}

int df1_write_raw(df1_t *h, int station, const char *addr, const uint8_t *buf, size_t nbytes)
{
	return client_raw(h, station, addr, buf, NULL, nbytes);
}
