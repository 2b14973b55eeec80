/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip - EtherNet/IP encapsulation, common packet format (CPF) and the CIP
 * messages libdf1 needs to carry PCCC (pure: no I/O, no clock, no allocation).
 * Both directions: what a client builds a server parses and the reverse.
 * The facts and their sources are in df1-eip(7).
 *
 * Everything on the wire is little-endian except the sockaddr of a
 * ListIdentity item (network order, as struct sockaddr_in).
 *
 * Parsers return 0 or DF1_E_TOO_SHORT (input ends inside a field),
 * DF1_E_TOO_LONG (a length field says more than the input holds or than a
 * limit), DF1_E_INVAL (a value the format does not allow). Parsed byte
 * ranges (const uint8_t *) point into the caller's input. Builders return the
 * bytes written or DF1_E_NOSPACE / DF1_E_INVAL.
 */
#ifndef LIBDF1_EIP_H
#define LIBDF1_EIP_H

#include "df1.h"

#define EIP_PORT 44818
#define EIP_HDR_LEN 24
#define EIP_DATA_MAX 65511            /* the header's length field: 65535 - 24 */
#define EIP_PROTOCOL_VERSION 1        /* RegisterSession and ListIdentity */

/* Encapsulation commands */
#define EIP_CMD_NOP                0x0000
#define EIP_CMD_LIST_SERVICES      0x0004
#define EIP_CMD_LIST_IDENTITY      0x0063
#define EIP_CMD_LIST_INTERFACES    0x0064
#define EIP_CMD_REGISTER_SESSION   0x0065
#define EIP_CMD_UNREGISTER_SESSION 0x0066
#define EIP_CMD_SEND_RR_DATA       0x006F
#define EIP_CMD_SEND_UNIT_DATA     0x0070

/* Encapsulation status */
#define EIP_ST_SUCCESS             0x0000
#define EIP_ST_INVALID_COMMAND     0x0001
#define EIP_ST_NO_MEMORY           0x0002
#define EIP_ST_INCORRECT_DATA      0x0003
#define EIP_ST_INVALID_SESSION     0x0064
#define EIP_ST_INVALID_LENGTH      0x0065
#define EIP_ST_UNSUPPORTED_VERSION 0x0069

/* Common packet format item type IDs */
#define EIP_ITEM_NULL              0x0000
#define EIP_ITEM_LIST_IDENTITY     0x000C
#define EIP_ITEM_CONNECTED_ADDR    0x00A1
#define EIP_ITEM_CONNECTED_DATA    0x00B1
#define EIP_ITEM_UNCONNECTED_DATA  0x00B2
#define EIP_ITEM_LIST_SERVICES     0x0100
#define EIP_ITEM_SOCKADDR_OT       0x8000
#define EIP_ITEM_SOCKADDR_TO       0x8001
#define EIP_ITEM_SEQUENCED_ADDR    0x8002
#define EIP_CPF_ITEMS_MAX 4

/* ListServices capability flags */
#define EIP_SERVICE_CIP_TCP  0x0020   /* CIP encapsulation over TCP */
#define EIP_SERVICE_CIP_UDP  0x0100   /* CIP class 0/1 over UDP */

/* CIP services */
#define CIP_SVC_GET_ATTRIBUTES_ALL  0x01
#define CIP_SVC_GET_ATTRIBUTE_SINGLE 0x0E
#define CIP_SVC_EXECUTE_PCCC        0x4B
#define CIP_SVC_FORWARD_CLOSE       0x4E
#define CIP_SVC_UNCONNECTED_SEND    0x52
#define CIP_SVC_FORWARD_OPEN        0x54
#define CIP_SVC_LARGE_FORWARD_OPEN  0x5B
#define CIP_SVC_REPLY               0x80   /* reply service = request | 0x80 */

/* CIP classes */
#define CIP_CLASS_IDENTITY          0x01
#define CIP_CLASS_MESSAGE_ROUTER    0x02
#define CIP_CLASS_CONNECTION_MANAGER 0x06
#define CIP_CLASS_PCCC              0x67

/* CIP general status */
#define CIP_ST_SUCCESS              0x00
#define CIP_ST_CONNECTION_FAILURE   0x01
#define CIP_ST_RESOURCE_UNAVAILABLE 0x02
#define CIP_ST_INVALID_PARAMETER    0x03
#define CIP_ST_PATH_SEGMENT         0x04
#define CIP_ST_PATH_DESTINATION     0x05
#define CIP_ST_SERVICE_NOT_SUPPORTED 0x08
#define CIP_ST_PRIVILEGE_VIOLATION  0x0F
#define CIP_ST_REPLY_TOO_LARGE      0x11
#define CIP_ST_NOT_ENOUGH_DATA      0x13
#define CIP_ST_ATTRIBUTE_NOT_SUPPORTED 0x14
#define CIP_ST_TOO_MUCH_DATA        0x15
#define CIP_ST_OBJECT_DOES_NOT_EXIST 0x16
#define CIP_ST_PATH_SIZE_INVALID    0x26

/* Connection Manager extended status (with general status 01) */
#define CIP_EXT_DUPLICATE_FORWARD_OPEN 0x0100
#define CIP_EXT_CONNECTION_NOT_FOUND   0x0107   /* Forward Close: no such connection */
#define CIP_EXT_NO_MORE_CONNECTIONS    0x0113
#define CIP_EXT_UNCONNECTED_TIMEOUT    0x0204   /* the target did not answer in time */
#define CIP_EXT_INVALID_SEGMENT        0x0315   /* invalid segment in connection path */
#define CIP_EXT_INVALID_PORT           0x0311   /* route path: no such port */
#define CIP_EXT_INVALID_LINK           0x0312   /* route path: invalid link address */

/* CIP EPATH segments this codec reads and writes */
#define CIP_SEG_CLASS8      0x20
#define CIP_SEG_CLASS16     0x21
#define CIP_SEG_INSTANCE8   0x24
#define CIP_SEG_INSTANCE16  0x25
#define CIP_SEG_POINT8      0x2C     /* connection point */
#define CIP_SEG_POINT16     0x2D
#define CIP_SEG_ATTRIBUTE8  0x30
#define CIP_SEG_ATTRIBUTE16 0x31
#define CIP_SEG_KEY         0x34     /* electronic key (format 4: 10 bytes) */
#define CIP_SEG_PORT_EXT    0x10     /* port segment flag: link address size follows */
#define CIP_SEG_DATA_SIMPLE 0x80
#define CIP_PATH_MAX 64              /* bytes of an EPATH we build or keep */

/* PCCC over CIP: the bridge's own port and the DF1 port of a route path */
#define EIP_ROUTE_PORT_SELF 1
#define EIP_ROUTE_PORT_DF1  2
#define EIP_REQID_MAX 32             /* requester ID bytes kept (its length byte included) */

/* ------------------------------------------------------------------------
 * Encapsulation header
 * ------------------------------------------------------------------------ */
struct eip_hdr {
	uint16_t command;
	uint16_t length;         /* bytes of data after the header */
	uint32_t session;
	uint32_t status;
	uint8_t context[8];      /* sender context: the reply echoes it */
	uint32_t options;
};

/* Parse the 24-byte header of buf[0..n). DF1_E_TOO_SHORT if n < 24. */
int eip_hdr_parse(struct eip_hdr *h, const uint8_t *buf, size_t n);
/* Write h (its length as given) at out. Returns 24 or DF1_E_NOSPACE. */
int eip_hdr_build(uint8_t *out, size_t cap, const struct eip_hdr *h);
/* The whole message's length from the header at buf[0..n) (n >= 24), or 0 if
 * n < 24 (need more). */
size_t eip_msg_len(const uint8_t *buf, size_t n);

/* RegisterSession data: protocol version, option flags. */
int eip_register_parse(uint16_t *version, uint16_t *options, const uint8_t *data, size_t n);
int eip_register_build(uint8_t *out, size_t cap, uint16_t version, uint16_t options);

/* ------------------------------------------------------------------------
 * Common packet format and the SendRRData / SendUnitData data
 * ------------------------------------------------------------------------ */
struct eip_item {
	uint16_t type;
	uint16_t len;
	const uint8_t *data;
};

struct eip_cpf {
	uint16_t count;
	struct eip_item item[EIP_CPF_ITEMS_MAX];
};

/* Item count and items of buf[0..n) (no bytes may follow the last item).
 * More than EIP_CPF_ITEMS_MAX items: DF1_E_TOO_LONG. */
int eip_cpf_parse(struct eip_cpf *c, const uint8_t *buf, size_t n);
/* SendRRData / SendUnitData data: interface handle (4, must be 0), timeout (2), CPF. */
int eip_rr_parse(uint16_t *timeout, struct eip_cpf *c, const uint8_t *data, size_t n);

/* What travels in a SendRRData (connected false: null address + B2) or a
 * SendUnitData (connected: A1 connection id + B1 sequence count + data). */
struct eip_packet {
	bool connected;
	uint32_t conn_id;
	uint16_t seq;
	const uint8_t *data;    /* the CIP message */
	size_t len;
};

/* The CIP message of a parsed CPF: the two items a packet holds (address first;
 * sockaddr items after them are allowed and ignored). DF1_E_INVAL when the
 * items are not null+B2 or A1+B1, DF1_E_TOO_SHORT when B1 has no sequence count
 * or A1 is not 4 bytes. */
int eip_packet_parse(struct eip_packet *p, const struct eip_cpf *c);
/* A whole message: header (command SendRRData or SendUnitData by p->connected,
 * session, context, status 0, options 0), interface handle 0, timeout, CPF.
 * p->data may not overlap out. Returns its total length. */
int eip_packet_build(uint8_t *out, size_t cap, uint32_t session, const uint8_t context[8],
                     uint16_t timeout, const struct eip_packet *p);

/* ------------------------------------------------------------------------
 * ListIdentity and ListServices
 * ------------------------------------------------------------------------ */
struct eip_identity {
	uint16_t encap_version;
	uint16_t sin_family;     /* host order here, network order on the wire */
	uint16_t sin_port;
	uint32_t sin_addr;
	uint16_t vendor_id, device_type, product_code;
	uint8_t rev_major, rev_minor;
	uint16_t status;
	uint32_t serial;
	char product_name[33];   /* short string: up to 32 characters */
	uint8_t state;
};

/* The reply data of ListIdentity: item count 1, item 0x0C. */
int eip_identity_build(uint8_t *out, size_t cap, const struct eip_identity *id);
/* One item 0x0C's data (after type and length). */
int eip_identity_parse(struct eip_identity *id, const uint8_t *data, size_t n);
/* The reply data of ListServices: item count 1, item 0x0100 "Communications". */
int eip_services_build(uint8_t *out, size_t cap, uint16_t flags);

/* ------------------------------------------------------------------------
 * CIP: EPATH, message router request and response
 * ------------------------------------------------------------------------ */
#define CIP_NONE (-1)

/* The parts of an EPATH this codec knows; absent ones are CIP_NONE. A port
 * segment's link address is kept when it is one byte (a DF1 station). */
struct cip_path {
	int port, link;
	int class_id, instance, attribute, point;
};

void cip_path_init(struct cip_path *p);
/* Segments of path[0..n): DF1_E_TOO_SHORT a segment cut off, DF1_E_INVAL a
 * segment type this codec does not know or a second port segment. Electronic
 * keys (0x34, format 4) and simple data segments are skipped. */
int cip_path_parse(struct cip_path *p, const uint8_t *path, size_t n);
/* Port (if any), class, instance, attribute, point (those set) with 8-bit
 * segments where the value fits, padded 16-bit ones where not. Bytes (even). */
int cip_path_build(uint8_t *out, size_t cap, const struct cip_path *p);

struct cip_req {
	uint8_t service;
	const uint8_t *path;     /* path_words * 2 bytes */
	size_t path_len;
	const uint8_t *data;
	size_t len;
};

/* DF1_E_TOO_SHORT: fewer than 2 bytes or the path size runs past the end. */
int cip_req_parse(struct cip_req *r, const uint8_t *buf, size_t n);
int cip_req_build(uint8_t *out, size_t cap, uint8_t service, const struct cip_path *p,
                  const uint8_t *data, size_t n);

struct cip_resp {
	uint8_t service;         /* request service | 0x80 */
	uint8_t status;
	uint8_t ext_words;
	uint16_t ext0;           /* the first additional status word (0 if none) */
	const uint8_t *data;
	size_t len;
};

int cip_resp_parse(struct cip_resp *r, const uint8_t *buf, size_t n);
/* service (the request's; | 0x80 is added), status, ext_words words of ext, data. */
int cip_resp_build(uint8_t *out, size_t cap, uint8_t service, uint8_t status, const uint16_t *ext,
                   size_t ext_words, const uint8_t *data, size_t n);

/* ------------------------------------------------------------------------
 * Execute PCCC (class 0x67 instance 1, service 0x4B; reply 0xCB)
 * ------------------------------------------------------------------------ */
struct eip_pccc {
	const uint8_t *reqid;    /* requester ID: its length byte, vendor(2), serial(4), more */
	size_t reqid_len;
	const uint8_t *pccc;     /* CMD STS TNS(2) [FNC] data */
	size_t len;
};

/* The request data (after the CIP path). DF1_E_INVAL a requester ID length
 * under 7, DF1_E_TOO_SHORT no room for it or for CMD STS TNS. */
int eip_pccc_parse(struct eip_pccc *p, const uint8_t *data, size_t n);
/* Requester ID of 7 bytes (vendor, serial) then the PCCC bytes. */
int eip_pccc_build(uint8_t *out, size_t cap, uint16_t vendor, uint32_t serial, const uint8_t *pccc,
                   size_t n);
/* A whole Execute PCCC request: service, path class 0x67 instance 1, the data. */
int eip_pccc_request_build(uint8_t *out, size_t cap, uint16_t vendor, uint32_t serial,
                           const uint8_t *pccc, size_t n);

/* ------------------------------------------------------------------------
 * Connection Manager (class 0x06 instance 1)
 * ------------------------------------------------------------------------ */
struct cip_fwd_open {
	bool large;                  /* Large Forward Open: 32-bit network parameters */
	uint8_t tick, timeout_ticks;
	uint32_t ot_conn_id, to_conn_id;
	uint16_t conn_serial, vendor_id;
	uint32_t orig_serial;
	uint8_t timeout_mult;
	uint32_t ot_rpi, ot_params, to_rpi, to_params;
	uint8_t transport;
	const uint8_t *path;         /* connection path */
	size_t path_len;
};

/* The request data of a (Large) Forward Open; large tells which layout. */
int cip_fwd_open_parse(struct cip_fwd_open *f, bool large, const uint8_t *data, size_t n);
/* The whole request (service, path 06/01, data); f->path has f->path_len bytes (even). */
int cip_fwd_open_build(uint8_t *out, size_t cap, const struct cip_fwd_open *f);
/* Success reply data: the connection ids (the target's choice of O->T), serials,
 * APIs = the RPIs, no application reply. */
int cip_fwd_open_reply_build(uint8_t *out, size_t cap, const struct cip_fwd_open *f);
int cip_fwd_open_reply_parse(struct cip_fwd_open *f, const uint8_t *data, size_t n);
/* Failure reply data (with status 01 and an extended status): serials and
 * remaining path size 0. */
int cip_fwd_fail_build(uint8_t *out, size_t cap, uint16_t conn_serial, uint16_t vendor_id,
                       uint32_t orig_serial);

struct cip_fwd_close {
	uint8_t tick, timeout_ticks;
	uint16_t conn_serial, vendor_id;
	uint32_t orig_serial;
	const uint8_t *path;
	size_t path_len;
};

int cip_fwd_close_parse(struct cip_fwd_close *f, const uint8_t *data, size_t n);
int cip_fwd_close_build(uint8_t *out, size_t cap, const struct cip_fwd_close *f);
/* Reply data (success and failure alike): serials, application reply size 0. */
int cip_fwd_close_reply_build(uint8_t *out, size_t cap, const struct cip_fwd_close *f);

struct cip_unconnected {
	uint8_t tick, timeout_ticks;
	const uint8_t *req;          /* the embedded message request */
	size_t req_len;
	const uint8_t *route;        /* route path */
	size_t route_len;
};

/* The longest embedded request an Unconnected Send may carry (bytes): CIP's
 * size for an unconnected message (man/man7/df1-eip.7 CONNECTION MANAGER,
 * Unconnected Send; doc/PROTOCOL.md names that page for the EtherNet/IP facts).
 * A PCCC command in Execute PCCC, with the longest requester ID kept, needs
 * 6 + EIP_REQID_MAX + 264 = 302. */
#define CIP_UNCONNECTED_REQ_MAX 504

/* DF1_E_TOO_SHORT: cut; DF1_E_TOO_LONG: bytes after the route path, or an
 * embedded request over CIP_UNCONNECTED_REQ_MAX (refused whatever follows). */
int cip_unconnected_parse(struct cip_unconnected *u, const uint8_t *data, size_t n);
/* The whole request: service 0x52, path 06/01, the embedded request, pad, route.
 * DF1_E_INVAL for a request over CIP_UNCONNECTED_REQ_MAX (no target takes it). */
int cip_unconnected_build(uint8_t *out, size_t cap, uint8_t tick, uint8_t timeout_ticks,
                          const uint8_t *req, size_t req_len, const uint8_t *route, size_t route_len);

/* ------------------------------------------------------------------------
 * Identity object (class 0x01 instance 1)
 * ------------------------------------------------------------------------ */
/* Get_Attributes_All reply data: vendor, device type, product code, revision,
 * status, serial, product name (attributes 1-7). */
int cip_identity_all_build(uint8_t *out, size_t cap, const struct eip_identity *id);
/* Get_Attribute_Single reply data for attribute 1-7; DF1_E_NOTSUP another. */
int cip_identity_attr_build(uint8_t *out, size_t cap, const struct eip_identity *id, int attribute);

#endif
