"""The F-pattern superstate and its inner loop (SMACC2: superstates/ss_f_pattern_1.hpp and
states/f_pattern_states/sti_fpattern_*.hpp).

One iteration, for direction RIGHT (upstream's): StiFPatternStartLoop → StiFPatternRotate1 (absolute
-90°, LED off) → StiFPatternForward1 (one ray length, LED on) → StiFPatternReturn1 (undo the ray
backwards) → StiFPatternRotate2 (absolute 0°) → StiFPatternForward2 (one pitch along x) →
StiFPatternStartLoop. So the robot draws the teeth of a comb along +x. After the last iteration
``EvLoopEnd[StiFPatternStartLoop]`` leaves for StNavigateReverse4 (ENDLOOP).

Upstream has transitions only on success (a failed motion stalls the machine), except Rotate2's failure
(→ Forward2). Added here: every failure goes on to the next state (ABORT), so a motion the behavior
server refuses (an obstacle within its look-ahead) costs one figure, never the machine. Sizes are in
waypoints.py.
"""

from __future__ import annotations

import enum
from typing import ClassVar

from smacc_py.clients.cl_nav2z import CbAbsoluteRotate, CbUndoPathBackwards
from smacc_py.state_machines.sm_dance_bot import waypoints as wp
from smacc_py.state_machines.sm_dance_bot.clients import CbLEDOff, CbLEDOn
from smacc_py.state_machines.sm_dance_bot.loop_pattern import LoopPattern, loop_end
from smacc_py.state_machines.sm_dance_bot.modestates import LoopingSuperstate, MsDanceBotRunMode


class TDirection(enum.Enum):
    """Which side the rays go to (SMACC2: ``f_pattern_states::TDirection``)."""

    LEFT = 90.0
    RIGHT = -90.0


class SsFPattern1(LoopingSuperstate, parent=MsDanceBotRunMode):
    """Rays to one side, each followed by a pitch forward (upstream: 9 × 3.25 m rays, 0.75 m pitch)."""

    inner_initial_state = "StiFPatternStartLoop"
    reactions = loop_end("StiFPatternStartLoop", "StNavigateReverse4")
    total_iterations = wp.F_ITERATIONS
    ray_length: ClassVar[float] = wp.F_RAY
    pitch_length: ClassVar[float] = wp.F_PITCH
    direction: ClassVar[TDirection] = TDirection.RIGHT


_F = LoopPattern(SsFPattern1, __name__)
StiFPatternStartLoop = _F.loop_start("StiFPatternStartLoop", "StiFPatternRotate1",
                                     "Another tooth, or the end of the comb.")
StiFPatternRotate1 = _F.motion(
    "StiFPatternRotate1", CbAbsoluteRotate, SsFPattern1.direction.value, led=CbLEDOff,
    following="StiFPatternForward1", doc="Face the ray's side (absolute ±90°), LED off.")
StiFPatternForward1 = _F.forward(
    "StiFPatternForward1", SsFPattern1.ray_length, led=CbLEDOn,
    following="StiFPatternReturn1", doc="Drive the ray, LED on.")
StiFPatternReturn1 = _F.motion(
    "StiFPatternReturn1", CbUndoPathBackwards, led=CbLEDOn,
    following="StiFPatternRotate2", doc="Undo the ray backwards, LED on.")
StiFPatternRotate2 = _F.motion(
    "StiFPatternRotate2", CbAbsoluteRotate, 0.0, led=CbLEDOff,
    following="StiFPatternForward2", doc="Face along x again (absolute 0°), LED off.")
StiFPatternForward2 = _F.forward(
    "StiFPatternForward2", SsFPattern1.pitch_length, led=CbLEDOff,
    following="StiFPatternStartLoop", doc="One pitch along x, LED off.")
