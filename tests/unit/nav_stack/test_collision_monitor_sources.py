"""collision_monitor's data and approach model (Nav2 Jazzy): scan → points, a synthetic point cloud
through its height window, the source timeout, the base shift correction, and the approach speed
for hand-made cases."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.collision_monitor import (
    NO_COLLISION,
    ActionType,
    PolygonParams,
    Rigid,
    Velocity,
    Zone,
    collision_time,
    decide,
    rigid_from_quaternion,
    scan_points,
    shift_corrected,
    source_valid,
    within_height,
)

FOOTPRINT = "[[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]]"


def planar(x: float, y: float, yaw: float, z: float = 0.0) -> Rigid:
    return rigid_from_quaternion(x, y, z, 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def approach_zone(points: str = FOOTPRINT, **fields: float) -> Zone:
    return Zone("FootprintApproach", PolygonParams(type="polygon", action_type="approach", points=points,
                                                   min_points=1, **fields))  # type: ignore[arg-type]


# -- sources -------------------------------------------------------------------------------------
def test_scan_returns_within_the_range_limits_become_points_at_their_beam_angle() -> None:
    ranges = [1.0, math.inf, math.nan, 0.05, 2.0, 3.5, 3.6, -math.inf]
    pts = scan_points(ranges, angle_min=0.0, angle_increment=math.pi / 4, range_min=0.12, range_max=3.5)
    expected = [(1.0, 0.0, 0.0),
                (2.0 * math.cos(math.pi), 2.0 * math.sin(math.pi), 0.0),
                (3.5 * math.cos(5 * math.pi / 4), 3.5 * math.sin(5 * math.pi / 4), 0.0)]
    assert pts == pytest.approx(np.array(expected))  # inf, NaN, below range_min, above range_max: gone


def test_a_synthetic_point_cloud_keeps_the_points_within_the_height_window_in_the_base_frame() -> None:
    sensor_in_base = planar(0.1, 0.0, math.pi / 2, z=0.3)  # 0.3 m up, looking left
    cloud = np.array([[1.0, 0.0, -0.28],  # base z 0.02: floor, below min_height 0.05
                      [1.0, 0.0, 0.0],  # base z 0.3: kept
                      [2.0, 0.5, 0.19],  # base z 0.49: kept
                      [1.0, 0.0, 0.3]])  # base z 0.6: above max_height 0.5
    kept = within_height(sensor_in_base.apply(cloud), 0.05, 0.5)
    assert kept == pytest.approx(np.array([[0.1, 1.0], [-0.4, 2.0]]))


def test_a_source_older_than_its_timeout_is_invalid_and_a_zero_timeout_never_expires() -> None:
    assert source_valid(10.0, 12.0, 2.0)
    assert not source_valid(10.0, 12.01, 2.0)
    now = 102_050_000_000 * 1e-9  # the node clock's ns as s, as the node computes it
    assert now - 100.05 > 2.0  # float seconds: exactly the timeout looks older (Nav2 stops on age > timeout)
    assert source_valid(100.05, now, 2.0)
    assert not source_valid(100.05, now + 1e-9, 2.0)
    assert source_valid(10.0, 1000.0, 0.0)


def test_base_shift_correction_moves_old_data_by_the_robots_motion_since_its_stamp() -> None:
    scan_in_base = planar(-0.064, 0.0, 0.0, z=0.122)  # the waffle's base_scan mount
    obstacle_in_scan = np.array([[0.5, 0.0, 0.0]])
    robot_then, robot_now = planar(1.0, 2.0, 0.0), planar(1.1, 2.0, 0.0)  # 0.1 m forward since the stamp
    corrected = shift_corrected(robot_then @ scan_in_base, robot_now).apply(obstacle_in_scan)
    assert corrected[0, :2] == pytest.approx([0.336, 0.0])  # 0.436 m ahead at the stamp, 0.336 now
    assert scan_in_base.apply(obstacle_in_scan)[0, 0] == pytest.approx(0.436)  # uncorrected: stale
    turned = shift_corrected(robot_then @ scan_in_base, planar(1.0, 2.0, math.pi / 2))
    assert turned.apply(obstacle_in_scan)[0, :2] == pytest.approx([0.0, -0.436])  # now on the right


def test_rigid_transforms_compose_and_invert() -> None:
    a, b = planar(1.0, 0.0, math.pi / 2), planar(0.0, 2.0, -math.pi / 4, z=0.5)
    p = np.array([[0.3, -0.2, 0.1]])
    assert (a @ b).apply(p) == pytest.approx(a.apply(b.apply(p)))
    assert (a.inverse() @ a).apply(p) == pytest.approx(p)
    with pytest.raises(ValueError, match="cannot be normalised"):
        rigid_from_quaternion(0, 0, 0, 0, 0, 0, 0)


# -- approach ------------------------------------------------------------------------------------
def test_approach_slows_so_the_first_contact_is_time_before_collision_away() -> None:
    # Footprint front at x = 0.2, obstacle at 0.57: contact after 0.37 m, 0.74 s at 0.5 m/s. The
    # simulation (0.1 s steps) first finds it inside after 8 steps (0.4 m) and reports the time
    # before that step, 0.7 s; the command is scaled by 0.7 / 1.2.
    zone = approach_zone(time_before_collision=1.2, simulation_time_step=0.1)
    obstacle = np.array([[0.57, 0.0]])
    assert collision_time(zone, obstacle, (0.5, 0.0, 0.0)) == pytest.approx(0.7)
    action = decide(Velocity(0.5, 0.0, 0.0), [zone], {"scan": obstacle})
    assert action.action_type == ActionType.APPROACH and action.polygon_name == "FootprintApproach"
    assert action.velocity == pytest.approx((0.5 * 0.7 / 1.2, 0.0, 0.0))
    assert 0.37 / action.velocity.x >= 1.2  # at the new speed the contact is at least 1.2 s away
    # At that speed the simulation needs 1.2 s or more: the output is a fixed point of the model.
    assert collision_time(zone, obstacle, (action.velocity.x, 0.0, 0.0)) >= 1.1


def test_approach_sees_a_turn_on_the_spot_sweep_the_footprint_into_a_point() -> None:
    long_body = "[[0.5, 0.1], [0.5, -0.1], [-0.5, -0.1], [-0.5, 0.1]]"
    zone = approach_zone(long_body)  # time_before_collision 2.0 (Nav2's default)
    beside = np.array([[0.3, 0.3]])  # 45° left, 0.424 m out: inside once turned by more than 0.548 rad
    assert collision_time(zone, beside, (0.0, 0.0, 1.0)) == pytest.approx(0.5)
    action = decide(Velocity(0.0, 0.0, 1.0), [zone], {"scan": beside})
    assert action.velocity == pytest.approx((0.0, 0.0, 0.25))
    assert collision_time(zone, beside, (0.0, 0.0, -1.0)) == NO_COLLISION  # turning away: not within 2 s


def test_approach_stops_on_data_already_inside_and_ignores_data_out_of_reach() -> None:
    zone = approach_zone(time_before_collision=1.0)
    inside = np.array([[0.1, 0.0]])
    assert collision_time(zone, inside, (-0.3, 0.0, 0.0)) == 0.0  # Nav2: even when backing away
    assert decide(Velocity(-0.3, 0.0, 0.0), [zone], {"scan": inside}).velocity == (0.0, 0.0, 0.0)
    far = np.array([[1.5, 0.0], [-0.5, 0.0]])
    assert collision_time(zone, far, (0.5, 0.0, 0.0)) == NO_COLLISION  # 1.3 m needs 2.6 s > 1 s
    assert collision_time(zone, far, (0.0, 0.0, 0.0)) == NO_COLLISION
    assert decide(Velocity(0.5, 0.0, 0.0), [zone], {"scan": far}).action_type == ActionType.DO_NOTHING
