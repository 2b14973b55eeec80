/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_poll - the poll engine (lib/poll: scan plan, block reads, station
 * health, write queue) against a hostile responder on the mock port
 * (fuzz_peer.h): a few tags on three stations, df1_poll() run a few times.
 *
 * Input: byte 0 the line (as fuzz_link: bit 0 half duplex, bit 1 BCC, bits
 * 2-4 PLC type), byte 1 the scans to run and the writes to queue, byte 2 a
 * tag count, then the responder's chunks.
 * Properties: df1_poll returns transactions or a DF1_E_* code; every tag's
 * quality, reason and values are sane; every queued write ends exactly once
 * (written or failed, never lost), at the latest when the handle is freed.
 */
#include "fuzz_peer.h"

#include <string.h>

static struct {
	int queued, done;
	int ids[8];
	int results[8];
} writes;

static void on_done(void *user, int tag_id, int write_id, int result)
{
	(void)user;
	(void)tag_id;
	for (int i = 0; i < writes.queued; i++)
		if (writes.ids[i] == write_id) {
			FUZZ_CHECK(writes.results[i] == 1, "write %d ended twice (%d, then %d)", write_id,
			           writes.results[i], result);
			writes.results[i] = result <= 0 ? result : 1 + result;
			writes.done++;
			return;
		}
	FUZZ_CHECK(0, "completion of write %d, never queued", write_id);
}

static int add_tag(df1_t *h, const char *name, const char *addr, int station, int count,
                   enum df1_access access)
{
	struct df1_tag_config c;

	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "%s", name);
	c.access = access;
	c.station = station;
	c.plc = h->cfg.plc;
	c.count = count;
	c.scan_ms = 0;
	if (df1_addr_parse(addr, &c.addr) < 0)
		return -1;
	return df1_tag_add(h, &c);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct fuzz_in in = { data, size };
	uint8_t line, plan, cnt;
	int tags[6], ntags = 0;
	df1_t *h;

	if (size < 3)
		return 0;
	line = fuzz_byte(&in);
	plan = fuzz_byte(&in);
	cnt = fuzz_byte(&in);
	if (df1_new(&h) != 0)
		return 0;
	h->cfg.duplex = (line & 1) ? DF1_HALF_DUPLEX_MASTER : DF1_FULL_DUPLEX;
	h->cfg.check = (line & 2) ? DF1_CHECK_BCC : DF1_CHECK_CRC;
	h->cfg.plc = (enum df1_plc)((line >> 2 & 7) % 5);
	h->cfg.plc5_float_swapped = (line & 0x20) != 0;
	h->cfg.timeout_ms = 50;
	h->cfg.cmd_timeout_ms = 500;
	h->next_tns = 1;
	if (line & 0x40)
		df1_poll_set_watchdog(h, 0, 1 + (cnt & 3));
	fuzz_peer_start(h, &in);

	tags[ntags++] = add_tag(h, "n", "N7:0", 1, cnt % 40 + 1, DF1_ACCESS_READWRITE);
	tags[ntags++] = add_tag(h, "f", "F8:0", 1, 2, DF1_ACCESS_READ);
	tags[ntags++] = add_tag(h, "b", "B3:0/5", 2, 3, DF1_ACCESS_READWRITE);
	tags[ntags++] = add_tag(h, "acc", "T4:0.ACC", 1, 1, DF1_ACCESS_READ);
	tags[ntags++] = add_tag(h, "s", "ST9:0", 2, 1, DF1_ACCESS_READ);
	tags[ntags++] = add_tag(h, "far", "N7:100", 16, cnt % 8 + 1, DF1_ACCESS_READWRITE);

	memset(&writes, 0, sizeof writes);
	for (int i = 0; i < (plan >> 4 & 3); i++) {
		struct df1_value v = { .kind = DF1_VAL_INT16, .v.i16 = (int16_t)(1000 + i) };
		int id = tags[i == 1 ? 5 : 0];
		if (id < 0)
			continue;
		int w = df1_tag_write(h, id, &v, 1, on_done, NULL);
		if (w > 0) {
			writes.ids[writes.queued] = w;
			writes.results[writes.queued++] = 1;   /* pending */
		}
	}
	for (int scan = 0; scan < (plan & 3) + 1; scan++) {
		int r = df1_poll(h, 0);
		FUZZ_CHECK(r >= 0 || strcmp(df1_errname(r), "DF1_E_UNKNOWN") != 0,
		           "df1_poll returned %d", r);
	}
	for (int i = 0; i < ntags; i++) {
		struct df1_tag_state st;
		if (tags[i] < 0 || df1_tag_get(h, tags[i], &st) < 0)
			continue;
		FUZZ_CHECK(st.quality <= DF1_QUALITY_GOOD && st.reason <= DF1_REASON_CONFIG,
		           "tag %d: quality %d reason %d", i, st.quality, st.reason);
		FUZZ_CHECK(st.quality != DF1_QUALITY_GOOD || st.has_value, "tag %d GOOD without a value", i);
		for (size_t k = 0; st.values && k < st.count; k++)
			if (st.values[k].kind == DF1_VAL_STRING)
				FUZZ_CHECK(st.values[k].v.str.len <= DF1_STRING_MAX, "tag %d: string of %u", i,
				           (unsigned)st.values[k].v.str.len);
	}
	fuzz_peer_stop();
	df1_free(h);
	FUZZ_CHECK(writes.done == writes.queued, "%d writes queued, %d ended", writes.queued,
	           writes.done);
	return 0;
}
