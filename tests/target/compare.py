#!/usr/bin/env python3
"""compare.py GOLDEN_DIR OUTPUT ARITH - checks the output of target_main.c
(from qemu or the host) against the golden reference with the tolerances of
the host tests:

  Magic Formula (tests/unit/test_mf_golden.c), every status GRIP_OK and
    float: |err| <= 1e-4 Fz (forces N, moments N m)
    fixed: |err| <= 0.005 D + 4 LSB_F (forces; D = peak force of the row),
           |err| <= 0.01 max|Mz| (rows within 10 % of the load) + 4 LSB_M
           LSB_F = FNOMIN 2^-16 N, LSB_M = FNOMIN R0 2^-16 N m
  Q15.16 primitives (tests/unit/test_q16.c): the bounds of its table
  MF 1989 (tests/unit/test_mf89.c), status GRIP_OK and
    float: |err| <= 1e-4 Fz;  fixed: |err| <= 0.005 peak + 0.03 N
  MF thermal (tests/unit/test_mf_thermal.c): forces at a temperature,
    status GRIP_OK, float 1e-4 Fz, fixed 0.005 peak + 0.03 N; time series
    (closed loop per scenario), forces as before, heat flux q within
    tol_F * vs + (1e-5 float, 0.005 fixed) * |q|, temperature within
    (2e-4 exc + 0.002 K float, 0.005 exc + 0.05 K fixed) with exc the
    largest reference excursion from the scenario's start so far; status
    GRIP_OK, or WARN_CLAMPED when the reference is within 1 K of t_max
  brush family (tests/unit/test_brush.c), normalized by f0 = mu_s Fz (Fz
    clamped to [fz_min, fz_max]) and l (1 for the brush model):
    max(|err Fx|, |err Fy|) / f0 and |err Mz| / (f0 l) <= 1e-4 float, 1e-3
    fixed; status GRIP_OK on V rows, GRIP_WARN_CLAMPED on C rows; FIALA's
    Fx exactly 0
  relaxation (tests/unit/test_relax.c), on kappa' and alpha', status OK or
    WARN_CLAMPED: float |err| <= 1e-4 max(|want|, 0.01) + 1e-7; fixed
    |err| <= 2e-4 + c, c carried from row to row as the host test does
    (c = exp(-v dt / sigma) c + 5.6e-6 / dt |x - x'_prev|)
  estimator (tests/unit/test_est_golden.c), over each whole sequence,
    status GRIP_OK on every step (GRIP_WARN_RATE where F_RATE), max |err| of
                 vx      beta    yaw_rate  yaw_rate_ref  mu      Fz     Fy
    float        2e-4    5e-5    5e-6      1e-4          2e-4    0.02   1e-3 peak
    fixed        3e-3    3e-3    2e-4      3e-3          6e-3    0.5    3e-3 peak
    (peak: largest reference |Fy| of the sequence); validity mask differing
    on no row (float), on at most 1 % of the rows (fixed)
Prints TAP comment lines with the figures; exit status 1 on any failure.
Stdlib only.
"""
import math
import os
import re
import struct
import sys

from gen_vectors import header_param   # same directory: the golden files' header

Q16_FUNCS = ['mul', 'div', 'sqrt', 'atan', 'atan2', 'sin', 'cos', 'exp', 'log']
# name: (abs LSB, rel_x, rel_y) as tests/unit/test_q16.c
Q16_BOUNDS = {'mul': (0.5, 0, 0), 'div': (0.5, 0, 0), 'sqrt': (0.5, 0, 0), 'atan': (0.6, 0, 0),
              'atan2': (0.6, 0, 0), 'sin': (0.6, 1e-9, 0), 'cos': (0.6, 1e-9, 0), 'exp': (0.6, 0, 5e-9),
              'log': (0.6, 0, 0)}
LSB = 1.0 / 65536.0


def s32(w):
    return w - (1 << 32) if w & 0x80000000 else w


def val(w, fmt, fixed):
    """A result word as a double: fmt 'qs' or 'ql'."""
    if fixed:
        return s32(w) / (65536.0 if fmt == 'qs' else 256.0)
    return struct.unpack('<f', struct.pack('<I', w))[0]


def as_built(v, f, fixed):
    """A parameter value as the build holds it (S QS, L QL, I int)."""
    if f == 'I':
        return float(int(v))
    if fixed:
        sc = 65536.0 if f == 'S' else 256.0
        return math.floor(abs(v) * sc + 0.5) * math.copysign(1.0, v) / sc
    return struct.unpack('<f', struct.pack('<f', v))[0]


# brush models: (name, parameter formats, index of mu_s, of l or None, of fz_min, of fz_max)
BRUSH = [('fiala', 'LSSLLS', 1, 2, 3, 4), ('brush', 'LSSSILLSS', 1, None, 5, 6),
         ('sakai', 'LLSSSLLSS', 2, 4, 5, 6), ('neofiala', 'SSLLSSSISSSSSSLLSSLLLSSSS', 4, 0, 19, 20)]
# estimator output columns (golden_est.out_columns) and their formats
EST_COLS = (['vx', 'vy', 'beta', 'yaw_rate', 'yaw_rate_ref', 'yaw_error', 'delta', 'mu', 'mu_conf'] +
            ['%s%d' % (q, i) for q in ('fz', 'kappa', 'alpha', 'fx', 'fy', 'mz', 'util') for i in range(4)] +
            ['fy_axle0', 'fy_axle1', 'util_axle0', 'util_axle1', 'fy_margin_front', 'steer_char', 'valid',
             'flags'])
EST_QL = set(['%s%d' % (q, i) for q in ('fz', 'fx', 'fy', 'mz') for i in range(4)] +
             ['fy_axle0', 'fy_axle1', 'fy_margin_front'])
# asserted quantities: name, columns, float tol, fixed tol (None: relative to the Fy peak)
EST_TOL = [('vx', ['vx'], 2e-4, 3e-3), ('beta', ['beta'], 5e-5, 3e-3), ('yaw_rate', ['yaw_rate'], 5e-6, 2e-4),
           ('yaw_rate_ref', ['yaw_rate_ref'], 1e-4, 3e-3), ('mu', ['mu'], 2e-4, 6e-3),
           ('Fz', ['fz%d' % i for i in range(4)], 0.02, 0.5), ('Fy', ['fy%d' % i for i in range(4)], 1e-3, 3e-3)]
# printed only (as the host test does)
EST_INFO = [('mu_conf', ['mu_conf']), ('Fx', ['fx%d' % i for i in range(4)]),
            ('alpha', ['alpha%d' % i for i in range(4)]), ('kappa', ['kappa%d' % i for i in range(4)])]


def check_brush(golden, recs, fixed, fails):
    tol = 1e-3 if fixed else 1e-4
    for m, (model, pfmt, i_mu, i_l, i_lo, i_hi) in enumerate(BRUSH):
        g = rows(os.path.join(golden, 'brush_%s.txt' % model))
        ps = {}
        for r in g:
            if r[0] == 'P':
                ps[int(r[1])] = [as_built(float(x), f, fixed) for x, f in zip(r[2:], pfmt)]
        got = [x for x in recs if x[0] == m]
        nin = {'fiala': 2, 'brush': 3, 'sakai': 3, 'neofiala': 5}[model]
        i_fz = {'fiala': 3, 'brush': 3, 'sakai': 4, 'neofiala': 5}[model]   # column of Fz
        me = [0.0] * 4
        worst = 0.0
        over = bad = nc = 0
        for _, row, st, wfx, wfy, wmz, wrh in got:
            r = g[row]
            p = ps[int(r[1])]
            fz = float(r[i_fz])
            want = [float(x) for x in r[2 + nin:6 + nin]]
            f0 = p[i_mu] * min(max(fz, p[i_lo]), p[i_hi])
            ll = p[i_l] if i_l is not None else 1.0
            gv = [val(wfx, 'ql', fixed), val(wfy, 'ql', fixed), val(wmz, 'ql', fixed), val(wrh, 'qs', fixed)]
            e = [abs(a - b) if math.isfinite(a) else math.inf for a, b in zip(gv, want)]
            ef = max(e[0], e[1]) / f0
            em = e[2] / (f0 * ll)
            for j in range(4):
                me[j] = max(me[j], e[j] / (f0 * ll if j == 2 else (f0 if j < 2 else 1.0)))
            worst = max(worst, ef / tol, em / tol)
            if not (ef <= tol and em <= tol):
                over += 1
            st = st - (1 << 32) if st & 0x80000000 else st
            nc += r[0] == 'C'
            if st != (1 if r[0] == 'C' else 0):
                bad += 1
            if model == 'fiala' and gv[0] != 0.0:
                bad += 1
        print('# brush %-8s %4d rows (%d clamped): max |err| Fx/(mu Fz) %.3g Fy/(mu Fz) %.3g Mz/(mu Fz l) %.3g '
              'rh %.3g; worst |err|/tol %.3f' % (model, len(got), nc, me[0], me[1], me[2], me[3], worst))
        if not got:
            fails.append('brush %s: no results' % model)
        if over or bad:
            fails.append('brush %s: %d rows beyond the tolerance, %d with a wrong status (or FIALA Fx != 0)' % (
                model, over, bad))


def check_relax(golden, recs, fixed, fails):
    path = os.path.join(golden, 'relax.txt')
    g = rows(path)
    sk, sa, vmin, vmax, kmax, amax = [float(header_param(path, k)) for k in (
        'sigma_kappa', 'sigma_alpha', 'v_min', 'v_max', 'kappa_max', 'alpha_max')]
    prev = None
    pk = pa = ck = ca = 0.0
    mk = ma = worst = 0.0
    over = bad = 0
    for row, st, wk, wa in recs:
        r = [float(x) for x in g[row]]
        sid, k, a, v, dt, want_k, want_a = int(r[0]), r[2], r[3], r[4], r[5], r[6], r[7]
        if sid != prev:
            prev, pk, pa, ck, ca = sid, 0.0, 0.0, 0.0, 0.0
        if fixed:
            vv = min(max(abs(v), vmin), vmax) * dt
            tdt = (lambda j: 2.0 * 2.8e-6 / dt * abs(j) if dt > 0.0 else 0.0)
            ck = math.exp(-vv / sk) * ck + tdt(max(min(k, kmax), -kmax) - pk)
            ca = math.exp(-vv / sa) * ca + tdt(max(min(a, amax), -amax) - pa)
            tk, ta = 2e-4 + ck, 2e-4 + ca
        else:
            tk = 1e-4 * max(abs(want_k), 0.01) + 1e-7
            ta = 1e-4 * max(abs(want_a), 0.01) + 1e-7
        gk, ga = val(wk, 'qs', fixed), val(wa, 'qs', fixed)
        ek = abs(gk - want_k) if math.isfinite(gk) else math.inf
        ea = abs(ga - want_a) if math.isfinite(ga) else math.inf
        mk, ma = max(mk, ek), max(ma, ea)
        worst = max(worst, ek / tk, ea / ta)
        if not (ek <= tk and ea <= ta):
            over += 1
        st = st - (1 << 32) if st & 0x80000000 else st
        if st not in (0, 1):
            bad += 1
        pk, pa = want_k, want_a
    print("# relax %d steps: max |err| kappa' %.3g, alpha' %.3g rad; worst |err|/tol %.3f" % (len(recs), mk, ma,
                                                                                            worst))
    if not recs:
        fails.append('relax: no results')
    if over or bad:
        fails.append('relax: %d steps beyond the tolerance, %d with a wrong status' % (over, bad))


def check_est(golden, seqs, recs, fixed, fails):
    for q, (rate, name) in sorted(seqs.items()):
        g = rows(os.path.join(golden, 'est_%s.txt' % name))
        got = [x for x in recs if x[0] == q]
        c_out = 1 + 18 + 1          # time, the 18 inputs, the valid mask
        peak = max(abs(float(r[c_out + EST_COLS.index('fy%d' % i)])) for r in g for i in range(4))
        me = {}
        mask_diff = bad = 0
        num = [(j, col, 'ql' if col in EST_QL else 'qs') for j, col in enumerate(EST_COLS)
               if col not in ('steer_char', 'valid', 'flags')]
        j_valid = EST_COLS.index('valid')
        j_flags = EST_COLS.index('flags')
        for _, row, st, words in got:
            r = g[row]
            for j, col, fmt in num:
                v = val(words[j], fmt, fixed)
                e = abs(v - float(r[c_out + j])) if math.isfinite(v) else math.inf
                if e > me.get(col, -1.0):
                    me[col] = e
            if int(float(r[c_out + j_valid])) != words[j_valid]:
                mask_diff += 1
            # GRIP_WARN_RATE (2) exactly where the reference flags F_RATE
            f_rate = (int(float(r[c_out + j_flags])) >> 17) & 1
            if st != (2 if f_rate else 0):
                bad += 1
        allowed_diff = 0.01 * len(got) if fixed else 0.0
        parts = []
        worst = 0.0
        for qn, cols, tf, tx in EST_TOL:
            e = max(me.get(c, 0.0) for c in cols)
            tol = tx if fixed else tf
            if qn == 'Fy':
                tol *= peak
            worst = max(worst, e / tol)
            parts.append('%s %.3g' % (qn, e))
            if not e <= tol:
                fails.append('estimator %s: %s max |err| %.3g beyond %.3g' % (name, qn, e, tol))
        info = ' '.join('%s %.3g' % (qn, max(me.get(c, 0.0) for c in cols)) for qn, cols in EST_INFO)
        print('# estimator %-14s %4d steps at %d Hz: max |err| %s (not asserted: %s); Fy peak %.0f N; '
              'worst |err|/tol %.3f; valid mask differs on %d rows' % (name, len(got), rate, ' '.join(parts),
                                                                       info, peak, worst, mask_diff))
        if len(got) != len(g):
            fails.append('estimator %s: %d of %d steps' % (name, len(got), len(g)))
        if bad:
            fails.append('estimator %s: %d steps with a status other than OK (WARN_RATE with F_RATE)' % (name, bad))
        if mask_diff > allowed_diff:
            fails.append('estimator %s: valid mask differs on %d rows (allowed %g)' % (name, mask_diff,
                                                                                       allowed_diff))


def rows(path):
    out = []
    with open(path) as f:
        for line in f:
            s = line.split()
            if s and not s[0].startswith('#'):
                out.append(s)
    return out


def main():
    golden, outp, arith = sys.argv[1], sys.argv[2], sys.argv[3]
    fixed = arith == 'fixed'
    with open(os.path.join(golden, 'mf_params.c')) as f:
        tires = re.findall(r'\{ "([^"]+)", "[^"]*", &\w+, "([^"]+)" \}', f.read())
    lines = [l.split() for l in open(outp, encoding='ascii', errors='replace')]
    fails = []
    if not lines or lines[0] != ['B', arith]:
        fails.append('first line is not "B %s"' % arith)
    ends = [l for l in lines if l and l[0] == 'E']
    if len(ends) != 1 or int(ends[0][1], 16) != len(lines) - 1:
        fails.append('output incomplete (no or wrong E line): the program did not finish')
    params = {}
    mf = {}
    q16 = []
    f89 = []
    th_f = []
    th_s = []
    br = []
    rl = []
    seqs = {}
    est = []
    for l in lines:
        if not l:
            continue
        if l[0] == 'P':
            params[int(l[1], 16)] = [int(x, 16) for x in l[2:]]
        elif l[0] == 'M':
            mf.setdefault(int(l[1], 16), []).append([int(x, 16) for x in l[2:]])
        elif l[0] == 'Q':
            q16.append([int(x, 16) for x in l[1:]])
        elif l[0] == 'F':
            f89.append([int(x, 16) for x in l[1:]])
        elif l[0] == 'H':
            th_f.append([int(x, 16) for x in l[1:]])
        elif l[0] == 'S':
            th_s.append([int(x, 16) for x in l[1:]])
        elif l[0] == 'R':
            br.append([int(x, 16) for x in l[1:]])
        elif l[0] == 'L':
            rl.append([int(x, 16) for x in l[1:]])
        elif l[0] == 'N':
            seqs[int(l[1], 16)] = (int(l[2], 16), l[3])
        elif l[0] == 'T':
            w = [int(x, 16) for x in l[1:]]
            est.append((w[0], w[1], s32(w[2]), w[3:]))
        elif l[0] == 'X':
            fails.append(' '.join(l))
    names = ['Fx0', 'Fy0', 'Mz0', 'Fx', 'Fy', 'Mz']
    n_mf = 0
    for t, (name, gname) in enumerate(tires):
        g = rows(os.path.join(golden, gname))
        gin = [[float(x) for x in r[:6]] for r in g]
        gout = [[float(x) for x in r[6:12]] for r in g]
        if t not in params or t not in mf:
            fails.append('%s: no results' % name)
            continue
        pw = params[t]
        fmts = ['ql', 'qs', 'ql', 'qs', 'qs', 'qs', 'qs', 'qs', 'qs', 'qs', 'qs', 'qs', 'qs', 'qs', 'qs', 'qs']
        (fnomin, lfzo, nompres, r0, pdx1, pdx2, pdx3, ppx3, ppx4, lmux, pdy1, pdy2, pdy3, ppy3, ppy4,
         lmuy) = [val(w, f, fixed) for w, f in zip(pw, fmts)]
        fz_sorted = sorted((gin[i][3], max(abs(gout[i][2]), abs(gout[i][5]))) for i in range(len(g)))
        mzpk_of = {}
        worst = [0.0] * 6
        maxerr = [0.0] * 6
        over = [0] * 6
        bad_status = 0
        per_fz = [0.0] * 6      # max |err| / Fz (Mz: / (Fz R0)) at Fz >= 0.05 FNOMIN
        for rec in mf[t]:
            i = rec[0]
            if rec[1] != 0 or rec[2] != 0:
                bad_status += 1
            kappa, alpha, gamma, fz, p, vx = gin[i]
            fz = max(fz, 0.0)
            fz0 = fnomin * lfzo
            dfz = (fz - fz0) / fz0
            dpi = (p - nompres) / nompres if nompres > 0 and p > 0 else 0.0
            g2 = gamma * gamma
            dx = abs((pdx1 + pdx2 * dfz) * (1 + ppx3 * dpi + ppx4 * dpi * dpi) * (1 - pdx3 * g2) * lmux * fz)
            dy = abs((pdy1 + pdy2 * dfz) * (1 + ppy3 * dpi + ppy4 * dpi * dpi) * (1 - pdy3 * g2) * lmuy * fz)
            if fz not in mzpk_of:   # the golden files use few distinct loads: one scan per load
                mzpk_of[fz] = max([m for (f, m) in fz_sorted if abs(f - fz) <= 0.1 * fz] or [0.0])
            mzpk = mzpk_of[fz]
            if fixed:
                lf = 4.0 * fnomin / 65536.0
                lm = 4.0 * fnomin * r0 / 65536.0
                allowed = [0.005 * dx + lf, 0.005 * dy + lf, 0.01 * mzpk + lm] * 2
            else:
                allowed = [1e-4 * fz] * 6
            for j in range(6):
                got = val(rec[3 + j], 'ql', fixed)
                e = abs(got - gout[i][j]) if math.isfinite(got) else math.inf
                maxerr[j] = max(maxerr[j], e)
                ratio = e / allowed[j] if allowed[j] > 0 else (math.inf if e > 0 else 0.0)
                worst[j] = max(worst[j], ratio)
                if not ratio <= 1.0:
                    over[j] += 1
                if fz >= 0.05 * fnomin:
                    per_fz[j] = max(per_fz[j], e / (fz * (r0 if j in (2, 5) else 1.0)))
            n_mf += 1
        print('# MF %-28s %4d rows: max |err| %s; worst |err|/tol %.3f%s' % (
            name, len(mf[t]), ' '.join('%s %.3g' % (names[j], maxerr[j]) for j in range(6)), max(worst),
            '' if bad_status == 0 else '; %d rows with status != OK' % bad_status))
        print('# MF %-28s max |err| / Fz (Mz: / (Fz R0)), Fz >= 0.05 FNOMIN: %s' % (
            name, ' '.join('%s %.2g' % (names[j], per_fz[j]) for j in range(6))))
        if bad_status:
            fails.append('%s: %d rows with status != OK' % (name, bad_status))
        for j in range(6):
            if over[j]:
                fails.append('%s %s: %d rows beyond the tolerance (worst %.2f x)' % (name, names[j], over[j],
                                                                                    worst[j]))
    # Q15.16
    gq = None
    if q16:
        with open(os.path.join(golden, 'q16.txt')) as f:
            gq = [l.split() for l in f if l.strip() and not l.startswith('#')]
        per = {}
        for fid, row, w in q16:
            fn = Q16_FUNCS[fid]
            r = gq[row]
            if r[0] != fn:
                fails.append('q16 row %d is %s, not %s' % (row, r[0], fn))
                continue
            a = int(r[1])
            want = float(r[3])
            got = s32(w) * LSB
            ab, rx, ry = Q16_BOUNDS[fn]
            bound = ab * LSB + rx * abs(a * LSB) + ry * abs(want)
            e = abs(got - want)
            st = per.setdefault(fn, [0, 0.0, 0])
            st[0] += 1
            st[1] = max(st[1], e)
            if not e <= bound:
                st[2] += 1
        print('# Q15.16 %d rows, max |err| in LSB: %s' % (
            len(q16), ' '.join('%s %.3f' % (fn, per[fn][1] / LSB) for fn in Q16_FUNCS if fn in per)))
        for fn, st in per.items():
            if st[2]:
                fails.append('q16 %s: %d rows beyond the bound' % (fn, st[2]))
        if len(per) != len(Q16_FUNCS):
            fails.append('q16: primitives missing')
    # MF 1989
    if f89:
        g89 = rows(os.path.join(golden, 'mf89.txt'))
        maxe = 0.0
        worst = 0.0
        over = 0
        bad = 0
        for row, s, w in f89:
            r = g89[row]
            fz, want, peak = float(r[2]), float(r[4]), float(r[5])
            got = val(w, 'ql', fixed)
            if s != 0:
                bad += 1
            tol = 0.005 * peak + 0.03 if fixed else 1e-4 * max(fz, 0.0)
            e = abs(got - want) if math.isfinite(got) else math.inf
            maxe = max(maxe, e)
            ratio = e / tol if tol > 0 else (math.inf if e > 0 else 0.0)
            worst = max(worst, ratio)
            if not ratio <= 1.0:
                over += 1
        print('# MF89 %d rows: max |err| %.3g N, worst |err|/tol %.3f' % (len(f89), maxe, worst))
        if over or bad:
            fails.append('mf89: %d rows beyond the tolerance, %d with status != OK' % (over, bad))
    else:
        fails.append('no MF89 results')
    # MF thermal
    gth = rows(os.path.join(golden, 'mf_thermal.txt'))
    t_max = [float(r[35]) for r in gth if r[0] == 'P'][0]
    tolf = (lambda fz, pk: 0.005 * pk + 0.03) if fixed else (lambda fz, pk: 1e-4 * fz)
    qrel = 0.005 if fixed else 1e-5
    tolt = (lambda e: 0.005 * e + 0.05) if fixed else (lambda e: 2e-4 * e + 0.002)
    if th_f:
        worst = maxe = 0.0
        over = bad = 0
        for row, s, wx, wy in th_f:
            r = gth[row]
            fz, want_x, want_y, pk = float(r[3]), float(r[5]), float(r[6]), float(r[7])
            tol = tolf(fz, pk)
            e = max(abs(val(wx, 'ql', fixed) - want_x), abs(val(wy, 'ql', fixed) - want_y))
            e = e if math.isfinite(e) else math.inf
            maxe = max(maxe, e)
            if tol > 0:
                worst = max(worst, e / tol)
            if s != 0:
                bad += 1
            if not e <= tol:
                over += 1
        print('# MF thermal forces %d rows: max |err| %.3g N, worst |err|/tol %.3f' % (len(th_f), maxe, worst))
        if over or bad:
            fails.append('mf_thermal forces: %d rows beyond the tolerance, %d with status != OK' % (over, bad))
    else:
        fails.append('no MF thermal force results')
    if th_s:
        scen = None
        t_init = exc = 0.0
        wf = wq = wt = 0.0
        mf_ = mq = mt = 0.0
        over = bad = 0
        for row, s, wx, wy, wqq, wtt in th_s:
            r = [float(x) for x in gth[row][1:]]
            k, fz, tb, wfx, wfy, wqr, wvs, wta, pk = int(r[0]), r[4], r[7], r[8], r[9], r[10], r[11], r[12], r[13]
            if k != scen:
                scen, t_init, exc = k, tb, 0.0
            exc = max(exc, abs(wta - t_init))
            s = s - (1 << 32) if s & 0x80000000 else s
            if not (s == 0 or (s == 1 and wta >= t_max - 1.0)):
                bad += 1
            tf_, tq_, tt_ = tolf(fz, pk), tolf(fz, pk) * wvs + qrel * abs(wqr), tolt(exc)
            ef = max(abs(val(wx, 'ql', fixed) - wfx), abs(val(wy, 'ql', fixed) - wfy))
            eq = abs(val(wqq, 'ql', fixed) - wqr)
            et = abs(val(wtt, 'qs', fixed) - wta)
            mf_, mq, mt = max(mf_, ef), max(mq, eq), max(mt, et)
            if tf_ > 0:
                wf = max(wf, ef / tf_)
            if tq_ > 0:
                wq = max(wq, eq / tq_)
            wt = max(wt, et / tt_)
            if not (ef <= tf_ and eq <= tq_ + 1e-9 and et <= tt_):
                over += 1
        print('# MF thermal series %d steps: max |err| F %.3g N, q %.3g W, T %.3g K; worst |err|/tol F %.3f q %.3f T %.3f'
              % (len(th_s), mf_, mq, mt, wf, wq, wt))
        if over or bad:
            fails.append('mf_thermal series: %d steps beyond the tolerance, %d with a wrong status' % (over, bad))
    else:
        fails.append('no MF thermal series results')
    if n_mf == 0:
        fails.append('no Magic Formula results')
    check_brush(golden, br, fixed, fails)
    check_relax(golden, rl, fixed, fails)
    check_est(golden, seqs, est, fixed, fails)
    if not seqs:
        fails.append('no estimator sequence')
    for f in fails:
        print('# FAIL ' + f)
    return 1 if fails else 0


if __name__ == '__main__':
    sys.exit(main())
