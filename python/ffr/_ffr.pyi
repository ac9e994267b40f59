"""Type stubs of the extension module ffr._ffr (re-exported by ffr)."""

import os
from typing import Dict, Iterator, List, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

FloatArray = npt.NDArray[np.float64]
#: A scene value: what a scene file can hold at a key.
SceneValue = Union[bool, int, float, str, Sequence["SceneValue"], Dict[str, "SceneValue"]]
#: A scene: an ffr.Scene or a scene file's path.
SceneLike = Union["Scene", str, "os.PathLike[str]"]

class FfrError(Exception):
    """An error of ffr: the message names the problem and, for input from a
    file, where (``file:line:col: …``)."""

class SceneError(FfrError):
    """A scene that does not load, or a key or value that does not fit it:
    the loader's located message."""

class SimulationError(FfrError):
    """A run or an analysis that failed (no convergence, divergence, a
    singular matrix, outputs that are not finite): why, and when."""

    #: From ``Scene.run()``: the samples up to the failure (times, outputs
    #: and statistics, as a run's result; all of them for a run refused for
    #: an output that is not finite); None when the run failed before its
    #: first sample and for the other calls.
    run: Optional["RunResult"]

class Scene:
    """A scene file's text with the values set so far, and the scene built
    from it (checked and ready to run)."""

    @staticmethod
    def load(path: Union[str, "os.PathLike[str]"]) -> "Scene":
        """Read a scene file (relative shape files against its directory);
        raises SceneError with the loader's located message."""
    @staticmethod
    def from_str(
        text: str, file: str = "<string>", base: Optional[Union[str, "os.PathLike[str]"]] = None
    ) -> "Scene":
        """A scene from its text; ``file`` names it in errors, ``base``
        (default: the current directory) resolves relative shape files."""
    def set(self, key: str, value: Union[SceneValue, "np.generic", "npt.NDArray[np.generic]"]) -> None:
        """Set the value at a dotted key (``bodies.beam.params.e``,
        ``joints.0.drive.omega``, ``t_end``); the scene is resolved and
        built again, and a key or value it refuses raises SceneError (the
        scene is left as it was). A key set again replaces its earlier
        value; at most 256 distinct keys (``MAX_OVERRIDES``). numpy scalars
        and arrays are their ``tolist()`` values (a 0-d array a number)."""
    def update(self, values: Dict[str, SceneValue]) -> None:
        """Set several dotted keys at once, checked together."""
    def get(self, key: str) -> Optional[SceneValue]:
        """The value at a dotted key, or None if the scene has none there:
        a table as a dict, an array of tables (``joints``) as a list of
        dicts."""
    @property
    def file(self) -> str:
        """The file's name as errors give it."""
    @property
    def text(self) -> str:
        """The scene's text as it reads now (the file with the values set)."""
    @property
    def overrides(self) -> List[Tuple[str, SceneValue]]:
        """The keys set so far and their values, in the order last set (a
        key set again, also spelt ``joints.00`` for ``joints.0``, replaces
        its earlier value; a value set as a whole drops the keys set
        inside it)."""
    def run(
        self, vtk: Optional[Union[str, "os.PathLike[str]"]] = None, every: int = 1
    ) -> "RunResult":
        """Run the scene with the GIL released; raises SimulationError if
        the run stops early or an output is not finite (as ``ffr run``),
        with the samples up to there as its ``run``. Ctrl-C stops it within
        about 50 ms (KeyboardInterrupt; the scene is unchanged).
        ``vtk=DIR`` also writes the ParaView time series of ``ffr run --vtk
        DIR --every EVERY`` (docs/vtk.md)."""
    def static(self, steps: Optional[int] = None) -> "Static":
        """The static equilibrium under the scene's loads at t = 0 with the
        GIL released, as ``ffr static --json``: ``outputs`` (each output's
        value), ``steps`` (load increments used), ``iterations``
        (Newton iterations) and ``warnings`` (each also issued once as a
        RuntimeWarning), plus ``rotations`` (each flexible body's largest
        elastic rotation there). ``steps=K`` takes K equal load increments
        (default: automatic). Raises SimulationError if there is no
        equilibrium (a mechanism, an unstable state, no convergence);
        Ctrl-C stops it (KeyboardInterrupt)."""

    def simulation(self) -> "Simulation":
        """A simulation of the scene as it is now, stepped by the caller:
        the steps of ``run()``, one at a time (later ``set`` calls on the
        scene do not change it). A refused initial state raises as
        ``run()`` does."""

class Simulation:
    """A scene stepped by its caller (``Scene.simulation()``): inputs
    (``[[inputs]]``) set between steps and held (zero-order hold), outputs
    read after each step, the state saved and restored exactly. Stepping to
    the end gives the samples of ``Scene.run()`` bit for bit."""

    #: The time (s).
    t: float
    #: The scene's step (s): what one ``step()`` advances.
    dt: float
    #: Steps taken.
    steps: int
    #: The scene's input and output names, in file order.
    input_names: List[str]
    output_names: List[str]
    #: The inputs' values now.
    inputs: Dict[str, float]
    #: The outputs at ``t`` (what ``run()`` records at that sample).
    outputs: Dict[str, float]
    #: The message of the step that failed, or None.
    failed: Optional[str]
    def step(self, inputs: Optional[Dict[str, float]] = None) -> None:
        """Set ``inputs`` (they hold until set again) and take one step of
        ``dt`` with the GIL released. An unknown name raises KeyError, a
        value that is not a finite number ValueError or TypeError, before
        anything changes; a failed step raises SimulationError (and every
        later step too, until ``restore``)."""
    def advance(self, t: float, inputs: Optional[Dict[str, float]] = None) -> None:
        """Set ``inputs`` as ``step`` does and take whole steps until ``t``
        (s), the GIL released; Ctrl-C stops it at a step
        (KeyboardInterrupt). A ``t`` behind the time or between two steps
        raises ValueError before any step."""
    def state(self) -> "SimulationState":
        """Everything the next step depends on, for ``restore``."""
    def restore(self, state: "SimulationState") -> None:
        """Put back a state: the simulation continues bit for bit as it did
        from there (a failure is forgotten); a state of another scene
        raises ValueError."""

class SimulationState:
    """A saved Simulation state (opaque)."""

    #: Its time (s).
    t: float

class RunResult:
    """A scene run: each output by name as a numpy array, the times ``t``,
    and the run's statistics."""

    @property
    def t(self) -> FloatArray: ...
    steps: int
    newton_iterations: int
    jacobians: int
    restarts: int
    splits: int
    #: Wall time of the simulation (s), as the library measures it.
    wall: float
    #: A body turned past what one floating frame describes, as ``ffr run``
    #: prints it (each also issued once as a RuntimeWarning).
    warnings: List[str]
    #: Each flexible body's largest elastic section rotation over the run.
    @property
    def rotations(self) -> List[Rotation]: ...
    def keys(self) -> List[str]: ...
    def __getitem__(self, name: str) -> FloatArray: ...
    def __contains__(self, name: str) -> bool: ...
    def __len__(self) -> int: ...
    def __iter__(self) -> Iterator[str]: ...

class Invariants(TypedDict):
    mass: float
    St0: FloatArray
    Sbar: FloatArray
    Skl: Dict[str, FloatArray]
    Ikl: Dict[str, FloatArray]
    theta: Dict[str, float]
    mff: FloatArray
    Kff: FloatArray
    dofs: List[str]

class Modes(TypedDict):
    body: str
    reduction: str
    omega: FloatArray
    hz: FloatArray
    labels: List[str]
    dofs: List[str]
    phi: FloatArray
    modal_mass: FloatArray
    modal_stiffness: FloatArray
    invariants: Invariants

class Linear(TypedDict):
    states: List[str]
    inputs: List[str]
    outputs: List[str]
    A: FloatArray
    B: FloatArray
    C: FloatArray
    D: FloatArray
    eigenvalues: npt.NDArray[np.complex128]

class CampbellMode(TypedDict):
    omega: float
    hz: float
    zeta: float
    label: str

class Campbell(TypedDict):
    speeds: FloatArray
    joint: int
    modes: List[List[CampbellMode]]
    warnings: List[str]

class Rotation(TypedDict):
    """A flexible body's largest elastic section rotation (rad) relative
    to its (segment's) frame, when (s) and where on the whole body's axis
    (m); ``segment`` is 1-based of the body's ``segments``."""

    body: str
    segment: int
    segments: int
    angle: float
    t: float
    x: float

class Static(TypedDict):
    outputs: Dict[str, float]
    steps: int
    iterations: int
    #: A body turned past what one floating frame describes (each also
    #: issued once as a RuntimeWarning), as ``ffr static`` warns.
    warnings: List[str]
    rotations: List[Rotation]

def invariants(
    shape: Optional[str] = None,
    elements: Optional[int] = None,
    reference: Optional[Literal["clamped", "pinned", "free"]] = None,
    formalism: Optional[Literal["consistent", "lumped"]] = None,
    *,
    length: Optional[float] = None,
    rho: Optional[float] = None,
    area: Optional[float] = None,
    iy: Optional[float] = None,
    iz: Optional[float] = None,
    e: Optional[float] = None,
    g: Optional[float] = None,
    j: Optional[float] = None,
    tape: bool = False,
    scene: Optional[SceneLike] = None,
    body: Optional[str] = None,
) -> Invariants:
    """A body's invariants at its parameters, keyed like ``ffr invariants
    --json``: a beam (defaults: beam3, 1 element, clamped, consistent, the
    command line's 1 m steel bar) or a scene's flexible body."""

def modes(
    shape: Optional[str] = None,
    elements: Optional[int] = None,
    reference: Optional[Literal["clamped", "pinned", "free"]] = None,
    formalism: Optional[Literal["consistent", "lumped"]] = None,
    *,
    count: Optional[int] = None,
    boundary: Optional[Union[Sequence[int], "npt.NDArray[np.integer]"]] = None,
    length: Optional[float] = None,
    rho: Optional[float] = None,
    area: Optional[float] = None,
    iy: Optional[float] = None,
    iz: Optional[float] = None,
    e: Optional[float] = None,
    g: Optional[float] = None,
    j: Optional[float] = None,
    scene: Optional[SceneLike] = None,
    body: Optional[str] = None,
) -> Modes:
    """A body's modes (modal truncation, or Craig–Bampton with
    ``boundary``), keyed like ``ffr modes --json``."""

def linearize(
    scene: SceneLike,
    at: Union[float, Literal["static"], None] = None,
    inputs: Optional[Sequence[str]] = None,
    outputs: Optional[Sequence[str]] = None,
) -> Linear:
    """A scene's linear model about its state at time ``at`` (default 0)
    or its static equilibrium, as ``ffr linearize --json`` (eigenvalues
    complex). Ctrl-C stops the run to ``at`` or the static solver
    (KeyboardInterrupt)."""

def campbell(
    scene: SceneLike,
    speeds: Union[Sequence[float], FloatArray],
    joint: Optional[int] = None,
    count: int = 10,
) -> Campbell:
    """A Campbell diagram, as ``ffr campbell --json`` (and the joint,
    1-based). ``speeds`` a sequence or a 1-d array (a 0-d array or a bare
    number raises TypeError). Ctrl-C stops it between Newton iterations
    (KeyboardInterrupt). Each of ``warnings`` is also issued once as a
    ``RuntimeWarning``."""
