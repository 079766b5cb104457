"""``MiniNavigator``: the calls nav2_simple_commander's BasicNavigator (Jazzy) makes, for system tests.

BasicNavigator is not on pip (and its source may not be copied here), so this repeats its protocol
over the same interfaces: the node is ``basic_navigator`` in ``namespace`` (BasicNavigator's
``node_name`` and ``namespace`` arguments), and every action, service and topic it uses is named
relatively (``navigate_to_pose``, ``amcl/get_state``, ``initialpose``, ``amcl_pose``...), so with
``namespace="robot2"`` they resolve to ``/robot2/...``, a fleet robot's stack (docs/fleet.md).

waitUntilNav2Active polls ``amcl/get_state`` until "active", publishes ``initialpose`` until
``amcl_pose`` arrives, then polls ``bt_navigator/get_state``; tasks are judged by GoalStatus only,
as BasicNavigator does. Method names are BasicNavigator's in snake case (``go_to_pose`` is
goToPose, ``is_task_complete`` isTaskComplete...). The node is spun by the caller's executor in
another thread (navsuite_testing.ros.BackgroundSpin), so every wait here polls with a deadline
where BasicNavigator spins or waits forever.
"""

from __future__ import annotations

import enum
import math
import time
from typing import Any

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from lifecycle_msgs.srv import GetState
from nav2_msgs.action import (
    BackUp,
    ComputePathToPose,
    DockRobot,
    FollowWaypoints,
    NavigateThroughPoses,
    NavigateToPose,
    Spin,
    UndockRobot,
)
from rclpy.context import Context
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from ros_tools.runtime.actions import ActionClient
from ros_tools.runtime.requests import call_until_answered, poll
from ros_tools.tf.ros import TransformListener
from tests.helpers.nav_ros_bt_stack import wait

AMCL_POSE_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                           durability=DurabilityPolicy.TRANSIENT_LOCAL)


class TaskResult(enum.Enum):
    """BasicNavigator's TaskResult: what getResult makes of the last task's GoalStatus."""

    UNKNOWN = 0
    SUCCEEDED = 1
    CANCELED = 2
    FAILED = 3


_TASK_RESULTS = {GoalStatus.STATUS_SUCCEEDED: TaskResult.SUCCEEDED,
                 GoalStatus.STATUS_CANCELED: TaskResult.CANCELED,
                 GoalStatus.STATUS_ABORTED: TaskResult.FAILED}


def pose_stamped(x: float, y: float, yaw: float = 0.0) -> PoseStamped:
    """A pose in ``map`` at (``x``, ``y``) m facing ``yaw`` rad, as BasicNavigator's users build it."""
    pose = PoseStamped()
    pose.header.frame_id = "map"
    pose.pose.position.x, pose.pose.position.y = x, y
    pose.pose.orientation.z, pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return pose


class MiniNavigator:
    """The subset of BasicNavigator's protocol, with its node, namespace and action/service names."""

    def __init__(self, context: Context, node_name: str = "basic_navigator", namespace: str = "") -> None:
        # Not in BasicNavigator, which has no TF listener: the TF wait in wait_until_nav2_active. A
        # namespaced stack's TF travels on <namespace>/tf, so the listener's /tf is remapped the way
        # Nav2's multi-robot launch remaps every namespaced node's (/tf:=tf).
        tf_remaps = ["--ros-args", "-r", "/tf:=tf", "-r", "/tf_static:=tf_static"] if namespace else None
        self.node = Node(node_name, namespace=namespace, context=context, cli_args=tf_remaps)
        self.clients = {name: ActionClient(self.node, kind, name) for name, kind in (
            ("navigate_to_pose", NavigateToPose), ("navigate_through_poses", NavigateThroughPoses),
            ("follow_waypoints", FollowWaypoints), ("compute_path_to_pose", ComputePathToPose),
            ("spin", Spin), ("backup", BackUp), ("dock_robot", DockRobot), ("undock_robot", UndockRobot))}
        self.initial_pose = pose_stamped(0.0, 0.0)  # BasicNavigator's default: the map origin
        self.initial_pose_pub = self.node.create_publisher(PoseWithCovarianceStamped, "initialpose", 10)
        self.amcl_poses: list[Any] = []
        self.node.create_subscription(PoseWithCovarianceStamped, "amcl_pose", self.amcl_poses.append,
                                      AMCL_POSE_QOS)
        self.handle: Any = None
        self.result_future: Any = None
        self.tf = TransformListener(self.node)
        self._services: dict[str, Any] = {}

    def call(self, srv_type: Any, name: str, request: Any, timeout: float = 30.0) -> Any:
        """Call ``name``, asking again while unanswered (ros_tools.runtime.requests; ``timeout`` s in all).

        Not in BasicNavigator, which waits forever: the server's response can be lost while its
        writer still matches this client's reader (seen in CI: get_state unanswered for 30 s). The
        client is kept per service, so later calls need no new discovery.
        """
        client = self._services.get(name)
        if client is None:
            client = self._services[name] = self.node.create_client(srv_type, name)
        wait(client.service_is_ready, timeout, f"service {name}")
        return call_until_answered(client, request, timeout)

    def _wait_active(self, node_name: str) -> None:
        def active() -> bool:
            state = self.call(GetState, f"{node_name}/get_state", GetState.Request()).current_state
            return state.label == "active"
        wait(active, 120.0, f"{node_name} to be active")

    def wait_until_nav2_active(self) -> None:
        """waitUntilNav2Active(): AMCL active, the initial pose confirmed on amcl_pose, the navigator
        active; then (not in BasicNavigator) map -> base_link in this node's TF."""
        self._wait_active("amcl")
        self.amcl_poses.clear()
        deadline = time.monotonic() + 60.0
        while not self.amcl_poses:
            assert time.monotonic() < deadline, "no amcl_pose after publishing initialpose"
            self._publish_initial_pose()
            poll(lambda: bool(self.amcl_poses), 1.0)  # published again each second until AMCL answers
        self._wait_active("bt_navigator")
        # Not in BasicNavigator: AMCL's map -> odom reaches each process a while after amcl_pose (up
        # to a second under a loaded full-suite run), and until then the planner answers 207 (its
        # costmap has no robot pose) and the controller 102. Seeing it here means it is on the way.
        self.tf.wait_for("map", "base_link", timeout=30.0)

    def set_initial_pose(self, x: float, y: float, yaw: float = 0.0) -> None:
        """setInitialPose(): keep the pose for wait_until_nav2_active and publish it once now."""
        self.initial_pose = pose_stamped(x, y, yaw)
        self._publish_initial_pose()

    def _publish_initial_pose(self) -> None:
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = self.initial_pose.header.frame_id
        msg.pose.pose = self.initial_pose.pose
        self.initial_pose_pub.publish(msg)

    def send(self, name: str, goal: Any) -> bool:
        """Send ``goal`` to the action ``name`` once its server is up; True if accepted. As each
        BasicNavigator task call does, the result is requested at once (for is_task_complete)."""
        client = self.clients[name]
        wait(client.server_is_ready, 30.0, f"action {name}")
        future = client.send_goal_async(goal)
        wait(future.done, 30.0, f"{name} acknowledgement")
        self.handle = future.result()
        self.result_future = self.handle.get_result_async() if self.handle.accepted else None
        return bool(self.handle.accepted)

    def start(self, name: str, goal: Any) -> None:
        """:meth:`send`, failing the test when the goal is rejected."""
        assert self.send(name, goal), f"{name} rejected the goal"

    def go_to_pose(self, pose: PoseStamped, behavior_tree: str = "") -> bool:
        """goToPose(): navigate_to_pose to ``pose``; True if the navigator accepted it."""
        return self.send("navigate_to_pose", NavigateToPose.Goal(pose=pose, behavior_tree=behavior_tree))

    def is_task_complete(self) -> bool:
        """isTaskComplete(): True once the last task has a result (or none was accepted)."""
        return self.result_future is None or self.result_future.done()

    def get_result(self) -> TaskResult:
        """getResult(): the last task's outcome from its GoalStatus (UNKNOWN while it runs)."""
        if self.result_future is None or not self.result_future.done():
            return TaskResult.UNKNOWN
        return _TASK_RESULTS.get(self.result_future.result().status, TaskResult.UNKNOWN)

    def result(self, timeout: float = 300.0) -> Any:
        """The last task's full result response (status and result), waiting up to ``timeout`` s."""
        assert self.result_future is not None, "no accepted task"
        wait(self.result_future.done, timeout, "the task result")
        return self.result_future.result()

    def cancel_task(self) -> None:
        """cancelTask(): ask the server to cancel the last task and wait for its answer."""
        future = self.handle.cancel_goal_async()
        wait(future.done, 30.0, "the cancel response")
