/* golden.c - see golden.h */
#include "golden.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int golden_open(golden_file *g, const char *name)
{
    const char *dir = getenv("GRIP_GOLDEN_DIR");
    memset(g, 0, sizeof(*g));
    snprintf(g->path, sizeof(g->path), "%s/%s", (dir != NULL) ? dir : "build/golden", name);
    g->file = fopen(g->path, "r");
    if (g->file == NULL) {
        fprintf(stderr, "golden: cannot open %s (run `make golden`)\n", g->path);
        return -1;
    }
    return 0;
}

int golden_next(golden_file *g)
{
    while (fgets(g->line, sizeof(g->line), g->file) != NULL) {
        char *p = g->line;
        char *tok;
        g->lineno++;
        if (p[0] == '#' || p[0] == '\n' || p[0] == '\r') {
            continue;
        }
        g->nfields = 0;
        for (tok = strtok(p, " \t,\r\n"); tok != NULL && g->nfields < GOLDEN_MAX_FIELDS;
             tok = strtok(NULL, " \t,\r\n")) {
            g->field[g->nfields++] = tok;
        }
        if (g->nfields > 0) {
            return g->nfields;
        }
    }
    return 0;
}

void golden_close(golden_file *g)
{
    if (g->file != NULL) {
        fclose(g->file);
        g->file = NULL;
    }
}

double golden_num(const golden_file *g, int i)
{
    char *end = NULL;
    double v;
    if (i >= g->nfields) {
        fprintf(stderr, "golden: %s:%lu: missing field %d\n", g->path, g->lineno, i);
        abort();
    }
    v = strtod(g->field[i], &end);
    if (end == g->field[i] || *end != '\0') {
        fprintf(stderr, "golden: %s:%lu: field %d '%s' is not a number\n", g->path, g->lineno, i,
                g->field[i]);
        abort();
    }
    return v;
}

void err_init(err_stats *s, const char *name, double rel_floor)
{
    memset(s, 0, sizeof(*s));
    s->name = name;
    s->rel_floor = rel_floor;
}

void err_add(err_stats *s, double got, double want, double in0, double in1, double in2)
{
    double e = fabs(got - want);
    double den = fabs(want) > s->rel_floor ? fabs(want) : s->rel_floor;
    if (!(e <= s->max_abs)) {   /* also catches NaN */
        s->max_abs = isnan(e) ? INFINITY : e;
        s->worst_in[0] = in0;
        s->worst_in[1] = in1;
        s->worst_in[2] = in2;
    }
    if (den > 0.0 && e / den > s->max_rel) {
        s->max_rel = e / den;
    }
    s->sum_sq_err += e * e;
    s->sum_sq_ref += want * want;
    s->n++;
}

double err_snr_db(const err_stats *s)
{
    if (s->sum_sq_err <= 0.0) {
        return INFINITY;
    }
    return 10.0 * log10(s->sum_sq_ref / s->sum_sq_err);
}

void err_print(const err_stats *s, const char *unit)
{
    printf("# %-28s n=%-7ld max|err|=%.3e %s  max rel=%.3e  SNR=%.1f dB  (worst at %.6g, %.6g, %.6g)\n",
           s->name, s->n, s->max_abs, unit, s->max_rel, err_snr_db(s), s->worst_in[0], s->worst_in[1],
           s->worst_in[2]);
    fflush(stdout);
}
