"""Regulated Pure Pursuit (nav2_regulated_pure_pursuit_controller), one cycle at a time.

Pure pursuit steers on the arc through a carrot on the path at the lookahead distance L:
curvature κ = 2y/L² with (x, y) the carrot in the robot frame, ω = v·κ. The speed is then
regulated: tight arcs (radius below ``regulated_linear_scaling_min_radius``) scale it by
radius/min_radius, high costs by gain·d/``cost_scaling_dist`` where d is the obstacle distance
recovered from the inflation formula, both floored at ``regulated_linear_scaling_min_speed``;
near the path end it ramps down to ``min_approach_linear_velocity``. Large heading errors and
the final goal heading are handled by rotating in place (with ``max_angular_accel``). The
command is simulated ahead up to the carrot, at most ``max_allowed_time_to_collision_up_to_carrot``
s, and a collision raises NoValidControl.

A blocked arc is retried toward a carrot at half the distance, down to two cells: a closer carrot
lies on an arc nearer the path, which the planner kept free, so the robot follows a bend instead of
stopping where the arc to the far carrot cuts the corner (Nav2 raises at once). When even that arc
is blocked, the robot faces away from the path's direction beside an obstacle; it turns on the spot
toward the closest carrot first, and where that turn would swing its body into the obstacle (its
back to a pillar), it steps straight ahead, or back, until the turn is free.

The collision check also ends at the first simulated pose within ``goal_dist_tol`` of the goal: the
robot stops there to turn onto the goal heading, so the rest of the arc is never driven. Without
that cut, a goal a few centimetres outside an obstacle's inscribed band (the seed's location3 beside
a pillar) is unreachable: the local costmap's lidar cells put the path's last stretch inside the
band, and every arc toward the goal "collides" beyond the point where the robot would have stopped.
A robot that finds itself inside the band may still turn and move out (``motion_collides``). The
final turn itself is checked to its end, not for the first second of a turn that starts slowly (and
never cut short by that goal rule: it starts within ``goal_dist_tol``). Where the robot stopped to
turn (up to ``goal_dist_tol`` short of such a goal, nearer the obstacle than the goal itself), a
final turn that would swing the body into it is not forced: the robot creeps on toward the goal
point at ``min_approach_linear_velocity`` and turns there (seen: the seed patrol wedged at location3,
its rear corner swung into the pillar by an unchecked turn, every recovery refused).

Two more choices beyond Nav2 Jazzy's RPP, both against the rotate/drive limit cycle at the goal:
``stateful`` (Nav2 PR #5167, later releases) keeps rotating to the goal heading once the goal was
within ``goal_dist_tol``, even when localization jitter or the turn itself moves the robot just
outside it (otherwise it turns back toward the goal point, then again to the heading, ...); and
in-place rotations brake to stop on their target angle, |ω| <= sqrt(2·max_angular_accel·|angle|),
instead of overshooting it at ``rotate_to_heading_angular_vel`` (ros-navigation/navigation2#4937).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_stack.core.control.base import (
    CircleFootprint,
    CostGrid,
    Footprint,
    NoValidControl,
    Twist2D,
    motion_collides,
    turn_in_place,
)
from nav_stack.core.geometry import FloatArray, Pose2D, path_length, to_frame
from nav_stack.core.grid import FREE_SPACE, MAX_NON_OBSTACLE, NO_INFORMATION

#: rad: heading error toward the closest carrot below which turning on the spot cannot help
ALIGNED = 0.05
#: m a blocked turn may be freed by a straight step (RegulatedPurePursuit._step_clear), and how far
#: off the path the robot may be for it: the step is a way out of a corner, not a detour.
STEP_CLEAR_DISTANCE, STEP_CLEAR_MAX_OFFSET = 0.10, 0.15
#: m: radius of the arc that turns the robot onto the goal heading where a turn on the spot is blocked
FINAL_ARC_RADIUS = 0.15


@dataclass(frozen=True)
class RPPParams:
    """RPP knobs with Nav2's code defaults; ``inscribed_radius`` and ``goal_dist_tol`` come from the
    costmap and the goal checker in Nav2, ``controller_frequency`` from the controller server."""

    desired_linear_vel: float = 0.5
    lookahead_dist: float = 0.6
    min_lookahead_dist: float = 0.3
    max_lookahead_dist: float = 0.9
    lookahead_time: float = 1.5
    use_velocity_scaled_lookahead_dist: bool = False
    rotate_to_heading_angular_vel: float = 1.8
    use_rotate_to_heading: bool = True
    rotate_to_heading_min_angle: float = 0.785
    max_angular_accel: float = 3.2
    min_approach_linear_velocity: float = 0.05
    approach_velocity_scaling_dist: float = 0.6
    use_regulated_linear_velocity_scaling: bool = True
    regulated_linear_scaling_min_radius: float = 0.9
    regulated_linear_scaling_min_speed: float = 0.25
    use_cost_regulated_linear_velocity_scaling: bool = True
    cost_scaling_dist: float = 0.6
    cost_scaling_gain: float = 1.0
    inflation_cost_scaling_factor: float = 3.0
    use_collision_detection: bool = True
    max_allowed_time_to_collision_up_to_carrot: float = 1.0
    inscribed_radius: float = 0.22
    goal_dist_tol: float = 0.25
    controller_frequency: float = 20.0
    stateful: bool = True

    def __post_init__(self) -> None:
        if not 0.0 < self.min_lookahead_dist <= self.max_lookahead_dist:
            raise ValueError(
                f"RPPParams lookahead bounds invalid: min {self.min_lookahead_dist}, "
                f"max {self.max_lookahead_dist}"
            )
        for name in (
            "desired_linear_vel",
            "lookahead_dist",
            "controller_frequency",
            "inflation_cost_scaling_factor",
            "regulated_linear_scaling_min_radius",
            "cost_scaling_dist",
            "approach_velocity_scaling_dist",
        ):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"RPPParams.{name} must be > 0, got {getattr(self, name)}")


def find_carrot(path: FloatArray, lookahead: float) -> FloatArray:
    """Point (x, y) at distance ``lookahead`` from the origin on a robot-frame path (its end if closer).

    The first pose at or beyond the lookahead and its predecessor bound a segment that crosses
    the lookahead circle; the crossing is returned (Nav2's use_interpolation).
    """
    dist = np.hypot(path[:, 0], path[:, 1])
    beyond = np.nonzero(dist >= lookahead)[0]
    if len(beyond) == 0:
        return np.asarray(path[-1, :2], dtype=np.float64)
    i = int(beyond[0])
    if i == 0:
        return np.asarray(path[0, :2], dtype=np.float64)
    a, b = path[i - 1, :2], path[i, :2]
    d = b - a
    qa, qb, qc = float(d @ d), 2.0 * float(a @ d), float(a @ a) - lookahead**2
    t = (-qb + math.sqrt(max(qb * qb - 4.0 * qa * qc, 0.0))) / (2.0 * qa) if qa > 0.0 else 1.0
    return np.asarray(a + min(max(t, 0.0), 1.0) * d, dtype=np.float64)


def curvature_to(carrot: FloatArray) -> float:
    """Pure pursuit curvature 2y/L² (1/m) of the arc from the robot through the carrot."""
    l2 = float(carrot @ carrot)
    return 2.0 * float(carrot[1]) / l2 if l2 > 1e-9 else 0.0


def obstacle_distance_from_cost(cost: int, inscribed_radius: float, scaling_factor: float) -> float:
    """Invert Nav2 inflation, cost = 252·exp(-k·(d − r)): d = −ln(cost/252)/k + r (m)."""
    return -math.log(cost / MAX_NON_OBSTACLE) / scaling_factor + inscribed_radius


def regulated_speed(p: RPPParams, curvature: float, pose_cost: int) -> float:
    """Desired speed after the curvature and cost regulations (before approach scaling)."""
    curvature_vel = cost_vel = p.desired_linear_vel
    radius = abs(1.0 / curvature) if curvature != 0.0 else math.inf
    if p.use_regulated_linear_velocity_scaling and radius < p.regulated_linear_scaling_min_radius:
        curvature_vel *= (
            1.0 - abs(radius - p.regulated_linear_scaling_min_radius) / p.regulated_linear_scaling_min_radius
        )
    if p.use_cost_regulated_linear_velocity_scaling and pose_cost not in (NO_INFORMATION, FREE_SPACE):
        d = obstacle_distance_from_cost(pose_cost, p.inscribed_radius, p.inflation_cost_scaling_factor)
        if d < p.cost_scaling_dist:
            cost_vel *= p.cost_scaling_gain * d / p.cost_scaling_dist
    if not (p.use_regulated_linear_velocity_scaling or p.use_cost_regulated_linear_velocity_scaling):
        return p.desired_linear_vel
    return max(min(curvature_vel, cost_vel), p.regulated_linear_scaling_min_speed)


def approach_scaled_speed(p: RPPParams, speed: float, path: FloatArray) -> float:
    """Slow down over the last ``approach_velocity_scaling_dist`` of the (robot-frame) path."""
    if path_length(path) + math.hypot(*path[0, :2]) >= p.approach_velocity_scaling_dist:
        return speed
    scaling = math.hypot(*path[-1, :2]) / p.approach_velocity_scaling_dist
    approach = (
        p.min_approach_linear_velocity
        if speed * scaling < p.min_approach_linear_velocity
        else speed * scaling
    )
    return min(speed, approach)


class RegulatedPurePursuit:
    """RPP controller; keeps only the last carrot for visualisation."""

    def __init__(self, params: RPPParams | None = None, footprint: Footprint | None = None) -> None:
        self.params = params or RPPParams()
        self.footprint: Footprint = footprint or CircleFootprint(self.params.inscribed_radius)
        self.last_carrot = np.zeros(2)
        self._heading_goal: tuple[float, float] | None = None  # goal (x, y) whose heading is latched

    def reset(self) -> None:
        self.last_carrot = np.zeros(2)
        self._heading_goal = None

    def _rotate(self, angle: float, velocity: Twist2D) -> Twist2D:
        """Turn in place toward ``angle`` (rad, robot frame) within the acceleration limit, braking
        so as to stop on it."""
        p = self.params
        return Twist2D(0.0, turn_in_place(angle, velocity.wz, p.rotate_to_heading_angular_vel,
                                          p.max_angular_accel, 1.0 / p.controller_frequency))

    def _rotating_to_goal_heading(self, goal_world: FloatArray, goal_local: FloatArray) -> bool:
        """Whether only the final turn onto the goal heading remains (latched per goal if stateful)."""
        p = self.params
        if not p.use_rotate_to_heading:
            return False
        goal_xy = (float(goal_world[0]), float(goal_world[1]))
        latched = self._heading_goal is not None and math.dist(self._heading_goal, goal_xy) < 1e-3
        if p.stateful and latched:
            return True
        if math.hypot(goal_local[0], goal_local[1]) < p.goal_dist_tol:
            self._heading_goal = goal_xy
            return True
        return False

    def compute_velocity(self, robot: Pose2D, velocity: Twist2D, path: FloatArray, grid: CostGrid) -> Twist2D:
        if len(path) == 0:
            raise NoValidControl("empty local path")
        p = self.params
        local = to_frame(path, robot)
        lookahead = p.lookahead_dist
        if p.use_velocity_scaled_lookahead_dist:
            lookahead = min(
                max(abs(velocity.vx) * p.lookahead_time, p.min_lookahead_dist), p.max_lookahead_dist
            )
        closest = 2.0 * grid.spec.resolution
        while True:
            cmd, carrot = self._command(robot, velocity, path, local, lookahead, grid)
            reach = float(np.hypot(*carrot))
            if not p.use_collision_detection:
                return cmd
            if self._rotating_to_goal_heading(path[-1], local[-1]):  # checked to its end, not for 1 s
                if not self._turn_blocked(robot, float(local[-1, 2]), grid):
                    return cmd
                creep = self._creep_to_goal(robot, local[-1], grid, 0.5 * grid.spec.resolution)
                if creep is not None:
                    return creep
                arc = self._arc_onto_heading(robot, float(local[-1, 2]), grid)
                return arc if arc is not None else cmd  # every escape blocked: turn on the spot after all
            if not self._collision_ahead(robot, cmd, reach, grid, path[-1]):
                return cmd
            if lookahead <= closest:
                return self._align_with(carrot, robot, velocity, grid, float(np.hypot(*local[0, :2])))
            lookahead = max(0.5 * lookahead, closest)  # a closer carrot: an arc nearer the (free) path

    def _creep_to_goal(self, robot: Pose2D, goal: FloatArray, grid: CostGrid, done: float) -> Twist2D | None:
        """The final turn is blocked where the robot stopped (up to ``goal_dist_tol`` short of the goal,
        its body would swing into an obstacle): creep on along the arc to the goal position, which the
        planner put clear of obstacles, and turn there. None when already within ``done`` (m) of it,
        when it lies behind, or when that arc is blocked too."""
        distance = float(np.hypot(goal[0], goal[1]))
        if distance > done and goal[0] > 0.0:
            speed = self.params.min_approach_linear_velocity
            creep = Twist2D(speed, speed * curvature_to(goal[:2]))
            if not self._collision_ahead(robot, creep, distance, grid):
                return creep
        return None

    def _arc_onto_heading(self, robot: Pose2D, angle: float, grid: CostGrid) -> Twist2D | None:
        """Even at the goal point the turn on the spot onto the goal heading (``angle`` rad, robot
        frame) is blocked: turn along a tight arc instead, ahead if that is free, else back, at
        ``min_approach_linear_velocity``. The centre moves while the body turns, so the corners sweep
        less near the obstacle beside the robot; the goal tolerance is already met (stateful goal
        checkers keep it met). Seen at the seed's location3, 0.408 m from a pillar's centre: a turn
        on the spot passes the waffle's rear corner within 2 cm of the pillar, less than a cell,
        while an arc of FINAL_ARC_RADIUS passes it by 6 cm or more. None when both arcs are blocked:
        the caller then turns on the spot after all, as before this check existed. Refusing ended the
        navigation with 104 (CI: the seed tree's patrol failed at location3), while the turn, judged
        by cells that make a 2 cm clearance look blocked, succeeds in most such runs."""
        speed = self.params.min_approach_linear_velocity
        for direction in (1.0, -1.0):
            arc = Twist2D(direction * speed, math.copysign(speed / FINAL_ARC_RADIUS, angle))
            if not self._collision_ahead(robot, arc, math.inf, grid, None, abs(angle) / abs(arc.wz)):
                return arc
        return None

    def _turn_blocked(self, robot: Pose2D, turn: float, grid: CostGrid) -> bool:
        """Whether turning on the spot by ``turn`` (rad, + = left) swings the body into an obstacle
        anywhere along the turn (a turn started slowly is not checked for its first second only)."""
        rate = self.params.rotate_to_heading_angular_vel
        probe = Twist2D(0.0, math.copysign(rate, turn))
        return self._collision_ahead(robot, probe, 0.0, grid, None, abs(turn) / rate)

    def _align_with(self, carrot: FloatArray, robot: Pose2D, velocity: Twist2D, grid: CostGrid,
                    offset: float) -> Twist2D:
        """Even the arc to the closest carrot is blocked: turn on the spot toward that carrot (the
        path's direction right there), from where the arcs run along the path. When the turn is
        blocked too, step straight away from what blocks it (:meth:`_step_clear`); raise if already
        facing the carrot or if no step is free either. ``offset``: the robot's distance (m) from the
        path."""
        angle = math.atan2(carrot[1], carrot[0])
        if abs(angle) > ALIGNED:
            turn = self._rotate(angle, velocity)
            if not self._collision_ahead(robot, turn, 0.0, grid):
                return turn
            if offset < STEP_CLEAR_MAX_OFFSET:
                step = self._step_clear(robot, grid)
                if step is not None:
                    return step
        raise NoValidControl("collision ahead on the way to the carrot")

    def _step_clear(self, robot: Pose2D, grid: CostGrid) -> Twist2D | None:
        """A turn on the spot that swings the body into an obstacle: the waffle's rear corners reach
        0.238 m from the axle, so with its back a few centimetres from a pillar it cannot turn toward a
        path that leaves sideways (seen: the battery patrol wedged beside the pillar at (-1.1, -1.1),
        spin and backup refused too). Creep straight ahead, else back, at
        ``min_approach_linear_velocity`` when that is free for STEP_CLEAR_DISTANCE (m); the next
        cycle turns once the corners clear. None when neither way is free."""
        speed = self.params.min_approach_linear_velocity
        for direction in (1.0, -1.0):
            step = Twist2D(direction * speed, 0.0)
            if not self._collision_ahead(robot, step, STEP_CLEAR_DISTANCE, grid):
                return step
        return None

    def _command(self, robot: Pose2D, velocity: Twist2D, path: FloatArray, local: FloatArray,
                 lookahead: float, grid: CostGrid) -> tuple[Twist2D, FloatArray]:
        """The command toward the carrot at ``lookahead`` (m), and that carrot (robot frame)."""
        p = self.params
        carrot = find_carrot(local, lookahead)
        self.last_carrot = carrot
        curvature = curvature_to(carrot)
        goal = local[-1]
        if self._rotating_to_goal_heading(path[-1], goal):
            return self._rotate(float(goal[2]), velocity), carrot
        if p.use_rotate_to_heading and abs(math.atan2(carrot[1], carrot[0])) > p.rotate_to_heading_min_angle:
            return self._rotate(math.atan2(carrot[1], carrot[0]), velocity), carrot
        pose_cost = int(grid.cost_at(robot.x, robot.y))
        speed = approach_scaled_speed(p, regulated_speed(p, curvature, pose_cost), local)
        speed = min(speed, p.desired_linear_vel)
        return Twist2D(speed, speed * curvature), carrot

    def _collision_ahead(self, robot: Pose2D, cmd: Twist2D, carrot_dist: float, grid: CostGrid,
                         goal: FloatArray | None = None, horizon: float | None = None) -> bool:
        """Simulate ``cmd`` in steps of ~one cell until the carrot distance, the first pose within
        ``goal_dist_tol`` of ``goal`` (world x, y), where the robot will stop, or ``horizon`` s
        (default ``max_allowed_time_to_collision_up_to_carrot``)."""
        p = self.params
        horizon = p.max_allowed_time_to_collision_up_to_carrot if horizon is None else horizon
        res = grid.spec.resolution
        if abs(cmd.vx) > 0.01:
            dt = res / abs(cmd.vx)
        elif abs(cmd.wz) > 1e-6:
            dt = 0.5 * res / abs(cmd.wz)
        else:
            dt = horizon
        t = dt * np.arange(0, int(horizon / dt) + 1)
        yaw = robot.yaw + cmd.wz * t
        if abs(cmd.wz) > 1e-9:
            x = robot.x + cmd.vx / cmd.wz * (np.sin(yaw) - math.sin(robot.yaw))
            y = robot.y - cmd.vx / cmd.wz * (np.cos(yaw) - math.cos(robot.yaw))
        else:
            x = robot.x + cmd.vx * t * math.cos(robot.yaw)
            y = robot.y + cmd.vx * t * math.sin(robot.yaw)
        keep = np.hypot(x - robot.x, y - robot.y) < max(carrot_dist, res)
        if goal is not None:  # where it stops to turn; a robot already there (turning) is checked all along
            arrived = np.nonzero(np.hypot(x - goal[0], y - goal[1]) < p.goal_dist_tol)[0]
            if len(arrived) and arrived[0] > 0:
                keep[arrived[0] + 1:] = False
        keep[0] = True
        return motion_collides(self.footprint, grid, x[keep], y[keep], yaw[keep])
