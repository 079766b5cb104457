"""Run a state machine against nav-bringup: what every mission command shares.

navsuite-demo (sm_nav2_test_1), sm-battery-patrol and sm_dance_bot's demo each start the Nav2-style
stack as a child process, wait for its "Nav2 is ready" line, run their machine in this process on sim
time as the stack's lockstep participant, and stop on the mission's end, a wall-clock timeout, Ctrl-C
or the stack's death. They live here once so the three commands start, fail, log and exit alike: the
exit codes below, the stack's logs in ``<log dir>/<process>.log``, the same console lines (tests and
benchmarks parse them).

Process side: the console options (``add_console_arguments``), the stack's command line
(``bringup_command``) and ``run_against_stack`` (launcher, signals, startup failure, the stack's
problems on a failed run, shutdown). In-process side: ``machine_runtime`` (the machine on its own rclpy
context, built before the stack starts so that DDS discovery overlaps the stack's bringup), ``running``
and ``wait_for_end``. rclpy is imported only once a machine runs, so ``--help`` stays quick.
"""

from __future__ import annotations

import argparse
import shlex
import shutil
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from navsuite_data import resolve, searched
from ros_tools.launch import Launcher, ProcessSpec

if TYPE_CHECKING:
    from ros_tools.console import StackConsole
    from smacc_py.core import SmaccStateMachineBase
    from smacc_py.ros.runtime import SmaccRuntime

READY_PATTERN = r"Nav2 is ready"
EXIT_SUCCESS, EXIT_ABORT, EXIT_TIMEOUT, EXIT_STACK, EXIT_INTERRUPTED = 0, 1, 2, 3, 130
#: The line said once the stack is up, formatted with ``elapsed`` (wall s) and ``log_dir``.
READY_NOTE = "the stack is ready ({elapsed:.1f} s); its logs: {log_dir}/<process>.log"


def parse_rtf(text: str) -> str:
    """``--rtf``: a positive number or ``max`` (as fast as the stack keeps up, in lockstep)."""
    if text.lower() in ("max", "inf"):
        return "max"
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive number or 'max', got {text!r}") from None
    if not value > 0.0:
        raise argparse.ArgumentTypeError(f"must be a positive number or 'max', got {text!r}")
    return f"{value:g}"


def existing_file(text: str) -> Path:
    """argparse type of the commands' file options: the user's path (absolute, or relative to the working
    directory), else the shipped file of that name (``config/...``: navsuite_data), so the documented
    commands also run outside a checkout; the error names the file and where it was looked for."""
    path = resolve(text)
    if not path.is_file():
        raise argparse.ArgumentTypeError(f"no such file: {text} ({searched(text)})")
    return path


def add_console_arguments(parser: argparse.ArgumentParser) -> None:
    """``--verbose``, ``--quiet`` and ``--log-dir``, shared by the mission commands."""
    parser.add_argument("--verbose", action="store_true",
                        help="stream every line of every process (default: the mission's own lines; the "
                             "stack's errors live, its last warnings if the run fails)")
    parser.add_argument("--quiet", action="store_true", help="the default console (kept for scripts)")
    parser.add_argument("--log-dir", type=Path, default=None,
                        help="each process's full log, as <process>.log (default: $NAVSUITE_LOG_DIR, "
                             "else artifacts/logs)")


def add_nav_params_argument(parser: argparse.ArgumentParser) -> None:
    """``--nav-params FILE`` (repeatable): the navigation's parameter files, passed to nav-bringup as
    ``--params`` (e.g. Nav2 Jazzy's own nav2_params.yaml; default: the robot's shipped file)."""
    parser.add_argument("--nav-params", action="append", default=None, metavar="FILE", type=existing_file,
                        help="Nav2 parameter file for nav-bringup's --params (repeatable; later files "
                             "override earlier ones), e.g. Nav2's own nav2_params.yaml")


def console_arguments(options: argparse.Namespace, log_dir: Path) -> list[str]:
    """What nav-bringup is told about the console: the same verbosity, the same log directory."""
    return [*(["--verbose"] if options.verbose else []), "--log-dir", str(log_dir)]


def bringup_command(rtf: str, custom: str | None = None, machine: str | None = None,
                    robot: str | None = None, console: Sequence[str] = (),
                    params: Sequence[str | Path] = ()) -> list[str]:
    """``nav-bringup --rtf N`` (the console script, or its module when not installed as a script), or
    ``custom`` (a command line; ``--rtf N`` is appended) to run another stack that prints the same line.

    ``machine`` names the state machine that will join lockstep: the simulator waits for it before
    its first step, so the mission starts at the same sim time on every run. ``robot`` is passed on
    as ``--robot`` (nav-bringup checks the name and picks that robot's simulation and parameters).
    ``console`` (nav-bringup's ``--verbose``, ``--log-dir``) and ``params`` (its ``--params`` files,
    made absolute) are for nav-bringup only.
    """
    robot_args = ["--robot", robot] if robot else []
    if custom:
        return [*shlex.split(custom), *robot_args, "--rtf", rtf]
    exe = shutil.which("nav-bringup")
    base = [exe] if exe else [sys.executable, "-m", "nav_stack.ros.bringup.nav_bringup"]
    param_args = [arg for file in params for arg in ("--params", str(Path(file).resolve()))]
    return [*base, *robot_args, *param_args, "--rtf", rtf, *(["--participant", machine] if machine else []),
            *console]


@dataclass(frozen=True)
class StackSession:
    """A running stack, as the mission sees it: where to print, the launcher, where the logs go, the
    Ctrl-C flag and the command's start (``time.monotonic()``)."""

    out: StackConsole
    launcher: Launcher
    log_dir: Path
    interrupted: threading.Event
    wall_start: float


def run_against_stack(options: argparse.Namespace, out: StackConsole, machine: str,
                      mission: Callable[[StackSession], int], *, extra_args: Sequence[str] = (),
                      companions: Sequence[ProcessSpec] = (), ready_note: str = READY_NOTE) -> int:
    """Start the stack for ``machine``, run ``mission`` once it is up, stop everything; the exit code.

    ``options`` holds ``rtf``, ``bringup``, ``ready_timeout``, the console options and, where the
    command has it, ``robot``. ``extra_args`` follow the stack's command line. ``companions`` start after
    the stack, each once ready, and count as part of it coming up. SIGINT and SIGTERM set
    ``interrupted`` and end the launcher's wait; the previous handlers are restored on return.
    """
    from ros_tools.launch import LaunchError, default_log_dir

    log_dir = options.log_dir or default_log_dir()
    launcher = Launcher(output=out.stack, log_dir=log_dir)
    session = StackSession(out, launcher, log_dir, threading.Event(), time.monotonic())

    def on_signal(signum: int, frame: object) -> None:
        session.interrupted.set()
        launcher.stop()

    previous = {sig: signal.signal(sig, on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    nav_params = getattr(options, "nav_params", None) or ()
    command = [*bringup_command(options.rtf, options.bringup, machine, getattr(options, "robot", None),
                                console_arguments(options, log_dir), nav_params), *extra_args]
    prefix = f"[{out.name}]"
    try:
        out.say(f"{prefix} starting the stack: {' '.join(command)}")
        try:
            nav = ProcessSpec("nav", command, ready=READY_PATTERN, ready_timeout=options.ready_timeout)
            for spec in (nav, *companions):
                launcher.start([spec])
        except LaunchError as error:
            out.show_kept()
            out.say(f"{prefix} FAILED: the stack did not come up: {error} (logs: {log_dir}/)")
            return EXIT_INTERRUPTED if session.interrupted.is_set() else EXIT_STACK
        elapsed = time.monotonic() - session.wall_start
        out.say(f"{prefix} {ready_note.format(elapsed=elapsed, log_dir=log_dir)}")
        code = mission(session)
        if code not in (EXIT_SUCCESS, EXIT_INTERRUPTED):
            # The warning that explains a failure (bt_navigator's "goal failed") is written before the
            # result reaches the machine, but it may still be in the pipes (two hops: the stack's
            # launcher, then ours): on a busy machine it came after this list was printed (CI run DJ).
            # Stopping the stack first reads every line it wrote.
            launcher.shutdown()
            out.show_problems(log_dir)
        return code
    finally:
        launcher.shutdown()  # SIGINT first: a recorder closes its file
        for sig, handler in previous.items():
            signal.signal(sig, handler)


#: The machine's ``enable_stamped_cmd_vel`` (ClNav2Z's cmd_vel type) when machine_runtime is not told:
#: nav-bringup in lockstep stamps velocity commands on both sides, and sim2d ignores the other type.
#: None leaves it unset: ClNav2Z then follows the type the robot's subscription takes.
_stamped_cmd_vel: list[bool | None] = [True]


def use_stamped_cmd_vel(stamped: bool | None) -> None:
    """Set the machines' ``enable_stamped_cmd_vel`` for the stack this command starts (``stack_stamps``)."""
    _stamped_cmd_vel[0] = stamped


def stack_stamps(custom: str | None, extra: Sequence[str] = ()) -> bool | None:
    """Whether the stack takes stamped velocity commands: nav-bringup in lockstep does (its default),
    not with ``--no-lockstep`` or ``--unstamped-cmd-vel`` among ``extra`` (its added arguments); of a
    custom stack command (``custom``) that runs nav-bringup the same holds of its own arguments; of any
    other nothing is known: None, the machine follows the robot's type."""
    words = [*shlex.split(custom or ""), *extra]
    bringups = ("nav-bringup", "nav_stack.ros.bringup.nav_bringup")
    if custom and not any(word.endswith(bringups) for word in words):
        return None
    return "--no-lockstep" not in words and "--unstamped-cmd-vel" not in words


@contextmanager
def machine_runtime(machine: type[SmaccStateMachineBase], params_file: Path | None = None,
                    overrides: Mapping[str, Any] | None = None) -> Iterator[SmaccRuntime]:
    """``machine`` on its own rclpy context and sim time, with ``params_file`` and ``overrides`` (name →
    value) as its parameters; not yet spinning nor started, so observers can be added first. Shut down,
    context included, when the block ends. ``enable_stamped_cmd_vel`` follows the stack
    (:func:`use_stamped_cmd_vel`) unless ``overrides`` set it."""
    from rclpy.context import Context
    from rclpy.parameter import Parameter

    from ros_tools.runtime.runner import ros_process
    from smacc_py.ros.runtime import SmaccRuntime

    args = ["--ros-args", "--params-file", str(params_file)] if params_file else []
    stamped = {} if _stamped_cmd_vel[0] is None else {"enable_stamped_cmd_vel": _stamped_cmd_vel[0]}
    values = {**stamped, **(overrides or {})}
    parameters = [Parameter("use_sim_time", value=True),
                  *(Parameter(name, value=value) for name, value in values.items())]
    # A library block inside a demo's process: its own context beside others, and no signal handling
    # of its own (the demo's run_stack_mission owns SIGINT and SIGTERM).
    with ros_process(args, context=Context(), handle_signals=False) as process:
        runtime = None
        try:
            runtime = SmaccRuntime(machine, context=process.context, parameter_overrides=parameters)
            yield runtime
        finally:
            if runtime is not None:
                runtime.shutdown()


@contextmanager
def running(runtime: SmaccRuntime) -> Iterator[SmaccRuntime]:
    """``runtime`` spinning in a background thread and started for the block; shut down when it ends.

    Why not leave the shutdown to ``machine_runtime``: the demos build the runtime before the stack
    (so DDS discovers the machine while the stack comes up) and the stack stops before that block
    ends. Stopping the machine here, at the mission's end, cancels its goals while the stack still
    runs to answer.
    """
    runtime.spin_in_background()
    runtime.start()
    try:
        yield runtime
    finally:
        runtime.shutdown()


def mission_sim_s(runtime: SmaccRuntime) -> float:
    """Sim seconds since the machine entered its initial state (0 if it never did)."""
    started = runtime.started_at_s
    return runtime.sm.now() - started if started is not None else 0.0


@dataclass(frozen=True)
class MissionEnd:
    """Why ``wait_for_end`` returned, most telling first: the mission finished, Ctrl-C, the wall-clock
    deadline, else the stack stopped (``stack_code``, the launcher's)."""

    finished: bool
    interrupted: bool
    timed_out: bool
    stack_code: int

    def verdict(self, finished: Callable[[], tuple[int, str]], timeout_s: float, where: object,
                what: str) -> tuple[int, str]:
        """(exit code, result line): ``finished()``'s when the mission finished, else the reason it
        did not; ``where`` is the machine's state at a timeout, ``what`` the mission's name."""
        if self.finished:
            return finished()
        if self.interrupted:
            return EXIT_INTERRUPTED, "interrupted"
        if self.timed_out:
            from smacc_py.ros.action_client import pending_goals

            waits = "".join(f"; waiting for the {goal}" for goal in pending_goals())
            return EXIT_TIMEOUT, f"TIMEOUT after {timeout_s:.0f} s wall in {where}{waits}"
        return EXIT_STACK, f"the stack stopped (exit code {self.stack_code}) before the {what} ended"


def wait_for_end(session: StackSession, done: Callable[[], bool], deadline: float,
                 tick: Callable[[], None] | None = None) -> MissionEnd:
    """Supervise the stack until ``done()``, Ctrl-C, ``deadline`` (``time.monotonic()``) or a process's
    death; ``tick`` runs at every poll (0.1 s wall), e.g. to redraw a live line."""
    timed_out = threading.Event()

    def until() -> bool:
        if tick is not None:
            tick()
        if done() or session.interrupted.is_set():
            return True
        if time.monotonic() > deadline:
            timed_out.set()
            return True
        return False

    stack_code = session.launcher.wait(until)
    return MissionEnd(done(), session.interrupted.is_set(), timed_out.is_set(), stack_code)
