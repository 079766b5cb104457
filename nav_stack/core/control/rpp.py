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

The collision checks and the moves for tight spots (a final turn beside a pillar, a body already
against one) live in rpp_moves.py.

Two more choices beyond Nav2 Jazzy's RPP, both against the rotate/drive limit cycle at the goal:
``stateful`` (Nav2 PR #5167, later releases) keeps rotating to the goal heading once the goal was
within ``goal_dist_tol``, even when localization jitter or the turn itself moves the robot just
outside it (otherwise it turns back toward the goal point, then again to the heading, ...); and
in-place rotations brake to stop on their target angle, |ω| <= sqrt(2·max_angular_accel·|angle|),
instead of overshooting it at ``rotate_to_heading_angular_vel`` (ros-navigation/navigation2#4937).
"""

from __future__ import annotations

import math

import numpy as np

from nav_stack.core.control.base import (
    CircleFootprint,
    CostGrid,
    Footprint,
    NoValidControl,
    Twist2D,
    turn_in_place,
)
from nav_stack.core.control.rpp_moves import STEP_CLEAR_DISTANCE, STEP_CLEAR_MAX_OFFSET, RPPMoves
from nav_stack.core.control.rpp_params import (
    RPPParams,
    approach_scaled_speed,
    curvature_to,
    find_carrot,
    regulated_speed,
)
from nav_stack.core.control.stall_escape import StallEscape
from nav_stack.core.geometry import FloatArray, Pose2D, to_frame

#: rad: heading error toward the closest carrot below which turning on the spot cannot help
ALIGNED = 0.05


class RegulatedPurePursuit:
    """RPP controller; keeps only the last carrot for visualisation."""

    def __init__(self, params: RPPParams | None = None, footprint: Footprint | None = None) -> None:
        self.params = params or RPPParams()
        self.footprint: Footprint = footprint or CircleFootprint(self.params.inscribed_radius)
        self.moves = RPPMoves(self.params, self.footprint)
        self.last_carrot = np.zeros(2)
        self._heading_goal: tuple[float, float] | None = None  # goal (x, y) whose heading is latched
        self._turn_way = 0.0  # the final turn's direction once it began: +1 left, -1 right, 0 not yet
        #: where the final turn will begin (m, world) and its direction, while the robot moves there
        self._turn_spot: tuple[float, float, float] | None = None
        self._turn_clean = False  # whether that turn keeps the body off lethal cells: re-checked
        # a slow command unanswered for half a second is blocked (stall_escape.py)
        self._escape = StallEscape(STEP_CLEAR_DISTANCE, self.params.min_approach_linear_velocity,
                                   round(0.5 * self.params.controller_frequency))

    def reset(self) -> None:
        self.last_carrot = np.zeros(2)
        self._heading_goal = None
        self._turn_way, self._turn_spot = 0.0, None
        self._escape.reset()

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
            if not latched:  # another goal: forget the last one's final turn
                self._turn_way, self._turn_spot = 0.0, None
            self._heading_goal = goal_xy
            return True
        return False

    def compute_velocity(self, robot: Pose2D, velocity: Twist2D, path: FloatArray, grid: CostGrid) -> Twist2D:
        """This cycle's command; first a step out of a spot where the last commands went unanswered
        (:mod:`stall_escape`), else pure pursuit along ``path``."""
        if len(path) == 0:
            raise NoValidControl("empty local path")
        self._escape.observe(robot, velocity)
        try:
            cmd = self._step_out(robot, grid) or self._pursue(robot, velocity, path, grid)
        except NoValidControl:
            self._escape.sent(Twist2D(0.0, 0.0))  # the controller server stops the robot
            raise
        self._escape.sent(cmd)
        return cmd

    def _step_out(self, robot: Pose2D, grid: CostGrid) -> Twist2D | None:
        """The straight step of an escape under way, or None (none, done, or no step free)."""
        directions = self._escape.directions(robot)
        if not directions:
            return None
        step = self.moves.step_clear(robot, grid, directions)
        self._escape.stepping(None if step is None else math.copysign(1.0, step.vx))
        return step

    def _pursue(self, robot: Pose2D, velocity: Twist2D, path: FloatArray, grid: CostGrid) -> Twist2D:
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
                return self._final_turn(robot, velocity, local[-1], grid, cmd)
            if not self.moves.collision_ahead(robot, cmd, reach, grid, path[-1]):
                return cmd
            if lookahead <= closest:
                return self._align_with(carrot, robot, velocity, grid, float(np.hypot(*local[0, :2])))
            lookahead = max(0.5 * lookahead, closest)  # a closer carrot: an arc nearer the (free) path

    def _final_turn(self, robot: Pose2D, velocity: Twist2D, goal: FloatArray, grid: CostGrid,
                    cmd: Twist2D) -> Twist2D:
        """The command onto the goal heading (``goal``: the path's end in the robot frame): the turn on
        the spot that :meth:`RPPMoves.final_turn` picks (the short way, or the long way round, maybe
        after a straight step to where it is free), checked to its end when it begins and then
        finished the same way round (one that kept the body off lethal cells is checked again each
        cycle, so that cells a new scan adds can stop it); where every such turn collides, a creep
        on to the goal point or an arc onto the heading (rpp_moves.py). With all of those blocked,
        ``cmd`` after all: refusing ended the navigation with 104, and the stall escape steps out if
        the body meets the obstacle. Why commit to a checked move: a body already touching lethal
        cells is judged against its own depth (``motion_collides``), so the same turn or step,
        re-judged from each new pose, flipped between free and blocked, and the robot dithered on
        the spot."""
        angle = float(goal[2])
        if self._turn_spot is not None:
            x, y, way = self._turn_spot
            ahead = (x - robot.x) * math.cos(robot.yaw) + (y - robot.y) * math.sin(robot.yaw)
            speed = self.params.min_approach_linear_velocity
            if abs(ahead) > 0.5 * speed / self.params.controller_frequency:
                return Twist2D(math.copysign(speed, ahead), 0.0)
            self._turn_spot, self._turn_way = None, way
        if self._turn_way:
            turn = angle
            if angle * self._turn_way < 0.0 and abs(angle) > ALIGNED:
                turn += math.copysign(2.0 * math.pi, self._turn_way)
            if not self._turn_clean or self.moves.turn_clean(robot, turn, grid):
                return self._rotate(turn, velocity)
            self._turn_way = 0.0  # the cells changed under a clean turn (a new scan): choose again
        plan = self.moves.final_turn(robot, angle, grid)
        if plan is not None:
            step, turn, self._turn_clean = plan
            self._turn_spot = (robot.x + step * math.cos(robot.yaw), robot.y + step * math.sin(robot.yaw),
                               math.copysign(1.0, turn))
            return self._final_turn(robot, velocity, goal, grid, cmd)
        creep = self.moves.creep_to_goal(robot, goal, grid, 0.5 * grid.spec.resolution)
        if creep is not None:
            return creep
        arc = self.moves.arc_onto_heading(robot, angle, grid)
        return arc if arc is not None else cmd

    def _align_with(self, carrot: FloatArray, robot: Pose2D, velocity: Twist2D, grid: CostGrid,
                    offset: float) -> Twist2D:
        """Even the arc to the closest carrot is blocked: turn on the spot toward that carrot (the
        path's direction right there), from where the arcs run along the path. When the turn is
        blocked too, step straight away from what blocks it (:meth:`RPPMoves.step_clear`); raise if already
        facing the carrot or if no step is free either. ``offset``: the robot's distance (m) from the
        path."""
        angle = math.atan2(carrot[1], carrot[0])
        if abs(angle) > ALIGNED:
            turn = self._rotate(angle, velocity)
            if not self.moves.collision_ahead(robot, turn, 0.0, grid):
                return turn
            if offset < STEP_CLEAR_MAX_OFFSET:
                step = self.moves.step_clear(robot, grid)
                if step is not None:
                    return step
        raise NoValidControl("collision ahead on the way to the carrot")

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
