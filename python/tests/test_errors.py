"""Bad input raises hp.SceneError (a ValueError) with the command line's one-line message,
and a planner already built keeps answering afterwards."""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import harmonic_planner as hp

ROOT = pathlib.Path(__file__).resolve().parents[2]

SQUARE = [[0, 0], [10, 0], [10, 10], [0, 10]]


def scene(**fields):
    d = {"workspace": SQUARE, "goal": {"circle": {"center": [8, 8], "radius": 0.3}}}
    d.update(fields)
    return d


BOW_TIE = scene(obstacles=[{"polygon": [[2, 2], [4, 4], [4, 2], [2, 4]]}])
GOAL_IN_OBSTACLE = scene(
    obstacles=[{"polygon": [[2, 2], [4, 2], [4, 4], [2, 4]]}],
    goal={"circle": {"center": [3, 3], "radius": 0.3}},
)


def raises(fn, *args, **kwargs):
    with pytest.raises(hp.SceneError) as info:
        fn(*args, **kwargs)
    message = str(info.value)
    assert "\n" not in message, message
    assert isinstance(info.value, ValueError)
    return message


def still_answers(planner):
    assert planner.plan([1.0, 9.0]).status == "reached_goal"
    assert planner.potential([[1.0, 9.0]]).shape == (1,)


def test_malformed_json(tmp_path, planner):
    assert raises(hp.Scene.from_json, '{"workspace": [[0,0],') == (
        "workspace: line 1, column 21: EOF while parsing a value"
    )
    bad = tmp_path / "bad.json"
    bad.write_text('{"workspace": [[0,0],')
    assert raises(hp.Scene.from_file, bad) == (
        f"{bad}: workspace: line 1, column 21: EOF while parsing a value"
    )
    assert "a scene is a JSON object" in raises(hp.Scene.from_json, "[1, 2]")
    still_answers(planner)


def test_unknown_field(planner):
    message = raises(hp.Scene.from_json, json.dumps(scene(colour=3)))
    assert message.startswith("colour: line 1, column ")
    assert "unknown field `colour`, expected one of `name`, `workspace`" in message
    message = raises(hp.Scene.from_dict, scene(colour=3))
    assert "unknown field `colour`" in message
    still_answers(planner)


def test_missing_file(tmp_path):
    missing = tmp_path / "nonexist.json"
    assert raises(hp.Scene.from_file, missing) == (
        f"{missing}: cannot read {missing}: No such file or directory (os error 2)"
    )


def test_self_intersecting_polygon(tmp_path, planner):
    s = hp.Scene.from_dict(BOW_TIE)
    assert raises(hp.Planner, s) == "obstacle 0: polygon self-intersects (edges 0 and 2)"
    f = tmp_path / "bow.json"
    f.write_text(json.dumps(BOW_TIE))
    assert raises(hp.Planner, hp.Scene.from_file(f)) == (
        f"{f}: obstacle 0: polygon self-intersects (edges 0 and 2)"
    )
    still_answers(planner)


def test_goal_inside_obstacle(planner):
    assert raises(hp.Planner, hp.Scene.from_dict(GOAL_IN_OBSTACLE)) == (
        "goal 0: lies inside obstacle 0 (after inflating obstacles by the robot radius)"
    )
    still_answers(planner)


def test_not_json_serialisable_dict():
    raises(hp.Scene.from_dict, scene(robot={"radius": float("nan")}))
    raises(hp.Scene.from_dict, {"workspace": object()})


@pytest.mark.parametrize(
    "call, fragment",
    [
        (lambda p: p.potential(np.zeros((4, 3))), "points: expected an array of shape (m, 2), got shape (4, 3)"),
        (lambda p: p.potential(np.zeros(2)), "points: expected an array of shape (m, 2), got shape (2,)"),
        (lambda p: p.psi(np.zeros((2, 2, 2))), "points: expected an array of shape (m, 2), got shape (2, 2, 2)"),
        (lambda p: p.gradient([[1.0]]), "points: expected an array of shape (m, 2), got shape (1, 1)"),
        (lambda p: p.potential("abc"), "points: expected an array of shape (m, 2)"),
        (lambda p: p.potential([[1, 2], [3]]), "points: expected an array of shape (m, 2)"),
        (lambda p: p.plan([1.0, 2.0, 3.0]), "start: expected an array of shape (2,), got shape (3,)"),
        (lambda p: p.plan([[1.0, 9.0]]), "start: expected an array of shape (2,), got shape (1, 2)"),
        (lambda p: p.plan([float("nan"), 9.0]), "start: coordinates must be finite numbers"),
        (lambda p: p.plan_many(np.zeros((3, 3))), "starts: expected an array of shape (m, 2), got shape (3, 3)"),
        (lambda p: p.plan_many([[1.0, float("inf")]]), "starts: coordinates must be finite numbers"),
        (lambda p: p.drive([1.0, 9.0]), "pose: expected an array of shape (3,), got shape (2,)"),
        (lambda p: p.drive([1.0, 9.0, 0.0], max_steer_deg=120.0), "option `max_steer` = 2.0943951023931953 is invalid: must lie in (0, π/2) radians"),
        (lambda p: p.drive([1.0, 9.0, 0.0], wheelbase=-1.0), "wheelbase"),
    ],
)
def test_bad_arguments(planner, call, fragment):
    message = raises(call, planner)
    assert fragment in message, message
    still_answers(planner)


def test_bad_options(reference_path):
    s = hp.Scene.from_file(reference_path)
    assert raises(hp.Planner, s, max_area=-1.0) == "max_area must be a positive number, got -1"
    assert "not volumes" in raises(hp.Planner, hp.Scene.from_file(ROOT / "meshes" / "torus3d.json"))
    assert "use Planner" in raises(hp.VolumePlanner, s)


def test_bad_maps(tmp_path):
    yaml = ROOT / "meshes" / "warehouse_map.yaml"
    message = raises(hp.Planner.from_map, yaml, goal=(100.0, 100.0))
    assert message.startswith("goal (100, 100) is outside the map (") and str(yaml) in message
    missing = tmp_path / "none.yaml"
    assert "cannot read" in raises(hp.Planner.from_map, missing, goal=(1.0, 1.0))
    assert "shape (2,)" in raises(hp.Planner.from_map, yaml, goal=(1.0, 1.0, 1.0))


def hplan():
    for candidate in (os.environ.get("HPLAN"), ROOT / "target" / "release" / "hplan",
                      ROOT / "target" / "debug" / "hplan"):
        if candidate and pathlib.Path(candidate).is_file():
            return str(candidate)
    return None


@pytest.mark.skipif(hplan() is None, reason="no hplan binary built (cargo build -p hplan)")
@pytest.mark.parametrize("content", [
    '{"workspace": [[0,0],',
    json.dumps(scene(colour=3)),
    json.dumps(BOW_TIE),
    json.dumps(GOAL_IN_OBSTACLE),
])
def test_same_message_as_the_command_line(tmp_path, content):
    f = tmp_path / "scene.json"
    f.write_text(content)
    cli = subprocess.run([hplan(), "plan", str(f), "--start", "1,1"], capture_output=True, text=True)
    assert cli.returncode != 0
    expected = cli.stderr.strip()
    assert expected.startswith("hplan: ")
    with pytest.raises(hp.SceneError) as info:
        hp.Planner(hp.Scene.from_file(f))
    assert "hplan: " + str(info.value) == expected


def test_a_panic_becomes_a_scene_error(planner):
    from harmonic_planner import _native

    assert raises(_native._panic_at_the_boundary) == "internal error: a deliberate panic"
    still_answers(planner)
