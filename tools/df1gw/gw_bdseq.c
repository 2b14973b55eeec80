/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_bdseq - Sparkplug's bdSeq kept across restarts (see gw_bdseq.h).
 */
#include "df1gw/gw_bdseq.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef NAME_MAX
#define NAME_MAX 255
#endif

int gw_bdseq_dir(char *out, size_t cap)
{
	const char *sd = getenv("STATE_DIRECTORY");
	const char *xdg = getenv("XDG_STATE_HOME");
	const char *home = getenv("HOME");
	int n = -1;

	if (cap)
		out[0] = '\0';
	if (sd && sd[0] == '/') {
		size_t len = strcspn(sd, ":");       /* systemd lists several with ':' */

		n = snprintf(out, cap, "%.*s", (int)len, sd);
	} else if (xdg && xdg[0] == '/') {     /* a relative one is to be ignored (XDG) */
		n = snprintf(out, cap, "%s/df1gw", xdg);
	} else if (home && home[0]) {
		n = snprintf(out, cap, "%s/.local/state/df1gw", home);
	}
	if (n < 0 || (size_t)n >= cap) {
		if (cap)
			out[0] = '\0';
		return -1;
	}
	return 0;
}

/* id, escaped, appended at *at (room: end). */
static int put_id(char **at, const char *end, const char *id)
{
	static const char hex[] = "0123456789ABCDEF";

	for (const unsigned char *p = (const unsigned char *)id; *p; p++) {
		bool plain = (*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') ||
		             *p == '-' || *p == '_' || *p == '.';

		if (end - *at < (plain ? 2 : 4))
			return -1;
		if (plain) {
			*(*at)++ = (char)*p;
		} else {
			*(*at)++ = '%';
			*(*at)++ = hex[*p >> 4];
			*(*at)++ = hex[*p & 15];
		}
	}
	**at = '\0';
	return 0;
}

int gw_bdseq_path(const char *dir, const char *group, const char *edge, char *out, size_t cap)
{
	char name[NAME_MAX + 1], *at = name, *end = name + sizeof name;
	int n;

	if (put_id(&at, end, group) < 0 || end - at < 2)
		return -1;
	*at++ = '@';
	if (put_id(&at, end, edge) < 0 || (size_t)(end - at) <= strlen(GW_BDSEQ_SUFFIX))
		return -1;
	strcpy(at, GW_BDSEQ_SUFFIX);
	n = snprintf(out, cap, "%s/%s", dir, name);
	return n < 0 || (size_t)n >= cap ? -1 : 0;
}

int gw_bdseq_mkdir(const char *dir)
{
	char p[PATH_MAX];
	size_t len = strlen(dir);

	if (len == 0 || len >= sizeof p) {
		errno = ENAMETOOLONG;
		return -1;
	}
	memcpy(p, dir, len + 1);
	for (char *s = p + 1; ; s++) {
		if (*s != '/' && *s != '\0')
			continue;
		char c = *s;

		*s = '\0';
		if (mkdir(p, 0700) < 0 && errno != EEXIST)
			return -1;
		*s = c;
		if (!c)
			break;
	}
	return access(dir, W_OK | X_OK);
}

int gw_bdseq_read(const char *path, unsigned *last)
{
	FILE *fp = fopen(path, "r");
	unsigned v;
	char extra;
	int n;

	if (!fp)
		return errno == ENOENT ? 0 : -1;
	n = fscanf(fp, "bdSeq %u%c", &v, &extra);
	fclose(fp);
	if (n < 1 || v > 255 || (n == 2 && extra != '\n')) {
		errno = EINVAL;
		return -1;
	}
	*last = v;
	return 1;
}

/* The folder of path made durable (the rename in it). */
static int sync_dir(const char *path)
{
	char d[PATH_MAX];
	const char *slash = strrchr(path, '/');
	int fd, r;

	if (!slash)
		snprintf(d, sizeof d, ".");
	else if (slash == path)
		snprintf(d, sizeof d, "/");
	else
		snprintf(d, sizeof d, "%.*s", (int)(slash - path), path);
	fd = open(d, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
	if (fd < 0)
		return -1;
	r = fsync(fd);
	close(fd);
	return r;
}

int gw_bdseq_write(const char *path, unsigned bdseq)
{
	char tmp[PATH_MAX], line[32];
	int fd, n, len, e;

	n = snprintf(tmp, sizeof tmp, "%s.new", path);
	if (n < 0 || (size_t)n >= sizeof tmp) {
		errno = ENAMETOOLONG;
		return -1;
	}
	len = snprintf(line, sizeof line, "bdSeq %u\n", bdseq & 0xFFu);
	fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
	if (fd < 0)
		return -1;
	errno = 0;
	if (write(fd, line, (size_t)len) != len || fsync(fd) < 0) {
		e = errno ? errno : EIO;
		close(fd);
		unlink(tmp);
		errno = e;
		return -1;
	}
	if (close(fd) < 0 || rename(tmp, path) < 0) {
		e = errno;
		unlink(tmp);
		errno = e;
		return -1;
	}
	return sync_dir(path);
}
