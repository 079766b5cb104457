"""A small process supervisor in place of `ros2 launch` (which pip does not provide).

Why: the seeds start the simulator, the stack and the state machine in separate terminals. A
launcher does it in one command: processes start in dependency order, each waits until the
previous one printed its readiness line, every output line is prefixed with the process name, the
launch stops with a clear error and a non-zero exit as soon as a process dies, and Ctrl-C (SIGINT
or SIGTERM) shuts everything down in reverse order without leaving orphans: children get SIGTERM
from the kernel if the launcher itself is killed (PR_SET_PDEATHSIG).

Respawn (ROS 2 launch's ``Node(respawn=True, respawn_delay=...)``, used by nav2_bringup's
``use_respawn``): a process whose spec sets ``respawn`` is started again with the same command and
environment after ``respawn_delay`` s when it exits, instead of ending the launch; its log file goes
on (appended). One that dies more than ``respawn_max_deaths`` times within ``respawn_window`` s is
given up with one ERROR line (ros_tools.launch_respawn), and the launch then ends as for any required
process that died. A restarted process is not waited for (its readiness line is logged when it comes).

A calm console: with ``log_dir`` every process's full output also goes to ``<log_dir>/<name>.log``,
and ``show`` picks which of its lines reach the console (``show_problems``: warnings and errors
only). A process that dies then has its last lines printed with the file they came from.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO

from ros_tools.dds import keep_dds_local
from ros_tools.launch_respawn import RESPAWN_MAX_DEATHS, RESPAWN_WINDOW, Respawn, RespawnTracker

_COLORS = ["\033[36m", "\033[33m", "\033[35m", "\033[32m", "\033[34m", "\033[31m"]
_RESET = "\033[0m"
_PR_SET_PDEATHSIG = 1
#: Markers of the lines ``show_problems`` lets through: ROS log levels WARN and up, Python tracebacks.
#: " is waiting for ": a process that is not ready yet says what it waits for (nav-bringup's components).
PROBLEM_MARKERS = ("[WARN]", "[ERROR]", "[FATAL]", "Traceback (most recent call last)", "Error: ", "error: ",
                   " is waiting for ")
LAST_LINES = 15  # lines of a dead process shown on the console


def default_log_dir() -> Path:
    """Where launches keep their process logs: ``$NAVSUITE_LOG_DIR``, else ``artifacts/logs`` (relative
    to the working directory, next to the run reports)."""
    return Path(os.environ.get("NAVSUITE_LOG_DIR") or Path("artifacts") / "logs")


def show_problems(line: str) -> bool:
    """``Launcher(show=...)`` for a calm console: warnings, errors and tracebacks only."""
    return any(marker in line for marker in PROBLEM_MARKERS)


class LaunchError(RuntimeError):
    """A process failed to start, to become ready, or died while the launch was running."""


@dataclass
class ProcessSpec:
    """One process of a launch.

    Attributes:
        name: prefix of its output lines and name in error messages.
        cmd: the command line.
        ready: a regex; the process is ready once one of its output lines matches.
            None means ready as soon as it started.
        ready_timeout: seconds (wall clock) to wait for readiness.
        env: extra environment variables.
        required: when a required process exits (even with code 0), the launch ends.
        respawn: start it again when it exits (launch's ``respawn``); the launch ends only once it
            has been given up (see ros_tools.launch_respawn).
        respawn_delay: s (wall) between its exit and its new start (launch's ``respawn_delay``).
        respawn_max_deaths: deaths within ``respawn_window`` s after which it is given up.
        respawn_window: s (wall) over which its deaths are counted.
        ready_before_next: wait for its readiness before starting the next process; False starts
            the next one at once (processes that do not need each other, e.g. the stacks of a
            fleet's robots), and its readiness is awaited later (:meth:`Launcher.start`).
    """

    name: str
    cmd: Sequence[str]
    ready: str | None = None
    ready_timeout: float = 60.0
    env: dict[str, str] = field(default_factory=dict)
    required: bool = True
    respawn: bool = False
    respawn_delay: float = 0.0
    respawn_max_deaths: int = RESPAWN_MAX_DEATHS
    respawn_window: float = RESPAWN_WINDOW
    ready_before_next: bool = True

    def respawn_policy(self) -> Respawn:
        """The respawn settings as one checked value (ValueError on a bad one)."""
        return Respawn(self.respawn, self.respawn_delay, self.respawn_max_deaths, self.respawn_window)


def die_with_parent() -> None:
    """Runs in the child before exec: ask the kernel for SIGTERM when the launcher dies."""
    with contextlib.suppress(OSError):
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)


class _Running:
    def __init__(self, spec: ProcessSpec, color: str, out: Callable[[str], None],
                 show: Callable[[str], bool], log_path: Path | None, append: bool = False) -> None:
        self.spec = spec
        self.color = color
        self.restart_at: float | None = None  # monotonic s of a scheduled respawn, after its exit
        self.ready = threading.Event() if spec.ready else None
        self._pattern = re.compile(spec.ready) if spec.ready else None
        self.log_path = log_path
        self.last_lines: deque[str] = deque(maxlen=LAST_LINES)
        self.hidden = False  # some line did not reach the console
        log: TextIO | None = None
        if log_path is not None:
            log_path.parent.mkdir(parents=True, exist_ok=True)
            log = log_path.open("a" if append else "w", encoding="utf-8", buffering=1)
        env = dict(os.environ, PYTHONUNBUFFERED="1", **spec.env)
        keep_dds_local(env)
        # A crash in native code (rclpy, Fast DDS, numba) leaves the Python stacks of every thread
        # in the process's log instead of a bare "Segmentation fault".
        env.setdefault("PYTHONFAULTHANDLER", "1")
        try:
            self.proc = subprocess.Popen(
                list(spec.cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                start_new_session=True, preexec_fn=die_with_parent, bufsize=1,
            )
        except OSError:
            if log is not None:
                log.close()
            raise
        prefix = f"{color}[{spec.name}]{_RESET} " if color else f"[{spec.name}] "
        self._reader = threading.Thread(target=self._pump, args=(prefix, out, show, log), daemon=True)
        self._reader.start()

    def _pump(self, prefix: str, out: Callable[[str], None], show: Callable[[str], bool],
              log: TextIO | None) -> None:
        assert self.proc.stdout is not None
        try:
            for line in self.proc.stdout:
                line = line.rstrip("\n")
                self.last_lines.append(line)
                if log is not None:
                    log.write(line + "\n")
                if show(line):
                    out(prefix + line)
                else:
                    self.hidden = True
                if self.ready is not None and not self.ready.is_set() and self._pattern.search(line):  # type: ignore[union-attr]
                    self.ready.set()
        finally:
            if log is not None:
                log.close()

    def drain(self, timeout: float = 2.0) -> None:
        """Wait (at most ``timeout`` s) until every line of an exited process has been read."""
        self._reader.join(timeout)

    def signal(self, sig: int) -> None:
        if self.proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.proc.pid, sig)


class Launcher:
    """Starts ProcessSpecs in order and supervises them until one ends or the user interrupts."""

    #: s (wall clock) between "waiting for <name>" status lines while a process gets ready.
    STATUS_PERIOD = 10.0

    def __init__(self, output: Callable[[str], None] | None = None, color: bool | None = None,
                 shutdown_grace: float = 10.0, log_dir: Path | str | None = None,
                 show: Callable[[str], bool] | None = None) -> None:
        """``output`` takes every console line; ``log_dir`` (None: no files) gets ``<name>.log`` per
        process; ``show`` picks the process lines the console gets (default: all of them)."""
        self._lock = threading.Lock()
        self._output = output or self._print
        self._color = sys.stdout.isatty() if color is None else color
        self._grace = shutdown_grace
        self.log_dir = Path(log_dir) if log_dir is not None else None
        self._show = show or (lambda _line: True)
        self.running: list[_Running] = []
        self._stop = threading.Event()
        self._respawns: dict[str, RespawnTracker] = {}  # process name → its deaths
        self._given_up: set[str] = set()  # respawning processes whose last exit is final
        self._awaiting_ready: list[_Running] = []  # respawned processes whose ready line is to come

    def _print(self, line: str) -> None:
        with self._lock:
            print(line, flush=True)

    def log(self, text: str) -> None:
        self._output(f"[launch] {text}")

    def start(self, specs: Sequence[ProcessSpec]) -> None:
        """Start each process and wait for its readiness line before starting the next.

        A spec with ``ready_before_next`` False lets the next process start at once; its readiness is
        awaited with that of the next spec that waits, or before ``start`` returns.
        """
        waiting: list[tuple[_Running, float]] = []  # (started process, monotonic s it started)
        for index, spec in enumerate(specs):
            color = _COLORS[index % len(_COLORS)] if self._color else ""
            self.log(f"starting {spec.name}: {' '.join(spec.cmd)}")
            try:
                self._respawns[spec.name] = RespawnTracker(spec.respawn_policy())
            except ValueError as error:
                raise LaunchError(f"{spec.name}: {error}") from error
            running = self._spawn(spec, color)
            self.running.append(running)
            if running.ready is None:
                continue
            waiting.append((running, time.monotonic()))
            if spec.ready_before_next:
                for started_one, started in waiting:
                    self._wait_ready(started_one, started)
                waiting = []
        for started_one, started in waiting:
            self._wait_ready(started_one, started)

    def _wait_ready(self, running: _Running, started: float) -> None:
        """Wait for ``running``'s readiness line; LaunchError when it dies, times out or the launch stops."""
        spec = running.spec
        assert running.ready is not None
        next_status = time.monotonic() + self.STATUS_PERIOD  # a process awaited late: none at once
        while not running.ready.wait(0.1):
            code = running.proc.poll()
            if code is not None:
                running.drain()  # its last lines (the ready line, maybe) may still be in the pipe
                if running.ready.is_set():
                    break  # ready, then exited: wait() reports its exit code
                self._show_last_lines(running)
                raise LaunchError(f"{spec.name} exited with code {code} before it was ready")
            if self._stop.is_set():
                raise LaunchError("interrupted during startup")
            now = time.monotonic()
            if now - started > spec.ready_timeout:
                raise LaunchError(
                    f"{spec.name} was not ready after {spec.ready_timeout:.0f} s "
                    f"(waited for a line matching '{spec.ready}')"
                )
            if now >= next_status:  # a live status line: a slow start is not a hang
                next_status += self.STATUS_PERIOD
                self.log(f"waiting for {spec.name}: {now - started:.0f} s of {spec.ready_timeout:.0f} s "
                         f"(until it prints '{spec.ready}')")
        self.log(f"{spec.name} is ready ({time.monotonic() - started:.1f} s)")

    def _spawn(self, spec: ProcessSpec, color: str, append: bool = False) -> _Running:
        try:
            log_path = self.log_dir / f"{spec.name}.log" if self.log_dir is not None else None
            return _Running(spec, color, self._output, self._show, log_path, append)
        except OSError as error:
            raise LaunchError(f"cannot start {spec.name} ({spec.cmd[0]}): {error}") from error

    def wait(self, until: Callable[[], bool] | None = None, poll: float = 0.1) -> int:
        """Supervise until a required process exits, ``until()`` is true or stop() is called.

        A process with ``respawn`` is started again instead (see the module docstring) until it is
        given up. Returns 0 when stopped by ``until``/stop() or when every process exited with 0;
        otherwise the exit code of the first required process that ended, after logging which one.
        """
        while not self._stop.is_set():
            if until is not None and until():
                return 0
            for index, running in enumerate(self.running):
                code = running.proc.poll()
                if code is None:
                    continue
                respawning = running.spec.respawn and running.spec.name not in self._given_up
                if respawning and self._respawn(index, running, code):
                    continue
                if not running.spec.required:
                    continue
                if code == 0:
                    self.log(f"{running.spec.name} finished")
                    return 0
                if running.spec.name not in self._given_up:  # a given-up process has said why already
                    self.log(f"ERROR: {running.spec.name} died with exit code {code}; stopping the launch")
                running.drain()
                self._show_last_lines(running)
                return code if code > 0 else 1
            self._log_ready_again()
            time.sleep(poll)
        return 0

    def _respawn(self, index: int, running: _Running, code: int) -> bool:
        """Handle the exit of a respawning process; False once it is given up (the caller ends)."""
        now = time.monotonic()
        if running.restart_at is None:  # its death, seen for the first time
            tracker = self._respawns[running.spec.name]
            restart_at = tracker.died(now)
            if restart_at is None:
                then = "; stopping the launch" if running.spec.required else ""
                self.log(f"ERROR: {tracker.given_up_message(running.spec.name, code)}{then}")
                self._given_up.add(running.spec.name)
                running.drain()
                return False
            running.restart_at = restart_at
            self.log(f"WARN: {running.spec.name} died with exit code {code}; respawning it "
                     f"(restart {tracker.count} of at most {tracker.policy.max_deaths} within "
                     f"{tracker.policy.window:.0f} s)")
            running.drain()
            self._show_last_lines(running)
        if now < running.restart_at:
            return True
        self.log(f"respawning {running.spec.name}: {' '.join(running.spec.cmd)}")
        try:
            fresh = self._spawn(running.spec, running.color, append=True)
        except LaunchError as error:
            self.log(f"ERROR: {error}")
            self._given_up.add(running.spec.name)
            return False
        self.running[index] = fresh
        if fresh.ready is not None:
            self._awaiting_ready.append(fresh)
        return True

    def _log_ready_again(self) -> None:
        for running in [r for r in self._awaiting_ready if r.ready is not None and r.ready.is_set()]:
            self._awaiting_ready.remove(running)
            self.log(f"{running.spec.name} is ready again after its respawn")

    def _show_last_lines(self, running: _Running) -> None:
        """After a death: the process's last lines, when the console did not show them all."""
        if not running.hidden:
            return
        where = f" (all of them in {running.log_path})" if running.log_path else ""
        self.log(f"last {len(running.last_lines)} lines of {running.spec.name}{where}:")
        for line in list(running.last_lines):
            self._output(f"[{running.spec.name}] {line}")

    def stop(self) -> None:
        """Ask ``wait`` to return (safe from signal handlers and other threads)."""
        self._stop.set()

    def shutdown(self) -> None:
        """Stop every process in reverse start order: SIGINT, then SIGTERM, then SIGKILL; return once
        every line they wrote has been read (``output`` has seen them all)."""
        for sig, grace in ((signal.SIGINT, self._grace), (signal.SIGTERM, 3.0), (signal.SIGKILL, 3.0)):
            alive = [r for r in reversed(self.running) if r.proc.poll() is None]
            if not alive:
                break
            for running in alive:
                running.signal(sig)
            deadline = time.monotonic() + grace
            while time.monotonic() < deadline and any(r.proc.poll() is None for r in alive):
                time.sleep(0.05)
        for running in self.running:
            running.proc.wait()
            running.drain()

    @contextlib.contextmanager
    def stopping_on_signals(self) -> Iterator[threading.Event]:
        """While inside, SIGINT and SIGTERM stop the launch (``stop``) instead of raising wherever the
        main thread happens to be; the event yielded tells whether that happened. The previous
        handlers come back on exit."""
        interrupted = threading.Event()

        def on_signal(signum: int, frame: object) -> None:
            interrupted.set()
            self.stop()

        previous = {sig: signal.signal(sig, on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
        try:
            yield interrupted
        finally:
            for sig, handler in previous.items():
                signal.signal(sig, handler)

    def run(self, specs: Sequence[ProcessSpec], until: Callable[[], bool] | None = None) -> int:
        """Start, supervise and shut down; handles SIGINT/SIGTERM. Returns the launch's exit code."""
        with self.stopping_on_signals() as interrupted:
            try:
                self.start(specs)
                code = self.wait(until)
            except LaunchError as error:
                self.log(f"ERROR: {error}")
                code = 130 if interrupted.is_set() else 1
            finally:
                self.log("shutting down")
                self.shutdown()
        if interrupted.is_set():
            return 130 if code == 0 else code
        return code
