"""Fixtures shared by integration tests: live nodes spun in a background thread, and ros2py CLI runners.

The CLI runs as a child process (``python -m navsuite_tools.cli.main``) that inherits the test's
ROS_DOMAIN_ID, exactly as a user's shell would run ``ros2py``; one-shot runs are
tests/helpers/ros_cli.py's ``run_cli``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import pytest

from navsuite_testing.ros import BackgroundSpin, start_python
from tests.helpers.ros_cli import CLI
from tests.helpers.streaming_cli import StreamingCli


@pytest.fixture
def stream_cli() -> Iterator[Callable[..., StreamingCli]]:
    """Start streaming CLI runs; any still running at the end are killed."""
    started: list[StreamingCli] = []

    def start(*args: str) -> StreamingCli:
        run = StreamingCli(start_python(CLI, args))
        started.append(run)
        return run

    yield start
    for run in started:
        if run.proc.poll() is None:
            run.proc.kill()
            run.proc.wait()


@pytest.fixture
def spinning(ros_context) -> Iterator[Callable[[str], object]]:
    """Create nodes on the test's context, spun by a MultiThreadedExecutor in a background thread."""
    import rclpy
    from rclpy.executors import MultiThreadedExecutor

    executor = MultiThreadedExecutor(context=ros_context)
    nodes = []

    def make_node(name: str, **kwargs: object) -> object:
        node = rclpy.create_node(name, context=ros_context, **kwargs)
        nodes.append(node)
        executor.add_node(node)
        return node

    spin = BackgroundSpin(executor, "cli peers")
    try:
        yield make_node
    finally:
        spin.stop(*nodes)
