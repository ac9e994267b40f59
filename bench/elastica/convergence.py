#!/usr/bin/env python3
"""`ffr static` on the large-deflection cantilever (Bisshopp & Drucker) as a
chain of N flexible bodies, against the elastica of reference.csv.

The beam (L = 1 m, E = 1e9 Pa, A = 1e-4 m^2, I = 1e-10 m^4: EI = 0.1 N m^2,
radius of gyration 1e-3 L, so the axial strain under the load is at most
about 1e-5) is split into N bodies of length L/N, each one element
(`beam2` planar, `beam3` spatial), `reference = "clamped"`; body 1 is
fixed to the ground, body K+1's frame to body K's end section by a `fixed`
joint (`bK@x=l` to `b{K+1}@x=0`). A dead tip load P = alpha EI/L^2 acts
along -y (planar) or, on the spatial beam (EI_y = 0.1, EI_z = 0.2 N m^2),
along -z: out of the beam's x-y plane, bending it in x-z about its weak
axis. Both with geometric stiffening (`stiffening = true`, fourth order)
and without (`false`): each body's frame carries its large rotation, and
the stiffening terms give each body the coupling of its axial force with
its bending that the elastica has.

Run (after `cargo build --release -p ffr-cli`):
    python3 bench/elastica/convergence.py [path/to/ffr]
It writes bench/elastica/convergence.csv: dim, stiffening, alpha, N, the
tip displacements over L, the error max(|du|, |dv|)/L against
reference.csv and the observed rate log2(e(N/2)/e(N)); a scene that has
no equilibrium on the load path is recorded as `no-equilibrium` (its
error empty). ffr-cli/tests/statics.rs runs the same scenes (stiffening on)
and checks the finest chain within 1e-3 L. No third-party modules.
"""

import csv
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
NS = [1, 2, 4, 8, 16, 32]
ALPHAS = [1.0, 2.0, 5.0, 10.0]
E, A, I = 1e9, 1e-4, 1e-10


def scene(n, alpha, dim, stiffening):
    """The chain of n bodies under the tip load alpha EI/L^2 (TOML text)."""
    p = alpha * E * I
    l = 1.0 / n
    out = [
        f"# The cantilever with a dead tip load, alpha = PL^2/EI = {alpha:g}, as {n} bodies",
        f"# (bench/elastica/convergence.py).",
        f"dimension = {dim}",
        "t_end = 1.0",
        "dt = 1e-3",
    ]
    for k in range(1, n + 1):
        out += [
            "",
            f"[bodies.b{k}]",
            f'shape = "beam{dim}"',
            "elements = 1",
            'reference = "clamped"',
            f"stiffening = {'true' if stiffening else 'false'}",
        ]
        if dim == 2:
            out.append(f"params = {{ length = {l!r}, rho = 1000.0, area = {A}, iz = {I}, e = {E} }}")
            out.append(f"position = [{(k - 1) * l!r}, 0.0]")
        else:
            out.append(
                f"params = {{ length = {l!r}, rho = 1000.0, area = {A}, iy = {I}, iz = {2 * I}, "
                f"e = {E}, g = {E / 2.6}, j = {2 * I} }}"
            )
            out.append(f"position = [{(k - 1) * l!r}, 0.0, 0.0]")
    out += ["", "[[joints]]", 'kind = "ground"', 'b = "b1"']
    for k in range(1, n):
        out += ["", "[[joints]]", 'kind = "fixed"', f'a = "b{k}@x={l!r}"', f'b = "b{k + 1}@x=0.0"']
    force = f"[0.0, {-p!r}]" if dim == 2 else f"[0.0, 0.0, {-p!r}]"
    out += ["", "[[forces]]", 'kind = "point"', f'at = "b{n}@x={l!r}"', f"force = {force}"]
    for c in ["x", "y"] if dim == 2 else ["x", "y", "z"]:
        out += [
            "",
            "[[outputs]]",
            f'name = "tip_{c}"',
            'kind = "position"',
            f'at = "b{n}@x={l!r}"',
            f'component = "{c}"',
        ]
    return "\n".join(out) + "\n"


def main():
    ffr = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "../../target/release/ffr")
    with open(os.path.join(HERE, "reference.csv")) as fh:
        ref = {float(r["alpha"]): r for r in csv.DictReader(fh)}
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for dim in (2, 3):
            for stiff in (True, False):
                for alpha in ALPHAS:
                    ru = float(ref[alpha]["tip_u_over_l"])
                    rv = float(ref[alpha]["tip_v_over_l"])
                    prev = None
                    for n in NS:
                        path = os.path.join(tmp, f"c{dim}_{n}.toml")
                        with open(path, "w") as fh:
                            fh.write(scene(n, alpha, dim, stiff))
                        r = subprocess.run([ffr, "static", path, "--json"], capture_output=True, text=True)
                        row = {"dim": dim, "stiffening": str(stiff).lower(), "alpha": f"{alpha:g}", "n": n}
                        if r.returncode != 0:
                            if "no static equilibrium" not in r.stderr:
                                sys.exit(f"dim {dim} alpha {alpha} N {n}: {r.stderr}")
                            row.update(tip_u_over_l="", tip_v_over_l="", error="", rate="", note="no-equilibrium")
                            prev = None
                        else:
                            o = json.loads(r.stdout)["outputs"]
                            u = o["tip_x"] - 1.0
                            v = o["tip_y"] if dim == 2 else o["tip_z"]
                            err = max(abs(u - ru), abs(v - rv))
                            rate = f"{math.log2(prev / err):.2f}" if prev else ""
                            row.update(
                                tip_u_over_l=f"{u:.9f}",
                                tip_v_over_l=f"{v:.9f}",
                                error=f"{err:.3e}",
                                rate=rate,
                                note="",
                            )
                            prev = err
                        rows.append(row)
                        print(row)
    with open(os.path.join(HERE, "convergence.csv"), "w", newline="") as fh:
        w = csv.DictWriter(
            fh,
            ["dim", "stiffening", "alpha", "n", "tip_u_over_l", "tip_v_over_l", "error", "rate", "note"],
            lineterminator="\n",
        )
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
