"""ffr: floating frame of reference (FFR) flexible multibody dynamics.

Scene files loaded, changed by dotted keys and run (the GIL released, the
outputs as numpy arrays); a body's modes and invariants; a scene's linear
model and Campbell diagram; a scene stepped by its caller
(``scene.simulation()``) and, with Gymnasium, as an environment
(``ffr.gym.SceneEnv``). The computations are the Rust library's, the
same as the ``ffr`` command line's. See docs/python.md.
"""

from ._ffr import (
    FfrError,
    RunResult,
    Scene,
    SceneError,
    Simulation,
    SimulationError,
    SimulationState,
    __version__,
    campbell,
    invariants,
    linearize,
    modes,
)

__all__ = [
    "FfrError",
    "RunResult",
    "Scene",
    "SceneError",
    "Simulation",
    "SimulationError",
    "SimulationState",
    "__version__",
    "campbell",
    "invariants",
    "linearize",
    "modes",
]
