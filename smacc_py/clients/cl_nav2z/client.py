"""``ClNav2Z``: the Nav2 client. It speaks NavigateToPose and the behavior-server actions.

Like SMACC2's cl_nav2z, it owns the ``navigate_to_pose`` action client and posts
``EvActionSucceeded/Aborted/Cancelled/Result/Feedback[ClNav2Z, Or]`` (ABSOLUTE lifetime) with the
result or feedback as payload (``result``, ``error_code``, ``error_msg``, ``action``), posted by the same
code as the generic ``CpActionClient`` (``event_posting_callbacks``). Because SMACC2's
custom Nav2 planner plugins (forward, backward, pure spinning, undo path) do not exist in a standard
Nav2, this client also holds clients for the Nav2 behavior-server actions that do the same motions:
``spin``, ``backup``, ``drive_on_heading``, plus ``follow_path`` on the controller server.

Events are posted only for goals somebody still owns: a goal abandoned when its state exited (see
``GoalTicket.abandon``) ends silently, so it cannot trigger a transition in the next state.

Every ROS endpoint of the client lives here (action clients, the cmd_vel publisher, the /bond
subscription of CbWaitNav2Nodes, the cancel-every-goal service client of CbAbortNavigation, the TF
lookups of CbWaitTransform), none in
its behaviors: a substitute ClNav2Z given to the machine
(``SmaccStateMachineBase(substitutes=...)``) then replaces all of Nav2 for the shipped behaviors.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from typing import Any

from action_msgs.srv import CancelGoal
from bond.msg import Status
from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import BackUp, DockRobot, DriveOnHeading, FollowPath, NavigateToPose, Spin, UndockRobot
from rclpy.exceptions import ParameterUninitializedException
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy

from ros_tools.cmd_vel import CmdVelPublisher
from ros_tools.runtime.action_watch import ServerLossWatch
from ros_tools.runtime.coroutines import spawn
from ros_tools.runtime.requests import call_service
from ros_tools.tf import Transform
from smacc_py.core import ISmaccClient
from smacc_py.ros.action_client import GoalOutcome, GoalTicket, RosActionClient
from smacc_py.ros.components.cp_action_client import event_posting_callbacks
from smacc_py.ros.context import ros_context

NAVIGATE_TO_POSE = "navigate_to_pose"
CANCEL_TIMEOUT_S = 5.0  # s (wall) CbAbortNavigation waits for the server's answer to a cancel-all
SPIN = "spin"
BACKUP = "backup"
DRIVE_ON_HEADING = "drive_on_heading"
FOLLOW_PATH = "follow_path"
DOCK_ROBOT = "dock_robot"
UNDOCK_ROBOT = "undock_robot"

ACTION_TYPES: dict[str, Any] = {
    NAVIGATE_TO_POSE: NavigateToPose,
    SPIN: Spin,
    BACKUP: BackUp,
    DRIVE_ON_HEADING: DriveOnHeading,
    FOLLOW_PATH: FollowPath,
    DOCK_ROBOT: DockRobot,
    UNDOCK_ROBOT: UndockRobot,
}

#: The error code of a goal whose server was lost: Nav2's UNKNOWN (bt_navigator's code for a fault of its
#: own: NavigateToPose's codes 9000-9999) for navigate_to_pose, the action's own UNKNOWN for the others.
SERVER_LOST_CODE = 9000
#: error_msg prefix of such a goal's result (a machine's guard tells a lost server by it: is_server_lost)
SERVER_LOST = "server lost"

#: bond/Status as Nav2's bond library publishes it (reliable; heartbeats at 10 Hz per bond).
BOND_QOS = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
STAMPED_PARAMETER = "enable_stamped_cmd_vel"  # the machine's parameter: cmd_vel as TwistStamped
BOND_DISCOVERY_GRACE_S = 3.0  # wall s lockstep waits for /bond to be matched (under sim2d's 5 s timeout)


class ClNav2Z(ISmaccClient):
    """Nav2 client; ``action_names`` may remap any action key to another server name.

    It also owns the machine's ``cmd_vel_topic`` publisher (geometry_msgs/Twist, created at startup so it
    is discovered before a behavior needs it) for the behaviors that command velocities directly. The
    machine's parameter ``enable_stamped_cmd_vel`` (Nav2 Jazzy's name) true makes it a TwistStamped
    publisher stamped with the machine clock, as the robot (sim2d) then expects; sim2d applies a
    stamped command at its stamp plus a fixed delay, so its effect does not depend on when it arrived.
    Unset, it follows the type the robot's cmd_vel subscription takes (nav-bringup's simulator takes
    TwistStamped in lockstep): a machine run by hand beside the stack needs no flag.
    """

    def __init__(self, action_names: dict[str, str] | None = None, cmd_vel_topic: str = "/cmd_vel") -> None:
        self.cmd_vel_topic = cmd_vel_topic
        self.stamped = False  # the cmd_vel type at startup (the parameter, else the robot's, else Twist)
        unknown = set(action_names or {}) - set(ACTION_TYPES)
        if unknown:
            raise ValueError(f"ClNav2Z: unknown action keys {sorted(unknown)}; known: {sorted(ACTION_TYPES)}")
        self.action_names = {key: key for key in ACTION_TYPES} | dict(action_names or {})
        self._clients: dict[str, RosActionClient] = {}
        self._watches: dict[str, ServerLossWatch] = {}
        # each goal's once-only done callback, to end it when its server is lost (watch_server)
        self._enders: weakref.WeakKeyDictionary[GoalTicket, Callable[[GoalTicket], None]] = \
            weakref.WeakKeyDictionary()

    def on_initialize(self) -> None:
        ctx = ros_context(self.sm)
        self.node = ctx.node
        for key, action_type in ACTION_TYPES.items():
            self._clients[key] = RosActionClient(ctx.node, action_type, self.action_names[key])
        if not ctx.node.has_parameter(STAMPED_PARAMETER):  # unset: follow the robot's cmd_vel type
            ctx.node.declare_parameter(STAMPED_PARAMETER, Parameter.Type.BOOL)
        try:
            value = ctx.node.get_parameter(STAMPED_PARAMETER).value
        except ParameterUninitializedException:  # declared by type only: not set
            value = None
        self._cmd_vel = CmdVelPublisher(ctx.node, None if value is None else bool(value),
                                        topic=self.cmd_vel_topic)
        self._cmd_vel.follow_subscribers()  # the robot may be known already (smacc-run after nav-bringup)
        self.stamped = self._cmd_vel.stamped
        # Created with the machine, so that it is discovered before CbAbortNavigation needs it.
        self._cancel_every_goal = ctx.node.create_client(CancelGoal, self.cancel_service_name)

    @property
    def cancel_service_name(self) -> str:
        """The navigate_to_pose server's cancel service (``<action>/_action/cancel_goal``)."""
        return f"{self.action_names[NAVIGATE_TO_POSE]}/_action/cancel_goal"

    def publish_twist(self, linear_x: float = 0.0, angular_z: float = 0.0) -> None:
        """Command a velocity (m/s, rad/s) on ``cmd_vel_topic``; no arguments means stop."""
        self._cmd_vel.publish(linear_x, angular_z)

    def action_client(self, key: str) -> RosActionClient:
        """The action client for ``key`` (navigate_to_pose, spin, backup, drive_on_heading, follow_path)."""
        try:
            return self._clients[key]
        except KeyError:
            raise ValueError(f"ClNav2Z has no action {key!r}; known: {sorted(self._clients)}") from None

    def send_goal(
        self,
        key: str,
        goal: Any,
        on_done: Callable[[GoalTicket], None] | None = None,
        on_feedback: Callable[[GoalTicket, Any], None] | None = None,
    ) -> GoalTicket:
        """Send a goal to action ``key``; the client posts its EvAction* events (payload ``action``: the key,
        even when ``action_names`` remaps the server), then ``on_done`` runs."""
        done, feedback = event_posting_callbacks(self, key, on_done, on_feedback)
        ended: list[bool] = []

        def once(ticket: GoalTicket) -> None:  # a lost goal's late result must not post a second end
            if not ended:
                ended.append(True)
                done(ticket)

        ticket = self.action_client(key).send_goal(goal, once, feedback)
        self._enders[ticket] = once
        return ticket

    def watch_server(self, key: str, ticket: GoalTicket) -> Callable[[], None] | None:
        """Watch the server of ``ticket``'s accepted goal (ros_tools.runtime.action_watch): if it is lost
        (its process died, or a respawned server does not know the goal), the goal ends ABORTED with
        SERVER_LOST_CODE and an error_msg starting with SERVER_LOST, through the same events as a real
        abort, so the machine's own retry or abort path runs. The function that stops watching; None
        while the goal has no accepted handle yet."""
        goal_id = ticket.goal_id
        if goal_id is None or ticket.done:
            return None
        if key not in self._watches:
            self._watches[key] = ServerLossWatch(self.node, ACTION_TYPES[key], self.action_names[key])
        return self._watches[key].watch(goal_id, lambda why: self._end_lost(key, ticket, why))

    def _end_lost(self, key: str, ticket: GoalTicket, why: str) -> None:
        ender = self._enders.get(ticket)
        if ticket.done or ender is None:
            return
        result_type = ACTION_TYPES[key].Result
        result = result_type()
        if hasattr(result, "error_code"):
            code = SERVER_LOST_CODE if key == NAVIGATE_TO_POSE else getattr(result_type, "UNKNOWN", 0)
            result.error_code, result.error_msg = code, f"{SERVER_LOST}: {why}"
        ticket.finish(GoalOutcome.ABORTED, result)
        ender(ticket)

    def send_navigation_goal(
        self, pose: PoseStamped, on_done: Callable[[GoalTicket], None] | None = None
    ) -> GoalTicket:
        """Send a NavigateToPose goal (default behavior tree)."""
        return self.send_goal(NAVIGATE_TO_POSE, NavigateToPose.Goal(pose=pose), on_done)

    def subscribe_bonds(
        self, callback: Callable[[str, bool], None], topic: str = "bond",
        hold_until: Callable[[], bool] | None = None,
    ) -> Callable[[], None]:
        """Call ``callback(node_id, active)`` for each bond heartbeat (bond/Status) on ``topic``, on the
        executor; returns the function that unsubscribes. Nav2's servers heartbeat a bond with their
        lifecycle manager once active, which is how CbWaitNav2Nodes knows that Nav2 is up.

        In lockstep, sim time waits (at most BOND_DISCOVERY_GRACE_S wall seconds) until
        ``hold_until()`` is true, by default until DDS has matched a heartbeat publisher. Otherwise a
        state's sim-time fallback (StAllSensorsGo's 15 s) could run out during discovery at
        ``--rtf max``, and the sim time at which Nav2 counts as up would follow the machine's load:
        the heartbeats run on a wall timer (every 0.1 s, as Nav2's)."""
        ctx = ros_context(self.sm)

        def on_status(msg: Status) -> None:
            callback(msg.id, msg.active)

        subscription = ctx.node.create_subscription(Status, topic, on_status, BOND_QOS)
        subscribed = [True]
        ready = hold_until or (lambda: subscription.get_publisher_count() > 0)
        ctx.hold_lockstep(lambda: not subscribed[0] or ready(), BOND_DISCOVERY_GRACE_S)

        def unsubscribe() -> None:
            subscribed[0] = False  # the hold must not ask a destroyed subscription
            ctx.node.destroy_subscription(subscription)

        return unsubscribe

    def lookup_transform(self, target_frame: str, source_frame: str) -> Transform:
        """The latest transform mapping points in ``source_frame`` into ``target_frame`` (tf2's
        ``lookupTransform(target, source)``) from the machine's shared TF listener, which starts
        listening on the first call; TransformError with tf2's message while it is not available."""
        return ros_context(self.sm).tf_listener().lookup(target_frame, source_frame)

    def cancel_navigation(self) -> None:
        """Cancel every NavigateToPose goal this client sent that is still running."""
        self._clients[NAVIGATE_TO_POSE].cancel_all()

    def cancel_every_navigation_goal(self, on_answer: Callable[[int | None], None]) -> None:
        """Ask the navigate_to_pose server to cancel every goal, whoever sent it (CancelGoal with a
        zero goal id and stamp). ``on_answer`` runs on the executor with the number of goals the
        server is canceling, or None when the server is not there or did not answer within
        CANCEL_TIMEOUT_S s. The request is sent again while unanswered (ros_tools.runtime.requests).
        """
        if not self._cancel_every_goal.service_is_ready():
            on_answer(None)
            return
        answer = spawn(self.node, call_service(self.node, self._cancel_every_goal, CancelGoal.Request(),
                                               CANCEL_TIMEOUT_S))
        answer.add_done_callback(lambda done: on_answer(
            None if done.result() is None else len(done.result().goals_canceling)))


def is_server_lost(event: Any) -> bool:
    """Whether an EvActionAborted / EvCbFailure says the action server was lost (ClNav2Z.watch_server),
    for a machine's guard: a lost navigator is worth a retry once the stack is back, a planning
    failure is not."""
    return str(getattr(event, "error_msg", "")).startswith(SERVER_LOST)
