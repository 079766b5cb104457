"""Battery patrol timing: one patrol cycle of the seed's tree in the simulator with the real stack.

A cycle is location1..4 with the counter battery (root FAILURE at check_battery4), timed by
autonomy_node on the node clock (sim s) and by this process (wall s, node start to exit, including its
startup). Needs ``nav-bringup`` (nav_stack.ros.bringup.nav_bringup); without it that part is skipped with a
message. Always measured: the cost of one tick of the seed tree with the pure seed nodes and a fake
navigator (the node's own overhead per 0.5 s tick).

Run: .venv/bin/python -m bench.bench_patrol [--rtf max] [--repeat 1] [--no-record]
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

from bench.harness import Benchmark
from nav_stack.core.bt import BehaviorTreeFactory
from nav_stack.ros.autonomy.battery import CounterBattery
from nav_stack.ros.autonomy.locations import load_locations
from nav_stack.ros.autonomy.seed_nodes import SeedContext, register_seed_nodes

REPO = Path(__file__).resolve().parents[1]
TREE = REPO / "config" / "trees" / "seed_battery_patrol_v3.xml"


def bench_tick(bench: Benchmark) -> None:
    from navsuite_testing.autonomy.fakes import FakeNavigator

    locations = load_locations(REPO / "config" / "locations.yaml")
    ctx = SeedContext(FakeNavigator(travel_ticks=2), CounterBattery(), locations)
    factory = BehaviorTreeFactory()
    register_seed_nodes(factory, ctx)
    tree = factory.create_tree_from_file(TREE)
    clock = {"t": 0.0}

    def tick() -> None:
        clock["t"] += 0.5
        tree.tick_once(clock["t"])

    stats = bench.time("seed tree tick (pure nodes, fake navigator)", tick, repeat=5000, warmup=50)
    bench.record("seed tree tick (pure nodes, fake navigator)", stats, "us", scale=1e6,
                 note="counter battery")


def bench_cycle(bench: Benchmark, rtf: str, repeat: int) -> None:
    from navsuite_testing.autonomy.system import run_autonomy, set_initial_pose, stack_available, start_stack

    if not stack_available():
        print("bench_patrol: nav_stack.ros.bringup.nav_bringup does not exist: skipping the simulator cycle",
              flush=True)
        return
    launcher = start_stack(rtf)
    sim_s: list[float] = []
    wall_s: list[float] = []
    try:
        set_initial_pose()
        for _ in range(repeat):
            run = run_autonomy({"battery_source": "counter", "max_cycles": 1, "server_timeout": 60.0},
                               timeout=1800.0)
            cycles = run.cycles()
            if run.returncode != 0 or not cycles:
                print(f"bench_patrol: the cycle did not complete:\n{run.output[-3000:]}", flush=True)
                return
            sim_s.append(cycles[0][1])
            wall_s.append(run.wall_s)
            print(f"bench_patrol: cycle {cycles[0][0]} in {cycles[0][1]:.1f} sim s, {run.wall_s:.1f} wall s",
                  flush=True)
    finally:
        launcher.shutdown()  # type: ignore[attr-defined]
    note = f"rtf {rtf}, location1..4, counter battery, n={len(sim_s)}"
    bench.record_value("one patrol cycle (sim time)", statistics.median(sim_s), "s", note=note)
    bench.record_value("one patrol cycle (wall time, incl. node start)", statistics.median(wall_s), "s",
                       note=note)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="bench_patrol")
    parser.add_argument("--rtf", default="max",
                        help="sim real-time factor (lockstep; max = as fast as the stack keeps up)")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--no-record", action="store_true")
    options = parser.parse_args(sys.argv[1:] if argv is None else argv)
    bench = Benchmark("patrol")
    bench_tick(bench)
    bench_cycle(bench, options.rtf, options.repeat)
    bench.save()


if __name__ == "__main__":
    main()
