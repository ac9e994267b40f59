"""Kane–Ryan–Banerjee spin-up beam in Exudyn (shared by the reference and peer scripts).

Data and conventions: /work/plan/PLAN.md, section "Benchmark data conventions"
(the same text is in bench/reference/README.md). All models are built in the
inertial frame; the clamp at the hub follows the prescribed hub angle theta(t)
exactly (user function), and the tip displacement is expressed in the hub frame
afterwards with the exact theta(t).

Models:
  ancf2d  ObjectANCFCable2D (Euler-Bernoulli, cubic Hermite, consistent mass,
          Gauss 9/5), clamp: GenericJoint between node 0 (MarkerNodeRigid: its
          position and slope angle) and a hub body whose angle is prescribed.
  gx2d    ObjectBeamGeometricallyExact2D (Simo-Reissner, shear deformable,
          NodeRigidBody2D nodes), clamp: CoordinateConstraints on node 0
          (x = 0, y = 0, angle = theta(t) via offsetUserFunction).
  gx3d    ObjectBeamGeometricallyExact (3D Simo-Reissner, Euler-parameter
          nodes) for the precone case, clamp: GenericJoint (all 6 axes) between
          node 0 and a hub body (Tait-Bryan node, angles (0, 0, theta(t))
          prescribed by CoordinateConstraints); the joint's rotationMarker
          carries the precone angle beta.
"""

import math
import time

import numpy as np
import exudyn as exu
from exudyn.itemInterface import (
    ObjectGround, NodePointGround, MarkerNodeCoordinate, CoordinateConstraint,
    NodeRigidBody2D, ObjectRigidBody2D, MarkerNodeRigid, MarkerBodyRigid,
    ObjectJointGeneric, NodePoint2DSlope1, ObjectANCFCable2D,
    ObjectBeamGeometricallyExact2D, ObjectBeamGeometricallyExact,
    NodeRigidBodyEP, NodeRigidBodyRxyz, ObjectRigidBody, SensorNode,
    VObjectANCFCable2D, VObjectBeamGeometricallyExact2D, VObjectBeamGeometricallyExact,
    VObjectRigidBody2D, VObjectRigidBody, VObjectJointGeneric,
    NodePointSlope1, ObjectANCFCable, VObjectANCFCable, MarkerNodeCoordinates,
    ObjectConnectorCoordinateVector, VObjectConnectorCoordinateVector,
    MarkerBodyMass, LoadMassProportional,
)

# ---- KRB data (PLAN.md) ----------------------------------------------------
L = 8.0
A = 7.2968e-5
I = 8.2189e-9
E = 6.8952e10
RHO = 2766.67
T_UP = 15.0

# Section data that the KRB sheet does not give (only shear and torsion need
# them; both are barely exercised). A solid circle or square cannot have this
# A and I (I/A^2 = 1.54), so the section is the thin circular tube with the
# same A and I: r_o^2 + r_i^2 = 4 I / A, r_o^2 - r_i^2 = A / pi.
NU = 0.33                      # aluminium (E and rho are aluminium's)
G = E / (2.0 * (1.0 + NU))
R_O = math.sqrt(0.5 * (4.0 * I / A + A / math.pi))
R_I = math.sqrt(0.5 * (4.0 * I / A - A / math.pi))
J_T = 2.0 * I                  # torsion constant of a circular tube = polar moment
_m = R_I / R_O                 # Cowper's shear coefficient of a hollow circle
K_SHEAR = (6.0 * (1.0 + NU) * (1.0 + _m**2) ** 2) / (
    (7.0 + 6.0 * NU) * (1.0 + _m**2) ** 2 + (20.0 + 12.0 * NU) * _m**2)

RHO_A = RHO * A
EA = E * A
EI = E * I
GA_K = K_SHEAR * G * A


def theta(t, omega_s):
    """KRB hub angle (rad)."""
    if t < T_UP:
        return (omega_s / T_UP) * (0.5 * t * t + (T_UP / (2.0 * math.pi)) ** 2
                                   * (math.cos(2.0 * math.pi * t / T_UP) - 1.0))
    return omega_s * (t - 0.5 * T_UP)


def theta_array(t, omega_s):
    t = np.asarray(t, dtype=float)
    up = (omega_s / T_UP) * (0.5 * t * t + (T_UP / (2.0 * np.pi)) ** 2
                             * (np.cos(2.0 * np.pi * t / T_UP) - 1.0))
    return np.where(t < T_UP, up, omega_s * (t - 0.5 * T_UP))


def _theta_offset(omega_s):
    """offsetUserFunction of a CoordinateConstraint: value of theta(t)."""
    a = omega_s / T_UP
    b = (T_UP / (2.0 * math.pi)) ** 2
    w = 2.0 * math.pi / T_UP
    half = 0.5 * T_UP
    cos = math.cos

    def uf(mbs, t, itemNumber, lOffset):
        if t < T_UP:
            return a * (0.5 * t * t + b * (cos(w * t) - 1.0))
        return omega_s * (t - half)
    return uf


def _ground_coordinate(mbs):
    n = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    return mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=n, coordinate=0))


def _prescribe(mbs, mGround, node, coords, uf_for):
    """CoordinateConstraints node.coordinate[i] = 0, or theta(t) where uf_for[i]."""
    for i in coords:
        m = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=i))
        if i in uf_for:
            mbs.AddObject(CoordinateConstraint(markerNumbers=[mGround, m], offset=0.0,
                                               offsetUserFunction=uf_for[i]))
        else:
            mbs.AddObject(CoordinateConstraint(markerNumbers=[mGround, m]))


# ---- planar models -----------------------------------------------------------
def build_ancf2d(mbs, n_el, omega_s, reduced=0):
    mbs.AddObject(ObjectGround())
    mGround = _ground_coordinate(mbs)
    le = L / n_el
    nodes = [mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[i * le, 0, 1, 0]))
             for i in range(n_el + 1)]
    for i in range(n_el):
        mbs.AddObject(ObjectANCFCable2D(
            nodeNumbers=[nodes[i], nodes[i + 1]], length=le, massPerLength=RHO_A,
            bendingStiffness=EI, axialStiffness=EA, useReducedOrderIntegration=reduced,
            visualization=VObjectANCFCable2D(show=False)))
    # hub: a rigid 2D body whose position is fixed and whose angle is theta(t)
    nHub = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0, 0, 0]))
    oHub = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nHub, mass=1.0, inertia=1.0,
                                           visualization=VObjectRigidBody2D(show=False)))
    _prescribe(mbs, mGround, nHub, [0, 1, 2], {2: _theta_offset(omega_s)})
    # clamp: node 0 position = hub position, slope angle = hub angle
    # (the joint constrains the slope direction only, not its length)
    mHub = mbs.AddMarker(MarkerBodyRigid(bodyNumber=oHub, localPosition=[0, 0, 0]))
    mN0 = mbs.AddMarker(MarkerNodeRigid(nodeNumber=nodes[0]))
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[mHub, mN0], constrainedAxes=[1, 1, 0, 0, 0, 1],
                                     visualization=VObjectJointGeneric(show=False)))
    return nodes[-1]


def build_gx2d(mbs, n_el, omega_s, shear=GA_K, rot_inertia=RHO * I):
    mbs.AddObject(ObjectGround())
    mGround = _ground_coordinate(mbs)
    le = L / n_el
    nodes = [mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[i * le, 0, 0]))
             for i in range(n_el + 1)]
    for i in range(n_el):
        mbs.AddObject(ObjectBeamGeometricallyExact2D(
            nodeNumbers=[nodes[i], nodes[i + 1]], length=le, massPerLength=RHO_A,
            crossSectionInertia=rot_inertia, bendingStiffness=EI, axialStiffness=EA,
            shearStiffness=shear, visualization=VObjectBeamGeometricallyExact2D(show=False)))
    _prescribe(mbs, mGround, nodes[0], [0, 1, 2], {2: _theta_offset(omega_s)})
    return nodes[-1]


# ---- spatial models (precone; gravity along the spin axis) --------------------
def _gravity_load(mbs, body, gravity):
    """Gravity g along -z (global, i.e. along the spin axis) on one element:
    a mass-proportional load, integrated with the element's own mass."""
    if gravity:
        m = mbs.AddMarker(MarkerBodyMass(bodyNumber=body))
        mbs.AddLoad(LoadMassProportional(markerNumber=m, loadVector=[0.0, 0.0, -gravity]))


def section3d():
    s = exu.BeamSection()
    s.massPerLength = RHO_A
    s.inertia = np.diag([RHO * J_T, RHO * I, RHO * I])
    s.stiffnessMatrix = np.diag([EA, GA_K, GA_K, G * J_T, EI, EI])
    return s


def build_gx3d_precone(mbs, n_el, omega_s, beta, gravity=0.0):
    mbs.AddObject(ObjectGround())
    mGround = _ground_coordinate(mbs)
    axis = np.array([math.cos(beta), 0.0, math.sin(beta)])
    # Ry(-beta): x -> (cos b, 0, sin b), z -> (-sin b, 0, cos b)
    cb, sb = math.cos(beta), math.sin(beta)
    R_beam = np.array([[cb, 0.0, -sb], [0.0, 1.0, 0.0], [sb, 0.0, cb]])
    # Euler parameters of R_beam (rotation about y by -beta)
    ep0 = [math.cos(-beta / 2), 0.0, math.sin(-beta / 2), 0.0]
    le = L / n_el
    sec = section3d()
    nodes = [mbs.AddNode(NodeRigidBodyEP(referenceCoordinates=list(i * le * axis) + ep0))
             for i in range(n_el + 1)]
    for i in range(n_el):
        o = mbs.AddObject(ObjectBeamGeometricallyExact(
            nodeNumbers=[nodes[i], nodes[i + 1]], length=le, sectionData=sec,
            visualization=VObjectBeamGeometricallyExact(show=False)))
        _gravity_load(mbs, o, gravity)
    # hub: Tait-Bryan node with angles (0, 0, theta); R = Rz(theta) since the
    # first two angles stay 0 (far from the xyz singularity)
    nHub = mbs.AddNode(NodeRigidBodyRxyz(referenceCoordinates=[0] * 6))
    oHub = mbs.AddObject(ObjectRigidBody(nodeNumber=nHub, mass=1.0,
                                         inertia=[1, 1, 1, 0, 0, 0],
                                         visualization=VObjectRigidBody(show=False)))
    _prescribe(mbs, mGround, nHub, [0, 1, 2, 3, 4, 5], {5: _theta_offset(omega_s)})
    mHub = mbs.AddMarker(MarkerBodyRigid(bodyNumber=oHub, localPosition=[0, 0, 0]))
    mN0 = mbs.AddMarker(MarkerNodeRigid(nodeNumber=nodes[0]))
    # joint frame of marker 0 = hub * R_beam, of marker 1 = node frame: they coincide
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[mHub, mN0], constrainedAxes=[1] * 6,
                                     rotationMarker0=R_beam, rotationMarker1=np.eye(3),
                                     visualization=VObjectJointGeneric(show=False)))
    return nodes[-1], R_beam


def build_ancf3d_precone(mbs, n_el, omega_s, beta, gravity=0.0):
    """3D ANCF cable (Euler-Bernoulli, no torsion), clamp: node 0 position = 0 and
    its slope parallel to the rotating beam axis e(t) = Rz(theta) (cos b, 0, sin b):
    two scalar constraints n_k(t) . r'(0) = 0 (direction only, the slope length,
    i.e. the root strain, stays free)."""
    mbs.AddObject(ObjectGround())
    mGround = _ground_coordinate(mbs)
    cb, sb = math.cos(beta), math.sin(beta)
    R_beam = np.array([[cb, 0.0, -sb], [0.0, 1.0, 0.0], [sb, 0.0, cb]])
    le = L / n_el
    nodes = [mbs.AddNode(NodePointSlope1(referenceCoordinates=[i * le * cb, 0.0, i * le * sb, cb, 0.0, sb]))
             for i in range(n_el + 1)]
    for i in range(n_el):
        o = mbs.AddObject(ObjectANCFCable(
            nodeNumbers=[nodes[i], nodes[i + 1]], length=le, massPerLength=RHO_A,
            bendingStiffness=EI, axialStiffness=EA, visualization=VObjectANCFCable(show=False)))
        _gravity_load(mbs, o, gravity)
    _prescribe(mbs, mGround, nodes[0], [0, 1, 2], {})
    nG = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    mG = mbs.AddMarker(MarkerNodeCoordinates(nodeNumber=nG))
    mN0 = mbs.AddMarker(MarkerNodeCoordinates(nodeNumber=nodes[0]))
    th = _theta_offset(omega_s)

    def normals(t):
        a = th(None, t, 0, 0.0)
        c, s = math.cos(a), math.sin(a)
        return (-s, c, 0.0), (-sb * c, -sb * s, cb)

    def uf_c(mbs_, t, itemNumber, q, q_t, velocityLevel):
        n1, n2 = normals(t)
        return [n1[0] * q[3] + n1[1] * q[4], n2[0] * q[3] + n2[1] * q[4] + n2[2] * q[5]]

    def uf_j(mbs_, t, itemNumber, q, q_t, velocityLevel):
        n1, n2 = normals(t)
        return [[0, 0, 0, n1[0], n1[1], 0.0], [0, 0, 0, n2[0], n2[1], n2[2]]]

    mbs.AddObject(ObjectConnectorCoordinateVector(markerNumbers=[mG, mN0],
                                                  scalingMarker0=np.zeros((2, 6)),
                                                  constraintUserFunction=uf_c,
                                                  jacobianUserFunction=uf_j,
                                                  ))
    mbs.variables['_keep'] = (uf_c, uf_j)
    return nodes[-1], R_beam


# ---- solver ----
def abs_tol_for(n_el):
    """Newton's absolute tolerance on the L2 norm of the residual (N). Its round-off
    floor grows like n^1.5 (axial stiffness EA/l_e times |x| eps, summed over sqrt(n)
    coordinates): about 1e-7 at 16 elements, 1.5e-6 for 256 Simo-Reissner elements."""
    return 1e-6 * max(1.0, (n_el / 32.0) ** 1.5)


def settings(dt, t_end, rho_inf=0.8, rel_tol=1e-8, abs_tol=1e-6, sample=None,
             sparse=True, modified_newton=True, verbose=0):
    s = exu.SimulationSettings()
    ti = s.timeIntegration
    ti.endTime = t_end
    ti.numberOfSteps = int(round(t_end / dt))
    ti.verboseMode = verbose
    ti.adaptiveStep = False          # fixed step: a step that fails is a failed run
    ti.generalizedAlpha.spectralRadius = rho_inf
    ti.generalizedAlpha.computeInitialAccelerations = True
    ti.newton.relativeTolerance = rel_tol
    ti.newton.absoluteTolerance = abs_tol
    ti.newton.useModifiedNewton = modified_newton
    s.solution.file.write = False
    s.solution.sensors.writePeriod = dt if sample is None else sample
    s.solution.sensors.writeHeader = False
    s.solution.restart.write = False
    s.show.computationTime = False
    s.linearSolver.solverType = (exu.LinearSolverType.EigenSparse if sparse
                                 else exu.LinearSolverType.EXUdense)
    return s


def run(model, n_el, omega_s, dt, t_end, beta=0.05, sample=None, kw_hints=False, gravity=0.0, **kw):
    """Build, solve; returns (t, cols, cpu_s). cols = (axial, transverse) in the hub
    frame (2D) or (u, v, w) in the clamped beam frame (precone). cpu_s is
    time.process_time() around mbs.SolveDynamic only."""
    model_kw = {k: kw.pop(k) for k in list(kw) if k in ('shear', 'rot_inertia', 'reduced')}
    kw.setdefault('abs_tol', abs_tol_for(n_el))
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    R_beam = None
    if model == 'ancf2d':
        tip = build_ancf2d(mbs, n_el, omega_s, **model_kw)
    elif model == 'gx2d':
        tip = build_gx2d(mbs, n_el, omega_s, **model_kw)
    elif model == 'ancf3d':
        tip, R_beam = build_ancf3d_precone(mbs, n_el, omega_s, beta, gravity)
    elif model == 'gx3d':
        tip, R_beam = build_gx3d_precone(mbs, n_el, omega_s, beta, gravity)
    else:
        raise ValueError(model)
    sens = mbs.AddSensor(SensorNode(nodeNumber=tip, outputVariableType=exu.OutputVariableType.Position,
                                    storeInternal=True, writeToFile=False))
    mbs.Assemble()
    s = settings(dt, t_end, sample=sample, **kw)
    c0 = time.process_time()
    mbs.SolveDynamic(s, showHints=kw_hints)
    cpu = time.process_time() - c0
    data = np.array(mbs.GetSensorStoredData(sens))
    t, p = data[:, 0], data[:, 1:4]
    th = theta_array(t, omega_s)
    c, sn = np.cos(th), np.sin(th)
    if R_beam is None:
        axial = c * p[:, 0] + sn * p[:, 1] - L
        transverse = -sn * p[:, 0] + c * p[:, 1]
        return t, (axial, transverse), cpu
    # hub frame, then beam frame
    hx = c * p[:, 0] + sn * p[:, 1]
    hy = -sn * p[:, 0] + c * p[:, 1]
    hz = p[:, 2]
    hub = np.stack([hx, hy, hz], axis=1)
    loc = hub @ R_beam            # rows: R_beam^T * hub_vector
    return t, (loc[:, 0] - L, loc[:, 1], loc[:, 2]), cpu
