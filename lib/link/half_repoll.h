/* SPDX-License-Identifier: MPL-2.0 */
/*
 * repoll - when a half-duplex master polls a slave again (pure: times in,
 * times out, no clock). A slave answers a command at the end of its program
 * scan; polling sooner only draws a DLE EOT, polling later wastes the line.
 * Each station's reply latency (from the ACK of our message to the poll that
 * got the reply) is learned as a moving average; the first poll goes out a
 * little before that, and after each EOT the next one when the reply is
 * likely ready, never closer together than the line's minimum gap, and less
 * often the longer a reply is overdue.
 */
#ifndef LIBDF1_REPOLL_H
#define LIBDF1_REPOLL_H

#include <stdint.h>

struct repoll_est {
	int64_t latency_us;         /* moving average; valid when samples > 0 */
	unsigned samples;
};

/* Take one latency (µs from our message's ACK to the poll that got the reply):
 * the first as it is, then 1/4 of each new one (a slower slave is followed
 * within a few transactions, a chance fast one does not stick). */
void repoll_learn(struct repoll_est *e, int64_t sample_us);
/* µs after the ACK before the first poll: 7/8 of the latency learned (a
 * little early: an EOT costs two characters, a late poll a whole wait), 0
 * while nothing is learned. */
int64_t repoll_first_us(const struct repoll_est *e);
/* µs to wait after an EOT (or a poll nobody answered), since_ack_us after the
 * ACK: until the learned latency when that is still ahead, else an eighth of
 * how overdue the reply is (so a slave much slower than learned is not polled
 * hundreds of times) but at most max_gap_us; never less than min_gap_us. */
int64_t repoll_next_us(const struct repoll_est *e, int64_t since_ack_us, int64_t min_gap_us,
                       int64_t max_gap_us);

#endif
