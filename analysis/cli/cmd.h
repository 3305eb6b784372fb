/*
 * cmd.h — the subcommands of brdfkit; each takes the arguments after its name
 * and returns the exit status (0 ok, 1 failure at run time, 2 bad usage).
 */
#ifndef ANALYSIS_CMD_H
#define ANALYSIS_CMD_H

int cmd_terms(int argc, char **argv);
int cmd_dfg(int argc, char **argv);
int cmd_lut(int argc, char **argv);
int cmd_lut_specular(int argc, char **argv); /* lut --specular (cmd_speclut.c) */
int cmd_albedo(int argc, char **argv);
int cmd_eval(int argc, char **argv);
int cmd_ops(int argc, char **argv);
int cmd_codegen(int argc, char **argv);
int cmd_catalog(int argc, char **argv);
int cmd_fit(int argc, char **argv);
int cmd_time(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_report(int argc, char **argv);
int cmd_stability(int argc, char **argv);
int cmd_search(int argc, char **argv);
int cmd_scene(int argc, char **argv);
int cmd_gpucost(int argc, char **argv);
int cmd_render(int argc, char **argv);

#endif
