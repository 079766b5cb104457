"""AMCL core: motion model statistics, laser model, KLD, convergence and recovery (nav2_amcl semantics)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.grid import GridSpec
from nav_stack.core.localization import Amcl, AmclParams, map_to_odom
from nav_stack.core.localization.clusters import estimate_pose
from nav_stack.core.localization.kld import bin_keys, kld_limit, kld_sample_count
from nav_stack.core.localization.motion_model import sample_differential, sample_omni
from nav_stack.core.localization.params import BEAM
from nav_stack.core.localization.sensor_model import LikelihoodFieldModel, select_beams
from nav_stack.core.localization.weighting import FitAverages, reweight
from nav_stack.core.map_io import load_map
from navsuite_testing.nav.fake_lidar import clutter_world, corridor_world, fake_scan

TB3_MAP = Path(__file__).resolve().parents[3] / "maps" / "turtlebot3_world.yaml"
N = 200_000


def moved(
    old: tuple[float, float, float],
    new: tuple[float, float, float],
    alphas: tuple[float, ...],
    omni: bool = False,
) -> np.ndarray:
    particles = np.tile(np.array(old, dtype=np.float64), (N, 1))
    (sample_omni if omni else sample_differential)(particles, old, new, alphas, np.random.default_rng(0))
    return particles


@pytest.mark.parametrize(
    ("alphas", "new", "column", "variance"),
    [
        ((0.0, 0.0, 0.2, 0.0, 0.0), (1.0, 0.0, 0.0), 0, 0.2 * 1.0),  # α3: translation from translation
        ((0.1, 0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.5), 2, 0.1 * 0.25),  # α1: rotation from rotation
        ((0.0, 0.05, 0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 2, 2 * 0.05),  # α2: rot1 and rot2 from translation
        ((0.0, 0.0, 0.0, 0.3, 0.0), (0.0, 0.0, 0.5), 0, 0.3 * 0.25),  # α4: translation from rotation
    ],
)
def test_differential_noise_variances_follow_the_alphas(
    alphas: tuple[float, ...], new: tuple[float, float, float], column: int, variance: float
) -> None:
    p = moved((0.0, 0.0, 0.0), new, alphas)
    assert p[:, column].mean() == pytest.approx(new[column], abs=0.01)
    assert p[:, column].var() == pytest.approx(variance, rel=0.03)


def test_differential_mean_follows_odometry_in_the_particle_frame() -> None:
    p = moved((1.0, 2.0, math.pi / 2), (1.0, 2.3, math.pi / 2 + 0.1), (0.01, 0.01, 0.01, 0.01, 0.0))
    assert p[:, 0].mean() == pytest.approx(1.0, abs=0.005)
    assert p[:, 1].mean() == pytest.approx(2.3, abs=0.005)
    assert p[:, 2].mean() == pytest.approx(math.pi / 2 + 0.1, abs=0.005)


def test_reversing_is_folded_so_it_adds_no_rotation_noise() -> None:
    # Driving 0.5 m straight back: rot1 = π, rot2 = −π; folded to 0 they carry no α1 noise.
    p = moved((0.0, 0.0, 0.0), (-0.5, 0.0, 0.0), (0.5, 0.0, 0.0, 0.0, 0.0))
    assert np.allclose(p, [-0.5, 0.0, 0.0], atol=1e-9)


def test_omni_strafe_noise_uses_alpha5() -> None:
    p = moved((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0, 0.1), omni=True)
    assert p[:, 1].var() == pytest.approx(0.1, rel=0.03)
    assert p[:, 0].var() < 1e-12


def _one_obstacle_model(**overrides: object) -> tuple[LikelihoodFieldModel, GridSpec]:
    spec = GridSpec(40, 40, 0.05)
    occ = np.zeros(spec.shape, dtype=np.int8)
    occ[20, 30] = 100  # cell centre (1.525, 1.025)
    return LikelihoodFieldModel(occ, spec, AmclParams(**overrides)), spec  # type: ignore[arg-type]


def test_likelihood_field_is_the_product_of_the_beam_pz() -> None:
    model, _ = _one_obstacle_model()
    particles = np.array([[1.025, 1.025, 0.0], [1.025, 0.925, 0.0], [5.0, 5.0, 0.0]])
    one = select_beams(LaserScan(np.array([0.5]), 0.0, 0.1, 0.1, 4.0), (0.0, 0.0, 0.0), model.params)
    pz_hit = 0.5 + 0.5 / 4.0  # endpoint on the obstacle: d = 0
    pz_near = 0.5 * math.exp(-(0.1**2) / (2 * 0.2**2)) + 0.5 / 4.0  # 2 cells away
    pz_off = 0.5 * math.exp(-(2.0**2) / (2 * 0.2**2)) + 0.5 / 4.0  # off the map: max distance
    expected = np.log([pz_hit, pz_near, pz_off])
    assert model.log_likelihood(particles, one) == pytest.approx(expected, rel=1e-5)
    two = select_beams(LaserScan(np.array([0.5, 0.5]), 0.0, 0.0, 0.1, 4.0), (0.0, 0.0, 0.0), model.params)
    # Π pz (a sum of logs), not Nav2's 1 + Σ pz³
    assert model.log_likelihood(particles, two) == pytest.approx(2 * expected, rel=1e-5)


def test_likelihood_peaks_within_a_cell_of_the_truth_on_the_tb3_map() -> None:
    """Laser pose, beam angles and map frame agree: the scan fits best where it was taken."""
    loaded = load_map(TB3_MAP)
    model = LikelihoodFieldModel(loaded.data, loaded.spec, AmclParams(sigma_hit=0.05))
    laser = (-0.064, 0.0, 0.0)
    for truth in [(-2.0, -0.5, 0.0), (0.55, 1.6, 2.8), (1.65, 0.5, -1.6)]:
        c, s = math.cos(truth[2]), math.sin(truth[2])
        sensor = (truth[0] + c * laser[0], truth[1] + s * laser[0], truth[2])
        scan = fake_scan(loaded.data, loaded.spec, sensor)
        beams = select_beams(scan, laser, model.params)
        grid = np.stack(np.meshgrid(np.arange(-0.1, 0.101, 0.02), np.arange(-0.1, 0.101, 0.02),
                                    np.arange(-0.1, 0.101, 0.02), indexing="ij"), axis=-1).reshape(-1, 3)
        best = grid[np.argmax(model.log_likelihood(grid + np.array(truth), beams))]
        assert math.hypot(best[0], best[1]) <= 0.05 and abs(best[2]) <= 0.02, (truth, best)


def test_beam_selection_follows_nav2_step_and_filters() -> None:
    ranges = np.full(360, 1.0)
    ranges[6] = np.nan
    ranges[12] = 3.5  # = range_max: dropped
    ranges[18] = 0.05  # ≤ range_min: treated as range_max, dropped
    beams = select_beams(LaserScan(ranges, 0.0, math.radians(1.0), 0.12, 3.5), (0.0, 0.0, 0.5), AmclParams())
    assert beams.ranges.size == 57  # step (360 − 1) // 59 = 6 → 60 beams, 3 invalid
    assert beams.bearings[0] == pytest.approx(0.5)
    assert beams.bearings[1] == pytest.approx(0.5 + math.radians(24))


def test_kld_limit_formula_and_clamps() -> None:
    k = 50
    b = 2.0 / (9.0 * (k - 1))
    expected = math.ceil((k - 1) / (2 * 0.05) * (1 - b + math.sqrt(b) * 0.99) ** 3)
    assert kld_limit(k, 0.05, 0.99, 1, 100_000) == expected
    assert kld_limit([1, 2, 10_000], 0.05, 0.99, 500, 2000).tolist() == [2000, 500, 2000]


def test_kld_sample_count_grows_with_the_number_of_bins() -> None:
    rng = np.random.default_rng(1)
    tight = np.column_stack([rng.normal(0, 0.05, 5000), rng.normal(0, 0.05, 5000), rng.normal(0, 0.05, 5000)])
    spread = np.column_stack([rng.uniform(-5, 5, 5000), rng.uniform(-5, 5, 5000), rng.uniform(-3, 3, 5000)])
    n_tight = kld_sample_count(bin_keys(tight), 0.05, 0.99, 10, 5000)
    n_spread = kld_sample_count(bin_keys(spread), 0.05, 0.99, 10, 5000)
    assert n_tight < 200 and n_spread == 5000


def test_estimate_is_the_mean_of_the_heaviest_cluster() -> None:
    rng = np.random.default_rng(2)
    a = np.column_stack([rng.normal(1.0, 0.05, 300), rng.normal(1.0, 0.05, 300), rng.normal(0.2, 0.02, 300)])
    b = np.column_stack(
        [rng.normal(-2.0, 0.05, 300), rng.normal(3.0, 0.05, 300), rng.normal(-1.0, 0.02, 300)]
    )
    weights = np.concatenate([np.full(300, 0.3), np.full(300, 0.7)])
    est = estimate_pose(np.vstack([a, b]), weights)
    assert est.cluster_count == 2
    assert (est.x, est.y, est.yaw) == (
        pytest.approx(-2.0, abs=0.02),
        pytest.approx(3.0, abs=0.02),
        pytest.approx(-1.0, abs=0.01),
    )
    assert est.cluster_weight == pytest.approx(0.7)
    assert est.covariance[0, 0] > 1.0  # the set's covariance spans both clusters, as Nav2 publishes


def test_a_cloud_facing_west_is_one_cluster_across_the_heading_wrap() -> None:
    """Headings just under +π and just over −π are neighbours: the yaw bins wrap round. Before, the
    cloud split into two clusters at ±π and the estimate was the mean of one half, 0.8 σ off (0.16 rad
    for a 0.2 rad spread: test_tb4 saw one 0.23 rad estimate while the robot turned through west)."""
    rng = np.random.default_rng(3)
    yaw = np.mod(math.pi + rng.normal(0.0, 0.2, 2000) + math.pi, math.tau) - math.pi
    cloud = np.column_stack([rng.normal(1.0, 0.05, 2000), rng.normal(2.0, 0.05, 2000), yaw])
    est = estimate_pose(cloud, np.ones(2000))
    assert est.cluster_count == 1
    assert abs(math.remainder(est.yaw - math.pi, math.tau)) < 0.02


def test_map_to_odom_composes_back_to_the_estimate() -> None:
    est, odom = (1.0, 2.0, 0.7), (0.3, -0.4, -0.5)
    tx, ty, tyaw = map_to_odom(est, odom)
    c, s = math.cos(tyaw), math.sin(tyaw)
    assert (tx + c * odom[0] - s * odom[1], ty + s * odom[0] + c * odom[1]) == (
        pytest.approx(1.0),
        pytest.approx(2.0),
    )
    assert tyaw + odom[2] == pytest.approx(0.7)


def test_initial_pose_validation_and_spread() -> None:
    grid, spec = corridor_world()
    amcl = Amcl(AmclParams(), grid, spec, np.random.default_rng(0))
    assert not amcl.initialized
    assert not amcl.update((0.0, 0.0, 0.0), fake_scan(grid, spec, (1.0, 1.0, 0.0))).updated
    with pytest.raises(ValueError, match="finite"):
        amcl.set_initial_pose(math.nan, 1.0, 0.0)
    with pytest.raises(ValueError, match="outside the map"):
        amcl.set_initial_pose(30.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="positive semi-definite"):
        amcl.set_initial_pose(1.0, 1.0, 0.0, np.diag([0.1, -0.1, 0.1]))
    with pytest.raises(ValueError, match="symmetric"):
        amcl.set_initial_pose(1.0, 1.0, 0.0, [[0.1, 0.05, 0], [0, 0.1, 0], [0, 0, 0.1]])
    amcl.set_initial_pose(1.0, 1.0, 0.3)
    assert amcl.particles.shape == (2000, 3)
    assert amcl.particles[:, 0].std() == pytest.approx(0.5, rel=0.1)
    assert amcl.particles[:, 2].std() == pytest.approx(math.pi / 12, rel=0.1)


def test_params_are_checked_with_the_field_name() -> None:
    with pytest.raises(ValueError, match="min_particles"):
        AmclParams(min_particles=3000)
    with pytest.raises(ValueError, match="laser_model_type must be one of likelihood_field, "
                                         "likelihood_field_prob, beam, got 'likelihood'"):
        AmclParams(laser_model_type="likelihood")
    with pytest.raises(ValueError, match="sigma_hit"):
        AmclParams(sigma_hit=0.0)


def _step(pose: np.ndarray, v: float, w: float) -> np.ndarray:
    yaw = pose[2] + w
    return np.array(
        [
            pose[0] + v * math.cos(pose[2]),
            pose[1] + v * math.sin(pose[2]),
            math.atan2(math.sin(yaw), math.cos(yaw)),
        ]
    )


def test_update_thresholds_gate_filter_updates() -> None:
    grid, spec = corridor_world()
    amcl = Amcl(AmclParams(), grid, spec, np.random.default_rng(0))
    amcl.set_initial_pose(1.0, 1.0, 0.0)
    scan = fake_scan(grid, spec, (1.0, 1.0, 0.0))
    assert amcl.update((0.0, 0.0, 0.0), scan).updated  # the first scan after an initial pose
    assert not amcl.update((0.2, 0.0, 0.1), scan).updated  # below update_min_d and update_min_a
    assert amcl.update((0.26, 0.0, 0.1), scan).updated
    assert not amcl.update((0.26, 0.1, 0.25), scan).updated
    assert amcl.update((0.26, 0.1, 0.31), scan).updated  # 0.21 rad turned
    amcl.request_nomotion_update()
    assert amcl.update((0.26, 0.1, 0.31), scan).updated


def drive(
    amcl: Amcl,
    grid: np.ndarray,
    spec: GridSpec,
    truth: np.ndarray,
    commands: list[tuple[float, float]],
    rng: np.random.Generator,
) -> np.ndarray:
    """Move the true robot and its (perfect) odometry; return the true pose at AMCL's last update."""
    odom = np.zeros(3)
    at_update = truth
    for v, w in commands:
        truth, odom = _step(truth, v, w), _step(odom, v, w)
        if amcl.update(tuple(odom), fake_scan(grid, spec, tuple(truth), noise_std=0.01, rng=rng)).updated:
            at_update = truth
    return at_update


def test_converges_in_a_corridor_from_an_offset_initial_pose() -> None:
    grid, spec = corridor_world()
    rng = np.random.default_rng(4)
    amcl = Amcl(AmclParams(), grid, spec, rng)
    truth = np.array([0.8, 1.0, 0.0])
    amcl.set_initial_pose(1.1, 0.8, 0.15)
    truth = drive(amcl, grid, spec, truth, [(0.05, 0.0)] * 120, rng)
    est = amcl.estimate()
    assert math.hypot(est.x - truth[0], est.y - truth[1]) < 0.1
    assert abs(est.yaw - truth[2]) < 0.05
    assert amcl.particles.shape[0] < 2000  # KLD shrank the set once the cloud was tight


def test_converges_and_shrinks_on_the_turtlebot3_world() -> None:
    if not TB3_MAP.exists():
        pytest.skip("maps/turtlebot3_world.yaml not generated yet")
    loaded = load_map(TB3_MAP)
    rng = np.random.default_rng(7)
    amcl = Amcl(AmclParams(), loaded.data, loaded.spec, rng)
    truth = np.array([-2.0, -0.5, 0.0])
    amcl.set_initial_pose(-1.7, -0.2, 0.2)  # 0.42 m and 0.2 rad off, within the default spread
    commands = [(0.05, 0.0)] * 30 + [(0.0, 0.15)] * 10 + [(0.05, 0.0)] * 20
    truth = drive(amcl, loaded.data, loaded.spec, truth, commands, rng)
    est = amcl.estimate()
    assert math.hypot(est.x - truth[0], est.y - truth[1]) < 0.1
    assert abs(math.atan2(math.sin(est.yaw - truth[2]), math.cos(est.yaw - truth[2]))) < 0.05
    assert amcl.particles.shape[0] < 1600  # KLD: fewer than the 2000 the initial pose spread
    assert np.sqrt(est.covariance[0, 0]) < 0.4  # tighter than the initial 0.5 m spread


def _kidnap(recovery: bool) -> tuple[float, int]:
    grid, spec = clutter_world()
    rng = np.random.default_rng(0)
    alphas = {"recovery_alpha_slow": 0.02, "recovery_alpha_fast": 0.3} if recovery else {}
    amcl = Amcl(AmclParams(**alphas), grid, spec, rng)  # type: ignore[arg-type]
    home, away = (-2.3, -2.3, 0.5), (1.0, 1.2, 2.5)
    amcl.set_initial_pose(*home)
    for _ in range(40):
        amcl.request_nomotion_update()
        amcl.update((0.0, 0.0, 0.0), fake_scan(grid, spec, home, noise_std=0.01, rng=rng))
    est = amcl.estimate()
    assert math.hypot(est.x - home[0], est.y - home[1]) < 0.1
    widest = 0
    for _ in range(60):  # kidnapped: the odometry saw nothing
        amcl.request_nomotion_update()
        amcl.update((0.0, 0.0, 0.0), fake_scan(grid, spec, away, noise_std=0.01, rng=rng))
        widest = max(widest, int(np.ptp(amcl.particles[:, 0]) > 3.0))
    est = amcl.estimate()
    return math.hypot(est.x - away[0], est.y - away[1]), widest


def test_recovery_respreads_after_a_kidnap_and_reconverges() -> None:
    error, spread = _kidnap(recovery=True)
    assert spread  # random free-space particles were injected across the room
    assert error < 0.2
    error_without, spread_without = _kidnap(recovery=False)  # Nav2's default: recovery off
    assert not spread_without and error_without > 1.0


def test_global_localization_spreads_over_free_space() -> None:
    grid, spec = clutter_world()
    amcl = Amcl(AmclParams(), grid, spec, np.random.default_rng(3))
    amcl.global_localization()
    mx, my = spec.world_to_cell(amcl.particles[:, 0], amcl.particles[:, 1])
    assert (grid[my, mx] == 0).all()
    assert np.ptp(amcl.particles[:, 0]) > 5.0 and np.ptp(amcl.particles[:, 2]) > 6.0


def test_beam_model_prefers_the_true_pose() -> None:
    grid, spec = clutter_world()
    amcl = Amcl(AmclParams(laser_model_type=BEAM), grid, spec, np.random.default_rng(0))
    truth = (-2.3, -2.3, 0.5)
    scan = fake_scan(grid, spec, truth, noise_std=0.01, rng=np.random.default_rng(1))
    beams = select_beams(scan, (0.0, 0.0, 0.0), amcl.params, keep_max=True)
    w = amcl.model.log_likelihood(np.array([truth, (-2.1, -2.3, 0.5), (-2.3, -2.3, 0.8)]), beams)
    assert w[0] > w[1] and w[0] > w[2]


def test_perfect_odometry_tracks_within_centimetres_through_drives_and_turns() -> None:
    """The cube-sum weight of Nav2 drifted 0.1–0.3 m here (bench/RESULTS.md); a correct MCL must not."""
    loaded = load_map(TB3_MAP)
    rng = np.random.default_rng(11)
    amcl = Amcl(AmclParams(), loaded.data, loaded.spec, rng)
    truth = np.array([-2.0, -0.5, 0.0])
    amcl.set_initial_pose(*truth, np.diag([1e-6, 1e-6, 1e-6]))
    odom = np.zeros(3)
    errors = []
    turn = [(0.0, 0.2)] * 8  # 1.6 rad in place, the motion Nav2's alphas punish most
    for v, w in [(0.05, 0.0)] * 60 + turn + [(0.05, 0.0)] * 16 + turn + [(0.05, 0.0)] * 16:
        truth, odom = _step(truth, v, w), _step(odom, v, w)
        scan = fake_scan(loaded.data, loaded.spec, tuple(truth), noise_std=0.01, rng=rng)
        if amcl.update(tuple(odom), scan).updated:
            est = amcl.estimate()
            errors.append((math.hypot(est.x - truth[0], est.y - truth[1]),
                           abs(math.atan2(math.sin(est.yaw - truth[2]), math.cos(est.yaw - truth[2])))))
    xy, yaw = np.array(errors).T
    assert len(errors) > 20
    assert math.sqrt(float(np.mean(xy**2))) < 0.05 and xy.max() < 0.1
    assert math.sqrt(float(np.mean(yaw**2))) < 0.05


def test_motion_model_without_noise_moves_every_particle_like_the_odometry() -> None:
    old, new = (1.0, 2.0, 0.5), (1.3, 2.1, 0.7)  # odom frame
    particles = np.array([[-1.0, 0.0, 2.0], [0.5, 0.5, -3.0]])
    c, s = math.cos(old[2]), math.sin(old[2])
    fwd, left = c * 0.3 + s * 0.1, -s * 0.3 + c * 0.1  # the step in the old odometry body frame
    sample_differential(particles, old, new, (0.0, 0.0, 0.0, 0.0), np.random.default_rng(0))
    for start, got in zip([(-1.0, 0.0, 2.0), (0.5, 0.5, -3.0)], particles, strict=True):
        cp, sp = math.cos(start[2]), math.sin(start[2])
        assert got[0] == pytest.approx(start[0] + cp * fwd - sp * left)
        assert got[1] == pytest.approx(start[1] + sp * fwd + cp * left)
        assert math.cos(got[2] - start[2] - 0.2) == pytest.approx(1.0)


def test_tempering_keeps_the_effective_sample_size() -> None:
    rng = np.random.default_rng(5)
    log_l = rng.normal(0.0, 30.0, 1000)  # a spread cloud: likelihoods differing by e^±60
    weights, gamma = reweight(np.full(1000, 1e-3), log_l, 0.5)
    assert 0.0 < gamma < 0.1
    assert 1.0 / float(weights @ weights) == pytest.approx(500, rel=0.01)
    weights, gamma = reweight(np.full(1000, 1e-3), rng.normal(0.0, 0.1, 1000), 0.5)
    assert gamma == 1.0  # a tight cloud gets the full likelihood
    assert reweight(np.full(1000, 1e-3), log_l, 0.0)[1] == 1.0  # 0 = no tempering


def test_recovery_averages_start_as_means_and_ignore_unhealthy_scans() -> None:
    fit = FitAverages(alpha_slow=0.001, alpha_fast=0.1)
    for value in (0.3, 0.5, 0.5, 0.5):  # the first scan, taken before convergence, is not the norm
        fit.add(value)
    assert fit.w_slow == pytest.approx(0.45)
    for _ in range(20):  # kidnapped: every scan fits badly
        fit.add(0.2)
    assert fit.w_slow > 0.44  # still the healthy norm, so injection continues
    assert fit.injection_probability > 0.4
    off = FitAverages(alpha_slow=0.0, alpha_fast=0.0)
    for value in (0.5, 0.2, 0.2):
        off.add(value)
    assert off.injection_probability == 0.0  # Nav2's defaults: recovery disabled
