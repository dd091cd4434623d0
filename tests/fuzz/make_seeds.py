#!/usr/bin/env python3
"""Writes the small seed corpora of tests/fuzz/corpus/<harness>/ (run once;
the files are kept in the repository). Stdlib only; deterministic."""
import os
import random
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def w(v, scale):
    """A word as fuzz_common.h decodes it: round(v * scale) as int32."""
    x = int(round(v * scale))
    return struct.pack('<i', max(-2**31 + 3, min(2**31 - 1, x)))


def qs(v):
    return w(v, 65536.0)


def ql(v):
    return w(v, 256.0)


def put(harness, name, data):
    d = os.path.join(HERE, 'corpus', harness)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), 'wb') as f:
        f.write(data)


def main():
    rnd = random.Random(8)
    # fuzz_mf: set, options, kappa alpha gamma fz p vx
    ops = [(0.0, 0.0, 0.0, 4000.0, 0.0, 20.0), (-0.1, 0.05, 0.02, 3000.0, 220000.0, 15.0),
           (0.3, -0.2, -0.05, 8000.0, 0.0, 30.0), (0.05, 0.1, 0.0, 0.0, 0.0, 10.0),
           (1.5, 1.5, 0.5, 40000.0, 500000.0, 300.0), (-1.0, 0.02, 0.0, 2000.0, 0.0, 0.5)]
    for i, (k, a, g, fz, p, vx) in enumerate(ops):
        put('mf', 'op%d' % i, bytes([i, (i * 7) & 0x1F]) + qs(k) + qs(a) + qs(g) + ql(fz) + ql(p) + qs(vx))
    # ... then phit omega, flags (1 no limits, 2 turn slip camber form, 4 an
    # invalid option bit, 8 raw request, 16 grip_mf_eval_ext: no spin
    # argument), the request word of
    # grip_mf_eval_ext (0x7FFFF: every channel; 1 << 24: turn slip on,
    # 1 << 26: no limits). Sets 5, 7, 8, 9 (FSAE, MF 6.1, 6.2, PacejkaBook)
    # have the turn-slip coefficients; option byte bit 7 asks for turn slip.
    ts = [(5, 0x80, 0.5, 0.0, 0, 0x7FFFF), (7, 0x00, -2.0, 45.0, 0, 0x7FFFF | (1 << 24)),
          (8, 0x80, 1.0, 0.0, 2, 0x7FFFF), (9, 0x80, 0.0, 0.0, 1, 0x7FFFF | (1 << 26)),
          (6, 0x80, 1.0, 0.0, 0, 0x7FFFF), (7, 0x00, 3.0, 0.0, 0, (1 << 24) | (1 << 25)),
          (5, 0x80, 2.0, 30.0, 16, 0x7FFFF)]
    for i, (st, opt, ph, om, flags, req) in enumerate(ts):
        k, a, g, fz, p, vx = ops[1 + i % 3]
        put('mf', 'ts%d' % i, bytes([st, opt]) + qs(k) + qs(a) + qs(g) + ql(fz) + ql(p) + qs(vx) + qs(ph) + qs(om)
            + bytes([flags]) + req.to_bytes(4, 'little'))
    # fuzz_mf89: alpha fz gamma lo hi
    for i, (a, fz, g) in enumerate([(0.1, 4000.0, 0.0), (-0.4, 9000.0, 0.1), (0.01, 100.0, -0.05)]):
        put('mf89', 'op%d' % i, qs(a) + ql(fz) + qs(g) + ql(1000.0) + ql(8000.0))
    # fuzz_mf_thermal: mode, t_init, dt, t, steps
    for i in range(3):
        b = bytes([0]) + qs(20.0 + 10 * i) + qs(0.01) + qs(50.0)
        for _ in range(6):
            b += qs(rnd.uniform(0, 40)) + qs(rnd.uniform(-0.3, 0.3)) + qs(rnd.uniform(-0.5, 0.5)) + \
                ql(rnd.uniform(0, 8000)) + qs(rnd.uniform(-10, 60))
        put('mf_thermal', 'steps%d' % i, b)
    # fuzz_brush: model, kappa alpha gamma fz vx
    for m in range(4):
        put('brush', 'model%d' % m, bytes([m]) + qs(-0.1) + qs(0.05) + qs(0.02) + ql(4000.0) + qs(20.0))
        put('brush', 'model%d_hi' % m, bytes([m]) + qs(0.8) + qs(0.5) + qs(0.15) + ql(9000.0) + qs(50.0))
    # fuzz_can mode 0: config, frames [dt lo hi][sel][len][flags][data][extract 3 bytes]
    b = bytes([0, 9, 2, 0, 5])
    for i in range(40):
        b += struct.pack('<h', 750) + bytes([i % 7 * 2 + 1, 8, 0]) + bytes(rnd.randrange(256) for _ in range(8))
        b += bytes([rnd.randrange(32), rnd.randrange(1, 17), rnd.randrange(8)])
    put('can', 'frames', b)
    # fuzz_can mode 1: the RAV4 text table, then frames from the same bytes
    with open(os.path.join(ROOT, 'tests/data/comma2k19-rav4/rav4.sigtab'), 'rb') as f:
        put('can', 'table', b'\x01' + f.read())
    # fuzz_candump: lines of the RAV4 log and the documented forms
    with open(os.path.join(ROOT, 'tests/data/comma2k19-rav4/rav4_bus0.log'), 'rb') as f:
        lines = f.read().splitlines()[:40]
    put('candump', 'rav4', b'\n'.join(lines) + b'\n')
    put('candump', 'forms', b'(1436509052.249713) vcan0 123#DEADBEEF\n'
        b'(1436509052.249713) vcan0 12345678#00\n(1436509052.249713) vcan0 123#R\n'
        b'(1436509052.249713) vcan0 123#R3\n(1436509052.249713) vcan0 123##1112233\n'
        b'(1436509052.249713) vcan0 20000080#0000000000000000\n(1436509052.2) can1 7FF#11.22.33 T\n')
    # fuzz_est: set, then steps [valid mask 3 bytes][17 inputs]: steady driving,
    # a steady left and a right turn (wheel speeds, steer, yaw, ax, ay, speed valid)
    for k, (v, steer, yaw, ay) in enumerate([(20.0, 0.0, 0.0, 0.0), (25.0, 0.05, 0.2, 4.0),
                                             (15.0, -0.1, -0.35, -6.0)]):
        b = bytes([k])
        for _ in range(60):
            b += bytes([0xFF, 0x01, 0x00])
            b += qs(v) * 4 + qs(steer) + qs(yaw) + qs(0.0) + qs(ay) + qs(v) + ql(0.0) * 8
        put('est', 'drive%d' % k, b)
        # fuzz_chain: the same drive behind an identity calibration (offset 0,
        # gain byte 85 = 1.0, delay 0) and behind a 3-step delay with offsets
        ident = bytes([0, 85, 0]) * 9
        skewed = bytes([6, 100, 3]) * 9
        put('chain', 'drive%d' % k, b[:1] + ident + b[1:])
        put('chain', 'skewed%d' % k, b[:1] + skewed + b[1:])
    # fuzz_tir: the small shared files and every reader test file
    for src in ['tests/data/chrono-tir/mf_185_80R14.tir', 'tests/data/mfeval-tir/MagicFormula61_Paramerters.tir',
                'tests/data/mfeval-tir/PacejkaBook_Defaults.tir']:
        d = os.path.join(HERE, 'corpus', 'tir')
        os.makedirs(d, exist_ok=True)
        shutil.copy(os.path.join(ROOT, src), os.path.join(d, os.path.basename(src)))
    tdir = os.path.join(ROOT, 'tests/data/tir')
    for n in sorted(os.listdir(tdir)):
        if n.endswith('.tir'):
            shutil.copy(os.path.join(tdir, n), os.path.join(HERE, 'corpus', 'tir', n))


if __name__ == '__main__':
    main()
