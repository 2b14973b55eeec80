/* SPDX-License-Identifier: MPL-2.0 */
/* Generated from include/df1.h by python/gen_cdefs.py: do not edit.
 * Regenerate after every change to df1.h (a test compares the two). */
#define DF1_ADDR_ASCII_MAX 52
#define DF1_ADDR_NONE -1
#define DF1_CATALOG_COUNT 61
#define DF1_DUP_AUTO 2
#define DF1_ERROR_COUNT 34
#define DF1_E_LAST_ -34
#define DF1_PCCC_MAX 262
#define DF1_PCCC_QUEUE_MAX 64
#define DF1_READ_MULTI_STOP 1
#define DF1_SILENT_ALL 256
#define DF1_STRING_MAX 82
#define DF1_TABLE_ELEMENTS_DEFAULT 256
#define DF1_TABLE_ELEMENTS_MAX 1000
#define DF1_TABLE_FILES_MAX 1000
#define DF1_VERSION_MAJOR 0
#define DF1_VERSION_MICRO 0
#define DF1_VERSION_MINOR 5

struct df1_version {
	int major;
	int minor;
	int micro;
	const char *string;
};
const struct df1_version *df1_version(void);
enum df1_error {
	DF1_OK = 0,
	DF1_E_INVAL = -1,
	DF1_E_SYS = -2,
	DF1_E_NOMEM = -3,
	DF1_E_TIMEOUT = -4,
	DF1_E_NAK_LIMIT = -5,
	DF1_E_ENQ_LIMIT = -6,
	DF1_E_REMOTE = -7,
	DF1_E_BCC = -8,
	DF1_E_CRC = -9,
	DF1_E_TOO_LONG = -10,
	DF1_E_TOO_SHORT = -11,
	DF1_E_SYMBOL = -12,
	DF1_E_ADDR_SYNTAX = -13,
	DF1_E_ADDR_RANGE = -14,
	DF1_E_BAD_FUNCTION = -15,
	DF1_E_INACTIVE = -16,
	DF1_E_WRONG_MSG = -17,
	DF1_E_BUSY = -18,
	DF1_E_NOTSUP = -19,
	DF1_E_TYPE = -20,
	DF1_E_RANGE = -21,
	DF1_E_NOT_OPEN = -22,
	DF1_E_CLOSED = -23,
	DF1_E_CONFIG = -24,
	DF1_E_INTR = -25,
	DF1_E_NOSPACE = -26,
	DF1_E_NAK = -27,
	DF1_E_BAD_REPLY = -28,
	DF1_E_NO_ETX = -29,
	DF1_E_NODEV = -30,
	DF1_E_PERM = -31,
	DF1_E_EIP = -32,
	DF1_E_CIP = -33,
};
const char *df1_strerror(int err);
const char *df1_errname(int err);
int df1_error_catalog_id(int err);
_Bool df1_error_unexecuted(int err);
_Bool df1_pccc_is_write(const uint8_t *pccc, size_t n);
const char *df1_sts_text(uint8_t sts);
const char *df1_ext_sts_text(uint8_t ext);
const char *df1_ext_sts_text_dh485(uint8_t ext);
enum df1_severity {
	DF1_SEV_CRITICAL = 0,
	DF1_SEV_ERROR = 1,
	DF1_SEV_NOTICE = 2,
	DF1_SEV_COUNTER = 3,
};
enum df1_catalog_id {
	DF1_ID_ERR_BAD_STATION = 2501,
	DF1_ID_ERR_BAD_PLC_TYPE = 2502,
	DF1_ID_ERR_ADDRESS_SYNTAX = 2503,
	DF1_ID_ERR_ADDRESS_RANGE = 2504,
	DF1_ID_ERR_BAD_FUNCTION_CODE = 2505,
	DF1_ID_ERR_BAD_CRC = 2506,
	DF1_ID_ERR_BAD_BCC = 2507,
	DF1_ID_ERR_COMMAND_TIMEOUT = 2508,
	DF1_ID_ERR_INACTIVE_STATION = 2509,
	DF1_ID_ERR_WRONG_MESSAGE = 2510,
	DF1_ID_ERR_RCVD_NAK_SYMBOL = 2511,
	DF1_ID_NTC_RCVD_MSG_TOO_LONG = 2512,
	DF1_ID_NTC_RCVD_MSG_TOO_SHORT = 2513,
	DF1_ID_NTC_INVALID_SYMBOL = 2514,
	DF1_ID_NTC_ACK_EXPECTED = 2515,
	DF1_ID_NTC_EOT_STX_EXPECTED = 2516,
	DF1_ID_NTC_RCVD_NAK_SYMBOL = 2517,
	DF1_ID_NTC_NO_ETX_RCVD = 2518,
	DF1_ID_NTC_NAK_LIMIT_EXCEEDED = 2519,
	DF1_ID_NTC_ENQ_LIMIT_EXCEEDED = 2520,
	DF1_ID_NTC_NAK_RETRY = 2521,
	DF1_ID_NTC_ENQ_RETRY = 2522,
	DF1_ID_NTC_REPLY_MSG_RCVD = 2523,
	DF1_ID_NTC_DUPLICATE_MSG_RCVD = 2524,
	DF1_ID_CNT_MSG_PACKETS_SENT = 2525,
	DF1_ID_CNT_MSG_PACKETS_RCVD = 2526,
	DF1_ID_CNT_CMD_MSGS_SENT = 2527,
	DF1_ID_CNT_CMD_MSGS_RCVD = 2528,
	DF1_ID_CNT_REPLY_MSGS_SENT = 2529,
	DF1_ID_CNT_REPLY_MSGS_RCVD = 2530,
	DF1_ID_CNT_POLL_MSGS_SENT = 2531,
	DF1_ID_CNT_POLL_MSGS_RCVD = 2532,
	DF1_ID_CNT_NAKS_SENT = 2533,
	DF1_ID_CNT_NAKS_RCVD = 2534,
	DF1_ID_CNT_ACKS_SENT = 2535,
	DF1_ID_CNT_ACKS_RCVD = 2536,
	DF1_ID_CNT_EOTS_SENT = 2537,
	DF1_ID_CNT_EOTS_RCVD = 2538,
	DF1_ID_CNT_ERROR_MSGS_SENT = 2539,
	DF1_ID_CNT_ERROR_MSGS_RCVD = 2540,
	DF1_ID_CNT_NAK_RETRIES = 2541,
	DF1_ID_CNT_NAK_LIMIT_EXCEEDED = 2542,
	DF1_ID_CNT_ENQ_RETRIES = 2543,
	DF1_ID_CNT_ENQ_LIMIT_EXCEEDED = 2544,
	DF1_ID_CNT_COMMAND_TIMEOUTS = 2545,
	DF1_ID_CNT_BCC_ERRORS = 2546,
	DF1_ID_CNT_CRC_ERRORS = 2547,
	DF1_ID_CNT_STALE_MSGS_RCVD = 2548,
	DF1_ID_CNT_DUPLICATE_MSGS_RCVD = 2549,
	DF1_ID_CNT_INVALID_MSGS_RCVD = 2550,
	DF1_ID_CNT_COM_READ_ERRORS = 2551,
	DF1_ID_CRT_BAD_STATION_ID = 2552,
	DF1_ID_CRT_BAD_DRIVER_MODE = 2553,
	DF1_ID_CRT_UNSUPPORTED_MODE = 2554,
	DF1_ID_CRT_BAD_PLC_TYPE = 2555,
	DF1_ID_CRT_BAD_ERROR_CODE = 2556,
	DF1_ID_CRT_BAD_NAK_RETRIES = 2557,
	DF1_ID_CRT_BAD_ENQ_RETRIES = 2558,
	DF1_ID_CRT_BAD_CMD_TIMEOUT = 2559,
	DF1_ID_CRD_CHAR_SENT = 2560,
	DF1_ID_CRD_CHAR_RECV = 2561,
};
struct df1_catalog_entry {
	int id;
	const char *mnemonic;
	enum df1_severity severity;
	const char *format;
	const char *description;
};
const struct df1_catalog_entry *df1_catalog_by_id(int id);
const struct df1_catalog_entry *df1_catalog_by_mnemonic(const char *mn);
const struct df1_catalog_entry *df1_catalog_at(size_t index);
enum df1_file_type {
	DF1_FT_NONE = 0,
	DF1_FT_O,
	DF1_FT_I,
	DF1_FT_S,
	DF1_FT_B,
	DF1_FT_T,
	DF1_FT_C,
	DF1_FT_R,
	DF1_FT_N,
	DF1_FT_F,
	DF1_FT_ST,
	DF1_FT_A,
	DF1_FT_L,
	DF1_FT_COUNT_,
	DF1_FT_D = 16
};
struct df1_addr {
	enum df1_file_type type;
	int file;
	int element;
	int sub;
	int bit;
	char ascii[52];
};
int df1_addr_parse(const char *text, struct df1_addr *a);
int df1_addr_format(const struct df1_addr *a, char *buf, size_t cap);
const char *df1_file_type_name(enum df1_file_type t);
int df1_file_type_element_size(enum df1_file_type t);
int df1_file_type_slc_code(enum df1_file_type t);
struct df1_tcr {
	uint16_t ctl;
	int16_t pre;
	int16_t acc;
};
enum df1_value_kind {
	DF1_VAL_INT16,
	DF1_VAL_INT32,
	DF1_VAL_FLOAT,
	DF1_VAL_BIT,
	DF1_VAL_STRING,
	DF1_VAL_TCR
};
struct df1_value {
	enum df1_value_kind kind;
	union {
		int16_t i16;
		int32_t i32;
		float f;
		_Bool bit;
		struct {
			uint16_t len;
			char text[82 + 1];
		} str;
		struct df1_tcr tcr;
	} v;
};
enum df1_value_kind df1_addr_value_kind(const struct df1_addr *a);
int df1_tcr_bit(enum df1_file_type t, const char *name);
int df1_value_format(const struct df1_value *v, enum df1_file_type t, char *buf, size_t cap);
int df1_value_parse(const struct df1_addr *a, const char *text, struct df1_value *v);
typedef struct df1 df1_t;
enum df1_duplex {
	DF1_FULL_DUPLEX = 0,
	DF1_HALF_DUPLEX_MASTER = 1,
	DF1_HALF_DUPLEX_SLAVE = 2,
	DF1_RADIO_MODEM = 3
};
enum df1_check {
	DF1_CHECK_CRC = 0,
	DF1_CHECK_BCC = 1,
	DF1_CHECK_AUTO = 2
};
enum df1_plc {
	DF1_PLC_SLC = 0,
	DF1_PLC_MICROLOGIX = 1,
	DF1_PLC_SLC502 = 2,
	DF1_PLC_PLC5 = 3,
	DF1_PLC_PLC2 = 4,
	DF1_PLC_PLC3 = 5,
};
int df1_addr_parse_plc(enum df1_plc plc, const char *text, struct df1_addr *a);
int df1_addr_format_plc(enum df1_plc plc, const struct df1_addr *a, char *buf, size_t cap);
enum df1_option {
	DF1_OPT_DUPLICATE_DETECT = 1,
	DF1_OPT_EMBEDDED_RESPONSES,
	DF1_OPT_HD_BCC_INCLUDES_STX,
	DF1_OPT_ACCEPT_NAK_0F,
	DF1_OPT_RS485,
	DF1_OPT_ECHO_DISCARD,
	DF1_OPT_MAX_PACKET,
	DF1_OPT_EOT_WITH_BCC,
	DF1_OPT_LOCAL_TCP,
	DF1_OPT_PLC5_TYPED_FLOAT_SWAPPED,
	DF1_OPT_SLC_IO_CODES_82,
	DF1_OPT_LISTEN_ONLY,
	DF1_OPT_PLC5_TIMER_WORDS,
	DF1_OPT_PLC2_WORD_ADDR,
	DF1_OPT_POLL_TIMEOUT_MS,
	DF1_OPT_SCAN_TIME_MS,
	DF1_OPT_NO_EOT,
	DF1_OPT_MAX_OUTSTANDING,
	DF1_OPT_EIP_CONNECTED,
	DF1_OPT_LOW_LATENCY,
	DF1_OPT_PLC5_REFUSE_LARGE,
	DF1_OPT_ROUTE,
	DF1_OPT_APP_RETRIES,
	DF1_OPT_RADIO_DUP_DETECT,
	DF1_OPT_RADIO_RTS_CTS,
	DF1_OPT_RTS_SEND_DELAY_MS,
	DF1_OPT_RTS_OFF_DELAY_MS,
	DF1_OPT_DCD_WAIT_MS,
};
int df1_new(df1_t **out);
void df1_free(df1_t *h);
int df1_set_serial(df1_t *h, int baud, int data_bits, char parity , int stop_bits);
int df1_set_handshake(df1_t *h, _Bool rts_cts);
int df1_set_duplex(df1_t *h, enum df1_duplex d);
int df1_set_check(df1_t *h, enum df1_check c);
int df1_set_station(df1_t *h, int own_station);
int df1_set_plc(df1_t *h, enum df1_plc plc);
int df1_set_timeout_ms(df1_t *h, int ms);
int df1_set_cmd_timeout_ms(df1_t *h, int ms);
int df1_set_retries(df1_t *h, int nak_retries, int enq_retries);
int df1_set_tx_delay_ms(df1_t *h, int ms);
int df1_set_option(df1_t *h, enum df1_option opt, int value);
int df1_recv_raw(df1_t *h, uint8_t *buf, size_t cap, int timeout_ms, struct timespec *when);
int df1_port_fd(const df1_t *h);
const char *df1_port_note(const df1_t *h);
int df1_get_option(const df1_t *h, enum df1_option opt);
int df1_set_forward(df1_t *h, const uint8_t *table);
int df1_get_forward(const df1_t *h, uint8_t *table);
int df1_forward_parse(const char *list, uint8_t *table);
struct df1_radio_stats {
	uint64_t sent, received, relayed, duplicates, bad_packets, undelivered;
};
int df1_radio_stats(const df1_t *h, struct df1_radio_stats *out);
typedef void (*df1_log_fn)(void *user, int catalog_id, enum df1_severity sev, const char *text);
void df1_set_log(df1_t *h, df1_log_fn fn, void *user);
enum df1_dir {
	DF1_DIR_RX = 0,
	DF1_DIR_TX = 1
};
typedef void (*df1_trace_fn)(void *user, enum df1_dir dir, const uint8_t *bytes, size_t n, uint64_t t_us);
void df1_set_trace(df1_t *h, df1_trace_fn fn, void *user);
int df1_open(df1_t *h, const char *target);
int df1_open_fd(df1_t *h, int fd, _Bool take_ownership);
void df1_close(df1_t *h);
_Bool df1_is_open(const df1_t *h);
int df1_set_cancel_fd(df1_t *h, int fd);
struct df1_error_detail {
	int code;
	int sys_errno;
	int station;
	uint8_t sts;
	uint8_t ext_sts;
	_Bool has_ext_sts;
	int catalog_id;
	char message[160];
	char address[64];
};
const struct df1_error_detail *df1_last_error(const df1_t *h);
int df1_read(df1_t *h, int station, const char *addr, struct df1_value *out, size_t n);
int df1_write(df1_t *h, int station, const char *addr, const struct df1_value *in, size_t n);
int df1_read_addr(df1_t *h, int station, const struct df1_addr *a, struct df1_value *out, size_t n);
int df1_write_addr(df1_t *h, int station, const struct df1_addr *a, const struct df1_value *in, size_t n);
int df1_read_int16(df1_t *h, int station, const char *addr, int16_t *out, size_t n);
int df1_read_int32(df1_t *h, int station, const char *addr, int32_t *out, size_t n);
int df1_read_float(df1_t *h, int station, const char *addr, float *out, size_t n);
int df1_read_bit(df1_t *h, int station, const char *addr, _Bool *out);
int df1_read_string(df1_t *h, int station, const char *addr, char *out, size_t cap);
int df1_read_tcr(df1_t *h, int station, const char *addr, struct df1_tcr *out, size_t n);
int df1_write_int16(df1_t *h, int station, const char *addr, const int16_t *in, size_t n);
int df1_write_int32(df1_t *h, int station, const char *addr, const int32_t *in, size_t n);
int df1_write_float(df1_t *h, int station, const char *addr, const float *in, size_t n);
int df1_write_bit(df1_t *h, int station, const char *addr, _Bool value);
int df1_write_string(df1_t *h, int station, const char *addr, const char *text);
int df1_write_tcr(df1_t *h, int station, const char *addr, const struct df1_tcr *in, size_t n);
int df1_read_raw(df1_t *h, int station, const char *addr, uint8_t *buf, size_t nbytes);
int df1_write_raw(df1_t *h, int station, const char *addr, const uint8_t *buf, size_t nbytes);
int df1_command(df1_t *h, int station, uint8_t cmd, const uint8_t *body, size_t body_len, uint8_t *reply, size_t reply_cap);
struct df1_diag_status {
	uint8_t type_code;
	char name[32];
	char series;
	int revision;
	int mode;
	char mode_text[24];
	char bulletin[16];
	uint8_t raw[64];
	size_t raw_len;
};
int df1_diag_status(df1_t *h, int station, struct df1_diag_status *out);
int df1_change_mode(df1_t *h, int station, int mode);
int df1_counter(const df1_t *h, int id, uint64_t *value);
void df1_counters_reset(df1_t *h);
int df1_station_active(const df1_t *h, int station);
int df1_station_set_active(df1_t *h, int station, _Bool active);
enum df1_sym {
	DF1_SYM_NONE = 0,
	DF1_SYM_ACK,
	DF1_SYM_NAK,
	DF1_SYM_ENQ,
	DF1_SYM_EOT,
	DF1_SYM_POLL,
	DF1_SYM_FRAME,
	DF1_SYM_ERROR,
};
struct df1_symbol {
	enum df1_sym kind;
	_Bool master_msg;
	_Bool has_station;
	uint8_t station;
	const uint8_t *data;
	size_t len;
	enum df1_check check;
	_Bool check_ok;
	uint16_t check_expected, check_actual;
	_Bool embedded;
	int error;
	uint8_t bad_byte;
	size_t wire_len;
};
struct df1_decoder;
int df1_decoder_new(struct df1_decoder **out, enum df1_check check);
void df1_decoder_free(struct df1_decoder *d);
void df1_decoder_reset(struct df1_decoder *d);
int df1_decoder_set_half_duplex(struct df1_decoder *d, _Bool on);
int df1_decoder_set_duplex_auto(struct df1_decoder *d, _Bool on);
int df1_decoder_set_option(struct df1_decoder *d, enum df1_option opt, int value);
size_t df1_decoder_feed(struct df1_decoder *d, const uint8_t *in, size_t n, struct df1_symbol *sym);
_Bool df1_decoder_dle_pending(const struct df1_decoder *d);
struct df1_msg {
	uint8_t dst, src, cmd, sts, fnc;
	uint16_t tns;
	_Bool is_reply;
	_Bool has_fnc;
	_Bool has_ext_sts;
	uint8_t ext_sts;
	const char *name;
	_Bool has_addr;
	struct df1_addr addr;
	int size;
	const uint8_t *data;
	size_t data_len;
};
int df1_msg_decode(const uint8_t *app, size_t n, struct df1_msg *m);
int df1_values_decode(enum df1_file_type t, const uint8_t *bytes, size_t n, struct df1_value *out, size_t max);
enum df1_mode {
	DF1_MODE_MASTER = 0,
	DF1_MODE_SLAVE = 1,
	DF1_MODE_PEER = 2
};
struct df1_net_config {
	int station;
	enum df1_mode mode;
	enum df1_plc plc;
	enum df1_check check;
	int nak_retries;
	int enq_retries;
	int cmd_timeout_ms;
	char port[256];
	int baud;
	int data_bits;
	int stop_bits;
	char parity;
	int timeout_ms;
	int tx_delay_ms;
	_Bool handshake;
	_Bool duplex_half;
	_Bool port_given;
	_Bool radio;
	_Bool forward_set;
	uint8_t forward[32];
};
struct df1_config_issue {
	int catalog_id;
	int item;
	int line;
	char text[200];
};
typedef void (*df1_config_issue_fn)(void *user, const struct df1_config_issue *issue);
void df1_net_config_defaults(struct df1_net_config *c);
int df1_net_config_load(const char *path, struct df1_net_config *c, df1_config_issue_fn fn, void *user);
int df1_apply_net_config(df1_t *h, const struct df1_net_config *c);
enum df1_access {
	DF1_ACCESS_READ = 1,
	DF1_ACCESS_WRITE = 2,
	DF1_ACCESS_READWRITE = 3,
	DF1_ACCESS_RECEIVE = 4
};
struct df1_tag_config {
	char name[64];
	enum df1_access access;
	char type[16];
	int station;
	enum df1_plc plc;
	struct df1_addr addr;
	int count;
	int scan_ms;
};
typedef int (*df1_tag_row_fn)(void *user, const struct df1_tag_config *tag);
int df1_map_load(const char *path, _Bool strict, df1_tag_row_fn row_fn, df1_config_issue_fn issue_fn, void *user);
enum df1_quality {
	DF1_QUALITY_BAD = 0,
	DF1_QUALITY_UNCERTAIN = 1,
	DF1_QUALITY_GOOD = 2,
};
enum df1_quality_reason {
	DF1_REASON_NONE = 0,
	DF1_REASON_NOT_YET_READ,
	DF1_REASON_COMM_FAILURE,
	DF1_REASON_STATION_OFFLINE,
	DF1_REASON_PLC_ERROR,
	DF1_REASON_CONFIG,
};
const char *df1_quality_name(enum df1_quality q);
const char *df1_reason_name(enum df1_quality_reason r);
struct df1_tag_state {
	int id;
	const struct df1_tag_config *config;
	size_t count;
	const struct df1_value *values;
	struct df1_value value;
	_Bool has_value;
	enum df1_quality quality;
	enum df1_quality_reason reason;
	int64_t last_good_ms;
	int64_t last_good_wall_ms;
	int64_t age_ms;
	int last_error;
	uint8_t sts, ext_sts;
	uint64_t reads;
};
int df1_tag_add(df1_t *h, const struct df1_tag_config *c);
int df1_tag_value_kind(const struct df1_tag_config *c);
int df1_tag_load_map(df1_t *h, const char *path, _Bool strict, df1_config_issue_fn issue_fn, void *user);
int df1_tag_count(const df1_t *h);
int df1_tag_find(const df1_t *h, const char *name);
int df1_tag_get(const df1_t *h, int id, struct df1_tag_state *st);
typedef void (*df1_tag_fn)(void *user, int id, const struct df1_tag_state *st);
int df1_set_tag_callback(df1_t *h, df1_tag_fn fn, void *user);
typedef void (*df1_write_done_fn)(void *user, int tag_id, int write_id, int result);
int df1_tag_write(df1_t *h, int id, const struct df1_value *v, size_t n, df1_write_done_fn done, void *user);
int df1_poll(df1_t *h, int timeout_ms);
int df1_poll_next_ms(const df1_t *h);
int df1_poll_fd(df1_t *h);
typedef void (*df1_pccc_done_fn)(void *user, int result, const uint8_t *reply, size_t n);
int df1_poll_submit_pccc(df1_t *h, int station, const uint8_t *pccc, size_t n, df1_pccc_done_fn done, void *user);
int df1_poll_cancel_queued(df1_t *h);
int df1_poll_set_watchdog(df1_t *h, int watchdog_ms, int absolute_retries);
int df1_poll_set_station_range(df1_t *h, int lo, int hi);
struct df1_poll_stats {
	uint64_t scans;
	int64_t last_scan_ms;
	int64_t max_scan_ms;
	unsigned last_scan_transactions;
	uint64_t transactions;
	uint64_t reads, read_failures;
	uint64_t probes, probe_failures;
	uint64_t writes, write_failures;
	uint64_t retries;
	uint64_t splits;
	unsigned tags, blocks;
	unsigned stations_offline;
	unsigned writes_queued;
};
int df1_poll_stats(const df1_t *h, struct df1_poll_stats *out);
enum df1_station_state {
	DF1_STATION_UNKNOWN = 0,
	DF1_STATION_OK,
	DF1_STATION_FAILING,
	DF1_STATION_OFFLINE,
	DF1_STATION_ABSENT,
};
struct df1_station_health {
	int station;
	enum df1_station_state state;
	int tags, blocks;
	int64_t last_good_ms;
	int64_t last_attempt_ms;
	int64_t next_retry_ms;
	int consecutive_failures;
	uint64_t attempts, failures;
	int last_error;
};
const char *df1_station_state_name(enum df1_station_state s);
struct df1_read_req {
	const char *text;
	struct df1_addr addr;
	size_t count;
	struct df1_value *values;
	int result;
};
int df1_read_multi(df1_t *h, int station, struct df1_read_req *reqs, size_t n, unsigned flags, unsigned *reads);
int df1_packet_max(enum df1_plc plc, _Bool write);
int df1_station_health(const df1_t *h, int station, struct df1_station_health *out);
int df1_poll_station(const df1_t *h, int station, struct df1_station_health *out) ;
struct df1_server_ops {
	int (*read)(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes);
	int (*write)(void *user, int station, const struct df1_addr *a, const uint8_t *buf, const uint8_t *mask, size_t nbytes);
	int (*diag_status)(void *user, int station, uint8_t *buf, size_t cap);
	int (*change_mode)(void *user, int station, int mode);
	int (*command)(void *user, int station, const struct df1_msg *cmd, uint8_t *reply, size_t cap);
};
int df1_server_add_station(df1_t *h, int station);
int df1_serve(df1_t *h, const struct df1_server_ops *ops, void *user, int timeout_ms);
enum df1_fault {
	DF1_FAULT_DROP_ACK = 1,
	DF1_FAULT_CORRUPT_REPLY,
	DF1_FAULT_NAK_COMMAND,
	DF1_FAULT_DELAY_REPLY,
	DF1_FAULT_SILENT_STATION,
	DF1_FAULT_STALE_REPLY,
	DF1_FAULT_NOISE,
};
int df1_server_set_fault(df1_t *h, enum df1_fault f, int per_mille, int value);
void df1_server_set_seed(df1_t *h, uint64_t seed);
int df1_server_set_max_queue(df1_t *h, int max_queue);
int df1_set_responder(df1_t *h, const struct df1_server_ops *ops, void *user);
int df1_server_source(const df1_t *h);
struct df1_route_stats {
	uint64_t executed, routed, broadcasts, route_replies, undeliverable;
};
int df1_route_stats(const df1_t *h, struct df1_route_stats *out);
int df1_set_line_baud(df1_t *h, int baud);
int df1_serve_pccc(df1_t *h, const struct df1_server_ops *ops, void *user, int station, const uint8_t *pccc, size_t n, uint8_t *reply, size_t cap);
struct df1_table;
int df1_table_new(struct df1_table **out, enum df1_plc plc);
void df1_table_free(struct df1_table *t);
int df1_table_clone(struct df1_table **out, const struct df1_table *t);
int df1_table_add_file(struct df1_table *t, enum df1_file_type type, int number, int elements);
int df1_table_add_default_files(struct df1_table *t);
int df1_table_file(const struct df1_table *t, int number, enum df1_file_type *type);
int df1_table_read(struct df1_table *t, const char *addr, struct df1_value *out, size_t n);
int df1_table_write(struct df1_table *t, const char *addr, const struct df1_value *in, size_t n);
int df1_table_read_addr(struct df1_table *t, const struct df1_addr *a, struct df1_value *out, size_t n);
int df1_table_write_addr(struct df1_table *t, const struct df1_addr *a, const struct df1_value *in, size_t n);
int df1_table_set_processor(struct df1_table *t, const char *name);
int df1_table_mode(const struct df1_table *t);
int df1_table_set_mode(struct df1_table *t, int mode);
int df1_table_load(struct df1_table *t, const char *path);
int df1_table_save(struct df1_table *t, const char *path);
const char *df1_table_error_text(const struct df1_table *t);
const struct df1_server_ops *df1_table_server_ops(const struct df1_table *t);
typedef struct df1_eip_server df1_eip_server_t;
struct df1_eip_identity {
	uint16_t vendor_id, device_type, product_code;
	uint8_t rev_major, rev_minor;
	uint16_t status;
	uint32_t serial;
	char product_name[33];
};
struct df1_eip_server_config {
	const char *listen;
	const char *allow;
	_Bool read_only;
	int max_clients;
	struct df1_eip_identity identity;
};
typedef void (*df1_eip_pccc_fn)(void *user, df1_eip_server_t *s, uint32_t request, int station, const uint8_t *pccc, size_t n);
int df1_eip_server_new(df1_eip_server_t **out, const struct df1_eip_server_config *c, df1_eip_pccc_fn fn, void *user);
const char *df1_eip_server_address(const df1_eip_server_t *s);
int df1_eip_server_fd(const df1_eip_server_t *s);
int df1_eip_server_process(df1_eip_server_t *s);
int df1_eip_server_reply(df1_eip_server_t *s, uint32_t request, const uint8_t *pccc_reply, size_t n);
int df1_eip_server_fail(df1_eip_server_t *s, uint32_t request, int cip_status);
struct df1_eip_server_stats {
	uint64_t sessions;
	uint64_t sessions_open;
	uint64_t requests;
	uint64_t errors;
	uint64_t refused_clients;
	uint64_t read_only_refusals;
};
void df1_eip_server_stats(const df1_eip_server_t *s, struct df1_eip_server_stats *st);
enum df1_eip_close_reason {
	DF1_EIP_CLOSE_NO_SESSION,
	DF1_EIP_CLOSE_IDLE,
	DF1_EIP_CLOSE_EVICTED
};
typedef void (*df1_eip_close_fn)(void *user, const char *peer, enum df1_eip_close_reason why);
struct df1_eip_server_limits {
	int register_ms;
	int idle_ms;
	_Bool no_evict;
	df1_eip_close_fn on_close;
	void *user;
};
int df1_eip_server_set_limits(df1_eip_server_t *s, const struct df1_eip_server_limits *l);
struct df1_eip_server_closes {
	uint64_t no_session, idle, evicted;
};
void df1_eip_server_closes(const df1_eip_server_t *s, struct df1_eip_server_closes *c);
int df1_eip_server_set_identity(df1_eip_server_t *s, const struct df1_eip_identity *id);
const char *df1_eip_server_error(const df1_eip_server_t *s);
void df1_eip_server_free(df1_eip_server_t *s);
struct df1_eip_device {
	char address[64];
	uint16_t vendor_id, device_type, product_code;
	uint8_t rev_major, rev_minor;
	uint16_t status;
	uint32_t serial;
	char product_name[33];
	uint8_t state;
};
typedef void (*df1_eip_device_fn)(void *user, const struct df1_eip_device *d);
int df1_eip_list_identity(df1_t *h, const char *target, int timeout_ms, df1_eip_device_fn fn, void *user);
struct df1_discover_result {
	int station;
	_Bool answered;
	_Bool identified;
	int error;
	uint64_t rtt_us;
	struct df1_diag_status status;
};
typedef int (*df1_discover_fn)(void *user, const struct df1_discover_result *r);
int df1_discover(df1_t *h, int lo, int hi, df1_discover_fn fn, void *user);
int df1_echo(df1_t *h, int station, const uint8_t *data, size_t n);
int df1_link_test(df1_t *h, int station);
enum df1_probe_stage {
	DF1_PROBE_LINK = 1,
	DF1_PROBE_CHECK = 2,
	DF1_PROBE_IDENTITY = 3,
};
struct df1_line_settings {
	int baud, data_bits, stop_bits;
	char parity;
	enum df1_duplex duplex;
	enum df1_check check;
	_Bool hd_bcc_stx;
	int station;
};
struct df1_probe_attempt {
	enum df1_probe_stage stage;
	struct df1_line_settings tried;
	const char *what;
	_Bool answered;
	int error;
};
typedef int (*df1_probe_fn)(void *user, const struct df1_probe_attempt *a);
struct df1_probe_result {
	struct df1_line_settings found;
	_Bool identified;
	struct df1_diag_status status;
	int nstations;
	uint8_t stations[255];
	int attempts;
	int64_t elapsed_ms;
};
int df1_probe_line(df1_t *h, int lo, int hi, df1_probe_fn fn, void *user, struct df1_probe_result *out);
int64_t df1_probe_line_bound_ms(const df1_t *h, int lo, int hi);
