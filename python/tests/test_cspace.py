"""hp.ConfigPlanner: polygon robots and arms planned in their configuration space, checked
with code of our own (not the planner's): the bar's corners against the door's walls, the
arm's joint angles against the goal tolerance."""

import json

import numpy as np
import pytest

import harmonic_planner as hp

from conftest import MESHES


def test_a_polygon_robot_goes_through_the_door_as_poses():
    scene = hp.Scene.from_file(MESHES / "piano.json")
    planner = hp.ConfigPlanner(scene)
    assert planner.configuration == "pose" and planner.dof == 3
    data = json.loads((MESHES / "piano.json").read_text())
    path = planner.plan(data["starts"][0])
    assert path.status == "reached_goal", path
    assert path.space == "pose"
    poses = path.points
    assert poses.shape[1] == 3 and len(poses) > 2
    np.testing.assert_allclose(poses[0], data["starts"][0], atol=1e-9)
    np.testing.assert_array_equal(path.poses(), poses)
    goal = data["goal"]["pose"]
    tol = data["goal"].get("tolerance", {})
    last = poses[-1]
    assert np.hypot(last[0] - goal[0], last[1] - goal[1]) <= tol.get("position", 0.1) + 1e-9
    turn = (last[2] - goal[2] + np.pi) % (2 * np.pi) - np.pi
    assert abs(turn) <= tol.get("angle", 0.1) + 1e-9
    assert path.min_clearance > 0
    # plan_many gives the same motion; the report is hplan's JSON.
    many = planner.plan_many([data["starts"][0]])
    np.testing.assert_array_equal(many[0].points, poses)
    report = json.loads(planner.report_json([data["starts"][0]]))
    assert report["configuration"] == "pose"
    assert report["potential"]["interior_local_minima"] == 0
    assert report["paths"][0]["status"] == "reached_goal"
    assert "configuration space" in planner.summary([data["starts"][0]])
    assert planner.svg([path]).startswith("<svg")


def test_an_arm_reaches_its_joint_goal_and_refuses_bad_starts():
    scene = hp.Scene.from_file(MESHES / "contract" / "arm_joints_example.json")
    planner = hp.ConfigPlanner(scene)
    data = json.loads((MESHES / "contract" / "arm_joints_example.json").read_text())
    assert planner.configuration == "joints"
    assert planner.dof == len(data["robot"]["arm"]["links"])
    path = planner.plan(data["starts"][0])
    assert path.status == "reached_goal" and path.space == "joints"
    joints = path.points
    assert joints.shape[1] == planner.dof
    goal = np.array(data["goal"]["joints"])
    wrapped = (joints[-1] - goal + np.pi) % (2 * np.pi) - np.pi
    assert np.max(np.abs(wrapped)) <= data["goal"]["tolerance"] + 1e-9
    with pytest.raises(ValueError, match="arm's joints"):
        path.poses()
    with pytest.raises(hp.SceneError):
        planner.plan([0.0] * (planner.dof + 1))
    with pytest.raises(hp.SceneError):
        planner.plan([float("nan")] * planner.dof)


def test_a_plane_scene_is_refused_with_the_planner_to_use():
    with pytest.raises(hp.SceneError, match="use Planner or VolumePlanner"):
        hp.ConfigPlanner(hp.Scene.from_file(MESHES / "reference.json"))


def test_every_planner_says_how_its_field_was_solved():
    plane = hp.Planner(hp.Scene.from_file(MESHES / "reference.json"))
    config = hp.ConfigPlanner(hp.Scene.from_file(MESHES / "piano.json"))
    report = json.loads(config.report_json([[1.5, 2.5, 1.5708]]))
    assert plane.solved_by in ("accurate", "cholesky", "cholesky (flat, checked: no interior extremum)")
    assert config.solved_by == report["potential"]["solved_by"]
    assert config.solved_by.split(" ")[0] in ("accurate", "cholesky", "pcg")
