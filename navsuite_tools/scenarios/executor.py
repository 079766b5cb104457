"""Where scenarios run: the ``Executor`` seam and its local backend, a pool of worker processes.

Each job becomes one ``python -m navsuite_tools.scenarios.worker`` process, in a session of its own, on a
ROS_DOMAIN_ID claimed for it alone (``domains``), with localhost discovery. A backend only has to turn
a ``Job`` into a ``concurrent.futures.Future[Outcome]``; the farm never looks past ``submit`` and
``shutdown``. ``run_job`` is one job's whole run on this machine: the local backend calls it from its
threads, the Ray backend (``cluster``) from a task on the node the task landed on.

Nothing is left behind: every process of a job inherits a marker in its environment
(``NAVSUITE_SCENARIO_RUN``), and once the worker ended (or was killed at its deadline) any process
still carrying the marker is killed and counted in the outcome's detail.
"""

from __future__ import annotations

import contextlib
import ctypes
import json
import os
import signal
import subprocess
import sys
import threading
import time
import uuid
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Protocol

from navsuite_tools.scenarios.commands import COMMAND_MARGIN
from navsuite_tools.scenarios.domains import DomainPool
from navsuite_tools.scenarios.schema import Scenario
from navsuite_tools.scenarios.verdict import Outcome
from ros_tools.launch import die_with_parent

MARKER = "NAVSUITE_SCENARIO_RUN"
#: wall s past a worker's own deadline (its scenario's timeout + COMMAND_MARGIN: it stops the mission then and
#: still has to shut the processes down, read the recording and draw the report) before the farm stops it
KILL_AFTER = 30.0
#: wall s a worker has after SIGTERM (its launcher's own SIGINT grace is 10 s) before SIGKILL
STOP_GRACE = 20.0
#: wall s sweep waits for the processes it killed to leave /proc
SWEEP_WAIT = 2.0


@dataclass(frozen=True)
class Job:
    """One scenario to run: which one, the file it is defined in, where its artifacts go."""

    scenario: Scenario
    source: Path
    artifact_dir: Path


class Executor(Protocol):
    """Runs jobs; ``shutdown(cancel=True)`` stops running ones and drops queued ones."""

    def submit(self, job: Job, on_start: Callable[[], None] | None = None) -> Future[Outcome]:
        """Queue ``job``; ``on_start`` is called (from any thread) when it leaves the queue."""

    def shutdown(self, cancel: bool = False) -> None: ...


class LocalExecutor:
    """Up to ``workers`` scenarios at a time on this machine, each on its own claimed domain id."""

    def __init__(self, workers: int, domains: DomainPool) -> None:
        self._pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="scenario")
        self._domains = domains
        self._run_id = uuid.uuid4().hex[:12]
        self._live: dict[str, subprocess.Popen[bytes]] = {}
        self._lock = threading.Lock()
        self._cancelled = threading.Event()

    def submit(self, job: Job, on_start: Callable[[], None] | None = None) -> Future[Outcome]:
        return self._pool.submit(self._run, job, on_start)

    def shutdown(self, cancel: bool = False) -> None:
        if cancel:
            self._cancelled.set()
            with self._lock:
                for proc in self._live.values():
                    _signal_group(proc, signal.SIGTERM)
        self._pool.shutdown(wait=True, cancel_futures=cancel)

    def _run(self, job: Job, on_start: Callable[[], None] | None) -> Outcome:
        if self._cancelled.is_set():
            return Outcome("ERROR", "cancelled before it started")
        if on_start is not None:
            on_start()
        marker = f"{self._run_id}:{job.scenario.name}"
        try:
            return run_job(job, self._domains, marker, lambda proc: self._track(marker, proc))
        finally:
            with self._lock:
                self._live.pop(marker, None)

    def _track(self, marker: str, proc: subprocess.Popen[bytes]) -> None:
        with self._lock:
            self._live[marker] = proc
            if self._cancelled.is_set():  # cancelled while it was starting
                _signal_group(proc, signal.SIGTERM)


def run_job(job: Job, domains: DomainPool, marker: str,
            on_spawn: Callable[[subprocess.Popen[bytes]], None] | None = None) -> Outcome:
    """Run ``job``'s worker process to its end on this machine: the unit every backend runs.

    The worker gets a ROS_DOMAIN_ID claimed from ``domains`` (held until its last process is gone),
    localhost discovery and ``MARKER=marker``; ``on_spawn`` sees the process as soon as it exists (to
    stop it on cancel). The worker dies with the thread that started it (PR_SET_PDEATHSIG), so a
    backend's process that is killed takes its scenario down with it rather than leave it running on
    a domain id it no longer holds. An exception while waiting (a cancelled Ray task gets
    KeyboardInterrupt) stops the worker and is passed on.
    """
    started = time.monotonic()
    job.artifact_dir.mkdir(parents=True, exist_ok=True)
    result_file = job.artifact_dir / "result.json"
    result_file.unlink(missing_ok=True)
    with domains.claim() as domain:
        env = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
                   NAVSUITE_LOG_DIR=str(job.artifact_dir / "logs"), PYTHONUNBUFFERED="1",
                   **{MARKER: marker})
        with (job.artifact_dir / "worker.log").open("wb") as log:
            proc = subprocess.Popen(
                [sys.executable, "-m", "navsuite_tools.scenarios.worker", str(job.source), job.scenario.name,
                 str(job.artifact_dir)],
                stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True,
                preexec_fn=_child_setup)
            try:
                if on_spawn is not None:
                    on_spawn(proc)
                killed = _wait(proc, hard_limit(job.scenario))
            finally:
                # Before the domain id is released, and on an interrupt too: the worker's own stop
                # does not wait for the stack processes it started (CI run DV found two of an
                # interrupted Ray run alive after the farm had said all were stopped).
                leftovers = sweep(marker)
    outcome = _read(result_file, proc.returncode)
    if killed:
        limit = hard_limit(job.scenario)
        outcome = Outcome("TIMEOUT", f"the farm stopped the run after {limit:.0f} s wall",
                          artifacts=outcome.artifacts)
    if leftovers:
        detail = f"{outcome.detail}; {leftovers} process(es) left behind, killed"
        outcome = replace(outcome, detail=detail)
    return replace(outcome, wall_time=time.monotonic() - started)


def _child_setup() -> None:
    """Runs in the worker between fork and exec: die with the thread that started it, and start from
    the default handling of every signal. A Ray worker ignores and blocks SIGINT, and both survive
    exec: inherited, they would make the scenario's processes deaf to its launcher's orderly stop."""
    die_with_parent()
    signal.pthread_sigmask(signal.SIG_SETMASK, set())
    libc = ctypes.CDLL("libc.so.6", use_errno=True)
    for sig in (signal.SIGINT, signal.SIGQUIT):  # signal.signal refuses to run off the main thread
        libc.signal(int(sig), 0)  # SIG_DFL


def _wait(proc: subprocess.Popen[bytes], limit: float) -> bool:
    """Wait for the worker; past ``limit`` s (wall) stop it. True when it had to be stopped."""
    try:
        proc.wait(timeout=limit)
        return False
    except subprocess.TimeoutExpired:
        pass
    except BaseException:
        _stop(proc)
        raise
    _stop(proc)
    return True


def _stop(proc: subprocess.Popen[bytes]) -> None:
    """SIGTERM the worker's process group; SIGKILL STOP_GRACE s later if it is still there."""
    _signal_group(proc, signal.SIGTERM)
    try:
        proc.wait(timeout=STOP_GRACE)
    except subprocess.TimeoutExpired:
        _signal_group(proc, signal.SIGKILL)
        proc.wait()


def hard_limit(scenario: Scenario) -> float:
    """Wall s after which the farm stops a scenario's worker (SIGTERM, then SIGKILL STOP_GRACE s later)."""
    return scenario.timeout + COMMAND_MARGIN + KILL_AFTER


def _signal_group(proc: subprocess.Popen[bytes], sig: int) -> None:
    if proc.poll() is None:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(proc.pid, sig)


def _read(result_file: Path, code: int | None) -> Outcome:
    try:
        return Outcome.from_json(json.loads(result_file.read_text(encoding="utf-8")))
    except (OSError, ValueError, TypeError) as error:
        return Outcome("ERROR", f"the worker wrote no result (exit code {code}): {error}")


def marked_processes(marker: str) -> list[int]:
    """PIDs of this user's processes whose environment carries ``MARKER=marker``."""
    return processes_with_env(f"{MARKER}={marker}")


def processes_with_env(entry: str) -> list[int]:
    """PIDs of this user's processes (this one excepted) whose environment has ``entry`` (NAME=value)."""
    needle = entry.encode() + b"\0"
    found = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit() or int(proc.name) == os.getpid():
            continue
        try:
            environ = (proc / "environ").read_bytes()
        except OSError:
            continue
        if needle in environ:
            found.append(int(proc.name))
    return found


def sweep(marker: str) -> int:
    """Kill every process still marked ``marker`` (SIGKILL) and return once they are gone (at most
    SWEEP_WAIT s: a killed process leaves /proc when its parent reaps it); how many there were."""
    pids = marked_processes(marker)
    for pid in pids:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(pid, signal.SIGKILL)
    deadline = time.monotonic() + SWEEP_WAIT
    while pids and marked_processes(marker) and time.monotonic() < deadline:
        time.sleep(0.02)
    return len(pids)
