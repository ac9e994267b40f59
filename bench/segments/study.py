#!/usr/bin/env python3
"""Segments against one floating frame (issue 35): the convergence study
behind `segments = N` and the single-frame warning's threshold
(src/scene/frames.rs, SINGLE_FRAME_ROTATION).

Runs `ffr run` on the report's spin-ups with 1, 2, 4 and 8 segments (16
elements in all) and records, per run: the largest elastic section rotation
of a body or segment (from the run summary), the tip error against the
geometrically exact reference of bench/reference/ (max |ffr - ref| over the
reference's peak, at the reference's times, 0-20 s), the CPU time and the
Newton work. Writes bench/segments/study.csv. Standard library only.

Usage: python3 bench/segments/study.py [--ffr PATH_TO_FFR] [--out CSV]
(default: target/release/ffr, built by `cargo build --release`).
"""

import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# (case, scene file, edits, reference CSV, output columns (ffr, reference))
CASES = [
    ("spin-up-3d", "scenes/spin_up_gravity.toml", [], "spin_up_gravity_omega4.csv",
     [("tip_v", "tip_v"), ("tip_w", "tip_w")]),
    ("spin-up-4", "scenes/spin_up.toml",
     [("elements = 8\n", "elements = 16\n"), ("dt = 0.01", "dt = 1e-3")],
     "spin_up_omega4.csv", [("tip_transverse", "tip_transverse")]),
    ("spin-up-10", "scenes/spin_up.toml",
     [("elements = 8\n", "elements = 16\n"), ("dt = 0.01", "dt = 1e-3"),
      ("omega = 4.0", "omega = 10.0")],
     "spin_up_omega10.csv", [("tip_transverse", "tip_transverse")]),
]
SEGMENTS = [1, 2, 4, 8]


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return rows


def error(run_rows, ref_rows, col_run, col_ref):
    ref = {round(float(r["t"]), 6): float(r[col_ref]) for r in ref_rows if float(r["t"]) <= 20.0 + 1e-9}
    peak = max(abs(v) for v in ref.values())
    e = 0.0
    for r in run_rows:
        t = round(float(r["t"]), 6)
        if t in ref:
            e = max(e, abs(float(r[col_run]) - ref[t]))
    return e / peak


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ffr", default=os.path.join(ROOT, "target", "release", "ffr"))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "segments", "study.csv"))
    a = ap.parse_args()
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for case, scene, edits, reference, cols in CASES:
            base = open(os.path.join(ROOT, scene)).read()
            for old, new in edits:
                assert base.count(old) == 1, (scene, old)
                base = base.replace(old, new)
            ref = read_csv(os.path.join(ROOT, "bench", "reference", reference))
            for n in SEGMENTS:
                text = base.replace("elements = 16\n", f"elements = 16\nsegments = {n}\n", 1)
                path = os.path.join(tmp, f"{case}-{n}.toml")
                with open(path, "w") as f:
                    f.write(text)
                csv_path = os.path.join(tmp, f"{case}-{n}.csv")
                p = subprocess.run([a.ffr, "run", path, "--csv", csv_path],
                                   capture_output=True, text=True, check=True)
                rot = max(float(x) for x in re.findall(r"elastic rotation of `[^`]*`: at most ([0-9.]+) rad", p.stdout))
                m = re.search(r"steps: (\d+) of dt = \S+ s, (\d+) Newton iterations, (\d+) iteration matrices.*CPU time ([0-9.]+) s", p.stdout)
                steps, its, mats, cpu = int(m[1]), int(m[2]), int(m[3]), float(m[4])
                restarts = re.search(r"(\d+) steps? restarted", p.stdout)
                rows = read_csv(csv_path)
                errs = [error(rows, ref, c, r) for c, r in cols]
                warned = "warning: body" in p.stderr
                out.append(dict(case=case, segments=n, elements=16, max_rotation=f"{rot:.3f}",
                                error=f"{max(errs):.3e}", cpu_s=f"{cpu:.2f}", steps=steps,
                                newton_iterations=its, iteration_matrices=mats,
                                restarts=int(restarts[1]) if restarts else 0,
                                warned=int(warned)))
                print(out[-1], flush=True)
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(out[0].keys()))
        w.writeheader()
        w.writerows(out)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    sys.exit(main())
