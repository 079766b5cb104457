"""A kinematic robot world for the docking cores (no rclpy), and the tag convention a detector follows.

``tag_pose_for(dock, params)`` inverts the SimpleChargingDock rule: the tag pose (in the dock's frame)
a detector must report so that the plugin refines it to ``dock``. Both the unit tests and the fake
robot node of the integration test (docking_robot.py) use it.

``FakeDockingWorld`` implements nav_stack.core.docking.world.DockingWorld with frames ``map``,
``odom`` (map→odom = ``map_to_odom``) and ``base_link`` (the robot). ``step(command, dt)`` integrates a
unicycle; a robot reaching ``contact`` (the dock's pose, along its heading) is held there, as a
physical dock stops it. ``detect(plugin, now)`` feeds the plugin a detection of the dock's tag in
``base_link`` unless ``hidden``. ``drive(...)`` ticks a sequence like the node's timer does.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from nav_stack.core.control.base import CircleFootprint, CostGrid
from nav_stack.core.docking.controller import Obstacles
from nav_stack.core.docking.errors import FrameUnavailable
from nav_stack.core.docking.simple_charging_dock import (
    Detection,
    SimpleChargingDock,
    SimpleChargingDockParams,
)
from nav_stack.core.docking.spatial import Pose3D, about_axis, compose, conjugate, inverse, multiply
from nav_stack.core.docking.world import DockingStep
from nav_stack.core.geometry import Pose2D
from nav_stack.core.geometry import compose as compose2d
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec

ORIGIN = Pose2D(0.0, 0.0, 0.0)
JAZZY_DOCK = SimpleChargingDockParams(  # nav2_params.yaml's simple_charging_dock (Jazzy)
    use_external_detection_pose=True, use_battery_status=False, external_detection_translation_x=-0.18,
    external_detection_rotation_roll=-1.57, external_detection_rotation_pitch=-1.57,
    external_detection_rotation_yaw=0.0)


def pose3d(pose: Pose2D) -> Pose3D:
    """A planar pose as a 3-D pose."""
    return Pose3D(pose.x, pose.y, 0.0, *about_axis("z", pose.yaw))


def tag_pose_for(dock: Pose2D, params: SimpleChargingDockParams, height: float = 0.1) -> Pose3D:
    """The tag pose that refines to ``dock``: orientation q_z(yaw) · q_offset⁻¹, position the dock's moved
    by -(tx, ty) along the dock heading (and ``height`` m up, which the rule drops)."""
    q = multiply(about_axis("z", dock.yaw), conjugate(params.offset_rotation()))
    tx, ty = params.external_detection_translation_x, params.external_detection_translation_y
    c, s = math.cos(dock.yaw), math.sin(dock.yaw)
    return Pose3D(dock.x - (c * tx - s * ty), dock.y - (s * tx + c * ty), height, *q)


def box_obstacle(x0: float, y0: float, x1: float, y1: float, resolution: float = 0.05) -> CostGrid:
    """A 6 m × 6 m costmap centred on the odom origin with one lethal box (m, odom frame)."""
    spec = GridSpec(120, 120, resolution, -3.0, -3.0)
    costs = np.zeros(spec.shape, dtype=np.uint8)
    my, mx = np.mgrid[0:spec.height, 0:spec.width]
    wx, wy = spec.cell_to_world(mx, my)
    costs[(wx >= x0) & (wx <= x1) & (wy >= y0) & (wy <= y1)] = LETHAL_OBSTACLE
    return CostGrid(costs, spec)


@dataclass
class FakeDockingWorld:
    """Robot pose in odom; ``dock`` in odom; optional lethal ``grid`` in odom; see the module docstring."""

    robot: Pose2D
    dock: Pose2D = ORIGIN
    map_to_odom: Pose2D = ORIGIN
    grid: CostGrid | None = None
    hidden: bool = False
    tf_broken: bool = False
    frozen: bool = False
    commands: list[tuple[float, float]] = field(default_factory=list)

    def robot_pose(self, frame: str) -> Pose2D:
        if self.tf_broken:
            raise FrameUnavailable(f'"{frame}" passed to lookupTransform argument target_frame does not '
                                   'exist')
        if frame == "odom":
            return self.robot
        if frame == "map":
            return compose2d(self.map_to_odom, self.robot)
        raise FrameUnavailable(f"frame [{frame}] does not exist")

    def transform(self, pose: Pose2D, source: str, target: str) -> Pose2D:
        if source == target:
            return pose
        if (source, target) == ("map", "odom"):
            return compose2d(self._odom_from_map(), pose)
        if (source, target) == ("odom", "map"):
            return compose2d(self.map_to_odom, pose)
        raise FrameUnavailable(f"no transform from '{source}' to '{target}'")

    def _odom_from_map(self) -> Pose2D:
        inv = inverse(pose3d(self.map_to_odom))
        return Pose2D(inv.x, inv.y, math.atan2(2 * inv.qw * inv.qz, 1 - 2 * inv.qz * inv.qz))

    def detection_in(self, detection: Detection, frame: str) -> Pose3D:
        if detection.frame == "base_link" and frame == "odom":
            return compose(pose3d(self.robot), detection.pose)
        raise FrameUnavailable(f"no transform from '{detection.frame}' to '{frame}'")

    def obstacles(self) -> Obstacles | None:
        return None if self.grid is None else Obstacles(self.grid, CircleFootprint(0.1), "odom")

    def detect(self, plugin: SimpleChargingDock, now: float) -> None:
        """The dock's tag as a camera on base_link sees it, stamped ``now``."""
        if self.hidden:
            return
        tag_in_odom = tag_pose_for(self.dock, plugin.params)
        plugin.on_detection(Detection(compose(inverse(pose3d(self.robot)), tag_in_odom), "base_link", now))

    def step(self, command: tuple[float, float] | None, dt: float) -> None:
        """Drive ``dt`` s with ``command`` (None: keep the last one); stop at the dock's contact."""
        if command is not None:
            self.commands.append((command[0], command[1]))
        if self.frozen or not self.commands:
            return
        v, w = self.commands[-1]
        x, y, yaw = self.robot
        moved = Pose2D(x + v * dt * math.cos(yaw), y + v * dt * math.sin(yaw), yaw + w * dt)
        c, s = math.cos(self.dock.yaw), math.sin(self.dock.yaw)
        ahead = (moved.x - self.dock.x) * c + (moved.y - self.dock.y) * s
        if ahead > 0.0 and math.hypot(moved.x - self.dock.x, moved.y - self.dock.y) < 0.1:
            moved = Pose2D(moved.x - ahead * c, moved.y - ahead * s, moved.yaw)  # the dock's face stops it
        self.robot = moved


def drive(sequence: Any, world: FakeDockingWorld, plugin: SimpleChargingDock | None, dt: float = 0.02,
          max_s: float = 200.0, on_step: Callable[[DockingStep, float], None] | None = None,
          start: float = 0.0) -> tuple[DockingStep, float]:
    """Tick ``sequence`` every ``dt`` s until it has a result; (last step, time). The world detects before
    each tick and moves after it, by the tick's command."""
    now = start
    while now < start + max_s:
        if plugin is not None:
            world.detect(plugin, now)
        step = sequence.tick(now)
        if on_step is not None:
            on_step(step, now)
        if step.result is not None:
            return step, now
        world.step(step.command, dt)
        now += dt
    phase = getattr(sequence, "phase", "?")
    raise AssertionError(f"the sequence did not finish within {max_s} s (phase {phase})")
