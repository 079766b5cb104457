"""The base of every Nav2-named server: a lifecycle node that also keeps a bond with its manager.

Nav2's servers (map_server, amcl, planner_server, ...) are lifecycle nodes: a lifecycle manager
configures and activates them in order, and each active node heartbeats a bond on ``bond`` (relative:
``/bond`` for a stack in the root namespace, ``/robot1/bond`` for a fleet robot's) so the manager
(and SMACC2's CbWaitNav2Nodes) can tell it is alive. This base gives subclasses four hooks
(``configure``, ``activate``, ``deactivate``, ``cleanup``) that may raise; an exception becomes a
logged FAILURE of the transition (the node keeps serving its lifecycle services) instead of a crash.
A transition that is not valid from the current state is answered ``success: false``, as rclcpp's
lifecycle nodes answer it (rclpy 7.1 raises from the service callback, which ends the process); a
manager that sent a transition again, its first answer lost in discovery, gets that answer.
"""

from __future__ import annotations

import uuid
from collections.abc import Callable
from typing import Any

from bond.msg import Status
from rclpy.clock import Clock, ClockType
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.timer import Timer

from ros_tools.runtime.clock_timers import ClockTimer
from ros_tools.runtime.executor import reentrant_default_group

RCLError = _rclpy.RCLError  # what rcl's lifecycle state machine raises for an invalid transition

#: Relative, as nav2_util::LifecycleNode::createBond and the lifecycle manager name it: a namespaced
#: stack's bonds stay in its namespace, where its manager (in the same namespace) listens.
BOND_TOPIC = "bond"
BOND_HEARTBEAT_PERIOD = 0.1  # s, as nav2_util::LifecycleNode::createBond sets it
BOND_HEARTBEAT_TIMEOUT = 4.0  # s, Nav2's default bond_timeout
BOND_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


class NavLifecycleNode(LifecycleNode):
    """A lifecycle node with Nav2's bond heartbeat and exception-safe transition hooks.

    Subclasses override ``configure``/``activate``/``deactivate``/``cleanup`` (no return value;
    raise to fail the transition with a logged reason).
    """

    def __init__(self, node_name: str, **kwargs: object) -> None:
        super().__init__(node_name, **kwargs)  # type: ignore[arg-type]
        reentrant_default_group(self)
        self._bond_pub = self.create_publisher(Status, BOND_TOPIC, BOND_QOS)
        self._bond_instance = str(uuid.uuid4())
        self._bond_timer: Timer | None = None
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._service_change_state.callback = self._refusing_invalid(self._service_change_state.callback)

    def _refusing_invalid(self, change_state: Callable[[Any, Any], Any]) -> Callable[[Any, Any], Any]:
        """rclpy's change_state callback, answering ``success: false`` to a transition that is not
        valid from the current state (the state is unchanged) instead of raising."""

        def guarded(request: Any, response: Any) -> Any:
            try:
                return change_state(request, response)
            except RCLError as error:
                label = self._state_machine.current_state[1]
                self.get_logger().warning(f"Unable to start transition {request.transition.id} from "
                                          f"current state {label}: {str(error).split(',')[0]}")
                response.success = False
                return response

        return guarded

    # -- hooks for subclasses ------------------------------------------------------------------
    def destroy_timer(self, timer: Any) -> bool:
        """rclpy's ``destroy_timer``, also for the clock-driven timers of
        ``ros_tools.runtime.timers.create_periodic_timer`` (sim time), which no executor holds."""
        if isinstance(timer, ClockTimer):
            timer.destroy()
            return True
        return super().destroy_timer(timer)

    def configure(self) -> None:
        """Declare and read parameters, create publishers, services and the core objects."""

    def activate(self) -> None:
        """Start working: timers, subscriptions that drive the core, action servers' acceptance."""

    def deactivate(self) -> None:
        """Stop producing output; keep configuration."""

    def cleanup(self) -> None:
        """Release what ``configure`` created."""

    # -- rclpy lifecycle callbacks -------------------------------------------------------------
    def _run(self, name: str, hook: object) -> TransitionCallbackReturn:
        try:
            hook()  # type: ignore[operator]
        except Exception as error:  # any failure must fail the transition, not kill the node
            self.get_logger().error(f"{name} failed: {error}")
            return TransitionCallbackReturn.FAILURE
        return TransitionCallbackReturn.SUCCESS

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.get_logger().info("Configuring")
        return self._run("configure", self.configure)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.get_logger().info("Activating")
        result = self._run("activate", self.activate)
        if result == TransitionCallbackReturn.SUCCESS:
            super().on_activate(state)  # activates LifecyclePublishers
            self._start_bond()
        return result

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.get_logger().info("Deactivating")
        self._stop_bond()
        super().on_deactivate(state)
        return self._run("deactivate", self.deactivate)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.get_logger().info("Cleaning up")
        return self._run("cleanup", self.cleanup)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.get_logger().info("Shutting down")
        self._stop_bond()
        return TransitionCallbackReturn.SUCCESS

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.get_logger().error(f"Lifecycle error while in state {state.label}")
        self._stop_bond()
        return TransitionCallbackReturn.SUCCESS

    # -- bond ------------------------------------------------------------------------------------
    def _bond_status(self, active: bool) -> Status:
        msg = Status()
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.id = self.get_name()
        msg.instance_id = self._bond_instance
        msg.active = active
        msg.heartbeat_timeout = BOND_HEARTBEAT_TIMEOUT
        msg.heartbeat_period = BOND_HEARTBEAT_PERIOD
        return msg

    def _start_bond(self) -> None:
        if self._bond_timer is None:
            self._bond_timer = self.create_timer(
                BOND_HEARTBEAT_PERIOD, lambda: self._bond_pub.publish(self._bond_status(True)),
                clock=self._steady,
            )

    def _stop_bond(self) -> None:
        if self._bond_timer is not None:
            self.destroy_timer(self._bond_timer)
            self._bond_timer = None
            self._bond_pub.publish(self._bond_status(False))
