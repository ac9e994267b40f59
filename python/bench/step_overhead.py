"""The per-step overhead of stepping a scene from Python (`sim.step()` in a
Python loop) against the library's own step (`sim.advance(t)`, a loop over
the same `Simulation::step` in Rust), on the default spin-up
(scenes/spin_up.toml), side by side in one process.

    python python/bench/step_overhead.py [--scene S] [--steps 200] [--repeats 40]

Each repeat restores the same saved state (t = 1 s, the beam turning) and
takes `--steps` steps both ways, in alternating order; the figures are the
medians over the repeats of the time per step, and of the difference per
step (the overhead: the Python call, the GIL released and taken back per
step). Also `sim.step(inputs={...})` on a scene with an input
(two_link_arm_inputs.toml), against `advance` there. Not a test: the
figures go to the README and docs/in-the-loop.md.
"""

import argparse
import statistics
import time
from pathlib import Path

import ffr

ROOT = Path(__file__).resolve().parents[2]


def per_step(sim, saved, steps, repeats, inputs=None):
    py, rust = [], []
    for r in range(repeats):
        order = (0, 1) if r % 2 == 0 else (1, 0)
        for way in order:
            sim.restore(saved)
            target = saved.t + steps * sim.dt
            if way == 0:
                t0 = time.perf_counter()
                if inputs is None:
                    for _ in range(steps):
                        sim.step()
                else:
                    for _ in range(steps):
                        sim.step(inputs=inputs)
                py.append((time.perf_counter() - t0) / steps)
            else:
                t0 = time.perf_counter()
                sim.advance(target, inputs=inputs)
                rust.append((time.perf_counter() - t0) / steps)
    diff = [a - b for a, b in zip(py, rust)]
    return statistics.median(py), statistics.median(rust), statistics.median(diff)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "spin_up.toml"))
    ap.add_argument("--inputs-scene", default=str(ROOT / "scenes" / "two_link_arm_inputs.toml"))
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=40)
    a = ap.parse_args()

    sim = ffr.Scene.load(a.scene).simulation()
    sim.advance(1.0)
    saved = sim.state()
    py, rust, diff = per_step(sim, saved, a.steps, a.repeats)
    print(f"{Path(a.scene).name}: sim.step() {py * 1e6:.2f} µs/step, advance {rust * 1e6:.2f} µs/step, "
          f"overhead {diff * 1e6:.2f} µs/step (medians of {a.repeats} interleaved repeats of {a.steps} steps)")

    sim = ffr.Scene.load(a.inputs_scene).simulation()
    sim.advance(0.1)
    saved = sim.state()
    name = sim.input_names[0]
    py, rust, diff = per_step(sim, saved, a.steps, a.repeats, inputs={name: 0.01})
    print(f"{Path(a.inputs_scene).name}: sim.step(inputs={{{name!r}: 0.01}}) {py * 1e6:.2f} µs/step, advance {rust * 1e6:.2f} µs/step, "
          f"overhead {diff * 1e6:.2f} µs/step")


if __name__ == "__main__":
    main()
