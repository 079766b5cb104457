"""Fleet declarations for nav-bringup (issue 48): fleet files, robot names, sim2d's fleet entries, and the
default spawns of `--robots N` (the world's spawns, then free space near the first)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from nav_stack.core.fleet_spawns import free_positions, spread_spawns
from nav_stack.core.fleet_spec import (
    FleetMember,
    FleetSpecError,
    check_fleet,
    load_fleet_file,
    numbered_fleet,
    sim_fleet_entries,
)
from nav_stack.core.grid import GridSpec
from nav_stack.core.map_io import OccupancyMap

MODELS = ("waffle", "burger", "tb4")


def _file(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "fleet.yaml"
    path.write_text(text)
    return path


def test_a_fleet_file_lists_robots_with_defaults_for_model_and_yaw(tmp_path: Path) -> None:
    path = _file(tmp_path, "- {name: robot1, model: tb4, x: -2.0, y: -0.5, yaw: 1.5}\n"
                           "- {name: scout_2, x: 1, y: 2}\n")
    assert load_fleet_file(path, MODELS, "waffle") == (FleetMember("robot1", "tb4", -2.0, -0.5, 1.5),
                                                       FleetMember("scout_2", "waffle", 1.0, 2.0, 0.0))
    wrapped = _file(tmp_path, "robots:\n  - {name: a, x: 0, y: 0}\n")
    assert [m.name for m in load_fleet_file(wrapped, MODELS, "burger")] == ["a"]


@pytest.mark.parametrize(("text", "message"), [
    ("[]", "a fleet needs at least one robot"),
    ("{name: robot1}", "expected a list of robots"),
    ("- [robot1, 0, 0]", "robot 0: expected a mapping"),
    ("- {name: robot1, x: 0}", "robot 0: missing y"),
    ("- {name: robot1, x: 0, y: 0, z: 1}", "robot 0: unknown key(s) z"),
    ("- {name: robot1, x: 0, y: zero}", "robot 0: y: expected a number, got 'zero'"),
    ("- {name: robot1, x: 0, y: .nan}", "robot 0: robot 'robot1': spawn (0.0, nan, 0.0) must be finite"),
    ("- {name: 1robot, x: 0, y: 0}", "robot 0: robot name '1robot' is not a valid ROS 2 namespace token"),
    ("- {name: robot__1, x: 0, y: 0}", "'robot__1' is not a valid ROS 2 namespace token"),
    ("- {name: r, x: 0, y: 0}\n- {name: r, x: 2, y: 0}", "robot name 'r' is declared twice"),
    ("- {name: r, model: roomba, x: 0, y: 0}",
     "robot 'r': unknown model 'roomba' (known: waffle, burger, tb4)"),
    ("- {name: r, x: 0, y: [0", "not valid YAML"),
])
def test_a_bad_fleet_file_is_refused_naming_the_file_the_robot_and_the_key(tmp_path: Path, text: str,
                                                                             message: str) -> None:
    path = _file(tmp_path, text)
    with pytest.raises(FleetSpecError) as info:
        load_fleet_file(path, MODELS, "waffle")
    assert str(info.value).startswith(f"{path}: ") and message in str(info.value), str(info.value)


def test_a_missing_fleet_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(FleetSpecError, match="cannot read it"):
        load_fleet_file(tmp_path / "none.yaml", MODELS, "waffle")


def test_numbered_fleets_use_nav2s_names_and_sim2d_gets_every_digit() -> None:
    fleet = numbered_fleet("tb4", [(-2.0, -0.5, 0.0), (0.1 + 0.2, 1.0, math.pi)])
    assert [m.name for m in fleet] == ["robot1", "robot2"]
    check_fleet(fleet, MODELS)
    assert sim_fleet_entries(fleet) == ["robot1:tb4:-2.0,-0.5,0.0",
                                        f"robot2:tb4:{0.1 + 0.2!r},1.0,{math.pi!r}"]


def _room(size_m: float = 6.0, resolution: float = 0.05) -> OccupancyMap:
    """A square room: free inside, a one-cell occupied wall round it."""
    cells = round(size_m / resolution)
    data = np.zeros((cells, cells), dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    return OccupancyMap(data, GridSpec(cells, cells, resolution, -size_m / 2, -size_m / 2))


def test_free_positions_keep_the_clearance_from_walls_and_unknown_space() -> None:
    room = _room()
    free = free_positions(room, 0.5)
    wall_inner = 3.0 - 0.025  # m from the centre to the wall cells' centres
    assert len(free) and np.all(np.abs(free) <= wall_inner - 0.5 + 1e-9)
    assert np.any(np.isclose(np.abs(free[:, 0]).max(), wall_inner - 0.5, atol=0.05))
    unknown = OccupancyMap(np.where(room.data == 0, -1, room.data).astype(np.int8), room.spec)
    assert len(free_positions(unknown, 0.5)) == 0


def test_spawns_take_the_worlds_own_first_then_free_space_nearest_the_first_robot() -> None:
    free = free_positions(_room(), 0.45)
    preferred = [(-2.0, -0.5, 0.3), (-1.9, -0.4, 0.0), (2.0, 2.0, 1.0)]   # the second is too near the first
    spawns = spread_spawns(4, preferred, free, separation=1.0)
    assert spawns[:2] == [preferred[0], preferred[2]]
    for i, a in enumerate(spawns):
        assert all(math.dist(a[:2], b[:2]) >= 1.0 for b in spawns[i + 1:])
    # the free-space robots stand next to the first one and face the way it does
    assert all(math.dist(s[:2], preferred[0][:2]) < 1.5 and s[2] == 0.3 for s in spawns[2:])
    assert spread_spawns(1, preferred, None) == [preferred[0]]


def test_too_many_robots_for_the_world_are_refused_with_how_many_fit() -> None:
    with pytest.raises(FleetSpecError, match=r"only 2 spawn pose\(s\) 1 m apart fit in this world for 3"):
        spread_spawns(3, [(0.0, 0.0, 0.0), (2.0, 0.0, 0.0)], None)
    with pytest.raises(FleetSpecError, match="at least one robot, got 0"):
        spread_spawns(0, [(0.0, 0.0, 0.0)], None)
    tiny = free_positions(_room(1.5), 0.45)
    assert len(spread_spawns(1, [], tiny)) == 1
    with pytest.raises(FleetSpecError, match="only 1 spawn"):
        spread_spawns(2, [], tiny)
