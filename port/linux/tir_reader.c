/*
 * tir_reader.c - host-side .tir reader (see tir_reader.h and docs/tools.md).
 *
 * The file is read whole first, at most GRIP_TIR_SIZE_MAX bytes, and its
 * bytes checked (no NUL, no line longer than GRIP_TIR_LINE_MAX); then line
 * by line (LF or CRLF). A line is one of:
 *   blank, or a comment starting with '$' or '!' (after optional blanks);
 *   [SECTION]            a section header (optionally followed by a comment);
 *   {text}               a table column header (ignored);
 *   KEY = value          value: a number, a quoted string ('..' or ".."),
 *                        a bare word, or nothing (an empty value); '$' or
 *                        '!' starts an inline comment;
 *   numbers only         a row of a table section such as [SHAPE] (ignored).
 * Anything else is an error. Coefficients of GRIP_MF_COEFFICIENTS are taken
 * only from their own section; the keys of tir_rules.h are known and not
 * read; any other key of a known section is a warning. The [UNITS] section
 * may stand anywhere: the conversion to SI is applied after the whole file
 * is read. The order of the checks is that of
 * tools/grip_tools/reference/tir.py, so both readers report the same first
 * error and the same warnings.
 */
#include "tir_reader.h"
#include "tir_rules.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

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
    { "lb", 0.45359237 }, { "lbs", 0.45359237 }, { "pound_mass", 0.45359237 }, { "lbm", 0.45359237 },
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
    unsigned flags;            /* GRIP_TIR_* */
    grip_tir_warn_fn warn;     /* NULL: stderr */
    void *warn_ctx;
    unsigned *nwarn;           /* counts the warnings given, or NULL */
} err_ctx;

static int fail(const err_ctx *e, unsigned long line, const char *key, const char *fmt, ...)
{
    char what[512];
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

/* A warning "FILE:LINE: KEY: what" to the caller's function (default:
 * "warning: ..." on stderr); under GRIP_TIR_STRICT the error
 * "FILE:LINE: KEY: what (refused: strict mode)" instead. 0 or -1. */
static int warn(const err_ctx *e, unsigned long line, const char *key, const char *fmt, ...)
{
    char what[384];
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if ((e->flags & GRIP_TIR_STRICT) != 0u) {
        return fail(e, line, key, "%s (refused: strict mode)", what);
    }
    snprintf(msg, sizeof msg, "%s:%lu: %s: %s", e->path, line, (key != NULL && key[0] != '\0') ? key : "-", what);
    if (e->warn != NULL) {
        e->warn(e->warn_ctx, msg);
    } else {
        fprintf(stderr, "warning: %s\n", msg);
    }
    if (e->nwarn != NULL) {
        (*e->nwarn)++;
    }
    return 0;
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

/* Reads the whole file, at most GRIP_TIR_SIZE_MAX bytes, into a buffer of
 * its own (*buf, *len; freed by the caller, also on error) and checks its
 * bytes line by line first: no NUL byte, no line longer than
 * GRIP_TIR_LINE_MAX. A device or a huge file (/dev/zero, a sparse 1 GiB
 * file) therefore ends after at most GRIP_TIR_SIZE_MAX + 1 bytes. */
static int read_bounded(FILE *f, char **buf, size_t *len, const err_ctx *e)
{
    struct stat st;
    size_t cap = 0;
    size_t n = 0;
    size_t lim;
    size_t i;
    size_t start = 0;
    unsigned long line = 1;
    const size_t most = (size_t)GRIP_TIR_SIZE_MAX + 1u;
    char *b = NULL;
    *buf = NULL;
    *len = 0;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        return fail(e, 0, NULL, "cannot open: %s", strerror(EISDIR));
    }
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > (off_t)GRIP_TIR_SIZE_MAX) {
        return fail(e, 0, NULL, "larger than %ld bytes: not a .tir file", GRIP_TIR_SIZE_MAX);
    }
    errno = 0;
    for (;;) {
        size_t got;
        if (n == cap) {
            size_t ncap = (cap == 0) ? 65536u : 2u * cap;
            char *nb;
            if (ncap > most) {
                ncap = most;
            }
            if (ncap == cap) {
                break;      /* GRIP_TIR_SIZE_MAX + 1 bytes read: too large */
            }
            nb = realloc(b, ncap + 1u);
            if (nb == NULL) {
                *buf = b;
                return fail(e, 0, NULL, "out of memory");
            }
            b = nb;
            cap = ncap;
        }
        got = fread(b + n, 1, cap - n, f);
        n += got;
        if (n < cap) {
            if (ferror(f)) {
                *buf = b;
                return fail(e, line, NULL, "read error: %s", strerror(errno != 0 ? errno : EIO));
            }
            break;          /* end of file */
        }
    }
    *buf = b;
    *len = n;
    lim = (n > (size_t)GRIP_TIR_SIZE_MAX) ? (size_t)GRIP_TIR_SIZE_MAX : n;
    for (i = 0; i < lim; i++) {
        char c = b[i];
        if (c == '\n') {
            line++;
            start = i + 1u;
            continue;
        }
        if (c == '\0') {
            return fail(e, line, NULL, "NUL byte at byte offset %lu (byte %lu of the line): not a text .tir file",
                        (unsigned long)i, (unsigned long)(i - start + 1u));
        }
        if (i - start >= (size_t)GRIP_TIR_LINE_MAX) {
            return fail(e, line, NULL, "line longer than %d bytes (at byte offset %lu): not a .tir file",
                        GRIP_TIR_LINE_MAX, (unsigned long)start);
        }
    }
    if (n > (size_t)GRIP_TIR_SIZE_MAX) {
        return fail(e, 0, NULL, "larger than %ld bytes: not a .tir file", GRIP_TIR_SIZE_MAX);
    }
    return 0;
}

/* Parses the checked bytes b[0..n) line by line (LF or CRLF). */
static int parse_text(const char *b, size_t n, tir_text *t, const err_ctx *e)
{
    char buf[GRIP_TIR_LINE_MAX + 1];
    char section[128] = "";
    int in_section = 0;
    unsigned long lineno = 0;
    unsigned long rows = 0;
    size_t pos = 0;
    int rc = 0;

    while (pos < n) {
        char *s;
        const char *nl = memchr(b + pos, '\n', n - pos);
        size_t len = (nl != NULL) ? (size_t)(nl - (b + pos)) : n - pos;
        lineno++;
        memcpy(buf, b + pos, len);   /* len <= GRIP_TIR_LINE_MAX: read_bounded */
        buf[len] = '\0';
        pos += len + 1u;
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
            size_t k;
            const section_rec *prev;
            if (close == NULL || close == s + 1 || !rest_is_empty(close + 1)) {
                rc = fail(e, lineno, NULL, "malformed section header '%.60s'", s);
                break;
            }
            k = (size_t)(close - (s + 1));
            if (k >= sizeof name) {
                rc = fail(e, lineno, NULL, "malformed section header '%.60s'", s);
                break;
            }
            memcpy(name, s + 1, k);
            name[k] = '\0';
            rtrim(name);
            nm = skip_ws(name);
            if (*nm == '\0') {
                rc = fail(e, lineno, NULL, "malformed section header '%.60s'", s);
                break;
            }
            for (k = 0; nm[k] != '\0'; k++) {
                section[k] = (char)toupper((unsigned char)nm[k]);
            }
            section[k] = '\0';
            /* a section may appear twice (some exporters repeat table
             * sections): its keys are merged, a repeated key is an error;
             * the first header's line is the section's line */
            prev = find_section(t, section);
            if (prev == NULL) {
                if (t->ns >= (size_t)GRIP_TIR_SECTIONS_MAX) {
                    rc = fail(e, lineno, NULL, "more than %d sections: not a .tir file", GRIP_TIR_SECTIONS_MAX);
                    break;
                }
                if (add_section(t, section, lineno) != 0) {
                    rc = fail(e, lineno, NULL, "out of memory");
                    break;
                }
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
            if (t->n >= (size_t)GRIP_TIR_KEYS_MAX) {
                rc = fail(e, lineno, NULL, "more than %d keys: not a .tir file", GRIP_TIR_KEYS_MAX);
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
            if (++rows > (unsigned long)GRIP_TIR_ROWS_MAX) {
                rc = fail(e, lineno, NULL, "more than %d table rows: not a .tir file", GRIP_TIR_ROWS_MAX);
                break;
            }
            continue;
        }
        rc = fail(e, lineno, NULL, "cannot read line '%.60s' (expected KEY = value)", s);
        break;
    }
    t->nlines = lineno;
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

/* FITTYP values of MF-Tyre and MFeval and the version grip evaluates:
 * 5 (MF-Tyre 5.0), 6 (MF 5.2 / PAC2002), 21 (MF-Tyre 5.2), 52 (MF 5.2, as
 * later MF-Tool exports write it; stored as 21), 61, 62 (MF 6.1, 6.2).
 * 0 if unsupported. */
static int32_t fittyp_model(double v)
{
    if (v == 5.0 || v == 6.0 || v == 21.0 || v == 61.0 || v == 62.0) {
        return (int32_t)v;
    }
    if (v == 52.0) {
        return 21;
    }
    return 0;
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

/* `KEY =` with nothing after it (a quoted '' is a value: a string). */
static int is_empty(const entry *x)
{
    return !x->quoted && x->raw[0] == '\0';
}

/* ---- the tables of tir_rules.h ----------------------------------------- */

#define X_SECTION(name) #name,
static const char *const KNOWN_SECTIONS[] = { GRIP_TIR_SECTIONS(X_SECTION) };
#undef X_SECTION

#define X_READKEY(section, key) { #section, #key },
static const struct {
    const char *section;
    const char *key;
} READ_KEYS[] = { GRIP_TIR_READ_KEYS(X_READKEY) };
#undef X_READKEY

#define X_KNOWN(key) #key,
static const char *const KNOWN_KEYS[] = { GRIP_TIR_KNOWN_KEYS(X_KNOWN) };
#undef X_KNOWN

typedef enum { RK_VAL, RK_VAL0, RK_ABS } range_kind;

#define X_RANGE(pattern, kind, lo, hi, what) { pattern, RK_##kind, lo, hi, what },
static const struct {
    const char *pattern;
    range_kind kind;
    double lo;
    double hi;
    const char *what;
} RANGES[] = { GRIP_TIR_RANGES(X_RANGE) };
#undef X_RANGE

#define N_OF(a) (sizeof(a) / sizeof((a)[0]))

static int section_known(const char *name)
{
    size_t i;
    for (i = 0; i < N_OF(KNOWN_SECTIONS); i++) {
        if (strcmp(KNOWN_SECTIONS[i], name) == 0) {
            return 1;
        }
    }
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        if (strcmp(COEFS[i].section, name) == 0) {
            return 1;
        }
    }
    return 0;
}

/* The section grip reads KEY from, or NULL if grip does not read it. */
static const char *read_section(const char *key)
{
    size_t i;
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        if (strcmp(COEFS[i].key, key) == 0) {
            return COEFS[i].section;
        }
    }
    for (i = 0; i < N_OF(READ_KEYS); i++) {
        if (strcmp(READ_KEYS[i].key, key) == 0) {
            return READ_KEYS[i].section;
        }
    }
    return NULL;
}

static int key_known(const char *key)
{
    size_t i;
    for (i = 0; i < N_OF(KNOWN_KEYS); i++) {
        if (strcmp(KNOWN_KEYS[i], key) == 0) {
            return 1;
        }
    }
    return 0;
}

/* Levenshtein distance of two keys shorter than 64 characters (else 99). */
static int edit_distance(const char *a, const char *b)
{
    int row[64];
    size_t na = strlen(a);
    size_t nb = strlen(b);
    size_t i;
    size_t j;
    if (na >= 64 || nb >= 64) {
        return 99;
    }
    for (j = 0; j <= nb; j++) {
        row[j] = (int)j;
    }
    for (i = 1; i <= na; i++) {
        int diag = row[0];
        row[0] = (int)i;
        for (j = 1; j <= nb; j++) {
            int up = row[j];
            int best = diag + (a[i - 1] != b[j - 1]);
            if (up + 1 < best) {
                best = up + 1;
            }
            if (row[j - 1] + 1 < best) {
                best = row[j - 1] + 1;
            }
            diag = up;
            row[j] = best;
        }
    }
    return row[nb];
}

/* The nearest key grip knows (distance <= 2, KEY of 4 or more
 * characters; the first of equals in table order), or NULL. */
static const char *nearest_key(const char *key)
{
    const char *best = NULL;
    int bd = 3;
    size_t i;
    if (strlen(key) < 4) {
        return NULL;
    }
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        int d = edit_distance(key, COEFS[i].key);
        if (d < bd) {
            bd = d;
            best = COEFS[i].key;
        }
    }
    for (i = 0; i < N_OF(READ_KEYS); i++) {
        int d = edit_distance(key, READ_KEYS[i].key);
        if (d < bd) {
            bd = d;
            best = READ_KEYS[i].key;
        }
    }
    for (i = 0; i < N_OF(KNOWN_KEYS); i++) {
        int d = edit_distance(key, KNOWN_KEYS[i]);
        if (d < bd) {
            bd = d;
            best = KNOWN_KEYS[i];
        }
    }
    return best;
}

/* Every key in file order: one grip reads but in another section, or one
 * no MF-Tyre file has in a known section, is a warning (an error under
 * GRIP_TIR_STRICT). Keys of unknown (vendor) sections are not checked,
 * except for keys grip reads. */
static int check_keys(const tir_text *t, const err_ctx *e)
{
    size_t i;
    for (i = 0; i < t->n; i++) {
        const entry *x = &t->e[i];
        const char *own = read_section(x->key);
        int known_section = section_known(x->section);
        int rc = 0;
        if (own != NULL) {
            if (strcmp(own, x->section) != 0 && !key_known(x->key)) {
                rc = warn(e, x->line, x->key, "grip reads %s from [%s], not from %s[%s]: this value is ignored",
                          x->key, own, known_section ? "" : "the unknown section ", x->section);
            }
        } else if (known_section && !key_known(x->key)) {
            const char *near = nearest_key(x->key);
            int ci = (near != NULL) ? grip_tir_coef_index(near) : -1;
            if (ci >= 0 && strcmp(COEFS[ci].section, x->section) == 0 &&
                find_entry(t, COEFS[ci].section, near) == NULL) {
                /* a misspelling of a coefficient the file does not give:
                 * its value would be lost and the default read instead */
                return fail(e, x->line, x->key,
                            "unknown key in [%s]: a misspelling of %s? The file does not give %s, which would "
                            "take its default %g: rename the key, or give %s",
                            x->section, near, near, COEFS[ci].def, near);
            }
            if (near != NULL) {
                rc = warn(e, x->line, x->key, "unknown key in [%s]: ignored (did you mean %s?)", x->section, near);
            } else {
                rc = warn(e, x->line, x->key, "unknown key in [%s]: ignored", x->section);
            }
        }
        if (rc != 0) {
            return rc;
        }
    }
    return 0;
}

/* USE_MODE (MF-Tyre): units digit the slip calculation (0 Fz only, 1 Fx/My,
 * 2 Fy/Mx/Mz, 3 uncombined, 4 combined, 5 combined + turn slip), tens digit
 * the dynamics (0 steady state, 1 and 2 relaxation, 3 rigid ring), hundreds
 * digit the road contact (0..5); MF-Tyre 5.x: negative = mirrored. grip
 * evaluates the steady-state Magic Formula at the contact point, so the
 * dynamics and contact digits do not change what it computes (relaxation
 * is lib/relax, applied by the caller); of the slip digits it implements 4
 * (grip_mf_eval) and, for a caller that evaluates pure slip, 3
 * (grip_mf_eval_pure). */
static int check_use_mode(const entry *x, grip_tir_values *out, const err_ctx *e)
{
    double v;
    int32_t m;
    int slip;
    if (x->quoted || parse_number(x->raw, &v) != 0 || v != floor(v)) {
        return fail(e, x->line, "USE_MODE", "value '%s' is not an integer", x->raw);
    }
    if (v < 0.0) {
        return fail(e, x->line, "USE_MODE",
                    "%s: a negative USE_MODE mirrors the tyre (MF-Tyre 5.x); grip mounts a tyre by TYRESIDE "
                    "and the side option (--side): write USE_MODE = %g and give the side", x->raw, -v);
    }
    if (v > 999.0) {
        return fail(e, x->line, "USE_MODE", "%s is not a USE_MODE of MF-Tyre (at most three digits)", x->raw);
    }
    m = (int32_t)v;
    if (m / 100 > 5) {
        return fail(e, x->line, "USE_MODE", "%d: hundreds digit %d is not a road contact of MF-Tyre (0..5)",
                    (int)m, (int)(m / 100));
    }
    if ((m / 10) % 10 > 3) {
        return fail(e, x->line, "USE_MODE",
                    "%d: tens digit %d is not a dynamics mode of MF-Tyre (0 steady state, 1 and 2 relaxation, "
                    "3 rigid ring)", (int)m, (int)((m / 10) % 10));
    }
    slip = (int)(m % 10);
    switch (slip) {
    case 0:
        return fail(e, x->line, "USE_MODE", "%d asks for Fz only, no Magic Formula forces; grip evaluates Fx, Fy "
                    "and Mz (USE_MODE units digit 4)", (int)m);
    case 1:
    case 2:
        return fail(e, x->line, "USE_MODE", "%d asks for %s only; grip evaluates Fx, Fy and Mz together "
                    "(USE_MODE units digit 4)", (int)m, slip == 1 ? "Fx and My" : "Fy, Mx and Mz");
    case 3:
        if ((e->flags & GRIP_TIR_PURE_SLIP) == 0u) {
            return fail(e, x->line, "USE_MODE", "%d asks for uncombined forces (pure slip); this evaluation is "
                        "combined slip (USE_MODE units digit 4): evaluate pure slip (grip-tire --pure, "
                        "grip_mf_eval_pure) or write USE_MODE = %d", (int)m, (int)(m + 1));
        }
        break;
    case 4:
        break;
    case 5:
        return fail(e, x->line, "USE_MODE", "%d asks for combined slip with turn slip; grip takes turn slip per "
                    "call, not from the file (grip_mf_eval_ext with GRIP_MF_USE_TURN_SLIP, grip-tire --turn-slip): "
                    "write USE_MODE = %d and ask for it there", (int)m, (int)(m - 1));
    default:
        return fail(e, x->line, "USE_MODE", "%d: units digit %d is not a slip calculation of MF-Tyre (0..5)",
                    (int)m, slip);
    }
    out->use_mode = m;
    out->use_mode_line = x->line;
    return 0;
}

/* The plausibility range of coefficient i: index into RANGES or -1. */
static int range_of(int i)
{
    size_t r;
    for (r = 0; r < N_OF(RANGES); r++) {
        const char *p = RANGES[r].pattern;
        size_t n = strlen(p);
        if ((n > 0 && p[n - 1] == '*') ? strncmp(p, COEFS[i].key, n - 1) == 0 : strcmp(p, COEFS[i].key) == 0) {
            return (int)r;
        }
    }
    return -1;
}

static int check_ranges(const grip_tir_values *out, const err_ctx *e)
{
    int i;
    for (i = 0; i < GRIP_TIR_NCOEF; i++) {
        int r;
        double v = out->v[i];
        double lo;
        double hi;
        int ok;
        char range[96];
        if (out->line[i] == 0) {
            continue;   /* a default */
        }
        r = range_of(i);
        if (r < 0) {
            continue;
        }
        lo = RANGES[r].lo;
        hi = RANGES[r].hi;
        switch (RANGES[r].kind) {
        case RK_VAL0:
            ok = (v == 0.0) || (v >= lo && v <= hi);
            snprintf(range, sizeof range, "0 or [%g, %g]", lo, hi);
            break;
        case RK_ABS:
            ok = fabs(v) >= lo && fabs(v) <= hi;
            snprintf(range, sizeof range, "|v| in [%g, %g]", lo, hi);
            break;
        default:
            ok = v >= lo && v <= hi;
            snprintf(range, sizeof range, "[%g, %g]", lo, hi);
            break;
        }
        if (!ok) {
            return fail(e, out->line[i], COEFS[i].key,
                        "value %g (SI) is outside the plausible range %s (%s); --no-range-check accepts it",
                        v, range, RANGES[r].what);
        }
    }
    return 0;
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

    memset(out, 0, sizeof *out);

    /* keys grip does not know, or reads from another section */
    if (check_keys(t, e) != 0) {
        return -1;
    }

    /* units */
    for (q = 0; q < Q_COUNT; q++) {
        unit[q] = 1.0;
        x = find_entry(t, "UNITS", QUANTITIES[q].key);
        if (x != NULL && is_empty(x)) {
            if (warn(e, x->line, QUANTITIES[q].key, "empty value: read as the SI unit") != 0) {
                return -1;
            }
            x = NULL;
        }
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
                return fail(e, x->line, QUANTITIES[q].key, "unit '%.60s' cannot be converted to SI", x->raw);
            }
            unit[q] = u->factor;
        }
    }
    x = find_entry(t, "UNITS", "PRESSURE");
    if (x == NULL || is_empty(x)) {
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
    x = find_entry(t, "MODEL", "FITTYP");
    if (x != NULL && is_empty(x)) {
        if (warn(e, x->line, "FITTYP", "empty value: read as not given") != 0) {
            return -1;
        }
        x = NULL;
    }
    if (x != NULL) {
        double v;
        if (x->quoted || parse_number(x->raw, &v) != 0) {
            return fail(e, x->line, "FITTYP", "value '%.60s' is not a number", x->raw);
        }
        out->fittyp = fittyp_model(v);
        if (out->fittyp == 0) {
            return fail(e, x->line, "FITTYP",
                        "unsupported Magic Formula version %.60s (supported: 5, 6, 21, 52 = MF 5.x / PAC2002; "
                        "61, 62 = MF 6.1, 6.2)", x->raw);
        }
        out->fittyp_file = (int32_t)v;
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
        out->fittyp_file = 0;
    }

    /* USE_MODE */
    x = find_entry(t, "MODEL", "USE_MODE");
    if (x != NULL && is_empty(x)) {
        if (warn(e, x->line, "USE_MODE", "empty value: read as not given") != 0) {
            return -1;
        }
        x = NULL;
    }
    out->use_mode = -1;
    out->use_mode_line = 0;
    if (x != NULL && check_use_mode(x, out, e) != 0) {
        return -1;
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
            return fail(e, x->line, "TYRESIDE", "unknown tyre side '%.60s' (LEFT, RIGHT, UNKNOWN)", x->raw);
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
        if (x != NULL && is_empty(x)) {
            if (COEFS[i].required) {
                return fail(e, x->line, COEFS[i].key, "empty value for a required key");
            }
            if (warn(e, x->line, COEFS[i].key, "empty value: the default %g is used", COEFS[i].def) != 0) {
                return -1;
            }
            x = NULL;
        }
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
            return fail(e, x->line, COEFS[i].key, "value '%.60s' is not a number", x->raw);
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

    /* plausibility (tir_rules.h) */
    if ((e->flags & GRIP_TIR_NO_RANGE_CHECK) == 0u && check_ranges(out, e) != 0) {
        return -1;
    }
    return 0;
}

int grip_tir_parse(const char *path, const grip_tir_options *opts,
                   grip_tir_values *out, char *err, size_t errlen)
{
    err_ctx e;
    tir_text text;
    grip_tir_values t;
    unsigned nwarn = 0;
    char *buf = NULL;
    size_t len = 0;
    FILE *f;
    int rc;
    e.path = (path != NULL) ? path : "(null)";
    e.err = err;
    e.errlen = errlen;
    e.flags = (opts != NULL) ? opts->flags : 0u;
    e.warn = (opts != NULL) ? opts->warn : NULL;
    e.warn_ctx = (opts != NULL) ? opts->warn_ctx : NULL;
    e.nwarn = &nwarn;
    if (path == NULL || out == NULL) {
        return fail(&e, 0, NULL, "no file or no output given");
    }
    if (opts != NULL && opts->side != GRIP_TIR_SIDE_FILE && opts->side != GRIP_TIR_SIDE_LEFT &&
        opts->side != GRIP_TIR_SIDE_RIGHT) {
        return fail(&e, 0, "TYRESIDE", "invalid side option %d", (int)opts->side);
    }
    if ((e.flags & ~(unsigned)GRIP_TIR_FLAGS_ALL) != 0u) {
        return fail(&e, 0, NULL, "unknown option flags 0x%x", e.flags & ~(unsigned)GRIP_TIR_FLAGS_ALL);
    }
    f = fopen(path, "rb");
    if (f == NULL) {
        return fail(&e, 0, NULL, "cannot open: %s", strerror(errno));
    }
    memset(&text, 0, sizeof text);
    rc = read_bounded(f, &buf, &len, &e);
    fclose(f);
    if (rc == 0 && len == 0) {
        rc = fail(&e, 0, NULL, "empty file");
    }
    if (rc == 0) {
        rc = parse_text(buf, len, &text, &e);
    }
    free(buf);
    if (rc == 0) {
        rc = validate(&text, opts, &t, &e);
    }
    text_free(&text);
    if (rc != 0) {
        return -1;
    }
    t.nwarnings = nwarn;
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

void grip_tir_options_init(grip_tir_options *o)
{
    if (o != NULL) {
        memset(o, 0, sizeof *o);
        o->side = GRIP_TIR_SIDE_FILE;
    }
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
