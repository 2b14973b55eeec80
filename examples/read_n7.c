/* SPDX-License-Identifier: MPL-2.0 */
/*
 * read_n7.c - read N7:0..9 from a PLC with libdf1 and print them.
 *
 *   cc -o read_n7 read_n7.c $(pkg-config --cflags --libs libdf1)
 *   ./read_n7 /dev/ttyUSB0 1            (device, destination station)
 *   ./read_n7 tcp://10.0.0.20:2101 3    (raw DF1 through a serial device server)
 *
 * The handle's life: df1_new (defaults, no I/O) -> df1_set_* (store settings)
 * -> df1_open -> df1_read_* ... -> df1_free (closes the port and restores its
 * settings). Every function returns >= 0 on success and a negative DF1_E_*
 * code on failure; df1_last_error() tells what went wrong in detail.
 */
#include <df1.h>

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
	df1_t *h = NULL;
	int16_t v[10];
	char *end;
	long station;
	int rc;

	if (argc != 3) {
		fprintf(stderr, "usage: %s DEVICE STATION\n", argv[0]);
		return 2;
	}
	station = strtol(argv[2], &end, 10);
	if (*argv[2] == '\0' || *end != '\0' || station < 0 || station > 254) {
		fprintf(stderr, "%s: station must be 0-254\n", argv[0]);
		return 2;
	}

	/* A handle with the defaults: 19200 8N1, full duplex, CRC, SLC commands,
	 * our own station 0. Nothing is opened yet. */
	rc = df1_new(&h);
	if (rc < 0) {
		fprintf(stderr, "df1_new: %s\n", df1_strerror(rc));
		return 1;
	}
	/* Settings are stored on the handle; for a half-duplex line with BCC:
	 *   df1_set_duplex(h, DF1_HALF_DUPLEX_MASTER);
	 *   df1_set_check(h, DF1_CHECK_BCC);
	 */
	df1_set_timeout_ms(h, 1000);

	/* Open the serial port (or TCP connection). The error's message names the
	 * device ("no such device: /dev/ttyUSB9"). */
	rc = df1_open(h, argv[1]);
	if (rc < 0) {
		fprintf(stderr, "%s: %s: %s\n", argv[0], df1_errname(rc), df1_last_error(h)->message);
		df1_free(h);
		return 1;
	}

	/* Read 10 integers from N7:0. The library picks the command for the PLC
	 * type and splits requests larger than one packet. It returns the number
	 * of elements read, or a negative error code. */
	rc = df1_read_int16(h, (int)station, "N7:0", v, 10);
	if (rc < 0) {
		/* The detail: catalog ID, the address it concerns (since 0.2 in its
		 * own field, "" when none), and a message that names the station;
		 * for an error reply of the PLC, its STS and EXT STS with their text:
		 *   read_n7: [2508] ERR_COMMAND_TIMEOUT: N7:0: no reply from station 1 */
		const struct df1_error_detail *e = df1_last_error(h);
		const struct df1_catalog_entry *c = df1_catalog_by_id(e->catalog_id);

		fprintf(stderr, "%s: ", argv[0]);
		if (c)
			fprintf(stderr, "[%d] %s: ", c->id, c->mnemonic);
		else
			fprintf(stderr, "%s: ", df1_errname(rc));
		if (e->address[0])
			fprintf(stderr, "%s: ", e->address);
		fprintf(stderr, "%s\n", e->message);
		df1_free(h);
		return 1;
	}
	for (int i = 0; i < rc; i++)
		printf("N7:%d = %d\n", i, v[i]);

	df1_free(h);    /* closes the port, restoring its settings */
	return 0;
}
