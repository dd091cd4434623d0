/*
 * fuzz_mf_thermal.c - grip_mf_thermal_init / _step / _forces.
 *
 * Base set: the golden-vector set of tools/grip_tools/golden_mf_thermal.
 * Input: [t_init][dt][t][steps: v alpha slip fz t_road (words)] ... with
 * mutations of the set applied first when byte 0 is odd.
 * Properties: no crash or sanitizer report; documented statuses; outputs
 * and the state temperature finite; the temperature stays in
 * [t_min, t_max] after every successful step; zero output and unchanged
 * state on error; with the unmutated set and finite inputs |Fx|, |Fy| <=
 * 3 Fz' + |svx| + |svy| + 1 N (Fz' clamped to [0, fz_max]).
 */
#include "fuzz_common.h"
#include "grip/grip_mf_thermal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define P(f) FZ_F(grip_mf_thermal_params, f, FZ_QS)
#define PL(f) FZ_F(grip_mf_thermal_params, f, FZ_QL)
static const fz_field fields[] = {
    PL(fz0), P(t0), PL(dx0), PL(kx0), P(cx), P(ex), P(shx), PL(svx), P(ax), P(bx),
    PL(dy0), PL(ky0), P(cy), P(ey), P(shy), PL(svy), P(ay), P(by),
    P(bxa), P(cxa), P(exa), P(shxa), P(bys), P(cys), P(eys), P(shys), PL(svys),
    PL(w), P(kappa), PL(fz_max), P(alpha_max), P(slip_max), P(v_max), P(t_min), P(t_max),
};

static void base(grip_mf_thermal_params *p)
{
    p->fz0 = fz_from_d(4600.0, FZ_QL); p->t0 = fz_from_d(30.0, FZ_QS);
    p->dx0 = fz_from_d(4800.0, FZ_QL); p->kx0 = fz_from_d(92000.0, FZ_QL);
    p->cx = fz_from_d(1.65, FZ_QS); p->ex = fz_from_d(-0.2, FZ_QS);
    p->shx = fz_from_d(0.0005, FZ_QS); p->svx = fz_from_d(15.0, FZ_QL);
    p->ax = fz_from_d(-0.004, FZ_QS); p->bx = fz_from_d(-0.006, FZ_QS);
    p->dy0 = fz_from_d(4500.0, FZ_QL); p->ky0 = fz_from_d(68000.0, FZ_QL);
    p->cy = fz_from_d(1.35, FZ_QS); p->ey = fz_from_d(-0.6, FZ_QS);
    p->shy = fz_from_d(0.0015, FZ_QS); p->svy = fz_from_d(25.0, FZ_QL);
    p->ay = fz_from_d(-0.003, FZ_QS); p->by = fz_from_d(-0.008, FZ_QS);
    p->bxa = fz_from_d(13.0, FZ_QS); p->cxa = fz_from_d(1.0, FZ_QS);
    p->exa = fz_from_d(-0.3, FZ_QS); p->shxa = fz_from_d(0.001, FZ_QS);
    p->bys = fz_from_d(9.0, FZ_QS); p->cys = fz_from_d(1.0, FZ_QS);
    p->eys = fz_from_d(-0.2, FZ_QS); p->shys = fz_from_d(0.002, FZ_QS);
    p->svys = fz_from_d(0.0, FZ_QL); p->w = fz_from_d(1500.0, FZ_QL);
    p->kappa = fz_from_d(0.08, FZ_QS); p->fz_max = fz_from_d(10000.0, FZ_QL);
    p->alpha_max = fz_from_d(0.5, FZ_QS); p->slip_max = fz_from_d(1.0, FZ_QS);
    p->v_max = fz_from_d(60.0, FZ_QS); p->t_min = fz_from_d(-30.0, FZ_QS);
    p->t_max = fz_from_d(130.0, FZ_QS);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r = { data, size };
    grip_mf_thermal_params p;
    grip_mf_thermal_state st;
    grip_real_t t_init;
    grip_real_t dt;
    grip_real_t t;
    grip_status_t s;
    int nmut = 0;
    int steps = 0;
    uint8_t mode = fz_u8(&r);
    base(&p);
    if (mode & 1u) {
        nmut = fz_mutate(&r, &p, fields, sizeof fields / sizeof fields[0], 1 + (mode >> 1) % 8);
    }
    t_init = fz_real(&r, FZ_QS);
    dt = fz_real(&r, FZ_QS);
    t = fz_real(&r, FZ_QS);
    s = grip_mf_thermal_init(&st, &p, t_init);
    FZ_CHECK(fz_status_known(s), "init status %d", (int)s);
    if (nmut == 0 && fz_finite(t_init)) {
        FZ_CHECK(s == GRIP_OK || s == GRIP_WARN_CLAMPED, "base set init %d", (int)s);
    }
    while (r.n > 0 && steps < 64) {
        grip_mf_thermal_inputs in;
        grip_mf_thermal_output o;
        grip_mf_thermal_state before = st;
        grip_real_t fx = 1;
        grip_real_t fy = 1;
        grip_status_t s2;
        int finite_in;
        in.v = fz_real(&r, FZ_QS);
        in.alpha = fz_real(&r, FZ_QS);
        in.slip = fz_real(&r, FZ_QS);
        in.fz = fz_real(&r, FZ_QL);
        in.t_road = fz_real(&r, FZ_QS);
        finite_in = fz_finite(in.v) && fz_finite(in.alpha) && fz_finite(in.slip) && fz_finite(in.fz) &&
                    fz_finite(in.t_road);
        s2 = grip_mf_thermal_forces(&st, &in, t, &fx, &fy);
        FZ_CHECK(fz_status_known(s2), "forces status %d", (int)s2);
        FZ_CHECK(fz_finite(fx) && fz_finite(fy), "forces non-finite");
        if (s2 < 0) {
            FZ_CHECK(fx == 0 && fy == 0, "forces error with output");
        }
        s2 = grip_mf_thermal_step(&st, &in, dt, &o);
        FZ_CHECK(fz_status_known(s2), "step status %d", (int)s2);
        FZ_CHECK(fz_finite(o.fx) && fz_finite(o.fy) && fz_finite(o.q) && fz_finite(o.vs) && fz_finite(o.t),
                 "step non-finite output");
        FZ_CHECK(fz_finite(st.t), "state non-finite");
        if (s2 < 0) {
            FZ_CHECK(o.fx == 0 && o.fy == 0 && o.q == 0 && o.vs == 0 && o.t == 0, "step error with output");
            FZ_CHECK(memcmp(&before, &st, sizeof st) == 0, "step error changed the state");
        } else {
            FZ_CHECK(st.t >= p.t_min && st.t <= p.t_max, "temperature %g outside [t_min, t_max]",
                     fz_d(st.t, FZ_QS));
            if (nmut == 0 && finite_in) {
                double f = fz_d(in.fz, FZ_QL);
                double fc = f < 0.0 ? 0.0 : (f > 10000.0 ? 10000.0 : f);
                double lim = 3.0 * fc + 15.0 + 25.0 + 1.0;
                FZ_CHECK(fabs(fz_d(o.fx, FZ_QL)) <= lim && fabs(fz_d(o.fy, FZ_QL)) <= lim,
                         "|F| beyond 3 Fz: fx %g fy %g fz %g", fz_d(o.fx, FZ_QL), fz_d(o.fy, FZ_QL), fc);
            }
        }
        steps++;
    }
    return 0;
}
