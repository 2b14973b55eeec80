/* SPDX-License-Identifier: MPL-2.0 */
/*
 * health.c - what a transaction's result means (outcome), the tags' values
 * and qualities after it, and station health: answers, failures, offline,
 * recovery (doc/REQUIREMENTS.md 000).
 */
#include "poll/poll_int.h"

static bool poll_addr_ext(uint8_t ext)
{
	switch (ext) {
	case 0x01: case 0x02: case 0x03: case 0x04: case 0x05: case 0x06: case 0x07:
	case 0x09: case 0x0A: case 0x11: case 0x13:
		return true;
	default:
		return false;
	}
}

enum outcome poll_outcome(const struct df1 *h, int rc)
{
	const struct df1_error_detail *d = &h->err;

	if (rc >= 0)
		return OUT_OK;
	switch (rc) {
	case DF1_E_REMOTE:
		if (d->sts == 0x50 || (d->sts == 0xF0 && d->has_ext_sts && poll_addr_ext(d->ext_sts)))
			return OUT_ADDR;
		return OUT_PLC;
	case DF1_E_INVAL: case DF1_E_NOTSUP: case DF1_E_ADDR_RANGE: case DF1_E_ADDR_SYNTAX:
	case DF1_E_TYPE: case DF1_E_RANGE: case DF1_E_NOSPACE:
		return OUT_LOCAL;
	case DF1_E_INTR: case DF1_E_NOMEM: case DF1_E_NOT_OPEN:
		return OUT_ABORT;
	default:
		return OUT_LINK;
	}
}

/* Tag failure without an answer: UNCERTAIN with a value, else BAD. */
void poll_tag_comm(struct poll_engine *e, struct ptag *t, int err)
{
	enum df1_quality q = DF1_QUALITY_BAD;

	t->last_error = err;
	if (t->r == DF1_REASON_STATION_OFFLINE)
		return;                 /* stays BAD offline until the station answers */
	if (t->has_value && (t->q == DF1_QUALITY_GOOD || t->q == DF1_QUALITY_UNCERTAIN))
		q = DF1_QUALITY_UNCERTAIN;
	poll_set_quality(e, t, q, DF1_REASON_COMM_FAILURE, false);
}

void poll_tag_good(struct poll_engine *e, struct ptag *t, const struct df1_value *v,
                   int64_t now, int64_t wall)
{
	size_t bytes = (size_t)t->cfg.count * sizeof *v;
	bool changed = !t->has_value || memcmp(t->values, v, bytes) != 0;

	if (changed)
		memcpy(t->values, v, bytes);
	t->has_value = true;
	t->last_good_ms = now;
	t->last_good_wall_ms = wall;
	t->last_error = 0;
	t->sts = t->ext = 0;
	t->saved = false;
	t->reads++;
	poll_set_quality(e, t, DF1_QUALITY_GOOD, DF1_REASON_NONE, changed);
}

void poll_tag_bad(struct poll_engine *e, struct ptag *t, enum df1_quality_reason r, int err,
                  const struct df1_error_detail *d)
{
	t->last_error = err;
	t->sts = d && err == DF1_E_REMOTE ? d->sts : 0;
	t->ext = d && err == DF1_E_REMOTE && d->has_ext_sts ? d->ext_sts : 0;
	t->saved = false;
	poll_set_quality(e, t, DF1_QUALITY_BAD, r, false);
}

/* The values of tag t out of block b's bytes (as on the wire: floats in order fo),
 * into e->vals. */
int poll_decode(struct poll_engine *e, const struct ptag *t, const struct pblock *b,
                enum value_float_order fo)
{
	const uint8_t *p = e->raw + (size_t)(t->e0 - b->first) * b->esize;
	const struct df1_addr *a = &t->cfg.addr;
	size_t es = b->esize;

	memset(e->vals, 0, (size_t)t->cfg.count * sizeof *e->vals);
	for (int i = 0; i < t->cfg.count; i++) {
		struct df1_value *v = &e->vals[i];

		switch (t->how) {
		case HOW_ELEM:
			if (value_decode_element(a->type, p + (size_t)i * es, es, v, fo) < 0)
				return DF1_E_BAD_REPLY;
			break;
		case HOW_WORD:
			v->kind = DF1_VAL_INT16;
			v->v.i16 = (int16_t)le16(p + (size_t)i * es + (size_t)t->word * 2);
			break;
		case HOW_BITS: {
			size_t g = (size_t)(a->bit + i);

			v->kind = DF1_VAL_BIT;
			if (t->word >= 0)               /* T/C/R: one word of the element */
				v->v.bit = value_get_bit(p + (size_t)t->word * 2, 2, g);
			else
				v->v.bit = value_get_bit(p, es, g);
			break;
		}
		case HOW_ALONE:
		default:
			return DF1_E_INVAL;
		}
	}
	return 0;
}

void poll_attempt(struct poll_engine *e, int stn, int64_t now)
{
	struct pstation *s = &e->st[stn];

	s->attempts++;
	s->last_attempt_ms = now;
	if (!s->first_attempt_ms)
		s->first_attempt_ms = now;
	e->stats.transactions++;
}

/* The tags of a station, through its blocks. */
#define FOR_STATION_TAGS(e, stn, t)                                                          \
	for (int b_ = (e)->st[stn].b0; b_ < (e)->st[stn].b0 + (e)->st[stn].nb; b_++)        \
		for (size_t m_ = (e)->blocks[b_].m0; m_ < (e)->blocks[b_].m0 + (e)->blocks[b_].nm; m_++) \
			if (((t) = (e)->tags[(e)->members[m_]]) != NULL)

/* The station answered (data, or a PLC error status). */
void poll_station_answer(struct poll_engine *e, int stn, int64_t now)
{
	struct pstation *s = &e->st[stn];
	struct ptag *t;

	s->fails = 0;
	s->last_good_ms = now;
	if (s->state == DF1_STATION_FAILING || s->state == DF1_STATION_OFFLINE) {
		/* doc/REQUIREMENTS.md 000: points back to their state before the failure, then a one-time
		 * poll of every point (the scan reads every block of the station now) */
		FOR_STATION_TAGS(e, stn, t) {
			if (t->saved) {
				t->saved = false;
				poll_set_quality(e, t, t->sq, t->sr, false);
			}
		}
		for (int b = s->b0; b < s->b0 + s->nb; b++)
			e->blocks[b].due_ms = 0;
		s->recovered = true;
	}
	s->state = DF1_STATION_OK;
}

/* An attempt to reach the station failed on the link. */
void poll_station_fail(struct poll_engine *e, int stn, int err, int64_t now)
{
	struct pstation *s = &e->st[stn];
	struct ptag *t;
	int64_t ref;
	bool expired;

	s->fails++;
	s->failures++;
	s->last_error = err;
	if (s->nb == 0 && s->last_good_ms == 0) {
		s->state = DF1_STATION_ABSENT;  /* discovery: nobody there (yet) */
		return;
	}
	if (s->state == DF1_STATION_OFFLINE) {
		s->next_retry_ms = now + e->wd_ms / 2;
		return;
	}
	if (s->state != DF1_STATION_FAILING) {
		s->state = DF1_STATION_FAILING;
		FOR_STATION_TAGS(e, stn, t) {
			if (!t->saved) {
				t->saved = true;
				t->sq = t->q;
				t->sr = t->r;
			}
		}
	}
	ref = s->last_good_ms ? s->last_good_ms : s->first_attempt_ms;
	expired = e->abs_retries > 0 ? s->fails > e->abs_retries : now - ref >= e->wd_ms;
	if (!expired)
		return;
	s->state = DF1_STATION_OFFLINE;
	s->next_retry_ms = now + e->wd_ms / 2;
	FOR_STATION_TAGS(e, stn, t) {
		t->last_error = err;
		poll_set_quality(e, t, DF1_QUALITY_BAD, DF1_REASON_STATION_OFFLINE, false);
	}
}

void poll_block_done(struct poll_engine *e, struct pblock *b, int64_t start)
{
	b->due_ms = start + b->period_ms;
	for (size_t m = b->m0; m < b->m0 + b->nm; m++) {
		struct ptag *t = e->tags[e->members[m]];

		t->next_due_ms = start + t->cfg.scan_ms;
	}
}

/* Attempts a station gets for a failing transaction in a scan (doc/REQUIREMENTS.md 002). */
int poll_tries(const struct pstation *s)
{
	return s->state == DF1_STATION_OK || s->state == DF1_STATION_UNKNOWN ? 1 + POLL_RETRIES_OK : 1;
}
