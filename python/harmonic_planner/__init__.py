"""Local-minimum-free robot path planning with harmonic potentials.

The potential phi solves Laplace's equation on the free space (walls and obstacles held
high, the goal low) with P1 finite elements on a constrained Delaunay mesh; paths follow it
downhill and cannot get stuck in a local minimum. Everything heavy (meshing, assembly,
factorisation) happens once in ``Planner(scene)``; queries reuse it.

>>> import harmonic_planner as hp                                   # doctest: +SKIP
>>> planner = hp.Planner(hp.Scene.from_file("meshes/reference.json"))  # doctest: +SKIP
>>> planner.plan([1.0, 9.0]).status                                  # doctest: +SKIP
'reached_goal'

Classes: Scene, Planner, Workspace (any goal from one factorisation), VolumePlanner,
ConfigPlanner (polygon robots and arms, in their configuration space), Path, CarRun;
exception: SceneError (a ValueError). Not bound yet: moving obstacles (harmonic-dynamic), the
baseline planners, VTK export.
"""

from ._native import (
    CarRun,
    ConfigPlanner,
    Path,
    Planner,
    Scene,
    SceneError,
    VolumePlanner,
    Workspace,
    __version__,
)

__all__ = [
    "CarRun",
    "ConfigPlanner",
    "Path",
    "Planner",
    "Scene",
    "SceneError",
    "VolumePlanner",
    "Workspace",
    "__version__",
]
