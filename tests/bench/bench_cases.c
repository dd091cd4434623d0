/* bench_cases.c - see bench_cases.h. Integer-only in the fixed build. */
#include "bench_cases.h"
#include <string.h>

#include "grip/grip_mf.h"
#include "grip/grip_mf_batch.h"
#include "grip/grip_q16.h"
#include "arith.h"
#include "mf_params.h"

static volatile int32_t sink;
static volatile grip_real_t rsink;

/* Q15.16 inputs spread over each primitive's typical domain */
static const int32_t q_in[BENCH_INPUTS] = {
    -3276800, -655360, -196608, -65536, -32768, -6554, -655, 0,
    655, 6554, 32768, 65536, 131072, 205887, 655360, 3276800,
};

static void b_mul(int i) { sink = grip_q16_mul(q_in[i], q_in[(i + 5) % BENCH_INPUTS]); }
static void b_div(int i) { sink = grip_q16_div(q_in[i], q_in[(i + 3) % BENCH_INPUTS] | 1); }
static void b_sqrt(int i) { sink = grip_q16_sqrt(q_in[i] < 0 ? -q_in[i] : q_in[i]); }
static void b_atan(int i) { sink = grip_q16_atan(q_in[i]); }
static void b_atan2(int i) { sink = grip_q16_atan2(q_in[i], q_in[(i + 7) % BENCH_INPUTS]); }
static void b_sin(int i) { sink = grip_q16_sin(q_in[i]); }
static void b_cos(int i) { sink = grip_q16_cos(q_in[i]); }
static void b_exp(int i) { sink = grip_q16_exp(q_in[i] / 8); }
static void b_log(int i) { sink = grip_q16_log(q_in[i] < 0 ? -q_in[i] : q_in[i] + 1); }

/* The arithmetic layer as the models see it: libm float or Q15.16. */
static const grip_real_t r_in[BENCH_INPUTS] = {
    RC(-50.0), RC(-10.0), RC(-3.0), RC(-1.0), RC(-0.5), RC(-0.1), RC(-0.01), RC(0.0),
    RC(0.01), RC(0.1), RC(0.5), RC(1.0), RC(2.0), RC(3.14159), RC(10.0), RC(50.0),
};

static void b_r_mul(int i) { rsink = r_mul(r_in[i], r_in[(i + 5) % BENCH_INPUTS]); }
static void b_r_div(int i) { rsink = r_div(r_in[i], r_add(r_abs(r_in[(i + 3) % BENCH_INPUTS]), RC(0.5))); }
static void b_r_sqrt(int i) { rsink = r_sqrt(r_abs(r_in[i])); }
static void b_r_atan2(int i) { rsink = r_atan2(r_in[i], r_in[(i + 7) % BENCH_INPUTS]); }
static void b_r_sin(int i) { rsink = r_sin(r_in[i]); }
static void b_r_atan(int i) { rsink = r_atan(r_in[i]); }
static void b_r_cos(int i) { rsink = r_cos(r_in[i]); }
static void b_r_exp(int i) { rsink = r_exp(r_mul(r_in[i], RC(0.125))); }

/* Magic Formula: a MF 6.1 passenger-car file (the longest equations) and
 * the G275 truck tire (MF 5.2), on 16 operating points spanning the
 * linear range, the peak and full sliding. */
static const grip_mf_params *mf61;
static const grip_mf_params *mf52;
static const grip_mf_params *mf62;
static grip_mf_input mf_in[BENCH_INPUTS];
static grip_mf_input mf52_in[BENCH_INPUTS];    /* mf_in at truck loads           */
static grip_mf_prepared mf61_prep;              /* grip_mf_prepare of mf61, mf52   */
static grip_mf_prepared mf52_prep;
/* Points per call of the lane cases: 64 in the float build, mf_in
 * (mf52_in) at four load levels (x 0.8, 0.9, 1.0, 1.1); 8 in the fixed
 * build, whose lane entry point is the scalar loop (64 would make these
 * cases 64 evaluations of ~62,000 traced Cortex-M0+ instructions each) */
#if GRIP_ARITH_FIXED
#define MF_BATCH_N 8
#else
#define MF_BATCH_N 64
#endif
static grip_mf_input mf_in_n[MF_BATCH_N];
static grip_mf_input mf52_in_n[MF_BATCH_N];
static grip_mf_output mf_out_n[MF_BATCH_N];
static grip_mf_spin mf_ts_in[BENCH_INPUTS];    /* a turn slip for mf_in, spin estimated */
static grip_mf_spin mf_tsw_in[BENCH_INPUTS];   /* ... with the spin given */
static volatile grip_real_t mf_sink;

static const grip_mf_params *tire_named(const char *name)
{
    int k;
    for (k = 0; k < grip_test_tire_count; ++k) {
        if (strcmp(grip_test_tires[k].name, name) == 0) {
            return grip_test_tires[k].params;
        }
    }
    return grip_test_tires[0].params;
}

/* Optional tables of the other model families, weakly referenced: absent
 * ones are NULL. */
extern const bench_case bench_brush_cases[] __attribute__((weak));
extern const int bench_brush_case_count __attribute__((weak));
void bench_brush_setup(void) __attribute__((weak));
extern const bench_case bench_est_cases[] __attribute__((weak));
extern const int bench_est_case_count __attribute__((weak));
void bench_est_setup(void) __attribute__((weak));
extern const bench_case bench_monitor_cases[] __attribute__((weak));
extern const int bench_monitor_case_count __attribute__((weak));
void bench_monitor_setup(void) __attribute__((weak));

const bench_case *bench_all[BENCH_MAX_CASES];
int bench_all_count;

static void bench_list(const bench_case *cases, const int *count)
{
    int k;
    if (cases == 0 || count == 0) {
        return;
    }
    for (k = 0; k < *count && bench_all_count < BENCH_MAX_CASES; ++k) {
        bench_all[bench_all_count++] = &cases[k];
    }
}

static void mf_setup(void);

void bench_cases_setup(void)
{
    mf_setup();
    if (bench_brush_setup != 0) {
        bench_brush_setup();
    }
    if (bench_est_setup != 0) {
        bench_est_setup();
    }
    if (bench_monitor_setup != 0) {
        bench_monitor_setup();
    }
    bench_all_count = 0;
    bench_list(bench_cases, &bench_case_count);
    bench_list(bench_brush_cases, &bench_brush_case_count);
    bench_list(bench_est_cases, &bench_est_case_count);
    bench_list(bench_monitor_cases, &bench_monitor_case_count);
}

static void mf_setup(void)
{
    static const grip_real_t kappa[4] = { RC(0.0), RC(0.02), RC(-0.12), RC(0.6) };
    static const grip_real_t alpha[4] = { RC(0.0), RC(0.03), RC(-0.12), RC(0.35) };
    static const grip_real_t load[4] = { RCL(1500.0), RCL(3000.0), RCL(4500.0), RCL(6500.0) };
    int i;
    mf61 = tire_named("MagicFormula61_Paramerters");
    mf52 = tire_named("335_65R22_5_G275MSA_60psi");
    mf62 = tire_named("MagicFormula62_Paramerters");
    for (i = 0; i < BENCH_INPUTS; ++i) {
        mf_in[i].kappa = kappa[i % 4];
        mf_in[i].alpha = alpha[(i / 4) % 4];
        mf_in[i].gamma = (i & 1) ? RC(0.03) : RC(-0.01);
        mf_in[i].fz = load[(i + i / 4) % 4];
        mf_in[i].p = R_ZERO;
        mf_in[i].vx = RC(20.0);
        mf_ts_in[i].omega = R_ZERO;
        mf_ts_in[i].phit = (i % 4 == 0) ? R_ZERO : ((i % 4 == 1) ? RC(0.5) : ((i % 4 == 2) ? RC(-1.0) : RC(2.0)));
        mf_tsw_in[i] = mf_ts_in[i];
        mf_tsw_in[i].omega = r_mul(r_add(R_ONE, mf_in[i].kappa), RC(20.0 / 0.3865));   /* (1 + kappa) vx / Re */
        mf52_in[i] = mf_in[i];
        mf52_in[i].fz = r_mul(RC(4.0), mf_in[i].fz);
    }
    for (i = 0; i < MF_BATCH_N; ++i) {
        static const grip_real_t scale[4] = { RC(0.8), RC(0.9), RC(1.0), RC(1.1) };
        mf_in_n[i] = mf_in[i % BENCH_INPUTS];
        mf_in_n[i].fz = r_mul(scale[i / BENCH_INPUTS], mf_in_n[i].fz);
        mf52_in_n[i] = mf52_in[i % BENCH_INPUTS];
        mf52_in_n[i].fz = r_mul(scale[i / BENCH_INPUTS], mf52_in_n[i].fz);
    }
    (void)grip_mf_prepare(mf61, mf61->options, &mf61_prep);
    (void)grip_mf_prepare(mf52, mf52->options, &mf52_prep);
}

static void b_mf61_pure(int i)
{
    grip_mf_output out;
    (void)grip_mf_eval_pure(mf61, &mf_in[i], &out);
    mf_sink = out.mz;
}

static void b_mf61_combined(int i)
{
    grip_mf_output out;
    (void)grip_mf_eval(mf61, &mf_in[i], &out);
    mf_sink = out.mz;
}

static void b_mf52_combined(int i)
{
    grip_mf_output out;
    grip_mf_input in = mf_in[i];
    in.fz = r_mul(RC(4.0), in.fz);   /* truck loads */
    (void)grip_mf_eval(mf52, &in, &out);
    mf_sink = out.mz;
}

/* The same with a prepared set (grip_mf_prepare, done once in mf_setup). */
static void b_mf61_prep_pure(int i)
{
    grip_mf_output out;
    (void)grip_mf_eval_pure_prepared(&mf61_prep, &mf_in[i], &out);
    mf_sink = out.mz;
}

static void b_mf61_prep_combined(int i)
{
    grip_mf_output out;
    (void)grip_mf_eval_prepared(&mf61_prep, &mf_in[i], &out);
    mf_sink = out.mz;
}

static void b_mf52_prep_combined(int i)
{
    grip_mf_output out;
    (void)grip_mf_eval_prepared(&mf52_prep, &mf52_in[i], &out);
    mf_sink = out.mz;
}

/* Four wheels per call (grip_mf_eval_prepared_batch): the count is per
 * call, a quarter of it per evaluation. */
static void b_mf61_prep_batch4(int i)
{
    grip_mf_output out[4];
    (void)grip_mf_eval_prepared_batch(&mf61_prep, 4u, &mf_in[i & ~3], out, 0);
    mf_sink = out[3].mz;
}

/* MF_BATCH_N points per call: the count is per call, 1/MF_BATCH_N of it
 * per point. The lane evaluation (grip_mf_eval_prepared_lanes: blocks of
 * GRIP_MF_LANES_N points side by side where GRIP_MF_LANES is 1, else the
 * scalar loop of grip_mf_eval_prepared_batch). The call's argument i does
 * not change the points. */
static void b_mf61_lanes(int i)
{
    (void)i;
    (void)grip_mf_eval_prepared_lanes(&mf61_prep, MF_BATCH_N, mf_in_n, mf_out_n, 0);
    mf_sink = mf_out_n[MF_BATCH_N - 1].mz;
}

static void b_mf61_lanes_pure(int i)
{
    (void)i;
    (void)grip_mf_eval_pure_prepared_lanes(&mf61_prep, MF_BATCH_N, mf_in_n, mf_out_n, 0);
    mf_sink = mf_out_n[MF_BATCH_N - 1].mz;
}

static void b_mf52_lanes(int i)
{
    (void)i;
    (void)grip_mf_eval_prepared_lanes(&mf52_prep, MF_BATCH_N, mf52_in_n, mf_out_n, 0);
    mf_sink = mf_out_n[MF_BATCH_N - 1].mz;
}

/* The extended outputs (grip_mf_eval_ext): the set (Re, the
 * relaxation lengths and the slip stiffnesses: at most 15 % above the plain
 * combined evaluation), every channel, and MF 6.2's iterated loaded
 * radius alone. */
#define MF_EXT_RE_SIGMA_K (GRIP_MF_EXT_RE | GRIP_MF_EXT_SIGMAX | GRIP_MF_EXT_SIGMAY | GRIP_MF_EXT_KXK | GRIP_MF_EXT_KYA)
static void b_mf61_ext_re_sigma_k(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext(mf61, &mf_in[i], MF_EXT_RE_SIGMA_K, &out);
    mf_sink = out.sigmay;
}

static void b_mf61_ext_all(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext(mf61, &mf_in[i], GRIP_MF_EXT_ALL, &out);
    mf_sink = out.my;
}

static void b_mf62_ext_rl(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext(mf62, &mf_in[i], GRIP_MF_EXT_RL, &out);
    mf_sink = out.rl;
}

/* Turn slip (grip_mf_eval_ext only): the forces alone without and with
 * it (the spin estimated from Re, or given), so that the difference is the
 * cost of the turn slip. */
static void b_mf61_ext_forces(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext(mf61, &mf_in[i], 0u, &out);
    mf_sink = out.mz;
}

static void b_mf61_ext_turn_slip(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext_spin(mf61, &mf_in[i], &mf_ts_in[i], GRIP_MF_USE_TURN_SLIP, &out);
    mf_sink = out.mz;
}

static void b_mf61_ext_turn_slip_omega(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext_spin(mf61, &mf_in[i], &mf_tsw_in[i], GRIP_MF_USE_TURN_SLIP, &out);
    mf_sink = out.mz;
}

static void b_mf52_ext_re_sigma_k(int i)
{
    grip_mf_output_ext out;
    grip_mf_input in = mf_in[i];
    in.fz = r_mul(RC(4.0), in.fz);   /* truck loads */
    (void)grip_mf_eval_ext(mf52, &in, MF_EXT_RE_SIGMA_K, &out);
    mf_sink = out.sigmay;
}

/* The same with a prepared set (grip_mf_eval_ext_prepared): against
 * mf61_prep_combined_fx_fy_mz, the cost of the channels alone. */
static void b_mf61_prep_ext_forces(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext_prepared(&mf61_prep, &mf_in[i], 0u, &out);
    mf_sink = out.mz;
}

static void b_mf61_prep_ext_re_sigma_k(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext_prepared(&mf61_prep, &mf_in[i], MF_EXT_RE_SIGMA_K, &out);
    mf_sink = out.sigmay;
}

static void b_mf61_prep_ext_re(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext_prepared(&mf61_prep, &mf_in[i], GRIP_MF_EXT_RE, &out);
    mf_sink = out.re;
}

static void b_mf61_prep_ext_k(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext_prepared(&mf61_prep, &mf_in[i], GRIP_MF_EXT_KXK | GRIP_MF_EXT_KYA, &out);
    mf_sink = out.kya;
}

static void b_mf61_prep_ext_sigma(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext_prepared(&mf61_prep, &mf_in[i], GRIP_MF_EXT_SIGMAX | GRIP_MF_EXT_SIGMAY, &out);
    mf_sink = out.sigmay;
}

static void b_mf52_prep_ext_re_sigma_k(int i)
{
    grip_mf_output_ext out;
    (void)grip_mf_eval_ext_prepared(&mf52_prep, &mf52_in[i], MF_EXT_RE_SIGMA_K, &out);
    mf_sink = out.sigmay;
}

const bench_case bench_cases[] = {
    { "mf61_pure_fx_fy_mz", b_mf61_pure }, { "mf61_combined_fx_fy_mz", b_mf61_combined },
    { "mf52_combined_fx_fy_mz", b_mf52_combined },
    { "mf61_prep_pure_fx_fy_mz", b_mf61_prep_pure }, { "mf61_prep_combined_fx_fy_mz", b_mf61_prep_combined },
    { "mf52_prep_combined_fx_fy_mz", b_mf52_prep_combined }, { "mf61_prep_batch4_combined", b_mf61_prep_batch4 },
    { "mf61_lanes_combined", b_mf61_lanes }, { "mf61_lanes_pure", b_mf61_lanes_pure },
    { "mf52_lanes_combined", b_mf52_lanes },
    { "mf61_ext_re_sigma_k", b_mf61_ext_re_sigma_k }, { "mf61_ext_all", b_mf61_ext_all },
    { "mf62_ext_rl", b_mf62_ext_rl }, { "mf52_ext_re_sigma_k", b_mf52_ext_re_sigma_k },
    { "mf61_ext_forces", b_mf61_ext_forces }, { "mf61_ext_turn_slip", b_mf61_ext_turn_slip },
    { "mf61_ext_turn_slip_omega", b_mf61_ext_turn_slip_omega },
    { "mf61_prep_ext_forces", b_mf61_prep_ext_forces }, { "mf61_prep_ext_re_sigma_k", b_mf61_prep_ext_re_sigma_k },
    { "mf52_prep_ext_re_sigma_k", b_mf52_prep_ext_re_sigma_k },
    { "mf61_prep_ext_re", b_mf61_prep_ext_re }, { "mf61_prep_ext_k", b_mf61_prep_ext_k },
    { "mf61_prep_ext_sigma", b_mf61_prep_ext_sigma },
    { "r_mul", b_r_mul }, { "r_div", b_r_div }, { "r_sqrt", b_r_sqrt },
    { "r_atan2", b_r_atan2 }, { "r_sin", b_r_sin }, { "r_exp", b_r_exp },
    { "r_atan", b_r_atan }, { "r_cos", b_r_cos },
    { "q16_mul", b_mul },   { "q16_div", b_div }, { "q16_sqrt", b_sqrt },
    { "q16_atan", b_atan }, { "q16_atan2", b_atan2 }, { "q16_sin", b_sin },
    { "q16_cos", b_cos },   { "q16_exp", b_exp }, { "q16_log", b_log },
};
const int bench_case_count = (int)(sizeof(bench_cases) / sizeof(bench_cases[0]));
