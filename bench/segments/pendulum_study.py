#!/usr/bin/env python3
"""Convergence study of scenes/flexible_pendulum.toml (the Berzeri-Shabana
flexible pendulum) in segments, elements, stiffening and dt against the Exudyn
reference bench/reference/flexible_pendulum.csv.

Each case is the scene file with `elements`, `segments`, `reference`,
`stiffening` and `dt` replaced, run by `ffr run` (release build, path in
$FFR or target/release/ffr). The error is the largest distance between the
run's tip and the reference's over the run's samples in 0-1 s (the reference
interpolated linearly; its rows are every 1e-3 s, the runs' samples fall on
them); CPU s is the `CPU time` ffr run prints (the steps only).

Usage: python3 bench/segments/pendulum_study.py [--cases quick|full] [--out bench/segments/pendulum.csv]
Needs numpy (bench/peers/.venv has it).
"""

import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, '..', '..'))
SCENE = os.path.join(ROOT, 'scenes', 'flexible_pendulum.toml')
REF = os.path.join(ROOT, 'bench', 'reference', 'flexible_pendulum.csv')
LIMITS = os.path.join(ROOT, 'bench', 'reference', 'flexible_pendulum_limits.csv')


def scene_text(elements, segments, reference, stiffening, dt, rtol=None):
    s = open(SCENE).read()
    for key in ('elements = 64\n', 'segments = 64\n', 'reference = "clamped"\n',
                'stiffening = "second-order"\n', 'dt = 1e-3\n'):
        assert s.count(key) == 1, key
    s = s.replace('elements = 64\n', f'elements = {elements}\n')
    s = s.replace('segments = 64\n', f'segments = {segments}\n')
    s = s.replace('stiffening = "second-order"\n', '' if stiffening == 'none' else f'stiffening = "{stiffening}"\n')
    s = s.replace('reference = "clamped"\n', f'reference = "{reference}"\n')
    s = s.replace('dt = 1e-3\n', f'dt = {dt:e}\n')
    if rtol is not None:
        key = 'rho_inf = 0.8 }'
        assert s.count(key) == 1
        s = s.replace(key, f'rho_inf = 0.8, rtol = {rtol:e} }}')
    return s


def tip_error(t, x, y, ref, cx='tip_x', cy='tip_y'):
    dx = x - np.interp(t, ref['t'], ref[cx])
    dy = y - np.interp(t, ref['t'], ref[cy])
    return np.hypot(dx, dy).max(), np.abs(dx).max(), np.abs(dy).max()


def run(ffr, ref, lim, elements, segments, reference, stiffening, dt, rtol=None):
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, 'p.toml')
        open(path, 'w').write(scene_text(elements, segments, reference, stiffening, dt, rtol))
        out = os.path.join(d, 'p.csv')
        p = subprocess.run([ffr, 'run', path, '--csv', out], capture_output=True, text=True)
        text = p.stdout + p.stderr
        cpu = float(re.search(r'CPU time ([0-9.e+-]+) s', text).group(1)) if 'CPU time' in text else float('nan')
        warned = 'warning: body' in p.stderr
        failed = p.returncode != 0
        data = np.genfromtxt(out, delimiter=',', names=True) if os.path.exists(out) else None
    nan = float('nan')
    row = dict(elements=elements, segments=segments, reference=reference, stiffening=stiffening, dt=dt,
               rtol=rtol if rtol is not None else 1e-10, failed=int(failed), t_reached=nan, warned=int(warned),
               cpu_s=cpu, err_tip=nan, err_x=nan, err_y=nan, err_tip_lin=nan, err_tip_gl=nan,
               err_tip_reached=nan)
    if data is not None and data.size:
        t = np.atleast_1d(data['t'])
        x, y = np.atleast_1d(data['tip_x']), np.atleast_1d(data['tip_y'])
        row['t_reached'] = t[-1]
        row['err_tip_reached'] = tip_error(t, x, y, ref)[0]
        if not failed and t[-1] >= 1.0 - 1e-9:   # a run that stopped has no error over 0-1 s
            row['err_tip'], row['err_x'], row['err_y'] = tip_error(t, x, y, ref)
            if lim is not None:
                row['err_tip_lin'] = tip_error(t, x, y, lim, 'lin_tip_x', 'lin_tip_y')[0]
                row['err_tip_gl'] = tip_error(t, x, y, lim, 'gl_tip_x', 'gl_tip_y')[0]
    return row


def cases(which):
    c = []
    if which == 'quick':
        for ref_kind in ('clamped', 'pinned'):
            for st in ('none', 'second-order', 'fourth-order'):
                for n in (8, 16, 32):
                    c.append((64, n, ref_kind, st, 1e-3))
        return c
    # segment ladders, every stiffening model, 32 / 64 / 128 elements, dt = 1e-3
    for st in ('none', 'second-order', 'fourth-order'):
        for el in (32, 64, 128):
            for n in (1, 2, 4, 8, 16, 32, 64, 128):
                if n <= el:
                    c.append((el, n, 'clamped', st, 1e-3))
    # the root frame's reference, one ladder
    for n in (1, 4, 16, 64):
        c.append((64, n, 'pinned', 'second-order', 1e-3))
    # step ladders at one element per segment
    for st in ('second-order', 'fourth-order'):
        for dt, rtol in ((2e-3, None), (5e-4, None), (2.5e-4, 1e-8), (2.5e-4, None)):
            c.append((64, 64, 'clamped', st, dt, rtol))
    return c


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--cases', default='full')
    ap.add_argument('--out', default=os.path.join(HERE, 'pendulum.csv'))
    ap.add_argument('--ref', default=REF)
    ap.add_argument('--case', action='append', default=[],
                    help='ELEMENTS,SEGMENTS,REFERENCE,STIFFENING,DT (repeatable; instead of --cases)')
    a = ap.parse_args()
    ffr = os.environ.get('FFR', os.path.join(ROOT, 'target', 'release', 'ffr'))
    ref = np.genfromtxt(a.ref, delimiter=',', names=True)
    lim = np.genfromtxt(LIMITS, delimiter=',', names=True) if os.path.exists(LIMITS) else None
    cs = [(int(x[0]), int(x[1]), x[2], x[3], float(x[4])) + tuple(float(v) for v in x[5:])
          for x in (c.split(',') for c in a.case)] or cases(a.cases)
    rows = []
    for c in cs:
        r = run(ffr, ref, lim, *c)
        rows.append(r)
        print(f"el {r['elements']:3d} seg {r['segments']:3d} {r['reference']:7s} {r['stiffening']:12s} dt {r['dt']:.0e}"
              f"  err {r['err_tip']:.3e} lin {r['err_tip_lin']:.3e} gl {r['err_tip_gl']:.3e}  reached {r['t_reached']:.3f}"
              f"  cpu {r['cpu_s']:.2f}  warned {r['warned']}", flush=True)
    with open(a.out, 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()), lineterminator='\n')
        w.writeheader()
        for r in rows:
            w.writerow({k: (f'{v:.4e}' if isinstance(v, float) and k.startswith(('err', 'cpu')) else
                            f'{v:g}' if isinstance(v, float) else v)
                        for k, v in r.items()})


if __name__ == '__main__':
    main()
