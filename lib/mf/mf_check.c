/*
 * mf_check.c - validation of Magic Formula parameter sets.
 */
#include "mf_internal.h"

/* Largest FNOMIN accepted: 4 * FNOMIN (the largest load, GRIP_MF_FZ_MAX_REL)
 * and the forces it produces must fit Q23.8 (+-8.3e6 N). */
#define MF_FNOMIN_MAX RCL(1.0e6)

static int fittyp_known(int32_t fittyp)
{
    return (fittyp == 5) || (fittyp == 6) || (fittyp == 21) || (fittyp == 61) || (fittyp == 62);
}

/* options: the option bits the evaluation accepts. */
static inline int mf_params_usable_body(const grip_mf_params *p, uint32_t options)
{
    if (!fittyp_known(p->fittyp)) {
        return 0;
    }
    if ((p->tyreside != 1) && (p->tyreside != -1)) {
        return 0;
    }
    if ((p->options & ~options) != 0u) {
        return 0;
    }
    /* The comparisons are false for NaN, so NaN is rejected too. */
    if (!((p->fnomin > R_ZERO) && (p->fnomin <= MF_FNOMIN_MAX))) {
        return 0;
    }
    if (!(p->unloaded_radius > R_ZERO) || !(p->lfzo > R_ZERO)) {
        return 0;
    }
    if (!(p->nompres >= R_ZERO) || !(p->inflpres >= R_ZERO)) {
        return 0;
    }
    /* Friction scale factors: negative friction has no meaning, and LMUV
     * needs the reference speed LONGVL. */
    if (!(p->lmux >= R_ZERO) || !(p->lmuy >= R_ZERO) || !(p->lmuv >= R_ZERO)) {
        return 0;
    }
    if ((p->lmuv > R_ZERO) && !(p->longvl > RC(0.1))) {
        return 0;
    }
    return 1;
}

int mf_params_usable(const grip_mf_params *p)
{
    return mf_params_usable_body(p, GRIP_MF_OPT_ALL);
}

/* grip_mf_eval, grip_mf_eval_pure: the use modes (turn slip, no limits)
 * are grip_mf_eval_ext's; a set that asks for them is refused. */
int mf_params_usable_plain(const grip_mf_params *p)
{
    return mf_params_usable_body(p, GRIP_MF_OPT_ALL & ~(GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS));
}

int mf_turn_slip_usable(const grip_mf_params *p)
{
    return (p->phyp1 > R_ZERO) && (p->qdrp1 > R_ZERO) && (p->qdrp1 < RC(2.0));
}

grip_status_t grip_mf_check_params(const grip_mf_params *p)
{
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!mf_params_usable(p)) {
        return GRIP_ERR_PARAM;
    }
    /* a set that asks for turn slip must have its coefficients */
    if (((p->options & GRIP_MF_OPT_TURN_SLIP) != 0u) && !mf_turn_slip_usable(p)) {
        return GRIP_ERR_PARAM;
    }
#define MF_CHECK_FINITE(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED) /* grip-deviation: MISRA-20.7 X-macro: field is a member name, cannot be parenthesized */ \
    if (!r_is_finite(p->field)) {                                         \
        return GRIP_ERR_PARAM;                                            \
    }
    GRIP_MF_COEFFICIENTS(MF_CHECK_FINITE)
#undef MF_CHECK_FINITE
    return GRIP_OK;
}
