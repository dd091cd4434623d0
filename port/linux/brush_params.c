/*
 * brush_params.c - parameter files of the brush-model family and the
 * grip-tire evaluation hook; see brush_params.h.
 */
#include "brush_params.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { FMT_QS, FMT_QL, FMT_INT };

typedef struct {
    const char *key;
    size_t offset;
    int fmt;
    double scale;      /* SI value * scale = struct unit (per kN fields: 1000) */
    double def;        /* default, SI (the dataclass defaults of brush.py)  */
} field_desc;

/* Field tables: struct order, formats and defaults as C_UNITS and the
 * dataclasses of tools/grip_tools/reference/brush.py (tests/unit/test_brush_params.c
 * checks that both agree). */
static const field_desc k_fiala_fields[] = {
    { "ky", offsetof(grip_fiala_params, ky), FMT_QL, 1.0, 60000.0 },
    { "mu", offsetof(grip_fiala_params, mu), FMT_QS, 1.0, 1.0 },
    { "l", offsetof(grip_fiala_params, l), FMT_QS, 1.0, 0.2 },
    { "fz_min", offsetof(grip_fiala_params, fz_min), FMT_QL, 1.0, 200.0 },
    { "fz_max", offsetof(grip_fiala_params, fz_max), FMT_QL, 1.0, 10000.0 },
    { "alpha_max", offsetof(grip_fiala_params, alpha_max), FMT_QS, 1.0, 0.6 },
};
static const field_desc k_brush_fields[] = {
    { "kx", offsetof(grip_brush_params, kx), FMT_QL, 1.0, 80000.0 },
    { "mu_s", offsetof(grip_brush_params, mu_s), FMT_QS, 1.0, 1.1 },
    { "mu_d0", offsetof(grip_brush_params, mu_d0), FMT_QS, 1.0, 0.9 },
    { "a_v", offsetof(grip_brush_params, a_v), FMT_QS, 1.0, 0.005 },
    { "n", offsetof(grip_brush_params, n), FMT_INT, 1.0, 4.0 },
    { "fz_min", offsetof(grip_brush_params, fz_min), FMT_QL, 1.0, 200.0 },
    { "fz_max", offsetof(grip_brush_params, fz_max), FMT_QL, 1.0, 10000.0 },
    { "kappa_max", offsetof(grip_brush_params, kappa_max), FMT_QS, 1.0, 1.0 },
    { "v_max", offsetof(grip_brush_params, v_max), FMT_QS, 1.0, 60.0 },
};
static const field_desc k_sakai_fields[] = {
    { "k", offsetof(grip_sakai_params, k), FMT_QL, 1.0, 57200.0 },
    { "g_y", offsetof(grip_sakai_params, g_y), FMT_QL, 1.0, 250000.0 },
    { "mu_s", offsetof(grip_sakai_params, mu_s), FMT_QS, 1.0, 1.0 },
    { "mu_d", offsetof(grip_sakai_params, mu_d), FMT_QS, 1.0, 0.8 },
    { "l", offsetof(grip_sakai_params, l), FMT_QS, 1.0, 0.18 },
    { "fz_min", offsetof(grip_sakai_params, fz_min), FMT_QL, 1.0, 200.0 },
    { "fz_max", offsetof(grip_sakai_params, fz_max), FMT_QL, 1.0, 10000.0 },
    { "alpha_max", offsetof(grip_sakai_params, alpha_max), FMT_QS, 1.0, 0.6 },
    { "kappa_max", offsetof(grip_sakai_params, kappa_max), FMT_QS, 1.0, 1.0 },
};
static const field_desc k_neofiala_fields[] = {
    { "l", offsetof(grip_neofiala_params, l), FMT_QS, 1.0, 0.18 },
    { "w", offsetof(grip_neofiala_params, w), FMT_QS, 1.0, 0.18 },
    { "kx", offsetof(grip_neofiala_params, kx), FMT_QL, 1.0, 70000.0 },
    { "ky", offsetof(grip_neofiala_params, ky), FMT_QL, 1.0, 60000.0 },
    { "mu_s", offsetof(grip_neofiala_params, mu_s), FMT_QS, 1.0, 1.1 },
    { "mu_d0", offsetof(grip_neofiala_params, mu_d0), FMT_QS, 1.0, 0.9 },
    { "a_v", offsetof(grip_neofiala_params, a_v), FMT_QS, 1.0, 0.004 },
    { "n", offsetof(grip_neofiala_params, n), FMT_INT, 1.0, 4.0 },
    { "q0", offsetof(grip_neofiala_params, q0), FMT_QS, 1.0, 0.0 },
    { "c_q", offsetof(grip_neofiala_params, c_q), FMT_QS, 1000.0, 0.0 },
    { "c_qm", offsetof(grip_neofiala_params, c_qm), FMT_QS, 1000.0, 0.0 },
    { "c_xc", offsetof(grip_neofiala_params, c_xc), FMT_QS, 1000.0, 0.0 },
    { "xi", offsetof(grip_neofiala_params, xi), FMT_QS, 1000.0, 0.0 },
    { "eps", offsetof(grip_neofiala_params, eps), FMT_QS, 1000.0, 0.0 },
    { "g_mz", offsetof(grip_neofiala_params, g_mz), FMT_QL, 1.0, 0.0 },
    { "a_x", offsetof(grip_neofiala_params, a_x), FMT_QL, 1.0, 0.0 },
    { "c_gamma", offsetof(grip_neofiala_params, c_gamma), FMT_QS, 1.0, 0.0 },
    { "h", offsetof(grip_neofiala_params, h), FMT_QS, 1.0, 0.0 },
    { "g_my", offsetof(grip_neofiala_params, g_my), FMT_QL, 1.0, 0.0 },
    { "fz_min", offsetof(grip_neofiala_params, fz_min), FMT_QL, 1.0, 200.0 },
    { "fz_max", offsetof(grip_neofiala_params, fz_max), FMT_QL, 1.0, 10000.0 },
    { "alpha_max", offsetof(grip_neofiala_params, alpha_max), FMT_QS, 1.0, 0.6 },
    { "kappa_max", offsetof(grip_neofiala_params, kappa_max), FMT_QS, 1.0, 1.0 },
    { "gamma_max", offsetof(grip_neofiala_params, gamma_max), FMT_QS, 1.0, 0.2 },
    { "v_max", offsetof(grip_neofiala_params, v_max), FMT_QS, 1.0, 60.0 },
};

typedef struct {
    const char *name;
    grip_brush_kind kind;
    const field_desc *fields;
    int nfields;
} model_desc;

#define NF(a) ((int)(sizeof(a) / sizeof((a)[0])))
static const model_desc k_models[] = {
    { "fiala", GRIP_BRUSH_KIND_FIALA, k_fiala_fields, NF(k_fiala_fields) },
    { "brush", GRIP_BRUSH_KIND_BRUSH, k_brush_fields, NF(k_brush_fields) },
    { "sakai", GRIP_BRUSH_KIND_SAKAI, k_sakai_fields, NF(k_sakai_fields) },
    { "neofiala", GRIP_BRUSH_KIND_NEOFIALA, k_neofiala_fields, NF(k_neofiala_fields) },
};
#define N_MODELS NF(k_models)
#define MAX_FIELDS 32

grip_brush_kind grip_brush_kind_of(const char *name)
{
    int i;
    if (name == NULL) {
        return GRIP_BRUSH_KIND_NONE;
    }
    for (i = 0; i < N_MODELS; ++i) {
        if (strcmp(name, k_models[i].name) == 0) {
            return k_models[i].kind;
        }
    }
    return GRIP_BRUSH_KIND_NONE;
}

static const model_desc *model_of_kind(grip_brush_kind k)
{
    int i;
    for (i = 0; i < N_MODELS; ++i) {
        if (k_models[i].kind == k) {
            return &k_models[i];
        }
    }
    return NULL;
}

static void *struct_of(grip_brush_tool *t, grip_brush_kind k)
{
    switch (k) {
    case GRIP_BRUSH_KIND_FIALA: return &t->fiala;
    case GRIP_BRUSH_KIND_BRUSH: return &t->brush;
    case GRIP_BRUSH_KIND_SAKAI: return &t->sakai;
    case GRIP_BRUSH_KIND_NEOFIALA: return &t->neofiala;
    default: return NULL;
    }
}

static const void *cstruct_of(const grip_brush_tool *t, grip_brush_kind k)
{
    return struct_of((grip_brush_tool *)(uintptr_t)t, k);
}

/* SI value -> the field's stored form; -1 when not representable. */
static int store(void *base, const field_desc *f, double si)
{
    double v = si * f->scale;
    char *p = (char *)base + f->offset;
    if (f->fmt == FMT_INT) {
        int32_t n;
        if (v != floor(v) || fabs(v) > 1000.0) {
            return -1;
        }
        n = (int32_t)v;
        memcpy(p, &n, sizeof n);
        return 0;
    }
#if GRIP_ARITH_FIXED
    {
        double q = v * ((f->fmt == FMT_QL) ? 256.0 : 65536.0);
        int32_t r;
        if (!(fabs(q) < 2147483647.0)) {
            return -1;
        }
        r = (int32_t)lround(q);
        memcpy(p, &r, sizeof r);
    }
#else
    {
        float r = (float)v;
        if (!isfinite(r)) {
            return -1;
        }
        memcpy(p, &r, sizeof r);
    }
#endif
    return 0;
}

static double load(const void *base, const field_desc *f)
{
    const char *p = (const char *)base + f->offset;
    if (f->fmt == FMT_INT) {
        int32_t n;
        memcpy(&n, p, sizeof n);
        return (double)n / f->scale;
    }
#if GRIP_ARITH_FIXED
    {
        int32_t r;
        memcpy(&r, p, sizeof r);
        return (double)r / ((f->fmt == FMT_QL) ? 256.0 : 65536.0) / f->scale;
    }
#else
    {
        float r;
        memcpy(&r, p, sizeof r);
        return (double)r / f->scale;
    }
#endif
}

static void trim(char **s, char **e)
{
    while (*s < *e && (**s == ' ' || **s == '\t')) {
        (*s)++;
    }
    while (*e > *s && ((*e)[-1] == ' ' || (*e)[-1] == '\t' || (*e)[-1] == '\r')) {
        (*e)--;
    }
}

static grip_status_t check(const grip_brush_tool *t, grip_check_detail_t *d)
{
    switch (t->kind) {
    case GRIP_BRUSH_KIND_FIALA: return grip_fiala_check_params_detail(&t->fiala, d);
    case GRIP_BRUSH_KIND_BRUSH: return grip_brush_check_params_detail(&t->brush, d);
    case GRIP_BRUSH_KIND_SAKAI: return grip_sakai_check_params_detail(&t->sakai, d);
    case GRIP_BRUSH_KIND_NEOFIALA: return grip_neofiala_check_params_detail(&t->neofiala, d);
    default: return GRIP_ERR_STATE;
    }
}

#define FAIL(...)                                    \
    do {                                             \
        if (err != NULL) {                           \
            snprintf(err, errlen, __VA_ARGS__);      \
        }                                            \
        memset(t, 0, sizeof *t);                     \
        return -1;                                   \
    } while (0)

int grip_brush_params_parse(const char *text, const char *name, const char *expect_model, grip_brush_tool *t,
                            char *err, size_t errlen)
{
    const model_desc *md = NULL;
    unsigned long lineno = 0;
    const char *cur = text;
    int seen[MAX_FIELDS];
    void *base = NULL;
    int i;

    if (t == NULL) {
        return -1;
    }
    memset(t, 0, sizeof *t);
    if (text == NULL) {
        FAIL("%s:0: no text", name);
    }
    memset(seen, 0, sizeof seen);
    while (*cur != '\0') {
        char line[512];
        const char *nl = strchr(cur, '\n');
        size_t len = (nl != NULL) ? (size_t)(nl - cur) : strlen(cur);
        char *s;
        char *e;
        char *eq;
        char *ks;
        char *ke;
        char *vs;
        char *ve;
        lineno++;
        if (len >= sizeof line) {
            FAIL("%s:%lu: line too long", name, lineno);
        }
        memcpy(line, cur, len);
        line[len] = '\0';
        cur += len + ((nl != NULL) ? 1 : 0);
        s = line;
        e = strchr(line, '#');
        if (e == NULL) {
            e = line + len;
        }
        trim(&s, &e);
        if (s == e) {
            continue;
        }
        *e = '\0';
        eq = strchr(s, '=');
        if (eq == NULL) {
            FAIL("%s:%lu: expected 'key = value'", name, lineno);
        }
        ks = s;
        ke = eq;
        vs = eq + 1;
        ve = e;
        trim(&ks, &ke);
        trim(&vs, &ve);
        *ke = '\0';
        *ve = '\0';
        if (strcmp(ks, "model") == 0) {
            grip_brush_kind k = grip_brush_kind_of(vs);
            if (md != NULL) {
                FAIL("%s:%lu: model: given twice", name, lineno);
            }
            if (k == GRIP_BRUSH_KIND_NONE) {
                FAIL("%s:%lu: model: '%s' is not one of fiala, brush, sakai, neofiala", name, lineno, vs);
            }
            if (expect_model != NULL && strcmp(vs, expect_model) != 0) {
                FAIL("%s:%lu: model: the file describes '%s', not '%s'", name, lineno, vs, expect_model);
            }
            md = model_of_kind(k);
            t->kind = k;
            base = struct_of(t, k);
            for (i = 0; i < md->nfields; ++i) {
                (void)store(base, &md->fields[i], md->fields[i].def);
            }
            continue;
        }
        if (md == NULL) {
            FAIL("%s:%lu: the first entry must be 'model = ...'", name, lineno);
        }
        for (i = 0; i < md->nfields; ++i) {
            if (strcmp(ks, md->fields[i].key) == 0) {
                break;
            }
        }
        if (i == md->nfields) {
            FAIL("%s:%lu: %s: unknown key for model %s", name, lineno, ks, md->name);
        }
        if (seen[i]) {
            FAIL("%s:%lu: %s: given twice (first on line %d)", name, lineno, ks, seen[i]);
        }
        seen[i] = (int)lineno;
        {
            char *end = NULL;
            double v;
            errno = 0;
            v = strtod(vs, &end);
            if (end == vs || *end != '\0' || errno == ERANGE || !isfinite(v)) {
                FAIL("%s:%lu: %s: '%s' is not a finite number", name, lineno, ks, vs);
            }
            if (store(base, &md->fields[i], v) != 0) {
                FAIL("%s:%lu: %s: %g is not representable in the %s build%s", name, lineno, ks, v,
                     GRIP_ARITH_NAME, (md->fields[i].fmt == FMT_INT) ? " (must be an integer)" : "");
            }
        }
    }
    if (md == NULL) {
        FAIL("%s:0: no 'model = ...' entry", name);
    }
    {
        grip_check_detail_t d;
        grip_status_t st = check(t, &d);
        if (st != GRIP_OK) {
            /* the line of the field the library names (0: its default) */
            int line = 0;
            for (i = 0; i < md->nfields; ++i) {
                if (strcmp(md->fields[i].key, d.field) == 0) {
                    line = seen[i];
                }
            }
            FAIL("%s:%d: %s: the library rejects the parameter set: %s must be %s%s (status %d, %s); valid "
                 "ranges: docs/brush-models.md", name, line, d.field[0] ? d.field : "-", d.field[0] ? d.field : "it",
                 d.rule, line ? "" : " (its default)", (int)st, grip_status_str(st));
        }
    }
    if (t->kind == GRIP_BRUSH_KIND_NEOFIALA && grip_neofiala_prepare(&t->neofiala, &t->nf_model) != GRIP_OK) {
        FAIL("%s:0: grip_neofiala_prepare failed", name);
    }
    return 0;
}

int grip_brush_params_read(const char *path, const char *expect_model, grip_brush_tool *t, char *err,
                           size_t errlen)
{
    FILE *f;
    char *buf;
    long n;
    int rc;
    if (t == NULL) {
        return -1;
    }
    memset(t, 0, sizeof *t);
    f = fopen(path, "rb");
    if (f == NULL) {
        FAIL("%s:0: cannot open: %s", path, strerror(errno));
    }
    if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || n > 1000000 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        FAIL("%s:0: cannot read (or larger than 1 MB)", path);
    }
    buf = malloc((size_t)n + 1);
    if (buf == NULL) {
        fclose(f);
        FAIL("%s:0: out of memory", path);
    }
    if (fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        fclose(f);
        FAIL("%s:0: read error", path);
    }
    buf[n] = '\0';
    fclose(f);
    {
        /* text only: a NUL would end the C string and hide the rest */
        long at;
        unsigned long line = 1;
        for (at = 0; at < n && buf[at] != '\0'; at++) {
            line += (buf[at] == '\n');
        }
        if (at < n) {
            free(buf);
            FAIL("%s:%lu: NUL byte at byte offset %ld: not a text parameter file", path, line, at);
        }
    }
    rc = grip_brush_params_parse(buf, path, expect_model, t, err, errlen);
    free(buf);
    return rc;
}

grip_status_t grip_brush_tool_eval(const grip_brush_tool *t, grip_real_t kappa, grip_real_t alpha,
                                   grip_real_t gamma, grip_real_t fz, grip_real_t vx, grip_real_t *fx,
                                   grip_real_t *fy, grip_real_t *mz)
{
    grip_brush_out o;
    grip_status_t st;
    if (fx == NULL || fy == NULL || mz == NULL) {
        return GRIP_ERR_NULL;
    }
    memset(&o, 0, sizeof o);
    if (t == NULL) {
        st = GRIP_ERR_NULL;
    } else {
        switch (t->kind) {
        case GRIP_BRUSH_KIND_FIALA: st = grip_fiala_eval(&t->fiala, alpha, fz, &o); break;
        case GRIP_BRUSH_KIND_BRUSH: st = grip_brush_eval(&t->brush, kappa, fz, vx, &o); break;
        case GRIP_BRUSH_KIND_SAKAI: st = grip_sakai_eval(&t->sakai, kappa, alpha, fz, &o); break;
        case GRIP_BRUSH_KIND_NEOFIALA:
            st = grip_neofiala_eval_model(&t->nf_model, kappa, alpha, gamma, fz, vx, &o);
            break;
        default: st = GRIP_ERR_STATE; break;
        }
    }
    *fx = o.fx;
    *fy = o.fy;
    *mz = o.mz;
    return st;
}

void grip_brush_params_dump(const grip_brush_tool *t, FILE *f)
{
    const model_desc *md;
    const void *base;
    int i;
    if (t == NULL || f == NULL) {
        return;
    }
    md = model_of_kind(t->kind);
    if (md == NULL) {
        return;
    }
    base = cstruct_of(t, t->kind);
    fprintf(f, "# grip brush-model parameter file (docs/brush-models.md), SI units, %s build\n",
            GRIP_ARITH_NAME);
    fprintf(f, "model = %s\n", md->name);
    for (i = 0; i < md->nfields; ++i) {
        if (md->fields[i].fmt == FMT_INT) {
            fprintf(f, "%s = %d\n", md->fields[i].key, (int)load(base, &md->fields[i]));
        } else {
            fprintf(f, "%s = %.17g\n", md->fields[i].key, load(base, &md->fields[i]));
        }
    }
}
