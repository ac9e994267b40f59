"""Issue 35 from Python: `segments` set and read by dotted key, the run's
and the static solution's warnings (a body turned past what one floating
frame describes) and each body's largest elastic rotation, the same as the
command line's."""

import json
import re
import warnings

import pytest

import ffr
from conftest import SCENES, cli


def gravity_scene(t_end=2.0):
    """The report's spatial spin-up under gravity (16 beam3 elements), its
    first `t_end` s: the beam falls from horizontal and swings past its sag,
    its sections turning about 0.6 rad relative to one frame."""
    s = ffr.Scene.load(SCENES / "spin_up_gravity.toml")
    s.set("t_end", t_end)
    return s


def stderr_warnings(ffr_bin, *args):
    """The `warning: …` lines `ffr` prints on stderr."""
    import subprocess

    r = subprocess.run([str(ffr_bin), *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert r.returncode == 0, r.stderr
    return [line[len("warning: "):] for line in r.stderr.splitlines() if line.startswith("warning: ")], r.stdout


def test_segments_are_set_and_read_by_key():
    s = gravity_scene()
    assert s.get("bodies.beam.segments") is None
    s.set("bodies.beam.segments", 4)
    assert s.get("bodies.beam.segments") == 4
    assert "segments = 4" in s.text
    # Refused values leave the scene as it was, with the loader's located message.
    for bad, message in [
        (3, "`segments` = 3 does not divide the body's 16 elements.*try 2 or 4"),
        (0, "`segments` must be 1 to 256, found 0"),
        (32, "`segments` = 32 is more than the body's 16 elements"),
    ]:
        with pytest.raises(ffr.SceneError, match=message):
            s.set("bodies.beam.segments", bad)
        assert s.get("bodies.beam.segments") == 4
    with pytest.raises(ffr.SceneError, match="segments"):
        s.set("bodies.beam.segments", 2.5)
    assert s.get("bodies.beam.segments") == 4


def test_run_warns_once_per_body_like_the_command_line(ffr_bin, tmp_path):
    s = gravity_scene()
    with pytest.warns(RuntimeWarning) as caught:
        r = s.run()
    assert len(r.warnings) == 1
    assert re.match(r"body `beam`: elastic rotation 0\.\d\d rad at t = .*; try segments = \d+", r.warnings[0])
    # Issued once each, as RuntimeWarnings, with the result's text.
    assert [str(w.message) for w in caught if w.category is RuntimeWarning] == r.warnings
    # The command line's: the same text on stderr, the same rotation in its summary.
    path = tmp_path / "gravity.toml"
    path.write_text(s.text)
    printed, out = stderr_warnings(ffr_bin, "run", path, "--csv", tmp_path / "out.csv", "--svg", tmp_path / "out.svg")
    assert printed == r.warnings
    [rot] = r.rotations
    assert rot["body"] == "beam" and (rot["segment"], rot["segments"]) == (1, 1)
    assert rot["angle"] > 0.27
    assert 0.0 < rot["t"] <= 2.0 and 0.0 <= rot["x"] <= 8.0
    m = re.search(r"elastic rotation of `beam`: at most (\S+) rad \(t = (\S+) s, x = (\S+) m\)", out)
    assert m, out
    assert m.group(1) == f"{rot['angle']:.3f}"
    assert m.group(2) == f"{rot['t']:.4f}"
    assert m.group(3) == f"{rot['x']:.4f}"


def test_segments_keep_each_frame_accurate():
    s = gravity_scene()
    # As the warning advises (4 segments still turn 0.32 rad in the root one).
    s.set("bodies.beam.segments", 8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = s.run()
    assert r.warnings == []
    [rot] = r.rotations
    assert rot["body"] == "beam" and rot["segments"] == 8 and 1 <= rot["segment"] <= 8
    assert 0.0 < rot["angle"] < 0.27


def test_static_exposes_its_warnings(ffr_bin, tmp_path):
    s = gravity_scene()
    # A softer beam sags past 0.27 rad at rest.
    s.set("bodies.beam.params.e", 3e10)
    path = tmp_path / "sag.toml"
    path.write_text(s.text)
    printed, out = stderr_warnings(ffr_bin, "static", path, "--json")
    js = json.loads(out)
    with pytest.warns(RuntimeWarning) as caught:
        r = s.static()
    assert set(r) == {"outputs", "steps", "iterations", "warnings", "rotations"}
    [rot] = r.pop("rotations")
    assert r == js
    assert len(r["warnings"]) == 1 and printed == r["warnings"]
    assert [str(w.message) for w in caught if w.category is RuntimeWarning] == r["warnings"]
    assert rot["body"] == "beam" and rot["angle"] > 0.27 and rot["t"] == 0.0
    # Split as the warnings advise until none is left (the advice assumes a
    # segment's rotation shrinks as its length to the power 0.58, as the
    # root segment of the spin-up under gravity does).
    tried = [1]
    while r["warnings"]:
        m = re.search(r"try segments = (\d+)", r["warnings"][0])
        tried.append(int(m.group(1)))
        assert tried[-1] > tried[-2] and len(tried) <= 4, tried
        s.set("bodies.beam.segments", tried[-1])
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            r = s.static()
        assert [str(w.message) for w in caught] == r["warnings"]
    assert r["rotations"][0]["angle"] < 0.27 and r["rotations"][0]["segments"] == tried[-1]
