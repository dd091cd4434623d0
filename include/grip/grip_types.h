/*
 * grip_types.h - the scalar type, status codes and symbol naming shared by
 * every grip module.
 *
 * grip_real_t is `float` in the float build and a Q-format int32_t in the
 * fixed build. Each physical quantity has one fixed-point format:
 *
 *   QS (Q15.16, 1 LSB = 2^-16): dimensionless values, slip, angles [rad],
 *      lengths [m], speeds [m/s], times [s], temperatures [degC or K].
 *   QL (Q23.8,  1 LSB = 2^-8):  forces [N], moments [N m], pressures [Pa],
 *      stiffnesses [N/rad, N/m], masses [kg].
 *
 * Public functions link under a name that states the number type
 * (grip_mf_eval_f32 or grip_mf_eval_q16), so an application compiled for one
 * build cannot silently link the library of the other.
 */
#ifndef GRIP_TYPES_H
#define GRIP_TYPES_H

#include <stdint.h>
#include "grip_config.h"
#include "grip_version.h"

#if GRIP_ARITH_FIXED
typedef int32_t grip_real_t;
#define GRIP_ARITH_NAME "fixed"
#define GRIP_TYPED(name) name##_q16
#else
typedef float grip_real_t;
#define GRIP_ARITH_NAME "float"
#define GRIP_TYPED(name) name##_f32
#endif

/*
 * Constants of each format, for compile-time literals only: in the fixed
 * build the float expression is folded by the compiler into an integer, so
 * no floating point reaches the object code. Passing a run-time value here
 * in the fixed build would pull in soft-float helpers; the firmware check
 * (tests/firmware/check_no_float.sh) fails if that ever happens.
 */
#if GRIP_ARITH_FIXED
#define GRIP_QS(x) ((grip_real_t)((x) * 65536.0 + (((x) >= 0) ? 0.5 : -0.5)))
#define GRIP_QL(x) ((grip_real_t)((x) * 256.0 + (((x) >= 0) ? 0.5 : -0.5)))
#else
#define GRIP_QS(x) ((grip_real_t)(x))
#define GRIP_QL(x) ((grip_real_t)(x))
#endif

/* Status of every public function. Negative values are errors: the outputs
 * were set to their documented safe values (zero forces, invalid flags) and
 * must not be used as measurements. Positive values are warnings: outputs
 * are valid, but for a modified input (e.g. clamped to its valid range). */
typedef enum {
    GRIP_OK = 0,
    GRIP_WARN_CLAMPED = 1,      /* an input was outside its valid range and was clamped */
    GRIP_WARN_RATE = 2,         /* the samples' times disagree with the configured step rate */
    GRIP_ERR_NULL = -1,         /* a required pointer was NULL */
    GRIP_ERR_PARAM = -2,        /* the parameter set is invalid or unsupported */
    GRIP_ERR_INPUT = -3,        /* an input is non-finite or physically impossible */
    GRIP_ERR_STATE = -4,        /* an instance was used before init or after a fatal error */
    GRIP_ERR_DOMAIN = -5        /* a math function was called outside its domain */
} grip_status_t;

/* Which field a parameter or configuration check rejected, for a message
 * such as "tire[1].fnomin: in (0, 1e6] N". Filled by the *_detail
 * functions (grip_mf_check_params_detail, grip_*_check_params_detail of
 * grip_brush.h, grip_est_init_detail, grip_monitor_init_detail); every
 * string is a constant of the library, never NULL. */
typedef struct {
    const char *part;   /* the member that holds the field, e.g. "tire"; "" for the struct itself */
    int32_t index;      /* the element of part (axle 0 front, 1 rear), or -1                     */
    const char *field;  /* the struct member that failed, e.g. "fnomin"; "" if none did          */
    const char *rule;   /* the condition it breaks, e.g. "in (0, 1e6] N"; "" if none             */
} grip_check_detail_t;

#define grip_status_str GRIP_TYPED(grip_status_str)
/* A short, constant, human-readable description of a status code. */
const char *grip_status_str(grip_status_t status);

#endif /* GRIP_TYPES_H */
