"""The Python side of the call-overhead comparison: planner.plan([1, 9]) and a one-point
planner.potential() timed with timeit (compare with examples/plan_timing.rs)."""

import pathlib
import timeit

import numpy as np

import harmonic_planner as hp

ROOT = pathlib.Path(__file__).resolve().parents[2]
planner = hp.Planner(hp.Scene.from_file(ROOT / "meshes" / "reference.json"))
one = np.array([[8.0, 3.0]])
cases = [
    ("planner.plan([1, 9])", lambda: planner.plan([1, 9]), 200),
    ("planner.plan([1, 9]).points", lambda: planner.plan([1, 9]).points, 200),
    ("planner.potential(one point)", lambda: planner.potential(one), 20000),
    ("planner.potential(10k points)", lambda: planner.potential(pts), 20),
]
pts = np.random.default_rng(1).uniform(0, 10, size=(10_000, 2))
for name, fn, n in cases:
    best = min(timeit.repeat(fn, number=n, repeat=5)) / n
    print(f"{name}: {best * 1e6:.2f} µs per call (best of 5 × {n})")
