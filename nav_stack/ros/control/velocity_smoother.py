"""velocity_smoother: Nav2 Jazzy's command smoother between the controllers and the robot.

Subscribes ``cmd_vel`` (nav2_bringup remaps it to ``cmd_vel_nav``), publishes ``cmd_vel_smoothed``;
both Twist, or TwistStamped with ``enable_stamped_cmd_vel``, with Nav2's cmd_vel QoS. In CLOSED_LOOP
it also reads ``odom_topic``. The law (limits, eta scaling, deadband, timeout) is
nav_stack.core.velocity_smoother; this node only translates messages and schedules its cycles.

Cycles run on a timer of the node clock (sim time), and a stamped output carries the cycle's nominal
time on the timer's grid, not the arrival time of the input (Nav2 Jazzy copies the input's stamp):
see ros_tools.runtime.timers.nominal_call_ns for why the grid keeps runs repeatable. The output's
frame is the last stamped input's frame, else ``base_link``.

Run-time parameter changes are taken while active, as Nav2's dynamicParametersCallback takes them;
``enable_stamped_cmd_vel`` changes the message types at the next configure only.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node

from nav_stack.core.velocity_smoother import CLOSED_LOOP, CommandSmoother, Velocity, VelocitySmootherParams
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.node_runner import with_sim_time
from nav_stack.ros.common.params import declare_dataclass, on_dataclass_update
from nav_stack.ros.common.qos import DEFAULT
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.cmd_vel import CMD_VEL_QOS, CmdVelPublisher
from ros_tools.runtime.timers import create_periodic_timer, nominal_call_ns

NODE_NAME = "velocity_smoother"
INPUT_TOPIC = "cmd_vel"
OUTPUT_TOPIC = "cmd_vel_smoothed"
DEFAULT_FRAME = "base_link"  # the output frame until a stamped input names one
WARN_PERIOD = 5.0  # s between two warnings about invalid commands


class VelocitySmoother(NavLifecycleNode):
    """The ``velocity_smoother`` lifecycle node."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self._timer: Any = None
        self._odom_sub: Any = None
        self._param_callback: Any = None

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        p = self.params = declare_dataclass(self, VelocitySmootherParams)
        self._smoother = CommandSmoother(p)
        self._frame_id = DEFAULT_FRAME
        self._cmd = CmdVelPublisher(self, p.enable_stamped_cmd_vel, DEFAULT_FRAME, OUTPUT_TOPIC)
        self._cmd_sub = self.create_subscription(TwistStamped if self._cmd.stamped else Twist, INPUT_TOPIC,
                                                 self._on_command, CMD_VEL_QOS)
        self._subscribe_odometry()

    def activate(self) -> None:
        self._start_timer()
        self._param_callback = on_dataclass_update(self, VelocitySmootherParams, "", lambda: self.params,
                                                   self._apply)

    def deactivate(self) -> None:
        self.remove_on_set_parameters_callback(self._param_callback)
        self._param_callback = None
        self.destroy_timer(self._timer)
        self._timer = None

    def cleanup(self) -> None:
        self.destroy_subscription(self._cmd_sub)
        if self._odom_sub is not None:
            self.destroy_subscription(self._odom_sub)
            self._odom_sub = None
        self._cmd.destroy()

    # -- inputs ------------------------------------------------------------------------------------
    def _on_command(self, msg: Twist | TwistStamped) -> None:
        twist = msg.twist if isinstance(msg, TwistStamped) else msg
        now = self.get_clock().now().nanoseconds * 1e-9
        if not self._smoother.command((twist.linear.x, twist.linear.y, twist.angular.z), now):
            self.get_logger().warning("Velocity message contains NaNs or Infs! Ignoring as invalid!",
                                      throttle_duration_sec=WARN_PERIOD)
            return
        if isinstance(msg, TwistStamped):
            self._frame_id = msg.header.frame_id or DEFAULT_FRAME

    def _on_odom(self, msg: Odometry) -> None:
        stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        t = msg.twist.twist
        self._smoother.odometry.add(stamp, (t.linear.x, t.linear.y, t.angular.z))

    def _subscribe_odometry(self) -> None:
        """Odometry is read in CLOSED_LOOP only (Nav2 makes its OdomSmoother only then)."""
        if self._odom_sub is not None:
            self.destroy_subscription(self._odom_sub)
            self._odom_sub = None
        if self.params.feedback == CLOSED_LOOP:
            self._odom_sub = self.create_subscription(Odometry, self.params.odom_topic, self._on_odom,
                                                      DEFAULT)

    # -- the smoothing cycle -----------------------------------------------------------------------
    def _start_timer(self) -> None:
        if self._timer is not None:
            self.destroy_timer(self._timer)
        self._timer = create_periodic_timer(self, 1.0 / self.params.smoothing_frequency, self._cycle)

    def _cycle(self) -> None:
        cycle_ns = nominal_call_ns(self, self._timer)
        output = self._smoother.cycle(cycle_ns * 1e-9)
        if output is not None:
            self._publish(output, cycle_ns)

    def _publish(self, velocity: Velocity, stamp_ns: int) -> None:
        """Publish (vx, vy, wz) in the last stamped input's frame."""
        self._cmd.frame_id = self._frame_id
        vx, vy, wz = velocity
        self._cmd.publish(vx, wz, stamp_ns, vy=vy)

    # -- run-time parameters -----------------------------------------------------------------------
    def _apply(self, params: VelocitySmootherParams) -> None:
        old, self.params = self.params, params
        self._smoother.update_params(params)
        if params.smoothing_frequency != old.smoothing_frequency and self._timer is not None:
            self._start_timer()
        if (params.feedback, params.odom_topic, params.odom_duration) != (
                old.feedback, old.odom_topic, old.odom_duration):
            self._subscribe_odometry()


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """The velocity_smoother node, ready to add to an executor."""
    kwargs = with_sim_time(kwargs, use_sim_time)
    return [VelocitySmoother(**kwargs)]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.control.velocity_smoother [--autostart] [--ros-args ...]``."""
    return run_nodes(build_nodes, argv, role=NODE_NAME)


if __name__ == "__main__":
    raise SystemExit(main())
