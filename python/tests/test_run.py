"""Scenes run from Python: the same numbers as `ffr run`, bit for bit."""

import csv
import subprocess
import re

import numpy as np
import pytest

import ffr
from conftest import ROOT, SCENES, cli


def digits(s):
    """The significant digits of a number's text (`-1.250e-3` → `125`)."""
    mantissa = re.split("[eE]", s)[0].lstrip("-+").replace(".", "")
    return mantissa.lstrip("0").rstrip("0") or "0"


@pytest.mark.parametrize("name", ["spin_up.toml", "two_link_arm.toml"])
def test_run_is_bit_identical_to_the_command_line(ffr_bin, tmp_path, name):
    path = SCENES / name
    csv_path = tmp_path / "out.csv"
    cli(ffr_bin, "run", path, "--csv", csv_path, "--svg", tmp_path / "out.svg")
    with open(csv_path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]

    r = ffr.Scene.load(path).run()
    assert header == ["t"] + r.keys()
    assert len(body) == len(r.t) > 1
    columns = [r.t] + [r[n] for n in r.keys()]
    for j, col in enumerate(columns):
        assert col.dtype == np.float64
        text = [row[j] for row in body]
        parsed = np.array([float(s) for s in text])
        # Float equality after parsing: the same f64s, not merely close.
        assert np.array_equal(parsed, col), (header[j], np.abs(parsed - col).max())
        # The command line writes the shortest text that reads back to the
        # same f64: the same significant digits as Python's repr.
        for s, x in zip(text, col):
            assert digits(s) == digits(repr(float(x))), (header[j], s, repr(float(x)))
    # The statistics the command line prints.
    out = cli(ffr_bin, "run", path, "--csv", csv_path, "--svg", tmp_path / "out.svg")
    m = re.search(r"steps: (\d+) of dt = .* s, (\d+) Newton iterations, (\d+) iteration matrices", out)
    assert m, out
    assert (r.steps, r.newton_iterations, r.jacobians) == tuple(map(int, m.groups()))
    assert r.wall > 0.0


def test_result_is_a_mapping_of_outputs():
    r = ffr.Scene.load(SCENES / "spin_up.toml").run()
    assert list(r) == ["tip_axial", "tip_transverse"] == r.keys()
    assert len(r) == 2 and "tip_axial" in r and "t" not in r
    assert r.t[0] == 0.0 and r.t[-1] == pytest.approx(20.0)
    assert len(r["tip_transverse"]) == len(r.t) == r.steps + 1
    with pytest.raises(KeyError, match="tip_axial, tip_transverse"):
        r["nope"]


def test_from_str_resolves_relative_files_against_base():
    text = (SCENES / "spin_up.toml").read_text()
    a = ffr.Scene.from_str(text, file="mine.toml", base=SCENES).run()
    b = ffr.Scene.load(SCENES / "spin_up.toml").run()
    assert np.array_equal(a["tip_transverse"], b["tip_transverse"])


def test_a_run_that_fails_raises_simulation_error():
    s = ffr.Scene.load(SCENES / "spin_up.toml")
    # Without geometric stiffening the spin-up beam's deflection grows
    # without bound: the runtime stops the run.
    s.set("bodies.beam.stiffening", False)
    with pytest.raises(ffr.SimulationError, match=r"^the run stopped at t = \d+\.\d{6} s: the run diverged"):
        s.run()
    assert issubclass(ffr.SimulationError, ffr.FfrError)
    assert issubclass(ffr.SceneError, ffr.FfrError)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # the cut run's elastic rotation
def test_simulation_error_carries_the_run_up_to_the_failure():
    s = ffr.Scene.load(SCENES / "spin_up.toml")
    s.set("bodies.beam.stiffening", False)
    with pytest.raises(ffr.SimulationError) as e:
        s.run()
    run = e.value.run
    assert isinstance(run, ffr.RunResult)
    # The samples up to the stop, whose time the message gives.
    stopped = float(str(e.value).split("t = ")[1].split(" s")[0])
    assert run.t[-1] == pytest.approx(stopped, abs=5e-7) and run.t[-1] < 20.0
    assert 0 < run.steps == len(run.t) - 1
    # The same samples as the run of the scene cut there (the same steps;
    # its last one may differ in the last bits, its step being t_end − t
    # rounded).
    s.set("t_end", float(run.t[-2]))
    cut = s.run()
    assert len(cut.t) == len(run.t) - 1
    for name in run:
        assert np.isfinite(run[name]).all()
        assert np.array_equal(run[name][:-2], cut[name][:-1]), name
        np.testing.assert_allclose(cut[name][-1], run[name][-2], rtol=1e-9, atol=1e-15)
    # Other failures carry none.
    assert ffr.SimulationError("x").run is None


def test_a_run_whose_initial_state_is_not_valid_is_refused_as_on_the_command_line(ffr_bin, tmp_path):
    # A bar thrown at 1e155 m/s: every coordinate finite, its kinetic
    # energy ½ m v² beyond the range of f64. The initial state passes the
    # validity check every later state passes, so nothing is integrated
    # (it used to run with an infinite energy until its outputs were
    # refused as not finite).
    text = (SCENES / "free_floating.toml").read_text()
    text = text.replace("velocity = [0.5, -1.0]", "velocity = [1e155, 0.0]").replace("t_end = 2.0", "t_end = 0.003")
    path = tmp_path / "thrown.toml"
    path.write_text(text)
    r = subprocess.run([str(ffr_bin), "run", str(path), "--csv", str(tmp_path / "x.csv")], capture_output=True, text=True)
    why = "the initial state is not valid: the kinetic energy is inf, not finite"
    assert r.returncode == 1 and why in r.stderr, r.stderr
    assert not (tmp_path / "x.csv").exists()
    with pytest.raises(ffr.SimulationError, match=re.escape(why)) as e:
        ffr.Scene.load(path).run()
    assert e.value.run is None
