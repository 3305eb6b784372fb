/*
 * cmd_terms.c — brdfkit terms: the registry, readable or as CSV.
 */
#include "brdf.h"
#include "cli.h"
#include "out.h"
#include "cmd.h"

#include <string.h>

/* Both options act in every run: there is no context to depend on. */
static const cli_rule rules[] = {
	{"--role", NULL, CLI_EVERYWHERE, 0, NULL, "D"},
	{"--csv", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
};
static const char *const setups[] = {"", NULL};
static const cli_table table = {NULL, 0, rules, sizeof rules / sizeof rules[0], setups};

int cmd_terms(int argc, char **argv)
{
	const char *role = NULL;
	int csv = 0;
	cli_opt opts[] = {
		{.name = "--role", .kind = CLI_STR, .metavar = "D|V|F|Fd", .help = "only terms of this role", .dest = &role},
		{.name = "--csv", .kind = CLI_FLAG, .help = "CSV with header name,role,args,summary,convention,citation", .dest = &csv},
	};
	cli_cmd cmd = {"terms", "Lists every term of libbrdf: name (as the formula language spells it), "
	               "arguments,\nwhat it computes, its convention and its citation.",
	               "[--role D|V|F|Fd] [--csv]", NULL, opts, 2, 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, NULL)))
		return rc == 1 ? 0 : rc;
	int want = -1;
	if (role) {
		for (int r = BK_ROLE_D; r <= BK_ROLE_FD; r++)
			if (strcmp(role, bk_role_name((bk_role)r)) == 0)
				want = r;
		if (want < 0) {
			return cli_bad("--role: unknown role '%s' (expected D, V, F or Fd)", role);
		}
	}
	if (csv)
		puts("name,role,args,summary,convention,citation");
	for (size_t i = 0; i < bk_term_count(); i++) {
		const bk_term *t = bk_term_at(i);
		if (want >= 0 && (int)t->role != want)
			continue;
		if (csv) {
			const char *f[6] = {t->name, bk_role_name(t->role), t->args, t->summary,
			                    t->convention, t->citation};
			for (int k = 0; k < 6; k++) {
				if (k)
					putchar(',');
				bk_csv_field(stdout, f[k]);
			}
			putchar('\n');
		} else {
			printf("%s(%s)  [%s]\n    %s\n    convention: %s\n    source: %s\n", t->name,
			       t->args, bk_role_name(t->role), t->summary, t->convention, t->citation);
		}
	}
	return 0;
}
