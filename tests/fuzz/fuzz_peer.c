/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_peer - the hostile responder of the link and poll targets (fuzz_peer.h).
 */
#include "fuzz_peer.h"

#include <string.h>

#include "proto/frame.h"
#include "link/link.h"
#include "support/mock_port.h"

static struct {
	struct df1 *h;
	struct fuzz_in *in;
	struct frame_decoder dec;     /* what the master sent */
	uint8_t cmd[FRAME_MAX_DATA];  /* its last command */
	size_t cmd_len;
	struct frame_decoder rx;      /* what the responder sent, as one stream */
	unsigned rx_opts;
	size_t ncmds, nreplies;
	struct fuzz_peer_frame cmds[64], replies[128];
} peer;

static void peer_keep(struct fuzz_peer_frame *list, size_t *n, size_t max, const struct df1_symbol *s)
{
	if (*n < max && s->len <= FRAME_MAX_DATA) {
		memcpy(list[*n].app, s->data, s->len);
		list[*n].len = s->len;
		(*n)++;
	}
}

/* Good reply frames in bytes the responder sent, through decoder d. */
static void peer_scan(struct frame_decoder *d, const uint8_t *buf, size_t n)
{
	while (n > 0) {
		struct df1_symbol s;
		size_t k = frame_decoder_feed(d, buf, n, &s);

		if (s.kind == DF1_SYM_FRAME && s.check_ok && s.len >= 6 && (s.data[2] & 0x40))
			peer_keep(peer.replies, &peer.nreplies, 128, &s);
		if (k == 0 && s.kind == DF1_SYM_NONE)
			break;
		buf += k;
		n -= k;
	}
}

static void peer_sent(const uint8_t *buf, size_t n)
{
	struct frame_decoder alone;

	peer_scan(&peer.rx, buf, n);
	frame_decoder_init(&alone, peer.h->cfg.check, peer.rx_opts);
	peer_scan(&alone, buf, n);
	mock_port_feed(buf, n);
}

size_t fuzz_peer_commands(const struct fuzz_peer_frame **out)
{
	*out = peer.cmds;
	return peer.ncmds;
}

size_t fuzz_peer_replies(const struct fuzz_peer_frame **out)
{
	*out = peer.replies;
	return peer.nreplies;
}

/* Nothing queued: the deadline has passed (the link takes the port's word for it). */
static void peer_idle(int64_t deadline_ms, void *user)
{
	(void)deadline_ms;
	(void)user;
	mock_port_expire();
}

static void peer_track(const uint8_t *buf, size_t n)
{
	while (n > 0) {
		struct df1_symbol s;
		size_t k = frame_decoder_feed(&peer.dec, buf, n, &s);

		if (s.kind == DF1_SYM_FRAME && s.check_ok && s.len >= 6) {
			memcpy(peer.cmd, s.data, s.len);
			peer.cmd_len = s.len;
			peer_keep(peer.cmds, &peer.ncmds, 64, &s);
		}
		if (k == 0 && s.kind == DF1_SYM_NONE)
			break;
		buf += k;
		n -= k;
	}
}

static void peer_answer(void)
{
	uint8_t app[FRAME_MAX_DATA + 8], wire[FRAME_MAX_WIRE + 8];
	const uint8_t *p;
	size_t len, n = 0, wn = 0;
	uint8_t c;

	if (peer.in->n < 2)
		return;
	c = fuzz_byte(peer.in);
	p = fuzz_take(peer.in, fuzz_byte(peer.in), &len);
	if (c & 0x80)
		return;
	if (c & 0x04) {
		wire[wn++] = DF1_DLE;
		wire[wn++] = DF1_ACK;
	}
	if (!(c & 0x01)) {
		memcpy(wire + wn, p, len);
		wn += len;
	} else {
		if ((c & 0x02) && peer.cmd_len >= 6) {
			app[0] = peer.cmd[1];
			app[1] = peer.cmd[0];
			app[2] = (uint8_t)(peer.cmd[2] | 0x40);
			app[3] = len > 0 ? p[0] : 0;
			app[4] = peer.cmd[4];
			app[5] = peer.cmd[5];
			n = 6;
			if (len > 1) {
				memcpy(app + n, p + 1, len - 1);
				n += len - 1;
			}
		} else {
			memcpy(app, p, len);
			n = len;
		}
		size_t k = frame_encode_full(peer.h->cfg.check, app, n, wire + wn, sizeof wire - wn);
		if (k > 0 && (c & 0x08))
			wire[wn + k - 1] ^= 0x5A;
		wn += k;
	}
	if (c & 0x10) {
		wire[wn++] = DF1_DLE;
		wire[wn++] = DF1_EOT;
	}
	if (wn > 0)
		peer_sent(wire, wn);
}

static void peer_on_write(const uint8_t *buf, size_t n, void *user)
{
	(void)user;
	peer_track(buf, n);
	peer_answer();
}

void fuzz_peer_start(struct df1 *h, struct fuzz_in *in)
{
	memset(&peer, 0, sizeof peer);
	peer.h = h;
	peer.in = in;
	frame_decoder_init(&peer.dec, h->cfg.check,
	                   (h->cfg.duplex != DF1_FULL_DUPLEX ? FRAME_OPT_HALF_DUPLEX : 0) |
	                   (h->cfg.hd_bcc_stx ? FRAME_OPT_HD_BCC_STX : 0));
	peer.rx_opts = link_decoder_opts(h);
	frame_decoder_init(&peer.rx, h->cfg.check, peer.rx_opts);
	mock_port_reset();
	mock_port_on_write(peer_on_write, NULL);
	mock_port_on_idle(peer_idle, NULL);
	h->port = &mock_port_ops;
	h->fd = 0;
}

void fuzz_peer_stop(void)
{
	mock_port_reset();
}
