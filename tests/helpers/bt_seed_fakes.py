"""Fakes of the seed project's six BT node types (Tannous987/nav_tb3_ws, battery_behavior.cpp and
navigation_behaviors.cpp), for running its tree.xml in unit tests without ROS.

Same logic as the seed, minus its bugs: the battery is an injected object, not a process-global
static; ``WaitSeconds`` waits in tree time without blocking; ``GoToPose`` "drives" for a fixed
number of ticks and fails on an unknown location instead of staying RUNNING forever.
"""

from __future__ import annotations

from dataclasses import dataclass, field

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

SEED_LOCATIONS = {
    "location1": (-1.03, -0.51, 0.0),
    "location2": (-0.56, -1.03, 0.0),
    "location3": (-1.43, -1.34, 3.14),
    "location4": (-1.58, -1.48, 3.14),
    "station": (-1.37, -0.82, 0.0),
}


@dataclass
class SeedWorld:
    """What the seed's nodes share: battery level (%), the event log, travel time in ticks."""

    battery: int = 100
    log: list[str] = field(default_factory=list)
    travel_ticks: int = 3
    locations: dict[str, tuple[float, float, float]] = field(default_factory=lambda: dict(SEED_LOCATIONS))


class IsBatteryLow(ConditionNode):
    """SUCCESS iff the battery is exactly empty (the seed's definition of 'low')."""

    def __init__(self, name: str, config: NodeConfig, world: SeedWorld) -> None:
        super().__init__(name, config)
        self.world = world

    def tick(self) -> NodeStatus:
        return NodeStatus.SUCCESS if self.world.battery == 0 else NodeStatus.FAILURE


class CheckBattery(IsBatteryLow):
    """SUCCESS iff some charge is left."""

    def tick(self) -> NodeStatus:
        return NodeStatus.SUCCESS if self.world.battery > 0 else NodeStatus.FAILURE


class DecrementBattery(SyncActionNode):
    """Battery −25 %, clamped at 0."""

    def __init__(self, name: str, config: NodeConfig, world: SeedWorld) -> None:
        super().__init__(name, config)
        self.world = world

    def tick(self) -> NodeStatus:
        self.world.battery = max(0, self.world.battery - 25)
        return NodeStatus.SUCCESS


class RechargeBattery(DecrementBattery):
    """Battery back to 100 %."""

    def tick(self) -> NodeStatus:
        self.world.battery = 100
        self.world.log.append("recharge")
        return NodeStatus.SUCCESS


class GoToPose(StatefulActionNode):
    """Drives to ``loc`` in ``world.travel_ticks`` ticks; logs the location when it arrives."""

    def __init__(self, name: str, config: NodeConfig, world: SeedWorld) -> None:
        super().__init__(name, config)
        self.world = world
        self._remaining = 0
        self._target = ""

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("loc", str, description="key in locations.yaml", required=True),)

    def on_start(self) -> NodeStatus:
        self._target = str(self.get_input("loc"))
        if self._target not in self.world.locations:
            return NodeStatus.FAILURE
        self._remaining = self.world.travel_ticks
        return NodeStatus.RUNNING

    def on_running(self) -> NodeStatus:
        self._remaining -= 1
        if self._remaining > 0:
            return NodeStatus.RUNNING
        self.world.log.append(self._target)
        return NodeStatus.SUCCESS

    def on_halted(self) -> None:
        self.world.log.append(f"halted:{self._target}")


class WaitSeconds(StatefulActionNode):
    """RUNNING for ``seconds`` of tree time (the seed blocked its executor for 30 s here)."""

    def __init__(self, name: str, config: NodeConfig, world: SeedWorld) -> None:
        super().__init__(name, config)
        self.world = world
        self._until = 0.0

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("seconds", int, description="wait time in s", required=True),)

    def on_start(self) -> NodeStatus:
        self._until = self.now() + int(self.get_input("seconds"))
        self.world.log.append("wait")
        return NodeStatus.RUNNING

    def on_running(self) -> NodeStatus:
        return NodeStatus.SUCCESS if self.now() >= self._until else NodeStatus.RUNNING


def register_seed_fakes(factory: BehaviorTreeFactory, world: SeedWorld) -> None:
    """Register the six seed node types, all sharing ``world``."""
    for node_id, node_type in (("IsBatteryLow", IsBatteryLow), ("CheckBattery", CheckBattery),
                               ("DecrementBattery", DecrementBattery), ("RechargeBattery", RechargeBattery),
                               ("GoToPose", GoToPose), ("WaitSeconds", WaitSeconds)):
        factory.register(node_id, node_type, world=world)
