"""velocity_smoother over DDS on a /clock this test drives: a 0.5 m/s step becomes a ramp within
max_accel that reaches the target; a silent input brakes to zero after velocity_timeout, then the
node falls silent. Run with Twist and with TwistStamped (stamps on the cycle grid, input frame kept)."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator
from typing import Any

import pytest

pytest.importorskip("rosgraph_msgs.msg")

from geometry_msgs.msg import Twist, TwistStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock

from nav_stack.core.velocity_smoother import VelocitySmootherParams, check_command_series
from nav_stack.ros.control.velocity_smoother import VelocitySmoother, build_nodes
from navsuite_testing.nav.world import Harness
from navsuite_testing.ros import wait_until
from ros_tools.cmd_vel import CMD_VEL_QOS

pytestmark = pytest.mark.ros

CLOCK_STEP_NS = 10_000_000  # sim time per /clock message
START_NS = 1_000_000_000
PARAMS = VelocitySmootherParams()  # the node's defaults: 20 Hz, 2.5 m/s², timeout 1 s
PERIOD_NS = round(1e9 / PARAMS.smoothing_frequency)
INPUT_FRAME = "base_footprint"


class Probe(Node):
    """Drives /clock, publishes cmd_vel like a controller, records cmd_vel_smoothed."""

    def __init__(self, context: Any, stamped: bool, sim_now_ns: Callable[[], int]) -> None:
        super().__init__("velocity_smoother_probe", context=context)
        self.stamped = stamped
        self.sim_now_ns = sim_now_ns
        self.type = TwistStamped if stamped else Twist
        self.clock_pub = self.create_publisher(Clock, "/clock", 10)
        self.cmd_pub = self.create_publisher(self.type, "cmd_vel", CMD_VEL_QOS)
        self.received: list[tuple[Any, int]] = []  # (message, server's sim time at arrival, ns)
        self.smoothed_sub = self.create_subscription(self.type, "cmd_vel_smoothed", self._on_smoothed,
                                                     CMD_VEL_QOS)
        self.now_ns = START_NS

    def _on_smoothed(self, msg: Any) -> None:
        self.received.append((msg, self.sim_now_ns()))

    def tick(self) -> None:
        """Publish the next /clock and wait until the smoother's clock reads it."""
        self.now_ns += CLOCK_STEP_NS
        self.clock_pub.publish(Clock(clock=_time(self.now_ns)))
        wait_until(lambda: self.sim_now_ns() >= self.now_ns, 10.0, "the node clock to follow /clock",
                   step=0.001)

    def command(self, vx: float) -> None:
        twist = Twist()
        twist.linear.x = vx
        if not self.stamped:
            self.cmd_pub.publish(twist)
            return
        msg = TwistStamped(twist=twist)
        msg.header.frame_id = INPUT_FRAME
        msg.header.stamp = _time(self.now_ns)
        self.cmd_pub.publish(msg)


def _time(ns: int) -> Any:
    from builtin_interfaces.msg import Time

    sec, nanosec = divmod(ns, 1_000_000_000)
    return Time(sec=sec, nanosec=nanosec)


@pytest.fixture(params=[False, True], ids=["Twist", "TwistStamped"])
def rig(request: Any, ros_context: Any) -> Iterator[tuple[Probe, Any]]:
    harness = Harness(ros_context)
    try:
        stamped = request.param
        (server,) = build_nodes(use_sim_time=True, context=ros_context, parameter_overrides=[
            Parameter("enable_stamped_cmd_vel", value=stamped)])
        probe = Probe(ros_context, stamped, lambda: server.get_clock().now().nanoseconds)
        harness.add(server, probe)
        probe.clock_pub.publish(Clock(clock=_time(START_NS)))
        wait_until(lambda: server.get_clock().now().nanoseconds == START_NS, 20.0, "the first /clock")
        harness.bring_up(server)
        wait_until(lambda: probe.cmd_pub.get_subscription_count() > 0
                   and probe.smoothed_sub.get_publisher_count() > 0, 20.0, "cmd_vel discovery")
        yield probe, server
    finally:
        harness.close()


def test_a_step_ramps_within_max_accel_and_a_silent_input_brakes_to_zero(rig: tuple[Probe, Any]) -> None:
    probe, _ = rig
    for k in range(100):  # 1 s of a 0.5 m/s command at 20 Hz, like a controller
        if k % 5 == 0:
            probe.command(0.5)
            last_command_ns = probe.now_ns
        probe.tick()
    timeout_ns = round(PARAMS.velocity_timeout * 1e9)
    while probe.now_ns < last_command_ns + timeout_ns + 1_000_000_000:  # silent input
        probe.tick()
    count = len(probe.received)
    for _ in range(50):  # half a second more: nothing new
        probe.tick()
    assert len(probe.received) == count

    twists = [msg.twist if probe.stamped else msg for msg, _ in probe.received]
    series = [(t.linear.x, t.linear.y, t.angular.z) for t in twists]
    xs = [round(x, 9) for x, _, _ in series]
    print(f"\n{len(xs)} outputs: {xs[:6]} ... {xs[-6:]}")
    step = PARAMS.max_accel[0] / PARAMS.smoothing_frequency  # 0.125 m/s per cycle
    assert xs[:4] == [step, 2 * step, 3 * step, 0.5]  # a ramp from rest that reaches the target
    assert check_command_series(series, PARAMS) == []
    assert max(abs(b - a) for a, b in zip([0.0, *xs], xs, strict=False)) <= step + 1e-9
    # after the timeout: braking at max_decel, a final zero, then silence
    assert xs[-5:] == [0.5, 3 * step, 2 * step, step, 0.0]
    braking_at = probe.received[-4][1]
    assert braking_at - last_command_ns >= timeout_ns  # not before velocity_timeout
    assert probe.received[-1][1] - last_command_ns <= timeout_ns + 4 * PERIOD_NS + 300_000_000
    if probe.stamped:
        stamps = [m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec for m, _ in probe.received]
        assert all(b - a == PERIOD_NS for a, b in itertools.pairwise(stamps))  # the cycle grid
        assert (stamps[0] - START_NS) % PERIOD_NS == 0
        assert stamps[-4] - last_command_ns > timeout_ns
        assert {msg.header.frame_id for msg, _ in probe.received} == {INPUT_FRAME}


def test_bad_parameters_fail_configure_and_bad_updates_are_refused(ros_context: Any, capfd: Any) -> None:
    from rclpy.lifecycle import TransitionCallbackReturn

    bad = VelocitySmoother(context=ros_context, parameter_overrides=[
        Parameter("max_decel", value=[-2.5, 0.0, 3.2])])
    good = VelocitySmoother(context=ros_context)
    try:
        assert bad.trigger_configure() == TransitionCallbackReturn.FAILURE
        reason = ("velocity_smoother: invalid parameters for VelocitySmootherParams: "
                  "max_decel[2] (theta) = 3.2: must be <= 0")
        assert reason in capfd.readouterr().err
        assert good.trigger_configure() == TransitionCallbackReturn.SUCCESS
        assert good.trigger_activate() == TransitionCallbackReturn.SUCCESS
        (refused,) = good.set_parameters([Parameter("feedback", value="ODOMETRY")])
        assert not refused.successful and "feedback = 'ODOMETRY'" in refused.reason
        (taken,) = good.set_parameters([Parameter("max_accel", value=[1.0, 0.0, 3.2])])
        assert taken.successful and good.params.max_accel == (1.0, 0.0, 3.2)
        assert good.params.feedback == "OPEN_LOOP" and good._odom_sub is None
        closed = good.set_parameters_atomically([Parameter("feedback", value="CLOSED_LOOP"),
                                                 Parameter("odom_topic", value="wheel_odom")])
        assert closed.successful and good._odom_sub is not None
        assert good._odom_sub.topic_name == "/wheel_odom"  # odometry is read from now on
    finally:
        bad.destroy_node()
        good.destroy_node()
