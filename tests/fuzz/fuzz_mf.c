/*
 * fuzz_mf.c - grip_mf_eval / grip_mf_eval_pure on hostile inputs.
 *
 * Parameter sets: every shared .tir file (tests/data/chrono-tir,
 * tests/data/mfeval-tir), read once at start-up with the host .tir reader.
 * Input: [set][options][kappa alpha gamma fz p vx as words][mutations:
 * (coefficient index, word)...]. The options byte selects option bits (also
 * invalid ones) and the tyre side.
 *
 * Properties: no crash or sanitizer report; the status is a documented one;
 * outputs finite; on an error status the outputs are zero; with an
 * unmutated set: status OK or WARN_CLAMPED for finite inputs (ERR_INPUT for
 * non-finite ones), Fz <= 0 gives zero outputs, and
 *   |Fx|, |Fy| <= 5 Fz' + 1 N,  |Mz| <= 5 Fz' R0 + 1 N m,
 * with Fz' = min(Fz, 4 FNOMIN) (the clamped load).
 * A mutated set must be rejected by grip_mf_check_params or give finite
 * outputs (no bound: coefficients can be absurd but finite).
 */
#include <glob.h>
#include "fuzz_common.h"
#include "grip/grip_mf.h"
#include "tir_reader.h"

#define MAX_SETS 32
static grip_mf_params sets[MAX_SETS];
static int nsets;
static fz_field fields[GRIP_TIR_NCOEF + 2];
static size_t nfields;

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    static const char *const pats[] = { "tests/data/chrono-tir/*.tir", "tests/data/mfeval-tir/*.tir" };
    size_t k;
    int i;
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
                grip_mf_check_params(&sets[nsets]) == GRIP_OK) {
                nsets++;
            }
        }
        globfree(&g);
    }
    if (nsets == 0) {
        fprintf(stderr, "fuzz_mf: no .tir parameter set found (run from the repository root)\n");
        exit(2);
    }
    /* coefficient i sits after the three header words */
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        fields[nfields].off = offsetof(grip_mf_params, options) + sizeof(uint32_t) + (size_t)i * sizeof(grip_real_t);
        fields[nfields].is_ql = grip_tir_coef_is_ql(i) ? FZ_QL : FZ_QS;
        nfields++;
    }
    fields[nfields].off = offsetof(grip_mf_params, fittyp);
    fields[nfields++].is_ql = 2;
    fields[nfields].off = offsetof(grip_mf_params, tyreside);
    fields[nfields++].is_ql = 2;
    return 0;
}

static void check_out(const char *what, grip_status_t s, const grip_mf_output *o, int pristine,
                      int finite_in, const grip_mf_params *p, const grip_mf_input *in)
{
    FZ_CHECK(fz_status_known(s), "%s status %d", what, (int)s);
    FZ_CHECK(fz_finite(o->fx) && fz_finite(o->fy) && fz_finite(o->mz), "%s non-finite output", what);
    if (s < 0) {
        FZ_CHECK(o->fx == 0 && o->fy == 0 && o->mz == 0, "%s error %d with non-zero output", what, (int)s);
    }
    if (pristine) {
        /* SAE J670: a loaded tyre has Fz < 0 */
        double fz = ((p->options & GRIP_MF_OPT_SAE) ? -1.0 : 1.0) * fz_d(in->fz, FZ_QL);
        double fnomin = fz_d(p->fnomin, FZ_QL);
        double r0 = fz_d(p->unloaded_radius, FZ_QS);
        double fzc;
        if (!finite_in) {
            FZ_CHECK(s == GRIP_ERR_INPUT, "%s non-finite input gave status %d", what, (int)s);
            return;
        }
        FZ_CHECK(s == GRIP_OK || s == GRIP_WARN_CLAMPED, "%s valid set, finite input: status %d", what, (int)s);
        if (!(fz > 0.0)) {
            FZ_CHECK(o->fx == 0 && o->fy == 0 && o->mz == 0, "%s Fz <= 0 with non-zero output", what);
            return;
        }
        fzc = fz < 4.0 * fnomin ? fz : 4.0 * fnomin;
        FZ_CHECK(fabs(fz_d(o->fx, FZ_QL)) <= 5.0 * fzc + 1.0, "%s |Fx| %g > 5 Fz (Fz %g)", what,
                 fz_d(o->fx, FZ_QL), fzc);
        FZ_CHECK(fabs(fz_d(o->fy, FZ_QL)) <= 5.0 * fzc + 1.0, "%s |Fy| %g > 5 Fz (Fz %g)", what,
                 fz_d(o->fy, FZ_QL), fzc);
        FZ_CHECK(fabs(fz_d(o->mz, FZ_QL)) <= 5.0 * fzc * r0 + 1.0, "%s |Mz| %g > 5 Fz R0 (Fz %g)", what,
                 fz_d(o->mz, FZ_QL), fzc);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r = { data, size };
    grip_mf_params p;
    grip_mf_input in;
    grip_mf_output o1;
    grip_mf_output o2;
    grip_status_t s1;
    grip_status_t s2;
    uint8_t opt;
    int nmut;
    int finite_in;
    int pristine;

    p = sets[fz_u8(&r) % (uint8_t)nsets];
    opt = fz_u8(&r);
    p.options = (opt & 0x80u) ? (uint32_t)(opt & 0x7Fu) : (uint32_t)(opt & GRIP_MF_OPT_ALL);
    if (opt & 0x40u) {
        p.tyreside = -p.tyreside;
    }
    in.kappa = fz_real(&r, FZ_QS);
    in.alpha = fz_real(&r, FZ_QS);
    in.gamma = fz_real(&r, FZ_QS);
    in.fz = fz_real(&r, FZ_QL);
    in.p = fz_real(&r, FZ_QL);
    in.vx = fz_real(&r, FZ_QS);
    finite_in = fz_finite(in.kappa) && fz_finite(in.alpha) && fz_finite(in.gamma) && fz_finite(in.fz) &&
                fz_finite(in.p) && fz_finite(in.vx);
    nmut = fz_mutate(&r, &p, fields, nfields, 8);
    pristine = (nmut == 0) && ((p.options & ~GRIP_MF_OPT_ALL) == 0u);
    if (pristine) {
        FZ_CHECK(grip_mf_check_params(&p) == GRIP_OK, "unmutated set rejected");
    } else {
        grip_status_t sc = grip_mf_check_params(&p);
        FZ_CHECK(sc == GRIP_OK || sc == GRIP_ERR_PARAM, "check_params status %d", (int)sc);
    }
    memset(&o1, 0x5A, sizeof o1);
    memset(&o2, 0x5A, sizeof o2);
    s1 = grip_mf_eval_pure(&p, &in, &o1);
    s2 = grip_mf_eval(&p, &in, &o2);
    check_out("pure", s1, &o1, pristine, finite_in, &p, &in);
    check_out("combined", s2, &o2, pristine, finite_in, &p, &in);
    /* NULL arguments */
    FZ_CHECK(grip_mf_eval(NULL, &in, &o1) == GRIP_ERR_NULL, "NULL params");
    FZ_CHECK(grip_mf_eval(&p, NULL, &o1) == GRIP_ERR_NULL, "NULL input");
    return 0;
}
