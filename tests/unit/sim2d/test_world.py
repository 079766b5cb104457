"""World loading: the turtlebot3_world figures, map worlds, and errors that name file and field."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from sim2d.core.geometry import is_convex_ccw, regular_polygon, ring_pieces
from sim2d.core.grid_shapes import map_to_geometry, merge_boxes
from sim2d.core.map_io import MapImage, load_map, write_map
from sim2d.core.world import load_world


def test_turtlebot3_world_has_nine_pillars_and_the_hexagonal_blocks() -> None:
    world = load_world("turtlebot3_world")
    grid = {(x, y) for x in (-1.1, 0.0, 1.1) for y in (-1.1, 0.0, 1.1)}
    assert {(float(x), float(y)) for x, y, _ in world.geometry.circles} == grid
    assert np.allclose(world.geometry.circles[:, 2], 0.15)
    blocked = [[2.4, 0.0], [-1.8, 2.05], [1.8, -2.05], [0.0, 2.7], [-3.1, 0.0]]
    inside = world.geometry.contains(np.array(blocked))
    assert inside.all()  # head, hands/feet, top wall, left wall corner
    free = world.geometry.contains(np.array([[-2.0, -0.5], [0.0, 2.0], [2.2, 0.0], [-2.8, 0.0]]))
    assert not free.any()  # spawn, Nav2 system-test goal, just left of the head, inside the left corner


def test_ring_pieces_are_convex_and_mitred() -> None:
    hexagon = regular_polygon((0.0, 0.0), 2.0, 6)
    pieces = ring_pieces(hexagon, 0.3)
    assert all(is_convex_ccw(p) for p in pieces)
    # the outer corner of one piece is the start of the next: no gap at the corners
    assert all(np.allclose(pieces[i][2], pieces[(i + 1) % 6][1]) for i in range(6))


@pytest.mark.parametrize(("text", "field"), [
    ("obstacles: [{type: circle, center: [0, 0], radius: -1}]", "obstacles[0].radius"),
    ("obstacles: [{type: blob}]", "obstacles[0].type"),
    ("obstacles: [{type: polygon, vertices: [[0, 0], [0, 1], [1, 0]]}]", "obstacles[0].vertices"),
    ("obstacles: [{type: circle, radius: 1}]", "obstacles[0].center"),
    ("walls: []", "obstacles"),
])
def test_bad_world_file_names_file_and_field(tmp_path: Path, text: str, field: str) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(ValueError, match=re.escape(f"bad.yaml: {field}")):
        load_world(path)


def test_unknown_world_name_lists_known_worlds() -> None:
    with pytest.raises(ValueError, match="turtlebot3_world"):
        load_world("no_such_world")


def test_merged_boxes_cover_exactly_the_occupied_cells() -> None:
    rng = np.random.default_rng(3)
    occupied = rng.random((40, 50)) < 0.3
    occupied[5:15, 10:20] = True
    boxes = merge_boxes(occupied)
    cover = np.zeros(occupied.shape, dtype=np.int64)
    for c0, r0, c1, r1 in boxes:
        cover[r0:r1, c0:c1] += 1
    assert np.array_equal(cover, occupied.astype(np.int64))  # union exact, boxes disjoint
    assert len(boxes) < occupied.sum()


def test_map_world_matches_its_cells(tmp_path: Path) -> None:
    image = np.full((20, 30), 254, dtype=np.uint8)
    image[0:4, 0:30] = 0     # image row 0 is the top: a wall along the top edge (largest y)
    image[10:12, 5:7] = 0
    write_map(tmp_path / "m.yaml", image, 0.1, (-1.0, -2.0))
    grid = load_map(tmp_path / "m.yaml")
    assert grid.occupied[-1].all() and not grid.occupied[0].any()  # flipped to row 0 = lowest y
    world = load_world(tmp_path / "m.yaml")
    # top wall spans y in [-2 + 1.6, -2 + 2.0]; the block spans x in [-0.5, -0.3], y in [-1.2, -1.0]
    points = np.array([[0.0, -0.2], [0.0, -0.45], [-0.4, -1.1], [-0.25, -1.1], [0.5, -1.5]])
    assert world.geometry.contains(points).tolist() == [True, False, True, False, False]


def test_boundary_segments_face_outwards() -> None:
    occupied = np.zeros((5, 5), dtype=bool)
    occupied[2, 2] = True
    geometry = map_to_geometry(MapImage(occupied, 1.0, (0.0, 0.0)))
    seg = geometry.ray_segments
    assert len(seg) == 4
    centre = np.array([2.5, 2.5])
    e = seg[:, 2:4] - seg[:, 0:2]
    rel = centre - seg[:, 0:2]
    assert np.all(e[:, 0] * rel[:, 1] - e[:, 1] * rel[:, 0] > 0)  # the cell is on each edge's left


def test_broken_map_yaml_names_the_field(tmp_path: Path) -> None:
    (tmp_path / "m.yaml").write_text("image: m.pgm\nresolution: 0.05\n")
    with pytest.raises(ValueError, match=re.escape("m.yaml: missing field 'origin'")):
        load_map(tmp_path / "m.yaml")
    (tmp_path / "n.yaml").write_text("image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
    with pytest.raises(ValueError, match=re.escape("missing.pgm: cannot read image")):
        load_map(tmp_path / "n.yaml")
