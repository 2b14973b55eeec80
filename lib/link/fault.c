/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fault.c - the fault dice of the serving side (the faults are set with
 * df1_server_set_fault and df1_server_set_seed, lib/server/server_api.c, into the
 * responder state; core.c, full.c and half.c decide where each fault acts). Deterministic: xorshift64* from the seed, advanced
 * by each roll of a fault switched on below 1000 per mille and by each burst
 * of noise bytes, so the same seed, faults and traffic inject the same faults.
 */
#include "link/link.h"

#include "link/link_int.h"

static uint64_t fault_next(struct link_faults *f)
{
	uint64_t x = f->rng ? f->rng : 0x9E3779B97F4A7C15ull;

	x ^= x >> 12; /* xorshift64* */
	x ^= x << 25;
	x ^= x >> 27;
	f->rng = x;
	return x * 0x2545F4914F6CDD1Dull;
}

bool link_fault(struct link_responder *r, enum df1_fault f)
{
	int pm;

	if ((int)f < 1 || (int)f >= FAULT_KINDS)
		return false;
	pm = r->faults.per_mille[f];
	if (pm <= 0)
		return false;
	if (pm >= 1000)
		return true;
	return fault_next(&r->faults) % 1000u < (uint64_t)pm;
}

bool link_fault_silent(struct link_responder *r, uint8_t station)
{
	int v = r->faults.value[DF1_FAULT_SILENT_STATION];

	if (r->faults.per_mille[DF1_FAULT_SILENT_STATION] <= 0 ||
	    (v != station && v != FAULT_SILENT_ALL))
		return false;
	return link_fault(r, DF1_FAULT_SILENT_STATION);
}

bool link_fault_silent_all(struct link_responder *r)
{
	if (r->faults.per_mille[DF1_FAULT_SILENT_STATION] <= 0 ||
	    r->faults.value[DF1_FAULT_SILENT_STATION] != FAULT_SILENT_ALL)
		return false;
	return link_fault(r, DF1_FAULT_SILENT_STATION);
}

/* Three garbage bytes, none of them DLE: noise the receiver must skip. */
size_t link_noise_bytes(struct link_responder *r, uint8_t *out)
{
	uint64_t x = fault_next(&r->faults);

	for (int i = 0; i < 3; i++) {
		uint8_t b = (uint8_t)(x >> (8 * i));

		out[i] = b == DF1_DLE ? 0x55 : b;
	}
	return 3;
}
