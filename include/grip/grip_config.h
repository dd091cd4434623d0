/*
 * grip_config.h - build-time configuration with documented defaults.
 *
 * Override any option on the compiler command line (-DGRIP_...=...) or put
 * your overrides in a header of your own and build with
 * -DGRIP_CONFIG_FILE='"my_grip_config.h"'; that header is read first, so it
 * wins over every default below. grip_config_check.h then rejects
 * contradictory settings with #error.
 */
#ifndef GRIP_CONFIG_H
#define GRIP_CONFIG_H

#ifdef GRIP_CONFIG_FILE
#include GRIP_CONFIG_FILE
#endif

/* Arithmetic: 0 = single-precision float (for FPUs such as Cortex-M4F),
 * 1 = Q-format integers only (for cores without FPU such as Cortex-M0+).
 * `make ARITH=fixed` sets 1. */
#ifndef GRIP_ARITH_FIXED
#define GRIP_ARITH_FIXED 0
#endif

/* Float build only: where the math functions of the arithmetic layer
 * (lib/arith/arith.h) come from:
 *   0 = the C library's atanf, atan2f, sinf, cosf, expf (libm);
 *   1 = grip's own single-precision polynomial kernels
 *       (lib/arith/f32_kernels.h) for atan and atan2, libm for the rest;
 *   2 = grip's kernels for atan, atan2, sin, cos and exp.
 * grip's kernels are inline, each within a measured, tested bound of the
 * exact function (docs/numerics.md, "Float kernels"). Default: 2 on a
 * Cortex-M core with a single-precision fused multiply-add (Cortex-M4F,
 * M7, M33 with FPU: __ARM_FEATURE_FMA), where they make a Magic Formula
 * evaluation a quarter shorter than newlib's functions; 0 elsewhere (on the
 * x86-64 host glibc's functions are faster; docs/performance.md, "Float
 * kernels"). sqrt and log are libm's in every case. The fixed build has its
 * own Q15.16 kernels and needs 0. */
#ifndef GRIP_FLOAT_KERNELS
#if (GRIP_ARITH_FIXED == 0) && defined(__ARM_FEATURE_FMA) && defined(__ARM_ARCH_PROFILE) && \
    (__ARM_ARCH_PROFILE == 'M')
#define GRIP_FLOAT_KERNELS 2
#else
#define GRIP_FLOAT_KERNELS 0
#endif
#endif

/* Fixed build only: count every saturation of a fixed-point operation and
 * remember the first one (grip_debug_saturation_count()). Costs a call on
 * every saturation; meant for host tests (`make ... DEBUG_SAT=1`). */
#ifndef GRIP_DEBUG_SATURATION
#define GRIP_DEBUG_SATURATION 0
#endif

/* Fractional bits of the two fixed-point formats (see docs/numerics.md).
 * QS carries dimensionless values, angles, lengths, speeds and times;
 * QL carries forces, moments, pressures, stiffnesses and masses. */
#ifndef GRIP_QS_BITS
#define GRIP_QS_BITS 16
#endif
#ifndef GRIP_QL_BITS
#define GRIP_QL_BITS 8
#endif

#include "grip_config_check.h"

#endif /* GRIP_CONFIG_H */
