"""SimpleSmoother (nav2_smoother, Jazzy) and the smoother server's checks, without ROS."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from nav_stack.core.control.base import CircleFootprint, CostGrid, PolygonFootprint
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, GridSpec
from nav_stack.core.smoothing import (
    SimpleSmoother,
    SimpleSmootherParams,
    SmoothErrorCode,
    SmootherServerCore,
    directional_segments,
)
from nav_stack.core.smoothing.simple_smoother import SEGMENT_MIN_STEPS


def zigzag(n: int = 61, step: float = 0.05, amplitude: float = 0.015) -> np.ndarray:
    """A straight line along +x with every other pose pushed sideways (no cusps: steps stay forward)."""
    x = np.arange(n) * step
    y = amplitude * np.where(np.arange(n) % 2 == 0, 1.0, -1.0)
    return np.column_stack([x, y, np.zeros(n)])


def total_turning(path: np.ndarray) -> float:
    """Sum of the absolute heading changes (rad) between consecutive steps."""
    d = np.diff(path[:, :2], axis=0)
    heading = np.arctan2(d[:, 1], d[:, 0])
    return float(np.abs(np.angle(np.exp(1j * np.diff(heading)))).sum())


def nav2_reference(path: np.ndarray, w_data: float = 0.2, w_smooth: float = 0.3, tolerance: float = 1e-10,
                   max_its: int = 1000) -> np.ndarray:
    """One pass of Nav2's loop, point by point (the definition the vectorised sweep must reproduce)."""
    data, new = path[:, :2].copy(), path[:, :2].copy()
    its, change = 0, tolerance
    while change >= tolerance:
        its += 1
        change = 0.0
        if its >= max_its:
            break
        for i, j in itertools.product(range(1, len(new) - 1), range(2)):
            before = new[i, j]
            pull = w_data * (data[i, j] - new[i, j])
            new[i, j] += pull + w_smooth * (new[i + 1, j] + new[i - 1, j] - 2 * new[i, j])
            change += abs(new[i, j] - before)
    return new


class StepClock:
    """A clock that advances ``step`` s every time it is read (the smoother reads it once per sweep)."""

    def __init__(self, step: float) -> None:
        self.now, self.step = 0.0, step

    def __call__(self) -> float:
        self.now += self.step
        return self.now


def test_a_zigzag_gets_straighter_and_keeps_its_endpoints() -> None:
    path = zigzag()
    out = SimpleSmoother().smooth(path, 5.0)
    assert not out.timed_out
    assert total_turning(out.path) < 0.2 * total_turning(path)
    np.testing.assert_array_equal(out.path[[0, -1], :2], path[[0, -1], :2])
    assert np.abs(out.path[5:-5, 1]).max() < 0.2 * 0.015  # the middle settles onto the line


def test_one_pass_equals_nav2s_point_by_point_loop() -> None:
    path = zigzag(41)
    path[:, 1] += 0.3 * np.sin(path[:, 0] * 3.0)  # a curve under the zigzag
    out = SimpleSmoother(SimpleSmootherParams(do_refinement=False)).smooth(path, 5.0)
    np.testing.assert_allclose(out.path[:, :2], nav2_reference(path), atol=1e-12)


def test_refinement_smooths_again_anchored_to_the_last_result() -> None:
    path = zigzag()
    path[:, 1] += 0.3 * np.sin(path[:, 0] * 3.0)
    once = SimpleSmoother(SimpleSmootherParams(do_refinement=False)).smooth(path, 5.0).path
    refined = SimpleSmoother(SimpleSmootherParams(refinement_num=2)).smooth(path, 5.0).path
    expected = nav2_reference(nav2_reference(nav2_reference(path)))
    np.testing.assert_allclose(refined[:, :2], expected, atol=1e-12)
    assert total_turning(refined) < total_turning(once)


def test_converges_within_max_its_and_stops_there_when_it_cannot() -> None:
    smoother = SimpleSmoother(SimpleSmootherParams(do_refinement=False))
    smoother.smooth(zigzag(), 5.0)
    assert 0 < smoother.iterations < 999
    capped = SimpleSmoother(SimpleSmootherParams(max_its=5, do_refinement=False))
    out = capped.smooth(zigzag(), 5.0)
    assert capped.iterations == 4 and not out.timed_out  # Nav2 counts the try that stops as one
    np.testing.assert_allclose(out.path[:, :2], nav2_reference(zigzag(), max_its=5), atol=1e-12)


def test_the_time_limit_is_honoured_on_the_injected_clock() -> None:
    clock = StepClock(0.01)
    smoother = SimpleSmoother(SimpleSmootherParams(tolerance=0.0), clock=clock)  # never converges
    out = smoother.smooth(zigzag(), 0.1)
    assert out.timed_out
    assert smoother.iterations <= 10 and clock.now < 0.2
    assert total_turning(out.path) < total_turning(zigzag())  # the sweeps done so far are kept
    core = SmootherServerCore({"simple_smoother": SimpleSmoother(SimpleSmootherParams(tolerance=0.0),
                                                                 clock=StepClock(0.01))})
    result = core.smooth_path(zigzag(), "", 0.1, None)
    assert (result.error_code, result.was_completed) == (SmoothErrorCode.TIMEOUT, False)
    assert "0.100 s" in result.error_msg


def test_a_cusp_is_kept_and_each_side_is_smoothed_on_its_own() -> None:
    forward = zigzag(21)
    back = np.column_stack([forward[-1, 0] - np.arange(1, 21) * 0.05, 0.03 * np.arange(1, 21),
                            np.zeros(20)])
    path = np.vstack([forward, back])
    assert directional_segments(path) == [(0, 20), (20, 40)]
    out = SimpleSmoother().smooth(path, 5.0).path
    np.testing.assert_array_equal(out[20, :2], path[20, :2])  # the cusp stays where it was
    d_in, d_out = out[20, :2] - out[19, :2], out[21, :2] - out[20, :2]
    assert float(np.dot(d_in, d_out)) < 0.0  # and is still a reversal
    across = SimpleSmoother(SimpleSmootherParams(enforce_path_inversion=False)).smooth(path, 5.0).path
    assert np.hypot(*(across[20, :2] - path[20, :2])) > 0.01  # smoothed as one segment it moves


def test_a_turn_on_the_spot_cuts_the_path_too() -> None:
    path = np.vstack([zigzag(15), zigzag(15) + np.array([0.7, 0.0, 0.0])])
    path[15:, 2] = math.pi / 2  # the robot turns where pose 14 and 15 meet...
    path[15, :2] = path[14, :2]  # ...without moving
    assert directional_segments(path) == [(0, 14), (14, 29)]
    path[15, :2] += [0.01, 0.0]  # moving a centimetre while turning is no turn on the spot
    assert directional_segments(path) == [(0, 29)]


def test_short_segments_are_left_alone() -> None:
    path = zigzag(SEGMENT_MIN_STEPS)  # spans SEGMENT_MIN_STEPS - 1 steps
    np.testing.assert_array_equal(SimpleSmoother().smooth(path, 5.0).path, path)
    longer = zigzag(SEGMENT_MIN_STEPS + 1)
    assert not np.array_equal(SimpleSmoother().smooth(longer, 5.0).path, longer)


def test_orientations_face_the_next_pose_and_flip_on_a_reversing_segment() -> None:
    path = zigzag()
    path[:, 1] += 0.3 * np.sin(path[:, 0] * 3.0)
    path[-1, 2] = 0.7  # the goal's heading is the goal's, never recomputed
    out = SimpleSmoother().smooth(path, 5.0).path
    d = np.diff(out[:, :2], axis=0)
    np.testing.assert_allclose(out[:-1, 2], np.arctan2(d[:, 1], d[:, 0]), atol=1e-12)
    assert out[-1, 2] == 0.7
    backwards = path.copy()
    backwards[:, 2] = math.pi  # driving this path in reverse: the robot faces away from travel
    out = SimpleSmoother().smooth(backwards, 5.0).path
    facing = np.arctan2(d[:, 1], d[:, 0]) + math.pi
    np.testing.assert_allclose(np.angle(np.exp(1j * (out[:-1, 2] - facing))), 0.0, atol=1e-9)


def test_a_sweep_that_would_touch_an_obstacle_is_undone() -> None:
    """A path bending round an inscribed cell: smoothing would cut the corner across it."""
    spec = GridSpec(40, 40, 0.05, -0.5, -0.5)
    costs = np.zeros(spec.shape, dtype=np.uint8)
    costs[18, 24] = INSCRIBED_INFLATED_OBSTACLE  # x 0.70 .. 0.75, y 0.40 .. 0.45: inside the corner
    grid = CostGrid(costs, spec)
    leg = np.arange(0, 16) * 0.05
    corner = np.vstack([np.column_stack([leg, np.full(16, 0.5)]),
                        np.column_stack([np.full(15, 0.8), 0.5 - np.arange(1, 16) * 0.05])])
    path = np.column_stack([corner, np.zeros(len(corner))])
    free = SimpleSmoother().smooth(path, 5.0).path
    assert (grid.cost_at(free[:, 0], free[:, 1]) > 252).any()  # without the costmap it cuts in
    guarded = SimpleSmoother().smooth(path, 5.0, grid).path
    assert (grid.cost_at(guarded[:, 0], guarded[:, 1]) <= 252).all()
    assert not np.array_equal(guarded[:, :2], path[:, :2])  # the sweeps before the contact are kept


def test_the_server_checks_the_id_and_the_path_before_smoothing() -> None:
    core = SmootherServerCore({"simple_smoother": SimpleSmoother()})
    result = core.smooth_path(zigzag(), "curvy", 1.0, None)
    assert result.error_code == SmoothErrorCode.INVALID_SMOOTHER and "simple_smoother" in result.error_msg
    result = core.smooth_path(np.zeros((0, 3)), "simple_smoother", 1.0, None)
    assert result.error_code == SmoothErrorCode.INVALID_PATH
    assert result.error_msg == "the path to smooth is empty"
    path = zigzag()
    path[7, 0] = math.nan
    result = core.smooth_path(path, "", 1.0, None)
    assert result.error_code == SmoothErrorCode.INVALID_PATH and "pose 7" in result.error_msg
    path = zigzag()
    path[3, 2] = math.nan
    assert "orientation" in core.smooth_path(path, "", 1.0, None).error_msg
    ok = core.smooth_path(zigzag(), "", 1.0, None)
    assert ok.ok and ok.was_completed and len(ok.path) == len(zigzag())
    cancelled = core.smooth_path(zigzag(), "", 1.0, None, should_stop=lambda: True)
    assert cancelled.cancelled and cancelled.error_code == 0 and not cancelled.was_completed
    two = SmootherServerCore({"a": SimpleSmoother(), "b": SimpleSmoother()})
    assert two.smooth_path(zigzag(), "", 1.0, None).error_code == SmoothErrorCode.INVALID_SMOOTHER


def test_the_collision_check_names_the_first_pose_in_collision() -> None:
    spec = GridSpec(80, 40, 0.05, -0.5, -1.0)
    costs = np.zeros(spec.shape, dtype=np.uint8)
    costs[:, 50:52] = LETHAL_OBSTACLE  # a wall across x = 2.0 .. 2.1
    grid = CostGrid(costs, spec)
    core = SmootherServerCore({"simple_smoother": SimpleSmoother()})
    square = PolygonFootprint(((0.1, 0.1), (0.1, -0.1), (-0.1, -0.1), (-0.1, 0.1)))
    short = zigzag(31)  # ends at x = 1.5
    assert core.smooth_path(short, "", 1.0, grid, True, square).ok
    long = zigzag(61)  # reaches x = 3.0, through the wall
    result = core.smooth_path(long, "", 1.0, grid, True, square)
    assert result.error_code == SmoothErrorCode.SMOOTHED_PATH_IN_COLLISION and result.was_completed
    hit = int(result.error_msg.split("pose ")[1].split(" ")[0])
    assert 1.85 <= result.path[hit, 0] <= 1.95  # the square's nose reaches the wall first
    assert len(result.path) == 61  # the smoothed path comes back with the failure
    no_costmap = core.smooth_path(long, "", 1.0, None, True, CircleFootprint())
    assert no_costmap.error_code == SmoothErrorCode.UNKNOWN


@pytest.mark.parametrize("bad", [{"w_smooth": 1.0}, {"w_data": -0.1}, {"max_its": 0}, {"refinement_num": 0},
                                 {"tolerance": -1.0}])
def test_bad_parameters_are_refused(bad: dict[str, float]) -> None:
    with pytest.raises(ValueError):
        SimpleSmootherParams(**bad)  # type: ignore[arg-type]
