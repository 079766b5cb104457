"""The docking controller: nav2_graceful_controller's smooth control law and the collision look-ahead."""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
import pytest

from nav_stack.core.control.base import CircleFootprint, CostGrid, PolygonFootprint
from nav_stack.core.docking.controller import DockingController, DockingControllerParams, Obstacles, relative
from nav_stack.core.docking.errors import FailedToControl
from nav_stack.core.docking.graceful import SmoothControlLawParams, ego_polar, next_pose, velocity_command
from nav_stack.core.docking.sequence import approach_target
from nav_stack.core.geometry import Pose2D, angle_diff
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec
from tests.helpers.docking_world import box_obstacle

ORIGIN = Pose2D(0.0, 0.0, 0.0)
TARGET = Pose2D(1.0, 0.5, 0.3)
STARTS = [(-1.0, 0.0, 0.0), (-1.0, 0.3, 0.0), (-1.0, -0.3, 0.5), (-0.8, 0.4, -0.6), (-1.2, 0.0, 1.0),
          (-0.7, 0.0, math.pi / 2), (-1.5, 1.0, -1.0), (-2.0, -0.5, 0.0)]


def _simulate(params: SmoothControlLawParams, start: Pose2D, target: Pose2D, backward: bool = False,
              dt: float = 0.02, max_s: float = 60.0) -> tuple[Pose2D, list[tuple[float, float]]]:
    """Unicycle integration of the law's commands until within 2 cm of the target (or ``max_s``)."""
    robot, commands, t = start, [], 0.0
    while math.hypot(robot.x - target.x, robot.y - target.y) >= 0.02 and t < max_s:
        v, w = velocity_command(relative(target, robot), ORIGIN, params, backward)
        commands.append((v, w))
        robot = Pose2D(robot.x + v * dt * math.cos(robot.yaw), robot.y + v * dt * math.sin(robot.yaw),
                       robot.yaw + w * dt)
        t += dt
    return robot, commands


@pytest.mark.parametrize("v_linear_min", [0.0, 0.1])
@pytest.mark.parametrize("start", STARTS)
def test_the_law_brings_the_robot_onto_the_target_pose(start: tuple[float, float, float],
                                                       v_linear_min: float) -> None:
    """From several starts, the first time within 2 cm of the target the heading is within 0.05 rad."""
    target = Pose2D(0.0, 0.0, 0.0)
    robot, _ = _simulate(SmoothControlLawParams(v_linear_min=v_linear_min), Pose2D(*start), target)
    assert math.hypot(robot.x - target.x, robot.y - target.y) < 0.02, f"never reached from {start}"
    assert abs(angle_diff(target.yaw, robot.yaw)) < 0.05


@pytest.mark.parametrize("start", STARTS[:5])
def test_backward_motion_reaches_the_target_tail_first(start: tuple[float, float, float]) -> None:
    """Backwards, the robot's heading ends opposite to its motion: the target pose's heading + π for a
    robot that backs in (the docking server turns the target round for that)."""
    target = Pose2D(0.0, 0.0, math.pi)  # backing in along +x means facing -x
    robot, commands = _simulate(SmoothControlLawParams(), Pose2D(start[0], start[1], start[2] + math.pi),
                                target, backward=True)
    assert math.hypot(robot.x, robot.y) < 0.02
    assert abs(angle_diff(target.yaw, robot.yaw)) < 0.05
    assert all(v <= 0.0 for v, _ in commands)


def test_commands_respect_the_velocity_limits() -> None:
    params = SmoothControlLawParams(v_linear_min=0.05, v_linear_max=0.2, v_angular_max=0.4)
    rng = np.random.default_rng(7)
    for x, y, yaw in rng.uniform([-3, -3, -math.pi], [3, 3, math.pi], size=(500, 3)):
        for backward in (False, True):
            v, w = velocity_command(Pose2D(x, y, yaw), ORIGIN, params, backward)
            assert abs(v) <= params.v_linear_max + 1e-12
            assert abs(w) <= params.v_angular_max + 1e-12
            assert (v <= 0.0) if backward else (v >= 0.0)


def test_speed_follows_nav2s_slowdown_and_curvature_rules() -> None:
    params = SmoothControlLawParams(v_linear_min=0.0, v_linear_max=0.3, slowdown_radius=0.5)
    far = velocity_command(Pose2D(3.0, 0.0, 0.0), ORIGIN, params)
    assert far == pytest.approx((0.3, 0.0))  # straight ahead: no curvature, full speed
    near = velocity_command(Pose2D(0.1, 0.0, 0.0), ORIGIN, params)
    assert near.vx == pytest.approx(0.3 * 0.1 / 0.5)  # within slowdown_radius: v_max · r / radius
    clamped = velocity_command(Pose2D(0.1, 0.0, 0.0), ORIGIN, SmoothControlLawParams(v_linear_min=0.1))
    assert clamped.vx == pytest.approx(0.1)  # never below v_linear_min


def test_ego_polar_coordinates_are_nav2s() -> None:
    """Target straight left, facing away: r = 1, line of sight -π/2, so phi = yaw - π/2 and delta = -π/2."""
    r, phi, delta = ego_polar(Pose2D(0.0, 1.0, 0.4), ORIGIN)
    assert (r, phi, delta) == pytest.approx((1.0, 0.4 - math.pi / 2, -math.pi / 2))
    r, phi, delta = ego_polar(Pose2D(0.0, 1.0, 0.4), ORIGIN, backward=True)
    assert (phi, delta) == pytest.approx((0.4 + math.pi / 2, math.pi / 2))


def test_next_pose_moves_then_turns() -> None:
    params = SmoothControlLawParams()
    v, w = velocity_command(TARGET, ORIGIN, params)
    assert next_pose(0.1, TARGET, ORIGIN, params) == pytest.approx((v * 0.1, 0.0, w * 0.1))


def test_bad_law_parameters_are_refused() -> None:
    with pytest.raises(ValueError, match="k_phi must be > 0"):
        SmoothControlLawParams(k_phi=0.0)
    with pytest.raises(ValueError, match="v_linear_min <= v_linear_max"):
        SmoothControlLawParams(v_linear_min=0.3, v_linear_max=0.2)
    with pytest.raises(ValueError, match="simulation_time_step > 0"):
        DockingControllerParams(simulation_time_step=0.0)


# -- the collision look-ahead ---------------------------------------------------------------------------
def _controller(**overrides: Any) -> DockingController:
    return DockingController(DockingControllerParams(v_linear_min=0.15, v_linear_max=0.15, **overrides))


def test_an_obstacle_on_the_way_to_the_dock_refuses_the_command() -> None:
    """Robot at (-1, 0) heading to a dock at the origin; a box at x = -0.5 blocks the way."""
    robot = Pose2D(-1.0, 0.0, 0.0)
    target = relative(approach_target(ORIGIN, False), robot)
    obstacles = Obstacles(box_obstacle(-0.55, -0.3, -0.45, 0.3), CircleFootprint(0.1), "odom")
    controller = _controller()
    hit = controller.collision(target, robot, obstacles, True, False)
    assert hit is not None and -0.7 < hit.x < -0.3
    with pytest.raises(FailedToControl, match="collision ahead"):
        controller.command(target, robot, obstacles, True, False)
    # Without collision detection, or with a free costmap, the command is the law's.
    assert _controller(use_collision_detection=False).command(target, robot, obstacles, True, False).vx > 0
    free = Obstacles(box_obstacle(2.0, 2.0, 2.1, 2.1), CircleFootprint(0.1), "odom")
    assert controller.command(target, robot, free, True, False).vx == pytest.approx(0.15)


def test_the_collision_message_names_the_obstacle_cell_not_only_the_robot_pose() -> None:
    """Issue 42 ("a dock blocked by an obstacle ... with a message saying what blocked it"): a 5 cm post
    9 cm beside the approach line, met by the waffle's body; the message gives the post's cell."""
    robot = Pose2D(-1.0, 0.0, 0.0)
    target = relative(approach_target(ORIGIN, False), robot)
    body = PolygonFootprint(((-0.197, -0.133), (0.069, -0.133), (0.069, 0.133), (-0.197, 0.133)))
    obstacles = Obstacles(box_obstacle(-0.5, 0.05, -0.45, 0.1), body, "odom")
    with pytest.raises(FailedToControl) as failure:
        _controller().command(target, robot, obstacles, True, False)
    match = re.search(r"the costmap cell at \((\S+), (\S+)\) \(cost 254\) under the robot at \((\S+), ",
                      str(failure.value))
    assert match is not None, str(failure.value)
    cell_x, cell_y, robot_x = (float(v) for v in match.groups())
    assert (cell_x, cell_y) == (pytest.approx(-0.475, abs=0.03), pytest.approx(0.075, abs=0.03))
    assert robot_x < -0.5 - 0.069 + 0.02  # the robot pose it names is short of the post, body included
    assert "in 'odom'" in str(failure.value)


def test_the_dock_itself_is_not_an_obstacle_within_the_threshold() -> None:
    """The last dock_collision_threshold m before the (projected) target are not checked while docking;
    while undocking the first ones from the robot are not."""
    robot = Pose2D(-0.5, 0.0, 0.0)  # 5 s at 0.15 m/s reach past the dock
    target = relative(approach_target(ORIGIN, False), robot)  # 0.25 m past the dock
    dock_body = Obstacles(box_obstacle(0.1, -0.3, 0.4, 0.3), CircleFootprint(0.1), "odom")
    assert _controller().collision(target, robot, dock_body, True, False) is None
    unskipped = _controller(dock_collision_threshold=0.0)
    assert unskipped.collision(target, robot, dock_body, True, False) is not None
    # Undocking from the dock at the origin towards a staging pose behind: the dock body at the start is
    # ignored, an obstacle further back is not.
    at_dock = Pose2D(0.0, 0.0, 0.0)
    staging = relative(Pose2D(-0.7, 0.0, 0.0), at_dock)
    body_at_start = Obstacles(box_obstacle(0.05, -0.3, 0.3, 0.3), CircleFootprint(0.1), "odom")
    assert _controller().collision(staging, at_dock, body_at_start, False, True) is None
    behind = Obstacles(box_obstacle(-0.6, -0.3, -0.5, 0.3), CircleFootprint(0.1), "odom")
    assert _controller().collision(staging, at_dock, behind, False, True) is not None


def test_command_to_pose_stops_within_the_tolerances() -> None:
    controller = _controller()
    pose = Pose2D(1.0, 1.0, 0.5)
    assert controller.command_to_pose(Pose2D(1.03, 1.0, 0.52), pose, 0.05, 0.05, ORIGIN, None, False,
                                      False) is None
    assert controller.command_to_pose(Pose2D(1.03, 1.0, 0.7), pose, 0.05, 0.05, ORIGIN, None, False,
                                      False) is not None  # heading still off


#: The dock files, the outline the look-ahead uses with each (m, base_link) and the distance (m) from
#: the dock pose to the Create 3 dock's face for that robot (sim2d: the robot's forward reach at the
#: contacts' 0.1 rad, + 0.01 m clearance).
TB4_OUTLINE = tuple((0.185 * math.cos(a), 0.185 * math.sin(a)) for a in np.arange(16) * math.pi / 8)
DOCK_FILES = {"turtlebot3_world": (None, 0.092), "depot_large": (TB4_OUTLINE, 0.184)}


def _dock_file_controller(world: str, **overrides: Any) -> tuple[DockingControllerParams, PolygonFootprint]:
    """A dock file's controller.* figures, and its footprint (else the robot's published one: the TB4's
    robot_radius 0.175 m circle as 16 points, padded by footprint_padding 0.01 m)."""
    import yaml

    from navsuite_testing.ros import REPO

    config = yaml.safe_load((REPO / "config" / "docks" / f"{world}.yaml").read_text())
    section = config["docking_server"]["ros__parameters"]["controller"]
    names = {"k_phi", "k_delta", "v_linear_min", "v_linear_max", "dock_collision_threshold"}
    params = DockingControllerParams(**{**{k: v for k, v in section.items() if k in names}, **overrides})
    outline = DOCK_FILES[world][0] or tuple(map(tuple, yaml.safe_load(section["footprint"])))
    return params, PolygonFootprint(outline)


def _own_dock_cells(face: float) -> CostGrid:
    """The Create 3 dock as the lidar may mark it for a dock pose at (0.7, 0, 0) (heading +x): its face
    ``face`` m ahead of the dock pose, and a beam 3 sigma short (0.03 m) in a cell ending at the face, so
    lethal cells begin ``face`` - 0.08 m ahead of the dock pose (cells aligned so that an edge lies there)."""
    near = 0.7 + face - 0.08
    spec = GridSpec(120, 120, 0.05, -3.0 + near % 0.05, -3.0)
    costs = np.zeros(spec.shape, dtype=np.uint8)
    my, mx = np.mgrid[0:spec.height, 0:spec.width]
    wx, wy = spec.cell_to_world(mx, my)
    costs[(wx > near) & (wx < near + 0.15) & (np.abs(wy) < 0.09)] = LETHAL_OBSTACLE
    return CostGrid(costs, spec)


OWN_DOCK_STARTS = [(0.0, 0.0, 0.0), (0.0, 0.1, -0.2), (0.3, -0.08, 0.25), (0.0, -0.2, 0.25)]


@pytest.mark.parametrize("world", sorted(DOCK_FILES))
@pytest.mark.parametrize("start", OWN_DOCK_STARTS)
def test_the_dock_files_threshold_leaves_the_own_dock_out_of_the_check(world: str,
                                                                       start: tuple[float, ...]) -> None:
    """Issue 42: with Jazzy's 0.3 m, the last checked roll-out pose put the robot's front on cells of the
    dock it was docking to (a false "collision ahead": 11 approaches in 30 bench dockings on
    turtlebot3_world, every approach on depot_large). Starts: the staging pose and where the staging
    navigation's goal tolerance or an approach may leave the robot."""
    params, footprint = _dock_file_controller(world)
    obstacles = Obstacles(_own_dock_cells(DOCK_FILES[world][1]), footprint, "odom")
    target = approach_target(Pose2D(0.7, 0.0, 0.0), False)
    robot = Pose2D(*start)
    assert DockingController(params).collision(relative(target, robot), robot, obstacles, True, False) is None
    stock, _ = _dock_file_controller(world, dock_collision_threshold=0.3)
    if start == (0.0, 0.0, 0.0):  # the false positive the file's value removes
        assert DockingController(stock).collision(relative(target, robot), robot, obstacles, True, False)


@pytest.mark.parametrize("world", sorted(DOCK_FILES))
def test_with_the_dock_files_threshold_an_obstacle_before_the_dock_is_still_seen(world: str) -> None:
    params, footprint = _dock_file_controller(world)
    grid = box_obstacle(0.5, -0.1, 0.55, 0.1)  # 0.15-0.2 m before the dock pose, across the approach
    target = approach_target(Pose2D(0.7, 0.0, 0.0), False)
    hit = DockingController(params).collision(relative(target, ORIGIN), ORIGIN,
                                              Obstacles(grid, footprint, "odom"), True, False)
    assert hit is not None and hit.x < 0.5
