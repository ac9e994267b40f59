#!/usr/bin/env python3
"""Exudyn work-precision points on the KRB spin-up beam (peer of `ffr report`).

For each scene (spin-up-4, spin-up-10: ANCF cable 2D, geometrically exact 2D
beam; spin-up-3d, the spatial spin-up under gravity along the spin axis:
geometrically exact 3D beam, ANCF cable 3D), model, number of elements and
time step: simulate 0-20 s with Exudyn's
implicit generalized-alpha solver (rho_inf = 0.8, fixed step), take the CPU
seconds of mbs.SolveDynamic only (time.process_time(), model building excluded,
no graphics, no files, one in-memory sensor sampled every 0.01 s,
verboseMode = 0), the minimum of --reps repetitions (default 3), and the error
against the committed geometrically exact reference (bench/reference/):

    error = max_k |y(t_k) - y_ref(t_k)| / max_k |y_ref(t_k)|,  t_k in [0, 20] s,

y = tip_transverse (hub frame), t_k the run's own output times (every 0.01 s),
y_ref interpolated linearly in the reference (every 0.002 s, so here exact).
On spin-up-3d the error is the larger of that measure for tip_v (in the
rotation plane) and tip_w (along the spin axis), each against its own
reference peak (bench/reference/spin_up_gravity_omega4.csv).

Writes bench/peers/results/exudyn.csv with the columns
scene,method,elements,dt,cpu_s,error,error_kind of ffr's report (rows of
scenes left out with --scenes are kept). A run that
fails (Newton does not converge with the fixed step) is left out and reported
on stderr.

Usage: bench/peers/.venv/bin/python bench/peers/spin_up_peer.py [--quick] [--reps 3] [--out FILE]
       [--methods exudyn-ancf-cable2d,...] [--scenes spin-up-4,spin-up-10,spin-up-3d]
"""

import argparse
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # no __pycache__ in the repository
import krb_exudyn as k  # noqa: E402

T_END = 20.0
SAMPLE = 0.01
GRAVITY = 9.81
SPATIAL = {'beta': 0.0, 'gravity': GRAVITY}  # spin-up-3d: no precone, gravity along -z (spin axis)
METHODS = {
    # method name -> (model, model options)
    'exudyn-ancf-cable2d': ('ancf2d', {}),
    # Simo-Reissner beam with the tube's section as a user would give it: shear
    # stiffness k G A and rotary inertia rho I (bench/reference/README.md). Its shear
    # flexibility alone puts it 4.5e-5 (omega 4) and 1.9e-4 (omega 10) away from the
    # Euler-Bernoulli reference, relative.
    'exudyn-beam-gx2d': ('gx2d', {}),
    # the same with ten times the shear stiffness, closer to the Euler-Bernoulli
    # beam of the reference (shear floor 4.6e-6 and 2.1e-5, relative)
    'exudyn-beam-gx2d-stiff': ('gx2d', {'shear': 10.0 * k.GA_K}),
    # spin-up-3d: the 3D geometrically exact (Simo-Reissner) beam with the tube's
    # section (shear kGA, torsion GJ, rotary inertia), and the 3D ANCF cable that
    # the reference comes from (Euler-Bernoulli, no torsion)
    'exudyn-beam-gx3d': ('gx3d', SPATIAL),
    'exudyn-ancf-cable3d': ('ancf3d', SPATIAL),
}
ELEMENTS = (2, 4, 8, 16, 32)
STEPS = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4)
# scene -> (omega_s, reference file, its compared columns, methods, elements, steps, quick elements)
PLANAR = ('exudyn-ancf-cable2d', 'exudyn-beam-gx2d', 'exudyn-beam-gx2d-stiff')
SPATIAL_METHODS = ('exudyn-beam-gx3d', 'exudyn-ancf-cable3d')
SCENES = {
    'spin-up-4': (4.0, 'spin_up_omega4.csv', ('tip_transverse',), PLANAR, ELEMENTS, STEPS, (2, 8)),
    'spin-up-10': (10.0, 'spin_up_omega10.csv', ('tip_transverse',), PLANAR, ELEMENTS, STEPS, (2, 8)),
    # both transverse components (in the rotation plane, along the spin axis)
    'spin-up-3d': (4.0, 'spin_up_gravity_omega4.csv', ('tip_v', 'tip_w'), SPATIAL_METHODS,
                   (4, 8, 16, 32), (1e-2, 5e-3, 2e-3, 1e-3), (4, 8)),
}
# the columns of k.run's output (2D: axial, transverse; 3D: u, v, w)
RUN_COLUMNS = {'tip_transverse': 1, 'tip_v': 1, 'tip_w': 2}


def load_reference(path, columns):
    with open(path) as f:
        header = f.readline().strip().split(',')
    d = np.loadtxt(path, delimiter=',', skiprows=1)
    return d[:, 0], [d[:, header.index(c)] for c in columns]


def one_point(method, n, dt, omega, ref, columns, reps):
    """Minimum CPU s of `reps` runs and the error: the largest over `columns` of
    max_k |y(t_k) - y_ref(t_k)| / max_k |y_ref(t_k)|, t_k <= T_END."""
    model, opts = METHODS[method]
    cpus = []
    err = None
    for _ in range(reps):
        # sparse LU from 16 elements on; the dense solver is ~10 % faster below
        t, cols, cpu = k.run(model, n, omega, dt, T_END, sample=SAMPLE, sparse=n >= 16, **opts)
        cpus.append(cpu)
        if err is None:
            mask = t <= T_END + 1e-9
            tr, yrs = ref
            keep = tr <= T_END + 1e-9
            errs = []
            for c, yr in zip(columns, yrs):
                y = cols[RUN_COLUMNS[c]]
                y_ref = np.interp(t[mask], tr[keep], yr[keep])
                errs.append(np.max(np.abs(y[mask] - y_ref)) / np.max(np.abs(yr[keep])))
            err = max(errs)
            if not np.isfinite(err):
                raise RuntimeError('non-finite result')
    return min(cpus), err


def summary(points):
    lines = ['| scene | target | cheapest CPU s | method | elements | dt | error |', '|---|---|---:|---|---:|---:|---:|']
    for scene in dict.fromkeys(p[0] for p in points):
        for tol in (1e-2, 1e-3, 1e-4):
            ok = [p for p in points if p[0] == scene and p[5] <= tol]
            if not ok:
                lines.append(f'| {scene} | <= {tol:g} | not reached | | | | |')
                continue
            p = min(ok, key=lambda p: p[4])
            lines.append(f'| {scene} | <= {tol:g} | {p[4]:.4g} | {p[1]} | {p[2]} | {p[3]:g} | {p[5]:.3e} |')
    return '\n'.join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--out', default=None,
                    help='default results/exudyn.csv; with --quick a file in the temporary directory')
    ap.add_argument('--reference', default=os.path.join(HERE, '..', 'reference'))
    ap.add_argument('--reps', type=int, default=3)
    ap.add_argument('--quick', action='store_true',
                    help='2 and 8 elements (3D: 4 and 8), dt 1e-2 and 2e-3, 1 repetition')
    ap.add_argument('--methods', default=','.join(METHODS), help='comma-separated subset of ' + ', '.join(METHODS))
    ap.add_argument('--scenes', default=','.join(SCENES),
                    help='comma-separated subset of ' + ', '.join(SCENES) + '; the output file keeps '
                         'the rows of the scenes not run')
    a = ap.parse_args()
    methods = a.methods.split(',')
    scenes = a.scenes.split(',')
    reps = 1 if a.quick else a.reps
    if a.out is None:  # a quick run must not overwrite the committed grid
        a.out = (os.path.join(tempfile.gettempdir(), 'exudyn-quick.csv') if a.quick
                 else os.path.join(HERE, 'results', 'exudyn.csv'))
    grid = []
    for scene in scenes:
        omega, fname, columns, scene_methods, elements, steps, quick_elements = SCENES[scene]
        if a.quick:
            elements, steps = quick_elements, (1e-2, 2e-3)
        for method in methods:
            if method in scene_methods:
                grid += [(scene, method, n, dt) for n in elements for dt in steps]
    import exudyn
    print(f'Exudyn {exudyn.__version__}: {len(grid)} runs x {reps} repetitions, t_end = {T_END} s',
          file=sys.stderr, flush=True)
    points = []
    w0 = time.time()
    refs = {}
    for scene, method, n, dt in grid:
        omega, fname, columns = SCENES[scene][:3]
        if scene not in refs:
            refs[scene] = load_reference(os.path.join(a.reference, fname), columns)
        try:
            cpu, err = one_point(method, n, dt, omega, refs[scene], columns, reps)
        except Exception as e:
            print(f'  left out: {scene} {method} n={n} dt={dt:g}: failed ({e})', file=sys.stderr, flush=True)
            continue
        points.append((scene, method, n, dt, cpu, err))
        print(f'  {scene:10s} {method:20s} n={n:2d} dt={dt:<7g} cpu {cpu:8.3f} s  error {err:.3e}',
              file=sys.stderr, flush=True)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    kept = []  # rows of the scenes this run left alone
    if os.path.exists(a.out):
        with open(a.out) as f:
            kept = [line for line in f.read().splitlines()[1:] if line and line.split(',')[0] not in scenes]
    with open(a.out, 'w') as f:
        f.write('scene,method,elements,dt,cpu_s,error,error_kind\n')
        for line in kept:
            f.write(line + '\n')
        for p in points:
            f.write(f'{p[0]},{p[1]},{p[2]},{p[3]:g},{p[4]:.6g},{p[5]:.6e},reference\n')
    print(f'wrote {a.out} ({len(points)} points) in {time.time() - w0:.0f} s wall', file=sys.stderr)
    print(summary(points))


if __name__ == '__main__':
    main()
