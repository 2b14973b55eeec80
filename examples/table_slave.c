/* SPDX-License-Identifier: MPL-2.0 */
/*
 * table_slave.c - a simulated SLC 5/04 with libdf1's data table: the files
 * O0 I1 S2 B3 T4 C5 R6 N7 F8 ST9 L10 A11 of 256 elements (N7:n = n ...),
 * served as a full-duplex DF1 peer on a pseudo-terminal, or on a port.
 *
 *   cc -o table_slave table_slave.c $(pkg-config --cflags --libs libdf1)
 *   ./table_slave                 prints the pty to use: df1read -d /dev/pts/5 N7:0,10
 *   ./table_slave /dev/ttyUSB0    serves a serial port (19200 8N1, CRC)
 *   ./table_slave - data.txt      a pty again, with initial values from data.txt
 *                                 (df1sim --data's format, see df1_table_load(3))
 *
 * The table answers reads and writes of every command set, masked and bit
 * writes, the diagnostic status (06/03) and mode changes (0F/80); it lives
 * in the program's memory until df1_table_free().
 */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE         /* cfmakeraw */
#endif
#ifndef _XOPEN_SOURCE
#define _XOPEN_SOURCE 700       /* posix_openpt, grantpt, ptsname */
#endif
#include <df1.h>

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <termios.h>

int main(int argc, char **argv)
{
	struct df1_table *t = NULL;
	df1_t *h = NULL;
	int rc, status = 1;

	if (df1_table_new(&t, DF1_PLC_SLC) < 0 || df1_table_add_default_files(t) < 0 || df1_new(&h) < 0)
		goto out;
	if (argc > 2 && df1_table_load(t, argv[2]) < 0) {
		fprintf(stderr, "%s: %s\n", argv[0], df1_table_error_text(t));
		status = 2;
		goto out;
	}
	if (argc > 1 && argv[1][0] != '-') {
		rc = df1_open(h, argv[1]);
		printf("%s\n", argv[1]);
	} else {
		/* a pty; our own descriptor on its slave side, raw, so that the
		 * master side sees no hangup between clients and echoes nothing */
		struct termios tio;
		int fd = posix_openpt(O_RDWR | O_NOCTTY), slave;

		if (fd < 0 || grantpt(fd) < 0 || unlockpt(fd) < 0 ||
		    (slave = open(ptsname(fd), O_RDWR | O_NOCTTY)) < 0)
			goto out;
		if (tcgetattr(slave, &tio) == 0) {
			cfmakeraw(&tio);
			tcsetattr(slave, TCSANOW, &tio);
		}
		rc = df1_open_fd(h, fd, true);
		printf("%s\n", ptsname(fd));
	}
	if (rc < 0) {
		fprintf(stderr, "%s: %s\n", argv[0], df1_last_error(h)->message);
		goto out;
	}
	fflush(stdout);

	/* the whole slave: serve the table until the line fails */
	while ((rc = df1_serve(h, df1_table_server_ops(t), t, 1000)) >= 0)
		;
	fprintf(stderr, "%s: %s\n", argv[0], df1_strerror(rc));
out:
	df1_free(h);            /* NULL is a no-op */
	df1_table_free(t);
	return status;
}
