"""Robot models: the round TurtleBot4 next to the boxy TurtleBot3s, and the lidar each one brings."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from sim2d.core.lidar import LDS_01, RPLIDAR_A1
from sim2d.core.robot import BURGER, ROBOTS, TB4, WAFFLE, Pose2D, RobotModel, robot_model
from sim2d.core.simulator import SimParams, Simulator
from sim2d.core.world import World, parse_world
from sim2d.ros.cli import parse
from sim2d.ros.config import build_config, declare_all, defaults
from tests.unit.sim2d.conftest import drive


def test_tb4_footprint_is_a_polygon_that_covers_its_circle() -> None:
    outline = np.array(TB4.footprint())
    assert outline.shape == (16, 2)
    corners = np.hypot(outline[:, 0], outline[:, 1])
    assert corners == pytest.approx(0.171 / math.cos(math.pi / 16))   # every corner outside the circle
    midpoints = 0.5 * (outline + np.roll(outline, -1, axis=0))
    assert np.hypot(midpoints[:, 0], midpoints[:, 1]) == pytest.approx(0.171)  # every edge touches it
    x, y = outline[:, 0], outline[:, 1]
    assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0.0       # counter-clockwise
    assert TB4.bounding_radius() == pytest.approx(0.1743, abs=1e-4)
    assert TB4.bounding_radius() < 0.175   # inside robot_radius of config/nav2_params_tb4.yaml


def test_box_footprints_are_unchanged() -> None:
    corners = np.array(WAFFLE.footprint())
    box = [(-0.197, -0.133), (0.069, -0.133), (0.069, 0.133), (-0.197, 0.133)]
    assert corners == pytest.approx(np.array(box))
    assert BURGER.bounding_radius() == pytest.approx(math.hypot(0.102, 0.070))


def test_a_model_has_exactly_one_footprint_shape() -> None:
    with pytest.raises(ValueError, match="robot tb4: give either footprint_radius or"):
        replace(TB4, footprint_length=0.3, footprint_width=0.3)
    with pytest.raises(ValueError, match="robot waffle: give either"):
        replace(WAFFLE, footprint_width=0.0)


def test_tb4_is_a_create3_with_an_rplidar() -> None:
    assert robot_model("tb4") is TB4 and set(ROBOTS) == {"waffle", "burger", "tb4"}
    assert (TB4.max_linear_velocity, TB4.max_angular_velocity) == (0.306, 1.90)
    assert (TB4.wheel_radius, TB4.wheel_separation) == (0.03575, 0.233)
    assert (TB4.scan_frame, TB4.scan_yaw) == ("rplidar_link", pytest.approx(math.pi / 2))
    assert TB4.lidar == RPLIDAR_A1 and (RPLIDAR_A1.range_min, RPLIDAR_A1.range_max) == (0.15, 12.0)
    assert WAFFLE.lidar == LDS_01 == BURGER.lidar and WAFFLE.scan_frame == "base_scan"


def test_tb4_commands_are_clamped_to_its_limits(make_sim) -> None:
    sim = make_sim(robot=TB4)
    drive(sim, 1.0, 0.0, 1.0)
    assert sim.v == pytest.approx(0.306)
    drive(sim, 0.0, -5.0, 2.0)
    assert (sim.v, sim.w) == (0.0, pytest.approx(-1.90))


def _walled_room() -> World:
    """A 10 m square room: the walls' inner faces at x = ±5 and y = ±5."""
    walls = [[[-5.1, -5.1], [5.1, -5.0]], [[-5.1, 5.0], [5.1, 5.1]], [[-5.1, -5.0], [-5.0, 5.0]],
             [[5.0, -5.0], [5.1, 5.0]]]
    boxes = [{"type": "box", "min": lo, "max": hi} for lo, hi in walls]
    return parse_world({"name": "room", "obstacles": boxes}, Path("room.yaml"))


def test_tb4_scans_in_its_turned_frame_beyond_the_lds01_range() -> None:
    pose = Pose2D(1.0, 0.0, 0.0)
    sim = Simulator(_walled_room(), TB4, SimParams(initial_pose=pose), np.random.default_rng(0),
                    lidar=replace(RPLIDAR_A1, noise_stddev=0.0))
    sensor = sim.scan_pose()
    assert (sensor.x, sensor.y, sensor.yaw) == pytest.approx((0.96, 0.0, math.pi / 2))
    ranges = sim.scan()                       # rplidar_link is turned +90°: beam 0 looks left (+y)
    assert ranges[0] == pytest.approx(5.0)
    assert ranges[270] == pytest.approx(5.0 - 0.96)   # -90° in the sensor frame: straight ahead
    assert ranges[90] == pytest.approx(5.0 + 0.96)    # behind the robot, 5.96 m: beyond the LDS-01's 3.5


def test_each_robot_brings_its_lidar_defaults() -> None:
    assert build_config({}).lidar == LDS_01
    assert build_config({"robot": "burger"}).lidar == LDS_01
    assert build_config({"robot": "tb4"}).lidar == RPLIDAR_A1
    values, _ = parse(["--robot", "tb4"])    # config/sim2d.yaml must not pin the LDS-01's figures
    assert build_config(values).lidar == RPLIDAR_A1
    assert defaults("tb4")["lidar.range_max"] == 12.0 and defaults()["lidar.range_max"] == 3.5


def test_explicit_lidar_values_override_the_robots(tmp_path: Path) -> None:
    assert build_config({"robot": "tb4", "lidar.rate": 10.0}).lidar == replace(RPLIDAR_A1, rate=10.0)
    params = tmp_path / "p.yaml"
    params.write_text("sim2d:\n  ros__parameters:\n    robot: tb4\n    lidar: {beams: 720}\n")
    values, _ = parse(["--params-file", str(params), "--ros-args", "-p", "lidar.range_max:=8.0"])
    assert build_config(values).lidar == replace(RPLIDAR_A1, beams=720, range_max=8.0)


def test_the_node_declares_robot_first_and_then_that_robots_lidar_defaults() -> None:
    overrides = {"robot": "tb4", "lidar.beams": 720}
    declared: list[tuple[str, object]] = []

    def declare(name: str, default: object) -> object:   # what rclpy's declare_parameter returns
        declared.append((name, default))
        return overrides.get(name, default)

    values = declare_all(declare)
    assert declared[0] == ("robot", "waffle") and len(declared) == len(defaults())
    assert dict(declared)["lidar.range_max"] == 12.0
    assert build_config(values).lidar == replace(RPLIDAR_A1, beams=720)


def test_unknown_robot_is_a_configuration_error() -> None:
    with pytest.raises(ValueError, match="robot: unknown model 'kobuki'"):
        build_config({"robot": "kobuki"})


def test_static_chain_and_scan_use_the_robots_scan_frame() -> None:
    pytest.importorskip("tf2_msgs.msg", reason="tf2_msgs is not built (run the interface build)")
    from sim2d.ros.messages import ScanBuilder, static_transforms

    def chain_of(robot: RobotModel) -> dict[tuple[str, str], Any]:
        transforms = static_transforms(robot, 0).transforms
        return {(t.header.frame_id, t.child_frame_id): t.transform for t in transforms}

    chain = chain_of(TB4)
    assert set(chain) == {("base_footprint", "base_link"), ("base_link", "rplidar_link")}
    assert chain[("base_footprint", "base_link")].translation.z == 0.0
    mount = chain[("base_link", "rplidar_link")]
    offset = (mount.translation.x, mount.translation.y, mount.translation.z)
    assert offset == pytest.approx((-0.04, 0.0, 0.1929))
    assert (mount.rotation.z, mount.rotation.w) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))
    assert chain_of(WAFFLE)[("base_link", "base_scan")].rotation.w == 1.0
    scan = ScanBuilder(RPLIDAR_A1, TB4.scan_frame).msg
    assert scan.header.frame_id == "rplidar_link"
    assert (scan.range_min, scan.range_max) == pytest.approx((0.15, 12.0))
