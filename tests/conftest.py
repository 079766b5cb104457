"""Test-session setup shared by every test.

* DDS stays on this machine: ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST unless the user chose a range.
* Every test session claims its own ROS_DOMAIN_ID (an exclusive lock per id, or
  NAVSUITE_TEST_DOMAIN_ID if set), so parallel runs, CI and a running demo never see each other.
  Child processes started by tests inherit both variables.
* Launches started by tests write their process logs to a directory of this session
  (NAVSUITE_LOG_DIR, a fresh temporary directory per worker), not to the user's artifacts/logs: two
  test workers running the stack at once would otherwise write the same files. Each test gets its
  own subdirectory (``_test_log_dir``, set by ``pytest_runtest_setup``), named in the report of a
  failed test.
* The ``ros_context`` fixture gives each rclpy test its own context, shut down in ``finally``.
* After every test that shut an rclpy context down, nodes whose context was shut down are destroyed
  (``_release_dds_participants``): a node outliving its context keeps that context's DDS participant
  alive, and with localhost discovery a domain holding more than about 30 participants stops
  discovering new ones.
* Once collection has imported every test module, what it created is frozen out of the garbage
  collector's reach (``pytest_collection_finish``), so that release and Python's own full collections
  walk only what the tests create.
"""

from __future__ import annotations

import fcntl
import gc
import os
import re
import tempfile
import warnings
from collections.abc import Iterator
from typing import Any

import pytest

from ros_tools.dds import keep_dds_local


def _claim_domain_id() -> int:
    """Pick a ROS_DOMAIN_ID no other test session on this machine holds, and hold it.

    Each candidate id (1..100; 0 is left to users) has a lock file; the session keeps an exclusive
    flock on the one it claims until it exits, so concurrent runs never share a DDS domain.
    """
    start = os.getpid() % 100
    for offset in range(100):
        domain = 1 + (start + offset) % 100
        path = os.path.join(tempfile.gettempdir(), f"navsuite-ros-domain-{domain}.lock")
        handle = open(path, "w")  # noqa: SIM115 - must stay open (locked) for the whole session
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        _DOMAIN_LOCKS.append(handle)  # released when the session's process exits
        return domain
    raise RuntimeError("all ROS domain ids 1..100 are held by other test sessions on this machine")


_DOMAIN_LOCKS: list[object] = []
keep_dds_local()
if "NAVSUITE_TEST_DOMAIN_ID" in os.environ:
    os.environ["ROS_DOMAIN_ID"] = os.environ["NAVSUITE_TEST_DOMAIN_ID"]
else:
    os.environ["ROS_DOMAIN_ID"] = str(_claim_domain_id())
# per process (each xdist worker has its own): a directory inherited from the controller would be shared
_SESSION_LOG_DIR = tempfile.mkdtemp(prefix=f"navsuite-logs-{os.environ['ROS_DOMAIN_ID']}-")
os.environ["NAVSUITE_LOG_DIR"] = _SESSION_LOG_DIR


def _test_log_dir(item: pytest.Item) -> str:
    """``<session log dir>/<test file>/<test name>``, with characters a path would trip on replaced."""
    module, _, name = item.nodeid.partition("::")
    safe = [re.sub(r"[^A-Za-z0-9_.-]+", "_", part)[:120] for part in (module, name or "_")]
    return os.path.join(_SESSION_LOG_DIR, *safe)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item: pytest.Item) -> None:
    """Point NAVSUITE_LOG_DIR at this test's own directory before its fixtures start anything.

    Why: with one directory per worker, the next test's stack overwrote ``sim2d.log`` and the other
    process logs of a failed one, and with them the evidence (CI run DD, 2026-11-28). A stack a
    module-scoped fixture starts logs under the directory of the module's first test.
    """
    os.environ["NAVSUITE_LOG_DIR"] = _test_log_dir(item)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Any:
    """Name the process-log directory of the test's module in the report of a failed test."""
    report = yield
    if report.failed:
        module_dir = os.path.dirname(_test_log_dir(item))
        if os.path.isdir(module_dir):
            report.sections.append(("process logs", f"{module_dir}/<test name>/<process>.log"))
    return report


@pytest.fixture
def ros_context() -> Iterator[object]:
    """A fresh, initialised rclpy context owned by one test and shut down afterwards."""
    import rclpy
    from rclpy.context import Context

    context = Context()
    rclpy.init(context=context)
    try:
        yield context
    finally:
        if context.ok():
            rclpy.shutdown(context=context)


def pytest_collection_finish(session: pytest.Session) -> None:
    """Move every object collection created (the modules, numba's and matplotlib's and rclpy's state)
    into the garbage collector's permanent generation.

    Why: the release after a test (``_release_dds_participants``) runs a full ``gc.collect`` and walks
    ``gc.get_objects()``, and both scale with the heap; collecting the whole suite leaves about 300,000
    objects in it. Frozen, they are skipped by both (and by Python's own full collections): a release
    took 0.28 s of CPU before and 0.01 s after, and tests/integration on three workers, machine idle,
    went from 144 to 30 s of teardown and from 285 to 234 s of wall time (2026-11-29). No node exists
    before the first test, so none is hidden from the release. The garbage collection left is
    collected first, so that none of it is frozen.
    """
    gc.collect()
    gc.freeze()


#: DDS participants a test worker may hold between tests before a test says so (helpers/dds_participants.py)
PARTICIPANTS_WARN = 8
_shutdowns = [0]  # rclpy contexts shut down since the last release (see _count_context_shutdowns)


def _count_context_shutdowns() -> None:
    """Count every rclpy ``Context.shutdown`` / ``try_shutdown`` of this session in ``_shutdowns``.

    Why: only a shut-down context can leave nodes holding a DDS participant behind, and the release
    (a full ``gc.collect`` and a walk over every object) costs up to a second per test once numba,
    matplotlib and rclpy fill the heap: run after every test it was 0.9 s x 888 unit tests, most of
    a CI run's teardown time (full suite with --durations=0, 2026-11-27). A module-scoped stack
    shut down at its module's end is released after the next test.
    """
    from rclpy.context import Context

    for name in ("shutdown", "try_shutdown"):
        original = getattr(Context, name)

        def counted(self: Context, _original: Any = original) -> None:
            _shutdowns[0] += 1
            _original(self)

        setattr(Context, name, counted)


_count_context_shutdowns()


@pytest.fixture(autouse=True)
def _no_process_outlives_its_test() -> Iterator[None]:
    """Kill what a test started and left running (tests/helpers/process_tree.py says why), with a
    warning that names it. Processes of module- and session-scoped fixtures are started before this
    fixture looks and stopped after it, so they are not touched."""
    from tests.helpers.process_tree import kill_leftovers, live_children

    before = live_children(os.getpid())
    yield
    killed = kill_leftovers(before)
    if killed:
        warnings.warn(f"the test left {len(killed)} process(es) running; killed: {killed}", stacklevel=1)


@pytest.fixture(autouse=True)
def _release_dds_participants() -> Iterator[None]:
    """After a test in which an rclpy context was shut down, free the DDS participants of the nodes
    it left behind (see the module doc)."""
    yield
    if _shutdowns[0]:
        from navsuite_testing.ros import release_dds_participants

        _shutdowns[0] = 0
        release_dds_participants()
    from tests.helpers.dds_participants import own_participants

    held = own_participants(int(os.environ["ROS_DOMAIN_ID"]))
    if held > PARTICIPANTS_WARN:
        warnings.warn(f"this test worker holds {held} DDS participants after the test (at about 30, new "
                      "processes of its domain are no longer discovered): something keeps a node alive",
                      stacklevel=1)
