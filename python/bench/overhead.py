"""The Python call overhead of `Scene.run()` against the same run through
the command line, on the default spin-up (scenes/spin_up.toml).

    python python/bench/overhead.py [--ffr target/release/ffr] [--repeats 30]

Prints, as medians of interleaved repeats on this machine:
- in one process: `scene.run()`'s wall time (the call: the run with the GIL
  released, the outputs handed to numpy) against the simulation's own wall
  time that the library measures (`result.wall`, the figure `ffr run`
  prints as "wall time");
- whole processes: `python -c "ffr.Scene.load(p).run()"` against
  `ffr run p` (which also writes its CSV and SVG).
Not a test: the figures go to docs/python.md.
"""

import argparse
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

import ffr

ROOT = Path(__file__).resolve().parents[2]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ffr", default=str(ROOT / "target" / "release" / "ffr"))
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "spin_up.toml"))
    ap.add_argument("--repeats", type=int, default=30)
    ap.add_argument("--out", default="/tmp/ffr-overhead")
    a = ap.parse_args()

    scene = ffr.Scene.load(a.scene)
    scene.run()  # warm-up: the first call maps the kernels' pages
    call, sim = [], []
    for _ in range(a.repeats):
        t = time.perf_counter()
        r = scene.run()
        call.append(time.perf_counter() - t)
        sim.append(r.wall)
    c, s = statistics.median(call), statistics.median(sim)
    print(f"in process: scene.run() {c * 1e3:.2f} ms, simulation (result.wall) {s * 1e3:.2f} ms, "
          f"overhead {(c - s) * 1e3:.3f} ms = {100 * (c - s) / s:.1f} %")
    # The mean of the per-run differences is less noisy than the difference of medians.
    d = statistics.median(x - y for x, y in zip(call, sim))
    print(f"  per-run median of (call - simulation): {d * 1e3:.3f} ms = {100 * d / s:.2f} % of the simulation")

    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    cli = [a.ffr, "run", a.scene, "--csv", str(out / "run.csv"), "--svg", str(out / "run.svg")]
    py = [sys.executable, "-c", f"import ffr; ffr.Scene.load({a.scene!r}).run()"]
    tc, tp, cli_wall = [], [], []
    for _ in range(a.repeats):
        for cmd, acc in ((cli, tc), (py, tp)):
            t = time.perf_counter()
            out = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True).stdout
            acc.append(time.perf_counter() - t)
            m = re.search(r"wall time ([0-9.]+) s", out)
            if m:
                cli_wall.append(float(m.group(1)))
    mc, mp = statistics.median(tc), statistics.median(tp)
    w = statistics.median(cli_wall)
    print(f"the CLI's own simulation wall time (printed, 1 ms resolution): {w * 1e3:.0f} ms; "
          f"scene.run() against it: {100 * (c - w) / w:+.1f} %")
    print(f"whole process: ffr run {mc * 1e3:.1f} ms, python -c 'Scene.load(p).run()' {mp * 1e3:.1f} ms "
          f"(ratio {mp / mc:.2f}; Python's start-up and imports included)")


if __name__ == "__main__":
    main()
