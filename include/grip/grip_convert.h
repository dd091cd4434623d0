/*
 * grip_convert.h - SI values (double, float) to and from grip's fixed-point
 * formats, for the code around the library: a host program that fills
 * parameter sets and inputs of the fixed build, reads its outputs, or
 * writes test vectors.
 *
 *   QS = Q15.16 (1 LSB = 2^-16): dimensionless values, rad, m, m/s, s, degC
 *   QL = Q23.8  (1 LSB = 2^-8):  N, N m, Pa, N/rad, N/m, kg
 *   (which field is which: the comment beside it in the public header)
 *
 * Every function is `static inline` in this header: nothing of it is part
 * of libgrip, so the fixed library stays free of floating point (what
 * `make firmware` checks on the Cortex-M0+ image). Only a translation unit
 * that calls one of them compiles it; calling one on a core without FPU
 * links the compiler's soft-float helpers into that program.
 *
 * SI -> Q (grip_qs_from_double, grip_ql_from_float, ...):
 *   rounds to the nearest Q value, halfway cases away from zero (as
 *   GRIP_QS()/GRIP_QL() round compile-time constants); returns
 *     GRIP_OK            the rounded value is within the format;
 *     GRIP_WARN_CLAMPED  it is not: *q is the nearest bound, +INT32_MAX or
 *                        -INT32_MAX (the symmetric range of grip_q16.h:
 *                        QS +-32768, QL +-8388608, less one LSB);
 *     GRIP_ERR_INPUT     the value is NaN or infinite: *q = 0;
 *     GRIP_ERR_NULL      q is NULL.
 *   The double functions are exact up to the final rounding (scaling by a
 *   power of two loses nothing); the float functions compute in single
 *   precision only, so that a Cortex-M4F uses its FPU.
 * Q -> SI (grip_qs_to_double, ...): never fail. To double: exact. To float:
 *   the nearest float (exact while |q| < 2^24).
 *
 * For source that builds against either library, the grip_real_t forms
 * convert to and from "a QS field" or "a QL field" of this build:
 *   fixed build: the Q functions above;
 *   float build: a cast to float, with the same statuses (NaN or infinity
 *   GRIP_ERR_INPUT, beyond +-FLT_MAX GRIP_WARN_CLAMPED to +-FLT_MAX).
 */
#ifndef GRIP_CONVERT_H
#define GRIP_CONVERT_H

#include <float.h>
#include <stddef.h>
#include <stdint.h>
#include "grip_types.h"

/* ---- Q format <- SI --------------------------------------------------- */

/* round(si * scale) into [-INT32_MAX, INT32_MAX]; scale a power of two. */
static inline grip_status_t grip_q_from_double_scaled(double si, double scale, int32_t *q)
{
    double s;
    double frac;
    int64_t t;
    if (q == NULL) {
        return GRIP_ERR_NULL;
    }
    /* NaN fails both comparisons, an infinity one of them */
    if (!((si >= -DBL_MAX) && (si <= DBL_MAX))) {
        *q = 0;
        return GRIP_ERR_INPUT;
    }
    s = si * scale;   /* exact, or an infinity caught just below */
    /* x.5 rounds away from zero: 2^31 - 0.5 already rounds to 2^31 */
    if (s >= 2147483647.5) {
        *q = INT32_MAX;
        return GRIP_WARN_CLAMPED;
    }
    if (s <= -2147483647.5) {
        *q = -INT32_MAX;
        return GRIP_WARN_CLAMPED;
    }
    t = (int64_t)s;            /* toward zero; |s| < 2^31 */
    frac = s - (double)t;      /* exact */
    if (frac >= 0.5) {
        t += 1;
    } else if (frac <= -0.5) {
        t -= 1;
    } else {
        /* already the nearest */
    }
    *q = (int32_t)t;
    return GRIP_OK;
}

/* The same in single precision only. */
static inline grip_status_t grip_q_from_float_scaled(float si, float scale, int32_t *q)
{
    float s;
    float frac;
    int32_t t;
    if (q == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!((si >= -FLT_MAX) && (si <= FLT_MAX))) {
        *q = 0;
        return GRIP_ERR_INPUT;
    }
    s = si * scale;
    /* The largest float below 2^31 is 2^31 - 128, an integer: every float
     * in (-2^31, 2^31) rounds into [-INT32_MAX, INT32_MAX]. */
    if (s >= 2147483648.0f) {
        *q = INT32_MAX;
        return GRIP_WARN_CLAMPED;
    }
    if (s <= -2147483648.0f) {
        *q = -INT32_MAX;
        return GRIP_WARN_CLAMPED;
    }
    t = (int32_t)s;            /* toward zero */
    frac = s - (float)t;       /* exact: |t| < 2^24 or s is an integer */
    if (frac >= 0.5f) {
        t += 1;
    } else if (frac <= -0.5f) {
        t -= 1;
    } else {
        /* already the nearest */
    }
    *q = t;
    return GRIP_OK;
}

/* SI value -> QS (Q15.16) / QL (Q23.8). */
static inline grip_status_t grip_qs_from_double(double si, int32_t *q)
{
    return grip_q_from_double_scaled(si, 65536.0, q);
}
static inline grip_status_t grip_ql_from_double(double si, int32_t *q)
{
    return grip_q_from_double_scaled(si, 256.0, q);
}
static inline grip_status_t grip_qs_from_float(float si, int32_t *q)
{
    return grip_q_from_float_scaled(si, 65536.0f, q);
}
static inline grip_status_t grip_ql_from_float(float si, int32_t *q)
{
    return grip_q_from_float_scaled(si, 256.0f, q);
}

/* ---- Q format -> SI --------------------------------------------------- */

static inline double grip_qs_to_double(int32_t q)
{
    return (double)q * (1.0 / 65536.0);
}
static inline double grip_ql_to_double(int32_t q)
{
    return (double)q * (1.0 / 256.0);
}
static inline float grip_qs_to_float(int32_t q)
{
    return (float)q * (1.0f / 65536.0f);
}
static inline float grip_ql_to_float(int32_t q)
{
    return (float)q * (1.0f / 256.0f);
}

/* ---- grip_real_t of this build <-> SI --------------------------------- */

#if GRIP_ARITH_FIXED
static inline grip_status_t grip_real_qs_from_si(double si, grip_real_t *r)
{
    return grip_qs_from_double(si, r);
}
static inline grip_status_t grip_real_ql_from_si(double si, grip_real_t *r)
{
    return grip_ql_from_double(si, r);
}
static inline double grip_real_qs_to_si(grip_real_t r)
{
    return grip_qs_to_double(r);
}
static inline double grip_real_ql_to_si(grip_real_t r)
{
    return grip_ql_to_double(r);
}
#else
static inline grip_status_t grip_real_from_si_float(double si, grip_real_t *r)
{
    if (r == NULL) {
        return GRIP_ERR_NULL;
    }
    if (!((si >= -DBL_MAX) && (si <= DBL_MAX))) {
        *r = 0.0f;
        return GRIP_ERR_INPUT;
    }
    if (si > (double)FLT_MAX) {
        *r = FLT_MAX;
        return GRIP_WARN_CLAMPED;
    }
    if (si < -(double)FLT_MAX) {
        *r = -FLT_MAX;
        return GRIP_WARN_CLAMPED;
    }
    *r = (float)si;
    return GRIP_OK;
}
static inline grip_status_t grip_real_qs_from_si(double si, grip_real_t *r)
{
    return grip_real_from_si_float(si, r);
}
static inline grip_status_t grip_real_ql_from_si(double si, grip_real_t *r)
{
    return grip_real_from_si_float(si, r);
}
static inline double grip_real_qs_to_si(grip_real_t r)
{
    return (double)r;
}
static inline double grip_real_ql_to_si(grip_real_t r)
{
    return (double)r;
}
#endif

#endif /* GRIP_CONVERT_H */
