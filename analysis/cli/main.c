/*
 * main.c — brdfkit, the one command-line tool: a table of subcommands.
 */
#include "brdf.h"
#include "cli.h"
#include "cmd.h"
#include "out.h"

#include <errno.h>
#include <fcntl.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

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

/* One command line, argv[0] "brdfkit", argv[1] the command. */
static int run_command(int argc, char **argv)
{
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

/* Hidden, for tests/cli_opts.sh's walk: each line of LIST is one case, the
 * words after "brdfkit" separated by \037, and runs as `brdfkit WORDS
 * --check-options` would, in a process of its own, its standard output and
 * error to DIR/N.out and DIR/N.err (N its line, from 1; standard input
 * /dev/null); "N<tab>STATUS" is printed for each. The process is a fork of
 * this one, not a new start: the walk's ~1,450 cases were as many starts of
 * the tool, most of its time sanitized (LeakSanitizer still checks each case
 * at its exit). */
static int check_each(const char *list, const char *dir)
{
	/* the whole list read first (cli_read_file, cli.h): a case's exit flushes
	 * an inherited stream, which moves the offset of the descriptor it
	 * shares with this process */
	size_t len;
	char *text = cli_read_file(list, &len);
	if (!text) {
		fprintf(stderr, "brdfkit help --check-each: %s: %s\n", list, strerror(errno));
		return 2;
	}
	int rc = 0;
	long n = 0;
	for (char *line = text, *next; rc == 0 && line && *line; line = next) {
		next = strchr(line, '\n');
		if (next)
			*next++ = 0;
		n++;
		char *argv[256];
		int argc = 0;
		argv[argc++] = "brdfkit";
		for (char *w = strtok(line, "\037"); w && argc < 254; w = strtok(NULL, "\037"))
			argv[argc++] = w;
		if (argc < 2 || argc == 254) {
			fprintf(stderr, "brdfkit help --check-each: %s:%ld: no command, or over 252 words\n", list, n);
			rc = 2;
			break;
		}
		argv[argc++] = "--check-options";
		argv[argc] = NULL;
		char out[4096], err[4096];
		snprintf(out, sizeof out, "%s/%ld.out", dir, n);
		snprintf(err, sizeof err, "%s/%ld.err", dir, n);
		fflush(NULL); /* nothing buffered twice */
		pid_t pid = fork();
		if (pid == 0) {
			int fi = open("/dev/null", O_RDONLY), fo = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0644),
			    fe = open(err, O_WRONLY | O_CREAT | O_TRUNC, 0644);
			if (fi < 0 || fo < 0 || fe < 0 || dup2(fi, 0) < 0 || dup2(fo, 1) < 0 || dup2(fe, 2) < 0)
				_exit(125);
			close(fi), close(fo), close(fe);
			exit(run_command(argc, argv));
		}
		int st;
		if (pid < 0 || waitpid(pid, &st, 0) != pid) {
			fprintf(stderr, "brdfkit help --check-each: %s:%ld: the case's process failed\n", list, n);
			rc = 2;
			break;
		}
		printf("%ld\t%d\n", n, WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st));
	}
	free(text);
	return rc;
}

/* Freed memory stays with the process. glibc's defaults hand a block of
 * 128 KB and over back to the kernel as it is freed (mmap, trim of the heap's
 * top, madvise of a thread's arena), and the next such block faults its
 * pages in again: a search's batches, fits and refits allocate and free the
 * same sizes again and again. Kept: a 3,000-fit vf2d search took 13,163 page
 * faults, not 32,263 (perf stat, the same bits out), on a machine where a
 * fault cost about 16 us (tests/README.md). The sanitized tool's allocator
 * ignores mallopt. */
static void keep_freed_memory(void)
{
#ifdef __GLIBC__
	mallopt(M_MMAP_THRESHOLD, 32 << 20);
	mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

int main(int argc, char **argv)
{
	keep_freed_memory();
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
	if (strcmp(argv[1], "help") == 0 && argc == 5 && strcmp(argv[2], "--check-each") == 0)
		return check_each(argv[3], argv[4]);
	if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
	    strcmp(argv[1], "help") == 0) {
		usage(stdout);
		return 0;
	}
	if (strcmp(argv[1], "--version") == 0) {
		printf("brdfkit %s\n", BK_VERSION);
		return 0;
	}
	return run_command(argc, argv);
}
