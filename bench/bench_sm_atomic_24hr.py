"""sm_atomic_24hr for 24 hours of sim time, as fast as it keeps up: does its memory and its pace hold?

SMACC2's endurance reference machine (State1 ⇄ State2, each a CbTimerCountdownOnce(500) on a 1 s
ClRosTimer: 7.2 transitions per hour) runs as the user runs it, ``smacc-run sm_atomic_24hr`` with
``use_sim_time:=true`` on the default executor (``--executor single`` to compare), in its own
process. This process is its clock: a ``smacc_py.ros.sim_clock.SimClockLeader`` publishes /clock in
steps of ``--step`` s (default 0.05 s, the runtime's 20 Hz polling period, so every poll and every
tick runs at its sim time) and sends the next step once the machine reported the last one
(lockstep), and it hears the machine's transition log. Recorded:

* the machine process's resident memory (VmRSS) after the first sim hour and at the end; the end must
  be within 5 % of the first hour (imports, DDS and the first transitions are done by then);
* transitions per sim hour, for each hour (stamps of the transition log, machine clock): steady means
  7 or 8 in every hour;
* the wall time of the 24 sim hours and its real-time factor.

    .venv/bin/python -m bench.bench_sm_atomic_24hr [--hours 24] [--step 0.05] [--executor events]
                                                   [--no-record]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

MACHINE, SM_NAME = "sm_atomic_24hr", "SmAtomic24Hr"
HOUR_S = 3600.0
MEMORY_LIMIT_PERCENT = 5.0  # end vs first hour
WALL_LIMIT_S = 4 * 3600.0  # give up when the run takes longer than this (a stuck machine)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--hours", type=int, default=24, help="sim hours to run (>= 2)")
    parser.add_argument("--step", type=float, default=0.05, help="sim s per /clock step")
    parser.add_argument("--executor", choices=("events", "single"), default="events",
                        help="the machine's rclpy executor (smacc-run --executor)")
    parser.add_argument("--no-record", action="store_true", help="print only; do not append to RESULTS.md")
    args = parser.parse_args()
    if args.hours < 2:
        parser.error("--hours must be at least 2 (the first hour is the memory baseline)")

    from bench.harness import Benchmark, Stats, claim_domain_id, code_version_with_fingerprint, version_note

    os.environ["ROS_DOMAIN_ID"] = str(claim_domain_id())
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from smacc2_msgs.msg import SmaccTransitionLogEntry

    from bench.proc_memory import rss_mib
    from smacc_py.ros.sim_clock import SimClockLeader

    started = code_version_with_fingerprint()
    context = Context()
    rclpy.init(context=context)
    node = rclpy.create_node("bench_sm_atomic_24hr", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    stamps: list[float] = []  # machine-clock s of each transition
    qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(SmaccTransitionLogEntry, f"/{SM_NAME}/smacc/transition_log",
                             lambda e: stamps.append(e.timestamp.sec + e.timestamp.nanosec * 1e-9),  # type: ignore[attr-defined]
                             qos)
    clock = SimClockLeader(node, SM_NAME, step_s=args.step)
    machine = subprocess.Popen([sys.executable, "-m", "smacc_py.ros.runner", MACHINE, "--executor",
                                args.executor, "--ros-args", "-p", "use_sim_time:=true", "--log-level",
                                "warn"])
    rss: list[float] = []  # MiB at the end of each sim hour
    wall_started = time.monotonic()
    try:
        for hour in range(1, args.hours + 1):
            end_s = hour * HOUR_S
            if not clock.run(executor, lambda end=end_s: clock.elapsed_s >= end,  # type: ignore[misc]
                             WALL_LIMIT_S - (time.monotonic() - wall_started)):
                raise RuntimeError(f"sim hour {hour} not reached within {WALL_LIMIT_S} s wall")
            memory = rss_mib(machine.pid)
            if memory is None:
                raise RuntimeError(f"the machine process ended during sim hour {hour}")
            rss.append(memory)
            print(f"sim hour {hour:2d}: RSS {memory:7.2f} MiB, {len(stamps)} transitions, "
                  f"wall {time.monotonic() - wall_started:7.1f} s", flush=True)
        wall_s = time.monotonic() - wall_started
        for _ in range(50):  # the last hour's transitions may still be in flight
            executor.spin_once(timeout_sec=0.01)
    finally:
        machine.send_signal(2)
        try:
            machine.wait(timeout=30)
        except subprocess.TimeoutExpired:
            machine.kill()
        clock.destroy()
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)

    start_s = clock.start_ns / 1e9
    per_hour = [sum(1 for s in stamps if h * HOUR_S <= s - start_s < (h + 1) * HOUR_S)
                for h in range(args.hours)]
    growth = 100.0 * (rss[-1] - rss[0]) / rss[0]
    steady = min(per_hour) >= 7 and max(per_hour) <= 8
    rtf = args.hours * HOUR_S / wall_s
    print(f"transitions per sim hour: {per_hour}")
    print(f"RSS first hour {rss[0]:.2f} MiB, end {rss[-1]:.2f} MiB ({growth:+.2f} %); hourly: "
          f"{', '.join(f'{m:.1f}' for m in rss)}")
    print(f"wall {wall_s:.0f} s for {args.hours} sim h (real-time factor {rtf:.0f}); steps {clock.steps}")

    bench = Benchmark("sm_atomic_24hr", record_results=not args.no_record)
    note = (f"{args.hours} sim h in {args.step} s /clock steps, lockstep, {args.executor} executor; "
            f"{version_note(started)}")
    bench.record_value("machine RSS after the first sim hour", rss[0], "MiB", note)
    bench.record_value(f"machine RSS after {args.hours} sim h", rss[-1], "MiB",
                       f"{growth:+.2f} % vs the first hour (limit {MEMORY_LIMIT_PERCENT:.0f} %); {note}")
    bench.record("transitions per sim hour", Stats.of([float(n) for n in per_hour]), "1/h",
                 note=f"each hour: {' '.join(map(str, per_hour))}; nominal 7.2 (500 s states); "
                      f"mean {statistics.mean(per_hour):.2f}; {note}")
    bench.record_value(f"wall time of {args.hours} sim h", wall_s, "s", f"real-time factor {rtf:.0f}; {note}")
    bench.save()
    return 0 if abs(growth) <= MEMORY_LIMIT_PERCENT and steady else 1


if __name__ == "__main__":
    raise SystemExit(main())
