"""The Ray backend of the farm: each scenario a Ray task on whichever node of a cluster has the CPUs.

``navsuite-scenarios run FILE --ray ADDRESS`` (or ``--ray auto``) connects to a running Ray cluster and
submits one task per scenario asking for ``--ray-cpus`` CPUs (default 1: a mission's stack, simulator
and recorder keep about one core busy, so a 2-core node runs two). Ray places, queues and retries the
tasks; this module only turns a ``Job`` into a task and the task's answer back into an ``Outcome``.

* On its node the task runs ``executor.run_job``, exactly what the local backend runs: a domain id
  claimed with ``domains`` (node-local lock files, so two scenarios on one node never share a DDS
  domain), localhost discovery, the process marker. Its artifacts go to a node-local directory, come
  back as one gzipped tar (the task's return value, through Ray's object store) and are unpacked by
  the driver into the job's artifact directory, their paths in the outcome rewritten to match.
* A task whose worker process dies (killed, out of memory, node lost) is re-queued once by Ray itself
  (``max_retries=1``). Each attempt records itself with a small ledger actor as it starts and reads
  its number as it ends (never waiting on it at the start: Ray lends the CPUs of a task blocked in
  ``ray.get`` to another task, which would put more missions on a node than it has cores), so the
  outcome of a re-queued scenario says so (``attempts`` 2, and its detail); a second death fails only
  that scenario. The worker of a dead attempt gets SIGTERM from the kernel (``run_job``'s PDEATHSIG), and
  an attempt landing on the same node kills what is left of it before claiming a domain id.
* Every node runs the same navsuite installation, and sees the scenario file at the driver's path
  (the file names maps and parameter files relative to itself and to the checkout).

Ray is imported lazily: the core install works without it; ``--ray`` without it names the extra.
"""

from __future__ import annotations

import io
import json
import shutil
import signal
import socket
import tarfile
import tempfile
import threading
import uuid
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from navsuite_tools.scenarios.domains import DomainPool
from navsuite_tools.scenarios.executor import Job, run_job, sweep
from navsuite_tools.scenarios.verdict import Outcome

INSTALL_HINT = "pip install navsuite[cluster]"
DEFAULT_CPUS = 1.0  # CPUs a task asks for: about one core per mission (stack + sim + recorder)
MAX_RETRIES = 1  # Ray re-runs a task whose worker died this many times
POLL = 0.5  # wall s between the driver's looks at finished tasks and newly started ones
Runner = Callable[[Job, DomainPool, str], Outcome]
#: The running task's attempt record (the ObjectRef of its ``AttemptLedger.begin``), for a runner that
#: ends its own process on purpose: it must wait for the record first, or the re-run cannot know it is
#: one (the record is sent asynchronously; on a busy machine it took over a second to arrive).
RUNNING_ATTEMPT: ContextVar[Any] = ContextVar("navsuite_running_attempt", default=None)


def require_ray() -> Any:
    """The ``ray`` module, or RuntimeError naming the extra that installs it."""
    try:
        import ray
    except ImportError:
        raise RuntimeError(f"--ray needs Ray, which the core install leaves out: {INSTALL_HINT}") from None
    return ray


class AttemptLedger:
    """Ray actor: counts the attempts of each job (by marker), so a re-run knows it is one."""

    def __init__(self) -> None:
        self._attempts: dict[str, int] = {}

    def begin(self, marker: str) -> int:
        """Record one more attempt of ``marker``; its number (1 for the first)."""
        self._attempts[marker] = self._attempts.get(marker, 0) + 1
        return self._attempts[marker]

    def attempts(self) -> dict[str, int]:
        return dict(self._attempts)


def run_on_node(job: Job, domains: tuple[int, int], marker: str, ledger: Any,
                runner: Runner) -> dict[str, Any]:
    """The Ray task: run ``job`` here with its artifacts in a node-local directory; the outcome,
    the attempt number and the artifacts as gzipped tar bytes."""
    import ray

    attempt = ledger.begin.remote(marker)  # read at the end: a task blocked in ray.get lends its CPUs out
    sweep(marker)  # a dead earlier attempt's processes on this node, still on a domain id they lost
    node_dir = Path(tempfile.gettempdir()) / f"navsuite-scenario-{marker.replace(':', '-')}"
    shutil.rmtree(node_dir, ignore_errors=True)
    token = RUNNING_ATTEMPT.set(attempt)
    try:
        with _interruptible():
            outcome = runner(replace(job, artifact_dir=node_dir), DomainPool(*domains), marker)
        return {"outcome": outcome.to_json(), "attempt": ray.get(attempt), "node_dir": str(node_dir),
                "archive": pack(node_dir)}
    finally:
        RUNNING_ATTEMPT.reset(token)
        shutil.rmtree(node_dir, ignore_errors=True)


@contextmanager
def _interruptible() -> Iterator[None]:
    """Let ``ray.cancel`` stop the run. Ray cancels a running task by simulating SIGINT in it
    (KeyboardInterrupt, upon which ``run_job`` stops the worker and frees its domain id), which does
    nothing in a worker that ignores SIGINT, as the raylet's workers do; so the block handles it."""
    try:
        previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    except ValueError:  # not on the main thread (Ray runs tasks there): nothing to change
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def pack(directory: Path) -> bytes:
    """``directory``'s files as a gzipped tar, paths relative to it."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:gz", compresslevel=1) as archive:  # MCAP is compressed
        archive.add(directory, arcname=".")
    return buffer.getvalue()


def receive(reply: dict[str, Any], artifact_dir: Path) -> Outcome:
    """Unpack a task's artifacts into ``artifact_dir``; its outcome with paths there and its attempts.

    ``result.json`` is rewritten with that outcome, so the file next to the artifacts is the one judged.
    """
    artifact_dir.mkdir(parents=True, exist_ok=True)
    with tarfile.open(fileobj=io.BytesIO(reply["archive"]), mode="r:gz") as archive:
        archive.extractall(artifact_dir, filter="data")
    outcome = Outcome.from_json(reply["outcome"])
    node_dir = reply["node_dir"]
    artifacts = {name: str(artifact_dir) + path[len(node_dir):] if path.startswith(node_dir) else path
                 for name, path in outcome.artifacts.items()}
    outcome = requeued(replace(outcome, artifacts=artifacts), reply["attempt"])
    (artifact_dir / "result.json").write_text(json.dumps(outcome.to_json(), indent=2), encoding="utf-8")
    return outcome


def requeued(outcome: Outcome, attempts: int) -> Outcome:
    """``outcome`` marked with its attempts; a re-queued one says so in its detail too."""
    if attempts <= 1:
        return outcome
    note = f"re-queued: its worker died on attempt 1, this is attempt {attempts}"
    return replace(outcome, attempts=attempts, detail=f"{outcome.detail}; {note}" if outcome.detail else note)


def _check_reachable(address: str, timeout: float = 5.0) -> None:
    """ConnectionError within ``timeout`` s when nothing listens at ``host:port`` (``ray.init`` itself
    retries for minutes); other forms ("auto") are left to Ray."""
    host, _, port = address.rpartition(":")
    if not host or not port.isdigit():
        return
    try:
        socket.create_connection((host, int(port)), timeout=timeout).close()
    except OSError as error:
        raise ConnectionError(f"no Ray cluster answers at {address}: {error}") from None


@dataclass
class _Pending:
    job: Job
    marker: str
    future: Future[Outcome]
    on_start: Callable[[], None] | None
    started: bool = False


def _announce(entry: _Pending, attempts: dict[str, int]) -> None:
    """Call the job's ``on_start`` once, when its task has begun an attempt."""
    if not entry.started and entry.marker in attempts:
        entry.started = True
        if entry.on_start is not None:
            entry.on_start()


class RayExecutor:
    """Runs each job as a Ray task on the cluster at ``address`` ("auto": the one started on this
    machine), ``num_cpus`` CPUs each, on domain ids of ``domains`` claimed on the node it lands on."""

    def __init__(self, address: str, domains: tuple[int, int], num_cpus: float = DEFAULT_CPUS,
                 runner: Runner = run_job) -> None:
        self._ray = ray = require_ray()
        _check_reachable(address)
        ray.init(address=address, log_to_driver=False, logging_level="warning")
        from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

        # on the driver's node: a worker node that dies must take only its scenarios down, not the counts
        here = NodeAffinitySchedulingStrategy(ray.get_runtime_context().get_node_id(), soft=False)
        self._ledger = ray.remote(num_cpus=0)(AttemptLedger).options(scheduling_strategy=here).remote()
        self._task = ray.remote(run_on_node).options(num_cpus=num_cpus, max_retries=MAX_RETRIES,
                                                     retry_exceptions=False)
        self._domains, self._runner = domains, runner
        self._run_id = uuid.uuid4().hex[:12]
        self._pending: dict[Any, _Pending] = {}  # ObjectRef → its job
        self._lock = threading.Lock()
        self._closing = threading.Event()
        self._collector = threading.Thread(target=self._collect, name="ray-collector", daemon=True)
        self._collector.start()

    def submit(self, job: Job, on_start: Callable[[], None] | None = None) -> Future[Outcome]:
        marker = f"{self._run_id}:{job.scenario.name}"
        future: Future[Outcome] = Future()
        future.set_running_or_notify_cancel()
        ref = self._task.remote(job, self._domains, marker, self._ledger, self._runner)
        with self._lock:
            self._pending[ref] = _Pending(job, marker, future, on_start)
        return future

    def shutdown(self, cancel: bool = False) -> None:
        """Wait for every task (``cancel``: cancel them first: a running one stops its worker, then
        ends); then disconnect from the cluster, which keeps running."""
        if cancel:
            with self._lock:
                refs = list(self._pending)
            for ref in refs:
                self._ray.cancel(ref)
        self._closing.set()
        self._collector.join()
        self._ray.kill(self._ledger)
        self._ray.shutdown()

    def _collect(self) -> None:
        """The driver's one waiting thread: reports starts (from the ledger) and settles finished tasks."""
        while True:
            with self._lock:
                pending = dict(self._pending)
            if not pending:
                if self._closing.is_set():
                    return
                self._closing.wait(POLL)
                continue
            done, running = self._ray.wait(list(pending), num_returns=len(pending), timeout=POLL)
            attempts = self._ray.get(self._ledger.attempts.remote())
            for ref in done:  # finishes first, so a slot that freed is reported before its next start
                entry = pending[ref]
                _announce(entry, attempts)
                entry.future.set_result(self._settle(ref, entry, attempts.get(entry.marker, 0)))
                with self._lock:
                    del self._pending[ref]
            for ref in running:  # left the queue: its task recorded an attempt
                _announce(pending[ref], attempts)

    def _settle(self, ref: Any, entry: _Pending, attempts: int) -> Outcome:
        """A finished task's outcome; a task that failed (cancelled, its worker died twice) an ERROR."""
        try:
            return receive(self._ray.get(ref), entry.job.artifact_dir)
        except self._ray.exceptions.TaskCancelledError:
            return Outcome("ERROR", "cancelled", attempts=max(attempts, 1))
        except Exception as error:  # the scenario fails, never the farm
            return requeued(Outcome("ERROR", describe(error)), attempts)


def describe(error: BaseException) -> str:
    """``Type: message`` of what failed: for a task's exception the cause, not Ray's wrapper (whose
    text is the remote traceback; its last line is the message)."""
    cause = getattr(error, "cause", None) or error
    lines = [line.strip() for line in str(cause).splitlines() if line.strip()]
    return f"{type(cause).__name__}: {lines[-1] if lines else ''}".rstrip(": ")
