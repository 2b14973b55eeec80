/* SPDX-License-Identifier: MPL-2.0 */
/*
 * server_slc.c - the responder's SLC commands (doc/PROTOCOL.md 4.5, 4.6):
 * 0F/A1 A2 protected typed logical read, 0F/A9 AA write and 0F/AB masked
 * write, by file type code, file, element and sub-element.
 *
 * Where the spec flags a doubt (doc/PROTOCOL.md 8): the O/I file type codes
 * 8B/8C and 82/83 are both taken, whatever DF1_OPT_SLC_IO_CODES_82 says
 * (doc/PROTOCOL.md 4.11).
 */
#include "server/server_int.h"

int srv_slc(struct srv *s, uint8_t fnc)
{
	bool three = fnc == PCCC_FNC_SLC_READ3 || fnc == PCCC_FNC_SLC_WRITE3 || fnc == PCCC_FNC_SLC_MASKED;
	bool rd = fnc == PCCC_FNC_SLC_READ2 || fnc == PCCC_FNC_SLC_READ3;
	bool masked = fnc == PCCC_FNC_SLC_MASKED;
	unsigned file, elem, sub;
	uint8_t nb, tc;
	enum df1_file_type t;
	const uint8_t *d;
	size_t rest, limit, off;
	int k, rc;

	k = pccc_dec_slc_fields(s->m->data, s->m->len, three, &nb, &file, &tc, &elem, &sub);
	if (k < 0 || nb == 0)
		return srv_fail_sts(s, 0x10);
	d = s->m->data + k;
	rest = s->m->len - (size_t)k;
	/* AB with one mask word for every word of the data (pycomm3 and NPC send
	 * it so for F, L and ST elements: doc/PROTOCOL.md 4.6) or a mask as long as the data */
	bool mask_word = masked && nb > 2 && !(nb & 1) && rest == 2u + nb;
	if (rest != (rd ? 0u : masked ? 2u * nb : nb) && !mask_word)
		return srv_fail_sts(s, 0x10);
	t = pccc_slc_code_file_type(tc);       /* O: 8B or 82, I: 8C or 83 (doc/PROTOCOL.md 4.11) */
	if (t == DF1_FT_NONE)
		return srv_fail_ext(s, 0x11);
	if (s->h && s->h->cfg.plc == DF1_PLC_SLC502)
		limit = PLC_SLC502_MAX;
	else
		limit = rd ? PLC_SLC_READ_MAX : PLC_SLC_WRITE_MAX;
	if (nb > limit)
		return srv_fail_ext(s, 0x09);
	off = (size_t)elem * srv_elem_size(t) + (size_t)sub * 2;
	if (rd)
		rc = srv_tbl_read(s, t, (int)file, off, s->data, nb);
	else if (mask_word) {
		uint8_t mask[255];

		for (size_t i = 0; i < nb; i++)
			mask[i] = d[i & 1];
		rc = srv_tbl_write(s, t, (int)file, off, d + 2, mask, nb);
	} else if (masked)
		rc = srv_tbl_write(s, t, (int)file, off, d + nb, d, nb);
	else
		rc = srv_tbl_write(s, t, (int)file, off, d, NULL, nb);
	if (rc)
		return srv_fail_rc(s, rc);
	s->len = rd ? nb : 0;
	return 0;
}
