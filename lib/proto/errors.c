/* SPDX-License-Identifier: MPL-2.0 */
/*
 * errors - the one home of every table of texts: library error codes (the
 * DF1_ERROR_TABLE X-macro of df1.h), the message catalog of doc/REQUIREMENTS.md 004
 * (IDs 2501-2561), and the PLC's STS / EXT STS codes (doc/PROTOCOL.md 3.2-3.4).
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

bool df1_error_unexecuted(int err)
{
	switch (err) {
	case DF1_E_REMOTE:       /* the PLC answered: it refused */
	case DF1_E_NAK:          /* the receiver did not take the frame */
	case DF1_E_INACTIVE:     /* the station did not answer its poll: nothing sent */
	case DF1_E_NOT_OPEN:
	case DF1_E_INVAL:
	case DF1_E_TYPE:
	case DF1_E_RANGE:
	case DF1_E_ADDR_SYNTAX:
	case DF1_E_ADDR_RANGE:
	case DF1_E_NOTSUP:
	case DF1_E_NOMEM:
	case DF1_E_BUSY:
	case DF1_E_CONFIG:
	case DF1_E_NOSPACE:
	case DF1_E_NODEV:
	case DF1_E_PERM:
		return true;
	default:
		return false;
	}
}

/* ------------------------------------------------------------------------
 * Message catalog (doc/REQUIREMENTS.md 004): the rows of DF1_CATALOG_TABLE (df1.h). Every
 * ID 2501-2561 is defined by the seed; the format is the seed's message text
 * before its " - explanation".
 * ------------------------------------------------------------------------ */

#define CATALOG_ROW(mnemonic, id, sev, format, description) \
	{ id, #mnemonic, DF1_SEV_##sev, format, description },
static const struct df1_catalog_entry catalog[] = { DF1_CATALOG_TABLE(CATALOG_ROW) };
#undef CATALOG_ROW

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
 * PLC status codes (M p.8-2..8-5, doc/PROTOCOL.md 3.2-3.4)
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

/* EXT STS after STS F0, CMD 0F (M p.8-4). 22-24: see doc/PROTOCOL.md 3.3 [UNCERTAIN]. */
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
