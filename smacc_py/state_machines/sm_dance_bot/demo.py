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
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Sequence

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")

from smacc_py.state_machines.sm_nav2_test_1.demo import (
    READY_PATTERN,
    add_console_arguments,
    bringup_command,
    console_arguments,
    parse_rtf,
)
from smacc_py.state_machines.sm_nav2_test_1.mission import (
    EXIT_ABORT,
    EXIT_INTERRUPTED,
    EXIT_STACK,
    EXIT_SUCCESS,
    EXIT_TIMEOUT,
    MissionObserver,
    summary,
)

MACHINE = "SmDanceBot"
INITIAL_LEAF = "StAcquireSensors"
RECOVERY = "MsDanceBotRecoveryMode"


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="sm_dance_bot.demo", description=__doc__.splitlines()[0])
    parser.add_argument("--rtf", type=parse_rtf, default="max",
                        help="upper bound on the real-time factor (default max; lockstep with the stack)")
    parser.add_argument("--timeout", type=float, default=600.0, help="wall-clock limit (s) for the dance")
    parser.add_argument("--heat-start", type=float, default=60.0,
                        help="sim s at which the temperature sensor starts to overheat")
    parser.add_argument("--heat-end", type=float, default=66.0, help="sim s at which it cools down")
    parser.add_argument("--no-overheat", action="store_true", help="no overheating: no recovery mode")
    parser.add_argument("--ready-timeout", type=float, default=180.0,
                        help="wall s to wait for 'Nav2 is ready'")
    parser.add_argument("--bringup", help="command that starts the stack instead of nav-bringup")
    add_console_arguments(parser)
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


def run_dance(options: argparse.Namespace, launcher: object, say: Callable[[str], None],
              interrupted: threading.Event, wall_start: float) -> int:
    """Run SmDanceBot until StFinalState, a timeout, Ctrl-C or the stack's death; the exit code."""
    import rclpy
    from rclpy.context import Context
    from rclpy.parameter import Parameter

    from smacc_py.ros.runtime import SmaccRuntime
    from smacc_py.state_machines.sm_dance_bot import SmDanceBot

    context = Context()
    rclpy.init(args=[], context=context)
    runtime = None
    try:
        runtime = SmaccRuntime(SmDanceBot, context=context,
                               parameter_overrides=[Parameter("use_sim_time", value=True)])
        observer = MissionObserver(say)
        runtime.sm.add_observer(observer)
        runtime.spin_in_background()
        runtime.start()
        mission_start = time.monotonic()
        deadline = mission_start + options.timeout
        timed_out = threading.Event()

        def until() -> bool:
            if time.monotonic() > deadline:
                timed_out.set()
            return observer.finished.is_set() or interrupted.is_set() or timed_out.is_set()

        stack_code = launcher.wait(until)  # type: ignore[attr-defined]
        sm = runtime.sm
        started = runtime.started_at_s
        sim_s = sm.now() - started if started is not None else 0.0
        records = list(observer.records)
        if observer.finished.is_set():
            ok = records[-1].tag.family() == "SUCCESS"
            code, result = (EXIT_SUCCESS, "SUCCESS: the dance is over") if ok else (EXIT_ABORT, "ABORT")
        elif interrupted.is_set():
            code, result = EXIT_INTERRUPTED, "interrupted"
        elif timed_out.is_set():
            where = sm.current_state_names()
            code, result = EXIT_TIMEOUT, f"TIMEOUT after {options.timeout:.0f} s wall in {where}"
        else:
            code, result = EXIT_STACK, f"the stack stopped (exit code {stack_code}) before the dance ended"
        for line in dance_report(sm, observer):
            say(line)
        for line in summary(records, INITIAL_LEAF, sim_s, time.monotonic() - wall_start, result,
                            time.monotonic() - mission_start):
            say(line)
        return code
    finally:
        if runtime is not None:
            runtime.shutdown()
        if context.ok():
            rclpy.shutdown(context=context)


def main(argv: Sequence[str] | None = None) -> int:
    from ros_tools.console import StackConsole
    from ros_tools.launch import Launcher, LaunchError, ProcessSpec, default_log_dir
    from smacc_py.state_machines.sm_dance_bot.support_nodes import READY_LINE

    options = parse_args(argv)
    out = StackConsole(options.verbose, "demo")
    log_dir = options.log_dir or default_log_dir()
    launcher = Launcher(output=out.stack, log_dir=log_dir)
    interrupted = threading.Event()

    def on_signal(signum: int, frame: object) -> None:
        interrupted.set()
        launcher.stop()

    previous = {sig: signal.signal(sig, on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    wall_start = time.monotonic()
    command = bringup_command(options.rtf, options.bringup, MACHINE, None,
                              console_arguments(options, log_dir))
    try:
        out.say(f"[demo] starting the stack: {' '.join(command)}")
        try:
            launcher.start([ProcessSpec("nav", command, ready=READY_PATTERN,
                                        ready_timeout=options.ready_timeout)])
            launcher.start([ProcessSpec("dance_support", support_command(options), ready=READY_LINE)])
        except LaunchError as error:
            out.show_kept()
            out.say(f"[demo] FAILED: the stack did not come up: {error} (logs: {log_dir}/)")
            return EXIT_INTERRUPTED if interrupted.is_set() else EXIT_STACK
        out.say(f"[demo] the stack is ready ({time.monotonic() - wall_start:.1f} s); its logs: {log_dir}/")
        code = run_dance(options, launcher, out.say, interrupted, wall_start)
        if code not in (EXIT_SUCCESS, EXIT_INTERRUPTED):
            out.show_problems(log_dir)
        return code
    finally:
        launcher.shutdown()
        for sig, handler in previous.items():
            signal.signal(sig, handler)


if __name__ == "__main__":
    sys.exit(main())
