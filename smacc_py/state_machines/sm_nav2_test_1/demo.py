"""``navsuite-demo``: the whole tutorial headless: simulator + Nav2-style stack + sm_nav2_test_1.

Starts ``nav-bringup --rtf N`` through ros_tools.launch (waits for its "Nav2 is ready" line), then runs
SmNav2Test1 in this process on sim time, prints every transition as it happens (sim time, source →
target, tag, triggering event and, on failures, the Nav2 error), and ends with a summary. On a
terminal a live line shows the state, pose, distance left, ETA, recoveries and real-time factor.
The stack's own output goes to ``artifacts/logs/<process>.log`` (``--verbose`` streams it). Exit status:
0 when the mission reached StFinalState through the SUCCESS path; 1 on the ABORT path, 2 on a wall-clock
timeout, 3 when a process of the stack died (or could not start), 130 on Ctrl-C.

Examples::

    navsuite-demo --rtf 1                       # real time, to watch in navsuite-viewer
    navsuite-demo --robot tb4                   # the same mission with a TurtleBot4
    navsuite-demo --waypoint1 5.0,3.0,1.57      # outside the map: ABORT, and the output says why

The run is recorded to ``<report>.mcap`` (the report's topics plus the robot's sensors, odometry,
TF, velocity commands and local plans, so ``navsuite-bag play`` can show the run again in the viewer
or Foxglove) and, after shutdown, turned into a run report PNG (map, true and AMCL trajectories,
plans, goals, collisions, state-machine timeline, localization error) whose path is printed:
artifacts/demo_report.png by default, ``--report PATH`` elsewhere, ``--no-report`` to skip both.
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from navsuite_data import config_path
from ros_tools.dds import keep_dds_local
from ros_tools.launch import ProcessSpec
from smacc_py.state_machines.stack_run import (
    StackSession,
    add_console_arguments,
    add_nav_params_argument,
    existing_file,
    parse_rtf,
    run_against_stack,
    stack_stamps,
    use_stamped_cmd_vel,
)

DEFAULT_PARAMS = config_path("sm_nav2_test_1.yaml")  # shipped data (navsuite_data)


def parse_pose(text: str) -> list[float]:
    """``x,y,yaw`` → [x, y, yaw]; argparse shows the ValueError message."""
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected x,y,yaw numbers, got {text!r}") from None
    if len(values) != 3:
        raise argparse.ArgumentTypeError(f"expected 3 numbers x,y,yaw, got {len(values)} in {text!r}")
    return values


REPORT_DEFAULT = Path("artifacts") / "demo_report.png"
#: What the run report draws: map, true and estimated trajectories, plans, goals, collisions, transitions.
REPORT_TOPICS = ("/map", "/ground_truth", "/amcl_pose", "/plan", "/goal_pose", "/sim2d/collisions",
                 "/SmNav2Test1/smacc/transition_log")
#: Recorded besides, so a replay shows what the robot sensed and did (about 100 small messages per sim
#: second, some 1-2 MB per run compressed). Left out on purpose: /particle_cloud (AMCL builds its
#: 2000-pose cloud only while someone subscribes, so recording it would load the run it records),
#: /clock (``play --clock`` regenerates it) and the costmaps (full grids, megabytes each second).
REPLAY_TOPICS = ("/scan", "/odom", "/tf", "/tf_static", "/cmd_vel", "/local_plan")
#: Nav2 Jazzy's velocity chain, when the parameter files configure it (controller → /cmd_vel_nav →
#: velocity_smoother → /cmd_vel_smoothed → collision_monitor → /cmd_vel): each stage's output.
CHAIN_TOPICS = ("/cmd_vel_nav", "/cmd_vel_smoothed")
#: sim2d's ground-truth gap to the nearest obstacle (m), for the scenario farm's ``min_clearance``
#: (sim2d computes it only for a listener: about 10 ms of CPU per sim second)
CLEARANCE_TOPICS = ("/sim2d/clearance",)
RECORDED_TOPICS = REPORT_TOPICS + REPLAY_TOPICS + CHAIN_TOPICS + CLEARANCE_TOPICS


def recorder_spec(report: Path) -> ProcessSpec:
    """A navsuite-bag recorder of RECORDED_TOPICS, writing ``<report>.mcap`` (stopped by SIGINT).

    A regex rather than a topic list: a listed topic must get a publisher within a timeout, and
    /sim2d/collisions or /plan may legitimately never be published before the run ends.
    """
    pattern = "^(" + "|".join(re.escape(topic) for topic in RECORDED_TOPICS) + ")$"
    return ProcessSpec("record", [sys.executable, "-m", "navsuite_tools.bag.main", "record", "-e", pattern,
                                  "--use-sim-time", "-o", str(report.with_suffix(".mcap"))],
                       required=False)


def write_run_report(report: Path, say: Callable[[str], None]) -> None:
    """Turn the run's recording into the report PNG and print where it is."""
    from navsuite_tools.report.render import write_report

    try:
        path = write_report(report.with_suffix(".mcap"), report)
    except Exception as error:  # a report must never turn a finished mission into a failure
        say(f"[demo] no run report: {error}")
        return
    say(f"[demo] run report: {path}")


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="navsuite-demo", description=__doc__.splitlines()[0])
    parser.add_argument("--rtf", type=parse_rtf, default="max",
                        help="upper bound on the real-time factor (default max: as fast as the stack "
                             "keeps up; the simulator runs in lockstep with it); 1 to watch in the viewer")
    parser.add_argument("--timeout", type=float, default=600.0, help="wall-clock limit (s) for the mission")
    parser.add_argument("--robot", help="the simulated robot, as nav-bringup's --robot (waffle, burger, tb4; "
                                        "default: nav-bringup's, waffle)")
    parser.add_argument("--waypoint1", type=parse_pose, help="x,y,yaw of the first goal (map frame)")
    parser.add_argument("--waypoint2", type=parse_pose, help="x,y,yaw of the second goal (map frame)")
    parser.add_argument(
        "--params-file",
        type=existing_file,
        default=DEFAULT_PARAMS if DEFAULT_PARAMS.exists() else None,
        help="ros__parameters YAML for node SmNav2Test1",
    )
    parser.add_argument(
        "--ready-timeout", type=float, default=180.0, help="wall s to wait for 'Nav2 is ready'"
    )
    parser.add_argument("--bringup", help="command that starts the stack instead of nav-bringup")
    add_nav_params_argument(parser)
    add_console_arguments(parser)
    parser.add_argument("--report", type=Path, default=REPORT_DEFAULT,
                        help=f"run report PNG, from a recording next to it (default {REPORT_DEFAULT})")
    parser.add_argument("--no-report", dest="report", action="store_const", const=None,
                        help="neither record the run nor write a report")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    keep_dds_local()  # before the machine's node: Fast DDS reads the settings once
    options = parse_args(argv)
    use_stamped_cmd_vel(stack_stamps(options.bringup))  # the machine's spins publish what sim2d takes
    from ros_tools.console import StackConsole
    from ros_tools.status_line import StatusLine

    out = StackConsole(options.verbose, "demo", StatusLine(sys.stdout, period=0.5))

    from smacc_py.state_machines.sm_nav2_test_1.mission import mission_runtime, run_mission

    try:
        # The machine is built first: DDS discovers its node while the stack comes up, not after.
        with mission_runtime(options) as runtime:

            def mission(session: StackSession) -> int:
                if options.report is not None:
                    options.report.parent.mkdir(parents=True, exist_ok=True)
                    session.launcher.start([recorder_spec(options.report)])
                return run_mission(options, session, runtime)

            return run_against_stack(options, out, "SmNav2Test1", mission)
    finally:  # after the stack's shutdown, which closed the recording
        if options.report is not None and options.report.with_suffix(".mcap").exists():
            write_run_report(options.report, out.say)


if __name__ == "__main__":
    sys.exit(main())
