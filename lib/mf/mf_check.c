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

int mf_params_usable(const grip_mf_params *p)
{
    if (!fittyp_known(p->fittyp)) {
        return 0;
    }
    if ((p->tyreside != 1) && (p->tyreside != -1)) {
        return 0;
    }
    if ((p->options & ~GRIP_MF_OPT_ALL) != 0u) {
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

grip_status_t grip_mf_check_params(const grip_mf_params *p)
{
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!mf_params_usable(p)) {
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
