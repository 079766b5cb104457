"""Scripted behaviour-tree leaves for unit tests of the BT engine, and fake Nav2 action leaves.

``Scripted``: a leaf that returns a scripted status per tick (the last one repeats), counting
ticks and halts in a shared ``Script`` (the py_trees ``StatusQueue`` idea).
``register_nav2_fakes``: ComputePathToPose, FollowPath, Spin, ... as asynchronous leaves with the
Jazzy ports; each run takes ``ticks_to_finish`` ticks and ends with the next scripted error code
for its node id (0 = success), so recovery paths of Nav2's trees can be driven deterministically.
"""

from __future__ import annotations

from collections import Counter, defaultdict, deque
from dataclasses import dataclass, field
from typing import ClassVar

from nav_stack.core.bt import (
    BehaviorTreeFactory,
    NodeConfig,
    NodeStatus,
    PortDirection,
    PortList,
    StatefulActionNode,
    SyncActionNode,
    TreeNode,
    input_port,
    output_port,
)

S, F, R, K = NodeStatus.SUCCESS, NodeStatus.FAILURE, NodeStatus.RUNNING, NodeStatus.SKIPPED


@dataclass
class Script:
    """Per-name status scripts plus what happened: ticks and halts per name, ordered events."""

    statuses: dict[str, list[NodeStatus]] = field(default_factory=dict)
    ticks: Counter[str] = field(default_factory=Counter)
    halts: Counter[str] = field(default_factory=Counter)
    events: list[str] = field(default_factory=list)


class Scripted(TreeNode):
    """Returns ``script.statuses[name][k]`` on its k-th tick (the last entry repeats)."""

    def __init__(self, name: str, config: NodeConfig, script: Script) -> None:
        super().__init__(name, config)
        self.script = script

    def tick(self) -> NodeStatus:
        sequence = self.script.statuses.get(self.name, [NodeStatus.SUCCESS])
        index = min(self.script.ticks[self.name], len(sequence) - 1)
        self.script.ticks[self.name] += 1
        self.script.events.append(f"tick:{self.name}")
        return sequence[index]

    def halt(self) -> None:
        if self.status is NodeStatus.RUNNING:
            self.script.halts[self.name] += 1
            self.script.events.append(f"halt:{self.name}")
        self.reset_status()


@dataclass
class FakeNav2:
    """Scripted outcomes (error codes, 0 = success) per node id and a log of finished runs.

    Each run lasts ``durations[node_id]`` ticks (default ``ticks_to_finish``) after the starting tick.
    """

    outcomes: dict[str, deque[int]] = field(default_factory=lambda: defaultdict(deque))
    log: list[str] = field(default_factory=list)
    inputs: list[tuple[str, dict[str, object]]] = field(default_factory=list)
    ticks_to_finish: int = 2
    durations: dict[str, int] = field(default_factory=dict)

    def script(self, node_id: str, *codes: int) -> None:
        """Queue outcomes for the next runs of ``node_id`` (then success)."""
        self.outcomes[node_id].extend(codes)


class FakeNav2Action(StatefulActionNode):
    """Base of the fake Nav2 action leaves; subclasses only declare ports."""

    def __init__(self, name: str, config: NodeConfig, fake: FakeNav2) -> None:
        super().__init__(name, config)
        self.fake = fake
        self._remaining = 0

    def on_start(self) -> NodeStatus:
        values = {port: self.get_input_or(port, None) for port, info in self.config.manifest.items()
                  if info.direction is PortDirection.INPUT}
        self.fake.inputs.append((self.name, values))
        self._remaining = self.fake.durations.get(self.registration_id, self.fake.ticks_to_finish)
        return NodeStatus.RUNNING

    def on_running(self) -> NodeStatus:
        self._remaining -= 1
        if self._remaining > 0:
            return NodeStatus.RUNNING
        queue = self.fake.outcomes[self.registration_id]
        code = queue.popleft() if queue else 0
        self.fake.log.append(self.name if code == 0 else f"{self.name}!{code}")
        if "error_code_id" in self.config.manifest:
            self.set_output("error_code_id", code)
        path_port = self.config.manifest.get("path")
        if code == 0 and path_port is not None and path_port.direction is PortDirection.OUTPUT:
            self.set_output("path", f"path#{len(self.fake.log)}")
        return NodeStatus.SUCCESS if code == 0 else NodeStatus.FAILURE

    def on_halted(self) -> None:
        self.fake.log.append(f"halted:{self.name}")


def _error_ports() -> PortList:
    return (output_port("error_code_id", int), output_port("error_msg", str))


class FakeComputePathToPose(FakeNav2Action):
    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("goal", object), input_port("start", object), input_port("planner_id", str, ""),
                output_port("path", object), *_error_ports())


class FakeComputePathThroughPoses(FakeNav2Action):
    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("goals", object), input_port("start", object), input_port("planner_id", str, ""),
                output_port("path", object), *_error_ports())


class FakeFollowPath(FakeNav2Action):
    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("path", object), input_port("controller_id", str, ""),
                input_port("goal_checker_id", str, ""), input_port("progress_checker_id", str, ""),
                *_error_ports())


class FakeSpin(FakeNav2Action):
    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("spin_dist", float, 1.57), input_port("time_allowance", float, 10.0),
                *_error_ports())


class FakeBackUp(FakeNav2Action):
    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("backup_dist", float, 0.15), input_port("backup_speed", float, 0.025),
                input_port("time_allowance", float, 10.0), *_error_ports())


class FakeWait(FakeNav2Action):
    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("wait_duration", float, 1.0),)


class FakeClearEntireCostmap(FakeNav2Action):
    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("service_name", str, required=True), input_port("server_timeout", float, 1.0))


class FakeRemovePassedGoals(SyncActionNode):
    """Passes the goals through unchanged (no robot pose in unit tests)."""

    ports: ClassVar[PortList] = (input_port("input_goals", object), output_port("output_goals", object),
                                 input_port("radius", float, 0.5))

    def __init__(self, name: str, config: NodeConfig, fake: FakeNav2) -> None:
        super().__init__(name, config)

    @classmethod
    def provided_ports(cls) -> PortList:
        return cls.ports

    def tick(self) -> NodeStatus:
        self.set_output("output_goals", self.get_input_or("input_goals", []))
        return NodeStatus.SUCCESS


NAV2_FAKES: dict[str, type[TreeNode]] = {
    "ComputePathToPose": FakeComputePathToPose,
    "ComputePathThroughPoses": FakeComputePathThroughPoses,
    "FollowPath": FakeFollowPath,
    "Spin": FakeSpin,
    "BackUp": FakeBackUp,
    "Wait": FakeWait,
    "ClearEntireCostmap": FakeClearEntireCostmap,
    "RemovePassedGoals": FakeRemovePassedGoals,
}


def register_nav2_fakes(factory: BehaviorTreeFactory, fake: FakeNav2) -> None:
    """Register every fake Nav2 leaf, all sharing ``fake``."""
    for node_id, node_type in NAV2_FAKES.items():
        factory.register(node_id, node_type, fake=fake)


def make_factory(script: Script | None = None) -> BehaviorTreeFactory:
    """A factory with the built-ins, Nav2 nodes and ``Scripted`` registered."""
    factory = BehaviorTreeFactory()
    factory.register("Scripted", Scripted, script=script or Script())
    return factory
