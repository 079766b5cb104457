"""RPP's way out of a spot where its commands go unanswered (nav_stack/core/control/stall_escape.py),
and its final turn beside a pillar (nav_stack/core/control/rpp_moves.py, RPPMoves.final_turn).

The closed loops run RPP against tests/helpers/tight_spot.py: the pillar beside location3 drawn as
lidar cells, and a robot whose box cannot enter the real pillar. The starts are the battery patrol's
approach to location3 in looped demos that wedged or touched the pillar (ground truth from their
recordings), with the cell borders shifted by up to 4 cm.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from nav_stack.core.control import CostGrid, PathHandler, RPPParams, SimpleGoalChecker, Twist2D
from nav_stack.core.control.base import CircleFootprint, PolygonFootprint
from nav_stack.core.control.rpp import RegulatedPurePursuit
from nav_stack.core.control.rpp_moves import STEP_CLEAR_DISTANCE, TURNING_SPOT_REACH
from nav_stack.core.control.stall_escape import StallEscape, unanswered
from nav_stack.core.geometry import Pose2D, headings_along
from tests.helpers.tight_spot import WAFFLE_BOX, box_clearance, lidar_costmap, step_with_contact

DT = 0.05  # s, RPP's 20 Hz
#: the planner's last metres to location3 in the wedged run, and location3's heading (rad)
APPROACH = [(-1.435, -1.227), (-1.425, -1.267), (-1.415, -1.307)]
GOAL_YAW = math.pi
STARTS = [Pose2D(-1.427, -1.200, -1.49), Pose2D(-1.429, -1.230, -1.72), Pose2D(-1.429, -1.233, -1.80)]
#: final turns at location3 that touched the pillar in looped patrol_recharge_each_round scenarios
TOUCHED_STARTS = [Pose2D(-1.478, -1.150, -2.02), Pose2D(-1.469, -1.120, -1.72), Pose2D(-1.456, -1.225, -1.71),
                  Pose2D(-1.483, -1.147, -1.71)]
SHIFTS = [(0.0, 0.0), (0.01, 0.0), (0.02, 0.0), (0.0, 0.01), (0.0, 0.02), (0.03, 0.03), (0.04, 0.01)]


def approach_path() -> np.ndarray:
    xy = np.array(APPROACH)
    path = np.column_stack((xy, headings_along(xy)))
    path[-1, 2] = GOAL_YAW
    return path


def run_to_location3(rpp: RegulatedPurePursuit, start: Pose2D, shift: tuple[float, float],
                     steps: int = 600, blind: bool = False) -> tuple[bool, Pose2D, int]:
    """Closed loop to the goal heading; (reached, end pose, cycles in which the pillar stopped the
    robot). ``blind``: the costmap has not seen the pillar (every cell free)."""
    grid = lidar_costmap(shift)
    if blind:
        grid = CostGrid(np.zeros_like(grid.costs), grid.spec)
    handler = PathHandler()
    handler.set_plan(approach_path())
    checker = SimpleGoalChecker()
    pose, measured, jammed = start, Twist2D(0.0, 0.0), 0
    for _ in range(steps):
        if checker.is_goal_reached(pose, handler.goal, measured):
            return True, pose, jammed
        local = handler.local_path(pose, Pose2D(0.0, 0.0, 0.0), grid)
        cmd = rpp.compute_velocity(pose, measured, local, grid)
        pose, measured = step_with_contact(pose, cmd, DT)
        jammed += measured != cmd
    return False, pose, jammed


def waffle_rpp() -> RegulatedPurePursuit:
    return RegulatedPurePursuit(RPPParams(stateful=True), CircleFootprint(0.22, PolygonFootprint(WAFFLE_BOX)))


def test_unanswered_judges_each_significant_component() -> None:
    assert unanswered(Twist2D(0.0, -0.16), Twist2D(0.0, 0.0), 0.2)
    assert not unanswered(Twist2D(0.0, -0.16), Twist2D(0.0, -0.1), 0.2)  # turning, if slower
    assert unanswered(Twist2D(0.05, -0.333), Twist2D(0.0, 0.001), 0.2)
    assert not unanswered(Twist2D(0.05, -0.333), Twist2D(0.04, 0.0), 0.2)  # moving: not jammed
    assert not unanswered(Twist2D(0.0, 0.05), Twist2D(0.0, 0.0), 0.2)  # the end of a braked turn
    assert not unanswered(Twist2D(0.0, 0.0), Twist2D(0.0, 0.0), 0.2)


def test_stall_escape_steps_ahead_then_back_and_ends_after_its_distance() -> None:
    escape = StallEscape(distance=0.1, max_speed=0.05, cycles=3)
    here = Pose2D(0.0, 0.0, 0.0)
    escape.sent(Twist2D(0.26, 0.0))  # driving fast is never judged
    for _ in range(5):
        escape.observe(here, Twist2D(0.0, 0.0))
    assert escape.directions(here) == ()
    escape.sent(Twist2D(0.0, 0.5))
    for _ in range(2):
        escape.observe(here, Twist2D(0.0, 0.0))
    assert escape.directions(here) == ()
    escape.observe(here, Twist2D(0.0, 0.0))
    assert escape.directions(here) == (1.0, -1.0)
    escape.stepping(1.0)
    escape.sent(Twist2D(0.05, 0.0))
    for _ in range(3):  # the step ahead is jammed too: back
        escape.observe(here, Twist2D(0.0, 0.0))
    assert escape.directions(here) == (-1.0, 1.0)
    assert escape.directions(Pose2D(-0.1, 0.0, 0.0)) == ()  # stepped far enough
    assert not escape.escaping


@pytest.mark.parametrize(("start", "shift"), list(itertools.product(STARTS + TOUCHED_STARTS, SHIFTS)))
def test_the_final_turn_at_location3_never_meets_the_pillar(
        start: Pose2D, shift: tuple[float, float]) -> None:
    """Beside the pillar every turn on the spot onto location3's heading swings the box's rear corner
    near it, and the cells draw the pillar a few centimetres off. RPP now picks, once, the step along
    its axis (up to TURNING_SPOT_REACH) and the way round whose motion keeps the box off lethal
    cells (else goes least deep into them), and finishes that turn. Before, over the first three
    touched starts: the box touched the pillar in 8 of 42 loops when it turned at once, and in 2
    when it stepped a fixed way first and then turned regardless. The fourth touched start (a looped
    scenario after that change) found no such motion within 0.10 m."""
    reached, pose, jammed = run_to_location3(waffle_rpp(), start, shift)
    assert reached, pose
    assert jammed == 0 and box_clearance(pose) >= 0.0
    assert math.hypot(pose.x - APPROACH[-1][0], pose.y - APPROACH[-1][1]) < 0.25 + TURNING_SPOT_REACH


@pytest.mark.parametrize("start", STARTS + TOUCHED_STARTS)
def test_rpp_steps_out_of_a_turn_jammed_against_a_pillar_its_costmap_has_not_seen(start: Pose2D) -> None:
    """The cells can be wrong by more than the final turn allows for: here they miss the pillar
    altogether, the turn onto location3's heading jams a rear corner against it, and RPP repeats
    the jammed command for good unless a command unanswered for half a second makes it step straight
    out by STEP_CLEAR_DISTANCE and try again."""
    reached, pose, jammed = run_to_location3(waffle_rpp(), start, (0.0, 0.0), blind=True)
    assert reached and jammed > 0, pose
    assert box_clearance(pose) >= 0.0
    stuck = waffle_rpp()
    stuck._escape = StallEscape(STEP_CLEAR_DISTANCE, 0.05, cycles=10**9)
    reached, _, jammed = run_to_location3(stuck, start, (0.0, 0.0), blind=True)
    assert not reached and jammed > 500
