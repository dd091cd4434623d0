/*
 * brush_params.h - host-side parameter files of the brush-model family
 * (include/grip/grip_brush.h) and the evaluation hook of `grip-tire --model
 * fiala|brush|sakai|neofiala`.
 *
 * File format (docs/brush-models.md, "Parameter files"), read and written
 * by tools/grip_tools/reference/brush.py (read_params / write_params) too:
 *
 *   # comment (also after a value)
 *   model = neofiala          first entry: fiala | brush | sakai | neofiala
 *   ky = 72000                key = value, SI units (N, m, rad, s), one a line
 *
 * Keys are the fields of the model's parameter struct; every key is
 * optional and takes the documented default (the defaults of brush.py).
 * Unknown keys, duplicates, values that are not finite numbers or do not
 * fit the build's number format, and sets the library rejects
 * (grip_*_check_params) are errors "FILE:LINE: KEY: what is wrong".
 * Coefficients that the structs keep per kN (c_q, c_qm, c_xc, xi, eps) are
 * given in SI in the file and converted here.
 *
 * Host code only (stdio, double).
 */
#ifndef GRIP_BRUSH_PARAMS_H
#define GRIP_BRUSH_PARAMS_H

#include <stddef.h>
#include <stdio.h>

#include "grip/grip_brush.h"

typedef enum {
    GRIP_BRUSH_KIND_NONE = 0,
    GRIP_BRUSH_KIND_FIALA = 1,
    GRIP_BRUSH_KIND_BRUSH = 2,
    GRIP_BRUSH_KIND_SAKAI = 3,
    GRIP_BRUSH_KIND_NEOFIALA = 4
} grip_brush_kind;

/* One loaded model (caller-owned; large: keep it static or on the heap). */
typedef struct {
    grip_brush_kind kind;
    grip_fiala_params fiala;
    grip_brush_params brush;
    grip_sakai_params sakai;
    grip_neofiala_params neofiala;
    grip_neofiala_model nf_model;   /* prepared when kind == NEOFIALA */
} grip_brush_tool;

/* The kind of a model name ("fiala", "brush", "sakai", "neofiala"), or
 * GRIP_BRUSH_KIND_NONE. */
grip_brush_kind grip_brush_kind_of(const char *name);

/* Reads `path` into *t. If expect_model is not NULL the file's model must
 * be that one. Returns 0, or -1 with a message in err (if err != NULL) and
 * *t left with kind NONE. */
int grip_brush_params_read(const char *path, const char *expect_model, grip_brush_tool *t, char *err,
                           size_t errlen);

/* The same from text in memory; `name` is used in messages. */
int grip_brush_params_parse(const char *text, const char *name, const char *expect_model, grip_brush_tool *t,
                            char *err, size_t errlen);

/* Evaluates the loaded model on grip-tire's inputs (ISO-W, SI, in the
 * build's number formats: kappa, alpha, gamma, vx QS; fz QL) and writes
 * fx, fy, mz (QL). Inputs a model does not use are ignored (fiala: kappa,
 * gamma, vx; brush: alpha, gamma; sakai: gamma, vx). Returns the model's
 * status; GRIP_ERR_NULL for NULL pointers, GRIP_ERR_STATE for kind NONE
 * (outputs zero). */
grip_status_t grip_brush_tool_eval(const grip_brush_tool *t, grip_real_t kappa, grip_real_t alpha,
                                   grip_real_t gamma, grip_real_t fz, grip_real_t vx, grip_real_t *fx,
                                   grip_real_t *fy, grip_real_t *mz);

/* Writes the loaded parameters as a parameter file (SI, as stored in this
 * build, %.17g) that grip_brush_params_read and brush.py read back. */
void grip_brush_params_dump(const grip_brush_tool *t, FILE *f);

#endif /* GRIP_BRUSH_PARAMS_H */
