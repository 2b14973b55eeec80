/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_telnet - the Telnet framing of rfc2217:// (lib/proto/telnet.c,
 * doc/PROTOCOL.md 9) as a device server's bytes reach it:
 *  - any input decodes without a subnegotiation over TELNET_SB_MAX and with
 *    every data byte accounted for;
 *  - the input taken as data, escaped (each 255 doubled) and decoded again,
 *    is the same bytes, all of them DATA;
 *  - a COM-PORT-OPTION command made from the input's first bytes decodes to
 *    one subnegotiation of option 44 holding the code and the value.
 * Input: any bytes.
 */
#include "fuzz.h"

#include <string.h>

#include "proto/telnet.h"

static void decode_any(const uint8_t *data, size_t size)
{
	struct telnet_decoder d;
	struct telnet_event ev;

	telnet_decoder_init(&d);
	for (size_t i = 0; i < size; i++) {
		enum telnet_ev e = telnet_feed(&d, data[i], &ev);

		if (e == TELNET_EV_SB)
			FUZZ_CHECK(ev.sb && ev.sb_len <= TELNET_SB_MAX, "subnegotiation of %zu bytes", ev.sb_len);
		FUZZ_CHECK(e >= TELNET_EV_NONE && e <= TELNET_EV_OTHER, "event %d", (int)e);
	}
}

static void escape_round_trip(const uint8_t *data, size_t size)
{
	static uint8_t esc[2 * 4096];
	struct telnet_decoder d;
	struct telnet_event ev;
	size_t used = 0, n, got = 0;

	if (size > sizeof esc / 2)
		size = sizeof esc / 2;
	n = telnet_escape(data, size, esc, sizeof esc, &used);
	FUZZ_CHECK(used == size, "escape took %zu of %zu bytes with room for all", used, size);
	telnet_decoder_init(&d);
	for (size_t i = 0; i < n; i++) {
		enum telnet_ev e = telnet_feed(&d, esc[i], &ev);

		if (e == TELNET_EV_NONE)
			continue;
		FUZZ_CHECK(e == TELNET_EV_DATA, "escaped data decoded to event %d at %zu", (int)e, i);
		FUZZ_CHECK(got < size && ev.byte == data[got], "byte %zu: %02x, sent %02x", got, ev.byte,
		           got < size ? data[got] : 0);
		got++;
	}
	FUZZ_CHECK(got == size, "%zu bytes back of %zu", got, size);
}

static void cpc_round_trip(const uint8_t *data, size_t size)
{
	uint8_t out[7 + 2 * 4];
	struct telnet_decoder d;
	struct telnet_event ev;
	size_t n, nval, sbs = 0;

	if (size < 1)
		return;
	nval = (size - 1) > 4 ? 4 : size - 1;
	n = telnet_cpc(data[0], data + 1, nval, out);
	FUZZ_CHECK(n >= 6 && n <= sizeof out, "telnet_cpc wrote %zu bytes", n);
	telnet_decoder_init(&d);
	for (size_t i = 0; i < n; i++) {
		enum telnet_ev e = telnet_feed(&d, out[i], &ev);

		if (e == TELNET_EV_NONE)
			continue;
		FUZZ_CHECK(e == TELNET_EV_SB && i == n - 1, "event %d at %zu of %zu", (int)e, i, n);
		FUZZ_CHECK(ev.opt == TELNET_OPT_COMPORT && ev.sb_len == 1 + nval && ev.sb[0] == data[0] &&
		           memcmp(ev.sb + 1, data + 1, nval) == 0, "subnegotiation differs from what was sent");
		sbs++;
	}
	FUZZ_CHECK(sbs == 1, "%zu subnegotiations from one command", sbs);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	decode_any(data, size);
	escape_round_trip(data, size);
	cpc_round_trip(data, size);
	return 0;
}
