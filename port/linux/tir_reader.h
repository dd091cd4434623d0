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
 * (LINE 0 when the problem is the whole file, e.g. it cannot be opened);
 * warnings have the same form.
 *
 * Bounded: a file is read whole but at most GRIP_TIR_SIZE_MAX (4 MiB)
 * bytes, lines of at most GRIP_TIR_LINE_MAX (4096) bytes, at most 4096 keys
 * and 4096 table rows (tir_rules.h); a longer line, a larger file or a NUL
 * byte is an error that names the bound or the byte offset.
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

/* Option flags (grip_tir_options.flags). */
#define GRIP_TIR_STRICT         (1u << 0) /* every warning is an error: an unknown key,
                                             a coefficient in another section, an
                                             empty value                            */
#define GRIP_TIR_NO_RANGE_CHECK (1u << 1) /* skip the plausibility ranges of
                                             tir_rules.h (the hard checks stay)     */
#define GRIP_TIR_PURE_SLIP      (1u << 2) /* the caller evaluates pure slip
                                             (grip_mf_eval_pure): USE_MODE with
                                             units digit 3 (uncombined) is accepted */
#define GRIP_TIR_FLAGS_ALL      (0x7u)

/* Receives each warning, "FILE:LINE: KEY: what" (without a newline). */
typedef void (*grip_tir_warn_fn)(void *ctx, const char *message);

/* Initialise with grip_tir_options_init() (or = {0}): fields may be added. */
typedef struct {
    grip_tir_side side;     /* default GRIP_TIR_SIDE_FILE: as fitted */
    unsigned flags;         /* GRIP_TIR_* bits, default 0 */
    grip_tir_warn_fn warn;  /* NULL: each warning as "warning: MESSAGE" on stderr */
    void *warn_ctx;         /* passed to warn */
} grip_tir_options;

/* The defaults: as fitted, no flags, warnings on stderr. */
void grip_tir_options_init(grip_tir_options *o);

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
    int32_t fittyp;         /* the Magic Formula evaluated: 5, 6, 21, 61, 62 */
    int32_t tyreside;
    uint32_t options;
    double v[GRIP_TIR_NCOEF];
    unsigned long line[GRIP_TIR_NCOEF];
    int32_t fittyp_file;    /* FITTYP as written (52 is read as 21); 0: not given */
    int32_t use_mode;       /* the file's USE_MODE (MF-Tyre), -1 if not given; grip_mf_params
                               has no field for it: the readers accept units digit 4
                               (combined slip), 3 with GRIP_TIR_PURE_SLIP, tens 0..3,
                               hundreds 0..5, and refuse the rest with the reason */
    unsigned long use_mode_line;  /* 0: not given */
    unsigned nwarnings;     /* warnings given while reading */
} grip_tir_values;

/* Reads `path` into `out`, mounted as fitted, warnings on stderr. Returns
 * 0, or -1 with a message in err (if err != NULL) and `out` left untouched. */
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
