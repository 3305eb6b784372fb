/*
 * test_prov.c — the provenance lines of brdfkit's CSVs (analysis/prov.h),
 * byte for byte: the texts here are typed out, not built by the module.
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdf.h" /* BK_VERSION */
#include "prov.h"

/* A memory stream for one test; got() closes it and returns its bytes. */
static char *buf;
static size_t len;
static FILE *open_mem(void)
{
	FILE *f = open_memstream(&buf, &len);
	cr_assert_not_null(f);
	return f;
}
static const char *got(FILE *f)
{
	cr_assert_eq(fclose(f), 0);
	return buf;
}

Test(prov, header_with_target)
{
	FILE *f = open_mem();
	bk_prov_header(f, "brdfkit fit --target f --out x", "f: exact Fresnel", "fitted %s", "coefficients");
	cr_assert_str_eq(got(f), "# brdfkit " BK_VERSION " fitted coefficients\n"
	                         "# command: brdfkit fit --target f --out x\n"
	                         "# target: f: exact Fresnel\n");
	free(buf);
}

Test(prov, header_without_target_and_empty_command)
{
	FILE *f = open_mem();
	bk_prov_header(f, NULL, NULL, "stability: %d forms", 3);
	cr_assert_str_eq(got(f), "# brdfkit " BK_VERSION " stability: 3 forms\n# command: \n");
	free(buf);
}

/* A line break goes on as a comment line, CR is dropped, every other control
 * character is a space: no text starts a row of data. The negative control:
 * the raw text would have put "b" at the start of a line. */
Test(prov, control_characters_stay_in_the_comment)
{
	static const char raw[] = "a\nb\rc\td\x1b" "e\x7f" "f";
	FILE *f = open_mem();
	bk_prov_command(f, raw);
	bk_prov_target(f, "t\n");
	const char *s = got(f);
	cr_assert_str_eq(s, "# command: a\n# bc d e f\n# target: t\n# \n");
	for (const char *p = s; (p = strchr(p, '\n')) && p[1]; p++)
		cr_assert_eq(p[1], '#', "a line that is not a comment: %s", p + 1);
	cr_assert_not_null(strstr(raw, "\nb"), "control: the raw text breaks a line before 'b'");
	free(buf);
}

/* A title longer than the stack buffer (1024 bytes) is written whole. */
Test(prov, long_title_whole)
{
	char word[3001];
	memset(word, 'x', sizeof word - 1);
	word[sizeof word - 1] = '\0';
	FILE *f = open_mem();
	bk_prov_title(f, "gpucost: %s.", word);
	const char *s = got(f);
	const char *lead = "# brdfkit " BK_VERSION " gpucost: ";
	cr_assert_eq(strlen(s), strlen(lead) + 3000 + 2, "%zu bytes", strlen(s));
	cr_assert_eq(strncmp(s, lead, strlen(lead)), 0);
	cr_assert_str_eq(s + strlen(s) - 3, "x.\n");
	free(buf);
}
