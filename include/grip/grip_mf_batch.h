/*
 * grip_mf_batch.h - the Magic Formula over N operating points in one call.
 *
 * For callers that evaluate many points with one parameter set: the four
 * wheels of an axle pair, a sweep, a table, the Python binding (grip.mf).
 * Every point gets exactly what grip_mf_eval / grip_mf_eval_pure gives it
 * (the same compiled code, bit for bit): the batch adds no second
 * implementation of the equations, only the loop, the checks of the
 * arguments done once per call, and the per-point statuses.
 *
 * Bounded: the loop runs exactly n times (the caller's count), no heap, no
 * recursion, no state; reentrant (different threads may evaluate different
 * slices of the same arrays with the same parameter set at the same time).
 */
#ifndef GRIP_MF_BATCH_H
#define GRIP_MF_BATCH_H

#include <stdint.h>
#include "grip_types.h"
#include "grip_mf.h"

#define grip_mf_eval_batch GRIP_TYPED(grip_mf_eval_batch)
#define grip_mf_eval_pure_batch GRIP_TYPED(grip_mf_eval_pure_batch)
#define grip_mf_eval_prepared_batch GRIP_TYPED(grip_mf_eval_prepared_batch)

/* Combined-slip Fx, Fy, Mz at in[0..n-1] into out[0..n-1]:
 * out[k] and status[k] are those of grip_mf_eval(p, &in[k], &out[k]), input
 * validation per point included (a non-finite input fails that point only,
 * GRIP_ERR_INPUT, zero outputs; a clamped input gives GRIP_WARN_CLAMPED).
 * status may be NULL when only the summary is wanted.
 *
 * Returns the summary: GRIP_OK for n == 0; GRIP_ERR_NULL when p, in or out
 * is NULL (n > 0; nothing is written); GRIP_ERR_PARAM when the parameter
 * set is structurally unusable or asks for a use mode of grip_mf_eval_ext
 * (GRIP_MF_OPT_TURN_SLIP, _NO_LIMITS), as grip_mf_eval refuses it (every
 * point: zero outputs, status GRIP_ERR_PARAM); otherwise the status of the first point that failed (a
 * negative status), else GRIP_WARN_CLAMPED when any point was clamped, else
 * GRIP_OK. in and out must not overlap. */
grip_status_t grip_mf_eval_batch(const grip_mf_params *p, uint32_t n, const grip_mf_input *in,
                                 grip_mf_output *out, grip_status_t *status);

/* The same with grip_mf_eval_pure (pure-slip Fx0, Fy0, Mz0) per point. */
grip_status_t grip_mf_eval_pure_batch(const grip_mf_params *p, uint32_t n, const grip_mf_input *in,
                                      grip_mf_output *out, grip_status_t *status);

/* The same with a prepared set (grip_mf_prepare): out[k] and status[k]
 * are those of grip_mf_eval_prepared(prep, &in[k], &out[k]), bit for bit
 * those of grip_mf_eval on the set (tests/unit/test_mf_prepared.c). A set
 * that did not prepare gives GRIP_ERR_PARAM at every point. */
grip_status_t grip_mf_eval_prepared_batch(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                          grip_mf_output *out, grip_status_t *status);

#endif /* GRIP_MF_BATCH_H */
