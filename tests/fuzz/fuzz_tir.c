/*
 * fuzz_tir.c - the .tir reader (port/linux/tir_reader.c).
 *
 * Input: a whole .tir file (written to a per-process temporary file, since
 * the reader takes a path). Both tyre-side options are tried, the first
 * with warnings (checked for their form), the second in strict mode
 * without the plausibility ranges.
 * Properties: no crash or sanitizer report; on failure an error message of
 * the documented form "FILE:LINE: ..." and the output struct untouched; on
 * success the set passes grip_mf_check_params (the reader validates at
 * least what the library requires), and grip_mf_eval / _pure give finite
 * outputs and a documented status on a few operating points.
 */
#include <unistd.h>
#include "fuzz_common.h"
#include "grip/grip_mf.h"
#include "tir_reader.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char path[64];

/* A warning has the form of an error: "FILE:LINE: KEY: what". */
static void check_warning(void *ctx, const char *message)
{
    const char *file = ctx;
    FZ_CHECK(strncmp(message, file, strlen(file)) == 0 && message[strlen(file)] == ':', "warning form: %s",
             message);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const double ops[4][6] = {
        { 0.0, 0.0, 0.0, 4000.0, 0.0, 20.0 },
        { -0.1, 0.05, 0.02, 3000.0, 200000.0, 15.0 },
        { 0.3, -0.2, -0.05, 8000.0, 0.0, 30.0 },
        { 1.0, 1.2, 0.4, 1e6, 1e9, 1000.0 },
    };
    int side;
    if (path[0] == '\0') {
        snprintf(path, sizeof path, "/tmp/grip-fuzz-tir-%ld.tir", (long)getpid());
    }
    {
        FILE *fp = fopen(path, "wb");
        if (fp == NULL) {
            return 0;
        }
        fwrite(data, 1, size, fp);
        fclose(fp);
    }
    for (side = 0; side < 2; side++) {
        grip_tir_options opt;
        grip_mf_params p;
        grip_mf_params before;
        char err[512];
        int rc;
        int k;
        grip_tir_options_init(&opt);
        opt.side = side ? GRIP_TIR_SIDE_RIGHT : GRIP_TIR_SIDE_FILE;
        /* plain (warnings checked for their form), then strict without the ranges */
        opt.flags = side ? (GRIP_TIR_STRICT | GRIP_TIR_NO_RANGE_CHECK) : 0u;
        opt.warn = check_warning;
        opt.warn_ctx = (void *)path;
        memset(&p, 0xA5, sizeof p);
        before = p;
        err[0] = '\0';
        rc = grip_tir_read_opts(path, &opt, &p, err, sizeof err);
        FZ_CHECK(rc == 0 || rc == -1, "rc %d", rc);
        if (rc != 0) {
            FZ_CHECK(strncmp(err, path, strlen(path)) == 0 && err[strlen(path)] == ':', "message form: %s", err);
            FZ_CHECK(memcmp(&p, &before, sizeof p) == 0, "output changed on error");
            continue;
        }
        {
            grip_status_t sc = grip_mf_check_params(&p);
            FZ_CHECK(sc == GRIP_OK, "reader accepted a set that grip_mf_check_params rejects (%d)", (int)sc);
        }
        for (k = 0; k < 4; k++) {
            grip_mf_input in;
            grip_mf_output o;
            grip_status_t s;
            in.kappa = fz_from_d(ops[k][0], FZ_QS);
            in.alpha = fz_from_d(ops[k][1], FZ_QS);
            in.gamma = fz_from_d(ops[k][2], FZ_QS);
            in.fz = fz_from_d(ops[k][3], FZ_QL);
            in.p = fz_from_d(ops[k][4], FZ_QL);
            in.vx = fz_from_d(ops[k][5], FZ_QS);
            s = grip_mf_eval(&p, &in, &o);
            FZ_CHECK(fz_status_known(s), "eval status %d", (int)s);
            FZ_CHECK(fz_finite(o.fx) && fz_finite(o.fy) && fz_finite(o.mz), "non-finite output");
            if (s < 0) {
                FZ_CHECK(o.fx == 0 && o.fy == 0 && o.mz == 0, "error with output");
            }
            s = grip_mf_eval_pure(&p, &in, &o);
            FZ_CHECK(fz_status_known(s), "eval_pure status %d", (int)s);
            FZ_CHECK(fz_finite(o.fx) && fz_finite(o.fy) && fz_finite(o.mz), "non-finite output");
        }
    }
    return 0;
}
