"""The issue's contract snippet, as written, run from the repository root."""

import os
import pathlib

import numpy as np
import pytest

import harmonic_planner as hp

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)


def test_contract_snippet(at_root):
    scene = hp.Scene.from_file("meshes/reference.json")
    planner = hp.Planner(scene)
    path = planner.plan([1.0, 9.0])
    assert path.status == "reached_goal"
    assert isinstance(path.points, np.ndarray)
    assert path.points.ndim == 2 and path.points.shape[1] == 2
    assert path.points.dtype == np.float64
    assert path.length > 0 and path.min_clearance > 0 and path.min_gradient > 0
    paths = planner.plan_many(np.array([[1.0, 9.0], [9.0, 9.0]]))
    assert isinstance(paths, list) and len(paths) == 2
    assert [p.status for p in paths] == ["reached_goal", "reached_goal"]

    phi = planner.potential(np.array([[8.0, 3.0], [1.0, 9.0]]))
    assert phi.shape == (2,)
    points = np.array([[8.0, 3.0], [1.0, 9.0]])
    psi = planner.psi(points)
    grad = planner.gradient(points)
    assert psi.shape == (2,) and grad.shape == (2, 2)
    vertices, triangles = planner.mesh()
    assert vertices.dtype == np.float64 and vertices.shape[1] == 2
    assert triangles.dtype == np.int64 and triangles.shape[1] == 3
    assert set(planner.timings) == {"mesh", "assemble", "solve"}
    assert all(v >= 0 for v in planner.timings.values())

    planner = hp.Planner.from_map(
        "meshes/warehouse_map.yaml", goal=(16.5, 1.5), robot_radius=0.2
    )
    run = hp.Planner(scene).drive([1.0, 9.0, 0.0], wheelbase=0.5, max_steer_deg=35.0)
    assert run.poses.ndim == 2 and run.poses.shape[1] == 3


def test_scene_constructors_agree(reference_path, reference_dict):
    a = hp.Scene.from_file(reference_path)
    b = hp.Scene.from_json(reference_path.read_text())
    c = hp.Scene.from_dict(reference_dict)
    assert a.to_dict() == b.to_dict() == c.to_dict()
    assert a.dimension == 2 and a.name == "reference"
    assert a.source == str(reference_path) and b.source is None
    np.testing.assert_array_equal(a.starts, [[1.0, 9.0]])


def test_docstrings_for_help():
    for obj in (hp.Scene, hp.Planner, hp.Planner.plan, hp.Planner.potential, hp.Path,
                hp.VolumePlanner, hp.SceneError, hp.Planner.from_map, hp.Planner.drive):
        assert obj.__doc__ and len(obj.__doc__) > 20, obj
    assert issubclass(hp.SceneError, ValueError)
    stubs = pathlib.Path(hp.__file__).with_name("_native.pyi")
    assert stubs.exists() and "Not bound yet" in stubs.read_text()
    assert pathlib.Path(hp.__file__).with_name("py.typed").exists()


def test_paths_are_printable(planner):
    path = planner.plan([1.0, 9.0])
    assert "reached_goal" in repr(path)
    assert len(path) == path.points.shape[0]
    assert "Planner(" in repr(planner)
    assert os.fspath(hp.Scene.from_file(ROOT / "meshes" / "reference.json").source)


def test_multigrid_plans_the_same_path(reference_path):
    scene = hp.Scene.from_file(reference_path)
    direct = hp.Planner(scene, max_area=0.004)
    refined = hp.Planner(scene, max_area=0.004, multigrid=2)
    for start in ([1.0, 1.0], [1.0, 9.0]):
        a, b = direct.plan(start), refined.plan(start)
        assert a.reached_goal and b.reached_goal
        assert abs(a.length - b.length) <= 5e-3 * a.length
    # 0 is the direct solve on the scene's own mesh: the same path as the default below
    # 100 000 estimated triangles.
    direct0 = hp.Planner(scene, max_area=0.004, multigrid=0)
    assert direct0.plan([1.0, 1.0]).length == direct.plan([1.0, 1.0]).length
    assert "multigrid" in refined.solved_by
    with pytest.raises(hp.SceneError, match="multigrid must be 0 to 8"):
        hp.Planner(scene, multigrid=9)
