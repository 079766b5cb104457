"""AMCL's likelihood_field_prob model (Nav2's LikelihoodFieldModelProb) and its beam skipping.

The reference below is a plain loop over particles and beam slots written from Nav2's description
(nav2_amcl/src/sensors/laser/likelihood_field_model_prob.cpp), with its own brute-force distance map,
so the vectorised model is checked against something that shares none of its code.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.grid import GridSpec
from nav_stack.core.localization import Amcl, AmclParams
from nav_stack.core.localization.likelihood_field_prob import LikelihoodFieldProbModel
from nav_stack.core.localization.params import LIKELIHOOD_FIELD, LIKELIHOOD_FIELD_PROB
from nav_stack.core.localization.sensor_model import select_beams
from navsuite_testing.nav.fake_lidar import cast_ranges, fake_scan

PROB = AmclParams(laser_model_type=LIKELIHOOD_FIELD_PROB, do_beamskip=True)
Pose = tuple[float, float, float]


def small_room() -> tuple[np.ndarray, GridSpec]:
    """A 3 m × 2 m walled room with two boxes, origin off (0, 0) so frame mistakes show."""
    spec = GridSpec(60, 40, 0.05, -1.3, -0.7)
    gy, gx = np.mgrid[0:spec.height, 0:spec.width]
    wx, wy = spec.cell_to_world(gx, gy)
    grid = np.zeros(spec.shape, dtype=np.int8)
    grid[(wx < -1.2) | (wx > 1.6) | (wy < -0.6) | (wy > 1.2)] = 100
    grid[(np.abs(wx - 0.9) < 0.12) & (np.abs(wy - 0.7) < 0.2)] = 100
    grid[(np.abs(wx + 0.7) < 0.1) & (np.abs(wy + 0.2) < 0.1)] = 100
    return grid, spec


def reference_log_weights(grid: np.ndarray, spec: GridSpec, params: AmclParams, scan: LaserScan, laser: Pose,
                          particles: np.ndarray, converged: bool) -> tuple[list[float], list[bool]]:
    """Σ log pz per particle and, per valid beam, whether it was integrated: Nav2's loops, one by one."""
    occupied = np.argwhere(grid == 100)  # (row, col)
    max_dist = params.laser_likelihood_max_dist

    def occ_dist(mi: int, mj: int) -> float:
        d = np.hypot(occupied[:, 1] - mi, occupied[:, 0] - mj).min() * spec.resolution
        return float(min(d, max_dist))

    range_max = min(scan.range_max, params.laser_max_range)
    ranges = [range_max if r <= scan.range_min else float(r) for r in scan.ranges]
    step = max(1, math.ceil(len(ranges) / params.max_beams))
    denom = 2.0 * params.sigma_hit**2
    z_rand = params.z_rand / range_max
    do_skip = params.do_beamskip and converged
    obs_count = [0] * params.max_beams
    valid = [False] * params.max_beams
    pzs = [[0.0] * params.max_beams for _ in particles]
    for j, (px, py, pyaw) in enumerate(particles):
        lx = px + math.cos(pyaw) * laser[0] - math.sin(pyaw) * laser[1]
        ly = py + math.sin(pyaw) * laser[0] + math.cos(pyaw) * laser[1]
        for slot, i in enumerate(range(0, len(ranges), step)):
            r = ranges[i]
            if math.isnan(r) or r >= range_max:
                continue
            valid[slot] = True
            bearing = pyaw + laser[2] + scan.angle_min + i * scan.angle_increment
            hx, hy = lx + r * math.cos(bearing), ly + r * math.sin(bearing)
            mi = math.floor((hx - spec.origin_x) / spec.resolution)
            mj = math.floor((hy - spec.origin_y) / spec.resolution)
            if 0 <= mi < spec.width and 0 <= mj < spec.height:
                z = occ_dist(mi, mj)
                if z < params.beam_skip_distance:
                    obs_count[slot] += 1
            else:
                z = max_dist
            pzs[j][slot] = params.z_hit * math.exp(-z * z / denom) + z_rand
    keep = [not do_skip or obs_count[b] / len(particles) > params.beam_skip_threshold
            for b in range(params.max_beams)]
    skipped = sum(not k for k in keep)  # slots without a valid reading count as skipped, as in Nav2
    if skipped >= params.max_beams * params.beam_skip_error_threshold:
        keep = [True] * params.max_beams
    integrated = [k and v for k, v in zip(keep, valid, strict=True)]
    logs = [sum(math.log(pz[b]) for b in range(params.max_beams) if integrated[b]) for pz in pzs]
    return logs, [k for k, v in zip(integrated, valid, strict=True) if v]


def _normalised(log_w: np.ndarray) -> np.ndarray:
    w = np.exp(log_w - log_w.max())
    return w / w.sum()


@pytest.mark.parametrize(("overrides", "skips", "too_many"), [
    ({"do_beamskip": False}, False, False),
    ({"beam_skip_distance": 0.15}, True, False),
    ({"beam_skip_distance": 0.0}, False, True),  # nothing agrees
])
def test_vectorised_model_matches_a_per_particle_per_beam_loop(overrides: dict[str, object], skips: bool,
                                                               too_many: bool) -> None:
    grid, spec = small_room()
    params = replace(PROB, max_beams=30, sigma_hit=0.1, **overrides)  # type: ignore[arg-type]
    world = grid.copy()  # the room plus a box the map does not have
    world[18:22, 34:38] = 100
    rng = np.random.default_rng(4)
    truth, laser = (0.25, 0.1, 0.3), (-0.06, 0.02, 0.05)
    c, s = math.cos(truth[2]), math.sin(truth[2])
    sensor = (truth[0] + c * laser[0] - s * laser[1], truth[1] + s * laser[0] + c * laser[1],
              truth[2] + laser[2])
    scan = fake_scan(world, spec, sensor, beams=90, range_max=2.5, noise_std=0.01, rng=rng)
    scan.ranges[5] = np.nan
    scan.ranges[9] = 0.05  # below range_min
    particles = np.array(truth) + rng.normal(0.0, [0.03, 0.03, 0.02], (40, 3))
    particles[-5:] = np.column_stack([rng.uniform(-1.0, 1.4, 5), rng.uniform(-0.4, 1.0, 5),
                                      rng.uniform(-math.pi, math.pi, 5)])  # a few far off
    model = LikelihoodFieldProbModel(grid, spec, params)
    result = model.weigh(particles, select_beams(scan, laser, params), converged=True)
    expected, integrated = reference_log_weights(grid, spec, params, scan, laser, particles, converged=True)
    assert result.integrated.tolist() == integrated
    np.testing.assert_allclose(result.log_likelihood, expected, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(_normalised(result.log_likelihood), _normalised(np.array(expected)), atol=1e-9)
    assert (result.skipped_count > 0) == skips and result.too_many_skipped == too_many


def corridor() -> tuple[np.ndarray, GridSpec, np.ndarray, np.ndarray]:
    """A corridor 2 m wide along x, thin walls (unknown behind), its end wall 2 m ahead of x = 0 and
    nothing behind within range; with the world frame coordinates of every cell."""
    spec = GridSpec(180, 50, 0.05, -6.5, -1.25)
    gy, gx = np.mgrid[0:spec.height, 0:spec.width]
    wx, wy = spec.cell_to_world(gx, gy)
    grid = np.full(spec.shape, -1, dtype=np.int8)
    grid[(np.abs(wy) <= 1.0) & (wx <= 2.0)] = 0
    grid[(np.abs(wy) > 1.0) & (np.abs(wy) <= 1.1) & (wx <= 2.1)] = 100
    grid[(wx > 2.0) & (wx <= 2.1) & (np.abs(wy) <= 1.1)] = 100
    return grid, spec, wx, wy


def test_beams_on_an_unmapped_obstacle_are_skipped_and_the_true_pose_wins() -> None:
    """A box 1 m wide against the end wall, 0.3 m deep, not in the map: without skipping the pose
    0.3 m ahead (which puts its beams on the wall) beats the truth; skipping drops those beams."""
    grid, spec, wx, wy = corridor()
    world = grid.copy()
    world[(wx > 1.7) & (wx <= 2.0) & (np.abs(wy) < 0.5)] = 100
    truth, favoured = (0.0, 0.0, 0.0), (0.3, 0.0, 0.0)
    scan = fake_scan(world, spec, truth, range_max=3.5, noise_std=0.005, rng=np.random.default_rng(1))
    params = replace(PROB, max_beams=180, beam_skip_distance=0.25)  # the box face is 0.3 m off the wall
    beams = select_beams(scan, (0.0, 0.0, 0.0), params)
    rng = np.random.default_rng(2)
    cloud = np.array(truth) + rng.normal(0.0, [0.03, 0.03, 0.01], (300, 3))  # converged on the truth
    particles = np.vstack([[truth, favoured], cloud, np.tile(favoured, (20, 1))])
    model = LikelihoodFieldProbModel(grid, spec, params)

    plain = model.weigh(particles, beams, converged=False).log_likelihood
    assert plain[1] > plain[0] + 5.0  # the premise: the box favours the wrong pose
    result = model.weigh(particles, beams, converged=True)
    assert result.skipping and not result.too_many_skipped
    assert result.log_likelihood[0] > result.log_likelihood[1] + 5.0
    kept = scan.ranges[::2] < 3.5  # step ceil(360 / 180) = 2
    mapped = cast_ranges(grid, spec, truth, scan.angles[::2], 3.5)[kept]
    on_box = np.abs(beams.ranges - mapped) > 0.1  # the beams the box cut short
    assert 10 <= np.count_nonzero(on_box) <= 25
    assert np.array_equal(~result.integrated, on_box)


def test_when_most_beams_disagree_none_are_skipped() -> None:
    """A cloud converged on the wrong place: skipping would drop ≥ 90 % of the beams, so all count."""
    grid, spec = small_room()
    scan = fake_scan(grid, spec, (0.25, 0.1, 0.3), beams=360, range_max=3.5)
    params = replace(PROB, beam_skip_distance=0.1)
    beams = select_beams(scan, (0.0, 0.0, 0.0), params)
    rng = np.random.default_rng(3)
    wrong = np.array((0.6, 0.4, 2.0)) + rng.normal(0.0, [0.02, 0.02, 0.01], (100, 3))
    model = LikelihoodFieldProbModel(grid, spec, params)
    result = model.weigh(wrong, beams, converged=True)
    assert result.too_many_skipped and result.integrated.all()
    assert np.mean(result.agreement > params.beam_skip_threshold) < 0.1
    np.testing.assert_allclose(result.log_likelihood, model.log_likelihood(wrong, beams), rtol=1e-12)
    right = np.array((0.25, 0.1, 0.3)) + rng.normal(0.0, [0.02, 0.02, 0.01], (100, 3))
    assert not model.weigh(right, beams, converged=True).too_many_skipped


def test_slots_without_a_valid_reading_count_as_skipped_like_nav2() -> None:
    """10 valid beams of 60 slots, 6 agreeing: 54 slots count as skipped (≥ 0.9 · 60), so all 10 count."""
    spec = GridSpec(100, 100, 0.05, -2.5, -2.5)
    grid = np.zeros(spec.shape, dtype=np.int8)
    grid[50, 70] = 100  # one post 1 m ahead: (1.025, 0.025)
    ranges = np.full(60, np.inf)
    ranges[:10] = [1.02] * 6 + [2.0] * 4  # 6 beams end in the post cell, 4 in open space
    scan = LaserScan(ranges, 0.0, 1e-4, 0.1, 3.5)
    model = LikelihoodFieldProbModel(grid, spec, PROB)
    beams = select_beams(scan, (0.0, 0.0, 0.0), PROB)
    result = model.weigh(np.zeros((10, 3)), beams, converged=True)
    assert result.too_many_skipped and result.integrated_count == 10
    strict = replace(PROB, beam_skip_error_threshold=0.95)  # 54 < 57: the 4 open-space beams go
    result = LikelihoodFieldProbModel(grid, spec, strict).weigh(np.zeros((10, 3)), beams, converged=True)
    assert not result.too_many_skipped and result.integrated.tolist() == [True] * 6 + [False] * 4
    far = replace(PROB, beam_skip_distance=5.0)  # beyond laser_likelihood_max_dist: still, off the map
    off_map = np.tile([100.0, 0.0, 0.0], (10, 1))  # never agrees
    result = LikelihoodFieldProbModel(grid, spec, far).weigh(off_map, beams, converged=True)
    assert not result.agreement.any()


def test_no_skipping_before_the_filter_converges_and_nav2_beam_step() -> None:
    grid, spec = small_room()
    amcl = Amcl(replace(PROB, beam_skip_distance=0.02), grid, spec, np.random.default_rng(0))
    amcl.set_initial_pose(0.25, 0.1, 0.3)  # σ 0.5 m: not converged
    scan = fake_scan(grid, spec, (0.25, 0.1, 0.3), beams=361, range_max=3.5)
    amcl.update((0.0, 0.0, 0.0), scan)
    assert amcl.last_scan_weights is not None and not amcl.last_scan_weights.skipping
    assert amcl.last_beams is not None and amcl.last_beams.considered == 52  # step ceil(361 / 60) = 7
    plain = select_beams(scan, (0.0, 0.0, 0.0), replace(PROB, laser_model_type=LIKELIHOOD_FIELD))
    assert plain.considered == 61  # step 360 // 59 = 6
    amcl.set_initial_pose(0.25, 0.1, 0.3, np.diag([1e-4, 1e-4, 1e-4]))
    for _ in range(2):
        amcl.request_nomotion_update()
        amcl.update((0.0, 0.0, 0.0), scan)
    assert amcl.converged and amcl.last_scan_weights.skipping


def test_params_accept_the_model_and_check_the_beam_skip_fractions() -> None:
    assert AmclParams(laser_model_type=LIKELIHOOD_FIELD_PROB).laser_model_type == LIKELIHOOD_FIELD_PROB
    with pytest.raises(ValueError, match="beam_skip_threshold"):
        AmclParams(beam_skip_threshold=1.5)
    with pytest.raises(ValueError, match="beam_skip_error_threshold"):
        AmclParams(beam_skip_error_threshold=-0.1)
    with pytest.raises(ValueError, match="beam_skip_distance"):
        AmclParams(beam_skip_distance=-1.0)
