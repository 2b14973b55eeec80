/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_format_sparkplug - the options of the Sparkplug B payload format
 * (gw_format_sparkplug.c; df1gw(1), SPARKPLUG), given to gw_fmts_enable_conf().
 */
#ifndef DF1_TOOLS_GW_FORMAT_SPARKPLUG_H
#define DF1_TOOLS_GW_FORMAT_SPARKPLUG_H

#include <stdbool.h>

#define GW_SPB_STATIONS 255

struct gw_spb_conf {
	const char *group;           /* --sparkplug GROUP_ID */
	const char *edge_node;       /* --edge-node ID */
	const char *primary_host;    /* --primary-host ID, or NULL */
	bool aliases;                /* --sparkplug-aliases */
	const char *device_name[GW_SPB_STATIONS];   /* --device-name N=NAME; NULL: "station<N>" */
};

#endif
