/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_pccc_command - the responder side (lib/server/server_*.c): a received command
 * decoded and run against a data table (df1_table, as df1sim serves it) for
 * each PLC type, and its reply built.
 * Input: byte 0 picks the PLC type (and bit 3 the PLC-5 float order), the rest
 * is the command's app bytes (DST SRC CMD STS TNS FNC ...).
 * Properties: a reply fits its buffer and is a reply to this command (DST and
 * SRC swapped, CMD | 40h, the same TNS); the table survives any command.
 */
#include "fuzz.h"

#include <string.h>

#include "df1_int.h"
#include "proto/pccc.h"
#include "server/server.h"

static df1_t *h;
static struct df1_table *pristine[5];

static void setup(void)
{
	if (h)
		return;
	FUZZ_CHECK(df1_new(&h) == 0, "df1_new");
	for (int p = 0; p < 5; p++) {
		FUZZ_CHECK(df1_table_new(&pristine[p], (enum df1_plc)p) == 0, "df1_table_new");
		FUZZ_CHECK(df1_table_add_default_files(pristine[p]) == 0, "default files");
		/* files past 254 (the FF escape), a long integer and an ASCII file */
		df1_table_add_file(pristine[p], DF1_FT_N, 300, 300);
		df1_table_add_file(pristine[p], DF1_FT_L, 12, 8);
		df1_table_add_file(pristine[p], DF1_FT_A, 13, 8);
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	uint8_t reply[FRAME_MAX_DATA + 64];
	struct server_ctx ctx;
	struct df1_table *t;
	struct pccc_msg m;
	int plc, r;

	setup();
	if (size < 1)
		return 0;
	plc = data[0] % 5;
	h->cfg.plc = (enum df1_plc)plc;
	h->cfg.plc5_float_swapped = (data[0] & 8) != 0;
	h->cfg.slc_io_82 = (data[0] & 16) != 0;
	data++;
	size--;
	if (size > FRAME_MAX_DATA)
		return 0;
	if (df1_table_clone(&t, pristine[plc]) < 0)
		return 0;
	ctx.ops = df1_table_server_ops(t);
	ctx.user = t;
	memset(reply, 0xEE, sizeof reply);
	r = server_handle(h, &ctx, data, size, reply, FRAME_MAX_DATA);
	FUZZ_CHECK(r <= FRAME_MAX_DATA, "reply of %d bytes", r);
	FUZZ_CHECK(reply[FRAME_MAX_DATA] == 0xEE, "reply written past its buffer");
	if (r > 0) {
		/* the header of a command is DST SRC CMD STS TNS (doc/PROTOCOL.md):
		 * a reply needs all six bytes to answer it */
		FUZZ_CHECK(size >= 6, "a reply of %d bytes to a command of %zu bytes", r, size);
		FUZZ_CHECK(pccc_decode(reply, (size_t)r, &m) >= 0 && m.is_reply,
		           "the reply (%d bytes) does not decode as one", r);
		FUZZ_CHECK(m.dst == data[1] && m.src == data[0] && m.cmd == (data[2] | 0x40) &&
		           m.tns == (uint16_t)(data[4] | data[5] << 8),
		           "reply header %02X %02X %02X TNS %04X to %02X %02X %02X", m.dst, m.src, m.cmd,
		           m.tns, data[0], data[1], data[2]);
	}
	df1_table_free(t);
	return 0;
}
