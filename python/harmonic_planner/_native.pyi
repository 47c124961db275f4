"""Type stubs of harmonic_planner's native module (re-exported by ``harmonic_planner``).

Bound: plane scenes (``Scene``, ``Planner``: plan, plan_many, potential, psi, gradient, mesh,
timings, ROS maps, car-like robots), any-goal workspaces (``Workspace``: one factorisation,
a planner per goal), volume scenes (``VolumePlanner``, points of shape (n, 3)) and polygon
robots and arms (``ConfigPlanner``: configurations in, checked motions out).

Not bound yet:
- replanning among moving obstacles (``harmonic-dynamic``), the baseline planners
  (``harmonic-baselines``), SVG / VTK export (use ``hplan``), stage-progress callbacks.
"""

from os import PathLike
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
StrPath = Union[str, "PathLike[str]"]

class SceneError(ValueError):
    """Bad input: an unreadable or invalid scene or map, a scene that cannot be meshed or
    solved, an option out of range, or an array of the wrong shape. The message is the
    command line's without ``hplan: `` (``<file>: <error>`` for files)."""

class Scene:
    """A scene (the JSON format of ``meshes/*.json``): plane, or volume (``"dimension": 3``)."""

    @staticmethod
    def from_file(path: StrPath) -> "Scene":
        """Reads a scene file; errors read ``<path>: <error>``."""
    @staticmethod
    def from_json(text: str) -> "Scene":
        """Parses JSON text; errors name the field, line and column."""
    @staticmethod
    def from_dict(d: Mapping[str, Any]) -> "Scene":
        """A scene from a dict of the file format (serialised with json.dumps(indent=1))."""
    def to_json(self) -> str:
        """The scene as JSON text, defaults filled in."""
    def to_dict(self) -> Dict[str, Any]:
        """The scene as a dict."""
    @property
    def dimension(self) -> int:
        """2 for a plane scene, 3 for a volume."""
    @property
    def name(self) -> Optional[str]: ...
    @property
    def source(self) -> Optional[str]:
        """The file it was read from, or None."""
    @property
    def starts(self) -> FloatArray:
        """The scene's query points, shape (n, 2) or (n, 3)."""

class Path:
    """A planned path. ``points``: shape (n, 2), (n, 3) from a VolumePlanner, (n, dof) of
    configurations from a ConfigPlanner (``space`` says which)."""

    @property
    def status(self) -> str:
        """"reached_goal", "unreachable", "stalled", "start_in_obstacle",
        "outside_workspace" or "max_steps"."""
    @property
    def reached_goal(self) -> bool: ...
    @property
    def goal(self) -> Optional[int]: ...
    @property
    def tracer(self) -> str:
        """"smooth" or "exact"."""
    @property
    def start(self) -> List[float]: ...
    @property
    def space(self) -> str:
        """"plane", "volume", "pose" (a polygon robot) or "joints" (an arm)."""
    @property
    def points(self) -> FloatArray: ...
    @property
    def length(self) -> float: ...
    @property
    def min_clearance(self) -> float: ...
    @property
    def min_gradient(self) -> float: ...
    def poses(
        self, start_heading: Optional[float] = None, goal_heading: Optional[float] = None
    ) -> FloatArray:
        """Shape (n, 3) of [x, y, theta]: headings along the path; ``start_heading`` for the
        first pose and, on reaching the goal, ``goal_heading`` for the last (a pose goal). A
        polygon robot's path is its poses; ValueError for a volume's or an arm's."""
    def __len__(self) -> int: ...

class CarRun:
    """A car-like robot's run; ``poses``: shape (n, 3) of [x, y, theta]."""

    @property
    def status(self) -> str: ...
    @property
    def reached_goal(self) -> bool: ...
    @property
    def goal(self) -> Optional[int]: ...
    @property
    def start(self) -> List[float]: ...
    @property
    def poses(self) -> FloatArray: ...
    @property
    def length(self) -> float: ...
    @property
    def min_clearance(self) -> float: ...
    @property
    def min_gradient(self) -> float: ...
    @property
    def max_curvature(self) -> float: ...
    def __len__(self) -> int: ...

class Planner:
    """A planner for one plane scene: meshed, assembled and solved once (GIL released).
    ``threads``: cores for the build and for ``plan_many`` (default: all, or
    ``RAYON_NUM_THREADS``); paths are the same at any count."""

    def __init__(
        self,
        scene: Scene,
        *,
        max_area: Optional[float] = None,
        multigrid: Optional[int] = None,
        threads: Optional[int] = None,
    ) -> None: ...
    @staticmethod
    def from_map(
        yaml: StrPath,
        goal: ArrayLike,
        robot_radius: float = 0.0,
        *,
        max_area: Optional[float] = None,
        cost_weight: float = 1.0,
        threads: Optional[int] = None,
    ) -> "Planner":
        """A planner on a ROS map_server YAML map towards ``goal`` (world coordinates);
        a ``scale``/``raw`` map's graded costs shape the field by ``cost_weight``."""
    def plan(self, start: ArrayLike) -> Path:
        """A path from ``start`` (x, y) to the goal."""
    def plan_exact(self, start: ArrayLike) -> Path:
        """The exact (triangle-to-triangle) tracer's path."""
    def plan_many(self, starts: ArrayLike) -> List[Path]:
        """Paths from every row of ``starts`` (n, 2), in parallel, same order."""
    def potential(self, points: ArrayLike) -> FloatArray:
        """phi at points (m, 2) -> (m,), NaN outside free space."""
    def psi(self, points: ArrayLike) -> FloatArray:
        """psi = reference - phi at points (m, 2) -> (m,), accurate when tiny."""
    def gradient(self, points: ArrayLike, *, smooth: bool = False) -> FloatArray:
        """grad phi at points (m, 2) -> (m, 2), NaN outside free space."""
    def mesh(self) -> Tuple[FloatArray, IntArray]:
        """(vertices (V, 2) float64, triangles (T, 3) int64)."""
    def phi_at_vertices(self) -> FloatArray:
        """phi at every mesh vertex, (V,)."""
    def psi_at_vertices(self) -> FloatArray:
        """psi at every mesh vertex, (V,)."""
    @property
    def reference(self) -> float:
        """The walls' value c (psi = c - phi)."""
    @property
    def solved_by(self) -> str:
        """What produced psi, as ``hplan plan --json`` says in ``potential.solved_by``."""
    @property
    def timings(self) -> Dict[str, float]:
        """Milliseconds: {"mesh", "assemble", "solve"}."""
    @property
    def source(self) -> Optional[str]: ...
    def drive(
        self,
        pose: ArrayLike,
        *,
        wheelbase: Optional[float] = None,
        max_steer_deg: float = 35.0,
        step: Optional[float] = None,
        check_footprint: bool = False,
    ) -> CarRun:
        """Drives a car-like robot from ``pose`` (x, y, theta) along the potential."""

class VolumePlanner:
    """A planner for one volume scene (``"dimension": 3``); points have shape (n, 3)."""

    def __init__(self, scene: Scene, *, max_volume: Optional[float] = None) -> None: ...
    def plan(self, start: ArrayLike) -> Path: ...
    def plan_many(self, starts: ArrayLike) -> List[Path]: ...
    def potential(self, points: ArrayLike) -> FloatArray: ...
    def psi(self, points: ArrayLike) -> FloatArray: ...
    def gradient(self, points: ArrayLike) -> FloatArray: ...
    def mesh(self) -> Tuple[FloatArray, IntArray]:
        """(vertices (V, 3) float64, tetrahedra (T, 4) int64)."""
    def phi_at_vertices(self) -> FloatArray: ...
    @property
    def solved_by(self) -> str:
        """What produced psi, as ``hplan plan --json`` says in ``potential.solved_by``."""
    @property
    def timings(self) -> Dict[str, float]: ...
    @property
    def source(self) -> Optional[str]: ...

class ConfigPlanner:
    """A polygon robot (``"robot": {"polygon": ...}``, configurations ``[x, y, theta]``) or a
    planar arm (``"robot": {"arm": ...}``, joint angles) planned in its configuration space.
    A path's ``points`` are configurations, shape (n, dof); every motion between two of them
    is checked against the robot's exact geometry."""

    def __init__(self, scene: Scene) -> None:
        """Meshes the free configurations, assembles and solves (the GIL is released)."""
    def plan(self, start: ArrayLike) -> Path: ...
    def plan_many(self, starts: ArrayLike) -> List[Path]: ...
    def report_json(self, starts: ArrayLike) -> str:
        """``hplan plan --json``'s report for ``starts``: mesh, timings, potential, paths."""
    def summary(self, starts: ArrayLike) -> str:
        """``hplan plan``'s text summary for ``starts``."""
    def svg(self, paths: List[Path]) -> str:
        """The scene with the robot drawn along each path."""
    @property
    def dof(self) -> int: ...
    @property
    def configuration(self) -> str:
        """``"pose"`` (a polygon robot) or ``"joints"`` (an arm)."""
    @property
    def solved_by(self) -> str:
        """What produced psi, as ``hplan plan --json`` says in ``potential.solved_by``."""
    @property
    def timings(self) -> Dict[str, float]: ...
    @property
    def source(self) -> Optional[str]: ...

class Workspace:
    """A plane scene (or map) meshed without its goals and its walls factored once; a
    ``Planner`` for any goal afterwards, by a few triangular solves (milliseconds)."""

    def __init__(self, scene: Scene, *, max_area: Optional[float] = None) -> None:
        """Meshes, assembles and factors (the GIL is released). The scene's goals are
        ignored; its goal condition must be Dirichlet (the default)."""
    @staticmethod
    def from_map(
        yaml: StrPath,
        around: ArrayLike,
        robot_radius: float = 0.0,
        *,
        max_area: Optional[float] = None,
    ) -> "Workspace":
        """A workspace on a ROS map_server map: the free area holding ``around``."""
    def planner(self, goal: ArrayLike, *, radius: float = 0.0) -> Planner:
        """A planner towards ``goal`` (x, y); paths end exactly on it."""
    def planners(self, goals: ArrayLike) -> List[Planner]:
        """One planner per goal of an (n, 2) array, solved together."""
    def planner_for_any(self, goals: ArrayLike) -> Planner:
        """One planner whose goal is the set: ``Path.goal`` says which was reached."""
    @property
    def timings(self) -> Dict[str, float]:
        """Milliseconds: ``mesh``, ``assemble``, ``factor`` (once for every goal)."""
    @property
    def triangles(self) -> int: ...
