"""The whole sm_dance_bot run, headless: simulator + Nav2-style stack + support nodes + SmDanceBot.

Starts ``nav-bringup --rtf N`` with SmDanceBot as a lockstep participant (waits for "Nav2 is ready"),
then the support nodes (LED, temperature, service3, as upstream's launch file does), then runs the
machine in this process on sim time. It prints every transition (sim time, source → target, tag,
event) and ends with the states visited, the loop counts of the superstates, the recovery mode's
entries and exits, the number of transitions, sim and wall time. Exit status: 0 when StFinalState was
reached through the SUCCESS path, 1 on the ABORT path, 2 on the wall-clock timeout, 3 when the stack
died or could not start, 130 on Ctrl-C.

Examples::

    python -m smacc_py.state_machines.sm_dance_bot.demo --rtf max
    python -m smacc_py.state_machines.sm_dance_bot.demo --rtf 1 --no-overheat     # to watch, no recovery
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from typing import TYPE_CHECKING

from ros_tools.dds import keep_dds_local
from smacc_py.state_machines import stack_run
from smacc_py.state_machines.sm_nav2_test_1.mission import MissionObserver, summary

if TYPE_CHECKING:
    from smacc_py.ros.runtime import SmaccRuntime

MACHINE = "SmDanceBot"
INITIAL_LEAF = "StAcquireSensors"
RECOVERY = "MsDanceBotRecoveryMode"


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="sm_dance_bot.demo", description=__doc__.splitlines()[0])
    parser.add_argument("--rtf", type=stack_run.parse_rtf, default="max",
                        help="upper bound on the real-time factor (default max; lockstep with the stack)")
    parser.add_argument("--timeout", type=float, default=600.0, help="wall-clock limit (s) for the dance")
    parser.add_argument("--heat-start", type=float, default=60.0,
                        help="sim s at which the temperature sensor starts to overheat")
    parser.add_argument("--heat-end", type=float, default=66.0, help="sim s at which it cools down")
    parser.add_argument("--no-overheat", action="store_true", help="no overheating: no recovery mode")
    parser.add_argument("--ready-timeout", type=float, default=180.0,
                        help="wall s to wait for 'Nav2 is ready'")
    parser.add_argument("--bringup", help="command that starts the stack instead of nav-bringup")
    stack_run.add_console_arguments(parser)
    return parser.parse_args(argv)


def support_command(options: argparse.Namespace) -> list[str]:
    """The support nodes' command line, with the overheating window."""
    heat = ["--no-overheat"] if options.no_overheat else []
    return [sys.executable, "-m", "smacc_py.state_machines.sm_dance_bot.support_nodes",
            "--heat-start", str(options.heat_start), "--heat-end", str(options.heat_end), *heat]


def dance_report(sm: object, observer: MissionObserver) -> list[str]:
    """Loop counts (from the blackboard) and the recovery mode's entries and exits (from the log)."""
    from smacc_py.state_machines.sm_dance_bot import LOOPING_SUPERSTATES, LOOPS_KEY

    loops = sm.get_global_sm_data(LOOPS_KEY, {})  # type: ignore[attr-defined]
    counts = ", ".join(f"{ss.__name__}={loops.get(ss.__name__, 0)}/{ss.total_iterations}"
                       for ss in LOOPING_SUPERSTATES)
    entered = sum(1 for r in observer.records if r.leaf.__name__ == RECOVERY)
    left = sum(1 for r in observer.records if r.source.__name__ == RECOVERY and r.history)
    return [f"[demo] loops: {counts}", f"[demo] recovery mode: entered {entered}, left {left}"]


def run_dance(options: argparse.Namespace, session: stack_run.StackSession, runtime: SmaccRuntime) -> int:
    """Run SmDanceBot (built, not started) until StFinalState, a timeout, Ctrl-C or the stack's death;
    the exit code."""
    say = session.out.say
    observer = MissionObserver(say)
    runtime.sm.add_observer(observer)
    with stack_run.running(runtime):
        mission_start = time.monotonic()
        end = stack_run.wait_for_end(session, observer.finished.is_set, mission_start + options.timeout)
        sm = runtime.sm
        records = list(observer.records)

        def finished() -> tuple[int, str]:
            if records[-1].tag.family() == "SUCCESS":
                return stack_run.EXIT_SUCCESS, "SUCCESS: the dance is over"
            return stack_run.EXIT_ABORT, "ABORT"

        code, result = end.verdict(finished, options.timeout, sm.current_state_names(), "dance")
        now, sim_s = time.monotonic(), stack_run.mission_sim_s(runtime)
        lines = summary(records, INITIAL_LEAF, sim_s, now - session.wall_start, result, now - mission_start)
        for line in [*dance_report(sm, observer), *lines]:
            say(line)
        return code


def main(argv: Sequence[str] | None = None) -> int:
    keep_dds_local()  # before the machine's node: Fast DDS reads the settings once
    from ros_tools.console import StackConsole
    from ros_tools.launch import ProcessSpec
    from smacc_py.state_machines.sm_dance_bot.support_nodes import READY_LINE

    options = parse_args(argv)
    support = ProcessSpec("dance_support", support_command(options), ready=READY_LINE)
    ready_note = "the stack is ready ({elapsed:.1f} s); its logs: {log_dir}/"
    from smacc_py.state_machines.sm_dance_bot import SmDanceBot

    with stack_run.machine_runtime(SmDanceBot) as runtime:  # built first: discovered while the stack comes up
        return stack_run.run_against_stack(options, StackConsole(options.verbose, "demo"), MACHINE,
                                           lambda session: run_dance(options, session, runtime),
                                           companions=[support], ready_note=ready_note)


if __name__ == "__main__":
    sys.exit(main())
