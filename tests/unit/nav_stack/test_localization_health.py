"""Localization health (nav_stack/core/localization/health.py): the evidence of one update, the causes
it names with their numbers, and the OK / DEGRADED hysteresis over consecutive updates."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.grid import GridSpec
from nav_stack.core.localization import Amcl, AmclParams
from nav_stack.core.localization.health import (
    HealthMonitor,
    HealthParams,
    HealthSample,
    LocalizationState,
    measure,
    position_std,
    problems,
)
from nav_stack.core.localization.params import BEAM
from nav_stack.core.localization.sensor_model import DistanceField, select_beams
from navsuite_testing.nav.fake_lidar import clutter_world, fake_scan

POSE = (0.3, -0.4, 0.2)
TIGHT = np.diag([0.01, 0.01, 0.005])  # σ 0.1 m, 0.07 rad
PARAMS = HealthParams()


def _sample(returns: int = 55, on_walls: int = 55, position: float = 0.1, yaw: float = 0.1) -> HealthSample:
    return HealthSample(60, returns, on_walls, 3.5, position, yaw)


GOOD, FEW_BEAMS = _sample(), _sample(returns=4, on_walls=4)


def _measure_at(pose: tuple[float, float, float], scan: LaserScan) -> HealthSample:
    grid, spec = clutter_world()
    beams = select_beams(scan, (0.0, 0.0, 0.0), AmclParams())
    return measure(DistanceField(grid, spec, 2.0), beams, pose, TIGHT, PARAMS.match_distance)


def test_at_the_true_pose_every_return_ends_on_a_wall() -> None:
    grid, spec = clutter_world()
    scan = fake_scan(grid, spec, POSE)
    sample = _measure_at(POSE, scan)
    assert sample.beams == 60
    assert sample.returns == int(np.count_nonzero(scan.ranges[::6] < 3.5)) > 40
    assert sample.on_walls == sample.returns
    assert (sample.position_std, sample.yaw_std) == pytest.approx((0.1, math.sqrt(0.005)))
    assert problems(sample, PARAMS) == []


def test_a_wrong_pose_puts_returns_in_free_space_and_is_named_with_the_share() -> None:
    grid, spec = clutter_world()
    sample = _measure_at((POSE[0] + 0.6, POSE[1] - 0.4, POSE[2] + 0.3), fake_scan(grid, spec, POSE))
    assert sample.matched_ratio < PARAMS.min_matched_ratio
    [cause] = problems(sample, PARAMS)
    assert cause == (f"scan disagrees with the map: {100 * sample.matched_ratio:.0f} % of returns on walls "
                     "(< 50 %)")


def test_a_scan_that_returns_almost_nothing_names_few_beams_with_its_numbers() -> None:
    ranges = np.full(360, np.inf)
    ranges[:24] = 1.0  # a few returns (from nowhere near a wall: agreement is not judged on 4 beams)
    sample = _measure_at(POSE, LaserScan(ranges, 0.0, 2 * math.pi / 360, 0.12, 3.5))
    assert (sample.beams, sample.returns) == (60, 4)
    assert problems(sample, PARAMS) == ["few beams on walls: 4 of 60 beams returned within 3.5 m (< 20 %)"]


def test_a_spread_cloud_names_position_and_yaw_sigma_against_their_limits() -> None:
    assert problems(_sample(position=0.62, yaw=0.5), PARAMS) == [
        "particles spread: position σ 0.62 m > 0.50 m, yaw σ 0.50 rad > 0.35 rad"]
    assert problems(_sample(returns=4, on_walls=4, yaw=0.4), PARAMS) == [
        "few beams on walls: 4 of 60 beams returned within 3.5 m (< 20 %)",
        "particles spread: yaw σ 0.40 rad > 0.35 rad"]


def test_position_sigma_is_taken_along_the_widest_axis() -> None:
    c, s = math.cos(0.7), math.sin(0.7)
    rotation = np.array([[c, -s], [s, c]])
    covariance = np.zeros((3, 3))
    covariance[:2, :2] = rotation @ np.diag([0.64, 0.01]) @ rotation.T
    assert position_std(covariance) == pytest.approx(0.8)


def test_max_range_readings_the_beam_model_keeps_are_not_returns() -> None:
    grid, spec = clutter_world()
    scan = fake_scan(grid, spec, POSE)
    ranges = np.where(np.arange(360) % 2 == 0, 3.5, scan.ranges)  # every other reading at range_max
    beams = select_beams(LaserScan(ranges, 0.0, scan.angle_increment, 0.12, 3.5), (0.0, 0.0, 0.0),
                         AmclParams(laser_model_type=BEAM), keep_max=True)
    sample = measure(DistanceField(grid, spec, 2.0), beams, POSE, TIGHT, PARAMS.match_distance)
    assert sample.beams == beams.ranges.size == 60
    assert sample.returns == int(np.count_nonzero(beams.ranges < 3.5)) < 60
    assert sample.on_walls == sample.returns


def test_monitor_degrades_after_k_bad_updates_and_recovers_after_k_good_ones() -> None:
    monitor = HealthMonitor(HealthParams(bad_updates_to_degrade=3, good_updates_to_recover=2))
    assert [monitor.update(FEW_BEAMS) for _ in range(3)] == [False, False, True]
    assert monitor.state is LocalizationState.DEGRADED
    assert monitor.cause == "few beams on walls: 4 of 60 beams returned within 3.5 m (< 20 %)"
    assert [monitor.update(GOOD) for _ in range(2)] == [False, True]
    assert (monitor.state, monitor.cause) == (LocalizationState.OK, "")


def test_one_good_update_breaks_the_streak_of_bad_ones() -> None:
    monitor = HealthMonitor(HealthParams(bad_updates_to_degrade=3))
    for sample in (FEW_BEAMS, FEW_BEAMS, GOOD, FEW_BEAMS, FEW_BEAMS):
        assert not monitor.update(sample)
    assert monitor.state is LocalizationState.OK


def test_while_degraded_the_cause_follows_the_latest_bad_update() -> None:
    monitor = HealthMonitor(HealthParams(bad_updates_to_degrade=1))
    monitor.update(FEW_BEAMS)
    monitor.update(_sample(position=0.7))
    assert monitor.cause == "particles spread: position σ 0.70 m > 0.50 m"
    monitor.update(GOOD)  # one good update is not yet a recovery: the last cause stays
    assert (monitor.state, monitor.cause) == (LocalizationState.DEGRADED,
                                              "particles spread: position σ 0.70 m > 0.50 m")


def test_reset_starts_over_as_ok() -> None:
    monitor = HealthMonitor(HealthParams(bad_updates_to_degrade=1))
    monitor.update(FEW_BEAMS)
    monitor.reset()
    assert (monitor.state, monitor.cause, monitor.sample) == (LocalizationState.OK, "", None)


@pytest.mark.parametrize(("field", "value"), [("min_valid_beams_ratio", 1.5), ("max_position_std", 0.0),
                                              ("bad_updates_to_degrade", 0), ("max_yaw_std", math.nan)])
def test_invalid_thresholds_name_the_field_and_value(field: str, value: float) -> None:
    with pytest.raises(ValueError, match=rf"HealthParams\.{field} must .*, got {value}"):
        HealthParams(**{field: value})  # type: ignore[arg-type]


def _drive(grid: np.ndarray, spec: GridSpec, start: tuple[float, float], metres: float) -> HealthMonitor:
    """The core filter, started on the truth, driven east ``metres`` with one health check per update."""
    amcl = Amcl(AmclParams(max_particles=500, min_particles=200), grid, spec, np.random.default_rng(1))
    amcl.set_initial_pose(start[0], start[1], 0.0, np.diag([0.01, 0.01, 0.005]))
    monitor = HealthMonitor(PARAMS)
    rng = np.random.default_rng(2)
    for step in range(round(metres / 0.05) + 1):
        x = start[0] + 0.05 * step
        if amcl.update((0.05 * step, 0.0, 0.0), fake_scan(grid, spec, (x, start[1], 0.0), noise_std=0.01,
                                                          rng=rng)).updated:
            est = amcl.estimate()
            assert amcl.last_beams is not None
            monitor.update(measure(amcl.distance_field, amcl.last_beams, (est.x, est.y, est.yaw),
                                   est.covariance, PARAMS.match_distance))
    return monitor


def test_the_filter_in_a_walled_room_stays_ok() -> None:
    grid, spec = clutter_world()
    monitor = _drive(grid, spec, (-2.0, 2.4), 3.0)
    assert monitor.state is LocalizationState.OK
    assert monitor.sample is not None and monitor.sample.returns > 40


def test_the_filter_in_open_space_degrades_and_says_few_beams() -> None:
    spec = GridSpec(400, 200, 0.05, -10.0, -5.0)  # 20 m x 10 m, walls only at the border
    grid = np.zeros(spec.shape, dtype=np.int8)
    grid[[0, -1], :] = grid[:, [0, -1]] = 100
    monitor = _drive(grid, spec, (-5.0, 0.0), 3.0)
    assert monitor.state is LocalizationState.DEGRADED
    assert monitor.cause.startswith("few beams on walls: 0 of 60 beams returned within 3.5 m")
