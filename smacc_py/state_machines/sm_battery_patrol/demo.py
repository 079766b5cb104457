"""``sm-battery-patrol``: the whole battery patrol headless: simulator + Nav2-style stack + SmBatteryPatrol.

Starts ``nav-bringup --rtf N`` (waits for its "Nav2 is ready" line), runs SmBatteryPatrol in this
process on sim time, prints every transition (sim time, source → target, tag, event), and stops once
``--cycles`` patrol rounds (location1..4) are complete. Exit status: 0 when they are; 2 on the
wall-clock timeout, 3 when the stack died or could not start, 130 on Ctrl-C.

Examples::

    sm-battery-patrol --rtf 5 --cycles 2
    sm-battery-patrol --robot tb4
    sm-battery-patrol --low-threshold 0.95 --charged-threshold 0.99   # recharge about once per round
    sm-battery-patrol --recharge dock   # recharge on turtlebot3_world's dock (Nav2's docking_server)
"""

from __future__ import annotations

import argparse
import sys
import threading
import time
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from typing import TYPE_CHECKING

from navsuite_data import config_path, data_dir
from ros_tools.dds import keep_dds_local
from smacc_py.core import SmaccObserver, SmaccStateMachineBase, TransitionRecord
from smacc_py.state_machines import stack_run

if TYPE_CHECKING:
    from smacc_py.ros.runtime import SmaccRuntime

DEFAULT_PARAMS = config_path("sm_battery_patrol.yaml")  # shipped data (navsuite_data)
#: sim2d's battery drained as in the seed (2 % per metre): a real waffle's would last two hours.
SIM_PARAMS = config_path("sim2d_battery_patrol.yaml")
CONFIG = data_dir("config")
#: --recharge dock: the docking_server overlay for turtlebot3_world, over the robot's Nav2 file, and the
#: docking patrols' sim2d overlay (the seed's fast battery, charged on the dock's contacts only).
DOCK_PARAMS = CONFIG / "docks" / "turtlebot3_world.yaml"
DOCK_SIM_PARAMS = CONFIG / "autonomy_docking.yaml"
NAV_PARAMS = {"tb4": CONFIG / "nav2_params_tb4.yaml"}  # else config/nav2_params.yaml (the TurtleBot3s)
CYCLES_KEY, VISITS_KEY, RECHARGES_KEY, DOCKINGS_KEY = "patrol_cycles", "visits", "recharges", "dockings"


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="sm-battery-patrol", description=__doc__.splitlines()[0])
    parser.add_argument("--rtf", type=stack_run.parse_rtf, default="max",
                        help="upper bound on the real-time factor (default max; the simulator runs in "
                             "lockstep with the stack)")
    parser.add_argument("--cycles", type=int, default=2, help="patrol rounds (location1..4) to complete")
    parser.add_argument("--timeout", type=float, default=900.0, help="wall-clock limit (s)")
    parser.add_argument("--robot", help="the simulated robot, as nav-bringup's --robot (waffle, burger, tb4; "
                                        "default: nav-bringup's, waffle)")
    default_params = DEFAULT_PARAMS if DEFAULT_PARAMS.exists() else None
    parser.add_argument("--params-file", type=stack_run.existing_file, default=default_params,
                        help="ros__parameters YAML for node SmBatteryPatrol")
    parser.add_argument("--low-threshold", type=float, help="charge (0..1) at which to recharge")
    parser.add_argument("--charged-threshold", type=float, help="charge (0..1) at which to resume")
    parser.add_argument("--recharge", choices=("station", "dock"),
                        help="recharge mode (default: the parameters file's, station); dock: Nav2's "
                             "DockRobot / UndockRobot on the world's dock, with --dock-params and, unless "
                             "--sim-params is given, config/autonomy_docking.yaml's sim2d battery")
    parser.add_argument("--dock-params", type=stack_run.existing_file, default=DOCK_PARAMS,
                        help="--recharge dock: nav-bringup's docking_server overlay (default "
                             "config/docks/turtlebot3_world.yaml), applied over the robot's Nav2 file")
    parser.add_argument("--ready-timeout", type=float, default=180.0,
                        help="wall s to wait for 'Nav2 is ready'")
    parser.add_argument("--sim-params", type=stack_run.existing_file, default=None,
                        help="nav-bringup --sim-params: sim2d parameters over config/sim2d.yaml "
                             "(default: the seed's fast-draining battery, charged at the station; with "
                             "--recharge dock on the dock)")
    parser.add_argument("--bringup", help="command that starts the stack instead of nav-bringup")
    parser.add_argument("--bringup-arg", action="append", default=[],
                        help="extra argument for the stack command (repeatable)")
    stack_run.add_console_arguments(parser)
    options = parser.parse_args(argv)
    if options.cycles < 1:
        parser.error(f"--cycles must be >= 1, got {options.cycles}")
    if options.sim_params is None:
        default = DOCK_SIM_PARAMS if options.recharge == "dock" else SIM_PARAMS
        options.sim_params = default if default.exists() else None
    # run_against_stack's nav-bringup --params: the robot's file and the docking overlay
    options.nav_params = ([NAV_PARAMS.get(options.robot or "waffle", CONFIG / "nav2_params.yaml"),
                           options.dock_params] if options.recharge == "dock" else None)
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


def patrol_runtime(options: argparse.Namespace) -> AbstractContextManager[SmaccRuntime]:
    """SmBatteryPatrol's runtime with the command's parameters file and thresholds (``machine_runtime``)."""
    from smacc_py.state_machines.sm_battery_patrol import SmBatteryPatrol

    overrides: dict[str, object] = {name: float(getattr(options, name))
                                    for name in ("low_threshold", "charged_threshold")
                                    if getattr(options, name) is not None}
    if options.recharge:
        overrides["recharge"] = options.recharge
    return stack_run.machine_runtime(SmBatteryPatrol, options.params_file, overrides)


def run_patrol(options: argparse.Namespace, session: stack_run.StackSession, runtime: SmaccRuntime) -> int:
    """Run the machine (built, not started) until the cycles are done, a timeout, Ctrl-C or the stack's
    death."""
    say = session.out.say
    wall_start = time.monotonic()
    observer = PatrolObserver(say, options.cycles)
    runtime.sm.add_observer(observer)
    with stack_run.running(runtime):
        end = stack_run.wait_for_end(session, observer.finished.is_set, wall_start + options.timeout)
        sm = runtime.sm
        visits = sm.get_global_sm_data(VISITS_KEY, [])
        say(f"[patrol] visited: {' -> '.join(visits)}")
        if options.recharge == "dock":  # a line of its own: tools parse the next one
            say(f"[patrol] dockings {len(sm.get_global_sm_data(DOCKINGS_KEY, []))}")
        say(f"[patrol] rounds {sm.get_global_sm_data(CYCLES_KEY, 0)}, recharges "
            f"{len(sm.get_global_sm_data(RECHARGES_KEY, []))}, sim {stack_run.mission_sim_s(runtime):.1f} s, "
            f"wall {time.monotonic() - wall_start:.1f} s")
        if end.finished:
            say("[patrol] result: SUCCESS")
            return stack_run.EXIT_SUCCESS
        if end.interrupted:
            return stack_run.EXIT_INTERRUPTED
        if end.timed_out:
            say(f"[patrol] result: TIMEOUT in {sm.current_state_names()}")
            return stack_run.EXIT_TIMEOUT
        say(f"[patrol] result: the stack stopped (exit code {end.stack_code})")
        return stack_run.EXIT_STACK


def main(argv: Sequence[str] | None = None) -> int:
    keep_dds_local()  # before the machine's node: Fast DDS reads the settings once
    from ros_tools.console import StackConsole

    options = parse_args(argv)
    stack_run.use_stamped_cmd_vel(stack_run.stack_stamps(options.bringup, options.bringup_arg))
    use_sim_params = options.sim_params is not None and not options.bringup
    sim_params = ["--sim-params", str(options.sim_params)] if use_sim_params else []
    console = StackConsole(options.verbose, "patrol")
    with patrol_runtime(options) as runtime:  # built first: discovered while the stack comes up
        return stack_run.run_against_stack(options, console, "SmBatteryPatrol",
                                           lambda session: run_patrol(options, session, runtime),
                                           extra_args=[*sim_params, *options.bringup_arg],
                                           ready_note="the stack is ready; its logs: {log_dir}/<process>.log")


if __name__ == "__main__":
    sys.exit(main())
