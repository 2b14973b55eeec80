/*
 * errors - the one home of every table of texts: library error codes (the
 * DF1_ERROR_TABLE X-macro of df1.h), the message catalog of seeds/004
 * (IDs 2501-2561), and the PLC's STS / EXT STS codes (spec/protocol.md 3.2-3.4).
 * Pure: const tables and lookups only.
 */
#include "df1.h"

#include <stddef.h>

#define COUNT_OF(a) (sizeof(a) / sizeof((a)[0]))

/* ------------------------------------------------------------------------
 * Library error codes
 * ------------------------------------------------------------------------ */

struct err_row {
	int code;
	int catalog_id;
	const char *name;
	const char *text;
};

#define ERR_ROW(name, value, id, text) { value, id, #name, text },
static const struct err_row err_rows[] = { DF1_ERROR_TABLE(ERR_ROW) };
#undef ERR_ROW

static const struct err_row *err_find(int err)
{
	for (size_t i = 0; i < COUNT_OF(err_rows); i++)
		if (err_rows[i].code == err)
			return &err_rows[i];
	return NULL;
}

const char *df1_strerror(int err)
{
	const struct err_row *r = err_find(err);

	return r ? r->text : "unknown error";
}

const char *df1_errname(int err)
{
	const struct err_row *r = err_find(err);

	return r ? r->name : "DF1_E_UNKNOWN";
}

int df1_error_catalog_id(int err)
{
	const struct err_row *r = err_find(err);

	return r ? r->catalog_id : 0;
}

/* ------------------------------------------------------------------------
 * Message catalog (seeds/004). Mnemonics and formats exactly as the seed
 * spells them (typos included: the IDs and names are an interface); the
 * format is the seed's message text before its " - explanation". Counters
 * have no message, so no format. Every ID 2501-2561 is defined by the seed.
 * Severity by range: 2501-2511 error, 2512-2524 notice, 2525-2551 and
 * 2560-2561 counters, 2552-2559 critical (configuration).
 * ------------------------------------------------------------------------ */

#define S_ERR DF1_SEV_ERROR
#define S_NTC DF1_SEV_NOTICE
#define S_CNT DF1_SEV_COUNTER
#define S_CRT DF1_SEV_CRITICAL

static const struct df1_catalog_entry catalog[] = {
	{ 2501, "ERR_BAD_STATION", S_ERR,
	  "Item: %d, Invalid station number (%d) must be less than %d",
	  "a mapping row's station is outside 0-254" },
	{ 2502, "ERR_BAD_PLC_TYPE", S_ERR,
	  "Item: %d, Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s",
	  "a mapping row's PLC type is invalid or unsupported" },
	{ 2503, "ERR_ADDRESS_SYNTAX", S_ERR,
	  "Item: %d, Invalid Address Syntax (%s)",
	  "a mapping row's address does not follow the address format" },
	{ 2504, "ERR_ADDRESS_RANGE", S_ERR,
	  "Item: %d, Address is out of range (%s, len=%d)",
	  "a mapping row's address is outside the valid address range" },
	{ 2505, "ERR_BAD_FUNCTION_CODE", S_ERR,
	  "Response with wrong command code (slv=%d, actual=%d, expected=%d)",
	  "a reply came back with the wrong command/function code" },
	{ 2506, "ERR_BAD_CRC", S_ERR,
	  "Response with wrong CRC (actual=0x%02x%02x, expected=0x%02x%02x)",
	  "a received frame had a bad CRC: line problems" },
	{ 2507, "ERR_BAD_BCC", S_ERR,
	  "Response with wrong BCC (actual=0x%02x%02x, expected=0x%02x%02x)",
	  "a received frame had a bad BCC: line problems" },
	{ 2508, "ERR_COMMAND_TIMEOUT", S_ERR,
	  "Command Timed Out",
	  "no valid reply to a command arrived in time" },
	{ 2509, "ERR_INACTIVE_STATION", S_ERR,
	  "Slave Station (%d) Inactive",
	  "too many errors: the slave was removed from the active station list" },
	{ 2510, "ERR_WRONG_MESSAGE", S_ERR,
	  "Wrong Message Received Src:0x%02x, Dst:0x%02x, Tns:0x%04x",
	  "an unexpected or wrong message was received" },
	{ 2511, "ERR_RCVD_NAK_SYMBOL", S_ERR,
	  "Received NAK Symbol",
	  "a DLE NAK was received" },
	{ 2512, "NTC_RCVD_MSG_TOO_LONG", S_NTC,
	  "Received Message Too Long (> %d bytes)",
	  "a received message was longer than the maximum DF1 message" },
	{ 2513, "NTC_RCVD_MSG_TOO_SHORT", S_NTC,
	  "Received Message Too Short (< %d bytes)",
	  "a received message was too short to be a DF1 message" },
	{ 2514, "NTC_INVALID_SYMBOL", S_NTC,
	  "Invalid Symbol received after DLE - (0x%02x)",
	  "the byte after a DLE was not a valid symbol there" },
	{ 2515, "NTC_ACK_EXPECTED", S_NTC,
	  "ACK Expected (last symbol received was 0x%02x)",
	  "an ACK was expected but something else arrived" },
	{ 2516, "NTC_EOT_STX_EXPECTED", S_NTC,
	  "EOT or STX Expected (last symbol received was 0x%02x)",
	  "a poll's answer (EOT or a message) was expected but something else arrived" },
	{ 2517, "NTC_RCVD_NAK_SYMBOL", S_NTC,
	  "Received NAK Symbol",
	  "a DLE NAK was received" },
	{ 2518, "NTC_NO_ETX_RCVD", S_NTC,
	  "Incomplete Message, No ETX received",
	  "a message began with SOH/STX but never reached DLE ETX" },
	{ 2519, "NTC_NAK_LIMIT_EXCEEDED", S_NTC,
	  "NAK Retry Limit (%d) exceeded",
	  "a message failed more often than the NAK retry limit" },
	{ 2520, "NTC_ENQ_LIMIT_EXCEEDED", S_NTC,
	  "ENQ Retry Limit (%d) exceeded",
	  "polling for a reply failed more often than the ENQ retry limit" },
	{ 2521, "NTC_NAK_RETRY", S_NTC,
	  "NAK Retry #%d, due to error %d",
	  "sending a message failed; it will be retried" },
	{ 2522, "NTC_ENQ_RETRY", S_NTC,
	  "ENQ Retry #%d, due to error %d",
	  "sending a poll failed; it will be retried" },
	{ 2523, "NTC_REPLY_MSG_RCVD", S_NTC,
	  "Reply Message received from Slave %d",
	  "a good reply arrived from a slave" },
	{ 2524, "NTC_DUPLICATE_MSG_RCVD", S_NTC,
	  "Duplicate Message received from Slave %d",
	  "a slave sent a message again (its ACK was probably lost)" },
	{ 2525, "CNT_MSG_PACKETS_SENT", S_CNT, NULL, "message packets transmitted" },
	{ 2526, "CNT_MSG_PACKETS_RCVD", S_CNT, NULL, "message packets received" },
	{ 2527, "CNT_CMD_MSGS_SENT", S_CNT, NULL, "command messages transmitted" },
	{ 2528, "CNT_CMD_MSGS_RCVD", S_CNT, NULL, "command messages received" },
	{ 2529, "CNT_REPLY_MSGS_SENT", S_CNT, NULL, "reply messages transmitted" },
	{ 2530, "CNT_REPLY_MSGS_RCVD", S_CNT, NULL, "reply messages received" },
	{ 2531, "CNT_POLL_MSGS_SENT", S_CNT, NULL, "master poll messages transmitted" },
	{ 2532, "CNT_POLL_MSGS_RCVD", S_CNT, NULL, "master poll messages received" },
	{ 2533, "CNT_NAKS_SENT", S_CNT, NULL, "NAK symbols transmitted" },
	{ 2534, "CNT_NAKS_RCVD", S_CNT, NULL, "NAK symbols received" },
	{ 2535, "CNT_ACKS_SENT", S_CNT, NULL, "ACK symbols transmitted" },
	{ 2536, "CNT_ACKS_RCVD", S_CNT, NULL, "ACK symbols received" },
	{ 2537, "CNT_EOTS_SENT", S_CNT, NULL, "EOT symbols transmitted" },
	{ 2538, "CNT_EOTS_RCVD", S_CNT, NULL, "EOT symbols received" },
	{ 2539, "CNT_ERROR_MSGS_SENT", S_CNT, NULL, "error messages transmitted" },
	{ 2540, "CNT_ERROR_MSGS_RCVD", S_CNT, NULL, "error messages received" },
	{ 2541, "CNT_NAK_RETRIES", S_CNT, NULL,
	  "message retries (no ACK, a NAK, or another communication error)" },
	{ 2542, "CNT_NAK_LIMIT_EXCEEDED", S_CNT, NULL, "messages aborted at the NAK retry limit" },
	{ 2543, "CNT_ENQ_RETRIES", S_CNT, NULL, "poll retries (no answer, a NAK, or another error)" },
	{ 2544, "CNT_ENQ_LIMIT_EXCEEDED", S_CNT, NULL, "messages aborted at the ENQ retry limit" },
	{ 2545, "CNT_COMMAND_TIMEOUTS", S_CNT, NULL,
	  "transactions over the command timeout (a NAK is sent to end them)" },
	{ 2546, "CNT_BCC_ERRORS", S_CNT, NULL, "BCC errors detected in received data" },
	{ 2547, "CNT_CRC_ERRORS", S_CNT, NULL, "CRC errors detected in received data" },
	{ 2548, "CNT_STALE_MSGS_RCVD", S_CNT, NULL, "stale (leftover) messages received" },
	{ 2549, "CNT_DUPLICATE_MSGS_RCVD", S_CNT, NULL, "duplicate messages received (lost ACKs)" },
	{ 2550, "CNT_INVALID_MSGS_RCVD", S_CNT, NULL, "invalid messages received (bad data, addressing)" },
	{ 2551, "CNT_COM_READ_ERRORS", S_CNT, NULL, "communication port read errors" },
	{ 2552, "CRT_BAD_STATION_ID", S_CRT,
	  "Invalid station number (%d) must be less than %d",
	  "the network file's station is outside 0-254" },
	{ 2553, "CRT_BAD_DRIVER_MODE", S_CRT,
	  "Invalid Driver Mode (%s), should be one of %s, %s, or %s",
	  "the network file's mode is not Master, Slave or Peer" },
	{ 2554, "CRT_UNSUPPORTED_MODE", S_CRT,
	  "Unsupported Driver Mode (%d), Supported Mode(s): %s",
	  "the network file's mode is not supported by this version" },
	{ 2555, "CRT_BAD_PLC_TYPE", S_CRT,
	  "Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s",
	  "the network file's PLC type is invalid or unsupported" },
	{ 2556, "CRT_BAD_ERROR_CODE", S_CRT,
	  "Invalid Error Code (%s), should be either %s, or %s",
	  "the network file's error check is not BCC or CRC" },
	{ 2557, "CRT_BAD_NAK_RETRIES", S_CRT,
	  "Invalid NAK Retries (%d) should be in range [0, %d]",
	  "the network file's NAK retries are out of range" },
	{ 2558, "CRT_BAD_ENQ_RETRIES", S_CRT,
	  "Invalid ENQ Retries (%d) should be in range [0, %d]",
	  "the network file's ENQ retries are out of range" },
	{ 2559, "CRT_BAD_CMD_TIMEOUT", S_CRT,
	  "Invalid Cmd Timeout (%d) should be in range [%d, %d]",
	  "the network file's command timeout is out of range" },
	{ 2560, "CRD_CHAR_SENT", S_CNT, NULL, "characters transmitted on the port" },
	{ 2561, "CRD_CHAR_RECV", S_CNT, NULL, "characters received from the port" },
};

#undef S_ERR
#undef S_NTC
#undef S_CNT
#undef S_CRT

const struct df1_catalog_entry *df1_catalog_by_id(int id)
{
	for (size_t i = 0; i < COUNT_OF(catalog); i++)
		if (catalog[i].id == id)
			return &catalog[i];
	return NULL;
}

/* ASCII only: a locale (e.g. Turkish i) must not change what matches. */
static int ascii_lower(int c)
{
	return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c;
}

static bool ascii_caseeq(const char *a, const char *b)
{
	for (; *a && *b; a++, b++)
		if (ascii_lower((unsigned char)*a) != ascii_lower((unsigned char)*b))
			return false;
	return *a == *b;
}

const struct df1_catalog_entry *df1_catalog_by_mnemonic(const char *mn)
{
	if (!mn)
		return NULL;
	for (size_t i = 0; i < COUNT_OF(catalog); i++)
		if (ascii_caseeq(catalog[i].mnemonic, mn))
			return &catalog[i];
	return NULL;
}

const struct df1_catalog_entry *df1_catalog_at(size_t index)
{
	return index < COUNT_OF(catalog) ? &catalog[index] : NULL;
}

/* ------------------------------------------------------------------------
 * PLC status codes (M p.8-2..8-5, spec/protocol.md 3.2-3.4)
 * ------------------------------------------------------------------------ */

struct code_text {
	uint8_t code;
	const char *text;
};

static const char unknown_status[] = "unknown status";

/* STS low nibble: errors found by the local interface (M p.8-2). */
static const struct code_text sts_local[] = {
	{ 0x00, "success, no error" },
	{ 0x01, "DST node is out of buffer space" },
	{ 0x02, "cannot guarantee delivery: link layer (the remote node did not ACK the command)" },
	{ 0x03, "duplicate token holder detected" },
	{ 0x04, "local port is disconnected" },
	{ 0x05, "application layer timed out waiting for a response" },
	{ 0x06, "duplicate node detected" },
	{ 0x07, "station is offline" },
	{ 0x08, "hardware fault" },
};

/* STS high nibble: errors found by the node that executes the command (M p.8-3). */
static const struct code_text sts_remote[] = {
	{ 0x10, "illegal command or format" },
	{ 0x20, "host has a problem and will not communicate" },
	{ 0x30, "remote node host is missing, disconnected, or shut down" },
	{ 0x40, "host could not complete function due to hardware fault" },
	{ 0x50, "addressing problem or memory protect rungs" },
	{ 0x60, "function not allowed due to command protection selection" },
	{ 0x70, "processor is in Program mode" },
	{ 0x80, "compatibility mode file missing or communication zone problem" },
	{ 0x90, "remote node cannot buffer command" },
	{ 0xA0, "wait ACK (1775-KA buffer full)" },
	{ 0xB0, "remote node problem due to download" },
	{ 0xC0, "wait ACK (1775-KA buffer full)" },
	{ 0xF0, "error code is in the EXT STS byte" },
};

/* EXT STS after STS F0, CMD 0F (M p.8-4). 22-24: see spec 3.3 [UNCERTAIN]. */
static const struct code_text ext_sts_0f[] = {
	{ 0x00, "not used" },
	{ 0x01, "a field has an illegal value" },
	{ 0x02, "less levels specified in address than minimum for any address" },
	{ 0x03, "more levels specified in address than system supports" },
	{ 0x04, "symbol not found" },
	{ 0x05, "symbol is of improper format" },
	{ 0x06, "address doesn't point to something usable" },
	{ 0x07, "file is wrong size" },
	{ 0x08, "cannot complete request, situation has changed since the start of the command" },
	{ 0x09, "data or file is too large" },
	{ 0x0A, "transaction size plus word address is too large" },
	{ 0x0B, "access denied, improper privilege" },
	{ 0x0C, "condition cannot be generated - resource is not available" },
	{ 0x0D, "condition already exists - resource is already available" },
	{ 0x0E, "command cannot be executed" },
	{ 0x0F, "histogram overflow" },
	{ 0x10, "no access" },
	{ 0x11, "illegal data type" },
	{ 0x12, "invalid parameter or invalid data" },
	{ 0x13, "address reference exists to deleted area" },
	{ 0x14, "command execution failure for unknown reason; possible PLC-3 histogram overflow" },
	{ 0x15, "data conversion error" },
	{ 0x16, "scanner not able to communicate with 1771 rack adapter" },
	{ 0x17, "type mismatch" },
	{ 0x18, "1771 module response was not valid" },
	{ 0x19, "duplicated label" },
	{ 0x1A, "file is open; another node owns it" },
	{ 0x1B, "another node is the program owner" },
	{ 0x1C, "reserved" },
	{ 0x1D, "reserved" },
	{ 0x1E, "data table element protection violation" },
	{ 0x1F, "temporary internal problem" },
	{ 0x22, "remote rack fault (pass-through DH+ to remote I/O)" },
	{ 0x23, "timeout (pass-through)" },
	{ 0x24, "unknown error (pass-through)" },
};

/* EXT STS for CMD 0B/1A/1B on DH-485 (M p.8-5). 1A/1B are followed by one
 * more byte: the owner's node address. */
static const struct code_text ext_sts_dh485[] = {
	{ 0x07, "insufficient memory module size (0000h returned)" },
	{ 0x0B, "access denied, privilege violation" },
	{ 0x0C, "resource not available or cannot do" },
	{ 0x0E, "CMD cannot be executed" },
	{ 0x12, "invalid parameter" },
	{ 0x14, "failure during processing" },
	{ 0x19, "duplicate label" },
	{ 0x1A, "file open by another node" },
	{ 0x1B, "program owned by another node" },
};

static const char *code_find(const struct code_text *t, size_t n, uint8_t code)
{
	for (size_t i = 0; i < n; i++)
		if (t[i].code == code)
			return t[i].text;
	return NULL;
}

/* Both nibbles set should not happen: a local error means the local node
 * turned the command round, so no remote node judged it. The local (low)
 * nibble therefore wins when it is a defined code (01-08); an undefined low
 * nibble (09-0F, "not used") is ignored in favour of the high one. */
const char *df1_sts_text(uint8_t sts)
{
	const char *t = code_find(sts_local, COUNT_OF(sts_local), sts & 0x0F);

	if (sts == 0)
		return sts_local[0].text;
	if (t && (sts & 0x0F))
		return t;
	t = code_find(sts_remote, COUNT_OF(sts_remote), sts & 0xF0);
	return t ? t : unknown_status;
}

const char *df1_ext_sts_text(uint8_t ext)
{
	const char *t = code_find(ext_sts_0f, COUNT_OF(ext_sts_0f), ext);

	return t ? t : unknown_status;
}

const char *df1_ext_sts_text_dh485(uint8_t ext)
{
	const char *t = code_find(ext_sts_dh485, COUNT_OF(ext_sts_dh485), ext);

	return t ? t : unknown_status;
}
