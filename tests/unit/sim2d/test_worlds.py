"""The shipped worlds: free spawns, every room reachable, the office generator, refused spawns."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

from sim2d.core.grid_shapes import rasterize
from sim2d.core.office_world import OfficeLayout, generate_office
from sim2d.core.robot import WAFFLE
from sim2d.core.world import WORLDS_DIR, World, check_spawn, load_world, parse_world
from sim2d.ros.cli import main

REPO = Path(__file__).resolve().parents[3]
WORLDS = sorted(p.stem for p in WORLDS_DIR.glob("*.yaml"))
#: seed, width, height, with a dock (scripts/generate_office_world.py --dock)
SHIPPED_OFFICES = {"office_small": (1, 12.0, 8.0, False), "depot_large": (2, 30.0, 15.0, True)}
ROBOT_RADIUS = max(math.hypot(x, y) for x, y in WAFFLE.footprint())  # 0.24 m: the waffle at any yaw
SPAWN_CLEARANCE = 0.3
RESOLUTION = 0.05


def _reachable(world: World, start: tuple[float, float], radius: float
               ) -> tuple[np.ndarray, tuple[float, float]]:
    """Cells (image rows flipped to row 0 = lowest y) a disc of ``radius`` (m) reaches from ``start``.

    The world is rasterised at 5 cm; obstacle cells are dilated by ``radius``; then a 4-connected
    wavefront grows from ``start`` through the free cells until it stops changing.
    """
    image, origin = rasterize(world.geometry, world.free_region, RESOLUTION, 0.5)
    occupied = image[::-1] == 0
    reach_cells = int(radius / RESOLUTION)
    blocked = occupied.copy()
    h, w = occupied.shape
    for dr in range(-reach_cells - 1, reach_cells + 2):
        for dc in range(-reach_cells - 1, reach_cells + 2):
            if math.hypot(dr, dc) * RESOLUTION <= radius:
                shifted = np.zeros_like(occupied)
                shifted[max(dr, 0):h + min(dr, 0), max(dc, 0):w + min(dc, 0)] = \
                    occupied[max(-dr, 0):h + min(-dr, 0), max(-dc, 0):w + min(-dc, 0)]
                blocked |= shifted
    free = ~blocked
    reached = np.zeros_like(free)
    reached[_cell(start, origin)] = True
    assert free[_cell(start, origin)], f"start {start} is not free at radius {radius}"
    count = 0
    while reached.sum() != count:
        count = int(reached.sum())
        grown = reached.copy()
        grown[1:] |= reached[:-1]
        grown[:-1] |= reached[1:]
        grown[:, 1:] |= reached[:, :-1]
        grown[:, :-1] |= reached[:, 1:]
        reached = grown & free
    return reached, origin


def _cell(point: tuple[float, float], origin: tuple[float, float]) -> tuple[int, int]:
    """(row, col) of the cell holding ``point`` (m), row 0 = lowest y."""
    return (int((point[1] - origin[1]) // RESOLUTION), int((point[0] - origin[0]) // RESOLUTION))


@pytest.mark.parametrize("name", WORLDS)
def test_every_spawn_is_free_with_clearance(name: str) -> None:
    world = load_world(name)
    assert world.spawns, "every world file lists spawns (the first is the default)"
    points = np.array([spawn[:2] for spawn in world.spawns])
    assert not world.geometry.contains(points).any()
    clearance = world.geometry.boundary_distance(points)
    assert clearance.min() >= SPAWN_CLEARANCE, dict(zip(world.spawns, clearance.round(3), strict=True))
    for x, y, _ in world.spawns:
        check_spawn(world, x, y, ROBOT_RADIUS)


@pytest.mark.parametrize("name", WORLDS)
def test_every_spawn_is_reachable_from_the_default_one(name: str) -> None:
    world = load_world(name)
    reached, origin = _reachable(world, world.spawns[0][:2], ROBOT_RADIUS)
    unreachable = [spawn for spawn in world.spawns if not reached[_cell(spawn[:2], origin)]]
    assert not unreachable


def test_house_default_spawn_is_the_tb3_house_spawn_in_the_living_room() -> None:
    world = load_world("turtlebot3_house")
    assert world.spawns[0] == (-2.0, 1.0, 0.0)
    xmin, ymin, xmax, ymax = world.geometry.bounds()
    assert (xmin, xmax) == pytest.approx((-7.5, 7.5), abs=0.1)
    assert (ymin, ymax) == pytest.approx((-5.3, 5.3), abs=0.1)
    # doors (centre of the gap, then a point on each side): living room → hall → east room → study
    doors = [(1.11, -0.17), (2.3, 0.4), (2.3, 4.63), (6.22, -0.17), (-6.31, 0.93), (-5.15, 3.3)]
    assert not world.geometry.contains(np.array(doors)).any()
    assert (world.geometry.boundary_distance(np.array(doors)) >= 0.4).all()  # ≥ 0.8 m wide


@pytest.mark.parametrize(("name", "seed", "width", "height", "dock"),
                         [(name, *spec) for name, spec in SHIPPED_OFFICES.items()])
def test_shipped_office_worlds_are_the_generator_output(name: str, seed: int, width: float,
                                                       height: float, dock: bool) -> None:
    shipped = yaml.safe_load((WORLDS_DIR / f"{name}.yaml").read_text())
    assert shipped == generate_office(width, height, seed, dock=dock).world(name)
    header = (WORLDS_DIR / f"{name}.yaml").read_text().splitlines()[1]
    assert f"--seed {seed} --width {width:g} --height {height:g} --out sim2d/worlds/{name}.yaml" in header
    assert header.endswith(" --dock") == dock


def test_a_generated_dock_leaves_the_rest_of_the_office_as_it_was() -> None:
    plain = generate_office(30.0, 15.0, 2).world("a")
    docked = generate_office(30.0, 15.0, 2, dock=True).world("a")
    assert "docks" not in plain and docked.pop("docks") and docked == plain


def test_office_generator_is_deterministic_per_seed_and_size() -> None:
    assert generate_office(12.0, 8.0, 1).world("a") == generate_office(12.0, 8.0, 1).world("a")
    assert generate_office(12.0, 8.0, 1).world("a") != generate_office(12.0, 8.0, 2).world("a")
    assert generate_office(12.0, 8.0, 1).world("a") != generate_office(14.0, 8.0, 1).world("a")


def _check_rooms_reachable(layout: OfficeLayout) -> None:
    world = parse_world(layout.world("generated"), Path("generated.yaml"))
    reached, origin = _reachable(world, layout.spawns[0][:2], ROBOT_RADIUS)
    assert all(reached[_cell(room.centre, origin)] for room in layout.rooms)


@pytest.mark.parametrize(("seed", "width", "height"), [spec[:3] for spec in SHIPPED_OFFICES.values()]
                         + [(3, 12.0, 8.0), (4, 9.0, 7.0), (5, 20.0, 12.0)])
def test_every_room_of_a_generated_office_is_reachable(seed: int, width: float, height: float) -> None:
    layout = generate_office(width, height, seed)
    assert len(layout.rooms) >= 2 and all(
        room.door[2] - room.door[0] >= 0.8 for room in layout.rooms)
    _check_rooms_reachable(layout)


def test_large_office_has_columns_and_small_one_keeps_its_corridor_clear() -> None:
    assert generate_office(30.0, 15.0, 2).columns
    assert not generate_office(12.0, 8.0, 1).columns


def test_office_too_small_is_refused() -> None:
    with pytest.raises(ValueError, match="too small"):
        generate_office(12.0, 4.0, 1)


def test_spawn_in_a_wall_is_refused_naming_file_pose_and_spawns() -> None:
    world = load_world("turtlebot3_house")
    with pytest.raises(ValueError) as error:
        check_spawn(world, -0.05, 3.0, ROBOT_RADIUS)  # inside the study's west wall
    message = str(error.value)
    assert message.startswith("spawn (-0.05, 3) in ")
    assert "turtlebot3_house.yaml is inside an obstacle" in message
    assert "pick a free pose, e.g. the world's spawns: (-2, 1, 0), (-3, 1, 0)" in message
    too_close = "is too close to an obstacle (0.17 m clearance, the robot needs 0.24 m)"
    with pytest.raises(ValueError, match=re.escape(too_close)):
        check_spawn(world, -0.3, 3.0, ROBOT_RADIUS)
    check_spawn(world, -0.5, 3.0, ROBOT_RADIUS)  # 0.4 m from the wall: fine


def test_map_world_has_no_spawns_and_still_refuses_a_spawn_in_a_wall() -> None:
    world = load_world(REPO / "maps" / "turtlebot3_world.yaml")
    assert world.spawns == ()
    with pytest.raises(ValueError, match=r"spawn \(0, 0\) in .*turtlebot3_world.yaml is inside an obstacle.*"
                                         r"the world lists no spawns"):
        check_spawn(world, 0.0, 0.0, ROBOT_RADIUS)  # the centre pillar


def test_cli_refuses_a_spawn_in_a_wall_with_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["--world", "turtlebot3_house", "--x", "-0.05", "--y", "3.0"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("sim2d: error: spawn (-0.05, 3) in ") and "inside an obstacle" in err


@pytest.mark.parametrize(("spawns", "message"), [
    ("spawns: [[0, 0]]", "spawns[0]: must be [x, y, yaw]"),
    ("spawns: {x: 0}", "spawns: must be a list"),
    ("spawns: [[-3, -3, 0], [0, 0, 0]]", "spawns[1]: [0, 0, 0] is inside an obstacle"),
])
def test_bad_spawns_name_file_and_field(tmp_path: Path, spawns: str, message: str) -> None:
    path = tmp_path / "w.yaml"
    path.write_text(f"obstacles: [{{type: circle, center: [0, 0], radius: 1}}]\n{spawns}\n")
    with pytest.raises(ValueError, match=re.escape(f"w.yaml: {message}")):
        load_world(path)
