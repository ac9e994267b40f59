#!/usr/bin/env python3
"""Reference solution of the flexible pendulum of Berzeri & Shabana (Exudyn 1.13.6).

A. Berzeri, A. A. Shabana, "Development of simple models for the elastic
forces in the absolute nodal co-ordinate formulation", Journal of Sound and
Vibration 235(4) (2000) 539-565; also A. Berzeri, M. Campanelli,
A. A. Shabana, "Definition of the elastic forces in the finite-element
absolute nodal coordinate formulation and the floating frame of reference
formulation", Multibody System Dynamics 5 (2001) 21-54.

A beam L = 1.2 m, A = 0.0018 m^2, I = 1.215e-8 m^4, rho = 5540 kg/m^3,
E = 0.7e6 N/m^2, pinned at x = 0 (revolute joint to the ground), released at
rest, straight and horizontal (along +x), under gravity g = 9.81 m/s^2
along -y. No damping.

Writes, into bench/reference/ (or --out):
  flexible_pendulum.csv    t,tip_x,tip_y,tip_u,tip_v every 0.001 s over 0-T
  flexible_pendulum_limits.csv  t,lin_tip_x,lin_tip_y,gl_tip_x,gl_tip_y: the
                           same beam with the strain energies ffr's segmented
                           beam2 converges to (below)
  pendulum-convergence.md  the refinement tables of this run

The limits: as the segments of ffr's beam2 shrink, the elastic rotation in
each segment vanishes and the axial displacement derivative in the segment
frame tends to eps = |r'| - 1, the second derivative of the transverse
displacement to (1 + eps) K (K the material curvature). The bending energy
becomes 1/2 EI (1 + eps)^2 K^2 for every stiffening model; the axial energy
1/2 EA eps^2 without stiffening or with the second-order (von Karman)
model, 1/2 EA e_GL^2 with the fourth-order model, whose axial strain is
Green-Lagrange's, e_GL = eps + eps^2 / 2. The ANCF cable with these laws
(axial force and bending moment user functions): `ancf-ffr` (lin) and
`ancf-gl` (gl), 128 elements, dt = 1e-4.

tip_x, tip_y: the tip's position (the pin is the origin). tip_u, tip_v: the
tip's position in the frame tangent to the beam at the pin (e_1 = the unit
slope at x = 0, e_2 = e_3 x e_1), minus (L, 0): the deflection that ffr's
`deflection` outputs measure with `reference = "clamped"`.

Reference: ObjectANCFCable2D (axial strain |r'| - 1, material curvature),
256 elements, dt = 5e-5; element ladder 16/32/64/128/256 at dt = 5e-5, step
ladder 2e-4/1e-4/5e-5 at 256 elements; checked against
ObjectBeamGeometricallyExact2D (Simo-Reissner; the same strain measures plus
shear) at 128/256/512 elements, with the strip's shear stiffness kGA and 10
and 100 times that, extrapolated to h -> 0 and GA -> infinity.

Usage: bench/peers/.venv/bin/python bench/peers/pendulum_reference.py [--jobs 2] [--out DIR]
"""

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

sys.dont_write_bytecode = True

# ---- Berzeri & Shabana (2000) data -------------------------------------------------
L = 1.2
A = 0.0018
I = 1.215e-8
RHO = 5540.0
E = 0.7e6
G_ACC = 9.81
RHO_A = RHO * A            # 9.972 kg/m
EA = E * A                 # 1260 N
EI = E * I                 # 8.505e-3 N m^2
# The paper gives no shear data (its elements are shear rigid). The
# Simo-Reissner beam gets a section with the same A and I, a 200 x 9 mm strip
# (b h = A, b h^3 / 12 = I), nu = 0.3, k = 5/6: kGA = 404 N (its shear
# changes the tip by 7e-3 m); and 10 and 100 times that, to extrapolate to the
# shear-rigid limit.
NU = 0.3
GA_K = 5.0 / 6.0 * E / (2.0 * (1.0 + NU)) * A

T_END = float(os.environ.get("PENDULUM_REF_T_END", "1"))
SAMPLE = 0.001
N_SAMPLES = int(round(T_END / SAMPLE)) + 1
RHO_INF = 0.8


def settings(dt, abs_tol):
    import exudyn as exu
    s = exu.SimulationSettings()
    ti = s.timeIntegration
    ti.endTime = T_END
    ti.numberOfSteps = int(round(T_END / dt))
    ti.verboseMode = 0
    ti.adaptiveStep = False          # fixed step: a step that fails is a failed run
    ti.generalizedAlpha.spectralRadius = RHO_INF
    ti.generalizedAlpha.computeInitialAccelerations = True
    ti.newton.relativeTolerance = 1e-8
    ti.newton.absoluteTolerance = abs_tol
    ti.newton.useModifiedNewton = True
    s.solution.file.write = False
    s.solution.sensors.writePeriod = SAMPLE
    s.solution.sensors.writeHeader = False
    s.solution.restart.write = False
    s.show.computationTime = False
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    return s


def _axial_gl(mbs, t, item, x, eps, eps_t, eps0, ea, da, k, k_t, k0):
    # energy 1/2 EA e_GL^2 + 1/2 EI (1 + eps)^2 K^2, e_GL = eps + eps^2 / 2: dW/d eps
    return ea * (eps + 0.5 * eps * eps) * (1.0 + eps) + EI * (1.0 + eps) * k * k


def _axial_lin(mbs, t, item, x, eps, eps_t, eps0, ea, da, k, k_t, k0):
    # energy 1/2 EA eps^2 + 1/2 EI (1 + eps)^2 K^2
    return ea * eps + EI * (1.0 + eps) * k * k


def _bending(mbs, t, item, x, k, k_t, k0, ei, di, eps, eps_t, eps0):
    # bending moment of 1/2 EI (1 + eps)^2 K^2: EI v'' with v'' = (1 + eps) K
    return ei * (1.0 + eps) ** 2 * k


def build(mbs, model, n, shear):
    """The pendulum; returns (tip node, root node)."""
    from exudyn.itemInterface import (
        ObjectGround, NodePointGround, MarkerNodeCoordinate, CoordinateConstraint,
        NodePoint2DSlope1, ObjectANCFCable2D, VObjectANCFCable2D, NodeRigidBody2D,
        ObjectBeamGeometricallyExact2D, VObjectBeamGeometricallyExact2D,
        MarkerBodyMass, LoadMassProportional)
    mbs.AddObject(ObjectGround())
    nG = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    mG = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nG, coordinate=0))
    le = L / n
    if model.startswith('ancf'):
        nodes = [mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[i * le, 0, 1, 0]))
                 for i in range(n + 1)]
    else:
        nodes = [mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[i * le, 0, 0]))
                 for i in range(n + 1)]
    for i in range(n):
        if model.startswith('ancf'):
            uf = {}
            if model in ('ancf-gl', 'ancf-ffr'):
                # the strain energies ffr's segmented beam converges to (see README)
                uf = dict(axialForceUserFunction=_axial_gl if model == 'ancf-gl' else _axial_lin,
                          bendingMomentUserFunction=_bending)
            o = mbs.AddObject(ObjectANCFCable2D(
                nodeNumbers=[nodes[i], nodes[i + 1]], length=le, massPerLength=RHO_A,
                bendingStiffness=EI, axialStiffness=EA,
                visualization=VObjectANCFCable2D(show=False), **uf))
        else:
            # no section rotary inertia: the Euler-Bernoulli beams (ANCF, ffr) have none
            o = mbs.AddObject(ObjectBeamGeometricallyExact2D(
                nodeNumbers=[nodes[i], nodes[i + 1]], length=le, massPerLength=RHO_A,
                crossSectionInertia=0.0, bendingStiffness=EI, axialStiffness=EA,
                shearStiffness=shear, visualization=VObjectBeamGeometricallyExact2D(show=False)))
        m = mbs.AddMarker(MarkerBodyMass(bodyNumber=o))
        mbs.AddLoad(LoadMassProportional(markerNumber=m, loadVector=[0.0, -G_ACC, 0.0]))
    # the pin: position of node 0 fixed, its slope (rotation) free
    for c in (0, 1):
        m = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[0], coordinate=c))
        mbs.AddObject(CoordinateConstraint(markerNumbers=[mG, m]))
    return nodes[-1], nodes[0]


def run(model, n, dt, shear=GA_K):
    """Returns (t, cols (4 x samples): tip_x, tip_y, tip_u, tip_v; cpu s)."""
    import exudyn as exu
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    tip, root = build(mbs, model, n, shear)
    st = mbs.AddSensor(exu.itemInterface.SensorNode(
        nodeNumber=tip, outputVariableType=exu.OutputVariableType.Position,
        storeInternal=True, writeToFile=False))
    sr = mbs.AddSensor(exu.itemInterface.SensorNode(
        nodeNumber=root, outputVariableType=exu.OutputVariableType.Coordinates,
        storeInternal=True, writeToFile=False))
    mbs.Assemble()
    # Newton's absolute tolerance on the residual (N): the loads are ~100 N,
    # its round-off floor grows with the number of coordinates
    s = settings(dt, 1e-8 * max(1.0, (n / 32.0) ** 1.5))
    c0 = time.process_time()
    mbs.SolveDynamic(s, showHints=os.environ.get("PENDULUM_HINTS") == "1")
    cpu = time.process_time() - c0
    p = np.array(mbs.GetSensorStoredData(st))
    r = np.array(mbs.GetSensorStoredData(sr))
    t = p[:, 0]
    x, y = p[:, 1], p[:, 2]
    if model.startswith('ancf'):
        # current slope at the pin = reference (1, 0) + coordinates 2, 3
        sx, sy = 1.0 + r[:, 3], r[:, 4]
        nrm = np.hypot(sx, sy)
        c, s_ = sx / nrm, sy / nrm
    else:
        phi = r[:, 3]            # rotation coordinate of node 0 (reference 0)
        c, s_ = np.cos(phi), np.sin(phi)
    u = c * x + s_ * y - L
    v = -s_ * x + c * y
    return t, np.stack([x, y, u, v]), cpu


def run_case(case):
    label, model, n, dt, shear = case
    w0 = time.time()
    try:
        t, cols, cpu = run(model, n, dt, shear)
    except Exception as e:  # reported, and the tables leave the run out
        print(f'  FAILED {label}: {e}', file=sys.stderr, flush=True)
        return dict(label=label, failed=True)
    idx = np.rint(t / SAMPLE).astype(int)
    if len(t) != N_SAMPLES or np.any(idx != np.arange(N_SAMPLES)):
        raise RuntimeError(f'{label}: unexpected sensor times ({len(t)} samples)')
    print(f'  done {label:26s} cpu {cpu:8.2f} s  wall {time.time() - w0:8.2f} s', file=sys.stderr, flush=True)
    return dict(label=label, model=model, n=n, dt=dt, cpu=cpu, cols=cols, failed=False)


REF = 'ancf n=256 dt=5e-5'


def cases():
    c = [(f'ancf n={n} dt=5e-5', 'ancf', n, 5e-5, None) for n in (16, 32, 64, 128, 256)]
    c += [(f'ancf n=256 dt={dt:g}', 'ancf', 256, dt, None) for dt in (2e-4, 1e-4)]
    c += [(f'sr kGA n={n} dt=5e-5', 'sr', n, 5e-5, GA_K) for n in (128, 256)]
    c += [(f'sr 10kGA n={n} dt=5e-5', 'sr', n, 5e-5, 10.0 * GA_K) for n in (256, 512)]
    c.append(('sr 100kGA n=512 dt=5e-5', 'sr', 512, 5e-5, 100.0 * GA_K))
    # the limits of ffr's segmented beams (Python user functions: slow)
    for m in ('ancf-ffr', 'ancf-gl'):
        c += [(f'{m} n={n} dt=1e-4', m, n, 1e-4, None) for n in (64, 128)]
    return c


def fmt(x):
    return f'{x:.2e}'


def tables(runs, lines):
    r = {x['label']: x for x in runs}
    ref = r[REF]
    lines.append('| run | CPU s | tip_y(1 s) (m) | vs | max |d tip_x| | max |d tip_y| | max |d tip_u| | max |d tip_v| |')
    lines.append('|---|---:|---:|---|---:|---:|---:|---:|')

    def row(a, b, cols=None):
        if a.get('failed') or (b is not None and b.get('failed')):
            lines.append(f"| {a['label']} | FAILED | | {b['label'] if b else ''} | | | | |")
            return
        ca = a['cols'] if cols is None else cols
        end = f"{ca[1][-1]:.6f}"
        cpu = f"{a['cpu']:.1f}" if cols is None else ''
        if b is None:
            lines.append(f"| {a['label']} | {cpu} | {end} | | | | | |")
            return
        d = np.abs(ca - b['cols']).max(axis=1)
        lines.append(f"| {a['label']} | {cpu} | {end} | {b['label']} | " + ' | '.join(fmt(x) for x in d) + ' |')

    ladder = [f'ancf n={n} dt=5e-5' for n in (16, 32, 64, 128, 256)]
    row(r[ladder[0]], None)
    for a, b in zip(ladder[1:], ladder[:-1]):
        row(r[a], r[b])
    row(r['ancf n=256 dt=0.0002'], None)
    row(r['ancf n=256 dt=0.0001'], r['ancf n=256 dt=0.0002'])
    row(r[REF], r['ancf n=256 dt=0.0001'])
    for lab in ('sr kGA n=128', 'sr kGA n=256', 'sr 10kGA n=256', 'sr 10kGA n=512', 'sr 100kGA n=512'):
        row(r[lab + ' dt=5e-5'], ref)
    sr = [r[f'{lab} dt=5e-5'] for lab in ('sr 10kGA n=256', 'sr 10kGA n=512', 'sr 100kGA n=512')]
    if not any(x['failed'] for x in sr):
        s256, s512, s512x = (x['cols'] for x in sr)
        # h -> 0 (second order) and GA -> inf (first order in 1/GA)
        ext = s512 + (s512 - s256) / 3.0 - (s512 - s512x) * 10.0 / 9.0
        row(dict(label='SR extrapolated (h -> 0, GA -> inf)', failed=False, cpu=0.0), ref, cols=ext)
    for m in ('ancf-ffr', 'ancf-gl'):
        row(r[f'{m} n=64 dt=1e-4'], None)
        row(r[f'{m} n=128 dt=1e-4'], r[f'{m} n=64 dt=1e-4'])
        row(r[f'{m} n=128 dt=1e-4'], ref)
    el = np.abs(ref['cols'] - r['ancf n=128 dt=5e-5']['cols']).max(axis=1)
    el2 = np.abs(r['ancf n=128 dt=5e-5']['cols'] - r['ancf n=64 dt=5e-5']['cols']).max(axis=1)
    st = np.abs(ref['cols'] - r['ancf n=256 dt=0.0001']['cols']).max(axis=1)
    lines.append(f'\nReference = {REF}. Element differences 128 -> 256 (x, y, u, v): '
                 f'{", ".join(fmt(x) for x in el)}; 64 -> 128: {", ".join(fmt(x) for x in el2)} '
                 f'(ratios {", ".join(f"{a / b:.1f}" for a, b in zip(el2, el))}). Step: difference to dt = 1e-4 '
                 f'/ 3 (second order): {", ".join(fmt(x / 3) for x in st)}.\n')
    return ref


def write_csv(path, cols, header='t,tip_x,tip_y,tip_u,tip_v'):
    with open(path, 'w') as f:
        f.write(header + '\n')
        for i in range(cols.shape[1]):
            f.write(f'{i / 1000:.3f},' + ','.join(f'{x:.10e}' for x in cols[:, i]) + '\n')


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--out', default=os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'reference'))
    ap.add_argument('--jobs', type=int, default=1)
    a = ap.parse_args()
    cs = cases()
    cs.sort(key=lambda c: -c[2] / c[3] * (0.7 if c[1] == 'sr' else 1.0))   # most expensive first
    import exudyn
    print(f'Exudyn {exudyn.__version__}, {len(cs)} runs, {a.jobs} job(s)', file=sys.stderr, flush=True)
    w0 = time.time()
    if a.jobs > 1:
        with ProcessPoolExecutor(a.jobs) as ex:
            runs = list(ex.map(run_case, cs))
    else:
        runs = [run_case(c) for c in cs]
    wall = time.time() - w0
    lines = ['# Convergence of the flexible pendulum reference (generated by bench/peers/pendulum_reference.py)\n',
             f'Exudyn {exudyn.__version__}, numpy {np.__version__}, Python {sys.version.split()[0]}; '
             f'generalized-alpha rho_inf = {RHO_INF}, Newton relTol 1e-8 (modified Newton), EigenSparse; '
             f'0-{T_END:g} s, output every {SAMPLE} s; differences are max over the whole history; '
             f'CPU s = time.process_time() around SolveDynamic. Total CPU '
             f'{sum(x.get("cpu", 0.0) for x in runs):.0f} s, wall {wall:.0f} s with {a.jobs} job(s).\n']
    ref = tables(runs, lines)
    os.makedirs(a.out, exist_ok=True)
    write_csv(os.path.join(a.out, 'flexible_pendulum.csv'), ref['cols'])
    r = {x['label']: x for x in runs}
    lim = [r[f'{m} n=128 dt=1e-4'] for m in ('ancf-ffr', 'ancf-gl')]
    if not any(x['failed'] for x in lim):
        write_csv(os.path.join(a.out, 'flexible_pendulum_limits.csv'),
                  np.concatenate([x['cols'][:2] for x in lim]), 't,lin_tip_x,lin_tip_y,gl_tip_x,gl_tip_y')
    with open(os.path.join(a.out, 'pendulum-convergence.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    print('\n'.join(lines))


if __name__ == '__main__':
    main()
