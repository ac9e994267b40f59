#!/usr/bin/env python3
"""Geometrically exact reference solutions of the KRB spin-up beam (Exudyn 1.13.6).

Writes, into bench/reference/ (or --out):
  spin_up_omega4.csv, spin_up_omega10.csv   t,tip_axial,tip_transverse (hub frame)
  spin_up_precone_omega4.csv                 t,tip_u,tip_v,tip_w (clamped beam frame)
  spin_up_gravity_omega4.csv                 t,tip_u,tip_v,tip_w (hub frame; gravity along -z)
  convergence.md                             the refinement tables of this run

Planar reference: ObjectANCFCable2D, 64 elements, dt = 1e-4 (element ladder
16/32/64 at dt = 1e-4, step ladder 4e-4/2e-4/1e-4 at 64 elements), checked
against ObjectBeamGeometricallyExact2D (Simo-Reissner) at 64/128/256 elements
with the tube's shear stiffness and with ten times that.
Precone reference: ObjectANCFCable (3D), 32 elements, dt = 1e-4 (ladders
8/16/32 and 4e-4/2e-4/1e-4), checked against ObjectBeamGeometricallyExact (3D
Simo-Reissner) at 16/32/64 elements. See bench/reference/README.md.
Gravity reference (the straight beam spun up under g = 9.81 along -z, the spin
axis): ObjectANCFCable, 64 elements, dt = 1e-4 (ladders 16/32/64 and
4e-4/2e-4/1e-4), checked against ObjectBeamGeometricallyExact at 16/32/64.

Usage: bench/peers/.venv/bin/python bench/peers/spin_up_reference.py [--jobs 2]
       [--only omega4,omega10,precone,gravity] [--out DIR]
"""

import argparse
import math
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # no __pycache__ in the repository
import krb_exudyn as k  # noqa: E402

T_END = float(os.environ.get("KRB_REF_T_END", "30"))  # override only to smoke-test the script
SAMPLE = 0.002
N_SAMPLES = int(round(T_END / SAMPLE)) + 1
N20 = int(round(min(T_END, 20.0) / SAMPLE)) + 1  # samples of the report's 0-20 s
RHO_INF = 0.8          # generalized-alpha spectral radius (rho = 1 drifts and fails, see README)
BETA = 0.05            # precone angle (rad)

# (label, model, elements, dt, omega_s, model options)
SR0 = dict(rot_inertia=0.0)                       # tube kGA, no section rotary inertia
SR10 = dict(rot_inertia=0.0, shear=10.0 * k.GA_K)  # ten times stiffer in shear


def planar_cases(om):
    c = []
    for n in (16, 32, 64):
        c.append((f'ancf2d n={n} dt=1e-4', 'ancf2d', n, 1e-4, om, {}))
    for dt in (4e-4, 2e-4):
        c.append((f'ancf2d n=64 dt={dt:g}', 'ancf2d', 64, dt, om, {}))
    for n in (64, 128, 256):
        c.append((f'gx2d kGA n={n} dt=2e-4', 'gx2d', n, 2e-4, om, SR0))
    c.append(('gx2d 10kGA n=256 dt=2e-4', 'gx2d', 256, 2e-4, om, SR10))
    return c


def precone_cases():
    c = []
    for n in (8, 16, 32):
        c.append((f'ancf3d n={n} dt=1e-4', 'ancf3d', n, 1e-4, 4.0, {}))
    for dt in (4e-4, 2e-4):
        c.append((f'ancf3d n=32 dt={dt:g}', 'ancf3d', 32, dt, 4.0, {}))
    for n in (16, 32, 64):
        c.append((f'gx3d n={n} dt=1e-3', 'gx3d', n, 1e-3, 4.0, {}))
    return c


GRAVITY = 9.81         # gravity case: g along -z, the spin axis; no precone
GRAV = dict(beta=0.0, gravity=GRAVITY)


def gravity_cases():
    """Spin-up of the straight beam (no precone) under gravity along the spin
    axis: both bending planes active. The precone case's ladders one element
    level finer (the beam swings through 3.3 m under gravity)."""
    c = []
    for n in (16, 32, 64):
        c.append((f'grav ancf3d n={n} dt=1e-4', 'ancf3d', n, 1e-4, 4.0, GRAV))
    for dt in (4e-4, 2e-4):
        c.append((f'grav ancf3d n=64 dt={dt:g}', 'ancf3d', 64, dt, 4.0, GRAV))
    for n in (16, 32, 64):
        c.append((f'grav gx3d n={n} dt=1e-3', 'gx3d', n, 1e-3, 4.0, GRAV))
    return c


def run_case(case):
    label, model, n, dt, om, opts = case
    kw = dict(beta=BETA)
    kw.update(opts)
    w0 = time.time()
    try:
        t, cols, cpu = k.run(model, n, om, dt, T_END, sample=SAMPLE, rho_inf=RHO_INF, **kw)
    except Exception as e:  # reported, and the tables leave the run out
        print(f'  FAILED {label} omega={om:g}: {e}', file=sys.stderr, flush=True)
        return dict(label=label, model=model, n=n, dt=dt, omega=om, failed=True)
    wall = time.time() - w0
    idx = np.rint(t / SAMPLE).astype(int)
    if len(t) != N_SAMPLES or np.any(idx != np.arange(N_SAMPLES)) or np.max(np.abs(t - idx * SAMPLE)) > 1e-9:
        raise RuntimeError(f'{label}: unexpected sensor times ({len(t)} samples)')
    print(f'  done {label:28s} omega={om:g}  cpu {cpu:8.2f} s  wall {wall:8.2f} s', file=sys.stderr, flush=True)
    return dict(label=label, model=model, n=n, dt=dt, omega=om, cpu=cpu,
                cols=np.stack(cols), failed=False)


def fmt(x):
    return f'{x:.3e}'


def peak(y):
    i = int(np.argmin(y))
    return y[i], i * SAMPLE


def planar_tables(runs, om, lines):
    r = {x['label']: x for x in runs}
    ref = r['ancf2d n=64 dt=1e-4']
    lines.append(f'\n## omega_s = {om:g} rad/s (planar)\n')
    lines.append('Peak = min tip_transverse over 0-30 s; differences are max over the whole 0-30 s history '
                 '(15 001 samples).\n')
    lines.append('| run | CPU s | peak tip_transverse (m) | at t (s) | vs | max |d tip_transverse| | max |d tip_axial| | d peak |')
    lines.append('|---|---:|---:|---:|---|---:|---:|---:|')

    def row(a, b):
        if a.get('failed') or (b is not None and b.get('failed')):
            lines.append(f"| {a['label']} | FAILED | | | {b['label'] if b else ''} | | | |")
            return
        pa, ta = peak(a['cols'][1])
        if b is None:
            lines.append(f"| {a['label']} | {a['cpu']:.1f} | {pa:.8f} | {ta:.3f} | | | | |")
            return
        pb, _ = peak(b['cols'][1])
        d = np.abs(a['cols'] - b['cols']).max(axis=1)
        lines.append(f"| {a['label']} | {a['cpu']:.1f} | {pa:.8f} | {ta:.3f} | {b['label']} | "
                     f"{fmt(d[1])} | {fmt(d[0])} | {fmt(pa - pb)} |")

    row(r['ancf2d n=16 dt=1e-4'], None)
    row(r['ancf2d n=32 dt=1e-4'], r['ancf2d n=16 dt=1e-4'])
    row(r['ancf2d n=64 dt=1e-4'], r['ancf2d n=32 dt=1e-4'])
    row(r['ancf2d n=64 dt=0.0004'], None)
    row(r['ancf2d n=64 dt=0.0002'], r['ancf2d n=64 dt=0.0004'])
    row(r['ancf2d n=64 dt=1e-4'], r['ancf2d n=64 dt=0.0002'])
    row(r['gx2d kGA n=64 dt=2e-4'], ref)
    row(r['gx2d kGA n=128 dt=2e-4'], ref)
    row(r['gx2d kGA n=256 dt=2e-4'], ref)
    row(r['gx2d 10kGA n=256 dt=2e-4'], ref)
    row(r['gx2d kGA n=128 dt=2e-4'], r['gx2d kGA n=64 dt=2e-4'])
    row(r['gx2d kGA n=256 dt=2e-4'], r['gx2d kGA n=128 dt=2e-4'])
    # Simo-Reissner extrapolated to h -> 0 (second order in h) and to infinite shear
    # stiffness (first order in 1/GA): the Euler-Bernoulli limit the ANCF cable models.
    if any(r[x]['failed'] for x in ('gx2d kGA n=128 dt=2e-4', 'gx2d kGA n=256 dt=2e-4', 'gx2d 10kGA n=256 dt=2e-4')):
        return finish_planar(r, ref, lines)
    s128 = r['gx2d kGA n=128 dt=2e-4']['cols']
    s256 = r['gx2d kGA n=256 dt=2e-4']['cols']
    s256x = r['gx2d 10kGA n=256 dt=2e-4']['cols']
    ext = s256 + (s256 - s128) / 3.0 - (s256 - s256x) * 10.0 / 9.0
    d = np.abs(ext - ref['cols']).max(axis=1)
    pe, te = peak(ext[1])
    pr, _ = peak(ref['cols'][1])
    lines.append(f"| SR extrapolated (h -> 0, GA -> inf) | | {pe:.8f} | {te:.3f} | {ref['label']} | "
                 f"{fmt(d[1])} | {fmt(d[0])} | {fmt(pe - pr)} |")
    return finish_planar(r, ref, lines)


def finish_planar(r, ref, lines):
    # error estimate of the reference
    dt_d = np.abs(r['ancf2d n=64 dt=1e-4']['cols'] - r['ancf2d n=64 dt=0.0002']['cols']).max(axis=1)
    el_d = np.abs(r['ancf2d n=64 dt=1e-4']['cols'] - r['ancf2d n=32 dt=1e-4']['cols']).max(axis=1)
    lines.append(f'\nReference = ancf2d n=64 dt=1e-4. Estimated error of tip_transverse: step '
                 f'{fmt(dt_d[1] / 3)} (difference to dt=2e-4 / 3, second order), elements <= '
                 f'{fmt(el_d[1])} (difference to 32 elements); tip_axial: step {fmt(dt_d[0] / 3)}, '
                 f'elements <= {fmt(el_d[0])}.\n')
    return ref


def precone_tables(runs, lines, prefix='', title=None, n=(8, 16, 32)):
    """The spatial tables; `prefix` selects the gravity case's labels, `n` its
    element ladder (the last is the reference mesh and the step ladder's)."""
    r = {x['label'][len(prefix):]: x for x in runs if x['label'].startswith(prefix)}
    n0, n1, n2 = n
    ref = r[f'ancf3d n={n2} dt=1e-4']
    if title is None:
        title = f'precone, omega_s = 4 rad/s, beta = {BETA:g} rad (spatial)'
    lines.append(f'\n## {title}\n')
    lines.append('Peaks: min tip_v and min tip_w over 0-30 s; differences are max over the 0-30 s history.\n')
    lines.append('| run | CPU s | peak tip_v (m) | peak tip_w (m) | vs | max |d u| | max |d v| | max |d w| |')
    lines.append('|---|---:|---:|---:|---|---:|---:|---:|')

    def row(a, b):
        if a.get('failed') or (b is not None and b.get('failed')):
            lines.append(f"| {a['label']} | FAILED | | | {b['label'] if b else ''} | | | |")
            return
        pv, _ = peak(a['cols'][1])
        pw, _ = peak(a['cols'][2])
        if b is None:
            lines.append(f"| {a['label']} | {a['cpu']:.1f} | {pv:.8f} | {pw:.8f} | | | | |")
            return
        d = np.abs(a['cols'] - b['cols']).max(axis=1)
        lines.append(f"| {a['label']} | {a['cpu']:.1f} | {pv:.8f} | {pw:.8f} | {b['label']} | "
                     f"{fmt(d[0])} | {fmt(d[1])} | {fmt(d[2])} |")

    row(r[f'ancf3d n={n0} dt=1e-4'], None)
    row(r[f'ancf3d n={n1} dt=1e-4'], r[f'ancf3d n={n0} dt=1e-4'])
    row(r[f'ancf3d n={n2} dt=1e-4'], r[f'ancf3d n={n1} dt=1e-4'])
    row(r[f'ancf3d n={n2} dt=0.0004'], None)
    row(r[f'ancf3d n={n2} dt=0.0002'], r[f'ancf3d n={n2} dt=0.0004'])
    row(r[f'ancf3d n={n2} dt=1e-4'], r[f'ancf3d n={n2} dt=0.0002'])
    row(r['gx3d n=16 dt=1e-3'], ref)
    row(r['gx3d n=32 dt=1e-3'], ref)
    row(r['gx3d n=64 dt=1e-3'], ref)
    row(r['gx3d n=32 dt=1e-3'], r['gx3d n=16 dt=1e-3'])
    row(r['gx3d n=64 dt=1e-3'], r['gx3d n=32 dt=1e-3'])
    if r['gx3d n=32 dt=1e-3']['failed'] or r['gx3d n=64 dt=1e-3']['failed']:
        return finish_precone(r, ref, lines, n1, n2)
    g32 = r['gx3d n=32 dt=1e-3']['cols']
    g64 = r['gx3d n=64 dt=1e-3']['cols']
    ext = g64 + (g64 - g32) / 3.0
    d = np.abs(ext - ref['cols']).max(axis=1)
    lines.append(f"| gx3d extrapolated (h -> 0) | | {peak(ext[1])[0]:.8f} | {peak(ext[2])[0]:.8f} | "
                 f"{ref['label']} | {fmt(d[0])} | {fmt(d[1])} | {fmt(d[2])} |")
    return finish_precone(r, ref, lines, n1, n2)


def finish_precone(r, ref, lines, n1=16, n2=32):
    dt_d = np.abs(r[f'ancf3d n={n2} dt=1e-4']['cols'] - r[f'ancf3d n={n2} dt=0.0002']['cols']).max(axis=1)
    el_d = np.abs(r[f'ancf3d n={n2} dt=1e-4']['cols'] - r[f'ancf3d n={n1} dt=1e-4']['cols']).max(axis=1)
    lines.append(f'\nReference = ancf3d n={n2} dt=1e-4. Estimated error (u, v, w): step '
                 f'{", ".join(fmt(x / 3) for x in dt_d)} (difference to dt=2e-4 / 3), elements <= '
                 f'{", ".join(fmt(x) for x in el_d)} (difference to {n1} elements). Peaks of the file over '
                 f'0-20 s (min v, min w): {np.min(ref["cols"][1][:N20]):.8f}, {np.min(ref["cols"][2][:N20]):.8f}.\n')
    return ref


def write_csv(path, header, cols):
    with open(path, 'w') as f:
        f.write(header + '\n')
        for i in range(cols.shape[1]):
            f.write(f'{i * 2 / 1000:.3f},' + ','.join(f'{x:.16e}' for x in cols[:, i]) + '\n')


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--out', default=os.path.join(HERE, '..', 'reference'))
    ap.add_argument('--jobs', type=int, default=1)
    ap.add_argument('--only', default='omega4,omega10,precone,gravity')
    a = ap.parse_args()
    which = a.only.split(',')
    cases = []
    if 'omega4' in which:
        cases += planar_cases(4.0)
    if 'omega10' in which:
        cases += planar_cases(10.0)
    if 'precone' in which:
        cases += precone_cases()
    if 'gravity' in which:
        cases += gravity_cases()
    # most expensive first, so that two workers finish together
    cost = {'ancf2d': 1.0, 'gx2d': 0.6, 'ancf3d': 1.3, 'gx3d': 12.0}
    cases.sort(key=lambda c: -cost[c[1]] * c[2] / c[3] * (1.5 if c[4] > 5 else 1.0))
    import exudyn
    print(f'Exudyn {exudyn.__version__}, {len(cases)} runs, {a.jobs} job(s)', file=sys.stderr, flush=True)
    w0 = time.time()
    if a.jobs > 1:
        with ProcessPoolExecutor(a.jobs) as ex:
            runs = list(ex.map(run_case, cases))
    else:
        runs = [run_case(c) for c in cases]
    wall = time.time() - w0
    os.makedirs(a.out, exist_ok=True)
    lines = [f'# Convergence of the reference runs (generated by bench/peers/spin_up_reference.py)\n',
             f'Exudyn {exudyn.__version__}, numpy {np.__version__}, Python {sys.version.split()[0]}; '
             f'generalized-alpha rho_inf = {RHO_INF}, Newton relTol 1e-8 absTol 1e-6 (modified Newton), '
             f'EigenSparse; output every {SAMPLE} s; CPU s = time.process_time() around SolveDynamic. '
             f'Total CPU {sum(x.get("cpu", 0.0) for x in runs):.0f} s, wall {wall:.0f} s with {a.jobs} job(s).']
    for om, name in ((4.0, 'omega4'), (10.0, 'omega10')):
        if name in which:
            ref = planar_tables([x for x in runs if x['omega'] == om and x['model'].endswith('2d')], om, lines)
            write_csv(os.path.join(a.out, f'spin_up_{name}.csv'), 't,tip_axial,tip_transverse', ref['cols'])
    if 'precone' in which:
        ref = precone_tables([x for x in runs if x['model'].endswith('3d') and not x['label'].startswith('grav ')],
                             lines)
        write_csv(os.path.join(a.out, 'spin_up_precone_omega4.csv'), 't,tip_u,tip_v,tip_w', ref['cols'])
    if 'gravity' in which:
        ref = precone_tables(runs, lines, prefix='grav ',
                             title=f'gravity along the spin axis, omega_s = 4 rad/s, g = {GRAVITY:g} m/s^2 along -z, '
                                   'no precone (spatial)', n=(16, 32, 64))
        write_csv(os.path.join(a.out, 'spin_up_gravity_omega4.csv'), 't,tip_u,tip_v,tip_w', ref['cols'])
    full = ['omega4', 'omega10', 'precone', 'gravity']
    name = 'convergence.md' if which == full else f'convergence-{"-".join(which)}.md'
    with open(os.path.join(a.out, name), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    print('\n'.join(lines))


if __name__ == '__main__':
    main()
