"""The SLAM map update: the compiled kernels against numpy references, and the sliced re-render."""

from __future__ import annotations

import numpy as np
import pytest

from nav_stack.core.costmap.raytrace import trace_cells
from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.slam import GridSlam, SlamParams, mapper
from nav_stack.core.slam.laser import ScanPoints
from nav_stack.core.slam.log_odds import LogOddsGrid
from nav_stack.core.slam.pose_graph_jit import block_tridiagonal_solve
from nav_stack.core.slam.rerender import Rerender
from navsuite_testing.slam.world import NoisyOdometry, interpolate, ring_world

Scan = tuple[tuple[float, float], FloatArray, FloatArray]


def _reference_integrate(grid: LogOddsGrid, scan: Scan) -> None:
    """The numpy update integrate_jit replaces: trace every ray, each cell once, endpoints win."""
    origin, hits, misses = scan
    spec = grid._ensure_covers(*np.vstack((hits, misses, np.array([origin]))).T)
    free: list[np.ndarray] = []
    for points, include_end in ((hits, False), (misses, True)):
        dx, dy = points[:, 0] - origin[0], points[:, 1] - origin[1]
        fx, fy = trace_cells(spec, origin, np.hypot(dx, dy), np.arctan2(dy, dx), include_end=include_end)
        free.append(fy * spec.width + fx)
    hx, hy = spec.world_to_cell(hits[:, 0], hits[:, 1])
    hit_cells = np.unique(hy * spec.width + hx)
    free_cells = np.setdiff1d(np.unique(np.concatenate(free)), hit_cells)
    flat, seen = grid._log_odds.reshape(-1), grid._seen.reshape(-1)
    flat[free_cells] = np.maximum(flat[free_cells] + grid._miss, grid._clamp[0])
    flat[hit_cells] = np.minimum(flat[hit_cells] + grid._hit, grid._clamp[1])
    seen[free_cells] = seen[hit_cells] = True


def _random_scans(count: int, seed: int) -> list[Scan]:
    rng = np.random.default_rng(seed)
    scans = []
    for _ in range(count):
        origin = rng.uniform(-3.0, 3.0, 2)
        angles = np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False) + rng.uniform(0.0, 1.0)
        ranges = rng.uniform(0.2, 3.5, 360)
        points = origin + np.column_stack((ranges * np.cos(angles), ranges * np.sin(angles)))
        hit = rng.random(360) < 0.7
        scans.append(((float(origin[0]), float(origin[1])), points[hit], points[~hit]))
    return scans


def _grid() -> LogOddsGrid:
    return LogOddsGrid(0.05, 0.7, 0.4, (0.12, 0.97))


def test_the_compiled_update_matches_the_numpy_reference_bit_for_bit() -> None:
    scans = _random_scans(60, seed=3)
    reference, one_by_one, batched = _grid(), _grid(), _grid()
    for scan in scans:
        _reference_integrate(reference, scan)
        one_by_one.integrate(*scan)
    batched.integrate_all(scans[:20])
    batched.integrate_all(scans[20:])
    assert one_by_one.state()[0] == reference.state()[0]
    for mine, theirs in zip(one_by_one.state()[1:], reference.state()[1:], strict=True):
        np.testing.assert_array_equal(mine, theirs)
    # a batch grows the grid once (another allocation), so compare the rendered maps and their extent
    expected_map, expected_spec = reference.occupancy(0.65, 0.196)
    batched_map, batched_spec = batched.occupancy(0.65, 0.196)
    np.testing.assert_array_equal(batched_map, expected_map)
    assert (batched_spec.width, batched_spec.height) == (expected_spec.width, expected_spec.height)
    np.testing.assert_allclose((batched_spec.origin_x, batched_spec.origin_y),
                               (expected_spec.origin_x, expected_spec.origin_y), atol=1e-9)


def test_the_compiled_block_tridiagonal_solve_matches_a_dense_solve() -> None:
    rng = np.random.default_rng(4)
    n, k = 40, 7
    roots = rng.normal(size=(n, 3, 3))
    diag = roots @ roots.transpose(0, 2, 1) + 3.0 * np.eye(3)
    upper = 0.3 * rng.normal(size=(n - 1, 3, 3))
    rhs = rng.normal(size=(n, 3, k))
    dense = np.zeros((3 * n, 3 * n))
    for b in range(n):
        dense[3 * b : 3 * b + 3, 3 * b : 3 * b + 3] = diag[b]
    for b in range(n - 1):
        dense[3 * b : 3 * b + 3, 3 * b + 3 : 3 * b + 6] = upper[b]
        dense[3 * b + 3 : 3 * b + 6, 3 * b : 3 * b + 3] = upper[b].T
    expected = np.linalg.solve(dense, rhs.reshape(3 * n, k)).reshape(n, 3, k)
    np.testing.assert_allclose(block_tridiagonal_solve(diag, upper, rhs), expected, atol=1e-10)


def test_a_rerender_in_slices_equals_one_in_a_single_pass() -> None:
    scans = _random_scans(25, seed=5)
    single, sliced = _grid(), Rerender(_grid())
    single.integrate_all(scans)
    # each scan as seen from its sensor (robot frame, yaw 0) and the sensor's pose in the map
    points = [ScanPoints((0.0, 0.0), h - np.array(o), m - np.array(o)) for o, h, m in scans]
    poses = np.array([[o[0], o[1], 0.0] for o, _, _ in scans])
    assert [sliced.advance(points, poses, 10) for _ in range(3)] == [False, False, True]
    np.testing.assert_array_equal(sliced.grid.occupancy(0.65, 0.196)[0], single.occupancy(0.65, 0.196)[0])


def test_after_a_loop_closure_the_published_map_stays_the_last_complete_one_until_rerendered(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(mapper, "RERENDER_SLICE_NODES", 20)  # a re-render then spans several scans
    world = ring_world()
    rng = np.random.default_rng(1)
    odometry = NoisyOdometry(rng, translation_noise=0.08, rotation_noise=0.05, rotation_bias=0.05)
    start = Pose2D(-4.25, -4.25, 0.0)
    slam = GridSlam(SlamParams(map_start_pose=(start.x, start.y, start.yaw)))
    lap = [start, Pose2D(4.25, -4.25, 0.0), Pose2D(4.25, 4.25, 0.0), Pose2D(-4.25, 4.25, 0.0), start,
           Pose2D(0.0, -4.25, 0.0)]
    closed, pending_scans = None, 0
    for k, true_pose in enumerate(interpolate(lap, 0.2)):
        scan = world.scan(true_pose, noise_std=0.01, rng=rng)
        update = slam.process(scan, odometry.update(true_pose), 0.2 * k)
        if closed is None and update.loop_closed and slam._rerender is not None:
            closed = slam.occupancy(complete=False)[0]
        elif closed is not None and slam._rerender is not None:
            pending_scans += 1
            np.testing.assert_array_equal(slam.occupancy(complete=False)[0], closed)  # never half re-rendered
        elif closed is not None:
            break
    assert closed is not None, "the lap closes a loop that moves the graph"
    assert pending_scans >= 2 and slam._rerender is None
    assert not np.array_equal(slam.occupancy(complete=False)[0], closed)  # swapped in once complete
