"""Pure helpers of cl_nav2z and the ROS layer (no node): geometry, path recording, undo plans, waypoint
files, parameter dataclasses, transition lines, machine lookup."""

from __future__ import annotations

import math

import pytest

from smacc_py.clients.cl_keyboard import key_of
from smacc_py.clients.cl_nav2z.cb_motion import undo_plan
from smacc_py.clients.cl_nav2z.geometry import (
    is_straight,
    normalize_angle,
    path_length,
)
from smacc_py.clients.cl_nav2z.odom_path import OdomPath, OdomTrackerParams, WorkingMode
from smacc_py.clients.cl_nav2z.waypoints_io import Waypoint, load_waypoints_file, waypoints_from_flat
from smacc_py.ros.loader import load_state_machine
from smacc_py.state_machines.sm_nav2_test_1 import SmNav2Test1, SmNav2Test1Params


def test_angles_wrap_to_minus_pi_exclusive() -> None:
    """(-π, π]; the quaternion round trip is ros_tools.geometry's (tests/unit/ros_tools/test_geometry.py)."""
    assert normalize_angle(3 * math.pi) == pytest.approx(math.pi)
    assert normalize_angle(-math.pi) == math.pi


def test_straightness_and_length() -> None:
    line = [(0.1 * i, 0.01 * (i % 2), 0.0) for i in range(11)]
    assert is_straight(line) and path_length(line) == pytest.approx(1.0, abs=0.01)
    arc = [(math.sin(a), 1 - math.cos(a), a) for a in (0.0, 0.3, 0.6, 0.9)]
    assert not is_straight(arc)


def test_odom_path_records_with_thresholds_and_clears_on_the_way_back() -> None:
    paths = OdomPath(
        OdomTrackerParams(record_point_distance_threshold=0.1, clear_point_distance_threshold=0.05)
    )
    assert not paths.feed((0.0, 0.0, 0.0))  # IDLE records nothing
    paths.push_path("go")
    paths.set_mode(WorkingMode.RECORD_PATH)
    for x in (0.0, 0.05, 0.2, 0.25, 0.4):
        paths.feed((x, 0.0, 0.0))
    assert paths.path() == [(0.0, 0.0, 0.0), (0.2, 0.0, 0.0), (0.4, 0.0, 0.0)]
    assert paths.feed((0.4, 0.0, 0.5))  # turning more than 0.1 rad records too
    paths.set_mode(WorkingMode.CLEAR_PATH)
    paths.feed((0.41, 0.0, 0.5))
    assert paths.path() == [(0.0, 0.0, 0.0), (0.2, 0.0, 0.0)]
    assert paths.pop_path() == [(0.0, 0.0, 0.0), (0.2, 0.0, 0.0)]
    assert paths.path() == []


@pytest.mark.parametrize(
    ("path", "plan"),
    [
        ([(0.0, 0.0, 0.0), (0.5, 0.0, 0.0), (1.0, 0.0, 0.0)], ("backup", 1.0)),
        ([(0.0, 0.0, 0.0), (-0.5, 0.0, 0.0), (-1.0, 0.0, 0.0)], ("drive_on_heading", 1.0)),
        (
            [(0.0, 0.0, 0.0), (0.5, 0.0, 0.0), (1.0, 0.5, 0.8)],
            ("follow_path", pytest.approx(0.5 + math.hypot(0.5, 0.5))),
        ),
        ([(0.0, 0.0, 0.0)], None),
    ],
)
def test_undo_plan_picks_the_honest_motion(path, plan) -> None:  # type: ignore[no-untyped-def]
    assert undo_plan(path) == plan


def test_waypoint_files_and_flat_parameters(tmp_path) -> None:  # type: ignore[no-untyped-def]
    good = tmp_path / "w.yaml"
    good.write_text("waypoints:\n  - {name: a, x: 1, y: 2, yaw: 0.5}\n  - {x: -1.5, y: 0}\n")
    assert load_waypoints_file(good) == [Waypoint(1.0, 2.0, 0.5, "a"), Waypoint(-1.5, 0.0, 0.0, "")]
    bad = tmp_path / "bad.yaml"
    bad.write_text("waypoints:\n  - {x: 1, y: 2}\n  - {x: 1, y: nope}\n")
    with pytest.raises(ValueError, match=r"bad.yaml: waypoints\[1\].y must be a finite number, got 'nope'"):
        load_waypoints_file(bad)
    assert waypoints_from_flat([1, 2, 3, 4, 5, 6], "p") == [Waypoint(1, 2, 3), Waypoint(4, 5, 6)]
    with pytest.raises(ValueError, match="x, y, yaw triples; got 4"):
        waypoints_from_flat([1, 2, 3, 4], "p")


def test_keys_map_to_their_own_letters() -> None:
    assert [key_of(ord(c)) for c in "aNyZ"] == ["A", "N", "Y", "Z"]
    assert key_of(ord("1")) is None and key_of(0x10FFFF + 1) is None


def test_machine_parameters_reject_bad_poses() -> None:
    with pytest.raises(ValueError, match="waypoint_1 must be 3 finite numbers"):
        SmNav2Test1Params(waypoint_1=(1.0, math.nan, 0.0))


def test_waypoint_2_default_is_clear_of_the_pillars() -> None:
    x, y, _ = SmNav2Test1Params().waypoint_2
    pillars = [(px, py) for px in (-1.1, 0.0, 1.1) for py in (-1.1, 0.0, 1.1)]
    clearance = min(math.hypot(x - px, y - py) for px, py in pillars) - 0.15
    assert clearance >= 0.45 + 0.15  # robot radius 0.22 m and Nav2's 0.55 m inflation both fit


def test_loader_finds_machines_by_name_module_and_class() -> None:
    assert load_state_machine("sm_nav2_test_1") is SmNav2Test1
    assert load_state_machine("smacc_py.state_machines.sm_nav2_test_1:SmNav2Test1") is SmNav2Test1
    with pytest.raises(ValueError, match=r"shipped machines: no smacc_py\.state_machines\.nope"):
        load_state_machine("nope")
