"""Angle, quaternion, path and frame helpers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.geometry import (
    Pose2D,
    angle_diff,
    angle_diffs,
    compose,
    cumulative_lengths,
    from_frame,
    headings_along,
    nearest_index,
    normalize_angle,
    normalize_angles,
    path_length,
    quaternion_from_yaw,
    to_frame,
    yaw_from_quaternion,
    yaw_or_nan,
)


def test_angles_wrap_to_minus_pi_pi() -> None:
    assert normalize_angle(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    assert normalize_angle(-7.0) == pytest.approx(-7.0 + 2 * math.pi)
    assert angle_diff(-3.0, 3.0) == pytest.approx(2 * math.pi - 6.0)
    assert np.allclose(
        normalize_angles(np.array([0.0, 4.0, -4.0])), [0.0, 4.0 - 2 * math.pi, 2 * math.pi - 4.0]
    )


def test_angle_diffs_is_angle_diff_element_wise() -> None:
    """The array form (MPPI's critics, AMCL) agrees with the scalar one, a scalar on either side."""
    to = np.array([-3.0, 0.5, 3.0, math.pi, -math.pi])
    frm = np.array([3.0, -0.5, -3.0, 0.0, 0.0])
    expected = [angle_diff(float(a), float(b)) for a, b in zip(to, frm, strict=True)]
    assert angle_diffs(to, frm).tolist() == expected
    assert angle_diffs(to, 0.25).tolist() == [angle_diff(float(a), 0.25) for a in to]
    assert angle_diffs(0.25, frm).tolist() == [angle_diff(0.25, float(b)) for b in frm]
    assert angle_diffs(to, frm)[0] == pytest.approx(2 * math.pi - 6.0)


@pytest.mark.parametrize("yaw", [0.0, 1.0, -2.5, math.pi - 1e-6])
def test_quaternion_round_trip(yaw: float) -> None:
    assert yaw_from_quaternion(*quaternion_from_yaw(yaw)) == pytest.approx(yaw)
    x, y, z, w = quaternion_from_yaw(yaw)
    assert yaw_from_quaternion(2 * x, 2 * y, 2 * z, 2 * w) == pytest.approx(yaw)  # unnormalised input


def test_bad_quaternions_are_refused() -> None:
    with pytest.raises(ValueError, match="NaN"):
        yaw_from_quaternion(0.0, 0.0, math.nan, 1.0)
    with pytest.raises(ValueError, match="zero norm"):
        yaw_from_quaternion(0.0, 0.0, 0.0, 0.0)
    assert math.isnan(yaw_or_nan(0.0, 0.0, 0.0, 0.0))


def test_path_measures() -> None:
    pts = np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]])
    assert path_length(pts) == pytest.approx(6.0)
    assert np.allclose(cumulative_lengths(pts), [0.0, 5.0, 6.0])
    assert nearest_index(pts, 3.1, 4.6) == 2
    assert nearest_index(pts, 0.0, 0.0, start=1) == 1
    assert np.allclose(headings_along(pts), [math.atan2(4, 3), math.pi / 2, math.pi / 2])


def test_frames_round_trip() -> None:
    frame = Pose2D(1.0, 2.0, math.pi / 2)
    poses = np.array([[2.0, 2.0, 0.0], [1.0, 3.0, 1.0]])
    local = to_frame(poses, frame)
    assert np.allclose(local[0], [0.0, -1.0, -math.pi / 2])
    assert np.allclose(from_frame(local, frame), poses)
    assert compose(frame, Pose2D(0.0, -1.0, -math.pi / 2)) == pytest.approx((2.0, 2.0, 0.0))
