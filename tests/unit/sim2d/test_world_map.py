"""maps/<world>.{yaml,pgm} agrees with sim2d/worlds/<world>.yaml, for every shipped world."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from sim2d.core.geometry import points_in_convex
from sim2d.core.map_io import read_pgm
from sim2d.core.world import WORLDS_DIR, load_world

REPO = Path(__file__).resolve().parents[3]
WORLDS = sorted(p.stem for p in WORLDS_DIR.glob("*.yaml"))
RESOLUTION = 0.05
SAMPLES = 10000


def _map(name: str) -> tuple[dict[str, Any], np.ndarray]:
    meta = yaml.safe_load((REPO / "maps" / f"{name}.yaml").read_text())
    return meta, read_pgm(REPO / "maps" / meta["image"])


def _pixels_at(name: str, points: np.ndarray) -> np.ndarray:
    meta, image = _map(name)
    res, (ox, oy, _) = meta["resolution"], meta["origin"]
    cols = np.floor((points[:, 0] - ox) / res).astype(int)
    rows = image.shape[0] - 1 - np.floor((points[:, 1] - oy) / res).astype(int)
    return image[rows, cols]


def _samples(name: str, seed: int, inset: float = 0.0) -> np.ndarray:
    """Uniform points (N, 2) over the world's bounding box shrunk by ``inset`` (m)."""
    xmin, ymin, xmax, ymax = load_world(name).geometry.bounds()
    rng = np.random.default_rng(seed)
    return rng.uniform((xmin + inset, ymin + inset), (xmax - inset, ymax - inset), size=(SAMPLES, 2))


def test_every_world_has_a_map() -> None:
    assert {"turtlebot3_world", "turtlebot3_house", "empty", "office_small", "depot_large"} <= set(WORLDS)
    assert all((REPO / "maps" / f"{name}.yaml").is_file() for name in WORLDS)


@pytest.mark.parametrize("name", WORLDS)
def test_map_header_is_map_server_trinary(name: str) -> None:
    meta, image = _map(name)
    assert meta["resolution"] == RESOLUTION and meta["negate"] == 0 and meta["mode"] == "trinary"
    assert meta["occupied_thresh"] == 0.65 and meta["free_thresh"] == 0.196
    assert set(np.unique(image).tolist()) == {0, 205, 254}
    xmin, ymin, xmax, ymax = load_world(name).geometry.bounds()
    ox, oy, _ = meta["origin"]
    height, width = image.shape
    assert ox < xmin and oy < ymin  # the origin covers the world with a margin
    assert ox + width * RESOLUTION > xmax and oy + height * RESOLUTION > ymax


@pytest.mark.parametrize("name", WORLDS)
def test_map_and_world_agree_on_sampled_points(name: str) -> None:
    world = load_world(name)
    points = _samples(name, 7)
    pixels = _pixels_at(name, points)
    in_obstacle = world.geometry.contains(points)
    far_from_edge = world.geometry.boundary_distance(points) > RESOLUTION * math.sqrt(2.0)
    assert np.array_equal((pixels == 0)[far_from_edge], in_obstacle[far_from_edge])
    assert (pixels == 0).sum() > 100 and in_obstacle.sum() > 100


@pytest.mark.parametrize("name", WORLDS)
def test_free_inside_the_free_region_and_unknown_outside(name: str) -> None:
    world = load_world(name)
    assert world.free_region is not None
    points = _samples(name, 8, inset=-0.4)  # reaches into the map's unknown margin
    pixels = _pixels_at(name, points)
    inside = points_in_convex(points, world.free_region)
    clear = ~world.geometry.contains(points) & (world.geometry.boundary_distance(points) > 0.08)
    assert np.all(pixels[inside & clear] == 254)
    assert np.all(pixels[~inside & clear] == 205)
    assert (inside & clear).any() and (~inside & clear).any()


@pytest.mark.parametrize("name", WORLDS)
def test_map_loaded_as_world_matches_the_world(name: str) -> None:
    analytic = load_world(name)
    from_map = load_world(REPO / "maps" / f"{name}.yaml")
    points = _samples(name, 9)
    far = analytic.geometry.boundary_distance(points) > RESOLUTION * math.sqrt(2.0)
    assert np.array_equal(from_map.geometry.contains(points)[far], analytic.geometry.contains(points)[far])
