/*
 * tir_reader.c - host-side .tir reader (see tir_reader.h and docs/tools.md).
 *
 * The file is read line by line (LF or CRLF). A line is one of:
 *   blank, or a comment starting with '$' or '!' (after optional blanks);
 *   [SECTION]            a section header (optionally followed by a comment);
 *   {text}               a table column header (ignored);
 *   KEY = value          value: a number, a quoted string ('..' or ".."),
 *                        or a bare word; '$' or '!' starts an inline comment;
 *   numbers only         a row of a table section such as [SHAPE] (ignored).
 * Anything else is an error. Coefficients of GRIP_MF_COEFFICIENTS are taken
 * only from their own section; other keys are ignored. The [UNITS] section
 * may stand anywhere: the conversion to SI is applied after the whole file
 * is read.
 */
#include "tir_reader.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ */
/* The coefficient table, generated from the one list.                 */

enum { FMT_QS = 0, FMT_QL = 1 };

typedef struct {
    const char *key;
    const char *section;
    int fmt;
    double def;
    int required;
    size_t offset;
} coef_desc;

static const coef_desc COEFS[GRIP_TIR_NCOEF] = {
#define X_DESC(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED) \
    { #KEY, #SECTION, FMT_##FORMAT, (double)(DEFAULT), REQUIRED, offsetof(grip_mf_params, field) },
    GRIP_MF_COEFFICIENTS(X_DESC)
#undef X_DESC
};

/* ------------------------------------------------------------------ */
/* Units: the physical dimension of the coefficients that have one. All
 * other coefficients are dimensionless Magic Formula factors and are
 * never scaled.                                                        */

typedef enum {
    DIM_NONE = 0,
    DIM_LENGTH,
    DIM_FORCE,
    DIM_ANGLE,
    DIM_PRESSURE,
    DIM_SPEED,        /* length / time */
    DIM_STIFFNESS     /* force / length */
} dimension;

static const struct {
    const char *key;
    dimension dim;
} DIMENSIONS[] = {
    { "LONGVL", DIM_SPEED },
    { "VXLOW", DIM_SPEED },
    { "UNLOADED_RADIUS", DIM_LENGTH },
    { "WIDTH", DIM_LENGTH },
    { "INFLPRES", DIM_PRESSURE },
    { "NOMPRES", DIM_PRESSURE },
    { "PRESMIN", DIM_PRESSURE },
    { "PRESMAX", DIM_PRESSURE },
    { "FNOMIN", DIM_FORCE },
    { "FZMIN", DIM_FORCE },
    { "FZMAX", DIM_FORCE },
    { "VERTICAL_STIFFNESS", DIM_STIFFNESS },
    { "LONGITUDINAL_STIFFNESS", DIM_STIFFNESS },
    { "LATERAL_STIFFNESS", DIM_STIFFNESS },
    { "ALPMIN", DIM_ANGLE },
    { "ALPMAX", DIM_ANGLE },
    { "CAMMIN", DIM_ANGLE },
    { "CAMMAX", DIM_ANGLE },
};

typedef struct {
    const char *name;
    double factor;    /* to SI */
} unit_name;

static const unit_name LENGTH_UNITS[] = {
    { "meter", 1.0 }, { "meters", 1.0 }, { "metre", 1.0 }, { "metres", 1.0 }, { "m", 1.0 },
    { "millimeter", 1e-3 }, { "millimeters", 1e-3 }, { "mm", 1e-3 },
    { "centimeter", 1e-2 }, { "centimeters", 1e-2 }, { "cm", 1e-2 },
    { "kilometer", 1e3 }, { "kilometers", 1e3 }, { "km", 1e3 },
    { "inch", 0.0254 }, { "inches", 0.0254 }, { "in", 0.0254 },
    { "foot", 0.3048 }, { "feet", 0.3048 }, { "ft", 0.3048 },
    { NULL, 0.0 }
};
static const unit_name FORCE_UNITS[] = {
    { "newton", 1.0 }, { "newtons", 1.0 }, { "n", 1.0 },
    { "kilonewton", 1e3 }, { "kilonewtons", 1e3 }, { "kn", 1e3 },
    { "pound_force", 4.4482216152605 }, { "lbf", 4.4482216152605 },
    { "kilogram_force", 9.80665 }, { "kgf", 9.80665 },
    { NULL, 0.0 }
};
static const unit_name ANGLE_UNITS[] = {
    { "radian", 1.0 }, { "radians", 1.0 }, { "rad", 1.0 },
    { "degree", 0.017453292519943295 }, { "degrees", 0.017453292519943295 },
    { "deg", 0.017453292519943295 },
    { NULL, 0.0 }
};
static const unit_name MASS_UNITS[] = {
    { "kg", 1.0 }, { "kilogram", 1.0 }, { "kilograms", 1.0 },
    { "gram", 1e-3 }, { "grams", 1e-3 }, { "g", 1e-3 },
    { "tonne", 1e3 }, { "tonnes", 1e3 },
    { "pound_mass", 0.45359237 }, { "lbm", 0.45359237 },
    { NULL, 0.0 }
};
static const unit_name TIME_UNITS[] = {
    { "second", 1.0 }, { "seconds", 1.0 }, { "sec", 1.0 }, { "s", 1.0 },
    { "millisecond", 1e-3 }, { "milliseconds", 1e-3 }, { "ms", 1e-3 },
    { "minute", 60.0 }, { "minutes", 60.0 }, { "min", 60.0 },
    { "hour", 3600.0 }, { "hours", 3600.0 }, { "h", 3600.0 },
    { NULL, 0.0 }
};
static const unit_name PRESSURE_UNITS[] = {
    { "pascal", 1.0 }, { "pascals", 1.0 }, { "pa", 1.0 }, { "n/m2", 1.0 }, { "n/m^2", 1.0 },
    { "kilopascal", 1e3 }, { "kpa", 1e3 },
    { "megapascal", 1e6 }, { "mpa", 1e6 },
    { "bar", 1e5 }, { "mbar", 1e2 },
    { "psi", 6894.757293168361 },
    { NULL, 0.0 }
};

enum { Q_LENGTH, Q_FORCE, Q_ANGLE, Q_MASS, Q_TIME, Q_PRESSURE, Q_COUNT };

static const struct {
    const char *key;
    const unit_name *units;
} QUANTITIES[Q_COUNT] = {
    { "LENGTH", LENGTH_UNITS },
    { "FORCE", FORCE_UNITS },
    { "ANGLE", ANGLE_UNITS },
    { "MASS", MASS_UNITS },
    { "TIME", TIME_UNITS },
    { "PRESSURE", PRESSURE_UNITS },
};

/* ------------------------------------------------------------------ */
/* Small helpers.                                                      */

typedef struct {
    const char *path;
    char *err;
    size_t errlen;
} err_ctx;

static int fail(const err_ctx *e, unsigned long line, const char *key, const char *fmt, ...)
{
    char what[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (e->err != NULL && e->errlen > 0) {
        snprintf(e->err, e->errlen, "%s:%lu: %s: %s", e->path, line,
                 (key != NULL && key[0] != '\0') ? key : "-", what);
    }
    return -1;
}

static int ieq(const char *a, const char *b)
{
    while (*a != '\0' && *b != '\0') {
        if (toupper((unsigned char)*a) != toupper((unsigned char)*b)) {
            return 0;
        }
        a++;
        b++;
    }
    return *a == *b;
}

static char *skip_ws(char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\f' || *s == '\v') {
        s++;
    }
    return s;
}

static void rtrim(char *s)
{
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r' ||
                     s[n - 1] == '\n' || s[n - 1] == '\f' || s[n - 1] == '\v')) {
        s[--n] = '\0';
    }
}

static int is_comment_char(char c)
{
    return c == '$' || c == '!';
}

/* Only blanks or a comment may follow. */
static int rest_is_empty(const char *s)
{
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    return *s == '\0' || is_comment_char(*s);
}

/* Strict number: the whole word, finite. Accepts Fortran 'D' exponents. */
static int parse_number(const char *word, double *v)
{
    char buf[128];
    char *end = NULL;
    size_t i;
    size_t n = strlen(word);
    if (n == 0 || n >= sizeof buf) {
        return -1;
    }
    for (i = 0; i < n; i++) {
        char c = word[i];
        if (c == 'd' || c == 'D') {
            c = 'e';
        }
        /* strtod would also take "inf", "nan" and hex: allow only decimal. */
        if (!(isdigit((unsigned char)c) || c == '+' || c == '-' || c == '.' || c == 'e' || c == 'E')) {
            return -1;
        }
        buf[i] = c;
    }
    buf[n] = '\0';
    errno = 0;
    *v = strtod(buf, &end);
    if (end == buf || *end != '\0' || errno == ERANGE || !isfinite(*v)) {
        return -1;
    }
    return 0;
}

static dimension dimension_of(const char *key)
{
    size_t i;
    for (i = 0; i < sizeof DIMENSIONS / sizeof DIMENSIONS[0]; i++) {
        if (strcmp(DIMENSIONS[i].key, key) == 0) {
            return DIMENSIONS[i].dim;
        }
    }
    return DIM_NONE;
}

/* ------------------------------------------------------------------ */
/* Parsing: the whole file into a list of KEY = value entries first,    */
/* then validation in the order of tools/grip_tools/reference/tir.py, so both    */
/* readers report the same first error.                                */

typedef struct {
    char *section;          /* upper case */
    char *key;              /* upper case */
    char *raw;              /* value text (without quotes) */
    int quoted;
    unsigned long line;
} entry;

typedef struct {
    char *name;             /* upper case */
    unsigned long line;
} section_rec;

typedef struct {
    entry *e;
    size_t n;
    size_t cap;
    section_rec *s;
    size_t ns;
    size_t caps;
    unsigned long nlines;
} tir_text;

static void text_free(tir_text *t)
{
    size_t i;
    for (i = 0; i < t->n; i++) {
        free(t->e[i].section);
        free(t->e[i].key);
        free(t->e[i].raw);
    }
    for (i = 0; i < t->ns; i++) {
        free(t->s[i].name);
    }
    free(t->e);
    free(t->s);
    memset(t, 0, sizeof *t);
}

static char *dup_upper(const char *s, int upper)
{
    size_t n = strlen(s);
    char *d = malloc(n + 1);
    size_t i;
    if (d == NULL) {
        return NULL;
    }
    for (i = 0; i <= n; i++) {
        d[i] = upper ? (char)toupper((unsigned char)s[i]) : s[i];
    }
    return d;
}

static const section_rec *find_section(const tir_text *t, const char *name)
{
    size_t i;
    for (i = 0; i < t->ns; i++) {
        if (strcmp(t->s[i].name, name) == 0) {
            return &t->s[i];
        }
    }
    return NULL;
}

static const entry *find_entry(const tir_text *t, const char *section, const char *key)
{
    size_t i;
    for (i = 0; i < t->n; i++) {
        if (strcmp(t->e[i].section, section) == 0 && ieq(t->e[i].key, key)) {
            return &t->e[i];
        }
    }
    return NULL;
}

/* Line to name for a key that is missing: its section's header, else the
 * last line of the file. */
static unsigned long missing_line(const tir_text *t, const char *section)
{
    const section_rec *s = find_section(t, section);
    return (s != NULL) ? s->line : t->nlines;
}

/* Splits "KEY = value $comment" in place. Returns 0, or -1 with *why set. */
static int split_assignment(char *s, char **key, char **value, int *quoted, const char **why)
{
    char *eq = strchr(s, '=');
    char *k = s;
    char *p;
    char *v;
    *quoted = 0;
    p = k;
    while (isalnum((unsigned char)*p) || *p == '_') {
        p++;
    }
    if (p == k) {
        *why = "expected KEY = value";
        return -1;
    }
    if (skip_ws(p) != eq) {
        *why = "expected '=' after the key";
        return -1;
    }
    *p = '\0';
    *key = k;
    v = skip_ws(eq + 1);
    if (*v == '\'' || *v == '"') {
        char q = *v;
        char *close = strchr(v + 1, q);
        if (close == NULL) {
            *why = "unterminated quoted string";
            return -1;
        }
        *close = '\0';
        if (!rest_is_empty(close + 1)) {
            *why = "unexpected text after the value";
            return -1;
        }
        *value = v + 1;
        *quoted = 1;
        return 0;
    }
    p = v;
    while (*p != '\0' && *p != ' ' && *p != '\t' && !is_comment_char(*p)) {
        p++;
    }
    if (!rest_is_empty(p)) {
        *why = "unexpected text after the value";
        return -1;
    }
    *p = '\0';
    *value = v;
    return 0;
}

/* Is the line a row of numbers (a table row, e.g. in [SHAPE])? */
static int is_table_row(const char *s)
{
    const char *p = s;
    int words = 0;
    for (;;) {
        char word[128];
        size_t n = 0;
        double v;
        while (*p == ' ' || *p == '\t') {
            p++;
        }
        if (*p == '\0' || is_comment_char(*p)) {
            break;
        }
        while (*p != '\0' && *p != ' ' && *p != '\t' && !is_comment_char(*p)) {
            if (n + 1 >= sizeof word) {
                return 0;
            }
            word[n++] = *p++;
        }
        word[n] = '\0';
        if (parse_number(word, &v) != 0) {
            return 0;
        }
        words++;
    }
    return words > 0;
}

static int add_entry(tir_text *t, const char *section, const char *key, const char *raw,
                     int quoted, unsigned long line)
{
    entry *x;
    if (t->n == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 256;
        entry *e = realloc(t->e, cap * sizeof *e);
        if (e == NULL) {
            return -1;
        }
        t->e = e;
        t->cap = cap;
    }
    x = &t->e[t->n];
    x->section = dup_upper(section, 1);
    x->key = dup_upper(key, 1);
    x->raw = dup_upper(raw, 0);
    x->quoted = quoted;
    x->line = line;
    if (x->section == NULL || x->key == NULL || x->raw == NULL) {
        free(x->section);
        free(x->key);
        free(x->raw);
        return -1;
    }
    t->n++;
    return 0;
}

static int add_section(tir_text *t, const char *name, unsigned long line)
{
    if (t->ns == t->caps) {
        size_t cap = t->caps ? 2 * t->caps : 32;
        section_rec *s = realloc(t->s, cap * sizeof *s);
        if (s == NULL) {
            return -1;
        }
        t->s = s;
        t->caps = cap;
    }
    t->s[t->ns].name = dup_upper(name, 1);
    if (t->s[t->ns].name == NULL) {
        return -1;
    }
    t->s[t->ns].line = line;
    t->ns++;
    return 0;
}

/* First word of s if it is an identifier (for messages), else "". */
static void first_key(const char *s, char *word, size_t len)
{
    size_t kn = 0;
    if (isalpha((unsigned char)s[0]) || s[0] == '_') {
        while ((isalnum((unsigned char)s[kn]) || s[kn] == '_') && kn + 1 < len) {
            word[kn] = s[kn];
            kn++;
        }
    }
    word[kn] = '\0';
}

static int parse_text(FILE *f, tir_text *t, const err_ctx *e)
{
    char *buf = NULL;
    size_t cap = 0;
    ssize_t got;
    char section[128] = "";
    int in_section = 0;
    unsigned long lineno = 0;
    int rc = 0;

    errno = 0;
    while ((got = getline(&buf, &cap, f)) != -1) {
        char *s;
        lineno++;
        if (memchr(buf, '\0', (size_t)got) != NULL) {
            rc = fail(e, lineno, NULL, "binary data (NUL byte): not a text .tir file");
            break;
        }
        rtrim(buf);
        s = buf;
        if (lineno == 1 && (unsigned char)s[0] == 0xEF && (unsigned char)s[1] == 0xBB &&
            (unsigned char)s[2] == 0xBF) {
            s += 3;  /* UTF-8 byte order mark */
        }
        s = skip_ws(s);
        if (*s == '\0' || is_comment_char(*s)) {
            continue;
        }
        if (*s == '[') {
            char *close = strchr(s, ']');
            char name[128];
            char *nm;
            size_t n;
            const section_rec *prev;
            if (close == NULL || close == s + 1 || !rest_is_empty(close + 1)) {
                rc = fail(e, lineno, NULL, "malformed section header '%s'", s);
                break;
            }
            n = (size_t)(close - (s + 1));
            if (n >= sizeof name) {
                rc = fail(e, lineno, NULL, "malformed section header '%s'", s);
                break;
            }
            memcpy(name, s + 1, n);
            name[n] = '\0';
            rtrim(name);
            nm = skip_ws(name);
            if (*nm == '\0') {
                rc = fail(e, lineno, NULL, "malformed section header '%s'", s);
                break;
            }
            for (n = 0; nm[n] != '\0'; n++) {
                section[n] = (char)toupper((unsigned char)nm[n]);
            }
            section[n] = '\0';
            /* a section may appear twice (some exporters repeat table
             * sections): its keys are merged, a repeated key is an error;
             * the first header's line is the section's line */
            prev = find_section(t, section);
            if (prev == NULL && add_section(t, section, lineno) != 0) {
                rc = fail(e, lineno, NULL, "out of memory");
                break;
            }
            in_section = 1;
            continue;
        }
        if (*s == '{') {
            continue;  /* table column names, e.g. {pen fz} */
        }
        if (strchr(s, '=') != NULL && (isalpha((unsigned char)*s) || *s == '_')) {
            char *key = NULL;
            char *value = NULL;
            int quoted = 0;
            const char *why = NULL;
            char keycopy[64];
            size_t i;
            first_key(s, keycopy, sizeof keycopy);
            if (split_assignment(s, &key, &value, &quoted, &why) != 0) {
                rc = fail(e, lineno, keycopy, "%s", why);
                break;
            }
            if (!in_section) {
                rc = fail(e, lineno, key, "key outside any [SECTION]");
                break;
            }
            for (i = 0; i < t->n; i++) {
                if (strcmp(t->e[i].section, section) == 0 && ieq(t->e[i].key, key)) {
                    break;
                }
            }
            if (i < t->n) {
                rc = fail(e, lineno, t->e[i].key, "duplicate key (first on line %lu)", t->e[i].line);
                break;
            }
            if (add_entry(t, section, key, value, quoted, lineno) != 0) {
                rc = fail(e, lineno, key, "out of memory");
                break;
            }
            continue;
        }
        if (is_table_row(s)) {
            if (!in_section) {
                rc = fail(e, lineno, NULL, "table row outside any [SECTION]");
                break;
            }
            continue;
        }
        rc = fail(e, lineno, NULL, "cannot read line '%.60s' (expected KEY = value)", s);
        break;
    }
    if (rc == 0 && ferror(f)) {
        rc = fail(e, lineno, NULL, "read error: %s", strerror(errno != 0 ? errno : EIO));
    }
    t->nlines = lineno;
    free(buf);
    return rc;
}

/* FITTYP when the file has none: from PROPERTY_FILE_FORMAT. */
static const struct {
    const char *format;
    int fittyp;
} FITTYP_FROM_FORMAT[] = {
    { "PAC2002", 6 }, { "MF_05", 5 }, { "MF05", 5 }, { "MF_52", 6 }, { "MF52", 6 },
    { "MF_61", 61 }, { "MF61", 61 }, { "MF_62", 62 }, { "MF62", 62 },
};

/* Largest magnitudes the fixed-point formats hold with margin, checked in
 * both builds so that a file means the same in each (grip_types.h). */
#define LIMIT_QS 32767.0
#define LIMIT_QL 8.3e6

static int is_supported_fittyp(double v)
{
    return v == 5.0 || v == 6.0 || v == 21.0 || v == 61.0 || v == 62.0;
}

/* A value with blanks around it removed, upper case, into buf. */
static void clean_upper(const char *raw, char *buf, size_t len)
{
    size_t n = 0;
    const char *p = raw;
    while (*p == ' ' || *p == '\t') {
        p++;
    }
    while (*p != '\0' && n + 1 < len) {
        buf[n++] = (char)toupper((unsigned char)*p++);
    }
    while (n > 0 && (buf[n - 1] == ' ' || buf[n - 1] == '\t')) {
        n--;
    }
    buf[n] = '\0';
}

#define IDX(field) GRIP_TIR_I_##field

static int validate(const tir_text *t, const grip_tir_options *opts, grip_tir_values *out,
                    const err_ctx *e)
{
    static const struct {
        int i;
        int strict;   /* 1: must be > 0, 0: must be >= 0 */
    } positive[] = {
        { IDX(fnomin), 1 },
        { IDX(unloaded_radius), 1 },
        { IDX(longvl), 1 },
        { IDX(vxlow), 1 },
        { IDX(width), 0 },
        { IDX(inflpres), 0 },
        { IDX(nompres), 0 },
        { IDX(vertical_stiffness), 0 },
        { IDX(longitudinal_stiffness), 0 },
        { IDX(lateral_stiffness), 0 },
        { IDX(presmin), 0 },
        { IDX(presmax), 0 },
        { IDX(fzmin), 0 },
        { IDX(fzmax), 0 },
    };
    static const struct {
        int lo;
        int hi;
    } ranges[] = {
        { IDX(fzmin), IDX(fzmax) },
        { IDX(kpumin), IDX(kpumax) },
        { IDX(alpmin), IDX(alpmax) },
        { IDX(cammin), IDX(cammax) },
        { IDX(presmin), IDX(presmax) },
    };
    double unit[Q_COUNT];
    double factor[DIM_STIFFNESS + 1];
    const entry *x;
    char word[64];
    size_t k;
    int q;
    int i;

    /* units */
    for (q = 0; q < Q_COUNT; q++) {
        unit[q] = 1.0;
        x = find_entry(t, "UNITS", QUANTITIES[q].key);
        if (x != NULL) {
            const unit_name *u;
            char name[64];
            clean_upper(x->raw, name, sizeof name);
            for (u = QUANTITIES[q].units; u->name != NULL; u++) {
                if (ieq(u->name, name)) {
                    break;
                }
            }
            if (u->name == NULL) {
                return fail(e, x->line, QUANTITIES[q].key, "unit '%s' cannot be converted to SI", x->raw);
            }
            unit[q] = u->factor;
        }
    }
    if (find_entry(t, "UNITS", "PRESSURE") == NULL) {
        unit[Q_PRESSURE] = unit[Q_FORCE] / (unit[Q_LENGTH] * unit[Q_LENGTH]);
    }
    factor[DIM_NONE] = 1.0;
    factor[DIM_LENGTH] = unit[Q_LENGTH];
    factor[DIM_FORCE] = unit[Q_FORCE];
    factor[DIM_ANGLE] = unit[Q_ANGLE];
    factor[DIM_PRESSURE] = unit[Q_PRESSURE];
    factor[DIM_SPEED] = unit[Q_LENGTH] / unit[Q_TIME];
    factor[DIM_STIFFNESS] = unit[Q_FORCE] / unit[Q_LENGTH];

    /* FITTYP */
    memset(out, 0, sizeof *out);
    x = find_entry(t, "MODEL", "FITTYP");
    if (x != NULL) {
        double v;
        if (x->quoted || parse_number(x->raw, &v) != 0) {
            return fail(e, x->line, "FITTYP", "value '%s' is not a number", x->raw);
        }
        if (!is_supported_fittyp(v)) {
            return fail(e, x->line, "FITTYP",
                        "unsupported Magic Formula version %s (supported: 5, 6, 21, 61, 62)", x->raw);
        }
        out->fittyp = (int32_t)v;
    } else {
        const entry *fmt = find_entry(t, "MODEL", "PROPERTY_FILE_FORMAT");
        int guess = 0;
        if (fmt != NULL) {
            clean_upper(fmt->raw, word, sizeof word);
            for (k = 0; k < sizeof FITTYP_FROM_FORMAT / sizeof FITTYP_FROM_FORMAT[0]; k++) {
                if (strcmp(FITTYP_FROM_FORMAT[k].format, word) == 0) {
                    guess = FITTYP_FROM_FORMAT[k].fittyp;
                }
            }
        }
        if (guess == 0) {
            return fail(e, missing_line(t, "MODEL"), "FITTYP",
                        "missing required key in [MODEL] (and no PROPERTY_FILE_FORMAT "
                        "that names the version: PAC2002, MF_05, MF_52, MF_61, MF_62)");
        }
        out->fittyp = guess;
    }

    /* TYRESIDE */
    out->tyreside = 1;
    x = find_entry(t, "MODEL", "TYRESIDE");
    if (x != NULL) {
        clean_upper(x->raw, word, sizeof word);
        if (strcmp(word, "RIGHT") == 0) {
            out->tyreside = -1;
        } else if (strcmp(word, "LEFT") == 0 || strcmp(word, "UNKNOWN") == 0 ||
                   strcmp(word, "SYMMETRIC") == 0 || word[0] == '\0') {
            out->tyreside = 1;
        } else {
            return fail(e, x->line, "TYRESIDE", "unknown tyre side '%s' (LEFT, RIGHT, UNKNOWN)", x->raw);
        }
    }
    /* the mounting side: as fitted unless the caller names one */
    {
        grip_tir_side mount = (opts != NULL) ? opts->side : GRIP_TIR_SIDE_FILE;
        if (mount == GRIP_TIR_SIDE_FILE) {
            mount = (out->tyreside == -1) ? GRIP_TIR_SIDE_RIGHT : GRIP_TIR_SIDE_LEFT;
        }
        out->options = (mount == GRIP_TIR_SIDE_RIGHT) ? GRIP_MF_OPT_RIGHT_SIDE : 0u;
    }

    /* coefficients */
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        double v;
        double xsi;
        x = find_entry(t, COEFS[i].section, COEFS[i].key);
        if (x == NULL) {
            if (COEFS[i].required) {
                return fail(e, missing_line(t, COEFS[i].section), COEFS[i].key,
                            "missing required key in [%s]", COEFS[i].section);
            }
            out->v[i] = COEFS[i].def;   /* defaults are SI already */
            out->line[i] = 0;
            continue;
        }
        if (x->quoted || parse_number(x->raw, &v) != 0) {
            return fail(e, x->line, COEFS[i].key, "value '%s' is not a number", x->raw);
        }
        xsi = v * factor[dimension_of(COEFS[i].key)];
        if (!isfinite(xsi)) {
            return fail(e, x->line, COEFS[i].key, "value overflows after unit conversion");
        }
        out->v[i] = xsi;
        out->line[i] = x->line;
    }

    /* physical sense */
    for (k = 0; k < sizeof positive / sizeof positive[0]; k++) {
        int j = positive[k].i;
        double v = out->v[j];
        if (positive[k].strict ? !(v > 0.0) : !(v >= 0.0)) {
            return fail(e, out->line[j] ? out->line[j] : missing_line(t, COEFS[j].section),
                        COEFS[j].key, "value %g must be %s", v, positive[k].strict ? "> 0" : ">= 0");
        }
    }
    for (k = 0; k < sizeof ranges / sizeof ranges[0]; k++) {
        int lo = ranges[k].lo;
        int hi = ranges[k].hi;
        /* only when both ends were given */
        if (out->line[lo] != 0 && out->line[hi] != 0 && !(out->v[lo] < out->v[hi])) {
            return fail(e, out->line[hi], COEFS[hi].key, "value %g must be greater than %s = %g",
                        out->v[hi], COEFS[lo].key, out->v[lo]);
        }
    }
    if (out->fittyp >= 61 && !(out->v[IDX(nompres)] > 0.0)) {
        int j = IDX(nompres);
        return fail(e, out->line[j] ? out->line[j] : missing_line(t, COEFS[j].section), COEFS[j].key,
                    "FITTYP %d needs a nominal pressure > 0 (got %g)", (int)out->fittyp, out->v[j]);
    }

    /* fixed-point range (both builds) */
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        int ql = COEFS[i].fmt == FMT_QL;
        double lim = ql ? LIMIT_QL : LIMIT_QS;
        if (!(fabs(out->v[i]) < lim)) {
            return fail(e, out->line[i] ? out->line[i] : missing_line(t, COEFS[i].section),
                        COEFS[i].key,
                        "value %g (SI) does not fit the fixed-point format %s = %s (|v| < %g)",
                        out->v[i], ql ? "QL" : "QS", ql ? "Q23.8" : "Q15.16", lim);
        }
    }
    return 0;
}

int grip_tir_parse(const char *path, const grip_tir_options *opts,
                   grip_tir_values *out, char *err, size_t errlen)
{
    err_ctx e;
    tir_text text;
    grip_tir_values t;
    FILE *f;
    int rc;
    e.path = (path != NULL) ? path : "(null)";
    e.err = err;
    e.errlen = errlen;
    if (path == NULL || out == NULL) {
        return fail(&e, 0, NULL, "no file or no output given");
    }
    if (opts != NULL && opts->side != GRIP_TIR_SIDE_FILE && opts->side != GRIP_TIR_SIDE_LEFT &&
        opts->side != GRIP_TIR_SIDE_RIGHT) {
        return fail(&e, 0, "TYRESIDE", "invalid side option %d", (int)opts->side);
    }
    f = fopen(path, "rb");
    if (f == NULL) {
        return fail(&e, 0, NULL, "cannot open: %s", strerror(errno));
    }
    memset(&text, 0, sizeof text);
    rc = parse_text(f, &text, &e);
    fclose(f);
    if (rc == 0 && text.nlines == 0) {
        rc = fail(&e, 0, NULL, "empty file");
    }
    if (rc == 0) {
        rc = validate(&text, opts, &t, &e);
    }
    text_free(&text);
    if (rc != 0) {
        return -1;
    }
    *out = t;
    return 0;
}

/* ------------------------------------------------------------------ */
/* Conversion to grip_real_t.                                          */

int grip_tir_to_real(double v, int is_ql, grip_real_t *r)
{
#if GRIP_ARITH_FIXED
    double scaled = v * (is_ql ? (double)(1L << GRIP_QL_BITS) : (double)(1L << GRIP_QS_BITS));
    double rounded = (scaled >= 0.0) ? floor(scaled + 0.5) : -floor(-scaled + 0.5);
    if (!(rounded <= (double)INT32_MAX && rounded >= -(double)INT32_MAX)) {
        return -1;
    }
    *r = (grip_real_t)rounded;
    return 0;
#else
    (void)is_ql;
    if (!(fabs(v) <= 3.4028234663852886e38)) {
        return -1;
    }
    *r = (grip_real_t)v;
    return 0;
#endif
}

int grip_tir_convert(const char *path, const grip_tir_values *in,
                     grip_mf_params *out, char *err, size_t errlen)
{
    err_ctx e;
    grip_mf_params p;
    int i;
    e.path = (path != NULL) ? path : "(values)";
    e.err = err;
    e.errlen = errlen;
    if (in == NULL || out == NULL) {
        return fail(&e, 0, NULL, "no input or no output given");
    }
    memset(&p, 0, sizeof p);
    p.fittyp = in->fittyp;
    p.tyreside = in->tyreside;
    p.options = in->options;
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        grip_real_t r;
        if (grip_tir_to_real(in->v[i], COEFS[i].fmt == FMT_QL, &r) != 0) {
#if GRIP_ARITH_FIXED
            return fail(&e, in->line[i], COEFS[i].key,
                        "value %g (SI) is not representable in the fixed format %s (|v| < %g)",
                        in->v[i], (COEFS[i].fmt == FMT_QL) ? "QL = Q23.8" : "QS = Q15.16",
                        (COEFS[i].fmt == FMT_QL) ? 8388608.0 : 32768.0);
#else
            return fail(&e, in->line[i], COEFS[i].key,
                        "value %g (SI) is not representable in single precision", in->v[i]);
#endif
        }
        memcpy((char *)&p + COEFS[i].offset, &r, sizeof r);
    }
    *out = p;
    return 0;
}

int grip_tir_read_opts(const char *path, const grip_tir_options *opts,
                       grip_mf_params *out, char *err, size_t errlen)
{
    grip_tir_values t;
    if (grip_tir_parse(path, opts, &t, err, errlen) != 0) {
        return -1;
    }
    return grip_tir_convert(path, &t, out, err, errlen);
}

int grip_tir_read(const char *path, grip_mf_params *out, char *err, size_t errlen)
{
    return grip_tir_read_opts(path, NULL, out, err, errlen);
}

/* ------------------------------------------------------------------ */
/* Table access.                                                       */

int grip_tir_coef_count(void)
{
    return GRIP_TIR_NCOEF;
}

const char *grip_tir_coef_key(int i)
{
    return (i >= 0 && i < GRIP_TIR_NCOEF) ? COEFS[i].key : NULL;
}

const char *grip_tir_coef_section(int i)
{
    return (i >= 0 && i < GRIP_TIR_NCOEF) ? COEFS[i].section : NULL;
}

int grip_tir_coef_is_ql(int i)
{
    return (i >= 0 && i < GRIP_TIR_NCOEF) ? (COEFS[i].fmt == FMT_QL) : 0;
}

int grip_tir_coef_index(const char *key)
{
    int i;
    if (key == NULL) {
        return -1;
    }
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        if (ieq(COEFS[i].key, key)) {
            return i;
        }
    }
    return -1;
}

double grip_tir_from_real(grip_real_t r, int is_ql)
{
#if GRIP_ARITH_FIXED
    return (double)r / (is_ql ? (double)(1L << GRIP_QL_BITS) : (double)(1L << GRIP_QS_BITS));
#else
    (void)is_ql;
    return (double)r;
#endif
}

double grip_tir_coef_get(const grip_mf_params *p, int i)
{
    grip_real_t r;
    if (p == NULL || i < 0 || i >= GRIP_TIR_NCOEF) {
        return 0.0;
    }
    memcpy(&r, (const char *)p + COEFS[i].offset, sizeof r);
    return grip_tir_from_real(r, COEFS[i].fmt == FMT_QL);
}
