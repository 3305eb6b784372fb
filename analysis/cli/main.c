/*
 * main.c — brdfkit, the one command-line tool: a table of subcommands.
 */
#include "brdf.h"
#include "cli.h"
#include "cmd.h"
#include "out.h"

#include <stdio.h>
#include <string.h>

static const struct {
	const char *name;
	int (*run)(int argc, char **argv);
	const char *summary;
} commands[] = {
	{"terms", cmd_terms, "list every term: name, what it computes, convention, citation"},
	{"dfg", cmd_dfg, "split-sum environment BRDF A, B at given NoV and roughness"},
	{"lut", cmd_lut, "write the DFG look-up table as OpenEXR and CSV into a directory"},
	{"albedo", cmd_albedo, "directional albedo of any D·V·F combination"},
	{"eval", cmd_eval, "evaluate a form in double, single and half precision"},
	{"ops", cmd_ops, "op counts per class and the cost of a form"},
	{"codegen", cmd_codegen, "generate a C, GLSL or HLSL function from a form"},
	{"catalog", cmd_catalog, "the published forms, as CSV"},
	{"fit", cmd_fit, "fit a form to a target with Ceres; tables, heatmaps, shaders"},
	{"time", cmd_time, "CPU ns per evaluation of forms (generated C, cc -O2) and SPIR-V size"},
	{"stability", cmd_stability, "half/single/double precision on stiff and extreme inputs; guards"},
	{"report", cmd_report, "the study's page from the compare sections"},
	{"search", cmd_search, "search closed forms: candidates fitted, the Pareto front of error against cost"},
	{"scene", cmd_scene, "from a scene file to one specialised, refitted shader per feature set"},
	{"compare", cmd_compare, "error against cost: catalog forms, refits, LUTs, the Pareto front"},
	{"gpucost", cmd_gpucost, "AMD machine code of forms (Mesa RADV null device, ACO), net of a baseline"},
	{"render", cmd_render, "spheres: exact BRDF, a candidate and their difference, emitted GLSL on lavapipe (single, half)"},
};

static void usage(FILE *out)
{
	fprintf(out, "usage: brdfkit COMMAND [options]   (brdfkit COMMAND --help for each)\n\n"
	             "brdfkit %s — exact BRDF terms, reference integrals and their approximations.\n"
	             "Conventions: r perceptual roughness, a = r^2, V = G/(4 NoL NoV), F Schlick\n"
	             "with f90 = 1, split sum f0·A + B (see brdf/brdf.h). Every command takes --help\n"
	             "and --quiet (no progress lines); precision is spelled double, single or half.\n\ncommands:\n",
	        BK_VERSION);
	for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
		fprintf(out, "  %-8s %s\n", commands[i].name, commands[i].summary);
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return 2;
	}
	if (strcmp(argv[1], "help") == 0 && argc == 3 && strcmp(argv[2], "--applicability") == 0) {
		/* hidden: every command's option-applicability table (cli.h), for
		 * tests/cli_opts.sh; a command without one prints "none" */
		char flag[] = "--help-applicability", *args[] = {flag, NULL};
		for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
			commands[i].run(1, args);
		return 0;
	}
	if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
	    strcmp(argv[1], "help") == 0) {
		usage(stdout);
		return 0;
	}
	if (strcmp(argv[1], "--version") == 0) {
		printf("brdfkit %s\n", BK_VERSION);
		return 0;
	}
	/* the command line for output markers; temporaries removed on SIGINT/SIGTERM */
	bk_out_init(argc, argv);
	for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
		if (strcmp(argv[1], commands[i].name) == 0)
			return commands[i].run(argc - 2, argv + 2);
	const char *names[sizeof commands / sizeof commands[0]];
	for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
		names[i] = commands[i].name;
	const char *near = cli_suggest(argv[1], names, (int)(sizeof names / sizeof names[0]));
	if (near)
		fprintf(stderr, "brdfkit: unknown command '%.60s'; did you mean '%s'? (see brdfkit --help)\n", argv[1], near);
	else
		fprintf(stderr, "brdfkit: unknown command '%.60s' (see brdfkit --help)\n", argv[1]);
	return 2;
}
