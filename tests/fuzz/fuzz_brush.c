/*
 * fuzz_brush.c - the brush family (grip_fiala_eval, grip_brush_eval,
 * grip_sakai_eval, grip_neofiala_eval / _prepare / _eval_model).
 *
 * Base sets: those of tests/unit/test_brush_inputs.c. Input: [model]
 * [kappa alpha gamma fz vx as words][mutations of that model's set...].
 * Properties: no crash or sanitizer report; documented statuses; outputs
 * finite, 0 <= rh <= 1; on error all outputs zero and rh = 1; Neo-FIALA:
 * grip_neofiala_eval and prepare + eval_model agree bit for bit (as the
 * header promises); with the unmutated set and finite inputs: status OK,
 * WARN_CLAMPED or (Fz <= 0) ERR_INPUT, and |Fx|, |Fy| <= 1.5 mu_s Fz' + 1 N,
 * |Mz| <= 2 mu_s Fz' l + 1 N m (Fz' the load clamped to [fz_min, fz_max]).
 */
#include "fuzz_common.h"
#include "grip/grip_brush.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const fz_field f_fiala[] = {
    FZ_F(grip_fiala_params, ky, FZ_QL), FZ_F(grip_fiala_params, mu, FZ_QS), FZ_F(grip_fiala_params, l, FZ_QS),
    FZ_F(grip_fiala_params, fz_min, FZ_QL), FZ_F(grip_fiala_params, fz_max, FZ_QL),
    FZ_F(grip_fiala_params, alpha_max, FZ_QS),
};
static const fz_field f_brush[] = {
    FZ_F(grip_brush_params, kx, FZ_QL), FZ_F(grip_brush_params, mu_s, FZ_QS),
    FZ_F(grip_brush_params, mu_d0, FZ_QS), FZ_F(grip_brush_params, a_v, FZ_QS), FZ_F(grip_brush_params, n, 2),
    FZ_F(grip_brush_params, fz_min, FZ_QL), FZ_F(grip_brush_params, fz_max, FZ_QL),
    FZ_F(grip_brush_params, kappa_max, FZ_QS), FZ_F(grip_brush_params, v_max, FZ_QS),
};
static const fz_field f_sakai[] = {
    FZ_F(grip_sakai_params, k, FZ_QL), FZ_F(grip_sakai_params, g_y, FZ_QL), FZ_F(grip_sakai_params, mu_s, FZ_QS),
    FZ_F(grip_sakai_params, mu_d, FZ_QS), FZ_F(grip_sakai_params, l, FZ_QS),
    FZ_F(grip_sakai_params, fz_min, FZ_QL), FZ_F(grip_sakai_params, fz_max, FZ_QL),
    FZ_F(grip_sakai_params, alpha_max, FZ_QS), FZ_F(grip_sakai_params, kappa_max, FZ_QS),
};
#define N(f, fmt) FZ_F(grip_neofiala_params, f, fmt)
static const fz_field f_neo[] = {
    N(l, FZ_QS), N(w, FZ_QS), N(kx, FZ_QL), N(ky, FZ_QL), N(mu_s, FZ_QS), N(mu_d0, FZ_QS), N(a_v, FZ_QS),
    N(n, 2), N(q0, FZ_QS), N(c_q, FZ_QS), N(c_qm, FZ_QS), N(c_xc, FZ_QS), N(xi, FZ_QS), N(eps, FZ_QS),
    N(g_mz, FZ_QL), N(a_x, FZ_QL), N(c_gamma, FZ_QS), N(h, FZ_QS), N(g_my, FZ_QL), N(fz_min, FZ_QL),
    N(fz_max, FZ_QL), N(alpha_max, FZ_QS), N(kappa_max, FZ_QS), N(gamma_max, FZ_QS), N(v_max, FZ_QS),
};
#define NF(a) (sizeof(a) / sizeof((a)[0]))
#define QS(x) fz_from_d((x), FZ_QS)
#define QL(x) fz_from_d((x), FZ_QL)

static void check(const char *what, grip_status_t s, const grip_brush_out *o, int pristine, int finite_in,
                  double fz, double fz_min, double fz_max, double mu, double l)
{
    FZ_CHECK(fz_status_known(s), "%s status %d", what, (int)s);
    FZ_CHECK(fz_finite(o->fx) && fz_finite(o->fy) && fz_finite(o->mz) && fz_finite(o->rh), "%s non-finite",
             what);
    FZ_CHECK(fz_d(o->rh, FZ_QS) >= 0.0 && fz_d(o->rh, FZ_QS) <= 1.0, "%s rh %g", what, fz_d(o->rh, FZ_QS));
    if (s < 0) {
        FZ_CHECK(o->fx == 0 && o->fy == 0 && o->mz == 0 && o->rh == QS(1.0), "%s error output not zero", what);
    }
    if (pristine && finite_in) {
        /* loads in (0, fz_min) are evaluated at fz_min, above fz_max at fz_max */
        double fc = fz > fz_max ? fz_max : (fz < fz_min ? fz_min : fz);
        if (!(fz > 0.0)) {
            FZ_CHECK(s == GRIP_ERR_INPUT, "%s Fz <= 0: status %d", what, (int)s);
            return;
        }
        FZ_CHECK(s == GRIP_OK || s == GRIP_WARN_CLAMPED, "%s valid call: status %d", what, (int)s);
        FZ_CHECK(fabs(fz_d(o->fx, FZ_QL)) <= 1.5 * mu * fc + 1.0 && fabs(fz_d(o->fy, FZ_QL)) <= 1.5 * mu * fc + 1.0,
                 "%s |F| beyond 1.5 mu Fz: fx %g fy %g fz %g", what, fz_d(o->fx, FZ_QL), fz_d(o->fy, FZ_QL), fc);
        FZ_CHECK(fabs(fz_d(o->mz, FZ_QL)) <= 2.0 * mu * fc * l + 1.0, "%s |Mz| %g beyond 2 mu Fz l", what,
                 fz_d(o->mz, FZ_QL));
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r = { data, size };
    uint8_t model = fz_u8(&r) % 4u;
    grip_real_t kappa = fz_real(&r, FZ_QS);
    grip_real_t alpha = fz_real(&r, FZ_QS);
    grip_real_t gamma = fz_real(&r, FZ_QS);
    grip_real_t fz = fz_real(&r, FZ_QL);
    grip_real_t vx = fz_real(&r, FZ_QS);
    int fin = fz_finite(kappa) && fz_finite(alpha) && fz_finite(gamma) && fz_finite(fz) && fz_finite(vx);
    double fzd = fz_d(fz, FZ_QL);
    grip_brush_out o;
    grip_status_t s;
    int nmut;
    memset(&o, 0x5A, sizeof o);
    if (model == 0) {
        grip_fiala_params p;
        p.ky = QL(60000.0); p.mu = QS(1.0); p.l = QS(0.2);
        p.fz_min = QL(200.0); p.fz_max = QL(10000.0); p.alpha_max = QS(0.6);
        nmut = fz_mutate(&r, &p, f_fiala, NF(f_fiala), 6);
        s = grip_fiala_check_params(&p);
        FZ_CHECK(s == GRIP_OK || s == GRIP_ERR_PARAM, "check %d", (int)s);
        s = grip_fiala_eval(&p, alpha, fz, &o);
        check("fiala", s, &o, nmut == 0, fin && fz_finite(alpha), fzd, 200.0, 10000.0, 1.0, 0.2);
    } else if (model == 1) {
        grip_brush_params p;
        p.kx = QL(80000.0); p.mu_s = QS(1.1); p.mu_d0 = QS(0.9); p.a_v = QS(0.005); p.n = 4;
        p.fz_min = QL(200.0); p.fz_max = QL(10000.0); p.kappa_max = QS(1.0); p.v_max = QS(60.0);
        nmut = fz_mutate(&r, &p, f_brush, NF(f_brush), 6);
        s = grip_brush_check_params(&p);
        FZ_CHECK(s == GRIP_OK || s == GRIP_ERR_PARAM, "check %d", (int)s);
        s = grip_brush_eval(&p, kappa, fz, vx, &o);
        check("brush", s, &o, nmut == 0, fin, fzd, 200.0, 10000.0, 1.1, 0.2);
    } else if (model == 2) {
        grip_sakai_params p;
        p.k = QL(57200.0); p.g_y = QL(250000.0); p.mu_s = QS(1.0); p.mu_d = QS(0.8); p.l = QS(0.18);
        p.fz_min = QL(200.0); p.fz_max = QL(10000.0); p.alpha_max = QS(0.6); p.kappa_max = QS(1.0);
        nmut = fz_mutate(&r, &p, f_sakai, NF(f_sakai), 6);
        s = grip_sakai_check_params(&p);
        FZ_CHECK(s == GRIP_OK || s == GRIP_ERR_PARAM, "check %d", (int)s);
        s = grip_sakai_eval(&p, kappa, alpha, fz, &o);
        check("sakai", s, &o, nmut == 0, fin, fzd, 200.0, 10000.0, 1.0, 0.18);
    } else {
        grip_neofiala_params p;
        grip_neofiala_model m;
        grip_brush_out o2;
        grip_status_t s2;
        memset(&p, 0, sizeof p);
        p.l = QS(0.16); p.w = QS(0.19); p.kx = QL(95000.0); p.ky = QL(72000.0); p.mu_s = QS(1.15);
        p.mu_d0 = QS(0.95); p.a_v = QS(0.003); p.n = 4; p.q0 = QS(0.05); p.c_q = QS(0.01);
        p.c_xc = QS(0.002); p.eps = QS(0.02); p.g_mz = QL(15000.0); p.a_x = QL(2.0); p.c_gamma = QS(0.15);
        p.h = QS(0.02); p.g_my = QL(200000.0); p.fz_min = QL(500.0); p.fz_max = QL(10000.0);
        p.alpha_max = QS(0.6); p.kappa_max = QS(1.0); p.gamma_max = QS(0.2); p.v_max = QS(60.0);
        nmut = fz_mutate(&r, &p, f_neo, NF(f_neo), 6);
        s = grip_neofiala_check_params(&p);
        FZ_CHECK(s == GRIP_OK || s == GRIP_ERR_PARAM, "check %d", (int)s);
        s = grip_neofiala_eval(&p, kappa, alpha, gamma, fz, vx, &o);
        check("neofiala", s, &o, nmut == 0, fin, fzd, 500.0, 10000.0, 1.15, 0.16);
        s2 = grip_neofiala_prepare(&p, &m);
        FZ_CHECK(s2 == GRIP_OK || s2 == GRIP_ERR_PARAM, "prepare %d", (int)s2);
        memset(&o2, 0x5A, sizeof o2);
        s2 = grip_neofiala_eval_model(&m, kappa, alpha, gamma, fz, vx, &o2);
        if (s2 == GRIP_ERR_STATE) {
            FZ_CHECK(s == GRIP_ERR_PARAM, "eval_model says unprepared, eval says %d", (int)s);
        } else {
            FZ_CHECK(s2 == s && memcmp(&o, &o2, sizeof o) == 0, "eval (%d) and eval_model (%d) differ", (int)s,
                     (int)s2);
        }
    }
    return 0;
}
