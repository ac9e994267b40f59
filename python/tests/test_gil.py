"""`Scene.run` releases the GIL: other Python threads go on during a run,
and two runs in two threads take less time than one after the other."""

import hashlib
import threading
import time

import numpy as np
import pytest

import ffr
from conftest import SCENES


def long_scene():
    """The spin-up with 32 elements and dt = 0.5 ms: a run of about half a
    second on the CI machine (40 000 steps)."""
    s = ffr.Scene.load(SCENES / "spin_up.toml")
    s.update({"bodies.beam.elements": 32, "dt": 5e-4})
    return s


def test_other_threads_run_during_a_run():
    s = long_scene()
    done = threading.Event()
    result = {}

    def work():
        result["r"] = s.run()
        done.set()

    th = threading.Thread(target=work)
    th.start()
    # Python bytecode in this thread while the run goes on: with the GIL
    # held for the whole run this loop could not advance until it ended.
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    th.join()
    assert result["r"].steps == 40000
    assert ticks >= 50, ticks


def timed_pair(f, g):
    """(serial, concurrent) wall times of f and g: one after the other, then
    in two threads."""
    t = time.perf_counter()
    f(), g()
    serial = time.perf_counter() - t
    ths = [threading.Thread(target=h) for h in (f, g)]
    t = time.perf_counter()
    for th in ths:
        th.start()
    for th in ths:
        th.join()
    return serial, time.perf_counter() - t


# The control's data, made once (making it holds the GIL).
DATA = b"\x5a" * (64 << 20)


def hashing():
    """A control that certainly runs without the GIL: hashlib releases it
    for data larger than 2047 bytes (its documentation). About as long as
    a run."""
    for _ in range(3):
        hashlib.sha256(DATA).digest()


def test_two_threads_run_two_scenes_faster_than_serially():
    a, b = long_scene(), long_scene()
    b.set("joints.0.drive.omega", 2.0)
    ra, rb = a.run(), b.run()
    out = {}

    def run(k, s):
        out[k] = s.run()

    # Best of three of each, interleaved, so that a burst of other load on
    # the machine does not decide the comparison.
    ser, con, ctrl_ser, ctrl_con = [], [], [], []
    for _ in range(3):
        ts, tc = timed_pair(hashing, hashing)
        ctrl_ser.append(ts)
        ctrl_con.append(tc)
        ts, tc = timed_pair(lambda: run("a", a), lambda: run("b", b))
        ser.append(ts)
        con.append(tc)
        # The same results whichever way they ran.
        assert np.array_equal(out["a"]["tip_transverse"], ra["tip_transverse"])
        assert np.array_equal(out["b"]["tip_transverse"], rb["tip_transverse"])
    control = min(ctrl_con) / min(ctrl_ser)
    if control > 0.8:
        # Other work holds the cores: not even GIL-free hashing runs in
        # parallel now, so no ratio can show it (the test above still
        # checks the release).
        pytest.skip(f"no free second core now: two hashing threads take {control:.2f} of serial")
    # On 2 free cores (CI's machine) two runs without the GIL take about
    # half the serial time (0.50 measured, as the control); with the GIL
    # held they would take the serial time or more (ratio >= 1). 0.8 leaves
    # room for the second core being partly busy and for the threads'
    # start-up, and still fails if the runs were serialized.
    assert min(con) < 0.8 * min(ser), (con, ser, control)
