/* SPDX-License-Identifier: MPL-2.0 */
/*
 * pccc_class.c - which PCCC commands only read (doc/PROTOCOL.md 4, the
 * command list): the rule for a command that is never sent twice once it may
 * have reached the controller (df1_poll_submit_pccc) and for a bridge that
 * gives data and no control (df1gw --eip-read-only). Pure.
 */
#include "proto/pccc.h"

/* FNC of CMD 06 that read: echo, diagnostic read, diagnostic status. The other
 * FNCs set interface variables, timeouts, retry counts or reset counters. */
static bool pccc_diag_reads(uint8_t fnc)
{
	return fnc == PCCC_FNC_ECHO || fnc == PCCC_FNC_DIAG_READ || fnc == PCCC_FNC_DIAG_STATUS;
}

/* FNC of CMD 0F that read: word range read, typed read, SLC typed logical
 * reads (2 and 3 address fields; file directory reads use 0F/A2 too). Writes,
 * bit writes, read-modify-write, mode changes, uploads and downloads and every
 * FNC not listed here count as writes. */
static bool pccc_typed_reads(uint8_t fnc)
{
	return fnc == PCCC_FNC_WORD_READ || fnc == PCCC_FNC_TYPED_READ || fnc == PCCC_FNC_SLC_READ2 ||
	       fnc == PCCC_FNC_SLC_READ3;
}

bool df1_pccc_is_write(const uint8_t *pccc, size_t n)
{
	uint8_t cmd;

	if (!pccc || n < 4)
		return true;            /* not a command we can tell: assume the worst */
	cmd = pccc[0];
	if (cmd == PCCC_CMD_UNPROT_READ)
		return false;           /* PLC-2 unprotected read: no FNC */
	if (n < 5)
		return true;
	if (cmd == PCCC_CMD_DIAG)
		return !pccc_diag_reads(pccc[4]);
	if (cmd == PCCC_CMD_TYPED)
		return !pccc_typed_reads(pccc[4]);
	return true;                    /* 00 02 05 08 write; 0B 1A 1B and the rest unknown */
}
