"""Any goal from one factorisation: hp.Workspace."""

import pathlib

import numpy as np
import pytest

import harmonic_planner as hp

ROOT = pathlib.Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "meshes" / "reference.json"
WAREHOUSE = ROOT / "meshes" / "warehouse_map.yaml"


@pytest.fixture(scope="module")
def workspace():
    return hp.Workspace(hp.Scene.from_file(REFERENCE), max_area=0.05)


def test_each_goal_gets_a_planner_whose_paths_end_on_it(workspace):
    assert workspace.timings["factor"] > 0
    assert workspace.triangles > 1000
    for goal in [(8.5, 1.5), (1.0, 1.0), (9.0, 9.0)]:
        path = workspace.planner(goal).plan([4.0, 5.5])
        assert path.reached_goal, path.status
        np.testing.assert_array_equal(path.points[-1], goal)


def test_several_goals_together_and_a_goal_set(workspace):
    goals = np.array([[8.5, 1.5], [1.0, 1.0], [9.0, 9.0]])
    planners = workspace.planners(goals)
    assert len(planners) == 3
    for goal, planner in zip(goals, planners):
        np.testing.assert_array_equal(planner.plan([4.0, 5.5]).points[-1], goal)
    anyone = workspace.planner_for_any(goals)
    path = anyone.plan([1.2, 1.1])
    assert path.goal == 1, path.goal
    np.testing.assert_array_equal(path.points[-1], goals[1])


def test_bad_goals_raise_scene_errors(workspace):
    with pytest.raises(hp.SceneError, match="not in the free space"):
        workspace.planner((2.5, 5.0))
    with pytest.raises(hp.SceneError, match="finite"):
        workspace.planner((float("nan"), 1.0))
    with pytest.raises(hp.SceneError, match="radius"):
        workspace.planner((1.0, 1.0), radius=-1.0)


def test_a_workspace_on_a_map():
    ws = hp.Workspace.from_map(WAREHOUSE, around=(16.5, 1.5), robot_radius=0.2)
    for goal in [(16.5, 1.5), (3.0, 4.0)]:
        path = ws.planner(goal).plan([13.0, 8.5])
        assert path.reached_goal, path.status
    assert "warehouse_map.yaml" in repr(ws)
