"""Behaviour-tree engine speed: loading Nav2's default tree and ticking it in steady state.

Why: bt_navigator ticks its tree every bt_loop_duration (10 ms in Nav2's yaml); the engine's own
cost per tick must stay a small fraction of that. The steady state measured here is the common
one: the path is being followed, so each tick runs both selectors, the RateController and the
RUNNING FollowPath leaf. Leaves are minimal stand-ins (no ROS) defined here.

Run: ``.venv/bin/python -m bench.bench_bt`` (``--no-record`` to skip RESULTS.md).
"""

from __future__ import annotations

from pathlib import Path

from bench.harness import Benchmark, parse_cli
from nav_stack.core.bt import BehaviorTreeFactory, NodeStatus, PortList, StatefulActionNode, input_port

TREES = Path(__file__).resolve().parents[1] / "config" / "trees"
TREE = TREES / "navigate_to_pose_w_replanning_and_recovery.xml"


class Leaf(StatefulActionNode):
    """Accepts any Nav2 port; succeeds at once except FollowPath, which keeps RUNNING."""

    @classmethod
    def provided_ports(cls) -> PortList:
        names = ("goal", "path", "planner_id", "error_code_id", "controller_id", "service_name",
                 "spin_dist", "wait_duration", "backup_dist", "backup_speed")
        return tuple(input_port(name, str) for name in names)

    def on_start(self) -> NodeStatus:
        return NodeStatus.RUNNING if self.registration_id == "FollowPath" else NodeStatus.SUCCESS

    def on_running(self) -> NodeStatus:
        return NodeStatus.RUNNING


def make_factory() -> BehaviorTreeFactory:
    factory = BehaviorTreeFactory()
    for node_id in ("ComputePathToPose", "FollowPath", "ClearEntireCostmap", "Spin", "Wait", "BackUp"):
        factory.register(node_id, Leaf)
    return factory


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("bt")
    factory = make_factory()
    load = bench.time("load default NavigateToPose tree", lambda: factory.create_tree_from_file(TREE),
                      repeat=50, warmup=3)
    bench.record("load default NavigateToPose tree", load, "ms", scale=1e3)

    tree = factory.create_tree_from_file(TREE)
    tree.blackboard.set("goal", (1.0, 2.0, 0.0))
    clock = [0.0]

    def tick() -> None:
        clock[0] += 0.01
        tree.tick_once(clock[0])

    for _ in range(5):
        tick()
    assert tree.status is NodeStatus.RUNNING
    stats = bench.time("tick default tree (following)", tick, repeat=2000, warmup=100)
    bench.record("tick default tree (following)", stats, "us", scale=1e6, note="2 selectors + RateController")
    bench.record_value("tick budget used at 100 Hz", stats.median / 0.01 * 100.0, "%")
    bench.save()


if __name__ == "__main__":
    main()
