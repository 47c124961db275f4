"""Local-minimum-free robot path planning with harmonic potentials.

The potential phi solves Laplace's equation on the free space (walls and obstacles held
high, the goal low) with P1 finite elements on a constrained Delaunay mesh; paths follow it
downhill and cannot get stuck in a local minimum. Everything heavy (meshing, assembly,
factorisation) happens once in ``Planner(scene)``; queries reuse it.

>>> import harmonic_planner as hp                                   # doctest: +SKIP
>>> planner = hp.Planner(hp.Scene.from_file("meshes/reference.json"))  # doctest: +SKIP
>>> planner.plan([1.0, 9.0]).status                                  # doctest: +SKIP
'reached_goal'

Classes: Scene, Planner, VolumePlanner, Path, CarRun; exception: SceneError (a ValueError).
Not bound yet: configuration-space robots and any-goal workspaces (planned in the Rust
crate, not there yet); moving obstacles (harmonic-dynamic), the baseline planners, SVG and
VTK export.
"""

from ._native import (
    CarRun,
    Path,
    Planner,
    Scene,
    SceneError,
    VolumePlanner,
    __version__,
)

__all__ = [
    "CarRun",
    "Path",
    "Planner",
    "Scene",
    "SceneError",
    "VolumePlanner",
    "__version__",
]
