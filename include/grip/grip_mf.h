/*
 * grip_mf.h - Magic Formula tire models (MF 5.2 / PAC2002, MF 6.1 / 6.2).
 *
 * CONTRACT (shared by lib/mf, port/linux's .tir reader and the Python
 * emitter in tools/grip_tools): the parameter struct is the three header
 * fields below followed by one grip_real_t per entry of
 * GRIP_MF_COEFFICIENTS (grip_mf_coefs.h), in that order, each in SI units
 * and in its listed fixed-point format.
 */
#ifndef GRIP_MF_H
#define GRIP_MF_H

#include <stdint.h>
#include "grip_types.h"
#include "grip_mf_coefs.h"

typedef struct {
    int32_t fittyp;      /* 5, 6, 21 (MF 5.2 / PAC2002), 61, 62 (MF 6.1 / 6.2) */
    int32_t tyreside;    /* +1: LEFT or not given; -1: RIGHT (mirrored)     */
    uint32_t options;    /* GRIP_MF_OPT_* bit set                            */
#define GRIP_MF_X_FIELD(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED) grip_real_t field; /* grip-deviation: MISRA-20.7 X-macro: field is a member name */
    GRIP_MF_COEFFICIENTS(GRIP_MF_X_FIELD)
#undef GRIP_MF_X_FIELD
} grip_mf_params;

/* ------------------------------------------------------------------------
 * Option bits of grip_mf_params.options (docs/magic-formula-c.md).
 * With no bit set the model is MF-Tyre's steady-state Magic Formula in the
 * ISO-W (TYDEX W) axis system, for a tyre mounted on the LEFT side of the
 * vehicle: a parameter set with tyreside == -1 (TYRESIDE = 'RIGHT') is
 * mirrored, as the struct contract says.
 */
#define GRIP_MF_OPT_BOOK         (1u << 0) /* Pacejka-book equation forms instead of MF-Tyre's   */
#define GRIP_MF_OPT_KAPPA_BRAKE  (1u << 1) /* input kappa is positive in braking (= -kappa ISO) */
#define GRIP_MF_OPT_MIRROR       (1u << 2) /* mirror once more (alpha, gamma, Fy, Mz)           */
#define GRIP_MF_OPT_RIGHT_SIDE   (1u << 3) /* tyre on the right: mirror if tyreside == +1 instead */
#define GRIP_MF_OPT_SAE          (1u << 4) /* inputs/outputs in the SAE J670 tyre axis system   */
#define GRIP_MF_OPT_MZ52_SVYK_CAMBER (1u << 5) /* MF 5.2 combined Mz: Fy' = Fy - SVyk with the    */
                                               /* cambered mu_y (grip's earlier form) instead of  */
                                               /* MFeval's mu_y at gamma = 0; no effect on MF 6.x */
/* Use modes (MFeval's useMode digits; docs/magic-formula-c.md section 9),
 * evaluated by grip_mf_eval_ext. As option bits they are the set's
 * defaults; grip_mf_eval_ext's request word can switch them per call
 * (GRIP_MF_USE_*). */
#define GRIP_MF_OPT_TURN_SLIP    (1u << 6) /* turn slip (useMode xx2): evaluated by           */
                                           /* grip_mf_eval_ext only; grip_mf_eval and         */
                                           /* grip_mf_eval_pure refuse a set with this bit    */
                                           /* (GRIP_ERR_PARAM) rather than drop the turn slip */
#define GRIP_MF_OPT_NO_LIMITS    (1u << 7) /* useMode 2xx: no low-speed model, no E <= 1      */
                                           /* limits, mu_y with its sign; grip_mf_eval_ext    */
                                           /* only (grip_mf_eval, _pure refuse the set)       */
#define GRIP_MF_OPT_TS_CAMBER    (0x100u)   /* turn slip with the camber's spin of the sign    */
                                           /* that keeps the camber thrust at phit = 0, Drp   */
                                           /* of the spin, Kzgr0 = Fz R0 (QDZ8 + QDZ9 dfz +   */
                                           /* (QDZ10 + QDZ11 dfz)|gamma|) LKZC; no effect     */
                                           /* without turn slip                               */
#define GRIP_MF_OPT_ALL          (0x1FFu)

/* Valid input domain (plain constants: wrap them in GRIP_QS()/GRIP_QL() or
 * cast them); inputs beyond it are clamped and GRIP_WARN_CLAMPED is
 * returned. Fz <= 0 (tyre off the ground) gives zero outputs and GRIP_OK.
 * The file's own *_RANGE values (KPUMIN, FZMAX, ...) are NOT applied. */
#define GRIP_MF_KAPPA_MAX      1.5        /* |kappa| (MF-Tyre's default KPUMIN/KPUMAX)        */
#define GRIP_MF_ALPHA_MAX      1.5707963  /* |alpha| <= pi/2 rad                             */
#define GRIP_MF_ALPHA_MAX_BOOK 1.5        /* |alpha| with GRIP_MF_OPT_BOOK (tan alpha <= 14)  */
#define GRIP_MF_GAMMA_MAX      0.5235988  /* |gamma| <= 30 deg (MF-Tyre's default CAMMIN/MAX) */
#define GRIP_MF_FZ_MAX_REL     4.0        /* Fz <= 4 * FNOMIN                                 */
#define GRIP_MF_DPI_MIN        (-0.5)     /* p >= 0.5 * NOMPRES (MF 6.x)                      */
#define GRIP_MF_DPI_MAX        1.0        /* p <= 2 * NOMPRES (MF 6.x)                        */
#define GRIP_MF_VX_MAX         300.0      /* |vx| [m/s]                                       */
#define GRIP_MF_PHIT_MAX       100.0      /* |phit| [1/m] (path radius 1 cm; turn slip only)  */
#define GRIP_MF_OMEGA_MAX      3000.0     /* |omega| [rad/s]                                  */

/* Operating point of one tyre (ISO-W unless GRIP_MF_OPT_SAE / _KAPPA_BRAKE). */
typedef struct {
    grip_real_t kappa;   /* QS  longitudinal slip [-], -1 = locked wheel        */
    grip_real_t alpha;   /* QS  slip angle [rad]                                */
    grip_real_t gamma;   /* QS  inclination (camber) angle [rad]                */
    grip_real_t fz;      /* QL  vertical load [N], > 0 when loaded              */
    grip_real_t p;       /* QL  inflation pressure [Pa]; <= 0: INFLPRES, or     */
                         /*     NOMPRES if INFLPRES = 0; ignored by MF 5.2      */
    grip_real_t vx;      /* QS  longitudinal speed of the contact centre [m/s]  */
} grip_mf_input;

/* The wheel's rotations, MFeval's input columns 5 and 8: inputs of
 * grip_mf_eval_ext_spin only (a struct of their own, so that the
 * grip_mf_input of every evaluation, four on the estimator's stack per
 * step, does not grow). */
typedef struct {
    grip_real_t phit;    /* QS  turn slip [1/m], MFeval's: yaw rate of the      */
                         /*     wheel = -phit Vc (ISO z up); used with turn slip*/
    grip_real_t omega;   /* QS  wheel spin [rad/s], > 0 rolling forward; 0:     */
                         /*     MFeval's estimate (1 + kappa) |vx| / Re (Re,    */
                         /*     Omega, Rl, rho, Cz and the spin of turn slip)   */
} grip_mf_spin;

/* Forces and moment at the contact centre. */
typedef struct {
    grip_real_t fx;      /* QL  longitudinal force [N]    */
    grip_real_t fy;      /* QL  lateral force [N]         */
    grip_real_t mz;      /* QL  aligning moment [N m]     */
} grip_mf_output;

/* ------------------------------------------------------------------------
 * Extended outputs: MFeval's other output channels (grip_mf_eval_ext).
 * Bits (bit n = channel n, in the order of grip_mf_output_ext) of the
 * `outputs` request and of grip_mf_output_ext.valid; each channel in SI
 * units, in the format stated (QS = Q15.16, QL = Q23.8 in the
 * fixed build). docs/magic-formula-c.md section 8 gives each channel's
 * equations, validity and accuracy.
 */
#define GRIP_MF_EXT_RE      0x00001u /* QS  effective rolling radius Re [m]                 */
#define GRIP_MF_EXT_OMEGA   0x00002u /* QS  wheel spin (1 + kappa) vx / Re [rad/s]          */
#define GRIP_MF_EXT_RL      0x00004u /* QS  loaded radius [m] (MF 6.2: its vertical model)   */
#define GRIP_MF_EXT_RHO     0x00008u /* QS  vertical deflection [m]                         */
#define GRIP_MF_EXT_CZ      0x00010u /* QL  vertical stiffness Fz / rho [N/m]               */
#define GRIP_MF_EXT_LENGTH  0x00020u /* QS  contact patch length 2a [m]                     */
#define GRIP_MF_EXT_WIDTH   0x00040u /* QS  contact patch width 2b [m]                      */
#define GRIP_MF_EXT_T       0x00080u /* QS  pneumatic trail t (combined slip) [m]           */
#define GRIP_MF_EXT_MZR     0x00100u /* QL  residual aligning moment Mzr [N m]              */
#define GRIP_MF_EXT_MUX     0x00200u /* QS  longitudinal friction coefficient [-]           */
#define GRIP_MF_EXT_MUY     0x00400u /* QS  lateral friction coefficient |mu_y| [-]         */
#define GRIP_MF_EXT_KXK     0x00800u /* QL  longitudinal slip stiffness Kxk [N]             */
#define GRIP_MF_EXT_KYA     0x01000u /* QL  cornering stiffness Kya [N/rad]                 */
#define GRIP_MF_EXT_CX      0x02000u /* QL  overall longitudinal stiffness [N/m]            */
#define GRIP_MF_EXT_CY      0x04000u /* QL  overall lateral stiffness [N/m]                 */
#define GRIP_MF_EXT_SIGMAX  0x08000u /* QS  longitudinal relaxation length [m]              */
#define GRIP_MF_EXT_SIGMAY  0x10000u /* QS  lateral relaxation length [m]                   */
#define GRIP_MF_EXT_MX      0x20000u /* QL  overturning moment Mx [N m]                     */
#define GRIP_MF_EXT_MY      0x40000u /* QL  rolling resistance moment My [N m]              */
#define GRIP_MF_EXT_ALL     0x7FFFFu

/* Use-mode bits of grip_mf_eval_ext's request word (with the channel
 * bits): each switches the set's default (GRIP_MF_OPT_*) for this call;
 * asking for both of a pair is GRIP_ERR_INPUT. */
#define GRIP_MF_USE_TURN_SLIP    (0x01000000u) /* turn slip on (MFeval useMode xx2)          */
#define GRIP_MF_USE_NO_TURN_SLIP (0x02000000u) /* turn slip off (xx1)                         */
#define GRIP_MF_USE_NO_LIMITS    (0x04000000u) /* limits off (2xx)                            */
#define GRIP_MF_USE_LIMITS       (0x08000000u) /* limits on (1xx)                             */
#define GRIP_MF_USE_ALL          (0x0F000000u)

/* Combined-slip forces and the extended channels. A channel not requested,
 * or requested but not available (its bit clear in `valid`), is zero. */
typedef struct {
    grip_real_t fx;             /* QL  as grip_mf_eval                      */
    grip_real_t fy;             /* QL                                       */
    grip_real_t mz;             /* QL                                       */
    grip_real_t re;             /* QS  [m]      GRIP_MF_EXT_RE              */
    grip_real_t omega;          /* QS  [rad/s]  GRIP_MF_EXT_OMEGA           */
    grip_real_t rl;             /* QS  [m]      GRIP_MF_EXT_RL              */
    grip_real_t rho;            /* QS  [m]      GRIP_MF_EXT_RHO             */
    grip_real_t cz;             /* QL  [N/m]    GRIP_MF_EXT_CZ              */
    grip_real_t contact_length; /* QS  [m] 2a   GRIP_MF_EXT_LENGTH          */
    grip_real_t contact_width;  /* QS  [m] 2b   GRIP_MF_EXT_WIDTH           */
    grip_real_t t;              /* QS  [m]      GRIP_MF_EXT_T               */
    grip_real_t mzr;            /* QL  [N m]    GRIP_MF_EXT_MZR             */
    grip_real_t mux;            /* QS  [-]      GRIP_MF_EXT_MUX             */
    grip_real_t muy;            /* QS  [-]      GRIP_MF_EXT_MUY             */
    grip_real_t kxk;            /* QL  [N]      GRIP_MF_EXT_KXK             */
    grip_real_t kya;            /* QL  [N/rad]  GRIP_MF_EXT_KYA             */
    grip_real_t cx;             /* QL  [N/m]    GRIP_MF_EXT_CX              */
    grip_real_t cy;             /* QL  [N/m]    GRIP_MF_EXT_CY              */
    grip_real_t sigmax;         /* QS  [m]      GRIP_MF_EXT_SIGMAX          */
    grip_real_t sigmay;         /* QS  [m]      GRIP_MF_EXT_SIGMAY          */
    grip_real_t mx;             /* QL  [N m]    GRIP_MF_EXT_MX              */
    grip_real_t my;             /* QL  [N m]    GRIP_MF_EXT_MY              */
    uint32_t valid;             /* GRIP_MF_EXT_* bits of the channels that  */
                                /* hold a value                             */
} grip_mf_output_ext;

/* ------------------------------------------------------------------------
 * Prepared parameter set (grip_mf_prepare): what the evaluation needs that
 * depends only on the parameter set and the options, formed and validated
 * once, so that each evaluation forms only what depends on its operating
 * point. Caller-owned (no heap; 72 B on a 32-bit target, 80 B on x86-64,
 * in either build). It refers to the parameter set, which must stay in place and
 * unchanged while the prepared set is used (prepare again after changing
 * it). Its members are lib/mf's: fill it with grip_mf_prepare only.
 */
#define GRIP_MF_DP_N 8
typedef struct {
    const grip_mf_params *p; /* the set; NULL when not prepared               */
    uint32_t options;        /* the GRIP_MF_OPT_* bits evaluated              */
    uint32_t flags;          /* the option decisions (lib/mf)                 */
    grip_real_t fz_max;      /* QL  GRIP_MF_FZ_MAX_REL * FNOMIN [N]           */
    grip_real_t dpi0;        /* QS  dpi at the default pressure (p <= 0)      */
    grip_real_t dp[GRIP_MF_DP_N]; /* QS  the pressure factors at dpi0         */
    grip_real_t ky_mu;       /* QS  LKY / LMUY (LMUV = 0)                     */
    grip_real_t lmux_p;      /* QS  LMUX', LMUY' (LMUV = 0)                   */
    grip_real_t lmuy_p;
    grip_real_t r0czp;       /* QL  R0 Cz0 (1 + PFZ1 dpi0) [N] (extended outputs) */
    grip_real_t re_k;        /* QS  FNOMIN / (R0 Cz0 (1 + PFZ1 dpi0))         */
} grip_mf_prepared;

#define grip_mf_prepare GRIP_TYPED(grip_mf_prepare)
#define grip_mf_prepare_detail GRIP_TYPED(grip_mf_prepare_detail)
#define grip_mf_eval_prepared GRIP_TYPED(grip_mf_eval_prepared)
#define grip_mf_eval_pure_prepared GRIP_TYPED(grip_mf_eval_pure_prepared)
#define grip_mf_eval_ext_prepared GRIP_TYPED(grip_mf_eval_ext_prepared)
#define grip_mf_check_params GRIP_TYPED(grip_mf_check_params)
#define grip_mf_check_params_detail GRIP_TYPED(grip_mf_check_params_detail)
#define grip_mf_eval_pure GRIP_TYPED(grip_mf_eval_pure)
#define grip_mf_eval GRIP_TYPED(grip_mf_eval)
#define grip_mf_eval_ext GRIP_TYPED(grip_mf_eval_ext)
#define grip_mf_eval_ext_spin GRIP_TYPED(grip_mf_eval_ext_spin)
#define grip_mf_ext_supported GRIP_TYPED(grip_mf_ext_supported)

/* Validates a parameter set: GRIP_OK, GRIP_ERR_NULL or GRIP_ERR_PARAM:
 * FITTYP not 5, 6, 21, 61, 62; TYRESIDE not +-1; unknown option bits;
 * GRIP_MF_OPT_TURN_SLIP without PHYP1 > 0 and 0 < QDRP1 < 2;
 * FNOMIN not in (0, 1e6] N; UNLOADED_RADIUS <= 0; LFZO <= 0; NOMPRES or
 * INFLPRES < 0; LMUX, LMUY or LMUV < 0; LMUV > 0 with LONGVL <= 0.1 m/s;
 * in the float build also any non-finite coefficient. grip_mf_eval and
 * grip_mf_eval_pure repeat the cheap structural checks on every call, not
 * the per-coefficient finiteness: call this once after loading a set (a
 * non-finite coefficient that reaches an output is caught there and gives
 * zeros and GRIP_ERR_PARAM). */
grip_status_t grip_mf_check_params(const grip_mf_params *p);

/* The same checks, in the same order; on GRIP_ERR_PARAM *detail (may be
 * NULL) names the first field that failed: its member name ("fnomin",
 * "fittyp", "pky1": the .tir key in lower case) and the rule it breaks. */
grip_status_t grip_mf_check_params_detail(const grip_mf_params *p, grip_check_detail_t *detail);

/* Pure-slip forces and moment: out->fx = Fx0(kappa), out->fy = Fy0(alpha),
 * out->mz = Mz0(alpha), each at the given gamma, Fz, p and vx.
 * Returns GRIP_OK, GRIP_WARN_CLAMPED (an input was clamped to the domain
 * above; outputs valid), GRIP_ERR_NULL, GRIP_ERR_PARAM, GRIP_ERR_INPUT (a
 * non-finite input, float build) or GRIP_ERR_DOMAIN (a non-finite result
 * from finite but absurd coefficients, float build); on every error the
 * outputs are zero. A set with GRIP_MF_OPT_TURN_SLIP or _NO_LIMITS is
 * refused (GRIP_ERR_PARAM): the use modes are grip_mf_eval_ext's. Pure
 * function: no state, reentrant. */
grip_status_t grip_mf_eval_pure(const grip_mf_params *p, const grip_mf_input *in,
                                grip_mf_output *out);

/* Combined-slip forces and moment Fx, Fy, Mz. Same status rules. */
grip_status_t grip_mf_eval(const grip_mf_params *p, const grip_mf_input *in, grip_mf_output *out);

/* grip_mf_eval's Fx, Fy, Mz and the channels requested in `outputs`
 * (GRIP_MF_EXT_* bits), from the same evaluation, in the use modes of the
 * set switched by the GRIP_MF_USE_* bits of `outputs` (turn slip, with
 * spin->phit and spin->omega; no limits). spin may be NULL: phit = 0 and
 * omega = 0 (the spin estimated); grip_mf_eval_ext is
 * grip_mf_eval_ext_spin with spin NULL. The status is that of grip_mf_eval
 * (an unknown bit in `outputs`, both bits of a GRIP_MF_USE_ pair, a NaN or
 * infinite omega, or phit with turn slip, is GRIP_ERR_INPUT; turn slip on
 * a set without its coefficients GRIP_ERR_PARAM; on every error all
 * outputs are zero and valid is 0). A non-zero omega is the wheel's spin
 * of Re, Omega, Rl, rho, Cz and of the turn slip (MFeval's input column
 * 8); 0: estimated. out->valid holds the bits of
 * the requested channels that were computed; a requested channel whose bit
 * is clear is zero and must not be used: its parameters are missing from
 * the set (see grip_mf_ext_supported), its equation has no solution at this
 * operating point (MF 6.2 loaded radius) or, in the fixed build, its value
 * does not fit its format. Fz <= 0: forces, moments, mu, Kxk, Kya, t, rho,
 * Cz and the contact length are zero; Re, Omega, Rl are those of the
 * unloaded wheel. Pure function, no loops with a data-dependent count. */
grip_status_t grip_mf_eval_ext_spin(const grip_mf_params *p, const grip_mf_input *in, const grip_mf_spin *spin,
                                    uint32_t outputs, grip_mf_output_ext *out);
grip_status_t grip_mf_eval_ext(const grip_mf_params *p, const grip_mf_input *in, uint32_t outputs,
                               grip_mf_output_ext *out);

/* Prepares *prep for grip_mf_eval_prepared / grip_mf_eval_pure_prepared
 * with the parameter set p evaluated under the option bits `options`
 * (GRIP_MF_OPT_*: pass p->options for the set's own; p->options itself is
 * not used): every check of grip_mf_check_params (the per-coefficient
 * finiteness included) runs here once, with `options` in place of
 * p->options. The use modes (GRIP_MF_OPT_TURN_SLIP, _NO_LIMITS) are
 * grip_mf_eval_ext's and are refused. Returns GRIP_OK, GRIP_ERR_NULL (p or
 * prep NULL) or GRIP_ERR_PARAM; on an error *prep (when not NULL) is
 * cleared, and an evaluation with it returns GRIP_ERR_PARAM. */
grip_status_t grip_mf_prepare(const grip_mf_params *p, uint32_t options, grip_mf_prepared *prep);

/* The same; on GRIP_ERR_PARAM *detail (may be NULL) names the first field
 * that failed, as grip_mf_check_params_detail ("options" for a use-mode or
 * unknown bit of `options`). */
grip_status_t grip_mf_prepare_detail(const grip_mf_params *p, uint32_t options, grip_mf_prepared *prep,
                                     grip_check_detail_t *detail);

/* grip_mf_eval and grip_mf_eval_pure with a prepared set: the same
 * outputs and status, bit for bit, as grip_mf_eval(p, in, out) on a set
 * whose options are prep->options (tests/unit/test_mf_prepared.c, and the
 * golden test over every shared .tir file); per call only the inputs are
 * checked (GRIP_ERR_NULL, GRIP_ERR_INPUT, GRIP_WARN_CLAMPED as there),
 * and a set that did not prepare gives GRIP_ERR_PARAM. */
grip_status_t grip_mf_eval_prepared(const grip_mf_prepared *prep, const grip_mf_input *in, grip_mf_output *out);
grip_status_t grip_mf_eval_pure_prepared(const grip_mf_prepared *prep, const grip_mf_input *in,
                                         grip_mf_output *out);

/* grip_mf_eval_ext with a prepared set: Fx, Fy, Mz of grip_mf_eval_prepared
 * and the channels requested in `outputs` (GRIP_MF_EXT_* bits only), bit
 * for bit those of grip_mf_eval_ext(p, in, outputs, out) on a set whose
 * options are prep->options (tests/unit/test_mf_prepared.c). The spin is
 * estimated (omega = 0) and a prepared set has no use mode: a GRIP_MF_USE_*
 * or unknown bit in `outputs` is GRIP_ERR_INPUT; for turn slip or the
 * given spin call grip_mf_eval_ext_spin. A set that did not prepare gives
 * GRIP_ERR_PARAM; on every error all outputs are zero and valid is 0. */
grip_status_t grip_mf_eval_ext_prepared(const grip_mf_prepared *prep, const grip_mf_input *in, uint32_t outputs,
                                        grip_mf_output_ext *out);

/* The GRIP_MF_EXT_* channels the parameter set can give (0 for NULL or an
 * unusable set): Re, Omega, Rl, rho, Cz and the contact patch need
 * VERTICAL_STIFFNESS > 0 (and Q_FZ1^2 = (Cz0 R0 / Fz0)^2 - 4 Q_FZ2 >= 0
 * for Rl, rho, Cz), the contact width WIDTH > 0, Cx and Cy (and, for
 * MF 6.x, sigma_x and sigma_y) LONGITUDINAL_ / LATERAL_STIFFNESS > 0. */
uint32_t grip_mf_ext_supported(const grip_mf_params *p);

#endif /* GRIP_MF_H */
