/*
 * scene_write.h — what brdfkit scene writes for one scene: per feature set
 * one shader per language, scene.csv, sets.csv, timing.csv, report.txt and
 * its part of the page section. Every string that comes from the scene file
 * or the command line (the scene's and the materials' names, the command,
 * the link prefix, the section's id) is escaped for where it lands: comment
 * text through bk_comment_text (ir.h), CSV fields through bk_csv_field, HTML
 * through bk_html_text; feature-set names are identifiers brdfkit makes
 * (scene.h). Numbers that were not measured (no spirv-opt, no C
 * compiler) and ratios of nothing (a set without a specular term) are empty
 * fields and the words "not measured", never -1, -2 or NaN.
 */
#ifndef ANALYSIS_SCENE_WRITE_H
#define ANALYSIS_SCENE_WRITE_H

#include "scene.h"
#include "scene_fit.h"

#include <stdio.h>

#define BK_SCENE_CHIPS 8

/* What the run decided for one feature set. */
typedef struct bk_scene_result {
	bk_scene_set set;
	int has[BK_SCENE_TERMS];
	bk_scene_choice ch[BK_SCENE_TERMS], gen[BK_SCENE_TERMS];
	double cost, gen_cost;   /* ALU + fetches, the scene's weights */
	int spirv, gen_spirv;    /* SPIR-V instructions of the forms (fetches not counted); -1: not measured */
	double ns, gen_ns;       /* CPU ns per evaluation of the forms, summed; NaN: not measured */
	/* --gpu: ACO's net instructions per term and chip (NaN: a LUT, nothing compiled), and
	 * summed over the set's terms (fetches not included) */
	double gpu[BK_SCENE_TERMS][BK_SCENE_CHIPS], gen_gpu[BK_SCENE_TERMS][BK_SCENE_CHIPS];
	double gpu_sum[BK_SCENE_CHIPS], gen_gpu_sum[BK_SCENE_CHIPS];
} bk_scene_result;

/* One scene's results and what its files say about where they came from. */
typedef struct bk_scene_doc {
	const bk_scene *sc;
	const bk_scene_result *R;
	int nset;
	const char *hash;       /* of the scene file's bytes */
	const char *command;    /* the command line */
	int nchips;             /* --gpu: the chips and the driver that counted */
	const char *const *chip;
	const char *driver;
} bk_scene_doc;

/* Languages by their bit in bk_scene.languages: 0 GLSL, 1 HLSL, 2 C, 3 MSL. */
const char *bk_scene_lang_ext(int li); /* "glsl", "hlsl", "c", "metal" */

/* Set i's functions in language li: a provenance comment, the chosen
 * terms, the diffuse, a comment for a LUT. Returns 0, or -1 with a message. */
int bk_scene_shader(FILE *f, const bk_scene_doc *d, int i, int li, char *err, size_t errlen);

/* The tidy table (a row per material and term), the saving per set, the
 * CPU timings (reps: the runs the median is of). */
void bk_scene_csv(FILE *f, const bk_scene_doc *d);
void bk_scene_sets_csv(FILE *f, const bk_scene_doc *d);
void bk_scene_timing_csv(FILE *f, const bk_scene_doc *d, int reps);

/* The report in words; with_time adds the CPU timings (stdout only:
 * report.txt stays reproducible). */
void bk_scene_report(FILE *f, const bk_scene_doc *d, int with_time);

/* The page section: its opening (id: the section's HTML id), one scene's
 * part (prefix: where the scene's files are seen from the page), its end. */
void bk_scene_section_open(FILE *f, const char *id);
void bk_scene_section_body(FILE *f, const bk_scene_doc *d, const char *prefix);
void bk_scene_section_close(FILE *f);

#endif
