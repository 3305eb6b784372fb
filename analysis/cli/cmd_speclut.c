/*
 * cmd_speclut.c — brdfkit lut --specular: the low tier's specular LUT
 * (speclut.h) written as an engine ships it (spec.png, 8 bits) with its
 * float twin (spec.exr) and a CSV, and, with --sweep, its error on the spec
 * target against every axis x warp x scale x size brdfkit tries, the best
 * one written beside it, and a section for the report page.
 */
#include "brdf.h"
#include "prov.h"
#include "cli.h"
#include "cmd.h"
#include "out.h"
#include "page.h"
#include "speclut.h"
#include "target.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* The sweep's grid (the issue's: axis x warp power x scale x size). */
static const int sweep_warps[] = {1, 2, 3, 4, 6, 8};
static const double sweep_scales[] = {1, 2, 4, 8, 16, 32};
static const int sweep_sizes[] = {32, 64, 128, 256};
#define NW (int)(sizeof sweep_warps / sizeof sweep_warps[0])
#define NS (int)(sizeof sweep_scales / sizeof sweep_scales[0])
#define NZ (int)(sizeof sweep_sizes / sizeof sweep_sizes[0])
#define SWEEP_N (BK_SPECLUT_AXES * NW * NS * NZ)

typedef struct scored {
	bk_speclut L;
	bk_fit_metrics m;      /* against the exact D·V·F·NoL */
	double albedo_rel;     /* rms over the cells of that error over the cell's exact albedo: the ranking */
	double albedo_rms;     /* rms over the cells of the directional albedo error */
	bk_fit_metrics st;     /* against the function the LUT encodes (storage alone) */
	double st_albedo_rms;
	double cost;           /* ALU (ir weights) + one fetch at ALU:TEX 16 */
} scored;

/* The ranking (M5): the rms over the (NoV, r) cells of the directional
 * albedo error against the exact lobe, each over the cell's exact albedo
 * (what a lit surface gets wrong in energy, as a share of what it has: 1 is
 * a LUT of zeros), then the absolute rms, rmse, cheaper, smaller. The
 * absolute rms alone is dominated by the grazing and smoothest cells, whose
 * albedo is largest and which no 8-bit LUT of D/4 without Fresnel gets
 * right: it put a LUT of zeros (0.1625) within 3 % of the best (0.1574),
 * where the relative one puts it at 1 against 0.68. */
static int better(const scored *a, const scored *b)
{
	if (a->albedo_rel != b->albedo_rel)
		return a->albedo_rel < b->albedo_rel;
	if (a->albedo_rms != b->albedo_rms)
		return a->albedo_rms < b->albedo_rms;
	if (a->m.rmse != b->m.rmse)
		return a->m.rmse < b->m.rmse;
	if (a->cost != b->cost)
		return a->cost < b->cost;
	return (long)a->L.nu * a->L.nr < (long)b->L.nu * b->L.nr;
}

static int score_one(const bk_samples *s, const double *albedo, const bk_speclut *L, double *plane, scored *o)
{
	bk_ops ops;
	o->L = *L;
	if (bk_speclut_score(L, BK_F64, s, &o->m, plane) || bk_speclut_ops(L, &ops))
		return -1;
	o->albedo_rms = bk_speclut_plane_rms(s, plane);
	o->albedo_rel = bk_speclut_plane_rel_rms(s, plane, albedo);
	if (bk_speclut_score_storage(L, s, &o->st, plane))
		return -1;
	o->st_albedo_rms = bk_speclut_plane_rms(s, plane);
	o->cost = bk_ops_cost(&ops, BK_COST_SIMPLE, BK_COST_COMPLEX) + bk_tier_alu_per_tex[0];
	return 0;
}

static void csv_row(FILE *f, const scored *o, const char *role)
{
	char name[96];
	bk_speclut_name(&o->L, name, sizeof name);
	fprintf(f, "%s,%s,%s,%d,%d,%d,%.9g,%s,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%g\n", name, role,
	        bk_speclut_axis_name(o->L.axis), o->L.warp, o->L.nu, o->L.nr, o->L.scale,
	        bk_speclut_fresnel_name(o->L.fresnel), bk_lut_format_name(o->L.fmt), o->albedo_rel, o->albedo_rms,
	        o->m.albedo_max_abs,
	        o->m.rmse, o->m.weighted_rmse, o->m.max_abs, o->m.max_rel, o->st_albedo_rms, o->st.albedo_max_abs,
	        o->st.rmse, o->cost);
}

static void write_sweep_csv(FILE *f, const scored *rows, int n, const scored *given, int best,
                            const char *description, const char *command)
{
	bk_prov_title(f, "specular LUT sweep: axis x warp power x scale x size, 8-bit UNORM, bilinear");
	fputs("# error of fetch*scale*NoL*F against the exact D*V*F*NoL on the spec target's samples (below), the LUT "
	      "as sampled (texel centres, clamp to edge, 8-bit weights and texels)\n", f);
	fprintf(f, "# samples: %s\n", description);
	fputs("# albedo_rel_rms (the ranking, then albedo_rms, then rmse): rms over the (NoV, r) cells of the "
	      "directional albedo error over the cell's exact albedo, every cell counting the same (1: a LUT of zeros; "
	      "the grazing and smoothest cells, which no 8-bit LUT of D/4 gets right, are near 1 for every LUT); "
	      "albedo_rms: rms over the cells of the absolute error, dominated by those cells; albedo_max_abs, rmse, weighted_rmse, max_abs, max_rel as brdfkit compare --target spec; storage_*: the "
	      "same against the function the LUT encodes, D(NoH(x), r^2)/4*NoL*F exact (the texture's own error: warp, "
	      "scale, size, 8 bits)\n", f);
	fprintf(f, "# cost: ALU ops (ir weights: simple 1, complex 4) + one fetch at ALU:TEX %d; role: given (the "
	        "options' LUT), best, or sweep\n", bk_tier_alu_per_tex[0]);
	bk_prov_command(f, command);
	fputs("name,role,axis,warp,width,height,scale,fresnel,format,albedo_rel_rms,albedo_rms,albedo_max_abs,rmse,weighted_rmse,max_abs,"
	      "max_rel,storage_albedo_rms,storage_albedo_max_abs,storage_rmse,cost\n", f);
	csv_row(f, given, "given");
	for (int k = 0; k < n; k++)
		csv_row(f, &rows[k], k == best ? "best" : "sweep");
}

static void html_row(FILE *f, const char *what, const scored *o, const char *link)
{
	char name[96];
	bk_speclut_name(&o->L, name, sizeof name);
	fputs("<tr><td>", f);
	bk_html_text(f, what);
	fputs("</td><td>", f);
	bk_html_text(f, name);
	fprintf(f, "</td><td>%.4g</td><td>%.4g</td><td>%.4g</td><td>%.4g</td><td>%.4g</td><td>%.4g</td><td>%g</td><td>",
	        o->albedo_rel, o->albedo_rms,
	        o->m.albedo_max_abs, o->m.rmse, o->st_albedo_rms, o->st.albedo_max_abs, o->cost);
	if (link) {
		fputs("<a href=\"", f);
		bk_html_link(f, NULL, link);
		fputs("\">spec.png</a>", f);
	}
	fputs("</td></tr>\n", f);
}

static void write_section(FILE *f, const scored *given, const scored *best, const scored *rows, int n,
                          const char *prefix, const char *description)
{
	char l1[300], l2[300];
	snprintf(l1, sizeof l1, "%sspec.png", prefix);
	snprintf(l2, sizeof l2, "%sbest/spec.png", prefix);
	fputs("<section id=\"speclut\">\n<h2>The low tier's specular LUT</h2>\n<p>The talk's low-end path "
	      "(&#8220;Optimizing for Low-end&#8221;): the specular intensity D&#183;V/16 in an 8-bit texture over "
	      "(R&#183;L or N&#183;H, roughness), one axis warped by a power, V the implicit geometric term (1/4), the "
	      "shader multiplying back by 16&#183;NoL&#183;f0 (no Fresnel). Scored as sampled (bilinear, texel centres, "
	      "8-bit texels) against the exact D&#183;V&#183;F&#183;NoL on ", f);
	bk_html_text(f, description);
	fprintf(f, ". Ranked by the rms over the (NoV, r) cells of the directional albedo error relative to the cell's "
	           "exact albedo (1: a LUT of zeros), then the absolute rms, then rmse (the absolute errors are largest "
	           "in the smoothest, most grazing cells, which no 8-bit LUT of D/4 gets right, for every LUT alike). Storage: the same against "
	           "the function the LUT encodes, D/4&#183;NoL&#183;f0 exact: what the texture alone gets wrong. Cost: "
	           "ALU ops plus one fetch at ALU:TEX %d. The talk names no size: 64&#215;64 is brdfkit's reading. "
	           "R&#183;L is mapped to N&#183;H by NoH = sqrt((1 + R&#183;L)/2), exact only in the plane of "
	           "incidence.</p>\n<table>\n<tr><th></th><th>LUT</th><th>albedo error / albedo, rms over cells</th><th>albedo error, rms over cells</th>"
	           "<th>albedo max |error|</th><th>rmse</th><th>storage: albedo rms</th><th>storage: albedo max</th>"
	           "<th>cost</th><th>texture</th></tr>\n",
	        bk_tier_alu_per_tex[0]);
	html_row(f, "the talk's choices", given, l1);
	html_row(f, "best of the sweep", best, l2);
	/* the best per axis and per scale: where the choice matters */
	for (int a = 0; a < BK_SPECLUT_AXES; a++) {
		int b = -1;
		for (int k = 0; k < n; k++)
			if (rows[k].L.axis == (bk_speclut_axis)a && (b < 0 || better(&rows[k], &rows[b])))
				b = k;
		char what[64];
		snprintf(what, sizeof what, "best with axis %s", bk_speclut_axis_name((bk_speclut_axis)a));
		if (b >= 0)
			html_row(f, what, &rows[b], NULL);
	}
	for (int q = 0; q < NS; q++) {
		int b = -1;
		for (int k = 0; k < n; k++)
			if (rows[k].L.scale == sweep_scales[q] && (b < 0 || better(&rows[k], &rows[b])))
				b = k;
		char what[64];
		snprintf(what, sizeof what, "best at scale %g", sweep_scales[q]);
		if (b >= 0)
			html_row(f, what, &rows[b], NULL);
	}
	fprintf(f, "</table>\n<p>Every LUT of the sweep (%d): <a href=\"", n);
	bk_html_link(f, prefix, "sweep.csv");
	fputs("\">sweep.csv</a>.</p>\n</section>\n", f);
}

static int write_all(const bk_speclut *L, int sweep, const char *out, const char *prefix)
{
	char err[700];
	bk_out_dir od;
	if (bk_out_dir_begin(&od, out, NULL, err, sizeof err))
		return cli_fail("lut", "--out %s", err);
	int rc = 0;
	bk_samples s;
	memset(&s, 0, sizeof s);
	scored *rows = NULL, given;
	double *plane = NULL, *albedo = NULL;
	int n = 0, best = -1;
	if (sweep) {
		bk_target_options to;
		bk_target_defaults(BK_TARGET_SPEC, &to);
		rows = malloc(SWEEP_N * sizeof *rows);
		if (!rows)
			rc = cli_fail("lut", "out of memory");
		else if (bk_target_build(&to, &s, NULL, NULL, err, sizeof err))
			rc = cli_fail("lut", "%s", err);
		if (!rc && !(plane = malloc(((size_t)s.plane_nx * (size_t)s.plane_ny + 1) * sizeof *plane)))
			rc = cli_fail("lut", "out of memory");
		if (!rc && !(albedo = malloc(((size_t)s.plane_nx * (size_t)s.plane_ny + 1) * sizeof *albedo)))
			rc = cli_fail("lut", "out of memory");
		if (!rc && bk_speclut_plane_albedo(&s, albedo))
			rc = cli_fail("lut", "out of memory");
		if (!rc && score_one(&s, albedo, L, plane, &given))
			rc = cli_fail("lut", "the LUT could not be scored");
		for (int a = 0; !rc && a < BK_SPECLUT_AXES; a++)
			for (int w = 0; !rc && w < NW; w++)
				for (int q = 0; !rc && q < NS; q++)
					for (int z = 0; !rc && z < NZ; z++) {
						bk_speclut c = {(bk_speclut_axis)a, sweep_warps[w], sweep_sizes[z], sweep_sizes[z], L->r_lo,
						                L->r_hi, sweep_scales[q], L->fresnel, BK_LUT_UNORM8};
						if (score_one(&s, albedo, &c, plane, &rows[n]))
							rc = cli_fail("lut", "a LUT of the sweep could not be scored");
						else if (best < 0 || better(&rows[n], &rows[best]))
							best = n;
						n++;
						cli_progress("lut: sweep", n, SWEEP_N);
					}
	}
	char path[4400];
	if (!rc && bk_speclut_write(L, od.tmp, bk_out_command(), err, sizeof err))
		rc = cli_fail("lut", "%s: writing the results failed: %s", out, err);
	if (!rc && sweep) {
		snprintf(path, sizeof path, "%s/best", od.tmp);
		if (mkdir(path, 0777) || bk_speclut_write(&rows[best].L, path, bk_out_command(), err, sizeof err))
			rc = cli_fail("lut", "%s: writing the results failed: %s", out, err);
		static const char *const names[2] = {"sweep.csv", "section.html"};
		for (int k = 0; k < 2 && !rc; k++) {
			bk_out o;
			snprintf(path, sizeof path, "%s/%s", od.tmp, names[k]);
			if (bk_out_open(&o, path, err, sizeof err)) {
				rc = cli_fail("lut", "%s: writing the results failed: %s", out, err);
				break;
			}
			if (k == 0)
				write_sweep_csv(o.f, rows, n, &given, best, s.description, bk_out_command());
			else
				write_section(o.f, &given, &rows[best], rows, n, prefix, s.description);
			if (bk_out_commit(&o, err, sizeof err))
				rc = cli_fail("lut", "%s: writing the results failed: %s", out, err);
		}
		if (!rc) { /* one line each for a log */
			char a[96], b[96];
			bk_speclut_name(L, a, sizeof a);
			bk_speclut_name(&rows[best].L, b, sizeof b);
			printf("given: %s: albedo_rel_rms %.4g, albedo_rms %.5g, albedo_max_abs %.4g, storage albedo_rms %.4g, "
			       "cost %g\n", a, given.albedo_rel, given.albedo_rms, given.m.albedo_max_abs, given.st_albedo_rms,
			       given.cost);
			printf("best:  %s: albedo_rel_rms %.4g, albedo_rms %.5g, albedo_max_abs %.4g, storage albedo_rms %.4g, "
			       "cost %g\n", b, rows[best].albedo_rel, rows[best].albedo_rms, rows[best].m.albedo_max_abs,
			       rows[best].st_albedo_rms, rows[best].cost);
		}
	}
	free(rows);
	free(plane);
	free(albedo);
	bk_samples_free(&s);
	if (rc) {
		bk_out_dir_abort(&od);
		return rc;
	}
	return bk_out_dir_commit(&od, err, sizeof err) ? cli_fail("lut", "--out %s", err) : 0;
}

/* ---- where the options act (cli.h) ----------------------------------------- */

enum { MODE_ONE, MODE_SWEEP };
static const cli_dim dims[] = {{"mode", {"one", "sweep"}, {" without --sweep", " with --sweep"}}};
static const cli_rule rules[] = {
	{"--link-prefix", NULL, 0, 1u << MODE_SWEEP, "it prefixes the links of section.html, written by --sweep", "x/"},
	{"--specular", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--sweep", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--axis", NULL, CLI_EVERYWHERE, 0, NULL, "noh"},
	{"--warp", NULL, CLI_EVERYWHERE, 0, NULL, "2"},
	{"--scale", NULL, CLI_EVERYWHERE, 0, NULL, "8"},
	{"--size", NULL, CLI_EVERYWHERE, 0, NULL, "16"},
	{"--rows", NULL, CLI_EVERYWHERE, 0, NULL, "8"},
	{"--r-range", NULL, CLI_EVERYWHERE, 0, NULL, "0.2:1"},
	{"--fresnel", NULL, CLI_EVERYWHERE, 0, NULL, "schlick"},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
};
static const char *const setups[] = {"--specular --out o", "--specular --sweep --out o", NULL};
static const cli_table table = {dims, 1, rules, sizeof rules / sizeof rules[0], setups};

int cmd_lut_specular(int argc, char **argv)
{
	long warp = 4, size = 64, rows = 0;
	double scale = 16;
	int specular = 0, sweep = 0;
	const char *axis = "rol", *fresnel = "none", *out = NULL, *r_range = NULL, *prefix = "";
	cli_opt opts[] = {
		{.name = "--specular", .kind = CLI_FLAG, .help = "the specular LUT (this command; without it, the DFG LUT)", .dest = &specular, .required = 1},
		{.name = "--axis", .kind = CLI_STR, .metavar = "rol|noh", .help = "x = saturate(R.L) (default, the talk's) or N.H", .dest = &axis},
		{.name = "--warp", .kind = CLI_INT, .metavar = "P", .help = "u = x^P, an integer power 1..16 (default 4, the talk's)", .dest = &warp, .lo = 1, .hi = BK_SPECLUT_MAX_WARP},
		{.name = "--scale", .kind = CLI_NUM, .metavar = "S", .help = "texel = intensity/S, a normal float32 as S must be (default 16, the talk's)", .dest = &scale, .lo = 0, .lo_open = 1, .hi = 1e6},
		{.name = "--size", .kind = CLI_INT, .metavar = "W", .help = "texels along u (default 64)", .dest = &size, .lo = 2, .hi = BK_SPECLUT_MAX_SIZE},
		{.name = "--rows", .kind = CLI_INT, .metavar = "H", .help = "texels along roughness (default: W)", .dest = &rows, .lo = 2, .hi = BK_SPECLUT_MAX_SIZE},
		{.name = "--r-range", .kind = CLI_STR, .metavar = "LO:HI", .help = "rows over roughness LO..HI (default 0:1)", .dest = &r_range},
		{.name = "--fresnel", .kind = CLI_STR, .metavar = "none|schlick", .help = "the shader multiplies by f0 (default, the talk's) or by F_schlick(f0, 1, LoH)", .dest = &fresnel},
		{.name = "--sweep", .kind = CLI_FLAG, .help = "also score the sweep on the spec target: sweep.csv, best/, section.html", .dest = &sweep},
		{.name = "--link-prefix", .kind = CLI_LINK, .metavar = "PATH/", .help = "prefix of links in section.html: a path relative to the page (no scheme, no //host), percent-encoded where written", .dest = &prefix},
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "directory for " BK_SPECLUT_EXR ", " BK_SPECLUT_PNG " and " BK_SPECLUT_CSV " (replaced whole)", .dest = &out, .required = 1},
	};
	cli_cmd cmd = {"lut", "--specular: the low tier's specular LUT (the talk's \"Optimizing for Low-end\"): the\n"
	               "intensity D*V/S in a 2-D texture over (x, r), x = saturate(R.L) or N.H warped by u = x^P,\n"
	               "V = 1/4 (the implicit geometric term), GGX D; the shader computes\n"
	               "texel(u, v)*S*NoL*f0 (or *F_schlick(f0, 1, LoH) with --fresnel schlick).\n"
	               "Writes DIR/" BK_SPECLUT_PNG " (8-bit grey, what an engine ships), DIR/" BK_SPECLUT_EXR
	               " (float) and DIR/" BK_SPECLUT_CSV ",\nthe layout in PNG tEXt chunks, EXR attributes and CSV comments.",
	               "--specular --out DIR [--axis rol|noh] [--warp P] [--scale S] [--size W] [--rows H]\n"
	               "       [--r-range LO:HI] [--fresnel none|schlick] [--sweep [--link-prefix PATH/]]",
	               "Layout: u = x^P at texel centres (i + 0.5)/W, v = (r - LO)/(HI - LO) at (j + 0.5)/H;\n"
	               "scanline 0 holds the smallest roughness (uv (0,0) = first texel); bilinear, clamp to\n"
	               "edge, a linear (not sRGB) R8 texture. With R.L the bake uses NoH = sqrt((1 + R.L)/2),\n"
	               "exact only when L is in the plane of V and N. 8 bits cut intensities above S.\n"
	               "--sweep scores this LUT and every axis x warp (1,2,3,4,6,8) x scale (1,2,4,8,16,32) x\n"
	               "size (32..256) at 8 bits on brdfkit's spec target (the exact D*V*F*NoL, f0 0.04),\n"
	               "as sampled; ranks them by the rms over (NoV, r) cells of the albedo error over the\n"
	               "cell's albedo (1: a LUT of zeros; every cell counts the same), then the absolute rms,\n"
	               "then rmse; writes\n"
	               "DIR/sweep.csv, DIR/best/ (the best LUT's three files) and DIR/section.html.",
	               opts, (int)(sizeof opts / sizeof opts[0]), 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, (int[]){sweep ? MODE_SWEEP : MODE_ONE})))
		return rc == 1 ? 0 : rc;
	bk_speclut L = BK_SPECLUT_TALK;
	static const char *const axes[] = {"rol", "noh"}, *const fresnels[] = {"none", "schlick"};
	if (bk_speclut_axis_parse(axis, &L.axis))
		return cli_unknown_value("--axis", axis, axes, 2);
	if (bk_speclut_fresnel_parse(fresnel, &L.fresnel))
		return cli_unknown_value("--fresnel", fresnel, fresnels, 2);
	if (r_range && cli_range("--r-range", r_range, 0, 1, &L.r_lo, &L.r_hi))
		return 2;
	L.warp = (int)warp;
	L.scale = scale;
	L.nu = (int)size;
	L.nr = rows ? (int)rows : (int)size;
	const char *bad = bk_speclut_check(&L);
	if (bad)
		return cli_usage(&cmd, "%s", bad);
	char why[300];
	if ((rc = bk_speclut_float_check(&L, why, sizeof why)) > 0) /* H3: the bound is the data's, not the option's */
		return cli_usage(&cmd, "--scale %g: %s", scale, why);
	if (rc < 0)
		return cli_fail("lut", "out of memory");
	return write_all(&L, sweep, out, prefix); /* the prefix reaches HTML through bk_html_text */
}
