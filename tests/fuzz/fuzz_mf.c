/*
 * fuzz_mf.c - grip_mf_eval / grip_mf_eval_pure / grip_mf_eval_ext on hostile
 * inputs, with the use modes (turn slip, no limits) per set and per call.
 *
 * Parameter sets: every shared .tir file (tests/data/chrono-tir,
 * tests/data/mfeval-tir), read once at start-up with the host .tir reader.
 * Input: [set][options][kappa alpha gamma fz p vx phit omega as words]
 * [flags][request word][mutations: (coefficient index, word)...]. The
 * options byte selects option bits 0-5, the tyre side and turn slip; the
 * flags byte no limits, the turn slip's camber form, an invalid option bit
 * and whether the request word of grip_mf_eval_ext is taken raw (any bits)
 * or limited to the channel and use-mode bits.
 *
 * Properties: no crash or sanitizer report; the status is a documented one;
 * outputs finite; on an error status the outputs are zero (and no channel
 * valid); a valid channel was requested; with an unmutated set: status OK
 * or WARN_CLAMPED for finite inputs (ERR_INPUT for non-finite ones or a
 * request with both bits of a use-mode pair; ERR_PARAM for turn slip on a
 * set without its coefficients, and from grip_mf_eval / _pure for a set
 * with GRIP_MF_OPT_TURN_SLIP or _NO_LIMITS), Fz <= 0 gives zero forces, and
 *   |Fx|, |Fy| <= 5 Fz' + 1 N,  |Mz| <= 5 Fz' R0 + 1 N m,
 * with Fz' = min(Fz, 4 FNOMIN) (the clamped load), turn slip included;
 * in mode 111 grip_mf_eval_ext's forces equal grip_mf_eval's bit for bit. A mutated set must be rejected by grip_mf_check_params or give
 * finite outputs (no bound: coefficients can be absurd but finite).
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
                      int finite_in, const grip_mf_params *p, const grip_mf_input *in, grip_status_t expect_err)
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
            FZ_CHECK(s == GRIP_ERR_INPUT || s == expect_err, "%s non-finite input gave status %d", what, (int)s);
            return;
        }
        if (expect_err != GRIP_OK) {
            FZ_CHECK(s == expect_err, "%s status %d, expected %d", what, (int)s, (int)expect_err);
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

/* The set has its turn-slip coefficients (mf_check.c's rule). */
static int ts_usable(const grip_mf_params *p)
{
    return fz_d(p->phyp1, FZ_QS) > 0.0 && fz_d(p->qdrp1, FZ_QS) > 0.0 && fz_d(p->qdrp1, FZ_QS) < 2.0;
}

static void check_ext(grip_status_t s, const grip_mf_output_ext *e, uint32_t req, int pristine, int finite_in,
                      const grip_mf_params *p, const grip_mf_input *in, int same_as_plain, grip_status_t expect_err,
                      grip_status_t s_plain, const grip_mf_output *plain)
{
    grip_mf_output f;
    const grip_real_t *v = &e->fx;
    size_t k;
    FZ_CHECK(fz_status_known(s), "ext status %d", (int)s);
    for (k = 0; k < sizeof *e / sizeof(grip_real_t) - 1u; k++) {
        FZ_CHECK(fz_finite(v[k]), "ext output %u not finite", (unsigned)k);
    }
    if (s < 0) {
        for (k = 0; k < sizeof *e / sizeof(grip_real_t) - 1u; k++) {
            FZ_CHECK(v[k] == 0, "ext error %d with non-zero output %u", (int)s, (unsigned)k);
        }
        FZ_CHECK(e->valid == 0u, "ext error %d with valid channels", (int)s);
    }
    FZ_CHECK((e->valid & ~(req & GRIP_MF_EXT_ALL)) == 0u, "ext valid channel not requested");
    f.fx = e->fx;
    f.fy = e->fy;
    f.mz = e->mz;
    check_out("ext", s, &f, pristine, finite_in, p, in, expect_err);
    if (pristine && same_as_plain && s >= 0 && s_plain >= 0) {
        FZ_CHECK(plain->fx == e->fx && plain->fy == e->fy && plain->mz == e->mz,
                 "ext without turn slip differs from grip_mf_eval");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_reader r = { data, size };
    grip_mf_params p;
    grip_mf_input in;
    grip_mf_spin sp;
    const grip_mf_spin *spp;
    grip_mf_output o1;
    grip_mf_output o2;
    grip_mf_output_ext oe;
    grip_status_t s1;
    grip_status_t s2;
    grip_status_t s3;
    grip_status_t want_plain = GRIP_OK;
    grip_status_t want_ext = GRIP_OK;
    uint8_t opt;
    uint8_t flags;
    uint32_t req;
    uint32_t mode;
    int nmut;
    int finite_in;
    int pristine;
    int ts;

    p = sets[fz_u8(&r) % (uint8_t)nsets];
    opt = fz_u8(&r);
    p.options = (uint32_t)(opt & 0x3Fu) | ((opt & 0x80u) ? GRIP_MF_OPT_TURN_SLIP : 0u);
    if (opt & 0x40u) {
        p.tyreside = -p.tyreside;
    }
    memset(&in, 0, sizeof in);
    in.kappa = fz_real(&r, FZ_QS);
    in.alpha = fz_real(&r, FZ_QS);
    in.gamma = fz_real(&r, FZ_QS);
    in.fz = fz_real(&r, FZ_QL);
    in.p = fz_real(&r, FZ_QL);
    in.vx = fz_real(&r, FZ_QS);
    sp.phit = fz_real(&r, FZ_QS);
    sp.omega = fz_real(&r, FZ_QS);
    flags = fz_u8(&r);
    /* flag 16: grip_mf_eval_ext, without the spin (phit, omega 0) */
    spp = ((flags & 16u) != 0u) ? NULL : &sp;
    if (spp == NULL) {
        sp.phit = 0;
        sp.omega = 0;
    }
    req = fz_u32(&r);
    p.options |= ((flags & 1u) ? GRIP_MF_OPT_NO_LIMITS : 0u) | ((flags & 2u) ? GRIP_MF_OPT_TS_CAMBER : 0u) |
                 ((flags & 4u) ? (1u << 9) : 0u);
    if ((flags & 8u) == 0u) {
        req &= GRIP_MF_EXT_ALL | GRIP_MF_USE_ALL;
    }
    finite_in = fz_finite(in.kappa) && fz_finite(in.alpha) && fz_finite(in.gamma) && fz_finite(in.fz) &&
                fz_finite(in.p) && fz_finite(in.vx);
    nmut = fz_mutate(&r, &p, fields, nfields, 8);
    pristine = (nmut == 0) && ((p.options & ~GRIP_MF_OPT_ALL) == 0u);
    /* the evaluation's use modes (mf_internal.h's mf_mode_use) */
    mode = p.options;
    mode = (req & GRIP_MF_USE_TURN_SLIP) ? (mode | GRIP_MF_OPT_TURN_SLIP) : mode;
    mode = (req & GRIP_MF_USE_NO_TURN_SLIP) ? (mode & ~GRIP_MF_OPT_TURN_SLIP) : mode;
    mode = (req & GRIP_MF_USE_NO_LIMITS) ? (mode | GRIP_MF_OPT_NO_LIMITS) : mode;
    mode = (req & GRIP_MF_USE_LIMITS) ? (mode & ~GRIP_MF_OPT_NO_LIMITS) : mode;
    ts = (mode & GRIP_MF_OPT_TURN_SLIP) != 0u;
    if (pristine) {
        grip_status_t sc = grip_mf_check_params(&p);
        if ((p.options & GRIP_MF_OPT_TURN_SLIP) != 0u && !ts_usable(&p)) {
            FZ_CHECK(sc == GRIP_ERR_PARAM, "set asking for turn slip without its coefficients accepted");
        } else {
            FZ_CHECK(sc == GRIP_OK, "unmutated set rejected");
        }
        /* grip_mf_eval / _pure refuse a set that asks for turn slip */
        want_plain = ((p.options & (GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS)) != 0u) ? GRIP_ERR_PARAM : GRIP_OK;
        if (((req & ~(GRIP_MF_EXT_ALL | GRIP_MF_USE_ALL)) != 0u) ||
            ((req & (GRIP_MF_USE_TURN_SLIP | GRIP_MF_USE_NO_TURN_SLIP)) ==
             (GRIP_MF_USE_TURN_SLIP | GRIP_MF_USE_NO_TURN_SLIP)) ||
            ((req & (GRIP_MF_USE_LIMITS | GRIP_MF_USE_NO_LIMITS)) == (GRIP_MF_USE_LIMITS | GRIP_MF_USE_NO_LIMITS))) {
            want_ext = GRIP_ERR_INPUT;
        } else if (!fz_finite(sp.omega) || (ts && !fz_finite(sp.phit))) {
            want_ext = GRIP_ERR_INPUT;
        } else if (ts && !ts_usable(&p)) {
            want_ext = GRIP_ERR_PARAM;
        } else {
            /* documented: OK or WARN_CLAMPED (or ERR_INPUT, non-finite) */
        }
    } else {
        grip_status_t sc = grip_mf_check_params(&p);
        FZ_CHECK(sc == GRIP_OK || sc == GRIP_ERR_PARAM, "check_params status %d", (int)sc);
    }
    memset(&o1, 0x5A, sizeof o1);
    memset(&o2, 0x5A, sizeof o2);
    memset(&oe, 0x5A, sizeof oe);
    s1 = grip_mf_eval_pure(&p, &in, &o1);
    s2 = grip_mf_eval(&p, &in, &o2);
    s3 = (spp == NULL) ? grip_mf_eval_ext(&p, &in, req, &oe) : grip_mf_eval_ext_spin(&p, &in, spp, req, &oe);
    check_out("pure", s1, &o1, pristine, finite_in, &p, &in, want_plain);
    check_out("combined", s2, &o2, pristine, finite_in, &p, &in, want_plain);
    /* in mode 111 grip_mf_eval_ext's forces are grip_mf_eval's */
    check_ext(s3, &oe, req, pristine, finite_in && (want_ext != GRIP_ERR_INPUT), &p, &in,
              ((mode | p.options) & (GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS)) == 0u, want_ext, s2, &o2);
    /* the prepared set (grip_mf_prepare with the set's own options): the
     * same bits and status as the unprepared evaluations when it
     * prepares; refused (GRIP_ERR_PARAM, zero outputs) when it does not */
    {
        grip_mf_prepared prep;
        grip_mf_output op1;
        grip_mf_output op2;
        grip_status_t sp = grip_mf_prepare(&p, p.options, &prep);
        grip_status_t sp1 = grip_mf_eval_pure_prepared(&prep, &in, &op1);
        grip_status_t sp2 = grip_mf_eval_prepared(&prep, &in, &op2);
        FZ_CHECK(sp == GRIP_OK || sp == GRIP_ERR_PARAM, "prepare status %d", (int)sp);
        if (sp == GRIP_OK) {
            FZ_CHECK(sp1 == s1 && memcmp(&op1, &o1, sizeof op1) == 0, "prepared pure differs (%d vs %d)", (int)sp1,
                     (int)s1);
            FZ_CHECK(sp2 == s2 && memcmp(&op2, &o2, sizeof op2) == 0, "prepared combined differs (%d vs %d)",
                     (int)sp2, (int)s2);
        } else {
            FZ_CHECK(sp1 == GRIP_ERR_PARAM && sp2 == GRIP_ERR_PARAM, "unprepared set evaluated (%d, %d)", (int)sp1,
                     (int)sp2);
            FZ_CHECK(op2.fx == 0 && op2.fy == 0 && op2.mz == 0, "unprepared set: non-zero outputs");
            /* grip_mf_check_params refuses what grip_mf_prepare refuses,
             * unless the set asks for a use mode (prepare refuses those) */
            FZ_CHECK(grip_mf_check_params(&p) != GRIP_OK ||
                         (p.options & (GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS)) != 0u,
                     "prepare refused a set grip_mf_check_params accepts");
        }
    }
    /* NULL arguments */
    FZ_CHECK(grip_mf_eval(NULL, &in, &o1) == GRIP_ERR_NULL, "NULL params");
    FZ_CHECK(grip_mf_eval(&p, NULL, &o1) == GRIP_ERR_NULL, "NULL input");
    return 0;
}
