/* SPDX-License-Identifier: MPL-2.0 */
/*
 * df1_probe.h - finding what is on a line: station discovery (df1_discover(3)),
 * the echo and link test, and auto-configuring an unknown line's settings
 * (df1_probe_line(3)). Installed beside df1.h, which includes it; include
 * df1.h.
 */
#ifndef LIBDF1_DF1_PROBE_H
#define LIBDF1_DF1_PROBE_H

#include "df1.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Station discovery (df1_discover(3)): which stations of lo..hi (0..254) answer,
 * and what they are. One station after the other, in ascending order:
 *  - half-duplex master: a poll (DLE ENQ STN, as df1_link_test); a station that
 *    answers it is asked its diagnostic status (06/03);
 *  - full duplex: first one DLE ENQ for the line (nobody answers: the scan ends
 *    with that error, fn never called); then the diagnostic status addressed to
 *    each station is the probe. A point-to-point peer may answer any DST.
 * The poll engine's discovery (df1_poll_set_station_range) uses the same probe.
 * fn (may be NULL) is called once per station probed, with r valid during the
 * call only; while it runs, df1_last_error(h) describes r->error. fn returns 0
 * to go on, anything else to stop (df1_discover then returns the count so far).
 * The cancel fd (df1_set_cancel_fd) is honoured in every wait and before each
 * station: DF1_E_INTR, and fn is not called for the station under way.
 * Returns the number of stations that answered, or DF1_E_*: DF1_E_INVAL (h NULL,
 * lo/hi outside 0..254 or lo > hi), DF1_E_NOT_OPEN, DF1_E_NOTSUP (half-duplex
 * slave), DF1_E_INTR, the line's error (full duplex, no answer to DLE ENQ).
 * @since 0.2 */
struct df1_discover_result {
	int station;                    /* 0..254 */
	bool answered;                  /* it replied (a reply with an error STS counts) */
	bool identified;                /* status holds its diagnostic status */
	int error;                      /* DF1_OK when identified; else why not (DF1_E_*) */
	uint64_t rtt_us;                /* round trip of the probe it answered (half duplex:
	                                 * the poll; full duplex: 06/03); 0 if none */
	struct df1_diag_status status;  /* type code, processor name, series, mode...: identified */
};
typedef int (*df1_discover_fn)(void *user, const struct df1_discover_result *r);
DF1_API int df1_discover(df1_t *h, int lo, int hi, df1_discover_fn fn, void *user);
/* 06/00 echo: sends data, checks it comes back. Returns the length echoed. */
DF1_API int df1_echo(df1_t *h, int station, const uint8_t *data, size_t n);
/* Link test: DLE ENQ (full duplex) or a poll (half duplex); 0 if the link answered. */
DF1_API int df1_link_test(df1_t *h, int station);
/* Auto-configure the open handle's line (df1_probe_line(3): the stages, the
 * order of the settings tried, the time it takes). Nothing is written to a
 * controller: link tests, echoes (06/00) and diagnostic status (06/03) only.
 * Returns 1 when found (*out; the handle is left at the settings found), 0
 * when nothing answered, or DF1_E_*. @since 0.5 */
enum df1_probe_stage {
	DF1_PROBE_LINK = 1,             /* baud, parity and duplex: a peer answers at all */
	DF1_PROBE_CHECK = 2,            /* CRC or BCC: an echo comes back intact */
	DF1_PROBE_IDENTITY = 3,         /* diagnostic status; half duplex: the stations */
};
struct df1_line_settings {
	int baud, data_bits, stop_bits;
	char parity;                    /* 'N', 'E' or 'O' */
	enum df1_duplex duplex;
	enum df1_check check;
	bool hd_bcc_stx;                /* half duplex: the BCC sums STX */
	int station;                    /* the station that answered (full duplex: -1) */
};
struct df1_probe_attempt {
	enum df1_probe_stage stage;
	struct df1_line_settings tried;
	const char *what;               /* "DLE ENQ", "poll", "echo 06/00", "diagnostic status" */
	bool answered;
	int error;                      /* DF1_OK, or why not */
};
/* Called once per attempt; a non-zero return stops the search (DF1_E_INTR). */
typedef int (*df1_probe_fn)(void *user, const struct df1_probe_attempt *a);
struct df1_probe_result {
	struct df1_line_settings found;
	bool identified;                /* status holds the diagnostic status */
	struct df1_diag_status status;
	int nstations;                  /* half duplex: the stations of lo..hi that answered */
	uint8_t stations[255];
	int attempts;
	int64_t elapsed_ms;
};
DF1_API int df1_probe_line(df1_t *h, int lo, int hi, df1_probe_fn fn, void *user, struct df1_probe_result *out);
/* The longest df1_probe_line(h, lo, hi, ...) can take at h's timeouts, in ms. @since 0.5 */
DF1_API int64_t df1_probe_line_bound_ms(const df1_t *h, int lo, int hi);

#ifdef __cplusplus
}
#endif

#endif /* LIBDF1_DF1_PROBE_H */
