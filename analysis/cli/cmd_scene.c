/*
 * cmd_scene.c — brdfkit scene: from a scene file (analysis/scene.h) to one
 * specialised shader per feature set, each term the cheapest form that meets
 * the error budget on the set's own domain (analysis/scene_fit.h), with the
 * fp16 guards it needs and none it does not, against the generic shader.
 */
#include "brdf.h"
#include "cli.h"
#include "clock.h"
#include "cmd.h"
#include "compare.h"
#include "expr.h"
#include "form_check.h"
#include "gpucost.h"
#include "out.h"
#include "page.h"
#include "pool.h"
#include "scene.h"
#include "scene_fit.h"
#include "scene_write.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TIME_REPS 7

/* M13: what a scene costs before it runs. Measured on a 2-core x86-64 (2020s,
 * one core per scene): a V*F term takes 2 s from the catalog and up to 20 s
 * when the short search runs (BK_SCENE_SEARCH_EVALS fits); an env term 16 to
 * 23 s (its reference integrals and the LUT scores); D a fraction of a
 * second. The estimate takes 30 s per V*F or env term, the slow case with a
 * margin for a loaded machine; above WARN_S the run says so before it starts
 * (it is not refused: the work is what the files ask for, it can be stopped
 * with Ctrl-C, and nothing is written until it is done). */
#define TERM_S 30.0
#define WARN_S 1800.0

/* --gpu: the chips, shared by every scene of the run */
static struct {
	const char *chip[BK_SCENE_CHIPS];
	int n;
	char buf[512], driver[256];
} gpu;

typedef struct scene_run {
	const char *file;
	char stem[64];  /* the file's name without directory and .json: its folder when several */
	char hash[20];  /* FNV-1a of the file's bytes */
	bk_scene sc;
	bk_scene_set sets[BK_SCENE_MAX_MATERIALS];
	bk_scene_result R[BK_SCENE_MAX_MATERIALS];
	int nset;
} scene_run;

static bk_scene_doc doc_of(const scene_run *S)
{
	bk_scene_doc d = {&S->sc, S->R, S->nset, S->hash, bk_out_command(), gpu.n, gpu.chip, gpu.driver};
	return d;
}

/* ---- measurements -------------------------------------------------------------- */

/* SPIR-V count of a choice's form (0 for a LUT: the fetch is counted apart);
 * -1 when it cannot be counted, with the reason told once per run (M8). */
static int spirv_of(const bk_scene_choice *c)
{
	static int told;
	if (c->lut || !c->text)
		return 0;
	char err[256] = "the form does not parse";
	int n = c->form ? bk_spirv_count(c->form, c->p, err, sizeof err) : -1;
	if (n < 0 && !told++)
		fprintf(stderr, "brdfkit scene: warning: SPIR-V counts not measured: %s\n", err);
	return n;
}

/* Adds a count to a sum that stays "not measured" (-1) once a part is. */
static void add_count(int *sum, int n)
{
	*sum = *sum < 0 || n < 0 ? -1 : *sum + n;
}

/* CPU ns per evaluation of every form of every set and of the generic, timed
 * together (interleaved) and summed per set; NaN (not measured) with the
 * reason told once when the forms cannot be compiled and run (M8). */
static void time_sets(bk_scene_result *R, int nset)
{
	static int told;
	size_t cap = (size_t)(nset > 0 ? nset : 1) * BK_SCENE_TERMS * 2;
	int n = 0, bad = 0;
	bk_compare_row *rows = calloc(cap, sizeof *rows);
	int *owner = calloc(cap, sizeof *owner);
	char err[256] = "out of memory";
	for (int i = 0; i < nset; i++)
		R[i].ns = R[i].gen_ns = 0;
	for (int i = 0; rows && owner && !bad && i < nset; i++)
		for (int t = 0; t < BK_SCENE_TERMS && !bad; t++)
			for (int g = 0; g < 2 && R[i].has[t] && !bad; g++) {
				const bk_scene_choice *c = g ? &R[i].gen[t] : &R[i].ch[t];
				if (c->lut || !c->text)
					continue;
				bk_compare_row *r = &rows[n];
				snprintf(r->name, sizeof r->name, "%s %s %d", R[i].set.name, bk_scene_term_name(t), g);
				snprintf(r->form, sizeof r->form, "%s", c->text);
				memcpy(r->params, c->p, sizeof r->params);
				/* the choice's own IR (scene_fit.h: a closed form's text is
				 * parsed once, where it is chosen), copied: the row frees its own */
				if (!c->form || !(r->f[0] = bk_form_dup(c->form))) {
					snprintf(err, sizeof err, "%s: %s", r->name, c->form ? "out of memory" : "no IR for its form");
					bad = 1;
					break;
				}
				r->nparams = bk_form_nparams(r->f[0]);
				owner[n++] = i * 2 + g;
			}
	if (bad || !rows || !owner || bk_time_rows(rows, n, TIME_REPS, err, sizeof err)) {
		if (!told++)
			fprintf(stderr, "brdfkit scene: warning: CPU timings not measured: %s\n", err);
		for (int i = 0; i < nset; i++)
			R[i].ns = R[i].gen_ns = NAN;
	} else {
		for (int k = 0; k < n; k++) {
			bk_scene_result *r = &R[owner[k] / 2];
			*(owner[k] % 2 ? &r->gen_ns : &r->ns) += rows[k].ns;
		}
	}
	bk_compare_rows_free(rows, n);
	free(rows);
	free(owner);
}

/* --gpu: every chosen and generic form of every set compiled for each chip
 * (one Vulkan instance per chip for the whole scene). Returns 0 or 1. */
static int gpu_sets(bk_scene_result *R, int nset)
{
	int n = 2 * nset * BK_SCENE_TERMS, nc = gpu.n, rc = 0;
	const bk_form **a = calloc((size_t)n, sizeof *a);
	const double **p = calloc((size_t)n, sizeof *p);
	double *insn = calloc((size_t)n * (size_t)nc + 1, sizeof *insn);
	char err[700];
	if (!a || !p || !insn)
		rc = cli_fail("scene", "out of memory");
	for (int i = 0; !rc && i < nset; i++)
		for (int t = 0; t < BK_SCENE_TERMS; t++)
			for (int g = 0; g < 2; g++) {
				const bk_scene_choice *c = g ? &R[i].gen[t] : &R[i].ch[t];
				int k = (i * BK_SCENE_TERMS + t) * 2 + g;
				a[k] = R[i].has[t] && !c->lut ? c->form : NULL; /* the choice's IR, parsed once */
				p[k] = c->p;
			}
	if (!rc && bk_gpucost_forms(a, NULL, p, n, gpu.chip, nc, insn, NULL, NULL, gpu.driver, sizeof gpu.driver, err,
	                            sizeof err))
		rc = cli_fail("scene", "--gpu: %s", err);
	for (int i = 0; !rc && i < nset; i++)
		for (int c = 0; c < nc; c++) {
			R[i].gpu_sum[c] = R[i].gen_gpu_sum[c] = 0;
			for (int t = 0; t < BK_SCENE_TERMS; t++)
				for (int g = 0; g < 2; g++) {
					double v = insn[((i * BK_SCENE_TERMS + t) * 2 + g) * nc + c];
					*(g ? &R[i].gen_gpu[t][c] : &R[i].gpu[t][c]) = v;
					if (!isnan(v))
						*(g ? &R[i].gen_gpu_sum[c] : &R[i].gpu_sum[c]) += v;
				}
		}
	free(a);
	free(p);
	free(insn);
	return rc;
}

/* ---- output ---------------------------------------------------------------------- */

/* One scene's files into dir (existing). */
static int write_scene(const char *dir, const scene_run *S, int timed, char *err, size_t errlen)
{
	char path[8800];
	int rc = 0;
	bk_scene_doc d = doc_of(S);
	for (int i = 0; i < S->nset && !rc; i++) {
		snprintf(path, sizeof path, "%s/%s", dir, S->R[i].set.name);
		if (mkdir(path, 0777))
			return -1;
		for (int li = 0; li < BK_SCENE_LANGS && !rc; li++) {
			if (!(S->sc.languages & (1u << li)))
				continue;
			snprintf(path, sizeof path, "%s/%s/shader.%s", dir, S->R[i].set.name, bk_scene_lang_ext(li));
			FILE *f = bk_out_fopen(path, err, errlen); /* failures named with their errno */
			if (!f)
				return -1;
			rc = bk_scene_shader(f, &d, i, li, err, errlen);
			if (bk_out_fclose(f, path, rc ? NULL : err, rc ? 0 : errlen))
				rc = -1;
		}
	}
	static const char *const files[] = {"scene.csv", "sets.csv", "report.txt", "timing.csv"};
	for (int k = 0; k < 4 && !rc; k++) {
		if (k == 3 && !timed)
			break;
		snprintf(path, sizeof path, "%s/%s", dir, files[k]);
		FILE *f = bk_out_fopen(path, err, errlen);
		if (!f)
			return -1;
		switch (k) {
		case 0: bk_scene_csv(f, &d); break;
		case 1: bk_scene_sets_csv(f, &d); break;
		case 2: bk_scene_report(f, &d, 0); break;
		default: bk_scene_timing_csv(f, &d, TIME_REPS); break;
		}
		if (bk_out_fclose(f, path, err, errlen))
			rc = -1;
	}
	return rc;
}

static int write_all(const char *dir, const scene_run *S, int n, const char *prefix, const char *id, int timed,
                     char *err, size_t errlen)
{
	char path[4400 + 64];
	int rc = 0;
	for (int k = 0; k < n && !rc; k++) {
		snprintf(path, sizeof path, "%s/%s", dir, S[k].stem);
		if (n > 1 && mkdir(path, 0777))
			return -1;
		rc = write_scene(n > 1 ? path : dir, &S[k], timed, err, errlen);
	}
	snprintf(path, sizeof path, "%s/section.html", dir);
	FILE *f = rc ? NULL : bk_out_fopen(path, err, errlen);
	if (!f)
		return -1;
	bk_scene_section_open(f, id);
	for (int k = 0; k < n; k++) {
		size_t len = strlen(prefix) + strlen(S[k].stem) + 2;
		char *pre = malloc(len);
		if (!pre) {
			rc = -1;
			break;
		}
		snprintf(pre, len, "%s%s%s", prefix, n > 1 ? S[k].stem : "", n > 1 ? "/" : "");
		bk_scene_doc d = doc_of(&S[k]);
		bk_scene_section_body(f, &d, pre); /* escapes the prefix, the file's stem with it */
		free(pre);
	}
	bk_scene_section_close(f);
	if (bk_out_fclose(f, path, rc ? NULL : err, rc ? 0 : errlen))
		rc = -1;
	return rc;
}

/* ---- the work ---------------------------------------------------------------------- */

/* Reads and checks one scene file into S: at most BK_SCENE_FILE_MAX bytes,
 * read with that bound (M12). Returns 0 or 1 after an error. */
static int load(scene_run *S, const char *file)
{
	memset(S, 0, sizeof *S);
	S->file = file;
	const char *base = strrchr(file, '/') ? strrchr(file, '/') + 1 : file;
	size_t n = strlen(base);
	if (n > 5 && !strcmp(base + n - 5, ".json"))
		n -= 5;
	snprintf(S->stem, sizeof S->stem, "%.*s", (int)(n < sizeof S->stem ? n : sizeof S->stem - 1), base);
	size_t len;
	char err[512], why[128];
	char *text = bk_read_bounded(file, BK_SCENE_FILE_MAX, &len, err, sizeof err);
	if (!text)
		return cli_fail("scene", "%s: %s%s", file, err, strstr(err, " bytes") ? " (a scene file is at most 1 MiB)" : "");
	if (cli_check_text(text, len, why, sizeof why)) {
		free(text);
		return cli_fail("scene", "%s: not a text file (%s)", file, why);
	}
	if (bk_scene_parse(text, len, &S->sc, err, sizeof err)) {
		free(text);
		return cli_fail("scene", "%s: %s", file, err);
	}
	snprintf(S->hash, sizeof S->hash, "%016llx", (unsigned long long)bk_hash_bytes(BK_HASH_INIT, text, len));
	free(text);
	S->nset = bk_scene_plan(&S->sc, S->sets);
	return 0;
}

/* The terms to fit in the sets of S: V*F and env (D is exact, the diffuse
 * Lambert's), what the estimate counts. */
static int terms_to_fit(const scene_run *S)
{
	int n = 0;
	for (int i = 0; i < S->nset; i++)
		n += S->sets[i].needs.vf + S->sets[i].needs.env + S->sets[i].needs.ms + S->sets[i].needs.sheen;
	return n;
}

/* The estimate before the work (M13), on one line; a warning above WARN_S. */
static void estimate(const scene_run *S, int n)
{
	int sets = 0, terms = 0;
	for (int k = 0; k < n; k++) {
		sets += S[k].nset;
		terms += terms_to_fit(&S[k]);
	}
	double s = terms * TERM_S;
	if (s <= WARN_S && cli_quiet()) /* a warning is printed whatever --quiet */
		return;
	fprintf(stderr, "brdfkit scene: %s%d feature set%s, %d term%s to fit: about %.0f %s (%.0f s per V*F or env term)\n",
	        s > WARN_S ? "warning: " : "", sets, sets == 1 ? "" : "s", terms, terms == 1 ? "" : "s",
	        s >= 3600 ? s / 3600 : s >= 60 ? s / 60 : s, s >= 3600 ? "h" : s >= 60 ? "min" : "s", TERM_S);
	if (s > WARN_S)
		fprintf(stderr, "brdfkit scene: warning: that is more than %.0f minutes; Ctrl-C stops it and writes nothing\n",
		        WARN_S / 60);
}

/* The sets of every scene are chosen by a few threads (pool.h), each set
 * whole by one (bk_scene_choose is thread-safe and a set's choices do not
 * depend on the others', so the results are the same bits for any count);
 * the SPIR-V counts after, in order (glslang). Progress per set, as each
 * ends; the error told is the first set's in order that failed. */
#define SCENE_THREADS_MAX 8

typedef struct spec_job {
	scene_run *S;
	int i;
	char err[512]; /* empty: chosen */
} spec_job;

typedef struct spec_run {
	spec_job *job;
	int done, total; /* under the pool's lock (spec_after) */
	double t0;
} spec_run;

static pthread_mutex_t progress_mu = PTHREAD_MUTEX_INITIALIZER;

/* cli_progress keeps its state in statics: one thread at a time */
static void locked_progress(void *label, int done, int total)
{
	pthread_mutex_lock(&progress_mu);
	cli_progress(label, done, total);
	pthread_mutex_unlock(&progress_mu);
}

static int choose_set(void *ctx, int k)
{
	spec_job *j = &((spec_run *)ctx)->job[k];
	scene_run *S = j->S;
	bk_scene_result *r = &S->R[j->i];
	r->set = S->sets[j->i];
	r->ns = r->gen_ns = NAN;
	r->has[BK_SCENE_TERM_D] = r->has[BK_SCENE_TERM_VF] = r->set.needs.vf;
	r->has[BK_SCENE_TERM_ENV] = r->set.needs.env;
	r->has[BK_SCENE_TERM_MS] = r->set.needs.ms;
	r->has[BK_SCENE_TERM_SHEEN] = r->set.needs.sheen;
	r->has[BK_SCENE_TERM_CLOTH] = r->set.needs.cloth;
	for (int t = 0; t < BK_SCENE_TERMS; t++) {
		if (!r->has[t])
			continue;
		pthread_mutex_lock(&progress_mu);
		cli_note("%s: %s: choosing %s", S->stem, r->set.name, bk_scene_term_name(t));
		pthread_mutex_unlock(&progress_mu);
		char err[400], label[200]; /* the phases' lines start with it (scene_fit.h) */
		snprintf(label, sizeof label, "scene: %s: %s: %s", S->stem, r->set.name, bk_scene_term_name(t));
		if (bk_scene_choose(&S->sc, &r->set, t, &r->ch[t], &r->gen[t], locked_progress, label, err, sizeof err)) {
			snprintf(j->err, sizeof j->err, "%s: %s: %s", S->file, r->set.name, err);
			return 1;
		}
		int taken; /* ms: E from env's LUT fetch where it has A and B (env is chosen first) */
		if (t == BK_SCENE_TERM_MS && r->has[BK_SCENE_TERM_ENV] &&
		    bk_scene_ms_from_env(&S->sc, &r->set, &r->ch[BK_SCENE_TERM_ENV], &r->ch[t], &r->gen[t], &taken, err,
		                         sizeof err)) {
			snprintf(j->err, sizeof j->err, "%s: %s: %s", S->file, r->set.name, err);
			return 1;
		}
		r->cost += r->ch[t].cost;
		r->gen_cost += r->gen[t].cost;
	}
	return 0;
}

static void spec_after(void *ctx, int k, int rc)
{
	spec_run *P = ctx;
	const scene_run *S = P->job[k].S;
	const bk_scene_result *r = &S->R[P->job[k].i];
	if (rc)
		return;
	P->done += r->set.needs.vf + r->set.needs.env + r->set.needs.ms + r->set.needs.sheen;
	double spent = bk_clock_now() - P->t0;
	char left[48] = "";
	if (P->done > 0 && P->done < P->total)
		snprintf(left, sizeof left, "; about %.0f s left", spent / P->done * (P->total - P->done));
	pthread_mutex_lock(&progress_mu);
	cli_note("%s: %s done (%d of %d terms fitted, %.0f s%s)", S->stem, r->set.name, P->done, P->total, spent, left);
	pthread_mutex_unlock(&progress_mu);
}

/* Chooses every term of every set of the n scenes of S, with threads (the
 * online cores, at most SCENE_THREADS_MAX; 1: in this thread). Returns 0
 * or 1. */
static int specialise(scene_run *S, int n, int total, double t0)
{
	spec_run P = {NULL, 0, total, t0};
	int njobs = 0;
	for (int k = 0; k < n; k++)
		njobs += S[k].nset;
	P.job = calloc((size_t)njobs + 1, sizeof *P.job);
	if (!P.job)
		return cli_fail("scene", "out of memory");
	for (int k = 0, q = 0; k < n; k++)
		for (int i = 0; i < S[k].nset; i++, q++)
			P.job[q] = (spec_job){&S[k], i, ""};
	bk_pool_run(njobs, bk_pool_cores(SCENE_THREADS_MAX), choose_set, spec_after, &P);
	int rc = 0;
	for (int q = 0; q < njobs && !rc; q++)
		if (P.job[q].err[0])
			rc = cli_fail("scene", "%s", P.job[q].err);
	for (int q = 0; q < njobs && !rc; q++) {
		bk_scene_result *r = &P.job[q].S->R[P.job[q].i];
		for (int t = 0; t < BK_SCENE_TERMS; t++)
			if (r->has[t]) {
				add_count(&r->spirv, spirv_of(&r->ch[t]));
				add_count(&r->gen_spirv, spirv_of(&r->gen[t]));
			}
	}
	free(P.job);
	return rc;
}

/* L8: a budget not met is a finding, not a failure (the run's answer is how
 * close the scene's candidates come, and thesis_no_lut's "no LUT" is an
 * example of it): exit 0, the report's "NOT MET" and one warning per term. */
static void tell_unmet(const scene_run *S)
{
	for (int i = 0; i < S->nset; i++)
		for (int t = BK_SCENE_TERM_VF; t <= BK_SCENE_TERM_ENV; t++) {
			const bk_scene_choice *c = &S->R[i].ch[t];
			if (S->R[i].has[t] && !c->meets)
				fprintf(stderr, "brdfkit scene: warning: %s: %s: %s budget %.3g not met: the most accurate candidate, "
				                "%s, is off by %.3g (exit status 0: the shaders are written, marked NOT MET)\n",
				        S->stem, S->R[i].set.name, bk_scene_term_name(t), c->budget, c->name, c->err);
		}
	for (int i = 0; i < S->nset; i++) /* the terms a scene asks for, the same words */
		for (int t = BK_SCENE_TERM_MS; t <= BK_SCENE_TERM_SHEEN; t++) {
			const bk_scene_choice *c = &S->R[i].ch[t];
			if (S->R[i].has[t] && !c->meets)
				fprintf(stderr, "brdfkit scene: warning: %s: %s: %s budget %.3g not met: the most accurate candidate, "
				                "%s, is off by %.3g (exit status 0: the shaders are written, marked NOT MET)\n",
				        S->stem, S->R[i].set.name, bk_scene_term_name(t), c->budget, c->name, c->err);
		}
}

/* M3: a term whose shader code, in the scene's precision, cannot hold the
 * result anywhere on its inputs' domain gets codegen's warning (form_check.h);
 * a LUT or a term the specular LUT replaces emits no such code. */
static void tell_lost(const scene_run *S)
{
	for (int i = 0; i < S->nset; i++)
		for (int t = 0; t < BK_SCENE_TERMS; t++) {
			const bk_scene_choice *c = &S->R[i].ch[t];
			if (!S->R[i].has[t] || c->lut || !c->text ||
			    (t == BK_SCENE_TERM_D && S->R[i].ch[BK_SCENE_TERM_VF].speclut))
				continue;
			char name[160];
			snprintf(name, sizeof name, "%s: %s_%s", S->stem, S->R[i].set.name, bk_scene_term_name(t));
			if (c->form)
				form_warn_precision("scene", name, c->form, c->p, S->sc.half ? BK_F16 : BK_F32);
		}
}

/* --id: it goes into an HTML attribute and comes back through brdfkit report's
 * section check, whose id is letters, digits, '-' and '_'. */
static int id_ok(const char *id)
{
	if (!*id)
		return 0;
	for (const char *c = id; *c; c++)
		if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '-' ||
		      *c == '_'))
			return 0;
	return strlen(id) < 64;
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* --out is required and every run writes DIR/section.html (so --id and
 * --link-prefix always land in it), times its sets unless --no-time and counts
 * them for --gpu, in any combination: every option acts in every context the
 * arguments give. What the files give is checked after they are read
 * (no_specular): the walk's setups cannot name a scene file. */
static const cli_rule rules[] = {
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--no-time", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--link-prefix", NULL, CLI_EVERYWHERE, 0, NULL, "x/"},
	{"--id", NULL, CLI_EVERYWHERE, 0, NULL, "s2"},
	{"--gpu", NULL, CLI_EVERYWHERE, 0, NULL, "navi21"},
};
static const char *const setups[] = {"s.json --out o", "a.json b.json --no-time --out o", NULL};
static const cli_table table = {NULL, 0, rules, sizeof rules / sizeof rules[0], setups};

/* --gpu counts the instructions of the sets' V*F and env forms (the diffuse
 * term is not counted, as in the SPIR-V and cost columns): a run whose sets
 * have none would get columns of zeros and still need the driver. Returns 0,
 * or 2 after the usage line in the table's wording. */
static int no_specular(const cli_cmd *cmd, const scene_run *S, int n)
{
	int terms = 0;
	for (int k = 0; k < n; k++)
		terms += terms_to_fit(&S[k]);
	if (!gpu.n || terms)
		return 0;
	return cli_usage(cmd, "--gpu has no effect: no feature set has a specular term (it counts the instructions of the "
	                      "V*F and env forms)");
}

int cmd_scene(int argc, char **argv)
{
	const char *out = NULL, *prefix = "", *id = "scenes", *chips = NULL;
	int no_time = 0;
	cli_opt opts[] = {
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "directory for the shaders, scene.csv, sets.csv, report.txt, section.html (replaced whole)", .dest = &out, .required = 1},
		{.name = "--no-time", .kind = CLI_FLAG, .help = "skip the CPU timing (timing.csv)", .dest = &no_time},
		{.name = "--link-prefix", .kind = CLI_LINK, .metavar = "PATH/", .help = "prefix of links in section.html: a path relative to the page (no scheme, no //host), percent-encoded where written", .dest = &prefix},
		{.name = "--id", .kind = CLI_STR, .metavar = "ID", .help = "the section's HTML id: letters, digits, '-', '_' (default scenes)", .dest = &id},
		{.name = "--gpu", .kind = CLI_STR, .metavar = "CHIPS", .help = "AMD instruction counts of every set's V*F and env forms and the generic's per chip (brdfkit gpucost), in scene.csv and sets.csv", .dest = &chips},
	};
	cli_cmd cmd = {"scene", "From a scene description (JSON) to one specialised shader per feature set: the terms the\n"
	               "scene needs and no others, each the cheapest form that meets the error budget on the\n"
	               "materials' own roughness, f0 and NoV range (catalog forms, published and refitted there;\n"
	               "for the environment BRDF also LUTs at the scene's ALU:TEX ratio; a short search for V*F),\n"
	               "with the fp16 guards it needs at the scene's precision and none it does not; against the\n"
	               "generic shader. Several files: each into DIR/NAME/ (NAME: the file's name without .json),\n"
	               "one section.html for all.",
	               "SCENE.json ... --out DIR",
	               "The scene file (all but materials optional; unknown keys are errors):\n"
	               "  {\"scene\": NAME, \"materials\": [{\"name\": N, \"roughness\": R, \"f0\": F, \"specular\": true,\n"
	               "                                 \"multiscatter\": false, \"cloth\": false}],\n"
	               "   \"lighting\": {\"punctual\": true, \"ibl\": true, \"diffuse\": true, \"multiscatter\": false},\n"
	               "   \"geometry\": {\"nov\": {\"min\": 0, \"max\": 1}},\n"
	               "   \"target\": {\"precision\": \"mediump\"|\"highp\", \"alu_tex\": 16|32|48|64 or\n"
	               "              \"costs\": {\"simple\": 1, \"complex\": 4, \"fetch\": 16},\n"
	               "              \"lut\": true, \"languages\": [\"glsl\", \"hlsl\", \"c\"],\n"
	               "              \"error\": E|\"generic\"|\"at-generic-cost\"|{\"vf\": E, \"env\": E, \"ms\": E, \"sheen\": E}}}\n"
	               "R: a number, a list (its hull), {\"min\": x, \"max\": y} or \"texture\" (= [0, 1]).\n"
	               "F: a number, a list, a range, \"dielectric\" (0.04), \"metal\" ([0.5, 1]) or \"texture\" ([0.02, 1]).\n"
	               "\"lut\": false: no DFG texture for the environment BRDF (no sampler to spare). LUTs are\n"
	               "16^2 to 128^2 in unorm8, half or float, in the engines' layout and laid out for the set\n"
	               "(one f0 folded into one channel, rows over its roughness range, x at sqrt(NoV); the\n"
	               "shader's comment gives the brdfkit lut command that makes it and the coordinates).\n"
	               "Defaults: all lighting on, NoV in [0, 1], highp, alu_tex 32, LUT allowed, glsl, hlsl and c\n"
	               "(msl on request), error \"generic\" (each term as accurate as the generic shader's on the\n"
	               "domain, in the scene's precision).\n"
	               "\"at-generic-cost\": each term the most accurate form at no more than the generic's cost\n"
	               "(a LUT: and no more texture memory) instead of the cheapest at a budget.\n"
	               "Errors: vf, the directional-albedo max abs error of D*V*F; env, the max abs error of\n"
	               "f0*A + B; at both ends of the f0 range; ms and sheen, the max abs error of E and of the\n"
	               "sheen albedo. \"multiscatter\": true adds ms, E = A + B for energy compensation\n"
	               "1 + f0*(1/E - 1) (from the env LUT's fetch where it holds A and B); \"cloth\": true adds the\n"
	               "exact Charlie D x Neubelt V lobe (cloth) and its albedo (sheen). The report also gives,\n"
	               "for env, the most accurate candidate at no more than the generic's cost and LUT memory.\n"
	               "A budget nothing meets keeps the most accurate, marked NOT MET, with a warning (exit\n"
	               "status 0).\n"
	               "The file keeps GLSL's words, what the shader declares: precision \"mediump\" is the\n"
	               "command line's half, \"highp\" its single; alu_tex N (or costs.fetch N) is the command\n"
	               "line's --fetch-cost N (compare, search): a texture fetch priced as N simple ops.\n"
	               "Before the work: an estimate (30 s per V*F or env term; a warning above 30 minutes);\n"
	               "after each set, how far it is. A scene file is at most 1 MiB.",
	               opts, 5, 16, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, NULL)))
		return rc == 1 ? 0 : rc;
	if (cmd.npos < 1)
		return cli_usage(&cmd, "give a scene file");
	if (!id_ok(id))
		return cli_usage(&cmd, "--id: '%.80s' is not 1 to 63 letters, digits, '-' and '_' (brdfkit report reads it back)",
		                 id);
	if (chips) {
		char gerr[700];
		snprintf(gpu.buf, sizeof gpu.buf, "%s", chips);
		if (bk_gpucost_chips(gpu.buf, gpu.chip, BK_SCENE_CHIPS, &gpu.n, gerr, sizeof gerr))
			return cli_usage(&cmd, "--gpu: %s", gerr);
	}
	int n = cmd.npos;
	scene_run *S = calloc(n, sizeof *S);
	if (!S)
		return cli_fail("scene", "out of memory");
	for (int k = 0; k < n && !rc; k++) { /* every file checked before any work */
		rc = load(&S[k], cmd.pos[k]);
		for (int j = 0; j < k && !rc && n > 1; j++)
			if (!strcmp(S[j].stem, S[k].stem))
				rc = cli_usage(&cmd, "'%s' and '%s' would both write DIR/%s/", S[j].file, S[k].file, S[k].stem);
	}
	if (!rc)
		rc = no_specular(&cmd, S, n);
	char err[512];
	if (!rc && bk_out_dir_check(out, err, sizeof err)) /* before the work, not after */
		rc = cli_fail("scene", "--out %s", err);
	char gerr[700];
	if (!rc && gpu.n && bk_gpucost_check(gpu.chip, gpu.n, gpu.driver, sizeof gpu.driver, gerr, sizeof gerr))
		rc = cli_fail("scene", "--gpu: %s", gerr);
	int total = 0;
	for (int k = 0; k < n && !rc; k++)
		total += terms_to_fit(&S[k]);
	if (!rc)
		estimate(S, n);
	if (!rc)
		rc = specialise(S, n, total, bk_clock_now());
	bk_scene_forget();
	for (int k = 0; k < n && !rc && !no_time; k++)
		time_sets(S[k].R, S[k].nset);
	for (int k = 0; k < n && !rc && gpu.n; k++)
		rc = gpu_sets(S[k].R, S[k].nset);
	if (!rc) {
		bk_out_dir od;
		if (bk_out_dir_begin(&od, out, NULL, err, sizeof err)) {
			rc = cli_fail("scene", "--out %s", err);
		} else {
			err[0] = 0;
			if (write_all(od.tmp, S, n, prefix, id, !no_time, err, sizeof err)) {
				bk_out_dir_abort(&od);
				rc = cli_fail("scene", "%s: writing the results failed%s%s", out, *err ? ": " : "", err);
			} else if (bk_out_dir_commit(&od, err, sizeof err)) {
				rc = cli_fail("scene", "--out %s", err);
			}
		}
	}
	for (int k = 0; k < n; k++) {
		if (!rc) {
			bk_scene_doc d = doc_of(&S[k]);
			bk_scene_report(stdout, &d, !no_time);
			tell_unmet(&S[k]);
			tell_lost(&S[k]);
		}
		for (int i = 0; i < S[k].nset; i++)
			for (int t = 0; t < BK_SCENE_TERMS; t++) {
				bk_scene_choice_free(&S[k].R[i].ch[t]);
				bk_scene_choice_free(&S[k].R[i].gen[t]);
			}
	}
	free(S);
	return rc;
}
