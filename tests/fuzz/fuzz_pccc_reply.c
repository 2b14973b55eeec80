/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_pccc_reply - the pure PCCC decoders a master (and df1mon) runs on what
 * comes back from the line (lib/proto/pccc.c, pccc_diag.c, msg.c): the
 * message header, typed-data descriptors and typed data (PLC-5 replies),
 * diagnostic status, element values of every file type, and the address and
 * request fields of commands as df1mon shows them.
 * Input: byte 0 picks the file type of the values, the rest is app bytes
 * (DST SRC CMD STS TNS ...).
 * Properties: what a decoder consumes lies inside its input; typed data
 * claims no more bytes than it was given; a decoded address formats or is
 * refused (DF1_E_INVAL).
 */
#include "fuzz.h"

#include <string.h>

#include "df1.h"
#include "proto/pccc.h"

static void check_addr(const struct df1_addr *a)
{
	char buf[128];

	/* the wire may name what the text syntax cannot (O162:162): refused, not overrun */
	int r = df1_addr_format(a, buf, sizeof buf);
	FUZZ_CHECK(r > 0 || r == DF1_E_INVAL, "decoded address formats to %d", r);
	FUZZ_CHECK(memchr(a->ascii, '\0', sizeof a->ascii) != NULL, "ascii address not terminated");
}

static void typed(const uint8_t *p, size_t n)
{
	struct pccc_typed t;
	unsigned id;
	uint32_t size;
	int r = pccc_dec_typedata(p, n, &id, &size);

	FUZZ_CHECK(r < 0 || (size_t)r <= n, "typedata consumed %d of %zu", r, n);
	memset(&t, 0, sizeof t);
	r = pccc_dec_typed(p, n, &t);
	if (r >= 0) {
		FUZZ_CHECK(t.consumed <= n, "typed data consumed %zu of %zu", t.consumed, n);
		FUZZ_CHECK(t.data >= p && t.data + t.len <= p + n, "typed data outside its input");
		FUZZ_CHECK(t.len == t.count * t.elem_size, "typed: %zu bytes for %zu x %u", t.len,
		           t.count, (unsigned)t.elem_size);
	}
}

static void fields(const uint8_t *p, size_t n)
{
	struct df1_addr a;
	struct pccc_plc5_req req;
	static const uint8_t fncs[] = { 0x00, 0x01, 0x02, 0x26, 0x67, 0x68 };
	uint8_t nbytes, code;
	unsigned file, elem, sub, v;
	int r;

	r = pccc_get_field(p, n, &v);
	FUZZ_CHECK(r < 0 || (size_t)r <= n, "field consumed %d of %zu", r, n);
	for (int three = 0; three < 2; three++) {
		r = pccc_dec_slc_fields(p, n, three, &nbytes, &file, &code, &elem, &sub);
		FUZZ_CHECK(r < 0 || (size_t)r <= n, "SLC fields consumed %d of %zu", r, n);
	}
	memset(&a, 0, sizeof a);
	r = pccc_dec_plc5_addr(p, n, &a);
	FUZZ_CHECK(r < 0 || (size_t)r <= n, "PLC-5 address consumed %d of %zu", r, n);
	if (r >= 0)
		check_addr(&a);
	for (size_t i = 0; i < sizeof fncs; i++) {
		memset(&req, 0, sizeof req);
		r = pccc_dec_plc5_req(fncs[i], p, n, &req);
		if (r >= 0) {
			FUZZ_CHECK(req.len == 0 || (req.data >= p && req.data + req.len <= p + n),
			           "PLC-5 request %02X: data outside its input", fncs[i]);
			check_addr(&req.addr);
		}
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct pccc_msg m;
	struct df1_msg dm;
	struct df1_diag_status ds;
	struct df1_value vals[128];
	enum df1_file_type ft;
	int r;

	if (size < 1)
		return 0;
	ft = (enum df1_file_type)(data[0] % DF1_FT_COUNT_);
	data++;
	size--;

	memset(&m, 0, sizeof m);
	r = pccc_decode(data, size, &m);
	if (r >= 0) {
		FUZZ_CHECK(m.len == 0 || (m.data >= data && m.data + m.len <= data + size),
		           "message data outside its input");
		if (m.is_reply) {
			typed(m.data, m.len);
			r = pccc_dec_diag_status(m.data, m.len, &ds);
			r = df1_values_decode(ft, m.data, m.len, vals, sizeof vals / sizeof vals[0]);
			FUZZ_CHECK(r <= (int)(sizeof vals / sizeof vals[0]), "%d values into 128", r);
		} else {
			fields(m.data, m.len);
		}
	}
	memset(&dm, 0, sizeof dm);
	r = df1_msg_decode(data, size, &dm);
	if (r >= 0) {
		FUZZ_CHECK(dm.name != NULL, "a message without a name");
		FUZZ_CHECK(dm.data_len == 0 || (dm.data >= data && dm.data + dm.data_len <= data + size),
		           "df1_msg data outside its input");
		if (dm.has_addr)
			check_addr(&dm.addr);
	}
	/* the decoders also meet these bytes where a reply's data would be */
	typed(data, size);
	fields(data, size);
	return 0;
}
