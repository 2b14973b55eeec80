/* SPDX-License-Identifier: MPL-2.0 */
/*
 * table_serve.c - df1_table_server_ops(): the struct df1_server_ops that serve
 * a data table through df1_serve() (df1_table(3); the contract of lib/server/server.h).
 * The responder turns every command set (SLC typed, PLC-5 typed and word range,
 * PLC-2, masked and bit writes) into these element reads and masked writes.
 */
#include "table/table.h"

#include <string.h>

static int table_op_read(void *user, int station, const struct df1_addr *a, uint8_t *buf, size_t nbytes)
{
	uint8_t *p = NULL;
	int rc = table_locate(user, a, nbytes, &p);

	(void)station;
	if (rc == 0 && nbytes)
		memcpy(buf, p, nbytes);
	return rc;
}

static int table_op_write(void *user, int station, const struct df1_addr *a, const uint8_t *buf,
                          const uint8_t *mask, size_t nbytes)
{
	uint8_t *p = NULL;
	int rc = table_locate(user, a, nbytes, &p);

	(void)station;
	if (rc)
		return rc;
	for (size_t i = 0; i < nbytes; i++)
		p[i] = mask ? (uint8_t)((p[i] & ~mask[i]) | (buf[i] & mask[i])) : buf[i];
	return 0;
}

static int table_op_change_mode(void *user, int station, int mode)
{
	struct df1_table *t = user;

	(void)station;
	if (mode != 1 && mode != 6 && mode != 7 && mode != 8)
		return 0x01;            /* a field has an illegal value */
	t->mode = mode;
	return 0;
}

static int table_op_diag_status(void *user, int station, uint8_t *buf, size_t cap)
{
	int rc = table_diag_status(user, station, buf, cap);

	return rc < 0 ? -0x10 : rc;     /* no room: STS 10h, illegal command or format */
}

static const struct df1_server_ops table_ops = {
	.read = table_op_read,
	.write = table_op_write,
	.diag_status = table_op_diag_status,
	.change_mode = table_op_change_mode,
};

const struct df1_server_ops *df1_table_server_ops(const struct df1_table *t)
{
	return t ? &table_ops : NULL;
}
