"""ROS maps, the car-like robot, volume scenes and the GIL."""

import math
import pathlib
import threading
import time

import numpy as np
import pytest

import harmonic_planner as hp

ROOT = pathlib.Path(__file__).resolve().parents[2]
WAREHOUSE = ROOT / "meshes" / "warehouse_map.yaml"
GOAL = (16.5, 1.5)


def blocked_cells():
    """Centres of the occupied and unknown cells of the warehouse map, read from its PGM
    (trinary mode, negate 0: occupancy (255 - v) / 255; free below 0.196)."""
    data = (ROOT / "meshes" / "warehouse_map.pgm").read_bytes()
    fields = data.split(maxsplit=4)
    assert fields[0] == b"P5"
    width, height, maxval = int(fields[1]), int(fields[2]), int(fields[3])
    pixels = np.frombuffer(fields[4][-width * height:], dtype=np.uint8).reshape(height, width)
    occupancy = (maxval - pixels.astype(float)) / maxval
    rows, cols = np.nonzero(occupancy >= 0.196)
    res, x0, y0 = 0.05, -2.0, -1.5
    # Image row 0 is the top of the map.
    return np.column_stack([x0 + (cols + 0.5) * res, y0 + (height - rows - 0.5) * res]), res


def distance_to_cells(points, cells, res):
    d = np.abs(points[:, None, :] - cells[None, :, :]) - res / 2
    return np.sqrt((np.clip(d, 0, None) ** 2).sum(axis=2)).min(axis=1)


@pytest.fixture(scope="module")
def warehouse():
    return hp.Planner.from_map(WAREHOUSE, goal=GOAL, robot_radius=0.2)


def test_from_map(warehouse):
    assert warehouse.source == str(WAREHOUSE)
    vertices, triangles = warehouse.mesh()
    # The map spans x in [-2, 18], y in [-1.5, 13.5] (400 x 300 cells of 5 cm).
    assert vertices[:, 0].min() >= -2.0 and vertices[:, 0].max() <= 18.0
    assert vertices[:, 1].min() >= -1.5 and vertices[:, 1].max() <= 13.5
    # Starts of the Rust map tests: reachable ones reach the goal, the closed closet does not.
    cells, res = blocked_cells()
    assert len(cells) > 1000
    reachable = [[-0.75, -0.5], [3.0, 4.0], [7.0, 12.0], [13.0, 8.5]]
    for path in warehouse.plan_many(reachable):
        assert path.status == "reached_goal", path
        end = path.points[-1]
        assert math.hypot(end[0] - GOAL[0], end[1] - GOAL[1]) < 0.5
        # A start the tracing margin leaves out is led in over clear cells (clearance 0 on
        # that stretch, which lies outside the meshed configuration space).
        assert path.min_clearance >= 0
        # Checked against the map's own cells: the disc of radius 0.2 stays off every occupied
        # or unknown cell (exactly: the cells were cleared on the grid; to rounding here).
        assert distance_to_cells(path.points, cells, res).min() >= 0.2 - 1e-9
    # The closed closet: clear cells with no way to the goal.
    assert warehouse.plan([16.4, 11.8]).status == "unreachable"
    # The patch seen through a window: too close to its walls for the radius.
    assert warehouse.plan([0.25, -1.3]).status == "start_in_obstacle"
    assert set(warehouse.timings) == {"mesh", "assemble", "solve"}


def test_drive(planner, reference_dict):
    run = planner.drive([1.0, 9.0, 0.0], wheelbase=0.5, max_steer_deg=35.0)
    poses = run.poses
    assert poses.ndim == 2 and poses.shape[1] == 3 and len(poses) == len(run) > 10
    np.testing.assert_allclose(poses[0], [1.0, 9.0, 0.0])
    assert run.start == [1.0, 9.0, 0.0]
    assert run.status == "reached_goal", run
    # It ends when the rear axle or the front-axle midpoint (L ahead) enters the goal circle.
    x, y, theta = poses[-1]
    rear = math.hypot(x - 8.5, y - 1.5)
    front = math.hypot(x + 0.5 * math.cos(theta) - 8.5, y + 0.5 * math.sin(theta) - 1.5)
    assert min(rear, front) <= 0.15 + 0.02, (rear, front)
    obstacles = [o["polygon"] for o in reference_dict["obstacles"]]
    from test_geometry import inside
    for p in poses:
        assert not any(inside(p[:2], o) for o in obstacles)
    # Curvature bounded by the steering limit.
    assert run.max_curvature <= math.tan(math.radians(35.0)) / 0.5 + 1e-9
    assert run.length > 0 and run.min_clearance > 0
    # Defaults as the command line's.
    assert planner.drive((1.0, 9.0, -1.0)).poses.shape[1] == 3


BOX_SCENE = {
    "dimension": 3,
    "workspace": {"box": {"min": [0, 0, 0], "max": [4, 2, 2]}},
    "obstacles": [{"box": {"min": [1.5, -1, -1], "max": [2.5, 1.2, 3]}}],
    "goal": {"sphere": {"center": [3.5, 1, 1], "radius": 0.3}},
    "mesh": {"max_volume": 0.004},
}


def test_volume_planner():
    scene = hp.Scene.from_dict(BOX_SCENE)
    assert scene.dimension == 3
    planner = hp.VolumePlanner(scene)
    path = planner.plan([0.5, 1.0, 1.0])
    assert path.status == "reached_goal"
    pts = path.points
    assert pts.shape[1] == 3
    # Around the wall through the gap beside it (y > 1.2), never inside the wall's box.
    assert np.any(pts[:, 1] > 1.2)
    in_wall = (pts[:, 0] > 1.5) & (pts[:, 0] < 2.5) & (pts[:, 1] < 1.2)
    assert not np.any(in_wall)
    assert np.linalg.norm(pts[-1] - [3.5, 1, 1]) <= 0.3 + 1e-6
    many = planner.plan_many([[0.5, 1.0, 1.0], [0.5, 0.5, 0.5]])
    np.testing.assert_array_equal(many[0].points, pts)
    phi = planner.potential([[0.5, 1.0, 1.0], [2.0, 0.5, 1.0], [9.0, 9.0, 9.0]])
    assert phi.shape == (3,) and 0 <= phi[0] <= 1 and np.isnan(phi[1]) and np.isnan(phi[2])
    np.testing.assert_allclose(planner.psi([[0.5, 1.0, 1.0]]), 1 - phi[:1], atol=1e-12)
    assert planner.gradient([[0.5, 1.0, 1.0]]).shape == (1, 3)
    vertices, tets = planner.mesh()
    assert vertices.shape[1] == 3 and tets.shape[1] == 4 and tets.dtype == np.int64
    assert tets.min() >= 0 and tets.max() < len(vertices)
    assert planner.phi_at_vertices().shape == (len(vertices),)
    with pytest.raises(hp.SceneError, match=r"expected an array of shape \(m, 3\), got shape \(1, 2\)"):
        planner.potential([[1.0, 1.0]])
    assert planner.plan([0.5, 1.0, 1.0]).status == "reached_goal"


def test_builds_release_the_gil(reference_path):
    scene = hp.Scene.from_file(reference_path)
    count = 0
    stop = threading.Event()

    def spin():
        nonlocal count
        while not stop.is_set():
            count += 1

    thread = threading.Thread(target=spin)
    thread.start()
    try:
        time.sleep(0.05)
        before = count
        hp.Planner(scene)  # ~0.1 s or more of meshing, assembly and factoring
        during = count - before
    finally:
        stop.set()
        thread.join()
    # With the GIL held for the whole build the other thread could not count at all.
    assert during > 1000


def test_pose_goal_headings(warehouse):
    path = warehouse.plan([3.0, 4.0])
    poses = path.poses(start_heading=-0.5, goal_heading=1.25)
    assert poses.shape == (len(path), 3)
    np.testing.assert_array_equal(poses[:, :2], path.points)
    assert poses[0, 2] == -0.5 and poses[-1, 2] == 1.25
    # In between, each pose heads along the segment leaving it.
    d = np.diff(path.points, axis=0)
    along = np.arctan2(d[:, 1], d[:, 0])
    moving = np.hypot(d[:, 0], d[:, 1]) > 1e-12
    np.testing.assert_allclose(poses[1:-1, 2][moving[1:]], along[1:][moving[1:]], atol=1e-12)


def test_graded_costs_turn_paths_away_by_weight():
    """The bundled scale map: a short route above a block through a costly band, a longer
    one below. Of seven starts down the left wall, fewer cross the band as cost_weight
    grows (the same counts as the Rust test), and none at weight 4."""
    band = ROOT / "meshes" / "costly_band.yaml"
    starts = [[0.5, 0.5 * k] for k in range(1, 8)]
    through = []
    for weight in (0.0, 1.0, 4.0):
        planner = hp.Planner.from_map(band, goal=(7.5, 2.0), cost_weight=weight)
        above = 0
        for path in planner.plan_many(starts):
            assert path.status == "reached_goal"
            over = path.points[(path.points[:, 0] >= 3.0) & (path.points[:, 0] <= 5.0)]
            above += bool(np.all(over[:, 1] > 2.9))
        through.append(above)
    assert through == sorted(through, reverse=True) and through[-1] == 0, through
    with pytest.raises(hp.SceneError, match="cost_weight"):
        hp.Planner.from_map(band, goal=(7.5, 2.0), cost_weight=-1.0)


def test_threads_option_plans_the_same_paths(reference_path):
    """``threads``: the build and ``plan_many`` on one core or two give the same paths;
    zero threads is a SceneError naming the count."""
    scene = hp.Scene.from_file(reference_path)
    starts = [[1.0, 9.0], [1.0, 1.0]]
    one = hp.Planner(scene, max_area=0.01, threads=1).plan_many(starts)
    two = hp.Planner(scene, max_area=0.01, threads=2).plan_many(starts)
    for a, b in zip(one, two):
        assert a.status == b.status
        assert abs(a.length - b.length) <= 1e-9 * max(a.length, 1.0)
    band = ROOT / "meshes" / "costly_band.yaml"
    lengths = [
        [p.length for p in hp.Planner.from_map(band, goal=(7.5, 2.0), threads=n).plan_many(starts[:1])]
        for n in (1, 2)
    ]
    assert abs(lengths[0][0] - lengths[1][0]) <= 1e-9 * lengths[0][0]
    with pytest.raises(hp.SceneError, match="0 threads"):
        hp.Planner(scene, threads=0)
