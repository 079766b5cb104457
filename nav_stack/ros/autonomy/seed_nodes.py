"""The seed project's six node types (tb3_autonomy: navigation_behaviors.cpp, battery_behavior.cpp)
for the nav_stack BT engine, with the seed's bugs fixed.

* GoToPose: NavigateToPose goal (map frame) for the location named by port ``loc``. Waits for the
  action server without blocking, up to ``server_timeout`` s (wall clock: discovery is wall time),
  then FAILURE with a log line; SUCCESS on SUCCEEDED; FAILURE on abort, cancel or rejection (the
  seed stayed RUNNING forever); halting it cancels the goal (the seed's onHalted was empty).
* IsBatteryLow, DecrementBattery, CheckBattery, RechargeBattery: ask a ``BatterySource``
  (battery.py: the seed's counter, or /battery_state). RechargeBattery is asynchronous.
* WaitSeconds: RUNNING for port ``seconds`` of tree time (sim time under ROS); the seed blocked
  its only executor thread with sleep_for for 30 s.

No ROS here: the navigator is injected (``Navigator`` protocol), so unit tests drive the real
classes with a fake and the node passes an rclpy action client (navigator.py).
"""

from __future__ import annotations

import enum
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Protocol

from nav_stack.core.bt import (
    BehaviorTreeFactory,
    ConditionNode,
    NodeConfig,
    NodeStatus,
    PortList,
    StatefulActionNode,
    SyncActionNode,
    input_port,
)
from nav_stack.ros.autonomy.battery import BatterySource, RechargeState
from nav_stack.ros.autonomy.locations import Location


class NavOutcome(enum.Enum):
    """How a NavigateToPose goal ended."""

    SUCCEEDED = "succeeded"
    ABORTED = "aborted"
    CANCELED = "canceled"
    REJECTED = "rejected"


class NavGoal(Protocol):
    """A goal in flight."""

    def outcome(self) -> NavOutcome | None:
        """None while running."""

    def detail(self) -> str:
        """Nav2's error code and message of a failed goal ('' when none)."""

    def cancel(self) -> None:
        """Ask the server to cancel (no-op once ended)."""


class Navigator(Protocol):
    """A NavigateToPose client that never blocks."""

    action_name: str

    def server_ready(self) -> bool:
        """True once the action server is discovered."""

    def send(self, location: Location) -> NavGoal:
        """Send a goal to ``location`` (map frame)."""


class Log(Protocol):
    """The subset of a logger the nodes use (rclpy's and stdlib's both fit)."""

    def info(self, message: str) -> object: ...

    def warning(self, message: str) -> object: ...

    def error(self, message: str) -> object: ...


class _NullLog:
    def info(self, message: str) -> None:
        pass

    warning = error = info


@dataclass
class SeedContext:
    """What the six node types share (one per tree; the seed used globals instead).

    Attributes:
        navigator: the NavigateToPose client.
        battery: the battery source (counter or topic).
        locations: name → pose, validated against the tree at load.
        server_timeout: wall s GoToPose waits for the action server before failing.
        wall_clock: wall time in s (injected for tests).
        log: where the nodes report arrivals and failures.
        trace: what happened, in order: location names on arrival, ``wait`` and ``recharge``.
    """

    navigator: Navigator
    battery: BatterySource
    locations: Mapping[str, Location]
    server_timeout: float = 10.0
    wall_clock: Callable[[], float] = time.monotonic
    log: Log = field(default_factory=_NullLog)
    trace: list[str] = field(default_factory=list)


class _SeedNode:
    ctx: SeedContext

    def __init__(self, name: str, config: NodeConfig, context: SeedContext) -> None:
        super().__init__(name, config)  # type: ignore[call-arg]
        self.ctx = context


class GoToPose(_SeedNode, StatefulActionNode):
    """Drive to the location named by ``loc`` through NavigateToPose."""

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("loc", str, description="name of a pose in the locations file", required=True),)

    def __init__(self, name: str, config: NodeConfig, context: SeedContext) -> None:
        super().__init__(name, config, context)
        self._goal: NavGoal | None = None
        self._location: Location | None = None
        self._server_deadline = 0.0

    def on_start(self) -> NodeStatus:
        loc = str(self.get_input("loc"))
        location = self.ctx.locations.get(loc)
        if location is None:  # only reachable through a {key} port: literals are checked at load
            self.ctx.log.error(f"{self.name}: unknown location '{loc}'")
            return NodeStatus.FAILURE
        self._location, self._goal = location, None
        self._server_deadline = self.ctx.wall_clock() + self.ctx.server_timeout
        return self._send_when_ready()

    def _send_when_ready(self) -> NodeStatus:
        assert self._location is not None
        navigator = self.ctx.navigator
        if not navigator.server_ready():
            if self.ctx.wall_clock() > self._server_deadline:
                self.ctx.log.error(f"{self.name}: action server '{navigator.action_name}' not available "
                                   f"after {self.ctx.server_timeout:g} s; is the navigation stack running?")
                return NodeStatus.FAILURE
            return NodeStatus.RUNNING
        loc = self._location
        self.ctx.log.info(f"{self.name}: going to {loc.name} ({loc.x:.2f}, {loc.y:.2f}, {loc.theta:.2f})")
        self._goal = navigator.send(loc)
        return NodeStatus.RUNNING

    def on_running(self) -> NodeStatus:
        if self._goal is None:
            return self._send_when_ready()
        outcome = self._goal.outcome()
        if outcome is None:
            return NodeStatus.RUNNING
        assert self._location is not None
        if outcome is NavOutcome.SUCCEEDED:
            self.ctx.log.info(f"{self.name}: reached {self._location.name}")
            self.ctx.trace.append(self._location.name)
            return NodeStatus.SUCCESS
        detail = self._goal.detail()
        self.ctx.log.warning(f"{self.name}: goal to {self._location.name} {outcome.value}"
                             + (f" ({detail})" if detail else ""))
        return NodeStatus.FAILURE

    def on_halted(self) -> None:
        if self._goal is not None and self._goal.outcome() is None:
            self.ctx.log.info(f"{self.name}: halted, cancelling the goal to "
                              f"{self._location.name if self._location else '?'}")
            self._goal.cancel()
        self._goal = None


class IsBatteryLow(_SeedNode, ConditionNode):
    """SUCCESS when the battery needs charging (counter: exactly empty)."""

    def tick(self) -> NodeStatus:
        return NodeStatus.SUCCESS if self.ctx.battery.is_low() else NodeStatus.FAILURE


class CheckBattery(_SeedNode, ConditionNode):
    """SUCCESS while some usable charge is left."""

    def tick(self) -> NodeStatus:
        if self.ctx.battery.has_charge():
            return NodeStatus.SUCCESS
        self.ctx.log.warning(f"{self.name}: battery {self.ctx.battery.describe()}: patrol stops, recharging")
        return NodeStatus.FAILURE


class DecrementBattery(_SeedNode, SyncActionNode):
    """Account for one patrol leg (counter: −25 %; topic: nothing, the simulator drains)."""

    def tick(self) -> NodeStatus:
        self.ctx.battery.decrement()
        self.ctx.log.info(f"{self.name}: battery {self.ctx.battery.describe()}")
        return NodeStatus.SUCCESS


class RechargeBattery(_SeedNode, StatefulActionNode):
    """Charge until full (counter: at once; topic: until the simulator reports the threshold)."""

    def on_start(self) -> NodeStatus:
        return self._from_recharge(self.ctx.battery.start_recharge(self.now()))

    def on_running(self) -> NodeStatus:
        return self._from_recharge(self.ctx.battery.poll_recharge(self.now()))

    def _from_recharge(self, state: RechargeState) -> NodeStatus:
        if state is RechargeState.CHARGING:
            return NodeStatus.RUNNING
        if state is RechargeState.CHARGED:
            self.ctx.log.info(f"{self.name}: recharged, battery {self.ctx.battery.describe()}")
            self.ctx.trace.append("recharge")
            return NodeStatus.SUCCESS
        self.ctx.log.error(f"{self.name}: recharge failed, battery {self.ctx.battery.describe()} "
                           "(is the robot parked at the station?)")
        return NodeStatus.FAILURE


class WaitSeconds(_SeedNode, StatefulActionNode):
    """RUNNING for ``seconds`` of tree time, without blocking."""

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("seconds", float, description="wait time in s", required=True),)

    def __init__(self, name: str, config: NodeConfig, context: SeedContext) -> None:
        super().__init__(name, config, context)
        self._until = 0.0

    def on_start(self) -> NodeStatus:
        seconds = float(self.get_input("seconds"))
        self._until = self.now() + seconds
        self.ctx.log.info(f"{self.name}: waiting {seconds:g} s")
        self.ctx.trace.append("wait")
        return NodeStatus.RUNNING if seconds > 0.0 else NodeStatus.SUCCESS

    def on_running(self) -> NodeStatus:
        return NodeStatus.SUCCESS if self.now() >= self._until else NodeStatus.RUNNING


SEED_NODE_TYPES: dict[str, type[_SeedNode]] = {
    "GoToPose": GoToPose,
    "IsBatteryLow": IsBatteryLow,
    "DecrementBattery": DecrementBattery,
    "CheckBattery": CheckBattery,
    "RechargeBattery": RechargeBattery,
    "WaitSeconds": WaitSeconds,
}


def register_seed_nodes(factory: BehaviorTreeFactory, context: SeedContext) -> None:
    """Register the six seed node types, all sharing ``context``."""
    for node_id, node_type in SEED_NODE_TYPES.items():
        factory.register(node_id, node_type, context=context)  # type: ignore[arg-type]
