/* SPDX-License-Identifier: MPL-2.0 */
/*
 * mon - what the files of df1mon share: the modes, the state of a run
 * (struct mon), the byte streams the decoding modes feed, and each file's
 * entry points. df1mon.c holds main, the option table and --map's call; the
 * other modes have a file each:
 *
 *   mon_stream.c    one byte stream through a decoder, symbols printed
 *   mon_decode.c    --decode: hex arguments or stdin lines
 *   mon_read.c      --read: a pcap (RTAC serial) or a raw byte dump
 *   mon_pcap.c      the pcap format: headers read, captures written
 *   mon_sniff.c     --sniff: the taps, -w's capture, the decode loop
 *   mon_radio.c     --duplex radio when decoding: relayed copies, the tallies
 *   mon_live.c      clocks, waits and stop reasons of the live modes
 *   mon_counters.c  the counter table, --counters alone
 *   mon_ping.c      --ping
 *   mon_who.c       --who, on df1_discover()
 *   mon_map.c       --map's live table (its own interface: mon_map.h)
 *   mon_serve.c     --serve: a data table answering a PLC's MSG
 *
 * Every mode's run function returns CLI_CONTINUE (the exit status then comes
 * from the decoding tallies) or an exit status.
 */
#ifndef DF1_TOOLS_MON_H
#define DF1_TOOLS_MON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "common/cli.h"
#include "common/decode.h"
#include "df1.h"

enum mon_mode {
	MODE_NONE = 0,
	MODE_DECODE,
	MODE_READ,
	MODE_SNIFF,
	MODE_PING,
	MODE_WHO,
	MODE_MAP,
	MODE_COUNTERS,   /* --counters alone */
	MODE_AUTOCONF,   /* --autoconf: mon_autoconf.c */
	MODE_SERVE,      /* --serve: mon_serve.c */
	MODE_COUNT_
};

enum {
	KEY_DECODE = CLI_KEY_EXTRA,
	KEY_SNIFF,
	KEY_SNIFF_B,
	KEY_PING,
	KEY_WHO,
	KEY_MAP,
	KEY_COUNTERS,
	KEY_DURATION,
	KEY_AUTOCONF,    /* mon_autoconf.c */
	KEY_STATIONS,
	KEY_SERVE,       /* mon_serve.c */
	KEY_SKIP_BAD_ROWS,
};

/* Options given, for the checks of what goes with which mode. */
enum {
	GIVEN_COUNT = 1 << 0,
	GIVEN_INTERVAL = 1 << 1,
	GIVEN_DURATION = 1 << 2,
	GIVEN_WRITE = 1 << 3,
	GIVEN_SNIFF_B = 1 << 4,
	GIVEN_ONCE = 1 << 5,
	GIVEN_COUNTERS = 1 << 6,
	GIVEN_STATIONS = 1 << 7,      /* --stations (--autoconf) */
	GIVEN_SKIP_BAD_ROWS = 1 << 8, /* --skip-bad-rows (--map) */
};

/* mon_radio.c: the last packets of a radio channel, and its tallies */
#define MON_RADIO_DEPTH 20     /* as a node's duplicate detection (doc/PROTOCOL.md 2.6) */
struct mon_radio_pkt {
	uint8_t key[6];            /* DST SRC CMD STS TNS */
	unsigned long first;       /* the symbol number of its first copy */
	const char *dir;           /* that copy's direction, or NULL */
	bool relayed;              /* a relayed copy was seen */
};
struct mon_radio {
	struct mon_radio_pkt last[MON_RADIO_DEPTH];
	unsigned n, head;
	unsigned long sent, received, relayed, duplicates, bad;
};

struct mon {
	struct cli cli;
	enum mon_mode mode;
	const char *read_file;
	struct decode_ctx dx;
	FILE *out;                 /* where symbol lines go (stdout, or /dev/null with -w -) */
	unsigned long index;       /* symbols printed */
	unsigned long long fed;    /* bytes fed to decoders */
	unsigned long long used;   /* bytes that belonged to a symbol */
	unsigned long frame_limit; /* --sniff -c N: stop after N frames (0: no limit) */

	/* live options */
	unsigned given;            /* GIVEN_* */
	bool counters;             /* --counters */
	long count;                /* -c */
	double interval_s;         /* -i */
	double duration_s;         /* --duration */
	bool once;                 /* -1 */
	bool skip_bad_rows;        /* --skip-bad-rows: --map loads the good rows of a file with bad ones */
	const char *sniff_b;       /* --sniff-b DEV2 */
	const char *pcap_path;     /* -w FILE */
	const char *map_file;      /* --map FILE */
	const char *serve_spec;    /* --serve REGION[,REGION...] */
	const char *who_range;     /* --who=LO-HI or the operand */
	int who_lo, who_hi;
	df1_t *h;                  /* the handle of a talking mode */
	int64_t t0_us;             /* monotonic start of a live mode */
	unsigned counter_prints;   /* counter tables printed */
	struct mon_radio radio;    /* --duplex radio: the decoding modes' packets */
};

/* ---- mon_pcap.c: the pcap format (read by --read, written by --sniff -w) ---- */

#define PCAP_HDR 24        /* the file header */
#define PCAP_REC_HDR 16    /* a record's header */
/* pcap link type 250 (RTAC serial) and its 12-byte header before the bytes */
#define LINKTYPE_RTAC_SERIAL 250
#define RTAC_HDR 12
#define RTAC_DATA_TX_END 0x03  /* the event types of the records written */
#define RTAC_DATA_RX_END 0x04
#define MON_PCAP_DATA_MAX 4096 /* the most bytes a record written holds */

struct pcap_fmt {
	bool swapped;   /* fields are big-endian */
	bool nsec;      /* nanosecond timestamps */
	uint32_t linktype;
};

/* The start of a file (n bytes): 1 pcap (*f set, but its linktype), 0 not a
 * pcap (a raw dump), -1 pcapng. */
int mon_pcap_detect(const uint8_t *b, size_t n, struct pcap_fmt *f);
/* The link type in a pcap's PCAP_HDR-byte header. */
uint32_t mon_pcap_linktype(const uint8_t *hdr, const struct pcap_fmt *f);
/* A record's PCAP_REC_HDR-byte header: its time (microseconds; 0 if out of
 * range) and the bytes it holds in the file. */
void mon_pcap_rec_hdr(const uint8_t *hdr, const struct pcap_fmt *f, uint32_t *sec, int32_t *usec,
                      uint32_t *incl);
/* A record's direction from its RTAC event type: 1 transmit, 0 receive. */
int mon_rtac_dir(uint8_t event);
/* The file header of a capture written; false on a write error. */
bool mon_pcap_write_header(FILE *f);
/* One record (n <= MON_PCAP_DATA_MAX): pcap record header, RTAC header (BE
 * seconds, BE microseconds, event type, control lines, 2 footer bytes), the
 * bytes; flushed at once so an interrupted capture is a valid file. */
bool mon_pcap_write_record(FILE *f, int64_t sec, int32_t usec, uint8_t event, uint8_t lines,
                           const uint8_t *b, size_t n);

/* ---- mon_stream.c: one byte stream (one direction of a capture, or one --decode chunk) ---- */

#define RING 256   /* records whose start and time a stream remembers */

struct stream {
	struct df1_decoder *dec;
	const char *dir;            /* "tx"/"rx" when a capture has both, else NULL */
	unsigned long long off;     /* bytes fed so far */
	/* where each recent record began in the stream, and its time */
	struct {
		unsigned long long off;
		int64_t sec;
		int32_t usec;
	} ring[RING];
	unsigned nring, head;
	bool timed;
	bool duplex_auto;           /* the decoder reads DLE ENQ by its shape */
	uint8_t tail[4];            /* the last bytes consumed, newest last */
};

/* Time base of a capture: the first record's time. */
struct timebase {
	bool set;
	int64_t sec;
	int32_t usec;
};

int mon_stream_init(struct mon *m, struct stream *s, const char *dir);
void mon_stream_free(struct stream *s);
void mon_stream_mark(struct stream *s, int64_t sec, int32_t usec);
void mon_stream_feed(struct mon *m, struct stream *s, const struct timebase *tb,
                     const uint8_t *p, size_t n);
/* End of the input: a symbol still under way is reported (cut: only a verdict on
 * the bytes that were there; a sniff stopped by a signal, -c or --duration). */
void mon_stream_finish_cut(struct mon *m, struct stream *s, const struct timebase *tb, bool cut);
void mon_stream_finish(struct mon *m, struct stream *s, const struct timebase *tb);

/* ---- the modes ---- */

int mon_run_decode(struct mon *m);            /* mon_decode.c */
int mon_run_read(struct mon *m);              /* mon_read.c */
int mon_run_sniff(struct mon *m);             /* mon_sniff.c */
int mon_run_counters(struct mon *m);          /* mon_counters.c */
int mon_run_ping(struct mon *m);              /* mon_ping.c */
int mon_run_who(struct mon *m);               /* mon_who.c */
int mon_run_autoconf(struct mon *m);          /* mon_autoconf.c */
int mon_run_serve(struct mon *m);             /* mon_serve.c */
int mon_serve_check(struct mon *m);           /* --serve's regions parse: CLI_CONTINUE, else exit 2 */
bool mon_who_is_eip(const struct mon *m);     /* mon_who.c: an eip:// device */
/* --who's operand "N" or "LO-HI" (0..254) into m->who_lo, who_hi; exit 2 if bad. */
int mon_parse_range(struct mon *m, const char *arg);
/* Every counter of the seed table in ID order, in the -f format; final: the one at exit. */
void mon_print_counters(struct mon *m, bool final);

/* ---- mon_radio.c: --duplex radio in the decoding modes ---- */

/* A symbol about to be printed (w->index set): tallied; a good packet that
 * repeats one of the last MON_RADIO_DEPTH gets w->copy_of, copy_relay and
 * copy_duplicate (decode.h). */
void mon_radio_seen(struct mon *m, const char *dir, const struct df1_symbol *sym,
                    struct decode_where *w);
/* One line after the decoding summary: sent, received, relayed, duplicates, bad. */
void mon_radio_summary(const struct mon *m, FILE *f);

/* ---- mon_live.c: clocks, waits, stop reasons ---- */

int64_t mon_mono_us(void);                    /* CLOCK_MONOTONIC, microseconds */
void mon_wall_now(int64_t *sec, int32_t *usec); /* CLOCK_REALTIME */
/* stdout cannot take more (a closed pipe): end the loop; main reports it, exit 1. */
bool mon_out_broken(void);
double mon_elapsed(const struct mon *m);      /* seconds since the live mode started */
/* Wait ms milliseconds, or until a signal (or --duration) stops us: false then. */
bool mon_sleep(long ms);
const char *mon_signal_name(int sig);         /* "--duration" for SIGALRM */
bool mon_interrupted(void);                   /* stopped by a signal, not by --duration */
long mon_ms_of(double seconds);

#endif
