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

from smacc_py.clients.cl_nav2z import CbAbsoluteRotate, CbNavigateForward, CbUndoPathBackwards
from smacc_py.core import (
    ABORT,
    CONTINUELOOP,
    ENDLOOP,
    EvLoopContinue,
    EvLoopEnd,
    SmaccState,
    Transition,
)
from smacc_py.state_machines.sm_dance_bot import waypoints as wp
from smacc_py.state_machines.sm_dance_bot.clients import CbLEDOff, CbLEDOn
from smacc_py.state_machines.sm_dance_bot.modestates import (
    LoopingSuperstate,
    LoopStartState,
    MsDanceBotRunMode,
)
from smacc_py.state_machines.sm_dance_bot.nav_events import (
    ABS_ROTATE_FAILED,
    ABS_ROTATE_OK,
    FORWARD_FAILED,
    FORWARD_OK,
    UNDO_FAILED,
    UNDO_OK,
)
from smacc_py.state_machines.sm_dance_bot.orthogonals import OrLED, OrNavigation


class TDirection(enum.Enum):
    """Which side the rays go to (SMACC2: ``f_pattern_states::TDirection``)."""

    LEFT = 90.0
    RIGHT = -90.0


class SsFPattern1(LoopingSuperstate, parent=MsDanceBotRunMode):
    """Rays to one side, each followed by a pitch forward (upstream: 9 × 3.25 m rays, 0.75 m pitch)."""

    inner_initial_state = "StiFPatternStartLoop"
    reactions = [Transition(EvLoopEnd["StiFPatternStartLoop"], "StNavigateReverse4", ENDLOOP)]
    total_iterations = wp.F_ITERATIONS
    ray_length: ClassVar[float] = wp.F_RAY
    pitch_length: ClassVar[float] = wp.F_PITCH
    direction: ClassVar[TDirection] = TDirection.RIGHT


class StiFPatternStartLoop(LoopStartState, parent=SsFPattern1):
    """Another tooth, or the end of the comb."""

    reactions = [Transition(EvLoopContinue["StiFPatternStartLoop"], "StiFPatternRotate1", CONTINUELOOP)]
    superstate = SsFPattern1


class StiFPatternRotate1(SmaccState, parent=SsFPattern1):
    """Face the ray's side (absolute ±90°), LED off."""

    reactions = [Transition(ABS_ROTATE_OK, "StiFPatternForward1"),
                 Transition(ABS_ROTATE_FAILED, "StiFPatternForward1", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbAbsoluteRotate, SsFPattern1.direction.value)
        cls.configure_orthogonal(OrLED, CbLEDOff)


class StiFPatternForward1(SmaccState, parent=SsFPattern1):
    """Drive the ray, LED on."""

    reactions = [Transition(FORWARD_OK, "StiFPatternReturn1"),
                 Transition(FORWARD_FAILED, "StiFPatternReturn1", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateForward, SsFPattern1.ray_length, wp.FORWARD_SPEED)
        cls.configure_orthogonal(OrLED, CbLEDOn)


class StiFPatternReturn1(SmaccState, parent=SsFPattern1):
    """Undo the ray backwards, LED on."""

    reactions = [Transition(UNDO_OK, "StiFPatternRotate2"),
                 Transition(UNDO_FAILED, "StiFPatternRotate2", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbUndoPathBackwards)
        cls.configure_orthogonal(OrLED, CbLEDOn)


class StiFPatternRotate2(SmaccState, parent=SsFPattern1):
    """Face along x again (absolute 0°), LED off."""

    reactions = [Transition(ABS_ROTATE_OK, "StiFPatternForward2"),
                 Transition(ABS_ROTATE_FAILED, "StiFPatternForward2", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbAbsoluteRotate, 0.0)
        cls.configure_orthogonal(OrLED, CbLEDOff)


class StiFPatternForward2(SmaccState, parent=SsFPattern1):
    """One pitch along x, LED off."""

    reactions = [Transition(FORWARD_OK, "StiFPatternStartLoop"),
                 Transition(FORWARD_FAILED, "StiFPatternStartLoop", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateForward, SsFPattern1.pitch_length, wp.FORWARD_SPEED)
        cls.configure_orthogonal(OrLED, CbLEDOff)
