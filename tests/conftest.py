"""Test-session setup shared by every test.

* DDS stays on this machine: ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST unless the user chose a range.
* Every test session gets its own ROS_DOMAIN_ID (derived from the process id, or taken from
  NAVSUITE_TEST_DOMAIN_ID), so parallel runs, CI and a running demo never see each other.
  Child processes started by tests inherit both variables.
* The ``ros_context`` fixture gives each rclpy test its own context, shut down in ``finally``.
"""

from __future__ import annotations

import os
from collections.abc import Iterator

import pytest

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
if "NAVSUITE_TEST_DOMAIN_ID" in os.environ:
    os.environ["ROS_DOMAIN_ID"] = os.environ["NAVSUITE_TEST_DOMAIN_ID"]
else:
    # Domain ids 1..100 are valid for Fast DDS with the default port mapping; 0 is left to users.
    os.environ["ROS_DOMAIN_ID"] = str(1 + os.getpid() % 100)


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
