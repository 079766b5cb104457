"""Helpers for tests that talk to real rclpy nodes: waits that poll a condition with a deadline.

No test sleeps for a fixed time: it spins an executor until a predicate holds or a deadline passes,
and the failure message says what was being waited for.
"""

from __future__ import annotations

import contextlib
import gc
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from rclpy.executors import Executor
from rclpy.node import Node

from ros_tools.runtime.requests import poll
from ros_tools.runtime.runner import spin_until_shutdown

REPO = Path(__file__).resolve().parents[1]

#: The simulator's real-time factor in whole-stack tests: ``max``, as fast as the slowest lockstep
#: participant keeps up. Lockstep does not yet cover messages in flight between processes or DDS
#: discovery (see the issue 17 note). NAV_SYSTEM_TEST_RTF=1 runs them at real time, e.g. to watch.
SYSTEM_RTF = os.environ.get("NAV_SYSTEM_TEST_RTF", "max")


def spin_until(
    executor: Executor,
    predicate: Callable[[], bool],
    timeout: float,
    what: str = "condition",
    step: float = 0.02,
) -> None:
    """Spin ``executor`` until ``predicate()`` is true; fail after ``timeout`` seconds (wall clock)."""
    if not spinning(executor, step)(predicate, timeout):
        raise AssertionError(f"timed out after {timeout:.1f} s waiting for {what}")


def spinning(executor: Executor, step: float = 0.02) -> Callable[[Callable[[], bool], float], bool]:
    """A ``wait(predicate, seconds) -> bool`` that spins ``executor`` meanwhile, for
    ros_tools.runtime.actions.send_until_acknowledged from the thread that spins the client."""

    def wait(predicate: Callable[[], bool], seconds: float) -> bool:
        deadline = time.monotonic() + seconds
        while not predicate():
            if time.monotonic() > deadline:
                return False
            executor.spin_once(timeout_sec=step)
        return True

    return wait


def wait_until(predicate: Callable[[], bool], timeout: float, what: str = "condition",
               step: float = 0.02) -> None:
    """Poll ``predicate()`` (without spinning) until true; fail after ``timeout`` seconds."""
    if not poll(predicate, timeout, step):
        raise AssertionError(f"timed out after {timeout:.1f} s waiting for {what}")


class BackgroundSpin:
    """An executor spinning in a daemon thread until :meth:`stop`.

    Why not ``Thread(target=executor.spin)``: stopping that means calling ``executor.shutdown()``
    from another thread while ``spin`` runs, and rclpy's shutdown races the spin loop (seen in CI
    as an unhandled AttributeError on the executor's guard condition in the spin thread at a system
    test's teardown). Here the thread spins in slices (``spin_until_shutdown``) and leaves between
    two of them when told, so the executor is shut down only once no thread uses it.
    """

    def __init__(self, executor: Executor, name: str = "test") -> None:
        self.executor = executor
        self._stopping = threading.Event()
        self.thread = threading.Thread(target=spin_until_shutdown, name=f"spin {name}", daemon=True,
                                       args=(executor, name, self._stopping.is_set))
        self.thread.start()

    def stop(self, *nodes: Any) -> None:
        """Stop spinning, wait for the thread, shut the executor down, then destroy ``nodes``.

        Why this order: a node destroyed while the thread still builds its wait set makes rclpy raise
        InvalidHandle ("cannot use Destroyable") in that thread.
        """
        self._stopping.set()
        self.thread.join(timeout=5.0)
        self.executor.shutdown()
        for node in nodes:
            node.destroy_node()


def connected(endpoints: Iterable[Any]) -> Callable[[], bool]:
    """A predicate: every subscription has a matched publisher and every publisher a subscription.

    Why: lockstep holds the simulator for its participants' callbacks, not for DDS discovery. A test
    node passes this as its LockstepParticipant ``ready`` so the simulator waits until the node can
    hear and be heard, instead of running on while a latched first message is still unmatched.
    """
    items = list(endpoints)

    def ready() -> bool:
        return all((e.get_subscription_count() if hasattr(e, "get_subscription_count")
                    else e.get_publisher_count()) > 0 for e in items)

    return ready


def release_dds_participants() -> int:
    """Free the DDS participants that nodes of shut-down contexts still hold; returns the node count.

    Why: rmw_fastrtps keeps a context's DomainParticipant (and its UDP discovery ports) until the
    last rmw node of that context is gone, and neither ``rclpy.shutdown`` nor ``Node.destroy_node``
    (which leaves action clients and servers alive, and they hold the node: destroyed here first)
    ends that by itself; the Python objects usually sit in reference cycles until a full collection.
    Localhost discovery (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST) pings a bounded range of participant
    ids, so after some thirty leftover participants in a test session, two new processes of the same
    domain never discover each other (seen in CI: /initialpose never matched AMCL's subscription).
    """
    from rclpy.action import ActionClient, ActionServer

    gc.collect()
    objects = gc.get_objects()
    # Action servers and clients first: each holds its node's rcl handle (and so the participant)
    # until destroyed, and Node.destroy_node leaves them alone (seen in CI: a later test's
    # ``ros2py node list`` still found three bt_navigator rigs and missed its own node).
    actions = [obj for obj in objects if isinstance(obj, (ActionServer, ActionClient))
               and getattr(obj, "_node", None) is not None and not obj._node.context.ok()]
    for action in actions:
        with contextlib.suppress(Exception):
            action.destroy()
    orphans = [obj for obj in objects
               if isinstance(obj, Node) and not obj.context.ok()]
    for node in orphans:
        with contextlib.suppress(Exception):  # a half-torn-down node must not fail the next test
            node.destroy_node()
    return len(orphans)


def start_python(module_or_script: str | Path, args: Iterable[str] = ()) -> subprocess.Popen[str]:
    """Start ``python -m module`` (or a script path) in a child process with the test's ROS env.

    The child inherits ROS_DOMAIN_ID and ROS_AUTOMATIC_DISCOVERY_RANGE from conftest; its stdout
    and stderr are captured as text so a failing test can show them.
    """
    target = str(module_or_script)
    cmd = [sys.executable, target] if target.endswith(".py") else [sys.executable, "-m", target]
    return subprocess.Popen(
        [*cmd, *args],
        cwd=REPO,
        env=dict(os.environ),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )


def stop_process(proc: subprocess.Popen[str], timeout: float = 10.0) -> str:
    """Interrupt a child (SIGINT, then SIGKILL after ``timeout``) and return its output."""
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    out = proc.stdout.read() if proc.stdout else ""
    return out
