#!/usr/bin/env python3
"""Writes scenes/data/nrel5mw_blade.csv from the NREL 5-MW blade's public input
files (see scenes/data/README.md for the sources, the commit and every mapping).

    bench/blade/.venv/bin/python bench/blade/make_csv.py \
        --elastodyn NRELOffshrBsline5MW_Blade.dat \
        --beamdyn NRELOffshrBsline5MW_BeamDyn_Blade.dat \
        [--out scenes/data/nrel5mw_blade.csv]

Only the standard library is used; all arithmetic on the table is exact
decimal arithmetic (``decimal.Decimal``), so the CSV holds the source's digits
times the documented factors, with no binary rounding, except the twist
(degrees to radians, written with 17 significant digits).

Columns written (SI, ffr's frame: x along the span from the root, y in the
rotor plane (edge), z out of the rotor plane (flap)):

    x       = BlFract * 61.5                         [m]
    mass    = BMassDen * AdjBlMs                     [kg/m]
    ea      = BeamDyn K33                            [N]
    ei_y    = FlpStff  (= BeamDyn K55)               [N m^2]  bending in x-z (w), flap
    ei_z    = EdgStff  (= BeamDyn K44)               [N m^2]  bending in x-y (v), edge
    gj      = BeamDyn K66                            [N m^2]
    rho_iy  = FlpIner * AdjBlMs, FlpIner = BeamDyn M55 [kg m]  (about the flap-rotation axis y)
    rho_iz  = EdgIner * AdjBlMs, EdgIner = BeamDyn M44 [kg m]  (about the edge-rotation axis z)
    twist   = -StrcTwst * pi/180                     [rad about +x]
"""

import argparse
import math
import re
import sys
from decimal import Decimal, getcontext
from pathlib import Path

getcontext().prec = 50

BLADE_LENGTH = Decimal("61.5")  # m, root (hub radius 1.5 m) to tip (63 m)
EXPECTED_STATIONS = 49


def dec(token: str, sig: int | None = None) -> Decimal:
    """A decimal from a number as written in the file. With ``sig``, the value is
    first rounded to ``sig`` significant digits: OpenFAST/r-test writes the
    ElastoDyn table with 16 digits of a binary double (9.672 -> 9.672000000000001),
    and 12 significant digits recover the decimal value the table was made from."""
    d = Decimal(token)
    if sig is not None and d != 0:
        d = Decimal(format(d, f".{sig - 1}e"))
    return d.normalize() if d != 0 else Decimal(0)


def read_elastodyn(path: Path):
    lines = path.read_text().splitlines()
    adj = None
    n = None
    for line in lines:
        parts = line.split()
        if len(parts) >= 2 and parts[1] == "AdjBlMs":
            adj = dec(parts[0])
        if len(parts) >= 2 and parts[1] == "NBlInpSt":
            n = int(parts[0])
    if adj is None or n is None:
        sys.exit(f"{path}: no AdjBlMs or NBlInpSt line")
    head = next(i for i, l in enumerate(lines) if l.split()[:1] == ["BlFract"])
    names = lines[head].split()
    rows = []
    for line in lines[head + 2 : head + 2 + n]:
        values = line.split()
        if len(values) != len(names):
            sys.exit(f"{path}: a table row has {len(values)} values for {len(names)} columns")
        rows.append({k: dec(v, sig=12) for k, v in zip(names, values)})
    return adj, names, rows


def read_beamdyn(path: Path):
    text = path.read_text()
    n = int(re.search(r"^\s*(\d+)\s+station_total", text, re.M).group(1))
    start = re.search(r"^\s*-+\s*distributed properties.*$", text, re.M | re.I).end()
    tokens = [l.split() for l in text[start:].splitlines() if l.strip()]
    stations = []
    i = 0
    for _ in range(n):
        eta = dec(tokens[i][0])
        k = [[dec(v) for v in tokens[i + 1 + r]] for r in range(6)]
        m = [[dec(v) for v in tokens[i + 7 + r]] for r in range(6)]
        if any(len(row) != 6 for row in k + m):
            sys.exit(f"{path}: a 6x6 matrix row without 6 values near station {eta}")
        stations.append((eta, k, m))
        i += 13
    return stations


def fmt(d: Decimal) -> str:
    d = d.normalize()
    if d == 0:
        return "0"
    if Decimal("1e-3") <= abs(d) < Decimal("1e6"):
        return format(d, "f")
    return format(d, "e").replace("e+", "e")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--elastodyn", required=True, type=Path)
    ap.add_argument("--beamdyn", required=True, type=Path)
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[2] / "scenes/data/nrel5mw_blade.csv")
    args = ap.parse_args()

    adj, names, ed = read_elastodyn(args.elastodyn)
    bd = read_beamdyn(args.beamdyn)
    if adj != Decimal("1.04536"):
        sys.exit(f"AdjBlMs is {adj}, the README documents 1.04536")
    if len(ed) != EXPECTED_STATIONS or len(bd) != EXPECTED_STATIONS:
        sys.exit(f"{len(ed)} ElastoDyn and {len(bd)} BeamDyn stations, expected {EXPECTED_STATIONS}")

    # The two files must describe the same blade: same stations, same mass per
    # length, same flap/edge stiffness; the BeamDyn matrices must be diagonal
    # (no offsets or couplings that the CSV would drop) and isotropic in mass.
    for row, (eta, k, m) in zip(ed, bd):
        checks = {
            "BlFract = eta": row["BlFract"] == eta,
            "BMassDen = M11 = M22 = M33": row["BMassDen"] == m[0][0] == m[1][1] == m[2][2],
            "FlpStff = K55": row["FlpStff"] == k[4][4],
            "EdgStff = K44": row["EdgStff"] == k[3][3],
            "K off-diagonal = 0": all(k[r][c] == 0 for r in range(6) for c in range(6) if r != c),
            "M off-diagonal = 0": all(m[r][c] == 0 for r in range(6) for c in range(6) if r != c),
            "M66 = M44 + M55": m[5][5] == m[3][3] + m[4][4],
        }
        failed = [name for name, ok in checks.items() if not ok]
        if failed:
            sys.exit(f"station {eta}: {', '.join(failed)}")
    if ed[0]["BlFract"] != 0 or ed[-1]["BlFract"] != 1:
        sys.exit("BlFract must run from 0 to 1")

    out_rows = []
    for row, (eta, k, m) in zip(ed, bd):
        twist = -float(row["StrcTwst"]) * math.pi / 180.0
        out_rows.append(
            [
                fmt(row["BlFract"] * BLADE_LENGTH),
                fmt(row["BMassDen"] * adj),
                fmt(k[2][2]),
                fmt(row["FlpStff"]),
                fmt(row["EdgStff"]),
                fmt(k[5][5]),
                fmt(m[4][4] * adj),
                fmt(m[3][3] * adj),
                "0" if twist == 0 else repr(twist),
            ]
        )
    header = "x,mass,ea,ei_y,ei_z,gj,rho_iy,rho_iz,twist"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(header + "\n" + "".join(",".join(r) + "\n" for r in out_rows))
    print(f"wrote {args.out} ({len(out_rows)} stations; ElastoDyn columns {' '.join(names)})")


if __name__ == "__main__":
    main()
