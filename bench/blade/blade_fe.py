#!/usr/bin/env python3
"""Independent finite-element reference for issue 19 (section tables): the
clamped, non-rotating NREL 5-MW blade of scenes/data/nrel5mw_blade.csv, and
the tapered cantilevers that validate this code against published and
semi-analytical frequencies. Shares no code with ffr.

    bench/blade/setup.sh
    bench/blade/.venv/bin/python bench/blade/blade_fe.py [--csv ...] [--out bench/blade/results.json]

Model (see README.md for the formulas and conventions):
- straight Euler-Bernoulli beam along x, clamped at x = 0; bending in x-y
  (displacement v) and x-z (displacement w) with cubic Hermite elements
  (nodal v, v', w, w'); axial u and torsion phi with linear elements;
- section properties are the CSV's columns interpolated linearly in x between
  stations; every element is integrated piecewise between the stations it
  contains, with Gauss-Legendre quadrature on each piece;
- structural twist t(x) rotates the principal axes about +x, giving
      EI_zz = ei_z cos^2 t + ei_y sin^2 t      (coefficient of v''^2)
      EI_yy = ei_y cos^2 t + ei_z sin^2 t      (coefficient of w''^2)
      EI_yz = (ei_z - ei_y) sin t cos t        (U = 1/2 int EI_zz v''^2 + 2 EI_yz v'' w'' + EI_yy w''^2)
  and the same for the rotary inertia (rho_iy, rho_iz -> rho_Iyy, rho_Izz,
  rho_Iyz with T = 1/2 int rho_Izz v.'^2 + 2 rho_Iyz v.' w.' + rho_Iyy w.'^2);
- generalized eigenproblem K q = omega^2 M q (scipy.sparse.linalg.eigsh,
  shift-invert about 0); each frequency is the Rayleigh quotient 2U/2T of its
  eigenvector with U, T integrated by quadrature (see modes()).
"""

import argparse
import json
import math
import platform
import time
from pathlib import Path

import numpy as np
import scipy
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
COLUMNS = ["x", "mass", "ea", "ei_y", "ei_z", "gj", "rho_iy", "rho_iz", "twist"]
GAUSS_POINTS = 6  # per piece between stations: exact for polynomials of degree 11


# ----------------------------------------------------------------------------
# Sections
# ----------------------------------------------------------------------------


class TableSections:
    """Columns of a section table, linear in x between stations.

    twist_mode:
      "angle"      - the twist angle is interpolated linearly and the principal
                     values are rotated at every quadrature point (the CSV's
                     columns, each linear, as the issue states them);
      "components" - the rotated components (EI_yy, EI_zz, EI_yz, rho_I..) are
                     formed at the stations and interpolated linearly (what an
                     exact rational integration of linear coefficients sees);
      "none"       - twist ignored (principal axes = y, z everywhere).
    """

    def __init__(self, table, twist_mode="angle", rotary=True):
        self.t = {k: np.asarray(v, dtype=float) for k, v in table.items()}
        x = self.t["x"]
        if x[0] != 0.0 or np.any(np.diff(x) <= 0):
            raise ValueError("x must start at 0 and increase")
        self.length = float(x[-1])
        self.breaks = x
        self.twist_mode = twist_mode
        self.rotary = rotary
        if twist_mode == "components":
            self.comp = rotated(self.t["ei_y"], self.t["ei_z"], self.t["rho_iy"], self.t["rho_iz"], self.t["twist"])

    def at(self, xq):
        x = self.t["x"]
        lin = lambda col: np.interp(xq, x, col)
        out = {"mass": lin(self.t["mass"]), "ea": lin(self.t["ea"]), "gj": lin(self.t["gj"])}
        rho_j = lin(self.t["rho_iy"] + self.t["rho_iz"])
        if self.twist_mode == "components":
            for k, v in self.comp.items():
                out[k] = lin(v)
        else:
            twist = lin(self.t["twist"]) if self.twist_mode == "angle" else np.zeros_like(xq)
            out.update(rotated(lin(self.t["ei_y"]), lin(self.t["ei_z"]), lin(self.t["rho_iy"]), lin(self.t["rho_iz"]), twist))
        if not self.rotary:
            for k in ("rIyy", "rIzz", "rIyz"):
                out[k] = np.zeros_like(xq)
        out["rho_j"] = rho_j
        return out


class FunctionSections:
    """Sections given by functions of x (the tapered validation beams)."""

    def __init__(self, length, fn):
        self.length = length
        self.breaks = np.array([0.0, length])
        self.fn = fn

    def at(self, xq):
        return self.fn(np.asarray(xq, dtype=float))


def rotated(ei_y, ei_z, r_iy, r_iz, t):
    c, s = np.cos(t), np.sin(t)
    return {
        "EIyy": ei_y * c * c + ei_z * s * s,
        "EIzz": ei_y * s * s + ei_z * c * c,
        "EIyz": (ei_z - ei_y) * s * c,
        "rIyy": r_iy * c * c + r_iz * s * s,
        "rIzz": r_iy * s * s + r_iz * c * c,
        "rIyz": (r_iz - r_iy) * s * c,
    }


def read_csv(path):
    lines = Path(path).read_text().split()
    header = lines[0].split(",")
    if header != COLUMNS:
        raise ValueError(f"{path}: header {header}, expected {COLUMNS}")
    rows = np.array([[float(v) for v in l.split(",")] for l in lines[1:]])
    return {k: rows[:, i] for i, k in enumerate(COLUMNS)}


# ----------------------------------------------------------------------------
# Finite elements
# ----------------------------------------------------------------------------

# dofs per node: u, v, v', w, w', phi
NDOF = 6
U, V, VP, W, WP, PHI = range(6)
FIELD_DOFS = {"u": [U], "v": [V, VP], "w": [W, WP], "phi": [PHI]}
FIELD_OF_DOF = {U: "axial", V: "edge", VP: "edge", W: "flap", WP: "flap", PHI: "torsion"}
_GAUSS = {}


def gauss(n):
    if n not in _GAUSS:
        _GAUSS[n] = np.polynomial.legendre.leggauss(n)
    return _GAUSS[n]


def hermite(xi, h):
    """Cubic Hermite shape functions on an element of length h at xi in [0, 1]:
    N, dN/dx, d2N/dx2, each (len(xi), 4) for the dofs (q1, q1', q2, q2')."""
    h = h[:, None]
    xi = xi[:, None]
    N = np.hstack([1 - 3 * xi**2 + 2 * xi**3, h * (xi - 2 * xi**2 + xi**3), 3 * xi**2 - 2 * xi**3, h * (-(xi**2) + xi**3)])
    dN = np.hstack([(-6 * xi + 6 * xi**2) / h, 1 - 4 * xi + 3 * xi**2, (6 * xi - 6 * xi**2) / h, -2 * xi + 3 * xi**2])
    d2N = np.hstack([(-6 + 12 * xi) / h**2, (-4 + 6 * xi) / h, (6 - 12 * xi) / h**2, (-2 + 6 * xi) / h])
    return N, dN, d2N


class Model:
    """Clamped beam on the given nodes: quadrature data, K, M and the energies
    of a displacement vector.

    Every element is cut at the stations (breakpoints) inside it and each piece
    gets GAUSS_POINTS Gauss-Legendre points, so piecewise-polynomial integrands
    are integrated exactly (up to degree 2*GAUSS_POINTS - 1 per piece)."""

    def __init__(self, nodes, sections, fields=("u", "v", "w", "phi")):
        nodes = np.asarray(nodes, dtype=float)
        self.nodes, self.fields = nodes, fields
        L = nodes[-1]
        br = np.asarray(sections.breaks, dtype=float)
        cuts = np.union1d(nodes, br[(br > 0) & (br < L)])
        cuts = cuts[np.concatenate([[True], np.diff(cuts) > 1e-12 * L])]
        cuts[-1] = L
        a, b = cuts[:-1], cuts[1:]
        elem = np.searchsorted(nodes, 0.5 * (a + b)) - 1
        g, w = gauss(GAUSS_POINTS)
        xq = (0.5 * (a + b))[:, None] + (0.5 * (b - a))[:, None] * g[None, :]
        self.wq = ((0.5 * (b - a))[:, None] * w[None, :]).ravel()
        self.xq = xq.ravel()
        self.e = np.repeat(elem, len(g))
        h = np.diff(nodes)[self.e]
        xi = (self.xq - nodes[self.e]) / h
        self.N, self.dN, self.d2N = hermite(xi, h)
        self.L = np.stack([1 - xi, xi], axis=1)
        self.dL = np.stack([-1.0 / h, 1.0 / h], axis=1)
        self.p = sections.at(self.xq)
        ne = len(nodes) - 1
        base = NDOF * np.arange(ne)[:, None]
        self.dofs = {
            "v": base + np.array([V, VP, NDOF + V, NDOF + VP]),
            "w": base + np.array([W, WP, NDOF + W, NDOF + WP]),
            "u": base + np.array([U, NDOF + U]),
            "phi": base + np.array([PHI, NDOF + PHI]),
        }
        local = sorted(d for f in fields for d in FIELD_DOFS[f])
        self.free = np.array([NDOF * i + d for i in range(1, len(nodes)) for d in local])
        self.n = NDOF * len(nodes)

    def _blocks(self):
        """(field a, field b, stiffness coefficient, mass terms) of the energy
        U = 1/2 sum coef * A_a B_b, T = 1/2 sum coef * C_a D_b."""
        p, N, dN, d2N, Lf, dL = self.p, self.N, self.dN, self.d2N, self.L, self.dL
        f = self.fields
        out = []
        if "v" in f:
            out.append(("v", "v", [(p["EIzz"], d2N, d2N)], [(p["mass"], N, N), (p["rIzz"], dN, dN)]))
        if "w" in f:
            out.append(("w", "w", [(p["EIyy"], d2N, d2N)], [(p["mass"], N, N), (p["rIyy"], dN, dN)]))
        if "v" in f and "w" in f:
            out.append(("v", "w", [(p["EIyz"], d2N, d2N)], [(p["rIyz"], dN, dN)]))
            out.append(("w", "v", [(p["EIyz"], d2N, d2N)], [(p["rIyz"], dN, dN)]))
        if "u" in f:
            out.append(("u", "u", [(p["ea"], dL, dL)], [(p["mass"], Lf, Lf)]))
        if "phi" in f:
            out.append(("phi", "phi", [(p["gj"], dL, dL)], [(p["rho_j"], Lf, Lf)]))
        return out

    def matrices(self):
        ne = len(self.nodes) - 1
        rows, cols, kv, mv = [], [], [], []
        for fa, fb, kt, mt in self._blocks():
            na, nb = self.dofs[fa].shape[1], self.dofs[fb].shape[1]
            for terms, acc in ((kt, kv), (mt, mv)):
                blk = np.zeros((ne, na, nb))
                for coef, A, B in terms:
                    np.add.at(blk, self.e, (self.wq * coef)[:, None, None] * A[:, :, None] * B[:, None, :])
                acc.append(blk.ravel())
            rows.append(np.broadcast_to(self.dofs[fa][:, :, None], (ne, na, nb)).ravel())
            cols.append(np.broadcast_to(self.dofs[fb][:, None, :], (ne, na, nb)).ravel())
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        K = sp.csc_matrix((np.concatenate(kv), (rows, cols)), shape=(self.n, self.n))
        M = sp.csc_matrix((np.concatenate(mv), (rows, cols)), shape=(self.n, self.n))
        return K, M

    def energies(self, q_full):
        """2U and 2T of the nodal vector q_full, by quadrature of squared
        curvatures, strains and velocities: sums of non-negative terms (for a
        positive-definite section), free of the cancellation in q^T K q."""
        val = {}
        for f, dofs in self.dofs.items():
            qe = q_full[dofs][self.e]  # (Q, ndof_elem)
            if f in ("v", "w"):
                val[f] = ((self.N * qe).sum(1), (self.dN * qe).sum(1), (self.d2N * qe).sum(1))
            else:
                val[f] = ((self.L * qe).sum(1), (self.dL * qe).sum(1), None)
        p, f = self.p, self.fields
        u2 = np.zeros_like(self.wq)
        t2 = np.zeros_like(self.wq)
        if "v" in f:
            u2 += p["EIzz"] * val["v"][2] ** 2
            t2 += p["mass"] * val["v"][0] ** 2 + p["rIzz"] * val["v"][1] ** 2
        if "w" in f:
            u2 += p["EIyy"] * val["w"][2] ** 2
            t2 += p["mass"] * val["w"][0] ** 2 + p["rIyy"] * val["w"][1] ** 2
        if "v" in f and "w" in f:
            u2 += 2 * p["EIyz"] * val["v"][2] * val["w"][2]
            t2 += 2 * p["rIyz"] * val["v"][1] * val["w"][1]
        if "u" in f:
            u2 += p["ea"] * val["u"][1] ** 2
            t2 += p["mass"] * val["u"][0] ** 2
        if "phi" in f:
            u2 += p["gj"] * val["phi"][1] ** 2
            t2 += p["rho_j"] * val["phi"][0] ** 2
        return float(self.wq @ u2), float(self.wq @ t2)


def modes(nodes, sections, count=12, fields=("u", "v", "w", "phi")):
    """Lowest natural frequencies (Hz) with the kinetic-energy share of the flap
    (w), edge (v), axial and torsion dofs, and the resulting label.

    The eigenvectors come from eigsh (shift-invert about 0). The frequency of
    each is its Rayleigh quotient 2U/2T evaluated by quadrature (Model.energies):
    the same discrete eigenvalue in exact arithmetic, but without the round-off
    of order eps * lambda_max / lambda (~1e-7 here on fine meshes: EA and EI
    span five decades along the blade) that the eigensolver's own value carries."""
    model = Model(nodes, sections, fields)
    K, M = model.matrices()
    free = model.free
    Kf, Mf = K[free][:, free], M[free][:, free]
    k = min(count, len(free) - 1)
    lam, vec = spla.eigsh(Kf, k=k, M=Mf, sigma=0.0, which="LM")
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    kinds = np.array([FIELD_OF_DOF[d % NDOF] for d in free])
    blocks = {kind: Mf[kinds == kind][:, kinds == kind] for kind in ("flap", "edge", "axial", "torsion") if (kinds == kind).any()}
    out = []
    for j in range(len(lam)):
        q = vec[:, j]
        qf = np.zeros(model.n)
        qf[free] = q
        u2, t2 = model.energies(qf)
        total = q @ (Mf @ q)
        # block-diagonal kinetic-energy shares (the v-w cross term of the twisted
        # rotary inertia is left out of the shares; it is < 1e-3 of the total)
        share = {kind: float(q[kinds == kind] @ (B @ q[kinds == kind]) / total) for kind, B in blocks.items()}
        label = max(share, key=share.get)
        out.append({"f_hz": math.sqrt(u2 / t2) / (2 * math.pi), "f_hz_eigsh": math.sqrt(max(lam[j], 0.0)) / (2 * math.pi),
                    "label": label, "share": share})
    return out


def pick(mode_list, wanted=(("flap", 1), ("flap", 2), ("edge", 1), ("edge", 2))):
    """The frequency of the n-th mode of each label, e.g. ("flap", 2)."""
    res = {}
    for label, n in wanted:
        hits = [m for m in mode_list if m["label"] == label]
        res[f"{label}{n}"] = hits[n - 1]["f_hz"] if len(hits) >= n else None
    return res


# ----------------------------------------------------------------------------
# Meshes
# ----------------------------------------------------------------------------


def mesh_equal(length, n):
    x = np.linspace(0.0, length, n + 1)
    x[-1] = length
    return x


def mesh_stations(x, sub=1):
    """Nodes on the stations, each station interval cut into `sub` equal elements."""
    pts = [x[0]]
    for a, b in zip(x[:-1], x[1:]):
        pts.extend(a + (b - a) * np.arange(1, sub) / sub)
        pts.append(b)
    return np.array(pts)


def fitted_order(hs, errs):
    """Least-squares slope of log(err) against log(h)."""
    pts = [(math.log(h), math.log(e)) for h, e in zip(hs, errs) if e > 0]
    if len(pts) < 2:
        return None
    x, y = np.array(pts).T
    return float(np.polyfit(x, y, 1)[0])


def orders(hs, errs):
    """Observed convergence orders between successive meshes."""
    out = []
    for (h1, e1), (h2, e2) in zip(zip(hs[:-1], errs[:-1]), zip(hs[1:], errs[1:])):
        out.append(math.log(e1 / e2) / math.log(h1 / h2) if e1 > 0 and e2 > 0 else None)
    return out


# ----------------------------------------------------------------------------
# The 5-MW blade
# ----------------------------------------------------------------------------

KEYS = ["flap1", "flap2", "edge1", "edge2"]


def blade_study(table):
    x = table["x"]
    L = float(x[-1])
    variants = {
        "full": dict(twist_mode="angle", rotary=True),
        "twist_components": dict(twist_mode="components", rotary=True),
        "no_twist": dict(twist_mode="none", rotary=True),
        "no_rotary_inertia": dict(twist_mode="angle", rotary=False),
        "no_twist_no_rotary_inertia": dict(twist_mode="none", rotary=False),
    }
    results = {}
    for name, opts in variants.items():
        sec = TableSections(table, **opts)
        ref_nodes = mesh_stations(x, 16)
        ref_modes = modes(ref_nodes, sec, count=14)
        ref = pick(ref_modes)
        ref_more = pick(ref_modes, (("flap", 3), ("edge", 3), ("torsion", 1), ("axial", 1)))
        check = pick(modes(mesh_stations(x, 32), sec, count=14))
        series = {}
        for sname, meshes in (
            ("stations", [(f"stations x{k}", mesh_stations(x, k)) for k in (1, 2, 4, 8)]),
            ("equal", [(f"{n} equal", mesh_equal(L, n)) for n in (8, 16, 32, 64, 128, 256, 512)]),
        ):
            rows = []
            for label, nodes in meshes:
                f = pick(modes(nodes, sec, count=14))
                rows.append(
                    {
                        "mesh": label,
                        "elements": len(nodes) - 1,
                        "h_max": float(np.max(np.diff(nodes))),
                        "f_hz": f,
                        "rel_err": {k: abs(f[k] - ref[k]) / ref[k] for k in KEYS},
                    }
                )
            hs = [r["h_max"] for r in rows]
            rates = {k: orders(hs, [r["rel_err"][k] for r in rows]) for k in KEYS}
            fit = {k: fitted_order(hs, [r["rel_err"][k] for r in rows]) for k in KEYS}
            series[sname] = {"rows": rows, "observed_order": rates, "fitted_order_all": fit}
            if sname == "equal":
                sub = [r for r in rows if r["elements"] <= 128]
                series[sname]["fitted_order_8_to_128"] = {
                    k: fitted_order([r["h_max"] for r in sub], [r["rel_err"][k] for r in sub]) for k in KEYS}
        results[name] = {
            "options": opts,
            "reference": {"mesh": "stations x16 (768 elements)", "f_hz": ref, "more_f_hz": ref_more,
                          "rel_change_to_stations_x32": {k: abs(check[k] - ref[k]) / ref[k] for k in KEYS}},
            "lowest_modes_reference": [{"f_hz": m["f_hz"], "f_hz_eigsh": m["f_hz_eigsh"], "label": m["label"], "share": m["share"]}
                                       for m in ref_modes[:10]],
            "series": series,
        }
    return results


def blade_integrals(table):
    """Mass, first and second mass moments about the root of the piecewise-linear
    mass per length (exact: Simpson's rule is exact for cubics on each piece)."""
    x, m = table["x"], table["mass"]
    tot = {"mass": 0.0, "first_moment": 0.0, "second_moment": 0.0}
    for a, b, ma, mb in zip(x[:-1], x[1:], m[:-1], m[1:]):
        c = 0.5 * (a + b)
        mc = 0.5 * (ma + mb)
        for k, p in (("mass", 0), ("first_moment", 1), ("second_moment", 2)):
            tot[k] += (b - a) / 6 * (ma * a**p + 4 * mc * c**p + mb * b**p)
    tot["cm_from_root"] = tot["first_moment"] / tot["mass"]
    return tot


# The 17 blade analysis nodes of the FAST 5-MW model (RNodes, DRNodes [m], from
# the hub centre; AeroDyn input CertTest/5MW_Baseline/
# NRELOffshrBsline5MW_AeroDyn_Equil_noTwr.dat of old-NWTC/FAST, BldNodes = 17 in
# its ElastoDyn inputs). FAST integrates the blade by the midpoint rule on them.
FAST_RNODES = [2.8667, 5.6, 8.3333, 11.75, 15.85, 19.95, 24.05, 28.15, 32.25, 36.35, 40.45, 44.55, 48.65, 52.75,
               56.1667, 58.9, 61.6333]
FAST_DRNODES = [2.7333] * 3 + [4.1] * 11 + [2.7333] * 3
HUB_RADIUS = 1.5


def fast_node_sums(table):
    """Mass and moments as FAST's 17-node midpoint rule gives them (mass per
    length interpolated linearly at the node centres): explains why the report's
    integrated blade mass differs from the exact integral of the table."""
    x = np.array(FAST_RNODES) - HUB_RADIUS
    dr = np.array(FAST_DRNODES)
    m = np.interp(x, table["x"], table["mass"]) * dr
    out = {"mass": float(m.sum()), "first_moment": float(m @ x), "second_moment": float(m @ x**2)}
    out["cm_from_root"] = out["first_moment"] / out["mass"]
    return out


# ----------------------------------------------------------------------------
# Validation: tapered cantilevers
# ----------------------------------------------------------------------------

# Mabie & Rogers (1972), "Transverse vibrations of double-tapered cantilever
# beams", J. Acoust. Soc. Am. 51, 1771-1774, as used by code_aster's validation
# test SDLL09 (guide VPCS SDLL09/89): L = 1 m, E = 2e11 Pa, rho = 7800 kg/m^3,
# clamped at the large end; depth (bending direction) h: 0.04 -> 0.01 m
# (alpha = h0/h1 = 4), breadth b: 0.04 -> 0.01 m (beta = 4, case 1) or
# 0.05 -> 0.01 m (beta = 5, case 2). f_i = lambda_i/(2 pi) * h1/L^2 * sqrt(E/(12 rho)).
MABIE_ROGERS = {
    "case1_alpha4_beta4": {"h": (0.04, 0.01), "b": (0.04, 0.01), "lambda": [23.289, 73.9, 165.23, 299.7, 478.1],
                           "f_ref_hz": [54.18, 171.94, 384.40, 697.24, 1112.28]},
    "case2_alpha4_beta5": {"h": (0.04, 0.01), "b": (0.05, 0.01), "lambda": [24.308, 75.56, 167.21, 301.9, 480.4],
                           "f_ref_hz": [56.55, 175.19, 389.01, 702.36, 1117.63]},
}
MR_L, MR_E, MR_RHO = 1.0, 2.0e11, 7800.0


def planar_fn(ei, m):
    def fn(xq):
        z = np.zeros_like(xq)
        return {"mass": m(xq), "EIzz": ei(xq), "EIyy": z, "EIyz": z, "rIyy": z, "rIzz": z, "rIyz": z,
                "ea": z, "gj": z, "rho_j": z}
    return fn


def double_taper(case):
    (h0, h1), (b0, b1) = case["h"], case["b"]
    h = lambda x: h0 + (h1 - h0) * x / MR_L
    b = lambda x: b0 + (b1 - b0) * x / MR_L
    return (lambda x: MR_E * b(x) * h(x) ** 3 / 12.0), (lambda x: MR_RHO * b(x) * h(x))


def station_table(ei, m, n_st, length):
    x = np.linspace(0.0, length, n_st)
    z = np.zeros_like(x)
    return {"x": x, "mass": m(x), "ea": z, "ei_y": ei(x), "ei_z": ei(x), "gj": z, "rho_iy": z, "rho_iz": z, "twist": z}


def mabie_rogers_study():
    out = {}
    for name, case in MABIE_ROGERS.items():
        ei, m = double_taper(case)
        sec = FunctionSections(MR_L, planar_fn(ei, m))
        h1 = case["h"][1]
        scale = h1 / MR_L**2 * math.sqrt(MR_E / (12 * MR_RHO)) / (2 * math.pi)
        f_lambda = [lam * scale for lam in case["lambda"]]
        f_fine = [md["f_hz"] for md in modes(mesh_equal(MR_L, 256), sec, count=6, fields=("v",))][:5]
        exact = shoot_frequencies(ei, m, MR_L, [2 * math.pi * f for f in f_fine])
        rows = []
        for n in (8, 16, 32, 64, 128, 256):
            f = [md["f_hz"] for md in modes(mesh_equal(MR_L, n), sec, count=6, fields=("v",))][:5]
            rows.append({"elements": n, "f_hz": f,
                         "lambda": [fi / scale for fi in f],
                         "rel_err_vs_shooting": [(fi - fe) / fe for fi, fe in zip(f, exact)],
                         "rel_diff_vs_lambda_table": [(fi - fl) / fl for fi, fl in zip(f, f_lambda)],
                         "rel_diff_vs_code_aster_vale_refe": [(fi - fr) / fr for fi, fr in zip(f, case["f_ref_hz"])]})
        # The same beam given as a section table (linear between equally spaced
        # stations), as ffr would read it: the frequencies ffr should reproduce.
        tables = []
        for n_st in (31, 121):
            tab = station_table(ei, m, n_st, MR_L)
            st = TableSections(tab, twist_mode="none", rotary=False)
            f = [md["f_hz"] for md in modes(mesh_stations(tab["x"], 8), st, count=6, fields=("v",))][:5]
            f_nodes = [md["f_hz"] for md in modes(tab["x"], st, count=6, fields=("v",))][:5]
            tables.append({"stations": n_st, "mesh": "stations x8", "f_hz": f,
                           "table": {"x": tab["x"].tolist(), "mass": tab["mass"].tolist(), "ei": tab["ei_z"].tolist()} if n_st <= 31 else "x_i = i/(n-1); mass, ei = the exact taper at x_i",
                           "f_hz_nodes_on_stations": f_nodes,
                           "rel_diff_vs_exact_taper": [(a - b) / b for a, b in zip(f, exact)]})
        out[name] = {"geometry": {"L": MR_L, "E": MR_E, "rho": MR_RHO, "h_root_tip": case["h"], "b_root_tip": case["b"]},
                     "published_lambda": case["lambda"], "published_f_hz_from_lambda": f_lambda,
                     "code_aster_vale_refe_hz": case["f_ref_hz"],
                     "f_exact_shooting_hz": exact, "lambda_exact_shooting": [f / scale for f in exact],
                     "rel_diff_published_lambda_vs_shooting": [(fl - fe) / fe for fl, fe in zip(f_lambda, exact)],
                     "rel_diff_code_aster_vale_refe_vs_shooting": [(fr - fe) / fe for fr, fe in zip(case["f_ref_hz"], exact)],
                     "fe": rows, "as_section_table": tables}
    return out


def shoot_frequencies(ei, m, length, guesses):
    """Exact (to ODE tolerance) cantilever frequencies of (EI w'')'' = w^2 m w by
    shooting: y = (w, w', M = EI w'', V = M'), clamped at 0, M = V = 0 at L."""

    def det(omega):
        def rhs(x, y):
            w, t, Mm, Vv = y
            return [t, Mm / ei(x), Vv, omega**2 * m(x) * w]

        ends = []
        for y0 in ([0, 0, 1, 0], [0, 0, 0, 1]):
            s = solve_ivp(rhs, (0, length), y0, method="DOP853", rtol=1e-13, atol=1e-15)
            ends.append(s.y[2:, -1])
        return ends[0][0] * ends[1][1] - ends[0][1] * ends[1][0]

    out = []
    for g in guesses:
        a, b = 0.97 * g, 1.03 * g
        out.append(brentq(det, a, b, xtol=1e-14, rtol=1e-15) / (2 * math.pi))
    return out


def width_taper_study():
    """Constant depth, breadth linear from b0 at the root to c*b0 at the tip: EI
    and m are exactly linear in x (the form of an ffr section table with two
    stations). Reference by shooting on the ODE (independent of the FE)."""
    out = {}
    for c in (1.0, 0.5, 0.25):
        ei = lambda x, c=c: 1.0 - (1.0 - c) * x
        m = lambda x, c=c: 1.0 - (1.0 - c) * x
        tab = {"x": np.array([0.0, 1.0]), "mass": np.array([1.0, c]), "ea": np.zeros(2), "ei_y": np.array([1.0, c]),
               "ei_z": np.array([1.0, c]), "gj": np.zeros(2), "rho_iy": np.zeros(2), "rho_iz": np.zeros(2), "twist": np.zeros(2)}
        sec = TableSections(tab, twist_mode="none", rotary=False)
        rows = []
        for n in (4, 8, 16, 32, 64):
            f = [md["f_hz"] for md in modes(mesh_equal(1.0, n), sec, count=6, fields=("v",))][:4]
            rows.append({"elements": n, "f_hz": f})
        exact = shoot_frequencies(ei, m, 1.0, [2 * math.pi * f for f in rows[-1]["f_hz"]])
        for r in rows:
            r["rel_err"] = [(a - b) / b for a, b in zip(r["f_hz"], exact)]
        hs = [1.0 / r["elements"] for r in rows]
        rates = [orders(hs, [abs(r["rel_err"][i]) for r in rows]) for i in range(4)]
        entry = {"tip_to_root_ratio": c, "EI0": 1.0, "m0": 1.0, "L": 1.0, "f_exact_hz": exact,
                 "omega_coefficients": [2 * math.pi * f for f in exact], "fe": rows, "observed_order": rates}
        if c == 1.0:
            beta = [1.8751040687119611, 4.6940911329741745, 7.8547574382376126, 10.995540734875467]
            entry["textbook_uniform_f_hz"] = [b**2 / (2 * math.pi) for b in beta]
        out[f"tip_ratio_{c:g}"] = entry
    return out


# ----------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--csv", default=str(ROOT / "scenes/data/nrel5mw_blade.csv"))
    ap.add_argument("--out", default=str(HERE / "results.json"))
    args = ap.parse_args()
    t0 = time.process_time()
    w0 = time.perf_counter()
    table = read_csv(args.csv)
    res = {
        "generator": "bench/blade/blade_fe.py",
        "versions": {"python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__},
        "csv": str(Path(args.csv).resolve().relative_to(ROOT)) if Path(args.csv).resolve().is_relative_to(ROOT) else args.csv,
        "gauss_points_per_piece": GAUSS_POINTS,
        "nrel5mw": {"integrals": blade_integrals(table), "fast_17_node_midpoint_sums": fast_node_sums(table),
                    "study": blade_study(table)},
        "validation": {"mabie_rogers_double_taper": mabie_rogers_study(), "width_taper_shooting": width_taper_study()},
    }
    res["cpu_seconds"] = round(time.process_time() - t0, 2)
    res["wall_seconds"] = round(time.perf_counter() - w0, 2)
    Path(args.out).write_text(json.dumps(res, indent=1) + "\n")
    summary(res)


def summary(res):
    b = res["nrel5mw"]
    print("NREL 5-MW blade, clamped, non-rotating")
    print("  exact integrals:", {k: round(v, 4) for k, v in b["integrals"].items()})
    print("  FAST 17-node sums:", {k: round(v, 4) for k, v in b["fast_17_node_midpoint_sums"].items()})
    for name, r in b["study"].items():
        f = r["reference"]["f_hz"]
        print(f"  {name:28s}", " ".join(f"{k}={f[k]:.6f}" for k in KEYS), " more:",
              " ".join(f"{k}={v:.4f}" for k, v in r["reference"]["more_f_hz"].items() if v))
    full = b["study"]["full"]["series"]
    for s in ("stations", "equal"):
        print(f"  series {s} (full):")
        for row in full[s]["rows"]:
            print(f"    {row['mesh']:14s}", " ".join(f"{k}={row['f_hz'][k]:.7f}({row['rel_err'][k]:.1e})" for k in KEYS))
        print("    observed orders:", {k: [None if o is None else round(o, 2) for o in v] for k, v in full[s]["observed_order"].items()})
        print("    fitted orders (all):", {k: round(v, 2) for k, v in full[s]["fitted_order_all"].items()},
              "(8-128):" if s == "equal" else "", {k: round(v, 2) for k, v in full[s].get("fitted_order_8_to_128", {}).items()})
    print("Mabie & Rogers double taper")
    for name, c in res["validation"]["mabie_rogers_double_taper"].items():
        r = c["fe"][-1]
        print(f"  {name}: FE({r['elements']}) lambda", [round(v, 4) for v in r["lambda"]], "published", c["published_lambda"])
        print("     FE rel err vs shooting", [f"{v:.1e}" for v in r["rel_err_vs_shooting"]])
        print("     published lambda rel to shooting", [f"{v:.1e}" for v in c["rel_diff_published_lambda_vs_shooting"]])
        print("     code_aster VALE_REFE rel to shooting", [f"{v:.1e}" for v in c["rel_diff_code_aster_vale_refe_vs_shooting"]])
        for t in c["as_section_table"]:
            print(f"     as {t['stations']}-station table: f", [round(v, 4) for v in t["f_hz"]], "rel vs exact taper", [f"{v:.1e}" for v in t["rel_diff_vs_exact_taper"]])
    print("Width taper (shooting reference)")
    for name, c in res["validation"]["width_taper_shooting"].items():
        print(f"  {name}: exact omega coefficients", [round(v, 6) for v in c["omega_coefficients"]],
              " FE 64 rel err", [f"{v:.1e}" for v in c["fe"][-1]["rel_err"]], " orders(f1)", [None if o is None else round(o, 2) for o in c["observed_order"][0]])
        if "textbook_uniform_f_hz" in c:
            print("     textbook uniform f", [round(v, 10) for v in c["textbook_uniform_f_hz"]], "shooting", [round(v, 10) for v in c["f_exact_hz"]])
    print(f"cpu {res['cpu_seconds']} s, wall {res['wall_seconds']} s")


if __name__ == "__main__":
    main()
