"""`Scene.set`: every kind of key (top level, table, inline table, array of
tables by index, array element, string and bool values), its effect seen in
the run; keys and values the scene refuses raise `SceneError` with the
loader's located message, the same as the command line's."""

import subprocess

import numpy as np
import pytest

import ffr
from conftest import SCENES

SPIN_UP = SCENES / "spin_up.toml"


@pytest.fixture(scope="module")
def base():
    return ffr.Scene.load(SPIN_UP).run()


def run_with(**changes):
    s = ffr.Scene.load(SPIN_UP)
    for k, v in changes.items():
        s.set(k.replace("__", "."), v)
    return s, s.run()


def test_top_level_key(base):
    s, r = run_with(t_end=5.0)
    assert s.get("t_end") == 5.0
    assert r.t[-1] == pytest.approx(5.0) and len(r.t) == 501 < len(base.t)
    # The same steps up to there.
    assert np.array_equal(r["tip_transverse"], base["tip_transverse"][:501])


def test_table_key(base):
    s, r = run_with(bodies__beam__elements=4)
    assert s.get("bodies.beam.elements") == 4
    assert len(r.t) == len(base.t)
    assert not np.array_equal(r["tip_transverse"], base["tip_transverse"])


def test_inline_table_key(base):
    s, r = run_with(bodies__beam__params__e=2 * 6.8952e10)
    assert s.get("bodies.beam.params.e") == 2 * 6.8952e10
    # A stiffer beam deflects less.
    assert np.abs(r["tip_transverse"]).max() < np.abs(base["tip_transverse"]).max()


def test_array_of_tables_by_index(base):
    s, r = run_with(joints__0__drive__omega=2.0)
    assert s.get("joints.0.drive.omega") == 2.0
    assert np.abs(r["tip_transverse"]).max() < np.abs(base["tip_transverse"]).max()


def test_array_element(base):
    # The beam's frame and the hub's ground point both moved 1 m along y
    # (an array element, and a string): the same motion, so the same tip
    # deflection up to round-off and the Newton tolerance.
    s = ffr.Scene.load(SPIN_UP)
    s.update({"bodies.beam.position.1": 1.0, "joints.0.a": "ground@[0.0, 1.0]"})
    assert s.get("bodies.beam.position") == [0.0, 1.0]
    assert s.get("joints.0.a") == "ground@[0.0, 1.0]"
    r = s.run()
    np.testing.assert_allclose(r["tip_transverse"], base["tip_transverse"], rtol=0, atol=1e-9)


def test_string_value(base):
    # The second output's component: now the same column as the first.
    s, r = run_with(outputs__1__component="x")
    assert s.get("outputs.1.component") == "x"
    assert np.array_equal(r["tip_transverse"], base["tip_axial"])


def test_bool_value():
    s = ffr.Scene.load(SPIN_UP)
    s.set("bodies.beam.stiffening", False)
    assert s.get("bodies.beam.stiffening") is False
    # Without stiffening the spin-up diverges (test_run.py).
    with pytest.raises(ffr.SimulationError):
        s.run()


def test_new_key_and_inline_table_value(base):
    # A key the file leaves at its default, and a whole inline table.
    s, r = run_with(integrator={"kind": "generalized-alpha", "rho_inf": 0.5})
    assert s.get("integrator") == {"kind": "generalized-alpha", "rho_inf": 0.5}
    assert not np.array_equal(r["tip_transverse"], base["tip_transverse"])
    assert r.t[-1] == pytest.approx(20.0)


def test_update_sets_keys_together():
    s = ffr.Scene.load(SPIN_UP)
    s.update({"bodies.beam.elements": 2, "t_end": 1.0})
    assert [k for k, _ in s.overrides] == ["bodies.beam.elements", "t_end"]
    assert len(s.run().t) == 101


@pytest.mark.parametrize(
    "key, message",
    [
        ("bodies.nope.e", "key `bodies.nope.e`: `bodies` has no `nope` (a table of: beam)"),
        ("joints.3.drive", "key `joints.3.drive`: `joints` has no `3` (an array of tables of: 0)"),
        ("bodies..e", "key `bodies..e`: an empty segment"),
        ("bodies.beam", "`beam` in `bodies` is a table; set the values inside it"),
    ],
)
def test_bad_keys_raise_scene_error(key, message):
    s = ffr.Scene.load(SPIN_UP)
    with pytest.raises(ffr.SceneError) as e:
        s.set(key, 1.0)
    assert str(e.value).startswith(f"{SPIN_UP}: key `")
    assert message in str(e.value)
    # The scene is as it was.
    assert s.overrides == [] and s.text == SPIN_UP.read_text()


def test_values_nested_too_deep_or_containing_themselves_raise():
    s = ffr.Scene.load(SPIN_UP)
    looped = []
    looped.append(looped)
    deep = 1.0
    for _ in range(40):
        deep = [deep]
    for value in (looped, deep):
        with pytest.raises(ValueError, match="nested more than 32"):
            s.set("bodies.beam.position", value)
    assert s.overrides == []


@pytest.mark.parametrize(
    "key, value, old, new",
    [
        ("bodies.beam.params.e", -1.0, "e = 6.8952e10", "e = -1.0"),
        ("bodies.beam.elements", "x", "elements = 8", 'elements = "x"'),
        ("joints.0.drive.omega", True, "omega = 4.0", "omega = true"),
        ("dt", 0.0, "dt = 0.01", "dt = 0.0"),
    ],
)
def test_bad_values_raise_the_located_message_of_the_command_line(ffr_bin, tmp_path, key, value, old, new):
    # The command line's message for the file with that value written in.
    text = SPIN_UP.read_text()
    assert text.count(old) == 1
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(old, new))
    r = subprocess.run([str(ffr_bin), "run", str(bad), "--csv", str(tmp_path / "x.csv")], capture_output=True, text=True)
    assert r.returncode != 0
    cli_message = r.stderr.strip().removeprefix("error: ")
    assert cli_message.startswith(f"{bad}:"), cli_message
    # Loaded from that file: the same message.
    with pytest.raises(ffr.SceneError) as e:
        ffr.Scene.load(bad)
    assert str(e.value) == cli_message
    # Set on the original: the same place and words, the key named.
    s = ffr.Scene.load(SPIN_UP)
    with pytest.raises(ffr.SceneError) as e:
        s.set(key, value)
    expected = cli_message.replace(str(bad), str(SPIN_UP), 1)
    assert str(e.value).startswith(expected + " (with " + key + " = "), (str(e.value), expected)
    assert s.overrides == []


def test_values_python_cannot_write_raise_type_error():
    s = ffr.Scene.load(SPIN_UP)
    with pytest.raises(TypeError):
        s.set("t_end", object())
    with pytest.raises(ffr.SceneError, match="not a finite number"):
        s.set("t_end", float("nan"))


def test_numpy_scalars_are_numbers():
    s = ffr.Scene.load(SPIN_UP)
    s.set("bodies.beam.elements", np.int64(4))
    s.set("t_end", np.float64(1.0))
    assert s.get("bodies.beam.elements") == 4 and s.get("t_end") == 1.0


def test_scene_file_errors_are_located(tmp_path):
    with pytest.raises(ffr.SceneError, match=r"^mine\.toml:1:\d+: "):
        ffr.Scene.from_str("t_end = = 1", file="mine.toml")
    with pytest.raises(ffr.SceneError):
        ffr.Scene.load(tmp_path / "missing.toml")


L_FRAME = SCENES / "l_frame.toml"


def test_a_force_profile_is_set_by_its_keys():
    # The L-frame's tip load ramps up by a table; a table that never
    # rises above 0 leaves the frame where it is, and a constant profile of
    # 1 loads it from the start.
    s = ffr.Scene.load(L_FRAME)
    s.set("t_end", 0.1)
    s.set("forces.0.profile.table", [[0, 0], [1, 0]])
    assert s.get("forces.0.profile.table") == [[0, 0], [1, 0]]
    r = s.run()
    assert np.all(r["tip_x"] == 1.0) and np.all(r["work"] == 0.0)
    s.set("forces.0.profile", {"kind": "constant", "value": 1.0})
    assert s.get("forces.0.profile") == {"kind": "constant", "value": 1.0}
    ramped = ffr.Scene.load(L_FRAME)
    ramped.set("t_end", 0.1)
    full, part = s.run()["tip_x"], ramped.run()["tip_x"]
    assert full[-1] - 1.0 > part[-1] - 1.0 > 0.0
    # Times that do not increase: the loader's located message (on the
    # file's table; `s` now has a `kind`, and a table beside it is refused
    # as giving the profile twice).
    with pytest.raises(ffr.SceneError, match=r"l_frame\.toml:\d+:\d+: row 2 of the profile `table`: the time 0\.0 is not after"):
        ramped.set("forces.0.profile.table", [[0.0, 0.0], [0.0, 1.0]])
    with pytest.raises(ffr.SceneError, match=r"`table` and `kind` both give the force's profile"):
        s.set("forces.0.profile.table", [[0.0, 0.0], [1.0, 1.0]])


def test_a_marker_is_set_as_a_string_or_a_table():
    s = ffr.Scene.load(L_FRAME)
    s.set("t_end", 0.05)
    assert s.get("joints.1.a") == {"at": "leg1@x=1.0", "axes": {"angle": 1.5707963267948966}}
    base = s.run()
    # The corner angle output at the plain section (a string): π/2 less
    # than leg 2's frame; with a turn of 0.5 (a table): π/2 − 0.5 less.
    for at, turn in (("leg1@x=1.0", 0.0), ({"at": "leg1@x=1.0", "axes": {"angle": 0.5}}, 0.5)):
        s.set("outputs.2.at", at)
        assert s.get("outputs.2.at") == at
        r = s.run()
        np.testing.assert_allclose(r["corner_angle"], base["leg2_angle"] - np.pi / 2 + turn, rtol=0, atol=1e-12)
    s.set("joints.1.a.axes.angle", 1.5707963267948966)
    with pytest.raises(ffr.SceneError, match="`axis` does not apply to a marker's `axes` in a planar scene"):
        s.set("joints.1.a.axes.axis", [0.0, 0.0, 1.0])


def test_a_key_set_again_replaces_its_value():
    # Sets of one key used to keep every one: each later set slower (20 000
    # sets took 24 s) and all of them in each error message. Now one, and a
    # set costs the same (1.5 ms, the scene's build, in each of 4 blocks of
    # 1000 sets measured).
    s = ffr.Scene.load(SPIN_UP)
    for i in range(3000):
        s.set("t_end", 1.0 + i % 7)
    assert s.overrides == [("t_end", 4.0)]
    s.set("joints.0.drive.omega", 2.0)
    s.set("joints.00.drive.omega", 3.0)  # the same entry, spelt otherwise
    assert [k for k, _ in s.overrides] == ["t_end", "joints.00.drive.omega"]
    with pytest.raises(ffr.SceneError) as e:
        s.set("dt", 0.0)
    assert str(e.value).endswith("(with t_end = 4, joints.00.drive.omega = 3, dt = 0)"), str(e.value)


def test_distinct_keys_are_bounded_with_the_bound_named():
    # A profile table of 300 rows: 300 distinct keys that all load.
    s = ffr.Scene.load(L_FRAME)
    s.set("forces.0.profile.table", [[float(i), 0.0] for i in range(300)])
    s.update({f"forces.0.profile.table.{i}.1": 1.0 for i in range(255)})
    assert len(s.overrides) == 256
    with pytest.raises(ffr.SceneError, match=r"more than 256 distinct keys .*MAX_OVERRIDES"):
        s.set("forces.0.profile.table.299.1", 1.0)
    assert len(s.overrides) == 256
    # Keys already set are replaced, and the table as a whole replaces them all.
    s.set("forces.0.profile.table.3.1", 0.5)
    s.set("forces.0.profile.table", [[0.0, 0.0], [1.0, 1.0]])
    assert s.overrides == [("forces.0.profile.table", [[0.0, 0.0], [1.0, 1.0]])]


def test_get_gives_tables_and_arrays_of_tables():
    # Compared with Python's own TOML reader of the file.
    tomllib = pytest.importorskip("tomllib")
    for path in (SPIN_UP, L_FRAME, SCENES / "two_link_arm.toml"):
        data = tomllib.loads(path.read_text())
        s = ffr.Scene.load(path)
        for key, value in data.items():
            assert s.get(key) == value, (path, key)
        assert s.get("joints") == data["joints"] and isinstance(s.get("joints.0"), dict)
        name = next(iter(data["bodies"]))
        assert s.get(f"bodies.{name}") == data["bodies"][name]
        assert s.get("no_such_key") is None


def no_hidden_characters(text):
    import unicodedata

    return not any(unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp") for c in text)


@pytest.mark.parametrize(
    "key",
    [
        "bodies.\x1b]0;owned\x07\x1b[2J.e",
        "bodies.beam.position.\u202e1",
        "joints.0.drive.omega.x\ny",
        "bodies.beam.\u2066x",
    ],
)
def test_user_text_in_exception_messages_is_escaped(key):
    s = ffr.Scene.load(SPIN_UP)
    with pytest.raises(ffr.SceneError) as e:
        s.set(key, 1.0)
    m = str(e.value)
    assert no_hidden_characters(m) and ("\\u{" in m or "\\n" in m), m
    # A key the loader refuses (the edit takes it): its message too.
    with pytest.raises(ffr.SceneError) as e:
        s.set("bodies.beam.x\x1b[2J\u202e", 1.0)
    assert no_hidden_characters(str(e.value)), str(e.value)
    # Names and values of other calls.
    evil = type("\x1b[31mEvil\u202e", (), {"__repr__": lambda self: "\x1b[2J\n" * 100})()
    for call in (
        lambda: s.set("t_end", evil),
        lambda: s.set("t_end", {evil: 1}),
        lambda: s.static(steps=evil),
        lambda: ffr.linearize(s, at=evil),
        lambda: ffr.campbell(s, evil),
        lambda: ffr.modes(reference="\x1b[2Jx"),
    ):
        with pytest.raises((TypeError, ValueError, ffr.FfrError)) as e:
            call()
        assert no_hidden_characters(str(e.value)) and len(str(e.value)) < 400, str(e.value)


def test_an_output_name_in_a_key_error_is_escaped():
    s = ffr.Scene.load(SPIN_UP)
    s.set("t_end", 0.05)
    r = s.run()
    with pytest.raises(KeyError) as e:
        r["tip\x1b[2J\u202e"]
    assert no_hidden_characters(e.value.args[0]) and "tip_axial" in e.value.args[0]


def test_numpy_arrays_are_values_and_0d_arrays_numbers():
    # numpy's internal "only integer scalar arrays can be converted to a
    # scalar index" / "iteration over a 0-d array" used to reach the user.
    s = ffr.Scene.load(SPIN_UP)
    s.set("t_end", np.array(2.0))
    s.set("bodies.beam.elements", np.array(4))
    s.update({"bodies.beam.position": np.array([0.0, 1.0]), "joints.0.a": "ground@[0.0, 1.0]"})
    assert s.get("t_end") == 2.0 and s.get("bodies.beam.elements") == 4
    assert s.get("bodies.beam.position") == [0.0, 1.0]
    with pytest.raises(TypeError, match=r"^a scene value is a bool, int, float, str, list or dict, not complex"):
        s.set("t_end", np.array(1j))


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda s: ffr.campbell(s, np.array(1.0)), r"^speeds = array\(1\.\): expected a sequence of rates \(rad/s\), not a 0-d numpy array"),
        (lambda s: ffr.campbell(s, 1.0), r"^speeds = 1\.0: expected a sequence of rates \(rad/s\), not float"),
        (lambda s: ffr.campbell(s, ["fast"]), r"^speeds = \['fast'\]: expected a sequence of rates \(rad/s\): item 0 is str"),
        (lambda s: ffr.linearize(s, inputs=np.array("joint1")), r"^inputs = .*not a 0-d numpy array"),
        (lambda s: ffr.linearize(s, outputs="tip_axial"), r"^outputs = 'tip_axial': expected a sequence of names \(str\), not str"),
        (lambda s: ffr.modes(boundary=np.array(1)), r"^boundary = array\(1\): expected a sequence of node numbers, not a 0-d numpy array"),
    ],
)
def test_sequence_arguments_refuse_0d_arrays_clearly(call, message):
    s = ffr.Scene.load(SPIN_UP)
    with pytest.raises(TypeError, match=message):
        call(s)


def test_sequence_arguments_take_1d_arrays():
    s = ffr.Scene.load(SPIN_UP)
    s.set("bodies.beam.elements", 2)
    a = ffr.campbell(s, np.array([0.0, 1.0]), count=2)
    b = ffr.campbell(s, [0.0, 1.0], count=2)
    assert a["modes"] == b["modes"]
