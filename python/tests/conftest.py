"""Shared fixtures: files are found relative to this file (the repository's meshes/)."""

import json
import pathlib

import pytest

import harmonic_planner as hp

ROOT = pathlib.Path(__file__).resolve().parents[2]
MESHES = ROOT / "meshes"


@pytest.fixture(scope="session")
def reference_path():
    return MESHES / "reference.json"


@pytest.fixture(scope="session")
def reference_dict(reference_path):
    return json.loads(reference_path.read_text())


@pytest.fixture(scope="session")
def planner(reference_path):
    return hp.Planner(hp.Scene.from_file(reference_path))
