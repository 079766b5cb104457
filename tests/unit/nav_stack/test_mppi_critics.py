"""Each MPPI critic's cost on hand-made trajectories is what its Nav2 Jazzy definition gives, in the
numpy reference and in the compiled kernels alike."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.control import CostGrid, PolygonFootprint, Twist2D
from nav_stack.core.control.mppi import (
    CRITIC_PARAMS,
    CostCriticParams,
    MPPIParams,
    ObstaclesCriticParams,
)
from nav_stack.core.control.mppi import critics as reference
from nav_stack.core.control.mppi.critics_jit import score
from nav_stack.core.control.mppi.packing import context, pack
from nav_stack.core.control.mppi.scene import FootprintModel, Rollouts, Scene
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec

T, DT = 56, 0.05
SPEC = GridSpec(60, 60, 0.05, -1.5, -1.5)
PATH = np.column_stack([np.arange(41) * 0.05, np.zeros(41), np.zeros(41)])  # 2 m along +x


def rollouts(x: list[float] | float, y: list[float] | float = 0.0, yaw: list[float] | float = 0.0,
             vx: list[float] | float = 0.0, wz: list[float] | float = 0.0, vy: float = 0.0) -> Rollouts:
    """One trajectory per entry, each held at a constant value over all T steps."""
    rows = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=float)) for v in (x, y, yaw, vx, wz, vy)))
    x_, y_, yaw_, vx_, wz_, vy_ = (np.repeat(r[:, None], T, axis=1) for r in rows)
    return Rollouts(vx_.copy(), vy_.copy(), wz_.copy(), vx_, vy_, wz_, x_, y_, yaw_)


ORIGIN = Pose2D(0.0, 0.0, 0.0)


def costs(name: str, r: Rollouts, robot: Pose2D = ORIGIN, goal: tuple[float, float, float] = (5.0, 0.0, 0.0),
          grid: CostGrid | None = None, path: np.ndarray = PATH, footprint: FootprintModel | None = None,
          params: object | None = None, **mppi: object) -> tuple[np.ndarray, bool]:
    """The critic's costs from the reference, checked against the compiled ones."""
    p = MPPIParams(**mppi)  # type: ignore[arg-type]
    critic = params or CRITIC_PARAMS[name]()
    grid = grid or CostGrid(np.zeros(SPEC.shape, dtype=np.uint8), SPEC)
    scene = Scene.make(robot, Twist2D(0.0, 0.0), path, np.array(goal), grid, footprint or FootprintModel())
    ref, ref_fail = reference.evaluate([(name, critic)], scene, r, p, 0.2)
    codes, table = pack([(name, critic)], p)
    jit = np.zeros((1, len(r.x)))
    jit_fail = score(codes, table, context(scene, p, 0.2), r.x, r.y, r.yaw, r.vx, r.vy, r.wz, grid.costs,
                     scene.grid_meta(), scene.footprint.outline, scene.path, jit)
    np.testing.assert_allclose(jit[0], ref[0], rtol=1e-12, atol=1e-12)
    assert jit_fail == ref_fail
    return ref[0], ref_fail


def grid_with(cells: dict[tuple[float, float], int]) -> CostGrid:
    costs = np.zeros(SPEC.shape, dtype=np.uint8)
    for (x, y), cost in cells.items():
        mx, my = SPEC.world_to_cell(x, y)
        costs[int(my), int(mx)] = cost
    return CostGrid(costs, SPEC)


def test_constraint_critic_charges_speed_beyond_the_limits_and_tight_ackermann_turns() -> None:
    # Nav2 folds vy_max into the limit even for DiffDrive: max speed sqrt(0.5² + 0.5²)
    out, _ = costs("ConstraintCritic", rollouts([0.0, 0.0, 0.0], vx=[0.8, 0.3, -0.9]))
    assert out == pytest.approx([4.0 * T * DT * (0.8 - math.sqrt(0.5)), 0.0,
                                 4.0 * T * DT * (0.9 - math.hypot(0.35, 0.5))])
    out, _ = costs("ConstraintCritic", rollouts([0.0, 0.0], vx=[0.1, 0.1], wz=[1.0, 0.2]),
                   motion_model="Ackermann")
    assert out == pytest.approx([4.0 * T * DT * (0.2 - 0.1), 0.0])  # radius 0.1 m < 0.2 m; 0.5 m is fine


def test_cost_critic_sums_centre_costs_and_makes_collisions_collision_cost() -> None:
    grid = grid_with({(0.5, 0.5): 100, (0.0, 0.5): 254, (-0.5, 0.5): 253})
    r = rollouts([0.5, 0.0, -0.5, 1.0, 2.0], [0.5, 0.5, 0.5, 1.0, 0.0])
    out, fail = costs("CostCritic", r, grid=grid)
    scale = 3.81 / 254.0 / 28  # 28 of the 56 poses checked (trajectory_point_step 2)
    assert out == pytest.approx([28 * 100 * scale, 1e6 * scale, 1e6 * scale, 0.0, 1e6 * scale])  # off grid
    assert not fail
    near, _ = costs("CostCritic", r, grid=grid, goal=(0.5, 0.0, 0.0))  # within near_goal_distance
    assert near[0] == 0.0 and near[1] == pytest.approx(1e6 * scale)
    _, fail = costs("CostCritic", rollouts([0.0], [0.5]), grid=grid)
    assert fail


def test_cost_critic_with_the_footprint_lets_the_outline_decide_and_charges_critical_cost() -> None:
    grid = grid_with({(0.0, 0.0): 253, (0.2, 0.0): 50, (0.33, 0.0): 254})
    square = FootprintModel.of(PolygonFootprint(((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1))), 0.1,
                               None)
    params = CostCriticParams(consider_footprint=True)
    out, _ = costs("CostCritic", rollouts([0.0, 0.2]), grid=grid, footprint=square, params=params)
    scale = 3.81 / 254.0 / 28
    # an inscribed centre costs critical_cost (the outline is clear); an outline on a lethal cell collides
    assert out == pytest.approx([28 * 300.0 * scale, 1e6 * scale])
    out, _ = costs("CostCritic", rollouts([0.27]), grid=grid, footprint=square, params=params)
    assert out == pytest.approx([0.0])  # a free centre is not checked further (Nav2's shortcut)


def test_obstacles_critic_turns_costs_into_distances() -> None:
    grid = grid_with({(0.5, 0.5): 100, (0.0, 0.5): 240, (-0.5, 0.5): 254})
    params = ObstaclesCriticParams(inflation_radius=0.55, cost_scaling_factor=3.0)
    out, _ = costs("ObstaclesCritic", rollouts([1.0, 0.5, 0.0, -0.5], [1.0, 0.5, 0.5, 0.5]), grid=grid,
                   params=params, footprint=FootprintModel(inscribed_radius=0.22))
    d100 = (math.log(253.0) - math.log(100.0)) / 3.0  # the centre's distance minus the inscribed radius
    d240 = (math.log(253.0) - math.log(240.0)) / 3.0
    # every pose of a trajectory adds to the critical term; the repulsion is normalised by T
    assert out == pytest.approx([0.0, 1.5 * (0.55 - d100), 20.0 * T * (0.1 - d240) + 1.5 * (0.55 - d240),
                                 20.0 * 100000.0])


def test_goal_critics_pull_toward_the_goal_only_near_it() -> None:
    r = rollouts([0.0, 1.0], yaw=[0.5, -0.2])
    near = Pose2D(0.5, 0.0, 0.0)
    out, _ = costs("GoalCritic", r, robot=near, goal=(1.0, 0.0, 0.0))
    assert out == pytest.approx([5.0 * 1.0, 0.0])
    out, _ = costs("GoalAngleCritic", r, robot=Pose2D(0.8, 0.0, 0.0), goal=(1.0, 0.0, 0.0))
    assert out == pytest.approx([3.0 * 0.5, 3.0 * 0.2])
    far, _ = costs("GoalCritic", r, robot=Pose2D(-1.0, 0.0, 0.0), goal=(1.0, 0.0, 0.0))
    assert not far.any()


def test_prefer_forward_and_twirling_charge_reversing_and_turning_away_from_the_goal() -> None:
    out, _ = costs("PreferForwardCritic", rollouts([0.0, 0.0], vx=[-0.2, 0.2]))
    assert out == pytest.approx([5.0 * 0.2 * DT * T, 0.0])
    out, _ = costs("TwirlingCritic", rollouts([0.0], wz=[-0.4]))
    assert out == pytest.approx([10.0 * 0.4])
    out, _ = costs("PreferForwardCritic", rollouts([0.0], vx=[-0.2]), goal=(0.3, 0.0, 0.0))
    assert out == pytest.approx([0.0])


def test_path_follow_critic_aims_offset_from_furthest_points_beyond_the_furthest_reached() -> None:
    out, _ = costs("PathFollowCritic", rollouts([0.5, 0.25], [0.0, 0.1]))
    # the furthest trajectory end reaches point 10 (0.5 m); the target is point 15 (0.75 m)
    assert out == pytest.approx([5.0 * 0.25, 5.0 * math.hypot(0.5, 0.1)])


def test_path_align_critic_charges_the_distance_to_the_path_at_equal_arc_length() -> None:
    r = rollouts([0.0], [0.1])  # 0.1 m beside the path, every 4th pose on a path point's arc length
    r.x[0] = np.arange(T) * 0.025  # to 1.375 m: point 27 reached
    out, _ = costs("PathAlignCritic", r)
    assert out == pytest.approx([14.0 * 0.1], rel=1e-9)
    short = rollouts([0.0], [0.1])
    short.x[0] = np.linspace(0.0, 0.5, T)  # only point 10 reached: fewer than offset_from_furthest (20)
    out, _ = costs("PathAlignCritic", short)
    assert out == pytest.approx([0.0])


def test_path_align_critic_aligns_only_with_the_path_up_to_the_furthest_reached_point() -> None:
    """As Nav2's: poses whose distance travelled goes beyond the furthest reached path point are compared
    with the last point before it, not with path points further on that no trajectory reached."""
    r = rollouts([0.0, 0.0], [0.1, 0.1])
    r.x[0] = np.linspace(0.0, 1.0, T)  # ends at path point 20: the furthest reached
    r.x[1] = np.concatenate([np.linspace(0.0, 1.0, T // 2), np.linspace(1.0, 0.3, T - T // 2)])  # and back
    whole, _ = costs("PathAlignCritic", r)
    up_to_furthest, _ = costs("PathAlignCritic", r, path=PATH[:21])
    assert whole[1] > 14.0 * 0.2  # it does cost: far off its arc length's point on the way back
    assert whole == pytest.approx(up_to_furthest, rel=1e-12)


def test_path_angle_critic_turns_a_robot_that_faces_away_from_the_path() -> None:
    r = rollouts([0.0, 0.0], yaw=[math.pi / 2, 0.0])
    out, _ = costs("PathAngleCritic", r, robot=Pose2D(0.0, 0.0, math.pi / 2))
    assert out == pytest.approx([2.0 * math.pi / 2, 0.0])
    out, _ = costs("PathAngleCritic", r, robot=Pose2D(0.0, 0.0, 0.5))  # within max_angle_to_furthest
    assert out == pytest.approx([0.0, 0.0])
