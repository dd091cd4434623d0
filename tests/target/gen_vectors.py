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
                 must run step by step) of mf_thermal.txt, with its P row.
Inputs are stored exactly as the host tests convert them: fixed build
lround(v * 2^16) (QS) / lround(v * 2^8) (QL) as in tests/unit/test_mf_golden.c,
float build the IEEE single nearest to the double (the C cast (float)v), as
raw 32-bit words. Stdlib only.
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
    o.append('#else')
    arr('tv_mf_in', float_in, 7)
    arr('tv_mf89_p', [p89_float], 21)
    arr('tv_mf89_in', [r[1] + [r[2]] for r in r89], 4)
    arr('tv_th_p', [tp_float], len(THERMAL_QL))
    arr('tv_th_f', [r[1] + [r[2]] for r in tf], 5)
    arr('tv_th_s', [r[1] + [r[2]] for r in ts], 9)
    o.append('#endif')
    arr('tv_q16', q16, 4)
    with open(out, 'w') as f:
        f.write('\n'.join(o) + '\n')
    print('# gen_vectors: %d MF rows (%d tyres, every %d-th), %d Q15.16 rows (every %d-th per primitive), '
          '%d MF89 rows (every %d-th), %d MF thermal force rows (every %d-th), %d MF thermal time steps (all)'
          % (first, len(meta), MF_STRIDE, len(q16), Q16_STRIDE, len(r89), MF89_STRIDE, len(tf), THERMAL_F_STRIDE,
             len(ts)))


if __name__ == '__main__':
    main()
