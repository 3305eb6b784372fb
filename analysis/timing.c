/*
 * timing.c — what a form costs when it runs: CPU nanoseconds per evaluation of
 * its generated C, and the size of its generated GLSL as SPIR-V after the
 * optimiser (compare.h declares both).
 *
 * Run time. Every timed row's C (bk_form_emit, parameters baked in) goes into
 * one temporary translation unit with a batch loop per row,
 *
 *     void bk_t<i>(size_t n, const float *NoV, ..., float *out)
 *
 * taking only the inputs the row reads, in the emitter's order NoV NoL NoH LoH
 * r a f0. A split-sum row (form and form_b) is one evaluation: the loop
 * computes A and B and stores their sum, so neither can be dropped. The unit is
 * built with `cc -std=c11 -O2 -fPIC -shared -lm` and nothing else:
 *   - no -ffast-math: it would let the compiler reassociate and contract
 *     (the generated C promises to round like bk_form_eval BK_F32, and -std=c11
 *     implies -ffp-contract=off), drop NaN/inf semantics that min/max/clamp
 *     rely on, and its crtfastmath.o would switch the host process to
 *     flush-to-zero on dlopen;
 *   - no -march: the figure is for the baseline x86-64 (SSE2) a distribution
 *     ships; gcc 12 at -O2 vectorises only loops with a known trip count, so
 *     each loop here runs scalar, one evaluation after another, whatever the
 *     form (libm calls like sqrtf with errno would block it anyway).
 * The shared object is loaded with dlopen (in libc itself since glibc 2.34:
 * no -ldl). Inputs: one deterministic stream of N = 2^20 points, the same for
 * every row; a warm-up pass per row, then reps runs, each timing one pass per
 * row, the rows interleaved (and the first row rotated) so that machine noise
 * and cache state hit all of them alike. ns = median, ns_min, ns_max over the
 * runs, per evaluation.
 *
 * SPIR-V size. The GLSL (highp) becomes a compute shader that loads its inputs
 * from a storage buffer (constants would fold), stores each input back and the
 * result beside them; an identical shader whose "result" is its first input
 * (or 0.0) is the baseline. Both go through glslang in-process
 * (bk_gpucost_spirv, gpucost's: Vulkan 1.1, SPIR-V 1.3; glslangValidator's
 * own words, test_timing.c, and the same counts as its SPIR-V 1.0 for every
 * catalog form), spirv-opt -O and spirv-dis; the count is the instructions
 * inside function bodies (OpFunction ... OpFunctionEnd, after spirv-opt has
 * inlined the form into main) of the form's shader minus the baseline's: the
 * form's own instructions,
 * without loads, stores, address arithmetic or module-level declarations
 * (constants, types). The baseline depends only on which inputs are read and is
 * cached per input set for the life of the process.
 *
 * Temporary files live in a mkdtemp directory under $TMPDIR (or /tmp) and are
 * removed on every path out, a SIGINT or SIGTERM included: the directory and
 * the compiler running are in out_registry.c's registry of live temporaries.
 */
#include "compare.h"
#include "gpucost.h"
#include "out.h"

#include "clock.h"

#include <dirent.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

#define TIME_N ((size_t)1 << 20) /* points per pass: ~1-30 ms a pass, far above the clock's resolution */

/* ---- temporary directory and external tools ------------------------------------ */

typedef struct workdir {
	char path[512];
	int slot; /* bk_out_track */
} workdir;

static int workdir_open(workdir *w, const char *prefix, char *err, size_t errlen)
{
	const char *tmp = getenv("TMPDIR");
	if (!tmp || !*tmp || strlen(tmp) > 400)
		tmp = "/tmp";
	snprintf(w->path, sizeof w->path, "%s/%s.XXXXXX", tmp, prefix);
	if (mkdtemp(w->path)) {
		w->slot = bk_out_track(w->path, 1);
		return 0;
	}
	snprintf(err, errlen, "%s: cannot create a temporary directory: %s", tmp, strerror(errno));
	return -1;
}

static void workdir_file(const workdir *w, const char *name, char *buf, size_t len)
{
	snprintf(buf, len, "%s/%s", w->path, name);
}

/* Removes every file in the directory (all ours: mkdtemp made it 0700), then it. */
static void workdir_close(workdir *w)
{
	DIR *d = opendir(w->path);
	if (d) {
		for (struct dirent *e; (e = readdir(d));) {
			if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
				continue;
			char p[1024];
			snprintf(p, sizeof p, "%s/%s", w->path, e->d_name);
			unlink(p);
		}
		closedir(d);
	}
	rmdir(w->path);
	bk_out_untrack(w->slot);
}

/* The first non-empty line of a tool's log, for a one-line error message. */
static void log_line(const char *log, char *buf, size_t len)
{
	buf[0] = '\0';
	FILE *f = fopen(log, "r");
	if (!f)
		return;
	char line[512];
	while (fgets(line, sizeof line, f)) {
		line[strcspn(line, "\r\n")] = '\0';
		if (line[strspn(line, " \t")]) {
			size_t k = strlen(line) < len ? strlen(line) : len - 1;
			memcpy(buf, line, k);
			buf[k] = '\0';
			break;
		}
	}
	fclose(f);
}

/* Runs argv (searched on PATH) with stdin from /dev/null and stdout and stderr
 * into log. Returns 0 on exit status 0, else -1 with a message naming the tool
 * and, when it is missing, the Debian package that has it. */
static int run_tool(char *const argv[], const char *package, const char *log, char *err, size_t errlen)
{
	posix_spawn_file_actions_t fa;
	posix_spawn_file_actions_init(&fa);
	posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
	posix_spawn_file_actions_addopen(&fa, 1, log, O_WRONLY | O_CREAT | O_TRUNC, 0600);
	posix_spawn_file_actions_adddup2(&fa, 1, 2);
	pid_t pid;
	int rc = posix_spawnp(&pid, argv[0], &fa, NULL, argv, environ);
	posix_spawn_file_actions_destroy(&fa);
	if (rc) {
		if (rc == ENOENT)
			snprintf(err, errlen, "%s not found on PATH (Debian package %s)", argv[0], package);
		else
			snprintf(err, errlen, "%s: cannot run: %s", argv[0], strerror(rc));
		return -1;
	}
	bk_out_track_child(pid); /* a signal handler kills it before removing its directory */
	int status;
	while (waitpid(pid, &status, 0) < 0)
		if (errno != EINTR) {
			bk_out_track_child(0);
			snprintf(err, errlen, "%s: waitpid: %s", argv[0], strerror(errno));
			return -1;
		}
	bk_out_track_child(0);
	if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
		return 0;
	char first[256];
	log_line(log, first, sizeof first);
	if (WIFEXITED(status))
		snprintf(err, errlen, "%s failed (exit %d): %s", argv[0], WEXITSTATUS(status), first);
	else
		snprintf(err, errlen, "%s killed by signal %d", argv[0], WIFSIGNALED(status) ? WTERMSIG(status) : 0);
	return -1;
}

static int write_bytes(const char *path, const void *p, size_t n, char *err, size_t errlen)
{
	FILE *f = fopen(path, "wb");
	int ok = f && fwrite(p, 1, n, f) == n;
	if (f && fclose(f) != 0)
		ok = 0;
	if (!ok)
		snprintf(err, errlen, "%s: cannot write: %s", path, strerror(errno));
	return ok ? 0 : -1;
}

static int write_text(const char *path, const char *text, char *err, size_t errlen)
{
	return write_bytes(path, text, strlen(text), err, errlen);
}

/* ---- run time: the generated unit --------------------------------------------------- */

/* A row's forms (the row's own IR, borrowed) and the inputs its batch loop
 * takes (union of A and B). */
typedef struct timed {
	int row;
	const bk_form *f[2]; /* A, and B or NULL */
	unsigned inputs;
	void (*fn)(void);
} timed;

/* One call of a form inside the loop: "bk_f3a(NoV[k], r[k])". */
static void put_call(bk_strbuf *b, const bk_form *f, int row, char part)
{
	bk_sb_put(b, "bk_f%d%c(", row, part);
	const char *sep = "";
	for (int k = 0; k < BK_IN_COUNT; k++)
		if (bk_form_inputs(f) >> k & 1) {
			bk_sb_put(b, "%s%s[k]", sep, bk_input_name((bk_input)k));
			sep = ", ";
		}
	bk_sb_put(b, ")");
}

static int put_row(bk_strbuf *b, const timed *t, const bk_compare_row *r, char *err, size_t errlen)
{
	for (int p = 0; p < 2 && t->f[p]; p++) {
		char name[32];
		snprintf(name, sizeof name, "bk_f%d%c", t->row, "ab"[p]);
		bk_emit_info info = {.name = name, .source = r->name};
		char *text = bk_form_emit(t->f[p], BK_LANG_C, 0, r->params, &info);
		if (!text) {
			snprintf(err, errlen, "%s: code generation failed", r->name);
			return -1;
		}
		bk_sb_put(b, "%s\n", text);
		free(text);
	}
	bk_sb_put(b, "void bk_t%d(size_t n", t->row);
	for (int k = 0; k < BK_IN_COUNT; k++)
		if (t->inputs >> k & 1)
			bk_sb_put(b, ", const float *%s", bk_input_name((bk_input)k));
	bk_sb_put(b, ", float *out)\n{\n\tfor (size_t k = 0; k < n; k++)\n\t\tout[k] = ");
	put_call(b, t->f[0], t->row, 'a');
	if (t->f[1]) {
		bk_sb_put(b, " + ");
		put_call(b, t->f[1], t->row, 'b');
	}
	bk_sb_put(b, ";\n}\n\n");
	return 0;
}

int bk_compare_row_parse(bk_compare_row *r, char *err, size_t errlen)
{
	const char *text[2] = {r->form, r->form_b};
	bk_compare_rows_free(r, 1);
	for (int p = 0; p < 2 && text[p][0]; p++) {
		bk_form_error fe;
		if (!(r->f[p] = bk_form_parse(text[p], &fe))) {
			snprintf(err, errlen, "%s: form:1:%d: %s", r->name, fe.column, fe.message);
			bk_compare_rows_free(r, 1);
			return -1;
		}
	}
	return 0;
}

void bk_compare_rows_free(bk_compare_row *rows, int n)
{
	for (int i = 0; rows && i < n; i++)
		for (int p = 0; p < 2; p++) {
			bk_form_free(rows[i].f[p]);
			rows[i].f[p] = NULL;
		}
}

/* The rows that have a form into t (m of them), each with its own IR: a row
 * whose text was never made IR (bk_compare_row_parse) is a caller's error. */
static int take_rows(const bk_compare_row *rows, int n, timed *t, int *m, char *err, size_t errlen)
{
	*m = 0;
	for (int i = 0; i < n; i++) {
		const bk_compare_row *r = &rows[i];
		if (!r->form[0] && !r->f[0])
			continue;
		if (!r->f[0] || (r->form_b[0] && !r->f[1])) {
			snprintf(err, errlen, "%s: its form was not parsed (bk_compare_row_parse)", r->name);
			return -1;
		}
		timed *x = &t[(*m)++];
		x->row = i;
		for (int p = 0; p < 2; p++) {
			x->f[p] = r->f[p];
			if (x->f[p] && bk_form_nparams(x->f[p]) > r->nparams) {
				snprintf(err, errlen, "%s: the form uses p0..p%d but the row has %d parameters", r->name,
				         bk_form_nparams(x->f[p]) - 1, r->nparams);
				return -1;
			}
		}
		x->inputs = bk_form_inputs(x->f[0]) | (x->f[1] ? bk_form_inputs(x->f[1]) : 0);
	}
	return 0;
}

/* Writes, compiles and loads the unit; *so gets the dlopen handle. */
static int build(const workdir *w, const bk_compare_row *rows, timed *t, int m, void **so, char *err,
                 size_t errlen)
{
	bk_strbuf b = {0};
	bk_sb_put(&b, "/* brdfkit timing unit: generated, compiled and removed by bk_time_rows */\n"
	           "#include <stddef.h>\n\n");
	for (int i = 0; i < m; i++)
		if (put_row(&b, &t[i], &rows[t[i].row], err, errlen)) {
			free(b.s);
			return -1;
		}
	char src[600], lib[600], log[600];
	workdir_file(w, "forms.c", src, sizeof src);
	workdir_file(w, "forms.so", lib, sizeof lib);
	workdir_file(w, "cc.log", log, sizeof log);
	int rc = b.oom ? (snprintf(err, errlen, "out of memory"), -1) : write_text(src, b.s, err, errlen);
	free(b.s);
	if (rc)
		return -1;
	char *argv[] = {"cc", "-std=c11", "-O2", "-fPIC", "-shared", "-o", lib, src, "-lm", NULL};
	if (run_tool(argv, "gcc", log, err, errlen))
		return -1;
	if (!(*so = dlopen(lib, RTLD_NOW | RTLD_LOCAL))) {
		snprintf(err, errlen, "dlopen: %s", dlerror());
		return -1;
	}
	for (int i = 0; i < m; i++) {
		char sym[32];
		snprintf(sym, sizeof sym, "bk_t%d", t[i].row);
		if (!(t[i].fn = (void (*)(void))dlsym(*so, sym))) {
			snprintf(err, errlen, "dlsym %s: %s", sym, dlerror());
			return -1;
		}
	}
	return 0;
}

/* ---- run time: inputs and the timed passes ------------------------------------------- */

/* Knuth's MMIX LCG; the top 24 bits are a float's whole mantissa. */
static uint32_t lcg24(uint64_t *s)
{
	*s = *s * 6364136223846793005u + 1442695040888963407u;
	return (uint32_t)(*s >> 40);
}

/* The input stream: cosines in (0.01, 1], r in (0.02, 1], a = r^2, f0 in
 * [0.02, 1]. Independent (no consistent geometry: timing does not need it);
 * the lower bounds keep every catalog form finite and away from float
 * denormals (a^4 >= 1.6e-7^2 ≈ 2.6e-14, 1/LoH^2 <= 1e4), whose slow path would
 * time the CPU's microcode rather than the form. */
static void fill_inputs(float *in[BK_IN_COUNT], size_t n)
{
	uint64_t s = 0x62726466u; /* "brdf" */
	const double top = 16777216.0; /* 2^24 */
	for (size_t k = 0; k < n; k++) {
		for (int c = BK_IN_NOV; c <= BK_IN_LOH; c++)
			in[c][k] = (float)(0.01 + 0.99 * ((lcg24(&s) + 1.0) / top));
		double r = 0.02 + 0.98 * ((lcg24(&s) + 1.0) / top);
		in[BK_IN_R][k] = (float)r;
		in[BK_IN_A][k] = (float)(r * r);
		in[BK_IN_F0][k] = (float)(0.02 + 0.98 * (lcg24(&s) / (top - 1.0)));
	}
}

typedef const float *cfp;

/* Calls a batch loop with the inputs it takes, in order. The function type
 * must match the definition exactly, hence one cast per arity. */
static void call_batch(const timed *t, float *const in[BK_IN_COUNT], size_t n, float *out)
{
	cfp a[BK_IN_COUNT];
	int k = 0;
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (t->inputs >> c & 1)
			a[k++] = in[c];
	switch (k) {
	case 0: ((void (*)(size_t, float *))t->fn)(n, out); break;
	case 1: ((void (*)(size_t, cfp, float *))t->fn)(n, a[0], out); break;
	case 2: ((void (*)(size_t, cfp, cfp, float *))t->fn)(n, a[0], a[1], out); break;
	case 3: ((void (*)(size_t, cfp, cfp, cfp, float *))t->fn)(n, a[0], a[1], a[2], out); break;
	case 4: ((void (*)(size_t, cfp, cfp, cfp, cfp, float *))t->fn)(n, a[0], a[1], a[2], a[3], out); break;
	case 5:
		((void (*)(size_t, cfp, cfp, cfp, cfp, cfp, float *))t->fn)(n, a[0], a[1], a[2], a[3], a[4], out);
		break;
	case 6:
		((void (*)(size_t, cfp, cfp, cfp, cfp, cfp, cfp, float *))t->fn)(n, a[0], a[1], a[2], a[3], a[4],
		                                                                  a[5], out);
		break;
	default:
		((void (*)(size_t, cfp, cfp, cfp, cfp, cfp, cfp, cfp, float *))t->fn)(n, a[0], a[1], a[2], a[3],
		                                                                       a[4], a[5], a[6], out);
		break;
	}
}

/* ns[i * reps + j]: row i, run j, per evaluation. */
static void run_passes(const timed *t, int m, int reps, float *const in[BK_IN_COUNT], float *out, double *ns)
{
	for (int i = 0; i < m; i++) /* warm-up: pages touched, libm symbols bound, clocks up */
		call_batch(&t[i], in, TIME_N, out);
	for (int j = 0; j < reps; j++)
		for (int q = 0; q < m; q++) {
			int i = (q + j) % m;
			double t0 = bk_clock_now();
			call_batch(&t[i], in, TIME_N, out);
			ns[i * reps + j] = (bk_clock_now() - t0) * 1e9 / (double)TIME_N;
		}
}

static void summarise(bk_compare_row *r, double *v, int reps)
{
	qsort(v, (size_t)reps, sizeof *v, bk_clock_cmp);
	r->ns = v[reps / 2];
	r->ns_min = v[0];
	r->ns_max = v[reps - 1];
}

static int measure(bk_compare_row *rows, const timed *t, int m, int reps, char *err, size_t errlen)
{
	float *in[BK_IN_COUNT] = {0}, *out = malloc(TIME_N * sizeof *out);
	double *ns = malloc((size_t)m * (size_t)reps * sizeof *ns);
	int ok = out && ns;
	for (int c = 0; c < BK_IN_COUNT; c++)
		ok = ok && (in[c] = malloc(TIME_N * sizeof *in[c]));
	if (ok) {
		fill_inputs(in, TIME_N);
		run_passes(t, m, reps, in, out, ns);
		for (int i = 0; i < m; i++)
			summarise(&rows[t[i].row], ns + (size_t)i * (size_t)reps, reps);
	} else {
		snprintf(err, errlen, "out of memory");
	}
	for (int c = 0; c < BK_IN_COUNT; c++)
		free(in[c]);
	free(out);
	free(ns);
	return ok ? 0 : -1;
}

int bk_time_rows(bk_compare_row *rows, int n, int reps, char *err, size_t errlen)
{
	if (n < 0 || reps < 1 || reps > 100000) {
		snprintf(err, errlen, "reps: %d is out of range [1, 100000]", reps);
		return -1;
	}
	for (int i = 0; i < n; i++)
		rows[i].ns = rows[i].ns_min = rows[i].ns_max = NAN;
	timed *t = calloc((size_t)n + 1, sizeof *t);
	if (!t) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	int m = 0, rc = take_rows(rows, n, t, &m, err, errlen);
	void *so = NULL;
	workdir w = {{0}, -1};
	if (rc == 0 && m > 0 && (rc = workdir_open(&w, "bk_time", err, errlen)) == 0) {
		rc = build(&w, rows, t, m, &so, err, errlen);
		workdir_close(&w); /* a loaded object stays mapped */
		if (rc == 0)
			rc = measure(rows, t, m, reps, err, errlen);
	}
	if (so)
		dlclose(so);
	free(t);
	return rc;
}

/* ---- SPIR-V size ------------------------------------------------------------------------ */

/* Inputs live at stride 8 in one float buffer, input c at offset c; the
 * result goes to offset 0 of the output and input c back to offset c + 1, so
 * that every load is used in the baseline too. fn is the form's GLSL function
 * (named bk_form), or NULL for the baseline. */
static void put_shader(bk_strbuf *b, const char *fn, unsigned inputs)
{
	bk_sb_put(b, "#version 310 es\nprecision highp float;\nlayout(local_size_x = 64) in;\n"
	          "layout(std430, binding = 0) readonly buffer Inputs { highp float v[]; } inb;\n"
	          "layout(std430, binding = 1) writeonly buffer Outputs { highp float v[]; } outb;\n\n%s\n"
	          "void main()\n{\n\tuint i = gl_GlobalInvocationID.x * 8u;\n",
	       fn ? fn : "");
	const char *first = NULL;
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (inputs >> c & 1) {
			const char *name = bk_input_name((bk_input)c);
			bk_sb_put(b, "\thighp float %s = inb.v[i + %du];\n\toutb.v[i + %du] = %s;\n", name, c, c + 1, name);
			first = first ? first : name;
		}
	if (!fn) {
		bk_sb_put(b, "\toutb.v[i] = %s;\n}\n", first ? first : "0.0");
		return;
	}
	bk_sb_put(b, "\toutb.v[i] = bk_form(");
	const char *sep = "";
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (inputs >> c & 1) {
			bk_sb_put(b, "%s%s", sep, bk_input_name((bk_input)c));
			sep = ", ";
		}
	bk_sb_put(b, ");\n}\n");
}

/* The opcode of one spirv-dis line ("%x = OpFoo ..." or "OpFoo ..."), or NULL. */
static const char *opcode(const char *line)
{
	line += strspn(line, " \t");
	if (*line == '%') {
		const char *eq = strstr(line, " = ");
		if (!eq)
			return NULL;
		line = eq + 3;
	}
	return strncmp(line, "Op", 2) == 0 ? line : NULL;
}

static int is_op(const char *op, const char *name)
{
	size_t k = strlen(name);
	return strncmp(op, name, k) == 0 && (op[k] == ' ' || op[k] == '\n' || op[k] == '\0');
}

/* Instructions from OpFunction to OpFunctionEnd, both counted. */
static int count_function_instructions(const char *path)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	char line[4096];
	int in_fn = 0, n = 0;
	while (fgets(line, sizeof line, f)) {
		const char *op = opcode(line);
		if (!op)
			continue;
		in_fn |= is_op(op, "OpFunction");
		n += in_fn;
		if (is_op(op, "OpFunctionEnd"))
			in_fn = 0;
	}
	fclose(f);
	return n;
}

/* GLSL text -> instruction count of its optimised SPIR-V; name tells files apart. */
static int spirv_of(const workdir *w, const char *name, const char *glsl, char *err, size_t errlen)
{
	char spv[600], opt[600], dis[600], log[600];
	snprintf(spv, sizeof spv, "%s/%s.spv", w->path, name);
	snprintf(opt, sizeof opt, "%s/%s.opt.spv", w->path, name);
	snprintf(dis, sizeof dis, "%s/%s.spvasm", w->path, name);
	snprintf(log, sizeof log, "%s/%s.log", w->path, name);
	char *sopt[] = {"spirv-opt", "-O", spv, "-o", opt, NULL};
	char *sdis[] = {"spirv-dis", "--no-header", "--no-color", "-o", dis, opt, NULL};
	size_t n = 0;
	unsigned *words = bk_gpucost_spirv(glsl, &n, err, errlen);
	int bad = !words || write_bytes(spv, words, n * sizeof *words, err, errlen);
	free(words);
	if (bad || run_tool(sopt, "spirv-tools", log, err, errlen) || run_tool(sdis, "spirv-tools", log, err, errlen))
		return -1;
	int k = count_function_instructions(dis);
	if (k < 0)
		snprintf(err, errlen, "%s: cannot read: %s", dis, strerror(errno));
	return k;
}

/* The baseline for an input set, cached (0: not yet known, else count + 1).
 * brdfkit is single-threaded; a race would only compute it twice. */
static int baseline_cache[1 << BK_IN_COUNT];

static int baseline(const workdir *w, unsigned inputs, char *err, size_t errlen)
{
	if (baseline_cache[inputs])
		return baseline_cache[inputs] - 1;
	bk_strbuf b = {0};
	put_shader(&b, NULL, inputs);
	int k = b.oom ? (snprintf(err, errlen, "out of memory"), -1) : spirv_of(w, "baseline", b.s, err, errlen);
	free(b.s);
	if (k >= 0)
		baseline_cache[inputs] = k + 1;
	return k;
}

int bk_spirv_count(const bk_form *f, const double *params, char *err, size_t errlen)
{
	bk_emit_info info = {.name = "bk_form"};
	char *fn = bk_form_emit(f, BK_LANG_GLSL, 0, params, &info);
	if (!fn) {
		snprintf(err, errlen, "code generation failed (parameters missing?)");
		return -1;
	}
	bk_strbuf b = {0};
	put_shader(&b, fn, bk_form_inputs(f));
	free(fn);
	workdir w;
	int k = -1;
	if (b.oom)
		snprintf(err, errlen, "out of memory");
	else if (workdir_open(&w, "bk_spirv", err, errlen) == 0) {
		int base = baseline(&w, bk_form_inputs(f), err, errlen);
		k = base < 0 ? -1 : spirv_of(&w, "form", b.s, err, errlen);
		k = k < 0 ? -1 : k - base;
		workdir_close(&w);
	}
	free(b.s);
	return k;
}
