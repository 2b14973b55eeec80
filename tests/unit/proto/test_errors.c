/* SPDX-License-Identifier: MPL-2.0 */
/*
 * test_errors - error codes, the doc/REQUIREMENTS.md 004 message catalog, STS / EXT STS texts.
 * The expected catalog below was written from doc/REQUIREMENTS.md 004's tables (IDs,
 * mnemonics as spelled there, message texts) and the STS texts from
 * doc/PROTOCOL.md 3.2-3.4, independently of lib/errors.c.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <ctype.h>
#include <string.h>

#include "df1.h"

/* ------------------------------------------------------------------------
 * Library error codes
 * ------------------------------------------------------------------------ */

struct err_expect {
	int code;
	const char *name;
	int id;
	const char *text;
};

#define ERR_EXPECT(name, value, id, text) { value, #name, id, text },
static const struct err_expect errs[] = { DF1_ERROR_TABLE(ERR_EXPECT) };
#undef ERR_EXPECT

static void test_errors_every_code_has_name_text_and_catalog(void **state)
{
	(void)state;
	assert_true(sizeof errs / sizeof errs[0] >= 32);
	for (size_t i = 0; i < sizeof errs / sizeof errs[0]; i++) {
		const struct err_expect *e = &errs[i];

		assert_string_equal(df1_errname(e->code), e->name);
		assert_string_equal(df1_strerror(e->code), e->text);
		assert_true(strlen(e->text) > 0);
		assert_int_equal(df1_error_catalog_id(e->code), e->id);
		if (e->id)
			assert_non_null(df1_catalog_by_id(e->id));
		assert_true(e->code <= 0 && e->code > DF1_E_LAST_);
		for (size_t j = 0; j < i; j++)
			assert_int_not_equal(errs[j].code, e->code);
	}
	assert_string_equal(df1_strerror(DF1_OK), "success");
	assert_string_equal(df1_errname(DF1_E_TIMEOUT), "DF1_E_TIMEOUT");
	assert_int_equal(df1_error_catalog_id(DF1_E_TIMEOUT), 2508);
	assert_int_equal(df1_error_catalog_id(DF1_E_CRC), 2506);
	assert_int_equal(df1_error_catalog_id(DF1_E_BCC), 2507);
}

/* Which failures leave a command surely unexecuted (DF1 manual: a NAK means the
 * receiver did not take the frame; an error reply means it was judged and
 * refused; no ACK or no reply means it may have been carried out). */
static void test_errors_unexecuted_follows_the_link_rules(void **state)
{
	static const int never[] = { DF1_E_REMOTE, DF1_E_NAK, DF1_E_INACTIVE, DF1_E_NOT_OPEN,
	                             DF1_E_INVAL, DF1_E_TYPE, DF1_E_RANGE, DF1_E_ADDR_SYNTAX,
	                             DF1_E_ADDR_RANGE, DF1_E_NOTSUP, DF1_E_NOMEM };
	static const int maybe[] = { DF1_OK, DF1_E_TIMEOUT, DF1_E_ENQ_LIMIT, DF1_E_NAK_LIMIT,
	                             DF1_E_BCC, DF1_E_CRC, DF1_E_CLOSED, DF1_E_INTR, DF1_E_SYS,
	                             DF1_E_WRONG_MSG, DF1_E_BAD_REPLY, DF1_E_NO_ETX, 42 };

	(void)state;
	for (size_t i = 0; i < sizeof never / sizeof never[0]; i++)
		assert_true(df1_error_unexecuted(never[i]));
	for (size_t i = 0; i < sizeof maybe / sizeof maybe[0]; i++)
		assert_false(df1_error_unexecuted(maybe[i]));
}

static void test_errors_unknown_code_gives_static_text(void **state)
{
	static const int bad[] = { 1, 42, DF1_E_LAST_, -1000, 2508 };

	(void)state;
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		assert_string_equal(df1_strerror(bad[i]), "unknown error");
		assert_non_null(df1_errname(bad[i]));
		assert_int_equal(df1_error_catalog_id(bad[i]), 0);
	}
}

/* ------------------------------------------------------------------------
 * Message catalog
 * ------------------------------------------------------------------------ */

struct cat_expect {
	int id;
	const char *mnemonic;
	const char *format;   /* NULL for counters */
};

/* doc/REQUIREMENTS.md 004: errors 2501-2511, notices 2512-2524, counters 2525-2551,
 * critical 2552-2559, character counters 2560-2561. */
static const struct cat_expect cat[] = {
	{ 2501, "ERR_BAD_STATION", "Item: %d, Invalid station number (%d) must be less than %d" },
	{ 2502, "ERR_BAD_PLC_TYPE", "Item: %d, Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s" },
	{ 2503, "ERR_ADDRESS_SYNTAX", "Item: %d, Invalid Address Syntax (%s)" },
	{ 2504, "ERR_ADDRESS_RANGE", "Item: %d, Address is out of range (%s, len=%d)" },
	{ 2505, "ERR_BAD_FUNCTION_CODE", "Response with wrong command code (slv=%d, actual=%d, expected=%d)" },
	{ 2506, "ERR_BAD_CRC", "Response with wrong CRC (actual=0x%02x%02x, expected=0x%02x%02x)" },
	{ 2507, "ERR_BAD_BCC", "Response with wrong BCC (actual=0x%02x%02x, expected=0x%02x%02x)" },
	{ 2508, "ERR_COMMAND_TIMEOUT", "Command Timed Out" },
	{ 2509, "ERR_INACTIVE_STATION", "Slave Station (%d) Inactive" },
	{ 2510, "ERR_WRONG_MESSAGE", "Wrong Message Received Src:0x%02x, Dst:0x%02x, Tns:0x%04x" },
	{ 2511, "ERR_RCVD_NAK_SYMBOL", "Received NAK Symbol" },
	{ 2512, "NTC_RCVD_MSG_TOO_LONG", "Received Message Too Long (> %d bytes)" },
	{ 2513, "NTC_RCVD_MSG_TOO_SHORT", "Received Message Too Short (< %d bytes)" },
	{ 2514, "NTC_INVALID_SYMBOL", "Invalid Symbol received after DLE - (0x%02x)" },
	{ 2515, "NTC_ACK_EXPECTED", "ACK Expected (last symbol received was 0x%02x)" },
	{ 2516, "NTC_EOT_STX_EXPECTED", "EOT or STX Expected (last symbol received was 0x%02x)" },
	{ 2517, "NTC_RCVD_NAK_SYMBOL", "Received NAK Symbol" },
	{ 2518, "NTC_NO_ETX_RCVD", "Incomplete Message, No ETX received" },
	{ 2519, "NTC_NAK_LIMIT_EXCEEDED", "NAK Retry Limit (%d) exceeded" },
	{ 2520, "NTC_ENQ_LIMIT_EXCEEDED", "ENQ Retry Limit (%d) exceeded" },
	{ 2521, "NTC_NAK_RETRY", "NAK Retry #%d, due to error %d" },
	{ 2522, "NTC_ENQ_RETRY", "ENQ Retry #%d, due to error %d" },
	{ 2523, "NTC_REPLY_MSG_RCVD", "Reply Message received from Slave %d" },
	{ 2524, "NTC_DUPLICATE_MSG_RCVD", "Duplicate Message received from Slave %d" },
	{ 2525, "CNT_MSG_PACKETS_SENT", NULL },
	{ 2526, "CNT_MSG_PACKETS_RCVD", NULL },
	{ 2527, "CNT_CMD_MSGS_SENT", NULL },
	{ 2528, "CNT_CMD_MSGS_RCVD", NULL },
	{ 2529, "CNT_REPLY_MSGS_SENT", NULL },
	{ 2530, "CNT_REPLY_MSGS_RCVD", NULL },
	{ 2531, "CNT_POLL_MSGS_SENT", NULL },
	{ 2532, "CNT_POLL_MSGS_RCVD", NULL },
	{ 2533, "CNT_NAKS_SENT", NULL },
	{ 2534, "CNT_NAKS_RCVD", NULL },
	{ 2535, "CNT_ACKS_SENT", NULL },
	{ 2536, "CNT_ACKS_RCVD", NULL },
	{ 2537, "CNT_EOTS_SENT", NULL },
	{ 2538, "CNT_EOTS_RCVD", NULL },
	{ 2539, "CNT_ERROR_MSGS_SENT", NULL },
	{ 2540, "CNT_ERROR_MSGS_RCVD", NULL },
	{ 2541, "CNT_NAK_RETRIES", NULL },
	{ 2542, "CNT_NAK_LIMIT_EXCEEDED", NULL },
	{ 2543, "CNT_ENQ_RETRIES", NULL },
	{ 2544, "CNT_ENQ_LIMIT_EXCEEDED", NULL },
	{ 2545, "CNT_COMMAND_TIMEOUTS", NULL },
	{ 2546, "CNT_BCC_ERRORS", NULL },
	{ 2547, "CNT_CRC_ERRORS", NULL },
	{ 2548, "CNT_STALE_MSGS_RCVD", NULL },
	{ 2549, "CNT_DUPLICATE_MSGS_RCVD", NULL },
	{ 2550, "CNT_INVALID_MSGS_RCVD", NULL },
	{ 2551, "CNT_COM_READ_ERRORS", NULL },
	{ 2552, "CRT_BAD_STATION_ID", "Invalid station number (%d) must be less than %d" },
	{ 2553, "CRT_BAD_DRIVER_MODE", "Invalid Driver Mode (%s), should be one of %s, %s, or %s" },
	{ 2554, "CRT_UNSUPPORTED_MODE", "Unsupported Driver Mode (%d), Supported Mode(s): %s" },
	{ 2555, "CRT_BAD_PLC_TYPE", "Invalid or Unsupported PLC Type (%s) should be one of %s, %s, %s, %s" },
	{ 2556, "CRT_BAD_ERROR_CODE", "Invalid Error Code (%s), should be either %s, or %s" },
	{ 2557, "CRT_BAD_NAK_RETRIES", "Invalid NAK Retries (%d) should be in range [0, %d]" },
	{ 2558, "CRT_BAD_ENQ_RETRIES", "Invalid ENQ Retries (%d) should be in range [0, %d]" },
	{ 2559, "CRT_BAD_CMD_TIMEOUT", "Invalid Cmd Timeout (%d) should be in range [%d, %d]" },
	{ 2560, "CRD_CHAR_SENT", NULL },
	{ 2561, "CRD_CHAR_RECV", NULL },
};

#define NCAT (sizeof cat / sizeof cat[0])

static enum df1_severity severity_of(int id)
{
	if (id <= 2511)
		return DF1_SEV_ERROR;
	if (id <= 2524)
		return DF1_SEV_NOTICE;
	if (id >= 2552 && id <= 2559)
		return DF1_SEV_CRITICAL;
	return DF1_SEV_COUNTER;
}

static void test_errors_catalog_has_every_seed_id(void **state)
{
	(void)state;
	/* the seed defines every ID from 2501 to 2561: none missing */
	assert_int_equal(NCAT, 2561 - 2501 + 1);
	for (size_t i = 0; i < NCAT; i++) {
		const struct df1_catalog_entry *e = df1_catalog_by_id(cat[i].id);

		assert_int_equal(cat[i].id, 2501 + (int)i);
		assert_non_null(e);
		assert_int_equal(e->id, cat[i].id);
		assert_string_equal(e->mnemonic, cat[i].mnemonic);
		assert_int_equal(e->severity, severity_of(cat[i].id));
		if (cat[i].format)
			assert_string_equal(e->format, cat[i].format);
		else
			assert_null(e->format);
		assert_non_null(e->description);
		assert_true(strlen(e->description) > 0);
	}
	assert_null(df1_catalog_by_id(2500));
	assert_null(df1_catalog_by_id(2562));
	assert_null(df1_catalog_by_id(0));
}

static void test_errors_catalog_by_mnemonic_any_case(void **state)
{
	(void)state;
	for (size_t i = 0; i < NCAT; i++) {
		const struct df1_catalog_entry *e = df1_catalog_by_id(cat[i].id);
		char lower[64], mixed[64];
		size_t n = strlen(cat[i].mnemonic);

		assert_true(n < sizeof lower);
		for (size_t k = 0; k <= n; k++) {
			lower[k] = (char)tolower((unsigned char)cat[i].mnemonic[k]);
			mixed[k] = k % 2 ? lower[k] : cat[i].mnemonic[k];
		}
		assert_ptr_equal(df1_catalog_by_mnemonic(cat[i].mnemonic), e);
		assert_ptr_equal(df1_catalog_by_mnemonic(lower), e);
		assert_ptr_equal(df1_catalog_by_mnemonic(mixed), e);
	}
	assert_null(df1_catalog_by_mnemonic(NULL));
	assert_null(df1_catalog_by_mnemonic(""));
	assert_null(df1_catalog_by_mnemonic("ERR_COMMAND_TIMEOUTX"));
	assert_null(df1_catalog_by_mnemonic("ERR_COMMAND_TIMEOU"));
}

static void test_errors_catalog_iterates_in_id_order(void **state)
{
	size_t i = 0;
	const struct df1_catalog_entry *e;

	(void)state;
	for (; (e = df1_catalog_at(i)) != NULL; i++) {
		assert_true(i < NCAT);
		assert_int_equal(e->id, cat[i].id);
		assert_ptr_equal(df1_catalog_by_id(e->id), e);
	}
	assert_int_equal(i, NCAT);
	assert_null(df1_catalog_at((size_t)-1));
}

/* The generated names: each DF1_ID_<MNEMONIC> constant has the ID the seed
 * gives that mnemonic (the typed-in table above), and the counts and the
 * error sentinel follow from the tables. */
static void test_errors_catalog_names_are_the_seed_ids(void **state)
{
#define NAME_ROW(mnemonic, id, sev, format, description) { #mnemonic, DF1_ID_##mnemonic },
	static const struct { const char *mnemonic; int id; } named[] = {
		DF1_CATALOG_TABLE(NAME_ROW)
	};
#undef NAME_ROW
	(void)state;
	assert_int_equal(DF1_CATALOG_COUNT, NCAT);
	assert_int_equal(sizeof named / sizeof named[0], NCAT);
	for (size_t i = 0; i < NCAT; i++) {
		size_t k = 0;

		while (k < NCAT && strcmp(cat[k].mnemonic, named[i].mnemonic) != 0)
			k++;
		assert_true(k < NCAT);
		assert_int_equal(named[i].id, cat[k].id);
	}
	assert_int_equal(DF1_ID_ERR_COMMAND_TIMEOUT, 2508);
	assert_int_equal(DF1_ID_CNT_ACKS_SENT, 2535);
	assert_int_equal(DF1_ID_CRT_BAD_CMD_TIMEOUT, 2559);
	assert_int_equal(DF1_ID_CRD_CHAR_RECV, 2561);
	assert_int_equal(DF1_ERROR_COUNT, 34);
	assert_int_equal(DF1_E_LAST_, DF1_E_CIP - 1);
	assert_int_equal(df1_error_catalog_id(DF1_E_TIMEOUT), 2508);
	assert_int_equal(df1_error_catalog_id(DF1_E_NO_ETX), 2518);
}

/* ------------------------------------------------------------------------
 * STS and EXT STS
 * ------------------------------------------------------------------------ */

static bool known(const char *t)
{
	return t && strcmp(t, "unknown status") != 0;
}

/* Every code of doc/PROTOCOL.md 3.2-3.4 (M p.8-2..8-5) with its text, typed in
 * from the spec. ASCII stands in for the spec's typography: an em dash is " - ",
 * "passthru" is "pass-through", an arrow is "to". */
struct code_expect {
	uint8_t code;
	const char *text;
};

static const struct code_expect sts_expect[] = {
	{ 0x00, "success, no error" },
	{ 0x01, "DST node is out of buffer space" },
	{ 0x02, "cannot guarantee delivery: link layer (the remote node did not ACK the command)" },
	{ 0x03, "duplicate token holder detected" },
	{ 0x04, "local port is disconnected" },
	{ 0x05, "application layer timed out waiting for a response" },
	{ 0x06, "duplicate node detected" },
	{ 0x07, "station is offline" },
	{ 0x08, "hardware fault" },
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

static const struct code_expect ext_0f_expect[] = {
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

static const struct code_expect ext_dh485_expect[] = {
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

#define NEXP(t) (sizeof(t) / sizeof((t)[0]))

/* Each table code gives its text; every other byte gives "unknown status"
 * (STS: unless one of its nibbles is a code, see test_errors_sts_texts). */
static void test_errors_every_sts_and_ext_sts_code_has_its_text(void **state)
{
	(void)state;
	for (size_t i = 0; i < NEXP(sts_expect); i++)
		if (strcmp(df1_sts_text(sts_expect[i].code), sts_expect[i].text) != 0)
			fail_msg("STS %02X: '%s', want '%s'", sts_expect[i].code,
			         df1_sts_text(sts_expect[i].code), sts_expect[i].text);
	for (size_t i = 0; i < NEXP(ext_0f_expect); i++)
		if (strcmp(df1_ext_sts_text(ext_0f_expect[i].code), ext_0f_expect[i].text) != 0)
			fail_msg("EXT STS %02X: '%s', want '%s'", ext_0f_expect[i].code,
			         df1_ext_sts_text(ext_0f_expect[i].code), ext_0f_expect[i].text);
	for (size_t i = 0; i < NEXP(ext_dh485_expect); i++)
		if (strcmp(df1_ext_sts_text_dh485(ext_dh485_expect[i].code), ext_dh485_expect[i].text) != 0)
			fail_msg("DH-485 EXT STS %02X: '%s', want '%s'", ext_dh485_expect[i].code,
			         df1_ext_sts_text_dh485(ext_dh485_expect[i].code), ext_dh485_expect[i].text);
	for (unsigned c = 0; c < 256; c++) {
		bool in0f = false, in485 = false;

		for (size_t i = 0; i < NEXP(ext_0f_expect); i++)
			in0f |= ext_0f_expect[i].code == c;
		for (size_t i = 0; i < NEXP(ext_dh485_expect); i++)
			in485 |= ext_dh485_expect[i].code == c;
		if (!in0f)
			assert_string_equal(df1_ext_sts_text((uint8_t)c), "unknown status");
		if (!in485)
			assert_string_equal(df1_ext_sts_text_dh485((uint8_t)c), "unknown status");
	}
}

static void test_errors_sts_texts(void **state)
{
	(void)state;
	/* M p.8-2 local codes 00-08, spot-checked texts */
	assert_string_equal(df1_sts_text(0x00), "success, no error");
	assert_string_equal(df1_sts_text(0x01), "DST node is out of buffer space");
	assert_string_equal(df1_sts_text(0x04), "local port is disconnected");
	assert_string_equal(df1_sts_text(0x07), "station is offline");
	assert_string_equal(df1_sts_text(0x08), "hardware fault");
	for (unsigned c = 0; c <= 8; c++)
		assert_true(known(df1_sts_text((uint8_t)c)));
	for (unsigned c = 9; c <= 0x0F; c++)
		assert_string_equal(df1_sts_text((uint8_t)c), "unknown status");
	/* M p.8-3 remote codes 10-C0 and F0; D0 and E0 are not used */
	assert_string_equal(df1_sts_text(0x10), "illegal command or format");
	assert_string_equal(df1_sts_text(0x50), "addressing problem or memory protect rungs");
	assert_string_equal(df1_sts_text(0x70), "processor is in Program mode");
	assert_string_equal(df1_sts_text(0xF0), "error code is in the EXT STS byte");
	for (unsigned c = 0x10; c <= 0xC0; c += 0x10)
		assert_true(known(df1_sts_text((uint8_t)c)));
	assert_string_equal(df1_sts_text(0xA0), df1_sts_text(0xC0)); /* the manual repeats it */
	assert_string_equal(df1_sts_text(0xD0), "unknown status");
	assert_string_equal(df1_sts_text(0xE0), "unknown status");
	/* both nibbles: a defined local code wins, an unused one defers to remote */
	assert_string_equal(df1_sts_text(0x72), df1_sts_text(0x02));
	assert_string_equal(df1_sts_text(0x19), df1_sts_text(0x10));
	assert_string_equal(df1_sts_text(0xDF), "unknown status");
	/* every byte has a text */
	for (unsigned c = 0; c < 256; c++)
		assert_non_null(df1_sts_text((uint8_t)c));
}

static void test_errors_ext_sts_texts_cmd_0f(void **state)
{
	(void)state;
	for (unsigned c = 0; c <= 0x1F; c++)
		assert_true(known(df1_ext_sts_text((uint8_t)c)));
	for (unsigned c = 0x22; c <= 0x24; c++)
		assert_true(known(df1_ext_sts_text((uint8_t)c)));
	assert_string_equal(df1_ext_sts_text(0x20), "unknown status");
	assert_string_equal(df1_ext_sts_text(0x21), "unknown status");
	assert_string_equal(df1_ext_sts_text(0x25), "unknown status");
	assert_string_equal(df1_ext_sts_text(0xFF), "unknown status");
	/* M p.8-4 texts */
	assert_string_equal(df1_ext_sts_text(0x01), "a field has an illegal value");
	assert_string_equal(df1_ext_sts_text(0x06), "address doesn't point to something usable");
	assert_string_equal(df1_ext_sts_text(0x07), "file is wrong size");
	assert_string_equal(df1_ext_sts_text(0x10), "no access");
	assert_string_equal(df1_ext_sts_text(0x17), "type mismatch");
	assert_string_equal(df1_ext_sts_text(0x1F), "temporary internal problem");
	assert_non_null(strstr(df1_ext_sts_text(0x22), "remote rack fault"));
	assert_non_null(strstr(df1_ext_sts_text(0x23), "timeout"));
	assert_non_null(strstr(df1_ext_sts_text(0x24), "unknown error"));
}

static void test_errors_ext_sts_texts_dh485(void **state)
{
	static const uint8_t codes[] = { 0x07, 0x0B, 0x0C, 0x0E, 0x12, 0x14, 0x19, 0x1A, 0x1B };
	unsigned n = 0;

	(void)state;
	for (size_t i = 0; i < sizeof codes; i++)
		assert_true(known(df1_ext_sts_text_dh485(codes[i])));
	for (unsigned c = 0; c < 256; c++)
		n += known(df1_ext_sts_text_dh485((uint8_t)c));
	assert_int_equal(n, sizeof codes);
	/* M p.8-5 texts */
	assert_non_null(strstr(df1_ext_sts_text_dh485(0x07), "insufficient memory module size"));
	assert_string_equal(df1_ext_sts_text_dh485(0x12), "invalid parameter");
	assert_string_equal(df1_ext_sts_text_dh485(0x19), "duplicate label");
	assert_string_equal(df1_ext_sts_text_dh485(0x1A), "file open by another node");
	assert_string_equal(df1_ext_sts_text_dh485(0x1B), "program owned by another node");
	assert_string_equal(df1_ext_sts_text_dh485(0x06), "unknown status");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_errors_every_code_has_name_text_and_catalog),
		cmocka_unit_test(test_errors_unknown_code_gives_static_text),
		cmocka_unit_test(test_errors_unexecuted_follows_the_link_rules),
		cmocka_unit_test(test_errors_catalog_has_every_seed_id),
		cmocka_unit_test(test_errors_catalog_by_mnemonic_any_case),
		cmocka_unit_test(test_errors_catalog_iterates_in_id_order),
		cmocka_unit_test(test_errors_catalog_names_are_the_seed_ids),
		cmocka_unit_test(test_errors_sts_texts),
		cmocka_unit_test(test_errors_ext_sts_texts_cmd_0f),
		cmocka_unit_test(test_errors_ext_sts_texts_dh485),
		cmocka_unit_test(test_errors_every_sts_and_ext_sts_code_has_its_text),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
