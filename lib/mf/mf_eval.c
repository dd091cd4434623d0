/*
 * mf_eval.c - steady-state Magic Formula (MF 5.2 / PAC2002, MF 6.1 / 6.2):
 * pure and combined slip Fx, Fy, Mz, written once for both arithmetics.
 *
 * Default equation forms are those of TNO's MF-Tyre (ISO-W axis system,
 * slip angle and inclination used as angles, A_mu = 1, the trail and
 * residual-moment forms of MF-Tyre 6.1); GRIP_MF_OPT_BOOK selects the forms
 * of Pacejka's book (alpha* = tan(alpha), gamma* = sin(gamma), ...).
 * The equations are in docs/magic-formula.md, what is specific to this C
 * code in docs/magic-formula-c.md; equation numbers below are the book's
 * (Tyre and Vehicle Dynamics, 3rd ed., section 4.3.2, "4.Exx").
 *
 * Everything is computed per unit load (mf_internal.h); the result is
 * scaled by Fz and Fz * R0 to N and N m at the very end. Pure functions:
 * no state, no loops.
 *
 * The use modes (MFeval's useMode: no limits, 2xx; turn slip, xx2, with
 * the zeta factors of Pacejka 4.3.3, "4.77" ... below, in the forms of
 * MFeval's Solver) are evaluated for grip_mf_eval_ext only (mf_eval_core_use).
 * The blocks the evaluations share are written once, as always-inline
 * bodies with a constant `ext` and a turn-slip context `ts`, and compiled
 * twice: the plain variants (ext = 0, ts = NULL, called by grip_mf_eval
 * and grip_mf_eval_pure) fold to the model without the use modes - the
 * same code, cost and stack as before they existed - and the _x variants
 * carry them. Those blocks, the equations of the model, are in
 * mf_equations.h, which the lane evaluation (mf_lanes.c) is built from as
 * well; this file calls them with the scalar kernels (mk NULL) and holds
 * the rest: the input checks, clamps and statuses, the order of the
 * blocks, the use modes, and the functions whose frames the stack budget
 * counts.
 */
#include "mf_equations.h"



/* |R0 phi| beyond this is limited: (PKYP1 R0^2 phi^2 stays in QS); reached
 * only by spins beyond the input domain (|phit| <= 100 1/m with R0 < 1.5 m). */
#define MF_TS_U_MAX RC(150.0)

/* The plain (grip_mf_eval, grip_mf_eval_pure) and extended (mf_eval_core_use)
 * variants of the blocks of mf_equations.h, with the scalar kernels (mk
 * NULL): separate functions with frames of their own, as the blocks were
 * before the use modes (the _x ones kept out of line: GCC inlined some into
 * the extended evaluation, whose frame then outgrew the stack budget). */
static void mf_lat_pure(const grip_mf_params *p, const mf_op *op, const mf_lat_common *c, grip_real_t g,
                        mf_lat *out)
{
    mf_lat_body(p, op, c, g, NULL, R_ONE, NULL, 0, out);
}

/* Fy0 at gamma = 0 (MF 6.x's Mz): mf_lat_pure with the inclination a
 * constant, so that its products by gamma and gamma^2 fold away (the same
 * function at the same arguments: the same bits) */
static void mf_lat_pure_g0(const grip_mf_params *p, const mf_op *op, const mf_lat_common *c, mf_lat *out)
{
    mf_lat_body(p, op, c, R_ZERO, NULL, R_ONE, NULL, 0, out);
}

/* A prepared set whose coefficient terms are certified (MF_PF_CERT,
 * mf_cert_ok): the evaluation's own copies of the blocks, with those terms
 * unchecked (cert = 1: mf_cmac ...; MF_CERT_PATH, mf_internal.h). */
#if MF_CERT_PATH
static void mf_lat_pure_c(const grip_mf_params *p, const mf_op *op, const mf_lat_common *c, grip_real_t g,
                          mf_lat *out)
{
    mf_lat_body(p, op, c, g, NULL, R_ONE, NULL, 1, out);
}

static void mf_lat_pure_g0_c(const grip_mf_params *p, const mf_op *op, const mf_lat_common *c, mf_lat *out)
{
    mf_lat_body(p, op, c, R_ZERO, NULL, R_ONE, NULL, 1, out);
}

static void mf_trail_coefs_c(const grip_mf_params *p, const mf_op *op, const mf_lat *lat, mf_trail *out)
{
    mf_trail_body(p, op, lat, R_ONE, NULL, 1, out);
}

static grip_real_t mf_gyk_c(const grip_mf_params *p, const mf_op *op, grip_real_t g)
{
    return mf_gyk_body(p, op, g, R_ONE, NULL, 1);
}
#endif

static MF_NOINLINE void mf_lat_pure_x(const grip_mf_params *p, const mf_op *op, const mf_lat_common *c,
                                      grip_real_t g, const mf_ts *ts, grip_real_t emax, mf_lat *out)
{
    mf_lat_body(p, op, c, g, ts, emax, NULL, 0, out);
}

static void mf_trail_coefs(const grip_mf_params *p, const mf_op *op, const mf_lat *lat, mf_trail *out)
{
    mf_trail_body(p, op, lat, R_ONE, NULL, 0, out);
}

/* with turn slip (ts not NULL): Dt times zeta5 (4.91, 4.E43), Br times
 * zeta6 (4.102, 4.E45) */
static MF_NOINLINE void mf_trail_coefs_x(const grip_mf_params *p, const mf_op *op, const mf_lat *lat,
                                         const mf_ts *ts, grip_real_t emax, mf_trail *out)
{
    mf_trail_body(p, op, lat, emax, NULL, 0, out);
    if (ts != NULL) {
        out->dt = r_mul(out->dt, r_cos_atan(r_mul(p->qdtp1, ts->u)));
        out->br = r_mul(out->br, r_cos_atan(r_mul(p->qbrp1, ts->u)));
    }
}

static grip_real_t mf_gyk(const grip_mf_params *p, const mf_op *op, grip_real_t g)
{
    return mf_gyk_body(p, op, g, R_ONE, NULL, 0);
}

static MF_NOINLINE grip_real_t mf_gyk_x(const grip_mf_params *p, const mf_op *op, grip_real_t g, grip_real_t emax)
{
    return mf_gyk_body(p, op, g, emax, NULL, 0);
}

/* Trail t / R0 at a (possibly equivalent) trail slip angle a (4.E33, 4.E73). */
static grip_real_t mf_trail_at(const mf_op *op, const mf_trail *tc, grip_real_t a)
{
    return mf_trail_at_k(op, tc, a, NULL, 0);
}

#if MF_CERT_PATH
static grip_real_t mf_trail_at_c(const mf_op *op, const mf_trail *tc, grip_real_t a)
{
    return mf_trail_at_k(op, tc, a, NULL, 1);
}
#endif

/* The certified copy of a block (certified: its call) where cert, a
 * constant in each caller, is 1 and the build has those copies
 * (MF_CERT_PATH), else the checked one (checked: its call). One expression
 * of both calls' type; without MF_CERT_PATH the certified call is not
 * compiled (its function does not exist). */
#if MF_CERT_PATH
#define MF_CERT_PICK(cert, certified, checked) ((cert) ? (certified) : (checked))
#else
#define MF_CERT_PICK(cert, certified, checked) ((void)(cert), (checked))
#endif

/* mf_trail_at or its certified copy */
static MF_ALWAYS_INLINE grip_real_t mf_trail_at_any(const mf_op *op, const mf_trail *tc, grip_real_t a, int cert)
{
    return MF_CERT_PICK(cert, mf_trail_at_c(op, tc, a), mf_trail_at(op, tc, a));
}

/* Residual moment Mzr / (Fz R0) at a residual slip angle a, Cr = 1 (4.E36). */
static grip_real_t mf_residual_at(const mf_trail *tc, grip_real_t a)
{
    return mf_residual_at_k(tc, a);
}

/* The equivalent slip angle of the combined aligning moment (4.E77-78). */
static grip_real_t mf_alpha_eq(const mf_op *op, grip_real_t a, grip_real_t kxk, grip_real_t kya)
{
    return mf_alpha_eq_k(op->book, op->kappa, a, kxk, kya, NULL);
}

/* The limit of the curvature factors E of an extended evaluation: 1 in
 * MFeval's limits mode (1xx), none with GRIP_MF_OPT_NO_LIMITS (2xx); the
 * plain variants use the constant 1. */
static MF_ALWAYS_INLINE grip_real_t mf_emax(uint32_t mode)
{
    return ((mode & GRIP_MF_OPT_NO_LIMITS) != 0u) ? RC(30000.0) : R_ONE;
}

/* ------------------------------------------------------ preparation */

/* dpi (4.E2b) of the inflation pressure pr (0: INFLPRES, else NOMPRES),
 * limited to the domain; 0 for MF 5.2 (no pressure terms) and without
 * NOMPRES. */
static MF_ALWAYS_INLINE grip_real_t mf_dpi(const grip_mf_params *p, grip_real_t pr, int mf52, int *clamped)
{
    grip_real_t dpi = R_ZERO;
    if (!mf52 && (p->nompres > R_ZERO)) {
        if (!(pr > R_ZERO)) {
            pr = (p->inflpres > R_ZERO) ? p->inflpres : p->nompres;
        }
        if (pr < r_mul(RC(1.0 + GRIP_MF_DPI_MIN), p->nompres)) {
            dpi = RC(GRIP_MF_DPI_MIN);
            *clamped = 1;
        } else if (pr > r_mul(RC(1.0 + GRIP_MF_DPI_MAX), p->nompres)) {
            dpi = RC(GRIP_MF_DPI_MAX);
            *clamped = 1;
        } else {
            dpi = mf_dpi_of(pr, p->nompres);                                         /* 4.E2b */
        }
    }
    return dpi;
}


/* FITTYP of MF 5.2 / PAC2002. */
static MF_ALWAYS_INLINE int mf_is_52(const grip_mf_params *p)
{
    return (p->fittyp == 5) || (p->fittyp == 6) || (p->fittyp == 21);
}

/* TYRESIDE: the characteristics are those of a tyre on the left side of
 * the vehicle (a RIGHT file is mirrored) or, with GRIP_MF_OPT_RIGHT_SIDE,
 * on the right side (a LEFT file is mirrored); GRIP_MF_OPT_MIRROR once
 * more. */
static MF_ALWAYS_INLINE int mf_mirror(const grip_mf_params *p, uint32_t opt)
{
    return ((opt & GRIP_MF_OPT_MIRROR) != 0u) ^ (p->tyreside == (((opt & GRIP_MF_OPT_RIGHT_SIDE) != 0u) ? 1 : -1));
}

/* LMU' of LMU* (4.E8): the book's A_mu = 10, LMU' = 10 LMU* / (1 + 9 LMU*);
 * MF-Tyre's A_mu = 1, LMU' = LMU*. */
static MF_ALWAYS_INLINE grip_real_t mf_lmu_prime(int book, grip_real_t lmu_s)
{
    if (book) {
        return mf_div_lim(r_mul(RC(10.0), lmu_s), r_add(R_ONE, r_mul(RC(9.0), lmu_s)), RC(10.0));
    }
    return lmu_s;
}

/* LMU* = LMU / (1 + LMUV Vs / V0), friction decaying with the slip speed
 * Vs = |Vx| sqrt(kappa^2 + tan^2 alpha), multiplied through by |cos alpha|
 * so that alpha = pi/2 needs no division (4.E7); LMU' (4.E8) and
 * LKY / LMUY*. op->lmux_s, lmuy_s hold LMUX, LMUY; op->cosa, book formed. */
static MF_ALWAYS_INLINE void mf_lmu(const grip_mf_params *p, mf_op *op, grip_real_t vx, grip_real_t kappa,
                                    grip_real_t sa, grip_real_t ca)
{
    if (p->lmuv > R_ZERO) {
        grip_real_t vs = r_mul(r_mul(p->lmuv, r_div(r_abs(vx), p->longvl)), mf_hypot(r_mul(kappa, ca), sa));
        grip_real_t f = mf_div_lim(op->cosa, r_add(op->cosa, vs), R_ONE);
        op->lmux_s = r_mul(f, p->lmux);
        op->lmuy_s = r_mul(f, p->lmuy);
    }
    op->lmux_p = mf_lmu_prime(op->book, op->lmux_s);
    op->lmuy_p = mf_lmu_prime(op->book, op->lmuy_s);
    op->ky_mu = mf_div_lim(p->lky, op->lmuy_s, MF_LIM_RATIO);
}

/* mode: the use-mode bits of an extended evaluation (ext); the plain ones
 * take the set's options. k: a prepared set (grip_mf_prepare) of p, whose
 * decisions and constants replace the checks and the forms below (p is
 * k->p); NULL (a constant in each caller, so that the test compiles away)
 * for the unprepared evaluations. */
static MF_ALWAYS_INLINE grip_status_t mf_prepare(const grip_mf_params *p, const grip_mf_prepared *k,
                                                 const grip_mf_input *in, uint32_t mode, mf_op *op, mf_io *io,
                                                 int ext, mf_core *x)
{
    uint32_t opt = ext ? mode : ((k != NULL) ? k->options : p->options);
    int limits = 1;
    int clamped = 0;
    grip_real_t kappa = in->kappa;
    grip_real_t alpha = in->alpha;
    grip_real_t gamma = in->gamma;
    grip_real_t fz = in->fz;
    grip_real_t vx = in->vx;
    grip_real_t pr = in->p;
    grip_real_t sa;
    grip_real_t ca;

    if (ext && ((mode & GRIP_MF_OPT_NO_LIMITS) != 0u)) {
        limits = 0;
    }
    /* the plain evaluations refuse a set with a use mode, at no cost; a
     * prepared set was checked once, by grip_mf_prepare */
    if ((k == NULL) && !(ext ? mf_params_usable(p) : mf_params_usable_plain(p))) {
        return GRIP_ERR_PARAM;
    }
    if (!r_is_finite(kappa) || !r_is_finite(alpha) || !r_is_finite(gamma) || !r_is_finite(fz) ||
        !r_is_finite(vx) || !r_is_finite(pr)) {
        return GRIP_ERR_INPUT;
    }

    /* Sign conventions -> ISO-W. */
    if (k != NULL) {
        io->sae = (k->flags & MF_PF_SAE) != 0u;
    } else {
        io->sae = (opt & GRIP_MF_OPT_SAE) != 0u;
    }
    if (io->sae) {
        alpha = r_neg(alpha);          /* rotation about z: z points down in SAE */
        fz = r_neg(fz);                /* a loaded tyre has Fz < 0 in SAE        */
    }
    if ((k != NULL) ? ((k->flags & MF_PF_KAPPA_BRAKE) != 0u) : ((opt & GRIP_MF_OPT_KAPPA_BRAKE) != 0u)) {
        kappa = r_neg(kappa);
    }
    if (k != NULL) {
        io->mirror = (k->flags & MF_PF_MIRROR) != 0u;
    } else {
        io->mirror = mf_mirror(p, opt);
    }
    if (io->mirror) {
        alpha = r_neg(alpha);
        gamma = r_neg(gamma);
    }

    /* Valid domain. Fz <= 0 (tyre off the ground) gives zero forces; the
     * operating point is still formed, at Fz = 0, for the extended outputs
     * of the unloaded wheel. */
    io->zero = !(fz > R_ZERO);
    if (k != NULL) {
        op->book = (k->flags & MF_PF_BOOK) != 0u;
        op->mf52 = (k->flags & MF_PF_MF52) != 0u;
    } else {
        op->book = (opt & GRIP_MF_OPT_BOOK) != 0u;
        op->mf52 = mf_is_52(p);
    }
    kappa = mf_clamp_sym(kappa, RC(GRIP_MF_KAPPA_MAX), &clamped);
    alpha = mf_clamp_sym(alpha, op->book ? RC(GRIP_MF_ALPHA_MAX_BOOK) : RC(GRIP_MF_ALPHA_MAX), &clamped);
    gamma = mf_clamp_sym(gamma, RC(GRIP_MF_GAMMA_MAX), &clamped);
    vx = mf_clamp_sym(vx, RC(GRIP_MF_VX_MAX), &clamped);
    if (x != NULL) {
        /* the inputs of the extended outputs: before the low-speed scaling */
        x->kap = kappa;
        x->gam = gamma;
        x->vx = vx;
    }
    {
        grip_real_t fz_max = (k != NULL) ? k->fz_max : r_mul(RC(GRIP_MF_FZ_MAX_REL), p->fnomin);
        if (io->zero) {
            fz = R_ZERO;
        } else if (fz > fz_max) {
            fz = fz_max;
            clamped = 1;
        } else {
            /* in the domain */
        }
    }

    mf_load(p, fz, op);
    if ((k != NULL) && !(pr > R_ZERO)) {
        /* the default pressure: its dpi and factors were formed once */
        op->dpi = k->dpi0;
        if ((k->flags & MF_PF_DPI0_CLAMP) != 0u) {
            clamped = 1;
        }
    } else {
        op->dpi = mf_dpi(p, pr, op->mf52, &clamped);
    }
    if (io->zero) {
        return GRIP_OK;
    }
    op->dp = ((k != NULL) && !(pr > R_ZERO)) ? k->dp : NULL;

    /* Low-speed model (VXLOW), as MF-Tyre (mf_low_smooth, mf_low_alpha):
     * for |Vx| <= VXLOW kappa fades linearly with the speed (times |Vx| /
     * VXLOW) and the shifts, the trail and the residual moment by the smooth
     * factor; alpha fades while |Vx| + |Vsy| is below VXLOW. Vx = 0 gives
     * zero slip, zero shifts and zero outputs. */
    op->smooth = R_ONE;
    r_sincos(alpha, &sa, &ca);
    if ((p->vxlow > R_ZERO) && limits) {
        grip_real_t avx = r_abs(vx);
        if (avx <= p->vxlow) {
            grip_real_t num;
            grip_real_t den;
            grip_real_t rl = r_div(avx, p->vxlow);
            kappa = r_mul(rl, kappa);
            op->smooth = mf_low_smooth(rl, NULL);
            /* num < den only here: above VXLOW, num = |Vx| (c + |s|) rounds
             * to at least VXLOW c = den (each product rounds monotonically) */
            mf_low_alpha(avx, sa, ca, p->vxlow, &num, &den);
            if (num < den) {
                /* the reduced angle needs its own sin, cos */
                alpha = r_mul(r_div(num, den), alpha);
                r_sincos(alpha, &sa, &ca);
            }
        }
    }

    op->kappa = kappa;
    /* The slips are defined with |Vx| (tan(alpha) = Vsy / |Vx|, kappa =
     * -Vsx / |Vx|), and the model uses |Vx| throughout: sgn(Vcx) = +1 in
     * 4.E3, 4.E42, 4.E47 and cos'(alpha) = |cos(alpha)|. */
    op->cosa = r_abs(ca);                                                           /* 4.E6 */
    if (!limits && (vx == R_ZERO)) {
        /* cos(alpha') = Vcx / (Vc + eps) is 0 at Vx = 0, where MFeval's 2xx
         * (no low-speed model) also has sgn(Vcx) = 0 in Dr */
        op->cosa = R_ZERO;
    }
    if (op->book) {
        op->alpha = r_div(sa, ca);                                                  /* 4.E3 */
        op->gamma = r_sin(gamma);                                                   /* 4.E4 */
    } else {
        op->alpha = alpha;
        op->gamma = gamma;
    }

    op->lmux_s = p->lmux;
    op->lmuy_s = p->lmuy;
    if ((k != NULL) && ((k->flags & MF_PF_LMU_CONST) != 0u)) {
        /* LMUV = 0: LMU' and LKY / LMUY* were formed once */
        op->lmux_p = k->lmux_p;
        op->lmuy_p = k->lmuy_p;
        op->ky_mu = k->ky_mu;
    } else {
        mf_lmu(p, op, vx, kappa, sa, ca);
    }

    mf_cambers(p, gamma, op);
    return clamped ? GRIP_WARN_CLAMPED : GRIP_OK;
}

/* Scale normalized results to N and N m, apply the output conventions and
 * make sure nothing non-finite leaves (float build). */
static grip_status_t mf_finish(const grip_mf_params *p, const mf_op *op, const mf_io *io, grip_status_t st,
                               grip_real_t fx, grip_real_t fy, grip_real_t mz, grip_mf_output *out)
{
    mf_scale_out(p, op, fx, fy, mz, out);
    if (io->mirror) {
        out->fy = r_neg(out->fy);
        out->mz = r_neg(out->mz);
    }
    if (io->sae) {
        out->fy = r_neg(out->fy);
        out->mz = r_neg(out->mz);
    }
    if (!r_is_finite(out->fx) || !r_is_finite(out->fy) || !r_is_finite(out->mz)) {
        out->fx = R_ZERO;
        out->fy = R_ZERO;
        out->mz = R_ZERO;
        return (grip_mf_check_params(p) != GRIP_OK) ? GRIP_ERR_PARAM : GRIP_ERR_DOMAIN;
    }
    return st;
}

/* ts: the turn-slip context when the evaluation has turn slip (mode), NULL
 * otherwise; a set that asks for turn slip where the evaluation has none
 * (grip_mf_eval, grip_mf_eval_pure) or that lacks the turn-slip
 * coefficients is refused. */
static MF_ALWAYS_INLINE grip_status_t mf_begin(const grip_mf_params *p, const grip_mf_prepared *k,
                                               const grip_mf_input *in, uint32_t mode, const mf_ts *ts, int ext,
                                               grip_mf_output *out, mf_op *op, mf_io *io, mf_core *x)
{
    grip_status_t st;
    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    out->fx = R_ZERO;
    out->fy = R_ZERO;
    out->mz = R_ZERO;
    if ((p == NULL) || (in == NULL)) {
        return GRIP_ERR_NULL;
    }
    if (ext && ((mode & GRIP_MF_OPT_TURN_SLIP) != 0u) && ((ts == NULL) || !mf_turn_slip_usable(p))) {
        return GRIP_ERR_PARAM;
    }
    st = mf_prepare(p, k, in, mode, op, io, ext, x);
    if ((st == GRIP_OK) && io->zero) {
        return GRIP_OK;
    }
    return st;
}

/* What both evaluations compute first: the operating point, the pure
 * longitudinal force and the common lateral factors (mf_pure_begin); then
 * each caller evaluates Fy0 and the trail coefficients into the same struct
 * (mf_lat_pure, mf_trail_coefs: called from the evaluations, not from the
 * helper, so that the helper adds no frame to the deepest call path - the
 * stack budget of the firmware, tests/firmware/check.sh). */
typedef struct {
    mf_op op;
    mf_io io;
    mf_long lon;
    mf_lat_common latc;
    mf_lat lat;          /* at gamma*                                          */
    mf_lat lat0;         /* at gamma = 0, filled by mf_lat_gamma0 if needed    */
    mf_trail tc;
} mf_pure;

/* cos(atan(num / den)) = |den| / hypot(num, den), 1 for 0 / 0. */
static grip_real_t mf_cos_atan_ratio(grip_real_t num, grip_real_t den)
{
    return (num == R_ZERO) ? R_ONE : mf_div_lim(r_abs(den), mf_hypot(num, den), R_ONE);
}

/* The spin of MFeval's parseInputs and the zeta factors that depend on it
 * and the operating point alone (op after mf_prepare):
 *   phit_e = phit cos(alpha) |Vx| / VXLOW-below-VXLOW in the limits mode
 *            (MFeval's "empirically discovered" reduction), phit otherwise;
 *   phi    = -phit_e - (1 - eps_gamma) Omega sin(gamma) / Vc' (MFeval's 4.76
 *            without the book's minus sign, ISO z up; + with
 *            GRIP_MF_OPT_TS_CAMBER), Vc' = |Vx| / cos(alpha) (alpha after
 *            the low-speed scaling), VXLOW below VXLOW; Omega the input or
 *            MFeval's estimate (1 + kappa) |Vx| / Re (ts->re, Re = R0 when it
 *            cannot be formed), so that R0 Omega / Vc' = (1 + kappa)
 *            cos(alpha) / r.
 * phit is a rate about z: it changes sign in SAE and in the mirror image,
 * as alpha does; |Vx| is used throughout (a given Omega changes sign with
 * Vx < 0). Returns 1 when phit or omega was clamped to the domain. */
static MF_NOINLINE int mf_ts_begin(const grip_mf_params *p, const grip_mf_input *in, const grip_mf_spin *spin,
                                   uint32_t mode, const mf_op *op, const mf_io *io, mf_ts *ts)
{
    int clamped = 0;
    int ignored = 0;     /* kappa, alpha, gamma, vx: mf_prepare reported them */
    grip_real_t dfz = op->dfz;
    grip_real_t r0 = p->unloaded_radius;
    grip_real_t kap = mf_clamp_sym(((mode & GRIP_MF_OPT_KAPPA_BRAKE) != 0u) ? r_neg(in->kappa) : in->kappa,
                                   RC(GRIP_MF_KAPPA_MAX), &ignored);
    grip_real_t ain = mf_clamp_sym(in->alpha, op->book ? RC(GRIP_MF_ALPHA_MAX_BOOK) : RC(GRIP_MF_ALPHA_MAX),
                                   &ignored);
    grip_real_t gam = mf_clamp_sym(io->mirror ? r_neg(in->gamma) : in->gamma, RC(GRIP_MF_GAMMA_MAX), &ignored);
    grip_real_t vx = mf_clamp_sym(in->vx, RC(GRIP_MF_VX_MAX), &ignored);
    grip_real_t avx = r_abs(vx);
    grip_real_t pt = mf_clamp_sym(spin->phit, RC(GRIP_MF_PHIT_MAX), &clamped);
    grip_real_t om = mf_clamp_sym(spin->omega, RC(GRIP_MF_OMEGA_MAX), &clamped);
    grip_real_t q;
    grip_real_t u;
    grip_real_t ared;
    grip_real_t byp;
    if (io->sae != io->mirror) {
        pt = r_neg(pt);
    }
    if (vx < R_ZERO) {
        om = r_neg(om);
    }
    if ((mode & GRIP_MF_OPT_NO_LIMITS) == 0u) {
        pt = r_mul(pt, r_cos(ain));
        if ((p->vxlow > R_ZERO) && (avx <= p->vxlow)) {
            pt = r_mul(pt, r_div(avx, p->vxlow));
        }
    }
    ts->ut = r_mul(r0, pt);
    ts->one_eg = r_sub(R_ONE, r_mul(p->pecp1, r_add(R_ONE, r_mul(p->pecp2, dfz))));           /* 4.90 */
    ts->gabs = r_abs(gam);
    ts->camber = 0;
    if ((mode & GRIP_MF_OPT_TS_CAMBER) != 0u) {
        ts->camber = 1;
    }
    /* q = R0 Omega / Vc' */
    if (om != R_ZERO) {
        q = (avx < p->vxlow) ? mf_div_lim(r_mul(r0, om), p->vxlow, MF_LIM_RATIO)
                             : mf_div_lim(r_mul(r_mul(r0, om), op->cosa), avx, MF_LIM_RATIO);
    } else {
        grip_real_t r = ts->re;
        grip_real_t k1 = r_add(R_ONE, kap);
        if (!(r > R_ZERO)) {
            r = R_ONE;   /* no Re: the free radius */
        }
        q = (avx < p->vxlow) ? mf_div_lim(r_mul(k1, avx), r_mul(r, p->vxlow), MF_LIM_RATIO)
                             : mf_div_lim(r_mul(k1, op->cosa), r, MF_LIM_RATIO);
    }
    q = r_mul(r_mul(ts->one_eg, r_sin(gam)), q);
    u = ts->camber ? r_add(r_neg(ts->ut), q) : r_sub(r_neg(ts->ut), q);
    u = r_clamp(u, r_neg(MF_TS_U_MAX), MF_TS_U_MAX);
    ts->u = u;
    /* zeta1 (4.105, 4.106) with the slip kappa of the model (low speed) */
    ts->z1 = r_cos_atan(r_mul(r_mul(r_mul(p->pdxp1, r_add(R_ONE, r_mul(p->pdxp2, dfz))),
                                    r_cos_atan(r_mul(p->pdxp3, op->kappa))),
                              u));
    /* zeta2 (4.77, 4.78): cos(atan(PDYP3 tan alpha)) of the slip angle
     * after the low-speed scaling (not alpha*) */
    ared = op->book ? r_atan(op->alpha) : op->alpha;
    byp = r_mul(r_mul(p->pdyp1, r_add(R_ONE, r_mul(p->pdyp2, dfz))),
                mf_cos_atan_ratio(r_mul(p->pdyp3, r_sin(ared)), r_cos(ared)));
    ts->z2 = r_cos_atan(r_mul(byp, r_add(r_abs(u), r_mul(p->pdyp4, r_sqrt(r_abs(u))))));
    ts->z3 = r_cos_atan(r_mul(p->pkyp1, r_sq(u)));                                           /* 4.79 */
    ts->cr = R_ONE;
    ts->shyp = R_ZERO;
    if (!op->mf52 && (vx != R_ZERO)) {
        /* SHyp (4.80-4.89): D_Hyp sin(C_Hyp atan(B_Hyp R0 phi - E_Hyp (...)))
         * with B_Hyp = Kyg0 / ((1 - eps_gamma) C_Hyp D_Hyp Kya0), Kya0 the
         * cornering stiffness at gamma = 0 times zeta3, all per unit load.
         * MFeval's sgn(Vcx) makes it 0 at Vx = 0. */
        grip_real_t kyd = r_add(R_ONE, r_mul(p->ppy2, op->dpi));
        grip_real_t kya0 = r_mul(r_mul(r_mul(r_mul(p->pky1, r_add(R_ONE, r_mul(p->ppy1, op->dpi))),
                                             mf_div_lim(r_sin(r_mul(p->pky4, mf_atan_ratio(op->fzp, r_mul(p->pky2, kyd)))),
                                                        op->fzp, MF_LIM_B)),
                                       p->lky),
                                 ts->z3);
        grip_real_t kyg0 = r_mul(r_mul(r_add(p->pky6, r_mul(p->pky7, dfz)), r_add(R_ONE, r_mul(p->ppy5, op->dpi))),
                                 MF_KYC(p, op));
        grip_real_t dhyp = r_add(p->phyp2, r_mul(p->phyp3, dfz));                             /* 4.86 */
        grip_real_t bhyp = mf_div_lim(kyg0, r_mul(r_mul(ts->one_eg, r_mul(p->phyp1, dhyp)), kya0), MF_LIM_B);
        ts->shyp = mf_sin_curve(bhyp, p->phyp1, dhyp, r_min(p->phyp4, mf_emax(mode)), u);
    }
    return clamped;
}

/* The turn-slip parts of the residual moment (MFeval's calculateMz0),
 * per Fz R0: returns Drp (zeta8 - 1, 4.94-4.99) and sets ts->cr = zeta7 =
 * 2/pi acos(x), x = Mzp90 / |Drp| (4.103) limited to [-1, 1] (MFeval's
 * acos of x > 1 is complex; its reported Mz grows without bound there, and
 * is Inf/NaN where Drp = 0). At phit_e = 0 (and phi = 0 with
 * GRIP_MF_OPT_TS_CAMBER) both vanish and x is the ratio of their slopes
 * Mzp_inf 2/pi QCRP2 Gyk / |Kzgr0 / (1 - eps_gamma)|. Kzgr0 as MFeval
 * writes it, Fz R0 (QDZ8 QDZ9 dfz + QDZ10 + QDZ11 dfz |gamma|) LKZC of
 * phit_e; with GRIP_MF_OPT_TS_CAMBER Fz R0 (QDZ8 + QDZ9 dfz + (QDZ10 +
 * QDZ11 dfz) |gamma|) LKZC (the camber stiffness of Dr) of phi. */
static MF_NOINLINE grip_real_t mf_ts_moment(const grip_mf_params *p, const mf_op *op, mf_ts *ts, grip_real_t muy,
                                grip_real_t gyk)
{
    grip_real_t dfz = op->dfz;
    grip_real_t q10 = MF6_ONLY(op, p->qdz10);
    grip_real_t q11 = MF6_ONLY(op, p->qdz11);
    /* Mzp_inf / (Fz R0) (4.95) */
    grip_real_t m = r_max(r_mul(r_mul(r_mul(p->qcrp1, r_abs(muy)), r_sqrt(op->fzp)), p->lmp), R_ZERO);
    grip_real_t ddrp = mf_div_lim(m, r_sin(r_mul(p->qdrp1, RC(1.5707963267949))), MF_LIM_RATIO);  /* 4.94 */
    grip_real_t kz;
    grip_real_t arg;
    grip_real_t den;
    grip_real_t drp = R_ZERO;
    grip_real_t x;
    grip_real_t f90 = r_mul(r_mul(m, MF_2_OVER_PI), gyk);
    if (ts->camber) {
        kz = r_mul(r_add(r_add(p->qdz8, r_mul(p->qdz9, dfz)), r_mul(r_add(q10, r_mul(q11, dfz)), ts->gabs)), MF_KZC(p, op));
        arg = ts->u;
    } else {
        kz = r_mul(r_add(r_mul(r_mul(p->qdz8, p->qdz9), dfz), r_add(q10, r_mul(r_mul(q11, dfz), ts->gabs))), MF_KZC(p, op));
        arg = ts->ut;
    }
    den = r_mul(p->qdrp1, ddrp);
    if (den > R_ZERO) {
        /* Drp = DDrp sin(CDrp atan(BDrp R0 phi)), BDrp R0 phi = Kzgr0 R0 phi /
         * ((1 - eps_gamma) CDrp DDrp): an atan2 keeps DDrp -> 0 finite */
        grip_real_t num = mf_div_lim(r_mul(kz, arg), ts->one_eg, MF_LIM_RATIO);
        drp = r_mul(ddrp, r_sin(r_mul(p->qdrp1, r_atan2(num, den))));
    }
    if ((ts->ut == R_ZERO) && (arg == R_ZERO)) {
        x = mf_div_lim(r_mul(r_mul(f90, p->qcrp2), r_abs(ts->one_eg)), r_abs(kz), R_ONE);
    } else {
        x = mf_div_lim(r_mul(f90, r_atan(r_mul(p->qcrp2, r_abs(ts->ut)))), r_abs(drp), R_ONE);
    }
    ts->cr = r_mul(MF_2_OVER_PI, r_atan2(r_sqrt(r_sub(R_ONE, r_sq(x))), x));                  /* acos(x) */
    return drp;
}

/* Status of the evaluation; the caller returns it at once when it is an
 * error or when io.zero (Fz <= 0: zero outputs). */
static MF_ALWAYS_INLINE grip_status_t mf_pure_begin_body(const grip_mf_params *p, const grip_mf_prepared *k,
                                                         const grip_mf_input *in, grip_mf_output *out, mf_pure *s,
                                                         int cert, mf_core *x)
{
    grip_status_t st = mf_begin(p, k, in, 0u, NULL, 0, out, &s->op, &s->io, x);
    if ((st < 0) || s->io.zero) {
        return st;
    }
    mf_long_pure(p, &s->op, NULL, R_ONE, NULL, cert, &s->lon);
    mf_lat_common_init(p, &s->op, cert, &s->latc);
    return st;
}

static grip_status_t mf_pure_begin(const grip_mf_params *p, const grip_mf_input *in, grip_mf_output *out,
                                   mf_pure *s)
{
    return mf_pure_begin_body(p, NULL, in, out, s, 0, NULL);
}

/* The same with a prepared set (p = k->p, not NULL). */
static grip_status_t mf_pure_begin_prep(const grip_mf_prepared *k, const grip_mf_input *in, grip_mf_output *out,
                                        mf_pure *s)
{
    return mf_pure_begin_body(k->p, k, in, out, s, 0, NULL);
}

/* The same for the prepared extended evaluation: also the inputs of the
 * extended outputs into *x (mf_prepare), which the channels would
 * otherwise convert and clamp again (a copy of its own, so that
 * grip_mf_eval_prepared stores nothing more). */
static grip_status_t mf_pure_begin_prep_x(const grip_mf_prepared *k, const grip_mf_input *in, grip_mf_output *out,
                                          mf_pure *s, mf_core *x)
{
    return mf_pure_begin_body(k->p, k, in, out, s, 0, x);
}

#if MF_CERT_PATH
/* ... whose coefficient terms are certified (MF_PF_CERT) */
static grip_status_t mf_pure_begin_prep_c(const grip_mf_prepared *k, const grip_mf_input *in, grip_mf_output *out,
                                          mf_pure *s)
{
    return mf_pure_begin_body(k->p, k, in, out, s, 1, NULL);
}

static grip_status_t mf_pure_begin_prep_c_x(const grip_mf_prepared *k, const grip_mf_input *in, grip_mf_output *out,
                                            mf_pure *s, mf_core *x)
{
    return mf_pure_begin_body(k->p, k, in, out, s, 1, x);
}
#endif

/* The pure-slip start of an evaluation: unprepared (k NULL), prepared, or
 * prepared and certified (cert, a constant in each caller); with a prepared
 * set and xin (a constant too), also the extended outputs' inputs into *x. */
static MF_ALWAYS_INLINE grip_status_t mf_pure_begin_any(const grip_mf_params *p, const grip_mf_prepared *k,
                                                        const grip_mf_input *in, grip_mf_output *out, mf_pure *s,
                                                        int cert, int xin, mf_core *x)
{
    if (xin && (k != NULL)) {
        return MF_CERT_PICK(cert, mf_pure_begin_prep_c_x(k, in, out, s, x), mf_pure_begin_prep_x(k, in, out, s, x));
    }
    return MF_CERT_PICK(cert, mf_pure_begin_prep_c(k, in, out, s),
                        (k != NULL) ? mf_pure_begin_prep(k, in, out, s) : mf_pure_begin(p, in, out, s));
}

/* mf_lat_pure, mf_lat_pure_g0, mf_trail_coefs, mf_gyk, or their certified
 * copies (cert: a constant in each caller) */
static MF_ALWAYS_INLINE void mf_lat_pure_any(const grip_mf_params *p, const mf_op *op, const mf_lat_common *c,
                                             grip_real_t g, int cert, mf_lat *out)
{
    MF_CERT_PICK(cert, mf_lat_pure_c(p, op, c, g, out), mf_lat_pure(p, op, c, g, out));
}

static MF_ALWAYS_INLINE void mf_lat_pure_g0_any(const grip_mf_params *p, const mf_op *op, const mf_lat_common *c,
                                                int cert, mf_lat *out)
{
    MF_CERT_PICK(cert, mf_lat_pure_g0_c(p, op, c, out), mf_lat_pure_g0(p, op, c, out));
}

static MF_ALWAYS_INLINE void mf_trail_coefs_any(const grip_mf_params *p, const mf_op *op, const mf_lat *lat,
                                                int cert, mf_trail *out)
{
    MF_CERT_PICK(cert, mf_trail_coefs_c(p, op, lat, out), mf_trail_coefs(p, op, lat, out));
}

static MF_ALWAYS_INLINE grip_real_t mf_gyk_any(const grip_mf_params *p, const mf_op *op, grip_real_t g, int cert)
{
    return MF_CERT_PICK(cert, mf_gyk_c(p, op, g), mf_gyk(p, op, g));
}


/* The same with the use modes of `mode` (mf_pure_begin_x), in three steps
 * called one after the other from the evaluation, so that their frames do
 * not add up on the deepest stack path: the operating point
 * (mf_begin_x), the turn slip (mf_ts_begin, when ts is not NULL), the pure
 * longitudinal force and the common lateral factors (mf_pure_rest_x). */
static MF_NOINLINE grip_status_t mf_begin_x(const grip_mf_params *p, const grip_mf_input *in, uint32_t mode,
                                            const mf_ts *ts, grip_mf_output *out, mf_pure *s)
{
    return mf_begin(p, NULL, in, mode, ts, 1, out, &s->op, &s->io, NULL);
}

static MF_NOINLINE void mf_pure_rest_x(const grip_mf_params *p, mf_pure *s, const mf_ts *ts, grip_real_t emax)
{
    mf_long_pure(p, &s->op, ts, emax, NULL, 0, &s->lon);
    mf_lat_common_init(p, &s->op, 0, &s->latc);
}

static MF_ALWAYS_INLINE grip_status_t mf_pure_begin_x(const grip_mf_params *p, const grip_mf_input *in,
                                                      const grip_mf_spin *spin, uint32_t mode, grip_real_t emax,
                                                      grip_mf_output *out, mf_pure *s, mf_ts *ts)
{
    grip_status_t st = mf_begin_x(p, in, mode, ts, out, s);
    if ((st < 0) || s->io.zero) {
        return st;
    }
    if ((ts != NULL) && mf_ts_begin(p, in, spin, mode, &s->op, &s->io, ts)) {
        st = GRIP_WARN_CLAMPED;
    }
    mf_pure_rest_x(p, s, ts, emax);
    return st;
}

/* The pure lateral force at gamma = 0 that the aligning moment of MF 6.x
 * needs: s->lat itself when gamma already is 0 (same function, same
 * inputs), else evaluated into s->lat0 (sharing s->latc). Forced inline:
 * called from three evaluations, it would otherwise get a frame of its own
 * on the deepest stack path (+16 B on the Cortex-M0+). */
static MF_ALWAYS_INLINE const mf_lat *mf_lat_gamma0(const grip_mf_params *p, mf_pure *s, const mf_ts *ts, int ext,
                                                    grip_real_t emax, int cert)
{
    if (s->op.gy == R_ZERO) {
        return &s->lat;
    }
    if (ext) {
        mf_lat_pure_x(p, &s->op, &s->latc, R_ZERO, ts, emax, &s->lat0);
    } else {
        mf_lat_pure_g0_any(p, &s->op, &s->latc, cert, &s->lat0);
    }
    return &s->lat0;
}

/* The pure-slip evaluation, unprepared (k NULL) or with the prepared set k
 * of p (a constant in each caller). */
static MF_ALWAYS_INLINE grip_status_t mf_pure_eval(const grip_mf_params *p, const grip_mf_prepared *k,
                                                   const grip_mf_input *in, grip_mf_output *out, int cert)
{
    mf_pure s;
    grip_real_t fy_ref;
    grip_real_t t0;
    grip_real_t mz0;
    grip_status_t st = mf_pure_begin_any(p, k, in, out, &s, cert, 0, NULL);
    if ((st < 0) || s.io.zero) {
        return st;
    }
    mf_lat_pure_any(p, &s.op, &s.latc, s.op.gy, cert, &s.lat);
    mf_trail_coefs_any(p, &s.op, &s.lat, cert, &s.tc);
    /* Mz0' = -t0 Fy0 (4.E32). MF 6.x uses Fy0 at gamma = 0 (camber acts on
     * Mz through Mzr); MF 5.2 the pure lateral force itself. */
    fy_ref = s.op.mf52 ? s.lat.fy0 : mf_lat_gamma0(p, &s, NULL, 0, R_ONE, cert)->fy0;
    t0 = mf_trail_at_any(&s.op, &s.tc, s.tc.alpha_t, cert);                          /* 4.E33 */
    mz0 = mf_mz0(p, &s.op, t0, mf_residual_at(&s.tc, s.tc.alpha_r), fy_ref);
    return mf_finish(p, &s.op, &s.io, st, s.lon.fx0, s.lat.fy0, mz0, out);
}

grip_status_t grip_mf_eval_pure(const grip_mf_params *p, const grip_mf_input *in, grip_mf_output *out)
{
    return mf_pure_eval(p, NULL, in, out, 0);
}

/* The combined evaluation; x != NULL also captures the intermediates of the
 * extended outputs (mf_core); ext (a constant in each caller): with the use
 * modes of `mode` (the _x variants); re: Re / R0 for turn slip's estimate
 * of Omega (mf_ts_radius). Inlined into its callers. */
static MF_ALWAYS_INLINE grip_status_t mf_combined(const grip_mf_params *p, const grip_mf_prepared *k,
                                                  const grip_mf_input *in, const grip_mf_spin *spin, uint32_t mode,
                                                  grip_real_t re, grip_mf_output *out, mf_core *x, int ext,
                                                  int cert, int xin)
{
    mf_pure s;
    mf_ts ts = { R_ZERO, R_ZERO, R_ZERO, R_ZERO, R_ZERO, R_ZERO, R_ZERO, R_ZERO, R_ZERO, R_ZERO, 0 };
    /* turn slip only with the capture of the extended outputs: NULL (and
     * compiled away) in grip_mf_eval */
    mf_ts *tsp = (ext && ((mode & GRIP_MF_OPT_TURN_SLIP) != 0u)) ? &ts : NULL;
    grip_real_t emax = ext ? mf_emax(mode) : R_ONE;
    grip_real_t fx;
    grip_real_t fy;
    grip_real_t mz;
    grip_real_t gyk;
    grip_real_t svyk;
    grip_real_t svyk_mz;
    grip_real_t fy_prime;
    grip_real_t t;
    grip_real_t mzr;
    grip_real_t sarm;
    grip_status_t st;
    const mf_op *op = &s.op;
    ts.re = re;
    if (ext) {
        st = mf_pure_begin_x(p, in, spin, mode, emax, out, &s, tsp);
    } else {
        st = mf_pure_begin_any(p, k, in, out, &s, cert, xin, x);
    }
    if ((x != NULL) && (st >= 0)) {
        x->op.fz_ql = s.op.fz_ql;
        x->op.fz = s.op.fz;
        x->op.fzp = s.op.fzp;
        x->op.dfz = s.op.dfz;
        x->op.dpi = s.op.dpi;
        x->op.gmux = s.io.zero ? R_ZERO : s.op.gmux;      /* not formed when unloaded */
        x->op.lmux_s = s.io.zero ? R_ZERO : s.op.lmux_s;
        x->op.mf52 = s.op.mf52;
        x->io = s.io;
    }
    if ((st < 0) || s.io.zero) {
        return st;
    }
    if (ext) {
        mf_lat_pure_x(p, op, &s.latc, op->gy, tsp, emax, &s.lat);
        mf_trail_coefs_x(p, op, &s.lat, tsp, emax, &s.tc);
    } else {
        mf_lat_pure_any(p, op, &s.latc, op->gy, cert, &s.lat);
        mf_trail_coefs_any(p, op, &s.lat, cert, &s.tc);
    }
    if (tsp != NULL) {
    }

    /* Fx = Gxa Fx0 (4.E50-E57). */
    fx = r_mul(mf_gxa(p, op, emax, NULL, cert), s.lon.fx0);

    /* Fy = Gyk Fy0 + SVyk (4.E58-E67). */
    {
        mf_svyk_f sf;
        grip_real_t dvyk;
        mf_svyk_factors(p, op, NULL, cert, &sf);
        /* grip-deviation: clang-analyzer-core.CallAndMessage false positive: mf_lat_pure writes every field of s.lat (the analyzer stops following mf_lat_body) */
        dvyk = mf_dvyk(s.lat.muy, &sf);                                                            /* 4.E67 */
        if (tsp != NULL) {
            dvyk = r_mul(dvyk, tsp->z2);
        }
        svyk = mf_svyk(p, op, &sf, dvyk);                                                          /* 4.E66 */
        gyk = ext ? mf_gyk_x(p, op, op->gy, emax) : mf_gyk_any(p, op, op->gy, cert);
        if (tsp != NULL) {
            /* 4.E47 with zeta0 = 0 (the camber term goes: the spin carries
             * it), zeta2 on the LRES term, zeta8 - 1 = Drp; Cr = zeta7 */
            grip_real_t drp = mf_ts_moment(p, op, tsp, s.lat.muy, gyk);
            s.tc.dr = r_add(r_mul(r_mul(r_mul(r_mul(r_add(p->qdz6, r_mul(p->qdz7, op->dfz)), p->lres), tsp->z2),
                                        op->lmuy_s),
                                  op->cosa),
                            drp);
        }
        fy = r_mac(svyk, gyk, s.lat.fy0);
        /* MF 5.2: the SVyk of Fy' = Fy - SVyk. MFeval (calculateMz) forms it
         * with mu_y at gamma = 0 (its muy_sub0; RVY3 keeps gamma); with
         * GRIP_MF_OPT_MZ52_SVYK_CAMBER the SVyk of Fy itself. */
        svyk_mz = svyk;
        if (op->mf52 && ((((k != NULL) ? k->options : p->options) & GRIP_MF_OPT_MZ52_SVYK_CAMBER) == 0u)) {
            svyk_mz = mf_svyk(p, op, &sf, mf_dvyk(r_mul(s.latc.mub, op->lmuy_s), &sf));
        }
    }

    /* Mz = -t Fy' + Mzr + s Fx (4.E71-E78). */
    {
        grip_real_t ar_eq = mf_alpha_eq(op, s.tc.alpha_r, s.lon.kxk, s.lat.kya);
        grip_real_t at_eq = mf_alpha_eq(op, s.tc.alpha_t, s.lon.kxk, s.lat.kya);
        sarm = mf_sarm(p, op, fy, cert);                                                                 /* 4.E76 */
        if (tsp != NULL) {
            mzr = r_mul(s.tc.dr, r_cos(r_mul(tsp->cr, r_atan(r_mul(s.tc.br, ar_eq)))));             /* 4.E75 */
        } else {
            mzr = mf_residual_at(&s.tc, ar_eq);                                                     /* 4.E75 */
        }
        t = mf_trail_at_any(op, &s.tc, at_eq, cert);                                                         /* 4.E73 */
        mf_mz_scale(p, op, &t, &mzr);
        if (op->mf52) {
            fy_prime = r_sub(fy, svyk_mz);  /* MF 5.2: Fy' = Fy - SVyk (above) */
        } else {
            /* MF 6.x: Fy' = Gyk Fy0(gamma = 0) (4.E74); MF-Tyre keeps the
             * inclination in Gyk, the book evaluates Gyk at gamma = 0 too. */
            /* grip-deviation: clang-analyzer-core.CallAndMessage false positive: mf_lat_pure writes every field of s.lat0 (the analyzer stops following mf_lat_body) */
            fy_prime = r_mul(op->book ? (ext ? mf_gyk_x(p, op, R_ZERO, emax) : mf_gyk_any(p, op, R_ZERO, cert)) : gyk,
                             mf_lat_gamma0(p, &s, tsp, ext, emax, cert)->fy0);
        }
        mz = mf_mz_sum(mzr, t, fy_prime, sarm, fx);                                                  /* 4.E71 */
    }
    if (x != NULL) {
        x->kxk = s.lon.kxk;
        x->kya = s.lat.kya;
        x->muy = s.lat.muy;
        x->t = t;
        x->mzr = mzr;
        x->fx = fx;
        x->fy = fy;
    }
    return mf_finish(p, op, &s.io, st, fx, fy, mz, out);
}

grip_status_t grip_mf_eval(const grip_mf_params *p, const grip_mf_input *in, grip_mf_output *out)
{
    return mf_combined(p, NULL, in, NULL, 0u, R_ZERO, out, NULL, 0, 0, 0);
}

/* The two variants of the extended evaluation, functions of their own
 * (inlined into one function their frames would add up on the deepest
 * stack path of grip_mf_eval_ext, tests/firmware/check.sh). */
grip_status_t mf_eval_core(const grip_mf_params *p, const grip_mf_input *in, uint32_t mode, grip_mf_output *out,
                           mf_core *x)
{
    return mf_combined(p, NULL, in, NULL, mode, R_ZERO, out, x, 0, 0, 0);
}

grip_status_t mf_eval_core_use(const grip_mf_params *p, const grip_mf_input *in, const grip_mf_spin *spin,
                               uint32_t mode, grip_real_t re, grip_mf_output *out, mf_core *x)
{
    return mf_combined(p, NULL, in, spin, mode, re, out, x, 1, 0, 0);
}

grip_status_t mf_eval_core_prepared(const grip_mf_prepared *k, const grip_mf_input *in, grip_mf_output *out,
                                    mf_core *x)
{
    if (MF_CERT_PATH && ((k->flags & MF_PF_CERT) != 0u)) {
        return mf_combined(k->p, k, in, NULL, k->options, R_ZERO, out, x, 0, 1, 1);
    }
    return mf_combined(k->p, k, in, NULL, k->options, R_ZERO, out, x, 0, 0, 1);
}

grip_real_t mf_ts_radius(const grip_mf_params *p, const grip_mf_input *in, uint32_t mode)
{
    int ignored = 0;
    int mf52 = 0;
    grip_real_t kap = mf_clamp_sym(((mode & GRIP_MF_OPT_KAPPA_BRAKE) != 0u) ? r_neg(in->kappa) : in->kappa,
                                   RC(GRIP_MF_KAPPA_MAX), &ignored);
    grip_real_t vx = mf_clamp_sym(in->vx, RC(GRIP_MF_VX_MAX), &ignored);
    grip_real_t fz = ((mode & GRIP_MF_OPT_SAE) != 0u) ? r_neg(in->fz) : in->fz;
    if (!mf_params_usable(p) || !(fz > R_ZERO)) {
        return R_ZERO;
    }
    if (mf_is_52(p)) {
        mf52 = 1;
    }
    fz = r_min(fz, r_mul(RC(GRIP_MF_FZ_MAX_REL), p->fnomin));
    return mf_rolling_radius(p, kap, vx, r_div(fz, p->fnomin), mf_dpi(p, in->p, mf52, &ignored));
}

/* ------------------------------------------------------ prepared sets */

/* out and prep of a prepared evaluation: GRIP_OK to go on, else the
 * status (outputs zeroed when out is not NULL). */
static MF_ALWAYS_INLINE grip_status_t mf_prepared_ready(const grip_mf_prepared *k, grip_mf_output *out)
{
    if (out == NULL) {
        return GRIP_ERR_NULL;
    }
    out->fx = R_ZERO;
    out->fy = R_ZERO;
    out->mz = R_ZERO;
    if (k == NULL) {
        return GRIP_ERR_NULL;
    }
    if (k->p == NULL) {
        return GRIP_ERR_PARAM;
    }
    return GRIP_OK;
}

grip_status_t grip_mf_eval_prepared(const grip_mf_prepared *prep, const grip_mf_input *in, grip_mf_output *out)
{
    grip_status_t st = mf_prepared_ready(prep, out);
    if (st != GRIP_OK) {
        return st;
    }
    if (MF_CERT_PATH && ((prep->flags & MF_PF_CERT) != 0u)) {
        return mf_combined(prep->p, prep, in, NULL, 0u, R_ZERO, out, NULL, 0, 1, 0);
    }
    return mf_combined(prep->p, prep, in, NULL, 0u, R_ZERO, out, NULL, 0, 0, 0);
}

grip_status_t grip_mf_eval_pure_prepared(const grip_mf_prepared *prep, const grip_mf_input *in,
                                         grip_mf_output *out)
{
    grip_status_t st = mf_prepared_ready(prep, out);
    if (st != GRIP_OK) {
        return st;
    }
    if (MF_CERT_PATH && ((prep->flags & MF_PF_CERT) != 0u)) {
        return mf_pure_eval(prep->p, prep, in, out, 1);
    }
    return mf_pure_eval(prep->p, prep, in, out, 0);
}

#if MF_CERT_PATH
/* The coefficients of the certified terms (mf_cmac, mf_cmsub, mf_cmul,
 * mf_cadd with cert in mf_equations.h and mf_internal.h) */
static const size_t mf_cert_coefs[] = {
    offsetof(grip_mf_params, phx1), offsetof(grip_mf_params, phx2), offsetof(grip_mf_params, pex1),
    offsetof(grip_mf_params, pex2), offsetof(grip_mf_params, pex3), offsetof(grip_mf_params, pex4),
    offsetof(grip_mf_params, pkx3), offsetof(grip_mf_params, pvx1), offsetof(grip_mf_params, pvx2),
    offsetof(grip_mf_params, pdx1), offsetof(grip_mf_params, pdx2), offsetof(grip_mf_params, pdx3),
    offsetof(grip_mf_params, pdy1), offsetof(grip_mf_params, pdy2), offsetof(grip_mf_params, pvy1),
    offsetof(grip_mf_params, pvy2), offsetof(grip_mf_params, phy1), offsetof(grip_mf_params, phy2),
    offsetof(grip_mf_params, pey1), offsetof(grip_mf_params, pey2), offsetof(grip_mf_params, pky2),
    offsetof(grip_mf_params, pky3), offsetof(grip_mf_params, pky4), offsetof(grip_mf_params, pky5),
    offsetof(grip_mf_params, pdy3), offsetof(grip_mf_params, pvy3), offsetof(grip_mf_params, pvy4),
    offsetof(grip_mf_params, pky6), offsetof(grip_mf_params, pky7), offsetof(grip_mf_params, pey3),
    offsetof(grip_mf_params, pey4), offsetof(grip_mf_params, pey5), offsetof(grip_mf_params, qhz1),
    offsetof(grip_mf_params, qhz2), offsetof(grip_mf_params, qhz3), offsetof(grip_mf_params, qhz4),
    offsetof(grip_mf_params, qdz1), offsetof(grip_mf_params, qdz2), offsetof(grip_mf_params, qdz3),
    offsetof(grip_mf_params, qdz4), offsetof(grip_mf_params, qbz1), offsetof(grip_mf_params, qbz2),
    offsetof(grip_mf_params, qbz3), offsetof(grip_mf_params, qbz4), offsetof(grip_mf_params, qbz5),
    offsetof(grip_mf_params, qbz6), offsetof(grip_mf_params, qez1), offsetof(grip_mf_params, qez2),
    offsetof(grip_mf_params, qez3), offsetof(grip_mf_params, qez4), offsetof(grip_mf_params, qez5),
    offsetof(grip_mf_params, qdz6), offsetof(grip_mf_params, qdz7), offsetof(grip_mf_params, qdz8),
    offsetof(grip_mf_params, qdz9), offsetof(grip_mf_params, qdz10), offsetof(grip_mf_params, qdz11),
    offsetof(grip_mf_params, rhy1), offsetof(grip_mf_params, rhy2), offsetof(grip_mf_params, rey1),
    offsetof(grip_mf_params, rey2), offsetof(grip_mf_params, rby1), offsetof(grip_mf_params, rby4),
    offsetof(grip_mf_params, rbx1), offsetof(grip_mf_params, rbx2), offsetof(grip_mf_params, rbx3),
    offsetof(grip_mf_params, rex1), offsetof(grip_mf_params, rex2), offsetof(grip_mf_params, rvy1),
    offsetof(grip_mf_params, rvy2), offsetof(grip_mf_params, rvy3), offsetof(grip_mf_params, rvy5),
    offsetof(grip_mf_params, rvy6), offsetof(grip_mf_params, ssz3), offsetof(grip_mf_params, ssz4),
};

/* The certificate of a prepared set (MF_PF_CERT; docs/numerics.md,
 * "Certified operations"): every certified term is a sum of at most three
 * products of a coefficient (|.| <= C) with a load, inclination, slip or
 * angle factor x, 1 or x^2 (|x| <= M), so its magnitude is at most
 * 1 + C (1 + M)^2 plus a few LSB of rounding. The set is certified when
 * that is below 30000 (Q15.16 ends at 32768). M bounds, for every input the
 * evaluation admits (mf_prepare's clamps): |dfz| (dfz in [-1, dfz at
 * fz_max], the divisions being monotone in Fz), |gamma*| and the
 * inclinations of each force (<= 1, times max |LGAx|, |LGAy|, |LGAz| in
 * MF 5.2), |kappa| (<= 1.5), and the arctangents (pi <= (1 + M)^2 for
 * M >= 1). Fixed build only: the float build has no range tests. */
static int mf_cert_ok(const grip_mf_params *p, grip_real_t fz_max, int mf52, int64_t *m_out)
{
    int64_t c = 0;
    int64_t m = 65536;                      /* 1 */
    int64_t g = 65536;
    int64_t b;
    grip_real_t dfz_max;
    size_t i;
    if ((p->fnomin <= 0) || (p->lfzo <= 0) || (fz_max <= 0)) {
        return 0;
    }
    for (i = 0u; i < (sizeof(mf_cert_coefs) / sizeof(mf_cert_coefs[0])); i++) {
        /* grip-deviation: MISRA-11.5 mf_cert_coefs holds offsetof() of grip_real_t fields of grip_mf_params: the cast returns to the field's own type */
        const grip_real_t *v = (const grip_real_t *)(const void *)((const char *)(const void *)p + mf_cert_coefs[i]);
        int64_t a = (*v < 0) ? -(int64_t)*v : (int64_t)*v;
        c = (a > c) ? a : c;
    }
    /* dfz at the largest load, by mf_load's operations */
    dfz_max = r_sub(r_div(r_div(fz_max, p->fnomin), p->lfzo), R_ONE);
    m = ((int64_t)dfz_max > m) ? (int64_t)dfz_max : m;
    if (mf52) {
        const grip_real_t lg[3] = { p->lgax, p->lgay, p->lgaz };
        for (i = 0u; i < 3u; i++) {
            int64_t a = (lg[i] < 0) ? -(int64_t)lg[i] : (int64_t)lg[i];
            g = (a + 1 > g) ? (a + 1) : g;   /* + 1 LSB: the rounding of gamma* lambda */
        }
    }
    m = (g > m) ? g : m;
    m = (RC(GRIP_MF_KAPPA_MAX) > m) ? RC(GRIP_MF_KAPPA_MAX) : m;
    if (m > ((int64_t)16 << 16)) {
        return 0;
    }
    *m_out = m;
    /* the shape factors C of the curves (C atan(.), mf_shape_eq): |C| <=
     * 20000 (+ 1 LSB: PCX1 LCX, PCY1 LCY round), so |C atan(.)| < 31417 */
    {
        const grip_real_t cs[5][2] = { { p->pcx1, p->lcx }, { p->pcy1, p->lcy }, { p->qcz1, R_ONE },
                                       { p->rcx1, R_ONE }, { p->rcy1, R_ONE } };
        for (i = 0u; i < 5u; i++) {
            int64_t a0 = (cs[i][0] < 0) ? -(int64_t)cs[i][0] : (int64_t)cs[i][0];
            int64_t a1 = (cs[i][1] < 0) ? -(int64_t)cs[i][1] : (int64_t)cs[i][1];
            if ((((a0 * a1) >> 16) + 1) > ((int64_t)20000 << 16)) {
                return 0;
            }
        }
    }
    /* 1 + C (1 + M)^2, rounded up: C < 2^31, 1 + M <= 17 */
    b = ((c * (65536 + m)) + 65535) >> 16;
    b = ((b * (65536 + m)) + 65535) >> 16;
    return (b + 65536) <= ((int64_t)30000 << 16);
}
#endif

/* The constants of the set under `options`, each formed by the expression
 * the unprepared evaluation uses (mf_prepare, mf_lmu, mf_dp_form), so that
 * the prepared evaluation is bit-identical to it. */
static void mf_prepare_fill(const grip_mf_params *p, uint32_t options, grip_mf_prepared *k)
{
    int i;
    int clamped = 0;
    int mf52 = mf_is_52(p);
    int book = 0;
    uint32_t f = 0u;
    if ((options & GRIP_MF_OPT_BOOK) != 0u) {
        book = 1;
    }
    f |= mf52 ? MF_PF_MF52 : 0u;
    f |= book ? MF_PF_BOOK : 0u;
    f |= ((options & GRIP_MF_OPT_SAE) != 0u) ? MF_PF_SAE : 0u;
    f |= ((options & GRIP_MF_OPT_KAPPA_BRAKE) != 0u) ? MF_PF_KAPPA_BRAKE : 0u;
    f |= mf_mirror(p, options) ? MF_PF_MIRROR : 0u;
    k->fz_max = r_mul(RC(GRIP_MF_FZ_MAX_REL), p->fnomin);
    k->dpi0 = mf_dpi(p, R_ZERO, mf52, &clamped);
    f |= clamped ? MF_PF_DPI0_CLAMP : 0u;
    for (i = 0; i < GRIP_MF_DP_N; i++) {
        k->dp[i] = mf_dp_form(p, k->dpi0, i);
    }
    k->lmux_p = mf_lmu_prime(book, p->lmux);
    k->lmuy_p = mf_lmu_prime(book, p->lmuy);
    k->ky_mu = mf_div_lim(p->lky, p->lmuy, MF_LIM_RATIO);
    f |= (p->lmuv > R_ZERO) ? 0u : MF_PF_LMU_CONST;
    {
        /* the vertical stiffness of the extended outputs (mf_ext.c) */
        mf_ext_cz z;
        mf_ext_cz_form(p, k->dpi0, &z);
        k->r0czp = z.r0czp;
        k->re_k = z.re_k;
        f |= z.flags;   /* MF_PF_CZ, MF_PF_RE, MF_PF_RE_U */
    }
#if !GRIP_ARITH_FIXED
    f |= mf_cert_ext_ok_f(p, k->fz_max) ? MF_PF_CERT_EXT : 0u;
#endif
#if MF_CERT_PATH
    {
        int64_t m = 0;
        if (mf_cert_ok(p, k->fz_max, mf52, &m)) {
            f |= MF_PF_CERT;
            f |= mf_cert_ext_ok(p, m) ? MF_PF_CERT_EXT : 0u;
        }
    }
#endif
    k->options = options;
    k->flags = f;
    k->p = p;
}

grip_status_t grip_mf_prepare_detail(const grip_mf_params *p, uint32_t options, grip_mf_prepared *prep,
                                     grip_check_detail_t *detail)
{
    grip_status_t st;
    if (prep != NULL) {
        prep->p = NULL;    /* not prepared until the checks pass */
        prep->options = 0u;
        prep->flags = 0u;
    }
    if ((p == NULL) || (prep == NULL)) {
        (void)mf_check_options(NULL, 0u, 0u, detail);   /* clears *detail */
        return GRIP_ERR_NULL;
    }
    st = mf_check_options(p, options, GRIP_MF_OPT_ALL & ~(GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS), detail);
    if (st == GRIP_OK) {
        mf_prepare_fill(p, options, prep);
    }
    return st;
}

grip_status_t grip_mf_prepare(const grip_mf_params *p, uint32_t options, grip_mf_prepared *prep)
{
    return grip_mf_prepare_detail(p, options, prep, NULL);
}
