/*
 * fault.c - fault injection on the serving side (df1_server_set_fault,
 * df1_server_set_seed; core.c, full.c and half.c decide where each fault
 * acts). Deterministic: xorshift64* from the seed, advanced
 * by each roll of a fault switched on below 1000 per mille and by each burst
 * of noise bytes, so the same seed, faults and traffic inject the same faults.
 */
#include "link.h"

#include "link_int.h"

static uint64_t fault_next(struct link_faults *f)
{
	uint64_t x = f->rng ? f->rng : 0x9E3779B97F4A7C15ull;

	x ^= x >> 12; /* xorshift64* */
	x ^= x << 25;
	x ^= x >> 27;
	f->rng = x;
	return x * 0x2545F4914F6CDD1Dull;
}

bool link_fault(struct df1 *h, enum df1_fault f)
{
	int pm;

	if ((int)f < 1 || (int)f >= FAULT_KINDS)
		return false;
	pm = h->faults.per_mille[f];
	if (pm <= 0)
		return false;
	if (pm >= 1000)
		return true;
	return fault_next(&h->faults) % 1000u < (uint64_t)pm;
}

bool link_fault_silent(struct df1 *h, uint8_t station)
{
	int v = h->faults.value[DF1_FAULT_SILENT_STATION];

	if (h->faults.per_mille[DF1_FAULT_SILENT_STATION] <= 0 ||
	    (v != station && v != FAULT_SILENT_ALL))
		return false;
	return link_fault(h, DF1_FAULT_SILENT_STATION);
}

bool link_fault_silent_all(struct df1 *h)
{
	if (h->faults.per_mille[DF1_FAULT_SILENT_STATION] <= 0 ||
	    h->faults.value[DF1_FAULT_SILENT_STATION] != FAULT_SILENT_ALL)
		return false;
	return link_fault(h, DF1_FAULT_SILENT_STATION);
}

DF1_API int df1_server_set_fault(df1_t *h, enum df1_fault f, int per_mille, int value)
{
	if (!h)
		return DF1_E_INVAL;
	if ((int)f < 1 || (int)f >= FAULT_KINDS)
		return df1_fail(h, DF1_E_INVAL, -1, "unknown fault kind %d", (int)f);
	if (per_mille < 0 || per_mille > 1000)
		return df1_fail(h, DF1_E_INVAL, -1, "fault probability %d: must be 0..1000 per mille",
		                per_mille);
	if (f == DF1_FAULT_DELAY_REPLY && (value < 0 || value > 3600000))
		return df1_fail(h, DF1_E_INVAL, -1, "reply delay %d ms: must be 0..3600000", value);
	if (f == DF1_FAULT_SILENT_STATION && (value < -1 || value > FAULT_SILENT_ALL))
		return df1_fail(h, DF1_E_INVAL, -1,
		                "silent station %d: must be -1 (none), 0..255, or %d (every station)",
		                value, FAULT_SILENT_ALL);
	h->faults.per_mille[f] = per_mille;
	h->faults.value[f] = value;
	if (f == DF1_FAULT_SILENT_STATION)
		h->link.silenced = false; /* the ENQs after a silenced frame: answered again */
	return 0;
}

DF1_API void df1_server_set_seed(df1_t *h, uint64_t seed)
{
	if (h)
		h->faults.rng = seed ? seed : 0x9E3779B97F4A7C15ull;
}

/* Three garbage bytes, none of them DLE: noise the receiver must skip. */
size_t link_noise_bytes(struct df1 *h, uint8_t *out)
{
	uint64_t r = fault_next(&h->faults);

	for (int i = 0; i < 3; i++) {
		uint8_t b = (uint8_t)(r >> (8 * i));

		out[i] = b == DF1_DLE ? 0x55 : b;
	}
	return 3;
}
