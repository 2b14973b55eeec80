/* SPDX-License-Identifier: MPL-2.0 */
/*
 * link_fixture - what the link tests (tests/unit/link/test_link_*.c) share: the
 * A2 read's frames of tests/data/vectors.txt, a handle on the scripted port
 * (tests/support/mock_port.c) with its log captured, byte-exact write checks,
 * replies built and fed, and a responder's handler and serve loop. The names
 * are the ones the tests were written with; they are global (each file of
 * tests/support is linked into every unit test), so no other test may define
 * a global of the same name (a static one is fine).
 */
#ifndef LINK_FIXTURE_H
#define LINK_FIXTURE_H

#include <stddef.h>
#include <stdint.h>

#include "df1_int.h"
#include "proto/frame.h"

/* SLC 0F/A2 read N7:0, 20 bytes, to station 1 (TNS filled in by the link) */
static const char A2_CMD[] = "01 00 0F 00 00 00 A2 14 07 89 00 00";
/* tests/data/vectors.txt derived-slc-A2-read-N7:0-20B, TNS 0001 */
static const char A2_FD_CRC[] = "10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 60 46";
static const char A2_FD_BCC[] = "10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 A9";
/* derived-hd-master-A2-stn1 */
static const char A2_HD_CRC[] = "10 01 01 10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 A2 84";
static const char A2_HD_BCC[] = "10 01 01 10 02 01 00 0F 00 01 00 A2 14 07 89 00 00 10 03 A8";
static const uint8_t ACK[2] = { 0x10, 0x06 };
static const uint8_t NAK[2] = { 0x10, 0x15 };
static const uint8_t ENQ[2] = { 0x10, 0x05 };
static const uint8_t EOT[2] = { 0x10, 0x04 };
/* the data of every reply the tests build */
static const uint8_t DATA20[20] = { 1, 0, 2, 0, 3, 0, 4, 0, 5, 0, 6, 0, 7, 0, 8, 0, 9, 0, 0x10, 0 };

/* the handle's log, captured (setup clears it) */
#define LOG_MAX 256
extern int log_ids[LOG_MAX];
extern size_t log_n;
extern char log_last[LOG_MAX][160];
/* the responder's handler (test_handler): calls, its STS, the last command */
extern int handler_calls;
extern uint8_t handler_sts;
extern uint8_t handler_last[FRAME_MAX_DATA];
extern size_t handler_last_len;

/* log capture; handles on the mock port; cmocka setups (full duplex, CRC) */
void log_cb(void *user, int id, enum df1_severity sev, const char *text);
size_t logged(int id);
const char *log_text(int id);
struct df1 *new_handle(enum df1_duplex duplex, enum df1_check check);
int setup(void **state);
int teardown(void **state);
/* a counter by catalog ID; hex text to bytes; the writes seen on the port */
uint64_t cnt(struct df1 *h, int id);
size_t hex(const char *text, uint8_t *buf);
void assert_write(size_t i, const char *text);
void assert_write_bytes(size_t i, const uint8_t *want, size_t n);
const uint8_t *write_after_ack(size_t i, size_t *n);
void assert_ack_and(size_t i, const uint8_t *want, size_t n);
/* replies built, framed and fed; the A2 read transacted and its reply checked */
size_t make_reply(uint8_t *app, uint8_t dst, uint8_t src, uint8_t cmd, uint8_t sts, uint16_t tns,
                  const uint8_t *data, size_t dn);
size_t feed_reply(enum df1_check c, uint8_t dst, uint8_t src, uint8_t cmdb, uint8_t sts,
                  uint16_t tns);
size_t reply_wire(enum df1_check c, uint16_t tns, uint8_t *wire);
int transact_a2(struct df1 *h, uint8_t *out, size_t cap);
void assert_reply_ok(int r, const uint8_t *out, uint16_t tns);
/* a responder: its handler, setups (half-duplex slave, full-duplex peer), the
 * serve loop over what is queued, a master's messages and polls fed to it */
int test_handler(struct df1 *h, void *ctx, const uint8_t *cmd, size_t n, uint8_t *reply,
                 size_t cap);
int setup_slave(void **state);
int serve_script(struct df1 *h);
size_t slave_reply_wire(enum df1_check c, uint8_t stn, uint16_t tns, uint8_t *wire);
void feed_master_msg(uint8_t stn, uint16_t tns);
void feed_poll(uint8_t stn);
int setup_peer(void **state);

#endif
