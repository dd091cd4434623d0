/*
 * fuzz_est_common.h - what the estimator harnesses (fuzz_est, fuzz_chain)
 * share: the estimator configurations of every shared .tir set, and the
 * properties every estimator output must have.
 */
#ifndef FUZZ_EST_COMMON_H
#define FUZZ_EST_COMMON_H

#include <glob.h>
#include "fuzz_common.h"
#include <string.h>
#include "grip/grip_est.h"
#include "grip/grip_signals.h"
#include "tir_reader.h"

#define FZ_EST_MAX_SETS 32

/* grip_est_config_default for each shared .tir set (tests/data/chrono-tir,
 * tests/data/mfeval-tir) that reads and initializes; the configurations
 * point into sets[], which must stay in place. Returns the count. */
static int fz_est_load_sets(grip_mf_params sets[FZ_EST_MAX_SETS], grip_est_config_t cfgs[FZ_EST_MAX_SETS])
{
    static const char *const pats[] = { "tests/data/chrono-tir/*.tir", "tests/data/mfeval-tir/*.tir" };
    static grip_est_t probe;
    int n = 0;
    size_t k;
    for (k = 0; k < 2; k++) {
        glob_t g;
        size_t j;
        if (glob(pats[k], 0, NULL, &g) != 0) {
            continue;
        }
        for (j = 0; j < g.gl_pathc && n < FZ_EST_MAX_SETS; j++) {
            char err[256];
            if (grip_tir_read(g.gl_pathv[j], &sets[n], err, sizeof err) == 0 &&
                grip_est_config_default(&cfgs[n], &sets[n]) == GRIP_OK &&
                grip_est_init(&probe, &cfgs[n]) == GRIP_OK) {
                n++;
            }
        }
        globfree(&g);
    }
    return n;
}

static int fz_est_in(grip_real_t v, double lo, double hi)
{
    double d = fz_d(v, FZ_QS);
    return d >= lo && d <= hi;
}

/* One input sample of step `step` from the fuzz bytes: a validity mask
 * (3 bytes), then every input's value in its format; an input the mask
 * leaves out is invalid and stale. */
static void fz_est_read_sample(fz_reader *r, int step, grip_input_sample_t *in)
{
    uint32_t mask = (uint32_t)fz_u8(r) | ((uint32_t)fz_u8(r) << 8) | ((uint32_t)fz_u8(r) << 16);
    uint32_t i;
    memset(in, 0, sizeof *in);
    in->t_us = (int64_t)step * 10000;
    in->step = (uint32_t)step;
    for (i = 0; i < GRIP_IN_COUNT; i++) {
        grip_real_t v = fz_real(r, grip_input_is_ql(i) ? FZ_QL : FZ_QS);
        if ((mask >> i) & 1u) {
            in->value[i] = v;
            in->valid[i] = 1u;
            in->fault[i] = GRIP_SIG_OK;
        } else {
            in->value[i] = 0;
            in->valid[i] = 0u;
            in->fault[i] = GRIP_SIG_STALE;
        }
    }
}

/* Every output finite; util in [0, 1.5]; mu_conf in [0, 1]; steer_char in
 * {-1, 0, 1}; no flag bit beyond the documented ones (bit 15, the
 * model-consistency flag, is the last). */
static void fz_est_check_output(int step, const grip_est_output_t *o)
{
    const grip_real_t *w = (const grip_real_t *)o;
    size_t nreal = offsetof(grip_est_output_t, steer_char) / sizeof(grip_real_t);
    size_t k;
    unsigned i;
    for (k = 0; k < nreal; k++) {
        FZ_CHECK(fz_finite(w[k]), "step %d: output word %zu non-finite", step, k);
    }
    for (i = 0; i < 4; i++) {
        FZ_CHECK(fz_est_in(o->util[i], 0.0, 1.5), "step %d: util[%u] %g", step, i, fz_d(o->util[i], FZ_QS));
    }
    FZ_CHECK(fz_est_in(o->mu_conf, 0.0, 1.0), "step %d: mu_conf %g", step, fz_d(o->mu_conf, FZ_QS));
    FZ_CHECK(o->steer_char >= -1 && o->steer_char <= 1, "step %d: steer_char %d", step, (int)o->steer_char);
    /* every bit the estimator sets has a name; F_INPUT_DEGRADED (bit 16)
     * is the monitor's, never the estimator's */
    FZ_CHECK((o->flags & ~(((uint32_t)GRIP_EST_F_BETA_DISAGREE << 1) - 1u)) == 0u &&
             (o->flags & GRIP_EST_F_INPUT_DEGRADED) == 0u,
             "step %d: unknown flag bits %x", step, (unsigned)o->flags);
}

#endif /* FUZZ_EST_COMMON_H */
