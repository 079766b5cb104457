"""Docks in world files: parsing, errors that name file, field and value; the shipped docks' approach is
clear for either robot and their bodies are not in the generated maps."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

from sim2d.core.collision import CollisionModel, CollisionParams
from sim2d.core.map_io import read_pgm
from sim2d.core.robot import TB4, WAFFLE, Pose2D, RobotModel
from sim2d.core.world import load_world

REPO = Path(__file__).resolve().parents[3]
ROOM = "obstacles: [{type: ring, vertices: [[-2, -2], [2, -2], [2, 2], [-2, 2]], thickness: 0.1}]\n"


def _load(tmp_path: Path, docks: str) -> object:
    path = tmp_path / "docks.yaml"
    path.write_text(ROOM + docks)
    return load_world(path)


def test_a_dock_entry_becomes_a_dock_with_the_type_s_figures(tmp_path: Path) -> None:
    world = _load(tmp_path, "docks:\n  - {id: a, type: create3_dock, pose: [1.0, 0.5, 1.2]}\n"
                            "  - {id: b, type: create3_dock, pose: [0, 0, 0], contact_tolerance: 0.02,"
                            " contact_yaw_tolerance: 0.05}\n")
    a, b = world.docks  # type: ignore[attr-defined]
    assert (a.id, a.type.name, a.pose) == ("a", "create3_dock", Pose2D(1.0, 0.5, 1.2))
    assert (a.contact_tolerance, a.contact_yaw_tolerance) == (0.05, 0.1)
    assert (b.contact_tolerance, b.contact_yaw_tolerance) == (0.02, 0.05)
    assert load_world("empty").docks == ()


@pytest.mark.parametrize(("docks", "field", "value"), [
    ("docks: {id: a}", "docks", "{'id': 'a'}"),
    ("docks: [[1, 2, 3]]", "docks[0]", "[1, 2, 3]"),
    ("docks: [{id: a, type: roomba_base, pose: [0, 0, 0]}]", "docks[0].type", "'roomba_base'"),
    ("docks: [{id: a, pose: [0, 0, 0]}]", "docks[0].type", "None"),
    ("docks: [{id: a, type: create3_dock, pose: [0, 0]}]", "docks[0].pose", "[0, 0]"),
    ("docks: [{id: a, type: create3_dock, pose: [0, north, 0]}]", "docks[0].pose", "[0, 'north', 0]"),
    ("docks: [{id: a, type: create3_dock}]", "docks[0].pose", "None"),
    ("docks: [{id: '', type: create3_dock, pose: [0, 0, 0]}]", "docks[0].id", "''"),
    ("docks: [{type: create3_dock, pose: [0, 0, 0]}]", "docks[0].id", "None"),
    ("docks: [{id: a, type: create3_dock, pose: [0, 0, 0]}, {id: a, type: create3_dock, pose: [1, 0, 0]}]",
     "docks[1].id", "'a'"),
    ("docks: [{id: a, type: create3_dock, pose: [2.05, 0, 0]}]", "docks[0].pose", "[2.05, 0, 0]"),
    ("docks: [{id: a, type: create3_dock, pose: [0, 0, 0], contact_tolerance: -0.1}]",
     "docks[0].contact_tolerance", "-0.1"),
    ("docks: [{id: a, type: create3_dock, pose: [0, 0, 0], tolerance: 0.1}]", "docks[0].tolerance", ""),
])
def test_bad_dock_entry_names_file_field_and_value(tmp_path: Path, docks: str, field: str,
                                                   value: str) -> None:
    with pytest.raises(ValueError, match=re.escape(f"docks.yaml: {field}") + ".*" + re.escape(value)):
        _load(tmp_path, docks + "\n")


def _approach_is_clear(world_name: str, robot: RobotModel) -> None:
    """The footprint swept every centimetre from the staging pose (0.7 m out) onto the contact pose
    touches neither the world nor the dock's body."""
    world = load_world(world_name)
    for dock in world.docks:
        model = CollisionModel(world.geometry.with_polygons((dock.body(robot),)), robot, CollisionParams())
        start, end = dock.staging_pose(), dock.pose
        for t in np.linspace(0.0, 1.0, 71):
            pose = Pose2D(start.x + t * (end.x - start.x), start.y + t * (end.y - start.y), end.yaw)
            assert not model.overlaps(pose), f"{world_name}: {dock.id}: {robot.name} touches at {pose}"
        for yaw in (end.yaw - math.pi / 2, end.yaw + math.pi / 2):   # and may turn at the staging pose
            if robot.footprint_radius:
                assert not model.overlaps(Pose2D(start.x, start.y, yaw))


@pytest.mark.parametrize("robot", [WAFFLE, TB4], ids=lambda r: r.name)
@pytest.mark.parametrize("world_name", ["turtlebot3_world", "depot_large"])
def test_shipped_docks_have_a_clear_straight_approach(world_name: str, robot: RobotModel) -> None:
    assert load_world(world_name).docks
    _approach_is_clear(world_name, robot)


def test_turtlebot3_world_dock_stages_with_room_to_spare() -> None:
    """The waffle can stand anywhere within 0.3 m of the staging pose, at any heading, touching nothing:
    a staging navigation ending within the planner's goal tolerance (0.25 m) leaves the robot clear,
    and it may turn there (the dock's earlier staging pose lay 0.02 m from a pillar)."""
    (dock,) = load_world("turtlebot3_world").docks
    world = load_world("turtlebot3_world")
    model = CollisionModel(world.geometry.with_polygons((dock.body(WAFFLE),)), WAFFLE, CollisionParams())
    staging = dock.staging_pose()
    for bearing in np.linspace(-math.pi, math.pi, 16, endpoint=False):
        for yaw in np.linspace(-math.pi, math.pi, 12, endpoint=False):
            pose = Pose2D(staging.x + 0.3 * math.cos(bearing), staging.y + 0.3 * math.sin(bearing), yaw)
            assert not model.overlaps(pose), f"the waffle touches at {pose}"


def test_depot_dock_is_near_the_spawn() -> None:
    world = load_world("depot_large")
    (dock,) = world.docks
    spawn = world.spawns[0]
    assert math.hypot(dock.pose.x - spawn[0], dock.pose.y - spawn[1]) < 1.2


@pytest.mark.parametrize("world_name", ["turtlebot3_world", "depot_large"])
def test_dock_bodies_are_not_in_the_generated_map(world_name: str) -> None:
    """A real dock is usually not in the map: the map stays the world's static obstacles only, so the
    map-world agreement holds (world.geometry has no docks) and the dock's cells are free."""
    meta = yaml.safe_load((REPO / "maps" / f"{world_name}.yaml").read_text())
    image = read_pgm(REPO / "maps" / meta["image"])
    res, (ox, oy, _) = meta["resolution"], meta["origin"]
    for dock in load_world(world_name).docks:
        centre = dock.body(TB4).mean(axis=0)
        col = int((centre[0] - ox) // res)
        row = image.shape[0] - 1 - int((centre[1] - oy) // res)
        assert image[row, col] == 254, f"{world_name}: {dock.id} drawn into the map"
