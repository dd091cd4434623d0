/*
 * onboard_driver.c - the onboard form of the analyze tool's updated tyre
 * models, for tests/python/loop/test_onboard.py. Built by that test against
 * build/<variant>/libgrip.a and libgrip_port.a (float or fixed); not part of
 * the library.
 *
 *   onboard_driver mf      TIR                 < rows > out
 *   onboard_driver mfgp    TIR                 < rows7 > out
 *   onboard_driver relax   TIR SIGMA           < rows > out
 *   onboard_driver thermal TIR THERMAL A B     < rows > out
 *
 * rows: "t kappa alpha fz vx" per line (SI, ISO-W), no header; rows7 (mfgp):
 *       "t kappa alpha fz vx gamma p" (gamma rad, p Pa).
 * out:  "fx fy status" per line (relax: then kappa' alpha').
 *
 * mf:      grip_mf_eval with the parameter set of TIR (e.g. the updated LMUV),
 *          gamma = 0 and p = 0 (INFLPRES or NOMPRES).
 * mfgp:    the same with the rows' camber and inflation pressure (the updated
 *          PKY6/PVY3 or PPX1/PPY1/PPX3/PPY3).
 * relax:   grip_relax (sigma_kappa = sigma_alpha = SIGMA, v_min 0.5 m/s), its
 *          kappa', alpha' fed into grip_mf_eval. Row i > 0 steps from t[i-1]
 *          to t[i] with the inputs and the speed of row i, the output of the
 *          step feeding row i's forces (the tool's grammar.relax_series:
 *          sigma -> 0 is the base model).
 * thermal: grip_mf_thermal state (parameters from THERMAL: "name value" lines
 *          in the order of grip_mf_thermal_params, SI) driven by V = vx /
 *          cos(alpha), alpha_seed = -alpha, S = -kappa, T_R = t0; the forces
 *          come from grip_mf_eval with LMUX, LMUY scaled by 1 + A (T - t0) and
 *          LKX, LKY by 1 + B (T - t0) at the temperature at the start of the
 *          step, then the state steps to the next row's time.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grip/grip_mf.h"
#include "grip/grip_mf_thermal.h"
#include "grip/grip_relax.h"
#include "tir_reader.h"

#if GRIP_ARITH_FIXED
#define QS(x) ((grip_real_t)lround((x) * 65536.0))
#define QL(x) ((grip_real_t)lround((x) * 256.0))
#define FROM_QS(v) ((double)(v) / 65536.0)
#define FROM_QL(v) ((double)(v) / 256.0)
#else
#define QS(x) ((grip_real_t)(x))
#define QL(x) ((grip_real_t)(x))
#define FROM_QS(v) ((double)(v))
#define FROM_QL(v) ((double)(v))
#endif

#define MAX_ROWS 20000

static double rows[MAX_ROWS][7];

static int read_rows(int ncol)
{
    int n = 0, j;
    for (n = 0; n < MAX_ROWS; n++) {
        for (j = 0; j < ncol; j++) {
            if (scanf("%lf", &rows[n][j]) != 1) {
                return n;
            }
        }
    }
    return n;
}

static grip_status_t mf_gp(const grip_mf_params *p, double kappa, double alpha, double fz, double vx,
                           double gamma, double pr, double *fx, double *fy)
{
    grip_mf_input in;
    grip_mf_output out;
    grip_status_t st;
    memset(&in, 0, sizeof in);
    in.kappa = QS(kappa);
    in.alpha = QS(alpha);
    in.gamma = QS(gamma);
    in.fz = QL(fz);
    in.p = QL(pr);
    in.vx = QS(vx);
    st = grip_mf_eval(p, &in, &out);
    *fx = FROM_QL(out.fx);
    *fy = FROM_QL(out.fy);
    return st;
}

static grip_status_t mf_at(const grip_mf_params *p, double kappa, double alpha, double fz, double vx,
                           double *fx, double *fy)
{
    return mf_gp(p, kappa, alpha, fz, vx, 0.0, 0.0, fx, fy);
}

static int load_thermal(const char *path, grip_mf_thermal_params *tp)
{
    static const struct { const char *name; size_t off; int ql; } F[] = {
#define TF(n, ql) { #n, offsetof(grip_mf_thermal_params, n), ql }
        TF(fz0, 1), TF(t0, 0), TF(dx0, 1), TF(kx0, 1), TF(cx, 0), TF(ex, 0), TF(shx, 0), TF(svx, 1),
        TF(ax, 0), TF(bx, 0), TF(dy0, 1), TF(ky0, 1), TF(cy, 0), TF(ey, 0), TF(shy, 0), TF(svy, 1),
        TF(ay, 0), TF(by, 0), TF(bxa, 0), TF(cxa, 0), TF(exa, 0), TF(shxa, 0), TF(bys, 0), TF(cys, 0),
        TF(eys, 0), TF(shys, 0), TF(svys, 1), TF(w, 1), TF(kappa, 0), TF(fz_max, 1), TF(alpha_max, 0),
        TF(slip_max, 0), TF(v_max, 0), TF(t_min, 0), TF(t_max, 0),
#undef TF
    };
    char name[64];
    double v;
    size_t i, found = 0;
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        return -1;
    }
    memset(tp, 0, sizeof *tp);
    while (fscanf(f, "%63s %lf", name, &v) == 2) {
        for (i = 0; i < sizeof F / sizeof F[0]; i++) {
            if (strcmp(name, F[i].name) == 0) {
                *(grip_real_t *)((char *)tp + F[i].off) = F[i].ql ? QL(v) : QS(v);
                found++;
            }
        }
    }
    fclose(f);
    return found == sizeof F / sizeof F[0] ? 0 : -1;
}

int main(int argc, char **argv)
{
    grip_mf_params p;
    char err[256];
    int n, i;
    double fx, fy;
    grip_status_t st;
    if (argc < 3) {
        fprintf(stderr, "usage: %s mf|mfgp|relax|thermal TIR [args]\n", argv[0]);
        return 2;
    }
    if (grip_tir_read(argv[2], &p, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return 3;
    }
    n = read_rows(strcmp(argv[1], "mfgp") == 0 ? 7 : 5);
    if (strcmp(argv[1], "mfgp") == 0) {
        for (i = 0; i < n; i++) {
            st = mf_gp(&p, rows[i][1], rows[i][2], rows[i][3], rows[i][4], rows[i][5], rows[i][6], &fx, &fy);
            printf("%.9g %.9g %d\n", fx, fy, (int)st);
        }
    } else if (strcmp(argv[1], "mf") == 0) {
        for (i = 0; i < n; i++) {
            st = mf_at(&p, rows[i][1], rows[i][2], rows[i][3], rows[i][4], &fx, &fy);
            printf("%.9g %.9g %d\n", fx, fy, (int)st);
        }
    } else if (strcmp(argv[1], "relax") == 0 && argc == 4) {
        grip_relax_params rp;
        grip_relax_state rs;
        grip_real_t kt, at;
        double sigma = atof(argv[3]);
        rp.sigma_kappa = QS(sigma);
        rp.sigma_alpha = QS(sigma);
        rp.v_min = QS(0.5);
        rp.v_max = QS(100.0);
        rp.kappa_max = QS(1.0);
        rp.alpha_max = QS(0.5);
        if (grip_relax_init(&rs, &rp, QS(rows[0][1]), QS(rows[0][2])) < 0) {
            fprintf(stderr, "grip_relax_init failed\n");
            return 4;
        }
        kt = rs.kappa_t;
        at = rs.alpha_t;
        for (i = 0; i < n; i++) {
            grip_status_t sr = GRIP_OK;
            if (i > 0) {
                sr = grip_relax_step(&rs, QS(rows[i][1]), QS(rows[i][2]), QS(rows[i][4]),
                                     QS(rows[i][0] - rows[i - 1][0]), &kt, &at);
            }
            st = mf_at(&p, FROM_QS(kt), FROM_QS(at), rows[i][3], rows[i][4], &fx, &fy);
            printf("%.9g %.9g %d %.9g %.9g\n", fx, fy, (int)(sr < 0 ? sr : st), FROM_QS(kt), FROM_QS(at));
        }
    } else if (strcmp(argv[1], "thermal") == 0 && argc == 6) {
        grip_mf_thermal_params tp;
        grip_mf_thermal_state ts;
        grip_mf_thermal_inputs tin;
        grip_mf_thermal_output tout;
        grip_mf_params ps = p;
        double a = atof(argv[4]), b = atof(argv[5]);
        double lmux = FROM_QS(p.lmux), lmuy = FROM_QS(p.lmuy), lkx = FROM_QS(p.lkx), lky = FROM_QS(p.lky);
        if (load_thermal(argv[3], &tp) != 0) {
            fprintf(stderr, "%s: incomplete thermal parameter file\n", argv[3]);
            return 3;
        }
        if (grip_mf_thermal_init(&ts, &tp, tp.t0) < 0) {
            fprintf(stderr, "grip_mf_thermal_init rejected the parameters\n");
            return 4;
        }
        for (i = 0; i < n; i++) {
            double dT = FROM_QS(ts.t) - FROM_QS(tp.t0);
            double fd = 1.0 + a * dT, fk = 1.0 + b * dT;
            grip_status_t sth = GRIP_OK;
            if (fd < 0.05) fd = 0.05;
            if (fk < 0.05) fk = 0.05;
            ps.lmux = QS(lmux * fd);
            ps.lmuy = QS(lmuy * fd);
            ps.lkx = QS(lkx * fk);
            ps.lky = QS(lky * fk);
            st = mf_at(&ps, rows[i][1], rows[i][2], rows[i][3], rows[i][4], &fx, &fy);
            if (i + 1 < n) {
                tin.v = QS(rows[i][4] / cos(rows[i][2]));
                tin.alpha = QS(-rows[i][2]);
                tin.slip = QS(-rows[i][1]);
                tin.fz = QL(rows[i][3]);
                tin.t_road = tp.t0;
                sth = grip_mf_thermal_step(&ts, &tin, QS(rows[i + 1][0] - rows[i][0]), &tout);
            }
            printf("%.9g %.9g %d\n", fx, fy, (int)(sth < 0 ? sth : st));
        }
    } else {
        fprintf(stderr, "unknown mode or wrong argument count\n");
        return 2;
    }
    return 0;
}
