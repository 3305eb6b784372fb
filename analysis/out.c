/*
 * out.c — what every writer of results shares: atomic output files (a
 * temporary beside the path, renamed into place on success), CSV and HTML
 * escaping, and names as file names.
 */
#include "out.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* strerror, lowercased so that every message reads "what: detail". */
static const char *errtext(int e)
{
	static char buf[128];
	snprintf(buf, sizeof buf, "%s", strerror(e));
	if (buf[0] >= 'A' && buf[0] <= 'Z')
		buf[0] = (char)(buf[0] - 'A' + 'a');
	return buf;
}

int bk_out_open(bk_out *o, const char *path, char *err, size_t errlen)
{
	if (strlen(path) >= sizeof o->path) {
		snprintf(err, errlen, "%.64s...: path too long", path);
		return -1;
	}
	strcpy(o->path, path);
	snprintf(o->tmp, sizeof o->tmp, "%s.tmpXXXXXX", path);
	int fd = mkstemp(o->tmp);
	if (fd < 0) {
		snprintf(err, errlen, "%s: cannot create: %s", path, errtext(errno));
		return -1;
	}
	/* mkstemp creates 0600; give the file the mode a plain fopen would. */
	mode_t um = umask(0);
	umask(um);
	fchmod(fd, 0666 & ~um);
	o->f = fdopen(fd, "w");
	if (!o->f) {
		snprintf(err, errlen, "%s: %s", path, errtext(errno));
		close(fd);
		unlink(o->tmp);
		return -1;
	}
	return 0;
}

int bk_out_commit(bk_out *o, char *err, size_t errlen)
{
	int bad = ferror(o->f);
	if (fclose(o->f) != 0 || bad) {
		snprintf(err, errlen, "%s: write failed: %s", o->path, errtext(errno));
		unlink(o->tmp);
		return -1;
	}
	o->f = NULL;
	if (rename(o->tmp, o->path) != 0) {
		snprintf(err, errlen, "%s: cannot rename into place: %s", o->path, errtext(errno));
		unlink(o->tmp);
		return -1;
	}
	return 0;
}

void bk_out_abort(bk_out *o)
{
	if (o->f)
		fclose(o->f);
	o->f = NULL;
	unlink(o->tmp);
}

void bk_csv_field(FILE *f, const char *s)
{
	if (!strpbrk(s, ",\"\n")) {
		fputs(s, f);
		return;
	}
	fputc('"', f);
	for (; *s; s++) {
		if (*s == '"')
			fputc('"', f);
		fputc(*s, f);
	}
	fputc('"', f);
}

void bk_rm_tree(const char *dir)
{
	DIR *d = opendir(dir);
	if (d) {
		for (struct dirent *e; (e = readdir(d));) {
			if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
				continue;
			char path[4400];
			snprintf(path, sizeof path, "%.4000s/%.255s", dir, e->d_name);
			struct stat st;
			if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
				bk_rm_tree(path);
			else
				unlink(path);
		}
		closedir(d);
	}
	rmdir(dir);
}


void bk_slug(const char *name, char *buf, size_t len)
{
	size_t k = 0;
	for (; *name && k + 1 < len; name++) {
		char c = *name;
		if ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')
			buf[k++] = c;
		else if (c >= 'A' && c <= 'Z')
			buf[k++] = (char)(c - 'A' + 'a');
		else if (k && buf[k - 1] != '_')
			buf[k++] = '_';
	}
	while (k && buf[k - 1] == '_')
		k--;
	buf[k] = '\0';
}

void bk_html_text(FILE *f, const char *s)
{
	for (; *s; s++)
		switch (*s) {
		case '&': fputs("&amp;", f); break;
		case '<': fputs("&lt;", f); break;
		case '>': fputs("&gt;", f); break;
		case '"': fputs("&quot;", f); break;
		default: fputc(*s, f);
		}
}
