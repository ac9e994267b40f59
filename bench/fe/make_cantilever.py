#!/usr/bin/env python3
"""A small solid cantilever from scikit-fem: the FE test data of issue 23.

Builds a box L x B x H (along x, y, z; the x = 0 face is the clamped
interface) of trilinear hexahedra (ElementHex1), assembles the consistent
mass matrix and the linear-elastic stiffness matrix (3 translations per node)
and writes, into the output directory (default: tests/data/fe):

- cantilever_nodes.csv        header `x,y,z`, one row per node (node i = row i)
- cantilever_mass.mtx         Matrix Market, coordinate real symmetric
- cantilever_stiffness.mtx    the same for K
- cantilever_interface.csv    header `node`: the 0-based nodes on x = 0
- cantilever_eigen.csv        header `mode,lambda,omega`: every eigenvalue
                              lambda = omega^2 (rad^2/s^2) of the clamped
                              model (interface DOFs removed), from
                              scipy.linalg.eigh on the dense reduced matrices
- cantilever_eigen_free.csv   the same for the free-free model (every DOF),
                              its six rigid-body eigenvalues (round-off)
                              dropped
- cantilever.json             what was built (sizes, material, mesh, orders)

Degrees of freedom are ordered node by node: ux, uy, uz of node 0, then of
node 1, ... scikit-fem numbers the DOFs of an ElementVector its own way
(`basis.nodal_dofs[c, i]` is the DOF of component c at node i); the matrices
are permuted explicitly to the node-by-node order before writing.

Values are written with 17 significant digits. The written lower triangle is
the matrix the eigenvalues are computed from (mirrored), so the files and
the reference eigenvalues agree bit for bit.

Needs numpy, scipy and scikit-fem (see bench/fe/README.md); installs nothing.
"""

import argparse
import csv
import json
import os
import sys

import numpy as np
import scipy
import scipy.io
import scipy.linalg
import scipy.sparse as sp
import skfem
from skfem import Basis, BilinearForm, ElementHex1, ElementVector, MeshHex, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

# Steel, SI units.
E = 210e9
NU = 0.3
RHO = 7850.0
# Box and mesh.
L, B, H = 1.0, 0.1, 0.1
NX, NY, NZ = 10, 2, 2


def build():
    mesh = MeshHex.init_tensor(
        np.linspace(0.0, L, NX + 1),
        np.linspace(-B / 2, B / 2, NY + 1),
        np.linspace(-H / 2, H / 2, NZ + 1),
    )
    basis = Basis(mesh, ElementVector(ElementHex1()))
    n = mesh.p.shape[1]
    if basis.N != 3 * n:
        sys.exit(f"expected 3 DOFs per node, scikit-fem has {basis.N} for {n} nodes")

    @BilinearForm
    def mass(u, v, w):
        return RHO * dot(u, v)

    lam, mu = lame_parameters(E, NU)
    m = asm(mass, basis).tocsr()
    k = asm(linear_elasticity(lam, mu), basis).tocsr()

    # perm[3 i + c] = scikit-fem's DOF of component c at node i.
    nodal = np.asarray(basis.nodal_dofs)
    perm = np.empty(3 * n, dtype=np.int64)
    for i in range(n):
        for c in range(3):
            perm[3 * i + c] = nodal[c, i]
    if sorted(perm.tolist()) != list(range(3 * n)):
        sys.exit("scikit-fem's nodal DOFs are not a permutation of 0..3n")
    m = m[perm][:, perm]
    k = k[perm][:, perm]
    return mesh, m, k


def lower_mirrored(a):
    """The lower triangle of `a` (explicit zeros dropped) and the dense
    symmetric matrix it denotes."""
    low = sp.tril(a, format="coo")
    low.eliminate_zeros()
    dense = low.toarray()
    dense = dense + np.tril(dense, -1).T
    return low, dense


def write_mtx(path, low, comment):
    # mmwrite's `symmetry="symmetric"` writes the lower triangle of a
    # symmetric matrix: give it the mirrored one so nothing is re-derived.
    full = (low + sp.tril(low, -1).T).tocoo()
    scipy.io.mmwrite(path, full, comment=comment, field="real", precision=17, symmetry="symmetric")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="tests/data/fe", help="output directory")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    mesh, m, k = build()
    n = mesh.p.shape[1]
    m_low, m_dense = lower_mirrored(m)
    k_low, k_dense = lower_mirrored(k)

    interface = [i for i in range(n) if mesh.p[0, i] == 0.0]
    clamped = {3 * i + c for i in interface for c in range(3)}
    free = [d for d in range(3 * n) if d not in clamped]
    lam = scipy.linalg.eigh(
        k_dense[np.ix_(free, free)], m_dense[np.ix_(free, free)], eigvals_only=True
    )

    # The free-free model: every DOF; the six rigid motions give eigenvalues
    # at round-off level (|lambda| ~ 1e-6 of the first elastic one or less),
    # dropped here; the elastic ones are written.
    lam_free = scipy.linalg.eigh(k_dense, m_dense, eigvals_only=True)
    if not (np.all(np.abs(lam_free[:6]) < 1e-6 * lam_free[6]) and lam_free[6] > 0):
        sys.exit(f"expected six rigid modes, got eigenvalues {lam_free[:8]}")
    lam_free = lam_free[6:]

    def p(name):
        return os.path.join(args.out, name)

    with open(p("cantilever_nodes.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["x", "y", "z"])
        for i in range(n):
            w.writerow([repr(float(v)) for v in mesh.p[:, i]])
    what = (
        f"scikit-fem {skfem.__version__}: box {L} x {B} x {H} m, {NX} x {NY} x {NZ} ElementHex1,"
        f" E = {E}, nu = {NU}, rho = {RHO}; DOFs node by node (ux, uy, uz)"
    )
    write_mtx(p("cantilever_mass.mtx"), m_low, "consistent mass matrix, " + what)
    write_mtx(p("cantilever_stiffness.mtx"), k_low, "linear-elastic stiffness matrix, " + what)
    with open(p("cantilever_interface.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["node"])
        for i in interface:
            w.writerow([i])
    with open(p("cantilever_eigen.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["mode", "lambda", "omega"])
        for j, v in enumerate(lam):
            w.writerow([j + 1, repr(float(v)), repr(float(np.sqrt(v)))])
    with open(p("cantilever_eigen_free.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["mode", "lambda", "omega"])
        for j, v in enumerate(lam_free):
            w.writerow([j + 1, repr(float(v)), repr(float(np.sqrt(v)))])
    meta = {
        "generator": "bench/fe/make_cantilever.py",
        "versions": {
            "scikit-fem": skfem.__version__,
            "scipy": scipy.__version__,
            "numpy": np.__version__,
        },
        "length": L,
        "width_y": B,
        "height_z": H,
        "elements": [NX, NY, NZ],
        "element": "ElementHex1 (trilinear hexahedron), default quadrature",
        "young": E,
        "poisson": NU,
        "density": RHO,
        "nodes": n,
        "dofs": 3 * n,
        "dof_order": "node by node: ux, uy, uz of node 0, then node 1, ...",
        "interface": "nodes with x = 0 (cantilever_interface.csv), all their DOFs clamped",
        "eigen": "scipy.linalg.eigh(K_ff, M_ff) of the clamped model, every mode",
        "eigen_free": "scipy.linalg.eigh(K, M) of the free model, the six rigid modes dropped",
    }
    with open(p("cantilever.json"), "w") as f:
        json.dump(meta, f, indent=2)
        f.write("\n")
    print(
        f"{n} nodes, {3 * n} DOFs, {len(interface)} interface nodes;"
        f" nnz(M lower) = {m_low.nnz}, nnz(K lower) = {k_low.nnz};"
        f" omega_1..4 = {np.sqrt(lam[:4])} rad/s; free-free omega_1..4 = {np.sqrt(lam_free[:4])} rad/s"
    )


if __name__ == "__main__":
    main()
