"""Fixtures for smacc_py integration tests: a machine on the real runtime against FakeNav2."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import pytest

pytest.importorskip("smacc2_msgs.msg", reason="smacc2_msgs is not built (run the interface build)")
pytest.importorskip("nav2_msgs.action", reason="nav2_msgs is not built (run the interface build)")

from rclpy.parameter import Parameter

from smacc_py.ros.runtime import SmaccRuntime
from tests.helpers.smacc_ros_fake_nav2 import FakeNav2

StackFactory = Callable[..., tuple[FakeNav2, SmaccRuntime]]


@pytest.fixture
def stack(ros_context: Any) -> Iterator[StackFactory]:
    """``stack(SmType, scripts=..., bond_nodes=..., clock_rate=..., frozen=..., params={...})`` starts a
    FakeNav2 and the machine (use_sim_time, on the fake's /clock); both are torn down afterwards."""
    created: list[tuple[FakeNav2, SmaccRuntime]] = []

    def make(
        sm_type: type, *, params: dict[str, Any] | None = None, **fake_kwargs: Any
    ) -> tuple[FakeNav2, SmaccRuntime]:
        fake = FakeNav2(ros_context, **fake_kwargs).start()
        overrides = [Parameter("use_sim_time", value=True)]
        overrides += [Parameter(name, value=value) for name, value in (params or {}).items()]
        try:
            runtime = SmaccRuntime(sm_type, context=ros_context, parameter_overrides=overrides)
        except Exception:
            fake.stop()
            raise
        created.append((fake, runtime))
        runtime.spin_in_background()
        runtime.start()
        return fake, runtime

    try:
        yield make
    finally:
        for fake, runtime in reversed(created):
            try:
                runtime.shutdown()
            finally:
                fake.stop()


def transition_keys(runtime: SmaccRuntime) -> list[tuple[str, str, str]]:
    """(source, target, tag) of every transition taken so far."""
    return [record.key() for record in list(runtime.sm.transition_log)]
