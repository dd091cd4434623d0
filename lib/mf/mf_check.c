/*
 * mf_check.c - validation of Magic Formula parameter sets.
 */
#include <stddef.h>

#include "mf_internal.h"
#include "../core/check_internal.h"

/* Largest FNOMIN accepted: 4 * FNOMIN (the largest load, GRIP_MF_FZ_MAX_REL)
 * and the forces it produces must fit Q23.8 (+-8.3e6 N). */
#define MF_FNOMIN_MAX RCL(1.0e6)

static int fittyp_known(int32_t fittyp)
{
    return (fittyp == 5) || (fittyp == 6) || (fittyp == 21) || (fittyp == 61) || (fittyp == 62);
}

/* The structural checks of p evaluated with the option bits opts, the
 * first failure named in *d (d may be NULL); options: the option bits the
 * evaluation accepts. */
static int mf_params_usable_opts(const grip_mf_params *p, uint32_t opts, uint32_t options, grip_check_detail_t *d)
{
    if (!fittyp_known(p->fittyp)) {
        return check_fail(d, "", -1, "fittyp", "one of 5, 6, 21 (MF 5.2), 61, 62 (MF 6.1, 6.2)");
    }
    if ((p->tyreside != 1) && (p->tyreside != -1)) {
        return check_fail(d, "", -1, "tyreside", "+1 (left) or -1 (right)");
    }
    if ((opts & ~options) != 0u) {
        return check_fail(d, "", -1, "options", "GRIP_MF_OPT_* bits only");
    }
    /* The comparisons are false for NaN, so NaN is rejected too. */
    if (!((p->fnomin > R_ZERO) && (p->fnomin <= MF_FNOMIN_MAX))) {
        return check_fail(d, "", -1, "fnomin", "in (0, 1e6] N");
    }
    if (!(p->unloaded_radius > R_ZERO)) {
        return check_fail(d, "", -1, "unloaded_radius", "> 0 m");
    }
    if (!(p->lfzo > R_ZERO)) {
        return check_fail(d, "", -1, "lfzo", "> 0");
    }
    if (!(p->nompres >= R_ZERO)) {
        return check_fail(d, "", -1, "nompres", ">= 0 Pa");
    }
    if (!(p->inflpres >= R_ZERO)) {
        return check_fail(d, "", -1, "inflpres", ">= 0 Pa");
    }
    /* Friction scale factors: negative friction has no meaning, and LMUV
     * needs the reference speed LONGVL. */
    if (!(p->lmux >= R_ZERO)) {
        return check_fail(d, "", -1, "lmux", ">= 0");
    }
    if (!(p->lmuy >= R_ZERO)) {
        return check_fail(d, "", -1, "lmuy", ">= 0");
    }
    if (!(p->lmuv >= R_ZERO)) {
        return check_fail(d, "", -1, "lmuv", ">= 0");
    }
    if ((p->lmuv > R_ZERO) && !(p->longvl > RC(0.1))) {
        return check_fail(d, "", -1, "longvl", "> 0.1 m/s when LMUV > 0");
    }
    return 1;
}

static int mf_params_usable_detail(const grip_mf_params *p, uint32_t options, grip_check_detail_t *d)
{
    return mf_params_usable_opts(p, p->options, options, d);
}

int mf_params_usable(const grip_mf_params *p)
{
    return mf_params_usable_detail(p, GRIP_MF_OPT_ALL, NULL);
}

/* grip_mf_eval, grip_mf_eval_pure: the use modes (turn slip, no limits)
 * are grip_mf_eval_ext's; a set that asks for them is refused. */
int mf_params_usable_plain(const grip_mf_params *p)
{
    return mf_params_usable_detail(p, GRIP_MF_OPT_ALL & ~(GRIP_MF_OPT_TURN_SLIP | GRIP_MF_OPT_NO_LIMITS), NULL);
}

int mf_turn_slip_usable(const grip_mf_params *p)
{
    return (p->phyp1 > R_ZERO) && (p->qdrp1 > R_ZERO) && (p->qdrp1 < RC(2.0));
}

grip_status_t mf_check_options(const grip_mf_params *p, uint32_t opts, uint32_t accepted,
                               grip_check_detail_t *detail)
{
    check_clear(detail);
    if (p == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!mf_params_usable_opts(p, opts, accepted, detail)) {
        return GRIP_ERR_PARAM;
    }
    /* a set that asks for turn slip must have its coefficients */
    if ((opts & GRIP_MF_OPT_TURN_SLIP) != 0u) {
        if (!(p->phyp1 > R_ZERO)) {
            (void)check_fail(detail, "", -1, "phyp1", "> 0 with GRIP_MF_OPT_TURN_SLIP");
            return GRIP_ERR_PARAM;
        }
        if (!((p->qdrp1 > R_ZERO) && (p->qdrp1 < RC(2.0)))) {
            (void)check_fail(detail, "", -1, "qdrp1", "in (0, 2) with GRIP_MF_OPT_TURN_SLIP");
            return GRIP_ERR_PARAM;
        }
    }
#define MF_CHECK_FINITE(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED) /* grip-deviation: MISRA-20.7 X-macro: field is a member name, cannot be parenthesized */ \
    if (!r_is_finite(p->field)) {                                         \
        (void)check_fail(detail, "", -1, #field, "finite");               \
        return GRIP_ERR_PARAM;                                            \
    }
    GRIP_MF_COEFFICIENTS(MF_CHECK_FINITE)
#undef MF_CHECK_FINITE
    return GRIP_OK;
}

grip_status_t grip_mf_check_params_detail(const grip_mf_params *p, grip_check_detail_t *detail)
{
    return mf_check_options(p, (p != NULL) ? p->options : 0u, GRIP_MF_OPT_ALL, detail);
}

grip_status_t grip_mf_check_params(const grip_mf_params *p)
{
    return grip_mf_check_params_detail(p, NULL);
}
