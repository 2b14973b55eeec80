/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_peer - a hostile responder on the scripted port of the unit tests
 * (tests/support/mock_port.c) for the link and poll targets: after each transmission
 * of the master it answers with the next chunk of the fuzz input. Reads find
 * an expired deadline when nothing is queued (virtual time: no waiting).
 *
 * A chunk is a control byte C, a length L and L bytes:
 *   C & 0x80   say nothing this time (the bytes are skipped)
 *   C & 0x01   the bytes are app bytes, framed here with the line's check
 *              (else they go out raw, as they are)
 *   C & 0x02   ... as the reply to the master's last command: its DST and SRC
 *              swapped, CMD | 40h, its TNS, then STS = the first byte, then the rest
 *   C & 0x04   DLE ACK first
 *   C & 0x08   the check is wrong (the last byte flipped)
 *   C & 0x10   DLE EOT after it (half duplex: nothing more to send)
 * so that replies that match reach the client's decoding despite the CRC.
 */
#ifndef LIBDF1_FUZZ_PEER_H
#define LIBDF1_FUZZ_PEER_H

#include "fuzz.h"

#include "df1_int.h"

/* Point h, configured, at the mock port and answer from in (which must outlive
 * the run). */
void fuzz_peer_start(struct df1 *h, struct fuzz_in *in);
/* Forget the port's queue and hooks. */
void fuzz_peer_stop(void);

/* What went over the line in this run, as app bytes of frames with a good
 * check: the master's commands, and every reply the responder sent (decoded
 * both as the continuing stream and chunk by chunk, since the master may have
 * flushed a chunk's start), whatever chunk kind produced it. */
struct fuzz_peer_frame {
	size_t len;
	uint8_t app[FRAME_MAX_DATA];
};
size_t fuzz_peer_commands(const struct fuzz_peer_frame **out);
size_t fuzz_peer_replies(const struct fuzz_peer_frame **out);

#endif
