/*
 * mf_params.h - the parameter sets of every shared .tir file, compiled in
 * from C emitted by `python -m grip_tools golden-all` (build/golden/mf_params.c),
 * with the golden-vector file that belongs to each.
 */
#ifndef GRIP_TEST_MF_PARAMS_H
#define GRIP_TEST_MF_PARAMS_H

#include "grip/grip_mf.h"

typedef struct {
    const char *name;           /* e.g. "G275MSA_60psi" */
    const char *tir_path;       /* the source .tir file */
    const grip_mf_params *params;
    const char *golden;         /* golden file name inside build/golden */
} grip_test_tire;

extern const grip_test_tire grip_test_tires[];
extern const int grip_test_tire_count;

/* The parameter set of the tire `name` (e.g. "PacejkaBook_Defaults"), NULL
 * if there is none; no libc, so the bare-metal programs can use it too. */
const grip_mf_params *grip_test_tire_params(const char *name);

#endif
