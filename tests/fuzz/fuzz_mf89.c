/*
 * fuzz_mf89.c - grip_mf89_fy / _check_params / _check_constraints.
 *
 * Base set: the golden-vector set of tools/grip_tools/golden/mf89.py.
 * Input: [alpha fz gamma as words][fz_lo fz_hi words][mutations...].
 * Properties: no crash or sanitizer report; documented statuses; finite
 * output; zero output on error; with the unmutated set and finite inputs:
 * OK or WARN_CLAMPED and |Fy| <= 3 Fz' + 1 N (Fz' the load clamped to
 * [0, fz_max]), Fy = 0 at Fz <= 0.
 */
#include "fuzz_common.h"
#include "grip/grip_mf89.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const double base_a[GRIP_MF89_NCOEF] = { 1.45, -30.0, 1200.0, 1400.0, 7.0, 0.01, -0.05, -0.2, 0.0,
                                                0.0, 0.006, 0.0, 0.0, -0.5, 18.0, 0.0015, 0.02, 0.0 };

static const fz_field fields[] = {
    { offsetof(grip_mf89_params, a) + 0 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 1 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 2 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 3 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 4 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 5 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 6 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 7 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 8 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 9 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 10 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 11 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 12 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 13 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 14 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 15 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 16 * sizeof(grip_real_t), FZ_QS },
    { offsetof(grip_mf89_params, a) + 17 * sizeof(grip_real_t), FZ_QS },
    FZ_F(grip_mf89_params, fz_max, FZ_QL),
    FZ_F(grip_mf89_params, alpha_max, FZ_QS),
    FZ_F(grip_mf89_params, gamma_max, FZ_QS),
};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r = { data, size };
    grip_mf89_params p;
    grip_real_t alpha;
    grip_real_t fz;
    grip_real_t gamma;
    grip_real_t lo;
    grip_real_t hi;
    grip_real_t fy = 1;
    grip_status_t s;
    uint32_t viol = 0;
    int i;
    int nmut;
    for (i = 0; i < GRIP_MF89_NCOEF; i++) {
        p.a[i] = fz_from_d(base_a[i], FZ_QS);
    }
    p.fz_max = fz_from_d(10000.0, FZ_QL);
    p.alpha_max = fz_from_d(0.4363250732421875, FZ_QS);
    p.gamma_max = fz_from_d(0.1396331787109375, FZ_QS);
    alpha = fz_real(&r, FZ_QS);
    fz = fz_real(&r, FZ_QL);
    gamma = fz_real(&r, FZ_QS);
    lo = fz_real(&r, FZ_QL);
    hi = fz_real(&r, FZ_QL);
    nmut = fz_mutate(&r, &p, fields, sizeof fields / sizeof fields[0], 8);
    s = grip_mf89_check_params(&p);
    FZ_CHECK(s == GRIP_OK || s == GRIP_ERR_PARAM, "check_params %d", (int)s);
    if (nmut == 0) {
        FZ_CHECK(s == GRIP_OK, "base set rejected");
    }
    s = grip_mf89_fy(&p, alpha, fz, gamma, &fy);
    FZ_CHECK(fz_status_known(s), "fy status %d", (int)s);
    FZ_CHECK(fz_finite(fy), "non-finite fy");
    if (s < 0) {
        FZ_CHECK(fy == 0, "error with output");
    }
    if (nmut == 0 && fz_finite(alpha) && fz_finite(fz) && fz_finite(gamma)) {
        double f = fz_d(fz, FZ_QL);
        double fc = f < 0.0 ? 0.0 : (f > 10000.0 ? 10000.0 : f);
        FZ_CHECK(s == GRIP_OK || s == GRIP_WARN_CLAMPED, "valid call status %d", (int)s);
        FZ_CHECK(fabs(fz_d(fy, FZ_QL)) <= 3.0 * fc + 1.0, "|Fy| %g > 3 Fz (%g)", fz_d(fy, FZ_QL), fc);
    }
    s = grip_mf89_check_constraints(&p, lo, hi, &viol);
    FZ_CHECK(s == GRIP_OK || s == GRIP_ERR_PARAM || s == GRIP_ERR_INPUT, "constraints status %d", (int)s);
    FZ_CHECK((viol & ~0x7Fu) == 0u, "unknown constraint bits %x", viol);
    return 0;
}
