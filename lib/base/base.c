/* SPDX-License-Identifier: MPL-2.0 */
/*
 * base.c - the handle's last-error detail, its counters (doc/REQUIREMENTS.md 004 IDs
 * 2525-2561) and catalog logging, for every layer above (lib/base/base.h).
 * The public getters (df1_last_error, df1_counter) are lib/handle.c's.
 */
#include "base/base.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "df1_int.h"

/* Format catalog message id with ap into buf; false if the catalog has no format. */
static bool base_catalog_vformat(char *buf, size_t cap, int id, va_list ap)
{
	const struct df1_catalog_entry *e = df1_catalog_by_id(id);

	if (!e || !e->format) {
		if (e && e->description)
			snprintf(buf, cap, "%s", e->description);
		else
			snprintf(buf, cap, "message %d", id);
		return false;
	}
	vsnprintf(buf, cap, e->format, ap);
	return true;
}

void df1_log(struct df1 *h, int catalog_id, ...)
{
	const struct df1_catalog_entry *e;
	char text[256];
	va_list ap;

	if (!h || !h->log_fn)
		return;
	e = df1_catalog_by_id(catalog_id);
	va_start(ap, catalog_id);
	base_catalog_vformat(text, sizeof text, catalog_id, ap);
	va_end(ap);
	h->log_fn(h->log_user, catalog_id, e ? e->severity : DF1_SEV_ERROR, text);
}

void df1_clear_error(struct df1 *h)
{
	if (!h)
		return;
	memset(&h->err, 0, sizeof h->err);
	h->err.station = -1;
}

int df1_fail(struct df1 *h, int code, int station, const char *fmt, ...)
{
	int saved_errno = errno;
	va_list ap;

	if (!h)
		return code;
	memset(&h->err, 0, sizeof h->err);
	h->err.code = code;
	h->err.sys_errno = code == DF1_E_SYS ? saved_errno : 0;
	h->err.station = station;
	h->err.catalog_id = df1_error_catalog_id(code);
	if (fmt) {
		va_start(ap, fmt);
		vsnprintf(h->err.message, sizeof h->err.message, fmt, ap);
		va_end(ap);
	} else {
		snprintf(h->err.message, sizeof h->err.message, "%s", df1_strerror(code));
	}
	errno = saved_errno;
	return code;
}

int df1_fail_remote(struct df1 *h, int station, uint8_t sts, uint8_t ext, bool has_ext)
{
	if (!h)
		return DF1_E_REMOTE;
	memset(&h->err, 0, sizeof h->err);
	h->err.code = DF1_E_REMOTE;
	h->err.station = station;
	h->err.sts = sts;
	h->err.ext_sts = has_ext ? ext : 0;
	h->err.has_ext_sts = has_ext;
	h->err.catalog_id = df1_error_catalog_id(DF1_E_REMOTE);
	if (has_ext)
		snprintf(h->err.message, sizeof h->err.message,
		         "PLC error: STS 0x%02X (%s), EXT STS 0x%02X (%s)", sts, df1_sts_text(sts), ext,
		         df1_ext_sts_text(ext));
	else
		snprintf(h->err.message, sizeof h->err.message, "PLC error: STS 0x%02X (%s)", sts,
		         df1_sts_text(sts));
	return DF1_E_REMOTE;
}

int df1_fail_catalog(struct df1 *h, int id, ...)
{
	va_list ap;

	memset(&h->err, 0, sizeof h->err);
	h->err.code = DF1_E_CONFIG;
	h->err.station = -1;
	h->err.catalog_id = id;
	va_start(ap, id);
	base_catalog_vformat(h->err.message, sizeof h->err.message, id, ap);
	va_end(ap);
	if (h->log_fn) {
		const struct df1_catalog_entry *e = df1_catalog_by_id(id);

		h->log_fn(h->log_user, id, e ? e->severity : DF1_SEV_CRITICAL, h->err.message);
	}
	return DF1_E_CONFIG;
}

void df1_count(struct df1 *h, int id)
{
	if (h && id >= CNT_BASE && id < CNT_BASE + CNT_COUNT)
		h->counters[id - CNT_BASE]++;
}

void df1_count_n(struct df1 *h, int id, uint64_t n)
{
	if (h && id >= CNT_BASE && id < CNT_BASE + CNT_COUNT)
		h->counters[id - CNT_BASE] += n;
}
