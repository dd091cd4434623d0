/*
 * fuzz_common.h - helpers shared by the libFuzzer harnesses of tests/fuzz.
 *
 * Input bytes are consumed front to back by a reader; a read past the end
 * yields zeros, so every input is valid. A 32-bit word w becomes a
 * grip_real_t in a way that is the same for both builds' corpora:
 *   fixed build: w itself (a raw Q15.16 / Q23.8 value);
 *   float build: w / 2^16 (QS) or w / 2^8 (QL), except that three words
 *                stand for NaN, +Inf and -Inf so that non-finite inputs
 *                are reached.
 * A property violation prints a message and aborts: libFuzzer records the
 * input as a crash.
 */
#ifndef GRIP_FUZZ_COMMON_H
#define GRIP_FUZZ_COMMON_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grip/grip_types.h"

typedef struct {
    const uint8_t *p;
    size_t n;
} fz_reader;

static inline uint8_t fz_u8(fz_reader *r)
{
    uint8_t v = 0;
    if (r->n > 0) {
        v = r->p[0];
        r->p++;
        r->n--;
    }
    return v;
}

static inline uint32_t fz_u32(fz_reader *r)
{
    uint32_t v = 0;
    int i;
    for (i = 0; i < 4; i++) {
        v |= (uint32_t)fz_u8(r) << (8 * i);
    }
    return v;
}

#define FZ_QS 0
#define FZ_QL 1

static inline grip_real_t fz_real_of(uint32_t w, int is_ql)
{
#if GRIP_ARITH_FIXED
    (void)is_ql;
    return (grip_real_t)(int32_t)w;
#else
    if (w == 0x80000000u) return NAN;
    if (w == 0x80000001u) return INFINITY;
    if (w == 0x80000002u) return -INFINITY;
    return (float)((double)(int32_t)w / (is_ql ? 256.0 : 65536.0));
#endif
}

static inline grip_real_t fz_real(fz_reader *r, int is_ql)
{
    return fz_real_of(fz_u32(r), is_ql);
}

/* SI value of a grip_real_t */
static inline double fz_d(grip_real_t v, int is_ql)
{
#if GRIP_ARITH_FIXED
    return (double)v / (is_ql ? 256.0 : 65536.0);
#else
    (void)is_ql;
    return (double)v;
#endif
}

static inline grip_real_t fz_from_d(double v, int is_ql)
{
#if GRIP_ARITH_FIXED
    double s = v * (is_ql ? 256.0 : 65536.0);
    if (s > 2147483647.0) s = 2147483647.0;   /* saturate like the library */
    if (s < -2147483647.0) s = -2147483647.0;
    return (grip_real_t)(s >= 0 ? s + 0.5 : s - 0.5);
#else
    (void)is_ql;
    return (grip_real_t)v;
#endif
}

static inline int fz_finite(grip_real_t v)
{
#if GRIP_ARITH_FIXED
    (void)v;
    return 1;
#else
    return isfinite(v) ? 1 : 0;
#endif
}

#define FZ_CHECK(cond, ...)                                                   \
    do {                                                                      \
        if (!(cond)) {                                                        \
            fprintf(stderr, "PROPERTY VIOLATED (%s:%d): %s: ", __FILE__,      \
                    __LINE__, #cond);                                         \
            fprintf(stderr, __VA_ARGS__);                                     \
            fprintf(stderr, "\n");                                            \
            abort();                                                          \
        }                                                                     \
    } while (0)

/* A status is one of the documented values. */
static inline int fz_status_known(grip_status_t s)
{
    return s == GRIP_OK || s == GRIP_WARN_CLAMPED || s == GRIP_ERR_NULL || s == GRIP_ERR_PARAM ||
           s == GRIP_ERR_INPUT || s == GRIP_ERR_STATE || s == GRIP_ERR_DOMAIN;
}

/* A parameter field that a mutation may overwrite. */
typedef struct {
    size_t off;
    int is_ql;    /* FZ_QS / FZ_QL; 2: int32 */
} fz_field;

#define FZ_F(type, f, fmt) { offsetof(type, f), fmt }

/* Applies mutations (field index byte, value word) until the input ends;
 * returns how many were applied. */
static inline int fz_mutate(fz_reader *r, void *base, const fz_field *fields, size_t nfields, int max)
{
    int k = 0;
    while (r->n >= 5 && k < max) {
        const fz_field *f = &fields[fz_u8(r) % nfields];
        uint32_t w = fz_u32(r);
        if (f->is_ql == 2) {
            int32_t v = (int32_t)w;
            memcpy((char *)base + f->off, &v, sizeof v);
        } else {
            grip_real_t v = fz_real_of(w, f->is_ql);
            memcpy((char *)base + f->off, &v, sizeof v);
        }
        k++;
    }
    return k;
}

#endif
