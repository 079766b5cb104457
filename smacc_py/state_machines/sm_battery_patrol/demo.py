"""``sm-battery-patrol``: the whole battery patrol headless: simulator + Nav2-style stack + SmBatteryPatrol.

Starts ``nav-bringup --rtf N`` (waits for its "Nav2 is ready" line), runs SmBatteryPatrol in this
process on sim time, prints every transition (sim time, source → target, tag, event), and stops once
``--cycles`` patrol rounds (location1..4) are complete. Exit status: 0 when they are; 2 on the
wall-clock timeout, 3 when the stack died or could not start, 130 on Ctrl-C.

Examples::

    sm-battery-patrol --rtf 5 --cycles 2
    sm-battery-patrol --robot tb4
    sm-battery-patrol --low-threshold 0.95 --charged-threshold 0.99   # recharge about once per round
"""

from __future__ import annotations

import argparse
import os
import sys
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")

from smacc_py.core import SmaccObserver, SmaccStateMachineBase, TransitionRecord
from smacc_py.state_machines.sm_nav2_test_1.demo import (
    READY_PATTERN,
    add_console_arguments,
    bringup_command,
    console_arguments,
    parse_rtf,
)

DEFAULT_PARAMS = Path(__file__).resolve().parents[3] / "config" / "sm_battery_patrol.yaml"
#: sim2d's battery drained as in the seed (2 % per metre): a real waffle's would last two hours.
SIM_PARAMS = Path(__file__).resolve().parents[3] / "config" / "sim2d_battery_patrol.yaml"
EXIT_SUCCESS, EXIT_TIMEOUT, EXIT_STACK, EXIT_INTERRUPTED = 0, 2, 3, 130
CYCLES_KEY, VISITS_KEY, RECHARGES_KEY = "patrol_cycles", "visits", "recharges"


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="sm-battery-patrol", description=__doc__.splitlines()[0])
    parser.add_argument("--rtf", type=parse_rtf, default="max",
                        help="upper bound on the real-time factor (default max; the simulator runs in "
                             "lockstep with the stack)")
    parser.add_argument("--cycles", type=int, default=2, help="patrol rounds (location1..4) to complete")
    parser.add_argument("--timeout", type=float, default=900.0, help="wall-clock limit (s)")
    parser.add_argument("--robot", help="the simulated robot, as nav-bringup's --robot (waffle, burger, tb4; "
                                        "default: nav-bringup's, waffle)")
    default_params = DEFAULT_PARAMS if DEFAULT_PARAMS.exists() else None
    parser.add_argument("--params-file", type=Path, default=default_params,
                        help="ros__parameters YAML for node SmBatteryPatrol")
    parser.add_argument("--low-threshold", type=float, help="charge (0..1) at which to recharge")
    parser.add_argument("--charged-threshold", type=float, help="charge (0..1) at which to resume")
    parser.add_argument("--ready-timeout", type=float, default=180.0,
                        help="wall s to wait for 'Nav2 is ready'")
    parser.add_argument("--sim-params", type=Path, default=SIM_PARAMS if SIM_PARAMS.exists() else None,
                        help="nav-bringup --sim-params: sim2d parameters over config/sim2d.yaml "
                             "(default: the seed's fast-draining battery)")
    parser.add_argument("--bringup", help="command that starts the stack instead of nav-bringup")
    parser.add_argument("--bringup-arg", action="append", default=[],
                        help="extra argument for the stack command (repeatable)")
    add_console_arguments(parser)
    options = parser.parse_args(argv)
    if options.cycles < 1:
        parser.error(f"--cycles must be >= 1, got {options.cycles}")
    return options


class PatrolObserver(SmaccObserver):
    """Prints each transition; sets ``finished`` when ``cycles`` rounds are complete."""

    def __init__(self, say: Callable[[str], None], cycles: int) -> None:
        from smacc_py.ros.transition_printer import format_transition

        self.say, self.format, self.cycles = say, format_transition, cycles
        self.finished = threading.Event()

    def on_transition(self, sm: SmaccStateMachineBase, record: TransitionRecord) -> None:
        self.say(f"[patrol] {self.format(record)}" + (" (history)" if record.history else ""))
        if sm.get_global_sm_data(CYCLES_KEY, 0) >= self.cycles:
            self.finished.set()


def run_patrol(options: argparse.Namespace, launcher: object, say: Callable[[str], None],
               interrupted: threading.Event) -> int:
    """Run the machine until the cycles are done, a timeout, Ctrl-C or the stack's death."""
    import rclpy
    from rclpy.context import Context
    from rclpy.parameter import Parameter

    from smacc_py.ros.runtime import SmaccRuntime
    from smacc_py.state_machines.sm_battery_patrol import SmBatteryPatrol

    args = ["--ros-args", "--params-file", str(options.params_file)] if options.params_file else []
    context = Context()
    rclpy.init(args=args, context=context)
    overrides = [Parameter("use_sim_time", value=True)]
    for name in ("low_threshold", "charged_threshold"):
        if getattr(options, name) is not None:
            overrides.append(Parameter(name, value=float(getattr(options, name))))
    runtime = None
    wall_start = time.monotonic()
    try:
        runtime = SmaccRuntime(SmBatteryPatrol, context=context, parameter_overrides=overrides)
        observer = PatrolObserver(say, options.cycles)
        runtime.sm.add_observer(observer)
        runtime.spin_in_background()
        runtime.start()
        deadline = wall_start + options.timeout
        timed_out = threading.Event()

        def until() -> bool:
            if time.monotonic() > deadline:
                timed_out.set()
            return observer.finished.is_set() or interrupted.is_set() or timed_out.is_set()

        stack_code = launcher.wait(until)  # type: ignore[attr-defined]
        sm = runtime.sm
        sim_s = sm.now() - (runtime.started_at_s or sm.now())
        visits = sm.get_global_sm_data(VISITS_KEY, [])
        say(f"[patrol] visited: {' -> '.join(visits)}")
        say(f"[patrol] rounds {sm.get_global_sm_data(CYCLES_KEY, 0)}, recharges "
            f"{len(sm.get_global_sm_data(RECHARGES_KEY, []))}, sim {sim_s:.1f} s, "
            f"wall {time.monotonic() - wall_start:.1f} s")
        if observer.finished.is_set():
            say("[patrol] result: SUCCESS")
            return EXIT_SUCCESS
        if interrupted.is_set():
            return EXIT_INTERRUPTED
        if timed_out.is_set():
            say(f"[patrol] result: TIMEOUT in {sm.current_state_names()}")
            return EXIT_TIMEOUT
        say(f"[patrol] result: the stack stopped (exit code {stack_code})")
        return EXIT_STACK
    finally:
        if runtime is not None:
            runtime.shutdown()
        if context.ok():
            rclpy.shutdown(context=context)


def main(argv: Sequence[str] | None = None) -> int:
    import signal

    from ros_tools.console import StackConsole
    from ros_tools.launch import Launcher, LaunchError, ProcessSpec, default_log_dir

    options = parse_args(argv)
    out = StackConsole(options.verbose, "patrol")
    log_dir = options.log_dir or default_log_dir()
    launcher = Launcher(output=out.stack, log_dir=log_dir)
    interrupted = threading.Event()

    def on_signal(signum: int, frame: object) -> None:
        interrupted.set()
        launcher.stop()

    previous = {sig: signal.signal(sig, on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    use_sim_params = options.sim_params is not None and not options.bringup
    sim_params = ["--sim-params", str(options.sim_params)] if use_sim_params else []
    command = [*bringup_command(options.rtf, options.bringup, "SmBatteryPatrol", options.robot,
                                console_arguments(options, log_dir)),
               *sim_params, *options.bringup_arg]
    try:
        out.say(f"[patrol] starting the stack: {' '.join(command)}")
        try:
            spec = ProcessSpec("nav", command, ready=READY_PATTERN, ready_timeout=options.ready_timeout)
            launcher.start([spec])
        except LaunchError as error:
            out.show_kept()
            out.say(f"[patrol] FAILED: the stack did not come up: {error} (logs: {log_dir}/)")
            return EXIT_INTERRUPTED if interrupted.is_set() else EXIT_STACK
        out.say(f"[patrol] the stack is ready; its logs: {log_dir}/<process>.log")
        code = run_patrol(options, launcher, out.say, interrupted)
        if code not in (EXIT_SUCCESS, EXIT_INTERRUPTED):
            out.show_problems(log_dir)
        return code
    finally:
        launcher.shutdown()
        for sig, handler in previous.items():
            signal.signal(sig, handler)


if __name__ == "__main__":
    sys.exit(main())
