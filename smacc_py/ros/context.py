"""How clients, components and behaviors reach the ROS node that runs their machine.

The core engine knows nothing about ROS. The runtime attaches one ``RosContext`` to the machine
before ``initialize()`` (so clients may create publishers in ``on_initialize``); everything below the
runtime fetches it with ``ros_context(sm)``. The node and the shared transform listener are injected
this way, never created behind the runtime's back (no singleton node).

Every callback of the node runs on the runtime's one executor thread, the same thread that
dispatches the machine's events, so client callbacks need no callback group and no lock against the
machine; they must return quickly and never wait (no sleep, no blocking future or event).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from smacc_py.core import SmaccError

if TYPE_CHECKING:
    from collections.abc import Callable

    from rclpy.node import Node

    from ros_tools.runtime.lockstep import LockstepParticipant
    from ros_tools.tf.ros import TransformListener

_ATTR = "_smacc_ros_context"
#: wall s a client holds lockstep while DDS discovers a peer it is about to talk to (an action server,
#: AMCL's initial pose subscription): a few hundred ms on localhost; under sim2d's 10 s participant timeout.
DISCOVERY_HOLD_S = 2.0


@dataclass
class RosContext:
    """The ROS side of one running machine.

    Attributes:
        node: the machine's node (named after the machine class).
        participant: the process's lockstep participant (None without ``use_sim_time``).
    """

    node: Node
    participant: LockstepParticipant | None = None
    _tf: TransformListener | None = field(default=None, repr=False)

    def hold_lockstep(self, until: Callable[[], bool], grace_s: float) -> None:
        """Keep a lockstep simulator from stepping on until ``until()`` or ``grace_s`` wall seconds.

        For a client that just subscribed to something a sim-time deadline waits for (see
        LockstepParticipant.hold); nothing happens when the machine is not in lockstep.
        """
        if self.participant is not None:
            self.participant.hold(until, grace_s)

    def tf_listener(self) -> TransformListener:
        """The machine's one TransformListener (created on first use, shared by every CpPose)."""
        if self._tf is None:
            from ros_tools.tf.ros import TransformListener

            self._tf = TransformListener(self.node)
        return self._tf

    def now_s(self) -> float:
        """The node clock in seconds (sim time when ``use_sim_time`` is true)."""
        return self.node.get_clock().now().nanoseconds * 1e-9

    def destroy(self) -> None:
        """Release the shared listener (the runtime destroys the node itself)."""
        if self._tf is not None:
            self._tf.destroy()
            self._tf = None


def attach_ros_context(sm: object, context: RosContext) -> None:
    """Give a machine its ROS context (the runtime calls this before ``initialize()``)."""
    setattr(sm, _ATTR, context)


def hold_lockstep(sm: object, until: Callable[[], bool], grace_s: float = DISCOVERY_HOLD_S) -> None:
    """:meth:`RosContext.hold_lockstep` for ``sm`` when a ROS runtime runs it; nothing otherwise (a
    machine driven by test stand-ins has no simulator to hold)."""
    context = getattr(sm, _ATTR, None)
    if context is not None:
        context.hold_lockstep(until, grace_s)


def ros_context(sm: object) -> RosContext:
    """The ROS context of ``sm``; SmaccError when the machine is not run by a ROS runtime."""
    context = getattr(sm, _ATTR, None)
    if context is None:
        raise SmaccError(
            f"{type(sm).__name__} has no ROS node: ROS clients need the machine to be run by "
            "smacc_py.ros.runtime.SmaccRuntime (or smacc-run)"
        )
    return context  # type: ignore[no-any-return]
