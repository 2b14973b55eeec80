/*
 * limits.c - the packet-limit table (plc_limits.h) for programs:
 * df1_packet_max(). Pure.
 */
#include "plc_limits.h"

int df1_packet_max(enum df1_plc plc, bool write)
{
	if ((int)plc < DF1_PLC_SLC || (int)plc > DF1_PLC_PLC2)
		return DF1_E_INVAL;
	return (int)plc_packet_max(plc, write, 0);
}
