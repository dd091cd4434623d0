/*
 * fuzz_est.c - the estimator (grip_est_step) on hostile input sequences.
 *
 * Configuration: grip_est_config_default with each shared .tir parameter set
 * (tests/data/chrono-tir, tests/data/mfeval-tir), read at start-up.
 * Input: [set] then up to 200 steps of [valid mask (3 bytes)] [17 input
 * words] (each input in its own format, grip_input_is_ql); an invalid input
 * gets fault GRIP_SIG_STALE and value 0, as the assembler would send it;
 * before every 16th step two more words: a road-friction measurement
 * (grip_est_measure_friction, mu_road and its deviation, QS), which must
 * return GRIP_OK or, out of its range, GRIP_ERR_INPUT.
 * Properties: no crash or sanitizer report; every step returns GRIP_OK;
 * every output finite; util in [0, 1.5]; mu_conf in [0, 1]; steer_char in
 * {-1, 0, 1}; unknown flag bits never set. Fault injection proper (which
 * outputs must lose validity for which missing input) is the estimator's
 * own test (tests/unit/test_est_robust.c); here only robustness.
 */
#include "fuzz_est_common.h"
#include "grip/grip_signals.h"

static grip_mf_params sets[FZ_EST_MAX_SETS];
static grip_est_config_t cfgs[FZ_EST_MAX_SETS];
static int nsets;

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    nsets = fz_est_load_sets(sets, cfgs);
    if (nsets == 0) {
        fprintf(stderr, "fuzz_est: no usable .tir parameter set (run from the repository root)\n");
        exit(2);
    }
    return 0;
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
        if ((steps & 15) == 15) {
            grip_real_t mu_road = fz_real(&r, 0);
            grip_real_t mu_sd = fz_real(&r, 0);
            s = grip_est_measure_friction(&est, mu_road, mu_sd);
            FZ_CHECK(s == GRIP_OK || s == GRIP_ERR_INPUT, "step %d: friction status %d", steps, (int)s);
        }
        fz_est_read_sample(&r, steps, &in);
        s = grip_est_step(&est, &in, &o);
        FZ_CHECK(s == GRIP_OK, "step %d: status %d", steps, (int)s);
        fz_est_check_output(steps, &o);
        steps++;
    }
    return 0;
}
