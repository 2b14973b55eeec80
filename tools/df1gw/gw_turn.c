/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_turn - the round robin between the bridge and the MQTT writes (see
 * gw_turn.h).
 */
#include "df1gw/gw_turn.h"

enum gw_turn gw_turn_next(const struct gw_turn_state *s)
{
	/* one batch on the line at a time, and batches start between two df1_poll
	 * calls only: inside one, the engine would run it before its next read */
	bool batch_waits = s->backlog > 0 && s->batch == 0 && !s->in_line;
	/* a full batch ran since the last read and a read is due: the read first */
	bool read_first = batch_waits && s->since_read >= s->duty && s->poll_due;
	bool batch_may = batch_waits && !read_first;

	if (s->bridge > 0 && batch_may)
		return s->last == GW_TURN_BRIDGE ? GW_TURN_WRITES : GW_TURN_BRIDGE;
	if (s->bridge > 0)
		return GW_TURN_BRIDGE;  /* behind the batch on the line, if any: its turn came */
	if (batch_may)
		return GW_TURN_WRITES;
	return read_first ? GW_TURN_POLL : GW_TURN_NONE;
}

const char *gw_turn_name(enum gw_turn t)
{
	switch (t) {
	case GW_TURN_NONE: return "none";
	case GW_TURN_BRIDGE: return "bridge";
	case GW_TURN_WRITES: return "writes";
	case GW_TURN_POLL: return "poll";
	}
	return "?";
}
