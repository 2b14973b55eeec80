/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1_catalog.h - libdf1's message catalog as one X-macro table.
 *
 * Installed next to df1.h, which includes it: include <df1.h>, not this file.
 * Kept apart because it is data (61 rows from doc/REQUIREMENTS.md 004), not interface.
 */
#ifndef LIBDF1_DF1_CATALOG_H
#define LIBDF1_DF1_CATALOG_H

/*
 * ONE table for the catalog: mnemonic (exactly as the seed spells it, typos
 * included: the names are an interface), ID, severity, printf format as the
 * seed gives it (NULL for counters, which have no message) and a one-line
 * description. It generates the DF1_ID_* constants below and the rows that
 * df1_catalog_by_id() returns.
 */
#define DF1_CATALOG_TABLE(X) \
	X(ERR_BAD_STATION, 2501, ERROR, \
	  "Item: %d, Invalid station number (%d) must be less than %d", \
	  "a mapping row's station is outside 0-254") \
	X(ERR_BAD_PLC_TYPE, 2502, ERROR, \
	  "Item: %d, Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s", \
	  "a mapping row's PLC type is invalid or unsupported") \
	X(ERR_ADDRESS_SYNTAX, 2503, ERROR, "Item: %d, Invalid Address Syntax (%s)", \
	  "a mapping row's address does not follow the address format") \
	X(ERR_ADDRESS_RANGE, 2504, ERROR, "Item: %d, Address is out of range (%s, len=%d)", \
	  "a mapping row's address is outside the valid address range") \
	X(ERR_BAD_FUNCTION_CODE, 2505, ERROR, \
	  "Response with wrong command code (slv=%d, actual=%d, expected=%d)", \
	  "a reply came back with the wrong command/function code") \
	X(ERR_BAD_CRC, 2506, ERROR, \
	  "Response with wrong CRC (actual=0x%02x%02x, expected=0x%02x%02x)", \
	  "a received frame had a bad CRC: line problems") \
	X(ERR_BAD_BCC, 2507, ERROR, \
	  "Response with wrong BCC (actual=0x%02x%02x, expected=0x%02x%02x)", \
	  "a received frame had a bad BCC: line problems") \
	X(ERR_COMMAND_TIMEOUT, 2508, ERROR, "Command Timed Out", \
	  "no valid reply to a command arrived in time") \
	X(ERR_INACTIVE_STATION, 2509, ERROR, "Slave Station (%d) Inactive", \
	  "too many errors: the slave was removed from the active station list") \
	X(ERR_WRONG_MESSAGE, 2510, ERROR, \
	  "Wrong Message Received Src:0x%02x, Dst:0x%02x, Tns:0x%04x", \
	  "an unexpected or wrong message was received") \
	X(ERR_RCVD_NAK_SYMBOL, 2511, ERROR, "Received NAK Symbol", "a DLE NAK was received") \
	X(NTC_RCVD_MSG_TOO_LONG, 2512, NOTICE, "Received Message Too Long (> %d bytes)", \
	  "a received message was longer than the maximum DF1 message") \
	X(NTC_RCVD_MSG_TOO_SHORT, 2513, NOTICE, "Received Message Too Short (< %d bytes)", \
	  "a received message was too short to be a DF1 message") \
	X(NTC_INVALID_SYMBOL, 2514, NOTICE, "Invalid Symbol received after DLE - (0x%02x)", \
	  "the byte after a DLE was not a valid symbol there") \
	X(NTC_ACK_EXPECTED, 2515, NOTICE, "ACK Expected (last symbol received was 0x%02x)", \
	  "an ACK was expected but something else arrived") \
	X(NTC_EOT_STX_EXPECTED, 2516, NOTICE, \
	  "EOT or STX Expected (last symbol received was 0x%02x)", \
	  "a poll's answer (EOT or a message) was expected but something else arrived") \
	X(NTC_RCVD_NAK_SYMBOL, 2517, NOTICE, "Received NAK Symbol", "a DLE NAK was received") \
	X(NTC_NO_ETX_RCVD, 2518, NOTICE, "Incomplete Message, No ETX received", \
	  "a message began with SOH/STX but never reached DLE ETX") \
	X(NTC_NAK_LIMIT_EXCEEDED, 2519, NOTICE, "NAK Retry Limit (%d) exceeded", \
	  "a message failed more often than the NAK retry limit") \
	X(NTC_ENQ_LIMIT_EXCEEDED, 2520, NOTICE, "ENQ Retry Limit (%d) exceeded", \
	  "polling for a reply failed more often than the ENQ retry limit") \
	X(NTC_NAK_RETRY, 2521, NOTICE, "NAK Retry #%d, due to error %d", \
	  "sending a message failed; it will be retried") \
	X(NTC_ENQ_RETRY, 2522, NOTICE, "ENQ Retry #%d, due to error %d", \
	  "sending a poll failed; it will be retried") \
	X(NTC_REPLY_MSG_RCVD, 2523, NOTICE, "Reply Message received from Slave %d", \
	  "a good reply arrived from a slave") \
	X(NTC_DUPLICATE_MSG_RCVD, 2524, NOTICE, "Duplicate Message received from Slave %d", \
	  "a slave sent a message again (its ACK was probably lost)") \
	X(CNT_MSG_PACKETS_SENT, 2525, COUNTER, NULL, "message packets transmitted") \
	X(CNT_MSG_PACKETS_RCVD, 2526, COUNTER, NULL, "message packets received") \
	X(CNT_CMD_MSGS_SENT, 2527, COUNTER, NULL, "command messages transmitted") \
	X(CNT_CMD_MSGS_RCVD, 2528, COUNTER, NULL, "command messages received") \
	X(CNT_REPLY_MSGS_SENT, 2529, COUNTER, NULL, "reply messages transmitted") \
	X(CNT_REPLY_MSGS_RCVD, 2530, COUNTER, NULL, "reply messages received") \
	X(CNT_POLL_MSGS_SENT, 2531, COUNTER, NULL, "master poll messages transmitted") \
	X(CNT_POLL_MSGS_RCVD, 2532, COUNTER, NULL, "master poll messages received") \
	X(CNT_NAKS_SENT, 2533, COUNTER, NULL, "NAK symbols transmitted") \
	X(CNT_NAKS_RCVD, 2534, COUNTER, NULL, "NAK symbols received") \
	X(CNT_ACKS_SENT, 2535, COUNTER, NULL, "ACK symbols transmitted") \
	X(CNT_ACKS_RCVD, 2536, COUNTER, NULL, "ACK symbols received") \
	X(CNT_EOTS_SENT, 2537, COUNTER, NULL, "EOT symbols transmitted") \
	X(CNT_EOTS_RCVD, 2538, COUNTER, NULL, "EOT symbols received") \
	X(CNT_ERROR_MSGS_SENT, 2539, COUNTER, NULL, "error messages transmitted") \
	X(CNT_ERROR_MSGS_RCVD, 2540, COUNTER, NULL, "error messages received") \
	X(CNT_NAK_RETRIES, 2541, COUNTER, NULL, \
	  "message retries (no ACK, a NAK, or another communication error)") \
	X(CNT_NAK_LIMIT_EXCEEDED, 2542, COUNTER, NULL, "messages aborted at the NAK retry limit") \
	X(CNT_ENQ_RETRIES, 2543, COUNTER, NULL, \
	  "poll retries (no answer, a NAK, or another error)") \
	X(CNT_ENQ_LIMIT_EXCEEDED, 2544, COUNTER, NULL, "messages aborted at the ENQ retry limit") \
	X(CNT_COMMAND_TIMEOUTS, 2545, COUNTER, NULL, \
	  "transactions over the command timeout (a NAK is sent to end them)") \
	X(CNT_BCC_ERRORS, 2546, COUNTER, NULL, "BCC errors detected in received data") \
	X(CNT_CRC_ERRORS, 2547, COUNTER, NULL, "CRC errors detected in received data") \
	X(CNT_STALE_MSGS_RCVD, 2548, COUNTER, NULL, "stale (leftover) messages received") \
	X(CNT_DUPLICATE_MSGS_RCVD, 2549, COUNTER, NULL, "duplicate messages received (lost ACKs)") \
	X(CNT_INVALID_MSGS_RCVD, 2550, COUNTER, NULL, \
	  "invalid messages received (bad data, addressing)") \
	X(CNT_COM_READ_ERRORS, 2551, COUNTER, NULL, "communication port read errors") \
	X(CRT_BAD_STATION_ID, 2552, CRITICAL, "Invalid station number (%d) must be less than %d", \
	  "the network file's station is outside 0-254") \
	X(CRT_BAD_DRIVER_MODE, 2553, CRITICAL, \
	  "Invalid Driver Mode (%s), should be one of %s, %s, or %s", \
	  "the network file's mode is not Master, Slave or Peer") \
	X(CRT_UNSUPPORTED_MODE, 2554, CRITICAL, \
	  "Unsupported Driver Mode (%d), Supported Mode(s): %s", \
	  "the network file's mode is not supported by this version") \
	X(CRT_BAD_PLC_TYPE, 2555, CRITICAL, \
	  "Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s", \
	  "the network file's PLC type is invalid or unsupported") \
	X(CRT_BAD_ERROR_CODE, 2556, CRITICAL, \
	  "Invalid Error Code (%s), should be either %s, or %s", \
	  "the network file's error check is not BCC or CRC") \
	X(CRT_BAD_NAK_RETRIES, 2557, CRITICAL, \
	  "Invalid NAK Retries (%d) should be in range [0, %d]", \
	  "the network file's NAK retries are out of range") \
	X(CRT_BAD_ENQ_RETRIES, 2558, CRITICAL, \
	  "Invalid ENQ Retries (%d) should be in range [0, %d]", \
	  "the network file's ENQ retries are out of range") \
	X(CRT_BAD_CMD_TIMEOUT, 2559, CRITICAL, \
	  "Invalid Cmd Timeout (%d) should be in range [%d, %d]", \
	  "the network file's command timeout is out of range") \
	X(CRD_CHAR_SENT, 2560, COUNTER, NULL, "characters transmitted on the port") \
	X(CRD_CHAR_RECV, 2561, COUNTER, NULL, "characters received from the port")

#endif /* LIBDF1_DF1_CATALOG_H */
