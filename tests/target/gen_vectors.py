#!/usr/bin/env python3
"""gen_vectors.py GOLDEN_DIR OUT_HEADER - a deterministic subset of the golden
vectors as C arrays for the bare-metal golden tests (tests/target).

Subset (stated in docs/assurance.md):
  Magic Formula  every MF_STRIDE-th data row (rows 0, k, 2k, ...) of each
                 mf_<tyre>.txt named in mf_params.c, in that file's order;
  Q15.16         every Q16_STRIDE-th row of each primitive in q16.txt
                 (counted per primitive, so every primitive is present);
  MF 1989        every MF89_STRIDE-th V row of mf89.txt (with its P row);
  MF thermal     every THERMAL_F_STRIDE-th F row (forces at a given
                 temperature) and EVERY S row (the closed-loop time series
                 must run step by step) of mf_thermal.txt, with its P row;
  brush family   every BRUSH_STRIDE-th V row of each brush_<model>.txt
                 (FIALA, brush, Sakai, Neo-FIALA; counted per parameter set,
                 so every set is present) and EVERY C row (clamped inputs),
                 with every P row (parameter set);
  relaxation     EVERY row of relax.txt (five closed-loop scenarios);
  estimator      EVERY row of the sequences EST_SEQS (est_<name>.txt): the
                 estimator is a closed loop, a sequence cannot be thinned.
                 A sequence whose file is absent (est_sim_sine_dwell needs
                 the vehicle simulator) is left out and listed as such.
Inputs are stored exactly as the host tests convert them: fixed build
lround(v * 2^16) (QS) / lround(v * 2^8) (QL) as in tests/unit/test_mf_golden.c,
float build the IEEE single nearest to the double (the C cast (float)v), as
raw 32-bit words. Estimator inputs as tests/unit/test_est_golden.c: fixed
NaN -> INT32_MAX, values beyond the Q range saturated to +-INT32_MAX; float
NaN and +-Inf kept. Stdlib only.
"""
import math
import os
import re
import struct
import sys

MF_STRIDE = 8
Q16_STRIDE = 50
MF89_STRIDE = 8
THERMAL_F_STRIDE = 16
BRUSH_STRIDE = 1
EST_SEQS = ['bicycle_100hz', 'faults_100hz', 'bicycle_1khz', 'sim_sine_dwell', 'aero_bank_100hz',
            'steer_offset_100hz']
# grip_est_config_t fields a sequence's header may set (golden_est
# write_sequence's cfg_kw; all QS); the others keep grip_est_config_default
EST_CFG_KEYS = ['cla', 'aero_front', 'air_density', 'cda', 'crr', 'tan_bank', 'tan_grade', 'latency', 'steer_lag',
                'steer_latency']
# brush models: (name, parameter field formats in struct order, input formats);
# S = QS, L = QL, I = int32 (the same word in both builds); as
# tools/grip_tools/reference/brush.py C_UNITS and tests/unit/test_brush.c
BRUSH_MODELS = [
    ('fiala', 'ky mu l fz_min fz_max alpha_max', 'LSSLLS', 'SL'),
    ('brush', 'kx mu_s mu_d0 a_v n fz_min fz_max kappa_max v_max', 'LSSSILLSS', 'SLS'),
    ('sakai', 'k g_y mu_s mu_d l fz_min fz_max alpha_max kappa_max', 'LLSSSLLSS', 'SSL'),
    ('neofiala', 'l w kx ky mu_s mu_d0 a_v n q0 c_q c_qm c_xc xi eps g_mz a_x c_gamma h g_my fz_min fz_max '
     'alpha_max kappa_max gamma_max v_max', 'SSLLSSSISSSSSSLLSSLLLSSSS', 'SSSLS'),
]
EST_NIN = 18
EST_QL = range(9, 17)   # inputs 9..16 (brake pressures, torques) are QL; 17 (rear steer) QS
# QL (1) / QS (0) of the grip_mf_thermal_params fields, in struct order (= the P row)
THERMAL_QL = [1, 0, 1, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 0,
              1, 0, 0, 0, 0, 0]
Q16_FUNCS = ['mul', 'div', 'sqrt', 'atan', 'atan2', 'sin', 'cos', 'exp', 'log']


def lround(x):
    """C lround: nearest integer, halves away from zero (exact for doubles)."""
    a = abs(x)
    r = math.floor(a)
    if a - r >= 0.5:
        r += 1
    return int(-r if x < 0 else r)


def q_word(v, shift):
    r = lround(v * float(1 << shift))
    if not -2**31 <= r < 2**31:
        raise ValueError('value %r not representable' % v)
    return r & 0xFFFFFFFF


def f_word(v):
    return struct.unpack('<I', struct.pack('<f', v))[0]


def est_word(v, shift, fixed):
    """An estimator input as tests/unit/test_est_golden.c converts it."""
    if not fixed:
        if math.isnan(v) or math.isinf(v):
            return f_word(v)
        return f_word(max(-3.4028234663852886e38, min(v, 3.4028234663852886e38)))
    if math.isnan(v):
        return 0x7FFFFFFF
    x = v * float(1 << shift)
    if x > 2147483647.0:
        return 0x7FFFFFFF
    if x < -2147483647.0:
        return (-0x7FFFFFFF) & 0xFFFFFFFF
    return lround(x) & 0xFFFFFFFF


def conv(v, f, fixed):
    """A value in format f (S QS, L QL, I int32) as the build's raw word."""
    if f == 'I':
        return int(v) & 0xFFFFFFFF
    if fixed:
        return q_word(v, 16 if f == 'S' else 8)
    return f_word(v)


def header_param(path, key):
    with open(path) as f:
        for line in f:
            if not line.startswith('#'):
                break
            m = re.match(r'# param %s: (.*)$' % re.escape(key), line.rstrip('\n'))
            if m:
                return m.group(1)
    return None


def rows(path):
    with open(path) as f:
        for line in f:
            s = line.split()
            if s and not s[0].startswith('#'):
                yield s


def tires(golden):
    with open(os.path.join(golden, 'mf_params.c')) as f:
        text = f.read()
    return re.findall(r'\{ "([^"]+)", "[^"]*", &\w+, "([^"]+)" \}', text)


def main():
    golden, out = sys.argv[1], sys.argv[2]
    fixed_in, float_in, meta = [], [], []
    tt = tires(golden)
    if not tt:
        sys.exit('gen_vectors: no tyre in mf_params.c')
    first = 0
    for name, gname in tt:
        n = 0
        for i, s in enumerate(rows(os.path.join(golden, gname))):
            if i % MF_STRIDE:
                continue
            v = [float(x) for x in s[:6]]
            fmt = [16, 16, 16, 8, 8, 16]   # kappa alpha gamma QS, fz p QL, vx QS
            fixed_in.append([q_word(x, sh) for x, sh in zip(v, fmt)] + [i])
            float_in.append([f_word(x) for x in v] + [i])
            n += 1
        meta.append((name, gname, first, n))
        first += n
    q16 = []
    count = {f: 0 for f in Q16_FUNCS}
    for i, s in enumerate(rows(os.path.join(golden, 'q16.txt'))):
        fn = s[0]
        k = count[fn]
        count[fn] += 1
        if k % Q16_STRIDE == 0:
            q16.append((Q16_FUNCS.index(fn), int(s[1]) & 0xFFFFFFFF, int(s[2]) & 0xFFFFFFFF, i))
    p89 = None
    r89 = []
    j = 0
    for i, s in enumerate(rows(os.path.join(golden, 'mf89.txt'))):
        if s[0] == 'P':
            p89 = [float(x) for x in s[1:]]
        elif s[0] == 'V':
            if j % MF89_STRIDE == 0:
                v = [float(x) for x in s[1:4]]   # alpha fz gamma
                r89.append(([q_word(v[0], 16), q_word(v[1], 8), q_word(v[2], 16)], [f_word(x) for x in v], i))
            j += 1
    if p89 is None or len(p89) != 21:
        sys.exit('gen_vectors: mf89.txt has no P row of 21 values')
    p89_fixed = [q_word(x, 16) for x in p89[:18]] + [q_word(p89[18], 8), q_word(p89[19], 16), q_word(p89[20], 16)]
    p89_float = [f_word(x) for x in p89]

    tp = None
    tf = []
    ts = []
    j = 0
    for i, s in enumerate(rows(os.path.join(golden, 'mf_thermal.txt'))):
        if s[0] == 'P':
            tp = [float(x) for x in s[1:]]
        elif s[0] == 'F':
            if j % THERMAL_F_STRIDE == 0:
                v = [float(x) for x in s[1:5]]   # alpha slip fz t
                tf.append(([q_word(v[0], 16), q_word(v[1], 16), q_word(v[2], 8), q_word(v[3], 16)],
                           [f_word(x) for x in v], i))
            j += 1
        elif s[0] == 'S':
            v = [float(x) for x in s[2:9]]       # v alpha slip fz t_road dt t_before
            fmt = [16, 16, 16, 8, 16, 16, 16]
            ts.append(([int(s[1])] + [q_word(x, sh) for x, sh in zip(v, fmt)], [int(s[1])] + [f_word(x) for x in v], i))
    if tp is None or len(tp) != len(THERMAL_QL):
        sys.exit('gen_vectors: mf_thermal.txt has no P row of %d values' % len(THERMAL_QL))
    tp_fixed = [q_word(x, 8 if ql else 16) for x, ql in zip(tp, THERMAL_QL)]
    tp_float = [f_word(x) for x in tp]

    # brush family: one row table for all four models
    br_rows = {True: [], False: []}
    br_params = {}
    br_count = []
    for m, (model, fields, pfmt, ifmt) in enumerate(BRUSH_MODELS):
        path = os.path.join(golden, 'brush_%s.txt' % model)
        if header_param(path, 'param_fields') != fields:
            sys.exit('gen_vectors: %s: parameter fields are not "%s"' % (path, fields))
        ps = {True: [], False: []}
        per_set = {}
        nv = nc = 0
        for i, s in enumerate(rows(path)):
            sid = int(s[1])
            if s[0] == 'P':
                if sid != len(ps[True]):
                    sys.exit('gen_vectors: %s: parameter sets out of order' % path)
                v = [float(x) for x in s[2:]]
                for fx in (True, False):
                    ps[fx].append([conv(x, f, fx) for x, f in zip(v, pfmt)])
                continue
            v = [float(x) for x in s[2:2 + len(ifmt)]]
            if s[0] == 'V':
                k = per_set.get(sid, 0)
                per_set[sid] = k + 1
                if k % BRUSH_STRIDE:
                    continue
                nv += 1
            else:
                nc += 1
            for fx in (True, False):
                w = [conv(x, f, fx) for x, f in zip(v, ifmt)]
                br_rows[fx].append([m, sid, 1 if s[0] == 'C' else 0, i] + w + [0] * (5 - len(w)))
        br_params[model] = ps
        br_count.append((model, len(ps[True]), nv, nc))
    # relaxation: every row; parameters from the file's header
    rpath = os.path.join(golden, 'relax.txt')
    rp = [float(header_param(rpath, k)) for k in ('sigma_kappa', 'sigma_alpha', 'v_min', 'v_max', 'kappa_max',
                                                  'alpha_max')]
    rl = {True: [], False: []}
    for i, s in enumerate(rows(rpath)):
        v = [float(x) for x in s[2:6]]   # kappa alpha vx dt
        for fx in (True, False):
            rl[fx].append([int(s[0])] + [conv(x, 'S', fx) for x in v] + [i])
    # estimator: whole sequences
    es = {True: [], False: []}
    est_meta = []
    est_missing = []
    for q, name in enumerate(EST_SEQS):
        path = os.path.join(golden, 'est_%s.txt' % name)
        if not os.path.exists(path):
            est_missing.append(name)
            continue
        dt = float(header_param(path, 'dt'))
        rate = int(round(1.0 / dt))
        cfg_mask, cfg_v = 0, []
        for j, key in enumerate(EST_CFG_KEYS):
            v = header_param(path, key)
            cfg_mask |= (1 << j) if v is not None else 0
            cfg_v.append(float(v) if v is not None else 0.0)
        est_first = len(es[True])
        for i, s in enumerate(rows(path)):
            if len(s) != 1 + EST_NIN + 1 + 50:   # golden_est.out_columns()
                sys.exit('gen_vectors: %s row %d: %d columns' % (path, i, len(s)))
            t_us = lround(float(s[0]) * 1e6)
            if not 0 <= t_us < 2**31:
                sys.exit('gen_vectors: %s: time out of range' % path)
            v = [float(x) for x in s[1:1 + EST_NIN]]
            mask = int(float(s[1 + EST_NIN]))
            for fx in (True, False):
                es[fx].append([t_us, mask, i] + [est_word(x, 8 if j in EST_QL else 16, fx)
                                                 for j, x in enumerate(v)])
        est_meta.append((q, name, rate, est_first, len(es[True]) - est_first, cfg_mask, cfg_v))

    o = []
    o.append('/* generated by tests/target/gen_vectors.py from %s: do not edit */' % golden)
    o.append('#define TV_MF_STRIDE %d' % MF_STRIDE)
    o.append('#define TV_Q16_STRIDE %d' % Q16_STRIDE)
    o.append('#define TV_MF89_STRIDE %d' % MF89_STRIDE)
    o.append('#define TV_NTIRES %d' % len(meta))
    o.append('#define TV_MF_ROWS %d' % first)
    o.append('#define TV_Q16_ROWS %d' % len(q16))
    o.append('#define TV_MF89_ROWS %d' % len(r89))
    o.append('#define TV_TH_NP %d' % len(THERMAL_QL))
    o.append('#define TV_TH_F_ROWS %d' % len(tf))
    o.append('#define TV_TH_S_ROWS %d' % len(ts))
    o.append('#define TV_BR_ROWS %d' % len(br_rows[True]))
    for model, _, _, _ in BRUSH_MODELS:
        o.append('#define TV_%s_NSETS %d' % (model.upper(), len(br_params[model][True])))
    o.append('#define TV_RELAX_ROWS %d' % len(rl[True]))
    o.append('#define TV_EST_NSEQ %d' % len(est_meta))
    o.append('#define TV_EST_ROWS %d' % len(es[True]))
    o.append('#define TV_EST_NIN %d' % EST_NIN)
    o.append('#define TV_EST_NCFG %d' % len(EST_CFG_KEYS))
    o.append('static const tv_seq tv_est_seqs[%d] = {' % max(1, len(est_meta)))
    for q, name, rate, f0, n, cmask, _ in est_meta:
        o.append('    { %d, "%s", %du, %d, %d, 0x%xu },' % (q, name, rate, f0, n, cmask))
    if not est_meta:
        o.append('    { 0, "", 100u, 0, 0, 0u },')
    o.append('};')
    o.append('static const tv_tire tv_tires[TV_NTIRES] = {')
    for name, gname, f0, n in meta:
        o.append('    { "%s", "%s", %d, %d },' % (name, gname, f0, n))
    o.append('};')

    def arr(name, rowsw, width):
        o.append('static const uint32_t %s[][%d] = {' % (name, width))
        for r in rowsw:
            o.append('    { ' + ', '.join('0x%08Xu' % (x & 0xFFFFFFFF) for x in r) + ' },')
        o.append('};')
    o.append('#if GRIP_ARITH_FIXED')
    arr('tv_mf_in', fixed_in, 7)
    arr('tv_mf89_p', [p89_fixed], 21)
    arr('tv_mf89_in', [r[0] + [r[2]] for r in r89], 4)
    arr('tv_th_p', [tp_fixed], len(THERMAL_QL))
    arr('tv_th_f', [r[0] + [r[2]] for r in tf], 5)
    arr('tv_th_s', [r[0] + [r[2]] for r in ts], 9)
    for model, _, pfmt, _ in BRUSH_MODELS:
        arr('tv_%s_p' % model, br_params[model][True], len(pfmt))
    arr('tv_br', br_rows[True], 9)
    arr('tv_relax_p', [[q_word(x, 16) for x in rp]], 6)
    arr('tv_relax', rl[True], 6)
    arr('tv_est', es[True] or [[0] * (3 + EST_NIN)], 3 + EST_NIN)
    arr('tv_est_cfg', [[q_word(x, 16) for x in m[6]] for m in est_meta] or [[0] * len(EST_CFG_KEYS)],
        len(EST_CFG_KEYS))
    o.append('#else')
    arr('tv_mf_in', float_in, 7)
    arr('tv_mf89_p', [p89_float], 21)
    arr('tv_mf89_in', [r[1] + [r[2]] for r in r89], 4)
    arr('tv_th_p', [tp_float], len(THERMAL_QL))
    arr('tv_th_f', [r[1] + [r[2]] for r in tf], 5)
    arr('tv_th_s', [r[1] + [r[2]] for r in ts], 9)
    for model, _, pfmt, _ in BRUSH_MODELS:
        arr('tv_%s_p' % model, br_params[model][False], len(pfmt))
    arr('tv_br', br_rows[False], 9)
    arr('tv_relax_p', [[f_word(x) for x in rp]], 6)
    arr('tv_relax', rl[False], 6)
    arr('tv_est', es[False] or [[0] * (3 + EST_NIN)], 3 + EST_NIN)
    arr('tv_est_cfg', [[f_word(x) for x in m[6]] for m in est_meta] or [[0] * len(EST_CFG_KEYS)],
        len(EST_CFG_KEYS))
    o.append('#endif')
    arr('tv_q16', q16, 4)
    with open(out, 'w') as f:
        f.write('\n'.join(o) + '\n')
    print('# gen_vectors: %d MF rows (%d tyres, every %d-th), %d Q15.16 rows (every %d-th per primitive), '
          '%d MF89 rows (every %d-th), %d MF thermal force rows (every %d-th), %d MF thermal time steps (all)'
          % (first, len(meta), MF_STRIDE, len(q16), Q16_STRIDE, len(r89), MF89_STRIDE, len(tf), THERMAL_F_STRIDE,
             len(ts)))
    print('# gen_vectors: brush family %s (V rows: %s, C rows: all); relaxation %d rows (all); '
          'estimator %s%s' % (
              ', '.join('%s %d sets %d V + %d C rows' % c for c in br_count),
              'all' if BRUSH_STRIDE == 1 else 'every %d-th per set' % BRUSH_STRIDE, len(rl[True]),
              ', '.join('%s %d steps at %d Hz' % (m[1], m[4], m[2]) for m in est_meta) or 'no sequence',
              ('; absent: ' + ' '.join(est_missing)) if est_missing else ''))


if __name__ == '__main__':
    main()
