/*
 * golden.h - host-side reading of golden-vector files and error statistics
 * (absolute, relative and SNR, as CMSIS-DSP states its tolerances).
 */
#ifndef GRIP_TEST_GOLDEN_H
#define GRIP_TEST_GOLDEN_H

#include <stdio.h>

#define GOLDEN_MAX_FIELDS 96

typedef struct {
    FILE *file;
    char path[512];
    unsigned long lineno;
    char line[4096];
    char *field[GOLDEN_MAX_FIELDS];
    int nfields;
} golden_file;

/* Opens $GRIP_GOLDEN_DIR/name (default build/golden). 0 on success. */
int golden_open(golden_file *g, const char *name);
/* Next data row, split on whitespace or commas; returns its field count,
 * 0 at end of file. Header lines ('#') are skipped. */
int golden_next(golden_file *g);
void golden_close(golden_file *g);
double golden_num(const golden_file *g, int i);

typedef struct {
    const char *name;
    long n;
    double max_abs;
    double max_rel;        /* relative to max(|want|, rel_floor) */
    double rel_floor;
    double sum_sq_err;
    double sum_sq_ref;
    double worst_in[3];    /* inputs of the max-abs case, for the report */
} err_stats;

void err_init(err_stats *s, const char *name, double rel_floor);
void err_add(err_stats *s, double got, double want, double in0, double in1, double in2);
double err_snr_db(const err_stats *s);
/* Prints one line "# <name>: n=.. max|err|=.. max rel=.. SNR=.. dB (worst at ...)" */
void err_print(const err_stats *s, const char *unit);

#endif
