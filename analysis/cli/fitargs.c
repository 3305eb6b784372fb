/*
 * fitargs.c — the target options of fit and search turned into a
 * bk_target_options (fitargs.h).
 */
#include "fitargs.h"
#include "brdf.h"
#include "params.h"
#include "tabtarget.h"

#include <stdio.h>
#include <string.h>

void fitargs_say_size(const bk_target_options *to)
{
	double n = (double)bk_target_samples(to);
	char what[64];
	snprintf(what, sizeof what, "%.3gM samples of target %s", n / 1e6, bk_target_name(to->kind));
	cli_estimate(what, n * 15e-6, n * 168, "168 bytes and 15 us a sample, measured");
}

/* --domain NAME=LO:HI[,NAME=LO:HI...]: the inputs of target form, in order. */
int fitargs_domain(const cli_cmd *cmd, const char *text, bk_target_options *to)
{
	char err[400];
	return bk_params_domain(text, CLI_RANGE_MIN_REL, to, err, sizeof err) ? cli_usage(cmd, "--domain: %s", err) : 0;
}

/* table, merl: --target-file read into *t (nothing for the other targets).
 * A bad file is bad input (2), one that cannot be read a failure (1). */
int fitargs_read_file(const cli_cmd *cmd, const fitargs *a, bk_target_kind kind, bk_samples *t)
{
	char err[600] = "";
	int rc = 0;
	memset(t, 0, sizeof *t);
	if (kind != BK_TARGET_TABLE && kind != BK_TARGET_MERL)
		return 0;
	if (!a->target_file)
		return cli_usage(cmd, "target %s needs --target-file FILE", bk_target_name(kind));
	if (kind == BK_TARGET_TABLE)
		rc = bk_tabtarget_table(a->target_file, a->channel, t, err, sizeof err);
	else {
		int ch = a->channel ? cli_choice("--channel", a->channel, bk_merl_channel_names, BK_MERL_CHANNELS)
		                    : BK_MERL_LUMINANCE;
		if (ch < 0)
			return 2;
		rc = bk_tabtarget_merl(a->target_file, (bk_merl_channel)ch, t, err, sizeof err);
	}
	if (rc == -2)
		return cli_fail(cmd->name, "--target-file %s", err);
	if (rc)
		return cli_bad("--target-file %s", err);
	return 0;
}

int fitargs_setup_target(const fitargs *a, bk_target_kind kind, bk_target_options *to)
{
	bk_target_defaults(kind, to);
	/* cosines and perceptual roughness: [0, 1], -0 refused as an option's would be */
	if (a->r_range && cli_range("--r-range", a->r_range, 0, 1, &to->r_lo, &to->r_hi))
		return 2;
	if (a->x_range && cli_range("--x-range", a->x_range, 0, 1, &to->x_lo, &to->x_hi))
		return 2;
	if (a->nx) to->nx = (int)a->nx;
	if (a->nr) to->nr = (int)a->nr;
	if (a->nu) to->nu = (int)a->nu;
	if (a->nphi) to->nphi = (int)a->nphi;
	if (a->f0.n) {
		if (a->f0.n > BK_TARGET_MAX_F0) {
			cli_bad("--f0: at most %d values", BK_TARGET_MAX_F0);
			return 2;
		}
		to->nf0 = a->f0.n;
		memcpy(to->f0, a->f0.v, sizeof(double) * (size_t)a->f0.n);
	}
	static const char *const talk[] = {"r", "a"};
	int v = a->talk ? cli_choice("--talk-roughness", a->talk, talk, 2) : 0;
	if (v < 0)
		return 2;
	to->talk_alpha = v == 1;
	if (a->smith && bk_smith_parse(a->smith, &to->smith)) {
		cli_bad("--smith: unknown model '%s'", a->smith);
		return 2;
	}
	if (a->ior > 0)
		to->eta = a->ior;
	to->k = a->k; /* with or without --ior (then glass's 1.5) */
	return 0;
}
