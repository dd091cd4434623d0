/*
 * mf_batch.c - the Magic Formula over N points (grip_mf_batch.h).
 *
 * One call per array instead of one per point: the arguments and the
 * parameter set's structure are checked once, then each point is evaluated
 * by grip_mf_eval / grip_mf_eval_pure themselves (the batch is not a second
 * implementation of the equations, so it is bit-identical to them by
 * construction, in both arithmetics). The loop count is the caller's n.
 * Direct calls only (no function pointer), so that the stack tool sees the
 * whole call graph (docs/porting.md, "Memory and time").
 */
#include "mf_internal.h"
#include "grip/grip_mf_batch.h"

/* Summary of the statuses seen so far: the first error wins, then a clamp. */
static grip_status_t mf_batch_merge(grip_status_t sum, grip_status_t st)
{
    if (sum < 0) {
        return sum;
    }
    if ((st < 0) || (st == GRIP_WARN_CLAMPED)) {
        return st;
    }
    return sum;
}

static grip_status_t mf_batch(const grip_mf_params *p, uint32_t n, const grip_mf_input *in, grip_mf_output *out,
                              grip_status_t *status, int pure)
{
    grip_status_t sum = GRIP_OK;
    uint32_t k;
    if (n == 0u) {
        return GRIP_OK;
    }
    if ((p == NULL) || (in == NULL) || (out == NULL)) {
        return GRIP_ERR_NULL;
    }
    /* the plain evaluations' check: a set with a use mode (turn slip, no
     * limits: grip_mf_eval_ext's) is refused as grip_mf_eval refuses it */
    if (!mf_params_usable_plain(p)) {
        for (k = 0u; k < n; k++) {
            out[k].fx = R_ZERO;
            out[k].fy = R_ZERO;
            out[k].mz = R_ZERO;
            if (status != NULL) {
                status[k] = GRIP_ERR_PARAM;
            }
        }
        return GRIP_ERR_PARAM;
    }
    for (k = 0u; k < n; k++) {
        grip_status_t st = pure ? grip_mf_eval_pure(p, &in[k], &out[k]) : grip_mf_eval(p, &in[k], &out[k]);
        if (status != NULL) {
            status[k] = st;
        }
        sum = mf_batch_merge(sum, st);
    }
    return sum;
}

grip_status_t grip_mf_eval_batch(const grip_mf_params *p, uint32_t n, const grip_mf_input *in,
                                 grip_mf_output *out, grip_status_t *status)
{
    return mf_batch(p, n, in, out, status, 0);
}

grip_status_t grip_mf_eval_pure_batch(const grip_mf_params *p, uint32_t n, const grip_mf_input *in,
                                      grip_mf_output *out, grip_status_t *status)
{
    return mf_batch(p, n, in, out, status, 1);
}

/* With a prepared set: the parameter set was checked by grip_mf_prepare, so
 * the loop has nothing to check but the pointers; a set that did not
 * prepare fails every point as grip_mf_eval_prepared does. */
grip_status_t grip_mf_eval_prepared_batch(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                          grip_mf_output *out, grip_status_t *status)
{
    grip_status_t sum = GRIP_OK;
    uint32_t k;
    if (n == 0u) {
        return GRIP_OK;
    }
    if ((prep == NULL) || (in == NULL) || (out == NULL)) {
        return GRIP_ERR_NULL;
    }
    for (k = 0u; k < n; k++) {
        grip_status_t st = grip_mf_eval_prepared(prep, &in[k], &out[k]);
        if (status != NULL) {
            status[k] = st;
        }
        sum = mf_batch_merge(sum, st);
    }
    return sum;
}
