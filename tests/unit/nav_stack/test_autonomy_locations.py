"""Locations file loading, validation against the tree, and reachability of the seed's poses."""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_stack.core.bt import BehaviorTreeFactory
from nav_stack.core.map_io import load_map
from nav_stack.ros.autonomy.battery import CounterBattery
from nav_stack.ros.autonomy.clearance import clearance_table
from nav_stack.ros.autonomy.locations import (
    Location,
    LocationsError,
    check_tree_locations,
    load_locations,
    nearest_location,
)
from nav_stack.ros.autonomy.seed_nodes import SeedContext, register_seed_nodes
from navsuite_testing.autonomy.fakes import FakeNavigator

REPO = Path(__file__).resolve().parents[3]
V3 = REPO / "config" / "trees" / "seed_battery_patrol_v3.xml"
SEED = {"location1": (-1.03, -0.51, 0.0), "location2": (-0.56, -1.03, 0.0), "location3": (-1.43, -1.34, 3.14),
        "location4": (-1.58, -1.48, 3.14), "station": (-1.37, -0.82, 0.0)}


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "locations.yaml"
    path.write_text(text)
    return path


def test_project_locations_file_holds_the_seed_values() -> None:
    locations = load_locations(REPO / "config" / "locations.yaml")
    assert {name: (loc.x, loc.y, loc.theta) for name, loc in locations.items()} == SEED


@pytest.mark.parametrize(("text", "expected"), [
    ("", "empty file"),
    ("- [1, 2, 3]\n", "expected a mapping"),
    ("station: [1.0, 2.0]\n", "location 'station': expected [x, y, theta], got [1.0, 2.0]"),
    ("station: [1.0, north, 0.0]\n", "location 'station': y must be a finite number, got 'north'"),
    ("station: [1.0, .nan, 0.0]\n", "location 'station': y must be a finite number"),
    ("station: [1.0, 2.0, true]\n", "location 'station': theta must be a finite number, got True"),
    ("station: {x: 1}\n", "location 'station': expected [x, y, theta]"),
    ("station: [1.0, 2.0, 0.0\n", "locations.yaml:2:"),
])
def test_malformed_files_give_one_line_naming_file_and_item(tmp_path: Path, text: str, expected: str) -> None:
    path = write(tmp_path, text)
    with pytest.raises(LocationsError) as info:
        load_locations(path)
    message = str(info.value)
    assert message.startswith(str(path)) and expected in message and "\n" not in message


def test_missing_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(LocationsError, match=r"nowhere\.yaml: cannot read"):
        load_locations(tmp_path / "nowhere.yaml")


def test_a_location_used_by_the_tree_but_not_defined_is_named_with_its_node(tmp_path: Path) -> None:
    path = write(tmp_path, "".join(f"{k}: {list(v)}\n" for k, v in SEED.items() if k != "station"))
    locations = load_locations(path)
    factory = BehaviorTreeFactory()
    register_seed_nodes(factory, SeedContext(FakeNavigator(), CounterBattery(), locations))
    tree = factory.create_tree_from_file(V3)
    with pytest.raises(LocationsError) as info:
        check_tree_locations(tree, locations, str(path))
    message = str(info.value)
    assert message.startswith(f"{path}: location 'station' used by GoToPose 'go_to_station' ({V3}:6)")
    assert "\n" not in message


def test_nearest_location_names_a_goal_within_tolerance() -> None:
    locations = [Location(k, *v) for k, v in SEED.items()]
    assert nearest_location(locations, -1.40, -1.36, 0.05) == "location3"
    assert nearest_location(locations, 0.0, 0.0, 0.05) is None


def test_clearance_of_the_seed_locations() -> None:
    locations = {k: Location(k, *v) for k, v in SEED.items()}
    grid = load_map(REPO / "maps" / "turtlebot3_world.yaml")
    rows = {row.name: row for row in clearance_table(locations, grid)}
    # Footprint: centre to the nearest pillar centre minus 0.22 m (robot) + 0.15 m (pillar).
    assert rows["station"].pillar_centre_distance == pytest.approx(0.389, abs=1e-3)
    assert rows["station"].footprint_gap == pytest.approx(0.019, abs=1e-3)
    assert rows["location3"].footprint_gap == pytest.approx(0.038, abs=1e-3)
    assert rows["location4"].footprint_gap == pytest.approx(0.242, abs=1e-3)
    # Static costmap: the goal cells of the station and location3 are 5 cells from the pillar's lethal
    # cells (0.25 m > 0.22 m inscribed): cost 230 < 253, so the planner may end there.
    assert rows["station"].lethal_distance == pytest.approx(0.25, abs=1e-6)
    assert rows["station"].cost == 230 and rows["location3"].cost == 230
    assert all(row.collision_free and row.reachable for row in rows.values())


def test_clearance_flags_a_pose_inside_the_inflation_core() -> None:
    grid = load_map(REPO / "maps" / "turtlebot3_world.yaml")
    (row,) = clearance_table({"bad": Location("bad", -1.1, -0.85, 0.0)}, grid)
    assert row.footprint_gap < 0 and not row.collision_free
    assert row.cost >= 253 and not row.reachable
