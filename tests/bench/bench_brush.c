/*
 * bench_brush.c - benchmark cases of the brush-model family
 * (include/grip/grip_brush.h). Integer-only in the fixed build: every input
 * and parameter is a compile-time RC()/RCL() constant.
 *
 * The Neo-FIALA inputs are all in partial adhesion (0 < rh < 1), i.e. the
 * worst-case path: the full fixed count of GRIP_BRUSH_ROOT_ITERS
 * Anderson-Bjorck steps (9 residual evaluations); full sliding returns after
 * one. The lead wires bench_brush_cases[] into the bench table and calls
 * bench_brush_setup() from bench_cases_setup() (it prepares the models of
 * the *_model cases, i.e. the per-call path of an ECU task).
 */
#include "bench_cases.h"
#include "grip/grip_brush.h"
#include "arith.h"

extern const bench_case bench_brush_cases[];
extern const int bench_brush_case_count;
void bench_brush_setup(void);

static volatile grip_real_t bsink;

/* A passenger-car set with every coupling active (docs/brush-models.md). */
static const grip_neofiala_params k_nf = {
    RC(0.16), RC(0.19), RCL(95000.0), RCL(72000.0), RC(1.15), RC(0.95), RC(0.003), 4,
    RC(0.05), RC(0.01), RC(0.0), RC(0.002), RC(0.0), RC(0.02), RCL(15000.0), RCL(2.0),
    RC(0.15), RC(0.02), RCL(200000.0), RCL(500.0), RCL(10000.0), RC(0.6), RC(1.0), RC(0.2), RC(60.0),
};
/* The pure-lateral variant of seed section 5.3: skew and shift from Mz. */
static const grip_neofiala_params k_nf_lat = {
    RC(0.16), RC(0.19), RCL(95000.0), RCL(72000.0), RC(1.15), RC(0.95), RC(0.003), 5,
    RC(0.0), RC(0.0), RC(0.1), RC(0.0), RC(0.0012), RC(0.02), RCL(15000.0), RCL(2.0),
    RC(0.0), RC(0.0), RCL(0.0), RCL(500.0), RCL(10000.0), RC(0.6), RC(1.0), RC(0.2), RC(60.0),
};
/* As k_nf, with n = 7 (the longest power chain) and the Mz-dependent skew
 * and centre shift as well (c_qm, xi != 0: the moment equation is the
 * quadratic, one square root more per residual): the most expensive path. */
static const grip_neofiala_params k_nf_all = {
    RC(0.16), RC(0.19), RCL(95000.0), RCL(72000.0), RC(1.15), RC(0.95), RC(0.003), 7,
    RC(0.05), RC(0.01), RC(0.05), RC(0.002), RC(0.001), RC(0.02), RCL(15000.0), RCL(2.0),
    RC(0.15), RC(0.02), RCL(200000.0), RCL(500.0), RCL(10000.0), RC(0.6), RC(1.0), RC(0.2), RC(60.0),
};
static const grip_brush_params k_br = {
    RCL(80000.0), RC(1.1), RC(0.9), RC(0.005), 4, RCL(200.0), RCL(10000.0), RC(1.0), RC(60.0),
};
static const grip_sakai_params k_sk = {
    RCL(57200.0), RCL(250000.0), RC(1.0), RC(0.8), RC(0.18), RCL(200.0), RCL(10000.0), RC(0.6), RC(1.0),
};
static const grip_fiala_params k_fi = {
    RCL(60000.0), RC(1.0), RC(0.2), RCL(200.0), RCL(10000.0), RC(0.6),
};

/* combined slip, braking and driving, partial adhesion */
static const grip_real_t k_kappa[BENCH_INPUTS] = {
    RC(-0.02), RC(-0.01), RC(-0.005), RC(0.0), RC(0.005), RC(0.01), RC(0.02), RC(-0.03),
    RC(-0.015), RC(0.015), RC(0.025), RC(-0.002), RC(0.002), RC(-0.008), RC(0.008), RC(0.0),
};
static const grip_real_t k_alpha[BENCH_INPUTS] = {
    RC(0.01), RC(-0.02), RC(0.03), RC(0.04), RC(-0.01), RC(0.005), RC(0.015), RC(0.0),
    RC(-0.03), RC(0.02), RC(-0.005), RC(0.045), RC(-0.04), RC(0.025), RC(-0.025), RC(0.01),
};
static const grip_real_t k_gamma[BENCH_INPUTS] = {
    RC(0.0), RC(0.02), RC(-0.02), RC(0.0), RC(0.05), RC(0.0), RC(-0.05), RC(0.01),
    RC(0.0), RC(0.03), RC(0.0), RC(-0.01), RC(0.0), RC(0.04), RC(0.0), RC(0.0),
};
static const grip_real_t k_fz[BENCH_INPUTS] = {
    RCL(4000.0), RCL(5000.0), RCL(3000.0), RCL(6000.0), RCL(4500.0), RCL(2500.0), RCL(7000.0), RCL(5500.0),
    RCL(4000.0), RCL(3500.0), RCL(6500.0), RCL(5000.0), RCL(4200.0), RCL(3800.0), RCL(4800.0), RCL(8000.0),
};

static void b_neofiala_combined(int i)
{
    grip_brush_out o;
    (void)grip_neofiala_eval(&k_nf, k_kappa[i], k_alpha[i], k_gamma[i], k_fz[i], RC(20.0), &o);
    bsink = o.mz;
}

static grip_neofiala_model m_nf;
static grip_neofiala_model m_nf_lat;
static grip_neofiala_model m_nf_all;

void bench_brush_setup(void)
{
    (void)grip_neofiala_prepare(&k_nf, &m_nf);
    (void)grip_neofiala_prepare(&k_nf_all, &m_nf_all);
    (void)grip_neofiala_prepare(&k_nf_lat, &m_nf_lat);
}

/* prepared once (bench_brush_setup): inputs validated per call, parameters not */
static void b_neofiala_combined_model(int i)
{
    grip_brush_out o;
    (void)grip_neofiala_eval_model(&m_nf, k_kappa[i], k_alpha[i], k_gamma[i], k_fz[i], RC(20.0), &o);
    bsink = o.mz;
}

/* every coupling active, n = 7 (k_nf_all), prepared */
static void b_neofiala_allcoupled_model(int i)
{
    grip_brush_out o;
    (void)grip_neofiala_eval_model(&m_nf_all, k_kappa[i], k_alpha[i], k_gamma[i], k_fz[i], RC(20.0), &o);
    bsink = o.mz;
}

static void b_neofiala_lateral_model(int i)
{
    grip_brush_out o;
    (void)grip_neofiala_eval_model(&m_nf_lat, R_ZERO, k_alpha[(i + 3) % BENCH_INPUTS], R_ZERO, k_fz[i], RC(20.0),
                                   &o);
    bsink = o.mz;
}

static void b_neofiala_lateral(int i)
{
    grip_brush_out o;
    (void)grip_neofiala_eval(&k_nf_lat, R_ZERO, k_alpha[(i + 3) % BENCH_INPUTS], R_ZERO, k_fz[i], RC(20.0), &o);
    bsink = o.mz;
}

static void b_brush(int i)
{
    grip_brush_out o;
    (void)grip_brush_eval(&k_br, k_kappa[i], k_fz[i], RC(20.0), &o);
    bsink = o.fx;
}

static void b_sakai(int i)
{
    grip_brush_out o;
    (void)grip_sakai_eval(&k_sk, k_kappa[i], k_alpha[i], k_fz[i], &o);
    bsink = o.mz;
}

static void b_fiala(int i)
{
    grip_brush_out o;
    (void)grip_fiala_eval(&k_fi, k_alpha[i], k_fz[i], &o);
    bsink = o.mz;
}

const bench_case bench_brush_cases[] = {
    { "neofiala_combined", b_neofiala_combined },
    { "neofiala_combined_model", b_neofiala_combined_model },
    { "neofiala_allcoupled_model", b_neofiala_allcoupled_model },
    { "neofiala_lateral", b_neofiala_lateral },
    { "neofiala_lateral_model", b_neofiala_lateral_model },
    { "brush_fx", b_brush },
    { "sakai", b_sakai },
    { "fiala", b_fiala },
};
const int bench_brush_case_count = (int)(sizeof(bench_brush_cases) / sizeof(bench_brush_cases[0]));
