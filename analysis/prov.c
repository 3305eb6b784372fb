/*
 * prov.c — the provenance header of brdfkit's CSVs (prov.h).
 */
#include "prov.h"
#include "brdf.h" /* BK_VERSION */

#include <stdarg.h>
#include <stdlib.h>

/* lead, then text kept to comment lines (prov.h), then a line break. */
static void line(FILE *f, const char *lead, const char *text)
{
	fputs(lead, f);
	for (const unsigned char *p = (const unsigned char *)text; *p; p++) {
		if (*p == '\n')
			fputs("\n# ", f);
		else if (*p != '\r')
			fputc(*p < 0x20 || *p == 0x7f ? ' ' : *p, f);
	}
	fputc('\n', f);
}

/* The title line: the text formatted into a stack buffer, or into one of
 * its own size when longer; out of memory, the text cut at the buffer's
 * size (the line still says who wrote the file). */
static void vtitle(FILE *f, const char *fmt, va_list ap)
{
	char buf[1024], *big = NULL;
	va_list again;
	va_copy(again, ap);
	int n = vsnprintf(buf, sizeof buf, fmt, ap);
	if (n >= (int)sizeof buf && (big = malloc((size_t)n + 1)))
		vsnprintf(big, (size_t)n + 1, fmt, again);
	va_end(again);
	line(f, "# brdfkit " BK_VERSION " ", big ? big : n < 0 ? "" : buf);
	free(big);
}

void bk_prov_title(FILE *f, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vtitle(f, fmt, ap);
	va_end(ap);
}

void bk_prov_command(FILE *f, const char *command)
{
	line(f, "# command: ", command ? command : "");
}

void bk_prov_target(FILE *f, const char *description)
{
	line(f, "# target: ", description ? description : "");
}

void bk_prov_header(FILE *f, const char *command, const char *target, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vtitle(f, fmt, ap);
	va_end(ap);
	bk_prov_command(f, command);
	if (target)
		bk_prov_target(f, target);
}
