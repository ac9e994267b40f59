"""A scene as a Gymnasium environment: actions are the values of the
scene's named inputs (``[[inputs]]``), observations the values of some of
its outputs, one environment step whole steps of the scene's ``dt``.

Gymnasium is an optional dependency (``pip install gymnasium``); importing
this module without it raises ``ImportError`` saying so. See
docs/in-the-loop.md.
"""

from __future__ import annotations

import math
import os
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np

try:
    import gymnasium
    from gymnasium import spaces
except ImportError as e:  # pragma: no cover - exercised without gymnasium
    raise ImportError(
        "ffr.gym needs Gymnasium, an optional dependency of ffr: pip install gymnasium"
    ) from e

from ._ffr import Scene, SimulationError

__all__ = ["SceneEnv"]

Bounds = Union[float, Sequence[float]]


def _bounds(value: Optional[Bounds], n: int, default: float, what: str) -> np.ndarray:
    if value is None:
        return np.full(n, default, dtype=np.float64)
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim == 0:
        arr = np.full(n, float(arr), dtype=np.float64)
    if arr.shape != (n,):
        raise ValueError(f"{what} has {arr.shape} values for {n} inputs")
    if np.isnan(arr).any():
        raise ValueError(f"{what} is NaN")
    return arr


class SceneEnv(gymnasium.Env):
    """A scene as a Gymnasium environment.

    - ``scene``: an ``ffr.Scene`` or the path of a scene file.
    - ``inputs``: names of the scene's ``[[inputs]]``; an action is their
      values, in this order (they hold over the environment step).
    - ``outputs``: names of the scene's ``[[outputs]]``; an observation is
      their values after the step, in this order (float64).
    - ``reward``: a callable taking the outputs after the step as a dict of
      floats (every output of the scene, by name) and returning a float.
    - ``dt``: the environment step (s), a whole number of the scene's
      ``dt`` (default: the scene's ``dt``).
    - ``t_end``: the episode's length (s); the step that reaches it is
      ``truncated`` (default: the scene's ``t_end``).
    - ``action_low`` / ``action_high``: the action space's bounds (a number
      or one per input; default unbounded). Actions are not clipped: an
      action outside them is passed to the scene as it is.

    ``reset`` puts back the scene's initial state (the inputs at their
    ``start`` values); the scene is deterministic, so ``seed`` changes
    nothing but ``np_random``. A scene step that fails (divergence, no
    convergence) ends the episode: ``terminated`` is True, the
    observation and reward are those of the last valid state, and
    ``info["error"]`` carries the message.
    """

    metadata = {"render_modes": []}

    def __init__(
        self,
        scene: Union[Scene, str, os.PathLike],
        inputs: Sequence[str],
        outputs: Sequence[str],
        reward: Callable[[Mapping[str, float]], float],
        dt: Optional[float] = None,
        t_end: Optional[float] = None,
        action_low: Optional[Bounds] = None,
        action_high: Optional[Bounds] = None,
    ) -> None:
        super().__init__()
        if not isinstance(scene, Scene):
            scene = Scene.load(os.fspath(scene))
        if isinstance(inputs, str) or isinstance(outputs, str):
            raise TypeError("inputs and outputs are lists of names, not a str")
        if not callable(reward):
            raise TypeError("reward must be a callable taking the outputs (a dict) and returning a float")
        self._sim = scene.simulation()
        self._initial = self._sim.state()
        self._inputs = list(inputs)
        self._outputs = list(outputs)
        known_in, known_out = self._sim.input_names, self._sim.output_names
        for n in self._inputs:
            if n not in known_in:
                raise KeyError(f"no input {n!r}; the scene's inputs are {known_in}")
        for n in self._outputs:
            if n not in known_out:
                raise KeyError(f"no output {n!r}; the scene's outputs are {known_out}")
        if len(set(self._inputs)) != len(self._inputs):
            raise ValueError(f"an input is named twice in {self._inputs}")
        if not self._inputs:
            raise ValueError("inputs is empty: an action needs at least one input")
        step = self._sim.dt
        if dt is None:
            dt = step
        dt = float(dt)
        k = round(dt / step) if math.isfinite(dt) and dt > 0 else 0
        if k < 1 or abs(dt - k * step) > 1e-9 * step:
            raise ValueError(f"dt = {dt} s is not a whole number of the scene's steps of {step} s")
        self._k = k
        self.dt = k * step
        self.t_end = float(scene.get("t_end") if t_end is None else t_end)
        if not (math.isfinite(self.t_end) and self.t_end > 0):
            raise ValueError(f"t_end = {self.t_end} s: the episode needs a positive finite length")
        self._reward = reward
        low = _bounds(action_low, len(self._inputs), -np.inf, "action_low")
        high = _bounds(action_high, len(self._inputs), np.inf, "action_high")
        if (low > high).any():
            raise ValueError(f"action_low {low} is above action_high {high}")
        self.action_space = spaces.Box(low=low, high=high, dtype=np.float64)
        # Outputs have no bounds: (-inf, inf), as Gymnasium's MuJoCo
        # environments declare theirs (the checker warns that an infinite
        # bound is probably too wide).
        self.observation_space = spaces.Box(
            low=-np.inf, high=np.inf, shape=(len(self._outputs),), dtype=np.float64
        )
        self._steps = 0

    @property
    def simulation(self):
        """The ``ffr.Simulation`` the environment steps."""
        return self._sim

    def _observation(self, outputs: Mapping[str, float]) -> np.ndarray:
        return np.array([outputs[n] for n in self._outputs], dtype=np.float64)

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        self._sim.restore(self._initial)
        self._steps = 0
        return self._observation(self._sim.outputs), {"t": self._sim.t}

    def step(self, action: Any):
        a = np.asarray(action, dtype=np.float64).reshape(-1)
        if a.shape != (len(self._inputs),):
            raise ValueError(f"an action of {a.size} values for {len(self._inputs)} inputs")
        values = {n: float(v) for n, v in zip(self._inputs, a)}
        self._steps += 1
        target = self._sim.t + self._k * self._sim.dt
        info: dict = {}
        terminated = False
        try:
            self._sim.advance(target, inputs=values)
        except SimulationError as e:
            terminated = True
            info["error"] = str(e)
        outputs = self._sim.outputs
        info["t"] = self._sim.t
        r = float(self._reward(dict(outputs)))
        truncated = not terminated and self._sim.t >= self.t_end - 1e-9 * self._sim.dt
        return self._observation(outputs), r, terminated, truncated, info
