"""maps/turtlebot3_world.{yaml,pgm} agrees with sim2d/worlds/turtlebot3_world.yaml."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import yaml

from sim2d.core.geometry import points_in_convex
from sim2d.core.map_io import read_pgm
from sim2d.core.world import load_world

REPO = Path(__file__).resolve().parents[3]
MAP_YAML = REPO / "maps" / "turtlebot3_world.yaml"


def _pixels_at(points: np.ndarray) -> np.ndarray:
    meta = yaml.safe_load(MAP_YAML.read_text())
    image = read_pgm(MAP_YAML.parent / meta["image"])
    res, (ox, oy, _) = meta["resolution"], meta["origin"]
    cols = np.floor((points[:, 0] - ox) / res).astype(int)
    rows = image.shape[0] - 1 - np.floor((points[:, 1] - oy) / res).astype(int)
    return image[rows, cols]


def test_map_header_is_map_server_trinary() -> None:
    meta = yaml.safe_load(MAP_YAML.read_text())
    assert meta["resolution"] == 0.05 and meta["negate"] == 0 and meta["mode"] == "trinary"
    assert meta["occupied_thresh"] == 0.65 and meta["free_thresh"] == 0.196
    image = read_pgm(MAP_YAML.parent / meta["image"])
    assert set(np.unique(image).tolist()) == {0, 205, 254}
    world = load_world("turtlebot3_world")
    xmin, ymin, xmax, ymax = world.geometry.bounds()
    ox, oy, _ = meta["origin"]
    height, width = image.shape
    assert ox < xmin and oy < ymin  # the origin covers the world with a margin
    assert ox + width * 0.05 > xmax and oy + height * 0.05 > ymax


def test_map_and_world_agree_on_sampled_points() -> None:
    world = load_world("turtlebot3_world")
    xmin, ymin, xmax, ymax = world.geometry.bounds()
    rng = np.random.default_rng(7)
    points = rng.uniform((xmin, ymin), (xmax, ymax), size=(20000, 2))
    pixels = _pixels_at(points)
    in_obstacle = world.geometry.contains(points)
    far_from_edge = world.geometry.boundary_distance(points) > 0.05 * math.sqrt(2.0)
    assert np.array_equal((pixels == 0)[far_from_edge], in_obstacle[far_from_edge])
    assert (pixels == 0).sum() > 1000 and in_obstacle.sum() > 1000


def test_free_inside_the_hexagon_and_unknown_outside() -> None:
    world = load_world("turtlebot3_world")
    rng = np.random.default_rng(8)
    points = rng.uniform((-3.8, -3.9), (4.8, 3.9), size=(20000, 2))
    pixels = _pixels_at(points)
    assert world.free_region is not None
    inside = points_in_convex(points, world.free_region)
    clear = ~world.geometry.contains(points) & (world.geometry.boundary_distance(points) > 0.08)
    assert np.all(pixels[inside & clear] == 254)
    assert np.all(pixels[~inside & clear] == 205)


def test_map_loaded_as_world_matches_the_world() -> None:
    analytic = load_world("turtlebot3_world")
    from_map = load_world(MAP_YAML)
    rng = np.random.default_rng(9)
    points = rng.uniform((-3.3, -3.4), (4.6, 3.4), size=(20000, 2))
    far = analytic.geometry.boundary_distance(points) > 0.05 * math.sqrt(2.0)
    assert np.array_equal(from_map.geometry.contains(points)[far], analytic.geometry.contains(points)[far])
