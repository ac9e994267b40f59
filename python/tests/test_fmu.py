"""The FMU of `ffr fmu` read by a real importer, FMPy (from PyPI):
validation, `simulate_fmu` with an input table against `ffr run` of the
same input history as a profile table (bit for bit), get/set state through
`FMU2Slave`, independent instances, and hostile calls (errors, never a
crash of this process).

How FMPy feeds an input table to a Co-Simulation FMU (fmpy.simulation,
`simulateCS` and `Input.interpolate`): at each communication point
`t_n = start + n * output_interval` (a product, not a sum) it sets every
continuous input to the table's value at `t_n`, linearly interpolated
between the rows around it, then calls `fmi2DoStep(t_n, t_{n+1} - t_n)`;
the FMU holds that value over the step. With `output_interval = dt` and a
table whose times are `n * dt` (the same products), the interpolation at a
row's own time is `0 * v_{n-1} + 1 * v_n`: the row's value exactly. So the
FMU steps with `u_n` held over step `n`, which is what the scene's
`profile = { table = … }` of that input gives `ffr run` (see
`staircase` below for how the table is written).
"""

import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT

fmpy = pytest.importorskip("fmpy")
from fmpy import read_model_description, simulate_fmu  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

DT = 1e-3
STEPS = 300

# The two-link arm of scenes/two_link_arm.toml with its shoulder driven by a
# named torque input instead of the PD motor, and a push at the hand.
ARM = """
description = "two-link flexible arm, shoulder torque and hand force as inputs"
dimension = 2
gravity = [0.0, -9.81]
t_end = 1.0
dt = 1e-3
integrator = {{ kind = "generalized-alpha", rho_inf = 0.9 }}

[bodies.hub]
mass = 1.0
inertia = 0.01
position = [0.0, 0.0]

[bodies.upper]
shape = "beam2"
elements = 4
reference = "clamped"
params = {{ length = 0.5, rho = 2700.0, area = 1e-4, iz = 8.333333333333334e-10, e = 7.0e10 }}
damping = {{ alpha = 0.0, beta = 1e-4 }}
position = [0.0, 0.0]
angle = 0.0

[bodies.forearm]
shape = "beam2"
elements = 4
reference = "clamped"
params = {{ length = 0.4, rho = 2700.0, area = 1e-4, iz = 8.333333333333334e-10, e = 7.0e10 }}
damping = {{ alpha = 0.0, beta = 1e-4 }}
position = [0.5, 0.0]
angle = 0.0

[[joints]]
kind = "revolute"
a = "ground@[0.0, 0.0]"
b = "hub"

[[joints]]
kind = "fixed"
a = "hub"
b = "upper"

[[joints]]
kind = "revolute"
a = "upper@x=0.5"
b = "forearm"

[[forces]]
kind = "rotational-spring-damper"
a = "upper@x=0.5"
b = "forearm"
stiffness = 2.0
damping = 0.02
rest_angle = 0.0

[[inputs]]
name = "tau"
kind = "torque"
joint = 1
{tau_profile}

[[inputs]]
name = "push"
kind = "force"
at = "forearm@x=0.4"
direction = [0.0, 1.0]
{push_profile}

[[outputs]]
name = "shoulder"
kind = "angle"
at = "hub"

[[outputs]]
name = "hand_y"
kind = "position"
at = "forearm@x=0.4"
component = "y"

[[outputs]]
name = "upper_tip_deflection"
kind = "deflection"
at = "upper@x=0.5"
component = "y"
"""


def arm_text(tau=None, push=None):
    def profile(rows):
        if rows is None:
            return "start = 0.0"
        body = ", ".join(f"[{t!r}, {v!r}]" for t, v in rows)
        return f"profile = {{ table = [{body}] }}"

    return ARM.format(tau_profile=profile(tau), push_profile=profile(push))


def staircase(values):
    """The profile table that holds `values[n]` over step n, as the FMU
    holds an input set at the n-th communication point. A scene's profile
    of an input is evaluated at the start of each step (the integrator's
    time, a sum of steps: 0, dt, dt + dt, …) and held over the step; the
    rows are at exactly those times, so that each evaluation is a row's own
    value (rows at the products n * dt would be a few ulps off the sums and
    interpolate between two values). The steps stay clear of `t_end`, whose
    last step is shortened to end on it."""
    rows, t = [], 0.0
    for v in values:
        rows.append((t, float(v)))
        t += DT
    return rows


@pytest.fixture(scope="session")
def fmu_lib(ffr_bin):
    """The FMU library of the same build as `ffr` (beside it after
    `cargo build --release -p ffr-cli -p ffr-fmu`; built here if missing)."""
    lib = ffr_bin.parent / "libffr_fmu.so"
    if not lib.is_file():
        subprocess.run(
            ["cargo", "build", "--release", "-p", "ffr-cli", "-p", "ffr-fmu"],
            cwd=ROOT,
            check=True,
        )
    assert lib.is_file(), lib
    return lib


def export(ffr_bin, fmu_lib, scene, out, *params):
    args = [str(ffr_bin), "fmu", str(scene), "--out", str(out), "--binary", str(fmu_lib)]
    for p in params:
        args += ["--parameter", p]
    r = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert r.returncode == 0, r.stderr
    return out


@pytest.fixture
def arm_fmu(tmp_path, ffr_bin, fmu_lib):
    scene = tmp_path / "arm.toml"
    scene.write_text(arm_text())
    return export(ffr_bin, fmu_lib, scene, tmp_path / "arm.fmu", "bodies.forearm.params.e")


def run_csv(ffr_bin, scene, csv):
    r = subprocess.run(
        [str(ffr_bin), "run", str(scene), "--csv", str(csv), "--svg", str(csv.with_suffix(".svg"))],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    lines = csv.read_text().splitlines()
    names = lines[0].split(",")
    rows = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    return {n: rows[:, i] for i, n in enumerate(names)}


def test_fmpy_validates_the_fmu(arm_fmu):
    assert validate_fmu(str(arm_fmu)) == []
    md = read_model_description(str(arm_fmu))
    assert md.fmiVersion == "2.0"
    assert md.generationTool.startswith("ffr ")
    cs = md.coSimulation
    assert cs.modelIdentifier == "arm"
    assert cs.canGetAndSetFMUstate and not cs.canSerializeFMUstate
    assert cs.canHandleVariableCommunicationStepSize
    v = {x.name: x for x in md.modelVariables}
    assert [v[n].causality for n in ("tau", "push")] == ["input", "input"]
    assert [v[n].causality for n in ("shoulder", "hand_y", "upper_tip_deflection")] == ["output"] * 3
    p = v["bodies.forearm.params.e"]
    assert (p.causality, p.variability, float(p.start)) == ("parameter", "fixed", 7.0e10)
    assert float(md.defaultExperiment.stepSize) == DT
    assert float(md.defaultExperiment.stopTime) == 1.0
    names = zipfile.ZipFile(arm_fmu).namelist()
    assert "binaries/linux64/arm.so" in names
    assert "resources/arm.toml" in names


def test_simulate_fmu_with_an_input_table_equals_ffr_run_with_the_profile(tmp_path, ffr_bin, arm_fmu):
    # An input history that changes at every step (and jumps): a torque
    # pulse and a push that alternates in sign.
    n = np.arange(STEPS + 1)
    t = n * DT
    tau = np.where(t < 0.1, 0.4 * np.sin(40 * t), -0.2)
    push = 0.05 * np.cos(25 * t) * np.where(n % 7 == 0, -1.0, 1.0)
    signals = np.array(list(zip(t, tau, push)), dtype=[("time", np.double), ("tau", np.double), ("push", np.double)])
    res = simulate_fmu(
        str(arm_fmu),
        stop_time=STEPS * DT,
        output_interval=DT,
        input=signals,
        output=["shoulder", "hand_y", "upper_tip_deflection"],
    )
    assert len(res) == STEPS + 1
    scene = tmp_path / "profiled.toml"
    scene.write_text(arm_text(tau=staircase(tau), push=staircase(push)))
    run = run_csv(ffr_bin, scene, tmp_path / "profiled.csv")
    for name in ("shoulder", "hand_y", "upper_tip_deflection"):
        np.testing.assert_array_equal(res[name], run[name][: STEPS + 1], err_msg=name)
    # The input moved the arm (the comparison is not of two rests).
    assert np.max(np.abs(run["shoulder"])) > 1e-3


def slave(fmu, tmp_path, name="a", unzip=None):
    md = read_model_description(str(fmu))
    unzip = unzip or fmpy.extract(str(fmu), str(tmp_path / f"unzip-{name}"))
    s = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzip,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName=name,
    )
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    vr = {v.name: v.valueReference for v in md.modelVariables}
    return s, vr, unzip


def steps(s, vr, t0, n, inputs):
    """n steps of DT from t0 with inputs(k) -> (tau, push); the outputs after each."""
    out = []
    for k in range(n):
        s.setReal([vr["tau"], vr["push"]], list(inputs(k)))
        s.doStep(currentCommunicationPoint=t0 + k * DT, communicationStepSize=DT)
        out.append(s.getReal([vr["shoulder"], vr["hand_y"], vr["upper_tip_deflection"]]))
    return out


def test_get_and_set_state_through_fmu2slave_continue_bit_for_bit(tmp_path, arm_fmu):
    s, vr, _ = slave(arm_fmu, tmp_path)
    steps(s, vr, 0.0, 50, lambda k: (0.3, 0.0))
    state = s.getFMUstate()
    u = lambda k: (0.3 - 0.01 * k, 0.02 * (-1) ** k)  # noqa: E731
    first = steps(s, vr, 50 * DT, 40, u)
    s.setFMUstate(state)
    assert steps(s, vr, 50 * DT, 40, u) == first
    # The held inputs are part of the state: back at the saved state, the
    # input reads what it was then.
    s.setFMUstate(state)
    assert s.getReal([vr["tau"]]) == [0.3]
    s.freeFMUstate(state)
    s.terminate()
    s.freeInstance()


def test_instances_are_independent_also_from_two_copies_of_the_library(tmp_path, arm_fmu):
    # a and b share one loaded library; c is the FMU extracted again, so its
    # library is loaded a second time (another file: dlopen loads a copy).
    a, vr, unzip = slave(arm_fmu, tmp_path, "a")
    b, _, _ = slave(arm_fmu, tmp_path, "b", unzip=unzip)
    c, _, _ = slave(arm_fmu, tmp_path, "c")
    ua = lambda k: (0.5, 0.0)  # noqa: E731
    ub = lambda k: (-0.2, 0.01)  # noqa: E731
    ra, rb, rc = [], [], []
    for k in range(60):
        ra += steps(a, vr, k * DT, 1, lambda _: ua(k))
        rb += steps(b, vr, k * DT, 1, lambda _: ub(k))
        rc += steps(c, vr, k * DT, 1, lambda _: ua(k))
    alone, _, _ = slave(arm_fmu, tmp_path, "alone", unzip=unzip)
    assert steps(alone, vr, 0.0, 60, ua) == ra
    assert rc == ra
    assert rb != ra
    for s in (a, b, c, alone):
        s.terminate()
        s.freeInstance()


class Log:
    """An FMPy logger that keeps the messages."""

    def __init__(self):
        self.messages = []

    def __call__(self, env, name, status, category, message):
        self.messages.append((status, message.decode()))


def logged_slave(fmu, tmp_path, name, unzip=None, guid=None):
    from ctypes import byref
    from fmpy.fmi2 import fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE
    from fmpy import calloc, free

    md = read_model_description(str(fmu))
    unzip = unzip or fmpy.extract(str(fmu), str(tmp_path / f"unzip-{name}"))
    log = Log()
    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(log)
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    s = FMU2Slave(
        guid=guid or md.guid,
        unzipDirectory=unzip,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName=name,
    )
    s._keep = (cb, byref(cb))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    return s, vr, log, cb, unzip


def test_hostile_calls_are_errors_with_messages_never_a_crash(tmp_path, arm_fmu):
    s, vr, log, cb, unzip = logged_slave(arm_fmu, tmp_path, "h")
    s.instantiate(callbacks=cb)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()

    def refused(call, says):
        with pytest.raises(FMICallException):
            call()
        assert says in log.messages[-1][1], log.messages[-1]

    refused(lambda: s.getReal([9999]), "value reference 9999 is not a variable")
    refused(lambda: s.setReal([vr["tau"]], [float("nan")]), "NaN for `tau`")
    refused(lambda: s.setReal([vr["tau"]], [float("inf")]), "not a finite number")
    assert s.getReal([vr["tau"]]) == [0.0]
    refused(lambda: s.doStep(0.0, 0.0), "communicationStepSize 0")
    refused(lambda: s.doStep(0.0, -DT), "must be positive")
    refused(lambda: s.doStep(0.0, 1.5 * DT), "not a whole number of the scene's steps")
    refused(lambda: s.doStep(DT, DT), "is not the FMU's time")
    refused(lambda: s.setReal([vr["bodies.forearm.params.e"]], [1e9]), "set only before")
    # Nothing moved: a valid step still works, from t = 0.
    s.doStep(0.0, DT)
    # A torque that tears the arm apart: the step fails (fmi2Discard) with
    # the run's message; stepping on is refused until a state is set.
    state = s.getFMUstate()
    s.setReal([vr["tau"]], [1e9])
    with pytest.raises(FMICallException) as e:
        for k in range(1, 200):
            s.doStep(k * DT, DT)
    assert e.value.status == 2  # fmi2Discard
    assert "the run stopped at t =" in log.messages[-1][1], log.messages[-1]
    refused(lambda: s.doStep(s.getRealStatus(2), DT), "the simulation failed at t =")
    s.setFMUstate(state)
    assert s.getReal([vr["tau"]]) == [0.0]
    s.doStep(DT, DT)
    s.freeFMUstate(state)
    s.terminate()
    s.freeInstance()


def test_a_missing_resource_or_another_guid_fails_to_instantiate_with_a_message(tmp_path, arm_fmu):
    s, _, log, cb, unzip = logged_slave(arm_fmu, tmp_path, "g", guid="{not-this-one}")
    with pytest.raises(Exception):
        s.instantiate(callbacks=cb)
    assert "is not this FMU's" in log.messages[-1][1], log.messages
    (Path(unzip) / "resources" / "arm.toml").unlink()
    s, _, log, cb, _ = logged_slave(arm_fmu, tmp_path, "m", unzip=unzip)
    with pytest.raises(Exception):
        s.instantiate(callbacks=cb)
    assert "arm.toml" in log.messages[-1][1], log.messages
    shutil.rmtree(unzip)


def test_a_parameter_set_before_initialization_reresolves_the_scene(tmp_path, ffr_bin, arm_fmu):
    md = read_model_description(str(arm_fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    res = simulate_fmu(
        str(arm_fmu),
        stop_time=100 * DT,
        output_interval=DT,
        start_values={"bodies.forearm.params.e": 3.5e10},
        input=np.array([(0.0, 0.3, 0.0)], dtype=[("time", np.double), ("tau", np.double), ("push", np.double)]),
        output=["hand_y"],
    )
    scene = tmp_path / "soft.toml"
    rows = staircase(np.full(101, 0.3))
    text = arm_text(tau=rows)
    i = text.index("[bodies.forearm]")
    text = text[:i] + text[i:].replace("e = 7.0e10", "e = 3.5e10", 1)
    scene.write_text(text)
    run = run_csv(ffr_bin, scene, tmp_path / "soft.csv")
    np.testing.assert_array_equal(res["hand_y"], run["hand_y"][:101])
    assert vr["bodies.forearm.params.e"] == 5
