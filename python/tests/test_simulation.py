"""A scene stepped from Python (`scene.simulation()`, issue 37): the same
bits as `Scene.run()`, exact save/restore, inputs checked before anything
changes, failures as `run()` reports them, and a closed loop whose decay
matches the closed-loop linear model of `ffr.linearize`."""

import math
import re

import numpy as np
import pytest

import ffr
from conftest import SCENES

# Shipped scenes stepped against run(): every sample, bit for bit (the
# 5-MW blade and the long spatial runs are left to the Rust test
# ffr-cli/tests/stepping.rs).
STEPPED = ["spin_up.toml", "two_link_arm.toml", "pendulum.toml", "slider_crank.toml", "free_floating.toml"]


def stepped_samples(sim, steps):
    """The outputs at t = 0 and after each of `steps` steps, as run() records them."""
    names = sim.output_names
    t, cols = [sim.t], {n: [sim.outputs[n]] for n in names}
    for _ in range(steps):
        sim.step()
        t.append(sim.t)
        out = sim.outputs
        for n in names:
            cols[n].append(out[n])
    return np.array(t), {n: np.array(c) for n, c in cols.items()}


@pytest.mark.parametrize("name", STEPPED)
def test_stepping_gives_the_bits_of_run(name):
    scene = ffr.Scene.load(SCENES / name)
    if name == "spin_up.toml":
        scene.set("t_end", 5.0)
    run = scene.run()
    sim = scene.simulation()
    t, cols = stepped_samples(sim, run.steps)
    assert np.array_equal(t, run.t)
    for n in run.keys():
        assert np.array_equal(cols[n], run[n]), n
    assert sim.steps == run.steps


def test_advance_is_whole_steps_and_refuses_times_off_the_grid():
    scene = ffr.Scene.load(SCENES / "spin_up.toml")
    a, b = scene.simulation(), scene.simulation()
    a.advance(0.5)
    for _ in range(50):
        b.step()
    assert a.t == b.t and a.steps == b.steps == 50 and a.outputs == b.outputs
    before = (a.t, a.steps, a.outputs)
    for t, what in [(0.505, "between two steps"), (0.4, "behind"), (math.nan, "nan"), (math.inf, "inf")]:
        with pytest.raises(ValueError, match="cannot advance to t = "):
            a.advance(t)
        assert (a.t, a.steps, a.outputs) == before, what
    with pytest.raises(TypeError):
        a.advance("1.0")


def test_a_restored_state_continues_bit_for_bit():
    scene = ffr.Scene.load(SCENES / "two_link_arm.toml")
    sim = scene.simulation()
    sim.advance(0.3)
    saved = sim.state()
    assert saved.t == sim.t
    t1, first = stepped_samples(sim, 200)
    sim.restore(saved)
    assert sim.t == saved.t
    t2, again = stepped_samples(sim, 200)
    assert np.array_equal(t1, t2)
    for n in first:
        assert np.array_equal(first[n], again[n]), n
    # Into another simulation of the same scene: the same continuation.
    other = scene.simulation()
    other.restore(saved)
    t3, third = stepped_samples(other, 200)
    assert np.array_equal(t1, t3)
    for n in first:
        assert np.array_equal(first[n], third[n]), n
    # A state of another scene is refused, and nothing changes.
    foreign = ffr.Scene.load(SCENES / "spin_up.toml").simulation().state()
    at = (sim.t, sim.outputs)
    with pytest.raises(ValueError, match="the saved state is of another scene"):
        sim.restore(foreign)
    assert (sim.t, sim.outputs) == at


ARM = (SCENES / "two_link_arm.toml").read_text()

INPUTS = """
[[inputs]]
name = "elbow_tau"
kind = "torque"
joint = 3

[[inputs]]
name = "push"
kind = "force"
at = "forearm@x=0.4"
direction = [0.0, 1.0]
axes = "body"
"""


def arm_with_inputs(**replace):
    text = ARM + INPUTS
    for old, new in replace.items():
        assert old in text, old
        text = text.replace(old, new)
    return ffr.Scene.from_str(text, "arm_inputs.toml", base=SCENES)


def test_inputs_are_checked_before_anything_changes():
    sim = arm_with_inputs().simulation()
    assert sim.input_names == ["elbow_tau", "push"]
    assert sim.inputs == {"elbow_tau": 0.0, "push": 0.0}
    sim.step(inputs={"elbow_tau": 0.01})
    before = (sim.t, sim.steps, sim.inputs, sim.outputs)
    with pytest.raises(KeyError, match=r"no input `nope`; the scene's inputs are `elbow_tau`, `push`"):
        sim.step(inputs={"push": 1.0, "nope": 1.0})
    for bad in [math.nan, math.inf, -math.inf]:
        with pytest.raises(ValueError, match="input `push` must be finite"):
            sim.step(inputs={"elbow_tau": 0.5, "push": bad})
    with pytest.raises(TypeError, match="input `push`: not a real number"):
        sim.step(inputs={"push": "1"})
    with pytest.raises(TypeError, match="an input name must be a str"):
        sim.step(inputs={1: 1.0})
    # Hostile names are escaped in the message.
    with pytest.raises(KeyError) as e:
        sim.advance(1.0, inputs={"a\x1b[2J\nb": 1.0})
    assert "\x1b" not in str(e.value) and "\n" not in str(e.value)
    assert (sim.t, sim.steps, sim.inputs, sim.outputs) == before
    # numpy scalars are numbers; the value holds until set again.
    sim.step(inputs={"push": np.float64(0.25)})
    sim.step()
    assert sim.inputs == {"elbow_tau": 0.01, "push": 0.25}


def test_inputs_set_by_the_caller_equal_a_profile_table():
    # A staircase set through step() at the steps' starts, and the same
    # values as a profile table: a table is sampled at each step's start
    # and held over the step (docs/in-the-loop.md), so the two runs are
    # the same bit for bit when the table is flat at value k from just
    # before step k's start (the starts are sums of dt, within 1e-15 s of
    # k dt) to just before step k + 1's.
    dt, n, eps = 1e-3, 600, 1e-9
    values = [0.02 * math.sin(7.0 * k * dt) for k in range(n)]
    rows = ", ".join(
        f"[{max(k * dt - eps, 0.0)!r}, {v!r}], [{(k + 1) * dt - 2 * eps!r}, {v!r}]" for k, v in enumerate(values)
    )
    table = arm_with_inputs(**{'joint = 3\n': f"joint = 3\nprofile = {{ table = [{rows}] }}\n"})
    table.set("t_end", n * dt)
    run = table.run()
    caller = arm_with_inputs()
    caller.set("t_end", n * dt)
    sim = caller.simulation()
    t, cols = [sim.t], {k: [v] for k, v in sim.outputs.items()}
    for v in values:
        sim.step(inputs={"elbow_tau": v})
        t.append(sim.t)
        for k, x in sim.outputs.items():
            cols[k].append(x)
    assert np.array_equal(np.array(t), run.t)
    for k in run.keys():
        assert np.array_equal(np.array(cols[k]), run[k]), k


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # the cut run's elastic rotation
def test_a_failed_step_raises_as_run_does_and_restore_clears_it():
    # Without geometric stiffening the spin-up beam's deflection grows
    # without bound: the divergence monitor stops the run.
    scene = ffr.Scene.load(SCENES / "spin_up.toml")
    scene.set("bodies.beam.stiffening", False)
    with pytest.raises(ffr.SimulationError) as run_error:
        scene.run()
    sim = scene.simulation()
    saved = sim.state()
    with pytest.raises(ffr.SimulationError) as step_error:
        sim.advance(scene.get("t_end"))
    assert str(step_error.value) == str(run_error.value)
    assert sim.failed == str(run_error.value)
    with pytest.raises(ffr.SimulationError, match=re.escape(str(run_error.value))):
        sim.step()
    sim.restore(saved)
    assert sim.failed is None and sim.t == 0.0
    sim.step()


def test_a_closed_loop_decays_as_the_closed_loop_linear_model():
    # The flexible two-link arm, shoulder held still, no gravity; a PD
    # controller on the elbow through sim.step: u = −K y, y = (elbow,
    # hand_vy). Released from a small elbow angle, the slowest mode's
    # decay rate and frequency, found from the stepped response by Prony's
    # method (linear prediction), equal the eigenvalue of A − B K C from
    # ffr.linearize at the static state.
    scene = arm_with_inputs(
        **{
            'motor = { target = { angle = "harmonic", amplitude = 0.5, frequency = 0.5 }, kp = 20.0, kd = 1.0 }': 'drive = { angle = "constant", value = 0.0 }',
            "gravity = [0.0, -9.81]": "gravity = [0.0, 0.0]",
            "dt = 1e-3": "dt = 2e-4",
            'position = [0.5, 0.0]       # at the upper arm\'s tip\nangle = 0.0': 'position = [0.5, 0.0]\nangle = 0.005',
        }
    )
    K = np.array([1.0, 0.1])  # N m/rad on the elbow angle, N s on the hand's velocity
    text = scene.text + '\n[[outputs]]\nname = "hand_vy"\nkind = "velocity"\nat = "forearm@x=0.4"\ncomponent = "y"\n'
    scene = ffr.Scene.from_str(text, "arm_pd.toml", base=SCENES)
    lin = ffr.linearize(scene, at="static", inputs=["elbow_tau"], outputs=["elbow", "hand_vy"])
    assert np.allclose(lin["D"], 0.0)
    closed = lin["A"] - lin["B"] @ K.reshape(1, 2) @ lin["C"]
    lam = np.linalg.eigvals(closed)
    osc = lam[np.abs(lam.imag) > 1e-6]
    slowest = osc[np.argmax(osc.real)]
    sim = scene.simulation()
    dt = sim.dt
    ys = []
    for _ in range(int(round(2.0 / dt))):
        out = sim.outputs
        y = np.array([out["elbow"], out["hand_vy"]])
        ys.append(y[0])
        sim.step(inputs={"elbow_tau": float(-K @ y)})
    ys = np.array(ys)
    # Prony on the response after the fast modes died out, decimated.
    skip, every, order = int(0.3 / dt), 25, 6
    s = ys[skip::every]
    rows = np.array([s[i : i + order] for i in range(len(s) - order)])
    coef = np.linalg.lstsq(rows, s[order:], rcond=None)[0]
    z = np.roots(np.concatenate(([1.0], -coef[::-1])))
    poles = np.log(z.astype(complex)) / (every * dt)
    found = poles[np.argmin(np.abs(poles - slowest))]
    print(f"closed loop: stepped {found:.6f}, A − B K C {slowest:.6f}")
    assert abs(found.real - slowest.real) <= 0.01 * abs(slowest.real), (found, slowest)
    assert abs(abs(found.imag) - abs(slowest.imag)) <= 0.01 * abs(slowest.imag), (found, slowest)


gymnasium = pytest.importorskip("gymnasium")


def arm_env(**kw):
    from ffr.gym import SceneEnv

    args = dict(
        inputs=["elbow_tau"],
        outputs=["elbow", "hand_y"],
        reward=lambda out: -out["elbow"] ** 2,
        dt=0.01,
        action_low=-0.1,
        action_high=0.1,
    )
    args.update(kw)
    return SceneEnv(arm_with_inputs(), **args)


def test_the_gymnasium_environment_passes_gymnasiums_checker():
    from gymnasium.utils.env_checker import check_env

    import warnings

    def checked(env):
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            check_env(env, skip_render_check=True)
        return sorted(re.sub(r"\x1b\[\d+m", "", str(w.message)) for w in said)

    # Actions in [-1, 1] N m: the checker passes; all it says is that the
    # observations' bounds are infinite (as in Gymnasium's MuJoCo
    # environments: outputs have no bounds).
    infinite = [
        "WARN: A Box observation space maximum value is infinity. This is probably too high.",
        "WARN: A Box observation space minimum value is -infinity. This is probably too low.",
    ]
    assert checked(arm_env(action_low=-1.0, action_high=1.0)) == infinite
    # Unbounded actions (the default) pass too.
    said = checked(arm_env(action_low=None, action_high=None))
    assert all("infinity" in w or "symmetric and normalized" in w for w in said), said


def test_an_environment_step_is_its_scene_steps_with_the_action_held():
    env = arm_env()
    obs, info = env.reset(seed=3)
    assert obs.dtype == np.float64 and obs.shape == (2,) and info["t"] == 0.0
    sim = arm_with_inputs().simulation()
    for k in range(30):
        a = np.array([0.05 * math.sin(0.3 * k)])
        obs, r, terminated, truncated, info = env.step(a)
        for _ in range(10):
            sim.step(inputs={"elbow_tau": float(a[0])})
        out = sim.outputs
        assert np.array_equal(obs, [out["elbow"], out["hand_y"]])
        assert r == -out["elbow"] ** 2 and not terminated and not truncated
        assert info["t"] == sim.t
    # reset puts back the initial state exactly.
    obs0, _ = env.reset()
    first = env.step(np.array([0.02]))[0]
    obs1, _ = env.reset()
    assert np.array_equal(obs0, obs1) and np.array_equal(first, env.step(np.array([0.02]))[0])


def test_an_episode_is_truncated_at_t_end_and_terminated_by_a_failure():
    env = arm_env(t_end=0.05)
    env.reset()
    flags = [env.step(np.array([0.0]))[3] for _ in range(5)]
    assert flags == [False, False, False, False, True]
    # A scene whose run diverges ends the episode with the message.
    from ffr.gym import SceneEnv

    scene = ffr.Scene.load(SCENES / "spin_up.toml")
    scene.set("bodies.beam.stiffening", False)
    text = scene.text + '\n[[inputs]]\nname = "hub"\nkind = "drive-acceleration"\njoint = 1\n'
    env = SceneEnv(
        ffr.Scene.from_str(text, "spin.toml", base=SCENES),
        inputs=["hub"],
        outputs=["tip_transverse"],
        reward=lambda out: 0.0,
        dt=1.0,
    )
    env.reset()
    for _ in range(20):
        obs, r, terminated, truncated, info = env.step(np.array([0.0]))
        if terminated:
            break
    assert terminated and not truncated and "the run diverged" in info["error"]
    assert np.isfinite(obs).all()


def test_the_environment_refuses_what_does_not_fit_the_scene():
    from ffr.gym import SceneEnv

    with pytest.raises(KeyError, match="no input 'nope'"):
        arm_env(inputs=["nope"])
    with pytest.raises(KeyError, match="no output 'nope'"):
        arm_env(outputs=["nope"])
    with pytest.raises(ValueError, match="not a whole number of the scene's steps"):
        arm_env(dt=0.0105)
    with pytest.raises(ValueError, match="not a whole number"):
        arm_env(dt=-0.01)
    with pytest.raises(ValueError, match="action_low"):
        arm_env(action_low=[0.0, 1.0])
    with pytest.raises(TypeError, match="reward must be a callable"):
        arm_env(reward=3.0)
    env = arm_env()
    env.reset()
    with pytest.raises(ValueError, match="1 inputs"):
        env.step(np.array([0.1, 0.2]))
    with pytest.raises(ValueError, match="must be finite"):
        env.step(np.array([math.nan]))
    assert isinstance(env, SceneEnv)
