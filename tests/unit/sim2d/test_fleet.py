"""Fleets (issue 48): robots in one world see each other, stop at each other with one collision each
naming the other, keep their own noise, and a one-robot fleet is today's Simulator bit for bit."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pytest

from sim2d.core.disturbances import DroppedObstacle
from sim2d.core.dock_detection import TagDetection
from sim2d.core.fleet import Fleet, FleetRobot
from sim2d.core.geometry import FloatArray, normalize_angle
from sim2d.core.lidar import LidarParams, cast_rays
from sim2d.core.lidar_jit import cast_each
from sim2d.core.robot import TB4, WAFFLE, Pose2D, RobotModel
from sim2d.core.simulator import RobotSim, SimParams, Simulator
from sim2d.core.world import World, load_world
from tests.unit.sim2d.conftest import room_with_docks
from tests.unit.sim2d.test_lidar_jit import random_world

NOISE_BOUND = 0.05   # m: 5 σ of the sensors' 0.01 m range noise


@pytest.fixture(scope="module")
def room() -> World:
    """An empty 6 x 6 m room: the walls stay beyond the robots' contacts and in lidar range."""
    return room_with_docks(half=3.0)


def _fleet(world: World, *robots: tuple[str, RobotModel, Pose2D], seed: int = 0, **components: Any) -> Fleet:
    declared = [FleetRobot(name, model, pose) for name, model, pose in robots]
    return Fleet(world, declared, SimParams(), np.random.default_rng(seed), **components)


def _facing(world: World, model_a: RobotModel, model_b: RobotModel, apart: float) -> Fleet:
    """robot1 at (-apart / 2, 0) facing +x, robot2 at (apart / 2, 0) facing it (m)."""
    return _fleet(world, ("robot1", model_a, Pose2D(-apart / 2.0, 0.0, 0.0)),
                  ("robot2", model_b, Pose2D(apart / 2.0, 0.0, math.pi)))


def _beam_towards(sim: RobotSim, bearing: float) -> int:
    """Index of the beam of ``sim``'s lidar pointing along ``bearing`` (rad, map frame)."""
    lidar = sim.lidar.params
    angle = normalize_angle(bearing - sim.pose.yaw - sim.robot.scan_yaw - lidar.angle_min) % (2.0 * math.pi)
    return round(angle / lidar.angle_increment) % lidar.beams


def _front(sim: RobotSim) -> float:
    """How far the footprint reaches ahead of base_footprint along the robot's heading (m)."""
    model = sim.robot
    return model.footprint_offset_x + (model.footprint_radius or model.footprint_length / 2.0)


def _drive(fleet: Fleet, commands: dict[str, tuple[float, float]], seconds: float) -> None:
    for _ in range(round(seconds / fleet.params.physics_step)):
        for name, (v, w) in commands.items():
            fleet.robots[name].command(v, w)
        fleet.step()


@pytest.mark.parametrize(("model_a", "model_b"), [(WAFFLE, WAFFLE), (TB4, WAFFLE)],
                         ids=["waffle+waffle", "tb4+waffle"])
def test_robots_facing_each_other_see_each_other_at_the_right_range(room: World, model_a: RobotModel,
                                                                    model_b: RobotModel) -> None:
    fleet = _facing(room, model_a, model_b, 2.0)
    a, b = fleet.robots["robot1"], fleet.robots["robot2"]
    for seer, seen, bearing in ((a, b, 0.0), (b, a, math.pi)):
        sensor_x = seer.scan_pose().x
        # each faces the other, so the other's front is the near face (a round base's circle is its front)
        near_face = seen.pose.x - math.cos(bearing) * _front(seen)
        beam = _beam_towards(seer, bearing)
        assert fleet.scan(seer.name)[beam] == pytest.approx(abs(near_face - sensor_x), abs=NOISE_BOUND)
        alone = Simulator(room, seer.robot, SimParams(initial_pose=seer.pose), np.random.default_rng(0))
        assert alone.scan()[beam] > abs(near_face - sensor_x) + 0.5     # without the other: the far wall


@pytest.mark.parametrize(("model_a", "model_b", "speed_b"), [
    (WAFFLE, WAFFLE, 0.2), (WAFFLE, WAFFLE, 0.0), (TB4, WAFFLE, 0.2), (WAFFLE, TB4, 0.0)],
    ids=["waffles-both-driving", "waffle-into-parked-waffle", "tb4+waffle-both-driving",
         "waffle-into-parked-tb4"])
def test_driving_together_stops_both_with_one_collision_each_naming_the_other(
        room: World, model_a: RobotModel, model_b: RobotModel, speed_b: float) -> None:
    fleet = _facing(room, model_a, model_b, 1.6)
    a, b = fleet.robots["robot1"], fleet.robots["robot2"]
    _drive(fleet, {"robot1": (0.2, 0.0), "robot2": (speed_b, 0.0)}, 8.0)   # pushing long after contact
    gap = (b.pose.x - _front(b)) - (a.pose.x + _front(a))
    assert 0.0 <= gap < 0.01                     # stopped at each other, not into each other
    assert a.collision.touching(a.pose) is None and b.collision.touching(b.pose) is None
    assert a.v == 0.0 and (speed_b == 0.0 or b.v == 0.0)
    assert a.pose.y == pytest.approx(0.0, abs=1e-9) and b.pose.y == pytest.approx(0.0, abs=1e-9)
    assert a.collision_count == b.collision_count == 1
    events_a, events_b = a.pop_collision_events(), b.pop_collision_events()
    assert [e.other for e in events_a] == ["robot2"] and [e.other for e in events_b] == ["robot1"]
    assert events_a[0].time_ns == events_b[0].time_ns
    for event in (events_a[0], events_b[0]):
        assert a.pose.x + _front(a) - 0.01 <= event.x <= b.pose.x - _front(b) + 0.01


def test_pushing_on_counts_one_collision_and_backing_off_ends_it(room: World) -> None:
    fleet = _facing(room, WAFFLE, WAFFLE, 1.6)
    _drive(fleet, {"robot1": (0.2, 0.0)}, 8.0)
    _drive(fleet, {"robot1": (-0.2, 0.0)}, 1.0)
    _drive(fleet, {"robot1": (0.2, 0.0)}, 2.0)
    assert fleet.robots["robot1"].collision_count == fleet.robots["robot2"].collision_count == 2


@dataclass
class _Trace:
    """What a run gives: true poses, odometry, scans, dock detections and collision events."""

    poses: list[Pose2D] = field(default_factory=list)
    odometry: list[Pose2D] = field(default_factory=list)
    scans: list[FloatArray] = field(default_factory=list)
    detections: list[TagDetection | None] = field(default_factory=list)
    events: list[tuple[int, float, float]] = field(default_factory=list)

    def same_as(self, other: _Trace) -> bool:
        return (self.poses == other.poses and self.odometry == other.odometry and self.events == other.events
                and self.detections == other.detections
                and all(np.array_equal(a, b) for a, b in zip(self.scans, other.scans, strict=True)))


def _run(sim: RobotSim, step: Callable[[], object], scan: Callable[[], FloatArray], seconds: float) -> _Trace:
    """Drive ``sim`` on a weave that meets obstacles, scanning and detecting docks every 40 steps."""
    trace = _Trace()
    for k in range(round(seconds / sim.params.physics_step)):
        sim.command(0.25, 0.5 * math.sin(k / 300.0))
        step()
        if k % 40 == 0:
            trace.scans.append(scan())
            trace.detections.append(sim.detect_dock())
        trace.poses.append(sim.pose)
        trace.odometry.append(sim.odometry.pose)
    trace.events = [(e.time_ns, e.x, e.y) for e in sim.pop_collision_events()]
    return trace


def _alone(world: World, model: RobotModel, pose: Pose2D, seed: int, seconds: float) -> _Trace:
    sim = Simulator(world, model, SimParams(initial_pose=pose), np.random.default_rng(seed), lidar=LIDAR)
    return _run(sim, sim.step, sim.scan, seconds)


LIDAR = LidarParams(dropout_probability=0.05)   # dropouts draw from the lidar stream as well


@pytest.mark.parametrize(("world_name", "model", "spawn"), [
    ("turtlebot3_world", WAFFLE, Pose2D(-2.0, 0.0, 0.0)),       # into the pillar at (-1.1, 0)
    ("depot_large", TB4, Pose2D(-14.2, 0.051, 0.0)),            # a world with a dock: detections too
], ids=["waffle-tb3_world", "tb4-depot_large"])
def test_a_one_robot_fleet_repeats_the_simulator_bit_for_bit(world_name: str, model: RobotModel,
                                                             spawn: Pose2D) -> None:
    world = load_world(world_name)
    fleet = _fleet(world, ("robot1", model, spawn), seed=11, lidar=LIDAR)
    sim = fleet.robots["robot1"]
    in_fleet = _run(sim, fleet.step, lambda: fleet.scan("robot1"), 12.0)
    assert in_fleet.events                      # the run did meet an obstacle
    assert in_fleet.same_as(_alone(world, model, spawn, 11, 12.0))
    assert fleet.time_ns == sim.time_ns


def test_robots_keep_their_own_noise_and_a_robot_added_last_changes_no_earlier_one() -> None:
    world = load_world("depot_large")
    first, far = Pose2D(-14.2, 0.051, 0.0), Pose2D(13.309, 5.981, -1.5708)   # 28 m apart: never in range
    pair = _fleet(world, ("robot1", WAFFLE, first), ("robot2", WAFFLE, far), seed=11, lidar=LIDAR)
    robot1 = _run(pair.robots["robot1"], pair.step, lambda: pair.scan("robot1"), 6.0)
    assert robot1.same_as(_alone(world, WAFFLE, first, 11, 6.0))
    # robot2's streams are its own: the same model at the same place alone with this seed reads otherwise
    alone = Simulator(world, WAFFLE, SimParams(initial_pose=far), np.random.default_rng(11), lidar=LIDAR)
    assert not np.array_equal(pair.scan("robot2"), alone.scan())


def test_same_seed_same_fleet_run_other_seed_other_noise(room: World) -> None:
    def run(seed: int) -> list[FloatArray]:
        fleet = _fleet(room, ("robot1", WAFFLE, Pose2D(-1.5, 0.0, 0.0)), ("robot2", TB4, Pose2D(0, 1, -1.5)),
                       ("robot3", WAFFLE, Pose2D(1.5, -1.0, 3.0)), seed=seed)
        scans = []
        for k in range(600):
            for i, sim in enumerate(fleet.robots.values()):
                sim.command(0.2, 0.8 * math.sin(k / 100.0 + i))
            fleet.step()
            if k % 50 == 0:
                scans += [fleet.scan(name) for name in fleet.robots]
        return scans

    same = run(4)
    assert all(np.array_equal(a, b) for a, b in zip(same, run(4), strict=True))
    assert not np.array_equal(same[0], run(5)[0])


@pytest.mark.parametrize(("robots", "message"), [
    ([], "declare at least one robot"),
    ([("robot1", Pose2D(-2.0, -0.5, 0.0)), ("robot1", Pose2D(-2.0, 0.5, 0.0))], "'robot1' is declared twice"),
    ([("robot1", Pose2D(-2.0, -0.5, 0.0)), ("robot2", Pose2D(0.0, 0.0, 0.0))],
     r"robot 'robot2': spawn \(0, 0\) .* is inside an obstacle"),
    ([("robot1", Pose2D(-2.0, -0.5, 0.0)), ("robot2", Pose2D(-1.8, -0.5, 1.0))],
     r"robot 'robot2': spawn \(-1.8, -0.5, 1\) overlaps robot 'robot1' at \(-2, -0.5, 0\)"),
    ([("robot1", Pose2D(math.nan, -0.5, 0.0))], r"robot 'robot1': spawn \(nan, -0.5, 0\) must be finite"),
], ids=["empty", "duplicate-name", "spawn-in-an-obstacle", "spawns-overlapping", "nan-spawn"])
def test_bad_declarations_are_refused_naming_the_robot_and_the_pose(
        tb3_world: World, robots: list[tuple[str, Pose2D]], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        _fleet(tb3_world, *[(name, WAFFLE, pose) for name, pose in robots])


@pytest.mark.parametrize("name", ["1robot", "robot-1", "", "robot__1", "/robot1", "robot 1"])
def test_names_must_be_ros_namespace_tokens(name: str) -> None:
    with pytest.raises(ValueError, match=f"robot name '{re.escape(name)}' is not a valid ROS 2 namespace"):
        FleetRobot(name, WAFFLE, Pose2D())


def test_robots_side_by_side_are_not_an_overlap(room: World) -> None:
    fleet = _fleet(room, ("robot1", WAFFLE, Pose2D(0.0, 0.0, 0.0)), ("tb4_a", TB4, Pose2D(0.0, 0.31, 0.0)))
    assert list(fleet.robots) == ["robot1", "tb4_a"]


def test_teleports_and_dropped_obstacles_respect_every_robot(room: World) -> None:
    fleet = _facing(room, WAFFLE, WAFFLE, 2.0)
    assert not fleet.teleport("robot2", Pose2D(-0.9, 0.0, 0.0))         # onto robot1
    assert fleet.teleport("robot2", Pose2D(0.0, 0.0, math.pi))
    a = fleet.robots["robot1"]
    beam = _beam_towards(a, 0.0)
    expected = (0.0 - _front(fleet.robots["robot2"])) - a.scan_pose().x
    assert fleet.scan("robot1")[beam] == pytest.approx(expected, abs=NOISE_BOUND)   # seen where it went
    assert not fleet.drop_obstacle(DroppedObstacle(0.0, 0.1, 0.05))     # on robot2
    assert fleet.drop_obstacle(DroppedObstacle(0.0, 1.5, 0.1))
    assert all(sim.dropped == [DroppedObstacle(0.0, 1.5, 0.1)] for sim in fleet.robots.values())
    _drive(fleet, {"robot2": (0.0, 0.0)}, 0.1)
    # robot1 drives on into robot2's old place: free now, then robot2 itself stops it
    _drive(fleet, {"robot1": (0.2, 0.0)}, 6.0)
    assert [e.other for e in fleet.robots["robot1"].pop_collision_events()] == ["robot2"]
    with pytest.raises(ValueError, match=r"no robot 'robot9' \(robots: robot1, robot2\)"):
        fleet.scan("robot9")


def test_a_robot_moved_away_leaves_no_body_behind(room: World) -> None:
    fleet = _facing(room, WAFFLE, WAFFLE, 0.6)
    _drive(fleet, {}, 0.1)
    assert fleet.teleport("robot2", Pose2D(2.0, 2.0, 0.0))
    robot1 = fleet.robots["robot1"]
    _drive(fleet, {"robot1": (0.2, 0.0)}, 6.0)           # through robot2's old place at x = 0.3
    assert robot1.collision_count == 0 and robot1.pose.x > 0.6
    fleet.reset()                                          # both back: robot2 stands in robot1's way again
    _drive(fleet, {"robot1": (0.2, 0.0)}, 4.0)
    assert [e.other for e in robot1.pop_collision_events()] == ["robot2"]


@pytest.mark.parametrize("seed", range(3))
def test_the_caster_of_robot_bodies_agrees_with_the_reference(seed: int) -> None:
    rng = np.random.default_rng(seed)
    geometry = random_world(rng)     # far more shapes than a fleet's, the same kinds
    for _ in range(10):
        origin = (float(rng.uniform(-25.0, 25.0)), float(rng.uniform(-16.0, 16.0)))
        angles = rng.uniform(-math.pi, 3.0 * math.pi, 360)
        max_range = float(rng.choice([3.5, 12.0]))
        expected = cast_rays(origin, angles, geometry, max_range)
        got = cast_each(origin, angles, geometry, max_range)
        assert np.array_equal(np.isinf(got), np.isinf(expected))
        assert got[np.isfinite(got)] == pytest.approx(expected[np.isfinite(expected)], abs=1e-12)
