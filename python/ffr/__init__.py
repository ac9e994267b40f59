"""ffr: floating frame of reference (FFR) flexible multibody dynamics.

Scene files loaded, changed by dotted keys and run (the GIL released, the
outputs as numpy arrays); a body's modes and invariants; a scene's linear
model and Campbell diagram. The computations are the Rust library's, the
same as the ``ffr`` command line's. See docs/python.md.
"""

from ._ffr import (
    FfrError,
    RunResult,
    Scene,
    SceneError,
    SimulationError,
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
    "SimulationError",
    "__version__",
    "campbell",
    "invariants",
    "linearize",
    "modes",
]
