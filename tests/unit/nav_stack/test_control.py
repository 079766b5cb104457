"""DWB, Regulated Pure Pursuit, path handling, goal/progress checkers (pure cores, kinematic loops)."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from nav_stack.core.control import (
    CircleFootprint,
    ControllerErrorCode,
    ControllerPlugins,
    CostGrid,
    DWBController,
    GoalCheckerParams,
    InvalidController,
    InvalidPath,
    NoValidControl,
    PathHandler,
    PolygonFootprint,
    RegulatedPurePursuit,
    RPPParams,
    SimpleGoalChecker,
    SimpleProgressChecker,
    StoppedGoalChecker,
    Twist2D,
)
from nav_stack.core.control.base import motion_collides
from nav_stack.core.control.rpp_moves import FINAL_ARC_RADIUS
from nav_stack.core.control.rpp_params import (
    approach_scaled_speed,
    curvature_to,
    find_carrot,
    obstacle_distance_from_cost,
    regulated_speed,
)
from nav_stack.core.geometry import Pose2D, headings_along
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, GridSpec
from nav_stack.core.planning.navfn import NavfnParams, NavfnPlanner
from tests.helpers.tight_spot import WAFFLE_BOX, tb3_world_grid

REPO = Path(__file__).resolve().parents[3]
DT = 0.05  # 20 Hz controller


def with_obstacle(
    spec: GridSpec, x0: float, x1: float, y0: float, y1: float, radius: float = 0.22
) -> CostGrid:
    """Lethal box plus an inscribed (253) ring of ``radius`` and a decaying inflation beyond it."""
    mx, my = np.meshgrid(np.arange(spec.width), np.arange(spec.height))
    x, y = spec.cell_to_world(mx, my)
    dx = np.maximum(np.maximum(x0 - x, x - x1), 0.0)
    dy = np.maximum(np.maximum(y0 - y, y - y1), 0.0)
    d = np.hypot(dx, dy)
    costs = np.where(
        d <= radius, INSCRIBED_INFLATED_OBSTACLE, np.floor(252 * np.exp(-3.0 * (d - radius))) * (d < 0.7)
    ).astype(np.uint8)
    costs[d == 0.0] = LETHAL_OBSTACLE
    return CostGrid(costs, spec)


def polyline_path(points: list[tuple[float, float]], spacing: float = 0.05) -> np.ndarray:
    pts = np.asarray(points, dtype=float)
    out = []
    for a, b in itertools.pairwise(pts):
        n = max(1, int(np.ceil(np.hypot(*(b - a)) / spacing)))
        out.append(a + np.arange(n)[:, None] / n * (b - a))
    xy = np.vstack([*out, pts[-1:]])
    return np.column_stack((xy, headings_along(xy)))


def unicycle(pose: Pose2D, cmd: Twist2D, dt: float = DT) -> Pose2D:
    yaw = pose.yaw + cmd.wz * dt / 2
    return Pose2D(
        pose.x + cmd.vx * math.cos(yaw) * dt, pose.y + cmd.vx * math.sin(yaw) * dt, pose.yaw + cmd.wz * dt
    )


def drive(
    controller: DWBController | RegulatedPurePursuit,
    path: np.ndarray,
    grid: CostGrid,
    start: Pose2D,
    goal_yaw: float,
    max_steps: int = 1200,
    poses: list[Pose2D] | None = None,
) -> tuple[Pose2D, bool, float]:
    """Closed kinematic loop: path handler → controller → unicycle; returns end pose, reached, worst
    cost, and appends every pose to ``poses`` when given."""
    path = path.copy()
    path[-1, 2] = goal_yaw
    handler = PathHandler()
    handler.set_plan(path)
    checker = SimpleGoalChecker()
    pose, vel = start, Twist2D(0.0, 0.0)
    worst = 0
    for _ in range(max_steps):
        if checker.is_goal_reached(pose, handler.goal, vel):
            return pose, True, worst
        local = handler.local_path(pose, Pose2D(0.0, 0.0, 0.0), grid)
        vel = controller.compute_velocity(pose, vel, local, grid)
        pose = unicycle(pose, vel)
        worst = max(worst, int(grid.cost_at(pose.x, pose.y)))
        if poses is not None:
            poses.append(pose)
    return pose, False, worst


# ------------------------------------------------------------------ DWB


def test_dwb_avoids_an_obstacle_straight_ahead() -> None:
    spec = GridSpec(60, 60, 0.05, -1.5, -1.5)
    grid = with_obstacle(spec, 0.45, 0.6, -0.1, 0.1)
    path = polyline_path([(0.0, 0.0), (1.4, 0.0)])
    dwb = DWBController()
    traj, scores = dwb.score(Pose2D(0.0, 0.0, 0.0), Twist2D(0.26, 0.0), path, grid)
    ends = traj.poses[:, -1]
    straight_fast = (np.abs(traj.commands[:, 1]) < 0.06) & (traj.commands[:, 0] > 0.2)
    assert straight_fast.any() and np.all(np.isinf(scores[straight_fast])), (
        "driving into the box must be rejected"
    )
    cmd = dwb.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.26, 0.0), path, grid)
    chosen = dwb.last_trajectory
    assert np.all(grid.cost_at(chosen[:, 0], chosen[:, 1]) < INSCRIBED_INFLATED_OBSTACLE)
    assert np.isfinite(scores).any() and len(ends) == len(scores)
    assert abs(cmd.wz) > 0.05 or cmd.vx < 0.2


def test_dwb_rejects_everything_when_boxed_in() -> None:
    spec = GridSpec(60, 60, 0.05, -1.5, -1.5)
    grid = with_obstacle(spec, -0.05, 0.05, -0.05, 0.05, radius=0.3)  # robot sits inside the inscribed zone
    path = polyline_path([(0.0, 0.0), (1.0, 0.0)])
    with pytest.raises(NoValidControl) as err:
        DWBController().compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), path, grid)
    assert err.value.code == ControllerErrorCode.NO_VALID_CONTROL == 106


def test_dwb_follows_a_path_to_the_goal_in_a_kinematic_loop() -> None:
    spec = GridSpec(80, 80, 0.05, -1.0, -1.0)
    grid = CostGrid(np.zeros(spec.shape, np.uint8), spec)
    path = polyline_path([(0.0, 0.0), (1.5, 0.0), (1.5, 1.5)])
    pose, reached, _ = drive(DWBController(), path, grid, Pose2D(0.0, 0.0, 0.0), goal_yaw=math.pi / 2)
    assert reached, f"DWB stopped at {pose}"
    assert math.hypot(pose.x - 1.5, pose.y - 1.5) <= 0.25
    assert abs(math.remainder(pose.yaw - math.pi / 2, 2 * math.pi)) <= 0.25


def test_dwb_passes_an_obstacle_beside_the_path_without_collision() -> None:
    spec = GridSpec(100, 60, 0.05, -0.5, -1.5)
    grid = with_obstacle(spec, 1.0, 1.2, -0.8, -0.35)
    path = polyline_path([(0.0, 0.0), (3.0, 0.0)])
    _pose, reached, worst = drive(DWBController(), path, grid, Pose2D(0.0, 0.0, 0.0), goal_yaw=0.0)
    assert reached and worst < INSCRIBED_INFLATED_OBSTACLE


# ------------------------------------------------------------------ RPP formulas


def test_rpp_carrot_and_curvature_by_hand() -> None:
    path = polyline_path([(0.0, 0.3), (2.0, 0.3)])
    carrot = find_carrot(path, 0.6)
    assert carrot == pytest.approx([math.sqrt(0.6**2 - 0.3**2), 0.3], abs=1e-9)
    assert curvature_to(carrot) == pytest.approx(2 * 0.3 / 0.36)
    assert find_carrot(path[:3], 5.0) == pytest.approx(path[2, :2])  # path shorter than lookahead → its end


def test_rpp_regulations_by_hand() -> None:
    p = RPPParams()
    # radius 0.5 m < 0.9 m: v = 0.5·(1 − 0.4/0.9) = 0.2778; free cell so no cost scaling
    assert regulated_speed(p, 2.0, 0) == pytest.approx(0.5 * (1 - 0.4 / 0.9))
    # radius 2 m: no curvature scaling; cost 126 → d = ln 2 / 3 + 0.22 = 0.451 m < 0.6 → v·d/0.6
    d = obstacle_distance_from_cost(126, 0.22, 3.0)
    assert d == pytest.approx(math.log(2) / 3 + 0.22)
    assert regulated_speed(p, 0.5, 126) == pytest.approx(0.5 * d / 0.6)
    # both scalings floor at regulated_linear_scaling_min_speed 0.25
    assert regulated_speed(p, 10.0, 250) == pytest.approx(0.25)
    # approach: 0.3 m left → scale 0.3 / 0.6; floored at 0.05
    near_end = polyline_path([(0.0, 0.0), (0.3, 0.0)])
    assert approach_scaled_speed(p, 0.5, near_end) == pytest.approx(0.25)
    very_near = polyline_path([(0.0, 0.0), (0.02, 0.0)])
    assert approach_scaled_speed(p, 0.5, very_near) == pytest.approx(0.05)
    far = polyline_path([(0.0, 0.0), (2.0, 0.0)])
    assert approach_scaled_speed(p, 0.5, far) == 0.5


def test_rpp_command_is_v_times_curvature_and_rotates_on_large_heading_error() -> None:
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = CostGrid(np.zeros(spec.shape, np.uint8), spec)
    rpp = RegulatedPurePursuit(RPPParams(use_collision_detection=False))
    path = polyline_path([(0.0, 0.2), (1.8, 0.2)])
    cmd = rpp.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.5, 0.0), path, grid)
    kappa = curvature_to(rpp.last_carrot)
    assert cmd.wz == pytest.approx(cmd.vx * kappa) and cmd.vx > 0.25
    behind = polyline_path([(0.0, 0.0), (-1.5, 0.0)])
    turn = rpp.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), behind, grid)
    assert turn.vx == 0.0 and abs(turn.wz) == pytest.approx(3.2 * DT)  # rotate, limited by max_angular_accel


def test_rpp_reaches_the_goal_and_its_heading_in_a_kinematic_loop() -> None:
    spec = GridSpec(100, 100, 0.05, -1.0, -1.0)
    grid = CostGrid(np.zeros(spec.shape, np.uint8), spec)
    path = polyline_path([(0.0, 0.0), (2.0, 0.0), (2.0, 2.0)])
    pose, reached, _ = drive(RegulatedPurePursuit(), path, grid, Pose2D(0.0, 0.0, 0.0), goal_yaw=math.pi)
    assert reached, f"RPP stopped at {pose}"
    assert abs(math.remainder(pose.yaw - math.pi, 2 * math.pi)) <= 0.25


def _rpp_near_goal(stateful: bool) -> tuple[RegulatedPurePursuit, CostGrid, np.ndarray]:
    """RPP that just started its final turn at 0.2 m from a goal whose heading is π/2 (robot faces 0)."""
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = CostGrid(np.zeros(spec.shape, np.uint8), spec)
    rpp = RegulatedPurePursuit(RPPParams(use_collision_detection=False, stateful=stateful))
    path = polyline_path([(0.0, 0.0), (0.2, 0.0)])
    path[-1, 2] = math.pi / 2
    first = rpp.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), path, grid)
    assert first.vx == 0.0 and first.wz > 0.0  # inside goal_dist_tol: turning onto the goal heading
    return rpp, grid, path


def test_stateful_rpp_keeps_turning_to_the_goal_heading_after_drifting_out_of_tolerance() -> None:
    rpp, grid, path = _rpp_near_goal(stateful=True)
    drifted = Pose2D(-0.1, 0.0, 0.3)  # 0.3 m from the goal: outside goal_dist_tol, goal point ahead
    cmd = rpp.compute_velocity(drifted, Twist2D(0.0, 0.5), path, grid)
    assert cmd.vx == 0.0 and cmd.wz > 0.0, "turned back toward the goal point instead of its heading"
    rpp.reset()  # a new goal forgets the latch
    cmd = rpp.compute_velocity(drifted, Twist2D(0.0, 0.0), path, grid)
    assert cmd.vx > 0.0, "the latch survived reset()"


def test_stateless_rpp_drives_back_toward_the_goal_point_as_nav2_jazzy_does() -> None:
    rpp, grid, path = _rpp_near_goal(stateful=False)
    cmd = rpp.compute_velocity(Pose2D(-0.1, 0.0, 0.3), Twist2D(0.0, 0.0), path, grid)
    assert cmd.vx > 0.0  # back toward the goal point, away from the final turn


def test_rpp_creeps_on_to_the_goal_when_the_final_turn_is_blocked_where_it_stopped() -> None:
    """0.2 m short of the goal a turn on the spot would swing the body into an obstacle (simulated
    here: every turn on the spot collides, after any step, and every arc is free): creep on toward
    the goal point, slowly; at the goal point itself, with the turn still blocked, turn along a tight
    arc ahead, else behind; with both arcs blocked too, turn on the spot after all (refusing ended
    the navigation)."""
    rpp, grid, path = _rpp_near_goal(stateful=True)
    rpp.params = RPPParams(stateful=True)  # collision detection on
    rpp.moves.final_turn = lambda *args: None  # type: ignore[method-assign]
    rpp.moves.collision_ahead = lambda robot, cmd, *args: cmd.vx == 0.0  # type: ignore[method-assign]
    creep = rpp.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), path, grid)
    assert creep.vx == pytest.approx(rpp.params.min_approach_linear_velocity) and abs(creep.wz) < 1e-9
    turn = float(path[-1, 2])
    arc = rpp.compute_velocity(Pose2D(0.2, 0.0, 0.0), Twist2D(0.0, 0.0), path, grid)
    assert arc.vx == pytest.approx(rpp.params.min_approach_linear_velocity)
    assert arc.wz == pytest.approx(math.copysign(arc.vx / FINAL_ARC_RADIUS, turn))
    rpp.moves.collision_ahead = lambda robot, cmd, *args: cmd.vx >= 0.0  # type: ignore[method-assign]
    assert rpp.compute_velocity(Pose2D(0.2, 0.0, 0.0), Twist2D(0.0, 0.0), path, grid).vx < 0.0
    rpp.moves.collision_ahead = lambda robot, cmd, *args: True  # type: ignore[method-assign]
    last_resort = rpp.compute_velocity(Pose2D(0.2, 0.0, 0.0), Twist2D(0.0, 0.0), path, grid)
    assert last_resort.vx == 0.0 and last_resort.wz > 0.0  # every escape blocked: the turn on the spot


def test_rpp_stops_a_clean_final_turn_when_a_new_scan_puts_an_obstacle_in_its_sweep() -> None:
    """A final turn that kept the waffle's box off lethal cells when it began is finished without
    being judged again from each pose (that made RPP dither), but it is checked again for cells a
    new scan adds: a cell that appears where the rear corner is about to pass stops the turn the
    same way round, and RPP chooses again."""
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = CostGrid(np.zeros(spec.shape, np.uint8), spec)
    rpp = RegulatedPurePursuit(RPPParams(stateful=True), CircleFootprint(0.22, PolygonFootprint(WAFFLE_BOX)))
    path = polyline_path([(-0.1, 0.0), (0.0, 0.0)])
    path[-1, 2] = math.pi / 2
    here = Pose2D(0.0, 0.0, 0.0)
    assert rpp.compute_velocity(here, Twist2D(0.0, 0.0), path, grid).wz > 0.0  # left, the short way
    corner = 0.25 * np.array([math.cos(math.radians(-169.0)), math.sin(math.radians(-169.0))])
    mx, my = spec.world_to_cell(np.array([corner[0]]), np.array([corner[1]]))
    costs = grid.costs.copy()
    costs[my[0], mx[0]] = LETHAL_OBSTACLE  # just beyond the rear-left corner, in its sweep to the left
    seen = CostGrid(costs, spec)
    assert rpp.compute_velocity(here, Twist2D(0.0, 0.16), path, grid).wz > 0.0  # committed
    again = rpp.compute_velocity(here, Twist2D(0.0, 0.32), path, seen)
    assert not (again.vx == 0.0 and again.wz > 0.0), again


def test_rpp_brakes_an_in_place_turn_to_stop_on_its_target() -> None:
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = CostGrid(np.zeros(spec.shape, np.uint8), spec)
    rpp = RegulatedPurePursuit(RPPParams(use_collision_detection=False))
    path = polyline_path([(0.0, 0.0), (0.1, 0.0)])
    path[-1, 2] = 0.05  # 0.05 rad to go while turning at full speed
    cmd = rpp.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 1.8), path, grid)
    assert cmd.wz == pytest.approx(1.8 - 3.2 * DT)  # braking as hard as max_angular_accel allows
    path[-1, 2] = 0.005
    slow = rpp.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.2), path, grid)
    assert slow.wz == pytest.approx(math.sqrt(2 * 3.2 * 0.005))  # what still stops on the target


def test_rpp_detects_a_collision_before_the_carrot() -> None:
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = with_obstacle(spec, 0.27, 0.37, -0.3, 0.3)  # inscribed from x = 0.05: within the closest carrot
    path = polyline_path([(0.0, 0.0), (1.8, 0.0)])
    with pytest.raises(NoValidControl):
        RegulatedPurePursuit().compute_velocity(Pose2D(0.01, 0.0, 0.0), Twist2D(0.5, 0.0), path, grid)
    far = with_obstacle(spec, 1.5, 1.6, -0.3, 0.3)  # beyond the carrot: no alarm
    RegulatedPurePursuit().compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.5, 0.0), path, far)


def test_rpp_takes_a_closer_carrot_when_the_arc_to_the_far_one_cuts_a_corner() -> None:
    """A free path bends left around a block; the arc to the carrot 0.9 m ahead cuts through the
    block's inscribed band, the one to a carrot 0.45 m ahead (on the straight part) does not."""
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = with_obstacle(spec, 0.2, 0.55, 0.38, 0.9)
    path = polyline_path([(0.0, 0.0), (0.8, 0.0), (0.8, 1.2)])
    mx, my = spec.world_to_cell(path[:, 0], path[:, 1])
    assert (grid.costs[my, mx] < 253).all(), "the path itself must be free"
    params = RPPParams(lookahead_dist=0.9, max_allowed_time_to_collision_up_to_carrot=3.0)  # to the carrot
    far_arc = RegulatedPurePursuit(params, footprint=None)
    arc = Twist2D(0.33, 0.33 * 2 * 0.4123 / 0.81)
    assert far_arc.moves.collision_ahead(Pose2D(0.0, 0.0, 0.0), arc, 0.9, grid)
    rpp = RegulatedPurePursuit(params)
    cmd = rpp.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.5, 0.0), path, grid)
    assert cmd.vx > 0.0 and abs(cmd.wz) < 0.05, cmd
    assert np.hypot(*rpp.last_carrot) == pytest.approx(0.45)


def test_rpp_stops_checking_for_collisions_where_the_goal_tolerance_stops_the_robot() -> None:
    """The band around a block begins 0.12 m before a goal placed inside it (a seed goal beside a
    pillar): the robot will stop 0.25 m before the goal, so the band beyond does not block it."""
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = with_obstacle(spec, 0.7, 0.8, -0.3, 0.3)  # inscribed band from x = 0.48
    rpp = RegulatedPurePursuit(RPPParams(max_allowed_time_to_collision_up_to_carrot=3.0))
    ahead = Twist2D(0.25, 0.0)
    assert rpp.moves.collision_ahead(Pose2D(0.0, 0.0, 0.0), ahead, 0.6, grid)
    assert not rpp.moves.collision_ahead(Pose2D(0.0, 0.0, 0.0), ahead, 0.6, grid, np.array([0.6, 0.0]))
    path = polyline_path([(0.0, 0.0), (0.6, 0.0)])
    cmd = rpp.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), path, grid)
    assert cmd.vx > 0.0 and np.hypot(*rpp.last_carrot) == pytest.approx(0.6)  # no closer carrot needed


def test_a_round_robot_inside_the_inscribed_band_may_turn_slide_and_back_out_but_not_push_in() -> None:
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = with_obstacle(spec, 0.5, 0.7, -1.0, 1.0)  # a wall at x = 0.5; band from x = 0.28
    fp = CircleFootprint(0.22)

    def collides(start: Pose2D, cmd: Twist2D) -> bool:
        t = np.linspace(0.0, 1.0, 11)
        yaw = start.yaw + cmd.wz * t
        x = start.x + cmd.vx * t * np.cos(yaw)
        y = start.y + cmd.vx * t * np.sin(yaw)
        return motion_collides(fp, grid, x, y, yaw)

    inside = Pose2D(0.32, 0.0, 0.0)
    assert grid.cost_at(inside.x, inside.y) == INSCRIBED_INFLATED_OBSTACLE
    assert not collides(inside, Twist2D(0.0, 1.0)), "a turn on the spot"
    assert not collides(inside, Twist2D(-0.1, 0.0)), "backing out"
    assert not collides(Pose2D(0.32, 0.0, math.pi / 2), Twist2D(0.1, 0.0)), "sliding along the wall"
    assert collides(inside, Twist2D(0.05, 0.0)), "pushing further in"
    outside = Pose2D(0.2, 0.0, 0.0)
    assert collides(outside, Twist2D(0.15, 0.0)), "entering the band from outside"




def test_a_body_outline_keeps_the_corners_of_a_turn_off_lethal_cells() -> None:
    """Centre 0.23 m from a wall (outside the 0.22 m band): the circle alone lets the robot turn
    on the spot, but the waffle's rear corners (0.238 m from the axle) would swing into the wall;
    once the body already touches, it may not go deeper (the next test)."""
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = with_obstacle(spec, 0.5, 0.7, -1.0, 1.0)  # lethal cells from x = 0.5
    yaw = np.linspace(0.0, 2.0 * math.pi, 37)

    def turn_collides(fp: CircleFootprint, x: float, heading: float) -> bool:
        return motion_collides(fp, grid, np.full_like(yaw, x), np.zeros_like(yaw), heading + yaw)

    circle, waffle = CircleFootprint(0.22), CircleFootprint(0.22, PolygonFootprint(WAFFLE_BOX))
    assert grid.cost_at(0.27, 0.0) < INSCRIBED_INFLATED_OBSTACLE
    assert not turn_collides(circle, 0.27, 0.0)
    assert turn_collides(waffle, 0.27, 0.0), "a rear corner reaches x = 0.508 m"
    assert not turn_collides(waffle, 0.20, 0.0), "0.30 m from the wall the corners clear it"
    assert turn_collides(waffle, 0.35, math.pi), "rear corners already 4.7 cm in may not swing in deeper"


def test_an_inset_moves_every_edge_inward_whatever_the_winding() -> None:
    inner = ((-0.172, -0.108), (0.044, -0.108), (0.044, 0.108), (-0.172, 0.108))
    box = PolygonFootprint(WAFFLE_BOX)
    assert np.allclose(box.inset(0.025).points, inner)
    assert np.allclose(PolygonFootprint(WAFFLE_BOX[::-1]).inset(0.025).points, inner[::-1])


def test_a_body_already_against_a_wall_may_slide_along_or_back_out_but_not_turn_a_corner_in() -> None:
    """The wedge at the centre pillar: centre 0.12 m from a wall (inside the 0.22 m band), heading
    along it, the right side 1.3 cm into the wall's lethal cells. A left turn on the spot keeps the
    centre's clearance, so the circle's rules allow it, but it swings the rear corner (0.197 m behind
    the axle) into the wall, and so does steering left while driving on; driving or backing along
    the wall keeps the side where it is."""
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = with_obstacle(spec, 0.5, 0.7, -1.0, 1.0)  # lethal cells from x = 0.5
    x0, heading = 0.38, math.pi / 2.0  # the right side at x = 0.513
    waffle = CircleFootprint(0.22, PolygonFootprint(WAFFLE_BOX))
    steps = np.linspace(0.0, 1.0, 21)

    def collides(vx: float, wz: float, fp: CircleFootprint = waffle) -> bool:
        yaw = heading + wz * steps
        if abs(wz) > 1e-9:
            x = x0 + vx / wz * (np.sin(yaw) - math.sin(heading))
            y = -vx / wz * (np.cos(yaw) - math.cos(heading))
        else:
            x, y = x0 + vx * steps * math.cos(heading), vx * steps * math.sin(heading)
        return motion_collides(fp, grid, x, y, yaw)

    assert grid.cost_at(x0, 0.0) == INSCRIBED_INFLATED_OBSTACLE
    assert not collides(0.0, 0.5, CircleFootprint(0.22)), "the circle alone lets it turn"
    assert collides(0.0, 0.5), "the rear corner swings into the wall"
    assert collides(0.25, 0.97), "the wedge seen in CI: the rear corner swings in while driving on"
    assert not collides(0.2, 0.0), "sliding along the wall"
    assert not collides(-0.2, 0.0), "backing along the wall"

    # 3 cm in, the box inset by one cell clears the wall: a 0.2 rad turn takes the rear corner 3.9 cm
    # further in, beyond that inset, so it collides (insetting by 1.5 cells would let it pass).
    x0 = 0.5 + 0.03 - 0.133
    assert collides(0.0, 0.2)


def test_rpp_facing_into_a_wall_turns_on_the_spot_then_leaves_the_band_without_closing_in() -> None:
    """In the inscribed band beside a wall (lethal from y = 0.22), heading 0.4 rad toward it, with
    the path leaving the band at 20°: every arc to a carrot first bends toward the wall, so RPP turns
    on the spot, then drives out, never closer to the wall than where it started (within the one
    sample per cell of the check, as Nav2 samples)."""
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = with_obstacle(spec, -1.0, 1.5, 0.22, 0.42)
    path = polyline_path([(0.0, 0.0), (1.5, -0.55)])
    start = Pose2D(0.0, 0.0, 0.4)
    assert grid.cost_at(start.x, start.y) == INSCRIBED_INFLATED_OBSTACLE
    first = RegulatedPurePursuit().compute_velocity(start, Twist2D(0.0, 0.0), path, grid)
    assert first.vx == 0.0 and first.wz < 0.0, first
    poses: list[Pose2D] = []
    pose, reached, _ = drive(RegulatedPurePursuit(), path, grid, start, goal_yaw=-0.35, poses=poses)
    assert reached, pose
    assert max(p.y for p in poses) < 0.005


def test_rpp_with_its_back_to_a_wall_steps_away_before_turning_toward_a_path_that_leaves_sideways() -> None:
    """The battery patrol's wedge beside a pillar: centre 0.23 m from a wall behind it (outside the
    0.22 m band), the path leaving 75° to the side. Turning on the spot would swing a rear corner
    (0.238 m from the axle) into the wall, so does every arc, and the behaviors refuse too; RPP creeps
    straight ahead as far as needed, then turns and follows the path without touching the wall."""
    spec = GridSpec(80, 80, 0.05, -2.0, -2.0)
    grid = with_obstacle(spec, 0.5, 0.7, -1.0, 1.0)  # lethal cells from x = 0.5
    waffle = CircleFootprint(0.22, PolygonFootprint(WAFFLE_BOX))
    start = Pose2D(0.27, 0.0, math.pi)
    path = polyline_path([(0.27, 0.0), (0.0, -1.0)])
    yaw = start.yaw + np.linspace(0.0, -1.3, 27)
    assert motion_collides(waffle, grid, np.full_like(yaw, start.x), np.zeros_like(yaw), yaw)
    poses: list[Pose2D] = []
    pose, reached, _ = drive(RegulatedPurePursuit(footprint=waffle), path, grid, start, -1.84, poses=poses)
    assert reached, pose
    xs, ys, yaws = (np.array([getattr(p, f) for p in poses]) for f in ("x", "y", "yaw"))
    assert not waffle.body.collides(waffle.body.cost(grid, xs, ys, yaws)).any()


@pytest.mark.parametrize("heading", [-3.14, -2.36, -1.57, -0.79, 0.0, 0.79])
def test_rpp_leaves_the_charging_spot_beside_a_pillar_along_the_planned_path(heading: float) -> None:
    """CI red again: the battery patrol stopped to charge at (-1.22, -0.742), within the station's
    goal tolerance and 0.21 m from the cells of the pillar at (-1.1, -1.1), at the edge of its
    inscribed band. NavFn's path to location3 runs round the pillar along that ragged edge, and
    every pose 5 cm on was "in the band": no valid command, for 1,600 s of retries. The waffle's
    circle may now enter the band by BAND_ENTRY while its box keeps off lethal cells."""
    grid = tb3_world_grid()
    waffle = CircleFootprint(0.22, PolygonFootprint(WAFFLE_BOX))
    start = Pose2D(-1.22, -0.742, heading)
    path = NavfnPlanner(NavfnParams(tolerance=0.5)).create_plan(
        start, Pose2D(-1.43, -1.34, math.pi), grid.costs, grid.spec)
    poses: list[Pose2D] = []
    pose, reached, _ = drive(RegulatedPurePursuit(RPPParams(stateful=True), footprint=waffle), path, grid,
                             start, float(path[-1, 2]), poses=poses, max_steps=1500)
    assert reached, pose
    xs, ys, yaws = (np.array([getattr(p, f) for p in poses]) for f in ("x", "y", "yaw"))
    assert not waffle.body.collides(waffle.body.cost(grid, xs, ys, yaws)).any()


@pytest.mark.parametrize(("start", "goal"), [
    ((-1.456, -1.058, -1.58), (-1.475, -1.375)), ((-1.478, -1.106, -1.55), (-1.475, -1.375)),
    ((-1.46, -1.074, -1.5), (-1.475, -1.375)), ((-1.48, -1.0, -1.6), (-1.475, -1.375)),
    ((-1.44, -1.08, -1.45), (-1.475, -1.375)), ((-1.479, -1.229, -1.46), (-1.43, -1.34)),
    ((-1.43, -1.34, -1.57), (-1.43, -1.34)),
])
def test_rpp_never_swings_the_body_into_the_pillar_on_the_final_turn_at_location3(
        start: tuple[float, float, float], goal: tuple[float, float]) -> None:
    """The battery patrol wedged at location3 (CI, and 2 runs in 18 of a loop): it arrived from the
    station facing south, 0.36 m west of the pillar at (-1.1, -1.1), within goal_dist_tol of the
    goal, and turned clockwise onto the goal heading (west). The turn was never checked: the check
    stopped at the first pose within goal_dist_tol, here the first one. Its rear-left corner (0.238 m
    from the axle) swung into the pillar and stuck. Now the whole turn is checked; blocked, the robot
    creeps on to the goal point and turns there; where even that turn on the spot is blocked (at
    location3 itself: the rear corner would pass within 2 cm of the pillar, less than a cell), it
    turns along a tight arc. The turtlebot3_world static costmap; starts seen in the runs and around
    them; goals: the planner's for location3 (moved out of the inscribed band) or location3 itself."""
    grid = tb3_world_grid()
    waffle = CircleFootprint(0.22, PolygonFootprint(WAFFLE_BOX))
    path = polyline_path([start[:2], goal])
    poses: list[Pose2D] = []
    pose, reached, _ = drive(RegulatedPurePursuit(RPPParams(stateful=True), footprint=waffle), path, grid,
                             Pose2D(*start), math.pi, poses=poses)
    assert reached, pose
    xs, ys, yaws = (np.array([getattr(p, f) for p in poses]) for f in ("x", "y", "yaw"))
    assert not waffle.body.collides(waffle.body.cost(grid, xs, ys, yaws)).any()


# ------------------------------------------------------------------ path handler


def test_path_handler_prunes_cuts_and_transforms() -> None:
    spec = GridSpec(40, 40, 0.05, -1.0, -1.0)  # 2 m local window around the odom origin
    grid = CostGrid(np.zeros(spec.shape, np.uint8), spec)
    handler = PathHandler()
    handler.set_plan(polyline_path([(10.0, 5.0), (14.0, 5.0)]))  # map frame
    odom_from_map = Pose2D(-10.0, -5.0, 0.0)  # the map frame's pose in odom
    local = handler.local_path(Pose2D(10.5, 5.0, 0.0), odom_from_map, grid)
    assert local[0, 0] == pytest.approx(0.5)  # poses behind the robot are pruned
    assert local[-1, 0] < 1.0 and len(local) == 10  # cut at the local costmap edge (x < 1.0)
    assert handler.distance_to_goal(Pose2D(10.5, 5.0, 0.0)) == pytest.approx(3.5)
    with pytest.raises(InvalidPath):
        handler.set_plan(np.zeros((0, 3)))


def test_plugins_are_selected_by_id() -> None:
    plugins = ControllerPlugins(
        {"FollowPath": DWBController()},
        {"general_goal_checker": SimpleGoalChecker()},
        {"progress_checker": SimpleProgressChecker()},
    )
    controller, _, _ = plugins.select("", "general_goal_checker", "")
    assert isinstance(controller, DWBController)
    with pytest.raises(InvalidController) as err:
        plugins.select("Nope", "", "")
    assert err.value.code == ControllerErrorCode.INVALID_CONTROLLER


# ------------------------------------------------------------------ checkers


def test_stateful_goal_checker_latches_xy() -> None:
    goal = Pose2D(1.0, 0.0, 0.0)
    still = Twist2D(0.0, 0.0)
    checker = SimpleGoalChecker()
    assert not checker.is_goal_reached(Pose2D(0.9, 0.0, 1.0), goal, still)  # xy ok, yaw off
    assert checker.xy_reached
    assert checker.is_goal_reached(Pose2D(0.6, 0.0, 0.1), goal, still)  # drifted out while rotating: latched
    stateless = SimpleGoalChecker(GoalCheckerParams(stateful=False))
    stateless.is_goal_reached(Pose2D(0.9, 0.0, 1.0), goal, still)
    assert not stateless.is_goal_reached(Pose2D(0.6, 0.0, 0.1), goal, still)
    checker.reset()
    assert not checker.is_goal_reached(Pose2D(0.6, 0.0, 0.1), goal, still)
    symmetric = SimpleGoalChecker(GoalCheckerParams(symmetric_yaw_tolerance=True))
    assert symmetric.is_goal_reached(Pose2D(1.0, 0.0, math.pi - 0.1), goal, still)


def test_stopped_goal_checker_needs_low_velocity() -> None:
    goal = Pose2D(0.0, 0.0, 0.0)
    checker = StoppedGoalChecker()
    assert not checker.is_goal_reached(goal, goal, Twist2D(0.3, 0.0))
    assert not checker.is_goal_reached(goal, goal, Twist2D(0.0, 0.3))
    assert checker.is_goal_reached(goal, goal, Twist2D(0.2, 0.2))


def test_progress_checker_semantics() -> None:
    checker = SimpleProgressChecker()
    assert checker.check(Pose2D(0.0, 0.0, 0.0), 0.0)
    assert checker.check(Pose2D(0.4, 0.0, 0.0), 9.0)  # within radius, within allowance
    assert not checker.check(Pose2D(0.4, 0.0, 3.0), 10.5)  # rotating is not progress
    assert checker.check(Pose2D(0.6, 0.0, 0.0), 11.0)  # left the radius: new window
    assert checker.check(Pose2D(0.6, 0.0, 0.0), 20.9)
    assert not checker.check(Pose2D(0.6, 0.0, 0.0), 21.1)


def test_final_rotation_at_goal_is_not_lack_of_progress() -> None:
    """The controller-server protocol: reset the progress checker while xy of the goal is reached."""
    goal = Pose2D(0.0, 0.0, math.pi)
    goal_checker, progress = (
        SimpleGoalChecker(GoalCheckerParams(yaw_goal_tolerance=0.05)),
        SimpleProgressChecker(),
    )
    pose = Pose2D(0.1, 0.0, 0.0)
    assert progress.check(pose, 0.0)
    turning = False
    for k in range(400):  # 40 s of slow rotation at 0.1 rad/s inside the xy tolerance
        now = 0.1 * k
        if goal_checker.is_goal_reached(pose, goal, Twist2D(0.0, 0.1)):
            break
        if goal_checker.xy_reached and not turning:
            turning = True
            progress.reset()
        assert progress.check(pose, now, turning=turning), f"no progress while turning at the goal, t={now}"
        pose = Pose2D(pose.x, pose.y, pose.yaw + 0.01)
    else:
        pytest.fail("never reached the goal heading")


def test_a_robot_that_cannot_turn_at_the_goal_fails_to_make_progress() -> None:
    """Wedged inside the xy tolerance (commanded to turn, but only wobbling): FAILED_TO_MAKE_PROGRESS
    after movement_time_allowance, not a final rotation that never ends."""
    progress = SimpleProgressChecker()
    progress.reset()
    results = [progress.check(Pose2D(0.1, 0.0, 0.1 * math.sin(k)), 0.1 * k, turning=True) for k in range(120)]
    assert all(results[:100]) and not results[-1]
