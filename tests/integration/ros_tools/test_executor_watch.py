"""ExecutorWatch: a callback that holds the executor thread is named, with the lag, then the catch-up."""

from __future__ import annotations

import threading
from typing import Any

import pytest
from rclpy.node import Node

from navsuite_testing.ros import spin_until, wait_until
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.executor_watch import ExecutorWatch

pytestmark = pytest.mark.ros


class _Lines:
    """A logger that keeps what it is told."""

    def __init__(self) -> None:
        self.warnings: list[str] = []
        self.infos: list[str] = []

    def warning(self, text: str) -> None:
        self.warnings.append(text)

    def info(self, text: str) -> None:
        self.infos.append(text)


@pytest.mark.parametrize("executor_kind", ["events", "single"])
def test_a_held_executor_is_named_with_its_callback(ros_context: Any, executor_kind: str) -> None:
    node = Node("watched", context=ros_context)
    executor = make_executor(executor_kind, ros_context)
    executor.add_node(node)
    release = threading.Event()
    held = threading.Event()

    def stuck_callback() -> None:  # stands for a callback that blocks: released by the test
        held.set()
        release.wait(10.0)

    lines = _Lines()
    watch = ExecutorWatch(executor, "watched", lines, period=0.05, threshold=0.3)
    watch.spinning_thread = threading.get_ident()
    watch.start()
    try:
        spin_until(executor, lambda: watch.worst_lag > 0.0, 10.0, "the first probe")
        assert lines.warnings == []  # an executor that keeps up says nothing
        timer = node.create_timer(0.01, stuck_callback)
        releaser = threading.Thread(target=lambda: (held.wait(10.0), wait_until(lambda: bool(lines.warnings),
                                                    10.0, "the warning"), release.set()))
        releaser.start()
        spin_until(executor, lambda: bool(lines.infos), 15.0, "the watch's catch-up line")
        node.destroy_timer(timer)
        releaser.join(10.0)
        assert watch.stalls == 1 and len(lines.warnings) == 1, lines.warnings
        assert "the executor is" in lines.warnings[0] and "behind" in lines.warnings[0]
        assert "stuck_callback" in lines.warnings[0], lines.warnings[0]  # the stack names the callback
        assert lines.infos[0].startswith("watched: the executor caught up after")
    finally:
        release.set()
        watch.stop()
        executor.shutdown()
        node.destroy_node()

