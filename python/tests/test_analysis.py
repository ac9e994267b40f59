"""`ffr.invariants`, `ffr.modes`, `ffr.linearize`, `ffr.campbell`: the same
numbers as the command line's `--json`, bit for bit (serde_json writes f64s
that read back exactly)."""

import json

import numpy as np
import pytest

import ffr
from conftest import SCENES, cli


def assert_same(py, js, path="$"):
    """Python's result (numpy arrays, dicts, lists) equal to the JSON's."""
    if isinstance(js, dict):
        assert isinstance(py, dict) and set(py) == set(js), (path, set(py) ^ set(js))
        for k in js:
            assert_same(py[k], js[k], f"{path}.{k}")
    elif isinstance(py, np.ndarray):
        assert py.dtype == np.float64, path
        assert np.array_equal(py, np.array(js, dtype=float).reshape(py.shape)), path
        assert py.shape == np.array(js).shape, path
    elif isinstance(js, list):
        assert isinstance(py, list) and len(py) == len(js), path
        for i, (a, b) in enumerate(zip(py, js)):
            assert_same(a, b, f"{path}[{i}]")
    else:
        assert py == js and type(py) is type(js), (path, py, js)


def test_invariants_of_a_beam(ffr_bin):
    args = dict(shape="beam3", elements=3, reference="pinned", formalism="lumped", length=2.0, e=7e10)
    js = json.loads(cli(ffr_bin, "invariants", "--shape", "beam3", "--elements", 3, "--reference", "pinned",
                        "--formalism", "lumped", "--length", 2.0, "--e", 7e10, "--json"))
    assert_same(ffr.invariants(**args), js)


def test_invariants_defaults_are_the_command_lines(ffr_bin):
    assert_same(ffr.invariants(), json.loads(cli(ffr_bin, "invariants", "--json")))


def test_invariants_of_a_scene_body(ffr_bin):
    path = SCENES / "two_link_arm.toml"
    js = json.loads(cli(ffr_bin, "invariants", "--scene", path, "--body", "upper", "--json"))
    assert_same(ffr.invariants(scene=path, body="upper"), js)
    # An ffr.Scene with a key set: its body as set.
    s = ffr.Scene.load(path)
    s.set("bodies.upper.elements", 2)
    assert len(ffr.invariants(scene=s, body="upper")["dofs"]) < len(js["dofs"])


def test_modes_of_a_beam(ffr_bin):
    js = json.loads(cli(ffr_bin, "modes", "--shape", "beam2", "--elements", 8, "--count", 3, "--length", 8, "--json"))
    assert_same(ffr.modes(shape="beam2", elements=8, count=3, length=8.0), js)


def test_craig_bampton(ffr_bin):
    js = json.loads(cli(ffr_bin, "modes", "--elements", 6, "--count", 2, "--boundary", "6", "--json"))
    r = ffr.modes(elements=6, count=2, boundary=[6])
    assert_same(r, js)
    assert r["reduction"] == js["reduction"] and len(r["labels"]) > 2


def test_modes_of_a_scene_body(ffr_bin):
    path = SCENES / "spin_up.toml"
    js = json.loads(cli(ffr_bin, "modes", "--scene", path, "--body", "beam", "--count", 4, "--json"))
    assert_same(ffr.modes(scene=path, body="beam", count=4), js)
    assert_same(ffr.modes(scene=ffr.Scene.load(path), body="beam", count=4), js)


def test_modes_errors_are_the_command_lines(ffr_bin):
    with pytest.raises(ffr.FfrError, match="no flexible body `nope`; the scene's flexible bodies are beam"):
        ffr.modes(scene=SCENES / "spin_up.toml", body="nope")
    with pytest.raises(ffr.FfrError, match="`e` must be positive"):
        ffr.invariants(e=-1.0)
    with pytest.raises(ValueError, match="the body is the scene's"):
        ffr.modes(scene=SCENES / "spin_up.toml", body="beam", elements=3)
    with pytest.raises(ValueError, match="unknown reference condition `fixed`"):
        ffr.modes(reference="fixed")


def test_linearize(ffr_bin):
    path = SCENES / "two_link_arm.toml"
    js = json.loads(cli(ffr_bin, "linearize", path, "--at", "static", "--inputs", "joint1", "--outputs", "hand_y", "--json"))
    r = ffr.linearize(path, at="static", inputs=["joint1"], outputs=["hand_y"])
    ev = r.pop("eigenvalues")
    ev_js = js.pop("eigenvalues")
    assert_same(r, js)
    assert np.array_equal(ev, np.array([complex(a, b) for a, b in ev_js]))


def test_campbell(ffr_bin):
    path = SCENES / "spin_up.toml"
    js = json.loads(cli(ffr_bin, "campbell", path, "--speeds", "0,2,4", "--count", 3, "--json"))
    r = ffr.campbell(path, [0.0, 2.0, 4.0], count=3)
    assert r.pop("joint") == 1
    assert_same(r, js)


def test_campbell_warnings_are_runtime_warnings():
    # A beam turning without stiffening: the warning in the result is also a
    # RuntimeWarning (it was only in the result before).
    scene = ffr.Scene.load(SCENES / "spin_up.toml")
    scene.set("bodies.beam.stiffening", False)
    with pytest.warns(RuntimeWarning, match="stiffening") as caught:
        r = ffr.campbell(scene, [0.0, 1.0], count=2)
    assert r["warnings"]
    assert [str(w.message) for w in caught if w.category is RuntimeWarning] == r["warnings"]


def test_static(ffr_bin):
    path = SCENES / "pendulum.toml"
    js = json.loads(cli(ffr_bin, "static", path, "--json"))
    r = ffr.Scene.load(path).static()
    # The JSON's keys, and each flexible body's largest elastic rotation;
    # `warnings` is always a list in Python, in the JSON only when there
    # are any (none here).
    assert set(r) == {"outputs", "steps", "iterations", "warnings", "rotations"}
    assert [x["body"] for x in r.pop("rotations")] == ["bar"]
    assert r.pop("warnings") == js.pop("warnings", []) == []
    assert_same(r, js)
    js3 = json.loads(cli(ffr_bin, "static", path, "--steps", 3, "--json"))
    r3 = ffr.Scene.load(path).static(steps=3)
    assert r3["steps"] == 3
    r3.pop("rotations")
    assert r3.pop("warnings") == js3.pop("warnings", [])
    assert_same(r3, js3)


def test_static_errors():
    scene = ffr.Scene.load(SCENES / "free_floating.toml")
    with pytest.raises(ffr.SimulationError, match="no static equilibrium found.*mechanism"):
        scene.static()
    pendulum = ffr.Scene.load(SCENES / "pendulum.toml")
    for bad in (0, -1, 10001):
        with pytest.raises(ValueError, match="steps"):
            pendulum.static(steps=bad)
    for bad in (2.0, True, "3"):
        with pytest.raises(TypeError, match="steps"):
            pendulum.static(steps=bad)
