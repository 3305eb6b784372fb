/*
 * scene.h — a scene description (what its materials, lights and target GPU
 * are) read from JSON with jansson, and the plan it implies: which terms each
 * material needs, and the feature sets (materials with the same needs share
 * one shader, after the embedded-PBR thesis, seed 000, chapter 4).
 *
 * The file (every key but "materials" optional; unknown keys are errors):
 *
 *   { "scene": "car paint",
 *     "materials": [ { "name": "paint",
 *                      "roughness": 0.5 | [0.1, 0.4, 0.7] | {"min": 0.05, "max": 0.3} | "texture",
 *                      "f0": 0.04 | {"min": .., "max": ..} | "dielectric" | "metal" | "texture",
 *                      "specular": true,
 *                      "multiscatter": false, "cloth": false } ],
 *     "lighting": { "punctual": true, "ibl": true, "diffuse": true, "multiscatter": false },
 *     "geometry": { "nov": {"min": 0.1, "max": 1} },
 *     "target": { "precision": "mediump" | "highp",
 *                 "alu_tex": 16 | 32 | 48 | 64,            (or)
 *                 "costs": {"simple": 1, "complex": 4, "fetch": 16},
 *                 "lut": true,
 *                 "languages": ["glsl", "hlsl", "c"],
 *                 "error": 0.01 | "generic" | "at-generic-cost" |
 *                          {"vf": 0.01, "env": 0.02, "ms": 0.01, "sheen": 0.01} } }
 *
 * Meanings: a roughness list is fitted on its hull (the values between are
 * cheap to cover and a texture may blend them); "texture" is the full range
 * [0, 1]. f0 "dielectric" is 0.04, "metal" the range [0.5, 1] (the
 * reflectances of common metals, iron 0.56 to silver 0.97), "texture" the
 * metalness workflow's [0.02, 1]. "specular": false leaves the material
 * diffuse only. "lut": false forbids a texture for the environment BRDF (the
 * thesis's "no LUT" variant: no sampler to spare). The error budget is per term, in the unit of each term's
 * error (scene_fit.h); "generic" asks each term to be as accurate as the
 * generic shader is on the scene's domain in the scene's precision (and
 * then as cheap as can be); "at-generic-cost" turns the question round: each
 * term the most accurate form at no more than the generic term's cost (a
 * LUT: and no more texture memory), the "more accurate at equal
 * cost" instead of "cheaper at equal error".
 *
 * "multiscatter": true (on a material, or on "lighting" for every specular
 * material) asks for multiple-scattering energy compensation: the set needs
 * the term ms, the single-scattering directional albedo E(NoV, r) = A + B
 * that Filament's 1 + f0 (1/E - 1) (Turquin 2019) reads. "cloth": true adds
 * a sheen layer on the material's roughness (Estevez & Kulla 2017's Charlie
 * D, Neubelt & Pettineo's V: Filament's cloth): the set needs the lobe
 * (term cloth, with punctual lights) and its albedo (term sheen: the IBL's
 * cloth DFG channel, and 1 - sheen albedo scaling the layer below); with
 * "specular": false the cloth is the whole lobe (Filament's cloth model).
 * A scene that asks for neither gets neither, and its files are what they
 * were before the keys existed.
 */
#ifndef ANALYSIS_SCENE_H
#define ANALYSIS_SCENE_H

#include <stddef.h>

#define BK_SCENE_NAME_MAX 64
#define BK_SCENE_MAX_MATERIALS 64
/* The largest scene file read: 64 materials of a few lines each fill a few
 * KB; 1 MiB leaves room for long roughness lists and comments' worth of
 * whitespace, and is read with that bound (a FIFO or /dev/zero included). */
#define BK_SCENE_FILE_MAX ((size_t)1 << 20)

/* The defaults of the named values (documented above). */
#define BK_SCENE_DIELECTRIC_F0 0.04
#define BK_SCENE_METAL_F0_LO 0.5
#define BK_SCENE_TEXTURE_F0_LO 0.02

typedef struct bk_scene_material {
	char name[BK_SCENE_NAME_MAX];
	double r_lo, r_hi;   /* perceptual roughness, hull of what was given */
	double f0_lo, f0_hi; /* equal: one f0, folded into the constants */
	int specular;
	int multiscatter;    /* energy compensation: the term ms */
	int cloth;           /* a sheen layer: the terms cloth and sheen */
} bk_scene_material;

/* MSL (Metal, SPIRV-Cross's translation of the GLSL, analysis/msl.h) only
 * when "languages" names it: the default stays GLSL, HLSL and C. */
enum { BK_SCENE_GLSL = 1, BK_SCENE_HLSL = 2, BK_SCENE_C = 4, BK_SCENE_MSL = 8 };
#define BK_SCENE_LANGS 4

/* Error budget: a number per term, or the generic shader's error. */
#define BK_SCENE_BUDGET_GENERIC (-1.0)
/* ... or the most accurate at the generic's cost (its budget is then the
 * generic's error, which the choice normally beats). */
#define BK_SCENE_BUDGET_AT_COST (-2.0)

typedef struct bk_scene {
	char name[BK_SCENE_NAME_MAX];
	int nmat;
	bk_scene_material mat[BK_SCENE_MAX_MATERIALS];
	int punctual, ibl, diffuse;
	double nov_lo, nov_hi;
	int half;            /* mediump: binary16 arithmetic */
	int alu_tex;         /* simple ALU ops one bilinear fetch costs (0: explicit costs) */
	double simple_cost, complex_cost, fetch_cost;
	int lut;             /* a DFG texture may replace the environment BRDF's math */
	unsigned languages;  /* BK_SCENE_GLSL | ... */
	double budget_vf, budget_env; /* or BK_SCENE_BUDGET_GENERIC, BK_SCENE_BUDGET_AT_COST */
	int multiscatter;    /* lighting.multiscatter: every specular material's */
	double budget_ms, budget_sheen; /* as budget_vf */
} bk_scene;

/* Reads and checks a scene from JSON text. A syntax error names its line and
 * column (jansson's); a bad value names its key by its path in the document,
 * "materials[1].roughness.max: 1.3 is outside [0, 1]" (jansson keeps no
 * positions of values, and the path is what a user searches for). Numbers
 * follow the command line's rules: a number that is not zero but underflows
 * to it (1e-999) is refused with its line and column (jansson would read 0),
 * -0 is read as 0. A UTF-8 byte-order mark is refused by name (JSON has
 * none: RFC 8259, 8.1). Names (the scene's, the materials') have no control
 * character; a language is listed once. Returns 0, or -1 with the message. */
int bk_scene_parse(const char *text, size_t len, bk_scene *sc, char *err, size_t errlen);

/* ---- the plan --------------------------------------------------------------- */

/* What one material needs. */
typedef struct bk_scene_needs {
	int vf;       /* punctual specular: D · V·F */
	int env;      /* image-based specular: the environment BRDF */
	int diffuse;  /* Lambert */
	int fixed_f0; /* one f0: folded into the constants, no f0 input (specular only) */
	double f0;    /* that f0 */
	int ms;       /* specular with energy compensation: E(NoV, r) */
	int cloth;    /* a sheen layer under punctual lights: D_charlie V_neubelt */
	int sheen;    /* a sheen layer: its directional albedo */
} bk_scene_needs;

void bk_scene_material_needs(const bk_scene *sc, int m, bk_scene_needs *n);

/* Materials with equal needs (and, for a folded f0, the same f0) share a
 * feature set; its domain is the hull of its materials' domains. A set's
 * name is an identifier made from its needs (the prefix of its functions and
 * its directory), made unique with "_2", "_3", ... where two folded f0 round
 * to the same three digits (0.0401 and 0.0404 are both f0_040). */
typedef struct bk_scene_set {
	char name[BK_SCENE_NAME_MAX]; /* from its needs: "spec_ibl_f0", "ibl_dielectric", ... */
	bk_scene_needs needs;
	double r_lo, r_hi, f0_lo, f0_hi;
	int nmat;
	int mat[BK_SCENE_MAX_MATERIALS];
} bk_scene_set;

/* The feature sets in order of their first material. Returns how many. */
int bk_scene_plan(const bk_scene *sc, bk_scene_set *sets);

#endif
