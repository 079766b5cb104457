"""The docking server's controller: the smooth control law plus a collision look-ahead (opennav_docking's
``Controller``).

Targets are given in the robot frame (the server transforms them there). Before a command is used,
the law is rolled out from the robot in ``simulation_time_step`` s steps for up to ``projection_time``
s, or until it comes within 1 cm of the target, and each pose is checked against the local costmap
(``use_collision_detection``). Poses within ``dock_collision_threshold`` m of the target while docking
(the dock itself is an obstacle the robot must touch), or of the start while undocking, are not
checked. A collision fails the command (FAILED_TO_CONTROL), so the robot stops clear of an obstacle
instead of pushing into it; the message names the costmap cell the footprint would touch (where the
obstacle is) as well as the robot pose at which it would (Nav2 says only "Failed to get control").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_stack.core.control.base import CostGrid, Footprint, PolygonFootprint, Twist2D
from nav_stack.core.docking.errors import FailedToControl
from nav_stack.core.docking.graceful import SmoothControlLawParams, next_pose, velocity_command
from nav_stack.core.geometry import Pose2D, angle_diff, compose, from_frame, to_frame

REACHED_TOLERANCE = 0.01  # m: the roll-out stops this close to the target (Nav2's 1e-2)


@dataclass(frozen=True)
class DockingControllerParams(SmoothControlLawParams):
    """``controller.*`` of docking_server (Nav2 Jazzy code defaults; nav2_params.yaml sets v_linear_min
    and v_linear_max 0.15). Units: s, m. ``costmap_topic``/``footprint_topic`` are read by the node.

    ``transform_tolerance`` is declared for compatibility: TF lookups here take the latest transform.
    nav2_params.yaml's ``simulation_step`` is not a parameter of Nav2's code (it reads
    ``simulation_time_step``), so it is ignored here too.
    """

    use_collision_detection: bool = True
    costmap_topic: str = "local_costmap/costmap_raw"
    footprint_topic: str = "local_costmap/published_footprint"
    transform_tolerance: float = 0.1
    projection_time: float = 5.0
    simulation_time_step: float = 0.1
    dock_collision_threshold: float = 0.3
    # Not in Nav2: the robot's outline for the collision look-ahead ("[[x, y], ...]" m in base_link),
    # used instead of the costmap's published footprint when set. Why: the waffle's costmap footprint
    # is the robot_radius circle (0.22 m + padding), 0.15 m wider ahead of base_link than its body; on
    # turtlebot3_world's dock that circle overlaps the dock and grazes the pillar beside the staging
    # pose, so every approach "collided" (measured: bench/bench_docking.py, 0 of 4 docked).
    footprint: str = ""

    def __post_init__(self) -> None:
        super().__post_init__()
        if not (self.simulation_time_step > 0.0 and self.projection_time >= 0.0
                and self.dock_collision_threshold >= 0.0 and self.transform_tolerance >= 0.0):
            raise ValueError(
                "need simulation_time_step > 0 s and projection_time, dock_collision_threshold, "
                f"transform_tolerance >= 0, got {self.simulation_time_step}, {self.projection_time}, "
                f"{self.dock_collision_threshold}, {self.transform_tolerance}")


@dataclass(frozen=True)
class Obstacles:
    """The local costmap and the robot outline, in the costmap's ``frame``."""

    grid: CostGrid
    footprint: Footprint
    frame: str


class DockingController:
    """Commands towards a target in the robot frame, refused when the roll-out collides."""

    def __init__(self, params: DockingControllerParams) -> None:
        self.params = params

    def rollout(self, target: Pose2D, backward: bool) -> list[Pose2D]:
        """The law's simulated poses from the robot (origin, excluded) towards ``target`` (robot frame)."""
        p = self.params
        steps = max(math.ceil(p.projection_time / p.simulation_time_step) - 1, 0)
        poses, pose = [], Pose2D(0.0, 0.0, 0.0)
        for _ in range(steps):
            pose = next_pose(p.simulation_time_step, target, pose, p, backward)
            poses.append(pose)
            if math.hypot(target.x - pose.x, target.y - pose.y) <= REACHED_TOLERANCE:
                break
        return poses

    def collision(self, target: Pose2D, robot: Pose2D, obstacles: Obstacles, is_docking: bool,
                  backward: bool) -> Pose2D | None:
        """The first colliding roll-out pose (in the costmap frame), or None.

        ``robot`` is the robot pose in ``obstacles.frame``; with ``use_collision_detection`` false
        nothing collides.
        """
        p = self.params
        if not p.use_collision_detection:
            return None
        poses = self.rollout(target, backward)
        checked = [q for q in poses
                   if (math.hypot(target.x - q.x, target.y - q.y) if is_docking else math.hypot(q.x, q.y))
                   > p.dock_collision_threshold]
        if not checked:
            return None
        world = [compose(robot, q) for q in checked]
        x, y, yaw = (np.array(values) for values in zip(*world, strict=True))
        hits = obstacles.footprint.collides(obstacles.footprint.cost(obstacles.grid, x, y, yaw))
        return world[int(np.argmax(hits))] if hits.any() else None

    def command(self, target: Pose2D, robot: Pose2D, obstacles: Obstacles | None, is_docking: bool,
                backward: bool) -> Twist2D:
        """The law's command towards ``target`` (robot frame); ``robot`` in the costmap frame.

        Without ``obstacles`` (DockingWorld.obstacles: no local costmap received yet) the roll-out
        cannot be checked, and the command is given unchecked, as with ``use_collision_detection`` off.

        Raises:
            FailedToControl: the roll-out collides.
        """
        if obstacles is not None:
            hit = self.collision(target, robot, obstacles, is_docking, backward)
            if hit is not None:
                raise collision_failure(obstacles, hit, robot, compose(robot, target), is_docking)
        return velocity_command(target, Pose2D(0.0, 0.0, 0.0), self.params, backward)

    def command_to_pose(self, robot: Pose2D, pose: Pose2D, linear_tolerance: float, angular_tolerance: float,
                        robot_in_costmap: Pose2D, obstacles: Obstacles | None, is_docking: bool,
                        backward: bool) -> Twist2D | None:
        """Nav2's getCommandToPose: None once ``robot`` is within the tolerances (m, rad) of ``pose`` (same
        frame), else the command towards it. FailedToControl when the motion collides."""
        if (math.hypot(robot.x - pose.x, robot.y - pose.y) < linear_tolerance
                and abs(angle_diff(pose.yaw, robot.yaw)) < angular_tolerance):
            return None
        return self.command(relative(pose, robot), robot_in_costmap, obstacles, is_docking, backward)


def collision_failure(obstacles: Obstacles, hit: Pose2D, robot: Pose2D, goal: Pose2D,
                      is_docking: bool) -> FailedToControl:
    """The error of a roll-out from ``robot`` towards ``goal`` that collides at ``hit`` (all in the
    costmap frame): it names the blocking cell and its cost, for the action's error_msg."""
    (x, y), cost = blocking_cell(obstacles, hit)
    return FailedToControl(f"collision ahead: the {'docking' if is_docking else 'undocking'} motion "
                           f"from ({robot.x:.2f}, {robot.y:.2f}, {robot.yaw:.2f}) towards "
                           f"({goal.x:.2f}, {goal.y:.2f}) would hit an obstacle: the costmap cell at "
                           f"({x:.2f}, {y:.2f}) (cost {cost}) under the robot at ({hit.x:.2f}, "
                           f"{hit.y:.2f}, {hit.yaw:.2f}) in '{obstacles.frame}'")


def blocking_cell(obstacles: Obstacles, pose: Pose2D) -> tuple[tuple[float, float], int]:
    """The centre (m, costmap frame) and cost of a cell that makes the robot at ``pose`` collide: the
    first colliding point of a polygon's outline, or the centre of a circle (whose cost decides)."""
    footprint, grid = obstacles.footprint, obstacles.grid
    points = np.array([[pose.x, pose.y]])
    if isinstance(footprint, PolygonFootprint):
        outline = footprint.outline()
        world = from_frame(np.column_stack([outline, np.zeros(len(outline))]), pose)[:, :2]
        colliding = footprint.collides(grid.cost_at(world[:, 0], world[:, 1]))
        points = world[colliding][:1] if colliding.any() else points
    mx, my = grid.spec.world_to_cell(points[:, 0], points[:, 1])
    cx, cy = grid.spec.cell_to_world(mx, my)
    return (float(cx[0]), float(cy[0])), int(grid.cost_at(points[:, 0], points[:, 1])[0])


def relative(pose: Pose2D, frame: Pose2D) -> Pose2D:
    """``pose`` expressed in the frame of ``frame`` (both given in one parent frame)."""
    x, y, yaw = to_frame(np.array([pose], dtype=np.float64), frame)[0]
    return Pose2D(float(x), float(y), float(yaw))
