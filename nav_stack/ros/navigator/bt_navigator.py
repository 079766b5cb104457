"""bt_navigator: serves navigate_to_pose and navigate_through_poses by ticking a behaviour tree.

Lifecycle node ``bt_navigator`` (Nav2 Jazzy names). A goal's ``behavior_tree`` field names another
XML file; a tree that fails to load aborts the goal with the loader's message (file, line, node).

Scheduling: one node-clock timer ticks the tree every ``bt_loop_duration`` ms (sim time under
use_sim_time, so the tree sees the same ticks however fast the simulation runs); every leaf's
client sends and receives on the same executor thread. Execute callbacks are coroutines that
only hand their goal to the loop and await its outcome, so the executor keeps serving.

Preemption: a new goal for the running navigator replaces the goal on the blackboard (GoalUpdated
fires) and the previous goal is aborted, as nav2_util's SimpleActionServer does; a goal asking for
a different tree is refused while another runs, and so is a goal of the other navigator. Unlike
Nav2, the tree then restarts from its root (its running actions are cancelled), so the new goal's
first plan comes before any path is followed: kept running, the old FollowPath could end the new
goal as reached at the old one before the 1 Hz replan (seen: the battery patrol's "go to the
station" succeeded 0.05 s after it preempted "go to location3", 0.65 m from the station). Cancel
halts the tree, which cancels the running actions (the controller stops the robot).

Result: on failure, error_code/error_msg come from the first non-zero code among
``error_code_names`` on the blackboard, with the failing server and its message (UNKNOWN, 9000,
when none is set: a failed goal never ends with 0; a goal in an empty or unknown frame is refused
with TF_ERROR, 9002), e.g.
"'compute_path_to_pose' failed with error code 206 (GOAL_OCCUPIED): ...". Status changes are
published as nav2_msgs/BehaviorTreeLog on ``behavior_tree_log``; a PoseStamped on ``goal_pose``
(RViz's "Nav2 Goal") is sent to our own navigate_to_pose (nav_stack/ros/navigator/goal_pose_forwarder.py).
While localization is not trustworthy (nav_stack/ros/navigator/localization_guard.py) a new goal is refused,
and a running one ends after ``localization_grace_period``, with UNKNOWN and "localization is not
trustworthy: <cause>".
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from nav2_msgs.msg import BehaviorTreeLog, BehaviorTreeStatusChange
from nav_msgs.msg import Odometry
from rclpy.action import CancelResponse, GoalResponse
from rclpy.clock import Clock, ClockType
from rclpy.node import Node

from nav_stack.core.bt import BehaviorTreeFactory, Blackboard, BtError, NodeStatus, Tree, TreeNode
from nav_stack.ros.bt_nodes import BtRosContext, SelectorTopics, register_ros_nodes
from nav_stack.ros.bt_nodes.actions import RECOVERIES_KEY
from nav_stack.ros.bt_nodes.navigators import (
    FAILED_TO_LOAD_BEHAVIOR_TREE,
    UNKNOWN,
    GoalError,
    NavigateThroughPosesNavigator,
    NavigateToPoseNavigator,
    Navigator,
    RobotState,
    has_robot_pose,
)
from nav_stack.ros.common.clock_watch import ClockWatch
from nav_stack.ros.common.frames import Frames
from nav_stack.ros.common.goal_runs import GoalRun, Outcome
from nav_stack.ros.common.node_runner import run, with_sim_time
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import DEFAULT
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from nav_stack.ros.navigator.goal_pose_forwarder import GoalPoseForwarder
from nav_stack.ros.navigator.localization_guard import (
    LocalizationGuard,
    LocalizationGuardParams,
    untrusted_message,
)
from ros_tools.runtime.actions import ActionServer
from ros_tools.runtime.timers import create_periodic_timer

ROBOT_POSE_WAIT_S = 5.0  # s (wall, steady clock) a new goal waits for the robot pose before TF_ERROR
FEEDBACK_PERIOD = 0.05  # s (wall) between feedback messages; Nav2 sends one per tick


@dataclass(frozen=True)
class BtNavigatorParams:
    """bt_navigator parameters (Nav2 Jazzy names; times in ms where Nav2 uses ms)."""

    global_frame: str = "map"
    robot_base_frame: str = "base_link"
    odom_topic: str = "odom"
    bt_loop_duration: int = 10  # ms between ticks
    default_server_timeout: int = 20  # ms (node clock, so sim time) a server may take to answer
    wait_for_service_timeout: int = 1000  # ms a leaf waits for its server to appear
    action_server_result_timeout: float = 900.0  # s results stay available to clients
    default_nav_to_pose_bt_xml: str = ""  # "" = config/trees/navigate_to_pose_w_replanning_and_recovery.xml
    default_nav_through_poses_bt_xml: str = ""
    goal_blackboard_id: str = "goal"
    goals_blackboard_id: str = "goals"
    path_blackboard_id: str = "path"
    error_code_names: tuple[str, ...] = ("compute_path_error_code", "follow_path_error_code")

    def __post_init__(self) -> None:
        for name in ("bt_loop_duration", "default_server_timeout", "wait_for_service_timeout"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be > 0 ms, got {getattr(self, name)}")


@dataclass
class Session:
    """The navigation being ticked: its goal run, navigator, tree and start time (node clock, s)."""

    run: GoalRun
    navigator: Navigator
    tree_file: str
    tree: Tree | None = None
    started: float = 0.0
    last_feedback: float = -1.0
    events: list[BehaviorTreeStatusChange] = field(default_factory=list)


class BtNavigator(NavLifecycleNode):
    """The ``bt_navigator`` lifecycle node."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("bt_navigator", **kwargs)
        self._active = False
        self._session: Session | None = None
        self._pending: tuple[GoalRun, Navigator] | None = None
        self._servers: list[ActionServer] = []
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._wall = Clock(clock_type=ClockType.SYSTEM_TIME)  # BT event stamps, as Nav2's logger
        self._timer: Any = None
        self._pose_wait_since: float | None = None  # s (steady clock) a new goal began waiting for the pose
        self.navigators: list[Navigator] = []

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        self.params = p = declare_dataclass(self, BtNavigatorParams)
        self.frames = Frames(self, p.robot_base_frame)
        self.ros = BtRosContext(self, self.frames)
        self.ros.global_frame, self.ros.robot_base_frame = p.global_frame, p.robot_base_frame
        self.selectors = SelectorTopics(self)
        self.factory = BehaviorTreeFactory()
        register_ros_nodes(self.factory, self.ros)
        self.localization = LocalizationGuard(self, declare_dataclass(self, LocalizationGuardParams))
        self.robot = RobotState(self.frames, p.global_frame, trust=self.localization.trust)
        self.navigators = [
            NavigateToPoseNavigator(p.default_nav_to_pose_bt_xml, p.path_blackboard_id, p.goal_blackboard_id),
            NavigateThroughPosesNavigator(p.default_nav_through_poses_bt_xml, p.path_blackboard_id,
                                          p.goals_blackboard_id),
        ]
        for navigator in self.navigators:
            self._load(navigator.default_tree)  # fail the transition on a broken default tree
        self._log_pub = self.create_publisher(BehaviorTreeLog, "behavior_tree_log", DEFAULT)
        self._odom_sub = self.create_subscription(Odometry, p.odom_topic, self._on_odom, DEFAULT)
        self._goal_pose = GoalPoseForwarder(self)
        self._servers = [
            ActionServer(self, nav.action_type, nav.action_name, self._executor_for(nav),
                         goal_callback=self._goal_filter(nav),
                         cancel_callback=lambda _: CancelResponse.ACCEPT,
                         result_timeout=int(p.action_server_result_timeout))
            for nav in self.navigators
        ]

    def activate(self) -> None:
        self._active = True
        # On the node clock: under use_sim_time the tree ticks every bt_loop_duration ms of sim time,
        # so a faster-than-real-time run ticks it as often per simulated second as a real-time one.
        self._timer = create_periodic_timer(self, self.params.bt_loop_duration / 1000.0, self._tick)
        self._clock_watch = ClockWatch(self, lambda: self._session is not None, "navigation")

    def deactivate(self) -> None:
        self._active = False
        self._clock_watch.destroy()
        if self._timer is not None:
            self.destroy_timer(self._timer)
            self._timer = None
        session, self._session = self._session, None
        pending, self._pending = self._pending, None
        if session is not None:
            self._end(session, Outcome.ABORTED, UNKNOWN, "bt_navigator was deactivated")
        if pending is not None:
            pending[0].finish(Outcome.ABORTED, UNKNOWN, "bt_navigator was deactivated")

    def cleanup(self) -> None:
        for server in self._servers:
            server.destroy()
        self._servers = []
        self._goal_pose.destroy()
        self.destroy_subscription(self._odom_sub)
        self.localization.destroy()
        self.destroy_publisher(self._log_pub)
        self.selectors.destroy()
        self.ros.destroy()
        self.frames.destroy()

    # -- goals -------------------------------------------------------------------------------------
    def _goal_filter(self, navigator: Navigator) -> Any:
        def accept(goal: Any) -> GoalResponse:
            session = self._session
            if not self._active:
                self.get_logger().warn(f"{navigator.action_name}: rejecting a goal, not active")
                return GoalResponse.REJECT
            if session is not None and session.navigator is not navigator:
                self.get_logger().warn(f"{navigator.action_name}: rejecting a goal while "
                                       f"{session.navigator.action_name} is running")
                return GoalResponse.REJECT
            return GoalResponse.ACCEPT
        return accept

    def _executor_for(self, navigator: Navigator) -> Any:
        async def execute(handle: Any) -> Any:
            goal_run = GoalRun(handle, navigator.action_type.Result())
            replaced, self._pending = self._pending, (goal_run, navigator)
            if self._timer is not None:
                self._timer.reset()
            if replaced is not None:
                replaced[0].finish(Outcome.ABORTED, error_msg="replaced by a newer goal before it started")
            return await goal_run.wait()
        return execute

    def _on_odom(self, msg: Odometry) -> None:
        v = msg.twist.twist.linear
        self.robot.speed = float((v.x * v.x + v.y * v.y) ** 0.5)

    # -- tree ----------------------------------------------------------------------------------------
    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _load(self, tree_file: str, board: Blackboard | None = None) -> Tree:
        return self.factory.create_tree_from_file(tree_file, blackboard=board, clock=self._now,
                                                  selection_source=self.selectors)

    def _new_board(self) -> Blackboard:
        board = Blackboard()
        p = self.params
        board.set("server_timeout", p.default_server_timeout)
        board.set("wait_for_service_timeout", p.wait_for_service_timeout)
        board.set("bt_loop_duration", p.bt_loop_duration)
        board.set(RECOVERIES_KEY, 0)
        for name in p.error_code_names:
            board.set(name, 0)
        return board

    def _start(self, goal_run: GoalRun, navigator: Navigator) -> None:
        goal = goal_run.handle.request
        session = Session(goal_run, navigator, navigator.tree_file(goal))
        board = self._new_board()
        try:
            navigator.write_goal(goal, board, self.robot)
        except GoalError as error:
            goal_run.finish(Outcome.ABORTED, error.code, f"{navigator.action_name}: {error}")
            return
        try:
            session.tree = self._load(session.tree_file, board)
        except (BtError, OSError) as error:
            message = f"failed to load behavior tree '{session.tree_file}': {error}"
            self.get_logger().error(message)
            goal_run.finish(Outcome.ABORTED, FAILED_TO_LOAD_BEHAVIOR_TREE, message)
            return
        session.tree.add_status_listener(lambda node, old, new: self._on_status(session, node, old, new))
        session.started = self._now()
        self.ros.clear_failures()
        self._session = session
        self.get_logger().info(f"{navigator.action_name}: begin navigating ({session.tree_file})")

    def _preempt(self, session: Session, goal_run: GoalRun, navigator: Navigator) -> None:
        goal = goal_run.handle.request
        if navigator.tree_file(goal) != session.tree_file or navigator is not session.navigator:
            goal_run.finish(Outcome.ABORTED, 0, "cannot preempt the running navigation with a different "
                            "behavior tree or navigator; cancel it first")
            return
        assert session.tree is not None
        try:
            navigator.write_goal(goal, session.tree.blackboard, self.robot)
        except GoalError as error:
            goal_run.finish(Outcome.ABORTED, error.code, f"{navigator.action_name}: {error}")
            return
        session.tree.halt()  # restart from the root: the new goal is planned before any path is followed
        session.run.finish(Outcome.ABORTED, 0, "preempted by a new goal")
        session.run = goal_run
        session.started = self._now()
        session.tree.blackboard.set(RECOVERIES_KEY, 0)
        self.get_logger().info(f"{navigator.action_name}: goal preempted by a new goal")

    def _robot_pose_awaited(self) -> bool:
        """True while a new goal should wait for the robot pose instead of being refused.

        Nav2 refuses a goal at once when the robot pose is unknown (TF_ERROR). Here the goal waits
        up to ROBOT_POSE_WAIT_S first: localization publishes map -> odom only after its first
        filter update (SLAM after its first scan), and this node's /tf subscription may still be
        matching the localizer's publisher, so a goal sent the moment the stack reports ready would
        be refused depending on how fast the messages crossed. The wait is in wall time (steady
        clock) because discovery is: at rtf 10 two seconds of sim time are 0.2 s of wall time (a
        CI run saw exactly that refusal). Past the wait, Navigator.write_goal refuses it as Nav2 does.
        """
        if has_robot_pose(self.robot):
            self._pose_wait_since = None
            return False
        now = self._steady.now().nanoseconds * 1e-9
        if self._pose_wait_since is None:
            self._pose_wait_since = now
        if now - self._pose_wait_since < ROBOT_POSE_WAIT_S:
            return True
        self._pose_wait_since = None
        return False

    def _tick(self) -> None:
        if self._session is None and self._pending is not None and self._robot_pose_awaited():
            return
        pending, self._pending = self._pending, None
        if pending is not None:
            if self._session is None:
                self._start(*pending)
            else:
                self._preempt(self._session, *pending)
        session = self._session
        if session is None:
            if self._timer is not None and self._pending is None:  # idle: no ticks until the next goal
                self._timer.cancel()
            return
        assert session.tree is not None
        if session.run.handle.is_cancel_requested:
            self._end(session, Outcome.CANCELED, 0, "navigation was canceled")
            return
        lost = self.localization.untrusted_past_grace(self._now())
        if lost is not None:
            self._end(session, Outcome.ABORTED, UNKNOWN,
                      f"{session.navigator.action_name}: {untrusted_message(lost)}")
            return
        try:
            status = session.tree.tick_once(self._now())
        except Exception as error:  # a misbehaving node fails the goal, never the navigator
            self.get_logger().error(f"behavior tree error: {type(error).__name__}: {error}")
            self._end(session, Outcome.ABORTED, 0, f"behavior tree error: {type(error).__name__}: {error}")
            return
        self._publish_log(session)
        if status is NodeStatus.SUCCESS:
            self._end(session, Outcome.SUCCEEDED, 0, "")
        elif status is NodeStatus.FAILURE:
            self._end(session, Outcome.ABORTED, *self._failure_of(session))
        else:
            self._publish_feedback(session)

    def _end(self, session: Session, outcome: Outcome, code: int, message: str) -> None:
        if session.tree is not None:
            session.tree.halt()
            self._publish_log(session)
        self._session = None
        session.run.finish(outcome, code, message)
        verb = {Outcome.SUCCEEDED: "succeeded", Outcome.CANCELED: "canceled"}.get(outcome, "failed")
        text = f"{session.navigator.action_name}: goal {verb}" + (f": {message}" if message else "")
        if outcome is Outcome.ABORTED:  # rclpy needs one severity per logging call site
            self.get_logger().warn(text)
        else:
            self.get_logger().info(text)

    def _failure_of(self, session: Session) -> tuple[int, str]:
        assert session.tree is not None
        board = session.tree.blackboard
        for name in self.params.error_code_names:
            code = int(board.get(name, 0) or 0)
            if code:
                failure = self.ros.failure(name)
                return code, failure.describe() if failure else f"{name} = {code}"
        latest = self.ros.latest_failure
        if latest is not None:  # e.g. a goal never acknowledged: a leaf failed, no server did
            return UNKNOWN, f"the behavior tree failed: {latest.describe()}"
        return UNKNOWN, "the behavior tree failed (no server reported an error code)"

    # -- output -------------------------------------------------------------------------------------
    def _publish_feedback(self, session: Session) -> None:
        wall = self._steady.now().nanoseconds * 1e-9
        if wall - session.last_feedback < FEEDBACK_PERIOD:
            return
        session.last_feedback = wall
        assert session.tree is not None
        stamp = self.get_clock().now().to_msg()
        board = session.tree.blackboard
        msg = session.navigator.feedback(board, self.robot, session.started, self._now(), stamp)
        session.run.handle.publish_feedback(msg)

    def _on_status(self, session: Session, node: TreeNode, previous: NodeStatus, current: NodeStatus) -> None:
        event = BehaviorTreeStatusChange(node_name=node.name, uid=node.uid, previous_status=previous.value,
                                         current_status=current.value)
        event.timestamp = self._wall.now().to_msg()
        session.events.append(event)

    def _publish_log(self, session: Session) -> None:
        if session.events:
            msg = BehaviorTreeLog(event_log=session.events)
            msg.timestamp = self.get_clock().now().to_msg()
            self._log_pub.publish(msg)
            session.events = []


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """The bt_navigator node (``kwargs`` go to its constructor: context, cli_args, overrides)."""
    kwargs = with_sim_time(kwargs, use_sim_time)
    return [BtNavigator(**kwargs)]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.navigator.bt_navigator [--autostart] [--ros-args ...]``."""
    return run(build_nodes, argv, role="bt_navigator")


if __name__ == "__main__":
    raise SystemExit(main())
