"""`ffr run --vtk` and `ffr modes --vtk` read back by VTK's own XML readers
(the `vtk` package): the axis points and FE nodes are the scene's position
outputs at those points, the `.pvd` times are the run's times, `--every` bounds the
files, the files are deterministic, and nothing that is not a file ffr wrote
is replaced (see docs/vtk.md)."""

import csv
import json
import math
import os
import subprocess
import tomllib

import numpy as np
import pytest

from conftest import ROOT, SCENES

import vtk  # noqa: E402  (the `vtk` package of requirements-test.txt)
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402


def run_ffr(ffr_bin, *args):
    return subprocess.run(
        [str(ffr_bin), *map(str, args)],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    return {n: data[:, i] for i, n in enumerate(names)}


def read_pvd(path):
    """(time, file) of every data set of a ParaView collection, parsed by
    VTK's XML parser (VTK has no reader of ParaView's `.pvd` itself; ParaView
    reads it with its PVD reader)."""
    p = vtk.vtkXMLDataParser()
    p.SetFileName(str(path))
    assert p.Parse() == 1, path
    root = p.GetRootElement()
    assert root.GetName() == "VTKFile" and root.GetAttribute("type") == "Collection"
    coll = root.GetNestedElement(0)
    assert coll.GetName() == "Collection"
    sets = [coll.GetNestedElement(i) for i in range(coll.GetNumberOfNestedElements())]
    return [float(d.GetAttribute("timestep")) for d in sets], [d.GetAttribute("file") for d in sets]


def read_vtp(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(str(path))
    r.Update()
    assert r.GetErrorCode() == 0, path
    poly = r.GetOutput()
    pd = poly.GetPointData()
    arrays = {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}
    return vtk_to_numpy(poly.GetPoints().GetData()), arrays, poly


# The slider-crank (a flexible rod, a rigid crank and slider, joints) for
# 0.01 s, with position outputs at every rod node, at points between nodes,
# and at the slider's frame origin.
ROD_ELEMENTS = 8
ROD_LENGTH = 0.3


def slider_crank(tmp_path):
    text = (SCENES / "slider_crank.toml").read_text()
    spec = tomllib.loads(text)
    assert spec["bodies"]["rod"]["elements"] == ROD_ELEMENTS
    assert spec["bodies"]["rod"]["params"]["length"] == ROD_LENGTH
    text = text.replace("t_end = 0.1\n", "t_end = 0.01\n")
    xs = [ROD_LENGTH * i / ROD_ELEMENTS for i in range(ROD_ELEMENTS + 1)]
    # points between nodes: the writer puts 3 at quarters of each element
    between = [xs[2] + (xs[3] - xs[2]) * k / 4 for k in (1, 2, 3)]
    for i, x in enumerate(xs + between):
        for c in "xy":
            text += f'\n[[outputs]]\nname = "p{i}_{c}"\nkind = "position"\nat = "rod@x={x!r}"\ncomponent = "{c}"\n'
    path = tmp_path / "crank.toml"
    path.write_text(text)
    return path, xs, between


def test_series_matches_position_outputs_and_times(ffr_bin, tmp_path):
    scene, xs, between = slider_crank(tmp_path)
    every = 7
    out = tmp_path / "vtk"
    r = run_ffr(ffr_bin, "run", scene, "--csv", tmp_path / "o.csv", "--vtk", out, "--every", every)
    assert r.returncode == 0, r.stderr
    cols = read_csv(tmp_path / "o.csv")
    t = cols["t"]
    times, files = read_pvd(out / "crank.pvd")
    rows = list(range(0, len(t), every))
    # --every bounds the files: one per `every` samples, the first included.
    assert len(files) == math.ceil(len(t) / every) == len(rows)
    assert sorted(os.listdir(out)) == sorted(files + ["crank.pvd"])
    # The .pvd times are the run's times (written in the shortest form that
    # reads back to the same double).
    assert times == [t[i] for i in rows]
    order = ["crank", "rod", "slider"]
    for f, i in zip(files, rows):
        pts, a, poly = read_vtp(out / f)
        rod = (a["body"] == order.index("rod"))
        # the rod's axis: nodes (kind 1) and points between (kind 0) in x order
        assert np.all(np.diff(a["x"][rod]) > 0)
        assert poly.GetNumberOfLines() == 1
        nodes = rod & (a["kind"] == 1)
        assert np.array_equal(a["x"][nodes], np.array(xs))
        got = pts[nodes][:, :2]
        want = np.array([[cols[f"p{j}_x"][i], cols[f"p{j}_y"][i]] for j in range(len(xs))])
        assert np.max(np.abs(got - want)) <= 1e-15 * (1 + np.max(np.abs(want)))
        mid = rod & (a["kind"] == 0) & (a["x"] > xs[2]) & (a["x"] < xs[3])
        got = pts[mid][:, :2]
        want = np.array(
            [[cols[f"p{len(xs) + k}_x"][i], cols[f"p{len(xs) + k}_y"][i]] for k in range(len(between))]
        )
        assert np.max(np.abs(got - want)) <= 1e-15 * (1 + np.max(np.abs(want)))
        # the rigid slider: its frame's origin (kind 2) is the slider_x output
        slider = (a["body"] == order.index("slider")) & (a["kind"] == 2)
        assert slider.sum() == 1
        assert abs(pts[slider][0, 0] - cols["slider_x"][i]) <= 1e-15 * (1 + abs(cols["slider_x"][i]))
        # joints (kind 3), at their markers `a` in file order: crank–rod,
        # rod–slider (at rod@x=0.3, the rod's last node), ground–slider
        # prismatic; the crank's revolute to the ground is folded into its
        # prescribed frame, not a joint of the system
        joints = pts[a["kind"] == 3]
        assert len(joints) == 3
        assert np.max(np.abs(joints[1] - pts[nodes][-1])) <= 1e-15
        # section axes are unit to first order in the small rotation
        for k in "xyz":
            assert np.all(np.abs(np.linalg.norm(a[f"axis_{k}"], axis=1) - 1) < 1e-3)


def test_series_is_deterministic(ffr_bin, tmp_path):
    scene, _, _ = slider_crank(tmp_path)
    dirs = [tmp_path / "a", tmp_path / "b"]
    for i, d in enumerate(dirs):
        r = run_ffr(ffr_bin, "run", scene, "--csv", tmp_path / f"o{i}.csv", "--vtk", d, "--every", 40)
        assert r.returncode == 0, r.stderr
    names = sorted(os.listdir(dirs[0]))
    assert names == sorted(os.listdir(dirs[1])) and len(names) > 2
    for n in names:
        assert (dirs[0] / n).read_bytes() == (dirs[1] / n).read_bytes(), n
    # and rewriting the same directory replaces ffr's own files
    r = run_ffr(ffr_bin, "run", scene, "--csv", tmp_path / "o0.csv", "--vtk", dirs[0], "--every", 40)
    assert r.returncode == 0, r.stderr


def test_refuses_to_replace_what_is_not_its_own(ffr_bin, tmp_path):
    scene = SCENES / "spin_up.toml"
    out = tmp_path / "vtk"
    out.mkdir()
    csv_out = tmp_path / "o.csv"
    # a directory where a step file goes
    (out / "spin_up_0100.vtp").mkdir()
    r = run_ffr(ffr_bin, "run", scene, "--csv", csv_out, "--vtk", out, "--every", 100)
    assert r.returncode != 0
    assert "spin_up_0100.vtp: is a directory, not a regular file: not replaced" in r.stderr
    assert sorted(os.listdir(out)) == ["spin_up_0100.vtp"]
    (out / "spin_up_0100.vtp").rmdir()
    # a symbolic link
    (tmp_path / "target").write_text("keep")
    os.symlink(tmp_path / "target", out / "spin_up.pvd")
    r = run_ffr(ffr_bin, "run", scene, "--csv", csv_out, "--vtk", out, "--every", 100)
    assert r.returncode != 0
    assert "spin_up.pvd: is a symbolic link, not a regular file" in r.stderr
    assert (tmp_path / "target").read_text() == "keep"
    os.unlink(out / "spin_up.pvd")
    # a regular file ffr did not write
    (out / "spin_up_0000.vtp").write_text("<VTKFile/>")
    r = run_ffr(ffr_bin, "run", scene, "--csv", csv_out, "--vtk", out, "--every", 100)
    assert r.returncode != 0
    assert "spin_up_0000.vtp: exists and was not written by ffr: not replaced" in r.stderr
    assert (out / "spin_up_0000.vtp").read_text() == "<VTKFile/>"
    assert sorted(os.listdir(out)) == ["spin_up_0000.vtp"]
    # DIR itself a file
    r = run_ffr(ffr_bin, "run", scene, "--csv", csv_out, "--vtk", tmp_path / "target")
    assert r.returncode != 0
    assert "exists and is not a directory" in r.stderr


def test_every_has_a_hard_bound(ffr_bin, tmp_path):
    # 20001 samples: more than the 10000 files a series may have.
    text = (SCENES / "spin_up.toml").read_text().replace("dt = 0.01\n", "dt = 0.001\n")
    scene = tmp_path / "fine.toml"
    scene.write_text(text)
    r = run_ffr(ffr_bin, "run", scene, "--csv", tmp_path / "o.csv", "--vtk", tmp_path / "v")
    assert r.returncode != 0
    assert "more than the limit of 10000" in r.stderr and "--every 3" in r.stderr
    assert not (tmp_path / "v").exists() or os.listdir(tmp_path / "v") == []


FRAMES = 24  # frames per period (ffr::scene::vtk::FRAMES_PER_PERIOD)


@pytest.mark.parametrize(
    "args, length",
    [
        (["--shape", "beam2", "--elements", "4", "--count", "3"], 1.0),
        (["--shape", "beam3", "--elements", "3", "--reference", "pinned", "--count", "2", "--length", "2.5"], 2.5),
    ],
)
def test_mode_animations_are_phi_scaled_as_documented(ffr_bin, tmp_path, args, length):
    out = tmp_path / "modes"
    r = run_ffr(ffr_bin, "modes", *args, "--json", "--vtk", out)
    assert r.returncode == 0, r.stderr
    m = json.loads(r.stdout)
    phi = np.array(m["phi"])
    dofs = m["dofs"]
    elements = int(args[args.index("--elements") + 1])
    shape = args[args.index("--shape") + 1]
    for j, omega in enumerate(m["omega"]):
        # node translations of mode j from phi by the coordinates' labels
        # (a coordinate the reference removes is zero)
        t = np.zeros((elements + 1, 3))
        for i in range(elements + 1):
            for c, axis in enumerate("xyz"):
                if f"u{axis}_{i}" in dofs:
                    t[i, c] = phi[dofs.index(f"u{axis}_{i}"), j]
        # documented amplitude: largest node displacement = 10 % of the length
        scale = 0.1 * length / np.max(np.linalg.norm(t, axis=1))
        times, files = read_pvd(out / f"{shape}_mode{j + 1:02}.pvd")
        assert len(files) == FRAMES
        period = 2 * math.pi / omega
        assert np.allclose(times, [period * k / FRAMES for k in range(FRAMES)], rtol=1e-15, atol=0)
        for k, f in enumerate(files):
            pts, a, poly = read_vtp(out / f)
            nodes = a["kind"] == 1
            assert np.allclose(a["x"][nodes], np.linspace(0, length, elements + 1), rtol=1e-15, atol=1e-15)
            want = scale * math.cos(2 * math.pi * k / FRAMES) * t
            assert np.max(np.abs(a["displacement"][nodes] - want)) <= 1e-14 * length
            # the points are the undeformed axis moved by the displacement
            undeformed = np.column_stack([a["x"], np.zeros(len(a["x"])), np.zeros(len(a["x"]))])
            assert np.max(np.abs(pts - undeformed - a["displacement"])) <= 1e-14 * length
        # frame 0 is the crest: the largest node displacement is 10 % of L
        _, a, _ = read_vtp(out / files[0])
        assert abs(np.max(np.linalg.norm(a["displacement"][a["kind"] == 1], axis=1)) - 0.1 * length) <= 1e-14


def test_campbell_animations_at_rest_are_the_modes(ffr_bin, tmp_path):
    """At Ω = 0 the spin-up beam's Campbell modes are its clamped modes: in
    every frame the nodes' displacement is a multiple of the node
    translations of `phi` (ffr modes --json), at the period 2π/ω of that
    mode; the largest over the period is 10 % of the 8 m length up to the
    24-frame sampling of the phase (cos(π/24))."""
    m = json.loads(
        run_ffr(ffr_bin, "modes", "--scene", SCENES / "spin_up.toml", "--body", "beam", "--count", "2", "--json").stdout
    )
    out = tmp_path / "campbell"
    r = run_ffr(ffr_bin, "campbell", SCENES / "spin_up.toml", "--speeds", "0,4", "--count", "2", "--vtk", out)
    assert r.returncode == 0, r.stderr
    dofs, phi, length = m["dofs"], np.array(m["phi"]), 8.0
    for j in range(2):
        t = np.zeros((9, 3))
        for i in range(9):
            for c, axis in enumerate("xy"):
                if f"u{axis}_{i}" in dofs:
                    t[i, c] = phi[dofs.index(f"u{axis}_{i}"), j]
        t = t.ravel() / np.linalg.norm(t)
        times, files = read_pvd(out / f"spin_up_speed01_mode{j + 1:02}.pvd")
        assert len(files) == FRAMES
        assert np.allclose(times, [2 * math.pi / m["omega"][j] * k / FRAMES for k in range(FRAMES)], rtol=1e-6)
        peak = 0.0
        for f in files:
            _, a, _ = read_vtp(out / f)
            d = a["displacement"][a["kind"] == 1].ravel()
            # d is c t for some c: what is left after removing t is round-off
            # of the inverse iteration's eigenvector
            assert np.linalg.norm(d - (d @ t) * t) <= 1e-6 * length
            peak = max(peak, np.max(np.linalg.norm(a["displacement"][a["kind"] == 1], axis=1)))
        assert 0.1 * length * math.cos(math.pi / FRAMES) * (1 - 1e-9) <= peak <= 0.1 * length * (1 + 1e-9)
    assert (out / "spin_up_speed02_mode02.pvd").exists()


# The FE pendulum (tests/data/fe/pendulum.toml: the solid cantilever, 99
# nodes, clamped to the nine nodes of its face x = 0, pinned there and
# swinging under gravity) for 0.03 s, its stiffness scaled down 100 times so
# the elastic displacement (up to 7.6e-4 m here) is far above round-off of
# the 1 m positions, with position outputs at some nodes and the deflection of
# the tip node.
FE = ROOT / "tests" / "data" / "fe"
FE_NODES = [0, 33, 40, 64, 98]  # an interface node, inner nodes, the tip (64), the last
FE_TIP = 64


def fe_nodes():
    """The cantilever's node coordinates (body frame), read from its node
    file."""
    with open(FE / "cantilever_nodes.csv", newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["x", "y", "z"]
    return np.array([[float(x) for x in r] for r in rows[1:]])


def fe_pendulum(tmp_path):
    text = (FE / "pendulum.toml").read_text()
    spec = tomllib.loads(text)
    assert spec["t_end"] == 1.0 and spec["dt"] == 1e-3
    text = text.replace("t_end = 1.0\n", "t_end = 0.03\n")
    for key in ("nodes", "mass", "stiffness"):
        name = spec["bodies"]["bar"]["fe"][key]
        text = text.replace(f'{key} = "{name}"', f"{key} = {json.dumps(str(FE / name))}")
    text = text.replace("cantilever_stiffness.mtx\" }", "cantilever_stiffness.mtx\", stiffness_scale = 0.01 }")
    assert "stiffness_scale = 0.01" in text
    for n in FE_NODES:
        for c in "xyz":
            text += f'\n[[outputs]]\nname = "n{n}_{c}"\nkind = "position"\nat = "bar@node={n}"\ncomponent = "{c}"\n'
    for c in "xyz":
        text += f'\n[[outputs]]\nname = "d{FE_TIP}_{c}"\nkind = "deflection"\nat = "bar@node={FE_TIP}"\ncomponent = "{c}"\n'
    path = tmp_path / "fe_pendulum.toml"
    path.write_text(text)
    return path


def test_fe_nodes_are_the_node_outputs(ffr_bin, tmp_path):
    """An FE body is drawn as its nodes (vertices, in node order, `node` =
    the node's number): at every written step a node's point is the scene's
    position output at `bar@node=N` to round-off; the points are the
    undeformed nodes turned by the body's axes (`axis_x/y/z`), moved with the
    frame, plus `displacement`; the tip's `displacement` is its `deflection`
    output (body frame) turned into global axes; no section rotation."""
    scene = fe_pendulum(tmp_path)
    every = 4
    out = tmp_path / "vtk"
    r = run_ffr(ffr_bin, "run", scene, "--csv", tmp_path / "o.csv", "--vtk", out, "--every", every)
    assert r.returncode == 0, r.stderr
    cols = read_csv(tmp_path / "o.csv")
    t = cols["t"]
    times, files = read_pvd(out / "fe_pendulum.pvd")
    rows = list(range(0, len(t), every))
    assert len(t) == 31 and len(files) == math.ceil(len(t) / every) == len(rows)
    assert times == [t[i] for i in rows]
    x0 = fe_nodes()
    largest = 0.0
    for f, i in zip(files, rows):
        pts, a, poly = read_vtp(out / f)
        bar = (a["body"] == 0) & (a["node"] >= 0)
        # 99 nodes as vertices (and one joint), no polyline
        assert bar.sum() == len(x0) == 99
        assert np.array_equal(a["node"][bar], np.arange(99))
        assert np.all(a["kind"][bar] == 1) and np.all(a["x"][bar] == 0)
        assert poly.GetNumberOfVerts() == 100 and poly.GetNumberOfLines() == 0
        assert np.all(a["node"][~bar] == -1)
        p = pts[bar]
        for n in FE_NODES:
            want = np.array([cols[f"n{n}_{c}"][i] for c in "xyz"])
            assert np.max(np.abs(p[n] - want)) <= 1e-15 * (1 + np.max(np.abs(want))), (f, n)
        # the frame's axes (the same at every node: nodes do not turn)
        axes = np.stack([a[f"axis_{c}"][bar] for c in "xyz"], axis=2)  # [node, component, axis]
        assert np.max(np.abs(axes - axes[0])) == 0
        rot = axes[0]
        assert np.max(np.abs(rot.T @ rot - np.eye(3))) <= 1e-12
        assert np.max(np.abs(a["rotation"][bar])) == 0
        d = a["displacement"][bar]
        # interface nodes (clamped) do not move relative to the frame
        assert np.max(np.abs(d[[0, 1, 2, 33, 34, 35, 66, 67, 68]])) == 0
        origin = p - d - x0 @ rot.T
        assert np.max(np.abs(origin - origin[0])) <= 1e-14
        defl = np.array([cols[f"d{FE_TIP}_{c}"][i] for c in "xyz"])
        assert np.max(np.abs(d[FE_TIP] - rot @ defl)) <= 1e-15 + 1e-12 * np.max(np.abs(defl))
        largest = max(largest, np.max(np.linalg.norm(d, axis=1)))
    # the elastic part (7.6e-4 m at the tip) is far above the tolerances
    # above: they test it
    assert largest > 1e-4


def test_fe_series_is_deterministic(ffr_bin, tmp_path):
    scene = fe_pendulum(tmp_path)
    dirs = [tmp_path / "a", tmp_path / "b"]
    for i, d in enumerate(dirs):
        r = run_ffr(ffr_bin, "run", scene, "--csv", tmp_path / f"o{i}.csv", "--vtk", d, "--every", 10)
        assert r.returncode == 0, r.stderr
    names = sorted(os.listdir(dirs[0]))
    assert names == sorted(os.listdir(dirs[1])) and len(names) == 5
    for n in names:
        assert (dirs[0] / n).read_bytes() == (dirs[1] / n).read_bytes(), n


@pytest.mark.parametrize(
    "args",
    [
        ["--count", "3"],  # clamped normal modes
        ["--count", "1", "--boundary", "64"],  # Craig–Bampton: 1 normal mode, 3 constraint modes
    ],
)
def test_fe_mode_animations_are_phi_scaled_as_documented(ffr_bin, tmp_path, args):
    """`ffr modes --scene … --body <FE body> --vtk`: in frame k of mode j the
    displacement of node N is a cos(2πk/24) (phi[ux_N][j], phi[uy_N][j],
    phi[uz_N][j]) (zero for a clamped interface node), a making the largest
    node displacement 10 % of the body's size (the longest side of its
    nodes' bounding box: 1 m); the points are the nodes plus it."""
    out = tmp_path / "modes"
    r = run_ffr(ffr_bin, "modes", "--scene", FE / "pendulum.toml", "--body", "bar", *args, "--json", "--vtk", out)
    assert r.returncode == 0, r.stderr
    m = json.loads(r.stdout)
    phi, dofs = np.array(m["phi"]), m["dofs"]
    x0 = fe_nodes()
    size = np.max(np.ptp(x0, axis=0))
    assert size == 1.0
    count = len(m["labels"])
    assert count == (3 if "--boundary" not in args else 4)
    assert sorted(os.listdir(out)) == sorted(
        [f"bar_mode{j + 1:02}.pvd" for j in range(count)]
        + [f"bar_mode{j + 1:02}_{k:02}.vtp" for j in range(count) for k in range(FRAMES)]
    )
    for j in range(count):
        t = np.zeros((len(x0), 3))
        for n in range(len(x0)):
            for c, axis in enumerate("xyz"):
                if f"u{axis}_{n}" in dofs:
                    t[n, c] = phi[dofs.index(f"u{axis}_{n}"), j]
        scale = 0.1 * size / np.max(np.linalg.norm(t, axis=1))
        times, files = read_pvd(out / f"bar_mode{j + 1:02}.pvd")
        assert len(files) == FRAMES
        # a constraint mode has no frequency: its times are fractions of 1
        period = 2 * math.pi / m["omega"][j] if j < len(m["omega"]) else 1.0
        assert np.allclose(times, [period * k / FRAMES for k in range(FRAMES)], rtol=1e-15, atol=0)
        for k, f in enumerate(files):
            pts, a, poly = read_vtp(out / f)
            assert np.array_equal(a["node"], np.arange(len(x0)))
            assert np.all(a["kind"] == 1) and poly.GetNumberOfVerts() == len(x0)
            want = scale * math.cos(2 * math.pi * k / FRAMES) * t
            assert np.max(np.abs(a["displacement"] - want)) <= 1e-14 * size
            assert np.max(np.abs(pts - x0 - a["displacement"])) <= 1e-15 * size
            assert np.max(np.abs(a["rotation"])) == 0
        _, a, _ = read_vtp(out / files[0])
        assert abs(np.max(np.linalg.norm(a["displacement"], axis=1)) - 0.1 * size) <= 1e-14


def test_fe_campbell_animations_draw_the_nodes(ffr_bin, tmp_path):
    """`ffr campbell --vtk` on a scene with an FE body (the FE pendulum
    without gravity, its revolute joint driven): the nodes are drawn, and at
    Ω = 0 the largest node displacement over the period is 10 % of the
    body's size (1 m) up to the 24-frame sampling of the phase."""
    text = (FE / "pendulum.toml").read_text()
    for key in ("nodes", "mass", "stiffness"):
        name = f"cantilever_{key}.{'csv' if key == 'nodes' else 'mtx'}"
        text = text.replace(f'"{name}"', json.dumps(str(FE / name)))
    text = text.replace("gravity = [0.0, -9.81, 0.0]", "gravity = [0.0, 0.0, 0.0]")
    text = text.replace('b = "bar"\n', 'b = "bar"\ndrive = { angle = "spin-up", omega = 4.0, ramp = 15.0 }\n')
    assert "drive" in text and "9.81" not in text
    scene = tmp_path / "rotor.toml"
    scene.write_text(text)
    out = tmp_path / "campbell"
    r = run_ffr(ffr_bin, "campbell", scene, "--speeds", "0", "--count", "2", "--vtk", out)
    assert r.returncode == 0, r.stderr
    for j in range(2):
        _, files = read_pvd(out / f"rotor_speed01_mode{j + 1:02}.pvd")
        assert len(files) == FRAMES
        peak = 0.0
        for f in files:
            _, a, _ = read_vtp(out / f)
            bar = a["node"] >= 0
            assert np.array_equal(a["node"][bar], np.arange(99))
            peak = max(peak, np.max(np.linalg.norm(a["displacement"][bar], axis=1)))
        assert 0.1 * math.cos(math.pi / FRAMES) * (1 - 1e-9) <= peak <= 0.1 * (1 + 1e-9)


def test_python_run_writes_the_command_lines_series(ffr_bin, tmp_path):
    """`Scene.run(vtk=DIR, every=K)` writes the bytes of `ffr run --vtk DIR
    --every K`; `every` without `vtk`, or 0, is a ValueError."""
    import ffr

    path = SCENES / "spin_up.toml"
    cli_dir, py_dir = tmp_path / "cli", tmp_path / "py"
    r = run_ffr(ffr_bin, "run", path, "--csv", tmp_path / "o.csv", "--vtk", cli_dir, "--every", 250)
    assert r.returncode == 0, r.stderr
    res = ffr.Scene.load(path).run(vtk=py_dir, every=250)
    assert len(res.t) == 2001
    names = sorted(os.listdir(cli_dir))
    assert names == sorted(os.listdir(py_dir)) and len(names) == 1 + math.ceil(2001 / 250)
    for n in names:
        assert (cli_dir / n).read_bytes() == (py_dir / n).read_bytes(), n
    with pytest.raises(ValueError, match="goes with vtk"):
        ffr.Scene.load(path).run(every=3)
    with pytest.raises(ValueError, match="every = 0"):
        ffr.Scene.load(path).run(vtk=py_dir, every=0)
    (py_dir / "spin_up_0000.vtp").write_text("mine")
    with pytest.raises(ffr.FfrError, match="was not written by ffr"):
        ffr.Scene.load(path).run(vtk=py_dir, every=250)
