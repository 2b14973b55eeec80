/* SPDX-License-Identifier: MPL-2.0 */
/*
 * eip.c - EtherNet/IP encapsulation, CPF and CIP codec (see eip.h; the layouts
 * and their sources are in df1-eip(7)). Pure: no I/O, clock or allocation.
 */
#include "eip/eip_codec.h"

#include <string.h>

#include "proto/value.h"

static void put_be16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)(v >> 8);
	p[1] = (uint8_t)v;
}

static uint16_t be16(const uint8_t *p)
{
	return (uint16_t)(p[0] << 8 | p[1]);
}

/* ------------------------------------------------------------------------
 * Encapsulation header
 * ------------------------------------------------------------------------ */

int eip_hdr_parse(struct eip_hdr *h, const uint8_t *buf, size_t n)
{
	if (!h || !buf)
		return DF1_E_INVAL;
	if (n < EIP_HDR_LEN)
		return DF1_E_TOO_SHORT;
	h->command = le16(buf);
	h->length = le16(buf + 2);
	h->session = le32(buf + 4);
	h->status = le32(buf + 8);
	memcpy(h->context, buf + 12, 8);
	h->options = le32(buf + 20);
	return 0;
}

int eip_hdr_build(uint8_t *out, size_t cap, const struct eip_hdr *h)
{
	if (!out || !h)
		return DF1_E_INVAL;
	if (cap < EIP_HDR_LEN)
		return DF1_E_NOSPACE;
	put_le16(out, h->command);
	put_le16(out + 2, h->length);
	put_le32(out + 4, h->session);
	put_le32(out + 8, h->status);
	memcpy(out + 12, h->context, 8);
	put_le32(out + 20, h->options);
	return EIP_HDR_LEN;
}

size_t eip_msg_len(const uint8_t *buf, size_t n)
{
	if (!buf || n < EIP_HDR_LEN)
		return 0;
	return EIP_HDR_LEN + (size_t)le16(buf + 2);
}

int eip_register_parse(uint16_t *version, uint16_t *options, const uint8_t *data, size_t n)
{
	if (!version || !options || (!data && n))
		return DF1_E_INVAL;
	if (n < 4)
		return DF1_E_TOO_SHORT;
	if (n > 4)
		return DF1_E_TOO_LONG;
	*version = le16(data);
	*options = le16(data + 2);
	return 0;
}

int eip_register_build(uint8_t *out, size_t cap, uint16_t version, uint16_t options)
{
	if (!out)
		return DF1_E_INVAL;
	if (cap < 4)
		return DF1_E_NOSPACE;
	put_le16(out, version);
	put_le16(out + 2, options);
	return 4;
}

/* ------------------------------------------------------------------------
 * Common packet format
 * ------------------------------------------------------------------------ */

int eip_cpf_parse(struct eip_cpf *c, const uint8_t *buf, size_t n)
{
	size_t pos = 2;

	if (!c || (!buf && n))
		return DF1_E_INVAL;
	memset(c, 0, sizeof *c);
	if (n < 2)
		return DF1_E_TOO_SHORT;
	c->count = le16(buf);
	if (c->count > EIP_CPF_ITEMS_MAX)
		return DF1_E_TOO_LONG;
	for (unsigned i = 0; i < c->count; i++) {
		struct eip_item *it = &c->item[i];

		if (n - pos < 4)
			return DF1_E_TOO_SHORT;
		it->type = le16(buf + pos);
		it->len = le16(buf + pos + 2);
		pos += 4;
		if (it->len > n - pos)
			return DF1_E_TOO_SHORT;
		it->data = buf + pos;
		pos += it->len;
	}
	return pos == n ? 0 : DF1_E_TOO_LONG;
}

int eip_rr_parse(uint16_t *timeout, struct eip_cpf *c, const uint8_t *data, size_t n)
{
	if (!timeout || !c || (!data && n))
		return DF1_E_INVAL;
	memset(c, 0, sizeof *c);
	if (n < 6)
		return DF1_E_TOO_SHORT;
	if (le32(data) != 0)        /* interface handle: 0 = CIP */
		return DF1_E_INVAL;
	*timeout = le16(data + 4);
	return eip_cpf_parse(c, data + 6, n - 6);
}

int eip_packet_parse(struct eip_packet *p, const struct eip_cpf *c)
{
	const struct eip_item *a, *d;

	if (!p || !c)
		return DF1_E_INVAL;
	memset(p, 0, sizeof *p);
	if (c->count < 2)
		return c->count ? DF1_E_TOO_SHORT : DF1_E_INVAL;
	a = &c->item[0];
	d = &c->item[1];
	for (unsigned i = 2; i < c->count; i++)
		if (c->item[i].type != EIP_ITEM_SOCKADDR_OT && c->item[i].type != EIP_ITEM_SOCKADDR_TO)
			return DF1_E_INVAL;
	if (a->type == EIP_ITEM_NULL && d->type == EIP_ITEM_UNCONNECTED_DATA) {
		if (a->len != 0)
			return DF1_E_INVAL;
		p->data = d->data;
		p->len = d->len;
		return 0;
	}
	if (a->type == EIP_ITEM_CONNECTED_ADDR && d->type == EIP_ITEM_CONNECTED_DATA) {
		if (a->len != 4 || d->len < 2)
			return DF1_E_TOO_SHORT;
		p->connected = true;
		p->conn_id = le32(a->data);
		p->seq = le16(d->data);
		p->data = d->data + 2;
		p->len = d->len - 2u;
		return 0;
	}
	return DF1_E_INVAL;
}

int eip_packet_build(uint8_t *out, size_t cap, uint32_t session, const uint8_t context[8],
                     uint16_t timeout, const struct eip_packet *p)
{
	static const uint8_t zero[8];
	struct eip_hdr h;
	size_t addr_len, data_len, total;
	uint8_t *q;

	if (!out || !p || (!p->data && p->len))
		return DF1_E_INVAL;
	addr_len = p->connected ? 4 : 0;
	data_len = p->len + (p->connected ? 2 : 0);
	total = EIP_HDR_LEN + 6 + 2 + 4 + addr_len + 4 + data_len;
	if (data_len > 0xFFFF || total - EIP_HDR_LEN > EIP_DATA_MAX)
		return DF1_E_INVAL;
	if (cap < total)
		return DF1_E_NOSPACE;
	memset(&h, 0, sizeof h);
	h.command = p->connected ? EIP_CMD_SEND_UNIT_DATA : EIP_CMD_SEND_RR_DATA;
	h.length = (uint16_t)(total - EIP_HDR_LEN);
	h.session = session;
	memcpy(h.context, context ? context : zero, 8);
	eip_hdr_build(out, cap, &h);
	q = out + EIP_HDR_LEN;
	put_le32(q, 0);
	put_le16(q + 4, timeout);
	put_le16(q + 6, 2);
	q += 8;
	put_le16(q, p->connected ? EIP_ITEM_CONNECTED_ADDR : EIP_ITEM_NULL);
	put_le16(q + 2, (uint16_t)addr_len);
	if (p->connected)
		put_le32(q + 4, p->conn_id);
	q += 4 + addr_len;
	put_le16(q, p->connected ? EIP_ITEM_CONNECTED_DATA : EIP_ITEM_UNCONNECTED_DATA);
	put_le16(q + 2, (uint16_t)data_len);
	q += 4;
	if (p->connected) {
		put_le16(q, p->seq);
		q += 2;
	}
	if (p->len)
		memcpy(q, p->data, p->len);
	return (int)total;
}

/* ------------------------------------------------------------------------
 * ListIdentity, ListServices
 * ------------------------------------------------------------------------ */

/* The name's bytes as sent: up to 32, stopping at its NUL. */
static size_t name_len(const char *s)
{
	size_t n = 0;

	while (n < 32 && s[n])
		n++;
	return n;
}

int eip_identity_build(uint8_t *out, size_t cap, const struct eip_identity *id)
{
	size_t nl, item, total;
	uint8_t *q;

	if (!out || !id)
		return DF1_E_INVAL;
	nl = name_len(id->product_name);
	item = 2 + 16 + 2 + 2 + 2 + 2 + 2 + 4 + 1 + nl + 1;
	total = 2 + 4 + item;
	if (cap < total)
		return DF1_E_NOSPACE;
	put_le16(out, 1);
	put_le16(out + 2, EIP_ITEM_LIST_IDENTITY);
	put_le16(out + 4, (uint16_t)item);
	q = out + 6;
	put_le16(q, id->encap_version);
	put_be16(q + 2, id->sin_family);
	put_be16(q + 4, id->sin_port);
	put_be16(q + 6, (uint16_t)(id->sin_addr >> 16));
	put_be16(q + 8, (uint16_t)id->sin_addr);
	memset(q + 10, 0, 8);
	q += 18;
	put_le16(q, id->vendor_id);
	put_le16(q + 2, id->device_type);
	put_le16(q + 4, id->product_code);
	q[6] = id->rev_major;
	q[7] = id->rev_minor;
	put_le16(q + 8, id->status);
	put_le32(q + 10, id->serial);
	q[14] = (uint8_t)nl;
	memcpy(q + 15, id->product_name, nl);
	q[15 + nl] = id->state;
	return (int)total;
}

int eip_identity_parse(struct eip_identity *id, const uint8_t *data, size_t n)
{
	size_t nl;

	if (!id || (!data && n))
		return DF1_E_INVAL;
	memset(id, 0, sizeof *id);
	if (n < 33)
		return DF1_E_TOO_SHORT;
	id->encap_version = le16(data);
	id->sin_family = be16(data + 2);
	id->sin_port = be16(data + 4);
	id->sin_addr = (uint32_t)be16(data + 6) << 16 | be16(data + 8);
	data += 18;
	id->vendor_id = le16(data);
	id->device_type = le16(data + 2);
	id->product_code = le16(data + 4);
	id->rev_major = data[6];
	id->rev_minor = data[7];
	id->status = le16(data + 8);
	id->serial = le32(data + 10);
	nl = data[14];
	if (nl > 32)
		return DF1_E_TOO_LONG;
	if (n < 33 + nl + 1)   /* 18 + 14 + length byte, the name, state */
		return DF1_E_TOO_SHORT;
	memcpy(id->product_name, data + 15, nl);
	id->product_name[nl] = '\0';
	id->state = data[15 + nl];
	return 0;
}

int eip_services_build(uint8_t *out, size_t cap, uint16_t flags)
{
	static const char name[16] = "Communications";

	if (!out)
		return DF1_E_INVAL;
	if (cap < 26)
		return DF1_E_NOSPACE;
	put_le16(out, 1);
	put_le16(out + 2, EIP_ITEM_LIST_SERVICES);
	put_le16(out + 4, 20);
	put_le16(out + 6, 1);          /* version */
	put_le16(out + 8, flags);
	memcpy(out + 10, name, 16);
	return 26;
}

/* ------------------------------------------------------------------------
 * EPATH
 * ------------------------------------------------------------------------ */

void cip_path_init(struct cip_path *p)
{
	p->port = p->link = CIP_NONE;
	p->class_id = p->instance = p->attribute = p->point = CIP_NONE;
}

static int *logical_slot(struct cip_path *p, uint8_t seg)
{
	switch (seg & 0xFC) {
	case 0x20: return &p->class_id;
	case 0x24: return &p->instance;
	case 0x2C: return &p->point;
	case 0x30: return &p->attribute;
	default: return NULL;
	}
}

/* A port segment at path[0..n): sets port/link, returns its bytes. */
static int port_seg(struct cip_path *p, const uint8_t *path, size_t n)
{
	size_t pos = 1, alen = 1;
	int port = path[0] & 0x0F;

	if (p->port != CIP_NONE)
		return DF1_E_INVAL;
	if (port == 0x0F) {      /* 16-bit port number follows */
		if (n < 3)
			return DF1_E_TOO_SHORT;
		port = le16(path + 1);
		pos = 3;
	}
	if (path[0] & CIP_SEG_PORT_EXT) {
		if (n < pos + 1)
			return DF1_E_TOO_SHORT;
		alen = path[pos++];
	}
	if (n < pos + alen)
		return DF1_E_TOO_SHORT;
	p->port = port;
	p->link = alen == 1 ? path[pos] : CIP_NONE;
	pos += alen;
	return (int)(pos + (pos & 1));   /* padded to a word */
}

int cip_path_parse(struct cip_path *p, const uint8_t *path, size_t n)
{
	size_t pos = 0;

	if (!p || (!path && n))
		return DF1_E_INVAL;
	cip_path_init(p);
	while (pos < n) {
		uint8_t seg = path[pos];
		int *slot = logical_slot(p, seg);
		size_t left = n - pos;

		if ((seg & 0xE0) == 0x00) {
			int used = port_seg(p, path + pos, left);

			if (used < 0)
				return used;
			if ((size_t)used > left)
				return DF1_E_TOO_SHORT;
			pos += (size_t)used;
		} else if (slot && (seg & 0x03) == 0) {
			if (left < 2)
				return DF1_E_TOO_SHORT;
			*slot = path[pos + 1];
			pos += 2;
		} else if (slot && (seg & 0x03) == 1) {
			if (left < 4)          /* segment, pad, 16-bit value */
				return DF1_E_TOO_SHORT;
			*slot = le16(path + pos + 2);
			pos += 4;
		} else if (seg == CIP_SEG_KEY) {
			if (left < 2 || path[pos + 1] != 4)
				return left < 2 ? DF1_E_TOO_SHORT : DF1_E_INVAL;
			if (left < 10)
				return DF1_E_TOO_SHORT;
			pos += 10;
		} else if (seg == CIP_SEG_DATA_SIMPLE) {
			if (left < 2 || left < 2 + 2 * (size_t)path[pos + 1])
				return DF1_E_TOO_SHORT;
			pos += 2 + 2 * (size_t)path[pos + 1];
		} else {
			return DF1_E_INVAL;
		}
	}
	return 0;
}

/* One logical segment: 8-bit if the value fits, else the padded 16-bit form. */
static size_t put_logical(uint8_t *q, uint8_t seg8, int v)
{
	if (v <= 0xFF) {
		q[0] = seg8;
		q[1] = (uint8_t)v;
		return 2;
	}
	q[0] = (uint8_t)(seg8 | 1);
	q[1] = 0;
	put_le16(q + 2, (uint16_t)v);
	return 4;
}

int cip_path_build(uint8_t *out, size_t cap, const struct cip_path *p)
{
	uint8_t tmp[CIP_PATH_MAX];
	size_t n = 0;

	if (!out || !p)
		return DF1_E_INVAL;
	if (p->port != CIP_NONE) {
		if (p->port < 1 || p->port > 14 || p->link < 0 || p->link > 0xFF)
			return DF1_E_INVAL;
		tmp[n++] = (uint8_t)p->port;
		tmp[n++] = (uint8_t)p->link;
	}
	const int vals[4] = { p->class_id, p->instance, p->attribute, p->point };
	static const uint8_t segs[4] = { CIP_SEG_CLASS8, CIP_SEG_INSTANCE8, CIP_SEG_ATTRIBUTE8, CIP_SEG_POINT8 };
	for (int i = 0; i < 4; i++) {
		if (vals[i] == CIP_NONE)
			continue;
		if (vals[i] < 0 || vals[i] > 0xFFFF)
			return DF1_E_INVAL;
		n += put_logical(tmp + n, segs[i], vals[i]);
	}
	if (cap < n)
		return DF1_E_NOSPACE;
	memcpy(out, tmp, n);
	return (int)n;
}

/* ------------------------------------------------------------------------
 * Message router request / response
 * ------------------------------------------------------------------------ */

int cip_req_parse(struct cip_req *r, const uint8_t *buf, size_t n)
{
	size_t plen;

	if (!r || (!buf && n))
		return DF1_E_INVAL;
	memset(r, 0, sizeof *r);
	if (n < 2)
		return DF1_E_TOO_SHORT;
	r->service = buf[0];
	plen = 2 * (size_t)buf[1];
	if (plen > n - 2)
		return DF1_E_TOO_SHORT;
	r->path = buf + 2;
	r->path_len = plen;
	r->data = buf + 2 + plen;
	r->len = n - 2 - plen;
	return 0;
}

int cip_req_build(uint8_t *out, size_t cap, uint8_t service, const struct cip_path *p,
                  const uint8_t *data, size_t n)
{
	uint8_t path[CIP_PATH_MAX];
	int pl = 0;

	if (!out || (!data && n))
		return DF1_E_INVAL;
	if (p) {
		pl = cip_path_build(path, sizeof path, p);
		if (pl < 0)
			return pl;
	}
	if (cap < 2 + (size_t)pl + n)
		return DF1_E_NOSPACE;
	out[0] = service;
	out[1] = (uint8_t)(pl / 2);
	memcpy(out + 2, path, (size_t)pl);
	if (n)
		memmove(out + 2 + pl, data, n);
	return 2 + pl + (int)n;
}

int cip_resp_parse(struct cip_resp *r, const uint8_t *buf, size_t n)
{
	size_t ext;

	if (!r || (!buf && n))
		return DF1_E_INVAL;
	memset(r, 0, sizeof *r);
	if (n < 4)
		return DF1_E_TOO_SHORT;
	if (!(buf[0] & CIP_SVC_REPLY))
		return DF1_E_INVAL;
	r->service = buf[0];
	r->status = buf[2];
	r->ext_words = buf[3];
	ext = 2 * (size_t)buf[3];
	if (ext > n - 4)
		return DF1_E_TOO_SHORT;
	if (ext)
		r->ext0 = le16(buf + 4);
	r->data = buf + 4 + ext;
	r->len = n - 4 - ext;
	return 0;
}

int cip_resp_build(uint8_t *out, size_t cap, uint8_t service, uint8_t status, const uint16_t *ext,
                   size_t ext_words, const uint8_t *data, size_t n)
{
	size_t need = 4 + 2 * ext_words + n;

	if (!out || (!ext && ext_words) || (!data && n) || ext_words > 0xFF)
		return DF1_E_INVAL;
	if (cap < need)
		return DF1_E_NOSPACE;
	if (n)
		memmove(out + 4 + 2 * ext_words, data, n);
	out[0] = (uint8_t)(service | CIP_SVC_REPLY);
	out[1] = 0;
	out[2] = status;
	out[3] = (uint8_t)ext_words;
	for (size_t i = 0; i < ext_words; i++)
		put_le16(out + 4 + 2 * i, ext[i]);
	return (int)need;
}

/* ------------------------------------------------------------------------
 * Execute PCCC
 * ------------------------------------------------------------------------ */

int eip_pccc_parse(struct eip_pccc *p, const uint8_t *data, size_t n)
{
	size_t idl;

	if (!p || (!data && n))
		return DF1_E_INVAL;
	memset(p, 0, sizeof *p);
	if (n < 1)
		return DF1_E_TOO_SHORT;
	idl = data[0];
	if (idl < 7)
		return DF1_E_INVAL;
	if (idl > EIP_REQID_MAX)
		return DF1_E_TOO_LONG;
	if (n < idl + 4)         /* CMD STS TNS(2) at least */
		return DF1_E_TOO_SHORT;
	p->reqid = data;
	p->reqid_len = idl;
	p->pccc = data + idl;
	p->len = n - idl;
	return 0;
}

int eip_pccc_build(uint8_t *out, size_t cap, uint16_t vendor, uint32_t serial, const uint8_t *pccc,
                   size_t n)
{
	if (!out || (!pccc && n))
		return DF1_E_INVAL;
	if (cap < 7 + n)
		return DF1_E_NOSPACE;
	if (n)
		memmove(out + 7, pccc, n);
	out[0] = 7;
	put_le16(out + 1, vendor);
	put_le32(out + 3, serial);
	return 7 + (int)n;
}

int eip_pccc_request_build(uint8_t *out, size_t cap, uint16_t vendor, uint32_t serial,
                           const uint8_t *pccc, size_t n)
{
	struct cip_path p;
	int rc;

	if (!out || (!pccc && n))
		return DF1_E_INVAL;
	if (cap < 6 + 7 + n)
		return DF1_E_NOSPACE;
	memmove(out + 6 + 7, pccc, n);
	rc = eip_pccc_build(out + 6, cap - 6, vendor, serial, out + 13, n);
	if (rc < 0)
		return rc;
	cip_path_init(&p);
	p.class_id = CIP_CLASS_PCCC;
	p.instance = 1;
	return cip_req_build(out, cap, CIP_SVC_EXECUTE_PCCC, &p, out + 6, (size_t)rc);
}

/* ------------------------------------------------------------------------
 * Connection Manager
 * ------------------------------------------------------------------------ */

static const struct cip_path cm_path = { CIP_NONE, CIP_NONE, CIP_CLASS_CONNECTION_MANAGER, 1,
                                         CIP_NONE, CIP_NONE };

int cip_fwd_open_parse(struct cip_fwd_open *f, bool large, const uint8_t *data, size_t n)
{
	size_t np = large ? 4 : 2, fixed = 32 + 2 * np, plen;

	if (!f || (!data && n))
		return DF1_E_INVAL;
	memset(f, 0, sizeof *f);
	if (n < fixed)
		return DF1_E_TOO_SHORT;
	f->large = large;
	f->tick = data[0];
	f->timeout_ticks = data[1];
	f->ot_conn_id = le32(data + 2);
	f->to_conn_id = le32(data + 6);
	f->conn_serial = le16(data + 10);
	f->vendor_id = le16(data + 12);
	f->orig_serial = le32(data + 14);
	f->timeout_mult = data[18];
	f->ot_rpi = le32(data + 22);
	f->ot_params = large ? le32(data + 26) : le16(data + 26);
	f->to_rpi = le32(data + 26 + np);
	f->to_params = large ? le32(data + 30 + np) : le16(data + 30 + np);
	f->transport = data[30 + 2 * np];
	plen = 2 * (size_t)data[31 + 2 * np];
	if (plen > n - fixed)
		return DF1_E_TOO_SHORT;
	if (plen < n - fixed)
		return DF1_E_TOO_LONG;
	f->path = data + fixed;
	f->path_len = plen;
	return 0;
}

int cip_fwd_open_build(uint8_t *out, size_t cap, const struct cip_fwd_open *f)
{
	size_t np, fixed;
	uint8_t *d;
	int hl;

	if (!out || !f || (!f->path && f->path_len) || (f->path_len & 1) || f->path_len > 510)
		return DF1_E_INVAL;
	np = f->large ? 4 : 2;
	fixed = 32 + 2 * np;
	hl = cip_req_build(out, cap, f->large ? CIP_SVC_LARGE_FORWARD_OPEN : CIP_SVC_FORWARD_OPEN, &cm_path,
	                   NULL, 0);
	if (hl < 0)
		return hl;
	if (cap < (size_t)hl + fixed + f->path_len)
		return DF1_E_NOSPACE;
	d = out + hl;
	memset(d, 0, fixed);
	d[0] = f->tick;
	d[1] = f->timeout_ticks;
	put_le32(d + 2, f->ot_conn_id);
	put_le32(d + 6, f->to_conn_id);
	put_le16(d + 10, f->conn_serial);
	put_le16(d + 12, f->vendor_id);
	put_le32(d + 14, f->orig_serial);
	d[18] = f->timeout_mult;
	put_le32(d + 22, f->ot_rpi);
	if (f->large)
		put_le32(d + 26, f->ot_params);
	else
		put_le16(d + 26, (uint16_t)f->ot_params);
	put_le32(d + 26 + np, f->to_rpi);
	if (f->large)
		put_le32(d + 30 + np, f->to_params);
	else
		put_le16(d + 30 + np, (uint16_t)f->to_params);
	d[30 + 2 * np] = f->transport;
	d[31 + 2 * np] = (uint8_t)(f->path_len / 2);
	if (f->path_len)
		memcpy(d + fixed, f->path, f->path_len);
	return hl + (int)(fixed + f->path_len);
}

int cip_fwd_open_reply_build(uint8_t *out, size_t cap, const struct cip_fwd_open *f)
{
	if (!out || !f)
		return DF1_E_INVAL;
	if (cap < 26)
		return DF1_E_NOSPACE;
	put_le32(out, f->ot_conn_id);
	put_le32(out + 4, f->to_conn_id);
	put_le16(out + 8, f->conn_serial);
	put_le16(out + 10, f->vendor_id);
	put_le32(out + 12, f->orig_serial);
	put_le32(out + 16, f->ot_rpi);
	put_le32(out + 20, f->to_rpi);
	out[24] = 0;     /* application reply size */
	out[25] = 0;
	return 26;
}

int cip_fwd_open_reply_parse(struct cip_fwd_open *f, const uint8_t *data, size_t n)
{
	if (!f || (!data && n))
		return DF1_E_INVAL;
	memset(f, 0, sizeof *f);
	if (n < 26 || n < 26 + 2 * (size_t)data[24])
		return DF1_E_TOO_SHORT;
	f->ot_conn_id = le32(data);
	f->to_conn_id = le32(data + 4);
	f->conn_serial = le16(data + 8);
	f->vendor_id = le16(data + 10);
	f->orig_serial = le32(data + 12);
	f->ot_rpi = le32(data + 16);
	f->to_rpi = le32(data + 20);
	return 0;
}

int cip_fwd_fail_build(uint8_t *out, size_t cap, uint16_t conn_serial, uint16_t vendor_id,
                       uint32_t orig_serial)
{
	if (!out)
		return DF1_E_INVAL;
	if (cap < 10)
		return DF1_E_NOSPACE;
	put_le16(out, conn_serial);
	put_le16(out + 2, vendor_id);
	put_le32(out + 4, orig_serial);
	out[8] = 0;      /* remaining path size */
	out[9] = 0;
	return 10;
}

int cip_fwd_close_parse(struct cip_fwd_close *f, const uint8_t *data, size_t n)
{
	size_t plen;

	if (!f || (!data && n))
		return DF1_E_INVAL;
	memset(f, 0, sizeof *f);
	if (n < 12)
		return DF1_E_TOO_SHORT;
	f->tick = data[0];
	f->timeout_ticks = data[1];
	f->conn_serial = le16(data + 2);
	f->vendor_id = le16(data + 4);
	f->orig_serial = le32(data + 6);
	plen = 2 * (size_t)data[10];
	if (plen > n - 12)
		return DF1_E_TOO_SHORT;
	if (plen < n - 12)
		return DF1_E_TOO_LONG;
	f->path = data + 12;
	f->path_len = plen;
	return 0;
}

int cip_fwd_close_build(uint8_t *out, size_t cap, const struct cip_fwd_close *f)
{
	uint8_t *d;
	int hl;

	if (!out || !f || (!f->path && f->path_len) || (f->path_len & 1) || f->path_len > 510)
		return DF1_E_INVAL;
	hl = cip_req_build(out, cap, CIP_SVC_FORWARD_CLOSE, &cm_path, NULL, 0);
	if (hl < 0)
		return hl;
	if (cap < (size_t)hl + 12 + f->path_len)
		return DF1_E_NOSPACE;
	d = out + hl;
	d[0] = f->tick;
	d[1] = f->timeout_ticks;
	put_le16(d + 2, f->conn_serial);
	put_le16(d + 4, f->vendor_id);
	put_le32(d + 6, f->orig_serial);
	d[10] = (uint8_t)(f->path_len / 2);
	d[11] = 0;
	if (f->path_len)
		memcpy(d + 12, f->path, f->path_len);
	return hl + 12 + (int)f->path_len;
}

int cip_fwd_close_reply_build(uint8_t *out, size_t cap, const struct cip_fwd_close *f)
{
	if (!f)
		return DF1_E_INVAL;
	return cip_fwd_fail_build(out, cap, f->conn_serial, f->vendor_id, f->orig_serial);
}

int cip_unconnected_parse(struct cip_unconnected *u, const uint8_t *data, size_t n)
{
	size_t rl, pos, plen;

	if (!u || (!data && n))
		return DF1_E_INVAL;
	memset(u, 0, sizeof *u);
	if (n < 4)
		return DF1_E_TOO_SHORT;
	u->tick = data[0];
	u->timeout_ticks = data[1];
	rl = le16(data + 2);
	if (rl > CIP_UNCONNECTED_REQ_MAX)
		return DF1_E_TOO_LONG;  /* what no client may send (eip_codec.h) */
	if (rl > n - 4)
		return DF1_E_TOO_SHORT;
	u->req = data + 4;
	u->req_len = rl;
	pos = 4 + rl + (rl & 1);
	if (pos + 2 > n)
		return DF1_E_TOO_SHORT;
	plen = 2 * (size_t)data[pos];
	pos += 2;
	if (plen > n - pos)
		return DF1_E_TOO_SHORT;
	if (plen < n - pos)
		return DF1_E_TOO_LONG;
	u->route = data + pos;
	u->route_len = plen;
	return 0;
}

int cip_unconnected_build(uint8_t *out, size_t cap, uint8_t tick, uint8_t timeout_ticks,
                          const uint8_t *req, size_t req_len, const uint8_t *route, size_t route_len)
{
	size_t pad = req_len & 1, need;
	uint8_t *d;
	int hl;

	if (!out || (!req && req_len) || (!route && route_len) || (route_len & 1) || route_len > 510 ||
	    req_len > CIP_UNCONNECTED_REQ_MAX)
		return DF1_E_INVAL;
	hl = cip_req_build(out, cap, CIP_SVC_UNCONNECTED_SEND, &cm_path, NULL, 0);
	if (hl < 0)
		return hl;
	need = (size_t)hl + 4 + req_len + pad + 2 + route_len;
	if (cap < need)
		return DF1_E_NOSPACE;
	d = out + hl;
	d[0] = tick;
	d[1] = timeout_ticks;
	put_le16(d + 2, (uint16_t)req_len);
	if (req_len)
		memmove(d + 4, req, req_len);
	d += 4 + req_len;
	if (pad)
		*d++ = 0;
	d[0] = (uint8_t)(route_len / 2);
	d[1] = 0;
	if (route_len)
		memmove(d + 2, route, route_len);
	return (int)need;
}

/* ------------------------------------------------------------------------
 * Identity object
 * ------------------------------------------------------------------------ */

int cip_identity_attr_build(uint8_t *out, size_t cap, const struct eip_identity *id, int attribute)
{
	size_t nl;

	if (!out || !id)
		return DF1_E_INVAL;
	switch (attribute) {
	case 1: case 2: case 3: case 5:
		if (cap < 2)
			return DF1_E_NOSPACE;
		put_le16(out, attribute == 1 ? id->vendor_id : attribute == 2 ? id->device_type
		              : attribute == 3 ? id->product_code : id->status);
		return 2;
	case 4:
		if (cap < 2)
			return DF1_E_NOSPACE;
		out[0] = id->rev_major;
		out[1] = id->rev_minor;
		return 2;
	case 6:
		if (cap < 4)
			return DF1_E_NOSPACE;
		put_le32(out, id->serial);
		return 4;
	case 7:
		nl = name_len(id->product_name);
		if (cap < 1 + nl)
			return DF1_E_NOSPACE;
		out[0] = (uint8_t)nl;
		memcpy(out + 1, id->product_name, nl);
		return 1 + (int)nl;
	default:
		return DF1_E_NOTSUP;
	}
}

int cip_identity_all_build(uint8_t *out, size_t cap, const struct eip_identity *id)
{
	size_t pos = 0;

	if (!out || !id)
		return DF1_E_INVAL;
	for (int a = 1; a <= 7; a++) {
		int rc = cip_identity_attr_build(out + pos, cap - pos, id, a);

		if (rc < 0)
			return rc;
		pos += (size_t)rc;
	}
	return (int)pos;
}
