/*
 * grip_config_check.h - reject contradictory or unsupported configuration.
 * Included by grip_config.h after all defaults are set; never include it
 * directly.
 */
#ifndef GRIP_CONFIG_CHECK_H
#define GRIP_CONFIG_CHECK_H

#if (GRIP_ARITH_FIXED != 0) && (GRIP_ARITH_FIXED != 1)
#error "GRIP_ARITH_FIXED must be 0 (float) or 1 (fixed)"
#endif

#if (GRIP_DEBUG_SATURATION != 0) && (GRIP_DEBUG_SATURATION != 1)
#error "GRIP_DEBUG_SATURATION must be 0 or 1"
#endif

#if GRIP_DEBUG_SATURATION && !GRIP_ARITH_FIXED
#error "GRIP_DEBUG_SATURATION needs GRIP_ARITH_FIXED=1: the float build never saturates"
#endif

#if (GRIP_FLOAT_KERNELS != 0) && (GRIP_FLOAT_KERNELS != 1) && (GRIP_FLOAT_KERNELS != 2)
#error "GRIP_FLOAT_KERNELS must be 0 (libm), 1 (grip's atan, atan2) or 2 (grip's atan, atan2, sin, cos, exp)"
#endif

#if GRIP_FLOAT_KERNELS && GRIP_ARITH_FIXED
#error "GRIP_FLOAT_KERNELS needs GRIP_ARITH_FIXED=0: the fixed build uses its Q15.16 kernels"
#endif

/* The fixed-point kernels (polynomials, range reduction, constants) are
 * derived for exactly these formats; other values would silently lose
 * accuracy, so they are refused rather than accepted. */
#if GRIP_QS_BITS != 16
#error "GRIP_QS_BITS: only 16 (Q15.16) is supported"
#endif
#if GRIP_QL_BITS != 8
#error "GRIP_QL_BITS: only 8 (Q23.8) is supported"
#endif

#if defined(__STDC_VERSION__) && (__STDC_VERSION__ < 199901L)
#error "grip needs a C99 compiler"
#endif

#endif /* GRIP_CONFIG_CHECK_H */
