/*
 * tir_reader.h - host-side reader of Magic Formula property files (.tir)
 * into grip_mf_params (include/grip/grip_mf.h).
 *
 * The coefficients read, their sections, fixed-point formats, defaults and
 * required flags come from the one list GRIP_MF_COEFFICIENTS
 * (include/grip/grip_mf_coefs.h). The validation rules are those of the
 * Python reader (tools/grip_tools/reference/tir.py); docs/tools.md lists them.
 *
 * Host code only (stdio, double): the library in lib/ never reads files.
 * Every error message has the form "FILE:LINE: KEY: what is wrong"
 * (LINE 0 when the problem is the whole file, e.g. it cannot be opened).
 */
#ifndef GRIP_TIR_READER_H
#define GRIP_TIR_READER_H

#include <stddef.h>
#include "grip/grip_mf.h"

/* Where the tyre is mounted. tyreside is always the file's TYRESIDE; the
 * mounting is GRIP_MF_OPT_RIGHT_SIDE in options, and the library mirrors the
 * characteristics when the two differ. GRIP_TIR_SIDE_FILE mounts the tyre on
 * the side it was fitted for (as fitted, never mirrored: the way MFeval and
 * MF-Tyre evaluate a property file). */
typedef enum {
    GRIP_TIR_SIDE_FILE = 0,
    GRIP_TIR_SIDE_LEFT = 1,
    GRIP_TIR_SIDE_RIGHT = -1
} grip_tir_side;

typedef struct {
    grip_tir_side side;     /* default GRIP_TIR_SIDE_FILE: as fitted */
} grip_tir_options;

/* GRIP_TIR_I_<field>: index of each coefficient in GRIP_MF_COEFFICIENTS;
 * GRIP_TIR_NCOEF: their number. */
enum {
#define GRIP_TIR_X_INDEX(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED) GRIP_TIR_I_##field,
    GRIP_MF_COEFFICIENTS(GRIP_TIR_X_INDEX)
#undef GRIP_TIR_X_INDEX
    GRIP_TIR_NCOEF
};

/*
 * The file's values in SI units and double precision, before conversion to
 * grip_real_t. v[i] belongs to the i-th entry of GRIP_MF_COEFFICIENTS;
 * line[i] is the line it was read from (0: the default was used).
 */
typedef struct {
    int32_t fittyp;
    int32_t tyreside;
    uint32_t options;
    double v[GRIP_TIR_NCOEF];
    unsigned long line[GRIP_TIR_NCOEF];
} grip_tir_values;

/* Reads `path` into `out`, mounted as fitted. Returns 0, or -1 with a
 * message in err (if err != NULL) and `out` left untouched. */
int grip_tir_read(const char *path, grip_mf_params *out, char *err, size_t errlen);

/* The same with options (opts may be NULL: defaults). */
int grip_tir_read_opts(const char *path, const grip_tir_options *opts,
                       grip_mf_params *out, char *err, size_t errlen);

/* Parses and validates (every check, including the fixed-point ranges,
 * which apply in both builds) into SI doubles, without the conversion to
 * grip_real_t. */
int grip_tir_parse(const char *path, const grip_tir_options *opts,
                   grip_tir_values *out, char *err, size_t errlen);

/* Converts parsed values into grip_real_t, range-checked in the fixed
 * build (QS: round(v * 2^16), QL: round(v * 2^8), |result| <= INT32_MAX).
 * `path` only names the file in messages. 0 or -1; out untouched on error. */
int grip_tir_convert(const char *path, const grip_tir_values *in,
                     grip_mf_params *out, char *err, size_t errlen);

/* Coefficient table access, for tests and tools. */
int grip_tir_coef_count(void);
const char *grip_tir_coef_key(int i);      /* "FNOMIN"; NULL if out of range */
const char *grip_tir_coef_section(int i);  /* "VERTICAL" */
int grip_tir_coef_is_ql(int i);            /* 1: QL format, 0: QS */
/* Index of KEY (case-insensitive) or -1. */
int grip_tir_coef_index(const char *key);
/* The i-th coefficient of p back in SI double (exact for the stored value). */
double grip_tir_coef_get(const grip_mf_params *p, int i);

/* SI double <-> grip_real_t in format QL (is_ql = 1) or QS (0). Float build:
 * (float)v; fixed build: round half away from zero of v * 2^8 or v * 2^16.
 * grip_tir_to_real returns -1 (r untouched) if v is not representable. */
int grip_tir_to_real(double v, int is_ql, grip_real_t *r);
double grip_tir_from_real(grip_real_t r, int is_ql);

#endif /* GRIP_TIR_READER_H */
