/*
 * target_main.c - golden-vector program for the target instruction set.
 *
 * Built three ways by tests/target/run_target_tests.sh from the same
 * source and the same vector subset (tv_vectors.h, made by gen_vectors.py):
 *   Cortex-M4F, float build  (qemu-system-arm -M mps2-an386, semihosting)
 *   Cortex-M0+, fixed build  (qemu-system-arm -M mps2-an385, semihosting)
 *   host, float and fixed    (the same program with stdio: host_bm.c)
 * It evaluates every vector and prints the raw 32-bit result words (float
 * bits or Q values) and statuses; the host compares them with the golden
 * reference under the host tests' tolerances (compare.py) and the fixed
 * results of target and host byte for byte.
 *
 * Output lines (hexadecimal words):
 *   B <arith>                                  build
 *   P <tyre> <16 parameter words>              the parameters the tolerances use
 *   M <tyre> <golden row> <s_pure> <s_comb> <Fx0 Fy0 Mz0 Fx Fy Mz>
 *   Q <primitive> <golden row> <result>
 *   F <golden row> <status> <Fy>               MF 1989
 *   H <golden row> <status> <Fx> <Fy>          MF thermal, forces at a temperature
 *   S <golden row> <status> <Fx> <Fy> <q> <T>  MF thermal time series (closed loop)
 *   R <model> <golden row> <status> <Fx> <Fy> <Mz> <rh>
 *                                              brush family (model 0 FIALA, 1 brush,
 *                                              2 Sakai, 3 Neo-FIALA)
 *   L <golden row> <status> <kappa'> <alpha'>  relaxation (closed loop per scenario)
 *   N <sequence> <rate_hz> <name>              an estimator sequence starts
 *   T <sequence> <golden row> <status> <45 output words in the golden file's
 *     column order: vx vy beta yaw_rate yaw_rate_ref yaw_error delta mu mu_conf
 *     fz[4] kappa[4] alpha[4] fx[4] fy[4] mz[4] util[4] fy_axle[2] util_axle[2]
 *     fy_margin_front steer_char valid flags>  estimator step (closed loop)
 *   E <count of lines>
 */
#include <stdint.h>
#include <string.h>
#include "grip/grip_types.h"
#include "grip/grip_q16.h"
#include "grip/grip_mf.h"
#include "grip/grip_mf89.h"
#include "grip/grip_mf_thermal.h"
#include "grip/grip_brush.h"
#include "grip/grip_relax.h"
#include "grip/grip_est.h"
#include "mf_params.h"
#include "grip_bm.h"

typedef struct {
    const char *name;
    const char *golden;
    int first;
    int n;
} tv_tire;

typedef struct {
    int id;
    const char *name;
    uint32_t rate_hz;
    int first;
    int n;
    uint32_t cfg_mask;   /* bit j: tv_est_cfg[seq][j] sets the j-th field of EST_CFG_KEYS */
} tv_seq;

#include "tv_vectors.h"
#if TV_EST_NCFG != 10
#error "tv_vectors.h: EST_CFG_KEYS of gen_vectors.py changed; update run_est's field table"
#endif

/* the thermal parameter words are copied into the struct in P-row order */
typedef char tv_th_size_check[(sizeof(grip_mf_thermal_params) == TV_TH_NP * sizeof(grip_real_t)) ? 1 : -1];
/* the brush parameter words are copied into the structs in P-row order
 * (every field is a grip_real_t or an int32_t) */
typedef char tv_fiala_size_check[(sizeof(grip_fiala_params) == sizeof tv_fiala_p[0]) ? 1 : -1];
typedef char tv_brush_size_check[(sizeof(grip_brush_params) == sizeof tv_brush_p[0]) ? 1 : -1];
typedef char tv_sakai_size_check[(sizeof(grip_sakai_params) == sizeof tv_sakai_p[0]) ? 1 : -1];
typedef char tv_neofiala_size_check[(sizeof(grip_neofiala_params) == sizeof tv_neofiala_p[0]) ? 1 : -1];
typedef char tv_relax_size_check[(sizeof(grip_relax_params) == sizeof tv_relax_p[0]) ? 1 : -1];

static char line[512];
static int pos;
static uint32_t nlines;

static void put_c(char c)
{
    if (pos < (int)sizeof line - 1) {
        line[pos++] = c;
    }
}

static void put_hex(uint32_t w)
{
    static const char hx[] = "0123456789abcdef";
    int i;
    put_c(' ');
    for (i = 7; i >= 0; i--) {
        put_c(hx[(w >> (4 * i)) & 0xFu]);
    }
}

static void put_s(const char *s)
{
    while (*s != '\0') {
        put_c(*s++);
    }
}

static void flush(void)
{
    put_c('\n');
    line[pos] = '\0';
    grip_bm_puts(line);
    pos = 0;
    nlines++;
}

static uint32_t word(grip_real_t v)
{
    uint32_t w;
    memcpy(&w, &v, sizeof w);
    return w;
}

static grip_real_t real(uint32_t w)
{
    grip_real_t v;
    memcpy(&v, &w, sizeof v);
    return v;
}

static grip_q16_t q16(uint32_t f, uint32_t a, uint32_t b)
{
    grip_q16_t x = (grip_q16_t)a;
    grip_q16_t y = (grip_q16_t)b;
    switch (f) {
    case 0: return grip_q16_mul(x, y);
    case 1: return grip_q16_div(x, y);
    case 2: return grip_q16_sqrt(x);
    case 3: return grip_q16_atan(x);
    case 4: return grip_q16_atan2(x, y);
    case 5: return grip_q16_sin(x);
    case 6: return grip_q16_cos(x);
    case 7: return grip_q16_exp(x);
    default: return grip_q16_log(x);
    }
}

static void put_out(const grip_brush_out *o)
{
    put_hex(word(o->fx));
    put_hex(word(o->fy));
    put_hex(word(o->mz));
    put_hex(word(o->rh));
}

/* brush family: FIALA, brush, Sakai, Neo-FIALA, parameter sets first */
static void run_brush(void)
{
    static grip_fiala_params fi[TV_FIALA_NSETS];
    static grip_brush_params br[TV_BRUSH_NSETS];
    static grip_sakai_params sa[TV_SAKAI_NSETS];
    static grip_neofiala_params nf[TV_NEOFIALA_NSETS];
    int i;
    memcpy(fi, tv_fiala_p, sizeof fi);
    memcpy(br, tv_brush_p, sizeof br);
    memcpy(sa, tv_sakai_p, sizeof sa);
    memcpy(nf, tv_neofiala_p, sizeof nf);
    for (i = 0; i < TV_BR_ROWS; i++) {
        const uint32_t *r = tv_br[i];
        uint32_t id = r[1];
        grip_brush_out o;
        grip_status_t s;
        memset(&o, 0, sizeof o);
        switch (r[0]) {
        case 0:
            s = grip_fiala_eval(&fi[id], real(r[4]), real(r[5]), &o);
            break;
        case 1:
            s = grip_brush_eval(&br[id], real(r[4]), real(r[5]), real(r[6]), &o);
            break;
        case 2:
            s = grip_sakai_eval(&sa[id], real(r[4]), real(r[5]), real(r[6]), &o);
            break;
        default:
            s = grip_neofiala_eval(&nf[id], real(r[4]), real(r[5]), real(r[6]), real(r[7]), real(r[8]), &o);
            break;
        }
        put_c('R');
        put_hex(r[0]);
        put_hex(r[3]);
        put_hex((uint32_t)s);
        put_out(&o);
        flush();
    }
}

/* relaxation length: every scenario from zero state, closed loop */
static int run_relax(void)
{
    static grip_relax_params rp;
    static grip_relax_state rs;
    uint32_t scen = 0xFFFFFFFFu;
    int i;
    memcpy(&rp, tv_relax_p[0], sizeof rp);
    for (i = 0; i < TV_RELAX_ROWS; i++) {
        grip_real_t kt = 0;
        grip_real_t at = 0;
        grip_status_t s;
        if (tv_relax[i][0] != scen) {
            scen = tv_relax[i][0];
            if (grip_relax_init(&rs, &rp, 0, 0) != GRIP_OK) {
                put_s("X relax init failed");
                flush();
                return 1;
            }
        }
        s = grip_relax_step(&rs, real(tv_relax[i][1]), real(tv_relax[i][2]), real(tv_relax[i][3]),
                            real(tv_relax[i][4]), &kt, &at);
        put_c('L');
        put_hex(tv_relax[i][5]);
        put_hex((uint32_t)s);
        put_hex(word(kt));
        put_hex(word(at));
        flush();
    }
    return 0;
}

static void put_words(const grip_real_t *v, int n)
{
    int k;
    for (k = 0; k < n; k++) {
        put_hex(word(v[k]));
    }
}

/* estimator: whole sequences, PacejkaBook_Defaults on both axles (as
 * tests/unit/test_est_golden.c) */
static int run_est(void)
{
    static grip_est_t est;
    static grip_input_sample_t in;
    static grip_est_output_t out;
    const grip_mf_params *tp = grip_test_tire_params("PacejkaBook_Defaults");
    int q;
    int k;
    if (tp == NULL && TV_EST_NSEQ > 0) {
        put_s("X missing parameter set PacejkaBook_Defaults");
        flush();
        return 1;
    }
    for (q = 0; q < TV_EST_NSEQ; q++) {
        const tv_seq *sq = &tv_est_seqs[q];
        grip_est_config_t cfg;
        int i;
        if (grip_est_config_default(&cfg, tp) != GRIP_OK) {
            put_s("X estimator configuration failed");
            flush();
            return 1;
        }
        cfg.rate_hz = sq->rate_hz;
        {
            /* the sequence's configuration beyond the default, in the order of
             * gen_vectors.py EST_CFG_KEYS */
            grip_real_t *field[TV_EST_NCFG];
            field[0] = &cfg.cla;
            field[1] = &cfg.aero_front;
            field[2] = &cfg.air_density;
            field[3] = &cfg.cda;
            field[4] = &cfg.crr;
            field[5] = &cfg.tan_bank;
            field[6] = &cfg.tan_grade;
            field[7] = &cfg.latency;
            field[8] = &cfg.steer_lag;
            field[9] = &cfg.steer_latency;
            for (k = 0; k < TV_EST_NCFG; k++) {
                if ((sq->cfg_mask >> k) & 1u) {
                    *field[k] = real(tv_est_cfg[q][k]);
                }
            }
        }
        if (grip_est_init(&est, &cfg) != GRIP_OK) {
            put_s("X estimator init failed");
            flush();
            return 1;
        }
        put_c('N');
        put_hex((uint32_t)sq->id);
        put_hex(sq->rate_hz);
        put_c(' ');
        put_s(sq->name);
        flush();
        for (i = 0; i < sq->n; i++) {
            const uint32_t *r = tv_est[sq->first + i];
            grip_status_t s;
            memset(&in, 0, sizeof in);
            memset(&out, 0, sizeof out);
            in.t_us = (int64_t)r[0];
            in.step = (uint32_t)i;
            for (k = 0; k < TV_EST_NIN; k++) {
                in.value[k] = real(r[3 + k]);
                in.valid[k] = (uint8_t)((r[1] >> k) & 1u);
                in.fault[k] = (uint8_t)(in.valid[k] ? GRIP_SIG_OK : GRIP_SIG_MISSING);
            }
            s = grip_est_step(&est, &in, &out);
            put_c('T');
            put_hex((uint32_t)sq->id);
            put_hex(r[2]);
            put_hex((uint32_t)s);
            put_hex(word(out.vx)); put_hex(word(out.vy)); put_hex(word(out.beta));
            put_hex(word(out.yaw_rate)); put_hex(word(out.yaw_rate_ref)); put_hex(word(out.yaw_error));
            put_hex(word(out.delta)); put_hex(word(out.mu)); put_hex(word(out.mu_conf));
            put_words(out.fz, 4);
            put_words(out.kappa, 4);
            put_words(out.alpha, 4);
            put_words(out.fx, 4);
            put_words(out.fy, 4);
            put_words(out.mz, 4);
            put_words(out.util, 4);
            put_words(out.fy_axle, 2);
            put_words(out.util_axle, 2);
            put_hex(word(out.fy_margin_front));
            put_hex((uint32_t)out.steer_char);
            put_hex(out.valid);
            put_hex(out.flags);
            flush();
        }
    }
    return 0;
}

int main(void)
{
    int t;
    int i;
    put_s("B ");
    put_s(GRIP_ARITH_NAME);
    flush();
    for (t = 0; t < TV_NTIRES; t++) {
        const grip_mf_params *p = NULL;
        int k;
        for (k = 0; k < grip_test_tire_count; k++) {
            if (strcmp(grip_test_tires[k].golden, tv_tires[t].golden) == 0) {
                p = grip_test_tires[k].params;
            }
        }
        if (p == NULL) {
            put_s("X missing parameter set ");
            put_s(tv_tires[t].name);
            flush();
            return 1;
        }
        put_c('P');
        put_hex((uint32_t)t);
        put_hex(word(p->fnomin)); put_hex(word(p->lfzo)); put_hex(word(p->nompres));
        put_hex(word(p->unloaded_radius));
        put_hex(word(p->pdx1)); put_hex(word(p->pdx2)); put_hex(word(p->pdx3));
        put_hex(word(p->ppx3)); put_hex(word(p->ppx4)); put_hex(word(p->lmux));
        put_hex(word(p->pdy1)); put_hex(word(p->pdy2)); put_hex(word(p->pdy3));
        put_hex(word(p->ppy3)); put_hex(word(p->ppy4)); put_hex(word(p->lmuy));
        flush();
        for (i = tv_tires[t].first; i < tv_tires[t].first + tv_tires[t].n; i++) {
            grip_mf_input in;
            grip_mf_output o1;
            grip_mf_output o2;
            grip_status_t s1;
            grip_status_t s2;
            in.kappa = real(tv_mf_in[i][0]);
            in.alpha = real(tv_mf_in[i][1]);
            in.gamma = real(tv_mf_in[i][2]);
            in.fz = real(tv_mf_in[i][3]);
            in.p = real(tv_mf_in[i][4]);
            in.vx = real(tv_mf_in[i][5]);
            s1 = grip_mf_eval_pure(p, &in, &o1);
            s2 = grip_mf_eval(p, &in, &o2);
            put_c('M');
            put_hex((uint32_t)t);
            put_hex(tv_mf_in[i][6]);
            put_hex((uint32_t)s1);
            put_hex((uint32_t)s2);
            put_hex(word(o1.fx)); put_hex(word(o1.fy)); put_hex(word(o1.mz));
            put_hex(word(o2.fx)); put_hex(word(o2.fy)); put_hex(word(o2.mz));
            flush();
        }
    }
    for (i = 0; i < TV_Q16_ROWS; i++) {
        put_c('Q');
        put_hex(tv_q16[i][0]);
        put_hex(tv_q16[i][3]);
        put_hex((uint32_t)q16(tv_q16[i][0], tv_q16[i][1], tv_q16[i][2]));
        flush();
    }
    {
        grip_mf89_params p;
        for (i = 0; i < GRIP_MF89_NCOEF; i++) {
            p.a[i] = real(tv_mf89_p[0][i]);
        }
        p.fz_max = real(tv_mf89_p[0][18]);
        p.alpha_max = real(tv_mf89_p[0][19]);
        p.gamma_max = real(tv_mf89_p[0][20]);
        for (i = 0; i < TV_MF89_ROWS; i++) {
            grip_real_t fy = 0;
            grip_status_t s = grip_mf89_fy(&p, real(tv_mf89_in[i][0]), real(tv_mf89_in[i][1]),
                                           real(tv_mf89_in[i][2]), &fy);
            put_c('F');
            put_hex(tv_mf89_in[i][3]);
            put_hex((uint32_t)s);
            put_hex(word(fy));
            flush();
        }
    }
    {
        static grip_mf_thermal_params tp;
        static grip_mf_thermal_state st;
        grip_mf_thermal_inputs in;
        grip_real_t tw[TV_TH_NP];
        uint32_t scen = 0xFFFFFFFFu;
        for (i = 0; i < TV_TH_NP; i++) {
            tw[i] = real(tv_th_p[0][i]);
        }
        memcpy(&tp, tw, sizeof tp);   /* the struct is TV_TH_NP grip_real_t in P-row order */
        if (grip_mf_thermal_init(&st, &tp, tp.t0) != GRIP_OK) {
            put_s("X thermal init failed");
            flush();
            return 1;
        }
        for (i = 0; i < TV_TH_F_ROWS; i++) {
            grip_real_t fx = 0;
            grip_real_t fy = 0;
            grip_status_t s;
            in.v = 0;
            in.alpha = real(tv_th_f[i][0]);
            in.slip = real(tv_th_f[i][1]);
            in.fz = real(tv_th_f[i][2]);
            in.t_road = GRIP_QS(20.0f);
            s = grip_mf_thermal_forces(&st, &in, real(tv_th_f[i][3]), &fx, &fy);
            put_c('H');
            put_hex(tv_th_f[i][4]);
            put_hex((uint32_t)s);
            put_hex(word(fx));
            put_hex(word(fy));
            flush();
        }
        for (i = 0; i < TV_TH_S_ROWS; i++) {
            grip_mf_thermal_output o;
            grip_status_t s;
            if (tv_th_s[i][0] != scen) {   /* new scenario: start from the reference's temperature */
                scen = tv_th_s[i][0];
                if (grip_mf_thermal_init(&st, &tp, real(tv_th_s[i][7])) != GRIP_OK) {
                    put_s("X thermal init failed");
                    flush();
                    return 1;
                }
            }
            in.v = real(tv_th_s[i][1]);
            in.alpha = real(tv_th_s[i][2]);
            in.slip = real(tv_th_s[i][3]);
            in.fz = real(tv_th_s[i][4]);
            in.t_road = real(tv_th_s[i][5]);
            s = grip_mf_thermal_step(&st, &in, real(tv_th_s[i][6]), &o);
            put_c('S');
            put_hex(tv_th_s[i][8]);
            put_hex((uint32_t)s);
            put_hex(word(o.fx));
            put_hex(word(o.fy));
            put_hex(word(o.q));
            put_hex(word(o.t));
            flush();
        }
    }
    run_brush();
    if (run_relax() != 0 || run_est() != 0) {
        return 1;
    }
    put_c('E');
    put_hex(nlines);
    flush();
    return 0;
}
