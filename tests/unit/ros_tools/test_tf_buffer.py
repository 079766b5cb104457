"""The transform buffer answers lookups the way tf2 does."""

from __future__ import annotations

import math

import pytest

from ros_tools.tf import ConnectivityError, ExtrapolationError, Transform, TransformBuffer, interpolate


def close(a: Transform, b: Transform, tol: float = 1e-9) -> bool:
    same_rotation = abs(abs(a.qx * b.qx + a.qy * b.qy + a.qz * b.qz + a.qw * b.qw) - 1.0) < tol
    return abs(a.x - b.x) < tol and abs(a.y - b.y) < tol and abs(a.z - b.z) < tol and same_rotation


def test_compose_then_inverse_is_identity():
    a = Transform.from_xy_yaw(1.0, 2.0, 0.7, z=0.3)
    b = Transform.from_xy_yaw(-0.5, 0.25, -2.0)
    assert close((a * b) * (a * b).inverse(), Transform())
    px, py, _ = (a * b).apply(1.0, 0.0)
    qx, qy, _ = a.apply(*b.apply(1.0, 0.0))
    assert math.isclose(px, qx) and math.isclose(py, qy)


def test_planar_yaw_and_apply():
    t = Transform.from_xy_yaw(1.0, 0.0, math.pi / 2)
    assert math.isclose(t.yaw, math.pi / 2)
    x, y, _ = t.apply(1.0, 0.0)
    assert math.isclose(x, 1.0, abs_tol=1e-12) and math.isclose(y, 1.0)


def test_chain_lookup_map_to_scan():
    buf = TransformBuffer()
    buf.set_transform("map", "odom", 10.0, Transform.from_xy_yaw(1.0, 0.0, 0.0))
    buf.set_transform("odom", "base_footprint", 10.0, Transform.from_xy_yaw(2.0, 0.0, math.pi / 2))
    buf.set_transform("base_footprint", "base_link", 0.0, Transform(z=0.01), static=True)
    buf.set_transform("base_link", "base_scan", 0.0, Transform(x=-0.064, z=0.122), static=True)
    t = buf.lookup("map", "base_scan")
    assert math.isclose(t.x, 3.0, abs_tol=1e-12)
    assert math.isclose(t.y, -0.064)
    assert math.isclose(t.z, 0.132)
    # And the other way round, between siblings' subtrees.
    back = buf.lookup("base_scan", "map")
    assert close(back, t.inverse())


def test_interpolates_between_stamps():
    buf = TransformBuffer()
    buf.set_transform("odom", "base", 1.0, Transform.from_xy_yaw(0.0, 0.0, 0.0))
    buf.set_transform("odom", "base", 2.0, Transform.from_xy_yaw(1.0, 0.0, 1.0))
    t = buf.lookup("odom", "base", 1.25)
    assert math.isclose(t.x, 0.25)
    assert math.isclose(t.yaw, 0.25)
    assert close(interpolate(Transform(), Transform.from_xy_yaw(0, 0, 1.0), 0.5),
                 Transform.from_xy_yaw(0, 0, 0.5))


def test_latest_common_time_uses_the_oldest_newest_stamp():
    buf = TransformBuffer()
    buf.set_transform("map", "odom", 1.0, Transform.from_xy_yaw(0.0, 0.0, 0.0))
    buf.set_transform("map", "odom", 3.0, Transform.from_xy_yaw(2.0, 0.0, 0.0))
    buf.set_transform("odom", "base", 1.0, Transform())
    buf.set_transform("odom", "base", 2.0, Transform())
    assert math.isclose(buf.lookup("map", "base").x, 1.0)  # at t = 2, where both are known


def test_extrapolation_errors_name_the_frames():
    buf = TransformBuffer()
    buf.set_transform("odom", "base", 1.0, Transform())
    buf.set_transform("odom", "base", 2.0, Transform())
    with pytest.raises(ExtrapolationError, match=r"future.*\[base\] to frame \[odom\]"):
        buf.lookup("odom", "base", 2.5)
    with pytest.raises(ExtrapolationError, match="past"):
        buf.lookup("odom", "base", 0.5)


def test_unknown_and_disconnected_frames():
    buf = TransformBuffer()
    buf.set_transform("map", "odom", 1.0, Transform())
    buf.set_transform("world", "other", 1.0, Transform())
    with pytest.raises(ConnectivityError, match=r"frame \[nowhere\] does not exist"):
        buf.lookup("map", "nowhere")
    with pytest.raises(ConnectivityError, match="not part of the same tree"):
        buf.lookup("map", "other")


def test_cache_drops_old_history_and_reparenting_replaces_edge():
    buf = TransformBuffer(cache_time=1.0)
    for i in range(50):
        buf.set_transform("odom", "base", i * 0.1, Transform(x=float(i)))
    with pytest.raises(ExtrapolationError):
        buf.lookup("odom", "base", 0.5)
    buf.set_transform("map", "base", 10.0, Transform(x=7.0))
    assert buf.frames()["base"] == "map"
    assert buf.lookup("map", "base").x == 7.0


def test_clear_keeps_static_transforms():
    buf = TransformBuffer()
    buf.set_transform("base", "scan", 0.0, Transform(x=1.0), static=True)
    buf.set_transform("odom", "base", 5.0, Transform())
    buf.clear()
    assert buf.lookup("base", "scan").x == 1.0
    assert not buf.can_transform("odom", "scan")


def test_a_stamp_within_a_nanosecond_of_either_end_is_that_transform():
    """Float seconds from a builtin Time can land a hair past the newest (or before the oldest) stamp;
    tf2 compares nanoseconds, so such a lookup is the stored transform, not an error."""
    buf = TransformBuffer()
    buf.set_transform("odom", "base_footprint", 100.0, Transform.from_xy_yaw(1.0, 0.0, 0.0))
    buf.set_transform("odom", "base_footprint", 100.2, Transform.from_xy_yaw(2.0, 0.0, 0.0))
    assert math.isclose(buf.lookup("odom", "base_footprint", 100.2 + 5e-10).x, 2.0)
    assert math.isclose(buf.lookup("odom", "base_footprint", 100.0 - 5e-10).x, 1.0)
    assert math.isclose(buf.lookup("odom", "base_footprint", 100.1).x, 1.5)
    with pytest.raises(ExtrapolationError):
        buf.lookup("odom", "base_footprint", 100.2 + 1e-6)
