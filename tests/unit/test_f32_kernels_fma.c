/*
 * test_f32_kernels_fma.c - test_f32_kernels.c on the kernels in the form
 * the Cortex-M4F build runs them (lib/arith/f32_kernels.h, GRIP_KF_FMA 1:
 * Horner's scheme with explicit fmaf), with the same measurements and the
 * bounds of that form (docs/numerics.md, "Float kernels").
 *
 * fmaf is exact arithmetic followed by one rounding wherever it runs
 * (vfma.f32 on the Cortex-M4F, vfmadd on an x86-64 with FMA, libm's
 * software fmaf elsewhere), so the explicit steps give the Cortex-M4F's
 * bits on the host. The Cortex-M4F build also contracts the kernels' other
 * a*b + c (-ffp-contract=fast: the reductions' m and exp's k, the sums
 * after them); with gcc on x86-64 this file does the same (the pragmas
 * below, and a host that has the instruction, checked at run time), so
 * that those are measured as fused too.
 */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#pragma GCC target("fma")
#pragma GCC optimize("fp-contract=fast")
#define GRIP_TEST_KF_HOST_FMA 1
#endif
#define GRIP_KF_FMA 1
#include "test_f32_kernels.c"
