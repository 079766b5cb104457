"""docking_server with the fake robot of docking_robot.py and a probe node, spun in the background, for
the integration tests of the server (nav_stack) and of the docking behaviors (smacc_py).

The dock is at (1, 0) in odom, (2, 0.5) in map; the robot starts 1 m in front of it. ``OVERRIDES`` are
nav2_params.yaml's docking_server section (Jazzy) with a dock ``home_dock`` and the battery switched on
(the fake battery charges within 2 cm of the dock).
"""

from __future__ import annotations

from functools import partial
from typing import Any, cast

from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import DockRobot
from rclpy.node import Node
from rclpy.parameter import Parameter

from nav_stack.core.geometry import Pose2D
from nav_stack.ros.docking.docking_server import DockingServer, build_nodes
from navsuite_testing.nav.world import Harness, get_result, send_goal
from navsuite_testing.ros import REPO, wait_until
from ros_tools.runtime.actions import ActionClient
from tests.helpers.docking_robot import FakeDockingRobot
from tests.helpers.docking_world import JAZZY_DOCK

MAP_TO_ODOM = Pose2D(1.0, 0.5, 0.0)
DOCK_IN_ODOM = Pose2D(1.0, 0.0, 0.0)
DOCK_IN_MAP = [2.0, 0.5, 0.0]
START = Pose2D(0.0, 0.05, 0.1)  # 1 m in front of the dock, a little off and turned
JAZZY_PARAMS = REPO / "config" / "jazzy" / "nav2_params.yaml"
#: nav2_params.yaml's docking_server section (Jazzy), with a dock and the battery switched on.
OVERRIDES = {
    "dock_plugins": ["simple_charging_dock"],
    "simple_charging_dock.plugin": "opennav_docking::SimpleChargingDock",
    "simple_charging_dock.use_external_detection_pose": True,
    "simple_charging_dock.use_battery_status": True,
    "simple_charging_dock.external_detection_translation_x": -0.18,
    "simple_charging_dock.external_detection_rotation_roll": -1.57,
    "simple_charging_dock.external_detection_rotation_pitch": -1.57,
    "docks": ["home_dock"],
    "home_dock.type": "simple_charging_dock",
    "home_dock.frame": "map",
    "home_dock.pose": DOCK_IN_MAP,
    "controller.v_linear_min": 0.15,
    "controller.v_linear_max": 0.15,
    "undock_angular_tolerance": 0.1,
}


class Docking:
    """docking_server (``overrides`` as parameters, or ``cli_args``), the fake robot and a probe; the
    server is active and sees the robot's TF when this returns. ``harness.close()`` in ``finally``."""

    def __init__(self, context: Any, overrides: dict[str, Any] | None = None,
                 cli_args: list[str] | None = None) -> None:
        self.harness = Harness(context)
        self.robot = FakeDockingRobot(START, DOCK_IN_ODOM, MAP_TO_ODOM, JAZZY_DOCK, context=context)
        self.probe = Node("docking_probe", context=context)
        self.poses: dict[str, PoseStamped] = {}  # the last dock_pose, filtered_dock_pose, staging_pose
        for topic in ("dock_pose", "filtered_dock_pose", "staging_pose"):
            self.probe.create_subscription(PoseStamped, topic, partial(self.poses.__setitem__, topic), 10)
        params = [Parameter(name, value=value) for name, value in (overrides or {}).items()]
        self.server = cast(DockingServer, build_nodes(use_sim_time=True, context=context,
                                                      parameter_overrides=params, cli_args=cli_args)[0])
        self.harness.add(self.robot, self.probe, self.server)
        wait_until(lambda: self.server.get_clock().now().nanoseconds > 100e9, 20.0, "the fake robot's /clock")
        self.harness.bring_up(self.server)
        buffer = self.server.frames.listener.buffer
        wait_until(lambda: buffer.can_transform("map", "base_link"), 20.0, "the robot TF at the server")
        self.feedback: list[Any] = []

    def run(self, action: Any, name: str, goal: Any, timeout: float = 60.0) -> tuple[int, Any]:
        handle = send_goal(ActionClient(self.probe, action, name), goal,
                           feedback=lambda msg: self.feedback.append(msg.feedback))
        return get_result(handle, timeout)

    def dock(self, dock_id: str = "home_dock") -> tuple[int, Any]:
        return self.run(DockRobot, "dock_robot",
                        DockRobot.Goal(use_dock_id=True, dock_id=dock_id, navigate_to_staging_pose=False))
