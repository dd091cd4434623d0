/*
 * fuzz_est.c - the estimator (grip_est_step) on hostile input sequences.
 *
 * Configuration: grip_est_config_default with each shared .tir parameter set
 * (tests/data/chrono-tir, tests/data/mfeval-tir), read at start-up.
 * Input: [set] then up to 200 steps of [valid mask (3 bytes)] [17 input
 * words] (each input in its own format, grip_input_is_ql); an invalid input
 * gets fault GRIP_SIG_STALE and value 0, as the assembler would send it.
 * Properties: no crash or sanitizer report; every step returns GRIP_OK;
 * every output finite; util in [0, 1.5]; mu_conf in [0, 1]; steer_char in
 * {-1, 0, 1}; unknown flag bits never set. Fault injection proper (which
 * outputs must lose validity for which missing input) is the estimator's
 * own test (tests/unit/test_est_robust.c); here only robustness.
 */
#include <glob.h>
#include "fuzz_common.h"
#include "grip/grip_est.h"
#include "grip/grip_signals.h"
#include "tir_reader.h"

#define MAX_SETS 32
static grip_mf_params sets[MAX_SETS];
static grip_est_config_t cfgs[MAX_SETS];
static int nsets;

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    static const char *const pats[] = { "tests/data/chrono-tir/*.tir", "tests/data/mfeval-tir/*.tir" };
    size_t k;
    (void)argc;
    (void)argv;
    for (k = 0; k < 2; k++) {
        glob_t g;
        size_t j;
        if (glob(pats[k], 0, NULL, &g) != 0) {
            continue;
        }
        for (j = 0; j < g.gl_pathc && nsets < MAX_SETS; j++) {
            char err[256];
            if (grip_tir_read(g.gl_pathv[j], &sets[nsets], err, sizeof err) == 0 &&
                grip_est_config_default(&cfgs[nsets], &sets[nsets]) == GRIP_OK) {
                /* the config points at sets[nsets], which stays in place */
                static grip_est_t probe;
                if (grip_est_init(&probe, &cfgs[nsets]) == GRIP_OK) {
                    nsets++;
                }
            }
        }
        globfree(&g);
    }
    if (nsets == 0) {
        fprintf(stderr, "fuzz_est: no usable .tir parameter set (run from the repository root)\n");
        exit(2);
    }
    return 0;
}

static int in01(grip_real_t v, double lo, double hi)
{
    double d = fz_d(v, FZ_QS);
    return d >= lo && d <= hi;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static grip_est_t est;
    fz_reader r = { data, size };
    int set = fz_u8(&r) % nsets;
    int steps = 0;
    grip_status_t s = grip_est_init(&est, &cfgs[set]);
    FZ_CHECK(s == GRIP_OK, "init %d", (int)s);
    while (r.n > 0 && steps < 200) {
        grip_input_sample_t in;
        grip_est_output_t o;
        uint32_t mask = (uint32_t)fz_u8(&r) | ((uint32_t)fz_u8(&r) << 8) | ((uint32_t)fz_u8(&r) << 16);
        uint32_t i;
        memset(&in, 0, sizeof in);
        in.t_us = (int64_t)steps * 10000;
        in.step = (uint32_t)steps;
        for (i = 0; i < GRIP_IN_COUNT; i++) {
            grip_real_t v = fz_real(&r, grip_input_is_ql(i) ? FZ_QL : FZ_QS);
            if ((mask >> i) & 1u) {
                in.value[i] = v;
                in.valid[i] = 1u;
                in.fault[i] = GRIP_SIG_OK;
            } else {
                in.value[i] = 0;
                in.valid[i] = 0u;
                in.fault[i] = GRIP_SIG_STALE;
            }
        }
        s = grip_est_step(&est, &in, &o);
        FZ_CHECK(s == GRIP_OK, "step %d: status %d", steps, (int)s);
        {
            const grip_real_t *w = (const grip_real_t *)&o;
            size_t nreal = offsetof(grip_est_output_t, steer_char) / sizeof(grip_real_t);
            size_t k;
            for (k = 0; k < nreal; k++) {
                FZ_CHECK(fz_finite(w[k]), "step %d: output word %zu non-finite", steps, k);
            }
        }
        for (i = 0; i < 4; i++) {
            FZ_CHECK(in01(o.util[i], 0.0, 1.5), "util[%u] %g", i, fz_d(o.util[i], FZ_QS));
        }
        FZ_CHECK(in01(o.mu_conf, 0.0, 1.0), "mu_conf %g", fz_d(o.mu_conf, FZ_QS));
        FZ_CHECK(o.steer_char >= -1 && o.steer_char <= 1, "steer_char %d", (int)o.steer_char);
        FZ_CHECK((o.flags >> 16) == 0u, "unknown flag bits %x", o.flags);
        steps++;
    }
    return 0;
}
