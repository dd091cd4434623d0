/*
 * grip_mf_batch.h - the Magic Formula over N operating points in one call.
 *
 * For callers that evaluate many points with one parameter set: the four
 * wheels of an axle pair, a sweep, a table, the Python binding (grip.mf).
 * The _batch functions give every point exactly what grip_mf_eval /
 * grip_mf_eval_pure (_prepared) gives it (the same compiled code, bit for
 * bit): they add no second implementation of the equations, only the
 * loop, the checks of the arguments done once per call, and the per-point
 * statuses. The _lanes functions (at the end) are the exception: the same
 * equations evaluated 8 points side by side in SIMD instructions, with the
 * branch-free forms of grip's float kernels, so the same statuses and the
 * same outputs within those kernels' accuracy (docs/magic-formula-c.md
 * section 7.2).
 *
 * Bounded: the loop runs over the caller's n points (the lanes: in blocks
 * of GRIP_MF_LANES_N), no heap, no recursion, no state; reentrant
 * (different threads may evaluate different slices of the same arrays
 * with the same parameter set at the same time).
 */
#ifndef GRIP_MF_BATCH_H
#define GRIP_MF_BATCH_H

#include <stdint.h>
#include "grip_types.h"
#include "grip_mf.h"

#define grip_mf_eval_batch GRIP_TYPED(grip_mf_eval_batch)
#define grip_mf_eval_pure_batch GRIP_TYPED(grip_mf_eval_pure_batch)
#define grip_mf_eval_prepared_batch GRIP_TYPED(grip_mf_eval_prepared_batch)
#define grip_mf_eval_prepared_lanes GRIP_TYPED(grip_mf_eval_prepared_lanes)
#define grip_mf_eval_pure_prepared_lanes GRIP_TYPED(grip_mf_eval_pure_prepared_lanes)

/* GRIP_MF_LANES: 1 when grip_mf_eval_prepared_lanes evaluates blocks of
 * GRIP_MF_LANES_N points side by side (lib/mf/mf_lanes.c): the float build
 * on a target with SIMD registers (x86-64's SSE2, Arm's NEON - the latter
 * not measured), where the compiler turns the lanes into vector
 * instructions; 0 (the scalar loop of grip_mf_eval_prepared_batch) in the
 * fixed build and on targets without SIMD (the Cortex-M4F:
 * docs/performance.md). May be set by the build (-DGRIP_MF_LANES=0 or 1;
 * 1 is refused in the fixed build). */
#define GRIP_MF_LANES_N 8u
#ifndef GRIP_MF_LANES
#if !GRIP_ARITH_FIXED && (defined(__SSE2__) || defined(__ARM_NEON))
#define GRIP_MF_LANES 1
#else
#define GRIP_MF_LANES 0
#endif
#endif
#if GRIP_MF_LANES && GRIP_ARITH_FIXED
#error "GRIP_MF_LANES needs the float build (GRIP_ARITH_FIXED 0)"
#endif

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

/* The same as grip_mf_eval_prepared_batch (pure: with
 * grip_mf_eval_pure_prepared per point), evaluated GRIP_MF_LANES_N points
 * at a time by the lane loop over the same equations where GRIP_MF_LANES is 1:
 * the same statuses per point and in the summary, the same outputs within
 * the accuracy of grip's float kernels (f32_kernels.h), which it uses
 * whatever GRIP_FLOAT_KERNELS says: bit for bit those of
 * grip_mf_eval_prepared in a build with GRIP_FLOAT_KERNELS=2, within
 * 2e-5 * Fz (forces) and 2e-5 * Fz * R0 (Mz) of them at level 0 (libm;
 * measured up to 1.0e-5 at extreme points, 5.5e-7 over the golden
 * vectors), and within the float build's golden tolerance of the
 * float64 reference (tests/unit/test_mf_lanes.c; docs/magic-formula-c.md
 * section 7.2). Sets with GRIP_MF_OPT_BOOK, a set that did
 * not prepare, the fixed build and GRIP_MF_LANES 0 take the scalar loop
 * (then bit-identical to grip_mf_eval_prepared_batch). Bounded: blocks of
 * GRIP_MF_LANES_N points, the last padded; no heap, no recursion. */
grip_status_t grip_mf_eval_prepared_lanes(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                          grip_mf_output *out, grip_status_t *status);
grip_status_t grip_mf_eval_pure_prepared_lanes(const grip_mf_prepared *prep, uint32_t n, const grip_mf_input *in,
                                               grip_mf_output *out, grip_status_t *status);

#endif /* GRIP_MF_BATCH_H */
