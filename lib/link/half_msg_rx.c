/* SPDX-License-Identifier: MPL-2.0 */
/*
 * half_msg_rx.c - what half_serve (lib/link/half.c) asks about a half-duplex
 * slave's own MSG while lib/link/half_msg.c waits for it: was our command
 * ACKed, is this master message its reply (ACKed and taken), is it over.
 */
#include "link/link.h"

#include <string.h>

#include "link/link_int.h"

bool half_msg_over(const struct df1 *h)
{
	const struct link_own_msg *m = h->own_msg;

	return m && (m->done || (m->cmd[0] == 255 && m->acked));
}

void half_msg_acked(struct df1 *h, const struct link_reply *r)
{
	struct link_own_msg *m = h->own_msg;

	if (m && r == m->slot && r->seq == m->seq)
		m->acked = true;
}

int half_msg_reply(struct df1 *h, const struct df1_symbol *s)
{
	struct link_own_msg *m = h->own_msg;
	const uint8_t *d = s->data, *c = m ? m->cmd : NULL;
	int r;

	if (!m || m->done || d[0] != c[1] || d[1] != c[0] || d[2] != (uint8_t)(c[2] | 0x40) ||
	    d[4] != c[4] || d[5] != c[5])
		return 0;
	r = link_send_sym(h, DF1_ACK);
	link_remember(h, s->station, d, s->len);
	df1_count(h, DF1_ID_CNT_MSG_PACKETS_RCVD);
	df1_count(h, DF1_ID_CNT_REPLY_MSGS_RCVD);
	if (d[3] != 0)
		df1_count(h, DF1_ID_CNT_ERROR_MSGS_RCVD);
	m->done = true;
	m->acked = true;
	if (r < 0)
		m->rc = r;
	else if (s->len > m->cap)
		m->rc = df1_fail(h, DF1_E_NOSPACE, d[1], "reply of %zu bytes, buffer holds %zu", s->len,
		                 m->cap);
	else
		memcpy(m->reply, d, m->len = s->len);
	return 1;
}
