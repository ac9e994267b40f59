"""Ctrl-C during the long calls: `Scene.run()`, `Scene.static()`,
`Simulation.advance`,
`ffr.linearize` (run to its time) and `ffr.campbell` raise
`KeyboardInterrupt` within a fraction of a second of a real SIGINT, not
after the call's end nor as a Rust panic, and the scene stays usable.

Each case runs in its own Python process (a SIGINT that arrived outside
the call under test would otherwise stop pytest itself): a timer thread
sends SIGINT to the process with `os.kill` while the main thread is in the
call; the process prints what happened as JSON."""

import json
import subprocess
import sys
import textwrap

import pytest

from conftest import SCENES

# The child: set up `call` (a function of no arguments that would take
# far longer than the test allows), time it uninterrupted on a cheap
# variant when asked, then interrupt it after DELAY seconds.
CHILD = textwrap.dedent(
    r"""
    import json, os, signal, sys, threading, time
    import ffr
    SCENES = sys.argv[1]
    DELAY = 0.3
    out = {}
    {setup}
    first = "numpy" not in sys.modules
    threading.Timer(DELAY, os.kill, (os.getpid(), signal.SIGINT)).start()
    t0 = time.perf_counter()
    try:
        call()
        out["raised"] = None
    except BaseException as e:
        out["raised"] = type(e).__name__
        out["message"] = str(e)[:300]
    out["after_signal"] = time.perf_counter() - t0 - DELAY
    out["numpy_loaded_by_import"] = not first
    # The scene is usable afterwards: a short run of it.
    after()
    out["after_ok"] = True
    print(json.dumps(out))
    """
)


def child(setup):
    code = CHILD.replace("{setup}", textwrap.dedent(setup).strip())
    r = subprocess.run(
        [sys.executable, "-c", code, str(SCENES)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


# Long variants of the shipped scenes and a short check afterwards.
# Uninterrupted they would take about 50 s (run, linearize: 4 million
# steps), 15 s (campbell: 500 speeds of 29 ms) and 30 s (static: 10 000
# increments of 2.9 ms), estimated from shorter calls on a loaded 2-core
# machine.
RUN = """
s = ffr.Scene.load(SCENES + "/spin_up.toml")
s.update({"bodies.beam.elements": 32, "dt": 5e-4, "t_end": 2000.0})
call = s.run
def after():
    s.set("t_end", 0.05)
    assert s.run().steps == 100
"""

LINEARIZE = """
s = ffr.Scene.load(SCENES + "/spin_up.toml")
s.update({"bodies.beam.elements": 32, "dt": 5e-4})
call = lambda: ffr.linearize(s, at=2000.0)
def after():
    assert ffr.linearize(s, at=0.01)["A"].shape[0] > 0
"""

CAMPBELL = """
import numpy as np
s = ffr.Scene.load(SCENES + "/spin_up.toml")
s.set("bodies.beam.elements", 32)
call = lambda: ffr.campbell(s, list(np.linspace(0.0, 4.0, 500)), count=2)
def after():
    assert len(ffr.campbell(s, [1.0], count=2)["modes"]) == 1
"""

STATIC = """
s = ffr.Scene.load(SCENES + "/boom_payload.toml")
s.set("bodies.boom.elements", 128)
call = lambda: s.static(steps=10000)
def after():
    s.set("bodies.boom.elements", 8)
    assert s.static()["steps"] >= 1
"""

ADVANCE = """
s = ffr.Scene.load(SCENES + "/spin_up.toml")
s.update({"bodies.beam.elements": 32, "dt": 5e-4})
sim = s.simulation()
call = lambda: sim.advance(2000.0)
def after():
    # Stopped at a whole step, usable: one more step, then back to t = 0.
    assert 0 < sim.steps < 4000000 and sim.failed is None
    t = sim.t
    sim.step()
    assert sim.t > t
"""


@pytest.mark.parametrize(
    "setup", [RUN, LINEARIZE, CAMPBELL, STATIC, ADVANCE], ids=["run", "linearize", "campbell", "static", "advance"]
)
def test_ctrl_c_stops_a_long_call_within_a_fraction_of_a_second(setup):
    out = child(setup)
    assert out["raised"] == "KeyboardInterrupt", out
    # Polled every 50 ms: the call ends well within a second of the signal
    # (without polling it would end after its whole run, minutes).
    assert out["after_signal"] < 1.0, out
    assert out["after_ok"], out


def test_ctrl_c_in_the_first_run_of_a_process_is_a_keyboard_interrupt():
    # The first call that makes numpy arrays used to load numpy's C API
    # after the run, with the KeyboardInterrupt pending: the import failed
    # and the numpy crate panicked (`PanicException`). Importing ffr loads
    # it now, so nothing is loaded after a call.
    out = child(RUN)
    assert out["raised"] == "KeyboardInterrupt", out
    assert out["numpy_loaded_by_import"], out
