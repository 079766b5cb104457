"""The S-pattern superstate and its inner loop (SMACC2: superstates/ss_s_pattern_1.hpp and
states/s_pattern_states/sti_spattern_*.hpp).

One iteration, for direction RIGHT (upstream's), with absolute headings: StiSPatternLoopStart →
Rotate1 (0°) → Forward1 (pitch1) → Rotate2 (-90°) → Forward2 (pitch2) → Rotate3 (0°) → Forward3
(pitch1) → Rotate4 (+90°) → Forward4 (pitch2) → StiSPatternLoopStart: a square wave along +x. Rotations
keep the LED off, forward legs switch it on. Upstream, a failed leg goes back to the rotation before
it and a failed rotation to the leg before it (or itself): a leg the behavior server keeps refusing (an
obstacle within its look-ahead) loops for ever. Here every failure goes on to the next state (ABORT),
so a refused motion costs one leg of the wave, never the machine. After
the last iteration ``EvLoopEnd[StiSPatternLoopStart]`` leaves for StRotateDegrees6 (ENDLOOP; upstream goes
to StNavigateReverse3 directly, leaving StRotateDegrees6, whose own successor is StNavigateReverse3,
unreachable). Sizes are in waypoints.py.
"""

from __future__ import annotations

from typing import ClassVar

from smacc_py.clients.cl_nav2z import CbAbsoluteRotate, CbNavigateForward
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
)
from smacc_py.state_machines.sm_dance_bot.orthogonals import OrLED, OrNavigation


class SsSPattern1(LoopingSuperstate, parent=MsDanceBotRunMode):
    """A square wave (upstream: 9 iterations, pitches 0.75 and 1.45 m)."""

    inner_initial_state = "StiSPatternLoopStart"
    reactions = [Transition(EvLoopEnd["StiSPatternLoopStart"], "StRotateDegrees6", ENDLOOP)]
    total_iterations = wp.S_ITERATIONS
    pitch1_length: ClassVar[float] = wp.S_PITCH_1
    pitch2_length: ClassVar[float] = wp.S_PITCH_2


class StiSPatternLoopStart(LoopStartState, parent=SsSPattern1):
    """Another period of the wave, or the end."""

    reactions = [Transition(EvLoopContinue["StiSPatternLoopStart"], "StiSPatternRotate1", CONTINUELOOP)]
    superstate = SsSPattern1


def _rotate(index: int, degrees: float, on_failure: str) -> type[SmaccState]:
    name = f"StiSPatternRotate{index}"

    @classmethod  # type: ignore[misc]
    def static_configure(cls: type[SmaccState]) -> None:
        cls.configure_orthogonal(OrNavigation, CbAbsoluteRotate, degrees)
        cls.configure_orthogonal(OrLED, CbLEDOff)

    namespace = {
        "reactions": [Transition(ABS_ROTATE_OK, f"StiSPatternForward{index}"),
                      Transition(ABS_ROTATE_FAILED, on_failure)],
        "static_configure": static_configure, "__module__": __name__, "__qualname__": name,
        "__doc__": f"Turn to {degrees:+.0f}° (absolute), LED off.",
    }
    return type(name, (SmaccState,), namespace, parent=SsSPattern1)


def _forward(index: int, length: float, following: str) -> type[SmaccState]:
    name = f"StiSPatternForward{index}"

    @classmethod  # type: ignore[misc]
    def static_configure(cls: type[SmaccState]) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateForward, length, wp.FORWARD_SPEED)
        cls.configure_orthogonal(OrLED, CbLEDOn)

    namespace = {
        "reactions": [Transition(FORWARD_OK, following),
                      Transition(FORWARD_FAILED, following, ABORT)],
        "static_configure": static_configure, "__module__": __name__, "__qualname__": name,
        "__doc__": f"Drive {length:g} m, LED on.",
    }
    return type(name, (SmaccState,), namespace, parent=SsSPattern1)


StiSPatternRotate1 = _rotate(1, 0.0, "StiSPatternForward1")
StiSPatternForward1 = _forward(1, SsSPattern1.pitch1_length, "StiSPatternRotate2")
StiSPatternRotate2 = _rotate(2, -90.0, "StiSPatternForward2")
StiSPatternForward2 = _forward(2, SsSPattern1.pitch2_length, "StiSPatternRotate3")
StiSPatternRotate3 = _rotate(3, 0.0, "StiSPatternForward3")
StiSPatternForward3 = _forward(3, SsSPattern1.pitch1_length, "StiSPatternRotate4")
StiSPatternRotate4 = _rotate(4, 90.0, "StiSPatternForward4")


class StiSPatternForward4(SmaccState, parent=SsSPattern1):
    """Drive pitch2 back up, LED on; then the next period."""

    reactions = [Transition(FORWARD_OK, "StiSPatternLoopStart"),
                 Transition(FORWARD_FAILED, "StiSPatternLoopStart", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateForward, SsSPattern1.pitch2_length, wp.FORWARD_SPEED)
        cls.configure_orthogonal(OrLED, CbLEDOn)
