/*
 * fuzz_chain.c - the onboard data flow on hostile input sequences:
 * sample -> grip_calib_apply -> grip_monitor_step (with the estimator's
 * previous output) -> grip_est_step -> grip_monitor_gate on a copy, as an
 * application wires it.
 *
 * Input: [set] [calibration: per calibrated input offset (int8 -> [-10, 10]),
 * gain (u8 -> [0.5, 2]), delay (u8 mod 33 steps)] then up to 200 steps of
 * [valid mask (3 bytes)] [17 input words] as in fuzz_est.c.
 * Properties: no crash or sanitizer report; every call returns GRIP_OK;
 * every calibrated value and every monitor residual finite, calibrated
 * values of invalid inputs never used (the estimator sees them invalid);
 * the gate clears the lateral outputs exactly when the monitor says degraded;
 * estimator outputs as fuzz_est checks them (fuzz_est_common.h).
 */
#include "fuzz_est_common.h"
#include "grip/grip_calib.h"
#include "grip/grip_monitor.h"
#include "grip/grip_signals.h"

static grip_mf_params sets[FZ_EST_MAX_SETS];
static grip_est_config_t cfgs[FZ_EST_MAX_SETS];
static int nsets;
static grip_monitor_config_t mon_cfg;

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    nsets = fz_est_load_sets(sets, cfgs);
    if (nsets == 0 || grip_monitor_config_default(&mon_cfg) != GRIP_OK) {
        fprintf(stderr, "fuzz_chain: no usable .tir parameter set or monitor default (run from the repository root)\n");
        exit(2);
    }
    return 0;
}

static grip_real_t qs_of(double x)
{
#if GRIP_ARITH_FIXED
    return (grip_real_t)(x * 65536.0);
#else
    return (grip_real_t)x;
#endif
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static grip_est_t est;
    static grip_calib_t cal;
    static grip_monitor_t mon;
    grip_calib_config_t ccfg;
    grip_est_output_t prev;
    fz_reader r = { data, size };
    int set = fz_u8(&r) % nsets;
    int steps = 0, have_prev = 0;
    uint32_t i;
    grip_status_t s;

    FZ_CHECK(grip_calib_config_identity(&ccfg) == GRIP_OK, "calib identity");
    for (i = 0; i < GRIP_CALIB_N; i++) {
        ccfg.offset[i] = qs_of((double)(int8_t)fz_u8(&r) * (10.0 / 128.0));
        ccfg.gain[i] = qs_of(0.5 + 1.5 * (double)fz_u8(&r) / 255.0);
        ccfg.delay[i] = (uint32_t)fz_u8(&r) % (GRIP_CALIB_DELAY_MAX + 1u);
    }
    s = grip_calib_init(&cal, &ccfg);
    FZ_CHECK(s == GRIP_OK, "calib init %d", (int)s);
    s = grip_monitor_init(&mon, &mon_cfg);
    FZ_CHECK(s == GRIP_OK, "monitor init %d", (int)s);
    s = grip_est_init(&est, &cfgs[set]);
    FZ_CHECK(s == GRIP_OK, "est init %d", (int)s);
    memset(&prev, 0, sizeof prev);

    while (r.n > 0 && steps < 200) {
        grip_input_sample_t in, c;
        grip_monitor_report_t rep;
        grip_est_output_t o;
        fz_est_read_sample(&r, steps, &in);
        s = grip_calib_apply(&cal, &in, &c);
        FZ_CHECK(s == GRIP_OK, "step %d: calib status %d", steps, (int)s);
        for (i = 0; i < GRIP_IN_COUNT; i++) {
            FZ_CHECK(!c.valid[i] || fz_finite(c.value[i]), "step %d: calibrated input %u non-finite", steps, i);
        }
        s = grip_monitor_step(&mon, &c, have_prev ? &prev : NULL, &rep);
        FZ_CHECK(s == GRIP_OK, "step %d: monitor status %d", steps, (int)s);
        for (i = 0; i < GRIP_MON_N; i++) {
            FZ_CHECK(fz_finite(rep.resid[i]), "step %d: monitor residual %u non-finite", steps, i);
        }
        FZ_CHECK(rep.detected == 0 || rep.detected == 1, "step %d: detected %d", steps, (int)rep.detected);
        s = grip_est_step(&est, &c, &o);
        FZ_CHECK(s == GRIP_OK, "step %d: est status %d", steps, (int)s);
        fz_est_check_output(steps, &o);
        {
            /* the consumer's copy through the degraded gate */
            grip_est_output_t use = o;
            s = grip_monitor_gate(&rep, GRIP_MON_GATE_DEFAULT, &use);
            FZ_CHECK(s == GRIP_OK, "step %d: gate status %d", steps, (int)s);
            FZ_CHECK(rep.degraded == 0u ? (use.valid == o.valid && use.flags == o.flags)
                                        : ((use.valid & GRIP_MON_GATE_CLEARS) == 0u &&
                                           (use.flags & GRIP_EST_F_INPUT_DEGRADED) != 0u),
                     "step %d: gate valid 0x%x flags 0x%x for degraded 0x%x", steps, (unsigned)use.valid,
                     (unsigned)use.flags, (unsigned)rep.degraded);
        }
        prev = o;
        have_prev = 1;
        steps++;
    }
    return 0;
}
