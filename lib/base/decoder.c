/* SPDX-License-Identifier: MPL-2.0 */
/*
 * decoder - the public incremental decoder (df1mon, tests): a heap-allocated
 * wrapper around the pure frame decoder. Allocation happens only in new.
 */
#include "df1.h"

#include <stdlib.h>

#include "proto/frame.h"

struct df1_decoder {
	struct frame_decoder fd;
};

int df1_decoder_new(struct df1_decoder **out, enum df1_check check)
{
	struct df1_decoder *d;

	if (!out)
		return DF1_E_INVAL;
	*out = NULL;
	if (check != DF1_CHECK_CRC && check != DF1_CHECK_BCC && check != DF1_CHECK_AUTO)
		return DF1_E_INVAL;
	d = malloc(sizeof *d);
	if (!d)
		return DF1_E_NOMEM;
	/* the library's own defaults: DLE 0F is NAK too, embedded responses on */
	frame_decoder_init(&d->fd, check, FRAME_OPT_ACCEPT_NAK_0F);
	*out = d;
	return DF1_OK;
}

void df1_decoder_free(struct df1_decoder *d)
{
	free(d);
}

void df1_decoder_reset(struct df1_decoder *d)
{
	if (d)
		frame_decoder_reset(&d->fd);
}

int df1_decoder_set_half_duplex(struct df1_decoder *d, bool on)
{
	if (!d)
		return DF1_E_INVAL;
	d->fd.opts &= ~(FRAME_OPT_HALF_DUPLEX | FRAME_OPT_DUPLEX_AUTO);
	if (on)
		d->fd.opts |= FRAME_OPT_HALF_DUPLEX;
	return DF1_OK;
}

int df1_decoder_set_duplex_auto(struct df1_decoder *d, bool on)
{
	if (!d)
		return DF1_E_INVAL;
	d->fd.opts &= ~(FRAME_OPT_HALF_DUPLEX | FRAME_OPT_DUPLEX_AUTO);
	if (on)
		d->fd.opts |= FRAME_OPT_DUPLEX_AUTO;
	return DF1_OK;
}

int df1_decoder_set_option(struct df1_decoder *d, enum df1_option opt, int value)
{
	unsigned bit;
	bool set;

	if (!d || (value != 0 && value != 1))
		return DF1_E_INVAL;
	switch (opt) {
	case DF1_OPT_HD_BCC_INCLUDES_STX: bit = FRAME_OPT_HD_BCC_STX; set = value; break;
	case DF1_OPT_ACCEPT_NAK_0F: bit = FRAME_OPT_ACCEPT_NAK_0F; set = value; break;
	case DF1_OPT_EOT_WITH_BCC: bit = FRAME_OPT_EOT_TRAILER; set = value; break;
	case DF1_OPT_EMBEDDED_RESPONSES: bit = FRAME_OPT_NO_EMBEDDED; set = !value; break;
	default: return DF1_E_INVAL;
	}
	if (set)
		d->fd.opts |= bit;
	else
		d->fd.opts &= ~bit;
	return DF1_OK;
}

bool df1_decoder_dle_pending(const struct df1_decoder *d)
{
	return d && frame_decoder_dle_pending(&d->fd);
}

size_t df1_decoder_feed(struct df1_decoder *d, const uint8_t *in, size_t n, struct df1_symbol *sym)
{
	if (!d || !sym || (!in && n)) {
		if (sym) {
			/* nothing decoded; an all-zero symbol is kind NONE */
			*sym = (struct df1_symbol){ .kind = DF1_SYM_NONE };
		}
		return 0;
	}
	return frame_decoder_feed(&d->fd, in, n, sym);
}
