"""Paths, potential, gradient and mesh checked against the scene's own geometry (read from
meshes/reference.json here, with point-in-polygon and distances written in this file)."""

import math

import numpy as np
import pytest

import harmonic_planner as hp

GOAL_CENTER = (8.5, 1.5)
GOAL_RADIUS = 0.15  # the goal polygon of reference.json is a 16-gon inscribed in this circle


def inside(point, polygon):
    """Even-odd ray casting: is `point` strictly inside `polygon` (a list of [x, y])?"""
    x, y = point
    result = False
    n = len(polygon)
    for i in range(n):
        (x0, y0), (x1, y1) = polygon[i], polygon[(i + 1) % n]
        if (y0 > y) != (y1 > y):
            xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
            if xc > x:
                result = not result
    return result


def segment_distance(p, a, b):
    px, py = p
    ax, ay = a
    bx, by = b
    dx, dy = bx - ax, by - ay
    t = ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)
    t = min(1.0, max(0.0, t))
    return math.hypot(px - (ax + t * dx), py - (ay + t * dy))


def polygon_distance(p, polygon):
    n = len(polygon)
    return min(segment_distance(p, polygon[i], polygon[(i + 1) % n]) for i in range(n))


def shoelace(polygon):
    n = len(polygon)
    return 0.5 * abs(
        sum(polygon[i][0] * polygon[(i + 1) % n][1] - polygon[(i + 1) % n][0] * polygon[i][1]
            for i in range(n))
    )


@pytest.fixture(scope="module")
def obstacles(reference_dict):
    return [o["polygon"] for o in reference_dict["obstacles"]]


@pytest.fixture(scope="module")
def workspace(reference_dict):
    return reference_dict["workspace"]


def test_self_check_of_point_in_polygon():
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    assert inside((0.5, 0.5), square) and not inside((1.5, 0.5), square)
    l_shape = [[5.5, 1.0], [7.0, 1.0], [7.0, 3.0], [6.5, 3.0], [6.5, 1.5], [5.5, 1.5]]
    assert inside((6.8, 2.5), l_shape) and not inside((6.0, 2.5), l_shape)


STARTS = [[1.0, 9.0], [9.0, 9.0], [0.5, 0.5], [4.0, 5.0], [9.5, 6.0], [6.0, 2.5]]


@pytest.mark.parametrize("start", STARTS)
def test_paths_stay_in_free_space_and_end_in_goal(planner, obstacles, workspace, start):
    path = planner.plan(start)
    assert path.status == "reached_goal", path
    assert path.reached_goal and path.goal == 0
    pts = path.points
    assert pts.shape[0] >= 2
    np.testing.assert_allclose(pts[0], start, atol=1e-12)
    end_distance = math.hypot(pts[-1][0] - GOAL_CENTER[0], pts[-1][1] - GOAL_CENTER[1])
    assert end_distance <= GOAL_RADIUS + 1e-6
    for p in pts:
        assert inside(p, workspace), p
        for k, obstacle in enumerate(obstacles):
            assert not inside(p, obstacle), (p, k)
    clearance = min(polygon_distance(p, poly) for p in pts for poly in obstacles + [workspace])
    assert clearance > 0
    # The reported clearance covers whole segments, so it is at most the vertices' clearance.
    assert 0 < path.min_clearance <= clearance + 1e-9
    steps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert path.length == pytest.approx(steps.sum(), rel=1e-9)
    # Downhill: phi at the end is below phi at the start.
    phi = planner.potential(pts[[0, -1]])
    assert phi[1] < phi[0]


def test_potential_is_nan_outside_free_space(planner, obstacles):
    outside = np.array([
        [2.5, 5.0],   # in the tall obstacle
        [7.0, 4.5],   # in the bar
        [5.5, 7.5],   # in the triangle
        [6.8, 2.5],   # in the L
        [-1.0, 5.0],  # left of the workspace
        [5.0, 10.5],  # above it
        [np.nan, 1.0],
    ])
    assert any(inside(outside[0], o) for o in obstacles)
    phi = planner.potential(outside)
    assert phi.shape == (len(outside),)
    assert np.all(np.isnan(phi))
    assert np.all(np.isnan(planner.psi(outside)))
    assert np.all(np.isnan(planner.gradient(outside)))


def test_potential_values_in_free_space(planner):
    rng = np.random.default_rng(7)
    points = rng.uniform(0.0, 10.0, size=(400, 2))
    phi = planner.potential(points)
    psi = planner.psi(points)
    free = ~np.isnan(phi)
    assert free.sum() > 250
    assert np.all(phi[free] >= -1e-12) and np.all(phi[free] <= 1 + 1e-12)
    assert planner.reference == 1.0
    np.testing.assert_allclose(psi[free], 1.0 - phi[free], atol=1e-12)
    assert np.array_equal(np.isnan(psi), ~free)
    # phi rises away from the goal (0 on its circle of radius 0.15) and is ~1 near a wall.
    near = planner.potential(np.array([[8.5, 1.66], [8.5, 1.7], [8.5, 2.5], [0.02, 5.0]]))
    assert 0 < near[0] < near[1] < near[2] < near[3]
    assert near[0] < 0.05 and near[3] > 0.99


def test_psi_keeps_precision_where_phi_rounds_to_one(planner):
    # Deep in the top-left corner, far from the goal: psi is tiny but positive, and exact
    # where 1 - phi would lose digits.
    p = np.array([[0.01, 9.99]])
    psi = planner.psi(p)[0]
    assert 0 < psi < 1e-2
    assert psi == pytest.approx(1.0 - planner.potential(p)[0], abs=1e-15)


def test_gradient_matches_finite_differences(planner):
    points = np.array([[1.0, 9.0], [4.0, 5.0], [8.0, 3.0], [9.3, 8.1]])
    grad = planner.gradient(points)
    assert grad.shape == (4, 2) and grad.dtype == np.float64
    h = 1e-7
    for p, g in zip(points, grad):
        fd = [
            (planner.potential([p + h * e])[0] - planner.potential([p - h * e])[0]) / (2 * h)
            for e in (np.array([1.0, 0.0]), np.array([0.0, 1.0]))
        ]
        np.testing.assert_allclose(fd, g, rtol=1e-4, atol=1e-9)
    smooth = planner.gradient(points, smooth=True)
    assert smooth.shape == (4, 2)
    # The recovered gradient is close to the P1 one on a fine mesh, and points the same way.
    cos = np.sum(smooth * grad, axis=1) / (np.linalg.norm(smooth, axis=1) * np.linalg.norm(grad, axis=1))
    assert np.all(cos > 0.9)


def test_mesh_shapes_indices_and_area(planner, obstacles, workspace, reference_dict):
    vertices, triangles = planner.mesh()
    assert vertices.ndim == 2 and vertices.shape[1] == 2 and vertices.dtype == np.float64
    assert triangles.ndim == 2 and triangles.shape[1] == 3 and triangles.dtype == np.int64
    assert triangles.min() >= 0 and triangles.max() < len(vertices)
    assert len(np.unique(triangles)) > 0.99 * len(vertices)
    assert vertices.min() >= -1e-12 and vertices.max() <= 10 + 1e-12
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    signed = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))
    assert np.all(signed > 0), "counter-clockwise triangles"
    # The goal region is a hole in the mesh too (its boundary holds phi = 0).
    goal = reference_dict["goal"]["polygon"]
    free_area = shoelace(workspace) - sum(shoelace(o) for o in obstacles) - shoelace(goal)
    assert signed.sum() == pytest.approx(free_area, rel=1e-9)
    centroids = (a + b + c) / 3
    for q in centroids[:: max(1, len(centroids) // 500)]:
        assert not any(inside(q, o) for o in obstacles + [goal])
    phi_v = planner.phi_at_vertices()
    assert phi_v.shape == (len(vertices),)
    np.testing.assert_allclose(planner.psi_at_vertices(), 1.0 - phi_v, atol=1e-12)
    interior = planner.potential(centroids[:50])
    expected = planner.phi_at_vertices()[triangles[:50]].mean(axis=1)
    np.testing.assert_allclose(interior, expected, atol=1e-12)


def test_plan_many_equals_individual_plans(planner):
    starts = np.array([[1.0, 9.0], [9.0, 9.0], [2.5, 5.0], [0.5, 0.5], [-3.0, 2.0], [4.0, 5.0], [9.5, 6.0]])
    many = planner.plan_many(starts)
    assert len(many) == len(starts)
    for s, p in zip(starts, many):
        single = planner.plan(s)
        assert p.status == single.status
        assert p.start == list(s)
        np.testing.assert_array_equal(p.points, single.points)
        assert p.length == single.length
    assert many[2].status == "start_in_obstacle"
    assert many[4].status == "outside_workspace"
    assert planner.plan_many(np.zeros((0, 2))) == []
    # Lists work as well as arrays.
    assert [p.status for p in planner.plan_many([[1, 9], [9, 9]])] == ["reached_goal"] * 2


def test_exact_tracer(planner, obstacles):
    path = planner.plan_exact([1.0, 9.0])
    assert path.status == "reached_goal" and path.tracer == "exact"
    phi = planner.potential(path.points[:-1])
    finite = phi[~np.isnan(phi)]
    assert np.all(np.diff(finite) <= 1e-12), "phi decreases along the exact path"


def test_large_arrays_match_small_ones(planner):
    # From 4096 points on, evaluation runs in parallel without the GIL: same answers.
    rng = np.random.default_rng(3)
    points = rng.uniform(-1.0, 11.0, size=(10_000, 2))
    big = planner.potential(points)
    small = np.concatenate([planner.potential(c) for c in np.array_split(points, 10)])
    np.testing.assert_array_equal(big, small)
    assert np.isnan(big).any() and (~np.isnan(big)).any()
    g_big = planner.gradient(points)
    g_small = np.concatenate([planner.gradient(c) for c in np.array_split(points, 10)])
    np.testing.assert_array_equal(g_big, g_small)
    # Non-contiguous and integer inputs are converted.
    np.testing.assert_array_equal(planner.potential(points[::2]), big[::2])
    assert planner.potential(np.array([[1, 9]])).shape == (1,)
